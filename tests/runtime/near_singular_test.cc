// The runtime near singular configurations (issue 12), on test models the project does not
// ship (tests/runtime/models/), against closed forms written here.
//
//  - watt2_locked: a Watt II six-bar whose second loop closes on the assembled mode of the
//    first loop only. FindModes must find the modes of both closed-form blocks (the old
//    search flipped block 0, saw block 1 fail and gave up: modes() empty, Newton on the
//    whole system every step). Oracle: the two circle-circle intersections written here.
//  - changepoint_fourbar: a = 1, b = 3, c = 2, d = 2 (s + l = p + q), change point at
//    theta_crank = 0; and with a = c = 1, b = d = 2 (a parallelogram), change points at 0
//    and 180 deg. Oracle: phi, K and L of the four-bar's closed form evaluated in quad
//    precision (__float128, 113-bit significand: at cond 1e6 the reference is still good to
//    ~1e-28 in L), K and L from the velocity and acceleration loop equations derived by
//    hand below (not from the generated code).
//    (b) After PassSingularity(kSwitchBranch) and a MoveTo that stops singular at
//    cond ~ 1e5..1e6, a MoveTo away from the singularity succeeds at once, and a 15-degree
//    sweep away loses no row; every row on the curve it was on (no silent branch switch).
//    (c) The error bounds of State (phi_error, K_error, L_error) hold against the
//    reference at every configuration of an approach to the change point (cond up to 1e6)
//    and at the stops, and flag the rows whose L is not to be trusted.
#include <quadmath.h>

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "changepoint_fourbar.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "test_util.h"
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

// ---- The change-point four-bar in quad precision ---------------------------------------
using CP = mech::changepoint_fourbar::Model;
using Quad = __float128;

struct Reference {
  double phi[2], K[2], L[2];
};

// Closed form of mode m (the side of BD on which C lies) at the double q, in quad.
Reference FourBarReference(const CP::ParamsT<double>& p, double q_double, int m) {
  const Quad a = p.a, b = p.b, c = p.c, d = p.d, q = q_double;
  const Quad Bx = a * cosq(q), By = a * sinq(q);
  const Quad wx = d - Bx, wy = -By;
  const Quad d2 = wx * wx + wy * wy;
  const Quad k = (b * b - c * c + d2) / (2 * d2);
  Quad h2 = b * b / d2 - k * k;
  if (h2 < 0) h2 = 0;
  const Quad h = m * sqrtq(h2);
  const Quad Cx = Bx + k * wx - h * wy, Cy = By + k * wy + h * wx;
  const Quad t2 = atan2q(Cy - By, Cx - Bx), t3 = atan2q(Cy, Cx - d);
  const Quad s2 = sinq(t2), c2 = cosq(t2), s3 = sinq(t3), c3 = cosq(t3);
  // Loop a e^{iq} + b e^{i t2} - c e^{i t3} = d, differentiated by hand:
  //   J (K2, K3) = (a sin q, -a cos q),
  //   J (L2, L3) = (a cos q + b c2 K2^2 - c c3 K3^2, a sin q + b s2 K2^2 - c s3 K3^2),
  // J = [-b s2, c s3; b c2, -c c3].
  const Quad J00 = -b * s2, J01 = c * s3, J10 = b * c2, J11 = -c * c3;
  const Quad det = J00 * J11 - J01 * J10;
  auto solve = [&](Quad r0, Quad r1, Quad* x0, Quad* x1) {
    *x0 = (r0 * J11 - J01 * r1) / det;
    *x1 = (J00 * r1 - J10 * r0) / det;
  };
  Quad K2, K3, L2, L3;
  solve(a * sinq(q), -a * cosq(q), &K2, &K3);
  solve(a * cosq(q) + b * c2 * K2 * K2 - c * c3 * K3 * K3,
        a * sinq(q) + b * s2 * K2 * K2 - c * s3 * K3 * K3, &L2, &L3);
  return {{double(t2), double(t3)}, {double(K2), double(K3)}, {double(L2), double(L3)}};
}

// The reference on the curve a configuration lies on: the closed-form mode nearest to it.
// (M: CP, or testing::PositionsOnly<CP>.)
template <class M>
Reference Nearest(const CP::ParamsT<double>& p, const State<M>& s, int* mode = nullptr) {
  Reference best{};
  double best_distance = std::numeric_limits<double>::infinity();
  for (int m : {+1, -1}) {
    const Reference r = FourBarReference(p, s.q(0), m);
    const double e = std::max(AngleDistance(s.phi(0), r.phi[0]), AngleDistance(s.phi(1), r.phi[1]));
    if (e < best_distance) {
      best_distance = e;
      best = r;
      if (mode != nullptr) *mode = m;
    }
  }
  return best;
}

struct Errors {
  double phi, K, L;
};
template <class M>
Errors ActualErrors(const Reference& r, const State<M>& s) {
  Errors e{0, 0, 0};
  for (int i = 0; i < 2; ++i) {
    e.phi = std::max(e.phi, AngleDistance(s.phi(i), r.phi[i]));
    e.K = std::max(e.K, std::abs(s.K(i) - r.K[i]));
    e.L = std::max(e.L, std::abs(s.L(i) - r.L[i]));
  }
  return e;
}

CP::ParamsT<double> Parallelogram() {
  CP::ParamsT<double> p;
  p.a = 1;
  p.b = 2;
  p.c = 1;
  p.d = 2;
  return p;
}

// Assembled on the closed-form mode +1 at q0.
template <class M = CP>
PositionSolver<M> AssembledAt(const CP::ParamsT<double>& p, double q0) {
  PositionSolver<M> solver(Options(), p);
  const Reference r = FourBarReference(p, q0, +1);
  Summary summary;
  EXPECT_EQ(solver.Assemble(Q(q0), Eigen::Vector2d(r.phi[0], r.phi[1]), 0, &summary),
            Status::kConverged)
      << FormatSummary(summary);
  return solver;
}

// Checks the three bounds of s against the reference; returns the actual errors.
template <class M>
Errors ExpectBoundsHold(const CP::ParamsT<double>& p, const State<M>& s, const char* where) {
  const Errors e = ActualErrors(Nearest(p, s), s);
  EXPECT_TRUE(std::isfinite(s.phi_error) && std::isfinite(s.K_error) && std::isfinite(s.L_error))
      << where;
  EXPECT_LE(e.phi, s.phi_error) << where << " q = " << s.q(0) << " cond " << s.condition;
  EXPECT_LE(e.K, s.K_error) << where << " q = " << s.q(0) << " cond " << s.condition;
  EXPECT_LE(e.L, s.L_error) << where << " q = " << s.q(0) << " cond " << s.condition;
  return e;
}

struct ChangePointCase {
  const char* name;
  CP::ParamsT<double> params;
  double q_star;  // a change point
};
std::vector<ChangePointCase> ChangePointCases() {
  return {{"a1_b3_c2_d2", CP::ParamsT<double>(), 0.0}, {"parallelogram", Parallelogram(), kPi}};
}

TEST(AccuracyBounds, HoldAgainstQuadPrecisionApproachingAChangePoint) {
  for (const ChangePointCase& test : ChangePointCases()) {
    SCOPED_TRACE(test.name);
    PositionSolver<CP> solver = AssembledAt(test.params, test.q_star - kPi / 2);
    double largest_condition = 0, largest_L_error = 0;
    for (int k = 0; k <= 14; ++k) {
      const double distance = 0.5 * std::pow(10.0, -0.5 * k);  // 0.5 .. 5e-8 rad
      Summary summary;
      const Status status = solver.MoveTo(Q(test.q_star - distance), &summary);
      // Converged, or stopped singular at the last valid configuration before it.
      ASSERT_TRUE(status == Status::kConverged || status == Status::kSingular)
          << FormatSummary(summary);
      const State<CP>& s = solver.state();
      EXPECT_EQ(summary.phi_error, s.phi_error);
      EXPECT_EQ(summary.L_error, s.L_error);
      const Errors e = ExpectBoundsHold(test.params, s, "approach");
      largest_condition = std::max(largest_condition, s.condition);
      largest_L_error = std::max(largest_L_error, e.L);
      // Away from the change point the bounds are small (not uselessly loose).
      if (s.condition < 100) {
        EXPECT_LT(s.phi_error, 1e-12);
        EXPECT_LT(s.K_error, 1e-9);
        EXPECT_LT(s.L_error, 1e-6);
      }
      // The rows whose L is wrong in its first digits are flagged.
      if (e.L > 1e-3 * (1 + std::abs(s.L(0)))) {
        EXPECT_GT(s.L_error, 1e-3) << s.q(0);
      }
      if (status == Status::kSingular) break;
    }
    // The approach got close: cond beyond 1e5, where L is off by more than 1e-6.
    EXPECT_GT(largest_condition, 1e5);
    EXPECT_GT(largest_L_error, 1e-6);
  }
}

TEST(AccuracyBounds, HoldForTheKAndLOfAPositionsOnlyModel) {
  // The same approach with the coefficients cut down to Phi and Phi_phi: the solver forms K
  // and L itself (from Model::Coeffs in dual numbers seeded with Solve's sin and cos). Its
  // bounds hold against the quad-precision closed form too, and it stops where the model
  // with the generated K and L stops, with the same status.
  using P = testing::PositionsOnly<CP>;
  for (const ChangePointCase& test : ChangePointCases()) {
    SCOPED_TRACE(test.name);
    PositionSolver<CP> full = AssembledAt(test.params, test.q_star - kPi / 2);
    PositionSolver<P> formed = AssembledAt<P>(test.params, test.q_star - kPi / 2);
    P::trig_calls = 0;
    double largest_condition = 0;
    for (int k = 0; k <= 14; ++k) {
      const double distance = 0.5 * std::pow(10.0, -0.5 * k);
      Summary summary;
      const Status status = formed.MoveTo(Q(test.q_star - distance), &summary);
      ASSERT_EQ(status, full.MoveTo(Q(test.q_star - distance), nullptr)) << FormatSummary(summary);
      ASSERT_TRUE(status == Status::kConverged || status == Status::kSingular)
          << FormatSummary(summary);
      const State<P>& s = formed.state();
      EXPECT_EQ(s.q, full.state().q);
      ExpectBoundsHold(test.params, s, "positions only");
      largest_condition = std::max(largest_condition, s.condition);
      if (s.condition < 100) {
        EXPECT_LT(s.K_error, 1e-9);
        EXPECT_LT(s.L_error, 1e-6);
      }
      if (status == Status::kSingular) break;
    }
    EXPECT_GT(largest_condition, 1e5);
    EXPECT_GT(P::trig_calls, 0);  // the seeded evaluation ran
  }
}

TEST(AccuracyBounds, InTheSweepCsv) {
  std::vector<SweepRecord<CP>> records;
  PositionSolver<CP> solver = AssembledAt(CP::ParamsT<double>(), -1);
  Sweep(&solver, Q(-1), Q(1), 200, Q(1), Q(0), &records);
  ASSERT_EQ(records[100].summary.status, Status::kSingular);
  for (int i = 0; i <= 100; ++i) ExpectBoundsHold(solver.params(), records[i].state, "sweep");
  EXPECT_GT(records[100].state.L_error, 1e3 * records[0].state.L_error);
}

TEST(Sweep, NotRunRowsKeepTheInputsTheyAskedFor) {
  // -1 .. 1 in 200 steps stops at the change point (row 100); rows 101..200 are not run and
  // hold q = -1 + i / 100, not NaN; their values are NaN.
  std::vector<SweepRecord<CP>> records;
  PositionSolver<CP> solver = AssembledAt(CP::ParamsT<double>(), -1);
  EXPECT_EQ(Sweep(&solver, Q(-1), Q(1), 200, Q(1), Q(0), &records), 101);
  ASSERT_EQ(records[100].summary.status, Status::kSingular);
  for (int i = 101; i <= 200; ++i) {
    EXPECT_EQ(records[i].summary.status, Status::kNotRun);
    EXPECT_NEAR(records[i].q(0), -1 + i / 100.0, 1e-12) << i;
    EXPECT_TRUE(std::isnan(records[i].state.phi(0)));
  }
  EXPECT_EQ(records[200].q(0), 1.0);
  // The same rows streamed one at a time (SweepRows) as collected (Sweep).
  PositionSolver<CP> again = AssembledAt(CP::ParamsT<double>(), -1);
  int rows = 0;
  SweepRows(&again, Q(-1), Q(1), 200, Q(1), Q(0), SweepOptions(),
            [&](int i, const SweepRecord<CP>& r) {
              EXPECT_EQ(i, rows++);
              EXPECT_EQ(r.summary.status, records[i].summary.status);
              EXPECT_EQ(r.q(0), records[i].q(0));
              if (r.state.valid) {
                EXPECT_EQ(r.state.phi, records[i].state.phi);
              }
            });
  EXPECT_EQ(rows, 201);
}

TEST(LeavingASingularity, MoveAwayAfterAStopNextToAChangePointSucceeds) {
  for (const ChangePointCase& test : ChangePointCases()) {
    SCOPED_TRACE(test.name);
    const double deg = kPi / 180, q0 = test.q_star;
    PositionSolver<CP> solver = AssembledAt(test.params, q0 - kPi / 2);
    Summary summary;
    ASSERT_EQ(solver.MoveTo(Q(q0 + 15 * deg), &summary), Status::kSingular);
    ASSERT_EQ(solver.PassSingularity(Q(q0 + 15 * deg), Crossing::kSwitchBranch, &summary),
              Status::kConverged)
        << FormatSummary(summary);
    ASSERT_EQ(solver.MoveTo(Q(q0 + 15 * deg), &summary), Status::kConverged);
    int mode = 0;
    Nearest(test.params, solver.state(), &mode);
    // Back towards the change point on the switched curve: stops next to it.
    ASSERT_EQ(solver.MoveTo(Q(q0 - 15 * deg), &summary), Status::kSingular);
    const State<CP> stop = solver.state();
    EXPECT_GT(stop.condition, 1e5);
    ExpectBoundsHold(test.params, stop, "stop");
    // Away again, in one call: converged at once, on the curve it came from.
    for (double away : {15.0, 1.0}) {
      PositionSolver<CP> again = solver;
      ASSERT_EQ(again.MoveTo(Q(q0 + away * deg), &summary), Status::kConverged)
          << away << " deg: " << FormatSummary(summary);
      EXPECT_LE(summary.rejected_substeps, 1) << FormatSummary(summary);
      int mode_after = 0;
      const Errors e = ActualErrors(Nearest(test.params, again.state(), &mode_after), again.state());
      EXPECT_EQ(mode_after, mode);
      EXPECT_LT(e.phi, 1e-12);
      EXPECT_LT(e.K, 1e-10);
    }
    // A 15-degree sweep away from the stop loses no row and stays on that curve.
    std::vector<SweepRecord<CP>> records;
    const double q_stop = stop.q(0);
    EXPECT_EQ(Sweep(&solver, Q(q_stop), Q(q_stop + 165 * deg), 11, Q(1), Q(0), &records), 0);
    int rejected = 0;
    for (size_t i = 1; i < records.size(); ++i) {
      const SweepRecord<CP>& r = records[i];
      ASSERT_EQ(r.summary.status, Status::kConverged) << i << " " << FormatSummary(r.summary);
      rejected += r.summary.rejected_substeps;
      int m = 0;
      const Errors e = ActualErrors(Nearest(test.params, r.state, &m), r.state);
      EXPECT_EQ(m, mode) << i;
      EXPECT_LT(e.phi, 1e-12) << i;
      EXPECT_LT(e.K, 1e-10) << i;
      EXPECT_LT(e.L, 1e-8) << i;
    }
    EXPECT_LE(rejected, 11);
  }
}

}  // namespace
}  // namespace mechgen::position
