// `mechgen study MODEL --study STUDY.yaml [--threads N] [--csv F] [--tolerance-csv F]`: a design
// study of one generated model (issue 29; the format: docs/studies.md), as a per-model program:
// compiled by generator/driver/tool_command.cc with -DMECHGEN_MODEL_INCLUDE and
// -DMECHGEN_MODEL_NAMESPACE, linked with yaml-cpp and threads (and with an MPI C++ compiler,
// -DMECHGEN_STUDY_MPI, where one is found). `mechgen study` runs the same study analysis
// (mechgen/analysis/study.h; study_run.h the command around it) through the runtime compiled
// once (`mechgen_view study`, tools/view/study.cc) and builds this program only for what the
// view does not do yet (study_run.h says what).
//
// The ranks of an MPI run (docs/studies.md, "Across machines"): MPI is started only when a
// launcher (mpirun, mpiexec, srun) started this process; a plain run is serial and never
// touches MPI. Rank 0 decides (the chunks to run, whether to go on) and every rank follows its
// decision; the other ranks send their samples to rank 0 and print nothing.
// Exit status: 0 done (every sample ok), 3 done but some samples failed (their status column),
// 4 stopped by --stop-after (the shards kept), 2 bad arguments or a bad study file (one line:
// file:line:column), 1 the study does not fit the model or an output cannot be written (nothing
// written).
#include "study_args.h"
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "study_args.cc"
#endif
#include "mechgen/analysis/study.h"
#include "study_run.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  // MPI_Init (under a launcher) before the arguments are read: it may take its own out of argv.
  const mechgen::study_tool::run_internal::Ranks ranks(&argc, &argv);
  mechgen::study_tool::Arguments arguments;
  int status = mechgen::study_tool::ParseArguments(argc, argv, Model::kName, &arguments);
  // The analysis (mechgen/analysis/study.h), the same source the runtime instantiated for the
  // model view runs (mechgen_view study), on the request the options are.
  if (status < 0)
    status = mechgen::study_tool::RunCommand(
        ranks, arguments, Model::kName, false,
        [](const mechgen::analysis::StudyRequest& request, const mechgen::analysis::StudyOutputs& outputs,
           const mechgen::analysis::StudyRanks& on) { return mechgen::analysis::Run(Model(), request, outputs, on); });
  return ranks.Agree(status);  // every rank ends as rank 0 does
}
