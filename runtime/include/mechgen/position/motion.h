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

#include "mechgen/core/model_traits.h"
#include "mechgen/position/state.h"

namespace mechgen::position {

/// Time derivatives at one configuration. All members start as NaN.
template <class M>
struct Motion {
  using T = ModelTypes<M>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  typename T::VecQ qd = T::VecQ::Constant(kNaN);         ///< input speeds (kNq)
  typename T::VecQ qdd = T::VecQ::Constant(kNaN);        ///< input accelerations (kNq)
  typename T::VecPhi phid = T::VecPhi::Constant(kNaN);   ///< K qd (kNphi)
  typename T::VecPhi phidd = T::VecPhi::Constant(kNaN);  ///< K qdd + L qd qd (kNphi)
  typename T::MatRP v_P = T::MatRP::Constant(kNaN);      ///< point velocities (2 x kNumPoints)
  typename T::MatRP a_P = T::MatRP::Constant(kNaN);      ///< accelerations (2 x kNumPoints)
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
  *motion = Motion<M>();
  motion->qd = qd;
  motion->qdd = qdd;
  if (!state.valid) return;
  typename T::VecQQ qd_qd;  // (qd (x) qd)(j + kNq k) = qd_j qd_k
  for (int k = 0; k < M::kNq; ++k) qd_qd.segment(M::kNq * k, M::kNq) = qd * qd(k);
  motion->phid = state.K * qd;
  motion->phidd = state.K * qdd + state.L * qd_qd;
  if constexpr (ModelFeatures<M>::kHasPointVelocities) {
    const Eigen::Matrix<double, 2 * M::kNumPoints, 1> v = state.K_P * qd;
    motion->v_P = Eigen::Map<const typename T::MatRP>(v.data());  // v(2m + a) -> (a, m)
  }
  if constexpr (ModelFeatures<M>::kHasPointAccelerations) {
    const Eigen::Matrix<double, 2 * M::kNumPoints, 1> a = state.K_P * qdd + state.L_P * qd_qd;
    motion->a_P = Eigen::Map<const typename T::MatRP>(a.data());
  }
}

}  // namespace mechgen::position
