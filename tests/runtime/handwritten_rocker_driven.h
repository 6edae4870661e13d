/**
 * \file handwritten_rocker_driven.h
 * The four-bar of handwritten_fourbar.h driven by its rocker instead of its crank, written by
 * hand in the shape of a generated header (namespace mech::handwritten_rocker_driven).
 *
 * It exercises the parts of the runtime that the crank-driven model does not: the rocker of
 * a crank-rocker only swings between two toggle positions, so inputs outside
 * th3 in [acos(-0.78125), acos(-0.197917)] = [101.4 deg, 141.4 deg] (upper mode) cannot be
 * assembled; the model has order 1 (K only, so the runtime computes L itself) and requests
 * no points and no scene.
 *   q = theta_rocker, phi = (theta_crank, theta_coupler);
 *   Phi(0) = a cos th1 + b cos th2 - d - c cos q,  Phi(1) = a sin th1 + b sin th2 - c sin q.
 */
#pragma once

#include <array>
#include <cstring>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/LU>

namespace mech::handwritten_rocker_driven {

struct Sizes {
  static constexpr int kNq = 1;
  static constexpr int kNphi = 2;
  static constexpr int kNc = 2;
  static constexpr int kNumLoops = 1;
  static constexpr int kMobility = 1;
  static constexpr int kOrder = 1;
  static constexpr int kNumPoints = 0;
  static constexpr int kNumLinks = 4;
  static constexpr int kNumScenePoints = 0;
};

template <typename Scalar = double>
struct Params {
  Scalar a = Scalar(1.0);
  Scalar b = Scalar(3.5);
  Scalar c = Scalar(3.0);
  Scalar d = Scalar(4.0);

  template <typename T>
  Params<T> Cast() const {
    Params<T> p;
    p.a = T(a);
    p.b = T(b);
    p.c = T(c);
    p.d = T(d);
    return p;
  }

  /// By name, as the generated Params (the tools' --set and --params).
  Scalar* Find(const char* name) {
    if (std::strcmp(name, "a") == 0) return &a;
    if (std::strcmp(name, "b") == 0) return &b;
    if (std::strcmp(name, "c") == 0) return &c;
    if (std::strcmp(name, "d") == 0) return &d;
    return nullptr;
  }
  static constexpr std::array<const char*, 4> kNames{ "a", "b", "c", "d" };
  static constexpr std::array<const char*, 0> kDerivedNames{};
};

template <typename Scalar, int R, int C>
using Mat = Eigen::Matrix<Scalar, R, C>;
template <typename Scalar, int R>
using Vec = Eigen::Matrix<Scalar, R, 1>;

template <typename Scalar = double>
struct Coefficients {
  Mat<Scalar, Sizes::kNphi, Sizes::kNq> K;
};

template <typename Scalar>
void EvalPhi(const Params<Scalar>& p,
             const Vec<Scalar, Sizes::kNq>& q,
             const Vec<Scalar, Sizes::kNphi>& phi,
             Vec<Scalar, Sizes::kNc>* Phi,
             Mat<Scalar, Sizes::kNc, Sizes::kNphi>* Phi_phi = nullptr,
             Mat<Scalar, Sizes::kNc, Sizes::kNq>* Phi_q = nullptr) {
  using std::cos;
  using std::sin;
  const Scalar S3 = sin(q(0)), C3 = cos(q(0));
  const Scalar S1 = sin(phi(0)), C1 = cos(phi(0));
  const Scalar S2 = sin(phi(1)), C2 = cos(phi(1));
  if (Phi != nullptr) {
    (*Phi)(0) = p.a * C1 + p.b * C2 - p.d - p.c * C3;
    (*Phi)(1) = p.a * S1 + p.b * S2 - p.c * S3;
  }
  if (Phi_phi != nullptr) {
    *Phi_phi << -p.a * S1, -p.b * S2, p.a * C1, p.b * C2;
  }
  if (Phi_q != nullptr) {
    *Phi_q << p.c * S3, -p.c * C3;
  }
}

template <typename Scalar>
void EvalCoefficients(const Params<Scalar>& p,
                      const Vec<Scalar, Sizes::kNq>& q,
                      const Vec<Scalar, Sizes::kNphi>& phi,
                      Coefficients<Scalar>* out) {
  Mat<Scalar, 2, 2> Phi_phi;
  Mat<Scalar, 2, 1> Phi_q;
  EvalPhi<Scalar>(p, q, phi, nullptr, &Phi_phi, &Phi_q);
  out->K = -Phi_phi.inverse() * Phi_q;
}

struct Model : Sizes {
  static constexpr const char* kName = "handwritten_rocker_driven";
  // Output flags (core/model_traits.h reads them; the same as a generated header):
  // positions and coefficients only.
  static constexpr bool kHasStatics = false;
  static constexpr bool kHasStaticsQ = false;
  static constexpr bool kHasStaticsStiffness = false;
  static constexpr bool kHasStaticsV = false;
  static constexpr bool kHasStaticsD2V = false;
  static constexpr bool kHasStaticsR = false;
  static constexpr bool kHasStaticsFriction = false;
  static constexpr bool kHasDynamics = false;
  static constexpr bool kHasExcess = false;
  static constexpr bool kHasShaking = false;
  static constexpr bool kHasKinematics = false;
  static constexpr bool kHasRhs = false;
  static constexpr bool kHasRhsConstants = false;
  static constexpr bool kHasDesignDerivatives = false;
  static constexpr bool kHasStaticsDesign = false;
  static constexpr bool kHasDynamicsDesign = false;
  // What else it has (core/model_traits.h reads these too): Coefficients with K only; no Solve, no drawing.
  static constexpr bool kHasCoeffsPhi = false;
  static constexpr bool kHasK = true;
  static constexpr bool kHasL = false;
  static constexpr bool kHasPoints = false;
  static constexpr bool kHasPointVelocities = false;
  static constexpr bool kHasPointAccelerations = false;
  static constexpr bool kHasSolve = false;
  static constexpr bool kHasNamedModes = false;
  static constexpr bool kHasTrig = false;
  static constexpr bool kHasSolveTrig = false;
  static constexpr bool kHasTransmissionAngles = false;
  static constexpr bool kHasSwitchModes = false;
  static constexpr bool kHasDrawing = false;
  static constexpr bool kHasCamProfile = false;
  static constexpr bool kHasAppliedLoads = false;
  static constexpr std::array<const char*, kNq> kQNames{"theta_rocker"};
  static constexpr std::array<const char*, kNphi> kPhiNames{"theta_crank", "theta_coupler"};
  static constexpr std::array<bool, kNq> kQIsAngle{true};
  static constexpr std::array<bool, kNphi> kPhiIsAngle{true, true};
  static constexpr std::array<const char*, kNumPoints> kPointNames{};
  static constexpr std::array<const char*, kNumLinks> kLinkNames{"ground", "crank", "coupler",
                                                                "rocker"};
  static constexpr int kGroundLink = 0;
  static constexpr std::array<const char*, kNumScenePoints> kScenePointNames{};
  static constexpr std::array<int, kNumScenePoints> kScenePointLink{};
  /// th3 = 120 deg; B below the x axis (th1 ~ -30 deg, th2 ~ 62 deg).
  static constexpr std::array<double, kNq> kAssemblyQ{2.0943951023931953};
  static constexpr std::array<double, kNphi> kAssemblyPhi{-0.5, 1.1};
  static constexpr std::array<double, kNq> kQMin{1.8};
  static constexpr std::array<double, kNq> kQMax{2.45};

  template <typename Scalar>
  using ParamsT = mech::handwritten_rocker_driven::Params<Scalar>;
  template <typename Scalar>
  using CoefficientsT = mech::handwritten_rocker_driven::Coefficients<Scalar>;

  template <typename Scalar>
  static void Phi(const Params<Scalar>& p,
                  const Vec<Scalar, kNq>& q,
                  const Vec<Scalar, kNphi>& phi,
                  Vec<Scalar, kNc>* Phi,
                  Mat<Scalar, kNc, kNphi>* Phi_phi = nullptr,
                  Mat<Scalar, kNc, kNq>* Phi_q = nullptr) {
    EvalPhi(p, q, phi, Phi, Phi_phi, Phi_q);
  }
  template <typename Scalar>
  static void Coeffs(const Params<Scalar>& p,
                     const Vec<Scalar, kNq>& q,
                     const Vec<Scalar, kNphi>& phi,
                     Coefficients<Scalar>* out) {
    EvalCoefficients(p, q, phi, out);
  }
};

}  // namespace mech::handwritten_rocker_driven
