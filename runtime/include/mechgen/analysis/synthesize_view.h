/**
 * \file analysis/synthesize_view.h
 * The synthesis analysis (analysis/synthesize.h: Check, Run) for the model view, declared
 * without the synthesis layer's headers (Ceres, yaml-cpp, the solvers): a program that includes
 * this header and links mechgen_runtime_view_synthesis (runtime/view/synthesis.cc, where they
 * are instantiated; synthesis/view_synthesis.h) runs a synthesis on any model's view without
 * compiling, or even reading, the synthesis layer (mechgen_view synthesize,
 * tools/view/synthesize.cc).
 */
#pragma once

#include <string>

#include "mechgen/analysis/synthesize_request.h"
#include "mechgen/core/view_model.h"

namespace mechgen::analysis {

// (defined in analysis/synthesize.h)
template <class M>
std::string Check(const M& model, const SynthesizeRequest& request);
template <class M>
int Run(const M& model, const SynthesizeRequest& request, const SynthesizeOutputs& outputs);

extern template std::string Check<ViewModel>(const ViewModel&, const SynthesizeRequest&);
extern template int Run<ViewModel>(const ViewModel&, const SynthesizeRequest&, const SynthesizeOutputs&);

}  // namespace mechgen::analysis
