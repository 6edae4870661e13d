// A parallelogram four-bar through a full turn (issue 26): crank AB = rocker DC = a = 1,
// coupler BC = ground AD = d = 3 (tests/kinematics/models/parallelogram.yaml), assembled
// as a parallelogram at theta_crank = 90 deg. Oracles by hand:
//  - on the parallelogram branch the rocker turns with the crank (theta_rocker =
//    theta_crank) and the coupler stays parallel to the ground (theta_coupler = 0): K =
//    (0, 1), L = 0;
//  - the change points, where all four links are collinear and the antiparallelogram branch
//    crosses this one, are theta_crank = 0 and 180 deg (and 360); there the dyad's relative
//    discriminant, sin^2 of the angle between coupler and rocker, is sin^2(theta_crank) on
//    the parallelogram: 0 exactly at the change points;
//  - the generated SolvePositions with fixed modes keeps mode +1 (C on one side of BD), which
//    past 180 deg is the antiparallelogram (the generator's note says so), and mode -1 there
//    is the parallelogram again.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "parallelogram.h"

namespace {

using M = mech::parallelogram::Model;
using mech::parallelogram::SolveStatus;
using Vec1 = Eigen::Matrix<double, 1, 1>;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

// |Phi|_inf at (q, phi), from the generated residual.
double Residual(const M::ParamsT<double>& p, double q, const Eigen::Vector2d& phi) {
  Eigen::Vector2d Phi;
  mech::parallelogram::EvalPhi(p, Vec1(q), phi, &Phi);
  return Phi.cwiseAbs().maxCoeff();
}

TEST(Parallelogram, TheHeaderNamesItsChangePoints) {
  // At 0, 180 and 360 deg of input 0, all in block 0 (the only one); none for shipped models.
  static_assert(M::kNumChangePoints == 3, "0, 180 and 360 deg");
  const double expected[] = {0, kPi, 2 * kPi};
  for (int i = 0; i < M::kNumChangePoints; ++i) {
    EXPECT_EQ(M::kChangePointInput[i], 0) << i;
    EXPECT_EQ(M::kChangePointBlock[i], 0) << i;
    EXPECT_NEAR(M::kChangePointQ[i], expected[i], 1e-12) << i;
  }
}

TEST(Parallelogram, FixedModesReportTheChangePointsAndNameTheOtherBranchPastThem) {
  const M::ParamsT<double> p;
  Eigen::Vector2d phi(M::kAssemblyPhi[0], M::kAssemblyPhi[1]);
  std::array<int, M::kNumBlocks> other = M::kDefaultModes;
  other[0] = -other[0];
  for (int k = 90; k <= 450; ++k) {  // from the assembly round to 90 deg again
    const double q = k * kDeg;
    const auto report = M::Solve(p, Vec1(q), &phi, M::kDefaultModes);
    ASSERT_EQ(report.status, SolveStatus::kConverged) << k;
    EXPECT_LE(Residual(p, q, phi), 1e-12) << k;
    const int deg = k % 360;
    if (deg == 0 || deg == 180) {
      // The crossing: reported by the branch measure at the right angles.
      EXPECT_LT(report.branch_measure, 1e-12) << k;
      EXPECT_EQ(report.branch_block, 0) << k;
      continue;
    }
    if (deg < 180) {  // the assembly's branch: the parallelogram
      EXPECT_LT(AngleDistance(phi(1), q), 1e-12) << k;
      EXPECT_LT(AngleDistance(phi(0), 0), 1e-12) << k;
      EXPECT_NEAR(report.branch_measure, std::sin(q) * std::sin(q), 1e-12) << k;
    } else {
      // Past 180 deg the same mode is the antiparallelogram: not the parallelogram, and its
      // branch measure is sin^2 of its own coupler-rocker angle.
      EXPECT_GT(AngleDistance(phi(1), q), 1e-3) << k;
      EXPECT_GT(AngleDistance(phi(0), 0), 1e-3) << k;
      const double s = std::sin(phi(1) - phi(0));
      EXPECT_NEAR(report.branch_measure, s * s, 1e-12) << k;
      // The other mode is the parallelogram there.
      Eigen::Vector2d parallel = phi;
      ASSERT_EQ(M::Solve(p, Vec1(q), &parallel, other).status, SolveStatus::kConverged) << k;
      EXPECT_LT(AngleDistance(parallel(1), q), 1e-12) << k;
      EXPECT_LT(AngleDistance(parallel(0), 0), 1e-12) << k;
    }
  }
}

TEST(Parallelogram, SweepFollowingTheTangentStaysOnTheParallelogramAndShowsTheCrossing) {
  // 1 deg -> 359 deg in 2 deg steps: the rows at 179 and 181 deg lie on either side of the
  // change point at 180 deg. Crossing::kFollowTangent passes it on the smooth curve, the
  // parallelogram; the crossing shows as the flip of sign det Phi_phi (state.branch) between
  // those two rows, and nowhere else.
  mechgen::position::PositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<mechgen::SweepRecord<M>> records;
  mechgen::SweepOptions options;
  options.at_singularity = mechgen::position::Crossing::kFollowTangent;
  EXPECT_EQ(mechgen::Sweep(&solver, Vec1(1 * kDeg), Vec1(359 * kDeg), 179, Vec1(1), Vec1(0), &records, options), 0);
  ASSERT_EQ(records.size(), 180u);
  int flips = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    ASSERT_EQ(r.summary.status, mechgen::position::Status::kConverged) << i;
    const double q = r.state.q(0);
    EXPECT_NEAR(q, (1 + 2.0 * i) * kDeg, 1e-12) << i;
    EXPECT_LT(AngleDistance(r.state.phi(1), q), 1e-9) << i;  // rocker turns with the crank
    EXPECT_LT(AngleDistance(r.state.phi(0), 0), 1e-9) << i;  // coupler parallel to ground
    EXPECT_NEAR(r.state.K(0, 0), 0, 1e-7) << i;
    EXPECT_NEAR(r.state.K(1, 0), 1, 1e-7) << i;
    if (i > 0 && r.state.branch != records[i - 1].state.branch) {
      ++flips;
      EXPECT_LT(records[i - 1].state.q(0), kPi) << i;
      EXPECT_GT(q, kPi) << i;
    }
  }
  EXPECT_EQ(flips, 1);
}

TEST(Parallelogram, SweepOfTwoTurnsPassesFourChangePoints) {
  // 0.5 deg -> 720.5 deg in 720 steps of 1 deg: the change points at 180, 360, 540 and 720
  // deg lie half a step from the rows on either side; each is passed on the parallelogram
  // with one flip of sign det Phi_phi there. (A row asked for exactly at a change point has
  // no K there, Phi_phi being singular: the runtime stops or passes beside it.)
  mechgen::position::PositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<mechgen::SweepRecord<M>> records;
  mechgen::SweepOptions options;
  options.at_singularity = mechgen::position::Crossing::kFollowTangent;
  EXPECT_EQ(mechgen::Sweep(&solver, Vec1(0.5 * kDeg), Vec1(720.5 * kDeg), 720, Vec1(1), Vec1(0), &records, options),
            0);
  std::vector<double> flips_at;
  for (size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    ASSERT_EQ(r.summary.status, mechgen::position::Status::kConverged) << i << mechgen::position::FormatSummary(r.summary);
    const double q = r.state.q(0);
    EXPECT_NEAR(q, (0.5 + static_cast<double>(i)) * kDeg, 1e-12) << i;
    EXPECT_LT(AngleDistance(r.state.phi(1), q), 1e-9) << i;
    EXPECT_LT(AngleDistance(r.state.phi(0), 0), 1e-9) << i;
    if (i > 0 && r.state.branch != records[i - 1].state.branch) flips_at.push_back(static_cast<double>(i));
  }
  // Row i is at i + 0.5 deg: a flip between rows i - 1 and i is a crossing at i deg.
  EXPECT_EQ(flips_at, (std::vector<double>{180, 360, 540, 720}));
}

TEST(Parallelogram, SweepThatStopsStopsJustBeforeTheChangePoint) {
  // Crossing::kStop (the default): the sweep ends at the last valid configuration before
  // 180 deg, with kSingular there, still on the parallelogram.
  mechgen::position::PositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<mechgen::SweepRecord<M>> records;
  EXPECT_GT(mechgen::Sweep(&solver, Vec1(1 * kDeg), Vec1(359 * kDeg), 179, Vec1(1), Vec1(0), &records), 0);
  bool stopped = false;
  for (const auto& r : records) {
    if (r.summary.status != mechgen::position::Status::kSingular) continue;
    stopped = true;
    EXPECT_LT(r.state.q(0), kPi);
    EXPECT_GT(r.state.q(0), 179 * kDeg);
    EXPECT_LT(AngleDistance(r.state.phi(1), r.state.q(0)), 1e-6);
    break;
  }
  EXPECT_TRUE(stopped);
}

}  // namespace
