/**
 * \file handwritten_fourbar.h
 * Paul's four-bar (Fig. 1.1-1a), written by hand in exactly the shape of a header that
 * mechgen generates from templates/mechanism.h.mustache (namespace mech::handwritten_fourbar).
 *
 * It serves three purposes: the runtime was developed against it before the generator
 * existed; its closed forms (circle–circle intersection for the positions, Paul's
 * eqs. (1.1-8) and (1.1-10) adapted to this numbering for K and L) are the test oracle for
 * the generated `mech::fourbar`; and it is the "hand-written closed form" of the benchmark.
 *
 * Geometry: ground pivots A = (0, 0) and D = (d, 0); crank AB = a at angle q = theta_crank;
 * coupler BC = b at angle theta_coupler; rocker DC = c at angle theta_rocker (measured at D);
 * coupler point P at (xi, eta) in the coupler frame (origin B, xi along BC).
 *   Phi(0) = a cos q + b cos th2 - d - c cos th3
 *   Phi(1) = a sin q + b sin th2     - c sin th3
 * det Phi_phi = b c sin(th2 - th3): its sign labels the assembly mode (branch).
 */
#pragma once

#include <array>
#include <cstring>
#include <cmath>

#include <Eigen/Core>

namespace mech::handwritten_fourbar {

struct Sizes {
  static constexpr int kNq = 1;
  static constexpr int kNphi = 2;
  static constexpr int kNc = 2;
  static constexpr int kNumLoops = 1;
  static constexpr int kMobility = 1;
  static constexpr int kOrder = 2;
  static constexpr int kNumPoints = 1;
  static constexpr int kNumLinks = 4;
  static constexpr int kNumScenePoints = 9;
};

template <typename Scalar = double>
struct Params {
  Scalar a = Scalar(1.0);    ///< crank AB
  Scalar b = Scalar(3.5);    ///< coupler BC
  Scalar c = Scalar(3.0);    ///< rocker DC
  Scalar d = Scalar(4.0);    ///< ground AD
  Scalar xi = Scalar(1.5);   ///< coupler point P along BC
  Scalar eta = Scalar(1.0);  ///< coupler point P normal to BC

  template <typename T>
  Params<T> Cast() const {
    Params<T> p;
    p.a = T(a);
    p.b = T(b);
    p.c = T(c);
    p.d = T(d);
    p.xi = T(xi);
    p.eta = T(eta);
    return p;
  }

  /// By name, as the generated Params (the tools' --set and --params).
  Scalar* Find(const char* name) {
    if (std::strcmp(name, "a") == 0) return &a;
    if (std::strcmp(name, "b") == 0) return &b;
    if (std::strcmp(name, "c") == 0) return &c;
    if (std::strcmp(name, "d") == 0) return &d;
    if (std::strcmp(name, "xi") == 0) return &xi;
    if (std::strcmp(name, "eta") == 0) return &eta;
    return nullptr;
  }
  static constexpr std::array<const char*, 6> kNames{ "a", "b", "c", "d", "xi", "eta" };
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
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  const Scalar S3 = sin(phi(1)), C3 = cos(phi(1));
  if (Phi != nullptr) {
    (*Phi)(0) = p.a * C1 + p.b * C2 - p.d - p.c * C3;
    (*Phi)(1) = p.a * S1 + p.b * S2 - p.c * S3;
  }
  if (Phi_phi != nullptr) {
    (*Phi_phi)(0, 0) = -p.b * S2;
    (*Phi_phi)(0, 1) = p.c * S3;
    (*Phi_phi)(1, 0) = p.b * C2;
    (*Phi_phi)(1, 1) = -p.c * C3;
  }
  if (Phi_q != nullptr) {
    (*Phi_q)(0, 0) = -p.a * S1;
    (*Phi_q)(1, 0) = p.a * C1;
  }
}

/// Paul's closed forms. With s23 = sin(th2 - th3):
///   K2 = a sin(th3 - q) / (b s23),  K3 = a sin(th2 - q) / (c s23)        (1.1-8)
/// and, differentiating the velocity loop once more with qd = 1, qdd = 0,
///   R1 = a cos q + b C2 K2^2 - c C3 K3^2,  R2 = a sin q + b S2 K2^2 - c S3 K3^2
///   L2 = -(C3 R1 + S3 R2) / (b s23),       L3 = -(C2 R1 + S2 R2) / (c s23)  (1.1-10)
template <typename Scalar>
void EvalCoefficients(const Params<Scalar>& p,
                      const Vec<Scalar, Sizes::kNq>& q,
                      const Vec<Scalar, Sizes::kNphi>& phi,
                      Coefficients<Scalar>* out) {
  using std::cos;
  using std::sin;
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  const Scalar S3 = sin(phi(1)), C3 = cos(phi(1));
  // sin(th2 - th3), sin(th3 - q), sin(th2 - q) by the addition theorems (no extra sin calls).
  const Scalar s23 = S2 * C3 - C2 * S3;
  const Scalar s31 = S3 * C1 - C3 * S1;
  const Scalar s21 = S2 * C1 - C2 * S1;
  const Scalar K2 = p.a * s31 / (p.b * s23);
  const Scalar K3 = p.a * s21 / (p.c * s23);
  const Scalar R1 = p.a * C1 + p.b * C2 * K2 * K2 - p.c * C3 * K3 * K3;
  const Scalar R2 = p.a * S1 + p.b * S2 * K2 * K2 - p.c * S3 * K3 * K3;
  const Scalar L2 = -(C3 * R1 + S3 * R2) / (p.b * s23);
  const Scalar L3 = -(C2 * R1 + S2 * R2) / (p.c * s23);
  out->K(0, 0) = K2;
  out->K(1, 0) = K3;
  out->L(0, 0) = L2;
  out->L(1, 0) = L3;
  // Coupler point (1.1.1-2): x_P = a C1 + xi C2 - eta S2, y_P = a S1 + xi S2 + eta C2.
  const Scalar dx2 = -p.xi * S2 - p.eta * C2;  // d x_P / d th2
  const Scalar dy2 = p.xi * C2 - p.eta * S2;   // d y_P / d th2
  out->r_P(0, 0) = p.a * C1 + p.xi * C2 - p.eta * S2;
  out->r_P(1, 0) = p.a * S1 + p.xi * S2 + p.eta * C2;
  out->K_P(0, 0) = -p.a * S1 + dx2 * K2;
  out->K_P(1, 0) = p.a * C1 + dy2 * K2;
  out->L_P(0, 0) = -p.a * C1 - dy2 * K2 * K2 + dx2 * L2;
  out->L_P(1, 0) = -p.a * S1 + dx2 * K2 * K2 + dy2 * L2;
}

template <typename Scalar>
void EvalScene(const Params<Scalar>& p,
               const Vec<Scalar, Sizes::kNq>& q,
               const Vec<Scalar, Sizes::kNphi>& phi,
               Mat<Scalar, 2, Sizes::kNumScenePoints>* r) {
  using std::cos;
  using std::sin;
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  const Scalar S3 = sin(phi(1)), C3 = cos(phi(1));
  const Scalar xB = p.a * C1, yB = p.a * S1;
  const Scalar xC = p.d + p.c * C3, yC = p.c * S3;
  const Scalar xP = xB + p.xi * C2 - p.eta * S2, yP = yB + p.xi * S2 + p.eta * C2;
  const Scalar zero(0);
  // ground.A ground.D crank.A crank.B coupler.B coupler.C coupler.P rocker.D rocker.C
  *r << zero, p.d, zero, xB, xB, xC, xP, p.d, xC,  //
      zero, zero, zero, yB, yB, yC, yP, zero, yC;
}

struct Model : Sizes {
  static constexpr const char* kName = "handwritten_fourbar";
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
  // What else it has (core/model_traits.h reads these too): Coefficients with K, L, r_P, K_P, L_P; no Solve, no drawing.
  static constexpr bool kHasCoeffsPhi = false;
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
  static constexpr std::array<const char*, kNphi> kPhiNames{"theta_coupler", "theta_rocker"};
  static constexpr std::array<bool, kNq> kQIsAngle{true};
  static constexpr std::array<bool, kNphi> kPhiIsAngle{true, true};
  static constexpr std::array<const char*, kNumPoints> kPointNames{"coupler.P"};
  static constexpr std::array<const char*, kNumLinks> kLinkNames{"ground", "crank", "coupler",
                                                                "rocker"};
  static constexpr int kGroundLink = 0;
  static constexpr std::array<const char*, kNumScenePoints> kScenePointNames{
      "ground.A",  "ground.D",  "crank.A",  "crank.B", "coupler.B",
      "coupler.C", "coupler.P", "rocker.D", "rocker.C"};
  static constexpr std::array<int, kNumScenePoints> kScenePointLink{0, 0, 1, 1, 2, 2, 2, 3, 3};
  /// Open mode: C above the line BD (th2 ~ 31.4 deg, th3 ~ 109.7 deg at q = 90 deg).
  static constexpr std::array<double, kNq> kAssemblyQ{1.5707963267948966};
  static constexpr std::array<double, kNphi> kAssemblyPhi{0.5, 1.9};
  static constexpr std::array<double, kNq> kQMin{0.0};
  static constexpr std::array<double, kNq> kQMax{6.283185307179586};

  template <typename Scalar>
  using ParamsT = mech::handwritten_fourbar::Params<Scalar>;
  template <typename Scalar>
  using CoefficientsT = mech::handwritten_fourbar::Coefficients<Scalar>;

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
  template <typename Scalar>
  static void Scene(const Params<Scalar>& p,
                    const Vec<Scalar, kNq>& q,
                    const Vec<Scalar, kNphi>& phi,
                    Mat<Scalar, 2, kNumScenePoints>* r) {
    EvalScene(p, q, phi, r);
  }
};

/**
 * \brief Closed-form position: C is an intersection of the circles (B, b) and (D, c).
 * \param[in]  p       Parameters.
 * \param[in]  q       Crank angle theta_crank.
 * \param[in]  branch  +1: C left of the directed line B->D (the open mode of Model's
 *                     assembly configuration); -1: the other (crossed) mode.
 * \param[out] phi     (theta_coupler, theta_rocker) (dim 2).
 * \return false when the loop cannot close (|BD| > b + c or |BD| < |b - c|).
 */
template <typename S>
bool ClosedFormPosition(const Params<S>& p, S q, int branch, Vec<S, 2>* phi) {
  using std::abs;
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S xB = p.a * cos(q), yB = p.a * sin(q);
  const S ex = p.d - xB, ey = -yB;  // B -> D
  const S l2 = ex * ex + ey * ey;
  const S l = sqrt(l2);
  // Written so that NaN inputs fail too.
  if (!(l <= p.b + p.c && l >= abs(p.b - p.c) && l > S(0))) return false;
  {
    const S x = (p.b * p.b - p.c * p.c + l2) / (S(2) * l);  // along B->D from B
    const S h = sqrt(p.b * p.b - x * x) * S(branch >= 0 ? 1 : -1);
    const S xC = xB + (x * ex - h * ey) / l;
    const S yC = yB + (x * ey + h * ex) / l;
    (*phi)(0) = atan2(yC - yB, xC - xB);
    (*phi)(1) = atan2(yC, xC - p.d);
  }
  return true;
}

}  // namespace mech::handwritten_fourbar
