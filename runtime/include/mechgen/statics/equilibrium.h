/**
 * \file statics/equilibrium.h
 * Equilibrium positions of a loaded mechanism (Paul §6.5.2): the configurations along a
 * motion where the generalized force of the loads, springs and gravity vanishes, Q(q) = 0
 * (frictionless: no actuator needed to hold it there), each with its stability from the
 * stiffness -dQ/dq = d2V/dq2 (a conservative model): stable when > 0 (V has a minimum).
 *
 * FindEquilibria() follows the straight line q_begin -> q_end with the position solver (one
 * continuation step per sample, on the branch it is assembled on), evaluates
 * g(t) = e . Q(q_begin + t e) (e the unit direction of the line; with one input g = Q, with
 * several g is the generalized force along the line and its zeros are the equilibria of the
 * mechanism constrained to the line: the full Q is reported with each), and refines every
 * sign change between neighbouring samples with the Illinois variant of regula falsi
 * (bracketing, superlinear), each point a continuation step of the same solver. A sign
 * change through a pole (|g| growing instead of vanishing: a dead point) is not reported.
 * A scan coarser than ScanOptions::kMinSamples samples or kMaxAngleStep per sample along an
 * angle input is refused (kInvalidInput): it would report "none" as converged where its few
 * samples straddle two equilibria. Two equilibria closer than one sample step are still
 * missed (g changes sign twice between the samples). Only the result list allocates. No
 * exceptions.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"

namespace mechgen::statics {

/// An equilibrium position.
template <class M>
struct Equilibrium {
  using T = ModelTypes<M>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  typename T::VecQ q = NaNs<typename T::VecQ>();      ///< inputs (kNq)
  typename T::VecPhi phi = NaNs<typename T::VecPhi>();  ///< dependent variables (kNphi)
  /// Q at the equilibrium (kNq; force units: N m per rad, N per length): ~0 along the line.
  typename T::VecQ Q = NaNs<typename T::VecQ>();
  /// e^T (-dQ/dq) e: the stiffness along the line (N m/rad for an angle input): from
  /// Model::Stiffness at the equilibrium, or for a model without Statics::stiffness (no
  /// potential) a central difference of e . Q at solved positions t +- 1e-6 (friction
  /// excluded either way); NaN if those could not be solved.
  double stiffness = kNaN;
  /// stiffness > 0: V has a minimum along the line (stable); false also when unknown (NaN).
  bool stable = false;
  /// Refinement evaluations it took; located: the bracket reached ScanOptions::tolerance
  /// (or Q was exactly 0 at a sample).
  int iterations = 0;
  bool located = false;
};

/**
 * \brief The equilibrium positions along the line q_begin -> q_end (see the file comment).
 * \param[in]     options  Statics options (the singular threshold).
 * \param[in]     scan     Samples and the refinement tolerance (input units along the line).
 * \param[in,out] solver   Assembled (state().valid); moved along the line; on return at the
 *                         last sample it reached.
 * \param[in]     q_begin  Start of the line (dim kNq).
 * \param[in]     q_end    End of the line (dim kNq), != q_begin.
 * \param[out]    found    The equilibria in the order of the line (cleared first).
 * \param[out]    summary  May be nullptr.
 * \return ScanSummary::status (statics/types.h).
 */
template <class M, class A>
Status FindEquilibria(const Options& options, const ScanOptions& scan,
                      position::PositionSolver<M, A>* solver,
                      const typename ModelTypes<M>::VecQ& q_begin,
                      const typename ModelTypes<M>::VecQ& q_end,
                      std::vector<Equilibrium<M>>* found, ScanSummary* summary = nullptr) {
  using VecQ = typename ModelTypes<M>::VecQ;
  using F = StaticsFeatures<M>;
  using C = ModelCalls<M>;
  const M& model = solver->model();
  ScanSummary s;
  found->clear();
  auto finish = [&](Status status, const char* reason) {
    s.status = status;
    s.reason = reason;
    if (summary != nullptr) *summary = s;
    return status;
  };
  const double length = (q_end - q_begin).norm();
  if (!options.IsValid(nullptr) || !scan.IsValid(nullptr) || !(length > 0) ||
      !std::isfinite(length) || !solver->state().valid) {
    return finish(Status::kInvalidInput,
                  "invalid options, empty or infinite line, or solver not assembled");
  }
  for (int j = 0; j < C::Nq(model); ++j) {
    if (C::QIsAngle(model, j) && !scan.ResolvesAngle(q_end(j) - q_begin(j))) {
      return finish(Status::kInvalidInput,
                    "scan too coarse: more than 10 deg per sample along an angle input "
                    "(ScanOptions::kMaxAngleStep); use more samples");
    }
  }
  const VecQ e = (q_end - q_begin) / length;
  auto at = [&](double t) { return VecQ(q_begin + t * e); };
  Solution<M> solution;
  typename ModelTypes<M>::Coefficients c;  // at the last evaluated configuration
  Options without_stiffness = options;
  without_stiffness.stiffness = false;  // evaluated at the equilibria only
  // g(t) into *g; false when unusable (position step or statics failed).
  auto evaluate = [&](double t, double* g) {
    const position::Status moved = solver->MoveTo(at(t), nullptr);
    if (moved != position::Status::kConverged) {
      if (s.position_status == position::Status::kConverged) s.position_status = moved;
      return false;
    }
    const position::State<M>& state = solver->state();
    C::Coeffs(model, solver->params(), state.q, state.phi, &c);
    const Status status = Solve<M>(model, without_stiffness, solver->params(), state.q, state.phi, c,
                                   internal::Zeros<VecQ>(C::Nq(model)), &solution);
    s.evaluations += solution.summary.iterations;
    if (status != Status::kConverged) return false;
    *g = e.dot(solution.statics.Q);
    return true;
  };
  // Records the equilibrium at solver->state() = at(t) (solution evaluated there).
  auto record = [&](double t, int iterations, bool located) {
    Equilibrium<M> eq;
    eq.q = solver->state().q;
    eq.phi = solver->state().phi;
    eq.Q = solution.statics.Q;
    bool stiffness = false;
    if constexpr (F::kHasStiffness) {
      if (C::HasStiffness(model)) {
        internal::EvaluateStiffness<M>(model, solver->params(), eq.q, eq.phi, c, &solution.statics);
        eq.stiffness = e.dot(Times(solution.statics.stiffness, e));
        stiffness = true;
      }
    }
    if (!stiffness) {
      // No Statics::stiffness (a model without potential): -dg/dt by a central difference
      // of g at solved positions, h = 1e-6 (truncation ~h^2, rounding ~1e-16 |Q| / h: both
      // ~1e-10 relative); then back to the equilibrium.
      const double h = 1e-6;
      double g_plus = 0, g_minus = 0;
      if (evaluate(t + h, &g_plus) && evaluate(t - h, &g_minus)) {
        eq.stiffness = -(g_plus - g_minus) / (2 * h);
      }
      solver->MoveTo(at(t), nullptr);
    }
    eq.stable = eq.stiffness > 0;
    eq.iterations = iterations;
    eq.located = located;
    found->push_back(eq);
  };
  bool refinement_failed = false;
  // Illinois regula falsi on [lo, hi] with g(lo) g(hi) < 0; records the root if it is one
  // (not a pole), then moves the solver back to t_resume.
  auto refine = [&](double lo, double g_lo, double hi, double g_hi, double t_resume) {
    const double bound = std::max(std::abs(g_lo), std::abs(g_hi));
    double t_c = lo, g_t = g_lo, c_previous = std::numeric_limits<double>::quiet_NaN();
    int side = 0, it = 0;
    bool usable = true, located = false;
    for (; it < scan.max_refinements; ++it) {
      t_c = (g_lo * hi - g_hi * lo) / (g_lo - g_hi);
      // Safeguard: bisection when the secant leaves the bracket.
      if (!(t_c > std::min(lo, hi) && t_c < std::max(lo, hi))) t_c = 0.5 * (lo + hi);
      if (!evaluate(t_c, &g_t)) {
        usable = false;
        break;
      }
      if (g_t == 0 || std::abs(hi - lo) <= scan.tolerance ||
          std::abs(t_c - c_previous) <= 0.5 * scan.tolerance) {
        located = true;
        break;
      }
      c_previous = t_c;
      if ((g_t > 0) == (g_hi > 0)) {
        hi = t_c;
        g_hi = g_t;
        if (side == -1) g_lo *= 0.5;
        side = -1;
      } else {
        lo = t_c;
        g_lo = g_t;
        if (side == +1) g_hi *= 0.5;
        side = +1;
      }
    }
    if (!usable) {
      refinement_failed = true;
    } else if (std::abs(g_t) <= bound) {  // a root, not a pole
      record(t_c, it + 1, located);
      if (!located) refinement_failed = true;
    }
    solver->MoveTo(at(t_resume), nullptr);
  };

  bool has_previous = false;
  double t_previous = 0, g_previous = 0;
  for (int k = 0; k <= scan.samples; ++k) {
    const double t = k == scan.samples ? length : length * k / scan.samples;
    double g = 0;
    ++s.samples;
    if (!evaluate(t, &g)) {
      ++s.unusable_samples;
      has_previous = false;
      continue;
    }
    if (g == 0) {
      record(t, 0, true);
    } else if (has_previous && g_previous != 0 && (g > 0) != (g_previous > 0)) {
      refine(t_previous, g_previous, t, g, t);
    }
    has_previous = true;
    t_previous = t;
    g_previous = g;
  }
  if (s.unusable_samples > 0) {
    return finish(s.position_status != position::Status::kConverged ? Status::kSingular
                                                                     : Status::kDidNotConverge,
                  "some samples were unusable (position step or statics failed)");
  }
  if (refinement_failed) return finish(Status::kDidNotConverge, "a refinement did not converge");
  return finish(Status::kConverged, "");
}

}  // namespace mechgen::statics
