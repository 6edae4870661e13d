/**
 * \file handwritten_statics_slider_crank.h
 * A slider-crank with a piston force and Coulomb friction at the crank bearing only,
 * written by hand in the shape of a header that mechgen generates with `forces` and
 * `reactions` (namespace mech::handwritten_statics_slider_crank): the oracle of the statics
 * runtime tests (statics_friction_test.cc, statics_sweep_test.cc), independent of the
 * generator.
 *
 * Geometry (no offset): crank OB = a at q = theta_crank about O = (0, 0); rod BC = b at
 * beta = theta_rod; the slider's pin C on the line y = 0 at x = s = s_slide.
 *   Phi(0) = a cos q + b cos beta - s,   Phi(1) = a sin q + b sin beta   (sin beta = -a sin q / b)
 * Load: the piston force (-F, 0) on the slider at C. Friction: a torque f on the crank by the
 * ground at O (friction circle radius mu_O r_O); none at B, C or the slide.
 *
 * Free-body analysis (massless links), written here by hand:
 *  - The rod carries forces at B and C only (no friction there): a two-force member, so the
 *    force of the rod on the slider is P u, u = (cos beta, sin beta) from B to C (P > 0:
 *    compression), and the force of the crank on the rod at B is the same P u.
 *  - Slider: P cos beta - F = 0 along x (no friction, no actuator at the slide), so
 *    P = F / cos beta; N + P sin beta = 0 along y, N = -P sin beta (the guide's force along
 *    n = (0, 1)); every force acts at C, so the guide's moment M = 0.
 *  - Crank: F_O - P u = 0, F_O = P u (force of the ground on the crank); moments about O:
 *    T + f + (B - O) x (-P u) = 0 with (B - O) x u = a sin(beta - q), so the driving torque
 *    T = P a sin(beta - q) - f, and the friction load f does not change P: the normal force
 *    at O is |F_O| = |P| whatever the friction.
 * Hence T0 = F a sin(beta - q) / cos beta, and with f = -mu_O r_O |P| sign(qdot):
 * T = T0 + mu_O r_O |P| sign(qdot). The load drives the crank backwards only where
 * |T0| > mu_O r_O |P|, i.e. a |sin(q - beta)| > mu_O r_O; inside, it is self-locking.
 * Reactions (contract order): F_O_x, F_O_y, F_B_x, F_B_y, F_C_x, F_C_y (each the force of
 * the joint's first link on its second), N_slide, T_slide, M_slide.
 * Q = -T (virtual work: Q = (-F) ds/dq + f); stiffness = -dQ/dq (friction excluded) = F s'',
 * from Model::Stiffness apart from Model::Forces (as generated headers do).
 * Parameters a = b make the rod stand vertical at q = 90 deg: a dead point (cos beta = 0)
 * where P = F / cos beta grows without bound.
 */
#pragma once

#include <array>
#include <cstring>
#include <cmath>

#include <Eigen/Core>

namespace mech::handwritten_statics_slider_crank {

struct Sizes {
  static constexpr int kNq = 1;
  static constexpr int kNphi = 2;
  static constexpr int kNc = 2;
  static constexpr int kNumLoops = 1;
  static constexpr int kMobility = 1;
  static constexpr int kOrder = 2;
  static constexpr int kNumPoints = 1;
  static constexpr int kNumLinks = 4;
  static constexpr int kNumScenePoints = 7;
  static constexpr int kNumReactions = 9;
  static constexpr int kNumFriction = 1;
};

template <typename Scalar = double>
struct Params {
  Scalar a = Scalar(0.1);     ///< crank OB (m)
  Scalar b = Scalar(0.35);    ///< rod BC (m)
  Scalar F = Scalar(1000.0);  ///< piston force on the slider along -x (N)
  Scalar mu_O = Scalar(0.2);  ///< friction coefficient at O
  Scalar r_O = Scalar(0.03);  ///< journal radius at O (m)

  /// By name, as the generated Params (the tools' --set and --params).
  Scalar* Find(const char* name) {
    if (std::strcmp(name, "a") == 0) return &a;
    if (std::strcmp(name, "b") == 0) return &b;
    if (std::strcmp(name, "F") == 0) return &F;
    if (std::strcmp(name, "mu_O") == 0) return &mu_O;
    if (std::strcmp(name, "r_O") == 0) return &r_O;
    return nullptr;
  }
  static constexpr std::array<const char*, 5> kNames{ "a", "b", "F", "mu_O", "r_O" };
  static constexpr std::array<const char*, 0> kDerivedNames{};
};

template <typename Scalar, int R, int C>
using Mat = Eigen::Matrix<Scalar, R, C>;
template <typename Scalar, int R>
using Vec = Eigen::Matrix<Scalar, R, 1>;

template <typename Scalar = double>
struct Coefficients {
  Mat<Scalar, Sizes::kNphi, Sizes::kNq> K;
  Mat<Scalar, Sizes::kNphi, Sizes::kNq * Sizes::kNq> L;
  Mat<Scalar, 2, Sizes::kNumPoints> r_P;
  Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNq> K_P;
  Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNq * Sizes::kNq> L_P;
  Vec<Scalar, Sizes::kNc> Phi;
  Mat<Scalar, Sizes::kNc, Sizes::kNphi> Phi_phi;
};

template <typename Scalar = double>
struct Statics {
  Vec<Scalar, Sizes::kNq> Q;
  Vec<Scalar, Sizes::kNq> drive;
  Mat<Scalar, Sizes::kNq, Sizes::kNq> stiffness;
  Vec<Scalar, Sizes::kNumReactions> R;
  Vec<Scalar, Sizes::kNumFriction> normal;
  Vec<Scalar, Sizes::kNumFriction> gain;
  Mat<Scalar, Sizes::kNumFriction, Sizes::kNq> K_rel;
};

template <typename Scalar>
void EvalPhi(const Params<Scalar>& p, const Vec<Scalar, 1>& q, const Vec<Scalar, 2>& phi,
             Vec<Scalar, 2>* Phi, Mat<Scalar, 2, 2>* Phi_phi = nullptr,
             Mat<Scalar, 2, 1>* Phi_q = nullptr) {
  using std::cos;
  using std::sin;
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  if (Phi != nullptr) {
    (*Phi)(0) = p.a * C1 + p.b * C2 - phi(1);
    (*Phi)(1) = p.a * S1 + p.b * S2;
  }
  if (Phi_phi != nullptr) *Phi_phi << -p.b * S2, Scalar(-1), p.b * C2, Scalar(0);
  if (Phi_q != nullptr) *Phi_q << -p.a * S1, p.a * C1;
}

/// K and L by differentiating a sin q + b sin beta = 0 and s = a cos q + b cos beta:
///   K_beta = -a cos q / (b cos beta),  K_s = -a sin q - b sin beta K_beta,
///   L_beta = (a sin q + b sin beta K_beta^2) / (b cos beta),
///   L_s = -a cos q - b cos beta K_beta^2 - b sin beta L_beta.
template <typename Scalar>
void EvalCoefficients(const Params<Scalar>& p, const Vec<Scalar, 1>& q, const Vec<Scalar, 2>& phi,
                      Coefficients<Scalar>* out) {
  using std::cos;
  using std::sin;
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  const Scalar Kb = -p.a * C1 / (p.b * C2);
  const Scalar Ks = -p.a * S1 - p.b * S2 * Kb;
  const Scalar Lb = (p.a * S1 + p.b * S2 * Kb * Kb) / (p.b * C2);
  const Scalar Ls = -p.a * C1 - p.b * C2 * Kb * Kb - p.b * S2 * Lb;
  out->K << Kb, Ks;
  out->L << Lb, Ls;
  out->r_P << phi(1), Scalar(0);
  out->K_P << Ks, Scalar(0);
  out->L_P << Ls, Scalar(0);
  EvalPhi(p, q, phi, &out->Phi, &out->Phi_phi);
}

/// The hand free-body solution of the file comment. friction: f (torque on the crank by the
/// ground at O, CCW +), or nullptr for none.
template <typename Scalar>
void EvalStatics(const Params<Scalar>& p, const Vec<Scalar, 1>& q, const Vec<Scalar, 2>& phi,
                 const Coefficients<Scalar>& /*c*/, Statics<Scalar>* out,
                 const Vec<Scalar, 1>* friction = nullptr) {
  using std::abs;
  using std::cos;
  using std::sin;
  const Scalar f = friction != nullptr ? (*friction)(0) : Scalar(0);
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  const Scalar P = p.F / C2;                       // rod force, compression > 0
  const Scalar sin_beta_q = S2 * C1 - C2 * S1;     // sin(beta - q)
  const Scalar T = P * p.a * sin_beta_q - f;       // driving torque on the crank
  out->drive(0) = T;
  out->Q(0) = -T;
  out->R << P * C2, P * S2, P * C2, P * S2, P * C2, P * S2, -P * S2, Scalar(0), Scalar(0);
  out->normal(0) = abs(P);
  out->gain(0) = p.mu_O * p.r_O;
  out->K_rel(0, 0) = Scalar(1);                    // d(theta_crank - 0)/dq
}

/// stiffness = -dQ/dq along the motion (friction excluded) = F s'' = F L_s, apart from
/// EvalStatics as in generated headers (EvalStiffness).
template <typename Scalar>
void EvalStiffness(const Params<Scalar>& p, const Coefficients<Scalar>& c, Statics<Scalar>* out) {
  out->stiffness(0, 0) = p.F * c.L(1, 0);
}

template <typename Scalar>
void EvalScene(const Params<Scalar>& p, const Vec<Scalar, 1>& q, const Vec<Scalar, 2>& phi,
               Mat<Scalar, 2, Sizes::kNumScenePoints>* r) {
  using std::cos;
  using std::sin;
  const Scalar xB = p.a * cos(q(0)), yB = p.a * sin(q(0)), s = phi(1), zero(0);
  // ground.O ground.S crank.O crank.B rod.B rod.C slider.C
  *r << zero, zero, zero, xB, xB, s, s,  //
      zero, zero, zero, yB, yB, zero, zero;
}

struct Model : Sizes {
  static constexpr const char* kName = "handwritten_statics_slider_crank";
  // Output flags (core/model_traits.h reads them; the same as a generated header):
  // Statics with Q, drive, stiffness (Model::Stiffness), reactions and friction.
  static constexpr bool kHasStatics = true;
  static constexpr bool kHasStaticsQ = true;
  static constexpr bool kHasStaticsStiffness = true;
  static constexpr bool kHasStaticsV = false;
  static constexpr bool kHasStaticsD2V = false;
  static constexpr bool kHasStaticsR = true;
  static constexpr bool kHasStaticsFriction = true;
  static constexpr bool kHasDynamics = false;
  static constexpr bool kHasExcess = false;
  static constexpr bool kHasShaking = false;
  static constexpr bool kHasKinematics = false;
  static constexpr bool kHasRhs = false;
  static constexpr bool kHasRhsConstants = false;
  static constexpr bool kHasDesignDerivatives = false;
  static constexpr bool kHasStaticsDesign = false;
  static constexpr bool kHasDynamicsDesign = false;
  // What else it has (core/model_traits.h reads these too): Coefficients with Phi, Phi_phi, K, L, r_P, K_P, L_P; no Solve, no drawing.
  static constexpr bool kHasCoeffsPhi = true;
  static constexpr bool kHasK = true;
  static constexpr bool kHasL = true;
  static constexpr bool kHasPoints = true;
  static constexpr bool kHasPointVelocities = true;
  static constexpr bool kHasPointAccelerations = true;
  static constexpr bool kHasSolve = false;
  static constexpr bool kHasNamedModes = false;
  static constexpr bool kHasTrig = false;
  static constexpr bool kHasSolveTrig = false;
  static constexpr bool kHasTransmissionAngles = false;
  static constexpr bool kHasSwitchModes = false;
  static constexpr bool kHasDrawing = false;
  static constexpr bool kHasCamProfile = false;
  static constexpr bool kHasAppliedLoads = false;
  static constexpr std::array<const char*, kNq> kQNames{"theta_crank"};
  static constexpr std::array<const char*, kNphi> kPhiNames{"theta_rod", "s_slide"};
  static constexpr std::array<bool, kNq> kQIsAngle{true};
  static constexpr std::array<bool, kNphi> kPhiIsAngle{true, false};
  static constexpr std::array<const char*, kNumPoints> kPointNames{"slider.C"};
  static constexpr std::array<const char*, kNumLinks> kLinkNames{"ground", "crank", "rod",
                                                                "slider"};
  static constexpr int kGroundLink = 0;
  static constexpr std::array<const char*, kNumScenePoints> kScenePointNames{
      "ground.O", "ground.S", "crank.O", "crank.B", "rod.B", "rod.C", "slider.C"};
  static constexpr std::array<int, kNumScenePoints> kScenePointLink{0, 0, 1, 1, 2, 2, 3};
  static constexpr std::array<const char*, kNumReactions> kReactionNames{
      "F_O_x", "F_O_y", "F_B_x", "F_B_y", "F_C_x", "F_C_y", "N_slide", "T_slide", "M_slide"};
  static constexpr std::array<const char*, kNumFriction> kFrictionJoints{"O"};
  static constexpr std::array<bool, kNumFriction> kFrictionPrismatic{false};
  static constexpr std::array<double, kNq> kAssemblyQ{1.5707963267948966};
  static constexpr std::array<double, kNphi> kAssemblyPhi{-0.29, 0.33};
  static constexpr std::array<double, kNq> kQMin{0.0};
  static constexpr std::array<double, kNq> kQMax{6.283185307179586};

  template <typename Scalar>
  using ParamsT = mech::handwritten_statics_slider_crank::Params<Scalar>;
  template <typename Scalar>
  using CoefficientsT = mech::handwritten_statics_slider_crank::Coefficients<Scalar>;
  template <typename Scalar>
  using StaticsT = mech::handwritten_statics_slider_crank::Statics<Scalar>;

  template <typename Scalar>
  static void Phi(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                  const Vec<Scalar, kNphi>& phi, Vec<Scalar, kNc>* Phi,
                  Mat<Scalar, kNc, kNphi>* Phi_phi = nullptr,
                  Mat<Scalar, kNc, kNq>* Phi_q = nullptr) {
    EvalPhi(p, q, phi, Phi, Phi_phi, Phi_q);
  }
  template <typename Scalar>
  static void Coeffs(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                     const Vec<Scalar, kNphi>& phi, Coefficients<Scalar>* out) {
    EvalCoefficients(p, q, phi, out);
  }
  template <typename Scalar>
  static void Forces(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                      const Vec<Scalar, kNphi>& phi, const Coefficients<Scalar>& c,
                      StaticsT<Scalar>* out, const Vec<Scalar, kNumFriction>* friction = nullptr) {
    EvalStatics(p, q, phi, c, out, friction);
  }
  template <typename Scalar>
  static void Stiffness(const Params<Scalar>& p, const Vec<Scalar, kNq>& /*q*/,
                        const Vec<Scalar, kNphi>& /*phi*/, const Coefficients<Scalar>& c,
                        StaticsT<Scalar>* out) {
    EvalStiffness(p, c, out);
  }
  template <typename Scalar>
  static void Scene(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                    const Vec<Scalar, kNphi>& phi, Mat<Scalar, 2, kNumScenePoints>* r) {
    EvalScene(p, q, phi, r);
  }
};

}  // namespace mech::handwritten_statics_slider_crank
