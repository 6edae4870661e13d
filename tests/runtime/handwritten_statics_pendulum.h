/**
 * \file handwritten_statics_pendulum.h
 * A pendulum with a torsional spring at its pivot under gravity, written by hand in the
 * shape of a generated header with `forces` and `potential` (namespace
 * mech::handwritten_statics_pendulum): the oracle of the equilibrium tests
 * (statics_equilibrium_test.cc). No friction and no friction argument, no Coefficients::Phi:
 * the other branches of the runtime's traits.
 *
 * The link turns about O = (0, 0) at q = theta_pendulum (from +x, CCW); its tip P = l (cos q,
 * sin q) runs in a cross slide whose two slides x_P, y_P are the dependent variables
 * (Phi = (l cos q - x_P, l sin q - y_P), Phi_phi = -I), so that the model has the kNphi = 2 of
 * a linkage. Mass m with its centre at distance lc from O; gravity g along -y; a torsional
 * spring of stiffness k at O with free angle q0: torque on the pendulum -k (q - q0).
 *   V = m g lc sin q + k (q - q0)^2 / 2,
 *   Q = -dV/dq = -m g lc cos q - k (q - q0),  stiffness = d2V/dq2 = k - m g lc sin q.
 * Reaction at O (force of the ground on the pendulum): the weight's opposite (0, m g), since
 * the drive and the spring are couples and the slides carry no force.
 * With the defaults (m g lc = 4.905 N m, k = 0.5 N m/rad, q0 = 0) it has three equilibria
 * in [-pi, 2 pi]: near -1.47 (stable), 1.67 (unstable), 4.6 rad (stable).
 */
#pragma once

#include <array>
#include <cstring>
#include <cmath>

#include <Eigen/Core>

namespace mech::handwritten_statics_pendulum {

struct Sizes {
  static constexpr int kNq = 1;
  static constexpr int kNphi = 2;
  static constexpr int kNc = 2;
  static constexpr int kNumLoops = 1;
  static constexpr int kMobility = 1;
  static constexpr int kOrder = 2;
  static constexpr int kNumPoints = 0;
  static constexpr int kNumLinks = 2;
  static constexpr int kNumScenePoints = 3;
  static constexpr int kNumReactions = 2;
};

template <typename Scalar = double>
struct Params {
  Scalar l = Scalar(1.0);    ///< pivot to tip (m)
  Scalar lc = Scalar(0.5);   ///< pivot to centre of mass (m)
  Scalar m = Scalar(1.0);    ///< mass (kg)
  Scalar g = Scalar(9.81);   ///< gravity along -y (m/s^2)
  Scalar k = Scalar(0.5);    ///< torsional spring at O (N m/rad)
  Scalar q0 = Scalar(0.0);   ///< its free angle (rad)

  /// By name, as the generated Params (the tools' --set and --params).
  Scalar* Find(const char* name) {
    if (std::strcmp(name, "l") == 0) return &l;
    if (std::strcmp(name, "lc") == 0) return &lc;
    if (std::strcmp(name, "m") == 0) return &m;
    if (std::strcmp(name, "g") == 0) return &g;
    if (std::strcmp(name, "k") == 0) return &k;
    if (std::strcmp(name, "q0") == 0) return &q0;
    return nullptr;
  }
  static constexpr std::array<const char*, 6> kNames{ "l", "lc", "m", "g", "k", "q0" };
  static constexpr std::array<const char*, 0> kDerivedNames{};
};

template <typename Scalar, int R, int C>
using Mat = Eigen::Matrix<Scalar, R, C>;
template <typename Scalar, int R>
using Vec = Eigen::Matrix<Scalar, R, 1>;

template <typename Scalar = double>
struct Coefficients {
  Mat<Scalar, 2, 1> K;
  Mat<Scalar, 2, 1> L;
};

template <typename Scalar = double>
struct Statics {
  Vec<Scalar, 1> Q;
  Vec<Scalar, 1> drive;
  Scalar V;
  Vec<Scalar, 1> dV_dq;
  Mat<Scalar, 1, 1> d2V_dq2;
  Mat<Scalar, 1, 1> stiffness;
  Vec<Scalar, Sizes::kNumReactions> R;
};

struct Model : Sizes {
  static constexpr const char* kName = "handwritten_statics_pendulum";
  // Output flags (core/model_traits.h reads them; the same as a generated header):
  // Statics with Q, drive, V, dV_dq, d2V_dq2 and stiffness (Model::Stiffness) and reactions.
  static constexpr bool kHasStatics = true;
  static constexpr bool kHasStaticsQ = true;
  static constexpr bool kHasStaticsStiffness = true;
  static constexpr bool kHasStaticsV = true;
  static constexpr bool kHasStaticsD2V = true;
  static constexpr bool kHasStaticsR = true;
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
  // What else it has (core/model_traits.h reads these too): Coefficients with K and L only; no Solve, no drawing.
  static constexpr bool kHasCoeffsPhi = false;
  static constexpr bool kHasK = true;
  static constexpr bool kHasL = true;
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
  static constexpr std::array<const char*, kNq> kQNames{"theta_pendulum"};
  static constexpr std::array<const char*, kNphi> kPhiNames{"x_P", "y_P"};
  static constexpr std::array<bool, kNq> kQIsAngle{true};
  static constexpr std::array<bool, kNphi> kPhiIsAngle{false, false};
  static constexpr std::array<const char*, kNumPoints> kPointNames{};
  static constexpr std::array<const char*, kNumLinks> kLinkNames{"ground", "pendulum"};
  static constexpr int kGroundLink = 0;
  static constexpr std::array<const char*, kNumScenePoints> kScenePointNames{
      "ground.O", "pendulum.O", "pendulum.P"};
  static constexpr std::array<int, kNumScenePoints> kScenePointLink{0, 1, 1};
  static constexpr std::array<const char*, kNumReactions> kReactionNames{"F_O_x", "F_O_y"};
  static constexpr std::array<double, kNq> kAssemblyQ{-3.141592653589793};
  static constexpr std::array<double, kNphi> kAssemblyPhi{-1.0, 0.0};
  static constexpr std::array<double, kNq> kQMin{-3.141592653589793};
  static constexpr std::array<double, kNq> kQMax{6.283185307179586};

  template <typename Scalar>
  using ParamsT = mech::handwritten_statics_pendulum::Params<Scalar>;
  template <typename Scalar>
  using CoefficientsT = mech::handwritten_statics_pendulum::Coefficients<Scalar>;
  template <typename Scalar>
  using StaticsT = mech::handwritten_statics_pendulum::Statics<Scalar>;

  template <typename Scalar>
  static void Phi(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                  const Vec<Scalar, kNphi>& phi, Vec<Scalar, kNc>* Phi,
                  Mat<Scalar, kNc, kNphi>* Phi_phi = nullptr,
                  Mat<Scalar, kNc, kNq>* Phi_q = nullptr) {
    using std::cos;
    using std::sin;
    if (Phi != nullptr) *Phi << p.l * cos(q(0)) - phi(0), p.l * sin(q(0)) - phi(1);
    if (Phi_phi != nullptr) *Phi_phi = -Mat<Scalar, 2, 2>::Identity();
    if (Phi_q != nullptr) *Phi_q << -p.l * sin(q(0)), p.l * cos(q(0));
  }
  template <typename Scalar>
  static void Coeffs(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                     const Vec<Scalar, kNphi>& /*phi*/, Coefficients<Scalar>* out) {
    using std::cos;
    using std::sin;
    out->K << -p.l * sin(q(0)), p.l * cos(q(0));
    out->L << -p.l * cos(q(0)), -p.l * sin(q(0));
  }
  template <typename Scalar>
  static void Forces(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                      const Vec<Scalar, kNphi>& /*phi*/, const Coefficients<Scalar>& /*c*/,
                      StaticsT<Scalar>* out) {
    using std::cos;
    using std::sin;
    const Scalar w = p.m * p.g * p.lc;
    const Scalar u = q(0) - p.q0;
    out->V = w * sin(q(0)) + p.k * u * u / Scalar(2);
    out->dV_dq(0) = w * cos(q(0)) + p.k * u;
    out->Q(0) = -out->dV_dq(0);
    out->drive(0) = -out->Q(0);
    out->R << Scalar(0), p.m * p.g;
  }
  /// d2V/dq2 = stiffness = k - w sin q, apart from Forces as in generated headers.
  template <typename Scalar>
  static void Stiffness(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                        const Vec<Scalar, kNphi>& /*phi*/, const Coefficients<Scalar>& /*c*/,
                        StaticsT<Scalar>* out) {
    using std::sin;
    out->d2V_dq2(0, 0) = p.k - p.m * p.g * p.lc * sin(q(0));
    out->stiffness = out->d2V_dq2;
  }
  template <typename Scalar>
  static void Scene(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                    const Vec<Scalar, kNphi>& /*phi*/, Mat<Scalar, 2, kNumScenePoints>* r) {
    using std::cos;
    using std::sin;
    *r << Scalar(0), Scalar(0), p.l * cos(q(0)), Scalar(0), Scalar(0), p.l * sin(q(0));
  }
};

}  // namespace mech::handwritten_statics_pendulum
