/**
 * \file statics/sweep.h
 * The statics sweep: for each configuration of a motion (the position sweep of
 * sweep/sweep.h, the same straight line q_begin -> q_end in equal steps, on the branch the
 * solver is assembled on), the driving forces without friction and, with friction, forward
 * and backward for each input, the reactions, V, the stiffness, the mechanical advantage and
 * a status per row. Output: statics/columns.h (CSV, table), statics/svg.h (the mechanism
 * with its reaction vectors).
 *
 * Rows whose position step failed get no forces: a row where the position sweep stopped at
 * a dead point (position::Status::kSingular) is a `singular` row, its forces withheld
 * (reactions grow without bound there), and so is a row whose Phi_phi is too badly
 * conditioned for statics (statics::Options::max_condition). The row vector is sized once;
 * the per-row evaluations do not allocate.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen::statics {

/// The statics' design derivatives (M::StaticsDesignT; for the view internal::ViewStaticsDesign,
/// core/view_model.h: its buffer with a map per member) and the same with every member NaN (or
/// the empty placeholder; for the view an empty value, SetNanStaticsDesign sizes it).
template <class M>
using StaticsDesignOf =
    typename ::mechgen::internal::StaticsDesignOf<M, StaticsFeatures<M>::kHasDesign>::type;
template <class M>
StaticsDesignOf<M> NanStaticsDesign() {
  StaticsDesignOf<M> d;
  if constexpr (StaticsFeatures<M>::kHasDesign && !ModelCalls<M>::kView) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    if constexpr (HasStaticsQ<M>::value) {
      d.dQ_dp.setConstant(nan);
      d.ddrive_dp.setConstant(nan);
    }
    if constexpr (HasStaticsV<M>::value) d.dV_dp.setConstant(nan);
    if constexpr (HasStaticsR<M>::value) d.dR_dp.setConstant(nan);
  }
  return d;
}
/// *d = every member NaN at the model's sizes (NanStaticsDesign; a view's placed on its layout).
template <class M>
void SetNanStaticsDesign(const M& model, StaticsDesignOf<M>* d) {
  if constexpr (ModelCalls<M>::kView) {
    ModelCalls<M>::SetNaN(model, d);
  } else {
    (void)model;
    *d = NanStaticsDesign<M>();
  }
}

/// One row of a statics sweep.
template <class M>
struct StaticsRecord {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  /// Inputs: kNq, or the view's maximum (the view's count at run time).
  static constexpr int kMaxQ = StaticsTypes<M>::kMaxQ;
  /// A generated M: every number NaN. A ViewModel: empty (StaticsRecord(model) sizes it).
  StaticsRecord() = default;
  /// Every number NaN at the model's sizes (for a generated M the same as StaticsRecord()).
  explicit StaticsRecord(const M& model) : kinematics(model), frictionless(model) {
    forward.fill(frictionless);
    backward.fill(frictionless);
    SetNanStaticsDesign(model, &design);
  }
  /// The configuration: q, the position State, motion and the position step's Summary.
  SweepRecord<M> kinematics;
  /// Without friction (no motion): Q, drive, V, R, and stiffness, d2V_dq2 (Model::Stiffness,
  /// evaluated for every converged row) — the members the model has.
  Solution<M> frictionless;
  /// Per input j (only j moving): T0, T_fwd, T_back, efficiencies, self-locking.
  std::array<DriveAnalysis, kMaxQ> drives{};
  /// Per input j with friction: moving along sign(T0_j) e_j (forward: the actuator drives the
  /// load) and along -sign(T0_j) e_j (backward: the load drives the machine). Models without
  /// friction: copies of `frictionless`.
  std::array<Solution<M>, kMaxQ> forward, backward;
  /// One input, a model with point velocity coefficients: 1 / |K_P| of its first requested
  /// point P (m^-1 for a crank, 1 for a slide input): the force a load at P along P's path
  /// balances per unit driving torque or force, by virtual work |F| |K_P| = |T| without
  /// friction (the ideal mechanical advantage; inf at a toggle, where |K_P| <= 1e-12 |r_P|,
  /// i.e. 0 up to rounding). NaN otherwise.
  double mechanical_advantage = kNaN;
  /// kConverged, kSingular (at or next to a dead point), kDidNotConverge (friction), or
  /// kInvalidInput (the position step failed otherwise: see kinematics.summary.status).
  Status status = Status::kNotRun;
  /// Generated statics evaluations of the row.
  int evaluations = 0;
  /// With Options::design (a model with EvalStaticsDesign): d/dp of Q, the drive, V and the
  /// reactions without friction; NaN where the frictionless solution is withheld, and at
  /// velocities that the statics read (the derivatives are of the statics at rest).
  StaticsDesignOf<M> design = NanStaticsDesign<M>();
};

/// The solution of row r with input j moving along +e_j (way > 0) or -e_j (way < 0): the
/// forward or the backward one, whichever moved that way (see DriveAnalysis).
template <class M>
const Solution<M>& Moving(const StaticsRecord<M>& r, int j, double way) {
  return r.forward[j].direction(j) * way > 0 ? r.forward[j] : r.backward[j];
}

/// The status text of a row: the statics status, or the position step's when it failed.
template <class M>
const char* RowStatus(const StaticsRecord<M>& r) {
  const position::Status p = r.kinematics.summary.status;
  if (p != position::Status::kConverged && p != position::Status::kSingular) {
    return position::ToString(p);
  }
  return ToString(r.status);
}

/**
 * \brief The statics of one valid configuration into *r (r->kinematics filled): every
 *        solution, the drive analyses and the mechanical advantage. No allocation.
 *        The coefficients (Phi_phi, K, L) from the state, as the position step evaluated them
 *        (Model::Coeffs only for a state without them), the frictionless statics once (with
 *        the stiffness; every input's drive analysis reads it), and per input with friction
 *        the forward and backward ones.
 * \param[in] p           The parameters the state was solved with (its coefficients are).
 * \param[in] velocities  The input velocities the loads are taken at (statics/solve.h,
 *                        "Speed"); nullptr: at rest.
 */
template <class M>
Status EvaluateRecord(const M& model, const Options& options, const typename ModelTypes<M>::Params& p,
                      StaticsRecord<M>* r,
                      const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  using VecQ = typename ModelTypes<M>::VecQ;
  using C = ModelCalls<M>;
  const position::State<M>& state = r->kinematics.state;
  const int nq = C::Nq(model);
  r->evaluations = 0;
  r->mechanical_advantage = StaticsRecord<M>::kNaN;
  SetNanStaticsDesign(model, &r->design);
  if (!state.valid || r->kinematics.summary.status != position::Status::kConverged) {
    const bool singular = r->kinematics.summary.status == position::Status::kSingular;
    if constexpr (C::kView) {
      r->frictionless = Solution<M>(model);
    } else {
      r->frictionless = Solution<M>();
    }
    r->frictionless.summary.status = singular ? Status::kSingular : Status::kInvalidInput;
    r->frictionless.summary.reason = singular ? "the position step stopped at a dead point"
                                              : "the position step failed";
    for (int j = 0; j < nq; ++j) {
      r->forward[j] = r->backward[j] = r->frictionless;
      r->drives[j] = DriveAnalysis();
      r->drives[j].input = j;
      r->drives[j].status = r->frictionless.summary.status;
    }
    return r->status = r->frictionless.summary.status;
  }
  // The coefficients the statics read (Phi_phi, K, L), as the position step evaluated them
  // (position::State), not evaluated again; a state that lacks them (Phi_phi NaN: a model whose
  // coefficients do not carry Phi_phi, or a state not from the solver) evaluates them.
  typename ModelTypes<M>::Coefficients c;
  bool from_state = false;
  if constexpr (ModelFeatures<M>::kCoeffsHavePhi && ModelFeatures<M>::kHasK) {
    from_state = C::CoeffsHavePhi(model) && C::HasK(model) && ::mechgen::internal::Finite(state.Phi_phi);
    if (from_state) C::StaticsCoefficients(model, state, &c);
  }
  if (!from_state) C::Coeffs(model, p, state.q, state.phi, &c);
  // The frictionless statics once per row, with the stiffness (it excludes friction anyway);
  // every input's drive analysis reads it.
  Options with_stiffness = options, without_stiffness = options;
  with_stiffness.stiffness = true;
  without_stiffness.stiffness = false;
  Status status = Solve<M>(model, with_stiffness, p, state.q, state.phi, c, internal::Zeros<VecQ>(nq),
                           &r->frictionless, velocities);
  r->evaluations += r->frictionless.summary.iterations;
  for (int j = 0; j < nq; ++j) {
    if (r->frictionless.summary.status != Status::kConverged) {
      r->forward[j] = r->backward[j] = r->frictionless;
      r->drives[j] = DriveAnalysis();
      r->drives[j].input = j;
      r->drives[j].status = r->frictionless.summary.status;
      continue;
    }
    const Status drive =
        AnalyzeDriveFrom<M>(model, without_stiffness, p, state.q, state.phi, c, j, r->frictionless,
                            &r->drives[j], &r->forward[j], &r->backward[j], velocities);
    if (internal::HasFriction(model)) {
      r->evaluations += r->forward[j].summary.iterations + r->backward[j].summary.iterations;
    }
    if (status == Status::kConverged) status = drive;
  }
  if constexpr (StaticsFeatures<M>::kHasDesign) {
    // The design derivatives are those of the statics at rest (EvalStaticsDesign takes no
    // velocities): none at a speed that the loads read.
    const bool at_speed = StaticsFeatures<M>::kReadsSpeed && C::ReadsSpeed(model) && velocities != nullptr;
    if (options.design && C::HasStaticsDesign(model) && !at_speed &&
        r->frictionless.summary.status == Status::kConverged) {
      position::EvalDesign<M>(model, p, state, &r->kinematics.design);
      C::StaticsDesign(model, p, state.q, state.phi, c, r->kinematics.design, &r->design);
    }
  }
  if constexpr ((M::kNq == 1 || C::kView) && ModelFeatures<M>::kHasPointVelocities) {
    if (status == Status::kConverged && nq == 1 && C::HasPointVelocities(model)) {
      // At a toggle K_P is 0 up to rounding (~eps |r_P|): report inf there, not 1 / rounding.
      const double speed = std::hypot(state.K_P(0, 0), state.K_P(1, 0));
      const double rounding = 1e-12 * std::hypot(state.r_P(0, 0), state.r_P(1, 0));
      r->mechanical_advantage =
          speed > rounding ? 1.0 / speed : std::numeric_limits<double>::infinity();
    }
  }
  return r->status = status;
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
Status EvaluateRecord(const Options& options, const typename ModelTypes<M>::Params& p,
                      StaticsRecord<M>* r,
                      const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  return EvaluateRecord<M>(M(), options, p, r, velocities);
}

/// The row callback of the view's StaticsSweepRows (pass an lvalue of this type).
template <class M>
using StaticsRowFn = std::function<void(int, const StaticsRecord<M>&)>;

/**
 * \brief Sweeps the inputs from q_begin to q_end in `steps` equal steps (steps + 1 rows) with
 *        the position solver, evaluates the statics of every row and hands it to
 *        `row(index, record)` as soon as it is evaluated (streaming: one record is held).
 * \param[in]     options        Statics options.
 * \param[in,out] solver         An assembled solver (state().valid), e.g. AssembleDefault().
 * \param[in]     q_begin        First inputs (dim kNq).
 * \param[in]     q_end          Last inputs (dim kNq).
 * \param[in]     steps          Number of steps, >= 1.
 * \param[in]     sweep_options  What the position sweep does at a dead point (default: stop).
 * \param[in]     velocities     The input velocities the loads are taken at in every row
 *                               (statics/solve.h, "Speed"; the constant speed of the motion);
 *                               nullptr: at rest.
 * \param[in]     row            Called as row(int index, const StaticsRecord<M>&), in order.
 * \return the number of rows whose status is not kConverged.
 */
template <class M, class A, class RowFn>
int StaticsSweepRows(const Options& options, position::PositionSolver<M, A>* solver,
                     const typename ModelTypes<M>::VecQ& q_begin,
                     const typename ModelTypes<M>::VecQ& q_end, int steps,
                     const SweepOptions& sweep_options,
                     const typename ModelTypes<M>::VecQ* velocities, RowFn&& row) {
  using VecQ = typename ModelTypes<M>::VecQ;
  const M& model = solver->model();
  const int nq = ModelCalls<M>::Nq(model);
  StaticsRecord<M> record(model);
  int failures = 0;
  auto evaluate = [&](int i, const SweepRecord<M>& k) {
    record.kinematics = k;
    if (EvaluateRecord<M>(model, options, solver->params(), &record, velocities) != Status::kConverged)
      ++failures;
    row(i, static_cast<const StaticsRecord<M>&>(record));
  };
  const VecQ ones = VecQ::Ones(nq), zeros = internal::Zeros<VecQ>(nq);
  if constexpr (ModelCalls<M>::kView) {
    // The instantiation of SweepRows in mechgen_runtime_view (core/view_runtime.h: ViewRowFn).
    std::function<void(int, const SweepRecord<M>&)> kinematics = evaluate;
    SweepRows(solver, q_begin, q_end, steps, ones, zeros, sweep_options, kinematics);
  } else {
    SweepRows(solver, q_begin, q_end, steps, ones, zeros, sweep_options, evaluate);
  }
  return failures;
}

/**
 * \brief StaticsSweepRows() into a vector: `records` gets steps + 1 rows.
 * \param[out]    records        steps + 1 rows.
 * The other parameters and the return value as in StaticsSweepRows().
 */
template <class M, class A>
int StaticsSweep(const Options& options, position::PositionSolver<M, A>* solver,
                 const typename ModelTypes<M>::VecQ& q_begin,
                 const typename ModelTypes<M>::VecQ& q_end, int steps,
                 std::vector<StaticsRecord<M>>* records,
                 const SweepOptions& sweep_options = SweepOptions(),
                 const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  records->clear();
  records->reserve(static_cast<size_t>(std::max(steps, 1)) + 1);
  return StaticsSweepRows(options, solver, q_begin, q_end, steps, sweep_options, velocities,
                          [records](int, const StaticsRecord<M>& r) { records->push_back(r); });
}

/**
 * \brief What a statics sweep of model M says about speed, for its printed output and its
 *        CSV's first comment line (the same text in both): empty when nothing in the statics
 *        reads a velocity and none is given. At rest (velocities nullptr), which loads read a
 *        velocity and that they are taken at qd = 0; at the velocities qd, that they are taken
 *        there, without the inertia forces. One line, no trailing period.
 */
template <class M>
std::string SpeedNote(const M& model, const typename ModelTypes<M>::VecQ* velocities) {
  using C = ModelCalls<M>;
  const std::vector<std::string> items = SpeedItems<M>(model);
  std::string what;
  for (size_t i = 0; i < items.size(); ++i)
    what += std::string(i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + "the " + items[i];
  if (velocities == nullptr) {
    if (items.empty()) return "";
    return "at rest: " + what +
           (items.size() == 1 ? " reads a velocity and is" : " read a velocity and are") +
           " taken at qd = 0, t = 0 (the value in a slow motion), not at the machine's speed; "
           "--speed gives the statics at a constant input speed";
  }
  std::string at;
  for (int j = 0; j < C::Nq(model); ++j) {
    char value[64];
    std::snprintf(value, sizeof(value), "%.9g", (*velocities)(j) + 0.0);  // no -0
    at += std::string(j == 0 ? "" : ", ") + C::QName(model, j) + "_dot = " + value +
          (C::QIsAngle(model, j) ? " rad/s" : " model length/s");
  }
  if (items.empty())
    return "at " + at + ": nothing in the statics reads a velocity (the same at any speed)";
  return "at " + at + ": " + what + (items.size() == 1 ? " is" : " are") +
         " taken at these velocities (the dependent ones K qd, t = 0), without the inertia "
         "forces (the kinetostatics at qdd = 0 without them); Coulomb friction for the input "
         "running in +q and -q alike; no stiffness (that of the loads at rest)";
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
std::string SpeedNote(const typename ModelTypes<M>::VecQ* velocities) {
  return SpeedNote<M>(M(), velocities);
}

}  // namespace mechgen::statics
