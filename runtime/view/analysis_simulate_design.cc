// The trajectory sensitivities (mechgen/analysis/simulate_design.h, dynamics/sensitivity.h)
// instantiated for the model view: simulate --design and the study's first order of a
// simulation metric, declared in mechgen/analysis/view_analysis.h (their own translation unit,
// the one that compiles TrajectorySensitivity<ViewModel>, apart from analysis_simulate.cc's and
// analysis_study.cc's, so that they compile in parallel).
#include "mechgen/analysis/view_analysis.h"

#if MECHGEN_SIMULATE_HAS_SENSITIVITY
namespace mechgen::analysis::simulate_internal {

template int RunDesign<ViewModel, dynamics::Dop853>(const ViewModel&,
                                                    const SimulateRequest&,
                                                    const SimulateOutputs&,
                                                    const Prepared<ViewModel>&);
template int RunDesign<ViewModel, dynamics::Dopri5>(const ViewModel&,
                                                    const SimulateRequest&,
                                                    const SimulateOutputs&,
                                                    const Prepared<ViewModel>&);
template bool SensitivitySamples<ViewModel, dynamics::Dopri5>(const ViewModel&,
                                                              const ModelTypes<ViewModel>::Params&,
                                                              const ModelTypes<ViewModel>::VecQ&,
                                                              const ModelTypes<ViewModel>::VecQ&,
                                                              double,
                                                              const dynamics::SensitivityOptions&,
                                                              std::vector<dynamics::SensitivitySample<ViewModel>>*,
                                                              std::string*);

}  // namespace mechgen::analysis::simulate_internal
#endif
