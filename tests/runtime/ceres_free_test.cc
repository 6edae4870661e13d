// The runtime without Ceres: this binary links mechgen::runtime only (not runtime_ceres) and
// fails to compile if any header it includes pulls in Ceres. PositionSolver<M> with its
// default Assembler (NewtonAssembler, fixed-size Levenberg–Marquardt) assembles from the
// model's guess and from poor guesses, refuses a loop that cannot close, and a sweep with
// its CSV and table runs. Oracle: the closed-form four-bar position
// (handwritten_fourbar.h: ClosedFormPosition), and finite differences of solved positions.
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "handwritten_fourbar.h"
#include "handwritten_rocker_driven.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/svg.h"
#include "mechgen/io/table.h"
#include "mechgen/position/motion.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"
#include "test_util.h"
#ifdef MECHGEN_HAVE_fourbar
#include "fourbar.h"
#endif

#if defined(CERES_PUBLIC_CERES_H_) || defined(CERES_PUBLIC_JET_H_) || \
    defined(CERES_PUBLIC_COST_FUNCTION_H_) || defined(CERES_PUBLIC_PROBLEM_H_)
#error "a Ceres-free runtime header included Ceres"
#endif

namespace mechgen::position {
namespace {

using FourBar = mech::handwritten_fourbar::Model;
using Rocker = mech::handwritten_rocker_driven::Model;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Vector2d;
constexpr double kPi = 3.14159265358979323846;

Vec1 Q(double q) { return Vec1::Constant(q); }
double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

static_assert(std::is_same_v<PositionSolver<FourBar>, PositionSolver<FourBar, NewtonAssembler>>,
              "the default Assembler is the Ceres-free one");

TEST(CeresFree, NewtonAssemblerAssemblesFromTheModelsGuess) {
  PositionSolver<FourBar> solver;
  Summary summary;
  ASSERT_EQ(solver.AssembleDefault(&summary), Status::kConverged) << FormatSummary(summary);
  EXPECT_TRUE(summary.used_assembler);
  // The guess (0.5, 1.9) at q = 90 deg is the open mode: C left of B->D (branch +1).
  Vec2 exact;
  ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(solver.params(), FourBar::kAssemblyQ[0],
                                                            +1, &exact));
  EXPECT_LT(AngleDistance(solver.state().phi(0), exact(0)), 1e-9);
  EXPECT_LT(AngleDistance(solver.state().phi(1), exact(1)), 1e-9);
  EXPECT_LE(testing::ResidualNorm<FourBar>(solver.params(), solver.state().q, solver.state().phi),
            1e-10);
}

TEST(CeresFree, PoorGuessesLandOnRequestedBranchOrSayOtherwise) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  const FourBar::ParamsT<double> p;
  int landed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double q = angle(gen);
    const int branch = trial % 2 ? +1 : -1;  // ClosedFormPosition's label
    const int det_sign = -branch;            // sign(det Phi_phi) of that mode
    Vec2 exact;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q, branch, &exact));
    PositionSolver<FourBar> solver;
    Summary summary;
    const Status status = solver.Assemble(Q(q), Vec2(angle(gen), angle(gen)), det_sign, &summary);
    if (status == Status::kConverged) {
      ++landed;
      EXPECT_EQ(solver.state().branch, det_sign);
      EXPECT_LT(AngleDistance(solver.state().phi(0), exact(0)), 1e-9);
      EXPECT_LT(AngleDistance(solver.state().phi(1), exact(1)), 1e-9);
    } else {
      EXPECT_EQ(status, Status::kWrongBranch) << FormatSummary(summary);
      EXPECT_EQ(summary.branch, -det_sign);
      EXPECT_FALSE(solver.state().valid);
    }
  }
  EXPECT_GT(landed, 50);
}

TEST(CeresFree, LoopThatCannotCloseIsNotAssemblable) {
  // The rocker beyond its swing (th3 <= acos(-0.78125) ~ 141.4 deg): no closing configuration.
  const double th_max = std::acos(-0.78125);
  PositionSolver<Rocker> solver;
  Summary summary;
  EXPECT_EQ(solver.Assemble(Q(th_max + 0.2), Vec2(-0.5, 1.1), 0, &summary),
            Status::kNotAssemblable)
      << FormatSummary(summary);
  EXPECT_FALSE(solver.state().valid);
  // Continuing into it stops at the dead point (the Assembler is the last fallback).
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  EXPECT_EQ(solver.MoveTo(Q(th_max + 0.05), &summary), Status::kSingular) << FormatSummary(summary);
  EXPECT_LT(std::abs(solver.state().q(0) - th_max), 1e-3);
}

TEST(CeresFree, SweepFollowsTheClosedFormAndWritesCsvAndTable) {
  PositionSolver<FourBar> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  std::vector<SweepRecord<FourBar>> records;
  ASSERT_EQ(Sweep(&solver, Q(0), Q(2 * kPi), 720, Q(1), Q(0), &records), 0);
  for (const SweepRecord<FourBar>& r : records) {
    Vec2 exact;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(solver.params(), r.q(0), +1, &exact));
    EXPECT_LT(AngleDistance(r.state.phi(0), exact(0)), 1e-9) << r.q(0);
    EXPECT_LT(AngleDistance(r.state.phi(1), exact(1)), 1e-9) << r.q(0);
  }
  std::ostringstream csv, table, svg;
  WriteCsv(records, csv);
  PrintTable(records, 8, table);
  WriteSvg(solver.params(), records, SvgOptions(), svg);
  const std::string text = csv.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 722);  // header + 721 rows
  EXPECT_NE(table.str().find("theta_coupler"), std::string::npos);
  EXPECT_NE(svg.str().find("</svg>"), std::string::npos);
}

#ifdef MECHGEN_HAVE_fourbar
TEST(CeresFree, GeneratedFourBarContinuesWithKAgainstFiniteDifferences) {
  // The generated model: Newton assembly from its guess, then MoveTo steps; K against the
  // central difference of solved positions (h = 1e-5: truncation ~ h^2 |phi'''| ~ 1e-10,
  // rounding ~ 1e-15 / h).
  using M = mech::fourbar::Model;
  using VecQ = ModelTypes<M>::VecQ;
  PositionSolver<M> solver, probe;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(probe.AssembleDefault(nullptr), Status::kConverged);
  const double h = 1e-5;
  for (double q = 0; q < 2 * kPi; q += 0.3) {
    ASSERT_EQ(solver.MoveTo(VecQ::Constant(q), nullptr), Status::kConverged);
    EXPECT_LE(testing::ResidualNorm<M>(solver.params(), solver.state().q, solver.state().phi),
              1e-10);
    ASSERT_EQ(probe.MoveTo(VecQ::Constant(q + h), nullptr), Status::kConverged);
    const auto phi_plus = probe.state().phi;
    ASSERT_EQ(probe.MoveTo(VecQ::Constant(q - h), nullptr), Status::kConverged);
    const auto phi_minus = probe.state().phi;
    EXPECT_LT((solver.state().K.col(0) - (phi_plus - phi_minus) / (2 * h)).cwiseAbs().maxCoeff(),
              1e-7)
        << "q = " << q;
  }
}
#endif

}  // namespace
}  // namespace mechgen::position
