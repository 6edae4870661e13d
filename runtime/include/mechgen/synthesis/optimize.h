/**
 * \file synthesis/optimize.h
 * The two stages of path synthesis (issue 28):
 *  - global: JADE's adaptive differential evolution (AdaptiveDifferentialEvolution:
 *    DE/current-to-pbest/1/bin with an archive, F and CR adapted from the successful trials,
 *    Deb's feasibility rule; the constraints that need no position solve kept by redrawing)
 *    over the task's variables within their bounds; Search::restarts independent runs, each
 *    with its own splitmix64 stream seeded from (seed, restart) and an equal share of
 *    Search::evaluations; with a task's `placement`, the frame's x, y and angle of every
 *    candidate are fitted to the targets in closed form (PathEvaluator::Place);
 *  - local: from up to Search::local_starts distinct basins of each run's final population
 *    (Deb's order, 0.05 of the box apart, each passing the continuation), sharing the last
 *    Search::local_share of the run's budget, Levenberg–Marquardt (Ceres) on the residuals
 *    r_P(q_i; p) - T_i over the variables and the timing (each q_i for free timing, the
 *    offset if free), within the variables' bounds. Its Jacobian is the generated one:
 *    d r_P/d p = Design::dr_P_dp (EvalDesignDerivatives), d r_P/d q = Coefficients::K_P,
 *    no automatic or numerical differentiation. The refined candidate is checked again (with
 *    the continuation, CheckByContinuation) and kept only if it is feasible and better; when
 *    LM leaves the feasible set, the last feasible point on its way is taken (LocalStage).
 * The runs go to `threads` std::threads (an atomic counter hands out run indices); each run's
 * result depends only on (seed, run), and the best is chosen by Deb's rule with ties to the
 * lower index: the same seed gives the same bytes for any number of threads.
 * The budget Search::evaluations covers both stages: the local stage's iterations are capped
 * by what is left, and an evaluation that would pass it is refused (Ceres then stops).
 * Counting: one evaluation = one candidate's objective (prescribed timing: n position
 * solves, with a placement n more, and the motion's check; free timing: also the curve's
 * samples), one residual evaluation of the local stage = 1, one Jacobian = 1 + its number of
 * parameters, one continuation check of a start = 1 (a checked candidate of the local stage
 * includes its continuation). The parameter-only constraints of a drawn point (no position
 * solve) are not counted.
 */
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <thread>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "mechgen/position/design.h"
#include "mechgen/position/solver.h"
#include "mechgen/synthesis/output.h"
#include "mechgen/synthesis/path.h"
#include "mechgen/synthesis/random.h"

namespace mechgen::synthesis {

/// One run's (or the whole search's) outcome.
struct RunResult {
  Candidate global;   ///< the global stage's best
  Candidate best;     ///< after the local stage (or the global one if that was not better)
  long long evaluations = 0;
  long long solves = 0;
  int local_iterations = 0;
  bool local_improved = false;
  int run = 0;
};

/// The options of every local stage (path, function and motion tasks): Levenberg-Marquardt
/// with a dense QR, up to 200 iterations, tolerances at the double's limit (the budget or the
/// iteration count ends a solve), one thread (the runs are the parallel unit), silent.
inline ceres::Solver::Options LocalSolverOptions() {
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-20;
  options.parameter_tolerance = 1e-16;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  return options;
}

/// Stops a local stage (keeping the best point so far) once `evaluator->evaluations` reaches
/// stop_at: a refused evaluation would end the solve with FAILURE and throw its progress away.
template <class Evaluator>
struct EvaluationBudget : ceres::IterationCallback {
  const Evaluator* evaluator = nullptr;
  long long stop_at = 0;
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return evaluator->evaluations >= stop_at ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }
};

/// The order in which the motion passes the targets: input order from the first target (free
/// timing: each q_i as first q + its angle from it in [0, 2 pi), the last target of a closed
/// curve after a full turn, as PathEvaluator::Check walks them), else as given. *q the inputs
/// by target so unwrapped, *order the targets' indices in the motion's order.
template <class M>
void MotionOrder(const BoundPath<M>& b, const Candidate& c, std::vector<double>* q, std::vector<int>* order) {
  *q = c.q;
  if (b.task.timing.free) {
    for (double& qi : *q) qi = c.q[0] + Wrap(qi - c.q[0]);
    if (b.n > 2 && (*q)[static_cast<size_t>(b.n - 1)] - c.q[0] < 1e-6) (*q)[static_cast<size_t>(b.n - 1)] += kTwoPi;  // as Check()
  }
  order->resize(static_cast<size_t>(b.n));
  for (int i = 0; i < b.n; ++i) (*order)[static_cast<size_t>(i)] = i;
  if (b.task.timing.free)
    std::stable_sort(order->begin(), order->end(),
                     [&](int u, int v) { return (*q)[static_cast<size_t>(u)] < (*q)[static_cast<size_t>(v)]; });
}

/// The input at each target in the order of the motion (MotionOrder), each reached directly
/// from the one before: what the written model's assembly and range are made of
/// (WriteSynthesizedModel).
template <class M>
std::vector<double> MotionInputs(const BoundPath<M>& b, const Candidate& c) {
  std::vector<double> q, motion;
  std::vector<int> order;
  MotionOrder(b, c, &q, &order);
  for (int i : order) motion.push_back(q[static_cast<size_t>(i)]);
  return motion;
}

/// The second way of checking a candidate: the runtime's continuation (PositionSolver,
/// assembled at the first target, then moved along the motion in steps of at most 10 deg,
/// staying on its branch) must arrive at every target on the configuration the synthesis used
/// (M::Solve on the model's assembly mode). "" if it does (phi within 1e-8), else what went
/// wrong.
template <class M>
std::string ContinuationCheck(PathEvaluator<M>* eval, const Candidate& c) {
  const BoundPath<M>& b = eval->bound();
  const auto p = eval->ParamsOf(c.x);
  typename PathEvaluator<M>::VecPhi phi;
  typename PathEvaluator<M>::Coeffs co;
  std::vector<double> q;
  std::vector<int> order;
  MotionOrder(b, c, &q, &order);
  using C = ModelCalls<M>;
  const M& model = eval->model();
  position::PositionSolver<M> solver(model, position::Options(), p);
  typename position::PositionSolver<M>::VecQ qv;
  qv.resize(1);
  if (!eval->PointAt(p, q[static_cast<size_t>(order[0])], &phi, &co)) return "the first target does not assemble";
  qv(0) = q[static_cast<size_t>(order[0])];
  if (solver.Assemble(qv, phi, 0, nullptr) != position::Status::kConverged) return "the runtime cannot assemble at the first target";
  for (int k = 0; k < b.n; ++k) {
    const int i = order[static_cast<size_t>(k)];
    const double target = q[static_cast<size_t>(i)];
    const double from = solver.state().q(0);
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(target - from) / (10 * M_PI / 180))));
    for (int s = 1; s <= steps; ++s) {
      qv(0) = from + (target - from) * s / steps;
      if (solver.MoveTo(qv, nullptr) != position::Status::kConverged)
        return "the continuation stops before target " + std::to_string(i + 1) + " (a dead point on the way)";
    }
    if (!eval->PointAt(p, target, &phi, &co)) return "target " + std::to_string(i + 1) + " does not assemble";
    for (int j = 0; j < C::Nphi(model); ++j) {
      double d = solver.state().phi(j) - phi(j);
      if (C::PhiIsAngle(model, j)) d = std::remainder(d, kTwoPi);
      if (!(std::abs(d) <= 1e-8))
        return "target " + std::to_string(i + 1) + " is reached on another branch by continuation (" +
               std::string(C::PhiName(model, j)) + " differs by " + Short(d) + ")";
    }
  }
  return "";
}

/// The violation given to a candidate whose checks pass but whose continuation does not.
constexpr double kContinuationDefect = 1e-9;

/// The continuation as a defect of a feasible candidate: when ContinuationCheck fails, the
/// candidate becomes infeasible (violation kContinuationDefect, the reason as its defect), so
/// that neither the local stage nor the choice of the answer keeps a mechanism the runtime
/// cannot follow through its targets (e.g. a change-point four-bar on the Grashof boundary,
/// where a crank-shortest optimum of prescribed timing tends to end).
template <class M>
void CheckByContinuation(PathEvaluator<M>* eval, Candidate* c) {
  if (!c->feasible()) return;
  const std::string why = ContinuationCheck(eval, *c);
  if (why.empty()) return;
  c->violation = kContinuationDefect;
  c->defect = "the continuation fails: " + why;
}

/// The residuals r_P(q_i) - T_i of a bound task, and their generated Jacobian.
template <class M>
class PathResiduals : public ceres::CostFunction {
 public:
  /// `limit`: the evaluator's count this cost may not pass (an evaluation that would is
  /// refused; LocalStage stops Ceres before that, see there).
  PathResiduals(PathEvaluator<M>* eval, int num_timing, long long limit = std::numeric_limits<long long>::max())
      : eval_(eval), num_timing_(num_timing), limit_(limit) {
    const BoundPath<M>& b = eval->bound();
    set_num_residuals(2 * b.n);
    mutable_parameter_block_sizes()->push_back(static_cast<int32_t>(b.task.variables.size()));
    if (num_timing > 0) mutable_parameter_block_sizes()->push_back(num_timing);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const BoundPath<M>& b = eval_->bound();
    const int nv = static_cast<int>(b.task.variables.size());
    // Ceres asks again at a point it has just had (the candidate, then its Jacobian): the
    // last evaluation is kept and handed out again, neither computed nor counted twice.
    const int nr = 2 * b.n;
    const bool want_j = jacobians != nullptr;
    std::vector<double>& at = scratch_;
    at.assign(parameters[0], parameters[0] + nv);
    if (num_timing_ > 0) at.insert(at.end(), parameters[1], parameters[1] + num_timing_);
    if (have_ && at == last_at_ && (!want_j || last_has_j_)) {
      std::copy(last_r_.begin(), last_r_.end(), residuals);
      if (want_j && jacobians[0] != nullptr) std::copy(last_jx_.begin(), last_jx_.end(), jacobians[0]);
      if (want_j && num_timing_ > 0 && jacobians[1] != nullptr) std::copy(last_jt_.begin(), last_jt_.end(), jacobians[1]);
      return true;
    }
    const long long cost = want_j ? 1 + nv + num_timing_ : 1;
    if (eval_->evaluations + cost > limit_) return false;
    eval_->evaluations += cost;
    // Always with the Jacobian into the cache when Ceres wants one; residuals alone otherwise.
    last_jx_.assign(static_cast<size_t>(nr * nv), 0.0);
    last_jt_.assign(static_cast<size_t>(nr * std::max(num_timing_, 1)), 0.0);
    double* cache_j[2] = {last_jx_.data(), last_jt_.data()};
    last_r_.assign(static_cast<size_t>(nr), 0.0);
    have_ = false;
    if (!Compute(parameters, last_r_.data(), want_j ? cache_j : nullptr)) return false;
    have_ = true;
    last_at_ = at;
    last_has_j_ = want_j;
    std::copy(last_r_.begin(), last_r_.end(), residuals);
    if (want_j && jacobians[0] != nullptr) std::copy(last_jx_.begin(), last_jx_.end(), jacobians[0]);
    if (want_j && num_timing_ > 0 && jacobians[1] != nullptr) std::copy(last_jt_.begin(), last_jt_.end(), jacobians[1]);
    return true;
  }

 private:
  bool Compute(double const* const* parameters, double* residuals, double** jacobians) const {
    const BoundPath<M>& b = eval_->bound();
    const int nv = static_cast<int>(b.task.variables.size());
    std::vector<double> x(parameters[0], parameters[0] + nv);
    const auto p = eval_->ParamsOf(x);
    typename PathEvaluator<M>::VecPhi phi;
    typename PathEvaluator<M>::Coeffs co;
    using C = ModelCalls<M>;
    const M& model = eval_->model();
    position::DesignOf<M> design;
    for (int i = 0; i < b.n; ++i) {
      double q;
      if (b.task.timing.free) {
        q = parameters[1][i];
      } else {
        std::vector<double> xg = x;
        if (b.offset_var >= 0) xg.push_back(parameters[1][0]);
        q = eval_->PrescribedQ(xg, i);
      }
      if (!eval_->PointAt(p, q, &phi, &co)) return false;
      const int m = b.point;
      residuals[2 * i] = co.r_P(0, m) - b.task.tx[static_cast<size_t>(i)];
      residuals[2 * i + 1] = co.r_P(1, m) - b.task.ty[static_cast<size_t>(i)];
      if (jacobians == nullptr) continue;
      typename ModelTypes<M>::VecQ qv;
      qv.resize(1);
      qv(0) = q;
      C::Design(model, p, qv, phi, &design);
      for (int a = 0; a < 2; ++a) {
        const double kp = co.K_P(2 * m + a, 0);
        if (jacobians[0] != nullptr) {
          double* row = jacobians[0] + (2 * i + a) * nv;
          for (int j = 0; j < nv; ++j) {
            row[j] = design.dr_P_dp(2 * m + a, b.column[static_cast<size_t>(j)]);
            if (j == b.relative_to) row[j] += kp;  // q_i moves with the frame's angle
          }
        }
        if (num_timing_ > 0 && jacobians[1] != nullptr) {
          double* row = jacobians[1] + (2 * i + a) * num_timing_;
          for (int k = 0; k < num_timing_; ++k) row[k] = b.task.timing.free ? (k == i ? kp : 0.0) : kp;
        }
      }
    }
    return true;
  }

 private:
  PathEvaluator<M>* eval_;
  int num_timing_;
  long long limit_;
  mutable std::vector<double> scratch_, last_at_, last_r_, last_jx_, last_jt_;
  mutable bool have_ = false, last_has_j_ = false;
};

/// LM over the variables and the timing from `start`: the refined candidate (checked).
template <class M>
Candidate LocalRefine(PathEvaluator<M>* eval, const Candidate& start, long long max_evaluations, int* iterations) {
  const BoundPath<M>& b = eval->bound();
  const int nv = static_cast<int>(b.task.variables.size());
  std::vector<double> x(start.x.begin(), start.x.begin() + nv);
  std::vector<double> timing;
  if (b.task.timing.free) timing = start.q;
  if (b.offset_var >= 0) timing.push_back(start.x[static_cast<size_t>(b.offset_var)]);
  const int num_timing = static_cast<int>(timing.size());
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  const long long cost_limit = eval->evaluations + max_evaluations;
  auto* cost = new PathResiduals<M>(eval, num_timing, cost_limit);
  if (num_timing > 0) {
    problem.AddResidualBlock(cost, nullptr, x.data(), timing.data());
  } else {
    problem.AddResidualBlock(cost, nullptr, x.data());
  }
  for (int j = 0; j < nv; ++j) {
    problem.SetParameterLowerBound(x.data(), j, b.task.variables[static_cast<size_t>(j)].lo);
    problem.SetParameterUpperBound(x.data(), j, b.task.variables[static_cast<size_t>(j)].hi);
  }
  ceres::Solver::Options options = LocalSolverOptions();
  // The budget: stop when less than two iterations' worth is left (an iteration evaluates the
  // residuals, the Jacobian after a successful step, and Ceres evaluates once more at the
  // end), so the limit above is only a backstop.
  const long long per_iteration = 2 + nv + num_timing;
  EvaluationBudget<PathEvaluator<M>> budget;
  budget.evaluator = eval;
  budget.stop_at = cost_limit - 2 * per_iteration - 1;
  options.callbacks.push_back(&budget);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  *iterations = static_cast<int>(summary.iterations.size());
  Candidate refined;
  refined.x = x;
  if (b.offset_var >= 0) refined.x.push_back(timing.back());
  if (b.task.timing.free) {
    refined.q = timing;
  } else {
    refined.q.resize(static_cast<size_t>(b.n));
    for (int i = 0; i < b.n; ++i) refined.q[static_cast<size_t>(i)] = eval->PrescribedQ(refined.x, i);
  }
  eval->Check(eval->ParamsOf(refined.x), &refined);
  CheckByContinuation(eval, &refined);
  return refined;
}

/// The last feasible candidate on the segment from `inside` (feasible) to `outside` (not):
/// bisection in the segment's parameter (40 halvings, one evaluation each).
template <class M>
Candidate BoundaryOnSegment(PathEvaluator<M>* eval, const Candidate& inside, const Candidate& outside) {
  const BoundPath<M>& b = eval->bound();
  Candidate best = inside;
  double lo = 0, hi = 1;
  for (int k = 0; k < 40; ++k) {
    const double t = 0.5 * (lo + hi);
    Candidate c;
    c.x.resize(inside.x.size());
    for (size_t j = 0; j < c.x.size(); ++j) c.x[j] = inside.x[j] + t * (outside.x[j] - inside.x[j]);
    c.q.resize(inside.q.size());
    for (size_t i = 0; i < c.q.size(); ++i)
      c.q[i] = b.task.timing.free ? inside.q[i] + t * (outside.q[i] - inside.q[i]) : eval->PrescribedQ(c.x, static_cast<int>(i));
    ++eval->evaluations;
    eval->Check(eval->ParamsOf(c.x), &c);
    CheckByContinuation(eval, &c);
    if (c.feasible()) {
      lo = t;
      best = c;
    } else {
      hi = t;
    }
  }
  return best;
}

/// The local stage from `start`: LM (LocalRefine); the refined candidate if it is better by
/// Deb's rule, else `start`. LM does not see the constraints (the ground region, Grashof, the
/// crank shortest, the continuation's): when it leaves the feasible set from a feasible
/// start, the last feasible point on the way (BoundaryOnSegment) is taken if better and LM
/// runs again from it (at most four rounds), so that an optimum outside ends on its boundary.
template <class M>
Candidate LocalStage(PathEvaluator<M>* eval, const Candidate& start, long long max_evaluations, int* iterations) {
  const long long stop = eval->evaluations + max_evaluations;
  Candidate current = start;
  for (int round = 0; round < 4; ++round) {
    const long long left = stop - eval->evaluations;
    if (left <= 0) break;
    int it = 0;
    const Candidate refined = LocalRefine(eval, current, left, &it);
    *iterations += it;
    if (Better(refined, current)) {
      current = refined;
      break;
    }
    if (!current.feasible() || refined.feasible() || stop - eval->evaluations < 40) break;
    const Candidate edge = BoundaryOnSegment(eval, current, refined);
    if (!Better(edge, current)) break;
    current = edge;
  }
  return current;
}

/// Differential evolution (DE/rand/1/bin, F dithered in [0.5, 1) per generation, CR 0.9,
/// Deb's rule for selection; a coordinate leaving [lo, hi] is put halfway between the parent
/// and the bound it crossed) from np uniform points, generations while more() says so. The
/// final population. `evaluate(x)` gives a candidate (with feasible(), error, violation);
/// every kind of task's global stage runs here.
template <class C, class Evaluate, class More>
std::vector<C> DifferentialEvolution(const std::vector<double>& lo, const std::vector<double>& hi, int np, SplitMix64* rng,
                                     Evaluate&& evaluate, More&& more) {
  const int dim = static_cast<int>(lo.size());
  std::vector<C> pop;
  pop.reserve(static_cast<size_t>(np));
  std::vector<double> x(static_cast<size_t>(dim));
  for (int k = 0; k < np; ++k) {
    for (int j = 0; j < dim; ++j)
      x[static_cast<size_t>(j)] = lo[static_cast<size_t>(j)] + rng->Uniform() * (hi[static_cast<size_t>(j)] - lo[static_cast<size_t>(j)]);
    pop.push_back(evaluate(x));
  }
  while (more()) {
    const double F = 0.5 + 0.5 * rng->Uniform();
    for (int k = 0; k < np; ++k) {
      int r1, r2, r3;
      do r1 = rng->Below(np); while (r1 == k);
      do r2 = rng->Below(np); while (r2 == k || r2 == r1);
      do r3 = rng->Below(np); while (r3 == k || r3 == r1 || r3 == r2);
      const int jrand = rng->Below(dim);
      for (int j = 0; j < dim; ++j) {
        const size_t u = static_cast<size_t>(j);
        double v = pop[static_cast<size_t>(k)].x[u];
        if (j == jrand || rng->Uniform() < 0.9) {
          v = pop[static_cast<size_t>(r1)].x[u] + F * (pop[static_cast<size_t>(r2)].x[u] - pop[static_cast<size_t>(r3)].x[u]);
          // Out of bounds: halfway between the parent and the bound it crossed.
          if (v < lo[u]) v = 0.5 * (lo[u] + pop[static_cast<size_t>(k)].x[u]);
          if (v > hi[u]) v = 0.5 * (hi[u] + pop[static_cast<size_t>(k)].x[u]);
        }
        x[u] = v;
      }
      C trial = evaluate(x);
      if (!Better(pop[static_cast<size_t>(k)], trial)) pop[static_cast<size_t>(k)] = std::move(trial);
    }
  }
  return pop;
}

/// JADE's adaptive differential evolution (Zhang & Sanderson 2009, IEEE TEC 13(5)) with
/// Deb's rule, the path tasks' global stage: DE/current-to-pbest/1/bin (the mutant
/// x_k + F (x_pbest - x_k) + F (x_r1 - x_r2), x_pbest one of the best max(2, 0.1 np) by Deb's
/// rule, r2 from the population and the archive of replaced parents), F_k Cauchy(mu_F, 0.1)
/// (drawn again while <= 0, cut at 1), CR_k normal(mu_CR, 0.1) cut to [0, 1]; after each
/// generation mu_CR moves 0.1 of the way to the mean of the successful CR and mu_F to the
/// Lehmer mean of the successful F (both start at 0.5). A coordinate leaving [lo, hi] is put
/// halfway between the parent and the bound it crossed.
/// Constraints that need no position solve (`parameter_violation(x)`: link lengths, Grashof,
/// the crank, the ground region; 0 when met) are kept by construction where possible: each
/// initial point is drawn again (up to 50 times) until it meets them, and a trial that misses
/// them against a parent that meets them (which Deb's rule would reject anyway) is drawn again
/// (new r1, r2, F; up to 8 times) and, if still missing them, not evaluated (the parent stays).
/// Those draws cost no evaluation (no position solve; the design checks' closed form only).
/// The final population. evaluate(x) gives a candidate (feasible(), error, violation).
template <class C, class Evaluate, class ParameterViolation, class More>
std::vector<C> AdaptiveDifferentialEvolution(const std::vector<double>& lo, const std::vector<double>& hi, int np,
                                             SplitMix64* rng, Evaluate&& evaluate,
                                             ParameterViolation&& parameter_violation, More&& more) {
  const int dim = static_cast<int>(lo.size());
  auto normal = [&]() {  // Box-Muller, one of the pair
    const double u1 = 1.0 - rng->Uniform(), u2 = rng->Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
  };
  std::vector<C> pop;
  pop.reserve(static_cast<size_t>(np));
  std::vector<double> x(static_cast<size_t>(dim));
  for (int k = 0; k < np; ++k) {
    for (int attempt = 0; attempt < 50; ++attempt) {
      for (int j = 0; j < dim; ++j)
        x[static_cast<size_t>(j)] = lo[static_cast<size_t>(j)] + rng->Uniform() * (hi[static_cast<size_t>(j)] - lo[static_cast<size_t>(j)]);
      if (!(parameter_violation(x) > 0)) break;
    }
    pop.push_back(evaluate(x));
  }
  std::vector<std::vector<double>> archive;
  double mu_cr = 0.5, mu_f = 0.5;
  const int top = std::max(2, static_cast<int>(0.1 * np));
  std::vector<int> order(static_cast<size_t>(np));
  std::vector<C> next;
  while (more()) {
    for (int k = 0; k < np; ++k) order[static_cast<size_t>(k)] = k;
    std::stable_sort(order.begin(), order.end(), [&](int u, int v) { return Better(pop[static_cast<size_t>(u)], pop[static_cast<size_t>(v)]); });
    next = pop;
    std::vector<double> good_cr, good_f;
    const int pool = np + static_cast<int>(archive.size());
    for (int k = 0; k < np; ++k) {
      const C& parent = pop[static_cast<size_t>(k)];
      const bool parent_meets = !(parameter_violation(parent.x) > 0);
      double cr = std::min(1.0, std::max(0.0, mu_cr + 0.1 * normal()));
      double f = 0;
      bool ok = false;
      for (int attempt = 0; attempt < 9 && !ok; ++attempt) {
        do f = mu_f + 0.1 * std::tan(M_PI * (rng->Uniform() - 0.5)); while (!(f > 0));
        f = std::min(f, 1.0);
        const int best = order[static_cast<size_t>(rng->Below(top))];
        int r1, r2;
        do r1 = rng->Below(np); while (r1 == k);
        do r2 = rng->Below(pool); while (r2 == k || r2 == r1);
        const std::vector<double>& x2 = r2 < np ? pop[static_cast<size_t>(r2)].x : archive[static_cast<size_t>(r2 - np)];
        const int jrand = rng->Below(dim);
        for (int j = 0; j < dim; ++j) {
          const size_t u = static_cast<size_t>(j);
          double v = parent.x[u];
          if (j == jrand || rng->Uniform() < cr) {
            v = parent.x[u] + f * (pop[static_cast<size_t>(best)].x[u] - parent.x[u]) +
                f * (pop[static_cast<size_t>(r1)].x[u] - x2[u]);
            if (v < lo[u]) v = 0.5 * (lo[u] + parent.x[u]);
            if (v > hi[u]) v = 0.5 * (hi[u] + parent.x[u]);
          }
          x[u] = v;
        }
        ok = !parent_meets || !(parameter_violation(x) > 0);
      }
      if (!ok) continue;  // Deb's rule would keep the parent: not evaluated
      C trial = evaluate(x);
      if (Better(trial, parent)) {
        good_cr.push_back(cr);
        good_f.push_back(f);
        archive.push_back(parent.x);
        next[static_cast<size_t>(k)] = std::move(trial);
      } else if (!Better(parent, trial)) {
        next[static_cast<size_t>(k)] = std::move(trial);  // a tie moves on (as DE's <=)
      }
    }
    // The archive: at most np, the surplus removed at random.
    while (static_cast<int>(archive.size()) > np) {
      const size_t r = static_cast<size_t>(rng->Below(static_cast<int>(archive.size())));
      archive[r] = std::move(archive.back());
      archive.pop_back();
    }
    if (!good_cr.empty()) {
      double sum_cr = 0, sum_f = 0, sum_f2 = 0;
      for (size_t s = 0; s < good_cr.size(); ++s) sum_cr += good_cr[s], sum_f += good_f[s], sum_f2 += good_f[s] * good_f[s];
      mu_cr = 0.9 * mu_cr + 0.1 * sum_cr / static_cast<double>(good_cr.size());
      mu_f = 0.9 * mu_f + 0.1 * sum_f2 / sum_f;
    }
    pop.swap(next);
  }
  return pop;
}

/// Runs work(r) for r = 0..runs-1 on `threads` std::threads (an atomic counter hands out the
/// indices; work must write only its own slot). progress (may be empty) as runs finish.
inline void RunParallel(int runs, int threads, const std::function<void(int)>& work,
                        const std::function<void(int done, int total)>& progress = {}) {
  std::atomic<int> next{0}, done{0};
  auto loop = [&]() {
    for (int r; (r = next.fetch_add(1)) < runs;) {
      work(r);
      const int d = ++done;
      if (progress) progress(d, runs);
    }
  };
  const int n = std::max(1, std::min(threads, runs));
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t) pool.emplace_back(loop);
  loop();
  for (std::thread& t : pool) t.join();
}

/// One run: adaptive DE (AdaptiveDifferentialEvolution) from its own stream, then the local
/// stage from up to Search::local_starts distinct basins of the final population: its
/// candidates in Deb's order, each taken only if it is at least 0.05 of the box's diagonal
/// (in bound-scaled coordinates) from every start taken before, and only if it passes the
/// continuation (CheckByContinuation; a start that does not is marked and skipped).
template <class M>
RunResult Run(const BoundPath<M>& b, uint64_t seed, int run, long long budget) {
  PathEvaluator<M> eval(b);
  SplitMix64 rng(seed, static_cast<uint64_t>(run));
  const int dim = b.num_global;
  std::vector<double> lo(static_cast<size_t>(dim)), hi(static_cast<size_t>(dim));
  for (int j = 0; j < static_cast<int>(b.task.variables.size()); ++j) {
    lo[static_cast<size_t>(j)] = b.task.variables[static_cast<size_t>(j)].lo;
    hi[static_cast<size_t>(j)] = b.task.variables[static_cast<size_t>(j)].hi;
  }
  if (b.offset_var >= 0) lo[static_cast<size_t>(b.offset_var)] = 0, hi[static_cast<size_t>(b.offset_var)] = kTwoPi;
  int np = b.task.search.population > 0 ? b.task.search.population : std::max(20, 10 * dim);
  np = static_cast<int>(std::max<long long>(4, std::min<long long>(np, budget)));
  const long long global_budget = budget - static_cast<long long>(b.task.search.local_share * static_cast<double>(budget));
  std::vector<Candidate> pop = AdaptiveDifferentialEvolution<Candidate>(
      lo, hi, np, &rng, [&](const std::vector<double>& x) { return eval.Evaluate(x); },
      [&](const std::vector<double>& x) { return eval.ParameterViolation(x); },
      [&]() { return eval.evaluations + np <= global_budget; });
  RunResult r;
  r.run = run;
  // The population by Deb's rule (ties: the lower index).
  std::vector<size_t> order(pop.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t u, size_t v) { return Better(pop[u], pop[v]); });
  // The starts: distinct basins that pass the continuation.
  const int wanted = std::max(1, std::min<int>(b.task.search.local_starts, np));
  std::vector<size_t> starts;
  auto distance = [&](const Candidate& u, const Candidate& v) {
    double s = 0;
    for (int j = 0; j < dim; ++j) {
      const size_t i = static_cast<size_t>(j);
      const double w = hi[i] > lo[i] ? (u.x[i] - v.x[i]) / (hi[i] - lo[i]) : 0.0;
      s += w * w;
    }
    return std::sqrt(s / dim);
  };
  for (size_t k = 0; k < order.size() && static_cast<int>(starts.size()) < wanted; ++k) {
    Candidate& c = pop[order[k]];
    bool distinct = true;
    for (size_t s : starts) distinct = distinct && distance(c, pop[s]) >= 0.05;
    if (!distinct) continue;
    if (c.feasible()) {
      ++eval.evaluations;  // the continuation: one evaluation
      CheckByContinuation(&eval, &c);
      if (!c.feasible()) continue;
    }
    starts.push_back(order[k]);
  }
  if (starts.empty()) starts.push_back(order[0]);  // none feasible: the least violation
  r.global = pop[starts[0]];  // the global stage's best that passed the continuation
  r.best = r.global;
  // The local stage from each start, sharing what is left of the budget.
  const int n_starts = static_cast<int>(starts.size());
  for (int k = 0; k < n_starts; ++k) {
    const long long left = budget - eval.evaluations;
    if (left <= 0) break;
    int iterations = 0;
    const Candidate refined = LocalStage(&eval, pop[starts[static_cast<size_t>(k)]], left / (n_starts - k), &iterations);
    r.local_iterations += iterations;
    if (Better(refined, r.best)) r.best = refined;
  }
  r.local_improved = r.best.error != r.global.error || r.best.violation != r.global.violation;
  r.evaluations = eval.evaluations;
  r.solves = eval.solves;
  return r;
}

/// What the whole search did.
struct SearchResult {
  RunResult best;                ///< the best run (Deb's rule, ties: the lower run index)
  std::vector<RunResult> runs;   ///< every run, by index
  long long evaluations = 0;     ///< over all runs
  long long solves = 0;
};

/// The search: task.search.restarts runs on `threads` threads. `progress` (may be empty) is
/// called from the worker threads as runs finish (for a progress line; not for results).
template <class M>
SearchResult Synthesize(const BoundPath<M>& b, uint64_t seed, int threads,
                        const std::function<void(int done, int total)>& progress = {}) {
  const int runs = b.task.search.restarts;
  const long long budget = std::max<long long>(1, b.task.search.evaluations / runs);
  SearchResult s;
  s.runs.resize(static_cast<size_t>(runs));
  RunParallel(runs, threads, [&](int r) { s.runs[static_cast<size_t>(r)] = Run(b, seed, r, budget); }, progress);
  size_t best = 0;
  for (size_t r = 0; r < s.runs.size(); ++r) {
    s.evaluations += s.runs[r].evaluations;
    s.solves += s.runs[r].solves;
    if (r > 0 && Better(s.runs[r].best, s.runs[best].best)) best = r;
  }
  s.best = s.runs[best];
  return s;
}

}  // namespace mechgen::synthesis
