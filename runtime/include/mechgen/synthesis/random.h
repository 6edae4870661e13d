/**
 * \file synthesis/random.h
 * The synthesis' random numbers: splitmix64 (Steele, Lea, Flood 2014; its mix in core/random.h), so that a
 * seed gives the same numbers with every standard library (no std:: distributions). One
 * stream per restart, seeded from (seed, restart): the restarts' results do not depend on
 * which thread ran them.
 */
#pragma once

#include <cstdint>

#include "mechgen/core/random.h"

namespace mechgen::synthesis {

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  /// The stream of restart `stream` of a run seeded `seed`.
  SplitMix64(uint64_t seed, uint64_t stream) : state_(seed) {
    state_ = Next() ^ (stream * 0xD1B54A32D192ED03ULL);
    Next();
  }
  uint64_t Next() {
    const uint64_t z = state_;
    state_ += 0x9E3779B97F4A7C15ULL;
    return Mix64(z);  // core/random.h: the same increment, then the finaliser
  }
  /// Uniform in [0, 1): the top 53 bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  /// Uniform integer in [0, n), n > 0 (the multiply-shift map; bias < n / 2^64).
  int Below(int n) {
    return static_cast<int>((static_cast<unsigned __int128>(Next()) * static_cast<uint64_t>(n)) >> 64);
  }

 private:
  uint64_t state_;
};

}  // namespace mechgen::synthesis
