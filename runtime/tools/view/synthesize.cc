// mechgen_view synthesize MODEL.so [synthesize options]: the synthesize command through the
// model view, the same RunSynthesize (synthesize_run.h) as every <model>_synthesize,
// instantiated for the view; the synthesis layer's part that reads the model comes from
// mechgen_runtime_view_synthesis (synthesis/view_synthesis.h).
#include <string>

#include "mechgen/core/view_runtime.h"
#include "mechgen/synthesis/view_synthesis.h"
#include "synthesize_args.h"
#include "synthesize_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Synthesize(const ModelView& view, int argc, char** argv) {
  synthesize_tool::Arguments arguments;
  const int parsed = synthesize_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  return synthesize_tool::RunSynthesize(ViewModel(view), arguments, argc > 0 ? argv[0] : "");
}

}  // namespace view_tool
}  // namespace mechgen
