/**
 * \file study/samples.h
 * The parameter values of every sample of a study (study/spec.h), drawn once, in sample
 * order, before any analysis: a grid (the Cartesian product of the values, the first
 * parameter varying slowest), a list (the i-th value of each), Monte-Carlo (each parameter
 * independently from its distribution) or a Latin hypercube (each parameter's range cut into
 * `count` strata of equal probability, each stratum used by exactly one sample, the strata
 * paired at random). Random numbers are study/random.h's: counter-based on (seed, parameter,
 * sample), so the values do not depend on threads or ranks.
 */
#pragma once

#include <cstdint>
#include <vector>

#include "mechgen/study/random.h"
#include "mechgen/study/spec.h"

namespace mechgen::study {

/// The value of a parameter of distribution `p` (its nominal resolved to `nominal`) at the
/// probability u in (0, 1).
inline double Quantile(const ParameterSpec& p, double nominal, double u) {
  if (p.distribution == Distribution::kUniform) return nominal + p.tolerance * (2 * u - 1);
  return nominal + p.sigma() * NormalQuantile(u);
}

// Streams of the random numbers: one per parameter for the values, one more per parameter
// for a Latin hypercube's permutation.
constexpr uint64_t kPermutationStream = 1ULL << 32;

/**
 * \brief The samples' values: (*values)[i * n + k] is parameter k's value in sample i
 *        (n = spec.parameters.size()). `nominal[k]`: parameter k's nominal (the spec's, or the
 *        model's default when the spec gives none).
 */
inline std::vector<double> DrawSamples(const StudySpec& spec, const std::vector<double>& nominal) {
  const uint64_t n = spec.parameters.size(), count = SampleCount(spec);
  std::vector<double> values(count * n);
  if (spec.method == Method::kList) {
    for (uint64_t i = 0; i < count; ++i)
      for (uint64_t k = 0; k < n; ++k) values[i * n + k] = spec.parameters[k].values[i];
  } else if (spec.method == Method::kGrid) {
    for (uint64_t i = 0; i < count; ++i) {
      uint64_t rest = i;
      for (uint64_t k = n; k-- > 0;) {
        const uint64_t m = spec.parameters[k].values.size();
        values[i * n + k] = spec.parameters[k].values[rest % m];
        rest /= m;
      }
    }
  } else if (spec.method == Method::kMonteCarlo) {
    for (uint64_t i = 0; i < count; ++i)
      for (uint64_t k = 0; k < n; ++k)
        values[i * n + k] = Quantile(spec.parameters[k], nominal[k], Uniform(spec.seed, k, i));
  } else {
    for (uint64_t k = 0; k < n; ++k) {
      const std::vector<uint64_t> strata = Permutation(count, spec.seed, kPermutationStream + k);
      for (uint64_t i = 0; i < count; ++i) {
        const double u = (static_cast<double>(strata[i]) + Uniform(spec.seed, k, i)) / static_cast<double>(count);
        values[i * n + k] = Quantile(spec.parameters[k], nominal[k], u);
      }
    }
  }
  return values;
}

}  // namespace mechgen::study
