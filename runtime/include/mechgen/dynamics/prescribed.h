/**
 * \file dynamics/prescribed.h
 * Motion generators (Paul §8.4.4, the DYMAC program's "motion generators"): some of the
 * generalized coordinates q of a generated model with dynamics are prescribed functions of
 * time (a motor at constant speed, a cam-like rest-to-rest law, a table of points), the others
 * are free. The equation of motion of the generated code
 *
 *     I(q) qdd + h(q, qd) = Q(t, q, qd) + F(t, q, qd) + S^T lambda
 *
 * (F: optional generalized forces of the caller, e.g. a controller's torques; S selects the
 * prescribed coordinates; lambda: the actuator forces that keep them on their law) is
 * partitioned into free (f) and prescribed (p) rows. With q_p, qd_p, qdd_p given by the law:
 *
 *     qdd_f  = I_ff^-1 (Q_f + F_f - h_f - I_fp qdd_p)          (the reduced forward dynamics)
 *     lambda = I_pf qdd_f + I_pp qdd_p + h_p - Q_p - F_p        (the actuator forces: outputs)
 *
 * I_ff is a principal block of the positive definite I, so it is positive definite wherever I
 * is. The reduction is numerical, from the generated I, h and Q (no generated code beyond
 * issue 15's EvalDynamics is needed), for any split of the kNq coordinates:
 *  - kNp = 0: plain forward dynamics with the caller's forces F (the forward half of "inverse
 *    then forward dynamics");
 *  - 0 < kNp < kNq: a machine with drivers and free coordinates;
 *  - kNp = kNq: inverse dynamics (every coordinate prescribed: a parallel robot's motor torques
 *    for a tool-point trajectory); the state then holds the work integrals only.
 *
 * The integrated state is y = (q_f, qd_f, W_nc, W_act, W_F): the free coordinates, their
 * speeds and the work of the non-conservative forces (P_nc of EvalDynamics), of the actuators
 * (lambda . qd_p) and of F (F . qd), so that T + V - W_nc - W_act - W_F is an invariant to
 * check (Sample::Balance()).
 *
 * Positions are solved at every stage by the generated solver, warm-started from the last
 * accepted configuration (no drift, as forward.h; with the generated SolveTrig the stages
 * solve the angles' sin and cos only, and the angles are recovered at accepted steps; the
 * integrator's last stage at an accepted step is reused, not evaluated again). A configuration where Phi_phi loses rank is
 * where the minimal coordinates break down (K and I grow without bound): after every accepted
 * step 1/cond_1(Phi_phi) and the sign of det Phi_phi are checked; a crossing of min_rcond (or a
 * sign change) is located on the dense output and ends the run with Status::kDeadPoint, the
 * figures in the Summary (t, 1/cond_1) and the last Sample (q, phi) -- never integrated
 * through. The actuator forces of a sample at a singular configuration (1/cond_1 below
 * min_rcond, or the sample where a run ended with kDeadPoint) are withheld, NaN: they grow like
 * 1/sigma_min(Phi_phi) there (a status, never a huge number; as the statics withholds its
 * forces). The event loop is the one of dynamics/simulator.h, shared with forward.h. Where the actuator forces' growth (like 1/sigma_min) makes the steps collapse before
 * 1/cond reaches min_rcond, PrescribedOptions::approach_steps accepted steps in a row with
 * 1/cond below approach_rcond and falling end the run there the same way.
 * Nothing allocates after construction; nothing throws.
 *
 * Coulomb friction (PrescribedOptions::coulomb, kHasDrivenFriction: every input driven, no
 * caller's forces): the friction loads at the driven motion (CoulombFriction::Prescribed,
 * dynamics/friction.h: each opposing its joint's relative velocity, 0 at relative rest where
 * it is indeterminate) are added to Q, their power to P_nc, and lambda includes them; the
 * sample's `friction` holds them. With free inputs the run leaves them out and says so.
 *
 * Motion laws (each a callable MotionState(double t)): ConstantSpeedLaw, RestToRestLaw
 * (3-4-5 polynomial or cycloidal), SplineLaw<N> (a cubic spline through a table; TableLaw when
 * the table's size is known at run time only); Drive<Laws...>
 * combines one law per prescribed coordinate into the motion callable the class takes:
 *     void motion(double t, VecP* q_p, VecP* qd_p, VecP* qdd_p).
 *
 * Units and signs: those of the model (models/README.md); lambda(i) is the generalized force
 * the actuator of prescribed coordinate i applies (a torque on the input link, CCW +, or a
 * force along the slide): EvalKinetostatics' `drive` for the same motion when kNp = kNq.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/friction.h"
#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/simulator.h"

namespace mechgen::dynamics {

/// A prescribed coordinate's value, speed and acceleration at one time.
struct MotionState {
  double q = 0, qd = 0, qdd = 0;
};

/// q = q0 + omega (t - t0): a motor at constant speed.
struct ConstantSpeedLaw {
  double q0 = 0;
  double omega = 0;
  double t0 = 0;
  MotionState operator()(double t) const { return {q0 + omega * (t - t0), omega, 0.0}; }
};

/**
 * A rest-to-rest move from q0 (t <= t0) to q1 (t >= t1), at rest outside [t0, t1]:
 *  - kPoly345: q = q0 + (q1 - q0)(10 u^3 - 15 u^4 + 6 u^5), u = (t - t0)/(t1 - t0): speed and
 *    acceleration continuous (zero at both ends);
 *  - kCycloidal: q = q0 + (q1 - q0)(u - sin(2 pi u) / (2 pi)): the same, with a finite jerk.
 */
struct RestToRestLaw {
  enum class Profile { kPoly345, kCycloidal };
  double q0 = 0, q1 = 0;
  double t0 = 0, t1 = 1;
  Profile profile = Profile::kPoly345;

  MotionState operator()(double t) const {
    const double T = t1 - t0, H = q1 - q0;
    if (!(T > 0)) return {t < t0 ? q0 : q1, 0.0, 0.0};
    if (t <= t0) return {q0, 0.0, 0.0};
    if (t >= t1) return {q1, 0.0, 0.0};
    const double u = (t - t0) / T;
    if (profile == Profile::kPoly345) {
      const double u2 = u * u, u3 = u2 * u;
      return {q0 + H * u3 * (10 - 15 * u + 6 * u2), H / T * 30 * u2 * (1 - 2 * u + u2),
              H / (T * T) * 60 * u * (1 - 3 * u + 2 * u2)};
    }
    const double two_pi = 6.283185307179586;
    return {q0 + H * (u - std::sin(two_pi * u) / two_pi), H / T * (1 - std::cos(two_pi * u)),
            H / (T * T) * two_pi * std::sin(two_pi * u)};
  }
};

namespace internal {
/**
 * The cubic spline through (t_i, q_i), i < n, of SplineLaw and TableLaw; Storage is
 * std::array<double, N> (fixed size) or std::vector<double> (sized once, at construction).
 */
template <class Storage>
class CubicSplineLaw {
 public:
  enum class Ends { kClamped, kNatural };

  CubicSplineLaw(Storage t, Storage q, Ends ends) : t_(std::move(t)), q_(std::move(q)), m_(t_) {
    const int n = static_cast<int>(t_.size());
    valid_ = n >= 2 && static_cast<int>(q_.size()) == n;
    for (int i = 0; valid_ && i + 1 < n; ++i)
      if (!(t_[i + 1] > t_[i])) valid_ = false;
    for (int i = 0; valid_ && i < n; ++i)
      if (!std::isfinite(t_[i]) || !std::isfinite(q_[i])) valid_ = false;
    std::fill(m_.begin(), m_.end(), 0.0);
    if (!valid_) return;
    // Rows: a_i m_{i-1} + b_i m_i + c_i m_{i+1} = d_i (m: second derivatives at the knots).
    Storage a = m_, b = m_, c = m_, d = m_;
    for (int i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      a[i] = h0 / 6;
      b[i] = (h0 + h1) / 3;
      c[i] = h1 / 6;
      d[i] = (q_[i + 1] - q_[i]) / h1 - (q_[i] - q_[i - 1]) / h0;
    }
    const double hf = t_[1] - t_[0], hl = t_[n - 1] - t_[n - 2];
    if (ends == Ends::kNatural) {
      b[0] = 1;
      b[n - 1] = 1;
    } else {  // q'(t_0) = q'(t_{n-1}) = 0
      b[0] = hf / 3;
      c[0] = hf / 6;
      d[0] = (q_[1] - q_[0]) / hf;
      a[n - 1] = hl / 6;
      b[n - 1] = hl / 3;
      d[n - 1] = -(q_[n - 1] - q_[n - 2]) / hl;
    }
    for (int i = 1; i < n; ++i) {
      const double w = a[i] / b[i - 1];
      b[i] -= w * c[i - 1];
      d[i] -= w * d[i - 1];
    }
    m_[n - 1] = d[n - 1] / b[n - 1];
    for (int i = n - 2; i >= 0; --i) m_[i] = (d[i] - c[i] * m_[i + 1]) / b[i];
  }

  /// false when there are fewer than two points, the t are not strictly increasing or a
  /// value is not finite (the law is then the constant q_0, or 0 without points).
  bool IsValid() const { return valid_; }

  MotionState operator()(double t) const {
    const int n = static_cast<int>(t_.size());
    if (!valid_) return {q_.size() > 0 ? q_[0] : 0.0, 0.0, 0.0};
    if (t < t_[0]) {
      const double s = Slope(0, t_[0]);
      return {q_[0] + s * (t - t_[0]), s, 0.0};
    }
    if (t > t_[n - 1]) {
      const double s = Slope(n - 2, t_[n - 1]);
      return {q_[n - 1] + s * (t - t_[n - 1]), s, 0.0};
    }
    const int i = std::min(
        n - 2, static_cast<int>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1);
    const double h = t_[i + 1] - t_[i], A = (t_[i + 1] - t) / h, B = (t - t_[i]) / h;
    const double q = A * q_[i] + B * q_[i + 1] + ((A * A * A - A) * m_[i] + (B * B * B - B) * m_[i + 1]) * h * h / 6;
    return {q, Slope(i, t), A * m_[i] + B * m_[i + 1]};
  }

 private:
  double Slope(int i, double t) const {
    const double h = t_[i + 1] - t_[i], A = (t_[i + 1] - t) / h, B = (t - t_[i]) / h;
    return (q_[i + 1] - q_[i]) / h - (3 * A * A - 1) / 6 * h * m_[i] + (3 * B * B - 1) / 6 * h * m_[i + 1];
  }
  Storage t_, q_, m_;
  bool valid_ = false;
};
}  // namespace internal

/**
 * A table law: the cubic spline through (t_i, q_i), i < N (t strictly increasing), with
 * zero speed at both ends (kClamped: a rest-to-rest move through via points; speed,
 * acceleration continuous inside) or zero acceleration there (kNatural). Outside [t_0, t_{N-1}]
 * the law continues with its end speed (kClamped: at rest) and zero acceleration: a clamped
 * spline's acceleration jumps there from its end value to 0 (speed and position continuous).
 * Fixed size, no allocation; the constructor solves the tridiagonal system of the knots'
 * second derivatives (Thomas).
 */
template <int N>
class SplineLaw : public internal::CubicSplineLaw<std::array<double, N>> {
 public:
  static_assert(N >= 2, "a spline needs at least two points");
  using Base = internal::CubicSplineLaw<std::array<double, N>>;
  using Ends = typename Base::Ends;
  SplineLaw(const std::array<double, N>& t, const std::array<double, N>& q,
            Ends ends = Ends::kClamped)
      : Base(t, q, ends) {}
};

/// SplineLaw with the number of points known at run time only (e.g. read from a CSV table):
/// allocates its tables once, at construction; evaluating it allocates nothing.
class TableLaw : public internal::CubicSplineLaw<std::vector<double>> {
 public:
  using Base = internal::CubicSplineLaw<std::vector<double>>;
  TableLaw(std::vector<double> t, std::vector<double> q, Ends ends = Ends::kClamped)
      : Base(std::move(t), std::move(q), ends) {}
};

/// One law per prescribed coordinate, in the order of the prescribed indices: the motion
/// callable of PrescribedDynamics. MakeDrive(law0, law1, ...) builds one.
template <class... Laws>
class Drive {
 public:
  static constexpr int kNp = static_cast<int>(sizeof...(Laws));
  using VecP = Eigen::Matrix<double, kNp, 1>;
  explicit Drive(Laws... laws) : laws_(std::move(laws)...) {}
  void operator()(double t, VecP* q, VecP* qd, VecP* qdd) const {
    Fill(t, q, qd, qdd, std::make_index_sequence<kNp>());
  }

 private:
  template <std::size_t... I>
  void Fill(double t, VecP* q, VecP* qd, VecP* qdd, std::index_sequence<I...>) const {
    (void)t;  // no laws (kNp = 0): nothing to fill
    (void)q;
    (void)qd;
    (void)qdd;
    (Set(static_cast<int>(I), std::get<I>(laws_)(t), q, qd, qdd), ...);
  }
  static void Set(int i, const MotionState& s, VecP* q, VecP* qd, VecP* qdd) {
    (*q)(i) = s.q;
    (*qd)(i) = s.qd;
    (*qdd)(i) = s.qdd;
  }
  std::tuple<Laws...> laws_;
};

template <class... Laws>
Drive<Laws...> MakeDrive(Laws... laws) {
  return Drive<Laws...>(std::move(laws)...);
}

/// A law chosen at run time (e.g. from a command line): one of the laws above.
using AnyLaw = std::variant<ConstantSpeedLaw, RestToRestLaw, TableLaw>;

/// The motion callable of PrescribedDynamics from NP laws chosen at run time (AnyLaw).
template <int NP>
class AnyDrive {
 public:
  static constexpr int kNp = NP;
  using VecP = Eigen::Matrix<double, kNp, 1>;
  explicit AnyDrive(std::array<AnyLaw, NP> laws) : laws_(std::move(laws)) {}
  void operator()(double t, VecP* q, VecP* qd, VecP* qdd) const {
    for (int i = 0; i < kNp; ++i) {
      const MotionState s = std::visit([t](const auto& law) { return law(t); }, laws_[i]);
      (*q)(i) = s.q;
      (*qd)(i) = s.qd;
      (*qdd)(i) = s.qdd;
    }
  }
  const std::array<AnyLaw, NP>& laws() const { return laws_; }

 private:
  std::array<AnyLaw, NP> laws_;
};

/// No forces of the caller (F = 0).
struct NoForce {
  template <class VecQ>
  void operator()(double, const VecQ&, const VecQ&, VecQ* F) const {
    F->setZero();
  }
};

struct PrescribedOptions {
  IntegratorOptions integrator;
  /// Dead point when 1/cond_1(Phi_phi) < min_rcond (or det Phi_phi changes sign); the
  /// actuator forces of a sample there are withheld (NaN).
  double min_rcond = kMinRcond;
  /// Events are located to |t - t_event| <= event_tolerance (s).
  double event_tolerance = 1e-12;
  /// Samples every sample_dt from t0 (and at the end); 0: at every accepted step.
  double sample_dt = 0;
  /// A run whose sample grid would hand out more samples than this is refused (kInvalidInput).
  int max_samples = 100000000;
  int max_solver_iterations = 20;
  double solver_tolerance = 0;
  /// A singular configuration approached: approach_steps accepted steps in a row with
  /// 1/cond_1(Phi_phi) < approach_rcond and falling also end the run with kDeadPoint (where
  /// the step size collapses before 1/cond reaches min_rcond).
  double approach_rcond = 1e-3;
  int approach_steps = 200;
  /// Switching points of the model's loads: restarted at as MinimalOptions says (forward.h).
  bool restart_at_switches = true;
  double switch_min_interval = 1e-6;
  int max_switch_restarts = 1000;

  /// Stop at a periodic steady state (simulator.h: per cycle of one coordinate, the change of
  /// the cycle-mean speed); off by default. Reported in the summary's `steady`.
  SteadyStateOptions steady;

  /// Coulomb friction of the model's friction joints in a motion with every input driven
  /// (PrescribedDynamics::kHasDrivenFriction): each joint's load opposes its relative velocity,
  /// iterated on the reactions (CoulombFriction::Prescribed; max_iterations and tolerance
  /// used), and the actuators' lambda include it. On by default.
  CoulombOptions coulomb;

  bool IsValid(std::string* error) const {
    if (!integrator.IsValid(error)) return false;
    if (!coulomb.IsValid()) {
      if (error != nullptr)
        *error = "PrescribedOptions::coulomb invalid: max_iterations >= 2, 0 < tolerance < 1e-3";
      return false;
    }
    char buffer[160];
    auto fail = [&](const char* field, double value, const char* rule) {
      std::snprintf(buffer, sizeof(buffer), "PrescribedOptions::%s = %g. Violated constraint: %s",
                    field, value, rule);
      if (error != nullptr) *error = buffer;
      return false;
    };
    if (!(min_rcond >= 0 && min_rcond < 1)) return fail("min_rcond", min_rcond, "0 <= min_rcond < 1");
    if (!(event_tolerance > 0)) return fail("event_tolerance", event_tolerance, "event_tolerance > 0");
    if (!(sample_dt >= 0) || !std::isfinite(sample_dt))
      return fail("sample_dt", sample_dt, "0 <= sample_dt < inf");
    if (max_samples < 1) return fail("max_samples", max_samples, "max_samples >= 1");
    if (max_solver_iterations < 1)
      return fail("max_solver_iterations", max_solver_iterations, "max_solver_iterations >= 1");
    if (!(approach_rcond >= 0 && approach_rcond < 1))
      return fail("approach_rcond", approach_rcond, "0 <= approach_rcond < 1");
    if (approach_steps < 1) return fail("approach_steps", approach_steps, "approach_steps >= 1");
    if (!(switch_min_interval >= 0) || !std::isfinite(switch_min_interval))
      return fail("switch_min_interval", switch_min_interval, "0 <= switch_min_interval < inf");
    if (max_switch_restarts < 0) return fail("max_switch_restarts", max_switch_restarts, "max_switch_restarts >= 0");
    return true;
  }
};

struct PrescribedSummary {
  Status status = Status::kNotRun;
  Event event = Event::kNone;  ///< kDeadPoint when a singular configuration ended the run
  IntegratorSummary integrator;
  double t_end = std::numeric_limits<double>::quiet_NaN();  ///< where the run ended
  int samples = 0;
  int position_failures = 0;
  /// The smallest 1/cond_1(Phi_phi) met at accepted steps, samples and the event (1 for kNphi = 0).
  double min_rcond_seen = std::numeric_limits<double>::infinity();
  /// max |T + V - W_nc - W_act - W_F - E0| over the samples: the energy balance's drift.
  double max_energy_error = 0;
  double max_abs_lambda = 0;  ///< max_i,samples |lambda_i|
  int switch_restarts = 0;    ///< switching points of the loads restarted at (forward.h)
  int switches_through = 0;   ///< ... and stepped through (the chattering guard)
  SteadyStateSummary steady;  ///< the steady-state detection (options.steady)
  /// The model's Coulomb friction was in the run (PrescribedDynamics::kHasDrivenFriction, a
  /// friction joint with a coefficient); its dissipated work -integral of sum f_J K_rel_J qd
  /// dt is in W_nc.
  bool coulomb = false;
  const char* message = "";

  bool IsSolutionUsable() const { return !IsFailure(status); }
};

inline std::string FormatSummary(const PrescribedSummary& s) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer),
                "%s (event %s) at t = %.9g: %d samples, %d steps, %d rejected, %d rhs evaluations, "
                "min 1/cond(Phi_phi) = %.3g, max |E - W - E0| = %.3g, max |lambda| = %.6g%s%s",
                ToString(s.status), ToString(s.event), s.t_end, s.samples, s.integrator.steps,
                s.integrator.rejected, s.integrator.rhs_evaluations, s.min_rcond_seen,
                s.max_energy_error, s.max_abs_lambda, s.message[0] != 0 ? "; " : "", s.message);
  return buffer + SwitchCounts(s.switch_restarts, s.switches_through) +
         (s.coulomb ? "; Coulomb friction in the actuator forces" : "");
}

/// One evaluated configuration with drivers.
template <class M, int NP>
struct PrescribedSample {
  static constexpr int kNq = M::kNq, kNphi = M::kNphi;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double t = kNaN;
  Eigen::Matrix<double, kNq, 1> q = Eigen::Matrix<double, kNq, 1>::Constant(kNaN);
  Eigen::Matrix<double, kNq, 1> qd = q, qdd = q;
  Eigen::Matrix<double, kNq, 1> Q = q;  ///< applied generalized forces of the model (EvalDynamics)
  Eigen::Matrix<double, kNq, 1> F = q;  ///< the caller's forces
  Eigen::Matrix<double, NP, 1> lambda = Eigen::Matrix<double, NP, 1>::Constant(kNaN);  ///< actuators
  Eigen::Matrix<double, kNphi, 1> phi = Eigen::Matrix<double, kNphi, 1>::Constant(kNaN);
  double T = kNaN, V = kNaN, E = kNaN;  ///< kinetic, potential, T + V
  double W_nc = 0, W_act = 0, W_F = 0;  ///< works since t0 (non-conservative, actuators, F)
  double P_nc = 0, P_act = 0, P_F = 0;  ///< their powers
  double rcond = 1;                     ///< 1/cond_1(Phi_phi) (1 for kNphi = 0)
  double det = 1;                       ///< det Phi_phi (its sign: the branch)
  /// Coulomb friction (PrescribedSummary::coulomb): the friction loads f_J of the model's
  /// kFrictionJoints (as Sample::friction: N m on the joint's second link by its first, CCW
  /// +; N on the slider along +u), in lambda and P_nc; 0 without.
  Eigen::Matrix<double, CoulombFeatures<M>::kNumFriction, 1> friction =
      Eigen::Matrix<double, CoulombFeatures<M>::kNumFriction, 1>::Zero();
  /// T + V - (W_nc + W_act + W_F): constant along an exact motion.
  double Balance() const { return E - W_nc - W_act - W_F; }
};

/**
 * PrescribedDynamics<M, NP, Motion, Force, Method>: model M with NP of its kNq coordinates
 * prescribed by `motion` (indices given at construction), the others free; `force` adds the
 * caller's generalized forces F(t, q, qd) to every coordinate. Initialize() assembles,
 * Simulate() integrates the free coordinates (Method: Dopri5 or Dop853) and hands out samples
 * with the actuator forces lambda; Evaluate() gives one configuration; Derivative() is the
 * reduced right-hand side for an integrator of your own.
 */
template <class M, int NP, class Motion, class Force = NoForce, template <int> class Method = Dopri5>
class PrescribedDynamics {
 public:
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kNp = NP;
  static constexpr int kNf = kNq - NP;
  static constexpr int kN = 2 * kNf + 3;  ///< (q_f, qd_f, W_nc, W_act, W_F)
  static_assert(NP >= 0 && NP <= M::kNq, "0 <= prescribed coordinates <= kNq");
  static_assert(internal::HasDynamics<M>::value,
                "PrescribedDynamics needs a model generated with `dynamics` (Model::DynamicsT)");
  static_assert(ModelFeatures<M>::kHasSolve, "PrescribedDynamics needs the generated M::Solve");
  using Params = typename M::template ParamsT<double>;
  using Coefficients = typename M::template CoefficientsT<double>;
  using Dyn = typename M::template DynamicsT<double>;
  using State = Eigen::Matrix<double, kN, 1>;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecP = Eigen::Matrix<double, kNp, 1>;
  using VecF = Eigen::Matrix<double, kNf, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using Modes = std::array<int, M::kNumBlocks>;
  using Integrator = Method<kN>;
  using SampleT = PrescribedSample<M, NP>;
  static constexpr bool kHasTrig = ModelFeatures<M>::kHasTrig;
  using Trig = typename mechgen::internal::TrigOf<M>::type;
  /// The stages solve only the sin and cos of the angles (M::SolveTrig, no atan2), as
  /// MinimalDynamics does; the angles are recovered where a sample needs them.
  static constexpr bool kStagesByTrig = kHasTrig && kNphi > 0 && internal::HasSolveTrig<M>::value;
  /// ... and by the one-pass M::Rhs where it is generated (forward.h: K, L, I, h, Q, Phi_phi).
  static constexpr bool kStagesByRhs = kStagesByTrig && internal::HasRhs<M>::value;
  /// The model's loads have switching points (M::SwitchModes): PrescribedOptions::restart_at_switches.
  static constexpr int kNumSwitches = internal::NumSwitches<M>::value;
  static constexpr bool kHasSwitches = kNumSwitches > 0;
  using SwitchModes = std::array<int, kNumSwitches>;
  /// Coulomb friction in the actuator forces (PrescribedOptions::coulomb): friction joints,
  /// every input driven (kNf = 0: the motion, and so every joint's relative velocity, is
  /// given) and no caller's forces (which the reactions would miss). A run with free inputs
  /// leaves it out and says so (PrescribedSummary::message).
  static constexpr bool kHasDrivenFriction =
      CoulombFeatures<M>::kHasFriction && kNf == 0 && std::is_same_v<Force, NoForce>;
  static constexpr bool kReportsFriction = kHasDrivenFriction;
  static constexpr int kNumFriction = CoulombFeatures<M>::kNumFriction;

  /// prescribed: the indices into q of the prescribed coordinates, distinct, each in
  /// [0, kNq), in the order of the motion's components (checked by Initialize()).
  PrescribedDynamics(const Params& params, const std::array<int, NP>& prescribed, Motion motion,
                     Force force = Force(), const PrescribedOptions& options = PrescribedOptions())
      : p_(params), prescribed_(prescribed), motion_(std::move(motion)), force_(std::move(force)),
        options_(options), integrator_(options.integrator) {
    std::array<bool, kNq> is_prescribed{};
    indices_valid_ = true;
    for (int i = 0; i < kNp; ++i) {
      const int k = prescribed_[i];
      if (k < 0 || k >= kNq || is_prescribed[k]) {
        indices_valid_ = false;
        return;
      }
      is_prescribed[k] = true;
    }
    int n = 0;
    for (int k = 0; k < kNq; ++k)
      if (!is_prescribed[k]) free_[n++] = k;
  }

  const Params& params() const { return p_; }
  /// The parameters, to change (M::Rhs' constants are prepared again at the next stage).
  Params* mutable_params() {
    rhs_constants_.MarkStale();
    return &p_;
  }
  const PrescribedOptions& options() const { return options_; }
  const std::array<int, NP>& prescribed() const { return prescribed_; }
  const std::array<int, kNf>& free() const { return free_; }
  const Motion& motion() const { return motion_; }

  /// The modes of the loads' switching items at (t, y) (M::SwitchModes at the positions
  /// there); false where the positions do not solve. Nothing for a model without switches.
  bool SwitchModesAt(double t, const State& y, SwitchModes* modes) {
    if constexpr (kHasSwitches) {
      VecQ q, qd;
      VecP qddp;
      Assemble(t, y.template head<kNf>(), y.template segment<kNf>(kNf), &q, &qd, &qddp);
      VecPhi phi = phi_ref_ + K_ref_ * (q - q_ref_);
      if (!SolveAt(q, &phi)) return false;
      Coefficients c;
      EvalCoefficients(q, phi, &c);
      M::template SwitchModes<double>(p_, q, phi, qd, t, c, modes);
      return true;
    } else {
      (void)t, (void)y, (void)modes;
      return true;
    }
  }

  /// The full q, qd (and qdd_p of the law) at t from the free state.
  void Assemble(double t, const VecF& qf, const VecF& qdf, VecQ* q, VecQ* qd, VecP* qddp) const {
    VecP qp, qdp;
    motion_(t, &qp, &qdp, qddp);
    for (int i = 0; i < kNp; ++i) {
      (*q)(prescribed_[i]) = qp(i);
      (*qd)(prescribed_[i]) = qdp(i);
    }
    for (int i = 0; i < kNf; ++i) {
      (*q)(free_[i]) = qf(i);
      (*qd)(free_[i]) = qdf(i);
    }
  }

  /**
   * \brief Assembles at time t0 with the free coordinates qf0 (the prescribed ones from the
   * motion) from phi_guess on the given modes. false when it does not assemble or the
   * prescribed indices are invalid.
   */
  bool Initialize(double t0, const VecF& qf0, const VecPhi& phi_guess,
                  const Modes& modes = M::kDefaultModes) {
    initialized_ = false;
    if (!indices_valid_) return false;
    modes_ = modes;
    VecQ q, qd;
    VecP qddp;
    Assemble(t0, qf0, VecF::Zero(), &q, &qd, &qddp);
    q_ref_ = q;
    phi_ref_ = phi_guess;
    K_ref_.setZero();
    ref_det_ = 0;
    VecPhi phi = phi_guess;
    if (!SolveAt(q, &phi)) return false;
    Coefficients c;
    EvalCoefficients(q, phi, &c);
    phi_ref_ = phi;
    K_ref_ = c.K;
    double rcond = 1;
    Conditioning(c, &rcond, &ref_det_);
    initialized_ = true;
    return true;
  }

  /// Initialize() from the model's assembly guess (kAssemblyPhi, kDefaultModes).
  bool Initialize(double t0, const VecF& qf0) {
    VecPhi guess;
    for (int i = 0; i < kNphi; ++i) guess(i) = M::kAssemblyPhi[i];
    return Initialize(t0, qf0, guess);
  }

  /**
   * \brief The configuration at (t, y): positions, I, h, Q, F, the free accelerations and the
   * actuator forces, into *s (W_* from y). false when the positions do not solve or I_ff is
   * not positive definite.
   */
  bool Evaluate(double t, const State& y, SampleT* s) {
    Coefficients c;
    return EvaluateFull(t, y, s, &c);
  }

  /**
   * \brief The reduced right-hand side: dy = (qd_f, qdd_f, P_nc, P_act, P_F) at (t, y).
   * \return false when the positions do not solve or I_ff is not positive definite.
   */
  bool Derivative(double t, const State& y, State* dy) {
    SampleT s;
    Coefficients c;
    if (!Stage(t, y, /*by_trig=*/true, &s, &c)) return false;
    for (int i = 0; i < kNf; ++i) {
      (*dy)(i) = s.qd(free_[i]);
      (*dy)(kNf + i) = s.qdd(free_[i]);
    }
    (*dy)(2 * kNf) = s.P_nc;
    (*dy)(2 * kNf + 1) = s.P_act;
    (*dy)(2 * kNf + 2) = s.P_F;
    if (caching_) {
      // Simulate() reuses the last evaluation (the FSAL one at an accepted step's end) for the
      // step's events and samples instead of evaluating that state again.
      cache_.valid = true;
      cache_.t = t;
      cache_.y = y;
      cache_.sample = s;
      cache_.c = c;
      if constexpr (kStagesByTrig) cache_.trig = trig_;
    }
    return dy->allFinite();
  }

  /**
   * \brief Integrates the free coordinates from (t0, qf0, qdf0) to t_end, the prescribed ones
   * following the motion. Initialize(t0, qf0, ...) first.
   * \param[in] observer  bool(const SampleT&): called at every sample; false stops.
   * \param[out] summary  not nullptr. kDeadPoint (Event::kDeadPoint) when 1/cond_1(Phi_phi)
   *            reached min_rcond (located; the sample there is the last one).
   * \param[out] last  The last sample; may be nullptr.
   * \return summary->IsSolutionUsable().
   */
  template <class Observer, class UserEvent>
  bool Simulate(double t0, const VecF& qf0, const VecF& qdf0, double t_end, Observer&& observer,
                UserEvent&& user_event, PrescribedSummary* summary, SampleT* last = nullptr) {
    *summary = PrescribedSummary();
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
    caching_ = true;  // stopped by EndRun() on every return
    cache_.valid = false;
    State y0 = State::Zero();
    y0.template head<kNf>() = qf0;
    y0.template segment<kNf>(kNf) = qdf0;
    internal::EventSettings events;
    events.min_rcond = options_.min_rcond;
    events.event_tolerance = options_.event_tolerance;
    events.sample_dt = options_.sample_dt;
    events.max_samples = options_.max_samples;
    events.steady = options_.steady;
    events.approach_rcond = options_.approach_rcond;
    events.approach_steps = options_.approach_steps;
    events.restart_at_switches = options_.restart_at_switches && kHasSwitches;
    events.switch_min_interval = options_.switch_min_interval;
    events.max_switch_restarts = options_.max_switch_restarts;
    coulomb_active_ = false;
    friction_failed_ = false;
    if constexpr (CoulombFeatures<M>::kHasFriction) {
      if (options_.coulomb.enabled) {
        if constexpr (kHasDrivenFriction) {
          VecQ q, qd;
          VecP qddp;
          Assemble(t0, qf0, qdf0, &q, &qd, &qddp);
          VecPhi phi = phi_ref_;
          Coefficients c;
          if (SolveAt(q, &phi)) {
            EvalCoefficients(q, phi, &c);
            coulomb_active_ = CoulombFriction<M>::AnyGain(M(), p_, q, phi, c);
          }
          summary->coulomb = coulomb_active_;
        } else {
          summary->message = kNf > 0 ? "Coulomb friction is not simulated in a driven run with free inputs"
                                     : "Coulomb friction is not simulated with a caller's forces";
        }
      }
    }
    return internal::EventLoop::Run(this, events, t0, y0, t_end, observer, user_event, summary, last);
  }

  /// Simulate() without a user event.
  template <class Observer>
  bool Simulate(double t0, const VecF& qf0, const VecF& qdf0, double t_end, Observer&& observer,
                PrescribedSummary* summary, SampleT* last = nullptr) {
    return Simulate(t0, qf0, qdf0, t_end, observer, NoUserEvent(), summary, last);
  }

 private:
  /// Evaluate() with the coefficients (positions by M::Solve, the angles included).
  bool EvaluateFull(double t, const State& y, SampleT* s, Coefficients* c) {
    if (!Stage(t, y, /*by_trig=*/false, s, c)) return false;
    Conditioning(*c, &s->rcond, &s->det);
    if (s->rcond < options_.min_rcond) Withhold(s);
    return true;
  }

  /// One evaluation without the conditioning. by_trig (and the model has SolveTrig): the
  /// positions as sin and cos only; s->phi is then the warm start's predictor.
  /// NaN in the members of *c that the by-Rhs stage does not compute (all but K, Phi_phi).
  static void MarkNotComputed(Coefficients* c) {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    using F = ModelFeatures<M>;
    if constexpr (F::kCoeffsHavePhi) c->Phi.setConstant(kNaN);
    if constexpr (F::kHasL) c->L.setConstant(kNaN);
    if constexpr (F::kHasPoints) c->r_P.setConstant(kNaN);
    if constexpr (F::kHasPointVelocities) c->K_P.setConstant(kNaN);
    if constexpr (F::kHasPointAccelerations) c->L_P.setConstant(kNaN);
  }

  bool Stage(double t, const State& y, bool by_trig, SampleT* s, Coefficients* c) {
    const VecF qf = y.template head<kNf>();
    const VecF qdf = y.template segment<kNf>(kNf);
    VecQ q, qd;
    VecP qddp;
    Assemble(t, qf, qdf, &q, &qd, &qddp);
    VecPhi phi = phi_ref_ + K_ref_ * (q - q_ref_);
    bool solved = false;
    Dyn d;
    bool evaluated = false;
    if (coulomb_active_) by_trig = false;  // the kinetostatics need every coefficient
    if constexpr (kStagesByRhs) {
      if (by_trig) {
        // One generated pass: the positions' sin and cos, K, L, I, h, Q (and Phi_phi for the
        // conditioning); c holds K and Phi_phi only, its other members are set NaN (not
        // computed) rather than left indeterminate (Derivative() copies c into its cache).
        last_solve_not_assemblable_ = false;
        typename M::template RhsT<double> r;
        const auto report =
            M::template Rhs<double>(p_, rhs_constants_.Of(p_), q, qd, t, modes_, &trig_, &r);
        solved = report.status == decltype(report.status)::kConverged;
        if (!solved) {
          last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
          ++position_failures_;
          return false;
        }
        c->K = r.K;
        c->Phi_phi = r.Phi_phi;
        MarkNotComputed(c);
        d.I = r.I;
        d.h = r.h;
        d.Q = r.Q;
        d.T = r.T;
        d.V = r.V;
        d.P_nc = r.P_nc;
        evaluated = true;
      }
    }
    if (evaluated) {
    } else if constexpr (kStagesByTrig) {
      if (by_trig) {
        last_solve_not_assemblable_ = false;
        const auto report = M::template SolveTrig<double>(p_, q, modes_, &trig_);
        solved = report.status == decltype(report.status)::kConverged;
        if (!solved) last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
      } else {
        solved = SolveAt(q, &phi);
      }
    } else {
      (void)by_trig;
      solved = SolveAt(q, &phi);
    }
    if (!solved) {
      ++position_failures_;
      return false;
    }
    if (!evaluated) {
      EvalCoefficients(q, phi, c);
      EvalDynamics(q, phi, qd, t, *c, &d);
    }
    VecQ F;
    force_(t, q, qd, &F);
    VecQ qdd;
    VecP lambda;
    if (!Accelerations(d, F, qddp, &qdd, &lambda)) return false;
    s->friction.setZero();
    if constexpr (kHasDrivenFriction) {
      if (coulomb_active_) {
        // Every input driven: the friction loads at the given motion, lambda = I qdd + h - Q - K_rel^T f.
        VecQ Q_f;
        int iterations = 0;
        friction_failed_ = false;
        if (!CoulombFriction<M>::Prescribed(M(), options_.coulomb, p_, q, phi, qd, qdd, t, *c, &s->friction, &Q_f,
                                            &iterations)) {
          friction_failed_ = true;
          return false;
        }
        for (int i = 0; i < kNp; ++i) lambda(i) -= Q_f(prescribed_[i]);
        d.Q += Q_f;
        d.P_nc += Q_f.dot(qd);
      }
    }
    s->t = t;
    s->q = q;
    s->qd = qd;
    s->qdd = qdd;
    s->Q = d.Q;
    s->F = F;
    s->lambda = lambda;
    s->phi = phi;
    s->T = d.T;
    s->V = d.V;
    s->E = d.T + d.V;
    s->W_nc = y(2 * kNf);
    s->W_act = y(2 * kNf + 1);
    s->W_F = y(2 * kNf + 2);
    s->P_nc = d.P_nc;
    double P_act = 0;
    for (int i = 0; i < kNp; ++i) P_act += lambda(i) * qd(prescribed_[i]);
    s->P_act = P_act;
    s->P_F = F.dot(qd);
    return true;
  }

  /// The sample at (t, y) from the last Derivative() call, if it was at exactly (t, y).
  bool FromCache(double t, const State& y, SampleT* s, Coefficients* c) const {
    if (!cache_.valid || cache_.t != t || cache_.y != y) return false;
    *s = cache_.sample;
    *c = cache_.c;
    if constexpr (kStagesByTrig) {
      // The angles from their sin and cos, within pi of the predictor (sample.phi).
      const double two_pi = 6.283185307179586;
      for (int i = 0; i < kNphi; ++i) {
        const double angle = std::atan2(cache_.trig.sin_phi(i), cache_.trig.cos_phi(i));
        const double turns = std::floor((angle - s->phi(i)) / two_pi + 0.5);
        s->phi(i) = std::isfinite(turns) ? angle - two_pi * turns : angle;
      }
    }
    Conditioning(*c, &s->rcond, &s->det);
    if (s->rcond < options_.min_rcond) Withhold(s);
    return true;
  }

  friend struct internal::EventLoop;
  static constexpr bool kCanProjectEnergy = false;

  // ---- the hooks of the event loop (simulator.h) ----
  void EndRun() {
    caching_ = false;
    cache_.valid = false;
  }
  static double Balance(const SampleT& s) { return s.Balance(); }
  static void Record(const SampleT& s, PrescribedSummary* summary) {
    for (int i = 0; i < kNp; ++i)
      if (std::isfinite(s.lambda(i)))
        summary->max_abs_lambda = std::max(summary->max_abs_lambda, std::abs(s.lambda(i)));
  }
  /// A sample where the run met a singular configuration: its actuator forces (which grow
  /// like 1/sigma_min(Phi_phi) there) are withheld, NaN, as the statics withholds its forces.
  static void OnDeadPoint(SampleT* s) { Withhold(s); }
  static void Withhold(SampleT* s) {
    s->lambda.setConstant(std::numeric_limits<double>::quiet_NaN());
    s->P_act = std::numeric_limits<double>::quiet_NaN();
  }
  /// The accepted step's configuration (from the last stage when it was there), made the
  /// reference of the warm starts.
  bool Accept(double t, const State& y, SampleT* cur) {
    Coefficients c;
    if (!FromCache(t, y, cur, &c) && !EvaluateFull(t, y, cur, &c)) return false;
    SetReference(*cur, c);
    return true;
  }

  void SetReference(const SampleT& s, const Coefficients& c) {
    q_ref_ = s.q;
    phi_ref_ = s.phi;
    ref_det_ = s.det;
    if constexpr (kNphi > 0) K_ref_ = c.K;
  }

  /// The partitioned solve (file comment): qdd (the law's qdd_p in the prescribed rows) and lambda.
  bool Accelerations(const Dyn& d, const VecQ& F, const VecP& qddp, VecQ* qdd, VecP* lambda) {
    singular_inertia_ = false;
    const VecQ rhs = d.Q + F - d.h;  // I qdd = rhs + S^T lambda
    for (int i = 0; i < kNp; ++i) (*qdd)(prescribed_[i]) = qddp(i);
    if constexpr (kNf > 0) {
      Eigen::Matrix<double, kNf, kNf> Iff;
      VecF b;
      for (int i = 0; i < kNf; ++i) {
        b(i) = rhs(free_[i]);
        for (int k = 0; k < kNp; ++k) b(i) -= d.I(free_[i], prescribed_[k]) * qddp(k);
        for (int j = 0; j < kNf; ++j) Iff(i, j) = d.I(free_[i], free_[j]);
      }
      VecF qddf;
      if constexpr (kNf == 1) {
        if (!(Iff(0, 0) > 0) || !std::isfinite(Iff(0, 0))) {
          singular_inertia_ = true;
          return false;
        }
        qddf(0) = b(0) / Iff(0, 0);
      } else if constexpr (kNf == 2) {
        // Positive definite iff I_00 > 0 and det > 0; Cramer's rule (a fixed-size LDLT with
        // pivoting costs several times more for two coordinates).
        const double det = Iff(0, 0) * Iff(1, 1) - Iff(0, 1) * Iff(1, 0);
        if (!(Iff(0, 0) > 0) || !(det > 0) || !std::isfinite(det)) {
          singular_inertia_ = true;
          return false;
        }
        qddf(0) = (Iff(1, 1) * b(0) - Iff(0, 1) * b(1)) / det;
        qddf(1) = (Iff(0, 0) * b(1) - Iff(1, 0) * b(0)) / det;
      } else {
        const Eigen::LDLT<Eigen::Matrix<double, kNf, kNf>> ldlt(Iff);
        if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0)) {
          singular_inertia_ = true;
          return false;
        }
        qddf = ldlt.solve(b);
      }
      for (int i = 0; i < kNf; ++i) (*qdd)(free_[i]) = qddf(i);
    }
    for (int i = 0; i < kNp; ++i) {
      const int r = prescribed_[i];
      (*lambda)(i) = d.I.row(r).dot(*qdd) - rhs(r);
    }
    return qdd->allFinite() && lambda->allFinite();
  }

  bool SolveAt(const VecQ& q, VecPhi* phi) {
    return internal::SolveOnBranch<M>(p_, q, phi, modes_, options_.max_solver_iterations,
                                      options_.solver_tolerance, ref_det_, &trig_,
                                      &last_solve_not_assemblable_);
  }

  void EvalCoefficients(const VecQ& q, const VecPhi& phi, Coefficients* c) {
    internal::CallCoeffs<M>(p_, q, phi, c, &trig_);
  }

  void EvalDynamics(const VecQ& q, const VecPhi& phi, const VecQ& qd, double t,
                    const Coefficients& c, Dyn* d) {
    internal::CallDynamics<M>(p_, q, phi, qd, t, c, d, &trig_);
  }

  static void Conditioning(const Coefficients& c, double* rcond, double* det) {
    if constexpr (kNphi == 0) {
      (void)c;
      *rcond = 1;
      *det = 1;
    } else {
      internal::ConditioningOf(c.Phi_phi, rcond, det);
    }
  }

  Params p_;
  std::array<int, NP> prescribed_;
  std::array<int, kNf> free_{};
  Motion motion_;
  Force force_;
  PrescribedOptions options_;
  Integrator integrator_;
  Modes modes_ = M::kDefaultModes;
  VecQ q_ref_ = VecQ::Zero();
  VecPhi phi_ref_ = VecPhi::Zero();
  Eigen::Matrix<double, kNphi, kNq> K_ref_ = Eigen::Matrix<double, kNphi, kNq>::Zero();
  Trig trig_{};
  internal::PreparedRhsConstants<M> rhs_constants_;  ///< kStagesByRhs: M::Prepare(p_)
  struct Cache {
    bool valid = false;
    double t = 0;
    State y = State::Zero();
    SampleT sample;
    Coefficients c{};
    Trig trig{};
  };
  Cache cache_;
  bool caching_ = false;
  double ref_det_ = 0;
  int position_failures_ = 0;
  bool indices_valid_ = false, initialized_ = false;
  bool last_solve_not_assemblable_ = false, singular_inertia_ = false;
  bool coulomb_active_ = false, friction_failed_ = false;
};

}  // namespace mechgen::dynamics
