/**
 * \file sweep/sweep.h
 * A sweep: the inputs move along the straight line q_begin -> q_end in equal steps and the
 * solver continues from one configuration to the next, on the branch it was assembled on.
 *
 * Every step is a PositionSolver::MoveTo() plus ComputeMotion(). SweepRows() hands each row
 * to a callback as soon as it is solved (a million-step sweep streams to its CSV and holds
 * one record); Sweep() collects the rows in a vector sized once before the loop. Neither
 * loop allocates (unless a step falls back to CeresAssembler). A step that fails is recorded
 * with its Status and NaN values, and the solver continues the next step from its last
 * valid configuration; a step that reaches a singular configuration (kSingular) stops the
 * sweep there, unless SweepOptions asks to pass it; the rows after a stop are kNotRun, with
 * the inputs they asked for.
 */
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_view.h"
#include "mechgen/position/design.h"
#include "mechgen/position/motion.h"
#include "mechgen/position/solver.h"

namespace mechgen {

/// One row of a sweep.
template <class M>
struct SweepRecord {
  /// The transmission angles' count (Eigen::Dynamic for a ViewModel: its view's).
  static constexpr int kNumMu = ModelFeatures<M>::kNumTransmissionAngles;
  using VecMu = Eigen::Matrix<double, kNumMu, 1, 0,
                              kNumMu == Eigen::Dynamic ? ModelView::kMaxTransmissionAngles : kNumMu, 1>;
  /// A generated M: every number NaN. A ViewModel: empty (SweepRecord(model) sizes it).
  SweepRecord() = default;
  /// Every number NaN at the model's sizes (for a generated M the same as SweepRecord()).
  explicit SweepRecord(const M& model) : state(model) {
    if constexpr (ModelCalls<M>::kView) {
      using C = ModelCalls<M>;
      constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
      q.setConstant(C::Nq(model), kNaN);
      motion = position::Motion<M>(C::Nq(model), C::Nphi(model), C::NumPoints(model));
      mu.setConstant(C::NumTransmissionAngles(model), kNaN);
      position::SetNanDesign(model, &design);
    }
  }
  /// Requested inputs (kNq); NaN until the sweep sets them (a fixed-size Eigen vector is
  /// left uninitialized by SweepRecord<M>() without this initializer).
  typename ModelTypes<M>::VecQ q = NaNs<typename ModelTypes<M>::VecQ>();
  position::State<M> state;    ///< the configuration at q; NaN and !valid when failed
  position::Motion<M> motion;  ///< velocities and accelerations; NaN when failed
  position::Summary summary;   ///< how the step went
  /// Transmission angle of each four-bar loop (M::kTransmissionJoints), radians in [0, pi];
  /// NaN when the step failed.
  VecMu mu = NaNs<VecMu>();
  /// d/dp of phi, K, L and the points for M's design parameters (position/design.h), where
  /// SweepOptions::design asks for them; NaN otherwise and where the step failed.
  position::DesignOf<M> design = position::NanDesign<M>();
};

/// What a sweep does at a singular configuration.
struct SweepOptions {
  /// kStop: the sweep stops at the first kSingular row (that row holds the last valid
  /// configuration, closest to the singular one; later rows are kNotRun). Otherwise
  /// PositionSolver::PassSingularity() with this choice, and the sweep goes on: after
  /// kReverseInput the input moves back (the remaining rows mirror about the dead point,
  /// and the input speed qd changes sign), so a rocker-driven linkage swings back and forth.
  position::Crossing at_singularity = position::Crossing::kStop;
  /// Evaluate the design derivatives of every row (SweepRecord::design; a model with a design
  /// section only: M::kHasDesignDerivatives).
  bool design = false;
};

/**
 * \brief Sweeps the inputs from q_begin to q_end in `steps` equal steps (steps + 1 rows),
 *        handing each row to `row(index, record)` as soon as it is solved (streaming: a
 *        sweep of any length holds one record; the callback writes it out or keeps it).
 * \param[in,out] solver   An assembled solver (state().valid), e.g. after AssembleDefault().
 *                         The first row is reached by continuation from solver->state().
 * \param[in]     q_begin  First inputs (dim kNq).
 * \param[in]     q_end    Last inputs (dim kNq).
 * \param[in]     steps    Number of steps, >= 1 (smaller values are taken as 1).
 * \param[in]     qd       Input speeds for the motion (dim kNq), the same at every row.
 * \param[in]     qdd      Input accelerations (dim kNq).
 * \param[in]     options  What to do at a singular configuration.
 * \param[in]     row      Called as row(int index, const SweepRecord<M>&) for index
 *                         0..steps, in order. A kNotRun row (after a stop) carries the input
 *                         it would have been solved at, and NaN values.
 * \return the number of rows that did not converge (kNotRun rows after a stop included).
 * Allocation-free apart from the solver's failure path and what `row` does.
 */
template <class M, class Assembler, class RowFn>
int SweepRows(position::PositionSolver<M, Assembler>* solver,
              const typename ModelTypes<M>::VecQ& q_begin,
              const typename ModelTypes<M>::VecQ& q_end,
              int steps,
              const typename ModelTypes<M>::VecQ& qd,
              const typename ModelTypes<M>::VecQ& qdd,
              const SweepOptions& options,
              RowFn&& row) {
  using VecQ = typename ModelTypes<M>::VecQ;
  if (steps < 1) steps = 1;
  const VecQ delta = q_end - q_begin;
  const double delta2 = delta.squaredNorm();
  // u: position along the line (q = q_begin + u delta); dir: +1 forward, -1 after a reversal.
  auto at = [&](double u) { return VecQ(q_begin + u * delta); };
  auto position_of = [&](const VecQ& q) {
    return delta2 > 0 ? (q - q_begin).dot(delta) / delta2 : 0.0;
  };
  double dir = 1;
  int failures = 0;
  bool stopped = false;
  double u_prev = 0;   // where the previous row ended (its q)
  double u_asked = 0;  // the input the previous row asked for
  const SweepRecord<M> nan_record(solver->model());  // every number NaN, at the model's sizes
  // The one record: a row that converges (or stops at a singular configuration) writes every
  // member of it that has a value (q, the summary, the state, the motion, the transmission
  // angles and the design derivatives where the model has them and they are asked for), the
  // same ones on every row, the others NaN from here; a row without values starts again from
  // nan_record. (Setting it to NaN before every row cost, for the view, a copy of every
  // bounded matrix of the record per row.)
  SweepRecord<M> record = nan_record;
  for (int i = 0; i <= steps; ++i) {
    if (stopped) {
      // Not run: the input this row would have been solved at, values NaN.
      record = nan_record;
      u_asked += dir / steps;
      record.q = (i == steps && dir > 0) ? q_end : at(u_asked);
      record.state.q = record.q;
      ++failures;
      row(i, static_cast<const SweepRecord<M>&>(record));
      continue;
    }
    double u = i == 0 ? 0.0 : u_prev + dir / steps;
    record.q = (i == steps && dir > 0) ? q_end : at(u);
    u_asked = u;
    position::Status status = solver->MoveTo(record.q, &record.summary);
    bool reversed = false;
    if (status == position::Status::kSingular &&
        options.at_singularity != position::Crossing::kStop) {
      // Pass, then finish the row: the rest of the step, mirrored after a reversal.
      const double u_singular = position_of(solver->state().q);
      position::Summary pass;
      if (solver->PassSingularity(record.q, options.at_singularity, &pass) ==
          position::Status::kConverged) {
        reversed = pass.input_reversed;
        if (reversed) {
          dir = -dir;
          u = 2 * u_singular - u;
          record.q = at(u);
          u_asked = u;
        }
        const double u_passed = position_of(solver->state().q);
        if ((u - u_passed) * dir > 0) {
          status = solver->MoveTo(record.q, &record.summary);
        } else {  // the pass already went beyond this row's input: record where it ended
          record.q = solver->state().q;
          record.summary = pass;
          status = position::Status::kConverged;
        }
        record.summary.iterations += pass.iterations;
        record.summary.input_reversed = reversed;
      } else {
        record.summary.reason = pass.reason;
      }
    }
    if (status == position::Status::kConverged || status == position::Status::kSingular) {
      // kSingular: stop at the last valid configuration, the closest to the singular one.
      record.state = solver->state();
      if (status == position::Status::kSingular) record.q = record.state.q;
      position::ComputeMotion(record.state, VecQ(dir * qd), qdd, &record.motion);
      if constexpr (SweepRecord<M>::kNumMu != 0) {  // (a view: its count at run time)
        ModelCalls<M>::TransmissionAngles(solver->model(), solver->params(), record.state.q,
                                          record.state.phi, &record.mu);
      }
      if (options.design) position::EvalDesign<M>(solver->model(), solver->params(), record.state, &record.design);
      if (status == position::Status::kSingular) {
        stopped = true;
        ++failures;
      }
    } else {
      // No values: every number NaN but the input asked for and the step's summary.
      const position::Summary summary = record.summary;
      const VecQ q = record.q;
      record = nan_record;
      record.q = q;
      record.summary = summary;
      record.state.q = record.q;
      ++failures;
    }
    u_prev = position_of(record.q);
    row(i, static_cast<const SweepRecord<M>&>(record));
  }
  return failures;
}

/**
 * \brief SweepRows() into a vector: `records` gets steps + 1 rows (sized once, before the
 *        loop). For long sweeps prefer SweepRows() with a callback that writes each row out.
 * \param[out] records  steps + 1 rows.
 * The other parameters and the return value as in SweepRows().
 */
template <class M, class Assembler>
int Sweep(position::PositionSolver<M, Assembler>* solver,
          const typename ModelTypes<M>::VecQ& q_begin,
          const typename ModelTypes<M>::VecQ& q_end,
          int steps,
          const typename ModelTypes<M>::VecQ& qd,
          const typename ModelTypes<M>::VecQ& qdd,
          std::vector<SweepRecord<M>>* records,
          const SweepOptions& options = SweepOptions()) {
  records->assign(static_cast<size_t>(std::max(steps, 1)) + 1, SweepRecord<M>(solver->model()));
  return SweepRows(solver, q_begin, q_end, steps, qd, qdd, options,
                   [records](int i, const SweepRecord<M>& r) {
                     (*records)[static_cast<size_t>(i)] = r;
                   });
}

}  // namespace mechgen
