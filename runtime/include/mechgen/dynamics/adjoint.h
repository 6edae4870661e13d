/**
 * \file dynamics/adjoint.h
 * Adjoint sensitivities (issue 46): the gradient dG/dp of one scalar of a free run,
 *
 *     G = g(t_end, q(t_end), qd(t_end); p) + integral over [t0, t_end] of r(t, q, qd; p) dt,
 *
 * with respect to all the design parameters p (M::kDesignNames), without the N columns of
 * dq/dp: a forward run of the state alone, stored, then one backward run of the adjoint
 * equations over it.
 *
 * The method is the discrete adjoint of dynamics/sensitivity.h's staggered method
 * (SensitivityMethod::kStaggered): the forward run is its state run (Method<2 kNq> with the
 * state's own step and error test; dead points and the predictor as there), keeping the state
 * at the S Lobatto nodes of every accepted step (S = Nodes, 6 by default as there; the
 * interior ones from the dense output: 2 S kNq + 2 doubles a step, the only storage; it
 * allocates, as CVODES' checkpoints do). Over
 * each step the forward sensitivities are one linear map (S0, Sd0, f_p at the nodes) ->
 * (S1, Sd1) (TrajectorySensitivity::CollocationStep); the backward run applies its transpose,
 * step by step from t_end: with mu_S, mu_V the adjoints of S and Sd at the step's end (at
 * t_end: dg/dq, dg/dqd) and the integral by the same Lobatto quadrature at the same nodes
 * (sum over the steps of h sum_j b_j r(t_j, x_j), order 2 S - 2), with e = S - 1 the last node,
 *
 *     nu_k   = h a_ek mu_S + [k = e] mu_V + h b_k r_qd,k + h^2 sum_j b_j a_jk r_q,j   (k = 0..e)
 *     w      = A^-T (nu_1 .. nu_e)                 (A the step's collocation matrix)
 *     lambda_j = h sum_{i=1..e} a_ij w_i           (the adjoint of Sd' at node j)
 *     mu_S  <- mu_S + h sum_j b_j r_q,j + sum_j f_q,j^T lambda_j
 *     mu_V  <- nu_0 + sum_i (1 - C0_i)^T w_i
 *     dG/dp += sum_j lambda_j^T f_p,j + h sum_j b_j r_p,j     (and dg/dp at t_end)
 *
 * so dG/dp equals, to rounding, what the forward sensitivities of the same steps give
 * (g_q S(t_end) + g_qd Sd(t_end) + g_p, and the quadrature of r_q S + r_qd Sd + r_p); at
 * t0, mu_S and mu_V are dG/dq0 and dG/dqd0.
 *
 * Cost: one run of the state (the steps of one simulation, with S - 2 dense-output evaluations
 * a step) and, backward, S - 1 evaluations of the partials a step (f, f_q and f_qd:
 * TrajectorySensitivity::Partials without f_p) and one LU of size (S - 1) kNq. f_p is never
 * formed: lambda_j^T f_p,j = mu^T (dQ/dp - dh/dp - (dI/dp) qdd) with mu = I^-1 lambda_j
 * (TrajectorySensitivity::DesignProduct), by the generated EvalDynamicsDesignProduct, a
 * reverse mode (symbolic/design.h, DesignDynamicsProduct: one backward sweep over the dynamics,
 * one over K, L from (q, phi, p), then phi's adjoint dotted with dphi/dp), so that only
 * dphi/dp (kNphi x N) and N dot products depend on N. A model without it (the dynamics
 * program not straight-line) contracts the forward mode's f_p (EvalDesignDerivatives,
 * EvalDynamicsDesign: all N columns) instead. Measured (bench/design/run.sh): 2.6 simulations
 * on the massive four-bar (N = 6), 3.4 on the five-bar (N = 13), where the forward mode's f_p
 * took 3.2 and 5.2.
 *
 * Not here: the sensitivity of the run's end time (t_end fixed), events and dead points
 * inside the run (a dead point ends the forward run with its status and no gradient).
 */
#pragma once

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "mechgen/dynamics/sensitivity.h"

namespace mechgen::dynamics {

struct AdjointSummary {
  Status status = Status::kNotRun;
  IntegratorSummary integrator;  ///< the forward run of the state
  double t_end = std::numeric_limits<double>::quiet_NaN();  ///< where the forward run ended
  int steps = 0;                  ///< steps stored by the forward run (and run backward)
  int partial_evaluations = 0;    ///< of f_q, f_qd, f_p in the backward run
  double min_rcond_seen = std::numeric_limits<double>::infinity();
  const char* message = "";

  bool IsSolutionUsable() const { return status == Status::kSuccess; }
};

inline std::string FormatSummary(const AdjointSummary& s) {
  char buffer[320];
  std::snprintf(buffer, sizeof(buffer),
                "%s at t = %.9g: %d steps, %d rejected, %d rhs evaluations forward, %d of the partials "
                "backward, min 1/cond(Phi_phi) = %.3g%s%s",
                ToString(s.status), s.t_end, s.steps, s.integrator.rejected, s.integrator.rhs_evaluations,
                s.partial_evaluations, s.min_rcond_seen, s.message[0] != 0 ? "; " : "", s.message);
  return buffer;
}

/**
 * AdjointSensitivity<M, Method>: dG/dp of a scalar G of the free motion of M (see the file
 * comment). Initialize() at q0, then Gradient().
 */
template <class M, template <int> class Method = Dop853, int Nodes = 6>
class AdjointSensitivity {
 public:
  using Forward = TrajectorySensitivity<M, Method, Nodes>;
  using Calls = typename Forward::Calls;
  static constexpr int kNq = Forward::kNq;
  static constexpr int kNp = Forward::kNp;
  static constexpr int kNodes = Forward::kNodes;
  static constexpr int kNc = Forward::kNc;
  using Params = typename Forward::Params;
  using VecQ = typename Forward::VecQ;
  using VecPhi = typename Forward::VecPhi;
  using MatQ = typename Forward::MatQ;
  using StateX = typename Forward::StateX;
  using Modes = typename Forward::Modes;
  using Partial = typename Forward::Partial;
  using RowP = typename Forward::RowP;
  using MatC = typename Forward::MatC;
  using MatCQ = typename Forward::MatCQ;
  using VecC = typename Forward::VecC;

  /// A part of the scalar at one (t, q, qd): its value and its partial derivatives along q, qd
  /// and p (the explicit dependence on p only; zero where there is none).
  struct Value {
    double v = 0;
    VecQ d_q = internal::ZeroOf<VecQ>(0, 1), d_qd = d_q;  ///< (the view's: sized by the callable)
    RowP d_p = internal::ZeroOf<RowP>(1, 0);
  };

  /// No integral (r = 0), or no final term (g = 0): a callable for Gradient().
  static bool Zero(double, const VecQ&, const VecQ&, Value* out) {
    *out = Value();
    return true;
  }

  /// options.sample_dt and options.method are not read (the run is the staggered state run).
  template <class X = M, std::enable_if_t<!ModelCalls<X>::kView, int> = 0>
  explicit AdjointSensitivity(const Params& params, const SensitivityOptions& options = SensitivityOptions())
      : forward_(M(), params, StateRunOptions(options)) {}
  /// For any model (a view: Forward::SupportedBy(model) first).
  AdjointSensitivity(const M& model, const Params& params, const SensitivityOptions& options)
      : forward_(model, params, StateRunOptions(options)) {}

  bool Initialize(const VecQ& q0) { return forward_.Initialize(q0); }
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess) { return forward_.Initialize(q0, phi_guess); }
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess, const Modes& modes) {
    return forward_.Initialize(q0, phi_guess, modes);
  }

  const Forward& forward() const { return forward_; }

  /**
   * \brief G = terminal(t_end, q, qd) + the integral of integrand(t, q, qd) over [t0, t_end]
   * along the free run from (t0, q0, qd0), and its gradient dG/dp. terminal and integrand: callables
   * bool(double t, const VecQ& q, const VecQ& qd, Value* out) (false: not evaluable there).
   * Initialize() first (at q0).
   * \param[out] G, dG_dp  The scalar and its gradient (NaN unless the run succeeds).
   * \param[out] dG_dq0, dG_dqd0  Its gradient with respect to q0 and qd0 (may be nullptr).
   * \return summary->IsSolutionUsable().
   */
  template <class Terminal, class Integrand>
  bool Gradient(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Terminal&& terminal, Integrand&& integrand,
                double* G, RowP* dG_dp, AdjointSummary* summary, VecQ* dG_dq0 = nullptr, VecQ* dG_dqd0 = nullptr) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    *summary = AdjointSummary();
    *G = kNaN;
    const int nq = forward_.nq_, np = forward_.np_;
    if constexpr (Forward::kView) {
      dG_dp->setConstant(1, np, kNaN);
      if (dG_dq0 != nullptr) dG_dq0->setConstant(nq, kNaN);
      if (dG_dqd0 != nullptr) dG_dqd0->setConstant(nq, kNaN);
    } else {
      (void)nq, (void)np;
      dG_dp->setConstant(kNaN);
      if (dG_dq0 != nullptr) dG_dq0->setConstant(kNaN);
      if (dG_dqd0 != nullptr) dG_dqd0->setConstant(kNaN);
    }
    auto finish = [&](Status status, const char* message) {
      summary->status = status;
      summary->message = message;
      summary->partial_evaluations = forward_.partial_evaluations_;
      return summary->IsSolutionUsable();
    };
    std::string error;
    if (!forward_.options_.IsValid(&error) || !(t_end > t0) || !std::isfinite(t_end) || !std::isfinite(t0)) {
      summary->t_end = t0;
      return finish(Status::kInvalidInput, "invalid options (or t_end <= t0)");
    }
    if (!forward_.initialized_) {
      summary->t_end = t0;
      return finish(Status::kInvalidInput, "Initialize() not called");
    }
    // Forward: the state alone, its nodes kept.
    const char* message = "";
    const Status forward_status = RecordRun(t0, q0, qd0, t_end, summary, &message);
    if (forward_status != Status::kSuccess) return finish(forward_status, message);

    // Backward: the transposed collocation steps from t_end (the predictor is anchored there).
    Value end_value;
    const StepRecord& last = steps_.back();
    const VecQ q_end = last.x[kNodes - 1].template head<kNq>(nq),
               qd_end = last.x[kNodes - 1].template segment<kNq>(nq, nq);
    if (!terminal(last.tb, q_end, qd_end, &end_value) || !std::isfinite(end_value.v))
      return finish(Status::kInvalidInput, "the final term does not evaluate at t_end");
    Backward b;
    b.value = end_value.v;
    b.mu_S = end_value.d_q;
    b.mu_V = end_value.d_qd;
    b.gradient = end_value.d_p;
    for (int s = static_cast<int>(steps_.size()) - 1; s >= 0; --s) {
      const Status status = BackwardStep(steps_[s], s + 1 < static_cast<int>(steps_.size()), integrand, &b, &message);
      if (status != Status::kSuccess) return finish(status, message);
    }
    const double value = b.value;
    const RowP gradient = b.gradient;
    const VecQ mu_S = b.mu_S, mu_V = b.mu_V;
    *G = value;
    *dG_dp = gradient;
    if (dG_dq0 != nullptr) *dG_dq0 = mu_S;
    if (dG_dqd0 != nullptr) *dG_dqd0 = mu_V;
    return finish(Status::kSuccess, "");
  }

 private:
  struct StepRecord {
    double ta = 0, tb = 0;
    StateX x[kNodes];
  };

  /// What the backward run carries from step to step: the adjoints of (S, Sd) at the later
  /// step's start, the scalar and its gradient so far, and the partials at the nodes of the step
  /// just done (its first node is the earlier step's last: the same (t, q, qd)).
  struct Backward {
    VecQ mu_S, mu_V;
    double value = 0;
    RowP gradient;
    Partial n[kNodes];
    typename Forward::NodeKeep keep[kNodes];
  };

  /// The forward run's per-step work (StaggeredSystem's OnStep): the step's nodes kept.
  struct Keep {
    AdjointSensitivity* self;
    bool operator()(double ta, double tb, const StateX* x, typename Forward::SampleT*) {
      StepRecord record;
      record.ta = ta;
      record.tb = tb;
      for (int j = 0; j < kNodes; ++j) record.x[j] = x[j];
      self->steps_.push_back(record);
      return true;
    }
  };

  /// The forward run of the state alone by the event loop (the staggered method's system,
  /// internal::StaggeredSystem, no sample grid), each accepted step's nodes kept in steps_;
  /// the summary's integrator, t_end, min_rcond_seen and steps filled.
  Status RecordRun(double t0, const VecQ& q0, const VecQ& qd0, double t_end, AdjointSummary* summary,
                   const char** message) {
    forward_.BeginRun();
    steps_.clear();
    Keep keep{this};
    const StateX x0 = forward_.StateOf(q0, qd0);
    internal::StaggeredSystem<Forward, Keep> system(&forward_, t0, x0, keep);
    SensitivitySummary run;
    auto observer = [](const typename Forward::SampleT&) { return true; };
    forward_.RunSystem(&system, t0, x0, t_end, true, observer, &run);
    *message = run.message;
    summary->integrator = run.integrator;
    summary->t_end = run.t_end;
    summary->min_rcond_seen = run.min_rcond_seen;
    summary->steps = static_cast<int>(steps_.size());
    if (run.status != Status::kSuccess || steps_.empty())
      return run.status == Status::kSuccess ? Status::kIntegratorFailed : run.status;
    forward_.partial_evaluations_ = 0;  // (the backward run's are counted)
    return Status::kSuccess;
  }

  /// One transposed collocation step, from its end (b's adjoints there) to its start.
  /// has_later: a later step was done before it (its first node's partials are this one's last).
  template <class Integrand>
  Status BackwardStep(const StepRecord& step, bool has_later, Integrand& integrand, Backward* b, const char** message) {
    const auto& a = forward_.lob_.a;
    Partial* const n = b->n;
    typename Forward::NodeKeep* const keep = b->keep;
    Value r[kNodes];
    const double h = step.tb - step.ta;
    const int nq = forward_.nq_;
    for (int j = kNodes - 1; j >= 0; --j) {
      const double t = j == kNodes - 1 ? step.tb : j == 0 ? step.ta : step.ta + forward_.lob_.c[j] * h;
      const VecQ q = step.x[j].template head<kNq>(nq), qd = step.x[j].template segment<kNq>(nq, nq);
      if (j == kNodes - 1 && has_later) {
        n[j] = n[0];  // the later step's first node: the same (t, q, qd)
        forward_.CopyKeep(keep[0], &keep[j]);
      } else {
        if (!forward_.Partials(t, q, qd, false, &n[j], &keep[j])) {
          *message = "the partials did not evaluate at a stored node of the backward run";
          return forward_.last_not_assemblable_ ? Status::kDeadPoint : Status::kPositionFailed;
        }
        forward_.Reanchor(n[j]);
      }
      if (!integrand(t, q, qd, &r[j]) || !std::isfinite(r[j].v)) {
        *message = "the integrand does not evaluate at a node";
        return Status::kInvalidInput;
      }
    }
    // nu_k, k = 0..kNodes-1: what (S, Sd) at the nodes carry into G through S1, Sd1 and the quadrature.
    VecQ nu[kNodes];
    VecQ r_q_sum = internal::ZeroOf<VecQ>(nq, 1);
    for (int k = 0; k < kNodes; ++k) {
      nu[k] = (h * a(kNodes - 1, k)) * b->mu_S + (h * a(kNodes - 1, k)) * r[k].d_qd;
      if (k == kNodes - 1) nu[k] += b->mu_V;
      for (int j = 1; j < kNodes; ++j) nu[k] += (h * h * a(kNodes - 1, j) * a(j, k)) * r[j].d_q;
      b->value += h * a(kNodes - 1, k) * r[k].v;
      b->gradient += (h * a(kNodes - 1, k)) * r[k].d_p;
      r_q_sum += (h * a(kNodes - 1, k)) * r[k].d_q;
    }
    MatC A;
    MatCQ C0;
    forward_.CollocationMatrix(h, n, &A, &C0);
    VecC w = Sized<VecC>((kNodes - 1) * nq);
    for (int i = 1; i < kNodes; ++i) w.template segment<kNq>(nq * (i - 1), nq) = nu[i];
    if (!internal::SolveSmall(MatC(A.transpose()), &w)) {
      *message = "the transposed collocation matrix is singular";
      return Status::kIntegratorFailed;
    }
    VecQ new_S = b->mu_S + r_q_sum;
    VecQ new_V = nu[0];
    for (int i = 1; i < kNodes; ++i)
      new_V += w.template segment<kNq>(nq * (i - 1), nq) -
               Times(C0.template block<kNq, kNq>(nq * (i - 1), 0, nq, nq).transpose(),
                     w.template segment<kNq>(nq * (i - 1), nq));
    for (int j = 0; j < kNodes; ++j) {
      VecQ lambda = internal::ZeroOf<VecQ>(nq, 1);
      for (int i = 1; i < kNodes; ++i) lambda += (h * a(i, j)) * w.template segment<kNq>(nq * (i - 1), nq);
      new_S += Times(n[j].F_q().transpose(), lambda);
      RowP product;
      if (!forward_.DesignProduct(n[j], keep[j], lambda, &product)) {
        *message = "lambda^T f_p is not finite at a node of the backward run";
        return Status::kIntegratorFailed;
      }
      b->gradient += product;
    }
    b->mu_S = new_S;
    b->mu_V = new_V;
    if (!b->mu_S.allFinite() || !b->mu_V.allFinite() || !b->gradient.allFinite()) {
      *message = "the backward run is not finite";
      return Status::kIntegratorFailed;
    }
    return Status::kSuccess;
  }

  static SensitivityOptions StateRunOptions(SensitivityOptions options) {
    options.sample_dt = 0;
    options.method = SensitivityMethod::kStaggered;
    return options;
  }

  Forward forward_;
  std::vector<StepRecord> steps_;
};

}  // namespace mechgen::dynamics
