// The analyses (mechgen/analysis/) instantiated for the model view: declared in
// mechgen/analysis/view_analysis.h.
#include "mechgen/analysis/view_analysis.h"

namespace mechgen::analysis {

template std::string Check<ViewModel>(const ViewModel&, const SweepRequest&);
template int Run<ViewModel, position::NewtonAssembler>(const ViewModel&, const SweepRequest&, const SweepOutputs&);
template std::string Check<ViewModel>(const ViewModel&, const StaticsRequest&);
template int Run<ViewModel, position::NewtonAssembler>(const ViewModel&, const StaticsRequest&, const StaticsOutputs&,
                                                       const std::function<int()>&, StaticsPlotFacts*);
template std::string Check<ViewModel>(const ViewModel&, const EngineRequest&);
template int Run<ViewModel>(const ViewModel&, const EngineRequest&, const EngineOutputs&);
template std::string Check<ViewModel>(const ViewModel&, const FlywheelRequest&);
template int Run<ViewModel>(const ViewModel&, const FlywheelRequest&, const FlywheelOutputs&, const std::function<int()>&,
                            FlywheelResult*);

}  // namespace mechgen::analysis
