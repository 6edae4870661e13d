// The runtime reads what a model has from its `kHas*` flags (core/model_traits.h), not from
// its members and functions (issue 24: the SFINAE re-detection is gone).
//
// Each model below is a generated model whose type still declares every member and function
// of the output (inherited), with one flag set false. A member detector would still find the
// output; the runtime must treat the model as lacking it. Oracles:
//  - fourbar_massive without kHasRhs: the simulation takes the path through M::Coeffs and
//    M::Dynamics instead of the one-pass M::Rhs; a free swing agrees with the one through
//    M::Rhs (a second implementation of the same equations) to the integrator's accuracy;
//  - slider_crank_friction without kHasStaticsFriction: the statics is frictionless in every
//    direction of motion, bit for bit the model's own frictionless evaluation (direction 0),
//    while the model with the flag gives a different (friction) drive;
//  - fourbar_massive without kHasStatics: no statics type, no reactions;
//  - fourbar_massive without kHasSolveTrig: the simulation stages by Solve (angles) instead of
//    SolveTrig (direction cosines) and agrees with the model's own run;
//  - fourbar without kHasL (and kHasPointAccelerations): the position solver forms L itself
//    (from Phi in dual numbers) although Coefficients::L is there, and it agrees with the
//    generated L to rounding;
//  - slider_crank_friction without kHasDrawing: its reactions' joints are not named, so the
//    statics finds no ground bearings (with the flag it finds the crank's bearing O);
//  - fourbar without kHasTransmissionAngles, slider_crank_motor without kHasSwitchModes:
//    no transmission angles, no switching items.
// That a type without the flags stops the build with a message naming the flag is checked by
// tests/dynamics/missing_flag.cc (a compile test in CMakeLists.txt).
#include <cmath>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "fourbar.h"
#include "fourbar_massive.h"
#include "handwritten_fourbar_dynamics.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/io/svg.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"
#include "mechgen/statics/columns.h"
#include "slider_crank_friction.h"
#include "slider_crank_motor.h"

namespace {

namespace fm = mech::fourbar_massive;
namespace sf = mech::slider_crank_friction;
using mechgen::ModelTypes;
using mechgen::statics::StaticsFeatures;

// fourbar_massive, its flags saying it has no one-pass Rhs (M::Rhs, M::RhsT and M::Prepare are
// still declared: inherited).
struct MassiveWithoutRhs : fm::Model {
  static constexpr bool kHasRhs = false;
  static constexpr bool kHasRhsConstants = false;
};
// slider_crank_friction, its flags saying its statics have no friction (Statics::normal, gain,
// K_rel and the friction argument of M::Forces are still there).
struct FrictionWithoutFrictionFlag : sf::Model {
  static constexpr bool kHasStaticsFriction = false;
};
// fourbar_massive, its flags saying it has no statics (M::StaticsT, M::Forces still there).
struct MassiveWithoutStatics : fm::Model {
  static constexpr bool kHasStatics = false;
  static constexpr bool kHasStaticsQ = false;
  static constexpr bool kHasStaticsR = false;
};

// fourbar_massive, its flags saying it has no SolveTrig (M::SolveTrig still declared).
struct MassiveWithoutSolveTrig : fm::Model {
  static constexpr bool kHasSolveTrig = false;
};
// fourbar, its flags saying its coefficients have no L and L_P (both still there).
struct FourbarWithoutL : mech::fourbar::Model {
  static constexpr bool kHasL = false;
  static constexpr bool kHasPointAccelerations = false;
};
// fourbar, its flags saying it has no transmission angles (M::TransmissionAngles still there).
struct FourbarWithoutTransmission : mech::fourbar::Model {
  static constexpr bool kHasTransmissionAngles = false;
};
// slider_crank_friction, its flags saying it has no drawing (M::Drawing, kDrawJoint* still there).
struct FrictionWithoutDrawing : sf::Model {
  static constexpr bool kHasDrawing = false;
};
// slider_crank_motor, its flags saying its loads do not switch (M::SwitchModes still there).
struct MotorWithoutSwitches : mech::slider_crank_motor::Model {
  static constexpr bool kHasSwitchModes = false;
};

// The flags, read.
static_assert(mechgen::dynamics::MinimalDynamics<fm::Model>::kStagesByTrig);
static_assert(!mechgen::dynamics::MinimalDynamics<MassiveWithoutSolveTrig>::kStagesByTrig);
static_assert(!mechgen::dynamics::MinimalDynamics<MassiveWithoutSolveTrig>::kStagesByRhs);
static_assert(mechgen::ModelFeatures<mech::fourbar::Model>::kHasL &&
              mechgen::ModelFeatures<mech::fourbar::Model>::kHasPointAccelerations);
static_assert(!mechgen::ModelFeatures<FourbarWithoutL>::kHasL &&
              !mechgen::ModelFeatures<FourbarWithoutL>::kHasPointAccelerations &&
              mechgen::ModelFeatures<FourbarWithoutL>::kHasK);
static_assert(mechgen::ModelFeatures<mech::fourbar::Model>::kNumTransmissionAngles ==
              mech::fourbar::Model::kNumTransmissionAngles);
static_assert(mech::fourbar::Model::kNumTransmissionAngles > 0);
static_assert(mechgen::ModelFeatures<FourbarWithoutTransmission>::kNumTransmissionAngles == 0);
static_assert(mechgen::statics::internal::HasJointLinks<sf::Model>::value);
static_assert(!mechgen::statics::internal::HasJointLinks<FrictionWithoutDrawing>::value);
static_assert(mechgen::internal::HasDrawing<sf::Model>::value);
static_assert(!mechgen::internal::HasDrawing<FrictionWithoutDrawing>::value);
static_assert(!mechgen::internal::HasCamProfile<sf::Model>::value);
static_assert(mechgen::dynamics::internal::NumSwitches<mech::slider_crank_motor::Model>::value ==
              mech::slider_crank_motor::Model::kNumSwitches);
static_assert(mech::slider_crank_motor::Model::kNumSwitches > 0);
static_assert(mechgen::dynamics::internal::NumSwitches<MotorWithoutSwitches>::value == 0);
static_assert(mechgen::dynamics::MinimalDynamics<mech::slider_crank_motor::Model>::kHasSwitches);
static_assert(!mechgen::dynamics::MinimalDynamics<MotorWithoutSwitches>::kHasSwitches);
static_assert(mechgen::HasRhs<fm::Model>::value && mechgen::HasRhsConstants<fm::Model>::value);
static_assert(!mechgen::HasRhs<MassiveWithoutRhs>::value);
static_assert(std::is_same_v<mechgen::internal::RhsConstantsOf<MassiveWithoutRhs>::type,
                             mechgen::internal::NoRhsConstants>);
static_assert(mechgen::dynamics::MinimalDynamics<fm::Model>::kStagesByRhs);
static_assert(!mechgen::dynamics::MinimalDynamics<MassiveWithoutRhs>::kStagesByRhs);
static_assert(mechgen::dynamics::MinimalDynamics<MassiveWithoutRhs>::kStagesByTrig);

static_assert(StaticsFeatures<sf::Model>::kHasFriction && StaticsFeatures<sf::Model>::kNumFriction == 4);
static_assert(StaticsFeatures<FrictionWithoutFrictionFlag>::kHasStatics);
static_assert(!StaticsFeatures<FrictionWithoutFrictionFlag>::kHasFriction);
static_assert(StaticsFeatures<FrictionWithoutFrictionFlag>::kNumFriction == 0);
static_assert(StaticsFeatures<FrictionWithoutFrictionFlag>::kHasReactions);

static_assert(StaticsFeatures<fm::Model>::kHasStatics && StaticsFeatures<fm::Model>::kHasReactions);
static_assert(!mechgen::HasStatics<MassiveWithoutStatics>::value);
static_assert(!StaticsFeatures<MassiveWithoutStatics>::kHasStatics);
static_assert(std::is_void_v<StaticsFeatures<MassiveWithoutStatics>::Statics>);
static_assert(StaticsFeatures<MassiveWithoutStatics>::kNumReactions == 0);
static_assert(mechgen::HasDynamics<MassiveWithoutStatics>::value);  // the others untouched

// The hand-written models say what they have (their flags, read through the same traits).
static_assert(mechgen::HasDynamics<mech::handwritten_fourbar_dynamics::Model>::value);
static_assert(mechgen::HasExcess<mech::handwritten_fourbar_dynamics::Model>::value);
static_assert(!mechgen::HasRhs<mech::handwritten_fourbar_dynamics::Model>::value);
static_assert(!mechgen::HasShaking<mech::handwritten_fourbar_dynamics::Model>::value);
static_assert(StaticsFeatures<mech::handwritten_fourbar_dynamics::Model>::kHasPotential);
static_assert(!StaticsFeatures<mech::handwritten_fourbar_dynamics::Model>::kHasStiffness);

template <class M>
std::vector<mechgen::dynamics::Sample<M>> FreeSwing(mechgen::dynamics::MinimalSummary* summary) {
  using Sim = mechgen::dynamics::MinimalDynamics<M>;
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.05;
  Sim sim(typename Sim::Params(), o);
  typename Sim::VecQ q0, qd0;
  q0(0) = 1.2;
  qd0(0) = 0.0;
  std::vector<mechgen::dynamics::Sample<M>> samples;
  if (!sim.Initialize(q0)) return samples;
  sim.Simulate(0.0, q0, qd0, 2.0, [&](const auto& s) {
    samples.push_back(s);
    return true;
  }, summary);
  return samples;
}

TEST(RuntimeReadsFlags, WithoutTheRhsFlagTheSimulationTakesTheOtherPathAndAgrees) {
  mechgen::dynamics::MinimalSummary by_rhs, by_dynamics;
  const auto a = FreeSwing<fm::Model>(&by_rhs);
  const auto b = FreeSwing<MassiveWithoutRhs>(&by_dynamics);
  ASSERT_EQ(by_rhs.status, mechgen::dynamics::Status::kSuccess) << by_rhs.message;
  ASSERT_EQ(by_dynamics.status, mechgen::dynamics::Status::kSuccess) << by_dynamics.message;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 30u);
  double max_dq = 0;
  bool moved = false;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].t, b[i].t);
    max_dq = std::max(max_dq, std::abs(a[i].q(0) - b[i].q(0)));
    EXPECT_NEAR(a[i].q(0), b[i].q(0), 1e-8) << a[i].t;
    EXPECT_NEAR(a[i].qd(0), b[i].qd(0), 1e-7) << a[i].t;
    moved = moved || std::abs(a[i].q(0) - 1.2) > 0.5;
  }
  EXPECT_TRUE(moved);  // it swung: the comparison is not of two resting states
  // Two paths: the right-hand sides differ in rounding, so the trajectories are not the same
  // bits (the flag changed what ran).
  EXPECT_GT(max_dq, 0.0);
}

TEST(RuntimeReadsFlags, WithoutTheSolveTrigFlagTheSimulationStagesByAnglesAndAgrees) {
  mechgen::dynamics::MinimalSummary by_trig, by_angles;
  const auto a = FreeSwing<fm::Model>(&by_trig);
  const auto b = FreeSwing<MassiveWithoutSolveTrig>(&by_angles);
  ASSERT_EQ(by_trig.status, mechgen::dynamics::Status::kSuccess) << by_trig.message;
  ASSERT_EQ(by_angles.status, mechgen::dynamics::Status::kSuccess) << by_angles.message;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 30u);
  double max_dq = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].t, b[i].t);
    max_dq = std::max(max_dq, std::abs(a[i].q(0) - b[i].q(0)));
    EXPECT_NEAR(a[i].q(0), b[i].q(0), 1e-8) << a[i].t;
    EXPECT_NEAR(a[i].qd(0), b[i].qd(0), 1e-7) << a[i].t;
  }
  EXPECT_GT(max_dq, 0.0);  // two paths, not the same bits
}

TEST(RuntimeReadsFlags, WithoutTheLFlagThePositionSolverFormsL) {
  // Over a turn of the crank, the L the solver forms for the model whose flag says it has no
  // L agrees with the generated L (which it does not read) to rounding, and is its own
  // computation (not the same bits everywhere).
  using M = mech::fourbar::Model;
  const ModelTypes<M>::Params p;
  mechgen::position::PositionSolver<M> exact(mechgen::position::Options(), p);
  mechgen::position::PositionSolver<FourbarWithoutL> formed(mechgen::position::Options(), p);
  ASSERT_EQ(exact.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  ASSERT_EQ(formed.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  using VecQ = ModelTypes<M>::VecQ;
  double worst = 0;
  for (int k = 1; k <= 72; ++k) {
    const double q = M_PI / 2 + k * M_PI / 36;
    ASSERT_EQ(exact.MoveTo(VecQ::Constant(q), nullptr), mechgen::position::Status::kConverged) << q;
    ASSERT_EQ(formed.MoveTo(VecQ::Constant(q), nullptr), mechgen::position::Status::kConverged) << q;
    ASSERT_EQ(formed.state().phi, exact.state().phi) << q;
    const auto& L = exact.state().L;
    ASSERT_TRUE(L.allFinite() && formed.state().L.allFinite()) << q;
    const double error = (formed.state().L - L).cwiseAbs().maxCoeff() / (1 + L.cwiseAbs().maxCoeff());
    worst = std::max(worst, error);
    EXPECT_LE(error, 1e-12) << q;
  }
  EXPECT_GT(worst, 0.0);
}

TEST(RuntimeReadsFlags, WithoutTheDrawingFlagTheReactionsNameNoBearings) {
  const auto with = mechgen::statics::GroundBearings<sf::Model>();
  ASSERT_EQ(with.size(), 1u);  // O: the crank on the ground (the slide is prismatic)
  EXPECT_EQ(with[0].joint, "O");
  EXPECT_EQ(with[0].link, "crank");
  EXPECT_TRUE(mechgen::statics::GroundBearings<FrictionWithoutDrawing>().empty());
}

TEST(RuntimeReadsFlags, WithoutTheFrictionFlagTheStaticsIsFrictionless) {
  using W = FrictionWithoutFrictionFlag;
  const ModelTypes<sf::Model>::Params p;
  mechgen::position::PositionSolver<sf::Model> solver(mechgen::position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  using VecQ = ModelTypes<sf::Model>::VecQ;
  int friction_differs = 0;
  for (int k = 0; k < 24; ++k) {
    const double q = 2 * M_PI * (k + 0.3) / 24;
    ASSERT_EQ(solver.MoveTo(VecQ::Constant(q), nullptr), mechgen::position::Status::kConverged);
    const auto& st = solver.state();
    ModelTypes<sf::Model>::Coefficients c;
    sf::Model::Coeffs<double>(p, st.q, st.phi, &c);
    mechgen::statics::Solution<sf::Model> frictionless, with_friction;
    mechgen::statics::Solution<W> flagged;
    const mechgen::statics::Options o;
    ASSERT_EQ(mechgen::statics::Solve<sf::Model>(o, p, st.q, st.phi, c, VecQ::Zero(),
                                                 &frictionless),
              mechgen::statics::Status::kConverged);
    ASSERT_EQ(mechgen::statics::Solve<sf::Model>(o, p, st.q, st.phi, c,
                                                 VecQ::Constant(1.0), &with_friction),
              mechgen::statics::Status::kConverged);
    ASSERT_EQ(mechgen::statics::Solve<W>(o, p, st.q, st.phi, c, VecQ::Constant(1.0),
                                         &flagged),
              mechgen::statics::Status::kConverged);
    EXPECT_EQ(flagged.statics.drive(0), frictionless.statics.drive(0)) << q;
    for (int r = 0; r < sf::Model::kNumReactions; ++r)
      EXPECT_EQ(flagged.statics.R(r), frictionless.statics.R(r)) << q;
    if (std::abs(with_friction.statics.drive(0) - frictionless.statics.drive(0)) > 1e-9)
      ++friction_differs;
  }
  EXPECT_EQ(friction_differs, 24);  // with the flag, friction acts at every angle
}

}  // namespace
