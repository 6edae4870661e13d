/**
 * \file statics/traits.h
 * What the statics of a generated model provide, decided at compile time from the model's
 * flags.
 *
 * A header generated with `outputs: quantities: [..., forces]` has (issue 14, the contract
 * in models/README.md) Sizes::kNumReactions, Sizes::kNumFriction, Model::kReactionNames,
 * Model::kFrictionJoints, Model::kFrictionPrismatic, the struct template Model::StaticsT<S>
 * (Q, drive, and, when asked for, V, dV_dq, d2V_dq2, stiffness, R, normal, gain, K_rel), the
 * static functions Model::Forces(p, q, phi, c, out, friction, trig) (EvalStatics) and
 * Model::Stiffness(p, q, phi, c, out) (EvalStiffness: d2V_dq2 and stiffness, apart because
 * they are long). Which of them a model has, its flags say (M::kHasStatics, kHasStaticsQ,
 * kHasStaticsV, kHasStaticsD2V, kHasStaticsStiffness, kHasStaticsR, kHasStaticsFriction;
 * read through core/model_traits.h): models without statics (or without reactions,
 * potential or friction) still compile against the runtime, StaticsFeatures<M>::kHasStatics
 * is false for them and the statics functions are not instantiated. Needs Eigen only;
 * nothing allocates.
 *
 * A model whose loads read a velocity (a load of <coordinate>_dot, a damper, viscous joint
 * friction: `dynamics` models) has Model::Forces(p, q, phi, c, out, friction, trig,
 * velocities) and the list Model::kStaticsAtSpeed of what reads them (the generator emits
 * both together, and only then): without velocities (nullptr) its statics hold the machine
 * at rest, with them they are the statics along a motion at those input velocities (the
 * kinetostatics without the inertia forces). StaticsFeatures<M>::kReadsSpeed says which.
 */
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"

namespace mechgen::statics {

namespace internal {

/// Model::StaticsT<double> (the view's: ModelTypes<ViewModel>::Statics), or void for a model
/// without statics.
template <class M, bool kHas, bool kView = ModelCalls<M>::kView>
struct StaticsOf {
  using type = void;
};
template <class M>
struct StaticsOf<M, true, false> {
  using type = typename M::template StaticsT<double>;
};
template <class M>
struct StaticsOf<M, true, true> {
  using type = typename ModelTypes<M>::Statics;
};

/// M::kNumReactions when the statics have reactions (kHasStaticsR), else 0 (Eigen::Dynamic
/// for the view: its count at run time).
template <class M, bool kHas>
struct NumReactionsOf : std::integral_constant<int, 0> {};
template <class M>
struct NumReactionsOf<M, true> : std::integral_constant<int, M::kNumReactions> {};
/// M::kNumFriction when the statics have friction (kHasStaticsFriction), else 0.
template <class M, bool kHas>
struct NumFrictionOf : std::integral_constant<int, 0> {};
template <class M>
struct NumFrictionOf<M, true> : std::integral_constant<int, M::kNumFriction> {};

}  // namespace internal

/// What the statics of model M may provide: its flags, combined (for the view: everything a
/// view may have, counts Eigen::Dynamic; ModelCalls<ViewModel> says at run time what it has).
template <class M>
struct StaticsFeatures {
  /// Model::StaticsT and Model::Forces with Q and drive (M::kHasStatics and kHasStaticsQ: the
  /// model asked for `forces`).
  static constexpr bool kHasStatics = HasStatics<M>::value && HasStaticsQ<M>::value;
  using Statics = typename internal::StaticsOf<M, kHasStatics>::type;  ///< void without statics
  /// Reaction components (kReactionNames) and friction joints (kFrictionJoints); 0 if none.
  static constexpr int kNumReactions =
      internal::NumReactionsOf<M, kHasStatics && HasStaticsR<M>::value>::value;
  static constexpr int kNumFriction =
      internal::NumFrictionOf<M, kHasStatics && HasStaticsFriction<M>::value>::value;
  static constexpr bool kHasReactions = kNumReactions != 0;
  /// Statics::normal, gain, K_rel, and Model::Forces takes the friction loads.
  static constexpr bool kHasFriction = kNumFriction != 0;
  /// V (the potential energy of springs and gravity) and dV/dq.
  static constexpr bool kHasPotential = kHasStatics && HasStaticsV<M>::value;
  /// d2V/dq2, set by Model::Stiffness.
  static constexpr bool kHasD2V = kHasStatics && HasStaticsD2V<M>::value;
  /// Statics::stiffness = -dQ/dq along the motion (friction excluded): d2V/dq2 for a
  /// conservative model. Filled by Model::Stiffness (EvalStiffness), apart from Model::Forces
  /// (kStiffnessApart, always so by the flag's definition).
  static constexpr bool kHasStiffness = kHasStatics && HasStaticsStiffness<M>::value;
  static constexpr bool kStiffnessApart = kHasStiffness;
  /// Model::Forces takes the input velocities: something in the statics reads a velocity
  /// (Model::kStaticsAtSpeed, SpeedItems()); without them it is taken at rest. (The view's
  /// Forces always takes them.)
  static constexpr bool kReadsSpeed = kHasStatics && (ModelCalls<M>::kDeclaresAtSpeed || ModelCalls<M>::kView);
  /// The design derivatives of the statics (EvalStaticsDesign): a generated model with them,
  /// or the view (whether it has them: ModelCalls<M>::HasStaticsDesign).
  static constexpr bool kHasDesign = HasStaticsDesign<M>::value;
};

/// What model M's statics take at the input velocities and at rest without them: "torque of
/// load 'motor' (theta_crank_dot)", "damper 'pump'", "viscous friction at joint O"; empty
/// when nothing reads a velocity (the statics are the same at any speed).
template <class M>
std::vector<std::string> SpeedItems(const M& model) {
  using C = ModelCalls<M>;
  std::vector<std::string> items;
  if constexpr (StaticsFeatures<M>::kReadsSpeed)
    for (int i = 0; i < C::NumStaticsAtSpeed(model); ++i) items.push_back(C::StaticsAtSpeed(model, i));
  return items;
}
template <class M>
std::vector<std::string> SpeedItems() {
  return SpeedItems<M>(M());
}

namespace internal {
/// The reactions' and the friction joints' vectors: fixed-size, or the view's bounded ones.
template <class M, bool kView = ModelCalls<M>::kView>
struct StaticsVectors {
  using VecR = Eigen::Matrix<double, StaticsFeatures<M>::kNumReactions, 1>;
  using VecF = Eigen::Matrix<double, StaticsFeatures<M>::kNumFriction, 1>;
};
template <class M>
struct StaticsVectors<M, true> {
  using VecR = typename ModelTypes<M>::VecR;
  using VecF = typename ModelTypes<M>::VecF;
};
}  // namespace internal

/// Types of the statics of model M (double): fixed-size for a generated M, bounded dynamic
/// for the view.
template <class M>
struct StaticsTypes {
  static constexpr int kNq = M::kNq;
  static constexpr int kNumReactions = StaticsFeatures<M>::kNumReactions;
  static constexpr int kNumFriction = StaticsFeatures<M>::kNumFriction;
  /// kNq, or the view's maximum (a bound on the arrays per input).
  static constexpr int kMaxQ = ModelTypes<M>::kMaxQ;
  using Statics = typename StaticsFeatures<M>::Statics;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecR = typename internal::StaticsVectors<M>::VecR;  ///< reactions (kReactionNames order)
  using VecF = typename internal::StaticsVectors<M>::VecF;  ///< one value per friction joint
};

}  // namespace mechgen::statics
