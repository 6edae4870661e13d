/**
 * \file machines/flywheel/machine_cycle.h
 * Flywheel sizing of any one-DOF machine with forces (Paul §6.9): the driving torque a
 * constant-speed motor must supply over one cycle of the input, its energy loop, the flywheel
 * for a coefficient of speed fluctuation C_s, and (with `dynamics`) a simulated check of that
 * flywheel under a motor law. The engines' own tool (engine_main.cc) does the same for gas
 * forces; this header is for the shaper, the punch press, the crusher: any generated model
 * with one input and the output `forces`.
 *
 * 1. The required torque (SampleMachineCycle). The input θ moves at the constant speed ω_m
 *    (> 0, counter-clockwise) over one cycle [θ_0, θ_0 + Θ): N samples θ_k = θ_0 + k Θ/N, the
 *    positions continued from the model's assembly configuration (sweep/sweep.h, the position
 *    solver's branch kept). At each sample
 *        T_req(θ) = T_static(θ) + T_dynamic(θ)                                     (N m, CCW +)
 *    T_static: the statics driving torque of the loads, weights and springs (statics/solve.h,
 *    the generated EvalStatics by virtual work; with Coulomb friction the friction iterated
 *    for the motion in +θ: the torque to run forward). T_dynamic, with the quantity
 *    `dynamics` only: Paul's one-DOF equation I(θ) θ̈ + ½ I'(θ) θ̇² = Q(θ, θ̇) at θ̇ = ω_m,
 *    θ̈ = 0 asks for the torque ½ I'(θ) ω_m² − Q(θ, ω_m) (the generated EvalDynamics' h and Q:
 *    the drive of EvalKinetostatics at that motion), of which the statics already counted
 *    the position-dependent part −Q_static = drive_0 (frictionless), so
 *        T_dynamic = h(θ, ω_m) − (Q(θ, ω_m) − Q_static(θ)),  h = ½ I' ω_m²:
 *    the inertia torque plus what the speed-dependent loads (dampers, viscous friction,
 *    speed tables) need. Without `dynamics` the machine is taken as massless (T_dynamic = 0).
 *    Coulomb friction is that of the static loads: the share of the bearing loads that the
 *    inertia forces add is not in it (a friction iteration on the kinetostatics is not done).
 *    A sample where the positions fail, or at a dead point (cond_1(Phi_phi) above the statics'
 *    max_condition: the driving torque grows without bound there), ends the sampling with a
 *    status and the angle: never a huge number.
 * 2. The energy loop (machines/flywheel/energy_loop.h, ExcessEnergy): a motor of constant
 *    torque T_m = mean(T_req) (the steady cycle: the motor's work per cycle equals the load's)
 *    leaves the excess torque ΔT = T_m − T_req, the excess energy E(θ) = ∫_{θ_0}^{θ} ΔT
 *    (E(θ_0) = 0), ΔE = E_max − E_min, and the constant inertia I_req = ΔE/(C_s ω_m²) that keeps
 *    the speed within ±C_s/2 of ω_m. With `dynamics` the machine already has I(θ): the flywheel
 *    to add is I_fly = I_req − mean I(θ) (as the engine tool does); without, I_fly = I_req.
 *    A machine whose loads do no net work (weights, springs, constant forces, the inertia
 *    torque: a conservative one) has T_mean = 0 but for rounding, of either sign by where the
 *    samples fall: |T_mean| <= 8 ε N max_k max(|T_req|, |T_static|, |T_inertia|, |T_speed|)
 *    is zero (MachineCycle::zero_mean; T_mean and the work set to exactly 0), and the machine
 *    is sized alike for both signs: the flywheel evens out the energy its inertia, weights and
 *    springs exchange. A mean negative beyond that is kNoLoad (the loads drive the machine).
 *    Accuracy: E is the 4-point rule of energy_loop.h, fourth order in the sample step h = Θ/N
 *    where T_req is smooth. A switched load (step(), clamp(), mod() in the model) makes T_req
 *    kink (a force switched on where its point does not move, e.g. the shaper's cut at the
 *    ram's dead points) or jump (a force switched on while its point moves); E is then second
 *    order at a kink (error h²/12 × the slope jump: the trapezoid's end terms) and first order
 *    at a jump between samples (error up to h × the torque jump / 2). A break (an angle in
 *    MachineCycleOptions::breaks, or a switch of the loads located from the generated switch
 *    modes: switch_breaks) keeps E fourth order (energy_loop.h's one-sided stencils, and each
 *    side's cubic in an interval with a break inside): at a kink or a jump, between samples
 *    or on one (whose value is then given to the side whose extrapolation it matches). The
 *    loop's closure, Θ × mean(T_req), is the periodic trapezoid rule (or with breaks the
 *    break-aware rule): exact to rounding for a smooth periodic T_req, second order at a kink
 *    that is not a break.
 * 3. The simulated check (CheckBySimulation, `dynamics` only): the model with I_fly added to
 *    the input (WithFlywheel<M>: I(θ) + I_fly in the generated dynamics) driven by a motor
 *    law (MotorLoad): kConstant, T = T_m; or kShunt, the linear torque–speed line of a
 *    shunt (or induction, near synchronism) motor T = T_stall (1 − ω/ω_0) through (ω_m, T_m)
 *    with the slip s = 1 − ω_m/ω_0 (T_stall = T_m/s). The run starts on the sized cycle: at θ_0
 *    with the speed the energy loop predicts there (½ I ω² = ½ I ω_m² + E − ½(E_max + E_min)),
 *    so it is near the periodic orbit from the first cycle. The one-DOF simulator
 *    (dynamics/forward.h, Dopri5) integrates until the cycle is steady by what C_s needs: the
 *    cycle-mean speed changing per cycle, relative, by less than steady_fraction (1e-3) times
 *    the C_s expected for this flywheel, ΔE/((I_fly + mean I) ω_m²), two cycles in a row
 *    (dynamics/simulator.h's detection), so the drift inside the measured cycle is that
 *    fraction of its ω_max − ω_min. What is left of the start's offset decays with the settling
 *    time τ = (I_fly + mean I)/b, b the slope of the mean load less the motor's torque against
 *    the speed (mean ∂T_req/∂ω by the loop's rule, plus T_stall/ω_0 for the shunt motor): a
 *    change c per cycle leaves about c τ/P to go, so the tolerance is divided by τ/P when that
 *    is above 1, and the run is allowed max_cycles, or 10 τ when that is longer (both when 10 τ
 *    is within kMaxSettlingCycles). A heavy flywheel with loads whose mean hardly depends on the speed
 *    (b near 0: the constant-torque motor with loads of the position only, a neutral cycle, or
 *    a cutting force switched by a table of the ram's speed) settles over thousands of
 *    cycles, but its mean speed only creeps, by (the error of Θ T_mean)/(I ω²) per cycle, far
 *    below that tolerance: steady from the first cycles, the creep reported (last_change).
 *    The slope is an estimate for loads smooth in the speed: a steep table's band near a
 *    switch enters it only through the samples that fall in it (the run's length, not the
 *    verdict, depends on it). The last cycle's speed trace, sampled at equal times, gives
 *    C_s = (ω_max − ω_min)/ω_mid (AnalyzeSpeedTrace), its extremes refined between samples by
 *    the cubic Hermite of ω and dω/dt. The energy loop assumes a constant inertia and a
 *    constant motor torque, and ω_max − ω_min from ½ I (ω_max² − ω_min²) = ΔE: with the
 *    constant-torque motor the simulated C_s agrees with the asked one to O(C_s) relative (the
 *    variation of I(θ) and of the speed-dependent loads over the cycle; the inertia torque
 *    ½ I' ω² taken at ω_m instead of ω(θ)). A shunt motor damps the fluctuation (its torque
 *    rises as the machine slows): each harmonic of the speed shrinks by |ikΩI|/|ikΩI + b|, the
 *    more so the smaller the slip, but their phases turn, so the peak-to-peak C_s is usually
 *    smaller and not always (the shaper of tests/flywheel, whose cut jumps: +0.2 %).
 *
 * Units: the model's (SI: rad, rad/s, N m, J, kg m²); angles CCW +. Allocates (the samples'
 * vectors, outside any solver's loop); nothing throws; every result has a status.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/core/view_model.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/position/input_step.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"
#include "mechgen/statics/traits.h"
#include "mechgen/sweep/sweep.h"


namespace mechgen::flywheel {

/// Why a machine could (not) be sized.
enum class CycleStatus {
  kOk = 0,
  kNotOneDof,       ///< the model has more (or fewer) than one input
  kNoForces,        ///< the model was generated without `forces`
  kNotAngle,        ///< the input is a slide: no cycle of a turning input
  kBadOptions,      ///< ω_m, Θ or the samples out of range
  kNotAssembled,    ///< the model does not assemble at its assembly configuration
  kPositionFailed,  ///< the positions failed at a sample (the loop does not close there)
  kDeadPoint,       ///< a dead point inside the cycle: cond_1(Phi_phi) too large at a sample
  kStaticsFailed,   ///< the statics (friction iteration) did not converge at a sample
  kNotFinite,       ///< a torque or an inertia at a sample is not finite
  kNoLoad,          ///< mean(T_req) < 0 beyond its rounding: the machine drives the motor
};

inline const char* ToString(CycleStatus s) {
  switch (s) {
    case CycleStatus::kOk:
      return "ok";
    case CycleStatus::kNotOneDof:
      return "not a one-DOF machine (flywheel sizing needs exactly one input)";
    case CycleStatus::kNoForces:
      return "the model has no forces (add `forces` to its outputs' quantities)";
    case CycleStatus::kNotAngle:
      return "the input is a slide, not a turning crank: no cycle to size a flywheel for";
    case CycleStatus::kBadOptions:
      return "bad options (speed, cycle or samples)";
    case CycleStatus::kNotAssembled:
      return "the model does not assemble at its assembly configuration";
    case CycleStatus::kPositionFailed:
      return "the positions failed inside the cycle";
    case CycleStatus::kDeadPoint:
      return "a dead point inside the cycle (the driving torque grows without bound there)";
    case CycleStatus::kStaticsFailed:
      return "the statics did not converge inside the cycle";
    case CycleStatus::kNotFinite:
      return "a torque or inertia inside the cycle is not finite";
    case CycleStatus::kNoLoad:
      return "the mean required torque is negative: the loads drive the machine (no motor to size)";
  }
  return "unknown";
}

struct MachineCycleOptions {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double omega = 0;       ///< ω_m, the mean speed (rad/s), > 0
  double theta0 = kNaN;   ///< θ_0 (rad); NaN: the model's kQMin
  double cycle = kNaN;    ///< Θ (rad); NaN: DefaultCycle()
  int samples = 720;      ///< N >= 4
  /// Angles (rad) where the load switches so that T_req kinks or jumps (energy_loop.h's
  /// breaks: E stays fourth order); on a sample (θ_0 + k Θ/N up to 1e-9 of a step) or between
  /// two, taken modulo Θ; at least 3 sample intervals from one another (else kBadOptions).
  std::vector<double> breaks;
  /// Find the breaks from the model's switching items (a model with M::SwitchModes, i.e. the
  /// quantity `dynamics` and a step(), clamp(), mod(), ... in its loads): where the modes of
  /// two neighbouring samples differ, the switch is located between them by bisection on the
  /// input (to rounding) and made a break, so that a load switched on over part of the cycle
  /// (a cutting force, a punch) keeps the loop fourth order without --break. A switch closer
  /// than 3 intervals to a break already kept is not made one (counted in
  /// MachineCycle::switches_unused: the loop is second order there).
  bool switch_breaks = true;
  statics::Options statics;

  bool IsValid() const {
    return std::isfinite(omega) && omega > 0 && samples >= 4 && samples <= 10000000 &&
           (std::isnan(theta0) || std::isfinite(theta0)) &&
           (std::isnan(cycle) || (std::isfinite(cycle) && cycle > 0)) && statics.IsValid(nullptr);
  }
};

/// One sample of the cycle.
struct CyclePoint {
  double theta = 0;      ///< θ_k (rad)
  double T_req = 0;      ///< the required driving torque (N m, on the input link, CCW +)
  double T_static = 0;   ///< its statics part (loads, weights, springs, Coulomb friction)
  double T_inertia = 0;  ///< h = ½ I'(θ) ω_m² (N m; 0 without `dynamics`)
  double T_speed = 0;    ///< what the speed-dependent loads need: Q_static − Q(θ, ω_m) (N m)
  double I = 0;          ///< the machine's generalized inertia I(θ) (kg m²; 0 without `dynamics`)
  /// ∂T_req/∂ω at ω_m (N m s/rad; 0 without `dynamics`): I'(θ) ω_m (the inertia torque's)
  /// less ∂Q/∂θ̇ (the speed-dependent loads', a central difference of the generated Q).
  double dT_domega = 0;
  double E = 0;          ///< the excess energy E(θ_k) (J), E(θ_0) = 0
  double condition = 0;  ///< cond_1(Phi_phi)
};

/// The sampled cycle, its energy loop and the flywheel.
struct MachineCycle {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  CycleStatus status = CycleStatus::kBadOptions;
  std::string message;        ///< what went wrong, with the angle and the figures ("" if ok)
  double failed_theta = kNaN; ///< the sample where it went wrong (rad)
  bool has_dynamics = false;  ///< T_inertia, T_speed and I are the model's (else 0)
  double omega = 0, theta0 = 0, cycle = 0;
  std::vector<CyclePoint> points;
  EnergyLoop loop;            ///< of ΔT = T_mean − T_req (E_max, E_min, their angles, ΔE)
  double T_mean = kNaN;       ///< mean(T_req) = the constant motor torque of a steady cycle (N m)
  double work = kNaN;         ///< Θ T_mean: the load's work per cycle (J)
  double T_max = kNaN, T_min = kNaN;  ///< extremes of T_req over the samples (N m)
  double theta_T_max = kNaN, theta_T_min = kNaN;
  double I_mean = 0;          ///< mean I(θ) (kg m²; 0 without `dynamics`)
  /// mean ∂T_req/∂ω (N m s/rad): how the mean load torque grows with the speed (the inertia
  /// torque's part averages out: ∮ I' dθ = 0). With the motor's own slope it sets how fast a
  /// steady cycle settles (CheckBySimulation: the time constant (I_fly + I_mean)/slope).
  double dT_mean_domega = 0;
  /// What "T_mean = 0" means: |T_mean| at most this (N m) is zero to rounding, the loads doing
  /// no net work (a conservative machine): 8 ε N max_k max(|T_req|, |T_static|, |T_inertia|,
  /// |T_speed|) (each sample's parts may cancel to a T_req far below them; N of them summed).
  double T_mean_rounding = 0;
  /// |T_mean| <= T_mean_rounding: T_mean and work are set to exactly 0, whatever the sign of
  /// the rounding, and the machine is sized (the flywheel only evens out the exchange of
  /// energy between the inertia, weights and springs); the constant motor supplies no torque.
  bool zero_mean = false;
  /// The switches of the loads located inside the cycle (rad, increasing; switch_breaks).
  std::vector<double> switches;
  int switches_unused = 0;    ///< of them, too close to another break to be one
  /// The breaks the energy loop used (rad, in [θ_0, θ_0 + Θ), increasing: the options' and the
  /// switches'), and where they fall: sample and fraction of the next interval (energy_loop.h).
  std::vector<double> breaks;
  std::vector<int> break_samples;
  std::vector<double> break_fractions;
  /// A break on a sample: whose value T_req there is (energy_loop.h's break_sides): 0 both
  /// sides' (a kink), −1 the left's, +1 the right's (a jump: the side whose cubic, extrapolated
  /// from the four samples beyond, comes nearer to it).
  std::vector<int> break_sides;
  bool IsUsable() const { return status == CycleStatus::kOk; }
};

/// The flywheel for a C_s.
struct FlywheelSize {
  double C_s = 0;          ///< asked
  double I_required = 0;   ///< ΔE/(C_s ω_m²): the total constant inertia (kg m²)
  double I_flywheel = 0;   ///< I_required − mean I(θ): the inertia to add (kg m²)
  bool needed = true;      ///< false when the machine's own mean inertia already suffices
};

/// Θ by default: the model's input range when it is a whole number of turns (720° for a
/// four-stroke engine model), else one turn.
template <class M>
double DefaultCycle(const M& model) {
  const double range = ModelCalls<M>::QMax(model)[0] - ModelCalls<M>::QMin(model)[0];
  const double turns = std::round(range / (2 * kPi));
  if (turns >= 1 && std::abs(range - turns * 2 * kPi) <= 1e-9 * range) return turns * 2 * kPi;
  return 2 * kPi;
}
/// The same for a generated model M (an empty tag).
template <class M>
double DefaultCycle() {
  return DefaultCycle(M());
}

namespace internal {
inline std::string Degrees(double theta) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "theta = %.6g deg", ToDegrees(theta));
  return buffer;
}

// A break at θ_0 + u h (u reduced modulo n into [0, n)): its sample and fraction, on the
// sample when within 1e-9 of a step of it.
inline void BreakPosition(double u, int n, int* k, double* sigma) {
  u = std::fmod(u, static_cast<double>(n));
  if (u < 0) u += n;
  double f = std::floor(u);
  double s = u - f;
  const double tolerance = 1e-9 * std::max(1.0, std::abs(u));
  if (s <= tolerance) s = 0;
  if (1 - s <= tolerance) s = 0, f += 1;
  *k = static_cast<int>(f) % n;
  *sigma = s;
}
}  // namespace internal

/**
 * \brief T_req over one cycle at ω_m, its energy loop (see the file comment).
 * \param[in] model  the model (a generated Model's empty tag, or a ViewModel: its one input and
 *                   statics at run time).
 * \param[in] p  the model's parameters.
 */
template <class M>
MachineCycle SampleMachineCycle(const M& model, const typename ModelTypes<M>::Params& p,
                                const MachineCycleOptions& o) {
  using C = ModelCalls<M>;
  MachineCycle out;
  if constexpr (!C::kView && M::kNq != 1) {
    (void)model, (void)p, (void)o;
    out.status = CycleStatus::kNotOneDof;
    out.message = ToString(out.status);
    return out;
  } else if constexpr (!statics::StaticsFeatures<M>::kHasStatics) {
    (void)model, (void)p, (void)o;
    out.status = CycleStatus::kNoForces;
    out.message = ToString(out.status);
    return out;
  } else {
    if (C::Nq(model) != 1 || !C::HasStatics(model)) {  // (a view's, at run time)
      out.status = C::Nq(model) != 1 ? CycleStatus::kNotOneDof : CycleStatus::kNoForces;
      out.message = ToString(out.status);
      return out;
    }
    using VecQ = typename ModelTypes<M>::VecQ;
    const int nq = 1;
    auto fail = [&](CycleStatus s, double theta, const std::string& why) {
      out.status = s;
      out.failed_theta = theta;
      out.message = std::string(ToString(s)) + (std::isnan(theta) ? "" : " at " + internal::Degrees(theta)) +
                    (why.empty() ? "" : ": " + why);
      return out;
    };
    if (!C::QIsAngle(model, 0)) return fail(CycleStatus::kNotAngle, MachineCycle::kNaN, "");
    if (!o.IsValid()) return fail(CycleStatus::kBadOptions, MachineCycle::kNaN, "");
    const int n = o.samples;
    out.omega = o.omega;
    out.theta0 = std::isnan(o.theta0) ? C::QMin(model)[0] : o.theta0;
    out.cycle = std::isnan(o.cycle) ? DefaultCycle(model) : o.cycle;
    const double h_theta = out.cycle / n;
    const double cycle_begin[1] = {0}, cycle_end[1] = {out.cycle};
    if (!position::CheckInputSteps(cycle_begin, cycle_end, 1, n).ok())
      return fail(CycleStatus::kBadOptions, MachineCycle::kNaN,
                  "the samples are further apart than the position solver's step limit; use more");
    constexpr bool kDynamics = HasDynamics<M>::value;  // (a view: C::HasDynamics at run time)
    out.has_dynamics = kDynamics && C::HasDynamics(model);
    position::PositionSolver<M> solver(model, position::Options(), p);
    position::Summary assembly;
    if (solver.AssembleDefault(&assembly) != position::Status::kConverged)
      return fail(CycleStatus::kNotAssembled, MachineCycle::kNaN, position::FormatSummary(assembly));
    out.points.assign(static_cast<size_t>(n), CyclePoint());
    auto q_begin = Sized<VecQ>(nq), q_end = Sized<VecQ>(nq), qd = Sized<VecQ>(nq), qdd = Sized<VecQ>(nq);
    q_begin(0) = out.theta0;
    // n steps to θ_0 + Θ; the last row (θ_0 + Θ = θ_0 of the next cycle) is not kept.
    q_end(0) = out.theta0 + out.cycle;
    qd(0) = o.omega;
    qdd(0) = 0;
    const VecQ forward = VecQ::Ones(nq);
    bool failed = false;
    // The switching items' modes and the positions at each sample and at the cycle's end.
    // (kMaySwitch: M may have switching items, a view's at run time: num_switches.)
    constexpr bool kMaySwitch = C::kView || ModelFeatures<M>::kNumSwitches > 0;
    const int num_switches = C::NumSwitches(model);
    using Modes = typename C::SwitchModesArray;  // (a view's beyond num_switches stay 0)
    using VecPhi = typename ModelTypes<M>::VecPhi;
    const bool find_switches = num_switches > 0 && o.switch_breaks;
    std::vector<Modes> modes(find_switches ? static_cast<size_t>(n) + 1 : 0);
    std::vector<VecPhi> phis(find_switches ? static_cast<size_t>(n) + 1 : 0);
    auto modes_at = [&](const VecQ& q, const VecPhi& phi, Modes* out_modes) {
      if constexpr (kMaySwitch) {
        typename ModelTypes<M>::Coefficients c;
        C::Coeffs(model, p, q, phi, &c);
        C::SwitchModes(model, p, q, phi, qd, 0.0, c, out_modes);
      } else {
        (void)q, (void)phi, (void)out_modes;
      }
    };
    auto row = [&](int k, const SweepRecord<M>& r) {
                if (failed || k > n) return;
                const double theta = out.theta0 + k * h_theta;
                const position::Status ps = r.summary.status;
                if (k == n) {  // the cycle's end: only its modes (for a switch in the last interval)
                  if (find_switches && ps == position::Status::kConverged && r.state.valid) {
                    phis[static_cast<size_t>(n)] = r.state.phi;
                    modes_at(r.state.q, r.state.phi, &modes[static_cast<size_t>(n)]);
                  } else if (find_switches) {
                    modes[static_cast<size_t>(n)] = modes[static_cast<size_t>(n) - 1];
                  }
                  return;
                }
                if (ps == position::Status::kSingular) {
                  failed = true;
                  fail(CycleStatus::kDeadPoint, theta, position::FormatSummary(r.summary));
                  return;
                }
                if (ps != position::Status::kConverged || !r.state.valid) {
                  failed = true;
                  fail(CycleStatus::kPositionFailed, theta, position::FormatSummary(r.summary));
                  return;
                }
                typename ModelTypes<M>::Coefficients c;
                C::Coeffs(model, p, r.state.q, r.state.phi, &c);
                statics::Solution<M> run;
                const statics::Status st =
                    statics::Solve<M>(model, o.statics, p, r.state.q, r.state.phi, c, forward, &run);
                if (st != statics::Status::kConverged) {
                  failed = true;
                  fail(st == statics::Status::kSingular ? CycleStatus::kDeadPoint
                                                        : CycleStatus::kStaticsFailed,
                       theta, statics::FormatSummary(run.summary));
                  return;
                }
                if (find_switches) {
                  phis[static_cast<size_t>(k)] = r.state.phi;
                  modes_at(r.state.q, r.state.phi, &modes[static_cast<size_t>(k)]);
                }
                CyclePoint& pt = out.points[static_cast<size_t>(k)];
                pt.theta = theta;
                pt.condition = run.summary.condition;
                pt.T_static = run.statics.drive(0);
                if constexpr (kDynamics) {
                 if (out.has_dynamics) {
                  // Q_static: the loads' generalized force without friction (the same as the
                  // run's with a frictionless model).
                  double Q_static = -run.statics.drive(0);
                  if constexpr (statics::StaticsFeatures<M>::kHasFriction) {
                   if (C::HasFriction(model)) {
                    statics::Solution<M> still;
                    statics::Solve<M>(model, o.statics, p, r.state.q, r.state.phi, c, VecQ::Zero(nq), &still);
                    Q_static = still.statics.Q(0);
                   }
                  }
                  typename C::template DynamicsOut<M> d;
                  C::Dynamics(model, p, r.state.q, r.state.phi, qd, 0.0, c, &d, nullptr);
                  pt.T_inertia = d.h(0);
                  pt.T_speed = Q_static - d.Q(0);
                  pt.I = d.I(0, 0);
                  // ∂T_req/∂ω: ∂h/∂ω = I' ω_m = 2h/ω_m, and −∂Q/∂θ̇ by a central difference
                  // (step 1e-6 ω_m: truncation O(1e-12) relative, rounding ε |Q|/1e-6).
                  const double dw = 1e-6 * o.omega;
                  VecQ qd_hi = qd, qd_lo = qd;
                  qd_hi(0) += dw;
                  qd_lo(0) -= dw;
                  typename C::template DynamicsOut<M> d_hi, d_lo;
                  C::Dynamics(model, p, r.state.q, r.state.phi, qd_hi, 0.0, c, &d_hi, nullptr);
                  C::Dynamics(model, p, r.state.q, r.state.phi, qd_lo, 0.0, c, &d_lo, nullptr);
                  pt.dT_domega = 2 * d.h(0) / o.omega - (d_hi.Q(0) - d_lo.Q(0)) / (2 * dw);
                 }
                }
                pt.T_req = pt.T_static + pt.T_inertia + pt.T_speed;
                if (!std::isfinite(pt.T_req) || !std::isfinite(pt.I) || !std::isfinite(pt.dT_domega)) {
                  failed = true;
                  fail(CycleStatus::kNotFinite, theta, "");
                }
              };
    if constexpr (C::kView) {  // (the view's SweepRows, compiled once: a ViewRowFn)
      std::function<void(int, const SweepRecord<M>&)> fn = row;
      SweepRows(&solver, q_begin, q_end, n, qd, qdd, SweepOptions(), fn);
    } else {
      SweepRows(&solver, q_begin, q_end, n, qd, qdd, SweepOptions(), row);
    }
    if (failed) {
      out.points.clear();
      return out;
    }
    // The energy loop of ΔT = T_mean − T_req: ExcessEnergy of −T_req with its mean removed.
    std::vector<double> minus_T(static_cast<size_t>(n)), E(static_cast<size_t>(n));
    out.T_max = -std::numeric_limits<double>::infinity();
    out.T_min = std::numeric_limits<double>::infinity();
    double I_sum = 0, slope_sum = 0, parts = 0;
    for (int k = 0; k < n; ++k) {
      const CyclePoint& pt = out.points[static_cast<size_t>(k)];
      minus_T[static_cast<size_t>(k)] = -pt.T_req;
      I_sum += pt.I;
      slope_sum += pt.dT_domega;
      parts = std::max({parts, std::abs(pt.T_req), std::abs(pt.T_static), std::abs(pt.T_inertia),
                        std::abs(pt.T_speed)});
      if (pt.T_req > out.T_max) out.T_max = pt.T_req, out.theta_T_max = pt.theta;
      if (pt.T_req < out.T_min) out.T_min = pt.T_req, out.theta_T_min = pt.theta;
    }
    out.I_mean = I_sum / n;
    out.dT_mean_domega = slope_sum / n;
    out.T_mean_rounding = 8 * std::numeric_limits<double>::epsilon() * n * parts;
    // The breaks: the options' (each must be finite), then the switches of the loads.
    struct Break {
      double u;  // θ_0 + u h, u in [0, n)
      int k;
      double sigma;
      bool given;
    };
    std::vector<Break> breaks;
    auto add_break = [&](double u, bool given) {
      Break b{0, 0, 0, given};
      internal::BreakPosition(u, n, &b.k, &b.sigma);
      b.u = b.k + b.sigma;
      breaks.push_back(b);
    };
    for (double b : o.breaks) {
      if (!std::isfinite(b)) {
        out.status = CycleStatus::kBadOptions;
        out.message = "a break angle is not finite";
        out.points.clear();
        return out;
      }
      add_break((b - out.theta0) / h_theta, true);
    }
    if constexpr (kMaySwitch) {
      if (find_switches) {
        using MatCPhi = typename ModelTypes<M>::MatCPhi;
        for (int k = 0; k < n; ++k) {
          const Modes& m0 = modes[static_cast<size_t>(k)];
          if (m0 == modes[static_cast<size_t>(k) + 1]) continue;
          // Bisection on [θ_k, θ_k+1]: the positions from the interpolated ones by Newton.
          double lo = 0, hi = 1;  // fractions of the interval
          bool located = true;
          for (int it = 0; it < 64 && hi - lo > 1e-15; ++it) {
            const double mid = 0.5 * (lo + hi);
            auto q = Sized<VecQ>(nq);
            q(0) = out.theta0 + (k + mid) * h_theta;
            VecPhi phi = (1 - mid) * phis[static_cast<size_t>(k)] + mid * phis[static_cast<size_t>(k) + 1];
            if constexpr (C::kView || M::kNc > 0) {
             if (C::Nc(model) > 0) {
              auto Phi_phi = Sized<MatCPhi>(C::Nc(model), C::Nphi(model));
              if (solver.Newton(q, &phi, &Phi_phi).status != position::Status::kConverged) {
                located = false;
                break;
              }
             }
            }
            Modes mm{};
            modes_at(q, phi, &mm);
            (mm == m0 ? lo : hi) = mid;
          }
          if (!located) continue;  // not a break: the loop is second order there
          out.switches.push_back(out.theta0 + (k + 0.5 * (lo + hi)) * h_theta);
          add_break(k + 0.5 * (lo + hi), false);
        }
      }
    }
    // The given breaks first, then the switches in cycle order; the same break once; a switch
    // too close to a kept break left out.
    std::stable_sort(breaks.begin(), breaks.end(),
                     [](const Break& a, const Break& b) { return a.given != b.given ? a.given : a.u < b.u; });
    std::vector<Break> kept;
    auto apart = [&](const Break& a, const Break& b) {  // energy_loop.h's rule for two breaks
      const int k2[2] = {a.k, b.k};
      const double s2[2] = {a.sigma, b.sigma};
      EnergyLoopOptions two;
      two.breaks = k2;
      two.break_fractions = s2;
      two.num_breaks = 2;
      return internal::Breaks{two, n}.Valid();
    };
    for (const Break& b : breaks) {
      bool same = false, fits = true;
      for (const Break& c : kept) {
        if (c.k == b.k && std::abs(c.sigma - b.sigma) <= 1e-9) same = true;
        else if (!apart(b, c)) fits = false;
      }
      if (same) continue;
      if (!fits && !b.given) {
        ++out.switches_unused;
        continue;
      }
      kept.push_back(b);  // a given break too close to another: ExcessEnergy refuses them
    }
    std::stable_sort(kept.begin(), kept.end(), [](const Break& a, const Break& b) { return a.u < b.u; });
    double peak = 0;
    for (double t : minus_T) peak = std::max(peak, std::abs(t));
    for (const Break& b : kept) {
      out.breaks.push_back(out.theta0 + b.u * h_theta);
      out.break_samples.push_back(b.k);
      out.break_fractions.push_back(b.sigma);
      int side = 0;
      if (b.sigma == 0 && n >= 8) {
        // Which side's value the sample holds: each side's cubic through its next four
        // samples, extrapolated to it. A kink: both agree with it (to O(h^4)): shared.
        auto T = [&](int j) { return minus_T[static_cast<size_t>(((j % n) + n) % n)]; };
        const double xl[4] = {-4, -3, -2, -1}, fl[4] = {T(b.k - 4), T(b.k - 3), T(b.k - 2), T(b.k - 1)};
        const double xr[4] = {1, 2, 3, 4}, fr[4] = {T(b.k + 1), T(b.k + 2), T(b.k + 3), T(b.k + 4)};
        const double d_left = std::abs(T(b.k) - internal::Cubic(xl, fl).Value(0));
        const double d_right = std::abs(T(b.k) - internal::Cubic(xr, fr).Value(0));
        if (std::max(d_left, d_right) > 1e-6 * peak && std::min(d_left, d_right) < 0.1 * std::max(d_left, d_right))
          side = d_left < d_right ? -1 : +1;
      }
      out.break_sides.push_back(side);
    }
    {  // a sided break needs one more interval of room: where that is not there, shared
      EnergyLoopOptions sided;
      sided.breaks = out.break_samples.data();
      sided.break_fractions = out.break_fractions.data();
      sided.break_sides = out.break_sides.data();
      sided.num_breaks = static_cast<int>(out.break_samples.size());
      if (!internal::Breaks{sided, n}.Valid()) std::fill(out.break_sides.begin(), out.break_sides.end(), 0);
    }
    EnergyLoopOptions loop_options;
    loop_options.remove_mean = true;
    loop_options.breaks = out.break_samples.data();
    loop_options.break_fractions = out.break_fractions.data();
    loop_options.break_sides = out.break_sides.data();
    loop_options.num_breaks = static_cast<int>(out.break_samples.size());
    out.loop = ExcessEnergy(minus_T.data(), n, out.cycle, out.theta0, loop_options, E.data());
    out.T_mean = -out.loop.mean_torque;
    out.work = out.T_mean * out.cycle;
    {
      // The mean of ∂T_req/∂ω by the same break-aware rule: a load switched by a speed table
      // has its slope in a narrow band near a switch, which the sample mean would weigh by
      // where the samples fall.
      std::vector<double> slope(static_cast<size_t>(n));
      for (int k = 0; k < n; ++k) slope[static_cast<size_t>(k)] = out.points[static_cast<size_t>(k)].dT_domega;
      const EnergyLoop s = ExcessEnergy(slope.data(), n, out.cycle, out.theta0, loop_options);
      if (s.status == LoopStatus::kOk) out.dT_mean_domega = s.mean_torque;
      // Zero to the central difference's rounding (ε |Q| / 1e-6 per sample, as a torque at ω_m).
      if (std::abs(out.dT_mean_domega) * o.omega <= 1e-8 * parts) out.dT_mean_domega = 0;
    }
    for (int k = 0; k < n; ++k) out.points[static_cast<size_t>(k)].E = E[static_cast<size_t>(k)];
    if (!out.loop.IsUsable()) {
      out.status = out.loop.status == LoopStatus::kTooFewSamples ? CycleStatus::kBadOptions
                                                                 : CycleStatus::kNotFinite;
      out.message = std::string("energy loop: ") + ToString(out.loop.status);
      if (out.loop.status == LoopStatus::kTooFewSamples && !out.breaks.empty())
        out.message = "the breaks are closer than 3 sample intervals to one another (or fewer than 8 "
                      "samples with a break between two): use more samples";
      return out;
    }
    // Zero to rounding, either sign: the same machine (a conservative one) is sized the same
    // whichever way the rounding of its samples fell.
    if (std::abs(out.T_mean) <= out.T_mean_rounding) {
      out.zero_mean = true;
      out.T_mean = 0;
      out.work = 0;
    }
    if (!(out.T_mean >= 0)) {
      out.status = CycleStatus::kNoLoad;
      char buffer[200];
      std::snprintf(buffer, sizeof(buffer), "%s (mean %.6g N m, beyond its rounding %.3g N m)",
                    ToString(out.status), out.T_mean, out.T_mean_rounding);
      out.message = buffer;
      return out;
    }
    out.status = CycleStatus::kOk;
    return out;
  }
}
/// The same for a generated model M (an empty tag).
template <class M>
MachineCycle SampleMachineCycle(const typename M::template ParamsT<double>& p, const MachineCycleOptions& o) {
  return SampleMachineCycle(M(), p, o);
}

/// The flywheel that keeps the speed of `cycle` within C_s (see the file comment).
inline FlywheelSize SizeFlywheel(const MachineCycle& cycle, double C_s) {
  FlywheelSize f;
  f.C_s = C_s;
  f.I_required = RequiredInertia(cycle.loop.delta_E, C_s, cycle.omega);
  f.I_flywheel = f.I_required - cycle.I_mean;
  f.needed = f.I_flywheel > 0;
  return f;
}

// ---------------------------------------------------------------------------------------
// The simulated check (models with `dynamics`).

/// How the motor's torque depends on the speed.
enum class MotorLaw { kConstant, kShunt };

inline const char* ToString(MotorLaw law) { return law == MotorLaw::kConstant ? "constant" : "shunt"; }

/// The motor: the Load of dynamics::MinimalDynamics (a torque on the input, CCW +).
struct MotorLoad {
  MotorLaw law = MotorLaw::kConstant;
  double T_mean = 0;   ///< N m: the torque at ω_m
  double T_stall = 0;  ///< kShunt: T_mean / slip (N m)
  double omega_0 = 0;  ///< kShunt: the no-load speed ω_m / (1 − slip) (rad/s)

  static MotorLoad Make(MotorLaw law, double T_mean, double omega_m, double slip) {
    MotorLoad m;
    m.law = law;
    m.T_mean = T_mean;
    m.T_stall = T_mean / slip;
    m.omega_0 = omega_m / (1 - slip);
    return m;
  }
  double Torque(double omega) const {
    return law == MotorLaw::kConstant ? T_mean : T_stall * (1 - omega / omega_0);
  }
  template <class VecQ, class MatK>
  void operator()(double /*t*/, const VecQ& /*q*/, const VecQ& qd, const MatK& /*K*/, VecQ* Q) const {
    (*Q)(0) = Torque(qd(0));
  }
};

namespace internal {
template <class T>
inline constexpr bool kAlwaysFalse = false;
}  // namespace internal

/**
 * WithFlywheel<M>: model M (one input) with a constant inertia I_flywheel added to its input:
 * a balanced rotor keyed to the input's shaft, turning with q̇ about an axis fixed in the frame
 * (a flywheel on the crank). Its parameters are M's with the member I_flywheel (kg m²) added.
 * Every generated function that yields the inertia, the kinetic energy or what is built from
 * them is shadowed, so that no path through the runtime silently lacks the flywheel:
 *  - Dynamics and the one-pass Rhs: I(0, 0) + I_fly, T + ½ I_fly q̇² (I' = dI_dq, C, h, Q, V
 *    and P_nc unchanged: the added inertia is constant and the rotor does no work of its own);
 *  - Kinetostatics: the rotor's inertia couple −I_fly q̈ on the input's link, carried by the
 *    drive: Q(0) − I_fly q̈, drive(0) + I_fly q̈; the reactions R unchanged (a pure couple on the
 *    link the drive acts on moves no joint force), the rest unchanged;
 *  - ExcessDynamics (x = (q, φ)): M_x(0, 0) + I_fly, T + ½ I_fly q̇² (h, g, Φ_x, γ unchanged).
 * Left to M, correct as they are: the kinematics (Solve, Coeffs, Kinematics, Prepare: no
 * inertia), the statics (Forces, Stiffness, StaticsDesign: no inertia) and DynamicsDesign (d/dp
 * of I, I', h, Q, T, V: the flywheel's share is constant, its derivatives 0; I_flywheel is no
 * design parameter).
 * Refused at compile time (kHasShaking false, and Shaking, ShakingDesign a static_assert): the
 * shaking moment gains −I_fly q̈ on the frame, but M's Shaking splits M by link (M_link) and the
 * rotor is no link of M's; a caller that needs it adds −I_fly q̈ to M's shaking moment itself.
 * The runtime's templates reach these through ModelCalls<WithFlywheel<M>> (core/model_calls.h);
 * a model reached through its view has WithFlywheel<ViewModel> below, whose calls add the same.
 */
template <class M>
struct WithFlywheel : M {
  static_assert(M::kNq == 1, "WithFlywheel: a flywheel on the one input of a one-DOF model");
  static constexpr bool kHasShaking = false;
  template <class S>
  struct ParamsT : M::template ParamsT<S> {
    S I_flywheel = S(0);
  };
  template <class S, class VQ, class VPhi, class VQd, class C, class Out, class... Rest>
  static void Dynamics(const ParamsT<S>& p, const VQ& q, const VPhi& phi, const VQd& qd, const S& t,
                       const C& c, Out* out, Rest... rest) {
    M::template Dynamics<S>(p, q, phi, qd, t, c, out, rest...);
    out->I(0, 0) += p.I_flywheel;
    out->T += S(0.5) * p.I_flywheel * qd(0) * qd(0);
  }
  template <class S, class RC, class VQ, class VQd, class Modes, class Trig, class Out, class... Rest>
  static auto Rhs(const ParamsT<S>& p, const RC& rc, const VQ& q, const VQd& qd, const S& t,
                  const Modes& modes, Trig* trig, Out* out, Rest... rest) {
    const auto report = M::template Rhs<S>(p, rc, q, qd, t, modes, trig, out, rest...);
    out->I(0, 0) += p.I_flywheel;
    out->T += S(0.5) * p.I_flywheel * qd(0) * qd(0);
    return report;
  }
  template <class S, class VQ, class VPhi, class VQd, class VQdd, class C, class Out, class... Rest>
  static void Kinetostatics(const ParamsT<S>& p, const VQ& q, const VPhi& phi, const VQd& qd, const VQdd& qdd,
                            const S& t, const C& c, Out* out, Rest... rest) {
    M::template Kinetostatics<S>(p, q, phi, qd, qdd, t, c, out, rest...);
    out->Q(0) -= p.I_flywheel * qdd(0);
    out->drive(0) += p.I_flywheel * qdd(0);
  }
  template <class S, class VQ, class VPhi, class VQd, class VPhid, class Out, class... Rest>
  static void ExcessDynamics(const ParamsT<S>& p, const VQ& q, const VPhi& phi, const VQd& qd, const VPhid& phid,
                             const S& t, Out* out, Rest... rest) {
    M::template ExcessDynamics<S>(p, q, phi, qd, phid, t, out, rest...);
    out->M(0, 0) += p.I_flywheel;
    out->T += S(0.5) * p.I_flywheel * qd(0) * qd(0);
  }
  template <class S = double, class... A>
  static void Shaking(const A&...) {
    static_assert(internal::kAlwaysFalse<S>,
                  "WithFlywheel<M>::Shaking: not provided (the rotor is no link of M's shaking "
                  "table); add -I_flywheel qdd to M's shaking moment M");
  }
  template <class S = double, class... A>
  static void ShakingDesign(const A&...) {
    static_assert(internal::kAlwaysFalse<S>, "WithFlywheel<M>::ShakingDesign: not provided (see Shaking)");
  }
};

/// The flywheel's parameters on a model view: the view's table and I_flywheel (kg m²).
struct ViewFlywheelParams : ViewParams {
  double I_flywheel = 0;
};

/**
 * WithFlywheel<ViewModel>: the flywheel on a model reached through its view (issue 43), the
 * same machine as WithFlywheel<M> of the generated model. A view's functions are pointers that
 * cannot be shadowed, so its ModelCalls (below, after this namespace) adds the flywheel instead,
 * in the same calls and by the same sums as WithFlywheel<M>'s shadows: Dynamics and Rhs
 * (I(0, 0) + I_fly, T + ½ I_fly q̇²) and Kinetostatics (Q(0) − I_fly q̈, drive(0) + I_fly q̈).
 * Every runtime template reads I, T and the kinetostatics through ModelCalls, so none can
 * miss the flywheel. The shaking table is refused (HasShaking false), as for WithFlywheel<M>;
 * the excess formulation is not reached through a view.
 */
template <>
struct WithFlywheel<ViewModel> : ViewModel {
  explicit WithFlywheel(const ViewModel& model) : ViewModel(model) {}
  static constexpr bool kHasShaking = false;
};

struct CheckOptions {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  /// The longest run the settling time may ask for (cycles at ω_m).
  static constexpr int kMaxSettlingCycles = 20000;
  MotorLaw law = MotorLaw::kConstant;
  double slip = 0.05;           ///< kShunt: s = 1 − ω_m/ω_0, in (0, 1)
  int samples_per_cycle = 720;  ///< the speed trace's equal-time samples per cycle
  /// Steady: the cycle-mean speed changing per cycle, relative, by less than steady_fraction
  /// times the fluctuation expected, C_s = ΔE/((I_fly + mean I) ω_m²), two cycles in a row:
  /// the drift inside the measured cycle is then that fraction of its ω_max − ω_min, and the
  /// measured C_s carries no more of it. Divided by the settling time in cycles τ/P when that
  /// is above 1 and the run can wait 10 τ: the change c per cycle leaves about c τ/P to go.
  /// In (0, 0.1].
  double steady_fraction = 1e-3;
  /// When finite (in (0, 0.5]): this relative change per cycle instead.
  double steady_tolerance = kNaN;
  /// Give up after this many cycles, or after 10 settling times (I_fly + mean I)/slope plus 3
  /// cycles when that is longer (at most kMaxSettlingCycles; SimulatedCheck::cycles_limit).
  int max_cycles = 400;
  double rtol = 1e-10, atol = 1e-10;
};

struct SimulatedCheck {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool ok = false;
  std::string message;          ///< why not ("" if ok)
  double I_flywheel = kNaN;     ///< the flywheel simulated (kg m²)
  double omega_start = kNaN;    ///< the speed at θ_0 the run started with (rad/s)
  int cycles = 0;               ///< cycles until the steady state
  int cycles_limit = 0;         ///< the run's limit (CheckOptions::max_cycles)
  double C_s_expected = kNaN;   ///< ΔE/((I_fly + mean I) ω_m²): the energy loop's C_s
  double steady_tolerance = kNaN;  ///< the relative change per cycle taken as steady
  /// The slope b of the mean load less the motor's torque against the speed (N m s/rad:
  /// mean ∂T_req/∂ω + the shunt motor's T_stall/ω_0) and the settling time (I_fly + mean I)/b
  /// of the cycle-mean speed (s; infinite when b <= 0: nothing pulls the mean speed back).
  double slope = kNaN, settling_time = kNaN;
  double period = kNaN;         ///< the steady cycle's duration (s)
  double last_change = kNaN;    ///< relative change of the cycle-mean speed at the end
  SpeedTrace trace;             ///< the last cycle's ω_max, ω_min, ω_mid, time mean, C_s
  double theta_at_max = kNaN, theta_at_min = kNaN;  ///< where (rad, in [θ_0, θ_0 + Θ))
  double max_energy_error = kNaN;  ///< the simulator's max |E − W_nc − E_0| (J)
};

/**
 * \brief The machine of `cycle` with the flywheel I_flywheel added, driven by the motor law,
 * integrated to a periodic steady state; C_s of its last cycle (see the file comment).
 */
template <class M>
SimulatedCheck CheckBySimulation(const M& model, const typename ModelTypes<M>::Params& p,
                                 const MachineCycle& cycle, double I_flywheel,
                                 const CheckOptions& o = CheckOptions()) {
  SimulatedCheck out;
  out.I_flywheel = I_flywheel;
  if constexpr (!HasDynamics<M>::value || (!ModelCalls<M>::kView && M::kNq != 1)) {
    (void)model, (void)p, (void)cycle, (void)o;
    out.message = "the model has no dynamics (add `dynamics` to its outputs' quantities)";
    return out;
  } else {
    if (!ModelCalls<M>::HasDynamics(model) || ModelCalls<M>::Nq(model) != 1) {  // (a view's, at run time)
      out.message = "the model has no dynamics (add `dynamics` to its outputs' quantities)";
      return out;
    }
    using Machine = WithFlywheel<M>;
    using Sim = dynamics::MinimalDynamics<Machine, dynamics::Dopri5, MotorLoad>;
    using VecQ = typename Sim::VecQ;
    char buffer[400];
    if (!cycle.IsUsable() || cycle.points.empty()) {
      out.message = "no usable cycle to check";
      return out;
    }
    if (!(I_flywheel >= 0) || !std::isfinite(I_flywheel) || !(o.slip > 0 && o.slip < 1) ||
        o.samples_per_cycle < 8 || o.max_cycles < 3) {
      out.message = "bad check options (flywheel, slip, samples or cycles)";
      return out;
    }
    typename ModelTypes<Machine>::Params pf;
    static_cast<typename ModelTypes<M>::Params&>(pf) = p;
    pf.I_flywheel = I_flywheel;
    const double w = cycle.omega;
    const double I_total = I_flywheel + cycle.I_mean;
    out.C_s_expected = cycle.loop.delta_E / (I_total * w * w);
    if (!(out.C_s_expected > 0 && std::isfinite(out.C_s_expected))) {
      std::snprintf(buffer, sizeof(buffer),
                    "the energy loop expects no fluctuation to check (dE = %.3g J, I_fly + mean I = %.3g kg m^2)",
                    cycle.loop.delta_E, I_total);
      out.message = buffer;
      return out;
    }
    out.steady_tolerance = std::isfinite(o.steady_tolerance) ? o.steady_tolerance : o.steady_fraction * out.C_s_expected;
    if (!(out.steady_tolerance > 0 && out.steady_tolerance <= 0.5) ||
        !(std::isnan(o.steady_tolerance) || o.steady_tolerance > 0) ||
        !(o.steady_fraction > 0 && o.steady_fraction <= 0.1)) {
      std::snprintf(buffer, sizeof(buffer),
                    "bad steadiness tolerance (%.3g relative per cycle; the expected C_s is %.3g)",
                    out.steady_tolerance, out.C_s_expected);
      out.message = buffer;
      return out;
    }
    // The speed at θ_0 on the cycle whose extremes the energy loop puts at ω_m ± C_s ω_m / 2:
    // ½ I ω² = ½ I ω_m² + E(θ) − ½ (E_max + E_min), E(θ_0) = 0.
    const double I0 = I_flywheel + cycle.points[0].I;
    const double w2 = w * w - (cycle.loop.E_max + cycle.loop.E_min) / I0;
    if (!(w2 > 0)) {
      out.message = "the flywheel is too small to keep the machine turning (the speed would reach zero)";
      return out;
    }
    out.omega_start = std::sqrt(w2);
    dynamics::MinimalOptions mo;
    mo.integrator.rtol = o.rtol;
    mo.integrator.atol = o.atol;
    const double period_guess = cycle.cycle / w;
    mo.sample_dt = period_guess / o.samples_per_cycle;
    mo.steady.enabled = true;
    mo.steady.coordinate = 0;
    mo.steady.cycle = cycle.cycle;
    // Steady by what C_s needs (CheckOptions::steady_fraction). The run starts on the sized
    // cycle's speed profile (ω at θ_0 above), so the periodic orbit is near from the start;
    // what is left settles with the time constant (I_fly + mean I)/b, b the slope of the mean
    // load less the motor against the speed: a change c per cycle leaves about c τ/P to go, so
    // the tolerance per cycle is steady_fraction C_s over max(1, τ/P). With b near 0 (a
    // constant-torque motor and loads of the position only, or loads whose mean hardly changes
    // with the speed: 10 τ beyond kMaxSettlingCycles) nothing pulls the mean speed back: it
    // creeps by (the error of Θ T_mean)/(I ω²) per cycle, far below steady_fraction C_s, and
    // the first cycles are steady; the run then waits max_cycles at most.
    out.slope = cycle.dT_mean_domega;
    const MotorLoad motor = MotorLoad::Make(o.law, cycle.T_mean, w, o.slip);
    if (o.law == MotorLaw::kShunt) out.slope += motor.T_stall / motor.omega_0;
    out.settling_time = out.slope > 0 ? I_total / out.slope : std::numeric_limits<double>::infinity();
    const double settle = std::ceil(10 * out.settling_time / period_guess) + 3;
    const bool settles = settle <= CheckOptions::kMaxSettlingCycles;
    if (settles && std::isnan(o.steady_tolerance))
      out.steady_tolerance /= std::max(1.0, out.settling_time / period_guess);
    mo.steady.tolerance = out.steady_tolerance;
    mo.steady.consecutive = 2;
    // The run: max_cycles, or 10 settling times when that is longer and within
    // kMaxSettlingCycles, and the speed trace's samples within the simulator's max_samples.
    double limit = o.max_cycles;
    if (settles) limit = std::max(limit, settle);
    limit = std::min(limit, std::floor(mo.max_samples / (o.samples_per_cycle + 1.0)));
    out.cycles_limit = static_cast<int>(limit);
    if (out.cycles_limit < 3) {
      out.message = "bad check options: the samples per cycle leave fewer than 3 cycles within the simulator's "
                    "max_samples";
      return out;
    }
    const Machine machine = [&model] {
      if constexpr (ModelCalls<M>::kView) {
        return Machine(model);
      } else {
        (void)model;
        return Machine();
      }
    }();
    Sim sim(machine, pf, mo, motor);
    auto q0 = Sized<VecQ>(1), qd0 = Sized<VecQ>(1);
    q0(0) = cycle.theta0;
    qd0(0) = out.omega_start;
    if (!sim.Initialize(q0)) {
      out.message = "the model does not assemble at the cycle's start";
      return out;
    }
    struct Point {
      double t, theta, omega, alpha;  // alpha = dω/dt, for the extremes between samples
    };
    std::vector<Point> trace;
    trace.reserve(static_cast<size_t>(o.samples_per_cycle) * 8);
    dynamics::MinimalSummary summary;
    const double t_end = out.cycles_limit * period_guess;
    sim.Simulate(
        0.0, q0, qd0, t_end,
        [&](const typename Sim::SampleT& s) {
          trace.push_back({s.t, s.q(0), s.qd(0), s.qdd(0)});
          // Keep the last few cycles only (the steady cycle is the last one).
          if (trace.size() > static_cast<size_t>(o.samples_per_cycle) * 16) {
            trace.erase(trace.begin(), trace.begin() + static_cast<long>(trace.size() / 2));
          }
          return true;
        },
        &summary);
    out.cycles = summary.steady.cycles;
    out.period = summary.steady.period;
    out.last_change = summary.steady.last_change;
    out.max_energy_error = summary.max_energy_error;
    if (!(summary.status == dynamics::Status::kStoppedByEvent &&
          summary.event == dynamics::Event::kSteadyState)) {
      std::snprintf(buffer, sizeof(buffer),
                    "the simulation did not reach a steady cycle: %s",
                    dynamics::FormatSummary(summary).c_str());
      out.message = buffer;
      if (summary.status == dynamics::Status::kSuccess) {
        std::snprintf(buffer, sizeof(buffer),
                      "no steady cycle within %d cycles (the cycle-mean speed still changing by "
                      "%.3g relative per cycle; asked %.3g%s; settling time %.3g s%s)",
                      out.cycles_limit, summary.steady.last_change, out.steady_tolerance,
                      std::isfinite(o.steady_tolerance) ? "" : " from steady_fraction x the expected C_s",
                      out.settling_time,
                      out.slope < 0 ? ": the mean load falls as the speed rises, no stable mean speed" : "");
        out.message = buffer;
      }
      return out;
    }
    // The last cycle: [t_crossing − period, t_crossing).
    const double t1 = summary.steady.t_crossing, t0 = t1 - summary.steady.period;
    std::vector<double> omega;
    size_t first = trace.size();
    for (size_t i = 0; i < trace.size(); ++i) {
      if (trace[i].t >= t0 && trace[i].t < t1) {
        if (first == trace.size()) first = i;
        omega.push_back(trace[i].omega);
      }
    }
    out.trace = AnalyzeSpeedTrace(omega.data(), static_cast<int>(omega.size()), TraceSampling::kTime);
    if (out.trace.status != TraceStatus::kOk || omega.size() < 8) {
      out.message = "the steady cycle's speed trace is unusable (too few samples or a speed <= 0)";
      return out;
    }
    // The extremes between samples: on the two intervals next to the extreme sample, the cubic
    // Hermite of ω with the slopes dω/dt (as ExcessEnergy refines E), so the measured C_s does
    // not depend on where the samples fall (to O(dt⁴) where ω is smooth, instead of O(dt²) of
    // the samples alone; O(dt) at a kink of ω, a jump of the torque, either way).
    auto refine = [&](int k, double sign, double* value, double* theta) {
      const size_t i = first + static_cast<size_t>(k);
      double best = sign * trace[i].omega, at = trace[i].theta;
      for (size_t a : {i - 1, i}) {
        if (i == 0 && a == i - 1) continue;
        if (a + 1 >= trace.size()) continue;
        const Point &pa = trace[a], &pb = trace[a + 1];
        internal::HermiteCandidates(pa.omega, pb.omega, pa.alpha, pb.alpha, pb.t - pa.t, [&](double u, double v) {
          if (sign * v > best) best = sign * v, at = pa.theta + u * (pb.theta - pa.theta);
        });
      }
      *value = sign * best;
      *theta = at;
    };
    double theta_max = 0, theta_min = 0;
    refine(out.trace.k_max, +1, &out.trace.omega_max, &theta_max);
    refine(out.trace.k_min, -1, &out.trace.omega_min, &theta_min);
    out.trace.omega_mid = 0.5 * (out.trace.omega_max + out.trace.omega_min);
    out.trace.C_s = (out.trace.omega_max - out.trace.omega_min) / out.trace.omega_mid;
    out.trace.C_s_time_mean = (out.trace.omega_max - out.trace.omega_min) / out.trace.omega_mean;
    auto wrap = [&](double th) {
      double a = std::fmod(th - cycle.theta0, cycle.cycle);
      if (a < 0) a += cycle.cycle;
      return cycle.theta0 + a;
    };
    out.theta_at_max = wrap(theta_max);
    out.theta_at_min = wrap(theta_min);
    out.ok = true;
    return out;
  }
}
/// The same for a generated model M (an empty tag).
template <class M>
SimulatedCheck CheckBySimulation(const typename M::template ParamsT<double>& p, const MachineCycle& cycle,
                                 double I_flywheel, const CheckOptions& o = CheckOptions()) {
  return CheckBySimulation(M(), p, cycle, I_flywheel, o);
}

}  // namespace mechgen::flywheel

// ---- WithFlywheel<ViewModel>: its types are the view's, its parameters carry I_flywheel ----
namespace mechgen {
template <class Scalar>
struct ModelTypes<flywheel::WithFlywheel<ViewModel>, Scalar> : ModelTypes<ViewModel, Scalar> {
  using Params = flywheel::ViewFlywheelParams;
};
template <class Scalar>
struct ModelFeatures<flywheel::WithFlywheel<ViewModel>, Scalar> : ModelFeatures<ViewModel, Scalar> {};
namespace internal {
template <class Scalar>
struct TrigOf<flywheel::WithFlywheel<ViewModel>, Scalar, true> : TrigOf<ViewModel, Scalar, true> {};
template <>
struct BlockCount<flywheel::WithFlywheel<ViewModel>, true> : BlockCount<ViewModel, true> {};
template <>
struct DesignDerivativesOf<flywheel::WithFlywheel<ViewModel>, true> : DesignDerivativesOf<ViewModel, true> {};
}  // namespace internal

/// The view's calls with the flywheel added where the inertia is read (WithFlywheel<ViewModel>).
template <>
struct ModelCalls<flywheel::WithFlywheel<ViewModel>> : ModelCalls<ViewModel> {
  using M = flywheel::WithFlywheel<ViewModel>;
  using Base = ModelCalls<ViewModel>;
  using T = ModelTypes<M>;
  using Params = flywheel::ViewFlywheelParams;

  /// The view's defaults, no flywheel.
  static Params DefaultParams(const M& m) {
    Params p;
    static_cast<ViewParams&>(p) = Base::DefaultParams(m);
    return p;
  }
  static void Dynamics(const M& m, const Params& p, const T::VecQ& q, const T::VecPhi& phi, const T::VecQ& qd,
                       double t, const T::Coefficients& c, T::DynamicsOut* d, const Trig* trig) {
    Base::Dynamics(m, p, q, phi, qd, t, c, d, trig);
    d->I(0, 0) += p.I_flywheel;
    d->T += 0.5 * p.I_flywheel * qd(0) * qd(0);
  }
  static ViewSolveReport Rhs(const M& m, const Params& p, const T::RhsConstantsOut& rc, const T::VecQ& q,
                             const T::VecQ& qd, double t, const Modes& modes, Trig* trig, T::RhsOut* r) {
    const ViewSolveReport report = Base::Rhs(m, p, rc, q, qd, t, modes, trig, r);
    r->I(0, 0) += p.I_flywheel;
    r->T += 0.5 * p.I_flywheel * qd(0) * qd(0);
    return report;
  }
  static void Kinetostatics(const M& m, const Params& p, const T::VecQ& q, const T::VecPhi& phi, const T::VecQ& qd,
                            const T::VecQ& qdd, double t, const T::Coefficients& c, T::KinetostaticsOut* out,
                            const T::VecFriction* friction) {
    Base::Kinetostatics(m, p, q, phi, qd, qdd, t, c, out, friction);
    out->Q(0) -= p.I_flywheel * qdd(0);
    out->drive(0) += p.I_flywheel * qdd(0);
  }
  /// The rotor is no link of the shaking table (WithFlywheel<M>: refused): none, and no call.
  static bool HasShaking(const M&) { return false; }
  template <class... A>
  static void Shaking(const A&...) = delete;
};
}  // namespace mechgen
