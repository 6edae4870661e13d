// The generated SolvePositions' own contract (issue 12, "The generated solver's own
// contract"):
//   - a report that says kConverged holds finite positions that close the loops;
//   - on any other status *phi is unchanged, bit for bit (solved into a local copy), even
//     when an earlier block had been solved;
//   - degenerate configurations (coincident circle centres, zero-length links, exact change
//     and dead points, non-finite inputs, parameters or starting guesses) get a status that
//     says so, never NaN or inf with kConverged;
//   - Newton blocks take no step after converging (at an exactly singular solution, with
//     --strategy monolithic, the solve returns the solution it was given, 0 iterations);
//   - the branch-point signal (SolveReport::branch_measure) equals sin^2 of the angle
//     between an RRR dyad's links, computed here from the solved angles (the oracle), so it
//     is 0 at a parallelogram's change points and away from 0 elsewhere;
//   - a slot at a non-zero angle on a rotating link keeps the closed-form dyad.
// Every shipped model (all_models.h) is swept over each input's declared range on every
// assembly mode, from continued guesses and from a NaN guess.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "all_models.h"
#include "contract_fourbar_monolithic.h"
#include "slot_angle.h"

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

template <class M>
using VecQ = Eigen::Matrix<double, M::kNq, 1>;
template <class M>
using VecPhi = Eigen::Matrix<double, M::kNphi, 1>;

template <class M>
bool SameBits(const VecPhi<M>& a, const VecPhi<M>& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * M::kNphi) == 0;
}

template <class M>
VecQ<M> AssemblyQ() {
  VecQ<M> q;
  for (int i = 0; i < M::kNq; ++i) q(i) = M::kAssemblyQ[i];
  return q;
}

template <class M>
VecPhi<M> AssemblyPhi() {
  VecPhi<M> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  return phi;
}

// One solve, checked against the contract. Returns the report; *phi gets the result.
template <class M>
auto CheckedSolve(const typename M::template ParamsT<double>& p, const VecQ<M>& q, VecPhi<M>* phi,
                  const std::array<int, M::kNumBlocks>& modes, const std::string& where) {
  const VecPhi<M> before = *phi;
  const auto report = M::Solve(p, q, phi, modes);
  using SolveStatus = decltype(report.status);
  if (report.status == SolveStatus::kConverged) {
    EXPECT_TRUE(phi->allFinite()) << where << ": converged with " << phi->transpose();
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(p, q, *phi, &Phi);
    EXPECT_LE(Phi.cwiseAbs().maxCoeff(), 1e-9) << where << ": converged but the loops do not close";
    EXPECT_TRUE(report.branch_measure >= 0 && report.branch_measure <= 1 + 1e-12)
        << where << ": branch_measure " << report.branch_measure;
  } else {
    EXPECT_TRUE(SameBits<M>(*phi, before)) << where << ": status " << static_cast<int>(report.status)
                                           << " but phi changed from " << before.transpose() << " to "
                                           << phi->transpose();
  }
  return report;
}

template <class M>
class SolveContractTest : public ::testing::Test {};
TYPED_TEST_SUITE(SolveContractTest, mechtest::AllModels, mechtest::ModelNames);

TYPED_TEST(SolveContractTest, EveryInputOverItsRangeOnEveryModeIsFiniteOrUnchanged) {
  using M = TypeParam;
  const typename M::template ParamsT<double> p;
  std::vector<std::array<int, M::kNumBlocks>> all_modes = {M::kDefaultModes};
  for (int b = 0; b < M::kNumBlocks; ++b) {
    if (!M::kBlockClosedForm[b]) continue;
    auto m = M::kDefaultModes;
    m[b] = -m[b];
    all_modes.push_back(m);
  }
  const int steps = 360;
  int converged = 0;
  for (size_t mi = 0; mi < all_modes.size(); ++mi) {
    for (int j = 0; j < M::kNq; ++j) {
      VecQ<M> q = AssemblyQ<M>();
      VecPhi<M> phi = AssemblyPhi<M>();
      for (int s = 0; s <= steps; ++s) {
        q(j) = M::kQMin[j] + (M::kQMax[j] - M::kQMin[j]) * s / steps;
        const std::string where = std::string(M::kName) + " modes #" + std::to_string(mi) + " input " +
                                  std::to_string(j) + " step " + std::to_string(s);
        const auto r = CheckedSolve<M>(p, q, &phi, all_modes[mi], where);
        converged += static_cast<int>(r.status) == 0;
        // From a guess of NaN: closed forms ignore it as a reference; Newton blocks fail.
        VecPhi<M> nan_guess = VecPhi<M>::Constant(kNaN);
        CheckedSolve<M>(p, q, &nan_guess, all_modes[mi], where + " (NaN guess)");
      }
    }
  }
  // The default modes at least assemble over the declared range.
  EXPECT_GE(converged, (steps + 1) * M::kNq) << M::kName;
}

TYPED_TEST(SolveContractTest, NonFiniteInputsAndParametersNeverConverge) {
  using M = TypeParam;
  const typename M::template ParamsT<double> p;
  for (const double bad : {kNaN, kInf, -kInf}) {
    for (int j = 0; j < M::kNq; ++j) {
      VecQ<M> q = AssemblyQ<M>();
      q(j) = bad;
      VecPhi<M> phi = AssemblyPhi<M>();
      const auto r = CheckedSolve<M>(p, q, &phi, M::kDefaultModes, std::string(M::kName) + " q non-finite");
      EXPECT_NE(static_cast<int>(r.status), 0) << M::kName << ": converged at q(" << j << ") = " << bad;
    }
  }
}

// ---- A table of degenerate configurations -------------------------------------------

using FourBar = mech::fourbar::Model;
using FourBarStatus = mech::fourbar::SolveStatus;

struct FourBarCase {
  const char* what;
  double a, b, c, d;  // crank, coupler, rocker, ground
  double theta;
  FourBarStatus status;
  double max_branch;  // kConverged: branch_measure at most this
};

class DegenerateFourBar : public ::testing::TestWithParam<FourBarCase> {};

TEST_P(DegenerateFourBar, SaysWhatItIs) {
  const FourBarCase& c = GetParam();
  FourBar::ParamsT<double> p;
  p.a = c.a;
  p.b = c.b;
  p.c = c.c;
  p.d = c.d;
  for (const double guess : {0.3, kNaN}) {
    Eigen::Matrix<double, 2, 1> phi(guess, guess + 1);
    const auto r = CheckedSolve<FourBar>(p, Eigen::Matrix<double, 1, 1>(c.theta), &phi, FourBar::kDefaultModes,
                                         c.what);
    EXPECT_EQ(r.status, c.status) << c.what << " (measure " << r.measure << ")";
    if (r.status == FourBarStatus::kConverged) {
      EXPECT_LE(r.branch_measure, c.max_branch) << c.what;
      EXPECT_EQ(r.branch_block, 0) << c.what;
    } else {
      EXPECT_EQ(r.block, 0) << c.what;
    }
    if (r.status == FourBarStatus::kSingular && c.a == c.d && c.theta == 0) {
      EXPECT_EQ(r.measure, 0.0) << c.what << ": the measure is the centres' squared distance";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    SolveContract, DegenerateFourBar,
    ::testing::Values(
        // a = d: the crank tip B meets the pivot D at theta = 0, the RRR dyad's circle centres.
        FourBarCase{"kite a = d, b = c at theta = 0: coincident centres", 2, 3, 3, 2, 0, FourBarStatus::kSingular, 0},
        FourBarCase{"kite a = d, b != c at theta = 0: coincident centres", 2, 3, 2.5, 2, 0, FourBarStatus::kSingular, 0},
        FourBarCase{"rhombus a = b = c = d at theta = 0", 1, 1, 1, 1, 0, FourBarStatus::kSingular, 0},
        // Parallelogram a = c, b = d: change points at 0 and 180 deg (circles tangent).
        FourBarCase{"parallelogram at theta = 0 (internal tangency)", 1, 4, 1, 4, 0, FourBarStatus::kConverged, 1e-12},
        FourBarCase{"parallelogram at theta = 180 deg (external tangency)", 1, 4, 1, 4, M_PI, FourBarStatus::kConverged,
                    1e-12},
        FourBarCase{"parallelogram at theta = 360 deg", 1, 4, 1, 4, 2 * M_PI, FourBarStatus::kConverged, 1e-12},
        // A crank-rocker's rocker at its limit is a dead point of the rocker, not of the dyad:
        // the dyad is regular there. Its limit of reach (a + d = b + c) is an exact tangency.
        FourBarCase{"Grashof-neutral a + d = b + c at theta = 180 deg", 1, 3, 2, 4, M_PI, FourBarStatus::kConverged,
                    1e-12},
        FourBarCase{"zero-length coupler", 1, 0, 3, 4, 1, FourBarStatus::kSingular, 0},
        FourBarCase{"zero-length rocker", 1, 3.5, 0, 4, 1, FourBarStatus::kSingular, 0},
        FourBarCase{"crank too long: the circles do not meet", 3.2, 3.5, 3, 4, M_PI, FourBarStatus::kNotAssemblable,
                    0},
        FourBarCase{"a NaN parameter", kNaN, 3.5, 3, 4, 1, FourBarStatus::kSingular, 0},
        FourBarCase{"an infinite parameter", 1, kInf, 3, 4, 1, FourBarStatus::kSingular, 0}));

TEST(SolveContract, SliderCrankDeadPointAndZeroRod) {
  using M = mech::slider_crank::Model;
  using S = mech::slider_crank::SolveStatus;
  M::ParamsT<double> p;
  // Offset e = a + b: at theta = 90 deg the rod is perpendicular to the slide's line and
  // the crank's tip is as far from it as the rod reaches (acos(1), one configuration).
  p.e = p.a + p.b;
  Eigen::Matrix<double, 2, 1> phi(0.3, 1.0);
  auto r = CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(M_PI / 2), &phi, M::kDefaultModes, "dead point");
  ASSERT_EQ(r.status, S::kConverged);
  EXPECT_LE(r.branch_measure, 1e-12);
  EXPECT_NEAR(phi(0), M_PI / 2, 1e-6) << "the rod points at the slide's line";
  // Just short of the dead point, the measure is sin^2 of the acos term (oracle: the rod's
  // angle from the slide's normal).
  p = M::ParamsT<double>();
  phi << 0.3, 1.0;
  r = CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(1.0), &phi, M::kDefaultModes, "regular");
  ASSERT_EQ(r.status, S::kConverged);
  const double cos_term = -(p.a * std::sin(1.0) - p.e) / p.b;
  EXPECT_NEAR(r.branch_measure, 1 - cos_term * cos_term, 1e-14);
  // A rod of zero length: the rod's angle moves nothing.
  p.b = 0;
  Eigen::Matrix<double, 2, 1> before(0.3, 1.0);
  phi = before;
  r = CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(1.0), &phi, M::kDefaultModes, "zero rod");
  EXPECT_EQ(r.status, S::kSingular);
}

TEST(SolveContract, InvertedSliderCrankThroughThePivot) {
  // d = a: at theta = 0 the block's pin B is on the rocker's pivot D, |DB| = s = 0, so the
  // rocker's angle is not determined (a slider at the end of its stroke).
  using M = mech::inverted_slider_crank::Model;
  M::ParamsT<double> p;
  p.d = p.a;
  Eigen::Matrix<double, 2, 1> phi(2.5, 1.0);
  const auto r = CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(0.0), &phi, M::kDefaultModes, "s = 0");
  EXPECT_EQ(r.status, mech::inverted_slider_crank::SolveStatus::kSingular);
  EXPECT_EQ(r.measure, 0.0);
}

TEST(SolveContract, PhiUnchangedWhenALaterBlockFails) {
  // Stephenson six-bar: block 0 (the four-bar) solves, block 1 (link5 and the output)
  // cannot reach an output pivot moved far away.
  using M = mech::stephenson_sixbar::Model;
  M::ParamsT<double> p;
  p.x6 = 100;
  const VecPhi<M> before = AssemblyPhi<M>();
  VecPhi<M> phi = before;
  const auto r = M::Solve(p, AssemblyQ<M>(), &phi);
  EXPECT_EQ(r.status, mech::stephenson_sixbar::SolveStatus::kNotAssemblable);
  EXPECT_EQ(r.block, 1);
  EXPECT_TRUE(SameBits<M>(phi, before)) << phi.transpose();
}

TEST(SolveContract, BranchSignalAtAParallelogramsChangePointsOnly) {
  // Parallelogram a = c = 1, b = d = 4, swept over a full turn with fixed modes. The oracle
  // is the solved configuration itself: sin^2 of the angle between coupler and rocker.
  FourBar::ParamsT<double> p;
  p.a = 1;
  p.b = 4;
  p.c = 1;
  p.d = 4;
  Eigen::Matrix<double, 2, 1> phi(0.1, 0.1);
  for (int deg = 0; deg <= 720; ++deg) {
    const double theta = deg * M_PI / 180;
    const std::string where = "theta = " + std::to_string(deg) + " deg";
    const auto r = CheckedSolve<FourBar>(p, Eigen::Matrix<double, 1, 1>(theta), &phi, FourBar::kDefaultModes, where);
    ASSERT_EQ(r.status, FourBarStatus::kConverged) << where;
    const double s = std::sin(phi(1) - phi(0));
    EXPECT_NEAR(r.branch_measure, s * s, 1e-12) << where;
    if (deg % 180 == 0) {
      EXPECT_LE(r.branch_measure, 1e-12) << where << ": a change point";
    } else {
      // sin^2 of the crank's angle from the line of the pivots (both branches): >= sin^2(1 deg).
      EXPECT_GE(r.branch_measure, 0.9 * std::pow(std::sin(M_PI / 180), 2)) << where;
    }
  }
}

TEST(SolveContract, BranchSignalQuietOnACrankRocker) {
  // The shipped four-bar (a crank-rocker) never comes near a branch point: its measure is
  // sin^2 of the transmission angle mu, which stays above sin^2(30 deg) there.
  const FourBar::ParamsT<double> p;
  Eigen::Matrix<double, 2, 1> phi = AssemblyPhi<FourBar>();
  for (int deg = 0; deg <= 360; ++deg) {
    const auto r = CheckedSolve<FourBar>(p, Eigen::Matrix<double, 1, 1>(deg * M_PI / 180), &phi,
                                         FourBar::kDefaultModes, "crank-rocker");
    ASSERT_EQ(r.status, FourBarStatus::kConverged);
    const double s = std::sin(phi(1) - phi(0));
    EXPECT_NEAR(r.branch_measure, s * s, 1e-12);
    EXPECT_GT(r.branch_measure, 0.25) << deg << " deg";
  }
}

TEST(SolveContract, MonolithicNewtonTakesNoStepAfterConverging) {
  // The parallelogram at theta = 0 is exactly singular (Phi_phi of rank 1 there). Started
  // at the exact solution, Newton has converged before any step: 0 iterations, the same
  // phi. (A step taken after convergence would solve with a singular Jacobian: 0/0.)
  using M = mech::contract_fourbar_monolithic::Model;
  using S = mech::contract_fourbar_monolithic::SolveStatus;
  M::ParamsT<double> p;
  p.a = 1;
  p.b = 4;
  p.c = 1;
  p.d = 4;
  const Eigen::Matrix<double, 2, 1> exact(0.0, 0.0);
  Eigen::Matrix<double, 2, 1> phi = exact;
  auto r = CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(0.0), &phi, M::kDefaultModes, "exact");
  ASSERT_EQ(r.status, S::kConverged);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_TRUE(SameBits<M>(phi, exact));
  // Near it, from guesses on both sides: converged and finite, or failed and unchanged.
  for (const double e : {1e-3, -1e-3, 1e-8, 0.3}) {
    phi << e, -e;
    CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(0.0), &phi, M::kDefaultModes, "near " + std::to_string(e));
    phi << e, e;
    CheckedSolve<M>(p, Eigen::Matrix<double, 1, 1>(M_PI), &phi, M::kDefaultModes, "near 180, " + std::to_string(e));
  }
}

TEST(SolveContract, SlotAtANonZeroAngleKeepsTheClosedForm) {
  // The inverted slider-crank with its slot at 0.001 deg on the rocker: still one
  // circle-line dyad, and its solution matches a dense Newton on the generated Phi.
  using M = mech::slot_angle::Model;
  static_assert(M::kNumBlocks == 1, "one block");
  EXPECT_TRUE(M::kBlockClosedForm[0]);
  const M::ParamsT<double> p;
  Eigen::Matrix<double, 2, 1> phi = AssemblyPhi<M>();
  for (int deg = 0; deg <= 360; deg += 5) {
    const Eigen::Matrix<double, 1, 1> q(deg * M_PI / 180);
    const auto r = CheckedSolve<M>(p, q, &phi, M::kDefaultModes, "slot at 0.001 deg");
    ASSERT_EQ(static_cast<int>(r.status), 0) << deg;
    EXPECT_EQ(r.iterations, 0) << "closed form";
    // Oracle: the slot's line through D at theta_rocker + 0.001 deg passes through B, at
    // distance s_slot from D.
    const double alpha = 0.001 * M_PI / 180;
    const double bx = p.a * std::cos(q(0)), by = p.a * std::sin(q(0));
    EXPECT_NEAR(p.d + phi(1) * std::cos(phi(0) + alpha), bx, 1e-12);
    EXPECT_NEAR(phi(1) * std::sin(phi(0) + alpha), by, 1e-12);
  }
}

}  // namespace
