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
  has_modes_ = false;
  if constexpr (Features::kHasSolve) {
    constexpr int nb = M::kNumBlocks;
    auto solve = [&](const Modes& m, VecPhi* x) {
      *x = s.phi;  // the reference of the closed forms' angles
      const auto r = M::template Solve<double>(params_, s.q, x, m, options_.max_newton_iterations,
                                               options_.tolerance);
      using SolveStatus = decltype(r.status);
      return r.status == SolveStatus::kConverged && x->allFinite();
    };
    auto differs = [](double a, double b) { return std::abs(a - b) > 1e-9 * (1 + std::abs(b)); };
    // Which coordinates each closed-form block owns: flipping block b's mode moves its own
    // coordinates and those of later blocks that depend on it, never earlier ones; so
    // own(b) = moved(b) minus moved(b') for every later b'.
    Modes base = M::kDefaultModes;
    VecPhi x0;
    if (!solve(base, &x0)) return;
    std::array<std::array<bool, M::kNphi>, nb> moved{};
    for (int b = 0; b < nb; ++b) {
      if (!M::kBlockClosedForm[b]) continue;
      Modes m = base;
      m[b] = -m[b];
      VecPhi x;
      if (!solve(m, &x)) return;
      for (int i = 0; i < M::kNphi; ++i) moved[b][i] = differs(x(i), x0(i));
    }
    std::array<int, M::kNphi> owner;
    owner.fill(-1);
    for (int b = nb - 1; b >= 0; --b) {
      for (int i = 0; i < M::kNphi; ++i) {
        if (moved[b][i] && owner[i] == -1) owner[i] = b;
      }
    }
    // In solve order, the mode of each block that is closer to s.phi on its coordinates
    // (earlier blocks are settled, so its inputs are right).
    Modes m = base;
    for (int b = 0; b < nb; ++b) {
      if (!M::kBlockClosedForm[b]) continue;
      VecPhi xa, xb;
      Modes flipped = m;
      flipped[b] = -flipped[b];
      const bool oka = solve(m, &xa), okb = solve(flipped, &xb);
      double ea = 0, eb = 0;
      for (int i = 0; i < M::kNphi; ++i) {
        if (owner[i] != b) continue;
        ea = std::max(ea, std::abs(xa(i) - s.phi(i)));
        eb = std::max(eb, std::abs(xb(i) - s.phi(i)));
      }
      if ((okb && !oka) || (oka && okb && eb < ea)) m = flipped;
    }
    VecPhi x;
    if (!solve(m, &x)) return;
    // Reproduced to the accuracy of s.phi (||Phi|| <= tolerance, 1/cond >= min_rcond).
    const double error = (x - s.phi).template lpNorm<Eigen::Infinity>();
    if (!(error <= 1e-6 * (1 + s.phi.template lpNorm<Eigen::Infinity>()))) return;
    modes_ = m;
    has_modes_ = true;
  }
}

}  // namespace mechgen::position
