// The Jet oracle of the design tests: the generated values code of a model with a design
// section, instantiated with ceres::Jet and seeded on its design parameters, gives the
// derivatives the generated EvalDesignDerivatives, EvalStaticsDesign and EvalDynamicsDesign
// must equal (forward-mode automatic differentiation, independent of the symbolic ones).
#pragma once

#include <ceres/jet.h>

#include <Eigen/Core>
#include <Eigen/LU>

namespace designtest {

/// The model's parameters as Jets seeded on its design parameters (dimension d of the Jet
/// for kDesignNames[d]); the others constant.
template <class M, class Jet>
typename M::template ParamsT<Jet> SeededParams(const typename M::template ParamsT<double>& p) {
  auto pj = p.template Cast<Jet>();
  auto pd = p;
  for (int d = 0; d < M::kNumDesign; ++d) *pj.Find(M::kDesignNames[d]) = Jet(*pd.Find(M::kDesignNames[d]), d);
  return pj;
}

/// dphi/dp = -Phi_phi^-1 Phi_p at a closed configuration, Phi_phi and Phi_p from Jets of the
/// generated EvalPhi seeded on (p_design, phi).
template <class M>
Eigen::Matrix<double, M::kNphi, M::kNumDesign> JetDphiDp(const typename M::template ParamsT<double>& p,
                                                          const Eigen::Matrix<double, M::kNq, 1>& q,
                                                          const Eigen::Matrix<double, M::kNphi, 1>& phi) {
  constexpr int kNd = M::kNumDesign, kNphi = M::kNphi;
  using J = ceres::Jet<double, kNd + kNphi>;
  const auto pj = SeededParams<M, J>(p);
  const Eigen::Matrix<J, M::kNq, 1> qj = q.template cast<J>();
  Eigen::Matrix<J, kNphi, 1> phij;
  for (int i = 0; i < kNphi; ++i) phij(i) = J(phi(i), kNd + i);
  Eigen::Matrix<J, M::kNc, 1> Phij;
  M::Phi(pj, qj, phij, &Phij);
  Eigen::Matrix<double, M::kNc, kNd> Phi_p;
  Eigen::Matrix<double, M::kNc, kNphi> Phi_phi;
  for (int r = 0; r < M::kNc; ++r) {
    Phi_p.row(r) = Phij(r).v.template head<kNd>().transpose();
    Phi_phi.row(r) = Phij(r).v.template tail<kNphi>().transpose();
  }
  return -Phi_phi.fullPivLu().solve(Phi_p);
}

/// phi as Jets carrying dphi/dp (first order in the design parameters).
template <class M, class Jet>
Eigen::Matrix<Jet, M::kNphi, 1> PhiJets(const Eigen::Matrix<double, M::kNphi, 1>& phi,
                                       const Eigen::Matrix<double, M::kNphi, M::kNumDesign>& dphi_dp) {
  Eigen::Matrix<Jet, M::kNphi, 1> out;
  for (int i = 0; i < M::kNphi; ++i) {
    out(i) = Jet(phi(i));
    out(i).v = dphi_dp.row(i).transpose();
  }
  return out;
}

}  // namespace designtest
