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
#include "mechgen/core/invalid_option.h"
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

/// The motion callable of PrescribedDynamics from NP laws chosen at run time (AnyLaw); NP =
/// Eigen::Dynamic: as many as given (the driven run through the model view, issue 43: the
/// laws' list allocated once, at construction; evaluating it allocates nothing).
template <int NP>
class AnyDrive {
 public:
  static constexpr int kNp = NP;
  using Laws = std::conditional_t<NP == Eigen::Dynamic, std::vector<AnyLaw>, std::array<AnyLaw, (NP > 0 ? NP : 0)>>;
  explicit AnyDrive(Laws laws) : laws_(std::move(laws)) {}
  /// q, qd, qdd of each law at t (a vector of a run-time size is sized first).
  template <class VecP>
  void operator()(double t, VecP* q, VecP* qd, VecP* qdd) const {
    const int n = static_cast<int>(laws_.size());
    if constexpr (VecP::SizeAtCompileTime == Eigen::Dynamic) {
      q->resize(n);
      qd->resize(n);
      qdd->resize(n);
    }
    for (int i = 0; i < n; ++i) {
      const MotionState s = std::visit([t](const auto& law) { return law(t); }, laws_[i]);
      (*q)(i) = s.q;
      (*qd)(i) = s.qd;
      (*qdd)(i) = s.qdd;
    }
  }
  const Laws& laws() const { return laws_; }

 private:
  Laws laws_;
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
  double event_tolerance = kEventTolerance;
  /// Samples every sample_dt from t0 (and at the end); 0: at every accepted step.
  double sample_dt = 0;
  /// A run whose sample grid would hand out more samples than this is refused (kInvalidInput).
  int max_samples = kMaxSimulationSamples;
  int max_solver_iterations = kMaxSolverIterations;
  double solver_tolerance = 0;
  /// A singular configuration approached: approach_steps accepted steps in a row with
  /// 1/cond_1(Phi_phi) < approach_rcond and falling also end the run with kDeadPoint (where
  /// the step size collapses before 1/cond reaches min_rcond).
  double approach_rcond = kApproachRcond;
  int approach_steps = kApproachSteps;
  /// Switching points of the model's loads: restarted at as MinimalOptions says (forward.h).
  bool restart_at_switches = true;
  double switch_min_interval = kSwitchMinInterval;
  int max_switch_restarts = kMaxSwitchRestarts;

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
    auto fail = [error](const char* field, double value, const char* rule) {
      return InvalidOption(error, "PrescribedOptions", field, value, rule);
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

namespace internal {
/// The indices of a run-time number of inputs, at most Max (the driven and free inputs of a
/// driven run through the model view): no allocation.
template <int Max>
struct IndexList {
  std::array<int, Max> index{};
  int count = 0;
  int size() const { return count; }
  int operator[](int i) const { return index[static_cast<size_t>(i)]; }
  int& operator[](int i) { return index[static_cast<size_t>(i)]; }
  void push_back(int k) { index[static_cast<size_t>(count++)] = k; }
};
/// N indices: std::array<int, N>, or IndexList<Max> where N is Eigen::Dynamic.
template <int N, int Max>
using IndicesOf = std::conditional_t<N == Eigen::Dynamic, IndexList<Max>, std::array<int, (N > 0 ? N : 0)>>;
/// A vector of N entries (Eigen::Dynamic: at most Max).
template <int N, int Max>
using VectorOf = Eigen::Matrix<double, N, 1, 0, N == Eigen::Dynamic ? Max : N, 1>;

/// a.dot(b) of two vectors: Eigen's for fixed sizes; for the model view's bounded dynamic ones
/// on fixed-size copies of their length (Eigen reduces a fixed length and a run-time one in
/// different orders: the same sums as the fixed-size instantiation's, to the bit).
template <int Max, int k = 1, class A, class B>
double DotOf(const A& a, const B& b) {
  if constexpr (A::SizeAtCompileTime != Eigen::Dynamic) {
    return a.dot(b);
  } else if constexpr (k <= Max) {
    if (a.size() != k) return DotOf<Max, k + 1>(a, b);
    return Eigen::Matrix<double, k, 1>(a).dot(Eigen::Matrix<double, k, 1>(b));
  } else {
    return a.dot(b);
  }
}
}  // namespace internal

/// One evaluated configuration with drivers. (The model view's vectors: bounded, sized at run
/// time, empty until assigned.)
template <class M, int NP>
struct PrescribedSample {
  static constexpr int kNq = M::kNq, kNphi = M::kNphi;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  using T_ = ModelTypes<M>;
  using VecP = internal::VectorOf<NP, T_::kMaxQ>;
  double t = kNaN;
  typename T_::VecQ q = NaNs<typename T_::VecQ>();
  typename T_::VecQ qd = q, qdd = q;
  typename T_::VecQ Q = q;  ///< applied generalized forces of the model (EvalDynamics)
  typename T_::VecQ F = q;  ///< the caller's forces
  VecP lambda = NaNs<VecP>();  ///< actuators
  typename T_::VecPhi phi = NaNs<typename T_::VecPhi>();
  double T = kNaN, V = kNaN, E = kNaN;  ///< kinetic, potential, T + V
  double W_nc = 0, W_act = 0, W_F = 0;  ///< works since t0 (non-conservative, actuators, F)
  double P_nc = 0, P_act = 0, P_F = 0;  ///< their powers
  double rcond = 1;                     ///< 1/cond_1(Phi_phi) (1 for kNphi = 0)
  double det = 1;                       ///< det Phi_phi (its sign: the branch)
  /// Coulomb friction (PrescribedSummary::coulomb): the friction loads f_J of the model's
  /// kFrictionJoints (as Sample::friction: N m on the joint's second link by its first, CCW
  /// +; N on the slider along +u), in lambda and P_nc; 0 without.
  using VecFriction =
      typename FrictionState<CoulombFeatures<M>::kNumFriction, CoulombFeatures<M>::kMaxFriction>::VecF;
  VecFriction friction = internal::ZeroOrEmpty<VecFriction>();
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
 *
 * The model is reached through ModelCalls<M> (core/model_calls.h): a generated model (its
 * empty tag; fixed sizes), or the model view (M = ViewModel, issue 43; NP = Eigen::Dynamic:
 * the driven inputs known at run time, the sizes bounded by the view's maxima), the same
 * source instantiated once in the library mechgen_runtime_view (core/view_runtime.h). The
 * view's arithmetic is the fixed-size one's: the reduced inertia solved and the inner
 * products taken on fixed-size copies of the run-time sizes.
 */
template <class M, int NP, class Motion, class Force = NoForce, template <int> class Method = Dopri5>
class PrescribedDynamics {
 public:
  using Calls = ModelCalls<M>;
  using Types = ModelTypes<M>;
  static constexpr bool kView = Calls::kView;
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kNp = NP;
  static constexpr int kMaxQ = Types::kMaxQ;
  static constexpr bool kDynamic = kNq == Eigen::Dynamic || NP == Eigen::Dynamic;
  static constexpr int kNf = kDynamic ? Eigen::Dynamic : kNq - NP;
  static constexpr int kN = kDynamic ? Eigen::Dynamic : 2 * kNf + 3;  ///< (q_f, qd_f, W_nc, W_act, W_F)
  static_assert(NP == Eigen::Dynamic || (NP >= 0 && (kNq == Eigen::Dynamic || NP <= kNq)),
                "0 <= prescribed coordinates <= kNq");
  static_assert(internal::HasDynamics<M>::value,
                "PrescribedDynamics needs a model generated with `dynamics` (Model::DynamicsT)");
  static_assert(ModelFeatures<M>::kHasSolve, "PrescribedDynamics needs the generated M::Solve");
  using Params = typename Types::Params;
  using Coefficients = typename Types::Coefficients;
  using Dyn = typename Calls::template DynamicsOut<M>;
  using State = internal::IntegratorState<kN>;
  using VecQ = typename Types::VecQ;
  using VecP = internal::VectorOf<NP, kMaxQ>;
  using VecF = internal::VectorOf<kNf, kMaxQ>;
  using VecPhi = typename Types::VecPhi;
  using MatK = typename Types::MatK;
  using MatCPhi = typename Types::MatCPhi;
  using Modes = typename Calls::Modes;
  using Integrator = Method<kN>;
  using SampleT = PrescribedSample<M, NP>;
  /// The prescribed and the free inputs' indices (std::array, or a bounded list of a run-time
  /// length).
  using Indices = internal::IndicesOf<NP, kMaxQ>;
  using FreeIndices = internal::IndicesOf<kNf, kMaxQ>;
  static constexpr bool kHasTrig = ModelFeatures<M>::kHasTrig;
  using Trig = typename Calls::Trig;
  /// The stages solve only the sin and cos of the angles (M::SolveTrig, no atan2), as
  /// MinimalDynamics does; the angles are recovered where a sample needs them. (For the view:
  /// whether its model may; StagesByTrig() says whether it does.)
  static constexpr bool kStagesByTrig = kHasTrig && kNphi != 0 && internal::HasSolveTrig<M>::value;
  /// ... and by the one-pass M::Rhs where it is generated (forward.h: K, L, I, h, Q, Phi_phi).
  static constexpr bool kStagesByRhs = kStagesByTrig && internal::HasRhs<M>::value;
  /// The model's loads may have switching points (M::SwitchModes): PrescribedOptions::restart_at_switches
  /// (HasSwitches(): whether they have).
  using SwitchModes = typename Calls::SwitchModesArray;
  static constexpr int kNumSwitches = static_cast<int>(std::tuple_size<SwitchModes>::value);
  static constexpr bool kHasSwitches = kNumSwitches > 0;
  /// Coulomb friction in the actuator forces (PrescribedOptions::coulomb): friction joints,
  /// every input driven (kNf = 0: the motion, and so every joint's relative velocity, is
  /// given) and no caller's forces (which the reactions would miss). A run with free inputs
  /// leaves it out and says so (PrescribedSummary::message). Through the view: whether it may
  /// (HasDrivenFriction(): whether it does).
  static constexpr bool kHasDrivenFriction = CoulombFeatures<M>::kHasFriction &&
                                             (kNf == 0 || kNf == Eigen::Dynamic) && std::is_same_v<Force, NoForce>;
  static constexpr bool kReportsFriction = kHasDrivenFriction;
  static constexpr int kNumFriction = CoulombFeatures<M>::kNumFriction;

  /// prescribed: the indices into q of the prescribed coordinates, distinct, each in
  /// [0, kNq), in the order of the motion's components (checked by Initialize()).
  /// (A generated M only: a ViewModel names its view.)
  template <class Model = M, std::enable_if_t<!ModelCalls<Model>::kView, int> = 0>
  PrescribedDynamics(const Params& params, const Indices& prescribed, Motion motion, Force force = Force(),
                     const PrescribedOptions& options = PrescribedOptions())
      : PrescribedDynamics(M(), params, prescribed, std::move(motion), std::move(force), options) {}
  /// The driven run of `model` (a ViewModel; for a generated M an empty tag).
  PrescribedDynamics(const M& model, const Params& params, const Indices& prescribed, Motion motion,
                     Force force = Force(), const PrescribedOptions& options = PrescribedOptions())
      : model_(model), p_(params), prescribed_(prescribed), motion_(std::move(motion)), force_(std::move(force)),
        options_(options), integrator_(options.integrator),
        tracker_(model, options.max_solver_iterations, options.solver_tolerance) {
    const int nq = Nq();
    std::array<bool, (kNq == Eigen::Dynamic ? kMaxQ : kNq)> is_prescribed{};
    indices_valid_ = Np() <= nq;
    for (int i = 0; i < Np() && indices_valid_; ++i) {
      const int k = prescribed_[i];
      if (k < 0 || k >= nq || is_prescribed[static_cast<size_t>(k)]) {
        indices_valid_ = false;
        return;
      }
      is_prescribed[static_cast<size_t>(k)] = true;
    }
    if (!indices_valid_) return;
    int n = 0;
    for (int k = 0; k < nq; ++k) {
      if (is_prescribed[static_cast<size_t>(k)]) continue;
      if constexpr (kNf == Eigen::Dynamic) {
        free_.push_back(k);
      } else {
        free_[static_cast<size_t>(n++)] = k;
      }
    }
    (void)n;
  }

  const M& model() const { return model_; }
  /// The model's inputs and angles (kNq, kNphi, or the view's at run time), the prescribed and
  /// the free inputs (NP, kNf, or at run time).
  int Nq() const { return Calls::Nq(model_); }
  int Nphi() const { return Calls::Nphi(model_); }
  int Np() const {
    if constexpr (NP == Eigen::Dynamic) {
      return prescribed_.size();
    } else {
      return NP;
    }
  }
  int Nf() const {
    if constexpr (kNf == Eigen::Dynamic) {
      return free_.size();
    } else {
      return kNf;
    }
  }
  /// Whether the stages solve by sin and cos only, and by M::Rhs (kStagesByTrig, kStagesByRhs;
  /// the view's model at run time).
  bool StagesByTrig() const {
    if constexpr (kView) {
      return Calls::HasSolveTrig(model_) && Nphi() > 0;
    } else {
      return kStagesByTrig;
    }
  }
  bool StagesByRhs() const {
    if constexpr (kView) {
      return StagesByTrig() && Calls::HasRhs(model_);
    } else {
      return kStagesByRhs;
    }
  }
  /// The model's loads have switching points (kHasSwitches; the view's at run time).
  bool HasSwitches() const { return Calls::NumSwitches(model_) > 0; }
  /// Coulomb friction can be in the actuator forces (kHasDrivenFriction; the view's friction
  /// joints and driven inputs at run time).
  bool HasDrivenFriction() const {
    if constexpr (kHasDrivenFriction) {
      return CoulombFriction<M>::Count(model_) > 0 && Nf() == 0;
    } else {
      return false;
    }
  }

  const Params& params() const { return p_; }
  /// The parameters, to change (M::Rhs' constants are prepared again at the next stage).
  Params* mutable_params() {
    rhs_constants_.MarkStale();
    return &p_;
  }
  /// Whether a run from q0 (the inputs at t0) has Coulomb friction in its actuator forces:
  /// HasDrivenFriction(), the option on, and a friction joint with a coefficient (gain mu r or
  /// mu not 0) at the parameters, at q0 (its positions from the model's assembly guess).
  bool SimulatesCoulombAt(const VecQ& q0) {
    if constexpr (kHasDrivenFriction) {
      if (!options_.coulomb.enabled || !HasDrivenFriction()) return false;
      auto phi = Sized<VecPhi>(Nphi());
      for (int i = 0; i < Nphi(); ++i) phi(i) = Calls::AssemblyPhi(model_)[i];
      bool not_assemblable = false;
      if (!internal::SolveOnBranch(model_, p_, q0, &phi, Calls::DefaultModes(model_), options_.max_solver_iterations,
                                   options_.solver_tolerance, 0.0, tracker_.trig(), &not_assemblable))
        return false;
      Coefficients c;
      EvalCoefficients(q0, phi, &c);
      return CoulombFriction<M>::AnyGain(model_, p_, q0, phi, c);
    } else {
      (void)q0;
      return false;
    }
  }

  const PrescribedOptions& options() const { return options_; }
  const Indices& prescribed() const { return prescribed_; }
  const FreeIndices& free() const { return free_; }
  const Motion& motion() const { return motion_; }

  /// The modes of the loads' switching items at (t, y) (M::SwitchModes at the positions
  /// there); false where the positions do not solve. Nothing for a model without switches.
  bool SwitchModesAt(double t, const State& y, SwitchModes* modes) {
    if constexpr (kHasSwitches) {
      if (!HasSwitches()) return true;
      VecQ q, qd;
      VecP qddp;
      Assemble(t, FreeOf(y, 0), FreeOf(y, 1), &q, &qd, &qddp);
      VecPhi phi = Predictor(q);
      if (!SolveAt(q, &phi)) return false;
      Coefficients c;
      EvalCoefficients(q, phi, &c);
      Calls::SwitchModes(model_, p_, q, phi, qd, t, c, modes);
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
    if constexpr (kNq == Eigen::Dynamic) {
      q->resize(Nq());
      qd->resize(Nq());
    }
    for (int i = 0; i < Np(); ++i) {
      (*q)(prescribed_[i]) = qp(i);
      (*qd)(prescribed_[i]) = qdp(i);
    }
    for (int i = 0; i < Nf(); ++i) {
      (*q)(free_[i]) = qf(i);
      (*qd)(free_[i]) = qdf(i);
    }
  }

  /**
   * \brief Assembles at time t0 with the free coordinates qf0 (the prescribed ones from the
   * motion) from phi_guess on the given modes (the model's default modes without). false when
   * it does not assemble or the prescribed indices are invalid.
   */
  bool Initialize(double t0, const VecF& qf0, const VecPhi& phi_guess) {
    return Initialize(t0, qf0, phi_guess, Calls::DefaultModes(model_));
  }
  bool Initialize(double t0, const VecF& qf0, const VecPhi& phi_guess, const Modes& modes) {
    initialized_ = false;
    if (!indices_valid_) return false;
    VecQ q, qd;
    VecP qddp;
    Assemble(t0, qf0, ZeroF(), &q, &qd, &qddp);
    tracker_.set_ref_det(0);  // (a new run: either branch)
    Coefficients c;
    if (!tracker_.Assemble(model_, p_, q, phi_guess, modes, &c, &last_solve_not_assemblable_)) return false;
    initialized_ = true;
    return true;
  }

  /// Initialize() from the model's assembly guess (kAssemblyPhi, kDefaultModes).
  bool Initialize(double t0, const VecF& qf0) {
    auto guess = Sized<VecPhi>(Nphi());
    for (int i = 0; i < Nphi(); ++i) guess(i) = Calls::AssemblyPhi(model_)[i];
    return Initialize(t0, qf0, guess);
  }

  /**
   * \brief The configuration at (t, y): positions, I, h, Q, F, the free accelerations and the
   * actuator forces, into *s (W_* from y). false when the positions do not solve or I_ff is
   * not positive definite.
   */
  bool Evaluate(double t, const State& y, SampleT* s) {
    Reference r;
    return EvaluateFull(t, y, s, &r);
  }

  /**
   * \brief The reduced right-hand side: dy = (qd_f, qdd_f, P_nc, P_act, P_F) at (t, y).
   * \return false when the positions do not solve or I_ff is not positive definite.
   */
  bool Derivative(double t, const State& y, State* dy) {
    SampleT s;
    Reference r;
    if (!Stage(t, y, /*by_trig=*/true, &s, &r)) return false;
    const int nf = Nf();
    if constexpr (kN == Eigen::Dynamic) dy->resize(2 * nf + 3);
    for (int i = 0; i < nf; ++i) {
      (*dy)(i) = s.qd(free_[i]);
      (*dy)(nf + i) = s.qdd(free_[i]);
    }
    (*dy)(2 * nf) = s.P_nc;
    (*dy)(2 * nf + 1) = s.P_act;
    (*dy)(2 * nf + 2) = s.P_F;
    if (caching_) {
      // Simulate() reuses the last evaluation (the FSAL one at an accepted step's end) for the
      // step's events and samples instead of evaluating that state again.
      cache_.valid = true;
      cache_.t = t;
      cache_.y = y;
      cache_.sample = s;
      cache_.reference = r;
      if constexpr (kStagesByTrig) cache_.trig = *tracker_.trig();
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
    const int nf = Nf();
    State y0 = ZeroY();
    for (int i = 0; i < nf; ++i) {
      y0(i) = qf0(i);
      y0(nf + i) = qdf0(i);
    }
    internal::EventSettings events;
    events.min_rcond = options_.min_rcond;
    events.event_tolerance = options_.event_tolerance;
    events.sample_dt = options_.sample_dt;
    events.max_samples = options_.max_samples;
    events.steady = options_.steady;
    events.approach_rcond = options_.approach_rcond;
    events.approach_steps = options_.approach_steps;
    events.restart_at_switches = options_.restart_at_switches && kHasSwitches && HasSwitches();
    events.switch_min_interval = options_.switch_min_interval;
    events.max_switch_restarts = options_.max_switch_restarts;
    coulomb_active_ = false;
    friction_failed_ = false;
    if constexpr (CoulombFeatures<M>::kHasFriction) {
      // (The view: only where its model has friction joints, as a generated model's type says.)
      if (options_.coulomb.enabled && CoulombFriction<M>::Count(model_) > 0) {
        if (HasDrivenFriction()) {
          if constexpr (kHasDrivenFriction) {
            VecQ q, qd;
            VecP qddp;
            Assemble(t0, qf0, qdf0, &q, &qd, &qddp);
            VecPhi phi = tracker_.phi_ref();
            Coefficients c;
            if (SolveAt(q, &phi)) {
              EvalCoefficients(q, phi, &c);
              coulomb_active_ = CoulombFriction<M>::AnyGain(model_, p_, q, phi, c);
            }
            summary->coulomb = coulomb_active_;
          }
        } else {
          summary->message = Nf() > 0 ? "Coulomb friction is not simulated in a driven run with free inputs"
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
  /// What an evaluation hands on to the accepted step: K (the warm starts' predictor) and
  /// Phi_phi (the conditioning), nothing else of the coefficients.
  struct Reference {
    MatK K = internal::ZeroState<MatK>();
    MatCPhi Phi_phi = internal::ZeroState<MatCPhi>();
  };

  /// Evaluate() with K and Phi_phi (positions by M::Solve, the angles included).
  bool EvaluateFull(double t, const State& y, SampleT* s, Reference* r) {
    if (!Stage(t, y, /*by_trig=*/false, s, r)) return false;
    Conditioning(r->Phi_phi, &s->rcond, &s->det);
    if (s->rcond < options_.min_rcond) Withhold(s);
    return true;
  }

  /// One evaluation without the conditioning. by_trig (and the model has SolveTrig): the
  /// positions as sin and cos only; s->phi is then the warm start's predictor. *r: K and
  /// Phi_phi there.
  bool Stage(double t, const State& y, bool by_trig, SampleT* s, Reference* r) {
    VecQ q, qd;
    VecP qddp;
    Assemble(t, FreeOf(y, 0), FreeOf(y, 1), &q, &qd, &qddp);
    VecPhi phi = Predictor(q);
    Dyn d;
    if (coulomb_active_) by_trig = false;  // the kinetostatics need every coefficient
    if constexpr (kStagesByRhs) {
      if (by_trig && StagesByRhs()) {
        // One generated pass: the positions' sin and cos, K, L, I, h, Q (and Phi_phi for the
        // conditioning), of which K and Phi_phi are handed on.
        last_solve_not_assemblable_ = false;
        typename Calls::template RhsOut<M> rhs;
        const auto report = Calls::Rhs(model_, p_, rhs_constants_.Of(model_, p_), q, qd, t, tracker_.modes(), tracker_.trig(), &rhs);
        if (report.status != decltype(report.status)::kConverged) {
          last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
          ++position_failures_;
          return false;
        }
        r->K = rhs.K;
        r->Phi_phi = rhs.Phi_phi;
        d.I = rhs.I;
        d.h = rhs.h;
        d.Q = rhs.Q;
        d.T = rhs.T;
        d.V = rhs.V;
        d.P_nc = rhs.P_nc;
        return Finish(t, y, q, qd, qddp, phi, nullptr, &d, s);
      }
    }
    bool solved = false;
    bool trig_only = false;
    if constexpr (kStagesByTrig) trig_only = by_trig && StagesByTrig();
    if (trig_only) {
      if constexpr (kStagesByTrig) {
        last_solve_not_assemblable_ = false;
        const auto report = Calls::SolveTrig(model_, p_, q, tracker_.modes(), tracker_.trig());
        solved = report.status == decltype(report.status)::kConverged;
        if (!solved) last_solve_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
      }
    } else {
      solved = SolveAt(q, &phi);
    }
    if (!solved) {
      ++position_failures_;
      return false;
    }
    Coefficients c;
    EvalCoefficients(q, phi, &c);
    EvalDynamics(q, phi, qd, t, c, &d);
    r->K = c.K;
    if constexpr (kNphi != 0) r->Phi_phi = c.Phi_phi;
    return Finish(t, y, q, qd, qddp, phi, &c, &d, s);
  }

  /// The rest of a stage from its dynamics *d: the caller's forces, the partitioned solve,
  /// Coulomb friction (c: the coefficients, which a stage with friction has), the sample.
  bool Finish(double t, const State& y, const VecQ& q, const VecQ& qd, const VecP& qddp, const VecPhi& phi,
              const Coefficients* c, Dyn* dp, SampleT* s) {
    Dyn& d = *dp;
    VecQ F = Sized<VecQ>(Nq());
    force_(t, q, qd, &F);
    VecQ qdd;
    VecP lambda;
    if (!Accelerations(d, F, qddp, &qdd, &lambda)) return false;
    if constexpr (kView) {
      if constexpr (CoulombFeatures<M>::kHasFriction) s->friction = CoulombFriction<M>::ZeroF(model_);
    } else {
      s->friction.setZero();
    }
    if constexpr (kHasDrivenFriction) {
      if (coulomb_active_) {
        // Every input driven: the friction loads at the given motion, lambda = I qdd + h - Q - K_rel^T f.
        VecQ Q_f;
        int iterations = 0;
        friction_failed_ = false;
        if (!CoulombFriction<M>::Prescribed(model_, options_.coulomb, p_, q, phi, qd, qdd, t, *c, &s->friction, &Q_f,
                                            &iterations)) {
          friction_failed_ = true;
          return false;
        }
        for (int i = 0; i < Np(); ++i) lambda(i) -= Q_f(prescribed_[i]);
        d.Q += Q_f;
        d.P_nc += internal::DotOf<kMaxQ>(Q_f, qd);
      }
    } else {
      (void)c;
    }
    const int nf = Nf();
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
    s->W_nc = y(2 * nf);
    s->W_act = y(2 * nf + 1);
    s->W_F = y(2 * nf + 2);
    s->P_nc = d.P_nc;
    double P_act = 0;
    for (int i = 0; i < Np(); ++i) P_act += lambda(i) * qd(prescribed_[i]);
    s->P_act = P_act;
    s->P_F = internal::DotOf<kMaxQ>(F, qd);
    return true;
  }

  /// The sample at (t, y) from the last Derivative() call, if it was at exactly (t, y).
  bool FromCache(double t, const State& y, SampleT* s, Reference* r) const {
    if (!cache_.valid || cache_.t != t || cache_.y != y) return false;
    *s = cache_.sample;
    *r = cache_.reference;
    if constexpr (kStagesByTrig) {
      // The angles from their sin and cos, within pi of the predictor (sample.phi).
      const double two_pi = 6.283185307179586;
      for (int i = 0; i < Nphi() && StagesByTrig(); ++i) {
        const double angle =
            std::atan2(Calls::TrigSinPhi(model_, cache_.trig, i), Calls::TrigCosPhi(model_, cache_.trig, i));
        const double turns = std::floor((angle - s->phi(i)) / two_pi + 0.5);
        s->phi(i) = std::isfinite(turns) ? angle - two_pi * turns : angle;
      }
    }
    Conditioning(r->Phi_phi, &s->rcond, &s->det);
    if (s->rcond < options_.min_rcond) Withhold(s);
    return true;
  }

  friend struct internal::EventLoop;
  template <class, class, class, class>
  friend class internal::EventLoopRun;
  static constexpr bool kCanProjectEnergy = false;

  // ---- the hooks of the event loop (simulator.h) ----
  void EndRun() {
    caching_ = false;
    cache_.valid = false;
  }
  static double Balance(const SampleT& s) { return s.Balance(); }
  static void Record(const SampleT& s, PrescribedSummary* summary) {
    for (int i = 0; i < static_cast<int>(s.lambda.size()); ++i)
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
    Reference r;
    if (!FromCache(t, y, cur, &r) && !EvaluateFull(t, y, cur, &r)) return false;
    if constexpr (kNphi != 0) {
      tracker_.SetReference(cur->q, cur->phi, r.K, cur->det);
    } else {
      tracker_.SetReference(cur->q, cur->phi, tracker_.K_ref(), cur->det);
    }
    return true;
  }

  /// The partitioned solve (file comment): qdd (the law's qdd_p in the prescribed rows) and lambda.
  bool Accelerations(const Dyn& d, const VecQ& F, const VecP& qddp, VecQ* qdd, VecP* lambda) {
    singular_inertia_ = false;
    const VecQ rhs = d.Q + F - d.h;  // I qdd = rhs + S^T lambda
    const int np = Np(), nf = Nf();
    if constexpr (kNq == Eigen::Dynamic) qdd->resize(Nq());
    if constexpr (NP == Eigen::Dynamic) lambda->resize(np);
    for (int i = 0; i < np; ++i) (*qdd)(prescribed_[i]) = qddp(i);
    if constexpr (kNf == Eigen::Dynamic) {
      if (nf > 0 && !SolveFreeOfSize<1>(d, rhs, qddp, qdd)) return false;
    } else if constexpr (kNf > 0) {
      if (!SolveFree<kNf>(d, rhs, qddp, qdd)) return false;
    }
    (void)nf;
    if constexpr (kNq == Eigen::Dynamic) {
      LambdaOfSize<1>(d, rhs, qdd, lambda);
    } else {
      Lambda<kNq>(d.I, rhs, *qdd, lambda);
    }
    return qdd->allFinite() && lambda->allFinite();
  }

  /// qdd_f = I_ff^-1 (rhs_f - I_fp qdd_p) on kF x kF (the view: kF the run-time Nf()).
  template <int kF>
  bool SolveFree(const Dyn& d, const VecQ& rhs, const VecP& qddp, VecQ* qdd) {
    Eigen::Matrix<double, kF, kF> Iff;
    Eigen::Matrix<double, kF, 1> b;
    for (int i = 0; i < kF; ++i) {
      b(i) = rhs(free_[i]);
      for (int k = 0; k < Np(); ++k) b(i) -= d.I(free_[i], prescribed_[k]) * qddp(k);
      for (int j = 0; j < kF; ++j) Iff(i, j) = d.I(free_[i], free_[j]);
    }
    Eigen::Matrix<double, kF, 1> qddf;
    if constexpr (kF == 1) {
      if (!(Iff(0, 0) > 0) || !std::isfinite(Iff(0, 0))) {
        singular_inertia_ = true;
        return false;
      }
      qddf(0) = b(0) / Iff(0, 0);
    } else if constexpr (kF == 2) {
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
      const Eigen::LDLT<Eigen::Matrix<double, kF, kF>> ldlt(Iff);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0)) {
        singular_inertia_ = true;
        return false;
      }
      qddf = ldlt.solve(b);
    }
    for (int i = 0; i < kF; ++i) (*qdd)(free_[i]) = qddf(i);
    return true;
  }
  template <int k>
  bool SolveFreeOfSize(const Dyn& d, const VecQ& rhs, const VecP& qddp, VecQ* qdd) {
    if constexpr (k <= kMaxQ) {
      if (Nf() != k) return SolveFreeOfSize<k + 1>(d, rhs, qddp, qdd);
      return SolveFree<k>(d, rhs, qddp, qdd);
    } else {
      (void)d, (void)rhs, (void)qddp, (void)qdd;
      singular_inertia_ = true;
      return false;
    }
  }

  /// lambda_i = I_r. qdd - rhs_r, r the i-th prescribed input, of a kQ x kQ inertia.
  template <int kQ, class MatI>
  void Lambda(const MatI& I, const VecQ& rhs, const Eigen::Matrix<double, kQ, 1>& qdd, VecP* lambda) const {
    for (int i = 0; i < Np(); ++i) {
      const int r = prescribed_[i];
      (*lambda)(i) = I.row(r).dot(qdd) - rhs(r);
    }
  }
  /// The same for the view's I and qdd, on fixed-size copies of their run-time size (the
  /// fixed-size instantiation's inner products, to the bit).
  template <int k>
  void LambdaOfSize(const Dyn& d, const VecQ& rhs, const VecQ* qdd, VecP* lambda) const {
    if constexpr (k <= kMaxQ) {
      if (Nq() != k) return LambdaOfSize<k + 1>(d, rhs, qdd, lambda);
      Lambda<k>(Eigen::Matrix<double, k, k>(d.I), rhs, Eigen::Matrix<double, k, 1>(*qdd), lambda);
    } else {
      (void)d, (void)rhs, (void)qdd, (void)lambda;
    }
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
  }

  /// 1/cond_1 and det of Phi_phi (1 and 1 without closed loops).
  template <class PhiPhi>
  static void Conditioning(const PhiPhi& Phi_phi, double* rcond, double* det) {
    if constexpr (kNphi == 0) {
      (void)Phi_phi;
      *rcond = 1;
      *det = 1;
    } else {
      internal::ConditioningOf(Phi_phi, rcond, det);
    }
  }

  // ---- the state's parts and the warm start, at the model's sizes ----
  /// The free coordinates (part 0) or their speeds (part 1) of a state.
  VecF FreeOf(const State& y, int part) const {
    if constexpr (kNf != Eigen::Dynamic) {
      return y.template segment<kNf>(part * kNf);
    } else {
      const int nf = Nf();
      VecF v(nf);
      ::mechgen::internal::CopyEntries(y.data() + part * nf, nf, v.data());
      return v;
    }
  }
  VecF ZeroF() const {
    if constexpr (kNf != Eigen::Dynamic) {
      return VecF::Zero();
    } else {
      return VecF::Zero(Nf());
    }
  }
  State ZeroY() const {
    if constexpr (kN != Eigen::Dynamic) {
      return State::Zero();
    } else {
      return State::Zero(2 * Nf() + 3);
    }
  }
  /// The warm start of the positions at q (PositionTracker::Predictor).
  VecPhi Predictor(const VecQ& q) const { return tracker_.Predictor(q); }

  M model_;
  Params p_;
  Indices prescribed_;
  FreeIndices free_{};
  Motion motion_;
  Force force_;
  PrescribedOptions options_;
  Integrator integrator_;
  PositionTracker<M> tracker_;  ///< the positions along the run: modes, reference, branch, sin and cos
  internal::PreparedRhsConstants<M> rhs_constants_;  ///< kStagesByRhs: M::Prepare(p_)
  struct Cache {
    bool valid = false;
    double t = 0;
    State y = internal::ZeroState<State>();
    SampleT sample;
    Reference reference;
    Trig trig{};
  };
  Cache cache_;
  bool caching_ = false;
  int position_failures_ = 0;
  bool indices_valid_ = false, initialized_ = false;
  bool last_solve_not_assemblable_ = false, singular_inertia_ = false;
  bool coulomb_active_ = false, friction_failed_ = false;
};

}  // namespace mechgen::dynamics
