// tests/generator/hostile/argument_names.yaml: parameters named like the generated functions'
// arguments (c, qd, qdd, out, trig, friction). Its library compiles with -Werror (an argument
// `c` that only a member p.c "mentions" used to be left without (void) and warned); here the
// generated dynamics against the hand values of a wheel with a mass at A (gravity off):
// I = J_G + m r^2 = qdd + trig out^2, Q = qd - (c + friction) w, and the statics' drive = -qd.
#include <gtest/gtest.h>

#include "argument_names.h"

namespace {

TEST(ArgumentNames, DynamicsOfTheWheelByHand) {
  using M = mech::argument_names::Model;
  mech::argument_names::Params<double> p;
  Eigen::Matrix<double, 1, 1> q, qd;
  q(0) = 0.7;
  qd(0) = 2.5;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  typename M::template DynamicsT<double> d;
  M::Dynamics(p, q, phi, qd, 0.0, c, &d);
  EXPECT_NEAR(d.I(0, 0), p.qdd + p.trig * p.out * p.out, 1e-15);
  EXPECT_NEAR(d.Q(0), p.qd - (p.c + p.friction) * qd(0), 1e-15);
  typename M::template StaticsT<double> s;
  M::Forces(p, q, phi, c, &s);
  EXPECT_NEAR(s.drive(0), -p.qd, 1e-15);  // at rest: the viscous terms are 0
}

}  // namespace
