/**
 * \file dynamics/position_tracker.h
 * The positions along a simulation (issue 46: one tracker, where the minimal method
 * (forward.h), the driven one (prescribed.h) and the excess-coordinate projection (excess.h)
 * each kept their own): the generated position solver M::Solve at each stage's inputs q,
 * warm-started from the predictor phi_ref + K_ref (q - q_ref) of the last accepted
 * configuration (phi_ref, K_ref at q_ref), on the assembly modes of the run, a Newton block's
 * result refused where it lands on the other branch (sign det Phi_phi against the reference's,
 * ref_det; 0: not checked). The sin and cos of the last solve are kept (Trig) for the
 * generated functions that take them.
 *
 * PositionTracker<M> holds that state (modes, reference, ref_det, sin and cos); the calls to the generated functions that the
 * simulations share (CallSolve, CallCoeffs, CallDynamics, SolveOnBranch, ConditioningOf) are
 * here too. The model and its parameters stay with the simulation and are passed in.
 *
 * Why not position::PositionSolver::MoveTo(): a continuation step there is a second-order
 * predictor (phi0 + K dq + 1/2 L dq dq), Newton on the whole system where M::Solve fails a
 * check, halving and an assembler fallback, and it computes L, the points, the error bounds
 * and the distance to singularity at every step: other arithmetic (the simulations' outputs
 * would change in their last bits) and several times the cost of a stage, which calls the
 * solver 6 to 12 times per step. The tracker keeps the stages' arithmetic; the assembly types
 * and the modes are PositionSolver's (ModelCalls<M>::Modes).
 */
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"

namespace mechgen::dynamics {
namespace internal {

template <class M>
constexpr bool AllBlocksClosedForm() {
  for (bool b : M::kBlockClosedForm)
    if (!b) return false;
  return true;
}

// ---- the calls to the generated functions that MinimalDynamics and PrescribedDynamics
// (prescribed.h) share: the sin and cos handed over where the model has them, M::Rhs'
// constants prepared once per parameter set ----

/// M::Solve, handing *trig over where the model has it (ModelCalls<M>::Solve).
template <class M, class Trig>
auto CallSolve(const M& model, const typename ModelTypes<M>::Params& p, const typename ModelTypes<M>::VecQ& q,
               typename ModelTypes<M>::VecPhi* phi, const typename ModelCalls<M>::Modes& modes, int max_iterations,
               double tolerance, Trig* trig) {
  return ModelCalls<M>::Solve(model, p, q, phi, modes, max_iterations, tolerance, trig);
}
template <class M, class Trig>
auto CallSolve(const typename M::template ParamsT<double>& p, const Eigen::Matrix<double, M::kNq, 1>& q,
               Eigen::Matrix<double, M::kNphi, 1>* phi, const std::array<int, M::kNumBlocks>& modes,
               int max_iterations, double tolerance, Trig* trig) {
  return CallSolve(M(), p, q, phi, modes, max_iterations, tolerance, trig);
}

/// M::Coeffs, given the sin and cos of the last solve where the model has them (and
/// positions: a model without phi solves nothing, and Coeffs takes its own sin and cos).
template <class M, class Trig>
void CallCoeffs(const M& model, const typename ModelTypes<M>::Params& p, const typename ModelTypes<M>::VecQ& q,
                const typename ModelTypes<M>::VecPhi& phi, typename ModelTypes<M>::Coefficients* c,
                const Trig* trig) {
  using Calls = ModelCalls<M>;
  Calls::Coeffs(model, p, q, phi, c, Calls::Nphi(model) > 0 ? trig : nullptr);
}
template <class M, class Trig>
void CallCoeffs(const typename M::template ParamsT<double>& p, const Eigen::Matrix<double, M::kNq, 1>& q,
                const Eigen::Matrix<double, M::kNphi, 1>& phi, typename M::template CoefficientsT<double>* c,
                const Trig* trig) {
  CallCoeffs(M(), p, q, phi, c, trig);
}

/// M::Dynamics, likewise (ModelCalls<M>::Dynamics).
template <class M, class Trig>
void CallDynamics(const M& model, const typename ModelTypes<M>::Params& p, const typename ModelTypes<M>::VecQ& q,
                  const typename ModelTypes<M>::VecPhi& phi, const typename ModelTypes<M>::VecQ& qd, double t,
                  const typename ModelTypes<M>::Coefficients& c,
                  typename ModelCalls<M>::template DynamicsOut<M>* d, const Trig* trig) {
  ModelCalls<M>::Dynamics(model, p, q, phi, qd, t, c, d, trig);
}
template <class M, class Trig>
void CallDynamics(const typename M::template ParamsT<double>& p, const Eigen::Matrix<double, M::kNq, 1>& q,
                  const Eigen::Matrix<double, M::kNphi, 1>& phi, const Eigen::Matrix<double, M::kNq, 1>& qd,
                  double t, const typename M::template CoefficientsT<double>& c,
                  typename M::template DynamicsT<double>* d, const Trig* trig) {
  CallDynamics(M(), p, q, phi, qd, t, c, d, trig);
}

/// Whether every block of M::Solve is closed-form (no Newton block can land on the other
/// branch): constant for a generated M, the view's at run time.
template <class M>
bool AllBlocksClosedFormOf(const M& model) {
  using Calls = ModelCalls<M>;
  if constexpr (Calls::kView) {
    for (int b = 0; b < Calls::NumBlocks(model); ++b)
      if (!Calls::BlockClosedForm(model, b)) return false;
    return true;
  } else {
    (void)model;
    return AllBlocksClosedForm<M>();
  }
}

/// The positions at q on the given modes from *phi (warm start): false when they do not
/// solve (*not_assemblable: the loop cannot close), are not finite, or (a Newton block) land
/// on the branch whose det Phi_phi has the other sign than ref_det (0: not checked).
template <class M, class Trig>
bool SolveOnBranch(const M& model, const typename ModelTypes<M>::Params& p, const typename ModelTypes<M>::VecQ& q,
                   typename ModelTypes<M>::VecPhi* phi, const typename ModelCalls<M>::Modes& modes,
                   int max_iterations, double tolerance, double ref_det, Trig* trig, bool* not_assemblable) {
  *not_assemblable = false;
  if constexpr (M::kNphi == 0) {
    (void)model, (void)p, (void)q, (void)phi, (void)modes, (void)max_iterations, (void)tolerance, (void)ref_det,
        (void)trig;
    return true;
  } else {
    using Calls = ModelCalls<M>;
    if (Calls::Nphi(model) == 0) return true;  // (a view without loops; constant otherwise)
    const auto report = CallSolve(model, p, q, phi, modes, max_iterations, tolerance, trig);
    if (report.status != decltype(report.status)::kConverged) {
      *not_assemblable = report.status == decltype(report.status)::kNotAssemblable;
      return false;
    }
    if (!phi->allFinite()) return false;
    bool check_branch = false;
    if constexpr (Calls::kView) {
      check_branch = !AllBlocksClosedFormOf(model);
    } else if constexpr (!AllBlocksClosedForm<M>()) {
      check_branch = true;
    }
    if (check_branch) {
      // A Newton block may converge to the other branch after a long step: refuse it.
      typename ModelTypes<M>::Coefficients c;
      CallCoeffs(model, p, q, *phi, &c, trig);
      double cond = 0, det = 0;
      ConditionAndDeterminant(c.Phi_phi, &cond, &det);
      if (ref_det != 0 && (det > 0) != (ref_det > 0)) return false;
    }
    return true;
  }
}
template <class M, class Trig>
bool SolveOnBranch(const typename M::template ParamsT<double>& p, const Eigen::Matrix<double, M::kNq, 1>& q,
                   Eigen::Matrix<double, M::kNphi, 1>* phi, const std::array<int, M::kNumBlocks>& modes,
                   int max_iterations, double tolerance, double ref_det, Trig* trig, bool* not_assemblable) {
  return SolveOnBranch(M(), p, q, phi, modes, max_iterations, tolerance, ref_det, trig, not_assemblable);
}

/// 1/cond_1 and det of Phi_phi (rcond 0 where cond is not finite); 1 and 1 for kNphi = 0.
template <class A>
void ConditioningOf(const A& Phi_phi, double* rcond, double* det) {
  if constexpr (A::RowsAtCompileTime == 0) {
    *rcond = 1;
    *det = 1;
  } else {
    if constexpr (A::RowsAtCompileTime == Eigen::Dynamic) {
      if (Phi_phi.rows() == 0) {  // (a view without loops)
        *rcond = 1;
        *det = 1;
        return;
      }
    }
    double cond = 0;
    ConditionAndDeterminant(Phi_phi, &cond, det);
    *rcond = std::isfinite(cond) && cond > 0 ? 1.0 / cond : 0.0;
  }
}

}  // namespace internal

/// The positions along one simulation of M (see the file comment). Not shared between
/// simulations: each holds its own (no shared state; simulations run on several threads).
template <class M>
class PositionTracker {
 public:
  using Calls = ModelCalls<M>;
  using Types = ModelTypes<M>;
  using Params = typename Types::Params;
  using Coefficients = typename Types::Coefficients;
  using VecQ = typename Types::VecQ;
  using VecPhi = typename Types::VecPhi;
  using MatK = typename Types::MatK;
  using Modes = typename Calls::Modes;
  using Trig = typename Calls::Trig;

  /// The model's default modes, a zero reference (at the model's sizes), no branch yet.
  PositionTracker(const M& model, int max_iterations, double tolerance)
      : modes_(Calls::DefaultModes(model)),
        q_ref_(Zero<VecQ>(Calls::Nq(model), 1)),
        phi_ref_(Zero<VecPhi>(Calls::Nphi(model), 1)),
        K_ref_(Zero<MatK>(Calls::Nphi(model), Calls::Nq(model))),
        max_iterations_(max_iterations),
        tolerance_(tolerance) {}

  /// Starts from (q, phi_guess) on `modes`: the predictor's reference there with K_ref = 0
  /// (the branch reference, ref_det, is left as it is).
  void Restart(const Modes& modes, const VecQ& q, const VecPhi& phi_guess) {
    modes_ = modes;
    q_ref_ = q;
    phi_ref_ = phi_guess;
    K_ref_.setZero();
  }
  /// Assembles at q0 from phi_guess on `modes` (Restart, then SolveAt): the reference there
  /// (its K from the coefficients *c at the solution, its branch the sign of det Phi_phi);
  /// false when it does not solve.
  bool Assemble(const M& model, const Params& p, const VecQ& q0, const VecPhi& phi_guess, const Modes& modes,
                Coefficients* c, bool* not_assemblable) {
    Restart(modes, q0, phi_guess);
    VecPhi phi = phi_guess;
    if (!SolveAt(model, p, q0, &phi, not_assemblable)) return false;
    internal::CallCoeffs(model, p, q0, phi, c, &trig_);
    phi_ref_ = phi;
    K_ref_ = c->K;
    double rcond = 1;
    if constexpr (M::kNphi == 0) {
      ref_det_ = 1;
    } else {
      internal::ConditioningOf(c->Phi_phi, &rcond, &ref_det_);
    }
    return true;
  }

  /// The positions at q from *phi (the caller's warm start: Predictor(q), or a reference of its
  /// own) on the run's modes and branch; false where they do not solve (*not_assemblable: the
  /// loop cannot close there; the system's flag, which the event loop reads).
  bool SolveAt(const M& model, const Params& p, const VecQ& q, VecPhi* phi, bool* not_assemblable) {
    return internal::SolveOnBranch(model, p, q, phi, modes_, max_iterations_, tolerance_, ref_det_, &trig_,
                                   not_assemblable);
  }
  /// phi_ref + K_ref (q - q_ref): the warm start of the positions at q (the coefficient-based
  /// product for the view's sizes, core/model_calls.h's Times).
  VecPhi Predictor(const VecQ& q) const { return phi_ref_ + Times(K_ref_, VecQ(q - q_ref_)); }

  /// Makes (q, phi, K) the reference of the warm starts, and det that of the branch.
  void SetReference(const VecQ& q, const VecPhi& phi, const MatK& K) {
    q_ref_ = q;
    phi_ref_ = phi;
    K_ref_ = K;
  }
  void SetReference(const VecQ& q, const VecPhi& phi, const MatK& K, double det) {
    SetReference(q, phi, K);
    ref_det_ = det;
  }
  void set_ref_det(double det) { ref_det_ = det; }
  double ref_det() const { return ref_det_; }
  const VecQ& q_ref() const { return q_ref_; }
  const VecPhi& phi_ref() const { return phi_ref_; }
  const MatK& K_ref() const { return K_ref_; }

  const Modes& modes() const { return modes_; }
  /// The sin and cos of the last solve (M::Solve, M::SolveTrig or M::Rhs), for the generated
  /// functions that take them.
  Trig* trig() { return &trig_; }
  const Trig& trig() const { return trig_; }

 private:
  template <class X>
  static X Zero(Eigen::Index rows, Eigen::Index cols) {
    if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
      (void)rows, (void)cols;
      return X::Zero();
    } else {
      return X::Zero(rows, cols);
    }
  }

  Modes modes_;
  VecQ q_ref_;
  VecPhi phi_ref_;
  MatK K_ref_;
  double ref_det_ = 0;
  Trig trig_{};
  int max_iterations_;
  double tolerance_;
};

}  // namespace mechgen::dynamics
