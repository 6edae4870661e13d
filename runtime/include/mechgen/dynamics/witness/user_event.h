/**
 * \file dynamics/witness/user_event.h
 * The user's witness (a sample witness, sample_witness.h): a stop condition
 * g(t, q, qd, phi) of the caller (NoUserEvent: none), firing over a step where it changes
 * sign from a nonzero value (0 counts as not positive). It keeps g at the last accepted state;
 * Reset() sets it anew where the motion restarts.
 */
#pragma once

namespace mechgen::dynamics {

/// No user stop condition.
struct NoUserEvent {
  template <class VecQ, class VecPhi>
  double operator()(double, const VecQ&, const VecQ&, const VecPhi&) const {
    return 1.0;
  }
};

namespace witness {

template <class UserEvent>
class UserWitness {
 public:
  explicit UserWitness(UserEvent& g) : g_(g) {}
  template <class Sample>
  void Reset(const Sample& s) {
    g_prev_ = Value(s);
  }
  /// The step to cur (at time cur.t): fires on a sign change since the last state; keeps
  /// g(cur) as the last state's.
  template <class Sample>
  bool Fires(const Sample& /*prev*/, const Sample& cur, double* ga, double* gb) {
    const double g = Value(cur);
    const bool fires = g_prev_ != 0 && (g_prev_ > 0) != (g > 0);
    *ga = g_prev_;
    *gb = g;
    g_prev_ = g;
    return fires;
  }
  template <class Sample>
  double Value(const Sample& s) const {
    return g_(s.t, s.q, s.qd, s.phi);
  }

 private:
  UserEvent& g_;
  double g_prev_ = 0;
};

}  // namespace witness
}  // namespace mechgen::dynamics
