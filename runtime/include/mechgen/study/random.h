/**
 * \file study/random.h
 * The random numbers of a design study (issue 29): counter-based, so that the value drawn for
 * sample i, dimension k depends on (seed, i, k) only, never on which thread drew it or in what
 * order: a study gives the same bytes for any number of threads (or ranks). No std::
 * distributions (their output differs between standard libraries): SplitMix64 (Steele, Lea and
 * Flood 2014) as a hash of the counter, 53-bit uniforms in (0, 1), and the normal by the
 * inverse CDF (Acklam's rational approximation, relative error 1.15e-9, then one Halley step
 * on erfc, to ~1e-15), which keeps a Latin hypercube's strata: u in stratum s maps to the
 * s-th equal-probability interval of the normal.
 */
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "mechgen/core/random.h"

namespace mechgen::study {

using mechgen::Mix64;  // core/random.h

/// 64 random bits for (seed, stream, index): a hash of the three (counter-based).
inline uint64_t Bits(uint64_t seed, uint64_t stream, uint64_t index) {
  return Mix64(Mix64(Mix64(seed) ^ stream) ^ index);
}

/// A uniform number in the open interval (0, 1) from 64 bits: (k + 0.5) / 2^53, k the top 53 bits.
inline double Uniform01(uint64_t bits) { return (static_cast<double>(bits >> 11) + 0.5) * (1.0 / 9007199254740992.0); }

/// The uniform of sample `index`, dimension `stream`.
inline double Uniform(uint64_t seed, uint64_t stream, uint64_t index) { return Uniform01(Bits(seed, stream, index)); }

/// The standard normal's quantile Phi^-1(u), u in (0, 1): Acklam's approximation refined by
/// one Halley step (|error| ~ 1e-15 relative). u <= 0 or >= 1 give -inf / +inf.
inline double NormalQuantile(double u) {
  if (!(u > 0)) return -INFINITY;
  if (!(u < 1)) return INFINITY;
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  constexpr double low = 0.02425;
  double x;
  if (u < low) {
    const double q = std::sqrt(-2 * std::log(u));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (u <= 1 - low) {
    const double q = u - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - u));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  // Halley: e = Phi(x) - u, Phi(x) = erfc(-x / sqrt 2) / 2.
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - u;
  const double w = e * 2.5066282746310002 * std::exp(x * x / 2);
  return x - w / (1 + x * w / 2);
}

/// A random permutation of 0..n-1 (Fisher-Yates driven by Bits(seed, stream, i)); the
/// strata order of one dimension of a Latin hypercube.
inline std::vector<uint64_t> Permutation(uint64_t n, uint64_t seed, uint64_t stream) {
  std::vector<uint64_t> p(n);
  for (uint64_t i = 0; i < n; ++i) p[i] = i;
  for (uint64_t i = n; i > 1; --i) {
    // j uniform in [0, i): the multiply-shift of 64 random bits (bias < i / 2^64).
    const unsigned __int128 wide = static_cast<unsigned __int128>(Bits(seed, stream, i)) * i;
    const uint64_t j = static_cast<uint64_t>(wide >> 64);
    std::swap(p[i - 1], p[j]);
  }
  return p;
}

}  // namespace mechgen::study
