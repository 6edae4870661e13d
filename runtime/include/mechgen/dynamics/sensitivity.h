/**
 * \file dynamics/sensitivity.h
 * Trajectory sensitivities (issue 27): dq(t)/dp and dqd(t)/dp of the free motion of a model
 * generated with `dynamics` and a `design` section, p its design parameters
 * (M::kDesignNames), by the forward sensitivity (variational) equations integrated with the
 * state:
 *
 *     q'  = qd,                       qd' = f(t, q, qd; p) = I^-1 (Q - h)
 *     S'  = Sd,                       Sd' = f_q S + f_qd Sd + f_p
 *     S = dq/dp, Sd = dqd/dp (kNq x kNp), S(t0) = Sd(t0) = 0 (q0 and qd0 do not depend on p).
 *
 * The partial derivatives of the right-hand side, at one evaluation:
 *  - f_p = I^-1 (dQ/dp - dh/dp - (dI/dp) qdd): the generated EvalDynamicsDesign (M::DynamicsDesign),
 *    whose design derivatives at fixed (q, qd) go through phi, K and L
 *    (EvalDesignDerivatives, M::Design);
 *  - f_q, f_qd = I^-1 (dQ/dx - dh/dx - (dI/dx) qdd), x = q, qd: dQ/dx and dh/dx from the generated
 *    EvalDynamicsJacobian (M::DynamicsJacobian, generated with EvalDynamicsDesign: the dynamics
 *    differentiated symbolically along q and qd, through K, L and the third-order coefficients
 *    dL/dq; generator/symbolic/jacobian.h) and dI/dq from EvalDynamics (Dynamics::dI_dq). For a
 *    model without it (a cam law's fourth derivative needed, or generated before it existed),
 *    or with SensitivityOptions::jet_jacobians: the generated EvalCoefficients and EvalDynamics
 *    instantiated with ceres::Jet<double, 2 kNq>
 *    seeded on (q, qd), the positions carrying dphi/dq = K (the implicit-function derivative of
 *    the loop closure), so that I, h and Q carry their total derivatives along q and qd. Both
 *    exact (no differences); they agree to rounding (tests/design/trajectory_sensitivity_test.cc).
 * The integrator's error control covers the sensitivities as well as (q, qd) (the whole state,
 * IntegratorOptions' rtol and atol on every component).
 *
 * The positions are solved at every stage by the generated position solver from the last
 * accepted configuration's predictor, as the free simulation (dynamics/forward.h) does; a
 * configuration whose 1/cond_1(Phi_phi) falls below SensitivityOptions::min_rcond, or that
 * approaches a singular one step after step (approach_rcond, approach_steps), ends the run
 * with Status::kDeadPoint at the accepted step where it was seen (near a dead point dq/dp
 * grows like 1/sigma_min(Phi_phi): a status, never a huge number returned as success).
 *
 * Not here (the model's loads only, smooth): Coulomb friction with stick and slip (a
 * non-differentiable mode change; its friction loads are zero here), the restarts at switching
 * points of the loads (at a kink of Q the sensitivities of a switch time are not modelled:
 * the step control steps through it), the energy projection and the user events of
 * MinimalDynamics.
 *
 * Units: S(i, d) in q_i's unit per unit of p_d, Sd(i, d) in q_i's unit per second per unit
 * of p_d. Nothing allocates after construction; nothing throws; no state outside the object.
 */
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include <ceres/jet.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/simulator.h"

namespace mechgen::dynamics {

struct SensitivityOptions {
  IntegratorOptions integrator;
  /// Dead point when 1/cond_1(Phi_phi) < min_rcond at an accepted step.
  double min_rcond = kMinRcond;
  /// A singular configuration approached (the steps collapse before 1/cond reaches min_rcond):
  /// approach_steps accepted steps in a row with 1/cond_1(Phi_phi) < approach_rcond and
  /// falling also end the run with kDeadPoint (as PrescribedOptions does).
  double approach_rcond = 1e-3;
  int approach_steps = 200;
  /// Samples every sample_dt from t0 (and at the end); 0: at every accepted step.
  double sample_dt = 0;
  /// A run whose sample grid would hand out more samples than this is refused.
  int max_samples = 100000000;
  /// Newton blocks of M::Solve: iterations and tolerance (0: the generated default).
  int max_solver_iterations = 20;
  double solver_tolerance = 0;
  /// f_q and f_qd by Jets of the generated EvalCoefficients and EvalDynamics even where the model
  /// has EvalDynamicsJacobian (a second method, for checks; slower).
  bool jet_jacobians = false;

  bool IsValid(std::string* error) const {
    if (!integrator.IsValid(error)) return false;
    auto fail = [&](const char* what) {
      if (error != nullptr) *error = what;
      return false;
    };
    if (!(min_rcond >= 0 && min_rcond < 1)) return fail("SensitivityOptions::min_rcond: 0 <= min_rcond < 1");
    if (!(sample_dt >= 0) || !std::isfinite(sample_dt)) return fail("SensitivityOptions::sample_dt: 0 <= sample_dt < inf");
    if (max_samples < 1) return fail("SensitivityOptions::max_samples >= 1");
    if (!(approach_rcond >= 0 && approach_rcond < 1))
      return fail("SensitivityOptions::approach_rcond: 0 <= approach_rcond < 1");
    if (approach_steps < 1) return fail("SensitivityOptions::approach_steps >= 1");
    if (max_solver_iterations < 1) return fail("SensitivityOptions::max_solver_iterations >= 1");
    return true;
  }
};

namespace internal {
/// Whether M has EvalDynamicsJacobian (M::DynamicsJacobian): generated with EvalDynamicsDesign
/// (kHasDynamicsDesign) where no cam law's fourth derivative is needed; no flag says so.
template <class M, class = void>
struct HasDynamicsJacobian : std::false_type {};
template <class M>
struct HasDynamicsJacobian<M, std::void_t<decltype(&M::template DynamicsJacobian<double>)>> : std::true_type {};
}  // namespace internal

/// One sample of a run with sensitivities.
template <class M>
struct SensitivitySample {
  static constexpr int kNq = M::kNq, kNphi = M::kNphi, kNp = M::kNumDesign;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double t = kNaN;
  Eigen::Matrix<double, kNq, 1> q = Eigen::Matrix<double, kNq, 1>::Constant(kNaN);
  Eigen::Matrix<double, kNq, 1> qd = q, qdd = q;
  Eigen::Matrix<double, kNphi, 1> phi = Eigen::Matrix<double, kNphi, 1>::Constant(kNaN);
  /// dq/dp and dqd/dp: S(i, d) = dq_i/dp_d, Sd(i, d) = dqd_i/dp_d (kNq x kNp).
  Eigen::Matrix<double, kNq, kNp> S = Eigen::Matrix<double, kNq, kNp>::Constant(kNaN);
  Eigen::Matrix<double, kNq, kNp> Sd = S;
  double rcond = 1;  ///< 1/cond_1(Phi_phi) (1 for kNphi = 0)
};

struct SensitivitySummary {
  Status status = Status::kNotRun;
  IntegratorSummary integrator;
  double t_end = std::numeric_limits<double>::quiet_NaN();  ///< where the run ended
  int samples = 0;
  int position_failures = 0;  ///< evaluations whose M::Solve failed (steps retried shorter)
  double min_rcond_seen = std::numeric_limits<double>::infinity();
  const char* message = "";

  bool IsSolutionUsable() const { return !IsFailure(status); }
};

inline std::string FormatSummary(const SensitivitySummary& s) {
  char buffer[384];
  std::snprintf(buffer, sizeof(buffer),
                "%s at t = %.9g: %d samples, %d steps, %d rejected, %d rhs evaluations (state and "
                "sensitivities), min 1/cond(Phi_phi) = %.3g%s%s",
                ToString(s.status), s.t_end, s.samples, s.integrator.steps, s.integrator.rejected,
                s.integrator.rhs_evaluations, s.min_rcond_seen, s.message[0] != 0 ? "; " : "",
                s.message);
  return buffer;
}

/**
 * TrajectorySensitivity<M, Method>: the free motion of M with its sensitivities to the design
 * parameters, integrated by Method (Dop853 or Dopri5) on the state
 * y = (q, qd, vec S, vec Sd) (column d of S, then of Sd, for each design parameter d).
 * Initialize() at q0, then Simulate(); or use Derivative() as your integrator's right-hand side.
 */
template <class M, template <int> class Method = Dop853>
class TrajectorySensitivity {
 public:
  static_assert(HasDynamics<M>::value, "TrajectorySensitivity needs a model generated with `dynamics`");
  static_assert(HasDynamicsDesign<M>::value,
                "TrajectorySensitivity needs a model with a `design` section and `dynamics` (M::DynamicsDesign)");
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kNp = M::kNumDesign;
  static constexpr int kN = 2 * kNq * (1 + kNp);
  using Params = typename M::template ParamsT<double>;
  using Coefficients = typename M::template CoefficientsT<double>;
  using Dyn = typename M::template DynamicsT<double>;
  using State = Eigen::Matrix<double, kN, 1>;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using MatQ = Eigen::Matrix<double, kNq, kNq>;
  using MatQP = Eigen::Matrix<double, kNq, kNp>;
  using Modes = std::array<int, M::kNumBlocks>;
  using SampleT = SensitivitySample<M>;
  using Integrator = Method<kN>;
  using Trig = typename mechgen::internal::TrigOf<M>::type;
  /// The Jet of the partial derivatives along (q, qd).
  using Jet = ceres::Jet<double, 2 * kNq>;

  explicit TrajectorySensitivity(const Params& params, const SensitivityOptions& options = SensitivityOptions())
      : p_(params), pj_(params.template Cast<Jet>()), options_(options), integrator_(options.integrator) {}

  const Params& params() const { return p_; }
  const SensitivityOptions& options() const { return options_; }

  /// Assembles at q0 from phi_guess on the given modes: false when it does not assemble.
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess, const Modes& modes = M::kDefaultModes) {
    modes_ = modes;
    q_ref_ = q0;
    phi_ref_ = phi_guess;
    K_ref_.setZero();
    VecPhi phi = phi_guess;
    bool not_assemblable = false;
    if (!internal::SolveOnBranch<M>(p_, q0, &phi, modes_, options_.max_solver_iterations,
                                    options_.solver_tolerance, 0.0, &trig_, &not_assemblable))
      return false;
    Coefficients c;
    internal::CallCoeffs<M>(p_, q0, phi, &c, &trig_);
    phi_ref_ = phi;
    K_ref_ = c.K;
    double rcond = 1;
    internal::ConditioningOf(PhiPhi(c), &rcond, &ref_det_);
    initialized_ = true;
    return true;
  }

  /// Assembles at q0 from the model's assembly guess (kAssemblyPhi, kDefaultModes).
  bool Initialize(const VecQ& q0) {
    VecPhi guess;
    for (int i = 0; i < kNphi; ++i) guess(i) = M::kAssemblyPhi[i];
    return Initialize(q0, guess);
  }

  /**
   * \brief The right-hand side dy at (t, y): (qd, qdd, vec Sd, vec(f_q S + f_qd Sd + f_p)).
   * \return false when the positions do not solve or I is not positive definite.
   */
  bool Derivative(double t, const State& y, State* dy) {
    const VecQ q = y.template head<kNq>();
    const VecQ qd = y.template segment<kNq>(kNq);
    VecPhi phi;
    Coefficients c;
    if (!Configuration(q, &phi, &c)) return false;
    Dyn d;
    internal::CallDynamics<M>(p_, q, phi, qd, t, c, &d, &trig_);
    VecQ qdd;
    Eigen::LLT<MatQ> llt;
    if (!Factorize(d.I, &llt)) return false;
    qdd = llt.solve(d.Q - d.h);
    if (!qdd.allFinite()) return false;

    // f_q, f_qd: I^-1 (dQ - dh - dI qdd)/dx for the 2 kNq directions x = (q, qd).
    const Eigen::Matrix<double, kNq, 2 * kNq> F_x = llt.solve(StateJacobian(t, q, phi, qd, c, d, qdd));

    // f_p: the generated design derivatives at fixed (q, qd).
    typename M::template DesignDerivativesT<double> dc;
    M::template Design<double>(p_, q, phi, &dc);
    typename M::template DynamicsDesignT<double> dd;
    M::template DynamicsDesign<double>(p_, q, phi, qd, t, c, dc, &dd);
    MatQP B = dd.dQ_dp - dd.dh_dp;
    for (int dp = 0; dp < kNp; ++dp) B.col(dp) -= dd.dI_dp.template block<kNq, kNq>(0, kNq * dp) * qdd;
    const MatQP F_p = llt.solve(B);

    const Eigen::Map<const MatQP> S(y.data() + 2 * kNq);
    const Eigen::Map<const MatQP> Sd(y.data() + 2 * kNq + kNq * kNp);
    dy->template head<kNq>() = qd;
    dy->template segment<kNq>(kNq) = qdd;
    Eigen::Map<MatQP> dS(dy->data() + 2 * kNq);
    Eigen::Map<MatQP> dSd(dy->data() + 2 * kNq + kNq * kNp);
    dS = Sd;
    dSd = F_x.template leftCols<kNq>() * S + F_x.template rightCols<kNq>() * Sd + F_p;
    return dy->allFinite();
  }

  /**
   * \brief (dQ - dh - dI qdd)/dx at (t, q, qd) for the 2 kNq directions x = (q_0.., qd_0..), at
   * the positions phi with their coefficients c, dynamics d and accelerations qdd: f_q and f_qd
   * times I. From M::DynamicsJacobian where the model has it (unless options().jet_jacobians),
   * else from Jets of M::Coeffs and M::Dynamics.
   */
  Eigen::Matrix<double, kNq, 2 * kNq> StateJacobian(double t, const VecQ& q, const VecPhi& phi, const VecQ& qd,
                                                    const Coefficients& c, const Dyn& d, const VecQ& qdd) const {
    Eigen::Matrix<double, kNq, 2 * kNq> G;
    if constexpr (internal::HasDynamicsJacobian<M>::value) {
      if (!options_.jet_jacobians) {
        MatQ dQ_dq, dh_dq, dQ_dqd, dh_dqd;
        M::template DynamicsJacobian<double>(p_, q, phi, qd, t, c, &dQ_dq, &dh_dq, &dQ_dqd, &dh_dqd);
        G.template leftCols<kNq>() = dQ_dq - dh_dq;
        G.template rightCols<kNq>() = dQ_dqd - dh_dqd;
        // dI_dq(j, k + kNq l) = dI(j, k)/dq_l.
        for (int l = 0; l < kNq; ++l) G.col(l) -= d.dI_dq.template block<kNq, kNq>(0, kNq * l) * qdd;
        return G;
      }
    }
    (void)d;
    Eigen::Matrix<Jet, kNq, 1> qj, qdj;
    for (int i = 0; i < kNq; ++i) {
      qj(i) = Jet(q(i), i);
      qdj(i) = Jet(qd(i), kNq + i);
    }
    Eigen::Matrix<Jet, kNphi, 1> phij;
    for (int r = 0; r < kNphi; ++r) {
      phij(r) = Jet(phi(r));
      phij(r).v.template head<kNq>() = c.K.row(r).transpose();
    }
    typename M::template CoefficientsT<Jet> cj;
    M::template Coeffs<Jet>(pj_, qj, phij, &cj);
    typename M::template DynamicsT<Jet> dj;
    const Jet tj(t);
    M::template Dynamics<Jet>(pj_, qj, phij, qdj, tj, cj, &dj);
    for (int i = 0; i < kNq; ++i) G.row(i) = (dj.Q(i).v - dj.h(i).v).transpose();
    for (int i = 0; i < kNq; ++i)
      for (int k = 0; k < kNq; ++k) G.row(i) -= dj.I(i, k).v.transpose() * qdd(k);
    return G;
  }

  /// An operator() for the integrator.
  bool operator()(double t, const State& y, State* dy) { return Derivative(t, y, dy); }

  /**
   * \brief Integrates from (t0, q0, qd0), S = Sd = 0, to t_end, handing every sample to
   * observer(const SampleT&) (return false to stop). Initialize() first (at q0).
   * \return summary->IsSolutionUsable().
   */
  template <class Observer>
  bool Simulate(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Observer&& observer,
                SensitivitySummary* summary) {
    *summary = SensitivitySummary();
    position_failures_ = 0;
    approaching_ = 0;
    last_rcond_ = 1;
    std::string error;
    auto refuse = [&](const char* message) {
      summary->status = Status::kInvalidInput;
      summary->message = message;
      summary->t_end = t0;
      return false;
    };
    if (!options_.IsValid(&error) || !(t_end > t0) || !std::isfinite(t_end))
      return refuse("invalid options (or t_end <= t0)");
    if (!initialized_) return refuse("Initialize() not called");
    if (options_.sample_dt > 0) {
      const double n = std::floor((t_end - t0) / options_.sample_dt);
      if (!(n + 2 <= options_.max_samples) || t0 + options_.sample_dt == t0)
        return refuse("the sample grid cannot advance or has more than max_samples samples");
    }
    State y0 = State::Zero();
    y0.template head<kNq>() = q0;
    y0.template segment<kNq>(kNq) = qd0;
    IntegratorStatus s = integrator_.Start(*this, t0, y0, t_end);
    auto finish = [&](Status status, const char* message) {
      summary->status = status;
      summary->message = message;
      summary->integrator = integrator_.summary();
      summary->integrator.status = s;
      summary->position_failures = position_failures_;
      return summary->IsSolutionUsable();
    };
    if (s != IntegratorStatus::kRunning) {
      summary->t_end = t0;
      return finish(Status::kInvalidInput, "the initial state does not evaluate");
    }
    // A sample at (t, y) to the observer: kNotRun to go on, else how the run ends.
    SampleT sample;
    auto emit = [&](double t, const State& y) {
      const Status e = Emit(t, y, &sample, summary);
      if (e != Status::kNotRun) return e;
      return observer(static_cast<const SampleT&>(sample)) ? Status::kNotRun : Status::kStoppedByObserver;
    };
    auto message_of = [](Status e) {
      return e == Status::kDeadPoint ? "1/cond(Phi_phi) fell below min_rcond: a dead point"
             : e == Status::kPositionFailed ? "the positions or the inertia did not evaluate at a sample"
                                            : "";
    };
    Status e = emit(t0, y0);
    if (e != Status::kNotRun) {
      summary->t_end = t0;
      return finish(e, message_of(e));
    }
    long k = 1;  // the next sample is t0 + k sample_dt (sample_dt > 0)
    double t_prev = t0;
    while (s == IntegratorStatus::kRunning) {
      s = integrator_.Step(*this);
      if (s != IntegratorStatus::kRunning && s != IntegratorStatus::kSuccess) {
        summary->t_end = t_prev;
        const bool dead = last_not_assemblable_ || summary->min_rcond_seen < 1e3 * options_.min_rcond;
        return finish(dead ? Status::kDeadPoint : Status::kIntegratorFailed,
                      dead ? "the integrator failed near a dead point (the loop does not close or "
                             "Phi_phi is near singular)"
                           : "the integrator failed");
      }
      const double t = integrator_.t();
      // The accepted state: re-anchor the predictor there and watch its conditioning.
      if (!Anchor(integrator_.y(), summary)) {
        summary->t_end = t;
        return finish(Status::kDeadPoint, approaching_ >= options_.approach_steps
                                             ? "a singular configuration approached: 1/cond(Phi_phi) "
                                               "below approach_rcond and falling for approach_steps steps"
                                             : message_of(Status::kDeadPoint));
      }
      if (options_.sample_dt > 0) {
        for (double t_k = t0 + k * options_.sample_dt; t_k < t && t_k < t_end; t_k = t0 + k * options_.sample_dt) {
          State y;
          e = integrator_.Dense(*this, t_k, &y) ? emit(t_k, y) : Status::kPositionFailed;
          if (e != Status::kNotRun) {
            summary->t_end = t_k;
            return finish(e, message_of(e));
          }
          ++k;
        }
        const bool on_grid = t0 + k * options_.sample_dt == t;
        if (on_grid) ++k;
        e = (s == IntegratorStatus::kSuccess || on_grid) ? emit(t, integrator_.y()) : Status::kNotRun;
      } else {
        e = emit(t, integrator_.y());
      }
      if (e != Status::kNotRun) {
        summary->t_end = t;
        return finish(e, message_of(e));
      }
      t_prev = t;
    }
    summary->t_end = t_end;
    return finish(Status::kSuccess, "");
  }

 private:
  template <class C>
  static auto PhiPhi(const C& c) {
    if constexpr (kNphi > 0) {
      return c.Phi_phi;
    } else {
      (void)c;
      return Eigen::Matrix<double, 0, 0>();
    }
  }

  static bool Factorize(const MatQ& I, Eigen::LLT<MatQ>* llt) {
    if (!I.allFinite()) return false;
    llt->compute(I);
    return llt->info() == Eigen::Success;
  }

  /// The positions and coefficients at q from the predictor of the last accepted state.
  bool Configuration(const VecQ& q, VecPhi* phi, Coefficients* c) {
    *phi = phi_ref_ + K_ref_ * (q - q_ref_);
    bool not_assemblable = false;
    if (!internal::SolveOnBranch<M>(p_, q, phi, modes_, options_.max_solver_iterations,
                                    options_.solver_tolerance, ref_det_, &trig_, &not_assemblable)) {
      last_not_assemblable_ = not_assemblable;
      ++position_failures_;
      return false;
    }
    last_not_assemblable_ = false;
    internal::CallCoeffs<M>(p_, q, *phi, c, &trig_);
    return true;
  }

  /// Makes the accepted state y the predictor's reference; false at a dead point.
  bool Anchor(const State& y, SensitivitySummary* summary) {
    const VecQ q = y.template head<kNq>();
    VecPhi phi;
    Coefficients c;
    if (!Configuration(q, &phi, &c)) return false;
    double rcond = 1, det = 1;
    internal::ConditioningOf(PhiPhi(c), &rcond, &det);
    summary->min_rcond_seen = std::min(summary->min_rcond_seen, rcond);
    if (kNphi > 0 && (rcond < options_.min_rcond || (det > 0) != (ref_det_ > 0))) return false;
    approaching_ = rcond < options_.approach_rcond && rcond < last_rcond_ ? approaching_ + 1 : 0;
    last_rcond_ = rcond;
    if (approaching_ >= options_.approach_steps) return false;
    q_ref_ = q;
    phi_ref_ = phi;
    K_ref_ = c.K;
    ref_det_ = det;
    return true;
  }

  /// The sample at (t, y): kNotRun when it evaluates, else kDeadPoint or kPositionFailed.
  Status Emit(double t, const State& y, SampleT* sample, SensitivitySummary* summary) {
    State dy;
    if (!Derivative(t, y, &dy)) return last_not_assemblable_ ? Status::kDeadPoint : Status::kPositionFailed;
    sample->t = t;
    sample->q = y.template head<kNq>();
    sample->qd = y.template segment<kNq>(kNq);
    sample->qdd = dy.template segment<kNq>(kNq);
    Coefficients c;
    if (!Configuration(sample->q, &sample->phi, &c)) return Status::kPositionFailed;
    double det = 1;
    internal::ConditioningOf(PhiPhi(c), &sample->rcond, &det);
    summary->min_rcond_seen = std::min(summary->min_rcond_seen, sample->rcond);
    if (kNphi > 0 && sample->rcond < options_.min_rcond) return Status::kDeadPoint;
    sample->S = Eigen::Map<const MatQP>(y.data() + 2 * kNq);
    sample->Sd = Eigen::Map<const MatQP>(y.data() + 2 * kNq + kNq * kNp);
    ++summary->samples;
    return Status::kNotRun;
  }

  Params p_;
  typename M::template ParamsT<Jet> pj_;
  SensitivityOptions options_;
  Integrator integrator_;
  Modes modes_ = M::kDefaultModes;
  VecQ q_ref_ = VecQ::Zero();
  VecPhi phi_ref_ = VecPhi::Zero();
  Eigen::Matrix<double, kNphi, kNq> K_ref_ = Eigen::Matrix<double, kNphi, kNq>::Zero();
  double ref_det_ = 0;
  Trig trig_{};
  bool initialized_ = false;
  bool last_not_assemblable_ = false;
  int position_failures_ = 0;
  int approaching_ = 0;  ///< accepted steps in a row with 1/cond < approach_rcond and falling
  double last_rcond_ = 1;
};

}  // namespace mechgen::dynamics
