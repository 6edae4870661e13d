/**
 * \file dynamics/witness/dead_point.h
 * The dead-point witness (a sample witness, sample_witness.h): a singular configuration of
 * Phi_phi, where the loop's positions stop being functions of the inputs.
 *
 * Over a step from prev to cur it fires when 1/cond_1(Phi_phi) falls below min_rcond or
 * det Phi_phi changes sign (the branch through a singular configuration between two samples);
 * its value is 1/cond - min_rcond, taken negative on the other side of a sign change of
 * det, so that it changes sign at the singular configuration in either case.
 *
 * The approach: where the steps collapse before 1/cond reaches min_rcond (forces grow like
 * 1/sigma_min(Phi_phi), the step size shrinks geometrically, and 1/cond may never reach
 * min_rcond inside the tiny window where the loop still closes), approach_steps accepted steps
 * in a row with 1/cond below approach_rcond and falling fire it at the step's end, with no
 * root to locate (approach_steps = 0: not watched).
 */
#pragma once

#include "mechgen/core/constants.h"

namespace mechgen::dynamics {

/// The approach to a singular configuration (DeadPointWitness): the one definition of these
/// defaults, read by PrescribedOptions, MinimalOptions' event settings and SensitivityOptions.
inline constexpr double kApproachRcond = 1e-3;
inline constexpr int kApproachSteps = 200;

namespace witness {

class DeadPointWitness {
 public:
  enum class Found { kNone, kCrossed, kApproached };

  DeadPointWitness(double min_rcond = kMinRcond, double approach_rcond = kApproachRcond, int approach_steps = 0)
      : min_rcond_(min_rcond), approach_rcond_(approach_rcond), approach_steps_(approach_steps) {}

  /// The step prev -> cur: kCrossed (then *ga, *gb the bracket of Value), kApproached (the
  /// approach_steps-th falling step below approach_rcond in a row), or kNone.
  /// Whether a step from a configuration of det Phi_phi prev_det to one of (rcond, det)
  /// crosses a singular one: the rule of Check(), for a system that must know at its accepted
  /// step whether the witness will end the run there (the trajectory sensitivities').
  static bool Crosses(double min_rcond, double prev_det, double rcond, double det) {
    return rcond < min_rcond || (prev_det > 0) != (det > 0);
  }

  template <class Sample>
  Found Check(const Sample& prev, const Sample& cur, double* ga, double* gb) {
    const bool sign_change = (prev.det > 0) != (cur.det > 0);
    if (Crosses(min_rcond_, prev.det, cur.rcond, cur.det)) {
      prev_det_positive_ = prev.det > 0;
      *ga = prev.rcond - min_rcond_;
      *gb = (sign_change ? -cur.rcond : cur.rcond) - min_rcond_;
      return Found::kCrossed;
    }
    if (approach_steps_ > 0) {
      if (cur.rcond < approach_rcond_ && cur.rcond < prev.rcond) {
        if (++count_ >= approach_steps_) return Found::kApproached;
      } else {
        count_ = 0;
      }
    }
    return Found::kNone;
  }

  /// Its value at a sample of the step last checked (the side of det of the step's start).
  template <class Sample>
  double Value(const Sample& s) const {
    return ((s.det > 0) == prev_det_positive_ ? s.rcond : -s.rcond) - min_rcond_;
  }

 private:
  double min_rcond_, approach_rcond_;
  int approach_steps_;
  int count_ = 0;  ///< accepted steps in a row below approach_rcond and falling
  bool prev_det_positive_ = true;
};

}  // namespace witness
}  // namespace mechgen::dynamics
