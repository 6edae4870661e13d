/**
 * \file dynamics/witness/locate.h
 * The one root finder of the simulator's witness functions (dynamics/simulator.h): a witness
 * whose value changes sign over an accepted step is located on the step's dense output by
 * Illinois regula falsi (LocateRoot); a witness that is a decision (the loads' modes, stuck
 * or not) by bisection (LocateChange). Both are templates on the evaluation, which reads the
 * dense output (or anything else: the tests give them closed-form functions).
 *
 * Nothing allocates, nothing throws.
 */
#pragma once

#include <algorithm>
#include <cmath>

namespace mechgen::dynamics::witness {

/// What the root finder looks for.
enum class Crossing {
  kSignChange,   ///< g(ta) and g(tb) have opposite signs; an exact zero of g is the root;
                 ///< tm lies beyond the root where g(tm) has g(tb)'s sign
  kFallsToZero,  ///< g(ta) > 0 >= g(tb); tm lies beyond where g(tm) <= 0
};

/**
 * Illinois regula falsi on [ta, tb] for the witness g (g(ta) = ga, g(tb) = gb, bracketing as
 * `crossing` says): at most max_iterations secants (a secant outside the bracket is replaced
 * by the midpoint), while the bracket is wider than tolerance; the end kept twice in a row has
 * its value halved. `g(double t, double* value)` returns false where it cannot be evaluated.
 * *t_root: the bracket's far end tb when done (or an exact zero, kSignChange). Returns false
 * when g failed (*t_root: the far end at that moment).
 */
template <class G>
bool LocateRoot(double ta, double tb, double ga, double gb, double tolerance, Crossing crossing, G&& g,
                double* t_root, int max_iterations = 100) {
  int side = 0;
  for (int it = 0; it < max_iterations && std::abs(tb - ta) > tolerance; ++it) {
    double tm = tb - gb * (tb - ta) / (gb - ga);
    if (!(tm > std::min(ta, tb) && tm < std::max(ta, tb))) tm = 0.5 * (ta + tb);
    double gm = 0;
    if (!g(tm, &gm)) {
      *t_root = tb;
      return false;
    }
    bool beyond = false;
    if (crossing == Crossing::kSignChange) {
      if (gm == 0) {
        *t_root = tm;
        return true;
      }
      beyond = (gm > 0) == (gb > 0);
    } else {
      beyond = gm <= 0;
    }
    if (beyond) {
      tb = tm;
      gb = gm;
      if (side == -1) ga *= 0.5;
      side = -1;
    } else {
      ta = tm;
      ga = gm;
      if (side == 1) gb *= 0.5;
      side = 1;
    }
  }
  *t_root = tb;
  return true;
}

/// What a decision says at a time of the bracket (LocateChange).
enum class Side { kBefore, kAfter, kFailed };

/**
 * Bisection of [*ta, *tb] (the decision `side(t)` kBefore at *ta, kAfter at *tb) down to
 * tolerance, at most max_iterations halvings, stopping where the midpoint is no longer
 * between the ends (rounding). `side(double t)` may record what it saw at an kAfter time (the
 * new modes): the last kAfter call is the one at the final *tb. Returns false when a decision
 * failed (*t_failed: where).
 */
template <class S>
bool LocateChange(double* ta, double* tb, double tolerance, S&& side, double* t_failed = nullptr,
                  int max_iterations = 200) {
  for (int it = 0; it < max_iterations && *tb - *ta > tolerance; ++it) {
    const double tm = 0.5 * (*ta + *tb);
    if (!(tm > *ta && tm < *tb)) break;
    const Side s = side(tm);
    if (s == Side::kFailed) {
      if (t_failed != nullptr) *t_failed = tm;
      return false;
    }
    (s == Side::kBefore ? *ta : *tb) = tm;
  }
  return true;
}

}  // namespace mechgen::dynamics::witness
