/**
 * \file dynamics/witness/stick_slip.h
 * The stick-slip witnesses of Coulomb friction (dynamics/friction.h, forward.h; the loop's
 * use in simulator.h): over an accepted step (t_start, t], where the friction's mode changes.
 *  - One input slipping along e: the stop, the first time with e qd <= 0, located by the one
 *    root finder (LocateRoot, kFallsToZero) on e qd of the dense output.
 *  - One input stuck: the breakaway, where the decision at rest says slip (the state does not
 *    move), by bisection on that decision (LocateChange); a stage of the step that saw the
 *    load above the bound (t_seen) has it looked for up to there even where the step's end is
 *    stuck again.
 *  - Several inputs: the first time a joint's margin (a slipping joint's dir K_rel qd, a stuck
 *    one's bound - |f|) is not positive, by bisection on the dense output; again up to a stage
 *    that saw it where the end does not.
 * Each is a function of callbacks (the speed, the decision, the margin at a time), so that a
 * test gives it closed forms; what to do at the transition is the loop's.
 */
#pragma once

#include "mechgen/dynamics/witness/locate.h"

namespace mechgen::dynamics::witness {

/// What a stick-slip witness found over a step.
enum class Found { kNone, kTransition, kFailed };

/**
 * The stop of a slip: g_start = e qd at t_start, g_end = e qd at t (<= 0). `speed(double t,
 * double* g)`: e qd on the dense output. *t_stop: the stop (t_start when the slip did not get
 * going, g_start <= 0: the chattering guard counts it). false when speed failed (*t_stop: the
 * far end so far).
 */
template <class Speed>
bool LocateSlipStop(double t_start, double t, double g_start, double g_end, double tolerance, Speed&& speed,
                    double* t_stop) {
  *t_stop = t_start;
  if (!(g_start > 0)) return true;
  return LocateRoot(t_start, t, g_start, g_end, tolerance, Crossing::kFallsToZero, speed, t_stop);
}

/**
 * The breakaway of a stuck input: `decide(double t, bool* stuck, double* e)` the decision at
 * rest at time t (false: it did not converge); t_seen the time of a stage that saw the load
 * above the bound (outside (t_start, t): none). kTransition: *t_break, and *e the direction of
 * the slip that starts there; kFailed: *t_failed where the decision failed.
 */
template <class Decide>
Found LocateBreakaway(double t_start, double t, double t_seen, double tolerance, Decide&& decide, double* t_break,
                      double* e, double* t_failed) {
  bool stuck_end = true;
  double e_end = 1;
  if (!decide(t, &stuck_end, &e_end)) {
    *t_failed = t;
    return Found::kFailed;
  }
  double t_high = t;
  if (stuck_end && t_seen > t_start && t_seen < t) {
    bool stuck_seen = true;
    double e_seen = 1;
    if (!decide(t_seen, &stuck_seen, &e_seen)) {
      *t_failed = t_seen;
      return Found::kFailed;
    }
    if (!stuck_seen) {
      stuck_end = false;
      e_end = e_seen;
      t_high = t_seen;
    }
  }
  if (stuck_end) return Found::kNone;
  double ta = t_start, tb = t_high;
  auto side = [&](double tm) {
    bool stuck_m = true;
    double e_m = 1;
    if (!decide(tm, &stuck_m, &e_m)) return Side::kFailed;
    if (stuck_m) return Side::kBefore;
    e_end = e_m;
    return Side::kAfter;
  };
  if (!LocateChange(&ta, &tb, tolerance, side, t_failed)) return Found::kFailed;
  *t_break = tb;
  *e = e_end;
  return Found::kTransition;
}

/**
 * Several inputs: the first time a joint's margin is not positive. g_end: the least margin at
 * the step's end t; `margin(double t, double* g)` the least margin on the dense output (false:
 * the friction loads did not converge); t_seen as in LocateBreakaway. kTransition: *t_change;
 * kFailed: *t_failed.
 */
template <class Margin>
Found LocateJointChange(double t_start, double t, double g_end, double t_seen, double tolerance, Margin&& margin,
                        double* t_change, double* t_failed) {
  double t_high = t;
  if (g_end > 0 && t_seen > t_start && t_seen < t) {
    // A stage saw a joint's margin fall to 0 that the step's end does not show (a brief
    // breakaway, or a relative velocity through zero and back): checked there.
    double gs = 0;
    if (!margin(t_seen, &gs)) {
      *t_failed = t_seen;
      return Found::kFailed;
    }
    if (gs <= 0) {
      g_end = gs;
      t_high = t_seen;
    }
  }
  if (!(g_end <= 0)) return Found::kNone;
  double ta = t_start, tb = t_high;
  auto side = [&](double tm) {
    double gm = 0;
    if (!margin(tm, &gm)) return Side::kFailed;
    return gm <= 0 ? Side::kAfter : Side::kBefore;
  };
  if (!LocateChange(&ta, &tb, tolerance, side, t_failed)) return Found::kFailed;
  *t_change = tb;
  return Found::kTransition;
}

}  // namespace mechgen::dynamics::witness
