// The dynamics instantiated for the model view, once (core/view_runtime.h, its Dynamics
// section): the free motion by the minimal method and the driven motion, each with both
// integrators, the kinetostatics and the simulate CSV's columns (free and driven), in the
// library mechgen_runtime_view.
//
// (GCC's -Wmaybe-uninitialized sees Eigen's 1-norm estimator (rcond(), the conditioning of a
// Phi_phi of 5 to 16 rows on its fixed-size copy) read old_sign_vector, which it sets in the
// first iteration before any read; the fixed-size tools of the shipped models, whose Phi_phi
// are smaller, do not instantiate it.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "mechgen/core/view_runtime.h"

namespace mechgen {
namespace dynamics {
MECHGEN_VIEW_MINIMAL_MEMBERS(, ViewMinimalDopri5)
MECHGEN_VIEW_MINIMAL_MEMBERS(, ViewMinimalDop853)

bool DerivativeOf(ViewMinimalDopri5* sim, double t, const ViewMinimalDopri5::State& y, ViewMinimalDopri5::State* dy) {
  return sim->Derivative(t, y, dy);
}
bool DerivativeOf(ViewMinimalDop853* sim, double t, const ViewMinimalDop853::State& y, ViewMinimalDop853::State* dy) {
  return sim->Derivative(t, y, dy);
}
bool EvaluateAt(ViewMinimalDopri5* sim, double t, const ViewMinimalDopri5::State& y, Sample<ViewModel>* s) {
  return sim->Evaluate(t, y, s);
}
bool EvaluateAt(ViewMinimalDop853* sim, double t, const ViewMinimalDop853::State& y, Sample<ViewModel>* s) {
  return sim->Evaluate(t, y, s);
}
bool SimulateFree(ViewMinimalDopri5* sim, double t0, const ModelTypes<ViewModel>::VecQ& q0,
                  const ModelTypes<ViewModel>::VecQ& qd0, double t_end, ViewSampleFn<ViewMinimalDopri5>& observer,
                  MinimalSummary* summary, Sample<ViewModel>* last) {
  return sim->Simulate(t0, q0, qd0, t_end, observer, summary, last);
}
bool SimulateFree(ViewMinimalDop853* sim, double t0, const ModelTypes<ViewModel>::VecQ& q0,
                  const ModelTypes<ViewModel>::VecQ& qd0, double t_end, ViewSampleFn<ViewMinimalDop853>& observer,
                  MinimalSummary* summary, Sample<ViewModel>* last) {
  return sim->Simulate(t0, q0, qd0, t_end, observer, summary, last);
}

MECHGEN_VIEW_PRESCRIBED_MEMBERS(, ViewPrescribedDopri5)
MECHGEN_VIEW_PRESCRIBED_MEMBERS(, ViewPrescribedDop853)
bool InitializePrescribed(ViewPrescribedDopri5* sim, double t0, const ViewPrescribedDopri5::VecF& qf0) {
  return sim->Initialize(t0, qf0);
}
bool InitializePrescribed(ViewPrescribedDop853* sim, double t0, const ViewPrescribedDop853::VecF& qf0) {
  return sim->Initialize(t0, qf0);
}
bool SimulatePrescribed(ViewPrescribedDopri5* sim, double t0, const ViewPrescribedDopri5::VecF& qf0,
                        const ViewPrescribedDopri5::VecF& qdf0, double t_end,
                        ViewSampleFn<ViewPrescribedDopri5>& observer, PrescribedSummary* summary,
                        ViewPrescribedSample* last) {
  return sim->Simulate(t0, qf0, qdf0, t_end, observer, summary, last);
}
bool SimulatePrescribed(ViewPrescribedDop853* sim, double t0, const ViewPrescribedDop853::VecF& qf0,
                        const ViewPrescribedDop853::VecF& qdf0, double t_end,
                        ViewSampleFn<ViewPrescribedDop853>& observer, PrescribedSummary* summary,
                        ViewPrescribedSample* last) {
  return sim->Simulate(t0, qf0, qdf0, t_end, observer, summary, last);
}
template table::Columns<CsvRow<ViewPrescribedSample>>
DrivenColumns<ViewModel, ViewPrescribedSample, ViewPrescribedDopri5::Indices>(const ViewPrescribedDopri5::Indices&,
                                                                              bool, const ViewModel&);

template class Kinetostatics<ViewModel>;
template table::Columns<CsvRow<Sample<ViewModel>>> FreeColumns<ViewModel, Sample<ViewModel>, true>(bool,
                                                                                                     const ViewModel&);
template std::vector<std::pair<int, std::string>> RevoluteMagnitudes<ViewModel>(const ViewModel&);
}  // namespace dynamics
}  // namespace mechgen
