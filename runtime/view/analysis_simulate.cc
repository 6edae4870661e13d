// The simulation analysis (mechgen/analysis/simulate.h) instantiated for the model view:
// declared in mechgen/analysis/view_analysis.h (its own translation unit, apart from
// analysis.cc's, so that the two compile in parallel).
#include "mechgen/analysis/view_analysis.h"

namespace mechgen::analysis {

template std::string Check<ViewModel>(const ViewModel&, const SimulateRequest&);
template int Run<ViewModel>(const ViewModel&, const SimulateRequest&, const SimulateOutputs&);

}  // namespace mechgen::analysis
