/**
 * \file synthesis/exact_path.h
 * Exact path synthesis of a four-bar (issue 44): five precision points of the coupler point
 * with both ground pivots given. Every isolated solution, by polynomial homotopy continuation
 * (synthesis/homotopy.h); the real ones as four-bars with their defect checks.
 *
 * The equations, in isotropic coordinates (a point (X, Y) is the pair z = X + iY, z̄ = X - iY,
 * and z̄ an unknown of its own). A is the crank's ground pivot, D the rocker's; P_0..P_4 the
 * precision points. At pose 0 the crank's coupler joint is B_0 = P_0 + x and the rocker's
 * C_0 = P_0 + y; at pose j the coupler has turned by Q_j = e^{i theta_j} (Q̄_j = 1/Q_j), so
 * B_j = P_j + Q_j x and C_j = P_j + Q_j y. The crank's and the rocker's lengths stay:
 * |B_j - A|^2 = |B_0 - A|^2 and |C_j - D|^2 = |C_0 - D|^2, which with u_j = P_j - A, Q_j Q̄_j = 1
 * (the x x̄ terms cancel) read, for j = 1..4,
 *
 *   ū_j x Q_j + u_j x̄ Q̄_j - ū_0 x - u_0 x̄ + |u_j|^2 - |u_0|^2 = 0     (and the same in y, v_j = P_j - D)
 *   Q_j Q̄_j - 1 = 0
 *
 * 12 equations in z = (x, x̄, y, ȳ, Q_1, Q̄_1, ..., Q_4, Q̄_4), each of degree 1 in (x, x̄, y, ȳ) and
 * 1 in (Q_j, Q̄_j), or 2 in (Q_j, Q̄_j): a 5-homogeneous Bezout count of 4^4 = 256, against the
 * total degree's 4096. The start system has the same structure, each equation a product of
 * random linear factors (a linear-product start system, Sommese and Wampler 2005, 8.4), whose
 * 256 solutions are small linear solves. Morgan and Wampler (J. Mech. Des. 112(4):544, 1990)
 * found 36 isolated solutions for generic data.
 *
 * The data are scaled first (u_j, v_j divided by |A - D|), the solutions mapped back. A solution is real when x̄ = conj(x), ȳ = conj(y), Q̄_j = conj(Q_j)
 * within `real_tolerance`; a real solution is a four-bar A B C D with the coupler point P.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mechgen/synthesis/homotopy.h"

namespace mechgen::synthesis {

/// Five precision points and both ground pivots (model units).
struct FivePointTask {
  std::array<double, 2> crank_pivot{};   ///< A
  std::array<double, 2> rocker_pivot{};  ///< D
  std::array<std::array<double, 2>, 5> points{};  ///< P_0 .. P_4, in the order the motion meets them
};

/// A real solution as a four-bar, named as tests/synthesis/models/synth_fourbar.yaml names it:
/// crank AB = a, coupler BC = b, rocker DC = c, ground AD = d at the angle theta0 from +x, A at
/// (x0, y0); the coupler point P at (xi, eta) in the coupler's frame (origin B, x along BC).
/// K precision points: five here, nine in nine_point.h.
template <size_t K>
struct FourBarOf {
  int solution = -1;  ///< its index among the solutions (ExactPathResult::solutions.finite)
  double a = 0, b = 0, c = 0, d = 0, xi = 0, eta = 0, x0 = 0, y0 = 0, theta0 = 0;
  std::array<double, K> crank{};  ///< the crank's angle (AB from +x, rad, in (-pi, pi]) at each point
  /// The assembly branch at each point: the side of the diagonal BD on which C lies, the sign
  /// of (D - B) x (C - B): +1 or -1 (0: on it, a dead point).
  std::array<int, K> branch{};
  bool same_branch = false;  ///< every point on one branch (necessary to reach them in one motion)
  /// +1: the crank's angle increases from each point to the next within one turn (the points
  /// in order with the crank turning counter-clockwise), -1: decreasing, 0: neither.
  int direction = 0;
  bool grashof = false;      ///< s + l <= p + q
  bool crank_turns = false;  ///< Grashof with the crank or the ground the shortest link
  double closure = 0;  ///< largest |P_j - reached point| of the loop equations, from the lengths
  std::string defect;  ///< "" or what fails first: "degenerate link", "branch", "order"
  /// The linkage is a usable solution of the task: no link of zero length, one branch, in
  /// order one way (the checks that set `defect`).
  bool defect_free() const { return defect.empty(); }
};
using ExactFourBar = FourBarOf<5>;

struct ExactPathOptions {
  homotopy::TrackOptions track;
  double real_tolerance = 1e-8;  ///< |x̄ - conj(x)| etc. relative to 1 + |z|_inf
  std::uint64_t seed = 20260317;  ///< the start system's and gamma's coefficients (fixed: same bytes every run)
};

struct ExactPathResult {
  int paths = 0;                        ///< tracked: the Bezout count, 256
  homotopy::Solutions<12> solutions;    ///< every path's end; .finite are the isolated solutions (scaled data)
  int num_solutions = 0;                ///< distinct finite nonsingular solutions
  std::vector<ExactFourBar> real;       ///< the real ones as four-bars
  double scale = 1;                     ///< the data's scale (|A - D|)
};

namespace exact_internal {
using homotopy::Complex;
using Vec12 = homotopy::VecN<12>;
using Mat12 = homotopy::MatN<12>;

/// A fixed stream of complex numbers of modulus in [0.5, 1.5) and any argument (the start
/// system's coefficients): mt19937_64's output is specified by the standard, so the same on
/// every platform (uniform_real_distribution's is not).
class Coefficients {
 public:
  explicit Coefficients(std::uint64_t seed) : rng_(seed) {}
  Complex Next() {
    const double r = 0.5 + Unit(), angle = 6.283185307179586 * Unit();
    return std::polar(r, angle);
  }

 private:
  double Unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  std::mt19937_64 rng_;
};

/// Index of Q_j (j = 1..4) in z; Q̄_j is the next one.
constexpr int QIndex(int j) { return 4 + 2 * (j - 1); }

/// The target system F on scaled data: u_j = P_j - A, v_j = P_j - D as complex numbers.
struct Target {
  std::array<Complex, 5> u, v;
  void operator()(const Vec12& z, Vec12* f, Mat12* J) const {
    f->setZero();
    J->setZero();
    const Complex x = z(0), xb = z(1), y = z(2), yb = z(3);
    for (int j = 1; j <= 4; ++j) {
      const int q = QIndex(j), r = 3 * (j - 1);
      const Complex Q = z(q), Qb = z(q + 1);
      const Complex uj = u[j], u0 = u[0], vj = v[j], v0 = v[0];
      (*f)(r) = std::conj(uj) * x * Q + uj * xb * Qb - std::conj(u0) * x - u0 * xb + (std::norm(uj) - std::norm(u0));
      (*J)(r, 0) = std::conj(uj) * Q - std::conj(u0);
      (*J)(r, 1) = uj * Qb - u0;
      (*J)(r, q) = std::conj(uj) * x;
      (*J)(r, q + 1) = uj * xb;
      (*f)(r + 1) = std::conj(vj) * y * Q + vj * yb * Qb - std::conj(v0) * y - v0 * yb + (std::norm(vj) - std::norm(v0));
      (*J)(r + 1, 2) = std::conj(vj) * Q - std::conj(v0);
      (*J)(r + 1, 3) = vj * Qb - v0;
      (*J)(r + 1, q) = std::conj(vj) * y;
      (*J)(r + 1, q + 1) = vj * yb;
      (*f)(r + 2) = Q * Qb - Complex(1);
      (*J)(r + 2, q) = Qb;
      (*J)(r + 2, q + 1) = Q;
    }
  }
};

/// The linear-product start system: row 3(j-1) is l_{j,0}(x, x̄, y, ȳ) m_{j,0}(Q_j, Q̄_j), row 3(j-1)+1
/// l_{j,1} m_{j,1}, row 3(j-1)+2 m_{j,2} m_{j,3}; l = c_0 + c . (x, x̄, y, ȳ), m = e_0 + e_1 Q + e_2 Q̄.
struct Start {
  std::array<std::array<std::array<Complex, 5>, 2>, 4> l;  // [j-1][k][0: constant, 1..4]
  std::array<std::array<std::array<Complex, 3>, 4>, 4> m;  // [j-1][k][0: constant, 1: Q, 2: Q̄]

  explicit Start(std::uint64_t seed) {
    Coefficients c(seed);
    for (auto& lj : l)
      for (auto& lk : lj)
        for (Complex& v : lk) v = c.Next();
    for (auto& mj : m)
      for (auto& mk : mj)
        for (Complex& v : mk) v = c.Next();
  }
  Complex L(int j, int k, const Vec12& z) const {
    const auto& c = l[static_cast<size_t>(j - 1)][static_cast<size_t>(k)];
    return c[0] + c[1] * z(0) + c[2] * z(1) + c[3] * z(2) + c[4] * z(3);
  }
  Complex M(int j, int k, const Vec12& z) const {
    const auto& e = m[static_cast<size_t>(j - 1)][static_cast<size_t>(k)];
    return e[0] + e[1] * z(QIndex(j)) + e[2] * z(QIndex(j) + 1);
  }
  void operator()(const Vec12& z, Vec12* g, Mat12* J) const {
    g->setZero();
    J->setZero();
    for (int j = 1; j <= 4; ++j) {
      const int q = QIndex(j), r = 3 * (j - 1);
      const auto& m_j = m[static_cast<size_t>(j - 1)];
      for (int k = 0; k < 2; ++k) {
        const auto& c = l[static_cast<size_t>(j - 1)][static_cast<size_t>(k)];
        const Complex lv = L(j, k, z), mv = M(j, k, z);
        (*g)(r + k) = lv * mv;
        for (int i = 0; i < 4; ++i) (*J)(r + k, i) = c[static_cast<size_t>(i + 1)] * mv;
        (*J)(r + k, q) = lv * m_j[static_cast<size_t>(k)][1];
        (*J)(r + k, q + 1) = lv * m_j[static_cast<size_t>(k)][2];
      }
      const Complex m2 = M(j, 2, z), m3 = M(j, 3, z);
      (*g)(r + 2) = m2 * m3;
      (*J)(r + 2, q) = m_j[2][1] * m3 + m2 * m_j[3][1];
      (*J)(r + 2, q + 1) = m_j[2][2] * m3 + m2 * m_j[3][2];
    }
  }
  /// Its 256 solutions: for each j, which of rows 3(j-1), 3(j-1)+1 vanishes by its l factor
  /// (the other by its m factor), and which factor of row 3(j-1)+2 vanishes.
  std::vector<Vec12> Solutions() const {
    std::vector<Vec12> out;
    out.reserve(256);
    for (int choice = 0; choice < 256; ++choice) {
      Eigen::Matrix<Complex, 4, 4> A;
      Eigen::Matrix<Complex, 4, 1> rhs;
      Vec12 z = Vec12::Zero();
      for (int j = 1; j <= 4; ++j) {
        const int bits = (choice >> (2 * (j - 1))) & 3;
        const int by_l = bits & 1, by_m = 1 - by_l, unit = 2 + (bits >> 1);
        const auto& c = l[static_cast<size_t>(j - 1)][static_cast<size_t>(by_l)];
        for (int i = 0; i < 4; ++i) A(j - 1, i) = c[static_cast<size_t>(i + 1)];
        rhs(j - 1) = -c[0];
        const auto& e1 = m[static_cast<size_t>(j - 1)][static_cast<size_t>(by_m)];
        const auto& e2 = m[static_cast<size_t>(j - 1)][static_cast<size_t>(unit)];
        const Complex det = e1[1] * e2[2] - e1[2] * e2[1];
        z(QIndex(j)) = (-e1[0] * e2[2] + e1[2] * e2[0]) / det;
        z(QIndex(j) + 1) = (-e1[1] * e2[0] + e1[0] * e2[1]) / det;
      }
      z.head<4>() = A.partialPivLu().solve(rhs);
      out.push_back(z);
    }
    return out;
  }
};

inline double Cross(const Complex& a, const Complex& b) { return a.real() * b.imag() - a.imag() * b.real(); }

/// The angle in (-pi, pi].
inline double Wrap(double a) {
  const double two_pi = 6.283185307179586;
  a = std::remainder(a, two_pi);
  return a <= -3.141592653589793 ? a + two_pi : a;
}
}  // namespace exact_internal

/**
 * \brief A real solution as a four-bar with its verdicts: A, D the ground pivots, P_j the K
 *        points, B_0 = P_0 + x and C_0 = P_0 + y the coupler's joints at point 0, Q_j the
 *        coupler's turn from point 0 to point j (Q_0 = 1, |Q_j| = 1).
 */
template <size_t K>
FourBarOf<K> JudgeFourBar(homotopy::Complex A, homotopy::Complex D, const std::array<homotopy::Complex, K>& P,
                          homotopy::Complex x, homotopy::Complex y, const std::array<homotopy::Complex, K>& Q) {
  using exact_internal::Cross;
  using homotopy::Complex;
  FourBarOf<K> bar;
  const Complex B0 = P[0] + x, C0 = P[0] + y;
  bar.a = std::abs(B0 - A);
  bar.b = std::abs(C0 - B0);
  bar.c = std::abs(C0 - D);
  bar.d = std::abs(D - A);
  bar.x0 = A.real(), bar.y0 = A.imag();
  bar.theta0 = std::arg(D - A);
  const Complex e = bar.b > 0 ? (C0 - B0) / bar.b : Complex(1);  // the coupler's x axis at pose 0
  const Complex local = (P[0] - B0) * std::conj(e);                // P - B in the coupler frame
  bar.xi = local.real(), bar.eta = local.imag();
  for (size_t j = 0; j < K; ++j) {
    const Complex Bj = P[j] + Q[j] * x;
    const Complex Cj = P[j] + Q[j] * y;
    bar.crank[j] = std::arg(Bj - A);
    const double side = Cross(D - Bj, Cj - Bj);
    bar.branch[j] = side > 0 ? 1 : side < 0 ? -1 : 0;
    bar.closure = std::max({bar.closure, std::abs(std::abs(Bj - A) - bar.a), std::abs(std::abs(Cj - D) - bar.c)});
  }
  bar.same_branch = bar.branch[0] != 0;
  for (size_t j = 1; j < K; ++j) bar.same_branch = bar.same_branch && bar.branch[j] == bar.branch[0];
  // In order: the crank's turn from P_0 to each point, counter-clockwise (or clockwise) in [0, 2 pi), increasing.
  for (int sign : {1, -1}) {
    bool increasing = true;
    double last = 0;
    for (size_t j = 1; j < K; ++j) {
      double turn = sign * (bar.crank[j] - bar.crank[0]);
      turn = std::fmod(std::fmod(turn, 6.283185307179586) + 6.283185307179586, 6.283185307179586);
      increasing = increasing && turn > last;
      last = turn;
    }
    if (increasing) {
      bar.direction = sign;
      break;
    }
  }
  std::array<double, 4> len{bar.a, bar.b, bar.c, bar.d};
  std::sort(len.begin(), len.end());
  bar.grashof = len[0] + len[3] <= len[1] + len[2];
  const double shortest = len[0];
  bar.crank_turns = bar.grashof && (bar.a == shortest || bar.d == shortest);
  if (!(bar.a > 0 && bar.b > 0 && bar.c > 0 && bar.d > 0)) {
    bar.defect = "degenerate link";
  } else if (!bar.same_branch) {
    bar.defect = "branch";
  } else if (bar.direction == 0) {
    bar.defect = "order";
  }
  return bar;
}

/**
 * \brief Every isolated solution of the five-point problem with both pivots given, and the
 *        real ones as four-bars (in the task's units).
 */
inline ExactPathResult SolveFivePointsWithPivots(const FivePointTask& task, const ExactPathOptions& options = {}) {
  using namespace exact_internal;
  ExactPathResult out;
  const Complex A(task.crank_pivot[0], task.crank_pivot[1]), D(task.rocker_pivot[0], task.rocker_pivot[1]);
  out.scale = std::abs(D - A);
  if (!(out.scale > 0) || !std::isfinite(out.scale)) return out;
  Target F;
  std::array<Complex, 5> P;
  for (int j = 0; j < 5; ++j) {
    P[static_cast<size_t>(j)] = Complex(task.points[static_cast<size_t>(j)][0], task.points[static_cast<size_t>(j)][1]);
    F.u[static_cast<size_t>(j)] = (P[static_cast<size_t>(j)] - A) / out.scale;
    F.v[static_cast<size_t>(j)] = (P[static_cast<size_t>(j)] - D) / out.scale;
  }
  const Start G(options.seed);
  Coefficients gamma_stream(options.seed ^ 0x9e3779b97f4a7c15ULL);
  const Complex gamma = gamma_stream.Next();
  const std::vector<Vec12> starts = G.Solutions();
  out.paths = static_cast<int>(starts.size());
  out.solutions = homotopy::TrackAll<12>(F, G, gamma, starts, options.track);
  out.num_solutions = static_cast<int>(out.solutions.finite.size());

  for (size_t index = 0; index < out.solutions.finite.size(); ++index) {
    const Vec12& z = out.solutions.finite[index];
    const double size = 1 + homotopy::internal::NormInf<12>(z);
    bool real = true;
    for (int k = 0; k < 12; k += 2) real = real && std::abs(z(k + 1) - std::conj(z(k))) <= options.real_tolerance * size;
    if (!real) continue;
    // The real solution, symmetrized (z and conj(z̄) agree to real_tolerance).
    const Complex x = 0.5 * (z(0) + std::conj(z(1))) * out.scale, y = 0.5 * (z(2) + std::conj(z(3))) * out.scale;
    std::array<Complex, 5> Q;
    Q[0] = 1;
    for (int j = 1; j <= 4; ++j) {
      const Complex q = 0.5 * (z(QIndex(j)) + std::conj(z(QIndex(j) + 1)));
      Q[static_cast<size_t>(j)] = q / std::abs(q);
    }
    ExactFourBar bar = JudgeFourBar<5>(A, D, P, x, y, Q);
    bar.solution = static_cast<int>(index);
    out.real.push_back(bar);
  }
  return out;
}

}  // namespace mechgen::synthesis
