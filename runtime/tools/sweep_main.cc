// <model>_sweep: the sweep command of one generated mechgen model.
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this one generic file per model
// with -DMECHGEN_MODEL_INCLUDE="<name>.h" -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It
// assembles the mechanism at the model's assembly configuration, sweeps the inputs along a
// straight line (by default every input over the model's kQMin..kQMax) staying on that
// assembly mode, and writes a CSV file, a short table and an SVG drawing with the traced
// point paths. Rows are streamed to the CSV as they are solved; every output file is written
// whole or not at all (io/output_file.h). Exit status: 0 every row converged, 3 some did not
// (the outputs are written; counts per status on stderr), 2 bad arguments, 1 the model does
// not assemble or an output cannot be written (nothing written). Example:
//   fourbar_sweep --steps 360 --csv out/fourbar.csv --svg out/fourbar.svg --table 8
//
// By default it assembles with Ceres (CeresPositionSolver, link mechgen::runtime_ceres).
// Compiled with -DMECHGEN_SWEEP_NO_CERES it needs Eigen and CLI11 only: the Ceres-free
// PositionSolver (NewtonAssembler, position/assembler.h), which compiles in a fraction of
// the time; `mechgen sweep <model.yaml>` builds it that way (generator/driver/). Both reach
// the same configurations (the solver's Newton polish follows either assembler), and on most
// shipped models the same CSV, table and SVG to the byte; not on stephenson_coupled, whose
// coupled block's Newton polish does not bring the two assemblers' results (a few ulp
// apart) to the same bits: every row then differs in the last bits, within a few
// eps cond(Phi_phi) (tests/runtime/view_solver_test.cc, CloseToCeresAssembly). And a step
// that ends in the Assembler (Fallback(): the row of a sweep stopped at a change point, as
// tests/runtime/models/changepoint_fourbar's) counts the assembler's own iterations, which
// differ (40 with Ceres, 39 without on that row). mechgen_view assembles with NewtonAssembler:
// it gives the -DMECHGEN_SWEEP_NO_CERES tool's bytes on every one of these models.
#include <string>

#include "sweep_args.h"
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "sweep_args.cc"
#endif
#include "sweep_run.h"
#include "mechgen/analysis/sweep.h"

#ifndef MECHGEN_SWEEP_NO_CERES
#include "mechgen/position/ceres_adapter.h"
#endif

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  mechgen::sweep_tool::Arguments arguments;
  const int parsed = mechgen::sweep_tool::ParseArguments(argc, argv, Model::kName,
                                                         mechgen::sweep_tool::kMaxSteps, &arguments);
  if (parsed >= 0) return parsed;
  // The analysis (mechgen/analysis/sweep.h), the same source the runtime instantiated for the
  // model view runs (mechgen_view sweep), on the request the options are.
  // Ceres assembles (position/ceres_adapter.h) unless MECHGEN_SWEEP_NO_CERES: then the
  // runtime's own Levenberg-Marquardt (NewtonAssembler), Eigen only.
#ifdef MECHGEN_SWEEP_NO_CERES
  return mechgen::analysis::Run<Model, mechgen::position::NewtonAssembler>(
      Model(), arguments, mechgen::sweep_tool::Outputs(arguments, "Levenberg-Marquardt"));
#else
  return mechgen::analysis::Run<Model, mechgen::position::CeresAssembler>(
      Model(), arguments, mechgen::sweep_tool::Outputs(arguments, "Ceres"));
#endif
}
