/**
 * \file machines/flywheel/cycle_design.h
 * Design sensitivities of a machine's cycle (issue 27): the derivatives of what flywheel
 * sizing gives (machine_cycle.h) — the mean driving torque T_mean, the energy loop's E_max,
 * E_min and ΔE, the machine's mean inertia and the flywheel for a C_s — with respect to the
 * model's design parameters (its `design` section, M::kDesignNames).
 *
 * At each sample of the cycle (the same positions, continued from the assembly as
 * SampleMachineCycle does) the generated design derivatives give dT_req/dp:
 *  - with `dynamics`: T_req = h(θ, ω_m) − Q(θ, ω_m) (the statics part −Q_static and the speed
 *    part Q_static − Q add up to −Q), so dT_req/dp = dh/dp − dQ/dp and dI/dp from
 *    EvalDynamicsDesign (M::DynamicsDesign) at θ̇ = ω_m;
 *  - without: T_req = the statics drive, d drive/dp from EvalStaticsDesign (M::StaticsDesign).
 * The energy loop is linear in the samples and its extremes are stationary points of their
 * interpolant, so its derivatives are exact for the computed figures (energy_loop.h,
 * ExcessEnergyDerivative): dT_mean/dp, dE_max/dp, dE_min/dp, dΔE/dp; then
 * dI_required/dp = (dΔE/dp)/(C_s ω_m²) and dI_flywheel/dp = dI_required/dp − d mean I/dp.
 * The loop's breaks (the cycle's: given and the located switches of the loads) are held at
 * their angles: where T_req jumps at a switch whose angle moves with p, the term
 * (T_req⁻ − T_req⁺) dθ_b/dp is not in the derivatives (it is 0 at a kink).
 *
 * Not differentiated (a status): Coulomb friction (the friction iteration's derivative is not
 * generated: EvalStaticsDesign holds the friction loads fixed). A sample where the positions
 * fail, or a dead point, ends it with the cycle's own status. Allocates (vectors per sample);
 * nothing throws.
 */
#pragma once

#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "mechgen/core/model_traits.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/machines/flywheel/machine_cycle.h"

namespace mechgen::flywheel {

namespace internal {
/// M::kNumDesign, or 0 for a model without a design section.
template <class M, bool = HasDesignDerivatives<M>::value>
struct NumDesign : std::integral_constant<int, 0> {};
template <class M>
struct NumDesign<M, true> : std::integral_constant<int, M::kNumDesign> {};
}  // namespace internal

/// The derivatives of a MachineCycle with respect to the design parameters.
template <class M>
struct CycleDesign {
  static constexpr int kNp = internal::NumDesign<M>::value;
  using VecP = Eigen::Matrix<double, kNp, 1>;
  CycleStatus status = CycleStatus::kBadOptions;
  std::string message;  ///< why it is not usable ("" when it is)
  std::vector<VecP> dT_req_dp;  ///< per sample: dT_req/dp_d (N m per unit of p_d)
  std::vector<VecP> dI_dp;      ///< per sample: dI/dp_d (kg m² per unit of p_d; 0 without `dynamics`)
  VecP dT_mean_dp = VecP::Zero();   ///< N m per unit of p_d
  VecP dE_max_dp = VecP::Zero();    ///< J per unit of p_d
  VecP dE_min_dp = VecP::Zero();
  VecP ddelta_E_dp = VecP::Zero();
  VecP dI_mean_dp = VecP::Zero();   ///< kg m² per unit of p_d
  bool IsUsable() const { return status == CycleStatus::kOk; }
};

/// The flywheel's derivatives for a C_s (kg m² per unit of p_d).
template <class M>
struct FlywheelSizeDesign {
  typename CycleDesign<M>::VecP dI_required_dp, dI_flywheel_dp;
};

/**
 * \brief The design derivatives of `cycle` (SampleMachineCycle(p, o), usable) with respect to
 * M::kDesignNames. A model without a design section, or with Coulomb friction, gets a status.
 */
template <class M>
CycleDesign<M> SampleMachineCycleDesign(const typename M::template ParamsT<double>& p, const MachineCycleOptions& o,
                                        const MachineCycle& cycle) {
  CycleDesign<M> out;
  if (!cycle.IsUsable()) {
    out.status = cycle.status;
    out.message = "the cycle itself is not usable: " + cycle.message;
    return out;
  }
  if constexpr (!HasDesignDerivatives<M>::value || M::kNq != 1 || !statics::StaticsFeatures<M>::kHasStatics) {
    (void)p, (void)o;
    out.status = CycleStatus::kBadOptions;
    out.message = "the model has no design section (the parameters to differentiate by)";
    return out;
  } else if constexpr (statics::StaticsFeatures<M>::kHasFriction) {
    (void)p, (void)o;
    out.status = CycleStatus::kBadOptions;
    out.message = "Coulomb friction: the derivative of the friction iteration is not generated";
    return out;
  } else {
    constexpr int kNp = M::kNumDesign;
    using VecQ = typename ModelTypes<M>::VecQ;
    using VecP = typename CycleDesign<M>::VecP;
    const int n = static_cast<int>(cycle.points.size());
    const double h_theta = cycle.cycle / n;
    position::PositionSolver<M> solver(position::Options(), p);
    position::Summary assembly;
    if (solver.AssembleDefault(&assembly) != position::Status::kConverged) {
      out.status = CycleStatus::kNotAssembled;
      out.message = position::FormatSummary(assembly);
      return out;
    }
    out.dT_req_dp.assign(static_cast<size_t>(n), VecP::Zero());
    out.dI_dp.assign(static_cast<size_t>(n), VecP::Zero());
    VecQ q_begin, q_end, qd, qdd;
    q_begin(0) = cycle.theta0;
    q_end(0) = cycle.theta0 + cycle.cycle;
    qd(0) = cycle.omega;
    qdd(0) = 0;
    bool failed = false;
    SweepRows(&solver, q_begin, q_end, n, qd, qdd, SweepOptions(), [&](int k, const SweepRecord<M>& r) {
      if (failed || k >= n) return;
      if (r.summary.status != position::Status::kConverged || !r.state.valid) {
        failed = true;
        out.status = CycleStatus::kPositionFailed;
        out.message = "the positions failed at " + internal::Degrees(cycle.theta0 + k * h_theta);
        return;
      }
      typename ModelTypes<M>::Coefficients c;
      M::template Coeffs<double>(p, r.state.q, r.state.phi, &c);
      typename M::template DesignDerivativesT<double> dc;
      M::template Design<double>(p, r.state.q, r.state.phi, &dc);
      if constexpr (HasDynamicsDesign<M>::value) {
        typename M::template DynamicsDesignT<double> dd;
        M::template DynamicsDesign<double>(p, r.state.q, r.state.phi, qd, 0.0, c, dc, &dd);
        out.dT_req_dp[static_cast<size_t>(k)] = (dd.dh_dp.row(0) - dd.dQ_dp.row(0)).transpose();
        out.dI_dp[static_cast<size_t>(k)] = dd.dI_dp.row(0).transpose();
      } else {
        typename M::template StaticsDesignT<double> sd;
        M::template StaticsDesign<double>(p, r.state.q, r.state.phi, c, dc, &sd);
        out.dT_req_dp[static_cast<size_t>(k)] = sd.ddrive_dp.row(0).transpose();
      }
      if (!out.dT_req_dp[static_cast<size_t>(k)].allFinite() || !out.dI_dp[static_cast<size_t>(k)].allFinite()) {
        failed = true;
        out.status = CycleStatus::kNotFinite;
        out.message = "a derivative is not finite at " + internal::Degrees(cycle.theta0 + k * h_theta);
      }
    });
    if (failed) return out;
    // The loop of -T_req (mean removed), as SampleMachineCycle integrates it, differentiated.
    EnergyLoopOptions loop_options;
    loop_options.remove_mean = true;
    loop_options.breaks = cycle.break_samples.data();
    loop_options.break_fractions = cycle.break_fractions.data();
    loop_options.break_sides = cycle.break_sides.data();
    loop_options.num_breaks = static_cast<int>(cycle.break_samples.size());
    std::vector<double> minus_dT(static_cast<size_t>(n)), dE(static_cast<size_t>(n));
    for (int d = 0; d < kNp; ++d) {
      double I_sum = 0;
      for (int k = 0; k < n; ++k) {
        minus_dT[static_cast<size_t>(k)] = -out.dT_req_dp[static_cast<size_t>(k)](d);
        I_sum += out.dI_dp[static_cast<size_t>(k)](d);
      }
      const EnergyLoopDerivative dl =
          ExcessEnergyDerivative(minus_dT.data(), cycle.loop, cycle.theta0, loop_options, dE.data());
      out.dT_mean_dp(d) = -dl.mean_torque;
      out.dE_max_dp(d) = dl.E_max;
      out.dE_min_dp(d) = dl.E_min;
      out.ddelta_E_dp(d) = dl.delta_E;
      out.dI_mean_dp(d) = I_sum / n;
    }
    out.status = CycleStatus::kOk;
    return out;
  }
}

/// The flywheel's derivatives for C_s (SizeFlywheel's figures, differentiated).
template <class M>
FlywheelSizeDesign<M> SizeFlywheelDesign(const MachineCycle& cycle, const CycleDesign<M>& design, double C_s) {
  FlywheelSizeDesign<M> f;
  f.dI_required_dp = design.ddelta_E_dp / (C_s * cycle.omega * cycle.omega);
  f.dI_flywheel_dp = f.dI_required_dp - design.dI_mean_dp;
  return f;
}

}  // namespace mechgen::flywheel
