/**
 * \file machines/engine/harmonics.h
 * The harmonic content of a periodic signal sampled over one cycle of a crank: crank torque,
 * a bearing load component, a shaking force component (Paul §6.8.5 on power smoothing and
 * ch. 7 on the primary and secondary shaking forces are statements about these orders).
 *
 * The cycle is Θ (rad of crank angle): 2π for a signal that repeats every revolution
 * (shaking forces, two-stroke torque), 4π for a four-stroke engine's torque. The N samples
 * f_k = f(θ_k) are at θ_k = θ_0 + k Θ/N, k = 0..N-1 (equally spaced, the end of the cycle
 * not repeated; θ_0 any offset). With ν_m = 2π m/Θ (so the order, in cycles per crank
 * revolution, is ν_m: m for Θ = 2π, m/2 for Θ = 4π) the discrete Fourier series is
 *     f(θ) = mean + Σ_{m>=1} (a_m cos ν_m θ + b_m sin ν_m θ)
 *          = mean + Σ_{m>=1} A_m cos(ν_m θ - φ_m),   A_m = √(a_m² + b_m²), φ_m = atan2(b_m, a_m),
 *     a_m = (2/N) Σ_k f_k cos ν_m θ_k,   b_m = (2/N) Σ_k f_k sin ν_m θ_k,   mean = (1/N) Σ_k f_k.
 * Phases are referred to the absolute crank angle θ = 0, not to the first sample, so the
 * same signal sampled from a different θ_0 gives the same a_m, b_m. They are exact for a
 * signal with no order at or above N/2 cycles per cycle (m < N/2; the Nyquist limit, which
 * Analyze() enforces: count - 1 < N/2); higher orders alias onto lower ones.
 * Parseval: (1/N) Σ f_k² = mean² + ½ Σ_{m=1}^{M} A_m² when M = (N-1)/2 (N odd) includes
 * every order the samples can hold.
 *
 * Units: those of the signal (the amplitudes), rad for θ and φ. Allocation-free (the caller
 * owns the arrays); nothing throws: a status names what was wrong.
 */
#pragma once

#include <cmath>

namespace mechgen::engine {

/// One order of a periodic signal (m = 0: the mean, a = mean, b = 0, amplitude = |mean|).
struct Harmonic {
  int m = 0;             ///< index of the order: ν = 2π m / Θ
  double order = 0;      ///< ν_m, cycles per crank revolution (m/2 for a 4π cycle)
  double a = 0;          ///< cosine coefficient a_m
  double b = 0;          ///< sine coefficient b_m
  double amplitude = 0;  ///< A_m = √(a_m² + b_m²)
  double phase = 0;      ///< φ_m = atan2(b_m, a_m) (rad): the term is A_m cos(ν_m θ - φ_m)
};

enum class HarmonicsStatus {
  kOk = 0,
  kTooFewSamples,  ///< N < 1, count < 1, or count - 1 >= N/2 (an order at or above Nyquist)
  kBadCycle,       ///< Θ not finite or <= 0
  kNonFinite,      ///< a sample or θ_0 is NaN or infinite
};

inline const char* ToString(HarmonicsStatus s) {
  switch (s) {
    case HarmonicsStatus::kOk:
      return "ok";
    case HarmonicsStatus::kTooFewSamples:
      return "too few samples for the orders asked (need count - 1 < N/2)";
    case HarmonicsStatus::kBadCycle:
      return "the cycle must be a finite positive angle";
    case HarmonicsStatus::kNonFinite:
      return "a sample or the start angle is not finite";
  }
  return "unknown";
}

/**
 * \brief The mean and the orders m = 1..count-1 of the samples f[0..n-1] over one cycle.
 * \param[in]  f       the samples f(θ_0 + k cycle/n), k = 0..n-1 (n values)
 * \param[in]  n       number of samples N
 * \param[in]  cycle   Θ (rad): 2π or 4π
 * \param[in]  theta0  θ_0, the crank angle of f[0] (rad)
 * \param[in]  count   harmonics to fill: out[0] the mean, out[m] order m (count - 1 < N/2)
 * \param[out] out     count Harmonic values
 */
inline HarmonicsStatus Analyze(const double* f, int n, double cycle, double theta0, int count, Harmonic* out) {
  if (n < 1 || count < 1 || 2 * (count - 1) >= n) return HarmonicsStatus::kTooFewSamples;
  if (!(std::isfinite(cycle) && cycle > 0)) return HarmonicsStatus::kBadCycle;
  if (!std::isfinite(theta0)) return HarmonicsStatus::kNonFinite;
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(f[k])) return HarmonicsStatus::kNonFinite;
  constexpr double kTwoPi = 6.28318530717958647692;
  for (int m = 0; m < count; ++m) {
    const double nu = kTwoPi * m / cycle;
    double sc = 0, ss = 0;
    for (int k = 0; k < n; ++k) {
      // ν θ_k reduced exactly in the sample index (k m mod n) to keep large k m accurate.
      const long long km = (static_cast<long long>(k) * m) % n;
      const double angle = nu * theta0 + kTwoPi * static_cast<double>(km) / n;
      sc += f[k] * std::cos(angle);
      ss += f[k] * std::sin(angle);
    }
    Harmonic& H = out[m];
    H.m = m;
    H.order = nu;
    if (m == 0) {
      H.a = sc / n;
      H.b = 0;
    } else {
      H.a = 2 * sc / n;
      H.b = 2 * ss / n;
    }
    H.amplitude = std::hypot(H.a, H.b);
    H.phase = m == 0 ? 0.0 : std::atan2(H.b, H.a);
  }
  return HarmonicsStatus::kOk;
}

/// f(θ) rebuilt from harmonics h[0..count-1] (h[0] the mean) of a cycle Θ.
inline double Reconstruct(const Harmonic* h, int count, double cycle, double theta) {
  constexpr double kTwoPi = 6.28318530717958647692;
  double f = count > 0 ? h[0].a : 0.0;
  for (int m = 1; m < count; ++m) {
    const double nu = kTwoPi * h[m].m / cycle;
    f += h[m].a * std::cos(nu * theta) + h[m].b * std::sin(nu * theta);
  }
  return f;
}

/// The mean square of the samples, (1/N) Σ f_k² (the left side of Parseval's identity).
inline double MeanSquare(const double* f, int n) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += f[k] * f[k];
  return n > 0 ? s / n : 0.0;
}

}  // namespace mechgen::engine
