// A switched load (issue 26): the shaper of tests/statics/models/shaper.yaml, whose cutting
// force F acts on the forward stroke only (F step(240 deg - mod(theta_crank + 30 deg, 360
// deg))), and the expression language's piecewise functions in the generated C++.
//  - The helpers ExprStep ... ExprMod of the generated header against the reader's
//    evaluation (GiNaC, exact and in floats) and hand values, on both sides of every switch
//    point, in double, float and ceres::Jet (the derivative of the branch taken).
//  - The work of the driving torque over one crank turn equals F times the stroke, the ram's
//    largest minus smallest position (work = -F (x(210 deg) - x(-30 deg)): the force
//    switches at the ram's extremes, where its velocity is 0, so the relation is exact).
//  - EvalStiffness (-dQ/dq along the motion, through min, max, clamp and sign of the
//    coordinates) against central differences of EvalStatics' Q, away from the switches.
#include "shaper.h"

#include <ceres/jet.h>
#include <ginac/ginac.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "model/expression_functions.h"
#include "statics_test_util.h"

namespace {

using M = mech::shaper::Model;
using mechtest::statics::kDeg;
using Phi = Eigen::Matrix<double, M::kNphi, 1>;
using Q = Eigen::Matrix<double, M::kNq, 1>;

// The reader's value of a piecewise function at numbers (GiNaC's eval on exact rationals of
// the doubles, evalf on floats): mechgen's own evaluation, independent of the generated C++.
double Reader(const GiNaC::ex& e) { return GiNaC::ex_to<GiNaC::numeric>(e.evalf()).to_double(); }
GiNaC::ex Exact(double v) {  // the double's exact binary value as a rational
  int e = 0;
  const double m = std::frexp(v, &e);
  return GiNaC::numeric(static_cast<long>(std::ldexp(m, 53))) * GiNaC::pow(GiNaC::numeric(2), e - 53);
}
GiNaC::ex Float(double v) { return GiNaC::numeric(v); }

void ExpectAll(double generated, double reader_exact, double reader_float, double hand, const char* what, double x) {
  const double tol = 1e-15 * std::max(1.0, std::abs(hand));
  EXPECT_NEAR(generated, hand, tol) << what << " at " << x;
  EXPECT_NEAR(reader_exact, hand, tol) << what << " at " << x << " (reader, exact)";
  EXPECT_NEAR(reader_float, hand, tol) << what << " at " << x << " (reader, floats)";
}

TEST(ShaperPiecewise, GeneratedHelpersMatchTheReaderOnBothSidesOfEverySwitch) {
  using namespace mech::shaper;
  const double e = 1e-12;
  for (double x : {-2.0, -e, 0.0, e, 3.0}) {
    ExpectAll(ExprStep(x), Reader(mechgen::mstep(Exact(x))), Reader(mechgen::mstep(Float(x))), x >= 0 ? 1 : 0, "step",
              x);
    ExpectAll(ExprSign(x), Reader(mechgen::msign(Exact(x))), Reader(mechgen::msign(Float(x))),
              x > 0   ? 1
              : x < 0 ? -1
                      : 0,
              "sign", x);
    EXPECT_EQ(ExprStep(static_cast<float>(x)), x >= 0 ? 1.0f : 0.0f);
  }
  for (const auto& [a, b] : {std::pair<double, double>{0.5, 0.5 + e}, {0.5, 0.5}, {0.5 + e, 0.5}, {-3, 2}, {2, -3}}) {
    ExpectAll(ExprMin(a, b), Reader(mechgen::mmin(Exact(a), Exact(b))), Reader(mechgen::mmin(Float(a), Float(b))),
              a < b ? a : b, "min", a - b);
    ExpectAll(ExprMax(a, b), Reader(mechgen::mmax(Exact(a), Exact(b))), Reader(mechgen::mmax(Float(a), Float(b))),
              a > b ? a : b, "max", a - b);
  }
  for (double p : {2 * M_PI, 3.0, 0.25}) {
    for (double x : {-7.5, -p - e, -p, -p + e, -e, 0.0, e, p - e, p, p + e, 2.5 * p, 13.0}) {
      double hand = std::fmod(x, p);  // exact
      if (hand < 0) hand += p;
      if (hand >= p) hand -= p;
      ExpectAll(ExprMod(x, p), Reader(mechgen::mmod(Exact(x), Exact(p))), Reader(mechgen::mmod(Float(x), Float(p))),
                hand, "mod", x);
      const double r = ExprMod(x, p);
      EXPECT_TRUE(r >= 0 && r < p) << x << " mod " << p << " = " << r;
      const float rf = ExprMod(static_cast<float>(x), static_cast<float>(p));
      EXPECT_TRUE(rf >= 0 && rf < static_cast<float>(p)) << x << " mod " << p << " = " << rf << " (float)";
    }
  }
}

TEST(ShaperPiecewise, JetsCarryTheDerivativeOfTheBranchTaken) {
  using Jet = ceres::Jet<double, 2>;
  using namespace mech::shaper;
  auto jet = [](double v, int i) { return Jet(v, i); };
  for (double x : {-1.0, 0.0, 1.0}) {
    EXPECT_EQ(ExprStep(jet(x, 0)).a, x >= 0 ? 1 : 0);
    EXPECT_EQ(ExprStep(jet(x, 0)).v.norm(), 0);
    EXPECT_EQ(ExprSign(jet(x, 0)).v.norm(), 0);
  }
  // min(a, b): d/da where a <= b (ties too, as the symbolic derivative step(b - a) says).
  for (const auto& [a, b] : {std::pair<double, double>{1, 2}, {2, 2}, {3, 2}}) {
    const Jet lo = ExprMin(jet(a, 0), jet(b, 1)), hi = ExprMax(jet(a, 0), jet(b, 1));
    EXPECT_EQ(lo.v(0), a <= b ? 1 : 0) << a << " " << b;
    EXPECT_EQ(lo.v(1), a <= b ? 0 : 1) << a << " " << b;
    EXPECT_EQ(hi.v(0), a >= b ? 1 : 0) << a << " " << b;
    EXPECT_EQ(hi.v(1), a >= b ? 0 : 1) << a << " " << b;
  }
  // mod(x, p): d/dx = 1, d/dp = -floor(x/p).
  const Jet r = ExprMod(jet(7.5, 0), jet(2.0, 1));
  EXPECT_DOUBLE_EQ(r.a, 1.5);
  EXPECT_DOUBLE_EQ(r.v(0), 1);
  EXPECT_DOUBLE_EQ(r.v(1), -3);
}

struct State {
  Phi phi;
  M::CoefficientsT<double> c;
  M::StaticsT<double> s;
};

State At(const M::ParamsT<double>& p, double u) {
  State st;
  EXPECT_TRUE(mechtest::statics::SolveAt<M>(p, u, &st.phi)) << u;
  const Q q = Q::Constant(u);
  M::Coeffs(p, q, st.phi, &st.c);
  M::Forces(p, q, st.phi, st.c, &st.s);
  return st;
}

// The ram's x where it is extreme, by golden-section search on [lo, hi] (sign +1: the
// largest x, -1: the smallest).
double Extreme(const M::ParamsT<double>& p, double lo, double hi, double sign) {
  auto x = [&](double u) { return sign * At(p, u).c.r_P(0, 0); };
  const double g = (std::sqrt(5.0) - 1) / 2;
  double a = lo, b = hi;
  for (int i = 0; i < 200 && b - a > 1e-10; ++i) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if (x(c) > x(d))
      b = d;
    else
      a = c;
  }
  return sign * x((a + b) / 2);
}

// Composite 3-point Gauss-Legendre over [a, b] in n panels: the nodes are interior, so no
// sample falls on the interval's ends (the switch points).
double Integral(const std::function<double(double)>& f, double a, double b, int n) {
  const double w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9}, t[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)};
  const double h = (b - a) / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) sum += w[k] * f(a + h * (i + 0.5 + 0.5 * t[k]));
  return sum * h / 2;
}

TEST(ShaperStatics, WorkPerCycleIsForceTimesStroke) {
  M::ParamsT<double> p;
  p.P = 0;  // the cutting force alone
  auto drive = [&](double u) { return At(p, u).s.drive(0); };
  // The stroke from the positions: the ram's largest and smallest x over a fine sweep, each
  // refined around its grid extreme.
  double u_max = 0, u_min = 0, x_max = -1e300, x_min = 1e300;
  for (int i = 0; i <= 3600; ++i) {
    const double u = (-30 + 0.1 * i) * kDeg, x = At(p, u).c.r_P(0, 0);
    if (x > x_max) x_max = x, u_max = u;
    if (x < x_min) x_min = x, u_min = u;
  }
  x_max = Extreme(p, u_max - 0.2 * kDeg, u_max + 0.2 * kDeg, 1);
  x_min = Extreme(p, u_min - 0.2 * kDeg, u_min + 0.2 * kDeg, -1);
  // The extremes are where the crank is perpendicular to the rocker (sin u = -r/d).
  EXPECT_NEAR(std::fmod(u_max + 2 * M_PI, 2 * M_PI), 330 * kDeg, 0.11 * kDeg);
  EXPECT_NEAR(u_min, 210 * kDeg, 0.11 * kDeg);
  const double stroke = x_max - x_min;
  EXPECT_GT(stroke, 1.0);
  // Split at the switch points -30 and 210 deg: smooth on each piece.
  const double forward = Integral(drive, -30 * kDeg, 210 * kDeg, 400);
  const double back = Integral(drive, 210 * kDeg, 330 * kDeg, 200);
  EXPECT_NEAR(forward, p.F * stroke, 1e-9 * p.F * stroke);
  EXPECT_NEAR(back, 0, 1e-12 * p.F * stroke);  // no load on the return
  // Inside the strokes: the driving torque does positive work on the forward stroke, none on
  // the return (to rounding).
  for (double u : {0.0, 90.0, 180.0}) EXPECT_GT(drive(u * kDeg), 0) << u;
  for (double u : {240.0, 270.0, 300.0}) EXPECT_EQ(drive(u * kDeg), 0) << u;
}

TEST(ShaperStatics, StiffnessIsMinusDQdqAwayFromTheSwitches) {
  M::ParamsT<double> p;
  p.P = 40;
  int checked = 0;
  for (double deg = -25; deg < 330; deg += 7.3) {
    const double u = deg * kDeg;
    const State st = At(p, u);
    // The probe's switches: theta_rocker - 90 deg at -0.2 and 0.3, s_slot at 1.6, cos u at 0,
    // s_stroke at 0.5; and the cut's at -30 and 210 deg.
    const double rocker = st.phi(0) - 90 * kDeg;
    const double gaps[] = {std::abs(rocker + 0.2), std::abs(rocker - 0.3),    std::abs(st.phi(2) - 1.6),
                           std::abs(std::cos(u)),  std::abs(st.phi(3) - 0.5), std::abs(deg - 210),
                           std::abs(deg + 30)};
    if (*std::min_element(std::begin(gaps), std::end(gaps)) < 0.02) continue;
    ++checked;
    M::StaticsT<double> s = st.s;
    const Q q = Q::Constant(u);
    M::Stiffness(p, q, st.phi, st.c, &s);
    const double h = 1e-5;
    const double fd = -(At(p, u + h).s.Q(0) - At(p, u - h).s.Q(0)) / (2 * h);
    EXPECT_NEAR(s.stiffness(0, 0), fd, 1e-6 * std::max(1.0, std::abs(fd))) << deg << " deg";
  }
  EXPECT_GE(checked, 25);
}

TEST(ShaperStatics, FloatAndJetInstantiationsAgreeWithDouble) {
  M::ParamsT<double> p;
  using Jet = ceres::Jet<double, 1>;
  for (double deg : {10.0, 100.0, 250.0}) {
    const State st = At(p, deg * kDeg);
    const M::ParamsT<float> pf = p.Cast<float>();
    Eigen::Matrix<float, M::kNphi, 1> phif = st.phi.cast<float>();
    const Eigen::Matrix<float, M::kNq, 1> qf =
        Eigen::Matrix<float, M::kNq, 1>::Constant(static_cast<float>(deg * kDeg));
    M::CoefficientsT<float> cf;
    M::StaticsT<float> sf;
    M::Coeffs(pf, qf, phif, &cf);
    M::Forces(pf, qf, phif, cf, &sf);
    EXPECT_NEAR(sf.drive(0), st.s.drive(0), 2e-3 * std::max(1.0, std::abs(st.s.drive(0)))) << deg;
    const M::ParamsT<Jet> pj = p.Cast<Jet>();
    Eigen::Matrix<Jet, M::kNphi, 1> phij;
    for (int i = 0; i < M::kNphi; ++i) phij(i) = Jet(st.phi(i));
    const Eigen::Matrix<Jet, M::kNq, 1> qj = Eigen::Matrix<Jet, M::kNq, 1>::Constant(Jet(deg * kDeg, 0));
    M::CoefficientsT<Jet> cj;
    M::StaticsT<Jet> sj;
    M::Coeffs(pj, qj, phij, &cj);
    M::Forces(pj, qj, phij, cj, &sj);
    EXPECT_NEAR(sj.drive(0).a, st.s.drive(0), 1e-12 * std::max(1.0, std::abs(st.s.drive(0)))) << deg;
  }
}

}  // namespace
