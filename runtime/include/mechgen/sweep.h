/**
 * \file sweep.h
 * A sweep: the inputs move along the straight line q_begin -> q_end in equal steps and the
 * solver continues from one configuration to the next, on the branch it was assembled on.
 *
 * Every step is a PositionSolver::MoveTo() plus ComputeMotion(); the record vector is sized
 * once before the loop, so the loop itself does not allocate (unless a step falls back to
 * Ceres). A step that fails is recorded with its Status and NaN values, and the solver
 * continues the next step from its last valid configuration.
 */
#pragma once

#include <vector>

#include "mechgen/kinematics.h"
#include "mechgen/solver.h"

namespace mechgen {

/// One row of a sweep.
template <class M>
struct SweepRecord {
  typename ModelTypes<M>::VecQ q;  ///< requested inputs (kNq)
  State<M> state;                  ///< the configuration at q; NaN and !valid when failed
  Motion<M> motion;                ///< velocities and accelerations; NaN when failed
  Summary summary;                 ///< how the step went
};

/**
 * \brief Sweeps the inputs from q_begin to q_end in `steps` equal steps (steps + 1 rows).
 * \param[in,out] solver   An assembled solver (state().valid), e.g. after AssembleDefault().
 *                         The first row is reached by continuation from solver->state().
 * \param[in]     q_begin  First inputs (dim kNq).
 * \param[in]     q_end    Last inputs (dim kNq).
 * \param[in]     steps    Number of steps, >= 1.
 * \param[in]     qd       Input speeds for the motion (dim kNq), the same at every row.
 * \param[in]     qdd      Input accelerations (dim kNq).
 * \param[out]    records  steps + 1 rows.
 * \return the number of rows that did not converge.
 */
template <class M>
int Sweep(PositionSolver<M>* solver,
          const typename ModelTypes<M>::VecQ& q_begin,
          const typename ModelTypes<M>::VecQ& q_end,
          int steps,
          const typename ModelTypes<M>::VecQ& qd,
          const typename ModelTypes<M>::VecQ& qdd,
          std::vector<SweepRecord<M>>* records) {
  if (steps < 1) steps = 1;
  records->assign(static_cast<size_t>(steps) + 1, SweepRecord<M>());
  int failures = 0;
  for (int i = 0; i <= steps; ++i) {
    SweepRecord<M>& record = (*records)[static_cast<size_t>(i)];
    record.q = i == steps ? q_end : typename ModelTypes<M>::VecQ(
                                        q_begin + (q_end - q_begin) * (double(i) / steps));
    if (solver->MoveTo(record.q, &record.summary) == Status::kConverged) {
      record.state = solver->state();
      ComputeMotion(record.state, qd, qdd, &record.motion);
    } else {
      record.state.q = record.q;
      ++failures;
    }
  }
  return failures;
}

}  // namespace mechgen
