// Helpers shared by the runtime tests: sweeping a model and measuring what a sweep must
// preserve (loop closure, rigid link lengths, continuity of the branch).
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen::position::testing {

template <class M>
using VecQ = typename ModelTypes<M>::VecQ;
template <class M>
using VecPhi = typename ModelTypes<M>::VecPhi;

template <class M>
VecQ<M> QMin() {
  return Eigen::Map<const VecQ<M>>(M::kQMin.data());
}
template <class M>
VecQ<M> QMax() {
  return Eigen::Map<const VecQ<M>>(M::kQMax.data());
}

/// ||Phi(q, phi)||_inf, evaluated independently of the solver.
template <class M>
double ResidualNorm(const typename ModelTypes<M>::Params& p, const VecQ<M>& q,
                    const VecPhi<M>& phi) {
  typename ModelTypes<M>::VecC Phi;
  M::template Phi<double>(p, q, phi, &Phi, nullptr, nullptr);
  return Phi.template lpNorm<Eigen::Infinity>();
}

/// Largest change, over the sweep, of the distance between two scene points of one link
/// (a rigid link keeps all of them), relative to the first row.
template <class M>
double MaxLinkLengthChange(const typename ModelTypes<M>::Params& p,
                           const std::vector<SweepRecord<M>>& records) {
  static_assert(M::kNumScenePoints > 0);
  using Scene = typename ModelTypes<M>::MatScene;
  Scene first;
  M::template Scene<double>(p, records.front().state.q, records.front().state.phi, &first);
  double worst = 0;
  for (const auto& r : records) {
    Scene scene;
    M::template Scene<double>(p, r.state.q, r.state.phi, &scene);
    for (int i = 0; i < M::kNumScenePoints; ++i)
      for (int j = i + 1; j < M::kNumScenePoints; ++j) {
        if (M::kScenePointLink[i] != M::kScenePointLink[j]) continue;
        const double d0 = (first.col(i) - first.col(j)).norm();
        const double d = (scene.col(i) - scene.col(j)).norm();
        worst = std::max(worst, std::abs(d - d0));
      }
  }
  return worst;
}

/// Largest |phi_{k+1} - (phi_k + K dq + 1/2 L (dq, dq))|_inf over consecutive rows: the
/// error of the second-order Taylor prediction, O(dq^3) on one branch, O(1) after a jump.
template <class M>
double MaxTaylorDefect(const std::vector<SweepRecord<M>>& records) {
  double worst = 0;
  for (size_t k = 0; k + 1 < records.size(); ++k) {
    const State<M>& a = records[k].state;
    const State<M>& b = records[k + 1].state;
    const VecQ<M> dq = b.q - a.q;
    typename ModelTypes<M>::VecQQ dq_dq;
    for (int j = 0; j < M::kNq; ++j) dq_dq.segment(M::kNq * j, M::kNq) = dq * dq(j);
    const VecPhi<M> predicted = a.phi + a.K * dq + 0.5 * a.L * dq_dq;
    worst = std::max(worst, (b.phi - predicted).template lpNorm<Eigen::Infinity>());
  }
  return worst;
}

// M with its coefficients cut down to Phi and Phi_phi (what `outputs: order: 0` without
// points generates): the solver forms K and L itself. With Model::TrigT it evaluates
// Model::Coeffs in dual numbers seeded with the sin and cos of M::Solve
// (position/internal/coefficients.h, PhiDerivatives::kFromTrig); trig_calls counts those.
template <class M>
struct PositionsOnly : M {
  static constexpr bool kHasK = false;
  static constexpr bool kHasL = false;
  static constexpr bool kHasPoints = false;
  static constexpr bool kHasPointVelocities = false;
  static constexpr bool kHasPointAccelerations = false;
  static inline int trig_calls = 0;
  template <typename Scalar>
  struct CoefficientsT {
    Eigen::Matrix<Scalar, M::kNc, 1> Phi;
    Eigen::Matrix<Scalar, M::kNc, M::kNphi> Phi_phi;
  };
  template <typename Scalar>
  static void Coeffs(const typename M::template ParamsT<Scalar>& p,
                     const Eigen::Matrix<Scalar, M::kNq, 1>& q,
                     const Eigen::Matrix<Scalar, M::kNphi, 1>& phi, CoefficientsT<Scalar>* out,
                     const typename M::template TrigT<Scalar>* trig = nullptr) {
    if (trig != nullptr) ++trig_calls;
    typename M::template CoefficientsT<Scalar> c;
    M::template Coeffs<Scalar>(p, q, phi, &c, trig);
    out->Phi = c.Phi;
    out->Phi_phi = c.Phi_phi;
  }
};

}  // namespace mechgen::position::testing
