// The generated functions never allocate: EvalPhi, EvalCoefficients, EvalScene,
// EvalDetPhiPhi and SolvePositions of every shipped model, in double and float, run (1) with
// Eigen's run-time malloc check armed (EIGEN_RUNTIME_NO_MALLOC + set_is_malloc_allowed(false)) and
// (2) under a global operator new counter.
//
// This TU does not link the model libraries: MECH_<NAME>_INSTANTIATING is defined for each
// (kinematics_shipped_models.h) so the headers' templates are instantiated here, compiled with
// EIGEN_RUNTIME_NO_MALLOC (a library object compiled without the macro would not be checked, and
// mixing the two would break the one-definition rule). eigen_assert is redefined to count failures,
// so the check works in Release builds too (the default eigen_assert is compiled out by NDEBUG).
#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> g_operator_new_calls{0};
}  // namespace
inline std::atomic<long> g_eigen_assert_failures{0};

// The replacements: operator new(size_t) and operator delete(void*) are the one malloc/free
// pair, kept out of line as they would be in a translation unit of their own; the array and
// sized forms forward to them, as the library's defaults do (operator new[] is counted too).
// Inlined into a caller, the malloc() or free() of one met the other's call there and GCC 12
// warned -Wmismatched-new-delete (free() on a pointer from operator new, or operator delete
// on one from malloc()).
[[gnu::noinline]] void* operator new(std::size_t size) {
  ++g_operator_new_calls;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { ::operator delete(p); }
void operator delete(void* p, std::size_t) noexcept { ::operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { ::operator delete(p); }

// clang-format off (the order matters: the macros, then Eigen, then the model headers)
#define eigen_assert(x)                    \
  do {                                     \
    if (!(x)) ++::g_eigen_assert_failures; \
  } while (false)
#define EIGEN_RUNTIME_NO_MALLOC
#include <Eigen/Core>

// Every shipped model's header, with MECH_<NAME>_INSTANTIATING defined before it.
#define MECHTEST_INSTANTIATE_MODELS_HERE
#include "kinematics_shipped_models.h"
// clang-format on

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

// Arms both checks for the lifetime of the object; reads them back on Stop().
class NoAllocationScope {
 public:
  NoAllocationScope()
      : news_(g_operator_new_calls.load()), asserts_(g_eigen_assert_failures.load()) {
    Eigen::internal::set_is_malloc_allowed(false);
  }
  ~NoAllocationScope() { Eigen::internal::set_is_malloc_allowed(true); }
  void Stop(long* news, long* eigen_mallocs) {
    Eigen::internal::set_is_malloc_allowed(true);
    *news = g_operator_new_calls.load() - news_;
    *eigen_mallocs = g_eigen_assert_failures.load() - asserts_;
  }

 private:
  long news_, asserts_;
};

// The checks are live: a dynamic Eigen vector and a new expression are both caught.
TEST(NoAllocationCheck, DetectsEigenHeapAllocationAndOperatorNew) {
  long news = 0, eigen_mallocs = 0;
  {
    NoAllocationScope scope;
    Eigen::VectorXd v(16);
    v.setOnes();
    int* volatile p = new int(3);
    scope.Stop(&news, &eigen_mallocs);
    delete p;
    EXPECT_EQ(v.sum(), 16.0);
  }
  EXPECT_GE(news, 1);
  EXPECT_GE(eigen_mallocs, 1);
}

template <class M>
class NoAllocationTest : public ::testing::Test {};
TYPED_TEST_SUITE(NoAllocationTest, mechtest::AllModels, mechtest::ModelNames);

template <class M, class Scalar>
double EvaluateAll(const std::vector<mechtest::Config<M>>& sweep) {
  const typename M::template ParamsT<Scalar> p =
      typename M::template ParamsT<double>().template Cast<Scalar>();
  double sum = 0;
  for (const auto& c : sweep) {
    const Eigen::Matrix<Scalar, M::kNq, 1> q = c.q.template cast<Scalar>();
    const Eigen::Matrix<Scalar, M::kNphi, 1> phi = c.phi.template cast<Scalar>();
    Eigen::Matrix<Scalar, M::kNc, 1> Phi;
    Eigen::Matrix<Scalar, M::kNc, M::kNphi> Phi_phi;
    Eigen::Matrix<Scalar, M::kNc, M::kNq> Phi_q;
    M::Phi(p, q, phi, &Phi, &Phi_phi, &Phi_q);
    typename M::template CoefficientsT<Scalar> coeffs;
    M::Coeffs(p, q, phi, &coeffs);
    Eigen::Matrix<Scalar, 2, M::kNumScenePoints> scene;
    M::Scene(p, q, phi, &scene);
    Scalar det = Scalar(0);
    M::DetPhiPhi(p, q, phi, &det);
    Eigen::Matrix<Scalar, M::kNphi, 1> phi_solved = phi;
    const auto report = M::Solve(p, q, &phi_solved);
    sum += double(det + phi_solved.sum()) +
           (report.status == decltype(report.status)::kConverged ? 0.0 : NAN);
    sum += double(Phi.sum() + Phi_phi.sum() + Phi_q.sum() + coeffs.K.sum() + coeffs.L.sum() +
                  coeffs.r_P.sum() + coeffs.K_P.sum() + coeffs.L_P.sum() + scene.sum());
  }
  return sum;
}

TYPED_TEST(NoAllocationTest, GeneratedFunctionsDoNotAllocate) {
  using M = TypeParam;
  const typename M::template ParamsT<double> p;
  const auto sweep = mechtest::SweepConfigs<M>(p, M::kNq == 1 ? 72 : M::kNq == 2 ? 9 : 20);
  ASSERT_FALSE(sweep.empty());
  long news = 0, eigen_mallocs = 0;
  double sum_d = 0, sum_f = 0;
  {
    NoAllocationScope scope;
    sum_d = EvaluateAll<M, double>(sweep);
    sum_f = EvaluateAll<M, float>(sweep);
    scope.Stop(&news, &eigen_mallocs);
  }
  EXPECT_EQ(news, 0) << "operator new calls";
  EXPECT_EQ(eigen_mallocs, 0) << "Eigen heap allocations (or other eigen_assert failures)";
  EXPECT_TRUE(std::isfinite(sum_d));
  EXPECT_TRUE(std::isfinite(sum_f));
}

}  // namespace
