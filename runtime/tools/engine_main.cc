// <model>_engine: crank torque, bearing loads, flywheel sizing and run-up of a reciprocating
// engine model made by tools/make_engine.py (Paul §6.8 DYREC, §6.9 FLYLOOP; issue 16).
//
// mechgen_add_model(<name> ... ENGINE) compiles this generic file per engine model with
// -DMECHGEN_MODEL_INCLUDE="<name>.h" -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It reads the
// engine from the model's parameters by name (Params::Find: bore, r, l, strokes, J_fly,
// phase_j, p_gas_j, gamma_j, beta_j, m_rod, l_G, J_rod, m_pis) and its coordinates
// (s_slide_j, theta_rod_j) and reactions (F_O, F_B_j, F_C_j, N_slide_j) by name.
//
// Gas: one pressure law for every cylinder (mechgen/machines/engine/gas.h), cylinder j at the cycle
// angle theta - phase_j: the parametric polytropic cycle with a Wiebe heat release (default),
// or --table FILE, an indicator diagram (CSV rows: cycle angle in deg from firing TDC, gauge
// pressure in Pa; a header line is skipped). The gas torque T_gas = -sum p_j A ds_j/dtheta
// (N m on the crank, CCW +) comes from the generated velocity coefficients
// (mechgen/machines/engine/crank_dynamics.h, GasTorque); the bearing loads and side thrusts come from
// the generated kinetostatics with the model's p_gas_j parameters set to p_j at each angle.
//
// Subcommands (signs: torques on the crank CCW +, N m; forces N in the fixed frame):
//   cycle     At constant crank speed (--rpm), over one cycle: CSV columns theta_deg, T_gas,
//             T_inertia = -1/2 I'(theta) omega^2 (the generated dynamics' h at thetadd = 0),
//             T_total, per cylinder p_j (gauge, Pa) and thrust_j (the force of piston j on the
//             cylinder wall along n_j = (-sin beta_j, cos beta_j), N), the main bearing load
//             F_O_x, F_O_y (frame on crank), per cylinder the crank pin load pin_j_x, pin_j_y
//             (crank on rod j), pin_j_u, pin_j_v (rod j on the crank pin in the crank's frame:
//             u along the throw outward, v 90 deg ahead: the polar diagram) and the wrist pin
//             load wrist_j_x, wrist_j_y (rod j on piston j), and for a model with `shaking` the
//             shaking force shake_F_x, shake_F_y (N, on the frame) and moment shake_M about O
//             (N m, CCW +) of the generated EvalShaking, and the rocking couple M_rock_x,
//             M_rock_y (N m, about axes across the crankshaft through its point at the mean of
//             the cylinders' axial positions z_j; z along the shaft; on the frame:
//             mechgen/machines/engine/couples.h). The crank is held at constant
//             speed by a dynamometer absorbing T_total. Summary: mean torque, its harmonics by
//             order (multiples of the crank speed; mechgen/machines/engine/harmonics.h), max/mean, and
//             the power smoothing of Paul §6.8.5: the torque of k cylinders evenly spaced over
//             the cycle, k = 1..n, each the torque of cylinder 1 of this model (its gas torque
//             plus its own inertia torque) shifted by cycle/k (summed phase-shifted
//             single-cylinder torques), k up to max(--smoothing, n).
//   flywheel  Energy loop (Paul §6.9.2; mechgen/machines/flywheel/energy_loop.h) of T_total at
//             constant speed about its mean: the
//             largest swing dE, the generalized inertia for --cs, I = dE / (C_s omega^2), and
//             J_fly = I - mean(I(theta) - J_fly) (the reciprocating parts' mean inertia taken
//             off); then the periodic steady state with that J_fly against the viscous load
//             c_load = T_mean / omega (FindSteadyCycle, Paul §6.9.1): simulated C_s against
//             the prescribed one, and what neglecting I(theta) (gas torque only, constant I)
//             predicts. CSVs: --loop FILE (theta_deg, T_total, T_mean, E: the energy loop),
//             --sweep FILE (J_fly, Cs_energy_loop, Cs_simulated), --wittenbauer FILE
//             (theta_deg, t, omega, I, T_kin of the steady cycle: Paul §6.9.3).
//   runup     From --idle-rpm against the load c_load = T_mean / omega(--rpm) (plus T_load of
//             the model), the one-DOF simulator (mechgen/dynamics/forward.h) until the cycle
//             mean speed settles (relative change < --steady-tol twice: the simulator's
//             steady-state detection, mechgen/dynamics/simulator.h) or --t-end: CSV t,
//             theta_deg, omega, rpm, T_gas, T_load; summary: the time to reach 99 % of the
//             final speed, the final mean speed, mean gas torque against the load.
// Options (CLI11; `<model>_engine --help` lists them with their defaults) may come before or
// after the subcommand; one that only another subcommand uses is accepted and ignored. Common:
// --rpm (default 3000), --samples per cycle (16..1e6, default 1440); cycle: --csv,
// --smoothing (1..64, default 6); flywheel: --cs (in [1e-6, 1), default 0.02), --loop, --sweep,
// --wittenbauer; runup: --csv, --idle-rpm, --t-end (60 s), --dt (0.002 s), --steady-tol
// (1e-5); CSVs default to <model>_<subcommand>.csv, <model>_energy_loop.csv,
// <model>_cs_sweep.csv, <model>_wittenbauer.csv. Pressure law: --table, or --cr (10),
// --p-intake (1e5 Pa), --p-ambient (101325 Pa), --n (1.32), --burn-start (-15 deg),
// --burn-duration (60 deg), --wiebe-a (5), --wiebe-m (2), --heat (800 J per cylinder and
// cycle). Numbers must be finite; speeds, times and the law's parameters > 0 (--burn-start
// any, --wiebe-m and --heat >= 0); the law's parameters are checked together by
// PolytropicWiebeCycle::Init.
// The model-dependent part is the engine analysis (mechgen/analysis/engine.h; engine_run.h the
// command around it), the same source the runtime instantiated once for the model view runs
// (mechgen_view engine, issue 43).
// Options are parsed by engine_args.cc (CLI11, independent of the model: included here, or
// compiled apart with -DMECHGEN_TOOL_ARGS_SEPARATE) with the command-line layer of every
// tool (runtime/tools/common/):
// `--opt=value` or `--opt value`, each number finite and in the range --help lists (e.g. --rpm
// in [1e-3, 1e5], --t-end in (0, 1e6] s, --dt at least --t-end / 1e8 so that the run-up's time
// advances).
// Exit status: 0 done, 1 a computation failed (the reason on stderr), 2 a usage error (an
// unknown or missing subcommand, an unknown option, a bad value, a bad pressure table or law;
// one line "<tool>: error: ..." on stderr). No output file is written unless the whole computation
// succeeded (io/output_file.h).
#include "engine_args.h"
#ifndef MECHGEN_TOOL_ARGS_SEPARATE
#include "engine_args.cc"
#endif
#include "engine_run.h"
#include "mechgen/analysis/engine.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

int main(int argc, char** argv) {
  using Model = MECHGEN_MODEL_NAMESPACE::Model;
  mechgen::engine_tool::Arguments a;
  const int rc = mechgen::engine_tool::ParseArguments(argc, argv, Model::kName,
                                                      mechgen::HasDesignDerivatives<Model>::value, &a);
  if (rc != -1) return rc;
  // The analysis (mechgen/analysis/engine.h), the same source the runtime instantiated for the
  // model view runs (mechgen_view engine), on the request the options are.
  return mechgen::analysis::Run(Model(), a, mechgen::engine_tool::Outputs(a));
}
