// Trajectory sensitivities (issue 27, dynamics/sensitivity.h): dq(t)/dp and dqd(t)/dp by the
// forward sensitivity equations, against
//  - Richardson-extrapolated central differences of two free simulations per design parameter
//    (MinimalDynamics, Dop853 at rtol 1e-13: the values alone, an independent integration);
//  - the energy of a conservative machine: T + V is constant along every trajectory of every
//    design, so d(T + V)/dp along the motion (through S, Sd and the explicit dT/dp, dV/dp)
//    stays equal to its value at t0;
//  - a run into a dead point ends with a status (never success with huge numbers).
// Models: the massive four-bar (one DOF, gravity only, six design parameters) and a two-DOF
// five-bar with a spring and dampers (thirteen design parameters).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "design_fivebar_massive.h"
#include "design_fourbar_massive.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/sensitivity.h"

namespace {

using mechgen::dynamics::Dop853;
using mechgen::dynamics::MinimalDynamics;
using mechgen::dynamics::MinimalOptions;
using mechgen::dynamics::SensitivityOptions;
using mechgen::dynamics::SensitivitySummary;
using mechgen::dynamics::Status;
using mechgen::dynamics::TrajectorySensitivity;

void RecordWorst(double worst) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", worst);
  ::testing::Test::RecordProperty("worst_relative_error", text);
}

/// q and qd at the samples of a free simulation with parameters p (Dop853, tight tolerance).
template <class M>
std::vector<Eigen::VectorXd> Trajectory(const typename M::template ParamsT<double>& p,
                                        const Eigen::Matrix<double, M::kNq, 1>& q0,
                                        const Eigen::Matrix<double, M::kNq, 1>& qd0, double t_end, double dt) {
  MinimalOptions options;
  options.integrator.rtol = 1e-13;
  options.integrator.atol = 1e-14;
  options.sample_dt = dt;
  MinimalDynamics<M, Dop853> sim(p, options);
  EXPECT_TRUE(sim.Initialize(q0));
  std::vector<Eigen::VectorXd> out;
  mechgen::dynamics::MinimalSummary summary;
  sim.Simulate(0.0, q0, qd0, t_end,
               [&](const auto& s) {
                 Eigen::VectorXd x(2 * M::kNq);
                 x << s.q, s.qd;
                 out.push_back(x);
                 return true;
               },
               &summary);
  EXPECT_EQ(summary.status, Status::kSuccess) << mechgen::dynamics::FormatSummary(summary);
  return out;
}

/// The worst |S - Richardson difference| / max(1, |difference|) over the samples, every q, qd
/// and design parameter; *worst_name says which.
template <class M>
double WorstAgainstDifferences(const Eigen::Matrix<double, M::kNq, 1>& q0,
                               const Eigen::Matrix<double, M::kNq, 1>& qd0, double t_end, double dt) {
  using Params = typename M::template ParamsT<double>;
  const Params p;
  SensitivityOptions options;
  options.integrator.rtol = 1e-12;
  options.integrator.atol = 1e-13;
  options.sample_dt = dt;
  TrajectorySensitivity<M> sens(p, options);
  EXPECT_TRUE(sens.Initialize(q0));
  std::vector<Eigen::MatrixXd> S;  // (q, qd) x p per sample
  SensitivitySummary summary;
  EXPECT_TRUE(sens.Simulate(0.0, q0, qd0, t_end,
                            [&](const auto& s) {
                              Eigen::MatrixXd x(2 * M::kNq, M::kNumDesign);
                              x << s.S, s.Sd;
                              S.push_back(x);
                              return true;
                            },
                            &summary))
      << FormatSummary(summary);
  double worst = 0;
  for (int d = 0; d < M::kNumDesign; ++d) {
    const double p0 = *Params().Find(M::kDesignNames[d]);
    const double h = 1e-3 * std::max(1.0, std::abs(p0));
    auto run = [&](double delta) {
      Params pp;
      *pp.Find(M::kDesignNames[d]) = p0 + delta;
      return Trajectory<M>(pp, q0, qd0, t_end, dt);
    };
    const auto plus = run(h), minus = run(-h), plus2 = run(h / 2), minus2 = run(-h / 2);
    EXPECT_EQ(plus.size(), S.size());
    const size_t n = std::min({S.size(), plus.size(), minus.size(), plus2.size(), minus2.size()});
    for (size_t k = 0; k < n; ++k) {
      const Eigen::VectorXd D1 = (plus[k] - minus[k]) / (2 * h);
      const Eigen::VectorXd D2 = (plus2[k] - minus2[k]) / h;
      const Eigen::VectorXd R = (4 * D2 - D1) / 3;
      for (int i = 0; i < 2 * M::kNq; ++i) {
        const double e = std::abs(S[k](i, d) - R(i)) / std::max(1.0, std::abs(R(i)));
        EXPECT_LT(e, 1e-7) << M::kDesignNames[d] << " sample " << k << " component " << i << ": "
                           << S[k](i, d) << " against " << R(i);
        worst = std::max(worst, e);
      }
    }
  }
  return worst;
}

TEST(TrajectorySensitivity, FourBarAgreesWithRichardsonDifferencesOfTwoSimulations) {
  using M = mech::design_fourbar_massive::Model;
  Eigen::Matrix<double, 1, 1> q0, qd0;
  q0 << M_PI / 2;
  qd0 << 1.5;
  const double worst = WorstAgainstDifferences<M>(q0, qd0, 2.0, 0.25);
  RecordWorst(worst);
}

TEST(TrajectorySensitivity, TwoDofFiveBarWithSpringAndDampersAgreesWithRichardsonDifferences) {
  using M = mech::design_fivebar_massive::Model;
  Eigen::Matrix<double, 2, 1> q0, qd0;
  q0 << M_PI / 2, M_PI / 2;
  qd0 << 0.3, -0.2;
  const double worst = WorstAgainstDifferences<M>(q0, qd0, 0.6, 0.1);
  RecordWorst(worst);
}

// T + V is the same at every time of a conservative run, for every design: its derivative
// along the motion, qd^T I Sd + (1/2 qd^T I_q qd + V_q) S + dT/dp + dV/dp (V_q = -Q: gravity
// is the only load), equals its value at t0, 1/2 qd0^T dI/dp qd0 + dV/dp at q0.
TEST(TrajectorySensitivity, KeepsTheDesignDerivativeOfTheEnergyOfAConservativeMachine) {
  using M = mech::design_fourbar_massive::Model;
  using Params = M::ParamsT<double>;
  const Params p;
  SensitivityOptions options;
  options.integrator.rtol = 1e-12;
  options.integrator.atol = 1e-13;
  options.sample_dt = 0.1;
  TrajectorySensitivity<M> sens(p, options);
  Eigen::Matrix<double, 1, 1> q0, qd0;
  q0 << 0.3;
  qd0 << 2.0;
  ASSERT_TRUE(sens.Initialize(q0));
  Eigen::Matrix<double, 1, M::kNumDesign> dE0;
  bool first = true;
  double worst = 0;
  int samples = 0;
  SensitivitySummary summary;
  ASSERT_TRUE(sens.Simulate(0.0, q0, qd0, 3.0,
                            [&](const auto& s) {
                              M::CoefficientsT<double> c;
                              M::Coeffs(p, s.q, s.phi, &c);
                              M::DynamicsT<double> d;
                              M::Dynamics(p, s.q, s.phi, s.qd, 0.0, c, &d);
                              M::DesignDerivativesT<double> dc;
                              M::Design(p, s.q, s.phi, &dc);
                              M::DynamicsDesignT<double> dd;
                              M::DynamicsDesign(p, s.q, s.phi, s.qd, 0.0, c, dc, &dd);
                              const double qd = s.qd(0);
                              Eigen::Matrix<double, 1, M::kNumDesign> dE =
                                  (dd.dT_dp + dd.dV_dp).transpose();
                              dE += d.I(0, 0) * qd * s.Sd.row(0) +
                                    (0.5 * qd * qd * d.dI_dq(0, 0) - d.Q(0)) * s.S.row(0);
                              if (first) dE0 = dE;
                              first = false;
                              for (int k = 0; k < M::kNumDesign; ++k)
                                worst = std::max(worst, std::abs(dE(k) - dE0(k)) / std::max(1.0, std::abs(dE0(k))));
                              ++samples;
                              return true;
                            },
                            &summary))
      << FormatSummary(summary);
  EXPECT_EQ(samples, 31);
  EXPECT_LT(worst, 1e-8);
  RecordWorst(worst);
}

// A non-Grashof four-bar (crank longer than the rest allows) swings into a limit position of
// its crank: the run ends at a dead point with that status, the sensitivities not returned as
// success.
TEST(TrajectorySensitivity, EndsAtADeadPointWithAStatus) {
  using M = mech::design_fourbar_massive::Model;
  M::ParamsT<double> p;
  *p.Find("a") = 2.0;
  *p.Find("b") = 3.5;
  *p.Find("c") = 2.5;
  *p.Find("d") = 4.0;
  SensitivityOptions options;
  options.sample_dt = 0.01;
  TrajectorySensitivity<M> sens(p, options);
  Eigen::Matrix<double, 1, 1> q0, qd0;
  q0 << M_PI / 2;
  qd0 << 3.0;
  ASSERT_TRUE(sens.Initialize(q0));
  double last_S = 0;
  SensitivitySummary summary;
  const bool ok = sens.Simulate(0.0, q0, qd0, 10.0,
                                [&](const auto& s) {
                                  EXPECT_TRUE(s.S.allFinite());
                                  last_S = s.S.cwiseAbs().maxCoeff();
                                  return true;
                                },
                                &summary);
  EXPECT_FALSE(ok);
  EXPECT_EQ(summary.status, Status::kDeadPoint) << FormatSummary(summary);
  EXPECT_LT(summary.t_end, 10.0);
  EXPECT_TRUE(std::isfinite(last_S));
}

TEST(TrajectorySensitivity, RefusesInvalidOptionsAndAnUninitializedRun) {
  using M = mech::design_fourbar_massive::Model;
  Eigen::Matrix<double, 1, 1> q0, qd0;
  q0 << 1.0;
  qd0 << 0.0;
  SensitivitySummary summary;
  TrajectorySensitivity<M> fresh{M::ParamsT<double>()};
  EXPECT_FALSE(fresh.Simulate(0.0, q0, qd0, 1.0, [](const auto&) { return true; }, &summary));
  EXPECT_EQ(summary.status, Status::kInvalidInput);
  SensitivityOptions bad;
  bad.sample_dt = -1;
  TrajectorySensitivity<M> sens(M::ParamsT<double>(), bad);
  ASSERT_TRUE(sens.Initialize(q0));
  EXPECT_FALSE(sens.Simulate(0.0, q0, qd0, 1.0, [](const auto&) { return true; }, &summary));
  EXPECT_EQ(summary.status, Status::kInvalidInput);
}

}  // namespace
