// The crank-shaper quick-return (models/quick_return.yaml) against its hand derivation
// (Paul §3.2.2). With O4 at the origin and O2 = (0, d), the crank pin is
//   A = (r cos t, d + r sin t),   s = |O4 A| = sqrt(r² + d² + 2 r d sin t),
//   theta4 = atan2(d + r sin t, r cos t),
//   theta4' = r (r + d sin t) / s²,   theta4'' = r d cos t (d² - r²) / s⁴,
//   s' = r d cos t / s,   s'' = -(r d sin t + s'²) / s.
// The link BC (l) keeps C on y = h:  l sin theta5 = h - L sin theta4, with C to the right
// of B (cos theta5 > 0), so
//   theta5' = -L cos theta4 theta4' / (l cos theta5),
//   theta5'' = (-L cos theta4 theta4'' + L sin theta4 theta4'² + l sin theta5 theta5'²) / (l cos theta5),
// and the ram x = L cos theta4 + l cos theta5:
//   x' = -L sin theta4 theta4' - l sin theta5 theta5',
//   x'' = -L cos theta4 theta4'² - L sin theta4 theta4'' - l cos theta5 theta5'² - l sin theta5 theta5''.
// The ram stops where theta4' = 0: sin t = -r/d, t = 210 and 330 deg for r/d = 1/2, so one
// stroke takes 240 deg of crank and the other 120: the time ratio is 2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "quick_return.h"

namespace {

using M = mech::quick_return::Model;

int PhiIndex(const char* name) {
  for (int i = 0; i < M::kNphi; ++i)
    if (std::strcmp(M::kPhiNames[i], name) == 0) return i;
  ADD_FAILURE() << "no coordinate " << name;
  return 0;
}

struct Hand {
  double theta4, theta5, s, x;        // positions
  double theta4d, theta5d, sd, xd;    // d/dt
  double theta4dd, theta5dd, sdd, xdd;  // d2/dt2
};

Hand HandQuickReturn(const M::ParamsT<double>& p, double t) {
  Hand h{};
  const double r = p.r, d = p.d, L = p.L, l = p.l;
  const double s2 = r * r + d * d + 2 * r * d * std::sin(t);
  h.s = std::sqrt(s2);
  h.theta4 = std::atan2(d + r * std::sin(t), r * std::cos(t));
  h.theta4d = r * (r + d * std::sin(t)) / s2;
  h.theta4dd = r * d * std::cos(t) * (d * d - r * r) / (s2 * s2);
  h.sd = r * d * std::cos(t) / h.s;
  h.sdd = -(r * d * std::sin(t) + h.sd * h.sd) / h.s;
  const double c4 = std::cos(h.theta4), s4 = std::sin(h.theta4);
  h.theta5 = std::asin((p.h - L * s4) / l);
  const double c5 = std::cos(h.theta5), s5 = std::sin(h.theta5);
  h.theta5d = -L * c4 * h.theta4d / (l * c5);
  h.theta5dd = (-L * c4 * h.theta4dd + L * s4 * h.theta4d * h.theta4d + l * s5 * h.theta5d * h.theta5d) / (l * c5);
  h.x = L * c4 + l * c5;
  h.xd = -L * s4 * h.theta4d - l * s5 * h.theta5d;
  h.xdd = -L * c4 * h.theta4d * h.theta4d - L * s4 * h.theta4dd - l * c5 * h.theta5d * h.theta5d - l * s5 * h.theta5dd;
  return h;
}

// 1e-12 relative to max(1, |value|): the hand formulas and the generated code both
// evaluate a few dozen well-conditioned operations (cond(Phi_phi) < 50 on this model).
void ExpectClose(double generated, double hand, const char* what, double t) {
  EXPECT_NEAR(generated, hand, 1e-12 * std::max(1.0, std::abs(hand))) << what << " at t = " << t;
}

TEST(PaulQuickReturn, PositionsVelocitiesAndAccelerationsOverAFullTurn) {
  const M::ParamsT<double> p;
  const int i4 = PhiIndex("theta_rocker"), i5 = PhiIndex("theta_link"), is = PhiIndex("s_slot"),
            ix = PhiIndex("s_stroke");
  Eigen::Matrix<double, 1, 1> q;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  mech::quick_return::Coefficients<double> c;
  for (int k = 0; k <= 720; ++k) {
    const double t = 2 * M_PI * k / 720;
    q(0) = t;
    ASSERT_EQ(static_cast<int>(M::Solve(p, q, &phi).status), 0) << "t = " << t;
    M::Coeffs(p, q, phi, &c);
    const Hand h = HandQuickReturn(p, t);
    ExpectClose(std::remainder(phi(i4) - h.theta4, 2 * M_PI), 0, "theta_rocker", t);
    ExpectClose(std::remainder(phi(i5) - h.theta5, 2 * M_PI), 0, "theta_link", t);
    ExpectClose(phi(is), h.s, "s_slot", t);
    ExpectClose(phi(ix), h.x, "ram x", t);
    ExpectClose(c.K(i4, 0), h.theta4d, "K theta_rocker", t);
    ExpectClose(c.K(i5, 0), h.theta5d, "K theta_link", t);
    ExpectClose(c.K(is, 0), h.sd, "K s_slot", t);
    ExpectClose(c.K(ix, 0), h.xd, "K ram", t);
    ExpectClose(c.L(i4, 0), h.theta4dd, "L theta_rocker", t);
    ExpectClose(c.L(i5, 0), h.theta5dd, "L theta_link", t);
    ExpectClose(c.L(is, 0), h.sdd, "L s_slot", t);
    ExpectClose(c.L(ix, 0), h.xdd, "L ram", t);
    // The ram's pin C (the requested point) moves on y = h with the ram.
    ExpectClose(c.r_P(0, 0), h.x, "ram.C x", t);
    ExpectClose(c.r_P(1, 0), p.h, "ram.C y", t);
    ExpectClose(c.K_P(0, 0), h.xd, "ram.C K x", t);
    ExpectClose(c.K_P(1, 0), 0, "ram.C K y", t);
    ExpectClose(c.L_P(0, 0), h.xdd, "ram.C L x", t);
  }
}

TEST(PaulQuickReturn, TimeRatioIsTwo) {
  // The ram's velocity coefficient changes sign at the stroke ends; find them along the
  // generated K and locate each zero by bisection on the generated code alone.
  const M::ParamsT<double> p;
  const int ix = PhiIndex("s_stroke");
  auto ram_speed = [&](double t, Eigen::Matrix<double, M::kNphi, 1>* phi) {
    Eigen::Matrix<double, 1, 1> q(t);
    EXPECT_EQ(static_cast<int>(M::Solve(p, q, phi).status), 0);
    mech::quick_return::Coefficients<double> c;
    M::Coeffs(p, q, *phi, &c);
    return c.K(ix, 0);
  };
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  std::vector<double> ends;
  double previous = ram_speed(0, &phi);
  for (int k = 1; k <= 720; ++k) {
    const double t0 = 2 * M_PI * (k - 1) / 720, t1 = 2 * M_PI * k / 720;
    const double v = ram_speed(t1, &phi);
    if ((v > 0) != (previous > 0)) {
      double a = t0, b = t1;
      Eigen::Matrix<double, M::kNphi, 1> work = phi;
      const double va = ram_speed(a, &work);
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (a + b);
        if ((ram_speed(mid, &work) > 0) == (va > 0)) a = mid; else b = mid;
      }
      ends.push_back(0.5 * (a + b));
    }
    previous = v;
  }
  ASSERT_EQ(ends.size(), 2u);
  const double expected_first = M_PI + std::asin(p.r / p.d), expected_second = 2 * M_PI - std::asin(p.r / p.d);
  EXPECT_NEAR(ends[0], expected_first, 1e-9);
  EXPECT_NEAR(ends[1], expected_second, 1e-9);
  const double short_stroke = ends[1] - ends[0], long_stroke = 2 * M_PI - short_stroke;
  EXPECT_NEAR(long_stroke / short_stroke, 2.0, 1e-8);
}

}  // namespace
