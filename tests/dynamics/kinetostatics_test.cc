// Kinetostatics (kinetostatics.h) on the handwritten massive four-bar. Oracles: the whole
// machine's momentum balance (ground reactions + weights = sum m a_G, with a_G by finite
// differences in time of the drawn centres of mass), the energy balance of a constant-speed
// cycle (the drive's work over a revolution = the damper's dissipation; 0 without), and a
// dead point as a status with figures.
#include <cmath>

#include <gtest/gtest.h>

#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/kinetostatics.h"

namespace {

namespace hw = mech::handwritten_fourbar_dynamics;
using mechgen::dynamics::Kinetostatics;
using mechgen::dynamics::KinetostaticsStatus;
using Vec1 = Eigen::Matrix<double, 1, 1>;
constexpr double kPi = 3.14159265358979323846;

// Centres of mass (crank, coupler, rocker) from the scene points at time t of the motion.
Eigen::Matrix<double, 2, 3> Centres(const hw::Params<double>& p, double q) {
  Eigen::Vector2d phi(0.5, 1.9);
  hw::SolvePositions(p, Vec1(q), &phi, hw::Model::kDefaultModes);
  Eigen::Matrix<double, 2, hw::Model::kNumScenePoints> r;
  hw::EvalScene(p, Vec1(q), phi, &r);
  Eigen::Matrix<double, 2, 3> g;
  for (int i = 0; i < 3; ++i) g.col(i) = 0.5 * (r.col(2 + 2 * i) + r.col(3 + 2 * i));
  return g;
}

TEST(Kinetostatics, GroundReactionsBalanceTheInertiaOfTheMachine) {
  hw::Params<double> p;
  auto motion = [](double t, Vec1* q, Vec1* qd, Vec1* qdd) {
    (*q)(0) = 0.4 + 3.0 * t + 0.5 * std::sin(2.0 * t);
    (*qd)(0) = 3.0 + std::cos(2.0 * t);
    (*qdd)(0) = -2.0 * std::sin(2.0 * t);
  };
  Kinetostatics<hw::Model> k(p);
  ASSERT_TRUE(k.Initialize(Vec1(0.4)));
  const double m[3] = {p.rho * p.a, p.rho * p.b, p.rho * p.c};
  int rows = 0;
  const auto summary = k.Cycle(motion, 0.0, 2.0, 40, [&](const auto& row) {
    EXPECT_EQ(row.status, KinetostaticsStatus::kOk);
    // a_G by central differences in time (h = 1e-4 s).
    const double h = 1e-4;
    Vec1 qa, qb, dummy;
    motion(row.t - h, &qa, &dummy, &dummy);
    motion(row.t + h, &qb, &dummy, &dummy);
    const auto a = ((Centres(p, qb(0)) - 2 * Centres(p, row.q(0)) + Centres(p, qa(0))) / (h * h))
                       .eval();
    Eigen::Vector2d ma = Eigen::Vector2d::Zero(), external = Eigen::Vector2d::Zero();
    for (int i = 0; i < 3; ++i) {
      ma += m[i] * a.col(i);
      external.y() -= m[i] * p.g;
    }
    const auto& R = row.statics.R;
    external += Eigen::Vector2d(R(0), R(1));  // ground on crank at A
    external -= Eigen::Vector2d(R(6), R(7));  // F_D is rocker on ground
    EXPECT_NEAR(external.x(), ma.x(), 1e-4 * (1 + ma.norm())) << "t = " << row.t;
    EXPECT_NEAR(external.y(), ma.y(), 1e-4 * (1 + ma.norm())) << "t = " << row.t;
    ++rows;
    return true;
  });
  EXPECT_EQ(rows, 41);
  EXPECT_TRUE(summary.IsSolutionUsable());
  EXPECT_GT(summary.max_reaction, 100.0);  // ~ weights of 15 kg plus inertia
}

TEST(Kinetostatics, DriveWorkOverARevolutionIsTheDissipation) {
  for (double damp : {0.0, 0.8}) {
    hw::Params<double> p;
    p.damp = damp;
    const double w = 4.0, period = 2 * kPi / w;
    Kinetostatics<hw::Model> k(p);
    ASSERT_TRUE(k.Initialize(Vec1(0.0)));
    const auto summary = k.Cycle(Kinetostatics<hw::Model>::ConstantSpeed(Vec1(0.0), Vec1(w)), 0.0,
                                 period, 4000, [](const auto&) { return true; });
    ASSERT_TRUE(summary.IsSolutionUsable());
    // Conservative forces do no net work over a cycle; the damper dissipates damp w^2 T.
    const double dissipated = damp * w * w * period;
    EXPECT_NEAR(summary.drive_work, dissipated, 1e-3 * summary.max_abs_drive * period)
        << "damp = " << damp;
  }
}

TEST(Kinetostatics, DeadPointIsAStatusWithFigures) {
  // Non-Grashof (d = 4, a = 2.5, b = 2, c = 3): the crank's range ends where coupler and
  // rocker align. Find that limit by bisection on solvability, then evaluate next to it.
  hw::Params<double> p;
  p.a = 2.5;
  p.b = 2.0;
  p.c = 3.0;
  auto closes = [&](double q) {
    Eigen::Vector2d phi(0.3, 1.8);
    return hw::SolvePositions(p, Vec1(q), &phi, hw::Model::kDefaultModes).status ==
           hw::SolveStatus::kConverged;
  };
  double lo = kPi / 2, hi = kPi;
  ASSERT_TRUE(closes(lo));
  ASSERT_FALSE(closes(hi));
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) (closes(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  Kinetostatics<hw::Model> k(p);
  ASSERT_TRUE(k.Initialize(Vec1(kPi / 2), Eigen::Vector2d(0.3, 1.8)));
  mechgen::dynamics::KinetostaticsRow<hw::Model> row;
  // Walk towards the limit (continuation) and evaluate at it.
  for (double q = kPi / 2; q < lo; q += 0.05) k.Evaluate(0, Vec1(q), Vec1(1.0), Vec1(0.0), &row);
  EXPECT_EQ(k.Evaluate(0, Vec1(lo), Vec1(1.0), Vec1(0.0), &row), KinetostaticsStatus::kSingular);
  EXPECT_GT(row.condition, 1e6);
  EXPECT_TRUE(std::isnan(row.statics.drive(0)));
  EXPECT_TRUE(std::isnan(row.statics.R(0)));
  EXPECT_GT(row.reaction_norm, 1e3);
  // Beyond it the loop does not close.
  EXPECT_EQ(k.Evaluate(0, Vec1(hi), Vec1(1.0), Vec1(0.0), &row),
            KinetostaticsStatus::kPositionFailed);
}

}  // namespace
