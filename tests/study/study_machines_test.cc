// Design studies of the machines' analyses per sample (issue 29; split from study_test.cc,
// which compiled alone at the end of the sanitizer build for 470 s): the flywheel, simulation,
// positions and engine analyses against hand formulas, the runtime run directly and differences
// of the study itself, and their errors.
#include "study_test_common.h"

namespace {

using namespace mechgen_study_test;  // NOLINT (the tests' shared helpers)

// ---- the flywheel analysis per sample ----------------------------------------------------------

#ifdef MECHGEN_STUDY_TEST_SHAPER
// The quick-return shaper of tests/statics (crank r about O2 = (0, d), the slotted rocker about
// O4 = (0, 0), rocker L, link l, the ram on y = h): a cutting force F on the forward stroke only
// (crank -30 to 210 deg, where sin theta = -r/d puts the rocker at its extremes), the probe
// torque off (P = 0). The ram's place by hand, for the work per turn F * stroke.
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
  using M = mech::shaper::Model;
  study::Study<M> s;
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
    M::ParamsT<double> p;
    p.F = F, p.L = L, p.l = l, p.P = 0;
    mechgen::flywheel::MachineCycleOptions o;
    o.omega = 2 * pi;
    o.samples = 720;
    const mechgen::flywheel::MachineCycle c = mechgen::flywheel::SampleMachineCycle<M>(p, o);
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
  using M = mech::shaper::Model;
  study::Study<M> s;
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
    M::ParamsT<double> p;
    p.F = v[3 * i], p.L = v[3 * i + 1], p.P = 0;
    mechgen::flywheel::MachineCycleOptions o;
    o.omega = 2 * pi;
    o.samples = 720;
    const mechgen::flywheel::MachineCycle c = mechgen::flywheel::SampleMachineCycle<M>(p, o);
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
  study::Study<M> b;
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
// damped press of tests/design: smooth loads, so the breaks do not move.
TEST(StudyFlywheel, FirstOrderOfTheCycleMetricsAgainstDifferencesOfTheStudy) {
  const study::StudySpec spec = Read("press.yaml",
                                     "method: grid\nanalysis: flywheel\nomega: 12.566370614359172\nsteps: 360\n"
                                     "parameters:\n  a: {values: [0.1]}\n  b: {values: [0.35]}\n  m3: {values: [8]}\n"
                                     "  c: {values: [400]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n  - {kind: flywheel_inertia, C_s: 0.05}\n"
                                     "  - {kind: energy_fluctuation}\n  - {kind: peak_torque}\n"
                                     "  - {kind: max, column: T_req}\n");
  using M = mech::design_press::Model;
  study::Study<M> s;
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
// The kinetic energy's metric has no first order, and says why; through the model view the same
// figures to the bit (the sensitivities compiled once, runtime/view/analysis_simulate_design.cc).
TEST(StudySimulate, FirstOrderOfTheSimulationMetricsAgainstDifferencesOfTheStudy) {
  const std::string text =
      "method: grid\nanalysis: simulate\nt_end: 0.4\nsteps: 40\nqd0: [6]\n"
      "parameters:\n  a: {values: [0.1]}\n  m3: {values: [8]}\n  c: {values: [400]}\n  k: {values: [2000]}\n"
      "metrics:\n  - {kind: at, column: theta_crank, step: 20}\n  - {kind: max, column: theta_crank_dot}\n"
      "  - {kind: min, column: theta_crank_dot}\n  - {kind: rms, column: theta_crank}\n"
      "  - {kind: at, column: theta_crank_dot, step: 40}\n  - {kind: max, column: T}\n";
  const study::StudySpec spec = Read("psim.yaml", text);
  using M = mech::design_press::Model;
  study::Study<M> s;
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
  // Through the model view: the same values and first order, to the bit (and the same why).
  ExpectViewFirstOrderSame<M>(mech::design_press::View(), spec);
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

#ifdef MECHGEN_STUDY_TEST_PENDULUM
// ---- the simulation per sample ----------------------------------------------------------------

// The pendulum of tests/runtime (bar OA = l on a pin at O, mass m at c, inertia Jc, gravity g,
// torsional spring k with free angle theta0, a constant force Fy along y at A) released at rest
// from theta = 0. The work of all its loads from 0 to theta is -(U(theta) - U(0)) with
//   U(theta) = m g c sin(theta) + k (theta - theta0)^2 / 2 - Fy l sin(theta),
// so the swing's far turning point solves U(theta_t) = U(0), the kinetic energy peaks at
// U(0) - U(theta_e) where U'(theta_e) = 0, and at the release (qd = 0) Newton on the bar gives
// alpha = -U'(0) / I_O and the pin's force on the bar (0, m c alpha + m g - Fy). Each sample of
// a grid over k and Fy against these, and 1 and 3 threads bit for bit.
TEST(StudySimulate, PendulumTurningPointPeakEnergyAndReleaseReactionAgainstHandFormulas) {
  const double t_end = 1.6;
  const int steps = 3200;
  const study::StudySpec spec = Read(
      "sim.yaml",
      "method: grid\nanalysis: simulate\nt_end: 1.6\nsteps: 3200\nq0: [0]\n"
      "parameters:\n  k: {values: [0, 3]}\n  Fy: {values: [0, 4]}\n"
      "metrics:\n  - {kind: min, column: theta_bar, name: far}\n  - {kind: max, column: T, name: T_peak}\n"
      "  - {kind: at, column: F_O_x, step: 0, name: Fx0}\n  - {kind: at, column: F_O_y, step: 0, name: Fy0}\n"
      "  - {kind: failures}\n");
  using M = mech::pendulum_spring::Model;
  study::Study<M> s;
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  EXPECT_EQ(s.Unit(1), "J");
  EXPECT_EQ(s.Unit(3), "N");
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> one, three;
  s.Run(v, 1, &one);
  s.Run(v, 3, &three);
  ASSERT_EQ(one.size(), 4u);
  const M::ParamsT<double> p0;
  const double l = p0.l, c = p0.c, m = p0.m, g = p0.g, theta0 = p0.theta0, I_O = p0.Jc + p0.m * p0.c * p0.c;
  const double dt = t_end / steps;
  for (size_t i = 0; i < one.size(); ++i) {
    const double k = v[2 * i], Fy = v[2 * i + 1];
    ASSERT_STREQ(one[i].status, "ok") << i;
    auto U = [&](double th) { return m * g * c * std::sin(th) + 0.5 * k * (th - theta0) * (th - theta0) - Fy * l * std::sin(th); };
    auto dU = [&](double th) { return m * g * c * std::cos(th) + k * (th - theta0) - Fy * l * std::cos(th); };
    auto ddU = [&](double th) { return -m * g * c * std::sin(th) + k + Fy * l * std::sin(th); };
    // theta_e: U' = 0 between -pi and 0 (U' > 0 at 0, < 0 at -pi/2 - 0.5 here), by bisection.
    auto bisect = [](auto f, double a, double b) {
      for (int n = 0; n < 200; ++n) {
        const double mid = 0.5 * (a + b);
        ((f(a) < 0) == (f(mid) < 0) ? a : b) = mid;
      }
      return 0.5 * (a + b);
    };
    ASSERT_GT(dU(0), 0) << i;
    const double theta_e = bisect(dU, -2.5, 0.0);
    const double theta_t = bisect([&](double th) { return U(th) - U(0); }, -4.0, theta_e);
    const double T_peak = U(0) - U(theta_e);
    // Sampling: the study sees the motion every dt; near an extreme a quantity differs from its
    // extreme by at most |second time derivative| (dt/2)^2 / 2; the integrator (rtol 1e-8 per
    // step, ~10^3 steps) adds up to 1e-6 relative.
    const double alpha_t = std::abs(dU(theta_t)) / I_O;  // |theta_ddot| at the turning point
    const double T_ddot = std::abs(ddU(theta_e)) * 2 * T_peak / I_O;
    EXPECT_NEAR(one[i].metrics[0], theta_t, 1.1 * alpha_t * dt * dt / 8 + 1e-6 * std::abs(theta_t)) << i;
    EXPECT_GE(one[i].metrics[0], theta_t - 1e-6 * std::abs(theta_t)) << i;  // no sample beyond it
    EXPECT_NEAR(one[i].metrics[1], T_peak, 1.1 * T_ddot * dt * dt / 8 + 1e-6 * T_peak) << i;
    EXPECT_LE(one[i].metrics[1], T_peak * (1 + 1e-6)) << i;
    const double alpha0 = -dU(0) / I_O;
    EXPECT_NEAR(one[i].metrics[2], 0, 1e-9) << i;
    EXPECT_NEAR(one[i].metrics[3], m * c * alpha0 + m * g - Fy, 1e-9 * (m * g)) << i;
    EXPECT_EQ(one[i].metrics[4], 0) << i;
    for (size_t q = 0; q < one[i].metrics.size(); ++q) {
      const double x = one[i].metrics[q], y = three[i].metrics[q];
      EXPECT_TRUE(std::memcmp(&x, &y, sizeof x) == 0) << i << " " << q;
    }
  }
  // No first order of a simulation, and why.
  std::string why;
  EXPECT_TRUE(std::isnan(s.Gradient(0, &why)[0]));
  EXPECT_NE(why.find("simulation"), std::string::npos) << why;
}

// The simulation's errors: t_end, q0's size, the metrics it has, a model without dynamics, a
// column the simulation's CSV does not have (the list of those it has).
TEST(StudySimulate, ErrorsNameTheirPlace) {
  const std::string e1 = ErrorOf("s1.yaml", "method: grid\nanalysis: simulate\nparameters:\n  k: {values: [1]}\n"
                                            "metrics: [{kind: failures}]\n");
  EXPECT_NE(e1.find("s1.yaml:2:11: error: analysis: simulate needs t_end:"), std::string::npos) << e1;
  const std::string e2 = ErrorOf("s2.yaml", "method: grid\nanalysis: simulate\nt_end: 1\nparameters:\n  k: {values: [1]}\n"
                                            "metrics:\n  - {kind: path_deviation, point: bar.A}\n");
  EXPECT_NE(e2.find("s2.yaml:7:5: error: with analysis: simulate the metrics are max, min"), std::string::npos) << e2;
  const std::string e3 = ErrorOf("s3.yaml", "method: grid\nt_end: 1\nparameters:\n  k: {values: [1]}\n"
                                            "metrics: [{kind: failures}]\n");
  EXPECT_NE(e3.find("s3.yaml:2:8: error: t_end: is for analysis: simulate"), std::string::npos) << e3;
  const std::string e4 = ErrorOf("s4.yaml", "method: grid\nanalysis: simulate\nt_end: 0\nparameters:\n  k: {values: [1]}\n"
                                            "metrics: [{kind: failures}]\n");
  EXPECT_NE(e4.find("s4.yaml:3:8: error: t_end: expected a time > 0"), std::string::npos) << e4;
  {
    const study::StudySpec spec = Read("s5.yaml", "method: grid\nanalysis: simulate\nt_end: 1\nq0: [0, 1]\n"
                                                  "parameters:\n  k: {values: [1]}\nmetrics: [{kind: failures}]\n");
    study::Study<mech::pendulum_spring::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("s5.yaml:4:5: error: q0: expected 1 value(s), one per input"), std::string::npos) << error;
  }
  {
    const study::StudySpec spec = Read("s6.yaml", "method: grid\nanalysis: simulate\nt_end: 1\n"
                                                  "parameters:\n  k: {values: [1]}\n"
                                                  "metrics:\n  - {kind: max, column: drive_theta_bar}\n");
    study::Study<mech::pendulum_spring::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("s6.yaml:7:5: error: no numeric column 'drive_theta_bar' in the simulation's output"),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("theta_bar_dot, theta_bar_ddot, T, V, E, W_nc"), std::string::npos) << error;
  }
  {
    const study::StudySpec spec = Read("s7.yaml", "method: grid\nanalysis: simulate\nt_end: 1\n"
                                                  "parameters:\n  a: {values: [1]}\nmetrics: [{kind: failures}]\n");
    study::Study<mech::fourbar::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("s7.yaml:2:11: error: analysis: simulate needs a model with `dynamics`"), std::string::npos)
        << error;
  }
}
// Driven: theta_bar turned at omega = 2 rad/s from 0 (every input driven: inverse dynamics). The
// motion is the law's, so the actuator torque is the static one, lambda = U'(theta) (gravity,
// spring, tip force), and the pin's force from Newton on the bar with a_G = -omega^2 c e_r:
// F_O = (-m omega^2 c cos, -m omega^2 c sin + m g - Fy). The study's peaks against those at every
// sample, and against PrescribedDynamics run directly (as `pendulum_spring_simulate --drive
// theta_bar=speed:2`), bit for bit; 1 and 2 threads the same bytes.
TEST(StudySimulate, DrivenPendulumPeakTorqueAndBearingAgainstHandFormulasAndTheRuntime) {
  const double t_end = 1.5, omega = 2;
  const int steps = 300;
  const study::StudySpec spec = Read(
      "driven.yaml",
      "method: grid\nanalysis: simulate\nt_end: 1.5\nsteps: 300\nq0: [0]\ndrive: {theta_bar: {speed: 2}}\n"
      "parameters:\n  k: {values: [0, 3]}\n  Fy: {values: [0, 4]}\n"
      "metrics:\n  - {kind: peak_drive}\n  - {kind: peak_bearing}\n"
      "  - {kind: at, column: lambda_theta_bar, step: 150, name: lambda_mid}\n  - {kind: failures}\n");
  using M = mech::pendulum_spring::Model;
  study::Study<M> s;
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  EXPECT_EQ(s.Unit(0), "N m");
  EXPECT_EQ(s.Unit(1), "N");
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> one, two;
  s.Run(v, 1, &one);
  s.Run(v, 2, &two);
  ASSERT_EQ(one.size(), 4u);
  const M::ParamsT<double> p0;
  const double l = p0.l, c = p0.c, m = p0.m, g = p0.g, theta0 = p0.theta0;
  for (size_t i = 0; i < one.size(); ++i) {
    const double k = v[2 * i], Fy = v[2 * i + 1];
    ASSERT_STREQ(one[i].status, "ok") << i;
    auto lambda = [&](double th) { return m * g * c * std::cos(th) + k * (th - theta0) - Fy * l * std::cos(th); };
    auto bearing = [&](double th) {
      return std::hypot(-m * omega * omega * c * std::cos(th), -m * omega * omega * c * std::sin(th) + m * g - Fy);
    };
    double peak_lambda = 0, peak_bearing = 0;
    for (int j = 0; j <= steps; ++j) {
      const double th = omega * (j * (t_end / steps));
      peak_lambda = std::max(peak_lambda, std::abs(lambda(th)));
      peak_bearing = std::max(peak_bearing, bearing(th));
    }
    EXPECT_NEAR(one[i].metrics[0], peak_lambda, 1e-9 * peak_lambda) << i;
    EXPECT_NEAR(one[i].metrics[1], peak_bearing, 1e-9 * peak_bearing) << i;
    EXPECT_NEAR(one[i].metrics[2], lambda(omega * t_end / 2), 1e-9 * (1 + std::abs(lambda(omega * t_end / 2)))) << i;
    EXPECT_EQ(one[i].metrics[3], 0) << i;
    // The runtime called directly, as the simulate tool's driven run.
    M::ParamsT<double> p;
    p.k = k;
    p.Fy = Fy;
    namespace dyn = mechgen::dynamics;
    using Sim = dyn::PrescribedDynamics<M, 1, dyn::AnyDrive<1>>;
    dyn::PrescribedOptions options;
    options.sample_dt = t_end / steps;
    Sim sim(p, std::array<int, 1>{0}, dyn::AnyDrive<1>({dyn::AnyLaw(dyn::ConstantSpeedLaw{0.0, omega, 0.0})}),
            dyn::NoForce(), options);
    Sim::VecF qf0;
    ASSERT_TRUE(sim.Initialize(0.0, qf0));
    double direct = 0;
    int samples = 0;
    dyn::PrescribedSummary summary;
    sim.Simulate(
        0.0, qf0, qf0, t_end,
        [&](const Sim::SampleT& x) {
          direct = std::max(direct, std::abs(x.lambda(0)));
          ++samples;
          return true;
        },
        &summary);
    EXPECT_EQ(samples, steps + 1);
    EXPECT_EQ(one[i].metrics[0], direct) << i;
    for (size_t q = 0; q < one[i].metrics.size(); ++q) {
      const double x = one[i].metrics[q], y = two[i].metrics[q];
      EXPECT_TRUE(std::memcmp(&x, &y, sizeof x) == 0) << i << " " << q;
    }
  }
}

TEST(StudySimulate, DriveErrorsNameTheirPlace) {
  using M = mech::pendulum_spring::Model;
  {
    const study::StudySpec spec = Read("d1.yaml", "method: grid\nanalysis: simulate\nt_end: 1\ndrive: {phi: {speed: 1}}\n"
                                                  "parameters:\n  k: {values: [1]}\nmetrics: [{kind: failures}]\n");
    study::Study<M> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("d1.yaml:4:9: error: drive: the model pendulum_spring has no input 'phi' (its inputs: "
                         "theta_bar)"),
              std::string::npos)
        << error;
  }
  const std::string e2 = ErrorOf("d2.yaml", "method: grid\nanalysis: simulate\nt_end: 1\n"
                                            "parameters:\n  k: {values: [1]}\nmetrics:\n  - {kind: peak_drive}\n");
  EXPECT_NE(e2.find("d2.yaml:7:5: error: peak_drive of a simulation is the largest |lambda| of a driven input"),
            std::string::npos)
      << e2;
  const std::string e3 = ErrorOf("d3.yaml", "method: grid\ndrive: {theta_bar: {speed: 1}}\n"
                                            "parameters:\n  k: {values: [1]}\nmetrics: [{kind: failures}]\n");
  EXPECT_NE(e3.find("d3.yaml:2:8: error: drive: is for analysis: simulate"), std::string::npos) << e3;
  const std::string e4 = ErrorOf("d4.yaml", "method: grid\nanalysis: simulate\nt_end: 1\n"
                                            "drive: {theta_bar: {move: [1, 0.5, 0.2]}}\n"
                                            "parameters:\n  k: {values: [1]}\nmetrics: [{kind: failures}]\n");
  EXPECT_NE(e4.find("d4.yaml:4:27: error: drive move: expected |Q1| <= 1e6 and 0 <= T0 < T1"), std::string::npos)
      << e4;
}
#endif

// ---- positions only -------------------------------------------------------------------------

// The positions-only analysis (each row solved alone by the generated closed form) against the
// kinematic sweep (PositionSolver's continuation) at the same inputs: the coupler point, its
// extremes, the transmission angles and the path deviation agree to rounding; the `at:` form at
// the same inputs gives the same rows; 1 and 2 threads the same bytes.
TEST(StudyPositions, FourbarCouplerPointAgainstTheSweep) {
  const std::string body =
      "method: monte_carlo\ncount: 200\nseed: 3\nparameters:\n  a: {tolerance: 0.01}\n  b: {tolerance: 0.01}\n"
      "  c: {tolerance: 0.01}\n  d: {tolerance: 0.01}\n  xi: {tolerance: 0.01}\n  eta: {tolerance: 0.01}\n"
      "metrics:\n  - {kind: at, column: coupler.P.x, step: 3, name: x3}\n  - {kind: at, column: coupler.P.y, step: 3, "
      "name: y3}\n  - {kind: max, column: coupler.P.y}\n  - {kind: min, column: theta_rocker}\n"
      "  - {kind: min_transmission_angle}\n  - {kind: path_deviation, point: coupler.P}\n  - {kind: failures}\n";
  const study::StudySpec sweep = Read("pos_sweep.yaml", "analysis: sweep\nsteps: 36\nrange: [0, 360deg]\n" + body);
  const study::StudySpec positions =
      Read("pos.yaml", "analysis: positions\nsteps: 36\nrange: [0, 360deg]\n" + body);
  std::string at = "analysis: positions\nat: [";
  for (int i = 0; i <= 36; ++i) at += (i ? ", " : "") + std::to_string(10 * i) + "deg";
  const study::StudySpec listed = Read("pos_at.yaml", at + "]\n" + body);
  using M = mech::fourbar::Model;
  study::Study<M> a, b, c;
  std::string error;
  ASSERT_TRUE(a.Prepare(sweep, &error)) << error;
  ASSERT_TRUE(b.Prepare(positions, &error)) << error;
  ASSERT_TRUE(c.Prepare(listed, &error)) << error;
  const std::vector<double> v = study::DrawSamples(sweep, a.nominal());
  ASSERT_EQ(v, study::DrawSamples(positions, b.nominal()));
  std::vector<study::SampleResult> ra, rb, rb2, rc;
  a.Run(v, 1, &ra);
  b.Run(v, 1, &rb);
  b.Run(v, 2, &rb2);
  c.Run(v, 1, &rc);
  ASSERT_EQ(ra.size(), 200u);
  for (size_t i = 0; i < ra.size(); ++i) {
    ASSERT_STREQ(ra[i].status, "ok") << i;
    ASSERT_STREQ(rb[i].status, "ok") << i;
    for (size_t k = 0; k < ra[i].metrics.size(); ++k) {
      const double tol = k == 5 ? 1e-12 : 1e-11 * (1 + std::abs(ra[i].metrics[k]));
      EXPECT_NEAR(rb[i].metrics[k], ra[i].metrics[k], tol) << i << " " << k;
      EXPECT_NEAR(rc[i].metrics[k], rb[i].metrics[k], tol) << i << " " << k;
      const double x = rb[i].metrics[k], y = rb2[i].metrics[k];
      EXPECT_TRUE(std::memcmp(&x, &y, sizeof x) == 0) << i << " " << k;
    }
  }
  // The first order of a positions study reads the same design columns as the sweep's.
  std::string why_a, why_b;
  const std::vector<double> ga = a.Gradient(0, &why_a), gb = b.Gradient(0, &why_b);
  for (size_t p = 0; p < ga.size(); ++p) EXPECT_NEAR(gb[p], ga[p], 1e-12) << p << why_b;
}

TEST(StudyPositions, ErrorsNameTheirPlace) {
  {
    const study::StudySpec spec = Read("p1.yaml", "method: grid\nanalysis: positions\nat: [0, 1]\n"
                                                  "parameters:\n  a: {values: [1]}\n"
                                                  "metrics:\n  - {kind: max, column: theta_rocker_dot}\n");
    study::Study<mech::fourbar::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("p1.yaml:7:5: error: no numeric column 'theta_rocker_dot'"), std::string::npos) << error;
    EXPECT_NE(error.find("(columns: theta_crank, theta_coupler, theta_rocker, coupler.P.x, coupler.P.y"),
              std::string::npos)
        << error;
  }
  const std::string e2 = ErrorOf("p2.yaml", "method: grid\nat: [0, 1]\nparameters:\n  a: {values: [1]}\n"
                                            "metrics: [{kind: failures}]\n");
  EXPECT_NE(e2.find("p2.yaml:2:5: error: at: is for analysis: positions"), std::string::npos) << e2;
  const std::string e3 = ErrorOf("p3.yaml", "method: grid\nanalysis: positions\nat: [0, 1]\nsteps: 3\n"
                                            "parameters:\n  a: {values: [1]}\nmetrics: [{kind: failures}]\n");
  EXPECT_NE(e3.find("p3.yaml:3:5: error: at: lists the input's values"), std::string::npos) << e3;
  const std::string e4 = ErrorOf("p4.yaml", "method: grid\nanalysis: positions\nat: [0, 1]\n"
                                            "parameters:\n  a: {values: [1]}\nmetrics: [{kind: peak_bearing}]\n");
  EXPECT_NE(e4.find("p4.yaml:6:11: error: analysis: positions has no forces"), std::string::npos) << e4;
}

// ---- threads --------------------------------------------------------------------------------

// 1, 2 and 4 threads: every metric of every sample the same double, and the statuses.
#ifdef MECHGEN_STUDY_TEST_ENGINE
// ---- the engine cycle per sample ---------------------------------------------------------------

// The engine analysis of one design run directly (machines/engine/cycle.h, as `engine_single_engine
// flywheel` runs it): the energy loop, the model's J_fly and the crank speed.
struct DirectEngine {
  mechgen::engine::EngineEnergy energy;
  double J_fly = 0;
  std::vector<mechgen::engine::CrankPoint<mech::engine_single::Model>> pts;  ///< the cycle's crank angles
  int R_O = -1;                                                                ///< the main bearing's reaction
};
DirectEngine RunEngineDirectly(double r, double l, double rpm, int samples, const mechgen::engine::PressureTable* table) {
  using M = mech::engine_single::Model;
  namespace eng = mechgen::engine;
  M::ParamsT<double> p;
  p.r = r, p.l = l;
  DirectEngine out;
  eng::Engine e;
  std::string error;
  EXPECT_TRUE(eng::ReadEngine<M>(&p, &e, &error)) << error;
  eng::PolytropicWiebeCycle wiebe;
  eng::PressureLaw law;
  EXPECT_TRUE(eng::InitPressureLaw(e, eng::PolytropicWiebeParams(), table, &wiebe, &law, &error)) << error;
  const eng::CycleGas gas = eng::MakeGas(&p, e, &law);
  std::vector<eng::CrankPoint<M>> pts;
  EXPECT_TRUE(eng::RunCycle<M>(p, e, gas, rpm * 2 * 3.14159265358979323846 / 60, samples, &pts, &error)) << error;
  out.energy = eng::EngineEnergyLoop(pts, e);
  out.J_fly = e.J_fly;
  out.pts = pts;
  out.R_O = e.R_O;
  return out;
}

// A grid of the crank radius and the rod length of the single-cylinder four-stroke engine at
// 3000 rpm under the parametric gas law (its volume from each sample's bore, r and l). Per sample:
// - the mean torque against the gas work by hand: the mean over the same 360 crank angles of
//   -p(theta) A x'(theta), x = r cos theta + sqrt(l^2 - r^2 sin^2 theta) the piston's place (the
//   inertia torque -1/2 I' omega^2, a derivative of a periodic function, has a zero mean);
// - the reciprocating parts' mean inertia that flywheel_inertia subtracts (Delta E / (C_s omega^2)
//   - flywheel_inertia) against the mean of m_pis x'^2 + m_rod |v_G|^2 + J_rod phi'^2 by hand
//   (the rod's angle phi from sin phi = -r sin theta / l, its centre l_G from B), and
//   speed_fluctuation against Delta E / ((J_fly + that mean) omega^2);
// - every metric the same bits as the engine analysis run directly at that design;
// and the same bits for 1 and 2 threads.
TEST(StudyEngine, CrankAndRodGridAgainstTheGasWorkByHandAndTheEngineRunDirectly) {
  const study::StudySpec spec = Read("engine.yaml",
                                     "method: grid\nanalysis: engine\nrpm: 3000\nsteps: 360\n"
                                     "parameters:\n  r: {values: [0.040, 0.046]}\n  l: {values: [0.140, 0.150]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n  - {kind: peak_torque}\n"
                                     "  - {kind: energy_fluctuation}\n  - {kind: flywheel_inertia, C_s: 0.02}\n"
                                     "  - {kind: speed_fluctuation}\n  - {kind: failures}\n");
  using M = mech::engine_single::Model;
  study::Study<M> s;
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  EXPECT_EQ(s.Unit(3), "kg m^2");
  EXPECT_EQ(s.Unit(4), "1");
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> one, two;
  s.Run(v, 1, &one);
  s.Run(v, 2, &two);
  ASSERT_EQ(one.size(), 4u);
  const double pi = 3.14159265358979323846, omega = 3000 * 2 * pi / 60;
  const M::ParamsT<double> defaults;
  const double A = pi * defaults.bore * defaults.bore / 4;
  for (size_t i = 0; i < one.size(); ++i) {
    ASSERT_STREQ(one[i].status, "ok") << i;
    const double r = v[2 * i], l = v[2 * i + 1];
    const std::vector<double>& m = one[i].metrics;
    // The gas work and the mean inertia by hand, over the cycle's 360 angles.
    mechgen::engine::PolytropicWiebeParams w;
    w.bore = defaults.bore, w.stroke = 2 * r, w.rod_length = l;
    mechgen::engine::PolytropicWiebeCycle law;
    ASSERT_TRUE(law.Init(w, &error)) << error;
    double gas = 0, inertia = 0;
    const int n = 360;
    for (int k = 0; k < n; ++k) {
      const double th = 4 * pi * k / n, sn = std::sin(th), cs = std::cos(th);
      const double root = std::sqrt(l * l - r * r * sn * sn);
      const double dx = -r * sn - r * r * sn * cs / root;
      gas += -law.Pressure(th) * A * dx / n;
      const double phi = std::asin(-r * sn / l), dphi = -r * cs / (l * std::cos(phi));
      const double vGx = -r * sn - defaults.l_G * dphi * std::sin(phi);
      const double vGy = r * cs + defaults.l_G * dphi * std::cos(phi);
      inertia += (defaults.m_pis * dx * dx + defaults.m_rod * (vGx * vGx + vGy * vGy) +
                  defaults.J_rod * dphi * dphi) / n;
    }
    EXPECT_NEAR(m[0], gas, 1e-9 * std::abs(gas)) << i;
    EXPECT_GT(m[0], 0) << i;
    const double I_recip = m[2] / (0.02 * omega * omega) - m[3];
    EXPECT_NEAR(I_recip, inertia, 1e-9 * inertia) << i;
    EXPECT_NEAR(m[4], m[2] / ((defaults.J_fly + inertia) * omega * omega), 1e-9 * m[4]) << i;
    EXPECT_GE(m[1], std::abs(m[0])) << i;
    EXPECT_EQ(m[5], 0) << i;
    // The engine analysis of this design run directly: the same code, the same bits.
    const DirectEngine d = RunEngineDirectly(r, l, 3000, 360, nullptr);
    ASSERT_TRUE(d.energy.ok()) << d.energy.message;
    EXPECT_EQ(m[0], d.energy.loop.mean_torque) << i;
    EXPECT_EQ(m[1], std::max(std::abs(d.energy.T_max), std::abs(d.energy.T_min))) << i;
    EXPECT_EQ(m[2], d.energy.loop.delta_E) << i;
    EXPECT_EQ(m[3], d.energy.loop.delta_E / (0.02 * omega * omega) - d.energy.I_recip) << i;
    EXPECT_EQ(m[4], d.energy.loop.delta_E / ((d.J_fly + d.energy.I_recip) * omega * omega)) << i;
    // 1 and 2 threads: the same bits.
    ASSERT_STREQ(two[i].status, "ok");
    ASSERT_EQ(two[i].metrics.size(), m.size());
    EXPECT_EQ(std::memcmp(two[i].metrics.data(), m.data(), m.size() * sizeof(double)), 0) << i;
  }
  // No first order of the engine's cycle in a study, and the reason.
  std::string why;
  EXPECT_TRUE(std::isnan(s.Gradient(0, &why)[0]));
  EXPECT_NE(why.find("engine cycle"), std::string::npos) << why;
}

// The engine's metrics read the engine tool's cycle CSV's and energy loop CSV's columns by name
// (analysis/engine_columns.h): max, min and at of a column, peak_torque the largest |T_total|,
// mean_torque the loop's T_mean; against the engine run directly (the main bearing's reaction
// and the gauge pressure at its crank angles, the loop's extremes of T_total, E and mean), the
// loop's last row at the cycle's end (E = 0) and a crank angle of the cycle's rows.
TEST(StudyEngine, ColumnsOfTheCycleAndTheLoopByName) {
  const study::StudySpec spec = Read("engine_columns.yaml",
                                     "method: grid\nanalysis: engine\nrpm: 3000\nsteps: 360\n"
                                     "parameters:\n  r: {values: [0.040, 0.046]}\n  l: {values: [0.145]}\n"
                                     "metrics:\n  - {kind: peak_torque}\n  - {kind: mean_torque}\n"
                                     "  - {kind: max, column: F_O_x}\n  - {kind: min, column: T_total}\n"
                                     "  - {kind: at, column: p_1, step: 45}\n  - {kind: max, column: E}\n"
                                     "  - {kind: at, column: E, step: 360}\n  - {kind: at, column: T_mean, step: 7}\n"
                                     "  - {kind: at, column: theta_deg, step: 180}\n");
  using M = mech::engine_single::Model;
  study::Study<M> s;
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  EXPECT_EQ(s.Unit(2), "N");
  EXPECT_EQ(s.Unit(4), "Pa");
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> results;
  s.Run(v, 2, &results);
  ASSERT_EQ(results.size(), 2u);
  for (size_t i = 0; i < results.size(); ++i) {
    ASSERT_STREQ(results[i].status, "ok") << i;
    const std::vector<double>& m = results[i].metrics;
    const DirectEngine d = RunEngineDirectly(v[2 * i], v[2 * i + 1], 3000, 360, nullptr);
    ASSERT_TRUE(d.energy.ok()) << d.energy.message;
    ASSERT_EQ(d.pts.size(), 360u);
    double F_O_x = -INFINITY;
    for (const auto& pt : d.pts) F_O_x = std::max(F_O_x, pt.R[static_cast<size_t>(d.R_O)]);
    EXPECT_EQ(m[0], std::max(std::abs(d.energy.T_max), std::abs(d.energy.T_min))) << i;
    EXPECT_EQ(m[1], d.energy.loop.mean_torque) << i;
    EXPECT_EQ(m[2], F_O_x) << i;
    EXPECT_EQ(m[3], d.energy.T_min) << i;
    EXPECT_EQ(m[4], d.pts[45].p[0]) << i;
    EXPECT_GT(m[4], 0) << i;  // 90 deg after firing TDC: the burnt gas expanding
    EXPECT_EQ(m[5], *std::max_element(d.energy.E.begin(), d.energy.E.end())) << i;
    EXPECT_EQ(m[6], 0) << i;  // the loop CSV's last row: the cycle's end, E = 0 as at its start
    EXPECT_EQ(m[7], m[1]) << i;
    EXPECT_NEAR(m[8], 360, 1e-12) << i;  // the cycle CSV's row 180 of 360 over 720 deg
  }
  const study::StudySpec bad = Read("engine_bad.yaml",
                                    "method: grid\nanalysis: engine\nrpm: 3000\nsteps: 360\nparameters:\n"
                                    "  r: {values: [0.04]}\nmetrics:\n  - {kind: max, column: T_req}\n");
  study::Study<M> b;
  EXPECT_FALSE(b.Prepare(bad, &error));
  EXPECT_NE(error.find("engine_bad.yaml:8:5: error: no numeric column 'T_req' in the engine's cycle or energy loop "
                       "output of engine_single (columns: theta_deg, T_gas, T_inertia, T_total, p_1, thrust_1, F_O_x"),
            std::string::npos)
      << error;
}

// gas: {table: FILE}, relative to the study file: the indicator diagram held for every sample,
// the metrics the engine run directly with that table, bit for bit.
TEST(StudyEngine, PressureTableAgainstTheEngineRunDirectly) {
  WriteStudy("indicator.csv", "angle_deg,p_gauge_Pa\n0,2e6\n30,3e6\n120,4e5\n180,1e5\n540,0\n690,6e5\n");
  const study::StudySpec spec = Read("engine_table.yaml",
                                     "method: list\nanalysis: engine\nrpm: 2000\nsteps: 240\n"
                                     "gas: {table: indicator.csv}\n"
                                     "parameters:\n  r: {values: [0.041, 0.045]}\n  l: {values: [0.150, 0.142]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n  - {kind: energy_fluctuation}\n"
                                     "  - {kind: flywheel_inertia, C_s: 0.05}\n");
  using M = mech::engine_single::Model;
  study::Study<M> s;
  std::string error;
  ASSERT_TRUE(s.Prepare(spec, &error)) << error;
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> results;
  s.Run(v, 2, &results);
  ASSERT_EQ(results.size(), 2u);
  mechgen::engine::PressureTable table;
  ASSERT_TRUE(table.Set({0, 30 * 0.017453292519943295, 120 * 0.017453292519943295, 180 * 0.017453292519943295,
                         540 * 0.017453292519943295, 690 * 0.017453292519943295},
                        {2e6, 3e6, 4e5, 1e5, 0, 6e5}, 4 * 3.14159265358979323846, &error))
      << error;
  const double omega = 2000 * 2 * 3.14159265358979323846 / 60;
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_STREQ(results[i].status, "ok") << i;
    const DirectEngine d = RunEngineDirectly(v[2 * i], v[2 * i + 1], 2000, 240, &table);
    EXPECT_EQ(results[i].metrics[0], d.energy.loop.mean_torque) << i;
    EXPECT_EQ(results[i].metrics[1], d.energy.loop.delta_E) << i;
    EXPECT_EQ(results[i].metrics[2], d.energy.loop.delta_E / (0.05 * omega * omega) - d.energy.I_recip) << i;
  }
}

// The engine analysis' errors, each at its place: rpm missing, speed_fluctuation elsewhere, a
// table beside the law's parameters, a bad law value, a missing table, a model that is not an
// engine (without dynamics, and with dynamics but without the engine's names).
TEST(StudyEngine, ErrorsNameTheirPlace) {
  const std::string e1 = ErrorOf("e1.yaml",
                                 "method: grid\nanalysis: engine\nparameters:\n  r: {values: [0.04]}\n"
                                 "metrics: [{kind: mean_torque}]\n");
  EXPECT_NE(e1.find("e1.yaml:2:11: error: analysis: engine needs rpm:"), std::string::npos) << e1;
  const std::string e2 = ErrorOf("e2.yaml",
                                 "method: grid\nanalysis: flywheel\nomega: 1\nparameters:\n  r: {values: [0.04]}\n"
                                 "metrics:\n  - {kind: speed_fluctuation}\n");
  EXPECT_NE(e2.find("e2.yaml:7:5: error: a metric of kind speed_fluctuation needs analysis: engine"),
            std::string::npos)
      << e2;
  const std::string e3 = ErrorOf("e3.yaml",
                                 "method: grid\nanalysis: engine\nrpm: 3000\ngas: {table: t.csv, heat: 500}\n"
                                 "parameters:\n  r: {values: [0.04]}\nmetrics: [{kind: mean_torque}]\n");
  EXPECT_NE(e3.find("e3.yaml:4:"), std::string::npos) << e3;
  EXPECT_NE(e3.find("give table: or the law's parameters, not both"), std::string::npos) << e3;
  const std::string e4 = ErrorOf("e4.yaml",
                                 "method: grid\nanalysis: engine\nrpm: 3000\ngas: {wiebe_a: -1}\n"
                                 "parameters:\n  r: {values: [0.04]}\nmetrics: [{kind: mean_torque}]\n");
  EXPECT_NE(e4.find("e4.yaml:4:16: error: gas: wiebe_a: expected a value in (0"), std::string::npos) << e4;
  const std::string e5 = ErrorOf("e5.yaml",
                                 "method: grid\nanalysis: engine\nrpm: 3000\nomega: 3\n"
                                 "parameters:\n  r: {values: [0.04]}\nmetrics: [{kind: mean_torque}]\n");
  EXPECT_NE(e5.find("e5.yaml:4:8: error: omega: is for analysis: flywheel"), std::string::npos) << e5;
  {
    const study::StudySpec spec = Read("e6.yaml",
                                       "method: grid\nanalysis: engine\nrpm: 3000\ngas: {table: nosuch.csv}\n"
                                       "parameters:\n  r: {values: [0.04]}\nmetrics: [{kind: mean_torque}]\n");
    study::Study<mech::engine_single::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("e6.yaml:4:14: error: gas: table: cannot read the pressure table"), std::string::npos)
        << error;
  }
  {
    const study::StudySpec spec = Read("e7.yaml",
                                       "method: grid\nanalysis: engine\nrpm: 3000\ngas: {cr: 0.5}\n"
                                       "parameters:\n  r: {values: [0.04]}\nmetrics: [{kind: mean_torque}]\n");
    study::Study<mech::engine_single::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("e7.yaml:4:6: error: the nominal design's engine cycle: pressure law: the compression ratio"),
              std::string::npos)
        << error;
  }
  const study::StudySpec spec = Read("e8.yaml",
                                     "method: grid\nanalysis: engine\nrpm: 3000\nparameters:\n  a: {values: [1]}\n"
                                     "metrics:\n  - {kind: mean_torque}\n");
  {
    study::Study<mech::fourbar::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("e8.yaml:2:11: error: analysis: engine needs an engine model of tools/make_engine.py"),
              std::string::npos)
        << error;
  }
#ifdef MECHGEN_STUDY_TEST_PENDULUM
  {
    const study::StudySpec p = Read("e9.yaml",
                                    "method: grid\nanalysis: engine\nrpm: 3000\nparameters:\n  k: {values: [1]}\n"
                                    "metrics:\n  - {kind: mean_torque}\n");
    study::Study<mech::pendulum_spring::Model> s;
    std::string error;
    EXPECT_FALSE(s.Prepare(p, &error));
    EXPECT_NE(error.find("e9.yaml:2:11: error: analysis: engine: the model pendulum_spring: the model has no "
                         "parameter 'bore'"),
              std::string::npos)
        << error;
  }
#endif
}
#endif
}  // namespace
