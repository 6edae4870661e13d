// <model>_simulate: the forward dynamics of one generated mechgen model (issue 15).
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this generic file per model
// whose outputs ask for `dynamics`, with -DMECHGEN_MODEL_INCLUDE="<name>.h"
// -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It assembles the mechanism at the model's assembly
// configuration (or --q0), starts from rest (or --qd0) and integrates the equation of motion
// I(q) qdd + 1/2 I'(q) qd^2 = Q(t, q, qd) by the minimal method (mechgen/dynamics/forward.h)
// until --t-end, or until the speed is periodic (steady state, the simulator's detection in
// mechgen/dynamics/simulator.h: the mean speed of a revolution of the first input changes by
// less than --steady-tol of the last one, two revolutions in a row; an angle input only), or
// until an event stops it. Writes a CSV (one row every --dt seconds; its columns
// declared once below with their units and signs and written by the one CSV writer, io/csv.h,
// every number so that it reads back to the same double; the file written whole or not at
// all, io/output_file.h: a CSV that cannot be written exits 1 with one line):
//   t [s], each input q [rad or m], its speed q_dot, acceleration q_ddot, the kinetic energy
//   T, potential V, E = T + V, W_nc = the work of the non-conservative forces since t = 0 [J],
//   Q_<input> = the generalized applied force (loads, motor curves, dampers, weights, springs;
//   a torque [N m] for an angle input, CCW +, a force [N] for a slide), then, when the model has
//   reactions, each reaction component of the generated kinetostatics at the simulated motion
//   (inertia forces included; the force of the joint's first link on its second, fixed frame)
//   and |F| of each revolute joint (F_<joint>_mag); a model with Coulomb friction (its
//   `friction:` joints with a coefficient) adds friction_<joint>, the friction
//   torque on the joint's second link by its first [N m, CCW +] or the friction force on the
//   slider along the slide's +u [N], and stuck (1 while static friction holds the motion at
//   rest, 0 while it moves; with several inputs stuck_<joint> per joint: 1 while that joint
//   holds its input at rest); the reactions then include the friction loads.
// Coulomb friction (mechgen/dynamics/friction.h: slip with the friction loads iterated on the
// reactions, stick where the applied force stays within the friction bound at rest, each
// transition located and given a row of its own; several inputs: each joint on its own): on by
// default for a model with it, off with --friction off (--friction on for a model without
// friction joints, or with --drive leaving an input free, is a usage error). The summary lists
// the stuck intervals (per joint with several inputs). With every input driven the actuator
// forces lambda include the joints' friction (friction_<joint> columns after rcond; 0 at a
// joint's relative rest, where it is indeterminate: the actuator then holds the whole load).
// With --design (a model with a `design` section) the free motion is integrated with its
// trajectory sensitivities (mechgen/dynamics/sensitivity.h: the forward sensitivity equations):
// the CSV has t, the inputs, speeds and accelerations, d<q>/d<p> and d<q>_dot/d<p> for every
// input q and design parameter p (q's unit, or per second, per unit of p) and rcond.
// Plot it with runtime/tools/plot_dynamics.gnuplot. Example:
//   slider_crank_motor_simulate --t-end 10 --dt 0.002 --csv out/motor.csv
//   gnuplot -e "csv='out/motor.csv'; png='out/motor.png'" runtime/tools/plot_dynamics.gnuplot
// With --drive (motion generators, Paul 8.4.4; mechgen/dynamics/prescribed.h) some inputs follow
// a law of time and the others are free; the CSV then also has, per driven input, the actuator
// force lambda_<input> that keeps it on its law (a torque [N m] on the input link, CCW +, or a
// force [N] along the slide), W_act = its work since t = 0, the balance E - W_nc - W_act (constant
// along an exact motion) and rcond = 1/cond_1(Phi_phi) (the run stops, exit 1, where it falls
// below 1e-6: a singular configuration, never integrated through). Example, the five-bar robot
// with its first motor at 2 rad/s and the second holding still (inverse dynamics when every
// input is driven):
//   fivebar_robot_simulate --drive theta_prox1=speed:2 --drive theta_prox2=speed:0 --t-end 0.5
// Exit status: 0 when the run reached --t-end or a steady state (or stopped at the speed
// through zero with --stop-at-speed-zero); 1 when it ended on a failure (a dead point, the
// position solver, a singular inertia, the integrator), with the reason on stderr; 2 for a
// usage error (one line "<tool>: error: ..."). A model generated without `dynamics` builds into
// a stub that says so (exit 2). Options are read by simulate_args.cc (model-independent:
// `mechgen simulate MODEL` answers --help and a usage error with it before compiling) on the
// command-line layer of every tool (runtime/tools/common/): `--opt=value` or `--opt value`;
// each number finite and in the range
// --help lists: --rtol in [1e-14, 0.1] (what double precision resolves), |--q0| <= 1e4,
// |--qd0| <= 1e5, --dt at least --t-end / 1e8 (so that t + dt > t all the way).
// The model-dependent part is the simulation analysis (mechgen/analysis/simulate.h; --design:
// analysis/simulate_design.h; simulate_run.h the command around it), the same source the
// runtime instantiated once for the model view runs (`mechgen_view simulate MODEL.so`, issue 43).
#include "simulate_args.h"
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "simulate_args.cc"  // the options (CLI11), in this translation unit
#endif
#include "simulate_run.h"
#include "mechgen/analysis/simulate.h"
#include "mechgen/analysis/simulate_design.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  mechgen::simulate_tool::Arguments args;
  const int parsed = mechgen::simulate_tool::ParseArguments(argc, argv, Model::kName, &args);
  if (parsed >= 0) return parsed;
  // The analysis (mechgen/analysis/simulate.h), the same source the runtime instantiated for the
  // model view runs (mechgen_view simulate), on the request the options are.
  return mechgen::analysis::Run(Model(), args, mechgen::simulate_tool::Outputs(args));
}
