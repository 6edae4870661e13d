// The four-stroke engine with its gas pressure written in the model (issue 26: "the engine with
// its pressure written as an expression over 720 deg against the same engine with the pressure
// table"). tests/engine/models/engine_gas_expression.yaml is models/engine_single.yaml whose
// gas load is `indicator(mod(theta_crank - phase_1, 4 Pi))` (a table over the 720 deg cycle)
// instead of the parameter p_gas_1 that the engine tool sets per sample. Oracles:
//  - the engine tool's route: engine_single (gas load 0) with GasTorque of a PressureTable of
//    the same points (machines/engine/gas.h, crank_dynamics.h), the torque through the
//    generated K; and a third, by hand: -p(a) A ds/dtheta with the centred slider-crank's
//    closed-form ds/dtheta and the test's own linear interpolation of the points;
//  - the steady cycle of both (FindSteadyCycle against a viscous load): the same speeds.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine_gas_expression.h"
#include "engine_single.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/gas.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

// The indicator diagram of the model's table `indicator`: cycle angle (deg), gauge pressure
// (Pa); the last point (720 deg) repeats the first.
const std::vector<double> kAngleDeg = {0, 15, 40, 90, 180, 190, 360, 540, 560, 630, 690, 720};
const std::vector<double> kPressure = {3.5e6, 5.0e6, 3.0e6, 1.2e6, 3.0e5, 5.0e4,
                                       1.0e4, -2.0e4, 0,     1.5e5, 8.0e5, 3.5e6};

// The test's own interpolation: linear between the points, periodic over 720 deg.
double PressureByHand(double a) {
  a = std::fmod(a, 4 * kPi);
  if (a < 0) a += 4 * kPi;
  for (size_t i = 0; i + 1 < kAngleDeg.size(); ++i) {
    const double a0 = kAngleDeg[i] * kDeg, a1 = kAngleDeg[i + 1] * kDeg;
    if (a <= a1) return kPressure[i] + (kPressure[i + 1] - kPressure[i]) * (a - a0) / (a1 - a0);
  }
  return kPressure.back();
}

using Expr = mech::engine_gas_expression::Model;
using Single = mech::engine_single::Model;
using Table = mechgen::engine::PressureTable;
using Gas = mechgen::engine::GasTorque<Table>;

Table EngineToolTable() {
  Table table;
  std::vector<double> a, p;
  for (size_t i = 0; i + 1 < kAngleDeg.size(); ++i) {  // [0, cycle): the wrap is the table's
    a.push_back(kAngleDeg[i] * kDeg);
    p.push_back(kPressure[i]);
  }
  std::string error;
  EXPECT_TRUE(table.Set(a, p, 4 * kPi, &error)) << error;
  return table;
}

Gas EngineToolGas(const Table* table, const mech::engine_single::Params<double>& p) {
  Gas gas;
  gas.law = table;
  gas.cycle = 4 * kPi;
  gas.count = 1;
  gas.cylinders[0] = {1, kPi * p.bore * p.bore / 4, p.phase_1};
  EXPECT_STREQ(Single::kPhiNames[1], "s_slide_1");
  return gas;
}

TEST(GasExpression, TorqueIsTheEngineToolsAndTheHandFormula) {
  mech::engine_gas_expression::Params<double> pe;
  mech::engine_single::Params<double> ps;
  ASSERT_EQ(pe.e, 0.0);  // the hand formula is the centred slider-crank's
  const Table table = EngineToolTable();
  const Gas gas = EngineToolGas(&table, ps);
  Eigen::Matrix<double, Expr::kNphi, 1> phi_e;
  Eigen::Matrix<double, Single::kNphi, 1> phi_s;
  for (int i = 0; i < Expr::kNphi; ++i) phi_e(i) = Expr::kAssemblyPhi[i];
  for (int i = 0; i < Single::kNphi; ++i) phi_s(i) = Single::kAssemblyPhi[i];
  const double A = kPi * pe.bore * pe.bore / 4, r = pe.r, l = pe.l;
  double worst_tool = 0, worst_hand = 0, largest = 0;
  int samples = 0;
  // Three cycles from -720 deg, every degree (on every point of the table and between them;
  // every 7th angle shifted 0.3 mrad, off the grid).
  for (int k = -720; k <= 1440; ++k) {
    const double theta = k * kDeg + (k % 7 == 0 ? 0.3e-3 : 0.0);
    Eigen::Matrix<double, 1, 1> q, qd;
    q(0) = theta;
    qd(0) = 120.0;  // the load's c_load is 0: Q does not depend on the speed here
    ASSERT_EQ(Expr::Solve(pe, q, &phi_e).status, decltype(Expr::Solve(pe, q, &phi_e).status)::kConverged);
    ASSERT_EQ(Single::Solve(ps, q, &phi_s).status, decltype(Single::Solve(ps, q, &phi_s).status)::kConverged);
    typename Expr::template CoefficientsT<double> ce;
    typename Single::template CoefficientsT<double> cs;
    Expr::Coeffs(pe, q, phi_e, &ce);
    Single::Coeffs(ps, q, phi_s, &cs);
    typename Expr::template DynamicsT<double> de;
    Expr::Dynamics(pe, q, phi_e, qd, 0.0, ce, &de);
    const double Q_tool = gas.Torque(theta, cs.K);
    const double s = std::sin(theta), c = std::cos(theta);
    const double ds = -r * s - r * r * s * c / std::sqrt(l * l - r * r * s * s);  // s = r cos + sqrt(l^2 - r^2 sin^2)
    const double Q_hand = -PressureByHand(theta - pe.phase_1) * A * ds;
    worst_tool = std::max(worst_tool, std::abs(de.Q(0) - Q_tool));
    worst_hand = std::max(worst_hand, std::abs(de.Q(0) - Q_hand));
    largest = std::max(largest, std::abs(Q_hand));
    ++samples;
  }
  EXPECT_GT(largest, 100.0);  // N m: the gas torque is there to compare
  EXPECT_LT(worst_tool, 1e-12 * largest);
  EXPECT_LT(worst_hand, 1e-11 * largest);
  std::printf("%d angles over three cycles: |Q_model - Q_engine tool| <= %.3g, |Q_model - Q_hand| <= %.3g N m "
              "of max %.6g N m\n",
              samples, worst_tool, worst_hand, largest);
}

TEST(GasExpression, SteadyCycleIsTheEngineTools) {
  mech::engine_gas_expression::Params<double> pe;
  mech::engine_single::Params<double> ps;
  const Table table = EngineToolTable();
  const Gas gas = EngineToolGas(&table, ps);
  // The mean gas torque (the cycle's work / 4 pi) by the hand formula, then a viscous load
  // that absorbs it at 2500 rev/min: c = mean torque / omega.
  const double A = kPi * pe.bore * pe.bore / 4, r = pe.r, l = pe.l;
  double W = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double a = (i + 0.5) * 4 * kPi / n, s = std::sin(a);
    W += -PressureByHand(a) * A * (-r * s - r * r * s * std::cos(a) / std::sqrt(l * l - r * r * s * s)) * 4 * kPi / n;
  }
  ASSERT_GT(W, 10.0);  // J: the diagram does work
  const double omega = 2500 * 2 * kPi / 60;
  pe.c_load = ps.c_load = W / (4 * kPi) / omega;
  mechgen::dynamics::MinimalOptions mo;
  mo.integrator.rtol = 1e-11;
  mo.integrator.atol = 1e-11;
  mechgen::dynamics::MinimalDynamics<Expr> model_sim(pe, mo);
  mechgen::engine::GasDriven<Single, Gas> tool_sim(ps, mo, {gas});
  mechgen::engine::SteadyCycleOptions so;
  so.cycle = 4 * kPi;
  so.omega_guess = 0.9 * omega;
  so.samples = 2000;
  const auto a = mechgen::engine::FindSteadyCycle(&model_sim, so);
  const auto b = mechgen::engine::FindSteadyCycle(&tool_sim, so);
  ASSERT_TRUE(a.ok) << a.message;
  ASSERT_TRUE(b.ok) << b.message;
  EXPECT_NEAR(a.omega0, b.omega0, 1e-8 * b.omega0);
  EXPECT_NEAR(a.omega_max, b.omega_max, 1e-8 * b.omega0);
  EXPECT_NEAR(a.omega_min, b.omega_min, 1e-8 * b.omega0);
  EXPECT_NEAR(a.Cs, b.Cs, 1e-6 * b.Cs);
  EXPECT_GT(a.Cs, 1e-4);  // the cycle fluctuates: the comparison sees the pressure
  // The load line: c w_mean = mean gas torque, to O(C_s^2).
  EXPECT_NEAR(a.omega_mean_time, omega, 2 * a.Cs * a.Cs * omega);
  std::printf("steady cycle at %.6g rad/s: model omega0 %.12g, engine tool %.12g; C_s %.9g and %.9g\n", omega,
              a.omega0, b.omega0, a.Cs, b.Cs);
}

}  // namespace
