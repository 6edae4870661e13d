/**
 * \file study/samples.h
 * The parameter values of the samples of a study (study/spec.h), drawn on demand (a
 * SampleSource: a chunk's samples as the chunk is run) or all at once in sample order
 * (DrawSamples): a grid (the Cartesian product of the values, the first
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
 * \brief Any sample's parameter values on demand, without storing them (a study of 10^8
 *        samples is run in chunks end to end): sample i's values depend on the spec, the
 *        nominals and i only. A Latin hypercube keeps its strata permutations (8 bytes per
 *        sample and parameter); the other methods keep nothing per sample.
 */
class SampleSource {
 public:
  /// `nominal[k]`: parameter k's nominal (the spec's, or the model's value when it gives none).
  SampleSource(const StudySpec& spec, const std::vector<double>& nominal)
      : spec_(&spec), nominal_(nominal), count_(SampleCount(spec)) {
    if (spec.method == Method::kLatinHypercube)
      for (uint64_t k = 0; k < spec.parameters.size(); ++k)
        strata_.push_back(Permutation(count_, spec.seed, kPermutationStream + k));
  }
  uint64_t count() const { return count_; }
  size_t parameters() const { return spec_->parameters.size(); }
  const std::vector<double>& nominal() const { return nominal_; }
  /// Sample i's values into out[0 .. parameters()).
  void Draw(uint64_t i, double* out) const {
    const StudySpec& spec = *spec_;
    const uint64_t n = spec.parameters.size();
    if (spec.method == Method::kList) {
      for (uint64_t k = 0; k < n; ++k) out[k] = spec.parameters[k].values[i];
    } else if (spec.method == Method::kGrid) {
      uint64_t rest = i;
      for (uint64_t k = n; k-- > 0;) {
        const uint64_t m = spec.parameters[k].values.size();
        out[k] = spec.parameters[k].values[rest % m];
        rest /= m;
      }
    } else if (spec.method == Method::kMonteCarlo) {
      for (uint64_t k = 0; k < n; ++k) out[k] = Quantile(spec.parameters[k], nominal_[k], Uniform(spec.seed, k, i));
    } else {
      for (uint64_t k = 0; k < n; ++k) {
        const double u = (static_cast<double>(strata_[k][i]) + Uniform(spec.seed, k, i)) / static_cast<double>(count_);
        out[k] = Quantile(spec.parameters[k], nominal_[k], u);
      }
    }
  }

 private:
  const StudySpec* spec_;  // the caller's, alive while the source is used
  std::vector<double> nominal_;
  uint64_t count_;
  std::vector<std::vector<uint64_t>> strata_;  // lhs: per parameter, the stratum of each sample
};

/**
 * \brief The samples' values: (*values)[i * n + k] is parameter k's value in sample i
 *        (n = spec.parameters.size()): every sample of a SampleSource, in order.
 */
inline std::vector<double> DrawSamples(const StudySpec& spec, const std::vector<double>& nominal) {
  const SampleSource source(spec, nominal);
  const uint64_t n = spec.parameters.size(), count = source.count();
  std::vector<double> values(count * n);
  for (uint64_t i = 0; i < count; ++i) source.Draw(i, &values[i * n]);
  return values;
}

}  // namespace mechgen::study
