/**
 * \file position/internal/singularity.h
 * Passing a dead point or a change point by pseudo-arclength continuation.
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::position {

template <class M, class Assembler>
Status PositionSolver<M, Assembler>::PassSingularity(const VecQ& q_toward, Crossing crossing,
                                          Summary* summary) {
  // (n + 1 columns: fixed for a generated M, bounded for the view.)
  constexpr int kX = M::kNphi == Eigen::Dynamic ? Eigen::Dynamic : M::kNphi + 1;
  constexpr int kMaxX = T::kMaxPhi + 1;
  constexpr int kJOptions = M::kNc == 1 && kX != 1 ? Eigen::RowMajor : Eigen::ColMajor;
  using VecX = Eigen::Matrix<double, kX, 1, Eigen::ColMajor, kMaxX, 1>;            // x = (t, phi)
  using MatJ = Eigen::Matrix<double, M::kNc, kX, kJOptions, T::kMaxPhi, kMaxX>;  // [Phi_q d, Phi_phi]
  using MatX = Eigen::Matrix<double, kX, kX, Eigen::ColMajor, kMaxX, kMaxX>;
  const int n = nphi();
  Summary s;
  auto finish = [&](Status status, const char* reason, const State<M>* at = nullptr) {
    s.reason = reason;
    return Finish(status, at, &s, summary);
  };
  if (!options_valid_ || !state_ref().valid || !q_toward.allFinite()) {
    return finish(Status::kInvalidInput, "no valid state() or input not finite");
  }
  const VecQ q0 = state_ref().q;
  VecQ d = q_toward - q0;
  const double length = d.norm();
  if (!(length > 0)) return finish(Status::kInvalidInput, "q_toward == state().q");
  d /= length;
  Describe(state_ref(), &s);
  if (crossing == Crossing::kStop) return finish(Status::kSingular, "Crossing::kStop");
  if constexpr (Features::kLoopFree) {
    return finish(Status::kSingular, "a model without constraints has no singular configuration");
  } else {
    MakeDistanceExact(&state_ref());  // the same configuration; only an estimate becomes exact
    s.sigma_min = state_ref().sigma_min;
    if (!(state_ref().sigma_min < options_.near_singular_ratio * state_ref().sigma_max)) {
      return finish(Status::kSingular,
                    "state() is not next to a singular configuration "
                    "(sigma_min / sigma_max >= Options::near_singular_ratio)");
    }

    // G(x) = Phi(q0 + t d, phi) and its Jacobian J = [Phi_q d, Phi_phi] (n x (n + 1)).
    auto eval = [&](const VecX& x, VecC* G, MatJ* J) {
      const VecQ q = q0 + x(0) * d;
      const VecPhi phi = x.tail(n);
      MatCPhi A;
      MatCQ B;
      Calls::Phi(model_, params_, q, phi, G, J != nullptr ? &A : nullptr, J != nullptr ? &B : nullptr);
      if (J != nullptr) {
        // The fixed-size block for a generated M (a dynamic block of a 1 x 2 J made GCC 12 warn
        // of a 16-byte store into 8 in the rolling wheel's sweep).
        if constexpr (Calls::kView) {
          J->resize(nc(), n + 1);
          J->col(0) = B * d;
          J->rightCols(n) = A;
        } else {
          J->col(0) = B * d;
          J->template rightCols<M::kNphi>() = A;
        }
      }
    };
    // Unit null vector of J (the curve's tangent) and sigma_n(J) / sigma_1(J), from the SVD
    // of J padded with a zero row (fixed size, no allocation).
    auto tangent = [&](const MatJ& J, VecX* tau, double* ratio) {
      MatX padded = MatX::Zero(n + 1, n + 1);
      padded.topRows(nc()) = J;
      const Eigen::JacobiSVD<MatX, Eigen::NoQRPreconditioner> svd(padded, Eigen::ComputeFullV);
      *tau = svd.matrixV().col(n);
      *ratio = svd.singularValues()(n - 1) / svd.singularValues()(0);
    };

    auto x0 = Sized<VecX>(n + 1);
    x0(0) = 0;
    x0.tail(n) = state_ref().phi;
    MatJ J0;
    VecC G;
    eval(x0, &G, &J0);
    auto tau0 = Sized<VecX>(n + 1);
    double ratio_J = 0;
    tangent(J0, &tau0, &ratio_J);
    if (tau0(0) < 0) tau0 = -tau0;  // the incoming motion: t increasing
    const double ratio_phi = state_ref().sigma_min / state_ref().sigma_max;
    // At a dead point J keeps full rank while Phi_phi loses it (ratio_J = O(1) >> ratio_phi);
    // at a change point both lose rank at the same rate. The geometric mean separates them.
    const bool dead_point = ratio_J > std::sqrt(ratio_phi);
    if (dead_point && crossing != Crossing::kReverseInput) {
      return finish(Status::kSingular,
                    "a dead point: the loop does not close beyond it; Crossing::kReverseInput "
                    "continues with the input reversed");
    }
    if (!dead_point && crossing == Crossing::kReverseInput) {
      return finish(Status::kSingular,
                    "a change point, not a dead point: choose Crossing::kFollowTangent or "
                    "kSwitchBranch");
    }

    VecX tau = tau0;
    if (crossing == Crossing::kSwitchBranch) {
      // Second derivatives psi^T Phi''(a, b) by central differences of the Jacobian along a.
      VecPhi v, psi;
      double smin = 0, smax = 0;
      MatCPhi A0 = J0.rightCols(n);
      SmallestSingular(A0, &smin, &smax, &v, &psi);
      VecX w = VecX::Zero(n + 1);
      w.tail(n) = v;
      const double h = std::cbrt(std::numeric_limits<double>::epsilon());
      auto second = [&](const VecX& a, const VecX& b) {
        MatJ J_plus, J_minus;
        VecC unused;
        eval(VecX(x0 + h * a), &unused, &J_plus);
        eval(VecX(x0 - h * a), &unused, &J_minus);
        return psi.dot((J_plus - J_minus) * b) / (2 * h);
      };
      const double c1 = second(tau0, w);
      const double c2 = second(w, w);
      // The bifurcation equation psi^T Phi''(tau1 + mu w, tau1 + mu w) = 0 has the roots
      // mu ~ 0 (the incoming curve) and mu = -2 c1 / c2 (the other one).
      VecX other = c2 * tau0 - 2 * c1 * w;
      if (!(other.norm() > 0) || !other.allFinite()) {
        return finish(Status::kSingular, "no second curve found at this change point");
      }
      other.normalize();
      if (other(0) < 0 || (other(0) == 0 && other.dot(tau0) < 0)) other = -other;
      if (std::abs(other.dot(tau0)) > 1 - 1e-6) {
        return finish(Status::kSingular, "the two tangents coincide: not a simple change point");
      }
      tau = other;
    }

    // Pseudo-arclength steps: predictor x + ds tau, corrector Newton on
    // [G(x); tau^T (x - x_pred)] = 0, until beyond the singular configuration.
    const double ds = options_.pass_step;
    VecX x = x0;
    State<M> next(model_);
    for (int step = 0; step < 64; ++step) {
      const VecX x_pred = x + ds * tau;
      VecX y = x_pred;
      bool converged = false;
      for (int it = 0; it <= 2 * options_.max_newton_iterations; ++it) {
        MatJ J;
        eval(y, &G, &J);
        ++s.iterations;
        const double norm = G.template lpNorm<Eigen::Infinity>();
        if (!std::isfinite(norm) || !y.allFinite()) break;
        if (norm <= options_.tolerance) {
          converged = true;
          break;
        }
        auto F = Sized<MatX>(n + 1, n + 1);
        F.topRows(nc()) = J;
        F.row(n) = tau.transpose();
        auto rhs = Sized<VecX>(n + 1);
        rhs.head(nc()) = G;
        rhs(n) = tau.dot(y - x_pred);
        y -= mechgen::internal::SolvePartialPivLU(F, rhs);  // (the view: the fixed-size LU of its size)
      }
      if (!converged || (y - x_pred).norm() > 0.5 * ds) {
        return finish(Status::kDidNotConverge, "pseudo-arclength corrector failed");
      }
      MatJ J;
      eval(y, &G, &J);
      auto tau_new = Sized<VecX>(n + 1);
      double unused = 0;
      tangent(J, &tau_new, &unused);
      if (tau_new.dot(tau) < 0) tau_new = -tau_new;
      x = y;
      tau = tau_new;
      ++s.substeps;
      // Beyond it when regular again, at least 2 steps on, with the expected sign of det.
      next.q = q0 + x(0) * d;
      next.phi = x.tail(n);
      MatCPhi Phi_phi = J.rightCols(n);
      const Factorization f(Phi_phi);
      const bool regular = Classify(Phi_phi, f, nullptr, &next);
      const bool flipped = next.branch == -state_ref().branch;
      const bool reversed = tau(0) < 0;
      bool done = false;
      if (crossing == Crossing::kSwitchBranch) {
        done = !flipped && !reversed;
      } else if (crossing == Crossing::kFollowTangent) {
        done = flipped && !reversed;
      } else {
        done = flipped && reversed;
      }
      if (step >= 1 && regular && next.sigma_min >= state_ref().sigma_min && done) {
        next.residual_norm = G.template lpNorm<Eigen::Infinity>();
        if (!FillCoefficients(f, nullptr, &next)) {
          return finish(Status::kSingular, "coefficients not finite beyond the crossing");
        }
        next.valid = true;
        state_ref() = next;
        FindModes(state_ref());  // the branch changed
        s.input_reversed = reversed;
        return finish(Status::kConverged, "", &next);
      }
    }
    return finish(Status::kSingular, "did not get beyond the singular configuration in 64 steps");
  }
}

}  // namespace mechgen::position
