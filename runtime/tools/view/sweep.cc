// mechgen_view sweep MODEL.so [sweep options]: the sweep command through the model view, the
// same sweep analysis (mechgen/analysis/sweep.h) as every <model>_sweep, instantiated once for
// the view in mechgen_runtime_view (analysis/view_analysis.h).
#include "mechgen/analysis/view_analysis.h"
#include "sweep_args.h"
#include "sweep_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Sweep(const ModelView& view, int argc, char** argv) {
  sweep_tool::Arguments arguments;
  const int parsed = sweep_tool::ParseArguments(argc, argv, view.name, sweep_tool::kMaxSteps, &arguments);
  if (parsed >= 0) return parsed;
  return analysis::Run(ViewModel(view), arguments, sweep_tool::Outputs(arguments));
}

}  // namespace view_tool
}  // namespace mechgen
