/**
 * \file position/state.h
 * State<M>: a closed configuration of model M and everything the model gives there (K, L,
 * the points, the distance to singularity, the branch). PositionSolver keeps its last valid
 * one (PositionSolver::state()); a sweep records one per row. Fixed-size, starts as NaN.
 */
#pragma once

#include <limits>

#include <Eigen/Core>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"

namespace mechgen::position {

/// A closed configuration and everything the model gives there. All members start as NaN.
template <class M>
struct State {
  using T = ModelTypes<M>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  /// A generated M: every member NaN. A ViewModel: empty (State(model) sizes it).
  State() = default;
  /// Every member NaN at the model's sizes (for a generated M the same as State()).
  explicit State(const M& model) {
    if constexpr (ModelCalls<M>::kView) {
      using C = ModelCalls<M>;
      const int nq = C::Nq(model), nphi = C::Nphi(model), np = C::NumPoints(model);
      q.setConstant(nq, kNaN);
      phi.setConstant(nphi, kNaN);
      K.setConstant(nphi, nq, kNaN);
      Phi_phi.setConstant(C::Nc(model), nphi, kNaN);
      L.setConstant(nphi, nq * nq, kNaN);
      r_P.setConstant(2, np, kNaN);
      K_P.setConstant(2 * np, nq, kNaN);
      L_P.setConstant(2 * np, nq * nq, kNaN);
      singular_direction.setConstant(nphi, kNaN);
      largest_direction.setConstant(nphi, kNaN);
    } else {
      (void)model;
    }
  }

  typename T::VecQ q = NaNs<typename T::VecQ>();        ///< inputs (kNq)
  typename T::VecPhi phi = NaNs<typename T::VecPhi>();  ///< dependent variables (kNphi)
  typename T::MatK K = NaNs<typename T::MatK>();        ///< dphi/dq (kNphi x kNq)
  /// dPhi/dphi (kNc x kNphi) from the Model::Coeffs that gave K and L (a model whose
  /// coefficients have it; NaN otherwise): the statics' multipliers read it with K and L
  /// (statics/sweep.h: a row's statics without evaluating the coefficients again).
  typename T::MatCPhi Phi_phi = NaNs<typename T::MatCPhi>();
  typename T::MatL L = NaNs<typename T::MatL>();        ///< L(i, j + kNq k) = dK(i,j)/dq_k
  typename T::MatRP r_P = NaNs<typename T::MatRP>();    ///< points (2 x kNumPoints)
  typename T::MatKP K_P = NaNs<typename T::MatKP>();    ///< d r_P / dq (2 kNumPoints x kNq)
  typename T::MatLP L_P = NaNs<typename T::MatLP>();    ///< d2 r_P / dq2 (2 kNumPoints x kNq^2)
  double residual_norm = kNaN;                         ///< ||Phi||_inf
  double condition = kNaN;                             ///< cond_1(Phi_phi)
  /// Distance to singularity: sigma_min(Phi_phi), its smallest singular value (model length
  /// units; 0 at a dead or change point), and sigma_max = ||Phi_phi||_2.
  double sigma_min = kNaN;
  double sigma_max = kNaN;
  /// Unit right singular vector of sigma_min (kNphi): the direction in which phi can move
  /// with Phi unchanged to first order when sigma_min -> 0 (the singular motion).
  typename T::VecPhi singular_direction = NaNs<typename T::VecPhi>();
  /// Unit right singular vector of sigma_max (kNphi); the next configuration's estimate
  /// starts from it and from singular_direction.
  typename T::VecPhi largest_direction = NaNs<typename T::VecPhi>();
  /// true: sigma_min, sigma_max and both directions are exact (a singular value
  /// decomposition: closed form for kNphi <= 2, JacobiSVD above); false: the estimate of
  /// PositionSolver's continuation steps for kNphi > 2 (see position/solver.h: "Distance to
  /// singularity"), sigma_min an upper bound and sigma_max a lower bound of the exact ones.
  bool sigma_exact = false;
  /// Error bounds implied by the conditioning (position/solver.h, "Accuracy"): estimates of
  /// ||phi - phi_exact||_inf, ||K - K_exact||_inf and ||L - L_exact||_inf at this q, growing
  /// like eps cond, eps cond^2 and eps cond^3 (cond = cond_1 Phi_phi) next to a singular
  /// configuration. NaN until the coefficients are computed.
  double phi_error = kNaN;
  double K_error = kNaN;
  double L_error = kNaN;
  /// ||Phi_phi^{-1}||_1 = cond_1 / ||Phi_phi||_1 (the scale of phi_error).
  double inverse_norm = kNaN;
  int branch = 0;                                      ///< sign(det Phi_phi)
  bool valid = false;                                  ///< a converged configuration
};

}  // namespace mechgen::position
