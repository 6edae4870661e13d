// machines/engine/harmonics.h against synthetic signals whose harmonics are known by construction, at
// several sampling offsets, and against Parseval's identity.
#include "mechgen/machines/engine/harmonics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using mechgen::engine::Analyze;
using mechgen::engine::Harmonic;
using mechgen::engine::HarmonicsStatus;
using mechgen::engine::MeanSquare;
using mechgen::engine::Reconstruct;
constexpr double kPi = 3.14159265358979323846;

// f(θ) = 3 + 2 cos(θ − 0.4) + 0.5 cos(2θ + 1.1) + 0.25 sin(4θ) over one revolution, sampled
// from several offsets θ_0: the coefficients are those of the construction, referred to θ = 0.
TEST(Harmonics, RecoversKnownOrdersAtAnySamplingOffset) {
  const int n = 37;
  for (double theta0 : {0.0, 0.3, -2.0, 17.5}) {
    std::vector<double> f(n);
    for (int k = 0; k < n; ++k) {
      const double t = theta0 + 2 * kPi * k / n;
      f[k] = 3 + 2 * std::cos(t - 0.4) + 0.5 * std::cos(2 * t + 1.1) + 0.25 * std::sin(4 * t);
    }
    Harmonic h[6];
    ASSERT_EQ(Analyze(f.data(), n, 2 * kPi, theta0, 6, h), HarmonicsStatus::kOk);
    EXPECT_NEAR(h[0].a, 3, 1e-13);
    EXPECT_NEAR(h[1].amplitude, 2, 1e-13);
    EXPECT_NEAR(h[1].phase, 0.4, 1e-13);
    EXPECT_NEAR(h[2].amplitude, 0.5, 1e-13);
    EXPECT_NEAR(h[2].phase, -1.1, 1e-13);
    EXPECT_NEAR(h[3].amplitude, 0, 1e-13);
    EXPECT_NEAR(h[4].a, 0, 1e-13);
    EXPECT_NEAR(h[4].b, 0.25, 1e-13);
    EXPECT_NEAR(h[5].amplitude, 0, 1e-13);
    EXPECT_DOUBLE_EQ(h[2].order, 2.0);
    // The reconstruction is the signal between the samples too.
    for (double t : {0.1, 1.0, 4.4})
      EXPECT_NEAR(Reconstruct(h, 6, 2 * kPi, t),
                  3 + 2 * std::cos(t - 0.4) + 0.5 * std::cos(2 * t + 1.1) + 0.25 * std::sin(4 * t), 1e-12);
  }
}

// A four-stroke signal over 4π: half orders. f = 1.5 cos(θ/2) + 0.7 sin(3θ/2 − 0.2) + cos(2θ):
// m = 1 is order 0.5, m = 3 order 1.5, m = 4 order 2.
TEST(Harmonics, FourStrokeCycleHasHalfOrders) {
  const int n = 64;
  const double theta0 = 0.77;
  std::vector<double> f(n);
  for (int k = 0; k < n; ++k) {
    const double t = theta0 + 4 * kPi * k / n;
    f[k] = 1.5 * std::cos(0.5 * t) + 0.7 * std::sin(1.5 * t - 0.2) + std::cos(2 * t);
  }
  Harmonic h[8];
  ASSERT_EQ(Analyze(f.data(), n, 4 * kPi, theta0, 8, h), HarmonicsStatus::kOk);
  EXPECT_DOUBLE_EQ(h[1].order, 0.5);
  EXPECT_DOUBLE_EQ(h[3].order, 1.5);
  EXPECT_NEAR(h[1].amplitude, 1.5, 1e-13);
  EXPECT_NEAR(h[1].phase, 0, 1e-13);
  // sin(x − 0.2) = cos(x − 0.2 − π/2).
  EXPECT_NEAR(h[3].amplitude, 0.7, 1e-13);
  EXPECT_NEAR(h[3].phase, 0.2 + kPi / 2, 1e-13);
  EXPECT_NEAR(h[4].amplitude, 1.0, 1e-13);
  EXPECT_NEAR(h[2].amplitude, 0, 1e-13);
  EXPECT_NEAR(h[0].a, 0, 1e-13);
}

// Parseval on random samples (odd N, every order the samples can hold): mean square =
// mean² + ½ Σ A_m², an identity of the DFT independent of the signal.
TEST(Harmonics, ParsevalOnRandomSamples) {
  std::mt19937 gen(42);
  std::uniform_real_distribution<double> u(-3, 5);
  for (int n : {5, 33, 101}) {
    std::vector<double> f(n);
    for (double& x : f) x = u(gen);
    const int count = (n - 1) / 2 + 1;
    std::vector<Harmonic> h(count);
    ASSERT_EQ(Analyze(f.data(), n, 2 * kPi, 0.9, count, h.data()), HarmonicsStatus::kOk);
    double energy = h[0].a * h[0].a;
    for (int m = 1; m < count; ++m) energy += 0.5 * h[m].amplitude * h[m].amplitude;
    EXPECT_NEAR(energy, MeanSquare(f.data(), n), 1e-12 * MeanSquare(f.data(), n)) << n;
    // ... and the harmonics interpolate the samples.
    for (int k = 0; k < n; ++k) EXPECT_NEAR(Reconstruct(h.data(), count, 2 * kPi, 0.9 + 2 * kPi * k / n), f[k], 1e-11);
  }
}

TEST(Harmonics, RefusesOrdersAboveNyquistAndBadInput) {
  double f[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  Harmonic h[6];
  EXPECT_EQ(Analyze(f, 8, 2 * kPi, 0, 5, h), HarmonicsStatus::kTooFewSamples);  // m = 4 = N/2
  EXPECT_EQ(Analyze(f, 8, 2 * kPi, 0, 4, h), HarmonicsStatus::kOk);
  EXPECT_EQ(Analyze(f, 8, 0.0, 0, 4, h), HarmonicsStatus::kBadCycle);
  f[3] = std::nan("");
  EXPECT_EQ(Analyze(f, 8, 2 * kPi, 0, 4, h), HarmonicsStatus::kNonFinite);
}

}  // namespace
