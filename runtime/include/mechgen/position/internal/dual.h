/**
 * \file position/internal/dual.h
 * Dual<N>: a forward-mode dual number with N derivative components, for evaluating a
 * generated Model::Phi<Scalar> once with its derivatives along N directions (exact to
 * rounding, no step size). PositionSolver uses it for L of a model whose coefficients lack
 * it (position/internal/coefficients.h): one evaluation of Phi, Phi_phi and Phi_q with their
 * derivatives in q and phi instead of two by central differences.
 *
 * The value part of every operation is the same double operation as in Model::Phi<double>,
 * so the values equal that evaluation bit for bit. Fixed size, no allocation. Covers what
 * generated constraint functions call: + - * /, comparisons, sin, cos, tan, sqrt, abs, fabs,
 * pow, exp, log, asin, acos, atan, atan2, hypot, floor, ceil.
 */
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace mechgen::internal {

template <int N>
struct Dual {
  double v = 0;
  double d[N] = {};

  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT(runtime/explicit): Scalar(0.5), int and double
  /// The variable number `i` (0 <= i < N) at `value`: derivative 1 along direction i.
  static Dual Variable(double value, int i) {
    Dual x(value);
    x.d[i] = 1;
    return x;
  }
  // a(v) -> (f(v), f'(v) d)
  static Dual Chain(double value, double slope, const Dual& a) {
    Dual r(value);
    for (int i = 0; i < N; ++i) r.d[i] = slope * a.d[i];
    return r;
  }

  Dual& operator+=(const Dual& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) d[i] += b.d[i];
    return *this;
  }
  Dual& operator-=(const Dual& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) d[i] -= b.d[i];
    return *this;
  }
  Dual& operator*=(const Dual& b) { return *this = *this * b; }
  Dual& operator/=(const Dual& b) { return *this = *this / b; }

  friend Dual operator+(const Dual& a) { return a; }
  friend Dual operator-(const Dual& a) {
    Dual r(-a.v);
    for (int i = 0; i < N; ++i) r.d[i] = -a.d[i];
    return r;
  }
  friend Dual operator+(Dual a, const Dual& b) { return a += b; }
  friend Dual operator-(Dual a, const Dual& b) { return a -= b; }
  friend Dual operator*(const Dual& a, const Dual& b) {
    Dual r(a.v * b.v);
    for (int i = 0; i < N; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
  }
  friend Dual operator/(const Dual& a, const Dual& b) {
    Dual r(a.v / b.v);
    const double inv = 1.0 / b.v;
    for (int i = 0; i < N; ++i) r.d[i] = (a.d[i] - r.v * b.d[i]) * inv;
    return r;
  }
  // With a double: the value part is exactly the double operation.
  friend Dual operator+(Dual a, double b) { return a += Dual(b); }
  friend Dual operator+(double a, Dual b) { return Dual(a) + b; }
  friend Dual operator-(Dual a, double b) { return a -= Dual(b); }
  friend Dual operator-(double a, const Dual& b) { return Dual(a) - b; }
  friend Dual operator*(const Dual& a, double b) { return Chain(a.v * b, b, a); }
  friend Dual operator*(double a, const Dual& b) { return Chain(a * b.v, a, b); }
  friend Dual operator/(const Dual& a, double b) {
    Dual r(a.v / b);
    for (int i = 0; i < N; ++i) r.d[i] = a.d[i] / b;
    return r;
  }
  friend Dual operator/(double a, const Dual& b) { return Dual(a) / b; }

  friend bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
  friend bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
  friend bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
  friend bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
  friend bool operator==(const Dual& a, const Dual& b) { return a.v == b.v; }
  friend bool operator!=(const Dual& a, const Dual& b) { return a.v != b.v; }

  friend Dual sin(const Dual& a) { return Chain(std::sin(a.v), std::cos(a.v), a); }
  friend Dual cos(const Dual& a) { return Chain(std::cos(a.v), -std::sin(a.v), a); }
  friend Dual tan(const Dual& a) {
    const double t = std::tan(a.v);
    return Chain(t, 1 + t * t, a);
  }
  friend Dual sqrt(const Dual& a) {
    const double s = std::sqrt(a.v);
    return Chain(s, 0.5 / s, a);
  }
  friend Dual abs(const Dual& a) { return Chain(std::abs(a.v), a.v < 0 ? -1.0 : 1.0, a); }
  friend Dual fabs(const Dual& a) { return abs(a); }
  friend Dual exp(const Dual& a) {
    const double e = std::exp(a.v);
    return Chain(e, e, a);
  }
  friend Dual log(const Dual& a) { return Chain(std::log(a.v), 1 / a.v, a); }
  friend Dual pow(const Dual& a, double b) {
    return Chain(std::pow(a.v, b), b * std::pow(a.v, b - 1), a);
  }
  friend Dual pow(const Dual& a, int b) { return pow(a, static_cast<double>(b)); }
  friend Dual pow(const Dual& a, const Dual& b) {
    // d(a^b) = b a^(b-1) da + a^b log(a) db
    const double value = std::pow(a.v, b.v);
    Dual r(value);
    const double da = b.v * std::pow(a.v, b.v - 1);
    const double db = a.v > 0 ? value * std::log(a.v) : 0.0;
    for (int i = 0; i < N; ++i) r.d[i] = da * a.d[i] + db * b.d[i];
    return r;
  }
  friend Dual asin(const Dual& a) { return Chain(std::asin(a.v), 1 / std::sqrt(1 - a.v * a.v), a); }
  friend Dual acos(const Dual& a) { return Chain(std::acos(a.v), -1 / std::sqrt(1 - a.v * a.v), a); }
  friend Dual atan(const Dual& a) { return Chain(std::atan(a.v), 1 / (1 + a.v * a.v), a); }
  friend Dual atan2(const Dual& y, const Dual& x) {
    Dual r(std::atan2(y.v, x.v));
    const double inv = 1 / (x.v * x.v + y.v * y.v);
    for (int i = 0; i < N; ++i) r.d[i] = (x.v * y.d[i] - y.v * x.d[i]) * inv;
    return r;
  }
  friend Dual hypot(const Dual& a, const Dual& b) {
    Dual r(std::hypot(a.v, b.v));
    for (int i = 0; i < N; ++i) r.d[i] = r.v > 0 ? (a.v * a.d[i] + b.v * b.d[i]) / r.v : 0.0;
    return r;
  }
  friend Dual floor(const Dual& a) { return Dual(std::floor(a.v)); }
  friend Dual ceil(const Dual& a) { return Dual(std::ceil(a.v)); }
};

}  // namespace mechgen::internal

namespace Eigen {
template <int N>
struct NumTraits<mechgen::internal::Dual<N>> : NumTraits<double> {
  using Real = mechgen::internal::Dual<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1 + N,
    AddCost = 1 + N,
    MulCost = 1 + 2 * N
  };
};
}  // namespace Eigen
