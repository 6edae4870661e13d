// Design sensitivities per configuration (issue 27): the values alone, the values with the
// generated derivatives with respect to the design parameters, and the same values code
// instantiated with ceres::Jet<double, N> (forward-mode automatic differentiation seeded on
// the N design parameters). One configuration per iteration, cycling through a crank turn in
// 0.5 deg steps on the model's default assembly branch.
#include <benchmark/benchmark.h>
#include <ceres/jet.h>

#include <cmath>
#include <vector>

#include "fourbar.h"
#include "watt_sixbar.h"

namespace {

template <class M>
std::vector<Eigen::Matrix<double, M::kNq, 1>> Inputs() {
  std::vector<Eigen::Matrix<double, M::kNq, 1>> q(720);
  for (int k = 0; k < 720; ++k) q[k](0) = M::kQMin[0] + (M::kQMax[0] - M::kQMin[0]) * k / 720.0;
  return q;
}

template <class M>
void Values(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  const auto qs = Inputs<M>();
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  typename M::template CoefficientsT<double> c;
  size_t k = 0;
  for (auto _ : state) {
    const auto& q = qs[k];
    k = k + 1 == qs.size() ? 0 : k + 1;
    M::Solve(p, q, &phi);
    M::Coeffs(p, q, phi, &c);
    benchmark::DoNotOptimize(c);
  }
}

template <class M>
void Derivatives(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  const auto qs = Inputs<M>();
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  typename M::template CoefficientsT<double> c;
  typename M::template DesignDerivativesT<double> d;
  size_t k = 0;
  for (auto _ : state) {
    const auto& q = qs[k];
    k = k + 1 == qs.size() ? 0 : k + 1;
    M::Solve(p, q, &phi);
    M::Coeffs(p, q, phi, &c);
    M::Design(p, q, phi, &d);
    benchmark::DoNotOptimize(c);
    benchmark::DoNotOptimize(d);
  }
}

template <class M>
void Jet(benchmark::State& state) {
  using J = ceres::Jet<double, M::kNumDesign>;
  const typename M::template ParamsT<double> p0;
  auto p = p0.template Cast<J>();
  for (int d = 0; d < M::kNumDesign; ++d) {
    J* v = p.Find(M::kDesignNames[d]);
    *v = J(v->a, d);
  }
  const auto qs = Inputs<M>();
  std::vector<Eigen::Matrix<J, M::kNq, 1>> qj;
  for (const auto& q : qs) qj.push_back(q.template cast<J>());
  Eigen::Matrix<J, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = J(M::kAssemblyPhi[i]);
  typename M::template CoefficientsT<J> c;
  size_t k = 0;
  for (auto _ : state) {
    const auto& q = qj[k];
    k = k + 1 == qj.size() ? 0 : k + 1;
    M::Solve(p, q, &phi);
    M::Coeffs(p, q, phi, &c);
    benchmark::DoNotOptimize(c);
  }
}

}  // namespace

BENCHMARK(Values<mech::fourbar::Model>)->Name("Values/fourbar");
BENCHMARK(Derivatives<mech::fourbar::Model>)->Name("Derivatives/fourbar");
BENCHMARK(Jet<mech::fourbar::Model>)->Name("Jet/fourbar");
BENCHMARK(Values<mech::watt_sixbar::Model>)->Name("Values/watt_sixbar");
BENCHMARK(Derivatives<mech::watt_sixbar::Model>)->Name("Derivatives/watt_sixbar");
BENCHMARK(Jet<mech::watt_sixbar::Model>)->Name("Jet/watt_sixbar");
BENCHMARK_MAIN();
