/**
 * \file dynamics/simulator.h
 * The one event loop of the runtime's simulations: the free (MinimalDynamics, forward.h),
 * driven (PrescribedDynamics, prescribed.h) and engine (engine::GasDriven, a MinimalDynamics
 * with a load) simulations configure it; it drives their integrator from t0 to t_end.
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
 * always at t_end) come from the dense output; an observer gets each and may stop the run.
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

#include "mechgen/core/constants.h"
#include "mechgen/dynamics/integrators.h"

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

/// No user stop condition.
struct NoUserEvent {
  template <class VecQ, class VecPhi>
  double operator()(double, const VecQ&, const VecQ&, const VecPhi&) const {
    return 1.0;
  }
};


/**
 * Steady-state detection: the one definition of "the motion has become periodic" that the
 * free, driven and engine simulations share (the simulate tool's stop at a steady state, the
 * engine's run-up).
 *
 * Cycles of coordinate q_c = q(coordinate): the levels q_c(t0) + k cycle (k integer). A
 * crossing is a sample at which q_c has passed into another interval between levels (either
 * direction) through a level other than the one last crossed; its time is interpolated
 * linearly between that sample and the one before, at the level passed (of the two levels
 * around the move, the one with the larger k). Passing the last crossed level again does not
 * count, and the start's level q_c(t0) counts as crossed at t0 (but not as a crossing): an
 * oscillation about a level completes no cycle, and a motion that starts backwards does not
 * pass its start level at once. Cycle n lies between two successive
 * crossings (two adjacent levels: q_c has advanced one cycle); its duration is P_n and its
 * mean speed w_n = cycle / P_n (the mean of |q_c dot| over it when q_c moves one way). The
 * start is not a crossing: the first timed cycle ends at the second crossing.
 *
 * Steady after cycle n when the last N = consecutive changes of the mean speed are all
 * smaller than tolerance times the latest mean speed:
 *     |w_i - w_(i-1)| < tolerance w_n   for i = n - N + 1, ..., n.
 * (This is the engine run-up's check as it was, N = 2, which this detector replaced without
 * moving a number; the simulate tool's old check compared successive periods, |P_n - P_(n-1)|
 * <= tolerance P_n, which differs from this one at second order in the tolerance.)
 * Reported in the summary's SteadyStateSummary: crossings and cycles counted, the last
 * period, mean speed and relative change |w_n - w_(n-1)| / w_n, and the time of the sample at
 * which the motion was found steady. Nothing allocates.
 */
struct SteadyStateOptions {
  static constexpr int kMaxConsecutive = 16;
  bool enabled = false;
  int coordinate = 0;        ///< which q (an index into the sample's q)
  double cycle = 2 * kPi;    ///< the advance of q_c per cycle (2 pi: a revolution; 4 pi: a
                             ///< four-stroke engine's cycle)
  double tolerance = 1e-4;   ///< relative, in (0, 0.5]
  int consecutive = 2;       ///< N, in [1, kMaxConsecutive]

  /// The options make sense for a sample q of kNq coordinates.
  bool IsValid(int kNq) const {
    return coordinate >= 0 && coordinate < kNq && std::isfinite(cycle) && cycle > 0 &&
           std::isfinite(tolerance) && tolerance > 0 && tolerance <= 0.5 && consecutive >= 1 &&
           consecutive <= kMaxConsecutive;
  }
};

/// What the steady-state detection saw (all NaN or 0 when it was not enabled).
struct SteadyStateSummary {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool steady = false;        ///< the run was found steady (and stopped there)
  int crossings = 0;          ///< levels q_c(t0) + k cycle passed
  int cycles = 0;             ///< cycles timed: crossings - 1 (0 before the second crossing)
  double t_crossing = kNaN;   ///< time of the last crossing (s)
  double period = kNaN;       ///< P_n: the duration of the last cycle (s)
  double mean_speed = kNaN;   ///< w_n = cycle / P_n (rad/s for an angle)
  double last_change = kNaN;  ///< |w_n - w_(n-1)| / w_n (NaN before two cycles)
  double t_steady = kNaN;     ///< the time of the sample at which the run was found steady
};

/// The detector of SteadyStateOptions, fed one sample (t, q_c) at a time.
class SteadyStateDetector {
 public:
  /// A run from (t0, q_c(t0)).
  void Start(const SteadyStateOptions& o, double t0, double q0) {
    o_ = o;
    origin_ = q0;
    prev_t_ = t0;
    prev_q_ = q0;
    k_ = 0;
    k_last_ = 0;
    prev_mean_ = SteadyStateSummary::kNaN;
    count_ = 0;
  }
  /// The sample (t, q_c) after the previous one; updates *s. True when it shows the motion
  /// steady (s->steady is then set).
  bool Add(double t, double q, SteadyStateSummary* s) {
    if (!std::isfinite(q)) return false;
    const double k_now = Interval(q);
    bool steady = false;
    const double k_level = std::max(k_now, k_);
    if (k_now != k_ && k_level != k_last_) {
      const double level = origin_ + o_.cycle * k_level;
      const double t_cross = prev_t_ + (t - prev_t_) * (level - prev_q_) / (q - prev_q_);
      if (s->crossings > 0 && t_cross > s->t_crossing) {
        const double period = t_cross - s->t_crossing;
        const double mean = o_.cycle / period;
        ++s->cycles;
        s->period = period;
        s->mean_speed = mean;
        if (s->cycles >= 2) {
          // The last N changes, newest first.
          for (int i = std::min(count_, SteadyStateOptions::kMaxConsecutive - 1); i > 0; --i)
            changes_[i] = changes_[i - 1];
          changes_[0] = std::abs(mean - prev_mean_);
          count_ = std::min(count_ + 1, SteadyStateOptions::kMaxConsecutive);
          s->last_change = changes_[0] / mean;
          if (count_ >= o_.consecutive) {
            steady = true;
            for (int i = 0; i < o_.consecutive; ++i) steady = steady && changes_[i] < o_.tolerance * mean;
          }
        }
        prev_mean_ = mean;
      }
      ++s->crossings;
      s->t_crossing = t_cross;
      k_last_ = k_level;
    }
    k_ = k_now;
    prev_t_ = t;
    prev_q_ = q;
    if (steady) {
      s->steady = true;
      s->t_steady = t;
    }
    return steady;
  }

 private:
  /// k with origin + k cycle <= q < origin + (k + 1) cycle, by the same comparisons against
  /// the levels that a crossing's interpolation uses.
  double Interval(double q) const {
    double k = std::floor((q - origin_) / o_.cycle);
    if (q >= origin_ + o_.cycle * (k + 1)) {
      k += 1;
    } else if (q < origin_ + o_.cycle * k) {
      k -= 1;
    }
    return k;
  }

  SteadyStateOptions o_;
  double origin_ = 0, prev_t_ = 0, prev_q_ = 0;
  double k_ = 0;       ///< the interval q_c was in at the last sample
  double k_last_ = 0;  ///< the level crossed last (its k); the start's level to begin with
  double prev_mean_ = SteadyStateSummary::kNaN;
  std::array<double, SteadyStateOptions::kMaxConsecutive> changes_{};
  int count_ = 0;  ///< changes held in changes_
};

namespace internal {

/// What the event loop watches: read from MinimalOptions or PrescribedOptions.
struct EventSettings {
  double min_rcond = kMinRcond;
  double event_tolerance = 1e-12;
  double sample_dt = 0;
  int max_samples = 100000000;
  bool stop_at_speed_zero = false;
  double approach_rcond = 1e-3;
  int approach_steps = 0;  ///< 0: the approach to a singular configuration is not watched
  bool energy_projection = false;
  SteadyStateOptions steady;
  /// Switching points of the loads (P::kHasSwitches): located and restarted at (see Run).
  bool restart_at_switches = false;
  double switch_min_interval = 1e-6;
  int max_switch_restarts = 1000;
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

/**
 * The event loop. P is the simulation (MinimalDynamics, PrescribedDynamics), which declares
 * `friend struct internal::EventLoop` and has:
 *   kNphi, State, SampleT, Integrator integrator_, int position_failures_,
 *   bool last_solve_not_assemblable_, singular_inertia_,
 *   bool Evaluate(t, y, SampleT*)          one configuration, updates nothing,
 *   bool Derivative(t, y, State*)          the right-hand side,
 *   bool Accept(t, y, SampleT*)            the accepted step's configuration (from the last
 *                                          stage when it was there), made the warm start,
 *   void EndRun()                          stops caching stages,
 *   static double Balance(const SampleT&)  the energy balance, constant along an exact motion,
 *   void Record(const SampleT&, Summary*)  its own figures of each sample,
 *   void OnDeadPoint(SampleT*)             what a sample at a singular configuration withholds,
 *   bool ProjectEnergy(f, E0, SampleT*)    when kCanProjectEnergy,
 *   kHasSwitches, SwitchModes               the loads' switching items (std::array<int, n>),
 *   bool SwitchModesAt(t, y, SwitchModes*)  their modes at a state, when kHasSwitches.
 * Summary has status, event, integrator, t_end, samples, position_failures, min_rcond_seen,
 * max_energy_error, steady, message (and projections when P::kCanProjectEnergy;
 * switch_restarts and switches_through when P::kHasSwitches).
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
struct EventLoop {
  /// The model's inputs: P::kNq, or the simulation's Nq() where that is Dynamic (the view's).
  template <class P>
  static int NumInputs(const P* sim) {
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
  static bool SeveralFrictionInputs(const P* sim) {
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

  template <class P, class Summary, class Observer, class UserEvent>
  static bool Run(P* sim, const EventSettings& o, double t0, const typename P::State& y0,
                  double t_end, Observer& observer, UserEvent& user_event, Summary* summary,
                  typename P::SampleT* last) {
    using SampleT = typename P::SampleT;
    using State = typename P::State;
    auto& integrator = sim->integrator_;
    auto finish = [&](Status s, double t) {
      if constexpr (HasCoulombHooks<P>::value) {
        if (SeveralFrictionInputs(sim)) {
          if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
            if (sim->CoulombActive()) sim->CloseStuck(t, summary);
          }
        } else if (sim->CoulombActive() && sim->Stuck() && summary->time_stuck >= 0 &&
                   t >= summary->last_stick_start) {
          summary->time_stuck += t - summary->last_stick_start;
        }
      }
      sim->EndRun();
      summary->status = s;
      summary->t_end = t;
      summary->position_failures = sim->position_failures_;
      if (summary->integrator.status == IntegratorStatus::kNotRun)
        summary->integrator = integrator.summary();
      return !IsFailure(s);
    };
    if (!SampleGridIsUsable(t0, t_end, o.sample_dt, o.max_samples)) {
      summary->message =
          "sample_dt cannot advance the sample grid (t + sample_dt == t) or gives more than "
          "max_samples samples";
      return finish(Status::kInvalidInput, t0);
    }
    if (o.steady.enabled && !o.steady.IsValid(NumInputs(sim))) {
      summary->message =
          "steady-state options invalid: coordinate out of range, cycle not > 0, tolerance not "
          "in (0, 0.5] or consecutive not in [1, 16]";
      return finish(Status::kInvalidInput, t0);
    }
    auto f = [sim](double t, const State& y, State* dy) { return sim->Derivative(t, y, dy); };
    auto dense_sample = [&](double t, SampleT* s) {
      State y;
      if (!integrator.Dense(f, t, &y)) return false;
      return sim->Evaluate(t, y, s);
    };
    // Root of g on [ta, tb] (g(ta) = ga, g(tb) = gb of opposite signs) on the dense output,
    // Illinois regula falsi; tb if the dense output cannot be evaluated.
    auto locate = [&](double ta, double tb, double ga, double gb, auto&& g) {
      if (!(ga * gb < 0)) return tb;
      int side = 0;
      for (int it = 0; it < 100 && std::abs(tb - ta) > o.event_tolerance; ++it) {
        double tm = tb - gb * (tb - ta) / (gb - ga);
        if (!(tm > std::min(ta, tb) && tm < std::max(ta, tb))) tm = 0.5 * (ta + tb);
        SampleT s;
        if (!dense_sample(tm, &s)) return tb;
        const double gm = g(s);
        if (gm == 0) return tm;
        if ((gm > 0) == (gb > 0)) {
          tb = tm;
          gb = gm;
          if (side == -1) ga *= 0.5;
          side = -1;
        } else {
          ta = tm;
          ga = gm;
          if (side == 1) gb *= 0.5;
          side = 1;
        }
      }
      return tb;
    };

    SampleT s0;
    if (!sim->Evaluate(t0, y0, &s0)) {
      if constexpr (ReportsFriction<P>::value) {
        if (sim->friction_failed_) {
          summary->message =
              "the slip's friction loads did not converge at the initial state "
              "(CoulombOptions::max_iterations): friction near jamming";
          return finish(Status::kFrictionFailed, t0);
        }
      }
      summary->message = "the initial state does not assemble (or its inertia is singular)";
      return finish(Status::kInvalidInput, t0);
    }
    const double E0 = s0.E;
    summary->min_rcond_seen = s0.rcond;
    if (s0.rcond < o.min_rcond) {
      summary->event = Event::kDeadPoint;
      summary->message = "the initial configuration is singular (Phi_phi): a dead point";
      sim->OnDeadPoint(&s0);
      if (last != nullptr) *last = s0;
      return finish(Status::kDeadPoint, t0);
    }
    // Each sample: the summary's figures and the steady-state detection, then the observer
    // (which sees them). False: stop with status `stop` (the observer, or a steady state).
    SteadyStateDetector steady;
    const int c = o.steady.coordinate;
    if (o.steady.enabled) steady.Start(o.steady, t0, s0.q(c));
    Status stop = Status::kStoppedByObserver;
    bool first = true;
    auto emit = [&](const SampleT& s) {
      ++summary->samples;
      if (last != nullptr) *last = s;
      summary->max_energy_error = std::max(summary->max_energy_error, std::abs(P::Balance(s) - E0));
      sim->Record(s, summary);
      const bool is_steady = o.steady.enabled && !first && steady.Add(s.t, s.q(c), &summary->steady);
      first = false;
      if (!observer(s)) {
        stop = Status::kStoppedByObserver;
        return false;
      }
      if (is_steady) {
        stop = Status::kStoppedByEvent;
        return false;
      }
      return true;
    };
    auto stopped = [&](double t) {
      if (stop == Status::kStoppedByEvent) {
        summary->event = Event::kSteadyState;
        summary->message = "a periodic steady state: the cycle-mean speed settled";
      }
      return finish(stop, t);
    };
    if (!emit(s0)) return stopped(t0);
    int sample_index = 1;
    double next_sample = t0 + o.sample_dt;

    IntegratorStatus is = integrator.Start(f, t0, y0, t_end);
    SampleT prev = s0, cur;
    double g_user_prev = user_event(t0, s0.q, s0.qd, s0.phi);
    int approach_steps = 0;
    // Switching points: the modes at the last accepted state; a pending switch is redone up
    // to t_switch_a, then restarted at t_switch_b with the step h_switch.
    typename P::SwitchModes modes_now{}, modes_b{};  // modes_b: those at t_switch_b
    bool switches_on = false, switch_pending = false;
    double t_switch_a = t0, t_switch_b = t0, h_switch = 0;
    double t_last_restart = -std::numeric_limits<double>::infinity();
    if constexpr (P::kHasSwitches) {
      switches_on = o.restart_at_switches && sim->SwitchModesAt(t0, y0, &modes_now);
    }
    // From (t_switch_a, integrator.y()) over the gap to t_switch_b, f evaluated afresh there;
    // the state there becomes prev (false: the positions failed there).
    auto restart = [&]() {
      if constexpr (P::kHasSwitches) {
        switch_pending = false;
        const State y_b = integrator.y() + (t_switch_b - t_switch_a) * integrator.dy();
        if (!integrator.Restart(f, t_switch_b, y_b, h_switch) || !sim->Accept(t_switch_b, y_b, &cur)) {
          summary->message = "the positions failed where the integrator restarted after a switch";
          return false;
        }
        is = integrator.summary().status;
        ++summary->switch_restarts;
        t_last_restart = t_switch_b;
        // The new side's modes as the bisection found them at t_switch_b (the state carried
        // over the gap may lie a rounding short of the switch: not a second switch).
        modes_now = modes_b;
        prev = cur;
      }
      return true;
    };
    double t_last_transition = -std::numeric_limits<double>::infinity();
    while (is == IntegratorStatus::kRunning) {
      double t_stop = switch_pending ? t_switch_a : std::numeric_limits<double>::quiet_NaN();
      if constexpr (HasCoulombHooks<P>::value) {
        if (sim->CoulombActive() && sim->Stuck()) {
          // Stuck: the breakaway is looked for at each step's end (see EventSettings::stick_step).
          double limit = std::min(t_end, integrator.t() + o.stick_step);
          if (o.sample_dt > 0 && next_sample > integrator.t()) limit = std::min(limit, next_sample);
          if (limit > integrator.t()) t_stop = std::isnan(t_stop) ? limit : std::min(t_stop, limit);
        }
      }
      if constexpr (HasCoulombHooks<P>::value) sim->BeginFrictionStep();
      is = integrator.Step(f, t_stop);
      if (is != IntegratorStatus::kRunning && is != IntegratorStatus::kSuccess) break;
      double t = integrator.t();
      bool restart_here = false;
      if constexpr (P::kHasSwitches) {
        if (switch_pending) {
          restart_here = t == t_switch_a;
        } else if (switches_on) {
          typename P::SwitchModes modes_end = modes_now;  // kept where the positions fail
          if (!sim->SwitchModesAt(t, integrator.y(), &modes_end)) modes_end = modes_now;
          if (modes_end != modes_now) {
            // The earliest change in (t_prev, t]: bisection on the mode vector.
            const double t_start = integrator.t_prev();
            double ta = t_start, tb = t;
            modes_b = modes_end;
            bool located = true;
            for (int it = 0; it < 200 && tb - ta > o.event_tolerance; ++it) {
              const double tm = 0.5 * (ta + tb);
              State ym;
              typename P::SwitchModes mm{};
              if (!(tm > ta && tm < tb)) break;
              if (!integrator.Dense(f, tm, &ym) || !sim->SwitchModesAt(tm, ym, &mm)) {
                located = false;
                break;
              }
              if (mm == modes_now) {
                ta = tm;
              } else {
                tb = tm;
                modes_b = mm;
              }
            }
            // A mode of zero width at the switch (sign(x) = 0 where x is 0 to the last bit):
            // the modes one bracket further on are the new side's.
            if (located && tb < t) {
              const double tc = std::min(t, tb + (tb - ta));
              State yc;
              typename P::SwitchModes mc{};
              if (integrator.Dense(f, tc, &yc) && sim->SwitchModesAt(tc, yc, &mc) && mc != modes_b &&
                  mc != modes_now) {
                tb = tc;
                modes_b = mc;
              }
            }
            const bool chattering = tb - t_last_restart < o.switch_min_interval;
            const bool capped = summary->switch_restarts >= o.max_switch_restarts;
            if (!located || chattering || capped) {
              ++summary->switches_through;
              modes_now = modes_end;
              if (capped)
                summary->message =
                    "max_switch_restarts reached: the later switching points of the loads were "
                    "stepped through";
            } else {
              h_switch = std::max(integrator.summary().h_last, 4 * (tb - ta));
              integrator.Rewind();
              t_switch_a = ta;
              t_switch_b = tb;
              is = IntegratorStatus::kRunning;
              if (ta > t_start) {
                switch_pending = true;  // redo the step up to t_switch_a
                continue;
              }
              // The switch is at the step's start (t_switch_a, already processed): restart at once.
              if (!restart()) return finish(Status::kPositionFailed, t_switch_b);
              continue;
            }
          }
        }
      }
      // Coulomb friction: a transition between stick and slip in (t_prev, t] ends the step there.
      bool friction_transition = false, new_stuck = false;
      double new_direction = 1;
      State y_transition = integrator.y();
      if constexpr (HasCoulombHooks<P>::value) {
        if (SeveralFrictionInputs(sim)) {
          // Several inputs: the first time in (t_prev, t] where a joint's margin (a slipping
          // joint's dir K_rel qd, a stuck one's bound - |f|) is not positive, by bisection.
          if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
          if (sim->CoulombActive()) {
            const double t_start = integrator.t_prev();
            double g_end = 0;
            int joint = -1;
            const double t_seen = sim->BreakawaySeen();  // a stage's margin <= 0, before the end's check
            if (!sim->FrictionMargin(t, integrator.y(), &g_end, &joint)) {
              summary->message = "the friction loads did not converge at a step's end";
              return finish(Status::kFrictionFailed, t);
            }
            double t_high = t;
            if (g_end > 0 && t_seen > t_start && t_seen < t) {
              // A stage saw a joint's margin fall to 0 that the step's end does not show (a
              // brief breakaway, or a relative velocity through zero and back): checked on
              // the dense output there.
              State ys;
              double gs = 0;
              if (!integrator.Dense(f, t_seen, &ys) || !sim->FrictionMargin(t_seen, ys, &gs, &joint)) {
                summary->message = "the friction loads did not converge where a joint's mode changes";
                return finish(Status::kFrictionFailed, t_seen);
              }
              if (gs <= 0) {
                g_end = gs;
                t_high = t_seen;
              }
            }
            if (g_end <= 0) {
              double ta = t_start, tb = t_high;
              for (int it = 0; it < 200 && tb - ta > o.event_tolerance; ++it) {
                const double tm = 0.5 * (ta + tb);
                if (!(tm > ta && tm < tb)) break;
                State ym;
                double gm = 0;
                if (!integrator.Dense(f, tm, &ym) || !sim->FrictionMargin(tm, ym, &gm, &joint)) {
                  summary->message = "the friction loads did not converge where a joint's mode changes";
                  return finish(Status::kFrictionFailed, tm);
                }
                (gm <= 0 ? tb : ta) = tm;
              }
              if (!integrator.Dense(f, tb, &y_transition)) {
                summary->message = "the dense output failed at a stick-slip transition";
                return finish(Status::kPositionFailed, tb);
              }
              t = tb;
              if (!dense_sample(t, &cur)) {
                summary->message = "the positions failed at a stick-slip transition";
                return finish(Status::kPositionFailed, t);
              }
              friction_transition = true;
            }
          }
          }
        } else if (sim->CoulombActive()) {
          const int kQd = NumInputs(sim);  // the index of qd(0) in the state
          const double t_start = integrator.t_prev();
          double t_transition = t;
          if (!sim->Stuck()) {
            const double e = sim->SlipDirection();
            const double g_end = e * integrator.y()(kQd);
            if (g_end <= 0) {
              // The speed's zero: the first time with e qd <= 0 (Illinois regula falsi).
              double ta = t_start, tb = t, ga = e * prev.qd(0), gb = g_end;
              bool dense_ok = true;
              if (ga > 0) {
                int side = 0;
                for (int it = 0; it < 100 && tb - ta > o.event_tolerance; ++it) {
                  double tm = tb - gb * (tb - ta) / (gb - ga);
                  if (!(tm > ta && tm < tb)) tm = 0.5 * (ta + tb);
                  State ym;
                  if (!integrator.Dense(f, tm, &ym)) {
                    dense_ok = false;
                    break;
                  }
                  const double gm = e * ym(kQd);
                  if (gm <= 0) {
                    tb = tm;
                    gb = gm;
                    if (side == -1) ga *= 0.5;
                    side = -1;
                  } else {
                    ta = tm;
                    ga = gm;
                    if (side == 1) gb *= 0.5;
                    side = 1;
                  }
                }
              } else {
                tb = t_start;  // a slip that did not get going: the chattering guard counts it
              }
              t_transition = tb;
              if (!dense_ok || !integrator.Dense(f, tb, &y_transition)) {
                summary->message = "the dense output failed where the speed reached zero";
                return finish(Status::kPositionFailed, tb);
              }
              y_transition(kQd) = 0;
              if (!sim->DecideAtRest(tb, sim->QOf(y_transition), &new_stuck, &new_direction)) {
                summary->message = "the friction at rest did not converge where the speed reached zero";
                return finish(Status::kFrictionFailed, tb);
              }
              friction_transition = true;
            }
          } else {
            bool stuck_end = true;
            double e_end = 1;
            if (!sim->DecideAtRest(t, sim->QOf(integrator.y()), &stuck_end, &e_end)) {
              summary->message = "the friction at rest did not converge while stuck";
              return finish(Status::kFrictionFailed, t);
            }
            // A breakaway that a stage of the step saw (the stages evaluate the holding load
            // and the bound at their times) but the step's end does not: the load rose above
            // the bound and fell back within the step. Looked for up to that stage.
            double t_high = t;
            const double t_seen = sim->BreakawaySeen();
            if (stuck_end && t_seen > t_start && t_seen < t) {
              bool stuck_seen = true;
              double e_seen = 1;
              if (!sim->DecideAtRest(t_seen, sim->QOf(integrator.y()), &stuck_seen, &e_seen)) {
                summary->message = "the friction at rest did not converge while stuck";
                return finish(Status::kFrictionFailed, t_seen);
              }
              if (!stuck_seen) {
                stuck_end = false;
                e_end = e_seen;
                t_high = t_seen;
              }
            }
            if (!stuck_end) {
              // The breakaway: bisection on the decision at rest (the state does not move).
              double ta = t_start, tb = t_high;
              for (int it = 0; it < 200 && tb - ta > o.event_tolerance; ++it) {
                const double tm = 0.5 * (ta + tb);
                if (!(tm > ta && tm < tb)) break;
                bool stuck_m = true;
                double e_m = 1;
                if (!sim->DecideAtRest(tm, sim->QOf(integrator.y()), &stuck_m, &e_m)) {
                  summary->message = "the friction at rest did not converge while stuck";
                  return finish(Status::kFrictionFailed, tm);
                }
                if (stuck_m) {
                  ta = tm;
                } else {
                  tb = tm;
                  e_end = e_m;
                }
              }
              t_transition = tb;
              new_stuck = false;
              new_direction = e_end;
              friction_transition = true;
            }
          }
          if (friction_transition) {
            // The step ends at the transition: its configuration there, in the old mode.
            t = t_transition;
            if (!dense_sample(t, &cur)) {
              summary->message = "the positions failed at a stick-slip transition";
              return finish(Status::kPositionFailed, t);
            }
          }
        }
      }
      if (!friction_transition && !sim->Accept(t, integrator.y(), &cur)) {
        summary->message = "the positions failed at an accepted step";
        return finish(Status::kPositionFailed, t);
      }
      summary->min_rcond_seen = std::min(summary->min_rcond_seen, cur.rcond);
      // Events, the earliest one in this step.
      Event event = Event::kNone;
      double t_event = t;
      bool approached = false;
      auto consider = [&](Event e, double t_root) {
        if (event == Event::kNone || t_root < t_event) {
          event = e;
          t_event = t_root;
        }
      };
      if constexpr (P::kNphi != 0) {  // (a Dynamic kNphi, the view's: rcond = det = 1 without loops)
        const bool sign_change = (prev.det > 0) != (cur.det > 0);
        if (cur.rcond < o.min_rcond || sign_change) {
          const double target = o.min_rcond;
          consider(Event::kDeadPoint,
                   locate(prev.t, t, prev.rcond - target,
                          (sign_change ? -cur.rcond : cur.rcond) - target, [&](const SampleT& s) {
                            return ((s.det > 0) == (prev.det > 0) ? s.rcond : -s.rcond) - target;
                          }));
        } else if (o.approach_steps > 0) {
          // Creeping towards a singular configuration: forces grow like 1/sigma_min(Phi_phi),
          // the step size shrinks geometrically and 1/cond may never reach min_rcond inside
          // the (tiny) window where the loop still closes.
          if (cur.rcond < o.approach_rcond && cur.rcond < prev.rcond) {
            if (++approach_steps >= o.approach_steps) {
              approached = true;
              consider(Event::kDeadPoint, t);
            }
          } else {
            approach_steps = 0;
          }
        }
      }
      if (o.stop_at_speed_zero && prev.qd(0) != 0 && (prev.qd(0) > 0) != (cur.qd(0) > 0)) {
        consider(Event::kSpeedZero,
                 locate(prev.t, t, prev.qd(0), cur.qd(0), [](const SampleT& s) { return s.qd(0); }));
      }
      const double g_user = user_event(t, cur.q, cur.qd, cur.phi);
      if (g_user_prev != 0 && (g_user_prev > 0) != (g_user > 0)) {
        consider(Event::kUser, locate(prev.t, t, g_user_prev, g_user, [&](const SampleT& s) {
                   return user_event(s.t, s.q, s.qd, s.phi);
                 }));
      }
      g_user_prev = g_user;
      const double t_stop_here = event != Event::kNone ? t_event : t;
      // Samples strictly inside (prev.t, t_stop_here).
      const double tiny = 1e-12 * std::max(1.0, std::abs(t));
      if (o.sample_dt > 0) {
        while (next_sample < t_stop_here - tiny) {
          SampleT s;
          if (!dense_sample(next_sample, &s)) {
            summary->message = "the positions failed at a sample";
            return finish(Status::kPositionFailed, next_sample);
          }
          if (!emit(s)) return stopped(s.t);
          next_sample = t0 + o.sample_dt * ++sample_index;
        }
      }
      if (event != Event::kNone) {
        SampleT s;
        if (!dense_sample(t_event, &s)) s = prev;
        if (event == Event::kDeadPoint) {
          summary->min_rcond_seen = std::min(summary->min_rcond_seen, s.rcond);
          sim->OnDeadPoint(&s);
        }
        emit(s);
        summary->event = event;
        summary->integrator = integrator.summary();
        if (event == Event::kDeadPoint) {
          summary->message = approached
                                 ? "the steps collapsed while 1/cond(Phi_phi) kept falling below "
                                   "approach_rcond: a singular configuration (dead point) ahead"
                                 : "1/cond(Phi_phi) fell below min_rcond: a singular "
                                   "configuration (dead point)";
          return finish(Status::kDeadPoint, s.t);
        }
        return finish(Status::kStoppedByEvent, t_event);
      }
      if constexpr (HasCoulombHooks<P>::value) {
        if (friction_transition) {
          // Restart in the new mode at the transition; its sample is handed out.
          ++summary->friction_transitions;
          if (t - t_last_transition < sim->options_.coulomb.min_interval) ++summary->chattering;
          t_last_transition = t;
          if (summary->chattering >= sim->options_.coulomb.max_chattering ||
              summary->friction_transitions > sim->options_.coulomb.max_transitions) {
            summary->message =
                summary->chattering >= sim->options_.coulomb.max_chattering
                    ? "stick-slip chattering: transitions closer than CoulombOptions::min_interval"
                    : "CoulombOptions::max_transitions stick-slip transitions reached";
            summary->integrator = integrator.summary();
            return finish(Status::kFrictionFailed, t);
          }
          if (SeveralFrictionInputs(sim)) {
            (void)new_stuck, (void)new_direction;
            if constexpr (P::kNq > 1 || P::kNq == Eigen::Dynamic) {
              if (!sim->ResolveJoints(t, &y_transition, summary)) {
                summary->integrator = integrator.summary();
                return finish(Status::kFrictionFailed, t);
              }
            }
          } else {
            if (sim->Stuck() && !new_stuck) summary->time_stuck += t - summary->last_stick_start;
            if (!sim->Stuck() && new_stuck) {
              ++summary->stick_intervals;
              summary->last_stick_start = t;
            }
            sim->SetFrictionMode(new_stuck, new_direction);
          }
          if constexpr (P::kHasSwitches) switch_pending = false;  // found again from here
          const double h = std::max(integrator.summary().h_last, 16 * o.event_tolerance);
          if (!integrator.Restart(f, t, y_transition, h) || !sim->Accept(t, y_transition, &cur)) {
            summary->message = "the dynamics failed where the motion restarted after a stick-slip transition";
            return finish(sim->friction_failed_ ? Status::kFrictionFailed : Status::kPositionFailed, t);
          }
          is = integrator.summary().status;
          g_user_prev = user_event(t, cur.q, cur.qd, cur.phi);
          if (!emit(cur)) return stopped(t);
          prev = cur;
          continue;
        }
      }
      if constexpr (P::kCanProjectEnergy) {
        if (o.energy_projection && sim->ProjectEnergy(f, E0, &cur)) ++summary->projections;
      }
      // The step's end is a sample when sampling every step, on the grid, or at t_end.
      const bool on_grid = o.sample_dt > 0 && std::abs(next_sample - t) <= tiny;
      if (on_grid) next_sample = t0 + o.sample_dt * ++sample_index;
      if (o.sample_dt == 0 || on_grid || is == IntegratorStatus::kSuccess) {
        if (!emit(cur)) return stopped(t);
      }
      if constexpr (P::kHasSwitches) {
        // The step ended at t_switch_a: restart on the other side, at t_switch_b.
        if (restart_here && !restart()) return finish(Status::kPositionFailed, t_switch_b);
      }
      prev = cur;
    }
    summary->integrator = integrator.summary();
    if (is == IntegratorStatus::kSuccess) {
      if (last != nullptr) *last = prev;
      return finish(Status::kSuccess, integrator.t());
    }
    // The integrator gave up: say why from what the positions did.
    const bool near_singular = prev.rcond < 1e3 * o.min_rcond;
    if (sim->last_solve_not_assemblable_ || near_singular) {
      summary->event = Event::kDeadPoint;
      summary->message =
          "the integrator stalled next to a singular configuration (Phi_phi nearly singular, or "
          "the loop cannot close beyond this input: a limit position): a dead point";
      sim->OnDeadPoint(&prev);
      if (last != nullptr) *last = prev;
      return finish(Status::kDeadPoint, integrator.t());
    }
    if (last != nullptr) *last = prev;
    if (sim->singular_inertia_) {
      summary->message = "the inertia matrix (of the free coordinates) is not positive definite";
      return finish(Status::kSingularInertia, integrator.t());
    }
    if constexpr (ReportsFriction<P>::value) {
      if (is == IntegratorStatus::kRhsFailed && sim->friction_failed_) {
        summary->message =
            "the slip's friction loads did not converge (CoulombOptions::max_iterations): friction "
            "near jamming";
        return finish(Status::kFrictionFailed, integrator.t());
      }
    }
    if (is == IntegratorStatus::kRhsFailed) {
      summary->message = "the position solver failed";
      return finish(Status::kPositionFailed, integrator.t());
    }
    summary->message = integrator.summary().message;
    return finish(Status::kIntegratorFailed, integrator.t());
  }
};

}  // namespace internal
}  // namespace mechgen::dynamics
