/**
 * \file handwritten_dynamics.h
 * The massive four-bar (ground d = 4, crank a = 1, coupler b = 3.5, rocker c = 3;
 * uniform slender bars of rho = 2 kg/m, centre of mass mid-length, J = m L^2 / 12; gravity
 * g = 9.81 along -y; open assembly; no driver), its equation of motion written by hand
 * (Paul §6.4: I(q) qdd + 1/2 I'(q) qd^2 = Q(q)), in two forms:
 *
 *   Rhs          the fast one: closed-form positions from direction cosines (one sqrt, no
 *                trigonometric function of a dependent angle), Paul's K and L by the addition
 *                theorems, I, I', Q written out;
 *   RhsTextbook  the textbook one: the dependent angles by atan2 and acos, K, L, I, I' with
 *                sines and cosines of angle differences.
 *
 * Both are templates on the scalar (long double for the reference solution). Nothing here is
 * generated: this is the benchmark's baseline and, in long double, the oracle of theta(3 s).
 *
 * Numbering as models/fourbar.yaml: A = (0, 0), D = (d, 0), q = theta_crank (AB),
 * th2 = theta_coupler (BC), th3 = theta_rocker (DC, measured at D); C has y > 0 at q = 90 deg.
 */
#pragma once

#include <cmath>
#include <limits>

namespace bench_dynamics {

template <typename S>
struct FourbarParams {
  S a = S(1), b = S(3.5), c = S(3), d = S(4);
  S rho = S(2);     // kg/m
  S g = S(9.81);    // m/s^2 along -y
  S m1() const { return rho * a; }
  S m2() const { return rho * b; }
  S m3() const { return rho * c; }
};

/// Positions, K, L of the four-bar at q (open assembly). Returns false past a dead point.
template <typename S>
struct FourbarKinematics {
  S c1{}, s1{}, c2{}, s2{}, c3{}, s3{};  // direction cosines of crank, coupler, rocker
  S K2{}, K3{}, L2{}, L3{};  // Paul's K and L of th2, th3 w.r.t. q
};

template <typename S>
inline bool Kinematics(const FourbarParams<S>& p, S q, FourbarKinematics<S>* k) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S c1 = cos(q), s1 = sin(q);
  // e = D - B; C = B + x e + h e_perp with |C - B| = b, |C - D| = c (circle-circle).
  const S ex = p.d - p.a * c1, ey = -p.a * s1;
  const S inv_f2 = S(1) / (ex * ex + ey * ey);
  const S x = S(0.5) * (p.b * p.b - p.c * p.c) * inv_f2 + S(0.5);
  const S h2 = p.b * p.b * inv_f2 - x * x;
  if (!(h2 >= S(0))) return false;
  const S h = sqrt(h2);
  const S bcx = x * ex - h * ey, bcy = x * ey + h * ex;  // C - B
  const S inv_b = S(1) / p.b, inv_c = S(1) / p.c;
  k->c1 = c1;
  k->s1 = s1;
  k->c2 = bcx * inv_b;
  k->s2 = bcy * inv_b;
  k->c3 = (bcx - ex) * inv_c;
  k->s3 = (bcy - ey) * inv_c;
  // Paul (1.1-8), (1.1-10) in this numbering (tests/runtime/handwritten_fourbar.h).
  const S s23 = k->s2 * k->c3 - k->c2 * k->s3;
  const S s31 = k->s3 * c1 - k->c3 * s1;
  const S s21 = k->s2 * c1 - k->c2 * s1;
  const S inv_s23 = S(1) / s23;
  k->K2 = p.a * s31 * inv_b * inv_s23;
  k->K3 = p.a * s21 * inv_c * inv_s23;
  const S bK2 = p.b * k->K2 * k->K2, cK3 = p.c * k->K3 * k->K3;
  const S R1 = p.a * c1 + bK2 * k->c2 - cK3 * k->c3;
  const S R2 = p.a * s1 + bK2 * k->s2 - cK3 * k->s3;
  k->L2 = -(k->c3 * R1 + k->s3 * R2) * inv_b * inv_s23;
  k->L3 = -(k->c2 * R1 + k->s2 * R2) * inv_c * inv_s23;
  return true;
}

/// What KinematicsChecked() reports: the generated EvalKinematics()'s report, by hand.
enum class CheckedStatus { kConverged, kSingular, kNotAssemblable };
template <typename S>
struct CheckedReport {
  CheckedStatus status = CheckedStatus::kConverged;
  S measure = S(0);         // the failing value (a squared length, |D - B|^2, the discriminant)
  S branch_measure = S(1);  // h^2 f^4 / (b^2 c^2) = sin^2 of the coupler-rocker angle, at most 1
};

/// The kinematics of Kinematics() with what the generated EvalKinematics() promises on top
/// (so that the benchmark can set the price of the promise apart from that of the formulas):
///  - the same refusals: a link of zero length or coincident centres (kSingular), circles that
///    do not meet beyond the rounding of their terms (kNotAssemblable), within it the touching
///    configuration (h^2 clamped to 0);
///  - the same branch measure in the report (the distance to the dyad's toggle);
///  - no non-finite direction cosine reported as converged: the same range checks as the
///    generated RRR dyad (squared lengths within [1e-138, 1e138], kSingular beyond), which
///    bound every value after them (generator/symbolic/dyads.cc);
///  - Phi_phi as an output, for the caller's conditioning check.
/// Same numbering and formulas as Kinematics(). When the status is kConverged the direction
/// cosines and Phi_phi are finite, and so are K and L except at a dead point (s23 = 0), where
/// they do not exist: as EvalKinematics().
template <typename S>
inline CheckedReport<S> KinematicsChecked(const FourbarParams<S>& p, S q, FourbarKinematics<S>* k,
                                          S Phi_phi[4]) {
  using std::abs;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S eps = std::numeric_limits<S>::epsilon();
  const S c1 = cos(q), s1 = sin(q);
  const S ex = p.d - p.a * c1, ey = -p.a * s1;
  const S bb = p.b * p.b, cc = p.c * p.c;
  const S norm2_max = S(1e138), norm2_min = S(1e-138);
  if (!(bb - norm2_min > S(0)) || !(norm2_max - bb > S(0))) return {CheckedStatus::kSingular, bb};
  if (!(cc - norm2_min > S(0)) || !(norm2_max - cc > S(0))) return {CheckedStatus::kSingular, cc};
  const S f2 = ex * ex + ey * ey;
  if (!(f2 - eps * eps * (bb + cc) > S(0))) return {CheckedStatus::kSingular, f2};
  if (!(norm2_max - f2 > S(0))) return {CheckedStatus::kSingular, f2};
  const S inv_f2 = S(1) / f2;
  const S x = S(0.5) * (bb - cc) * inv_f2 + S(0.5);
  const S h2 = bb * inv_f2 - x * x;
  if (!(h2 >= S(0)) && !(h2 >= -S(64) * eps * (bb * inv_f2 + abs(x) * (S(1) + (bb + cc) * inv_f2))))
    return {CheckedStatus::kNotAssemblable, h2};
  const S h2c = h2 > S(0) ? h2 : S(0);
  const S h = sqrt(h2c);
  const S bcx = x * ex - h * ey, bcy = x * ey + h * ex;  // C - B
  const S inv_b = S(1) / p.b, inv_c = S(1) / p.c;
  const S c2 = bcx * inv_b, s2 = bcy * inv_b, c3 = (bcx - ex) * inv_c, s3 = (bcy - ey) * inv_c;
  const S branch = f2 * f2 * h2c * (inv_b * inv_b) * (inv_c * inv_c);
  k->c1 = c1;
  k->s1 = s1;
  k->c2 = c2;
  k->s2 = s2;
  k->c3 = c3;
  k->s3 = s3;
  const S s23 = s2 * c3 - c2 * s3, s31 = s3 * c1 - c3 * s1, s21 = s2 * c1 - c2 * s1;
  const S inv_s23 = S(1) / s23;
  k->K2 = p.a * s31 * inv_b * inv_s23;
  k->K3 = p.a * s21 * inv_c * inv_s23;
  const S bK2 = p.b * k->K2 * k->K2, cK3 = p.c * k->K3 * k->K3;
  const S R1 = p.a * c1 + bK2 * c2 - cK3 * c3, R2 = p.a * s1 + bK2 * s2 - cK3 * s3;
  k->L2 = -(c3 * R1 + s3 * R2) * inv_b * inv_s23;
  k->L3 = -(c2 * R1 + s2 * R2) * inv_c * inv_s23;
  // Phi = a e1 + b e2 - c e3 - d e_x (models/fourbar.yaml), columns th2, th3.
  Phi_phi[0] = -p.b * s2;
  Phi_phi[1] = p.c * s3;
  Phi_phi[2] = p.b * c2;
  Phi_phi[3] = -p.c * c3;
  return {CheckedStatus::kConverged, S(0), branch < S(1) ? branch : S(1)};
}

/// What one right-hand side evaluation produces.
template <typename S>
struct FourbarEom {
  S I = S(0), dI = S(0), Q = S(0), qdd = S(0);  // generalized inertia, dI/dq, generalized force (weights), acceleration
};

/// I = m1 a^2/3 + m2 (a^2 + a b K2 cos(th2 - q) + b^2 K2^2 / 3) + m3 c^2 K3^2 / 3,
/// I' = dI/dq, Q = -g sum m_i d(y_Gi)/dq; qdd = (Q - I'/2 qd^2) / I.
template <typename S>
inline void EomFromKinematics(const FourbarParams<S>& p, const FourbarKinematics<S>& k, S qd,
                              FourbarEom<S>* out) {
  const S m1 = p.m1(), m2 = p.m2(), m3 = p.m3();
  const S c21 = k.c2 * k.c1 + k.s2 * k.s1;  // cos(th2 - q)
  const S s21 = k.s2 * k.c1 - k.c2 * k.s1;  // sin(th2 - q)
  const S ab = p.a * p.b, b2 = p.b * p.b, c2 = p.c * p.c;
  out->I = m1 * p.a * p.a * S(1.0 / 3) +
           m2 * (p.a * p.a + ab * k.K2 * c21 + b2 * k.K2 * k.K2 * S(1.0 / 3)) +
           m3 * c2 * k.K3 * k.K3 * S(1.0 / 3);
  out->dI = m2 * (ab * (k.L2 * c21 - k.K2 * (k.K2 - S(1)) * s21) +
                  S(2.0 / 3) * b2 * k.K2 * k.L2) +
            S(2.0 / 3) * m3 * c2 * k.K3 * k.L3;
  out->Q = -p.g * (m1 * S(0.5) * p.a * k.c1 + m2 * (p.a * k.c1 + S(0.5) * p.b * k.c2 * k.K2) +
                   m3 * S(0.5) * p.c * k.c3 * k.K3);
  out->qdd = (out->Q - S(0.5) * out->dI * qd * qd) / out->I;
}

/// The fast hand-written right-hand side: positions + K + L + I + I' + Q + qdd.
template <typename S>
inline bool Rhs(const FourbarParams<S>& p, S q, S qd, FourbarEom<S>* out) {
  FourbarKinematics<S> k;
  if (!Kinematics(p, q, &k)) return false;
  EomFromKinematics(p, k, qd, out);
  return true;
}

/// Total energy T + V (V = 0 at y = 0).
template <typename S>
inline S Energy(const FourbarParams<S>& p, S q, S qd) {
  FourbarKinematics<S> k;
  FourbarEom<S> e;
  Kinematics(p, q, &k);
  EomFromKinematics(p, k, qd, &e);
  const S V = p.g * (p.m1() * S(0.5) * p.a * k.s1 + p.m2() * (p.a * k.s1 + S(0.5) * p.b * k.s2) +
                     p.m3() * S(0.5) * p.c * k.s3);
  return S(0.5) * e.I * qd * qd + V;
}

/// The textbook form: th2 = angle(BD) + acos(...), th3 = atan2(C - D); K, L, I, I', Q with
/// sin/cos of the angles and of their differences.
template <typename S>
inline bool RhsTextbook(const FourbarParams<S>& p, S q, S qd, FourbarEom<S>* out) {
  using std::acos;
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S bx = p.a * cos(q), by = p.a * sin(q);
  const S ex = p.d - bx, ey = -by;
  const S f = sqrt(ex * ex + ey * ey);
  const S arg = (p.b * p.b + f * f - p.c * p.c) / (S(2) * p.b * f);
  if (!(arg >= S(-1) && arg <= S(1))) return false;
  const S th2 = atan2(ey, ex) + acos(arg);
  const S th3 = atan2(by + p.b * sin(th2), bx + p.b * cos(th2) - p.d);
  const S s23 = sin(th2 - th3);
  const S K2 = p.a * sin(th3 - q) / (p.b * s23);
  const S K3 = p.a * sin(th2 - q) / (p.c * s23);
  // Differentiate b K2 e2 - c K3 e3 = -a e1' once more (qd = 1, qdd = 0), project on e3_perp / e2_perp.
  const S L2 = (-p.a * cos(th3 - q) - p.b * K2 * K2 * cos(th2 - th3) + p.c * K3 * K3) / (p.b * s23);
  const S L3 = (-p.a * cos(th2 - q) - p.b * K2 * K2 + p.c * K3 * K3 * cos(th2 - th3)) / (p.c * s23);
  const S m1 = p.m1(), m2 = p.m2(), m3 = p.m3();
  out->I = m1 * p.a * p.a / S(3) +
           m2 * (p.a * p.a + p.a * p.b * K2 * cos(th2 - q) + p.b * p.b * K2 * K2 / S(3)) +
           m3 * p.c * p.c * K3 * K3 / S(3);
  out->dI = m2 * (p.a * p.b * (L2 * cos(th2 - q) - K2 * (K2 - S(1)) * sin(th2 - q)) +
                  S(2) * p.b * p.b * K2 * L2 / S(3)) +
            S(2) * m3 * p.c * p.c * K3 * L3 / S(3);
  out->Q = -p.g * (m1 * p.a / S(2) * cos(q) + m2 * (p.a * cos(q) + p.b / S(2) * cos(th2) * K2) +
                   m3 * p.c / S(2) * cos(th3) * K3);
  out->qdd = (out->Q - out->dI * qd * qd / S(2)) / out->I;
  return true;
}

}  // namespace bench_dynamics
