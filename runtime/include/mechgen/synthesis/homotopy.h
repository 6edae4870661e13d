/**
 * \file synthesis/homotopy.h
 * Polynomial homotopy continuation for a square system F(z) = 0 in n complex unknowns (issue
 * 44: exact synthesis). The solutions of a start system G(z) = 0 whose solutions are known are
 * carried to those of F along
 *
 *   H(z, t) = (1 - t) gamma G(z) + t F(z),   t from 0 to 1,
 *
 * with a complex gamma (the "gamma trick": for all but finitely many gamma on the unit circle
 * no path meets a singularity for t < 1; Sommese and Wampler, *The Numerical Solution of
 * Systems of Polynomials*, 2005, ch. 7). Each path: a fourth-order Runge–Kutta predictor on
 * dz/dt = -H_z^{-1} H_t, a Newton corrector at the new t, the step halved when the corrector
 * does not contract and doubled after three accepted steps; a path whose largest coordinate
 * passes `divergence_bound`, or that stalls near t = 1 while |z| keeps growing decade after
 * decade of 1 - t, goes to a solution at infinity of the affine system (the start system has
 * more solutions than F: Bezout's count against F's). At t = 1, Newton on F alone,
 * and the endpoint's residual and the reciprocal condition of F_z are reported: a finite,
 * nonsingular solution is what the path reached with a small residual and rcond above
 * `singular_rcond`.
 *
 * TrackHomotopy() is the same tracker on any homotopy h(z, t) with h(., 1) = F: the parameter
 * homotopies F(z; p(t)) of the nine-point problem's monodromy (nine_point.h); TrackPath() is it
 * on the straight-line H above.
 *
 * TrackAll() follows every start solution and sorts the endpoints; two paths that reach the
 * same nonsingular solution have jumped (a path crossed to another): those are tracked again
 * with a tenth of the largest step, and what still coincides is counted, never hidden.
 *
 * Deterministic: the same system, start solutions and options give the same bytes. Needs Eigen.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace mechgen::synthesis::homotopy {

using Complex = std::complex<double>;
template <int N>
using VecN = Eigen::Matrix<Complex, N, 1>;
template <int N>
using MatN = Eigen::Matrix<Complex, N, N>;

/// The path tracker's settings.
struct TrackOptions {
  double initial_step = 0.02;       ///< first step in t
  double max_step = 0.05;           ///< largest step in t
  double min_step = 1e-13;          ///< below this a path has failed
  double corrector_tolerance = 1e-9;  ///< Newton's step relative to 1 + |z|, to accept a step
  int corrector_iterations = 3;     ///< Newton iterations per step
  double divergence_bound = 1e8;    ///< |z|_inf above this: a solution at infinity
  int max_steps = 100000;           ///< per path
  int final_iterations = 10;        ///< Newton on F at t = 1
  double residual_tolerance = 1e-9;  ///< |F(z)|_inf relative to 1 + |z|_inf at a finite solution
  double singular_rcond = 1e-10;    ///< rcond of F_z below this: a singular endpoint
  double same_tolerance = 1e-7;     ///< two endpoints closer than this (relative) are one
  /// A path that stalls near t = 1 goes to infinity when |z| grew by more than this factor over
  /// each of its last two decades of 1 - t (and is above 10): see TrackPath.
  double growth_per_decade = 1.5;
};

enum class PathStatus {
  kFinite,      ///< reached t = 1 at a nonsingular solution of F
  kSingular,    ///< reached t = 1, but F_z is singular there (or Newton did not settle)
  kAtInfinity,  ///< diverged: a solution at infinity of the affine system
  kFailed,      ///< the step fell below min_step, or max_steps were used
};

inline const char* ToString(PathStatus s) {
  switch (s) {
    case PathStatus::kFinite: return "finite";
    case PathStatus::kSingular: return "singular";
    case PathStatus::kAtInfinity: return "at infinity";
    case PathStatus::kFailed: return "failed";
  }
  return "?";
}

template <int N>
struct PathEnd {
  PathStatus status = PathStatus::kFailed;
  VecN<N> z = VecN<N>::Zero();
  double t = 0;         ///< where the path stopped
  double residual = 0;  ///< |F(z)|_inf at the end
  double rcond = 0;     ///< smallest over largest singular value of F_z at the end
  int steps = 0;        ///< accepted steps
  int start = -1;       ///< index of its start solution
};

namespace internal {
template <int N>
double NormInf(const VecN<N>& v) {
  double m = 0;
  for (int i = 0; i < N; ++i) m = std::max(m, std::abs(v(i)));
  return m;
}

/// H and its derivatives at (z, t): H, H_z, H_t.
template <int N, class Target, class Start>
void EvalH(const Target& F, const Start& G, Complex gamma, const VecN<N>& z, double t, VecN<N>* H,
           MatN<N>* Hz, VecN<N>* Ht) {
  VecN<N> f, g;
  MatN<N> fz, gz;
  F(z, &f, &fz);
  G(z, &g, &gz);
  *H = (1 - t) * gamma * g + t * f;
  *Hz = (1 - t) * gamma * gz + t * fz;
  *Ht = f - gamma * g;
}

/// dz/dt = -H_z^{-1} H_t; false where H_z is singular or the tangent is not finite.
template <int N, class Hom>
bool Tangent(const Hom& h, const VecN<N>& z, double t, VecN<N>* dz) {
  VecN<N> H, Ht;
  MatN<N> Hz;
  h(z, t, &H, &Hz, &Ht);
  const Eigen::PartialPivLU<MatN<N>> lu(Hz);
  *dz = -lu.solve(Ht);
  return dz->allFinite();
}

/// Newton on H(., t) from *z: true when a step fell below tol (1 + |z|) within `iterations`
/// and each step contracted.
template <int N, class Hom>
bool Correct(const Hom& h, double t, int iterations, double tol, VecN<N>* z) {
  double last = HUGE_VAL;
  for (int k = 0; k < iterations; ++k) {
    VecN<N> H, Ht;
    MatN<N> Hz;
    h(*z, t, &H, &Hz, &Ht);
    const VecN<N> dz = Eigen::PartialPivLU<MatN<N>>(Hz).solve(H);
    if (!dz.allFinite()) return false;
    const double size = NormInf<N>(dz);
    *z -= dz;
    if (size <= tol * (1 + NormInf<N>(*z))) return true;
    if (k > 0 && size > 0.5 * last) return false;  // not contracting: the step was too long
    last = size;
  }
  return false;
}
}  // namespace internal

/**
 * \brief Follows one path of a homotopy h from z0 (h(z0, 0) = 0) at t = 0 to t = 1, where
 *        h(., 1) = F.
 * \param hom  hom(z, t, &H, &H_z, &H_t) (VecN<N>, MatN<N>, VecN<N>): the homotopy and its derivatives
 * \param F    the target system F(z, &f, &F_z): Newton on it at t = 1, its residual and F_z's
 *           conditioning judge the end
 * The straight-line homotopy of TrackPath, or a parameter homotopy F(z; p(t)) (nine_point.h).
 */
template <int N, class Hom, class Target>
PathEnd<N> TrackHomotopy(const Hom& hom, const Target& F, const VecN<N>& z0, const TrackOptions& o) {
  PathEnd<N> end;
  VecN<N> z = z0;
  double t = 0, h = o.initial_step;
  int good = 0;
  // |z| where the path passed t = 1 - 10^-k (k = 1, 2, ...): a path that stalls short of t = 1
  // while |z| grew by more than growth_per_decade over each of the last two decades goes to
  // infinity as (1 - t)^-alpha with alpha > 0 (a slow divergence that does not reach the bound:
  // solutions at infinity of higher multiplicity).
  std::vector<double> decade_norm;
  while (t < 1) {
    if (end.steps + 1 > o.max_steps || h < o.min_step) {
      const size_t k = decade_norm.size();
      const double now = internal::NormInf<N>(z);
      const bool diverging = k >= 3 && now > 10 && now >= decade_norm[k - 1] &&
                             decade_norm[k - 1] > o.growth_per_decade * decade_norm[k - 2] &&
                             decade_norm[k - 2] > o.growth_per_decade * decade_norm[k - 3];
      end.status = diverging ? PathStatus::kAtInfinity : PathStatus::kFailed;
      end.z = z;
      end.t = t;
      return end;
    }
    const double step = std::min(h, 1 - t);
    // Runge–Kutta 4 on dz/dt = -H_z^{-1} H_t.
    VecN<N> k1, k2, k3, k4;
    bool ok = internal::Tangent<N>(hom, z, t, &k1) &&
              internal::Tangent<N>(hom, VecN<N>(z + 0.5 * step * k1), t + 0.5 * step, &k2) &&
              internal::Tangent<N>(hom, VecN<N>(z + 0.5 * step * k2), t + 0.5 * step, &k3) &&
              internal::Tangent<N>(hom, VecN<N>(z + step * k3), t + step, &k4);
    VecN<N> next = z + (step / 6) * (k1 + 2 * k2 + 2 * k3 + k4);
    // The corrector; the predictor's own jump is bounded too (a path stays near its start).
    ok = ok && internal::NormInf<N>(VecN<N>(next - z)) <= 0.5 * (1 + internal::NormInf<N>(z)) &&
         internal::Correct<N>(hom, t + step, o.corrector_iterations, o.corrector_tolerance, &next);
    if (!ok) {
      h *= 0.5;
      good = 0;
      continue;
    }
    z = next;
    t = step == 1 - t ? 1.0 : t + step;
    ++end.steps;
    while (t < 1 && 1 - t <= std::pow(10.0, -static_cast<double>(decade_norm.size() + 1)))
      decade_norm.push_back(internal::NormInf<N>(z));
    if (internal::NormInf<N>(z) > o.divergence_bound) {
      end.status = PathStatus::kAtInfinity;
      end.z = z;
      end.t = t;
      return end;
    }
    if (++good >= 3) {
      h = std::min(2 * h, o.max_step);
      good = 0;
    }
  }
  // At t = 1: Newton on F, then its residual and conditioning.
  for (int k = 0; k < o.final_iterations; ++k) {
    VecN<N> f;
    MatN<N> fz;
    F(z, &f, &fz);
    const VecN<N> dz = Eigen::PartialPivLU<MatN<N>>(fz).solve(f);
    if (!dz.allFinite()) break;
    z -= dz;
    if (internal::NormInf<N>(dz) <= 1e-15 * (1 + internal::NormInf<N>(z))) break;
  }
  VecN<N> f;
  MatN<N> fz;
  F(z, &f, &fz);
  end.z = z;
  end.t = 1;
  end.residual = internal::NormInf<N>(f);
  const Eigen::JacobiSVD<MatN<N>> svd(fz);
  const auto& s = svd.singularValues();
  end.rcond = s(0) > 0 ? s(N - 1) / s(0) : 0;
  const bool settled = end.residual <= o.residual_tolerance * (1 + internal::NormInf<N>(z)) && z.allFinite();
  end.status = settled && end.rcond >= o.singular_rcond ? PathStatus::kFinite : PathStatus::kSingular;
  return end;
}

/**
 * \brief Follows one path of H from the start solution z0 (G(z0) = 0) at t = 0 to t = 1.
 * \param F      target system: F(z, &f, &F_z) (VecN<N>, MatN<N>)
 * \param G      start system, the same signature
 * \param gamma  the complex constant of H (not real, not on a finite bad set: a fixed
 *               "random" value)
 */
template <int N, class Target, class Start>
PathEnd<N> TrackPath(const Target& F, const Start& G, Complex gamma, const VecN<N>& z0,
                     const TrackOptions& o) {
  const auto h = [&](const VecN<N>& z, double t, VecN<N>* H, MatN<N>* Hz, VecN<N>* Ht) {
    internal::EvalH<N>(F, G, gamma, z, t, H, Hz, Ht);
  };
  return TrackHomotopy<N>(h, F, z0, o);
}

/// Every path and the distinct finite solutions.
template <int N>
struct Solutions {
  std::vector<PathEnd<N>> paths;  ///< one per start solution, in their order
  std::vector<VecN<N>> finite;    ///< the distinct nonsingular solutions, in the order first reached
  int at_infinity = 0, singular = 0, failed = 0;
  int retracked = 0;   ///< paths tracked again after reaching an endpoint another path reached
  int duplicates = 0;  ///< paths that still reach another path's endpoint (a path jump not cured)
};

/**
 * \brief Tracks every start solution; the paths that meet another's endpoint are tracked again
 *        with max_step / 10 (then / 100).
 */
template <int N, class Target, class Start>
Solutions<N> TrackAll(const Target& F, const Start& G, Complex gamma, const std::vector<VecN<N>>& starts,
                      const TrackOptions& options) {
  Solutions<N> out;
  out.paths.reserve(starts.size());
  for (size_t i = 0; i < starts.size(); ++i) {
    out.paths.push_back(TrackPath<N>(F, G, gamma, starts[i], options));
    out.paths.back().start = static_cast<int>(i);
  }
  auto same = [&](const VecN<N>& a, const VecN<N>& b) {
    return internal::NormInf<N>(VecN<N>(a - b)) <=
           options.same_tolerance * (1 + std::max(internal::NormInf<N>(a), internal::NormInf<N>(b)));
  };
  // Paths whose finite endpoint another path reached too: track them again, finer.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<size_t> again;
    for (size_t i = 0; i < out.paths.size(); ++i) {
      if (out.paths[i].status != PathStatus::kFinite) continue;
      for (size_t j = 0; j < out.paths.size(); ++j)
        if (j != i && out.paths[j].status == PathStatus::kFinite && same(out.paths[i].z, out.paths[j].z)) {
          again.push_back(i);
          break;
        }
    }
    if (again.empty()) break;
    TrackOptions finer = options;
    finer.max_step = options.max_step * (pass == 0 ? 0.1 : 0.01);
    finer.initial_step = std::min(finer.initial_step, finer.max_step);
    for (size_t i : again) {
      out.paths[i] = TrackPath<N>(F, G, gamma, starts[i], finer);
      out.paths[i].start = static_cast<int>(i);
      ++out.retracked;
    }
  }
  for (const PathEnd<N>& p : out.paths) {
    switch (p.status) {
      case PathStatus::kAtInfinity: ++out.at_infinity; break;
      case PathStatus::kSingular: ++out.singular; break;
      case PathStatus::kFailed: ++out.failed; break;
      case PathStatus::kFinite: {
        bool seen = false;
        for (const VecN<N>& s : out.finite) seen = seen || same(s, p.z);
        if (seen) {
          ++out.duplicates;
        } else {
          out.finite.push_back(p.z);
        }
        break;
      }
    }
  }
  return out;
}

}  // namespace mechgen::synthesis::homotopy
