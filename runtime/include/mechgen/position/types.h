/**
 * \file position/types.h
 * Status, Crossing, Options and Summary of the position solver (namespace
 * mechgen::position, so that statics and dynamics can have their own), in the style of Ceres
 * (include/ceres/types.h, tiny_solver.h): every outcome of a position solve is a Status
 * value whose meaning is stated as a formula, options carry their defaults inline and are
 * checked by Options::IsValid(), and nothing here throws. Summary holds numbers only (no
 * std::string), so that filling it inside a sweep step never allocates; FormatSummary()
 * builds the human-readable message on demand.
 *
 * Notation (Paul): q inputs (dim kNq), phi dependent variables (dim kNphi), Phi(q, phi) the
 * loop-closure residual (dim kNc == kNphi), Phi_phi = dPhi/dphi (square), Phi_q = dPhi/dq,
 * K = -Phi_phi^{-1} Phi_q, L = dK/dq. Norms of Phi are max-norms in model length units.
 */
#pragma once

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "mechgen/core/constants.h"
#include "mechgen/core/invalid_option.h"

namespace mechgen::position {

/// The outcome of a position solve (assembly or continuation step).
enum class Status {
  /// ||Phi(q, phi)||_inf <= Options::tolerance and 1/cond_1(Phi_phi) >= Options::min_rcond
  /// at the returned configuration, which lies on the branch the solve started on (or the
  /// requested one): sign(det Phi_phi) unchanged.
  kConverged = 0,
  /// The loop cannot close at q: Levenberg–Marquardt reached a stationary point of
  /// 1/2 ||Phi(q, phi)||_2^2 (Phi_phi^T Phi ~ 0) with ||Phi||_inf > Options::tolerance.
  kNotAssemblable,
  /// Phi_phi loses rank on the way: 1/cond_1(Phi_phi) < Options::min_rcond at the solution,
  /// or the only closing configuration reachable lies on the other branch (det Phi_phi
  /// would have to pass through 0: a change point), or the continuation stalls at its
  /// smallest sub-step next to a configuration with sigma_min(Phi_phi) / sigma_max(Phi_phi)
  /// < Options::near_singular_ratio (a dead point / toggle, beyond which the loop does not
  /// close). K is undefined there. MoveTo() then leaves state() at the last valid
  /// configuration on the way, the closest to the singular one (within
  /// |q - q0| 2^-max_bisections); PositionSolver::PassSingularity() continues through it.
  kSingular,
  /// Neither Newton (Options::max_newton_iterations, all sub-steps) nor Levenberg–Marquardt
  /// (Options::max_lm_iterations) reached ||Phi||_inf <= Options::tolerance.
  kDidNotConverge,
  /// Some input is not finite (!std::isfinite(q_i), phi_i, parameters), a step is absurdly
  /// large (|q_j - state().q_j| > Options::max_input_step), or the solver has no assembled
  /// configuration to continue from.
  kInvalidInput,
  /// Assembly converged (||Phi||_inf <= tolerance) but sign(det Phi_phi) differs from the
  /// branch the caller required; the configuration is reported, not adopted.
  kWrongBranch,
  /// Nothing was solved yet.
  kNotRun,
};

/// A short, static, human-readable name of a Status.
inline const char* ToString(Status status) {
  switch (status) {
    case Status::kConverged:
      return "converged";
    case Status::kNotAssemblable:
      return "not_assemblable";
    case Status::kSingular:
      return "singular";
    case Status::kDidNotConverge:
      return "did_not_converge";
    case Status::kInvalidInput:
      return "invalid_input";
    case Status::kWrongBranch:
      return "wrong_branch";
    case Status::kNotRun:
      return "not_run";
  }
  return "unknown";
}

/// What PositionSolver::PassSingularity() and a Sweep do at a singular configuration.
enum class Crossing {
  /// Do not pass: the step (and a sweep) stops with kSingular at the last valid configuration.
  kStop = 0,
  /// Change point (two solution curves cross, e.g. a Grashof-neutral four-bar with
  /// s + l = p + q folded flat): continue on the same smooth curve, along its tangent
  /// (sign det Phi_phi flips).
  kFollowTangent,
  /// Change point: continue on the other curve through it (its tangent from the second-order
  /// bifurcation equation psi^T Phi''(tau, tau) = 0, psi the left null vector).
  kSwitchBranch,
  /// Dead point (fold: the input reaches an extreme, e.g. the rocker of a rocker-driven
  /// crank-rocker): continue along the curve, which turns back, so the input reverses.
  kReverseInput,
};

inline const char* ToString(Crossing crossing) {
  switch (crossing) {
    case Crossing::kStop:
      return "stop";
    case Crossing::kFollowTangent:
      return "follow_tangent";
    case Crossing::kSwitchBranch:
      return "switch_branch";
    case Crossing::kReverseInput:
      return "reverse_input";
  }
  return "unknown";
}

/// Options of PositionSolver. The defaults suit models with lengths of order 1..1000.
struct Options {
  /// Converged when ||Phi(q, phi)||_inf <= tolerance (model length units). Rounding in Phi
  /// is ~ 1e-15 * (sum of link lengths), so 1e-10 leaves 5 orders of margin above it while
  /// the phi error (~ cond(Phi_phi) * tolerance / link length) stays far below plotting or
  /// engineering resolution.
  double tolerance = 1e-10;
  /// Newton–Raphson (Paul's NEWTR) iterations per continuation sub-step (and for polishing
  /// the Levenberg–Marquardt result). Quadratic convergence from the second-order predictor
  /// needs 1–2 at 0.5 deg steps.
  int max_newton_iterations = 8;
  /// Singular when 1/cond_1(Phi_phi) = 1/(||Phi_phi||_1 ||Phi_phi^{-1}||_1) < min_rcond.
  /// Not the rounding limit (1e-16) but the accuracy limit: next to a singular point
  /// Newton converges only linearly, so a configuration solved to ||Phi|| ~ r is off by
  /// ~ r / sigma_min in phi and K by ~ r / sigma_min^2. At a change point approached to
  /// 1e-6 rad (1/cond ~ 1e-6) K already loses ~ 6 digits (bench/stability/README.md);
  /// closer, a solve landing on the crossing itself returns K with O(1) errors.
  double min_rcond = kMinRcond;  // core/constants.h: the one threshold
  /// A continuation step q0 -> q1 that fails (no convergence, branch change, or a correction
  /// too large for the predictor) is retried on halves, down to |q1 - q0| / 2^max_bisections.
  int max_bisections = 16;
  /// Upper bound on accepted plus rejected sub-steps of one MoveTo(), a guard against
  /// dithering at a toggle position.
  int max_substeps = 10000;
  /// Branch guard: a corrector result phi is accepted only when
  /// ||phi - phi_pred||_inf <= max_correction_ratio * ||last predictor term||_inf
  ///                           + max_correction_abs,
  /// the last term being 1/2 L(dq, dq) (K dq for a first-order predictor): on one smooth
  /// solution curve the correction is the next, smaller Taylor term, O(dq^3), while a jump
  /// to another curve moves phi by O(dq) (at a change point) or O(1) (another assembly mode).
  double max_correction_ratio = 0.5;
  double max_correction_abs = 1e-6;
  /// Predictor phi ~ phi0 + K dq + 1/2 L(dq, dq); false: first order phi0 + K dq.
  bool second_order_predictor = true;
  /// When Newton fails on the smallest sub-step, run the solver's Assembler from the
  /// predictor (Levenberg–Marquardt: CeresAssembler builds a ceres::Problem and allocates,
  /// NewtonAssembler does not; either only runs on the failure path).
  bool assembly_fallback = true;
  /// Levenberg–Marquardt iterations of the Assembler, for assembly and for the fallback.
  int max_lm_iterations = 200;
  /// A sub-step is tried only when its predictor moves every angle coordinate of phi by at
  /// most this (rad): larger steps are split before Newton runs. Beyond ~1 rad the Taylor
  /// predictor no longer says which 2 pi-periodic solution is meant, and the correction
  /// guard above (relative to the predicted motion) would accept any of them.
  double max_predicted_angle = 0.5;
  /// A MoveTo() with |q_j - state().q_j| > max_input_step for some j (model units, rad for
  /// angles; 1e3 rad = 159 turns) is refused with kInvalidInput: no sweep step is that long,
  /// so it is a units or bookkeeping mistake, and following it would take more than
  /// max_substeps sub-steps anyway.
  double max_input_step = 1e3;
  /// When the continuation stalls at its smallest sub-step and the last valid configuration
  /// has sigma_min(Phi_phi) / sigma_max(Phi_phi) < near_singular_ratio, the step is reported
  /// as kSingular (a dead point on the way) rather than kNotAssemblable. A regular
  /// configuration (ratio >= 1e-2) cannot stall: Newton's basin there is wider than any
  /// sub-step of 2^-max_bisections of a step; at a dead point approached to within delta,
  /// the ratio is ~ sqrt(delta) ~ 4e-4 for 0.5 deg steps.
  double near_singular_ratio = 1e-2;
  /// Distance to singularity during the continuation (kNphi > 2 only; up to 2 x 2 it is
  /// always exact, in closed form): each step estimates sigma_min and sigma_max from the
  /// previous configuration's singular vectors (one inverse and one power iteration, State::
  /// sigma_exact false) and runs the full Jacobi SVD only when the estimated
  /// sigma_min / sigma_max < exact_sigma_ratio. 10 x near_singular_ratio leaves a margin for
  /// the estimate; 1 makes every step exact.
  double exact_sigma_ratio = 0.1;
  /// Arc length (in (t, phi), t the input along the motion, rad or model units) of the
  /// pseudo-arclength steps with which PassSingularity() steps over a singular
  /// configuration. Small enough that the tangent predictor errs by O(step^2) = 1e-6, far
  /// less than the O(step) separation of the two curves after a change point; large enough
  /// to leave the singular configuration with 1/cond ~ 1e-3.
  double pass_step = 1e-3;

  /// Checks every field; on failure writes "Options::field = value. Violated constraint: ..."
  /// to *error (if not nullptr) and returns false.
  bool IsValid(std::string* error) const {
    auto fail = [error](const char* field, double value, const char* rule) {
      return InvalidOption(error, "Options", field, value, rule);
    };
    if (!(tolerance > 0) || !std::isfinite(tolerance))
      return fail("tolerance", tolerance, "0 < tolerance < inf");
    if (max_newton_iterations < 1)
      return fail("max_newton_iterations", max_newton_iterations, "max_newton_iterations >= 1");
    if (!(min_rcond >= 0 && min_rcond < 1))
      return fail("min_rcond", min_rcond, "0 <= min_rcond < 1");
    if (max_bisections < 0 || max_bisections > 60)
      return fail("max_bisections", max_bisections, "0 <= max_bisections <= 60");
    if (max_substeps < 1) return fail("max_substeps", max_substeps, "max_substeps >= 1");
    if (!(max_correction_ratio > 0))
      return fail("max_correction_ratio", max_correction_ratio, "max_correction_ratio > 0");
    if (!(max_correction_abs >= 0))
      return fail("max_correction_abs", max_correction_abs, "max_correction_abs >= 0");
    if (max_lm_iterations < 1)
      return fail("max_lm_iterations", max_lm_iterations, "max_lm_iterations >= 1");
    if (!(max_predicted_angle > 0))
      return fail("max_predicted_angle", max_predicted_angle, "max_predicted_angle > 0");
    if (!(max_input_step > 0))
      return fail("max_input_step", max_input_step, "max_input_step > 0");
    if (!(near_singular_ratio >= 0 && near_singular_ratio < 1))
      return fail("near_singular_ratio", near_singular_ratio, "0 <= near_singular_ratio < 1");
    if (!(exact_sigma_ratio >= 0 && exact_sigma_ratio <= 1))
      return fail("exact_sigma_ratio", exact_sigma_ratio, "0 <= exact_sigma_ratio <= 1");
    if (!(pass_step > 0 && pass_step < 1))
      return fail("pass_step", pass_step, "0 < pass_step < 1");
    return true;
  }
};

/// What a solve did. Plain numbers, so that a sweep step fills it without allocating.
struct Summary {
  Status status = Status::kNotRun;
  /// Newton iterations (linear solves) plus Levenberg–Marquardt iterations.
  int iterations = 0;
  /// Continuation sub-steps accepted (1 when the step needed no splitting).
  int substeps = 0;
  /// Sub-steps rejected (bisections) by the convergence or branch checks.
  int rejected_substeps = 0;
  /// ||Phi(q, phi)||_inf at the returned configuration; for kNotAssemblable, at the
  /// Levenberg–Marquardt minimum. NaN when nothing was evaluated.
  double residual_norm = std::numeric_limits<double>::quiet_NaN();
  /// cond_1(Phi_phi) = ||Phi_phi||_1 ||Phi_phi^{-1}||_1 (exact for kNphi <= 4, else Eigen's
  /// 1/rcond estimate) at the returned configuration; inf when singular.
  double condition = std::numeric_limits<double>::quiet_NaN();
  /// sign(det Phi_phi) at the returned configuration: the assembly mode (+1 / -1), 0 unknown.
  int branch = 0;
  /// Distance to singularity: sigma_min(Phi_phi), the smallest singular value (2-norm
  /// distance of Phi_phi to the nearest singular matrix; model length units), at the
  /// returned configuration. State::singular_direction holds its right singular vector.
  double sigma_min = std::numeric_limits<double>::quiet_NaN();
  /// Error bounds implied by the conditioning at the returned configuration (State::
  /// phi_error, K_error, L_error; position/solver.h, "Accuracy"): how far phi, K and L may
  /// be from the exact ones. Grow like eps cond, eps cond^2, eps cond^3 next to a singular
  /// configuration: a converged row with cond = 3e5 can have L wrong in its first digit,
  /// and says so here. NaN when nothing was computed.
  double phi_error = std::numeric_limits<double>::quiet_NaN();
  double K_error = std::numeric_limits<double>::quiet_NaN();
  double L_error = std::numeric_limits<double>::quiet_NaN();
  /// The Assembler (Levenberg–Marquardt from a poor guess: assembly, or the fallback of a
  /// continuation step) ran; Ceres when the solver's Assembler is CeresAssembler.
  bool used_assembler = false;
  /// PassSingularity() went through a dead point: the input now moves the other way.
  bool input_reversed = false;
  /// What the failure was about, a static string ("" when converged), e.g. "step larger
  /// than Options::max_input_step".
  const char* reason = "";

  bool IsSolutionUsable() const { return status == Status::kConverged; }
};

/// Result of one Newton–Raphson solve at fixed q.
struct NewtonResult {
  Status status = Status::kNotRun;  ///< kConverged or kDidNotConverge
  int iterations = 0;               ///< linear solves
  double residual_norm = std::numeric_limits<double>::quiet_NaN();  ///< final ||Phi||_inf
};

/// A one-line description of a Summary, e.g.
/// "converged: 2 iterations, 1 sub-step, |Phi|_inf = 3.1e-16, cond(Phi_phi) = 4.2, branch +1".
inline std::string FormatSummary(const Summary& s) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer),
                "%s: %d iteration%s, %d sub-step%s (%d rejected), |Phi|_inf = %.3g, "
                "cond(Phi_phi) = %.3g, sigma_min = %.3g, branch %+d%s%s%s%s",
                ToString(s.status), s.iterations, s.iterations == 1 ? "" : "s", s.substeps,
                s.substeps == 1 ? "" : "s", s.rejected_substeps, s.residual_norm, s.condition,
                s.sigma_min, s.branch, s.used_assembler ? ", Levenberg-Marquardt used" : "",
                s.input_reversed ? ", input reversed" : "", s.reason[0] != 0 ? "; " : "",
                s.reason);
  return buffer;
}

}  // namespace mechgen::position
