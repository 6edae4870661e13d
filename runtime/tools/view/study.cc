// mechgen_view study MODEL.so [study options]: the design study through the model view, the same
// study analysis (mechgen/analysis/study.h) as the per-model study program (study_main.cc),
// instantiated once for the view in mechgen_runtime_view (analysis/view_analysis.h). Under an MPI
// launcher it runs the ranks where the build found MPI (runtime/CMakeLists.txt:
// -DMECHGEN_STUDY_MPI here); built without it, it refuses such a run and `mechgen study` runs the
// per-model program, compiled with MPI (common/not_through_view.h).
#include "mechgen/analysis/view_analysis.h"
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
  return study_tool::RunCommand(ranks, arguments, view.name, true,
                                [&view](const analysis::StudyRequest& request, const analysis::StudyOutputs& outputs,
                                        const analysis::StudyRanks& on) {
                                  return analysis::Run(ViewModel(view), request, outputs, on);
                                });
}

}  // namespace view_tool
}  // namespace mechgen
