/**
 * \file machines/engine/gas.h
 * Cylinder pressure laws of reciprocating engines (Paul §6.8): the gas gauge pressure p (Pa)
 * against the cycle angle a (rad) of one cylinder, a = 0 at its firing top dead centre (TDC),
 * periodic over the cycle (4π for a four-stroke, 2π for a two-stroke engine). Each law has
 * `double Pressure(double cycle_angle) const`, the interface of engine::GasTorque
 * (crank_dynamics.h), and `double cycle() const`.
 *
 *  - PressureTable: an indicator diagram, (a_i, p_i) points over one cycle, interpolated
 *    linearly and periodically (the segment from the last point wraps to the first + cycle).
 *  - PolytropicWiebeCycle: a parametric cycle. Closed part from bottom dead centre (BDC)
 *    before firing TDC to BDC after it (a in [-π, π]): a polytropic compression from the
 *    intake pressure with a Wiebe heat release,
 *        d(p V^n) = (n - 1) V^(n-1) dQ,   Q(a) = Q_total x_b(a),
 *        x_b = 1 - exp(-w ((a - a_s)/Δa)^(m+1))  for a >= a_s (0 before),
 *    so p(a) = [p_in V_bdc^n + (n - 1) Q_total ∫_{-π}^{a} V^(n-1) x_b' da] / V(a)^n (absolute
 *    pressure; the single-zone heat-release equation with the polytropic exponent n in place
 *    of the ratio of specific heats). Four-stroke: the exhaust stroke (a in (π, 2π]) at
 *    ambient pressure p_amb, the intake stroke (a in (2π, 3π)) at p_in, the blow-down and the
 *    valve events instantaneous at the dead centres. Two-stroke: the closed part only,
 *    scavenged instantaneously at BDC back to p_in. The gauge pressure is p - p_amb.
 *    V(a) = V_c + A x(a), x(a) = r (1 - cos a) + l - sqrt(l^2 - r^2 sin^2 a) the piston's
 *    distance from TDC of a centred slider-crank (no offset), A = π bore^2/4, V_c = V_d/(ε - 1),
 *    V_d = 2 r A.
 *
 * Work identities (for tests): over the closed part p dV = dQ - d(p V)/(n - 1), so
 *    W_closed = Q_total x_b(π) - (p(π) - p_in) V_bdc / (n - 1);
 * motored (Q_total = 0) the four-stroke cycle's work is the pumping loop (p_in - p_amb) V_d.
 * Units: SI (m, Pa, J, rad). Construction allocates (a table); Pressure() does not.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mechgen/core/constants.h"

namespace mechgen::engine {

namespace internal {
/// a modulo c, in [0, c).
inline double Wrap(double a, double c) {
  double x = std::fmod(a, c);
  if (x < 0) x += c;
  if (x >= c) x -= c;
  return x;
}
}  // namespace internal

/// An indicator diagram: gauge pressure (Pa) at cycle angles (rad), linear and periodic.
class PressureTable {
 public:
  PressureTable() = default;
  /// angles strictly increasing within [0, cycle) (at least 2 points), pressures finite.
  /// false with *error set otherwise (the table is then unusable).
  bool Set(std::vector<double> angles, std::vector<double> pressures, double cycle,
           std::string* error) {
    ok_ = false;
    if (!(cycle > 0) || !std::isfinite(cycle)) return Fail(error, "the cycle must be > 0");
    if (angles.size() != pressures.size() || angles.size() < 2)
      return Fail(error, "a pressure table needs at least 2 points, as many pressures as angles");
    for (size_t i = 0; i < angles.size(); ++i) {
      if (!std::isfinite(angles[i]) || !std::isfinite(pressures[i]))
        return Fail(error, "point " + std::to_string(i + 1) + " is not finite");
      if (angles[i] < 0 || angles[i] >= cycle)
        return Fail(error, "point " + std::to_string(i + 1) + ": the angle is outside [0, cycle)");
      if (i > 0 && !(angles[i] > angles[i - 1]))
        return Fail(error, "point " + std::to_string(i + 1) + ": the angles must increase strictly");
    }
    a_ = std::move(angles);
    p_ = std::move(pressures);
    cycle_ = cycle;
    ok_ = true;
    return true;
  }
  bool ok() const { return ok_; }
  double cycle() const { return cycle_; }
  /// Gauge pressure (Pa) at cycle angle a (any real: taken modulo the cycle).
  double Pressure(double a) const {
    const double x = internal::Wrap(a, cycle_);
    const size_t n = a_.size();
    // The segment [a_k, a_k+1] holding x; before a_0 or after a_n-1: the wrapping segment.
    size_t k = static_cast<size_t>(std::upper_bound(a_.begin(), a_.end(), x) - a_.begin());
    double a0, a1, p0, p1;
    if (k == 0 || k == n) {
      a0 = a_[n - 1];
      p0 = p_[n - 1];
      a1 = a_[0] + cycle_;
      p1 = p_[0];
      const double xx = k == 0 ? x + cycle_ : x;
      return p0 + (p1 - p0) * (xx - a0) / (a1 - a0);
    }
    a0 = a_[k - 1];
    a1 = a_[k];
    p0 = p_[k - 1];
    p1 = p_[k];
    return p0 + (p1 - p0) * (x - a0) / (a1 - a0);
  }

 private:
  static bool Fail(std::string* error, const std::string& what) {
    if (error != nullptr) *error = "pressure table: " + what;
    return false;
  }
  std::vector<double> a_, p_;
  double cycle_ = 4 * kPi;
  bool ok_ = false;
};

/// The parameters of PolytropicWiebeCycle (SI; angles in rad from firing TDC).
struct PolytropicWiebeParams {
  int strokes = 4;                 ///< 2 or 4
  double compression_ratio = 10;   ///< ε = V_bdc / V_c (> 1)
  double bore = 0.086;             ///< m
  double stroke = 0.086;           ///< m (2 r)
  double rod_length = 0.145;       ///< l (m), > r
  double p_intake = 1.0e5;         ///< absolute intake pressure (Pa)
  double p_ambient = 1.01325e5;    ///< absolute ambient pressure (Pa): gauge 0
  double n = 1.32;                 ///< polytropic exponent (> 1)
  double burn_start = FromDegrees(-15);  ///< a_s (rad, > -π)
  double burn_duration = FromDegrees(60);  ///< Δa (rad, > 0, a_s + Δa < π)
  double wiebe_a = 5;              ///< w: x_b = 1 - exp(-w) at the end of the burn
  double wiebe_m = 2;              ///< form factor m (>= 0)
  double heat = 800;               ///< Q_total, heat released per cycle (J, >= 0)
};

/// The parametric cycle (see the file comment). Construct, Init() (validates and tabulates
/// the heat-release integral), then Pressure().
class PolytropicWiebeCycle {
 public:
  bool Init(const PolytropicWiebeParams& P, std::string* error) {
    ok_ = false;
    P_ = P;
    auto fail = [&](const char* what) {
      if (error != nullptr) *error = std::string("pressure law: ") + what;
      return false;
    };
    if (P.strokes != 2 && P.strokes != 4) return fail("strokes must be 2 or 4");
    if (!(P.compression_ratio > 1)) return fail("the compression ratio must be > 1");
    if (!(P.bore > 0) || !(P.stroke > 0)) return fail("bore and stroke must be > 0");
    if (!(P.rod_length > P.stroke / 2)) return fail("the rod must be longer than the crank (stroke/2)");
    if (!(P.p_intake > 0) || !(P.p_ambient > 0)) return fail("the pressures must be > 0 (absolute)");
    if (!(P.n > 1)) return fail("the polytropic exponent n must be > 1");
    if (!(P.heat >= 0)) return fail("the heat released must be >= 0");
    if (!(P.burn_duration > 0) || !(P.burn_start > -kPi) ||
        !(P.burn_start + P.burn_duration < kPi))
      return fail("the burn must lie between the BDCs: -180 deg < start, start + duration < 180 deg");
    if (!(P.wiebe_a > 0) || !(P.wiebe_m >= 0)) return fail("Wiebe a must be > 0, m >= 0");
    r_ = P.stroke / 2;
    l_ = P.rod_length;
    A_ = kPi * P.bore * P.bore / 4;
    Vd_ = 2 * r_ * A_;
    Vc_ = Vd_ / (P.compression_ratio - 1);
    cycle_ = P.strokes == 4 ? 4 * kPi : 2 * kPi;
    // F(a) = ∫_{a_s}^{a} V^(n-1) x_b' da at nodes: 1024 panels over the burn and as long
    // again (however short the burn), 1024 more from there to BDC.
    const double a_end = kPi;
    const double a_mid = std::min(P.burn_start + 2 * P.burn_duration, a_end);
    x_.clear();
    for (int k = 0; k <= 1024; ++k) x_.push_back(P.burn_start + (a_mid - P.burn_start) * k / 1024);
    if (a_mid < a_end)
      for (int k = 1; k <= 1024; ++k) x_.push_back(a_mid + (a_end - a_mid) * k / 1024);
    F_.assign(x_.size(), 0.0);
    for (size_t k = 0; k + 1 < x_.size(); ++k) F_[k + 1] = F_[k] + Gauss(x_[k], x_[k + 1]);
    ok_ = true;
    return true;
  }
  bool ok() const { return ok_; }
  double cycle() const { return cycle_; }
  const PolytropicWiebeParams& params() const { return P_; }

  /// Cylinder volume (m^3) at cycle angle a.
  double Volume(double a) const {
    const double s = std::sin(a);
    return Vc_ + A_ * (r_ * (1 - std::cos(a)) + l_ - std::sqrt(l_ * l_ - r_ * r_ * s * s));
  }
  double displacement() const { return Vd_; }
  double clearance() const { return Vc_; }
  double area() const { return A_; }
  /// Burned fraction x_b at a closed-part angle a in [-π, π].
  double Burned(double a) const {
    if (a <= P_.burn_start) return 0;
    const double u = (a - P_.burn_start) / P_.burn_duration;
    return 1 - std::exp(-P_.wiebe_a * std::pow(u, P_.wiebe_m + 1));
  }
  /// Absolute pressure on the closed part, a in [-π, π].
  double ClosedPressure(double a) const {
    const double n = P_.n;
    const double Vb = Volume(kPi);
    double F = 0;
    if (a > x_.front()) {
      // the last node at or below a (a beyond BDC: the last node)
      const size_t k = static_cast<size_t>(std::upper_bound(x_.begin(), x_.end(), a) - x_.begin()) - 1;
      F = F_[k] + Gauss(x_[k], a);
    }
    return (P_.p_intake * std::pow(Vb, n) + (n - 1) * P_.heat * F) / std::pow(Volume(a), n);
  }
  /// Gauge pressure (Pa) at cycle angle a (taken modulo the cycle).
  double Pressure(double a) const {
    const double pi = kPi;
    const double x = internal::Wrap(a, cycle_);
    if (P_.strokes == 2) return ClosedPressure(x < pi ? x : x - 2 * pi) - P_.p_ambient;
    if (x <= pi) return ClosedPressure(x) - P_.p_ambient;
    if (x <= 2 * pi) return 0;                              // exhaust
    if (x < 3 * pi) return P_.p_intake - P_.p_ambient;     // intake
    return ClosedPressure(x - 4 * pi) - P_.p_ambient;      // compression
  }

 private:
  double Integrand(double a) const {
    if (a <= P_.burn_start) return 0;
    const double u = (a - P_.burn_start) / P_.burn_duration;
    const double m = P_.wiebe_m;
    const double dx = P_.wiebe_a * (m + 1) / P_.burn_duration * std::pow(u, m) *
                      std::exp(-P_.wiebe_a * std::pow(u, m + 1));
    return std::pow(Volume(a), P_.n - 1) * dx;
  }
  /// 5-point Gauss-Legendre on [a, b].
  double Gauss(double a, double b) const {
    static constexpr double x[5] = {0.0, 0.5384693101056831, -0.5384693101056831,
                                    0.9061798459386640, -0.9061798459386640};
    static constexpr double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
                                    0.2369268850561891, 0.2369268850561891};
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    double s = 0;
    for (int i = 0; i < 5; ++i) s += w[i] * Integrand(c + h * x[i]);
    return s * h;
  }

  PolytropicWiebeParams P_;
  double r_ = 0, l_ = 0, A_ = 0, Vd_ = 0, Vc_ = 0, cycle_ = 4 * kPi;
  std::vector<double> x_, F_;  ///< nodes from the burn's start to BDC, the integral there
  bool ok_ = false;
};

}  // namespace mechgen::engine
