/**
 * \file position/internal/assembly.h
 * Assembly from a poor guess: the Assembler, then Newton, then the checks.
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::position {

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::Assemble(const VecQ& q, const VecPhi& phi_guess, int required_branch,
                                   Summary* summary) {
  if constexpr (Features::kLoopFree) {
    (void)phi_guess;
    (void)required_branch;
    return PlaceLoopFree(q, summary);
  } else {
    if constexpr (Calls::kView) {
      if (Calls::LoopFree(model_)) return PlaceLoopFree(q, summary);
    }
    Summary s;
    s.used_assembler = true;
    auto finish = [&](Status status, const State<M>* at = nullptr) {
      return Finish(status, at, &s, summary);
    };
    if (!options_valid_ || !q.allFinite() || !phi_guess.allFinite()) {
      return finish(Status::kInvalidInput);
    }
    VecC Phi;
    Calls::Phi(model_, params_, q, phi_guess, &Phi, nullptr, nullptr);
    if (!Phi.allFinite()) return finish(Status::kInvalidInput);  // parameters not finite

    VecPhi phi = phi_guess;
    const AssemblyResult lm = Assembler::Minimize(model_, params_, q, &phi, options_.max_lm_iterations);
    s.iterations = lm.iterations;
    s.residual_norm = lm.residual_norm;
    MatCPhi Phi_phi;
    MatCQ Phi_q;
    // Newton to Options::tolerance, and one polishing step.
    const NewtonResult newton = FullNewton(q, &phi, &Phi_phi, NeedPhiQ() ? &Phi_q : nullptr);
    s.iterations += newton.iterations;
    if (newton.status != Status::kConverged) {
      return finish(lm.stationary ? Status::kNotAssemblable : Status::kDidNotConverge);
    }
    State<M> next(model_);
    next.q = q;
    next.phi = phi;
    next.residual_norm = newton.residual_norm;
    const Factorization f(Phi_phi);
    const bool regular = Classify(Phi_phi, f, nullptr, &next);
    s.substeps = 1;
    if (!regular) return finish(Status::kSingular, &next);
    if (required_branch != 0 && next.branch != Sign(required_branch)) {
      return finish(Status::kWrongBranch, &next);
    }
    if (!FillCoefficients(f, NeedPhiQ() ? &Phi_q : nullptr, &next)) {
      return finish(Status::kSingular, &next);
    }
    next.valid = true;
    state_ref() = next;
    FindModes(state_ref());
    return finish(Status::kConverged, &next);
  }
}

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::AssembleDefault(Summary* summary) {
  const VecQ q = Eigen::Map<const VecQ>(Calls::AssemblyQ(model_), nq());
  if constexpr (Features::kLoopFree) {
    return PlaceLoopFree(q, summary);
  } else {
    if constexpr (Calls::kView) {
      if (Calls::LoopFree(model_)) return PlaceLoopFree(q, summary);
    }
    const VecPhi phi = Eigen::Map<const VecPhi>(Calls::AssemblyPhi(model_), nphi());
    MatCPhi Phi_phi;
    Calls::Phi(model_, params_, q, phi, nullptr, &Phi_phi, nullptr);
    double cond = 0, det = 0;
    if constexpr (Calls::kView) {
      det = Factorization(Phi_phi).determinant();  // (its sign only: the branch of the guess)
    } else {
      ConditionAndDeterminant(Phi_phi, &cond, &det);
    }
    return Assemble(q, phi, Sign(det), summary);
  }
}

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::PlaceLoopFree(const VecQ& q, Summary* summary) {
  Summary s;
  State<M> next(model_);
  next.q = q;
  if (!options_valid_ || !q.allFinite()) {
    s.reason = !options_valid_ ? "invalid Options" : "input not finite";
    return Finish(Status::kInvalidInput, nullptr, &s, summary);
  }
  typename T::Coefficients c;
  if constexpr (kCallCoeffs) {
    if (CallCoeffs()) Calls::Coeffs(model_, params_, q, next.phi, &c);
  }
  (void)c;
  bool finite = true;
  // phi, K and L are empty (0 rows).
  if constexpr (Features::kHasPoints) {
    if (Calls::HasPoints(model_)) {
      next.r_P = c.r_P;
      finite = next.r_P.allFinite();
    }
  }
  if constexpr (Features::kHasPointVelocities) {
    if (Calls::HasPointVelocities(model_)) next.K_P = c.K_P;
  }
  if constexpr (Features::kHasPointAccelerations) {
    if (Calls::HasPointAccelerations(model_)) next.L_P = c.L_P;
  }
  next.residual_norm = 0;
  next.condition = 1;
  next.inverse_norm = 0;
  next.sigma_min = std::numeric_limits<double>::infinity();
  next.sigma_max = 0;
  next.sigma_exact = true;
  next.phi_error = next.K_error = next.L_error = 0;
  next.branch = 1;
  s.substeps = 1;
  if (!finite) {  // parameters not finite
    s.reason = "points not finite (parameters not finite?)";
    return Finish(Status::kInvalidInput, nullptr, &s, summary);
  }
  next.valid = true;
  state_ref() = next;
  return Finish(Status::kConverged, &next, &s, summary);
}

}  // namespace mechgen::position
