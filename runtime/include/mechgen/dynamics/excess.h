/**
 * \file dynamics/excess.h
 * The excess-coordinate method (Paul §6.6.2), the baseline the minimal method (forward.h) is
 * compared with, and the differential-equation method of kinematics it generalizes.
 *
 * ExcessDynamics<M, Method>: all coordinates x = (q, phi) (n = kNq + kNphi) and their speeds are
 * integrated, with the constraints as an index-1 DAE (the generated EvalExcess, Model::ExcessT):
 *   [ M       -Phi_x^T ] [ xdd    ]   [ g - h                                 ]
 *   [ Phi_x    0       ] [ lambda ] = [ gamma - 2 alpha Phid - beta^2 Phi     ]
 * (Phid = Phi_x xd), solved by a fixed-size partial-pivoting LU each evaluation. Baumgarte's
 * stabilization (alpha, beta; 0 = none) damps the drift of Phi and Phid; the coordinate
 * projection (ExcessOptions::projection) puts the state back on the constraint manifold after
 * every accepted step: phi from the generated position solver at the integrated q (closed-form
 * blocks exactly), then phid = K qd. The drift |Phi|, |Phid| is reported.
 *
 * It is a system of the one simulator (dynamics/system.h, simulator.h): the event loop steps
 * it, samples it on the grid, projects it after each accepted step (its ProjectEnergy hook),
 * and watches its witnesses (the speed's zero and the user's event; its samples carry no
 * conditioning of Phi_phi, so no dead point is watched).
 *
 * KinematicsByIntegration<M, Method>: Paul's differential-equation method of kinematics,
 * dphi/dq = K(q, phi) integrated in q (one-DOF models; kNq > 1 along a direction) instead of
 * solving the positions; its drift against the position solver is measured at every sample.
 *
 * Nothing allocates (fixed-size Eigen); nothing throws.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/position_tracker.h"
#include "mechgen/dynamics/simulator.h"

namespace mechgen::dynamics {

struct ExcessOptions {
  IntegratorOptions integrator;
  /// Baumgarte's stabilization: gamma - 2 alpha Phid - beta^2 Phi (1/s, 1/s). 0: none.
  double alpha = 0;
  double beta = 0;
  /// Coordinate projection after each accepted step (phi solved at q, phid = K qd).
  bool projection = false;
  /// Samples every sample_dt (0: every accepted step).
  double sample_dt = 0;
  /// Stop where the first input's speed changes sign (Event::kSpeedZero).
  bool stop_at_speed_zero = false;
  /// Events are located to |t - t_event| <= event_tolerance (s).
  double event_tolerance = kEventTolerance;
};

struct ExcessSummary {
  IntegratorSummary integrator;
  double max_Phi = 0;    ///< max over the samples of ||Phi||_inf
  double max_Phid = 0;   ///< max over the samples of ||Phi_x xd||_inf
  int projections = 0;
  int failed_projections = 0;
  bool IsSolutionUsable() const { return integrator.IsSolutionUsable(); }
  // What the simulator reports of every run (simulator.h).
  Status status = Status::kNotRun;
  Event event = Event::kNone;
  double t_end = 0;
  int samples = 0;
  int position_failures = 0;
  double min_rcond_seen = 1;
  double max_energy_error = 0;  ///< max |E - E0| over the samples (no work of loads here)
  SteadyStateSummary steady;
  std::string message;
};

namespace internal {
/// core/model_traits.h: the one place that says what a model has.
template <class M>
using HasExcess = mechgen::HasExcess<M>;
}  // namespace internal

template <class M>
struct ExcessSample {
  static constexpr int kN = M::kNq + M::kNphi;
  double t = 0;
  Eigen::Matrix<double, kN, 1> x, xd;
  /// x's parts, as the simulator's witnesses read them.
  Eigen::Matrix<double, M::kNq, 1> q, qd;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  double T = 0, V = 0, E = 0;
  double Phi_norm = 0, Phid_norm = 0;
  double rcond = 1, det = 1;  ///< (not evaluated: no dead point is watched)
};

template <class M, template <int> class Method = Dopri5>
class ExcessDynamics {
 public:
  static_assert(internal::HasExcess<M>::value,
                "ExcessDynamics needs Model::ExcessT / Model::ExcessDynamics (EvalExcess)");
  static constexpr int kNq = M::kNq, kNphi = M::kNphi, kNc = M::kNc;
  static constexpr int kN = kNq + kNphi;
  static constexpr int kState = 2 * kN;
  using Params = typename M::template ParamsT<double>;
  using Ex = typename M::template ExcessT<double>;
  using State = Eigen::Matrix<double, kState, 1>;
  using VecN = Eigen::Matrix<double, kN, 1>;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using Integrator = Method<kState>;
  using SampleT = ExcessSample<M>;

  ExcessDynamics(const Params& p, const ExcessOptions& options = ExcessOptions())
      : p_(p), options_(options), integrator_(options.integrator), tracker_(M(), 20, 0.0) {}

  /// dy = (xd, xdd) at y = (x, xd).
  bool Derivative(double t, const State& y, State* dy) {
    Ex e;
    Eval(t, y, &e);
    constexpr int kA = kN + kNc;
    Eigen::Matrix<double, kA, kA> A = Eigen::Matrix<double, kA, kA>::Zero();
    Eigen::Matrix<double, kA, 1> b;
    A.template topLeftCorner<kN, kN>() = e.M;
    A.template topRightCorner<kN, kNc>() = -e.Phi_x.transpose();
    A.template bottomLeftCorner<kNc, kN>() = e.Phi_x;
    const VecN xd = y.template segment<kN>(kN);
    b.template head<kN>() = e.g - e.h;
    b.template tail<kNc>() = e.gamma - 2 * options_.alpha * (e.Phi_x * xd) -
                             options_.beta * options_.beta * e.Phi;
    const Eigen::PartialPivLU<Eigen::Matrix<double, kA, kA>> lu(A);
    const Eigen::Matrix<double, kA, 1> z = lu.solve(b);
    if (!z.allFinite()) return false;
    dy->template head<kN>() = xd;
    dy->template segment<kN>(kN) = z.template head<kN>();
    return true;
  }

  /**
   * \brief Integrates from (q0, qd0) (phi solved at q0 from phi_guess on M::kDefaultModes,
   * phid0 = K qd0: a consistent start) to t_end by the one simulator; observer(sample) at
   * every sample (false stops), user_event(t, q, qd, phi) a stop condition (NoUserEvent).
   */
  template <class Observer, class UserEvent>
  bool Simulate(double t0, const VecQ& q0, const VecQ& qd0, const VecPhi& phi_guess, double t_end,
                Observer&& observer, UserEvent&& user_event, ExcessSummary* summary, SampleT* last = nullptr) {
    *summary = ExcessSummary();
    State y0;
    VecPhi phi = phi_guess, phid;
    if (!(t_end > t0) || !Consistent(q0, qd0, &phi, &phid)) {
      summary->status = Status::kInvalidInput;
      summary->t_end = t0;
      summary->message = "t_end <= t0, or the initial state does not assemble";
      return false;
    }
    y0.template head<kNq>() = q0;
    y0.template segment<kNphi>(kNq) = phi;
    y0.template segment<kNq>(kN) = qd0;
    y0.template segment<kNphi>(kN + kNq) = phid;
    integrator_.set_options(options_.integrator);
    internal::EventSettings events;
    events.min_rcond = 0;  // (no conditioning evaluated)
    events.event_tolerance = options_.event_tolerance;
    events.sample_dt = options_.sample_dt;
    events.stop_at_speed_zero = options_.stop_at_speed_zero;
    events.energy_projection = options_.projection;  // the coordinate projection
    failed_projections_ = 0;
    const bool ok = internal::EventLoop::Run(this, events, t0, y0, t_end, observer, user_event, summary, last);
    summary->failed_projections = failed_projections_;
    return ok;
  }
  /// Simulate() without a user event.
  template <class Observer>
  bool Simulate(double t0, const VecQ& q0, const VecQ& qd0, const VecPhi& phi_guess, double t_end,
                Observer&& observer, ExcessSummary* summary, SampleT* last = nullptr) {
    NoUserEvent none;
    return Simulate(t0, q0, qd0, phi_guess, t_end, observer, none, summary, last);
  }

  const Integrator& integrator() const { return integrator_; }

 private:
  void Eval(double t, const State& y, Ex* e) const {
    const VecQ q = y.template head<kNq>();
    const VecPhi phi = y.template segment<kNphi>(kNq);
    const VecQ qd = y.template segment<kNq>(kN);
    const VecPhi phid = y.template segment<kNphi>(kN + kNq);
    M::template ExcessDynamics<double>(p_, q, phi, qd, phid, t, e);
  }

  void Sample(double t, const State& y, SampleT* s) const {
    Ex e;
    Eval(t, y, &e);
    s->t = t;
    s->x = y.template head<kN>();
    s->xd = y.template segment<kN>(kN);
    s->q = y.template head<kNq>();
    s->phi = y.template segment<kNphi>(kNq);
    s->qd = y.template segment<kNq>(kN);
    s->T = e.T;
    s->V = e.V;
    s->E = e.T + e.V;
    s->Phi_norm = e.Phi.cwiseAbs().maxCoeff();
    s->Phid_norm = (e.Phi_x * s->xd).cwiseAbs().maxCoeff();
  }

  // ---- the system's hooks (dynamics/system.h) ----
  friend struct internal::EventLoop;
  template <class, class, class, class>
  friend class internal::EventLoopRun;
  static constexpr bool kCanProjectEnergy = true;  ///< (the coordinate projection)
  static constexpr bool kHasSwitches = false;
  using SwitchModes = std::array<int, 0>;

  static void Record(const SampleT& s, ExcessSummary* summary) {
    summary->max_Phi = std::max(summary->max_Phi, s.Phi_norm);
    summary->max_Phid = std::max(summary->max_Phid, s.Phid_norm);
  }
  static double Balance(const SampleT& s) { return s.E; }
  static void OnDeadPoint(SampleT*) {}
  void EndRun() {}
  bool Evaluate(double t, const State& y, SampleT* s) const {
    Sample(t, y, s);
    return true;
  }
  bool Accept(double t, const State& y, SampleT* cur) const { return Evaluate(t, y, cur); }
  /// The coordinate projection of the accepted state (ExcessOptions::projection): phi solved at
  /// the integrated q, phid = K qd, the integrator reset there; *cur the sample there.
  template <class F>
  bool ProjectEnergy(F& f, double /*E0*/, SampleT* cur) {
    State y = integrator_.y();
    VecQ q = y.template head<kNq>();
    VecQ qd = y.template segment<kNq>(kN);
    VecPhi ph = y.template segment<kNphi>(kNq), phd;
    if (!Consistent(q, qd, &ph, &phd)) {
      ++failed_projections_;
      return false;
    }
    y.template segment<kNphi>(kNq) = ph;
    y.template segment<kNphi>(kN + kNq) = phd;
    integrator_.Reset(f, y);
    Sample(cur->t, integrator_.y(), cur);
    return true;
  }

  /// phi solved at q (the one position tracker's solve, from *phi: the integrated phi, on the
  /// default modes, either branch), phid = K qd.
  bool Consistent(const VecQ& q, const VecQ& qd, VecPhi* phi, VecPhi* phid) {
    bool not_assemblable = false;  // (not the event loop's flag: a failed projection is counted)
    if (!tracker_.SolveAt(M(), p_, q, phi, &not_assemblable)) return false;
    typename M::template CoefficientsT<double> c;
    M::template Coeffs<double>(p_, q, *phi, &c);
    *phid = c.K * qd;
    return phid->allFinite();
  }

  Params p_;
  ExcessOptions options_;
  Integrator integrator_;
  PositionTracker<M> tracker_;  ///< the projection's solves (M::kDefaultModes, 20 iterations)
  int position_failures_ = 0;
  bool last_solve_not_assemblable_ = false, singular_inertia_ = false;
  int failed_projections_ = 0;
};

/**
 * Paul's differential-equation method of kinematics: phi(q) by integrating dphi/dq = K(q, phi)
 * from (q0, phi0) (kNq = 1), each sample compared with the generated position solver.
 */
template <class M, template <int> class Method = Dopri5>
class KinematicsByIntegration {
 public:
  static_assert(M::kNq == 1, "one input (integrate along q)");
  static constexpr int kNphi = M::kNphi;
  using Params = typename M::template ParamsT<double>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using Vec1 = Eigen::Matrix<double, 1, 1>;

  struct Summary {
    IntegratorSummary integrator;
    double max_drift = 0;  ///< max ||phi_integrated - phi_solved||_inf over the samples
    double max_Phi = 0;    ///< max ||Phi(q, phi_integrated)||_inf
  };

  KinematicsByIntegration(const Params& p, const IntegratorOptions& options = IntegratorOptions())
      : p_(p), integrator_(options) {}

  /// phi0 must solve Phi(q0, phi0) = 0 (on M::kDefaultModes). observer(q, phi_int, phi_solved).
  template <class Observer>
  bool Run(double q0, const VecPhi& phi0, double q1, int samples, Observer&& observer,
           Summary* summary) {
    *summary = Summary();
    auto f = [this](double q, const VecPhi& phi, VecPhi* dphi) {
      typename M::template CoefficientsT<double> c;
      M::template Coeffs<double>(p_, Vec1(q), phi, &c);
      *dphi = c.K.col(0);
      return true;
    };
    VecPhi phi_solved = phi0;
    IntegratorStatus is = integrator_.Start(f, q0, phi0, q1);
    for (int k = 1; k <= samples && (is == IntegratorStatus::kRunning ||
                                     is == IntegratorStatus::kSuccess);
         ++k) {
      const double q = q0 + (q1 - q0) * k / samples;
      while (is == IntegratorStatus::kRunning && (q1 > q0 ? integrator_.t() < q : integrator_.t() > q))
        is = integrator_.Step(f);
      if (is != IntegratorStatus::kRunning && is != IntegratorStatus::kSuccess) break;
      VecPhi phi;
      if (!integrator_.Dense(f, q, &phi)) return false;
      const auto report = M::template Solve<double>(p_, Vec1(q), &phi_solved, M::kDefaultModes, 20, 0.0);
      if (report.status != decltype(report.status)::kConverged) return false;
      Eigen::Matrix<double, M::kNc, 1> Phi;
      M::template Phi<double>(p_, Vec1(q), phi, &Phi);
      summary->max_drift = std::max(summary->max_drift, (phi - phi_solved).cwiseAbs().maxCoeff());
      summary->max_Phi = std::max(summary->max_Phi, Phi.cwiseAbs().maxCoeff());
      observer(q, phi, phi_solved);
    }
    summary->integrator = integrator_.summary();
    return summary->integrator.IsSolutionUsable() || is == IntegratorStatus::kSuccess;
  }

 private:
  Params p_;
  Method<kNphi> integrator_;
};

}  // namespace mechgen::dynamics
