// <model>_statics: the statics command of one generated mechgen model (issue 14).
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this one generic file per model
// whose outputs ask for `forces`, with -DMECHGEN_MODEL_INCLUDE="<name>.h"
// -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It assembles the mechanism at the model's assembly
// configuration, sweeps the inputs along a straight line (by default every input over the
// model's kQMin..kQMax) staying on that assembly mode, and at every configuration reports
// the driving forces (without friction and, with friction, forward and backward), the
// reactions, V, the mechanical advantage and a status per row; optionally the dead zones
// (self-locking intervals) and the equilibrium positions along the range. Writes a CSV file,
// a short table and an SVG force diagram (statics/svg.h: the reactions, and the applied loads
// and springs where the model has Model::AppliedLoads). `--plots PREFIX` runs gnuplot on
// the CSV: PREFIX_drive.png (runtime/tools/plot_statics.gnuplot: the driving torque, with
// friction to run in +q and -q, and the reaction magnitudes against the input) and
// PREFIX_bearings.png (plot_bearings.gnuplot: the polar diagram of each ground bearing's
// load); gnuplot missing or the scripts not found: one line, exit 1, before anything is
// computed. Example:
//   slider_crank_friction_statics --steps 720 --csv out/scf.csv --svg out/scf.svg --plots out/scf
// Speed (issue 45): where the model's loads read a velocity (a load of <coordinate>_dot, a
// damper, viscous joint friction; statics::SpeedItems), every run says so on its output and in
// its CSV's first comment line (statics::SpeedNote): at rest they are taken at qd = 0. With
// --speed SPEED the statics are taken along the motion at that constant speed of the swept
// input (the first input that moves; rad/s, m/s, or rev/min with 'rpm' as the flywheel's
// --rpm): the loads at qd and the dependent velocities K qd, t = 0, without the inertia
// forces (the kinetostatics without inertia); the dead-zone and equilibrium scans stay at rest.
// The model-dependent part is the statics analysis (mechgen/analysis/statics.h, around which
// statics_run.h is the command), the same source `mechgen_view statics` runs through the model
// view; the rows are streamed to the CSV (held in memory only
// for --svg). Options are read by statics_args.cc (model-independent, CLI11; the command-line
// layer of every tool, runtime/tools/common/): `--opt=value` or `--opt value`, every number
// finite and in the range --help lists; --steps up to 10^6; --samples from
// 36 (statics::ScanOptions::kMinSamples) and at most 10 deg apart along an angle input, so
// that a scan cannot report what a few samples happen to show as converged. Exit status: 0
// done, 2 a usage error (one line "<tool>: error: ..."), 3 the model does not assemble, 4 an
// output cannot be written.
// A model generated without `forces` builds into a stub that says so (exit status 2).
// Compiled with -DMECHGEN_TOOL_NO_CERES it needs Eigen and CLI11 only: it assembles with the
// Ceres-free PositionSolver (NewtonAssembler, position/assembler.h), as `mechgen statics
// <model.yaml>` builds it (generator/driver/); the Newton polish follows either assembler.
#include <functional>
#include <string>

#include "statics_args.h"
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "statics_args.cc"
#endif
#include "statics_run.h"
#include "mechgen/analysis/statics.h"

#ifndef MECHGEN_TOOL_NO_CERES
#include "mechgen/position/ceres_adapter.h"
#endif

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  // A model generated without statics: a stub that says so, before reading any option.
  if (!mechgen::statics::StaticsFeatures<Model>::kHasStatics) {
    return mechgen::analysis::RunIfStatics(Model(), mechgen::analysis::StaticsRequest(),
                                           mechgen::analysis::StaticsOutputs());
  }
  mechgen::statics_tool::Arguments args;
  if (const int parsed = mechgen::statics_tool::ParseArguments(argc, argv, Model::kName, &args); parsed >= 0)
    return parsed;
  // The analysis (mechgen/analysis/statics.h), the same source the runtime instantiated for the
  // model view runs (mechgen_view statics), on the request the options are. Ceres assembles
  // (position/ceres_adapter.h) unless MECHGEN_TOOL_NO_CERES: then the runtime's own
  // Levenberg-Marquardt (NewtonAssembler), Eigen only.
#ifdef MECHGEN_TOOL_NO_CERES
  using Assembler = mechgen::position::NewtonAssembler;
#else
  using Assembler = mechgen::position::CeresAssembler;
#endif
  mechgen::statics_tool::Command command(args);
  return command([&args](const mechgen::analysis::StaticsOutputs& outputs, const std::function<int()>& prepare,
                         mechgen::analysis::StaticsPlotFacts* facts) {
    return mechgen::analysis::RunIfStatics<Model, Assembler>(Model(), args, outputs, prepare, facts);
  });
}
