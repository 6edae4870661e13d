/**
 * \file dynamics/witness/speed_zero.h
 * The speed-zero witness (a sample witness, sample_witness.h): the first input's speed qd(0)
 * through zero (a pendulum's turning point, a run-down that stops). It fires over a step
 * whose start has qd(0) != 0 and whose end has qd(0) on the other side (0 counts as not
 * positive); its value is qd(0).
 */
#pragma once

namespace mechgen::dynamics::witness {

struct SpeedZeroWitness {
  template <class Sample>
  bool Fires(const Sample& prev, const Sample& cur, double* ga, double* gb) const {
    if (!(prev.qd(0) != 0 && (prev.qd(0) > 0) != (cur.qd(0) > 0))) return false;
    *ga = prev.qd(0);
    *gb = cur.qd(0);
    return true;
  }
  template <class Sample>
  double Value(const Sample& s) const {
    return s.qd(0);
  }
};

}  // namespace mechgen::dynamics::witness
