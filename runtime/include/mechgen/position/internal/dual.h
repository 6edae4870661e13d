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
 *
 * HyperDual<N>: the same with the second derivatives too (value, gradient d[N] and the
 * symmetric matrix dd[N][N] of second derivatives), for the second derivatives of Phi along
 * the motion (L of a model whose coefficients lack it, from Model::Coeffs with the sin and
 * cos of a closed-form Solve: position/internal/coefficients.h). Covers the same functions.
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

/// Second-order forward mode: x = v + sum_i d_i t_i + 1/2 sum_ij dd_ij t_i t_j (+ O(t^3)), the
/// value, first and second derivatives of a function along N directions t_i. An input moving
/// along a straight line x0 + sum_i w_i t_i has d = w and dd = 0; every operation applies the
/// chain rule f(a)_ij = f'(a) a_ij + f''(a) a_i a_j.
template <int N>
struct HyperDual {
  double v = 0;
  double d[N] = {};
  double dd[N][N] = {};

  HyperDual() = default;
  HyperDual(double value) : v(value) {}  // NOLINT(runtime/explicit): Scalar(0.5), int and double
  /// f(a) from f(a.v) = value, f'(a.v) = slope, f''(a.v) = curvature.
  static HyperDual Chain(double value, double slope, double curvature, const HyperDual& a) {
    HyperDual r(value);
    for (int i = 0; i < N; ++i) r.d[i] = slope * a.d[i];
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) r.dd[i][j] = slope * a.dd[i][j] + curvature * a.d[i] * a.d[j];
    }
    return r;
  }

  HyperDual& operator+=(const HyperDual& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) d[i] += b.d[i];
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) dd[i][j] += b.dd[i][j];
    }
    return *this;
  }
  HyperDual& operator-=(const HyperDual& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) d[i] -= b.d[i];
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) dd[i][j] -= b.dd[i][j];
    }
    return *this;
  }
  HyperDual& operator*=(const HyperDual& b) { return *this = *this * b; }
  HyperDual& operator/=(const HyperDual& b) { return *this = *this / b; }

  friend HyperDual operator+(const HyperDual& a) { return a; }
  friend HyperDual operator-(const HyperDual& a) { return Chain(-a.v, -1, 0, a); }
  friend HyperDual operator+(HyperDual a, const HyperDual& b) { return a += b; }
  friend HyperDual operator-(HyperDual a, const HyperDual& b) { return a -= b; }
  // (ab)_ij = a_ij b + a_i b_j + a_j b_i + a b_ij
  friend HyperDual operator*(const HyperDual& a, const HyperDual& b) {
    HyperDual r(a.v * b.v);
    for (int i = 0; i < N; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        r.dd[i][j] = a.dd[i][j] * b.v + a.d[i] * b.d[j] + a.d[j] * b.d[i] + a.v * b.dd[i][j];
      }
    }
    return r;
  }
  // r = a / b from a = r b: r_i = (a_i - r b_i) / b, r_ij = (a_ij - r_i b_j - r_j b_i - r b_ij) / b
  friend HyperDual operator/(const HyperDual& a, const HyperDual& b) {
    HyperDual r(a.v / b.v);
    const double inv = 1.0 / b.v;
    for (int i = 0; i < N; ++i) r.d[i] = (a.d[i] - r.v * b.d[i]) * inv;
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        r.dd[i][j] =
            (a.dd[i][j] - r.d[i] * b.d[j] - r.d[j] * b.d[i] - r.v * b.dd[i][j]) * inv;
      }
    }
    return r;
  }
  friend HyperDual operator+(HyperDual a, double b) { return a += HyperDual(b); }
  friend HyperDual operator+(double a, HyperDual b) { return HyperDual(a) + b; }
  friend HyperDual operator-(HyperDual a, double b) { return a -= HyperDual(b); }
  friend HyperDual operator-(double a, const HyperDual& b) { return HyperDual(a) - b; }
  friend HyperDual operator*(const HyperDual& a, double b) { return Chain(a.v * b, b, 0, a); }
  friend HyperDual operator*(double a, const HyperDual& b) { return Chain(a * b.v, a, 0, b); }
  friend HyperDual operator/(const HyperDual& a, double b) { return Chain(a.v / b, 1 / b, 0, a); }
  friend HyperDual operator/(double a, const HyperDual& b) { return HyperDual(a) / b; }

  friend bool operator<(const HyperDual& a, const HyperDual& b) { return a.v < b.v; }
  friend bool operator>(const HyperDual& a, const HyperDual& b) { return a.v > b.v; }
  friend bool operator<=(const HyperDual& a, const HyperDual& b) { return a.v <= b.v; }
  friend bool operator>=(const HyperDual& a, const HyperDual& b) { return a.v >= b.v; }
  friend bool operator==(const HyperDual& a, const HyperDual& b) { return a.v == b.v; }
  friend bool operator!=(const HyperDual& a, const HyperDual& b) { return a.v != b.v; }

  friend HyperDual sin(const HyperDual& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return Chain(s, c, -s, a);
  }
  friend HyperDual cos(const HyperDual& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return Chain(c, -s, -c, a);
  }
  friend HyperDual tan(const HyperDual& a) {
    const double t = std::tan(a.v);
    return Chain(t, 1 + t * t, 2 * t * (1 + t * t), a);
  }
  friend HyperDual sqrt(const HyperDual& a) {
    const double s = std::sqrt(a.v);
    return Chain(s, 0.5 / s, -0.25 / (s * a.v), a);
  }
  friend HyperDual abs(const HyperDual& a) {
    return Chain(std::abs(a.v), a.v < 0 ? -1.0 : 1.0, 0, a);
  }
  friend HyperDual fabs(const HyperDual& a) { return abs(a); }
  friend HyperDual exp(const HyperDual& a) {
    const double e = std::exp(a.v);
    return Chain(e, e, e, a);
  }
  friend HyperDual log(const HyperDual& a) {
    return Chain(std::log(a.v), 1 / a.v, -1 / (a.v * a.v), a);
  }
  friend HyperDual pow(const HyperDual& a, double b) {
    return Chain(std::pow(a.v, b), b * std::pow(a.v, b - 1), b * (b - 1) * std::pow(a.v, b - 2),
                 a);
  }
  friend HyperDual pow(const HyperDual& a, int b) { return pow(a, static_cast<double>(b)); }
  friend HyperDual pow(const HyperDual& a, const HyperDual& b) {
    // a^b = exp(b log a), its value std::pow's
    HyperDual r = exp(b * log(a));
    r.v = std::pow(a.v, b.v);
    return r;
  }
  friend HyperDual asin(const HyperDual& a) {
    const double w = 1 / (1 - a.v * a.v);  // f' = sqrt(w), f'' = a w^(3/2)
    return Chain(std::asin(a.v), std::sqrt(w), a.v * w * std::sqrt(w), a);
  }
  friend HyperDual acos(const HyperDual& a) {
    const double w = 1 / (1 - a.v * a.v);
    return Chain(std::acos(a.v), -std::sqrt(w), -a.v * w * std::sqrt(w), a);
  }
  friend HyperDual atan(const HyperDual& a) {
    const double w = 1 / (1 + a.v * a.v);
    return Chain(std::atan(a.v), w, -2 * a.v * w * w, a);
  }
  // theta_i = (x y_i - y x_i) / r2, r2 = x^2 + y^2;
  // theta_ij = (x_j y_i + x y_ij - y_j x_i - y x_ij - 2 theta_i (x x_j + y y_j)) / r2
  friend HyperDual atan2(const HyperDual& y, const HyperDual& x) {
    HyperDual r(std::atan2(y.v, x.v));
    const double inv = 1 / (x.v * x.v + y.v * y.v);
    for (int i = 0; i < N; ++i) r.d[i] = (x.v * y.d[i] - y.v * x.d[i]) * inv;
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        r.dd[i][j] = (x.d[j] * y.d[i] + x.v * y.dd[i][j] - y.d[j] * x.d[i] - y.v * x.dd[i][j] -
                      2 * r.d[i] * (x.v * x.d[j] + y.v * y.d[j])) *
                     inv;
      }
    }
    return r;
  }
  // h_i = (x x_i + y y_i) / h, h_ij = (x_i x_j + x x_ij + y_i y_j + y y_ij - h_i h_j) / h
  friend HyperDual hypot(const HyperDual& x, const HyperDual& y) {
    HyperDual r(std::hypot(x.v, y.v));
    if (!(r.v > 0)) return r;
    const double inv = 1 / r.v;
    for (int i = 0; i < N; ++i) r.d[i] = (x.v * x.d[i] + y.v * y.d[i]) * inv;
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) {
        r.dd[i][j] = (x.d[i] * x.d[j] + x.v * x.dd[i][j] + y.d[i] * y.d[j] + y.v * y.dd[i][j] -
                      r.d[i] * r.d[j]) *
                     inv;
      }
    }
    return r;
  }
  friend HyperDual floor(const HyperDual& a) { return HyperDual(std::floor(a.v)); }
  friend HyperDual ceil(const HyperDual& a) { return HyperDual(std::ceil(a.v)); }
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
template <int N>
struct NumTraits<mechgen::internal::HyperDual<N>> : NumTraits<double> {
  using Real = mechgen::internal::HyperDual<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1 + N + N * N,
    AddCost = 1 + N + N * N,
    MulCost = 1 + 2 * N + 4 * N * N
  };
};
}  // namespace Eigen
