/**
 * \file machines/flywheel/energy_loop.h
 * Flywheel sizing by the energy-loop method (Paul §6.9.2, the book's FLYLOOP) and by
 * Wittenbauer's diagram (Paul §6.9.3), with the coefficient of speed fluctuation of a speed
 * trace (the simulation route of Paul §6.9.1 ends with one).
 *
 * Energy loop. Over one cycle Θ of the crank (rad; 2π, or 4π for a four-stroke engine, or
 * the period of the turning-moment diagram, e.g. π when it repeats every half turn) the
 * excess torque ΔT(θ) = T_d(θ) − T_l(θ) (N m; T_d the driving torque on the crank, positive in
 * the sense of rotation, T_l the load torque, positive when it opposes the rotation) does the
 * excess work
 *     E(θ) = ∫_{θ_0}^{θ} ΔT(s) ds        (J; E(θ_0) = 0),
 * which goes into kinetic energy. In a steady cycle E(θ_0 + Θ) = 0, i.e. the mean of ΔT over
 * the cycle is zero (otherwise the machine speeds up or slows down: ExcessEnergy() reports
 * kNotSteady with the mean torque). The largest swing of the kinetic energy is
 *     ΔE = E_max − E_min,
 * and with a constant inertia I (the flywheel dominating; the variation of I(θ) neglected)
 *     ΔE = ½ I (ω_max² − ω_min²) = I ω_m² C_s,   ω_m = ½(ω_max + ω_min),
 *     C_s = (ω_max − ω_min)/ω_m   (the coefficient of fluctuation of speed),
 * so I_required = ΔE / (C_s ω_m²) and, for a given flywheel, C_s = ΔE / (I ω_m²) (exact under
 * that assumption; ω_m is then, to O(C_s²), also the time mean of the speed).
 * The samples ΔT_k = ΔT(θ_0 + k h), h = Θ/N, k = 0..N-1, are periodic (the end of the cycle
 * not repeated). E is integrated interval by interval with the 4-point periodic formula
 *     ∫_{θ_k}^{θ_{k+1}} ΔT ≈ h/24 (−ΔT_{k−1} + 13 ΔT_k + 13 ΔT_{k+1} − ΔT_{k+2})
 * (local error O(h⁵), so E is O(h⁴) for a smooth ΔT; over the whole cycle it sums to the
 * periodic trapezoid rule h Σ ΔT_k, which is spectrally accurate: E(θ_0 + Θ) = Θ·mean exactly).
 * At a kink of ΔT (a switched load) both are only second order, unless the kink is a sample
 * named in EnergyLoopOptions::breaks: the stencils then do not reach across it (one-sided
 * 4-point formulas), and E and the closure stay fourth order. A break between samples
 * (EnergyLoopOptions::break_fractions) splits its interval, each side integrated with the
 * cubic of its own samples: fourth order at a kink or a jump there.
 * The extremes are refined between samples with the cubic Hermite interpolant of E (values
 * E_k and slopes ΔT_k) on the two intervals next to the extreme sample, so ΔE and the angles
 * of E_max and E_min do not depend on where the samples fall to within O(h⁴).
 *
 * Loop areas. The textbook form: the areas between the turning-moment curve and the mean
 * torque line, in order, alternately above (+) and below (−); the energy at the end of each
 * area is the running sum and ΔE = max − min of the running sums (0 included, for the start).
 *
 * Wittenbauer's diagram (Paul §6.9.3). The kinetic energy T = ½ I(θ) ω² of a one-DOF machine
 * plotted against its generalized inertia I(θ): a ray from the origin to a point of the curve
 * has the slope ω²/2, so ω_max and ω_min are the slopes of the two rays tangent to the curve
 * (Wittenbauer()). In design the origin is unknown: only the excess work E(θ) and the
 * machine's own inertia I_m(θ) are known, and the flywheel I_f and the energy T_0 at θ_0 are
 * sought, T = T_0 + E, I = I_f + I_m. The lines of slopes s_max = ω_max²/2 and s_min = ω_min²/2
 * that touch the (I_m, E) curve from above and from below,
 *     E = s_max I_m + c_max,  c_max = max_k (E_k − s_max I_m,k),
 *     E = s_min I_m + c_min,  c_min = min_k (E_k − s_min I_m,k),
 * meet at the true origin (I_m, E) = (−I_f, −T_0):
 *     I_f = (c_max − c_min)/(s_max − s_min),  T_0 = s_max I_f − c_max
 * (DesignByWittenbauer()); unlike the energy loop, this accounts for the variation of I(θ).
 *
 * Units: SI (N m, J, rad, rad/s, kg m²) or any consistent set. Allocation-free (the caller owns
 * the arrays); nothing throws: each result has a status, and the figures that explain it.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "mechgen/core/constants.h"

namespace mechgen::flywheel {

enum class LoopStatus {
  kOk = 0,
  kTooFewSamples,  ///< fewer than 4 samples (the 4-point formula), or no areas, or a break
                   ///< out of range or fewer than 3 intervals from another
  kBadCycle,       ///< Θ not finite or <= 0
  kNonFinite,      ///< a sample, area or the start angle is NaN or infinite, or a sum of them
                   ///< (the mean, E, a running sum of the areas) overflows
  /// |mean(ΔT)| > mean_tolerance · max|ΔT| (or |Σ areas| > tolerance · Σ|areas|): the cycle is
  /// not steady, E(θ_0 + Θ) = Θ·mean ≠ 0; E and ΔE are still filled (with the drift in them).
  kNotSteady,
};

inline const char* ToString(LoopStatus s) {
  switch (s) {
    case LoopStatus::kOk:
      return "ok";
    case LoopStatus::kTooFewSamples:
      return "too few samples (need at least 4 torque samples or 1 area)";
    case LoopStatus::kBadCycle:
      return "the cycle must be a finite positive angle";
    case LoopStatus::kNonFinite:
      return "a sample or area, or a sum of them, is not finite (beyond the range of numbers)";
    case LoopStatus::kNotSteady:
      return "not a steady cycle: the mean excess torque is not zero (the loop does not close)";
  }
  return "unknown";
}

struct EnergyLoopOptions {
  /// The cycle counts as steady when |mean ΔT| <= mean_tolerance · max_k |ΔT_k|.
  double mean_tolerance = 1e-9;
  /// Subtract the mean of ΔT before integrating: the load is taken as T_l + mean, the constant
  /// extra load that makes the cycle steady (the textbook's "mean torque line" when only T_d
  /// is given). The mean is still reported; the status is then kOk.
  bool remove_mean = false;
  /// Breaks: the samples k (0 <= k < n, any order) where ΔT has a kink (a switched load, e.g.
  /// a force switched on where its point is at rest) or where the two sides meet. The 4-point
  /// stencil of an interval never reaches across a break: next to one it takes the one-sided
  /// 4-point formula of the same order, h/24 (9 f_k + 19 f_{k+1} − 5 f_{k+2} + f_{k+3}) and its
  /// mirror, and on an interval with a break at both ends the trapezoid. So a ΔT smooth between
  /// breaks keeps E fourth order (without breaks a kink makes E, and even the cycle's closure,
  /// second order: the trapezoid's end terms h²/12 × the slope jump do not cancel). A jump of
  /// ΔT at a sample cannot be represented by one value there: put it between samples or
  /// accept first order. Not owned; nullptr / 0: none.
  const int* breaks = nullptr;
  int num_breaks = 0;
  /// Breaks between samples: break i lies at θ_0 + (breaks[i] + break_fractions[i]) h, the
  /// fraction in [0, 1) (0: on the sample, as above). A break inside an interval (a switch of
  /// the loads located between two samples, e.g. by MachineCycleOptions::switch_breaks) is
  /// integrated on each side with the cubic through the 4 samples of that side, extrapolated
  /// to the break (∫ over the interval = ∫_{θ_k}^{θ_b} p_left + ∫_{θ_b}^{θ_k+1} p_right), and
  /// the intervals next to it take the one-sided formulas as at a break on a sample: E stays
  /// fourth order at a kink and also at a jump of ΔT there. Needs N >= 8, and at least 3
  /// intervals between the last sample before one break and the first after the next (two
  /// breaks in one interval are refused). Not owned; nullptr: every break on its sample.
  const double* break_fractions = nullptr;
  /// A break on a sample (fraction 0) where ΔT jumps: whose value the sample's is. 0: both
  /// sides' (a kink: the one-sided formulas share it); −1: the left side's (the jump just after
  /// it: the interval after it is integrated with the right side's cubic alone); +1: the
  /// right side's (the interval before it with the left side's cubic). Not owned; nullptr: 0.
  const int* break_sides = nullptr;
};

/// The result of ExcessEnergy(): the swing of the excess energy over one cycle.
struct EnergyLoop {
  LoopStatus status = LoopStatus::kTooFewSamples;
  int n = 0;                   ///< samples N
  double cycle = 0;            ///< Θ (rad)
  double mean_torque = 0;      ///< (1/N) Σ ΔT_k (N m), before any removal; with breaks
                               ///< the break-aware integral of ΔT over Θ, divided by Θ
  double cycle_work = 0;       ///< E(θ_0 + Θ) as integrated (J): 0 steady, Θ·mean otherwise
  double E_max = 0;            ///< largest E (J), refined between samples
  double theta_max = 0;        ///< where (rad, in [θ_0, θ_0 + Θ))
  double E_min = 0;            ///< smallest E (J)
  double theta_min = 0;        ///< where (rad)
  double delta_E = 0;          ///< ΔE = E_max − E_min (J)
  int k_max = -1, k_min = -1;  ///< the sample with the largest / smallest E
  bool IsUsable() const { return status == LoopStatus::kOk; }
};

namespace internal {

// Cubic Hermite on one interval of width h: p(0) = p0, p(1) = p1, p'(0) = h g0, p'(1) = h g1
// (s = (θ − θ_a)/h). Calls visit(s, p(s)) at s = 0, 1 and the stationary points in (0, 1).
template <class Visit>
void HermiteCandidates(double p0, double p1, double g0, double g1, double h, Visit visit) {
  const double m0 = h * g0, m1 = h * g1;
  auto value = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
  };
  visit(0.0, p0);
  visit(1.0, p1);
  // p'(s) = A s² + B s + C.
  const double A = 6 * p0 + 3 * m0 - 6 * p1 + 3 * m1;
  const double B = -6 * p0 - 4 * m0 + 6 * p1 - 2 * m1;
  const double C = m0;
  const double scale = std::abs(A) + std::abs(B) + std::abs(C);
  if (!(scale > 0)) return;
  if (std::abs(A) <= 1e-14 * scale) {
    if (B != 0) {
      const double s = -C / B;
      if (s > 0 && s < 1) visit(s, value(s));
    }
    return;
  }
  const double disc = B * B - 4 * A * C;
  if (disc < 0) return;
  // Stable roots: q = −½(B + sign(B)√disc), s1 = q/A, s2 = C/q.
  const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  const double roots[2] = {q / A, q != 0 ? C / q : std::numeric_limits<double>::quiet_NaN()};
  for (double s : roots)
    if (s > 0 && s < 1) visit(s, value(s));
}

// The cubic Hermite's value at s (same conventions as HermiteCandidates).
inline double HermiteValue(double p0, double p1, double g0, double g1, double h, double s) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * g0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * h * g1;
}

// The cubic through (x_j, f_j), j = 0..3, as c_0 + c_1 s + c_2 s^2 + c_3 s^3 (Lagrange's form
// expanded); its integral over [a, b] and its value at s.
struct Cubic {
  double c[4] = {0, 0, 0, 0};
  Cubic(const double x[4], const double f[4]) {
    for (int j = 0; j < 4; ++j) {
      double p[4] = {1, 0, 0, 0}, denominator = 1;
      int degree = 0;
      for (int m = 0; m < 4; ++m) {
        if (m == j) continue;
        for (int d = degree + 1; d >= 1; --d) p[d] = p[d - 1] - x[m] * p[d];
        p[0] = -x[m] * p[0];
        ++degree;
        denominator *= x[j] - x[m];
      }
      for (int d = 0; d < 4; ++d) c[d] += f[j] * p[d] / denominator;
    }
  }
  double Value(double s) const { return ((c[3] * s + c[2]) * s + c[1]) * s + c[0]; }
  double Integral(double a, double b) const {
    double sum = 0, pa = a, pb = b;
    for (int d = 0; d < 4; ++d, pa *= a, pb *= b) sum += c[d] * (pb - pa) / (d + 1);
    return sum;
  }
};

// The breaks of EnergyLoopOptions on n samples. Break i is either shared (on its sample b_i,
// whose value both sides use: its walls, the last sample on its left and the first on its
// right, are both b_i) or splits an interval j_i at the fraction σ_i in [0, 1] (walls j_i and
// j_i + 1): one between samples (σ_i in (0, 1), j_i = b_i), or one on a sample whose value is
// the left side's (side -1: j_i = b_i, σ_i = 0) or the right side's (side +1: j_i = b_i − 1,
// σ_i = 1).
struct Breaks {
  const EnergyLoopOptions& o;
  int n;
  static int Wrap(int k, int n) { return ((k % n) + n) % n; }
  double Fraction(int i) const { return o.break_fractions != nullptr ? o.break_fractions[i] : 0.0; }
  int Side(int i) const { return o.break_sides != nullptr && Fraction(i) == 0 ? o.break_sides[i] : 0; }
  bool Split(int i) const { return Fraction(i) > 0 || Side(i) != 0; }
  int Interval(int i) const { return Wrap(o.breaks[i] - (Side(i) > 0 ? 1 : 0), n); }
  double Sigma(int i) const { return Side(i) > 0 ? 1.0 : (Side(i) < 0 ? 0.0 : Fraction(i)); }
  int LeftWall(int i) const { return Interval(i); }
  int RightWall(int i) const { return Split(i) ? Wrap(Interval(i) + 1, n) : o.breaks[i]; }
  // On samples or in an interval, N >= 8 for a split one, and apart (see the options).
  bool Valid() const {
    for (int i = 0; i < o.num_breaks; ++i) {
      const double s = Fraction(i);
      if (o.breaks[i] < 0 || o.breaks[i] >= n || !(s >= 0 && s < 1)) return false;
      if (o.break_sides != nullptr && (o.break_sides[i] < -1 || o.break_sides[i] > 1)) return false;
      if (Split(i) && n < 8) return false;
    }
    for (int i = 0; i < o.num_breaks; ++i) {
      for (int j = 0; j < o.num_breaks; ++j) {
        if (i == j) continue;
        if (!Split(i) && !Split(j) && o.breaks[i] == o.breaks[j]) continue;  // the same shared break
        if (Split(i) && Split(j) && Interval(i) == Interval(j) && Sigma(i) == Sigma(j)) continue;  // the same
        const int d = Wrap(LeftWall(j) - RightWall(i), n);
        if (d == 1 || d == 2) return false;
        if (d == 0 && (Split(i) || Split(j))) return false;
        if (Split(i) && Split(j) && Interval(i) == Interval(j)) return false;  // two in one interval
      }
    }
    return true;
  }
  // The interval [k, k+1] is split at *sigma in [0, 1].
  bool SplitAt(int k, double* sigma) const {
    const int kk = Wrap(k, n);
    for (int i = 0; i < o.num_breaks; ++i)
      if (Split(i) && Interval(i) == kk) return *sigma = Sigma(i), true;
    return false;
  }
  bool IsLeftWall(int k) const {  // the last sample before a break
    const int kk = Wrap(k, n);
    for (int i = 0; i < o.num_breaks; ++i)
      if (LeftWall(i) == kk) return true;
    return false;
  }
  bool IsRightWall(int k) const {  // the first sample after a break
    const int kk = Wrap(k, n);
    for (int i = 0; i < o.num_breaks; ++i)
      if (RightWall(i) == kk) return true;
    return false;
  }
  // The two sides' cubics of the interval [k, k+1] (in s = (θ − θ_k)/h) through the samples
  // g(k-3..k) and g(k+1..k+4).
  template <class G>
  static Cubic Left(int k, G g) {
    const double x[4] = {-3, -2, -1, 0}, f[4] = {g(k - 3), g(k - 2), g(k - 1), g(k)};
    return Cubic(x, f);
  }
  template <class G>
  static Cubic Right(int k, G g) {
    const double x[4] = {1, 2, 3, 4}, f[4] = {g(k + 1), g(k + 2), g(k + 3), g(k + 4)};
    return Cubic(x, f);
  }
};

}  // namespace internal

/**
 * \brief The excess energy E(θ) of the excess torque samples ΔT over one cycle, its extremes
 * and ΔE (see the file comment).
 * \param[in]  dT       ΔT_k = T_d − T_l at θ_0 + k Θ/n, k = 0..n-1 (N m), periodic
 * \param[in]  n        N >= 4
 * \param[in]  cycle    Θ (rad)
 * \param[in]  theta0   θ_0 (rad), the angle of dT[0] (E = 0 there)
 * \param[out] E        optional: n values E(θ_k) (J), E[0] = 0 (the mean removed if asked)
 */
inline EnergyLoop ExcessEnergy(const double* dT,
                               int n,
                               double cycle,
                               double theta0,
                               const EnergyLoopOptions& options = EnergyLoopOptions(),
                               double* E = nullptr) {
  EnergyLoop r;
  r.n = n;
  r.cycle = cycle;
  if (n < 4) return r;
  if (!(std::isfinite(cycle) && cycle > 0)) {
    r.status = LoopStatus::kBadCycle;
    return r;
  }
  // Breaks: on samples or inside intervals, and at least 3 intervals apart (the one-sided
  // stencils).
  const internal::Breaks breaks{options, n};
  if (!breaks.Valid()) return r;
  double sum = 0, peak = 0;
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(dT[k]) || !std::isfinite(theta0)) {
      r.status = LoopStatus::kNonFinite;
      return r;
    }
    sum += dT[k];
    peak = std::max(peak, std::abs(dT[k]));
  }
  r.mean_torque = sum / n;
  if (!std::isfinite(r.mean_torque)) {  // finite samples whose sum overflows
    r.status = LoopStatus::kNonFinite;
    return r;
  }
  double shift = 0;
  const double h = cycle / n;
  auto g = [&](int k) { return dT[((k % n) + n) % n] - shift; };
  // The integral over [θ_k, θ_k+1]: the centred 4-point rule, one-sided next to a break,
  // each side's cubic on an interval with a break inside.
  auto interval = [&](int k) {
    double sigma = 0;
    if (options.num_breaks > 0 && breaks.SplitAt(k, &sigma))
      return h * (internal::Breaks::Left(k, g).Integral(0, sigma) +
                  internal::Breaks::Right(k, g).Integral(sigma, 1));
    const bool left = options.num_breaks > 0 && breaks.IsRightWall(k);
    const bool right = options.num_breaks > 0 && breaks.IsLeftWall(k + 1);
    if (left && right) return h / 2 * (g(k) + g(k + 1));
    if (left) return h / 24 * (9 * g(k) + 19 * g(k + 1) - 5 * g(k + 2) + g(k + 3));
    if (right) return h / 24 * (9 * g(k + 1) + 19 * g(k) - 5 * g(k - 1) + g(k - 2));
    return h / 24 * (-g(k - 1) + 13 * g(k) + 13 * g(k + 1) - g(k + 2));
  };
  if (options.num_breaks > 0) {
    // The mean as the break-aware rule integrates it (the sample mean is the trapezoid's).
    double W = 0;
    for (int k = 0; k < n; ++k) W += interval(k);
    r.mean_torque = W / cycle;
    if (!std::isfinite(r.mean_torque)) {
      r.status = LoopStatus::kNonFinite;
      return r;
    }
  }
  shift = options.remove_mean ? r.mean_torque : 0.0;
  const bool steady = options.remove_mean || std::abs(r.mean_torque) <= options.mean_tolerance * peak;
  // First pass: E at the samples, the extreme samples, the cycle's work.
  double e = 0, e_hi = 0, e_lo = 0;
  int k_hi = 0, k_lo = 0;
  if (E != nullptr) E[0] = 0;
  for (int k = 0; k < n; ++k) {
    e += interval(k);
    if (k + 1 < n) {
      if (E != nullptr) E[k + 1] = e;
      if (e > e_hi) e_hi = e, k_hi = k + 1;
      if (e < e_lo) e_lo = e, k_lo = k + 1;
    }
  }
  r.cycle_work = e;
  // E at sample j of the periodic extension, j in [-1, n] (E_{-1} = E_{n-1} − W, E_n = W),
  // integrated again from θ_0 (O(N), six times: no storage needed when E is not asked for).
  auto E_at = [&](int j) {
    const int jj = ((j % n) + n) % n;
    double v = 0;
    for (int k = 0; k < jj; ++k) v += interval(k);
    if (j < 0) v -= e;
    if (j >= n) v += e;
    return v;
  };
  auto refine = [&](int k, double sign, double* value, double* theta) {
    // Candidates on [k-1, k] and [k, k+1]; keep the largest sign·E.
    double best = sign * E_at(k), best_theta = theta0 + k * h;
    auto keep = [&](double u, double v) {  // u: the angle in steps from θ_0
      if (sign * v > best) best = sign * v, best_theta = theta0 + u * h;
    };
    for (int j : {k - 1, k}) {
      const double Ej = E_at(j), Ej1 = E_at(j + 1);
      double sigma = 0;
      if (options.num_breaks > 0 && breaks.SplitAt(j, &sigma)) {
        // On each side of the break the Hermite of that side's cubic (E at the break from it).
        const internal::Cubic left = internal::Breaks::Left(j, g), right = internal::Breaks::Right(j, g);
        const double Eb = Ej + h * left.Integral(0, sigma);
        internal::HermiteCandidates(Ej, Eb, g(j), left.Value(sigma), sigma * h,
                                    [&](double s, double v) { keep(j + s * sigma, v); });
        internal::HermiteCandidates(Eb, Ej1, right.Value(sigma), g(j + 1), (1 - sigma) * h,
                                    [&](double s, double v) { keep(j + sigma + s * (1 - sigma), v); });
      } else {
        internal::HermiteCandidates(Ej, Ej1, g(j), g(j + 1), h, [&](double s, double v) { keep(j + s, v); });
      }
    }
    // Angles into [θ_0, θ_0 + Θ); a steady E is periodic, so the value needs no shift.
    if (best_theta < theta0) best_theta += cycle;
    if (best_theta >= theta0 + cycle) best_theta -= cycle;
    *value = sign * best;
    *theta = best_theta;
  };
  r.k_max = k_hi;
  r.k_min = k_lo;
  refine(k_hi, +1, &r.E_max, &r.theta_max);
  refine(k_lo, -1, &r.E_min, &r.theta_min);
  r.delta_E = r.E_max - r.E_min;
  // E is a sum of h ΔT: finite samples over a finite cycle can still overflow it.
  if (!(std::isfinite(r.cycle_work) && std::isfinite(r.delta_E))) {
    r.status = LoopStatus::kNonFinite;
    return r;
  }
  r.status = steady ? LoopStatus::kOk : LoopStatus::kNotSteady;
  return r;
}

/// The derivatives of an energy loop's figures with respect to one parameter (design
/// sensitivities, issue 27): of mean_torque, E_max, E_min and ΔE, in their units per unit of it.
struct EnergyLoopDerivative {
  double mean_torque = 0;
  double E_max = 0;
  double E_min = 0;
  double delta_E = 0;
};

/**
 * \brief The derivatives of `loop` (ExcessEnergy(dT, ...)) given the derivatives ddT_k of its
 * samples with respect to a parameter: exact for the computed figures. E is linear in the
 * samples (the same rule, mean removal and breaks: ExcessEnergy of ddT); each extreme is the
 * Hermite interpolant's value at its refined angle, a stationary point of it (or a sample), so
 * that the angle's own change does not enter to first order (the envelope theorem): dE_max is
 * the interpolant of (dE, dg) at that angle. Valid while the extremes stay on the same
 * intervals (a tie between two maxima of E makes ΔE kink: its derivative is then one-sided).
 * \param[in] ddT  n values d(ΔT_k)/dp; options and theta0 as given to ExcessEnergy for `loop`.
 * \param[out] dE  scratch for n values: dE(θ_k)/dp on return.
 */
inline EnergyLoopDerivative ExcessEnergyDerivative(const double* ddT, const EnergyLoop& loop, double theta0,
                                                   const EnergyLoopOptions& options, double* dE) {
  EnergyLoopDerivative d;
  const int n = loop.n;
  const EnergyLoop dl = ExcessEnergy(ddT, n, loop.cycle, theta0, options, dE);
  d.mean_torque = dl.mean_torque;
  const double h = loop.cycle / n;
  const double shift = options.remove_mean ? dl.mean_torque : 0.0;
  auto dg = [&](int k) { return ddT[((k % n) + n) % n] - shift; };
  const internal::Breaks breaks{options, n};
  auto dE_at = [&](int j) {  // the periodic extension, E_n = E_0 + the cycle's work
    const int jj = ((j % n) + n) % n;
    return dE[jj] + (j >= n ? dl.cycle_work : 0.0) - (j < 0 ? dl.cycle_work : 0.0);
  };
  auto at = [&](double theta) {
    double u = (theta - theta0) / h;
    int j = static_cast<int>(std::floor(u));
    double s = u - j;
    if (s > 1 - 1e-12) ++j, s = 0;  // on a sample (up to the angle's rounding)
    if (s < 1e-12) return dE_at(j);
    double sigma = 0;
    if (options.num_breaks > 0 && breaks.SplitAt(j, &sigma)) {  // as ExcessEnergy refines there
      const internal::Cubic left = internal::Breaks::Left(j, dg), right = internal::Breaks::Right(j, dg);
      const double dEb = dE_at(j) + h * left.Integral(0, sigma);
      if (s <= sigma) return internal::HermiteValue(dE_at(j), dEb, dg(j), left.Value(sigma), sigma * h, s / sigma);
      return internal::HermiteValue(dEb, dE_at(j + 1), right.Value(sigma), dg(j + 1), (1 - sigma) * h,
                                    (s - sigma) / (1 - sigma));
    }
    return internal::HermiteValue(dE_at(j), dE_at(j + 1), dg(j), dg(j + 1), h, s);
  };
  d.E_max = at(loop.theta_max);
  d.E_min = at(loop.theta_min);
  d.delta_E = d.E_max - d.E_min;
  return d;
}

/// The same from the driving and load torques sampled at the same angles (N m): ΔT_k =
/// T_d[k] − T_l[k]. `work` is scratch for n values (holds ΔT on return).
inline EnergyLoop ExcessEnergy(const double* T_d,
                               const double* T_l,
                               int n,
                               double cycle,
                               double theta0,
                               double* work,
                               const EnergyLoopOptions& options = EnergyLoopOptions(),
                               double* E = nullptr) {
  for (int k = 0; k < n; ++k) work[k] = T_d[k] - T_l[k];
  return ExcessEnergy(work, n, cycle, theta0, options, E);
}

/// The result of DeltaEFromAreas().
struct AreaLoop {
  LoopStatus status = LoopStatus::kTooFewSamples;
  double closure = 0;  ///< Σ areas (0 for a steady cycle)
  double max = 0;      ///< largest running sum (0 counts: the start)
  double min = 0;      ///< smallest running sum
  double delta = 0;    ///< max − min: ΔE in area units
  int after_max = 0;   ///< the running sum is largest after this many areas (0: at the start)
  int after_min = 0;
};

/**
 * \brief ΔE from the loop areas of a turning-moment diagram, the textbook way: the running
 * sums S_0 = 0, S_i = a_1 + … + a_i; ΔE = max S − min S (area units; multiply by the scale of
 * the diagram, e.g. (N m per mm)·(rad per mm), to get J).
 * \param[in] areas  the n signed areas in order (+ above the mean torque line, − below)
 * \param[in] closure_tolerance  |Σ a| <= closure_tolerance · Σ|a| counts as closed (steady)
 */
inline AreaLoop DeltaEFromAreas(const double* areas, int n, double closure_tolerance = 1e-9) {
  AreaLoop r;
  if (n < 1) return r;
  double s = 0, total = 0;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(areas[i])) {
      r.status = LoopStatus::kNonFinite;
      return r;
    }
    s += areas[i];
    total += std::abs(areas[i]);
    if (s > r.max) r.max = s, r.after_max = i + 1;
    if (s < r.min) r.min = s, r.after_min = i + 1;
  }
  r.closure = s;
  r.delta = r.max - r.min;
  if (!(std::isfinite(total) && std::isfinite(r.delta))) {  // the running sums overflow
    r.status = LoopStatus::kNonFinite;
    return r;
  }
  r.status = std::abs(s) <= closure_tolerance * total ? LoopStatus::kOk : LoopStatus::kNotSteady;
  return r;
}

/// The smallest C_s the tools size for: a fluctuation of a millionth of the speed. Below it a
/// C_s cannot mean anything a flywheel does (the speed of a real drive wanders by more), the
/// simulated checks cannot resolve it (their integrators keep the speed to about 1e-10
/// relative, and a cycle's mean speed is timed to about as much), and ΔE/(C_s ω_m²) runs off
/// to the end of the numbers (C_s = 1e-300 overflows).
constexpr double kMinSpeedFluctuation = 1e-6;

/// I = ΔE / (C_s ω_m²) (kg m²): the constant inertia that keeps the speed within C_s of the mean
/// speed ω_m (rad/s). NaN unless ΔE >= 0, C_s > 0, ω_m > 0 and I is finite.
inline double RequiredInertia(double delta_E, double C_s, double omega_mean) {
  if (!(delta_E >= 0 && C_s > 0 && omega_mean > 0 && std::isfinite(delta_E * C_s * omega_mean)))
    return std::numeric_limits<double>::quiet_NaN();
  const double I = delta_E / (C_s * omega_mean * omega_mean);
  return std::isfinite(I) ? I : std::numeric_limits<double>::quiet_NaN();
}

/// C_s = ΔE / (I ω_m²): the coefficient of fluctuation of speed with a constant inertia I.
/// NaN unless ΔE >= 0, I > 0, ω_m > 0 and C_s is finite.
inline double SpeedFluctuation(double delta_E, double inertia, double omega_mean) {
  if (!(delta_E >= 0 && inertia > 0 && omega_mean > 0 && std::isfinite(delta_E * inertia * omega_mean)))
    return std::numeric_limits<double>::quiet_NaN();
  const double C_s = delta_E / (inertia * omega_mean * omega_mean);
  return std::isfinite(C_s) ? C_s : std::numeric_limits<double>::quiet_NaN();
}

/// rev/min -> rad/s.
inline double RpmToRadPerSecond(double rpm) { return rpm * 2 * kPi / 60; }

/// How a speed trace was sampled: at equal time steps, or at equal crank angle steps.
enum class TraceSampling { kTime, kAngle };

enum class TraceStatus {
  kOk = 0,
  kTooFewSamples,     ///< fewer than 2 samples
  kNonFinite,         ///< a sample is NaN or infinite
  kNonPositiveSpeed,  ///< a speed <= 0 (the machine stops or reverses: no C_s)
};

/// The coefficient of fluctuation of speed of a speed trace over one steady cycle.
struct SpeedTrace {
  TraceStatus status = TraceStatus::kTooFewSamples;
  double omega_max = 0, omega_min = 0;  ///< rad/s
  int k_max = -1, k_min = -1;           ///< their samples
  double omega_mid = 0;                 ///< ½(ω_max + ω_min)
  /// The time mean: the plain mean of time samples, or Θ / ∫dθ/ω = N / Σ 1/ω_k of angle samples.
  double omega_mean = 0;
  double C_s = 0;            ///< (ω_max − ω_min)/ω_mid (the textbook definition, consistent with ΔE)
  double C_s_time_mean = 0;  ///< (ω_max − ω_min)/omega_mean
};

/// ω_max, ω_min, the means and C_s of n samples omega over one cycle (the end not repeated).
inline SpeedTrace AnalyzeSpeedTrace(const double* omega, int n, TraceSampling sampling) {
  SpeedTrace r;
  if (n < 2) return r;
  double sum = 0, inverse_sum = 0;
  r.omega_max = -std::numeric_limits<double>::infinity();
  r.omega_min = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(omega[k])) {
      r.status = TraceStatus::kNonFinite;
      return r;
    }
    if (!(omega[k] > 0)) {
      r.status = TraceStatus::kNonPositiveSpeed;
      return r;
    }
    if (omega[k] > r.omega_max) r.omega_max = omega[k], r.k_max = k;
    if (omega[k] < r.omega_min) r.omega_min = omega[k], r.k_min = k;
    sum += omega[k];
    inverse_sum += 1 / omega[k];
  }
  r.omega_mid = 0.5 * (r.omega_max + r.omega_min);
  r.omega_mean = sampling == TraceSampling::kTime ? sum / n : n / inverse_sum;
  r.C_s = (r.omega_max - r.omega_min) / r.omega_mid;
  r.C_s_time_mean = (r.omega_max - r.omega_min) / r.omega_mean;
  r.status = TraceStatus::kOk;
  return r;
}

enum class WittenbauerStatus {
  kOk = 0,
  kTooFewSamples,  ///< fewer than 2 samples
  kNonFinite,      ///< a sample or a speed is NaN or infinite
  kNonPositive,    ///< an inertia <= 0 or (analysis) a kinetic energy <= 0
  kBadSpeeds,      ///< (design) not 0 < ω_min < ω_max
  /// (design) I_f < 0: the machine alone already keeps the speed within the limits (reaching
  /// them exactly would take removing inertia); no flywheel is needed (I_f, T_0 still filled).
  kNoFlywheelNeeded,
};

/// Wittenbauer's diagram read as an analysis: the rays from the origin of the (I, T) plane
/// tangent to the curve, and the speeds they give.
struct WittenbauerSpeeds {
  WittenbauerStatus status = WittenbauerStatus::kTooFewSamples;
  double slope_max = 0, slope_min = 0;  ///< max and min of T/I (J per kg m² = (rad/s)²)
  double omega_max = 0, omega_min = 0;  ///< √(2 slope) (rad/s)
  int k_max = -1, k_min = -1;           ///< the tangent points
};

/// The speeds of a machine from samples of its generalized inertia I_k (kg m², > 0) and kinetic
/// energy T_k (J, > 0) over a cycle: ω_max² / 2 = max T/I, ω_min² / 2 = min T/I.
inline WittenbauerSpeeds Wittenbauer(const double* I, const double* T, int n) {
  WittenbauerSpeeds r;
  if (n < 2) return r;
  r.slope_max = -std::numeric_limits<double>::infinity();
  r.slope_min = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(I[k]) || !std::isfinite(T[k])) {
      r.status = WittenbauerStatus::kNonFinite;
      return r;
    }
    if (!(I[k] > 0 && T[k] > 0)) {
      r.status = WittenbauerStatus::kNonPositive;
      return r;
    }
    const double s = T[k] / I[k];
    if (s > r.slope_max) r.slope_max = s, r.k_max = k;
    if (s < r.slope_min) r.slope_min = s, r.k_min = k;
  }
  r.omega_max = std::sqrt(2 * r.slope_max);
  r.omega_min = std::sqrt(2 * r.slope_min);
  r.status = WittenbauerStatus::kOk;
  return r;
}

/// Wittenbauer's diagram read as a design (see the file comment): the flywheel and the energy
/// at θ_0 that keep the speed between ω_min and ω_max.
struct WittenbauerDesign {
  WittenbauerStatus status = WittenbauerStatus::kTooFewSamples;
  double slope_max = 0, slope_min = 0;  ///< ω_max²/2, ω_min²/2
  double c_max = 0, c_min = 0;          ///< the tangent lines E = slope I_m + c (J)
  int k_max = -1, k_min = -1;           ///< their points of contact (the samples at ω_max, ω_min)
  double I_flywheel = 0;                ///< I_f (kg m²), the constant inertia to add
  double T0 = 0;                        ///< T_0 (J), the kinetic energy at θ_0 (where E = 0)
  bool IsUsable() const { return status == WittenbauerStatus::kOk; }
};

/**
 * \brief The flywheel by Wittenbauer's tangents.
 * \param[in] I_m    the machine's generalized inertia I_m(θ_k) (kg m², >= 0), n values
 * \param[in] E      the excess work E(θ_k) (J) from θ_0, n values (e.g. from ExcessEnergy())
 * \param[in] omega_max, omega_min  the allowed speeds (rad/s), 0 < ω_min < ω_max
 */
inline WittenbauerDesign DesignByWittenbauer(
    const double* I_m, const double* E, int n, double omega_max, double omega_min) {
  WittenbauerDesign r;
  if (n < 2) return r;
  if (!std::isfinite(omega_max) || !std::isfinite(omega_min)) {
    r.status = WittenbauerStatus::kNonFinite;
    return r;
  }
  if (!(omega_min > 0 && omega_max > omega_min)) {
    r.status = WittenbauerStatus::kBadSpeeds;
    return r;
  }
  r.slope_max = 0.5 * omega_max * omega_max;
  r.slope_min = 0.5 * omega_min * omega_min;
  r.c_max = -std::numeric_limits<double>::infinity();
  r.c_min = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(I_m[k]) || !std::isfinite(E[k])) {
      r.status = WittenbauerStatus::kNonFinite;
      return r;
    }
    if (I_m[k] < 0) {
      r.status = WittenbauerStatus::kNonPositive;
      return r;
    }
    const double up = E[k] - r.slope_max * I_m[k], down = E[k] - r.slope_min * I_m[k];
    if (up > r.c_max) r.c_max = up, r.k_max = k;
    if (down < r.c_min) r.c_min = down, r.k_min = k;
  }
  r.I_flywheel = (r.c_max - r.c_min) / (r.slope_max - r.slope_min);
  r.T0 = r.slope_max * r.I_flywheel - r.c_max;
  r.status = r.I_flywheel >= 0 ? WittenbauerStatus::kOk : WittenbauerStatus::kNoFlywheelNeeded;
  return r;
}

}  // namespace mechgen::flywheel
