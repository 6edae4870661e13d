/**
 * \file synthesis/trace.h
 * The trace test (issue 44): a certificate that a set of solutions of the five-point problem
 * (exact_path.h) at given data is all of them, independent of how it was found (the homotopy
 * from the linear-product start system, or monodromy). Sommese, Verschelde and Wampler
 * ("Symmetric functions applied to decomposing solution sets of polynomial systems", SIAM J.
 * Numer. Anal. 40(6), 2002); Leykin, Rodriguez and Sottile ("Trace test", Arnold Math. J. 4,
 * 2018); the construction as in HomotopyContinuation.jl's verify_solution_completeness (del
 * Campo and Rodriguez, J. Symb. Comput. 79, 2017).
 *
 * Why not the traces of the fibres themselves: along a line of data p(λ) the sum of the
 * solutions z_i(λ) is a rational function of λ, not an affine one: where the line meets data
 * at which a solution goes to infinity (Problem 7's data have three), the sum has a pole.
 * The solutions over the line form a curve C = {(z, λ) : F(z; p(λ)) = 0}; a function φ on C
 * whose fibres are witness sets and which has a pole wherever the traced coordinates do gives
 * affine traces. Here
 *
 *   φ(z, λ) = -(a . X - 1) λ,   X = (x, x̄, y, ȳ) (the dyads' unknowns), a random complex,
 *
 * whose fibre φ = 0 is the solutions at the data (λ = 0, the set to certify) and the points of
 * C on the hyperplane a . X = 1 (the "additional witnesses"). At a point at infinity of C where
 * X has a pole, a . X has one of the same order (a generic) and λ is not 0 (at λ = 0 all the
 * solutions are finite: the data are generic), so φ's pole is at least X's; where X stays
 * finite it adds no pole. So the sums of X and of λ over a fibre φ = -t are polynomials of
 * degree at most one in t: affine. A proper subset of the fibre has no such reason (the
 * monodromy of C over φ is transitive: the sum of the points left out is not affine).
 *
 * The test: the additional witnesses by homotopy continuation on the square system
 * [F(z; p(λ)); a . X - 1] (13 unknowns; a linear-product start system of its multihomogeneous
 * structure, 1024 paths), then every point of the fibre t = 0 tracked along the pencil
 * [F(z; p(λ)); (a . X - 1) λ + t] to t = τ/2 and t = τ (τ complex), and the second difference
 * of the traces of X and λ, T(0) - 2 T(τ/2) + T(τ), against the sum of the points' sizes: zero
 * to round-off exactly when the fibre is complete.
 *
 * The line of data moves the conjugate coordinates only: P̄_j(λ) = P̄_j + λ e_j (P_j, the pivots
 * fixed; complex data off λ = 0), so that F is affine in λ (its constant term u_j ū_j is then
 * linear in λ) and the witness system keeps the five-point system's structure times one factor
 * linear in λ.
 *
 * Deterministic (fixed coefficients from `seed`). Needs Eigen.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <vector>

#include "mechgen/synthesis/exact_path.h"
#include "mechgen/synthesis/homotopy.h"

namespace mechgen::synthesis::trace {

using homotopy::Complex;
constexpr int kW = 13;  ///< the five-point system's 12 unknowns and λ
using VecW = homotopy::VecN<kW>;
using MatW = homotopy::MatN<kW>;

struct TraceOptions {
  homotopy::TrackOptions track;
  std::uint64_t seed = 20261129;        ///< the line, a, the start system and gamma
  Complex tau = std::polar(0.5, 1.1);  ///< the pencil's far end (t = 0, τ/2, τ)
};

struct TraceResult {
  int fiber = 0;          ///< the solutions at the data given (the set to certify)
  int witness_paths = 0;  ///< paths of the additional witnesses' homotopy (1024)
  int witnesses = 0;      ///< additional witnesses found: the points of C on a . X = 1
  int witness_at_infinity = 0, witness_singular = 0, witness_failed = 0, witness_duplicates = 0;
  /// Points of the fibre whose path along the pencil did not end finite and nonsingular at
  /// τ/2 or τ, or ended where another did: the traces are then no verdict.
  int lost = 0;
  /// |T(0) - 2 T(τ/2) + T(τ)|_inf over the sum of the points' sizes (|w|_inf over the traced
  /// coordinates, the largest of the three): round-off when the fibre is complete.
  double residual = HUGE_VAL;
  /// The same with fiber solution i left out (the witnesses all kept), for each i.
  std::vector<double> dropped;
};

namespace trace_internal {
using exact_internal::Coefficients;
using exact_internal::QIndex;
using Vec12 = exact_internal::Vec12;

/// The five-point system (exact_path.h's Target) on the line of data: u_j, v_j fixed, ū_j(λ) =
/// ū_j + λ e_j and v̄_j(λ) = v̄_j + λ e_j (P̄_j moved by e_j). Rows 0..11 of f and J (column 12:
/// dF/dλ); row 12 is the caller's.
struct Line {
  std::array<Complex, 5> u, v, ub, vb, e;
  void Fill(const VecW& w, VecW* f, MatW* J) const {
    f->setZero();
    J->setZero();
    const Complex lambda = w(12);
    for (int j = 1; j <= 4; ++j) {
      const int q = QIndex(j), r = 3 * (j - 1);
      const Complex Q = w(q), Qb = w(q + 1);
      const size_t J0 = 0, Jj = static_cast<size_t>(j);
      for (int side = 0; side < 2; ++side) {
        const std::array<Complex, 5>& U = side == 0 ? u : v;
        const std::array<Complex, 5>& Ub = side == 0 ? ub : vb;
        const int o = 2 * side, row = r + side;
        const Complex X = w(o), Xb = w(o + 1);
        const Complex ubj = Ub[Jj] + lambda * e[Jj], ub0 = Ub[J0] + lambda * e[J0];
        (*f)(row) = ubj * X * Q + U[Jj] * Xb * Qb - ub0 * X - U[J0] * Xb + U[Jj] * ubj - U[J0] * ub0;
        (*J)(row, o) = ubj * Q - ub0;
        (*J)(row, o + 1) = U[Jj] * Qb - U[J0];
        (*J)(row, q) = ubj * X;
        (*J)(row, q + 1) = U[Jj] * Xb;
        (*J)(row, 12) = e[Jj] * X * Q - e[J0] * X + U[Jj] * e[Jj] - U[J0] * e[J0];
      }
      (*f)(r + 2) = Q * Qb - Complex(1);
      (*J)(r + 2, q) = Qb;
      (*J)(r + 2, q + 1) = Q;
    }
  }
};

inline Complex Dot(const std::array<Complex, 4>& a, const VecW& w) {
  return a[0] * w(0) + a[1] * w(1) + a[2] * w(2) + a[3] * w(3);
}

/// The additional witnesses' system: F(z; p(λ)) and a . X - 1.
struct WitnessTarget {
  const Line* line;
  std::array<Complex, 4> a;
  void operator()(const VecW& w, VecW* f, MatW* J) const {
    line->Fill(w, f, J);
    (*f)(12) = Dot(a, w) - Complex(1);
    for (int i = 0; i < 4; ++i) (*J)(12, i) = a[static_cast<size_t>(i)];
  }
};

/// Its linear-product start system: row 3(j-1)+k (k = 0, 1) l_{jk}(X) m_{jk}(Q_j) n_{jk}(λ),
/// row 3(j-1)+2 m_{j2} m_{j3}, row 12 l_a(X); l = c_0 + c . X, m = e_0 + e_1 Q_j + e_2 Q̄_j,
/// n = n_0 + n_1 λ. The target's rows have this structure (degree at most one in X, in
/// (Q_j, Q̄_j) and in λ; two in (Q_j, Q̄_j); one in X): the multihomogeneous Bezout count of
/// the groups X, (Q_j, Q̄_j) j = 1..4, λ is 4^4 x 4 = 1024, and these are the start solutions.
struct WitnessStart {
  std::array<std::array<std::array<Complex, 5>, 2>, 4> l;
  std::array<std::array<std::array<Complex, 3>, 4>, 4> m;
  std::array<std::array<std::array<Complex, 2>, 2>, 4> n;
  std::array<Complex, 5> la;

  explicit WitnessStart(Coefficients* c) {
    for (auto& lj : l)
      for (auto& lk : lj)
        for (Complex& v : lk) v = c->Next();
    for (auto& mj : m)
      for (auto& mk : mj)
        for (Complex& v : mk) v = c->Next();
    for (auto& nj : n)
      for (auto& nk : nj)
        for (Complex& v : nk) v = c->Next();
    for (Complex& v : la) v = c->Next();
  }
  static Complex L(const std::array<Complex, 5>& c, const VecW& w) {
    return c[0] + c[1] * w(0) + c[2] * w(1) + c[3] * w(2) + c[4] * w(3);
  }
  static Complex M(const std::array<Complex, 3>& e, int j, const VecW& w) {
    return e[0] + e[1] * w(QIndex(j)) + e[2] * w(QIndex(j) + 1);
  }
  void operator()(const VecW& w, VecW* g, MatW* J) const {
    g->setZero();
    J->setZero();
    for (int j = 1; j <= 4; ++j) {
      const size_t jj = static_cast<size_t>(j - 1);
      const int q = QIndex(j), r = 3 * (j - 1);
      for (size_t k = 0; k < 2; ++k) {
        const auto& c = l[jj][k];
        const auto& e = m[jj][k];
        const auto& nn = n[jj][k];
        const Complex lv = L(c, w), mv = M(e, j, w), nv = nn[0] + nn[1] * w(12);
        const int row = r + static_cast<int>(k);
        (*g)(row) = lv * mv * nv;
        for (int i = 0; i < 4; ++i) (*J)(row, i) = c[static_cast<size_t>(i + 1)] * mv * nv;
        (*J)(row, q) = lv * e[1] * nv;
        (*J)(row, q + 1) = lv * e[2] * nv;
        (*J)(row, 12) = lv * mv * nn[1];
      }
      const auto& e2 = m[jj][2];
      const auto& e3 = m[jj][3];
      const Complex m2 = M(e2, j, w), m3 = M(e3, j, w);
      (*g)(r + 2) = m2 * m3;
      (*J)(r + 2, q) = e2[1] * m3 + m2 * e3[1];
      (*J)(r + 2, q + 1) = e2[2] * m3 + m2 * e3[2];
    }
    (*g)(12) = L(la, w);
    for (int i = 0; i < 4; ++i) (*J)(12, i) = la[static_cast<size_t>(i + 1)];
  }
  /// For each j: which of rows 3(j-1), 3(j-1)+1 vanishes by its m factor (with the chosen
  /// factor of row 3(j-1)+2: Q_j), the other by l or n; exactly one of those four by n (λ),
  /// the other three and l_a by l (X, a 4 x 4 solve).
  std::vector<VecW> Solutions() const {
    std::vector<VecW> out;
    out.reserve(1024);
    for (int choice = 0; choice < 256; ++choice) {
      for (int by_n = 1; by_n <= 4; ++by_n) {
        Eigen::Matrix<Complex, 4, 4> A;
        Eigen::Matrix<Complex, 4, 1> rhs;
        VecW w = VecW::Zero();
        int row = 0;
        for (int j = 1; j <= 4; ++j) {
          const size_t jj = static_cast<size_t>(j - 1);
          const int bits = (choice >> (2 * (j - 1))) & 3;
          const size_t other = static_cast<size_t>(bits & 1), by_m = 1 - other, unit = 2 + static_cast<size_t>(bits >> 1);
          const auto& e1 = m[jj][by_m];
          const auto& e2 = m[jj][unit];
          const Complex det = e1[1] * e2[2] - e1[2] * e2[1];
          w(QIndex(j)) = (-e1[0] * e2[2] + e1[2] * e2[0]) / det;
          w(QIndex(j) + 1) = (-e1[1] * e2[0] + e1[0] * e2[1]) / det;
          if (j == by_n) {
            w(12) = -n[jj][other][0] / n[jj][other][1];
          } else {
            const auto& c = l[jj][other];
            for (int i = 0; i < 4; ++i) A(row, i) = c[static_cast<size_t>(i + 1)];
            rhs(row++) = -c[0];
          }
        }
        for (int i = 0; i < 4; ++i) A(row, i) = la[static_cast<size_t>(i + 1)];
        rhs(row) = -la[0];
        w.head<4>() = A.partialPivLu().solve(rhs);
        out.push_back(w);
      }
    }
    return out;
  }
};

/// The pencil [F(z; p(λ)); (a . X - 1) λ + t] at t, and the homotopy from t0 to t1 along the
/// segment (s in [0, 1]).
struct Pencil {
  const Line* line;
  std::array<Complex, 4> a;
  Complex t0, t1;
  void At(const VecW& w, Complex t, VecW* f, MatW* J) const {
    line->Fill(w, f, J);
    const Complex ax = Dot(a, w) - Complex(1), lambda = w(12);
    (*f)(12) = ax * lambda + t;
    for (int i = 0; i < 4; ++i) (*J)(12, i) = a[static_cast<size_t>(i)] * lambda;
    (*J)(12, 12) = ax;
  }
  void operator()(const VecW& w, double s, VecW* H, MatW* Hw, VecW* Hs) const {
    At(w, t0 + s * (t1 - t0), H, Hw);
    Hs->setZero();
    (*Hs)(12) = t1 - t0;
  }
};

/// The traced coordinates: X and λ.
constexpr std::array<int, 5> kTraced = {0, 1, 2, 3, 12};
}  // namespace trace_internal

/**
 * \brief The trace test of `fiber` (solutions of the five-point system on `task`'s scaled data,
 *        as ExactPathResult::solutions.finite holds them).
 */
inline TraceResult FivePointTrace(const FivePointTask& task, const std::vector<exact_internal::Vec12>& fiber,
                                  const TraceOptions& options = {}) {
  using namespace trace_internal;
  TraceResult r;
  r.fiber = static_cast<int>(fiber.size());
  const Complex A(task.crank_pivot[0], task.crank_pivot[1]), D(task.rocker_pivot[0], task.rocker_pivot[1]);
  const double scale = std::abs(D - A);
  if (!(scale > 0) || !std::isfinite(scale)) return r;
  Coefficients c(options.seed);
  Line line;
  for (size_t j = 0; j < 5; ++j) {
    const Complex P(task.points[j][0], task.points[j][1]);
    line.u[j] = (P - A) / scale;
    line.v[j] = (P - D) / scale;
    line.ub[j] = std::conj(line.u[j]);
    line.vb[j] = std::conj(line.v[j]);
    line.e[j] = c.Next();
  }
  std::array<Complex, 4> a;
  for (Complex& v : a) v = c.Next();
  // The additional witnesses: C on a . X = 1.
  const WitnessStart G(&c);
  const WitnessTarget W{&line, a};
  const Complex gamma = c.Next();
  const std::vector<VecW> starts = G.Solutions();
  r.witness_paths = static_cast<int>(starts.size());
  const homotopy::Solutions<kW> found = homotopy::TrackAll<kW>(W, G, gamma, starts, options.track);
  r.witnesses = static_cast<int>(found.finite.size());
  r.witness_at_infinity = found.at_infinity;
  r.witness_singular = found.singular;
  r.witness_failed = found.failed;
  r.witness_duplicates = found.duplicates;
  // The fibre φ = 0: the solutions at the data (λ = 0), then the witnesses.
  std::vector<VecW> points;
  for (const exact_internal::Vec12& z : fiber) {
    VecW w;
    w.head<12>() = z;
    w(12) = 0;
    points.push_back(w);
  }
  points.insert(points.end(), found.finite.begin(), found.finite.end());
  // Along the pencil to τ/2, then to τ.
  const Pencil first{&line, a, Complex(0), 0.5 * options.tau}, second{&line, a, 0.5 * options.tau, options.tau};
  const auto end_of = [](const Pencil& p) {
    return [&p](const VecW& w, VecW* f, MatW* J) { p.At(w, p.t1, f, J); };
  };
  std::vector<std::array<VecW, 3>> at(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    at[i][0] = points[i];
    const homotopy::PathEnd<kW> e1 = homotopy::TrackHomotopy<kW>(first, end_of(first), points[i], options.track);
    const homotopy::PathEnd<kW> e2 = homotopy::TrackHomotopy<kW>(second, end_of(second), e1.z, options.track);
    if (e1.status != homotopy::PathStatus::kFinite || e2.status != homotopy::PathStatus::kFinite) ++r.lost;
    at[i][1] = e1.z;
    at[i][2] = e2.z;
  }
  for (size_t s = 1; s < 3; ++s)
    for (size_t i = 0; i < at.size(); ++i)
      for (size_t j = i + 1; j < at.size(); ++j) {
        const double d = homotopy::internal::NormInf<kW>(VecW(at[i][s] - at[j][s]));
        if (d <= options.track.same_tolerance * (1 + homotopy::internal::NormInf<kW>(at[i][s]))) ++r.lost;
      }
  // The second difference of the traces, relative to the sum of the points' sizes.
  const auto residual = [&](size_t skip) {
    std::array<Complex, kTraced.size()> d{};
    double size = 0;
    for (size_t i = 0; i < at.size(); ++i) {
      if (i == skip) continue;
      double biggest = 0;
      for (size_t k = 0; k < kTraced.size(); ++k) {
        const int c_ = kTraced[k];
        d[k] += at[i][0](c_) - 2.0 * at[i][1](c_) + at[i][2](c_);
        for (size_t s = 0; s < 3; ++s) biggest = std::max(biggest, std::abs(at[i][s](c_)));
      }
      size += biggest;
    }
    double worst = 0;
    for (const Complex& v : d) worst = std::max(worst, std::abs(v));
    return size > 0 ? worst / size : HUGE_VAL;
  };
  r.residual = residual(at.size());
  for (size_t i = 0; i < fiber.size(); ++i) r.dropped.push_back(residual(i));
  return r;
}

}  // namespace mechgen::synthesis::trace
