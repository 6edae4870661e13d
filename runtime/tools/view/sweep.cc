// mechgen_view sweep MODEL.so [sweep options]: the sweep command through the model view, the
// same RunSweep (sweep_run.h) as every <model>_sweep, instantiated for the view.
#include "mechgen/core/view_runtime.h"
#include "sweep_args.h"
#include "sweep_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Sweep(const ModelView& view, int argc, char** argv) {
  sweep_tool::Arguments arguments;
  const int parsed = sweep_tool::ParseArguments(argc, argv, view.name, sweep_tool::kMaxSteps, &arguments);
  if (parsed >= 0) return parsed;
  return sweep_tool::RunSweep(ViewModel(view), arguments);
}

}  // namespace view_tool
}  // namespace mechgen
