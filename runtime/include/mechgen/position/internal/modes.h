/**
 * \file position/internal/modes.h
 * The assembly modes of the closed-form blocks of M::Solve on the current branch.
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::position {

template <class M, class Assembler>
void PositionSolver<M, Assembler>::FindModes(const State<M>& s) {
  const bool had_modes = has_modes_;
  has_modes_ = false;
  if constexpr (Features::kHasSolve) {
    if (!Calls::HasSolve(model_)) return;  // (constant but for the view)
    // Block by block on the solved configuration s, in solve order: a mode vector is right
    // when M::Solve on it reproduces s.phi. A block's closed form depends only on earlier
    // blocks' coordinates, and at s every block closes when the blocks before it are on
    // s's modes; so when Solve fails in block f, some block before f has the wrong mode
    // (that branch of the search is dropped), and when it converges elsewhere than s, a
    // later block's mode is tried. Depth-first from the previous modes (or the model's
    // defaults): one Solve when they still hold (the common case after a Newton step),
    // a few where flipping a block makes a later one unassemblable (which the former
    // search, flipping one block at a time from the defaults, took as "no modes").
    const int nb = Calls::NumBlocks(model_);
    std::array<int, internal::BlockCount<M>::value> closed{};  // the closed-form blocks, in solve order
    int nc = 0;
    for (int b = 0; b < nb; ++b)
      if (Calls::BlockClosedForm(model_, b)) closed[static_cast<size_t>(nc++)] = b;
    const double accuracy = 1e-6 * (1 + s.phi.template lpNorm<Eigen::Infinity>());
    Modes m = had_modes ? modes_ : Calls::DefaultModes(model_);
    int budget = 4096;  // Solve calls; 2^12 covers every mode vector of 12 closed-form blocks
    // -1: Solve(m) reproduces s.phi; nb: converged elsewhere; else the block that failed.
    auto attempt = [&]() {
      --budget;
      VecPhi x = s.phi;  // the reference of the closed forms' angles
      const auto r = Calls::Solve(model_, params_, s.q, &x, m, options_.max_newton_iterations,
                                  options_.tolerance);
      using SolveStatus = decltype(r.status);
      if (r.status != SolveStatus::kConverged) return r.block >= 0 ? r.block : 0;
      if (!x.allFinite()) return 0;
      return (x - s.phi).template lpNorm<Eigen::Infinity>() <= accuracy ? -1 : nb;
    };
    // Blocks closed[0..k) are settled; tries both modes of closed[k] (the current first).
    auto search = [&](auto& self, int k) -> bool {
      if (k >= nc) return false;
      const int b = closed[static_cast<size_t>(k)];
      for (int flip = 0; flip < 2 && budget > 0; ++flip) {
        if (flip) m[static_cast<size_t>(b)] = -m[static_cast<size_t>(b)];
        const int result = attempt();
        if (result == -1) return true;
        // Failed in block b or before it: b's mode (the earlier ones are settled) is wrong.
        if (result > b && self(self, k + 1)) return true;
      }
      m[static_cast<size_t>(b)] = -m[static_cast<size_t>(b)];  // restore
      return false;
    };
    bool found = false;
    if (nc == 0) {
      found = attempt() == -1;  // Newton blocks only: Solve must still reproduce s
    } else {
      found = search(search, 0);
    }
    if (!found) return;
    modes_ = m;
    has_modes_ = true;
  }
}

}  // namespace mechgen::position
