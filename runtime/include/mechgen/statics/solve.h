/**
 * \file statics/solve.h
 * Statics at one configuration: the generated Model::Forces (EvalStatics: generalized forces by virtual
 * work, driving forces, reactions; Paul ch. 5) plus what the generated code cannot do
 * alone: Coulomb friction that depends on the reactions it changes (Paul §5.6), the
 * forward / backward driving force and self-locking of an input (§5.6.3), and the refusal
 * to report forces at a dead point of the kinematics.
 *
 * Who calls it: the scans in statics/dead_zones.h and statics/equilibrium.h, the statics
 * sweep (statics/sweep.h), and products that need forces at a configuration they solved
 * (position::PositionSolver::state()). Fixed-size Eigen only; nothing allocates; no
 * exceptions. Units and sign conventions: statics/types.h.
 *
 * Friction (the friction circle at a revolute joint, |N| at a prismatic one). The generated
 * Statics is linear in the friction loads f it is given, and reports for each friction
 * joint J its normal force normal_J (|F_J| at a pin, |N_J| at a slide), its gain_J (mu_J r_J
 * at a pin, mu_J at a slide) and K_rel_J = d(theta_b - theta_a)/dq (pin) or ds/dq (slide).
 * For a direction of motion e in q (qdot = e times a positive speed), Coulomb friction
 * opposes the relative motion of each joint:
 *     f_J = -gain_J normal_J(f) sign(K_rel_J . e),
 * a fixed point in f because the normal forces depend on the friction loads. Solve()
 * iterates it from f = 0 (the frictionless solution), one generated evaluation per step,
 * until the driving forces and f settle (Options tolerances). A joint that does not move
 * relatively (K_rel_J . e = 0) gets f_J = 0: static friction is then indeterminate, anywhere
 * in [-gain_J normal_J, gain_J normal_J], and the frictionless value is the one reported.
 * Several inputs are fully supported: e is a vector over all inputs, so any combination of
 * input motions defines the relative motion of every joint; AnalyzeDrive() moves one input
 * at a time (e = +-e_j) for the forward / backward figures of that input.
 *
 * Speed. A model whose loads read a velocity (StaticsFeatures<M>::kReadsSpeed: a load of
 * <coordinate>_dot, a damper, viscous joint friction) is taken at rest (qd = 0, t = 0) unless
 * the input velocities qd are given (`velocities`): then every load is taken at qd (the
 * dependent velocities K qd), the statics along a motion at that speed without the inertia
 * forces (the generated EvalKinetostatics at qdd = 0 with the masses left out). The Coulomb
 * friction iteration is the same (the direction e is independent of qd: the forward and
 * backward figures of an input are both taken at the loads of qd). The stiffness (Model::
 * Stiffness, -dQ/dq of the loads at rest) is not evaluated then: it is left NaN (no value).
 * Velocities of a model whose statics read none change nothing.
 */
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/position/state.h"
#include "mechgen/statics/traits.h"
#include "mechgen/statics/types.h"

namespace mechgen::statics {

namespace internal {
/// X::Zero() for a fixed-size X, X::Zero(rows, cols) for a bounded dynamic one.
template <class X>
MECHGEN_ALWAYS_INLINE X Zeros(Eigen::Index rows, Eigen::Index cols = 1) {
  if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
    (void)rows, (void)cols;
    return X::Zero();
  } else {
    return X::Zero(rows, cols);
  }
}
}  // namespace internal

/// The statics of model M at one configuration, for one direction of motion.
template <class M>
struct Solution {
  using Types = StaticsTypes<M>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  /// The generated Model::StaticsT<double> at the converged friction loads: Q, drive, V,
  /// stiffness, R, normal, ... (the members the model asked for). All NaN unless
  /// summary.status is kConverged (kDidNotConverge: the last iterate).
  typename Types::Statics statics;
  /// The friction loads f_J (kNumFriction) the statics were evaluated with: torque on link_b
  /// by link_a (pin, CCW +) or force on the slider along +u (slide); 0 without friction.
  typename Types::VecF friction = NaNs<typename Types::VecF>();
  /// The direction of motion e (kNq) the friction opposes; 0: no motion (frictionless).
  typename Types::VecQ direction = internal::Zeros<typename Types::VecQ>(0);
  Summary summary;

  /// A generated M: every value NaN. A ViewModel: empty (Solution(model) sizes it; Solve()
  /// sizes what it writes).
  Solution();
  /// Every value NaN at the model's sizes (for a generated M the same as Solution()).
  explicit Solution(const M& model);
};

namespace internal {

/// x with rows x cols entries, each v: x->setConstant(v) for a fixed-size X (the same code as
/// before), setConstant(rows, cols, v) for a bounded dynamic one (the view).
template <class X>
MECHGEN_ALWAYS_INLINE void Fill(X* x, Eigen::Index rows, Eigen::Index cols, double v) {
  if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
    (void)rows, (void)cols;
    x->setConstant(v);
  } else {  // (without Eigen's dynamic-size loop: the few entries of a small model)
    x->resize(rows, cols);
    ::mechgen::internal::FillEntries(x->data(), rows * cols, v);
  }
}

/// max_i |x_i| of a vector with at least one entry (Eigen's cwiseAbs().maxCoeff()): a generated
/// model's reaction norm. (The view's is generated: ModelView::StaticsChecks, the same code on
/// the fixed-size R.)
template <class X>
MECHGEN_ALWAYS_INLINE double MaxAbs(const X& x) {
  return x.cwiseAbs().maxCoeff();
}

/// A.row(J).dot(e): Eigen's for a fixed-size A; for a bounded dynamic one (the view's map) the
/// same sum in Eigen's order (a run-time length: A(J, 0) e_0 + A(J, 1) e_1 + ..., one term after
/// the other), without its dynamic-size reduction.
template <class A, class E>
MECHGEN_ALWAYS_INLINE double RowDot(const A& a, int J, const E& e) {
  if constexpr (A::SizeAtCompileTime != Eigen::Dynamic) {
    return a.row(J).dot(e);
  } else {
    const Eigen::Index n = e.size();
    double sum = a(J, 0) * e(0);
    for (Eigen::Index k = 1; k < n; ++k) sum += a(J, k) * e(k);
    return sum;
  }
}

/// Whether the model's statics have friction joints (constant for a generated M).
template <class M>
MECHGEN_ALWAYS_INLINE constexpr bool HasFriction(const M& model) {
  if constexpr (StaticsFeatures<M>::kHasFriction) {
    return ModelCalls<M>::HasFriction(model);
  } else {
    (void)model;
    return false;
  }
}

/// Every member of model M's Statics set to NaN ("no value"), whichever the model has (for the
/// view: sized as its members, those it lacks empty).
template <class M>
void SetNaN(const M& model, typename StaticsTypes<M>::Statics* s) {
  using F = StaticsFeatures<M>;
  using C = ModelCalls<M>;
  if constexpr (C::kView) {  // (the members are maps of the view's buffer, placed on its layout)
    C::SetNaNStatics(model, s);
  } else {
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    const int nq = C::Nq(model);
    Fill(&s->Q, nq, 1, kNaN);
    Fill(&s->drive, nq, 1, kNaN);
    if constexpr (F::kHasPotential) {
      s->V = kNaN;
      Fill(&s->dV_dq, C::HasPotential(model) ? nq : 0, 1, kNaN);
    }
    if constexpr (F::kHasD2V) Fill(&s->d2V_dq2, C::HasD2V(model) ? nq : 0, nq, kNaN);
    if constexpr (F::kHasStiffness) Fill(&s->stiffness, C::HasStiffness(model) ? nq : 0, nq, kNaN);
    if constexpr (F::kHasReactions) Fill(&s->R, C::NumReactions(model), 1, kNaN);
    if constexpr (F::kHasFriction) {
      const int nf = C::NumFriction(model);
      Fill(&s->normal, nf, 1, kNaN);
      Fill(&s->gain, nf, 1, kNaN);
      Fill(&s->K_rel, nf, nq, kNaN);
    }
  }
}

/// Every value Model::Forces fills is finite (NaN and inf are not); stiffness and d2V_dq2
/// (Model::Stiffness) are not checked. (The view's generated code states the same rule again:
/// ModelView::StaticsChecks, codegen/emit.cc; tests/kinematics/model_view_test.cc checks on
/// every shipped model that the two agree.)
template <class M>
bool AllFinite(const M& model, const typename StaticsTypes<M>::Statics& s) {
  using F = StaticsFeatures<M>;
  if constexpr (ModelCalls<M>::kView) {
    // (s on the view's layout: the generated struct's own reads at its fixed sizes.)
    if (s.view == model.view) return ModelCalls<M>::StaticsChecks(model, s, nullptr);
  }
  using ::mechgen::internal::Finite;  // (allFinite(); for the view without Eigen's reductions)
  bool finite = Finite(s.Q) && Finite(s.drive);
  if constexpr (F::kHasPotential)
    if (ModelCalls<M>::HasPotential(model)) finite = finite && std::isfinite(s.V) && Finite(s.dV_dq);
  if constexpr (F::kHasReactions) finite = finite && Finite(s.R);
  if constexpr (F::kHasFriction) finite = finite && Finite(s.normal);
  (void)model;
  return finite;
}

/// One generated evaluation, with the friction loads f when the model has friction and the
/// input velocities qd (nullptr: at rest) when its statics read them.
template <class M>
MECHGEN_ALWAYS_INLINE void Evaluate(const M& model, const typename ModelTypes<M>::Params& p,
                                    const typename ModelTypes<M>::VecQ& q,
                                    const typename ModelTypes<M>::VecPhi& phi,
                                    const typename ModelTypes<M>::Coefficients& c,
                                    const typename StaticsTypes<M>::VecF* f,
                                    typename StaticsTypes<M>::Statics* out,
                                    const typename ModelTypes<M>::VecQ* qd = nullptr) {
  ModelCalls<M>::Forces(model, p, q, phi, c, out, f, qd);
}

/// Model::Stiffness into out (d2V_dq2, stiffness) when the model has them.
template <class M>
void EvaluateStiffness(const M& model, const typename ModelTypes<M>::Params& p,
                       const typename ModelTypes<M>::VecQ& q,
                       const typename ModelTypes<M>::VecPhi& phi,
                       const typename ModelTypes<M>::Coefficients& c,
                       typename StaticsTypes<M>::Statics* out) {
  if constexpr (StaticsFeatures<M>::kStiffnessApart) {
    if (ModelCalls<M>::HasStiffness(model) || ModelCalls<M>::HasD2V(model))
      ModelCalls<M>::Stiffness(model, p, q, phi, c, out);
  } else {
    (void)model, (void)p, (void)q, (void)phi, (void)c, (void)out;
  }
}

/// cond_1(Phi_phi) at (q, phi): from the coefficients when they carry Phi_phi (generated
/// headers do), else from Model::Phi; 1 for a model without constraints (kLoopFree: the
/// empty Phi_phi, never singular).
template <class M>
double Condition(const M& model, const typename ModelTypes<M>::Params& p,
                 const typename ModelTypes<M>::VecQ& q, const typename ModelTypes<M>::VecPhi& phi,
                 const typename ModelTypes<M>::Coefficients& c) {
  using C = ModelCalls<M>;
  double cond = 0, det = 0;
  if constexpr (ModelFeatures<M>::kLoopFree) {
    (void)model, (void)p, (void)q, (void)phi, (void)c, (void)det;
    cond = 1;
  } else if constexpr (C::kView) {
    using MatCPhi = typename ModelTypes<M>::MatCPhi;
    if (C::LoopFree(model)) {
      cond = 1;
    } else if (C::CoeffsHavePhi(model)) {
      // (A map of the view's buffer: a fixed-size copy where the sizes are fixed, SizedViewModel.)
      if constexpr (MatCPhi::RowsAtCompileTime == Eigen::Dynamic) {
        ConditionAndDeterminantDynamic(c.Phi_phi, &cond, &det);
      } else {
        ConditionAndDeterminant(MatCPhi(c.Phi_phi), &cond, &det);
      }
    } else {
      MatCPhi Phi_phi;
      C::Phi(model, p, q, phi, nullptr, &Phi_phi, nullptr);
      ConditionAndDeterminant(Phi_phi, &cond, &det);
    }
  } else if constexpr (ModelFeatures<M>::kCoeffsHavePhi) {
    (void)model;
    ConditionAndDeterminant(c.Phi_phi, &cond, &det);
  } else {
    (void)c;
    typename ModelTypes<M>::MatCPhi Phi_phi;
    C::Phi(model, p, q, phi, nullptr, &Phi_phi, nullptr);
    ConditionAndDeterminant(Phi_phi, &cond, &det);
  }
  return cond;
}

}  // namespace internal

template <class M>
Solution<M>::Solution() {
  if constexpr (!ModelCalls<M>::kView) internal::SetNaN<M>(M(), &statics);
}

template <class M>
Solution<M>::Solution(const M& model) {
  internal::SetNaN<M>(model, &statics);
  if constexpr (ModelCalls<M>::kView) {
    friction.setConstant(ModelCalls<M>::NumFriction(model), kNaN);
    direction.setZero(ModelCalls<M>::Nq(model));
  }
}

/**
 * \brief The statics at (q, phi) for motion in direction e, with Coulomb friction iterated
 *        to consistency with the reactions (see the file comment). No allocation.
 * \param[in]  model      The model (a generated model's empty tag, or a ViewModel).
 * \param[in]  options    Tolerances, the singular threshold (statics/types.h).
 * \param[in]  p          Parameters.
 * \param[in]  q          Inputs (dim kNq).
 * \param[in]  phi        Dependent variables (dim kNphi) closing the loops at q.
 * \param[in]  c          Model::Coeffs at the same (q, phi) (the generated Statics uses K, L).
 * \param[in]  direction  e (dim kNq): the direction of motion; only its signs along each
 *                        joint matter (sign(K_rel_J . e)). Zero, or a model without
 *                        friction: one frictionless evaluation.
 * \param[out] out        Not nullptr. out->statics NaN unless kConverged (kDidNotConverge:
 *                        the last iterate).
 * \param[in]  velocities The input velocities qd (dim kNq) the loads are taken at (see
 *                        "Speed" in the file comment); nullptr: at rest.
 * \return kConverged, kSingular (cond_1(Phi_phi) > Options::max_condition or a value not
 *         finite; out->summary.condition and reaction_norm say how bad), kDidNotConverge,
 *         kInvalidInput.
 */
template <class M>
Status Solve(const M& model, const Options& options, const typename ModelTypes<M>::Params& p,
             const typename ModelTypes<M>::VecQ& q, const typename ModelTypes<M>::VecPhi& phi,
             const typename ModelTypes<M>::Coefficients& c,
             const typename ModelTypes<M>::VecQ& direction, Solution<M>* out,
             const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  static_assert(StaticsFeatures<M>::kHasStatics,
                "the model has no statics: ask for `forces` in its outputs");
  using Types = StaticsTypes<M>;
  using F = StaticsFeatures<M>;
  using C = ModelCalls<M>;
  Summary& s = out->summary;
  s = Summary();
  Assign(&out->direction, direction);
  internal::Fill(&out->friction, C::NumFriction(model), 1, 0.0);
  internal::SetNaN<M>(model, &out->statics);  // nothing stale from an earlier call
  // The stiffness is that of the loads at rest: none at a speed that the loads read.
  const bool at_speed = F::kReadsSpeed && velocities != nullptr && C::ReadsSpeed(model);
  auto finish = [&](Status status, const char* reason, bool withhold) {
    s.status = status;
    s.reason = reason;
    if (withhold) internal::SetNaN<M>(model, &out->statics);
    if (status == Status::kConverged && options.stiffness && !at_speed) {
      internal::EvaluateStiffness<M>(model, p, q, phi, c, &out->statics);
    }
    return status;
  };
  if (!options.IsValid(nullptr)) return finish(Status::kInvalidInput, "invalid Options", true);
  using ::mechgen::internal::Finite;  // (allFinite(); for the view without Eigen's reductions)
  if (!Finite(q) || !Finite(phi) || !Finite(direction) || (velocities != nullptr && !Finite(*velocities))) {
    return finish(Status::kInvalidInput, "q, phi, the direction or the velocities not finite", true);
  }
  s.condition = internal::Condition<M>(model, p, q, phi, c);

  // The frictionless evaluation: the answer without friction, the start of the iteration
  // with it, and the figure |R| that a singular configuration reports.
  bool finite = false;
  if constexpr (C::kView) {
    // Forces and the reads of its results (AllFinite, max |R|) in the view's one call, on the
    // generated struct's fixed sizes, as the generated model's code below makes them.
    finite = C::ForcesChecked(model, p, q, phi, c, &out->statics, nullptr, velocities,
                              C::HasReactions(model) ? &s.reaction_norm : nullptr);
  } else {
    internal::Evaluate<M>(model, p, q, phi, c, nullptr, &out->statics, velocities);
    if constexpr (F::kHasReactions)
      if (C::HasReactions(model)) s.reaction_norm = internal::MaxAbs(out->statics.R);
    finite = internal::AllFinite<M>(model, out->statics);
  }
  s.iterations = 1;
  if (!(s.condition <= options.max_condition)) {
    return finish(Status::kSingular, "cond_1(Phi_phi) > Options::max_condition (a dead point)",
                  true);
  }
  if (!finite) return finish(Status::kSingular, "a generated value is not finite", true);
  s.last_change = 0;
  if constexpr (F::kHasFriction) {
    using VecF = typename Types::VecF;
    const int nf = C::NumFriction(model);
    if (nf == 0) return finish(Status::kConverged, "", false);  // (a view without friction)
    // sign(K_rel_J . e): K_rel depends on the configuration only.
    auto sign = Sized<VecF>(nf);
    bool moving = false;
    for (int J = 0; J < nf; ++J) {
      sign(J) = Sign(internal::RowDot(out->statics.K_rel, J, direction));
      moving = moving || sign(J) != 0;
    }
    if (!moving) return finish(Status::kConverged, "", false);
    if constexpr (C::kView) {
      // The iteration of the generated M (below) on the view's storage, in place: the same
      // values in the same order.
      // f is out->friction itself (sized nf above), handed to the view's Forces as it is; the
      // gains, normal forces and driving forces are read through pointers into out->statics'
      // buffer, which the view's Forces writes in place (they do not move), taken once; the
      // previous f and drive in two local arrays. (Per iteration: no copy of f, no map's size
      // read again, no dispatch on a run-time size.)
      double* const f = out->friction.data();
      const double* const gain = out->statics.gain.data();
      const double* const normal = out->statics.normal.data();
      const double* const drive = out->statics.drive.data();
      const double* const sign_of = sign.data();
      const int nq = C::Nq(model);
      std::array<double, VecF::MaxRowsAtCompileTime> f_prev;  // 0: the frictionless start
      ::mechgen::internal::FillEntries(f_prev.data(), nf, 0.0);
      std::array<double, Types::VecQ::MaxRowsAtCompileTime> drive_prev;
      ::mechgen::internal::CopyEntries(drive, nq, drive_prev.data());
      for (int k = 1; k < options.max_friction_iterations; ++k) {
        for (int J = 0; J < nf; ++J) f[J] = -(gain[J] * normal[J]) * sign_of[J];
        // (Forces and internal::AllFinite of what it wrote in the view's one call.)
        const bool statics_finite =
            C::ForcesChecked(model, p, q, phi, c, &out->statics, &out->friction, velocities, nullptr);
        ++s.iterations;
        // Finite(f), max |f - f_prev| and max |f| in one loop (f_prev is finite: the last
        // iteration's f, or 0); the maxima of the finite values that the convergence test reads
        // (else the iteration stops here, and they are not read).
        double f_change = 0, f_scale = 0, zero = 0;
        for (int J = 0; J < nf; ++J) {
          const double x = f[J];
          zero += x - x;
          const double d = std::abs(x - f_prev[static_cast<size_t>(J)]), a = std::abs(x);
          f_change = f_change > d ? f_change : d;
          f_scale = f_scale > a ? f_scale : a;
        }
        if (!statics_finite || !(zero == 0)) {
          return finish(Status::kDidNotConverge, "friction iteration diverged", false);
        }
        // drive and drive_prev are finite here: their maxima in any order are the same.
        double drive_change = 0, drive_scale = 0;
        for (int j = 0; j < nq; ++j) {
          const double d = std::abs(drive[j] - drive_prev[static_cast<size_t>(j)]), a = std::abs(drive[j]);
          drive_change = drive_change > d ? drive_change : d;
          drive_scale = drive_scale > a ? drive_scale : a;
        }
        s.last_change = drive_change;
        if (drive_change <= options.relative_tolerance * drive_scale + options.absolute_tolerance &&
            f_change <= options.relative_tolerance * f_scale + options.absolute_tolerance) {
          return finish(Status::kConverged, "", false);
        }
        // (CopyEntries: a plain loop here became a call of memcpy.)
        ::mechgen::internal::CopyEntries(f, nf, f_prev.data());
        ::mechgen::internal::CopyEntries(drive, nq, drive_prev.data());
      }
      return finish(Status::kDidNotConverge,
                    "friction iteration reached Options::max_friction_iterations", false);
    } else {
      VecF f_prev = internal::Zeros<VecF>(nf);
      typename Types::VecQ drive_prev;
      Assign(&drive_prev, out->statics.drive);
      for (int k = 1; k < options.max_friction_iterations; ++k) {
        auto f = Sized<VecF>(nf);
        f = -(out->statics.gain.cwiseProduct(out->statics.normal)).cwiseProduct(sign);
        internal::Evaluate<M>(model, p, q, phi, c, &f, &out->statics, velocities);
        ++s.iterations;
        Assign(&out->friction, f);
        if (!internal::AllFinite<M>(model, out->statics) || !Finite(f)) {
          return finish(Status::kDidNotConverge, "friction iteration diverged", false);
        }
        const double drive_change = (out->statics.drive - drive_prev).template lpNorm<Eigen::Infinity>();
        const double f_change = (f - f_prev).template lpNorm<Eigen::Infinity>();
        const double drive_scale = out->statics.drive.template lpNorm<Eigen::Infinity>();
        const double f_scale = f.template lpNorm<Eigen::Infinity>();
        s.last_change = drive_change;
        if (drive_change <= options.relative_tolerance * drive_scale + options.absolute_tolerance &&
            f_change <= options.relative_tolerance * f_scale + options.absolute_tolerance) {
          return finish(Status::kConverged, "", false);
        }
        Assign(&f_prev, f);
        Assign(&drive_prev, out->statics.drive);
      }
      return finish(Status::kDidNotConverge,
                    "friction iteration reached Options::max_friction_iterations", false);
    }
  } else {
    return finish(Status::kConverged, "", false);
  }
}
/// Solve() for a generated model M (its empty tag).
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
Status Solve(const Options& options, const typename ModelTypes<M>::Params& p,
             const typename ModelTypes<M>::VecQ& q, const typename ModelTypes<M>::VecPhi& phi,
             const typename ModelTypes<M>::Coefficients& c,
             const typename ModelTypes<M>::VecQ& direction, Solution<M>* out,
             const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  return Solve<M>(M(), options, p, q, phi, c, direction, out, velocities);
}

/// Solve() at a configuration of the position solver (state.valid): evaluates Model::Coeffs
/// there first. kInvalidInput when !state.valid.
template <class M>
Status SolveAt(const M& model, const Options& options, const typename ModelTypes<M>::Params& p,
               const position::State<M>& state, const typename ModelTypes<M>::VecQ& direction,
               Solution<M>* out, const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  if (!state.valid) {
    out->summary = Summary();
    out->summary.status = Status::kInvalidInput;
    out->summary.reason = "no valid configuration";
    internal::SetNaN<M>(model, &out->statics);
    return Status::kInvalidInput;
  }
  typename ModelTypes<M>::Coefficients c;
  ModelCalls<M>::Coeffs(model, p, state.q, state.phi, &c);
  return Solve<M>(model, options, p, state.q, state.phi, c, direction, out, velocities);
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
Status SolveAt(const Options& options, const typename ModelTypes<M>::Params& p,
               const position::State<M>& state, const typename ModelTypes<M>::VecQ& direction,
               Solution<M>* out, const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  return SolveAt<M>(M(), options, p, state, direction, out, velocities);
}

/// The driving force of one input with friction, forward and backward, and self-locking
/// (Paul §5.6.3). Only input j moves (direction +-e_j). Forces: statics/types.h.
///
/// Two ways to name the same two solutions:
///   - by the direction of the input's motion: T_plus (the input runs in +q_j, q_j
///     increasing) and T_minus (-q_j). Friction opposes the motion, so by virtual work
///     T_plus = T0 + sum_J gain_J normal_J |K_rel_J| >= T0 >= T_minus = T0 - sum_J (...),
///     each with its own normal forces: continuous curves along a motion wherever T0 and the
///     reactions are (they do not swap where T0 changes sign).
///   - by who drives: forward, the motion along sign(T0) (the actuator drives the load, does
///     positive work: T_fwd = T_plus where T0 >= 0, T_minus where T0 < 0), and backward, the
///     motion against it (the load drives the machine, the actuator holds back). The
///     efficiencies and self-locking are defined on these; the curves T_fwd, T_back swap
///     where T0 changes sign.
struct DriveAnalysis {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  int input = 0;  ///< j
  /// T0 = drive_j without friction (N m for an angle input, N for a slide).
  double drive = kNaN;
  /// T_fwd = drive_j moving along sign(T0) e_j (+e_j when T0 = 0): the actuator drives the
  /// load (does positive work); |T_fwd| >= |T0| when friction only dissipates.
  double drive_forward = kNaN;
  /// T_back = drive_j moving along -sign(T0) e_j: the load drives the machine backwards,
  /// the actuator only holds back (T_back T0 > 0) or, self-locking, has to push along the
  /// motion (T_back T0 <= 0).
  double drive_backward = kNaN;
  /// T_plus = drive_j moving along +e_j (the input's coordinate increasing).
  double drive_plus = kNaN;
  /// T_minus = drive_j moving along -e_j; T_minus <= T0 <= T_plus (friction opposes motion).
  double drive_minus = kNaN;
  /// T0 / T_fwd: the forward efficiency (1 without friction, in (0, 1] with it).
  double efficiency_forward = kNaN;
  /// T_back / T0: the backward efficiency (1 without friction; <= 0 when self-locking; NaN
  /// where T0 = 0 up to rounding, |T0| <= 1e-12 |T_fwd|).
  double efficiency_backward = kNaN;
  /// T_back T0 <= 0: the load alone cannot move the machine (a dead zone).
  bool self_locking = false;
  /// kConverged when all three solves converged, else the first failure's status.
  Status status = Status::kNotRun;
};

/**
 * \brief T0, T_fwd, T_back, the efficiencies and self-locking of input j at (q, phi) from the
 *        frictionless solution there, already solved (Solve() with direction 0 and the same
 *        velocities): two more Solve() calls with friction, none without. No allocation.
 * \param[in]  frictionless  Solve() at (q, phi) with no motion; its status is the analysis'
 *                           when not kConverged.
 * \param[in]  input         j in [0, kNq).
 * \param[out] out           Not nullptr; NaN values unless out->status is kConverged.
 * \param[out] forward, backward  With motion along +-sign(T0) e_j (may be nullptr); copies of
 *                           `frictionless` (with those directions) for a model without friction.
 * \param[in]  velocities    The input velocities the loads are taken at (nullptr: at rest).
 */
template <class M>
Status AnalyzeDriveFrom(const M& model, const Options& options, const typename ModelTypes<M>::Params& p,
                        const typename ModelTypes<M>::VecQ& q,
                        const typename ModelTypes<M>::VecPhi& phi,
                        const typename ModelTypes<M>::Coefficients& c, int input,
                        const Solution<M>& frictionless, DriveAnalysis* out,
                        Solution<M>* forward = nullptr, Solution<M>* backward = nullptr,
                        const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  using VecQ = typename ModelTypes<M>::VecQ;
  *out = DriveAnalysis();
  out->input = input;
  Solution<M> local[2];
  Solution<M>* s1 = forward != nullptr ? forward : &local[0];
  Solution<M>* s2 = backward != nullptr ? backward : &local[1];
  const int nq = ModelCalls<M>::Nq(model);
  if (input < 0 || input >= nq) {
    for (Solution<M>* s : {s1, s2}) {
      s->summary = Summary();
      s->summary.status = Status::kInvalidInput;
      s->summary.reason = "input index out of range";
    }
    return out->status = Status::kInvalidInput;
  }
  const Solution<M>& s0 = frictionless;
  Status status = s0.summary.status;
  if (status != Status::kConverged) {
    *s1 = s0;
    *s2 = s0;
    return out->status = status;
  }
  const double T0 = s0.statics.drive(input);
  const double sign = T0 < 0 ? -1.0 : 1.0;
  VecQ e;
  if constexpr (VecQ::SizeAtCompileTime != Eigen::Dynamic) {
    e = VecQ::Unit(input);
  } else {
    e = VecQ::Unit(nq, input);
  }
  if (internal::HasFriction(model)) {
    const Status fwd = Solve<M>(model, options, p, q, phi, c, VecQ(sign * e), s1, velocities);
    const Status back = Solve<M>(model, options, p, q, phi, c, VecQ(-sign * e), s2, velocities);
    status = fwd != Status::kConverged ? fwd : back;
  } else {
    *s1 = s0;
    *s2 = s0;
    s1->direction = sign * e;
    s2->direction = -sign * e;
  }
  if (status != Status::kConverged) return out->status = status;
  out->drive = T0;
  out->drive_forward = s1->statics.drive(input);
  out->drive_backward = s2->statics.drive(input);
  out->drive_plus = sign > 0 ? out->drive_forward : out->drive_backward;
  out->drive_minus = sign > 0 ? out->drive_backward : out->drive_forward;
  out->efficiency_forward = T0 / out->drive_forward;
  // T_back / T0 tends to -inf as T0 -> 0 inside a dead zone; where T0 is 0 up to rounding
  // (|T0| <= 1e-12 |T_fwd|, a dead centre) the ratio says nothing: NaN.
  out->efficiency_backward = std::abs(T0) > 1e-12 * std::abs(out->drive_forward)
                                 ? out->drive_backward / T0
                                 : std::numeric_limits<double>::quiet_NaN();
  out->self_locking = out->drive_backward * T0 <= 0;
  return out->status = Status::kConverged;
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
Status AnalyzeDriveFrom(const Options& options, const typename ModelTypes<M>::Params& p,
                        const typename ModelTypes<M>::VecQ& q,
                        const typename ModelTypes<M>::VecPhi& phi,
                        const typename ModelTypes<M>::Coefficients& c, int input,
                        const Solution<M>& frictionless, DriveAnalysis* out,
                        Solution<M>* forward = nullptr, Solution<M>* backward = nullptr,
                        const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  return AnalyzeDriveFrom<M>(M(), options, p, q, phi, c, input, frictionless, out, forward, backward,
                             velocities);
}

/**
 * \brief T0, T_fwd, T_back, the efficiencies and self-locking of input j at (q, phi).
 *        Three Solve() calls (one without friction, then AnalyzeDriveFrom()). No allocation.
 * \param[in]  input         j in [0, kNq).
 * \param[out] out           Not nullptr; NaN values unless out->status is kConverged.
 * \param[out] frictionless  Solve() with no motion (may be nullptr); forward, backward: with
 *                           motion along +-sign(T0) e_j (may be nullptr).
 * \param[in]  velocities    The input velocities the loads are taken at (nullptr: at rest).
 */
template <class M>
Status AnalyzeDrive(const M& model, const Options& options, const typename ModelTypes<M>::Params& p,
                    const typename ModelTypes<M>::VecQ& q,
                    const typename ModelTypes<M>::VecPhi& phi,
                    const typename ModelTypes<M>::Coefficients& c, int input,
                    DriveAnalysis* out, Solution<M>* frictionless = nullptr,
                    Solution<M>* forward = nullptr, Solution<M>* backward = nullptr,
                    const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  using VecQ = typename ModelTypes<M>::VecQ;
  Solution<M> local;
  Solution<M>* s0 = frictionless != nullptr ? frictionless : &local;
  const int nq = ModelCalls<M>::Nq(model);
  if (input < 0 || input >= nq) {
    s0->summary = Summary();
    s0->summary.status = Status::kInvalidInput;
    s0->summary.reason = "input index out of range";
  } else {
    Solve<M>(model, options, p, q, phi, c, internal::Zeros<VecQ>(nq), s0, velocities);
  }
  return AnalyzeDriveFrom<M>(model, options, p, q, phi, c, input, *s0, out, forward, backward,
                             velocities);
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
Status AnalyzeDrive(const Options& options, const typename ModelTypes<M>::Params& p,
                    const typename ModelTypes<M>::VecQ& q,
                    const typename ModelTypes<M>::VecPhi& phi,
                    const typename ModelTypes<M>::Coefficients& c, int input,
                    DriveAnalysis* out, Solution<M>* frictionless = nullptr,
                    Solution<M>* forward = nullptr, Solution<M>* backward = nullptr,
                    const typename ModelTypes<M>::VecQ* velocities = nullptr) {
  return AnalyzeDrive<M>(M(), options, p, q, phi, c, input, out, frictionless, forward, backward,
                         velocities);
}

/// AnalyzeDrive() at a configuration of the position solver (evaluates Model::Coeffs).
template <class M>
Status AnalyzeDriveAt(const M& model, const Options& options, const typename ModelTypes<M>::Params& p,
                      const position::State<M>& state, int input, DriveAnalysis* out,
                      Solution<M>* frictionless = nullptr, Solution<M>* forward = nullptr,
                      Solution<M>* backward = nullptr) {
  if (!state.valid) {
    *out = DriveAnalysis();
    out->input = input;
    return out->status = Status::kInvalidInput;
  }
  typename ModelTypes<M>::Coefficients c;
  ModelCalls<M>::Coeffs(model, p, state.q, state.phi, &c);
  return AnalyzeDrive<M>(model, options, p, state.q, state.phi, c, input, out, frictionless, forward,
                         backward);
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
Status AnalyzeDriveAt(const Options& options, const typename ModelTypes<M>::Params& p,
                      const position::State<M>& state, int input, DriveAnalysis* out,
                      Solution<M>* frictionless = nullptr, Solution<M>* forward = nullptr,
                      Solution<M>* backward = nullptr) {
  return AnalyzeDriveAt<M>(M(), options, p, state, input, out, frictionless, forward, backward);
}

}  // namespace mechgen::statics
