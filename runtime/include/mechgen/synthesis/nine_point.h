/**
 * \file synthesis/nine_point.h
 * The general nine-point path synthesis of the four-bar (issue 44): every four-bar whose
 * coupler point passes through nine given points, pivots free. Wampler, Morgan and Sommese
 * (J. Mech. Des. 114(1):153, 1992) found 8652 isolated solutions for generic points, 1442
 * classes up to the exchange of the two dyads (x 2) and Roberts' cognates (x 3). Solved here by
 * monodromy (Duff et al., "Solving polynomial systems via homotopy continuation and
 * monodromy", IMA J. Numer. Anal. 39(3), 2019; the formulation as in HomotopyContinuation.jl's
 * nine-point example): parameter homotopies around loops in the space of point sets, then one
 * parameter homotopy to the given points.
 *
 * The equations, in isotropic coordinates (a point (X, Y) is z = X + iY with z̄ = X - iY an
 * unknown of its own). P_0..P_8 the points, delta_j = P_j - P_0 (j = 1..8). At point 0 the
 * crank's coupler joint is B_0 = P_0 + x, the rocker's C_0 = P_0 + y; the crank's pivot is
 * A = P_0 + a, the rocker's D = P_0 + b. At point j the coupler has turned by Q_j = 1 + gamma_j
 * (Q̄_j = 1 + gammā_j = 1/Q_j), B_j = P_j + Q_j x. |B_j - A|^2 = |B_0 - A|^2 reads, with the
 * x x̄ and a ā terms cancelled,
 *
 *   (ā - deltā_j) x gamma_j + (a - delta_j) x̄ gammā_j + (ā - x̄) delta_j + (a - x) deltā_j
 *       - delta_j deltā_j = 0,
 *
 * the same in (y, b) for the rocker, and gamma_j gammā_j + gamma_j + gammā_j = 0 (Q_j Q̄_j = 1):
 * 24 equations in z = (x, x̄, a, ā, y, ȳ, b, b̄, gamma_1..8, gammā_1..8), the 16 parameters
 * p = (delta_1..8, deltā_1..8). A real point set has deltā_j = conj(delta_j); a real solution
 * has x̄ = conj(x), ..., gammā_j = conj(gamma_j), and is a four-bar (A, B_0, C_0, D, P_0).
 *
 * The symmetries, maps of the solutions at a parameter p onto themselves (they commute with any
 * parameter homotopy, so the monodromy tracks one solution per class):
 *   - Relabel: the dyads exchanged, (x, a) <-> (y, b) and their partners;
 *   - Cognate: Roberts' cognate through P_0 on the pivot A, (x, a, y, b) -> ((x - a) y / (x - y),
 *     (b x - a y) / (x - y), a - x, a) (and the same on the partners), its gamma_j, gammā_j from
 *     the two (linear) length equations at delta_j; Cognate twice is the third cognate, three
 *     times the identity. With Relabel: a group of order 6, the class of a solution.
 *
 * The monodromy (Monodromy): from a random complex point set with one solution built by
 * construction (RandomStartPair: random x, a, y, b and Q_j, each delta_j from its two length
 * equations), loops p_0 -> p_1 -> p_2 -> p_0 through random complex point sets, each edge a
 * straight-line parameter homotopy F(z; (1 - t) p + t p') (straight lines between random complex
 * points: the gamma trick of the parameter space, since the bad set has real codimension 2).
 * Each class representative goes once around every loop; an endpoint in no known class is a
 * new class (its orbit under the symmetries kept to recognise it again), which then goes around
 * every loop too. When every class went around every loop, a new loop; the run stops when
 * `stall_loops` new loops in a row found no new class. Then Solve tracks every class from the
 * base to the given points (scaled by the largest |delta_j|), and expands the orbits there.
 *
 * Deterministic: the same points and options give the same bytes for any number of threads
 * (each path's end depends only on its start and its loop; the ends merge in a fixed order).
 * Needs Eigen and std::thread.
 */
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <map>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "mechgen/synthesis/exact_path.h"
#include "mechgen/synthesis/homotopy.h"

namespace mechgen::synthesis::nine_point {

using homotopy::Complex;
constexpr int kN = 24;  ///< unknowns and equations
using Vec = homotopy::VecN<kN>;
using Mat = homotopy::MatN<kN>;
/// p(j - 1) = delta_j, p(8 + j - 1) = deltā_j, j = 1..8.
using Params = Eigen::Matrix<Complex, 16, 1>;
using NineBar = FourBarOf<9>;

/// Where the unknowns sit in z.
enum : int { kX = 0, kXb = 1, kA = 2, kAb = 3, kY = 4, kYb = 5, kB = 6, kBb = 7 };
constexpr int GammaIndex(int j) { return 8 + (j - 1); }      ///< gamma_j, j = 1..8
constexpr int GammaBarIndex(int j) { return 16 + (j - 1); }  ///< gammā_j

/**
 * \brief F(z; p), F_z, and F_p dp (the change of F along the parameter direction dp).
 *        Rows j - 1: the crank's length at point j; 8 + j - 1: the rocker's; 16 + j - 1: |Q_j| = 1.
 */
inline void Evaluate(const Vec& z, const Params& p, const Params& dp, Vec* f, Mat* J, Vec* fp) {
  f->setZero();
  J->setZero();
  fp->setZero();
  for (int j = 1; j <= 8; ++j) {
    const int g = GammaIndex(j), gb = GammaBarIndex(j);
    const Complex G = z(g), Gb = z(gb), d = p(j - 1), db = p(8 + j - 1);
    for (int side = 0; side < 2; ++side) {
      const int r = 8 * side + (j - 1), o = 4 * side;
      const Complex X = z(o), Xb = z(o + 1), A = z(o + 2), Ab = z(o + 3);
      (*f)(r) = (Ab - db) * X * G + (A - d) * Xb * Gb + (Ab - Xb) * d + (A - X) * db - d * db;
      (*J)(r, o) = (Ab - db) * G - db;
      (*J)(r, o + 1) = (A - d) * Gb - d;
      (*J)(r, o + 2) = Xb * Gb + db;
      (*J)(r, o + 3) = X * G + d;
      (*J)(r, g) = (Ab - db) * X;
      (*J)(r, gb) = (A - d) * Xb;
      (*fp)(r) = (-Xb * Gb + Ab - Xb - db) * dp(j - 1) + (-X * G + A - X - d) * dp(8 + j - 1);
    }
    const int r = 16 + (j - 1);
    (*f)(r) = G * Gb + G + Gb;
    (*J)(r, g) = Gb + Complex(1);
    (*J)(r, gb) = G + Complex(1);
  }
}

/// The system at fixed parameters: F(z, &f, &F_z) for homotopy.h.
struct AtParams {
  Params p;
  void operator()(const Vec& z, Vec* f, Mat* J) const {
    Vec unused;
    Evaluate(z, p, Params::Zero(), f, J, &unused);
  }
};

/// The parameter homotopy H(z, t) = F(z; (1 - t) from + t to).
struct Segment {
  Params from, to;
  void operator()(const Vec& z, double t, Vec* H, Mat* Hz, Vec* Ht) const {
    const Params p = (1 - t) * from + t * to;
    Evaluate(z, p, to - from, H, Hz, Ht);
  }
};

/**
 * \brief The same system homogenized, on a random affine chart of projective space: w =
 *        (z, w0) ~ (z / w0, 1), each equation multiplied by the powers of w0 that make it
 *        homogeneous (the length equations of degree 3, |Q_j| = 1 of degree 2), and a 25th,
 *        linear equation chart . w = 1. A solution far out (|z| ~ 1e3: a pivot far away, Q_j large)
 *        is a w of moderate size with a small w0, where the affine z's equations have entries of
 *        sizes |z| and |z|^3 and Newton in double precision cannot settle to the corrector's
 *        tolerance: every edge is tracked here (TrackEdge).
 */
constexpr int kNP = kN + 1;  ///< unknowns of the chart: z, then w0
using PVec = homotopy::VecN<kNP>;
using PMat = homotopy::MatN<kNP>;

inline void EvaluateProjective(const PVec& w, const Params& p, const Params& dp, const PVec& chart, PVec* f, PMat* J,
                               PVec* fp) {
  f->setZero();
  J->setZero();
  fp->setZero();
  const Complex w0 = w(kN), w02 = w0 * w0;
  for (int j = 1; j <= 8; ++j) {
    const int g = GammaIndex(j), gb = GammaBarIndex(j);
    const Complex G = w(g), Gb = w(gb), d = p(j - 1), db = p(8 + j - 1);
    for (int side = 0; side < 2; ++side) {
      const int r = 8 * side + (j - 1), o = 4 * side;
      const Complex X = w(o), Xb = w(o + 1), A = w(o + 2), Ab = w(o + 3);
      const Complex lin = (Ab - Xb) * d + (A - X) * db;
      (*f)(r) = (Ab - db * w0) * X * G + (A - d * w0) * Xb * Gb + w02 * lin - d * db * w02 * w0;
      (*J)(r, o) = (Ab - db * w0) * G - w02 * db;
      (*J)(r, o + 1) = (A - d * w0) * Gb - w02 * d;
      (*J)(r, o + 2) = Xb * Gb + w02 * db;
      (*J)(r, o + 3) = X * G + w02 * d;
      (*J)(r, g) = (Ab - db * w0) * X;
      (*J)(r, gb) = (A - d * w0) * Xb;
      (*J)(r, kN) = -db * X * G - d * Xb * Gb + Complex(2) * w0 * lin - Complex(3) * d * db * w02;
      (*fp)(r) = (-w0 * Xb * Gb + w02 * (Ab - Xb) - db * w02 * w0) * dp(j - 1) +
                 (-w0 * X * G + w02 * (A - X) - d * w02 * w0) * dp(8 + j - 1);
    }
    const int r = 16 + (j - 1);
    (*f)(r) = G * Gb + w0 * (G + Gb);
    (*J)(r, g) = Gb + w0;
    (*J)(r, gb) = G + w0;
    (*J)(r, kN) = G + Gb;
  }
  (*f)(kN) = (chart.transpose() * w)(0) - Complex(1);
  J->row(kN) = chart.transpose();
}

/// The chart's fixed random coefficients (the same every run).
inline PVec ProjectiveChart() {
  exact_internal::Coefficients c(0x9e3779b97f4a7c15ULL);
  PVec chart;
  for (int k = 0; k < kNP; ++k) chart(k) = c.Next();
  return chart;
}

/// z on the chart, and back (w0 = 0: at infinity, not finite).
inline PVec ToChart(const Vec& z, const PVec& chart) {
  PVec w;
  w.head<kN>() = z;
  w(kN) = 1;
  return w / (chart.transpose() * w)(0);
}
inline Vec FromChart(const PVec& w) { return w.head<kN>() / w(kN); }

/// The homogenized system at fixed parameters, and the parameter homotopy on the chart.
struct AtParamsProjective {
  Params p;
  PVec chart;
  void operator()(const PVec& w, PVec* f, PMat* J) const {
    PVec unused;
    EvaluateProjective(w, p, Params::Zero(), chart, f, J, &unused);
  }
};
struct SegmentProjective {
  Params from, to;
  PVec chart;
  void operator()(const PVec& w, double t, PVec* H, PMat* Hw, PVec* Ht) const {
    const Params p = (1 - t) * from + t * to;
    EvaluateProjective(w, p, to - from, chart, H, Hw, Ht);
  }
};

/// |F(z; p)|_inf.
inline double Residual(const Vec& z, const Params& p) {
  Vec f;
  Mat J;
  AtParams{p}(z, &f, &J);
  return homotopy::internal::NormInf<kN>(f);
}

/// The dyads exchanged.
inline Vec Relabel(const Vec& z) {
  Vec r = z;
  for (int k = 0; k < 4; ++k) std::swap(r(k), r(4 + k));
  return r;
}

/// Roberts' cognate (file comment); false where x = y or a point's length equations do not fix
/// its gamma_j, gammā_j.
inline bool Cognate(const Vec& z, const Params& p, Vec* out) {
  Vec c = Vec::Zero();
  for (int bar = 0; bar < 2; ++bar) {  // the unknowns, then their partners
    const Complex x = z(kX + bar), a = z(kA + bar), y = z(kY + bar), b = z(kB + bar);
    const Complex w = x - y;
    if (!(std::abs(w) > 0)) return false;
    c(kX + bar) = (x - a) * y / w;
    c(kA + bar) = (b * x - a * y) / w;
    c(kY + bar) = a - x;
    c(kB + bar) = a;
  }
  for (int j = 1; j <= 8; ++j) {
    const Complex d = p(j - 1), db = p(8 + j - 1);
    Eigen::Matrix<Complex, 2, 2> M;
    Eigen::Matrix<Complex, 2, 1> rhs;
    for (int side = 0; side < 2; ++side) {
      const int o = 4 * side;
      const Complex X = c(o), Xb = c(o + 1), A = c(o + 2), Ab = c(o + 3);
      M(side, 0) = (Ab - db) * X;
      M(side, 1) = (A - d) * Xb;
      rhs(side) = -((Ab - Xb) * d + (A - X) * db - d * db);
    }
    const Complex det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
    if (!(std::abs(det) > 0)) return false;
    c(GammaIndex(j)) = (rhs(0) * M(1, 1) - M(0, 1) * rhs(1)) / det;
    c(GammaBarIndex(j)) = (M(0, 0) * rhs(1) - rhs(0) * M(1, 0)) / det;
  }
  if (!c.allFinite()) return false;
  *out = c;
  return true;
}

/// The class of z: z, its two cognates, and the three relabelled (fewer where Cognate fails).
inline std::vector<Vec> Orbit(const Vec& z, const Params& p) {
  std::vector<Vec> o = {z};
  Vec c1, c2;
  if (Cognate(z, p, &c1)) {
    o.push_back(c1);
    if (Cognate(c1, p, &c2)) o.push_back(c2);
  }
  const size_t n = o.size();
  for (size_t k = 0; k < n; ++k) o.push_back(Relabel(o[k]));
  return o;
}

/// A real solution: x̄ = conj(x), ..., gammā_j = conj(gamma_j) within tol (1 + |z|_inf).
inline bool IsReal(const Vec& z, double tol) {
  const double size = tol * (1 + homotopy::internal::NormInf<kN>(z));
  for (int k = 0; k < 8; k += 2)
    if (std::abs(z(k + 1) - std::conj(z(k))) > size) return false;
  for (int j = 1; j <= 8; ++j)
    if (std::abs(z(GammaBarIndex(j)) - std::conj(z(GammaIndex(j)))) > size) return false;
  return true;
}

/// A solution built by construction and its parameters.
struct StartPair {
  Params p = Params::Zero();
  Vec z = Vec::Zero();
};

/**
 * \brief Random complex x, a, y, b (and partners) and turns Q_j (Q̄_j = 1/Q_j); each delta_j,
 *        deltā_j from the two length equations at point j: their difference is linear, so
 *        deltā_j = u + v delta_j, and the crank's equation a quadratic in delta_j (its root with
 *        the + sign of the square root). Same seed, same pair.
 */
inline StartPair RandomStartPair(std::uint64_t seed) {
  exact_internal::Coefficients c(seed);
  StartPair s;
  for (int k = 0; k < 8; ++k) s.z(k) = c.Next();
  for (int j = 1; j <= 8; ++j) {
    const Complex Q = c.Next();
    const Complex G = Q - Complex(1), Gb = Complex(1) / Q - Complex(1);
    s.z(GammaIndex(j)) = G, s.z(GammaBarIndex(j)) = Gb;
    // Side s: k_s + alpha_s delta + beta_s deltā - delta deltā.
    Complex k[2], alpha[2], beta[2];
    for (int side = 0; side < 2; ++side) {
      const int o = 4 * side;
      const Complex X = s.z(o), Xb = s.z(o + 1), A = s.z(o + 2), Ab = s.z(o + 3);
      k[side] = Ab * X * G + A * Xb * Gb;
      alpha[side] = -Xb * Gb + Ab - Xb;
      beta[side] = -X * G + A - X;
    }
    const Complex u = -(k[0] - k[1]) / (beta[0] - beta[1]), v = -(alpha[0] - alpha[1]) / (beta[0] - beta[1]);
    // k0 + alpha0 d + beta0 (u + v d) - d (u + v d) = 0.
    const Complex q2 = -v, q1 = alpha[0] + beta[0] * v - u, q0 = k[0] + beta[0] * u;
    const Complex root = std::sqrt(q1 * q1 - Complex(4) * q2 * q0);
    const Complex big = -q1 - (std::real(std::conj(q1) * root) >= 0 ? root : -root);  // no cancellation
    const Complex d = big / (Complex(2) * q2);
    s.p(j - 1) = d;
    s.p(8 + j - 1) = u + v * d;
  }
  // One Newton step on F at the built parameters (the construction's rounding).
  Vec f;
  Mat J;
  AtParams{s.p}(s.z, &f, &J);
  s.z -= Eigen::PartialPivLU<Mat>(J).solve(f);
  return s;
}

/// A random complex point set (parameters), each of modulus in [0.5, 1.5).
inline Params RandomParams(exact_internal::Coefficients* c) {
  Params p;
  for (int k = 0; k < 16; ++k) p(k) = c->Next();
  return p;
}

struct MonodromyOptions {
  /// The tracker's settings; an end is nonsingular by ScaledRcond >= scaled_rcond (its
  /// singular_rcond is not used).
  homotopy::TrackOptions track = [] {
    homotopy::TrackOptions o;
    o.divergence_bound = 1e7;
    return o;
  }();
  double scaled_rcond = 1e-10;
  int threads = 1;
  int stall_loops = 3;      ///< stop after this many new loops in a row found no new class
  int max_loops = 40;       ///< and after this many loops in all
  int max_classes = 0;      ///< stop as soon as this many classes are known (0: no cap; a short run in a test)
  double same_tolerance = 1e-6;  ///< two solutions closer than this (relative) are one
  std::uint64_t seed = 20261129;  ///< the loops' points (fixed: the same bytes every run)
};

struct MonodromyResult {
  Params base = Params::Zero();
  std::vector<Vec> classes;  ///< one solution per class at `base`, in the order found
  std::vector<int> found_at_loop;  ///< the loop (0-based) whose tracking found each class
  int loops = 0;       ///< loops made
  long paths = 0;      ///< edges tracked (three per trip around a loop)
  long failed = 0;     ///< trips that did not come back to a nonsingular solution
  double seconds = 0;
};

namespace internal {

/// Runs f(i) for i in [0, n) on `threads` threads; out[i] its result (the order of i, whatever
/// thread ran it).
template <class R, class Fn>
std::vector<R> ParallelMap(size_t n, int threads, const Fn& f) {
  std::vector<R> out(n);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < n; i = next++) out[i] = f(i);
  };
  const int extra = std::max(0, std::min(threads, static_cast<int>(n)) - 1);
  std::vector<std::thread> pool;
  for (int k = 0; k < extra; ++k) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  return out;
}

/// The known solutions, each with the class it belongs to: a lookup by a fixed linear form
/// Re(w . z), then the whole vector compared.
class ClassSet {
 public:
  explicit ClassSet(double tol) : tol_(tol) {
    for (int k = 0; k < kN; ++k) w_(k) = std::polar(1.0, 0.7 + 1.3 * k);
  }
  /// The class of z, or -1.
  int Find(const Vec& z) const {
    const double size = 1 + homotopy::internal::NormInf<kN>(z);
    const double key = Key(z), window = tol_ * (2 * size + 1) * kN;
    for (auto it = index_.lower_bound(key - window); it != index_.end() && it->first <= key + window; ++it) {
      const Vec& m = members_[static_cast<size_t>(it->second)];
      const double scale = std::max(size, 1 + homotopy::internal::NormInf<kN>(m));
      if (homotopy::internal::NormInf<kN>(Vec(m - z)) <= tol_ * scale) return class_[static_cast<size_t>(it->second)];
    }
    return -1;
  }
  /// Adds the members of a new class; its number.
  int Add(const std::vector<Vec>& orbit) {
    const int c = classes_++;
    for (const Vec& m : orbit) {
      index_.emplace(Key(m), static_cast<int>(members_.size()));
      members_.push_back(m);
      class_.push_back(c);
    }
    return c;
  }
  int size() const { return classes_; }

 private:
  double Key(const Vec& z) const { return (w_.transpose() * z)(0).real(); }
  double tol_;
  Vec w_;
  std::multimap<double, int> index_;
  std::vector<Vec> members_;
  std::vector<int> class_;
  int classes_ = 0;
};

/// The reciprocal condition of F_z at z equilibrated (Ruiz: rows and columns divided by the
/// square roots of their largest entries, ten sweeps, towards largest entries of 1 in every row
/// and column): a solution far out (a pivot far away) has F_z's entries of sizes |z|^-1 to
/// |z|^2 apart, so that the unscaled rcond says nothing about whether it is singular (one
/// sweep of column then row scaling leaves 5e-11 at a nonsingular solution with |z| = 5e3).
inline double ScaledRcond(const Vec& z, const Params& p) {
  Vec f;
  Mat J;
  AtParams{p}(z, &f, &J);
  for (int sweep = 0; sweep < 10; ++sweep) {
    for (int c = 0; c < kN; ++c) {
      const double m = J.col(c).cwiseAbs().maxCoeff();
      if (m > 0) J.col(c) /= std::sqrt(m);
    }
    for (int r = 0; r < kN; ++r) {
      const double m = J.row(r).cwiseAbs().maxCoeff();
      if (m > 0) J.row(r) /= std::sqrt(m);
    }
  }
  const Eigen::JacobiSVD<Mat> svd(J);
  const auto& s = svd.singularValues();
  return s(0) > 0 && std::isfinite(s(0)) ? s(kN - 1) / s(0) : 0;
}

/// A path along one edge, tracked on the projective chart (EvaluateProjective): its end when it
/// settles (the tracker's residual test on the chart), is finite and F_z there, equilibrated, is
/// nonsingular (rcond at least `scaled_rcond`).
inline bool TrackEdge(const Params& from, const Params& to, const Vec& z0, const homotopy::TrackOptions& o, Vec* z,
                      double scaled_rcond = 1e-10) {
  static const PVec chart = ProjectiveChart();
  homotopy::TrackOptions settle = o;
  settle.singular_rcond = 0;  // judged here, equilibrated
  const homotopy::PathEnd<kNP> e = homotopy::TrackHomotopy<kNP>(SegmentProjective{from, to, chart},
                                                                 AtParamsProjective{to, chart}, ToChart(z0, chart), settle);
  if (e.status != homotopy::PathStatus::kFinite) return false;
  const Vec end = FromChart(e.z);
  if (!end.allFinite() || !(ScaledRcond(end, to) >= scaled_rcond)) return false;
  *z = end;
  return true;
}

}  // namespace internal

/**
 * \brief Every class at `start.p` reachable by monodromy from `start.z` (file comment).
 */
inline MonodromyResult Monodromy(const StartPair& start, const MonodromyOptions& o) {
  using namespace internal;
  const auto t0 = std::chrono::steady_clock::now();
  MonodromyResult r;
  r.base = start.p;
  exact_internal::Coefficients rng(o.seed);
  std::vector<std::pair<Params, Params>> loops;
  ClassSet known(o.same_tolerance);
  std::vector<int> trips;  // loops each class went around (in order)
  auto add = [&](const Vec& z, int loop) {
    if (known.Find(z) >= 0) return false;
    known.Add(Orbit(z, r.base));
    r.classes.push_back(z);
    r.found_at_loop.push_back(loop);
    trips.push_back(0);
    return true;
  };
  add(start.z, 0);
  int stalled = 0;
  int classes_when_added = 0;
  auto capped = [&] { return o.max_classes > 0 && static_cast<int>(r.classes.size()) >= o.max_classes; };
  while (!capped()) {
    std::vector<size_t> pending;
    for (size_t i = 0; i < r.classes.size(); ++i)
      if (trips[i] < static_cast<int>(loops.size())) pending.push_back(i);
    if (pending.empty()) {
      if (!loops.empty()) stalled = static_cast<int>(r.classes.size()) > classes_when_added ? 0 : stalled + 1;
      if (stalled >= o.stall_loops || static_cast<int>(loops.size()) >= o.max_loops) break;
      loops.emplace_back(RandomParams(&rng), RandomParams(&rng));
      classes_when_added = static_cast<int>(r.classes.size());
      continue;
    }
    struct Trip {
      bool ok = false;
      Vec z = Vec::Zero();
      int loop = 0;
      int edges = 0;
    };
    const std::vector<Trip> ends = ParallelMap<Trip>(pending.size(), o.threads, [&](size_t k) {
      Trip t;
      const size_t i = pending[k];
      t.loop = trips[i];
      const auto& L = loops[static_cast<size_t>(t.loop)];
      Vec z1, z2, z3;
      t.edges = 1;
      if (!TrackEdge(r.base, L.first, r.classes[i], o.track, &z1, o.scaled_rcond)) return t;
      t.edges = 2;
      if (!TrackEdge(L.first, L.second, z1, o.track, &z2, o.scaled_rcond)) return t;
      t.edges = 3;
      if (!TrackEdge(L.second, r.base, z2, o.track, &z3, o.scaled_rcond)) return t;
      t.ok = true;
      t.z = z3;
      return t;
    });
    for (size_t k = 0; k < pending.size(); ++k) {
      ++trips[pending[k]];
      r.paths += ends[k].edges;
      if (!ends[k].ok) {
        ++r.failed;
        continue;
      }
      add(ends[k].z, ends[k].loop);
      if (capped()) break;
    }
  }
  r.loops = static_cast<int>(loops.size());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

/// Nine points (model units), in the order the motion meets them.
using NinePoints = std::array<std::array<double, 2>, 9>;

/// The parameters of nine points scaled by *scale (the largest |P_j - P_0|).
inline Params PointParams(const NinePoints& P, double* scale) {
  const Complex P0(P[0][0], P[0][1]);
  double s = 0;
  for (size_t j = 1; j < 9; ++j) s = std::max(s, std::abs(Complex(P[j][0], P[j][1]) - P0));
  *scale = s;
  Params p;
  for (int j = 1; j <= 8; ++j) {
    const Complex d = (Complex(P[static_cast<size_t>(j)][0], P[static_cast<size_t>(j)][1]) - P0) / s;
    p(j - 1) = d;
    p(8 + j - 1) = std::conj(d);
  }
  return p;
}

/// A solution on the points' scale as a four-bar (x, a, y, b and the Q_j from the symmetrized
/// real solution), judged by JudgeFourBar.
inline NineBar ToFourBar(const Vec& z, const NinePoints& points, double scale) {
  std::array<Complex, 9> P, Q;
  for (size_t j = 0; j < 9; ++j) P[j] = Complex(points[j][0], points[j][1]);
  auto real = [&](int k, int kb) { return 0.5 * (z(k) + std::conj(z(kb))); };
  const Complex x = real(kX, kXb) * scale, a = real(kA, kAb) * scale, y = real(kY, kYb) * scale,
                b = real(kB, kBb) * scale;
  Q[0] = 1;
  for (int j = 1; j <= 8; ++j) {
    const Complex q = Complex(1) + real(GammaIndex(j), GammaBarIndex(j));
    Q[static_cast<size_t>(j)] = q / std::abs(q);
  }
  return JudgeFourBar<9>(P[0] + a, P[0] + b, P, x, y, Q);
}

struct NinePointOptions {
  MonodromyOptions monodromy;
  double real_tolerance = 1e-8;   ///< a real solution (relative, IsReal)
  std::uint64_t start_seed = 20261130;  ///< the start pair (RandomStartPair)
};

/// A real solution at the points: the four-bar and its verdicts.
struct NineSolution {
  int klass = -1;   ///< its class (index into NinePointResult::at_target)
  int member = 0;   ///< which member of the class's orbit
  Vec z = Vec::Zero();  ///< on the scaled points
  NineBar bar;
  double residual = 0;  ///< |F(z; p)|_inf on the scaled points
};

struct NinePointResult {
  MonodromyResult monodromy;
  std::vector<Vec> at_target;  ///< one solution per class reached at the points (scaled), distinct classes
  int lost = 0;                ///< classes not reached at the points (their paths, their cognates' and three detours failed)
  std::vector<int> lost_classes;  ///< their indices in monodromy.classes
  int retracked = 0;           ///< paths tracked again: with a finer step, or a cognate's path
  int detours = 0;             ///< detours tried for a class still lost (each two paths)
  long paths = 0;              ///< every edge tracked: the monodromy's and the last homotopy's
  int solutions = 0;           ///< distinct solutions at the points: the orbits' members
  int real_classes = 0;
  std::vector<NineSolution> real;  ///< every real solution (six per real class), in class order
  int defect_free = 0;
  double scale = 1;
  double seconds = 0;          ///< wall time of the whole solve
};

/**
 * \brief Every four-bar through the nine points: monodromy at a random complex point set,
 *        then one parameter homotopy per class to the points (scaled); a path that fails or
 *        meets another class's end is tracked again with max_step / 10 (then / 100), one that
 *        still fails from its cognates, and a class still lost by detours; the orbits expanded
 *        at the points; the real solutions as four-bars.
 */
inline NinePointResult SolveAtPoints(const MonodromyResult& monodromy, const NinePoints& points,
                                     const NinePointOptions& o = {}) {
  using namespace internal;
  const auto t0 = std::chrono::steady_clock::now();
  NinePointResult out;
  const Params target = PointParams(points, &out.scale);
  out.monodromy = monodromy;
  const MonodromyResult& m = out.monodromy;
  out.paths = m.paths;
  struct End {
    bool ok = false;
    Vec z = Vec::Zero();
  };
  auto track = [&](const homotopy::TrackOptions& track) {
    return [&, track](size_t i) {
      End e;
      e.ok = TrackEdge(m.base, target, m.classes[i], track, &e.z, o.monodromy.scaled_rcond);
      return e;
    };
  };
  std::vector<End> ends = ParallelMap<End>(m.classes.size(), o.monodromy.threads, track(o.monodromy.track));
  out.paths += static_cast<long>(ends.size());
  // Which ends share a class at the target (a path jumped): those, and the failed, again finer.
  for (int pass = 0; pass < 2; ++pass) {
    ClassSet at(o.monodromy.same_tolerance);
    std::vector<int> owner(ends.size(), -1);
    std::vector<size_t> again;
    std::vector<int> first_of_class;
    for (size_t i = 0; i < ends.size(); ++i) {
      if (!ends[i].ok) {
        again.push_back(i);
        continue;
      }
      const int c = at.Find(ends[i].z);
      if (c >= 0) {
        again.push_back(i);
        const size_t j = static_cast<size_t>(first_of_class[static_cast<size_t>(c)]);
        if (std::find(again.begin(), again.end(), j) == again.end()) again.push_back(j);
        continue;
      }
      at.Add(Orbit(ends[i].z, target));
      first_of_class.push_back(static_cast<int>(i));
    }
    if (again.empty()) break;
    std::sort(again.begin(), again.end());
    homotopy::TrackOptions finer = o.monodromy.track;
    finer.max_step *= pass == 0 ? 0.1 : 0.01;
    finer.initial_step = std::min(finer.initial_step, finer.max_step);
    finer.max_steps *= 10;
    const auto redo = ParallelMap<End>(again.size(), o.monodromy.threads,
                                       [&](size_t k) { return track(finer)(again[k]); });
    for (size_t k = 0; k < again.size(); ++k) ends[again[k]] = redo[k];
    out.retracked += static_cast<int>(again.size());
    out.paths += static_cast<long>(again.size());
  }
  // A path that still fails: its class's cognates' paths (the symmetries commute with the
  // homotopy: the same class at the points; a pivot far out in one cognate is not in another).
  for (size_t i = 0; i < ends.size(); ++i) {
    if (ends[i].ok) continue;
    const std::vector<Vec> orbit = Orbit(m.classes[i], m.base);
    for (size_t k = 1; k < orbit.size() / 2 && !ends[i].ok; ++k) {
      ends[i].ok = TrackEdge(m.base, target, orbit[k], o.monodromy.track, &ends[i].z, o.monodromy.scaled_rcond);
      ++out.paths, ++out.retracked;
    }
  }
  ClassSet at(o.monodromy.same_tolerance);
  auto place = [&](const Vec& z) {
    const std::vector<Vec> orbit = Orbit(z, target);
    at.Add(orbit);
    out.at_target.push_back(z);
    // The orbit's distinct members.
    std::vector<Vec> distinct;
    for (const Vec& v : orbit) {
      bool seen = false;
      for (const Vec& u : distinct)
        seen = seen || homotopy::internal::NormInf<kN>(Vec(u - v)) <=
                           o.monodromy.same_tolerance * (1 + homotopy::internal::NormInf<kN>(v));
      if (!seen) distinct.push_back(v);
    }
    out.solutions += static_cast<int>(distinct.size());
    if (!IsReal(z, o.real_tolerance)) return;
    ++out.real_classes;
    for (size_t k = 0; k < distinct.size(); ++k) {
      NineSolution s;
      s.klass = static_cast<int>(out.at_target.size()) - 1;
      s.member = static_cast<int>(k);
      s.z = distinct[k];
      s.residual = Residual(s.z, target);
      s.bar = ToFourBar(s.z, points, out.scale);
      s.bar.solution = static_cast<int>(out.real.size());
      if (s.bar.defect_free()) ++out.defect_free;
      out.real.push_back(s);
    }
  };
  std::vector<size_t> lost;
  for (size_t i = 0; i < ends.size(); ++i) {
    if (!ends[i].ok || at.Find(ends[i].z) >= 0) {
      lost.push_back(i);
      continue;
    }
    place(ends[i].z);
  }
  // The classes still lost: by detours through random complex point sets (base -> q -> points,
  // up to three per lost class); an end in no class found yet is one (which class of the base it
  // came from no longer matters: the set at the points is what is sought).
  exact_internal::Coefficients detour(o.monodromy.seed ^ 0x5bd1e995ULL);
  for (size_t i : lost) {
    bool found = false;
    for (int k = 0; k < 3 && !found; ++k) {
      const Params q = RandomParams(&detour);
      Vec z1, z2;
      out.paths += 2;
      ++out.detours;
      if (TrackEdge(m.base, q, m.classes[i], o.monodromy.track, &z1, o.monodromy.scaled_rcond) &&
          TrackEdge(q, target, z1, o.monodromy.track, &z2, o.monodromy.scaled_rcond) && at.Find(z2) < 0) {
        place(z2);
        found = true;
      }
    }
    if (!found) ++out.lost, out.lost_classes.push_back(static_cast<int>(i));
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() + m.seconds;
  return out;
}

inline NinePointResult SolveNinePoints(const NinePoints& points, const NinePointOptions& o = {}) {
  return SolveAtPoints(Monodromy(RandomStartPair(o.start_seed), o.monodromy), points, o);
}

/// The joints B, C and the coupler point P of `bar` at crank angle q with C on side `side` of
/// B -> D (the sign of (D - B) x (C - B)), by circle intersection; false where the loop does
/// not close.
inline bool Configuration(const NineBar& bar, double q, int side, Complex* Bq, Complex* Cq, Complex* P) {
  const Complex A(bar.x0, bar.y0), D = A + std::polar(bar.d, bar.theta0), B = A + std::polar(bar.a, q);
  const double L = std::abs(D - B);
  if (!(L > 0)) return false;
  const Complex e = (D - B) / L;
  const double s = (bar.b * bar.b - bar.c * bar.c + L * L) / (2 * L), h2 = bar.b * bar.b - s * s;
  if (!(h2 >= 0)) return false;
  const Complex C = B + e * Complex(s, side * std::sqrt(h2));
  *Bq = B, *Cq = C;
  *P = B + (C - B) / bar.b * Complex(bar.xi, bar.eta);
  return true;
}

/**
 * \brief An SVG drawing of one four-bar through the nine points: its coupler curve (the branch
 *        through the points in blue, the other in grey; 720 crank angles each) over the linkage
 *        at point 1 (pivots, crank, coupler triangle, rocker), the points numbered.
 */
inline std::string NineBarSvg(const NineBar& bar, const NinePoints& points, const std::string& title) {
  const Complex A(bar.x0, bar.y0), D = A + std::polar(bar.d, bar.theta0);
  Complex B = A, C = D, P0(points[0][0], points[0][1]);
  Configuration(bar, bar.crank[0], bar.branch[0] != 0 ? bar.branch[0] : 1, &B, &C, &P0);
  std::vector<std::vector<Complex>> curves[2];
  double lo[2] = {std::min(A.real(), D.real()), std::min(A.imag(), D.imag())};
  double hi[2] = {std::max(A.real(), D.real()), std::max(A.imag(), D.imag())};
  auto grow = [&](const Complex& z) {
    lo[0] = std::min(lo[0], z.real()), lo[1] = std::min(lo[1], z.imag());
    hi[0] = std::max(hi[0], z.real()), hi[1] = std::max(hi[1], z.imag());
  };
  for (const Complex& z : {B, C, P0}) grow(z);
  for (const auto& p : points) grow(Complex(p[0], p[1]));
  for (int k = 0; k < 2; ++k) {
    const int side = k == 0 ? (bar.branch[0] != 0 ? bar.branch[0] : 1) : -(bar.branch[0] != 0 ? bar.branch[0] : 1);
    std::vector<Complex> piece;
    for (int s = 0; s <= 720; ++s) {
      Complex Bs, Cs, P;
      if (Configuration(bar, bar.crank[0] + 6.283185307179586 * s / 720, side, &Bs, &Cs, &P) && std::isfinite(P.real()) &&
          std::isfinite(P.imag())) {
        piece.push_back(P);
        grow(P);
      } else if (!piece.empty()) {
        curves[k].push_back(piece);
        piece.clear();
      }
    }
    if (!piece.empty()) curves[k].push_back(piece);
  }
  const double size = 480, margin = 30;
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-12});
  auto X = [&](const Complex& z) { return std::to_string(margin + (z.real() - lo[0]) / span * size); };
  auto Y = [&](const Complex& z) { return std::to_string(margin + (hi[1] - z.imag()) / span * size); };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(size + 2 * margin) +
                    "\" height=\"" + std::to_string(size + 2 * margin + 20) + "\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += "<text x=\"8\" y=\"16\" font-size=\"12\" font-family=\"sans-serif\">" + title + "</text>\n";
  svg += "<polygon points=\"" + X(B) + "," + Y(B) + " " + X(C) + "," + Y(C) + " " + X(P0) + "," + Y(P0) +
         "\" fill=\"#f3d9a4\" fill-opacity=\"0.5\" stroke=\"black\" stroke-width=\"1.5\"/>\n";
  for (const auto& link : {std::make_pair(A, B), std::make_pair(D, C)})
    svg += "<line x1=\"" + X(link.first) + "\" y1=\"" + Y(link.first) + "\" x2=\"" + X(link.second) + "\" y2=\"" +
           Y(link.second) + "\" stroke=\"black\" stroke-width=\"2.5\"/>\n";
  for (const Complex& g : {A, D})
    svg += "<path d=\"M" + X(g) + " " + Y(g) + " l-6 10 h12 z\" fill=\"#555555\"/>\n";
  for (int k = 1; k >= 0; --k)
    for (const auto& piece : curves[k]) {
      svg += std::string("<polyline fill=\"none\" stroke=\"") + (k == 0 ? "#1f5fa8" : "#bbbbbb") +
             "\" stroke-width=\"1.2\" points=\"";
      for (const Complex& z : piece) svg += X(z) + "," + Y(z) + " ";
      svg += "\"/>\n";
    }
  for (size_t j = 0; j < 9; ++j) {
    const Complex p(points[j][0], points[j][1]);
    svg += "<circle cx=\"" + X(p) + "\" cy=\"" + Y(p) + "\" r=\"4\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"1.5\"/>\n";
    svg += "<text x=\"" + X(p) + "\" y=\"" + Y(p) + "\" dx=\"6\" dy=\"-6\" font-size=\"11\" font-family=\"sans-serif\">" +
           std::to_string(j + 1) + "</text>\n";
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace mechgen::synthesis::nine_point
