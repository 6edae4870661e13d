// The statics along a motion at a given input speed (issue 45), on the shaper whose cutting
// force is a table of the ram's speed (models/shaper_speed.yaml: with a damper along the ram,
// viscous friction at O4, Coulomb friction at O2, masses and gravity):
//  - at the velocities qd the runtime's statics (the generated EvalStatics with `velocities`,
//    statics::Solve) are the generated kinetostatics at (qd, qdd = 0) with the inertia forces
//    left out, two ways: the kinetostatics of the machine with every mass (and so every moment
//    of inertia) 0, and the kinetostatics of the machine as it is minus that of its inertia
//    forces alone (the same machine with no loads and no gravity: everything in it is linear
//    in the forces on the links); its generalized force is EvalDynamics' Q at qd (what the
//    flywheel command reads); with Coulomb friction, at the friction loads the runtime
//    converged to, and those loads its fixed point;
//  - at rest the cutting force is 0 (cutting(0) = 0): a statics sweep at rest drives nothing
//    against it, one at the speed finds the peak that the cutting stroke needs, against the
//    ram's velocity coefficient by central differences of the positions (hand: drive =
//    -Fc cutting(omega ds/dtheta) ds/dtheta with everything else off);
//  - the note every run of the statics command prints and writes into its CSV's first line.
// Part of statics_slider_crank_friction_test (no test program of its own).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/solve.h"
#include "mechgen/statics/sweep.h"
#include "shaper_speed.h"
#include "slider_crank_friction.h"

namespace {

using M = mech::shaper_speed::Model;
using P = M::ParamsT<double>;
using VecQ = Eigen::Matrix<double, M::kNq, 1>;
using VecF = Eigen::Matrix<double, M::kNumFriction, 1>;
using Statics = M::StaticsT<double>;
namespace statics = mechgen::statics;

static_assert(statics::StaticsFeatures<M>::kReadsSpeed, "shaper_speed's statics read the ram's speed");
static_assert(!statics::StaticsFeatures<mech::slider_crank_friction::Model>::kReadsSpeed,
              "slider_crank_friction's statics read no speed");

constexpr double kPi = 3.141592653589793;
constexpr double kOmega = 2 * kPi;  // 60 rpm

// Every mass 0: no weights, no inertia forces (the moments of inertia are proportional).
P Massless(P p) {
  p.m_crank = p.m_rocker = p.m_block = p.m_link = p.m_ram = 0;
  return p;
}

// Only the inertia forces: no loads, dampers, viscous or Coulomb friction, gravity.
P InertiaOnly(P p) {
  p.Fc = p.c_ram = p.c_O4 = p.mu = p.g = 0;
  return p;
}

struct Configuration {
  VecQ q;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  M::CoefficientsT<double> c;
};

// The configurations at theta = 0, 15, ..., 345 deg on the model's assembly branch.
std::vector<Configuration> Configurations(const P& p) {
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), p);
  EXPECT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<Configuration> out;
  for (int k = 0; k < 24; ++k) {
    Configuration x;
    x.q(0) = k * 15 * kPi / 180;
    EXPECT_EQ(solver.MoveTo(x.q, nullptr), mechgen::position::Status::kConverged) << k;
    x.phi = solver.state().phi;
    M::Coeffs<double>(p, x.q, x.phi, &x.c);
    out.push_back(x);
  }
  return out;
}

Statics Kinetostatics(const P& p, const Configuration& x, const VecQ& qd, const VecF* f = nullptr) {
  Statics out;
  M::Kinetostatics<double>(p, x.q, x.phi, qd, VecQ::Zero(), 0.0, x.c, &out, f);
  return out;
}

// |a - b| <= 1e-12 (|a| + |b| + scale) for every entry.
template <class A, class B>
void ExpectClose(const A& a, const B& b, double scale, const std::string& what) {
  for (int i = 0; i < a.size(); ++i)
    EXPECT_LE(std::abs(a(i) - b(i)), 1e-12 * (std::abs(a(i)) + std::abs(b(i)) + scale))
        << what << "(" << i << "): " << a(i) << " vs " << b(i);
}

void ExpectSameStatics(const Statics& a, const Statics& b, double scale, const std::string& what) {
  ExpectClose(a.Q, b.Q, scale, what + " Q");
  ExpectClose(a.drive, b.drive, scale, what + " drive");
  ExpectClose(a.R, b.R, scale, what + " R");
  ExpectClose(a.normal, b.normal, scale, what + " normal");
}

TEST(StaticsSpeed, IsTheKinetostaticsWithoutTheInertiaForces) {
  const P p;
  const VecQ qd = VecQ::Constant(kOmega);
  int cutting = 0, changed = 0;
  for (const Configuration& x : Configurations(p)) {
    const std::string at = "theta " + std::to_string(x.q(0) * 180 / kPi) + " deg";
    // The massless machine: the kinetostatics has nothing to leave out.
    statics::Solution<M> massless;
    ASSERT_EQ(statics::Solve<M>(statics::Options(), Massless(p), x.q, x.phi, x.c, VecQ::Zero(),
                                &massless, &qd),
              statics::Status::kConverged);
    const Statics ks0 = Kinetostatics(Massless(p), x, qd);
    const double scale0 = ks0.R.cwiseAbs().maxCoeff();
    ExpectSameStatics(massless.statics, ks0, scale0, "massless, " + at);
    // The machine with its masses: its kinetostatics minus that of its inertia forces alone.
    statics::Solution<M> s;
    ASSERT_EQ(statics::Solve<M>(statics::Options(), p, x.q, x.phi, x.c, VecQ::Zero(), &s, &qd),
              statics::Status::kConverged);
    const Statics ks = Kinetostatics(p, x, qd), inertia = Kinetostatics(InertiaOnly(p), x, qd);
    Statics difference = ks;
    difference.Q = ks.Q - inertia.Q;
    difference.drive = ks.drive - inertia.drive;
    difference.R = ks.R - inertia.R;
    const double scale = std::max(ks.R.cwiseAbs().maxCoeff(), inertia.R.cwiseAbs().maxCoeff());
    ExpectClose(s.statics.Q, difference.Q, scale, "with masses, Q, " + at);
    ExpectClose(s.statics.drive, difference.drive, scale, "with masses, drive, " + at);
    ExpectClose(s.statics.R, difference.R, scale, "with masses, R, " + at);
    // The generalized force is EvalDynamics' Q at (q, qd), the applied forces the flywheel
    // command reads (machines/flywheel/machine_cycle.h: Q_static - Q(theta, omega)).
    M::DynamicsT<double> dynamics;
    M::Dynamics<double>(p, x.q, x.phi, qd, 0.0, x.c, &dynamics);
    ExpectClose(s.statics.Q, dynamics.Q, scale, "EvalDynamics' Q, " + at);
    // The inertia forces are there to leave out, and the speed changes the statics.
    EXPECT_GT(inertia.R.cwiseAbs().maxCoeff(), 1.0) << at;
    statics::Solution<M> rest;
    ASSERT_EQ(statics::Solve<M>(statics::Options(), p, x.q, x.phi, x.c, VecQ::Zero(), &rest),
              statics::Status::kConverged);
    // (except at the rocker's extremes, 210 and 330 deg, where the ram and the rocker stand
    // still: the cutting force, the damper and the viscous friction are 0 there).
    changed += (s.statics.R - rest.statics.R).cwiseAbs().maxCoeff() > 1.0;
    cutting += std::abs(massless.statics.drive(0)) > 0.5 * p.Fc;
    // The stiffness is that of the loads at rest: not evaluated at a speed.
    statics::Options with_stiffness;
    with_stiffness.stiffness = true;
    statics::Solution<M> stiff;
    statics::Solve<M>(with_stiffness, p, x.q, x.phi, x.c, VecQ::Zero(), &stiff, &qd);
    EXPECT_TRUE(std::isnan(stiff.statics.stiffness(0, 0))) << at;
  }
  EXPECT_EQ(changed, 22);  // all but the two extremes of the rocker
  EXPECT_GT(cutting, 4);   // the cutting force acts at several of these angles
}

TEST(StaticsSpeed, CoulombFrictionAtTheLoadsOfTheSpeed) {
  const P p = Massless(P());
  for (const double omega : {kOmega, -kOmega}) {
    const VecQ qd = VecQ::Constant(omega);
    for (const Configuration& x : Configurations(p)) {
      const std::string at = "theta " + std::to_string(x.q(0) * 180 / kPi) + " deg, omega " +
                             std::to_string(omega);
      for (const double way : {1.0, -1.0}) {
        statics::Solution<M> s;
        ASSERT_EQ(statics::Solve<M>(statics::Options(), p, x.q, x.phi, x.c, VecQ::Constant(way),
                                    &s, &qd),
                  statics::Status::kConverged)
            << at;
        // The kinetostatics of the massless machine at the converged friction loads ...
        const Statics ks = Kinetostatics(p, x, qd, &s.friction);
        ExpectSameStatics(s.statics, ks, ks.R.cwiseAbs().maxCoeff(), at);
        // ... whose friction loads are those loads: f = -mu r |F_O2| sign(K_rel . e).
        for (int J = 0; J < M::kNumFriction; ++J) {
          const double sign = ks.K_rel(J, 0) * way > 0 ? 1.0 : ks.K_rel(J, 0) * way < 0 ? -1.0 : 0.0;
          const double f = -ks.gain(J) * ks.normal(J) * sign;
          EXPECT_LE(std::abs(f - s.friction(J)), 1e-10 * (1 + std::abs(f))) << at << " joint " << J;
        }
      }
    }
  }
}

// The ram's x along the motion (s_stroke among the dependent coordinates).
int StrokeIndex() {
  for (int i = 0; i < M::kNphi; ++i)
    if (std::string(M::kPhiNames[i]) == "s_stroke") return i;
  return -1;
}

TEST(StaticsSpeed, TheSweepAtTheSpeedFindsTheCuttingPeak) {
  // Everything but the cutting force off: drive = -Q = -Fc cutting(omega ds/dtheta) ds/dtheta.
  P p = Massless(P());
  p.c_ram = p.c_O4 = p.mu = 0;
  const int stroke = StrokeIndex();
  ASSERT_GE(stroke, 0);
  const int steps = 720;
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  const VecQ begin = VecQ::Zero(), end = VecQ::Constant(2 * kPi), qd = VecQ::Constant(kOmega);
  std::vector<statics::StaticsRecord<M>> rest, moving;
  ASSERT_EQ(statics::StaticsSweep(statics::Options(), &solver, begin, end, steps, &rest), 0);
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  ASSERT_EQ(statics::StaticsSweep(statics::Options(), &solver, begin, end, steps, &moving,
                                  mechgen::SweepOptions(), &qd),
            0);
  // The ram's velocity coefficient by central differences of its positions (step 1e-5 rad:
  // error ~ 1e-10 h^2 s''' and rounding 1e-16 / 1e-5 m/rad).
  mechgen::position::PositionSolver<M> fd(mechgen::position::Options(), p);
  ASSERT_EQ(fd.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  auto ram_at = [&](double theta) {
    EXPECT_EQ(fd.MoveTo(VecQ::Constant(theta), nullptr), mechgen::position::Status::kConverged);
    return fd.state().phi(stroke);
  };
  constexpr double h = 1e-5;
  double peak_rest = 0, peak = 0, peak_hand = 0;
  for (int i = 0; i <= steps; ++i) {
    ASSERT_EQ(moving[i].status, statics::Status::kConverged);
    const double theta = moving[i].kinematics.q(0);
    const double ds = (ram_at(theta + h) - ram_at(theta - h)) / (2 * h);
    const double speed = kOmega * ds;
    // cutting(v): 1 up to -0.05 m/s, then linearly to 0 at rest, 0 beyond.
    const double cutting = speed <= -0.05 ? 1.0 : speed < 0 ? -speed / 0.05 : 0.0;
    const double hand = -p.Fc * cutting * ds;
    const double drive = moving[i].frictionless.statics.drive(0);
    // Near v = 0 the table's slope 20 s/m times the central difference's error.
    EXPECT_NEAR(drive, hand, 1e-5 * p.Fc) << "theta " << theta;
    peak_rest = std::max(peak_rest, std::abs(rest[i].frictionless.statics.drive(0)));
    peak = std::max(peak, std::abs(drive));
    peak_hand = std::max(peak_hand, std::abs(hand));
  }
  EXPECT_EQ(peak_rest, 0.0);  // at rest the cutting force is cutting(0) = 0
  EXPECT_NEAR(peak, peak_hand, 1e-6 * peak_hand);
  // The cutting stroke's largest ds/dtheta, r L / (d + r) ~ 1.33 m/rad on a 4 m rocker: a
  // peak of about Fc x 1.3 (hundreds of N m), where the statics at rest said 0.
  EXPECT_GT(peak, 1.2 * p.Fc);
  EXPECT_LT(peak, 1.5 * p.Fc);
}

TEST(StaticsSpeed, TheNoteSaysWhatReadsAVelocity) {
  const std::string rest = statics::SpeedNote<M>(nullptr);
  for (const char* part : {"at rest", "x of load 'cut' (s_stroke_dot)", "damper 'ram'",
                           "viscous friction at joint O4", "qd = 0", "--speed"})
    EXPECT_NE(rest.find(part), std::string::npos) << part << " in: " << rest;
  const VecQ qd = VecQ::Constant(kOmega);
  const std::string at = statics::SpeedNote<M>(&qd);
  for (const char* part : {"theta_crank_dot = 6.28318531 rad/s", "x of load 'cut' (s_stroke_dot)",
                           "without the inertia forces"})
    EXPECT_NE(at.find(part), std::string::npos) << part << " in: " << at;
  // A model whose statics read no velocity: nothing to say at rest, and that a speed changes
  // nothing.
  using SF = mech::slider_crank_friction::Model;
  EXPECT_EQ(statics::SpeedNote<SF>(nullptr), "");
  const Eigen::Matrix<double, SF::kNq, 1> speed = Eigen::Matrix<double, SF::kNq, 1>::Constant(1.0);
  EXPECT_NE(statics::SpeedNote<SF>(&speed).find("nothing in the statics reads a velocity"),
            std::string::npos);
  // The CSV's first comment line carries it (as statics_main.cc writes it).
  P p;
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<statics::StaticsRecord<M>> records;
  statics::StaticsSweep(statics::Options(), &solver, VecQ::Zero(), VecQ::Constant(1.0), 4, &records);
  std::ostringstream csv;
  statics::WriteStaticsCsv(records, csv,
                           mechgen::Described(mechgen::CsvAbout("shaper_speed_statics", M::kName,
                                                                "statics sweep (" + rest + ")",
                                                                statics::kStaticsSigns)));
  const std::string first = csv.str().substr(0, csv.str().find('\n'));
  EXPECT_EQ(first.rfind("# shaper_speed_statics, model shaper_speed: statics sweep (at rest: ", 0), 0u)
      << first;
}

}  // namespace
