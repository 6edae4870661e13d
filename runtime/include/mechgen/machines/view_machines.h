/**
 * \file machines/view_machines.h
 * The machines (machines/engine/, machines/flywheel/) instantiated once for the model view
 * (issue 43), compiled into the library mechgen_runtime_view (runtime/view/machines.cc): the
 * engine's cycle at constant speed, its gas-driven simulation (the run-up, the steady cycle by
 * shooting) and the flywheel's cycle, its design sensitivities and simulated check. Each is a
 * plain function on the view's types beside the template it instantiates: a call with a
 * ViewModel (unqualified, found by its arguments, as analysis/engine.h and analysis/flywheel.h make
 * it) takes the plain function, so a program that includes this header and links the library
 * does not compile the cycle, the integrator or the event loop again. The same templates, instantiated for a generated
 * model's type, are the per-model tools' (fixed sizes): one source, two instantiations.
 */
#pragma once

#include <string>
#include <vector>

#include "mechgen/core/view_model.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/cycle.h"
#include "mechgen/machines/flywheel/cycle_design.h"
#include "mechgen/machines/flywheel/machine_cycle.h"

namespace mechgen {
namespace engine {
/// The engine's crank dynamics with its gas torque, through the view.
using ViewGasDriven = GasDriven<ViewModel, CycleGas>;

/// RunCycle<ViewModel> (cycle.h).
bool RunCycle(const ViewModel& model, const ViewParams& p0, const Engine& e, const CycleGas& gas, double omega,
              int samples, std::vector<CrankPoint<ViewModel>>* out, std::string* error);
/// RunCycleDesign<ViewModel> (cycle.h): flywheel --design's sensitivities at the samples.
bool RunCycleDesign(const ViewModel& model, const ViewParams& p, const Engine& e, const CycleGas& gas, double omega,
                    int samples, std::vector<double>* dT, std::vector<double>* dI, std::string* error);
/// FindSteadyCycle<ViewGasDriven> (crank_dynamics.h).
SteadyCycle FindSteadyCycle(ViewGasDriven* sim, const SteadyCycleOptions& o);
/// sim->Simulate(t0, q0, qd0, t_end, observer, summary): the run-up (analysis/engine.h).
bool SimulateGasDriven(ViewGasDriven* sim, double t0, const ModelTypes<ViewModel>::VecQ& q0,
                       const ModelTypes<ViewModel>::VecQ& qd0, double t_end,
                       dynamics::ViewSampleFn<ViewGasDriven>& observer, dynamics::MinimalSummary* summary);
}  // namespace engine

namespace dynamics {
// The members of the gas-driven simulation a program calls (compiled in the library).
extern template engine::ViewGasDriven::MinimalDynamics(const ViewModel&, const ViewParams&, const MinimalOptions&,
                                                       engine::GasLoad<engine::CycleGas>);
extern template bool engine::ViewGasDriven::Initialize(const ModelTypes<ViewModel>::VecQ&);
}  // namespace dynamics

namespace flywheel {
/// SampleMachineCycle<ViewModel> (machine_cycle.h).
MachineCycle SampleMachineCycle(const ViewModel& model, const ViewParams& p, const MachineCycleOptions& o);
/// CheckBySimulation<ViewModel> (machine_cycle.h): WithFlywheel<ViewModel> driven by the motor.
SimulatedCheck CheckBySimulation(const ViewModel& model, const ViewParams& p, const MachineCycle& cycle,
                                 double I_flywheel, const CheckOptions& o);
/// SampleMachineCycleDesign<ViewModel> (cycle_design.h): the cycle's design sensitivities.
CycleDesign<ViewModel> SampleMachineCycleDesign(const ViewModel& model, const ViewParams& p,
                                                const MachineCycleOptions& o, const MachineCycle& cycle);
}  // namespace flywheel
}  // namespace mechgen
