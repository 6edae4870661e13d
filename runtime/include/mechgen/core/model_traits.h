/**
 * \file core/model_traits.h
 * The fixed-size Eigen types of a generated model and compile-time questions about it.
 *
 * A generated header (templates/mechanism.h.mustache) defines `struct Model : Sizes` with
 * sizes kNq, kNphi, kNc, kNumPoints, kNumScenePoints, the templates ParamsT<S> and
 * CoefficientsT<S>, and static functions Phi(), Coeffs() and, when it has a scene, Scene().
 * Coefficients only has the members the model asked for (K, L, r_P, K_P, L_P); the model's
 * flags (kHasK, ..., listed below) say which, and the traits below read them.
 * Everything is fixed-size: nothing here allocates. Needs Eigen only.
 */
#pragma once

#include <array>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

namespace mechgen {

/// Fixed-size types of model M in the scalar type Scalar (double by default; the generated
/// functions are templates on their scalar too, e.g. float, or ceres::Jet for derivatives).
/// Sizes in the names: Q = kNq, Phi = kNphi, C = kNc (rows of Phi), P = kNumPoints,
/// S = kNumScenePoints.
template <class M, class Scalar = double>
struct ModelTypes {
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kNc = M::kNc;
  static constexpr int kNumPoints = M::kNumPoints;
  static constexpr int kNumScenePoints = M::kNumScenePoints;
  static_assert(kNc == kNphi, "Phi_phi must be square: kNc == kNphi");
  /// The bounds of the sizes (ModelTypes<ViewModel>: the view's maxima; here the sizes).
  static constexpr int kMaxQ = kNq;
  static constexpr int kMaxPhi = kNphi;
  static constexpr int kMaxPoints = kNumPoints;

  using ScalarType = Scalar;
  using Params = typename M::template ParamsT<Scalar>;
  using Coefficients = typename M::template CoefficientsT<Scalar>;
  using VecQ = Eigen::Matrix<Scalar, kNq, 1>;
  using VecPhi = Eigen::Matrix<Scalar, kNphi, 1>;
  using VecC = Eigen::Matrix<Scalar, kNc, 1>;
  using VecQQ = Eigen::Matrix<Scalar, kNq * kNq, 1>;       ///< qd (x) qd
  using MatCPhi = Eigen::Matrix<Scalar, kNc, kNphi>;       ///< Phi_phi
  using MatCQ = Eigen::Matrix<Scalar, kNc, kNq>;           ///< Phi_q
  using MatK = Eigen::Matrix<Scalar, kNphi, kNq>;          ///< K
  using MatL = Eigen::Matrix<Scalar, kNphi, kNq * kNq>;    ///< L
  using MatRP = Eigen::Matrix<Scalar, 2, kNumPoints>;      ///< r_P
  using MatKP = Eigen::Matrix<Scalar, 2 * kNumPoints, kNq>;        ///< K_P
  using MatLP = Eigen::Matrix<Scalar, 2 * kNumPoints, kNq * kNq>;  ///< L_P
  using MatScene = Eigen::Matrix<Scalar, 2, kNumScenePoints>;
};

// ---- What a generated model has: the one place the runtime asks. ----
// Every generated header declares 30 `static constexpr bool kHas*` flags, rendered by
// generator/codegen/output_spec.cc from its descriptions: one per output struct and one per
// optional member of Statics (OutputSpec), and one per optional member of Coefficients and
// optional function of Model (ModelFlags). tests/kinematics/output_flags_test.cc checks them
// against what the headers hold. The runtime reads those flags here and nowhere else; it does
// not detect members or functions. A hand-written model declares the same flags with the
// values that describe it. A type without a flag that the runtime reads stops the build with
// one static_assert naming the flag (the detector below only serves that message; its answer
// is never used as the flag's value).
//
//   kHasCoeffsPhi           Coefficients::Phi, Phi_phi
//   kHasK, kHasL            Coefficients::K, L
//   kHasPoints              Coefficients::r_P (and kNumPoints > 0)
//   kHasPointVelocities     Coefficients::K_P
//   kHasPointAccelerations  Coefficients::L_P
//   kHasSolve               Solve(p, q, &phi, modes, max_iterations, tolerance), kNumBlocks,
//                           kDefaultModes, kBlockClosedForm
//   kHasNamedModes          kNumNamedModes, kModeNames, kNamedModes, ModesByName
//   kHasTrig                TrigT; Solve's and Coeffs' last argument (Trig)
//   kHasSolveTrig           SolveTrig(p, q, modes, &trig)
//   kHasTransmissionAngles  TransmissionAngles, kNumTransmissionAngles, kTransmissionJoints
//   kHasSwitchModes         SwitchModes, kNumSwitches
//   kHasDrawing             Drawing, kNumDrawJoints, kNumDrawValues, kDrawJoint*
//   kHasCamProfile          CamProfile
//   kHasAppliedLoads        AppliedLoads, kNumAppliedLoads, kAppliedLoadNames, Kind, Units
//   kHasStatics ... kHasKinematics, kHasRhs, kHasRhsConstants, kHasDesignDerivatives,
//   kHasStaticsDesign, kHasDynamicsDesign:
//                           the output structs and Statics' members (below).

namespace internal {
// Declares<Flag>_<M>: whether M declares `Flag` at all. ReadFlag_<Flag><M>(): M::Flag, after a
// static_assert that names the flag when M lacks it (and then false, so no second error).
#define MECHGEN_MODEL_FLAG_READER(Flag)                                                      \
  template <class M, class = void>                                                           \
  struct Declares_##Flag : std::false_type {};                                               \
  template <class M>                                                                         \
  struct Declares_##Flag<M, std::void_t<decltype(M::Flag)>> : std::true_type {};             \
  template <class M>                                                                         \
  constexpr bool ReadFlag_##Flag() {                                                         \
    static_assert(Declares_##Flag<M>::value,                                                 \
                  "the model type does not declare `static constexpr bool " #Flag            \
                  "`: every generated header has it; a hand-written model must declare it "  \
                  "(true only if it provides what the flag names)");                         \
    if constexpr (Declares_##Flag<M>::value) {                                               \
      return static_cast<bool>(M::Flag);                                                     \
    } else {                                                                                 \
      return false;                                                                          \
    }                                                                                        \
  }
MECHGEN_MODEL_FLAG_READER(kHasCoeffsPhi)
MECHGEN_MODEL_FLAG_READER(kHasK)
MECHGEN_MODEL_FLAG_READER(kHasL)
MECHGEN_MODEL_FLAG_READER(kHasPoints)
MECHGEN_MODEL_FLAG_READER(kHasPointVelocities)
MECHGEN_MODEL_FLAG_READER(kHasPointAccelerations)
MECHGEN_MODEL_FLAG_READER(kHasSolve)
MECHGEN_MODEL_FLAG_READER(kHasNamedModes)
MECHGEN_MODEL_FLAG_READER(kHasTrig)
MECHGEN_MODEL_FLAG_READER(kHasSolveTrig)
MECHGEN_MODEL_FLAG_READER(kHasTransmissionAngles)
MECHGEN_MODEL_FLAG_READER(kHasSwitchModes)
MECHGEN_MODEL_FLAG_READER(kHasDrawing)
MECHGEN_MODEL_FLAG_READER(kHasCamProfile)
MECHGEN_MODEL_FLAG_READER(kHasAppliedLoads)
MECHGEN_MODEL_FLAG_READER(kHasStatics)
MECHGEN_MODEL_FLAG_READER(kHasStaticsQ)
MECHGEN_MODEL_FLAG_READER(kHasStaticsStiffness)
MECHGEN_MODEL_FLAG_READER(kHasStaticsV)
MECHGEN_MODEL_FLAG_READER(kHasStaticsD2V)
MECHGEN_MODEL_FLAG_READER(kHasStaticsR)
MECHGEN_MODEL_FLAG_READER(kHasStaticsFriction)
MECHGEN_MODEL_FLAG_READER(kHasDynamics)
MECHGEN_MODEL_FLAG_READER(kHasExcess)
MECHGEN_MODEL_FLAG_READER(kHasShaking)
MECHGEN_MODEL_FLAG_READER(kHasKinematics)
MECHGEN_MODEL_FLAG_READER(kHasRhs)
MECHGEN_MODEL_FLAG_READER(kHasRhsConstants)
MECHGEN_MODEL_FLAG_READER(kHasDesignDerivatives)
MECHGEN_MODEL_FLAG_READER(kHasStaticsDesign)
MECHGEN_MODEL_FLAG_READER(kHasDynamicsDesign)
#undef MECHGEN_MODEL_FLAG_READER

/// M::TrigT<Scalar> (M::kHasSolve and M::kHasTrig): sin and cos of the angles that M::Solve
/// hands out (its last argument) and M::Coeffs takes (its last argument) instead of calling
/// sin and cos again; an empty placeholder otherwise.
struct NoTrig {};
template <class M, class Scalar = double, bool = ReadFlag_kHasSolve<M>() && ReadFlag_kHasTrig<M>()>
struct TrigOf {
  using type = NoTrig;
  static constexpr bool value = false;
};
template <class M, class Scalar>
struct TrigOf<M, Scalar, true> {
  using type = typename M::template TrigT<Scalar>;
  static constexpr bool value = true;
};

/// M::kNumBlocks when M has Solve, else 1.
template <class M, bool = ReadFlag_kHasSolve<M>()>
struct BlockCount {
  static constexpr int value = 1;
};
template <class M>
struct BlockCount<M, true> {
  static constexpr int value = M::kNumBlocks;
};

/// Number of transmission angles of a model (M::kNumTransmissionAngles where it has
/// M::TransmissionAngles); 0 for a model without them.
template <class M, bool = ReadFlag_kHasTransmissionAngles<M>()>
struct TransmissionAngleCount : std::integral_constant<int, 0> {};
template <class M>
struct TransmissionAngleCount<M, true> : std::integral_constant<int, M::kNumTransmissionAngles> {};

/// Number of switching items of the model's loads (M::kNumSwitches where it has
/// M::SwitchModes); 0 for a model without them.
template <class M, bool = ReadFlag_kHasSwitchModes<M>()>
struct SwitchCount : std::integral_constant<int, 0> {};
template <class M>
struct SwitchCount<M, true> : std::integral_constant<int, M::kNumSwitches> {};

/// Its constants (M::RhsConstantsT, when M::kHasRhsConstants), or an empty placeholder.
struct NoRhsConstants {};
template <class M, bool = ReadFlag_kHasRhsConstants<M>()>
struct RhsConstantsOf {
  using type = NoRhsConstants;
};
template <class M>
struct RhsConstantsOf<M, true> {
  using type = typename M::template RhsConstantsT<double>;
};

/// Its design derivatives (M::DesignDerivativesT, when M::kHasDesignDerivatives), or an empty
/// placeholder.
struct NoDesignDerivatives {};
template <class M, bool = ReadFlag_kHasDesignDerivatives<M>()>
struct DesignDerivativesOf {
  using type = NoDesignDerivatives;
};
template <class M>
struct DesignDerivativesOf<M, true> {
  using type = typename M::template DesignDerivativesT<double>;
};
/// Its statics' design derivatives (M::StaticsDesignT, when M::kHasStaticsDesign), or empty.
struct NoStaticsDesign {};
template <class M, bool = ReadFlag_kHasStaticsDesign<M>()>
struct StaticsDesignOf {
  using type = NoStaticsDesign;
};
template <class M>
struct StaticsDesignOf<M, true> {
  using type = typename M::template StaticsDesignT<double>;
};
}  // namespace internal

/// What model M provides in the scalar type Scalar, decided at compile time.
template <class M, class Scalar = double>
struct ModelFeatures {
  using Coefficients = typename ModelTypes<M, Scalar>::Coefficients;
  static constexpr bool kHasK = internal::ReadFlag_kHasK<M>();
  static constexpr bool kHasL = internal::ReadFlag_kHasL<M>();
  static constexpr bool kHasPoints = M::kNumPoints > 0 && internal::ReadFlag_kHasPoints<M>();
  static constexpr bool kHasPointVelocities =
      kHasPoints && internal::ReadFlag_kHasPointVelocities<M>();
  static constexpr bool kHasPointAccelerations =
      kHasPoints && internal::ReadFlag_kHasPointAccelerations<M>();
  static constexpr bool kHasScene = M::kNumScenePoints > 0;
  /// Model::Coeffs also gives Phi and Phi_phi (Coefficients::Phi, Phi_phi): a continuation
  /// step checks closure and conditioning on them, without a separate Model::Phi call.
  static constexpr bool kCoeffsHavePhi = internal::ReadFlag_kHasCoeffsPhi<M>();
  /// The generated block-ordered solver Model::Solve (closed-form dyads, Newton blocks).
  static constexpr bool kHasSolve = internal::ReadFlag_kHasSolve<M>();
  /// Model::Solve hands sin and cos of the angles to Model::Coeffs (Model::TrigT): a
  /// continuation step then calls no sin or cos for the angles a closed form solved.
  static constexpr bool kHasTrig = internal::TrigOf<M, Scalar>::value;
  /// Model::TransmissionAngles (EvalTransmissionAngles) gives this many angles; 0 without it.
  static constexpr int kNumTransmissionAngles = internal::TransmissionAngleCount<M>::value;
  /// Model::SwitchModes gives the modes of this many switching items of the loads; 0 without.
  static constexpr int kNumSwitches = internal::SwitchCount<M>::value;
  /// No constraint equations (kNc = 0: no closed loop, every coordinate an input: a
  /// pendulum, a lever): q alone is the configuration; Phi, Phi_phi and K are empty.
  static constexpr bool kLoopFree = M::kNc == 0;
};

/// M::kHasStatics: EvalStatics (M::StaticsT, M::Forces; the `forces` or `potential`
/// quantity). What the statics hold (Q, potential, reactions, friction) are the member flags
/// below; statics::StaticsFeatures combines them.
template <class M>
struct HasStatics : std::bool_constant<internal::ReadFlag_kHasStatics<M>()> {};
/// M::kHasStaticsQ: Statics::Q and drive (the `forces` quantity).
template <class M>
struct HasStaticsQ : std::bool_constant<internal::ReadFlag_kHasStaticsQ<M>()> {};
/// M::kHasStaticsStiffness: Statics::stiffness, set by M::Stiffness (EvalStiffness).
template <class M>
struct HasStaticsStiffness : std::bool_constant<internal::ReadFlag_kHasStaticsStiffness<M>()> {};
/// M::kHasStaticsV: Statics::V and dV_dq (the `potential` quantity).
template <class M>
struct HasStaticsV : std::bool_constant<internal::ReadFlag_kHasStaticsV<M>()> {};
/// M::kHasStaticsD2V: Statics::d2V_dq2, set by M::Stiffness (EvalStiffness).
template <class M>
struct HasStaticsD2V : std::bool_constant<internal::ReadFlag_kHasStaticsD2V<M>()> {};
/// M::kHasStaticsR: Statics::R, the reactions (M::kNumReactions, M::kReactionNames; with a
/// drawing, kHasDrawing, also M::kReactionJoint: statics/columns.h HasJointLinks).
template <class M>
struct HasStaticsR : std::bool_constant<internal::ReadFlag_kHasStaticsR<M>()> {};
/// M::kHasStaticsFriction: Statics::normal, gain, K_rel and the friction loads M::Forces
/// takes (M::kNumFriction, M::kFrictionJoints): Coulomb friction.
template <class M>
struct HasStaticsFriction : std::bool_constant<internal::ReadFlag_kHasStaticsFriction<M>()> {};
/// M::kHasDynamics: EvalDynamics (M::DynamicsT, M::Dynamics: I, h, Q, T, V, P_nc; the
/// `dynamics` quantity).
template <class M>
struct HasDynamics : std::bool_constant<internal::ReadFlag_kHasDynamics<M>()> {};
/// M::kHasExcess: EvalExcess (M::ExcessT, M::ExcessDynamics: the excess-coordinate
/// formulation).
template <class M>
struct HasExcess : std::bool_constant<internal::ReadFlag_kHasExcess<M>()> {};
/// M::kHasShaking: EvalShaking (M::ShakingT, M::Shaking: the shaking force and moment, Paul
/// ch. 7).
template <class M>
struct HasShaking : std::bool_constant<internal::ReadFlag_kHasShaking<M>()> {};
/// M::kHasKinematics: EvalKinematics (M::KinematicsT, M::Kinematics: SolveTrig, K, L and Phi_phi
/// in one pass; every model with SolveTrig that asks for K).
template <class M>
struct HasKinematics : std::bool_constant<internal::ReadFlag_kHasKinematics<M>()> {};
/// M::kHasRhs: EvalRhs (M::RhsT, M::Rhs, M::Prepare: SolveTrig, K, L and the equation of
/// motion in one pass).
template <class M>
struct HasRhs : std::bool_constant<internal::ReadFlag_kHasRhs<M>()> {};
/// M::kHasRhsConstants: M::RhsConstantsT (what M::Prepare computes once per parameter set).
template <class M>
struct HasRhsConstants : std::bool_constant<internal::ReadFlag_kHasRhsConstants<M>()> {};
/// M::kHasDesignDerivatives: EvalDesignDerivatives (M::DesignDerivativesT, M::Design: d/dp of
/// phi, K, L and the points for the design parameters M::kDesignNames; the `design` section).
template <class M>
struct HasDesignDerivatives : std::bool_constant<internal::ReadFlag_kHasDesignDerivatives<M>()> {};
/// M::kHasStaticsDesign: EvalStaticsDesign (M::StaticsDesignT, M::StaticsDesign: d/dp of Q, the
/// drive, V and the reactions; a design section and statics).
template <class M>
struct HasStaticsDesign : std::bool_constant<internal::ReadFlag_kHasStaticsDesign<M>()> {};
/// M::kHasDynamicsDesign: EvalDynamicsDesign (M::DynamicsDesignT, M::DynamicsDesign: d/dp of I,
/// I', h, Q, T and V; a design section and dynamics). dynamics/sensitivity.h integrates with it.
template <class M>
struct HasDynamicsDesign : std::bool_constant<internal::ReadFlag_kHasDynamicsDesign<M>()> {};
/// M::kHasSolveTrig: SolveTrig (every block a closed form handing out its angles' sin and cos).
template <class M>
struct HasSolveTrig : std::bool_constant<internal::ReadFlag_kHasSolveTrig<M>()> {};
/// M::kHasNamedModes: the model's named assembly modes (kNamedModes, kModeNames, ModesByName).
template <class M>
struct HasNamedModes : std::bool_constant<internal::ReadFlag_kHasNamedModes<M>()> {};
/// M::kHasSwitchModes: SwitchModes and kNumSwitches (switching items of the loads).
template <class M>
struct HasSwitchModes : std::bool_constant<internal::ReadFlag_kHasSwitchModes<M>()> {};
/// M::kHasDrawing: Drawing and the drawing constants (kNumDrawJoints, kDrawJoint*).
template <class M>
struct HasDrawing : std::bool_constant<internal::ReadFlag_kHasDrawing<M>()> {};
/// M::kHasCamProfile: CamProfile (cams to draw).
template <class M>
struct HasCamProfile : std::bool_constant<internal::ReadFlag_kHasCamProfile<M>()> {};

}  // namespace mechgen
