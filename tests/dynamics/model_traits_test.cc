// core/model_traits.h: the model's fixed-size types in a second scalar type (long double, as
// a ceres::Jet run would use them), and the named traits of what a model has.
//
// Oracles: the positions and velocity coefficients solved in long double through
// ModelTypes<M, long double> agree with the double ones to double precision, and K agrees
// with central differences of the long double positions (an independent derivative); the
// named traits agree with the flags the generator wrote (kHasShaking, kHasDynamics) and with
// the functions each generated header declares (read off the committed headers).
#include <cmath>
#include <type_traits>

#include <gtest/gtest.h>

#include "engine_single.h"
#include "fivebar_robot.h"
#include "fourbar.h"
#include "fourbar_massive.h"
#include "mechgen/core/model_traits.h"

namespace {

using mechgen::ModelFeatures;
using mechgen::ModelTypes;

template <class M, class Scalar>
bool SolveAndCoefficients(const typename ModelTypes<M, Scalar>::VecQ& q,
                          typename ModelTypes<M, Scalar>::VecPhi* phi,
                          typename ModelTypes<M, Scalar>::Coefficients* c) {
  using T = ModelTypes<M, Scalar>;
  const typename T::Params p;
  for (int i = 0; i < T::kNphi; ++i) (*phi)(i) = static_cast<Scalar>(M::kAssemblyPhi[i]);
  const auto report = M::template Solve<Scalar>(p, q, phi, M::kDefaultModes, 50, Scalar(0));
  if (report.status != decltype(report.status)::kConverged) return false;
  if (c != nullptr) M::template Coeffs<Scalar>(p, q, *phi, c);
  return true;
}

TEST(ModelTraits, TypesInLongDoubleSolveAsInDouble) {
  using M = mech::fourbar_massive::Model;
  using TL = ModelTypes<M, long double>;
  using TD = ModelTypes<M>;
  static_assert(std::is_same_v<TL::ScalarType, long double>);
  static_assert(std::is_same_v<TD::ScalarType, double>);
  static_assert(std::is_same_v<TL::Params, M::ParamsT<long double>>);
  static_assert(std::is_same_v<TL::MatK, Eigen::Matrix<long double, M::kNphi, M::kNq>>);
  static_assert(ModelFeatures<M, long double>::kHasSolve && ModelFeatures<M, long double>::kHasTrig);
  static_assert(ModelFeatures<M, long double>::kHasK && ModelFeatures<M, long double>::kHasL);
  static_assert(ModelFeatures<M, float>::kHasSolve);
  for (double angle : {0.3, 1.0, 2.5, 4.0}) {
    SCOPED_TRACE(angle);
    TL::VecQ qL;
    qL(0) = angle;
    TL::VecPhi phiL;
    TL::Coefficients cL;
    ASSERT_TRUE((SolveAndCoefficients<M, long double>(qL, &phiL, &cL)));
    TD::VecQ qD;
    qD(0) = angle;
    TD::VecPhi phiD;
    TD::Coefficients cD;
    ASSERT_TRUE((SolveAndCoefficients<M, double>(qD, &phiD, &cD)));
    for (int i = 0; i < M::kNphi; ++i) {
      EXPECT_NEAR(static_cast<double>(phiL(i)), phiD(i), 1e-13);
      EXPECT_NEAR(static_cast<double>(cL.K(i, 0)), cD.K(i, 0), 1e-12 * (1 + std::abs(cD.K(i, 0))));
    }
    // K = dphi/dq by central differences of the long double positions.
    const long double h = 1e-6L;
    TL::VecQ qp = qL, qm = qL;
    qp(0) += h;
    qm(0) -= h;
    TL::VecPhi phip, phim;
    ASSERT_TRUE((SolveAndCoefficients<M, long double>(qp, &phip, nullptr)));
    ASSERT_TRUE((SolveAndCoefficients<M, long double>(qm, &phim, nullptr)));
    for (int i = 0; i < M::kNphi; ++i) {
      const long double fd = (phip(i) - phim(i)) / (2 * h);
      EXPECT_NEAR(static_cast<double>(cL.K(i, 0)), static_cast<double>(fd), 1e-9);
    }
  }
}

TEST(ModelTraits, NamedTraitsAgreeWithTheGeneratedHeaders) {
  using mechgen::HasDynamics;
  using mechgen::HasExcess;
  using mechgen::HasKinematics;
  using mechgen::HasRhs;
  using mechgen::HasShaking;
  using mechgen::HasSolveTrig;
  using mechgen::HasStatics;
  using Fourbar = mech::fourbar::Model;
  using Massive = mech::fourbar_massive::Model;
  using Robot = mech::fivebar_robot::Model;
  using Engine = mech::engine_single::Model;
  // The generator's own flags.
  static_assert(HasShaking<Massive>::value == Massive::kHasShaking);
  static_assert(HasShaking<Robot>::value == Robot::kHasShaking);
  static_assert(HasShaking<Engine>::value == Engine::kHasShaking);
  static_assert(HasShaking<Fourbar>::value == Fourbar::kHasShaking);
  static_assert(HasDynamics<Massive>::value == Massive::kHasDynamics);
  static_assert(HasDynamics<Robot>::value == Robot::kHasDynamics);
  static_assert(HasDynamics<Engine>::value == Engine::kHasDynamics);
  // What the committed headers declare (generated/<model>.h): a kinematic four-bar has no
  // dynamics, statics, excess or one-pass Rhs; the engine (slides: not every block a closed
  // form of angles) has no SolveTrig and no Rhs.
  static_assert(!HasDynamics<Fourbar>::value && !HasStatics<Fourbar>::value);
  static_assert(!HasExcess<Fourbar>::value && !HasRhs<Fourbar>::value);
  static_assert(HasSolveTrig<Fourbar>::value);
  static_assert(HasStatics<Massive>::value && HasExcess<Massive>::value && HasRhs<Massive>::value);
  static_assert(HasSolveTrig<Massive>::value);
  static_assert(HasStatics<Robot>::value && HasRhs<Robot>::value && HasSolveTrig<Robot>::value);
  static_assert(HasStatics<Engine>::value && HasExcess<Engine>::value);
  static_assert(!HasRhs<Engine>::value && !HasSolveTrig<Engine>::value);
  // The one-pass kinematics: wherever SolveTrig exists and the model asks for K (the kinematic
  // four-bar too, which has no Rhs).
  static_assert(HasKinematics<Fourbar>::value && HasKinematics<Massive>::value && HasKinematics<Robot>::value);
  static_assert(!HasKinematics<Engine>::value && HasKinematics<Engine>::value == Engine::kHasKinematics);
  SUCCEED();
}

}  // namespace
