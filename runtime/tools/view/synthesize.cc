// mechgen_view synthesize MODEL.so [synthesize options]: the synthesize command through the
// model view, the same synthesis analysis (mechgen/analysis/synthesize.h) as every
// <model>_synthesize, instantiated once for the view in mechgen_runtime_view_synthesis
// (runtime/view/synthesis.cc); declared by analysis/synthesize_view.h, so that this file reads
// none of the synthesis layer (Ceres, yaml-cpp).
#include "mechgen/analysis/synthesize_view.h"
#include "synthesize_args.h"
#include "synthesize_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Synthesize(const ModelView& view, int argc, char** argv) {
  synthesize_tool::Arguments arguments;
  const int parsed = synthesize_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  return analysis::Run(ViewModel(view), synthesize_tool::Request(arguments, argc > 0 ? argv[0] : ""),
                       synthesize_tool::Outputs(arguments));
}

}  // namespace view_tool
}  // namespace mechgen
