/**
 * \file position/motion.h
 * Velocities and accelerations from Paul's velocity and centripetal coefficients.
 *
 * At a closed configuration (a State from PositionSolver) and for given input speeds qd and
 * accelerations qdd (Paul §4, one or several degrees of freedom):
 *   phid  = K qd,                 phidd = K qdd + L (qd (x) qd)
 *   v_P   = K_P qd,               a_P   = K_P qdd + L_P (qd (x) qd)
 * with (qd (x) qd)(j + kNq k) = qd_j qd_k, matching L(i, j + kNq k) = dK(i, j)/dq_k.
 * Point velocities need a model with K_P (order >= 1), accelerations L_P (order 2); when the
 * model lacks them they stay NaN. Fixed-size, no allocation.
 */
#pragma once

#include <limits>

#include <Eigen/Core>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/position/state.h"

namespace mechgen::position {

/// Time derivatives at one configuration. All members start as NaN.
template <class M>
struct Motion {
  using T = ModelTypes<M>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  /// A generated M: every member NaN. A ViewModel: empty (Motion(nq, nphi, np) sizes it).
  Motion() = default;
  /// Every member NaN at these sizes (for a generated M, its own: the same as Motion()).
  Motion(int nq, int nphi, int num_points) {
    if constexpr (ModelCalls<M>::kView) {
      qd.setConstant(nq, kNaN);
      qdd.setConstant(nq, kNaN);
      phid.setConstant(nphi, kNaN);
      phidd.setConstant(nphi, kNaN);
      v_P.setConstant(2, num_points, kNaN);
      a_P.setConstant(2, num_points, kNaN);
    } else {
      (void)nq, (void)nphi, (void)num_points;
    }
  }
  typename T::VecQ qd = NaNs<typename T::VecQ>();         ///< input speeds (kNq)
  typename T::VecQ qdd = NaNs<typename T::VecQ>();        ///< input accelerations (kNq)
  typename T::VecPhi phid = NaNs<typename T::VecPhi>();   ///< K qd (kNphi)
  typename T::VecPhi phidd = NaNs<typename T::VecPhi>();  ///< K qdd + L qd qd (kNphi)
  typename T::MatRP v_P = NaNs<typename T::MatRP>();      ///< point velocities (2 x kNumPoints)
  typename T::MatRP a_P = NaNs<typename T::MatRP>();      ///< accelerations (2 x kNumPoints)
};

/**
 * \brief Velocities and accelerations of every dependent variable and requested point.
 * \param[in]  state   A valid configuration (state.valid); otherwise *motion is all NaN.
 * \param[in]  qd      Input speeds (dim kNq).
 * \param[in]  qdd     Input accelerations (dim kNq).
 * \param[out] motion  Not nullptr.
 */
template <class M>
void ComputeMotion(const State<M>& state,
                   const typename ModelTypes<M>::VecQ& qd,
                   const typename ModelTypes<M>::VecQ& qdd,
                   Motion<M>* motion) {
  using T = ModelTypes<M>;
  // The sizes: the model's (for a ViewModel, the state's, which State(model) set).
  const int nq = static_cast<int>(state.q.size()), np = static_cast<int>(state.r_P.cols());
  if (!state.valid) {
    *motion = Motion<M>(nq, static_cast<int>(state.phi.size()), np);
    motion->qd = qd;
    motion->qdd = qdd;
    return;
  }
  // Every member is written below (v_P and a_P NaN where the model lacks them): *motion is not
  // set to NaN first (for the view that would be six more bounded matrices filled and copied).
  Assign(&motion->qd, qd);
  Assign(&motion->qdd, qdd);
  auto qd_qd = Sized<typename T::VecQQ>(nq * nq);  // (qd (x) qd)(j + kNq k) = qd_j qd_k
  for (int k = 0; k < nq; ++k) qd_qd.segment(nq * k, nq) = qd * qd(k);
  // (Times: for the view the coefficient-based products the fixed sizes get, not Eigen's
  // general matrix-vector kernel, which costs more than the products at these sizes.)
  motion->phid = Times(state.K, qd);
  motion->phidd = Times(state.K, qdd) + Times(state.L, qd_qd);
  // (A view's state without K_P or L_P holds NaN there: its v_P, a_P stay NaN.)
  constexpr int kRows = M::kNumPoints == Eigen::Dynamic ? Eigen::Dynamic : 2 * M::kNumPoints;
  using VecP = Eigen::Matrix<double, kRows, 1, 0, kRows == Eigen::Dynamic ? 2 * T::kMaxPoints : kRows, 1>;
  if constexpr (ModelFeatures<M>::kHasPointVelocities) {
    const VecP v = Times(state.K_P, qd);
    motion->v_P = Eigen::Map<const typename T::MatRP>(v.data(), 2, np);  // v(2m + a) -> (a, m)
  } else {
    motion->v_P = NaNs<typename T::MatRP>();
  }
  if constexpr (ModelFeatures<M>::kHasPointAccelerations) {
    const VecP a = Times(state.K_P, qdd) + Times(state.L_P, qd_qd);
    motion->a_P = Eigen::Map<const typename T::MatRP>(a.data(), 2, np);
  } else {
    motion->a_P = NaNs<typename T::MatRP>();
  }
}

}  // namespace mechgen::position
