/**
 * \file core/model_calls.h
 * How the runtime's templates reach their model M: one source, two instantiations (issue 43).
 *
 * A runtime template keeps its parameter M and holds `const M& model` (or a copy: a generated
 * Model is an empty tag). It reads the model's sizes, constants and flags and calls its
 * functions through ModelCalls<M>, never through M:: directly:
 *  - for a generated model (mech::<name>::Model, or a hand-written one in its shape) every
 *    accessor is constexpr and every call forwards to the static function: the fixed-size path
 *    compiles to the code it compiled to before (zero cost; bench/fourbar_bench.cc);
 *  - for mechgen::ViewModel (core/view_model.h: a ModelView, the model's sizes known at run
 *    time) the specialization there reads the view and calls its function pointers on the
 *    bounded dynamic types of ModelTypes<ViewModel> (Eigen::Matrix<double, Dynamic, ..., Max,
 *    Max>: no allocation).
 * ModelCalls<M>::kView says which; ModelFeatures<M> (core/model_traits.h) holds what M may
 * have at compile time (for the view: everything a view can have), and the Has*() accessors
 * below what it has (for the view: its flags).
 * Sizes used as template arguments go through Rows<N>(): fixed where N is, runtime otherwise.
 */
#pragma once

#include <array>
#include <limits>
#include <type_traits>

#include <Eigen/Core>

#include "mechgen/core/inline.h"
#include "mechgen/core/model_traits.h"

namespace mechgen {

/// A matrix of type X with rows x cols entries, uninitialized: X() when X is fixed-size (the
/// same code as a plain declaration), X(rows, cols) when a size is dynamic (bounded: no
/// allocation).
template <class X>
MECHGEN_ALWAYS_INLINE X Sized(Eigen::Index rows, Eigen::Index cols = 1) {
  if constexpr (X::RowsAtCompileTime != Eigen::Dynamic && X::ColsAtCompileTime != Eigen::Dynamic) {
    (void)rows, (void)cols;
    return X();
  } else {
    return X(rows, cols);
  }
}

/// X::Constant(NaN) for a fixed-size X; an empty X (nothing to fill) for a dynamic one.
template <class X>
X NaNs() {
  if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
    return X::Constant(std::numeric_limits<double>::quiet_NaN());
  } else {
    return X();
  }
}

/// a * b: for bounded dynamic matrices (ModelTypes<ViewModel>) as the coefficient-based
/// product (lazyProduct) that Eigen picks for small fixed sizes, with the same sums in the same
/// order; for fixed sizes Eigen's own choice.
template <class A, class B>
MECHGEN_ALWAYS_INLINE auto Times(const A& a, const B& b) {
  if constexpr (A::SizeAtCompileTime == Eigen::Dynamic) {
    return a.lazyProduct(b);
  } else {
    return a * b;
  }
}

/// x.middleCols<N>(start) for a fixed N, x.middleCols(start, n) for a dynamic one.
template <int N, class X>
MECHGEN_ALWAYS_INLINE auto MiddleCols(X&& x, Eigen::Index start, Eigen::Index n) {
  if constexpr (N == Eigen::Dynamic) {
    return x.middleCols(start, n);
  } else {
    (void)n;
    return x.template middleCols<N>(start);
  }
}

/// *dst = src for a plain column-major src of dst's shape (a matrix or a Map of one): Eigen's
/// assignment for a fixed-size dst; for a bounded dynamic one (ModelTypes<ViewModel>) a resize
/// and a loop over the entries, the same values, without Eigen's dynamic-size assignment
/// (alignment peeling, packet and tail loops: more than the few entries of a small model cost).
template <class Dst, class Src>
MECHGEN_ALWAYS_INLINE void Assign(Dst* dst, const Src& src) {
  if constexpr (Dst::SizeAtCompileTime != Eigen::Dynamic) {
    *dst = src;
  } else {
    dst->resize(src.rows(), src.cols());
    const Eigen::Index n = src.size();
    double* const d = dst->data();
    const double* const s = src.data();
    switch (n) {  // (up to 4 entries without a loop: a small model's vectors and 2 x 2 matrices)
      case 4:
        d[3] = s[3];
        [[fallthrough]];
      case 3:
        d[2] = s[2];
        [[fallthrough]];
      case 2:
        d[1] = s[1];
        [[fallthrough]];
      case 1:
        d[0] = s[0];
        [[fallthrough]];
      case 0:
        break;
      default:
        for (Eigen::Index i = 0; i < n; ++i) d[i] = s[i];
    }
  }
}

namespace internal {
/// d[0, n) = s[0, n) and d[0, n) = v for the view's buffers and bounded matrices: in chunks of
/// four and a tail, inline. (std::copy_n and std::fill_n with a count known only at run time
/// call memmove and memset, and so does a plain loop, which the compiler turns into them: their
/// set-up costs more than the few entries of a small model's members.)
MECHGEN_ALWAYS_INLINE void CopyEntries(const double* s, Eigen::Index n, double* d) {
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) {
    d[i] = s[i];
    d[i + 1] = s[i + 1];
    d[i + 2] = s[i + 2];
    d[i + 3] = s[i + 3];
  }
  switch (n - i) {
    case 3:
      d[i + 2] = s[i + 2];
      [[fallthrough]];
    case 2:
      d[i + 1] = s[i + 1];
      [[fallthrough]];
    case 1:
      d[i] = s[i];
      [[fallthrough]];
    default:
      break;
  }
}
MECHGEN_ALWAYS_INLINE void FillEntries(double* d, Eigen::Index n, double v) {
  Eigen::Index i = 0;
  for (; i + 4 <= n; i += 4) {
    d[i] = v;
    d[i + 1] = v;
    d[i + 2] = v;
    d[i + 3] = v;
  }
  switch (n - i) {
    case 3:
      d[i + 2] = v;
      [[fallthrough]];
    case 2:
      d[i + 1] = v;
      [[fallthrough]];
    case 1:
      d[i] = v;
      [[fallthrough]];
    default:
      break;
  }
}
}  // namespace internal

// ---- Design (a `design:` section): the counts of a generated model's (0 without) ----
namespace internal {
/// M::kNumDesign and M::kNumDesignChecks where M has a design section (kHasDesignDerivatives),
/// else 0.
template <class M, bool = ReadFlag_kHasDesignDerivatives<M>()>
struct DesignCounts {
  static constexpr int kDesign = 0, kChecks = 0;
};
template <class M>
struct DesignCounts<M, true> {
  static constexpr int kDesign = M::kNumDesign, kChecks = M::kNumDesignChecks;
};
}  // namespace internal

namespace internal {
/// Whether M has EvalDynamicsJacobian (M::DynamicsJacobian): generated with EvalDynamicsDesign
/// (kHasDynamicsDesign) where no cam law's fourth derivative is needed; no flag says so.
template <class M, class = void>
struct HasDynamicsJacobian : std::false_type {};
template <class M>
struct HasDynamicsJacobian<M, std::void_t<decltype(&M::template DynamicsJacobian<double>)>> : std::true_type {};
/// Whether M has EvalDynamicsDesignProduct (M::DynamicsDesignProduct): mu^T (dQ/dp - dh/dp -
/// (dI/dp) qdd) by reverse mode over the dynamics, generated with EvalDynamicsDesign where the
/// dynamics program is straight-line (the adjoint's lambda^T f_p, dynamics/adjoint.h).
template <class M, class = void>
struct HasDynamicsDesignProduct : std::false_type {};
template <class M>
struct HasDynamicsDesignProduct<M, std::void_t<decltype(&M::template DynamicsDesignProduct<double>)>> : std::true_type {
};
}  // namespace internal

/// Sizes, constants, flags and functions of a generated model M (static; the object is an
/// empty tag). Specialized for ViewModel in core/view_model.h.
template <class M>
struct ModelCalls {
  static constexpr bool kView = false;
  using T = ModelTypes<M>;
  using F = ModelFeatures<M>;
  using Trig = typename internal::TrigOf<M>::type;
  using Modes = std::array<int, internal::BlockCount<M>::value>;

  static constexpr int Nq(const M&) { return M::kNq; }
  static constexpr int Nphi(const M&) { return M::kNphi; }
  static constexpr int Nc(const M&) { return M::kNc; }
  static constexpr int NumPoints(const M&) { return M::kNumPoints; }
  static constexpr int NumBlocks(const M&) { return internal::BlockCount<M>::value; }
  static constexpr bool QIsAngle(const M&, int i) { return M::kQIsAngle[static_cast<size_t>(i)]; }
  static constexpr bool PhiIsAngle(const M&, int i) { return M::kPhiIsAngle[static_cast<size_t>(i)]; }
  static const double* AssemblyQ(const M&) { return M::kAssemblyQ.data(); }
  static const double* QMin(const M&) { return M::kQMin.data(); }
  static const double* QMax(const M&) { return M::kQMax.data(); }
  static const double* AssemblyPhi(const M&) { return M::kAssemblyPhi.data(); }
  static constexpr bool BlockClosedForm(const M&, int b) {
    if constexpr (F::kHasSolve) return M::kBlockClosedForm[static_cast<size_t>(b)];
    (void)b;
    return false;
  }
  static Modes DefaultModes(const M&) {
    if constexpr (F::kHasSolve) {
      return M::kDefaultModes;
    } else {
      return Modes{};
    }
  }
  /// The named assembly modes (the model's assembly_modes:): how many, their names, and mode
  /// i's blocks' modes into *modes.
  static constexpr int NumNamedModes(const M&) {
    if constexpr (HasNamedModes<M>::value) return M::kNumNamedModes;
    return 0;
  }
  static const char* ModeName(const M&, int i) {
    if constexpr (HasNamedModes<M>::value) return M::kModeNames[static_cast<size_t>(i)];
    (void)i;
    return "";
  }
  static void NamedModes(const M&, int i, Modes* modes) {
    if constexpr (HasNamedModes<M>::value) {
      *modes = M::kNamedModes[static_cast<size_t>(i)];
    } else {
      (void)i, (void)modes;
    }
  }
  static typename T::Params DefaultParams(const M&) { return typename T::Params(); }
  static constexpr const char* Name(const M&) { return M::kName; }
  static const char* QName(const M&, int j) { return M::kQNames[static_cast<size_t>(j)]; }
  static const char* PhiName(const M&, int i) { return M::kPhiNames[static_cast<size_t>(i)]; }
  static const char* PointName(const M&, int p) { return M::kPointNames[static_cast<size_t>(p)]; }
  static constexpr int NumTransmissionAngles(const M&) { return F::kNumTransmissionAngles; }
  static const char* TransmissionJoint(const M&, int t) {
    if constexpr (F::kNumTransmissionAngles > 0) return M::kTransmissionJoints[static_cast<size_t>(t)];
    (void)t;
    return "";
  }

  // What M has (ModelFeatures<M>, constant here).
  static constexpr bool HasK(const M&) { return F::kHasK; }
  static constexpr bool HasL(const M&) { return F::kHasL; }
  static constexpr bool HasPoints(const M&) { return F::kHasPoints; }
  static constexpr bool HasPointVelocities(const M&) { return F::kHasPointVelocities; }
  static constexpr bool HasPointAccelerations(const M&) { return F::kHasPointAccelerations; }
  static constexpr bool CoeffsHavePhi(const M&) { return F::kCoeffsHavePhi; }
  static constexpr bool HasSolve(const M&) { return F::kHasSolve; }
  static constexpr bool HasTrig(const M&) { return F::kHasTrig; }
  static constexpr bool LoopFree(const M&) { return F::kLoopFree; }

  // ---- The functions, in double ----
  template <class Q, class P>
  MECHGEN_ALWAYS_INLINE static void Phi(const M&, const typename T::Params& p, const Q& q, const P& phi,
                                        typename T::VecC* Phi, typename T::MatCPhi* Phi_phi,
                                        typename T::MatCQ* Phi_q) {
    M::template Phi<double>(p, q, phi, Phi, Phi_phi, Phi_q);
  }
  /// det Phi_phi (its sign is the assembly's branch).
  static void DetPhiPhi(const M&, const typename T::Params& p, const typename T::VecQ& q,
                        const typename T::VecPhi& phi, double* det) {
    M::DetPhiPhi(p, q, phi, det);
  }
  /// Model::Coeffs, with the sin and cos of Model::Solve where M has them (trig may be
  /// nullptr: Coeffs then calls its own).
  MECHGEN_ALWAYS_INLINE static void Coeffs(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                           const typename T::VecPhi& phi, typename T::Coefficients* c,
                                           const Trig* trig = nullptr) {
    if constexpr (F::kHasTrig) {
      M::template Coeffs<double>(p, q, phi, c, trig);
    } else {
      (void)trig;
      M::template Coeffs<double>(p, q, phi, c);
    }
  }
  /// Model::TransmissionAngles (nothing for a model without them).
  template <class Mu>
  static void TransmissionAngles(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                 const typename T::VecPhi& phi, Mu* mu) {
    if constexpr (F::kNumTransmissionAngles > 0) {
      M::TransmissionAngles(p, q, phi, mu);
    } else {
      (void)p, (void)q, (void)phi, (void)mu;
    }
  }
  /// Model::Solve on modes; hands out trig where M has it (trig may be nullptr otherwise).
  MECHGEN_ALWAYS_INLINE static auto Solve(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                          typename T::VecPhi* phi, const Modes& modes, int max_iterations,
                                          const double& tolerance, Trig* trig = nullptr) {
    if constexpr (F::kHasTrig) {
      return M::template Solve<double>(p, q, phi, modes, max_iterations, tolerance, trig);
    } else {
      (void)trig;
      return M::template Solve<double>(p, q, phi, modes, max_iterations, tolerance);
    }
  }

  // ---- Statics (statics/): the loads, reactions and their functions ----
  // What M's statics have (its flags, constant here; statics::StaticsFeatures combines them at
  // compile time, these the same at run time for the view).
  static constexpr bool HasStatics(const M&) { return ::mechgen::HasStatics<M>::value && HasStaticsQ<M>::value; }
  static constexpr int NumReactions(const M& m) {
    if constexpr (::mechgen::HasStatics<M>::value && HasStaticsQ<M>::value && HasStaticsR<M>::value) {
      return M::kNumReactions;
    } else {
      (void)m;
      return 0;
    }
  }
  static constexpr int NumFriction(const M& m) {
    if constexpr (::mechgen::HasStatics<M>::value && HasStaticsQ<M>::value && HasStaticsFriction<M>::value) {
      return M::kNumFriction;
    } else {
      (void)m;
      return 0;
    }
  }
  static constexpr bool HasReactions(const M& m) { return NumReactions(m) > 0; }
  static constexpr bool HasFriction(const M& m) { return NumFriction(m) > 0; }
  static constexpr bool HasPotential(const M& m) { return HasStatics(m) && HasStaticsV<M>::value; }
  static constexpr bool HasD2V(const M& m) { return HasStatics(m) && HasStaticsD2V<M>::value; }
  static constexpr bool HasStiffness(const M& m) { return HasStatics(m) && HasStaticsStiffness<M>::value; }
  /// Whether M declares kStaticsAtSpeed (its Forces then takes the input velocities).
  template <class X, class = void>
  struct DeclaresAtSpeed : std::false_type {};
  template <class X>
  struct DeclaresAtSpeed<X, std::void_t<decltype(X::kStaticsAtSpeed)>> : std::true_type {};
  static constexpr bool kDeclaresAtSpeed = DeclaresAtSpeed<M>::value;
  /// What in the statics reads a velocity (M::kStaticsAtSpeed), and how many.
  static constexpr int NumStaticsAtSpeed(const M&) {
    if constexpr (kDeclaresAtSpeed) {
      return static_cast<int>(M::kStaticsAtSpeed.size());
    } else {
      return 0;
    }
  }
  static constexpr bool ReadsSpeed(const M& m) { return HasStatics(m) && kDeclaresAtSpeed; }
  /// The friction joints of M's statics (read only where called: a model without statics
  /// need not have them).
  template <class X, bool = ::mechgen::HasStatics<X>::value && HasStaticsQ<X>::value && HasStaticsFriction<X>::value>
  struct FrictionCount : std::integral_constant<int, 0> {};
  template <class X>
  struct FrictionCount<X, true> : std::integral_constant<int, X::kNumFriction> {};
  static const char* StaticsAtSpeed(const M&, int i) {
    if constexpr (kDeclaresAtSpeed) return M::kStaticsAtSpeed[static_cast<size_t>(i)];
    (void)i;
    return "";
  }
  static const char* ReactionName(const M&, int i) {
    if constexpr (HasStaticsR<M>::value) return M::kReactionNames[static_cast<size_t>(i)];
    (void)i;
    return "";
  }
  static int ReactionJoint(const M&, int i) {
    if constexpr (HasStaticsR<M>::value && HasDrawing<M>::value) return M::kReactionJoint[static_cast<size_t>(i)];
    (void)i;
    return -1;
  }
  static const char* FrictionJoint(const M&, int i) {
    if constexpr (HasStaticsFriction<M>::value) return M::kFrictionJoints[static_cast<size_t>(i)];
    (void)i;
    return "";
  }
  /// Whether friction joint i is a slide (its load a force, N) or a pin (a torque, N m).
  static bool FrictionPrismatic(const M&, int i) {
    if constexpr (HasStaticsFriction<M>::value) return M::kFrictionPrismatic[static_cast<size_t>(i)];
    (void)i;
    return false;
  }
  /// The links of each joint (a model with reactions and a drawing: kReactionJoint,
  /// kDrawJointLinkA, kDrawJointLinkB, kGroundLink, kLinkNames).
  static constexpr bool HasJointLinks(const M& m) { return HasReactions(m) && HasDrawing<M>::value; }
  static int DrawJointLinkA(const M&, int j) {
    if constexpr (HasDrawing<M>::value) return M::kDrawJointLinkA[static_cast<size_t>(j)];
    (void)j;
    return -1;
  }
  static int DrawJointLinkB(const M&, int j) {
    if constexpr (HasDrawing<M>::value) return M::kDrawJointLinkB[static_cast<size_t>(j)];
    (void)j;
    return -1;
  }
  static int GroundLink(const M&) {
    if constexpr (HasDrawing<M>::value) return M::kGroundLink;
    return 0;
  }
  static const char* LinkName(const M&, int l) {
    if constexpr (HasDrawing<M>::value) return M::kLinkNames[static_cast<size_t>(l)];
    (void)l;
    return "";
  }
  /// Model::Forces: with the friction loads f where M has friction, with the input velocities
  /// qd (nullptr: at rest) where M's statics read them.
  template <class S, class VecF>
  MECHGEN_ALWAYS_INLINE static void Forces(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                           const typename T::VecPhi& phi, const typename T::Coefficients& c,
                                           S* out, const VecF* f, const typename T::VecQ* qd) {
    // Forces takes the friction loads (statics::StaticsFeatures<M>::kHasFriction) and the
    // velocities (kReadsSpeed).
    constexpr bool kForcesFriction = FrictionCount<M>::value > 0;
    constexpr bool kForcesSpeed = ::mechgen::HasStatics<M>::value && HasStaticsQ<M>::value && kDeclaresAtSpeed;
    if constexpr (kForcesSpeed && kForcesFriction) {
      M::template Forces<double>(p, q, phi, c, out, f, nullptr, qd);
    } else if constexpr (kForcesSpeed) {
      (void)f;
      M::template Forces<double>(p, q, phi, c, out, nullptr, nullptr, qd);
    } else if constexpr (kForcesFriction) {
      (void)qd;
      M::template Forces<double>(p, q, phi, c, out, f);
    } else {
      (void)f, (void)qd;
      M::template Forces<double>(p, q, phi, c, out);
    }
  }
  /// The coefficients at a configuration where the position step evaluated them
  /// (position::State: Phi_phi, K, L and the points, copied from its Model::Coeffs), for the
  /// statics (Model::Forces, Stiffness read Phi_phi, K and L). Phi, which the state does not
  /// keep, is 0 (the loops closed; not read by the statics).
  template <class State>
  MECHGEN_ALWAYS_INLINE static void StaticsCoefficients(const M&, const State& s, typename T::Coefficients* c) {
    if constexpr (F::kCoeffsHavePhi) {
      c->Phi.setZero();
      c->Phi_phi = s.Phi_phi;
    }
    if constexpr (F::kHasK) c->K = s.K;
    if constexpr (F::kHasL) c->L = s.L;
    if constexpr (F::kHasPoints) c->r_P = s.r_P;
    if constexpr (F::kHasPointVelocities) c->K_P = s.K_P;
    if constexpr (F::kHasPointAccelerations) c->L_P = s.L_P;
  }
  /// Model::Stiffness (d2V_dq2, stiffness) where M has it.
  template <class S>
  MECHGEN_ALWAYS_INLINE static void Stiffness(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                              const typename T::VecPhi& phi, const typename T::Coefficients& c,
                                              S* out) {
    if constexpr (HasStaticsStiffness<M>::value) {
      M::template Stiffness<double>(p, q, phi, c, out);
    } else {
      (void)p, (void)q, (void)phi, (void)c, (void)out;
    }
  }

  // ---- Design (a `design:` section): the design derivatives (position/design.h), the
  //      statics' (statics/sweep.h) and the design checks; nothing without the section ----
  static constexpr bool HasDesign(const M&) { return HasDesignDerivatives<M>::value; }
  /// The design parameters (M::kDesignNames) and the design checks (M::kDesignCheckNames).
  static constexpr int NumDesign(const M&) { return internal::DesignCounts<M>::kDesign; }
  static const char* DesignName(const M&, int d) {
    if constexpr (HasDesignDerivatives<M>::value) return M::kDesignNames[static_cast<size_t>(d)];
    (void)d;
    return "";
  }
  static constexpr int NumDesignChecks(const M&) { return internal::DesignCounts<M>::kChecks; }
  static const char* DesignCheckName(const M&, int i) {
    if constexpr (internal::DesignCounts<M>::kChecks > 0) return M::kDesignCheckNames[static_cast<size_t>(i)];
    (void)i;
    return "";
  }
  /// EvalStaticsDesign (M::StaticsDesign): a design section and statics.
  static constexpr bool HasStaticsDesign(const M& m) {
    return HasStatics(m) && ::mechgen::HasStaticsDesign<M>::value;
  }
  /// Model::Design: d/dp of phi, K, L and the points at (q, phi) into *out
  /// (position::DesignOf<M>).
  template <class D>
  static void Design(const M&, const typename T::Params& p, const typename T::VecQ& q,
                     const typename T::VecPhi& phi, D* out) {
    if constexpr (HasDesignDerivatives<M>::value) {
      M::Design(p, q, phi, out);
    } else {
      (void)p, (void)q, (void)phi, (void)out;
    }
  }
  /// Model::StaticsDesign: d/dp of Q, the drive, V and the reactions, from the coefficients c
  /// and the design derivatives dc at the same configuration.
  template <class DC, class SD>
  static void StaticsDesign(const M&, const typename T::Params& p, const typename T::VecQ& q,
                            const typename T::VecPhi& phi, const typename T::Coefficients& c, const DC& dc,
                            SD* out) {
    if constexpr (::mechgen::HasStaticsDesign<M>::value) {
      M::StaticsDesign(p, q, phi, c, dc, out);
    } else {
      (void)p, (void)q, (void)phi, (void)c, (void)dc, (void)out;
    }
  }
  /// Model::DesignChecks: the checks' margins (NumDesignChecks) and, where dmargin_dp is not
  /// nullptr, their derivatives (NumDesignChecks x NumDesign).
  using DesignMargins = Eigen::Matrix<double, internal::DesignCounts<M>::kChecks, 1>;
  using DesignMarginsDp =
      Eigen::Matrix<double, internal::DesignCounts<M>::kChecks, internal::DesignCounts<M>::kDesign>;
  static void DesignChecks(const M&, const typename T::Params& p, DesignMargins* margin,
                           DesignMarginsDp* dmargin_dp = nullptr) {
    if constexpr (internal::DesignCounts<M>::kChecks > 0) {
      M::DesignChecks(p, margin, dmargin_dp);
    } else {
      (void)p, (void)margin, (void)dmargin_dp;
    }
  }

  // ---- Dynamics (dynamics/, machines/): inertia, right-hand side, kinetostatics ----
  // The generated structs by their role (alias templates: named only where M has them).
  template <class X = M>
  using DynamicsOut = typename X::template DynamicsT<double>;
  template <class X = M>
  using RhsOut = typename X::template RhsT<double>;
  template <class X = M>
  using RhsConstantsOut = typename internal::RhsConstantsOf<X>::type;
  /// The Statics struct that Model::Kinetostatics fills (drive, Q, R, friction's normal, gain,
  /// K_rel), named apart from the statics' own accessors.
  template <class X = M>
  using KinetostaticsOut = typename X::template StaticsT<double>;
  /// A vector of the friction joints' loads (Model::Kinetostatics' friction argument).
  template <class X = M>
  using VecKinetoFriction = Eigen::Matrix<double, ModelCalls<X>::ReadKinetoNumFriction(), 1>;

  static constexpr bool HasDynamics(const M&) { return mechgen::HasDynamics<M>::value; }
  static constexpr bool HasSolveTrig(const M&) { return mechgen::HasSolveTrig<M>::value; }
  static constexpr bool HasRhs(const M&) { return mechgen::HasRhs<M>::value; }
  /// Switching items of the loads (Model::SwitchModes; 0 without), and their modes.
  static constexpr int NumSwitches(const M&) { return internal::SwitchCount<M>::value; }
  using SwitchModesArray = std::array<int, internal::SwitchCount<M>::value>;
  /// Reaction components and friction joints of Model::Kinetostatics (statics/traits.h's
  /// StaticsFeatures, by the same flags; 0 without).
  static constexpr int KinetoNumReactions(const M&) {
    if constexpr (internal::ReadFlag_kHasStatics<M>() && internal::ReadFlag_kHasStaticsQ<M>() &&
                  internal::ReadFlag_kHasStaticsR<M>()) {
      return M::kNumReactions;
    } else {
      return 0;
    }
  }
  static constexpr int ReadKinetoNumFriction() {
    if constexpr (internal::ReadFlag_kHasStatics<M>() && internal::ReadFlag_kHasStaticsQ<M>() &&
                  internal::ReadFlag_kHasStaticsFriction<M>()) {
      return M::kNumFriction;
    } else {
      return 0;
    }
  }
  static constexpr int KinetoNumFriction(const M&) { return ReadKinetoNumFriction(); }
  static const char* KinetoReactionName(const M&, int k) {
    if constexpr (internal::ReadFlag_kHasStatics<M>() && internal::ReadFlag_kHasStaticsQ<M>() &&
                  internal::ReadFlag_kHasStaticsR<M>()) {
      return M::kReactionNames[static_cast<size_t>(k)];
    } else {
      (void)k;
      return "";
    }
  }

  /// sin(phi_i) and cos(phi_i) as a solve left them in its Trig (M::TrigT).
  static double TrigSinPhi(const M&, const Trig& trig, int i) { return trig.sin_phi(i); }
  static double TrigCosPhi(const M&, const Trig& trig, int i) { return trig.cos_phi(i); }
  /// *to = from: a solve's sin and cos kept for later (the view: the entries its model has).
  static void CopyTrig(const M&, const Trig& from, Trig* to) { *to = from; }

  /// Model::Dynamics, with the sin and cos of the last solve where M has them (and kNphi > 0).
  template <class X = M>
  MECHGEN_ALWAYS_INLINE static void Dynamics(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                             const typename T::VecPhi& phi, const typename T::VecQ& qd, double t,
                                             const typename T::Coefficients& c, DynamicsOut<X>* d, const Trig* trig) {
    if constexpr (F::kHasTrig && M::kNphi > 0) {
      M::template Dynamics<double>(p, q, phi, qd, t, c, d, nullptr, trig);
    } else {
      (void)trig;
      M::template Dynamics<double>(p, q, phi, qd, t, c, d);
    }
  }
  /// Model::SolveTrig: the sin and cos of the positions only.
  MECHGEN_ALWAYS_INLINE static auto SolveTrig(const M&, const typename T::Params& p, const typename T::VecQ& q,
                                              const Modes& modes, Trig* trig) {
    return M::template SolveTrig<double>(p, q, modes, trig);
  }
  /// Model::Prepare: the constants of Model::Rhs at p.
  template <class X = M>
  static void Prepare(const M&, const typename T::Params& p, RhsConstantsOut<X>* rc) {
    M::template Prepare<double>(p, rc);
  }
  /// Model::Rhs: positions by their sin and cos, K, I, h, Q, T, V, P_nc, Phi_phi in one pass.
  template <class X = M>
  MECHGEN_ALWAYS_INLINE static auto Rhs(const M&, const typename T::Params& p, const RhsConstantsOut<X>& rc,
                                        const typename T::VecQ& q, const typename T::VecQ& qd, double t,
                                        const Modes& modes, Trig* trig, RhsOut<X>* r) {
    return M::template Rhs<double>(p, rc, q, qd, t, modes, trig, r);
  }
  /// Model::SwitchModes (the modes of the loads' switching items).
  template <class SwitchModesT>
  static void SwitchModes(const M&, const typename T::Params& p, const typename T::VecQ& q,
                          const typename T::VecPhi& phi, const typename T::VecQ& qd, double t,
                          const typename T::Coefficients& c, SwitchModesT* modes) {
    M::template SwitchModes<double>(p, q, phi, qd, t, c, modes);
  }
  /// Model::Kinetostatics, with the friction loads where M has friction joints (friction may be
  /// nullptr).
  template <class X = M>
  static void Kinetostatics(const M&, const typename T::Params& p, const typename T::VecQ& q,
                            const typename T::VecPhi& phi, const typename T::VecQ& qd, const typename T::VecQ& qdd,
                            double t, const typename T::Coefficients& c, KinetostaticsOut<X>* out,
                            const VecKinetoFriction<X>* friction) {
    if constexpr (ReadKinetoNumFriction() > 0) {
      M::template Kinetostatics<double>(p, q, phi, qd, qdd, t, c, out, friction);
    } else {
      (void)friction;
      M::template Kinetostatics<double>(p, q, phi, qd, qdd, t, c, out);
    }
  }

  // ---- Machines (engine, flywheel): what machines/ reads beyond the layers above ----
  /// A free parameter by its name in *p (the generated Params::Find), nullptr where M has none;
  /// after setting some, ParametersSet(m, p) (nothing to do here: a generated model's derived
  /// parameters are no members, its expressions read their definitions).
  static double* FindParameter(const M&, typename T::Params* p, const char* name) { return p->Find(name); }
  static void ParametersSet(const M&, typename T::Params*) {}
  /// The links with the ground (M::kNumLinks, named by LinkName where M has a drawing).
  static constexpr int NumLinks(const M&) { return M::kNumLinks; }
  /// Model::Shaking (the quantity `shaking`): F, M and each link's share F_link, M_link.
  static constexpr bool HasShaking(const M&) { return mechgen::HasShaking<M>::value; }
  template <class X = M>
  using ShakingOut = typename X::template ShakingT<double>;
  template <class X = M>
  static void Shaking(const M&, const typename T::Params& p, const typename T::VecQ& q,
                      const typename T::VecPhi& phi, const typename T::VecQ& qd, const typename T::VecQ& qdd,
                      const typename T::Coefficients& c, ShakingOut<X>* out) {
    M::template Shaking<double>(p, q, phi, qd, qdd, c, out);
  }

  // ---- Design sensitivities of the dynamics (machines/: engine and flywheel --design):
  //      Model::DynamicsDesign and Model::ShakingDesign. Both read dc, the design derivatives of
  //      positions, K and L at the same (q, phi) (Model::Design: the Design section's calls, not
  //      these); the friction loads are none (the machines refuse Coulomb friction). ----
  /// Whether M has EvalDynamicsDesign (a `design` section and dynamics) and EvalShakingDesign
  /// (also the quantity `shaking`).
  static constexpr bool HasDynamicsDesign(const M&) { return mechgen::HasDynamicsDesign<M>::value; }
  static constexpr bool HasShakingDesign(const M&) {
    return mechgen::HasDynamicsDesign<M>::value && mechgen::HasShaking<M>::value;
  }
  /// d/dp of I, dI/dq, h, Q, T, V (members dI_dp, ddI_dq_dp, dh_dp, dQ_dp, dT_dp, dV_dp).
  template <class X = M>
  using DynamicsDesignOut = typename X::template DynamicsDesignT<double>;
  /// d/dp of the shaking force (2 x kNumDesign) and moment (kNumDesign).
  template <class X = M>
  using ShakingDesignForce = Eigen::Matrix<double, 2, X::kNumDesign>;
  template <class X = M>
  using ShakingDesignMoment = Eigen::Matrix<double, X::kNumDesign, 1>;
  /// Model::DynamicsDesign at (t, q, qd): dc is Model::Design's output at (q, phi).
  template <class X = M, class DesignOut>
  static void DynamicsDesign(const M&, const typename T::Params& p, const typename T::VecQ& q,
                             const typename T::VecPhi& phi, const typename T::VecQ& qd, double t,
                             const typename T::Coefficients& c, const DesignOut& dc, DynamicsDesignOut<X>* out) {
    M::template DynamicsDesign<double>(p, q, phi, qd, t, c, dc, out);
  }
  /// Model::ShakingDesign at (q, qd, qdd); dF_dp or dM_dp may be nullptr.
  template <class X = M, class DesignOut>
  static void ShakingDesign(const M&, const typename T::Params& p, const typename T::VecQ& q,
                            const typename T::VecPhi& phi, const typename T::VecQ& qd, const typename T::VecQ& qdd,
                            const typename T::Coefficients& c, const DesignOut& dc, ShakingDesignForce<X>* dF_dp,
                            ShakingDesignMoment<X>* dM_dp) {
    M::template ShakingDesign<double>(p, q, phi, qd, qdd, c, dc, dF_dp, dM_dp);
  }

  // ---- Trajectory sensitivities (dynamics/sensitivity.h, adjoint.h): the Jacobians of the
  //      equation of motion along the state and the adjoint's product; dI/dq of Dynamics ----
  /// The bound of NumDesign (its value here).
  static constexpr int kMaxDesign = internal::DesignCounts<M>::kDesign;
  /// The design derivatives' struct (Model::Design's output; position::DesignOf<M>).
  template <class X = M>
  using DesignDerivativesOut = typename X::template DesignDerivativesT<double>;
  /// Whether M has EvalDynamicsJacobian and EvalDynamicsDesignProduct (constant here).
  static constexpr bool HasDynamicsJacobian(const M&) { return internal::HasDynamicsJacobian<M>::value; }
  static constexpr bool HasDynamicsDesignProduct(const M&) { return internal::HasDynamicsDesignProduct<M>::value; }
  /// Model::DynamicsJacobian at (t, q, qd): dQ/dq, dh/dq, dQ/dqd, dh/dqd (kNq x kNq each).
  template <class MatQQ>
  static void DynamicsJacobian(const M&,
                               const typename T::Params& p,
                               const typename T::VecQ& q,
                               const typename T::VecPhi& phi,
                               const typename T::VecQ& qd,
                               double t,
                               const typename T::Coefficients& c,
                               MatQQ* dQ_dq,
                               MatQQ* dh_dq,
                               MatQQ* dQ_dqd,
                               MatQQ* dh_dqd) {
    M::template DynamicsJacobian<double>(p, q, phi, qd, t, c, dQ_dq, dh_dq, dQ_dqd, dh_dqd);
  }
  /// Model::DynamicsDesignProduct at (t, q, qd) for qdd and mu: mu^T (dQ/dp - dh/dp - (dI/dp) qdd)
  /// (kNumDesign).
  template <class VecP>
  static void DynamicsDesignProduct(const M&,
                                    const typename T::Params& p,
                                    const typename T::VecQ& q,
                                    const typename T::VecPhi& phi,
                                    const typename T::VecQ& qd,
                                    double t,
                                    const typename T::Coefficients& c,
                                    const typename T::VecQ& qdd,
                                    const typename T::VecQ& mu,
                                    VecP* product) {
    M::template DynamicsDesignProduct<double>(p, q, phi, qd, t, c, qdd, mu, product);
  }
  /// *to = from (the view's Coefficients are not copyable: its own copy).
  static void CopyCoefficients(const M&, const typename T::Coefficients& from, typename T::Coefficients* to) {
    *to = from;
  }
  /// dI/dq of Model::Dynamics' output d (dI_dq(j, k + kNq l) = dI(j, k)/dq_l).
  template <class X = M>
  static const auto& DynamicsDIdq(const M&, const DynamicsOut<X>& d) {
    return d.dI_dq;
  }

  // ---- Synthesis (synthesis/): the parameter table's names, the scene's ground points ----
  /// The free parameters (the Params members, in their order), by index.
  static constexpr int NumFreeParameters(const M&) { return static_cast<int>(T::Params::kNames.size()); }
  static const char* FreeParameterName(const M&, int i) { return T::Params::kNames[static_cast<size_t>(i)]; }
  /// The scene: every named point of every link (M::kNumScenePoints; none without a scene).
  static constexpr int NumScenePoints(const M&) { return M::kNumScenePoints; }
  static const char* ScenePointName(const M&, int k) {
    if constexpr (M::kNumScenePoints > 0) return M::kScenePointNames[static_cast<size_t>(k)];
    (void)k;
    return "";
  }
  static int ScenePointLink(const M&, int k) {
    if constexpr (M::kNumScenePoints > 0) return M::kScenePointLink[static_cast<size_t>(k)];
    (void)k;
    return -1;
  }
  /// Model::Scene (only where NumScenePoints > 0).
  static void Scene(const M&, const typename T::Params& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                    typename T::MatScene* r) {
    if constexpr (M::kNumScenePoints > 0) M::Scene(p, q, phi, r);
  }
};

}  // namespace mechgen
