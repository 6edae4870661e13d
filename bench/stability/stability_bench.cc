// Stability study: how position, K and L degrade as a four-bar approaches a singular
// configuration, for each way of computing them. One CSV row per case x method x distance:
//   case,method,distance,status,iterations,err_phi,err_K,err_L,branch_kept
//
// Cases (hand-written models from tests/runtime, q* the singular input, Delta = 1e-1..1e-10):
//   toggle         the crank-rocker of handwritten_rocker_driven.h driven by its rocker
//                  towards its dead point th3* = acos(-0.78125) (crank and coupler folded,
//                  |AC| = b - a): q = q* - Delta. A fold: K ~ Delta^-1/2, L ~ Delta^-3/2.
//   change_in      the Grashof-neutral four-bar a = 1, b = 3, c = 2, d = 2 (s + l = p + q),
//                  crank-driven towards its change point q* = 0 (all links collinear):
//                  q = -Delta, on closed-form branch +1. Two curves cross; K stays finite.
//   change_through the same, one step from -Delta to +Delta over the change point. Kept =
//                  on the smooth curve through q* (closed-form branch -1 for q > 0).
// Oracle: closed forms evaluated in long double (64-bit mantissa) at the same double q:
// circle–circle intersection for phi (for the change point a cancellation-free form, see
// NeutralSmoothPosition), Paul's K and L (handwritten_fourbar.h, templated), and for the
// rocker-driven case K = -Phi_phi^{-1} Phi_q, L from the differentiated velocity loop,
// written below. Errors: phi max-norm in rad (angles mod 2 pi); K and L scaled,
// ||X - X*||_inf / max(1, ||X*||_inf): relative where K, L blow up (toggle: K ~ Delta^-1/2,
// L ~ Delta^-3/2), absolute where they stay O(1) or vanish (change point: L ~ Delta). branch_kept: 1 when phi is closer to the oracle's curve than
// to the other solution at that q, 0 otherwise, -1 when the method returned nothing.
// Methods:
//   closed_form     double closed form with the branch sign fixed (+1 at the change point)
//   newton_raw      Newton at fixed q from the previous Delta's solution; K, L from the
//                   model at the result; no conditioning or branch checks (a naive solver)
//   continuation    PositionSolver::MoveTo (predictor + Newton + guards), as shipped
//   continuation_pass  change_through only: MoveTo, and on kSingular
//                   PassSingularity(kFollowTangent) then MoveTo
//   ceres_analytic  Ceres LM, generated-style analytic Jacobian (PhiCostFunction)
//   ceres_autodiff  Ceres LM, AutoDiffCostFunction (Jets)
//   ceres_numeric   Ceres LM, NumericDiffCostFunction (central differences)
//   finite_diff     positions by newton_raw; K and L by central differences of solved
//                   positions, h = cbrt(eps) for K and eps^(1/4) for L
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "handwritten_fourbar.h"
#include "handwritten_rocker_driven.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"

namespace {

using FourBar = mech::handwritten_fourbar::Model;
using Rocker = mech::handwritten_rocker_driven::Model;
using LD = long double;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Vector2d;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

double AngleDist(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }
double AngleDist(const Vec2& a, const Vec2& b) {
  return std::max(AngleDist(a(0), b(0)), AngleDist(a(1), b(1)));
}

// The solution of one case at one q: phi (dim 2), K (2 x 1), L (2 x 1).
struct Solution {
  bool ok = false;
  Vec2 phi = Vec2::Constant(kNaN), K = Vec2::Constant(kNaN), L = Vec2::Constant(kNaN);
  int iterations = 0;
  std::string status = "ok";
};

// ---- rocker-driven four-bar: closed form, K and L (any scalar) ------------------------
// q = th3 (rocker), phi = (th1 crank, th2 coupler). B is an intersection of the circles
// (A, a) and (C, b) with C = (d + c cos q, c sin q); `branch` picks the side of AC.
template <typename S>
bool RockerPosition(const mech::handwritten_rocker_driven::Params<S>& p, S q, int branch,
                    Eigen::Matrix<S, 2, 1>* phi) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S xC = p.d + p.c * cos(q), yC = p.c * sin(q);
  const S l2 = xC * xC + yC * yC, l = sqrt(l2);
  const S x = (p.a * p.a - p.b * p.b + l2) / (S(2) * l);
  const S h2 = p.a * p.a - x * x;
  if (!(h2 >= S(0))) return false;
  const S h = sqrt(h2) * S(branch);
  const S ux = xC / l, uy = yC / l;
  const S xB = x * ux - h * uy, yB = x * uy + h * ux;
  (*phi)(0) = atan2(yB, xB);
  (*phi)(1) = atan2(yC - yB, xC - xB);
  return true;
}

// K and L of the rocker-driven four-bar: the velocity loop Phi_phi K = -Phi_q differentiated
// once more along the motion gives Phi_phi L = -[-a C1 K1^2 - b C2 K2^2 + c C3;
//                                               -a S1 K1^2 - b S2 K2^2 + c S3].
template <typename S>
void RockerKL(const mech::handwritten_rocker_driven::Params<S>& p, S q,
              const Eigen::Matrix<S, 2, 1>& phi, Eigen::Matrix<S, 2, 1>* K,
              Eigen::Matrix<S, 2, 1>* L) {
  using std::cos;
  using std::sin;
  const S S1 = sin(phi(0)), C1 = cos(phi(0)), S2 = sin(phi(1)), C2 = cos(phi(1));
  const S S3 = sin(q), C3 = cos(q);
  Eigen::Matrix<S, 2, 2> A;
  A << -p.a * S1, -p.b * S2, p.a * C1, p.b * C2;
  const Eigen::Matrix<S, 2, 1> B(p.c * S3, -p.c * C3);
  const Eigen::Matrix<S, 2, 2> Ainv = A.inverse();
  *K = -Ainv * B;
  const S K1 = (*K)(0), K2 = (*K)(1);
  const Eigen::Matrix<S, 2, 1> r(-p.a * C1 * K1 * K1 - p.b * C2 * K2 * K2 + p.c * C3,
                                 -p.a * S1 * K1 * K1 - p.b * S2 * K2 * K2 + p.c * S3);
  *L = -Ainv * r;
}

// ---- a case: the model, the oracle and its alternative -------------------------------
struct Case {
  std::string name;
  double q_singular = 0;
  double direction = 1;   // q = q* - direction * Delta before the singular point
  bool through = false;   // evaluate at q* + direction * Delta, after one step over q*
  double q_start = 0;     // a regular input to start every continuation from
};

// Oracle on the expected curve at q and the other solution there (for branch_kept).
template <class M>
struct Oracle;

template <>
struct Oracle<Rocker> {
  mech::handwritten_rocker_driven::Params<double> p;
  int branch = 0;  // the closed-form branch of the assembled configuration
  bool Exact(double q, bool /*after*/, Solution* s, Vec2* other) const {
    const auto pl = p.Cast<LD>();
    Eigen::Matrix<LD, 2, 1> phi, phi_other, K, L;
    if (!RockerPosition<LD>(pl, q, branch, &phi)) return false;
    RockerPosition<LD>(pl, q, -branch, &phi_other);
    RockerKL<LD>(pl, q, phi, &K, &L);
    s->phi = phi.cast<double>();
    s->K = K.cast<double>();
    s->L = L.cast<double>();
    *other = phi_other.cast<double>();
    return true;
  }
  bool ClosedForm(double q, Solution* s) const {
    if (!RockerPosition<double>(p, q, branch, &s->phi)) return false;
    RockerKL<double>(p, q, s->phi, &s->K, &s->L);
    return true;
  }
};

// The Grashof-neutral four-bar's positions without the cancellation of the textbook closed
// form: with l = |BD|, b^2 - x^2 = ((b + c)^2 - l^2)(l^2 - (b - c)^2) / (4 l^2), and since
// d - a = b - c, l^2 - (b - c)^2 = 4 a d sin^2(q / 2). So the signed height of C over BD is
//   h = sqrt(a d ((b + c)^2 - l^2)) sin(q / 2) / l,
// analytic through q = 0: the smooth curve (closed-form branch +1 for q < 0, -1 for q > 0).
// The textbook form sqrt(b^2 - x^2) loses half the digits there (b^2 - x^2 ~ q^2).
template <typename S>
void NeutralSmoothPosition(const mech::handwritten_fourbar::Params<S>& p, S q, int curve,
                           Eigen::Matrix<S, 2, 1>* phi) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S xB = p.a * cos(q), yB = p.a * sin(q);
  const S ex = p.d - xB, ey = -yB;
  const S l2 = ex * ex + ey * ey, l = sqrt(l2);
  const S x = (p.b * p.b - p.c * p.c + l2) / (S(2) * l);
  const S bc = p.b + p.c;
  // curve -1: the smooth curve entering on branch +1; curve +1: the other one.
  const S h = S(curve) * sqrt(p.a * p.d * (bc * bc - l2)) * sin(q / S(2)) / l;
  const S xC = xB + (x * ex - h * ey) / l, yC = yB + (x * ey + h * ex) / l;
  (*phi)(0) = atan2(yC - yB, xC - xB);
  (*phi)(1) = atan2(yC, xC - p.d);
}

template <>
struct Oracle<FourBar> {
  FourBar::ParamsT<double> p;
  // Incoming on closed-form branch +1 (q < 0); the expected curve is the smooth one through
  // q* = 0, which is closed-form branch -1 for q > 0.
  bool Exact(double q, bool /*after*/, Solution* s, Vec2* other) const {
    const auto pl = p.Cast<LD>();
    Eigen::Matrix<LD, 2, 1> phi, phi_other;
    NeutralSmoothPosition<LD>(pl, q, -1, &phi);
    NeutralSmoothPosition<LD>(pl, q, +1, &phi_other);
    mech::handwritten_fourbar::Coefficients<LD> c;
    mech::handwritten_fourbar::EvalCoefficients<LD>(pl, Eigen::Matrix<LD, 1, 1>(LD(q)), phi, &c);
    s->phi = phi.cast<double>();
    s->K = c.K.cast<double>();
    s->L = c.L.cast<double>();
    *other = phi_other.cast<double>();
    return true;
  }
  bool ClosedForm(double q, Solution* s) const {
    if (!mech::handwritten_fourbar::ClosedFormPosition<double>(p, q, +1, &s->phi)) return false;
    mech::handwritten_fourbar::Coefficients<double> c;
    mech::handwritten_fourbar::EvalCoefficients<double>(p, Vec1(q), s->phi, &c);
    s->K = c.K;
    s->L = c.L;
    return true;
  }
};

// K, L at phi from the model: the generated-style Coeffs when it has L, else K from Coeffs
// and L from the formula (only the rocker model lacks L).
template <class M>
void ModelKL(const typename M::template ParamsT<double>& p, double q, Solution* s) {
  if constexpr (std::is_same_v<M, Rocker>) {
    RockerKL<double>(p, q, s->phi, &s->K, &s->L);
  } else {
    typename M::template CoefficientsT<double> c;
    M::template Coeffs<double>(p, Vec1(q), s->phi, &c);
    s->K = c.K;
    s->L = c.L;
  }
}

// Newton at fixed q from phi (no guards): PositionSolver::Newton with default tolerance.
template <class M>
bool RawNewton(const mechgen::position::CeresPositionSolver<M>& solver, double q, Vec2* phi, int* iterations) {
  Eigen::Matrix2d Phi_phi;
  const mechgen::position::NewtonResult r = solver.Newton(Vec1(q), phi, &Phi_phi);
  *iterations += r.iterations;
  return r.status == mechgen::position::Status::kConverged;
}

template <class M, class Cost>
struct CeresMethod {
  typename M::template ParamsT<double> p;
  Vec1 q = Vec1::Zero();
  Vec2 phi;
  ceres::Problem problem;
  explicit CeresMethod(const typename M::template ParamsT<double>& params, const Vec2& phi0)
      : p(params), phi(phi0) {
    ceres::CostFunction* cost = nullptr;
    if constexpr (std::is_same_v<Cost, ceres::CostFunction>) {
      cost = new mechgen::position::PhiCostFunction<M>(&p, &q);
    } else {
      cost = new Cost(new mechgen::position::PhiAutoDiffFunctor<M>(&p, &q));
    }
    problem.AddResidualBlock(cost, nullptr, phi.data());
  }
  Solution Solve(double q_new) {
    q(0) = q_new;
    ceres::Solver::Summary summary;
    ceres::Solve(mechgen::position::LevenbergMarquardtOptions(200), &problem, &summary);
    Solution s;
    s.phi = phi;
    s.iterations = static_cast<int>(summary.iterations.size());
    Eigen::Vector2d Phi;
    M::template Phi<double>(p, q, phi, &Phi, nullptr, nullptr);
    s.ok = summary.termination_type == ceres::CONVERGENCE && Phi.lpNorm<Eigen::Infinity>() <= 1e-10;
    s.status = s.ok ? "ok" : (Phi.lpNorm<Eigen::Infinity>() <= 1e-10 ? "no_convergence_flag"
                                                                    : "residual_above_1e-10");
    ModelKL<M>(p, q_new, &s);
    return s;
  }
};

template <class M>
using AutoDiff = ceres::AutoDiffCostFunction<mechgen::position::PhiAutoDiffFunctor<M>, 2, 2>;
template <class M>
using NumericDiff =
    ceres::NumericDiffCostFunction<mechgen::position::PhiAutoDiffFunctor<M>, ceres::CENTRAL, 2, 2>;

void Print(const Case& c, const std::string& method, double delta, const Solution& s,
           const Solution& exact, const Vec2& other) {
  double err_phi = kNaN, err_K = kNaN, err_L = kNaN;
  int kept = -1;
  if (s.phi.allFinite()) {
    err_phi = AngleDist(s.phi, exact.phi);
    kept = err_phi < AngleDist(s.phi, other) ? 1 : 0;
    err_K = (s.K - exact.K).cwiseAbs().maxCoeff() / std::max(1.0, exact.K.cwiseAbs().maxCoeff());
    err_L = (s.L - exact.L).cwiseAbs().maxCoeff() / std::max(1.0, exact.L.cwiseAbs().maxCoeff());
  }
  std::printf("%s,%s,%.0e,%s,%d,%.3e,%.3e,%.3e,%d\n", c.name.c_str(), method.c_str(), delta,
              s.status.c_str(), s.iterations, err_phi, err_K, err_L, kept);
}

template <class M>
void Run(const Case& c, const Oracle<M>& oracle) {
  const std::vector<double> deltas = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6,
                                      1e-7, 1e-8, 1e-9, 1e-10};
  const auto& p = oracle.p;
  Solution start;
  Vec2 unused;
  oracle.Exact(c.q_start, false, &start, &unused);
  auto q_before = [&](double d) { return c.q_singular - c.direction * d; };
  auto q_at = [&](double d) { return c.through ? c.q_singular + c.direction * d : q_before(d); };

  // Every method walks the distances in decreasing order, carrying its state.
  mechgen::position::CeresPositionSolver<M> solver(mechgen::position::Options(), p);
  mechgen::position::CeresPositionSolver<M> passing(mechgen::position::Options(), p);
  solver.Assemble(Vec1(c.q_start), start.phi, 0, nullptr);
  passing.Assemble(Vec1(c.q_start), start.phi, 0, nullptr);
  Vec2 raw_phi = start.phi;
  CeresMethod<M, ceres::CostFunction> analytic(p, start.phi);
  CeresMethod<M, AutoDiff<M>> autodiff(p, start.phi);
  CeresMethod<M, NumericDiff<M>> numeric(p, start.phi);

  for (double d : deltas) {
    const double q = q_at(d);
    Solution exact;
    Vec2 other;
    if (!oracle.Exact(q, c.through, &exact, &other)) {
      std::fprintf(stderr, "%s: no oracle at q = %.17g\n", c.name.c_str(), q);
      continue;
    }
    // closed form (double)
    Solution cf;
    cf.ok = oracle.ClosedForm(q, &cf);
    if (!cf.ok) cf.status = "no_real_solution";
    Print(c, "closed_form", d, cf, exact, other);

    // Newton without guards (from the previous result; through: first at q*-Delta).
    Solution raw;
    if (c.through) RawNewton(solver, q_before(d), &raw_phi, &raw.iterations);
    raw.ok = RawNewton(solver, q, &raw_phi, &raw.iterations);
    raw.phi = raw_phi;
    raw.status = raw.ok ? "ok" : "no_convergence";
    if (raw.ok) ModelKL<M>(p, q, &raw); else raw.phi.setConstant(kNaN);
    if (!raw.ok) raw_phi = exact.phi;  // restart the next distance from the oracle
    Print(c, "newton_raw", d, raw, exact, other);

    // The shipped continuation.
    {
      Solution s;
      mechgen::position::Summary summary;
      if (c.through) solver.MoveTo(Vec1(q_before(d)), &summary);
      const mechgen::position::Status status = solver.MoveTo(Vec1(q), &summary);
      s.iterations = summary.iterations;
      s.status = mechgen::position::ToString(status);
      if (status == mechgen::position::Status::kConverged) {
        s.phi = solver.state().phi;
        s.K = solver.state().K;
        s.L = solver.state().L;
      }
      Print(c, "continuation", d, s, exact, other);
    }
    if (c.through) {
      // Through the change point on request: a fresh solver from q_start to q* - Delta
      // (it stops next to q* if Delta is inside its refusal zone), MoveTo(q), and on
      // kSingular PassSingularity(kFollowTangent) and MoveTo(q) again (which refuses when
      // q lies between q* and where the pass ended, i.e. inside the refusal zone).
      Solution s;
      mechgen::position::CeresPositionSolver<M> pass(mechgen::position::Options(), p);
      pass.Assemble(Vec1(c.q_start), start.phi, 0, nullptr);
      mechgen::position::Summary summary;
      pass.MoveTo(Vec1(q_before(d)), &summary);
      mechgen::position::Status status = pass.MoveTo(Vec1(q), &summary);
      s.iterations = summary.iterations;
      if (status == mechgen::position::Status::kSingular) {
        mechgen::position::Summary ps;
        status = pass.PassSingularity(Vec1(q), mechgen::position::Crossing::kFollowTangent, &ps);
        s.iterations += ps.iterations;
        if (status == mechgen::position::Status::kConverged) {
          status = pass.MoveTo(Vec1(q), &summary);
          s.iterations += summary.iterations;
        }
      }
      s.status = mechgen::position::ToString(status);
      if (status == mechgen::position::Status::kConverged) {
        s.phi = pass.state().phi;
        s.K = pass.state().K;
        s.L = pass.state().L;
      }
      Print(c, "continuation_pass", d, s, exact, other);
    }

    // Ceres, three Jacobians.
    if (c.through) {
      analytic.Solve(q_before(d));
      autodiff.Solve(q_before(d));
      numeric.Solve(q_before(d));
    }
    Print(c, "ceres_analytic", d, analytic.Solve(q), exact, other);
    Print(c, "ceres_autodiff", d, autodiff.Solve(q), exact, other);
    Print(c, "ceres_numeric", d, numeric.Solve(q), exact, other);

    // Finite differences of solved positions for K and L, around newton_raw's phi.
    {
      Solution s;
      s.phi = raw.phi;
      s.iterations = 0;
      const double eps = std::numeric_limits<double>::epsilon();
      const double hK = std::cbrt(eps), hL = std::sqrt(std::sqrt(eps));
      Vec2 plus = raw.phi, minus = raw.phi, plus2 = raw.phi, minus2 = raw.phi;
      bool ok = raw.ok;
      ok = ok && RawNewton(solver, q + hK, &plus, &s.iterations);
      ok = ok && RawNewton(solver, q - hK, &minus, &s.iterations);
      ok = ok && RawNewton(solver, q + hL, &plus2, &s.iterations);
      ok = ok && RawNewton(solver, q - hL, &minus2, &s.iterations);
      if (ok) {
        auto wrap = [](Vec2 x) { return Vec2(std::remainder(x(0), 2 * kPi), std::remainder(x(1), 2 * kPi)); };
        s.K = wrap(plus - minus) / (2 * hK);
        s.L = (wrap(plus2 - raw.phi) + wrap(minus2 - raw.phi)) / (hL * hL);
        s.status = "ok";
      } else {
        s.status = raw.ok ? "probe_failed" : "no_position";
        s.phi.setConstant(kNaN);
      }
      Print(c, "finite_diff", d, s, exact, other);
    }
  }
}

}  // namespace

int main() {
  std::printf("case,method,distance,status,iterations,err_phi,err_K,err_L,branch_kept\n");
  {
    Oracle<Rocker> oracle;
    // The assembled configuration's closed-form branch.
    mechgen::position::CeresPositionSolver<Rocker> probe;
    probe.AssembleDefault(nullptr);
    Vec2 plus;
    RockerPosition<double>(oracle.p, probe.state().q(0), +1, &plus);
    oracle.branch = AngleDist(plus, probe.state().phi) < 1e-6 ? +1 : -1;
    Case c;
    c.name = "toggle";
    c.q_singular = static_cast<double>(std::acos(-0.78125L));
    c.direction = 1;
    c.q_start = c.q_singular - 0.3;
    Run<Rocker>(c, oracle);
  }
  for (bool through : {false, true}) {
    Oracle<FourBar> oracle;
    oracle.p.a = 1;
    oracle.p.b = 3;
    oracle.p.c = 2;
    oracle.p.d = 2;
    Case c;
    c.name = through ? "change_through" : "change_in";
    c.q_singular = 0;
    c.direction = 1;
    c.through = through;
    c.q_start = -0.3;
    Run<FourBar>(c, oracle);
  }
  return 0;
}
