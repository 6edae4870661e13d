// mechgen_view flywheel MODEL.so [flywheel options]: the flywheel command through the model
// view, the same RunFlywheel (flywheel_run.h) as every <model>_flywheel, instantiated for the
// view (the cycle's sampling and the simulated check compiled once:
// mechgen/machines/view_machines.h).
#include "mechgen/core/view_runtime.h"
#include "mechgen/machines/view_machines.h"
#include "flywheel_args.h"
#include "flywheel_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Flywheel(const ModelView& view, int argc, char** argv) {
  flywheel_tool::Arguments arguments;
  const int parsed =
      flywheel_tool::ParseArguments(argc, argv, view.name, flywheel_tool::kMaxCheckSamples, &arguments);
  if (parsed >= 0) return parsed;
  return flywheel_tool::RunFlywheel(ViewModel(view), arguments);
}

}  // namespace view_tool
}  // namespace mechgen
