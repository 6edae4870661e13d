// mechgen_view engine MODEL.so [engine options]: the engine command through the model view, the
// same RunEngine (engine_run.h) as every <model>_engine, instantiated for the view (its cycle
// and simulations compiled once: mechgen/machines/view_machines.h).
#include "mechgen/core/view_runtime.h"
#include "mechgen/machines/view_machines.h"
#include "engine_args.h"
#include "engine_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Engine(const ModelView& view, int argc, char** argv) {
  engine_tool::Arguments arguments;
  const int parsed = engine_tool::ParseArguments(argc, argv, view.name, view.flags.kHasDesignDerivatives, &arguments);
  if (parsed >= 0) return parsed;
  return engine_tool::RunEngine(ViewModel(view), arguments);
}

}  // namespace view_tool
}  // namespace mechgen
