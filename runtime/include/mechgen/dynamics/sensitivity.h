/**
 * \file dynamics/sensitivity.h
 * Trajectory sensitivities (issues 27, 46): dq(t)/dp and dqd(t)/dp of the free motion of a model
 * generated with `dynamics` and a `design` section, p its design parameters
 * (M::kDesignNames), by the forward sensitivity (variational) equations integrated with the
 * state:
 *
 *     q'  = qd,                       qd' = f(t, q, qd; p) = I^-1 (Q - h)
 *     S'  = Sd,                       Sd' = f_q S + f_qd Sd + f_p
 *     S = dq/dp, Sd = dqd/dp (kNq x kNp), S(t0) = Sd(t0) = 0 (q0 and qd0 do not depend on p).
 *
 * The partial derivatives of the right-hand side, at one evaluation (Partials(): one position
 * solve, one Cholesky factor of I shared by f, f_q, f_qd and f_p):
 *  - f_p = I^-1 (dQ/dp - dh/dp - (dI/dp) qdd), the design derivatives at fixed (q, qd) through
 *    phi, K and L: row i = mu^T (...) with mu = I^-1's row i, by the generated reverse-mode
 *    EvalDynamicsDesignProduct (M::DynamicsDesignProduct, the adjoint's: one sweep for all N,
 *    kNq sweeps) where the model has it and kNq <= N; else by the forward mode's
 *    EvalDynamicsDesign (M::DynamicsDesign) from EvalDesignDerivatives (M::Design), N directions;
 *  - f_q, f_qd = I^-1 (dQ/dx - dh/dx - (dI/dx) qdd), x = q, qd: dQ/dx and dh/dx from the generated
 *    EvalDynamicsJacobian (M::DynamicsJacobian, generated with EvalDynamicsDesign: the dynamics
 *    differentiated symbolically along q and qd, through K, L and the third-order coefficients
 *    dL/dq; generator/symbolic/jacobian.h) and dI/dq from EvalDynamics (Dynamics::dI_dq). For a
 *    model without it (a cam law's fourth derivative needed, or generated before it existed),
 *    or with SensitivityOptions::jet_jacobians: the generated EvalCoefficients and EvalDynamics
 *    instantiated with ceres::Jet<double, 2 kNq>
 *    seeded on (q, qd), the positions carrying dphi/dq = K (the implicit-function derivative of
 *    the loop closure), so that I, h and Q carry their total derivatives along q and qd. Both
 *    exact (no differences); they agree to rounding (tests/design/trajectory_sensitivity_test.cc).
 *
 * Two methods (SensitivityOptions::method; CVODES' choice of the sensitivities in the error
 * test or not):
 *  - kStaggered (the default, by measurement: bench/design/run.sh, 0.36x and 0.29x the N + 1
 *    simulations of forward differences on the massive four-bar and the five-bar against the
 *    simultaneous method's 0.71x and 0.91x, its steps those of a simulation where the
 *    simultaneous method takes 1.5x): (q, qd) alone by Method with its own step and error
 *    test (the step the simulation of the values takes; its stages by the one-pass M::Rhs
 *    where the model has it, as the free simulation's); after each accepted step [t0, t1],
 *    h = t1 - t0, S and Sd by the 6-node Lobatto IIIA collocation (nodes 0, 1 and the roots of
 *    P'_5: order 10) of the linear sensitivity equations over that step, the state at the
 *    interior nodes from the integrator's dense output, the partials at the 6 nodes (the
 *    first is the last step's end, the last the accepted state whose positions the step's
 *    anchoring solved: 5 evaluations of the partials per step, 4 position solves, against
 *    12 of Dop853's stages). Why order 10 where Dop853 is of order 8: the collocation's error
 *    constant is larger than Dop853's (whose 8th-order solution is far inside its error
 *    estimate), so with 5 nodes (order 8) the sensitivities' own truncation error dominated:
 *    against Richardson differences at rtol 1e-10, 1.5e-8 on the four-bar while its state was
 *    within 3e-10 (4 nodes: 4.9e-6, 3 nodes: 3.4e-4, the collocation's orders showing); 6
 *    nodes give 8.3e-10 there (1.9e-10 at rtol 1e-12), one evaluation of the partials more per
 *    step (Nodes = 5 stays for a cheaper, less exact run: 0.30x and 0.24x). The equations are
 *    linear in (S, Sd): the collocation is one linear solve per step, of size 5 kNq (S
 *    eliminated by S_i = S0 + h sum_k a_ik Sd_k), for all kNp columns at once. The
 *    sensitivities are not in the error test (CVODES' errconS = false): the step is the
 *    state's, chosen for its tolerance. Each sample time is a step's end (the state's steps
 *    stop there), so that every sample carries the collocation's order-10 values.
 *  - kSimultaneous: y = (q, qd, vec S, vec Sd) through Method, the error control on every
 *    component (IntegratorOptions' rtol and atol on S and Sd too: about 1.5x the steps).
 *
 * Both methods are systems of the one event loop (dynamics/sensitivity_system.h,
 * simulator.h), as the free simulation is: its steps, samples and dead-point witness. The
 * positions are solved at every stage by the generated position solver from the last
 * accepted configuration's predictor, as the free simulation (dynamics/forward.h) does; a
 * configuration whose 1/cond_1(Phi_phi) falls below SensitivityOptions::min_rcond (or det
 * Phi_phi changes sign), located on the dense output, or that approaches a singular one step
 * after step (approach_rcond, approach_steps), ends the run with Status::kDeadPoint and
 * Event::kDeadPoint; the sample there is handed out with S and Sd withheld (NaN: near a dead
 * point dq/dp grows like 1/sigma_min(Phi_phi), a status, never a huge number returned as
 * success).
 *
 * Not here (the model's loads only, smooth): Coulomb friction with stick and slip (a
 * non-differentiable mode change; its friction loads are zero here), the restarts at switching
 * points of the loads (at a kink of Q the sensitivities of a switch time are not modelled:
 * the step control steps through it), the energy projection and the user events of
 * MinimalDynamics. The gradient of one scalar of a run by the adjoint equations:
 * dynamics/adjoint.h.
 *
 * Units: S(i, d) in q_i's unit per unit of p_d, Sd(i, d) in q_i's unit per second per unit
 * of p_d. Nothing allocates after construction; nothing throws; no state outside the object.
 */
#pragma once

#include <ceres/jet.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/position_tracker.h"
#include "mechgen/dynamics/sensitivity_system.h"
#include "mechgen/dynamics/simulator.h"

namespace mechgen::dynamics {

/// How the sensitivities are integrated with the state (see the file comment).
enum class SensitivityMethod {
  kStaggered,     ///< the state's own step and error test; S, Sd by collocation over each step
  kSimultaneous,  ///< (q, qd, S, Sd) through the integrator, S and Sd in the error test
};

struct SensitivityOptions {
  IntegratorOptions integrator;
  /// kStaggered: the sensitivities left out of the error test (CVODES' errconS = false), the
  /// state's steps; kSimultaneous: in it (more steps, the step control seeing S and Sd).
  SensitivityMethod method = SensitivityMethod::kStaggered;
  /// Dead point when 1/cond_1(Phi_phi) < min_rcond at an accepted step.
  double min_rcond = kMinRcond;
  /// A singular configuration approached (the steps collapse before 1/cond reaches min_rcond):
  /// approach_steps accepted steps in a row with 1/cond_1(Phi_phi) < approach_rcond and
  /// falling also end the run with kDeadPoint (as PrescribedOptions does; the defaults'
  /// one definition is witness/dead_point.h).
  double approach_rcond = kApproachRcond;
  int approach_steps = kApproachSteps;
  /// Samples every sample_dt from t0 (and at the end); 0: at every accepted step.
  double sample_dt = 0;
  /// A run whose sample grid would hand out more samples than this is refused.
  int max_samples = kMaxSimulationSamples;
  /// Newton blocks of M::Solve: iterations and tolerance (0: the generated default).
  int max_solver_iterations = kMaxSolverIterations;
  double solver_tolerance = 0;
  /// f_q and f_qd by Jets of the generated EvalCoefficients and EvalDynamics even where the model
  /// has EvalDynamicsJacobian (a second method, for checks; slower).
  bool jet_jacobians = false;

  bool IsValid(std::string* error) const {
    if (!integrator.IsValid(error)) return false;
    auto fail = [&](const char* what) {
      if (error != nullptr) *error = what;
      return false;
    };
    if (!(min_rcond >= 0 && min_rcond < 1)) return fail("SensitivityOptions::min_rcond: 0 <= min_rcond < 1");
    if (!(sample_dt >= 0) || !std::isfinite(sample_dt)) return fail("SensitivityOptions::sample_dt: 0 <= sample_dt < inf");
    if (max_samples < 1) return fail("SensitivityOptions::max_samples >= 1");
    if (!(approach_rcond >= 0 && approach_rcond < 1))
      return fail("SensitivityOptions::approach_rcond: 0 <= approach_rcond < 1");
    if (approach_steps < 1) return fail("SensitivityOptions::approach_steps >= 1");
    if (max_solver_iterations < 1) return fail("SensitivityOptions::max_solver_iterations >= 1");
    if (method != SensitivityMethod::kStaggered && method != SensitivityMethod::kSimultaneous)
      return fail("SensitivityOptions::method: kStaggered or kSimultaneous");
    return true;
  }
};

namespace internal {
/// Whether M has EvalDynamicsJacobian and EvalDynamicsDesignProduct (core/model_calls.h).
using ::mechgen::internal::HasDynamicsDesignProduct;
using ::mechgen::internal::HasDynamicsJacobian;

/// A matrix of R x C doubles bounded by MR x MC (Eigen's default storage order: a row vector
/// row-major), the same type as Eigen::Matrix<double, R, C> where the sizes are fixed.
template <int R, int C, int MR = R, int MC = C>
using BoundedMatrix = Eigen::Matrix<double, R, C, (R == 1 && C != 1) ? Eigen::RowMajor : Eigen::ColMajor, MR, MC>;
/// X::Zero() of a fixed-size X; X::Zero(rows, cols) of a bounded dynamic one.
template <class X>
X ZeroOf(Eigen::Index rows, Eigen::Index cols) {
  if constexpr (X::SizeAtCompileTime != Eigen::Dynamic) {
    (void)rows, (void)cols;
    return X::Zero();
  } else {
    return X::Zero(rows, cols);
  }
}

/**
 * The Lobatto IIIA collocation method with S = 3 to 6 nodes (the Lobatto points: 0 and 1 and
 * the roots of P'_{S-1} on [0, 1]; for 5: 0, (7 - sqrt 21)/14, 1/2, (7 + sqrt 21)/14, 1; for 6:
 * 0, (1 -+ sqrt(1/3 + 2 sqrt 7/21))/2, (1 -+ sqrt(1/3 - 2 sqrt 7/21))/2, 1): a(i, j) = the
 * integral over [0, c_i] of the Lagrange polynomial l_j of the nodes, so a(0, .) = 0 and
 * a(S - 1, .) = the Lobatto quadrature weights b (for 5: 1/20, 49/180, 16/45, 49/180, 1/20;
 * for 6: 1/30, (14 - sqrt 7)/60, (14 + sqrt 7)/60, the same mirrored); order 2 S - 2 at the
 * step's end (8 for 5 nodes, 10 for 6). Computed from the nodes at construction: l_j as the
 * product of (x - c_m)/(c_j - c_m), integrated by the 3-point Gauss-Legendre rule (exact to
 * degree 5, l_j's degree S - 1).
 */
template <int S>
struct LobattoIIIA {
  static_assert(S >= 3 && S <= 6, "Lobatto IIIA with 3 to 6 nodes");
  static constexpr int kNodes = S;
  double c[kNodes];
  Eigen::Matrix<double, kNodes, kNodes> a;

  LobattoIIIA() {
    const double r5 = std::sqrt(21.0) / 14, r4 = std::sqrt(5.0) / 10;
    const double r6o = std::sqrt(1.0 / 3 + 2 * std::sqrt(7.0) / 21) / 2, r6i = std::sqrt(1.0 / 3 - 2 * std::sqrt(7.0) / 21) / 2;
    const double n6[6] = {0, 0.5 - r6o, 0.5 - r6i, 0.5 + r6i, 0.5 + r6o, 1};
    const double n5[5] = {0, 0.5 - r5, 0.5, 0.5 + r5, 1}, n4[4] = {0, 0.5 - r4, 0.5 + r4, 1}, n3[3] = {0, 0.5, 1};
    for (int i = 0; i < kNodes; ++i) c[i] = S == 6 ? n6[i] : S == 5 ? n5[i] : S == 4 ? n4[i] : n3[i];
    auto lagrange = [&](int j, double x) {
      double l = 1;
      for (int m = 0; m < kNodes; ++m)
        if (m != j) l *= (x - c[m]) / (c[j] - c[m]);
      return l;
    };
    const double g = std::sqrt(0.6) / 2;
    const double gx[3] = {0.5 - g, 0.5, 0.5 + g}, gw[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
    for (int i = 0; i < kNodes; ++i)
      for (int j = 0; j < kNodes; ++j) {
        double sum = 0;
        for (int k = 0; k < 3; ++k) sum += gw[k] * lagrange(j, c[i] * gx[k]);
        a(i, j) = c[i] * sum;
      }
  }
};
/// The collocation with 5 nodes, order 8 (Dop853's).
using LobattoIIIA5 = LobattoIIIA<5>;

/**
 * Solves A X = B for the collocation's small sizes (fixed, or bounded dynamic: the view's) by
 * Gaussian elimination with partial
 * pivoting, B overwritten with X (Eigen's PartialPivLU solves several right-hand sides through
 * its blocked triangular solver, slower at these sizes; the same pivots, so the same
 * stability). \return false when a pivot is zero or X is not finite.
 */
template <class MatA, class MatB>
bool SolveSmall(MatA A, MatB* B) {
  auto& X = *B;
  const int n = static_cast<int>(A.rows()), m = static_cast<int>(X.cols());
  // Column-major: every inner loop runs down a column (contiguous).
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (std::abs(A(i, k)) > std::abs(A(p, k))) p = i;
    if (!(A(p, k) != 0)) return false;
    if (p != k) {
      for (int j = k; j < n; ++j) std::swap(A(k, j), A(p, j));
      for (int j = 0; j < m; ++j) std::swap(X(k, j), X(p, j));
    }
    const double inv = 1 / A(k, k);
    for (int i = k + 1; i < n; ++i) A(i, k) *= inv;  // the multipliers l_ik
    for (int j = k + 1; j < n; ++j) {
      const double a_kj = A(k, j);
      for (int i = k + 1; i < n; ++i) A(i, j) -= A(i, k) * a_kj;
    }
    for (int j = 0; j < m; ++j) {
      const double x_kj = X(k, j);
      for (int i = k + 1; i < n; ++i) X(i, j) -= A(i, k) * x_kj;
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    const double inv = 1 / A(k, k);
    for (int j = 0; j < m; ++j) {
      const double x_kj = X(k, j) * inv;
      X(k, j) = x_kj;
      for (int i = 0; i < k; ++i) X(i, j) -= A(i, k) * x_kj;
    }
  }
  return X.allFinite();
}

/**
 * \brief qdd = I^-1 f and, unless I_inv is nullptr, I^-1 (n x n): for n = 1 a division, for
 * n = 2 the closed-form inverse (I positive definite: I_00 > 0 and det I > 0), else
 * Cholesky's factor.
 * \return false unless I is positive definite and qdd finite.
 */
template <int n>
bool SolveInertia(const Eigen::Matrix<double, n, n>& I,
                  const Eigen::Matrix<double, n, 1>& f,
                  Eigen::Matrix<double, n, 1>* qdd,
                  Eigen::Matrix<double, n, n>* I_inv) {
  using MatQ = Eigen::Matrix<double, n, n>;
  if constexpr (n == 1) {
    const double I00 = I(0, 0);
    if (!(I00 > 0) || !std::isfinite(I00)) return false;
    (*qdd)(0) = f(0) / I00;
    if (I_inv != nullptr) (*I_inv)(0, 0) = 1 / I00;
  } else if constexpr (n == 2) {
    const double det = I(0, 0) * I(1, 1) - I(0, 1) * I(1, 0);
    if (!(I(0, 0) > 0) || !(det > 0) || !std::isfinite(det)) return false;
    MatQ inv;
    inv << I(1, 1) / det, -I(0, 1) / det, -I(1, 0) / det, I(0, 0) / det;
    *qdd = inv * f;
    if (I_inv != nullptr) *I_inv = inv;
  } else {
    Eigen::LLT<MatQ> llt;
    if (!I.allFinite()) return false;
    llt.compute(I);
    if (llt.info() != Eigen::Success) return false;
    *qdd = llt.solve(f);
    if (I_inv != nullptr) *I_inv = llt.solve(MatQ::Identity());
  }
  return qdd->allFinite();
}

/// The Jet of the partial derivatives along (q, qd) and M's parameters in it (a generated
/// model's; none for the view, whose sensitivities read the generated EvalDynamicsJacobian).
template <class M, bool = ModelCalls<M>::kView>
struct JetOf {
  using Jet = ceres::Jet<double, 2 * M::kNq>;
  using Params = typename M::template ParamsT<Jet>;
};
template <class M>
struct JetOf<M, true> {
  using Jet = double;
  struct Params {};
};
}  // namespace internal

template <class M, template <int> class Method, int Nodes>
class AdjointSensitivity;

/// One sample of a run with sensitivities.
template <class M>
struct SensitivitySample {
  static constexpr int kNq = M::kNq, kNphi = M::kNphi, kNp = M::kNumDesign;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  /// (The view's: bounded dynamic, empty until a run fills them.)
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  using MatQP = internal::BoundedMatrix<kNq, kNp, ModelTypes<M>::kMaxQ, ModelCalls<M>::kMaxDesign>;
  double t = kNaN;
  VecQ q = NaNs<VecQ>();
  VecQ qd = q, qdd = q;
  VecPhi phi = NaNs<VecPhi>();
  /// dq/dp and dqd/dp: S(i, d) = dq_i/dp_d, Sd(i, d) = dqd_i/dp_d (kNq x kNp).
  MatQP S = NaNs<MatQP>();
  MatQP Sd = S;
  double rcond = 1;  ///< 1/cond_1(Phi_phi) (1 for kNphi = 0)
  double det = 1;    ///< det Phi_phi (1 for kNphi = 0)
};

struct SensitivitySummary {
  Status status = Status::kNotRun;
  Event event = Event::kNone;  ///< the witness that ended the run (a dead point), if one did
  IntegratorSummary integrator;
  double t_end = std::numeric_limits<double>::quiet_NaN();  ///< where the run ended
  int samples = 0;
  int position_failures = 0;  ///< evaluations whose M::Solve failed (steps retried shorter)
  int partial_evaluations = 0;  ///< evaluations of f_q, f_qd and f_p (Partials())
  double min_rcond_seen = std::numeric_limits<double>::infinity();
  const char* message = "";

  bool IsSolutionUsable() const { return !IsFailure(status); }
};

inline std::string FormatSummary(const SensitivitySummary& s) {
  char buffer[384];
  std::snprintf(buffer, sizeof(buffer),
                "%s at t = %.9g: %d samples, %d steps, %d rejected, %d rhs evaluations, %d of the "
                "partials f_q, f_qd, f_p, min 1/cond(Phi_phi) = %.3g%s%s",
                ToString(s.status), s.t_end, s.samples, s.integrator.steps, s.integrator.rejected,
                s.integrator.rhs_evaluations, s.partial_evaluations, s.min_rcond_seen, s.message[0] != 0 ? "; " : "",
                s.message);
  return buffer;
}

/**
 * TrajectorySensitivity<M, Method>: the free motion of M with its sensitivities to the design
 * parameters, integrated by Method (Dop853 or Dopri5): kStaggered, the state (q, qd) by
 * Method<2 kNq> and (S, Sd) by collocation over its steps; kSimultaneous, the state
 * y = (q, qd, vec S, vec Sd) (column d of S, then of Sd, for each design parameter d) by
 * Method<kN>. Initialize() at q0, then Simulate(); or use Derivative() as your integrator's
 * right-hand side. Nodes: the staggered method's Lobatto IIIA nodes per step (6: order 10, the
 * default; 5: order 8, one evaluation of the partials fewer per step; 4: order 6; 3: order 4).
 */
template <class M, template <int> class Method = Dop853, int Nodes = 6>
class TrajectorySensitivity {
 public:
  /// The model's calls (core/model_calls.h): a generated model's fixed sizes, or the view's
  /// (ViewModel: the sizes at run time, bounded; see SupportedBy()).
  using Calls = ModelCalls<M>;
  using Types = ModelTypes<M>;
  static constexpr bool kView = Calls::kView;
  static_assert(kView || HasDynamics<M>::value, "TrajectorySensitivity needs a model generated with `dynamics`");
  static_assert(kView || HasDynamicsDesign<M>::value,
                "TrajectorySensitivity needs a model with a `design` section and `dynamics` (M::DynamicsDesign)");
  static constexpr int kNq = M::kNq;
  static constexpr int kNphi = M::kNphi;
  static constexpr int kNp = M::kNumDesign;
  static constexpr int kMaxQ = Types::kMaxQ;
  static constexpr int kMaxP = Calls::kMaxDesign;
  /// The simultaneous method's state (kSimultaneous: fixed sizes only) and the staggered one's.
  static constexpr int kN = kView ? Eigen::Dynamic : 2 * kNq * (1 + kNp);
  static constexpr int kNx = kView ? Eigen::Dynamic : 2 * kNq;
  using Params = typename Types::Params;
  using Coefficients = typename Types::Coefficients;
  using Dyn = typename Calls::template DynamicsOut<M>;
  using State = internal::IntegratorState<kN>;
  using StateX = internal::IntegratorState<kNx>;  ///< (q, qd): the staggered method's state
  using VecQ = typename Types::VecQ;
  using VecPhi = typename Types::VecPhi;
  using MatK = typename Types::MatK;
  using MatQ = internal::BoundedMatrix<kNq, kNq, kMaxQ, kMaxQ>;
  using MatQP = internal::BoundedMatrix<kNq, kNp, kMaxQ, kMaxP>;
  using RowP = internal::BoundedMatrix<1, kNp, 1, kMaxP>;
  using VecP = internal::BoundedMatrix<kNp, 1, kMaxP, 1>;
  using MatQX = internal::BoundedMatrix<kNq, kNx, kMaxQ, 2 * kMaxQ>;  ///< (f_q, f_qd)
  using Modes = typename Calls::Modes;
  using SampleT = SensitivitySample<M>;
  using Integrator = Method<kN>;
  using StateIntegrator = Method<kNx>;
  using Trig = typename Calls::Trig;
  using Tracker = PositionTracker<M>;
  /// The Jet of the partial derivatives along (q, qd) (fixed sizes only: jet_jacobians).
  using Jet = typename internal::JetOf<M>::Jet;
  using Collocation = internal::LobattoIIIA<Nodes>;
  static constexpr int kNodes = Collocation::kNodes;
  /// The collocation's unknowns Sd at the nodes 1..kNodes - 1 (kNodes - 1 blocks of kNq rows).
  static constexpr int kNc = kView ? Eigen::Dynamic : (kNodes - 1) * kNq;
  static constexpr int kMaxC = (kNodes - 1) * kMaxQ;
  using MatC = internal::BoundedMatrix<kNc, kNc, kMaxC, kMaxC>;
  using MatCQ = internal::BoundedMatrix<kNc, kNq, kMaxC, kMaxQ>;
  using MatCP = internal::BoundedMatrix<kNc, kNp, kMaxC, kMaxP>;
  using VecC = internal::BoundedMatrix<kNc, 1, kMaxC, 1>;
  /// The state's stages by the one-pass M::Rhs where the model has it (every block a closed
  /// form handing out sin and cos: MinimalDynamics' kStagesByRhs), else positions, coefficients
  /// and dynamics. (For the view: whether its model may; StateByRhs() says whether it does.)
  static constexpr bool kStateByRhs = mechgen::internal::TrigOf<M>::value && kNphi != 0 &&
                                      mechgen::HasSolveTrig<M>::value && mechgen::HasRhs<M>::value;

  /// The right-hand side and its partial derivatives at one (t, q, qd).
  struct Partial {
    double t = 0;
    VecQ q, qd, qdd;
    VecPhi phi;
    MatK K;
    MatQX F_x;  ///< (f_q, f_qd)
    MatQP F_p;
    double rcond = 1, det = 1;  ///< 1/cond_1(Phi_phi) and its determinant (when asked for)
    auto F_q() const { return F_x.template leftCols<kNq>(F_x.rows()); }
    auto F_qd() const { return F_x.template rightCols<kNq>(F_x.rows()); }
  };

  /// What DesignProduct() reads at a node besides its Partial: kept by Partials(..., keep) in
  /// place of f_p where the model has M::DynamicsDesignProduct.
  struct NodeKeep {
    Coefficients c;
    MatQ I_inv;
  };
  /// *to = from (the view's coefficients: copied into place).
  void CopyKeep(const NodeKeep& from, NodeKeep* to) const {
    Calls::CopyCoefficients(model_, from.c, &to->c);
    to->I_inv = from.I_inv;
  }
  /// Whether the model has M::DynamicsDesignProduct (for the view: may have; HasDesignProduct()).
  static constexpr bool kHasDesignProduct = kView || internal::HasDynamicsDesignProduct<M>::value;

  /**
   * \brief Whether the sensitivities run on `model`: a generated model that compiles here
   * does; a view needs dynamics, a design section and the generated EvalDynamicsJacobian
   * (the Jets of the fixed-size models are not the view's) and fits the bounded state (2 nq
   * within the integrators' kMaxDynamicState). \return false with *why where it does not.
   */
  static bool SupportedBy(const M& model, std::string* why) {
    if constexpr (kView) {
      auto fail = [&](const char* what) {
        if (why != nullptr) *why = what;
        return false;
      };
      if (!Calls::HasDynamics(model) || !Calls::HasDesign(model) || !Calls::HasDynamicsDesign(model))
        return fail("the trajectory sensitivities need a model with a `design` section and `dynamics`");
      if (!Calls::HasDynamicsJacobian(model))
        return fail(
            "the trajectory sensitivities through the model view need the generated EvalDynamicsJacobian, "
            "which this model lacks (a cam law's fourth derivative): use its per-model tool");
      if (2 * Calls::Nq(model) > internal::kMaxDynamicState)
        return fail("the trajectory sensitivities through the model view: too many inputs");
      return true;
    } else {
      (void)model, (void)why;
      return true;
    }
  }

  /// For a generated model (an empty tag).
  template <class X = M, std::enable_if_t<!ModelCalls<X>::kView, int> = 0>
  explicit TrajectorySensitivity(const Params& params, const SensitivityOptions& options = SensitivityOptions())
      : TrajectorySensitivity(M(), params, options) {}
  /// For any model (a view: SupportedBy(model) first).
  TrajectorySensitivity(const M& model, const Params& params, const SensitivityOptions& options)
      : model_(model),
        p_(params),
        pj_(JetParams(params)),
        options_(options),
        integrator_(options.integrator),
        state_integrator_(options.integrator),
        tracker_(model, options.max_solver_iterations, options.solver_tolerance),
        nq_(Calls::Nq(model)),
        np_(Calls::NumDesign(model)),
        state_by_rhs_(ReadStateByRhs(model)),
        has_design_product_(ReadHasDesignProduct(model)) {
    initial_.q = internal::ZeroOf<VecQ>(nq_, 1);
    initial_.phi = internal::ZeroOf<VecPhi>(Calls::Nphi(model), 1);
    initial_.K = internal::ZeroOf<MatK>(Calls::Nphi(model), nq_);
  }

  const Params& params() const { return p_; }
  const SensitivityOptions& options() const { return options_; }
  const Collocation& collocation() const { return lob_; }
  const M& model() const { return model_; }
  /// The design parameters' count (kNp; the view's at run time).
  int NumDesign() const { return np_; }
  /// Whether the state's stages run by M::Rhs (kStateByRhs; the view's model at run time).
  bool StateByRhs() const { return state_by_rhs_; }
  /// Whether DesignProduct() reads M::DynamicsDesignProduct (else lambda^T F_p).
  bool HasDesignProduct() const { return has_design_product_; }

  /// Assembles at q0 from phi_guess on the given modes: false when it does not assemble.
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess, const Modes& modes) {
    anchor_valid_ = false;
    Coefficients c;
    bool not_assemblable = false;
    tracker_.set_ref_det(0);  // (the assembly's branch is not checked)
    if (!tracker_.Assemble(model_, p_, q0, phi_guess, modes, &c, &not_assemblable)) return false;
    initial_.q = q0;
    initial_.phi = tracker_.phi_ref();
    initial_.K = c.K;
    initial_.det = tracker_.ref_det();
    initialized_ = true;
    return true;
  }
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess) {
    return Initialize(q0, phi_guess, Calls::DefaultModes(model_));
  }

  /// Assembles at q0 from the model's assembly guess (kAssemblyPhi, kDefaultModes).
  bool Initialize(const VecQ& q0) {
    const int nphi = Calls::Nphi(model_);
    VecPhi guess = internal::ZeroOf<VecPhi>(nphi, 1);
    for (int i = 0; i < nphi; ++i) guess(i) = Calls::AssemblyPhi(model_)[i];
    return Initialize(q0, guess);
  }

  /**
   * \brief qdd and the partial derivatives f_q, f_qd (F_x) and f_p at (t, q, qd), the
   * positions solved from the predictor; with conditioning, 1/cond_1(Phi_phi) and its det.
   * With keep (the adjoint) and M::DynamicsDesignProduct: f_p is not formed (n->F_p is left
   * as it was); what DesignProduct() reads of the node is kept instead.
   * \return false when the positions do not solve or I is not positive definite.
   */
  bool Partials(double t, const VecQ& q, const VecQ& qd, bool conditioning, Partial* n, NodeKeep* keep = nullptr) {
    ++partial_evaluations_;
    n->t = t;
    n->q = q;
    n->qd = qd;
    Coefficients c;
    // At the accepted configuration (a step's end: Anchor solved it from the same q), its
    // positions, coefficients and conditioning are read, not solved again.
    const bool anchored = anchor_valid_ && (q.array() == tracker_.q_ref().array()).all();
    if (anchored) {
      n->phi = tracker_.phi_ref();
      Calls::CopyCoefficients(model_, anchor_c_, &c);
      *tracker_.trig() = anchor_trig_;  // the sin and cos of that solve, which M::Dynamics may read
    } else if (!Configuration(q, &n->phi, &c)) {
      return false;
    }
    Dyn d;
    internal::CallDynamics(model_, p_, q, n->phi, qd, t, c, &d, tracker_.trig());
    // I^-1 once (kNq columns), then products: the solves of 2 kNq + kNp right-hand sides
    // went through Eigen's blocked triangular solver, slower at these sizes.
    MatQ I_inv;
    if (!SolveInertia(d.I, VecQ(d.Q - d.h), &n->qdd, &I_inv)) return false;
    // f_q, f_qd: I^-1 (dQ - dh - dI qdd)/dx for the 2 kNq directions x = (q, qd).
    const MatQX G = StateJacobian(t, q, n->phi, qd, c, d, n->qdd);
    n->F_x.noalias() = I_inv.lazyProduct(G);
    if (keep != nullptr) {
      Calls::CopyCoefficients(model_, c, &keep->c);
      keep->I_inv = I_inv;
    }
    if (kHasDesignProduct && has_design_product_ && keep != nullptr) {
      n->K = c.K;
      if (conditioning) {
        if (anchored) {
          n->rcond = anchor_rcond_;
          n->det = tracker_.ref_det();
        } else {
          internal::ConditioningOf(PhiPhi(c), &n->rcond, &n->det);
        }
      }
      return n->F_x.allFinite();
    }
    // f_p = I^-1 B, B = dQ/dp - dh/dp - (dI/dp) qdd, the generated design derivatives at fixed
    // (q, qd): by nq reverse-mode products where the model has them and nq <= np (FpByProducts),
    // else by the forward mode.
    if (!FpByProducts(t, q, qd, c, I_inv, n)) {
      typename Calls::template DesignDerivativesOut<M> dc;
      Calls::Design(model_, p_, q, n->phi, &dc);
      typename Calls::template DynamicsDesignOut<M> dd;
      Calls::DynamicsDesign(model_, p_, q, n->phi, qd, t, c, dc, &dd);
      MatQP B = dd.dQ_dp - dd.dh_dp;
      for (int dp = 0; dp < np_; ++dp)
        B.col(dp) -= Times(dd.dI_dp.template block<kNq, kNq>(0, nq_ * dp, nq_, nq_), n->qdd);
      n->F_p.noalias() = I_inv.lazyProduct(B);
    }
    n->K = c.K;
    if (conditioning) {
      if (anchored) {
        n->rcond = anchor_rcond_;
        n->det = tracker_.ref_det();
      } else {
        internal::ConditioningOf(PhiPhi(c), &n->rcond, &n->det);
      }
    }
    return n->F_x.allFinite() && n->F_p.allFinite();
  }

  /**
   * \brief f_p = I^-1 B (B = dQ/dp - dh/dp - (dI/dp) qdd) row by row: row i is mu^T B with mu =
   * I^-1's row i, one reverse sweep of the generated M::DynamicsDesignProduct for all np columns,
   * nq sweeps in all, where the forward mode carries np directions through every local and fills
   * what f_p does not read (dI/dq's, T's and V's derivatives, the points'): 0.77 against 1.73 us
   * per evaluation on the five-bar (nq = 2, np = 13), 0.25 against 0.34 on the massive four-bar
   * (bench/design/run.sh). Where nq > np the forward mode's np directions are the fewer passes
   * (not measured: no model here has it).
   * \return false (nothing written) where the model lacks the product or nq > np.
   */
  bool FpByProducts(double t, const VecQ& q, const VecQ& qd, const Coefficients& c, const MatQ& I_inv,
                    Partial* n) const {
    if constexpr (kHasDesignProduct) {
      if (has_design_product_ && nq_ <= np_) {
        n->F_p.resize(nq_, np_);
        for (int i = 0; i < nq_; ++i) {
          const VecQ mu = I_inv.row(i).transpose();
          VecP row;
          Calls::DynamicsDesignProduct(model_, p_, q, n->phi, qd, t, c, n->qdd, mu, &row);
          n->F_p.row(i) = row.transpose();
        }
        return true;
      }
    }
    (void)t, (void)q, (void)qd, (void)c, (void)I_inv, (void)n;
    return false;
  }

  /**
   * \brief lambda^T f_p at a node of Partials(..., keep): with mu = I^-1 lambda (I symmetric),
   * lambda^T I^-1 (dQ/dp - dh/dp - (dI/dp) qdd) = mu^T (...), by the generated reverse-mode
   * M::DynamicsDesignProduct (one sweep for all kNp; dphi/dp, dK/dp and dL/dp derived inside
   * it, not the points'); lambda^T
   * n.F_p where the model does not have it.
   * \return false where it is not finite.
   */
  bool DesignProduct(const Partial& n, const NodeKeep& keep, const VecQ& lambda, RowP* out) const {
    if constexpr (kHasDesignProduct) {
      if (has_design_product_) {
        const VecQ mu = Times(keep.I_inv, lambda);
        VecP product;
        Calls::DynamicsDesignProduct(model_, p_, n.q, n.phi, n.qd, n.t, keep.c, n.qdd, mu, &product);
        *out = product.transpose();
        return out->allFinite();
      }
    }
    (void)keep;
    *out = Times(lambda.transpose(), n.F_p);
    return out->allFinite();
  }

  /**
   * \brief The right-hand side dy at (t, y): (qd, qdd, vec Sd, vec(f_q S + f_qd Sd + f_p))
   * (kSimultaneous).
   * \return false when the positions do not solve or I is not positive definite.
   */
  bool Derivative(double t, const State& y, State* dy) {
    static_assert(!kView, "kSimultaneous: a generated model's fixed sizes (the view's state is bounded)");
    Partial n;
    if (!Partials(t, y.template head<kNq>(), y.template segment<kNq>(kNq), false, &n)) return false;
    const Eigen::Map<const MatQP> S(y.data() + 2 * kNq);
    const Eigen::Map<const MatQP> Sd(y.data() + 2 * kNq + kNq * kNp);
    dy->template head<kNq>() = n.qd;
    dy->template segment<kNq>(kNq) = n.qdd;
    Eigen::Map<MatQP> dS(dy->data() + 2 * kNq);
    Eigen::Map<MatQP> dSd(dy->data() + 2 * kNq + kNq * kNp);
    dS = Sd;
    dSd = n.F_x.template leftCols<kNq>() * S + n.F_x.template rightCols<kNq>() * Sd + n.F_p;
    return dy->allFinite();
  }

  /// The state's right-hand side (qd, qdd) at (t, x = (q, qd)) (kStaggered): false where the
  /// positions do not solve or I is not positive definite.
  bool StateDerivative(double t, const StateX& x, StateX* dx) {
    const VecQ q = x.template head<kNq>(nq_);
    const VecQ qd = x.template segment<kNq>(nq_, nq_);
    if constexpr (kStateByRhs) {
      if (state_by_rhs_) {
        // One generated pass (M::Rhs, as the free simulation's stages): the positions by their
        // sin and cos (closed forms on the modes' branch, no predictor), K, L, I, h, Q.
        typename Calls::template RhsOut<M> r;
        const auto report =
            Calls::Rhs(model_, p_, rhs_constants_.Of(model_, p_), q, qd, t, tracker_.modes(), tracker_.trig(), &r);
        if (report.status != decltype(report.status)::kConverged) {
          last_not_assemblable_ = report.status == decltype(report.status)::kNotAssemblable;
          ++position_failures_;
          return false;
        }
        last_not_assemblable_ = false;
        VecQ qdd;
        if (!SolveInertia(r.I, VecQ(r.Q - r.h), &qdd, nullptr)) return false;
        return StateOf(qd, qdd, dx);
      }
    }
    VecPhi phi;
    Coefficients c;
    if (!Configuration(q, &phi, &c)) return false;
    Dyn d;
    internal::CallDynamics(model_, p_, q, phi, qd, t, c, &d, tracker_.trig());
    VecQ qdd;
    if (!SolveInertia(d.I, VecQ(d.Q - d.h), &qdd, nullptr)) return false;
    return StateOf(qd, qdd, dx);
  }

  /// *dx = (qd, qdd), sized; whether it is finite.
  bool StateOf(const VecQ& qd, const VecQ& qdd, StateX* dx) const {
    if constexpr (kView) dx->resize(2 * nq_);
    dx->template head<kNq>(nq_) = qd;
    dx->template segment<kNq>(nq_, nq_) = qdd;
    return dx->allFinite();
  }

  /**
   * \brief qdd = I^-1 f and, unless I_inv is nullptr, I^-1 (internal::SolveInertia<kNq>; the
   * view's I on a fixed-size copy of its size, so that both take the same arithmetic).
   * \return false unless I is positive definite and qdd finite.
   */
  template <class MatI>
  static bool SolveInertia(const MatI& I, const VecQ& f, VecQ* qdd, MatQ* I_inv) {
    if constexpr (kView) {
      // The view's I (nq at run time): the fixed-size code of its size, the same arithmetic.
      return SolveInertiaOf<1>(I, f, qdd, I_inv);
    } else {
      return internal::SolveInertia<kNq>(I, f, qdd, I_inv);
    }
  }
  /// The view's SolveInertia on a k x k copy of I (k its size).
  template <int k, class MatI>
  static bool SolveInertiaOf(const MatI& I, const VecQ& f, VecQ* qdd, MatQ* I_inv) {
    if constexpr (k <= kMaxQ) {
      if (I.rows() != k) return SolveInertiaOf<k + 1>(I, f, qdd, I_inv);
      Eigen::Matrix<double, k, 1> qdd_k = Eigen::Matrix<double, k, 1>::Zero();
      Eigen::Matrix<double, k, k> I_inv_k = Eigen::Matrix<double, k, k>::Zero();
      if (!internal::SolveInertia<k>(Eigen::Matrix<double, k, k>(I), Eigen::Matrix<double, k, 1>(f), &qdd_k,
                                     I_inv != nullptr ? &I_inv_k : nullptr))
        return false;  // (nothing read after a failure: qdd and I_inv left as they were)
      // Entry by entry (the same values): Eigen's assignment of a k x k into the bounded
      // matrix keeps a two-double packet path that GCC 12 flags (-Warray-bounds) for k = 1.
      qdd->resize(k);
      ::mechgen::internal::CopyEntries(qdd_k.data(), k, qdd->data());
      if (I_inv != nullptr) {
        I_inv->resize(k, k);
        ::mechgen::internal::CopyEntries(I_inv_k.data(), k * k, I_inv->data());
      }
      return true;
    } else {
      (void)I, (void)f, (void)qdd, (void)I_inv;
      return false;
    }
  }

  /**
   * \brief (dQ - dh - dI qdd)/dx at (t, q, qd) for the 2 kNq directions x = (q_0.., qd_0..), at
   * the positions phi with their coefficients c, dynamics d and accelerations qdd: f_q and f_qd
   * times I. From M::DynamicsJacobian where the model has it (unless options().jet_jacobians),
   * else from Jets of M::Coeffs and M::Dynamics.
   */
  MatQX StateJacobian(double t,
                      const VecQ& q,
                      const VecPhi& phi,
                      const VecQ& qd,
                      const Coefficients& c,
                      const Dyn& d,
                      const VecQ& qdd) const {
    MatQX G = Sized<MatQX>(nq_, 2 * nq_);
    if constexpr (kView || internal::HasDynamicsJacobian<M>::value) {
      if (kView || !options_.jet_jacobians) {  // (the view: SupportedBy() asked for it)
        MatQ dQ_dq, dh_dq, dQ_dqd, dh_dqd;
        Calls::DynamicsJacobian(model_, p_, q, phi, qd, t, c, &dQ_dq, &dh_dq, &dQ_dqd, &dh_dqd);
        G.template leftCols<kNq>(nq_) = dQ_dq - dh_dq;
        G.template rightCols<kNq>(nq_) = dQ_dqd - dh_dqd;
        // dI_dq(j, k + kNq l) = dI(j, k)/dq_l.
        const auto& dI_dq = Calls::DynamicsDIdq(model_, d);
        for (int l = 0; l < nq_; ++l) G.col(l) -= Times(dI_dq.template block<kNq, kNq>(0, nq_ * l, nq_, nq_), qdd);
        return G;
      }
    }
    if constexpr (!kView) return JetJacobian(t, q, phi, qd, c, qdd);
    (void)d;
    return G;
  }

  /// StateJacobian by Jets of M::Coeffs and M::Dynamics (a generated model's fixed sizes).
  MatQX JetJacobian(
      double t, const VecQ& q, const VecPhi& phi, const VecQ& qd, const Coefficients& c, const VecQ& qdd) const {
    MatQX G;
    Eigen::Matrix<Jet, kNq, 1> qj, qdj;
    for (int i = 0; i < kNq; ++i) {
      qj(i) = Jet(q(i), i);
      qdj(i) = Jet(qd(i), kNq + i);
    }
    Eigen::Matrix<Jet, kNphi, 1> phij;
    for (int r = 0; r < kNphi; ++r) {
      phij(r) = Jet(phi(r));
      phij(r).v.template head<kNq>() = c.K.row(r).transpose();
    }
    typename M::template CoefficientsT<Jet> cj;
    M::template Coeffs<Jet>(pj_, qj, phij, &cj);
    typename M::template DynamicsT<Jet> dj;
    const Jet tj(t);
    M::template Dynamics<Jet>(pj_, qj, phij, qdj, tj, cj, &dj);
    for (int i = 0; i < kNq; ++i) G.row(i) = (dj.Q(i).v - dj.h(i).v).transpose();
    for (int i = 0; i < kNq; ++i)
      for (int k = 0; k < kNq; ++k) G.row(i) -= dj.I(i, k).v.transpose() * qdd(k);
    return G;
  }

  /// An operator() for the integrator (kSimultaneous).
  bool operator()(double t, const State& y, State* dy) { return Derivative(t, y, dy); }

  /**
   * \brief The collocation's matrix over a step h with the partials n[0..4] at its nodes: the
   * equations for Sd at the nodes 1..4 (S eliminated, S_j = S0 + h sum_k a_jk Sd_k), block
   * (i, k) = [i == k] 1 - h a_ik f_qd,k - h^2 sum_j a_ij a_jk f_q,j (i, k = 1..4). The same
   * expression with k = 0 is the block *C0 that multiplies Sd0 (moved to the right-hand side).
   */
  void CollocationMatrix(double h, const Partial* n, MatC* A, MatCQ* C0) const {
    const auto& a = lob_.a;
    const int nc = (kNodes - 1) * nq_;
    if constexpr (kView) A->resize(nc, nc), C0->resize(nc, nq_);
    for (int i = 1; i < kNodes; ++i)
      for (int k = 0; k < kNodes; ++k) {
        MatQ block = (i == k ? 1.0 : 0.0) * Identity() - (h * a(i, k)) * n[k].F_qd();
        for (int j = 1; j < kNodes; ++j) block -= (h * h * a(i, j) * a(j, k)) * n[j].F_q();  // a(0, .) = 0
        if (k == 0)
          C0->template block<kNq, kNq>(nq_ * (i - 1), 0, nq_, nq_) = block;
        else
          A->template block<kNq, kNq>(nq_ * (i - 1), nq_ * (k - 1), nq_, nq_) = block;
      }
  }
  /// The identity of kNq (the view's nq).
  MatQ Identity() const {
    if constexpr (kView) {
      return MatQ::Identity(nq_, nq_);
    } else {
      return MatQ::Identity();
    }
  }

  /**
   * \brief One collocation step of the sensitivity equations: (S, Sd) at t0 to t0 + h, with
   * the partials n[0..4] at the nodes t0 + c_j h. Sd_i - h sum_j a_ij (f_q,j S_j + f_qd,j Sd_j)
   * = Sd0 + h sum_j a_ij f_p,j (i = 1..4), Sd1 = Sd_4, S1 = S_4 (Lobatto IIIA: a(4, .) = b).
   * \return false when the solution is not finite.
   */
  bool CollocationStep(double h, const Partial* n, MatQP* S, MatQP* Sd) const {
    const auto& a = lob_.a;
    MatC A;
    MatCQ C0;
    CollocationMatrix(h, n, &A, &C0);
    MatCP R = Sized<MatCP>((kNodes - 1) * nq_, np_);
    MatQP W[kNodes];  // f_q,j S0 + f_p,j
    for (int j = 0; j < kNodes; ++j) W[j] = Times(n[j].F_q(), *S) + n[j].F_p;
    for (int i = 1; i < kNodes; ++i) {
      MatQP r = *Sd;
      for (int j = 0; j < kNodes; ++j) r += (h * a(i, j)) * W[j];
      r -= Times(C0.template block<kNq, kNq>(nq_ * (i - 1), 0, nq_, nq_), *Sd);
      R.template block<kNq, kNp>(nq_ * (i - 1), 0, nq_, np_) = r;
    }
    MatCP V = R;
    if (!internal::SolveSmall(A, &V)) return false;
    MatQP S1 = *S + (h * a(kNodes - 1, 0)) * *Sd;
    for (int k = 1; k < kNodes; ++k)
      S1 += (h * a(kNodes - 1, k)) * V.template block<kNq, kNp>(nq_ * (k - 1), 0, nq_, np_);
    *S = S1;
    *Sd = V.template block<kNq, kNp>(nq_ * (kNodes - 2), 0, nq_, np_);
    return S->allFinite() && Sd->allFinite();
  }

  /**
   * \brief Integrates from (t0, q0, qd0), S = Sd = 0, to t_end, handing every sample to
   * observer(const SampleT&) (return false to stop). Initialize() first (at q0).
   * \return summary->IsSolutionUsable().
   */
  template <class Observer>
  bool Simulate(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Observer&& observer,
                SensitivitySummary* summary) {
    *summary = SensitivitySummary();
    std::string error;
    auto refuse = [&](const char* message) {
      summary->status = Status::kInvalidInput;
      summary->message = message;
      summary->t_end = t0;
      return false;
    };
    if (!options_.IsValid(&error) || !(t_end > t0) || !std::isfinite(t_end))
      return refuse("invalid options (or t_end <= t0)");
    if (!initialized_) return refuse("Initialize() not called");
    if (options_.sample_dt > 0) {
      const double n = std::floor((t_end - t0) / options_.sample_dt);
      if (!(n + 2 <= options_.max_samples) || t0 + options_.sample_dt == t0)
        return refuse("the sample grid cannot advance or has more than max_samples samples");
    }
    BeginRun();
    if (options_.method == SensitivityMethod::kStaggered)
      return SimulateStaggered(t0, q0, qd0, t_end, observer, summary);
    if constexpr (kView) {
      return refuse("kSimultaneous: a generated model's fixed sizes only (the view's state is bounded)");
    } else {
      return SimulateSimultaneous(t0, q0, qd0, t_end, observer, summary);
    }
  }

 private:
  template <class, template <int> class, int>
  friend class AdjointSensitivity;
  template <class>
  friend class internal::SensitivitySystemBase;
  template <class, class>
  friend class internal::StaggeredSystem;
  template <class>
  friend class internal::SimultaneousSystem;

  /// The event loop's settings of a run (min_rcond, the approach, the sample grid; with
  /// steps_end_at_samples, the staggered method's, every sample a step's end).
  internal::EventSettings Events(bool steps_end_at_samples) const {
    internal::EventSettings events;
    events.min_rcond = options_.min_rcond;
    events.approach_rcond = options_.approach_rcond;
    events.approach_steps = options_.approach_steps;
    events.sample_dt = options_.sample_dt;
    events.max_samples = options_.max_samples;
    events.steps_end_at_samples = steps_end_at_samples;
    return events;
  }

  /// The event loop's run of a system from (t0, y0), its summary written into *summary.
  template <class System, class Observer>
  bool RunSystem(System* system, double t0, const typename System::State& y0, double t_end, bool steps_end_at_samples,
                 Observer& observer, SensitivitySummary* summary) {
    internal::SensitivityLoopSummary<SensitivitySummary> run;
    run.min_rcond_seen = summary->min_rcond_seen;
    NoUserEvent none;
    internal::EventLoop::Run(system, Events(steps_end_at_samples), t0, y0, t_end, observer, none, &run,
                             static_cast<SampleT*>(nullptr));
    *summary = run;
    if (summary->status == Status::kPositionFailed && system->failure() != Status::kNotRun) {
      summary->status = system->failure();  // (why the accepted step failed: the system's word)
      summary->message = system->failure_message();
    }
    summary->partial_evaluations = partial_evaluations_;
    return summary->IsSolutionUsable();
  }

  /// The staggered method's per-step work (StaggeredSystem's OnStep): the partials at the
  /// step's nodes (the first the last step's end), then S and Sd over the step by collocation
  /// into the sample at its end.
  struct Collocate {
    explicit Collocate(TrajectorySensitivity* s) : self(s) {}
    TrajectorySensitivity* self;
    internal::StaggeredSystem<TrajectorySensitivity, Collocate>* system = nullptr;
    Partial n[kNodes];  ///< n[kNodes - 1]: at the last step's end
    MatQP S, Sd;
    bool operator()(double ta, double tb, const StateX* x, SampleT* sample) {
      const int nq = self->nq_;
      n[0] = n[kNodes - 1];
      for (int j = 1; j < kNodes; ++j) {
        const double t = j == kNodes - 1 ? tb : ta + self->lob_.c[j] * (tb - ta);
        if (!self->Partials(t, x[j].template head<kNq>(nq), x[j].template segment<kNq>(nq, nq), j == kNodes - 1,
                            &n[j]))
          return system->FailStep(self->last_not_assemblable_ ? Status::kDeadPoint : Status::kPositionFailed,
                                  "the positions or the inertia did not evaluate at a collocation node");
      }
      if (!self->CollocationStep(tb - ta, n, &S, &Sd))
        return system->FailStep(Status::kIntegratorFailed, "the sensitivities' collocation step is not finite");
      sample->qdd = n[kNodes - 1].qdd;
      sample->S = S;
      sample->Sd = Sd;
      return true;
    }
  };

  /// The staggered method: the state's run by the event loop (StaggeredSystem), the
  /// collocation over each accepted step.
  template <class Observer>
  bool SimulateStaggered(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Observer& observer,
                         SensitivitySummary* summary) {
    Collocate collocate(this);
    collocate.S = internal::ZeroOf<MatQP>(nq_, np_);
    collocate.Sd = collocate.S;
    if (!Partials(t0, q0, qd0, true, &collocate.n[kNodes - 1])) {  // (the first step's first node)
      summary->t_end = t0;
      summary->status = last_not_assemblable_ ? Status::kDeadPoint : Status::kPositionFailed;
      summary->message = "the positions or the inertia did not evaluate at the initial state";
      summary->position_failures = position_failures_;
      summary->partial_evaluations = partial_evaluations_;
      return false;
    }
    internal::StaggeredSystem<TrajectorySensitivity, Collocate> system(this, t0, StateOf(q0, qd0), collocate);
    collocate.system = &system;
    return RunSystem(&system, t0, StateOf(q0, qd0), t_end, true, observer, summary);
  }

  /// The whole state (q, qd, S, Sd) through Method<kN> (kSimultaneous) by the event loop
  /// (SimultaneousSystem).
  template <class Observer>
  bool SimulateSimultaneous(double t0, const VecQ& q0, const VecQ& qd0, double t_end, Observer& observer,
                            SensitivitySummary* summary) {
    State y0 = State::Zero();
    y0.template head<kNq>() = q0;
    y0.template segment<kNq>(kNq) = qd0;
    internal::SimultaneousSystem<TrajectorySensitivity> system(this);
    return RunSystem(&system, t0, y0, t_end, false, observer, summary);
  }

  /// (q, qd) as the staggered method's state.
  StateX StateOf(const VecQ& q, const VecQ& qd) const {
    StateX x;
    if constexpr (kView) x.resize(2 * nq_);
    x.template head<kNq>(nq_) = q;  // (not the comma initializer: GCC 12 -Warray-bounds on 1 x 1)
    x.template segment<kNq>(nq_, nq_) = qd;
    return x;
  }

  template <class C>
  static auto PhiPhi(const C& c) {
    if constexpr (kNphi != 0) {  // (the view's: its size at run time, 0 x 0 without loops)
      return c.Phi_phi;
    } else {
      (void)c;
      return Eigen::Matrix<double, 0, 0>();
    }
  }

  /// The positions and coefficients at q from the predictor of the last accepted state.
  bool Configuration(const VecQ& q, VecPhi* phi, Coefficients* c) {
    *phi = tracker_.Predictor(q);
    bool not_assemblable = false;
    if (!tracker_.SolveAt(model_, p_, q, phi, &not_assemblable)) {
      last_not_assemblable_ = not_assemblable;
      ++position_failures_;
      return false;
    }
    last_not_assemblable_ = false;
    internal::CallCoeffs(model_, p_, q, *phi, c, tracker_.trig());
    return true;
  }

  /// A run starts at Initialize()'s configuration, its counts at zero.
  void BeginRun() {
    position_failures_ = 0;
    partial_evaluations_ = 0;
    last_not_assemblable_ = false;
    anchor_valid_ = false;
    tracker_.SetReference(initial_.q, initial_.phi, initial_.K, initial_.det);
  }

  /// The predictor's reference at an evaluated configuration (the adjoint's backward run).
  void Reanchor(const Partial& n) {
    anchor_valid_ = false;
    tracker_.SetReference(n.q, n.phi, n.K);
  }

  /// Makes the accepted configuration (q, phi, c; its 1/cond and det Phi_phi) the predictor's
  /// reference, read by Partials() there.
  void SetAnchor(const VecQ& q, const VecPhi& phi, const Coefficients& c, double rcond, double det) {
    tracker_.SetReference(q, phi, c.K, det);
    Calls::CopyCoefficients(model_, c, &anchor_c_);
    anchor_trig_ = *tracker_.trig();
    anchor_rcond_ = rcond;
    anchor_valid_ = true;
  }

  /// The state's sample at (t, q, qd) (S and Sd left as they are): its positions from the
  /// predictor, qdd, 1/cond and det Phi_phi. \return false where they do not evaluate.
  bool StateSample(double t, const VecQ& q, const VecQ& qd, SampleT* sample) {
    Coefficients c;
    if (!Configuration(q, &sample->phi, &c)) return false;
    Dyn d;
    internal::CallDynamics(model_, p_, q, sample->phi, qd, t, c, &d, tracker_.trig());
    if (!SolveInertia(d.I, VecQ(d.Q - d.h), &sample->qdd, nullptr)) return false;
    sample->t = t;
    sample->q = q;
    sample->qd = qd;
    internal::ConditioningOf(PhiPhi(c), &sample->rcond, &sample->det);
    return true;
  }

  /// The simultaneous method's sample at (t, y): qdd from the derivative, the positions and
  /// their conditioning, S and Sd read from y. \return false where they do not evaluate.
  bool FullSample(double t, const State& y, SampleT* sample) {
    State dy;
    if (!Derivative(t, y, &dy)) return false;
    sample->t = t;
    sample->q = y.template head<kNq>();
    sample->qd = y.template segment<kNq>(kNq);
    sample->qdd = dy.template segment<kNq>(kNq);
    Coefficients c;
    if (!Configuration(sample->q, &sample->phi, &c)) return false;
    internal::ConditioningOf(PhiPhi(c), &sample->rcond, &sample->det);
    sample->S = Eigen::Map<const MatQP>(y.data() + 2 * kNq);
    sample->Sd = Eigen::Map<const MatQP>(y.data() + 2 * kNq + kNq * kNp);
    return true;
  }

  struct Reference {
    VecQ q;
    VecPhi phi;
    MatK K;
    double det = 0;
  };

  static typename internal::JetOf<M>::Params JetParams(const Params& params) {
    if constexpr (kView) {
      (void)params;
      return {};
    } else {
      return params.template Cast<Jet>();
    }
  }
  static bool ReadStateByRhs(const M& model) {
    if constexpr (kView) {
      return Calls::HasSolveTrig(model) && Calls::HasRhs(model) && Calls::HasTrig(model) && Calls::Nphi(model) > 0;
    } else {
      (void)model;
      return kStateByRhs;
    }
  }
  static bool ReadHasDesignProduct(const M& model) {
    if constexpr (kView) {
      return Calls::HasDynamicsDesignProduct(model);
    } else {
      (void)model;
      return kHasDesignProduct;
    }
  }

  M model_;
  Params p_;
  typename internal::JetOf<M>::Params pj_;
  SensitivityOptions options_;
  Integrator integrator_;
  StateIntegrator state_integrator_;
  Collocation lob_;
  Tracker tracker_;  ///< the predictor's reference (q_ref, phi_ref, K_ref), branch, modes, sin and cos
  int nq_;           ///< kNq (the view's)
  int np_;           ///< kNp (the view's)
  bool state_by_rhs_;
  bool has_design_product_;
  Reference initial_;                                ///< Initialize()'s configuration: each run starts from it
  internal::PreparedRhsConstants<M> rhs_constants_;  ///< kStateByRhs: M::Prepare(p_)
  /// Anchor()'s configuration at q_ref_ (its coefficients and 1/cond), read by Partials() there.
  Coefficients anchor_c_{};
  Trig anchor_trig_{};
  double anchor_rcond_ = 1;
  bool anchor_valid_ = false;
  bool initialized_ = false;
  bool last_not_assemblable_ = false;
  int position_failures_ = 0;
  int partial_evaluations_ = 0;
};

}  // namespace mechgen::dynamics
