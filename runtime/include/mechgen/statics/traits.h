/**
 * \file statics/traits.h
 * What the statics of a generated model provide, decided at compile time.
 *
 * A header generated with `outputs: quantities: [..., forces]` has (issue 14, the contract
 * in models/README.md) Sizes::kNumReactions, Sizes::kNumFriction, Model::kReactionNames,
 * Model::kFrictionJoints, Model::kFrictionPrismatic, the struct template Model::StaticsT<S>
 * (Q, drive, and, when asked for, V, dV_dq, d2V_dq2, stiffness, R, normal, gain, K_rel), the
 * static functions Model::Forces(p, q, phi, c, out, friction, trig) (EvalStatics) and
 * Model::Stiffness(p, q, phi, c, out) (EvalStiffness: d2V_dq2 and stiffness, apart because
 * they are long). Every member is
 * detected here, like the Coefficients members in core/model_traits.h, so that models
 * without statics (or without reactions, potential or friction) still compile against the
 * runtime: StaticsFeatures<M>::kHasStatics is false for them and the statics functions are
 * not instantiated. Needs Eigen only; nothing allocates.
 */
#pragma once

#include <array>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "mechgen/core/model_traits.h"

namespace mechgen::statics {

namespace internal {

// Members of Model::StaticsT<double>.
template <class S, class = void>
struct HasQ : std::false_type {};
template <class S>
struct HasQ<S, std::void_t<decltype(std::declval<S&>().Q), decltype(std::declval<S&>().drive)>>
    : std::true_type {};
template <class S, class = void>
struct HasV : std::false_type {};
template <class S>
struct HasV<S, std::void_t<decltype(std::declval<S&>().V)>> : std::true_type {};
template <class S, class = void>
struct HasDV : std::false_type {};
template <class S>
struct HasDV<S, std::void_t<decltype(std::declval<S&>().dV_dq)>> : std::true_type {};
template <class S, class = void>
struct HasD2V : std::false_type {};
template <class S>
struct HasD2V<S, std::void_t<decltype(std::declval<S&>().d2V_dq2)>> : std::true_type {};
template <class S, class = void>
struct HasStiffness : std::false_type {};
template <class S>
struct HasStiffness<S, std::void_t<decltype(std::declval<S&>().stiffness)>> : std::true_type {};
template <class S, class = void>
struct HasR : std::false_type {};
template <class S>
struct HasR<S, std::void_t<decltype(std::declval<S&>().R)>> : std::true_type {};
template <class S, class = void>
struct HasFrictionMembers : std::false_type {};
template <class S>
struct HasFrictionMembers<
    S, std::void_t<decltype(std::declval<S&>().normal), decltype(std::declval<S&>().gain),
                   decltype(std::declval<S&>().K_rel)>> : std::true_type {};

// Sizes::kNumReactions / kNumFriction, 0 when absent.
template <class M, class = void>
struct NumReactions : std::integral_constant<int, 0> {};
template <class M>
struct NumReactions<M, std::void_t<decltype(M::kNumReactions), decltype(M::kReactionNames)>>
    : std::integral_constant<int, M::kNumReactions> {};
template <class M, class = void>
struct NumFriction : std::integral_constant<int, 0> {};
template <class M>
struct NumFriction<M, std::void_t<decltype(M::kNumFriction), decltype(M::kFrictionJoints)>>
    : std::integral_constant<int, M::kNumFriction> {};

/// Model::StaticsT<double> and Model::Forces(p, q, phi, c, out): the statics of a model.
template <class M, class = void>
struct StaticsOf {
  using type = void;
  static constexpr bool value = false;
};
template <class M>
struct StaticsOf<
    M, std::void_t<typename M::template StaticsT<double>,
                   decltype(M::template Forces<double>(
                       std::declval<const typename M::template ParamsT<double>&>(),
                       std::declval<const Eigen::Matrix<double, M::kNq, 1>&>(),
                       std::declval<const Eigen::Matrix<double, M::kNphi, 1>&>(),
                       std::declval<const typename M::template CoefficientsT<double>&>(),
                       std::declval<typename M::template StaticsT<double>*>()))>> {
  using type = typename M::template StaticsT<double>;
  static constexpr bool value = HasQ<type>::value;
};

/// Model::Forces takes the friction loads as its 6th argument (a pointer to kNumFriction
/// values); false for a model whose Statics has no such argument.
template <class M, class = void>
struct StaticsTakesFriction : std::false_type {};
template <class M>
struct StaticsTakesFriction<
    M, std::void_t<decltype(M::template Forces<double>(
           std::declval<const typename M::template ParamsT<double>&>(),
           std::declval<const Eigen::Matrix<double, M::kNq, 1>&>(),
           std::declval<const Eigen::Matrix<double, M::kNphi, 1>&>(),
           std::declval<const typename M::template CoefficientsT<double>&>(),
           std::declval<typename M::template StaticsT<double>*>(),
           std::declval<const Eigen::Matrix<double, NumFriction<M>::value, 1>*>()))>>
    : std::true_type {};

/// Model::Stiffness(p, q, phi, c, out): d2V/dq2 and the stiffness -dQ/dq apart from Forces
/// (generated EvalStiffness: long expressions, only the equilibria need them).
template <class M, class = void>
struct HasStiffnessFunction : std::false_type {};
template <class M>
struct HasStiffnessFunction<
    M, std::void_t<decltype(M::template Stiffness<double>(
           std::declval<const typename M::template ParamsT<double>&>(),
           std::declval<const Eigen::Matrix<double, M::kNq, 1>&>(),
           std::declval<const Eigen::Matrix<double, M::kNphi, 1>&>(),
           std::declval<const typename M::template CoefficientsT<double>&>(),
           std::declval<typename M::template StaticsT<double>*>()))>> : std::true_type {};

}  // namespace internal

/// What the statics of model M provide.
template <class M>
struct StaticsFeatures {
  /// Model::StaticsT and Model::Forces exist (the model asked for `forces`).
  static constexpr bool kHasStatics = internal::StaticsOf<M>::value;
  using Statics = typename internal::StaticsOf<M>::type;  ///< void without statics
  /// Reaction components (kReactionNames) and friction joints (kFrictionJoints); 0 if none.
  static constexpr int kNumReactions = internal::NumReactions<M>::value;
  static constexpr int kNumFriction = internal::NumFriction<M>::value;
  static constexpr bool kHasReactions =
      kHasStatics && kNumReactions > 0 && internal::HasR<Statics>::value;
  static constexpr bool kHasFriction = kHasStatics && kNumFriction > 0 &&
                                       internal::HasFrictionMembers<Statics>::value &&
                                       internal::StaticsTakesFriction<M>::value;
  /// V (the potential energy of springs and gravity) and dV/dq.
  static constexpr bool kHasPotential = kHasStatics && internal::HasV<Statics>::value;
  /// Statics::stiffness = -dQ/dq along the motion (friction excluded): d2V/dq2 for a
  /// conservative model. Filled by Model::Stiffness (EvalStiffness) when the model has it
  /// (kStiffnessApart; generated headers), else by Model::Forces itself.
  static constexpr bool kHasStiffness = kHasStatics && internal::HasStiffness<Statics>::value;
  static constexpr bool kStiffnessApart = kHasStiffness && internal::HasStiffnessFunction<M>::value;
};

/// Fixed-size types of the statics of model M (double).
template <class M>
struct StaticsTypes {
  static constexpr int kNq = M::kNq;
  static constexpr int kNumReactions = StaticsFeatures<M>::kNumReactions;
  static constexpr int kNumFriction = StaticsFeatures<M>::kNumFriction;
  using Statics = typename StaticsFeatures<M>::Statics;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecR = Eigen::Matrix<double, kNumReactions, 1>;  ///< reactions (kReactionNames order)
  using VecF = Eigen::Matrix<double, kNumFriction, 1>;   ///< one value per friction joint
};

}  // namespace mechgen::statics
