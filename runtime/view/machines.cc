// The machines instantiated for the model view, once (machines/view_machines.h): the engine's
// cycle and gas-driven simulation, the flywheel's cycle, its design sensitivities and simulated
// check (with WithFlywheel<ViewModel>), in the library mechgen_runtime_view.
//
// (-Wmaybe-uninitialized: as in instantiations.cc, the fixed-size factorizations the view's
// condition number dispatches to.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "mechgen/core/view_runtime.h"
#include "mechgen/machines/view_machines.h"

namespace mechgen {
namespace dynamics {
template engine::ViewGasDriven::MinimalDynamics(const ViewModel&, const ViewParams&, const MinimalOptions&,
                                                engine::GasLoad<engine::CycleGas>);
template bool engine::ViewGasDriven::Initialize(const ModelTypes<ViewModel>::VecQ&);
}  // namespace dynamics

namespace engine {
bool RunCycle(const ViewModel& model, const ViewParams& p0, const Engine& e, const CycleGas& gas, double omega,
              int samples, std::vector<CrankPoint<ViewModel>>* out, std::string* error) {
  return RunCycle<ViewModel>(model, p0, e, gas, omega, samples, out, error);
}
bool RunCycleDesign(const ViewModel& model, const ViewParams& p, const Engine& e, const CycleGas& gas, double omega,
                    int samples, std::vector<double>* dT, std::vector<double>* dI, std::string* error) {
  return RunCycleDesign<ViewModel>(model, p, e, gas, omega, samples, dT, dI, error);
}
SteadyCycle FindSteadyCycle(ViewGasDriven* sim, const SteadyCycleOptions& o) {
  return FindSteadyCycle<ViewGasDriven>(sim, o);
}
bool SimulateGasDriven(ViewGasDriven* sim, double t0, const ModelTypes<ViewModel>::VecQ& q0,
                       const ModelTypes<ViewModel>::VecQ& qd0, double t_end,
                       dynamics::ViewSampleFn<ViewGasDriven>& observer, dynamics::MinimalSummary* summary) {
  return sim->Simulate(t0, q0, qd0, t_end, observer, summary);
}
}  // namespace engine

namespace flywheel {
MachineCycle SampleMachineCycle(const ViewModel& model, const ViewParams& p, const MachineCycleOptions& o) {
  return SampleMachineCycle<ViewModel>(model, p, o);
}
SimulatedCheck CheckBySimulation(const ViewModel& model, const ViewParams& p, const MachineCycle& cycle,
                                 double I_flywheel, const CheckOptions& o) {
  return CheckBySimulation<ViewModel>(model, p, cycle, I_flywheel, o);
}
CycleDesign<ViewModel> SampleMachineCycleDesign(const ViewModel& model, const ViewParams& p,
                                                const MachineCycleOptions& o, const MachineCycle& cycle) {
  return SampleMachineCycleDesign<ViewModel>(model, p, o, cycle);
}
}  // namespace flywheel
}  // namespace mechgen
