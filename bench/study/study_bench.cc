// Design studies (issue 29): what one sample costs, per analysis, on one core, and how a study
// scales with threads. The figures of docs/studies.md "Speed" and the README's scaling model.
//
// MonteCarloCouplerPoint: the positions-only Monte-Carlo of the four-bar's coupler point, 10^6
// samples per iteration: each sample draws its six dimensions (a, b, c, d, xi, eta normal, sigma
// 0.01/3; study/random.h's counter-based normals, as `mechgen study` draws them), solves the
// positions at theta = 60 deg by the generated closed form (SolvePositions, the assembly's
// branch) and evaluates the coupler point (EvalCoefficients with the solve's sines and
// cosines). The sum of the points is kept so that nothing is optimised away.
#include <benchmark/benchmark.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "fourbar.h"
#include "fourbar_loaded.h"
#ifdef MECHGEN_STUDY_BENCH_MASSIVE
#include "fourbar_massive.h"
#endif
#include "mechgen/study/random.h"
#include "mechgen/study/run.h"
#include "mechgen/study/samples.h"
#include "mechgen/study/spec.h"
#include "shaper.h"

namespace {

namespace study = mechgen::study;

void MonteCarloCouplerPoint(benchmark::State& state) {
  using M = mech::fourbar::Model;
  const int n = static_cast<int>(state.range(0));
  const M::ParamsT<double> nominal;
  const double sigma = 0.01 / 3;
  mech::fourbar::Vec<double, 1> q;
  q(0) = 60 * 3.14159265358979323846 / 180;
  int failed = 0;
  double sum = 0;
  for (auto _ : state) {
    for (int i = 0; i < n; ++i) {
      M::ParamsT<double> p = nominal;
      p.a += sigma * study::NormalQuantile(study::Uniform(1, 0, i));
      p.b += sigma * study::NormalQuantile(study::Uniform(1, 1, i));
      p.c += sigma * study::NormalQuantile(study::Uniform(1, 2, i));
      p.d += sigma * study::NormalQuantile(study::Uniform(1, 3, i));
      p.xi += sigma * study::NormalQuantile(study::Uniform(1, 4, i));
      p.eta += sigma * study::NormalQuantile(study::Uniform(1, 5, i));
      mech::fourbar::Vec<double, M::kNphi> phi = Eigen::Map<const mech::fourbar::Vec<double, M::kNphi>>(M::kAssemblyPhi.data());
      mech::fourbar::Trig<double> trig;
      const auto report = M::Solve(p, q, &phi, M::kDefaultModes, 20, 0.0, &trig);
      if (report.status != mech::fourbar::SolveStatus::kConverged) {
        ++failed;
        continue;
      }
      mech::fourbar::Coefficients<double> c;
      mech::fourbar::EvalCoefficients(p, q, phi, &c, &trig);
      sum += c.r_P(0, 0) + c.r_P(1, 0);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.counters["failed"] = failed;
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(MonteCarloCouplerPoint)->Arg(1000000)->Unit(benchmark::kMillisecond);

// A study file in /tmp for the benchmarks below.
study::StudySpec Spec(const std::string& text) {
  const std::string path = "/tmp/mechgen_study_bench.yaml";
  std::ofstream(path) << text;
  study::StudySpec spec;
  std::string error;
  if (!study::ReadStudy(path, &spec, &error)) std::abort();
  return spec;
}

template <class M>
void Sample(benchmark::State& state, const std::string& text) {
  const study::StudySpec spec = Spec(text);
  study::Study<M> s;
  std::string error;
  if (!s.Prepare(spec, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  const size_t n = spec.parameters.size(), count = v.size() / n;
  typename study::Study<M>::Rows rows;
  size_t i = 0;
  for (auto _ : state) {
    study::SampleResult r = s.Evaluate(&v[(i++ % count) * n], &rows);
    benchmark::DoNotOptimize(r.metrics.data());
  }
  state.counters["analyses_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                        benchmark::Counter::kIsRate);
}

const char* kFourbarSweep =
    "method: monte_carlo\ncount: 64\nsteps: 360\nparameters:\n  a: {tolerance: 0.01}\n  b: {tolerance: 0.01}\n"
    "  c: {tolerance: 0.01}\n  d: {tolerance: 0.01}\nmetrics:\n  - {kind: max, column: coupler.P.y}\n"
    "  - {kind: min_transmission_angle}\n  - {kind: path_deviation, point: coupler.P}\n";

void StudySampleSweep(benchmark::State& state) { Sample<mech::fourbar::Model>(state, kFourbarSweep); }
BENCHMARK(StudySampleSweep)->Unit(benchmark::kMicrosecond);

void StudySampleOneConfiguration(benchmark::State& state) {
  Sample<mech::fourbar::Model>(state,
                               "method: monte_carlo\ncount: 64\nsteps: 1\nrange: [60deg, 60deg]\nparameters:\n"
                               "  a: {tolerance: 0.01}\n  b: {tolerance: 0.01}\n  c: {tolerance: 0.01}\n"
                               "  d: {tolerance: 0.01}\nmetrics:\n  - {kind: at, column: coupler.P.x, step: 0}\n");
}
BENCHMARK(StudySampleOneConfiguration)->Unit(benchmark::kMicrosecond);

void StudySampleStatics(benchmark::State& state) {
  Sample<mech::fourbar_loaded::Model>(state,
                                      "method: monte_carlo\ncount: 64\nsteps: 360\nanalysis: statics\nparameters:\n"
                                      "  a: {tolerance: 0.01}\n  c: {tolerance: 0.01}\n  k: {tolerance: 2}\n"
                                      "metrics:\n  - {kind: peak_drive}\n  - {kind: peak_bearing}\n");
}
BENCHMARK(StudySampleStatics)->Unit(benchmark::kMicrosecond);

void StudySampleFlywheel(benchmark::State& state) {
  Sample<mech::shaper::Model>(state,
                              "method: monte_carlo\ncount: 64\nsteps: 720\nanalysis: flywheel\nomega: 6.28\n"
                              "parameters:\n  L: {tolerance: 0.01}\n  l: {tolerance: 0.01}\n  P: {range: [0, 0.001], "
                              "distribution: uniform}\nmetrics:\n  - {kind: flywheel_inertia, C_s: 0.05}\n"
                              "  - {kind: peak_torque}\n");
}
BENCHMARK(StudySampleFlywheel)->Unit(benchmark::kMicrosecond);

// analysis: positions through the study itself: a Monte-Carlo of 10^6 four-bar coupler points
// (a, b, c, d, xi, eta normal, sigma 0.01/3) at theta = 60 deg: the draw of every sample's six
// values (study/samples.h) and Study::Run on one thread (each sample: Params, the generated
// closed form, the coupler point, a SampleResult), i.e. `mechgen study` without its CSV.
void StudyPositionsMonteCarlo(benchmark::State& state) {
  const study::StudySpec spec = Spec(
      "method: monte_carlo\ncount: " + std::to_string(state.range(0)) +
      "\nanalysis: positions\nat: [60deg]\nparameters:\n  a: {tolerance: 0.01}\n  b: {tolerance: 0.01}\n"
      "  c: {tolerance: 0.01}\n  d: {tolerance: 0.01}\n  xi: {tolerance: 0.01}\n  eta: {tolerance: 0.01}\n"
      "metrics:\n  - {kind: at, column: coupler.P.x, step: 0}\n  - {kind: at, column: coupler.P.y, step: 0}\n");
  study::Study<mech::fourbar::Model> s;
  std::string error;
  if (!s.Prepare(spec, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  std::vector<study::SampleResult> results;
  for (auto _ : state) {
    const std::vector<double> v = study::DrawSamples(spec, s.nominal());
    s.Run(v, 1, &results);
    benchmark::DoNotOptimize(results.data());
  }
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(state.range(0)) * state.iterations(),
                                                       benchmark::Counter::kIsRate);
}
BENCHMARK(StudyPositionsMonteCarlo)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Its two parts apart: the draw of the 10^6 x 6 values (t_draw of the scaling model), and
// Study::Run alone on values drawn once (the results' storage reused between iterations).
void StudyDrawSixNormals(benchmark::State& state) {
  const study::StudySpec spec = Spec(
      "method: monte_carlo\ncount: 1000000\nanalysis: positions\nat: [60deg]\nparameters:\n  a: {tolerance: 0.01}\n"
      "  b: {tolerance: 0.01}\n  c: {tolerance: 0.01}\n  d: {tolerance: 0.01}\n  xi: {tolerance: 0.01}\n"
      "  eta: {tolerance: 0.01}\nmetrics:\n  - {kind: at, column: coupler.P.x, step: 0}\n");
  const std::vector<double> nominal{1, 3.5, 3, 4, 0.5, 0.5};
  for (auto _ : state) {
    const std::vector<double> v = study::DrawSamples(spec, nominal);
    benchmark::DoNotOptimize(v.data());
  }
}
BENCHMARK(StudyDrawSixNormals)->Unit(benchmark::kMillisecond);

void StudyPositionsRunOnly(benchmark::State& state) {
  const study::StudySpec spec = Spec(
      "method: monte_carlo\ncount: 1000000\nanalysis: positions\nat: [60deg]\nparameters:\n  a: {tolerance: 0.01}\n"
      "  b: {tolerance: 0.01}\n  c: {tolerance: 0.01}\n  d: {tolerance: 0.01}\n  xi: {tolerance: 0.01}\n"
      "  eta: {tolerance: 0.01}\nmetrics:\n  - {kind: at, column: coupler.P.x, step: 0}\n"
      "  - {kind: at, column: coupler.P.y, step: 0}\n");
  study::Study<mech::fourbar::Model> s;
  std::string error;
  if (!s.Prepare(spec, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> results;
  for (auto _ : state) {
    s.Run(v, 1, &results);
    benchmark::DoNotOptimize(results.data());
  }
}
BENCHMARK(StudyPositionsRunOnly)->Unit(benchmark::kMillisecond);

// One sample of analysis: positions at 360 inputs (the cheap counterpart of StudySampleSweep).
void StudySamplePositions(benchmark::State& state) {
  Sample<mech::fourbar::Model>(state,
                               "method: monte_carlo\ncount: 64\nanalysis: positions\nsteps: 359\n"
                               "range: [0, 359deg]\nparameters:\n  a: {tolerance: 0.01}\n  b: {tolerance: 0.01}\n"
                               "  c: {tolerance: 0.01}\n  d: {tolerance: 0.01}\nmetrics:\n"
                               "  - {kind: max, column: coupler.P.y}\n  - {kind: min_transmission_angle}\n"
                               "  - {kind: path_deviation, point: coupler.P}\n");
}
BENCHMARK(StudySamplePositions)->Unit(benchmark::kMicrosecond);

#ifdef MECHGEN_STUDY_BENCH_MASSIVE
// A 3 s simulation per sample, the massive four-bar (models/fourbar_massive.yaml): the free
// swing under gravity from 90 deg, and the crank driven at 2 pi rad/s (its motor torque lambda
// and the bearing loads from the kinetostatics at every sample), 300 samples each.
void StudySampleSimulateFree(benchmark::State& state) {
  Sample<mech::fourbar_massive::Model>(state,
                                       "method: monte_carlo\ncount: 64\nanalysis: simulate\nt_end: 3\nsteps: 300\n"
                                       "parameters:\n  a: {tolerance: 0.01}\n  c: {tolerance: 0.01}\n"
                                       "metrics:\n  - {kind: max, column: T}\n  - {kind: min, column: theta_crank}\n");
}
BENCHMARK(StudySampleSimulateFree)->Unit(benchmark::kMicrosecond);

void StudySampleSimulateDriven(benchmark::State& state) {
  Sample<mech::fourbar_massive::Model>(state,
                                       "method: monte_carlo\ncount: 64\nanalysis: simulate\nt_end: 3\nsteps: 300\n"
                                       "drive: {theta_crank: {speed: 6.283}}\n"
                                       "parameters:\n  a: {tolerance: 0.01}\n  c: {tolerance: 0.01}\n"
                                       "metrics:\n  - {kind: peak_drive}\n  - {kind: peak_bearing}\n");
}
BENCHMARK(StudySampleSimulateDriven)->Unit(benchmark::kMicrosecond);
#endif

// The whole tolerance study of models/fourbar.study.yaml's shape (2000 samples, 72 steps) on
// n threads: parallel efficiency = t(1) / (n t(n)).
void StudyThreads(benchmark::State& state) {
  const study::StudySpec spec = Spec(
      "method: monte_carlo\ncount: 2000\nsteps: 72\nparameters:\n  a: {tolerance: 0.01}\n  b: {tolerance: 0.01}\n"
      "  c: {tolerance: 0.01}\n  d: {distribution: uniform, tolerance: 0.01}\nmetrics:\n"
      "  - {kind: max, column: coupler.P.y}\n  - {kind: min_transmission_angle}\n");
  study::Study<mech::fourbar::Model> s;
  std::string error;
  if (!s.Prepare(spec, &error)) std::abort();
  const std::vector<double> v = study::DrawSamples(spec, s.nominal());
  std::vector<study::SampleResult> results;
  for (auto _ : state) s.Run(v, static_cast<int>(state.range(0)), &results);
  state.counters["samples_per_s"] = benchmark::Counter(2000.0 * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(StudyThreads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
