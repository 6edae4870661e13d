// The simulate command's model-dependent part, RunSimulate(model, arguments): one source for
// the per-model tool <model>_simulate (simulate_main.cc, M the generated model's type, fixed
// sizes) and for the runtime instantiated once for the model view (M = mechgen::ViewModel,
// core/view_runtime.h; the library mechgen_runtime_view, `mechgen_view simulate`). It checks the
// options against the model, assembles, integrates (rows streamed to the CSV), prints the
// summary and writes the CSV whole or not at all. Exit statuses and the CSV's columns as
// simulate_main.cc says.
//
// --params/--set read the view's parameter table (common/view_params.h). Coulomb friction with
// stick and slip goes through the view, of one input and of several (each joint's own stick
// and slip); --drive (the driven motion, dynamics/prescribed.h) goes through the view with the
// driven inputs counted at run time. Through the view, not yet: --design (the trajectory
// sensitivities, dynamics/sensitivity.h): it is refused
// (common/not_through_view.h: a usage error naming the per-model tool that has it, or for
// mechgen the fallback to that tool) before anything is computed or written.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/numbers.h"
#include "common/not_through_view.h"
#include "common/view_params.h"
#include "simulate_args.h"

#include "mechgen/core/model_calls.h"
#include "mechgen/dynamics/columns.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "mechgen/dynamics/prescribed.h"
#if __has_include(<ceres/jet.h>)  // --design: the trajectory sensitivities need ceres::Jet (a header)
#include "mechgen/dynamics/sensitivity.h"
#define MECHGEN_SIMULATE_HAS_SENSITIVITY 1
#else
#define MECHGEN_SIMULATE_HAS_SENSITIVITY 0
#endif
#include "mechgen/io/csv.h"
#include "mechgen/io/output_file.h"
#include "mechgen/statics/traits.h"
#include "mechgen/table/columns.h"

namespace mechgen::simulate_tool {
namespace run_internal {


constexpr double kTwoPi = 6.283185307179586;

namespace tools = mechgen::tools;

using mechgen::simulate_tool::Arguments;

using Args = mechgen::simulate_tool::Arguments;
using mechgen::simulate_tool::DriveSpec;
using mechgen::simulate_tool::ParseList;

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
    if (!ParseList(line, &values) || values.size() != 2) {
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

// The inputs' initial values and speeds from the model's assembly, --q0 and --qd0. 0 or the
// usage error's exit status.
template <class M, class VecQ>
int InitialState(const M& model, const Args& args, VecQ* q0, VecQ* qd0) {
  const int kNq = ModelCalls<M>::Nq(model);
  *q0 = Sized<VecQ>(kNq);
  *qd0 = Sized<VecQ>(kNq);
  qd0->setZero();
  for (int i = 0; i < kNq; ++i) (*q0)(i) = ModelCalls<M>::AssemblyQ(model)[i];
  if (!args.q0.empty()) {
    if (static_cast<int>(args.q0.size()) != kNq) {
      return tools::UsageError(args.tool, "--q0: bad value " + tools::Quote(args.q0_text) +
                                              ": expected " + std::to_string(kNq) +
                                              " value(s), one per input");
    }
    for (int i = 0; i < kNq; ++i) (*q0)(i) = args.q0[i];
  }
  if (!args.qd0.empty()) {
    if (static_cast<int>(args.qd0.size()) != kNq) {
      return tools::UsageError(args.tool, "--qd0: bad value " + tools::Quote(args.qd0_text) +
                                              ": expected " + std::to_string(kNq) +
                                              " value(s), one per input");
    }
    for (int i = 0; i < kNq; ++i) (*qd0)(i) = args.qd0[i];
  }
  return 0;
}

template <class M, template <int> class Method>
int RunFree(const M& model, const Args& args) {
  using C = ModelCalls<M>;
  using Sim = mechgen::dynamics::MinimalDynamics<M, Method>;
  using Kineto = mechgen::dynamics::Kinetostatics<M>;
  using VecQ = typename Sim::VecQ;
  using SampleT = typename Sim::SampleT;
  const char* const name = C::Name(model);
  const int num_reactions = C::KinetoNumReactions(model);
  typename ModelTypes<M>::Params params = C::DefaultParams(model);
  if (std::string why; !tools::ApplyModelParameters(args.params, model, &params, &why))
    return tools::UsageError(args.tool, why);

  VecQ q0, qd0;
  if (const int status = InitialState(model, args, &q0, &qd0); status != 0) return status;

  mechgen::dynamics::MinimalOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  options.energy_projection = args.energy_projection;
  options.stop_at_speed_zero = args.stop_at_speed_zero;
  // Steady state: the simulator's detection (dynamics/simulator.h) per revolution of the first
  // input, an angle: the cycle-mean speed settled to --steady-tol over two successive cycles.
  const bool angle = C::QIsAngle(model, 0);
  options.steady.enabled = angle && args.steady;
  options.steady.coordinate = 0;
  options.steady.cycle = kTwoPi;
  options.steady.tolerance = args.steady_tol;
  options.steady.consecutive = 2;
  // Coulomb friction: the model's friction section unless --friction says otherwise.
  if (args.friction == "on" && (!Sim::kHasCoulomb || C::KinetoNumFriction(model) == 0)) {
    return tools::UsageError(args.tool, "--friction on: the model has no friction joints (`friction:`)");
  }
  options.coulomb.enabled = args.friction != "off";
  Sim sim(model, params, options);
  if (!sim.Initialize(q0)) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs\n", name);
    return 1;
  }
  Kineto kineto(model, params);
  kineto.Initialize(q0);
  // The kinetostatics' friction loads where the simulation has none (the view, --friction
  // off): zeros, as a run without Coulomb friction's samples hold.
  typename Kineto::VecF no_friction = Sized<typename Kineto::VecF>(C::KinetoNumFriction(model));
  no_friction.setZero();
  (void)num_reactions, (void)no_friction;  // (a model without reactions reads neither)

  const std::string csv_path = args.csv.empty() ? std::string(name) + "_simulate.csv" : args.csv;
  // The CSV, written to a temporary file and renamed when whole (io/output_file.h).
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  const auto columns = FreeColumns<M, SampleT, Sim::kHasCoulomb>(sim.SimulatesCoulomb(q0), model);
  const auto magnitudes = RevoluteMagnitudes<M>(model);
  mechgen::WriteCsvHeader(columns, csv.stream(), SimulateCsvOptions(name, "free motion"));

  double max_reaction = 0;
  // The stuck intervals (Coulomb friction): [start, end) from the transition rows.
  std::vector<std::pair<double, double>> stuck;
  bool was_stuck = false;

  // Several inputs: each friction joint's stuck intervals (num_friction of at most
  // Sim::kMaxFriction: the view's count at run time).
  const int num_friction = Sim::kNumFriction == Eigen::Dynamic ? C::KinetoNumFriction(model) : Sim::kNumFriction;
  std::array<std::vector<std::pair<double, double>>, Sim::kMaxFriction> joint_stuck;
  std::array<bool, Sim::kMaxFriction> joint_was_stuck{};
  auto observer = [&](const SampleT& s) {
    if (s.stuck && !was_stuck) stuck.emplace_back(s.t, std::numeric_limits<double>::quiet_NaN());
    if (!s.stuck && was_stuck) stuck.back().second = s.t;
    was_stuck = s.stuck;
    for (int J = 0; J < num_friction; ++J) {
      if (s.joint_stuck[J] && !joint_was_stuck[J])
        joint_stuck[J].emplace_back(s.t, std::numeric_limits<double>::quiet_NaN());
      if (!s.joint_stuck[J] && joint_was_stuck[J]) joint_stuck[J].back().second = s.t;
      joint_was_stuck[J] = s.joint_stuck[J];
    }
    // The row is written inside the branch that holds the kinetostatics it points into.
    CsvRow<SampleT> row{&s, nullptr};
    if constexpr (Kineto::kMayHaveReactions) {
      if (num_reactions > 0) {
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
        if (k.status == mechgen::dynamics::KinetostaticsStatus::kOk) {
          row.R = k.statics.R.data();
          for (const auto& m : magnitudes)
            max_reaction = std::max(max_reaction, std::hypot(k.statics.R(m.first), k.statics.R(m.first + 1)));
        }
        mechgen::WriteCsvRow(columns, row, csv.stream());
        return true;
      }
    }
    mechgen::WriteCsvRow(columns, row, csv.stream());
    return true;
  };

  mechgen::dynamics::MinimalSummary summary;
  SampleT last;
  if constexpr (C::kView) {
    // The runtime instantiated for the view (core/view_runtime.h; found by its argument).
    dynamics::ViewSampleFn<Sim> fn = observer;
    SimulateFree(&sim, 0.0, q0, qd0, args.t_end, fn, &summary, &last);
  } else {
    sim.Simulate(0.0, q0, qd0, args.t_end, observer, &summary, &last);
  }
  if (!CommitCsv(&csv)) return 1;
  const bool failure = mechgen::dynamics::IsFailure(summary.status);
  if (!args.quiet) {
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

// The run with NP of the inputs driven (--drive): PrescribedDynamics (through the view NP is
// Eigen::Dynamic: the number of --drive options, at run time).
template <class M, template <int> class Method, int NP>
int RunDriven(const M& model, const Args& args) {
  namespace dyn = mechgen::dynamics;
  using C = ModelCalls<M>;
  using Drive = dyn::AnyDrive<NP>;
  using Sim = dyn::PrescribedDynamics<M, NP, Drive, dyn::NoForce, Method>;
  using VecQ = typename Sim::VecQ;
  using VecF = typename Sim::VecF;
  using SampleT = typename Sim::SampleT;
  using Kineto = mechgen::dynamics::Kinetostatics<M>;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  const int np = static_cast<int>(args.drives.size());
  typename ModelTypes<M>::Params params = C::DefaultParams(model);
  if (std::string why; !tools::ApplyModelParameters(args.params, model, &params, &why))
    return tools::UsageError(args.tool, why);

  VecQ q0, qd0;
  if (const int status = InitialState(model, args, &q0, &qd0); status != 0) return status;
  typename Sim::Indices prescribed{};
  typename Drive::Laws laws{};
  if constexpr (NP == Eigen::Dynamic) laws.resize(static_cast<size_t>(np));
  for (int i = 0; i < np; ++i) {
    const DriveSpec& d = args.drives[i];
    int k = -1;
    for (int j = 0; j < nq; ++j)
      if (d.name == C::QName(model, j)) k = j;
    if (k < 0) {
      std::string names;
      for (int j = 0; j < nq; ++j) names += std::string(j ? ", " : "") + C::QName(model, j);
      return tools::UsageError(args.tool, "--drive: bad value " + tools::Quote(d.text) +
                                              ": the model has no input " +
                                              tools::Quote(d.name) + " (its inputs: " + names +
                                              ")");
    }
    for (int j = 0; j < i; ++j) {
      if (prescribed[j] == k) {
        return tools::UsageError(args.tool, "--drive: bad value " + tools::Quote(d.text) +
                                                ": input " + tools::Quote(d.name) +
                                                " is driven twice");
      }
    }
    if constexpr (NP == Eigen::Dynamic) {
      prescribed.push_back(k);
    } else {
      prescribed[i] = k;
    }
    if (d.kind == "speed") {
      laws[i] = dyn::ConstantSpeedLaw{q0(k), d.values[0], 0.0};
    } else if (d.kind == "move" || d.kind == "cycloidal") {
      laws[i] = dyn::RestToRestLaw{q0(k), d.values[0], d.values[1], d.values[2],
                                   d.kind == "move" ? dyn::RestToRestLaw::Profile::kPoly345
                                                    : dyn::RestToRestLaw::Profile::kCycloidal};
    } else {
      std::vector<double> t, q;
      std::string error;
      if (!ReadTable(d.file, &t, &q, &error)) {
        return tools::UsageError(args.tool, "--drive: " + tools::Quote(d.text) + ": " + error);
      }
      dyn::TableLaw law(std::move(t), std::move(q));
      if (!law.IsValid()) {
        return tools::UsageError(args.tool, "--drive: " + tools::Quote(d.text) + ": the times of " +
                                                d.file +
                                                " must increase strictly and every value be "
                                                "finite");
      }
      laws[i] = std::move(law);
    }
  }

  dyn::PrescribedOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  // Coulomb friction in the actuator forces: every input driven (else --friction on is a usage
  // error, and the run without it says so).
  const bool has_friction = dyn::CoulombFeatures<M>::kHasFriction && C::KinetoNumFriction(model) > 0;
  if (args.friction == "on" && !(Sim::kHasDrivenFriction && has_friction && np == nq)) {
    return tools::UsageError(args.tool,
                             has_friction
                                 ? "--friction on: Coulomb friction is simulated in a driven run only when every "
                                   "input is driven (--drive each)"
                                 : "--friction on: the model has no friction joints (`friction:`)");
  }
  options.coulomb.enabled = args.friction != "off";
  Sim sim(model, params, prescribed, Drive(std::move(laws)), dyn::NoForce(), options);
  VecF qf0 = Sized<VecF>(nq - np), qdf0 = Sized<VecF>(nq - np);
  for (int i = 0; i < nq - np; ++i) {
    qf0(i) = q0(sim.free()[i]);
    qdf0(i) = qd0(sim.free()[i]);
  }
  bool assembled = false;
  if constexpr (C::kView) {
    assembled = InitializePrescribed(&sim, 0.0, qf0);  // (the library's, core/view_runtime.h)
  } else {
    assembled = sim.Initialize(0.0, qf0);
  }
  if (!assembled) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs and the drives' t = 0\n", name);
    return 1;
  }
  Kineto kineto(model, params);
  kineto.Initialize(q0);

  const std::string csv_path = args.csv.empty() ? std::string(name) + "_simulate.csv" : args.csv;
  // The CSV, written to a temporary file and renamed when whole (io/output_file.h).
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  bool coulomb = false;  // the run has the friction (a joint with a coefficient at q0)
  if constexpr (Sim::kHasDrivenFriction) {
    if (options.coulomb.enabled) {
      if constexpr (C::kView) {
        coulomb = sim.SimulatesCoulombAt(q0);
      } else {
        mechgen::dynamics::MinimalDynamics<M, Method> probe(params);
        coulomb = probe.Initialize(q0) && probe.SimulatesCoulomb(q0);
      }
    }
  }
  const auto columns = DrivenColumns<M, SampleT>(prescribed, coulomb, model);
  mechgen::WriteCsvHeader(columns, csv.stream(), SimulateCsvOptions(name, "driven motion"));
  // The summary's extremes: each lambda's range and the largest bearing load (|F| at a
  // revolute joint) over the written rows.
  const auto magnitudes = RevoluteMagnitudes<M>(model);
  std::array<double, ModelTypes<M>::kMaxQ> lambda_min, lambda_max;
  lambda_min.fill(std::numeric_limits<double>::infinity());
  lambda_max.fill(-std::numeric_limits<double>::infinity());
  double max_reaction = 0;
  std::string max_reaction_joint;
  auto observer = [&](const SampleT& s) {
    for (int i = 0; i < np; ++i) {
      if (!std::isfinite(s.lambda(i))) continue;
      lambda_min[i] = std::min(lambda_min[i], double(s.lambda(i)));
      lambda_max[i] = std::max(lambda_max[i], double(s.lambda(i)));
    }
    // The row is written inside the branch that holds the kinetostatics it points into.
    CsvRow<SampleT> row{&s, nullptr};
    if constexpr (Kineto::kMayHaveReactions) {
      if (C::KinetoNumReactions(model) > 0) {
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
        if (k.status == mechgen::dynamics::KinetostaticsStatus::kOk) {
          row.R = k.statics.R.data();
          for (const auto& m : magnitudes) {
            const double f = std::hypot(k.statics.R(m.first), k.statics.R(m.first + 1));
            if (f > max_reaction) {
              max_reaction = f;
              max_reaction_joint = m.second;
            }
          }
        }
        mechgen::WriteCsvRow(columns, row, csv.stream());
        return true;
      }
    }
    mechgen::WriteCsvRow(columns, row, csv.stream());
    return true;
  };
  dyn::PrescribedSummary summary;
  SampleT last;
  if constexpr (C::kView) {
    // The runtime instantiated for the view (core/view_runtime.h; found by its argument).
    dyn::ViewSampleFn<Sim> fn = observer;
    SimulatePrescribed(&sim, 0.0, qf0, qdf0, args.t_end, fn, &summary, &last);
  } else {
    sim.Simulate(0.0, qf0, qdf0, args.t_end, observer, &summary, &last);
  }
  if (!CommitCsv(&csv)) return 1;
  const bool failure = dyn::IsFailure(summary.status);
  if (!args.quiet) {
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

#if MECHGEN_SIMULATE_HAS_SENSITIVITY
// The free motion with its trajectory sensitivities (--design; dynamics/sensitivity.h): the
// CSV has t, each input, its speed and acceleration, d<q>/d<p> and d<q>_dot/d<p> for every
// input q and design parameter p (q's unit, or q's unit per second, per unit of p, p in the
// model file's units) and rcond = 1/cond_1(Phi_phi).
template <class M, template <int> class Method>
int RunDesign(const Args& args) {
  using Sim = mechgen::dynamics::TrajectorySensitivity<M, Method>;
  using VecQ = typename Sim::VecQ;
  using SampleT = typename Sim::SampleT;
  constexpr int kNq = M::kNq, kNp = M::kNumDesign;
  typename M::template ParamsT<double> params;
  if (std::string why; !tools::ApplyParameters(args.params, &params, &why)) return tools::UsageError(args.tool, why);
  VecQ q0, qd0;
  if (const int status = InitialState(M(), args, &q0, &qd0); status != 0) return status;
  mechgen::dynamics::SensitivityOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  Sim sim(params, options);
  if (!sim.Initialize(q0)) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs\n", M::kName);
    return 1;
  }
  const std::string csv_path = args.csv.empty() ? std::string(M::kName) + "_simulate.csv" : args.csv;
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  using Row = CsvRow<SampleT>;
  mechgen::table::Columns<Row> columns;
  mechgen::table::Builder<Row> add(&columns);
  auto unit = [](int i, const char* per) { return std::string(M::kQIsAngle[i] ? "rad" : "m") + per; };
  AddInputColumns<M, SampleT>(&add);
  for (int i = 0; i < kNq; ++i)
    for (int d = 0; d < kNp; ++d)
      add.Number(std::string("d") + M::kQNames[i] + "/d" + M::kDesignNames[d],
                 unit(i, " per unit of ") + M::kDesignNames[d], "trajectory sensitivity dq/dp",
                 [i, d](const Row& r) { return r.s->S(i, d); });
  for (int i = 0; i < kNq; ++i)
    for (int d = 0; d < kNp; ++d)
      add.Number(std::string("d") + M::kQNames[i] + "_dot/d" + M::kDesignNames[d],
                 unit(i, "/s per unit of ") + M::kDesignNames[d], "trajectory sensitivity dqd/dp",
                 [i, d](const Row& r) { return r.s->Sd(i, d); });
  add.Number("rcond", "1", "1/cond_1(Phi_phi) (1 without a closed loop)",
             [](const Row& r) { return r.s->rcond; });
  mechgen::WriteCsvHeader(columns, csv.stream(),
                          SimulateCsvOptions(M::kName, "free motion with trajectory sensitivities"));
  SampleT last;
  auto observer = [&](const SampleT& s) {
    mechgen::WriteCsvRow(columns, Row{&s, nullptr}, csv.stream());
    last = s;
    return true;
  };
  mechgen::dynamics::SensitivitySummary summary;
  sim.Simulate(0.0, q0, qd0, args.t_end, observer, &summary);
  if (!CommitCsv(&csv)) return 1;
  const bool failure = mechgen::dynamics::IsFailure(summary.status);
  if (!args.quiet) {
    if (const std::string changed = tools::ChangedParameters(params); !changed.empty())
      std::printf("parameters set: %s\n", changed.c_str());
    std::printf("%s: %s\n", M::kName, mechgen::dynamics::FormatSummary(summary).c_str());
    if (summary.samples > 0) {
      std::printf("end: t = %.6g s, %s = %.9g %s; d%s/dp:", last.t, M::kQNames[0], last.q(0),
                  M::kQIsAngle[0] ? "rad" : "m", M::kQNames[0]);
      for (int d = 0; d < kNp; ++d) std::printf(" %s %.6g%s", M::kDesignNames[d], last.S(0, d), d + 1 < kNp ? "," : "");
      std::printf("\n");
    }
    std::printf("wrote %s (%d rows)\n", csv_path.c_str(), summary.samples);
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s: %s\n", M::kName,
                 mechgen::dynamics::ToString(summary.status), summary.t_end, summary.message);
    return 1;
  }
  return 0;
}
#endif

// RunDriven with NP = the number of --drive options (1 ... kNq).
template <class M, template <int> class Method, int NP = 1>
int DispatchDriven(const Args& args) {
  if constexpr (NP > M::kNq) {
    return tools::UsageError(args.tool, std::to_string(args.drives.size()) +
                                            " --drive options for a model with " +
                                            std::to_string(M::kNq) + " input(s)");
  } else {
    if (static_cast<int>(args.drives.size()) == NP) return RunDriven<M, Method, NP>(M(), args);
    return DispatchDriven<M, Method, NP + 1>(args);
  }
}

// The per-model tool: every option (the view refuses some: RunSimulate).
template <class M>
int Main(const Args& args) {
  {
    if (args.design) {
#if !MECHGEN_SIMULATE_HAS_SENSITIVITY
      return tools::UsageError(args.tool, "--design: this build has no ceres/jet.h (Ceres' headers), which the "
                                          "trajectory sensitivities need");
#else
      if constexpr (!mechgen::HasDynamicsDesign<M>::value) {
        return tools::UsageError(args.tool, "--design: the model has no `design` section (the parameters to "
                                            "differentiate by); add one, e.g. `design: {parameters: all}`");
      } else {
        const char* conflict = !args.drives.empty()          ? "--drive"
                               : args.friction == "on"        ? "--friction on"
                               : args.energy_projection       ? "--energy-projection"
                               : args.stop_at_speed_zero      ? "--stop-at-speed-zero"
                                                              : nullptr;
        if (conflict != nullptr)
          return tools::UsageError(args.tool, std::string("--design: not with ") + conflict +
                                                  " (the sensitivities of the free motion only)");
        return args.method == "dop853" ? RunDesign<M, mechgen::dynamics::Dop853>(args)
                                       : RunDesign<M, mechgen::dynamics::Dopri5>(args);
      }
#endif
    }
    if (!args.drives.empty()) {
      return args.method == "dop853" ? DispatchDriven<M, mechgen::dynamics::Dop853>(args)
                                     : DispatchDriven<M, mechgen::dynamics::Dopri5>(args);
    }
    return args.method == "dop853" ? RunFree<M, mechgen::dynamics::Dop853>(M(), args)
                                   : RunFree<M, mechgen::dynamics::Dopri5>(M(), args);
  }
}


}  // namespace run_internal

/**
 * \brief The simulate command on `model` with the parsed `args` (simulate_args.h).
 * \tparam M  A generated model (the per-model tool) or mechgen::ViewModel.
 * \return The exit status (0, 1, 2: simulate_main.cc).
 */
template <class M>
int RunSimulate(const M& model, const Arguments& args) {
  using namespace run_internal;
  using C = ModelCalls<M>;
  const char* const name = C::Name(model);
  if (!C::HasDynamics(model)) {
    std::fprintf(stderr, "%s: this model was generated without `dynamics` (add it to outputs.quantities)\n", name);
    return 2;
  }
  if constexpr (C::kView) {
    // What the runtime instantiated for the view does not do yet (the file comment).
    if (args.design)
      return tools::NotThroughView(args.tool, "--design: the trajectory sensitivities are", name, "simulate");
    if (!args.drives.empty()) {
      // The driven motion: as many inputs driven as --drive options (1 ... the model's inputs).
      if (static_cast<int>(args.drives.size()) > C::Nq(model))
        return tools::UsageError(args.tool, std::to_string(args.drives.size()) + " --drive options for a model with " +
                                                std::to_string(C::Nq(model)) + " input(s)");
      return args.method == "dop853" ? RunDriven<M, mechgen::dynamics::Dop853, Eigen::Dynamic>(model, args)
                                     : RunDriven<M, mechgen::dynamics::Dopri5, Eigen::Dynamic>(model, args);
    }
    return args.method == "dop853" ? RunFree<M, mechgen::dynamics::Dop853>(model, args)
                                   : RunFree<M, mechgen::dynamics::Dopri5>(model, args);
  } else {
    if constexpr (mechgen::HasDynamics<M>::value) {
      return Main<M>(args);
    } else {
      return 2;  // (said above)
    }
  }
}

}  // namespace mechgen::simulate_tool
