// mechgen_view simulate MODEL.so [simulate options]: the simulate command through the model
// view, the same RunSimulate (simulate_run.h) as every <model>_simulate, instantiated for the
// view.
#include "mechgen/core/view_runtime.h"
#include "simulate_args.h"
#include "simulate_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Simulate(const ModelView& view, int argc, char** argv) {
  simulate_tool::Arguments arguments;
  const int parsed = simulate_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  return simulate_tool::RunSimulate(ViewModel(view), arguments);
}

}  // namespace view_tool
}  // namespace mechgen
