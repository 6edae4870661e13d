// mechgen_view engine MODEL.so [engine options]: the engine command through the model view, the
// same engine analyses (mechgen/analysis/engine.h) as every <model>_engine, instantiated once
// for the view in mechgen_runtime_view (analysis/view_analysis.h; its cycle and simulations:
// mechgen/machines/view_machines.h).
#include "mechgen/analysis/view_analysis.h"
#include "engine_args.h"
#include "engine_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Engine(const ModelView& view, int argc, char** argv) {
  engine_tool::Arguments arguments;
  const int parsed = engine_tool::ParseArguments(argc, argv, view.name, view.flags.kHasDesignDerivatives, &arguments);
  if (parsed >= 0) return parsed;
  return analysis::Run(ViewModel(view), arguments, engine_tool::Outputs(arguments));
}

}  // namespace view_tool
}  // namespace mechgen
