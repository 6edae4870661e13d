// Every generated model carries a kHas* flag for every output (codegen/output_spec.h): the
// flags must say exactly what the header holds. The oracle is the header itself, detected
// here member by member and alias by alias (the way the runtime detected them before the
// flags existed), for models with no outputs, statics only (with friction), and the
// dynamics, shaking and one-pass right-hand side.
#include <gtest/gtest.h>

#include <type_traits>
#include <utility>

#include "fourbar.h"
#include "fourbar_balanced.h"
#include "fourbar_massive.h"
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
