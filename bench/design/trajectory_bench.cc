// Trajectory sensitivities (issues 27, 46): one run of the forward sensitivity equations
// (dynamics/sensitivity.h: the state and dq/dp, dqd/dp for N design parameters) against the
// N + 1 simulations of the values alone that forward differences need (dynamics/forward.h),
// and the one simulation of the values alone; the sensitivities by the staggered method (the
// state's own step, S and Sd by collocation over it, not in the error test) and by the
// simultaneous one (the whole state through the integrator, S and Sd in the error test), f_q
// and f_qd generated (EvalDynamicsJacobian) or by Jets; and the adjoint gradient of one scalar
// (dynamics/adjoint.h: q_1(t_end) plus the integral of qd^T qd / 2). Same integrator (Dop853),
// same tolerances (rtol 1e-10, atol 1e-12), same motion: the massive four-bar
// (tests/design/models/design_fourbar_massive.yaml, N = 6) swinging for 2 s from 90 deg at
// 1.5 rad/s, and the two-DOF five-bar with a spring and dampers (N = 13) for 0.6 s. The
// counters give each run's accepted steps and evaluations.
#include <benchmark/benchmark.h>

#include "design_fivebar_massive.h"
#include "design_fourbar_massive.h"
#include "mechgen/dynamics/adjoint.h"
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
double Simulate(const typename M::template ParamsT<double>& p, benchmark::State* counters = nullptr) {
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
  if (counters != nullptr) {
    counters->counters["steps"] = s.integrator.steps;
    counters->counters["rejected"] = s.integrator.rejected;
    counters->counters["rhs"] = s.integrator.rhs_evaluations;
  }
  return q_end;
}

// One simulation of the values.
template <class M>
void Values(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  for (auto _ : state) benchmark::DoNotOptimize(Simulate<M>(p));
  Simulate<M>(p, &state);
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

// One run of the forward sensitivity equations by the staggered or the simultaneous method,
// f_q and f_qd from the generated EvalDynamicsJacobian (jets = false) or from Jets of the
// generated code (jets = true).
template <class M, mechgen::dynamics::SensitivityMethod method, bool jets = false, int nodes = 6>
void Sensitivities(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  mechgen::dynamics::SensitivityOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.sample_dt = Motion<M>::kTEnd;
  o.method = method;
  o.jet_jacobians = jets;
  mechgen::dynamics::SensitivitySummary s;
  for (auto _ : state) {
    mechgen::dynamics::TrajectorySensitivity<M, Dop853, nodes> sim(p, o);
    sim.Initialize(Motion<M>::q0());
    double S_end = 0;
    sim.Simulate(0.0, Motion<M>::q0(), Motion<M>::qd0(), Motion<M>::kTEnd,
                 [&](const auto& sample) {
                   S_end = sample.S(0, 0);
                   return true;
                 },
                 &s);
    benchmark::DoNotOptimize(S_end);
  }
  if (s.status != mechgen::dynamics::Status::kSuccess) state.SkipWithError("the sensitivity run failed");
  state.counters["steps"] = s.integrator.steps;
  state.counters["rejected"] = s.integrator.rejected;
  state.counters["rhs"] = s.integrator.rhs_evaluations;
  state.counters["partials"] = s.partial_evaluations;
}

// The adjoint gradient of G = q_1(t_end) + the integral of qd^T qd / 2 with respect to the N
// design parameters (one forward run of the state, one backward run).
template <class M>
void Adjoint(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  mechgen::dynamics::SensitivityOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  using Adj = mechgen::dynamics::AdjointSensitivity<M, Dop853>;
  using VecQ = typename Adj::VecQ;
  auto terminal = [](double, const VecQ& q, const VecQ&, typename Adj::Value* out) {
    *out = typename Adj::Value();
    out->v = q(0);
    out->d_q(0) = 1;
    return true;
  };
  auto integrand = [](double, const VecQ&, const VecQ& qd, typename Adj::Value* out) {
    *out = typename Adj::Value();
    out->v = 0.5 * qd.squaredNorm();
    out->d_qd = qd;
    return true;
  };
  mechgen::dynamics::AdjointSummary s;
  for (auto _ : state) {
    Adj adjoint(p, o);
    adjoint.Initialize(Motion<M>::q0());
    double G = 0;
    typename Adj::RowP dG_dp;
    adjoint.Gradient(0.0, Motion<M>::q0(), Motion<M>::qd0(), Motion<M>::kTEnd, terminal, integrand, &G, &dG_dp, &s);
    benchmark::DoNotOptimize(dG_dp);
  }
  if (s.status != mechgen::dynamics::Status::kSuccess) state.SkipWithError("the adjoint run failed");
  state.counters["steps"] = s.steps;
  state.counters["rhs"] = s.integrator.rhs_evaluations;
  state.counters["partials"] = s.partial_evaluations;
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

// One evaluation of the state's right-hand side alone (the staggered method's stages) and one
// of the partials f_q, f_qd, f_p (its collocation nodes), at t0, q0, qd0.
template <class M, bool partials>
void Evaluation(benchmark::State& state) {
  const typename M::template ParamsT<double> p;
  using Sim = mechgen::dynamics::TrajectorySensitivity<M, Dop853>;
  Sim sim(p);
  sim.Initialize(Motion<M>::q0());
  typename Sim::StateX x, dx;
  x.template head<M::kNq>() = Motion<M>::q0();
  x.template tail<M::kNq>() = Motion<M>::qd0();
  typename Sim::Partial n;
  for (auto _ : state) {
    if constexpr (partials) {
      sim.Partials(0.0, Motion<M>::q0(), Motion<M>::qd0(), false, &n);
      benchmark::DoNotOptimize(n.F_p);
    } else {
      sim.StateDerivative(0.0, x, &dx);
      benchmark::DoNotOptimize(dx);
    }
  }
}

using FourBar = mech::design_fourbar_massive::Model;
using FiveBar = mech::design_fivebar_massive::Model;
constexpr auto kStaggered = mechgen::dynamics::SensitivityMethod::kStaggered;
constexpr auto kSimultaneous = mechgen::dynamics::SensitivityMethod::kSimultaneous;
BENCHMARK(Values<FourBar>)->Name("Trajectory/Values/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Differences<FourBar>)->Name("Trajectory/Differences/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FourBar, kStaggered>)->Name("Trajectory/Sensitivities/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FourBar, kSimultaneous>)->Name("Trajectory/Simultaneous/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FourBar, kStaggered, true>)->Name("Trajectory/JetSensitivities/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FourBar, kStaggered, false, 5>)->Name("Trajectory/Staggered5/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Adjoint<FourBar>)->Name("Trajectory/Adjoint/design_fourbar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Values<FiveBar>)->Name("Trajectory/Values/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Differences<FiveBar>)->Name("Trajectory/Differences/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FiveBar, kStaggered>)->Name("Trajectory/Sensitivities/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FiveBar, kSimultaneous>)->Name("Trajectory/Simultaneous/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FiveBar, kStaggered, true>)->Name("Trajectory/JetSensitivities/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Sensitivities<FiveBar, kStaggered, false, 5>)->Name("Trajectory/Staggered5/design_fivebar_massive")->Unit(benchmark::kMicrosecond);
BENCHMARK(Adjoint<FiveBar>)->Name("Trajectory/Adjoint/design_fivebar_massive")->Unit(benchmark::kMicrosecond);

BENCHMARK(Derivative<FourBar>)->Name("Trajectory/Derivative/design_fourbar_massive");
BENCHMARK(Derivative<FourBar, true>)->Name("Trajectory/JetDerivative/design_fourbar_massive");
BENCHMARK(Derivative<FiveBar>)->Name("Trajectory/Derivative/design_fivebar_massive");
BENCHMARK(Derivative<FiveBar, true>)->Name("Trajectory/JetDerivative/design_fivebar_massive");

BENCHMARK(Evaluation<FourBar, false>)->Name("Trajectory/StateRhs/design_fourbar_massive");
BENCHMARK(Evaluation<FourBar, true>)->Name("Trajectory/Partials/design_fourbar_massive");
BENCHMARK(Evaluation<FiveBar, false>)->Name("Trajectory/StateRhs/design_fivebar_massive");
BENCHMARK(Evaluation<FiveBar, true>)->Name("Trajectory/Partials/design_fivebar_massive");

}  // namespace
