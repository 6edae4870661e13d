// Design studies of the simulation and the positions per sample (issue 29): the pendulum's
// turning point, peak energy and reactions against hand formulas and the runtime, the driven
// pendulum, the coupler point against the sweep, and their errors. The pendulum's studies and
// runs through its view (Study<ViewModel>, the simulation compiled once: core/view_runtime.h).
#include "study_test_common.h"

namespace {

using namespace mechgen_study_test;  // NOLINT (the tests' shared helpers)

#ifdef MECHGEN_STUDY_TEST_PENDULUM
// ---- the simulation per sample ----------------------------------------------------------------

// The pendulum's model through its view.
mechgen::ViewModel PendulumModel() { return mechgen::ViewModel(mech::pendulum_spring::View()); }

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
  using M = mech::pendulum_spring::Model;  // (its parameters' defaults)
  study::Study<mechgen::ViewModel> s{PendulumModel()};
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
    study::Study<mechgen::ViewModel> s{PendulumModel()};
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("s5.yaml:4:5: error: q0: expected 1 value(s), one per input"), std::string::npos) << error;
  }
  {
    const study::StudySpec spec = Read("s6.yaml", "method: grid\nanalysis: simulate\nt_end: 1\n"
                                                  "parameters:\n  k: {values: [1]}\n"
                                                  "metrics:\n  - {kind: max, column: drive_theta_bar}\n");
    study::Study<mechgen::ViewModel> s{PendulumModel()};
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
// theta_bar=speed:2`; through the view, as `mechgen_view simulate`), bit for bit; 1 and 2
// threads the same bytes.
TEST(StudySimulate, DrivenPendulumPeakTorqueAndBearingAgainstHandFormulasAndTheRuntime) {
  const double t_end = 1.5, omega = 2;
  const int steps = 300;
  const study::StudySpec spec = Read(
      "driven.yaml",
      "method: grid\nanalysis: simulate\nt_end: 1.5\nsteps: 300\nq0: [0]\ndrive: {theta_bar: {speed: 2}}\n"
      "parameters:\n  k: {values: [0, 3]}\n  Fy: {values: [0, 4]}\n"
      "metrics:\n  - {kind: peak_drive}\n  - {kind: peak_bearing}\n"
      "  - {kind: at, column: lambda_theta_bar, step: 150, name: lambda_mid}\n  - {kind: failures}\n");
  using M = mech::pendulum_spring::Model;  // (its parameters' defaults)
  const mechgen::ViewModel model = PendulumModel();
  study::Study<mechgen::ViewModel> s{model};
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
    // The runtime called directly, as the simulate tool's driven run (the library's).
    const mechgen::ViewParams p = ParamsOf(model, {{"k", k}, {"Fy", Fy}});
    namespace dyn = mechgen::dynamics;
    using Sim = dyn::ViewPrescribedDopri5;
    dyn::PrescribedOptions options;
    options.sample_dt = t_end / steps;
    Sim::Indices driven;
    driven.push_back(0);
    Sim sim(model, p, driven, dyn::ViewDrive({dyn::AnyLaw(dyn::ConstantSpeedLaw{0.0, omega, 0.0})}), dyn::NoForce(),
            options);
    Sim::VecF qf0;
    ASSERT_TRUE(dyn::InitializePrescribed(&sim, 0.0, qf0));
    double direct = 0;
    int samples = 0;
    dyn::PrescribedSummary summary;
    dyn::ViewSampleFn<Sim> observer = [&](const Sim::SampleT& x) {
      direct = std::max(direct, std::abs(x.lambda(0)));
      ++samples;
      return true;
    };
    dyn::SimulatePrescribed(&sim, 0.0, qf0, qf0, t_end, observer, &summary, nullptr);
    EXPECT_EQ(samples, steps + 1);
    EXPECT_EQ(one[i].metrics[0], direct) << i;
    for (size_t q = 0; q < one[i].metrics.size(); ++q) {
      const double x = one[i].metrics[q], y = two[i].metrics[q];
      EXPECT_TRUE(std::memcmp(&x, &y, sizeof x) == 0) << i << " " << q;
    }
  }
}

TEST(StudySimulate, DriveErrorsNameTheirPlace) {
  {
    const study::StudySpec spec = Read("d1.yaml", "method: grid\nanalysis: simulate\nt_end: 1\ndrive: {phi: {speed: 1}}\n"
                                                  "parameters:\n  k: {values: [1]}\nmetrics: [{kind: failures}]\n");
    study::Study<mechgen::ViewModel> s{PendulumModel()};
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

}  // namespace
