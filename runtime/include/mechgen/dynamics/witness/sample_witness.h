/**
 * \file dynamics/witness/sample_witness.h
 * Witnesses whose value is read from a sample (dynamics/simulator.h): at each accepted step
 * the simulator hands a witness the samples at the step's two ends; when it fires it gives the
 * bracket's two values (ga at the start, gb at the end) and its value at any sample of the
 * dense output, and LocateOnSamples finds the time with the one root finder (locate.h).
 *
 * A witness here is a small class with
 *     bool Fires(const Sample& prev, const Sample& cur, double* ga, double* gb)
 *     double Value(const Sample& s) const
 * (Fires may keep what Value needs, e.g. the sign of det Phi_phi at the step's start). The
 * dead point (dead_point.h), the speed's zero (speed_zero.h) and the user's event
 * (user_event.h) are such witnesses; a new one ("a coupler point leaves a box") is one more.
 */
#pragma once

#include "mechgen/dynamics/witness/locate.h"

namespace mechgen::dynamics::witness {

/**
 * The time in [ta, tb] where the witness' value changes sign (ga, gb of opposite signs, else
 * tb), on samples of the dense output: `dense(double t, Sample*)` (false: not evaluated; the
 * far end of the bracket so far is taken). Illinois regula falsi to `tolerance` (LocateRoot).
 */
template <class Sample, class Witness, class Dense>
double LocateOnSamples(double ta, double tb, double ga, double gb, double tolerance, const Witness& w,
                       Dense&& dense) {
  if (!(ga * gb < 0)) return tb;
  double t_root = tb;
  LocateRoot(
      ta, tb, ga, gb, tolerance, Crossing::kSignChange,
      [&](double t, double* g) {
        Sample s;
        if (!dense(t, &s)) return false;
        *g = w.Value(s);
        return true;
      },
      &t_root);
  return t_root;
}

}  // namespace mechgen::dynamics::witness
