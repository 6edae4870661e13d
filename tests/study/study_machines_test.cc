// Design studies of the flywheel analysis per sample (issue 29): the shaper against the hand
// work, the columns of the energy loop by name, the first order of the cycle metrics against
// differences of the study, and its errors. (study_test.cc was split in four: in the cold
// sanitizer build the whole file compiled alone for the last 470 s of the build.)
#include "study_test_common.h"

namespace {

using namespace mechgen_study_test;  // NOLINT (the tests' shared helpers)

// ---- the flywheel analysis per sample ----------------------------------------------------------

#ifdef MECHGEN_STUDY_TEST_SHAPER
// The quick-return shaper of tests/statics (crank r about O2 = (0, d), the slotted rocker about
// O4 = (0, 0), rocker L, link l, the ram on y = h): a cutting force F on the forward stroke only
// (crank -30 to 210 deg, where sin theta = -r/d puts the rocker at its extremes), the probe
// torque off (P = 0). The ram's place by hand, for the work per turn F * stroke. Its studies and
// machine cycles through its view (Study<ViewModel>, the cycle compiled once).
double ShaperRamX(double theta, double L, double l) {
  const double r = 0.75, d = 1.5, h = 4.2;
  const double ax = r * std::cos(theta), ay = d + r * std::sin(theta);
  const double beta = std::atan2(ay, ax);
  const double bx = L * std::cos(beta), by = L * std::sin(beta);
  return bx + std::sqrt(l * l - (h - by) * (h - by));
}

// A grid of F, L and l: per sample the mean torque against F * stroke / 2 pi from the hand
// geometry (to the trapezoid's kink error of the cycle's 720 samples, h^2/12 times the slope
// jumps of T_req = F |x'| at the stroke's ends, as tests/flywheel bounds it); the flywheel
// inertia, the energy fluctuation and the peak torque proportional to F (T_req is F times the
// geometry; massless: no inertia to subtract), and each sample the same bits as the machine
// cycle run alone at its parameters.
TEST(StudyFlywheel, ShaperGridAgainstTheHandWorkAndLinearInTheForce) {
  const study::StudySpec spec = Read("fly.yaml",
                                     "method: grid\nanalysis: flywheel\nomega: 6.283185307179586\nsteps: 720\n"
                                     "parameters:\n  F: {values: [500, 1500]}\n  L: {values: [3.9, 4.0]}\n"
                                     "  l: {values: [1.5, 1.6]}\n  P: {values: [0]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n  - {kind: flywheel_inertia, C_s: 0.05}\n"
                                     "  - {kind: energy_fluctuation}\n  - {kind: peak_torque}\n  - {kind: failures}\n");
  const mechgen::ViewModel model(mech::shaper::View());
  study::Study<mechgen::ViewModel> s{model};
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  EXPECT_EQ(s.Unit(1), "kg m^2");
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> results;
  s.Run(v, 2, &results);
  ASSERT_EQ(results.size(), 8u);
  const double pi = 3.14159265358979323846, theta0 = -pi / 6, theta_end = 7 * pi / 6, h = 2 * pi / 720;
  for (size_t i = 0; i < 8; ++i) {
    ASSERT_STREQ(results[i].status, "ok") << i;
    const double F = v[4 * i], L = v[4 * i + 1], l = v[4 * i + 2];
    auto x = [&](double t) { return ShaperRamX(t, L, l); };
    auto x2 = [&](double t) { return (x(t + 1e-4) - 2 * x(t) + x(t - 1e-4)) / 1e-8; };
    const double stroke = x(theta0) - x(theta_end);
    const double jumps = F * (std::abs(x2(theta0)) + std::abs(x2(theta_end)));
    EXPECT_NEAR(results[i].metrics[0], F * stroke / (2 * pi), 1.02 * h * h / 12 * jumps / (2 * pi)) << i;
    EXPECT_EQ(results[i].metrics[4], 0);
    // The same design with F three times larger (the grid's first parameter varies slowest).
    if (F == 500) {
      const study::SampleResult& big = results[i + 4];
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(big.metrics[k] / results[i].metrics[k], 3, 1e-12) << i << " " << k;
    }
    // The study's figure is the machine cycle's at that design, bit for bit.
    const mechgen::ViewParams p = ParamsOf(model, {{"F", F}, {"L", L}, {"l", l}, {"P", 0}});
    mechgen::flywheel::MachineCycleOptions o;
    o.omega = 2 * pi;
    o.samples = 720;
    const mechgen::flywheel::MachineCycle c = mechgen::flywheel::SampleMachineCycle(model, p, o);
    ASSERT_TRUE(c.IsUsable()) << c.message;
    EXPECT_EQ(results[i].metrics[1], mechgen::flywheel::SizeFlywheel(c, 0.05).I_flywheel);
    EXPECT_EQ(results[i].metrics[1], c.loop.delta_E / (0.05 * 4 * pi * pi));  // massless
  }
  // No design section: no first order, and the reason.
  std::string why;
  EXPECT_TRUE(std::isnan(s.Gradient(1, &why)[0]));
  EXPECT_NE(why.find("no design section"), std::string::npos) << why;
}

// The flywheel's metrics read the energy loop CSV's columns by name (analysis/flywheel_columns.h,
// what `mechgen flywheel --csv` writes): max, min, rms and at of a column, peak_torque the largest
// |T_req|; against the machine cycle run directly (its own extremes of T_req, E(theta0) = 0 by
// definition, the cycle's start, its mean). An unknown column names the energy loop's.
TEST(StudyFlywheel, ColumnsOfTheEnergyLoopByName) {
  const study::StudySpec spec = Read("flycolumns.yaml",
                                     "method: grid\nanalysis: flywheel\nomega: 6.283185307179586\nsteps: 720\n"
                                     "parameters:\n  F: {values: [500, 1500]}\n  L: {values: [3.9]}\n  P: {values: [0]}\n"
                                     "metrics:\n  - {kind: peak_torque}\n  - {kind: max, column: T_req}\n"
                                     "  - {kind: min, column: T_req}\n  - {kind: at, column: E, step: 0}\n"
                                     "  - {kind: at, column: theta, step: 0}\n  - {kind: rms, column: T_mean}\n"
                                     "  - {kind: at, column: theta_deg, step: 720}\n");
  const mechgen::ViewModel model(mech::shaper::View());
  study::Study<mechgen::ViewModel> s{model};
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  EXPECT_EQ(s.Unit(1), "N m");
  EXPECT_EQ(s.Unit(4), "rad");
  EXPECT_EQ(s.Description(1), "largest T_req over the cycle's samples");
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> results;
  s.Run(v, 2, &results);
  ASSERT_EQ(results.size(), 2u);
  const double pi = 3.14159265358979323846;
  for (size_t i = 0; i < results.size(); ++i) {
    ASSERT_STREQ(results[i].status, "ok") << i;
    const std::vector<double>& m = results[i].metrics;
    const mechgen::ViewParams p = ParamsOf(model, {{"F", v[3 * i]}, {"L", v[3 * i + 1]}, {"P", 0}});
    mechgen::flywheel::MachineCycleOptions o;
    o.omega = 2 * pi;
    o.samples = 720;
    const mechgen::flywheel::MachineCycle c = mechgen::flywheel::SampleMachineCycle(model, p, o);
    ASSERT_TRUE(c.IsUsable()) << c.message;
    EXPECT_EQ(m[0], std::max(std::abs(c.T_max), std::abs(c.T_min))) << i;
    EXPECT_EQ(m[1], c.T_max) << i;
    EXPECT_EQ(m[2], c.T_min) << i;
    EXPECT_GT(m[1], 0) << i;
    EXPECT_EQ(m[3], 0) << i;  // E(theta0) = 0
    EXPECT_EQ(m[4], c.theta0) << i;  // the cycle's start
    EXPECT_NEAR(m[5], std::abs(c.T_mean), 1e-14 * std::abs(c.T_mean)) << i;  // a constant column
    EXPECT_TRUE(std::isnan(m[6])) << i;  // 720 samples: rows 0 .. 719, the end not repeated
  }
  const study::StudySpec bad = Read("flybad.yaml",
                                    "method: grid\nanalysis: flywheel\nomega: 1\nparameters:\n  F: {values: [500]}\n"
                                    "metrics:\n  - {kind: max, column: ram.x}\n");
  study::Study<mechgen::ViewModel> b{model};
  EXPECT_FALSE(b.Prepare(bad, &error));
  EXPECT_NE(error.find("flybad.yaml:7:5: error: no numeric column 'ram.x' in the flywheel's energy loop output of "
                       "shaper (columns: theta, theta_deg, T_req, T_mean, E, T_static"),
            std::string::npos)
      << error;
  const std::string e = ErrorOf("flymu.yaml",
                                "method: grid\nanalysis: flywheel\nomega: 1\nparameters:\n  F: {values: [500]}\n"
                                "metrics:\n  - {kind: min_transmission_angle}\n");
  EXPECT_NE(e.find("flymu.yaml:7:5: error: with analysis: flywheel the metrics are flywheel_inertia, mean_torque, "
                   "peak_torque, energy_fluctuation, max, min, rms and at of a column"),
            std::string::npos)
      << e;
}

// Richardson's extrapolation of central differences of a study's own metric k along its
// parameter p (each sample evaluated again at the nominal +- h and +- h/2): the oracle of the
// first-order tests below.
template <class M>
double RichardsonOfMetric(study::Study<M>* s, const std::vector<double>& nominal, size_t p, size_t k, double h) {
  typename study::Study<M>::Rows rows;
  auto at = [&](double delta) {
    std::vector<double> v = nominal;
    v[p] += delta;
    const study::SampleResult r = s->Evaluate(v.data(), &rows);
    EXPECT_STREQ(r.status, "ok");
    return r.metrics[k];
  };
  const double D1 = (at(h) - at(-h)) / (2 * h);
  const double D2 = (at(h / 2) - at(-h / 2)) / h;
  return (4 * D2 - D1) / 3;
}

#ifdef MECHGEN_STUDY_TEST_DESIGN_PRESS
// The first order of the flywheel metrics (from machines/flywheel/cycle_design.h through
// Study::Gradient) against Richardson central differences of the study's own metrics,
// evaluated sample by sample at p +- h (the whole analysis again: an independent route). The
// damped press of tests/design: smooth loads, so the breaks do not move. Through its view (the
// generated press's study: the same figures to the bit, StudyView below).
TEST(StudyFlywheel, FirstOrderOfTheCycleMetricsAgainstDifferencesOfTheStudy) {
  const study::StudySpec spec = Read("press.yaml",
                                     "method: grid\nanalysis: flywheel\nomega: 12.566370614359172\nsteps: 360\n"
                                     "parameters:\n  a: {values: [0.1]}\n  b: {values: [0.35]}\n  m3: {values: [8]}\n"
                                     "  c: {values: [400]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n  - {kind: flywheel_inertia, C_s: 0.05}\n"
                                     "  - {kind: energy_fluctuation}\n  - {kind: peak_torque}\n"
                                     "  - {kind: max, column: T_req}\n");
  study::Study<mechgen::ViewModel> s{mechgen::ViewModel(mech::design_press::View())};
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  const std::vector<double> nominal = s.nominal();
  double worst = 0;
  for (size_t k = 0; k < spec.metrics.size(); ++k) {
    std::string why;
    const std::vector<double> g = s.Gradient(k, &why);
    ASSERT_TRUE(why.empty()) << why;
    for (size_t p = 0; p < nominal.size(); ++p) {
      const double R = RichardsonOfMetric(&s, nominal, p, k, 1e-4 * std::abs(nominal[p]));
      const double e = std::abs(g[p] - R) / std::max(1.0, std::abs(R));
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-7) << "metric " << k << " parameter " << spec.parameters[p].name << ": " << g[p]
                         << " against " << R;
      EXPECT_NE(g[p], 0) << k << " " << p;  // every one of them moves every metric here
    }
  }
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", worst);
  RecordProperty("worst_relative_error", text);
}

// The first order of the simulation metrics (the trajectory sensitivities dq/dp, dq_dot/dp of
// dynamics/sensitivity.h along the nominal's free motion, through Study::Gradient) against
// Richardson central differences of the study's own metrics, each sample's whole simulation
// again at p +- h (the minimal method's run: an independent route). The damped press of
// tests/design thrown from its assembly at 6 rad/s: the crank's angle and speed at a sample,
// their extremes (the sample held) and an rms. The study's runs and the sensitivities' are
// each integrated to rtol 1e-8 (the simulation's defaults), so differences of the metrics carry
// ~1e-8 relative noise over h: agreement to 1e-5 relative (measured: worst_relative_error).
// The kinetic energy's metric has no first order, and says why. The study through the model view
// (the sensitivities compiled once, runtime/view/analysis_simulate_design.cc), and the generated
// press's the same figures to the bit.
TEST(StudySimulate, FirstOrderOfTheSimulationMetricsAgainstDifferencesOfTheStudy) {
  const std::string text =
      "method: grid\nanalysis: simulate\nt_end: 0.4\nsteps: 40\nqd0: [6]\n"
      "parameters:\n  a: {values: [0.1]}\n  m3: {values: [8]}\n  c: {values: [400]}\n  k: {values: [2000]}\n"
      "metrics:\n  - {kind: at, column: theta_crank, step: 20}\n  - {kind: max, column: theta_crank_dot}\n"
      "  - {kind: min, column: theta_crank_dot}\n  - {kind: rms, column: theta_crank}\n"
      "  - {kind: at, column: theta_crank_dot, step: 40}\n  - {kind: max, column: T}\n";
  const study::StudySpec spec = Read("psim.yaml", text);
  study::Study<mechgen::ViewModel> s{mechgen::ViewModel(mech::design_press::View())};
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  const std::vector<double> nominal = s.nominal();
  double worst = 0;
  for (size_t k = 0; k + 1 < spec.metrics.size(); ++k) {
    std::string why;
    const std::vector<double> g = s.Gradient(k, &why);
    ASSERT_TRUE(why.empty()) << k << ": " << why;
    for (size_t p = 0; p < nominal.size(); ++p) {
      const double R = RichardsonOfMetric(&s, nominal, p, k, 1e-3 * std::abs(nominal[p]));
      // (per unit of the parameter's own scale: the metric's change over a 100 % change of p)
      const double e = std::abs(g[p] - R) * std::abs(nominal[p]) /
                       std::max(std::abs(R * nominal[p]), 1e-3 * std::abs(s.Value(k, s.nominal_rows()).value));
      worst = std::max(worst, e);
      EXPECT_LT(e, 1e-5) << "metric " << k << " parameter " << spec.parameters[p].name << ": " << g[p]
                         << " against " << R;
      EXPECT_TRUE(std::isfinite(g[p])) << k << " " << p;
    }
  }
  char figure[32];
  std::snprintf(figure, sizeof(figure), "%.3g", worst);
  RecordProperty("worst_relative_error", figure);
  std::string why;
  EXPECT_TRUE(std::isnan(s.Gradient(spec.metrics.size() - 1, &why)[0]));
  EXPECT_NE(why.find("no trajectory sensitivity of the column T"), std::string::npos) << why;
  // The generated press's study: the same values and first order, to the bit (and the same why).
  ExpectViewFirstOrderSame<mech::design_press::Model>(mech::design_press::View(), spec);
}

// The flywheel's metrics through the model view (the cycle and its design derivatives compiled
// once, machines/view_machines.h) read the energy loop's columns as the generated model's study
// does: each metric at the nominal and its first order (dT_req/d<p> at the peak's sample for
// peak_torque and max of T_req) the same bits.
TEST(StudyView, FlywheelColumnsAndTheirFirstOrderAsTheGeneratedModels) {
  ExpectViewFirstOrderSame<mech::design_press::Model>(
      mech::design_press::View(),
      Read("vflywheel.yaml", "method: monte_carlo\ncount: 4\nanalysis: flywheel\nomega: 12.566370614359172\n"
                             "steps: 360\nparameters:\n  a: {tolerance: 0.001}\n  m3: {tolerance: 0.5}\n"
                             "metrics:\n  - {kind: mean_torque}\n  - {kind: peak_torque}\n"
                             "  - {kind: max, column: T_req}\n  - {kind: min, column: E}\n"
                             "  - {kind: at, column: T_static, step: 90}\n  - {kind: rms, column: T_inertia}\n"));
}
#endif

// The flywheel analysis' errors: its metrics need it, it needs omega and the model's forces.
TEST(StudyFlywheel, ErrorsNameTheirPlace) {
  const std::string e1 = ErrorOf("f1.yaml",
                                 "method: grid\nanalysis: flywheel\nparameters:\n  F: {values: [1]}\n"
                                 "metrics: [{kind: mean_torque}]\n");
  EXPECT_NE(e1.find("f1.yaml:2:11: error: analysis: flywheel needs omega:"), std::string::npos) << e1;
  const std::string e2 = ErrorOf("f2.yaml",
                                 "method: grid\nparameters:\n  F: {values: [1]}\n"
                                 "metrics:\n  - {kind: flywheel_inertia, C_s: 0.02}\n");
  EXPECT_NE(e2.find("f2.yaml:5:5: error: a metric of this kind needs analysis: flywheel"), std::string::npos) << e2;
  const std::string e3 = ErrorOf("f3.yaml",
                                 "method: grid\nanalysis: flywheel\nomega: 1\nparameters:\n  F: {values: [1]}\n"
                                 "metrics:\n  - {kind: flywheel_inertia}\n");
  EXPECT_NE(e3.find("f3.yaml:7:5: error: a metric of kind flywheel_inertia needs C_s:"), std::string::npos) << e3;
  const study::StudySpec spec = Read("f4.yaml",
                                     "method: grid\nanalysis: flywheel\nomega: 1\nparameters:\n  a: {values: [1]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n");
  study::Study<mech::fourbar::Model> s;
  std::string error;
  EXPECT_FALSE(s.Prepare(spec, &error));
  EXPECT_NE(error.find("f4.yaml:2:11: error: analysis: flywheel needs a one-input machine"), std::string::npos)
      << error;
}
#endif

}  // namespace
