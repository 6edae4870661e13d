// mechgen_view study MODEL.so [study options]: the design study through the model view, the same
// RunStudy (study_run.h) as the per-model study program (study_main.cc), instantiated for the
// view. Under an MPI launcher it runs the ranks where the build found MPI (runtime/CMakeLists.txt:
// -DMECHGEN_STUDY_MPI here); built without it, it refuses such a run and `mechgen study` runs the
// per-model program, compiled with MPI (common/not_through_view.h).
#include "mechgen/core/view_runtime.h"
#include "mechgen/machines/view_machines.h"  // (before study_run.h: the machines compiled once)
#include "study_args.h"
#include "study_run.h"
#include "view/commands.h"

namespace mechgen {
namespace view_tool {

int Study(const ModelView& view, int argc, char** argv) {
  const study_tool::run_internal::Ranks ranks(&argc, &argv);  // (MPI_Init under a launcher, with MPI)
  study_tool::Arguments arguments;
  const int parsed = study_tool::ParseArguments(argc, argv, view.name, &arguments);
  if (parsed >= 0) return parsed;
  return study_tool::RunStudy(ViewModel(view), ranks, arguments);
}

}  // namespace view_tool
}  // namespace mechgen
