// Phi_phi = dPhi/dphi and Phi_q = dPhi/dq of every shipped model against (1) central
// differences of the generated Phi and (2) ceres::Jet forward-mode autodiff through the
// templated EvalPhi. (2) also proves that the generated header compiles for Jet scalars
// (no std::-qualified math calls, no double-only literals in the way).
//
// The Jacobians are checked at random (q, phi) -- not only closed configurations, since
// EvalPhi is defined everywhere -- drawn with a fixed seed: angles uniform in [-pi, pi],
// displacements uniform in [0.5, 4] (the scale of the shipped models).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

using mechtest::kPi;
using mechtest::ParamsD;
using mechtest::VecPhi;
using mechtest::VecQ;

constexpr int kNumPoints = 1000;
constexpr unsigned kSeed = 42;

// Central differences of Phi, h = 1e-5: Phi is a sum of O(5) terms a*cos(.), so rounding
// is ~eps * 5 / h ~ 1e-10 and truncation h^2/6 * 5 ~ 1e-10. kFdTol = 1e-8 absolute (entries
// are O(1..4)) leaves two orders of margin; a wrong entry is off by O(0.1) or more.
constexpr double kH = 1e-5;
constexpr double kFdTol = 1e-8;
// Jet derivatives are the analytic derivatives evaluated in double: agreement to rounding.
// A handful of flops on O(4) values: 1e-14 absolute is ~20 ulps of 4.
constexpr double kJetTol = 1e-14;

template <class M>
struct RandomState {
  VecQ<M> q;
  VecPhi<M> phi;
};

template <class M>
std::vector<RandomState<M>> RandomStates() {
  std::mt19937 gen(kSeed);
  std::uniform_real_distribution<double> angle(-kPi, kPi), length(0.5, 4.0);
  std::vector<RandomState<M>> out(kNumPoints);
  for (auto& s : out) {
    for (int j = 0; j < M::kNq; ++j) s.q(j) = M::kQIsAngle[j] ? angle(gen) : length(gen);
    for (int i = 0; i < M::kNphi; ++i) s.phi(i) = M::kPhiIsAngle[i] ? angle(gen) : length(gen);
  }
  return out;
}

template <class M>
class ConstraintJacobianTest : public ::testing::Test {
 protected:
  using PhiVec = Eigen::Matrix<double, M::kNc, 1>;
  using PhiPhiMat = Eigen::Matrix<double, M::kNc, M::kNphi>;
  using PhiQMat = Eigen::Matrix<double, M::kNc, M::kNq>;
  ParamsD<M> p_;
  PhiVec PhiAt(const VecQ<M>& q, const VecPhi<M>& phi) const {
    PhiVec r;
    M::Phi(p_, q, phi, &r);
    return r;
  }
};
TYPED_TEST_SUITE(ConstraintJacobianTest, mechtest::AllModels, mechtest::ModelNames);

TYPED_TEST(ConstraintJacobianTest, PhiPhiAndPhiQMatchCentralDifferencesOfPhi) {
  using M = TypeParam;
  for (const auto& s : RandomStates<M>()) {
    typename TestFixture::PhiVec Phi;
    typename TestFixture::PhiPhiMat Phi_phi;
    typename TestFixture::PhiQMat Phi_q;
    M::Phi(this->p_, s.q, s.phi, &Phi, &Phi_phi, &Phi_q);
    for (int i = 0; i < M::kNphi; ++i) {
      VecPhi<M> pp = s.phi, pm = s.phi;
      pp(i) += kH;
      pm(i) -= kH;
      const auto fd = ((this->PhiAt(s.q, pp) - this->PhiAt(s.q, pm)) / (2 * kH)).eval();
      for (int r = 0; r < M::kNc; ++r) {
        EXPECT_NEAR(Phi_phi(r, i), fd(r), kFdTol)
            << "Phi_phi(" << r << ", " << M::kPhiNames[i] << ") at q = " << s.q.transpose()
            << ", phi = " << s.phi.transpose();
      }
    }
    for (int j = 0; j < M::kNq; ++j) {
      VecQ<M> qp = s.q, qm = s.q;
      qp(j) += kH;
      qm(j) -= kH;
      const auto fd = ((this->PhiAt(qp, s.phi) - this->PhiAt(qm, s.phi)) / (2 * kH)).eval();
      for (int r = 0; r < M::kNc; ++r) {
        EXPECT_NEAR(Phi_q(r, j), fd(r), kFdTol)
            << "Phi_q(" << r << ", " << M::kQNames[j] << ") at q = " << s.q.transpose()
            << ", phi = " << s.phi.transpose();
      }
    }
  }
}

// Leaving optional outputs null must not change the others.
TYPED_TEST(ConstraintJacobianTest, OptionalOutputsAreIndependent) {
  using M = TypeParam;
  for (const auto& s : RandomStates<M>()) {
    typename TestFixture::PhiVec Phi_all, Phi_only;
    typename TestFixture::PhiPhiMat Phi_phi_all, Phi_phi_only;
    typename TestFixture::PhiQMat Phi_q_all, Phi_q_only;
    M::Phi(this->p_, s.q, s.phi, &Phi_all, &Phi_phi_all, &Phi_q_all);
    M::Phi(this->p_, s.q, s.phi, &Phi_only);
    // Typed null pointers: a bare nullptr cannot deduce Scalar for the Phi parameter.
    using PhiVec = typename TestFixture::PhiVec;
    using PhiPhiMat = typename TestFixture::PhiPhiMat;
    M::Phi(this->p_, s.q, s.phi, static_cast<PhiVec*>(nullptr), &Phi_phi_only);
    M::Phi(this->p_, s.q, s.phi, static_cast<PhiVec*>(nullptr), static_cast<PhiPhiMat*>(nullptr),
           &Phi_q_only);
    EXPECT_EQ(Phi_all, Phi_only);
    EXPECT_EQ(Phi_phi_all, Phi_phi_only);
    EXPECT_EQ(Phi_q_all, Phi_q_only);
  }
}

// EvalCoefficients hands out the Phi and Phi_phi it evaluates (the runtime checks closure
// and conditioning with them instead of a second EvalPhi): the same values as EvalPhi's,
// to rounding (the two functions share subexpressions differently).
TYPED_TEST(ConstraintJacobianTest, CoefficientsCarryEvalPhisResidualAndJacobian) {
  using M = TypeParam;
  for (const auto& s : RandomStates<M>()) {
    typename TestFixture::PhiVec Phi;
    typename TestFixture::PhiPhiMat Phi_phi;
    M::Phi(this->p_, s.q, s.phi, &Phi, &Phi_phi);
    typename M::template CoefficientsT<double> c;
    c.Phi.setConstant(NAN);
    c.Phi_phi.setConstant(NAN);
    M::Coeffs(this->p_, s.q, s.phi, &c);
    for (int r = 0; r < M::kNc; ++r) {
      EXPECT_NEAR(c.Phi(r), Phi(r), kJetTol) << "Phi(" << r << ")";
      for (int i = 0; i < M::kNphi; ++i) {
        EXPECT_NEAR(c.Phi_phi(r, i), Phi_phi(r, i), kJetTol)
            << "Phi_phi(" << r << ", " << M::kPhiNames[i] << ")";
      }
    }
  }
}

// EvalDetPhiPhi (a product of block determinants, with the sign of the block permutation)
// is the determinant of the full Phi_phi, including its sign.
TYPED_TEST(ConstraintJacobianTest, DetPhiPhiIsTheDeterminantOfPhiPhi) {
  using M = TypeParam;
  for (const auto& s : RandomStates<M>()) {
    typename TestFixture::PhiPhiMat Phi_phi;
    M::Phi(this->p_, s.q, s.phi, static_cast<typename TestFixture::PhiVec*>(nullptr), &Phi_phi);
    const double ref = Phi_phi.determinant();
    double det = NAN;
    M::DetPhiPhi(this->p_, s.q, s.phi, &det);
    // Entries are O(4): the 2x2 (or block) determinant is exact to ~1e-15 * 16.
    EXPECT_NEAR(det, ref, 1e-13 * std::max(1.0, std::abs(ref)))
        << "at q = " << s.q.transpose() << ", phi = " << s.phi.transpose();
  }
}

TYPED_TEST(ConstraintJacobianTest, PhiPhiAndPhiQMatchJetAutodiff) {
  using M = TypeParam;
  constexpr int kN = M::kNq + M::kNphi;
  using Jet = ceres::Jet<double, kN>;
  const auto pj = this->p_.template Cast<Jet>();
  for (const auto& s : RandomStates<M>()) {
    Eigen::Matrix<Jet, M::kNq, 1> qj;
    Eigen::Matrix<Jet, M::kNphi, 1> phij;
    for (int j = 0; j < M::kNq; ++j) qj(j) = Jet(s.q(j), j);
    for (int i = 0; i < M::kNphi; ++i) phij(i) = Jet(s.phi(i), M::kNq + i);
    Eigen::Matrix<Jet, M::kNc, 1> Phij;
    M::Phi(pj, qj, phij, &Phij);

    typename TestFixture::PhiVec Phi;
    typename TestFixture::PhiPhiMat Phi_phi;
    typename TestFixture::PhiQMat Phi_q;
    M::Phi(this->p_, s.q, s.phi, &Phi, &Phi_phi, &Phi_q);
    for (int r = 0; r < M::kNc; ++r) {
      EXPECT_NEAR(Phij(r).a, Phi(r), kJetTol);
      for (int j = 0; j < M::kNq; ++j) {
        EXPECT_NEAR(Phi_q(r, j), Phij(r).v(j), kJetTol)
            << "Phi_q(" << r << ", " << M::kQNames[j] << ")";
      }
      for (int i = 0; i < M::kNphi; ++i) {
        EXPECT_NEAR(Phi_phi(r, i), Phij(r).v(M::kNq + i), kJetTol)
            << "Phi_phi(" << r << ", " << M::kPhiNames[i] << ")";
      }
    }
  }
}

}  // namespace
