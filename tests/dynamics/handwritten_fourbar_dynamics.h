/**
 * \file handwritten_fourbar_dynamics.h
 * The massive four-bar of issue 15 (Paul ch. 6), written by hand in exactly the shape of a
 * header that mechgen generates with `outputs.quantities: [K, L, forces, potential,
 * dynamics]` (namespace mech::handwritten_fourbar_dynamics): the runtime (mechgen/dynamics)
 * was developed against it before the generator had dynamics, and its closed forms are an
 * oracle for the generated models/fourbar_massive.yaml.
 *
 * Geometry (as tests/runtime/handwritten_fourbar.h): ground pivots A = (0, 0), D = (d, 0);
 * crank AB = a at q = theta_crank; coupler BC = b at theta_coupler; rocker DC = c at
 * theta_rocker (measured at D). Defaults: d = 4, a = 1, b = 3.5, c = 3 (m).
 *   Phi(0) = a cos q + b cos th2 - d - c cos th3,   Phi(1) = a sin q + b sin th2 - c sin th3
 * Mass: uniform slender bars of rho kg/m (2 by default): m_i = rho L_i, centre of mass at
 * mid-length, J_i = m_i L_i^2 / 12 about it. Gravity g (9.81 m/s^2) along -y. Optional loads
 * (0 by default, so that the machine is conservative): a constant torque `tau` on the crank
 * (from the ground, CCW +) and a torsional viscous damper `damp` at A (torque -damp qd on
 * the crank).
 *
 * Everything is written out by hand, with the velocity and centripetal coefficients of Paul
 * (1.1-8), (1.1-10) adapted to this numbering:
 *   K2 = a sin(th3 - q) / (b sin(th2 - th3)),  K3 = a sin(th2 - q) / (c sin(th2 - th3))
 * and the centres of mass G1 = a/2 e1, G2 = a e1 + b/2 e2, G3 = D + c/2 e3 (e_i = (C_i, S_i),
 * n_i = (-S_i, C_i)):
 *   K_G1 = a/2 n1,  K_G2 = a n1 + b/2 K2 n2,  K_G3 = c/2 K3 n3
 *   L_G1 = -a/2 e1, L_G2 = -a e1 + b/2 (L2 n2 - K2^2 e2),  L_G3 = c/2 (L3 n3 - K3^2 e3)
 *   I = sum m |K_G|^2 + J1 + J2 K2^2 + J3 K3^2,  dI/dq = 2 (sum m K_G.L_G + J2 K2 L2 + J3 K3 L3)
 *   V = g sum m y_G,  Q = -g sum m K_G,y + tau - damp qd
 * The kinetostatics (EvalKinetostatics) is a separate derivation: Newton–Euler on each link
 * with d'Alembert's forces -m a_G, -J alpha (the rocker's moments about D and the coupler's
 * about B give F_C; the force balances give F_B, F_A; the crank's moment about A gives the
 * drive), so that "drive = I qdd + h - Q" is a check between two derivations, not an identity.
 */
#pragma once

#include <array>
#include <cstring>
#include <cmath>

#include <Eigen/Core>

namespace mech::handwritten_fourbar_dynamics {

struct Sizes {
  static constexpr int kNq = 1;
  static constexpr int kNphi = 2;
  static constexpr int kNc = 2;
  static constexpr int kNumLoops = 1;
  static constexpr int kMobility = 1;
  static constexpr int kOrder = 2;
  static constexpr int kNumPoints = 0;
  static constexpr int kNumLinks = 4;
  static constexpr int kNumScenePoints = 8;
  static constexpr int kNumBlocks = 1;
  static constexpr int kNumReactions = 8;
  static constexpr int kNumFriction = 0;
};

template <typename Scalar = double>
struct Params {
  Scalar a = Scalar(1.0);     ///< crank AB (m)
  Scalar b = Scalar(3.5);     ///< coupler BC (m)
  Scalar c = Scalar(3.0);     ///< rocker DC (m)
  Scalar d = Scalar(4.0);     ///< ground AD (m)
  Scalar rho = Scalar(2.0);   ///< mass per length of the bars (kg/m)
  Scalar g = Scalar(9.81);    ///< gravity along -y (m/s^2)
  Scalar tau = Scalar(0.0);   ///< constant torque on the crank, CCW (N m)
  Scalar damp = Scalar(0.0);  ///< torsional viscous damper at A (N m s/rad)

  template <typename T>
  Params<T> Cast() const {
    Params<T> p;
    p.a = T(a);
    p.b = T(b);
    p.c = T(c);
    p.d = T(d);
    p.rho = T(rho);
    p.g = T(g);
    p.tau = T(tau);
    p.damp = T(damp);
    return p;
  }

  /// By name, as the generated Params (the tools' --set and --params).
  Scalar* Find(const char* name) {
    if (std::strcmp(name, "a") == 0) return &a;
    if (std::strcmp(name, "b") == 0) return &b;
    if (std::strcmp(name, "c") == 0) return &c;
    if (std::strcmp(name, "d") == 0) return &d;
    if (std::strcmp(name, "rho") == 0) return &rho;
    if (std::strcmp(name, "g") == 0) return &g;
    if (std::strcmp(name, "tau") == 0) return &tau;
    if (std::strcmp(name, "damp") == 0) return &damp;
    return nullptr;
  }
  static constexpr std::array<const char*, 8> kNames{ "a", "b", "c", "d", "rho", "g", "tau", "damp" };
  static constexpr std::array<const char*, 0> kDerivedNames{};
};

template <typename Scalar, int R, int C>
using Mat = Eigen::Matrix<Scalar, R, C>;
template <typename Scalar, int R>
using Vec = Eigen::Matrix<Scalar, R, 1>;
template <typename T>
struct NonDeduced {
  using type = T;
};
template <typename T>
using Out = typename NonDeduced<T>::type*;

template <typename Scalar = double>
struct Coefficients {
  Vec<Scalar, Sizes::kNc> Phi;
  Mat<Scalar, Sizes::kNc, Sizes::kNphi> Phi_phi;
  Mat<Scalar, Sizes::kNphi, Sizes::kNq> K;
  Mat<Scalar, Sizes::kNphi, Sizes::kNq * Sizes::kNq> L;
};

template <typename Scalar = double>
struct Trig {
  Vec<Scalar, Sizes::kNq> sin_q, cos_q;
  Vec<Scalar, Sizes::kNphi> sin_phi, cos_phi;
};

template <typename Scalar = double>
struct Statics {
  Vec<Scalar, Sizes::kNq> Q;
  Vec<Scalar, Sizes::kNq> drive;
  Scalar V;
  Vec<Scalar, Sizes::kNq> dV_dq;
  Vec<Scalar, Sizes::kNumReactions> R;
};

template <typename Scalar = double>
struct Dynamics {
  Mat<Scalar, Sizes::kNq, Sizes::kNq> I;
  Mat<Scalar, Sizes::kNq, Sizes::kNq * Sizes::kNq> dI_dq;
  Mat<Scalar, Sizes::kNq, Sizes::kNq * Sizes::kNq> C;
  Vec<Scalar, Sizes::kNq> h;
  Vec<Scalar, Sizes::kNq> Q;
  Scalar T;
  Scalar V;
  Scalar P_nc;
};

template <typename Scalar = double>
struct Excess {
  Mat<Scalar, 3, 3> M;
  Vec<Scalar, 3> h;
  Vec<Scalar, 3> g;
  Mat<Scalar, Sizes::kNc, 3> Phi_x;
  Vec<Scalar, Sizes::kNc> Phi;
  Vec<Scalar, Sizes::kNc> gamma;
  Scalar T, V;
};

enum class SolveStatus { kConverged, kNotAssemblable, kDidNotConverge };

template <typename Scalar>
struct SolveReport {
  SolveStatus status = SolveStatus::kConverged;
  int block = -1;
  int iterations = 0;
  Scalar measure = Scalar(0);
};

template <typename Scalar>
Scalar AngleNear(const Scalar& angle, const Scalar& reference) {
  using std::floor;
  const Scalar two_pi = Scalar(6.283185307179586);
  return angle - two_pi * floor((angle - reference) / two_pi + Scalar(0.5));
}

template <typename Scalar>
void EvalPhi(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
             const Vec<Scalar, Sizes::kNphi>& phi, Out<Vec<Scalar, Sizes::kNc>> Phi,
             Out<Mat<Scalar, Sizes::kNc, Sizes::kNphi>> Phi_phi = nullptr,
             Out<Mat<Scalar, Sizes::kNc, Sizes::kNq>> Phi_q = nullptr) {
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

namespace internal {
/// sin and cos of q, th2, th3 from trig or by calls.
template <typename Scalar>
void SinCos(const Vec<Scalar, 1>& q, const Vec<Scalar, 2>& phi, const Trig<Scalar>* trig,
            Scalar* S1, Scalar* C1, Scalar* S2, Scalar* C2, Scalar* S3, Scalar* C3) {
  using std::cos;
  using std::sin;
  if (trig != nullptr) {
    *S1 = trig->sin_q(0), *C1 = trig->cos_q(0);
    *S2 = trig->sin_phi(0), *C2 = trig->cos_phi(0);
    *S3 = trig->sin_phi(1), *C3 = trig->cos_phi(1);
  } else {
    *S1 = sin(q(0)), *C1 = cos(q(0));
    *S2 = sin(phi(0)), *C2 = cos(phi(0));
    *S3 = sin(phi(1)), *C3 = cos(phi(1));
  }
}

/// Kinematics of the centres of mass along the motion (per unit qd, qdd = 0 for L).
template <typename Scalar>
struct MassKinematics {
  Scalar K2, K3, L2, L3;
  Scalar KG[3][2], LG[3][2];  // K_G and L_G of crank, coupler, rocker
  Scalar yG[3];
  Scalar m[3], J[3];
};

template <typename Scalar>
void EvalMassKinematics(const Params<Scalar>& p, Scalar S1, Scalar C1, Scalar S2, Scalar C2,
                        Scalar S3, Scalar C3, MassKinematics<Scalar>* k) {
  const Scalar s23 = S2 * C3 - C2 * S3;
  const Scalar s31 = S3 * C1 - C3 * S1;
  const Scalar s21 = S2 * C1 - C2 * S1;
  k->K2 = p.a * s31 / (p.b * s23);
  k->K3 = p.a * s21 / (p.c * s23);
  const Scalar R1 = p.a * C1 + p.b * C2 * k->K2 * k->K2 - p.c * C3 * k->K3 * k->K3;
  const Scalar R2 = p.a * S1 + p.b * S2 * k->K2 * k->K2 - p.c * S3 * k->K3 * k->K3;
  k->L2 = -(C3 * R1 + S3 * R2) / (p.b * s23);
  k->L3 = -(C2 * R1 + S2 * R2) / (p.c * s23);
  const Scalar h(0.5);
  k->KG[0][0] = -h * p.a * S1;
  k->KG[0][1] = h * p.a * C1;
  k->LG[0][0] = -h * p.a * C1;
  k->LG[0][1] = -h * p.a * S1;
  k->KG[1][0] = -p.a * S1 - h * p.b * k->K2 * S2;
  k->KG[1][1] = p.a * C1 + h * p.b * k->K2 * C2;
  k->LG[1][0] = -p.a * C1 + h * p.b * (-k->L2 * S2 - k->K2 * k->K2 * C2);
  k->LG[1][1] = -p.a * S1 + h * p.b * (k->L2 * C2 - k->K2 * k->K2 * S2);
  k->KG[2][0] = -h * p.c * k->K3 * S3;
  k->KG[2][1] = h * p.c * k->K3 * C3;
  k->LG[2][0] = h * p.c * (-k->L3 * S3 - k->K3 * k->K3 * C3);
  k->LG[2][1] = h * p.c * (k->L3 * C3 - k->K3 * k->K3 * S3);
  k->yG[0] = h * p.a * S1;
  k->yG[1] = p.a * S1 + h * p.b * S2;
  k->yG[2] = h * p.c * S3;
  const Scalar len[3] = {p.a, p.b, p.c};
  for (int i = 0; i < 3; ++i) {
    k->m[i] = p.rho * len[i];
    k->J[i] = k->m[i] * len[i] * len[i] / Scalar(12);
  }
}
}  // namespace internal

template <typename Scalar>
void EvalCoefficients(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
                      const Vec<Scalar, Sizes::kNphi>& phi, Coefficients<Scalar>* out,
                      const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
  Scalar S1, C1, S2, C2, S3, C3;
  internal::SinCos(q, phi, trig, &S1, &C1, &S2, &C2, &S3, &C3);
  const Scalar s23 = S2 * C3 - C2 * S3;
  const Scalar s31 = S3 * C1 - C3 * S1;
  const Scalar s21 = S2 * C1 - C2 * S1;
  const Scalar K2 = p.a * s31 / (p.b * s23);
  const Scalar K3 = p.a * s21 / (p.c * s23);
  const Scalar R1 = p.a * C1 + p.b * C2 * K2 * K2 - p.c * C3 * K3 * K3;
  const Scalar R2 = p.a * S1 + p.b * S2 * K2 * K2 - p.c * S3 * K3 * K3;
  out->Phi(0) = p.a * C1 + p.b * C2 - p.d - p.c * C3;
  out->Phi(1) = p.a * S1 + p.b * S2 - p.c * S3;
  out->Phi_phi << -p.b * S2, p.c * S3, p.b * C2, -p.c * C3;
  out->K << K2, K3;
  out->L << -(C3 * R1 + S3 * R2) / (p.b * s23), -(C2 * R1 + S2 * R2) / (p.c * s23);
}

template <typename Scalar>
void EvalDetPhiPhi(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& /*q*/,
                   const Vec<Scalar, Sizes::kNphi>& phi, Scalar* det_Phi_phi) {
  using std::sin;
  *det_Phi_phi = p.b * p.c * sin(phi(0) - phi(1));
}

/// Closed form: C is an intersection of the circles (B, b) and (D, c); modes[0] = +1 puts C
/// left of the directed line B -> D (the open mode, det Phi_phi > 0), -1 the crossed mode.
template <typename Scalar>
SolveReport<Scalar> SolvePositions(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
                                   Vec<Scalar, Sizes::kNphi>* phi_io,
                                   const std::array<int, Sizes::kNumBlocks>& modes,
                                   int /*max_iterations*/ = 20,
                                   const Scalar& /*tolerance*/ = Scalar(0),
                                   Out<Trig<Scalar>> trig = nullptr) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar xB = p.a * C1, yB = p.a * S1;
  const Scalar ex = p.d - xB, ey = -yB;  // B -> D
  const Scalar l2 = ex * ex + ey * ey;
  const Scalar x = (p.b * p.b - p.c * p.c + l2) / (Scalar(2) * l2);  // along B->D, per l
  const Scalar h2 = p.b * p.b / l2 - x * x;
  if (!(h2 >= Scalar(0))) return {SolveStatus::kNotAssemblable, 0, 0, h2};
  const Scalar h = sqrt(h2) * Scalar(modes[0]);
  const Scalar ux = x * ex - h * ey, uy = x * ey + h * ex;  // B -> C
  const Scalar vx = ux - ex, vy = uy - ey;                  // D -> C
  (*phi_io)(0) = AngleNear(atan2(uy, ux), (*phi_io)(0));
  (*phi_io)(1) = AngleNear(atan2(vy, vx), (*phi_io)(1));
  if (trig != nullptr) {
    trig->sin_q(0) = S1;
    trig->cos_q(0) = C1;
    trig->cos_phi(0) = ux / p.b;
    trig->sin_phi(0) = uy / p.b;
    trig->cos_phi(1) = vx / p.c;
    trig->sin_phi(1) = vy / p.c;
  }
  return {SolveStatus::kConverged, -1, 0, Scalar(0)};
}

/// I, I', C = I'/2, h = C qd^2, Q, T, V and P_nc (see the file comment).
template <typename Scalar>
void EvalDynamics(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
                  const Vec<Scalar, Sizes::kNphi>& phi, const Vec<Scalar, Sizes::kNq>& qd,
                  const Scalar& /*t*/, const Coefficients<Scalar>& /*c*/, Dynamics<Scalar>* out,
                  const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type* = nullptr,
                  const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
  Scalar S1, C1, S2, C2, S3, C3;
  internal::SinCos(q, phi, trig, &S1, &C1, &S2, &C2, &S3, &C3);
  internal::MassKinematics<Scalar> k;
  internal::EvalMassKinematics(p, S1, C1, S2, C2, S3, C3, &k);
  Scalar I = k.J[0] + k.J[1] * k.K2 * k.K2 + k.J[2] * k.K3 * k.K3;
  Scalar C = k.J[1] * k.K2 * k.L2 + k.J[2] * k.K3 * k.L3;
  Scalar V(0), dV(0);
  for (int i = 0; i < 3; ++i) {
    I += k.m[i] * (k.KG[i][0] * k.KG[i][0] + k.KG[i][1] * k.KG[i][1]);
    C += k.m[i] * (k.KG[i][0] * k.LG[i][0] + k.KG[i][1] * k.LG[i][1]);
    V += k.m[i] * p.g * k.yG[i];
    dV += k.m[i] * p.g * k.KG[i][1];
  }
  const Scalar Qnc = p.tau - p.damp * qd(0);
  out->I(0, 0) = I;
  out->dI_dq(0, 0) = Scalar(2) * C;
  out->C(0, 0) = C;
  out->h(0) = C * qd(0) * qd(0);
  out->Q(0) = -dV + Qnc;
  out->T = Scalar(0.5) * I * qd(0) * qd(0);
  out->V = V;
  out->P_nc = Qnc * qd(0);
}

/// Newton–Euler with d'Alembert's inertia forces (see the file comment). Reactions as in
/// generated headers: F_A ground on crank, F_B crank on coupler, F_C coupler on rocker,
/// F_D rocker on ground; Q = Q_applied - (I qdd + h) and drive = -Q come out of the crank's
/// moment balance (the drive is the torque of the ground on the crank that the motion needs).
template <typename Scalar>
void EvalKinetostatics(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
                       const Vec<Scalar, Sizes::kNphi>& phi, const Vec<Scalar, Sizes::kNq>& qd,
                       const Vec<Scalar, Sizes::kNq>& qdd, const Scalar& /*t*/,
                       const Coefficients<Scalar>& /*c*/, Statics<Scalar>* out,
                       const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type* = nullptr,
                       const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
  Scalar S1, C1, S2, C2, S3, C3;
  internal::SinCos(q, phi, trig, &S1, &C1, &S2, &C2, &S3, &C3);
  internal::MassKinematics<Scalar> k;
  internal::EvalMassKinematics(p, S1, C1, S2, C2, S3, C3, &k);
  const Scalar w = qd(0), wd = qdd(0), w2 = w * w;
  // Effective forces E_i = weight - m a_G and moments -J alpha on each link.
  Scalar E[3][2], Mi[3];
  const Scalar alpha[3] = {wd, k.K2 * wd + k.L2 * w2, k.K3 * wd + k.L3 * w2};
  for (int i = 0; i < 3; ++i) {
    E[i][0] = -k.m[i] * (k.KG[i][0] * wd + k.LG[i][0] * w2);
    E[i][1] = -k.m[i] * (k.KG[i][1] * wd + k.LG[i][1] * w2) - k.m[i] * p.g;
    Mi[i] = -k.J[i] * alpha[i];
  }
  const Scalar h(0.5);
  // Arms: u = C - D (rocker), v = C - B (coupler), G3 - D = u/2, G2 - B = v/2, G1 - A = (B-A)/2.
  const Scalar ux = p.c * C3, uy = p.c * S3, vx = p.b * C2, vy = p.b * S2;
  const Scalar bx = p.a * C1, by = p.a * S1;
  // Rocker about D:  u x F_C + (u/2) x E3 + M3 = 0.
  // Coupler about B: v x (-F_C) + (v/2) x E2 + M2 = 0.
  const Scalar r1 = -(h * (ux * E[2][1] - uy * E[2][0]) + Mi[2]);
  const Scalar r2 = h * (vx * E[1][1] - vy * E[1][0]) + Mi[1];
  // [-uy ux; -vy vx] F = (r1, r2)
  const Scalar det = -uy * vx + ux * vy;
  const Scalar FCx = (r1 * vx - ux * r2) / det;
  const Scalar FCy = (-uy * r2 + vy * r1) / det;
  // Coupler: F_B - F_C + E2 = 0; crank: F_A - F_B + E1 = 0; rocker: F_C - F_D + E3 = 0.
  const Scalar FBx = FCx - E[1][0], FBy = FCy - E[1][1];
  const Scalar FAx = FBx - E[0][0], FAy = FBy - E[0][1];
  const Scalar FDx = FCx + E[2][0], FDy = FCy + E[2][1];
  // Crank about A: tau_drive + tau + damper + B x (-F_B) + (B/2) x E1 + M1 = 0.
  const Scalar applied = p.tau - p.damp * w;
  const Scalar drive =
      -(applied - (bx * FBy - by * FBx) + h * (bx * E[0][1] - by * E[0][0]) + Mi[0]);
  out->drive(0) = drive;
  out->Q(0) = -drive;
  Scalar V(0), dV(0);
  for (int i = 0; i < 3; ++i) {
    V += k.m[i] * p.g * k.yG[i];
    dV += k.m[i] * p.g * k.KG[i][1];
  }
  out->V = V;
  out->dV_dq(0) = dV;
  out->R << FAx, FAy, FBx, FBy, FCx, FCy, FDx, FDy;
}

/// Statics: the kinetostatics at rest (qd = qdd = 0).
template <typename Scalar>
void EvalStatics(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
                 const Vec<Scalar, Sizes::kNphi>& phi, const Coefficients<Scalar>& c,
                 Statics<Scalar>* out,
                 const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type* = nullptr,
                 const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
  const Vec<Scalar, 1> zero = Vec<Scalar, 1>::Zero();
  EvalKinetostatics(p, q, phi, zero, zero, Scalar(0), c, out, nullptr, trig);
}

/// Excess coordinates x = (q, th2, th3): M xdd + h = g + Phi_x^T lambda, Phi_x xdd = gamma.
template <typename Scalar>
void EvalExcess(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
                const Vec<Scalar, Sizes::kNphi>& phi, const Vec<Scalar, Sizes::kNq>& qd,
                const Vec<Scalar, Sizes::kNphi>& phid, const Scalar& /*t*/, Excess<Scalar>* out,
                const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type* = nullptr) {
  using std::cos;
  using std::sin;
  const Scalar S1 = sin(q(0)), C1 = cos(q(0));
  const Scalar S2 = sin(phi(0)), C2 = cos(phi(0));
  const Scalar S3 = sin(phi(1)), C3 = cos(phi(1));
  const Scalar w1 = qd(0), w2 = phid(0), w3 = phid(1);
  const Scalar m1 = p.rho * p.a, m2 = p.rho * p.b, m3 = p.rho * p.c;
  const Scalar J1 = m1 * p.a * p.a / 12, J2 = m2 * p.b * p.b / 12, J3 = m3 * p.c * p.c / 12;
  const Scalar h(0.5);
  // Jacobians of the centres of mass (2 x 3) and their quadratic velocity terms.
  Mat<Scalar, 2, 3> G1, G2, G3;
  G1 << -h * p.a * S1, 0, 0, h * p.a * C1, 0, 0;
  G2 << -p.a * S1, -h * p.b * S2, 0, p.a * C1, h * p.b * C2, 0;
  G3 << 0, 0, -h * p.c * S3, 0, 0, h * p.c * C3;
  Vec<Scalar, 2> c1, c2, c3;
  c1 << -h * p.a * C1 * w1 * w1, -h * p.a * S1 * w1 * w1;
  c2 << -p.a * C1 * w1 * w1 - h * p.b * C2 * w2 * w2, -p.a * S1 * w1 * w1 - h * p.b * S2 * w2 * w2;
  c3 << -h * p.c * C3 * w3 * w3, -h * p.c * S3 * w3 * w3;
  out->M = m1 * G1.transpose() * G1 + m2 * G2.transpose() * G2 + m3 * G3.transpose() * G3;
  out->M(0, 0) += J1;
  out->M(1, 1) += J2;
  out->M(2, 2) += J3;
  out->h = m1 * G1.transpose() * c1 + m2 * G2.transpose() * c2 + m3 * G3.transpose() * c3;
  out->g = -p.g * (m1 * G1.row(1).transpose() + m2 * G2.row(1).transpose() +
                   m3 * G3.row(1).transpose());
  out->g(0) += p.tau - p.damp * w1;
  out->Phi_x << -p.a * S1, -p.b * S2, p.c * S3, p.a * C1, p.b * C2, -p.c * C3;
  out->Phi << p.a * C1 + p.b * C2 - p.d - p.c * C3, p.a * S1 + p.b * S2 - p.c * S3;
  out->gamma << p.a * C1 * w1 * w1 + p.b * C2 * w2 * w2 - p.c * C3 * w3 * w3,
      p.a * S1 * w1 * w1 + p.b * S2 * w2 * w2 - p.c * S3 * w3 * w3;
  Vec<Scalar, 3> xd;
  xd << w1, w2, w3;
  out->T = h * xd.dot(out->M * xd);
  out->V = p.g * (m1 * h * p.a * S1 + m2 * (p.a * S1 + h * p.b * S2) + m3 * h * p.c * S3);
}

template <typename Scalar>
void EvalScene(const Params<Scalar>& p, const Vec<Scalar, Sizes::kNq>& q,
               const Vec<Scalar, Sizes::kNphi>& phi, Mat<Scalar, 2, Sizes::kNumScenePoints>* r) {
  using std::cos;
  using std::sin;
  const Scalar xB = p.a * cos(q(0)), yB = p.a * sin(q(0));
  const Scalar xC = p.d + p.c * cos(phi(1)), yC = p.c * sin(phi(1));
  const Scalar zero(0);
  // ground.A ground.D crank.A crank.B coupler.B coupler.C rocker.D rocker.C
  *r << zero, p.d, zero, xB, xB, xC, p.d, xC,  //
      zero, zero, zero, yB, yB, yC, zero, yC;
}

struct Model : Sizes {
  static constexpr const char* kName = "handwritten_fourbar_dynamics";
  // Output flags (core/model_traits.h reads them; the same as a generated header):
  // Statics with Q, drive, V, dV_dq and reactions (no stiffness, no friction), Dynamics and Excess.
  static constexpr bool kHasStatics = true;
  static constexpr bool kHasStaticsQ = true;
  static constexpr bool kHasStaticsStiffness = false;
  static constexpr bool kHasStaticsV = true;
  static constexpr bool kHasStaticsD2V = false;
  static constexpr bool kHasStaticsR = true;
  static constexpr bool kHasStaticsFriction = false;
  static constexpr bool kHasDynamics = true;
  static constexpr bool kHasExcess = true;
  static constexpr bool kHasShaking = false;
  static constexpr bool kHasKinematics = false;
  static constexpr bool kHasRhs = false;
  static constexpr bool kHasRhsConstants = false;
  static constexpr bool kHasDesignDerivatives = false;
  static constexpr bool kHasStaticsDesign = false;
  static constexpr bool kHasDynamicsDesign = false;
  // What else it has (core/model_traits.h reads these too): Coefficients with Phi, Phi_phi, K, L; Solve with Trig (no SolveTrig); no drawing.
  static constexpr bool kHasCoeffsPhi = true;
  static constexpr bool kHasK = true;
  static constexpr bool kHasL = true;
  static constexpr bool kHasPoints = false;
  static constexpr bool kHasPointVelocities = false;
  static constexpr bool kHasPointAccelerations = false;
  static constexpr bool kHasSolve = true;
  static constexpr bool kHasNamedModes = false;
  static constexpr bool kHasTrig = true;
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
  static constexpr std::array<const char*, kNumPoints> kPointNames{};
  static constexpr std::array<const char*, kNumLinks> kLinkNames{"ground", "crank", "coupler",
                                                                "rocker"};
  static constexpr int kGroundLink = 0;
  static constexpr std::array<const char*, kNumScenePoints> kScenePointNames{
      "ground.A", "ground.D", "crank.A", "crank.B", "coupler.B", "coupler.C", "rocker.D",
      "rocker.C"};
  static constexpr std::array<int, kNumScenePoints> kScenePointLink{0, 0, 1, 1, 2, 2, 3, 3};
  /// Released from rest at theta_crank = 90 deg, open mode (th2 ~ 31.4, th3 ~ 109.7 deg).
  static constexpr std::array<double, kNq> kAssemblyQ{1.5707963267948966};
  static constexpr std::array<double, kNphi> kAssemblyPhi{0.5, 1.9};
  static constexpr std::array<int, kNumBlocks> kDefaultModes{1};
  static constexpr std::array<bool, kNumBlocks> kBlockClosedForm{true};
  static constexpr std::array<double, kNq> kQMin{0.0};
  static constexpr std::array<double, kNq> kQMax{6.283185307179586};
  static constexpr std::array<const char*, kNumReactions> kReactionNames{
      "F_A_x", "F_A_y", "F_B_x", "F_B_y", "F_C_x", "F_C_y", "F_D_x", "F_D_y"};
  static constexpr std::array<int, kNumReactions> kReactionJoint{0, 0, 1, 1, 2, 2, 3, 3};
  static constexpr std::array<const char*, 4> kJointNames{"A", "B", "C", "D"};
  static constexpr std::array<const char*, kNumFriction> kFrictionJoints{};
  static constexpr std::array<bool, kNumFriction> kFrictionPrismatic{};

  template <typename Scalar>
  using ParamsT = mech::handwritten_fourbar_dynamics::Params<Scalar>;
  template <typename Scalar>
  using CoefficientsT = mech::handwritten_fourbar_dynamics::Coefficients<Scalar>;
  template <typename Scalar>
  using TrigT = mech::handwritten_fourbar_dynamics::Trig<Scalar>;
  template <typename Scalar>
  using StaticsT = mech::handwritten_fourbar_dynamics::Statics<Scalar>;
  template <typename Scalar>
  using DynamicsT = mech::handwritten_fourbar_dynamics::Dynamics<Scalar>;
  template <typename Scalar>
  using ExcessT = mech::handwritten_fourbar_dynamics::Excess<Scalar>;

  template <typename Scalar>
  static void Phi(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                  const Vec<Scalar, kNphi>& phi, Out<Vec<Scalar, kNc>> Phi,
                  Out<Mat<Scalar, kNc, kNphi>> Phi_phi = nullptr,
                  Out<Mat<Scalar, kNc, kNq>> Phi_q = nullptr) {
    EvalPhi(p, q, phi, Phi, Phi_phi, Phi_q);
  }
  template <typename Scalar>
  static void Coeffs(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                     const Vec<Scalar, kNphi>& phi, Coefficients<Scalar>* out,
                     const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
    EvalCoefficients(p, q, phi, out, trig);
  }
  template <typename Scalar>
  static void DetPhiPhi(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                        const Vec<Scalar, kNphi>& phi, Scalar* det) {
    EvalDetPhiPhi(p, q, phi, det);
  }
  template <typename Scalar>
  static SolveReport<Scalar> Solve(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                                   Vec<Scalar, kNphi>* phi_io,
                                   const std::array<int, kNumBlocks>& modes = kDefaultModes,
                                   int max_iterations = 20, const Scalar& tolerance = Scalar(0),
                                   Out<Trig<Scalar>> trig = nullptr) {
    return SolvePositions(p, q, phi_io, modes, max_iterations, tolerance, trig);
  }
  template <typename Scalar>
  static void Forces(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                     const Vec<Scalar, kNphi>& phi, const Coefficients<Scalar>& c,
                     Statics<Scalar>* out,
                     const typename NonDeduced<Vec<Scalar, kNumFriction>>::type* friction = nullptr,
                     const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
    EvalStatics(p, q, phi, c, out, friction, trig);
  }
  template <typename Scalar>
  static void Dynamics(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                       const Vec<Scalar, kNphi>& phi, const Vec<Scalar, kNq>& qd,
                       const Scalar& t, const Coefficients<Scalar>& c, DynamicsT<Scalar>* out,
                       const typename NonDeduced<Vec<Scalar, kNumFriction>>::type* friction = nullptr,
                       const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
    EvalDynamics(p, q, phi, qd, t, c, out, friction, trig);
  }
  template <typename Scalar>
  static void Kinetostatics(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                            const Vec<Scalar, kNphi>& phi, const Vec<Scalar, kNq>& qd,
                            const Vec<Scalar, kNq>& qdd, const Scalar& t,
                            const Coefficients<Scalar>& c, Statics<Scalar>* out,
                            const typename NonDeduced<Vec<Scalar, kNumFriction>>::type* friction = nullptr,
                            const typename NonDeduced<Trig<Scalar>>::type* trig = nullptr) {
    EvalKinetostatics(p, q, phi, qd, qdd, t, c, out, friction, trig);
  }
  template <typename Scalar>
  static void ExcessDynamics(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                             const Vec<Scalar, kNphi>& phi, const Vec<Scalar, kNq>& qd,
                             const Vec<Scalar, kNphi>& phid, const Scalar& t, ExcessT<Scalar>* out,
                             const typename NonDeduced<Vec<Scalar, kNumFriction>>::type* friction = nullptr) {
    EvalExcess(p, q, phi, qd, phid, t, out, friction);
  }
  template <typename Scalar>
  static void Scene(const Params<Scalar>& p, const Vec<Scalar, kNq>& q,
                    const Vec<Scalar, kNphi>& phi, Mat<Scalar, 2, kNumScenePoints>* r) {
    EvalScene(p, q, phi, r);
  }
};

}  // namespace mech::handwritten_fourbar_dynamics
