// The generated statics of models/slider_crank_friction.yaml (a centred slider-crank, a
// piston force F along -x, Coulomb friction at the pins O, B, C and at the slide):
//   - with given friction loads f (numbers), the reactions, the drive and Q against the
//     Newton–Euler solution with the same loads, every link's equilibrium, and the virtual
//     work of the piston force and of the friction loads over a small motion;
//   - normal, gain and K_rel against the N-E reaction magnitudes, the model's mu r and mu,
//     and central differences of the relative angles and of s;
//   - the friction iteration of the contract (f_J = -gain_J normal_J sign(dir K_rel_J))
//     on the generated values against the free-body solver's own iteration;
//   - the dead zone near the dead centres with friction at O only: the piston cannot turn
//     the crank where the rod's line passes inside O's friction circle,
//     a |sin(q - th_rod)| <= mu_O r_O (hand derivation), against the generated drive.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mechgen/statics/solve.h"
#include "slider_crank_fb.h"
#include "slider_crank_friction.h"
#include "statics_test_util.h"

namespace {

namespace sf = mech::slider_crank_friction;
using M = sf::Model;
using P = M::ParamsT<double>;
using mechtest::fb::FreeBodySystem;
using mechtest::fb::SliderCrankFb;
using mechtest::fb::SliderKs;
using mechtest::fb::SliderRodAngle;
using mechtest::fb::Vec2;
using mechtest::statics::IndexOf;
using mechtest::statics::kDeg;
using mechtest::statics::Near;
using Phi = Eigen::Matrix<double, M::kNphi, 1>;
using Q1 = Eigen::Matrix<double, M::kNq, 1>;
using VecF = Eigen::Matrix<double, M::kNumFriction, 1>;

constexpr double kTol = 1e-9;  // forces ~1000 N; see fourbar_loaded_test.cc
constexpr double kH = 1e-5;
constexpr double kFdTol = 1e-6;

class SliderCrankFrictionStatics : public ::testing::Test {
 protected:
  P p;
  int i_rod = -1, i_s = -1;
  int f_O = -1, f_B = -1, f_C = -1, f_S = -1;  // friction joints' indices

  void SetUp() override {
    i_rod = IndexOf(M::kPhiNames, "theta_rod");
    i_s = IndexOf(M::kPhiNames, "s_slide");
    f_O = IndexOf(M::kFrictionJoints, "O");
    f_B = IndexOf(M::kFrictionJoints, "B");
    f_C = IndexOf(M::kFrictionJoints, "C");
    f_S = IndexOf(M::kFrictionJoints, "slide");
    ASSERT_GE(i_rod, 0);
    ASSERT_GE(i_s, 0);
    ASSERT_GE(f_O, 0);
    ASSERT_GE(f_B, 0);
    ASSERT_GE(f_C, 0);
    ASSERT_GE(f_S, 0);
  }

  bool Eval(double q, Phi* phi, sf::Statics<double>* st, const VecF* f) const {
    if (!mechtest::statics::SolveAt<M>(p, q, phi)) return false;
    sf::Coefficients<double> c;
    const Q1 qv = Q1::Constant(q);
    sf::EvalCoefficients(p, qv, *phi, &c);
    sf::EvalStatics(p, qv, *phi, c, st, f);
    return true;
  }
  SliderCrankFb MakeFb() const {
    SliderCrankFb fb(p.a, p.b);
    fb.s.SetForce(fb.slider_force, Vec2(-p.F, 0));
    return fb;
  }
  // The free-body joint of friction joint i.
  int FbJoint(const SliderCrankFb& fb, int i) const {
    if (i == f_O) return fb.jO;
    if (i == f_B) return fb.jB;
    if (i == f_C) return fb.jC;
    return fb.jS;
  }
  int R(const std::string& name) const {
    const int i = IndexOf(M::kReactionNames, name);
    EXPECT_GE(i, 0) << name;
    return i;
  }
  Eigen::VectorXd Unknowns(SliderCrankFb& fb, const sf::Statics<double>& st) const {
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
  // Relative angles / displacement of the friction joints at q, from the generated
  // positions: O: th_crank - 0, B: th_rod - th_crank, C: 0 - th_rod (the piston does not
  // turn), slide: s.
  VecF Relative(double q) const {
    Phi phi;
    EXPECT_TRUE(mechtest::statics::SolveAt<M>(p, q, &phi));
    VecF r;
    r(f_O) = q;
    r(f_B) = phi(i_rod) - q;
    r(f_C) = -phi(i_rod);
    r(f_S) = phi(i_s);
    return r;
  }
  VecF KRelFd(double q) const { return (Relative(q + kH) - Relative(q - kH)) / (2 * kH); }
  void CheckGivenFriction(const char* name, const VecF& f);
  void CheckFrictionIteration();
  void CheckOneFrictionJoint(bool at_O);
};

// Sample crank angles, off the angles where a relative velocity vanishes.
std::vector<double> Angles() {
  std::vector<double> v;
  for (int k = 0; k < 360; k += 2) v.push_back((k + 0.5) * kDeg);
  return v;
}

TEST_F(SliderCrankFrictionStatics, DeclaresFrictionJointsAndGains) {
  ASSERT_EQ(M::kNumFriction, 4);
  EXPECT_FALSE(M::kFrictionPrismatic[f_O]);
  EXPECT_FALSE(M::kFrictionPrismatic[f_B]);
  EXPECT_FALSE(M::kFrictionPrismatic[f_C]);
  EXPECT_TRUE(M::kFrictionPrismatic[f_S]);
  Phi phi;
  sf::Statics<double> st;
  ASSERT_TRUE(Eval(30 * kDeg, &phi, &st, nullptr));
  EXPECT_DOUBLE_EQ(st.gain(f_O), p.mu_O * p.r_O);
  EXPECT_DOUBLE_EQ(st.gain(f_B), p.mu_B * p.r_B);
  EXPECT_DOUBLE_EQ(st.gain(f_C), p.mu_C * p.r_C);
  EXPECT_DOUBLE_EQ(st.gain(f_S), p.mu_s);
}

// (a), (b), (c) with given friction loads: the generated reactions and drive equal the
// Newton–Euler solution with the same loads; T_slide is the slide's friction force; every
// link is in equilibrium; normal = |F_J| or |N|; K_rel against differences of positions; Q
// is the work of the piston force and of the friction loads (f_J K_rel_J) per unit angle.
void SliderCrankFrictionStatics::CheckGivenFriction(const char* name, const VecF& f_given) {
  SliderCrankFb fb = MakeFb();
  const char* unknowns[] = {"F_O_x", "F_O_y", "drive", "F_B_x", "F_B_y", "F_C_x", "F_C_y",
                            "N_slide", "M_slide"};
  const char* rows[] = {"crank Fx", "crank Fy", "crank M", "rod Fx", "rod Fy", "rod M",
                        "piston Fx", "piston Fy", "piston M"};
  {
    const VecF* f = &f_given;
    for (double q : Angles()) {
      Phi phi;
      sf::Statics<double> st;
      ASSERT_TRUE(Eval(q, &phi, &st, f));
      fb.Place(q, phi(i_rod), phi(i_s));
      for (int i = 0; i < M::kNumFriction; ++i) fb.s.SetFriction(FbJoint(fb, i), (*f)(i));
      Eigen::VectorXd x;
      ASSERT_TRUE(fb.s.Solve(&x));
      const Eigen::VectorXd g = Unknowns(fb, st);
      const double scale = x.lpNorm<Eigen::Infinity>();
      const std::string at = "q = " + std::to_string(q / kDeg) + " deg, friction loads: " + name;
      for (int i = 0; i < x.size(); ++i) EXPECT_TRUE(Near(g(i), x(i), kTol, scale, unknowns[i])) << at;
      EXPECT_TRUE(Near(st.R(R("T_slide")), (*f)(f_S), kTol, scale, "T_slide")) << at;
      EXPECT_TRUE(Near(st.drive(0), -st.Q(0), kTol, scale, "drive = -Q")) << at;
      const Eigen::VectorXd res = fb.s.Residual(g);
      for (int i = 0; i < res.size(); ++i) EXPECT_TRUE(Near(res(i), 0.0, kTol, scale, rows[i])) << at;
      for (int i = 0; i < M::kNumFriction; ++i) {
        EXPECT_TRUE(Near(st.normal(i), fb.s.Normal(FbJoint(fb, i), x), kTol, scale,
                         std::string("normal at ") + M::kFrictionJoints[i])) << at;
      }
      const VecF K_rel = KRelFd(q);
      for (int i = 0; i < M::kNumFriction; ++i) {
        EXPECT_TRUE(Near(st.K_rel(i, 0), K_rel(i), kFdTol, 1,
                         std::string("K_rel at ") + M::kFrictionJoints[i])) << at;
      }
      const double Qw = -p.F * K_rel(f_S) + f->dot(K_rel);
      EXPECT_TRUE(Near(st.Q(0), Qw, kFdTol, 1000, "Q by virtual work")) << at;
    }
  }
}


TEST_F(SliderCrankFrictionStatics, NoFrictionLoadsAgainstNewtonEuler) {
  CheckGivenFriction("none", VecF::Zero());
}

TEST_F(SliderCrankFrictionStatics, PinFrictionLoadsAgainstNewtonEuler) {
  VecF f = VecF::Zero();
  f(f_O) = 3.0;   // N m, of the ground on the crank
  f(f_B) = -1.5;  // N m, of the crank on the rod
  f(f_C) = 0.8;   // N m, of the rod on the piston
  CheckGivenFriction("pins (3, -1.5, 0.8) N m", f);
}

// The slide's friction force (40 N along +x on the piston): it enters Q and every reaction.
TEST_F(SliderCrankFrictionStatics, SlideFrictionLoadAgainstNewtonEuler) {
  VecF f = VecF::Zero();
  f(f_S) = 40.0;  // N, on the piston along +x
  CheckGivenFriction("slide 40 N", f);
}

// The contract's friction iteration on the generated values (forward and backward) against
// the free-body solver's own iteration, whose signs of relative motion come from
// differences of positions.
void SliderCrankFrictionStatics::CheckFrictionIteration() {
  SliderCrankFb fb = MakeFb();
  for (double dir : {+1.0, -1.0}) {
    for (double q : Angles()) {
      const VecF K_rel = KRelFd(q);
      // Generated: iterate f = -gain normal sign(dir K_rel).
      Phi phi;
      sf::Statics<double> st;
      VecF f = VecF::Zero();
      bool settled = false;
      for (int it = 0; it < 200 && !settled; ++it) {
        ASSERT_TRUE(Eval(q, &phi, &st, &f));
        VecF next;
        for (int i = 0; i < M::kNumFriction; ++i) {
          const double sgn = dir * st.K_rel(i, 0) > 0 ? 1.0 : -1.0;
          next(i) = -st.gain(i) * st.normal(i) * sgn;
        }
        settled = (next - f).lpNorm<Eigen::Infinity>() <= 1e-12 * (1 + f.lpNorm<Eigen::Infinity>());
        f = next;
      }
      ASSERT_TRUE(settled) << q;
      ASSERT_TRUE(Eval(q, &phi, &st, &f));
      // Oracle.
      fb.Place(q, phi(i_rod), phi(i_s));
      std::vector<FreeBodySystem::FrictionSpec> specs;
      specs.push_back({fb.jO, p.mu_O * p.r_O, dir * K_rel(f_O) > 0 ? 1.0 : -1.0});
      specs.push_back({fb.jB, p.mu_B * p.r_B, dir * K_rel(f_B) > 0 ? 1.0 : -1.0});
      specs.push_back({fb.jC, p.mu_C * p.r_C, dir * K_rel(f_C) > 0 ? 1.0 : -1.0});
      specs.push_back({fb.jS, p.mu_s, dir * K_rel(f_S) > 0 ? 1.0 : -1.0});
      Eigen::VectorXd x;
      ASSERT_TRUE(fb.s.SolveWithFriction(specs, &x));
      const double scale = x.lpNorm<Eigen::Infinity>();
      const std::string at = "q = " + std::to_string(q / kDeg) + " deg, dir " + std::to_string(dir);
      EXPECT_TRUE(Near(st.drive(0), fb.s.Drive(fb.jO, x), 1e-8, scale, "drive with friction")) << at;
      EXPECT_TRUE(Near(st.R(R("N_slide")), fb.s.PrismaticN(fb.jS, x), 1e-8, scale, "N_slide")) << at;
      EXPECT_TRUE(Near(st.R(R("F_B_x")), fb.s.RevoluteForce(fb.jB, x).x(), 1e-8, scale, "F_B_x")) << at;
      EXPECT_TRUE(Near(st.R(R("F_B_y")), fb.s.RevoluteForce(fb.jB, x).y(), 1e-8, scale, "F_B_y")) << at;
      EXPECT_TRUE(Near(st.R(R("T_slide")), fb.s.PrismaticT(fb.jS, x), 1e-8, scale, "T_slide")) << at;
      // Friction always costs the actuator: forward it needs more than without friction.
      sf::Statics<double> st0;
      ASSERT_TRUE(Eval(q, &phi, &st0, nullptr));
      EXPECT_GT(dir * (st.drive(0) - st0.drive(0)), 0.0) << at;
    }
  }
}

// Friction at the three pins (mu_s = 0).
TEST_F(SliderCrankFrictionStatics, FrictionIterationPinsAgainstNewtonEuler) {
  p.mu_s = 0;
  CheckFrictionIteration();
}

// Friction at the pins and at the slide.
TEST_F(SliderCrankFrictionStatics, FrictionIterationAgainstNewtonEuler) {
  CheckFrictionIteration();
}

// The dead zone (Paul §5.6.3), friction at O only (mu_B = mu_C = mu_s = 0): the piston
// drives (the slider moves along its force, -x) and the crank's actuator brakes. The rod is
// a two-force member along BC, the crank's bearing carries the rod force R, whose moment
// about O is R a |sin(q - th_rod)|, the friction torque mu_O r_O R: the piston cannot turn
// the crank (the brake would have to push, drive * qdot > 0) where
//   a |sin(q - th_rod)| < mu_O r_O.
// The generated drive, iterated with the contract's rule, against this predicate over a full
// turn, and the first boundary after top dead centre by bisection against the hand angle.
TEST_F(SliderCrankFrictionStatics, DeadZoneMatchesTheFrictionCircle) {
  p.mu_B = p.mu_C = p.mu_s = 0;
  const double circle = p.mu_O * p.r_O;
  // The generated drive with friction, the slider moving along -x: qdot = sdot / K_s.
  auto driven_power_sign = [&](double q) {
    Phi phi;
    sf::Statics<double> st;
    VecF f = VecF::Zero();
    EXPECT_TRUE(Eval(q, &phi, &st, nullptr));
    const double dir = st.K_rel(f_S, 0) > 0 ? -1.0 : 1.0;  // sign of qdot for sdot < 0
    for (int it = 0; it < 100; ++it) {
      for (int i = 0; i < M::kNumFriction; ++i) {
        f(i) = -st.gain(i) * st.normal(i) * (dir * st.K_rel(i, 0) > 0 ? 1.0 : -1.0);
      }
      EXPECT_TRUE(Eval(q, &phi, &st, &f));
    }
    return st.drive(0) * dir;  // > 0: the actuator must push: dead
  };
  auto hand = [&](double q) {  // < 0 inside the dead zone
    return p.a * std::abs(std::sin(q - SliderRodAngle(p.a, p.b, q))) - circle;
  };
  int dead = 0;
  for (int k = 0; k < 3600; ++k) {
    const double q = (k + 0.25) * 0.1 * kDeg;
    const double h = hand(q);
    if (std::abs(h) < 1e-6) continue;  // at the boundary
    const bool hand_dead = h < 0;
    dead += hand_dead;
    EXPECT_EQ(driven_power_sign(q) > 0, hand_dead) << "q = " << q / kDeg << " deg";
  }
  EXPECT_GT(dead, 20) << "the zones around 0 and 180 deg are several tenths of a degree wide";
  // The boundary after q = 0: bisection on each side.
  auto bisect = [](auto fn, double lo, double hi) {
    const bool s_lo = fn(lo) > 0;
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((fn(mid) > 0) == s_lo ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  const double q_hand = bisect(hand, 1e-6, 20 * kDeg);
  const double q_gen = bisect(driven_power_sign, 1e-6, 20 * kDeg);
  // Small angles: a sin(q (1 + a/b)) ~ mu r, q ~ 0.006 / (0.1 * 1.2857) = 2.67 deg.
  EXPECT_NEAR(q_hand / kDeg, 2.67, 0.02);
  EXPECT_NEAR(q_gen, q_hand, 1e-9) << "dead zone boundary (rad)";
}

// Closed forms with one friction joint at a time, the contract's iteration on the generated
// values, forward and backward (dir = sign of qdot). The rod is a two-force member (its pins
// frictionless), in compression R_c along u_rod; on the piston R_c cos th_r - F + f_s = 0,
// R_c sin th_r + N = 0; the crank torque is R_c a sin(th_r - q) (= F K_s without friction).
//   Friction circle at O only: R_c = F / cos th_r and |F_O| = R_c, so
//     drive = F K_s + dir mu_O r_O F / cos th_r.
//   Slide only (sigma = sign sdot = sign(dir K_s)), f_s = -mu_s |N| sigma:
//     R_c = F / (cos th_r - sigma mu_s |sin th_r|),  drive = R_c a sin(th_r - q).
void SliderCrankFrictionStatics::CheckOneFrictionJoint(const bool at_O) {
  const P defaults;
  auto iterate = [&](double q, double dir, sf::Statics<double>* st) {
    Phi phi;
    VecF f = VecF::Zero();
    for (int it = 0; it < 200; ++it) {
      EXPECT_TRUE(Eval(q, &phi, st, &f));
      for (int i = 0; i < M::kNumFriction; ++i) {
        f(i) = -st->gain(i) * st->normal(i) * (dir * st->K_rel(i, 0) > 0 ? 1.0 : -1.0);
      }
    }
    EXPECT_TRUE(Eval(q, &phi, st, &f));
  };
  {
    p = defaults;
    if (at_O) {
      p.mu_B = p.mu_C = p.mu_s = 0;
    } else {
      p.mu_O = p.mu_B = p.mu_C = 0;
    }
    for (double dir : {+1.0, -1.0}) {
      for (double q : Angles()) {
        sf::Statics<double> st;
        iterate(q, dir, &st);
        const double th = SliderRodAngle(p.a, p.b, q), Ks = SliderKs(p.a, p.b, q);
        double expected;
        if (at_O) {
          expected = p.F * Ks + dir * p.mu_O * p.r_O * p.F / std::cos(th);
        } else {
          const double sigma = dir * Ks > 0 ? 1.0 : -1.0;
          const double Rc = p.F / (std::cos(th) - sigma * p.mu_s * std::abs(std::sin(th)));
          expected = Rc * p.a * std::sin(th - q);
        }
        EXPECT_TRUE(Near(st.drive(0), expected, kTol, p.F, at_O ? "drive, friction circle at O"
                                                               : "drive, slide friction"))
            << "q = " << q / kDeg << " deg, dir " << dir;
      }
    }
  }
}

TEST_F(SliderCrankFrictionStatics, FrictionCircleAtOClosedForm) { CheckOneFrictionJoint(true); }

TEST_F(SliderCrankFrictionStatics, SlideFrictionClosedForm) { CheckOneFrictionJoint(false); }

// The driving torque with friction to run the crank in +q and in -q (issue 26), from the
// runtime (AnalyzeDrive on the generated statics), against the Newton–Euler free bodies
// with each joint's friction opposing that motion (pins and slide). Friction opposes the
// motion, so T_minus <= T0 <= T_plus; and the two curves are continuous through the dead
// centres, where T0 changes sign and the forward / backward pair swaps (jumps by
// T_plus - T_minus).
TEST_F(SliderCrankFrictionStatics, DrivePlusMinusAgainstNewtonEulerAndContinuous) {
  namespace statics = mechgen::statics;
  SliderCrankFb fb = MakeFb();
  auto analyze = [&](double q, statics::DriveAnalysis* d) {
    Phi phi;
    if (!mechtest::statics::SolveAt<M>(p, q, &phi)) return false;
    sf::Coefficients<double> c;
    const Q1 qv = Q1::Constant(q);
    sf::EvalCoefficients(p, qv, phi, &c);
    return statics::AnalyzeDrive<M>(statics::Options(), p, qv, phi, c, 0, d) ==
           statics::Status::kConverged;
  };
  auto oracle = [&](double q, double dir) {
    Phi phi;
    EXPECT_TRUE(mechtest::statics::SolveAt<M>(p, q, &phi));
    const VecF K_rel = KRelFd(q);
    fb.Place(q, phi(i_rod), phi(i_s));
    std::vector<FreeBodySystem::FrictionSpec> specs;
    specs.push_back({fb.jO, p.mu_O * p.r_O, dir * K_rel(f_O) > 0 ? 1.0 : -1.0});
    specs.push_back({fb.jB, p.mu_B * p.r_B, dir * K_rel(f_B) > 0 ? 1.0 : -1.0});
    specs.push_back({fb.jC, p.mu_C * p.r_C, dir * K_rel(f_C) > 0 ? 1.0 : -1.0});
    specs.push_back({fb.jS, p.mu_s, dir * K_rel(f_S) > 0 ? 1.0 : -1.0});
    Eigen::VectorXd x;
    EXPECT_TRUE(fb.s.SolveWithFriction(specs, &x));
    return fb.s.Drive(fb.jO, x);
  };
  int negative_T0 = 0, positive_T0 = 0;
  for (double q : Angles()) {
    statics::DriveAnalysis d;
    ASSERT_TRUE(analyze(q, &d)) << q;
    const std::string at = "q = " + std::to_string(q / kDeg) + " deg";
    const double scale = std::abs(d.drive_plus) + std::abs(d.drive_minus);
    EXPECT_TRUE(Near(d.drive_plus, oracle(q, +1), 1e-8, scale, "drive_plus")) << at;
    EXPECT_TRUE(Near(d.drive_minus, oracle(q, -1), 1e-8, scale, "drive_minus")) << at;
    EXPECT_LT(d.drive_minus, d.drive) << at;
    EXPECT_GT(d.drive_plus, d.drive) << at;
    (d.drive < 0 ? negative_T0 : positive_T0)++;
  }
  EXPECT_GT(negative_T0, 10);  // both signs of T0 are visited
  EXPECT_GT(positive_T0, 10);
  // Through each dead centre (T0 = 0, located by bisection) forward and backward swap. The
  // plus and minus torques do not: with the slide's friction they jump only by what the
  // slide's friction force reversing with the piston's velocity (K_rel of the slide changes
  // sign there) does to the pins' loads, the same jump as the free bodies'; without it they
  // change by no more than a slope times the step.
  for (const double mu_s : {p.mu_s, 0.0})
  for (const double centre : {180 * kDeg, 360 * kDeg}) {
    p.mu_s = mu_s;
    fb = MakeFb();
    double lo = centre - 5 * kDeg, hi = centre + 5 * kDeg;
    statics::DriveAnalysis d_lo, d_hi;
    ASSERT_TRUE(analyze(lo, &d_lo));
    ASSERT_TRUE(analyze(hi, &d_hi));
    ASSERT_LT(d_lo.drive * d_hi.drive, 0.0) << centre / kDeg;
    const double lo_sign = d_lo.drive;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      statics::DriveAnalysis d;
      ASSERT_TRUE(analyze(mid, &d));
      (d.drive * lo_sign > 0 ? lo : hi) = mid;
    }
    const double delta = 1e-7;
    statics::DriveAnalysis before, after;
    ASSERT_TRUE(analyze(lo - delta, &before));
    ASSERT_TRUE(analyze(hi + delta, &after));
    ASSERT_LT(before.drive * after.drive, 0.0);
    const double width = before.drive_plus - before.drive_minus;  // the friction's span
    ASSERT_GT(width, 1.0);                                       // N m: friction is there
    const std::string at = "dead centre near " + std::to_string(centre / kDeg) +
                           " deg, mu_s = " + std::to_string(mu_s);
    const double jump_plus = oracle(hi + delta, +1) - oracle(lo - delta, +1);
    const double jump_minus = oracle(hi + delta, -1) - oracle(lo - delta, -1);
    EXPECT_NEAR(after.drive_plus - before.drive_plus, jump_plus, 1e-9 * width) << at;
    EXPECT_NEAR(after.drive_minus - before.drive_minus, jump_minus, 1e-9 * width) << at;
    const double bound = mu_s > 0 ? 1e-2 * width : 1e-5 * width;
    EXPECT_LT(std::abs(after.drive_plus - before.drive_plus), bound) << at;
    EXPECT_LT(std::abs(after.drive_minus - before.drive_minus), bound) << at;
    // The forward curve (the motion along sign T0) jumps by the whole span there.
    EXPECT_NEAR(std::abs(after.drive_forward - before.drive_forward), width, 1e-2 * width) << at;
  }
}

}  // namespace
