/**
 * \file analysis/simulate.h
 * The simulation as an analysis (issue 43: one analysis layer for every tool): the free motion
 * by the minimal method (dynamics/forward.h, Coulomb friction with stick and slip), the motion
 * with some or every input driven (dynamics/prescribed.h) and the free motion with its
 * trajectory sensitivities (design: analysis/simulate_design.h), asked for
 * by a SimulateRequest (analysis/simulate_request.h). Check(model, request) says what is wrong
 * with the request on this model; Run(model, request, outputs) assembles, integrates (the rows
 * streamed to the CSV), prints the summary and writes the CSV from its column table
 * (dynamics/columns.h) whole or not at all (io/output_file.h). Both read the request through
 * one Prepare, so that each check is written once. EvaluateFree and EvaluateDriven are the
 * run alone (no I/O: the rows of the column table handed over), which Run writes and the study
 * keeps (study/run.h, analysis: simulate). One source for the per-model tool
 * <model>_simulate (tools/simulate_main.cc, M the generated model's type, fixed sizes) and for
 * the model view (M = ViewModel: runtime/view/analysis_simulate.cc, declared in
 * analysis/view_analysis.h; `mechgen_view simulate`; the simulators and the kinetostatics
 * compiled once in mechgen_runtime_view: core/view_runtime.h, runtime/view/dynamics.cc). What
 * it computes, its CSV's columns and exit statuses: tools/simulate_main.cc.
 *
 * Through the view, design runs where the model has the generated EvalDynamicsJacobian (the
 * Jacobians along the state; a model without it, a cam law's fourth derivative needed, is the
 * per-model tool's, whose Jets the view does not have): otherwise Run hands it to
 * SimulateOutputs::not_through_view (the command's refusal, or mechgen's fallback to the
 * per-model tool) before anything is computed or written. A program that runs Run includes
 * analysis/simulate_design.h, which defines design's run (RunDesign), when Ceres' headers are
 * there.
 *
 * --params/--set read the model's parameter table (analysis/view_params.h).
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"
#include "mechgen/analysis/simulate_request.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/core/constants.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/dynamics/columns.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "mechgen/dynamics/prescribed.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/output_file.h"
#include "mechgen/table/columns.h"

// design: the trajectory sensitivities need ceres::Jet (a header; analysis/simulate_design.h).
#if __has_include(<ceres/jet.h>)
#define MECHGEN_SIMULATE_HAS_SENSITIVITY 1
#else
#define MECHGEN_SIMULATE_HAS_SENSITIVITY 0
#endif

namespace mechgen::analysis {
namespace simulate_internal {

namespace tools = mechgen::tools;

constexpr double kTwoPi = 6.283185307179586;

// The rows t,q of a CSV file (a first line that is not two numbers is a header). False with
// a message naming the file and line.
inline bool ReadTable(const std::string& path, std::vector<double>* t, std::vector<double>* q,
                      std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read " + path;
    return false;
  }
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<double> values;
    if (!ParseSimulateList(line, &values) || values.size() != 2) {
      if (number == 1) continue;  // a header
      *error = path + ":" + std::to_string(number) + ": expected two numbers t,q";
      return false;
    }
    t->push_back(values[0]);
    q->push_back(values[1]);
  }
  if (t->size() < 2) {
    *error = path + ": a table needs at least two rows t,q";
    return false;
  }
  return true;
}

// ---- output: the CSV's column table (dynamics/columns.h), written by io/csv.h -------------
using mechgen::dynamics::AddInputColumns;
using mechgen::dynamics::CsvRow;
using mechgen::dynamics::DrivenColumns;
using mechgen::dynamics::FreeColumns;
using mechgen::dynamics::RevoluteMagnitudes;

// The CSV's comment lines (io/csv.h): the tool, the model, the run and the signs, then every
// column's unit and meaning.
// (The tool is named <model>_simulate through the view too: the same CSV.)
inline mechgen::CsvOptions SimulateCsvOptions(const char* name, const char* run) {
  return mechgen::Described(mechgen::CsvAbout(
      std::string(name) + "_simulate", name, run,
      "Q_<q> and lambda_<q> act on the input: a torque CCW + for an angle, a force along +q for "
      "a slide; reactions (inertia forces included) are the force (and moment) of each joint's "
      "first link on its second, fixed frame; angles CCW + from the fixed x axis"));
}

// The CSV's path: as asked, or <model>_simulate.csv.
inline std::string CsvPath(const SimulateOutputs& out, const char* name) {
  return out.csv.empty() ? std::string(name) + "_simulate.csv" : out.csv;
}

// Commits the CSV (io/output_file.h: whole or absent); false with one line on stderr.
inline bool CommitCsv(mechgen::OutputFile* csv) {
  std::string error;
  if (csv->Commit(&error)) return true;
  std::fprintf(stderr, "error: %s\n", error.c_str());
  return false;
}

// The standard output flushed; false with one line on stderr when it cannot be written.
inline bool FlushStdout() {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return true;
  std::fprintf(stderr, "error: cannot write the standard output\n");
  return false;
}

/// Why Prepare refused a request.
enum class Refusal {
  kNone,
  kUsage,           ///< a usage error (exit 2)
  kNoDynamics,      ///< the model has no `dynamics` (exit 2: "<model>: <text>")
  kNotThroughView,  ///< what the view does not do yet (SimulateOutputs::not_through_view)
};

/// What Prepare reads from a request and a model, for Check and Run alike.
template <class M>
struct Prepared {
  typename ModelTypes<M>::Params params;
  typename ModelTypes<M>::VecQ q0, qd0;  ///< the inputs' initial values and speeds
  std::vector<int> driven;               ///< drives: the driven inputs' indices, in the order given
  std::vector<mechgen::dynamics::AnyLaw> laws;  ///< ... and their laws
  Refusal refusal = Refusal::kNone;
};

// The inputs' initial values and speeds from the model's assembly, q0 and qd0. The usage
// error's text, empty when they fit.
template <class M, class VecQ>
std::string InitialState(const M& model, const SimulateRequest& a, VecQ* q0, VecQ* qd0) {
  const int kNq = ModelCalls<M>::Nq(model);
  *q0 = Sized<VecQ>(kNq);
  *qd0 = Sized<VecQ>(kNq);
  qd0->setZero();
  for (int i = 0; i < kNq; ++i) (*q0)(i) = ModelCalls<M>::AssemblyQ(model)[i];
  if (!a.q0.empty()) {
    if (static_cast<int>(a.q0.size()) != kNq) {
      return "--q0: bad value " + tools::Quote(a.q0_text) + ": expected " + std::to_string(kNq) +
             " value(s), one per input";
    }
    for (int i = 0; i < kNq; ++i) (*q0)(i) = a.q0[i];
  }
  if (!a.qd0.empty()) {
    if (static_cast<int>(a.qd0.size()) != kNq) {
      return "--qd0: bad value " + tools::Quote(a.qd0_text) + ": expected " + std::to_string(kNq) +
             " value(s), one per input";
    }
    for (int i = 0; i < kNq; ++i) (*qd0)(i) = a.qd0[i];
  }
  return "";
}

// The drives' inputs and laws into p->driven and p->laws (at p->q0): the usage error's text,
// empty when they fit.
template <class M>
std::string ReadDrives(const M& model, const SimulateRequest& a, Prepared<M>* p) {
  namespace dyn = mechgen::dynamics;
  using C = ModelCalls<M>;
  const int nq = C::Nq(model);
  for (const SimulateDrive& d : a.drives) {
    int k = -1;
    for (int j = 0; j < nq; ++j)
      if (d.name == C::QName(model, j)) k = j;
    if (k < 0) {
      std::string names;
      for (int j = 0; j < nq; ++j) names += std::string(j ? ", " : "") + C::QName(model, j);
      return "--drive: bad value " + tools::Quote(d.text) + ": the model has no input " + tools::Quote(d.name) +
             " (its inputs: " + names + ")";
    }
    for (int j : p->driven) {
      if (j == k) return "--drive: bad value " + tools::Quote(d.text) + ": input " + tools::Quote(d.name) + " is driven twice";
    }
    p->driven.push_back(k);
    if (d.kind == "speed") {
      p->laws.emplace_back(dyn::ConstantSpeedLaw{p->q0(k), d.values[0], 0.0});
    } else if (d.kind == "move" || d.kind == "cycloidal") {
      p->laws.emplace_back(dyn::RestToRestLaw{p->q0(k), d.values[0], d.values[1], d.values[2],
                                              d.kind == "move" ? dyn::RestToRestLaw::Profile::kPoly345
                                                               : dyn::RestToRestLaw::Profile::kCycloidal});
    } else {
      std::vector<double> t, q;
      std::string error;
      if (!ReadTable(d.file, &t, &q, &error)) return "--drive: " + tools::Quote(d.text) + ": " + error;
      dyn::TableLaw law(std::move(t), std::move(q));
      if (!law.IsValid()) {
        return "--drive: " + tools::Quote(d.text) + ": the times of " + d.file +
               " must increase strictly and every value be finite";
      }
      p->laws.emplace_back(std::move(law));
    }
  }
  return "";
}

/// Reads the request against the model into *p: the parameters, the initial state, the drives'
/// inputs and laws. The error's text, empty when it fits; p->refusal says what kind it is
/// (kNotThroughView: the text names what, e.g. "--design: the trajectory sensitivities are").
/// Prints nothing.
template <class M>
std::string Prepare(const M& model, const SimulateRequest& a, Prepared<M>* p) {
  using C = ModelCalls<M>;
  if (!C::HasDynamics(model)) {
    p->refusal = Refusal::kNoDynamics;
    return "this model was generated without `dynamics` (add it to outputs.quantities)";
  }
  p->refusal = Refusal::kUsage;
  if constexpr (mechgen::HasDynamics<M>::value) {  // (a ViewModel's: its model's, at run time)
    if (a.design) {
#if !MECHGEN_SIMULATE_HAS_SENSITIVITY
      return "--design: this build has no ceres/jet.h (Ceres' headers), which the trajectory sensitivities need";
#else
      if (!C::HasDynamicsDesign(model)) {  // (a generated model's: constant)
        return "--design: the model has no `design` section (the parameters to differentiate by); add one, e.g. "
               "`design: {parameters: all}`";
      }
      const char* conflict = !a.drives.empty()      ? "--drive"
                             : a.friction == "on"   ? "--friction on"
                             : a.energy_projection  ? "--energy-projection"
                             : a.stop_at_speed_zero ? "--stop-at-speed-zero"
                                                    : nullptr;
      if (conflict != nullptr)
        return std::string("--design: not with ") + conflict + " (the sensitivities of the free motion only)";
      if constexpr (C::kView) {
        // f_q and f_qd through the view from the generated EvalDynamicsJacobian only (the Jets
        // of a model without it are the per-model tool's: mechgen falls back to it).
        if (!C::HasDynamicsJacobian(model)) {
          p->refusal = Refusal::kNotThroughView;
          return "--design: the trajectory sensitivities of a model without the generated EvalDynamicsJacobian (a "
                 "cam law's fourth derivative) are";
        }
      }
#endif
    }
    const int nq = C::Nq(model);
    if (static_cast<int>(a.drives.size()) > nq)
      return std::to_string(a.drives.size()) + " --drive options for a model with " + std::to_string(nq) + " input(s)";
    p->params = C::DefaultParams(model);
    if (std::string why; !tools::ApplyModelParameters(a.params, model, &p->params, &why)) return why;
    if (std::string why = InitialState(model, a, &p->q0, &p->qd0); !why.empty()) return why;
    if (!a.design) {
      if (!a.drives.empty()) {
        if (std::string why = ReadDrives(model, a, p); !why.empty()) return why;
        // Coulomb friction in the actuator forces: every input driven (PrescribedDynamics::
        // kHasDrivenFriction: no free input, no caller's force), else friction on is a usage
        // error, and the run without it says so.
        const bool has_friction = mechgen::dynamics::CoulombFeatures<M>::kHasFriction && C::KinetoNumFriction(model) > 0;
        if (a.friction == "on" && !(has_friction && static_cast<int>(a.drives.size()) == nq)) {
          return has_friction ? "--friction on: Coulomb friction is simulated in a driven run only when every "
                                "input is driven (--drive each)"
                              : "--friction on: the model has no friction joints (`friction:`)";
        }
      } else {
        // Coulomb friction: the model's friction section unless friction says otherwise.
        using Sim = mechgen::dynamics::MinimalDynamics<M, mechgen::dynamics::Dopri5>;  // (either method's)
        if (a.friction == "on" && (!Sim::kHasCoulomb || C::KinetoNumFriction(model) == 0))
          return "--friction on: the model has no friction joints (`friction:`)";
      }
    }
  }
  p->refusal = Refusal::kNone;
  return "";
}

/// What became of a simulation's Evaluate (EvaluateFree, EvaluateDriven).
enum class Evaluated {
  kRan,           ///< the run went (its summary says how it ended)
  kNotAssembled,  ///< the model does not assemble at the initial inputs (and the drives' t = 0)
  kStopped,       ///< begin returned false: nothing run
};

// The free motion's options from the request: the integrator, the samples every dt, energy
// projection, the stop at speed zero, the steady state of an angle input (the cycle-mean speed
// per revolution of the first input settled to steady_tol over two successive cycles,
// dynamics/simulator.h) and Coulomb friction (the model's friction section unless friction
// says otherwise; friction on without it: Prepare).
template <class M>
mechgen::dynamics::MinimalOptions FreeOptions(const M& model, const SimulateRequest& args) {
  mechgen::dynamics::MinimalOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  options.energy_projection = args.energy_projection;
  options.stop_at_speed_zero = args.stop_at_speed_zero;
  options.steady.enabled = ModelCalls<M>::QIsAngle(model, 0) && args.steady;
  options.steady.coordinate = 0;
  options.steady.cycle = kTwoPi;
  options.steady.tolerance = args.steady_tol;
  options.steady.consecutive = 2;
  options.coulomb.enabled = args.friction != "off";
  return options;
}

/**
 * \brief The rows of the free motion asked for by `args` (its options: FreeOptions) from p.q0,
 * p.qd0 under p.params (Prepare's, or the caller's: the study's sample), no I/O.
 *
 * begin(sim) once the model assembled (false: nothing run, kStopped), then row(r) at every
 * sample: r the row of the free motion's column table (FreeColumns): the sample and, where
 * `reactions`, the model has them and the kinetostatics found them, its reactions R (else R
 * null; the friction loads in them: the sample's where the run has Coulomb friction, zeros
 * where it has none). *summary says how the run ended, *last (may be null) its last sample.
 */
template <class M, template <int> class Method, class Begin, class RowFn>
Evaluated EvaluateFree(const M& model, const SimulateRequest& args, const Prepared<M>& p, bool reactions,
                       Begin&& begin, RowFn&& row, mechgen::dynamics::MinimalSummary* summary,
                       typename mechgen::dynamics::MinimalDynamics<M, Method>::SampleT* last) {
  using C = ModelCalls<M>;
  using Sim = mechgen::dynamics::MinimalDynamics<M, Method>;
  using Kineto = mechgen::dynamics::Kinetostatics<M>;
  using SampleT = typename Sim::SampleT;
  Sim sim(model, p.params, FreeOptions(model, args));
  if (!sim.Initialize(p.q0)) return Evaluated::kNotAssembled;
  Kineto kineto(model, p.params);
  if (reactions) kineto.Initialize(p.q0);
  // The kinetostatics' friction loads where the simulation has none (the view, friction
  // off): zeros, as a run without Coulomb friction's samples hold.
  typename Kineto::VecF no_friction = Sized<typename Kineto::VecF>(C::KinetoNumFriction(model));
  no_friction.setZero();
  (void)no_friction;  // (a model without reactions reads none)
  if (!begin(sim)) return Evaluated::kStopped;
  auto observer = [&](const SampleT& s) {
    // The row is handed over inside the branch that holds the kinetostatics it points into.
    CsvRow<SampleT> r{&s, nullptr};
    if constexpr (Kineto::kMayHaveReactions) {
      if (reactions && C::KinetoNumReactions(model) > 0) {
        mechgen::dynamics::KinetostaticsRow<M> k;
        if constexpr (Sim::kHasCoulomb) {
          // The friction loads included (the view's samples of a run without Coulomb friction
          // have none: zeros, as a generated model's hold there).
          kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k, s.friction.size() == no_friction.size() ? &s.friction : &no_friction);
        } else if (C::KinetoNumFriction(model) > 0) {
          kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k, &no_friction);
        } else {
          kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k);
        }
        if (k.status == mechgen::dynamics::KinetostaticsStatus::kOk) r.R = k.statics.R.data();
        return static_cast<bool>(row(static_cast<const CsvRow<SampleT>&>(r)));
      }
    }
    return static_cast<bool>(row(static_cast<const CsvRow<SampleT>&>(r)));
  };
  if constexpr (C::kView) {
    // The runtime instantiated for the view (core/view_runtime.h; found by its argument).
    mechgen::dynamics::ViewSampleFn<Sim> fn = observer;
    SimulateFree(&sim, 0.0, p.q0, p.qd0, args.t_end, fn, summary, last);
  } else {
    sim.Simulate(0.0, p.q0, p.qd0, args.t_end, observer, summary, last);
  }
  return Evaluated::kRan;
}

// The indices of the driven inputs (p.driven) as PrescribedDynamics takes them.
template <int NP, class Sim>
typename Sim::Indices DrivenIndices(const std::vector<int>& driven) {
  typename Sim::Indices prescribed{};
  for (size_t i = 0; i < driven.size(); ++i) {
    if constexpr (NP == Eigen::Dynamic) {
      prescribed.push_back(driven[i]);
    } else {
      prescribed[i] = driven[i];
    }
  }
  return prescribed;
}

/**
 * \brief The rows of the motion with NP of the inputs driven (p.driven on p.laws, which it
 * takes: Prepare's or the caller's), the others free from p.q0, p.qd0 under p.params:
 * PrescribedDynamics with the request's integrator, samples every dt and Coulomb friction in
 * the actuator forces unless friction is off (through the view NP is Eigen::Dynamic: the
 * number of drives, at run time). No I/O.
 *
 * begin(sim) once the model assembled at the initial inputs and the drives' t = 0 (false:
 * kStopped), then row(r) at every sample: r the row of the driven motion's column table
 * (DrivenColumns): the sample (its actuator forces lambda) and, where `reactions`, the model
 * has them and the kinetostatics found them, the reactions R (with the sample's friction loads
 * where the run has friction in lambda). *summary, *last (may be null): as EvaluateFree.
 */
template <class M, template <int> class Method, int NP, class Begin, class RowFn>
Evaluated EvaluateDriven(
    const M& model, const SimulateRequest& args, Prepared<M>* p, bool reactions, Begin&& begin, RowFn&& row,
    mechgen::dynamics::PrescribedSummary* summary,
    typename mechgen::dynamics::PrescribedDynamics<M, NP, mechgen::dynamics::AnyDrive<NP>, mechgen::dynamics::NoForce,
                                                   Method>::SampleT* last) {
  namespace dyn = mechgen::dynamics;
  using C = ModelCalls<M>;
  using Drive = dyn::AnyDrive<NP>;
  using Sim = dyn::PrescribedDynamics<M, NP, Drive, dyn::NoForce, Method>;
  using VecF = typename Sim::VecF;
  using SampleT = typename Sim::SampleT;
  using Kineto = mechgen::dynamics::Kinetostatics<M>;
  const int nq = C::Nq(model);
  const int np = static_cast<int>(p->driven.size());
  typename Drive::Laws laws{};
  if constexpr (NP == Eigen::Dynamic) laws.resize(static_cast<size_t>(np));
  for (int i = 0; i < np; ++i) laws[i] = std::move(p->laws[i]);
  dyn::PrescribedOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  // Coulomb friction in the actuator forces: every input driven (else friction on is a usage
  // error, Prepare's, and the run without it says so).
  options.coulomb.enabled = args.friction != "off";
  Sim sim(model, p->params, DrivenIndices<NP, Sim>(p->driven), Drive(std::move(laws)), dyn::NoForce(), options);
  VecF qf0 = Sized<VecF>(nq - np), qdf0 = Sized<VecF>(nq - np);
  for (int i = 0; i < nq - np; ++i) {
    qf0(i) = p->q0(sim.free()[i]);
    qdf0(i) = p->qd0(sim.free()[i]);
  }
  bool assembled = false;
  if constexpr (C::kView) {
    assembled = InitializePrescribed(&sim, 0.0, qf0);  // (the library's, core/view_runtime.h)
  } else {
    assembled = sim.Initialize(0.0, qf0);
  }
  if (!assembled) return Evaluated::kNotAssembled;
  Kineto kineto(model, p->params);
  if (reactions) kineto.Initialize(p->q0);
  if (!begin(sim)) return Evaluated::kStopped;
  auto observer = [&](const SampleT& s) {
    // The row is handed over inside the branch that holds the kinetostatics it points into.
    CsvRow<SampleT> r{&s, nullptr};
    if constexpr (Kineto::kMayHaveReactions) {
      if (reactions && C::KinetoNumReactions(model) > 0) {
        mechgen::dynamics::KinetostaticsRow<M> k;
        if constexpr (Sim::kHasDrivenFriction) {
          if (sim.HasDrivenFriction()) {
            kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k, &s.friction);  // the friction loads included
          } else {
            kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k);
          }
        } else {
          kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k);
        }
        if (k.status == mechgen::dynamics::KinetostaticsStatus::kOk) r.R = k.statics.R.data();
        return static_cast<bool>(row(static_cast<const CsvRow<SampleT>&>(r)));
      }
    }
    return static_cast<bool>(row(static_cast<const CsvRow<SampleT>&>(r)));
  };
  if constexpr (C::kView) {
    // The runtime instantiated for the view (core/view_runtime.h; found by its argument).
    dyn::ViewSampleFn<Sim> fn = observer;
    SimulatePrescribed(&sim, 0.0, qf0, qdf0, args.t_end, fn, summary, last);
  } else {
    sim.Simulate(0.0, qf0, qdf0, args.t_end, observer, summary, last);
  }
  return Evaluated::kRan;
}

template <class M, template <int> class Method>
int RunFree(const M& model, const SimulateRequest& args, const SimulateOutputs& out, const Prepared<M>& p) {
  using C = ModelCalls<M>;
  using Sim = mechgen::dynamics::MinimalDynamics<M, Method>;
  using SampleT = typename Sim::SampleT;
  const char* const name = C::Name(model);
  const typename ModelTypes<M>::Params& params = p.params;
  const bool angle = C::QIsAngle(model, 0);

  const std::string csv_path = CsvPath(out, name);
  // The CSV, written to a temporary file and renamed when whole (io/output_file.h), opened
  // once the model assembled.
  mechgen::OutputFile csv;
  decltype(FreeColumns<M, SampleT, Sim::kHasCoulomb>(false, model)) columns;
  const auto magnitudes = RevoluteMagnitudes<M>(model);
  auto begin = [&](Sim& sim) {
    std::string error;
    if (!csv.Open(csv_path, &error)) {
      std::fprintf(stderr, "error: %s\n", error.c_str());
      return false;
    }
    columns = FreeColumns<M, SampleT, Sim::kHasCoulomb>(sim.SimulatesCoulomb(p.q0), model);
    mechgen::WriteCsvHeader(columns, csv.stream(), SimulateCsvOptions(name, "free motion"));
    return true;
  };

  double max_reaction = 0;
  // The stuck intervals (Coulomb friction): [start, end) from the transition rows.
  std::vector<std::pair<double, double>> stuck;
  bool was_stuck = false;

  // Several inputs: each friction joint's stuck intervals (num_friction of at most
  // Sim::kMaxFriction: the view's count at run time).
  const int num_friction = Sim::kNumFriction == Eigen::Dynamic ? C::KinetoNumFriction(model) : Sim::kNumFriction;
  std::array<std::vector<std::pair<double, double>>, Sim::kMaxFriction> joint_stuck;
  std::array<bool, Sim::kMaxFriction> joint_was_stuck{};
  auto row = [&](const CsvRow<SampleT>& r) {
    const SampleT& s = *r.s;
    if (s.stuck && !was_stuck) stuck.emplace_back(s.t, std::numeric_limits<double>::quiet_NaN());
    if (!s.stuck && was_stuck) stuck.back().second = s.t;
    was_stuck = s.stuck;
    for (int J = 0; J < num_friction; ++J) {
      if (s.joint_stuck[J] && !joint_was_stuck[J])
        joint_stuck[J].emplace_back(s.t, std::numeric_limits<double>::quiet_NaN());
      if (!s.joint_stuck[J] && joint_was_stuck[J]) joint_stuck[J].back().second = s.t;
      joint_was_stuck[J] = s.joint_stuck[J];
    }
    if (r.R != nullptr)
      for (const auto& m : magnitudes) max_reaction = std::max(max_reaction, std::hypot(r.R[m.first], r.R[m.first + 1]));
    mechgen::WriteCsvRow(columns, r, csv.stream());
    return true;
  };

  mechgen::dynamics::MinimalSummary summary;
  SampleT last;
  const Evaluated evaluated = EvaluateFree<M, Method>(model, args, p, true, begin, row, &summary, &last);
  if (evaluated == Evaluated::kNotAssembled)
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs\n", name);
  if (evaluated != Evaluated::kRan) return 1;
  if (!CommitCsv(&csv)) return 1;
  const bool failure = mechgen::dynamics::IsFailure(summary.status);
  if (!out.quiet) {
    if (const std::string changed = tools::ChangedModelParameters(model, params); !changed.empty())
      std::printf("parameters set: %s\n", changed.c_str());
    std::printf("%s: %s\n", name, mechgen::dynamics::FormatSummary(summary).c_str());
    if constexpr (Sim::kHasCoulomb) {
     if (summary.coulomb) {
      auto list = [](const char* what, const std::vector<std::pair<double, double>>& intervals) {
        std::printf("%s:", what);
        if (intervals.empty()) std::printf(" never");
        constexpr size_t kListed = 20;
        for (size_t i = 0; i < intervals.size() && i < kListed; ++i) {
          if (std::isnan(intervals[i].second)) {
            std::printf(" [%.9g s, end)", intervals[i].first);
          } else {
            std::printf(" [%.9g s, %.9g s)", intervals[i].first, intervals[i].second);
          }
        }
        if (intervals.size() > kListed) std::printf(" ... (%zu intervals)", intervals.size());
        std::printf("\n");
      };
      if (C::Nq(model) == 1) {
        list("stuck by static friction", stuck);
      } else {
        for (int J = 0; J < num_friction; ++J)
          list((std::string("joint ") + C::FrictionJoint(model, J) + " stuck by static friction").c_str(),
               joint_stuck[J]);
      }
     }
    }
    const auto& steady = summary.steady;
    if (steady.steady) {
      std::printf("steady state at t = %.6g s: revolution time %.6g s (mean speed %.6g rad/s)\n",
                  steady.t_steady, steady.period, steady.mean_speed);
    } else if (angle && args.steady) {
      std::printf("no periodic steady state detected (%d revolutions)\n", steady.cycles);
    }
    // Units said: an angle in rad (and deg), a slide in m.
    const bool q0_angle = C::QIsAngle(model, 0);
    std::printf("end: t = %.6g s, %s = %.6g %s", summary.t_end, C::QName(model, 0), last.q(0), q0_angle ? "rad" : "m");
    if (q0_angle) std::printf(" (%.6g deg)", mechgen::ToDegrees(last.q(0)));
    std::printf(", %s_dot = %.6g %s; E - W_nc drift %.3g J; max |F| %.6g N\n", C::QName(model, 0), last.qd(0),
                q0_angle ? "rad/s" : "m/s", summary.max_energy_error, max_reaction);
    std::string png = csv_path;
    if (png.size() > 4 && png.compare(png.size() - 4, 4, ".csv") == 0) png.resize(png.size() - 4);
    png += ".png";
    std::printf("wrote %s (%d rows); plot: gnuplot -e \"csv='%s'; png='%s'\" plot_dynamics.gnuplot\n",
                csv_path.c_str(), summary.samples, csv_path.c_str(), png.c_str());
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s: %s\n", name,
                 mechgen::dynamics::ToString(summary.status), summary.t_end, summary.message);
    return 1;
  }
  return 0;
}

// The run with NP of the inputs driven (drives): PrescribedDynamics (through the view NP is
// Eigen::Dynamic: the number of drives, at run time).
template <class M, template <int> class Method, int NP>
int RunDriven(const M& model, const SimulateRequest& args, const SimulateOutputs& out, Prepared<M>* p) {
  namespace dyn = mechgen::dynamics;
  using C = ModelCalls<M>;
  using Drive = dyn::AnyDrive<NP>;
  using Sim = dyn::PrescribedDynamics<M, NP, Drive, dyn::NoForce, Method>;
  using SampleT = typename Sim::SampleT;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  const int np = static_cast<int>(p->driven.size());
  const typename ModelTypes<M>::Params& params = p->params;
  const typename Sim::Indices prescribed = DrivenIndices<NP, Sim>(p->driven);

  const std::string csv_path = CsvPath(out, name);
  // The CSV, written to a temporary file and renamed when whole (io/output_file.h), opened
  // once the model assembled.
  mechgen::OutputFile csv;
  decltype(DrivenColumns<M, SampleT>(prescribed, false, model)) columns;
  auto begin = [&](Sim& sim) {
    std::string error;
    if (!csv.Open(csv_path, &error)) {
      std::fprintf(stderr, "error: %s\n", error.c_str());
      return false;
    }
    bool coulomb = false;  // the run has the friction (a joint with a coefficient at q0)
    if constexpr (Sim::kHasDrivenFriction) {
      if (args.friction != "off") {
        if constexpr (C::kView) {
          coulomb = sim.SimulatesCoulombAt(p->q0);
        } else {
          mechgen::dynamics::MinimalDynamics<M, Method> probe(params);
          coulomb = probe.Initialize(p->q0) && probe.SimulatesCoulomb(p->q0);
        }
      }
    }
    (void)sim;
    columns = DrivenColumns<M, SampleT>(prescribed, coulomb, model);
    mechgen::WriteCsvHeader(columns, csv.stream(), SimulateCsvOptions(name, "driven motion"));
    return true;
  };
  // The summary's extremes: each lambda's range and the largest bearing load (|F| at a
  // revolute joint) over the written rows.
  const auto magnitudes = RevoluteMagnitudes<M>(model);
  std::array<double, ModelTypes<M>::kMaxQ> lambda_min, lambda_max;
  lambda_min.fill(std::numeric_limits<double>::infinity());
  lambda_max.fill(-std::numeric_limits<double>::infinity());
  double max_reaction = 0;
  std::string max_reaction_joint;
  auto row = [&](const CsvRow<SampleT>& r) {
    const SampleT& s = *r.s;
    for (int i = 0; i < np; ++i) {
      if (!std::isfinite(s.lambda(i))) continue;
      lambda_min[i] = std::min(lambda_min[i], double(s.lambda(i)));
      lambda_max[i] = std::max(lambda_max[i], double(s.lambda(i)));
    }
    if (r.R != nullptr) {
      for (const auto& m : magnitudes) {
        const double f = std::hypot(r.R[m.first], r.R[m.first + 1]);
        if (f > max_reaction) {
          max_reaction = f;
          max_reaction_joint = m.second;
        }
      }
    }
    mechgen::WriteCsvRow(columns, r, csv.stream());
    return true;
  };
  dyn::PrescribedSummary summary;
  SampleT last;
  const Evaluated evaluated = EvaluateDriven<M, Method, NP>(model, args, p, true, begin, row, &summary, &last);
  if (evaluated == Evaluated::kNotAssembled)
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs and the drives' t = 0\n", name);
  if (evaluated != Evaluated::kRan) return 1;
  if (!CommitCsv(&csv)) return 1;
  const bool failure = dyn::IsFailure(summary.status);
  if (!out.quiet) {
    if (const std::string changed = tools::ChangedModelParameters(model, params); !changed.empty())
      std::printf("parameters set: %s\n", changed.c_str());
    std::printf("%s (%d of %d inputs driven): %s\n", name, np, nq, dyn::FormatSummary(summary).c_str());
    for (int i = 0; i < np; ++i) {
      const char* q_name = C::QName(model, prescribed[i]);
      const bool angle = C::QIsAngle(model, prescribed[i]);
      // (a run that ended before its first sample: the view's last sample has no lambda)
      const double lambda_end =
          i < last.lambda.size() ? double(last.lambda(i)) : std::numeric_limits<double>::quiet_NaN();
      if (std::isfinite(lambda_end))
        std::printf("end: lambda_%s = %.6g %s (the actuator force the law needs)\n", q_name, lambda_end,
                    angle ? "N m" : "N");
      else
        std::printf("end: lambda_%s withheld (a singular configuration)\n", q_name);
      if (lambda_min[i] <= lambda_max[i])
        std::printf("  over the run: lambda_%s from %.6g to %.6g %s\n", q_name, lambda_min[i], lambda_max[i],
                    angle ? "N m" : "N");
    }
    if (!max_reaction_joint.empty())
      std::printf("largest bearing load: %.6g N at joint %s (inertia forces included)\n", max_reaction,
                  max_reaction_joint.c_str());
    std::printf("wrote %s (%d rows)\n", csv_path.c_str(), summary.samples);
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s (1/cond(Phi_phi) = %.3g): %s\n", name,
                 dyn::ToString(summary.status), summary.t_end, last.rcond, summary.message);
    return 1;
  }
  return 0;
}

// RunDriven with NP = the number of drives (1 ... kNq; more: Prepare's usage error).
template <class M, template <int> class Method, int NP = 1>
int DispatchDriven(const M& model, const SimulateRequest& args, const SimulateOutputs& out, Prepared<M>* p) {
  if constexpr (NP < M::kNq) {
    if (static_cast<int>(p->driven.size()) != NP) return DispatchDriven<M, Method, NP + 1>(model, args, out, p);
  }
  return RunDriven<M, Method, NP>(model, args, out, p);
}

#if MECHGEN_SIMULATE_HAS_SENSITIVITY
/// design's run: defined in analysis/simulate_design.h (dynamics/sensitivity.h, ceres::Jet), which
/// a program running Run includes (the per-model tool; for the view runtime/view/analysis_simulate_design.cc).
template <class M, template <int> class Method>
int RunDesign(const M& model, const SimulateRequest& args, const SimulateOutputs& out, const Prepared<M>& p);
#endif

}  // namespace simulate_internal

/// What is wrong with `request` on `model` (one line), empty when Run can go on: the model's
/// dynamics, design (the model's `design` section and the options it excludes; through the
/// view, not yet), the number of drives, the parameters, q0 and qd0 against the inputs, each
/// drive's input and law (a table's file read), friction on against the model's friction.
template <class M>
std::string Check(const M& model, const SimulateRequest& request) {
  simulate_internal::Prepared<M> p;
  const std::string error = simulate_internal::Prepare(model, request, &p);
  if (p.refusal == simulate_internal::Refusal::kNotThroughView) return error + " not reached through the model view yet";
  return error;
}

/**
 * \brief The simulation of `model` asked for by `request`: the free motion, the driven one or
 * (a generated model) the free motion with its trajectory sensitivities.
 * \tparam M  A generated model (the per-model tool) or mechgen::ViewModel.
 * \return The exit status (0, 1, 2: tools/simulate_main.cc; through the view, design:
 *         outputs.not_through_view's).
 */
template <class M>
int Run(const M& model, const SimulateRequest& request, const SimulateOutputs& outputs) {
  using namespace simulate_internal;
  using C = ModelCalls<M>;
  namespace dyn = mechgen::dynamics;
  const char* const name = C::Name(model);
  Prepared<M> p;
  if (const std::string error = Prepare(model, request, &p); !error.empty()) {
    if (p.refusal == Refusal::kNoDynamics) {
      std::fprintf(stderr, "%s: %s\n", name, error.c_str());
      return tools::kExitUsage;
    }
    if (p.refusal == Refusal::kNotThroughView && outputs.not_through_view) return outputs.not_through_view(error, name);
    return tools::UsageError(outputs.tool, p.refusal == Refusal::kNotThroughView
                                               ? error + " not reached through the model view yet"
                                               : error);
  }
  if constexpr (mechgen::HasDynamics<M>::value) {
    const bool dop853 = request.method == "dop853";
#if MECHGEN_SIMULATE_HAS_SENSITIVITY
    if constexpr (mechgen::HasDynamicsDesign<M>::value) {  // (a ViewModel's: its model's, at run time)
      if (request.design)
        return dop853 ? RunDesign<M, dyn::Dop853>(model, request, outputs, p)
                      : RunDesign<M, dyn::Dopri5>(model, request, outputs, p);
    }
#endif
    if (!request.drives.empty()) {
      // The driven motion: as many inputs driven as drives (1 ... the model's inputs).
      if constexpr (C::kView) {
        return dop853 ? RunDriven<M, dyn::Dop853, Eigen::Dynamic>(model, request, outputs, &p)
                      : RunDriven<M, dyn::Dopri5, Eigen::Dynamic>(model, request, outputs, &p);
      } else {
        return dop853 ? DispatchDriven<M, dyn::Dop853>(model, request, outputs, &p)
                      : DispatchDriven<M, dyn::Dopri5>(model, request, outputs, &p);
      }
    }
    return dop853 ? RunFree<M, dyn::Dop853>(model, request, outputs, p)
                  : RunFree<M, dyn::Dopri5>(model, request, outputs, p);
  } else {
    return tools::kExitUsage;  // (Prepare said: no dynamics)
  }
}

}  // namespace mechgen::analysis
