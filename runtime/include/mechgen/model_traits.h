/**
 * \file model_traits.h
 * The fixed-size Eigen types of a generated model and compile-time questions about it.
 *
 * A generated header (templates/mechanism.h.mustache) defines `struct Model : Sizes` with
 * sizes kNq, kNphi, kNc, kNumPoints, kNumScenePoints, the templates ParamsT<S> and
 * CoefficientsT<S>, and static functions Phi(), Coeffs() and, when it has a scene, Scene().
 * Coefficients only has the members the model asked for (K, L, r_P, K_P, L_P); the traits
 * below detect each member, so the runtime never relies on how the generator decided.
 * Everything is fixed-size: nothing here allocates.
 */
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace mechgen {

/// Fixed-size types of model M (double precision). Sizes in the names: Q = kNq,
/// Phi = kNphi, C = kNc (rows of Phi), P = kNumPoints, S = kNumScenePoints.
template <class M>
struct ModelTypes {
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kNc = M::kNc;
  static constexpr int kNumPoints = M::kNumPoints;
  static constexpr int kNumScenePoints = M::kNumScenePoints;
  static_assert(kNc == kNphi, "Phi_phi must be square: kNc == kNphi");

  using Params = typename M::template ParamsT<double>;
  using Coefficients = typename M::template CoefficientsT<double>;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using VecC = Eigen::Matrix<double, kNc, 1>;
  using VecQQ = Eigen::Matrix<double, kNq * kNq, 1>;       ///< qd (x) qd
  using MatCPhi = Eigen::Matrix<double, kNc, kNphi>;       ///< Phi_phi
  using MatCQ = Eigen::Matrix<double, kNc, kNq>;           ///< Phi_q
  using MatK = Eigen::Matrix<double, kNphi, kNq>;          ///< K
  using MatL = Eigen::Matrix<double, kNphi, kNq * kNq>;    ///< L
  using MatRP = Eigen::Matrix<double, 2, kNumPoints>;      ///< r_P
  using MatKP = Eigen::Matrix<double, 2 * kNumPoints, kNq>;        ///< K_P
  using MatLP = Eigen::Matrix<double, 2 * kNumPoints, kNq * kNq>;  ///< L_P
  using MatScene = Eigen::Matrix<double, 2, kNumScenePoints>;
};

namespace internal {

template <class C, class = void>
struct HasK : std::false_type {};
template <class C>
struct HasK<C, std::void_t<decltype(std::declval<C&>().K)>> : std::true_type {};
template <class C, class = void>
struct HasL : std::false_type {};
template <class C>
struct HasL<C, std::void_t<decltype(std::declval<C&>().L)>> : std::true_type {};
template <class C, class = void>
struct HasRP : std::false_type {};
template <class C>
struct HasRP<C, std::void_t<decltype(std::declval<C&>().r_P)>> : std::true_type {};
template <class C, class = void>
struct HasKP : std::false_type {};
template <class C>
struct HasKP<C, std::void_t<decltype(std::declval<C&>().K_P)>> : std::true_type {};
template <class C, class = void>
struct HasLP : std::false_type {};
template <class C>
struct HasLP<C, std::void_t<decltype(std::declval<C&>().L_P)>> : std::true_type {};

/// ||A||_1: the largest column sum of |a_ij|.
template <class Derived>
double Norm1(const Eigen::MatrixBase<Derived>& A) {
  return A.cwiseAbs().colwise().sum().maxCoeff();
}

}  // namespace internal

/// What model M provides, decided at compile time.
template <class M>
struct ModelFeatures {
  using Coefficients = typename ModelTypes<M>::Coefficients;
  static constexpr bool kHasK = internal::HasK<Coefficients>::value;
  static constexpr bool kHasL = internal::HasL<Coefficients>::value;
  static constexpr bool kHasPoints = M::kNumPoints > 0 && internal::HasRP<Coefficients>::value;
  static constexpr bool kHasPointVelocities = kHasPoints && internal::HasKP<Coefficients>::value;
  static constexpr bool kHasPointAccelerations =
      kHasPoints && internal::HasLP<Coefficients>::value;
  static constexpr bool kHasScene = M::kNumScenePoints > 0;
};

/**
 * \brief cond_1(A) = ||A||_1 ||A^{-1}||_1 and det A of a square fixed-size matrix.
 * \param[in]  A     Square matrix (n x n), typically Phi_phi.
 * \param[out] cond  Exact cond_1 for n <= 4 (closed-form inverse), else Eigen's
 *                   PartialPivLU 1/rcond() estimate; +inf when A is singular or not finite.
 * \param[out] det   det A (its sign labels the assembly mode).
 */
template <class Derived>
void ConditionAndDeterminant(const Eigen::MatrixBase<Derived>& A, double* cond, double* det) {
  using Matrix = typename Derived::PlainObject;
  constexpr int n = Matrix::RowsAtCompileTime;
  static_assert(n == Matrix::ColsAtCompileTime && n != Eigen::Dynamic, "square, fixed size");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if constexpr (n <= 4) {
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
template <class Derived>
void SmallestSingular(const Eigen::MatrixBase<Derived>& A,
                      double* sigma_min,
                      double* sigma_max,
                      Eigen::Matrix<double, Derived::RowsAtCompileTime, 1>* v,
                      Eigen::Matrix<double, Derived::RowsAtCompileTime, 1>* u = nullptr) {
  using Matrix = typename Derived::PlainObject;
  constexpr int n = Matrix::RowsAtCompileTime;
  static_assert(n == Matrix::ColsAtCompileTime && n != Eigen::Dynamic, "square, fixed size");
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

/// +1, -1, or 0 (zero or NaN).
inline int Sign(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

}  // namespace mechgen
