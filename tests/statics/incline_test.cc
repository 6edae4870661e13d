// The generated statics of tests/statics/models/incline.yaml: a block driven along an
// incline (a prismatic input: the drive is a force), its weight at an offset centre of
// mass, Coulomb friction at the slide, against
//   - the closed forms: pushing up takes W (sin a + mu cos a), letting down W (sin a -
//     mu cos a), self-locking (<= 0) exactly when tan a <= mu; N = W cos a, T_slide (the
//     actuator's force + the friction force) = W sin a, M_slide = cx W; the unloaded crank
//     and rod carry nothing;
//   - the Newton–Euler solution with the same friction load, and every link's equilibrium.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "free_body.h"
#include "incline.h"
#include "statics_test_util.h"

namespace {

namespace in = mech::incline;
using M = in::Model;
using P = M::ParamsT<double>;
using mechtest::fb::FreeBodySystem;
using mechtest::fb::Vec2;
using mechtest::statics::IndexOf;
using mechtest::statics::kDeg;
using mechtest::statics::Near;
using Phi = Eigen::Matrix<double, M::kNphi, 1>;
using Q1 = Eigen::Matrix<double, M::kNq, 1>;
using VecF = Eigen::Matrix<double, M::kNumFriction, 1>;

constexpr double kTol = 1e-10;  // forces ~50 N, a handful of operations

class InclineStatics : public ::testing::Test {
 protected:
  P p;
  int i_crank = -1, i_rod = -1, f_s = -1;

  void SetUp() override {
    ASSERT_STREQ(M::kQNames[0], "s_slide");
    i_crank = IndexOf(M::kPhiNames, "theta_crank");
    i_rod = IndexOf(M::kPhiNames, "theta_rod");
    f_s = IndexOf(M::kFrictionJoints, "slide");
    ASSERT_GE(i_crank, 0);
    ASSERT_GE(i_rod, 0);
    ASSERT_EQ(f_s, 0);
    ASSERT_TRUE(M::kFrictionPrismatic[0]);
  }
  bool Eval(double s, in::Statics<double>* st, const VecF* f, Phi* phi) const {
    if (!mechtest::statics::SolveAt<M>(p, s, phi)) return false;
    in::Coefficients<double> c;
    const Q1 q = Q1::Constant(s);
    in::EvalCoefficients(p, q, *phi, &c);
    in::EvalStatics(p, q, *phi, c, st, f);
    return true;
  }
  // The contract's iteration: f = -mu |N| sign(dir K_rel), K_rel = ds/ds = 1.
  double Iterate(double s, double dir, in::Statics<double>* st) const {
    Phi phi;
    VecF f = VecF::Zero();
    for (int it = 0; it < 100; ++it) {
      EXPECT_TRUE(Eval(s, st, &f, &phi));
      f(0) = -st->gain(0) * st->normal(0) * (dir * st->K_rel(0, 0) > 0 ? 1.0 : -1.0);
    }
    EXPECT_TRUE(Eval(s, st, &f, &phi));
    return f(0);
  }
  double R(const in::Statics<double>& st, const char* name) const {
    const int i = IndexOf(M::kReactionNames, name);
    EXPECT_GE(i, 0) << name;
    return i >= 0 ? st.R(i) : NAN;
  }
  void CheckClosedForms();
  void CheckNewtonEuler(double f_slide);
};

void InclineStatics::CheckClosedForms() {
  for (double alpha_deg : {5.0, 10.0, 16.0, 17.5, 30.0, 45.0, 60.0}) {
    p.alpha = alpha_deg * kDeg;
    const double W = p.m * p.g, sa = std::sin(p.alpha), ca = std::cos(p.alpha);
    for (double s : {0.42, 0.5, 0.58}) {
      in::Statics<double> up, down;
      const double f_up = Iterate(s, +1, &up);
      const double f_down = Iterate(s, -1, &down);
      const std::string at = std::to_string(alpha_deg) + " deg, s = " + std::to_string(s);
      EXPECT_TRUE(Near(up.drive(0), W * (sa + p.mu * ca), kTol, W, "push up")) << at;
      EXPECT_TRUE(Near(down.drive(0), W * (sa - p.mu * ca), kTol, W, "let down")) << at;
      EXPECT_EQ(down.drive(0) <= 0, std::tan(p.alpha) <= p.mu) << "self-locking, " << at;
      EXPECT_TRUE(Near(f_up, -p.mu * W * ca, kTol, W, "friction force up")) << at;
      EXPECT_TRUE(Near(f_down, p.mu * W * ca, kTol, W, "friction force down")) << at;
      for (const in::Statics<double>* st : {&up, &down}) {
        EXPECT_TRUE(Near(R(*st, "N_slide"), W * ca, kTol, W, "N_slide")) << at;
        EXPECT_TRUE(Near(R(*st, "T_slide"), W * sa, kTol, W, "T_slide = drive + friction")) << at;
        EXPECT_TRUE(Near(R(*st, "M_slide"), p.cx * W, kTol, W, "M_slide")) << at;
        for (const char* n : {"F_O_x", "F_O_y", "F_B_x", "F_B_y", "F_C_x", "F_C_y"}) {
          EXPECT_TRUE(Near(R(*st, n), 0.0, kTol, W, n)) << "unloaded linkage, " << at;
        }
        EXPECT_TRUE(Near(st->normal(0), W * ca, kTol, W, "normal")) << at;
      }
    }
  }
}

// With a given friction force, against the Newton–Euler solution (the slide driven) and
// every link's equilibrium.
void InclineStatics::CheckNewtonEuler(double f_slide) {
  FreeBodySystem fb;
  const int ground = fb.AddLink("ground", true), crank = fb.AddLink("crank"),
            rod = fb.AddLink("rod"), block = fb.AddLink("block");
  const int pO = fb.AddPoint(Vec2(0, 0)), pB = fb.AddPoint(), pC = fb.AddPoint(), pG = fb.AddPoint();
  const int jO = fb.AddRevolute("O", ground, crank, pO);
  const int jB = fb.AddRevolute("B", crank, rod, pB);
  const int jC = fb.AddRevolute("C", rod, block, pC);
  const int jS = fb.AddPrismatic("slide", ground, block, pC, p.alpha, /*driven=*/true);
  fb.AddWeight(block, pG, p.m, Vec2(0, -p.g));
  const VecF f = VecF::Constant(f_slide);
  for (int k = 0; k <= 40; ++k) {
    const double s = 0.4 + 0.2 * k / 40;
    Phi phi;
    in::Statics<double> st;
    ASSERT_TRUE(Eval(s, &st, &f, &phi));
    const Vec2 u(std::cos(p.alpha), std::sin(p.alpha));
    fb.SetPoint(pB, p.a * Vec2(std::cos(phi(i_crank)), std::sin(phi(i_crank))));
    fb.SetPoint(pC, s * u);
    fb.SetPoint(pG, s * u + Vec2(p.cx, p.cy));
    fb.SetFriction(jS, f(0));
    Eigen::VectorXd x;
    ASSERT_TRUE(fb.Solve(&x));
    Eigen::VectorXd g(fb.num_unknowns());
    const std::pair<int, const char*> pins[] = {{jO, "O"}, {jB, "B"}, {jC, "C"}};
    for (const auto& [j, n] : pins) {
      g(fb.unknown_index(j)) = R(st, (std::string("F_") + n + "_x").c_str());
      g(fb.unknown_index(j) + 1) = R(st, (std::string("F_") + n + "_y").c_str());
    }
    g(fb.unknown_index(jS)) = R(st, "N_slide");
    g(fb.unknown_index(jS) + 1) = R(st, "M_slide");
    g(fb.unknown_index(jS) + 2) = st.drive(0);
    const double scale = x.lpNorm<Eigen::Infinity>();
    for (int i = 0; i < x.size(); ++i) {
      EXPECT_TRUE(Near(g(i), x(i), kTol, scale, "unknown " + std::to_string(i))) << "s = " << s;
    }
    EXPECT_TRUE(Near(R(st, "T_slide"), fb.PrismaticT(jS, x), kTol, scale, "T_slide")) << s;
    EXPECT_LT(fb.Residual(g).lpNorm<Eigen::Infinity>(), kTol * scale) << "s = " << s;
  }
}

// Without friction (mu = 0): the drive is W sin a both ways.
TEST_F(InclineStatics, FrictionlessClosedForms) {
  p.mu = 0;
  CheckClosedForms();
}

TEST_F(InclineStatics, FrictionlessAgainstNewtonEuler) { CheckNewtonEuler(0.0); }

// With friction (mu = 0.3) at several inclines, both ways.
TEST_F(InclineStatics, UpDownAndSelfLockingClosedForms) { CheckClosedForms(); }

TEST_F(InclineStatics, AgainstNewtonEulerWithFriction) { CheckNewtonEuler(-7.5); }  // f = -7.5 N

}  // namespace
