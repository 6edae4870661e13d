/**
 * \file machines/balancing/rotor.h
 * Static and two-plane dynamic balancing of a rigid rotor (Paul §7.1).
 *
 * The rotor turns about its z axis. Unbalance i is a mass m_i (kg) at radius r_i (m) and angle
 * θ_i (rad) in the rotor's frame, at the axial position z_i (m). At speed ω it loads the
 * bearings with the rotating centrifugal force m_i r_i ω² e^{i(θ_i + ωt)}, so, as complex
 * numbers in the rotor's frame (x + i y),
 *     U = Σ m_i r_i e^{iθ_i}          (kg m: the static unbalance, the resultant force / ω²)
 *     M = Σ m_i r_i z_i e^{iθ_i}      (kg m²: its moment about z = 0, turned by −90° about z:
 *                                      the true moment vector is i ω² M, for ω along +z).
 * Static balancing (one plane) cancels U: a correction m_c r_c e^{iθ_c} = −U (mass m_c at the
 * given radius r_c, angle θ_c = arg(−U)); a long rotor still shakes with the couple of M.
 * Dynamic (two-plane) balancing adds C_L = m_L r_L e^{iθ_L} at z_L and C_R = m_R r_R e^{iθ_R}
 * at z_R with
 *     C_L + C_R = −U,   z_L C_L + z_R C_R = −M
 *  ⇒  C_L = (M − z_R U)/(z_R − z_L),   C_R = (z_L U − M)/(z_R − z_L),
 * after which the rotor has neither resultant force nor moment at any speed (any rigid-rotor
 * unbalance is equivalent to one unbalance in each of two planes).
 *
 * Angles in rad, measured in the rotor's frame from the same reference mark and in the same
 * sense as the given θ_i; results in (−π, π]. Allocation-free; nothing throws: a status says
 * which input was bad (and which unbalance).
 */
#pragma once

#include <cmath>
#include <complex>

namespace mechgen::balancing {

/// One unbalance: m (kg) at radius r (m), angle (rad) in the rotor's frame, axial position z (m).
struct Unbalance {
  double m = 0;
  double r = 0;
  double angle = 0;
  double z = 0;
};

/// A correction mass in one plane.
struct Correction {
  double mass = 0;    ///< m_c (kg) at the given radius
  double radius = 0;  ///< r_c (m)
  double angle = 0;   ///< θ_c (rad, (−π, π]); 0 when no correction is needed
  double mr = 0;      ///< m_c r_c (kg m)
  double z = 0;       ///< the plane (m)
};

enum class RotorStatus {
  kOk = 0,
  kBadUnbalance,      ///< unbalance `index`: m < 0, r < 0, or a value not finite
  kZeroRadius,        ///< a correction radius <= 0 or not finite
  kCoincidentPlanes,  ///< |z_R − z_L| <= 1e-12 · (|z_L| + |z_R| + span of the z_i), or not finite
  kNotFinite,         ///< finite data whose sums U, M or correction masses m = |C|/r overflow
};

inline const char* ToString(RotorStatus s) {
  switch (s) {
    case RotorStatus::kOk:
      return "ok";
    case RotorStatus::kBadUnbalance:
      return "bad unbalance (mass and radius must be finite and >= 0, angle and z finite)";
    case RotorStatus::kZeroRadius:
      return "the correction radius must be finite and > 0";
    case RotorStatus::kCoincidentPlanes:
      return "the two correction planes coincide (z_L = z_R)";
    case RotorStatus::kNotFinite:
      return "the unbalance sums or the correction masses are beyond the range of numbers (give the "
             "unbalances in other units, or a larger correction radius)";
  }
  return "unknown";
}

/// The unbalance sums of a rotor.
struct UnbalanceSums {
  std::complex<double> U;  ///< Σ m r e^{iθ} (kg m)
  std::complex<double> M;  ///< Σ m r z e^{iθ} (kg m²)
};

/// U and M of the n unbalances (no checks).
inline UnbalanceSums Sums(const Unbalance* u, int n) {
  UnbalanceSums s;
  for (int i = 0; i < n; ++i) {
    const std::complex<double> mr = std::polar(u[i].m * u[i].r, u[i].angle);
    s.U += mr;
    s.M += mr * u[i].z;
  }
  return s;
}

namespace internal {
inline int FirstBadUnbalance(const Unbalance* u, int n) {
  for (int i = 0; i < n; ++i) {
    const Unbalance& x = u[i];
    if (!(std::isfinite(x.m) && std::isfinite(x.r) && std::isfinite(x.angle) && std::isfinite(x.z) && x.m >= 0 &&
          x.r >= 0))
      return i;
  }
  return -1;
}
inline Correction MakeCorrection(std::complex<double> c, double radius, double z) {
  Correction k;
  k.radius = radius;
  k.z = z;
  k.mr = std::abs(c);
  k.mass = k.mr / radius;
  k.angle = k.mr > 0 ? std::arg(c) : 0.0;
  return k;
}
inline bool IsFinite(std::complex<double> c) { return std::isfinite(std::abs(c)); }
inline bool IsFinite(const Correction& k) { return std::isfinite(k.mr) && std::isfinite(k.mass); }
}  // namespace internal

/// The result of BalanceStatic() / BalanceTwoPlanes().
struct RotorBalance {
  RotorStatus status = RotorStatus::kOk;
  int index = -1;          ///< the bad unbalance (kBadUnbalance), else −1
  UnbalanceSums before;    ///< U, M of the given unbalances
  Correction left, right;  ///< two-plane: at z_L and z_R; static: `left` only
  bool IsUsable() const { return status == RotorStatus::kOk; }
};

/**
 * \brief Static (single-plane) balancing: the correction mass at radius r_c that cancels U.
 * \param[in] u, n  the unbalances
 * \param[in] radius  r_c (m) > 0
 * \param[in] z       the correction plane (reported only; the couple is not balanced)
 */
inline RotorBalance BalanceStatic(const Unbalance* u, int n, double radius, double z = 0) {
  RotorBalance r;
  r.index = internal::FirstBadUnbalance(u, n);
  if (r.index >= 0) {
    r.status = RotorStatus::kBadUnbalance;
    return r;
  }
  if (!(std::isfinite(radius) && radius > 0)) {
    r.status = RotorStatus::kZeroRadius;
    return r;
  }
  r.before = Sums(u, n);
  r.left = internal::MakeCorrection(-r.before.U, radius, z);
  if (!(internal::IsFinite(r.before.U) && internal::IsFinite(r.before.M) && internal::IsFinite(r.left)))
    r.status = RotorStatus::kNotFinite;
  return r;
}

/**
 * \brief Two-plane dynamic balancing (see the file comment for the formulas).
 * \param[in] u, n           the unbalances
 * \param[in] z_left, z_right  the correction planes (m), distinct
 * \param[in] r_left, r_right  the correction radii (m) > 0
 */
inline RotorBalance BalanceTwoPlanes(
    const Unbalance* u, int n, double z_left, double z_right, double r_left, double r_right) {
  RotorBalance r;
  r.index = internal::FirstBadUnbalance(u, n);
  if (r.index >= 0) {
    r.status = RotorStatus::kBadUnbalance;
    return r;
  }
  if (!(std::isfinite(r_left) && r_left > 0 && std::isfinite(r_right) && r_right > 0)) {
    r.status = RotorStatus::kZeroRadius;
    return r;
  }
  double z_lo = 0, z_hi = 0;
  for (int i = 0; i < n; ++i) {
    z_lo = i == 0 ? u[i].z : std::fmin(z_lo, u[i].z);
    z_hi = i == 0 ? u[i].z : std::fmax(z_hi, u[i].z);
  }
  const double span = z_right - z_left;
  const double scale = std::abs(z_left) + std::abs(z_right) + (z_hi - z_lo);
  if (!std::isfinite(span) || !(std::abs(span) > 1e-12 * scale)) {
    r.status = RotorStatus::kCoincidentPlanes;
    return r;
  }
  r.before = Sums(u, n);
  const std::complex<double> C_L = (r.before.M - z_right * r.before.U) / span;
  const std::complex<double> C_R = (z_left * r.before.U - r.before.M) / span;
  r.left = internal::MakeCorrection(C_L, r_left, z_left);
  r.right = internal::MakeCorrection(C_R, r_right, z_right);
  if (!(internal::IsFinite(r.before.U) && internal::IsFinite(r.before.M) && internal::IsFinite(r.left) &&
        internal::IsFinite(r.right)))
    r.status = RotorStatus::kNotFinite;
  return r;
}

/// U and M of the unbalances with the corrections added (the residual: 0 to rounding).
inline UnbalanceSums Residual(const Unbalance* u, int n, const RotorBalance& b, bool two_planes = true) {
  UnbalanceSums s = Sums(u, n);
  const Correction* planes[2] = {&b.left, &b.right};
  for (int p = 0; p < (two_planes ? 2 : 1); ++p) {
    const std::complex<double> c = std::polar(planes[p]->mass * planes[p]->radius, planes[p]->angle);
    s.U += c;
    s.M += c * planes[p]->z;
  }
  return s;
}

}  // namespace mechgen::balancing
