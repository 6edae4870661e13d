/**
 * \file core/view_runtime.h
 * The runtime instantiated once for the model view (issue 43): the templates of the layers
 * below for M = ViewModel (core/view_model.h), compiled into the library mechgen_runtime_view
 * (runtime/view/instantiations.cc). A program that includes this header and links that library
 * reaches any model through its ModelView without compiling the runtime's algorithms again:
 * the `extern template` declarations keep them out of its translation units. The same
 * templates, instantiated for a generated model's type, are the fixed-size path (embedding,
 * the per-model tools, the benchmarks): one source, two instantiations.
 *
 * Instantiated: the position solver (position/), the sweep (sweep/sweep.h: SweepRows with a
 * ViewRowFn, ComputeMotion, the design derivatives of --design), its columns (sweep/columns.h,
 * the design columns with them) and motion summary (sweep/motion_summary.h); the statics
 * (statics/: Solve, the drive analysis, the statics sweep with a ViewStaticsRowFn and its
 * design derivatives, its columns, the dead-zone and equilibrium scans; not the force diagram,
 * statics/svg.h);
 * the free motion by the minimal method (dynamics/forward.h:
 * MinimalDynamics with Dopri5 and Dop853, samples handed to a ViewSampleFn), the
 * driven motion (dynamics/prescribed.h: PrescribedDynamics with the driven inputs counted
 * at run time and their laws chosen at run time, Dopri5 and Dop853, samples handed to a
 * ViewSampleFn), the kinetostatics (dynamics/kinetostatics.h) and the simulate CSV's columns
 * (dynamics/columns.h: free and driven).
 */
#pragma once

#include <functional>
#include <vector>

#include "mechgen/core/view_model.h"
#include "mechgen/core/view_sized.h"
#include "mechgen/dynamics/columns.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "mechgen/dynamics/prescribed.h"
#include "mechgen/position/assembler.h"
#include "mechgen/position/motion.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/solve.h"
#include "mechgen/statics/sweep.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/motion_summary.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen {
// Phi_phi's conditioning on fixed-size copies of 1 to 16 rows (core/linear_algebra.h), of a
// bounded copy of the view's matrices: compiled in the library only (runtime/view/
// conditioning.cc), read by the statics, the dynamics' position tracking and the
// kinetostatics.
extern template void ConditionAndDeterminantDynamic<1, Eigen::Map<const Eigen::MatrixXd>>(
    const Eigen::Map<const Eigen::MatrixXd>&, double*, double*);
extern template void ConditionAndDeterminantDynamic<1, ModelTypes<ViewModel>::MatCPhi>(
    const ModelTypes<ViewModel>::MatCPhi&, double*, double*);

namespace position {
extern template class PositionSolver<ViewModel, NewtonAssembler>;
extern template void ComputeMotion<ViewModel>(const State<ViewModel>&, const ModelTypes<ViewModel>::VecQ&,
                                              const ModelTypes<ViewModel>::VecQ&, Motion<ViewModel>*);
}  // namespace position

/// The row callback of the view's SweepRows (pass an lvalue of this type).
using ViewRowFn = std::function<void(int, const SweepRecord<ViewModel>&)>;
/// The position solver of the runtime instantiated for the view.
using ViewPositionSolver = position::PositionSolver<ViewModel, position::NewtonAssembler>;

extern template int SweepRows<ViewModel, position::NewtonAssembler, ViewRowFn&>(
    ViewPositionSolver*, const ModelTypes<ViewModel>::VecQ&, const ModelTypes<ViewModel>::VecQ&, int,
    const ModelTypes<ViewModel>::VecQ&, const ModelTypes<ViewModel>::VecQ&, const SweepOptions&, ViewRowFn&);
extern template std::vector<SweepColumn<ViewModel>> SweepColumns<ViewModel>(const ViewModel&);
extern template void AppendDesignColumns<ViewModel>(const ViewModel&, std::vector<SweepColumn<ViewModel>>*);
extern template class MotionSummaryBuilder<ViewModel>;

// ---- Statics (statics/; instantiated in runtime/view/statics.cc) ----
namespace statics {
/// The row callback of the view's StaticsSweepRows (pass an lvalue of this type).
using ViewStaticsRowFn = StaticsRowFn<ViewModel>;
using ViewVecQ = ModelTypes<ViewModel>::VecQ;

extern template struct Solution<ViewModel>;
extern template Status Solve<ViewModel>(const ViewModel&, const Options&, const ViewParams&, const ViewVecQ&,
                                        const ModelTypes<ViewModel>::VecPhi&,
                                        const ModelTypes<ViewModel>::Coefficients&, const ViewVecQ&,
                                        Solution<ViewModel>*, const ViewVecQ*);
extern template Status SolveAt<ViewModel>(const ViewModel&, const Options&, const ViewParams&,
                                          const position::State<ViewModel>&, const ViewVecQ&, Solution<ViewModel>*,
                                          const ViewVecQ*);
extern template Status AnalyzeDriveAt<ViewModel>(const ViewModel&, const Options&, const ViewParams&,
                                                 const position::State<ViewModel>&, int, DriveAnalysis*,
                                                 Solution<ViewModel>*, Solution<ViewModel>*, Solution<ViewModel>*);
extern template Status EvaluateRecord<ViewModel>(const ViewModel&, const Options&, const ViewParams&,
                                                 StaticsRecord<ViewModel>*, const ViewVecQ*);
extern template int StaticsSweepRows<ViewModel, position::NewtonAssembler, ViewStaticsRowFn&>(
    const Options&, ViewPositionSolver*, const ViewVecQ&, const ViewVecQ&, int, const SweepOptions&,
    const ViewVecQ*, ViewStaticsRowFn&);
extern template Status FindDeadZones<ViewModel, position::NewtonAssembler>(const Options&, const ScanOptions&,
                                                                           ViewPositionSolver*, int, double, double,
                                                                           std::vector<DeadZone>*, ScanSummary*);
extern template Status FindEquilibria<ViewModel, position::NewtonAssembler>(
    const Options&, const ScanOptions&, ViewPositionSolver*, const ViewVecQ&, const ViewVecQ&,
    std::vector<Equilibrium<ViewModel>>*, ScanSummary*);
extern template std::vector<StaticsColumn<ViewModel>> StaticsColumns<ViewModel>(const ViewModel&, bool);
extern template std::vector<ReactionJoint> ReactionJoints<ViewModel>(const ViewModel&);
extern template std::vector<GroundBearing> GroundBearings<ViewModel>(const ViewModel&);
extern template std::string SpeedNote<ViewModel>(const ViewModel&, const ViewVecQ*);
}  // namespace statics

// ---- The runtime sized to the commonest shape, one input and two dependent coordinates
//      (core/view_sized.h; instantiated in runtime/view/analysis_sized.cc, where the sweep and
//      the statics of a view of that shape run: analysis::RunSized) ----
using ViewSized12 = SizedViewModel<1, 2>;
namespace position {
extern template class PositionSolver<ViewSized12, NewtonAssembler>;
}  // namespace position
/// The row callbacks of SweepRows and StaticsSweepRows at those sizes.
using ViewSized12RowFn = std::function<void(int, const SweepRecord<ViewSized12>&)>;
extern template int SweepRows<ViewSized12, position::NewtonAssembler, ViewSized12RowFn&>(
    position::PositionSolver<ViewSized12, position::NewtonAssembler>*, const ModelTypes<ViewSized12>::VecQ&,
    const ModelTypes<ViewSized12>::VecQ&, int, const ModelTypes<ViewSized12>::VecQ&,
    const ModelTypes<ViewSized12>::VecQ&, const SweepOptions&, ViewSized12RowFn&);
namespace statics {
using ViewSized12RowFn = StaticsRowFn<ViewSized12>;
extern template int StaticsSweepRows<ViewSized12, position::NewtonAssembler, ViewSized12RowFn&>(
    const Options&, position::PositionSolver<ViewSized12, position::NewtonAssembler>*,
    const ModelTypes<ViewSized12>::VecQ&, const ModelTypes<ViewSized12>::VecQ&, int, const SweepOptions&,
    const ModelTypes<ViewSized12>::VecQ*, ViewSized12RowFn&);
}  // namespace statics

// ---- Dynamics (dynamics/; instantiated in runtime/view/dynamics.cc) ----
namespace dynamics {
/// The minimal method through the view, with each integrator (its sample observer: pass an
/// lvalue of ViewSampleFn<...>).
using ViewMinimalDopri5 = MinimalDynamics<ViewModel, Dopri5>;
using ViewMinimalDop853 = MinimalDynamics<ViewModel, Dop853>;

// What a program calls (the members they call are compiled with them in the library).
#define MECHGEN_VIEW_MINIMAL_MEMBERS(EXTERN, Sim)                                                              \
  EXTERN template Sim::MinimalDynamics(const ViewModel&, const ViewParams&, const MinimalOptions&, NoLoad);   \
  EXTERN template bool Sim::Initialize(const ModelTypes<ViewModel>::VecQ&);                                    \
  EXTERN template bool Sim::Initialize(const ModelTypes<ViewModel>::VecQ&, const ModelTypes<ViewModel>::VecPhi&); \
  EXTERN template bool Sim::SimulatesCoulomb(const ModelTypes<ViewModel>::VecQ&);
MECHGEN_VIEW_MINIMAL_MEMBERS(extern, ViewMinimalDopri5)
MECHGEN_VIEW_MINIMAL_MEMBERS(extern, ViewMinimalDop853)
/// sim->Simulate(t0, q0, qd0, t_end, observer, summary, last), compiled in the library (a
/// function, not an inline member: the event loop and the integrator are not compiled again
/// where it is called).
/// sim->Derivative(t, y, dy) and sim->Evaluate(t, y, s), compiled in the library (as
/// SimulateFree below).
bool DerivativeOf(ViewMinimalDopri5* sim, double t, const ViewMinimalDopri5::State& y, ViewMinimalDopri5::State* dy);
bool DerivativeOf(ViewMinimalDop853* sim, double t, const ViewMinimalDop853::State& y, ViewMinimalDop853::State* dy);
bool EvaluateAt(ViewMinimalDopri5* sim, double t, const ViewMinimalDopri5::State& y, Sample<ViewModel>* s);
bool EvaluateAt(ViewMinimalDop853* sim, double t, const ViewMinimalDop853::State& y, Sample<ViewModel>* s);
bool SimulateFree(ViewMinimalDopri5* sim, double t0, const ModelTypes<ViewModel>::VecQ& q0,
                  const ModelTypes<ViewModel>::VecQ& qd0, double t_end, ViewSampleFn<ViewMinimalDopri5>& observer,
                  MinimalSummary* summary, Sample<ViewModel>* last);
bool SimulateFree(ViewMinimalDop853* sim, double t0, const ModelTypes<ViewModel>::VecQ& q0,
                  const ModelTypes<ViewModel>::VecQ& qd0, double t_end, ViewSampleFn<ViewMinimalDop853>& observer,
                  MinimalSummary* summary, Sample<ViewModel>* last);


/// The driven motion through the view (dynamics/prescribed.h: `mechgen_view simulate --drive`,
/// a study's drive:): the driven inputs and their laws (AnyDrive) known at run time, with
/// each integrator (its sample observer: pass an lvalue of ViewSampleFn<...>).
using ViewDrive = AnyDrive<Eigen::Dynamic>;
using ViewPrescribedDopri5 = PrescribedDynamics<ViewModel, Eigen::Dynamic, ViewDrive, NoForce, Dopri5>;
using ViewPrescribedDop853 = PrescribedDynamics<ViewModel, Eigen::Dynamic, ViewDrive, NoForce, Dop853>;
using ViewPrescribedSample = PrescribedSample<ViewModel, Eigen::Dynamic>;
// (The constructor is not among them: it sets up the index lists only, and GCC emitted no
// symbol for its explicit instantiation, so that a caller compiled at -O1 did not link; each
// caller instantiates it.)
#define MECHGEN_VIEW_PRESCRIBED_MEMBERS(EXTERN, Sim) \
  EXTERN template bool Sim::SimulatesCoulombAt(const ModelTypes<ViewModel>::VecQ&);
MECHGEN_VIEW_PRESCRIBED_MEMBERS(extern, ViewPrescribedDopri5)
MECHGEN_VIEW_PRESCRIBED_MEMBERS(extern, ViewPrescribedDop853)
/// sim->Initialize(t0, qf0), compiled in the library.
bool InitializePrescribed(ViewPrescribedDopri5* sim, double t0, const ViewPrescribedDopri5::VecF& qf0);
bool InitializePrescribed(ViewPrescribedDop853* sim, double t0, const ViewPrescribedDop853::VecF& qf0);
/// sim->Simulate(t0, qf0, qdf0, t_end, observer, summary, last), compiled in the library (as
/// SimulateFree).
bool SimulatePrescribed(ViewPrescribedDopri5* sim, double t0, const ViewPrescribedDopri5::VecF& qf0,
                        const ViewPrescribedDopri5::VecF& qdf0, double t_end,
                        ViewSampleFn<ViewPrescribedDopri5>& observer, PrescribedSummary* summary,
                        ViewPrescribedSample* last);
bool SimulatePrescribed(ViewPrescribedDop853* sim, double t0, const ViewPrescribedDop853::VecF& qf0,
                        const ViewPrescribedDop853::VecF& qdf0, double t_end,
                        ViewSampleFn<ViewPrescribedDop853>& observer, PrescribedSummary* summary,
                        ViewPrescribedSample* last);
extern template table::Columns<CsvRow<ViewPrescribedSample>>
DrivenColumns<ViewModel, ViewPrescribedSample, ViewPrescribedDopri5::Indices>(const ViewPrescribedDopri5::Indices&,
                                                                              bool, const ViewModel&);

extern template class Kinetostatics<ViewModel>;
extern template table::Columns<CsvRow<Sample<ViewModel>>> FreeColumns<ViewModel, Sample<ViewModel>, true>(
    bool, const ViewModel&);
extern template std::vector<std::pair<int, std::string>> RevoluteMagnitudes<ViewModel>(const ViewModel&);
}  // namespace dynamics
}  // namespace mechgen
