/**
 * \file synthesis/view_synthesis.h
 * The synthesis layer instantiated once for the model view (issue 43): its functions that read
 * the model (through ModelCalls<M>) for M = ViewModel (core/view_model.h), compiled into the
 * library mechgen_runtime_view_synthesis (runtime/view/synthesis.cc, with Ceres and yaml-cpp,
 * which the synthesis layer includes). A program that includes this header and links that
 * library runs these kinds of synthesis on any model through its ModelView without compiling
 * them again (mechgen_view synthesize: the synthesis analysis, analysis/synthesize.h); the same
 * templates instantiated for a generated model's type are the per-model <model>_synthesize.
 *
 * Instantiated: path generation (BindPathTask, SynthesizePath: the global and local stages or
 * the projection, PathEvaluator, ContinuationCheck, Report, CurveSvg; the local stage's Jacobian
 * from the view's design derivatives, ModelCalls<ViewModel>::Design), motion generation
 * (SynthesizeMotion: the Burmester pairs and their four-bars checked on the model, beyond five
 * poses the least squares on the design derivatives, four poses the curves), exact path synthesis (BindExactTask, RunExactTask: every real solution
 * checked on the model's kinematics and continuation), function generation (BindFunctionTask,
 * SynthesizeFunction: the exact start, Levenberg-Marquardt on the view's design derivatives,
 * differential evolution and the minimax exchange; FunctionEvaluator, FunctionReport,
 * FunctionModelParameters, FunctionWrittenInputs, FunctionSvg), and the synthesized model file
 * and its report lines (WriteSynthesizedModel, SetParametersText, WrittenModelText); and the
 * synthesis analysis on them (analysis/synthesize.h: Check, Run; declared for the view in
 * analysis/synthesize_view.h, which mechgen_view synthesize includes without this header), here
 * rather than in analysis/view_analysis.h's library because it needs the synthesis layer.
 */
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/analysis/synthesize.h"
#include "mechgen/analysis/synthesize_view.h"  // the analysis's Check and Run for the view
#include "mechgen/core/view_model.h"
#include "mechgen/synthesis/exact.h"
#include "mechgen/synthesis/function.h"
#include "mechgen/synthesis/motion.h"
#include "mechgen/synthesis/output.h"
#include "mechgen/synthesis/path.h"
#include "mechgen/synthesis/projection.h"
#include "mechgen/synthesis/report.h"

namespace mechgen::synthesis {

extern template bool SynthesizeMotion<ViewModel>(const ViewModel&, const MotionTask&, const ViewParams&, MotionResult*,
                                                 std::string*);
extern template bool BindExactTask<ViewModel>(const ViewModel&, const ExactTask&, const ViewParams&,
                                              BoundExact<ViewModel>*, std::string*);
extern template ExactRun RunExactTask<ViewModel>(const BoundExact<ViewModel>&, const std::string&, const std::string&,
                                                 std::vector<std::pair<std::string, std::string>>*,
                                                 const ExactPathOptions&);
extern template bool WriteSynthesizedModel<ViewModel>(const ViewModel&, const std::string&, const ViewParams&,
                                                      const std::vector<std::string>&, const std::vector<double>&,
                                                      std::string*, WrittenAssembly*, std::string*,
                                                      const ModelCalls<ViewModel>::Modes*);
extern template std::string SetParametersText<ViewModel>(const ViewModel&, const ViewParams&,
                                                         const std::vector<std::string>&);
extern template std::string WrittenModelText<ViewModel>(const ViewModel&, const WrittenAssembly&, const ViewParams&);

extern template class PathEvaluator<ViewModel>;
extern template bool BindPathTask<ViewModel>(const ViewModel&, const PathTask&, const ViewParams&, BoundPath<ViewModel>*,
                                   std::string*);
extern template bool SynthesizePath<ViewModel>(const BoundPath<ViewModel>&, uint64_t, int, SearchResult*, std::string*,
                                     const std::function<void(int, int)>&);
extern template std::string ContinuationCheck<ViewModel>(PathEvaluator<ViewModel>*, const Candidate&);
extern template std::string Report<ViewModel>(PathEvaluator<ViewModel>*, const SearchResult&, const std::string&, uint64_t, int,
                                    double, double, const std::string&);
extern template std::string CurveSvg<ViewModel>(PathEvaluator<ViewModel>*, const Candidate&, int);

extern template class FunctionEvaluator<ViewModel>;
extern template bool BindFunctionTask<ViewModel>(const ViewModel&, const FunctionTask&, const ViewParams&,
                                                 BoundFunction<ViewModel>*, std::string*);
extern template FunctionResult SynthesizeFunction<ViewModel>(const BoundFunction<ViewModel>&, uint64_t, int);
extern template std::string FunctionReport<ViewModel>(const BoundFunction<ViewModel>&, const FunctionResult&, uint64_t,
                                                      int);
extern template void FunctionModelParameters<ViewModel>(const BoundFunction<ViewModel>&, const FunctionCandidate&,
                                                        std::vector<std::string>*, std::vector<double>*);
extern template std::vector<double> FunctionWrittenInputs<ViewModel>(const BoundFunction<ViewModel>&,
                                                                     const FunctionCandidate&);
extern template std::string FunctionSvg<ViewModel>(FunctionEvaluator<ViewModel>*, const FunctionCandidate&, int);

}  // namespace mechgen::synthesis
