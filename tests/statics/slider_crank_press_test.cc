// The generated statics of models/slider_crank_press.yaml (a centred slider-crank, the
// press load F = -P0 h / (h + a + b - s) along x on the ram, the links' weights) over a full
// crank turn, against the Newton–Euler free-body solution, the equilibrium of each link,
// virtual work by central differences, Paul's crank torque T = F K_s (+ the weights'
// share, by hand) and the toggle at top dead centre (q = 0): with no weight the drive goes
// to zero and the mechanical advantage |F| / |T| = 1 / |K_s| grows without bound.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "slider_crank_fb.h"
#include "slider_crank_press.h"
#include "statics_test_util.h"

namespace {

namespace sp = mech::slider_crank_press;
using M = sp::Model;
using P = M::ParamsT<double>;
using mechtest::fb::SliderCrankFb;
using mechtest::fb::SliderKs;
using mechtest::fb::SliderRodAngle;
using mechtest::fb::SliderS;
using mechtest::fb::Vec2;
using mechtest::statics::IndexOf;
using mechtest::statics::kDeg;
using mechtest::statics::Near;
using Phi = Eigen::Matrix<double, M::kNphi, 1>;
using Q1 = Eigen::Matrix<double, M::kNq, 1>;

constexpr int kSamples = 360;
// Forces up to ~2000 N (P0) from O(0.1) geometry; rounding ~1e-14 relative. See
// fourbar_loaded_test.cc for the reasoning behind the tolerances.
constexpr double kTol = 1e-9;
constexpr double kH = 1e-5;
constexpr double kFdTol = 1e-6;

class SliderCrankPressStatics : public ::testing::Test {
 protected:
  P p;
  int i_rod = -1, i_s = -1;

  void SetUp() override {
    i_rod = IndexOf(M::kPhiNames, "theta_rod");
    i_s = IndexOf(M::kPhiNames, "s_slide");
    ASSERT_GE(i_rod, 0);
    ASSERT_GE(i_s, 0);
  }
  double Press(double s) const { return -p.P0 * p.h / (p.h + p.a + p.b - s); }

  bool Eval(double q, Phi* phi, sp::Statics<double>* st) const {
    if (!mechtest::statics::SolveAt<M>(p, q, phi)) return false;
    sp::Coefficients<double> c;
    const Q1 qv = Q1::Constant(q);
    sp::EvalCoefficients(p, qv, *phi, &c);
    sp::EvalStatics(p, qv, *phi, c, st);
    sp::EvalStiffness(p, qv, *phi, c, st);  // d2V/dq2 and the stiffness
    return true;
  }
  SliderCrankFb MakeFb() const { return SliderCrankFb(p.a, p.b, p.g, p.m1, p.m2, p.m3); }
  void Place(SliderCrankFb* fb, double q, const Phi& phi) const {
    fb->Place(q, phi(i_rod), phi(i_s));
    fb->s.SetForce(fb->slider_force, Vec2(Press(phi(i_s)), 0));
  }
  int R(const std::string& name) const {
    const int i = IndexOf(M::kReactionNames, name);
    EXPECT_GE(i, 0) << name;
    return i;
  }
  Eigen::VectorXd Unknowns(SliderCrankFb& fb, const sp::Statics<double>& st) const {
    Eigen::VectorXd x(fb.s.num_unknowns());
    const std::pair<int, const char*> pins[] = {{fb.jO, "O"}, {fb.jB, "B"}, {fb.jC, "C"}};
    for (const auto& [j, name] : pins) {
      x(fb.s.unknown_index(j)) = st.R(R(std::string("F_") + name + "_x"));
      x(fb.s.unknown_index(j) + 1) = st.R(R(std::string("F_") + name + "_y"));
    }
    x(fb.s.unknown_index(fb.jO) + 2) = st.drive(0);
    x(fb.s.unknown_index(fb.jS)) = st.R(R("N_slide"));
    x(fb.s.unknown_index(fb.jS) + 1) = st.R(R("M_slide"));
    return x;
  }
  double Potential(const SliderCrankFb& fb) const {
    return p.g * (p.m1 * fb.s.point(fb.pG1).y() + p.m2 * fb.s.point(fb.pG2).y() +
                  p.m3 * fb.s.point(fb.pC).y());
  }
};

TEST_F(SliderCrankPressStatics, DeclaresPinAndSlideReactions) {
  ASSERT_EQ(M::kNumReactions, 9);
  for (const char* n : {"F_O_x", "F_O_y", "F_B_x", "F_B_y", "F_C_x", "F_C_y", "N_slide",
                        "T_slide", "M_slide"}) {
    EXPECT_GE(IndexOf(M::kReactionNames, n), 0) << n;
  }
}

// The generated positions are the closed form's (the tests below place points from them).
TEST_F(SliderCrankPressStatics, PositionsAreTheClosedForm) {
  for (int k = 0; k < kSamples; ++k) {
    const double q = k * kDeg;
    Phi phi;
    ASSERT_TRUE(mechtest::statics::SolveAt<M>(p, q, &phi));
    EXPECT_NEAR(phi(i_s), SliderS(p.a, p.b, q), 1e-13) << k;
    EXPECT_NEAR(std::remainder(phi(i_rod) - SliderRodAngle(p.a, p.b, q), 2 * M_PI), 0, 1e-13) << k;
    SliderCrankFb fb = MakeFb();
    Place(&fb, q, phi);
    Eigen::Matrix<double, 2, M::kNumScenePoints> r;
    sp::EvalScene(p, Q1(Q1::Constant(q)), phi, &r);
    const std::pair<const char*, int> points[] = {{"crank.B", fb.pB}, {"rod.C", fb.pC}, {"ram.C", fb.pC}};
    for (const auto& [name, id] : points) {
      const int i = IndexOf(M::kScenePointNames, name);
      ASSERT_GE(i, 0) << name;
      EXPECT_LT((r.col(i) - fb.s.point(id)).norm(), 1e-12) << name << " at q = " << k << " deg";
    }
  }
}

// (a) reactions and drive = the Newton–Euler solution; T_slide = 0 (no actuator, no
// friction at the slide); (b) every moving link in equilibrium with the generated values.
TEST_F(SliderCrankPressStatics, ReactionsDriveAndEquilibriumAgainstNewtonEuler) {
  SliderCrankFb fb = MakeFb();
  const char* rows[] = {"crank Fx", "crank Fy", "crank M", "rod Fx", "rod Fy", "rod M",
                        "ram Fx", "ram Fy", "ram M"};
  const char* unknowns[] = {"F_O_x", "F_O_y", "drive", "F_B_x", "F_B_y", "F_C_x", "F_C_y",
                            "N_slide", "M_slide"};
  for (int k = 0; k < kSamples; ++k) {
    const double q = k * kDeg;
    Phi phi;
    sp::Statics<double> st;
    ASSERT_TRUE(Eval(q, &phi, &st)) << k;
    Place(&fb, q, phi);
    Eigen::VectorXd x;
    ASSERT_TRUE(fb.s.Solve(&x)) << k;
    const Eigen::VectorXd g = Unknowns(fb, st);
    const double scale = x.lpNorm<Eigen::Infinity>();
    for (int i = 0; i < x.size(); ++i) {
      EXPECT_TRUE(Near(g(i), x(i), kTol, scale, unknowns[i])) << "q = " << k << " deg";
    }
    EXPECT_TRUE(Near(st.R(R("T_slide")), 0.0, kTol, scale, "T_slide")) << "q = " << k << " deg";
    EXPECT_TRUE(Near(st.drive(0), -st.Q(0), kTol, scale, "drive = -Q")) << k;
    const Eigen::VectorXd res = fb.s.Residual(g);
    for (int i = 0; i < res.size(); ++i) {
      EXPECT_TRUE(Near(res(i), 0.0, kTol, scale, rows[i])) << "q = " << k << " deg";
    }
  }
}

// (c) Q = the press load's work over a small motion minus the change of the weights'
// potential; V and d2V/dq2 against m g y and its differences; the stiffness
// -dQ/dq (the load depends on s) against differences of the Newton–Euler drive.
TEST_F(SliderCrankPressStatics, VirtualWorkPotentialAndStiffness) {
  SliderCrankFb fb = MakeFb();
  auto at = [&](double q, Phi* phi) {
    EXPECT_TRUE(mechtest::statics::SolveAt<M>(p, q, phi));
    Place(&fb, q, *phi);
  };
  auto V = [&](double q) {
    Phi phi;
    at(q, &phi);
    return Potential(fb);
  };
  auto ne_drive = [&](double q) {
    Phi phi;
    at(q, &phi);
    Eigen::VectorXd x;
    EXPECT_TRUE(fb.s.Solve(&x));
    return fb.s.Drive(fb.jO, x);
  };
  for (int k = 0; k < kSamples; ++k) {
    const double q = k * kDeg;
    Phi phi, phi_p, phi_m;
    sp::Statics<double> st;
    ASSERT_TRUE(Eval(q, &phi, &st)) << k;
    at(q + kH, &phi_p);
    at(q - kH, &phi_m);
    const double work = Press(phi(i_s)) * (phi_p(i_s) - phi_m(i_s)) / (2 * kH);
    const double dV = (V(q + kH) - V(q - kH)) / (2 * kH);
    EXPECT_TRUE(Near(st.Q(0), work - dV, kFdTol, 2000, "Q")) << "q = " << k << " deg";
    EXPECT_TRUE(Near(st.V, V(q), kTol, 10, "V = sum m g y")) << "q = " << k << " deg";
    const double h2 = 1e-4;
    const double d2V = (V(q + h2) - 2 * V(q) + V(q - h2)) / (h2 * h2);
    EXPECT_TRUE(Near(st.d2V_dq2(0, 0), d2V, 1e-4, 10, "d2V/dq2")) << "q = " << k << " deg";
    const double stiff = (ne_drive(q + kH) - ne_drive(q - kH)) / (2 * kH);
    EXPECT_TRUE(Near(st.stiffness(0, 0), stiff, kFdTol, 1e4, "stiffness")) << "q = " << k << " deg";
  }
}

// dV/dq against central differences of m g y.
// DISABLED (wt/statoracle report, issue 14, main at 71979df): mechgen's output for this
// model is not reproducible: in some runs of `mechgen generate` the generated dV_dq reads
// `Q_0 + ...` (= Q + dV/dq) instead of dV/dq (generator/symbolic/statics.cc: along_motion(items,
// conservative, j) reads `conservative` past its end once the actuators' items are appended).
// Enable when the generator is fixed.
TEST_F(SliderCrankPressStatics, DISABLED_PotentialFirstDerivativeByFiniteDifferences) {
  SliderCrankFb fb = MakeFb();
  auto V = [&](double q) {
    Phi phi;
    EXPECT_TRUE(mechtest::statics::SolveAt<M>(p, q, &phi));
    Place(&fb, q, phi);
    return Potential(fb);
  };
  for (int k = 0; k < kSamples; ++k) {
    const double q = k * kDeg;
    Phi phi;
    sp::Statics<double> st;
    ASSERT_TRUE(Eval(q, &phi, &st)) << k;
    const double dV = (V(q + kH) - V(q - kH)) / (2 * kH);
    EXPECT_TRUE(Near(st.dV_dq(0), dV, kFdTol, 10, "dV/dq")) << "q = " << k << " deg";
  }
}

// (d) Paul: the crank torque that holds a piston force F is T = -F K_s (virtual work,
// K_s = ds/dq in closed form), plus the weights' share dV/dq = g a cos q (m1 + m2) / 2
// (crank's centre at a/2, the rod's at (y_B + 0) / 2, the ram's at y = 0).
TEST_F(SliderCrankPressStatics, CrankTorqueIsFKsPlusWeights) {
  for (int k = 0; k < kSamples; ++k) {
    const double q = k * kDeg;
    Phi phi;
    sp::Statics<double> st;
    ASSERT_TRUE(Eval(q, &phi, &st)) << k;
    const double F = Press(SliderS(p.a, p.b, q));
    const double T = -F * SliderKs(p.a, p.b, q) + p.g * p.a * std::cos(q) * (p.m1 + p.m2) / 2;
    EXPECT_TRUE(Near(st.drive(0), T, kTol, p.P0, "crank torque")) << "q = " << k << " deg";
  }
}

// (d) The toggle: without weights (g = 0) the crank torque at top dead centre is zero and
// the mechanical advantage |F| / |T| = 1 / |K_s| grows without bound as q -> 0, like
// 1 / (a (1 + a / b) |q|).
TEST_F(SliderCrankPressStatics, ToggleMechanicalAdvantageGrowsWithoutBound) {
  p.g = 0;
  Phi phi;
  sp::Statics<double> st;
  ASSERT_TRUE(Eval(0.0, &phi, &st));
  EXPECT_NEAR(st.drive(0), 0.0, 1e-12 * p.P0) << "crank torque at the toggle";
  EXPECT_TRUE(st.R.allFinite());
  EXPECT_NEAR(st.R(R("F_O_x")), -Press(p.a + p.b), kTol * p.P0) << "the load goes to the bearing";
  double previous = 0;
  for (double deg : {20.0, 10.0, 3.0, 1.0, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001}) {
    for (double sign : {+1.0, -1.0}) {
      const double q = sign * deg * kDeg;
      ASSERT_TRUE(Eval(q, &phi, &st)) << deg;
      const double F = Press(phi(i_s));
      const double ma = std::abs(F) / std::abs(st.drive(0));
      EXPECT_TRUE(Near(ma, 1 / std::abs(SliderKs(p.a, p.b, q)), 1e-6, ma, "|F| / |T|"))
          << "q = " << q / kDeg << " deg";
      if (sign > 0) {
        EXPECT_GT(ma, previous) << "q = " << deg << " deg";
        previous = ma;
      }
      if (deg <= 0.01) {
        EXPECT_NEAR(ma * std::abs(q) * p.a * (1 + p.a / p.b), 1.0, 1e-4) << deg;
      }
    }
  }
  EXPECT_GT(previous, 1e5) << "mechanical advantage at 0.001 deg";
}

}  // namespace
