// Dynamics of the massive four-bar (issue 15), side by side (Google Benchmark; medians by
// bench/dynamics/run.sh).
//
// (a) One right-hand side (positions + I + I' + Q + qdd), one configuration per 0.5 deg step:
//   Rhs/Handwritten        direction cosines, Paul's K and L, I, I', Q by hand
//                          (handwritten_dynamics.h)
//   Rhs/Textbook           atan2/acos angles, sines of angle differences
//   Rhs/Generated          mech::fourbar_massive's Rhs (EvalRhs: SolveTrig's closed-form
//                          direction cosines, K, L, I, h, Q in one generated pass) + qdd
//   Rhs/GeneratedThreeCalls  the same from SolveTrig + Coeffs + Dynamics (the general functions)
//   Rhs/MinimalDynamics    the runtime's right-hand side (mechgen/dynamics/forward.h): the same
//                          with the warm-started position solve and qdd
//   Kinematics/Handwritten positions + K + L by hand
//   Kinematics/HandwrittenChecked  the same with the generated one-pass function's promise
//                          (refusals, range checks, branch measure, Phi_phi output): the
//                          price of the promise apart from that of the formulas
//   Kinematics/Generated   Solve + Coeffs of mech::fourbar_massive (with the angles)
//   Kinematics/GeneratedTrig  SolveTrig + Coeffs (sin and cos of the angles only): two calls,
//                          and Coeffs forms Phi and the coupler point's r_P, K_P, L_P too
//   Kinematics/GeneratedOnePass  Model::Kinematics (EvalKinematics: SolveTrig's closed-form
//                          direction cosines, K, L, Phi_phi in one generated pass; issue 24's
//                          kinematics target, bench/dynamics/run.sh)
// (b) Simulate/<method>/<tolerance>: 3 s from rest at theta = 90 deg, integrator tolerance
//   rtol = atol = 1e-4 .. 1e-10 (Simbody: Integrator::setAccuracy, and 1e-11, 1e-12 so that
//   its curve reaches the errors of the others); counters: error =
//   |theta(3 s) - reference| (reference.h), steps, rhs (evaluations; Simbody: realizations).
//   Methods: Mechgen<integrator> (MinimalDynamics), Excess<integrator> (the excess-coordinate
//   method of the runtime, excess.h, with the coordinate projection), Hand<integrator> (the hand-written EOM, the same integrator
//   classes), Simbody{Debian,Release}/{RKMerson,RKFeldberg,CPodes}.
// --drift_csv=FILE [--drift_t=T]: instead of the benchmarks, writes E(t) - E(0) against
//   simulated time (every 0.05 s up to T, default 30 s) for each method at tolerances 1e-6
//   and 1e-9, long format: method,tolerance,t,drift.
// MECHGEN_BENCH_SIMBODY_ONLY (dynamics_bench_simbody_release): only the Simbody part, named
// after MECHGEN_BENCH_SIMBODY_LABEL.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include <benchmark/benchmark.h>

#include "handwritten_dynamics.h"
#include "reference.h"
#include "simbody_fourbar.h"

#ifndef MECHGEN_BENCH_SIMBODY_ONLY
#if __has_include("mechgen/dynamics/integrators.h")
#define MECHGEN_BENCH_HAVE_INTEGRATORS 1
#include "mechgen/dynamics/integrators.h"
#endif
#if defined(MECHGEN_BENCH_HAVE_FOURBAR_MASSIVE)
#include "fourbar_massive.h"
#if __has_include("mechgen/dynamics/forward.h") && defined(MECHGEN_BENCH_HAVE_INTEGRATORS)
#define MECHGEN_BENCH_HAVE_MINIMAL 1
#include "mechgen/dynamics/forward.h"
#endif
#if __has_include("mechgen/dynamics/excess.h") && defined(MECHGEN_BENCH_HAVE_INTEGRATORS)
#define MECHGEN_BENCH_HAVE_EXCESS 1
#include "mechgen/dynamics/excess.h"
#endif
#endif
#endif

#ifndef MECHGEN_BENCH_SIMBODY_LABEL
#define MECHGEN_BENCH_SIMBODY_LABEL "Simbody"
#endif

namespace {

using namespace bench_dynamics;

constexpr double kTEnd = 3.0;
constexpr double kQ0 = M_PI / 2;
constexpr double kStep = 0.5 * M_PI / 180;

double ReferenceTheta() {
  static const double theta = static_cast<double>(ComputeReference(kTEnd, 16).theta);
  return theta;
}

struct SimResult {
  double theta = NAN;
  double thetad = NAN;
  long steps = 0;
  long rhs = 0;
  bool ok = false;
};

// The parameters are run-time values for every variant and method (as in a design tool): their address
// escapes, so the compiler cannot fold the lengths and masses into the loop as constants.
template <class P>
void RuntimeValues(P* p) {
  benchmark::DoNotOptimize(p);
  benchmark::ClobberMemory();
}

// ---------------------------------------------------------------------------------------------
// (a) One right-hand side.
#ifndef MECHGEN_BENCH_SIMBODY_ONLY
void RhsHandwritten(benchmark::State& state) {
  FourbarParams<double> p;
  RuntimeValues(&p);
  FourbarEom<double> e;
  long k = 0;
  for (auto _ : state) {
    const bool ok = Rhs(p, (k++ % 720) * kStep, 1.0, &e);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(e);
  }
}
BENCHMARK(RhsHandwritten)->Name("Rhs/Handwritten");

void RhsTextbook(benchmark::State& state) {
  FourbarParams<double> p;
  RuntimeValues(&p);
  FourbarEom<double> e;
  long k = 0;
  for (auto _ : state) {
    const bool ok = bench_dynamics::RhsTextbook(p, (k++ % 720) * kStep, 1.0, &e);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(e);
  }
}
BENCHMARK(RhsTextbook)->Name("Rhs/Textbook");

void KinematicsHandwritten(benchmark::State& state) {
  FourbarParams<double> p;
  RuntimeValues(&p);
  FourbarKinematics<double> kin;
  long k = 0;
  for (auto _ : state) {
    const bool ok = Kinematics(p, (k++ % 720) * kStep, &kin);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(kin);
  }
}
BENCHMARK(KinematicsHandwritten)->Name("Kinematics/Handwritten");

// The hand-written kinematics with the generated one-pass function's promise (its refusals,
// range checks, branch measure and Phi_phi output; KinematicsChecked). Before timing, it
// must agree with Kinematics() at every configuration of the loop, and its branch measure with
// sin^2 of the coupler-rocker angle, else the row is an error.
void KinematicsHandwrittenChecked(benchmark::State& state) {
  FourbarParams<double> p;
  RuntimeValues(&p);
  FourbarKinematics<double> kin, plain;
  double Phi_phi[4];
  for (long i = 0; i < 720; ++i) {
    const auto report = KinematicsChecked(p, i * kStep, &kin, Phi_phi);
    const bool ok = Kinematics(p, i * kStep, &plain);
    const double d[] = {kin.c2 - plain.c2, kin.s2 - plain.s2, kin.c3 - plain.c3, kin.s3 - plain.s3,
                        kin.K2 - plain.K2, kin.K3 - plain.K3, kin.L2 - plain.L2, kin.L3 - plain.L3};
    bool same = ok == (report.status == CheckedStatus::kConverged);
    for (double x : d) same = same && std::abs(x) <= 1e-12;
    // |h| f^2 = |(C - B) x (D - B)| = b c |sin(th2 - th3)|: the measure is sin^2 (at most 1).
    const double s23 = plain.s2 * plain.c3 - plain.c2 * plain.s3;
    same = same && std::abs(report.branch_measure - std::min(1.0, s23 * s23)) <= 1e-12;
    if (!same) {
      state.SkipWithError("KinematicsChecked disagrees with Kinematics");
      return;
    }
  }
  long k = 0;
  for (auto _ : state) {
    const auto report = KinematicsChecked(p, (k++ % 720) * kStep, &kin, Phi_phi);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(kin);
    benchmark::DoNotOptimize(Phi_phi);
  }
}
BENCHMARK(KinematicsHandwrittenChecked)->Name("Kinematics/HandwrittenChecked");
#endif

#ifdef MECHGEN_BENCH_HAVE_FOURBAR_MASSIVE
using Model = mech::fourbar_massive::Model;

void KinematicsGenerated(benchmark::State& state) {
  Model::ParamsT<double> p;
  RuntimeValues(&p);
  Model::CoefficientsT<double> c;
  Model::TrigT<double> trig;
  Eigen::Matrix<double, Model::kNphi, 1> phi;
  for (int i = 0; i < Model::kNphi; ++i) phi(i) = Model::kAssemblyPhi[i];
  long k = 0;
  for (auto _ : state) {
    const Eigen::Matrix<double, 1, 1> q = Eigen::Matrix<double, 1, 1>::Constant((k++ % 720) * kStep);
    const auto report = Model::Solve(p, q, &phi, Model::kDefaultModes, 20, 0.0, &trig);
    Model::Coeffs(p, q, phi, &c, &trig);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(phi);
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(KinematicsGenerated)->Name("Kinematics/Generated");

// The kinematics the dynamics needs: sin and cos of the angles (Model::SolveTrig, no atan2).
void KinematicsGeneratedTrig(benchmark::State& state) {
  Model::ParamsT<double> p;
  RuntimeValues(&p);
  Model::CoefficientsT<double> c;
  Model::TrigT<double> trig;
  Eigen::Matrix<double, Model::kNphi, 1> phi;
  for (int i = 0; i < Model::kNphi; ++i) phi(i) = Model::kAssemblyPhi[i];
  long k = 0;
  for (auto _ : state) {
    const Eigen::Matrix<double, 1, 1> q = Eigen::Matrix<double, 1, 1>::Constant((k++ % 720) * kStep);
    const auto report = Model::SolveTrig(p, q, Model::kDefaultModes, &trig);
    Model::Coeffs(p, q, phi, &c, &trig);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(KinematicsGeneratedTrig)->Name("Kinematics/GeneratedTrig");

// The same kinematics in one generated pass (Model::Kinematics = EvalKinematics: SolveTrig, K, L
// and Phi_phi; no residual, no points).
void KinematicsGeneratedOnePass(benchmark::State& state) {
  Model::ParamsT<double> p;
  RuntimeValues(&p);
  Model::KinematicsT<double> kin;
  Model::TrigT<double> trig;
  long k = 0;
  for (auto _ : state) {
    const Eigen::Matrix<double, 1, 1> q = Eigen::Matrix<double, 1, 1>::Constant((k++ % 720) * kStep);
    const auto report = Model::Kinematics(p, q, Model::kDefaultModes, &trig, &kin);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(trig);
    benchmark::DoNotOptimize(kin);
  }
}
BENCHMARK(KinematicsGeneratedOnePass)->Name("Kinematics/GeneratedOnePass");

// The generated one-pass right-hand side (Model::Rhs = EvalRhs: SolveTrig, K, L, I, h, Q).
void RhsGenerated(benchmark::State& state) {
  Model::ParamsT<double> p;
  RuntimeValues(&p);
  Model::RhsConstantsT<double> rc;
  Model::Prepare(p, &rc);
  Model::TrigT<double> trig;
  Model::RhsT<double> rhs;
  const Eigen::Matrix<double, 1, 1> qd = Eigen::Matrix<double, 1, 1>::Constant(1.0);
  long k = 0;
  for (auto _ : state) {
    const Eigen::Matrix<double, 1, 1> q = Eigen::Matrix<double, 1, 1>::Constant((k++ % 720) * kStep);
    const auto report = Model::Rhs(p, rc, q, qd, 0.0, Model::kDefaultModes, &trig, &rhs);
    const double qdd = (rhs.Q(0) - rhs.h(0)) / rhs.I(0, 0);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(&qdd);
    benchmark::DoNotOptimize(rhs);
  }
}
BENCHMARK(RhsGenerated)->Name("Rhs/Generated");

// The same from the three general functions (SolveTrig, Coeffs, Dynamics), each compiled in
// the model's library.
void RhsGeneratedThreeCalls(benchmark::State& state) {
  Model::ParamsT<double> p;
  RuntimeValues(&p);
  Model::CoefficientsT<double> c;
  Model::TrigT<double> trig;
  Model::DynamicsT<double> dyn;
  Eigen::Matrix<double, Model::kNphi, 1> phi;
  for (int i = 0; i < Model::kNphi; ++i) phi(i) = Model::kAssemblyPhi[i];
  const Eigen::Matrix<double, 1, 1> qd = Eigen::Matrix<double, 1, 1>::Constant(1.0);
  long k = 0;
  for (auto _ : state) {
    const Eigen::Matrix<double, 1, 1> q = Eigen::Matrix<double, 1, 1>::Constant((k++ % 720) * kStep);
    // sin and cos of the angles only (Model::SolveTrig): the functions given trig do not read phi.
    const auto report = Model::SolveTrig(p, q, Model::kDefaultModes, &trig);
    Model::Coeffs(p, q, phi, &c, &trig);
    Model::Dynamics(p, q, phi, qd, 0.0, c, &dyn, nullptr, &trig);
    const double qdd = (dyn.Q(0) - dyn.h(0)) / dyn.I(0, 0);
    benchmark::DoNotOptimize(report);
    benchmark::DoNotOptimize(&qdd);
    benchmark::DoNotOptimize(dyn);
  }
}
BENCHMARK(RhsGeneratedThreeCalls)->Name("Rhs/GeneratedThreeCalls");
#endif

// ---------------------------------------------------------------------------------------------
// (b) Simulations.
#ifdef MECHGEN_BENCH_HAVE_INTEGRATORS
namespace dyn = mechgen::dynamics;
using State2 = Eigen::Matrix<double, 2, 1>;

struct HandRhs {
  FourbarParams<double> p;
  bool operator()(double /*t*/, const State2& y, State2* dy) const {
    FourbarEom<double> e;
    if (!Rhs(p, y(0), y(1), &e)) return false;
    (*dy)(0) = y(1);
    (*dy)(1) = e.qdd;
    return true;
  }
};

dyn::IntegratorOptions Tolerance(double tol) {
  dyn::IntegratorOptions o;
  o.rtol = tol;
  o.atol = tol;
  return o;
}

template <class Integrator>
SimResult SimulateHand(double tol) {
  HandRhs f;
  RuntimeValues(&f.p);
  Integrator integ(Tolerance(tol));
  const State2 y0(kQ0, 0.0);
  State2 y;
  dyn::IntegratorSummary s;
  SimResult r;
  r.ok = dyn::Integrate(&integ, f, 0.0, y0, kTEnd, &y, &s);
  r.theta = y(0);
  r.thetad = y(1);
  r.steps = s.steps;
  r.rhs = s.rhs_evaluations;
  return r;
}

// Energy drift of an integrator-driven method: `energy(y)` at the sample times by dense output.
template <class Integrator, class F, class Energy>
void DriftOf(F& f, const typename Integrator::State& y0, double tol, double t_end, double dt,
             Energy energy, std::vector<double>* drift) {
  Integrator integ(Tolerance(tol));
  const double e0 = energy(y0);
  drift->assign(1, 0.0);
  int next = 1;
  dyn::IntegratorSummary s;
  typename Integrator::State y;
  dyn::Integrate(
      &integ, f, 0.0, y0, t_end,
      [&](Integrator& it) {
        typename Integrator::State yd;
        while (next * dt <= it.t() + 1e-12) {
          if (!it.Dense(f, std::min(next * dt, it.t()), &yd)) return false;
          drift->push_back(energy(yd) - e0);
          ++next;
        }
        return true;
      },
      &y, &s);
}
#endif

#ifdef MECHGEN_BENCH_HAVE_MINIMAL
// The mechgen minimal method, as a user runs it (forward.h): samples only at the start and
// the end (sample_dt = t_end), no events but the dead-point check the runtime always makes.
template <template <int> class Method>
SimResult SimulateMechgen(double tol) {
  using Sim = dyn::MinimalDynamics<Model, Method>;
  static const typename Sim::Params p;
  dyn::MinimalOptions o;
  o.integrator = Tolerance(tol);
  o.sample_dt = kTEnd;
  Sim sim(p, o);
  const typename Sim::VecQ q0 = Sim::VecQ::Constant(kQ0), qd0 = Sim::VecQ::Zero();
  SimResult r;
  if (!sim.Initialize(q0)) return r;
  dyn::MinimalSummary summary;
  typename Sim::SampleT last;
  r.ok = sim.Simulate(0.0, q0, qd0, kTEnd, [](const typename Sim::SampleT&) { return true; },
                      &summary, &last);
  r.theta = last.q(0);
  r.thetad = last.qd(0);
  r.steps = summary.integrator.steps;
  r.rhs = summary.integrator.rhs_evaluations;
  return r;
}

// The runtime's right-hand side (MinimalDynamics::Derivative): warm-started positions, K, L,
// dynamics, qdd; one configuration per 0.5 deg step.
void RhsMinimalDynamics(benchmark::State& state) {
  using Sim = dyn::MinimalDynamics<Model, dyn::Dopri5>;
  const typename Sim::Params p;
  Sim sim(p);
  if (!sim.Initialize(Sim::VecQ::Constant(kQ0))) {
    state.SkipWithError("assembly failed");
    return;
  }
  typename Sim::State y, dy;
  y << 0.0, 1.0, 0.0;
  long k = 0;
  for (auto _ : state) {
    y(0) = (k++ % 720) * kStep;
    const bool ok = sim.Derivative(0.0, y, &dy);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(dy);
  }
}
BENCHMARK(RhsMinimalDynamics)->Name("Rhs/MinimalDynamics");
#endif

#ifdef MECHGEN_BENCH_HAVE_EXCESS
// The excess-coordinate method (excess.h): x = (q, phi) and xd integrated with the
// constraints at the acceleration level, the coordinate projection after each accepted step
// (positions by the generated solver, phid = K qd); samples at the start and the end only.
template <template <int> class Method>
SimResult SimulateExcess(double tol) {
  using Sim = dyn::ExcessDynamics<Model, Method>;
  static const typename Sim::Params p;
  dyn::ExcessOptions o;
  o.integrator = Tolerance(tol);
  o.projection = true;
  o.sample_dt = kTEnd;
  Sim sim(p, o);
  const typename Sim::VecQ q0 = Sim::VecQ::Constant(kQ0), qd0 = Sim::VecQ::Zero();
  typename Sim::VecPhi guess;
  for (int i = 0; i < Model::kNphi; ++i) guess(i) = Model::kAssemblyPhi[i];
  dyn::ExcessSummary summary;
  typename Sim::SampleT last;
  SimResult r;
  r.ok = sim.Simulate(0.0, q0, qd0, guess, kTEnd, [](const typename Sim::SampleT&) { return true; },
                      &summary, &last) &&
         std::abs(last.t - kTEnd) < 1e-12;
  r.theta = last.x(0);
  r.thetad = last.xd(0);
  r.steps = summary.integrator.steps;
  r.rhs = summary.integrator.rhs_evaluations;
  return r;
}
#endif

struct Method {
  std::string name;
  std::function<SimResult(double)> simulate;
};

std::vector<Method> Methods() {
  std::vector<Method> m;
#ifndef MECHGEN_BENCH_SIMBODY_ONLY
#ifdef MECHGEN_BENCH_HAVE_INTEGRATORS
#ifdef MECHGEN_BENCH_HAVE_MINIMAL
  m.push_back({"MechgenDopri5", SimulateMechgen<dyn::Dopri5>});
  m.push_back({"MechgenDop853", SimulateMechgen<dyn::Dop853>});
#endif
#ifdef MECHGEN_BENCH_HAVE_EXCESS
  m.push_back({"ExcessDopri5", SimulateExcess<dyn::Dopri5>});
  m.push_back({"ExcessDop853", SimulateExcess<dyn::Dop853>});
#endif
  m.push_back({"HandDopri5", SimulateHand<dyn::Dopri5<2>>});
  m.push_back({"HandDop853", SimulateHand<dyn::Dop853<2>>});
#endif
#endif
  static const SimbodyFourbar simbody;
  for (SimbodyIntegrator integ : {SimbodyIntegrator::kRungeKuttaMerson,
                                  SimbodyIntegrator::kRungeKuttaFeldberg,
                                  SimbodyIntegrator::kCPodes}) {
    m.push_back({std::string(MECHGEN_BENCH_SIMBODY_LABEL) + Name(integ), [integ](double tol) {
                   const SimbodyRun run = simbody.Simulate(integ, tol, kTEnd);
                   SimResult r;
                   r.theta = run.theta;
                   r.steps = run.steps;
                   r.rhs = run.realizations;
                   r.ok = run.ok;
                   return r;
                 }});
  }
  return m;
}

void RegisterSimulations() {
  static const std::vector<Method> methods = Methods();
  for (const Method& method : methods) {
    // Simbody also at 1e-11 and 1e-12: its errors at 1e-10 are larger than ours, and the
    // comparison at equal accuracy interpolates between measured points.
    const int e_max = method.name.find("Simbody") != std::string::npos ? 12 : 10;
    for (int e = 4; e <= e_max; ++e) {
      const double tol = std::pow(10.0, -e);
      const std::string name = "Simulate/" + method.name + "/1e-" + std::to_string(e);
      benchmark::RegisterBenchmark(name.c_str(), [&method, tol](benchmark::State& state) {
        SimResult r;
        for (auto _ : state) {
          r = method.simulate(tol);
          benchmark::DoNotOptimize(r);  // not a double: GB 1.7's "+m,r" on a double is broken with GCC
        }
        state.counters["error"] = std::fabs(r.theta - ReferenceTheta());
        state.counters["steps"] = static_cast<double>(r.steps);
        state.counters["rhs"] = static_cast<double>(r.rhs);
        state.counters["tol"] = tol;
        if (!r.ok) state.SkipWithError("simulation failed");
      })->Unit(benchmark::kMicrosecond);
    }
  }
}

int WriteDrift(const char* path, double t_end) {
  FILE* out = std::fopen(path, "w");
  if (out == nullptr) {
    std::fprintf(stderr, "cannot write %s\n", path);
    return 1;
  }
  const double dt = 0.05;
  const int n = static_cast<int>(std::lround(t_end / dt));
  std::vector<double> times;
  for (int i = 0; i <= n; ++i) times.push_back(i * dt);
  std::fprintf(out, "method,tolerance,t,drift\n");
  auto write = [&](const std::string& method, double tol, const std::vector<double>& drift) {
    for (size_t i = 0; i < drift.size() && i < times.size(); ++i)
      std::fprintf(out, "%s,%.0e,%.2f,%.6e\n", method.c_str(), tol, times[i], drift[i]);
  };
  for (double tol : {1e-6, 1e-9}) {
    std::vector<double> drift;
#ifndef MECHGEN_BENCH_SIMBODY_ONLY
#ifdef MECHGEN_BENCH_HAVE_INTEGRATORS
    {
      HandRhs f;
      const FourbarParams<double> p;
      auto energy = [&p](const State2& y) { return Energy(p, y(0), y(1)); };
      DriftOf<dyn::Dopri5<2>>(f, State2(kQ0, 0.0), tol, t_end, dt, energy, &drift);
      write("HandDopri5", tol, drift);
      DriftOf<dyn::Dop853<2>>(f, State2(kQ0, 0.0), tol, t_end, dt, energy, &drift);
      write("HandDop853", tol, drift);
    }
#endif
#ifdef MECHGEN_BENCH_HAVE_MINIMAL
    {
      const FourbarParams<double> hp;
      auto run = [&](auto* sim_tag, bool projection, const char* name) {
        using Sim = std::remove_pointer_t<decltype(sim_tag)>;
        const typename Sim::Params p;
        dyn::MinimalOptions o;
        o.integrator = Tolerance(tol);
        o.sample_dt = dt;
        o.energy_projection = projection;
        Sim sim(p, o);
        const typename Sim::VecQ q0 = Sim::VecQ::Constant(kQ0), qd0 = Sim::VecQ::Zero();
        drift.clear();
        if (!sim.Initialize(q0)) return;
        const double e0 = Energy(hp, kQ0, 0.0);
        dyn::MinimalSummary summary;
        sim.Simulate(0.0, q0, qd0, t_end,
                     [&](const typename Sim::SampleT& smp) {
                       drift.push_back(Energy(hp, smp.q(0), smp.qd(0)) - e0);
                       return true;
                     },
                     &summary);
        write(name, tol, drift);
      };
      run(static_cast<dyn::MinimalDynamics<Model, dyn::Dopri5>*>(nullptr), false, "MechgenDopri5");
      run(static_cast<dyn::MinimalDynamics<Model, dyn::Dop853>*>(nullptr), false, "MechgenDop853");
      run(static_cast<dyn::MinimalDynamics<Model, dyn::Dopri5>*>(nullptr), true,
          "MechgenDopri5EnergyProjection");
    }
#endif
#ifdef MECHGEN_BENCH_HAVE_EXCESS
    {
      using Sim = dyn::ExcessDynamics<Model, dyn::Dopri5>;
      const FourbarParams<double> hp;
      const Sim::Params p;
      dyn::ExcessOptions o;
      o.integrator = Tolerance(tol);
      o.projection = true;
      o.sample_dt = dt;
      Sim sim(p, o);
      Sim::VecPhi guess;
      for (int i = 0; i < Model::kNphi; ++i) guess(i) = Model::kAssemblyPhi[i];
      const double e0 = Energy(hp, kQ0, 0.0);
      drift.clear();
      dyn::ExcessSummary summary;
      sim.Simulate(0.0, Sim::VecQ::Constant(kQ0), Sim::VecQ::Zero(), guess, t_end,
                   [&](const Sim::SampleT& smp) {
                     drift.push_back(Energy(hp, smp.x(0), smp.xd(0)) - e0);
                     return true;
                   },
                   &summary);
      write("ExcessDopri5", tol, drift);
    }
#endif
#endif
    const SimbodyFourbar simbody;
    for (SimbodyIntegrator integ : {SimbodyIntegrator::kRungeKuttaMerson,
                                    SimbodyIntegrator::kRungeKuttaFeldberg,
                                    SimbodyIntegrator::kCPodes}) {
      simbody.EnergyDrift(integ, tol, times, &drift);
      write(std::string(MECHGEN_BENCH_SIMBODY_LABEL) + Name(integ), tol, drift);
    }
  }
  std::fclose(out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const char* drift_csv = nullptr;
  double drift_t = 30.0;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--drift_csv=", 12) == 0) drift_csv = argv[i] + 12;
    if (std::strncmp(argv[i], "--drift_t=", 10) == 0) drift_t = std::atof(argv[i] + 10);
  }
  if (drift_csv != nullptr) return WriteDrift(drift_csv, drift_t);
  char ref[64];
  std::snprintf(ref, sizeof(ref), "%.16f", ReferenceTheta());
  benchmark::AddCustomContext("reference_theta_3s", ref);
  benchmark::AddCustomContext("simbody_library", SimbodyFourbar::LibraryPath());
  RegisterSimulations();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
