/**
 * \file dynamics/system.h
 * The system interface of the one simulator (dynamics/simulator.h, internal::EventLoop): what a
 * simulation declares so that the loop can integrate it, watch it and sample it. The anchors
 * are Drake's System (state, derivatives, discrete updates at a step, witness functions) and
 * SUNDIALS CVODES (the right-hand side, the root functions g_i(t, y) located on the
 * interpolant). The free motion (MinimalDynamics, forward.h; the engine's gas-driven run is one
 * with a load), the driven motion (PrescribedDynamics, prescribed.h), the excess-coordinate
 * motion (ExcessDynamics, excess.h) and the trajectory sensitivities' runs (staggered,
 * simultaneous and the adjoint's forward run: sensitivity_system.h) are such systems.
 *
 * A system P is a class (compile-time duck typing, C++17: the loop is a template on P, one
 * instantiation per system and model, nothing virtual) that declares
 * `friend struct internal::EventLoop;` and
 * `template <class, class, class, class> friend class internal::EventLoopRun;` and has:
 *
 * The state and its derivative
 *   kNq, kNphi                              its sizes (Eigen::Dynamic through the model view:
 *                                           then int Nq() gives the inputs),
 *   State                                   the integrator's state y (q, qd and the integrals
 *                                           of power), an Eigen vector,
 *   Integrator integrator_                  its integrator (Dopri5 or Dop853, integrators.h),
 *   bool Derivative(t, y, State* dy)        the right-hand side (false: not evaluated there).
 *
 * A configuration, and what happens at an accepted step
 *   SampleT                                 one evaluated configuration: t, q, qd, phi,
 *                                           rcond, det (the fields the witnesses read),
 *   bool Evaluate(t, y, SampleT*)           one configuration; updates nothing,
 *   bool Accept(t, y, SampleT*)             the accepted step's configuration (from the last
 *                                           stage when it was there), made the warm start of
 *                                           the next stages,
 *   void EndRun()                           the run ended (stops caching stages),
 *   static double Balance(const SampleT&)   the energy balance, constant along an exact motion,
 *   void Record(const SampleT&, Summary*)   its own figures of each sample,
 *   void OnDeadPoint(SampleT*)              what a sample at a singular configuration withholds,
 *   kCanProjectEnergy, bool ProjectEnergy(f, E0, SampleT*)
 *                                           the energy projection after a step (when true),
 *   int position_failures_, bool last_solve_not_assemblable_, singular_inertia_
 *                                           why a step failed, read when the integrator gives up.
 *
 * Its witness functions (dynamics/witness/: each a small class; the loop watches them after
 * every accepted step and locates the earliest on the dense output)
 *   - the dead point (witness/dead_point.h), when kNphi != 0: 1/cond_1(Phi_phi) and det
 *     Phi_phi of the samples;
 *   - the speed's zero (witness/speed_zero.h) and the user's event (witness/user_event.h), on
 *     the samples;
 *   - the steady state (witness/steady_state.h), on the samples handed out;
 *   - the loads' switching points (witness/switches.h), when kHasSwitches: SwitchModes (a
 *     std::array<int, n>) and bool SwitchModesAt(t, y, SwitchModes*);
 *   - stick and slip (Coulomb friction, friction.h), when kHasCoulomb: bool CoulombActive(),
 *     Stuck(), double SlipDirection(), SetFrictionMode(stuck, e), BeginFrictionStep(),
 *     double BreakawaySeen(), bool DecideAtRest(t, q, bool*, double*), QOf(y); with several
 *     inputs SeveralInputs(), FrictionMargin(t, y, double*, int*), ResolveJoints(t, State*,
 *     Summary*), CloseStuck(t, Summary*); options_.coulomb (CoulombOptions) and
 *     friction_failed_; kReportsFriction for a system that reports friction_failed_ without
 *     stick and slip (the driven motion's actuators).
 *
 * A new witness on the samples (e.g. "a coupler point leaves a box") is a class with Fires()
 * and Value() (witness/sample_witness.h) and two lines in EventLoopRun::FindEvents; its
 * event a value of Event.
 */
#pragma once

#include "mechgen/dynamics/simulator.h"
