/**
 * \file core/view_runtime.h
 * The runtime instantiated once for the model view (issue 43): the templates of the layers
 * below for M = ViewModel (core/view_model.h), compiled into the library mechgen_runtime_view
 * (runtime/view/instantiations.cc). A program that includes this header and links that library
 * reaches any model through its ModelView without compiling the runtime's algorithms again:
 * the `extern template` declarations keep them out of its translation units. The same
 * templates, instantiated for a generated model's type, are the fixed-size path (embedding,
 * the per-model tools, the benchmarks): one source, two instantiations.
 */
#pragma once

#include "mechgen/core/view_model.h"
#include "mechgen/position/assembler.h"
#include "mechgen/position/solver.h"

namespace mechgen::position {
extern template class PositionSolver<ViewModel, NewtonAssembler>;
}  // namespace mechgen::position
