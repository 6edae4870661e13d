// mechgen_view simulate MODEL.so [simulate options]: the simulate command through the model
// view, the same simulation analysis (mechgen/analysis/simulate.h) as every <model>_simulate,
// instantiated once for the view in mechgen_runtime_view (analysis/view_analysis.h,
// runtime/view/analysis_simulate.cc).
#include "mechgen/analysis/view_analysis.h"
#include "simulate_args.h"
#include "simulate_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Simulate(const ModelView& view, int argc, char** argv) {
  simulate_tool::Arguments arguments;
  const int parsed = simulate_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  return analysis::Run(ViewModel(view), arguments, simulate_tool::Outputs(arguments));
}

}  // namespace view_tool
}  // namespace mechgen
