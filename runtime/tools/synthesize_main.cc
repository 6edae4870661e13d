// `mechgen synthesize MODEL --task TASK.yaml [--seed N] [--threads N] [--out DIR]`: dimensional
// synthesis of a generated model (issue 28): path generation, motion generation (`synthesis:
// motion`: synthesis/motion.h; Burmester and, beyond five poses, least squares: report.txt
// with the model file, or for four poses curves.csv and curves.svg), and function generation
// (`synthesis: function`: synthesis/function.h; pairs or a function over a range; it writes
// function.svg for path.svg; its global stage's runs go to --threads like path tasks'), and exact
// path synthesis (`synthesis: path`, `kind: exact`: synthesis/exact.h; five points with both
// pivots given, every isolated solution by homotopy continuation, each real one a model file,
// solutions.csv, report.txt; --seed, --threads and --evaluations do not apply). The model gives
// the topology, the design parameters (its `design:` section: their derivatives are the local
// stage's Jacobian) and the point; the task file (docs/synthesis.md) the targets, the timing,
// the variables' bounds, the constraints and the search's budget.
//
// `mechgen synthesize` (generator/driver/tool_command.cc) runs the same source (the synthesis
// analysis, mechgen/analysis/synthesize.h; synthesize_run.h the command around it) through the
// model view (mechgen_view synthesize) with argv[0] = "mechgen synthesize MODEL": the model file
// is read from there to write the synthesized model; with MECHGEN_VIEW=0 (or a build without
// mechgen_view) it compiles this file against the model (with Ceres and yaml-cpp) and runs it the same way. What it does: synthesis/optimize.h (seeded differential
// evolution restarts on --threads threads, then Levenberg–Marquardt with the generated
// Jacobian) or, with the task's `search: {projection: true}`, synthesis/projection.h (the
// four-bar's placement, scale, rotation and coupler point by linear least squares, the search
// over the link ratios and the timing; SynthesizePath chooses), every candidate's defect
// checks (synthesis/path.h), the result followed by the
// runtime's continuation (ContinuationCheck, synthesis/optimize.h; the report: synthesis/report.h). Writes into --out (created if needed):
//   <model file name>  the input model with the synthesized parameter values (every analysis
//                      of the project works on it: `mechgen sweep DIR/<model>.yaml`);
//   path.svg           the coupler curve against the targets;
//   report.txt         error per target, defect checks, transmission-angle range, the search.
// All three are written only when a feasible mechanism was found (written whole, then renamed).
// The same --seed gives the same bytes of the model file for any --threads.
// Exit status: 0 done; 1 a bad task file (FILE:LINE:COLUMN: what to change) or the model
// cannot take it (no design section, no such point or parameter), or an output cannot be
// written; 2 a usage error (one line); 3 no mechanism satisfies the constraints (the best
// candidate's report on stderr, nothing written).
#include <string>

#include "synthesize_args.h"
// The command-line part in this translation unit, unless it is linked compiled once
// (-DMECHGEN_TOOL_ARGS_SEPARATE: synthesize_args.h).
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "synthesize_args.cc"
#endif
#include "mechgen/analysis/synthesize.h"
#include "synthesize_run.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  mechgen::synthesize_tool::Arguments arguments;
  if (const int status = mechgen::synthesize_tool::ParseArguments(argc, argv, Model::kName, &arguments); status >= 0)
    return status;
  // The analysis (mechgen/analysis/synthesize.h), the same source the runtime instantiated for
  // the model view runs (mechgen_view synthesize), on the request the options are.
  return mechgen::analysis::Run(Model(), mechgen::synthesize_tool::Request(arguments, argc > 0 ? argv[0] : ""),
                                mechgen::synthesize_tool::Outputs(arguments));
}
