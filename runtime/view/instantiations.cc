// The runtime's templates instantiated for the model view, once (core/view_runtime.h): the
// library mechgen_runtime_view.
//
// (GCC's -Wmaybe-uninitialized sees SquareFactorization<Dynamic> copy the inverse of a fixed-size
// factorization that Eigen's closed-form inverse (computeInverseAndDetWithCheck) leaves unwritten
// for a singular matrix; ok() is false then and the copy is never read. The fixed-size
// instantiations inline the same code without the copy and without the warning.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "mechgen/core/view_runtime.h"

namespace mechgen {
namespace position {
template class PositionSolver<ViewModel, NewtonAssembler>;
template void ComputeMotion<ViewModel>(const State<ViewModel>&, const ModelTypes<ViewModel>::VecQ&,
                                       const ModelTypes<ViewModel>::VecQ&, Motion<ViewModel>*);
}  // namespace position

template int SweepRows<ViewModel, position::NewtonAssembler, ViewRowFn&>(
    ViewPositionSolver*, const ModelTypes<ViewModel>::VecQ&, const ModelTypes<ViewModel>::VecQ&, int,
    const ModelTypes<ViewModel>::VecQ&, const ModelTypes<ViewModel>::VecQ&, const SweepOptions&, ViewRowFn&);
template std::vector<SweepColumn<ViewModel>> SweepColumns<ViewModel>(const ViewModel&);
template void AppendDesignColumns<ViewModel>(const ViewModel&, std::vector<SweepColumn<ViewModel>>*);
template class MotionSummaryBuilder<ViewModel>;
}  // namespace mechgen
