// The runtime on the generated models of issue 15's later steps:
//  - damped_fourbar (dampers, viscous friction, a load of time, a load of a dependent speed):
//    the energy balance E - W_nc = E0 along a run (W_nc the integrated power of the
//    non-conservative forces), and with the harmonic torque off E never increases;
//  - fivebar_massive (two inputs: a 2 x 2 inertia, the LDLT path): energy kept under gravity;
//  - slider_crank_motor: the start-up from rest reaches a periodic steady state below the
//    motor's synchronous speed, with the energy balance kept;
//  - the excess-coordinate formulation of fourbar_massive against the handwritten one (two
//    derivations of M, h, g, Phi_x, gamma) and against the minimal method.
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "damped_fourbar.h"
#include "fivebar_massive.h"
#include "fourbar_massive.h"
#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/excess.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/prescribed.h"
#include "slider_crank_motor.h"

namespace {

namespace hw = mech::handwritten_fourbar_dynamics;
namespace fm = mech::fourbar_massive;
using mechgen::dynamics::Dop853;
using mechgen::dynamics::Dopri5;
using mechgen::dynamics::MinimalDynamics;
using mechgen::dynamics::MinimalOptions;
using mechgen::dynamics::MinimalSummary;
using mechgen::dynamics::Status;
using Vec1 = Eigen::Matrix<double, 1, 1>;
constexpr double kPi = 3.14159265358979323846;

TEST(MinimalGeneratedMore, DampedFourbarKeepsTheEnergyBalance) {
  namespace df = mech::damped_fourbar;
  for (double T0 : {3.0, 0.0}) {
    df::Params<double> p;
    p.T0 = T0;
    MinimalOptions o;
    o.integrator.rtol = 1e-11;
    o.integrator.atol = 1e-12;
    o.sample_dt = 0.01;
    MinimalDynamics<df::Model, Dop853> sim(p, o);
    ASSERT_TRUE(sim.Initialize(Vec1(kPi / 2)));
    MinimalSummary summary;
    double E0 = std::numeric_limits<double>::quiet_NaN(), max_balance = 0, E_prev = 0;
    bool increased = false;
    ASSERT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(4.0), 5.0,
                             [&](const auto& s) {
                               if (std::isnan(E0)) E0 = s.E;
                               else if (s.E > E_prev + 1e-9 * E0) increased = true;
                               E_prev = s.E;
                               max_balance = std::max(max_balance, std::abs(s.E - s.W - E0));
                               return true;
                             },
                             &summary))
        << mechgen::dynamics::FormatSummary(summary);
    EXPECT_LT(max_balance, 1e-8 * E0) << "T0 = " << T0;
    EXPECT_LT(E_prev, 0.8 * E0) << "T0 = " << T0;  // the dampers took a good part of it
    if (T0 == 0) {
      EXPECT_FALSE(increased);  // dissipation only: E never grows
    }
  }
}

TEST(MinimalGeneratedMore, TwoInputFivebarKeepsItsEnergy) {
  namespace fb = mech::fivebar_massive;
  MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  const Eigen::Vector2d q0(fb::Model::kAssemblyQ[0], fb::Model::kAssemblyQ[1]);
  {
    MinimalDynamics<fb::Model, Dopri5> sim(fb::Params<double>(), o);
    ASSERT_TRUE(sim.Initialize(q0));
    MinimalSummary summary;
    double E0 = std::numeric_limits<double>::quiet_NaN(), max_err = 0, moved = 0;
    ASSERT_TRUE(sim.Simulate(0.0, q0, Eigen::Vector2d(0.3, -0.2), 0.8,
                             [&](const auto& s) {
                               if (std::isnan(E0)) E0 = s.E;
                               max_err = std::max(max_err, std::abs(s.E - E0));
                               moved = std::max(moved, (s.q - q0).norm());
                               return true;
                             },
                             &summary))
        << mechgen::dynamics::FormatSummary(summary);
    EXPECT_GT(moved, 0.1);
    EXPECT_LT(max_err, 1e-7 * (1 + std::abs(E0)));
  }
  {
    // Later (t ~ 1.1 s) links BC and DC align: Phi_phi turns singular and the two cranks' angles
    // no longer describe the motion. The run ends there as a dead point, not with NaN and not
    // after a million steps.
    o.integrator.max_steps = 20000;
    MinimalDynamics<fb::Model, Dopri5> sim(fb::Params<double>(), o);
    ASSERT_TRUE(sim.Initialize(q0));
    MinimalSummary summary;
    bool finite = true;
    EXPECT_FALSE(sim.Simulate(0.0, q0, Eigen::Vector2d(0.3, -0.2), 2.0,
                              [&](const auto& s) {
                                finite = finite && s.q.allFinite() && s.qd.allFinite();
                                return true;
                              },
                              &summary));
    EXPECT_EQ(summary.status, Status::kDeadPoint) << mechgen::dynamics::FormatSummary(summary);
    EXPECT_TRUE(finite);
    EXPECT_LT(summary.min_rcond_seen, 1e-3);
    EXPECT_GT(summary.t_end, 0.8);
  }
}

TEST(MinimalGeneratedMore, SliderCrankMotorStartsUpToASteadyState) {
  namespace sm = mech::slider_crank_motor;
  MinimalOptions o;
  o.integrator.rtol = 1e-9;
  o.integrator.atol = 1e-11;
  o.sample_dt = 0.001;
  MinimalDynamics<sm::Model, Dopri5> sim(sm::Params<double>(), o);
  const double q0 = sm::Model::kAssemblyQ[0];
  ASSERT_TRUE(sim.Initialize(Vec1(q0)));
  // Revolution times (crossings of q0 + 2 pi k).
  std::vector<double> crossings;
  double prev_t = 0, prev_q = q0, E0 = std::numeric_limits<double>::quiet_NaN(), balance = 0;
  double speed = 0;
  MinimalSummary summary;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(q0), Vec1(0.0), 20.0,
                           [&](const auto& s) {
                             if (std::isnan(E0)) E0 = s.E;
                             balance = std::max(balance, std::abs(s.E - s.W - E0));
                             const double k0 = std::floor((prev_q - q0) / (2 * kPi));
                             const double k1 = std::floor((s.q(0) - q0) / (2 * kPi));
                             if (k1 > k0) {
                               const double level = q0 + 2 * kPi * k1;
                               crossings.push_back(prev_t + (s.t - prev_t) * (level - prev_q) /
                                                                (s.q(0) - prev_q));
                             }
                             prev_t = s.t;
                             prev_q = s.q(0);
                             speed = s.qd(0);
                             return true;
                           },
                           &summary))
      << mechgen::dynamics::FormatSummary(summary);
  ASSERT_GT(crossings.size(), 20u);
  const size_t n = crossings.size();
  const double last = crossings[n - 1] - crossings[n - 2];
  const double before = crossings[n - 2] - crossings[n - 3];
  EXPECT_NEAR(last, before, 1e-4 * last);  // periodic
  const double mean_speed = 2 * kPi / last;
  EXPECT_GT(mean_speed, 100.0);
  EXPECT_LT(mean_speed, 157.0796);  // an induction motor runs below its synchronous speed
  EXPECT_GT(speed, 0.0);
  // E - W_nc: the motor's work and the losses accounted for (J; E of the order of the
  // flywheel's 1/2 J w^2 ~ 5 kJ).
  EXPECT_LT(balance, 1e-5 * 0.5 * 0.5 * mean_speed * mean_speed);
}

TEST(MinimalGeneratedMore, ExcessFormulationMatchesTheHandwrittenOne) {
  const fm::Params<double> pg;
  const hw::Params<double> ph;
  for (double q = 0.1; q < 2 * kPi; q += 0.8) {
    // Any state, on or off the constraint manifold.
    const Eigen::Vector2d phi(0.4 + 0.1 * q, 1.8 - 0.05 * q), phid(0.7, -1.1);
    const Vec1 qq(q), qd(1.3);
    fm::Excess<double> eg;
    hw::Excess<double> eh;
    fm::Model::ExcessDynamics(pg, qq, phi, qd, phid, 0.0, &eg);
    hw::Model::ExcessDynamics(ph, qq, phi, qd, phid, 0.0, &eh);
    EXPECT_LT((eg.M - eh.M).cwiseAbs().maxCoeff(), 1e-11) << "q = " << q;
    EXPECT_LT((eg.h - eh.h).cwiseAbs().maxCoeff(), 1e-11) << "q = " << q;
    EXPECT_LT((eg.g - eh.g).cwiseAbs().maxCoeff(), 1e-10) << "q = " << q;
    EXPECT_LT((eg.Phi_x - eh.Phi_x).cwiseAbs().maxCoeff(), 1e-12) << "q = " << q;
    EXPECT_LT((eg.Phi - eh.Phi).cwiseAbs().maxCoeff(), 1e-12) << "q = " << q;
    EXPECT_LT((eg.gamma - eh.gamma).cwiseAbs().maxCoeff(), 1e-11) << "q = " << q;
    EXPECT_NEAR(eg.T, eh.T, 1e-11);
    EXPECT_NEAR(eg.V, eh.V, 1e-10);
  }
}

TEST(MinimalGeneratedMore, ExcessMethodAgreesWithTheMinimalMethodOnTheGeneratedModel) {
  MinimalOptions o;
  o.integrator.rtol = 1e-12;
  o.integrator.atol = 1e-13;
  MinimalDynamics<fm::Model, Dop853> minimal(fm::Params<double>(), o);
  ASSERT_TRUE(minimal.Initialize(Vec1(kPi / 2)));
  MinimalSummary ms;
  mechgen::dynamics::Sample<fm::Model> m_last;
  ASSERT_TRUE(minimal.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 3.0, [](const auto&) { return true; },
                               &ms, &m_last));
  mechgen::dynamics::ExcessOptions eo;
  eo.integrator.rtol = 1e-11;
  eo.integrator.atol = 1e-12;
  eo.projection = true;
  mechgen::dynamics::ExcessDynamics<fm::Model, Dop853> excess(fm::Params<double>(), eo);
  mechgen::dynamics::ExcessSummary es;
  mechgen::dynamics::ExcessSample<fm::Model> e_last;
  ASSERT_TRUE(excess.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), Eigen::Vector2d(0.5, 1.9), 3.0,
                              [](const auto&) { return true; }, &es, &e_last));
  EXPECT_NEAR(e_last.x(0), m_last.q(0), 1e-7);
  EXPECT_NEAR(e_last.xd(0), m_last.qd(0), 1e-6);
  EXPECT_LT(es.max_Phi, 1e-9);
}

// The systems of the one simulator on two threads at once give the bytes of one at a time
// (issue 46; tests/runtime/two_threads_test.cc covers the engine and the free swing of the
// minimal method): the excess-coordinate system (ExcessDynamics, projected), a free two-input
// five-bar (MinimalDynamics) and the same five-bar with crank2 driven through via points
// (PrescribedDynamics). The oracle: each run done alone on this thread first; every double a
// run hands out (each sample's state and figures, the summary's) compared with memcmp.
using Numbers = std::vector<double>;
template <class Derived>
void Append(const Eigen::MatrixBase<Derived>& m, Numbers* out) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i) out->push_back(m(i, j));
}
bool SameBytes(const Numbers& a, const Numbers& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}
/// The figures every system's summary has; its status and event last.
template <class Summary>
void AppendSummary(const Summary& s, Numbers* out) {
  out->insert(out->end(), {s.t_end, static_cast<double>(s.samples), static_cast<double>(s.integrator.steps),
                           static_cast<double>(s.integrator.rejected), s.max_energy_error, s.min_rcond_seen,
                           static_cast<double>(s.status), static_cast<double>(s.event)});
}

Numbers ExcessRun() {
  mechgen::dynamics::ExcessOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.projection = true;
  o.sample_dt = 0.01;
  mechgen::dynamics::ExcessDynamics<fm::Model, Dop853> excess(fm::Params<double>(), o);
  mechgen::dynamics::ExcessSummary summary;
  Numbers out;
  excess.Simulate(0.0, Vec1(kPi / 2), Vec1(2.0), Eigen::Vector2d(0.5, 1.9), 2.0,
                  [&](const mechgen::dynamics::ExcessSample<fm::Model>& s) {
                    out.insert(out.end(), {s.t, s.T, s.V, s.Phi_norm, s.Phid_norm});
                    Append(s.x, &out);
                    Append(s.xd, &out);
                    return true;
                  },
                  &summary);
  out.push_back(summary.max_Phi);
  out.push_back(static_cast<double>(summary.projections));
  AppendSummary(summary, &out);
  return out;
}

Numbers FreeFivebarRun() {
  using FB = mech::fivebar_massive::Model;
  MinimalOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.01;
  MinimalDynamics<FB> sim(FB::ParamsT<double>(), o);
  // (TwoInputFivebarKeepsItsEnergy's swing, which reaches a singular configuration after 1.1 s.)
  const Eigen::Vector2d q0(FB::kAssemblyQ[0], FB::kAssemblyQ[1]), qd0(0.3, -0.2);
  Numbers out;
  if (!sim.Initialize(q0)) return out;
  MinimalSummary summary;
  sim.Simulate(0.0, q0, qd0, 0.8,
               [&](const mechgen::dynamics::Sample<FB>& s) {
                 out.insert(out.end(), {s.t, s.T, s.V, s.W, s.P_nc, s.rcond, s.det});
                 Append(s.q, &out);
                 Append(s.qd, &out);
                 Append(s.qdd, &out);
                 Append(s.phi, &out);
                 return true;
               },
               &summary);
  AppendSummary(summary, &out);
  return out;
}

Numbers DrivenFivebarRun() {
  namespace dyn = mechgen::dynamics;
  using FB = mech::fivebar_massive::Model;
  // crank2 through via points (a clamped spline from rest to rest), crank1 free.
  const dyn::SplineLaw<5> law({0.0, 0.3, 0.7, 1.0, 1.4}, {kPi / 2, 1.9, 2.2, 1.8, 1.4});
  auto drive = dyn::MakeDrive(law);
  dyn::PrescribedOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.01;
  dyn::PrescribedDynamics<FB, 1, decltype(drive), dyn::NoForce, Dop853> sim(FB::ParamsT<double>(), {1}, drive,
                                                                            dyn::NoForce(), o);
  Numbers out;
  if (!sim.Initialize(0.0, Vec1(kPi / 2))) return out;
  dyn::PrescribedSummary summary;
  sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 1.6,
               [&](const dyn::PrescribedSample<FB, 1>& s) {
                 out.insert(out.end(), {s.t, s.T, s.V, s.W_act, s.P_act, s.rcond, s.det});
                 Append(s.q, &out);
                 Append(s.qd, &out);
                 Append(s.qdd, &out);
                 Append(s.lambda, &out);
                 Append(s.phi, &out);
                 return true;
               },
               &summary);
  out.push_back(summary.max_abs_lambda);
  AppendSummary(summary, &out);
  return out;
}

TEST(MinimalGeneratedMore, ExcessFreeAndDrivenSystemsOnTwoThreadsGiveTheBytesOfOneAtATime) {
  using Job = std::function<Numbers()>;
  const std::vector<Job> jobs = {ExcessRun, FreeFivebarRun, DrivenFivebarRun};
  std::vector<Numbers> one_at_a_time;
  for (const Job& job : jobs) one_at_a_time.push_back(job());
  for (size_t k = 0; k < jobs.size(); ++k) {
    const Numbers& r = one_at_a_time[k];
    ASSERT_GT(r.size(), 1000u) << "job " << k;  // (100 samples and more, each of many numbers)
    // The run reached its end (the summary's status, the last figure but one).
    EXPECT_EQ(r[r.size() - 2], static_cast<double>(Status::kSuccess)) << "job " << k;
  }
  // At once: thread A runs the excess system and the driven five-bar, thread B the free
  // five-bar and the excess system again; several rounds, both released together.
  constexpr int kRounds = 10;
  std::vector<std::vector<Numbers>> at_once(2 * jobs.size());
  std::atomic<int> ready{0};
  auto worker = [&](std::vector<size_t> mine, size_t slot) {
    ready.fetch_add(1);
    while (ready.load() < 2) std::this_thread::yield();
    for (int round = 0; round < kRounds; ++round)
      for (size_t k : mine) at_once[slot + k].push_back(jobs[k]());
  };
  std::thread a(worker, std::vector<size_t>{0, 2}, 0);
  std::thread b(worker, std::vector<size_t>{1, 0}, jobs.size());
  a.join();
  b.join();
  for (size_t slot = 0; slot < at_once.size(); ++slot) {
    const size_t k = slot % jobs.size();
    const bool ran = (slot < jobs.size() && k != 1) || (slot >= jobs.size() && k != 2);
    ASSERT_EQ(at_once[slot].size(), ran ? static_cast<size_t>(kRounds) : 0u) << "slot " << slot;
    for (const Numbers& r : at_once[slot]) EXPECT_TRUE(SameBytes(r, one_at_a_time[k])) << "job " << k;
  }
}

TEST(MinimalGeneratedMore, ASampleGridThatCannotAdvanceIsRefused) {
  // A sample step so small that t + sample_dt == t (the simulate tool's --dt, the engine's
  // run-up) is refused with a status before any step, never a loop without end; so is one at
  // times so large that a step of sample_dt does not move them, and a grid of more than
  // max_samples samples. The same options with a usable step run.
  struct Case {
    double t0, t_end, sample_dt;
    int max_samples;
    Status expected;
  };
  const Case cases[] = {{0.0, 1.0, 1e-300, 100000000, Status::kInvalidInput},
                        {0.0, 1.0, 1e-17, 100000000, Status::kInvalidInput},
                        {1e20, 1e20 + 1e5, 1.0, 100000000, Status::kInvalidInput},
                        {0.0, 1.0, 1e-3, 999, Status::kInvalidInput},
                        {0.0, 1.0, 1e-3, 1000, Status::kSuccess}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.sample_dt);
    MinimalOptions o;
    o.sample_dt = c.sample_dt;
    o.max_samples = c.max_samples;
    MinimalDynamics<fm::Model> sim(fm::Params<double>(), o);
    ASSERT_TRUE(sim.Initialize(Vec1(kPi / 2)));
    MinimalSummary summary;
    int samples = 0;
    sim.Simulate(c.t0, Vec1(kPi / 2), Vec1(0.0), c.t_end,
                 [&](const auto&) {
                   ++samples;
                   return true;
                 },
                 &summary);
    EXPECT_EQ(summary.status, c.expected) << mechgen::dynamics::FormatSummary(summary);
    if (c.expected == Status::kInvalidInput) {
      EXPECT_EQ(samples, 0);
      EXPECT_EQ(summary.integrator.steps, 0);
    } else {
      EXPECT_EQ(samples, 1001);
    }
  }
}

}  // namespace
