/**
 * \file dynamics/forward.h
 * Forward dynamics by the minimal method (Paul §6.6.1): integrate the generalized coordinates
 * q and speeds qd of a generated model with dynamics, the dependent positions phi solved at
 * every stage by the generated position solver (no drift in phi: Phi(q, phi) = 0 to round-off
 * at every evaluation, the assembly mode kept by the solver's modes).
 *
 * One evaluation of the right-hand side at (t, q, qd):
 *   1. phi = M::Solve(p, q, phi_ref + K_ref (q - q_ref), modes): closed-form blocks exactly on
 *      their mode, Newton blocks from that predictor (phi_ref, K_ref: the last accepted
 *      configuration; the one position tracker of the simulations, dynamics/position_tracker.h). A failed solve makes the evaluation fail (a status, never NaN): the
 *      integrator then shortens the step, and a failure down to its minimal step ends the run
 *      with Status::kDeadPoint (the loop cannot close: the motion reached a limit position of
 *      the input) or kPositionFailed.
 *   2. M::Coeffs (K, L, Phi_phi), M::Dynamics (I, C, h, Q, T, V, P_nc).
 *   3. qdd = I^-1 (Q - h) (a division for kNq = 1, a fixed-size LDLT otherwise; I must be
 *      positive definite, else the evaluation fails).
 * The state integrated is y = (q, qd, W) with W = integral of P_nc dt, the work of the
 * non-conservative forces, so that E - W = T + V - W is an invariant to check (and the energy
 * level that MinimalOptions::energy_projection keeps).
 *
 * Events, checked after every accepted step by the one event loop of the runtime
 * (dynamics/simulator.h, shared with prescribed.h) and located on the integrator's dense
 * output by the Illinois variant of regula falsi:
 *  - dead point: 1/cond_1(Phi_phi) falls below MinimalOptions::min_rcond (or det Phi_phi
 *    changes sign): a failure (Status::kDeadPoint) with figures in the Summary;
 *  - speed through zero (kNq = 1: qd; a reversing machine), if MinimalOptions::stop_at_speed_zero;
 *  - a user stop condition g(t, q, qd, phi): stops where it changes sign;
 *  - a switching point of the loads (a model with M::SwitchModes, Model::kNumSwitches > 0, and
 *    MinimalOptions::restart_at_switches): not an event that stops the run; the step that
 *    crossed it is redone up to it and the integrator restarts just after it (simulator.h).
 * Samples at requested times (MinimalOptions::sample_dt, 0: every accepted step) come from
 * the dense output with the positions solved there, handed to an observer as a Sample
 * (t, q, qd, qdd, phi, T, V, E, W, Q, P_nc). Nothing allocates after construction; nothing
 * throws.
 *
 * Units and signs: those of the model (SI: rad, m, s, kg, N, N m, J); q and qd in the
 * model's coordinates (an angle input CCW +); Q is the generalized applied force (torque for an
 * angle input) of the loads, weights, springs, dampers and motor curves.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/invalid_option.h"
#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/friction.h"
#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/position_tracker.h"
#include "mechgen/dynamics/simulator.h"

namespace mechgen::dynamics {

struct MinimalOptions {
  IntegratorOptions integrator;
  /// Dead point when 1/cond_1(Phi_phi) < min_rcond (the position solver's limit, kMinRcond).
  double min_rcond = kMinRcond;
  /// Stop (kStoppedByEvent, Event::kSpeedZero) where qd(0) changes sign.
  bool stop_at_speed_zero = false;
  /// Events are located to |t - t_event| <= event_tolerance (s).
  double event_tolerance = kEventTolerance;
  /// Samples every sample_dt from t0 (and at the end); 0: at every accepted step.
  double sample_dt = 0;
  /// A run whose sample grid would hand out more samples than this is refused (kInvalidInput).
  int max_samples = kMaxSimulationSamples;
  /// Energy-keeping long runs: after each accepted step scale qd so that T + V - W equals its
  /// initial value (T* = E0 + W - V; qd <- qd sqrt(T* / T) when T* > 0 and T > energy_floor
  /// |E0|-scale; skipped near rest, where |qd| carries no energy to correct). One extra
  /// evaluation per step. Exact for one DOF: at a given q, E fixes |qd|.
  bool energy_projection = false;
  double energy_floor = 1e-6;
  /// Switching points of the model's loads (a step, sign, min, max, mod or table in Q: the
  /// generated M::SwitchModes, where Model::kNumSwitches > 0): after a step whose end has other
  /// modes than its start, the earliest change is located on the dense output (bisection to
  /// event_tolerance), the step is redone up to just before it (no stage straddles the jump or
  /// kink) and the integrator restarts just after it with f evaluated there. Off, or for a
  /// model without switches: the integrator steps through them (shrinking its steps).
  bool restart_at_switches = true;
  /// Chattering guard (a load that switches ever more often, such as a bang-bang spring
  /// -K sign(theta - theta_b) whose swings shorten without end): a switch less than
  /// switch_min_interval (s) after the last restart is stepped through (counted in
  /// MinimalSummary::switches_through), and after max_switch_restarts restarts every later
  /// switch is (the summary's message says so).
  double switch_min_interval = kSwitchMinInterval;
  int max_switch_restarts = kMaxSwitchRestarts;
  /// Newton blocks of M::Solve: iterations and tolerance (0: the generated default).
  int max_solver_iterations = kMaxSolverIterations;
  double solver_tolerance = 0;

  /// Stop at a periodic steady state (simulator.h: per cycle of one coordinate, the change of
  /// the cycle-mean speed); off by default. Reported in the summary's `steady`.
  SteadyStateOptions steady;

  /// Coulomb friction at the model's friction joints, with stick and slip (dynamics/friction.h;
  /// on by default: a model whose friction joints have a coefficient moves with it). While
  /// stuck, the steps end on the sample grid (sample_dt > 0) and at most stick_step (s) apart:
  /// the breakaway of a time-dependent load is looked for at each step's end (and located
  /// between it and the step before), so a load that rises above the friction bound and falls
  /// back within one such step is not seen.
  CoulombOptions coulomb;
  double stick_step = std::numeric_limits<double>::infinity();

  bool IsValid(std::string* error) const {
    if (!integrator.IsValid(error)) return false;
    auto fail = [error](const char* field, double value, const char* rule) {
      return InvalidOption(error, "MinimalOptions", field, value, rule);
    };
    if (!(min_rcond >= 0 && min_rcond < 1)) return fail("min_rcond", min_rcond, "0 <= min_rcond < 1");
    if (!(event_tolerance > 0)) return fail("event_tolerance", event_tolerance, "event_tolerance > 0");
    if (!(sample_dt >= 0) || !std::isfinite(sample_dt))
      return fail("sample_dt", sample_dt, "0 <= sample_dt < inf");
    if (max_samples < 1) return fail("max_samples", max_samples, "max_samples >= 1");
    if (!(energy_floor >= 0)) return fail("energy_floor", energy_floor, "energy_floor >= 0");
    if (!(switch_min_interval >= 0) || !std::isfinite(switch_min_interval))
      return fail("switch_min_interval", switch_min_interval, "0 <= switch_min_interval < inf");
    if (max_switch_restarts < 0) return fail("max_switch_restarts", max_switch_restarts, "max_switch_restarts >= 0");
    if (max_solver_iterations < 1)
      return fail("max_solver_iterations", max_solver_iterations, "max_solver_iterations >= 1");
    if (!coulomb.IsValid()) {
      if (error != nullptr)
        *error = "MinimalOptions::coulomb invalid: max_iterations >= 2, 0 < tolerance < 1e-3, "
                 "min_interval >= 0, max_chattering >= 1, max_transitions >= 1";
      return false;
    }
    if (!(stick_step > 0)) return fail("stick_step", stick_step, "stick_step > 0");
    return true;
  }
};

struct MinimalSummary {
  Status status = Status::kNotRun;
  Event event = Event::kNone;
  IntegratorSummary integrator;
  double t_end = std::numeric_limits<double>::quiet_NaN();  ///< where the run ended
  int samples = 0;
  int position_failures = 0;  ///< evaluations whose M::Solve failed (steps retried shorter)
  /// The smallest 1/cond_1(Phi_phi) met at accepted steps and samples (1 for kNphi = 0).
  double min_rcond_seen = std::numeric_limits<double>::infinity();
  /// max |T + V - W - E0| over the samples (energy units): the energy balance's drift.
  double max_energy_error = 0;
  int projections = 0;  ///< energy projections made
  /// Switching points of the loads (MinimalOptions::restart_at_switches): located and
  /// restarted at, and stepped through (the chattering guard, or after max_switch_restarts).
  int switch_restarts = 0;
  int switches_through = 0;
  SteadyStateSummary steady;  ///< the steady-state detection (options.steady)
  /// Coulomb friction (MinimalOptions::coulomb): simulated; transitions between stick and
  /// slip (each at a located time, with a sample there); the stuck intervals begun, the time
  /// spent stuck (s) and the start of the last one (NaN: none); transitions that came within
  /// CoulombOptions::min_interval of the one before (the chattering guard's count).
  bool coulomb = false;
  int friction_transitions = 0;
  int stick_intervals = 0;
  double time_stuck = 0;
  double last_stick_start = std::numeric_limits<double>::quiet_NaN();
  int chattering = 0;
  /// Several inputs: the friction joint a kFrictionFailed names (M::kFrictionJoints), or "".
  const char* friction_joint = "";
  const char* message = "";

  bool IsSolutionUsable() const { return !IsFailure(status); }
};

inline std::string FormatSummary(const MinimalSummary& s) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer),
                "%s (event %s) at t = %.9g: %d samples, %d steps, %d rejected, %d rhs "
                "evaluations, min 1/cond(Phi_phi) = %.3g, max |E - W - E0| = %.3g%s%s",
                ToString(s.status), ToString(s.event), s.t_end, s.samples, s.integrator.steps,
                s.integrator.rejected, s.integrator.rhs_evaluations, s.min_rcond_seen,
                s.max_energy_error, s.message[0] != 0 ? "; " : "", s.message);
  std::string text = buffer + SwitchCounts(s.switch_restarts, s.switches_through);
  if (s.friction_joint[0] != 0) text += std::string(" (joint '") + s.friction_joint + "')";
  if (s.coulomb) {
    std::snprintf(buffer, sizeof(buffer),
                  "; Coulomb friction: %d stick-slip transitions, %d stuck intervals, %.9g s stuck",
                  s.friction_transitions, s.stick_intervals, s.time_stuck);
    text += buffer;
  }
  return text;
}

namespace internal {
// What the model has: core/model_traits.h (the one place), by these names here too.
template <class M>
using HasDynamics = mechgen::HasDynamics<M>;
template <class M>
using HasSolveTrig = mechgen::HasSolveTrig<M>;
template <class M>
using HasRhs = mechgen::HasRhs<M>;
using mechgen::internal::NoRhsConstants;
using mechgen::internal::RhsConstantsOf;

/// The number of switching items of the model's loads (Model::kNumSwitches where its flag
/// kHasSwitchModes says it has some; 0 otherwise).
template <class M>
using NumSwitches = mechgen::internal::SwitchCount<M>;

/// M::Rhs' constants (M::Prepare), prepared again after the parameters may have changed.
template <class M>
class PreparedRhsConstants {
 public:
  using Constants = typename ModelCalls<M>::template RhsConstantsOut<M>;
  void MarkStale() { stale_ = true; }
  /// The constants of p, prepared first if stale (a model without M::Rhs has none).
  const Constants& Of(const M& model, const typename ModelTypes<M>::Params& p) {
    if constexpr (HasRhs<M>::value) {
      if (stale_ && ModelCalls<M>::HasRhs(model)) ModelCalls<M>::Prepare(model, p, &rc_);
    } else {
      (void)model, (void)p;
    }
    stale_ = false;
    return rc_;
  }
  const Constants& Of(const typename ModelTypes<M>::Params& p) { return Of(M(), p); }

 private:
  Constants rc_{};
  bool stale_ = true;
};

/// M::Rhs' output struct (ModelCalls<M>::RhsOut), or an empty placeholder where M has no Rhs.
template <class M, bool = HasRhs<M>::value>
struct RhsOutOf {
  struct type {};
};
template <class M>
struct RhsOutOf<M, true> {
  using type = typename ModelCalls<M>::template RhsOut<M>;
};
}  // namespace internal

namespace internal {
/// The type of Statics::K_rel (the generated one, or the view's bounded one); Fallback where
/// Statics has none (a model without friction joints: never read).
template <class Statics, class Fallback, class = void>
struct KrelOf {
  using type = Fallback;
};
template <class Statics, class Fallback>
struct KrelOf<Statics, Fallback, std::void_t<decltype(std::declval<Statics&>().K_rel)>> {
  using type = std::decay_t<decltype(std::declval<Statics&>().K_rel)>;
};
/// Coulomb friction with stick and slip as the minimal method simulates it
/// (friction.h's CoulombFeatures; through the model view a count known at run time, at most
/// kMaxFriction, and its inputs' count: several inputs each joint its own mode, as kNq > 1).
template <class M>
struct MinimalCoulomb : CoulombFeatures<M> {};
}  // namespace internal

/// One evaluated configuration of the minimal method.
template <class M>
struct Sample {
  static constexpr int kNq = M::kNq, kNphi = M::kNphi;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  using T_ = ModelTypes<M>;
  double t = kNaN;
  /// (NaN for a generated model's fixed sizes; empty for the view's, until assigned.)
  typename T_::VecQ q = NaNs<typename T_::VecQ>();
  typename T_::VecQ qd = q, qdd = q, Q = q;
  typename T_::VecPhi phi = NaNs<typename T_::VecPhi>();
  /// Velocity coefficients at (q, phi): phid = K qd.
  typename T_::MatK K = NaNs<typename T_::MatK>();
  double T = 0, V = 0, E = 0;  ///< kinetic, potential, T + V
  double W = 0;                ///< work of the non-conservative forces since t0
  double P_nc = 0;             ///< their power
  double rcond = 1;            ///< 1/cond_1(Phi_phi) (1 for kNphi = 0)
  double det = 1;              ///< det Phi_phi (its sign: the branch)
  /// Coulomb friction (MinimalSummary::coulomb): the friction loads f_J of the model's
  /// kFrictionJoints (dynamics/friction.h: the torque on the joint's second link by its first,
  /// N m, CCW +; the force on a slider along +u, N), included in Q and P_nc; 0 without.
  /// (Zero for a generated model's fixed size; empty for the view's, until assigned.)
  using VecFriction = typename FrictionState<internal::MinimalCoulomb<M>::kNumFriction,
                                             internal::MinimalCoulomb<M>::kMaxFriction>::VecF;
  VecFriction friction = internal::ZeroOrEmpty<VecFriction>();
  bool stuck = false;  ///< stuck by static friction (qd = qdd = 0); several inputs: any joint stuck
  /// Several inputs: joint J stuck (holding its input at rest); one input: every entry = stuck.
  std::array<bool, internal::MinimalCoulomb<M>::kMaxFriction> joint_stuck{};

  Sample() = default;
  Sample(const Sample&) = default;
  /// Every member, the vectors and K by Assign (core/model_calls.h): Eigen's assignment at a
  /// generated model's fixed sizes; at the view's bounded ones a resize and a few stores each,
  /// where Eigen's dynamic-size assignment calls its loops (a simulation copies a sample at
  /// every step).
  Sample& operator=(const Sample& o) {
    t = o.t;
    ::mechgen::Assign(&q, o.q);
    ::mechgen::Assign(&qd, o.qd);
    ::mechgen::Assign(&qdd, o.qdd);
    ::mechgen::Assign(&Q, o.Q);
    ::mechgen::Assign(&phi, o.phi);
    ::mechgen::Assign(&K, o.K);
    T = o.T;
    V = o.V;
    E = o.E;
    W = o.W;
    P_nc = o.P_nc;
    rcond = o.rcond;
    det = o.det;
    ::mechgen::Assign(&friction, o.friction);
    stuck = o.stuck;
    joint_stuck = o.joint_stuck;
    return *this;
  }
};

/// No load of the caller: the model's own Q only.
struct NoLoad {};

/// The sample observer of a simulation through the model view (issue 43): the runtime
/// instantiated once for the view (core/view_runtime.h) takes an lvalue of this type.
template <class Sim>
using ViewSampleFn = std::function<bool(const typename Sim::SampleT&)>;

/**
 * MinimalDynamics<M, Method, Load>: the minimal method on model M with the integrator Method
 * (Dopri5 or Dop853). Construct with the parameters and options, Initialize() at (t0, q0,
 * qd0), then Simulate() to t_end, or use Derivative() as the right-hand side of your own
 * integrator (bench15 does).
 *
 * Load (NoLoad: none) adds a generalized force of the caller to the model's Q (and its power
 * Q_load . qd to P_nc, so that T + V - W stays the invariant): an object held by value in the
 * simulation (each simulation its own: no shared state, so simulations run on several
 * threads at once) with
 *     void operator()(double t, const VecQ& q, const VecQ& qd, const MatK& K, VecQ* Q_load) const
 * (K: the velocity coefficients of the configuration, kNphi x kNq); e.g. engine::GasLoad.
 */
template <class M, template <int> class Method = Dopri5, class Load = NoLoad>
class MinimalDynamics {
 public:
  /// The model's sizes, constants and functions (core/model_calls.h): constant for a generated
  /// M, the view's (at run time) for ViewModel, whose sizes here are Eigen::Dynamic.
  using Calls = ModelCalls<M>;
  using Types = ModelTypes<M>;
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kN = kNq == Eigen::Dynamic ? Eigen::Dynamic : 2 * kNq + 1;  ///< (q, qd, W)
  static_assert(internal::HasDynamics<M>::value,
                "MinimalDynamics needs a model generated with `dynamics` (Model::DynamicsT)");
  static_assert(ModelFeatures<M>::kHasSolve, "MinimalDynamics needs the generated M::Solve");
  using Params = typename Types::Params;
  using Coefficients = typename Types::Coefficients;
  using Dyn = typename Calls::template DynamicsOut<M>;
  using State = internal::IntegratorState<kN>;
  using VecQ = typename Types::VecQ;
  using VecPhi = typename Types::VecPhi;
  using MatK = typename Types::MatK;
  using Modes = typename Calls::Modes;
  using Integrator = Method<kN>;
  using SampleT = Sample<M>;
  static constexpr bool kHasTrig = ModelFeatures<M>::kHasTrig;
  using Trig = typename Calls::Trig;
  /// The stages solve only the sin and cos of the angles (M::SolveTrig, no atan2); the angles
  /// are recovered, continuous with the warm start's predictor, only where a sample needs them.
  /// (For the view: whether its model may; StagesByTrig() says whether it does.)
  static constexpr bool kStagesByTrig = kHasTrig && kNphi != 0 && internal::HasSolveTrig<M>::value;
  /// ... and, where the model has it, by the one-pass M::Rhs (no residual, no points, no C).
  /// A model wrapper that changes M::Dynamics (an added load) must change M::Rhs alike.
  static constexpr bool kStagesByRhs = kStagesByTrig && internal::HasRhs<M>::value;

  static constexpr bool kHasLoad = !std::is_same_v<Load, NoLoad>;
  /// The model's loads may have switching points (M::SwitchModes): see
  /// MinimalOptions::restart_at_switches (HasSwitches(): whether they have).
  using SwitchModes = typename Calls::SwitchModesArray;
  static constexpr int kNumSwitches = static_cast<int>(std::tuple_size<SwitchModes>::value);
  static constexpr bool kHasSwitches = kNumSwitches > 0;
  /// Coulomb friction with stick and slip can be simulated (MinimalOptions::coulomb): friction
  /// joints, no caller's load (dynamics/friction.h; several inputs: each joint its own mode).
  /// Through the model view: whether it may (the view's friction joints at run time;
  /// internal::MinimalCoulomb).
  static constexpr bool kHasCoulomb = internal::MinimalCoulomb<M>::kHasFriction && !kHasLoad;
  static constexpr bool kReportsFriction = kHasCoulomb;
  static constexpr int kNumFriction = internal::MinimalCoulomb<M>::kNumFriction;
  /// kNumFriction, or the bound of the view's run-time count.
  static constexpr int kMaxFriction = internal::MinimalCoulomb<M>::kMaxFriction;
  using FrictionStateT = FrictionState<kNumFriction, kMaxFriction>;
  /// Several inputs may have each friction joint its own mode (JointModes): kNq > 1, or the
  /// view's (SeveralInputs() says at run time).
  static constexpr bool kMaySeveralInputs = kNq > 1 || kNq == Eigen::Dynamic;
  /// The run's friction joints are in JointModes (several inputs), not in stuck_ / slip_dir_.
  bool SeveralInputs() const {
    if constexpr (kNq == Eigen::Dynamic) {
      return Nq() > 1;
    } else {
      return kNq > 1;
    }
  }

  /// (A generated M only: a ViewModel names its view.)
  template <class Model = M, std::enable_if_t<!ModelCalls<Model>::kView, int> = 0>
  explicit MinimalDynamics(const Params& params, const MinimalOptions& options = MinimalOptions(),
                           Load load = Load())
      : MinimalDynamics(M(), params, options, std::move(load)) {}
  /// The simulation of `model` (a ViewModel; for a generated M an empty tag).
  MinimalDynamics(const M& model, const Params& params, const MinimalOptions& options = MinimalOptions(),
                  Load load = Load())
      : model_(model),
        nq_(Calls::Nq(model)),
        nphi_(Calls::Nphi(model)),
        stages_by_trig_(ReadStagesByTrig(model)),
        stages_by_rhs_(stages_by_trig_ && ReadHasRhs(model)),
        p_(params),
        options_(options),
        integrator_(options.integrator),
        load_(std::move(load)),
        tracker_(model, options.max_solver_iterations, options.solver_tolerance) {
    // Through the view, rhs_'s maps of its buffer placed once, for this model (its copies
    // place their own): the right-hand side calls Calls::RhsPlaced.
    if constexpr (Calls::kView && kStagesByRhs) {
      if (stages_by_rhs_) Calls::PlaceRhs(model_, &rhs_);
    }
  }

  const M& model() const { return model_; }
  /// The model's inputs (kNq, or the view's at run time).
  /// (Read once at construction: through the view each is a load from the view's table, and the
  /// right-hand side asks for them at every stage.)
  int Nq() const { return nq_; }
  int Nphi() const { return nphi_; }
  /// Whether the stages solve by sin and cos only, and by M::Rhs (kStagesByTrig, kStagesByRhs;
  /// the view's model at run time).
  bool StagesByTrig() const { return stages_by_trig_; }
  bool StagesByRhs() const { return stages_by_rhs_; }
  /// The model's loads have switching points (kHasSwitches; the view's at run time).
  bool HasSwitches() const { return Calls::NumSwitches(model_) > 0; }

  const Params& params() const { return p_; }
  /// The caller's load (a copy of it lives in each simulation).
  const Load& load() const { return load_; }
  /// The parameters, to change (the constants of M::Rhs are prepared again at the next
  /// stage).
  Params* mutable_params() {
    rhs_constants_.MarkStale();
    return &p_;
  }
  const MinimalOptions& options() const { return options_; }
  const Integrator& integrator() const { return integrator_; }
  const Modes& modes() const { return tracker_.modes(); }

  /**
   * \brief Assembles at q0 from phi_guess on the given modes and sets the reference
   * configuration of the warm starts. false when it does not assemble.
   */
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess) { return Initialize(q0, phi_guess, Calls::DefaultModes(model_)); }
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess, const Modes& modes) {
    Coefficients c;
    if (!tracker_.Assemble(model_, p_, q0, phi_guess, modes, &c, &last_solve_not_assemblable_)) return false;
    initialized_ = true;
    return true;
  }

  /// Assembles at q0 from the model's assembly guess (kAssemblyPhi, kDefaultModes).
  bool Initialize(const VecQ& q0) {
    auto guess = Sized<VecPhi>(Nphi());
    for (int i = 0; i < Nphi(); ++i) guess(i) = Calls::AssemblyPhi(model_)[i];
    return Initialize(q0, guess);
  }

  /**
   * \brief The right-hand side: dy = (qd, qdd, P_nc) at (t, y = (q, qd, W)).
   * \return false when the positions do not solve or I is not positive definite.
   */
  bool Derivative(double t, const State& y, State* dy) {
    last_.valid = false;
    if constexpr (kHasCoulomb) {
      if (coulomb_active_) return DerivativeCoulomb(t, y, dy);
    }
    if constexpr (kStagesByRhs) {
      if (StagesByRhs()) {
        if constexpr (Calls::kView && !kHasLoad) {
          return DerivativeByRhsInPlace(t, y, dy);
        } else {
          return DerivativeByRhs(t, y, dy);
        }
      }
    }
    const VecQ q = QOf(y);
    const VecQ qd = QdOf(y);
    return DerivativeBySolve(t, y, q, qd, dy);
  }

  /**
   * \brief Everything at one state: positions (warm-started from the reference), qdd, the
   * energies, Q, the conditioning of Phi_phi. Updates nothing. false if it does not solve.
   */
  bool Evaluate(double t, const State& y, SampleT* s) {
    s->t = t;
    s->q = QOf(y);
    s->qd = QdOf(y);
    s->W = y(2 * Nq());
    if constexpr (kHasCoulomb) {
      if (coulomb_active_) {
        Coefficients c;
        Dyn d;
        FrictionStateT fs;
        if (!EvalCoulomb(t, s->q, s->qd, &s->phi, &c, &d, &s->qdd, &fs)) return false;
        FillSample(d, c, fs, s);
        return true;
      }
    }
    if constexpr (Calls::kView && kHasCoulomb) s->friction = Friction::ZeroF(model_);  // (see Simulate)
    s->phi = Predictor(s->q);
    if (!SolveAt(s->q, &s->phi)) return false;
    Coefficients c;
    EvalCoefficients(s->q, s->phi, &c);
    Dyn d;
    EvalDynamics(s->q, s->phi, s->qd, t, c, &d);
    s->qdd.resize(Nq());
    if (!SolveInertia(d, &s->qdd)) return false;
    s->T = d.T;
    s->V = d.V;
    s->E = d.T + d.V;
    s->P_nc = d.P_nc;
    s->Q = d.Q;
    s->K = c.K;
    Conditioning(c, &s->rcond, &s->det);
    return true;
  }

  /// The positions phi at q (warm start from the reference configuration), and K there.
  bool Positions(const VecQ& q, VecPhi* phi, Coefficients* c) {
    *phi = Predictor(q);
    if (!SolveAt(q, phi)) return false;
    EvalCoefficients(q, *phi, c);
    return true;
  }

  /// The modes of the loads' switching items at (t, y) (M::SwitchModes at the positions there);
  /// false where the positions do not solve. Nothing for a model without switches.
  bool SwitchModesAt(double t, const State& y, SwitchModes* modes) {
    if constexpr (kHasSwitches) {
      if (!HasSwitches()) return true;
      const VecQ q = QOf(y);
      const VecQ qd = QdOf(y);
      VecPhi phi;
      Coefficients c;
      if (!Positions(q, &phi, &c)) return false;
      Calls::SwitchModes(model_, p_, q, phi, qd, t, c, modes);
      return true;
    } else {
      (void)t, (void)y, (void)modes;
      return true;
    }
  }

  /// Whether a run from q0 simulates Coulomb friction (MinimalSummary::coulomb): the option on,
  /// kHasCoulomb, and a friction joint with a coefficient (gain mu r or mu not 0) at the
  /// parameters. Initialize() first.
  bool SimulatesCoulomb(const VecQ& q0) {
    if constexpr (kHasCoulomb) {
      if (!options_.coulomb.enabled) return false;
      return AnyCoulombGain(q0);
    } else {
      (void)q0;
      return false;
    }
  }

  /// Makes (q, phi, K) the reference of the warm starts (Simulate does after each step).
  void SetReference(const VecQ& q, const VecPhi& phi, const MatK& K) {
    // The last evaluation's predictor is taken from the reference it was evaluated against
    // (FromCache: from the current one, until this changes it).
    if (last_.valid && last_.by_rhs && !last_.predicted) {
      last_.sample.phi = Predictor(QOf(last_.y));
      last_.predicted = true;
    }
    tracker_.SetReference(q, phi, K);
  }

  /**
   * \brief Integrates from (t0, q0, qd0) to t_end (Initialize() first, at q0).
   * \param[in] observer  bool(const SampleT&): called at every sample; false stops.
   * \param[in] user_event  double(double t, const VecQ& q, const VecQ& qd, const VecPhi& phi):
   *            the run stops where it changes sign (Event::kUser); NoUserEvent for none.
   * \param[out] summary  not nullptr.
   * \param[out] last  The last sample (where the run ended, or the observer stopped it). May be
   *            nullptr.
   */
  template <class Observer, class UserEvent>
  bool Simulate(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Observer&& observer,
                UserEvent&& user_event, MinimalSummary* summary, SampleT* last = nullptr) {
    *summary = MinimalSummary();
    position_failures_ = 0;
    std::string error;
    if (!options_.IsValid(&error) || !initialized_ || !(t_end > t0)) {
      summary->message = initialized_ ? "invalid options (or t_end <= t0)" : "Initialize() not called";
      EndRun();
      summary->status = Status::kInvalidInput;
      summary->t_end = t0;
      summary->integrator = integrator_.summary();
      return false;
    }
    integrator_.set_options(options_.integrator);
    // Cache the last evaluation during this run (stopped on every return by EndRun()).
    caching_ = true;
    State y0;
    // By segments: a comma initializer from 1 x 1 blocks trips GCC 12's -Warray-bounds.
    SetDerivative(q0, qd0, 0.0, &y0);
    internal::EventSettings events;
    events.min_rcond = options_.min_rcond;
    events.event_tolerance = options_.event_tolerance;
    events.sample_dt = options_.sample_dt;
    events.max_samples = options_.max_samples;
    events.steady = options_.steady;
    events.stop_at_speed_zero = options_.stop_at_speed_zero;
    events.energy_projection = options_.energy_projection;
    events.restart_at_switches = options_.restart_at_switches && kHasSwitches && HasSwitches();
    events.switch_min_interval = options_.switch_min_interval;
    events.max_switch_restarts = options_.max_switch_restarts;
    if (!StartCoulomb(t0, q0, qd0, &y0, summary)) {
      EndRun();
      summary->status = Status::kFrictionFailed;
      summary->t_end = t0;
      summary->integrator = integrator_.summary();
      return false;
    }
    events.stick_step = options_.stick_step;
    if constexpr (Calls::kView && kHasCoulomb) {
      // The view's samples carry the friction loads of every friction joint, zeros where the
      // run does not simulate Coulomb friction, as a generated model's fixed-size ones do.
      last_.sample.friction = Friction::ZeroF(model_);
    }
    return internal::EventLoop::Run(this, events, t0, y0, t_end, observer, user_event, summary, last);
  }

  /// Simulate() without a user event.
  template <class Observer>
  bool Simulate(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Observer&& observer,
                MinimalSummary* summary, SampleT* last = nullptr) {
    return Simulate(t0, q0, qd0, t_end, observer, NoUserEvent(), summary, last);
  }

 private:
  friend struct internal::EventLoop;
  template <class, class, class, class>
  friend class internal::EventLoopRun;
  static constexpr bool kCanProjectEnergy = true;
  using Friction = CoulombFriction<M>;

  /// The run's first friction mode (MinimalSummary::coulomb; coulomb_active_ where it simulates
  /// Coulomb friction): slip along qd0, or the decision at rest; several inputs each joint its
  /// own (StartJoints). false (summary's message) when the friction at rest did not converge.
  bool StartCoulomb(double t0, const VecQ& q0, const VecQ& qd0, State* y0, MinimalSummary* summary) {
    (void)y0;  // (read with several inputs only)
    coulomb_active_ = false;
    friction_failed_ = false;
    if constexpr (internal::MinimalCoulomb<M>::kHasFriction) {
      // (The view: only where its model has friction joints, as a generated model's type says.)
      if (!(options_.coulomb.enabled && Friction::Count(model_) > 0)) return true;
      if constexpr (!kHasCoulomb) {
        summary->message = "Coulomb friction is not simulated with a caller's load";
        (void)t0, (void)q0, (void)qd0, (void)y0;
      } else {
        const bool simulates = SimulatesCoulomb(q0);
        if (simulates && SeveralInputs()) {
          coulomb_active_ = true;
          summary->coulomb = true;
          if constexpr (kMaySeveralInputs) {
            // Each joint slips along its relative velocity; those at relative rest decided.
            if (!StartJoints(t0, y0, summary)) return false;
          }
        } else if (simulates) {
          coulomb_active_ = true;
          summary->coulomb = true;
          // The first mode: slip along qd0, or the decision at rest.
          stuck_ = false;
          slip_dir_ = qd0(0) < 0 ? -1.0 : 1.0;
          if (qd0(0) == 0) {
            bool stuck = false;
            double e = 1;
            if (!DecideAtRest(t0, q0, &stuck, &e)) {
              summary->message = "the friction at rest did not converge at the initial state";
              return false;
            }
            stuck_ = stuck;
            slip_dir_ = e;
          }
          if (stuck_) {
            summary->stick_intervals = 1;
            summary->last_stick_start = t0;
          }
        }
      }
    } else {
      (void)t0, (void)q0, (void)qd0, (void)y0, (void)summary;
    }
    return true;
  }

  /// A friction joint with a coefficient (gain mu r or mu not 0) at the parameters, at q0.
  bool AnyCoulombGain(const VecQ& q0) {
    VecPhi phi;
    Coefficients c;
    return Friction::Count(model_) > 0 && Positions(q0, &phi, &c) && Friction::AnyGain(model_, p_, q0, phi, c);
  }

  // ---- Coulomb friction (dynamics/friction.h): the mode (stuck, or slipping along
  // slip_dir_) is the simulation's, changed by the event loop at located transitions ----
  /// Positions, coefficients, the dynamics with the friction loads and qdd at (t, q, qd) in
  /// the current mode; false (friction_failed_ for the friction) when something fails.
  bool EvalCoulomb(double t, const VecQ& q, const VecQ& qd, VecPhi* phi, Coefficients* c, Dyn* d,
                   VecQ* qdd, FrictionStateT* fs) {
    friction_failed_ = false;
    if constexpr (kNq == Eigen::Dynamic) qdd->resize(Nq());
    *phi = Predictor(q);
    if (!SolveAt(q, phi)) return false;
    EvalCoefficients(q, *phi, c);
    if constexpr (kMaySeveralInputs) {
      if (SeveralInputs()) return EvalJoints(t, q, qd, *phi, *c, d, qdd, fs, nullptr, nullptr);
    }
    if (stuck_) {
      const VecQ zero = ZeroQ();
      EvalDynamics(q, *phi, zero, t, *c, d);
      FrictionStateT b;
      if (!Friction::Bound(model_, options_.coulomb, p_, q, *phi, t, *c, d->Q(0), &b)) {
        friction_failed_ = true;
        return false;
      }
      if (std::abs(d->Q(0)) > b.bound) breakaway_seen_ = std::min(breakaway_seen_, t);
      Friction::Holding(d->Q(0), b, fs);
      d->Q(0) += fs->Q_friction;
      d->P_nc = 0;
      *qdd = ZeroQ();
      return true;
    }
    EvalDynamics(q, *phi, qd, t, *c, d);
    const double I = d->I(0, 0);
    singular_inertia_ = !(I > 0) || !std::isfinite(I);
    if (singular_inertia_) return false;
    if (!Friction::Slip(model_, options_.coulomb, p_, q, *phi, qd, t, *c, I, d->Q(0) - d->h(0), slip_dir_, qdd,
                        fs)) {
      friction_failed_ = true;
      return false;
    }
    d->Q(0) += fs->Q_friction;
    d->P_nc += fs->Q_friction * qd(0);
    return true;
  }

  bool DerivativeCoulomb(double t, const State& y, State* dy) {
    const VecQ q = QOf(y);
    const VecQ qd = QdOf(y);
    VecPhi phi;
    Coefficients c;
    Dyn d;
    VecQ qdd;
    FrictionStateT fs;
    if (!EvalCoulomb(t, q, qd, &phi, &c, &d, &qdd, &fs)) {
      ++position_failures_;
      return false;
    }
    SetDerivative(stuck_ ? ZeroQ() : qd, qdd, d.P_nc, dy);
    if (caching_) {
      last_.t = t;
      last_.y = y;
      FillSample(d, c, fs, &last_.sample);
      last_.sample.qdd = qdd;
      last_.sample.phi = phi;
      if constexpr (kNphi != 0) last_.Phi_phi = c.Phi_phi;
      last_.by_rhs = false;
      last_.valid = true;
    }
    return true;
  }

  void FillSample(const Dyn& d, const Coefficients& c, const FrictionStateT& fs, SampleT* s) {
    s->T = d.T;
    s->V = d.V;
    s->E = d.T + d.V;
    s->P_nc = d.P_nc;
    s->Q = d.Q;
    s->K = c.K;
    s->friction = fs.f;
    if (SeveralInputs()) {
      s->joint_stuck = joints_.stuck;
      s->stuck = joints_.AnyStuck();
    } else {
      s->stuck = stuck_;
      s->joint_stuck.fill(stuck_);
    }
    Conditioning(c, &s->rcond, &s->det);
  }

  /// At rest at (t, q): *stuck, or the slip's direction *e (dynamics/friction.h: |Q0| <= B
  /// sticks; else the slip along sign(Q0) if its acceleration points that way). false: the
  /// positions or the friction failed.
  bool DecideAtRest(double t, const VecQ& q, bool* stuck, double* e) {
    VecPhi phi;
    Coefficients c;
    if (!Positions(q, &phi, &c)) return false;
    Dyn d;
    const VecQ zero = ZeroQ();
    EvalDynamics(q, phi, zero, t, c, &d);
    const double Q0 = d.Q(0);
    FrictionStateT b;
    if (!Friction::Bound(model_, options_.coulomb, p_, q, phi, t, c, Q0, &b)) return false;
    *stuck = true;
    *e = Q0 > 0 ? 1.0 : -1.0;
    if (!(std::abs(Q0) > b.bound)) return true;
    const double I = d.I(0, 0);
    if (!(I > 0) || !std::isfinite(I)) return false;
    VecQ qdd = Sized<VecQ>(Nq());
    FrictionStateT s;
    if (!Friction::Slip(model_, options_.coulomb, p_, q, phi, zero, t, c, I, Q0 - d.h(0), *e, &qdd, &s)) return false;
    *stuck = !(*e * qdd(0) > 0);
    return true;
  }
  // ---- several inputs (kNq > 1, or the view's Nq() > 1): each friction joint its own mode
  // (JointModes) ----
  /// A vector of the friction joints (bounds) and their K_rel (the generated Statics' type).
  using VecBound = typename FrictionStateT::VecF;
  using MatKrel = typename internal::KrelOf<typename Friction::Statics, Eigen::Matrix<double, kNumFriction, kNq>>::type;
  /// K_rel_J v: joint J's relative velocity (v = qd) or acceleration (v = qdd). (The view's:
  /// a sum of Nq() products in order; from three inputs on, its last bit may differ from the
  /// fixed-size instantiation's unrolled sum. No such model is shipped.)
  static double RowTimes(const MatKrel& K, int J, const VecQ& v) { return K.row(J).dot(v); }

  /// The dynamics in the joints' modes at (t, q, qd) (positions solved): EvalDynamics, then
  /// CoulombFriction::Mixed; *bound and *K_rel of every joint if not nullptr.
  bool EvalJoints(double t, const VecQ& q, const VecQ& qd, const VecPhi& phi, const Coefficients& c, Dyn* d,
                  VecQ* qdd, FrictionStateT* fs, VecBound* bound, MatKrel* K_rel) {
    EvalDynamics(q, phi, qd, t, c, d);
    VecBound B;
    MatKrel K;
    if (!Friction::Mixed(model_, options_.coulomb, p_, q, phi, qd, t, c, d->I, VecQ(d->Q - d->h), joints_, qdd, &fs->f, &B, &K,
                         &fs->iterations)) {
      friction_failed_ = true;
      return false;
    }
    // The friction's generalized force (the stuck joints' holding loads included) and power.
    // (The view's: Times, the coefficient-based product's sums; from three friction joints on
    // their last bit may differ from the fixed-size product's. No such model is shipped.)
    const VecQ Q_f = Times(K.transpose(), fs->f);
    d->Q += Q_f;
    d->P_nc += Q_f.dot(qd);
    const int nf = Friction::Count(model_);
    for (int J = 0; J < nf; ++J) {
      const bool past = joints_.stuck[J] ? std::abs(fs->f(J)) > B(J)
                                         : B(J) != 0 && !(joints_.dir[J] * RowTimes(K, J, qd) > 0);
      if (past) breakaway_seen_ = std::min(breakaway_seen_, t);
    }
    fs->Q_friction = 0;
    fs->bound = std::numeric_limits<double>::quiet_NaN();
    if (bound != nullptr) *bound = B;
    if (K_rel != nullptr) *K_rel = K;
    return true;
  }

  /// The margin of the joints' modes at (t, y): min over the joints of dir_J K_rel_J qd
  /// (slipping) and bound_J - |f_J| (stuck); *joint the joint of the minimum. false: the
  /// positions or the friction failed.
  bool FrictionMargin(double t, const State& y, double* g, int* joint) {
    const VecQ q = QOf(y);
    const VecQ qd = QdOf(y);
    VecPhi phi;
    Coefficients c;
    if (!Positions(q, &phi, &c)) return false;
    Dyn d;
    VecQ qdd;
    FrictionStateT fs;
    VecBound B;
    MatKrel K;
    if (!EvalJoints(t, q, qd, phi, c, &d, &qdd, &fs, &B, &K)) return false;
    *g = std::numeric_limits<double>::infinity();
    *joint = -1;
    const int nf = Friction::Count(model_);
    for (int J = 0; J < nf; ++J) {
      if (B(J) == 0 && !joints_.stuck[J]) continue;  // no friction there: no mode to change
      const double gJ = joints_.stuck[J] ? B(J) - std::abs(fs.f(J)) : joints_.dir[J] * RowTimes(K, J, qd);
      if (gJ < *g) {
        *g = gJ;
        *joint = J;
      }
    }
    return true;
  }

  /// Decides the modes of the joints in `at_rest` (each at zero relative velocity, or stuck)
  /// at (t, *y): each must hold one input (CoulombFriction::InputJoint; else a failure naming
  /// it in *failed_joint), whose speed is set 0 in *y; all stuck first, then the one whose
  /// holding load exceeds its bound the most released at a time (slipping against its holding
  /// load) until every stuck one holds, a released one whose slip would at once stop again
  /// (dir_J K_rel_J qdd <= 0) stuck for good. false: the friction failed (*failed_joint -1) or
  /// no consistent mode.
  bool DecideJoints(double t, State* y, const std::array<bool, kMaxFriction>& at_rest, int* failed_joint) {
    *failed_joint = -1;
    const VecQ q = QOf(*y);
    VecPhi phi;
    Coefficients c;
    if (!Positions(q, &phi, &c)) return false;
    Dyn d;
    VecQ qdd;
    FrictionStateT fs;
    VecBound B;
    MatKrel K;
    // K_rel from one evaluation (it does not depend on the modes).
    {
      typename Friction::Statics st;
      const VecQ zero = ZeroQ();
      Friction::Kineto(model_, p_, q, phi, zero, zero, t, c, &st, nullptr);
      K = st.K_rel;
    }
    const int nf = Friction::Count(model_);
    std::array<bool, kMaxFriction> final_stuck{};
    for (int J = 0; J < nf; ++J) {
      if (!at_rest[J]) continue;
      int i = -1;
      double k = 0;
      if (!Friction::InputJoint(K, J, &i, &k)) {
        *failed_joint = J;
        return false;
      }
      joints_.stuck[J] = true;
      joints_.held[J] = i;
      joints_.k[J] = k;
      (*y)(Nq() + i) = 0;
    }
    for (int J = 0; J < nf; ++J)
      for (int L = J + 1; L < nf; ++L)
        if (joints_.stuck[J] && joints_.stuck[L] && joints_.held[J] == joints_.held[L]) {
          *failed_joint = L;  // two joints holding one input: indeterminate
          return false;
        }
    const VecQ qd = QdOf(*y);
    for (int pass = 0; pass < 2 * nf + 2; ++pass) {
      if (!EvalJoints(t, q, qd, phi, c, &d, &qdd, &fs, &B, &K)) return false;
      int worst = -1;
      double excess = 1;
      for (int J = 0; J < nf; ++J) {
        if (!at_rest[J] || !joints_.stuck[J] || final_stuck[J]) continue;
        const double a = std::abs(fs.f(J));
        const double ratio = B(J) > 0 ? a / B(J) : (a > 0 ? std::numeric_limits<double>::infinity() : 0);
        if (ratio > excess) {
          excess = ratio;
          worst = J;
        }
      }
      if (worst >= 0) {
        joints_.stuck[worst] = false;
        joints_.dir[worst] = fs.f(worst) > 0 ? -1.0 : 1.0;
        continue;
      }
      int inconsistent = -1;
      for (int J = 0; J < nf && inconsistent < 0; ++J)
        if (at_rest[J] && !joints_.stuck[J] && !(joints_.dir[J] * RowTimes(K, J, qdd) > 0)) inconsistent = J;
      if (inconsistent < 0) return true;
      joints_.stuck[inconsistent] = true;
      final_stuck[inconsistent] = true;
    }
    return false;
  }

  /// The first modes of a run from y0 (several inputs): joints moving slip along their
  /// relative velocity, those at relative rest decided (DecideJoints). false: a status.
  bool StartJoints(double t0, State* y0, MinimalSummary* summary) {
    const VecQ q = QOf(*y0);
    const VecQ qd = QdOf(*y0);
    VecPhi phi;
    Coefficients c;
    if (!Positions(q, &phi, &c)) {
      summary->message = "the initial state does not assemble";
      return false;
    }
    typename Friction::Statics st;
    const VecQ zero = ZeroQ();
    Friction::Kineto(model_, p_, q, phi, zero, zero, t0, c, &st, nullptr);
    std::array<bool, kMaxFriction> at_rest{};
    bool any = false;
    joints_ = JointModes<kMaxFriction>();
    const int nf = Friction::Count(model_);
    for (int J = 0; J < nf; ++J) {
      const double v = RowTimes(st.K_rel, J, qd);
      joints_.dir[J] = v < 0 ? -1.0 : 1.0;
      joints_.held[J] = -1;
      at_rest[J] = v == 0 && st.gain(J) != 0;
      any = any || at_rest[J];
    }
    stuck_since_.fill(t0);
    if (!any) return true;
    int failed = -1;
    if (!DecideJoints(t0, y0, at_rest, &failed)) {
      NameFailure(failed, "at the initial state", summary);
      return false;
    }
    for (int J = 0; J < nf; ++J)
      if (joints_.stuck[J]) {
        ++summary->stick_intervals;
        summary->last_stick_start = t0;
      }
    return true;
  }

  /// A transition at (t, *y) (several inputs): the joints at or past their margin's zero
  /// decided again; the summary's stuck bookkeeping. false: a status (the message set).
  bool ResolveJoints(double t, State* y, MinimalSummary* summary) {
    const JointModes<kMaxFriction> before = joints_;
    std::array<bool, kMaxFriction> at_rest{};
    const int nf = Friction::Count(model_);
    // Every joint whose margin is not positive here (slipping: at relative rest; stuck: at
    // its bound), and every stuck one (their holding loads change with the others' modes).
    {
      const VecQ q = QOf(*y);
      const VecQ qd = QdOf(*y);
      VecPhi phi;
      Coefficients c;
      Dyn d;
      VecQ qdd;
      FrictionStateT fs;
      VecBound B;
      MatKrel K;
      if (!Positions(q, &phi, &c) || !EvalJoints(t, q, qd, phi, c, &d, &qdd, &fs, &B, &K)) {
        summary->message = "the friction loads did not converge at a stick-slip transition";
        return false;
      }
      for (int J = 0; J < nf; ++J) {
        if (joints_.stuck[J]) {
          at_rest[J] = true;
        } else if (B(J) != 0) {
          at_rest[J] = !(joints_.dir[J] * RowTimes(K, J, qd) > 0);
        }
      }
    }
    int failed = -1;
    if (!DecideJoints(t, y, at_rest, &failed)) {
      NameFailure(failed, "at a stick-slip transition", summary);
      return false;
    }
    for (int J = 0; J < nf; ++J) {
      if (before.stuck[J] && !joints_.stuck[J]) summary->time_stuck += t - stuck_since_[J];
      if (!before.stuck[J] && joints_.stuck[J]) {
        ++summary->stick_intervals;
        summary->last_stick_start = t;
        stuck_since_[J] = t;
      }
    }
    last_.valid = false;
    return true;
  }

  /// The time the joints stuck at the run's end t have been stuck (added to the summary).
  void CloseStuck(double t, MinimalSummary* summary) const {
    const int nf = Friction::Count(model_);
    for (int J = 0; J < nf; ++J)
      if (joints_.stuck[J] && t >= stuck_since_[J]) summary->time_stuck += t - stuck_since_[J];
  }

  void NameFailure(int joint, const char* where, MinimalSummary* summary) {
    (void)where;
    if (joint >= 0) {
      summary->friction_joint = Calls::FrictionJoint(model_, joint);
      summary->message =
          "a friction joint came to relative rest whose relative motion is not one input's alone (or "
          "shares its input with another stuck joint): its stick is not simulated with several inputs";
    } else {
      summary->message = "the friction at rest did not converge, or no stick-slip mode is consistent";
    }
  }

  /// The earliest time an evaluation of this step saw a mode's margin crossed (one input,
  /// stuck: |Q0| > B; several: a joint's margin <= 0), +inf if none: the event loop checks it
  /// where the step's end does not show a transition.
  void BeginFrictionStep() { breakaway_seen_ = std::numeric_limits<double>::infinity(); }
  double BreakawaySeen() const { return breakaway_seen_; }
  bool CoulombActive() const { return coulomb_active_; }
  bool Stuck() const {
    if (SeveralInputs()) return joints_.AnyStuck();
    return stuck_;
  }
  double SlipDirection() const { return slip_dir_; }
  void SetFrictionMode(bool stuck, double e) {
    stuck_ = stuck;
    slip_dir_ = e;
    last_.valid = false;
  }

  // ---- the hooks of the event loop (simulator.h) ----
  void EndRun() {
    caching_ = false;
    last_.valid = false;
  }
  static double Balance(const SampleT& s) { return s.E - s.W; }
  static void Record(const SampleT&, MinimalSummary*) {}
  static void OnDeadPoint(SampleT*) {}
  /// The accepted step's configuration (from the last stage when it was there), made the
  /// reference of the warm starts.
  bool Accept(double t, const State& y, SampleT* cur) {
    if (!FromCache(t, y, cur) && !Evaluate(t, y, cur)) return false;
    SetReference(cur->q, cur->phi, cur->K);
    tracker_.set_ref_det(cur->det);
    return true;
  }
  /// Energy projection (MinimalOptions::energy_projection) of the accepted state *cur.
  template <class F>
  bool ProjectEnergy(F& f, double E0, SampleT* cur) {
    const double T_target = E0 + cur->W - cur->V;
    const double scale = std::max({std::abs(E0), std::abs(cur->T), std::abs(cur->V), 1e-300});
    if (!(T_target > 0 && cur->T > options_.energy_floor * scale)) return false;
    State y = integrator_.y();
    if constexpr (kNq != Eigen::Dynamic) {
      y.template segment<kNq>(kNq) *= std::sqrt(T_target / cur->T);
    } else {
      y.segment(Nq(), Nq()) *= std::sqrt(T_target / cur->T);
    }
    if (!integrator_.Reset(f, y)) return false;
    cur->qd = QdOf(y);
    cur->qdd = QdOf(integrator_.dy());
    cur->T = T_target;
    cur->E = cur->T + cur->V;
    return true;
  }

  bool SolveAt(const VecQ& q, VecPhi* phi) {
    return tracker_.SolveAt(model_, p_, q, phi, &last_solve_not_assemblable_);
  }

  void EvalCoefficients(const VecQ& q, const VecPhi& phi, Coefficients* c) {
    internal::CallCoeffs(model_, p_, q, phi, c, tracker_.trig());
  }

  void EvalDynamics(const VecQ& q, const VecPhi& phi, const VecQ& qd, double t,
                    const Coefficients& c, Dyn* d) {
    internal::CallDynamics(model_, p_, q, phi, qd, t, c, d, tracker_.trig());
    AddLoad(t, q, qd, c.K, &d->Q, &d->P_nc);
  }

  /// The caller's load added to Q and its power to P_nc (nothing without one).
  template <class MatK, class VecQLike>
  void AddLoad(double t, const VecQ& q, const VecQ& qd, const MatK& K, VecQLike* Q, double* P_nc) const {
    if constexpr (kHasLoad) {
      VecQ Q_load;
      load_(t, q, qd, K, &Q_load);
      *Q += Q_load;
      *P_nc += Q_load.dot(qd);
    } else {
      (void)t, (void)q, (void)qd, (void)K, (void)Q, (void)P_nc;
    }
  }

  bool SolveInertia(const Dyn& d, VecQ* qdd) { return SolveInertia(d.I, d.Q - d.h, qdd); }
  /// qdd = I^-1 f; false (singular_inertia_) unless I is positive definite. (A Dynamic I, the
  /// view's: on a fixed-size copy of its size, the same arithmetic.)
  template <class MatI, class VecF>
  bool SolveInertia(const MatI& I, const VecF& f, VecQ* qdd) {
    if constexpr (kNq == Eigen::Dynamic) {
      if (Nq() == 1) {
        qdd->resize(1);
        return SolveInertia1(I(0, 0), f(0), qdd->data());
      }
      singular_inertia_ = false;
      return SolveInertiaFixed<2>(I, f, qdd);
    } else {
      return SolveInertiaOf(Eigen::Matrix<double, kNq, kNq>(I), VecQ(f), qdd);
    }
  }
  /// The one-input case of a Dynamic I (the view's): qdd = f / I, false (singular_inertia_)
  /// unless I > 0 and finite, or where qdd is not finite.
  MECHGEN_ALWAYS_INLINE bool SolveInertia1(double I00, double f0, double* qdd) {
    singular_inertia_ = false;
    if (!(I00 > 0) || !std::isfinite(I00)) {
      singular_inertia_ = true;
      return false;
    }
    *qdd = f0 / I00;
    return std::isfinite(*qdd);  // (qdd->allFinite(), without Eigen's reduction)
  }
  /// The inertia solve of a Dynamic I of size k or more, on a k x k copy.
  template <int k, class MatI, class VecF>
  bool SolveInertiaFixed(const MatI& I, const VecF& f, VecQ* qdd) {
    if constexpr (k <= Types::kMaxQ) {
      if (I.rows() != k) return SolveInertiaFixed<k + 1>(I, f, qdd);
      const Eigen::Matrix<double, k, k> Ik = I;
      const Eigen::Matrix<double, k, 1> fk = f;
      Eigen::Matrix<double, k, 1> qddk;
      const Eigen::LDLT<Eigen::Matrix<double, k, k>> ldlt(Ik);
      singular_inertia_ = false;
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
        singular_inertia_ = true;
        return false;
      }
      qddk = ldlt.solve(fk);
      *qdd = qddk;
      return qdd->allFinite();
    } else {
      (void)I, (void)f, (void)qdd;
      singular_inertia_ = true;
      return false;
    }
  }
  bool SolveInertiaOf(const Eigen::Matrix<double, (kNq > 0 ? kNq : 1), (kNq > 0 ? kNq : 1)>& I,
                      const Eigen::Matrix<double, (kNq > 0 ? kNq : 1), 1>& f,
                      VecQ* qdd) {
    singular_inertia_ = false;
    if constexpr (kNq == 1) {
      const double I00 = I(0, 0);
      if (!(I00 > 0) || !std::isfinite(I00)) {
        singular_inertia_ = true;
        return false;
      }
      (*qdd)(0) = f(0) / I00;
    } else {
      const Eigen::LDLT<Eigen::Matrix<double, kNq, kNq>> ldlt(I);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
        singular_inertia_ = true;
        return false;
      }
      *qdd = ldlt.solve(f);
    }
    return qdd->allFinite();
  }

  void Conditioning(const Coefficients& c, double* rcond, double* det) {
    if constexpr (kNphi == 0) {
      (void)c;
      *rcond = 1;
      *det = 1;
    } else {
      internal::ConditioningOf(c.Phi_phi, rcond, det);
    }
  }

  /// The sample at (t, y) from the last Derivative() call, if it was at exactly (t, y).
  /// (By M::Rhs it takes the predictor, once: last_.predicted.)
  bool FromCache(double t, const State& y, SampleT* s) {
    if (!last_.valid || last_.t != t || !SameState(last_.y, y)) return false;
    bool by_rhs = false;
    if constexpr (kStagesByRhs) by_rhs = last_.by_rhs;
    if (by_rhs) {
      if constexpr (kStagesByRhs) {
        // By M::Rhs: its outputs read where it wrote them (CacheRhs keeps only the state and
        // qdd), the predictor taken from the reference of the evaluation (now, or by
        // SetReference() before it moved) and kept, so that it is taken once. The sample's
        // other members are the cache's (as *s = last_.sample), member by member: the rest
        // of it is written below.
        // (Assign: Eigen's assignment at a fixed size; at the view's bounded Dynamic one a
        // resize and a few stores, where Eigen's dynamic-size assignment calls its loops.)
        if (!last_.predicted) {
          last_.sample.phi = Predictor(QOf(y));
          last_.predicted = true;
        }
        ::mechgen::Assign(&s->phi, last_.sample.phi);
        ::mechgen::Assign(&s->qdd, last_.sample.qdd);
        ::mechgen::Assign(&s->K, rhs_.K);
        ::mechgen::Assign(&s->Q, rhs_.Q);
        s->T = rhs_.T;
        s->V = rhs_.V;
        s->P_nc = rhs_.P_nc;
        ::mechgen::Assign(&s->friction, last_.sample.friction);
        s->stuck = last_.sample.stuck;
        s->joint_stuck = last_.sample.joint_stuck;
      }
    } else {
      *s = last_.sample;
    }
    s->t = t;
    PartInto(y, 0, &s->q);
    PartInto(y, Nq(), &s->qd);
    s->W = y(2 * Nq());
    s->E = s->T + s->V;
    if constexpr (kStagesByTrig) {
      // The angles from their sin and cos, within pi of the predictor (sample.phi); with
      // Coulomb friction the stages solved the angles themselves.
      const double two_pi = 6.283185307179586;
      for (int i = 0; i < Nphi() && !coulomb_active_ && StagesByTrig(); ++i) {
        const double angle =
            std::atan2(Calls::TrigSinPhi(model_, last_.trig, i), Calls::TrigCosPhi(model_, last_.trig, i));
        const double turns = std::floor((angle - s->phi(i)) / two_pi + 0.5);
        s->phi(i) = std::isfinite(turns) ? angle - two_pi * turns : angle;
      }
    }
    if constexpr (kStagesByRhs) {
      if (by_rhs) {
        if constexpr (std::is_same_v<std::decay_t<decltype(rhs_.Phi_phi)>, typename Types::MatCPhi>) {
          internal::ConditioningOf(rhs_.Phi_phi, &s->rcond, &s->det);
        } else {
          // (the view's map of its buffer, read through the const map that
          // ConditionAndDeterminantDynamic is instantiated for: no copy of its bounded size)
          const Eigen::Map<const Eigen::MatrixXd> Phi_phi(rhs_.Phi_phi.data(), rhs_.Phi_phi.rows(),
                                                          rhs_.Phi_phi.cols());
          internal::ConditioningOf(Phi_phi, &s->rcond, &s->det);
        }
        return true;
      }
    }
    internal::ConditioningOf(last_.Phi_phi, &s->rcond, &s->det);
    return true;
  }

  // ---- the right-hand side's two ways (Derivative) ----
  /// By the one generated pass M::Rhs (kStagesByRhs). (The view without a caller's load:
  /// DerivativeByRhsInPlace, the same arithmetic.)
  bool DerivativeByRhs(double t, const State& y, State* dy) {
    const VecQ q = QOf(y);
    const VecQ qd = QdOf(y);
    // One generated pass (M::Rhs): positions by their sin and cos, K, L, I, h, Q.
    last_solve_not_assemblable_ = false;
    auto& r = rhs_;
    const auto report = Calls::Rhs(model_, p_, rhs_constants_.Of(model_, p_), q, qd, t, tracker_.modes(), &last_.trig, &r);
    if (report.status != decltype(report.status)::kConverged) {
      last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
      ++position_failures_;
      return false;
    }
    AddLoad(t, q, qd, r.K, &r.Q, &r.P_nc);
    auto qdd = Sized<VecQ>(Nq());
    if (!SolveInertia(r.I, r.Q - r.h, &qdd)) return false;
    SetDerivative(qd, qdd, r.P_nc, dy);
    if (caching_) CacheRhs(t, y, qdd);
    return true;
  }

  /// DerivativeByRhs() through the model view without a caller's load: q and qd read in place
  /// from y and qd written from there into dy (no VecQ copies of the state, each a loop over
  /// a run-time count), inline in Derivative(). The same values in the same order.
  MECHGEN_ALWAYS_INLINE bool DerivativeByRhsInPlace(double t, const State& y, State* dy) {
    last_solve_not_assemblable_ = false;
    const int nq = Nq();
    const double* const q = y.data();
    const double* const qd = q + nq;
    auto& r = rhs_;  // (its maps placed by the constructor)
    const auto report =
        Calls::RhsPlaced(model_, p_, rhs_constants_.Of(model_, p_), q, qd, t, tracker_.modes(), &last_.trig, &r);
    if (report.status != decltype(report.status)::kConverged) {
      last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
      ++position_failures_;
      return false;
    }
    if (nq == 1) {
      // One input (most models): the same on the buffer's entries, no VecQ (a bounded vector
      // and its size) between them.
      double qdd0 = 0;
      if (!SolveInertia1(r.I.data()[0], r.Q.data()[0] - r.h.data()[0], &qdd0)) return false;
      if (caching_) {
        CacheRhsState(t, y);
        last_.sample.qdd.resize(1);
        last_.sample.qdd(0) = qdd0;
      }
      dy->resize(3);
      double* const d = dy->data();
      d[0] = qd[0];  // (dy may be y: qd[0] is y(1), read before d[1] is written)
      d[1] = qdd0;
      d[2] = r.P_nc;
      return true;
    }
    auto qdd = Sized<VecQ>(nq);
    if (!SolveInertia(r.I, r.Q - r.h, &qdd)) return false;
    if (caching_) CacheRhs(t, y, qdd);  // (before dy is written: dy may be y)
    dy->resize(2 * nq + 1);
    ::mechgen::internal::CopyEntries(qd, nq, dy->data());  // (reads y's qd, writes over its q only)
    ::mechgen::internal::CopyEntries(qdd.data(), nq, dy->data() + nq);
    (*dy)(2 * nq) = r.P_nc;
    return true;
  }
  /// The last evaluation, by M::Rhs, for Simulate() (see DerivativeBySolve()): kept at every
  /// call of a simulation's right-hand side, so it keeps only the state and qdd. M::Rhs wrote
  /// the rest where FromCache() reads it (rhs_, and its sin and cos in last_.trig), and the
  /// predictor is taken there (or by SetReference(), before the reference moves).
  void CacheRhs(double t, const State& y, const VecQ& qdd) {
    CacheRhsState(t, y);
    ::mechgen::Assign(&last_.sample.qdd, qdd);
  }
  /// CacheRhs() but qdd (which the caller writes).
  MECHGEN_ALWAYS_INLINE void CacheRhsState(double t, const State& y) {
    last_.t = t;
    ::mechgen::Assign(&last_.y, y);  // (at every evaluation: see FromCache() on Assign)
    last_.by_rhs = true;
    last_.predicted = false;
    last_.valid = true;
  }

  /// By the positions (M::SolveTrig's sin and cos, or M::Solve), then the coefficients and
  /// the dynamics.
  bool DerivativeBySolve(double t, const State& y, const VecQ& q, const VecQ& qd, State* dy) {
    VecPhi phi = Predictor(q);
    bool by_trig = false;
    if constexpr (kStagesByTrig) by_trig = StagesByTrig();
    if (by_trig) {
      if constexpr (kStagesByTrig) {
        // sin and cos only: phi stays the predictor, which the generated functions given trig
        // do not read; FromCache() recovers the angles at an accepted step.
        last_solve_not_assemblable_ = false;
        const auto report = Calls::SolveTrig(model_, p_, q, tracker_.modes(), tracker_.trig());
        if (report.status != decltype(report.status)::kConverged) {
          last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
          ++position_failures_;
          return false;
        }
      }
    } else if (!SolveAt(q, &phi)) {
      ++position_failures_;
      return false;
    }
    Coefficients c;
    EvalCoefficients(q, phi, &c);
    Dyn d;
    EvalDynamics(q, phi, qd, t, c, &d);
    auto qdd = Sized<VecQ>(Nq());
    if (!SolveInertia(d, &qdd)) return false;
    SetDerivative(qd, qdd, d.P_nc, dy);
    if (caching_) {
      // Simulate() reuses the last evaluation (the FSAL one at the accepted step's end) for
      // the step's events and samples instead of evaluating that state again.
      last_.t = t;
      last_.y = y;
      last_.sample.phi = phi;
      last_.sample.K = c.K;
      last_.sample.qdd = qdd;
      last_.sample.Q = d.Q;
      last_.sample.T = d.T;
      last_.sample.V = d.V;
      last_.sample.P_nc = d.P_nc;
      if constexpr (kNphi != 0) last_.Phi_phi = c.Phi_phi;
      if constexpr (kStagesByTrig) {
        if (by_trig) Calls::CopyTrig(model_, *tracker_.trig(), &last_.trig);
      }
      last_.by_rhs = false;
      last_.valid = true;
    }
    return true;
  }

  /// StagesByTrig() of `model`: kStagesByTrig, or the view's at run time.
  static bool ReadStagesByTrig(const M& model) {
    if constexpr (Calls::kView) {
      return Calls::HasSolveTrig(model) && Calls::Nphi(model) > 0;
    } else {
      (void)model;
      return kStagesByTrig;
    }
  }
  /// Whether the view's model has M::Rhs (a generated model: kStagesByRhs says).
  static bool ReadHasRhs(const M& model) {
    if constexpr (Calls::kView) {
      return Calls::HasRhs(model);
    } else {
      (void)model;
      return kStagesByRhs;
    }
  }

  // ---- the state's parts and the warm start, at the model's sizes ----
  // (The view: the entries copied by ::mechgen::internal::CopyEntries, without Eigen's
  // dynamic-size assignment, whose set-up costs more than a small model's few entries.)
  /// *v = the Nq() entries of y from `first` (0: q, Nq(): qd), written in place.
  MECHGEN_ALWAYS_INLINE void PartInto(const State& y, int first, VecQ* v) const {
    if constexpr (kNq != Eigen::Dynamic) {
      *v = y.template segment<kNq>(first);
    } else {
      v->resize(Nq());
      ::mechgen::internal::CopyEntries(y.data() + first, Nq(), v->data());
    }
  }
  /// a == b entry by entry (Eigen's == at a fixed size; at a Dynamic one a loop, and false
  /// where the sizes differ). A NaN equals nothing, as with Eigen's.
  static bool SameState(const State& a, const State& b) {
    if constexpr (kN != Eigen::Dynamic) {
      return a == b;
    } else {
      if (a.size() != b.size()) return false;
      for (Eigen::Index i = 0; i < a.size(); ++i) {
        if (!(a(i) == b(i))) return false;
      }
      return true;
    }
  }
  VecQ QOf(const State& y) const {
    VecQ q;
    PartInto(y, 0, &q);
    return q;
  }
  VecQ QdOf(const State& y) const {
    VecQ qd;
    PartInto(y, Nq(), &qd);
    return qd;
  }
  /// *y = (a, b, w): a state (q, qd, W) or its derivative (qd, qdd, P_nc).
  void SetDerivative(const VecQ& a, const VecQ& b, double w, State* y) const {
    if constexpr (kNq != Eigen::Dynamic) {
      y->template head<kNq>() = a;
      y->template segment<kNq>(kNq) = b;
      (*y)(2 * kNq) = w;
    } else {
      const int nq = Nq();
      y->resize(2 * nq + 1);
      ::mechgen::internal::CopyEntries(a.data(), nq, y->data());
      ::mechgen::internal::CopyEntries(b.data(), nq, y->data() + nq);
      (*y)(2 * nq) = w;
    }
  }
  /// phi_ref + K_ref (q - q_ref): the warm start of the positions at q.
  VecPhi Predictor(const VecQ& q) const { return tracker_.Predictor(q); }
  VecQ ZeroQ() const {
    if constexpr (kNq != Eigen::Dynamic) {
      return VecQ::Zero();
    } else {
      return VecQ::Zero(Nq());
    }
  }
  M model_;
  // The model's sizes and how the stages solve, read once (Nq(), Nphi(), StagesByTrig(),
  // StagesByRhs()).
  int nq_;
  int nphi_;
  bool stages_by_trig_;
  bool stages_by_rhs_;
  Params p_;
  MinimalOptions options_;
  Integrator integrator_;
  Load load_;
  PositionTracker<M> tracker_;  ///< the positions along the run: modes, reference, branch, sin and cos
  internal::PreparedRhsConstants<M> rhs_constants_;  ///< kStagesByRhs: M::Prepare(p_)
  struct LastEvaluation {
    bool valid = false;
    double t = 0;
    State y = internal::ZeroState<State>();
    SampleT sample;
    typename Types::MatCPhi Phi_phi = internal::ZeroState<typename Types::MatCPhi>();
    Trig trig{};  ///< kStagesByTrig: the stage's sin and cos, for the angles
    /// By M::Rhs (CacheRhs): phi (the predictor), K, Q, T, V, P_nc and Phi_phi are rhs_'s
    /// (phi in sample once SetReference() took it: predicted).
    bool by_rhs = false;
    bool predicted = false;
  };
  LastEvaluation last_;
  /// M::Rhs' output at the last stage (kStagesByRhs), where FromCache() reads it.
  typename internal::RhsOutOf<M>::type rhs_{};
  bool caching_ = false;
  int position_failures_ = 0;
  bool initialized_ = false, last_solve_not_assemblable_ = false, singular_inertia_ = false;
  bool coulomb_active_ = false, stuck_ = false, friction_failed_ = false;
  double slip_dir_ = 1;
  double breakaway_seen_ = std::numeric_limits<double>::infinity();
  JointModes<kMaxFriction> joints_;                  ///< several inputs: each joint's mode
  std::array<double, kMaxFriction> stuck_since_{};  ///< ... and when it stuck
};

}  // namespace mechgen::dynamics
