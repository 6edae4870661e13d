/**
 * \file core/linear_algebra.h
 * The small dense linear algebra of the position solver, fixed-size and allocation-free:
 * max-norms that see NaN (MaxAbsDiff), finiteness (AllFinite), cond_1 and det
 * (ConditionAndDeterminant), the smallest singular value and its vector (SmallestSingular, and
 * SingularValues2x2 in closed form), and SquareFactorization, the one factorization of Phi_phi
 * a continuation step has.
 * Needs Eigen only.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "mechgen/core/inline.h"
#include "mechgen/core/model_calls.h"

namespace mechgen {

namespace internal {

/// max_i |a_i - b_i| over the entries of two same-size fixed matrices (b = nullptr: max |a_i|),
/// NaN when any entry is NaN (Eigen's lpNorm<Infinity> leaves that to maxCoeff, which may
/// drop a NaN), so that a test `MaxAbsDiff(...) <= tolerance` fails on NaN.
/// Branch-free: which entry is largest is often rounding noise (the residual), and a
/// branch on it mispredicts about every other step (measured: 0.8 per four-bar step).
template <class A, class B = A>
MECHGEN_ALWAYS_INLINE double MaxAbsDiff(const A& a, const B* b = nullptr) {
  double m = 0;
  bool nan = false;
  // (A bounded dynamic matrix, ModelTypes<ViewModel>: its size at run time.)
  const Eigen::Index size =
      A::SizeAtCompileTime != Eigen::Dynamic ? static_cast<Eigen::Index>(A::SizeAtCompileTime) : a.size();
  if constexpr (A::SizeAtCompileTime == Eigen::Dynamic) {
    if (size <= 2) {  // (a small model's vectors without a loop: the same maximum)
      const double d0 = size > 0 ? std::abs(b == nullptr ? a.data()[0] : a.data()[0] - b->data()[0]) : 0.0;
      const double d1 = size > 1 ? std::abs(b == nullptr ? a.data()[1] : a.data()[1] - b->data()[1]) : 0.0;
      m = d0 > d1 ? d0 : d1;
      nan = (d0 != d0) | (d1 != d1);
      return nan ? std::numeric_limits<double>::quiet_NaN() : m;
    }
  }
  for (Eigen::Index i = 0; i < size; ++i) {
    const double d = std::abs(b == nullptr ? a.data()[i] : a.data()[i] - b->data()[i]);
    m = m > d ? m : d;  // maxsd
    nan = nan | (d != d);
  }
  return nan ? std::numeric_limits<double>::quiet_NaN() : m;
}

/// Every entry of a fixed-size matrix is finite: x - x is 0 exactly for finite x, NaN for inf
/// and NaN, so their sum is 0 exactly when all are. Branch-free; Eigen's allFinite() goes
/// through an unrolled evaluator that the compiler stops inlining in the continuation step's
/// functions (a call per test).
template <class A>
MECHGEN_ALWAYS_INLINE bool AllFinite(const A& a) {
  double zero = 0;
  const Eigen::Index size =
      A::SizeAtCompileTime != Eigen::Dynamic ? static_cast<Eigen::Index>(A::SizeAtCompileTime) : a.size();
  if constexpr (A::SizeAtCompileTime == Eigen::Dynamic) {
    if (size <= 2) {  // (a small model's vectors without a loop)
      const double x0 = size > 0 ? a.data()[0] : 0.0, x1 = size > 1 ? a.data()[size - 1] : 0.0;
      return (x0 - x0) + (x1 - x1) == 0;
    }
    // Four sums, not one chain of dependent additions through every entry (the same answer:
    // each is 0 exactly when its entries are finite).
    const double* x = a.data();
    double z0 = 0, z1 = 0, z2 = 0, z3 = 0;
    Eigen::Index i = 0;
    for (; i + 4 <= size; i += 4) {
      z0 += x[i] - x[i];
      z1 += x[i + 1] - x[i + 1];
      z2 += x[i + 2] - x[i + 2];
      z3 += x[i + 3] - x[i + 3];
    }
    for (; i < size; ++i) z0 += x[i] - x[i];
    return (z0 + z1) + (z2 + z3) == 0;
  }
  for (Eigen::Index i = 0; i < size; ++i) zero += a.data()[i] - a.data()[i];
  return zero == 0;
}

/// ||x||_inf and x.allFinite() of a plain matrix: Eigen's for a fixed-size x (the fixed-size
/// instantiation's code as it was); for a bounded dynamic one (ModelTypes<ViewModel>)
/// MaxAbsDiff() and AllFinite() above (the same results for finite entries; InfNorm NaN for a
/// NaN), without Eigen's dynamic-size reductions.
template <class X>
MECHGEN_ALWAYS_INLINE double InfNorm(const X& x) {
  if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
    return x.template lpNorm<Eigen::Infinity>();
  } else {
    return MaxAbsDiff(x);
  }
}
template <class X>
MECHGEN_ALWAYS_INLINE bool Finite(const X& x) {
  if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
    return x.allFinite();
  } else {
    return AllFinite(x);
  }
}

/// ||A||_1: the largest column sum of |a_ij|.
template <class Derived>
double Norm1(const Eigen::MatrixBase<Derived>& A) {
  return A.cwiseAbs().colwise().sum().maxCoeff();
}

/// Norm1() of the rows x cols column-major x for 3 <= rows <= 16, each column summed as a
/// fixed-size column of its size is (Eigen's unrolled reduction of k entries), where Eigen's
/// reduction of a run-time length adds them in another order: the view's K and L of 8 rows
/// (engine_inline4) gave K_error and L_error one ulp away from the fixed-size ones.
template <int k>
double FixedRowsNorm1(const double* x, Eigen::Index rows, Eigen::Index cols) {
  if constexpr (k > 16) {
    return Norm1(Eigen::Map<const Eigen::MatrixXd>(x, rows, cols));
  } else {
    if (rows != k) return FixedRowsNorm1<k + 1>(x, rows, cols);
    double m = Eigen::Map<const Eigen::Matrix<double, k, 1>>(x).cwiseAbs().sum();
    for (Eigen::Index j = 1; j < cols; ++j) {
      m = std::max(m, Eigen::Map<const Eigen::Matrix<double, k, 1>>(x + k * j).cwiseAbs().sum());
    }
    return m;
  }
}

/// Norm1() of a bounded dynamic matrix (ModelTypes<ViewModel>): of at most two rows, a loop
/// over its columns, |a_0j| + |a_1j| as the fixed-size sum adds them (the same value for
/// finite entries), without Eigen's dynamic-size reductions; Norm1() above otherwise.
template <class Derived>
MECHGEN_ALWAYS_INLINE double SmallNorm1(const Eigen::MatrixBase<Derived>& A) {
  if constexpr (Derived::RowsAtCompileTime == Eigen::Dynamic) {
    const Derived& a = A.derived();
    const Eigen::Index cols = a.cols();
    const double* x = a.data();
    if (a.rows() == 2 && cols > 0) {
      double m = std::abs(x[0]) + std::abs(x[1]);
      for (Eigen::Index j = 1; j < cols; ++j) m = std::max(m, std::abs(x[2 * j]) + std::abs(x[2 * j + 1]));
      return m;
    }
    if (a.rows() == 1 && cols > 0) {
      double m = std::abs(x[0]);
      for (Eigen::Index j = 1; j < cols; ++j) m = std::max(m, std::abs(x[j]));
      return m;
    }
    if (a.rows() <= 16 && cols > 0) return FixedRowsNorm1<3>(x, a.rows(), cols);
  }
  return Norm1(A);
}

}  // namespace internal

template <int k = 1, class A>
void ConditionAndDeterminantDynamic(const A& a, double* cond, double* det);

/**
 * \brief cond_1(A) = ||A||_1 ||A^{-1}||_1 and det A of a square matrix.
 * \param[in]  A     Square matrix (n x n), typically Phi_phi. Of a size known at run time
 *                   only (the model view's): ConditionAndDeterminantDynamic(), below, compiled
 *                   once for the view's two types (view/conditioning.cc); any other run-time-
 *                   sized type compiles its sixteen fixed-size LUs where it is called (about a
 *                   minute of compile per translation unit).
 * \param[out] cond  Exact cond_1 for n <= 4 (closed-form inverse), else Eigen's
 *                   PartialPivLU 1/rcond() estimate; +inf when A is singular or not finite.
 * \param[out] det   det A (its sign labels the assembly mode).
 */
template <class Derived>
void ConditionAndDeterminant(const Eigen::MatrixBase<Derived>& A, double* cond, double* det) {
  using Matrix = typename Derived::PlainObject;
  constexpr int n = Matrix::RowsAtCompileTime;
  static_assert(n == Matrix::ColsAtCompileTime, "square");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if constexpr (n == Eigen::Dynamic) {
    ConditionAndDeterminantDynamic(A.derived(), cond, det);
    return;
  } else if constexpr (n == 1) {
    // Eigen's 1 x 1 computeInverseAndDetWithCheck, written out: the same arithmetic, and no
    // inverse left unwritten when a == 0 (GCC 12 warned it may be read uninitialized).
    const double a = A.derived().coeff(0, 0);
    *det = a;
    const bool invertible = std::abs(a) > 0.0;
    const double inverse = invertible ? 1.0 / a : 0.0;
    *cond = (invertible && std::isfinite(inverse)) ? std::abs(a) * std::abs(inverse) : kInf;
  } else if constexpr (n <= 4) {
    Matrix inverse;
    bool invertible = false;
    A.derived().computeInverseAndDetWithCheck(inverse, *det, invertible, 0.0);
    *cond = (invertible && inverse.allFinite()) ? internal::Norm1(A) * internal::Norm1(inverse)
                                                : kInf;
  } else {
    const Eigen::PartialPivLU<Matrix> lu(A);
    *det = lu.determinant();
    const double rcond = lu.rcond();
    *cond = rcond > 0 ? 1.0 / rcond : kInf;
  }
  if (!std::isfinite(*cond)) *cond = kInf;
}

/// The largest square matrix ConditionAndDeterminantDynamic() takes beyond its fixed sizes
/// (the view's Phi_phi has at most ModelView::kMaxPhi = 48 rows).
inline constexpr int kMaxDynamicPhi = 64;

/**
 * \brief ConditionAndDeterminant() of a square matrix whose size is known at run time only
 *        (the view's Phi_phi, issue 43).
 *
 * On a fixed-size copy up to 16 x 16: the same arithmetic as the fixed-size instantiation, so
 * the same bits; beyond, Eigen's PartialPivLU on a bounded dynamic copy (at most
 * kMaxDynamicPhi rows; no allocation; the same method, its sums perhaps in another order).
 * The view's library compiles it once for its matrices (core/view_runtime.h: extern template).
 */
template <int k, class A>
void ConditionAndDeterminantDynamic(const A& a, double* cond, double* det) {
  if constexpr (k <= 16) {
    if (a.rows() == k) {
      ConditionAndDeterminant(Eigen::Matrix<double, k, k>(a), cond, det);
      return;
    }
    ConditionAndDeterminantDynamic<k + 1>(a, cond, det);
  } else {
    using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDynamicPhi, kMaxDynamicPhi>;
    const Eigen::PartialPivLU<Matrix> lu{Matrix(a)};
    *det = lu.determinant();
    const double rcond = lu.rcond();
    *cond = rcond > 0 && std::isfinite(1.0 / rcond) ? 1.0 / rcond : std::numeric_limits<double>::infinity();
  }
}

/**
 * \brief The smallest singular value of a square fixed-size matrix and its right singular
 *        vector: the distance of A to the nearest singular matrix in the 2-norm
 *        (Eckart–Young), and the direction A nearly annihilates.
 * \param[in]  A          Square matrix (n x n), typically Phi_phi.
 * \param[out] sigma_min  sigma_n(A) >= 0 (NaN if A is not finite).
 * \param[out] sigma_max  sigma_1(A) = ||A||_2.
 * \param[out] v          Unit right singular vector of sigma_n (dim n): A v = sigma_n u. Its
 *                        sign is fixed so that its largest-magnitude entry is positive, so
 *                        that it does not flip between neighbouring configurations.
 * \param[out] u          Unit left singular vector of sigma_n (dim n); may be nullptr.
 * Eigen's two-sided Jacobi SVD on a fixed-size matrix: no allocation, backward stable (the
 * error of sigma_n is ~ eps sigma_1, unlike the eigenvalues of A^T A whose error ~ eps
 * sigma_1^2 / sigma_n would swamp sigma_n below sqrt(eps) sigma_1), about 60 ns for 2 x 2.
 */
template <class Derived, class Vector = Eigen::Matrix<double, Derived::RowsAtCompileTime, 1>>
void SmallestSingular(const Eigen::MatrixBase<Derived>& A,
                      double* sigma_min,
                      double* sigma_max,
                      Vector* v,
                      Vector* u = nullptr) {
  using Matrix = typename Derived::PlainObject;
  static_assert(Matrix::RowsAtCompileTime == Matrix::ColsAtCompileTime, "square");
  // (Fixed size, or bounded dynamic: ModelTypes<ViewModel>.)
  const Eigen::Index n = A.rows();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!A.allFinite()) {
    *sigma_min = *sigma_max = kNaN;
    v->setConstant(kNaN);
    if (u != nullptr) u->setConstant(kNaN);
    return;
  }
  const Eigen::JacobiSVD<Matrix, Eigen::NoQRPreconditioner> svd(
      A, Eigen::ComputeFullV | (u != nullptr ? Eigen::ComputeFullU : 0));
  *sigma_min = svd.singularValues()(n - 1);
  *sigma_max = svd.singularValues()(0);
  *v = svd.matrixV().col(n - 1);
  Eigen::Index largest = 0;
  v->cwiseAbs().maxCoeff(&largest);
  const double sign = (*v)(largest) < 0 ? -1.0 : 1.0;
  *v *= sign;
  if (u != nullptr) *u = sign * svd.matrixU().col(n - 1);
}

namespace internal {
/// A^{-1} r by Eigen's PartialPivLU of A's type when its size is fixed; for a bounded dynamic A
/// (ModelTypes<ViewModel>) up to 16 x 16 by PartialPivLU of a fixed-size copy of its size k,
/// the code a generated model of that size runs. Eigen's solve() on a dynamic size takes another
/// path: its triangular solves are column-oriented loops (an axpy per column) where the
/// fixed-size ones are unrolled row by row (a dot product per entry), so the sums round in
/// another order. Measured on stephenson_coupled's 4 x 4 damped normal equations of
/// NewtonAssembler's first step: from the same matrix and right-hand side the two steps differed
/// in the last one to three bits of every entry, and the assembly after them (Newton from a
/// start some ulp away: its polished result is not a fixed point to the bit) in the last bits
/// of phi, hence of every row of the sweep. Above 16, the dynamic LU.
template <int k = 1, class A, class R>
Eigen::Matrix<double, A::RowsAtCompileTime, 1, 0, A::MaxRowsAtCompileTime, 1> SolvePartialPivLU(const A& a,
                                                                                               const R& r) {
  using Result = Eigen::Matrix<double, A::RowsAtCompileTime, 1, 0, A::MaxRowsAtCompileTime, 1>;
  if constexpr (A::RowsAtCompileTime != Eigen::Dynamic) {
    return Eigen::PartialPivLU<typename A::PlainObject>(a).solve(r);
  } else if constexpr (k > 16 || k > A::MaxRowsAtCompileTime) {
    return Result(Eigen::PartialPivLU<typename A::PlainObject>(a).solve(r));
  } else {
    if (a.rows() != k) return SolvePartialPivLU<k + 1>(a, r);
    using Fixed = Eigen::Matrix<double, k, k>;
    // Solved into a fixed-size vector, then copied: Eigen's solve() runs its triangular
    // solves on the destination's type, and on a dynamic one they are other code.
    const Eigen::Matrix<double, k, 1> x = Eigen::PartialPivLU<Fixed>(Fixed(a)).solve(Eigen::Matrix<double, k, 1>(r));
    return Result(x);
  }
}

/// A^{-1} r for a bounded dynamic square A (ModelTypes<ViewModel>): the fixed-size code of its
/// size, as PositionSolver's Newton step runs it for a generated model (the closed-form inverse
/// up to 4 x 4, PartialPivLU above), so that both give the same step to the bit.
template <class A, class R>
Eigen::Matrix<double, Eigen::Dynamic, 1, 0, A::MaxRowsAtCompileTime, 1> SolveSmallInverse(const A& a,
                                                                                         const R& r) {
  using Result = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, A::MaxRowsAtCompileTime, 1>;
  switch (a.rows()) {
    case 1:
      return Result(Eigen::Matrix<double, 1, 1>(a).inverse() * Eigen::Matrix<double, 1, 1>(r));
    case 2:
      return Result(Eigen::Matrix2d(a).inverse() * Eigen::Vector2d(r));
    case 3:
      return Result(Eigen::Matrix3d(a).inverse() * Eigen::Vector3d(r));
    case 4:
      return Result(Eigen::Matrix4d(a).inverse() * Eigen::Vector4d(r));
    default:
      return SolvePartialPivLU(a, r);
  }
}
}  // namespace internal

/// +1, -1, or 0 (zero or NaN).
inline int Sign(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

namespace internal {
/// v with its sign chosen so that its largest-magnitude entry is positive (the convention of
/// SmallestSingular(), so that a singular vector does not flip between configurations).
template <class Vec>
void FixSign(Vec* v) {
  Eigen::Index largest = 0;
  v->cwiseAbs().maxCoeff(&largest);
  if ((*v)(largest) < 0) *v = -*v;
}

/// FixSign() for two entries, without Eigen's indexed maxCoeff (a store and a reload):
/// the first entry decides on a tie, as there.
inline void FixSign2(double* x, double* y) {
  const bool flip = std::abs(*y) > std::abs(*x) ? *y < 0 : *x < 0;
  if (flip) {
    *x = -*x;
    *y = -*y;
  }
}
}  // namespace internal

/**
 * \brief Both singular values of a 2 x 2 matrix in closed form, and the right singular vectors
 *        of the smaller (and of the larger) one; the same results as SmallestSingular() at a
 *        few flops.
 *
 * For A = [a b; c d]: sigma_max = (sqrt((a + d)^2 + (c - b)^2) + sqrt((a - d)^2 + (b + c)^2)) / 2
 * (the sum of two non-negative square roots: no cancellation), and
 * sigma_min = |det A| / sigma_max: relative accuracy ~ eps sigma_max / sigma_min in sigma_min,
 * i.e. an absolute error ~ eps sigma_max as for a backward stable SVD; the textbook form
 * sqrt((|A|_F^2 - sqrt(|A|_F^4 - 4 det^2)) / 2) would lose all digits of sigma_min below
 * sqrt(eps) sigma_max. The vector v is the null vector of A^T A - sigma_min^2 I = [alpha g; g
 * beta] - sigma_min^2 I, orthogonal to the larger of its two rows: with e = alpha - beta and
 * the eigenvalue gap D = sigma_max^2 - sigma_min^2 = sqrt(e^2 + 4 g^2), that row is
 * ((e + D)/2, g) for e >= 0 and (g, (D - e)/2) else, so v ~ (-2g, |e| + D) or (|e| + D, -2g):
 * no cancellation, and D comes from its own square root, in parallel with sigma_max instead
 * of after sigma_min (a shorter chain of dependent sqrt and divisions: ~5 ns per continuation
 * step). sigma_min = |det| / sigma_max needs only the first two square roots; |w| (a third
 * square root and a division) scales v last, off the path of sigma_min, on which the
 * continuation's checks wait (one division, 1 / (sigma_max |w|), for both was a longer chain:
 * values within a few ulp of it). Its sign makes the largest-magnitude entry
 * positive (FixSign). u = the unit vector
 * orthogonal to v, sign-fixed the same way (the right singular vector of sigma_max); may be
 * nullptr. Not finite input gives NaN outputs.
 */
namespace internal {
/// SingularValues2x2() for a matrix the caller knows to be finite when known_finite is true
/// (PositionSolver: after a successful factorization), which skips the test.
inline void SingularValues2x2(const Eigen::Matrix2d& A, double* sigma_min, double* sigma_max,
                              Eigen::Vector2d* v, Eigen::Vector2d* u, bool known_finite) {
  const double a = A(0, 0), b = A(0, 1), c = A(1, 0), d = A(1, 1);
  // sqrt of sums of squares, not std::hypot (several times slower): the entries of Phi_phi
  // are lengths, far from overflow.
  const double p = std::sqrt((a + d) * (a + d) + (c - b) * (c - b));
  const double r = std::sqrt((a - d) * (a - d) + (b + c) * (b + c));
  const double smax = 0.5 * (p + r);
  const double det = a * d - b * c;
  const double alpha = a * a + c * c, beta = b * b + d * d, g = a * b + c * d;
  const double e = alpha - beta;
  const double gap = p * r;  // (p r)^2 = |A|_F^4 - 4 det^2 = e^2 + 4 g^2
  const double big = std::abs(e) + gap;  // >= |2 g|: the larger entry of w
  double w0 = e >= 0 ? -2 * g : big;
  double w1 = e >= 0 ? big : -2 * g;
  // sigma_min from the first two square roots only (its own division), so that the
  // continuation's checks on it need not wait for the vector's square root and division
  // (perf, four-bar step: those two stalls were ~45% of this function's time). The signs are
  // fixed on w before it is scaled (a positive scale changes neither the signs nor which
  // entry is largest).
  const double smin = smax > 0 ? std::abs(det) / smax : 0.0;
  const double norm_sq = w0 * w0 + w1 * w1;
  if (!known_finite && !A.allFinite()) {
    *sigma_min = *sigma_max = std::numeric_limits<double>::quiet_NaN();
    v->setConstant(std::numeric_limits<double>::quiet_NaN());
    if (u != nullptr) u->setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  *sigma_min = smin;
  *sigma_max = smax;
  double inv = 1.0;
  if (norm_sq > 0) {
    inv = 1.0 / std::sqrt(norm_sq);
  } else {  // A^T A = sigma^2 I (every vector is singular) or A = 0
    w0 = 1;
    w1 = 0;
  }
  // FixSign2(&w0, &w1), and u = (-w1, w0) with its sign fixed the same way, which follows
  // from w's: its larger entry is w's other one (the first decides on a tie).
  const double m0 = std::abs(w0), m1 = std::abs(w1);
  if (m1 > m0 ? w1 < 0 : w0 < 0) {
    w0 = -w0;
    w1 = -w1;
  }
  (*v)(0) = w0 * inv;
  (*v)(1) = w1 * inv;
  if (u != nullptr) {
    const bool keep = m0 > m1 || !(w1 > 0);
    (*u)(0) = (keep ? -w1 : w1) * inv;
    (*u)(1) = (keep ? w0 : -w0) * inv;
  }
}
}  // namespace internal

inline void SingularValues2x2(const Eigen::Matrix2d& A, double* sigma_min, double* sigma_max,
                              Eigen::Vector2d* v, Eigen::Vector2d* u = nullptr) {
  internal::SingularValues2x2(A, sigma_min, sigma_max, v, u, false);
}

/**
 * \brief One factorization of a square fixed-size matrix (typically Phi_phi) that gives its
 *        determinant, cond_1, and solves with it and its transpose. No allocation.
 *
 * Up to 4 x 4 the closed-form inverse (cofactors; several times faster than PartialPivLU for
 * these sizes), up to 16 x 16 the inverse by Gauss-Jordan with partial pivoting, both with the
 * exact cond_1 = ||A||_1 ||A^{-1}||_1 and solves as products with the inverse; above, Eigen's
 * PartialPivLU with its 1/rcond() estimate of cond_1 (a lower bound). ok() is false when A is
 * singular or not finite.
 */
template <int n, int MaxN = n>
class SquareFactorization {
 public:
  using Matrix = Eigen::Matrix<double, n, n>;
  using Vector = Eigen::Matrix<double, n, 1>;

  // 2 x 2 inline (a continuation step of a four-bar factors one), larger ones in Factor().
  MECHGEN_ALWAYS_INLINE explicit SquareFactorization(const Matrix& A) {
    if constexpr (n == 2) {
      constexpr double kInf = std::numeric_limits<double>::infinity();
      // Closed form: A^{-1} = adj(A) / det, and ||adj(A)||_1 = ||A||_inf, so
      // cond_1 = ||A||_1 ||A||_inf / |det| without forming the inverse's norms.
      // One division (1/det) serves the inverse and cond_1.
      const double a = A(0, 0), b = A(0, 1), c = A(1, 0), d = A(1, 1);
      det_ = a * d - b * c;
      ok_ = det_ != 0 && std::isfinite(det_);
      const double inv = 1.0 / det_;
      inverse_ << d * inv, -b * inv, -c * inv, a * inv;
      norm1_ = std::max(std::abs(a) + std::abs(c), std::abs(b) + std::abs(d));
      const double norm_inf = std::max(std::abs(a) + std::abs(b), std::abs(c) + std::abs(d));
      inverse_norm1_ = norm_inf * std::abs(inv);
      cond_ = ok_ ? norm1_ * norm_inf * std::abs(inv) : kInf;
      RefuseNonFinite();
    } else {
      Factor(A);
    }
  }
  bool ok() const { return ok_; }
  double determinant() const { return det_; }
  /// cond_1(A) (exact for n <= 16, else Eigen's estimate); +inf when singular.
  double condition() const { return cond_; }
  /// ||A||_1, and ||A^{-1}||_1 (exact for n <= 16: ||A||_inf / |det| for n = 2; else
  /// cond_1 / ||A||_1 from Eigen's estimate; +inf when singular), the two factors of
  /// condition(), without dividing one by the other.
  double norm1() const { return norm1_; }
  double inverse_norm1() const { return inverse_norm1_; }
  /// A^{-1} B for any number of columns.
  template <class Rhs>
  auto Solve(const Eigen::MatrixBase<Rhs>& B) const {
    using Result = Eigen::Matrix<double, n, Rhs::ColsAtCompileTime>;
    if constexpr (kHasInverse) {
      return Result(inverse_ * B);
    } else {
      return Result(lu_.solve(B));
    }
  }
  /// A^{-T} b.
  Vector SolveTransposed(const Vector& b) const {
    if constexpr (kHasInverse) {
      return inverse_.transpose() * b;
    } else {
      return lu_.transpose().solve(b);
    }
  }

 private:
  template <int, int>
  friend class SquareFactorization;
  // The factorization of a matrix larger than 2 x 2 (see the class comment).
  void Factor(const Matrix& A) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if constexpr (n <= 4) {
      bool invertible = false;
      A.computeInverseAndDetWithCheck(inverse_, det_, invertible, 0.0);
      ok_ = invertible && inverse_.allFinite() && std::isfinite(det_);
      norm1_ = internal::Norm1(A);
      inverse_norm1_ = internal::Norm1(inverse_);
      cond_ = ok_ ? norm1_ * inverse_norm1_ : kInf;
    } else if constexpr (n <= kMaxExplicitInverse) {
      // Gauss–Jordan with partial pivoting (the pivot PartialPivLU would take: the largest
      // |entry| of the column), on row-major copies: the inverse itself, so the exact cond_1
      // and solves as products with it. Eigen's rcond() estimate (solves with the LU and its
      // transpose) and the transposed LU solves of the distance estimate cost ~40% of an
      // 8 x 8 continuation step (perf, chain_4), and Eigen's inverse from the LU (its general
      // triangular-solve kernel) ~30%. Measured faster up to 16 x 16 (chain_8: 4.0 -> 3.2 us
      // per step).
      Eigen::Matrix<double, n, n, Eigen::RowMajor> work = A, inverse;
      inverse.setIdentity();
      det_ = 1;
      for (int k = 0; k < n; ++k) {
        int pivot = k;
        double largest = std::abs(work(k, k));
        for (int i = k + 1; i < n; ++i) {
          const double candidate = std::abs(work(i, k));
          if (candidate > largest) {
            largest = candidate;
            pivot = i;
          }
        }
        if (pivot != k) {
          work.row(k).swap(work.row(pivot));
          inverse.row(k).swap(inverse.row(pivot));
          det_ = -det_;
        }
        const double diagonal = work(k, k);
        det_ *= diagonal;
        if (!(diagonal != 0)) break;  // singular (or NaN): det_ is 0 or NaN, ok_ false below
        const double scale = 1.0 / diagonal;
        work.row(k) *= scale;
        inverse.row(k) *= scale;
        for (int i = 0; i < n; ++i) {
          if (i == k) continue;
          const double factor = work(i, k);
          work.row(i) -= factor * work.row(k);
          inverse.row(i) -= factor * inverse.row(k);
        }
      }
      inverse_ = inverse;
      ok_ = det_ != 0 && std::isfinite(det_) && inverse_.allFinite();
      if (!ok_) inverse_.setConstant(std::numeric_limits<double>::quiet_NaN());
      norm1_ = internal::Norm1(A);
      inverse_norm1_ = ok_ ? internal::Norm1(inverse_) : kInf;
      cond_ = ok_ ? norm1_ * inverse_norm1_ : kInf;
    } else {
      lu_.compute(A);
      det_ = lu_.determinant();
      ok_ = det_ != 0 && std::isfinite(det_);
      const double rcond = ok_ ? lu_.rcond() : 0.0;
      cond_ = rcond > 0 ? 1.0 / rcond : kInf;
      norm1_ = internal::Norm1(A);
      inverse_norm1_ = cond_ / norm1_;
    }
    RefuseNonFinite();
  }
  // Every size's last step: a cond_1 that is not finite makes the factorization singular, and a
  // singular one has ||A^{-1}||_1 = inf (as cond_1 / ||A||_1 was).
  void RefuseNonFinite() {
    if (!std::isfinite(cond_)) {
      cond_ = std::numeric_limits<double>::infinity();
      ok_ = false;
    }
    if (!ok_) inverse_norm1_ = std::numeric_limits<double>::infinity();
  }
  struct None {};
  bool ok_ = false;
  double det_ = 0;
  double cond_ = std::numeric_limits<double>::infinity();
  double norm1_ = std::numeric_limits<double>::quiet_NaN();
  double inverse_norm1_ = std::numeric_limits<double>::quiet_NaN();
  // Up to kMaxExplicitInverse the inverse is kept (closed form up to 4, Gauss-Jordan above).
  static constexpr int kMaxExplicitInverse = 16;
  static constexpr bool kHasInverse = n <= kMaxExplicitInverse;
  std::conditional_t<kHasInverse, Matrix, None> inverse_;
  std::conditional_t<kHasInverse, None, Eigen::PartialPivLU<Matrix>> lu_;
};

/**
 * \brief SquareFactorization of a matrix whose size is known at run time only (at most MaxN;
 *        the position solver instantiated for ModelTypes<ViewModel>). No allocation.
 *
 * Up to 16 x 16 it factors a fixed-size copy with SquareFactorization<k> (k the size): the same
 * arithmetic, so the same determinant, cond_1 and inverse to the bit as the fixed-size
 * instantiation; above, Eigen's PartialPivLU on the bounded matrix.
 */
template <int MaxN>
class SquareFactorization<Eigen::Dynamic, MaxN> {
 public:
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, MaxN, MaxN>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxN, 1>;

  // 2 x 2 inline (the four-bar's continuation step factors one, as the fixed-size code does),
  // the other sizes in Factor().
  MECHGEN_ALWAYS_INLINE explicit SquareFactorization(const Matrix& A) : n_(static_cast<int>(A.rows())) {
    if (n_ == 2) {
      Take(SquareFactorization<2>{Eigen::Matrix2d(A)});
    } else {
      Factor(A);
    }
  }
  bool ok() const { return ok_; }
  double determinant() const { return det_; }
  double condition() const { return cond_; }
  double norm1() const { return norm1_; }
  double inverse_norm1() const { return inverse_norm1_; }
  /// A^{-1} B for any number of columns.
  template <class Rhs>
  auto Solve(const Eigen::MatrixBase<Rhs>& B) const {
    using Result = Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime, 0, MaxN,
                                 Rhs::MaxColsAtCompileTime>;
    if (n_ <= kMaxExplicitInverse) return Result(inverse_ * B);
    return Result(lu_->solve(B));
  }
  /// A^{-T} b.
  Vector SolveTransposed(const Vector& b) const {
    if (n_ <= kMaxExplicitInverse) return inverse_.transpose() * b;
    return lu_->transpose().solve(b);
  }

 private:
  static constexpr int kMaxExplicitInverse = 16;
  // Every size but 2: the fixed-size factorization of its size up to 16, PartialPivLU above.
  MECHGEN_NOINLINE void Factor(const Matrix& A) {
    if (!FactorFixed<1>(A)) {
      lu_.emplace(A);
      det_ = lu_->determinant();
      ok_ = det_ != 0 && std::isfinite(det_);
      const double rcond = ok_ ? lu_->rcond() : 0.0;
      cond_ = rcond > 0 ? 1.0 / rcond : std::numeric_limits<double>::infinity();
      norm1_ = internal::Norm1(A);
      inverse_norm1_ = cond_ / norm1_;
      if (!std::isfinite(cond_)) {
        cond_ = std::numeric_limits<double>::infinity();
        ok_ = false;
      }
      if (!ok_) inverse_norm1_ = std::numeric_limits<double>::infinity();
    }
  }
  // The fixed-size factorization of size k (k <= 16), chosen by n_; false above 16.
  template <int k>
  bool FactorFixed(const Matrix& A) {
    if constexpr (k > kMaxExplicitInverse || k > MaxN) {
      (void)A;
      return false;
    } else {
      if (n_ != k) return FactorFixed<k + 1>(A);
      Take(SquareFactorization<k>{Eigen::Matrix<double, k, k>(A)});
      return true;
    }
  }
  // The results of the fixed-size factorization f of this size.
  template <int k>
  MECHGEN_ALWAYS_INLINE void Take(const SquareFactorization<k>& f) {
    ok_ = f.ok_;
    det_ = f.det_;
    cond_ = f.cond_;
    norm1_ = f.norm1_;
    inverse_norm1_ = f.inverse_norm1_;
    Assign(&inverse_, f.inverse_);
  }
  int n_;
  bool ok_ = false;
  double det_ = 0;
  double cond_ = std::numeric_limits<double>::infinity();
  double norm1_ = std::numeric_limits<double>::quiet_NaN();
  double inverse_norm1_ = std::numeric_limits<double>::quiet_NaN();
  Matrix inverse_;
  // Above 16 x 16 only (constructed there: a factorization of a small matrix, every
  // continuation step of the view, does not set up the bounded LU's members).
  std::optional<Eigen::PartialPivLU<Matrix>> lu_;
};

}  // namespace mechgen
