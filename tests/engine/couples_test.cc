// Rocking couples of the engine models (mechgen/machines/engine/couples.h) from the generated per-link
// shaking forces (Shaking::F_link) and the axial positions z_j, against independent oracles:
//  - in-line four (flat crank 0-180-180-0, z mirror-symmetric): no couple about the middle at
//    any crank angle (while the couple about an end is not zero: the secondary force's arm);
//  - cross-plane V8: the order-1 harmonic of the couple vector over a revolution at constant
//    speed (a direct DFT here) equals the two-mass table of mechgen/machines/balancing/engine_balance.h for
//    the same masses and axial positions: exact for the first harmonic (the rod split into masses
//    at B and C by its centre of mass; the exact piston acceleration's first Fourier coefficient is
//    r w^2 without offset); with the textbook's z (pairs of a pin at one z) it is
//    (1 + 2 m_rot/m_rec) sqrt(10) m_rec r w^2 a turning with the crank; the order-2 couple is zero;
//  - the reference-point rule M(z') = M(z) + (z - z') z^ x F where the total force is not zero;
//  - a model without z_j parameters is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>

#include "engine_inline4.h"
#include "engine_single.h"
#include "engine_v8.h"
#include "mechgen/machines/balancing/engine_balance.h"
#include "mechgen/machines/engine/couples.h"
#include "slider_crank.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
using C = std::complex<double>;

/// The generated shaking (EvalShaking) at crank angle theta, constant speed omega.
template <class M>
bool ShakingAt(typename M::template ParamsT<double>& p, double theta, double omega,
               Eigen::Matrix<double, M::kNphi, 1>* phi, typename M::template ShakingT<double>* sh) {
  Eigen::Matrix<double, 1, 1> q, qd, qdd;
  q(0) = theta;
  qd(0) = omega;
  qdd(0) = 0;
  const auto rep = M::Solve(p, q, phi);
  if (rep.status != decltype(rep.status)::kConverged) return false;
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, q, *phi, &c);
  M::Shaking(p, q, *phi, qd, qdd, c, sh);
  return true;
}

template <class M>
Eigen::Matrix<double, M::kNphi, 1> AssemblyPhi() {
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  return phi;
}

/// Reciprocating and rotating mass per cylinder of the two-mass model (rod split at B and C).
template <class P>
void TwoMasses(P& p, double* m_rec, double* m_rot) {
  const double l = *p.Find("l"), lG = *p.Find("l_G"), m_rod = *p.Find("m_rod");
  *m_rec = *p.Find("m_pis") + m_rod * lG / l;
  *m_rot = m_rod * (l - lG) / l;
}

/// The order-n forward and backward parts of the couple X = M_x + i M_y over one revolution at
/// constant speed, by a direct DFT of N samples: X(t) = f e^{int} + b e^{-int} + other orders.
struct Orders {
  C f[3], b[3];
};

template <class M>
Orders CoupleOrders(typename M::template ParamsT<double>& p, double omega, int N, double* max_force) {
  Orders o{};
  auto phi = AssemblyPhi<M>();
  const auto axial = mechgen::engine::LinkAxialPositions<M>(p);
  EXPECT_TRUE(axial.ok()) << mechgen::engine::ToString(axial.status);
  *max_force = 0;
  for (int k = 0; k < N; ++k) {
    const double t = 2 * kPi * k / N;
    typename M::template ShakingT<double> sh;
    EXPECT_TRUE(ShakingAt<M>(p, t, omega, &phi, &sh)) << "theta " << t;
    *max_force = std::max(*max_force, sh.F.norm());
    const Eigen::Vector2d m = mechgen::engine::RockingCouple(sh, axial);
    const C x(m(0), m(1));
    for (int n = 1; n <= 2; ++n) {
      o.f[n] += x * std::polar(1.0 / N, -n * t);
      o.b[n] += x * std::polar(1.0 / N, n * t);
    }
  }
  return o;
}

TEST(EngineCouples, InlineFourFlatCrankHasNoRockingCoupleAboutItsMiddle) {
  using M = mech::engine_inline4::Model;
  mech::engine_inline4::Params<double> p;
  const double omega = 300, r = *p.Find("r");
  double m_rec = 0, m_rot = 0;
  TwoMasses(p, &m_rec, &m_rot);
  const auto axial = mechgen::engine::LinkAxialPositions<M>(p);
  ASSERT_TRUE(axial.ok()) << mechgen::engine::ToString(axial.status);
  ASSERT_EQ(axial.cylinders, 4);
  const double spacing = *p.Find("z_2") - *p.Find("z_1");
  ASSERT_GT(spacing, 0);
  EXPECT_NEAR(axial.z_mean, (*p.Find("z_1") + *p.Find("z_4")) / 2, 1e-15);
  // rod_j and piston_j at z_j, the ground and the crank at the mean
  for (int l = 0; l < M::kNumLinks; ++l) {
    const std::string name = M::kLinkNames[l];
    const auto us = name.find('_');
    const double expected = us == std::string::npos ? axial.z_mean : *p.Find(("z_" + name.substr(us + 1)).c_str());
    EXPECT_EQ(axial.z(l), expected) << name;
  }
  const double unit = m_rec * r * omega * omega * spacing;
  auto phi = AssemblyPhi<M>();
  double worst = 0, worst_end = 0;
  for (int k = 0; k < 360; ++k) {
    const double t = 2 * kPi * k / 360;
    mech::engine_inline4::Shaking<double> sh;
    ASSERT_TRUE(ShakingAt<M>(p, t, omega, &phi, &sh)) << "theta " << t;
    // the per-link columns add up to the shaking force
    EXPECT_NEAR((sh.F_link.rowwise().sum() - sh.F).norm(), 0.0, 1e-12 * unit / spacing);
    const Eigen::Vector2d m = mechgen::engine::RockingCouple(sh, axial);
    const Eigen::Vector2d m2 = mechgen::engine::RockingCouple(sh.F_link, axial.z, axial.z_mean);
    EXPECT_EQ(m, m2);
    worst = std::max(worst, m.cwiseAbs().maxCoeff());
    // about cylinder 1 the secondary force has an arm: not zero (the test can fail)
    worst_end = std::max(worst_end, mechgen::engine::RockingCouple(sh.F_link, axial.z, *p.Find("z_1")).norm());
  }
  EXPECT_LT(worst, 1e-9 * unit);
  EXPECT_GT(worst_end, 0.1 * unit);
  std::printf("in-line four: max |M| about the middle %.3g N m, about cylinder 1 %.6g N m (m_rec r w^2 a = %.6g N m)\n",
              worst, worst_end, unit);
}

/// The order-1 couple of the model against the two-mass table, the model's cylinders at their
/// z_j; returns the generated forward part (N m).
void ExpectV8MatchesTable(mech::engine_v8::Params<double>& p, double omega, double* generated_fwd,
                          double* analytic_fwd, double* order2) {
  using M = mech::engine_v8::Model;
  const double r = *p.Find("r");
  double m_rec = 0, m_rot = 0;
  TwoMasses(p, &m_rec, &m_rot);
  const auto axial = mechgen::engine::LinkAxialPositions<M>(p);
  ASSERT_TRUE(axial.ok());
  ASSERT_EQ(axial.cylinders, 8);
  // The same engine in the table: throws, banks, z about the reference point (units a = 1 m).
  mechgen::balancing::EngineLayout layout;
  layout.count = 8;
  for (int j = 0; j < 8; ++j) {
    const std::string k = std::to_string(j + 1);
    layout.cylinders[j] = {*p.Find(("gamma_" + k).c_str()), *p.Find(("beta_" + k).c_str()),
                           *p.Find(("z_" + k).c_str()) - axial.z_mean};
  }
  const mechgen::balancing::EngineBalance table = mechgen::balancing::AnalyzeBalance(layout, m_rot / m_rec);
  const double unit = m_rec * r * omega * omega;  // N; moments: N m with a = 1 m
  double max_force = 0;
  const Orders o = CoupleOrders<M>(p, omega, 360, &max_force);
  const C f1 = table.moment[0].forward * unit, b1 = table.moment[0].backward * unit;
  const double scale = std::max(std::abs(f1), std::abs(b1));
  ASSERT_GT(scale, 0.1 * unit * 0.095);  // a couple of the order of m r w^2 times the spacing
  EXPECT_NEAR(std::abs(o.f[1] - f1), 0.0, 1e-8 * scale) << o.f[1] << " vs " << f1;
  EXPECT_NEAR(std::abs(o.b[1] - b1), 0.0, 1e-8 * scale) << o.b[1] << " vs " << b1;
  // The secondary couple is zero, in the table and in the model; so is the total force's
  // primary and secondary (the couple is a free couple: the same about any point).
  EXPECT_LT(table.moment[1].Max(), 1e-12);
  EXPECT_LT(std::abs(o.f[2]) + std::abs(o.b[2]), 1e-10 * scale);
  EXPECT_LT(table.force[0].Max() + table.force[1].Max(), 1e-12);
  std::printf("V8 primary couple: generated forward %.15g N m (backward %.3g), two-mass table %.15g N m "
              "(difference %.2g relative); order 2 %.3g N m; max |F| %.3g N\n",
              std::abs(o.f[1]), std::abs(o.b[1]), std::abs(f1), std::abs(o.f[1] - f1) / scale,
              std::abs(o.f[2]) + std::abs(o.b[2]), max_force);
  *generated_fwd = std::abs(o.f[1]);
  *analytic_fwd = std::abs(f1);
  *order2 = std::abs(o.f[2]) + std::abs(o.b[2]);
}

TEST(EngineCouples, CrossPlaneV8PrimaryCoupleIsTheTwoMassTables) {
  mech::engine_v8::Params<double> p;  // the shipped z_j: 0, pitch, ..., 7 pitch
  double g = 0, a = 0, o2 = 0;
  ExpectV8MatchesTable(p, 300, &g, &a, &o2);
  EXPECT_GT(g, 0);
}

TEST(EngineCouples, CrossPlaneV8TextbookLayoutSqrtTenCouple) {
  // The textbook's cross-plane V8 (engine_balance.h's preset v8_crossplane): the two cylinders of
  // one pin at one z, pins at -1.5, -0.5, 0.5, 1.5 spacings a.
  using namespace mechgen::balancing;
  const auto layouts = EngineLayouts();
  const EngineLayout* v8 = FindLayout(layouts, "v8_crossplane");
  ASSERT_NE(v8, nullptr);
  mech::engine_v8::Params<double> p;
  const double a = 0.095, omega = 250;
  for (int j = 0; j < 8; ++j) {
    const std::string k = std::to_string(j + 1);
    const double g = *p.Find(("gamma_" + k).c_str()), b = *p.Find(("beta_" + k).c_str());
    int found = -1;
    for (int i = 0; i < v8->count; ++i) {
      const Cylinder& c = v8->cylinders[i];
      if (std::abs(std::remainder(c.throw_angle - g, 2 * kPi)) < 1e-12 &&
          std::abs(std::remainder(c.bank_angle - b, 2 * kPi)) < 1e-12)
        found = i;
    }
    ASSERT_GE(found, 0) << "cylinder " << k << " is not in the preset";
    *p.Find(("z_" + k).c_str()) = 0.3 + a * v8->cylinders[found].z;  // middle at 0.3 m
  }
  double generated = 0, analytic = 0, order2 = 0;
  ExpectV8MatchesTable(p, omega, &generated, &analytic, &order2);
  double m_rec = 0, m_rot = 0;
  TwoMasses(p, &m_rec, &m_rot);
  const double closed = (1 + 2 * m_rot / m_rec) * std::sqrt(10.0) * m_rec * *p.Find("r") * omega * omega * a;
  EXPECT_NEAR(generated, closed, 1e-8 * closed);
  std::printf("textbook V8: (1 + 2 m_rot/m_rec) sqrt(10) m_rec r w^2 a = %.12g N m, generated %.12g N m\n", closed,
              generated);
}

/// M about z' recomputed against M about z plus (z - z') z^ x F, where F is not zero.
template <class M>
void ExpectReferenceRule(typename M::template ParamsT<double>& p, double z_ref, double z_ref_new, double omega) {
  auto phi = AssemblyPhi<M>();
  const auto axial = mechgen::engine::LinkAxialPositions<M>(p);
  ASSERT_TRUE(axial.ok());
  double worst = 0, largest_shift = 0, scale = 0;
  for (int k = 0; k < 72; ++k) {
    const double t = 2 * kPi * k / 72 + 0.1;
    typename M::template ShakingT<double> sh;
    ASSERT_TRUE(ShakingAt<M>(p, t, omega, &phi, &sh));
    const Eigen::Vector2d m0 = mechgen::engine::RockingCouple(sh.F_link, axial.z, z_ref);
    const Eigen::Vector2d m1 = mechgen::engine::RockingCouple(sh.F_link, axial.z, z_ref_new);
    const double d = z_ref - z_ref_new;
    const Eigen::Vector2d by_hand(m0(0) - d * sh.F(1), m0(1) + d * sh.F(0));  // + d z^ x F
    scale = std::max(scale, sh.F.norm() * (std::abs(z_ref - axial.z_mean) + std::abs(d) + 0.1));
    worst = std::max(worst, (m1 - by_hand).norm());
    worst = std::max(worst, (m1 - mechgen::engine::ShiftReference(m0, sh.F, z_ref, z_ref_new)).norm());
    largest_shift = std::max(largest_shift, (m1 - m0).norm());
  }
  EXPECT_LT(worst, 1e-12 * scale);
  EXPECT_GT(largest_shift, 1e-2 * scale);  // the couple does depend on the point here
}

TEST(EngineCouples, ReferencePointRuleSingleCylinder) {
  mech::engine_single::Params<double> p;
  *p.Find("z_1") = 0.07;
  ExpectReferenceRule<mech::engine_single::Model>(p, 0.0, 0.25, 400);
}

TEST(EngineCouples, ReferencePointRuleInlineFour) {
  mech::engine_inline4::Params<double> p;  // secondary force 4 m r w^2 lambda cos 2t: not zero
  ExpectReferenceRule<mech::engine_inline4::Model>(p, 0.05, 0.31, 300);
}

TEST(EngineCouples, CrankAxialPositionIsTheCallers) {
  using M = mech::engine_v8::Model;
  mech::engine_v8::Params<double> p;
  const double zc = -0.4;
  const auto axial = mechgen::engine::LinkAxialPositions<M>(p, &zc);
  ASSERT_TRUE(axial.ok());
  EXPECT_EQ(axial.z(0), zc);  // ground
  EXPECT_EQ(axial.z(1), zc);  // crank
  EXPECT_EQ(axial.z(2), *p.Find("z_1"));
  EXPECT_EQ(axial.z(M::kNumLinks - 1), *p.Find("z_8"));
  EXPECT_NEAR(axial.z_mean, 0.3325, 1e-15);
}

TEST(EngineCouples, ModelWithoutAxialPositionsIsRefused) {
  mech::slider_crank::Params<double> p;
  const auto axial = mechgen::engine::LinkAxialPositions<mech::slider_crank::Model>(p);
  EXPECT_FALSE(axial.ok());
  EXPECT_EQ(axial.status, mechgen::engine::AxialStatus::kNoAxialPositions);
  EXPECT_EQ(axial.cylinders, 0);
  EXPECT_NE(std::string(mechgen::engine::ToString(axial.status)).find("z_1"), std::string::npos);
}

TEST(EngineCouples, OrderAmplitudeIsTheLargestMagnitudeOverATurn) {
  // Against a brute-force maximum over the turn and the table's OrderVector::Max().
  const double cases[][4] = {{1, 0, 0, 1}, {1, 0, 0, -1}, {2, 0, 0, 0}, {0.3, -1.2, 0.7, 0.4}, {0, 0, 0, 0}};
  for (const auto& k : cases) {
    double brute = 0;
    for (int i = 0; i < 100000; ++i) {
      const double t = 2 * kPi * i / 100000;
      brute = std::max(brute, std::hypot(k[0] * std::cos(t) + k[1] * std::sin(t), k[2] * std::cos(t) + k[3] * std::sin(t)));
    }
    const double amp = mechgen::engine::CoupleOrderAmplitude(k[0], k[1], k[2], k[3]);
    EXPECT_NEAR(amp, brute, 1e-8 * (1 + brute));
    mechgen::balancing::OrderVector v;
    v.forward = C(k[0] + k[3], k[2] - k[1]) / 2.0;
    v.backward = C(k[0] - k[3], k[2] + k[1]) / 2.0;
    EXPECT_NEAR(v.ax(), k[0], 1e-15);
    EXPECT_NEAR(v.bx(), k[1], 1e-15);
    EXPECT_NEAR(v.ay(), k[2], 1e-15);
    EXPECT_NEAR(v.by(), k[3], 1e-15);
    EXPECT_NEAR(amp, v.Max(), 1e-15);
  }
}

// A model whose links name a cylinder without its z_j.
struct FakeParams {
  double z_1 = 0.1;
  double* Find(const char* name) { return std::string(name) == "z_1" ? &z_1 : nullptr; }
};
struct FakeModel {
  static constexpr int kNumLinks = 5;
  static constexpr std::array<const char*, kNumLinks> kLinkNames{"ground", "crank", "rod_1", "piston_1", "rod_2"};
};

TEST(EngineCouples, LinkWithoutItsCylinderIsRefused) {
  FakeParams p;
  const auto axial = mechgen::engine::LinkAxialPositions<FakeModel>(p);
  EXPECT_EQ(axial.status, mechgen::engine::AxialStatus::kMissingCylinder);
  EXPECT_EQ(axial.bad_link, 4);
  EXPECT_EQ(axial.cylinders, 1);
}

}  // namespace
