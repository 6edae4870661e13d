// Design studies of the engine cycle per sample (issue 29): the crank and rod grid against the
// gas work by hand and the engine run directly, the columns of the cycle and the loop by name,
// a pressure table, and the errors. The engine's studies and cycles through its view
// (Study<ViewModel>, the cycle compiled once: machines/view_machines.h).
#include "study_test_common.h"

namespace {

using namespace mechgen_study_test;  // NOLINT (the tests' shared helpers)

#ifdef MECHGEN_STUDY_TEST_ENGINE
// ---- the engine cycle per sample ---------------------------------------------------------------

// The engine's model through its view.
mechgen::ViewModel EngineModel() { return mechgen::ViewModel(mech::engine_single::View()); }

// The engine analysis of one design run directly (machines/engine/cycle.h, as `engine_single_engine
// flywheel` runs it; the cycle the library's, machines/view_machines.h): the energy loop, the
// model's J_fly and the crank speed.
struct DirectEngine {
  mechgen::engine::EngineEnergy energy;
  double J_fly = 0;
  std::vector<mechgen::engine::CrankPoint<mechgen::ViewModel>> pts;  ///< the cycle's crank angles
  int R_O = -1;                                                        ///< the main bearing's reaction
};
DirectEngine RunEngineDirectly(double r, double l, double rpm, int samples, const mechgen::engine::PressureTable* table) {
  namespace eng = mechgen::engine;
  const mechgen::ViewModel model = EngineModel();
  mechgen::ViewParams p = ParamsOf(model, {{"r", r}, {"l", l}});
  DirectEngine out;
  eng::Engine e;
  std::string error;
  EXPECT_TRUE(eng::ReadEngine(model, &p, &e, &error)) << error;
  eng::PolytropicWiebeCycle wiebe;
  eng::PressureLaw law;
  EXPECT_TRUE(eng::InitPressureLaw(e, eng::PolytropicWiebeParams(), table, &wiebe, &law, &error)) << error;
  const eng::CycleGas gas = eng::MakeGas(model, &p, e, &law);
  std::vector<eng::CrankPoint<mechgen::ViewModel>> pts;
  EXPECT_TRUE(eng::RunCycle(model, p, e, gas, rpm * 2 * 3.14159265358979323846 / 60, samples, &pts, &error)) << error;
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
  using M = mech::engine_single::Model;  // (its parameters' defaults)
  study::Study<mechgen::ViewModel> s{EngineModel()};
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
  study::Study<mechgen::ViewModel> s{EngineModel()};
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
  study::Study<mechgen::ViewModel> b{EngineModel()};
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
  study::Study<mechgen::ViewModel> s{EngineModel()};
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
    study::Study<mechgen::ViewModel> s{EngineModel()};
    std::string error;
    EXPECT_FALSE(s.Prepare(spec, &error));
    EXPECT_NE(error.find("e6.yaml:4:14: error: gas: table: cannot read the pressure table"), std::string::npos)
        << error;
  }
  {
    const study::StudySpec spec = Read("e7.yaml",
                                       "method: grid\nanalysis: engine\nrpm: 3000\ngas: {cr: 0.5}\n"
                                       "parameters:\n  r: {values: [0.04]}\nmetrics: [{kind: mean_torque}]\n");
    study::Study<mechgen::ViewModel> s{EngineModel()};
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
    study::Study<mechgen::ViewModel> s{mechgen::ViewModel(mech::pendulum_spring::View())};
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
