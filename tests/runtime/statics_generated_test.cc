// The statics runtime on the generated models with statics (models/slider_crank_friction,
// slider_crank_press, fourbar_loaded), against oracles written here:
//  - slider_crank_friction with friction at the crank bearing O only (the other pins' radii
//    and the slide's coefficient set to 0 through Params): the friction circle
//    T = T0 +- mu_O r_O |P| with P = F / cos(beta) (the rod a two-force member), and the
//    dead zones against the hand-derived limits a |sin(q - beta)| = mu_O r_O (the same
//    closed form as statics_friction_test.cc);
//  - with all four friction joints: the converged loads reproduce themselves,
//    f_J = -gain_J normal_J sign(K_rel_J qdot), and the driving torque is the frictionless
//    one minus the virtual work of the friction loads, drive(f) = drive(0) - sum f_J K_rel_J;
//    friction only dissipates (forward efficiency in (0, 1]);
//  - slider_crank_press without gravity: |drive| MA = the press law P0 h / (h + a + b - s)
//    (virtual work), MA growing without bound towards the toggle at q = 0;
//  - fourbar_loaded: equilibria (Q = 0) with stiffness against a central difference of Q;
//  - a slider-crank made singular (a = b): the statics sweep stops with a `singular` row that
//    prints no force; every model's CSV columns are unique.
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fourbar_loaded.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/sweep.h"
#include "slider_crank_friction.h"
#include "slider_crank_press.h"

namespace mechgen::statics {
namespace {

using Friction = mech::slider_crank_friction::Model;
using Press = mech::slider_crank_press::Model;
using Loaded = mech::fourbar_loaded::Model;

static_assert(StaticsFeatures<Friction>::kHasStatics && StaticsFeatures<Friction>::kHasFriction);
static_assert(StaticsFeatures<Friction>::kNumFriction == 4);
static_assert(StaticsFeatures<Press>::kHasStatics && StaticsFeatures<Press>::kHasPotential);
static_assert(!StaticsFeatures<Press>::kHasFriction);
static_assert(StaticsFeatures<Loaded>::kHasReactions && StaticsFeatures<Loaded>::kHasStiffness);
static_assert(StaticsFeatures<Loaded>::kStiffnessApart && StaticsFeatures<Press>::kStiffnessApart);
static_assert(!StaticsFeatures<mech::fourbar_loaded::Model>::kHasFriction);

template <class M>
void ExpectUniqueColumns() {
  const std::vector<std::string> names = StaticsCsvColumns<M>();
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
}

TEST(StaticsGenerated, ColumnNamesAreUnique) {
  ExpectUniqueColumns<Friction>();
  ExpectUniqueColumns<Press>();
  ExpectUniqueColumns<Loaded>();
  const std::vector<std::string> names = StaticsCsvColumns<Loaded>();
  for (const char* name : {"drive_theta_crank", "F_A_x", "F_D_y", "F_B_mag", "V", "stiffness",
                           "mechanical_advantage", "status"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
}

// Friction only at the crank bearing O.
ModelTypes<Friction>::Params OnlyO() {
  ModelTypes<Friction>::Params p;
  p.r_B = 0;
  p.r_C = 0;
  p.mu_s = 0;
  return p;
}
double Beta(double a, double b, double q) { return std::asin(-a * std::sin(q) / b); }
double Lever(double a, double b, double q) {  // a sin(q - beta)
  return a * std::sin(q) * (std::cos(Beta(a, b, q)) + a / b * std::cos(q));
}

TEST(StaticsGenerated, SliderCrankFrictionCircleAtO) {
  const auto p = OnlyO();
  const double mu_r = p.mu_O * p.r_O;
  position::PositionSolver<Friction> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  using VecQ = ModelTypes<Friction>::VecQ;
  for (int k = 0; k < 72; ++k) {
    const double q = 2 * M_PI * (k + 0.3) / 72;
    ASSERT_EQ(solver.MoveTo(VecQ::Constant(q), nullptr), position::Status::kConverged);
    // Hand closed forms (zero offset): s = a cos q + b cos beta, T0 = F ds/dq.
    const double beta = Beta(p.a, p.b, q);
    const double sq = p.a * std::sin(q), root = std::sqrt(p.b * p.b - sq * sq);
    const double T0 = p.F * (-sq - sq * p.a * std::cos(q) / root);
    const double P = p.F / std::cos(beta);
    EXPECT_NEAR(solver.state().phi(1), p.a * std::cos(q) + root, 1e-12);
    DriveAnalysis d;
    ASSERT_EQ(AnalyzeDriveAt<Friction>(Options(), p, solver.state(), 0, &d), Status::kConverged);
    const double sign = T0 < 0 ? -1 : 1;
    EXPECT_NEAR(d.drive, T0, 1e-9 * p.F) << q;
    EXPECT_NEAR(d.drive_forward, T0 + sign * mu_r * P, 1e-9 * p.F) << q;
    EXPECT_NEAR(d.drive_backward, T0 - sign * mu_r * P, 1e-9 * p.F) << q;
    EXPECT_NEAR(d.drive_plus, T0 + mu_r * P, 1e-9 * p.F) << q;
    EXPECT_NEAR(d.drive_minus, T0 - mu_r * P, 1e-9 * p.F) << q;
    if (std::abs(std::abs(Lever(p.a, p.b, q)) - mu_r) > 1e-9) {
      EXPECT_EQ(d.self_locking, std::abs(Lever(p.a, p.b, q)) <= mu_r) << q;
    }
  }
}

TEST(StaticsGenerated, SliderCrankDeadZonesMatchHandDerivedAngles) {
  const auto p = OnlyO();
  const double mu_r = p.mu_O * p.r_O;
  auto solve = [&](double lo, double hi) {
    const bool lo_positive = Lever(p.a, p.b, lo) > mu_r;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((Lever(p.a, p.b, mid) > mu_r) == lo_positive ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  const double q1 = solve(1e-9, M_PI / 2), q2 = solve(M_PI / 2, M_PI - 1e-9);
  position::PositionSolver<Friction> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<DeadZone> zones;
  ScanSummary summary;
  ASSERT_EQ(FindDeadZones(Options(), ScanOptions(), &solver, 0, 0.0, 2 * M_PI, &zones, &summary),
            Status::kConverged)
      << summary.reason;
  ASSERT_EQ(zones.size(), 3u);
  EXPECT_NEAR(zones[0].end, q1, 1e-9);
  EXPECT_NEAR(zones[1].begin, q2, 1e-9);
  EXPECT_NEAR(zones[1].end, 2 * M_PI - q2, 1e-9);
  EXPECT_NEAR(zones[2].begin, 2 * M_PI - q1, 1e-9);
  // q1 ~ 2.68 deg, q2 ~ 175.19 deg for a = 0.1, b = 0.35, mu_O r_O = 0.006.
  EXPECT_NEAR(q1 * 180 / M_PI, 2.68, 0.01);
  EXPECT_NEAR(q2 * 180 / M_PI, 175.19, 0.01);

  // All four friction joints widen the dead zones.
  const ModelTypes<Friction>::Params all;
  solver.set_params(all);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<DeadZone> wider;
  ASSERT_EQ(FindDeadZones(Options(), ScanOptions(), &solver, 0, 0.0, 2 * M_PI, &wider, nullptr),
            Status::kConverged);
  ASSERT_EQ(wider.size(), 3u);
  EXPECT_GT(wider[0].end, zones[0].end);
  EXPECT_LT(wider[1].begin, zones[1].begin);
  EXPECT_GT(wider[1].end, zones[1].end);
}

// The friction iteration with all four friction joints: the normal forces at B, C and the
// slide change with the friction loads, so the iteration runs more than once.
TEST(StaticsGenerated, AllFrictionJointsSelfConsistentByVirtualWork) {
  const ModelTypes<Friction>::Params p;
  position::PositionSolver<Friction> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  using VecQ = ModelTypes<Friction>::VecQ;
  int max_iterations = 0;
  for (int k = 0; k < 72; ++k) {
    const double q = 2 * M_PI * (k + 0.3) / 72;
    ASSERT_EQ(solver.MoveTo(VecQ::Constant(q), nullptr), position::Status::kConverged);
    Solution<Friction> s0;
    ASSERT_EQ(SolveAt<Friction>(Options(), p, solver.state(), VecQ::Zero(), &s0),
              Status::kConverged);
    for (double dir : {+1.0, -1.0}) {
      Solution<Friction> s;
      ASSERT_EQ(SolveAt<Friction>(Options(), p, solver.state(), VecQ::Constant(dir), &s),
                Status::kConverged)
          << FormatSummary(s.summary);
      max_iterations = std::max(max_iterations, s.summary.iterations);
      double work = 0;  // sum f_J K_rel_J: the virtual work of the friction loads per unit dq
      for (int J = 0; J < 4; ++J) {
        const double rel = s.statics.K_rel(J, 0) * dir;
        const double expected = rel == 0 ? 0 : -s.statics.gain(J) * s.statics.normal(J) *
                                                   (rel > 0 ? 1 : -1);
        EXPECT_NEAR(s.friction(J), expected, 1e-9 * p.F) << "joint " << J << " q " << q;
        EXPECT_LE(s.friction(J) * rel, 0.0);  // opposes the relative motion
        work += s.friction(J) * s.statics.K_rel(J, 0);
      }
      EXPECT_NEAR(s.statics.drive(0), s0.statics.drive(0) - work, 1e-9 * p.F);
      // Friction costs the actuator: it works against it in the direction of motion.
      EXPECT_GE(s.statics.drive(0) * dir, s0.statics.drive(0) * dir - 1e-9);
    }
    DriveAnalysis d;
    ASSERT_EQ(AnalyzeDriveAt<Friction>(Options(), p, solver.state(), 0, &d), Status::kConverged);
    EXPECT_GT(d.efficiency_forward, 0.0);
    EXPECT_LE(d.efficiency_forward, 1.0);
  }
  EXPECT_LE(max_iterations, 12);
  EXPECT_GT(max_iterations, 3);
}

// A friction force f on the slider along +u does the virtual work f ds: Q changes by
// f ds/dq = f K_rel (the generator of main 5007af7 left it out; fixed in 36e53a7).
TEST(StaticsGenerated, SlideFrictionEntersQ) {
  const ModelTypes<Friction>::Params p;
  position::PositionSolver<Friction> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  using VecQ = ModelTypes<Friction>::VecQ;
  for (double q : {0.5, 2.0, 4.0}) {
    ASSERT_EQ(solver.MoveTo(VecQ::Constant(q), nullptr), position::Status::kConverged);
    const auto& st = solver.state();
    ModelTypes<Friction>::Coefficients c;
    Friction::Coeffs<double>(p, st.q, st.phi, &c);
    Friction::StaticsT<double> s0, s1;
    Friction::Forces<double>(p, st.q, st.phi, c, &s0, nullptr);
    const Eigen::Matrix<double, 4, 1> f(0, 0, 0, 1.0);  // 1 N on the slider along +u
    Friction::Forces<double>(p, st.q, st.phi, c, &s1, &f);
    EXPECT_NEAR(s1.Q(0) - s0.Q(0), s1.K_rel(3, 0), 1e-12) << "q = " << q;
  }
}

TEST(StaticsGenerated, PressMechanicalAdvantageGrowsAtTheToggle) {
  ModelTypes<Press>::Params p;
  p.g = 0;  // the press load alone
  position::PositionSolver<Press> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  using VecQ = ModelTypes<Press>::VecQ;
  std::vector<StaticsRecord<Press>> records;
  ASSERT_EQ(StaticsSweep(Options(), &solver, VecQ::Constant(0.5), VecQ::Constant(0.002), 249,
                         &records),
            0);
  double previous = 0;
  for (const StaticsRecord<Press>& r : records) {
    const double s = r.kinematics.state.phi(1);
    const double load = p.P0 * p.h / (p.h + p.a + p.b - s);
    EXPECT_NEAR(std::abs(r.frictionless.statics.drive(0)) * r.mechanical_advantage, load,
                1e-9 * load);
    EXPECT_GT(r.mechanical_advantage, previous);  // grows as q -> 0
    previous = r.mechanical_advantage;
  }
  // MA ~ 1 / (a (1 + a / b) q) near q = 0 (ds/dq ~ -a (1 + a / b) q).
  const double q = records.back().kinematics.q(0);
  EXPECT_NEAR(records.back().mechanical_advantage * p.a * (1 + p.a / p.b) * q, 1.0, 1e-3);
  EXPECT_GT(records.back().mechanical_advantage, 1e3);
}

TEST(StaticsGenerated, LoadedFourBarEquilibria) {
  const ModelTypes<Loaded>::Params p;
  position::PositionSolver<Loaded> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  using VecQ = ModelTypes<Loaded>::VecQ;
  std::vector<Equilibrium<Loaded>> found;
  ScanSummary summary;
  ASSERT_EQ(FindEquilibria(Options(), ScanOptions(), &solver, VecQ::Constant(0.0),
                           VecQ::Constant(2 * M_PI), &found, &summary),
            Status::kConverged)
      << summary.reason;
  ASSERT_GE(found.size(), 2u);  // Q is 2 pi periodic: zeros come in pairs over a turn
  EXPECT_EQ(found.size() % 2, 0u);
  int stable = 0;
  for (const Equilibrium<Loaded>& e : found) {
    EXPECT_TRUE(e.located);
    const double h = 1e-5;
    double Q[2];
    for (int side = 0; side < 2; ++side) {
      ASSERT_EQ(solver.MoveTo(VecQ::Constant(e.q(0) + (side ? h : -h)), nullptr),
                position::Status::kConverged);
      Solution<Loaded> s;
      ASSERT_EQ(SolveAt<Loaded>(Options(), p, solver.state(), VecQ::Zero(), &s),
                Status::kConverged);
      Q[side] = s.statics.Q(0);
    }
    const double scale = std::abs(Q[0]) / h + 1;
    EXPECT_NEAR(std::abs(e.Q(0)), 0.0, 1e-9 * scale);
    EXPECT_NEAR(e.stiffness, -(Q[1] - Q[0]) / (2 * h), 1e-5 * std::max(1.0, std::abs(e.stiffness)));
    stable += e.stable;
  }
  EXPECT_EQ(2 * stable, static_cast<int>(found.size()));  // alternating along a turn
}

// slider_crank_friction has no potential, so no Statics::stiffness: FindEquilibria takes
// -dQ/dq by a central difference; against F s'' = -F a cos q (1 + a cos q / b) at the dead
// centres (V = F s: q = 0 a maximum, unstable; q = pi a minimum, stable).
TEST(StaticsGenerated, EquilibriaWithoutStiffnessByDifference) {
  static_assert(!StaticsFeatures<Friction>::kHasStiffness);
  const ModelTypes<Friction>::Params p;
  position::PositionSolver<Friction> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  using VecQ = ModelTypes<Friction>::VecQ;
  std::vector<Equilibrium<Friction>> found;
  ScanOptions scan;
  scan.samples = 100;
  ASSERT_EQ(FindEquilibria(Options(), scan, &solver, VecQ::Constant(-0.5), VecQ::Constant(5.5),
                           &found),
            Status::kConverged);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_NEAR(found[0].q(0), 0.0, 1e-10);
  EXPECT_NEAR(found[1].q(0), M_PI, 1e-10);
  for (const Equilibrium<Friction>& e : found) {
    const double c = std::cos(e.q(0));
    EXPECT_NEAR(e.stiffness, -p.F * p.a * c * (1 + p.a * c / p.b), 1e-5 * p.F * p.a);
  }
  EXPECT_FALSE(found[0].stable);
  EXPECT_TRUE(found[1].stable);
}

TEST(StaticsGenerated, DeadPointRowIsSingularAndEmpty) {
  ModelTypes<Friction>::Params p;
  p.a = p.b = 0.3;  // the rod stands vertical at q = 90 deg
  position::PositionSolver<Friction> solver(position::Options(), p);
  using VecQ = ModelTypes<Friction>::VecQ;
  const ModelTypes<Friction>::VecPhi guess(-1.0, 2 * p.a * std::cos(1.0));
  ASSERT_EQ(solver.Assemble(VecQ::Constant(1.0), guess, 0, nullptr),
            position::Status::kConverged);
  std::vector<StaticsRecord<Friction>> records;
  EXPECT_GT(StaticsSweep(Options(), &solver, VecQ::Constant(1.0), VecQ::Constant(1.8), 40,
                         &records),
            0);
  std::ostringstream csv;
  WriteStaticsCsv(records, csv);
  std::istringstream in(csv.str());
  std::string header, line;
  std::getline(in, header);
  int singular = 0;
  while (std::getline(in, line)) {
    if (line.find(",singular,") == std::string::npos) continue;
    ++singular;
    // q, then empty cells up to the status (phi of the last valid configuration aside).
    const std::string values = line.substr(0, line.find(",singular,"));
    size_t numbers = 0;
    std::stringstream cells(values);
    std::string cell;
    while (std::getline(cells, cell, ',')) numbers += !cell.empty();
    EXPECT_LE(numbers, 3u) << line;  // theta_crank, theta_rod, s_slide
  }
  EXPECT_EQ(singular, 1);
}

}  // namespace
}  // namespace mechgen::statics
