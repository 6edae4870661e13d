// Statics of the loaded four-bar per configuration, side by side (Google Benchmark).
//
// Every iteration advances the crank by 0.5 deg along a full turn (models/fourbar_loaded.yaml:
// a spring E-P, a coupler force, a rocker torque, the links' weights) and computes:
//   Kinematics   (1) the generated closed-form positions (Model::Solve, which hands sin and
//                    cos to) + EvalCoefficients: phi, K, L, the points
//   Forces       (2) (1) + EvalStatics of fourbar_loaded_forces (the model with quantities
//                    [K, L, scene, forces], no `reactions:`): Q and the driving torque
//   Reactions    (3) (1) + EvalStatics of fourbar_loaded_reactions (the same with
//                    `reactions: [A, B, C, D]`): (2) + the four pins' reactions
//   Full         (3+) (1) + EvalStatics of the shipped fourbar_loaded, which also asks for
//                    `potential`: (3) + V and dV/dq
//   FullStiffness     (3+) + EvalStiffness: d2V/dq2 and the stiffness -dQ/dq
//   NewtonEuler  (4) the same generated positions, then the numeric baseline: the points
//                    placed from the angles, the 9 x 9 Newton–Euler free-body system of the
//                    three moving links (3 equations each; unknowns: 4 pins x 2 + the crank
//                    torque) assembled and solved by a dense LU (Eigen::PartialPivLU on
//                    dynamic matrices), tests/statics/free_body.h; the description is built
//                    once, outside the timed loop, and nothing reallocates inside it.
//   NewtonEulerFixedLU     (4) with the LU on a fixed-size 9 x 9 copy of the matrix
//   NewtonEulerSolveOnly   (4) without the positions: assembly + LU from the stored angles
// The targets: (3) <= 1.5 x (1), and (4) >= 5 x (3). bench/statics/run.sh prints
// the medians and the ratios.
#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "fourbar_loaded.h"
#include "fourbar_loaded_fb.h"
#include "fourbar_loaded_forces.h"
#include "fourbar_loaded_reactions.h"
#include "fourbar_loaded_statics.h"

namespace {

namespace fl = mech::fourbar_loaded;
namespace ff = mech::fourbar_loaded_forces;
namespace fr = mech::fourbar_loaded_reactions;
namespace fs = mech::fourbar_loaded_statics;
using M = fl::Model;
using MF = ff::Model;
using MR = fr::Model;
using MS = fs::Model;
using Q1 = Eigen::Matrix<double, 1, 1>;

constexpr double kStep = 0.5 * M_PI / 180;  // 0.5 deg per configuration
double CrankAngle(long k) { return (k % 720) * kStep; }

template <typename Model>
Eigen::Matrix<double, Model::kNphi, 1> AssemblyPhi() {
  Eigen::Matrix<double, Model::kNphi, 1> phi;
  for (int i = 0; i < Model::kNphi; ++i) phi(i) = Model::kAssemblyPhi[i];
  return phi;
}

// (0) the position solve alone, as (4) calls it: what every pipeline below pays first.
void Positions(benchmark::State& state) {
  const fl::Params<double> p;
  Eigen::Matrix<double, M::kNphi, 1> phi = AssemblyPhi<M>();
  long k = 0;
  for (auto _ : state) {
    const auto report = M::Solve(p, Q1(Q1::Constant(CrankAngle(k++))), &phi);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(phi);
  }
}
BENCHMARK(Positions);

void Kinematics(benchmark::State& state) {
  const fl::Params<double> p;
  fl::Coefficients<double> c;
  fl::Trig<double> trig;
  Eigen::Matrix<double, M::kNphi, 1> phi = AssemblyPhi<M>();
  long k = 0;
  for (auto _ : state) {
    const Q1 q = Q1::Constant(CrankAngle(k++));
    const auto report = M::Solve(p, q, &phi, M::kDefaultModes, 20, 0.0, &trig);
    fl::EvalCoefficients(p, q, phi, &c, &trig);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(Kinematics);

// (1) + EvalStatics of model namespace NS (Model type Mod); EXTRA: more calls per step.
#define MECHGEN_STATICS_BENCH(NAME, NS, Mod, EXTRA)                              \
  void NAME(benchmark::State& state) {                                           \
    const NS::Params<double> p;                                                  \
    NS::Coefficients<double> c;                                                  \
    NS::Trig<double> trig;                                                       \
    NS::Statics<double> st;                                                      \
    Eigen::Matrix<double, Mod::kNphi, 1> phi = AssemblyPhi<Mod>();               \
    long k = 0;                                                                  \
    for (auto _ : state) {                                                       \
      const Q1 q = Q1::Constant(CrankAngle(k++));                                \
      const auto report = Mod::Solve(p, q, &phi, Mod::kDefaultModes, 20, 0.0, &trig); \
      NS::EvalCoefficients(p, q, phi, &c, &trig);                                \
      NS::EvalStatics(p, q, phi, c, &st, nullptr, &trig);                        \
      EXTRA;                                                                     \
      benchmark::DoNotOptimize(report);                                          \
      benchmark::DoNotOptimize(c);                                               \
      benchmark::DoNotOptimize(st);                                              \
    }                                                                            \
  }                                                                              \
  BENCHMARK(NAME)

MECHGEN_STATICS_BENCH(Forces, ff, MF, (void)0);
MECHGEN_STATICS_BENCH(Reactions, fr, MR, (void)0);
// (3s) the same reactions from a model that asks for no more than statics needs (no L, no scene).
MECHGEN_STATICS_BENCH(StaticsOnly, fs, MS, (void)0);
MECHGEN_STATICS_BENCH(Full, fl, M, (void)0);
MECHGEN_STATICS_BENCH(FullStiffness, fl, M, fl::EvalStiffness(p, q, phi, c, &st));

int PhiIndex(const char* name) {
  for (int i = 0; i < M::kNphi; ++i) {
    if (std::string(M::kPhiNames[i]) == name) return i;
  }
  return -1;
}

void NewtonEuler(benchmark::State& state) {
  const fl::Params<double> p;
  mechtest::fb::FourbarLoadedFb<fl::Params<double>> fb(p);
  const int i_cpl = PhiIndex("theta_coupler"), i_rck = PhiIndex("theta_rocker");
  Eigen::Matrix<double, M::kNphi, 1> phi = AssemblyPhi<M>();
  Eigen::VectorXd x(fb.s.num_unknowns());
  long k = 0;
  bool ok = true;
  for (auto _ : state) {
    const double q = CrankAngle(k++);
    const auto report = M::Solve(p, Q1(Q1::Constant(q)), &phi);
    fb.Place(p, q, phi(i_cpl), phi(i_rck));
    ok &= fb.s.Solve(&x);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(x.data());
  }
  if (!ok) state.SkipWithError("a Newton-Euler solve failed");
}
BENCHMARK(NewtonEuler);

// (4) with the LU on a fixed-size 9 x 9 matrix (the same assembly, copied): a baseline that
// knows its size at compile time, for scale.
void NewtonEulerFixedLU(benchmark::State& state) {
  const fl::Params<double> p;
  mechtest::fb::FourbarLoadedFb<fl::Params<double>> fb(p);
  const int i_cpl = PhiIndex("theta_coupler"), i_rck = PhiIndex("theta_rocker");
  Eigen::Matrix<double, M::kNphi, 1> phi = AssemblyPhi<M>();
  Eigen::MatrixXd A(9, 9);
  Eigen::VectorXd b(9);
  if (fb.s.num_unknowns() != 9 || fb.s.num_equations() != 9) {
    state.SkipWithError("not a 9 x 9 system");
    return;
  }
  Eigen::Matrix<double, 9, 9> A9;
  Eigen::Matrix<double, 9, 1> b9, x9;
  Eigen::PartialPivLU<Eigen::Matrix<double, 9, 9>> lu;
  long k = 0;
  for (auto _ : state) {
    const double q = CrankAngle(k++);
    const auto report = M::Solve(p, Q1(Q1::Constant(q)), &phi);
    fb.Place(p, q, phi(i_cpl), phi(i_rck));
    fb.s.Assemble(&A, &b);
    A9 = A;
    b9 = b;
    lu.compute(A9);
    x9 = lu.solve(b9);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(x9);
  }
}
BENCHMARK(NewtonEulerFixedLU);

void NewtonEulerSolveOnly(benchmark::State& state) {
  const fl::Params<double> p;
  mechtest::fb::FourbarLoadedFb<fl::Params<double>> fb(p);
  const int i_cpl = PhiIndex("theta_coupler"), i_rck = PhiIndex("theta_rocker");
  // The positions of the sweep, solved beforehand.
  std::vector<Eigen::Matrix<double, M::kNphi, 1>> sweep(720, AssemblyPhi<M>());
  for (int i = 0; i < 720; ++i) M::Solve(p, Q1(Q1::Constant(CrankAngle(i))), &sweep[i]);
  Eigen::VectorXd x(fb.s.num_unknowns());
  long k = 0;
  bool ok = true;
  for (auto _ : state) {
    const long i = k++ % 720;
    fb.Place(p, CrankAngle(i), sweep[i](i_cpl), sweep[i](i_rck));
    ok &= fb.s.Solve(&x);
    benchmark::DoNotOptimize(x.data());
  }
  if (!ok) state.SkipWithError("a Newton-Euler solve failed");
}
BENCHMARK(NewtonEulerSolveOnly);

}  // namespace

BENCHMARK_MAIN();
