// machines/balancing/engine_balance.h against (1) the classical balance facts of multi-cylinder engines
// (Taylor, *The Internal-Combustion Engine in Theory and Practice*, vol. 2, the chapter on
// engine balance; the same table is in most machine-dynamics texts), with the amplitudes
// derived by hand in the comments, and (2) an independent time-domain route: the per-cylinder two-mass forces
// summed as real x, y components over a turn, and their moments, analysed by machines/engine/harmonics.h.
// The analytic route sums rotating complex vectors instead; the two must agree to rounding.
// (3) The exact slider-crank kinematics: its first order is exactly the two-mass primary, its
// second order is λ (1 + λ²/4 + 15λ⁴/128 + 35λ⁶/512 + …), the known series.
#include "mechgen/machines/balancing/engine_balance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "mechgen/machines/engine/harmonics.h"

namespace {

namespace bal = mechgen::balancing;
using mechgen::engine::Analyze;
using mechgen::engine::Harmonic;
using mechgen::engine::HarmonicsStatus;
constexpr double kPi = 3.14159265358979323846;

const bal::EngineLayout& Layout(const char* name) {
  static const auto all = bal::EngineLayouts();
  const bal::EngineLayout* e = bal::FindLayout(all, name);
  EXPECT_NE(e, nullptr) << name;
  return *e;
}

// The classical table. Amplitudes in m r ω² (primary force), m r ω² λ (secondary), times a
// (the cylinder spacing) for moments about the middle of the engine.
//  - single: primary m r ω² cos θ, secondary m r ω² λ cos 2θ, both on the cylinder axis.
//  - in-line 4, flat crank: Σ e^{iα} = 1 − 1 − 1 + 1 = 0, Σ z e^{iα} = −1.5 + 0.5 − 0.5 + 1.5 = 0;
//    Σ e^{2iα} = 4: secondary force 4 m r ω² λ cos 2θ; Σ z e^{2iα} = Σ z = 0.
//  - in-line 3: Σ e^{iα} = 0 over 0, 120, 240; Σ z e^{iα} = −1 + e^{i240°}, |·| = √3, and the
//    same for e^{2iα}: primary and secondary couples √3 m r ω² a and √3 m r ω² λ a.
//  - in-line 6: two mirrored threes: everything zero.
//  - V8 90° cross-plane: each pin's pair gives the rotating e^{i(θ + α)} (backward terms
//    e^{i(2β − α)} cancel between β = ±45°); Σ z e^{iα} = −1.5 − 0.5i − 0.5(−i)… = −3 − i,
//    |·| = √10: a primary couple √10 m r ω² a of constant length turning with the crank;
//    secondary: Σ e^{2iα} = 0 and Σ z e^{2iα} = −1.5 + 0.5 − 0.5 + 1.5 = 0.
//  - boxer 4: opposed pistons cancel both orders' forces and the primary couple; the
//    secondary couple is 2 m r ω² λ a (pairs at z = ±1.5 and ±0.5 with alternating signs).
//  - V-twin 90°, common pin: primary m r ω² of constant length, rotating (b_1 = ½(e^{i90°} +
//    e^{−i90°}) = 0); secondary √2 m r ω² λ on the horizontal line (f_2 = cos 45°, b_2 = −cos 45°).
struct Expected {
  const char* name;
  double force1, force2, moment1, moment2;  // max over a turn (0: balanced)
  bal::OrderKind kind1;                     // of the primary force, or couple if force is 0
};

TEST(EngineBalance, ClassicalBalanceTable) {
  const double r3 = std::sqrt(3.0), r10 = std::sqrt(10.0), r2 = std::sqrt(2.0);
  const Expected table[] = {
      {"single", 1, 1, 0, 0, bal::OrderKind::kLine},
      {"inline2_360", 2, 2, 0, 0, bal::OrderKind::kLine},
      {"inline2_180", 0, 2, 1, 0, bal::OrderKind::kLine},
      {"inline3", 0, 0, r3, r3, bal::OrderKind::kLine},
      {"inline4", 0, 4, 0, 0, bal::OrderKind::kBalanced},
      {"inline6", 0, 0, 0, 0, bal::OrderKind::kBalanced},
      {"v8_crossplane", 0, 0, r10, 0, bal::OrderKind::kRotating},
      {"boxer4", 0, 0, 0, 2, bal::OrderKind::kBalanced},
      {"vtwin90", 1, r2, 0, 0, bal::OrderKind::kRotating},
  };
  for (const Expected& x : table) {
    const bal::EngineBalance b = bal::AnalyzeBalance(Layout(x.name));
    EXPECT_NEAR(b.force[0].Max(), x.force1, 1e-14) << x.name;
    EXPECT_NEAR(b.force[1].Max(), x.force2, 1e-14) << x.name;
    EXPECT_NEAR(b.moment[0].Max(), x.moment1, 1e-14) << x.name;
    EXPECT_NEAR(b.moment[1].Max(), x.moment2, 1e-14) << x.name;
    const bal::OrderVector& primary = x.force1 > 0 ? b.force[0] : b.moment[0];
    EXPECT_EQ(bal::Classify(primary), x.kind1) << x.name;
  }
  // In-line five, firing order 1-2-4-5-3 (throws 0, 216, 144, 72, 288 at z = −2..2): forces
  // balanced; Σ z e^{iα} = −2 − e^{i216°} + e^{i72°} + 2 e^{i288°} = −0.264 − 0.363i, |·| = 0.449;
  // Σ z e^{2iα} = −2 − e^{i72°} + e^{i144°} + 2 e^{i216°} = −4.736 − 1.539i, |·| = 4.980: the
  // widely quoted 0.449 m r ω² a and 4.98 m r ω² (r/l) a of the five-cylinder engine.
  const bal::EngineBalance i5 = bal::AnalyzeBalance(Layout("inline5"));
  EXPECT_NEAR(i5.force[0].Max(), 0, 1e-14);
  EXPECT_NEAR(i5.force[1].Max(), 0, 1e-14);
  EXPECT_NEAR(i5.moment[0].Max(), 0.449, 0.0005);
  EXPECT_NEAR(i5.moment[1].Max(), 4.98, 0.005);
  EXPECT_EQ(bal::Classify(i5.moment[0]), bal::OrderKind::kLine);
  // V6 60° with common pins: forces balanced, both couples not.
  const bal::EngineBalance v6 = bal::AnalyzeBalance(Layout("v6_60_common"));
  EXPECT_NEAR(v6.force[0].Max(), 0, 1e-14);
  EXPECT_NEAR(v6.force[1].Max(), 0, 1e-14);
  EXPECT_GT(v6.moment[0].Max(), 1);
  EXPECT_GT(v6.moment[1].Max(), 1);
  // Secondary of the V-twin lies on the horizontal (y) line: x-coefficients zero.
  const bal::EngineBalance vt = bal::AnalyzeBalance(Layout("vtwin90"));
  EXPECT_NEAR(vt.force[1].ax(), 0, 1e-15);
  EXPECT_NEAR(vt.force[1].bx(), 0, 1e-15);
  // A rotating mass at the pin adds to the primary: the single with m_rot = m has
  // 1.5 forward + 0.5 backward, max 2 m r ω² (both masses along x at θ = 0).
  EXPECT_NEAR(bal::AnalyzeBalance(Layout("single"), 1.0).force[0].Max(), 2, 1e-15);
  EXPECT_NEAR(bal::AnalyzeBalance(Layout("inline4"), 1.0).force[0].Max(), 0, 1e-15);
}

// The time-domain route: per cylinder, the reciprocating mass's force m r ω² (cos ψ + λ cos 2ψ)
// along (cos β, sin β) and the rotating mass's m_rot r ω² (cos(θ + α), sin(θ + α)), summed in x
// and y, with moments M_x = −Σ z F_y, M_y = Σ z F_x; DFT of the four components over a turn.
void TimeDomain(const bal::EngineLayout& e,
                double lambda,
                double rho,
                bool exact,
                int n,
                std::vector<double>* Fx,
                std::vector<double>* Fy,
                std::vector<double>* Mx,
                std::vector<double>* My) {
  Fx->assign(n, 0);
  Fy->assign(n, 0);
  Mx->assign(n, 0);
  My->assign(n, 0);
  for (int k = 0; k < n; ++k) {
    const double theta = 0.1 + 2 * kPi * k / n;
    for (int j = 0; j < e.count; ++j) {
      const bal::Cylinder& c = e.cylinders[j];
      const double psi = theta + c.throw_angle - c.bank_angle;
      double along = 0;  // −(piston acceleration)/(r ω²): the inertia force along the axis
      if (exact) {
        // x = r cos ψ + l √(1 − λ² sin² ψ): d²x/dψ² = −r [cos ψ + λ (cos 2ψ/S + λ² sin² 2ψ/(4 S³))].
        const double S = std::sqrt(1 - lambda * lambda * std::sin(psi) * std::sin(psi));
        along = std::cos(psi) +
                lambda * (std::cos(2 * psi) / S + lambda * lambda * std::pow(std::sin(2 * psi), 2) / (4 * S * S * S));
      } else {
        along = std::cos(psi) + lambda * std::cos(2 * psi);
      }
      const double fx = along * std::cos(c.bank_angle) + rho * std::cos(theta + c.throw_angle);
      const double fy = along * std::sin(c.bank_angle) + rho * std::sin(theta + c.throw_angle);
      (*Fx)[k] += fx;
      (*Fy)[k] += fy;
      (*Mx)[k] -= c.z * fy;
      (*My)[k] += c.z * fx;
    }
  }
}

TEST(EngineBalance, AnalyticAgreesWithTimeDomainHarmonicsForEveryLayout) {
  const int n = 64;
  const double lambda = 0.3, rho = 0.4;
  for (const bal::EngineLayout& e : bal::EngineLayouts()) {
    const bal::EngineBalance b = bal::AnalyzeBalance(e, rho);
    std::vector<double> comp[4];
    TimeDomain(e, lambda, rho, false, n, &comp[0], &comp[1], &comp[2], &comp[3]);
    Harmonic h[4][4];
    for (int c = 0; c < 4; ++c) ASSERT_EQ(Analyze(comp[c].data(), n, 2 * kPi, 0.1, 4, h[c]), HarmonicsStatus::kOk);
    for (int order = 1; order <= 2; ++order) {
      const double unit = order == 1 ? 1 : lambda;
      const bal::OrderVector& F = b.force[order - 1];
      const bal::OrderVector& M = b.moment[order - 1];
      // x, y of the force and the moment vector: (ax, bx), (ay, by).
      EXPECT_NEAR(h[0][order].a, unit * F.ax(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[0][order].b, unit * F.bx(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[1][order].a, unit * F.ay(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[1][order].b, unit * F.by(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[2][order].a, unit * M.ax(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[2][order].b, unit * M.bx(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[3][order].a, unit * M.ay(), 1e-13) << e.name << " order " << order;
      EXPECT_NEAR(h[3][order].b, unit * M.by(), 1e-13) << e.name << " order " << order;
      // The ellipse's semi-axes are the singular values of [[ax, bx], [ay, by]].
      const double a = h[0][order].a, bb = h[0][order].b, c = h[1][order].a, d = h[1][order].b;
      const double s1 = std::hypot(a + d, c - bb), s2 = std::hypot(a - d, c + bb);
      EXPECT_NEAR(0.5 * (s1 + s2), unit * F.Max(), 1e-13) << e.name;
      EXPECT_NEAR(0.5 * std::abs(s1 - s2), unit * F.Min(), 1e-13) << e.name;
    }
    // No mean and no third order in the two-mass model.
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(h[c][0].a, 0, 1e-13) << e.name;
      EXPECT_NEAR(h[c][3].amplitude, 0, 1e-13) << e.name;
    }
  }
}

// The exact kinematics of the slider-crank against the two-mass approximation: the primary is
// exact; the secondary is λ A₂/λ with A₂/λ = 1 + λ²/4 + 15λ⁴/128 + 35λ⁶/512 + O(λ⁸).
TEST(EngineBalance, ExactKinematicsPrimaryExactSecondaryFollowsTheSeries) {
  const int n = 256;
  for (double lambda : {0.1, 0.2, 0.3}) {
    for (const char* name : {"single", "inline4", "vtwin90"}) {
      const bal::EngineBalance b = bal::AnalyzeBalance(Layout(name));
      std::vector<double> Fx, Fy, Mx, My;
      TimeDomain(Layout(name), lambda, 0, true, n, &Fx, &Fy, &Mx, &My);
      Harmonic hx[3], hy[3];
      ASSERT_EQ(Analyze(Fx.data(), n, 2 * kPi, 0.1, 3, hx), HarmonicsStatus::kOk);
      ASSERT_EQ(Analyze(Fy.data(), n, 2 * kPi, 0.1, 3, hy), HarmonicsStatus::kOk);
      EXPECT_NEAR(hx[1].a, b.force[0].ax(), 1e-13) << name;
      EXPECT_NEAR(hy[1].b, b.force[0].by(), 1e-13) << name;
      const double series =
          1 + std::pow(lambda, 2) / 4 + 15 * std::pow(lambda, 4) / 128 + 35 * std::pow(lambda, 6) / 512;
      // Each cylinder's exact second order is A₂ cos 2ψ: every coefficient scales by A₂/λ.
      const double tolerance = std::pow(lambda, 8) * lambda * b.force[1].Max();
      EXPECT_NEAR(hx[2].a, lambda * series * b.force[1].ax(), tolerance) << name << lambda;
      EXPECT_NEAR(hx[2].b, lambda * series * b.force[1].bx(), tolerance) << name << lambda;
      EXPECT_NEAR(hy[2].a, lambda * series * b.force[1].ay(), tolerance) << name << lambda;
      EXPECT_NEAR(hy[2].b, lambda * series * b.force[1].by(), tolerance) << name << lambda;
      EXPECT_GT(std::abs(series - 1), 100 * std::pow(lambda, 8));  // the series term matters
    }
  }
}

// Counterweights on the crank (BalancePrimaryForward) put into the time-domain sums as rotating masses: the V-twin's
// primary force and the cross-plane V8's primary couple vanish at every crank angle; the single keeps a force of
// constant length ½ m r ω² (the backward half, which a counterweight cannot reach).
TEST(EngineBalance, CrankCounterweightsCancelTheRotatingPrimary) {
  struct Case {
    const char* name;
    double force_left, moment_left;  // |F|, |M| of the primary after the counterweights, at every angle
  };
  for (const Case& c : {Case{"vtwin90", 0, 0}, Case{"v8_crossplane", 0, 0}, Case{"single", 0.5, 0}}) {
    const bal::EngineLayout& e = Layout(c.name);
    const bal::PrimaryCounterweights w = bal::BalancePrimaryForward(bal::AnalyzeBalance(e), 2.0);
    for (int k = 0; k < 72; ++k) {
      const double theta = 0.05 + 2 * kPi * k / 72;
      double Fx = 0, Fy = 0, Mx = 0, My = 0;
      auto add = [&](double fx, double fy, double z) {
        Fx += fx;
        Fy += fy;
        Mx -= z * fy;
        My += z * fx;
      };
      for (int j = 0; j < e.count; ++j) {
        const bal::Cylinder& cyl = e.cylinders[j];
        const double along = std::cos(theta + cyl.throw_angle - cyl.bank_angle);  // primary only
        add(along * std::cos(cyl.bank_angle), along * std::sin(cyl.bank_angle), cyl.z);
      }
      for (const bal::Counterweight& cw : {w.force, w.couple[0], w.couple[1]})
        add(cw.mr * std::cos(theta + cw.angle), cw.mr * std::sin(theta + cw.angle), cw.z);
      EXPECT_NEAR(std::hypot(Fx, Fy), c.force_left, 1e-14) << c.name << " " << theta;
      EXPECT_NEAR(std::hypot(Mx, My), c.moment_left, 1e-14) << c.name << " " << theta;
    }
  }
  // The V8's couple counterweights: √10 / (2 · 2) m r each at z = ±2 a.
  const bal::PrimaryCounterweights v8 = bal::BalancePrimaryForward(bal::AnalyzeBalance(Layout("v8_crossplane")), 2.0);
  EXPECT_NEAR(v8.couple[0].mr, std::sqrt(10.0) / 4, 1e-15);
  EXPECT_NEAR(v8.force.mr, 0, 1e-15);
}

TEST(EngineBalance, TablePrintsEveryLayout) {
  std::ostringstream text, csv;
  bal::PrintBalanceTable(bal::EngineLayouts(), text);
  bal::PrintBalanceTable(bal::EngineLayouts(), csv, true);
  std::printf("%s\n%s", text.str().c_str(), csv.str().c_str());
  for (const bal::EngineLayout& e : bal::EngineLayouts()) {
    EXPECT_NE(text.str().find(e.name), std::string::npos);
    EXPECT_NE(csv.str().find(std::string("\n") + e.name + ","), std::string::npos);
  }
  EXPECT_NE(csv.str().find("inline4,4,0,0,balanced,4,0,line,0,0,balanced,0,0,balanced"), std::string::npos);
}

}  // namespace
