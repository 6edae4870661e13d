// mechgen_view statics MODEL.so [statics options]: the statics command through the model view,
// the same statics analysis (mechgen/analysis/statics.h) as every <model>_statics, instantiated
// once for the view in mechgen_runtime_view (analysis/view_analysis.h).
#include <functional>

#include "mechgen/analysis/view_analysis.h"
#include "statics_args.h"
#include "statics_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Statics(const ModelView& view, int argc, char** argv) {
  statics_tool::Arguments arguments;
  const int parsed = statics_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  statics_tool::Command command(arguments);
  return command([&view, &arguments](const analysis::StaticsOutputs& outputs, const std::function<int()>& prepare,
                                     analysis::StaticsPlotFacts* facts) {
    return analysis::Run(ViewModel(view), arguments, outputs, prepare, facts);
  });
}

}  // namespace view_tool
}  // namespace mechgen
