/**
 * \file position/internal/continuation.h
 * The continuation step, one path: MoveTo() runs Step() once straight to the target (the
 * common case: predictor, M::Solve on the branch's modes, the checks) and only when that
 * fails Subdivide() (halves, then the Assembler in Fallback()). Step() itself falls back
 * from M::Solve to Newton on the whole system (NewtonCorrector()) in a branch, not a copy.
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::internal {
/// The second-order predictor of a model with one input (a crank, a slide), dispatched at run
/// time for the view (PositionSolver::Predict()): its products and sums entry by entry, in
/// their order ((phi0 + K dq) + 1/2 (L dq^2), Times' sums of one term), without Eigen's
/// dynamic-size loops around each of them: the same values. *last_term: MaxAbsDiff of the
/// second-order term (NaN when any entry is).
template <class VecPhi, class State, class VecQ>
VecPhi PredictOneInput(const State& from, const VecQ& q, int n, double* last_term) {
  const double dq = q(0) - from.q(0);
  const double dq_dq = dq * dq;
  VecPhi predicted(n);
  double largest = 0;
  bool nan = false;
  for (int i = 0; i < n; ++i) {
    const double second = 0.5 * (from.L(i, 0) * dq_dq);
    predicted(i) = from.phi(i) + from.K(i, 0) * dq + second;
    const double d = std::abs(second);
    largest = largest > d ? largest : d;
    nan = nan | (d != d);
  }
  *last_term = nan ? std::numeric_limits<double>::quiet_NaN() : largest;
  return predicted;
}
/// max |q_target - q|: for the view by MaxAbsDiff(), the same maximum for the finite inputs it
/// is taken of, without Eigen's dynamic-size reduction.
template <bool kView, class VecQ>
MECHGEN_ALWAYS_INLINE double InputStep(const VecQ& q_target, const VecQ& q) {
  if constexpr (kView) {
    return MaxAbsDiff(q_target, &q);
  } else {
    return (q_target - q).cwiseAbs().maxCoeff();
  }
}
}  // namespace mechgen::internal

namespace mechgen::position {

template <class M, class Assembler>
typename PositionSolver<M, Assembler>::VecPhi PositionSolver<M, Assembler>::Predict(const State<M>& from,
                                                              const VecQ& q,
                                                              double* last_term) const {
  if constexpr (Calls::kView) {
    if (nq() == 1 && options_.second_order_predictor)
      return internal::PredictOneInput<VecPhi>(from, q, nphi(), last_term);  // (a prvalue: no copy)
  }
  const VecQ dq = q - from.q;
  // (The view: the coefficient-based product that the fixed sizes get, not Eigen's general
  // matrix-vector kernel, which costs more than the product at these sizes.)
  const VecPhi first = Times(from.K, dq);
  if (!options_.second_order_predictor) {
    *last_term = internal::MaxAbsDiff(first);
    return from.phi + first;
  }
  auto dq_dq = Sized<typename T::VecQQ>(nq() * nq());  // (dq (x) dq)(j + kNq k) = dq_j dq_k
  for (int k = 0; k < nq(); ++k) dq_dq.segment(nq() * k, nq()) = dq * dq(k);
  VecPhi second;
  if constexpr (Calls::kView) {
    second = 0.5 * Times(from.L, dq_dq);
  } else {
    second = 0.5 * from.L * dq_dq;
  }
  *last_term = internal::MaxAbsDiff(second);
  return from.phi + first + second;
}

template <class M, class Assembler>
bool PositionSolver<M, Assembler>::Accept(const State<M>& from, const VecQ& q, const VecPhi& predicted,
                               double last_term, const VecPhi& phi, const MatCPhi* Phi_phi,
                               const MatCQ* Phi_q, double residual, State<M>* to,
                               const typename internal::TrigOf<M>::type* trig,
                               PendingDistance* later) const {
  // (CorrectionAcceptable() fails on a phi that is not finite.) Next to a singular
  // configuration from's L (error ~ eps cond^3) may spoil the predictor: a step that leaves
  // it is judged about its end instead (CorrectionAcceptableBackwards(), below, once that
  // end's coefficients are known).
  const bool from_near_singular =
      from.sigma_min < options_.near_singular_ratio * from.sigma_max;
  if (!from_near_singular && !CorrectionAcceptable(last_term, predicted, phi)) return false;
  if (!internal::AllFinite(phi) || MovesTooFar(from.phi, phi, true)) return false;
  MatCPhi A;
  MatCQ B;
  typename T::Coefficients c;
  bool have_coefficients = false;
  PhiDerivatives derivatives;
  bool have_derivatives = false;
  if (Phi_phi == nullptr) {  // the residual test of a result of M::Solve
    bool from_coeffs = false;  // (constant but for the view)
    (void)from_coeffs;
    if constexpr (kPhiFromCoeffs) {
      if (PhiFromCoeffs()) {
        // One evaluation gives Phi and Phi_phi for the checks and K, L and the points: the
        // coefficients are computed before the conditioning test, and discarded (with the
        // whole step) when it fails, so a singular Phi_phi never reaches the state.
        // (trig == nullptr: Coeffs calls its own sin and cos.)
        Calls::Coeffs(model_, params_, q, phi, &c, trig);
        residual = internal::MaxAbsDiff(c.Phi);
        if (!(residual <= options_.tolerance)) return false;
        if constexpr (std::is_same_v<std::decay_t<decltype(c.Phi_phi)>, MatCPhi>) {
          Phi_phi = &c.Phi_phi;  // (a generated model's, or a sized view's: a plain member)
        } else {  // (the view's: a map of its buffer)
          Assign(&A, c.Phi_phi);
          Phi_phi = &A;
        }
        have_coefficients = true;
        from_coeffs = true;
      }
    }
    if constexpr (!kPhiFromCoeffs || Calls::kView) if (!from_coeffs) {
      VecC Phi;
      if constexpr (kDualL) {
        // The same Phi, Phi_phi and Phi_q, with their derivatives for L: one evaluation
        // (from Model::Coeffs with trig when there is one).
        EvalPhiWithDerivatives(q, phi, &Phi, &A, &B, &derivatives, trig);
        have_derivatives = true;
      } else {
        Calls::Phi(model_, params_, q, phi, &Phi, &A, NeedPhiQ() ? &B : nullptr);
      }
      residual = Phi.template lpNorm<Eigen::Infinity>();
      if (!(residual <= options_.tolerance)) return false;
      Phi_phi = &A;
      Phi_q = NeedPhiQ() ? &B : nullptr;
    }
  }
  Assign(&to->q, q);
  Assign(&to->phi, phi);
  to->residual_norm = residual;
  const Factorization f(*Phi_phi);
  // The distance to singularity (State::sigma_min, sigma_max and their directions) is read by
  // no check below unless `from` is next to a singular configuration (Leaving()); otherwise
  // it is computed last, after every check, or by MoveTo() (PendingDistance): the same
  // values, but its chain of square roots and divisions no longer holds up the step.
  const bool distance_first = from_near_singular;
  if (!Classify(*Phi_phi, f, &from, to, distance_first) || to->branch != from.branch) return false;
  const PhiDerivatives* d = have_derivatives ? &derivatives : nullptr;
  if (have_coefficients ? !CopyCoefficients(c, f, Phi_q, to, d) : !FillCoefficients(f, Phi_q, to, d)) {
    return false;
  }
  if (from_near_singular) {
    const bool ok = Leaving(from, *to) ? CorrectionAcceptableBackwards(from, *to)
                                       : CorrectionAcceptable(last_term, predicted, phi);
    if (!ok) return false;
  }
  if (!VelocityConsistent(from, *to)) return false;
  if (!distance_first) {
    if constexpr (M::kNphi == Eigen::Dynamic || M::kNphi <= 2) {
      if (later != nullptr && nphi() <= 2) {
        Assign(&later->Phi_phi, *Phi_phi);  // finite: its factorization succeeded
        later->pending = true;
      } else {
        Distance(*Phi_phi, f, &from, to);
      }
    } else {
      (void)later;
      Distance(*Phi_phi, f, &from, to);
    }
  }
  to->valid = true;
  return true;
}

template <class M, class Assembler>
bool PositionSolver<M, Assembler>::Step(const State<M>& from, const VecQ& q, State<M>* to, Summary* s,
                                bool* used_newton, PendingDistance* later) const {
  double last_term = 0;
  const VecPhi predicted = Predict(from, q, &last_term);
  if (MovesTooFar(from.phi, predicted)) return false;  // split before running a corrector
  if constexpr (Features::kHasSolve) {
    if (has_modes_) {  // (false for a view without Solve: FindModes())
      // The generated solver on this branch's modes: closed-form blocks are exact and cost
      // no iteration, Newton blocks start from the predictor (and polish).
      VecPhi phi;
      Assign(&phi, predicted);
      // With Model::TrigT, Solve also hands out sin and cos of the angles it solved (a
      // closed-form dyad from its own dot and cross products), and Coeffs uses them.
      typename internal::TrigOf<M>::type trig;
      const auto report = Calls::Solve(model_, params_, q, &phi, modes_, options_.max_newton_iterations,
                                       options_.tolerance, &trig);
      s->iterations += report.iterations;
      using SolveStatus = decltype(report.status);
      // (A phi that is not finite fails Accept()'s first check.)
      if (report.status == SolveStatus::kConverged &&
          Accept(from, q, predicted, last_term, phi, nullptr, nullptr, 0.0, to,
                 Features::kHasTrig ? &trig : nullptr, later)) {
        return true;
      }
    }
  }
  // Models without M::Solve, and the rare branch where M::Solve fails or its result fails a
  // check: Newton on the whole system from the same predictor.
  if (!NewtonCorrector(from, q, predicted, last_term, to, s)) return false;
  *used_newton = true;
  return true;
}

template <class M, class Assembler>
bool PositionSolver<M, Assembler>::NewtonCorrector(const State<M>& from, const VecQ& q,
                                           const VecPhi& predicted, double last_term,
                                           State<M>* to, Summary* s) const {
  VecPhi phi = predicted;
  MatCPhi Phi_phi;
  MatCQ Phi_q;
  const NewtonResult newton = FullNewton(q, &phi, &Phi_phi, NeedPhiQ() ? &Phi_q : nullptr);
  s->iterations += newton.iterations;
  return newton.status == Status::kConverged &&
         Accept(from, q, predicted, last_term, phi, &Phi_phi, NeedPhiQ() ? &Phi_q : nullptr,
                newton.residual_norm, to);
}

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::MoveTo(const VecQ& q_target, Summary* summary) {
  if (summary == nullptr) {  // (a local Summary only then: not set up on every step)
    Summary local;
    return MoveTo(q_target, &local);
  }
  Summary* s = summary;
  *s = Summary();
  const State<M>& from = state_ref();
  if (!options_valid_ || !from.valid || !internal::AllFinite(q_target) ||
      !(internal::InputStep<Calls::kView>(q_target, from.q) <= options_.max_input_step)) {
    s->reason = !options_valid_      ? "invalid Options"
                : !from.valid         ? "nothing assembled to continue from"
                : !q_target.allFinite() ? "input not finite"
                                        : "step larger than Options::max_input_step";
    return Finish(Status::kInvalidInput, nullptr, s);
  }
  if constexpr (Features::kLoopFree) {
    return PlaceLoopFree(q_target, s);
  } else {
    if constexpr (Calls::kView) {
      if (Calls::LoopFree(model_)) return PlaceLoopFree(q_target, s);
    }
    // The common case (every step of a sweep with small steps): one sub-step straight to
    // q_target, written into the other state and adopted by flipping current_.
    bool used_newton = false;
    PendingDistance later;
    if (Step(from, q_target, &states_[1 - current_], s, &used_newton, &later)) {
      current_ = 1 - current_;
      if (used_newton) FindModes(state_ref());
      s->substeps = 1;
      // The distance to singularity last (PendingDistance), before Finish() reports it.
      if constexpr (M::kNphi == Eigen::Dynamic || M::kNphi <= 2) {
        if (later.pending) SmallDistance(later.Phi_phi, true, &state_ref());
      }
      return Finish(Status::kConverged, &state_ref(), s);
    }
    ++s->rejected_substeps;
    return Subdivide(q_target, s);
  }
}

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::Subdivide(const VecQ& q_target, Summary* s) {
  // Split the step: halve on failure, double after success, down to h_min of the step.
  const VecQ q_start = state_ref().q;
  const VecQ delta = q_target - q_start;
  const double h_min = std::ldexp(1.0, -options_.max_bisections);
  State<M> current = state_ref();
  State<M> next(model_);
  bool used_newton = false;
  double t = 0;    // fraction of the step done
  double h = 0.5;  // fraction tried next
  int attempts = 1;
  while (t < 1) {
    if (++attempts > options_.max_substeps) {
      s->reason = "more than Options::max_substeps sub-steps";
      return Finish(Status::kDidNotConverge, nullptr, s);
    }
    h = std::min(h, 1 - t);
    const bool last = t + h >= 1;
    const VecQ q = last ? q_target : VecQ(q_start + (t + h) * delta);
    if (Step(current, q, &next, s, &used_newton)) {
      current = next;
      t = last ? 1 : t + h;
      ++s->substeps;
      h *= 2;
      continue;
    }
    ++s->rejected_substeps;
    if (h > h_min) {
      h *= 0.5;
      continue;
    }
    Status status = Fallback(current, q, &next, s);
    if (status != Status::kConverged) {
      // The smallest sub-step failed. Next to a singular configuration that is a dead point
      // (nothing closes beyond it) or a change point (only the other branch closes).
      // Decided on (and reported with) the exact distance to singularity.
      MakeDistanceExact(&current);
      const bool near_singular =
          current.sigma_min < options_.near_singular_ratio * current.sigma_max;
      if (status == Status::kSingular || near_singular) {
        s->reason = near_singular ? "reached a singular configuration (dead point or change "
                                    "point); state() is the last valid one before it"
                                  : "only the other branch closes beyond this point";
        state_ref() = current;  // the last valid configuration, the closest to the singular one
        return Finish(Status::kSingular, &current, s);
      }
      return Finish(status, nullptr, s);
    }
    current = next;
    used_newton = true;
    t = last ? 1 : t + h;
    ++s->substeps;
  }
  state_ref() = current;
  if (used_newton) FindModes(state_ref());
  return Finish(Status::kConverged, &current, s);
}

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::Fallback(const State<M>& from, const VecQ& q, State<M>* to,
                                      Summary* s) const {
  double last_term = 0;
  const VecPhi predicted = Predict(from, q, &last_term);
  VecPhi phi = predicted;
  if (!phi.allFinite()) phi = from.phi;
  if (!options_.assembly_fallback) return Status::kDidNotConverge;
  const AssemblyResult lm =
      Assembler::Minimize(model_, params_, q, &phi, options_.max_lm_iterations);
  s->used_assembler = true;
  s->iterations += lm.iterations;
  s->residual_norm = lm.residual_norm;
  MatCPhi Phi_phi;
  MatCQ Phi_q;
  const NewtonResult newton = FullNewton(q, &phi, &Phi_phi, NeedPhiQ() ? &Phi_q : nullptr);
  s->iterations += newton.iterations;
  if (newton.status != Status::kConverged) {
    return (lm.stationary && lm.residual_norm > options_.tolerance) ? Status::kNotAssemblable
                                                                    : Status::kDidNotConverge;
  }
  to->q = q;
  to->phi = phi;
  to->residual_norm = newton.residual_norm;
  const Factorization f(Phi_phi);
  const bool regular = Classify(Phi_phi, f, nullptr, to);
  Describe(*to, s);  // the configuration found, also when it is refused below
  // The loop closes at q, but only on the other branch (det Phi_phi would pass through 0 on
  // the way) or exactly at a singular configuration: either way Phi_phi loses rank.
  if (!regular || to->branch != from.branch) return Status::kSingular;
  // Judged about the better-conditioned end when the step leaves a singular configuration
  // (as in Accept()).
  const bool from_near_singular =
      from.sigma_min < options_.near_singular_ratio * from.sigma_max;
  if ((!from_near_singular && !CorrectionAcceptable(last_term, predicted, phi)) ||
      MovesTooFar(from.phi, phi)) {
    return Status::kDidNotConverge;
  }
  if (!FillCoefficients(f, NeedPhiQ() ? &Phi_q : nullptr, to)) return Status::kSingular;
  if (from_near_singular && !(Leaving(from, *to) ? CorrectionAcceptableBackwards(from, *to)
                                                 : CorrectionAcceptable(last_term, predicted, phi))) {
    return Status::kDidNotConverge;
  }
  if (!VelocityConsistent(from, *to)) return Status::kDidNotConverge;
  to->valid = true;
  return Status::kConverged;
}

}  // namespace mechgen::position
