/**
 * \file position/assembler.h
 * Assembly from a poor guess: the Assembler policy of PositionSolver<M, Assembler>, and
 * NewtonAssembler, the one that needs nothing but Eigen.
 *
 * An Assembler minimizes 1/2 ||Phi(q, phi)||_2^2 over phi at fixed q from a guess that may be
 * far from closing (PositionSolver::Assemble(), and the fallback of a continuation step whose
 * smallest sub-step failed). It decides kNotAssemblable: a stationary point with a residual
 * above tolerance means the loop cannot close at q. The solver then polishes the result with
 * its own Newton–Raphson, so an Assembler only has to get into Newton's basin.
 *
 * The policy is one static function template:
 *   template <class M>
 *   static AssemblyResult Minimize(const M& model, const Params& params, const VecQ& q,
 *                                  VecPhi* phi, int max_iterations);
 * (model: the solver's, core/model_calls.h; an empty tag for a generated M, a ViewModel for
 * the runtime instantiated for the view.)
 * Two are provided:
 *  - NewtonAssembler (this file, the default): Levenberg–Marquardt on the generated analytic
 *    Phi_phi with fixed-size Eigen (Newton steps damped by mu diag(J^T J)); no allocation,
 *    no Ceres. The continuation, the sweeps and the output never need more.
 *  - CeresAssembler (position/ceres_adapter.h): the same minimization by Ceres
 *    (ceres::Problem, DENSE_QR); allocates. The <model>_sweep tools and the tests that pin
 *    today's iteration counts use it (CeresPositionSolver<M>).
 * The two minimizers stop at points a few ulp apart, and PositionSolver's Newton polish after
 * them is not a fixed point to the bit: where it does not reach the same bits from both (the
 * coupled block of stephenson_coupled), every configuration of a sweep from that assembly
 * differs in its last bits, within a few eps cond(Phi_phi) (view_solver_test.cc).
 * A policy type rather than a compile-time switch on whether <ceres/ceres.h> is present: the
 * choice is visible in the solver's type, and two translation units that see different
 * include paths cannot give one name two meanings (an ODR violation).
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"

namespace mechgen::position {

/// Outcome of an Assembler's Minimize().
struct AssemblyResult {
  /// Stopped on a convergence criterion: a stationary point of 1/2 ||Phi||^2 (which may
  /// close the loop or not), not on the iteration limit or a failed evaluation.
  bool stationary = false;
  /// Iterations (accepted and rejected steps).
  int iterations = 0;
  /// ||Phi(q, phi)||_inf at the result.
  double residual_norm = std::numeric_limits<double>::quiet_NaN();
};

/// Levenberg–Marquardt with fixed-size Eigen on the generated Phi and Phi_phi: the Ceres-free
/// Assembler. Stationary (as Ceres' CONVERGENCE with the tolerances of
/// LevenbergMarquardtOptions()) when the relative decrease of the cost is below 1e-12, the
/// gradient's max-norm below 1e-14, or the step below 1e-14 (|phi| + 1e-14).
struct NewtonAssembler {
  template <class M>
  static AssemblyResult Minimize(const M& model, const typename ModelTypes<M>::Params& params,
                                 const typename ModelTypes<M>::VecQ& q,
                                 typename ModelTypes<M>::VecPhi* phi,
                                 int max_iterations) {
    using T = ModelTypes<M>;
    using Calls = ModelCalls<M>;
    using MatA = typename T::MatCPhi;  // kNphi x kNphi
    AssemblyResult result;
    typename T::VecC Phi;
    typename T::MatCPhi J;
    auto cost_at = [&](const typename T::VecPhi& x, typename T::MatCPhi* jacobian) {
      Calls::Phi(model, params, q, x, &Phi, jacobian, nullptr);
      const double c = 0.5 * Phi.squaredNorm();
      return std::isfinite(c) ? c : std::numeric_limits<double>::infinity();
    };
    double cost = cost_at(*phi, &J);
    double mu = 1e-4;  // Ceres' default: 1 / initial_trust_region_radius
    double nu = 2;
    bool need_jacobian = false;
    for (int it = 0; it < max_iterations && std::isfinite(cost); ++it) {
      if (need_jacobian) cost_at(*phi, &J);
      need_jacobian = false;
      const typename T::VecPhi gradient = J.transpose() * Phi;
      if (cost == 0 || gradient.template lpNorm<Eigen::Infinity>() <= 1e-14) {
        result.stationary = true;
        break;
      }
      ++result.iterations;
      const MatA JtJ = J.transpose() * J;
      MatA damped = JtJ;
      for (int i = 0; i < Calls::Nphi(model); ++i) {
        damped(i, i) += mu * std::min(std::max(JtJ(i, i), 1e-6), 1e32);
      }
      // (The view: PartialPivLU of the fixed size of its size, as a generated model's: the
      // same step to the bit, mechgen::internal::SolvePartialPivLU.)
      const typename T::VecPhi step = -mechgen::internal::SolvePartialPivLU(damped, gradient);
      if (!step.allFinite()) break;
      if (step.norm() <= 1e-14 * (phi->norm() + 1e-14)) {
        result.stationary = true;
        break;
      }
      const typename T::VecPhi candidate = *phi + step;
      typename T::VecC Phi_old = Phi;
      const double new_cost = cost_at(candidate, nullptr);
      // Gain ratio: actual over predicted decrease of the linearized model.
      const double predicted = -(step.dot(gradient) + 0.5 * (J * step).squaredNorm());
      const double rho = predicted > 0 ? (cost - new_cost) / predicted : -1;
      if (new_cost < cost && rho > 0) {
        const double decrease = cost - new_cost;
        *phi = candidate;
        cost = new_cost;
        need_jacobian = true;
        mu *= std::max(1.0 / 3.0, 1 - std::pow(2 * rho - 1, 3));
        nu = 2;
        if (decrease <= 1e-12 * (cost + decrease)) {
          result.stationary = true;
          break;
        }
      } else {
        Phi = Phi_old;
        mu *= nu;
        nu *= 2;
        if (mu > 1e32) {
          result.stationary = true;
          break;
        }
      }
    }
    Calls::Phi(model, params, q, *phi, &Phi, nullptr, nullptr);
    result.residual_norm = Phi.template lpNorm<Eigen::Infinity>();
    return result;
  }
};

}  // namespace mechgen::position
