// The sweep and the statics of a view of one input and two dependent coordinates (the four-bars
// and slider-cranks) on the runtime instantiated at those sizes (core/view_sized.h): the same
// analyses (analysis/sweep.h, statics.h) as for any view, their continuation step and statics
// in fixed-size arithmetic. analysis::Run<ViewModel> comes here first (RunSized).
//
// (-Wmaybe-uninitialized: as in instantiations.cc, Eigen's closed-form inverse of a singular
// fixed-size matrix, never read then.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "mechgen/analysis/view_analysis.h"
#include "mechgen/core/view_sized.h"

namespace mechgen {
namespace position {
template class PositionSolver<ViewSized12, NewtonAssembler>;
}  // namespace position
template int SweepRows<ViewSized12, position::NewtonAssembler, ViewSized12RowFn&>(
    position::PositionSolver<ViewSized12, position::NewtonAssembler>*, const ModelTypes<ViewSized12>::VecQ&,
    const ModelTypes<ViewSized12>::VecQ&, int, const ModelTypes<ViewSized12>::VecQ&,
    const ModelTypes<ViewSized12>::VecQ&, const SweepOptions&, ViewSized12RowFn&);
namespace statics {
template int StaticsSweepRows<ViewSized12, position::NewtonAssembler, ViewSized12RowFn&>(
    const Options&, position::PositionSolver<ViewSized12, position::NewtonAssembler>*,
    const ModelTypes<ViewSized12>::VecQ&, const ModelTypes<ViewSized12>::VecQ&, int, const SweepOptions&,
    const ModelTypes<ViewSized12>::VecQ*, ViewSized12RowFn&);
}  // namespace statics
}  // namespace mechgen

namespace mechgen::analysis {
namespace {
using Sized12 = ViewSized12;
bool Sized(const ViewModel& model) { return model.sized && Sized12::Fits(model); }
}  // namespace

bool RunSized(const ViewModel& model, const SweepRequest& request, const SweepOutputs& outputs, int* status) {
  if (!Sized(model)) return false;
  *status = Run<Sized12, position::NewtonAssembler>(Sized12(model), request, outputs);
  return true;
}

bool RunSized(const ViewModel& model, const StaticsRequest& request, const StaticsOutputs& outputs,
              const std::function<int()>& prepare, StaticsPlotFacts* facts, int* status) {
  if (!Sized(model)) return false;
  *status = Run<Sized12, position::NewtonAssembler>(Sized12(model), request, outputs, prepare, facts);
  return true;
}

}  // namespace mechgen::analysis
