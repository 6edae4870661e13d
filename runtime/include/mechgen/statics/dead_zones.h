/**
 * \file statics/dead_zones.h
 * Dead zones of an input (Paul §5.6.3): the intervals of its range where the mechanism is
 * self-locking, i.e. where the load alone cannot drive it backwards because friction
 * absorbs more than the load's generalized force: T_back T0 <= 0, with T0 the frictionless
 * driving force of the input and T_back its driving force when moving along -sign(T0)
 * (statics/solve.h, AnalyzeDrive()). Example: a slider-crank driven from its piston locks
 * near the dead centres, where the rod's line of action passes inside the friction circle
 * of the crank bearing, a |sin(theta - beta)| <= mu_O r_O.
 *
 * FindDeadZones() samples the range with the position solver (one continuation step per
 * sample, on the branch it is assembled on), evaluates self-locking at each sample, and
 * refines every change between neighbouring samples by bisection on the sign of
 * T_back T0, each bisection point a continuation step of the same solver. A scan coarser
 * than ScanOptions::kMinSamples samples or kMaxAngleStep per sample along an angle input is
 * refused (kInvalidInput): samples that all land in the zones (the dead centres) would make
 * the whole range one zone. A zone, or a gap between zones, narrower than one sample step
 * can still be missed. Only the zone list allocates (push_back); the evaluations do not. No
 * exceptions.
 */
#pragma once

#include <cmath>
#include <vector>

#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"

namespace mechgen::statics {

/// An interval of input j where the mechanism is self-locking.
struct DeadZone {
  int input = 0;  ///< j
  /// The interval's ends, input units (rad for an angle, model length for a slide), in the
  /// order of the scan (begin < end when the scan runs upwards).
  double begin = 0;
  double end = 0;
  /// true: the end is a transition located to ScanOptions::tolerance; false: the interval is
  /// cut by the scanned range (a full turn: a zone across 0 = 360 deg comes as two zones,
  /// one at each end of the range) or by an unusable sample next to it.
  bool begin_located = false;
  bool end_located = false;
};

/**
 * \brief The dead zones of input j over [begin, end] (other inputs at solver->state().q).
 * \param[in]     options  Statics options (friction iteration, singular threshold).
 * \param[in]     scan     Samples and the refinement tolerance.
 * \param[in,out] solver   Assembled (state().valid); moved along the range; on return at the
 *                         last sample it reached.
 * \param[in]     input    j in [0, kNq).
 * \param[in]     begin    First input value, input units (rad for angles).
 * \param[in]     end      Last input value.
 * \param[out]    zones    The dead zones in scan order (cleared first).
 * \param[out]    summary  May be nullptr.
 * \return ScanSummary::status (statics/types.h).
 */
template <class M, class A>
Status FindDeadZones(const Options& options, const ScanOptions& scan,
                     position::PositionSolver<M, A>* solver, int input, double begin, double end,
                     std::vector<DeadZone>* zones, ScanSummary* summary = nullptr) {
  using VecQ = typename ModelTypes<M>::VecQ;
  using C = ModelCalls<M>;
  const M& model = solver->model();
  ScanSummary s;
  zones->clear();
  auto finish = [&](Status status, const char* reason) {
    s.status = status;
    s.reason = reason;
    if (summary != nullptr) *summary = s;
    return status;
  };
  if (!options.IsValid(nullptr) || !scan.IsValid(nullptr) || input < 0 || input >= C::Nq(model) ||
      !std::isfinite(begin) || !std::isfinite(end) || !solver->state().valid) {
    return finish(Status::kInvalidInput,
                  "invalid options or input, range not finite, or solver not assembled");
  }
  if (C::QIsAngle(model, input) && !scan.ResolvesAngle(end - begin)) {
    return finish(Status::kInvalidInput,
                  "scan too coarse: more than 10 deg per sample along an angle input "
                  "(ScanOptions::kMaxAngleStep); use more samples");
  }
  VecQ q0 = solver->state().q;
  auto at = [&](double t) {
    VecQ q = q0;
    q(input) = begin + t;
    return q;
  };
  const double length = end - begin;
  bool refinement_failed = false;
  // 1: self-locking, 0: not, -1: unusable (position step or statics failed).
  auto locked = [&](double t) {
    const position::Status moved = solver->MoveTo(at(t), nullptr);
    if (moved != position::Status::kConverged) {
      if (s.position_status == position::Status::kConverged) s.position_status = moved;
      return -1;
    }
    DriveAnalysis drive;
    Solution<M> frictionless, forward, backward;
    const Status status = AnalyzeDriveAt<M>(model, options, solver->params(), solver->state(), input,
                                            &drive, &frictionless, &forward, &backward);
    s.evaluations += frictionless.summary.iterations;
    if (internal::HasFriction(model)) {
      s.evaluations += forward.summary.iterations + backward.summary.iterations;
    }
    if (status != Status::kConverged) return -1;
    return drive.self_locking ? 1 : 0;
  };
  // The transition between t_from (state from_value) and t_to, by bisection; leaves the
  // solver at t_to again.
  auto refine = [&](double t_from, int from_value, double t_to, bool* located) {
    double lo = t_from, hi = t_to;
    *located = true;
    for (int it = 0; it < scan.max_refinements && std::abs(hi - lo) > scan.tolerance; ++it) {
      const double mid = 0.5 * (lo + hi);
      const int value = locked(mid);
      if (value < 0) {
        *located = false;
        refinement_failed = true;
        break;
      }
      (value == from_value ? lo : hi) = mid;
    }
    if (std::abs(hi - lo) > scan.tolerance) *located = false;
    solver->MoveTo(at(t_to), nullptr);
    return begin + 0.5 * (lo + hi);
  };

  DeadZone zone;
  zone.input = input;
  bool in_zone = false;
  int previous = -1;
  double t_previous = 0;
  for (int k = 0; k <= scan.samples; ++k) {
    const double t = k == scan.samples ? length : length * k / scan.samples;
    const int value = locked(t);
    ++s.samples;
    if (value < 0) {
      ++s.unusable_samples;
      if (in_zone) {
        zone.end = begin + t_previous;
        zone.end_located = false;
        zones->push_back(zone);
        in_zone = false;
      }
      previous = -1;
      continue;
    }
    if (previous < 0) {
      if (value == 1) {  // the first usable sample is inside a zone
        zone.begin = begin + t;
        zone.begin_located = false;
        in_zone = true;
      }
    } else if (value != previous) {
      bool located = false;
      const double boundary = refine(t_previous, previous, t, &located);
      if (value == 1) {
        zone.begin = boundary;
        zone.begin_located = located;
        in_zone = true;
      } else {
        zone.end = boundary;
        zone.end_located = located;
        zones->push_back(zone);
        in_zone = false;
      }
    }
    previous = value;
    t_previous = t;
  }
  if (in_zone) {
    zone.end = begin + t_previous;
    zone.end_located = false;
    zones->push_back(zone);
  }
  if (s.unusable_samples > 0) {
    return finish(s.position_status != position::Status::kConverged ? Status::kSingular
                                                                     : Status::kDidNotConverge,
                  "some samples were unusable (position step or statics failed)");
  }
  if (refinement_failed) {
    return finish(Status::kDidNotConverge, "a refinement point was unusable");
  }
  return finish(Status::kConverged, "");
}

}  // namespace mechgen::statics
