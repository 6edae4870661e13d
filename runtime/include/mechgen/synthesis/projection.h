/**
 * \file synthesis/projection.h
 * Variable projection for path generation with the four-bar (issue 44): `search: {projection:
 * true}` in a path task.
 *
 * What holds: for given link ratios (a/d, b/d, c/d) and crank angles psi_i measured from the
 * ground line, the four-bar's coupler point is
 *     P_i = A + z B_i + w u_i,
 * B_i = (a/d) e^{i psi_i} the crank's end and u_i = e^{i gamma_i} the coupler's direction of
 * the linkage normalized to A = 0, D = 1 (closed form, the circle intersection on the model's
 * assembly mode), A = (x0, y0) the crank pivot, z = d e^{i theta0} the scale times the rotation,
 * w = (xi + i eta) e^{i theta0} the coupler point turned with the frame. P is linear in A, z
 * and w: six real unknowns (fewer when the task fixes the frame: A given, or theta0 given and
 * z = d e^{i theta0} with one unknown d), found for each candidate by one small linear least
 * squares (Householder QR). The search (adaptive differential evolution, then
 * Levenberg-Marquardt, both in Deb's rule) runs over the rest only: the three log link ratios,
 * plus the free offset (prescribed timing, `offset: free`) or the crank angles (free timing:
 * psi_1 and each other target's angle from it, sorted when the targets must come in order; a
 * last target equal to the first (a closed curve) is reached after a full turn and is no
 * variable).
 *
 * Constraints, as PathEvaluator::Check has them, judged on the full design that the linear
 * solve gives: the link-length bounds become bounds on |z| (each link = its ratio x |z| within
 * its variable's bounds), and the least squares is solved on that interval exactly (the
 * quadratic in z, the other unknowns eliminated, on the circle |z| = R by its secular equation
 * when the unconstrained |z| is outside: a bound-active optimum such as case 4's is reached,
 * not clipped); the other bounds (xi, eta, x0, y0, theta0) are violations (Deb's rule). The
 * crank shortest and Grashof are kept by repair (Lamarckian: the repaired ratios replace the
 * candidate's): a crank longer than the shortest other link is shortened to 1e-12 (relative)
 * below it, then a longest link that breaks s + l <= p + q is shortened to 1e-8 (relative) inside
 * p + q - s, so that a boundary optimum (case 4: a kite at the Grashof boundary) is reached and
 * written satisfying Grashof strictly in double arithmetic. Not closer: exactly on the boundary
 * the four-bar is a change point, singular where the crank lies along the ground line, and the
 * full turn's motion check (the crank must turn) refuses it there by the project's threshold;
 * 1e-8 inside it is regular (case 4: 1.216212; 1e-6 inside: 1.216247). Every other
 * parameter-only constraint (CheckParameterConstraints) is judged on the full design. Assembly
 * at every target and along the motion between them (or the full turn when the crank must
 * turn), regular by the project's threshold (1/cond_1 of the closed form's Phi_phi, the test
 * path.h's Regular makes on the generated one), at the curve's step, is checked in the reduced
 * evaluation; the transmission-angle bounds are judged by the full check only.
 *
 * The answer of each run is the full design checked as every candidate is (PathEvaluator::Check
 * with the generated model, then the runtime's continuation): the reduced evaluation is the
 * search's objective, the generated model the judge.
 *
 * Counting (the published benchmarks count objective evaluations): one reduced evaluation (the
 * n targets' closed-form positions, the walk between them, one least squares of at most six
 * unknowns) = 1 evaluation; a Levenberg-Marquardt Jacobian (forward differences) = its number
 * of reduced variables (each a reduced evaluation); the full check of a run's answer with the
 * generated model = 1, its continuation = 1. All inside Search::evaluations.
 *
 * Which model: the roles are the parameters a (crank AB), b (coupler BC), c (rocker DC), d
 * (ground AD), xi, eta (the coupler point in the frame at B along BC), x0, y0 (the crank pivot)
 * and theta0 (the ground line's angle), the input the crank's absolute angle
 * (tests/synthesis/models/synth_fourbar.yaml). BindProjection checks that the model's point is
 * this closed form (at the model's values and at moved ones, to 1e-9) and refuses otherwise.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "mechgen/synthesis/optimize.h"

namespace mechgen::synthesis {

/// The four-bar's roles in the model and how the reduced vector is laid out (BindProjection).
struct Projection {
  int sigma = 1;  ///< the model's assembly mode: C to the left (+1) or right (-1) of B -> D
  /// Each role's variable index in task.variables (-1: fixed at the model's value).
  int var_a = -1, var_b = -1, var_c = -1, var_d = -1, var_xi = -1, var_eta = -1, var_x0 = -1, var_y0 = -1,
      var_theta0 = -1;
  double x0 = 0, y0 = 0, theta0 = 0;  ///< fixed values (when not variables)
  bool free_timing = false;
  bool offset_free = false;
  double psi_shift = 0;    ///< prescribed: psi_i = offset + angle_i + psi_shift
  bool closing = false;    ///< free timing: the last target is the first one (after a full turn)
  int timing_vars = 0;     ///< free timing: psi_1 and the others' angles from it
  int dim = 0;             ///< reduced variables: 3 log ratios (+ offset | + timing)
  std::vector<double> lo, hi;
};

namespace projection_internal {
/// The closed form on a normalized four-bar (A = 0, D = (1, 0)): the crank end B, the coupler
/// direction u (B -> C) and the rocker direction v (D -> C). false where it does not assemble.
inline bool Dyad(double ra, double rb, double rc, double psi, int sigma, double* bx, double* by, double* ux, double* uy,
                 double* vx, double* vy) {
  *bx = ra * std::cos(psi), *by = ra * std::sin(psi);
  const double ex = 1 - *bx, ey = -*by;
  const double l2 = ex * ex + ey * ey, l = std::sqrt(l2);
  if (!(l > 0)) return false;
  const double along = (l2 + rb * rb - rc * rc) / (2 * l);
  const double h2 = rb * rb - along * along;
  if (!(h2 >= 0)) return false;
  const double h = sigma * std::sqrt(h2);
  const double cx = *bx + (along * ex - h * ey) / l, cy = *by + (along * ey + h * ex) / l;
  *ux = (cx - *bx) / rb, *uy = (cy - *by) / rb;
  *vx = (cx - 1) / rc, *vy = cy / rc;
  return std::isfinite(*ux) && std::isfinite(*uy);
}
/// The same without the rocker.
inline bool Dyad(double ra, double rb, double rc, double psi, int sigma, double* bx, double* by, double* ux, double* uy) {
  double vx, vy;
  return Dyad(ra, rb, rc, psi, sigma, bx, by, ux, uy, &vx, &vy);
}

/// Regular by the project's threshold (core/constants.h: 1/cond_1(Phi_phi) >= kMinRcond, as
/// synthesis/path.h's Regular on the generated Phi_phi): Phi_phi of the loop closure
/// A + a e^{i theta} + b e^{i gamma} - c e^{i beta} - (D - A) = 0 in (gamma, beta), the
/// coupler and rocker directions turned by the frame's angle (c, s).
inline bool RegularDyad(double rb, double rc, double ux, double uy, double vx, double vy, double c, double s) {
  const double gx = c * ux - s * uy, gy = s * ux + c * uy, kx = c * vx - s * vy, ky = s * vx + c * vy;
  const double p00 = -rb * gy, p01 = rc * ky, p10 = rb * gx, p11 = -rc * kx;
  const double det = p00 * p11 - p01 * p10;
  if (!(det != 0) || !std::isfinite(det)) return false;
  const double norm = std::max(std::abs(p00) + std::abs(p10), std::abs(p01) + std::abs(p11));
  const double inv = std::max(std::abs(p11) + std::abs(p10), std::abs(p01) + std::abs(p00)) / std::abs(det);
  return norm * inv * kMinRcond <= 1.0;
}
}  // namespace projection_internal

/// Binds the projection to a bound path task: the roles must exist and be the four-bar's, the
/// links and the coupler point must be variables, the frame x0, y0 both or neither, the timing
/// free or measured from theta0 (or theta0 fixed). false and *error (FILE:LINE:COLUMN).
template <class M>
bool BindProjection(const BoundPath<M>& b, Projection* out, std::string* error) {
  const PathTask& t = b.task;
  const std::string where = bind_internal::Where(t.file, t.search.projection_line, t.search.projection_column);
  using Params = typename ModelTypes<M>::Params;
  const M& model = *b.model;
  auto find = [&model](Params* p, const char* name) { return ModelCalls<M>::FindParameter(model, p, name); };
  Params base = b.base;
  const char* roles[9] = {"a", "b", "c", "d", "xi", "eta", "x0", "y0", "theta0"};
  for (const char* r : roles)
    if (find(&base, r) == nullptr) {
      *error = where + "projection: the model has no parameter '" + r +
               "'; it needs the four-bar's a, b, c, d, xi, eta, x0, y0, theta0 (tests/synthesis/models/synth_fourbar.yaml)";
      return false;
    }
  Projection pr;
  int* vars[9] = {&pr.var_a, &pr.var_b, &pr.var_c, &pr.var_d, &pr.var_xi, &pr.var_eta, &pr.var_x0, &pr.var_y0, &pr.var_theta0};
  for (size_t j = 0; j < t.variables.size(); ++j) {
    bool role = false;
    for (int k = 0; k < 9; ++k)
      if (t.variables[j].name == roles[k]) *vars[k] = static_cast<int>(j), role = true;
    if (!role) {
      *error = bind_internal::Where(t.file, t.variables[j].line, t.variables[j].column) + "projection: variable '" +
               t.variables[j].name + "' is none of the four-bar's a, b, c, d, xi, eta, x0, y0, theta0; remove it or `projection`";
      return false;
    }
  }
  for (int k = 0; k < 6; ++k)
    if (*vars[k] < 0) {
      *error = where + "projection: '" + roles[k] + "' must be a variable (the links and the coupler point are solved or searched)";
      return false;
    }
  if ((pr.var_x0 < 0) != (pr.var_y0 < 0)) {
    *error = where + "projection: x0 and y0 must both be variables or both fixed";
    return false;
  }
  pr.x0 = *find(&base, "x0"), pr.y0 = *find(&base, "y0"), pr.theta0 = *find(&base, "theta0");
  pr.free_timing = t.timing.free;
  if (!t.timing.free) {
    pr.offset_free = t.timing.offset_free;
    if (t.timing.relative_to == "theta0") {
      pr.psi_shift = 0;
    } else if (pr.var_theta0 < 0 && b.relative_to < 0) {
      pr.psi_shift = b.relative_fixed - pr.theta0;  // absolute angles on a fixed frame
    } else {
      *error = bind_internal::Where(t.file, t.timing.line, t.timing.column) +
               "projection: prescribed angles must be measured from theta0 (relative_to: theta0) when theta0 varies";
      return false;
    }
  } else {
    const double size = 1 + std::hypot(t.tx[0], t.ty[0]);
    pr.closing = b.n > 2 && std::hypot(t.tx[static_cast<size_t>(b.n - 1)] - t.tx[0], t.ty[static_cast<size_t>(b.n - 1)] - t.ty[0]) <=
                                1e-9 * size;
    pr.timing_vars = pr.closing ? b.n - 1 : b.n;
  }
  // The log ratios' bounds: each link within its bounds over the ground within its, a link at
  // least 1e-3 of its upper bound.
  const std::vector<Variable>& v = t.variables;
  const Variable& vd = v[static_cast<size_t>(pr.var_d)];
  const double d_lo = std::max(vd.lo, 1e-3 * vd.hi), d_hi = vd.hi;
  for (int k = 0; k < 3; ++k) {
    const Variable& vk = v[static_cast<size_t>(*vars[k])];
    pr.lo.push_back(std::log(std::max(vk.lo, 1e-3 * vk.hi) / d_hi));
    pr.hi.push_back(std::log(vk.hi / d_lo));
  }
  if (pr.offset_free) pr.lo.push_back(0), pr.hi.push_back(kTwoPi);
  for (int k = 0; k < pr.timing_vars; ++k) pr.lo.push_back(0), pr.hi.push_back(kTwoPi);
  pr.dim = static_cast<int>(pr.lo.size());
  // The mode, and that the model's point is the closed form: at the model's values and at
  // moved ones, at the input angles where the model assembles.
  PathEvaluator<M> eval(b);
  Params moved = base;
  *find(&moved, "a") *= 0.9, *find(&moved, "xi") += 0.3, *find(&moved, "eta") -= 0.2, *find(&moved, "x0") += 0.5;
  *find(&moved, "y0") -= 0.25, *find(&moved, "theta0") += 0.3;
  ModelCalls<M>::ParametersSet(model, &moved);
  int agree[2] = {0, 0}, solved = 0;
  for (Params* p : {&base, &moved}) {
    const double a = *find(p, "a"), bb = *find(p, "b"), c = *find(p, "c"), d = *find(p, "d");
    const double xi = *find(p, "xi"), eta = *find(p, "eta"), th = *find(p, "theta0");
    for (int k = 0; k < 24; ++k) {
      const double q = kTwoPi * k / 24;
      typename PathEvaluator<M>::VecPhi phi;
      typename PathEvaluator<M>::Coeffs co;
      if (!eval.PointAt(*p, q, &phi, &co)) continue;
      ++solved;
      for (int s = 0; s < 2; ++s) {
        double bx, by, ux, uy;
        if (!projection_internal::Dyad(a / d, bb / d, c / d, q - th, s == 0 ? 1 : -1, &bx, &by, &ux, &uy)) continue;
        const double zr = d * std::cos(th), zi = d * std::sin(th);
        const double wr = xi * std::cos(th) - eta * std::sin(th), wi = xi * std::sin(th) + eta * std::cos(th);
        const double px = *find(p, "x0") + zr * bx - zi * by + wr * ux - wi * uy;
        const double py = *find(p, "y0") + zr * by + zi * bx + wr * uy + wi * ux;
        const double size = 1 + std::hypot(px, py);
        if (std::hypot(co.r_P(0, b.point) - px, co.r_P(1, b.point) - py) <= 1e-9 * size) ++agree[s];
      }
    }
  }
  if (solved == 0 || (agree[0] != solved && agree[1] != solved)) {
    *error = where + "projection: the model's point " + t.point +
             " is not the four-bar's coupler point P = A + a e^(i theta) + (xi + i eta) e^(i theta_BC) with A = (x0, y0), "
             "D = A + d e^(i theta0) (checked at the model's values); remove `projection`";
    return false;
  }
  pr.sigma = agree[0] == solved ? 1 : -1;
  *out = pr;
  return true;
}

/// A candidate of the reduced search: the reduced vector x (after its repairs), its error and
/// violation, and the full design the linear solve gave (x: the task's variables and the free
/// offset, q: the input at each target).
struct ProjectedCandidate {
  std::vector<double> x;
  double error = kInf, violation = kInf;
  std::vector<double> residual;  ///< model - target, 2 per target (empty if a target does not assemble)
  Candidate full;
  bool feasible() const { return violation == 0; }
};

/// The reduced evaluation (one per thread; counts into the full evaluator's `evaluations`).
template <class M>
class ProjectedEvaluator {
 public:
  ProjectedEvaluator(const BoundPath<M>& b, const Projection& pr) : full(b), b_(b), pr_(pr) {}
  PathEvaluator<M> full;  ///< the generated model's checks; its counter is the run's

  /// The crank's angle from the ground line at each target (the reduced vector repaired).
  void Angles(const std::vector<double>& x, std::vector<double>* psi) const {
    const int n = b_.n;
    psi->assign(static_cast<size_t>(n), 0.0);
    if (!pr_.free_timing) {
      const Timing& t = b_.task.timing;
      const double offset = pr_.offset_free ? x[3] : t.offset;
      for (int i = 0; i < n; ++i) (*psi)[static_cast<size_t>(i)] = offset + t.angles[static_cast<size_t>(i)] + pr_.psi_shift;
      return;
    }
    const double first = x[3];
    (*psi)[0] = first;
    for (int i = 1; i < pr_.timing_vars; ++i) (*psi)[static_cast<size_t>(i)] = first + x[static_cast<size_t>(3 + i)];
    if (pr_.closing) (*psi)[static_cast<size_t>(n - 1)] = first + kTwoPi;
  }

  /// The repairs (Lamarckian, module comment): the crank to 1e-12 below the shortest other link
  /// (crank_shortest), the longest link to 1e-8 inside p + q - s (grashof, crank_*); the angles
  /// from the first target sorted (order).
  void Repair(std::vector<double>* x) const {
    const Constraints& c = b_.task.constraints;
    std::array<double, 4> len = {std::exp((*x)[0]), std::exp((*x)[1]), std::exp((*x)[2]), 1.0};
    bool changed = false;
    if (c.crank_shortest) {
      const double other = std::min({len[1], len[2], len[3]});
      if (len[0] > other) len[0] = other * (1 - 1e-12), changed = true;
    }
    if (c.grashof || c.crank_shortest || c.crank_rotates) {
      std::array<double, 4> sorted = len;
      std::sort(sorted.begin(), sorted.end());
      const double room = sorted[1] + sorted[2] - sorted[0];
      if (sorted[3] > room * (1 - 1e-8)) {
        const int longest = static_cast<int>(std::max_element(len.begin(), len.end()) - len.begin());
        len[static_cast<size_t>(longest)] = room * (1 - 1e-8);
        changed = true;
      }
    }
    if (changed)
      for (int k = 0; k < 3; ++k) (*x)[static_cast<size_t>(k)] = std::log(len[static_cast<size_t>(k)] / len[3]);
    if (pr_.free_timing) {
      for (int i = 1; i < pr_.timing_vars; ++i) (*x)[static_cast<size_t>(3 + i)] = Wrap((*x)[static_cast<size_t>(3 + i)]);
      if (c.order) std::sort(x->begin() + 4, x->begin() + 3 + pr_.timing_vars);
    }
  }

  /// The reduced evaluation of x (module comment): repaired, the positions in closed form,
  /// the linear part by least squares, the full design and its constraints.
  ProjectedCandidate Evaluate(const std::vector<double>& x_in) {
    ++full.evaluations;
    ProjectedCandidate cand;
    cand.x = x_in;
    Repair(&cand.x);
    const std::vector<double>& x = cand.x;
    const PathTask& t = b_.task;
    const int n = b_.n;
    const double ra = std::exp(x[0]), rb = std::exp(x[1]), rc = std::exp(x[2]);
    Angles(x, &psi_);
    double violation = 0;
    // The targets' positions (normalized linkage).
    bx_.resize(n), by_.resize(n), ux_.resize(n), uy_.resize(n);
    for (int i = 0; i < n; ++i)
      if (!projection_internal::Dyad(ra, rb, rc, psi_[static_cast<size_t>(i)], pr_.sigma, &bx_(i), &by_(i), &ux_(i), &uy_(i)))
        violation += 1.0;
    if (violation > 0) {
      cand.violation = violation;
      return cand;
    }
    // The linear part.
    double zr, zi, wr, wi, ax, ay;
    if (!Solve(ra, rb, rc, &zr, &zi, &wr, &wi, &ax, &ay)) {
      cand.violation = violation + 1.0;
      return cand;
    }
    cand.residual.assign(static_cast<size_t>(2 * n), 0.0);
    double error = 0;
    for (int i = 0; i < n; ++i) {
      const double px = ax + zr * bx_(i) - zi * by_(i) + wr * ux_(i) - wi * uy_(i);
      const double py = ay + zr * by_(i) + zi * bx_(i) + wr * uy_(i) + wi * ux_(i);
      const double rx = px - t.tx[static_cast<size_t>(i)], ry = py - t.ty[static_cast<size_t>(i)];
      cand.residual[static_cast<size_t>(2 * i)] = rx, cand.residual[static_cast<size_t>(2 * i + 1)] = ry;
      error += rx * rx + ry * ry;
    }
    // The full design.
    const double d = std::hypot(zr, zi);
    double th = pr_.var_theta0 >= 0 ? std::atan2(zi, zr) : pr_.theta0;
    const std::vector<Variable>& v = t.variables;
    std::vector<double>& fx = cand.full.x;
    fx.assign(static_cast<size_t>(b_.num_global), 0.0);
    auto put = [&](int var, double value) {
      if (var < 0) return;
      const Variable& vv = v[static_cast<size_t>(var)];
      // A bound met by the solve (a link at its bound) may be passed by rounding: kept on it.
      const double slack = 1e-12 * (1 + std::abs(value));
      if (value < vv.lo && value >= vv.lo - slack) value = vv.lo;
      if (value > vv.hi && value <= vv.hi + slack) value = vv.hi;
      fx[static_cast<size_t>(var)] = value;
      violation += std::max(0.0, vv.lo - value) + std::max(0.0, value - vv.hi);
    };
    if (pr_.var_theta0 >= 0) {
      const Variable& vt = v[static_cast<size_t>(pr_.var_theta0)];
      th = vt.lo + Wrap(th - vt.lo);
      put(pr_.var_theta0, th);
    }
    put(pr_.var_a, ra * d), put(pr_.var_b, rb * d), put(pr_.var_c, rc * d), put(pr_.var_d, d);
    const double ct = std::cos(th), st = std::sin(th);
    // The motion between the targets (or the full turn when the crank must turn fully): the
    // dyad assembles and is regular (the project's threshold) at the curve's step, as Check.
    const bool full_turn = t.constraints.crank_rotates || t.constraints.crank_shortest;
    const double step = kTwoPi / t.search.curve_samples;
    auto walk = [&](double q0, double q1) {
      const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(q1 - q0) / step)));
      for (int s = 0; s <= steps; ++s) {
        double bx, by, ux, uy, vx, vy;
        if (!projection_internal::Dyad(ra, rb, rc, q0 + (q1 - q0) * s / steps, pr_.sigma, &bx, &by, &ux, &uy, &vx, &vy) ||
            !projection_internal::RegularDyad(rb, rc, ux, uy, vx, vy, ct, st))
          violation += 1.0 / (steps + 1);
      }
    };
    if (full_turn) {
      walk(psi_[0], psi_[0] + kTwoPi);
    } else {
      order_ = psi_;
      if (pr_.free_timing) {
        for (int i = 1; i < n; ++i) order_[static_cast<size_t>(i)] = psi_[0] + Wrap(psi_[static_cast<size_t>(i)] - psi_[0]);
        if (pr_.closing) order_[static_cast<size_t>(n - 1)] = psi_[0] + kTwoPi;
        std::sort(order_.begin(), order_.end());
      }
      for (int i = 0; i + 1 < n; ++i) walk(order_[static_cast<size_t>(i)], order_[static_cast<size_t>(i + 1)]);
    }
    put(pr_.var_xi, wr * ct + wi * st), put(pr_.var_eta, -wr * st + wi * ct);
    put(pr_.var_x0, ax), put(pr_.var_y0, ay);
    if (b_.offset_var >= 0) fx[static_cast<size_t>(b_.offset_var)] = x[3];
    cand.full.q.assign(static_cast<size_t>(n), 0.0);
    for (int i = 0; i < n; ++i) cand.full.q[static_cast<size_t>(i)] = psi_[static_cast<size_t>(i)] + th;
    // The parameter-only constraints on the full design (the generated design checks).
    CheckParameterConstraints(full.model(), full.ParamsOf(fx), t.constraints, b_.checks, [&](double amount, const std::string&) {
      if (amount > 0) violation += amount;
    });
    cand.error = std::isfinite(error) ? error : kInf;
    cand.violation = std::isfinite(error) ? violation : violation + 1.0;
    return cand;
  }

  /// The full check of a reduced candidate's design (the generated model, then the
  /// continuation): 2 evaluations.
  Candidate Judge(const ProjectedCandidate& c) {
    Candidate full_c = c.full;
    if (full_c.x.empty()) return full_c;  // never solved: infeasible
    full.evaluations += 2;
    full.Check(full.ParamsOf(full_c.x), &full_c);
    CheckByContinuation(&full, &full_c);
    return full_c;
  }

  /// The linear least squares (module comment): A, z, w for the positions in bx_ .. uy_, with
  /// |z| (the ground d) within the links' bounds over their ratios. false if degenerate.
  bool Solve(double ra, double rb, double rc, double* zr, double* zi, double* wr, double* wi, double* ax, double* ay) {
    const PathTask& t = b_.task;
    const int n = b_.n;
    const bool angle_free = pr_.var_theta0 >= 0, place_free = pr_.var_x0 >= 0;
    const int nz = angle_free ? 2 : 1, k = nz + 2 + (place_free ? 2 : 0);
    if (2 * n < k) return false;
    Mz_.resize(2 * n, nz), My_.resize(2 * n, k - nz), t_.resize(2 * n);
    const double ct = std::cos(pr_.theta0), st = std::sin(pr_.theta0);
    for (int i = 0; i < n; ++i) {
      const int rx = 2 * i, ry = 2 * i + 1;
      t_(rx) = t.tx[static_cast<size_t>(i)] - (place_free ? 0.0 : pr_.x0);
      t_(ry) = t.ty[static_cast<size_t>(i)] - (place_free ? 0.0 : pr_.y0);
      if (angle_free) {
        Mz_(rx, 0) = bx_(i), Mz_(rx, 1) = -by_(i);
        Mz_(ry, 0) = by_(i), Mz_(ry, 1) = bx_(i);
      } else {  // z = d e^{i theta0}
        Mz_(rx, 0) = ct * bx_(i) - st * by_(i);
        Mz_(ry, 0) = st * bx_(i) + ct * by_(i);
      }
      My_(rx, 0) = ux_(i), My_(rx, 1) = -uy_(i);
      My_(ry, 0) = uy_(i), My_(ry, 1) = ux_(i);
      if (place_free) My_(rx, 2) = 1, My_(rx, 3) = 0, My_(ry, 2) = 0, My_(ry, 3) = 1;
    }
    // |z| = d within [r_lo, r_hi]: every link (ratio x d) within its bounds.
    const std::vector<Variable>& v = t.variables;
    const double ratio[4] = {ra, rb, rc, 1.0};
    const int var[4] = {pr_.var_a, pr_.var_b, pr_.var_c, pr_.var_d};
    double r_lo = 0, r_hi = kInf;
    for (int j = 0; j < 4; ++j) {
      r_lo = std::max(r_lo, v[static_cast<size_t>(var[j])].lo / ratio[j]);
      r_hi = std::min(r_hi, v[static_cast<size_t>(var[j])].hi / ratio[j]);
    }
    if (!(r_lo <= r_hi)) r_lo = r_hi = 0.5 * (r_lo + r_hi);  // no scale meets them all: the bounds' violation says so
    // Eliminate y = (w, A): z's quadratic from the projections onto My's complement.
    qr_.compute(My_);
    if (qr_.rank() < k - nz) return false;
    const Eigen::MatrixXd Pz = Mz_ - My_ * qr_.solve(Mz_);
    const Eigen::VectorXd pt = t_ - My_ * qr_.solve(t_);
    const Eigen::MatrixXd H = Pz.transpose() * Pz;
    const Eigen::VectorXd g = Pz.transpose() * pt;
    Eigen::VectorXd z(nz);
    if (nz == 1) {
      if (!(H(0, 0) > 0)) return false;
      z(0) = std::min(r_hi, std::max(r_lo, g(0) / H(0, 0)));
    } else {
      const Eigen::Matrix2d H2 = H;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(H2);
      const Eigen::Vector2d h = es.eigenvalues(), c = es.eigenvectors().transpose() * g;
      auto at = [&](double lambda) {
        return Eigen::Vector2d(es.eigenvectors() * Eigen::Vector2d(c(0) / (h(0) + lambda), c(1) / (h(1) + lambda)));
      };
      if (!(h(1) > 0)) return false;
      Eigen::Vector2d zz = h(0) > 1e-14 * h(1) ? at(0) : Eigen::Vector2d(es.eigenvectors().col(1) * (c(1) / h(1)));
      const double norm = zz.norm();
      if (norm > r_hi || norm < r_lo) {
        const double R = norm > r_hi ? r_hi : r_lo;
        // |z(lambda)| = R, decreasing in lambda on (-h0, inf): bisection on the bracket.
        double lo, hi;
        if (norm > r_hi) {
          lo = 0, hi = std::max(1e-300, c.norm() / std::max(R, 1e-300));
        } else {
          lo = -h(0), hi = 0;
        }
        if (norm < r_lo && (std::abs(c(0)) <= 1e-14 * c.norm() || h(0) <= 1e-14 * h(1))) {
          // The hard case: out along the flattest direction (optimal when it is flat).
          zz += std::sqrt(std::max(0.0, R * R - norm * norm)) * Eigen::Vector2d(es.eigenvectors().col(0));
        } else {
          for (int it = 0; it < 200; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid == lo || mid == hi) break;
            if (at(mid).norm() > R) lo = mid; else hi = mid;
          }
          zz = at(norm > r_hi ? hi : lo);
          zz *= R / zz.norm();  // on the circle to rounding
        }
      }
      z = zz;
    }
    const Eigen::VectorXd y = qr_.solve(Eigen::VectorXd(t_ - Mz_ * z));
    if (angle_free) {
      *zr = z(0), *zi = z(1);
    } else {
      *zr = z(0) * ct, *zi = z(0) * st;
    }
    *wr = y(0), *wi = y(1);
    *ax = place_free ? y(2) : pr_.x0;
    *ay = place_free ? y(3) : pr_.y0;
    return std::isfinite(*zr) && std::isfinite(*zi) && std::isfinite(*wr) && std::isfinite(*wi) && std::isfinite(*ax) &&
           std::isfinite(*ay);
  }

  const Projection& projection() const { return pr_; }

 private:
  const BoundPath<M>& b_;
  Projection pr_;
  std::vector<double> psi_, order_;
  Eigen::VectorXd bx_, by_, ux_, uy_, t_;
  Eigen::MatrixXd Mz_, My_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

/// Levenberg-Marquardt on the reduced residuals from `start` (forward-difference Jacobian, each
/// column one reduced evaluation; a step kept only when Deb's rule prefers it, so a feasible
/// start stays feasible), within the reduced bounds, until `max_evaluations` are spent or it
/// stalls. *iterations: the Jacobians taken.
template <class M>
ProjectedCandidate ProjectedLevenbergMarquardt(ProjectedEvaluator<M>* eval, const ProjectedCandidate& start,
                                               long long max_evaluations, int* iterations) {
  const Projection& pr = eval->projection();
  const int dim = pr.dim;
  const long long stop = eval->full.evaluations + max_evaluations;
  ProjectedCandidate cur = start;
  if (cur.residual.empty()) return cur;
  const int m = static_cast<int>(cur.residual.size());
  double lambda = 1e-3;
  int stalled = 0;
  Eigen::MatrixXd J(m, dim);
  while (eval->full.evaluations + dim + 1 <= stop && cur.error > 1e-32 && lambda < 1e16 && stalled < 12) {
    ++*iterations;
    const Eigen::Map<const Eigen::VectorXd> r0(cur.residual.data(), m);
    bool ok = true;
    for (int j = 0; j < dim && ok; ++j) {
      std::vector<double> xs = cur.x;
      double h = 1e-7 * std::max(1.0, std::abs(xs[static_cast<size_t>(j)]));
      if (xs[static_cast<size_t>(j)] + h > pr.hi[static_cast<size_t>(j)]) h = -h;
      xs[static_cast<size_t>(j)] += h;
      const ProjectedCandidate c = eval->Evaluate(xs);
      if (static_cast<int>(c.residual.size()) != m) {
        J.col(j).setZero();
        continue;
      }
      // The repair may have moved the point (a ratio onto the Grashof boundary): the actual step.
      const double actual = c.x[static_cast<size_t>(j)] - cur.x[static_cast<size_t>(j)];
      J.col(j) = (Eigen::Map<const Eigen::VectorXd>(c.residual.data(), m) - r0) / (actual != 0 ? actual : h);
    }
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r0;
    bool improved = false;
    while (eval->full.evaluations + 1 <= stop && lambda < 1e16) {
      Eigen::MatrixXd Al = A;
      for (int j = 0; j < dim; ++j) Al(j, j) += lambda * std::max(A(j, j), 1e-12);
      const Eigen::VectorXd step = Al.ldlt().solve(-g);
      std::vector<double> xt = cur.x;
      for (int j = 0; j < dim; ++j)
        xt[static_cast<size_t>(j)] = std::min(pr.hi[static_cast<size_t>(j)], std::max(pr.lo[static_cast<size_t>(j)], xt[static_cast<size_t>(j)] + step(j)));
      const ProjectedCandidate c = eval->Evaluate(xt);
      if (Better(c, cur) && static_cast<int>(c.residual.size()) == m) {
        stalled = c.error > cur.error * (1 - 1e-10) ? stalled + 1 : 0;
        cur = c;
        lambda = std::max(1e-12, lambda / 3);
        improved = true;
        break;
      }
      lambda *= 4;
    }
    if (!improved) break;
  }
  return cur;
}

/// One run of the projected search: adaptive DE over the reduced vector, then LM from up to
/// Search::local_starts distinct basins (as Run), then the full check of each refined start
/// (PathEvaluator::Check, the continuation); the best by Deb's rule on the full checks.
template <class M>
RunResult RunProjected(const BoundPath<M>& b, const Projection& pr, uint64_t seed, int run, long long budget) {
  ProjectedEvaluator<M> eval(b, pr);
  SplitMix64 rng(seed, static_cast<uint64_t>(run));
  const int dim = pr.dim;
  int np = b.task.search.population > 0 ? b.task.search.population : std::max(20, 10 * dim);
  np = static_cast<int>(std::max<long long>(4, std::min<long long>(np, budget / 2)));
  const int wanted = std::max(1, std::min<int>(b.task.search.local_starts, np));
  const long long reserve = 2 * (wanted + 1);  // the full checks at the end
  const long long global_budget =
      budget - reserve - static_cast<long long>(b.task.search.local_share * static_cast<double>(budget));
  std::vector<ProjectedCandidate> pop = AdaptiveDifferentialEvolution<ProjectedCandidate>(
      pr.lo, pr.hi, np, &rng, [&](const std::vector<double>& x) { return eval.Evaluate(x); },
      [](const std::vector<double>&) { return 0.0; }, [&]() { return eval.full.evaluations + np <= global_budget; });
  std::vector<size_t> order(pop.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t u, size_t v) { return Better(pop[u], pop[v]); });
  auto distance = [&](const ProjectedCandidate& u, const ProjectedCandidate& v) {
    double s = 0;
    for (int j = 0; j < dim; ++j) {
      const size_t i = static_cast<size_t>(j);
      const double w = (u.x[i] - v.x[i]) / (pr.hi[i] - pr.lo[i]);
      s += w * w;
    }
    return std::sqrt(s / dim);
  };
  std::vector<size_t> starts;
  for (size_t k = 0; k < order.size() && static_cast<int>(starts.size()) < wanted; ++k) {
    bool distinct = true;
    for (size_t s : starts) distinct = distinct && distance(pop[order[k]], pop[s]) >= 0.05;
    if (distinct) starts.push_back(order[k]);
  }
  RunResult r;
  r.run = run;
  const int n_starts = static_cast<int>(starts.size());
  std::vector<ProjectedCandidate> refined;
  for (int k = 0; k < n_starts; ++k) {
    const long long left = budget - reserve - eval.full.evaluations;
    const ProjectedCandidate& s0 = pop[starts[static_cast<size_t>(k)]];
    if (left <= 0) {
      refined.push_back(s0);
      continue;
    }
    int iterations = 0;
    refined.push_back(ProjectedLevenbergMarquardt(&eval, s0, left / (n_starts - k), &iterations));
    r.local_iterations += iterations;
  }
  // The judge: the generated model's checks and the continuation, on the refined starts (and
  // the global stage's best as it was).
  r.global = eval.Judge(pop[starts[0]]);
  r.best = r.global;
  for (const ProjectedCandidate& c : refined) {
    const Candidate judged = eval.Judge(c);
    if (Better(judged, r.best)) r.best = judged;
  }
  r.local_improved = r.best.error != r.global.error || r.best.violation != r.global.violation;
  r.evaluations = eval.full.evaluations;
  r.solves = eval.full.solves;
  return r;
}

/// The path search: the projected one (RunProjected) when the task asks for it, else
/// Synthesize's. *error and false when the projection cannot be bound (the task's place).
template <class M>
bool SynthesizePath(const BoundPath<M>& b, uint64_t seed, int threads, SearchResult* out, std::string* error,
                    const std::function<void(int done, int total)>& progress = {}) {
  if (!b.task.search.projection) {
    *out = Synthesize(b, seed, threads, progress);
    return true;
  }
  Projection pr;
  if (!BindProjection(b, &pr, error)) return false;
  const int runs = b.task.search.restarts;
  const long long budget = std::max<long long>(1, b.task.search.evaluations / runs);
  SearchResult s;
  s.runs.resize(static_cast<size_t>(runs));
  RunParallel(runs, threads, [&](int r) { s.runs[static_cast<size_t>(r)] = RunProjected(b, pr, seed, r, budget); }, progress);
  size_t best = 0;
  for (size_t r = 0; r < s.runs.size(); ++r) {
    s.evaluations += s.runs[r].evaluations;
    s.solves += s.runs[r].solves;
    if (r > 0 && Better(s.runs[r].best, s.runs[best].best)) best = r;
  }
  s.best = s.runs[best];
  *out = s;
  return true;
}

}  // namespace mechgen::synthesis
