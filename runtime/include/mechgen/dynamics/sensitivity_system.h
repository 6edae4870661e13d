/**
 * \file dynamics/sensitivity_system.h
 * The trajectory sensitivities' runs as systems of the one event loop (issue 46;
 * dynamics/system.h, simulator.h): the loop steps them, samples them and watches their
 * dead-point witness as it does the free, driven and excess-coordinate simulations.
 *
 *  - StaggeredSystem<TS, OnStep>: the state x = (q, qd) alone, by TS's state integrator with
 *    its own step and error test, every sample time a step's end
 *    (EventSettings::steps_end_at_samples). At each accepted step [ta, tb]: the configuration
 *    at tb solved from the last accepted one's predictor, its conditioning the witness's; then,
 *    unless the witness will end the run there, tb made the predictor's reference and
 *    OnStep(ta, tb, x, sample) run over the step's collocation nodes x[0..kNodes-1] (x[0] and
 *    x[kNodes-1] the step's ends, the others its dense output): TS's collocation (the forward
 *    sensitivities S, Sd at tb in the sample) or the adjoint's record of the nodes
 *    (adjoint.h).
 *  - SimultaneousSystem<TS>: y = (q, qd, vec S, vec Sd) by TS's integrator, S and Sd in the
 *    error test; its samples between steps from the dense output, as the free simulation's.
 *
 * At a dead point the loop locates the witness's root on the dense output and hands out the
 * sample there with S and Sd withheld (NaN: near a singular Phi_phi dq/dp grows like
 * 1/sigma_min, a status and never a number), the run ending with Status::kDeadPoint. S and Sd
 * are known at t0 (zero) and at the steps' ends; a sample the loop evaluates elsewhere (at an
 * event) has them NaN.
 *
 * Why an accepted step can fail (Accept() returns false, the loop ends the run): the
 * positions at its end, the partials at a node or the collocation's solve; failure() says
 * which, read by TS after the run (the loop itself says "the positions failed").
 */
#pragma once

#include <array>
#include <limits>

#include "mechgen/dynamics/simulator.h"
#include "mechgen/dynamics/witness/dead_point.h"
#include "mechgen/dynamics/witness/steady_state.h"

namespace mechgen::dynamics::internal {

/// What the event loop writes of a sensitivity run: the run's summary (Base) and the loop's
/// figures that such a run leaves at their start (no energy integral, no steady state).
template <class Base>
struct SensitivityLoopSummary : Base {
  double max_energy_error = 0;
  SteadyStateSummary steady;
};

/// The hooks both sensitivity systems share (dynamics/system.h): no switches, no energy, the
/// accepted configuration and why a step failed.
template <class TS>
class SensitivitySystemBase {
 public:
  static constexpr int kNq = TS::kNq, kNphi = TS::kNphi;
  static constexpr bool kHasSwitches = false, kCanProjectEnergy = false;
  using SwitchModes = std::array<int, 0>;
  using SampleT = typename TS::SampleT;
  using VecQ = typename TS::VecQ;

  explicit SensitivitySystemBase(TS* ts)
      : ts_(ts),
        position_failures_(ts->position_failures_),
        last_solve_not_assemblable_(ts->last_not_assemblable_),
        prev_det_(ts->tracker_.ref_det()) {}

  int Nq() const { return ts_->nq_; }
  /// How an accepted step failed (Status::kNotRun: none did) and why.
  Status failure() const { return failure_; }
  const char* failure_message() const { return failure_message_; }

  static double Balance(const SampleT&) { return 0; }  ///< (no energy integral here)
  template <class Summary>
  static void Record(const SampleT&, Summary*) {}
  /// A sample at a singular configuration: S and Sd withheld.
  void OnDeadPoint(SampleT* s) const { FillS(s, std::numeric_limits<double>::quiet_NaN()); }
  /// S and Sd of *s all `value`, sized nq x np (the view's bounded ones start empty).
  void FillS(SampleT* s, double value) const {
    s->S.setConstant(ts_->nq_, ts_->np_, value);
    s->Sd.setConstant(ts_->nq_, ts_->np_, value);
  }
  void EndRun() {}

  TS* ts_;
  int& position_failures_;
  bool& last_solve_not_assemblable_;
  bool singular_inertia_ = false;  ///< (SolveInertia's failure is the right-hand side's)

 protected:
  /// The accepted configuration at q into *s (t, q, qd, phi, rcond, det; S, Sd and qdd NaN):
  /// solved from the last accepted one's predictor; unless singular by the dead-point
  /// witness's rule (*singular: the loop's witness ends the run at this step), made the
  /// predictor's reference and TS::Partials()' anchor. \return false (failure_ set) when the
  /// positions do not solve.
  bool AcceptConfiguration(double t, const VecQ& q, const VecQ& qd, SampleT* s, bool* singular) {
    s->t = t;
    s->q = q;
    s->qd = qd;
    s->qdd.setConstant(ts_->nq_, std::numeric_limits<double>::quiet_NaN());
    FillS(s, std::numeric_limits<double>::quiet_NaN());
    typename TS::Coefficients c;
    if (!ts_->Configuration(q, &s->phi, &c))
      return Fail(Status::kDeadPoint,
                  "the positions did not solve at an accepted step (the loop does not close there, or "
                  "Phi_phi is near singular): a dead point");
    internal::ConditioningOf(TS::PhiPhi(c), &s->rcond, &s->det);
    *singular = TS::Calls::Nphi(ts_->model_) > 0 &&
                witness::DeadPointWitness::Crosses(ts_->options_.min_rcond, prev_det_, s->rcond, s->det);
    if (*singular) return true;
    prev_det_ = s->det;
    ts_->SetAnchor(q, s->phi, c, s->rcond, s->det);
    return true;
  }

  bool Fail(Status status, const char* message) {
    failure_ = status;
    failure_message_ = message;
    return false;
  }

 private:
  double prev_det_;  ///< det Phi_phi at the last accepted configuration
  Status failure_ = Status::kNotRun;
  const char* failure_message_ = "";
};

/// The staggered method's run (see the file comment). OnStep: bool operator()(double ta,
/// double tb, const State* x, SampleT* sample_at_tb); false: the step failed (it calls
/// Fail() through the system's failure: see FailStep()).
template <class TS, class OnStep>
class StaggeredSystem : public SensitivitySystemBase<TS> {
 public:
  using Base = SensitivitySystemBase<TS>;
  using typename Base::SampleT;
  using typename Base::VecQ;
  using State = typename TS::StateX;
  static constexpr int kNodes = TS::kNodes;

  StaggeredSystem(TS* ts, double t0, const State& x0, OnStep& on_step)
      : Base(ts), integrator_(ts->state_integrator_), t0_(t0), on_step_(on_step) {
    x_[kNodes - 1] = x0;
  }

  /// The state's right-hand side (qd, qdd).
  bool Derivative(double t, const State& x, State* dx) { return this->ts_->StateDerivative(t, x, dx); }

  /// The configuration at (t, x) (an event's, or t0's): S = Sd = 0 at t0, NaN elsewhere.
  bool Evaluate(double t, const State& x, SampleT* s) {
    if (!this->ts_->StateSample(t, Q(x), Qd(x), s)) return false;
    this->FillS(s, t == t0_ ? 0.0 : std::numeric_limits<double>::quiet_NaN());
    return true;
  }

  /// The accepted step (ta, tb]: its configuration, then OnStep over its nodes.
  bool Accept(double t, const State& x, SampleT* cur) {
    bool singular = false;
    if (!this->AcceptConfiguration(t, Q(x), Qd(x), cur, &singular)) return false;
    if (singular) return true;  // (the dead-point witness ends the run at this step)
    const double ta = integrator_.t_prev(), h = t - ta;
    x_[0] = x_[kNodes - 1];
    x_[kNodes - 1] = x;
    Rhs f{this};
    for (int j = 1; j + 1 < kNodes; ++j)
      if (!integrator_.Dense(f, ta + this->ts_->lob_.c[j] * h, &x_[j]))
        return this->Fail(this->last_solve_not_assemblable_ ? Status::kDeadPoint : Status::kPositionFailed,
                          "the state's dense output did not evaluate at a collocation node");
    return on_step_(ta, t, static_cast<const State*>(x_), cur);
  }

  /// OnStep's failure, recorded as the step's.
  bool FailStep(Status status, const char* message) { return this->Fail(status, message); }

  decltype(std::declval<TS&>().state_integrator_)& integrator_;

 private:
  struct Rhs {
    StaggeredSystem* self;
    bool operator()(double t, const State& x, State* dx) const { return self->Derivative(t, x, dx); }
  };
  VecQ Q(const State& x) const { return x.template head<TS::kNq>(this->ts_->nq_); }
  VecQ Qd(const State& x) const { return x.template segment<TS::kNq>(this->ts_->nq_, this->ts_->nq_); }

  double t0_;
  OnStep& on_step_;
  State x_[kNodes];  ///< the last step's nodes (x_[kNodes - 1]: the last accepted state)
};

/// The simultaneous method's run (fixed sizes): y = (q, qd, vec S, vec Sd) through TS's
/// integrator.
template <class TS>
class SimultaneousSystem : public SensitivitySystemBase<TS> {
 public:
  using Base = SensitivitySystemBase<TS>;
  using typename Base::SampleT;
  using typename Base::VecQ;
  using State = typename TS::State;

  explicit SimultaneousSystem(TS* ts) : Base(ts), integrator_(ts->integrator_) {}

  bool Derivative(double t, const State& y, State* dy) { return this->ts_->Derivative(t, y, dy); }
  /// The sample at (t, y): qdd, phi and the conditioning evaluated; S and Sd read from y.
  bool Evaluate(double t, const State& y, SampleT* s) { return this->ts_->FullSample(t, y, s); }
  /// The accepted configuration, then the sample there.
  bool Accept(double t, const State& y, SampleT* cur) {
    bool singular = false;
    if (!this->AcceptConfiguration(t, y.template head<TS::kNq>(), y.template segment<TS::kNq>(TS::kNq), cur,
                                   &singular))
      return false;
    if (singular) return true;  // (the dead-point witness ends the run at this step)
    if (!Evaluate(t, y, cur))
      return this->Fail(Status::kPositionFailed, "the positions or the inertia did not evaluate at an accepted step");
    return true;
  }

  decltype(std::declval<TS&>().integrator_)& integrator_;
};

}  // namespace mechgen::dynamics::internal
