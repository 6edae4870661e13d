/**
 * \file statics/types.h
 * Status, Options and Summary of the statics runtime (namespace mechgen::statics), in the
 * style of position/types.h: every outcome of a statics evaluation is a Status whose
 * meaning is stated as a formula, options carry their defaults inline and are checked by
 * Options::IsValid(), Summary holds numbers and static strings only (filling it never
 * allocates), and nothing here throws.
 *
 * Units and signs (the contract of the generated statics, models/README.md): forces in the
 * model's force unit (N with SI models), torques in force x length (N m); an angle input's
 * driving force is a torque, a slide input's a force. drive_j is what the actuator of input
 * j applies for static equilibrium: the torque on the input's moving link (the ground
 * takes the opposite), counter-clockwise positive, or the force along the slide on the
 * slider. A revolute reaction F_J = (F_J_x, F_J_y) is the force of link_a on link_b at the
 * pin, fixed frame. A friction load f_J is the friction torque on link_b by link_a
 * (revolute, CCW +) or the friction force on the slider along the slide's +u (prismatic).
 */
#pragma once

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "mechgen/core/invalid_option.h"
#include "mechgen/position/types.h"

namespace mechgen::statics {

/// The outcome of a statics evaluation at one configuration.
enum class Status {
  /// The values are usable: cond_1(Phi_phi) <= Options::max_condition, every value finite,
  /// and with friction the iteration converged: for two successive evaluations k-1, k,
  /// ||drive_k - drive_{k-1}||_inf <= relative_tolerance ||drive_k||_inf + absolute_tolerance
  /// and ||f_k - f_{k-1}||_inf <= relative_tolerance ||f_k||_inf + absolute_tolerance.
  kConverged = 0,
  /// A dead point of the kinematics: cond_1(Phi_phi) > Options::max_condition (or a value is
  /// not finite). Reactions and driving forces grow like 1 / sigma_min(Phi_phi) there, so
  /// they are withheld (NaN in Solution::statics); Summary::condition and
  /// Summary::reaction_norm give the figures.
  kSingular,
  /// The friction iteration made Options::max_friction_iterations evaluations without
  /// converging (Summary::last_change is its last drive change), or diverged (a value not
  /// finite after the first evaluation). The last iterate is kept in Solution::statics but
  /// is not an equilibrium.
  kDidNotConverge,
  /// Not a configuration to evaluate: q or phi not finite, the position step before it
  /// failed, an input index out of range, or Options::IsValid() false.
  kInvalidInput,
  /// Nothing was evaluated.
  kNotRun,
};

/// A short, static, human-readable name of a Status.
inline const char* ToString(Status status) {
  switch (status) {
    case Status::kConverged:
      return "converged";
    case Status::kSingular:
      return "singular";
    case Status::kDidNotConverge:
      return "did_not_converge";
    case Status::kInvalidInput:
      return "invalid_input";
    case Status::kNotRun:
      return "not_run";
  }
  return "unknown";
}

/// Options of the statics runtime.
struct Options {
  /// Singular when cond_1(Phi_phi) > max_condition. The position solver accepts
  /// configurations down to 1/cond_1 = position::Options::min_rcond = 1e-6; at a dead point
  /// approached to within delta (rad) cond grows like 1/delta and so do the reactions
  /// (a slider-crank with a = b, rod force F / cos(beta)). 1e6 matches the position
  /// solver: a configuration it accepts gets its forces, one it refuses does not.
  double max_condition = kMaxCondition;  // 1 / kMinRcond (core/constants.h)
  /// Friction iteration (Paul §5.6): f_J <- -gain_J normal_J(f) sign(K_rel_J . direction),
  /// one generated evaluation each, at most this many evaluations. The iteration contracts
  /// by ~ gain / lever arm per step (pin radius x mu / link length, 1e-2 typically), so it
  /// converges to 1e-12 in 3-8 evaluations; more means the friction is close to jamming.
  int max_friction_iterations = 100;
  /// Convergence of the friction iteration (see Status::kConverged); model force units.
  double relative_tolerance = 1e-12;
  double absolute_tolerance = 1e-10;
  /// Also evaluate Statics::stiffness and d2V_dq2 (Model::Stiffness, the generated
  /// EvalStiffness) in Solve() when it converges. Off by default: the second derivatives of the
  /// loads and springs are long (fourbar_loaded: 2727 operations, 14 x EvalStatics), and only
  /// the equilibria (FindEquilibria evaluates them at each one) and the statics sweep (once
  /// per row, without friction) need them.
  bool stiffness = false;
  /// The statics sweep also evaluates the design derivatives of each row (a model with
  /// EvalStaticsDesign: StaticsRecord::design, the columns of --design).
  bool design = false;

  /// Checks every field; on failure writes "Options::field = value. Violated constraint: ..."
  /// to *error (if not nullptr) and returns false.
  bool IsValid(std::string* error) const {
    auto fail = [error](const char* field, double value, const char* rule) {
      return InvalidOption(error, "Options", field, value, rule);
    };
    if (!(max_condition >= 1))
      return fail("max_condition", max_condition, "max_condition >= 1");
    if (max_friction_iterations < 2)
      return fail("max_friction_iterations", max_friction_iterations,
                  "max_friction_iterations >= 2");
    if (!(relative_tolerance >= 0) || !std::isfinite(relative_tolerance))
      return fail("relative_tolerance", relative_tolerance, "0 <= relative_tolerance < inf");
    if (!(absolute_tolerance >= 0) || !std::isfinite(absolute_tolerance))
      return fail("absolute_tolerance", absolute_tolerance, "0 <= absolute_tolerance < inf");
    if (!(relative_tolerance > 0 || absolute_tolerance > 0))
      return fail("absolute_tolerance", absolute_tolerance,
                  "relative_tolerance > 0 or absolute_tolerance > 0");
    return true;
  }
};

/// What a statics evaluation did. Plain numbers, so that a sweep row fills it without
/// allocating.
struct Summary {
  Status status = Status::kNotRun;
  /// Generated Model::Forces (EvalStatics) evaluations (1 without friction).
  int iterations = 0;
  /// ||drive_k - drive_{k-1}||_inf of the last two evaluations of the friction iteration
  /// (force units); 0 without friction, NaN when not evaluated.
  double last_change = std::numeric_limits<double>::quiet_NaN();
  /// cond_1(Phi_phi) at the configuration; inf when Phi_phi is singular.
  double condition = std::numeric_limits<double>::quiet_NaN();
  /// max_i |R_i| of the frictionless reactions (force units; a prismatic joint's moment in
  /// force x length), evaluated even when kSingular (the figure that says how large they
  /// grow); NaN for a model without reactions.
  double reaction_norm = std::numeric_limits<double>::quiet_NaN();
  /// What the failure was about, a static string ("" when converged).
  const char* reason = "";

  bool IsSolutionUsable() const { return status == Status::kConverged; }
};

/// Options of the scans along an input's range (FindDeadZones, FindEquilibria).
struct ScanOptions {
  /// The range is sampled at samples + 1 equally spaced inputs (continuation from one to the
  /// next with the position solver); a transition narrower than one sample step can be
  /// missed (two sign changes between neighbouring samples cancel).
  int samples = 360;
  /// The coarsest scan FindDeadZones() and FindEquilibria() accept (a coarser one returns
  /// kInvalidInput): at least kMinSamples samples, and at most kMaxAngleStep (10 deg) per
  /// sample along every angle input that moves. A coarser scan reports what its few samples
  /// happen to show as converged: 2 samples of a slider-crank's full turn land on its dead
  /// centres, all self-locking, and make the whole turn one dead zone; 1 sample of a turn
  /// sees Q with the same sign at both ends and no equilibrium where there are two. Even at
  /// this resolution a pair of transitions closer than one sample step cancels: the result
  /// is certain only down to the step (the statics tool prints it).
  static constexpr int kMinSamples = 36;
  static constexpr double kMaxAngleStep = 0.17453292519943295;  ///< 10 deg, rad
  /// True when an angle input moving by `angle_range` (rad) is sampled at most
  /// kMaxAngleStep apart.
  bool ResolvesAngle(double angle_range) const {
    return std::abs(angle_range) <= kMaxAngleStep * samples;
  }
  /// A transition found between two samples is refined (bisection for dead zones, the
  /// Illinois variant of regula falsi for equilibria, each evaluation a continuation step to
  /// the new input) until its bracket is shorter than `tolerance` (input units: rad for an
  /// angle, model length for a slide) or after max_refinements evaluations.
  double tolerance = 1e-10;
  int max_refinements = 100;

  bool IsValid(std::string* error) const {
    auto fail = [error](const char* field, double value, const char* rule) {
      return InvalidOption(error, "ScanOptions", field, value, rule);
    };
    if (samples < kMinSamples) return fail("samples", samples, "samples >= kMinSamples = 36");
    if (!(tolerance > 0) || !std::isfinite(tolerance))
      return fail("tolerance", tolerance, "0 < tolerance < inf");
    if (max_refinements < 1) return fail("max_refinements", max_refinements, "max_refinements >= 1");
    return true;
  }
};

/// What a scan did.
struct ScanSummary {
  /// kConverged: every sample was usable and every transition refined to the tolerance;
  /// kSingular: some samples were singular (position or statics), their neighbourhood is not
  /// resolved; kDidNotConverge: a friction iteration or a refinement did not converge;
  /// kInvalidInput: bad options, input index, a scan too coarse for its range
  /// (ScanOptions::kMinSamples, kMaxAngleStep), or the solver not assembled.
  Status status = Status::kNotRun;
  int samples = 0;             ///< samples evaluated
  int unusable_samples = 0;    ///< samples whose position step or statics failed
  int evaluations = 0;         ///< statics evaluations (generated calls), refinements included
  /// The first failing position step, if any (kConverged when none failed).
  position::Status position_status = position::Status::kConverged;
  const char* reason = "";
};

/// A one-line description of a Summary, e.g.
/// "converged: 3 evaluations, last change 0, cond(Phi_phi) = 4.2, max |R| = 1.1e+03".
inline std::string FormatSummary(const Summary& s) {
  char buffer[384];
  std::snprintf(buffer, sizeof(buffer),
                "%s: %d evaluation%s, last change %.3g, cond(Phi_phi) = %.3g, max |R| = %.3g%s%s",
                ToString(s.status), s.iterations, s.iterations == 1 ? "" : "s", s.last_change,
                s.condition, s.reaction_norm, s.reason[0] != 0 ? "; " : "", s.reason);
  return buffer;
}

}  // namespace mechgen::statics
