/**
 * \file core/random.h
 * The one random-bit mix of the runtime: SplitMix64's step (Steele, Lea and Flood 2014),
 * written out so that a seed gives the same numbers with every standard library (no std::
 * distributions, whose output differs between libraries). The studies hash their counters with
 * it (study/random.h); the synthesis' restarts draw streams of it (synthesis/random.h).
 */
#pragma once

#include <cstdint>

namespace mechgen {

/// SplitMix64: the golden-ratio increment, then the bijective finaliser of 64 bits.
inline uint64_t Mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace mechgen
