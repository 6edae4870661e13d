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

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen::statics {

/// One row of a statics sweep.
/// The statics' design derivatives with every member NaN (or the empty placeholder).
template <class M>
typename ::mechgen::internal::StaticsDesignOf<M>::type NanStaticsDesign() {
  typename ::mechgen::internal::StaticsDesignOf<M>::type d;
  if constexpr (HasStaticsDesign<M>::value) {
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

template <class M>
struct StaticsRecord {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  /// The configuration: q, the position State, motion and the position step's Summary.
  SweepRecord<M> kinematics;
  /// Without friction (no motion): Q, drive, V, R, and stiffness, d2V_dq2 (Model::Stiffness,
  /// evaluated for every converged row) — the members the model has.
  Solution<M> frictionless;
  /// Per input j (only j moving): T0, T_fwd, T_back, efficiencies, self-locking.
  std::array<DriveAnalysis, M::kNq> drives{};
  /// Per input j with friction: moving along sign(T0_j) e_j (forward: the actuator drives the
  /// load) and along -sign(T0_j) e_j (backward: the load drives the machine). Models without
  /// friction: copies of `frictionless`.
  std::array<Solution<M>, M::kNq> forward, backward;
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
  /// reactions without friction; NaN where the frictionless solution is withheld.
  typename ::mechgen::internal::StaticsDesignOf<M>::type design = NanStaticsDesign<M>();
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
 */
template <class M>
Status EvaluateRecord(const Options& options, const typename ModelTypes<M>::Params& p,
                      StaticsRecord<M>* r) {
  using VecQ = typename ModelTypes<M>::VecQ;
  const position::State<M>& state = r->kinematics.state;
  r->evaluations = 0;
  r->mechanical_advantage = StaticsRecord<M>::kNaN;
  if (!state.valid || r->kinematics.summary.status != position::Status::kConverged) {
    const bool singular = r->kinematics.summary.status == position::Status::kSingular;
    r->frictionless = Solution<M>();
    r->frictionless.summary.status = singular ? Status::kSingular : Status::kInvalidInput;
    r->frictionless.summary.reason = singular ? "the position step stopped at a dead point"
                                              : "the position step failed";
    for (int j = 0; j < M::kNq; ++j) {
      r->forward[j] = r->backward[j] = r->frictionless;
      r->drives[j] = DriveAnalysis();
      r->drives[j].input = j;
      r->drives[j].status = r->frictionless.summary.status;
    }
    return r->status = r->frictionless.summary.status;
  }
  typename ModelTypes<M>::Coefficients c;
  M::template Coeffs<double>(p, state.q, state.phi, &c);
  r->design = NanStaticsDesign<M>();
  // The stiffness once per row, without friction (it excludes friction anyway).
  Options with_stiffness = options, without_stiffness = options;
  with_stiffness.stiffness = true;
  without_stiffness.stiffness = false;
  Status status =
      Solve<M>(with_stiffness, p, state.q, state.phi, c, VecQ::Zero(), &r->frictionless);
  r->evaluations += r->frictionless.summary.iterations;
  for (int j = 0; j < M::kNq; ++j) {
    if (r->frictionless.summary.status != Status::kConverged) {
      r->forward[j] = r->backward[j] = r->frictionless;
      r->drives[j] = DriveAnalysis();
      r->drives[j].input = j;
      r->drives[j].status = r->frictionless.summary.status;
      continue;
    }
    Solution<M> unused;
    const Status drive =
        AnalyzeDrive<M>(without_stiffness, p, state.q, state.phi, c, j, &r->drives[j], &unused,
                        &r->forward[j], &r->backward[j]);
    if constexpr (StaticsFeatures<M>::kHasFriction) {
      r->evaluations += r->forward[j].summary.iterations + r->backward[j].summary.iterations;
    }
    if (status == Status::kConverged) status = drive;
  }
  if constexpr (HasStaticsDesign<M>::value) {
    if (options.design && r->frictionless.summary.status == Status::kConverged) {
      position::EvalDesign<M>(p, state, &r->kinematics.design);
      M::StaticsDesign(p, state.q, state.phi, c, r->kinematics.design, &r->design);
    }
  }
  if constexpr (M::kNq == 1 && ModelFeatures<M>::kHasPointVelocities) {
    if (status == Status::kConverged) {
      // At a toggle K_P is 0 up to rounding (~eps |r_P|): report inf there, not 1 / rounding.
      const double speed = std::hypot(state.K_P(0, 0), state.K_P(1, 0));
      const double rounding = 1e-12 * std::hypot(state.r_P(0, 0), state.r_P(1, 0));
      r->mechanical_advantage =
          speed > rounding ? 1.0 / speed : std::numeric_limits<double>::infinity();
    }
  }
  return r->status = status;
}

/**
 * \brief Sweeps the inputs from q_begin to q_end in `steps` equal steps (steps + 1 rows) with
 *        the position solver, and evaluates the statics of every row.
 * \param[in]     options        Statics options.
 * \param[in,out] solver         An assembled solver (state().valid), e.g. AssembleDefault().
 * \param[in]     q_begin        First inputs (dim kNq).
 * \param[in]     q_end          Last inputs (dim kNq).
 * \param[in]     steps          Number of steps, >= 1.
 * \param[out]    records        steps + 1 rows.
 * \param[in]     sweep_options  What the position sweep does at a dead point (default: stop).
 * \return the number of rows whose status is not kConverged.
 */
template <class M, class A>
int StaticsSweep(const Options& options, position::PositionSolver<M, A>* solver,
                 const typename ModelTypes<M>::VecQ& q_begin,
                 const typename ModelTypes<M>::VecQ& q_end, int steps,
                 std::vector<StaticsRecord<M>>* records,
                 const SweepOptions& sweep_options = SweepOptions()) {
  using VecQ = typename ModelTypes<M>::VecQ;
  std::vector<SweepRecord<M>> kinematics;
  Sweep(solver, q_begin, q_end, steps, VecQ::Ones(), VecQ::Zero(), &kinematics, sweep_options);
  records->assign(kinematics.size(), StaticsRecord<M>());
  int failures = 0;
  for (size_t i = 0; i < kinematics.size(); ++i) {
    StaticsRecord<M>& r = (*records)[i];
    r.kinematics = kinematics[i];
    if (EvaluateRecord<M>(options, solver->params(), &r) != Status::kConverged) ++failures;
  }
  return failures;
}

}  // namespace mechgen::statics
