/**
 * \file dynamics/simulator.h
 * The one event loop of the runtime's simulations: the free (MinimalDynamics, forward.h),
 * driven (PrescribedDynamics, prescribed.h), engine (engine::GasDriven, a MinimalDynamics
 * with a load) and excess-coordinate (excess.h) simulations and the trajectory sensitivities'
 * runs (sensitivity_system.h: staggered, simultaneous, the adjoint's forward run) configure it;
 * it drives their integrator from t0 to t_end.
 *
 * The loop runs a system (dynamics/system.h: the hooks a simulation declares, its state, its
 * derivative, its accepted step) and watches its witness functions (dynamics/witness/: each a
 * small class, located on the dense output by the one root finder, witness/locate.h).
 *
 * After every accepted step (the configuration there from the integrator's last stage when it
 * was at exactly that state, else evaluated; it becomes the warm start of the next stages):
 *  - singular configuration (a dead point): 1/cond_1(Phi_phi) below min_rcond or det Phi_phi
 *    changing sign, located on the dense output (Illinois regula falsi) and ending the run with
 *    Status::kDeadPoint; where the steps collapse before 1/cond reaches min_rcond,
 *    approach_steps accepted steps in a row with 1/cond below approach_rcond and falling end
 *    it there the same way (approach_steps = 0: not watched);
 *  - the speed qd(0) through zero (stop_at_speed_zero): Status::kStoppedByEvent;
 *  - a user stop condition g(t, q, qd, phi) changing sign: Status::kStoppedByEvent;
 *  - a periodic steady state (SteadyStateOptions, when enabled): per cycle of one coordinate,
 *    the cycle-mean speeds of the last N cycles settled; Status::kStoppedByEvent,
 *    Event::kSteadyState after the sample that shows it (the observer sees that sample).
 * The earliest event of a step wins. Samples at t0 + k sample_dt (0: every accepted step, and
 * always at t_end) come from the dense output (or, with steps_end_at_samples, are steps' ends);
 * an observer gets each and may stop the run.
 * Energy projection (free simulation only) after each step keeps T + V - W on its initial
 * value. When the integrator gives up, the figures of the last configuration say why (a dead
 * point, a singular inertia, the position solver, the integrator).
 *
 * A sample grid that cannot advance (t + sample_dt == t anywhere in [t0, t_end]) or that would
 * hand out more than max_samples samples is refused with Status::kInvalidInput before any
 * step: never a loop without end.
 *
 * Nothing allocates; nothing throws; no state outside the simulation objects (two simulations
 * run at once on two threads).
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "mechgen/core/constants.h"
#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/witness/dead_point.h"
#include "mechgen/dynamics/witness/locate.h"
#include "mechgen/dynamics/witness/sample_witness.h"
#include "mechgen/dynamics/witness/speed_zero.h"
#include "mechgen/dynamics/witness/steady_state.h"
#include "mechgen/dynamics/witness/stick_slip.h"
#include "mechgen/dynamics/witness/switches.h"
#include "mechgen/dynamics/witness/user_event.h"

namespace mechgen::dynamics {

/// How a simulation ended.
enum class Status {
  kSuccess,            ///< t_end reached
  kStoppedByEvent,     ///< a terminal event that is not a failure: speed zero or the user's
  kDeadPoint,          ///< 1/cond_1(Phi_phi) < min_rcond, det Phi_phi changed sign, the
                       ///< loop could not close (M::Solve kNotAssemblable) down to h_min, or
                       ///< the integrator failed with 1/cond_1(Phi_phi) < 1e3 min_rcond
  kPositionFailed,     ///< M::Solve did not converge (a Newton block) down to h_min
  kSingularInertia,    ///< I(q) not positive definite (or not finite)
  kIntegratorFailed,   ///< max_steps, or the step fell below h_min for accuracy
  kStoppedByObserver,  ///< the sample observer returned false
  kInvalidInput,       ///< options invalid, the initial state does not assemble, or the
                       ///< sample grid cannot advance
  kFrictionFailed,     ///< Coulomb friction (dynamics/friction.h): the slip's friction loads
                       ///< did not converge down to h_min (friction near jamming), or the
                       ///< stick-slip transitions chattered (CoulombOptions)
  kNotRun,
};

inline const char* ToString(Status s) {
  switch (s) {
    case Status::kSuccess:
      return "success";
    case Status::kStoppedByEvent:
      return "stopped_by_event";
    case Status::kDeadPoint:
      return "dead_point";
    case Status::kPositionFailed:
      return "position_failed";
    case Status::kSingularInertia:
      return "singular_inertia";
    case Status::kIntegratorFailed:
      return "integrator_failed";
    case Status::kStoppedByObserver:
      return "stopped_by_observer";
    case Status::kInvalidInput:
      return "invalid_input";
    case Status::kFrictionFailed:
      return "friction_failed";
    case Status::kNotRun:
      return "not_run";
  }
  return "unknown";
}

/// A failure is a run that did not reach t_end nor stop where it was asked to.
inline bool IsFailure(Status s) {
  return !(s == Status::kSuccess || s == Status::kStoppedByEvent ||
           s == Status::kStoppedByObserver);
}

enum class Event { kNone, kDeadPoint, kSpeedZero, kUser, kSteadyState };

inline const char* ToString(Event e) {
  switch (e) {
    case Event::kNone:
      return "none";
    case Event::kDeadPoint:
      return "dead_point";
    case Event::kSpeedZero:
      return "speed_zero";
    case Event::kUser:
      return "user";
    case Event::kSteadyState:
      return "steady_state";
  }
  return "unknown";
}

/// What a summary line adds about the loads' switching points ("; 4 switch restarts, 0
/// switches stepped through"; nothing when there were none).
inline std::string SwitchCounts(int restarts, int through) {
  if (restarts == 0 && through == 0) return "";
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "; %d switch restarts, %d switches stepped through", restarts, through);
  return buffer;
}

/// The simulator's defaults, the one definition that MinimalOptions (forward.h),
/// PrescribedOptions (prescribed.h) and the event loop's settings read (the approach to a
/// singular configuration: kApproachRcond, kApproachSteps in witness/dead_point.h).
inline constexpr double kEventTolerance = 1e-12;      ///< events located to this (s)
inline constexpr int kMaxSimulationSamples = 100000000;  ///< a longer sample grid is refused
inline constexpr double kSwitchMinInterval = 1e-6;    ///< switches closer than this stepped through (s)
inline constexpr int kMaxSwitchRestarts = 1000;       ///< then the switches are stepped through
inline constexpr int kMaxSolverIterations = 20;       ///< Newton iterations of the positions

namespace internal {

/// What the event loop watches: read from MinimalOptions or PrescribedOptions.
struct EventSettings {
  double min_rcond = kMinRcond;
  double event_tolerance = kEventTolerance;
  double sample_dt = 0;
  int max_samples = kMaxSimulationSamples;
  /// Every sample time a step's end (sample_dt > 0): the steps stop there, so that no sample
  /// comes from the dense output between steps (the staggered trajectory sensitivities', whose
  /// S and Sd are known at the steps' ends only).
  bool steps_end_at_samples = false;
  bool stop_at_speed_zero = false;
  double approach_rcond = kApproachRcond;
  int approach_steps = 0;  ///< 0: the approach to a singular configuration is not watched
  bool energy_projection = false;
  SteadyStateOptions steady;
  /// Switching points of the loads (P::kHasSwitches): located and restarted at (see Run).
  bool restart_at_switches = false;
  double switch_min_interval = kSwitchMinInterval;
  int max_switch_restarts = kMaxSwitchRestarts;
  /// Coulomb friction (P::kHasCoulomb): while stuck, steps end at most stick_step apart and
  /// on the sample grid.
  double stick_step = std::numeric_limits<double>::infinity();
};

/// The simulation has Coulomb friction with stick and slip (MinimalDynamics::kHasCoulomb).
template <class P, class = void>
struct HasCoulombHooks : std::false_type {};
template <class P>
struct HasCoulombHooks<P, std::enable_if_t<P::kHasCoulomb>> : std::true_type {};

/// The simulation reports a failure of its Coulomb friction (friction_failed_): the free one
/// with stick and slip, the driven one with the actuators' friction (prescribed.h).
template <class P, class = void>
struct ReportsFriction : std::false_type {};
template <class P>
struct ReportsFriction<P, std::enable_if_t<P::kReportsFriction>> : std::true_type {};

/// The sample grid t0 + k sample_dt over [t0, t_end] advances at every t in it and has at
/// most max_samples points (sample_dt = 0: a sample per accepted step).
inline bool SampleGridIsUsable(double t0, double t_end, double sample_dt, int max_samples) {
  if (sample_dt == 0) return true;
  const double t_far = std::max(std::abs(t0), std::abs(t_end));
  if (!(t_far + sample_dt > t_far)) return false;
  return (t_end - t0) / sample_dt <= static_cast<double>(max_samples);
}

/// The model's inputs: P::kNq, or the simulation's Nq() where that is Dynamic (the view's).
template <class P>
int NumInputs(const P* sim) {
  if constexpr (P::kNq == Eigen::Dynamic) {
    return sim->Nq();
  } else {
    (void)sim;
    return P::kNq;
  }
}

/// Several inputs whose friction joints each have their own mode (P::SeveralInputs(): kNq >
/// 1, or the view's Nq() > 1); false for a simulation without Coulomb friction's hooks.
template <class P>
bool SeveralFrictionInputs(const P* sim) {
  if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
    if constexpr (HasCoulombHooks<P>::value) {
      return sim->SeveralInputs();
    } else {
      (void)sim;
      return false;
    }
  } else {
    (void)sim;
    return false;
  }
}

/**
 * The event loop. P is a system (dynamics/system.h: its hooks and witnesses). Summary has status,
 * event, integrator, t_end, samples, position_failures, min_rcond_seen, max_energy_error, steady,
 * message (and projections when P::kCanProjectEnergy; switch_restarts and switches_through when
 * P::kHasSwitches).
 *
 * Switching points (P::kHasSwitches and EventSettings::restart_at_switches): after a step
 * (t_a, t_b] whose end has other modes than the last accepted state, the earliest change is
 * bracketed on the dense output by bisection on the mode vector to [t_s-, t_s+] (width
 * event_tolerance; t_s- has the old modes, t_s+ the new); the step is undone
 * (Integrator::Rewind) and made again up to t_s- exactly (every stage on the old side; the
 * steps up to it are ordinary accepted steps, with their events and samples), then the
 * integrator restarts at t_s+ (Integrator::Restart: f evaluated afresh on the new side, the
 * state carried over the gap by y + (t_s+ - t_s-) f, the step size of before the switch).
 * Chattering guard: a switch within switch_min_interval of the last restart, or after
 * max_switch_restarts restarts, is stepped through (counted; the message says when the cap
 * was reached).
 *
 * Coulomb friction (P::kHasCoulomb, active for the run: dynamics/friction.h, forward.h), one
 * input. Slipping along e, the step's end with e qd <= 0 is a stop: the speed's zero located
 * on the dense output (Illinois regula falsi on e qd to event_tolerance; the friction load is
 * smooth there, extended past the zero in the slip's direction) at t_z, where the state is
 * taken with qd = 0 and the decision at rest (P::DecideAtRest: stick when |Q0| <= the
 * friction bound B, else slip along sign(Q0)) gives the next mode. Stuck, the step's end
 * where the decision at rest says slip is a breakaway, located by bisection on that decision
 * (the state does not move) to event_tolerance. Either way the step's samples before the
 * transition come from its dense output in the old mode, its events (dead point, speed zero,
 * the user's) are looked for up to the transition, the integrator restarts there
 * (Integrator::Restart) in the new mode and the sample there is handed out (off the grid:
 * every transition has its row). Chattering guard: a transition within
 * CoulombOptions::min_interval of the one before counts; max_chattering of them, or
 * max_transitions in all, end the run with Status::kFrictionFailed. A stuck step whose end
 * stays stuck but one of whose stages saw the load above the bound (P::BreakawaySeen) has the
 * breakaway looked for up to that stage.
 *
 * Several inputs (kNq > 1): each joint's margin (slipping: dir_J K_rel_J qd; stuck: its bound
 * minus |f_J|), their minimum checked at the step's end (and at a stage that saw it <= 0); the
 * first time it is <= 0 bisected on the dense output to event_tolerance; there the joints at
 * relative rest and the stuck ones are decided together (P::ResolveJoints, forward.h), the
 * held inputs' speeds set 0, and the integrator restarts as above.
 */
template <class P, class Summary, class Observer, class UserEvent>
class EventLoopRun {
 public:
  using SampleT = typename P::SampleT;
  using State = typename P::State;

  EventLoopRun(P* sim, const EventSettings& o, double t0, const State& y0, double t_end, Observer& observer,
               UserEvent& user_event, Summary* summary, SampleT* last)
      : sim_(sim),
        o_(o),
        t0_(t0),
        y0_(y0),
        t_end_(t_end),
        observer_(observer),
        summary_(summary),
        last_(last),
        integrator_(sim->integrator_),
        f_{sim},
        dead_point_(o.min_rcond, o.approach_rcond, o.approach_steps),
        user_(user_event) {}

  /// The run from (t0, y0) to t_end (EventLoop::Run).
  bool Run() {
    if (Begin() == Flow::kDone) return result_;
    while (is_ == IntegratorStatus::kRunning) {
      const Flow flow = Step();
      if (flow == Flow::kDone) return result_;
      if (flow == Flow::kEnd) break;
    }
    return End();
  }

 private:
  /// What a part of a step says: go on with the step, go on with the next step, the run
  /// ended (result_), the integrator stopped stepping.
  enum class Flow { kOn, kNextStep, kDone, kEnd };

  /// The right-hand side as the integrator calls it.
  struct Rhs {
    P* sim;
    bool operator()(double t, const State& y, State* dy) const { return sim->Derivative(t, y, dy); }
  };

  // ---- the run's ends ----
  Flow Finish(Status s, double t) {
    if constexpr (HasCoulombHooks<P>::value) {
      if (SeveralFrictionInputs(sim_)) {
        if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
          if (sim_->CoulombActive()) sim_->CloseStuck(t, summary_);
        }
      } else if (sim_->CoulombActive() && sim_->Stuck() && summary_->time_stuck >= 0 &&
                 t >= summary_->last_stick_start) {
        summary_->time_stuck += t - summary_->last_stick_start;
      }
    }
    sim_->EndRun();
    summary_->status = s;
    summary_->t_end = t;
    summary_->position_failures = sim_->position_failures_;
    if (summary_->integrator.status == IntegratorStatus::kNotRun) summary_->integrator = integrator_.summary();
    result_ = !IsFailure(s);
    return Flow::kDone;
  }

  /// The end after Emit() returned false: the observer's stop, or a steady state.
  Flow Stopped(double t) {
    if (stop_ == Status::kStoppedByEvent) {
      summary_->event = Event::kSteadyState;
      summary_->message = "a periodic steady state: the cycle-mean speed settled";
    }
    return Finish(stop_, t);
  }

  /// Each sample: the summary's figures and the steady-state witness, then the observer
  /// (which sees them). False: stop with status stop_ (the observer, or a steady state).
  bool Emit(const SampleT& s) {
    ++summary_->samples;
    if (last_ != nullptr) *last_ = s;
    summary_->max_energy_error = std::max(summary_->max_energy_error, std::abs(P::Balance(s) - E0_));
    sim_->Record(s, summary_);
    const bool is_steady = o_.steady.enabled && !first_ && steady_.Add(s.t, s.q(c_), &summary_->steady);
    first_ = false;
    if (!observer_(s)) {
      stop_ = Status::kStoppedByObserver;
      return false;
    }
    if (is_steady) {
      stop_ = Status::kStoppedByEvent;
      return false;
    }
    return true;
  }

  /// The configuration at t on the last step's dense output.
  bool DenseSample(double t, SampleT* s) {
    State y;
    if (!integrator_.Dense(f_, t, &y)) return false;
    return sim_->Evaluate(t, y, s);
  }

  /// The checks before any step, the initial sample, the integrator started.
  Flow Begin() {
    if (!SampleGridIsUsable(t0_, t_end_, o_.sample_dt, o_.max_samples)) {
      summary_->message =
          "sample_dt cannot advance the sample grid (t + sample_dt == t) or gives more than "
          "max_samples samples";
      return Finish(Status::kInvalidInput, t0_);
    }
    if (o_.steady.enabled && !o_.steady.IsValid(NumInputs(sim_))) {
      summary_->message =
          "steady-state options invalid: coordinate out of range, cycle not > 0, tolerance not "
          "in (0, 0.5] or consecutive not in [1, 16]";
      return Finish(Status::kInvalidInput, t0_);
    }
    SampleT s0;
    if (!sim_->Evaluate(t0_, y0_, &s0)) {
      if constexpr (ReportsFriction<P>::value) {
        if (sim_->friction_failed_) {
          summary_->message =
              "the slip's friction loads did not converge at the initial state "
              "(CoulombOptions::max_iterations): friction near jamming";
          return Finish(Status::kFrictionFailed, t0_);
        }
      }
      summary_->message = "the initial state does not assemble (or its inertia is singular)";
      return Finish(Status::kInvalidInput, t0_);
    }
    E0_ = P::Balance(s0);  // (the integrals of power start at 0: T + V there)
    summary_->min_rcond_seen = s0.rcond;
    if (s0.rcond < o_.min_rcond) {
      summary_->event = Event::kDeadPoint;
      summary_->message = "the initial configuration is singular (Phi_phi): a dead point";
      sim_->OnDeadPoint(&s0);
      if (last_ != nullptr) *last_ = s0;
      return Finish(Status::kDeadPoint, t0_);
    }
    c_ = o_.steady.coordinate;
    if (o_.steady.enabled) steady_.Start(o_.steady, t0_, s0.q(c_));
    if (!Emit(s0)) return Stopped(t0_);
    next_sample_ = t0_ + o_.sample_dt;
    is_ = integrator_.Start(f_, t0_, y0_, t_end_);
    prev_ = s0;
    user_.Reset(s0);
    if constexpr (P::kHasSwitches) {
      switches_on_ = o_.restart_at_switches && sim_->SwitchModesAt(t0_, y0_, &modes_now_);
    }
    return Flow::kOn;
  }

  /// One accepted step of the integrator and all that follows it.
  Flow Step() {
    double t_stop = switch_pending_ ? t_switch_a_ : std::numeric_limits<double>::quiet_NaN();
    if (o_.steps_end_at_samples && o_.sample_dt > 0 && next_sample_ < t_end_)
      t_stop = std::isnan(t_stop) ? next_sample_ : std::min(t_stop, next_sample_);
    if constexpr (HasCoulombHooks<P>::value) {
      if (sim_->CoulombActive() && sim_->Stuck()) {
        // Stuck: the breakaway is looked for at each step's end (see EventSettings::stick_step).
        double limit = std::min(t_end_, integrator_.t() + o_.stick_step);
        if (o_.sample_dt > 0 && next_sample_ > integrator_.t()) limit = std::min(limit, next_sample_);
        if (limit > integrator_.t()) t_stop = std::isnan(t_stop) ? limit : std::min(t_stop, limit);
      }
      sim_->BeginFrictionStep();
    }
    is_ = integrator_.Step(f_, t_stop);
    if (is_ != IntegratorStatus::kRunning && is_ != IntegratorStatus::kSuccess) return Flow::kEnd;
    t_ = integrator_.t();
    restart_here_ = false;
    if constexpr (P::kHasSwitches) {
      const Flow flow = Switches();
      if (flow != Flow::kOn) return flow;
    }
    // Coulomb friction: a transition between stick and slip in (t_prev, t] ends the step there.
    friction_transition_ = false;
    new_stuck_ = false;
    new_direction_ = 1;
    y_transition_ = integrator_.y();
    if constexpr (HasCoulombHooks<P>::value) {
      const Flow flow = Friction();
      if (flow != Flow::kOn) return flow;
    }
    if (!friction_transition_ && !sim_->Accept(t_, integrator_.y(), &cur_)) {
      summary_->message = "the positions failed at an accepted step";
      return Finish(Status::kPositionFailed, t_);
    }
    summary_->min_rcond_seen = std::min(summary_->min_rcond_seen, cur_.rcond);
    Event event = Event::kNone;
    double t_event = t_;
    bool approached = false;
    FindEvents(&event, &t_event, &approached);
    const double t_stop_here = event != Event::kNone ? t_event : t_;
    const double tiny = 1e-12 * std::max(1.0, std::abs(t_));
    const Flow flow = SamplesBefore(t_stop_here, tiny);
    if (flow != Flow::kOn) return flow;
    if (event != Event::kNone) return EndAtEvent(event, t_event, approached);
    if constexpr (HasCoulombHooks<P>::value) {
      if (friction_transition_) return RestartAfterTransition();
    }
    return EndOfStep(tiny);
  }

  /// The step's sample witnesses, the earliest that fires (its time located on the dense output).
  void FindEvents(Event* event, double* t_event, bool* approached) {
    auto consider = [&](Event e, double t_root) {
      if (*event == Event::kNone || t_root < *t_event) {
        *event = e;
        *t_event = t_root;
      }
    };
    auto dense = [this](double t, SampleT* s) { return DenseSample(t, s); };
    const double tol = o_.event_tolerance;
    double ga = 0, gb = 0;
    if constexpr (P::kNphi != 0) {  // (a Dynamic kNphi, the view's: rcond = det = 1 without loops)
      const auto found = dead_point_.Check(prev_, cur_, &ga, &gb);
      if (found == witness::DeadPointWitness::Found::kCrossed) {
        consider(Event::kDeadPoint, witness::LocateOnSamples<SampleT>(prev_.t, t_, ga, gb, tol, dead_point_, dense));
      } else if (found == witness::DeadPointWitness::Found::kApproached) {
        *approached = true;
        consider(Event::kDeadPoint, t_);
      }
    }
    if (o_.stop_at_speed_zero && speed_zero_.Fires(prev_, cur_, &ga, &gb)) {
      consider(Event::kSpeedZero, witness::LocateOnSamples<SampleT>(prev_.t, t_, ga, gb, tol, speed_zero_, dense));
    }
    if (user_.Fires(prev_, cur_, &ga, &gb)) {
      consider(Event::kUser, witness::LocateOnSamples<SampleT>(prev_.t, t_, ga, gb, tol, user_, dense));
    }
  }

  /// The samples on the grid strictly inside (prev.t, t_stop_here).
  Flow SamplesBefore(double t_stop_here, double tiny) {
    if (o_.sample_dt > 0) {
      while (next_sample_ < t_stop_here - tiny) {
        SampleT s;
        if (!DenseSample(next_sample_, &s)) {
          summary_->message = "the positions failed at a sample";
          return Finish(Status::kPositionFailed, next_sample_);
        }
        if (!Emit(s)) return Stopped(s.t);
        next_sample_ = t0_ + o_.sample_dt * ++sample_index_;
      }
    }
    return Flow::kOn;
  }

  /// A witness fired: its sample, and the run's end.
  Flow EndAtEvent(Event event, double t_event, bool approached) {
    SampleT s;
    if (!DenseSample(t_event, &s)) s = prev_;
    if (event == Event::kDeadPoint) {
      summary_->min_rcond_seen = std::min(summary_->min_rcond_seen, s.rcond);
      sim_->OnDeadPoint(&s);
    }
    Emit(s);
    summary_->event = event;
    summary_->integrator = integrator_.summary();
    if (event == Event::kDeadPoint) {
      summary_->message = approached ? "the steps collapsed while 1/cond(Phi_phi) kept falling below "
                                       "approach_rcond: a singular configuration (dead point) ahead"
                                     : "1/cond(Phi_phi) fell below min_rcond: a singular "
                                       "configuration (dead point)";
      return Finish(Status::kDeadPoint, s.t);
    }
    return Finish(Status::kStoppedByEvent, t_event);
  }

  /// An ordinary step's end: the energy projection, its sample, a pending switch's restart.
  Flow EndOfStep(double tiny) {
    if constexpr (P::kCanProjectEnergy) {
      if (o_.energy_projection && sim_->ProjectEnergy(f_, E0_, &cur_)) ++summary_->projections;
    }
    // The step's end is a sample when sampling every step, on the grid, or at t_end.
    const bool on_grid = o_.sample_dt > 0 && std::abs(next_sample_ - t_) <= tiny;
    if (on_grid) next_sample_ = t0_ + o_.sample_dt * ++sample_index_;
    if (o_.sample_dt == 0 || on_grid || is_ == IntegratorStatus::kSuccess) {
      if (!Emit(cur_)) return Stopped(t_);
    }
    if constexpr (P::kHasSwitches) {
      // The step ended at t_switch_a: restart on the other side, at t_switch_b.
      if (restart_here_ && !RestartAtSwitch()) return Finish(Status::kPositionFailed, t_switch_b_);
    }
    prev_ = cur_;
    return Flow::kOn;
  }

  /// The integrator stopped stepping: t_end reached, or why it gave up from what the
  /// positions did.
  bool End() {
    summary_->integrator = integrator_.summary();
    if (is_ == IntegratorStatus::kSuccess) {
      if (last_ != nullptr) *last_ = prev_;
      Finish(Status::kSuccess, integrator_.t());
      return result_;
    }
    const bool near_singular = prev_.rcond < 1e3 * o_.min_rcond;
    if (sim_->last_solve_not_assemblable_ || near_singular) {
      summary_->event = Event::kDeadPoint;
      summary_->message =
          "the integrator stalled next to a singular configuration (Phi_phi nearly singular, or "
          "the loop cannot close beyond this input: a limit position): a dead point";
      sim_->OnDeadPoint(&prev_);
      if (last_ != nullptr) *last_ = prev_;
      Finish(Status::kDeadPoint, integrator_.t());
      return result_;
    }
    if (last_ != nullptr) *last_ = prev_;
    Status status = Status::kIntegratorFailed;
    if (sim_->singular_inertia_) {
      summary_->message = "the inertia matrix (of the free coordinates) is not positive definite";
      status = Status::kSingularInertia;
    } else if (FrictionFailedInStep()) {
      summary_->message =
          "the slip's friction loads did not converge (CoulombOptions::max_iterations): friction "
          "near jamming";
      status = Status::kFrictionFailed;
    } else if (is_ == IntegratorStatus::kRhsFailed) {
      summary_->message = "the position solver failed";
      status = Status::kPositionFailed;
    } else {
      summary_->message = integrator_.summary().message;
    }
    Finish(status, integrator_.t());
    return result_;
  }

  bool FrictionFailedInStep() const {
    if constexpr (ReportsFriction<P>::value) {
      return is_ == IntegratorStatus::kRhsFailed && sim_->friction_failed_;
    } else {
      return false;
    }
  }

  // ---- the loads' switching points (witness/switches.h) ----
  /// After a step whose end has other modes: the step undone and made again up to the
  /// switch (switch_pending_), or the restart at once where the switch is at its start.
  Flow Switches() {
    if (switch_pending_) {
      restart_here_ = t_ == t_switch_a_;
      return Flow::kOn;
    }
    if (!switches_on_) return Flow::kOn;
    typename P::SwitchModes modes_end = modes_now_;  // kept where the positions fail
    if (!sim_->SwitchModesAt(t_, integrator_.y(), &modes_end)) modes_end = modes_now_;
    if (modes_end == modes_now_) return Flow::kOn;
    // The earliest change in (t_prev, t]: bisection on the mode vector.
    const double t_start = integrator_.t_prev();
    double ta = t_start, tb = t_;
    auto modes_at = [this](double t, typename P::SwitchModes* m) {
      State y;
      return integrator_.Dense(f_, t, &y) && sim_->SwitchModesAt(t, y, m);
    };
    const bool located =
        witness::LocateSwitch(t_start, t_, o_.event_tolerance, modes_now_, modes_end, modes_at, &ta, &tb, &modes_b_);
    const bool chattering = tb - t_last_restart_ < o_.switch_min_interval;
    const bool capped = summary_->switch_restarts >= o_.max_switch_restarts;
    if (!located || chattering || capped) {
      ++summary_->switches_through;
      modes_now_ = modes_end;
      if (capped)
        summary_->message =
            "max_switch_restarts reached: the later switching points of the loads were "
            "stepped through";
      return Flow::kOn;
    }
    h_switch_ = std::max(integrator_.summary().h_last, 4 * (tb - ta));
    integrator_.Rewind();
    t_switch_a_ = ta;
    t_switch_b_ = tb;
    is_ = IntegratorStatus::kRunning;
    if (ta > t_start) {
      switch_pending_ = true;  // redo the step up to t_switch_a
      return Flow::kNextStep;
    }
    // The switch is at the step's start (t_switch_a, already processed): restart at once.
    if (!RestartAtSwitch()) return Finish(Status::kPositionFailed, t_switch_b_);
    return Flow::kNextStep;
  }

  /// From (t_switch_a, integrator.y()) over the gap to t_switch_b, f evaluated afresh there;
  /// the state there becomes prev (false: the positions failed there).
  bool RestartAtSwitch() {
    switch_pending_ = false;
    const State y_b = integrator_.y() + (t_switch_b_ - t_switch_a_) * integrator_.dy();
    if (!integrator_.Restart(f_, t_switch_b_, y_b, h_switch_) || !sim_->Accept(t_switch_b_, y_b, &cur_)) {
      summary_->message = "the positions failed where the integrator restarted after a switch";
      return false;
    }
    is_ = integrator_.summary().status;
    ++summary_->switch_restarts;
    t_last_restart_ = t_switch_b_;
    // The new side's modes as the bisection found them at t_switch_b (the state carried over
    // the gap may lie a rounding short of the switch: not a second switch).
    modes_now_ = modes_b_;
    prev_ = cur_;
    return true;
  }

  // ---- stick and slip (Coulomb friction, friction.h) ----
  /// A transition in (t_prev, t]: friction_transition_, the step's end moved there (t_, cur_,
  /// y_transition_), the new mode (new_stuck_, new_direction_).
  Flow Friction() {
    if (SeveralFrictionInputs(sim_)) {
      if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
        if (sim_->CoulombActive()) return FrictionJoints();
      }
      return Flow::kOn;
    }
    if (!sim_->CoulombActive()) return Flow::kOn;
    const double t_start = integrator_.t_prev();
    double t_transition = t_;
    const Flow flow = sim_->Stuck() ? Breakaway(t_start, &t_transition) : SlipStop(t_start, &t_transition);
    if (flow != Flow::kOn) return flow;
    if (friction_transition_) {
      // The step ends at the transition: its configuration there, in the old mode.
      t_ = t_transition;
      if (!DenseSample(t_, &cur_)) {
        summary_->message = "the positions failed at a stick-slip transition";
        return Finish(Status::kPositionFailed, t_);
      }
    }
    return Flow::kOn;
  }

  /// Slipping along e: the speed's zero, the first time with e qd <= 0 (witness/stick_slip.h);
  /// there the state with qd = 0 and the decision at rest give the next mode.
  Flow SlipStop(double t_start, double* t_transition) {
    const int kQd = NumInputs(sim_);  // the index of qd(0) in the state
    const double e = sim_->SlipDirection();
    const double g_end = e * integrator_.y()(kQd);
    if (g_end > 0) return Flow::kOn;
    auto speed = [&](double tm, double* gm) {
      State ym;
      if (!integrator_.Dense(f_, tm, &ym)) return false;
      *gm = e * ym(kQd);
      return true;
    };
    double tb = t_start;
    const bool dense_ok = witness::LocateSlipStop(t_start, t_, e * prev_.qd(0), g_end, o_.event_tolerance, speed, &tb);
    *t_transition = tb;
    if (!dense_ok || !integrator_.Dense(f_, tb, &y_transition_)) {
      summary_->message = "the dense output failed where the speed reached zero";
      return Finish(Status::kPositionFailed, tb);
    }
    y_transition_(kQd) = 0;
    if (!sim_->DecideAtRest(tb, sim_->QOf(y_transition_), &new_stuck_, &new_direction_)) {
      summary_->message = "the friction at rest did not converge where the speed reached zero";
      return Finish(Status::kFrictionFailed, tb);
    }
    friction_transition_ = true;
    return Flow::kOn;
  }

  /// Stuck: the breakaway (witness/stick_slip.h), where the decision at rest says slip.
  Flow Breakaway(double t_start, double* t_transition) {
    auto decide = [this](double t, bool* stuck, double* e) {
      return sim_->DecideAtRest(t, sim_->QOf(integrator_.y()), stuck, e);
    };
    double t_break = t_, e = 1, t_failed = t_;
    const witness::Found found =
        witness::LocateBreakaway(t_start, t_, sim_->BreakawaySeen(), o_.event_tolerance, decide, &t_break, &e, &t_failed);
    if (found == witness::Found::kFailed) {
      summary_->message = "the friction at rest did not converge while stuck";
      return Finish(Status::kFrictionFailed, t_failed);
    }
    if (found == witness::Found::kTransition) {
      *t_transition = t_break;
      new_stuck_ = false;
      new_direction_ = e;
      friction_transition_ = true;
    }
    return Flow::kOn;
  }

  /// Several inputs: the first time a joint's margin is not positive (witness/stick_slip.h);
  /// the step ends there.
  Flow FrictionJoints() {
    const double t_start = integrator_.t_prev();
    double g_end = 0;
    int joint = -1;
    const double t_seen = sim_->BreakawaySeen();  // a stage's margin <= 0, before the end's check
    if (!sim_->FrictionMargin(t_, integrator_.y(), &g_end, &joint)) {
      summary_->message = "the friction loads did not converge at a step's end";
      return Finish(Status::kFrictionFailed, t_);
    }
    auto margin = [&](double tm, double* gm) {
      State ym;
      return integrator_.Dense(f_, tm, &ym) && sim_->FrictionMargin(tm, ym, gm, &joint);
    };
    double tb = t_, t_failed = t_;
    const witness::Found found =
        witness::LocateJointChange(t_start, t_, g_end, t_seen, o_.event_tolerance, margin, &tb, &t_failed);
    if (found == witness::Found::kFailed) {
      summary_->message = "the friction loads did not converge where a joint's mode changes";
      return Finish(Status::kFrictionFailed, t_failed);
    }
    if (found == witness::Found::kNone) return Flow::kOn;
    if (!integrator_.Dense(f_, tb, &y_transition_)) {
      summary_->message = "the dense output failed at a stick-slip transition";
      return Finish(Status::kPositionFailed, tb);
    }
    t_ = tb;
    if (!DenseSample(t_, &cur_)) {
      summary_->message = "the positions failed at a stick-slip transition";
      return Finish(Status::kPositionFailed, t_);
    }
    friction_transition_ = true;
    return Flow::kOn;
  }

  /// Restart in the new mode at the transition; its sample is handed out. The chattering
  /// guard first (CoulombOptions).
  Flow RestartAfterTransition() {
    const auto& coulomb = sim_->options_.coulomb;
    ++summary_->friction_transitions;
    if (t_ - t_last_transition_ < coulomb.min_interval) ++summary_->chattering;
    t_last_transition_ = t_;
    if (summary_->chattering >= coulomb.max_chattering || summary_->friction_transitions > coulomb.max_transitions) {
      summary_->message = summary_->chattering >= coulomb.max_chattering
                              ? "stick-slip chattering: transitions closer than CoulombOptions::min_interval"
                              : "CoulombOptions::max_transitions stick-slip transitions reached";
      summary_->integrator = integrator_.summary();
      return Finish(Status::kFrictionFailed, t_);
    }
    if (SeveralFrictionInputs(sim_)) {
      if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
        if (!sim_->ResolveJoints(t_, &y_transition_, summary_)) {
          summary_->integrator = integrator_.summary();
          return Finish(Status::kFrictionFailed, t_);
        }
      }
    } else {
      if (sim_->Stuck() && !new_stuck_) summary_->time_stuck += t_ - summary_->last_stick_start;
      if (!sim_->Stuck() && new_stuck_) {
        ++summary_->stick_intervals;
        summary_->last_stick_start = t_;
      }
      sim_->SetFrictionMode(new_stuck_, new_direction_);
    }
    if constexpr (P::kHasSwitches) switch_pending_ = false;  // found again from here
    const double h = std::max(integrator_.summary().h_last, 16 * o_.event_tolerance);
    if (!integrator_.Restart(f_, t_, y_transition_, h) || !sim_->Accept(t_, y_transition_, &cur_)) {
      summary_->message = "the dynamics failed where the motion restarted after a stick-slip transition";
      return Finish(sim_->friction_failed_ ? Status::kFrictionFailed : Status::kPositionFailed, t_);
    }
    is_ = integrator_.summary().status;
    user_.Reset(cur_);
    if (!Emit(cur_)) return Stopped(t_);
    prev_ = cur_;
    return Flow::kNextStep;
  }

  P* sim_;
  const EventSettings& o_;
  double t0_;
  const State& y0_;
  double t_end_;
  Observer& observer_;
  Summary* summary_;
  SampleT* last_;
  decltype(std::declval<P&>().integrator_)& integrator_;
  Rhs f_;
  bool result_ = false;
  // The witnesses on the samples.
  witness::DeadPointWitness dead_point_;
  witness::SpeedZeroWitness speed_zero_;
  witness::UserWitness<UserEvent> user_;
  SteadyStateDetector steady_;
  int c_ = 0;  ///< the steady state's coordinate
  // The samples: the energy balance at t0 (P::Balance), the grid, the observer's stop.
  double E0_ = 0;
  Status stop_ = Status::kStoppedByObserver;
  bool first_ = true;
  int sample_index_ = 1;
  double next_sample_ = 0;
  // The integrator's status and the last accepted state's sample (prev_), the step's (cur_).
  IntegratorStatus is_ = IntegratorStatus::kNotRun;
  SampleT prev_, cur_;
  double t_ = 0;  ///< the step's end (moved to a stick-slip transition)
  // Switching points: the modes at the last accepted state; a pending switch is redone up to
  // t_switch_a, then restarted at t_switch_b with the step h_switch.
  typename P::SwitchModes modes_now_{}, modes_b_{};  // modes_b: those at t_switch_b
  bool switches_on_ = false, switch_pending_ = false, restart_here_ = false;
  double t_switch_a_ = 0, t_switch_b_ = 0, h_switch_ = 0;
  double t_last_restart_ = -std::numeric_limits<double>::infinity();
  // Stick and slip: the step's transition and the new mode.
  bool friction_transition_ = false, new_stuck_ = false;
  double new_direction_ = 1;
  State y_transition_;
  double t_last_transition_ = -std::numeric_limits<double>::infinity();
};

struct EventLoop {
  template <class P, class Summary, class Observer, class UserEvent>
  static bool Run(P* sim, const EventSettings& o, double t0, const typename P::State& y0, double t_end,
                  Observer& observer, UserEvent& user_event, Summary* summary, typename P::SampleT* last) {
    EventLoopRun<P, Summary, Observer, UserEvent> run(sim, o, t0, y0, t_end, observer, user_event, summary, last);
    return run.Run();
  }
};

}  // namespace internal
}  // namespace mechgen::dynamics
