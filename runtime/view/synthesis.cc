// The synthesis layer and the synthesis analysis (analysis/synthesize.h) instantiated for the
// model view, once (synthesis/view_synthesis.h): the library mechgen_runtime_view_synthesis.
#include "mechgen/synthesis/view_synthesis.h"

#include "mechgen/core/view_runtime.h"  // the position solver's instantiation: not compiled again here

namespace mechgen::synthesis {

template bool SynthesizeMotion<ViewModel>(const ViewModel&, const MotionTask&, const ViewParams&, MotionResult*,
                                          std::string*);
template bool BindExactTask<ViewModel>(const ViewModel&, const ExactTask&, const ViewParams&, BoundExact<ViewModel>*,
                                       std::string*);
template ExactRun RunExactTask<ViewModel>(const BoundExact<ViewModel>&, const std::string&, const std::string&,
                                          std::vector<std::pair<std::string, std::string>>*, const ExactPathOptions&);
template bool WriteSynthesizedModel<ViewModel>(const ViewModel&, const std::string&, const ViewParams&,
                                               const std::vector<std::string>&, const std::vector<double>&,
                                               std::string*, WrittenAssembly*, std::string*,
                                               const ModelCalls<ViewModel>::Modes*);
template std::string SetParametersText<ViewModel>(const ViewModel&, const ViewParams&, const std::vector<std::string>&);
template std::string WrittenModelText<ViewModel>(const ViewModel&, const WrittenAssembly&, const ViewParams&);

template class PathEvaluator<ViewModel>;
template bool BindPathTask<ViewModel>(const ViewModel&, const PathTask&, const ViewParams&, BoundPath<ViewModel>*,
                                   std::string*);
template bool SynthesizePath<ViewModel>(const BoundPath<ViewModel>&, uint64_t, int, SearchResult*, std::string*,
                                     const std::function<void(int, int)>&);
template std::string ContinuationCheck<ViewModel>(PathEvaluator<ViewModel>*, const Candidate&);
template std::string Report<ViewModel>(PathEvaluator<ViewModel>*, const SearchResult&, const std::string&, uint64_t, int,
                                    double, double, const std::string&);
template std::string CurveSvg<ViewModel>(PathEvaluator<ViewModel>*, const Candidate&, int);

template class FunctionEvaluator<ViewModel>;
template bool BindFunctionTask<ViewModel>(const ViewModel&, const FunctionTask&, const ViewParams&,
                                          BoundFunction<ViewModel>*, std::string*);
template FunctionResult SynthesizeFunction<ViewModel>(const BoundFunction<ViewModel>&, uint64_t, int);
template std::string FunctionReport<ViewModel>(const BoundFunction<ViewModel>&, const FunctionResult&, uint64_t, int);
template void FunctionModelParameters<ViewModel>(const BoundFunction<ViewModel>&, const FunctionCandidate&,
                                                 std::vector<std::string>*, std::vector<double>*);
template std::vector<double> FunctionWrittenInputs<ViewModel>(const BoundFunction<ViewModel>&, const FunctionCandidate&);
template std::string FunctionSvg<ViewModel>(FunctionEvaluator<ViewModel>*, const FunctionCandidate&, int);

}  // namespace mechgen::synthesis

namespace mechgen::analysis {

template std::string Check<ViewModel>(const ViewModel&, const SynthesizeRequest&);
template int Run<ViewModel>(const ViewModel&, const SynthesizeRequest&, const SynthesizeOutputs&);

}  // namespace mechgen::analysis
