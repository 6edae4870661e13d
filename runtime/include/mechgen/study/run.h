/**
 * \file study/run.h
 * Runs a design study (study/spec.h) on a generated model M: for each sample, the model's
 * parameters set to the sample's values, the mechanism assembled at its assembly
 * configuration, the analysis over the motion (a kinematic sweep, or statics at every row; the
 * machine's cycle at a mean speed; an engine's cycle at a crank speed under its gas law,
 * machines/engine/cycle.h; or a simulation of the free motion), then the sample's
 * metrics from the rows. The metrics read the same column tables as the sweep's, the statics',
 * the simulation's, the flywheel's energy loop and the engine's cycle and energy loop CSVs
 * (sweep/columns.h, statics/columns.h, dynamics/columns.h, analysis/flywheel_columns.h,
 * analysis/engine_columns.h), by their CSV names (mean_torque and peak_torque too: T_mean, the
 * largest |T_req| or |T_total|), and
 * their first-order sensitivities (at the nominal design) read the design columns of those
 * tables: d<column>/d<p> (the generated EvalDesignDerivatives, EvalStaticsDesign).
 *
 * Parallel: Run() and RunPacked() evaluate the samples on `threads` std::threads; each sample
 * is evaluated by one thread with its own solver and rows (nothing is shared but the read-only
 * tables and the work counter, one atomic operation per item of several samples), and its
 * result stored at its index: the results, and so the CSV, are the same bytes for any number
 * of threads. RunPacked (the command's) draws each sample on the thread that runs it and packs
 * its result into the caller's chunk buffer (no allocation per sample), and calls back when a
 * chunk is done, on that thread (its shard, its CSV rows: study/rows.h).
 *
 * One source, two instantiations (issue 43): Study<M> reaches its model through ModelCalls<M>
 * (core/model_calls.h), for a generated model (fixed sizes, the per-model study program) and for
 * mechgen::ViewModel (the runtime compiled once, `mechgen_view study`; the design derivatives
 * of the tolerance analysis, the envelope's first order and the design checks the view's,
 * ModelCalls<M>::Design, StaticsDesign and DesignChecks; the first order of a flywheel study's
 * metrics the view's cycle design derivatives, machines/view_machines.h; the driven simulation
 * dynamics/prescribed.h instantiated for the view).
 * With analysis: flywheel and engine a view's sample runs the machines' cycle compiled once
 * (machines/view_machines.h, declared before this header where the view's study is compiled).
 */
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "mechgen/analysis/engine.h"
#include "mechgen/analysis/engine_columns.h"
#include "mechgen/analysis/flywheel_columns.h"
#include "mechgen/analysis/simulate.h"
#if MECHGEN_SIMULATE_HAS_SENSITIVITY  // (analysis/simulate.h: Ceres' ceres/jet.h is there)
#include "mechgen/analysis/simulate_design.h"
#endif
#include "mechgen/analysis/sweep.h"
#include "mechgen/dynamics/columns.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "mechgen/dynamics/prescribed.h"
#include "mechgen/machines/engine/cycle.h"
#include "mechgen/machines/flywheel/cycle_design.h"
#include "mechgen/machines/flywheel/machine_cycle.h"
#include "mechgen/position/input_step.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/sweep.h"
#include "mechgen/study/samples.h"
#include "mechgen/study/shards.h"
#include "mechgen/study/spec.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen::study {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// What became of one sample.
struct SampleResult {
  /// "ok"; "rows_failed" (some rows of the motion did not converge: the metrics are over the
  /// others, `failures` counts them); "not_assembled" (no configuration at the assembly
  /// inputs: every metric NaN but failures); "cycle_failed" (analysis: flywheel: the cycle is
  /// not usable, machines/flywheel/machine_cycle.h's status; analysis: engine: the positions
  /// failed at a crank angle, the energy loop is not usable or the mean torque not positive,
  /// machines/engine/cycle.h: every metric NaN but failures = 1);
  /// "simulation_failed" (analysis: simulate: the run ended before t_end, dynamics/simulator.h's
  /// status: the metrics are over the samples reached, failures = 1).
  const char* status = "not_run";
  std::vector<double> metrics;
  /// With an envelope: the point's x, y at every row (x0, y0, x1, ...), NaN where a row failed.
  std::vector<double> path;
};

namespace run_internal {
template <class M, bool kStatics = statics::StaticsFeatures<M>::kHasStatics>
struct StaticsRowOf {
  struct type {};
};
template <class M>
struct StaticsRowOf<M, true> {
  using type = statics::StaticsRecord<M>;
};
// The design derivatives a study can read (EvalDesignDerivatives, EvalStaticsDesign): a
// generated model's where it has them; the view's where its model has them
// (ModelCalls<ViewModel>::HasDesign, HasStaticsDesign: checked at run time).
template <class M>
constexpr bool kDesign = HasDesignDerivatives<M>::value;
template <class M>
constexpr bool kStaticsDesign = HasStaticsDesign<M>::value;
// A simulation's sample with the reactions of the generated kinetostatics there (has_R when
// they were found): a row of analysis: simulate, free or driven.
// (The view's count is known at run time: a bounded vector, empty until set.)
template <class SampleT, int kNumReactions>
struct SimulatedRow {
  SampleT s;
  using VecR = std::conditional_t<kNumReactions == Eigen::Dynamic,
                                  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, ModelView::kMaxReactions, 1>,
                                  Eigen::Matrix<double, (kNumReactions > 0 ? kNumReactions : 1), 1>>;
  VecR R = ZeroVector();
  bool has_R = false;
  static VecR ZeroVector() {
    if constexpr (kNumReactions == Eigen::Dynamic) {
      return VecR();
    } else {
      return VecR::Zero();
    }
  }
};
// analysis: simulate: the free motion of a model with `dynamics` and M::Solve
// (dynamics/forward.h), a sample and the reactions of the generated kinetostatics there.
template <class M, bool = HasDynamics<M>::value && ModelFeatures<M>::kHasSolve>
struct SimulationOf {
  static constexpr bool kOk = false;
  struct Row {};
  using Columns = std::vector<int>;
};
template <class M>
struct SimulationOf<M, true> {
  static constexpr bool kOk = true;
  using Sim = dynamics::MinimalDynamics<M>;
  using SampleT = typename Sim::SampleT;
  static constexpr int kNumReactions = statics::StaticsFeatures<M>::kNumReactions;
  using Row = SimulatedRow<SampleT, kNumReactions>;
  using Columns = table::Columns<dynamics::CsvRow<SampleT>>;
};
// analysis: simulate with drive: one input on a law of time, the others free
// (dynamics/prescribed.h's PrescribedDynamics, as `<model>_simulate --drive`), a sample with the
// actuator force lambda and the reactions of the generated kinetostatics there. (Through the
// model view: the driven run instantiated in mechgen_runtime_view, core/view_runtime.h, its
// one driven input counted at run time.)
template <class M, bool = HasDynamics<M>::value && ModelFeatures<M>::kHasSolve>
struct DrivenOf {
  static constexpr bool kOk = false;
  struct Row {};
  using Columns = std::vector<int>;
};
template <class M>
struct DrivenOf<M, true> {
  static constexpr bool kOk = true;
  static constexpr int kNp = ModelCalls<M>::kView ? Eigen::Dynamic : 1;
  using Drive = dynamics::AnyDrive<kNp>;
  using Sim = dynamics::PrescribedDynamics<M, kNp, Drive>;
  using SampleT = typename Sim::SampleT;
  static constexpr int kNumReactions = statics::StaticsFeatures<M>::kNumReactions;
  using Row = SimulatedRow<SampleT, kNumReactions>;
  using Columns = table::Columns<dynamics::CsvRow<SampleT>>;
  /// The indices of the one driven input k.
  static typename Sim::Indices Driven(int k) {
    typename Sim::Indices indices{};
    if constexpr (kNp == Eigen::Dynamic) {
      indices.push_back(k);
    } else {
      indices[0] = k;
    }
    return indices;
  }
};
// analysis: engine: the engine's cycle at its crank angles (machines/engine/cycle.h's
// CrankPoint) and the columns of the engine tool's cycle CSV (analysis/engine_columns.h).
template <class M, bool = engine::CanRunEngineCycle<M>()>
struct EngineOf {
  using Points = std::vector<int>;
  using Columns = std::vector<int>;
};
template <class M>
struct EngineOf<M, true> {
  using Points = std::vector<engine::CrankPoint<M>>;
  using Columns = table::Columns<engine::CrankPoint<M>>;
};
}  // namespace run_internal

/// A study of model M: the spec checked against the model, the tables, the nominal rows. M is
/// a generated model (an empty tag: Study()) or mechgen::ViewModel (Study(model)).
template <class M>
class Study {
 public:
  using C = ModelCalls<M>;
  using Params = typename ModelTypes<M>::Params;
  using Kinematics = SweepRecord<M>;
  using StaticsRow = typename run_internal::StaticsRowOf<M>::type;
  static constexpr bool kHasStatics = statics::StaticsFeatures<M>::kHasStatics;
  static constexpr bool kView = C::kView;
  static constexpr bool kDesign = run_internal::kDesign<M>;
  static constexpr bool kStaticsDesign = run_internal::kStaticsDesign<M>;

  /// A study of the generated model M (its parameters' defaults the base). (A template, so
  /// that the explicit instantiation of Study<ViewModel>, which has no default model, skips it.)
  template <class X = M, std::enable_if_t<!ModelCalls<X>::kView, int> = 0>
  Study() : model_(), base_(C::DefaultParams(model_)) {}
  /// A study of `model` (a ViewModel; the view must outlive the study).
  explicit Study(const M& model) : model_(model), base_(C::DefaultParams(model_)) {}
  const M& model() const { return model_; }

  /// The rows of one sample's motion.
  struct Rows {
    std::vector<Kinematics> kinematics;
    std::vector<StaticsRow> statics;  ///< statics analysis only
    flywheel::MachineCycle cycle;     ///< flywheel analysis only
    flywheel::CycleDesign<M> cycle_design;  ///< flywheel analysis, the nominal's (first order) only
    /// simulate analysis: the samples (every t_end / steps, and where friction sticks or slips)
    /// and how the run ended.
    std::vector<typename run_internal::SimulationOf<M>::Row> simulation;
    /// simulate with drive: the samples of the driven run (its actuator force lambda).
    std::vector<typename run_internal::DrivenOf<M>::Row> driven;
    dynamics::Status simulation_status = dynamics::Status::kNotRun;
    /// engine analysis: the energy loop of the engine's cycle (machines/engine/cycle.h), the
    /// model's own flywheel J_fly, and why the cycle failed (engine.message).
    engine::EngineEnergy engine;
    double engine_J_fly = 0;
    /// engine analysis: the cycle's crank angles (the rows of the engine tool's cycle CSV) and
    /// the cycle's length (rad: the energy loop's rows).
    typename run_internal::EngineOf<M>::Points engine_points;
    double engine_cycle = 0;
    Params params;
    bool assembled = false;  ///< flywheel: the cycle is usable
    bool kinematics_design = false;  ///< kinematics hold design derivatives (the nominal's rows)
  };

  /// The model's parameters that the study's do not vary (and the nominal of those without
  /// nominal:): the generated defaults unless set here before Prepare (`--params`, `--set`).
  void SetBase(const Params& base) { base_ = base; }
  const Params& base() const { return base_; }

  /// Checks the names of `spec` against M and builds the tables; false and *error
  /// ("file:line:column: error: ...") when the study does not fit the model.
  bool Prepare(const StudySpec& spec, std::string* error) {
    spec_ = spec;
    driven_input_ = -1;
    sweep_request_ = analysis::SweepRequest();
    sweep_request_.steps = spec.steps;
    auto fail = [&](Place p, const std::string& message) {
      *error = spec.path + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": error: " + message;
      return false;
    };
    const std::string names = ParameterNames();
    const char* const name = C::Name(model_);
    nominal_.clear();
    index_.clear();
    for (const ParameterSpec& p : spec.parameters) {
      Params probe = base_;
      double* target = Parameter(&probe, p.name);
      if (IsDerived(p.name))
        return fail(p.place,
                    "'" + p.name + "' is a derived parameter of the model; vary the parameters it is defined by");
      if (target == nullptr)
        return fail(p.place, "no parameter '" + p.name + "' in the model " + name + " (parameters: " + names + ")");
      nominal_.push_back(p.has_nominal ? p.nominal : *target);
      if (spec.method != Method::kGrid && spec.method != Method::kList && !SpreadFits(p, nominal_.back())) {
        char value[32];
        std::snprintf(value, sizeof(value), "%g", nominal_.back());
        return fail(p.place, "parameter '" + p.name + "' about the model's value " + value + ": " + SpreadProblem(p));
      }
      int design = -1;
      if constexpr (kDesign)
        for (int d = 0; d < C::NumDesign(model_); ++d)  // (0 without a design section)
          if (p.name == C::DesignName(model_, d)) design = d;
      index_.push_back(design);
    }
    for (const ClearanceSpec& c : spec.clearances) {
      bool found = false;
      for (const ParameterSpec& p : spec.parameters) found = found || p.name == c.parameter;
      if (!found)
        return fail(c.place, "the clearance of joint '" + c.joint + "' changes '" + c.parameter +
                                 "', which is not among the study's parameters; add it there (its tolerance)");
    }
    const int nq = C::Nq(model_);
    if (spec.analysis == Analysis::kStatics && !HasStatics())
      return fail(spec.analysis_place,
                  std::string("analysis: statics needs a model with `forces` among its outputs' quantities; ") +
                      name + " has none (use analysis: sweep, or add forces)");
    if (spec.analysis == Analysis::kSimulate) {
      if (!SimulationOk())
        return fail(spec.analysis_place, std::string("analysis: simulate needs a model with `dynamics` among its "
                                                     "outputs' quantities; ") +
                                             name + " has none");
      if (!spec.q0.empty() && static_cast<int>(spec.q0.size()) != nq)
        return fail(spec.q0_place, "q0: expected " + std::to_string(nq) + " value(s), one per input");
      if (!spec.qd0.empty() && static_cast<int>(spec.qd0.size()) != nq)
        return fail(spec.qd0_place, "qd0: expected " + std::to_string(nq) + " value(s), one per input");
      driven_input_ = -1;
      if (!spec.drive.input.empty()) {
        std::string inputs;
        for (int j = 0; j < nq; ++j) {
          inputs += (j ? ", " : "") + std::string(C::QName(model_, j));
          if (spec.drive.input == C::QName(model_, j)) driven_input_ = j;
        }
        if (driven_input_ < 0)
          return fail(spec.drive.place, "drive: the model " + std::string(name) + " has no input '" +
                                            spec.drive.input + "' (its inputs: " + inputs + ")");
      }
      simulate_request_ = SimulateRequestOf(spec);
    }

    if (spec.analysis == Analysis::kEngine) {
      const std::string not_an_engine =
          std::string("analysis: engine needs an engine model of tools/make_engine.py (one crank input, "
                      "`dynamics` and `forces` among its outputs' quantities, no Coulomb friction); ") +
          name + " is not one";
      if constexpr (!engine::CanRunEngineCycle<M>()) {
        return fail(spec.analysis_place, not_an_engine);
      } else {
        if (!engine::CanRunEngineCycle(model_)) return fail(spec.analysis_place, not_an_engine);  // (a view's)
        // The engine's names (ReadEngine), and the indicator diagram over its cycle.
        Params nominal = base_;
        for (size_t k = 0; k < spec.parameters.size(); ++k) *Parameter(&nominal, spec.parameters[k].name) = nominal_[k];
        engine::Engine e;
        std::string why;
        if (!engine::ReadEngine(model_, &nominal, &e, &why))
          return fail(spec.analysis_place, std::string("analysis: engine: the model ") + name + ": " + why);
        has_table_ = !spec.gas.table.empty();
        if (has_table_) {
          auto parse = [](const std::string& text, double* x) {
            char* end = nullptr;
            *x = std::strtod(text.c_str(), &end);
            while (end != nullptr && (*end == ' ' || *end == '\r')) ++end;
            return !text.empty() && end != nullptr && *end == '\0' && std::isfinite(*x);
          };
          if (!engine::ReadPressureTable(spec.gas.table, e.cycle, &table_, &why, parse))
            return fail(spec.gas.place, "gas: table: " + why);
        }
        // The engine tool's cycle CSV's and energy loop CSV's columns (its cylinders and
        // reactions: the nominal's engine, every sample's).
        engine_columns_ = analysis::EngineCycleColumns(model_, e);
        engine_loop_columns_ = analysis::EngineLoopColumns();
      }
    }
    if (spec.analysis == Analysis::kFlywheel && (!HasStatics() || nq != 1 || !C::QIsAngle(model_, 0)))
      return fail(spec.analysis_place, std::string("analysis: flywheel needs a one-input machine turned by a crank "
                                                   "with `forces` among its outputs' quantities; ") +
                                           name + " is not one");
    // The first input's motion.
    q_begin_ = Eigen::Map<const typename ModelTypes<M>::VecQ>(C::QMin(model_), nq);
    q_end_ = Eigen::Map<const typename ModelTypes<M>::VecQ>(C::QMax(model_), nq);
    if (spec.has_range) {
      q_begin_(0) = spec.q_begin;
      q_end_(0) = spec.q_end;
    }
    if (spec.analysis != Analysis::kSimulate && spec.analysis != Analysis::kPositions &&
        spec.analysis != Analysis::kEngine) {
      // At range: (or steps:, or analysis: when the model's range is used), with %g figures.
      const position::InputStepCheck check = position::CheckInputSteps(q_begin_, q_end_, 1, spec.steps);
      char text[320];
      if (!std::isfinite(check.step))
        std::snprintf(text, sizeof(text), "the motion of %s from %g to %g overflows a double; give a narrower range:",
                      C::QName(model_, 0), q_begin_(0), q_end_(0));
      else
        std::snprintf(text, sizeof(text),
                      "the motion of %s from %g to %g in %d steps moves %g per step, more than the solver's limit %g; "
                      "use more steps: (at least %.6g) or a shorter range:",
                      C::QName(model_, 0), q_begin_(0), q_end_(0), spec.steps, check.step, check.limit,
                      check.min_steps);
      if (!check.ok()) return fail(spec.range_place, text);
    }
    sweep_columns_ = SweepColumns<M>(model_);
    if constexpr (kDesign) AppendDesignColumns<M>(model_, &sweep_columns_);  // (none without a design section)
    // analysis: flywheel: the flywheel tool's energy-loop CSV's columns, with dT_req/d<p> for
    // the design parameters (the nominal's, from the cycle's design derivatives; NaN in a
    // sample's rows, as the sweep's design columns).
    flywheel_columns_.clear();
    nan_design_.clear();
    if (spec.analysis == Analysis::kFlywheel) {
      std::vector<std::string> design;
      if constexpr (kDesign)
        if (HasDesign())
          for (int d = 0; d < C::NumDesign(model_); ++d) design.push_back(C::DesignName(model_, d));
      nan_design_.assign(design.size() + 1, kNaN);
      flywheel_columns_ = analysis::FlywheelLoopColumns(C::HasDynamics(model_), design);
    }
    if constexpr (kHasStatics)
      if (HasStatics()) statics_columns_ = statics::StaticsColumns<M>(model_, HasStaticsDesign());
    if constexpr (run_internal::SimulationOf<M>::kOk) {
      if (SimulationOk()) {
        using Sim = typename run_internal::SimulationOf<M>::Sim;
        using SampleT = typename run_internal::SimulationOf<M>::SampleT;
        simulation_columns_ = dynamics::FreeColumns<M, SampleT, Sim::kHasCoulomb>(Sim::kHasCoulomb, model_);
        // The columns after the motion's, the forces' and the friction's are the reactions' and
        // their magnitudes: a metric that reads one needs the kinetostatics at every sample.
        first_reaction_column_ = static_cast<int>(simulation_columns_.size()) - NumSimulationReactions() -
                                 static_cast<int>(dynamics::RevoluteMagnitudes<M>(model_).size());
      }
    }
    if constexpr (run_internal::DrivenOf<M>::kOk) {
      if (driven_input_ >= 0) {
        using SampleT = typename run_internal::DrivenOf<M>::SampleT;
        driven_columns_ =
            dynamics::DrivenColumns<M, SampleT>(run_internal::DrivenOf<M>::Driven(driven_input_), false, model_);
        // The driven table ends, like the free one, with the reactions and their magnitudes.
        first_driven_reaction_column_ = static_cast<int>(driven_columns_.size()) - NumSimulationReactions() -
                                        static_cast<int>(dynamics::RevoluteMagnitudes<M>(model_).size());
      }
    }
    needs_reactions_ = false;
    refs_.assign(spec.metrics.size(), Ref());
    for (size_t k = 0; k < spec.metrics.size(); ++k) {
      const MetricSpec& m = spec.metrics[k];
      Ref& r = refs_[k];
      const bool needs_statics = m.kind == MetricKind::kPeakDrive || m.kind == MetricKind::kPeakBearing;
      if (needs_statics && spec.analysis != Analysis::kStatics && spec.analysis != Analysis::kSimulate)
        return fail(m.place, "a metric of this kind needs analysis: statics (or simulate)");
      if (!m.column.empty()) {
        if (!FindColumn(m.column, &r.table, &r.column)) {
          std::string list;
          for (const auto& c : sweep_columns_)
            if (c.value && c.name.find('/') == std::string::npos) list += (list.empty() ? "" : ", ") + c.name;
          if constexpr (kHasStatics)
            if (spec.analysis == Analysis::kStatics)
              for (const auto& c : statics_columns_)
                if (c.value && c.name.find('/') == std::string::npos) list += ", " + c.name;
          if (spec.analysis == Analysis::kSimulate) {
            list.clear();
            if constexpr (run_internal::SimulationOf<M>::kOk)
              for (const auto& c : simulation_columns_) list += (list.empty() ? "" : ", ") + c.name;
            if constexpr (run_internal::DrivenOf<M>::kOk)
              if (driven_input_ >= 0) {
                list.clear();
                for (const auto& c : driven_columns_) list += (list.empty() ? "" : ", ") + c.name;
              }
          }
          if (spec.analysis == Analysis::kPositions) {
            list.clear();
            for (const std::string& c : PositionColumns()) list += (list.empty() ? "" : ", ") + c;
          }
          if (spec.analysis == Analysis::kFlywheel) {
            list.clear();
            for (const auto& c : flywheel_columns_)
              if (c.name.find('/') == std::string::npos) list += (list.empty() ? "" : ", ") + c.name;
          }
          if (spec.analysis == Analysis::kEngine) {
            list.clear();
            if constexpr (engine::CanRunEngineCycle<M>())
              for (const auto& c : engine_columns_) list += (list.empty() ? "" : ", ") + c.name;
            for (const auto& c : engine_loop_columns_) {
              int in = 0, at = 0;
              if (FindColumn(c.name, &in, &at) && in == 6) list += ", " + c.name;  // (not the cycle's too)
            }
          }
          return fail(m.place, "no numeric column '" + m.column + "' in the " +
                                   (spec.analysis == Analysis::kStatics    ? "sweep or statics"
                                    : spec.analysis == Analysis::kSimulate ? "simulation's"
                                    : spec.analysis == Analysis::kFlywheel ? "flywheel's energy loop"
                                    : spec.analysis == Analysis::kEngine   ? "engine's cycle or energy loop"
                                                                           : "sweep") +
                                   " output of " + name + " (columns: " + list + ")");
        }
        if (r.table == 2 && r.column >= first_reaction_column_) needs_reactions_ = true;
        if (r.table == 3 && r.column >= first_driven_reaction_column_) needs_reactions_ = true;
      }
      if (m.kind == MetricKind::kMeanTorque || m.kind == MetricKind::kPeakTorque) {
        // The cycle's columns by name: the flywheel's energy loop (T_mean, T_req), the engine's
        // loop (T_mean) and cycle (T_total).
        const std::string column = m.kind == MetricKind::kMeanTorque     ? "T_mean"
                                   : spec.analysis == Analysis::kEngine ? "T_total"
                                                                        : "T_req";
        if (!FindColumn(column, &r.table, &r.column)) return fail(m.place, "the cycle has no column " + column);
      }
      if (m.kind == MetricKind::kPeakDrive && spec.analysis == Analysis::kSimulate) {
        // The driven input's actuator force lambda (a torque on the input link, or a force).
        if (!FindColumn("lambda_" + spec.drive.input, &r.table, &r.column))
          return fail(m.place, "the driven run has no column lambda_" + spec.drive.input);
      } else if (m.kind == MetricKind::kPeakBearing && spec.analysis == Analysis::kSimulate) {
        // |F| of each revolute joint among the reactions (F_<joint>_mag, inertia forces included).
        for (const auto& j : dynamics::RevoluteMagnitudes<M>(model_)) {
          Ref c;
          if (FindColumn("F_" + j.second + "_mag", &c.table, &c.column)) r.magnitudes.push_back(c.column), r.table = c.table;
        }
        if (r.magnitudes.empty())
          return fail(m.place, std::string("the model ") + name +
                                   " has no reactions at revolute joints (outputs: reactions:)");
        needs_reactions_ = true;
      } else if (m.kind == MetricKind::kPeakDrive) {
        if (!FindColumn("drive_" + std::string(C::QName(model_, 0)), &r.table, &r.column))
          return fail(m.place, "the statics has no drive column");
      }
      if (m.kind == MetricKind::kPeakBearing && spec.analysis != Analysis::kSimulate) {
        if constexpr (kHasStatics && statics::StaticsFeatures<M>::kHasReactions) {
          if (HasStatics())
            for (const statics::ReactionJoint& j : statics::ReactionJoints<M>(model_)) r.joints.push_back(j);
        }
        if (r.joints.empty())
          return fail(m.place, std::string("the model ") + name + " has no reactions (outputs: reactions:)");
      }
      if (m.kind == MetricKind::kMinTransmissionAngle && C::NumTransmissionAngles(model_) == 0)
        return fail(m.place, std::string("the model ") + name +
                                 " has no four-bar loop on the ground (no transmission angle)");
      if (m.kind == MetricKind::kPathDeviation) {
        r.point = -1;
        for (int i = 0; i < C::NumPoints(model_); ++i)
          if (m.point == C::PointName(model_, i)) r.point = i;
        if (r.point < 0) {
          std::string list;
          for (int i = 0; i < C::NumPoints(model_); ++i) list += (i ? ", " : "") + std::string(C::PointName(model_, i));
          return fail(m.place, "no point '" + m.point + "' among the model's output points (" +
                                   (list.empty() ? "none" : list) + ")");
        }
      }
      if (m.kind == MetricKind::kDesignMargin) {
        if (const int checks = C::NumDesignChecks(model_); checks > 0) {
          r.check = -1;
          for (int i = 0; i < checks; ++i)
            if (m.check == C::DesignCheckName(model_, i)) r.check = i;
          if (!m.check.empty() && r.check < 0) {
            std::string list;
            for (int i = 0; i < checks; ++i) list += (i ? ", " : "") + std::string(C::DesignCheckName(model_, i));
            return fail(m.place, "no design check '" + m.check + "' (checks: " + list + ")");
          }
        } else {
          return fail(m.place, std::string("the model ") + name + " has no design checks (add a design: section)");
        }
      }
    }
    envelope_point_ = -1;
    if (!spec.envelope.empty()) {
      for (int i = 0; i < C::NumPoints(model_); ++i)
        if (spec.envelope == C::PointName(model_, i)) envelope_point_ = i;
      if (envelope_point_ < 0) {
        std::string list;
        for (int i = 0; i < C::NumPoints(model_); ++i) list += (i ? ", " : "") + std::string(C::PointName(model_, i));
        return fail(spec.envelope_place, "envelope: no point '" + spec.envelope +
                                             "' among the model's output points (" + (list.empty() ? "none" : list) +
                                             ")");
      }
    }
    // The nominal design's rows: the reference of path_deviation and of the first-order analysis.
    nominal_rows_ = Rows();
    Analyze(nominal_.data(), /*design=*/true, &nominal_rows_);
    if (!nominal_rows_.assembled)
      return fail(spec.analysis == Analysis::kEngine ? spec.gas.place : spec.analysis_place,
                  spec.analysis == Analysis::kFlywheel ? "the nominal design's cycle: " + nominal_rows_.cycle.message
                  : spec.analysis == Analysis::kEngine
                      ? "the nominal design's engine cycle: " + nominal_rows_.engine.message
                      : std::string("the model ") + name + " does not assemble at the nominal design" +
                            (spec.analysis == Analysis::kSimulate ? " (at q0)" : ""));
    return true;
  }

  const StudySpec& spec() const { return spec_; }
  /// The unit of metric k (its column's, or the kind's) and what it is.
  std::string Unit(size_t k) const {
    const MetricSpec& m = spec_.metrics[k];
    const Ref& r = refs_[k];
    switch (m.kind) {
      case MetricKind::kMinTransmissionAngle:
        return "rad";
      case MetricKind::kPeakBearing:
        return "N";
      case MetricKind::kPathDeviation:
        return "model length";
      case MetricKind::kFailures:
        return "1";
      case MetricKind::kDesignMargin:
        return "model length";
      case MetricKind::kFlywheelInertia:
        return "kg m^2";
      case MetricKind::kMeanTorque:
      case MetricKind::kPeakTorque:
        return "N m";
      case MetricKind::kEnergyFluctuation:
        return "J";
      case MetricKind::kSpeedFluctuation:
        return "1";
      default:
        if (r.table >= 4) return CycleColumnUnit(r);
        if constexpr (run_internal::DrivenOf<M>::kOk)
          if (r.table == 3) return driven_columns_[r.column].unit;
        if constexpr (run_internal::SimulationOf<M>::kOk)
          if (r.table == 2) return simulation_columns_[r.column].unit;
        return r.table == 0 ? sweep_columns_[r.column].unit : statics_columns_[r.column].unit;
    }
  }
  std::string Description(size_t k) const {
    const MetricSpec& m = spec_.metrics[k];
    const bool cycle = spec_.analysis == Analysis::kFlywheel || spec_.analysis == Analysis::kEngine;
    const std::string rows = spec_.analysis == Analysis::kSimulate ? " over the simulation's samples"
                             : cycle                              ? " over the cycle's samples"
                                                                  : " over the motion's rows that converged";
    switch (m.kind) {
      case MetricKind::kMax:
        return "largest " + m.column + rows;
      case MetricKind::kMin:
        return "smallest " + m.column + rows;
      case MetricKind::kRms:
        return "root mean square of " + m.column + rows;
      case MetricKind::kAt:
        if (spec_.analysis == Analysis::kSimulate)
          return m.column + " at t = " + std::to_string(m.step) + " t_end / steps (nan if not reached)";
        if (cycle) return m.column + " at sample " + std::to_string(m.step) + " of the cycle (nan beyond it)";
        return m.column + " at row " + std::to_string(m.step) + " (nan if that row failed)";
      case MetricKind::kMinTransmissionAngle:
        return "smallest min(mu, pi - mu) of the transmission angles mu" + rows;
      case MetricKind::kPeakDrive:
        if (spec_.analysis == Analysis::kSimulate)
          return "largest |lambda_" + spec_.drive.input + "| (the actuator force of the drive)" + rows;
        return "largest |drive_" + std::string(C::QName(model_, 0)) + "| without friction" + rows;
      case MetricKind::kPeakBearing:
        if (spec_.analysis == Analysis::kSimulate)
          return "largest |F| of a revolute joint (inertia forces included)" + rows;
        return "largest magnitude of a joint's reaction force without friction" + rows;
      case MetricKind::kPathDeviation:
        return "largest distance of " + m.point + " from its place at the same row of the nominal design";
      case MetricKind::kFailures:
        if (spec_.analysis == Analysis::kFlywheel || spec_.analysis == Analysis::kEngine)
          return "1 when the cycle failed (status cycle_failed), else 0";
        return spec_.analysis == Analysis::kSimulate
                   ? "1 when the simulation ended before t_end (or did not assemble), else 0"
                   : "rows of the motion that did not converge (all of them when not assembled)";
      case MetricKind::kDesignMargin:
        return m.check.empty() ? "smallest margin of the model's design checks (>= 0: acceptable)"
                               : "margin of the design check " + m.check;
      case MetricKind::kFlywheelInertia:
        if (spec_.analysis == Analysis::kEngine)
          return "the flywheel J_fly for C_s = " + std::to_string(m.C_s) +
                 ": Delta E / (C_s omega^2) - the mean of I(theta) - J_fly (the reciprocating parts' mean; "
                 "<engine>_engine flywheel)";
        return "the flywheel inertia to add for C_s = " + std::to_string(m.C_s) +
               ": Delta E / (C_s omega^2) - the machine's mean inertia (machines/flywheel)";
      case MetricKind::kMeanTorque:
        if (spec_.analysis == Analysis::kEngine)
          return "mean crank torque T_total = T_gas + T_inertia over the cycle at rpm, CCW + (the load it drives)";
        return "mean required driving torque over the cycle at omega (the steady motor torque)";
      case MetricKind::kPeakTorque:
        if (spec_.analysis == Analysis::kEngine) return "largest |T_total| over the cycle's samples at rpm";
        return "largest |required driving torque| over the cycle's samples at omega";
      case MetricKind::kEnergyFluctuation:
        if (spec_.analysis == Analysis::kEngine)
          return "Delta E = E_max - E_min of the energy loop of T_total about its mean";
        return "Delta E = E_max - E_min of the cycle's energy loop";
      case MetricKind::kSpeedFluctuation:
        return "C_s = Delta E / ((J_fly + the reciprocating parts' mean inertia) omega^2) with the model's J_fly";
    }
    return "";
  }
  /// Each parameter's nominal (the study's, else the model's default), in the spec's order.
  const std::vector<double>& nominal() const { return nominal_; }
  const Rows& nominal_rows() const { return nominal_rows_; }
  /// The design-parameter index (ModelCalls<M>::DesignName) of each of the study's parameters; -1: none.
  const std::vector<int>& design_index() const { return index_; }
  int rows() const { return spec_.steps + 1; }

  /// The analysis of the design `values` (one per spec parameter) into *rows.
  void Analyze(const double* values, bool design, Rows* out) const {
    out->params = base_;
    for (size_t k = 0; k < spec_.parameters.size(); ++k) *Parameter(&out->params, spec_.parameters[k].name) = values[k];
    FinishParameters(&out->params);
    if (spec_.analysis == Analysis::kPositions) {
      Positions(design, out);
      return;
    }
    if (spec_.analysis == Analysis::kEngine) {
      EngineCycle(out);  // its own positions from theta = 0 (machines/engine/cycle.h)
      return;
    }
    // No kinematic rows unless this sample's sweep fills them (a sample that does not assemble
    // has none); their storage is kept for the next sample of this thread.
    std::vector<Kinematics> kinematics = std::move(out->kinematics);
    out->kinematics.clear();
    if constexpr (kHasStatics) out->statics.clear();
    if (spec_.analysis == Analysis::kFlywheel) {
      // The machine's cycle at omega (machines/flywheel/machine_cycle.h): its own assembly
      // and continuation over `steps` samples.
      flywheel::MachineCycleOptions o;
      o.omega = spec_.omega;
      o.samples = spec_.steps;
      // (a view's: the library's, machines/view_machines.h)
      out->cycle = flywheel::SampleMachineCycle(model_, out->params, o);
      out->assembled = out->cycle.IsUsable();
      // The nominal's derivatives of the cycle (machines/flywheel/cycle_design.h): the first
      // order of the flywheel metrics (Gradient()). (A view's: the library's.)
      if (design && out->assembled)
        out->cycle_design = flywheel::SampleMachineCycleDesign(model_, out->params, o, out->cycle);
      return;
    }
    if (spec_.analysis == Analysis::kSimulate) {
      out->assembled = false;
      out->simulation.clear();
      out->driven.clear();
      out->simulation_status = dynamics::Status::kNotRun;
      if (driven_input_ >= 0) {
        SimulateDriven(out);
      } else if constexpr (run_internal::SimulationOf<M>::kOk) {
        if (SimulationOk()) Simulate(out);
      }
      return;
    }
    // analysis: sweep or statics: the rows of the sweep analysis (analysis/sweep.h's
    // EvaluateSweep, as `<model>_sweep`) for sweep_request_ (the design columns on the
    // nominal's rows) from the model's assembly, under the sample's parameters, with qd = 1,
    // qdd = 0.
    analysis::SweepRequest request = sweep_request_;
    request.design = design && HasDesign();
    using VecQ = typename ModelTypes<M>::VecQ;
    const int nq = C::Nq(model_);
    analysis::sweep_internal::Inputs<M> in;
    in.q_begin = q_begin_;
    in.q_end = q_end_;
    in.qd = VecQ::Ones(nq);
    in.qdd = VecQ::Zero(nq);
    in.modes = C::DefaultModes(model_);
    in.params = out->params;
    // A sample's rows: sized once per thread (every number NaN, the design derivatives too,
    // which a sample never evaluates), then every row's configuration, motion, summary and
    // transmission angles copied over: not the 60 % of a record that the design takes
    // (SweepRecord<fourbar>: 1040 bytes, 624 of them design; 361 rows were 375 KB written
    // twice per sample, more than a core's L2). The nominal's rows (request.design) copy the
    // design derivatives too (SweepRows' record: NaN where a row failed).
    auto begin = [&]() {
      out->kinematics = std::move(kinematics);
      const size_t n = static_cast<size_t>(std::max(spec_.steps, 1)) + 1;
      if (out->kinematics.size() != n || out->kinematics_design) out->kinematics.assign(n, Kinematics());
      out->kinematics_design = request.design;
      return true;
    };
    const bool with_design = request.design;
    auto copy = [out, with_design](int i, const Kinematics& r) {
      Kinematics& k = out->kinematics[static_cast<size_t>(i)];
      k.q = r.q;
      k.state = r.state;
      k.motion = r.motion;
      k.summary = r.summary;
      k.mu = r.mu;
      if (with_design) k.design = r.design;
    };
    position::Summary assembly;
    double det = 0;
    int failures = 0;
    out->assembled = analysis::EvaluateSweep<M>(model_, request, in, begin, copy, &assembly, &det, &failures) ==
                     analysis::SweepEvaluated::kRan;
    if (!out->assembled) return;
    if constexpr (kHasStatics) {
      if (spec_.analysis == Analysis::kStatics) {
        statics::Options so;
        so.design = design && HasStaticsDesign();
        out->statics.assign(out->kinematics.size(), StaticsRow());
        for (size_t i = 0; i < out->kinematics.size(); ++i) {
          out->statics[i].kinematics = out->kinematics[i];
          statics::EvaluateRecord<M>(model_, so, out->params, &out->statics[i]);
        }
      }
    }
  }

  /// One sample: its analysis and metrics (rows: the caller's, reused between samples).
  SampleResult Evaluate(const double* values, Rows* rows) const {
    std::vector<double> packed(Width());
    EvaluateInto(values, rows, packed.data());
    return Unpack(packed.data());
  }
  /// The same as Width() doubles at out (Pack's layout: the status code, the metrics, the
  /// envelope's path), allocating nothing per sample.
  void EvaluateInto(const double* values, Rows* rows, double* out) const {
    Analyze(values, /*design=*/false, rows);
    const size_t metrics = spec_.metrics.size();
    double* metric = out + 1;
    std::fill(metric, metric + metrics, kNaN);
    if (envelope_point_ >= 0) PathInto(*rows, metric + metrics);
    if (spec_.analysis == Analysis::kFlywheel || spec_.analysis == Analysis::kEngine) {
      out[0] = StatusCode(rows->assembled ? "ok" : "cycle_failed");
      for (size_t k = 0; k < metrics; ++k) metric[k] = Value(k, *rows).value;
      return;
    }
    if (!rows->assembled) {
      out[0] = StatusCode("not_assembled");
      for (size_t k = 0; k < metrics; ++k)
        if (spec_.metrics[k].kind == MetricKind::kFailures)
          metric[k] = spec_.analysis == Analysis::kSimulate ? 1 : spec_.steps + 1;
      return;
    }
    if (spec_.analysis == Analysis::kSimulate) {
      out[0] = StatusCode(dynamics::IsFailure(rows->simulation_status) ? "simulation_failed" : "ok");
      for (size_t k = 0; k < metrics; ++k) metric[k] = Value(k, *rows).value;
      return;
    }
    bool failed = false;
    for (int i = 0; i <= spec_.steps; ++i) failed = failed || !RowOk(*rows, i);
    out[0] = StatusCode(failed ? "rows_failed" : "ok");
    for (size_t k = 0; k < metrics; ++k) metric[k] = Value(k, *rows).value;
  }

  /// The envelope's point (M::kPointNames index), -1: none.
  int envelope_point() const { return envelope_point_; }
  /// The envelope point's x, y at every row (NaN where the row failed).
  std::vector<double> Path(const Rows& rows) const {
    std::vector<double> path(2 * static_cast<size_t>(spec_.steps + 1));
    PathInto(rows, path.data());
    return path;
  }
  /// The same into path[0, 2 (steps + 1)).
  void PathInto(const Rows& rows, double* path) const {
    std::fill(path, path + 2 * static_cast<size_t>(spec_.steps + 1), kNaN);
    if constexpr (M::kNumPoints != 0) {  // (a view: its count at run time)
      for (int i = 0; i < static_cast<int>(rows.kinematics.size()) && i <= spec_.steps; ++i) {
        if (rows.kinematics[i].summary.status != position::Status::kConverged) continue;
        path[2 * i] = rows.kinematics[i].state.r_P(0, envelope_point_);
        path[2 * i + 1] = rows.kinematics[i].state.r_P(1, envelope_point_);
      }
    }
  }
  /// d(x or y of the envelope point at row i)/dp for each study parameter at the nominal (the
  /// generated dr_P/dp); NaN for a parameter that is not a design parameter.
  std::vector<double> PathGradient(int i, int axis) const {
    std::vector<double> g(spec_.parameters.size(), kNaN);
    if constexpr (kDesign && M::kNumPoints != 0) {  // (a view: its count at run time)
      if (i < static_cast<int>(nominal_rows_.kinematics.size()))
        for (size_t p = 0; p < g.size(); ++p)
          if (index_[p] >= 0) g[p] = nominal_rows_.kinematics[i].design.dr_P_dp(2 * envelope_point_ + axis, index_[p]);
    }
    return g;
  }

  /// Metric k of `rows` and where it was taken (the row and the sign of the quantity there).
  struct Taken {
    double value = kNaN;
    int step = -1;    ///< the row (max, min, at, peaks); -1: none or every row (rms)
    double sign = 1;  ///< the metric is sign * the column there
    int check = -1;   ///< design_margin: the check
  };
  Taken Value(size_t k, const Rows& rows) const {
    const MetricSpec& m = spec_.metrics[k];
    const Ref& r = refs_[k];
    Taken t;
    const bool simulation = spec_.analysis == Analysis::kSimulate;
    const int n = r.table >= 4 ? CycleRows(r.table, rows)
                               : static_cast<int>(simulation ? (driven_input_ >= 0 ? rows.driven.size()
                                                                                    : rows.simulation.size())
                                                             : rows.kinematics.size());
    auto consider = [&t](double v, int i, double sign, bool larger) {
      if (!std::isfinite(v)) return;
      if (t.step < 0 || (larger ? v > t.value : v < t.value)) {
        t.value = v;
        t.step = i;
        t.sign = sign;
      }
    };
    const bool cycle = spec_.analysis == Analysis::kFlywheel || spec_.analysis == Analysis::kEngine;
    if (cycle && !rows.assembled && m.kind != MetricKind::kFailures && m.kind != MetricKind::kDesignMargin) return t;
    if (spec_.analysis == Analysis::kEngine && IsFlywheelMetric(m.kind)) {
      // As `<engine>_engine flywheel` computes them (machines/engine/cycle.h's energy loop).
      const engine::EngineEnergy& en = rows.engine;
      const double omega = EngineOmega();
      // mean_torque and peak_torque by name from the tool's energy loop CSV (T_mean) and cycle
      // CSV (T_total); the energy loop's figures (dE: its extremes refined between the samples)
      // are no column.
      switch (m.kind) {
        case MetricKind::kMeanTorque:
        case MetricKind::kPeakTorque: return CycleValue(k, rows, n);
        case MetricKind::kEnergyFluctuation: t.value = en.loop.delta_E; break;
        case MetricKind::kFlywheelInertia: {
          const double I_req = en.loop.delta_E / (m.C_s * omega * omega);
          t.value = I_req - en.I_recip;
          break;
        }
        case MetricKind::kSpeedFluctuation:
          t.value = en.loop.delta_E / ((rows.engine_J_fly + en.I_recip) * omega * omega);
          break;
        default: break;
      }
      return t;
    }
    switch (m.kind) {
      case MetricKind::kFlywheelInertia:
        t.value = flywheel::SizeFlywheel(rows.cycle, m.C_s).I_flywheel;
        break;
      case MetricKind::kMeanTorque:
      case MetricKind::kPeakTorque:
        return CycleValue(k, rows, n);  // the energy loop CSV's T_mean, T_req by name
      case MetricKind::kEnergyFluctuation:
        t.value = rows.cycle.loop.delta_E;
        break;
      case MetricKind::kSpeedFluctuation:
        break;
      case MetricKind::kMax:
      case MetricKind::kMin:
        for (int i = 0; i < n; ++i) consider(Cell(r, rows, i), i, 1, m.kind == MetricKind::kMax);
        break;
      case MetricKind::kAt:
        t.step = simulation ? SampleAt(rows, m.step) : m.step;
        t.value = t.step >= 0 && t.step < n ? Cell(r, rows, t.step) : kNaN;
        break;
      case MetricKind::kRms: {
        double sum = 0;
        int count = 0;
        for (int i = 0; i < n; ++i) {
          const double v = Cell(r, rows, i);
          if (std::isfinite(v)) sum += v * v, ++count;
        }
        if (count > 0) t.value = std::sqrt(sum / count);
        break;
      }
      case MetricKind::kMinTransmissionAngle:
        if constexpr (ModelFeatures<M>::kNumTransmissionAngles != 0) {  // (a view: its count at run time)
          for (int i = 0; i < n; ++i) {
            if (rows.kinematics[i].summary.status != position::Status::kConverged) continue;
            for (int l = 0; l < C::NumTransmissionAngles(model_); ++l) {
              const double mu = rows.kinematics[i].mu(l);
              const double pi = 3.14159265358979323846;
              consider(std::min(mu, pi - mu), i * 64 + l, mu <= pi / 2 ? 1 : -1, false);
            }
          }
        }
        break;
      case MetricKind::kPeakDrive:
        for (int i = 0; i < n; ++i) {
          const double v = Cell(r, rows, i);
          consider(std::abs(v), i, v >= 0 ? 1 : -1, true);
        }
        break;
      case MetricKind::kPeakBearing:
        if (simulation) {
          // The largest |F| of a revolute joint over the simulation's samples.
          for (int i = 0; i < n; ++i)
            for (size_t j = 0; j < r.magnitudes.size(); ++j) {
              Ref c = r;
              c.column = r.magnitudes[j];
              consider(Cell(c, rows, i), i, 1, true);
            }
          break;
        }
        if constexpr (kHasStatics && statics::StaticsFeatures<M>::kHasReactions) {
          for (int i = 0; i < n; ++i) {
            if (rows.statics[i].frictionless.summary.status != statics::Status::kConverged) continue;
            for (size_t j = 0; j < r.joints.size(); ++j) {
              const double before = t.value;
              consider(statics::ReactionMagnitude(r.joints[j], rows.statics[i].frictionless.statics.R), i, 1, true);
              if (t.step == i && !(t.value == before)) t.check = static_cast<int>(j);
            }
          }
        }
        break;
      case MetricKind::kPathDeviation:
        if constexpr (M::kNumPoints != 0) {
          for (int i = 0; i < n && i < static_cast<int>(nominal_rows_.kinematics.size()); ++i) {
            const auto& a = rows.kinematics[i].state.r_P;
            const auto& b = nominal_rows_.kinematics[i].state.r_P;
            consider(std::hypot(a(0, r.point) - b(0, r.point), a(1, r.point) - b(1, r.point)), i, 1, true);
          }
        }
        break;
      case MetricKind::kFailures: {
        int failures = 0;
        if (cycle) {
          failures = !rows.assembled;
        } else if (simulation) {
          failures = !rows.assembled || dynamics::IsFailure(rows.simulation_status);
        } else {
          for (int i = 0; i < n; ++i) failures += !RowOk(rows, i);
        }
        t.value = failures;
        break;
      }
      case MetricKind::kDesignMargin: {
        typename C::DesignMargins margin;
        C::DesignChecks(model_, rows.params, &margin);  // (Prepare: the model has checks)
        for (int c = 0; c < C::NumDesignChecks(model_); ++c)
          if (r.check < 0 || r.check == c) {
            if (t.check < 0 || margin(c) < t.value) t.value = margin(c), t.check = c;
          }
        break;
      }
    }
    if (m.kind == MetricKind::kMinTransmissionAngle && t.step >= 0) {
      t.check = t.step % 64;
      t.step /= 64;
    }
    return t;
  }

  /**
   * \brief d metric_k / d p for each of the study's parameters at the nominal design, from the
   *        generated design derivatives (the design columns of the nominal rows): at the row
   *        where a max, min or peak is taken (the derivative of the value there: the peak's
   *        row held, exact where the peak does not jump between rows), summed over the rows
   *        for an RMS, the design checks' own derivatives for a margin. NaN for a parameter
   *        that is not a design parameter of M, and for a metric with no derivative here
   *        (*why says which: failures, path_deviation). peak_bearing: d|F| = F . dF / |F| at
   *        the peak's row and joint.
   */
  std::vector<double> Gradient(size_t k, std::string* why) const { return DesignGradient(k, why); }

  /// Evaluates every sample (values: DrawSamples()) on `threads` threads into *results (in
  /// sample order); `progress(done)` is called from the calling thread about once a second.
  void Run(const std::vector<double>& values,
           int threads,
           std::vector<SampleResult>* results,
           const std::function<void(uint64_t done)>& progress = nullptr) const {
    const size_t n = spec_.parameters.size();
    const uint64_t count = n == 0 ? 0 : values.size() / n;
    results->assign(count, SampleResult());
    RunChunks(values, Chunks{count, std::max<uint64_t>(count, 1)}, {0}, threads, results, nullptr, progress);
  }
 private:
  // The first order of a metric of analysis: simulate (the free motion): the trajectory
  // sensitivities dq/dp and dq_dot/dp (dynamics/sensitivity.h's TrajectorySensitivity, run by
  // analysis/simulate_design.h's SensitivitySamples: a generated model's, or the view's with its
  // model's generated EvalDynamicsJacobian, compiled once in runtime/view/analysis_simulate_design.cc)
  // along the nominal's run, sampled on the study's grid and read at the nominal's samples
  // (matched by time): max, min and at of an input q or its speed q_dot: d(column)/dp at the
  // metric's sample (that sample held, as for the other extremes); rms: the mean of v dv/dp over
  // the samples, over the rms. NaN and why for the rest (the reactions, the accelerations, the
  // energy: no sensitivities of those; a driven run, Coulomb friction: the sensitivities are the
  // free motion's without friction).
  std::vector<double> SimulationGradient(size_t k, const Taken& t, std::string* why) const {
    std::vector<double> g(spec_.parameters.size(), kNaN);
    const MetricSpec& m = spec_.metrics[k];
    {
#if MECHGEN_SIMULATE_HAS_SENSITIVITY
      if constexpr (HasDynamicsDesign<M>::value && run_internal::SimulationOf<M>::kOk) {
        using SampleT = dynamics::SensitivitySample<M>;
        if (!C::HasDynamicsDesign(model_)) {
          *why = "no design derivatives of a simulation of this model (its `design` section and `dynamics` give them)";
          return g;
        }
        if (driven_input_ >= 0) {
          *why = "no design derivatives of a driven simulation (the trajectory sensitivities are the free motion's)";
          return g;
        }
        if (run_internal::SimulationOf<M>::Sim::kHasCoulomb && C::KinetoNumFriction(model_) > 0) {
          *why = "no design derivatives of a simulation with Coulomb friction (the trajectory sensitivities are the "
                 "free motion's without it)";
          return g;
        }
        if (m.kind != MetricKind::kMax && m.kind != MetricKind::kMin && m.kind != MetricKind::kAt &&
            m.kind != MetricKind::kRms) {
          *why = "no design derivatives of this metric of a simulation (max, min, at and rms of an input or its "
                 "speed have them)";
          return g;
        }
        const std::string column = ColumnName(refs_[k]);
        int input = -1;
        bool speed = false;
        for (int j = 0; j < C::Nq(model_); ++j) {
          if (column == C::QName(model_, j)) input = j, speed = false;
          if (column == std::string(C::QName(model_, j)) + "_dot") input = j, speed = true;
        }
        if (input < 0) {
          *why = "no trajectory sensitivity of the column " + column + " (those of the inputs and their speeds only)";
          return g;
        }
        const Rows& rows = nominal_rows_;
        typename ModelTypes<M>::VecQ q0, qd0;
        (void)analysis::simulate_internal::InitialState(model_, simulate_request_, &q0, &qd0);  // (checked: Prepare)
        dynamics::SensitivityOptions o;
        o.sample_dt = simulate_request_.dt;
        std::vector<SampleT> samples;
        samples.reserve(static_cast<size_t>(spec_.steps) + 2);
        if (!analysis::simulate_internal::SensitivitySamples<M, dynamics::Dopri5>(model_, rows.params, q0, qd0,
                                                                                  spec_.t_end, o, &samples, why))
          return g;
        // d(column)/d(design parameter d) at the nominal's sample r (NaN: no sensitivity sample
        // at its time).
        auto derivative = [&](int r, int d) {
          const double tr = rows.simulation[static_cast<size_t>(r)].s.t;
          for (const SampleT& s : samples)
            if (std::abs(s.t - tr) <= 1e-9 * spec_.t_end) return speed ? s.Sd(input, d) : s.S(input, d);
          return kNaN;
        };
        for (size_t p = 0; p < spec_.parameters.size(); ++p) {
          const int d = index_[p];
          if (d < 0) continue;
          if (m.kind == MetricKind::kRms) {
            double sum = 0;
            int count = 0;
            for (size_t r = 0; r < rows.simulation.size(); ++r) {
              const double v = Cell(refs_[k], rows, static_cast<int>(r));
              if (std::isfinite(v)) sum += v * derivative(static_cast<int>(r), d), ++count;
            }
            g[p] = sum / count / t.value;
          } else if (t.step >= 0) {
            g[p] = t.sign * derivative(t.step, d);
          }
        }
        return g;
      } else {
        *why = "no design derivatives of a simulation of this model (its `design` section and `dynamics` give them)";
        return g;
      }
#else
      *why = "no design derivatives of a simulation in this build (the trajectory sensitivities need Ceres' "
             "ceres/jet.h)";
      return g;
#endif
    }
  }
  // Gradient(): the model's design derivatives (a generated model's, or the view's).
  std::vector<double> DesignGradient(size_t k, std::string* why) const {
    const MetricSpec& m = spec_.metrics[k];
    const Ref& r = refs_[k];
    const Rows& rows = nominal_rows_;
    const Taken t = Value(k, rows);
    std::vector<double> g(spec_.parameters.size(), kNaN);
    why->clear();
    if (m.kind == MetricKind::kFailures) {
      *why = "a count";
      return g;
    }
    if (m.kind == MetricKind::kPathDeviation) {
      *why = "a distance, 0 at the nominal: not differentiable there";
      return g;
    }
    if (spec_.analysis == Analysis::kEngine && m.kind != MetricKind::kDesignMargin) {
      *why = "no design derivatives of the engine cycle in a study (the engine tool's flywheel --design gives "
             "them with the pressure trace held)";
      return g;
    }
    if (spec_.analysis == Analysis::kSimulate && m.kind != MetricKind::kDesignMargin) {
      if (!std::isfinite(t.value)) {
        *why = "no value at the nominal";
        return g;
      }
      return SimulationGradient(k, t, why);
    }
    if (!std::isfinite(t.value)) {
      *why = "no value at the nominal";
      return g;
    }
    if (IsFlywheelMetric(m.kind)) {
      // The cycle's design derivatives (machines/flywheel/cycle_design.h: exact for the computed
      // figures; the breaks held at their angles). peak_torque: dT_req/dp at the sample where
      // |T_req| peaks (that sample held, as for the other peaks).
      const flywheel::CycleDesign<M>& cd = rows.cycle_design;
      if (!cd.IsUsable()) {
        *why = cd.message.empty() ? "no design derivatives of the cycle" : cd.message;
        return g;
      }
      for (size_t p = 0; p < spec_.parameters.size(); ++p) {
        const int d = index_[p];
        if (d < 0) continue;
        switch (m.kind) {
          case MetricKind::kMeanTorque: g[p] = cd.dT_mean_dp(d); break;
          case MetricKind::kEnergyFluctuation: g[p] = cd.ddelta_E_dp(d); break;
          case MetricKind::kFlywheelInertia:
            g[p] = flywheel::SizeFlywheelDesign<M>(rows.cycle, cd, m.C_s).dI_flywheel_dp(d);
            break;
          case MetricKind::kPeakTorque: {
            // The energy loop CSV's design column dT_req/d<p> at the peak's sample (Value's).
            Ref column;
            if (t.step >= 0 && FindColumn("dT_req/d" + spec_.parameters[p].name, &column.table, &column.column))
              g[p] = t.sign * Cell(column, rows, t.step);
            break;
          }
          default: break;
        }
      }
      return g;
    }
    if (r.table == 4 && !rows.cycle_design.IsUsable()) {  // a column of the flywheel's energy loop
      *why = rows.cycle_design.message.empty() ? "no design derivatives of the cycle" : rows.cycle_design.message;
      return g;
    }
    for (size_t p = 0; p < spec_.parameters.size(); ++p) {
      if (index_[p] < 0) continue;
      const std::string& name = spec_.parameters[p].name;
      if (m.kind == MetricKind::kPeakBearing) {
        // |F| = hypot of the joint's components (or |F| of a scalar): d|F| = sum F_c dF_c / |F|
        // from the reactions' design columns dF_c/dp at the peak's row.
        if constexpr (kHasStatics && statics::StaticsFeatures<M>::kHasReactions) {
          const statics::ReactionJoint& j = r.joints[t.check];
          const auto& R = rows.statics[t.step].frictionless.statics.R;
          double sum = 0;
          bool found = true;
          for (int c : {j.x, j.y, j.n, j.t, j.scalar}) {
            if (c < 0) continue;
            Ref d;
            const std::string column = "d" + std::string(C::ReactionName(model_, c)) + "/d" + name;
            if (!FindColumn(column, &d.table, &d.column)) {
              *why = "no design column " + column;
              found = false;
              break;
            }
            sum += R(c) * Cell(d, rows, t.step);
          }
          if (found) g[p] = sum / t.value;
        }
        continue;
      }
      if (m.kind == MetricKind::kDesignMargin) {
        typename C::DesignMargins margin;
        typename C::DesignMarginsDp dmargin;
        C::DesignChecks(model_, rows.params, &margin, &dmargin);
        g[p] = dmargin(t.check, index_[p]);
        continue;
      }
      Ref d;
      std::string column;
      if (m.kind == MetricKind::kMinTransmissionAngle) {
        if constexpr (ModelFeatures<M>::kNumTransmissionAngles != 0)  // (a view: its count at run time)
          column = "dmu_" + std::string(C::TransmissionJoint(model_, t.check)) + "/d" + name;
      } else {
        column = "d" + ColumnName(r) + "/d" + name;
        // One input moving at qd = 1, qdd = 0 (the study's sweep): phi_i_dot = K_i0, so its
        // derivative is dK's column.
        if (C::Nq(model_) == 1 && C::HasK(model_))
          for (int i = 0; i < C::Nphi(model_); ++i)
            if (r.table == 0 && ColumnName(r) == std::string(C::PhiName(model_, i)) + "_dot")
              column = "dK_" + std::string(C::PhiName(model_, i)) + "_" + C::QName(model_, 0) + "/d" + name;
      }
      if (!FindColumn(column, &d.table, &d.column)) {
        *why = "no design column " + column;
        continue;
      }
      if (m.kind == MetricKind::kRms) {
        double sum = 0;
        int count = 0;
        const int n = r.table >= 4 ? CycleRows(r.table, rows) : static_cast<int>(rows.kinematics.size());
        for (int i = 0; i < n; ++i) {
          const double v = Cell(r, rows, i);
          if (std::isfinite(v)) sum += v * Cell(d, rows, i), ++count;
        }
        g[p] = sum / count / t.value;
      } else {
        g[p] = t.sign * Cell(d, rows, t.step);
      }
    }
    return g;
  }

 public:
  /**
   * \brief Evaluates the samples of the chunks `list` (of `chunks`; values: DrawSamples()) on
   *        `threads` threads into their places of *results (sized to every sample; the others
   *        are left alone). Each thread takes the next sample of the list from a shared
   *        counter; when the last sample of a chunk is done, `chunk_done(c)` is called from
   *        the thread that did it (its results are then all in place: a shard can be written).
   *        `progress(done)` (samples of the list done) is called from the calling thread about
   *        once a second.
   */
  void RunChunks(const std::vector<double>& values,
                 const Chunks& chunks,
                 const std::vector<uint64_t>& list,
                 int threads,
                 std::vector<SampleResult>* results,
                 const std::function<void(uint64_t chunk)>& chunk_done,
                 const std::function<void(uint64_t done)>& progress = nullptr) const {
    const size_t n = spec_.parameters.size();
    RunChunks([&values, n](uint64_t i, double* out) { std::copy(&values[i * n], &values[i * n] + n, out); }, chunks,
              list, threads, [results](uint64_t i) { return &(*results)[i]; }, chunk_done, progress);
  }

  /**
   * \brief The same, end to end in chunks: sample i's values from `draw(i, out)` (a
   *        SampleSource's Draw) when a thread takes it, its result into *slot(i) (the caller's
   *        storage of the chunks of `list`, alive and sized before the call): nothing is held
   *        for the samples outside the list.
   */
  void RunChunks(const std::function<void(uint64_t i, double* out)>& draw,
                 const Chunks& chunks,
                 const std::vector<uint64_t>& list,
                 int threads,
                 const std::function<SampleResult*(uint64_t i)>& slot,
                 const std::function<void(uint64_t chunk)>& chunk_done,
                 const std::function<void(uint64_t done)>& progress = nullptr) const {
    Schedule(
        chunks, list, threads,
        [&](uint64_t i, Rows* rows, double* values) {
          draw(i, values);
          *slot(i) = Evaluate(values, rows);
        },
        chunk_done, progress, nullptr);
  }

  /**
   * \brief The samples of the chunks `list` drawn and evaluated on `threads` threads, each
   *        sample's values drawn by the thread that evaluates it into values(i) (its
   *        parameters' count of doubles; values == nullptr: not kept) and its result packed
   *        into result(i) (Width() doubles, Pack's layout): no allocation per sample, nothing
   *        shared but the work counter. When a chunk's last sample is done `chunk_done(c)` is
   *        called from the thread that did it (the chunk's values and results are then all in
   *        place: its shard and its CSV rows can be made there); the calling thread calls
   *        `ready()` whenever a chunk is done (e.g. to write the chunks done so far in order)
   *        and `progress(done)` about once a second. The results depend on the samples alone,
   *        never on the threads or the order the samples were taken in.
   */
  void RunPacked(const SampleSource& source,
                 const Chunks& chunks,
                 const std::vector<uint64_t>& list,
                 int threads,
                 const std::function<double*(uint64_t i)>& values,
                 const std::function<double*(uint64_t i)>& result,
                 const std::function<void(uint64_t chunk)>& chunk_done,
                 const std::function<void(uint64_t done)>& progress = nullptr,
                 const std::function<void()>& ready = nullptr) const {
    Schedule(
        chunks, list, threads,
        [&](uint64_t i, Rows* rows, double* scratch) {
          double* v = values ? values(i) : scratch;
          source.Draw(i, v);
          EvaluateInto(v, rows, result(i));
        },
        chunk_done, progress, ready);
  }

  /**
   * \brief The scheduler of RunChunks and RunPacked: the samples of the chunks `list` cut into
   *        work items of at most `batch` consecutive samples of one chunk (about 256 items per
   *        thread: the last items, which some threads finish while others wait, are short),
   *        taken in order from one counter alone on its cache line, one atomic operation per
   *        item (not three per sample: the next sample, the chunk's and the progress count).
   *        `sample(i, rows, scratch)` runs sample i with the thread's own Rows and a scratch of
   *        the parameters' count of doubles.
   */
  template <class SampleFn>
  void Schedule(const Chunks& chunks,
                const std::vector<uint64_t>& list,
                int threads,
                SampleFn&& sample,
                const std::function<void(uint64_t chunk)>& chunk_done,
                const std::function<void(uint64_t done)>& progress,
                const std::function<void()>& ready) const {
    struct Item {
      uint64_t begin, end;
      size_t j;  // list[j]: its chunk
    };
    threads = std::max(threads, 1);
    uint64_t total = 0;
    for (uint64_t c : list) total += chunks.end(c) - chunks.begin(c);
    const uint64_t batch = std::clamp<uint64_t>(total / (256 * static_cast<uint64_t>(threads)), 1, 1024);
    std::vector<Item> items;
    std::vector<std::atomic<uint64_t>> left(list.size());
    for (size_t j = 0; j < list.size(); ++j) {
      const uint64_t b = chunks.begin(list[j]), n = chunks.end(list[j]) - b;
      const uint64_t parts = std::max<uint64_t>(1, (n + batch - 1) / batch);
      left[j].store(parts, std::memory_order_relaxed);
      for (uint64_t k = 0; k < parts; ++k) items.push_back({b + n * k / parts, b + n * (k + 1) / parts, j});
    }
    struct alignas(64) Counter {
      std::atomic<uint64_t> value{0};
    };
    Counter next, done;
    std::mutex mutex;
    std::condition_variable wake;
    const size_t n = spec_.parameters.size();
    auto work = [&]() {
      Rows rows;
      std::vector<double> scratch(std::max<size_t>(n, 1));
      for (uint64_t k; (k = next.value.fetch_add(1, std::memory_order_relaxed)) < items.size();) {
        const Item& item = items[k];
        for (uint64_t i = item.begin; i < item.end; ++i) sample(i, &rows, scratch.data());
        // acq_rel: the thread that ends a chunk sees every result of it.
        const bool ended = left[item.j].fetch_sub(1, std::memory_order_acq_rel) == 1;
        if (ended && chunk_done) chunk_done(list[item.j]);
        // After chunk_done: once `done` is the total, every chunk_done has returned.
        const bool last =
            done.value.fetch_add(item.end - item.begin, std::memory_order_acq_rel) + (item.end - item.begin) == total;
        if (ended || last) {
          { std::lock_guard<std::mutex> lock(mutex); }
          wake.notify_all();
        }
      }
    };
    const bool watch = progress || ready;
    std::vector<std::thread> pool;
    for (int t = watch ? 0 : 1; t < threads; ++t) pool.emplace_back(work);
    if (watch) {
      // The calling thread watches while `threads` others work.
      auto last = std::chrono::steady_clock::now();
      std::unique_lock<std::mutex> lock(mutex);
      while (done.value.load(std::memory_order_acquire) < total) {
        wake.wait_for(lock, std::chrono::seconds(1));
        lock.unlock();
        if (ready) ready();
        const auto now = std::chrono::steady_clock::now();
        if (progress && now - last >= std::chrono::seconds(1)) {
          progress(done.value.load(std::memory_order_acquire));
          last = now;
        }
        lock.lock();
      }
    } else {
      work();
    }
    for (std::thread& t : pool) t.join();
    if (ready) ready();
    if (progress) progress(total);
  }

  /// Doubles per sample in a shard or a gather between ranks: the status code, the metrics,
  /// the envelope's path (x, y per row) if the study has one.
  uint64_t Width() const {
    return 1 + spec_.metrics.size() + (envelope_point_ >= 0 ? 2 * static_cast<uint64_t>(spec_.steps + 1) : 0);
  }
  /// Sample result r as Width() doubles at out.
  void Pack(const SampleResult& r, double* out) const {
    out[0] = StatusCode(r.status);
    std::copy(r.metrics.begin(), r.metrics.end(), out + 1);
    std::copy(r.path.begin(), r.path.end(), out + 1 + spec_.metrics.size());
  }
  SampleResult Unpack(const double* in) const {
    SampleResult r;
    r.status = StatusOfCode(in[0]);
    r.metrics.assign(in + 1, in + 1 + spec_.metrics.size());
    if (envelope_point_ >= 0) r.path.assign(in + 1 + spec_.metrics.size(), in + Width());
    return r;
  }
  /**
   * \brief The study's identity for its shards: the study file's bytes, the model (its name,
   *        the parameters it starts from (SetBase) and the nominal design's metrics, bit for
   *        bit), the chunk size, the samples' count and nominals and the values of the first
   *        64 samples and the last (what the spec and the nominals determine, drawn: a change
   *        of the sampler changes them). A change of any of them makes old shards another
   *        study's.
   */
  uint64_t Key(const std::string& study_bytes, const SampleSource& source, uint64_t chunk) const {
    KeyHash h;
    h.Add(study_bytes);
    h.Add(std::string(C::Name(model_)));
    for (double v : FreeParameters(base_)) h.Add(v);
    for (size_t k = 0; k < spec_.metrics.size(); ++k) h.Add(Value(k, nominal_rows_).value);
    h.Add(chunk);
    h.Add(Width());
    h.Add(source.count());
    for (double v : source.nominal()) h.Add(v);
    std::vector<double> values(source.parameters());
    auto add = [&](uint64_t i) {
      source.Draw(i, values.data());
      for (double v : values) h.Add(v);
    };
    const uint64_t first = std::min<uint64_t>(source.count(), 64);
    for (uint64_t i = 0; i < first; ++i) add(i);
    if (source.count() > first) add(source.count() - 1);
    return h.value();
  }

 private:
  // ---- The model's parameters by name: a generated model's Params, or the view's table
  //      (its free parameters first, then the derived ones, which FinishParameters computes) ----
  std::string ParameterNames() const {
    std::string names;
    if constexpr (kView) {
      const ModelView& v = *model_.view;
      for (int i = 0; i < v.num_free_params; ++i) names += (names.empty() ? "" : ", ") + std::string(v.params[i].name);
    } else {
      for (const char* n : Params::kNames) names += (names.empty() ? "" : ", ") + std::string(n);
    }
    return names;
  }
  // The free parameter `name` of *p, or nullptr.
  double* Parameter(Params* p, const std::string& name) const {
    if constexpr (kView) {
      const int i = FindParameter(*model_.view, name.c_str());
      return i >= 0 && i < model_.view->num_free_params ? &p->values[static_cast<size_t>(i)] : nullptr;
    } else {
      return p->Find(name.c_str());
    }
  }
  bool IsDerived(const std::string& name) const {
    if constexpr (kView) {
      return FindParameter(*model_.view, name.c_str()) >= model_.view->num_free_params;
    } else {
      bool derived = false;
      for (const char* d : Params::kDerivedNames) derived = derived || name == d;
      return derived;
    }
  }
  // The derived parameters from the free ones (the view's table; a generated Params has none).
  void FinishParameters(Params* p) const {
    if constexpr (kView) {
      if (model_.view->fill_derived != nullptr) model_.view->fill_derived(p->data());
    } else {
      (void)p;
    }
  }
  // The free parameters' values in the model's order.
  std::vector<double> FreeParameters(const Params& p) const {
    std::vector<double> values;
    if constexpr (kView) {
      values.assign(p.values.begin(), p.values.begin() + model_.view->num_free_params);
    } else {
      Params copy = p;
      for (const char* name : Params::kNames) values.push_back(*copy.Find(name));
    }
    return values;
  }
  // What the model has for the analyses (constant for a generated model, the view's flags).
  bool HasStatics() const {
    if constexpr (kView) {
      return C::HasStatics(model_);
    } else {
      return kHasStatics;
    }
  }
  bool SimulationOk() const {
    if constexpr (kView) {
      return C::HasDynamics(model_) && C::HasSolve(model_);
    } else {
      return run_internal::SimulationOf<M>::kOk;
    }
  }
  // Whether the model has the design derivatives (a design section), and the statics' (the
  // view's at run time).
  bool HasDesign() const {
    if constexpr (kDesign) {
      return C::HasDesign(model_);
    } else {
      return false;
    }
  }
  bool HasStaticsDesign() const {
    if constexpr (kStaticsDesign) {
      return C::HasStaticsDesign(model_);
    } else {
      return false;
    }
  }
  int NumSimulationReactions() const {
    if constexpr (kView) {
      return C::KinetoNumReactions(model_);
    } else if constexpr (run_internal::SimulationOf<M>::kOk) {
      return run_internal::SimulationOf<M>::kNumReactions;
    } else {
      return 0;  // (no dynamics: no simulation; the study refuses analysis: simulate)
    }
  }

  struct Ref {
    // 0: sweep columns, 1: statics columns, 2: simulation columns, 3: the driven simulation's,
    // 4: the flywheel's energy loop, 5: the engine's cycle, 6: the engine's energy loop
    int table = 0;
    int column = -1;
    int point = -1;
    int check = -1;
    std::vector<statics::ReactionJoint> joints;
    std::vector<int> magnitudes;  ///< simulate's peak_bearing: the F_<joint>_mag columns
  };

  bool FindColumn(const std::string& name, int* table, int* column) const {
    // The numeric column `name` of `columns`, table t.
    auto in = [&](const auto& columns, int t) {
      for (size_t c = 0; c < columns.size(); ++c)
        if (columns[c].name == name && columns[c].value) {
          *table = t, *column = static_cast<int>(c);
          return true;
        }
      return false;
    };
    if (spec_.analysis == Analysis::kFlywheel) return in(flywheel_columns_, 4);
    if (spec_.analysis == Analysis::kEngine) {
      if constexpr (engine::CanRunEngineCycle<M>())
        if (in(engine_columns_, 5)) return true;
      return in(engine_loop_columns_, 6);
    }
    if (spec_.analysis == Analysis::kSimulate && driven_input_ >= 0) {
      if constexpr (run_internal::DrivenOf<M>::kOk) return in(driven_columns_, 3);
      return false;
    }
    if (spec_.analysis == Analysis::kPositions) {
      bool position = name.find('/') != std::string::npos;  // a design column, d<column>/d<p>
      for (const std::string& c : PositionColumns()) position = position || c == name;
      if (!position) return false;
    }
    if (spec_.analysis == Analysis::kSimulate) {
      if constexpr (run_internal::SimulationOf<M>::kOk) return in(simulation_columns_, 2);
      return false;
    }
    return in(sweep_columns_, 0) || (spec_.analysis == Analysis::kStatics && in(statics_columns_, 1));
  }
  // The sweep's columns that a positions-only analysis fills: the inputs, the dependent
  // coordinates, the points' x and y and the transmission angles.
  std::vector<std::string> PositionColumns() const {
    std::vector<std::string> names;
    for (int j = 0; j < C::Nq(model_); ++j) names.push_back(C::QName(model_, j));
    for (int i = 0; i < C::Nphi(model_); ++i) names.push_back(C::PhiName(model_, i));
    for (int i = 0; i < C::NumPoints(model_); ++i)
      for (const char* axis : {".x", ".y"}) names.push_back(std::string(C::PointName(model_, i)) + axis);
    for (int t = 0; t < C::NumTransmissionAngles(model_); ++t)
      names.push_back(std::string("mu_") + C::TransmissionJoint(model_, t));
    return names;
  }
  std::string ColumnName(const Ref& r) const {
    if (r.table == 4) return flywheel_columns_[r.column].name;
    if (r.table == 6) return engine_loop_columns_[r.column].name;
    if constexpr (engine::CanRunEngineCycle<M>())
      if (r.table == 5) return engine_columns_[r.column].name;
    if constexpr (run_internal::DrivenOf<M>::kOk)
      if (r.table == 3) return driven_columns_[r.column].name;
    if constexpr (run_internal::SimulationOf<M>::kOk)
      if (r.table == 2) return simulation_columns_[r.column].name;
    return r.table == 0 ? sweep_columns_[r.column].name : statics_columns_[r.column].name;
  }
  // The simulation's sample at t = step t_end / steps (the sample grid's; -1: not reached).
  int SampleAt(const Rows& rows, int step) const {
    const double t = step * (spec_.t_end / spec_.steps);
    for (size_t i = 0; i < rows.simulation.size(); ++i)
      if constexpr (run_internal::SimulationOf<M>::kOk)
        if (std::abs(rows.simulation[i].s.t - t) <= 1e-9 * spec_.t_end) return static_cast<int>(i);
    for (size_t i = 0; i < rows.driven.size(); ++i)
      if constexpr (run_internal::DrivenOf<M>::kOk)
        if (std::abs(rows.driven[i].s.t - t) <= 1e-9 * spec_.t_end) return static_cast<int>(i);
    return -1;
  }
  // analysis: simulate: the simulate analysis's Request (analysis/simulate_request.h) for the
  // spec: from q0, qd0 (empty: the model's assembly, from rest) to t_end, a sample every
  // t_end / steps, the integrator's defaults (dopri5), no steady-state stop, the model's
  // friction; with drive: its one input on its law.
  static analysis::SimulateRequest SimulateRequestOf(const StudySpec& spec) {
    analysis::SimulateRequest r;
    r.t_end = spec.t_end;
    r.dt = spec.t_end / spec.steps;
    r.q0 = spec.q0;
    r.qd0 = spec.qd0;
    r.steady = false;
    if (!spec.drive.input.empty()) {
      analysis::SimulateDrive d;
      d.text = spec.drive.input + "=" + spec.drive.law;
      d.name = spec.drive.input;
      d.kind = spec.drive.law;
      d.values = spec.drive.values;
      r.drives.push_back(d);
    }
    return r;
  }
  // A row of the simulate analysis (the sample and its reactions, when found) as the study
  // keeps it.
  template <class Row, class SampleT>
  Row KeepRow(const dynamics::CsvRow<SampleT>& r) const {
    Row row;
    row.s = *r.s;
    if constexpr (statics::StaticsFeatures<M>::kNumReactions != 0) {
      if (r.R != nullptr) {
        row.R = Eigen::Map<const Eigen::VectorXd>(r.R, C::KinetoNumReactions(model_));
        row.has_R = true;
      }
    }
    return row;
  }
  // analysis: simulate with drive: the input driven_input_ on its law from q0 (the others free
  // from q0, qd0) to t_end (dynamics/prescribed.h), a sample every t_end / steps, with the
  // kinetostatics' reactions where a metric reads them: the rows of the simulate analysis
  // (analysis/simulate.h's EvaluateDriven, as `<model>_simulate --drive`) for
  // simulate_request_, under the sample's parameters.
  void SimulateDriven(Rows* out) const {
    if constexpr (run_internal::DrivenOf<M>::kOk) {
      using Driven = run_internal::DrivenOf<M>;
      using Sim = typename Driven::Sim;
      using SampleT = typename Driven::SampleT;
      analysis::simulate_internal::Prepared<M> p;
      p.params = out->params;
      (void)analysis::simulate_internal::InitialState(model_, simulate_request_, &p.q0, &p.qd0);  // (checked: Prepare)
      (void)analysis::simulate_internal::ReadDrives(model_, simulate_request_, &p);
      auto row = [&](const dynamics::CsvRow<SampleT>& r) {
        out->driven.push_back(KeepRow<typename Driven::Row>(r));
        return true;
      };
      dynamics::PrescribedSummary summary;
      const auto evaluated = analysis::simulate_internal::EvaluateDriven<M, dynamics::Dopri5, Driven::kNp>(
          model_, simulate_request_, &p, needs_reactions_, [](Sim&) { return true; }, row, &summary, nullptr);
      out->assembled = evaluated != analysis::simulate_internal::Evaluated::kNotAssembled;
      if (!out->assembled) return;
      out->simulation_status = summary.status;
    } else {
      (void)out;
    }
  }
  // analysis: positions: each row's configuration alone (no velocities): q of row i, the
  // dependent coordinates, the points and the transmission angles. A model whose every block
  // is a closed form solves each row by M::Solve on the assembly's branch (kDefaultModes; the
  // cheapest analysis, no continuation); otherwise, and for the nominal's design derivatives,
  // the continuation of PositionSolver from the model's assembly through the rows in order.
  // analysis: engine: the crank speed (rad/s), as the engine tool has it from --rpm.
  double EngineOmega() const { return spec_.rpm * 2 * 3.14159265358979323846 / 60; }
  // analysis: engine: the engine's cycle at rpm under the study's gas law and its energy loop,
  // the same code as `<engine>_engine flywheel` (machines/engine/cycle.h): the engine read from
  // the sample's parameters, the parametric law's volume from its bore, r and l.
  void EngineCycle(Rows* out) const {
    out->assembled = false;
    out->engine = engine::EngineEnergy();
    if constexpr (engine::CanRunEngineCycle<M>()) {
      Params p = out->params;
      engine::Engine e;
      std::string error;
      engine::PolytropicWiebeCycle wiebe;
      engine::PressureLaw law;
      // The cycle's rows kept (the engine tool's CSV's: the metrics read its columns), their
      // storage this thread's from sample to sample.
      std::vector<engine::CrankPoint<M>>& pts = out->engine_points;
      pts.clear();
      if (!engine::ReadEngine(model_, &p, &e, &error) ||
          !engine::InitPressureLaw(e, spec_.gas.wiebe, has_table_ ? &table_ : nullptr, &wiebe, &law, &error)) {
        out->engine.message = error;
        return;
      }
      const engine::CycleGas gas = engine::MakeGas(model_, &p, e, &law);
      // The engine analysis's rows (analysis/engine.h), as `<engine>_engine flywheel`'s.
      out->assembled =
          analysis::EvaluateEngineCycle(model_, p, e, gas, EngineOmega(), spec_.steps, &pts, &out->engine, &error);
      out->engine_J_fly = e.J_fly;
      out->engine_cycle = e.cycle;
    } else {
      out->engine.message = "not an engine model";
    }
  }
  typename ModelTypes<M>::VecQ RowInput(int i) const {
    using VecQ = typename ModelTypes<M>::VecQ;
    if (!spec_.at.empty()) {
      VecQ q = Eigen::Map<const VecQ>(C::AssemblyQ(model_), C::Nq(model_));
      q(0) = spec_.at[static_cast<size_t>(i)];
      return q;
    }
    if (i == spec_.steps) return q_end_;
    return VecQ(q_begin_ + (double(i) / spec_.steps) * (q_end_ - q_begin_));
  }
  bool AllClosedForm() const {
    if (!C::HasSolve(model_)) return false;
    for (int b = 0; b < C::NumBlocks(model_); ++b)
      if (!C::BlockClosedForm(model_, b)) return false;
    return true;
  }
  void Positions(bool design, Rows* out) const {
    using VecQ = typename ModelTypes<M>::VecQ;
    using VecPhi = typename ModelTypes<M>::VecPhi;
    const size_t n = static_cast<size_t>(spec_.steps) + 1;
    if (out->kinematics.size() != n) out->kinematics.assign(n, Kinematics());
    int converged = 0;
    if constexpr (ModelFeatures<M>::kHasSolve) {
      if (!design && AllClosedForm()) {
        const int nphi = C::Nphi(model_), np = C::NumPoints(model_);
        const typename C::Modes modes = C::DefaultModes(model_);
        VecPhi phi = Eigen::Map<const VecPhi>(C::AssemblyPhi(model_), nphi);
        for (size_t i = 0; i < n; ++i) {
          Kinematics& k = out->kinematics[i];
          const VecQ q = RowInput(static_cast<int>(i));
          k.q = q;
          k.state.q = q;
          typename C::Trig trig;
          typename ModelTypes<M>::Coefficients c;
          VecPhi ph = phi;
          // (C::Solve and C::Coeffs hand the sin and cos over where the model has them.)
          const auto report = C::Solve(model_, out->params, q, &ph, modes, 20, 0.0, &trig);
          using Status = decltype(report.status);
          bool ok = report.status == Status::kConverged && ph.allFinite();
          if (ok) C::Coeffs(model_, out->params, q, ph, &c, &trig);
          if constexpr (M::kNumPoints != 0)
            if (np > 0) ok = ok && c.r_P.allFinite();
          k.summary.status = ok ? position::Status::kConverged : position::Status::kNotRun;
          if (ok) {
            k.state.phi = ph;
          } else {
            k.state.phi.setConstant(nphi, kNaN);
          }
          if constexpr (M::kNumPoints != 0) {
            if (ok) {
              k.state.r_P = c.r_P;
            } else {
              k.state.r_P.setConstant(2, np, kNaN);
            }
          }
          if constexpr (SweepRecord<M>::kNumMu != 0) {
            k.mu.setConstant(C::NumTransmissionAngles(model_), kNaN);
            if (ok) C::TransmissionAngles(model_, out->params, q, ph, &k.mu);
          }
          if (ok) phi = ph, ++converged;
        }
        out->assembled = converged > 0;
        return;
      }
    }
    position::PositionSolver<M> solver(model_, position::Options(), out->params);
    position::Summary summary;
    out->assembled = solver.AssembleDefault(&summary) == position::Status::kConverged;
    if (!out->assembled) return;
    for (size_t i = 0; i < n; ++i) {
      Kinematics& k = out->kinematics[i];
      k = Kinematics();
      k.q = RowInput(static_cast<int>(i));
      const position::Status status = solver.MoveTo(k.q, &k.summary);
      if (status != position::Status::kConverged) {
        k.summary.status = position::Status::kNotRun;
        k.state.q = k.q;
        if constexpr (kDesign && kView)  // (a view's record holds no design values until placed)
          if (design && HasDesign()) position::SetNanDesign(model_, &k.design);
        continue;
      }
      k.state = solver.state();
      if constexpr (SweepRecord<M>::kNumMu != 0) C::TransmissionAngles(model_, out->params, k.state.q, k.state.phi, &k.mu);
      if constexpr (kDesign)
        if (design && HasDesign()) position::EvalDesign<M>(model_, out->params, k.state, &k.design);
    }
  }
  // analysis: simulate: the free motion from q0, qd0 to t_end (dynamics/forward.h), a sample
  // every t_end / steps, with the kinetostatics' reactions where a metric reads them: the rows
  // of the simulate analysis (analysis/simulate.h's EvaluateFree, as `<model>_simulate`) for
  // simulate_request_, under the sample's parameters.
  void Simulate(Rows* out) const {
    if constexpr (run_internal::SimulationOf<M>::kOk) {
      using Sim = typename run_internal::SimulationOf<M>::Sim;
      using SampleT = typename run_internal::SimulationOf<M>::SampleT;
      analysis::simulate_internal::Prepared<M> p;
      p.params = out->params;
      (void)analysis::simulate_internal::InitialState(model_, simulate_request_, &p.q0, &p.qd0);  // (checked: Prepare)
      auto row = [&](const dynamics::CsvRow<SampleT>& r) {
        out->simulation.push_back(KeepRow<typename run_internal::SimulationOf<M>::Row>(r));
        return true;
      };
      dynamics::MinimalSummary summary;
      const auto evaluated = analysis::simulate_internal::EvaluateFree<M, dynamics::Dopri5>(
          model_, simulate_request_, p, needs_reactions_, [](Sim&) { return true; }, row, &summary, nullptr);
      out->assembled = evaluated != analysis::simulate_internal::Evaluated::kNotAssembled;
      if (!out->assembled) return;
      out->simulation_status = summary.status;
    } else {
      (void)out;
    }
  }
  // The rows of the cycle's tables: 4 the flywheel's energy loop (a row per sample of the
  // cycle), 5 the engine's cycle (a row per crank angle), 6 the engine's energy loop (those
  // and the cycle's end, as the engine tool's loop CSV).
  int CycleRows(int table, const Rows& rows) const {
    if (table == 4) return static_cast<int>(rows.cycle.points.size());
    const int n = static_cast<int>(rows.engine_points.size());
    return table == 5 || n == 0 ? n : n + 1;
  }
  std::string CycleColumnUnit(const Ref& r) const {
    if (r.table == 4) return flywheel_columns_[r.column].unit;
    if constexpr (engine::CanRunEngineCycle<M>())
      if (r.table == 5) return engine_columns_[r.column].unit;
    return engine_loop_columns_[r.column].unit;
  }
  // mean_torque and peak_torque of analysis: flywheel and engine from the cycle's columns
  // (refs_[k]: T_mean; T_req or T_total): the mean at the first row (every row's), the peak the
  // largest |T| over the cycle's n samples, where (the first such sample) and T's sign there.
  Taken CycleValue(size_t k, const Rows& rows, int n) const {
    const Ref& r = refs_[k];
    Taken t;
    if (spec_.metrics[k].kind == MetricKind::kMeanTorque) {
      if (n > 0) t.value = Cell(r, rows, 0);
      return t;
    }
    for (int i = 0; i < n; ++i) {
      const double v = Cell(r, rows, i);
      if (std::isfinite(v) && (t.step < 0 || std::abs(v) > t.value)) t.value = std::abs(v), t.step = i, t.sign = v >= 0 ? 1 : -1;
    }
    return t;
  }
  double Cell(const Ref& r, const Rows& rows, int i) const {
    if (r.table == 4) {
      // A row of the flywheel's energy loop CSV (its design columns: the nominal's, else NaN).
      const size_t k = static_cast<size_t>(i);
      const double* design =
          k < rows.cycle_design.dT_req_dp.size() ? rows.cycle_design.dT_req_dp[k].data() : nan_design_.data();
      return flywheel_columns_[r.column].value(analysis::FlywheelLoopRow{rows.cycle.points[k], rows.cycle.T_mean, design});
    }
    if constexpr (engine::CanRunEngineCycle<M>()) {
      const auto& pts = rows.engine_points;
      if (r.table == 5) return engine_columns_[r.column].value(pts[static_cast<size_t>(i)]);
      if (r.table == 6) {
        // A row of the engine tool's energy loop CSV (analysis/engine.h's Flywheel).
        const int n = static_cast<int>(pts.size());
        return engine_loop_columns_[r.column].value(analysis::EngineLoopRow{
            rows.engine_cycle / n * i, pts[static_cast<size_t>(i % n)].T_total, rows.engine.loop.mean_torque,
            i < n ? rows.engine.E[static_cast<size_t>(i)] : 0.0});
      }
    }
    if constexpr (run_internal::DrivenOf<M>::kOk) {
      if (r.table == 3) {
        const auto& row = rows.driven[i];
        return driven_columns_[r.column].value(
            dynamics::CsvRow<typename run_internal::DrivenOf<M>::SampleT>{&row.s, row.has_R ? row.R.data() : nullptr});
      }
    }
    if constexpr (run_internal::SimulationOf<M>::kOk) {
      if (r.table == 2) {
        const auto& row = rows.simulation[i];
        return simulation_columns_[r.column].value(
            dynamics::CsvRow<typename run_internal::SimulationOf<M>::SampleT>{&row.s, row.has_R ? row.R.data() : nullptr});
      }
    }
    if (r.table == 0) {
      const Kinematics& k = rows.kinematics[i];
      if (k.summary.status != position::Status::kConverged) return kNaN;
      return sweep_columns_[r.column].value(k);
    }
    if constexpr (kHasStatics) {
      const StaticsRow& s = rows.statics[i];
      if (s.status != statics::Status::kConverged) return kNaN;
      return statics_columns_[r.column].value(s);
    }
    return kNaN;
  }
  bool RowOk(const Rows& rows, int i) const {
    if (i >= static_cast<int>(rows.kinematics.size())) return false;
    if (rows.kinematics[i].summary.status != position::Status::kConverged) return false;
    if constexpr (kHasStatics)
      if (spec_.analysis == Analysis::kStatics && rows.statics[i].status != statics::Status::kConverged) return false;
    return true;
  }

  M model_;     // (declared first: base_ is initialized from it)
  StudySpec spec_;
  int envelope_point_ = -1;
  Params base_;  // SetBase()
  std::vector<double> nominal_;
  std::vector<int> index_;
  std::vector<Ref> refs_;
  typename ModelTypes<M>::VecQ q_begin_, q_end_;
  std::vector<SweepColumn<M>> sweep_columns_;
  using StaticsColumnTable = std::vector<table::Column<StaticsRow>>;
  StaticsColumnTable statics_columns_;
  typename run_internal::SimulationOf<M>::Columns simulation_columns_;
  int first_reaction_column_ = 0;  ///< simulation_columns_: the first reaction's
  int driven_input_ = -1;          ///< simulate with drive: the driven input (M::kQNames)
  typename run_internal::DrivenOf<M>::Columns driven_columns_;
  int first_driven_reaction_column_ = 0;  ///< driven_columns_: the first reaction's
  bool needs_reactions_ = false;   ///< a metric reads a reaction column of the simulation
  /// analysis: simulate: the simulate analysis's Request the spec makes (SimulateRequestOf).
  analysis::SimulateRequest simulate_request_;
  /// analysis: sweep and statics: the sweep analysis's Request the spec makes (its steps).
  analysis::SweepRequest sweep_request_;
  table::Columns<analysis::FlywheelLoopRow> flywheel_columns_;  ///< flywheel analysis: the energy loop's
  std::vector<double> nan_design_;  ///< flywheel: a sample's dT_req/d<p> (NaN: the nominal's alone)
  typename run_internal::EngineOf<M>::Columns engine_columns_;  ///< engine analysis: the cycle's
  table::Columns<analysis::EngineLoopRow> engine_loop_columns_;   ///< engine analysis: the energy loop's
  engine::PressureTable table_;    ///< engine analysis: the indicator diagram (gas: table:)
  bool has_table_ = false;
  Rows nominal_rows_;
};

}  // namespace mechgen::study
