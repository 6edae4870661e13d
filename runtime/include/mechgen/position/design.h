/**
 * \file position/design.h
 * Design sensitivities at a configuration (issue 27): the generated EvalDesignDerivatives
 * (M::Design) of a model with a `design` section gives d/dp of phi, K, L and the points for
 * its design parameters M::kDesignNames. Here: the type the runtime holds them in (an empty
 * struct for a model without a design section), a NaN-filled value for a step that failed,
 * and the evaluation at a valid State (the same conditioning the values were accepted at:
 * near a singular configuration the derivatives grow like 1/sigma_min(Phi_phi), as K does, and
 * a step the solver refused holds NaN, not a huge number).
 */
#pragma once

#include <limits>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/position/state.h"

namespace mechgen::position {

/// M::DesignDerivativesT<double>, or an empty struct without a design section.
template <class M>
using DesignOf = typename internal::DesignDerivativesOf<M>::type;

/// Every member NaN (a step that failed, or one where they were not asked for).
template <class M>
DesignOf<M> NanDesign() {
  DesignOf<M> d;
  if constexpr (HasDesignDerivatives<M>::value && !ModelCalls<M>::kView) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    d.dphi_dp.setConstant(nan);
    if constexpr (M::kNumPoints > 0) d.dr_P_dp.setConstant(nan);
    if constexpr (M::kOrder >= 1) d.dK_dp.setConstant(nan);
    if constexpr (M::kOrder >= 1 && M::kNumPoints > 0) d.dK_P_dp.setConstant(nan);
    if constexpr (M::kOrder >= 2) d.dL_dp.setConstant(nan);
    if constexpr (M::kOrder >= 2 && M::kNumPoints > 0) d.dL_P_dp.setConstant(nan);
    if constexpr (M::kNumTransmissionAngles > 0) d.dmu_dp.setConstant(nan);
  }
  return d;
}

/// The design derivatives at a valid state (state.valid), else NaN. Allocation-free.
template <class M>
void EvalDesign(const typename ModelTypes<M>::Params& p, const State<M>& state, DesignOf<M>* out) {
  if constexpr (HasDesignDerivatives<M>::value && !ModelCalls<M>::kView) {
    if (state.valid) {
      M::Design(p, state.q, state.phi, out);
      return;
    }
  }
  *out = NanDesign<M>();
}

}  // namespace mechgen::position
