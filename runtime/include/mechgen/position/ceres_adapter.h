/**
 * \file position/ceres_adapter.h
 * The only runtime header that includes Ceres (link mechgen::runtime_ceres). Ceres views of
 * a generated model's loop-closure residual, used for assembly from a rough guess (and as
 * the fallback of the continuation's Newton corrector) by CeresAssembler, the Ceres
 * Assembler policy of PositionSolver (position/assembler.h); CeresPositionSolver<M> names
 * the solver that uses it.
 *
 * PhiCostFunction feeds Ceres the generated analytic Jacobian Phi_phi, not autodiff. Ceres
 * stores jacobians[0] row-major (jacobians[0][r * kNphi + c] = dPhi_r/dphi_c, see
 * include/ceres/cost_function.h) while Eigen and the generated code are column-major, so the
 * adapter maps it as Eigen::Matrix<double, kNc, kNphi, RowMajor> (tests/runtime covers this).
 * PhiAutoDiffFunctor is the same residual for ceres::AutoDiffCostFunction (through
 * Model::Phi with Jets); the runtime does not use it, the benchmark compares against it.
 * SolveLevenbergMarquardt() builds a ceres::Problem, so it allocates: never call it per step.
 */
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>

#include "mechgen/core/model_traits.h"
#include "mechgen/position/assembler.h"
#include "mechgen/position/solver.h"

namespace mechgen::position {

/// Residual Phi(q, phi) (kNc) over the parameter block phi (kNphi), with the analytic
/// Jacobian Phi_phi. q and the parameters are held by pointer, so one cost function can be
/// reused across the steps of a sweep by changing *q.
template <class M>
class PhiCostFunction : public ceres::SizedCostFunction<M::kNc, M::kNphi> {
 public:
  using T = ModelTypes<M>;
  /// \param[in] params  Model parameters; must outlive this object.
  /// \param[in] q       Inputs (dim kNq); must outlive this object, may change between solves.
  PhiCostFunction(const typename T::Params* params, const typename T::VecQ* q)
      : params_(params), q_(q) {}

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const typename T::VecPhi> phi(parameters[0]);
    typename T::VecC Phi;
    typename T::MatCPhi Phi_phi;
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    M::template Phi<double>(*params_, *q_, phi, &Phi, want_jacobian ? &Phi_phi : nullptr,
                            nullptr);
    Eigen::Map<typename T::VecC> residual_map(residuals);
    residual_map = Phi;
    if (want_jacobian) {
      // Eigen forbids a row-major matrix with one column; then both layouts coincide.
      constexpr int kLayout = M::kNphi == 1 ? Eigen::ColMajor : Eigen::RowMajor;
      Eigen::Map<Eigen::Matrix<double, M::kNc, M::kNphi, kLayout>> jacobian(jacobians[0]);
      jacobian = Phi_phi;
      if (!Phi_phi.allFinite()) return false;
    }
    return Phi.allFinite();
  }

 private:
  const typename T::Params* params_;
  const typename T::VecQ* q_;
};

/// Phi(q, phi) for ceres::AutoDiffCostFunction<PhiAutoDiffFunctor<M>, kNc, kNphi>.
template <class M>
struct PhiAutoDiffFunctor {
  using T = ModelTypes<M>;
  PhiAutoDiffFunctor(const typename T::Params* params, const typename T::VecQ* q)
      : params(params), q(q) {}

  template <typename S>
  bool operator()(const S* phi_in, S* residual) const {
    const typename M::template ParamsT<S> p = params->template Cast<S>();
    const Eigen::Matrix<S, M::kNq, 1> q_s = q->template cast<S>();
    const Eigen::Matrix<S, M::kNphi, 1> phi = Eigen::Map<const Eigen::Matrix<S, M::kNphi, 1>>(phi_in);
    Eigen::Matrix<S, M::kNc, 1> Phi;
    M::template Phi<S>(p, q_s, phi, &Phi, nullptr, nullptr);
    Eigen::Map<Eigen::Matrix<S, M::kNc, 1>> residual_map(residual);
    residual_map = Phi;
    return true;
  }

  const typename T::Params* params;
  const typename T::VecQ* q;
};

/// The Ceres options used for assembly: Levenberg–Marquardt, dense QR, silent, and
/// tolerances tight enough that a closing configuration is reached to ~ machine precision
/// (the Newton polish that follows then needs 0–1 iterations) while a loop that cannot
/// close stops at the stationary point of 1/2 ||Phi||^2 (relative cost change < 1e-12).
inline ceres::Solver::Options LevenbergMarquardtOptions(int max_iterations) {
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  options.num_threads = 1;
  return options;
}

/// Outcome of SolveLevenbergMarquardt(): stationary = Ceres stopped on a convergence
/// criterion (ceres::CONVERGENCE).
using LevenbergMarquardtResult = AssemblyResult;

/**
 * \brief Minimizes 1/2 ||Phi(q, phi)||^2 over phi with Ceres Levenberg–Marquardt and the
 *        analytic Jacobian. Allocates (builds a ceres::Problem).
 * \param[in]     params          Model parameters.
 * \param[in]     q               Inputs (dim kNq).
 * \param[in,out] phi             Guess in, minimizer out (dim kNphi).
 * \param[in]     max_iterations  Ceres max_num_iterations.
 */
template <class M>
LevenbergMarquardtResult SolveLevenbergMarquardt(const typename ModelTypes<M>::Params& params,
                                                 const typename ModelTypes<M>::VecQ& q,
                                                 typename ModelTypes<M>::VecPhi* phi,
                                                 int max_iterations) {
  LevenbergMarquardtResult result;
  ceres::Problem problem;
  problem.AddResidualBlock(new PhiCostFunction<M>(&params, &q), nullptr, phi->data());
  ceres::Solver::Summary summary;
  ceres::Solve(LevenbergMarquardtOptions(max_iterations), &problem, &summary);
  result.stationary = summary.termination_type == ceres::CONVERGENCE;
  result.iterations = static_cast<int>(summary.iterations.size());
  typename ModelTypes<M>::VecC Phi;
  M::template Phi<double>(params, q, *phi, &Phi, nullptr, nullptr);
  result.residual_norm = Phi.template lpNorm<Eigen::Infinity>();
  return result;
}

/// The Ceres Assembler policy of PositionSolver (position/assembler.h):
/// SolveLevenbergMarquardt(). Allocates; runs only for assembly and on the failure path.
struct CeresAssembler {
  template <class M>
  static AssemblyResult Minimize(const M&, const typename ModelTypes<M>::Params& params,
                                 const typename ModelTypes<M>::VecQ& q,
                                 typename ModelTypes<M>::VecPhi* phi,
                                 int max_iterations) {
    return SolveLevenbergMarquardt<M>(params, q, phi, max_iterations);
  }
};

/// The position solver whose assembly from a poor guess (and continuation fallback) is
/// Ceres Levenberg–Marquardt.
template <class M>
using CeresPositionSolver = PositionSolver<M, CeresAssembler>;

}  // namespace mechgen::position
