/**
 * \file types.h
 * Status, Options and Summary of the mechgen runtime, in the style of Ceres
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

namespace mechgen {

/// The outcome of a position solve (assembly or continuation step).
enum class Status {
  /// ||Phi(q, phi)||_inf <= Options::tolerance and 1/cond_1(Phi_phi) >= Options::min_rcond
  /// at the returned configuration, which lies on the branch the solve started on (or the
  /// requested one): sign(det Phi_phi) unchanged.
  kConverged = 0,
  /// The loop cannot close at q: Levenberg–Marquardt reached a stationary point of
  /// 1/2 ||Phi(q, phi)||_2^2 (Phi_phi^T Phi ~ 0) with ||Phi||_inf > Options::tolerance.
  kNotAssemblable,
  /// Phi_phi loses rank: 1/cond_1(Phi_phi) < Options::min_rcond at the solution, or the only
  /// closing configuration reachable lies on the other branch, i.e. det Phi_phi would have
  /// to pass through 0 on the way (a toggle / change point). K is undefined there.
  kSingular,
  /// Neither Newton (Options::max_newton_iterations, all sub-steps) nor Levenberg–Marquardt
  /// (Options::max_lm_iterations) reached ||Phi||_inf <= Options::tolerance.
  kDidNotConverge,
  /// Some input is not finite (!std::isfinite(q_i), phi_i, parameters), or the solver has no
  /// assembled configuration to continue from.
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
  /// Singular when 1/cond_1(Phi_phi) = 1/(||Phi_phi||_1 ||Phi_phi^{-1}||_1) < min_rcond:
  /// K = -Phi_phi^{-1} Phi_q would lose all but ~ -log10(min_rcond * 1e16) = 4 digits.
  double min_rcond = 1e-12;
  /// A continuation step q0 -> q1 that fails (no convergence, branch change, or a correction
  /// too large for the predictor) is retried on halves, down to |q1 - q0| / 2^max_bisections.
  int max_bisections = 16;
  /// Upper bound on accepted plus rejected sub-steps of one MoveTo(), a guard against
  /// dithering at a toggle position.
  int max_substeps = 10000;
  /// Branch guard: a corrector result phi is accepted only when
  /// ||phi - phi_pred||_inf <= max_correction_ratio * ||phi_pred - phi0||_inf + max_correction_abs,
  /// i.e. the corrector moved phi much less than the predicted motion. A jump to the other
  /// assembly mode moves phi by O(1) while the second-order predictor errs by O(dq^3).
  double max_correction_ratio = 0.5;
  double max_correction_abs = 1e-6;
  /// Predictor phi ~ phi0 + K dq + 1/2 L(dq, dq); false: first order phi0 + K dq.
  bool second_order_predictor = true;
  /// When Newton fails on the smallest sub-step, try Ceres Levenberg–Marquardt (this builds
  /// a ceres::Problem and allocates; it only runs on the failure path).
  bool ceres_fallback = true;
  /// Levenberg–Marquardt iterations for assembly and for the fallback.
  int max_lm_iterations = 200;

  /// Checks every field; on failure writes "Options::field = value. Violated constraint: ..."
  /// to *error (if not nullptr) and returns false.
  bool IsValid(std::string* error) const {
    char buffer[160];
    auto fail = [&](const char* field, double value, const char* rule) {
      std::snprintf(buffer, sizeof(buffer), "Options::%s = %g. Violated constraint: %s", field,
                    value, rule);
      if (error != nullptr) *error = buffer;
      return false;
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
  /// Levenberg–Marquardt (Ceres) was used.
  bool used_ceres = false;

  bool IsSolutionUsable() const { return status == Status::kConverged; }
};

/// A one-line description of a Summary, e.g.
/// "converged: 2 iterations, 1 sub-step, |Phi|_inf = 3.1e-16, cond(Phi_phi) = 4.2, branch +1".
inline std::string FormatSummary(const Summary& s) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer),
                "%s: %d iteration%s, %d sub-step%s (%d rejected), |Phi|_inf = %.3g, "
                "cond(Phi_phi) = %.3g, branch %+d%s",
                ToString(s.status), s.iterations, s.iterations == 1 ? "" : "s", s.substeps,
                s.substeps == 1 ? "" : "s", s.rejected_substeps, s.residual_norm, s.condition,
                s.branch, s.used_ceres ? ", Levenberg-Marquardt used" : "");
  return buffer;
}

}  // namespace mechgen
