// Design sensitivities of flywheel sizing (issue 27, machines/flywheel/cycle_design.h): the
// derivatives of the required torque at every sample, its mean, the energy loop's extremes
// and swing, the machine's mean inertia and the flywheel for a C_s, against
// Richardson-extrapolated central differences of the whole analysis (SampleMachineCycle and
// SizeFlywheel run again with one design parameter moved), on a press whose damped ram makes
// the motor supply a positive mean torque (with `dynamics`: EvalDynamicsDesign) and on a
// massless loaded four-bar (the statics' EvalStaticsDesign). Through the model view (issue 43:
// the same source instantiated once for ViewModel, mechgen_runtime_view) both give the
// fixed-size figures to the bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "design_fourbar_loaded.h"
#include "design_press.h"
#include "mechgen/machines/flywheel/cycle_design.h"
#include "mechgen/machines/view_machines.h"

namespace mech::design_press {
const mechgen::ModelView& View();
}
namespace mech::design_fourbar_loaded {
const mechgen::ModelView& View();
}

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
template <class Model>
Eigen::VectorXd Figures(const typename Model::template ParamsT<double>& p) {
  const fw::MachineCycle cycle = fw::SampleMachineCycle<Model>(p, Options());
  EXPECT_TRUE(cycle.IsUsable()) << cycle.message;
  const fw::FlywheelSize size = fw::SizeFlywheel(cycle, 0.05);
  Eigen::VectorXd x(6 + 12);
  x << cycle.T_mean, cycle.loop.E_max, cycle.loop.E_min, cycle.loop.delta_E, cycle.I_mean, size.I_flywheel,
      Eigen::VectorXd::Zero(12);
  for (int j = 0; j < 12; ++j) x(6 + j) = cycle.points[static_cast<size_t>(30 * j)].T_req;
  return x;
}

template <class Model>
void ExpectAgreesWithRichardsonDifferences() {
  using P = typename Model::template ParamsT<double>;
  const P p;
  const fw::MachineCycle cycle = fw::SampleMachineCycle<Model>(p, Options());
  ASSERT_TRUE(cycle.IsUsable()) << cycle.message;
  const auto design = fw::SampleMachineCycleDesign<Model>(p, Options(), cycle);
  ASSERT_TRUE(design.IsUsable()) << design.message;
  const auto size = fw::SizeFlywheelDesign<Model>(cycle, design, 0.05);
  const char* names[6] = {"T_mean", "E_max", "E_min", "delta_E", "I_mean", "I_flywheel"};
  double worst = 0;
  for (int d = 0; d < Model::kNumDesign; ++d) {
    Eigen::VectorXd got(18);
    got << design.dT_mean_dp(d), design.dE_max_dp(d), design.dE_min_dp(d), design.ddelta_E_dp(d),
        design.dI_mean_dp(d), size.dI_flywheel_dp(d), Eigen::VectorXd::Zero(12);
    for (int j = 0; j < 12; ++j) got(6 + j) = design.dT_req_dp[static_cast<size_t>(30 * j)](d);
    const double p0 = *P().Find(Model::kDesignNames[d]);
    const double h = 1e-4 * std::max(1e-2, std::abs(p0));
    auto at = [&](double delta) {
      P pp;
      *pp.Find(Model::kDesignNames[d]) = p0 + delta;
      return Figures<Model>(pp);
    };
    const Eigen::VectorXd D1 = (at(h) - at(-h)) / (2 * h);
    const Eigen::VectorXd D2 = (at(h / 2) - at(-h / 2)) / h;
    const Eigen::VectorXd R = (4 * D2 - D1) / 3;
    for (int i = 0; i < got.size(); ++i) {
      const double e = std::abs(got(i) - R(i)) / std::max(1.0, std::abs(R(i)));
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-7) << "d" << (i < 6 ? names[i] : ("T_req sample " + std::to_string(30 * (i - 6))).c_str())
                         << "/d" << Model::kDesignNames[d] << ": " << got(i) << " against " << R(i);
    }
  }
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", worst);
  ::testing::Test::RecordProperty("worst_relative_error", text);
}

TEST(CycleDesign, FlywheelSizingAgreesWithRichardsonDifferencesOfTheWholeAnalysis) {
  const fw::MachineCycle cycle = fw::SampleMachineCycle<M>(Params(), Options());
  ASSERT_GT(cycle.T_mean, 0);
  ExpectAgreesWithRichardsonDifferences<M>();
}

TEST(CycleDesign, MasslessMachineByTheStaticsAgreesWithRichardsonDifferences) {
  using F = mech::design_fourbar_loaded::Model;
  static_assert(!mechgen::HasDynamics<F>::value && mechgen::HasStaticsDesign<F>::value);
  ExpectAgreesWithRichardsonDifferences<F>();
}

// x and y the same bits (NaN included).
bool SameBits(double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; }
template <class A, class B>
::testing::AssertionResult SameVector(const char* what, const A& a, const B& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << what << ": " << a.size() << " vs " << b.size();
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!SameBits(a(i), b(i))) return ::testing::AssertionFailure() << what << "(" << i << "): " << a(i) << " vs " << b(i);
  return ::testing::AssertionSuccess();
}

// The cycle and its design sensitivities through the view (the library's SampleMachineCycle
// and SampleMachineCycleDesign for ViewModel) against the fixed-size ones: every figure.
template <class Model>
void ExpectViewSame(const mechgen::ModelView& view) {
  using CV = mechgen::ModelCalls<mechgen::ViewModel>;
  ASSERT_TRUE(mechgen::ViewCompatible(view));
  const mechgen::ViewModel model(view);
  const typename Model::template ParamsT<double> p;
  const mechgen::ViewParams p_view = CV::DefaultParams(model);
  const fw::MachineCycle cycle = fw::SampleMachineCycle<Model>(p, Options());
  const fw::MachineCycle cycle_view = fw::SampleMachineCycle(model, p_view, Options());
  ASSERT_TRUE(cycle.IsUsable() && cycle_view.IsUsable()) << cycle.message << cycle_view.message;
  const auto design = fw::SampleMachineCycleDesign<Model>(p, Options(), cycle);
  const auto design_view = fw::SampleMachineCycleDesign(model, p_view, Options(), cycle_view);
  ASSERT_TRUE(design.IsUsable()) << design.message;
  ASSERT_TRUE(design_view.IsUsable()) << design_view.message;
  EXPECT_TRUE(SameVector("dT_mean_dp", design.dT_mean_dp, design_view.dT_mean_dp));
  EXPECT_TRUE(SameVector("dE_max_dp", design.dE_max_dp, design_view.dE_max_dp));
  EXPECT_TRUE(SameVector("dE_min_dp", design.dE_min_dp, design_view.dE_min_dp));
  EXPECT_TRUE(SameVector("ddelta_E_dp", design.ddelta_E_dp, design_view.ddelta_E_dp));
  EXPECT_TRUE(SameVector("dI_mean_dp", design.dI_mean_dp, design_view.dI_mean_dp));
  ASSERT_EQ(design.dT_req_dp.size(), design_view.dT_req_dp.size());
  for (size_t k = 0; k < design.dT_req_dp.size(); ++k) {
    EXPECT_TRUE(SameVector("dT_req_dp", design.dT_req_dp[k], design_view.dT_req_dp[k])) << "sample " << k;
    EXPECT_TRUE(SameVector("dI_dp", design.dI_dp[k], design_view.dI_dp[k])) << "sample " << k;
  }
  EXPECT_GT(design.ddelta_E_dp.cwiseAbs().maxCoeff(), 1e-3);  // (not a comparison of zeros)
}

TEST(CycleDesign, ThroughTheViewTheSameBitsByTheDynamics) {
  ExpectViewSame<M>(mech::design_press::View());
}
TEST(CycleDesign, ThroughTheViewTheSameBitsByTheStatics) {
  ExpectViewSame<mech::design_fourbar_loaded::Model>(mech::design_fourbar_loaded::View());
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
