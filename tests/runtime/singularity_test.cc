// Singular configurations, distance to singularity and hostile inputs (issue 7).
//
// Mechanisms (hand-written models, closed forms written here as oracles):
//  - Grashof-neutral four-bar a = 1, b = 3, c = 2, d = 2 (s + l = 1 + 3 = p + q = 2 + 2),
//    crank-driven: at theta_crank = 0, |BD| = d - a = b - c, the two circle intersections
//    coincide and the two solution curves cross (a change point). Incoming from q < 0 on the
//    closed-form branch +1, the smooth curve continues as closed-form branch -1 (C crosses
//    the line BD: sign det Phi_phi flips), the other curve as branch +1.
//  - The crank-rocker of handwritten_rocker_driven.h driven by its rocker: dead points at
//    th3 = acos(-0.78125) and acos(-0.197917), where crank and coupler are collinear.
// Tolerances: positions 1e-9 (solver tolerance 1e-10, cond(Phi_phi) <= ~1e3 at the rows
// compared); K by central differences of the closed form at h = 1e-5 (truncation
// h^2 |phi'''| / 6 ~ 1e-10, rounding 1e-16 / h ~ 1e-11), compared at 1e-6.
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "handwritten_fourbar.h"
#include "handwritten_rocker_driven.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/svg.h"
#include "mechgen/io/table.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"
#include "test_util.h"

namespace mechgen::position {
namespace {

using FourBar = mech::handwritten_fourbar::Model;
using Rocker = mech::handwritten_rocker_driven::Model;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Vector2d;
constexpr double kPi = 3.14159265358979323846;

Vec1 Q(double q) { return Vec1::Constant(q); }
double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }
double AngleDistance(const Vec2& a, const Vec2& b) {
  return std::max(AngleDistance(a(0), b(0)), AngleDistance(a(1), b(1)));
}

FourBar::ParamsT<double> NeutralParams() {
  FourBar::ParamsT<double> p;
  p.a = 1;
  p.b = 3;
  p.c = 2;
  p.d = 2;
  return p;
}

Vec2 ClosedForm(const FourBar::ParamsT<double>& p, double q, int branch) {
  Vec2 phi;
  EXPECT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q, branch, &phi)) << q;
  return phi;
}

// Assembled at q = -1 on closed-form branch +1 of the Grashof-neutral four-bar.
CeresPositionSolver<FourBar> NeutralSolver() {
  const auto p = NeutralParams();
  CeresPositionSolver<FourBar> solver(Options(), p);
  EXPECT_EQ(solver.Assemble(Q(-1), ClosedForm(p, -1, +1), 0, nullptr), Status::kConverged);
  return solver;
}

TEST(DistanceToSingularity, SigmaMinAndDirectionMatchClosedForm) {
  // Phi_phi = [-b S2, c S3; b C2, -c C3]: Phi_phi^T Phi_phi = [b^2, -bc g; -bc g, c^2] with
  // g = cos(th2 - th3), so sigma_min^2 = (b^2 + c^2 - sqrt((b^2 - c^2)^2 + 4 b^2 c^2 g^2)) / 2.
  CeresPositionSolver<FourBar> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const auto& p = solver.params();
  for (double q = 0; q < 2 * kPi; q += 0.1) {
    ASSERT_EQ(solver.MoveTo(Q(q), nullptr), Status::kConverged);
    const State<FourBar>& s = solver.state();
    const double g = std::cos(s.phi(0) - s.phi(1));
    const double b2 = p.b * p.b, c2 = p.c * p.c;
    const double root = std::sqrt((b2 - c2) * (b2 - c2) + 4 * b2 * c2 * g * g);
    const double sigma_min = std::sqrt((b2 + c2 - root) / 2);
    const double sigma_max = std::sqrt((b2 + c2 + root) / 2);
    EXPECT_NEAR(s.sigma_min, sigma_min, 1e-12 * sigma_max) << q;
    EXPECT_NEAR(s.sigma_max, sigma_max, 1e-12 * sigma_max) << q;
    Eigen::Matrix2d Phi_phi;
    FourBar::Phi<double>(p, s.q, s.phi, nullptr, &Phi_phi, nullptr);
    EXPECT_NEAR(s.singular_direction.norm(), 1, 1e-14);
    EXPECT_NEAR((Phi_phi * s.singular_direction).norm(), sigma_min, 1e-12 * sigma_max) << q;
  }
}

TEST(DistanceToSingularity, ClosedForm2x2MatchesJacobiSvd) {
  // SingularValues2x2 (closed form, used every continuation step of a 2 x 2 Phi_phi) against
  // SmallestSingular (Eigen's JacobiSVD): values to eps * sigma_max, both vectors unit, with
  // the same sign convention, singular vectors of A (A v = sigma_min u, A w = sigma_max u');
  // random matrices, nearly singular ones down to sigma_min / sigma_max = 1e-14, diagonal
  // ones with either entry larger (both branches e >= 0, e < 0 of the vector's formula),
  // equal singular values, a zero matrix, and non-finite input (NaN outputs).
  std::vector<Eigen::Matrix2d> cases;
  std::srand(7);
  for (int i = 0; i < 2000; ++i) cases.push_back(Eigen::Matrix2d::Random());
  for (double t : {1e-2, 1e-5, 1e-8, 1e-11, 1e-14}) {
    for (int i = 0; i < 50; ++i) {
      Eigen::Matrix2d A = Eigen::Matrix2d::Random();
      A.col(1) = A.col(0) * Eigen::Vector2d::Random()(0) + t * Eigen::Vector2d::Random();
      cases.push_back(A);
    }
  }
  cases.push_back((Eigen::Matrix2d() << 3, 0, 0, 1e-3).finished());
  cases.push_back((Eigen::Matrix2d() << 1e-3, 0, 0, 3).finished());
  cases.push_back((Eigen::Matrix2d() << 0, -3, 2, 0).finished());
  cases.push_back((Eigen::Matrix2d() << 2, 0, 0, -2).finished());  // equal singular values
  // Singular vectors with entries of equal magnitude (the sign conventions' ties).
  cases.push_back((Eigen::Matrix2d() << 1, 1, 1, 1).finished());
  cases.push_back((Eigen::Matrix2d() << 1, -1, 1, -1).finished());
  cases.push_back((Eigen::Matrix2d() << 2, 1, 1, 2).finished());
  cases.push_back((Eigen::Matrix2d() << 2, -1, -1, 2).finished());
  cases.push_back(Eigen::Matrix2d::Zero());
  for (const Eigen::Matrix2d& A : cases) {
    double smin = 0, smax = 0, ref_min = 0, ref_max = 0;
    Vec2 v, u, ref_v;
    SingularValues2x2(A, &smin, &smax, &v, &u);
    SmallestSingular(A, &ref_min, &ref_max, &ref_v);
    const double scale = std::max(ref_max, 1e-300);
    EXPECT_NEAR(smin, ref_min, 1e-14 * scale) << A;
    EXPECT_NEAR(smax, ref_max, 1e-14 * scale) << A;
    EXPECT_NEAR(v.norm(), 1, 1e-14) << A;
    EXPECT_NEAR(u.norm(), 1, 1e-14) << A;
    EXPECT_NEAR(v.dot(u), 0, 1e-14) << A;
    EXPECT_NEAR((A * v).norm(), smin, 1e-13 * scale) << A;
    EXPECT_NEAR((A * u).norm(), smax, 1e-13 * scale) << A;
    // The largest-magnitude entry is positive (the same vector as JacobiSVD's, sign fixed,
    // where sigma_min is simple and the vector well determined).
    Eigen::Index largest = 0;
    v.cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(v(largest), 0) << A;
    // u too (State::largest_direction): its larger entry positive, the first on a tie.
    EXPECT_GT(std::abs(u(1)) > std::abs(u(0)) ? u(1) : u(0), 0) << A;
    if (ref_max - ref_min > 1e-6 * ref_max) {
      EXPECT_LT((v - ref_v).norm(), 1e-9) << A;
    }
  }
  double smin = 0, smax = 0;
  Vec2 v, u;
  Eigen::Matrix2d bad;
  bad << 1, std::numeric_limits<double>::quiet_NaN(), 0, 1;
  SingularValues2x2(bad, &smin, &smax, &v, &u);
  EXPECT_TRUE(std::isnan(smin) && std::isnan(smax) && v.hasNaN() && u.hasNaN());
  bad << 1, std::numeric_limits<double>::infinity(), 0, 1;
  SingularValues2x2(bad, &smin, &smax, &v, &u);
  EXPECT_TRUE(std::isnan(smin) && std::isnan(smax) && v.hasNaN() && u.hasNaN());
}

TEST(LinearAlgebra, AllFiniteAndMaxAbsDiffSeeEveryNonFiniteEntry) {
  // The continuation step's tests of finiteness and max-norms (internal::AllFinite,
  // internal::MaxAbsDiff) against std::isnan and std::abs of the entry put in: every position
  // of a 2 x 3 matrix in turn NaN, +inf or -inf, and a finite matrix and an empty one.
  using mechgen::internal::AllFinite;
  using mechgen::internal::MaxAbsDiff;
  const Eigen::Matrix<double, 2, 3> base =
      (Eigen::Matrix<double, 2, 3>() << 1, -2, 3e300, -4e-300, 0, -0.0).finished();
  const Eigen::Matrix<double, 2, 3> other = Eigen::Matrix<double, 2, 3>::Constant(0.5);
  EXPECT_TRUE(AllFinite(base));
  EXPECT_EQ(MaxAbsDiff(base), 3e300);
  EXPECT_EQ(MaxAbsDiff(base, &other), 3e300);
  EXPECT_TRUE(AllFinite(Eigen::Matrix<double, 0, 1>()));
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    for (int i = 0; i < 6; ++i) {
      Eigen::Matrix<double, 2, 3> m = base;
      m.data()[i] = bad;
      EXPECT_FALSE(AllFinite(m)) << i << " " << bad;
      const double norm = MaxAbsDiff(m);
      EXPECT_TRUE(std::isnan(bad) ? std::isnan(norm) : norm == std::abs(bad)) << i << " " << bad;
    }
  }
}

// SquareFactorization<n> (the one factorization of Phi_phi a continuation step has) against
// independent oracles: det from Eigen's FullPivLU, A^{-1} b from FullPivLU's solve, cond_1 from
// the FullPivLU inverse's norms; random and nearly singular (sigma_min / sigma_max down to
// 1e-10) matrices, a row swap needed at the first pivot, an exactly singular and a NaN matrix
// (ok() false, cond +inf). For 5 <= n <= 16 cond_1 is exact (Gauss-Jordan inverse), so it
// must match the oracle's to the rounding that cond amplifies; above 16, Eigen's estimate, a
// lower bound within a factor n of it (Higham).
template <int n>
void ExpectFactorizationMatchesFullPivLu() {
  using Matrix = Eigen::Matrix<double, n, n>;
  using Vector = Eigen::Matrix<double, n, 1>;
  std::srand(11 + n);
  std::vector<Matrix> cases;
  for (int i = 0; i < 200; ++i) cases.push_back(Matrix::Random());
  for (double t : {1e-3, 1e-6, 1e-10}) {
    for (int i = 0; i < 20; ++i) {
      Matrix A = Matrix::Random();
      A.col(n - 1) = A.leftCols(n - 1) * Eigen::Matrix<double, n - 1, 1>::Random() +
                     t * Vector::Random();
      cases.push_back(A);
    }
  }
  Matrix swap = Matrix::Random();
  swap(0, 0) = 0;  // the first pivot must come from another row
  cases.push_back(swap);
  for (const Matrix& A : cases) {
    const SquareFactorization<n> f(A);
    const Eigen::FullPivLU<Matrix> ref(A);
    const Matrix inverse = ref.inverse();
    const double cond = A.cwiseAbs().colwise().sum().maxCoeff() *
                        inverse.cwiseAbs().colwise().sum().maxCoeff();
    ASSERT_TRUE(f.ok()) << A;
    EXPECT_NEAR(f.determinant(), ref.determinant(), 1e-14 * cond * std::abs(ref.determinant()))
        << A;
    if (n <= 16) {
      EXPECT_NEAR(f.condition(), cond, 1e-14 * cond * cond) << A;
    } else {
      EXPECT_LE(f.condition(), cond * (1 + 1e-14 * cond)) << A;
      EXPECT_GE(f.condition(), cond / n) << A;
    }
    EXPECT_NEAR(f.norm1() * f.inverse_norm1(), f.condition(), 1e-14 * f.condition()) << A;
    const Vector b = Vector::Random();
    const double tolerance = 1e-14 * cond * (1 + inverse.cwiseAbs().maxCoeff());
    EXPECT_LT((f.Solve(b) - ref.solve(b)).template lpNorm<Eigen::Infinity>(), tolerance) << A;
    EXPECT_LT((f.SolveTransposed(b) - inverse.transpose() * b).template lpNorm<Eigen::Infinity>(),
              tolerance)
        << A;
  }
  Matrix singular = Matrix::Random();
  singular.col(n - 1).setZero();  // exactly singular: a pivot is exactly 0
  const SquareFactorization<n> fs(singular);
  EXPECT_FALSE(fs.ok());
  EXPECT_EQ(fs.condition(), std::numeric_limits<double>::infinity());
  Matrix bad = Matrix::Identity();
  bad(1, 2) = std::numeric_limits<double>::quiet_NaN();
  const SquareFactorization<n> fb(bad);
  EXPECT_FALSE(fb.ok());
  EXPECT_EQ(fb.condition(), std::numeric_limits<double>::infinity());
}

TEST(DistanceToSingularity, SquareFactorizationMatchesFullPivLu) {
  ExpectFactorizationMatchesFullPivLu<3>();
  ExpectFactorizationMatchesFullPivLu<5>();
  ExpectFactorizationMatchesFullPivLu<8>();
  ExpectFactorizationMatchesFullPivLu<16>();
  ExpectFactorizationMatchesFullPivLu<20>();
}

TEST(DistanceToSingularity, DecreasesTowardsChangePointAndIsInCsv) {
  // Along the smooth curve the change point is a transversal zero of det Phi_phi, so
  // sigma_min ~ |q|: halving the distance halves sigma_min (to 10 %).
  CeresPositionSolver<FourBar> solver = NeutralSolver();
  double previous = 0;
  for (double q : {-0.4, -0.2, -0.1, -0.05, -0.025}) {
    ASSERT_EQ(solver.MoveTo(Q(q), nullptr), Status::kConverged);
    if (previous > 0) {
      EXPECT_NEAR(solver.state().sigma_min / previous, 0.5, 0.05) << q;
    }
    previous = solver.state().sigma_min;
  }
  std::vector<SweepRecord<FourBar>> records;
  CeresPositionSolver<FourBar> sweeper = NeutralSolver();
  Sweep(&sweeper, Q(-1), Q(-0.5), 4, Q(1), Q(0), &records);
  std::ostringstream csv;
  WriteCsv(records, csv);
  const std::string header = csv.str().substr(0, csv.str().find('\n'));
  EXPECT_NE(header.find(",sigma_min,singular_theta_coupler,singular_theta_rocker"),
            std::string::npos)
      << header;
}

TEST(ChangePoint, SweepStopsSingularAtLastValidConfiguration) {
  CeresPositionSolver<FourBar> solver = NeutralSolver();
  std::vector<SweepRecord<FourBar>> records;
  const int failures = Sweep(&solver, Q(-1), Q(1), 200, Q(1), Q(0), &records);
  // Rows 0..99 (q <= -0.01) converge on branch +1; row 100 (q = 0) stops, the rest not run.
  EXPECT_EQ(failures, 101);
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(records[i].summary.status, Status::kConverged) << i;
    EXPECT_LT(AngleDistance(records[i].state.phi, ClosedForm(solver.params(), records[i].q(0), +1)),
              1e-9)
        << i;
  }
  const SweepRecord<FourBar>& stop = records[100];
  EXPECT_EQ(stop.summary.status, Status::kSingular) << FormatSummary(stop.summary);
  EXPECT_TRUE(stop.state.valid);
  EXPECT_LT(stop.state.q(0), 0);
  EXPECT_GT(stop.state.q(0), -1e-4);
  EXPECT_EQ(stop.state.branch, records[0].state.branch);
  EXPECT_LT(AngleDistance(stop.state.phi, ClosedForm(solver.params(), stop.state.q(0), +1)),
            1e-8);
  for (int i = 101; i <= 200; ++i) EXPECT_EQ(records[i].summary.status, Status::kNotRun) << i;
  // The singular direction at the stop is the null vector of Phi_phi at the change point,
  // where coupler and rocker are collinear (th2 = th3 = 0): Phi_phi = [0, 0; b, -c], null
  // vector (c, b) / |(c, b)|.
  const Vec2 v = Vec2(2, 3).normalized();
  EXPECT_LT((stop.state.singular_direction - v).norm(), 1e-3) << stop.state.singular_direction;
}

TEST(ChangePoint, OneLongStepOverItStopsInsteadOfSwitchingCurves) {
  // -0.1 -> +0.1: the first bisection lands exactly on q* = 0, where Newton converges only
  // linearly to a point ~1e-5 off the crossing with 1/cond ~ 2e-6 and K = (-1, -1), on no
  // curve; from there the other curve (same sign of det) was reachable. The K guard
  // (K ~ K0 + L0 dq) refuses that landing, so the step stops before q*.
  for (double d : {0.1, 0.01, 1e-3}) {
    CeresPositionSolver<FourBar> solver = NeutralSolver();
    ASSERT_EQ(solver.MoveTo(Q(-d), nullptr), Status::kConverged);
    Summary summary;
    EXPECT_EQ(solver.MoveTo(Q(d), &summary), Status::kSingular) << d << FormatSummary(summary);
    EXPECT_LT(solver.state().q(0), 0);
    EXPECT_LT(AngleDistance(solver.state().phi, ClosedForm(solver.params(), solver.state().q(0), +1)),
              1e-8);
  }
}

// After passing, every row must match the closed form of `branch_after` for q > 0, and K
// its central difference.
void ExpectPassedOnto(Crossing crossing, int branch_after) {
  CeresPositionSolver<FourBar> solver = NeutralSolver();
  std::vector<SweepRecord<FourBar>> records;
  SweepOptions options;
  options.at_singularity = crossing;
  EXPECT_EQ(Sweep(&solver, Q(-1), Q(1), 200, Q(1), Q(0), &records, options), 0);
  const auto p = solver.params();
  const double h = 1e-5;
  for (const SweepRecord<FourBar>& r : records) {
    ASSERT_EQ(r.summary.status, Status::kConverged) << r.q(0);
    const double q = r.q(0);
    const int branch = q < 0 ? +1 : branch_after;
    EXPECT_LT(AngleDistance(r.state.phi, ClosedForm(p, q, branch)), 1e-9) << q;
    if (std::abs(q) > 2 * h) {
      const Vec2 K = (ClosedForm(p, q + h, branch) - ClosedForm(p, q - h, branch)) / (2 * h);
      EXPECT_LT((r.state.K - K).cwiseAbs().maxCoeff(), 1e-6) << q;
    }
  }
}

TEST(ChangePoint, FollowTangentContinuesOnTheSmoothCurve) {
  ExpectPassedOnto(Crossing::kFollowTangent, -1);
}

TEST(ChangePoint, SwitchBranchContinuesOnTheOtherCurve) {
  ExpectPassedOnto(Crossing::kSwitchBranch, +1);
}

TEST(ChangePoint, ReverseInputIsRefusedAndStateKept) {
  CeresPositionSolver<FourBar> solver = NeutralSolver();
  ASSERT_EQ(solver.MoveTo(Q(0.01), nullptr), Status::kSingular);
  const State<FourBar> before = solver.state();
  Summary summary;
  EXPECT_EQ(solver.PassSingularity(Q(0.01), Crossing::kReverseInput, &summary),
            Status::kSingular);
  EXPECT_NE(std::string(summary.reason).find("change point"), std::string::npos)
      << summary.reason;
  EXPECT_EQ(solver.state().phi, before.phi);
  EXPECT_EQ(solver.state().q, before.q);
  // Far from any singular configuration there is nothing to pass.
  ASSERT_EQ(solver.MoveTo(Q(-0.5), nullptr), Status::kConverged);
  EXPECT_EQ(solver.PassSingularity(Q(0.01), Crossing::kFollowTangent, &summary),
            Status::kSingular);
}

// The crank position for a rocker angle q: B is an intersection of the circles (A, a) and
// (C, b), C = (d + c cos q, c sin q). Both intersections, as crank angles.
void RockerClosedForms(double q, double* crank_plus, double* crank_minus) {
  const mech::handwritten_rocker_driven::Params<double> p;
  const double xC = p.d + p.c * std::cos(q), yC = p.c * std::sin(q);
  const double l2 = xC * xC + yC * yC, l = std::sqrt(l2);
  const double x = (p.a * p.a - p.b * p.b + l2) / (2 * l);
  const double h = std::sqrt(std::max(0.0, p.a * p.a - x * x));
  const double ux = xC / l, uy = yC / l;
  *crank_plus = std::atan2(x * uy + h * ux, x * ux - h * uy);
  *crank_minus = std::atan2(x * uy - h * ux, x * ux + h * uy);
}

TEST(DeadPoint, RockerDrivenSweepReversesAndTheCrankKeepsTurning) {
  // Driven by the rocker from 2.0 towards 4.0 rad (1000 rows of 2e-3 rad) with Crossing::kReverseInput, the input
  // bounces between the dead points (141.38 and 101.42 deg) and the crank turns one way,
  // through more than a full turn: one full cycle of the mechanism.
  const double th_min = std::acos(-0.197916666666667), th_max = std::acos(-0.78125);
  CeresPositionSolver<Rocker> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  std::vector<SweepRecord<Rocker>> records;
  SweepOptions options;
  options.at_singularity = Crossing::kReverseInput;
  EXPECT_EQ(Sweep(&solver, Q(2.0), Q(4.0), 1000, Q(1), Q(0), &records, options), 0);
  int reversals = 0;
  double crank_turned = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const SweepRecord<Rocker>& r = records[i];
    ASSERT_EQ(r.summary.status, Status::kConverged) << i << FormatSummary(r.summary);
    reversals += r.summary.input_reversed;
    EXPECT_GE(r.state.q(0), th_min - 1e-12);
    EXPECT_LE(r.state.q(0), th_max + 1e-12);
    double plus = 0, minus = 0;
    RockerClosedForms(r.state.q(0), &plus, &minus);
    EXPECT_LT(std::min(AngleDistance(r.state.phi(0), plus), AngleDistance(r.state.phi(0), minus)),
              1e-8)
        << i;
    EXPECT_LE(testing::ResidualNorm<Rocker>(solver.params(), r.state.q, r.state.phi), 1e-10);
    if (i > 0) {
      const double step = std::remainder(r.state.phi(0) - records[i - 1].state.phi(0), 2 * kPi);
      EXPECT_LT(step, 0) << i;  // the crank turns clockwise throughout
      crank_turned += step;
    }
  }
  EXPECT_GE(reversals, 2);
  EXPECT_LT(crank_turned, -2 * kPi);
}

TEST(DeadPoint, FollowTangentIsRefusedThere) {
  CeresPositionSolver<Rocker> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(solver.MoveTo(Q(2.6), nullptr), Status::kSingular);
  Summary summary;
  EXPECT_EQ(solver.PassSingularity(Q(2.6), Crossing::kFollowTangent, &summary),
            Status::kSingular);
  EXPECT_NE(std::string(summary.reason).find("dead point"), std::string::npos);
  EXPECT_EQ(solver.PassSingularity(Q(2.6), Crossing::kReverseInput, &summary),
            Status::kConverged)
      << FormatSummary(summary);
  EXPECT_TRUE(summary.input_reversed);
}

TEST(HostileInput, AbsurdlyFarNonFiniteInputsAreRefusedAndNextCallWorks) {
  CeresPositionSolver<FourBar> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  for (double q : {1e6, -1e6, 1e300, -1e300, double(INFINITY), double(-INFINITY), double(NAN),
                   1.5707963267948966 + 1000.5}) {
    const State<FourBar> before = solver.state();
    Summary summary;
    EXPECT_EQ(solver.MoveTo(Q(q), &summary), Status::kInvalidInput) << q;
    EXPECT_GT(std::string(summary.reason).size(), 0u);
    EXPECT_EQ(solver.state().phi, before.phi);
    EXPECT_EQ(solver.state().q, before.q);
    ASSERT_EQ(solver.MoveTo(Q(0.5), &summary), Status::kConverged) << FormatSummary(summary);
    EXPECT_LT(AngleDistance(solver.state().phi, ClosedForm(solver.params(), 0.5, +1)), 1e-9);
  }
}

TEST(HostileInput, LongButSaneStepStaysOnBranch) {
  // 999 rad (159 turns) in one call: sub-steps limited by Options::max_predicted_angle keep
  // the branch; before that limit, one sub-step accepted a phi ~ 1e5 rad away.
  CeresPositionSolver<FourBar> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const double q = 1.5707963267948966 + 999;
  Summary summary;
  ASSERT_EQ(solver.MoveTo(Q(q), &summary), Status::kConverged) << FormatSummary(summary);
  EXPECT_LT(AngleDistance(solver.state().phi, ClosedForm(solver.params(), q, +1)), 1e-9);
  EXPECT_LT(solver.state().phi.cwiseAbs().maxCoeff(), 2 * kPi + 1);
}

}  // namespace
}  // namespace mechgen::position
