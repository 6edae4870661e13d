// The runtime (mechgen/dynamics) on generated models, against independent oracles:
//  - fourbar_massive against the massive four-bar written by hand (closed forms, Newton–Euler):
//    the generated I, I', Q, T, V and kinetostatics, then whole simulations;
//  - pendulum (kNphi = 0): the period of a large swing against the complete elliptic integral
//    (K(k) by the arithmetic–geometric mean), by simulation and by the energy integral;
//  - slider_crank_torque from rest: 1/2 I(th) thd^2 = M (th - th0) along the run (Paul §6.5);
//  - inverse then forward dynamics on fourbar_massive.
#include <cmath>

#include <gtest/gtest.h>

#include "dynamics_test_util.h"
#include "fourbar_massive.h"
#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/energy.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "pendulum.h"
#include "slider_crank_torque.h"

namespace {

namespace hw = mech::handwritten_fourbar_dynamics;
namespace fm = mech::fourbar_massive;
using mechgen::dynamics::Dop853;
using mechgen::dynamics::Dopri5;
using mechgen::dynamics::MinimalDynamics;
using mechgen::dynamics::MinimalOptions;
using mechgen::dynamics::MinimalSummary;
using mechgen::dynamics::Status;
using Vec1 = Eigen::Matrix<double, 1, 1>;
constexpr double kPi = 3.14159265358979323846;

TEST(MinimalGenerated, FourbarMassiveMatchesTheHandwrittenModel) {
  const fm::Params<double> pg;
  const hw::Params<double> ph;
  for (double q = 0.05; q < 2 * kPi; q += 0.4) {
    Eigen::Vector2d phi_g(0.5, 1.9), phi_h(0.5, 1.9);
    ASSERT_EQ(fm::Model::Solve(pg, Vec1(q), &phi_g).status, fm::SolveStatus::kConverged);
    ASSERT_EQ(hw::Model::Solve(ph, Vec1(q), &phi_h).status, hw::SolveStatus::kConverged);
    EXPECT_NEAR(phi_g(0), phi_h(0), 1e-12);
    EXPECT_NEAR(phi_g(1), phi_h(1), 1e-12);
    fm::Coefficients<double> cg;
    hw::Coefficients<double> ch;
    fm::Model::Coeffs(pg, Vec1(q), phi_g, &cg);
    hw::Model::Coeffs(ph, Vec1(q), phi_h, &ch);
    const Vec1 qd(1.7), qdd(-0.9);
    fm::Dynamics<double> dg;
    hw::Dynamics<double> dh;
    fm::Model::Dynamics(pg, Vec1(q), phi_g, qd, 0.0, cg, &dg);
    hw::Model::Dynamics(ph, Vec1(q), phi_h, qd, 0.0, ch, &dh);
    const double tol = 1e-10 * (1 + std::abs(dh.I(0, 0)));
    EXPECT_NEAR(dg.I(0, 0), dh.I(0, 0), tol) << "q = " << q;
    EXPECT_NEAR(dg.dI_dq(0, 0), dh.dI_dq(0, 0), tol) << "q = " << q;
    EXPECT_NEAR(dg.h(0), dh.h(0), tol) << "q = " << q;
    EXPECT_NEAR(dg.Q(0), dh.Q(0), 1e-10 * (1 + std::abs(dh.Q(0)))) << "q = " << q;
    EXPECT_NEAR(dg.T, dh.T, tol);
    EXPECT_NEAR(dg.V, dh.V, 1e-10 * (1 + std::abs(dh.V)));
    EXPECT_NEAR(dg.P_nc, 0.0, 1e-12);
    fm::Statics<double> kg;
    hw::Statics<double> kh;
    fm::Model::Kinetostatics(pg, Vec1(q), phi_g, qd, qdd, 0.0, cg, &kg);
    hw::Model::Kinetostatics(ph, Vec1(q), phi_h, qd, qdd, 0.0, ch, &kh);
    EXPECT_NEAR(kg.drive(0), kh.drive(0), 1e-9 * (1 + std::abs(kh.drive(0)))) << "q = " << q;
    ASSERT_EQ(fm::Model::kNumReactions, hw::Model::kNumReactions);
    for (int r = 0; r < hw::Model::kNumReactions; ++r) {
      EXPECT_STREQ(fm::Model::kReactionNames[r], hw::Model::kReactionNames[r]);
      EXPECT_NEAR(kg.R(r), kh.R(r), 1e-9 * (1 + kh.R.cwiseAbs().maxCoeff()))
          << fm::Model::kReactionNames[r] << " at q = " << q;
    }
  }
}

template <class M, template <int> class Method>
double ThetaAt3s(double rtol, double* energy_error) {
  MinimalOptions o;
  o.integrator.rtol = rtol;
  o.integrator.atol = rtol * 1e-2;
  MinimalDynamics<M, Method> sim(typename M::template ParamsT<double>(), o);
  EXPECT_TRUE(sim.Initialize(Vec1(kPi / 2)));
  MinimalSummary summary;
  mechgen::dynamics::Sample<M> last;
  EXPECT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 3.0, [](const auto&) { return true; },
                           &summary, &last))
      << mechgen::dynamics::FormatSummary(summary);
  *energy_error = summary.max_energy_error;
  return last.q(0);
}

TEST(MinimalGenerated, FourbarMassiveSimulationMatchesTheHandwrittenOne) {
  double e_g = 0, e_h = 0;
  const double th_g5 = ThetaAt3s<fm::Model, Dopri5>(1e-11, &e_g);
  const double th_h5 = ThetaAt3s<hw::Model, Dopri5>(1e-11, &e_h);
  EXPECT_NEAR(th_g5, th_h5, 1e-9);
  EXPECT_LT(e_g, 1e-6);
  const double th_g8 = ThetaAt3s<fm::Model, Dop853>(1e-12, &e_g);
  const double th_h8 = ThetaAt3s<hw::Model, Dop853>(1e-12, &e_h);
  EXPECT_NEAR(th_g8, th_h8, 1e-9);
  EXPECT_LT(e_g, 1e-7);
  // Both integrators converge to the same theta(3 s).
  EXPECT_NEAR(th_g5, th_g8, 1e-7);
}

// The pendulum's period: T = 4 sqrt(I_O / (m g lc)) K(sin(theta0 / 2)), theta0 the amplitude
// from the hanging position (-90 deg), I_O = J + m lc^2.
TEST(MinimalGenerated, PendulumPeriodIsTheEllipticIntegral) {
  const mech::pendulum::Params<double> p;
  const double I_O = p.J + p.m * p.lc * p.lc, mglc = p.m * p.g * p.lc;
  for (double amplitude_deg : {10.0, 60.0, 120.0, 170.0}) {
    const double amplitude = amplitude_deg * kPi / 180;
    const double exact = dynamics_test::PendulumPeriod(I_O, mglc, amplitude);
    const double q0 = -kPi / 2 + amplitude;  // released from rest at the amplitude
    MinimalOptions o;
    o.integrator.rtol = 1e-12;
    o.integrator.atol = 1e-14;
    o.stop_at_speed_zero = true;
    MinimalDynamics<mech::pendulum::Model, Dop853> sim(p, o);
    ASSERT_TRUE(sim.Initialize(Vec1(q0)));
    MinimalSummary summary;
    mechgen::dynamics::Sample<mech::pendulum::Model> last;
    ASSERT_TRUE(sim.Simulate(0.0, Vec1(q0), Vec1(0.0), 100.0, [](const auto&) { return true; },
                             &summary, &last))
        << mechgen::dynamics::FormatSummary(summary);
    ASSERT_EQ(summary.event, mechgen::dynamics::Event::kSpeedZero);
    EXPECT_NEAR(2 * summary.t_end, exact, 1e-8 * exact) << amplitude_deg << " deg";
    EXPECT_NEAR(last.q(0), -kPi / 2 - amplitude, 1e-7);
    // The energy integral's quadrature agrees too.
    mechgen::dynamics::EnergyIntegral<mech::pendulum::Model> energy(p);
    ASSERT_TRUE(energy.Initialize(q0, 0.0, Eigen::Matrix<double, 0, 1>()));
    double period = 0;
    ASSERT_TRUE(energy.SwingPeriod(2 * kPi, 100, &period));
    EXPECT_NEAR(period, exact, 1e-9 * exact) << amplitude_deg << " deg";
  }
}

TEST(MinimalGenerated, PendulumDopri5Period) {
  const mech::pendulum::Params<double> p;
  const double I_O = p.J + p.m * p.lc * p.lc, mglc = p.m * p.g * p.lc;
  const double amplitude = 1.0;
  const double exact = dynamics_test::PendulumPeriod(I_O, mglc, amplitude);
  MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-13;
  o.stop_at_speed_zero = true;
  MinimalDynamics<mech::pendulum::Model, Dopri5> sim(p, o);
  ASSERT_TRUE(sim.Initialize(Vec1(-kPi / 2 + amplitude)));
  MinimalSummary summary;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(-kPi / 2 + amplitude), Vec1(0.0), 100.0,
                           [](const auto&) { return true; }, &summary));
  EXPECT_NEAR(2 * summary.t_end, exact, 1e-8 * exact);
}

// Constant crank torque M from rest, no gravity, no friction: 1/2 I(th) thd^2 = M (th - th0).
TEST(MinimalGenerated, SliderCrankTorqueObeysTheEnergyIntegral) {
  namespace sc = mech::slider_crank_torque;
  const sc::Params<double> p;
  const double th0 = sc::Model::kAssemblyQ[0];
  for (int method = 0; method < 2; ++method) {
    MinimalOptions o;
    o.integrator.rtol = 1e-11;
    o.integrator.atol = 1e-13;
    o.sample_dt = 0.01;
    MinimalSummary summary;
    int rows = 0;
    double max_rel = 0, th_end = th0;
    auto check = [&](const auto& s) {
      const double work = p.M * (s.q(0) - th0);
      max_rel = std::max(max_rel, std::abs(s.T - work) / (1 + work));
      th_end = s.q(0);
      ++rows;
      return true;
    };
    if (method == 0) {
      MinimalDynamics<sc::Model, Dopri5> sim(p, o);
      ASSERT_TRUE(sim.Initialize(Vec1(th0)));
      ASSERT_TRUE(sim.Simulate(0.0, Vec1(th0), Vec1(0.0), 3.0, check, &summary))
          << mechgen::dynamics::FormatSummary(summary);
    } else {
      MinimalDynamics<sc::Model, Dop853> sim(p, o);
      ASSERT_TRUE(sim.Initialize(Vec1(th0)));
      ASSERT_TRUE(sim.Simulate(0.0, Vec1(th0), Vec1(0.0), 3.0, check, &summary))
          << mechgen::dynamics::FormatSummary(summary);
    }
    EXPECT_EQ(rows, 301);
    EXPECT_GT(th_end - th0, 4 * kPi);  // it spun up through several revolutions
    // Global error: ~ (number of steps) x rtol.
    EXPECT_LT(max_rel, 1e-7) << "method " << method;
  }
}

// Inverse then forward on the generated model: the drive of a prescribed motion from
// EvalKinetostatics, applied as a torque, reproduces the motion.
struct Prescribed {
  static double q(double t) { return 0.3 + 2.0 * t + 0.4 * std::sin(3.0 * t); }
  static double qd(double t) { return 2.0 + 1.2 * std::cos(3.0 * t); }
  static double qdd(double t) { return -3.6 * std::sin(3.0 * t); }
};

struct DrivenFourbarMassive : fm::Model {
  template <typename Scalar>
  static void Dynamics(const fm::Params<Scalar>& p, const fm::Vec<Scalar, 1>& q,
                       const fm::Vec<Scalar, 2>& phi, const fm::Vec<Scalar, 1>& qd,
                       const Scalar& t, const fm::Coefficients<Scalar>& c,
                       fm::Dynamics<Scalar>* out, const void* = nullptr,
                       const fm::Trig<Scalar>* trig = nullptr) {
    fm::EvalDynamics(p, q, phi, qd, t, c, out, nullptr, trig);
    out->Q(0) += Drive(p, t);
  }
  // The stages' one-pass right-hand side (MinimalDynamics uses it where it is generated):
  // the same drive added.
  template <typename Scalar>
  static fm::SolveReport<Scalar> Rhs(const fm::Params<Scalar>& p, const fm::RhsConstants<Scalar>& rc,
                                     const fm::Vec<Scalar, 1>& q, const fm::Vec<Scalar, 1>& qd,
                                     const Scalar& t, const std::array<int, 1>& modes,
                                     fm::Trig<Scalar>* trig, fm::Rhs<Scalar>* out) {
    const auto report = fm::EvalRhs(p, rc, q, qd, t, modes, trig, out);
    out->Q(0) += Drive(p, t);
    return report;
  }
  static double Drive(const fm::Params<double>& p, double t) {
    static mechgen::dynamics::Kinetostatics<fm::Model> k(p);
    static bool initialized = k.Initialize(Vec1(Prescribed::q(0)));
    EXPECT_TRUE(initialized);
    mechgen::dynamics::KinetostaticsRow<fm::Model> row;
    k.Evaluate(t, Vec1(Prescribed::q(t)), Vec1(Prescribed::qd(t)), Vec1(Prescribed::qdd(t)), &row);
    return row.statics.drive(0);
  }
};

TEST(MinimalGenerated, InverseThenForwardReproducesThePrescribedMotion) {
  MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.05;
  MinimalDynamics<DrivenFourbarMassive, Dop853> sim(fm::Params<double>(), o);
  ASSERT_TRUE(sim.Initialize(Vec1(Prescribed::q(0))));
  MinimalSummary summary;
  double max_err = 0;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(Prescribed::q(0)), Vec1(Prescribed::qd(0)), 4.0,
                           [&](const auto& s) {
                             max_err = std::max(max_err, std::abs(s.q(0) - Prescribed::q(s.t)));
                             return true;
                           },
                           &summary))
      << mechgen::dynamics::FormatSummary(summary);
  EXPECT_EQ(summary.samples, 81);
  EXPECT_LT(max_err, 1e-7);
}

}  // namespace
