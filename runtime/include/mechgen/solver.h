/**
 * \file solver.h
 * Position analysis of a generated model: assembly from a rough guess, then continuation
 * along a motion that stays on the assembly mode (branch) it started on.
 *
 * PositionSolver<Model> works with any header generated from templates/mechanism.h.mustache.
 *  - Assemble(): Ceres Levenberg–Marquardt on Phi with the generated analytic Jacobian
 *    Phi_phi (ceres_adapter.h), polished by Newton. Allocates (a ceres::Problem).
 *  - MoveTo(): one continuation step q0 -> q1. Predictor phi ~ phi0 + K dq + 1/2 L(dq, dq)
 *    from the coefficients of the last configuration, then Paul's Newton–Raphson corrector
 *    (NEWTR) phi <- phi - Phi_phi^{-1} Phi, fixed-size (closed-form inverse up to 4 x 4,
 *    PartialPivLU above). The step is
 *    accepted when ||Phi||_inf <= tolerance, sign(det Phi_phi) is unchanged (same branch),
 *    Phi_phi is well conditioned and the corrector moved phi much less than the predictor
 *    did; otherwise it is split in halves. Ceres is only the fallback after the smallest
 *    half failed, and decides kNotAssemblable. The normal path never allocates.
 * On any failure the solver keeps its last valid configuration (state()).
 *
 * K and L come from Model::Coeffs when the model has them; otherwise K = -Phi_phi^{-1} Phi_q
 * and L by central differences of Phi_phi and Phi_q along the motion (see NumericalL()).
 * L is stored as the generated code does: L(i, j + kNq*k) = dK(i, j)/dq_k.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "mechgen/ceres_adapter.h"
#include "mechgen/model_traits.h"
#include "mechgen/types.h"

namespace mechgen {

/// A closed configuration and everything the model gives there. All members start as NaN.
template <class M>
struct State {
  using T = ModelTypes<M>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  typename T::VecQ q = T::VecQ::Constant(kNaN);        ///< inputs (kNq)
  typename T::VecPhi phi = T::VecPhi::Constant(kNaN);  ///< dependent variables (kNphi)
  typename T::MatK K = T::MatK::Constant(kNaN);        ///< dphi/dq (kNphi x kNq)
  typename T::MatL L = T::MatL::Constant(kNaN);        ///< L(i, j + kNq k) = dK(i,j)/dq_k
  typename T::MatRP r_P = T::MatRP::Constant(kNaN);    ///< points (2 x kNumPoints)
  typename T::MatKP K_P = T::MatKP::Constant(kNaN);    ///< d r_P / dq (2 kNumPoints x kNq)
  typename T::MatLP L_P = T::MatLP::Constant(kNaN);    ///< d2 r_P / dq2 (2 kNumPoints x kNq^2)
  double residual_norm = kNaN;                         ///< ||Phi||_inf
  double condition = kNaN;                             ///< cond_1(Phi_phi)
  int branch = 0;                                      ///< sign(det Phi_phi)
  bool valid = false;                                  ///< a converged configuration
};

/// Result of one Newton–Raphson solve at fixed q.
struct NewtonResult {
  Status status = Status::kNotRun;  ///< kConverged or kDidNotConverge
  int iterations = 0;               ///< linear solves
  double residual_norm = std::numeric_limits<double>::quiet_NaN();  ///< final ||Phi||_inf
};

template <class M>
class PositionSolver {
 public:
  using T = ModelTypes<M>;
  using Params = typename T::Params;
  using VecQ = typename T::VecQ;
  using VecPhi = typename T::VecPhi;
  using VecC = typename T::VecC;
  using MatCPhi = typename T::MatCPhi;
  using MatCQ = typename T::MatCQ;
  using Features = ModelFeatures<M>;

  /// Invalid options (Options::IsValid() false) make every solve return kInvalidInput.
  explicit PositionSolver(const Options& options = Options(), const Params& params = Params())
      : options_(options), params_(params), options_valid_(options.IsValid(nullptr)) {}

  const Options& options() const { return options_; }
  const Params& params() const { return params_; }
  /// Changes the parameters; the configuration must be assembled again.
  void set_params(const Params& params) {
    params_ = params;
    state_ = State<M>();
  }
  /// The last valid configuration (state().valid is false before the first assembly).
  const State<M>& state() const { return state_; }

  /**
   * \brief Assembles the mechanism at q from a rough guess.
   * \param[in]  q               Inputs (dim kNq).
   * \param[in]  phi_guess       Rough dependent variables (dim kNphi).
   * \param[in]  required_branch +1 / -1: the required sign(det Phi_phi); 0: accept either.
   * \param[out] summary         May be nullptr.
   * \return kConverged (state() updated), kWrongBranch, kNotAssemblable, kSingular,
   *         kDidNotConverge or kInvalidInput (state() unchanged).
   */
  Status Assemble(const VecQ& q, const VecPhi& phi_guess, int required_branch, Summary* summary);

  /// Assembles at the model's kAssemblyQ from kAssemblyPhi, requiring the branch of the guess
  /// (sign(det Phi_phi) at kAssemblyPhi; either branch if that is 0).
  Status AssembleDefault(Summary* summary);

  /**
   * \brief Moves the assembled mechanism to q along the straight line from state().q,
   *        staying on its branch. Never allocates unless Newton fails on the smallest
   *        sub-step (then Ceres runs).
   * \param[in]  q        Target inputs (dim kNq).
   * \param[out] summary  May be nullptr.
   * \return kConverged (state() at q), else state() keeps the configuration it had.
   */
  Status MoveTo(const VecQ& q, Summary* summary);

  /**
   * \brief Paul's NEWTR at fixed q: phi <- phi - Phi_phi^{-1} Phi(q, phi) until
   *        ||Phi||_inf <= Options::tolerance. No allocation.
   * \param[in]     q        Inputs (dim kNq).
   * \param[in,out] phi      Start and result (dim kNphi).
   * \param[out]    Phi_phi  dPhi/dphi at the final phi (kNc x kNphi).
   */
  NewtonResult Newton(const VecQ& q, VecPhi* phi, MatCPhi* Phi_phi) const;

 private:
  // cond and sign(det) of Phi_phi into *s; false when singular (1/cond < min_rcond).
  bool Classify(const MatCPhi& Phi_phi, State<M>* s) const;
  // K, L and the points at (s->q, s->phi); false if any is not finite.
  bool FillCoefficients(const MatCPhi& Phi_phi, State<M>* s) const;
  void NumericalL(const VecQ& q, const VecPhi& phi, const MatCPhi& Phi_phi,
                  const typename T::MatK& K, typename T::MatL* L) const;
  VecPhi Predict(const State<M>& from, const VecQ& q) const;
  bool CorrectionAcceptable(const VecPhi& phi0, const VecPhi& pred, const VecPhi& phi) const {
    const double predicted = (pred - phi0).template lpNorm<Eigen::Infinity>();
    const double correction = (phi - pred).template lpNorm<Eigen::Infinity>();
    return correction <=
           options_.max_correction_ratio * predicted + options_.max_correction_abs;
  }
  // One continuation sub-step from `from` to q by predictor + Newton; no allocation.
  bool TryStep(const State<M>& from, const VecQ& q, State<M>* to, Summary* s) const;
  // Levenberg–Marquardt at q starting from the predictor; the failure path.
  Status Fallback(const State<M>& from, const VecQ& q, State<M>* to, Summary* s) const;

  Options options_;
  Params params_;
  bool options_valid_;
  State<M> state_;
  State<M> scratch_;  // the fast path's result, kept to avoid re-initializing it per step
};

// ---------------------------------------------------------------------------------------
// Implementation.

template <class M>
NewtonResult PositionSolver<M>::Newton(const VecQ& q, VecPhi* phi, MatCPhi* Phi_phi) const {
  NewtonResult result;
  VecC Phi;
  for (int iteration = 0;; ++iteration) {
    M::template Phi<double>(params_, q, *phi, &Phi, Phi_phi, nullptr);
    result.residual_norm = Phi.template lpNorm<Eigen::Infinity>();
    result.iterations = iteration;
    if (!std::isfinite(result.residual_norm) || !phi->allFinite()) {
      result.status = Status::kDidNotConverge;
      return result;
    }
    if (result.residual_norm <= options_.tolerance) {
      result.status = Status::kConverged;
      return result;
    }
    if (iteration == options_.max_newton_iterations) {
      result.status = Status::kDidNotConverge;
      return result;
    }
    // A singular Phi_phi gives inf/NaN here, caught by the finiteness test above.
    // Up to 4 x 4, Eigen's fixed-size inverse (cofactors) is several times faster than
    // PartialPivLU (measured 20 ns vs 3 ns for 2 x 2, a sixth of a whole step), and with
    // cond(Phi_phi) bounded by Options::min_rcond it is as accurate here; larger systems
    // use the pivoted LU. Both are fixed-size: no allocation.
    if constexpr (M::kNphi <= 4) {
      *phi -= Phi_phi->inverse() * Phi;
    } else {
      const Eigen::PartialPivLU<MatCPhi> lu(*Phi_phi);
      *phi -= lu.solve(Phi);
    }
  }
}

template <class M>
bool PositionSolver<M>::Classify(const MatCPhi& Phi_phi, State<M>* s) const {
  double det = 0;
  ConditionAndDeterminant(Phi_phi, &s->condition, &det);
  s->branch = Sign(det);
  return std::isfinite(s->condition) && s->condition * options_.min_rcond <= 1.0 &&
         s->branch != 0;
}

template <class M>
void PositionSolver<M>::NumericalL(const VecQ& q, const VecPhi& phi, const MatCPhi& Phi_phi,
                                   const typename T::MatK& K, typename T::MatL* L) const {
  // K = -Phi_phi^{-1} Phi_q  =>  dK/dq_k = -Phi_phi^{-1} (D_k Phi_phi K + D_k Phi_q), where
  // D_k is the total derivative along the motion (dq, dphi) = (e_k, K e_k), taken by central
  // differences. h = cbrt(eps) ~ 6e-6 balances truncation O(h^2) and rounding O(eps/h):
  // both ~ 1e-11 relative.
  const Eigen::PartialPivLU<MatCPhi> lu(Phi_phi);
  const double h = std::cbrt(std::numeric_limits<double>::epsilon());
  for (int k = 0; k < M::kNq; ++k) {
    VecQ dq = VecQ::Zero();
    dq(k) = h;
    const VecPhi dphi = K.col(k) * h;
    MatCPhi A_plus, A_minus;
    MatCQ B_plus, B_minus;
    M::template Phi<double>(params_, VecQ(q + dq), VecPhi(phi + dphi), nullptr, &A_plus,
                            &B_plus);
    M::template Phi<double>(params_, VecQ(q - dq), VecPhi(phi - dphi), nullptr, &A_minus,
                            &B_minus);
    const MatCPhi dA = (A_plus - A_minus) / (2 * h);
    const MatCQ dB = (B_plus - B_minus) / (2 * h);
    for (int j = 0; j < M::kNq; ++j) {
      L->col(j + M::kNq * k) = -lu.solve(VecC(dA * K.col(j) + dB.col(j)));
    }
  }
}

template <class M>
bool PositionSolver<M>::FillCoefficients(const MatCPhi& Phi_phi, State<M>* s) const {
  typename T::Coefficients c;
  if constexpr (Features::kHasK || Features::kHasL || Features::kHasPoints) {
    M::template Coeffs<double>(params_, s->q, s->phi, &c);
  }
  if constexpr (Features::kHasK) {
    s->K = c.K;
  } else {
    MatCQ Phi_q;
    M::template Phi<double>(params_, s->q, s->phi, nullptr, nullptr, &Phi_q);
    s->K = -Eigen::PartialPivLU<MatCPhi>(Phi_phi).solve(Phi_q);
  }
  if constexpr (Features::kHasL) {
    s->L = c.L;
  } else {
    NumericalL(s->q, s->phi, Phi_phi, s->K, &s->L);
  }
  bool finite = s->K.allFinite() && s->L.allFinite();
  if constexpr (Features::kHasPoints) {
    s->r_P = c.r_P;
    finite = finite && s->r_P.allFinite();
  }
  if constexpr (Features::kHasPointVelocities) s->K_P = c.K_P;
  if constexpr (Features::kHasPointAccelerations) s->L_P = c.L_P;
  return finite;
}

template <class M>
typename PositionSolver<M>::VecPhi PositionSolver<M>::Predict(const State<M>& from,
                                                              const VecQ& q) const {
  const VecQ dq = q - from.q;
  VecPhi phi = from.phi + from.K * dq;
  if (options_.second_order_predictor) {
    typename T::VecQQ dq_dq;  // (dq (x) dq)(j + kNq k) = dq_j dq_k
    for (int k = 0; k < M::kNq; ++k) dq_dq.segment(M::kNq * k, M::kNq) = dq * dq(k);
    phi += 0.5 * from.L * dq_dq;
  }
  return phi;
}

template <class M>
bool PositionSolver<M>::TryStep(const State<M>& from, const VecQ& q, State<M>* to,
                                Summary* s) const {
  const VecPhi predicted = Predict(from, q);
  VecPhi phi = predicted;
  MatCPhi Phi_phi;
  const NewtonResult newton = Newton(q, &phi, &Phi_phi);
  s->iterations += newton.iterations;
  if (newton.status != Status::kConverged) return false;
  if (!CorrectionAcceptable(from.phi, predicted, phi)) return false;
  to->q = q;
  to->phi = phi;
  to->residual_norm = newton.residual_norm;
  if (!Classify(Phi_phi, to) || to->branch != from.branch) return false;
  if (!FillCoefficients(Phi_phi, to)) return false;
  to->valid = true;
  return true;
}

template <class M>
Status PositionSolver<M>::Fallback(const State<M>& from, const VecQ& q, State<M>* to,
                                   Summary* s) const {
  VecPhi phi = Predict(from, q);
  if (!phi.allFinite()) phi = from.phi;
  if (!options_.ceres_fallback) return Status::kDidNotConverge;
  const LevenbergMarquardtResult lm =
      SolveLevenbergMarquardt<M>(params_, q, &phi, options_.max_lm_iterations);
  s->used_ceres = true;
  s->iterations += lm.iterations;
  s->residual_norm = lm.residual_norm;
  MatCPhi Phi_phi;
  const NewtonResult newton = Newton(q, &phi, &Phi_phi);
  s->iterations += newton.iterations;
  if (newton.status != Status::kConverged) {
    return (lm.stationary && lm.residual_norm > options_.tolerance) ? Status::kNotAssemblable
                                                                    : Status::kDidNotConverge;
  }
  to->q = q;
  to->phi = phi;
  to->residual_norm = newton.residual_norm;
  s->residual_norm = newton.residual_norm;
  const bool regular = Classify(Phi_phi, to);
  s->condition = to->condition;
  s->branch = to->branch;
  // The loop closes at q, but only on the other branch (det Phi_phi would pass through 0 on
  // the way) or exactly at a singular configuration: either way Phi_phi loses rank.
  if (!regular || to->branch != from.branch) return Status::kSingular;
  if (!CorrectionAcceptable(from.phi, Predict(from, q), phi)) return Status::kDidNotConverge;
  if (!FillCoefficients(Phi_phi, to)) return Status::kSingular;
  to->valid = true;
  return Status::kConverged;
}

template <class M>
Status PositionSolver<M>::MoveTo(const VecQ& q_target, Summary* summary) {
  Summary s;
  auto finish = [&](Status status) {
    s.status = status;
    if (summary != nullptr) *summary = s;
    return status;
  };
  if (!options_valid_ || !state_.valid || !q_target.allFinite()) {
    return finish(Status::kInvalidInput);
  }
  // Fast path (every step of a sweep with small steps): one sub-step straight to q_target.
  if (TryStep(state_, q_target, &scratch_, &s)) {
    state_ = scratch_;
    s.substeps = 1;
    s.residual_norm = state_.residual_norm;
    s.condition = state_.condition;
    s.branch = state_.branch;
    return finish(Status::kConverged);
  }
  ++s.rejected_substeps;
  // Split the step: halve on failure, double after success, down to h_min of the step.
  const VecQ q_start = state_.q;
  const VecQ delta = q_target - q_start;
  const double h_min = std::ldexp(1.0, -options_.max_bisections);
  State<M> current = state_;
  State<M> next;
  double t = 0;    // fraction of the step done
  double h = 0.5;  // fraction tried next
  int attempts = 1;
  while (t < 1) {
    if (++attempts > options_.max_substeps) return finish(Status::kDidNotConverge);
    h = std::min(h, 1 - t);
    const bool last = t + h >= 1;
    const VecQ q = last ? q_target : VecQ(q_start + (t + h) * delta);
    if (TryStep(current, q, &next, &s)) {
      current = next;
      t = last ? 1 : t + h;
      ++s.substeps;
      h *= 2;
      continue;
    }
    ++s.rejected_substeps;
    if (h > h_min) {
      h *= 0.5;
      continue;
    }
    const Status status = Fallback(current, q, &next, &s);
    if (status != Status::kConverged) return finish(status);
    current = next;
    t = last ? 1 : t + h;
    ++s.substeps;
  }
  state_ = current;
  s.residual_norm = current.residual_norm;
  s.condition = current.condition;
  s.branch = current.branch;
  return finish(Status::kConverged);
}

template <class M>
Status PositionSolver<M>::Assemble(const VecQ& q, const VecPhi& phi_guess, int required_branch,
                                   Summary* summary) {
  Summary s;
  s.used_ceres = true;
  auto finish = [&](Status status) {
    s.status = status;
    if (summary != nullptr) *summary = s;
    return status;
  };
  if (!options_valid_ || !q.allFinite() || !phi_guess.allFinite()) {
    return finish(Status::kInvalidInput);
  }
  VecC Phi;
  M::template Phi<double>(params_, q, phi_guess, &Phi, nullptr, nullptr);
  if (!Phi.allFinite()) return finish(Status::kInvalidInput);  // parameters not finite

  VecPhi phi = phi_guess;
  const LevenbergMarquardtResult lm =
      SolveLevenbergMarquardt<M>(params_, q, &phi, options_.max_lm_iterations);
  s.iterations = lm.iterations;
  s.residual_norm = lm.residual_norm;
  MatCPhi Phi_phi;
  const NewtonResult newton = Newton(q, &phi, &Phi_phi);  // polish to Options::tolerance
  s.iterations += newton.iterations;
  if (newton.status != Status::kConverged) {
    return finish(lm.stationary ? Status::kNotAssemblable : Status::kDidNotConverge);
  }
  State<M> next;
  next.q = q;
  next.phi = phi;
  next.residual_norm = newton.residual_norm;
  s.residual_norm = newton.residual_norm;
  const bool regular = Classify(Phi_phi, &next);
  s.condition = next.condition;
  s.branch = next.branch;
  s.substeps = 1;
  if (!regular) return finish(Status::kSingular);
  if (required_branch != 0 && next.branch != Sign(required_branch)) {
    return finish(Status::kWrongBranch);
  }
  if (!FillCoefficients(Phi_phi, &next)) return finish(Status::kSingular);
  next.valid = true;
  state_ = next;
  return finish(Status::kConverged);
}

template <class M>
Status PositionSolver<M>::AssembleDefault(Summary* summary) {
  const VecQ q = Eigen::Map<const VecQ>(M::kAssemblyQ.data());
  const VecPhi phi = Eigen::Map<const VecPhi>(M::kAssemblyPhi.data());
  MatCPhi Phi_phi;
  M::template Phi<double>(params_, q, phi, nullptr, &Phi_phi, nullptr);
  double cond = 0, det = 0;
  ConditionAndDeterminant(Phi_phi, &cond, &det);
  return Assemble(q, phi, Sign(det), summary);
}

}  // namespace mechgen
