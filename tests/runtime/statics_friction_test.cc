// The statics runtime at one configuration (statics/solve.h) and its dead-zone scan
// (statics/dead_zones.h) on the hand-written slider-crank with friction at the crank bearing
// (handwritten_statics_slider_crank.h), against closed forms written here:
//  - the slider position s(q) = a cos q + sqrt(b^2 - a^2 sin^2 q) (zero offset) and the
//    frictionless torque by virtual work T0 = F ds/dq (F pushes the slider along -x), with
//    ds/dq by a central difference of s(q);
//  - the rod force P = F / cos(beta) (the rod a two-force member), and the friction circle:
//    T = T0 + mu r |P| sign(qdot) at the crank bearing;
//  - self-locking where a |sin(q - beta)| <= mu r, its limits found here by bisection on the
//    scalar closed form sin(q - beta) = sin q (cos beta + (a / b) cos q);
//  - a dead point (a = b, the rod vertical at q = 90 deg): status singular, nothing printed.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "handwritten_statics_slider_crank.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/solve.h"

namespace mechgen::statics {
namespace {

using M = mech::handwritten_statics_slider_crank::Model;
using Params = ModelTypes<M>::Params;
using VecQ = ModelTypes<M>::VecQ;
using VecPhi = ModelTypes<M>::VecPhi;
using Coefficients = ModelTypes<M>::Coefficients;

static_assert(StaticsFeatures<M>::kHasStatics);
static_assert(StaticsFeatures<M>::kHasFriction);
static_assert(StaticsFeatures<M>::kHasReactions);
static_assert(!StaticsFeatures<M>::kHasPotential);
static_assert(StaticsFeatures<M>::kHasStiffness && StaticsFeatures<M>::kStiffnessApart);

// The closed-form configuration (zero offset, rod to the right of the crank pin).
double Beta(const Params& p, double q) { return std::asin(-p.a * std::sin(q) / p.b); }
double SliderX(const Params& p, double q) {
  const double sq = p.a * std::sin(q);
  return p.a * std::cos(q) + std::sqrt(p.b * p.b - sq * sq);
}
VecPhi Configuration(const Params& p, double q) { return VecPhi(Beta(p, q), SliderX(p, q)); }
// T0 = F ds/dq by virtual work (the load (-F, 0) at C: Q = -F ds/dq, drive = -Q), with
// ds/dq = -a sin q - a^2 sin q cos q / sqrt(b^2 - a^2 sin^2 q).
double T0ByVirtualWork(const Params& p, double q) {
  const double sq = p.a * std::sin(q);
  return p.F * (-sq - sq * p.a * std::cos(q) / std::sqrt(p.b * p.b - sq * sq));
}
// The same by a central difference of s(q) (checks the closed form above).
double T0ByDifference(const Params& p, double q) {
  const double h = 1e-5;
  return p.F * (SliderX(p, q + h) - SliderX(p, q - h)) / (2 * h);
}
double RodForce(const Params& p, double q) { return p.F / std::cos(Beta(p, q)); }
// a sin(q - beta) = a sin q (cos beta + (a / b) cos q): the lever of the rod force about O.
double Lever(const Params& p, double q) {
  return p.a * std::sin(q) * (std::cos(Beta(p, q)) + p.a / p.b * std::cos(q));
}

Coefficients CoeffsAt(const Params& p, double q) {
  Coefficients c;
  M::Coeffs<double>(p, VecQ::Constant(q), Configuration(p, q), &c);
  return c;
}

TEST(StaticsFriction, FrictionlessDriveIsVirtualWork) {
  const Params p;
  for (int k = 0; k < 72; ++k) {
    const double q = 2 * M_PI * (k + 0.3) / 72;
    Solution<M> s;
    ASSERT_EQ(Solve<M>(Options(), p, VecQ::Constant(q), Configuration(p, q), CoeffsAt(p, q),
                       VecQ::Zero(), &s),
              Status::kConverged)
        << FormatSummary(s.summary);
    EXPECT_EQ(s.summary.iterations, 1);
    EXPECT_NEAR(T0ByVirtualWork(p, q), T0ByDifference(p, q), 1e-5);
    EXPECT_NEAR(s.statics.drive(0), T0ByVirtualWork(p, q), 1e-9 * p.F) << "q = " << q;
    EXPECT_NEAR(s.statics.Q(0), -T0ByVirtualWork(p, q), 1e-6);
    EXPECT_EQ(s.friction(0), 0.0);
    // max |R_i|: the rod force's components P (cos beta, sin beta), |beta| < 45 deg.
    EXPECT_NEAR(s.summary.reaction_norm, p.F, 1e-9 * p.F);
  }
}

TEST(StaticsFriction, IterationMatchesTheFrictionCircle) {
  const Params p;
  const double mu_r = p.mu_O * p.r_O;
  for (int k = 0; k < 72; ++k) {
    const double q = 2 * M_PI * (k + 0.3) / 72;
    const double T0 = T0ByVirtualWork(p, q);
    const double P = RodForce(p, q);
    for (double d : {+1.0, -1.0}) {
      Solution<M> s;
      ASSERT_EQ(Solve<M>(Options(), p, VecQ::Constant(q), Configuration(p, q), CoeffsAt(p, q),
                         VecQ::Constant(d), &s),
                Status::kConverged)
          << FormatSummary(s.summary);
      // The friction torque on the crank opposes its rotation: -mu r |P| sign(qdot).
      EXPECT_NEAR(s.friction(0), -mu_r * std::abs(P) * d, 1e-9 * p.F);
      EXPECT_NEAR(s.statics.drive(0), T0 + d * mu_r * std::abs(P), 1e-6) << "q = " << q;
      // The rod force does not depend on the crank's friction torque: converged after the
      // frictionless evaluation, one with f, and one confirming it.
      EXPECT_EQ(s.summary.iterations, 3);
      EXPECT_EQ(s.summary.last_change, 0.0);
      EXPECT_EQ(s.summary.status, Status::kConverged);
    }
  }
}

TEST(StaticsFriction, ForwardBackwardAndEfficiency) {
  const Params p;
  const double mu_r = p.mu_O * p.r_O;
  int locked = 0;
  for (int k = 0; k < 360; ++k) {
    const double q = 2 * M_PI * (k + 0.5) / 360;
    DriveAnalysis d;
    ASSERT_EQ(AnalyzeDrive<M>(Options(), p, VecQ::Constant(q), Configuration(p, q),
                              CoeffsAt(p, q), 0, &d),
              Status::kConverged);
    const double T0 = T0ByVirtualWork(p, q);
    const double friction = mu_r * std::abs(RodForce(p, q));
    const double sign = T0 < 0 ? -1 : 1;
    EXPECT_NEAR(d.drive, T0, 1e-6);
    EXPECT_NEAR(d.drive_forward, T0 + sign * friction, 1e-6);   // moving along sign(T0)
    EXPECT_NEAR(d.drive_backward, T0 - sign * friction, 1e-6);  // the load drives it back
    EXPECT_NEAR(d.drive_plus, T0 + friction, 1e-6);   // running in +q, whatever sign T0
    EXPECT_NEAR(d.drive_minus, T0 - friction, 1e-6);  // running in -q
    EXPECT_NEAR(d.efficiency_forward, T0 / (T0 + sign * friction), 1e-9);
    EXPECT_NEAR(d.efficiency_backward, (T0 - sign * friction) / T0, 1e-6);
    EXPECT_GT(d.efficiency_forward, 0.0);
    EXPECT_LE(d.efficiency_forward, 1.0);
    // Hand-derived: self-locking where the rod's line passes inside the friction circle.
    const bool hand_locked = std::abs(Lever(p, q)) <= mu_r;
    EXPECT_EQ(d.self_locking, hand_locked) << "q = " << q << " lever " << Lever(p, q);
    locked += d.self_locking;
  }
  EXPECT_GT(locked, 0);
  EXPECT_LT(locked, 360);
}

// Model::Stiffness runs only when asked for (Options::stiffness); stiffness = F s''.
TEST(StaticsFriction, StiffnessOnRequest) {
  const Params p;
  const double q = 1.0, h = 1e-5;
  Solution<M> s;
  ASSERT_EQ(Solve<M>(Options(), p, VecQ::Constant(q), Configuration(p, q), CoeffsAt(p, q),
                     VecQ::Zero(), &s),
            Status::kConverged);
  EXPECT_TRUE(std::isnan(s.statics.stiffness(0, 0)));
  Options options;
  options.stiffness = true;
  ASSERT_EQ(Solve<M>(options, p, VecQ::Constant(q), Configuration(p, q), CoeffsAt(p, q),
                     VecQ::Constant(1.0), &s),
            Status::kConverged);
  // -dQ/dq = dT0/dq, T0 = F ds/dq in closed form, by a central difference.
  EXPECT_NEAR(s.statics.stiffness(0, 0),
              (T0ByVirtualWork(p, q + h) - T0ByVirtualWork(p, q - h)) / (2 * h), 1e-5);
}

TEST(StaticsFriction, NoMotionMeansNoFriction) {
  const Params p;
  const double q = 1.0;
  Solution<M> s;
  ASSERT_EQ(Solve<M>(Options(), p, VecQ::Constant(q), Configuration(p, q), CoeffsAt(p, q),
                     VecQ::Zero(), &s),
            Status::kConverged);
  EXPECT_EQ(s.summary.iterations, 1);
  EXPECT_EQ(s.friction(0), 0.0);
}

TEST(StaticsFriction, IterationLimitIsReported) {
  const Params p;
  const double q = 1.0;
  Options options;
  options.max_friction_iterations = 2;  // the frictionless evaluation and one with friction
  Solution<M> s;
  EXPECT_EQ(Solve<M>(options, p, VecQ::Constant(q), Configuration(p, q), CoeffsAt(p, q),
                     VecQ::Constant(1.0), &s),
            Status::kDidNotConverge);
  EXPECT_GT(s.summary.last_change, 0.0);
  EXPECT_NEAR(s.summary.last_change, p.mu_O * p.r_O * std::abs(RodForce(p, q)), 1e-9 * p.F);
}

TEST(StaticsFriction, InvalidInputs) {
  const Params p;
  Solution<M> s;
  VecPhi phi = Configuration(p, 1.0);
  phi(0) = std::nan("");
  EXPECT_EQ(Solve<M>(Options(), p, VecQ::Constant(1.0), phi, CoeffsAt(p, 1.0), VecQ::Zero(), &s),
            Status::kInvalidInput);
  EXPECT_TRUE(std::isnan(s.statics.drive(0)));
  Options bad;
  bad.max_condition = 0.5;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("max_condition"), std::string::npos) << error;
  EXPECT_EQ(Solve<M>(bad, p, VecQ::Constant(1.0), Configuration(p, 1.0), CoeffsAt(p, 1.0),
                     VecQ::Zero(), &s),
            Status::kInvalidInput);
  DriveAnalysis d;
  EXPECT_EQ(AnalyzeDrive<M>(Options(), p, VecQ::Constant(1.0), Configuration(p, 1.0),
                            CoeffsAt(p, 1.0), 1, &d),
            Status::kInvalidInput);
}

// a = b: the rod stands vertical at q = 90 deg (beta = -q on this branch), where Phi_phi is
// singular and the rod force F / cos(beta) grows without bound.
TEST(StaticsSingular, DeadPointWithholdsTheForces) {
  Params p;
  p.a = p.b = 1.0;
  for (double delta : {1e-2, 1e-4, 1e-7, 1e-10}) {
    const double q = M_PI / 2 - delta;
    const VecPhi phi(-q, 2 * p.a * std::cos(q));
    Coefficients c;
    M::Coeffs<double>(p, VecQ::Constant(q), phi, &c);
    for (double d : {0.0, 1.0}) {
      Solution<M> s;
      const Status status = Solve<M>(Options(), p, VecQ::Constant(q), phi, c, VecQ::Constant(d), &s);
      // Phi_phi ~ [[1, -1], [delta, 0]]: cond_1 = 2 (1 + delta) / delta.
      EXPECT_GT(s.summary.condition, 1 / delta);
      // max |R_i| = |F_O_y| = P |sin beta| = F cot(delta).
      EXPECT_NEAR(s.summary.reaction_norm, p.F / std::tan(delta), 1e-5 * p.F / delta);
      if (s.summary.condition <= Options().max_condition) {
        EXPECT_EQ(status, Status::kConverged) << delta;
        EXPECT_NEAR(s.statics.R(0), p.F, 1e-6 * p.F);  // P cos(beta) = F
        EXPECT_TRUE(s.statics.drive.allFinite());
      } else {
        EXPECT_EQ(status, Status::kSingular) << delta;
        EXPECT_TRUE(std::isnan(s.statics.drive(0)));
        EXPECT_TRUE(std::isnan(s.statics.R(0)));
        EXPECT_NE(std::string(s.summary.reason), "");
      }
    }
  }
  // The threshold: 1e-7 rad from the dead point is singular by default, converged at 1e9.
  const double q = M_PI / 2 - 1e-7;
  const VecPhi phi(-q, 2 * p.a * std::cos(q));
  Coefficients c;
  M::Coeffs<double>(p, VecQ::Constant(q), phi, &c);
  Solution<M> s;
  EXPECT_EQ(Solve<M>(Options(), p, VecQ::Constant(q), phi, c, VecQ::Zero(), &s), Status::kSingular);
  Options loose;
  loose.max_condition = 1e9;
  EXPECT_EQ(Solve<M>(loose, p, VecQ::Constant(q), phi, c, VecQ::Zero(), &s), Status::kConverged);
  DriveAnalysis d;
  EXPECT_EQ(AnalyzeDrive<M>(Options(), p, VecQ::Constant(q), phi, c, 0, &d), Status::kSingular);
  EXPECT_TRUE(std::isnan(d.drive));
}

// The dead zones of a full crank turn against the hand-derived limits |Lever(q)| = mu r.
TEST(StaticsDeadZones, MatchHandDerivedAngles) {
  const Params p;
  const double mu_r = p.mu_O * p.r_O;
  // Limits by bisection on the closed form: q1 in (0, pi/2) with Lever = mu r, and
  // q2 in (pi/2, pi) with Lever = mu r (the zone about pi is [q2, 2 pi - q2]).
  auto solve = [&](double lo, double hi) {
    const double f_lo = Lever(p, lo) - mu_r;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((Lever(p, mid) - mu_r > 0) == (f_lo > 0) ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  const double q1 = solve(1e-9, M_PI / 2);
  const double q2 = solve(M_PI / 2, M_PI - 1e-9);
  // Small-angle estimates, a sanity check of the closed form itself.
  EXPECT_NEAR(q1, mu_r / (p.a * (1 + p.a / p.b)), 1e-3);
  EXPECT_NEAR(M_PI - q2, mu_r / (p.a * (1 - p.a / p.b)), 1e-3);

  position::PositionSolver<M> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<DeadZone> zones;
  ScanSummary summary;
  ASSERT_EQ(FindDeadZones(Options(), ScanOptions(), &solver, 0, 0.0, 2 * M_PI, &zones, &summary),
            Status::kConverged)
      << summary.reason;
  ASSERT_EQ(zones.size(), 3u);
  // [0, q1] (cut by the range start), [q2, 2 pi - q2], [2 pi - q1, 2 pi] (cut by its end).
  EXPECT_EQ(zones[0].begin, 0.0);
  EXPECT_FALSE(zones[0].begin_located);
  EXPECT_TRUE(zones[0].end_located);
  EXPECT_NEAR(zones[0].end, q1, 1e-9);
  EXPECT_TRUE(zones[1].begin_located && zones[1].end_located);
  EXPECT_NEAR(zones[1].begin, q2, 1e-9);
  EXPECT_NEAR(zones[1].end, 2 * M_PI - q2, 1e-9);
  EXPECT_NEAR(zones[2].begin, 2 * M_PI - q1, 1e-9);
  EXPECT_NEAR(zones[2].end, 2 * M_PI, 1e-12);
  EXPECT_FALSE(zones[2].end_located);
  EXPECT_EQ(summary.samples, ScanOptions().samples + 1);
  EXPECT_EQ(summary.unusable_samples, 0);
  EXPECT_GT(summary.evaluations, 3 * summary.samples);

  // Without friction nothing locks except exactly where T0 = 0 (none of the samples).
  Params frictionless = p;
  frictionless.mu_O = 0;
  solver.set_params(frictionless);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  ScanOptions scan;
  scan.samples = 357;  // no sample on the dead centre q = pi, where T0 = 0 exactly
  ASSERT_EQ(FindDeadZones(Options(), scan, &solver, 0, 0.1, 2 * M_PI - 0.1, &zones, &summary),
            Status::kConverged);
  EXPECT_TRUE(zones.empty());

  // A scan too coarse for its range is refused (issue 24): 2 samples of the full turn land on
  // 0, pi and 2 pi, all inside the zones above, and used to report the whole turn as one dead
  // zone, converged; 40 samples over two turns are more than 10 deg apart.
  solver.set_params(p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  for (int samples : {2, ScanOptions::kMinSamples - 1}) {
    scan.samples = samples;
    EXPECT_EQ(FindDeadZones(Options(), scan, &solver, 0, 0.0, 2 * M_PI, &zones, &summary),
              Status::kInvalidInput)
        << samples;
    EXPECT_TRUE(zones.empty());
  }
  scan.samples = 40;
  EXPECT_EQ(FindDeadZones(Options(), scan, &solver, 0, 0.0, 4 * M_PI, &zones, &summary),
            Status::kInvalidInput);
  // At the minimum (10 deg a sample) the three zones of the turn, located as above.
  scan.samples = ScanOptions::kMinSamples;
  ASSERT_EQ(FindDeadZones(Options(), scan, &solver, 0, 0.0, 2 * M_PI, &zones, &summary),
            Status::kConverged)
      << summary.reason;
  ASSERT_EQ(zones.size(), 3u);
  EXPECT_NEAR(zones[0].end, q1, 1e-9);
  EXPECT_NEAR(zones[1].begin, q2, 1e-9);
  EXPECT_NEAR(zones[1].end, 2 * M_PI - q2, 1e-9);
  EXPECT_NEAR(zones[2].begin, 2 * M_PI - q1, 1e-9);
}

}  // namespace
}  // namespace mechgen::statics
