// Trajectory sensitivities (issue 27): one run of the forward sensitivity equations
// (dynamics/sensitivity.h: the state and dq/dp, dqd/dp for N design parameters integrated
// together) against the N + 1 simulations of the values alone that forward differences need
// (dynamics/forward.h), and the one simulation of the values alone; the sensitivities with the
// right-hand side's Jacobians generated (EvalDynamicsJacobian) and by Jets, side by side. Same integrator (Dop853),
// same tolerances (rtol 1e-10, atol 1e-12), same motion: the massive four-bar
// (tests/design/models/design_fourbar_massive.yaml, N = 6) swinging for 2 s from 90 deg at
// 1.5 rad/s, and the two-DOF five-bar with a spring and dampers (N = 13) for 0.6 s.
#include <benchmark/benchmark.h>

#include "design_fivebar_massive.h"
#include "design_fourbar_massive.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/sensitivity.h"

namespace {

using mechgen::dynamics::Dop853;

template <class M>
struct Motion;
template <>
struct Motion<mech::design_fourbar_massive::Model> {
  static Eigen::Matrix<double, 1, 1> q0() { return Eigen::Matrix<double, 1, 1>(M_PI / 2); }
  static Eigen::Matrix<double, 1, 1> qd0() { return Eigen::Matrix<double, 1, 1>(1.5); }
  static constexpr double kTEnd = 2.0;
};
template <>
struct Motion<mech::design_fivebar_massive::Model> {
  static Eigen::Matrix<double, 2, 1> q0() { return Eigen::Matrix<double, 2, 1>(M_PI / 2, M_PI / 2); }
  static Eigen::Matrix<double, 2, 1> qd0() { return Eigen::Matrix<double, 2, 1>(0.3, -0.2); }
  static constexpr double kTEnd = 0.6;
};

template <class M>
double Simulate(const typename M::template ParamsT<double>& p) {
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.sample_dt = Motion<M>::kTEnd;  // the start and the end only
  o.restart_at_switches = false;
  mechgen::dynamics::MinimalDynamics<M, Dop853> sim(p, o);
  sim.Initialize(Motion<M>::q0());
  mechgen::dynamics::MinimalSummary s;
  double q_end = 0;
  sim.Simulate(0.0, Motion<M>::q0(), Motion<M>::qd0(), Motion<M>::kTEnd,
               [&](const auto& sample) {
                 q_end = sample.q(0);
                 return true;
               },
               &s);
  return q_end;
}

// One simulation of the values.
template <class M>
void Values(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  for (auto _ : state) benchmark::DoNotOptimize(Simulate<M>(p));
}

// N + 1 simulations: the values and one per design parameter moved (forward differences).
template <class M>
void Differences(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  for (auto _ : state) {
    double sum = Simulate<M>(p);
    for (int d = 0; d < M::kNumDesign; ++d) {
      auto moved = p;
      *moved.Find(M::kDesignNames[d]) += 1e-6;
      sum += Simulate<M>(moved);
    }
    benchmark::DoNotOptimize(sum);
  }
}

// One run of the forward sensitivity equations, f_q and f_qd from the generated
// EvalDynamicsJacobian (jets = false) or from Jets of the generated code (jets = true).
template <class M, bool jets = false>
void Sensitivities(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  mechgen::dynamics::SensitivityOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.sample_dt = Motion<M>::kTEnd;
  o.jet_jacobians = jets;
  for (auto _ : state) {
    mechgen::dynamics::TrajectorySensitivity<M, Dop853> sim(p, o);
    sim.Initialize(Motion<M>::q0());
    mechgen::dynamics::SensitivitySummary s;
    double S_end = 0;
    sim.Simulate(0.0, Motion<M>::q0(), Motion<M>::qd0(), Motion<M>::kTEnd,
                 [&](const auto& sample) {
                   S_end = sample.S(0, 0);
                   return true;
                 },
                 &s);
    benchmark::DoNotOptimize(S_end);
  }
}

// One evaluation of the right-hand side with the sensitivities (Derivative at t0, q0, qd0 with S
// and Sd set to 0.01): f_q and f_qd generated (jets = false) or by Jets (jets = true).
template <class M, bool jets = false>
void Derivative(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  mechgen::dynamics::SensitivityOptions o;
  o.jet_jacobians = jets;
  using Sim = mechgen::dynamics::TrajectorySensitivity<M, Dop853>;
  Sim sim(p, o);
  sim.Initialize(Motion<M>::q0());
  typename Sim::State y = Sim::State::Constant(0.01), dy;
  y.template head<M::kNq>() = Motion<M>::q0();
  y.template segment<M::kNq>(M::kNq) = Motion<M>::qd0();
  for (auto _ : state) {
    sim.Derivative(0.0, y, &dy);
    benchmark::DoNotOptimize(dy);
  }
}

using FourBar = mech::design_fourbar_massive::Model;
using FiveBar = mech::design_fivebar_massive::Model;
BENCHMARK(Values<FourBar>)->Name("Trajectory/Values/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Differences<FourBar>)->Name("Trajectory/Differences/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FourBar>)->Name("Trajectory/Sensitivities/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FourBar, true>)->Name("Trajectory/JetSensitivities/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Values<FiveBar>)->Name("Trajectory/Values/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Differences<FiveBar>)->Name("Trajectory/Differences/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FiveBar>)->Name("Trajectory/Sensitivities/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FiveBar, true>)->Name("Trajectory/JetSensitivities/design_fivebar_massive")->Unit(benchmark::kMicrosecond);

BENCHMARK(Derivative<FourBar>)->Name("Trajectory/Derivative/design_fourbar_massive");
BENCHMARK(Derivative<FourBar, true>)->Name("Trajectory/JetDerivative/design_fourbar_massive");
BENCHMARK(Derivative<FiveBar>)->Name("Trajectory/Derivative/design_fivebar_massive");
BENCHMARK(Derivative<FiveBar, true>)->Name("Trajectory/JetDerivative/design_fivebar_massive");

}  // namespace
