// The runtime near singular configurations (issue 12), on test models the project does not
// ship (tests/runtime/models/), against closed forms written here.
//
//  - watt2_locked: a Watt II six-bar whose second loop closes on the assembled mode of the
//    first loop only. FindModes must find the modes of both closed-form blocks (the old
//    search flipped block 0, saw block 1 fail and gave up: modes() empty, Newton on the
//    whole system every step). Oracle: the two circle-circle intersections written here.
//  - changepoint_fourbar: a = 1, b = 3, c = 2, d = 2 (s + l = p + q), change point at
//    theta_crank = 0.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "changepoint_fourbar.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "watt2_locked.h"

namespace mechgen::position {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Vec1 = Eigen::Matrix<double, 1, 1>;
Vec1 Q(double q) { return Vec1::Constant(q); }
double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

// The intersection of the circles (P, r1) and (Q, r2) on side `mode` of PQ (+1: left).
Eigen::Vector2d Intersect(const Eigen::Vector2d& P, double r1, const Eigen::Vector2d& Q,
                          double r2, int mode) {
  const Eigen::Vector2d w = Q - P;
  const double d2 = w.squaredNorm();
  const double k = (r1 * r1 - r2 * r2 + d2) / (2 * d2);
  const double h = mode * std::sqrt(r1 * r1 / d2 - k * k);
  return P + k * w + h * Eigen::Vector2d(-w.y(), w.x());
}
double Angle(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

using Watt = mech::watt2_locked::Model;

// theta_coupler, theta_rocker, theta_link5, theta_output of watt2_locked at crank angle t
// with loop 1 on mode m1 and loop 2 on mode m2; false when loop 2 does not close.
bool WattClosedForm(const Watt::ParamsT<double>& p, double t, int m1, int m2,
                    Eigen::Vector4d* phi) {
  const Eigen::Vector2d B(p.a * std::cos(t), p.a * std::sin(t)), O4(p.g, 0), O6(p.x6, p.y6);
  const Eigen::Vector2d C = Intersect(B, p.b, O4, p.c, m1);
  const double th3 = Angle(C - O4);
  const Eigen::Vector2d E =
      O4 + p.e * Eigen::Vector2d(std::cos(th3 + p.beta), std::sin(th3 + p.beta));
  const double dist = (E - O6).norm();
  if (dist > p.f + p.o || dist < std::abs(p.f - p.o)) return false;
  const Eigen::Vector2d F = Intersect(E, p.f, O6, p.o, m2);
  *phi << Angle(C - B), th3, Angle(F - E), Angle(F - O6);
  return true;
}

TEST(FindModes, LaterBlockUnassemblableOnTheOtherModeKeepsTheClosedForms) {
  CeresPositionSolver<Watt> solver;
  Summary summary;
  ASSERT_EQ(solver.AssembleDefault(&summary), Status::kConverged) << FormatSummary(summary);
  const Watt::ParamsT<double> p = solver.params();
  // The premise: at the assembly, loop 2 does not close on loop 1's other mode.
  Eigen::Vector4d assembled, other;
  const double t0 = solver.state().q(0);
  int m1 = 0, m2 = 0;
  for (int a : {+1, -1})
    for (int b : {+1, -1})
      if (WattClosedForm(p, t0, a, b, &other)) {
        double e = 0;
        for (int i = 0; i < 4; ++i) e = std::max(e, AngleDistance(other(i), solver.state().phi(i)));
        if (e < 1e-9) m1 = a, m2 = b;
      }
  ASSERT_NE(m1, 0) << "the assembly is none of the closed forms' configurations";
  ASSERT_FALSE(WattClosedForm(p, t0, -m1, +1, &other));
  ASSERT_FALSE(WattClosedForm(p, t0, -m1, -1, &other));

  PositionSolver<Watt>::Modes modes;
  ASSERT_TRUE(solver.modes(&modes)) << "modes() empty: Newton on the whole system every step";
  // Block 0 is loop 1, block 1 loop 2 (the generated solve order): Solve on these modes
  // reproduces the assembly.
  Eigen::Matrix<double, 4, 1> phi = solver.state().phi;
  const auto report = Watt::Solve<double>(p, solver.state().q, &phi, modes, 20, 1e-12);
  EXPECT_EQ(int(report.status), 0);
  EXPECT_LT((phi - solver.state().phi).cwiseAbs().maxCoeff(), 1e-12);

  // A full crank turn in 1-degree steps from the assembly: every step by the closed forms
  // (no Newton iteration), on the modes of the assembly, equal to the closed form here.
  std::vector<SweepRecord<Watt>> records;
  EXPECT_EQ(Sweep(&solver, Q(t0), Q(t0 + 2 * kPi), 360, Q(1), Q(0), &records), 0);
  int newton_iterations = 0;
  for (const SweepRecord<Watt>& r : records) {
    ASSERT_EQ(r.summary.status, Status::kConverged) << FormatSummary(r.summary);
    newton_iterations += r.summary.iterations;
    Eigen::Vector4d expected;
    ASSERT_TRUE(WattClosedForm(p, r.q(0), m1, m2, &expected));
    for (int i = 0; i < 4; ++i) EXPECT_LT(AngleDistance(r.state.phi(i), expected(i)), 1e-12) << i;
  }
  EXPECT_EQ(newton_iterations, 0);
  ASSERT_TRUE(solver.modes(&modes));
}

}  // namespace
}  // namespace mechgen::position
