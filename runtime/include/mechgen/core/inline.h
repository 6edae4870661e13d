/**
 * \file core/inline.h
 * Where a function's code goes, for the hot paths (the continuation step): the one place these
 * compiler hints are spelled. GCC and Clang; elsewhere plain `inline` and nothing.
 *  - MECHGEN_ALWAYS_INLINE: inline a small function the compiler would otherwise call (its
 *    heuristics give up inside the continuation step's larger functions). Measured with
 *    callgrind on the four-bar's continuation step (bench/fourbar_bench.cc,
 *    MechgenContinuation): each such call saved its arguments, the caller's live registers and
 *    a frame (position/solver.h).
 *  - MECHGEN_NOINLINE, MECHGEN_COLD_PATH: keep a rare branch out of the hot function that calls
 *    it (its frame and register saves); the second also lays it out apart as unlikely.
 */
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define MECHGEN_ALWAYS_INLINE inline __attribute__((always_inline))
#define MECHGEN_NOINLINE __attribute__((noinline))
#define MECHGEN_COLD_PATH __attribute__((noinline, cold))
#else
#define MECHGEN_ALWAYS_INLINE inline
#define MECHGEN_NOINLINE
#define MECHGEN_COLD_PATH
#endif
