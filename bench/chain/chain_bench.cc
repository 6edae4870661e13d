// Per-configuration cost of the N-chain (tools/make_chain.sh) for the two emission
// strategies, side by side in one run (Google Benchmark):
//   blocks/N      the generated SolvePositions in the block order (one closed-form RRR dyad
//                 per loop) + EvalCoefficients (K, L by forward substitution over blocks)
//   monolithic/N  the same functions generated with --strategy monolithic: Newton over all
//                 2N unknowns with a dense LU, K and L by one dense LU
// Each iteration moves the crank 0.5 deg along a full turn and computes positions, K, L and
// the last rocker's point; both start from the second-order predictor phi + K dq + L dq^2/2
// of the previous configuration (the closed form ignores it, Newton starts there).
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

// #include "chain_<N>.h" and "chain_<N>_monolithic.h" for every N (written by CMake).
#include "chain_headers.h"

namespace {

constexpr double kStep = 0.5 * M_PI / 180;

template <class M>
void Chain(benchmark::State& state) {
  using Vq = Eigen::Matrix<double, M::kNq, 1>;
  using Vphi = Eigen::Matrix<double, M::kNphi, 1>;
  const typename M::template ParamsT<double> p;
  typename M::template CoefficientsT<double> c;
  Vq q = Vq::Constant(M::kAssemblyQ[0]);
  Vphi phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  if (static_cast<int>(M::Solve(p, q, &phi).status) != 0) {
    state.SkipWithError("assembly failed");
    return;
  }
  M::Coeffs(p, q, phi, &c);
  long k = 0;
  int failures = 0;
  for (auto _ : state) {
    const double next = (++k % 720) * kStep;
    double dq = next - q(0);
    if (dq < -M_PI) dq += 2 * M_PI;
    phi += c.K.col(0) * dq + 0.5 * c.L.col(0) * dq * dq;
    q(0) = next;
    const auto report = M::Solve(p, q, &phi);
    failures += static_cast<int>(report.status) != 0;
    M::Coeffs(p, q, phi, &c);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
  if (failures) state.SkipWithError("a solve failed along the sweep");
  state.counters["unknowns"] = M::kNphi;
}

}  // namespace

int main(int argc, char** argv) {
#define REGISTER(n)                                                                      \
  benchmark::RegisterBenchmark("blocks/" #n, &Chain<mech::chain_##n::Model>);            \
  benchmark::RegisterBenchmark("monolithic/" #n, &Chain<mech::chain_##n##_monolithic::Model>);
#define X(n) REGISTER(n)
  MECHGEN_CHAINS
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
