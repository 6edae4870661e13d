// Equilibrium positions (statics/equilibrium.h, Paul §6.5.2) against closed forms written
// here:
//  - the pendulum with a torsional spring (handwritten_statics_pendulum.h): Q(q) =
//    -w cos q - k (q - q0), w = m g lc, whose zeros this test finds by bisection on that
//    scalar formula, with stability from V'' = k - w sin q; the runtime's stiffness also
//    against a central difference of the Q it reports at solved neighbouring positions;
//  - the slider-crank under a constant piston force (handwritten_statics_slider_crank.h,
//    friction off): V = F s, equilibria at the dead centres q = 0 (s maximal: unstable) and
//    q = pi (s minimal: stable), stiffness F s'' with s'' = -a cos q (1 + a cos q / b) there.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "handwritten_statics_pendulum.h"
#include "handwritten_statics_slider_crank.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/equilibrium.h"

namespace mechgen::statics {
namespace {

using Pendulum = mech::handwritten_statics_pendulum::Model;
using SliderCrank = mech::handwritten_statics_slider_crank::Model;

static_assert(StaticsFeatures<Pendulum>::kHasStatics);
static_assert(StaticsFeatures<Pendulum>::kHasPotential);
static_assert(!StaticsFeatures<Pendulum>::kHasFriction);
static_assert(StaticsFeatures<Pendulum>::kNumFriction == 0);
static_assert(StaticsFeatures<Pendulum>::kHasReactions);

TEST(StaticsEquilibrium, PendulumWithTorsionalSpring) {
  using VecQ = ModelTypes<Pendulum>::VecQ;
  const ModelTypes<Pendulum>::Params p;
  const double w = p.m * p.g * p.lc;
  auto Q = [&](double q) { return -w * std::cos(q) - p.k * (q - p.q0); };
  // The zeros of Q by sign changes on a fine grid and bisection (independent of the runtime).
  std::vector<double> roots;
  const double lo = -M_PI, hi = 2 * M_PI;
  for (int i = 0; i < 3000; ++i) {
    double a = lo + (hi - lo) * i / 3000, b = lo + (hi - lo) * (i + 1) / 3000;
    if ((Q(a) > 0) == (Q(b) > 0)) continue;
    for (int k = 0; k < 200; ++k) {
      const double m = 0.5 * (a + b);
      ((Q(m) > 0) == (Q(a) > 0) ? a : b) = m;
    }
    roots.push_back(0.5 * (a + b));
  }
  ASSERT_EQ(roots.size(), 3u);

  position::PositionSolver<Pendulum> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<Equilibrium<Pendulum>> found;
  ScanSummary summary;
  ScanOptions scan;
  scan.samples = 90;
  ASSERT_EQ(FindEquilibria(Options(), scan, &solver, VecQ::Constant(lo), VecQ::Constant(hi),
                           &found, &summary),
            Status::kConverged)
      << summary.reason;
  ASSERT_EQ(found.size(), roots.size());
  for (size_t i = 0; i < roots.size(); ++i) {
    const Equilibrium<Pendulum>& e = found[i];
    EXPECT_TRUE(e.located);
    EXPECT_NEAR(e.q(0), roots[i], 1e-9);
    EXPECT_NEAR(e.Q(0), 0.0, 1e-8);
    EXPECT_NEAR(e.phi(0), p.l * std::cos(roots[i]), 1e-9);  // the solver's configuration
    const double V2 = p.k - w * std::sin(roots[i]);
    EXPECT_NEAR(e.stiffness, V2, 1e-8);
    EXPECT_EQ(e.stable, V2 > 0);
    EXPECT_LT(e.iterations, 20);  // superlinear refinement

    // stiffness = -dQ/dq: a central difference of the runtime's own Q at solved positions.
    const double h = 1e-5;
    double Q_at[2];
    for (int side = 0; side < 2; ++side) {
      ASSERT_EQ(solver.MoveTo(VecQ::Constant(e.q(0) + (side ? h : -h)), nullptr),
                position::Status::kConverged);
      Solution<Pendulum> s;
      ASSERT_EQ(SolveAt<Pendulum>(Options(), p, solver.state(), VecQ::Zero(), &s),
                Status::kConverged);
      Q_at[side] = s.statics.Q(0);
    }
    EXPECT_NEAR(e.stiffness, -(Q_at[1] - Q_at[0]) / (2 * h), 1e-6);
  }
  EXPECT_TRUE(found[0].stable);
  EXPECT_FALSE(found[1].stable);
  EXPECT_TRUE(found[2].stable);
}

TEST(StaticsEquilibrium, SliderCrankDeadCentres) {
  using VecQ = ModelTypes<SliderCrank>::VecQ;
  ModelTypes<SliderCrank>::Params p;
  p.mu_O = 0;
  position::PositionSolver<SliderCrank> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<Equilibrium<SliderCrank>> found;
  ScanOptions scan;
  scan.samples = 100;  // no sample on 0 or pi
  ASSERT_EQ(FindEquilibria(Options(), scan, &solver, VecQ::Constant(-0.5), VecQ::Constant(5.5),
                           &found),
            Status::kConverged);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_NEAR(found[0].q(0), 0.0, 1e-10);
  EXPECT_NEAR(found[1].q(0), M_PI, 1e-10);
  for (const Equilibrium<SliderCrank>& e : found) {
    const double c = std::cos(e.q(0));
    EXPECT_NEAR(e.stiffness, p.F * (-p.a * c * (1 + p.a * c / p.b)), 1e-6);
  }
  EXPECT_FALSE(found[0].stable);  // top dead centre: V = F s maximal
  EXPECT_TRUE(found[1].stable);   // bottom dead centre
}

// A scan too coarse for its range is refused, never reported as converged (issue 24): one
// sample over a full turn sees Q with the same sign at both ends (the two dead centres in
// between, SliderCrankDeadCentres) and used to report no equilibrium, converged.
TEST(StaticsEquilibrium, RefusesTooCoarseScan) {
  using VecQ = ModelTypes<SliderCrank>::VecQ;
  ModelTypes<SliderCrank>::Params p;
  p.mu_O = 0;
  position::PositionSolver<SliderCrank> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<Equilibrium<SliderCrank>> found;
  ScanSummary summary;
  ScanOptions scan;
  for (int samples : {1, 2, ScanOptions::kMinSamples - 1}) {
    scan.samples = samples;
    EXPECT_FALSE(scan.IsValid(nullptr)) << samples;
    EXPECT_EQ(FindEquilibria(Options(), scan, &solver, VecQ::Constant(-0.5), VecQ::Constant(5.5),
                             &found, &summary),
              Status::kInvalidInput)
        << samples;
    EXPECT_TRUE(found.empty());
  }
  // Enough samples, but more than 10 deg apart along the angle: two turns in 40 samples.
  scan.samples = 40;
  EXPECT_TRUE(scan.IsValid(nullptr));
  EXPECT_FALSE(scan.ResolvesAngle(4 * M_PI));
  EXPECT_EQ(FindEquilibria(Options(), scan, &solver, VecQ::Constant(-0.5),
                           VecQ::Constant(-0.5 + 4 * M_PI), &found, &summary),
            Status::kInvalidInput);
  EXPECT_NE(std::string(summary.reason).find("too coarse"), std::string::npos) << summary.reason;
  // The minimum itself over one turn (10 deg a sample) finds both dead centres.
  scan.samples = ScanOptions::kMinSamples;
  EXPECT_TRUE(scan.ResolvesAngle(2 * M_PI));
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  ASSERT_EQ(FindEquilibria(Options(), scan, &solver, VecQ::Constant(-0.5),
                           VecQ::Constant(-0.5 + 2 * M_PI), &found, &summary),
            Status::kConverged)
      << summary.reason;
  ASSERT_EQ(found.size(), 2u);
  EXPECT_NEAR(found[0].q(0), 0.0, 1e-10);
  EXPECT_NEAR(found[1].q(0), M_PI, 1e-10);
}

TEST(StaticsEquilibrium, RejectsBadInput) {
  using VecQ = ModelTypes<Pendulum>::VecQ;
  position::PositionSolver<Pendulum> solver;
  std::vector<Equilibrium<Pendulum>> found;
  // Not assembled.
  EXPECT_EQ(FindEquilibria(Options(), ScanOptions(), &solver, VecQ::Constant(0.0),
                           VecQ::Constant(1.0), &found),
            Status::kInvalidInput);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  // An empty line.
  EXPECT_EQ(FindEquilibria(Options(), ScanOptions(), &solver, VecQ::Constant(1.0),
                           VecQ::Constant(1.0), &found),
            Status::kInvalidInput);
  ScanOptions bad;
  bad.samples = 0;
  EXPECT_FALSE(bad.IsValid(nullptr));
}

}  // namespace
}  // namespace mechgen::statics
