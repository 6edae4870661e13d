// The free-body solver (free_body.h) on hand cases with closed-form answers: a lever, a
// two-bar truss of two-force members, a slider-crank's crank torque from a piston force,
// a block on an incline with Coulomb friction (up, down, self-locking when tan a <= mu), a
// lever on a pin with the friction circle, and a dead point it must report as singular.
#include <gtest/gtest.h>

#include <cmath>

#include "free_body.h"
#include "slider_crank_fb.h"

namespace {

using mechtest::fb::Cross;
using mechtest::fb::FreeBodySystem;
using mechtest::fb::Vec2;

constexpr double kDeg = M_PI / 180;
// Every system below has O(1..100) entries and a handful of unknowns: LU rounding is
// ~1e-14 relative; 1e-11 is far above that and far below any wrong term.
constexpr double kTol = 1e-11;

// A bar O-B pivoted on the ground at O, driven at O, a weight W hanging at B.
TEST(FreeBody, LeverTorqueAndPinReaction) {
  const double L = 2.0, W = 30.0;
  for (double beta : {-70.0, -10.0, 0.0, 35.0, 89.0, 140.0}) {
    FreeBodySystem s;
    const int ground = s.AddLink("ground", true), bar = s.AddLink("bar");
    const int O = s.AddPoint(Vec2(0, 0));
    const int B = s.AddPoint(L * Vec2(std::cos(beta * kDeg), std::sin(beta * kDeg)));
    const int jO = s.AddRevolute("O", ground, bar, O, /*driven=*/true);
    s.AddForce(bar, B, Vec2(0, -W));
    Eigen::VectorXd x;
    ASSERT_TRUE(s.Solve(&x));
    EXPECT_NEAR(s.Drive(jO, x), W * L * std::cos(beta * kDeg), kTol) << beta;
    EXPECT_NEAR(s.RevoluteForce(jO, x).x(), 0.0, kTol);
    EXPECT_NEAR(s.RevoluteForce(jO, x).y(), W, kTol);
    EXPECT_LT(s.Residual(x).lpNorm<Eigen::Infinity>(), kTol);
  }
}

// Two bars pinned to the ground at A = (0, 0) and C = (2, 0), pinned together at B = (1, 1),
// a load P = (0, -10) on bar 1 at B. Both are two-force members, each in compression
// P / (2 sin 45 deg) = 10 / sqrt 2 (method of joints).
TEST(FreeBody, TrussOfTwoForceMembers) {
  FreeBodySystem s;
  const int ground = s.AddLink("ground", true), bar1 = s.AddLink("bar1"), bar2 = s.AddLink("bar2");
  const int A = s.AddPoint(Vec2(0, 0)), B = s.AddPoint(Vec2(1, 1)), C = s.AddPoint(Vec2(2, 0));
  const int jA = s.AddRevolute("A", ground, bar1, A);
  const int jB = s.AddRevolute("B", bar1, bar2, B);
  const int jC = s.AddRevolute("C", ground, bar2, C);
  s.AddForce(bar1, B, Vec2(0, -10));
  ASSERT_EQ(s.num_equations(), 6);
  ASSERT_EQ(s.num_unknowns(), 6);
  Eigen::VectorXd x;
  ASSERT_TRUE(s.Solve(&x));
  EXPECT_NEAR(s.RevoluteForce(jA, x).x(), 5.0, kTol);
  EXPECT_NEAR(s.RevoluteForce(jA, x).y(), 5.0, kTol);
  EXPECT_NEAR(s.RevoluteForce(jB, x).x(), 5.0, kTol);  // bar1 on bar2: pushes bar2 toward C
  EXPECT_NEAR(s.RevoluteForce(jB, x).y(), -5.0, kTol);
  EXPECT_NEAR(s.RevoluteForce(jC, x).x(), -5.0, kTol);
  EXPECT_NEAR(s.RevoluteForce(jC, x).y(), 5.0, kTol);
  EXPECT_NEAR(s.RevoluteForce(jB, x).norm(), 10 / std::sqrt(2.0), kTol);
}

// A centred slider-crank, crank OB = a driven at O, rod BC = b, slider C on y = 0, a
// piston force F along x on the slider. Virtual work: tau dq + F ds = 0, so the crank
// torque is tau = -F K_s with K_s = ds/dq = -a sin q - a^2 sin q cos q / sqrt(b^2 - a^2 sin^2 q)
// (Paul); the rod is a two-force member (F_B along BC); N balances the rod's vertical push.
struct SliderCrankFb {
  FreeBodySystem s;
  int crank, rod, piston, jO, jB, jC, jS, pB, pC, load;
  SliderCrankFb() {
    const int ground = s.AddLink("ground", true);
    crank = s.AddLink("crank");
    rod = s.AddLink("rod");
    piston = s.AddLink("piston");
    const int pO = s.AddPoint(Vec2(0, 0));
    pB = s.AddPoint();
    pC = s.AddPoint();
    jO = s.AddRevolute("O", ground, crank, pO, /*driven=*/true);
    jB = s.AddRevolute("B", crank, rod, pB);
    jC = s.AddRevolute("C", rod, piston, pC);
    jS = s.AddPrismatic("slide", ground, piston, pC, 0.0);
    load = s.AddForce(piston, pC);
  }
  void Place(double a, double b, double q) {
    const Vec2 B(a * std::cos(q), a * std::sin(q));
    const double w = std::sqrt(b * b - B.y() * B.y());
    s.SetPoint(pB, B);
    s.SetPoint(pC, Vec2(B.x() + w, 0));
  }
};

TEST(FreeBody, SliderCrankCrankTorqueFromPistonForce) {
  const double a = 0.1, b = 0.35, F = -1000;
  SliderCrankFb m;
  m.s.SetForce(m.load, Vec2(F, 0));
  ASSERT_EQ(m.s.num_equations(), m.s.num_unknowns());
  for (int k = 1; k < 360; ++k) {
    if (k == 180) continue;
    const double q = k * kDeg;
    m.Place(a, b, q);
    Eigen::VectorXd x;
    ASSERT_TRUE(m.s.Solve(&x)) << k;
    const double sq = std::sin(q), cq = std::cos(q);
    const double Ks = -a * sq - a * a * sq * cq / std::sqrt(b * b - a * a * sq * sq);
    EXPECT_NEAR(m.s.Drive(m.jO, x), -F * Ks, kTol * std::abs(F)) << k;
    const Vec2 FB = m.s.RevoluteForce(m.jB, x);
    const Vec2 BC = m.s.point(m.pC) - m.s.point(m.pB);
    EXPECT_NEAR(Cross(BC, FB), 0.0, kTol * std::abs(F)) << "two-force member, " << k;
    EXPECT_NEAR((m.s.RevoluteForce(m.jC, x) - FB).norm(), 0.0, kTol * std::abs(F));
    // The piston: rod force + N + F = 0, no moment (all forces through C).
    EXPECT_NEAR(m.s.PrismaticN(m.jS, x), -FB.y(), kTol * std::abs(F));
    EXPECT_NEAR(m.s.PrismaticM(m.jS, x), 0.0, kTol * std::abs(F));
  }
}

// The piston driven instead (a prismatic input) against a torque on the crank: at the dead
// centres (q = 0, 180 deg) no piston force holds a torque: the system is singular.
TEST(FreeBody, DeadPointIsReportedSingular) {
  const double a = 0.1, b = 0.35;
  FreeBodySystem s;
  const int ground = s.AddLink("ground", true), crank = s.AddLink("crank"), rod = s.AddLink("rod"),
            piston = s.AddLink("piston");
  const int pO = s.AddPoint(Vec2(0, 0)), pB = s.AddPoint(), pC = s.AddPoint();
  s.AddRevolute("O", ground, crank, pO);
  s.AddRevolute("B", crank, rod, pB);
  s.AddRevolute("C", rod, piston, pC);
  const int jS = s.AddPrismatic("slide", ground, piston, pC, 0.0, /*driven=*/true);
  s.AddTorque(crank, 10.0);
  // s.num_unknowns(): 3 * 2 + 3 = 9 = 3 moving links * 3.
  Eigen::VectorXd x;
  for (double q : {0.0, M_PI}) {
    const Vec2 B(a * std::cos(q), a * std::sin(q));
    s.SetPoint(pB, B);
    s.SetPoint(pC, Vec2(B.x() + b, 0));
    EXPECT_FALSE(s.Solve(&x)) << q;
  }
  const double q = 60 * kDeg;
  const Vec2 B(a * std::cos(q), a * std::sin(q));
  s.SetPoint(pB, B);
  s.SetPoint(pC, Vec2(B.x() + std::sqrt(b * b - B.y() * B.y()), 0));
  ASSERT_TRUE(s.Solve(&x));
  // Virtual work: T dq + F_act ds = 0 with the crank torque T = 10.
  const double sq = std::sin(q), cq = std::cos(q);
  const double Ks = -a * sq - a * a * sq * cq / std::sqrt(b * b - a * a * sq * sq);
  EXPECT_NEAR(s.Drive(jS, x), -10.0 / Ks, kTol * 100);
  EXPECT_NEAR(s.PrismaticT(jS, x), s.Drive(jS, x), 0.0);
}

// A block of weight W on a guide inclined at alpha, pushed along the guide by the actuator
// of the prismatic joint, Coulomb friction mu on the normal force W cos alpha: the push to
// move it up is W (sin a + mu cos a), down W (sin a - mu cos a) (<= 0, a pull... i.e. it
// must be pushed down: self-locking, when tan a <= mu).
TEST(FreeBody, InclineWithCoulombFriction) {
  const double W = 50.0, mu = 0.3;
  for (double alpha_deg : {5.0, 10.0, 16.699, 30.0, 45.0, 60.0}) {
    const double alpha = alpha_deg * kDeg;
    FreeBodySystem s;
    const int ground = s.AddLink("ground", true), block = s.AddLink("block");
    const int P = s.AddPoint(Vec2(0.7, 0.7 * std::tan(alpha)));
    const int G = s.AddPoint(Vec2(0.7, 0.7 * std::tan(alpha)) + 0.05 * Vec2(-std::sin(alpha), std::cos(alpha)));
    const int j = s.AddPrismatic("slide", ground, block, P, alpha, /*driven=*/true);
    s.AddWeight(block, G, W / 9.81, Vec2(0, -9.81));
    Eigen::VectorXd x;
    ASSERT_TRUE(s.SolveWithFriction({{j, mu, +1}}, &x));
    const double up = s.Drive(j, x);
    EXPECT_NEAR(up, W * (std::sin(alpha) + mu * std::cos(alpha)), kTol * W) << alpha_deg;
    EXPECT_NEAR(s.PrismaticN(j, x), W * std::cos(alpha), kTol * W);
    EXPECT_NEAR(s.friction(j), -mu * W * std::cos(alpha), kTol * W);
    // T_J: the actuator's force plus the friction force = the weight's component, W sin a.
    EXPECT_NEAR(s.PrismaticT(j, x), W * std::sin(alpha), kTol * W);
    ASSERT_TRUE(s.SolveWithFriction({{j, mu, -1}}, &x));
    const double down = s.Drive(j, x);
    EXPECT_NEAR(down, W * (std::sin(alpha) - mu * std::cos(alpha)), kTol * W) << alpha_deg;
    const bool self_locking = std::tan(alpha) <= mu;
    EXPECT_EQ(down <= 1e-9, self_locking) << alpha_deg << " deg, down push " << down;
  }
}

// A lever pivoted on a pin of radius r (coefficient mu) at O, driven at O, with a weight W
// at B = (d, 0) and a horizontal force H at C = (0, h). The load torque about O is
// W d + H h; the pin reaction has magnitude sqrt(W^2 + H^2), so the friction circle (radius
// mu r) adds mu r sqrt(W^2 + H^2) against the rotation.
TEST(FreeBody, PinWithFrictionCircle) {
  const double W = 200, H = 150, d = 0.4, h = 0.25, mu = 0.25, r = 0.02;
  FreeBodySystem s;
  const int ground = s.AddLink("ground", true), lever = s.AddLink("lever");
  const int O = s.AddPoint(Vec2(0, 0)), B = s.AddPoint(Vec2(d, 0)), C = s.AddPoint(Vec2(0, h));
  const int j = s.AddRevolute("O", ground, lever, O, /*driven=*/true);
  s.AddForce(lever, B, Vec2(0, -W));
  s.AddForce(lever, C, Vec2(H, 0));
  const double R = std::hypot(W, H);
  Eigen::VectorXd x;
  for (double sign : {+1.0, -1.0}) {
    ASSERT_TRUE(s.SolveWithFriction({{j, mu * r, sign}}, &x));
    EXPECT_NEAR(s.Drive(j, x), W * d + H * h + sign * mu * r * R, kTol * W) << sign;
    EXPECT_NEAR(s.Normal(j, x), R, kTol * W);
    // The reaction's line passes at distance mu r from O (tangent to the friction circle):
    // its moment about O is the friction torque.
    EXPECT_NEAR(std::abs(s.friction(j)), mu * r * R, kTol * W);
  }
}

// Springs: tension and energy from their definitions; the force acts along the line.
TEST(FreeBody, SpringHoldsALever) {
  // Lever O-B (length 1) at angle beta, spring from the ground point E = (0, 1) to B,
  // k = 100, L0 = 0.5, preload 3: the torque at O balances the spring's moment.
  const double k = 100, L0 = 0.5, F0 = 3;
  for (double beta_deg : {-30.0, 0.0, 20.0, 75.0}) {
    const double beta = beta_deg * kDeg;
    FreeBodySystem s;
    const int ground = s.AddLink("ground", true), lever = s.AddLink("lever");
    const int O = s.AddPoint(Vec2(0, 0)), E = s.AddPoint(Vec2(0, 1));
    const Vec2 rB(std::cos(beta), std::sin(beta));
    const int B = s.AddPoint(rB);
    const int j = s.AddRevolute("O", ground, lever, O, true);
    const int sp = s.AddSpring(ground, E, lever, B, k, L0, F0);
    const double l = (rB - Vec2(0, 1)).norm();
    EXPECT_NEAR(s.SpringLength(sp), l, 1e-15);
    EXPECT_NEAR(s.SpringTension(sp), F0 + k * (l - L0), 1e-12);
    EXPECT_NEAR(s.SpringEnergy(), F0 * (l - L0) + 0.5 * k * (l - L0) * (l - L0), 1e-12);
    Eigen::VectorXd x;
    ASSERT_TRUE(s.Solve(&x));
    const Vec2 on_B = s.SpringTension(sp) * (Vec2(0, 1) - rB) / l;
    EXPECT_NEAR(s.Drive(j, x), -Cross(rB, on_B), kTol * 100) << beta_deg;
    // Virtual work: tau = dV/dbeta (the actuator holds the spring), by central differences
    // of the energy: l(beta)^2 = 2 - 2 sin beta.
    auto V = [&](double bb) {
      const double ll = std::sqrt(2 - 2 * std::sin(bb));
      return F0 * (ll - L0) + 0.5 * k * (ll - L0) * (ll - L0);
    };
    const double hh = 1e-5;
    EXPECT_NEAR(s.Drive(j, x), (V(beta + hh) - V(beta - hh)) / (2 * hh), 1e-6 * 100);
  }
}

// The dead zone of a slider-crank with friction at the crank bearing O only (the oracle of
// slider_crank_friction_test.cc's dead-zone test, checked here on the solver alone): the
// piston force F (along -x) drives, the crank's actuator brakes; the rod is a two-force
// member, so the piston cannot turn the crank where the rod's line passes inside O's
// friction circle, a |sin(q - th_rod)| < mu r. Inside, the iterated actuator torque has the
// sign of the motion (the actuator must push); outside, the opposite.
TEST(FreeBody, SliderCrankDeadZoneIsTheFrictionCircle) {
  const double a = 0.1, b = 0.35, F = 1000, mu = 0.2, r = 0.03;
  mechtest::fb::SliderCrankFb m(a, b);
  m.s.SetForce(m.slider_force, Vec2(-F, 0));
  int dead = 0;
  for (int k = 0; k < 3600; ++k) {
    const double q = (k + 0.25) * 0.1 * kDeg;
    const double th = mechtest::fb::SliderRodAngle(a, b, q);
    m.Place(q, th, mechtest::fb::SliderS(a, b, q));
    const double h = a * std::abs(std::sin(q - th)) - mu * r;
    if (std::abs(h) < 1e-6) continue;
    const double qdot = mechtest::fb::SliderKs(a, b, q) > 0 ? -1.0 : 1.0;  // sdot < 0
    Eigen::VectorXd x;
    ASSERT_TRUE(m.s.SolveWithFriction({{m.jO, mu * r, qdot}}, &x)) << k;
    EXPECT_EQ(m.s.Drive(m.jO, x) * qdot > 0, h < 0) << "q = " << q / kDeg << " deg";
    // The friction torque is mu r times the rod force (the bearing carries it all).
    EXPECT_NEAR(std::abs(m.s.friction(m.jO)), mu * r * m.s.RevoluteForce(m.jB, x).norm(), 1e-9 * F);
    dead += h < 0;
  }
  EXPECT_GT(dead, 20);
}

}  // namespace
