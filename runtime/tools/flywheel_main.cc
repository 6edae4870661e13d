// <model>_flywheel: flywheel sizing of one generated one-DOF machine (issue 25).
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this generic file per model whose
// outputs ask for `forces`, with -DMECHGEN_MODEL_INCLUDE="<name>.h"
// -DMECHGEN_MODEL_NAMESPACE=mech::<name>; `mechgen flywheel <model.yaml>` compiles it the same
// way for any model file (generator/driver/tool_command.cc). What it computes
// (mechgen/machines/flywheel/machine_cycle.h): the driving torque T_req(theta) a motor turning
// the input at the constant speed --rpm must supply over one cycle (the statics of the loads,
// weights, springs and friction, plus with `dynamics` the inertia torque 1/2 I'(theta) w^2 and
// the speed-dependent loads: Paul's one-DOF equation at constant speed), its mean (the
// constant motor torque of a steady cycle), the energy loop E(theta) of the excess torque
// T_mean - T_req (Paul §6.9.2), dE = E_max - E_min and the flywheel for --cs: I = dE/(C_s w^2)
// (less the machine's own mean inertia with `dynamics`). With `dynamics` (and not --no-check)
// it then simulates the machine with that flywheel, driven by a --motor law (constant torque
// T_mean, or a shunt motor's line T = T_stall (1 - w/w_0) through (w_m, T_mean) with --slip),
// to a periodic steady state, and prints the simulated C_s against the asked one.
// Writes the energy loop as CSV (--csv; its columns described in its '#' header lines, every
// number so that it reads back to the same double) and draws it with gnuplot (--png, --svg:
// runtime/tools/plot_energy_loop.gnuplot, found as common/gnuplot.h says: $MECHGEN_TOOLS_DIR
// alone when set, else share/mechgen/tools beside the installed program, else the source
// tree's). Example:
//   shaper_flywheel --rpm 60 --cs 0.05 --csv out/shaper_loop.csv --png out/shaper_loop.png
// Signs: the input turns counter-clockwise (theta increasing) at w > 0; torques on the input
// link, CCW +; T_req > 0 where the motor drives, < 0 where the machine gives energy back.
// Exit status: 0 done; 1 the machine cannot be sized (not one-DOF, a slide input, a dead point
// or a failed position inside the cycle: the angle is printed; no net load) or the simulated
// check failed or an output cannot be written, or a picture is asked for and gnuplot or its
// script is not found (one line, before anything is computed or written); 2 a usage error
// (one line "<tool>: error: ..."); 3 the model does not assemble. A model generated without
// `forces` builds into a stub that says so (exit status 2). The options are parsed by
// flywheel_args.cc (CLI11, independent of the model: included here, or compiled apart with
// -DMECHGEN_TOOL_ARGS_SEPARATE). Eigen, CLI11 only (the runtime's
// Newton assembler). The model-dependent part is the flywheel analysis
// (mechgen/analysis/flywheel.h; flywheel_run.h the command around it: the pictures), the same
// source the runtime instantiated once for the model view runs (mechgen_view flywheel, issue 43).
#include "flywheel_args.h"
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "flywheel_args.cc"
#endif
#include <functional>

#include "flywheel_run.h"
#include "mechgen/analysis/flywheel.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  mechgen::flywheel_tool::Arguments a;
  if (const int parsed = mechgen::flywheel_tool::ParseArguments(argc, argv, Model::kName,
                                                                mechgen::flywheel_tool::kMaxCheckSamples, &a);
      parsed >= 0)
    return parsed;
  // The analysis (mechgen/analysis/flywheel.h), the same source the runtime instantiated for the
  // model view runs (mechgen_view flywheel), on the request the options are.
  mechgen::flywheel_tool::Command command(a);
  return command([&a](const mechgen::analysis::FlywheelOutputs& outputs, const std::function<int()>& prepare,
                      mechgen::analysis::FlywheelResult* result) {
    return mechgen::analysis::Run(Model(), a, outputs, prepare, result);
  });
}
