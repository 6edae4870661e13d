/**
 * \file analysis/flywheel.h
 * The flywheel sizing as an analysis (issue 43: one analysis layer for every tool): the
 * machine's cycle at a constant mean speed (machines/flywheel/machine_cycle.h: T_req, the
 * energy loop), the flywheel for a C_s, --design's sensitivities and the simulated check,
 * asked for by a FlywheelRequest (analysis/flywheel_request.h). Check(model, request) says
 * what is wrong with the request on this model; Run(model, request, outputs, prepare, result)
 * computes, prints, and writes the energy loop's CSV from its column table (analysis/flywheel_columns.h)
 * whole or not at all; the command draws its pictures from that CSV afterwards
 * (tools/flywheel_run.h). One source for the per-model tool <model>_flywheel
 * (tools/flywheel_main.cc, M the generated model's type, fixed sizes) and for the model view
 * (M = ViewModel: runtime/view/analysis.cc, declared in analysis/view_analysis.h; `mechgen_view
 * flywheel`; the cycle's sampling, --design's sensitivities of it
 * (machines/flywheel/cycle_design.h) and the simulated check compiled once in
 * mechgen_runtime_view: mechgen/machines/view_machines.h, runtime/view/machines.cc). What it
 * computes, its CSV, pictures and exit statuses: tools/flywheel_main.cc.
 *
 * --params/--set read the model's parameter table (analysis/view_params.h).
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <unistd.h>
#include <vector>

#include "mechgen/analysis/flywheel_columns.h"
#include "mechgen/analysis/flywheel_request.h"
#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/io/format.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/output_file.h"
#include "mechgen/machines/flywheel/cycle_design.h"
#include "mechgen/machines/flywheel/machine_cycle.h"
#include "mechgen/position/input_step.h"
#include "mechgen/table/columns.h"

namespace mechgen::analysis {
namespace flywheel_internal {

namespace tools = mechgen::tools;
namespace fw = mechgen::flywheel;

// One CSV row and the CSV's columns: analysis/flywheel_columns.h (the study reads them too).
using LoopRow = FlywheelLoopRow;
inline mechgen::table::Columns<LoopRow> LoopColumns(bool dynamics, const std::vector<std::string>& design) {
  return FlywheelLoopColumns(dynamics, design);
}

static_assert(kFlywheelSteadyFraction == fw::CheckOptions{}.steady_fraction,
              "--steady-fraction's default is CheckOptions::steady_fraction");
static_assert(kFlywheelMaxCheckSamples == mechgen::dynamics::MinimalOptions{}.max_samples,
              "kFlywheelMaxCheckSamples is the simulator's max_samples");

/// A FlywheelRequest read against the model: the parameters and the cycle's options.
template <class M>
struct Inputs {
  typename ModelTypes<M>::Params params;
  fw::MachineCycleOptions options;
};

/// Reads the request against the model into *in; the usage error's text, empty when it fits.
template <class M>
std::string Resolve(const M& model, const FlywheelRequest& a, Inputs<M>* in) {
  using C = ModelCalls<M>;
  const char* const name = C::Name(model);
  const int samples = a.samples;
  if (a.design && !C::HasDesign(model))
    return "--design: the model has no `design` section (the parameters to differentiate by); add one, e.g. "
           "`design: {parameters: all}`";
  if (a.check && !C::HasDynamics(model))
    return std::string("--check needs a model with `dynamics` (") + name + " has none: its machine is massless)";
  in->params = C::DefaultParams(model);
  if (std::string why; !tools::ApplyModelParameters(a.params, model, &in->params, &why)) return why;
  fw::MachineCycleOptions& options = in->options;
  options.omega = fw::RpmToRadPerSecond(a.rpm);
  options.samples = samples;
  options.switch_breaks = !a.no_switch_breaks;
  options.theta0 = a.theta0;
  options.cycle = a.cycle;
  options.breaks = a.breaks;
  const double cycle = std::isnan(options.cycle) ? fw::DefaultCycle(model) : options.cycle;
  const double cycle_begin[1] = {0}, cycle_end[1] = {cycle};
  if (const auto check = mechgen::position::CheckInputSteps(cycle_begin, cycle_end, 1, samples); !check.ok())
    return tools::BadValue("--samples", std::to_string(samples),
                           "at least " + tools::FormatNumber(check.min_steps) +
                               " for this cycle (the position solver's step limit)");
  return "";
}

template <class M>
int RunOneInput(const M& model, const FlywheelRequest& a, const FlywheelOutputs& outputs,
                const std::function<int()>& prepare, FlywheelResult* result) {
  using C = ModelCalls<M>;
  const char* const name = C::Name(model);
  const std::string& tool = outputs.tool;
  const double rpm = a.rpm, cs = a.cs, slip = a.slip, steady_fraction = a.steady_fraction, steady_tol = a.steady_tol;
  const int samples = a.samples, check_samples = a.check_samples, max_cycles = a.max_cycles;
  const bool no_check = a.no_check, design = a.design;
  const std::string &motor = a.motor, &csv_path = outputs.csv_path;
  Inputs<M> in;
  if (const std::string why = Resolve(model, a, &in); !why.empty()) return tools::UsageError(tool, why);
  const typename ModelTypes<M>::Params& params = in.params;
  const fw::MachineCycleOptions& options = in.options;

  // The pictures' gnuplot and script (their paths checked by the parser), before anything is
  // computed or written.
  if (prepare) {
    if (const int status = prepare(); status >= 0) return status;
  }

  // (unqualified: the view's, compiled once, found by its arguments: machines/view_machines.h)
  const fw::MachineCycle machine = SampleMachineCycle(model, params, options);
  if (machine.status == fw::CycleStatus::kNotAssembled) {
    std::cerr << "error: cannot size a flywheel for " << name << ": " << machine.message << "\n";
    return 3;
  }
  if (machine.status == fw::CycleStatus::kBadOptions && !options.breaks.empty())
    return tools::UsageError(tool, "--break: " + machine.message);
  if (!machine.IsUsable()) {
    std::cerr << "error: cannot size a flywheel for " << name << ": " << machine.message << "\n";
    return 1;
  }
  const fw::FlywheelSize size = fw::SizeFlywheel(machine, cs);
  const fw::EnergyLoop& loop = machine.loop;
  std::printf("mechgen flywheel of '%s': %s from %.6g deg over %.6g deg in %d samples at %.6g rpm "
              "(w_m = %.9g rad/s)%s\n",
              name, C::QName(model, 0), internal::ToDegrees(machine.theta0), internal::ToDegrees(machine.cycle), samples,
              rpm, machine.omega,
              machine.has_dynamics ? "; statics + inertia torque (dynamics)" : "; statics only (massless)");
  if (const std::string changed = tools::ChangedModelParameters(model, params); !changed.empty())
    std::printf("parameters set: %s\n", changed.c_str());
  std::printf("  required torque T_req: mean %.9g N m (the constant motor torque%s), max %.6g N m at "
              "%.6g deg, min %.6g N m at %.6g deg\n",
              machine.T_mean,
              machine.zero_mean ? (": zero to rounding, |mean| <= " + tools::FormatNumber(machine.T_mean_rounding) +
                                   " N m; the loads do no net work")
                                      .c_str()
                                : "",
              machine.T_max, internal::ToDegrees(machine.theta_T_max), machine.T_min, internal::ToDegrees(machine.theta_T_min));
  std::printf("  work per cycle %.9g J; mean power %.6g W\n", machine.work, machine.T_mean * machine.omega);
  std::printf("  energy loop: E_max = %.9g J at %.6g deg, E_min = %.9g J at %.6g deg; dE = %.9g J\n",
              loop.E_max, internal::ToDegrees(loop.theta_max), loop.E_min, internal::ToDegrees(loop.theta_min),
              loop.delta_E);
  if (!machine.breaks.empty() || !machine.switches.empty()) {
    std::string list;
    for (double b : machine.breaks) list += (list.empty() ? "" : ", ") + tools::FormatNumber(internal::ToDegrees(b));
    std::printf("  breaks of the loop (deg): %s; %zu switches of the loads located%s\n",
                list.empty() ? "none" : list.c_str(), machine.switches.size(),
                machine.switches_unused > 0
                    ? (", " + std::to_string(machine.switches_unused) +
                       " too close to another break (second order there: use more samples)")
                          .c_str()
                    : "");
  }
  if (!std::isfinite(size.I_required) || !std::isfinite(size.I_flywheel)) {
    std::cerr << "error: the flywheel for C_s = " << tools::FormatNumber(cs) << " is beyond the range of numbers: dE = "
              << tools::FormatNumber(loop.delta_E) << " J over C_s w_m^2 = " << tools::FormatNumber(cs * machine.omega * machine.omega)
              << " (change --cs or --rpm)\n";
    return 1;
  }
  std::printf("  C_s = %.6g: I = dE/(C_s w_m^2) = %.9g kg m^2", cs, size.I_required);
  if (machine.has_dynamics) {
    std::printf("; the machine's own mean I = %.6g kg m^2; flywheel I_fly = %.9g kg m^2%s\n",
                machine.I_mean, size.I_flywheel,
                size.needed ? "" : " (none needed: the machine's own inertia suffices)");
  } else {
    std::printf(" (the flywheel; the machine is massless: no `dynamics`)\n");
  }

  // --design: the sensitivities printed, and dT_req/d<p> per sample for the CSV.
  std::vector<std::string> design_names;
  std::vector<std::vector<double>> dT_req_dp;
  if constexpr (mechgen::HasDesignDerivatives<M>::value) {
    if (design) {
      // (unqualified: the view's, compiled once, found by its arguments)
      const fw::CycleDesign<M> cycle_design = SampleMachineCycleDesign(model, params, options, machine);
      if (!cycle_design.IsUsable()) {
        std::cerr << "error: no design sensitivities for " << name << ": " << cycle_design.message << "\n";
        return 1;
      }
      const auto dsize = fw::SizeFlywheelDesign<M>(machine, cycle_design, cs);
      std::printf("  design sensitivities of T_mean = %.17g N m, dE = %.17g J, I = %.17g kg m^2, I_fly = %.17g "
                  "kg m^2 (per unit of each parameter, in the model file's units):\n",
                  machine.T_mean, loop.delta_E, size.I_required, size.I_flywheel);
      std::printf("    %-12s %16s %16s %16s %16s\n", "p", "dT_mean/dp", "d(dE)/dp", "dI/dp", "dI_fly/dp");
      for (int d = 0; d < C::NumDesign(model); ++d) {
        design_names.push_back(C::DesignName(model, d));
        std::printf("    %-12s %16.9g %16.9g %16.9g %16.9g\n", C::DesignName(model, d), cycle_design.dT_mean_dp(d),
                    cycle_design.ddelta_E_dp(d), dsize.dI_required_dp(d), dsize.dI_flywheel_dp(d));
      }
      for (const auto& v : cycle_design.dT_req_dp) dT_req_dp.emplace_back(v.data(), v.data() + v.size());
    }
  }

  int status = 0;
  const bool do_check = machine.has_dynamics && !no_check && size.needed;
  if (do_check) {
    fw::CheckOptions co;
    co.law = motor == "shunt" ? fw::MotorLaw::kShunt : fw::MotorLaw::kConstant;
    co.slip = slip;
    co.samples_per_cycle = check_samples;
    co.max_cycles = max_cycles;
    co.steady_fraction = steady_fraction;
    co.steady_tolerance = steady_tol;
    const fw::SimulatedCheck sim = CheckBySimulation(model, params, machine, size.I_flywheel, co);
    if (!sim.ok) {
      std::cerr << "error: the simulated check failed: " << sim.message << "\n";
      status = 1;
    } else {
      std::printf("  simulated with I_fly and a %s motor%s: steady after %d cycles (period %.6g s); "
                  "w %.9g .. %.9g rad/s (max at %.6g deg, min at %.6g deg), w_mid %.9g, time mean "
                  "%.9g rad/s\n",
                  fw::ToString(co.law), co.law == fw::MotorLaw::kShunt ? (" (slip " + tools::FormatNumber(slip) + ")").c_str() : "",
                  sim.cycles, sim.period, sim.trace.omega_min, sim.trace.omega_max,
                  internal::ToDegrees(sim.theta_at_max), internal::ToDegrees(sim.theta_at_min), sim.trace.omega_mid,
                  sim.trace.omega_mean);
      // The settling time of the cycle-mean speed: I over the slope of the mean load and motor
      // torque against the speed; beyond the run, or none, the mean speed only creeps.
      std::string settling = "none (the slope of the mean load and motor torque against the speed is " +
                             tools::FormatNumber(sim.slope) + " N m s/rad: a neutral cycle, its mean speed only creeps)";
      if (std::isfinite(sim.settling_time)) {
        settling = tools::FormatNumber(sim.settling_time) + " s (I over the slope " + tools::FormatNumber(sim.slope) +
                   " N m s/rad of the mean load and motor torque against the speed)";
        if (sim.settling_time > sim.cycles_limit * sim.period)
          settling += ", far beyond the run: a near-neutral cycle, its mean speed only creeps";
      }
      std::printf("  steady: the cycle-mean speed changed by %.3g relative over the last cycle (tolerance %.3g "
                  "%s); settling time %s\n",
                  sim.last_change, sim.steady_tolerance,
                  std::isnan(steady_tol)
                      ? ("= " + tools::FormatNumber(steady_fraction) + " x the expected C_s " +
                         tools::FormatNumber(sim.C_s_expected) +
                         (sim.steady_tolerance < steady_fraction * sim.C_s_expected
                              ? " / the settling time in cycles " + tools::FormatNumber(sim.settling_time / sim.period)
                              : std::string()))
                            .c_str()
                      : "(--steady-tol)",
                  settling.c_str());
      std::printf("  simulated C_s = %.6g against the asked %.6g (%+.3f %%; the energy loop is exact "
                  "to O(C_s) relative)\n",
                  sim.trace.C_s, cs, 100 * (sim.trace.C_s / cs - 1));
    }
  } else if (machine.has_dynamics && !no_check && !size.needed) {
    std::printf("  no simulated check: no flywheel to add\n");
  }

  // The CSV (whole or absent), then the pictures from it.
  std::vector<LoopRow> rows;
  rows.reserve(machine.points.size());
  for (size_t k = 0; k < machine.points.size(); ++k)
    rows.push_back({machine.points[k], machine.T_mean, dT_req_dp.empty() ? nullptr : dT_req_dp[k].data()});
  const auto columns = LoopColumns(machine.has_dynamics, design_names);
  const bool picture = outputs.picture;
  std::string csv_for_plot = csv_path;
  std::string temporary;
  if (csv_path.empty() && picture) {
    char name[] = "/tmp/mechgen_flywheel_XXXXXX";
    const int fd = mkstemp(name);
    if (fd < 0) {
      std::cerr << "error: cannot create a temporary CSV for the picture\n";
      return 1;
    }
    close(fd);
    temporary = csv_for_plot = name;
  }
  if (!csv_for_plot.empty()) {
    mechgen::OutputFile csv;
    std::string error;
    if (!csv.Open(csv_for_plot, &error)) {
      std::cerr << "error: " << error << "\n";
      return 1;
    }
    mechgen::WriteCsv(columns, rows, csv.stream(),
                      mechgen::Described(mechgen::CsvAbout(
                          std::string(name) + "_flywheel", name,
                          "energy loop at " + tools::FormatNumber(rpm) + " rpm (w_m = " +
                              tools::FormatNumber(machine.omega) + " rad/s), C_s = " +
                              tools::FormatNumber(cs) + ", dE = " + tools::FormatNumber(loop.delta_E) +
                              " J, I = " + tools::FormatNumber(size.I_required) + " kg m^2",
                          "torques on the input link, CCW + (the input turns CCW at w_m > 0); E > 0 "
                          "where the machine runs ahead of its mean")));
    if (!csv.Close(&error) || !csv.Commit(&error)) {
      std::cerr << "error: " << error << "\n";
      if (!temporary.empty()) std::remove(temporary.c_str());
      return 1;
    }
    if (!csv_path.empty())
      std::printf("wrote %s (%zu rows x %zu columns)\n", csv_path.c_str(), rows.size(), columns.size());
  }
  result->written = true;
  result->csv = csv_for_plot;
  result->temporary = temporary;
  return status;
}

}  // namespace flywheel_internal

/// What is wrong with `request` on `model` (one line), empty when Run can go on: a model of
/// one input with statics, --design without a design section, --check on a massless machine,
/// the parameters, the samples for the cycle (the position solver's step limit).
template <class M>
std::string Check(const M& model, const FlywheelRequest& request) {
  using C = ModelCalls<M>;
  if (C::Nq(model) != 1)
    return std::string("the model '") + C::Name(model) + "' has " + std::to_string(C::Nq(model)) +
           " inputs; flywheel sizing is for one-DOF machines";
  if (!C::HasStatics(model))
    return std::string("the model '") + C::Name(model) +
           "' was generated without statics; add `forces` to its outputs' quantities";
  if constexpr (C::kView || (mechgen::statics::StaticsFeatures<M>::kHasStatics && M::kNq == 1)) {
    flywheel_internal::Inputs<M> in;
    return flywheel_internal::Resolve(model, request, &in);
  }
  return "";
}

/**
 * \brief The flywheel of `model` asked for by `request`: for a one-input model with statics;
 * for the others one line, exit 1 (not one input) or 2 (no statics).
 * \tparam M  A generated model (the per-model tool) or mechgen::ViewModel.
 * \param prepare  Called once the request is checked, before anything is computed or written
 *                 (the command's pictures: gnuplot and its script found); -1 to go on, else the
 *                 exit status to end with.
 * \param result   Where the CSV the pictures read was left (its `written` false when Run ended
 *                 before it).
 * \return The exit status (tools/flywheel_main.cc).
 */
template <class M>
int Run(const M& model, const FlywheelRequest& request, const FlywheelOutputs& outputs,
        const std::function<int()>& prepare, FlywheelResult* result) {
  using C = ModelCalls<M>;
  const int nq = C::Nq(model);
  const bool statics = C::HasStatics(model);
  result->written = false;
  if (nq == 1 && statics) {
    if constexpr (C::kView || (mechgen::statics::StaticsFeatures<M>::kHasStatics && M::kNq == 1))
      return flywheel_internal::RunOneInput(model, request, outputs, prepare, result);
  }
  if (nq != 1) {
    std::cerr << "error: the model '" << C::Name(model) << "' has " << nq
              << " inputs; flywheel sizing is for one-DOF machines\n";
    return 1;
  }
  std::cerr << "error: the model '" << C::Name(model)
            << "' was generated without statics; add `forces` to its outputs' quantities\n";
  return 2;
}

}  // namespace mechgen::analysis
