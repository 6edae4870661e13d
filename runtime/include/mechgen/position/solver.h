/**
 * \file position/solver.h
 * Position analysis of a generated model: assembly from a rough guess, then continuation
 * along a motion that stays on the assembly mode (branch) it started on.
 *
 * PositionSolver<Model, Assembler> works with any header generated from
 * templates/mechanism.h.mustache. Needs Eigen only; Ceres only through the Assembler
 * CeresAssembler (position/ceres_adapter.h, CeresPositionSolver<M>).
 *  - Assemble(): the Assembler's Levenberg–Marquardt on Phi with the generated analytic
 *    Jacobian Phi_phi (position/assembler.h: NewtonAssembler, fixed-size Eigen, the
 *    default; or CeresAssembler, which allocates a ceres::Problem), polished by Newton.
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
 *    did, and K agrees with K0 + L0 dq; otherwise it is split in halves. The Assembler is
 *    only the fallback after the smallest half failed, and decides kNotAssemblable. The
 *    normal path never allocates. One step path: the common case (one sub-step straight to
 *    the target, corrected by M::Solve) and the rare ones (Newton on the whole system,
 *    halving, the Assembler) are branches of Step() and MoveTo(), not copies
 *    (position/internal/continuation.h).
 * On any failure the solver keeps its last valid configuration (state()); on kSingular that
 * is the last valid configuration before the singular one, and PassSingularity() continues
 * through it on the curve the caller chooses (position/types.h, Crossing).
 *
 * Distance to singularity (State::sigma_min, sigma_max, singular_direction), every
 * configuration, from the one factorization of Phi_phi a step has (closed-form inverse up
 * to 4 x 4, Gauss-Jordan up to 16 x 16, PartialPivLU above), which also gives det (branch)
 * and cond_1 (exact up to 16 x 16). No check of a continuation step reads it unless the step
 * starts next to a singular configuration (Leaving()), so it is computed after the checks:
 * last in Accept(), and for kNphi <= 2 on MoveTo()'s one-sub-step path last in MoveTo(),
 * before Summary reports it (PendingDistance): the same values, but its chain of square
 * roots and divisions no longer holds up the step (measured: a few percent of a four-bar
 * step). A step that starts next to a singular configuration computes it before its checks.
 *  - kNphi <= 2: exact, in closed form (SingularValues2x2; about 20 ns of a four-bar step in a
 *    perf profile, half of it waiting on the singular vectors' square root and division,
 *    which are off the path of sigma_min).
 *  - kNphi > 2, continuation steps: one inverse iteration on Phi_phi^T Phi_phi from the
 *    previous configuration's singular direction and one power iteration from its largest
 *    direction; sigma_min = ||Phi_phi v|| (an upper bound), sigma_max = ||Phi_phi u|| (a
 *    lower bound), State::sigma_exact = false. When that ratio falls below
 *    Options::exact_sigma_ratio (0.1), a fixed-size JacobiSVD runs instead (exact).
 *  - Exact (SVD) always at assembly, in the Assembler fallback, in PassSingularity(), and for
 *    the configuration reported at a kSingular stop: the singular direction reported
 *    there is exact.
 * A result of M::Solve is checked (residual, conditioning, branch) on the Phi and Phi_phi
 * that Model::Coeffs hands out with K, L and the points (Coefficients::Phi, Phi_phi;
 * ModelFeatures::kCoeffsHavePhi): one generated evaluation per step. Models whose
 * coefficients lack them (or that ask for positions only) evaluate Model::Phi instead.
 * K and L come from Model::Coeffs when the model has them; otherwise K = -Phi_phi^{-1} Phi_q
 * (Phi_q from the same evaluation as Phi_phi, the step's factorization) and L from the
 * derivatives of Phi_phi and Phi_q along the motion (NumericalL()) and kNq^2 solves with the
 * same factorization. Those derivatives come, for a model of at most 12 coordinates, from
 * the step's one evaluation of Model::Phi, done in dual numbers (position/internal/dual.h:
 * exact to rounding, and Phi, Phi_phi, Phi_q bit for bit those of Model::Phi<double>); for a
 * larger one, by central differences (two more evaluations). After a closed-form M::Solve
 * that hands out sin and cos (Model::TrigT), from Model::Coeffs in dual numbers seeded with
 * them instead, calling no sin or cos (position/internal/coefficients.h, PhiDerivatives).
 * L is kept because the default second-order predictor and the K-consistency guard need it.
 * L is stored as the generated code does: L(i, j + kNq*k) = dK(i, j)/dq_k.
 *
 * Accuracy (State::phi_error, K_error, L_error, copied into Summary and the sweep's CSV):
 * error bounds that the conditioning implies, by first-order propagation, for every
 * configuration with coefficients. With u = eps/2, n = kNphi, kappa = cond_1(Phi_phi),
 * ||Phi_phi^{-1}||_1 = kappa / ||Phi_phi||_1 (State::inverse_norm) and
 * rho = ||Phi||_inf + 4 n u ||Phi_phi||_1 (1 + ||phi||_inf) (the residual plus the rounding
 * of evaluating Phi):
 *   phi_error = ||Phi_phi^{-1}||_1 n rho + u ||phi||_inf                     (~ eps cond)
 *   K_error   = kappa (phi_error + n u) (1 + ||K||_1)                         (~ eps cond^2)
 *   L_error   = kappa ((phi_error + n u) (||L||_1 + (1 + ||K||_1)^2)
 *                      + 2 K_error (1 + ||K||_1))                             (~ eps cond^3)
 * in the units of phi (rad or length), K and L. Scale: the second and third derivatives of
 * Phi are taken as bounded by ||Phi_phi||_1 (link lengths: a revolute chain's Phi sums terms
 * l (cos, sin), each derivative of which is bounded by l); a model with much larger
 * constant terms (far-away ground pivots) has a larger rounding than rho assumes. For
 * kNphi > 16, kappa is Eigen's estimate. Checked against a quad-precision closed form next to
 * two change points (tests/runtime/near_singular_test.cc): the bounds hold up to cond 1e6,
 * where L is off in its first digit; far from singular configurations they are ~1e-13
 * (phi), ~1e-10 (K), ~1e-7 (L) or smaller.
 * Leaving a singular configuration: a continuation step whose start is next to a singular
 * configuration (sigma_min < Options::near_singular_ratio sigma_max) and whose end is
 * farther from it is judged about its end: the branch guard on phi and the K-consistency
 * guard expand about the end (its K and L), not about the start, whose L (error
 * ~ eps cond^3) is unreliable there; the start's K_error widens the K guard. A landing on
 * the other curve of a change point still fails the K guard (the curves' K differ by O(1)).
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "mechgen/core/inline.h"
#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/position/assembler.h"
#include "mechgen/position/internal/dual.h"
#include "mechgen/position/state.h"
#include "mechgen/position/types.h"

namespace mechgen::position {

template <class M, class Assembler = NewtonAssembler>
class PositionSolver;

/// \tparam M          A generated model (mech::<name>::Model) or one written the same way.
/// \tparam Assembler  Assembly from a poor guess and the continuation's last fallback
///                    (position/assembler.h): NewtonAssembler (no Ceres) or CeresAssembler.
template <class M, class Assembler>
class PositionSolver {
 public:
  using Options = position::Options;
  using Summary = position::Summary;
  using Status = position::Status;
  using T = ModelTypes<M>;
  using Params = typename T::Params;
  using VecQ = typename T::VecQ;
  using VecPhi = typename T::VecPhi;
  using VecC = typename T::VecC;
  using MatCPhi = typename T::MatCPhi;
  using MatCQ = typename T::MatCQ;
  using Features = ModelFeatures<M>;
  /// The model's sizes, constants and functions (core/model_calls.h): constant for a generated
  /// M, the view's for ViewModel.
  using Calls = ModelCalls<M>;
  using Factorization = SquareFactorization<M::kNphi, T::kMaxPhi>;
  /// Assembly modes of the blocks of M::Solve (one entry for a model without it).
  using Modes = typename Calls::Modes;

  /// Invalid options (Options::IsValid() false) make every solve return kInvalidInput.
  /// (A generated M only: a ViewModel names its view.)
  template <class Model = M, std::enable_if_t<!ModelCalls<Model>::kView, int> = 0>
  explicit PositionSolver(const Options& options = Options(), const Params& params = Params())
      : PositionSolver(M(), options, params) {}
  /// The solver of `model` (a ViewModel; for a generated M an empty tag), with its
  /// parameters' defaults or `params`.
  explicit PositionSolver(const M& model, const Options& options = Options())
      : PositionSolver(model, options, Calls::DefaultParams(model)) {}
  PositionSolver(const M& model, const Options& options, const Params& params)
      : model_(model),
        options_(options),
        params_(params),
        options_valid_(options.IsValid(nullptr)),
        states_{State<M>(model), State<M>(model)} {}

  const M& model() const { return model_; }
  const Options& options() const { return options_; }
  const Params& params() const { return params_; }
  /// Changes the parameters; the configuration must be assembled again.
  void set_params(const Params& params) {
    params_ = params;
    state_ref() = State<M>(model_);
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
   *        sub-step (then the Assembler runs; CeresAssembler allocates).
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
  // A model without constraints (Features::kLoopFree: no loop, every coordinate an input):
  // the configuration at q is q itself, with its coefficients from Model::Coeffs. Assemble(),
  // MoveTo() and PassSingularity() of such a model come here only, so nothing that factors the
  // empty Phi_phi is instantiated. The state: residual 0, cond 1, branch +1 (det of the empty
  // matrix), sigma_min +inf and sigma_max 0 (no singular value: never singular), error
  // bounds 0. kInvalidInput for options, q or coefficients that are not valid or finite.
  Status PlaceLoopFree(const VecQ& q, Summary* summary);
  // The model's sizes (constexpr for a generated M).
  MECHGEN_ALWAYS_INLINE int nq() const { return Calls::Nq(model_); }
  MECHGEN_ALWAYS_INLINE int nphi() const { return Calls::Nphi(model_); }
  MECHGEN_ALWAYS_INLINE int nc() const { return Calls::Nc(model_); }
  // True when phi moves an angle coordinate by more than Options::max_predicted_angle from
  // phi0, or is not finite.
  bool MovesTooFar(const VecPhi& phi0, const VecPhi& phi, bool known_finite = false) const {
    if (!known_finite && !internal::AllFinite(phi)) return true;
    for (int i = 0; i < nphi(); ++i) {
      if (Calls::PhiIsAngle(model_, i) && !(std::abs(phi(i) - phi0(i)) <= options_.max_predicted_angle))
        return true;
    }
    return false;
  }
  // A model whose coefficients lack K needs Phi_q for K = -Phi_phi^{-1} Phi_q (the view: may
  // lack K, NeedPhiQ() says).
  static constexpr bool kNeedPhiQ = !Features::kHasK;
  MECHGEN_ALWAYS_INLINE bool NeedPhiQ() const { return kNeedPhiQ || !Calls::HasK(model_); }

  // cond, sign(det) and the distance to singularity of Phi_phi (factored as f) into *s;
  // false when singular (1/cond < min_rcond). warm: the neighbouring configuration whose
  // singular vectors start the estimate (kNphi > 2); nullptr: exact. distance false: without
  // the distance (the caller calls Distance() itself later; the test does not read it).
  bool Classify(const MatCPhi& Phi_phi, const Factorization& f, const State<M>* warm,
                State<M>* s, bool distance = true) const;
  // sigma_min, sigma_max and their right singular vectors into *s (see the file comment).
  void Distance(const MatCPhi& Phi_phi, const Factorization& f, const State<M>* warm,
                State<M>* s) const;
  // Distance() for kNphi <= 2 (exact, closed form; needs no factorization). known_finite:
  // every entry of A is finite (its factorization succeeded).
  // (Mat: MatCPhi, or for the view PendingDistance's bounded 2 x 2.)
  template <class Mat>
  void SmallDistance(const Mat& A, bool known_finite, State<M>* s) const;
  // The distance to singularity of a kNphi <= 2 configuration that Accept() left to its
  // caller, MoveTo(), to compute last (SmallDistance() on Phi_phi there, the same values):
  // its square roots and divisions then overlap the start of the next step instead of
  // holding up the end of this one. pending: not computed yet. (Empty above 2 x 2; for the
  // view a bounded 2 x 2, not a MatCPhi of the view's maximum: MoveTo() holds it on every step.)
  using PendingMatrix = std::conditional_t<M::kNphi == Eigen::Dynamic,
                                           Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2, 2>,
                                           std::conditional_t<(M::kNphi <= 2), MatCPhi, std::array<double, 0>>>;
  struct PendingDistance {
    PendingMatrix Phi_phi;
    bool pending = false;
  };
  // The exact distance (a full SVD above 2 x 2) at s's configuration, if s has an estimate.
  void MakeDistanceExact(State<M>* s) const;
  // K, L and the points at (s->q, s->phi); false if any is not finite. Phi_q: dPhi/dq
  // there, or nullptr (evaluated when the model lacks K). Calls Model::Coeffs once.
  // Derivatives of Phi_phi and Phi_q at (s->q, s->phi) (PhiDerivatives): from the caller's
  // EvalPhiWithDerivatives() there, or nullptr (evaluated here when L needs them).
  struct PhiDerivatives;
  bool FillCoefficients(const Factorization& f, const MatCQ* Phi_q, State<M>* s,
                        const PhiDerivatives* d = nullptr) const {
    if constexpr (kCallCoeffs) {
      if (CallCoeffs()) {  // (constant but for the view)
        typename T::Coefficients c;
        Calls::Coeffs(model_, params_, s->q, s->phi, &c);
        return CopyCoefficients(c, f, Phi_q, s, d);
      }
    }
    if constexpr (!kCallCoeffs || Calls::kView) {
      // nothing in Coeffs for the state: CopyCoefficients does not read c
      static const typename T::Coefficients kNone{};
      return CopyCoefficients(kNone, f, Phi_q, s, d);
    }
    return false;  // (not reached)
  }
  // The same from c = Model::Coeffs at (s->q, s->phi), already evaluated (unused when the
  // model's coefficients have neither K, L nor points).
  bool CopyCoefficients(const typename T::Coefficients& c, const Factorization& f,
                        const MatCQ* Phi_q, State<M>* s, const PhiDerivatives* d = nullptr) const;
  // The error bounds of s (State::phi_error, K_error, L_error) from its residual, its
  // conditioning (Classify()) and its coefficients; see "Accuracy" in the file comment.
  // f: the factorization of Phi_phi at s (its ||Phi_phi||_1).
  MECHGEN_ALWAYS_INLINE void ErrorBounds(const Factorization& f, State<M>* s) const;
  // True when `from` is next to a singular configuration and `to` farther from it: the step
  // leaves the singularity, and is judged by to's coefficients, not from's (whose K and L
  // carry errors ~ eps cond^2, eps cond^3).
  bool Leaving(const State<M>& from, const State<M>& to) const {
    return from.sigma_min < options_.near_singular_ratio * from.sigma_max &&
           to.sigma_min > from.sigma_min;
  }
  static constexpr bool kCallCoeffs =
      Features::kHasK || Features::kHasL || Features::kHasPoints;
  MECHGEN_ALWAYS_INLINE bool CallCoeffs() const {
    return Calls::HasK(model_) || Calls::HasL(model_) || Calls::HasPoints(model_);
  }
  // A result of M::Solve is checked on the Phi and Phi_phi of Model::Coeffs (one evaluation
  // per step) when the coefficients have them and the step needs Coeffs anyway; else on
  // Model::Phi (a model without Coefficients::Phi_phi, or asking for positions only).
  static constexpr bool kPhiFromCoeffs = Features::kCoeffsHavePhi && kCallCoeffs;
  MECHGEN_ALWAYS_INLINE bool PhiFromCoeffs() const { return Calls::CoeffsHavePhi(model_) && CallCoeffs(); }
  // L of a model whose coefficients lack it: dK/dq_k = -Phi_phi^{-1} (D_k Phi_phi K + D_k Phi_q)
  // with D_k the derivative along the motion (e_k, K e_k). kDualL: from the derivatives of one
  // evaluation of Phi in dual numbers (d, or evaluated when nullptr; exact to rounding); else
  // by central differences (two more evaluations of Phi per input).
  void NumericalL(const VecQ& q, const VecPhi& phi, const Factorization& f,
                  const typename T::MatK& K, typename T::MatL* L,
                  const PhiDerivatives* d = nullptr) const;
  // The number of directions of the dual numbers (every q and phi), and whether L is taken
  // with them: a model without L, of at most 12 coordinates (the derivatives of Phi_phi and
  // Phi_q in every direction are kept: (kNq + kNphi) kNc (kNphi + kNq) numbers).
  // (Not for the view: its functions are in double only; L then by central differences.)
  static constexpr int kDualN = Calls::kView ? 0 : M::kNq + M::kNphi;
  static constexpr bool kDualL = !Calls::kView && !Features::kHasL && kDualN <= 12;
  // Phi, Phi_phi and Phi_q at (q, phi), equal bit for bit to Model::Phi<double> there, and the
  // derivatives of Phi_phi and Phi_q in each of the kDualN directions (q first, then phi), from
  // one evaluation of Model::Phi in internal::Dual<kDualN>; or with trig, the sin and cos from
  // Model::Solve, from Model::Coeffs (PhiDerivatives::kFromTrig; d then keeps trig for L).
  void EvalPhiWithDerivatives(const VecQ& q, const VecPhi& phi, VecC* Phi, MatCPhi* Phi_phi,
                              MatCQ* Phi_q, PhiDerivatives* d,
                              const typename internal::TrigOf<M>::type* trig = nullptr) const;
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
  // later: when not nullptr, a kNphi <= 2 distance to singularity that no check needs is
  // left to the caller (PendingDistance).
  bool Accept(const State<M>& from, const VecQ& q, const VecPhi& predicted, double last_term,
              const VecPhi& phi, const MatCPhi* Phi_phi, const MatCQ* Phi_q, double residual,
              State<M>* to, const typename internal::TrigOf<M>::type* trig = nullptr,
              PendingDistance* later = nullptr) const;
  // The predictor phi0 + K dq (+ 1/2 L(dq, dq) for the second-order one) at q; *last_term:
  // the max-norm of the last Taylor term it used, the scale of CorrectionAcceptable().
  MECHGEN_ALWAYS_INLINE VecPhi Predict(const State<M>& from, const VecQ& q, double* last_term) const;
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
  MECHGEN_ALWAYS_INLINE bool VelocityConsistent(const State<M>& from, const State<M>& to) const {
    if (Leaving(from, to)) return VelocityConsistentBackwards(from, to);
    if constexpr (Calls::kView) {
      // The same sums in the same order, entry by entry (change = 0 + L_0 dq_0 + L_1 dq_1 ...,
      // remainder (K - K0) - change), without the temporary matrix: Eigen's dynamic-size loops
      // stored it and read it back at once (a store-forwarding stall, ~5 ns of a four-bar
      // step). The maxima of the absolute values are those of lpNorm<Infinity> (K, K0 and L0
      // are finite here: CopyCoefficients() and the last step checked them).
      const int n = nphi(), m = nq();
      double remainder = 0, change_norm = 0, from_norm = 0;
      for (int j = 0; j < m; ++j) {
        for (int i = 0; i < n; ++i) {
          double change = 0;
          for (int k = 0; k < m; ++k) change += from.L(i, m * k + j) * (to.q(k) - from.q(k));
          remainder = std::max(remainder, std::abs(to.K(i, j) - from.K(i, j) - change));
          change_norm = std::max(change_norm, std::abs(change));
          from_norm = std::max(from_norm, std::abs(from.K(i, j)));
        }
      }
      return remainder <= options_.max_correction_ratio * change_norm +
                              options_.max_correction_abs * (1 + from_norm);
    }
    const VecQ dq = to.q - from.q;
    typename T::MatK change = T::MatK::Zero(nphi(), nq());  // L(i, j + kNq k) dq_k summed over k
    for (int k = 0; k < nq(); ++k) change += MiddleCols<M::kNq>(from.L, nq() * k, nq()) * dq(k);
    const double remainder = (to.K - from.K - change).template lpNorm<Eigen::Infinity>();
    return remainder <= options_.max_correction_ratio * change.template lpNorm<Eigen::Infinity>() +
                            options_.max_correction_abs *
                                (1 + from.K.template lpNorm<Eigen::Infinity>());
  }
  // The same guard for a step that leaves a singular configuration, expanded about `to`
  // (the better-conditioned end): K(from) ~ K(to) - L(to) dq, within the K error bound of
  // `from`. Its phi and K are still good there (errors eps cond, eps cond^2) while its L
  // (eps cond^3) is not: a stop at cond 1e6 has L off by O(1), and judged by it every step
  // away was refused. Landing on the other curve of a change point still fails: the two
  // curves' K differ by O(1) at the crossing.
  bool VelocityConsistentBackwards(const State<M>& from, const State<M>& to) const {
    const VecQ dq = to.q - from.q;
    typename T::MatK change = T::MatK::Zero(nphi(), nq());
    for (int k = 0; k < nq(); ++k) change += MiddleCols<M::kNq>(to.L, nq() * k, nq()) * dq(k);
    const double remainder = (from.K - to.K + change).template lpNorm<Eigen::Infinity>();
    return remainder <= options_.max_correction_ratio * change.template lpNorm<Eigen::Infinity>() +
                            options_.max_correction_abs *
                                (1 + to.K.template lpNorm<Eigen::Infinity>()) +
                            from.K_error + to.K_error;
  }
  // The branch guard on phi for a step that leaves a singular configuration, expanded about
  // `to`: phi(from) ~ phi(to) - K(to) dq + 1/2 L(to)(dq, dq), the correction measured
  // against that last term (the Taylor remainder about the better-conditioned end).
  bool CorrectionAcceptableBackwards(const State<M>& from, const State<M>& to) const {
    const VecQ dq = to.q - from.q;
    auto dq_dq = Sized<typename T::VecQQ>(nq() * nq());
    for (int k = 0; k < nq(); ++k) dq_dq.segment(nq() * k, nq()) = dq * dq(k);
    const VecPhi second = 0.5 * to.L * dq_dq;
    const VecPhi back = to.phi - to.K * dq + second;
    return internal::MaxAbsDiff(from.phi, &back) <=
           options_.max_correction_ratio * internal::MaxAbsDiff(second) +
               options_.max_correction_abs + from.phi_error;
  }
  // One continuation sub-step from `from` to q: predictor, then the corrector M::Solve on
  // the branch's modes (has_modes_), and when that fails or the model has none, Newton on
  // the whole system (NewtonCorrector()); no allocation. Adds the iterations to
  // s->iterations; *used_newton is set when the accepted result did not come from M::Solve.
  MECHGEN_ALWAYS_INLINE bool Step(const State<M>& from, const VecQ& q, State<M>* to, Summary* s,
                                  bool* used_newton, PendingDistance* later = nullptr) const;
  // Step()'s corrector by Newton on the whole system from `predicted` (for a model without
  // M::Solve the common case, else the rare one; not inlined into Step(), which stays lean).
  MECHGEN_NOINLINE bool NewtonCorrector(const State<M>& from, const VecQ& q,
                                        const VecPhi& predicted, double last_term,
                                        State<M>* to, Summary* s) const;
  // MoveTo() after its first sub-step failed: halves down to 2^-max_bisections of the step,
  // then the Assembler from the predictor (Fallback()); on a stall next to a singular
  // configuration, kSingular at the last valid configuration.
  MECHGEN_COLD_PATH Status Subdivide(const VecQ& q_target, Summary* s);
  // The numbers of a configuration a Summary reports: residual, condition, sigma_min, branch.
  static void Describe(const State<M>& at, Summary* s) {
    s->residual_norm = at.residual_norm;
    s->condition = at.condition;
    s->sigma_min = at.sigma_min;
    s->branch = at.branch;
    s->phi_error = at.phi_error;
    s->K_error = at.K_error;
    s->L_error = at.L_error;
  }
  // The Assembler at q starting from the predictor; the failure path.
  Status Fallback(const State<M>& from, const VecQ& q, State<M>* to, Summary* s) const;
  // The one place a Summary is completed: its status, and the numbers of the configuration
  // it ends at (at: nullptr when none, Describe()). Copies *s to *out when out is not s and
  // not nullptr.
  static Status Finish(Status status, const State<M>* at, Summary* s, Summary* out = nullptr) {
    s->status = status;
    if (at != nullptr) Describe(*at, s);
    if (out != nullptr && out != s) *out = *s;
    return status;
  }

  M model_;
  Options options_;
  Params params_;
  bool options_valid_;
  // The last valid configuration is states_[current_]; a one-sub-step MoveTo() writes the
  // other one and flips current_ (no copy of a State per step).
  State<M>& state_ref() { return states_[current_]; }
  State<M> states_[2];
  int current_ = 0;
  Modes modes_{};     // assembly mode of each block of M::Solve on state()'s branch
  bool has_modes_ = false;
};


}  // namespace mechgen::position

// The member definitions, by job.
#include "mechgen/position/internal/newton.h"
#include "mechgen/position/internal/distance.h"
#include "mechgen/position/internal/coefficients.h"
#include "mechgen/position/internal/modes.h"
#include "mechgen/position/internal/continuation.h"
#include "mechgen/position/internal/assembly.h"
#include "mechgen/position/internal/singularity.h"
