// Four-bar position analysis per configuration, side by side (Google Benchmark).
//
// Every benchmark iteration advances the crank by 0.5 deg along a full turn and produces the
// same outputs: the dependent angles phi, the velocity and centripetal coefficients K and L
// and the coupler point (r_P, K_P, L_P):
//   ClosedForm          hand-written circle–circle intersection + Paul's K and L
//                       (tests/runtime/handwritten_fourbar.h)
//   MechgenContinuation PositionSolver::MoveTo(): second-order predictor, the generated
//                       Solve (closed-form dyad) on the branch's mode, which hands the
//                       angles' sin and cos (Model::TrigT) to one generated Coeffs
//                       (K, L, points, and the Phi / Phi_phi the step's checks use: residual,
//                       cond_1, branch sign, sigma_min and directions, correction size,
//                       K-consistency)
//   MechgenClosedForm   the generated SolvePositions (closed-form RRR dyad) + Coeffs, sin and
//                       cos passed from one to the other
//   CeresAnalyticReused Ceres LM with the generated Jacobian, one ceres::Problem reused,
//                       started from the previous phi; then Coeffs
//   CeresAutoDiffReused the same with AutoDiffCostFunction over Model::Phi (Jets)
//   CeresNewProblem     a new ceres::Problem (analytic Jacobian) per solve; then Coeffs
// MECHGEN_BENCH_MODEL_INCLUDE / _NAMESPACE select the model for the last four (the generated
// mech::fourbar when it exists, else the hand-written one); ClosedForm is always the oracle.
#include <array>
#include <cmath>

#include <benchmark/benchmark.h>
#include <ceres/ceres.h>

#include "handwritten_fourbar.h"
#ifdef MECHGEN_BENCH_HAVE_fourbar_pos
#include "fourbar_pos.h"
#endif
#ifdef MECHGEN_BENCH_HAVE_watt_sixbar
#include "watt_sixbar.h"
#endif
#ifdef MECHGEN_BENCH_CHAINS
#include "chain_4.h"
#include "chain_8.h"
#endif
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#ifdef MECHGEN_BENCH_VIEW_ANALYSES
#include <type_traits>
#include <vector>

#include "fourbar_massive.h"
#include "slider_crank_friction.h"
#include "mechgen/core/view_runtime.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/statics/sweep.h"
MECHGEN_DECLARE_MODEL_VIEW(slider_crank_friction)
MECHGEN_DECLARE_MODEL_VIEW(fourbar_massive)
#endif
#ifdef MECHGEN_BENCH_VIEW
#include "mechgen/core/view_runtime.h"
namespace mech::fourbar {
const mechgen::ModelView& View();
}
#endif

#ifdef MECHGEN_BENCH_MODEL_INCLUDE
#include MECHGEN_BENCH_MODEL_INCLUDE
using Model = MECHGEN_BENCH_MODEL_NAMESPACE::Model;
#else
using Model = mech::handwritten_fourbar::Model;
#endif

namespace {

using Types = mechgen::ModelTypes<Model>;
constexpr double kStep = 0.5 * M_PI / 180;  // 0.5 deg per configuration

// Crank angle of step k; one full turn is 720 steps.
double CrankAngle(long k) { return (k % 720) * kStep; }

void ClosedForm(benchmark::State& state) {
  using namespace mech::handwritten_fourbar;
  const Params<double> p;
  Coefficients<double> c;
  Vec<double, 2> phi;
  long k = 0;
  for (auto _ : state) {
    const Vec<double, 1> q = Vec<double, 1>::Constant(CrankAngle(k++));
    const bool ok = ClosedFormPosition(p, q(0), +1, &phi);
    EvalCoefficients(p, q, phi, &c);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(ClosedForm);

void MechgenContinuation(benchmark::State& state) {
  mechgen::position::CeresPositionSolver<Model> solver;
  mechgen::position::Summary summary;
  if (solver.AssembleDefault(&summary) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  // Start the sweep at q = 0 (the continuation from the assembly input is not timed).
  solver.MoveTo(Types::VecQ::Zero(), &summary);
  long k = 1;  // continuation, so q keeps increasing: no jump back at the end of a turn
  for (auto _ : state) {
    const Types::VecQ q = Types::VecQ::Constant(k++ * kStep);
    solver.MoveTo(q, &summary);
    benchmark::DoNotOptimize(solver.state());
  }
  if (summary.status != mechgen::position::Status::kConverged) state.SkipWithError("step failed");
}
BENCHMARK(MechgenContinuation);

#ifdef MECHGEN_BENCH_VIEW
// MechgenContinuation through the runtime compiled once for the model view (issue 43):
// PositionSolver<ViewModel> from mechgen_runtime_view on mech::fourbar::View(), the same steps.
void MechgenContinuationView(benchmark::State& state) {
  mechgen::ViewPositionSolver solver{mechgen::ViewModel(mech::fourbar::View())};
  mechgen::position::Summary summary;
  if (solver.AssembleDefault(&summary) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  using VecQ = mechgen::ModelTypes<mechgen::ViewModel>::VecQ;
  solver.MoveTo(VecQ::Zero(1), &summary);
  long k = 1;
  for (auto _ : state) {
    const VecQ q = VecQ::Constant(1, k++ * kStep);
    solver.MoveTo(q, &summary);
    benchmark::DoNotOptimize(solver.state());
  }
  if (summary.status != mechgen::position::Status::kConverged) state.SkipWithError("step failed");
}
BENCHMARK(MechgenContinuationView);

// The same steps on the runtime sized to the view's shape (core/view_sized.h: one input, two
// dependent coordinates), which `mechgen sweep` and `mechgen statics` run for such a model
// (analysis::RunSized): PositionSolver<SizedViewModel<1, 2>> from mechgen_runtime_view.
void MechgenContinuationSized(benchmark::State& state) {
  using Sized = mechgen::ViewSized12;
  mechgen::position::PositionSolver<Sized, mechgen::position::NewtonAssembler> solver{
      Sized(mechgen::ViewModel(mech::fourbar::View()))};
  mechgen::position::Summary summary;
  if (solver.AssembleDefault(&summary) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  using VecQ = mechgen::ModelTypes<Sized>::VecQ;
  solver.MoveTo(VecQ::Zero(), &summary);
  long k = 1;
  for (auto _ : state) {
    const VecQ q = VecQ::Constant(k++ * kStep);
    solver.MoveTo(q, &summary);
    benchmark::DoNotOptimize(solver.state());
  }
  if (summary.status != mechgen::position::Status::kConverged) state.SkipWithError("step failed");
}
BENCHMARK(MechgenContinuationSized);
#endif

#ifdef MECHGEN_BENCH_VIEW_ANALYSES
// slider_crank_friction as Model: the generated model's tag, or a view of it.
template <class Model>
Model SliderCrankFriction() {
  if constexpr (std::is_same_v<Model, mech::slider_crank_friction::Model>) {
    return Model();
  } else {
    return Model(mechgen::ViewModel(mech::slider_crank_friction::View()));
  }
}

// A statics row and a simulation's right-hand side, fixed-size and through the view (issue 43:
// each within 1.15x): the statics sweep of slider_crank_friction (Coulomb friction in four
// joints; each row the position step and the statics with its friction iteration, forward and
// backward) over its range in 360 steps, per iteration of the benchmark; the right-hand side
// (qd, qdd, P_nc) of fourbar_massive's minimal equations at one state.
// Model: the generated one (fixed sizes), mechgen::ViewModel (any view) or mechgen::ViewSized12
// (the view on the runtime sized to its shape, as `mechgen statics` runs this model).
template <class Model>
void StaticsRows(benchmark::State& state) {
  using M = mech::slider_crank_friction::Model;
  constexpr bool kView = !std::is_same_v<Model, M>;
  const Model model = SliderCrankFriction<Model>();
  using T = mechgen::ModelTypes<Model>;
  mechgen::position::PositionSolver<Model> solver(model);
  if (solver.AssembleDefault(nullptr) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  const typename T::VecQ q0 = Eigen::Map<const typename T::VecQ>(mechgen::ModelCalls<Model>::QMin(model), 1);
  const typename T::VecQ q1 = Eigen::Map<const typename T::VecQ>(mechgen::ModelCalls<Model>::QMax(model), 1);
  int failures = 0;
  for (auto _ : state) {
    if constexpr (kView) {
      // (The library's instantiations take the row callback as a std::function.)
      mechgen::statics::StaticsRowFn<Model> row = [](int, const mechgen::statics::StaticsRecord<Model>& r) {
        benchmark::DoNotOptimize(r);
      };
      failures += mechgen::statics::StaticsSweepRows(mechgen::statics::Options(), &solver, q0, q1, 360,
                                                     mechgen::SweepOptions(), nullptr, row);
    } else {
      auto row = [](int, const mechgen::statics::StaticsRecord<M>& r) { benchmark::DoNotOptimize(r); };
      failures += mechgen::statics::StaticsSweepRows(mechgen::statics::Options(), &solver, q0, q1, 360,
                                                     mechgen::SweepOptions(), nullptr, row);
    }
  }
  if (failures != 0) state.SkipWithError("rows failed");
  state.SetItemsProcessed(state.iterations() * 361);  // items: rows
}
BENCHMARK_TEMPLATE(StaticsRows, mech::slider_crank_friction::Model)->Name("StaticsRows");
BENCHMARK_TEMPLATE(StaticsRows, mechgen::ViewModel)->Name("StaticsRowsView");
BENCHMARK_TEMPLATE(StaticsRows, mechgen::ViewSized12)->Name("StaticsRowsSized");

// Where a statics row's time through the view goes (for reference, no target): one
// statics::Solve of slider_crank_friction at its assembled configuration, fixed-size and on the
// sized view, without motion (kWay 0: one generated evaluation, what the row's frictionless
// solve does) and moving (kWay 1: the friction iteration, 12 evaluations here; a row does one
// at rest and two moving, forward and backward). The difference of the first is the view's
// cost per solve (its set-up and the reads of the evaluation's results: the reaction norm, the
// finite check), that of the second less the first its cost per friction iteration.
// (Solve<ViewSized12> is instantiated in this program, not taken from mechgen_runtime_view.)
template <class Model, int kWay>
void StaticsSolve(benchmark::State& state) {
  using C = mechgen::ModelCalls<Model>;
  using T = mechgen::ModelTypes<Model>;
  const Model model = SliderCrankFriction<Model>();
  mechgen::position::PositionSolver<Model> solver(model);
  if (solver.AssembleDefault(nullptr) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  const mechgen::position::State<Model>& s = solver.state();
  typename T::Coefficients c;
  C::Coeffs(model, solver.params(), s.q, s.phi, &c);
  mechgen::statics::Solution<Model> solution(model);
  const typename T::VecQ direction = T::VecQ::Constant(1, static_cast<double>(kWay));
  const mechgen::statics::Options options;
  mechgen::statics::Status status = mechgen::statics::Status::kNotRun;
  for (auto _ : state) {
    status = mechgen::statics::Solve<Model>(model, options, solver.params(), s.q, s.phi, c, direction, &solution);
    benchmark::DoNotOptimize(solution);
  }
  if (status != mechgen::statics::Status::kConverged) state.SkipWithError("the statics did not converge");
  state.counters["evaluations"] = solution.summary.iterations;
}
BENCHMARK_TEMPLATE(StaticsSolve, mech::slider_crank_friction::Model, 0)->Name("StaticsSolveAtRest");
BENCHMARK_TEMPLATE(StaticsSolve, mechgen::ViewSized12, 0)->Name("StaticsSolveAtRestSized");
BENCHMARK_TEMPLATE(StaticsSolve, mech::slider_crank_friction::Model, 1)->Name("StaticsSolveMoving");
BENCHMARK_TEMPLATE(StaticsSolve, mechgen::ViewSized12, 1)->Name("StaticsSolveMovingSized");

// fourbar_massive's minimal method with Dopri5 (Coulomb friction off), fixed-size or through the
// view.
template <bool kView>
using RhsSim = mechgen::dynamics::MinimalDynamics<
    std::conditional_t<kView, mechgen::ViewModel, mech::fourbar_massive::Model>, mechgen::dynamics::Dopri5>;
template <bool kView>
RhsSim<kView> MakeRhsSim() {
  using Sim = RhsSim<kView>;
  mechgen::dynamics::MinimalOptions options;
  options.coulomb.enabled = false;
  if constexpr (kView) {
    const mechgen::ViewModel model(mech::fourbar_massive::View());
    return Sim(model, mechgen::ModelCalls<mechgen::ViewModel>::DefaultParams(model), options);
  } else {
    return Sim(typename Sim::Params(), options);
  }
}

// kChained false: each call's state from the table alone, so that consecutive calls are
// independent and the processor overlaps one call's tail with the next one's start (a
// throughput figure: calls in flight at once). kChained true: each call's q and qd also read the
// last call's output, y = s + 1e-300 dy (the same states to the bit: the term is below half an
// ulp of every entry), as an integrator's stage reads the stages before it: a simulation's
// calls wait for each other, and the figure is the call's latency.
template <bool kView, bool kChained>
void RightHandSide(benchmark::State& state) {
  using M = mech::fourbar_massive::Model;
  using Sim = RhsSim<kView>;
  Sim sim = MakeRhsSim<kView>();
  typename Sim::VecQ q0 = Sim::VecQ::Constant(1, M::kAssemblyQ[0]);
  if (!sim.Initialize(q0)) {
    state.SkipWithError("initialize failed");
    return;
  }
  // The states, as a simulation's stages see them: q, qd and t all vary from one call to the
  // next, read from a table the compiler cannot see into (written before the loop, then
  // clobbered by DoNotOptimize): neither side can fold a constant qd or t into the inlined
  // generated Rhs. (This did not move the ratio: view / fixed 1.30 with qd = 2, t = 0 constant,
  // 47.7 / 61.8 ns; 1.32 with the table, 46.8 / 61.7 and 46.9 / 62.1 ns; 2026-11-29, a loaded
  // machine. The fixed side folded little: qd enters h and T only, t nothing.)
  constexpr int kStates = 1000;
  std::vector<std::array<double, 3>> states(kStates);
  for (int k = 0; k < kStates; ++k) {
    states[k] = {q0(0) + 1e-3 * k, 2.0 + std::sin(0.37 * k), 1e-3 * k};  // (q, qd, t)
  }
  benchmark::DoNotOptimize(states.data());
  benchmark::ClobberMemory();
  typename Sim::State y = Sim::State::Zero(3), dy = Sim::State::Zero(3);
  int k = 0;
  for (auto _ : state) {
    const std::array<double, 3>& s = states[k];
    k = k + 1 < kStates ? k + 1 : 0;
    if constexpr (kChained) {
      y(0) = s[0] + 1e-300 * dy(0);
      y(1) = s[1] + 1e-300 * dy(1);
    } else {
      y(0) = s[0];
      y(1) = s[1];
    }
    bool ok = false;
    if constexpr (kView) {
      ok = mechgen::dynamics::DerivativeOf(&sim, s[2], y, &dy);
    } else {
      ok = sim.Derivative(s[2], y, &dy);
    }
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(dy);
  }
}
BENCHMARK_TEMPLATE(RightHandSide, false, false)->Name("RightHandSide");
BENCHMARK_TEMPLATE(RightHandSide, true, false)->Name("RightHandSideView");
BENCHMARK_TEMPLATE(RightHandSide, false, true)->Name("RightHandSideChained");
BENCHMARK_TEMPLATE(RightHandSide, true, true)->Name("RightHandSideChainedView");

// A whole free simulation of fourbar_massive (Dopri5, 0.5 s from the assembly at 2 rad/s, a
// sample at every accepted step handed to an observer that keeps the last one), as `mechgen
// simulate` runs it without its CSV: the counter `rhs` is the right-hand side's evaluations
// per run, so that time / rhs is the simulation's cost per evaluation, the integrator's
// arithmetic, the steps' control and the samples included (on the view, its bounded dynamic
// sizes and a std::function observer; fixed-size, a lambda).
template <bool kView>
void Simulation(benchmark::State& state) {
  using M = mech::fourbar_massive::Model;
  using Sim = RhsSim<kView>;
  Sim sim = MakeRhsSim<kView>();
  const typename Sim::VecQ q0 = Sim::VecQ::Constant(1, M::kAssemblyQ[0]);
  const typename Sim::VecQ qd0 = Sim::VecQ::Constant(1, 2.0);
  if (!sim.Initialize(q0)) {
    state.SkipWithError("initialize failed");
    return;
  }
  double last_t = 0;
  long evaluations = 0;
  mechgen::dynamics::MinimalSummary summary;
  for (auto _ : state) {
    bool ok = false;
    if constexpr (kView) {
      mechgen::dynamics::ViewSampleFn<Sim> observer = [&last_t](const typename Sim::SampleT& s) {
        last_t = s.t;
        return true;
      };
      ok = mechgen::dynamics::SimulateFree(&sim, 0.0, q0, qd0, 0.5, observer, &summary, nullptr);
    } else {
      ok = sim.Simulate(0.0, q0, qd0, 0.5, [&last_t](const typename Sim::SampleT& s) {
        last_t = s.t;
        return true;
      }, &summary);
    }
    if (!ok) {
      state.SkipWithError("the simulation failed");
      return;
    }
    evaluations += summary.integrator.rhs_evaluations;
    benchmark::DoNotOptimize(last_t);
  }
  state.counters["rhs"] = benchmark::Counter(static_cast<double>(evaluations), benchmark::Counter::kAvgIterations);
}
BENCHMARK_TEMPLATE(Simulation, false)->Name("Simulation");
BENCHMARK_TEMPLATE(Simulation, true)->Name("SimulationView");
#endif

#ifdef MECHGEN_BENCH_MODEL_INCLUDE
// The generated closed-form dyad (Model::Solve, circle–circle in the solve order) + the
// generated Coeffs: what a product calls directly, without the runtime.
void MechgenClosedForm(benchmark::State& state) {
  const Model::ParamsT<double> p;
  Model::CoefficientsT<double> c;
  Model::TrigT<double> trig;
  Types::VecPhi phi;
  for (int i = 0; i < Model::kNphi; ++i) phi(i) = Model::kAssemblyPhi[i];
  long k = 0;
  for (auto _ : state) {
    const Types::VecQ q = Types::VecQ::Constant(CrankAngle(k++));
    const auto report = Model::Solve(p, q, &phi, Model::kDefaultModes, 20, 0.0, &trig);
    Model::Coeffs(p, q, phi, &c, &trig);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(MechgenClosedForm);
#endif

// Ceres LM on one reused problem; CostFunction is PhiCostFunction or the autodiff one.
template <bool kAutoDiff>
void CeresReused(benchmark::State& state) {
  const Types::Params params;
  Types::VecQ q = Types::VecQ::Zero();
  Types::VecPhi phi = Eigen::Map<const Types::VecPhi>(Model::kAssemblyPhi.data());
  ceres::CostFunction* cost;
  if constexpr (kAutoDiff) {
    cost = new ceres::AutoDiffCostFunction<mechgen::position::PhiAutoDiffFunctor<Model>, Model::kNc,
                                           Model::kNphi>(
        new mechgen::position::PhiAutoDiffFunctor<Model>(&params, &q));
  } else {
    cost = new mechgen::position::PhiCostFunction<Model>(&params, &q);
  }
  ceres::Problem problem;  // owns `cost`
  problem.AddResidualBlock(cost, nullptr, phi.data());
  const ceres::Solver::Options options = mechgen::position::LevenbergMarquardtOptions(100);
  ceres::Solver::Summary summary;
  q = Eigen::Map<const Types::VecQ>(Model::kAssemblyQ.data());
  ceres::Solve(options, &problem, &summary);  // assemble on the model's branch
  Types::Coefficients c;
  long k = 0;
  for (auto _ : state) {
    q = Types::VecQ::Constant(CrankAngle(k++));
    ceres::Solve(options, &problem, &summary);
    Model::Coeffs<double>(params, q, phi, &c);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
  if (summary.final_cost > 1e-18) state.SkipWithError("Ceres did not close the loop");
}
BENCHMARK_TEMPLATE(CeresReused, false)->Name("CeresAnalyticReused");
BENCHMARK_TEMPLATE(CeresReused, true)->Name("CeresAutoDiffReused");

void CeresNewProblem(benchmark::State& state) {
  const Types::Params params;
  Types::VecPhi phi = Eigen::Map<const Types::VecPhi>(Model::kAssemblyPhi.data());
  const ceres::Solver::Options options = mechgen::position::LevenbergMarquardtOptions(100);
  ceres::Solver::Summary summary;
  Types::Coefficients c;
  Types::VecQ q = Eigen::Map<const Types::VecQ>(Model::kAssemblyQ.data());
  long k = -1;  // the first pass assembles at the model's assembly input
  for (auto _ : state) {
    if (k >= 0) q = Types::VecQ::Constant(CrankAngle(k));
    ++k;
    ceres::Problem problem;
    problem.AddResidualBlock(new mechgen::position::PhiCostFunction<Model>(&params, &q), nullptr,
                             phi.data());
    ceres::Solve(options, &problem, &summary);
    Model::Coeffs<double>(params, q, phi, &c);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(CeresNewProblem);

// ---- The runtime on other models: PositionSolver::MoveTo per 0.5 deg input step, against a
// plain Newton loop (first-order extrapolation of the last two solutions, Newton on the
// generated Phi/Phi_phi to |Phi|_inf <= 1e-10 plus one step, then the generated Coeffs):
// what a product would write by hand without branch tracking or a distance to singularity.
template <class M>
void RuntimeContinuation(benchmark::State& state) {
  using T = mechgen::ModelTypes<M>;
  mechgen::position::CeresPositionSolver<M> solver;
  mechgen::position::Summary summary;
  if (solver.AssembleDefault(&summary) != mechgen::position::Status::kConverged ||
      solver.MoveTo(T::VecQ::Zero(), &summary) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  long k = 1;
  for (auto _ : state) {
    solver.MoveTo(T::VecQ::Constant(k++ * kStep), &summary);
    benchmark::DoNotOptimize(solver.state());
  }
  if (summary.status != mechgen::position::Status::kConverged) state.SkipWithError("step failed");
}

template <class M>
void PlainNewton(benchmark::State& state) {
  using T = mechgen::ModelTypes<M>;
  mechgen::position::CeresPositionSolver<M> solver;
  mechgen::position::Summary summary;
  if (solver.AssembleDefault(&summary) != mechgen::position::Status::kConverged ||
      solver.MoveTo(T::VecQ::Zero(), &summary) != mechgen::position::Status::kConverged) {
    state.SkipWithError("assembly failed");
    return;
  }
  const typename T::Params p;
  typename T::VecPhi phi = solver.state().phi, phi_prev = phi;
  typename T::Coefficients c;
  long k = 0;
  bool ok = true;
  for (auto _ : state) {
    const typename T::VecQ q = T::VecQ::Constant(k++ * kStep);
    typename T::VecPhi x = 2 * phi - phi_prev;
    typename T::VecC Phi;
    typename T::MatCPhi A;
    int it = 0;
    for (;; ++it) {
      M::template Phi<double>(p, q, x, &Phi, &A, nullptr);
      const bool done = Phi.template lpNorm<Eigen::Infinity>() <= 1e-10;
      x -= Eigen::PartialPivLU<typename T::MatCPhi>(A).solve(Phi);
      if (done || it == 8) break;
    }
    ok = ok && it < 8;
    phi_prev = phi;
    phi = x;
    if constexpr (mechgen::ModelFeatures<M>::kHasK) M::template Coeffs<double>(p, q, phi, &c);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
  if (!ok) state.SkipWithError("Newton did not converge");
}

#define MECHGEN_RUNTIME_BENCH(NS, NAME)                                       \
  BENCHMARK_TEMPLATE(RuntimeContinuation, NS::Model)->Name("Continuation/" NAME); \
  BENCHMARK_TEMPLATE(PlainNewton, NS::Model)->Name("PlainNewton/" NAME);

#ifdef MECHGEN_BENCH_MODEL_INCLUDE
MECHGEN_RUNTIME_BENCH(MECHGEN_BENCH_MODEL_NAMESPACE, "fourbar")
#endif
#ifdef MECHGEN_BENCH_HAVE_fourbar_pos
MECHGEN_RUNTIME_BENCH(mech::fourbar_pos, "fourbar_pos")
#endif
#ifdef MECHGEN_BENCH_HAVE_watt_sixbar
MECHGEN_RUNTIME_BENCH(mech::watt_sixbar, "watt_sixbar")
#endif
#ifdef MECHGEN_BENCH_CHAINS
MECHGEN_RUNTIME_BENCH(mech::chain_4, "chain_4")
MECHGEN_RUNTIME_BENCH(mech::chain_8, "chain_8")
#endif

}  // namespace

BENCHMARK_MAIN();
