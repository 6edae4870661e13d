// Two simulations and two sweeps on two threads at once give the same bytes as one at a time
// (issue 24: no mutable globals or statics in the runtime). The oracle is the same runs done
// one at a time on this thread first; each result is reduced to every double it holds and
// compared with memcmp (bitwise, NaN-safe).
//
// The simulations are two engine run-ups of engine_single under two different gas laws (a
// per-run source: the gas law used to sit in a static pointer, so two of them could not run
// at once) and a free swing of fourbar_massive; the sweeps are position sweeps of fourbar and
// of slider_crank.
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "engine_single.h"
#include "fourbar.h"
#include "fourbar_massive.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/gas.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "slider_crank.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Numbers = std::vector<double>;

Vec1 V1(double x) { return Vec1::Constant(x); }

template <class Derived>
void Append(const Eigen::MatrixBase<Derived>& m, Numbers* out) {
  for (int j = 0; j < m.cols(); ++j)
    for (int i = 0; i < m.rows(); ++i) out->push_back(m(i, j));
}

/// A run-up of engine_single from 100 rad/s under the gas law of the given compression ratio
/// and heat per cycle: every sample (t, theta, omega, its derivative, T, Q, W) and the
/// summary's figures.
Numbers EngineRun(double compression_ratio, double heat) {
  using M = mech::engine_single::Model;
  mech::engine_single::Params<double> p;
  mechgen::engine::PolytropicWiebeParams P;
  P.bore = p.bore;
  P.stroke = 2 * p.r;
  P.rod_length = p.l;
  P.compression_ratio = compression_ratio;
  P.heat = heat;
  mechgen::engine::PolytropicWiebeCycle law;
  std::string error;
  if (!law.Init(P, &error)) return {-1};
  using Gas = mechgen::engine::GasTorque<mechgen::engine::PolytropicWiebeCycle>;
  Gas gas;
  gas.law = &law;
  gas.cycle = law.cycle();
  gas.count = 1;
  gas.cylinders[0] = {1, kPi * p.bore * p.bore / 4, p.phase_1};
  p.c_load = 0.02;
  mechgen::dynamics::MinimalOptions mo;
  mo.integrator.rtol = 1e-9;
  mo.integrator.atol = 1e-10;
  mo.sample_dt = 1e-3;
  mechgen::engine::GasDriven<M, Gas> sim(p, mo, {gas});
  if (!sim.Initialize(V1(0.0))) return {-2};
  Numbers out;
  mechgen::dynamics::MinimalSummary summary;
  sim.Simulate(0.0, V1(0.0), V1(100.0), 0.25,
               [&](const auto& s) {
                 out.insert(out.end(), {s.t, s.q(0), s.qd(0), s.qdd(0), s.T, s.Q(0), s.W});
                 return true;
               },
               &summary);
  out.insert(out.end(), {static_cast<double>(summary.status), summary.t_end,
                         static_cast<double>(summary.integrator.steps), summary.max_energy_error});
  return out;
}

/// A free swing of fourbar_massive from rest at 90 degrees.
Numbers FreeRun() {
  using M = mech::fourbar_massive::Model;
  mechgen::dynamics::MinimalOptions mo;
  mo.sample_dt = 1e-2;
  mechgen::dynamics::MinimalDynamics<M> sim(mech::fourbar_massive::Params<double>(), mo);
  if (!sim.Initialize(V1(kPi / 2))) return {-2};
  Numbers out;
  mechgen::dynamics::MinimalSummary summary;
  sim.Simulate(0.0, V1(kPi / 2), V1(0.0), 3.0,
               [&](const auto& s) {
                 out.insert(out.end(), {s.t, s.q(0), s.qd(0), s.qdd(0), s.T, s.V, s.W, s.rcond});
                 Append(s.phi, &out);
                 return true;
               },
               &summary);
  out.insert(out.end(), {static_cast<double>(summary.status), summary.t_end,
                         static_cast<double>(summary.integrator.steps), summary.max_energy_error});
  return out;
}

/// A position sweep of model M over [q0, q1] in `steps` steps: every row's status, q, phi,
/// phid and phidd.
template <class M>
Numbers SweepRun(double q0, double q1, int steps) {
  mechgen::position::PositionSolver<M> solver;
  if (solver.AssembleDefault(nullptr) != mechgen::position::Status::kConverged) return {-2};
  Numbers out;
  const int failed = mechgen::SweepRows(
      &solver, V1(q0), V1(q1), steps, V1(1.0), V1(0.0), mechgen::SweepOptions(),
      [&](int i, const mechgen::SweepRecord<M>& r) {
        out.insert(out.end(), {static_cast<double>(i), static_cast<double>(r.summary.status), r.q(0)});
        Append(r.state.phi, &out);
        Append(r.motion.phid, &out);
        Append(r.motion.phidd, &out);
      });
  out.push_back(failed);
  return out;
}

bool SameBytes(const Numbers& a, const Numbers& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(TwoThreads, TwoSimulationsAndTwoSweepsAtOnceGiveTheBytesOfOneAtATime) {
  using Job = std::function<Numbers()>;
  const std::vector<Job> jobs = {
      [] { return EngineRun(10.0, 800.0); },
      [] { return EngineRun(8.0, 500.0); },
      [] { return FreeRun(); },
      [] { return SweepRun<mech::fourbar::Model>(0.0, 2 * kPi, 720); },
      [] { return SweepRun<mech::slider_crank::Model>(-kPi, 3 * kPi, 720); },
  };
  // The oracle: one at a time, on this thread.
  std::vector<Numbers> one_at_a_time;
  for (const Job& job : jobs) one_at_a_time.push_back(job());
  for (size_t k = 0; k < jobs.size(); ++k) ASSERT_GT(one_at_a_time[k].size(), 100u) << "job " << k;
  // The two engine runs differ (else the test could not see one law used for both), and the
  // engine ran (its last summary figure is a status: success).
  ASSERT_FALSE(SameBytes(one_at_a_time[0], one_at_a_time[1]));
  for (int k : {0, 1, 2}) {
    const Numbers& r = one_at_a_time[k];
    ASSERT_EQ(r[r.size() - 4], static_cast<double>(mechgen::dynamics::Status::kSuccess)) << "job " << k;
  }
  // At once: thread A runs the first engine run and the fourbar sweep, thread B the second
  // engine run, the free swing and the slider-crank sweep; every job several times, both
  // threads released together so that the runs overlap.
  constexpr int kRounds = 10;
  std::vector<std::vector<Numbers>> at_once(jobs.size());
  std::atomic<int> ready{0};
  auto worker = [&](std::vector<size_t> mine) {
    ready.fetch_add(1);
    while (ready.load() < 2) std::this_thread::yield();
    for (int round = 0; round < kRounds; ++round)
      for (size_t k : mine) at_once[k].push_back(jobs[k]());
  };
  std::thread a(worker, std::vector<size_t>{0, 3});
  std::thread b(worker, std::vector<size_t>{1, 2, 4});
  a.join();
  b.join();
  for (size_t k = 0; k < jobs.size(); ++k) {
    ASSERT_EQ(at_once[k].size(), static_cast<size_t>(kRounds));
    for (int round = 0; round < kRounds; ++round)
      EXPECT_TRUE(SameBytes(at_once[k][round], one_at_a_time[k])) << "job " << k << ", round " << round;
  }
}

}  // namespace
