/**
 * \file position/internal/distance.h
 * Conditioning, branch and distance to singularity of Phi_phi (see the file comment of
 * position/solver.h, "Distance to singularity").
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::position {

template <class M, class Assembler>
bool PositionSolver<M, Assembler>::Classify(const MatCPhi& Phi_phi, const Factorization& f,
                                 const State<M>* warm, State<M>* s, bool distance) const {
  s->condition = f.condition();
  s->inverse_norm = f.inverse_norm1();  // ||Phi_phi^{-1}||_1, no division by ||Phi_phi||_1
  s->branch = Sign(f.determinant());
  if (distance) Distance(Phi_phi, f, warm, s);
  // f.ok(): det finite and nonzero (so branch != 0), cond_1 finite.
  return f.ok() && s->condition * options_.min_rcond <= 1.0;
}

template <class M, class Assembler>
void PositionSolver<M, Assembler>::Distance(const MatCPhi& A, const Factorization& f,
                                 const State<M>* warm, State<M>* s) const {
  constexpr int kN = M::kNphi;
  const int n = nphi();
  s->sigma_exact = true;
  if constexpr (kN != Eigen::Dynamic && kN <= 2) {
    // f.ok(): det and cond_1 finite, so every entry of A is.
    (void)n;
    SmallDistance(A, f.ok(), s);
  } else {
    if (kN == Eigen::Dynamic && n <= 2) {  // the view: the same, chosen at run time
      SmallDistance(A, f.ok(), s);
      return;
    }
    // One step of inverse iteration on Phi_phi^T Phi_phi from the neighbour's singular
    // direction (two solves with the factorization the step has anyway) and one step of
    // the power iteration from its largest direction (two products). The Rayleigh
    // quotients ||A v|| >= sigma_min and ||A u|| <= sigma_max; the warm start carries the
    // iteration from configuration to configuration, and next to a singular configuration
    // (sigma_min << sigma_{n-1}) one step converges by the factor (sigma_min/sigma_{n-1})^2.
    // When the estimated ratio drops below Options::exact_sigma_ratio, the full SVD runs.
    if (warm != nullptr && f.ok() && options_.exact_sigma_ratio < 1 &&
        warm->singular_direction.allFinite() && warm->largest_direction.allFinite()) {
      VecPhi v = f.Solve(f.SolveTransposed(warm->singular_direction));
      VecPhi u = A.transpose() * (A * warm->largest_direction);
      const double nv = v.norm(), nu = u.norm();
      if (std::isfinite(nv) && std::isfinite(nu) && nv > 0 && nu > 0) {
        v /= nv;
        u /= nu;
        const double smin = (A * v).norm();
        const double smax = std::max((A * u).norm(), smin);
        if (smin >= options_.exact_sigma_ratio * smax) {
          internal::FixSign(&v);
          internal::FixSign(&u);
          s->sigma_min = smin;
          s->sigma_max = smax;
          s->singular_direction = v;
          s->largest_direction = u;
          s->sigma_exact = false;
          return;
        }
      }
    }
    if (!A.allFinite()) {
      constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
      s->sigma_min = s->sigma_max = kNaN;
      s->singular_direction.setConstant(n, kNaN);
      s->largest_direction.setConstant(n, kNaN);
      return;
    }
    const Eigen::JacobiSVD<MatCPhi, Eigen::NoQRPreconditioner> svd(A, Eigen::ComputeFullV);
    s->sigma_min = svd.singularValues()(n - 1);
    s->sigma_max = svd.singularValues()(0);
    s->singular_direction = svd.matrixV().col(n - 1);
    s->largest_direction = svd.matrixV().col(0);
    internal::FixSign(&s->singular_direction);
    internal::FixSign(&s->largest_direction);
  }
}

template <class M, class Assembler>
template <class Mat>
void PositionSolver<M, Assembler>::SmallDistance(const Mat& A, bool known_finite,
                                                 State<M>* s) const {
  constexpr int n = M::kNphi;
  s->sigma_exact = true;
  if constexpr (n == Eigen::Dynamic) {
    // The view: the fixed-size code of A's size (1 or 2).
    if (nphi() == 1) {
      s->sigma_min = s->sigma_max = std::abs(A(0, 0));
      s->singular_direction.setOnes(1);
      s->largest_direction.setOnes(1);
      if (!A.allFinite()) s->sigma_min = s->sigma_max = std::numeric_limits<double>::quiet_NaN();
    } else if (nphi() == 2) {
      Eigen::Vector2d v, u;
      Eigen::Matrix2d A2;
      A2 << A(0, 0), A(0, 1), A(1, 0), A(1, 1);
      internal::SingularValues2x2(A2, &s->sigma_min, &s->sigma_max, &v, &u, known_finite);
      Assign(&s->singular_direction, v);
      Assign(&s->largest_direction, u);
    }
  } else if constexpr (n == 1) {
    (void)known_finite;
    s->sigma_min = s->sigma_max = std::abs(A(0, 0));
    s->singular_direction.setOnes();
    s->largest_direction.setOnes();
    if (!A.allFinite()) {
      s->sigma_min = s->sigma_max = std::numeric_limits<double>::quiet_NaN();
    }
  } else if constexpr (n == 2) {
    internal::SingularValues2x2(A, &s->sigma_min, &s->sigma_max, &s->singular_direction,
                                &s->largest_direction, known_finite);
  } else {
    (void)A, (void)known_finite, (void)s;
  }
}

template <class M, class Assembler>
void PositionSolver<M, Assembler>::MakeDistanceExact(State<M>* s) const {
  if (s->sigma_exact) return;
  MatCPhi Phi_phi;
  Calls::Phi(model_, params_, s->q, s->phi, nullptr, &Phi_phi, nullptr);
  const Factorization f(Phi_phi);
  Distance(Phi_phi, f, nullptr, s);
}

}  // namespace mechgen::position
