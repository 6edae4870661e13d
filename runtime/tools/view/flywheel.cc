// mechgen_view flywheel MODEL.so [flywheel options]: the flywheel command through the model
// view, the same flywheel analysis (mechgen/analysis/flywheel.h) as every <model>_flywheel,
// instantiated once for the view in mechgen_runtime_view (analysis/view_analysis.h; the cycle's
// sampling and the simulated check: mechgen/machines/view_machines.h).
#include <functional>

#include "mechgen/analysis/view_analysis.h"
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
  flywheel_tool::Command command(arguments);
  return command([&view, &arguments](const analysis::FlywheelOutputs& outputs, const std::function<int()>& prepare,
                                     analysis::FlywheelResult* result) {
    return analysis::Run(ViewModel(view), arguments, outputs, prepare, result);
  });
}

}  // namespace view_tool
}  // namespace mechgen
