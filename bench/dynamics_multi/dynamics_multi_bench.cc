// The five-bar robot in a pick-and-place cycle (robot_cycle.h: the tool's 1 s cycle, PD-
// controlled motors, gravity), mechgen against Simbody, side by side (Google Benchmark;
// medians by bench/dynamics_multi/run.sh).
//   Rhs/Mechgen              one right-hand side of the two-DOF minimal method:
//                            PrescribedDynamics<Robot, 0, ...>::Derivative (the generated
//                            closed-form positions, K, L, I, h, Q, the PD torques, qdd by LDLT)
//   Rhs/Simbody<Label>       Simbody: set t, q, u of a recorded state, realize(Acceleration)
//                            (positions, velocities, forces, the loop constraint's multiplier)
//   Simulate/<method>/<tol>  the 1 s cycle from rest at q_ref(0), integrator tolerance tol;
//                            counters: error = max_i |q_i(1 s) - reference| (rad), steps, rhs
//                            (Simbody: realizations). Methods: MechgenDopri5, MechgenDop853,
//                            Simbody<Label>{RKMerson,RKFeldberg,CPodes}, and each again with
//                            "Breaks": integrated piece by piece between the set point's breaks
//                            (robot_cycle.h kCycleBreaks), the integrator started again at each.
//   Chain/Mechgen/<N>        one right-hand side of the N-loop chain (make_dyn_chain.sh: N
//                            massive crank-rocker loops in series, one input, gravity):
//                            MinimalDynamics<dyn_chain_N>::Derivative, N = 1, 2, 4, 8, 16
//   Chain/Simbody<Label>/<N> the same chain in Simbody (simbody_chain.cc): realize(Acceleration)
//                            at recorded states (positions, velocities, forces, N loop constraints)
// The reference q(1 s): mechgen with Dop853 at rtol = atol = 1e-13, restarted at the breaks of
// the set point's law (robot_cycle.h kCycleBreaks); its difference to Simbody
// RKMerson at accuracy 1e-12 is printed in the context (reference_vs_simbody).
// MECHGEN_BENCH_SIMBODY_ONLY (the binary linked to the Release Simbody): only the Simbody
// benchmarks are registered (the reference is still mechgen's).
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_fivebar_robot.h"
#include "dyn_chain_1.h"
#include "dyn_chain_16.h"
#include "dyn_chain_2.h"
#include "dyn_chain_4.h"
#include "dyn_chain_8.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/prescribed.h"
#include "robot_cycle.h"
#include "simbody_chain.h"
#include "simbody_fivebar.h"

#ifndef MECHGEN_BENCH_SIMBODY_LABEL
#define MECHGEN_BENCH_SIMBODY_LABEL "Simbody"
#endif

namespace {

using namespace bench_multi;
namespace dyn = mechgen::dynamics;
using Robot = mech::bench_fivebar_robot::Model;
using V2 = Eigen::Vector2d;
using V0 = Eigen::Matrix<double, 0, 1>;
constexpr double kTEnd = 1.0;

struct PD {
  RobotParams p;
  void operator()(double t, const V2& q, const V2& qd, V2* F) const {
    double tau[2];
    Torques(p, t, q.data(), qd.data(), tau);
    (*F)(0) = tau[0];
    (*F)(1) = tau[1];
  }
};
using Drive0 = dyn::Drive<>;
template <template <int> class Method>
using Sim = dyn::PrescribedDynamics<Robot, 0, Drive0, PD, Method>;

struct SimResult {
  double q[2] = {NAN, NAN};
  long steps = 0, rhs = 0;
  bool ok = false;
};

// breaks: integrate piece by piece between robot_cycle.h's kCycleBreaks (the integrator starts
// again at each: Simulate() from the last sample; the position reference is kept).
template <template <int> class Method, bool kBreaks = false>
SimResult SimulateMechgen(double tol) {
  dyn::PrescribedOptions o;
  o.integrator.rtol = tol;
  o.integrator.atol = tol;
  o.sample_dt = kTEnd;  // samples at 0 and at the end only
  Sim<Method> sim(Robot::ParamsT<double>(), {}, Drive0(), PD(), o);
  double q0[2], qd0[2];
  Commanded(RobotParams(), 0.0, q0, qd0);
  SimResult r;
  if (!sim.Initialize(0.0, V2(q0[0], q0[1]))) return r;
  dyn::PrescribedSummary summary;
  typename Sim<Method>::SampleT last;
  last.t = 0.0;
  last.q = V2(q0[0], q0[1]);
  last.qd = V2::Zero();
  r.ok = true;
  auto piece = [&](double t_to) {
    if (!r.ok) return;
    r.ok = sim.Simulate(last.t, last.q, last.qd, t_to,
                        [](const typename Sim<Method>::SampleT&) { return true; }, &summary, &last);
    r.steps += summary.integrator.steps;
    r.rhs += summary.integrator.rhs_evaluations;
  };
  if constexpr (kBreaks)
    for (double t_break : kCycleBreaks)
      if (t_break < kTEnd) piece(t_break);
  piece(kTEnd);
  r.q[0] = last.q(0);
  r.q[1] = last.q(1);
  r.ok = r.ok && std::abs(last.t - kTEnd) < 1e-12;
  return r;
}

const double* Reference() {
  static double q[2] = {NAN, NAN};
  static bool done = false;
  if (!done) {
    // Restarted at the set point's breaks: without, the integrator's error at the breaks is
    // the reference's (about 1e-12).
    const SimResult r = SimulateMechgen<dyn::Dop853, true>(1e-13);
    q[0] = r.q[0];
    q[1] = r.q[1];
    done = true;
  }
  return q;
}

SimbodyFivebar& Simbody() {
  static SimbodyFivebar simbody;
  return simbody;
}

#ifndef MECHGEN_BENCH_SIMBODY_ONLY
void RhsMechgen(benchmark::State& state) {
  dyn::PrescribedOptions o;
  o.integrator.rtol = 1e-8;
  o.integrator.atol = 1e-8;
  o.sample_dt = kTEnd / 256;
  Sim<dyn::Dopri5> sim(Robot::ParamsT<double>(), {}, Drive0(), PD(), o);
  double q0[2], qd0[2];
  Commanded(RobotParams(), 0.0, q0, qd0);
  sim.Initialize(0.0, V2(q0[0], q0[1]));
  std::vector<std::pair<double, Sim<dyn::Dopri5>::State>> states;
  dyn::PrescribedSummary summary;
  sim.Simulate(0.0, V2(q0[0], q0[1]), V2::Zero(), kTEnd,
               [&](const Sim<dyn::Dopri5>::SampleT& s) {
                 Sim<dyn::Dopri5>::State y;
                 y << s.q, s.qd, s.W_nc, s.W_act, s.W_F;
                 states.emplace_back(s.t, y);
                 return true;
               },
               &summary);
  sim.Initialize(0.0, V2(q0[0], q0[1]));
  Sim<dyn::Dopri5>::State dy;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [t, y] = states[k++ % states.size()];
    const bool ok = sim.Derivative(t, y, &dy);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(dy);
  }
  state.counters["states"] = static_cast<double>(states.size());
}
BENCHMARK(RhsMechgen)->Name("Rhs/Mechgen");

// The control law alone (the commanded q_ref, qd_ref by the inverse kinematics, and the PD
// torques): a cost both sides pay in every right-hand side.
void PdLaw(benchmark::State& state) {
  const RobotParams p;
  const double q[2] = {2.3, 0.9}, qd[2] = {0.1, -0.2};
  double tau[2];
  long k = 0;
  for (auto _ : state) {
    Torques(p, (k++ % 256) / 256.0, q, qd, tau);
    benchmark::DoNotOptimize(tau);
  }
}
BENCHMARK(PdLaw)->Name("Rhs/ControlLawOnly");
#endif

void RhsSimbody(benchmark::State& state) {
  SimbodyFivebar& simbody = Simbody();
  simbody.RecordStates(256, kTEnd);
  int k = 0;
  for (auto _ : state) {
    const double a = simbody.Rhs(k++);
    benchmark::DoNotOptimize(a);
  }
}

// ---- the N-loop chain: one right-hand side ----
template <class M>
void ChainMechgen(benchmark::State& state) {
  using Sim = dyn::MinimalDynamics<M, dyn::Dopri5>;
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-8;
  o.integrator.atol = 1e-8;
  o.sample_dt = 1.0 / 256;
  Sim sim(typename M::template ParamsT<double>(), o);
  const typename Sim::VecQ q0 = Sim::VecQ::Constant(M_PI / 2);
  if (!sim.Initialize(q0)) {
    state.SkipWithError("does not assemble");
    return;
  }
  std::vector<std::pair<double, typename Sim::State>> states;
  dyn::MinimalSummary summary;
  sim.Simulate(0.0, q0, Sim::VecQ::Zero(), 1.0,
               [&](const typename Sim::SampleT& s) {
                 typename Sim::State y;
                 y.template head<Sim::kNq>() = s.q;
                 y.template segment<Sim::kNq>(Sim::kNq) = s.qd;
                 y(2 * Sim::kNq) = s.W;
                 states.emplace_back(s.t, y);
                 return true;
               },
               &summary);
  if (!summary.IsSolutionUsable() || states.empty()) {
    state.SkipWithError("the recording run failed");
    return;
  }
  sim.Initialize(q0);
  typename Sim::State dy;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [t, y] = states[k++ % states.size()];
    const bool ok = sim.Derivative(t, y, &dy);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(dy);
  }
  state.counters["states"] = static_cast<double>(states.size());
  state.counters["nphi"] = M::kNphi;
}

void ChainSimbody(benchmark::State& state, int n) {
  SimbodyChain chain(n);
  chain.RecordStates(256);
  int k = 0;
  for (auto _ : state) {
    const double a = chain.Rhs(k++);
    benchmark::DoNotOptimize(a);
  }
}

void RegisterChains() {
#ifndef MECHGEN_BENCH_SIMBODY_ONLY
  benchmark::RegisterBenchmark("Chain/Mechgen/1", ChainMechgen<mech::dyn_chain_1::Model>);
  benchmark::RegisterBenchmark("Chain/Mechgen/2", ChainMechgen<mech::dyn_chain_2::Model>);
  benchmark::RegisterBenchmark("Chain/Mechgen/4", ChainMechgen<mech::dyn_chain_4::Model>);
  benchmark::RegisterBenchmark("Chain/Mechgen/8", ChainMechgen<mech::dyn_chain_8::Model>);
  benchmark::RegisterBenchmark("Chain/Mechgen/16", ChainMechgen<mech::dyn_chain_16::Model>);
#endif
  for (int n : {1, 2, 4, 8, 16}) {
    const std::string name = std::string("Chain/") + MECHGEN_BENCH_SIMBODY_LABEL + "/" + std::to_string(n);
    benchmark::RegisterBenchmark(name.c_str(), [n](benchmark::State& state) { ChainSimbody(state, n); });
  }
}

struct Method {
  std::string name;
  std::function<SimResult(double)> simulate;
};

std::vector<Method> Methods() {
  std::vector<Method> m;
#ifndef MECHGEN_BENCH_SIMBODY_ONLY
  m.push_back({"MechgenDopri5", SimulateMechgen<dyn::Dopri5>});
  m.push_back({"MechgenDop853", SimulateMechgen<dyn::Dop853>});
  m.push_back({"MechgenDopri5Breaks", SimulateMechgen<dyn::Dopri5, true>});
  m.push_back({"MechgenDop853Breaks", SimulateMechgen<dyn::Dop853, true>});
#endif
  for (bool breaks : {false, true})
  for (SimbodyIntegrator integ : {SimbodyIntegrator::kRungeKuttaMerson,
                                  SimbodyIntegrator::kRungeKuttaFeldberg,
                                  SimbodyIntegrator::kCPodes}) {
    m.push_back({std::string(MECHGEN_BENCH_SIMBODY_LABEL) + Name(integ) + (breaks ? "Breaks" : ""),
                 [integ, breaks](double tol) {
                   const SimbodyRobotRun run = Simbody().Simulate(integ, tol, kTEnd, breaks);
                   SimResult r;
                   r.q[0] = run.q[0];
                   r.q[1] = run.q[1];
                   r.steps = run.steps;
                   r.rhs = run.realizations;
                   r.ok = run.ok;
                   return r;
                 }});
  }
  return m;
}

void Register() {
  benchmark::RegisterBenchmark((std::string("Rhs/") + MECHGEN_BENCH_SIMBODY_LABEL).c_str(), RhsSimbody);
  static const std::vector<Method> methods = Methods();
  for (const Method& method : methods) {
    const int e_max = method.name.find("Simbody") != std::string::npos ? 12 : 10;
    for (int e = 4; e <= e_max; ++e) {
      const double tol = std::pow(10.0, -e);
      const std::string name = "Simulate/" + method.name + "/1e-" + std::to_string(e);
      benchmark::RegisterBenchmark(name.c_str(), [&method, tol](benchmark::State& state) {
        SimResult r;
        for (auto _ : state) {
          r = method.simulate(tol);
          benchmark::DoNotOptimize(r);
        }
        const double* ref = Reference();
        state.counters["error"] = std::max(std::fabs(r.q[0] - ref[0]), std::fabs(r.q[1] - ref[1]));
        state.counters["steps"] = static_cast<double>(r.steps);
        state.counters["rhs"] = static_cast<double>(r.rhs);
        state.counters["tol"] = tol;
        if (!r.ok) state.SkipWithError("simulation failed");
      })->Unit(benchmark::kMicrosecond);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const double* ref = Reference();
  char text[128];
  std::snprintf(text, sizeof(text), "%.16f %.16f", ref[0], ref[1]);
  benchmark::AddCustomContext("reference_q_1s", text);
  const SimbodyRobotRun tight = Simbody().Simulate(SimbodyIntegrator::kRungeKuttaMerson, 1e-12, kTEnd);
  std::snprintf(text, sizeof(text), "%.3g", std::max(std::fabs(tight.q[0] - ref[0]), std::fabs(tight.q[1] - ref[1])));
  benchmark::AddCustomContext("reference_vs_simbody_rkmerson_1e-12", text);
  benchmark::AddCustomContext("simbody_library", SimbodyFivebar::LibraryPath());
  Register();
  RegisterChains();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
