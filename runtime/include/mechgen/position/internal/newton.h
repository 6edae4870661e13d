/**
 * \file position/internal/newton.h
 * Paul's Newton–Raphson (NEWTR) on the whole system at fixed q, with one polishing step.
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::position {

template <class M, class Assembler>
NewtonResult PositionSolver<M, Assembler>::FullNewton(const VecQ& q, VecPhi* phi, MatCPhi* Phi_phi,
                                           MatCQ* Phi_q) const {
  NewtonResult result;
  auto Phi = Sized<VecC>(nc());
  // A singular Phi_phi gives inf/NaN in the step, caught by the finiteness tests.
  // Up to 4 x 4, Eigen's fixed-size inverse (cofactors) is several times faster than
  // PartialPivLU (measured 20 ns vs 3 ns for 2 x 2, a sixth of a whole step), and with
  // cond(Phi_phi) bounded by Options::min_rcond it is as accurate here; larger systems
  // use the pivoted LU. Both are fixed-size: no allocation.
  auto step = [](const MatCPhi& A, const VecC& r) -> VecPhi {
    if constexpr (M::kNphi == Eigen::Dynamic) {
      return internal::SolveSmallInverse(A, r);  // the fixed-size code of A's size
    } else if constexpr (M::kNphi <= 4) {
      return A.inverse() * r;
    } else {
      return Eigen::PartialPivLU<MatCPhi>(A).solve(r);
    }
  };
  for (int iteration = 0;; ++iteration) {
    Calls::Phi(model_, params_, q, *phi, &Phi, Phi_phi, Phi_q);
    result.residual_norm = Phi.template lpNorm<Eigen::Infinity>();
    result.iterations = iteration;
    if (!std::isfinite(result.residual_norm) || !phi->allFinite()) {
      result.status = Status::kDidNotConverge;
      return result;
    }
    if (result.residual_norm <= options_.tolerance) {
      // Polish: one more step after the residual test passed. Newton converges
      // quadratically here, so phi goes from ~ cond * tolerance / length (1e-10) to the
      // rounding level (~1e-15) for the price of one solve and one evaluation. Kept only
      // when it does not make the residual worse (at the rounding floor it may not help).
      const VecPhi polished = *phi - step(*Phi_phi, Phi);
      VecC Phi2;
      MatCPhi A2;
      MatCQ B2;
      Calls::Phi(model_, params_, q, polished, &Phi2, &A2, Phi_q != nullptr ? &B2 : nullptr);
      const double r2 = Phi2.template lpNorm<Eigen::Infinity>();
      ++result.iterations;
      if (polished.allFinite() && A2.allFinite() && r2 <= result.residual_norm) {
        *phi = polished;
        *Phi_phi = A2;
        if (Phi_q != nullptr) *Phi_q = B2;
        result.residual_norm = r2;
      }
      result.status = Status::kConverged;
      return result;
    }
    if (iteration == options_.max_newton_iterations) {
      result.status = Status::kDidNotConverge;
      return result;
    }
    *phi -= step(*Phi_phi, Phi);
  }
}

}  // namespace mechgen::position
