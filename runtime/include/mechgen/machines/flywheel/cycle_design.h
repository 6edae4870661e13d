/**
 * \file machines/flywheel/cycle_design.h
 * Design sensitivities of a machine's cycle (issue 27): the derivatives of what flywheel
 * sizing gives (machine_cycle.h) — the mean driving torque T_mean, the energy loop's E_max,
 * E_min and ΔE, the machine's mean inertia and the flywheel for a C_s — with respect to the
 * model's design parameters (its `design` section: ModelCalls<M>::DesignName). M is a generated
 * model (fixed sizes) or the model view (ViewModel: its sizes, design section and dynamics at
 * run time; compiled once, machines/view_machines.h): one source, every generated function
 * reached through ModelCalls<M>.
 *
 * At each sample of the cycle (the same positions, continued from the assembly as
 * SampleMachineCycle does) the generated design derivatives give dT_req/dp:
 *  - with `dynamics`: T_req = h(θ, ω_m) − Q(θ, ω_m) (the statics part −Q_static and the speed
 *    part Q_static − Q add up to −Q), so dT_req/dp = dh/dp − dQ/dp and dI/dp from
 *    EvalDynamicsDesign (ModelCalls<M>::DynamicsDesign) at θ̇ = ω_m;
 *  - without: T_req = the statics drive, d drive/dp from EvalStaticsDesign
 *    (ModelCalls<M>::StaticsDesign);
 * both from EvalDesignDerivatives (ModelCalls<M>::Design) at the sample.
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

#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/core/model_view.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/machines/flywheel/machine_cycle.h"
#include "mechgen/position/design.h"
#include "mechgen/statics/sweep.h"

namespace mechgen::flywheel {

namespace internal {
/// The design parameters' count at compile time and its bound: M::kNumDesign (0 for a model
/// without a design section); for the view Eigen::Dynamic, at most ModelView::kMaxDesign.
template <class M, bool = ModelCalls<M>::kView, bool = HasDesignDerivatives<M>::value>
struct NumDesign {
  static constexpr int value = 0, kMax = 0;
};
template <class M>
struct NumDesign<M, false, true> {
  static constexpr int value = M::kNumDesign, kMax = M::kNumDesign;
};
template <class M, bool kHas>
struct NumDesign<M, true, kHas> {
  static constexpr int value = Eigen::Dynamic, kMax = ModelView::kMaxDesign;
};
/// V::Zero() for a fixed-size V; an empty V for the view's (SampleMachineCycleDesign sizes it).
template <class V>
V ZeroVector() {
  if constexpr (V::SizeAtCompileTime != Eigen::Dynamic) {
    return V::Zero();
  } else {
    return V();
  }
}
inline constexpr const char* kNoDesignSection =
    "the model has no design section (the parameters to differentiate by)";
inline constexpr const char* kFrictionNotDifferentiated =
    "Coulomb friction: the derivative of the friction iteration is not generated";
}  // namespace internal

/// The derivatives of a MachineCycle with respect to the design parameters (vectors of
/// ModelCalls<M>::NumDesign entries where usable; a view's are empty otherwise).
template <class M>
struct CycleDesign {
  static constexpr int kNp = internal::NumDesign<M>::value;
  using VecP = Eigen::Matrix<double, kNp, 1, 0, internal::NumDesign<M>::kMax, 1>;
  CycleStatus status = CycleStatus::kBadOptions;
  std::string message;  ///< why it is not usable ("" when it is)
  std::vector<VecP> dT_req_dp;  ///< per sample: dT_req/dp_d (N m per unit of p_d)
  std::vector<VecP> dI_dp;      ///< per sample: dI/dp_d (kg m² per unit of p_d; 0 without `dynamics`)
  VecP dT_mean_dp = internal::ZeroVector<VecP>();  ///< N m per unit of p_d
  VecP dE_max_dp = internal::ZeroVector<VecP>();   ///< J per unit of p_d
  VecP dE_min_dp = internal::ZeroVector<VecP>();
  VecP ddelta_E_dp = internal::ZeroVector<VecP>();
  VecP dI_mean_dp = internal::ZeroVector<VecP>();  ///< kg m² per unit of p_d
  bool IsUsable() const { return status == CycleStatus::kOk; }
};

/// The flywheel's derivatives for a C_s (kg m² per unit of p_d).
template <class M>
struct FlywheelSizeDesign {
  typename CycleDesign<M>::VecP dI_required_dp, dI_flywheel_dp;
};

/**
 * \brief The design derivatives of `cycle` (SampleMachineCycle(model, p, o), usable) with
 * respect to the model's design parameters (ModelCalls<M>::DesignName). A model without a
 * design section, or with Coulomb friction, gets a status (a view's at run time).
 */
template <class M>
CycleDesign<M> SampleMachineCycleDesign(const M& model, const typename ModelTypes<M>::Params& p,
                                        const MachineCycleOptions& o, const MachineCycle& cycle) {
  using C = ModelCalls<M>;
  CycleDesign<M> out;
  if (!cycle.IsUsable()) {
    out.status = cycle.status;
    out.message = "the cycle itself is not usable: " + cycle.message;
    return out;
  }
  auto refuse = [&out](const char* why) {
    out.status = CycleStatus::kBadOptions;
    out.message = why;
    return out;
  };
  if constexpr (!HasDesignDerivatives<M>::value || (!C::kView && M::kNq != 1) ||
                !statics::StaticsFeatures<M>::kHasStatics) {
    (void)model, (void)p, (void)o;
    return refuse(internal::kNoDesignSection);
  } else if constexpr (!C::kView && statics::StaticsFeatures<M>::kHasFriction) {
    (void)model, (void)p, (void)o;
    return refuse(internal::kFrictionNotDifferentiated);
  } else {
    // (A view's, at run time: its design section, one input, statics and a design function of
    // its dynamics or statics; no friction.)
    if (!C::HasDesign(model) || C::Nq(model) != 1 || !C::HasStatics(model) ||
        (!C::HasDynamicsDesign(model) && !C::HasStaticsDesign(model)))
      return refuse(internal::kNoDesignSection);
    if (C::HasFriction(model)) return refuse(internal::kFrictionNotDifferentiated);
    const int np = C::NumDesign(model);
    using VecQ = typename ModelTypes<M>::VecQ;
    using VecP = typename CycleDesign<M>::VecP;
    const int n = static_cast<int>(cycle.points.size());
    const double h_theta = cycle.cycle / n;
    position::PositionSolver<M> solver(model, position::Options(), p);
    position::Summary assembly;
    if (solver.AssembleDefault(&assembly) != position::Status::kConverged) {
      out.status = CycleStatus::kNotAssembled;
      out.message = position::FormatSummary(assembly);
      return out;
    }
    out.dT_req_dp.assign(static_cast<size_t>(n), VecP::Zero(np));
    out.dI_dp.assign(static_cast<size_t>(n), VecP::Zero(np));
    const int nq = 1;
    auto q_begin = Sized<VecQ>(nq), q_end = Sized<VecQ>(nq), qd = Sized<VecQ>(nq), qdd = Sized<VecQ>(nq);
    q_begin(0) = cycle.theta0;
    q_end(0) = cycle.theta0 + cycle.cycle;
    qd(0) = cycle.omega;
    qdd(0) = 0;
    bool failed = false;
    auto row = [&](int k, const SweepRecord<M>& r) {
      if (failed || k >= n) return;
      if (r.summary.status != position::Status::kConverged || !r.state.valid) {
        failed = true;
        out.status = CycleStatus::kPositionFailed;
        out.message = "the positions failed at " + internal::Degrees(cycle.theta0 + k * h_theta);
        return;
      }
      typename ModelTypes<M>::Coefficients c;
      C::Coeffs(model, p, r.state.q, r.state.phi, &c);
      position::DesignOf<M> dc;
      C::Design(model, p, r.state.q, r.state.phi, &dc);
      bool by_dynamics = false;  // (with `dynamics`; else by the statics)
      if constexpr (HasDynamicsDesign<M>::value) {
        if (C::HasDynamicsDesign(model)) {
          by_dynamics = true;
          typename C::template DynamicsDesignOut<M> dd;
          C::DynamicsDesign(model, p, r.state.q, r.state.phi, qd, 0.0, c, dc, &dd);
          out.dT_req_dp[static_cast<size_t>(k)] = (dd.dh_dp.row(0) - dd.dQ_dp.row(0)).transpose();
          out.dI_dp[static_cast<size_t>(k)] = dd.dI_dp.row(0).transpose();
        }
      }
      if constexpr (C::kView || !HasDynamicsDesign<M>::value) {
        if (!by_dynamics) {
          statics::StaticsDesignOf<M> sd;
          C::StaticsDesign(model, p, r.state.q, r.state.phi, c, dc, &sd);
          out.dT_req_dp[static_cast<size_t>(k)] = sd.ddrive_dp.row(0).transpose();
        }
      }
      if (!out.dT_req_dp[static_cast<size_t>(k)].allFinite() || !out.dI_dp[static_cast<size_t>(k)].allFinite()) {
        failed = true;
        out.status = CycleStatus::kNotFinite;
        out.message = "a derivative is not finite at " + internal::Degrees(cycle.theta0 + k * h_theta);
      }
    };
    if constexpr (C::kView) {  // (the view's SweepRows, compiled once: a ViewRowFn)
      std::function<void(int, const SweepRecord<M>&)> fn = row;
      SweepRows(&solver, q_begin, q_end, n, qd, qdd, SweepOptions(), fn);
    } else {
      SweepRows(&solver, q_begin, q_end, n, qd, qdd, SweepOptions(), row);
    }
    if (failed) return out;
    // The loop of -T_req (mean removed), as SampleMachineCycle integrates it, differentiated.
    EnergyLoopOptions loop_options;
    loop_options.remove_mean = true;
    loop_options.breaks = cycle.break_samples.data();
    loop_options.break_fractions = cycle.break_fractions.data();
    loop_options.break_sides = cycle.break_sides.data();
    loop_options.num_breaks = static_cast<int>(cycle.break_samples.size());
    std::vector<double> minus_dT(static_cast<size_t>(n)), dE(static_cast<size_t>(n));
    out.dT_mean_dp.setZero(np);
    out.dE_max_dp.setZero(np);
    out.dE_min_dp.setZero(np);
    out.ddelta_E_dp.setZero(np);
    out.dI_mean_dp.setZero(np);
    for (int d = 0; d < np; ++d) {
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
/// The same for a generated model M (an empty tag).
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
CycleDesign<M> SampleMachineCycleDesign(const typename ModelTypes<M>::Params& p, const MachineCycleOptions& o,
                                        const MachineCycle& cycle) {
  return SampleMachineCycleDesign<M>(M(), p, o, cycle);
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
