/**
 * \file position/design.h
 * Design sensitivities at a configuration (issue 27): the generated EvalDesignDerivatives
 * (M::Design) of a model with a `design` section gives d/dp of phi, K, L and the points for
 * its design parameters M::kDesignNames. Here: the type the runtime holds them in (an empty
 * struct for a model without a design section; for the model view its buffer with a map per
 * member, core/view_model.h), a NaN-filled value for a step that failed, and the evaluation at
 * a valid State through ModelCalls<M>::Design (the same conditioning the values were accepted at:
 * near a singular configuration the derivatives grow like 1/sigma_min(Phi_phi), as K does, and
 * a step the solver refused holds NaN, not a huge number).
 */
#pragma once

#include <limits>
#include <type_traits>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/position/state.h"

namespace mechgen::position {

/// M::DesignDerivativesT<double>, or an empty struct without a design section; for a
/// ViewModel internal::ViewDesignDerivatives (core/view_model.h: the view's buffer, each
/// member a map of it, placed on the view's layout by SetNanDesign or EvalDesign).
template <class M>
using DesignOf = typename internal::DesignDerivativesOf<M>::type;

/// Every member NaN (a step that failed, or one where they were not asked for); for a
/// ViewModel an empty value (SetNanDesign sizes it).
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

/// *d = every member NaN at the model's sizes (NanDesign; a view's placed on its layout).
template <class M>
void SetNanDesign(const M& model, DesignOf<M>* d) {
  if constexpr (ModelCalls<M>::kView) {
    ModelCalls<M>::SetNaN(model, d);
  } else {
    (void)model;
    *d = NanDesign<M>();
  }
}

/// The design derivatives at a valid state (state.valid), else NaN. Allocation-free.
template <class M>
void EvalDesign(const M& model, const typename ModelTypes<M>::Params& p, const State<M>& state, DesignOf<M>* out) {
  using C = ModelCalls<M>;
  if constexpr (HasDesignDerivatives<M>::value) {
    if (state.valid && C::HasDesign(model)) {
      C::Design(model, p, state.q, state.phi, out);
      return;
    }
  }
  SetNanDesign<M>(model, out);
}
/// EvalDesign of a generated model M (its empty tag).
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
void EvalDesign(const typename ModelTypes<M>::Params& p, const State<M>& state, DesignOf<M>* out) {
  EvalDesign<M>(M(), p, state, out);
}

}  // namespace mechgen::position
