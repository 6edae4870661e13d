/**
 * \file analysis/view_analysis.h
 * The analyses (analysis/sweep.h, statics.h, engine.h, flywheel.h, simulate.h, study.h) instantiated
 * once for the model view (issue 43), compiled into mechgen_runtime_view (runtime/view/analysis.cc,
 * analysis_simulate.cc, analysis_simulate_design.cc, analysis_study.cc; the synthesis in
 * mechgen_runtime_view_synthesis): a program that includes this header and links that library (mechgen_view's commands,
 * tools/view/<command>.cc) runs an analysis on any model's view without compiling it again; the `extern template`
 * declarations keep the instantiations out of its translation units. The same templates, instantiated for a generated
 * model's type, are the per-model tools' (tools/<tool>_main.cc).
 */
#pragma once

#include <string>

#include "mechgen/analysis/engine.h"
#include "mechgen/analysis/flywheel.h"
#include "mechgen/analysis/simulate.h"
#if MECHGEN_SIMULATE_HAS_SENSITIVITY
#include "mechgen/analysis/simulate_design.h"
#endif
#include "mechgen/analysis/statics.h"
#include "mechgen/analysis/sweep.h"
#include "mechgen/analysis/study.h"
#include "mechgen/core/view_runtime.h"
#include "mechgen/machines/view_machines.h"

namespace mechgen::analysis {

extern template std::string Check<ViewModel>(const ViewModel&, const SweepRequest&);
extern template int Run<ViewModel, position::NewtonAssembler>(const ViewModel&, const SweepRequest&,
                                                              const SweepOutputs&);
extern template std::string Check<ViewModel>(const ViewModel&, const StaticsRequest&);
extern template int Run<ViewModel, position::NewtonAssembler>(const ViewModel&, const StaticsRequest&,
                                                              const StaticsOutputs&, const std::function<int()>&,
                                                              StaticsPlotFacts*);
extern template std::string Check<ViewModel>(const ViewModel&, const EngineRequest&);
extern template int Run<ViewModel>(const ViewModel&, const EngineRequest&, const EngineOutputs&);
extern template std::string Check<ViewModel>(const ViewModel&, const FlywheelRequest&);
extern template int Run<ViewModel>(const ViewModel&, const FlywheelRequest&, const FlywheelOutputs&,
                                   const std::function<int()>&, FlywheelResult*);
extern template std::string Check<ViewModel>(const ViewModel&, const SimulateRequest&);
extern template int Run<ViewModel>(const ViewModel&, const SimulateRequest&, const SimulateOutputs&);
#if MECHGEN_SIMULATE_HAS_SENSITIVITY
// The trajectory sensitivities (simulate --design, the study's first order of a simulation
// metric): runtime/view/analysis_simulate_design.cc.
namespace simulate_internal {
extern template int RunDesign<ViewModel, dynamics::Dop853>(const ViewModel&,
                                                           const SimulateRequest&,
                                                           const SimulateOutputs&,
                                                           const Prepared<ViewModel>&);
extern template int RunDesign<ViewModel, dynamics::Dopri5>(const ViewModel&,
                                                           const SimulateRequest&,
                                                           const SimulateOutputs&,
                                                           const Prepared<ViewModel>&);
extern template bool SensitivitySamples<ViewModel, dynamics::Dopri5>(
    const ViewModel&,
    const ModelTypes<ViewModel>::Params&,
    const ModelTypes<ViewModel>::VecQ&,
    const ModelTypes<ViewModel>::VecQ&,
    double,
    const dynamics::SensitivityOptions&,
    std::vector<dynamics::SensitivitySample<ViewModel>>*,
    std::string*);
}  // namespace simulate_internal
#endif
extern template std::string Check<ViewModel>(const ViewModel&, const StudyRequest&, const StudyOutputs&);
extern template int Run<ViewModel>(const ViewModel&, const StudyRequest&, const StudyOutputs&, const StudyRanks&);

}  // namespace mechgen::analysis

// The whole study through the view, compiled once (runtime/view/analysis_study.cc).
extern template class mechgen::study::Study<mechgen::ViewModel>;
