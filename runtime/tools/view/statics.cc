// mechgen_view statics MODEL.so [statics options]: the statics command through the model view,
// the same RunStatics (statics_run.h) as every <model>_statics, instantiated for the view.
#include "mechgen/core/view_runtime.h"
#include "statics_args.h"
#include "statics_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Statics(const ModelView& view, int argc, char** argv) {
  statics_tool::Arguments arguments;
  const int parsed = statics_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  return statics_tool::RunStatics(ViewModel(view), arguments);
}

}  // namespace view_tool
}  // namespace mechgen
