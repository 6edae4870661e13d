// The statics (statics/) instantiated for the model view, once (core/view_runtime.h): part of
// the library mechgen_runtime_view.
//
// (-Wmaybe-uninitialized: as in instantiations.cc, the fixed-size factorizations the view's
// condition number dispatches to.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "mechgen/core/view_runtime.h"

namespace mechgen::statics {

template struct Solution<ViewModel>;
template Status Solve<ViewModel>(const ViewModel&, const Options&, const ViewParams&, const ViewVecQ&,
                                 const ModelTypes<ViewModel>::VecPhi&, const ModelTypes<ViewModel>::Coefficients&,
                                 const ViewVecQ&, Solution<ViewModel>*, const ViewVecQ*);
template Status SolveAt<ViewModel>(const ViewModel&, const Options&, const ViewParams&,
                                   const position::State<ViewModel>&, const ViewVecQ&, Solution<ViewModel>*,
                                   const ViewVecQ*);
template Status AnalyzeDriveAt<ViewModel>(const ViewModel&, const Options&, const ViewParams&,
                                          const position::State<ViewModel>&, int, DriveAnalysis*,
                                          Solution<ViewModel>*, Solution<ViewModel>*, Solution<ViewModel>*);
template Status EvaluateRecord<ViewModel>(const ViewModel&, const Options&, const ViewParams&,
                                          StaticsRecord<ViewModel>*, const ViewVecQ*);
template int StaticsSweepRows<ViewModel, position::NewtonAssembler, ViewStaticsRowFn&>(
    const Options&, ViewPositionSolver*, const ViewVecQ&, const ViewVecQ&, int, const SweepOptions&,
    const ViewVecQ*, ViewStaticsRowFn&);
template Status FindDeadZones<ViewModel, position::NewtonAssembler>(const Options&, const ScanOptions&,
                                                                    ViewPositionSolver*, int, double, double,
                                                                    std::vector<DeadZone>*, ScanSummary*);
template Status FindEquilibria<ViewModel, position::NewtonAssembler>(const Options&, const ScanOptions&,
                                                                     ViewPositionSolver*, const ViewVecQ&,
                                                                     const ViewVecQ&,
                                                                     std::vector<Equilibrium<ViewModel>>*,
                                                                     ScanSummary*);
template std::vector<StaticsColumn<ViewModel>> StaticsColumns<ViewModel>(const ViewModel&, bool);
template std::vector<ReactionJoint> ReactionJoints<ViewModel>(const ViewModel&);
template std::vector<GroundBearing> GroundBearings<ViewModel>(const ViewModel&);
template std::string SpeedNote<ViewModel>(const ViewModel&, const ViewVecQ*);

}  // namespace mechgen::statics
