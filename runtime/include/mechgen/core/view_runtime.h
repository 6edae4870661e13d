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
 * ViewRowFn, ComputeMotion), its columns (sweep/columns.h) and motion summary
 * (sweep/motion_summary.h); the statics (statics/: Solve, the drive analysis, the statics sweep
 * with a ViewStaticsRowFn, its columns, the dead-zone and equilibrium scans; not the force
 * diagram, statics/svg.h).
 */
#pragma once

#include <functional>
#include <vector>

#include "mechgen/core/view_model.h"
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

// ---- Dynamics (dynamics/; instantiated in runtime/view/dynamics.cc) ----
}  // namespace mechgen
