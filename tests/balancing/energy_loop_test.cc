// machines/flywheel/energy_loop.h: a textbook flywheel with published numbers, a closed-form excess
// torque with the convergence of the sampled integration, and Wittenbauer's tangents on
// synthetic data whose flywheel is known by construction.
#include "mechgen/machines/flywheel/energy_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

namespace fw = mechgen::flywheel;
constexpr double kPi = 3.14159265358979323846;

// Khurmi & Gupta, *Theory of Machines* (S. Chand), ch. 16 "Turning Moment Diagrams and
// Flywheel", the petrol-engine example: the turning-moment diagram is drawn to 1 mm = 5 N m
// vertically and 1 mm = 1° horizontally and repeats every half revolution; the areas above
// and below the mean torque line are, in order, +295, −685, +40, −340, +960, −270 mm²; the
// rotating parts are 36 kg at a radius of gyration of 150 mm, at 1800 rpm. Published: the
// maximum fluctuation of energy 985 mm² ≈ 86 N m, the coefficient of fluctuation of speed
// C_s ≈ 0.003. Exactly: ΔE = 985 · 5 · π/180 = 85.957 J, I = 36 · 0.15² = 0.81 kg m²,
// ω = 1800 · 2π/60 = 188.50 rad/s, C_s = 85.957/(0.81 · 188.50²) = 0.0029866.
constexpr double kAreas[6] = {295, -685, 40, -340, 960, -270};
constexpr double kTorqueScale = 5;         // N m per mm
constexpr double kAngleScale = kPi / 180;  // rad per mm

TEST(EnergyLoop, KhurmiGuptaPetrolEngineFromLoopAreas) {
  const fw::AreaLoop loop = fw::DeltaEFromAreas(kAreas, 6);
  ASSERT_EQ(loop.status, fw::LoopStatus::kOk);
  // Running sums 0, 295, −390, −350, −690, 270, 0: largest after area 1, smallest after 4.
  EXPECT_DOUBLE_EQ(loop.delta, 985.0);
  EXPECT_EQ(loop.after_max, 1);
  EXPECT_EQ(loop.after_min, 4);
  const double delta_E = loop.delta * kTorqueScale * kAngleScale;
  EXPECT_NEAR(delta_E, 86.0, 0.05);  // published "≈ 86 N m"
  const double omega = fw::RpmToRadPerSecond(1800);
  const double C_s = fw::SpeedFluctuation(delta_E, 36 * 0.15 * 0.15, omega);
  EXPECT_NEAR(C_s, 0.003, 0.00005);  // published "≈ 0.003" (3 significant digits)
  EXPECT_NEAR(C_s, 0.0029866, 5e-7);
  // And back: the inertia for that C_s is the given flywheel.
  EXPECT_NEAR(fw::RequiredInertia(delta_E, C_s, omega), 0.81, 1e-12);
  std::printf("Khurmi & Gupta: dE = %.0f mm^2 = %.4f J, C_s = %.7f\n", loop.delta, delta_E, C_s);
}

// A smooth turning-moment curve with those loop areas: six lobes of unequal widths over the
// half revolution, lobe i: ΔT = h_i sin²(π (θ − s_i)/w_i) with area h_i w_i/2 = A_i (sin²
// rather than sin lobes so that the curve is C¹ where the lobes meet, which is where E has its
// extremes; a kink there limits the integration to second order). The sampled curve's ΔE must
// reproduce 985 mm² (in J), converging as the samples grow.
double KhurmiCurve(double theta /* rad */) {
  const double widths[6] = {25, 45, 10, 30, 50, 20};  // mm = deg, sum 180
  double deg = std::fmod(theta / kAngleScale, 180.0);
  if (deg < 0) deg += 180;
  double start = 0;
  for (int i = 0; i < 6; ++i) {
    if (deg < start + widths[i] || i == 5) {
      const double h = 2 * kAreas[i] / widths[i];  // mm
      const double s = std::sin(kPi * (deg - start) / widths[i]);
      return kTorqueScale * h * s * s;
    }
    start += widths[i];
  }
  return 0;
}

TEST(EnergyLoop, SmoothCurveWithTheTextbookAreasReproducesDeltaE) {
  const double exact = 985 * kTorqueScale * kAngleScale;
  double previous = 1e300;
  for (int n : {90, 180, 360, 720, 1440}) {
    const double theta0 = 0.0123;
    std::vector<double> dT(n), E(n);
    for (int k = 0; k < n; ++k) dT[k] = KhurmiCurve(theta0 + kPi * k / n);
    // The kinks at the lobe ends leave the samples' mean slightly off zero (O(h²)); the
    // textbook measures the areas from the mean torque line, so the mean is removed.
    fw::EnergyLoopOptions o;
    o.remove_mean = true;
    const fw::EnergyLoop loop = fw::ExcessEnergy(dT.data(), n, kPi, theta0, o, E.data());
    ASSERT_EQ(loop.status, fw::LoopStatus::kOk);
    EXPECT_LT(std::abs(loop.mean_torque), 1.0 / n);
    const double error = std::abs(loop.delta_E - exact);
    std::printf("n = %5d  mean %.2e N m  dE = %.9f J  error %.3e  max at %.3f deg, min at %.3f deg\n", n,
                loop.mean_torque, loop.delta_E, error, loop.theta_max / kAngleScale, loop.theta_min / kAngleScale);
    EXPECT_LT(error, previous);
    previous = error;
    // The maximum is at the end of lobe 1 (25°), the minimum at the end of lobe 4 (110°).
    if (n >= 360) {
      EXPECT_NEAR(loop.theta_max / kAngleScale, 25.0, 180.0 / n);
      EXPECT_NEAR(loop.theta_min / kAngleScale, 110.0, 180.0 / n);
    }
  }
  EXPECT_LT(previous, 1e-6 * exact);
}

// ΔT = A sin(nθ) over a turn: E(θ) = A/n (cos nθ_0 − cos nθ), ΔE = 2A/n. The integration is
// fourth order: the error falls by about 16 per doubling of the samples.
TEST(EnergyLoop, ClosedFormSineConvergesAtFourthOrder) {
  const double A = 120, theta0 = 0.37;
  for (int order : {1, 3}) {
    double previous = 0;
    for (int n : {24, 48, 96, 192}) {
      std::vector<double> dT(n), E(n);
      for (int k = 0; k < n; ++k) dT[k] = A * std::sin(order * (theta0 + 2 * kPi * k / n));
      const fw::EnergyLoop loop = fw::ExcessEnergy(dT.data(), n, 2 * kPi, theta0, {}, E.data());
      ASSERT_EQ(loop.status, fw::LoopStatus::kOk);
      EXPECT_NEAR(loop.mean_torque, 0, 1e-12 * A);
      double e_error = 0;
      for (int k = 0; k < n; ++k) {
        const double t = theta0 + 2 * kPi * k / n;
        e_error = std::max(e_error, std::abs(E[k] - A / order * (std::cos(order * theta0) - std::cos(order * t))));
      }
      const double error = std::abs(loop.delta_E - 2 * A / order);
      std::printf("order %d n = %4d  dE error %.3e  E error %.3e\n", order, n, error, e_error);
      if (previous > 0) {
        EXPECT_GT(previous / error, 12.0) << n;
      }
      previous = error;
      // The extremes of E are at nθ = π (max) and nθ = 0 (min), modulo 2π/n.
      EXPECT_NEAR(std::cos(order * loop.theta_max), -1, 1e-6);
      EXPECT_NEAR(std::cos(order * loop.theta_min), 1, 1e-6);
    }
    EXPECT_LT(previous, 1e-5 * 2 * A / order);
  }
}

TEST(EnergyLoop, ReportsAnUnsteadyCycleAndBadInput) {
  const int n = 100;
  std::vector<double> dT(n);
  for (int k = 0; k < n; ++k) dT[k] = 50 * std::sin(2 * kPi * k / n) + 2.5;  // mean 2.5 N m
  fw::EnergyLoop loop = fw::ExcessEnergy(dT.data(), n, 2 * kPi, 0.0);
  EXPECT_EQ(loop.status, fw::LoopStatus::kNotSteady);
  EXPECT_NEAR(loop.mean_torque, 2.5, 1e-12);
  EXPECT_NEAR(loop.cycle_work, 2.5 * 2 * kPi, 1e-11);
  // With the mean removed it is the closed form 2A: ΔE = 100 J to the integration error.
  fw::EnergyLoopOptions o;
  o.remove_mean = true;
  loop = fw::ExcessEnergy(dT.data(), n, 2 * kPi, 0.0, o);
  EXPECT_EQ(loop.status, fw::LoopStatus::kOk);
  EXPECT_NEAR(loop.delta_E, 100, 1e-4);
  EXPECT_NEAR(loop.cycle_work, 0, 1e-11);
  // T_d and T_l given apart: the same as their difference.
  std::vector<double> T_d(n), T_l(n, 2.5), work(n);
  for (int k = 0; k < n; ++k) T_d[k] = dT[k];
  loop = fw::ExcessEnergy(T_d.data(), T_l.data(), n, 2 * kPi, 0.0, work.data());
  EXPECT_EQ(loop.status, fw::LoopStatus::kOk);
  EXPECT_NEAR(loop.delta_E, 100, 1e-4);

  EXPECT_EQ(fw::ExcessEnergy(dT.data(), 3, 2 * kPi, 0.0).status, fw::LoopStatus::kTooFewSamples);
  EXPECT_EQ(fw::ExcessEnergy(dT.data(), n, -1.0, 0.0).status, fw::LoopStatus::kBadCycle);
  dT[7] = std::nan("");
  EXPECT_EQ(fw::ExcessEnergy(dT.data(), n, 2 * kPi, 0.0).status, fw::LoopStatus::kNonFinite);
  const double open[3] = {10, -4, -5};
  EXPECT_EQ(fw::DeltaEFromAreas(open, 3).status, fw::LoopStatus::kNotSteady);
  EXPECT_DOUBLE_EQ(fw::DeltaEFromAreas(open, 3).closure, 1.0);
  EXPECT_TRUE(std::isnan(fw::RequiredInertia(10, 0, 100)));
  EXPECT_TRUE(std::isnan(fw::SpeedFluctuation(10, -1, 100)));
  // Finite samples whose sums overflow (issue 45): a status, never an infinite figure.
  const double huge_areas[4] = {1e308, 1e308, -1e308, -1e308};
  EXPECT_EQ(fw::DeltaEFromAreas(huge_areas, 4).status, fw::LoopStatus::kNonFinite);
  std::vector<double> huge(8, 1e308);
  EXPECT_EQ(fw::ExcessEnergy(huge.data(), 8, 2 * kPi, 0.0).status, fw::LoopStatus::kNonFinite);  // the mean's sum
  for (int k = 0; k < 8; ++k) huge[k] = k < 4 ? 1.5e308 : -1.5e308;  // mean 0, E = h * sum overflows
  o.remove_mean = true;
  EXPECT_EQ(fw::ExcessEnergy(huge.data(), 8, 2 * kPi, 0.0, o).status, fw::LoopStatus::kNonFinite);
  for (int k = 0; k < 8; ++k) huge[k] = k < 4 ? 1e300 : -1e300;  // large but within the numbers: computed
  const fw::EnergyLoop large = fw::ExcessEnergy(huge.data(), 8, 2 * kPi, 0.0, o);
  EXPECT_EQ(large.status, fw::LoopStatus::kOk);
  EXPECT_TRUE(std::isfinite(large.delta_E));
  // The flywheel formulas: NaN where the result overflows (C_s = 1e-300), the figure otherwise.
  EXPECT_TRUE(std::isnan(fw::RequiredInertia(1e300, 1e-300, 1)));
  EXPECT_TRUE(std::isnan(fw::SpeedFluctuation(1e300, 1e-300, 1)));
  EXPECT_DOUBLE_EQ(fw::RequiredInertia(1e300, 1e-6, 1e3), 1e300);
}

// Wittenbauer's diagram on synthetic data: a machine with I_m(θ) = 0.2 + 0.05 cos 2θ + 0.02 sin θ
// (kg m²) and the excess work E(θ) = 30 sin θ + 12 (sin(2θ + 0.5) − sin 0.5) (J), a flywheel
// I_f = 1.3 kg m² and T_0 = 900 J at θ = 0. The speed trace ω = √(2 (T_0 + E)/(I_f + I_m))
// gives ω_max and ω_min; the tangents of slopes ω²/2 must give back I_f and T_0, and the rays
// from the true origin must give back ω_max and ω_min.
TEST(Wittenbauer, TangentsRecoverTheFlywheelAndTheSpeeds) {
  const int n = 3600;
  const double I_f = 1.3, T0 = 900;
  std::vector<double> I_m(n), E(n), I(n), T(n), omega(n), dT(n), E_loop(n);
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n;
    I_m[k] = 0.2 + 0.05 * std::cos(2 * t) + 0.02 * std::sin(t);
    E[k] = 30 * std::sin(t) + 12 * (std::sin(2 * t + 0.5) - std::sin(0.5));
    dT[k] = 30 * std::cos(t) + 24 * std::cos(2 * t + 0.5);
    I[k] = I_f + I_m[k];
    T[k] = T0 + E[k];
    omega[k] = std::sqrt(2 * T[k] / I[k]);
  }
  const fw::SpeedTrace trace = fw::AnalyzeSpeedTrace(omega.data(), n, fw::TraceSampling::kAngle);
  ASSERT_EQ(trace.status, fw::TraceStatus::kOk);

  const fw::WittenbauerSpeeds speeds = fw::Wittenbauer(I.data(), T.data(), n);
  ASSERT_EQ(speeds.status, fw::WittenbauerStatus::kOk);
  EXPECT_NEAR(speeds.omega_max, trace.omega_max, 1e-12 * trace.omega_max);
  EXPECT_NEAR(speeds.omega_min, trace.omega_min, 1e-12 * trace.omega_min);
  EXPECT_EQ(speeds.k_max, trace.k_max);
  EXPECT_EQ(speeds.k_min, trace.k_min);

  const fw::WittenbauerDesign design =
      fw::DesignByWittenbauer(I_m.data(), E.data(), n, trace.omega_max, trace.omega_min);
  ASSERT_EQ(design.status, fw::WittenbauerStatus::kOk);
  EXPECT_NEAR(design.I_flywheel, I_f, 1e-10);
  EXPECT_NEAR(design.T0, T0, 1e-8);
  // Every point of the curve lies between the two tangent lines.
  for (int k = 0; k < n; ++k) {
    EXPECT_LE(E[k], design.slope_max * I_m[k] + design.c_max + 1e-9);
    EXPECT_GE(E[k], design.slope_min * I_m[k] + design.c_min - 1e-9);
  }

  // The energy loop from the torque (integrated, not the closed-form E) neglects the variation
  // of I: its flywheel differs from the true one; reported, and exact for a constant I_m below.
  const fw::EnergyLoop loop = fw::ExcessEnergy(dT.data(), n, 2 * kPi, 0.0, {}, E_loop.data());
  ASSERT_EQ(loop.status, fw::LoopStatus::kOk);
  double e_error = 0, mean_I_m = 0;
  for (int k = 0; k < n; ++k) {
    e_error = std::max(e_error, std::abs(E_loop[k] - E[k]));
    mean_I_m += I_m[k] / n;
  }
  EXPECT_LT(e_error, 1e-9);
  const double I_loop = fw::RequiredInertia(loop.delta_E, trace.C_s, trace.omega_mid) - mean_I_m;
  std::printf("Wittenbauer I_f = %.6f kg m^2, energy loop (I variation neglected) %.6f: %+.2f%%\n", design.I_flywheel,
              I_loop, 100 * (I_loop - I_f) / I_f);

  // Constant machine inertia: the energy loop is exact, ΔE = ½ I (ω_max² − ω_min²).
  for (int k = 0; k < n; ++k) omega[k] = std::sqrt(2 * T[k] / (I_f + 0.2));
  const fw::SpeedTrace constant = fw::AnalyzeSpeedTrace(omega.data(), n, fw::TraceSampling::kAngle);
  const double delta_E_samples = *std::max_element(E.begin(), E.end()) - *std::min_element(E.begin(), E.end());
  EXPECT_NEAR(fw::RequiredInertia(delta_E_samples, constant.C_s, constant.omega_mid), I_f + 0.2, 1e-12);
  // The time mean of an angle-sampled trace is the harmonic mean; close to the mid-range speed.
  EXPECT_LT(std::abs(constant.omega_mean - constant.omega_mid), constant.C_s * constant.omega_mid);
}

TEST(Wittenbauer, BadInput) {
  const double I_m[3] = {1, 1.1, 1.2}, E[3] = {0, 5, -3};
  EXPECT_EQ(fw::DesignByWittenbauer(I_m, E, 3, 10, 12).status, fw::WittenbauerStatus::kBadSpeeds);
  const double T[3] = {5, -1, 4};
  EXPECT_EQ(fw::Wittenbauer(I_m, T, 3).status, fw::WittenbauerStatus::kNonPositive);
  const double omega[3] = {3, 0, 2};
  EXPECT_EQ(fw::AnalyzeSpeedTrace(omega, 3, fw::TraceSampling::kTime).status, fw::TraceStatus::kNonPositiveSpeed);
}

}  // namespace
