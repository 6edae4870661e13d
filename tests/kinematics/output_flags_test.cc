// Every generated model carries a kHas* flag for every output and for every optional member
// of Coefficients and function of Model (codegen/output_spec.h: OutputSpec, ModelFlags): the
// flags must say exactly what the header holds. The oracle is the header itself, detected
// here member by member, alias by alias and function by function (the way the runtime
// detected them before the flags existed), for models with no outputs, positions only
// (fourbar_positions: no K, no L, no drawing), Newton blocks only (no SolveTrig), named
// assembly modes, cams, switching loads, statics only (with friction), and the dynamics,
// shaking and one-pass right-hand side; and for the hand-written models, whose flags are
// written by hand.
#include <gtest/gtest.h>

#include <array>
#include <type_traits>
#include <utility>

#include "cam_roller.h"
#include "contract_fourbar_monolithic.h"
#include "fivebar.h"
#include "fourbar.h"
#include "fourbar_balanced.h"
#include "fourbar_massive.h"
#include "fourbar_named_modes.h"
#include "fourbar_positions.h"
#include "handwritten_fourbar.h"
#include "handwritten_fourbar_dynamics.h"
#include "handwritten_rocker_driven.h"
#include "handwritten_statics_pendulum.h"
#include "handwritten_statics_slider_crank.h"
#include "slider_crank_friction.h"
#include "slider_crank_motor.h"

namespace {

template <class M, class = void>
struct HasStaticsT : std::false_type {};
template <class M>
struct HasStaticsT<M, std::void_t<typename M::template StaticsT<double>>> : std::true_type {};
template <class M, class = void>
struct HasDynamicsT : std::false_type {};
template <class M>
struct HasDynamicsT<M, std::void_t<typename M::template DynamicsT<double>>> : std::true_type {};
template <class M, class = void>
struct HasExcessT : std::false_type {};
template <class M>
struct HasExcessT<M, std::void_t<typename M::template ExcessT<double>>> : std::true_type {};
template <class M, class = void>
struct HasShakingT : std::false_type {};
template <class M>
struct HasShakingT<M, std::void_t<typename M::template ShakingT<double>>> : std::true_type {};
template <class M, class = void>
struct HasKinematicsT : std::false_type {};
template <class M>
struct HasKinematicsT<M, std::void_t<typename M::template KinematicsT<double>,
                                     decltype(&M::template Kinematics<double>)>> : std::true_type {};
template <class M, class = void>
struct HasRhsT : std::false_type {};
template <class M>
struct HasRhsT<M, std::void_t<typename M::template RhsT<double>>> : std::true_type {};
template <class M, class = void>
struct HasRhsConstantsT : std::false_type {};
template <class M>
struct HasRhsConstantsT<M, std::void_t<typename M::template RhsConstantsT<double>>> : std::true_type {};

// Members of Statics (void for a model without it: no member).
template <class M, class = void>
struct StaticsOf {
  using type = void;
};
template <class M>
struct StaticsOf<M, std::void_t<typename M::template StaticsT<double>>> {
  using type = typename M::template StaticsT<double>;
};
#define MEMBER_DETECTOR(Name, member)                                                          \
  template <class S, class = void>                                                             \
  struct Name : std::false_type {};                                                            \
  template <class S>                                                                           \
  struct Name<S, std::void_t<decltype(std::declval<S&>().member)>> : std::true_type {};
MEMBER_DETECTOR(HasQ, Q)
MEMBER_DETECTOR(HasDrive, drive)
MEMBER_DETECTOR(HasV, V)
MEMBER_DETECTOR(HasDV, dV_dq)
MEMBER_DETECTOR(HasD2V, d2V_dq2)
MEMBER_DETECTOR(HasStiffness, stiffness)
MEMBER_DETECTOR(HasR, R)
MEMBER_DETECTOR(HasNormal, normal)
MEMBER_DETECTOR(HasKRel, K_rel)
#undef MEMBER_DETECTOR

// Members of Coefficients.
#define MEMBER_DETECTOR(Name, member)                                                          \
  template <class S, class = void>                                                             \
  struct Name : std::false_type {};                                                            \
  template <class S>                                                                           \
  struct Name<S, std::void_t<decltype(std::declval<S&>().member)>> : std::true_type {};
MEMBER_DETECTOR(HasPhiMember, Phi)
MEMBER_DETECTOR(HasPhiPhiMember, Phi_phi)
MEMBER_DETECTOR(HasKMember, K)
MEMBER_DETECTOR(HasLMember, L)
MEMBER_DETECTOR(HasRPMember, r_P)
MEMBER_DETECTOR(HasKPMember, K_P)
MEMBER_DETECTOR(HasLPMember, L_P)
#undef MEMBER_DETECTOR

// Functions and constants of Model.
template <class M>
using ParamsOf = typename M::template ParamsT<double>;
template <class M>
using VecQOf = Eigen::Matrix<double, M::kNq, 1>;
template <class M>
using VecPhiOf = Eigen::Matrix<double, M::kNphi, 1>;
template <class M>
using ModesOf = std::array<int, M::kNumBlocks>;
template <class M, class = void>
struct DetectSolve : std::false_type {};
template <class M>
struct DetectSolve<M, std::void_t<decltype(M::template Solve<double>(
                                      std::declval<const ParamsOf<M>&>(), std::declval<const VecQOf<M>&>(),
                                      std::declval<VecPhiOf<M>*>(), std::declval<const ModesOf<M>&>(), 0, 0.0)),
                                  decltype(M::kDefaultModes), decltype(M::kBlockClosedForm)>> : std::true_type {};
template <class M, class = void>
struct DetectNamedModes : std::false_type {};
template <class M>
struct DetectNamedModes<M, std::void_t<decltype(M::kNamedModes), decltype(M::kModeNames), decltype(&M::ModesByName)>>
    : std::true_type {};
template <class M, class = void>
struct DetectTrig : std::false_type {};
template <class M>
struct DetectTrig<
    M, std::void_t<typename M::template TrigT<double>,
                   decltype(M::template Solve<double>(std::declval<const ParamsOf<M>&>(),
                                                      std::declval<const VecQOf<M>&>(), std::declval<VecPhiOf<M>*>(),
                                                      std::declval<const ModesOf<M>&>(), 0, 0.0,
                                                      std::declval<typename M::template TrigT<double>*>())),
                   decltype(M::template Coeffs<double>(
                       std::declval<const ParamsOf<M>&>(), std::declval<const VecQOf<M>&>(),
                       std::declval<const VecPhiOf<M>&>(), std::declval<typename M::template CoefficientsT<double>*>(),
                       std::declval<const typename M::template TrigT<double>*>()))>> : std::true_type {};
template <class M, class = void>
struct DetectSolveTrig : std::false_type {};
template <class M>
struct DetectSolveTrig<M, std::void_t<decltype(M::template SolveTrig<double>(
                              std::declval<const ParamsOf<M>&>(), std::declval<const VecQOf<M>&>(),
                              std::declval<const ModesOf<M>&>(), std::declval<typename M::template TrigT<double>*>()))>>
    : std::true_type {};
template <class M, class = void>
struct DetectTransmissionAngles : std::false_type {};
template <class M>
struct DetectTransmissionAngles<M, std::void_t<decltype(&M::template TransmissionAngles<double>)>>
    : std::bool_constant<(M::kNumTransmissionAngles > 0)> {};
template <class M, class = void>
struct DetectSwitchModes : std::false_type {};
template <class M>
struct DetectSwitchModes<M, std::void_t<decltype(&M::template SwitchModes<double>), decltype(M::kNumSwitches)>>
    : std::true_type {};
template <class M, class = void>
struct DetectDrawing : std::false_type {};
template <class M>
struct DetectDrawing<M, std::void_t<decltype(&M::template Drawing<double>), decltype(M::kNumDrawJoints),
                                    decltype(M::kDrawJointLinkA), decltype(M::kDrawJointLinkB)>>
    : std::true_type {};
template <class M, class = void>
struct DetectCamProfile : std::false_type {};
template <class M>
struct DetectCamProfile<M, std::void_t<decltype(&M::template CamProfile<double>)>> : std::true_type {};
template <class M, class = void>
struct DetectAppliedLoads : std::false_type {};
template <class M>
struct DetectAppliedLoads<M, std::void_t<decltype(&M::template AppliedLoads<double>), decltype(M::kNumAppliedLoads),
                                         decltype(M::kAppliedLoadNames)>> : std::true_type {};
template <class M, class = void>
struct DetectDesign : std::false_type {};
template <class M>
struct DetectDesign<M, std::void_t<decltype(&M::template Design<double>), decltype(M::kNumDesign),
                                   typename M::template DesignDerivativesT<double>>> : std::true_type {};
template <class M, class = void>
struct DetectReactionJoint : std::false_type {};
template <class M>
struct DetectReactionJoint<M, std::void_t<decltype(M::kReactionJoint)>> : std::true_type {};

// The flags of M about its Coefficients and functions (ModelFlags) against what its header
// holds; returns true so that it can sit in a test.
template <class M>
constexpr bool ModelFlagsMatchHeader() {
  using C = typename M::template CoefficientsT<double>;
  static_assert(M::kHasCoeffsPhi == (HasPhiMember<C>::value && HasPhiPhiMember<C>::value), "kHasCoeffsPhi");
  static_assert(M::kHasK == HasKMember<C>::value, "kHasK");
  static_assert(M::kHasL == HasLMember<C>::value, "kHasL");
  static_assert(M::kHasPoints == HasRPMember<C>::value, "kHasPoints");
  static_assert(M::kHasPointVelocities == HasKPMember<C>::value, "kHasPointVelocities");
  static_assert(M::kHasPointAccelerations == HasLPMember<C>::value, "kHasPointAccelerations");
  static_assert(M::kHasSolve == DetectSolve<M>::value, "kHasSolve");
  static_assert(M::kHasNamedModes == DetectNamedModes<M>::value, "kHasNamedModes");
  static_assert(M::kHasTrig == DetectTrig<M>::value, "kHasTrig");
  static_assert(M::kHasSolveTrig == DetectSolveTrig<M>::value, "kHasSolveTrig");
  static_assert(M::kHasTransmissionAngles == DetectTransmissionAngles<M>::value, "kHasTransmissionAngles");
  static_assert(M::kHasSwitchModes == DetectSwitchModes<M>::value, "kHasSwitchModes");
  static_assert(M::kHasDrawing == DetectDrawing<M>::value, "kHasDrawing");
  static_assert(M::kHasCamProfile == DetectCamProfile<M>::value, "kHasCamProfile");
  static_assert(M::kHasAppliedLoads == DetectAppliedLoads<M>::value, "kHasAppliedLoads");
  static_assert(M::kHasDesignDerivatives == DetectDesign<M>::value, "kHasDesignDerivatives");
  // Reactions with a drawing name their joints (what statics/columns.h reads then).
  static_assert(!(M::kHasStaticsR && M::kHasDrawing) || DetectReactionJoint<M>::value, "kReactionJoint");
  return true;
}

// The flags of M against what its header holds; returns true so that it can sit in a test.
template <class M>
constexpr bool FlagsMatchHeader() {
  using S = typename StaticsOf<M>::type;
  static_assert(M::kHasStatics == HasStaticsT<M>::value, "kHasStatics");
  static_assert(M::kHasStaticsQ == (HasQ<S>::value && HasDrive<S>::value), "kHasStaticsQ");
  static_assert(M::kHasStaticsV == (HasV<S>::value && HasDV<S>::value), "kHasStaticsV");
  static_assert(M::kHasStaticsD2V == HasD2V<S>::value, "kHasStaticsD2V");
  static_assert(M::kHasStaticsStiffness == HasStiffness<S>::value, "kHasStaticsStiffness");
  static_assert(M::kHasStaticsR == HasR<S>::value, "kHasStaticsR");
  static_assert(M::kHasStaticsFriction == (HasNormal<S>::value && HasKRel<S>::value), "kHasStaticsFriction");
  static_assert(M::kHasDynamics == HasDynamicsT<M>::value, "kHasDynamics");
  static_assert(M::kHasExcess == HasExcessT<M>::value, "kHasExcess");
  static_assert(M::kHasShaking == HasShakingT<M>::value, "kHasShaking");
  static_assert(M::kHasKinematics == HasKinematicsT<M>::value, "kHasKinematics");
  static_assert(!M::kHasKinematics || (M::kHasSolveTrig && M::kHasK), "kHasKinematics: SolveTrig and K");
  static_assert(M::kHasRhs == HasRhsT<M>::value, "kHasRhs");
  static_assert(M::kHasRhsConstants == HasRhsConstantsT<M>::value, "kHasRhsConstants");
  return true;
}

TEST(OutputFlags, AgreeWithTheHeaderInEveryKindOfModel) {
  EXPECT_TRUE(FlagsMatchHeader<mech::fourbar::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::slider_crank_friction::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::slider_crank_motor::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::fourbar_massive::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::fourbar_balanced::Model>());
}

TEST(ModelFlags, AgreeWithTheHeaderInEveryKindOfModel) {
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::fourbar::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::fourbar_positions::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::contract_fourbar_monolithic::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::fivebar::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::cam_roller::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::slider_crank_friction::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::slider_crank_motor::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::fourbar_massive::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::fourbar_balanced::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::fourbar_named_modes::Model>());
}

TEST(ModelFlags, HandWrittenModelsDeclareWhatTheyHave) {
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::handwritten_fourbar::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::handwritten_rocker_driven::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::handwritten_statics_pendulum::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::handwritten_statics_slider_crank::Model>());
  EXPECT_TRUE(ModelFlagsMatchHeader<mech::handwritten_fourbar_dynamics::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::handwritten_fourbar::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::handwritten_statics_slider_crank::Model>());
  EXPECT_TRUE(FlagsMatchHeader<mech::handwritten_fourbar_dynamics::Model>());
}

// Each flag true in one model and false in another (a flag rendered constant would be caught):
// the values the models' YAML and structure imply.
TEST(ModelFlags, SayWhatEachModelHas) {
  using F = mech::fourbar::Model;  // order 2, a coupler point, a scene, closed-form dyad
  EXPECT_TRUE(F::kHasK && F::kHasL && F::kHasPoints && F::kHasPointVelocities && F::kHasPointAccelerations);
  EXPECT_TRUE(F::kHasSolve && F::kHasTrig && F::kHasSolveTrig && F::kHasTransmissionAngles && F::kHasDrawing);
  EXPECT_FALSE(F::kHasSwitchModes || F::kHasCamProfile || F::kHasNamedModes);
  EXPECT_TRUE(mech::fourbar_named_modes::Model::kHasNamedModes);
  using P = mech::fourbar_positions::Model;  // order 0, no scene: positions and r_P only
  EXPECT_FALSE(P::kHasK || P::kHasL || P::kHasPointVelocities || P::kHasPointAccelerations || P::kHasDrawing);
  EXPECT_TRUE(P::kHasPoints && P::kHasCoeffsPhi);
  using N = mech::contract_fourbar_monolithic::Model;  // Newton over everything: no SolveTrig
  EXPECT_TRUE(N::kHasSolve);
  EXPECT_FALSE(N::kHasSolveTrig);
  using V = mech::fivebar::Model;  // two inputs, no four-bar loop on the ground
  EXPECT_FALSE(V::kHasTransmissionAngles);
  EXPECT_TRUE(mech::cam_roller::Model::kHasCamProfile);
  EXPECT_TRUE(mech::slider_crank_motor::Model::kHasSwitchModes);
  EXPECT_GT(mech::slider_crank_motor::Model::kNumSwitches, 0);
  using H = mech::handwritten_fourbar::Model;  // no Solve, no Phi in its Coefficients
  EXPECT_FALSE(H::kHasSolve || H::kHasTrig || H::kHasCoeffsPhi);
}

// The same flags as the models ask for them (their YAML's quantities), so that a flag that is
// false everywhere (or true everywhere) would be caught too.
TEST(OutputFlags, SayWhatEachModelAskedFor) {
  using F = mech::fourbar::Model;  // kinematics only
  EXPECT_FALSE(F::kHasStatics || F::kHasDynamics || F::kHasExcess || F::kHasShaking || F::kHasRhs);
  using SF = mech::slider_crank_friction::Model;  // statics with Coulomb friction, no dynamics
  EXPECT_TRUE(SF::kHasStatics && SF::kHasStaticsQ && SF::kHasStaticsFriction);
  EXPECT_FALSE(SF::kHasDynamics || SF::kHasShaking || SF::kHasRhs);
  using SM = mech::slider_crank_motor::Model;  // statics, dynamics and shaking
  EXPECT_TRUE(SM::kHasStatics && SM::kHasDynamics && SM::kHasExcess && SM::kHasShaking);
  using FM = mech::fourbar_massive::Model;  // dynamics with the one-pass right-hand side
  EXPECT_TRUE(FM::kHasDynamics && FM::kHasRhs && FM::kHasRhsConstants);
}

}  // namespace
