// Design sensitivities of flywheel sizing (issue 27, machines/flywheel/cycle_design.h): the
// derivatives of the required torque at every sample, its mean, the energy loop's extremes
// and swing, the machine's mean inertia and the flywheel for a C_s, against
// Richardson-extrapolated central differences of the whole analysis (SampleMachineCycle and
// SizeFlywheel run again with one design parameter moved), on a press whose damped ram makes
// the motor supply a positive mean torque.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "design_press.h"
#include "mechgen/machines/flywheel/cycle_design.h"

namespace {

namespace fw = mechgen::flywheel;
using M = mech::design_press::Model;
using Params = M::ParamsT<double>;

fw::MachineCycleOptions Options() {
  fw::MachineCycleOptions o;
  o.omega = 4 * M_PI;  // 120 rpm
  o.samples = 360;
  return o;
}

// The figures the derivatives are of, in one vector: T_mean, E_max, E_min, dE, I_mean,
// I_flywheel (C_s = 0.05), then T_req at every 30th sample.
Eigen::VectorXd Figures(const Params& p) {
  const fw::MachineCycle cycle = fw::SampleMachineCycle<M>(p, Options());
  EXPECT_TRUE(cycle.IsUsable()) << cycle.message;
  const fw::FlywheelSize size = fw::SizeFlywheel(cycle, 0.05);
  Eigen::VectorXd x(6 + 12);
  x << cycle.T_mean, cycle.loop.E_max, cycle.loop.E_min, cycle.loop.delta_E, cycle.I_mean, size.I_flywheel,
      Eigen::VectorXd::Zero(12);
  for (int j = 0; j < 12; ++j) x(6 + j) = cycle.points[static_cast<size_t>(30 * j)].T_req;
  return x;
}

TEST(CycleDesign, FlywheelSizingAgreesWithRichardsonDifferencesOfTheWholeAnalysis) {
  const Params p;
  const fw::MachineCycle cycle = fw::SampleMachineCycle<M>(p, Options());
  ASSERT_TRUE(cycle.IsUsable()) << cycle.message;
  ASSERT_GT(cycle.T_mean, 0);
  const auto design = fw::SampleMachineCycleDesign<M>(p, Options(), cycle);
  ASSERT_TRUE(design.IsUsable()) << design.message;
  const auto size = fw::SizeFlywheelDesign<M>(cycle, design, 0.05);
  const char* names[6] = {"T_mean", "E_max", "E_min", "delta_E", "I_mean", "I_flywheel"};
  double worst = 0;
  for (int d = 0; d < M::kNumDesign; ++d) {
    Eigen::VectorXd got(18);
    got << design.dT_mean_dp(d), design.dE_max_dp(d), design.dE_min_dp(d), design.ddelta_E_dp(d),
        design.dI_mean_dp(d), size.dI_flywheel_dp(d), Eigen::VectorXd::Zero(12);
    for (int j = 0; j < 12; ++j) got(6 + j) = design.dT_req_dp[static_cast<size_t>(30 * j)](d);
    const double p0 = *Params().Find(M::kDesignNames[d]);
    const double h = 1e-4 * std::max(1e-2, std::abs(p0));
    auto at = [&](double delta) {
      Params pp;
      *pp.Find(M::kDesignNames[d]) = p0 + delta;
      return Figures(pp);
    };
    const Eigen::VectorXd D1 = (at(h) - at(-h)) / (2 * h);
    const Eigen::VectorXd D2 = (at(h / 2) - at(-h / 2)) / h;
    const Eigen::VectorXd R = (4 * D2 - D1) / 3;
    for (int i = 0; i < got.size(); ++i) {
      const double e = std::abs(got(i) - R(i)) / std::max(1.0, std::abs(R(i)));
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-7) << "d" << (i < 6 ? names[i] : ("T_req sample " + std::to_string(30 * (i - 6))).c_str())
                         << "/d" << M::kDesignNames[d] << ": " << got(i) << " against " << R(i);
    }
  }
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", worst);
  RecordProperty("worst_relative_error", text);
}

TEST(CycleDesign, AnUnusableCycleGivesAStatus) {
  fw::MachineCycleOptions o = Options();
  o.omega = -1;  // refused
  const fw::MachineCycle cycle = fw::SampleMachineCycle<M>(Params(), o);
  ASSERT_FALSE(cycle.IsUsable());
  const auto design = fw::SampleMachineCycleDesign<M>(Params(), o, cycle);
  EXPECT_FALSE(design.IsUsable());
  EXPECT_FALSE(design.message.empty());
}

}  // namespace
