// Engine models of tools/make_engine.py (issue 16) against independent oracles:
//  - single cylinder: the reciprocating inertia force of piston and rod from the generated
//    positions, K and L against the two-mass approximation m_rec r w^2 (cos t + lambda cos 2t)
//    plus the rotating part at the pin; its error shrinks like lambda^3 (lambda = r/l), i.e.
//    like lambda^2 relative to the secondary term, for l/r = 3, 4, 6, 10 (set at run time);
//  - in-line four: primary shaking force zero, secondary amplitude 4 m_rec r w^2 A2(lambda)
//    with the textbook series A2 = lambda + lambda^3/4 + 15 lambda^5/128;
//  - the work of the gas over a cycle three ways: the integral of the gas torque (GasTorque
//    through the generated K), the integral of p dV (the law's pressure and the hand-derived
//    piston volume), and the thermodynamic identity of the polytropic cycle;
//  - the steady state against a viscous load: the load's work over the cycle equals the gas's.
// The shaking force is the generated one (`shaking` quantity, EvalShaking), cross-checked
// with the sum of m a_G from the generated positions, K and L.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "engine_inline4.h"
#include "engine_single.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/gas.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The inertia force sum m a_G of the pistons and rods (fixed frame, N) at crank angle theta
/// and constant speed omega: minus the generated shaking force (EvalShaking), checked against
/// the same sum from the generated phi, K, L (crank's centre of mass on O).
template <class M>
bool ReciprocatingForce(typename M::template ParamsT<double>& p, int n, double theta, double omega,
                        Eigen::Matrix<double, M::kNphi, 1>* phi, double* Fx, double* Fy) {
  Eigen::Matrix<double, 1, 1> q;
  q(0) = theta;
  const auto rep = M::Solve(p, q, phi);
  if (rep.status != decltype(rep.status)::kConverged) return false;
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, q, *phi, &c);
  const double r = *p.Find("r"), lG = *p.Find("l_G"), m_rod = *p.Find("m_rod"), m_pis = *p.Find("m_pis");
  const double w2 = omega * omega;
  *Fx = *Fy = 0;
  for (int j = 0; j < n; ++j) {
    const std::string k = std::to_string(j + 1);
    const double g = *p.Find(("gamma_" + k).c_str()), b = *p.Find(("beta_" + k).c_str());
    int is = -1, ir = -1;
    for (int i = 0; i < M::kNphi; ++i) {
      if (("s_slide_" + k) == M::kPhiNames[i]) is = i;
      if (("theta_rod_" + k) == M::kPhiNames[i]) ir = i;
    }
    if (is < 0 || ir < 0) return false;
    const double a = theta + g, f = (*phi)(ir), Kf = c.K(ir, 0), Lf = c.L(ir, 0);
    // piston: d2s/dt2 = L_s w^2 along the axis
    *Fx += m_pis * c.L(is, 0) * w2 * std::cos(b);
    *Fy += m_pis * c.L(is, 0) * w2 * std::sin(b);
    // rod's centre of mass G = B + l_G (cos f, sin f)
    *Fx += m_rod * w2 * (-r * std::cos(a) - lG * (Lf * std::sin(f) + Kf * Kf * std::cos(f)));
    *Fy += m_rod * w2 * (-r * std::sin(a) + lG * (Lf * std::cos(f) - Kf * Kf * std::sin(f)));
  }
  // The generated shaking force is -sum m a_G of every moving link (the crank's centre of
  // mass is on O): it must be the negative of the sum above; the tests use the generated one.
  typename M::template ShakingT<double> sh;
  Eigen::Matrix<double, 1, 1> qd, qdd;
  qd(0) = omega;
  qdd(0) = 0;
  M::Shaking(p, q, *phi, qd, qdd, c, &sh);
  const double scale = (m_rod + m_pis) * n * r * w2;
  EXPECT_NEAR(-sh.F(0), *Fx, 1e-12 * scale) << "theta " << theta;
  EXPECT_NEAR(-sh.F(1), *Fy, 1e-12 * scale) << "theta " << theta;
  *Fx = -sh.F(0);
  *Fy = -sh.F(1);
  return true;
}

TEST(Engine, SingleCylinderTwoMassApproximationErrorShrinksLikeLambdaCubed) {
  using M = mech::engine_single::Model;
  const double omega = 400;
  std::vector<double> lambdas, errors;
  for (double l_over_r : {3.0, 4.0, 6.0, 10.0}) {
    mech::engine_single::Params<double> p;
    const double r = 0.05, l = l_over_r * r, m = 0.6, lG = 0.3 * l;
    *p.Find("r") = r;
    *p.Find("l") = l;
    *p.Find("l_G") = lG;
    *p.Find("m_rod") = m;
    *p.Find("J_rod") = m * lG * (l - lG);  // dynamically equivalent to masses at B and C
    const double m_pis = *p.Find("m_pis");
    // G at l_G from the crank pin B: m_C = m l_G / l at the wrist pin, m_B = m (l - l_G)/l.
    const double m_rec = m_pis + m * lG / l, m_rot = m * (l - lG) / l;
    const double lambda = r / l;
    Eigen::Matrix<double, M::kNphi, 1> phi(0.0, r + l);
    double worst = 0;
    for (int i = 0; i < 360; ++i) {
      const double t = 2 * kPi * i / 360;
      double Fx = 0, Fy = 0;
      ASSERT_TRUE(ReciprocatingForce<M>(p, 1, t, omega, &phi, &Fx, &Fy));
      const double two_mass_x = -m_rec * r * omega * omega * (std::cos(t) + lambda * std::cos(2 * t)) -
                                m_rot * r * omega * omega * std::cos(t);
      const double two_mass_y = -m_rot * r * omega * omega * std::sin(t);
      // Across the axis only the rotating part: exact for the equivalent masses.
      ASSERT_NEAR(Fy, two_mass_y, 1e-9 * m_rot * r * omega * omega) << "theta " << t;
      worst = std::max(worst, std::abs(Fx - two_mass_x) / (m_rec * r * omega * omega));
    }
    // Leading error terms: lambda^3/4 (cos 2t - cos 4t): at most lambda^3/2 relative.
    EXPECT_GT(worst, 0.2 * std::pow(lambda, 3)) << "l/r " << l_over_r;
    EXPECT_LT(worst, 0.6 * std::pow(lambda, 3)) << "l/r " << l_over_r;
    lambdas.push_back(lambda);
    errors.push_back(worst);
  }
  // Relative to the secondary term's amplitude lambda, the error falls like lambda^2.
  for (size_t i = 1; i < lambdas.size(); ++i) {
    const double slope = std::log((errors[i] / lambdas[i]) / (errors[i - 1] / lambdas[i - 1])) /
                         std::log(lambdas[i] / lambdas[i - 1]);
    EXPECT_NEAR(slope, 2.0, 0.15) << "between l/r " << 1 / lambdas[i - 1] << " and " << 1 / lambdas[i];
  }
}

TEST(Engine, InlineFourPrimaryBalancedSecondaryFourTimes) {
  using M = mech::engine_inline4::Model;
  mech::engine_inline4::Params<double> p;
  const double omega = 300, r = *p.Find("r"), l = *p.Find("l"), lG = *p.Find("l_G");
  const double m_rec = *p.Find("m_pis") + *p.Find("m_rod") * lG / l;
  const double lambda = r / l;
  const int n = 720;
  std::vector<std::complex<double>> c(5, 0.0);
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  double max_y = 0;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * i / n;
    double Fx = 0, Fy = 0;
    ASSERT_TRUE(ReciprocatingForce<M>(p, 4, t, omega, &phi, &Fx, &Fy));
    max_y = std::max(max_y, std::abs(Fy));
    for (int k = 1; k <= 4; ++k) c[k] += Fx * std::polar(2.0 / n, -k * t);
  }
  const double unit = m_rec * r * omega * omega;
  EXPECT_LT(max_y, 1e-9 * unit);              // rotating parts at 0, 180, 180, 0 deg cancel
  EXPECT_LT(std::abs(c[1]), 1e-9 * unit);     // primary balanced
  EXPECT_LT(std::abs(c[3]), 1e-9 * unit);
  const double A2 = lambda + std::pow(lambda, 3) / 4 + 15 * std::pow(lambda, 5) / 128;
  EXPECT_NEAR(std::abs(c[2]), 4 * unit * A2, 2e-4 * 4 * unit * A2);
  EXPECT_NEAR(std::abs(c[2]), 4 * unit * lambda, 0.05 * 4 * unit * lambda);  // to leading order
  // secondary in phase with cos 2 theta, pointing to -x at theta = 0 (sum m a = -...)
  EXPECT_NEAR(std::arg(-c[2]), 0.0, 1e-9);
}

/// The work of the gas of engine_single over a cycle by its gas torque through the generated K.
double GasTorqueWork(const mechgen::engine::PolytropicWiebeCycle& law) {
  using M = mech::engine_single::Model;
  mech::engine_single::Params<double> p;
  mechgen::engine::GasTorque<mechgen::engine::PolytropicWiebeCycle> gas;
  gas.law = &law;
  gas.cycle = law.cycle();
  gas.count = 1;
  gas.cylinders[0].slide = 1;  // s_slide_1
  gas.cylinders[0].area = kPi * p.bore * p.bore / 4;
  gas.cylinders[0].phase = p.phase_1;
  EXPECT_STREQ(M::kPhiNames[1], "s_slide_1");
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  auto torque = [&](double t) {
    Eigen::Matrix<double, 1, 1> q;
    q(0) = t;
    M::Solve(p, q, &phi);
    typename M::template CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    return gas.Torque(t, c.K);
  };
  // Composite 5-point Gauss-Legendre between the law's kinks and jumps (BDCs, burn start).
  static const double x[5] = {0.0, 0.5384693101056831, -0.5384693101056831, 0.9061798459386640,
                              -0.9061798459386640};
  static const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                              0.2369268850561891, 0.2369268850561891};
  std::vector<double> breaks = {0, kPi, law.cycle()};
  if (law.cycle() > 2 * kPi + 1) breaks = {0, kPi, 2 * kPi, 3 * kPi, 4 * kPi};
  breaks.push_back(law.params().burn_start + law.cycle());
  breaks.push_back(law.params().burn_start + law.params().burn_duration);
  std::sort(breaks.begin(), breaks.end());
  double W = 0;
  for (size_t b = 0; b + 1 < breaks.size(); ++b) {
    const int panels = 400;
    const double h = (breaks[b + 1] - breaks[b]) / panels;
    for (int k = 0; k < panels; ++k) {
      const double c0 = breaks[b] + (k + 0.5) * h;
      for (int i = 0; i < 5; ++i) W += w[i] * torque(c0 + 0.5 * h * x[i]) * 0.5 * h;
    }
  }
  return W;
}

/// The integral of p dV over the cycle from the law and the hand-derived volume of a centred
/// slider-crank: V' = A (r sin a + r^2 sin a cos a / sqrt(l^2 - r^2 sin^2 a)).
double PdVWork(const mechgen::engine::PolytropicWiebeCycle& law, double A, double r, double l) {
  const int n = 400000;
  const double h = law.cycle() / n;
  double W = 0;
  for (int i = 0; i < n; ++i) {  // midpoint rule, the jumps on panel edges
    const double a = (i + 0.5) * h, s = std::sin(a);
    W += law.Pressure(a) * A * (r * s + r * r * s * std::cos(a) / std::sqrt(l * l - r * r * s * s)) * h;
  }
  return W;
}

TEST(Engine, GasWorkThreeWays) {
  mech::engine_single::Params<double> p;
  for (int strokes : {4, 2}) {
    for (double heat : {800.0, 0.0}) {
      mechgen::engine::PolytropicWiebeParams P;
      P.strokes = strokes;
      P.bore = p.bore;
      P.stroke = 2 * p.r;
      P.rod_length = p.l;
      P.heat = heat;
      mechgen::engine::PolytropicWiebeCycle law;
      std::string error;
      ASSERT_TRUE(law.Init(P, &error)) << error;
      // Thermodynamics: over the closed part p dV = dQ - d(pV)/(n - 1); the four-stroke's
      // pumping loop (p_in - p_amb) V_d.
      const double Vb = law.Volume(kPi), p_end = law.ClosedPressure(kPi);
      double W_thermo = heat * law.Burned(kPi) - (p_end - P.p_intake) * Vb / (P.n - 1);
      if (strokes == 4) W_thermo += (P.p_intake - P.p_ambient) * law.displacement();
      const double W_torque = GasTorqueWork(law);
      const double W_pdv = PdVWork(law, law.area(), p.r, p.l);
      const double scale = std::max(std::abs(W_thermo), 1.0);
      EXPECT_NEAR(W_torque, W_thermo, 1e-8 * scale) << strokes << "-stroke, Q = " << heat;
      EXPECT_NEAR(W_pdv, W_thermo, 1e-5 * scale) << strokes << "-stroke, Q = " << heat;
      if (heat == 0 && strokes == 2) {
        EXPECT_NEAR(W_torque, 0.0, 1e-8);
      }
    }
  }
  // Otto's limit: a burn of 0.1 deg at TDC gives W = Q (1 - eps^(1 - n)).
  mechgen::engine::PolytropicWiebeParams P;
  P.bore = p.bore;
  P.stroke = 2 * p.r;
  P.rod_length = p.l;
  P.burn_start = -0.05 * kPi / 180;
  P.burn_duration = 0.1 * kPi / 180;
  P.wiebe_a = 30;  // burned to 1 - e^-30
  P.p_intake = P.p_ambient;
  mechgen::engine::PolytropicWiebeCycle law;
  std::string error;
  ASSERT_TRUE(law.Init(P, &error)) << error;
  const double otto = P.heat * (1 - std::pow(P.compression_ratio, 1 - P.n));
  EXPECT_NEAR(GasTorqueWork(law), otto, 1e-4 * otto);
}

TEST(Engine, SteadyCycleLoadBalancesTheGas) {
  using M = mech::engine_single::Model;
  mech::engine_single::Params<double> p;
  mechgen::engine::PolytropicWiebeParams P;
  P.bore = p.bore;
  P.stroke = 2 * p.r;
  P.rod_length = p.l;
  mechgen::engine::PolytropicWiebeCycle law;
  std::string error;
  ASSERT_TRUE(law.Init(P, &error)) << error;
  using Gas = mechgen::engine::GasTorque<mechgen::engine::PolytropicWiebeCycle>;
  Gas gas;
  gas.law = &law;
  gas.cycle = law.cycle();
  gas.count = 1;
  gas.cylinders[0] = {1, kPi * p.bore * p.bore / 4, p.phase_1};
  const double W_gas = GasTorqueWork(law);  // J per cycle (checked above)
  const double omega = 250;
  p.c_load = W_gas / law.cycle() / omega;  // mean gas torque / omega
  mechgen::dynamics::MinimalOptions mo;
  mo.integrator.rtol = 1e-10;
  mo.integrator.atol = 1e-10;
  mechgen::engine::GasDriven<M, Gas> sim(p, mo, {gas});
  mechgen::engine::SteadyCycleOptions so;
  so.cycle = law.cycle();
  so.omega_guess = 0.8 * omega;  // start away from the answer
  so.samples = 8000;
  const auto sc = mechgen::engine::FindSteadyCycle(&sim, so);
  ASSERT_TRUE(sc.ok) << sc.message;
  // Over a periodic cycle the kinetic energy returns: the load's work c int(w dtheta) = W_gas.
  double W_load = 0;
  for (size_t i = 0; i + 1 < sc.points.size(); ++i) {
    const auto &a = sc.points[i], &b = sc.points[i + 1];
    W_load += 0.5 * p.c_load * (a.omega * a.omega + b.omega * b.omega) * (b.t - a.t);
  }
  const auto& last = sc.points.back();
  EXPECT_NEAR(last.theta, so.theta0 + so.cycle, 1e-6);
  EXPECT_NEAR(last.omega, sc.omega0, 1e-7 * sc.omega0);
  EXPECT_NEAR(W_load, W_gas, 1e-5 * W_gas);
  // The mean speed is the load line's: c w_mean = mean gas torque, to O(C_s^2).
  EXPECT_NEAR(sc.omega_mean_time, omega, sc.Cs * sc.Cs * omega);
  EXPECT_GT(sc.Cs, 0.0);
}

}  // namespace
