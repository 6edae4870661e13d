/**
 * \file solver.h
 * Position analysis of a generated model: assembly from a rough guess, then continuation
 * along a motion that stays on the assembly mode (branch) it started on.
 *
 * PositionSolver<Model> works with any header generated from templates/mechanism.h.mustache.
 *  - Assemble(): Ceres Levenberg–Marquardt on Phi with the generated analytic Jacobian
 *    Phi_phi (ceres_adapter.h), polished by Newton. Allocates (a ceres::Problem).
 *  - MoveTo(): one continuation step q0 -> q1. Predictor phi ~ phi0 + K dq + 1/2 L(dq, dq)
 *    from the coefficients of the last configuration, then the corrector: the generated
 *    M::Solve(p, q, &phi_pred, modes) on the assembly modes of the current branch (found
 *    after assembly and after PassSingularity(), modes()): closed-form blocks are exact and
 *    cost no iteration, Newton blocks start from the predictor and polish. Models without
 *    M::Solve, and any step whose M::Solve result fails a check, use Paul's Newton–Raphson
 *    (NEWTR) on the whole system, phi <- phi - Phi_phi^{-1} Phi, plus one polishing step
 *    after the residual test passes (phi to ~1e-15, not ~cond * tolerance). The step is
 *    accepted when ||Phi||_inf <= tolerance, sign(det Phi_phi) is unchanged (same branch),
 *    Phi_phi is well conditioned and the corrector moved phi much less than the predictor
 *    did, and K agrees with K0 + L0 dq; otherwise it is split in halves. Ceres is only the
 *    fallback after the smallest half failed, and decides kNotAssemblable. The normal path
 *    never allocates.
 * On any failure the solver keeps its last valid configuration (state()); on kSingular that
 * is the last valid configuration before the singular one, and PassSingularity() continues
 * through it on the curve the caller chooses (types.h, Crossing).
 *
 * Distance to singularity (State::sigma_min, sigma_max, singular_direction), every
 * configuration, from the one factorization of Phi_phi a step has (closed-form inverse up
 * to 4 x 4, PartialPivLU above), which also gives det (branch) and cond_1:
 *  - kNphi <= 2: exact, in closed form (SingularValues2x2; ~5 ns).
 *  - kNphi > 2, continuation steps: one inverse iteration on Phi_phi^T Phi_phi from the
 *    previous configuration's singular direction and one power iteration from its largest
 *    direction; sigma_min = ||Phi_phi v|| (an upper bound), sigma_max = ||Phi_phi u|| (a
 *    lower bound), State::sigma_exact = false. When that ratio falls below
 *    Options::exact_sigma_ratio (0.1), a fixed-size JacobiSVD runs instead (exact).
 *  - Exact (SVD) always at assembly, in the Ceres fallback, in PassSingularity(), and for
 *    the configuration reported at a kSingular stop: the singular direction reported
 *    there is exact.
 * A result of M::Solve is checked (residual, conditioning, branch) on the Phi and Phi_phi
 * that Model::Coeffs hands out with K, L and the points (Coefficients::Phi, Phi_phi;
 * ModelFeatures::kCoeffsHavePhi): one generated evaluation per step. Models whose
 * coefficients lack them (or that ask for positions only) evaluate Model::Phi instead.
 * K and L come from Model::Coeffs when the model has them; otherwise K = -Phi_phi^{-1} Phi_q
 * (Phi_q from the same evaluation as Phi_phi, the step's factorization) and L by central
 * differences of Phi_phi and Phi_q along the motion (NumericalL(): two more evaluations
 * and kNq^2 solves with the same factorization). Numeric L is kept because the default
 * second-order predictor and the K-consistency guard need it.
 * L is stored as the generated code does: L(i, j + kNq*k) = dK(i, j)/dq_k.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

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
  /// Distance to singularity: sigma_min(Phi_phi), its smallest singular value (model length
  /// units; 0 at a dead or change point), and sigma_max = ||Phi_phi||_2.
  double sigma_min = kNaN;
  double sigma_max = kNaN;
  /// Unit right singular vector of sigma_min (kNphi): the direction in which phi can move
  /// with Phi unchanged to first order when sigma_min -> 0 (the singular motion).
  typename T::VecPhi singular_direction = T::VecPhi::Constant(kNaN);
  /// Unit right singular vector of sigma_max (kNphi); the next configuration's estimate
  /// starts from it and from singular_direction.
  typename T::VecPhi largest_direction = T::VecPhi::Constant(kNaN);
  /// true: sigma_min, sigma_max and both directions are exact (a singular value
  /// decomposition: closed form for kNphi <= 2, JacobiSVD above); false: the estimate of
  /// PositionSolver's continuation steps for kNphi > 2 (see solver.h: "Distance to
  /// singularity"), sigma_min an upper bound and sigma_max a lower bound of the exact ones.
  bool sigma_exact = false;
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
  using Factorization = SquareFactorization<M::kNphi>;
  /// Assembly modes of the blocks of M::Solve (one entry for a model without it).
  using Modes = std::array<int, internal::BlockCount<M>::value>;

  /// Invalid options (Options::IsValid() false) make every solve return kInvalidInput.
  explicit PositionSolver(const Options& options = Options(), const Params& params = Params())
      : options_(options), params_(params), options_valid_(options.IsValid(nullptr)) {}

  const Options& options() const { return options_; }
  const Params& params() const { return params_; }
  /// Changes the parameters; the configuration must be assembled again.
  void set_params(const Params& params) {
    params_ = params;
    state_ref() = State<M>();
    has_modes_ = false;
  }
  /// The last valid configuration (state().valid is false before the first assembly).
  const State<M>& state() const { return states_[current_]; }

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
  NewtonResult Newton(const VecQ& q, VecPhi* phi, MatCPhi* Phi_phi) const {
    return FullNewton(q, phi, Phi_phi, nullptr);
  }

  /// The assembly mode (+1 / -1) of each block of the generated M::Solve on the current
  /// branch, found after assembly (and after passing a singular configuration); false when
  /// the model has no M::Solve or no modes reproduce the configuration (the continuation
  /// then corrects with Newton on the whole system).
  bool modes(Modes* out) const {
    if (has_modes_ && out != nullptr) *out = modes_;
    return has_modes_;
  }

  /**
   * \brief Passes the singular configuration next to state() (after MoveTo() returned
   *        kSingular) by pseudo-arclength continuation in (t, phi), t the input along the
   *        line state().q -> q_toward, and leaves state() just beyond it.
   *
   * Classifies the singular configuration: a dead point (fold: the augmented Jacobian
   * [Phi_q d, Phi_phi] keeps full rank, the curve turns back in t) or a change point (both
   * lose rank: two curves cross). Then steps of Options::pass_step along the tangent:
   *  - kFollowTangent (change point): the incoming curve's tangent; sign det Phi_phi flips.
   *  - kSwitchBranch (change point): the other curve's tangent, tau = c2 tau1 - 2 c1 w with
   *    w = (0, v), c1 = psi^T Phi''(tau1, w), c2 = psi^T Phi''(w, w) (v, psi the right and
   *    left singular vectors; Phi'' by central differences of the generated Jacobian).
   *  - kReverseInput (dead point): along the curve, which turns back; the input reverses
   *    (Summary::input_reversed) and sign det Phi_phi flips.
   * A choice that does not fit the singular configuration (kReverseInput at a change point,
   * kFollowTangent at a dead point, ...) returns kSingular with Summary::reason saying which
   * fits; state() is unchanged. Allocation-free.
   * \param[in]  q_toward  Where the input was heading (dim kNq), != state().q.
   * \param[in]  crossing  The continuation the caller chooses (kStop: returns kSingular).
   * \param[out] summary   May be nullptr.
   * \return kConverged (state() beyond the singular configuration, on the chosen curve),
   *         kSingular (choice does not fit, or state() is not next to a singular
   *         configuration), kDidNotConverge or kInvalidInput.
   */
  Status PassSingularity(const VecQ& q_toward, Crossing crossing, Summary* summary);

 private:
  // True when phi moves an angle coordinate by more than Options::max_predicted_angle from
  // phi0, or is not finite.
  bool MovesTooFar(const VecPhi& phi0, const VecPhi& phi, bool known_finite = false) const {
    if (!known_finite && !phi.allFinite()) return true;
    for (int i = 0; i < M::kNphi; ++i) {
      if (M::kPhiIsAngle[i] && !(std::abs(phi(i) - phi0(i)) <= options_.max_predicted_angle))
        return true;
    }
    return false;
  }
  // A model whose coefficients lack K needs Phi_q for K = -Phi_phi^{-1} Phi_q.
  static constexpr bool kNeedPhiQ = !Features::kHasK;

  // cond, sign(det) and the distance to singularity of Phi_phi (factored as f) into *s;
  // false when singular (1/cond < min_rcond). warm: the neighbouring configuration whose
  // singular vectors start the estimate (kNphi > 2); nullptr: exact.
  bool Classify(const MatCPhi& Phi_phi, const Factorization& f, const State<M>* warm,
                State<M>* s) const;
  // sigma_min, sigma_max and their right singular vectors into *s (see the file comment).
  void Distance(const MatCPhi& Phi_phi, const Factorization& f, const State<M>* warm,
                State<M>* s) const;
  // The exact distance (a full SVD above 2 x 2) at s's configuration, if s has an estimate.
  void MakeDistanceExact(State<M>* s) const;
  // K, L and the points at (s->q, s->phi); false if any is not finite. Phi_q: dPhi/dq
  // there, or nullptr (evaluated when the model lacks K). Calls Model::Coeffs once.
  bool FillCoefficients(const Factorization& f, const MatCQ* Phi_q, State<M>* s) const {
    typename T::Coefficients c;
    if constexpr (kCallCoeffs) M::template Coeffs<double>(params_, s->q, s->phi, &c);
    return CopyCoefficients(c, f, Phi_q, s);
  }
  // The same from c = Model::Coeffs at (s->q, s->phi), already evaluated (unused when the
  // model's coefficients have neither K, L nor points).
  bool CopyCoefficients(const typename T::Coefficients& c, const Factorization& f,
                        const MatCQ* Phi_q, State<M>* s) const;
  static constexpr bool kCallCoeffs =
      Features::kHasK || Features::kHasL || Features::kHasPoints;
  // A result of M::Solve is checked on the Phi and Phi_phi of Model::Coeffs (one evaluation
  // per step) when the coefficients have them and the step needs Coeffs anyway; else on
  // Model::Phi (a model without Coefficients::Phi_phi, or asking for positions only).
  static constexpr bool kPhiFromCoeffs = Features::kCoeffsHavePhi && kCallCoeffs;
  void NumericalL(const VecQ& q, const VecPhi& phi, const Factorization& f,
                  const typename T::MatK& K, typename T::MatL* L) const;
  // Newton–Raphson on the whole system with a polishing step (Newton() with Phi_q).
  NewtonResult FullNewton(const VecQ& q, VecPhi* phi, MatCPhi* Phi_phi, MatCQ* Phi_q) const;
  // The assembly modes of every closed-form block of M::Solve that reproduce s.phi at s.q
  // into modes_ (has_modes_ false when there are none: M::Solve is then not used).
  void FindModes(const State<M>& s);
  // The checks of a continuation sub-step on a corrected phi; on success *to is complete.
  // Phi, Phi_phi, Phi_q: at (q, phi) when the caller has them, else nullptr (evaluated).
  // predicted, last_term: Predict() at q.
  // trig: sin and cos of the angles from the M::Solve that gave phi (Features::kHasTrig), or
  // nullptr.
  bool Accept(const State<M>& from, const VecQ& q, const VecPhi& predicted, double last_term,
              const VecPhi& phi, const MatCPhi* Phi_phi, const MatCQ* Phi_q, double residual,
              State<M>* to, const typename internal::TrigOf<M>::type* trig = nullptr) const;
  // The predictor phi0 + K dq (+ 1/2 L(dq, dq) for the second-order one) at q; *last_term:
  // the max-norm of the last Taylor term it used, the scale of CorrectionAcceptable().
  VecPhi Predict(const State<M>& from, const VecQ& q, double* last_term) const;
  // Branch guard: the corrector may move phi by less than max_correction_ratio times the
  // last Taylor term the predictor used (1/2 L(dq, dq), or K dq for a first-order
  // predictor) plus max_correction_abs. On one smooth curve the correction is the next,
  // smaller term (O(dq^3)); landing on another curve costs O(dq) (K differs) and is
  // refused, also at a change point where that curve keeps sign(det Phi_phi). False when
  // phi is not finite.
  bool CorrectionAcceptable(double last_term, const VecPhi& pred, const VecPhi& phi) const {
    return internal::MaxAbsDiff(phi, &pred) <=
           options_.max_correction_ratio * last_term + options_.max_correction_abs;
  }
  // The same guard on K: K(q) ~ K0 + L0 dq, and the remainder must be smaller than the
  // last term. Catches a sub-step that lands on (or next to) a change point, where Newton
  // converges only linearly to a point whose phi passes the guard above but whose K is
  // O(1) off (it belongs to no solution curve), and the jump onto another curve after it.
  bool VelocityConsistent(const State<M>& from, const State<M>& to) const {
    const VecQ dq = to.q - from.q;
    typename T::MatK change = T::MatK::Zero();  // L(i, j + kNq k) dq_k summed over k
    for (int k = 0; k < M::kNq; ++k) change += from.L.template middleCols<M::kNq>(M::kNq * k) * dq(k);
    const double remainder = (to.K - from.K - change).template lpNorm<Eigen::Infinity>();
    return remainder <= options_.max_correction_ratio * change.template lpNorm<Eigen::Infinity>() +
                            options_.max_correction_abs *
                                (1 + from.K.template lpNorm<Eigen::Infinity>());
  }
  // One continuation sub-step from `from` to q by predictor + corrector (M::Solve on the
  // branch's modes, else / then Newton on the whole system); no allocation. *used_newton
  // is set when the accepted result did not come from M::Solve. try_solved: false when the
  // caller already ran SolvedStep() from `from` to q and it failed (the same again would).
  bool TryStep(const State<M>& from, const VecQ& q, State<M>* to, Summary* s,
               bool* used_newton, bool try_solved = true) const;
  // The part of TryStep() that corrects with M::Solve on the branch's modes (has_modes_);
  // adds M::Solve's iterations to *iterations.
  bool SolvedStep(const State<M>& from, const VecQ& q, State<M>* to, int* iterations) const;
  // MoveTo() after its fast path: the checks with their reasons, TryStep() (M::Solve, then
  // Newton) and the split into sub-steps. iterations: those the fast path already spent;
  // solved_tried: the fast path ran SolvedStep() to q (and it failed).
  Status MoveToGeneral(const VecQ& q, Summary* summary, int iterations, bool solved_tried);
  // MoveTo() tries SolvedStep() inline first (every step of a sweep with small steps) when
  // the model has M::Solve and its Coefficients have Phi and Phi_phi.
  static constexpr bool kInlineFastPath = Features::kHasSolve && kPhiFromCoeffs;
  // Levenberg–Marquardt at q starting from the predictor; the failure path.
  Status Fallback(const State<M>& from, const VecQ& q, State<M>* to, Summary* s) const;

  Options options_;
  Params params_;
  bool options_valid_;
  // The last valid configuration is states_[current_]; the fast path of MoveTo() writes the
  // other one and flips current_ (no copy of a State per step).
  State<M>& state_ref() { return states_[current_]; }
  State<M> states_[2];
  int current_ = 0;
  Modes modes_{};     // assembly mode of each block of M::Solve on state()'s branch
  bool has_modes_ = false;
};

// ---------------------------------------------------------------------------------------
// Implementation.

template <class M>
NewtonResult PositionSolver<M>::FullNewton(const VecQ& q, VecPhi* phi, MatCPhi* Phi_phi,
                                           MatCQ* Phi_q) const {
  NewtonResult result;
  VecC Phi;
  // A singular Phi_phi gives inf/NaN in the step, caught by the finiteness tests.
  // Up to 4 x 4, Eigen's fixed-size inverse (cofactors) is several times faster than
  // PartialPivLU (measured 20 ns vs 3 ns for 2 x 2, a sixth of a whole step), and with
  // cond(Phi_phi) bounded by Options::min_rcond it is as accurate here; larger systems
  // use the pivoted LU. Both are fixed-size: no allocation.
  auto step = [](const MatCPhi& A, const VecC& r) -> VecPhi {
    if constexpr (M::kNphi <= 4) {
      return A.inverse() * r;
    } else {
      return Eigen::PartialPivLU<MatCPhi>(A).solve(r);
    }
  };
  for (int iteration = 0;; ++iteration) {
    M::template Phi<double>(params_, q, *phi, &Phi, Phi_phi, Phi_q);
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
      M::template Phi<double>(params_, q, polished, &Phi2, &A2, Phi_q != nullptr ? &B2 : nullptr);
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

template <class M>
bool PositionSolver<M>::Classify(const MatCPhi& Phi_phi, const Factorization& f,
                                 const State<M>* warm, State<M>* s) const {
  s->condition = f.condition();
  s->branch = Sign(f.determinant());
  Distance(Phi_phi, f, warm, s);
  // f.ok(): det finite and nonzero (so branch != 0), cond_1 finite.
  return f.ok() && s->condition * options_.min_rcond <= 1.0;
}

template <class M>
void PositionSolver<M>::Distance(const MatCPhi& A, const Factorization& f,
                                 const State<M>* warm, State<M>* s) const {
  constexpr int n = M::kNphi;
  s->sigma_exact = true;
  if constexpr (n == 1) {
    s->sigma_min = s->sigma_max = std::abs(A(0, 0));
    s->singular_direction.setOnes();
    s->largest_direction.setOnes();
    if (!A.allFinite()) {
      s->sigma_min = s->sigma_max = std::numeric_limits<double>::quiet_NaN();
    }
  } else if constexpr (n == 2) {
    // f.ok(): det and cond_1 finite, so every entry of A is.
    internal::SingularValues2x2(A, &s->sigma_min, &s->sigma_max, &s->singular_direction,
                                &s->largest_direction, f.ok());
  } else {
    // One step of inverse iteration on Phi_phi^T Phi_phi from the neighbour's singular
    // direction (two solves with the factorization the step has anyway) and one step of
    // the power iteration from its largest direction (two products). The Rayleigh
    // quotients ||A v|| >= sigma_min and ||A u|| <= sigma_max; the warm start carries the
    // iteration from configuration to configuration, and next to a singular configuration
    // (sigma_min << sigma_{n-1}) one step converges by the factor (sigma_min/sigma_{n-1})^2.
    // When the estimated ratio drops below Options::exact_sigma_ratio, the full SVD runs.
    if (warm != nullptr && f.ok() && options_.exact_sigma_ratio < 1 &&
        warm->singular_direction.allFinite() && warm->largest_direction.allFinite()) {
      VecPhi v = f.Solve(f.SolveTransposed(warm->singular_direction));
      VecPhi u = A.transpose() * (A * warm->largest_direction);
      const double nv = v.norm(), nu = u.norm();
      if (std::isfinite(nv) && std::isfinite(nu) && nv > 0 && nu > 0) {
        v /= nv;
        u /= nu;
        const double smin = (A * v).norm();
        const double smax = std::max((A * u).norm(), smin);
        if (smin >= options_.exact_sigma_ratio * smax) {
          internal::FixSign(&v);
          internal::FixSign(&u);
          s->sigma_min = smin;
          s->sigma_max = smax;
          s->singular_direction = v;
          s->largest_direction = u;
          s->sigma_exact = false;
          return;
        }
      }
    }
    if (!A.allFinite()) {
      constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
      s->sigma_min = s->sigma_max = kNaN;
      s->singular_direction.setConstant(kNaN);
      s->largest_direction.setConstant(kNaN);
      return;
    }
    const Eigen::JacobiSVD<MatCPhi, Eigen::NoQRPreconditioner> svd(A, Eigen::ComputeFullV);
    s->sigma_min = svd.singularValues()(n - 1);
    s->sigma_max = svd.singularValues()(0);
    s->singular_direction = svd.matrixV().col(n - 1);
    s->largest_direction = svd.matrixV().col(0);
    internal::FixSign(&s->singular_direction);
    internal::FixSign(&s->largest_direction);
  }
}

template <class M>
void PositionSolver<M>::MakeDistanceExact(State<M>* s) const {
  if (s->sigma_exact) return;
  MatCPhi Phi_phi;
  M::template Phi<double>(params_, s->q, s->phi, nullptr, &Phi_phi, nullptr);
  const Factorization f(Phi_phi);
  Distance(Phi_phi, f, nullptr, s);
}

template <class M>
void PositionSolver<M>::NumericalL(const VecQ& q, const VecPhi& phi, const Factorization& f,
                                   const typename T::MatK& K, typename T::MatL* L) const {
  // K = -Phi_phi^{-1} Phi_q  =>  dK/dq_k = -Phi_phi^{-1} (D_k Phi_phi K + D_k Phi_q), where
  // D_k is the total derivative along the motion (dq, dphi) = (e_k, K e_k), taken by central
  // differences. h = cbrt(eps) ~ 6e-6 balances truncation O(h^2) and rounding O(eps/h):
  // both ~ 1e-11 relative. Uses the step's factorization of Phi_phi.
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
    L->template middleCols<M::kNq>(M::kNq * k) = -f.Solve(MatCQ(dA * K + dB));
  }
}

template <class M>
bool PositionSolver<M>::CopyCoefficients(const typename T::Coefficients& c,
                                         const Factorization& f, const MatCQ* Phi_q,
                                         State<M>* s) const {
  (void)c;
  if constexpr (Features::kHasK) {
    s->K = c.K;
  } else {
    MatCQ B;
    if (Phi_q == nullptr) {
      M::template Phi<double>(params_, s->q, s->phi, nullptr, nullptr, &B);
      Phi_q = &B;
    }
    s->K = -f.Solve(*Phi_q);
  }
  if constexpr (Features::kHasL) {
    s->L = c.L;
  } else {
    NumericalL(s->q, s->phi, f, s->K, &s->L);
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
                                                              const VecQ& q,
                                                              double* last_term) const {
  const VecQ dq = q - from.q;
  const VecPhi first = from.K * dq;
  if (!options_.second_order_predictor) {
    *last_term = internal::MaxAbsDiff(first);
    return from.phi + first;
  }
  typename T::VecQQ dq_dq;  // (dq (x) dq)(j + kNq k) = dq_j dq_k
  for (int k = 0; k < M::kNq; ++k) dq_dq.segment(M::kNq * k, M::kNq) = dq * dq(k);
  const VecPhi second = 0.5 * from.L * dq_dq;
  *last_term = internal::MaxAbsDiff(second);
  return from.phi + first + second;
}

template <class M>
bool PositionSolver<M>::Accept(const State<M>& from, const VecQ& q, const VecPhi& predicted,
                               double last_term, const VecPhi& phi, const MatCPhi* Phi_phi,
                               const MatCQ* Phi_q, double residual, State<M>* to,
                               const typename internal::TrigOf<M>::type* trig) const {
  // (CorrectionAcceptable() fails on a phi that is not finite.)
  if (!CorrectionAcceptable(last_term, predicted, phi) || MovesTooFar(from.phi, phi, true)) {
    return false;
  }
  MatCPhi A;
  MatCQ B;
  typename T::Coefficients c;
  bool have_coefficients = false;
  if (Phi_phi == nullptr) {  // the residual test of a result of M::Solve
    if constexpr (kPhiFromCoeffs) {
      // One evaluation gives Phi and Phi_phi for the checks and K, L and the points: the
      // coefficients are computed before the conditioning test, and discarded (with the
      // whole step) when it fails, so a singular Phi_phi never reaches the state.
      if constexpr (Features::kHasTrig) {
        M::template Coeffs<double>(params_, q, phi, &c, trig);  // trig == nullptr: its own sin, cos
      } else {
        (void)trig;
        M::template Coeffs<double>(params_, q, phi, &c);
      }
      residual = internal::MaxAbsDiff(c.Phi);
      if (!(residual <= options_.tolerance)) return false;
      Phi_phi = &c.Phi_phi;
      have_coefficients = true;
    } else {
      VecC Phi;
      M::template Phi<double>(params_, q, phi, &Phi, &A, kNeedPhiQ ? &B : nullptr);
      residual = Phi.template lpNorm<Eigen::Infinity>();
      if (!(residual <= options_.tolerance)) return false;
      Phi_phi = &A;
      Phi_q = kNeedPhiQ ? &B : nullptr;
    }
  }
  to->q = q;
  to->phi = phi;
  to->residual_norm = residual;
  const Factorization f(*Phi_phi);
  if (!Classify(*Phi_phi, f, &from, to) || to->branch != from.branch) return false;
  if (have_coefficients ? !CopyCoefficients(c, f, Phi_q, to) : !FillCoefficients(f, Phi_q, to)) {
    return false;
  }
  if (!VelocityConsistent(from, *to)) return false;
  to->valid = true;
  return true;
}

template <class M>
bool PositionSolver<M>::SolvedStep(const State<M>& from, const VecQ& q, State<M>* to,
                                   int* iterations) const {
  if constexpr (Features::kHasSolve) {
    double last_term = 0;
    const VecPhi predicted = Predict(from, q, &last_term);
    if (MovesTooFar(from.phi, predicted)) return false;  // split before running a corrector
    // The generated solver on this branch's modes: closed-form blocks are exact and cost
    // no iteration, Newton blocks start from the predictor (and polish).
    VecPhi phi = predicted;
    // With Model::TrigT, Solve also hands out sin and cos of the angles it solved (a
    // closed-form dyad from its own dot and cross products), and Coeffs uses them.
    typename internal::TrigOf<M>::type trig;
    const auto report = [&]() {
      if constexpr (Features::kHasTrig) {
        return M::template Solve<double>(params_, q, &phi, modes_, options_.max_newton_iterations,
                                         options_.tolerance, &trig);
      } else {
        return M::template Solve<double>(params_, q, &phi, modes_, options_.max_newton_iterations,
                                         options_.tolerance);
      }
    }();
    *iterations += report.iterations;
    using SolveStatus = decltype(report.status);
    // (A phi that is not finite fails Accept()'s first check.)
    return report.status == SolveStatus::kConverged &&
           Accept(from, q, predicted, last_term, phi, nullptr, nullptr, 0.0, to,
                  Features::kHasTrig ? &trig : nullptr);
  } else {
    return false;
  }
}

template <class M>
bool PositionSolver<M>::TryStep(const State<M>& from, const VecQ& q, State<M>* to,
                                Summary* s, bool* used_newton, bool try_solved) const {
  double last_term = 0;
  const VecPhi predicted = Predict(from, q, &last_term);
  if (MovesTooFar(from.phi, predicted)) return false;  // split before running a corrector
  if constexpr (Features::kHasSolve) {
    // The generated solver on this branch's modes: closed-form blocks are exact and cost
    // no iteration, Newton blocks start from the predictor (and polish).
    if (has_modes_ && try_solved && SolvedStep(from, q, to, &s->iterations)) return true;
  }
  // Newton on the whole system from the predictor: models without M::Solve, and the
  // fallback when M::Solve fails or its result fails a check.
  VecPhi phi = predicted;
  MatCPhi Phi_phi;
  MatCQ Phi_q;
  const NewtonResult newton = FullNewton(q, &phi, &Phi_phi, kNeedPhiQ ? &Phi_q : nullptr);
  s->iterations += newton.iterations;
  if (newton.status != Status::kConverged) return false;
  if (!Accept(from, q, predicted, last_term, phi, &Phi_phi, kNeedPhiQ ? &Phi_q : nullptr,
              newton.residual_norm, to)) {
    return false;
  }
  *used_newton = true;
  return true;
}

template <class M>
void PositionSolver<M>::FindModes(const State<M>& s) {
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

template <class M>
Status PositionSolver<M>::Fallback(const State<M>& from, const VecQ& q, State<M>* to,
                                   Summary* s) const {
  double last_term = 0;
  const VecPhi predicted = Predict(from, q, &last_term);
  VecPhi phi = predicted;
  if (!phi.allFinite()) phi = from.phi;
  if (!options_.ceres_fallback) return Status::kDidNotConverge;
  const LevenbergMarquardtResult lm =
      SolveLevenbergMarquardt<M>(params_, q, &phi, options_.max_lm_iterations);
  s->used_ceres = true;
  s->iterations += lm.iterations;
  s->residual_norm = lm.residual_norm;
  MatCPhi Phi_phi;
  MatCQ Phi_q;
  const NewtonResult newton = FullNewton(q, &phi, &Phi_phi, kNeedPhiQ ? &Phi_q : nullptr);
  s->iterations += newton.iterations;
  if (newton.status != Status::kConverged) {
    return (lm.stationary && lm.residual_norm > options_.tolerance) ? Status::kNotAssemblable
                                                                    : Status::kDidNotConverge;
  }
  to->q = q;
  to->phi = phi;
  to->residual_norm = newton.residual_norm;
  s->residual_norm = newton.residual_norm;
  const Factorization f(Phi_phi);
  const bool regular = Classify(Phi_phi, f, nullptr, to);
  s->condition = to->condition;
  s->sigma_min = to->sigma_min;
  s->branch = to->branch;
  // The loop closes at q, but only on the other branch (det Phi_phi would pass through 0 on
  // the way) or exactly at a singular configuration: either way Phi_phi loses rank.
  if (!regular || to->branch != from.branch) return Status::kSingular;
  if (!CorrectionAcceptable(last_term, predicted, phi) || MovesTooFar(from.phi, phi)) {
    return Status::kDidNotConverge;
  }
  if (!FillCoefficients(f, kNeedPhiQ ? &Phi_q : nullptr, to)) return Status::kSingular;
  if (!VelocityConsistent(from, *to)) return Status::kDidNotConverge;
  to->valid = true;
  return Status::kConverged;
}

template <class M>
Status PositionSolver<M>::MoveTo(const VecQ& q_target, Summary* summary) {
  if constexpr (kInlineFastPath) {
    // The fast path of MoveToGeneral() without its bookkeeping: valid input, one sub-step
    // straight to q_target corrected by M::Solve. Anything else (and any failure) goes the
    // general way, which repeats the checks with their reasons but not a SolvedStep() that
    // already failed here.
    const State<M>& from = state_ref();
    int iterations = 0;
    const bool try_solved = has_modes_ && options_valid_ && from.valid && q_target.allFinite() &&
                            (q_target - from.q).cwiseAbs().maxCoeff() <= options_.max_input_step;
    if (try_solved) {
      if (SolvedStep(from, q_target, &states_[1 - current_], &iterations)) {
        current_ = 1 - current_;
        if (summary != nullptr) {
          const State<M>& to = state_ref();
          *summary = Summary();
          summary->status = Status::kConverged;
          summary->iterations = iterations;
          summary->substeps = 1;
          summary->residual_norm = to.residual_norm;
          summary->condition = to.condition;
          summary->sigma_min = to.sigma_min;
          summary->branch = to.branch;
        }
        return Status::kConverged;
      }
    }
    return MoveToGeneral(q_target, summary, iterations, try_solved);
  } else {
    return MoveToGeneral(q_target, summary, 0, false);
  }
}

template <class M>
Status PositionSolver<M>::MoveToGeneral(const VecQ& q_target, Summary* summary,
                                        int iterations, bool solved_tried) {
  Summary s;
  s.iterations = iterations;
  auto finish = [&](Status status) {
    s.status = status;
    if (summary != nullptr) *summary = s;
    return status;
  };
  if (!options_valid_ || !state_ref().valid || !q_target.allFinite()) {
    s.reason = !options_valid_  ? "invalid Options"
               : !state_ref().valid ? "nothing assembled to continue from"
                               : "input not finite";
    return finish(Status::kInvalidInput);
  }
  if (!((q_target - state_ref().q).cwiseAbs().maxCoeff() <= options_.max_input_step)) {
    s.reason = "step larger than Options::max_input_step";
    return finish(Status::kInvalidInput);
  }
  // Fast path (every step of a sweep with small steps): one sub-step straight to q_target.
  bool used_newton = false;
  if (TryStep(state_ref(), q_target, &states_[1 - current_], &s, &used_newton, !solved_tried)) {
    current_ = 1 - current_;
    if (used_newton) FindModes(state_ref());
    s.substeps = 1;
    s.residual_norm = state_ref().residual_norm;
    s.condition = state_ref().condition;
    s.sigma_min = state_ref().sigma_min;
    s.branch = state_ref().branch;
    return finish(Status::kConverged);
  }
  ++s.rejected_substeps;
  // Split the step: halve on failure, double after success, down to h_min of the step.
  const VecQ q_start = state_ref().q;
  const VecQ delta = q_target - q_start;
  const double h_min = std::ldexp(1.0, -options_.max_bisections);
  State<M> current = state_ref();
  State<M> next;
  double t = 0;    // fraction of the step done
  double h = 0.5;  // fraction tried next
  int attempts = 1;
  while (t < 1) {
    if (++attempts > options_.max_substeps) {
      s.reason = "more than Options::max_substeps sub-steps";
      return finish(Status::kDidNotConverge);
    }
    h = std::min(h, 1 - t);
    const bool last = t + h >= 1;
    const VecQ q = last ? q_target : VecQ(q_start + (t + h) * delta);
    if (TryStep(current, q, &next, &s, &used_newton)) {
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
    Status status = Fallback(current, q, &next, &s);
    if (status != Status::kConverged) {
      // The smallest sub-step failed. Next to a singular configuration that is a dead point
      // (nothing closes beyond it) or a change point (only the other branch closes).
      // Decided on (and reported with) the exact distance to singularity.
      MakeDistanceExact(&current);
      const bool near_singular =
          current.sigma_min < options_.near_singular_ratio * current.sigma_max;
      if (status == Status::kSingular || near_singular) {
        status = Status::kSingular;
        s.reason = near_singular ? "reached a singular configuration (dead point or change "
                                   "point); state() is the last valid one before it"
                                 : "only the other branch closes beyond this point";
        state_ref() = current;  // the last valid configuration, the closest to the singular one
        s.residual_norm = current.residual_norm;
        s.condition = current.condition;
        s.sigma_min = current.sigma_min;
        s.branch = current.branch;
      }
      return finish(status);
    }
    current = next;
    used_newton = true;
    t = last ? 1 : t + h;
    ++s.substeps;
  }
  state_ref() = current;
  if (used_newton) FindModes(state_ref());
  s.residual_norm = current.residual_norm;
  s.condition = current.condition;
  s.sigma_min = current.sigma_min;
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
  MatCQ Phi_q;
  // Newton to Options::tolerance, and one polishing step.
  const NewtonResult newton = FullNewton(q, &phi, &Phi_phi, kNeedPhiQ ? &Phi_q : nullptr);
  s.iterations += newton.iterations;
  if (newton.status != Status::kConverged) {
    return finish(lm.stationary ? Status::kNotAssemblable : Status::kDidNotConverge);
  }
  State<M> next;
  next.q = q;
  next.phi = phi;
  next.residual_norm = newton.residual_norm;
  s.residual_norm = newton.residual_norm;
  const Factorization f(Phi_phi);
  const bool regular = Classify(Phi_phi, f, nullptr, &next);
  s.condition = next.condition;
  s.sigma_min = next.sigma_min;
  s.branch = next.branch;
  s.substeps = 1;
  if (!regular) return finish(Status::kSingular);
  if (required_branch != 0 && next.branch != Sign(required_branch)) {
    return finish(Status::kWrongBranch);
  }
  if (!FillCoefficients(f, kNeedPhiQ ? &Phi_q : nullptr, &next)) {
    return finish(Status::kSingular);
  }
  next.valid = true;
  state_ref() = next;
  FindModes(state_ref());
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

template <class M>
Status PositionSolver<M>::PassSingularity(const VecQ& q_toward, Crossing crossing,
                                          Summary* summary) {
  constexpr int n = M::kNphi;
  using VecX = Eigen::Matrix<double, n + 1, 1>;       // x = (t, phi)
  using MatJ = Eigen::Matrix<double, M::kNc, n + 1>;  // [Phi_q d, Phi_phi]
  using MatX = Eigen::Matrix<double, n + 1, n + 1>;
  Summary s;
  auto finish = [&](Status status, const char* reason) {
    s.status = status;
    s.reason = reason;
    if (summary != nullptr) *summary = s;
    return status;
  };
  if (!options_valid_ || !state_ref().valid || !q_toward.allFinite()) {
    return finish(Status::kInvalidInput, "no valid state() or input not finite");
  }
  const VecQ q0 = state_ref().q;
  VecQ d = q_toward - q0;
  const double length = d.norm();
  if (!(length > 0)) return finish(Status::kInvalidInput, "q_toward == state().q");
  d /= length;
  s.branch = state_ref().branch;
  s.sigma_min = state_ref().sigma_min;
  s.condition = state_ref().condition;
  if (crossing == Crossing::kStop) return finish(Status::kSingular, "Crossing::kStop");
  MakeDistanceExact(&state_ref());  // the same configuration; only an estimate becomes exact
  s.sigma_min = state_ref().sigma_min;
  if (!(state_ref().sigma_min < options_.near_singular_ratio * state_ref().sigma_max)) {
    return finish(Status::kSingular,
                  "state() is not next to a singular configuration "
                  "(sigma_min / sigma_max >= Options::near_singular_ratio)");
  }

  // G(x) = Phi(q0 + t d, phi) and its Jacobian J = [Phi_q d, Phi_phi] (n x (n + 1)).
  auto eval = [&](const VecX& x, VecC* G, MatJ* J) {
    const VecQ q = q0 + x(0) * d;
    const VecPhi phi = x.template tail<n>();
    MatCPhi A;
    MatCQ B;
    M::template Phi<double>(params_, q, phi, G, J != nullptr ? &A : nullptr,
                            J != nullptr ? &B : nullptr);
    if (J != nullptr) {
      J->col(0) = B * d;
      J->template rightCols<n>() = A;
    }
  };
  // Unit null vector of J (the curve's tangent) and sigma_n(J) / sigma_1(J), from the SVD
  // of J padded with a zero row (fixed size, no allocation).
  auto tangent = [](const MatJ& J, VecX* tau, double* ratio) {
    MatX padded = MatX::Zero();
    padded.template topRows<M::kNc>() = J;
    const Eigen::JacobiSVD<MatX, Eigen::NoQRPreconditioner> svd(padded, Eigen::ComputeFullV);
    *tau = svd.matrixV().col(n);
    *ratio = svd.singularValues()(n - 1) / svd.singularValues()(0);
  };

  VecX x0;
  x0(0) = 0;
  x0.template tail<n>() = state_ref().phi;
  MatJ J0;
  VecC G;
  eval(x0, &G, &J0);
  VecX tau0;
  double ratio_J = 0;
  tangent(J0, &tau0, &ratio_J);
  if (tau0(0) < 0) tau0 = -tau0;  // the incoming motion: t increasing
  const double ratio_phi = state_ref().sigma_min / state_ref().sigma_max;
  // At a dead point J keeps full rank while Phi_phi loses it (ratio_J = O(1) >> ratio_phi);
  // at a change point both lose rank at the same rate. The geometric mean separates them.
  const bool dead_point = ratio_J > std::sqrt(ratio_phi);
  if (dead_point && crossing != Crossing::kReverseInput) {
    return finish(Status::kSingular,
                  "a dead point: the loop does not close beyond it; Crossing::kReverseInput "
                  "continues with the input reversed");
  }
  if (!dead_point && crossing == Crossing::kReverseInput) {
    return finish(Status::kSingular,
                  "a change point, not a dead point: choose Crossing::kFollowTangent or "
                  "kSwitchBranch");
  }

  VecX tau = tau0;
  if (crossing == Crossing::kSwitchBranch) {
    // Second derivatives psi^T Phi''(a, b) by central differences of the Jacobian along a.
    VecPhi v, psi;
    double smin = 0, smax = 0;
    MatCPhi A0 = J0.template rightCols<n>();
    SmallestSingular(A0, &smin, &smax, &v, &psi);
    VecX w = VecX::Zero();
    w.template tail<n>() = v;
    const double h = std::cbrt(std::numeric_limits<double>::epsilon());
    auto second = [&](const VecX& a, const VecX& b) {
      MatJ J_plus, J_minus;
      VecC unused;
      eval(VecX(x0 + h * a), &unused, &J_plus);
      eval(VecX(x0 - h * a), &unused, &J_minus);
      return psi.dot((J_plus - J_minus) * b) / (2 * h);
    };
    const double c1 = second(tau0, w);
    const double c2 = second(w, w);
    // The bifurcation equation psi^T Phi''(tau1 + mu w, tau1 + mu w) = 0 has the roots
    // mu ~ 0 (the incoming curve) and mu = -2 c1 / c2 (the other one).
    VecX other = c2 * tau0 - 2 * c1 * w;
    if (!(other.norm() > 0) || !other.allFinite()) {
      return finish(Status::kSingular, "no second curve found at this change point");
    }
    other.normalize();
    if (other(0) < 0 || (other(0) == 0 && other.dot(tau0) < 0)) other = -other;
    if (std::abs(other.dot(tau0)) > 1 - 1e-6) {
      return finish(Status::kSingular, "the two tangents coincide: not a simple change point");
    }
    tau = other;
  }

  // Pseudo-arclength steps: predictor x + ds tau, corrector Newton on
  // [G(x); tau^T (x - x_pred)] = 0, until beyond the singular configuration.
  const double ds = options_.pass_step;
  VecX x = x0;
  double arc = 0;
  State<M> next;
  for (int step = 0; step < 64; ++step) {
    const VecX x_pred = x + ds * tau;
    VecX y = x_pred;
    bool converged = false;
    for (int it = 0; it <= 2 * options_.max_newton_iterations; ++it) {
      MatJ J;
      eval(y, &G, &J);
      ++s.iterations;
      const double norm = G.template lpNorm<Eigen::Infinity>();
      if (!std::isfinite(norm) || !y.allFinite()) break;
      if (norm <= options_.tolerance) {
        converged = true;
        break;
      }
      MatX F;
      F.template topRows<M::kNc>() = J;
      F.row(n) = tau.transpose();
      VecX rhs;
      rhs.template head<M::kNc>() = G;
      rhs(n) = tau.dot(y - x_pred);
      y -= Eigen::PartialPivLU<MatX>(F).solve(rhs);
    }
    if (!converged || (y - x_pred).norm() > 0.5 * ds) {
      return finish(Status::kDidNotConverge, "pseudo-arclength corrector failed");
    }
    MatJ J;
    eval(y, &G, &J);
    VecX tau_new;
    double unused = 0;
    tangent(J, &tau_new, &unused);
    if (tau_new.dot(tau) < 0) tau_new = -tau_new;
    x = y;
    tau = tau_new;
    arc += ds;
    ++s.substeps;
    // Beyond it when regular again, at least 2 steps on, with the expected sign of det.
    next.q = q0 + x(0) * d;
    next.phi = x.template tail<n>();
    MatCPhi Phi_phi = J.template rightCols<n>();
    const Factorization f(Phi_phi);
    const bool regular = Classify(Phi_phi, f, nullptr, &next);
    const bool flipped = next.branch == -state_ref().branch;
    const bool reversed = tau(0) < 0;
    bool done = false;
    if (crossing == Crossing::kSwitchBranch) {
      done = !flipped && !reversed;
    } else if (crossing == Crossing::kFollowTangent) {
      done = flipped && !reversed;
    } else {
      done = flipped && reversed;
    }
    if (step >= 1 && regular && next.sigma_min >= state_ref().sigma_min && done) {
      next.residual_norm = G.template lpNorm<Eigen::Infinity>();
      if (!FillCoefficients(f, nullptr, &next)) {
        return finish(Status::kSingular, "coefficients not finite beyond the crossing");
      }
      next.valid = true;
      state_ref() = next;
      FindModes(state_ref());  // the branch changed
      s.residual_norm = next.residual_norm;
      s.condition = next.condition;
      s.sigma_min = next.sigma_min;
      s.branch = next.branch;
      s.input_reversed = reversed;
      return finish(Status::kConverged, "");
    }
  }
  return finish(Status::kSingular, "did not get beyond the singular configuration in 64 steps");
}

}  // namespace mechgen
