// The design study (mechgen/analysis/study.h) instantiated for the model view: declared in
// mechgen/analysis/view_analysis.h; apart from runtime/view/analysis.cc (its own translation
// unit: the study's Study<ViewModel> and the statistics compile beside the other analyses).
#include "mechgen/analysis/view_analysis.h"

namespace mechgen::analysis {

template std::string Check<ViewModel>(const ViewModel&, const StudyRequest&, const StudyOutputs&);
template int Run<ViewModel>(const ViewModel&, const StudyRequest&, const StudyOutputs&, const StudyRanks&);

}  // namespace mechgen::analysis

// The whole Study<ViewModel> (extern in view_analysis.h): the tests that run a study through
// the view (tests/study) compile none of it.
template class mechgen::study::Study<mechgen::ViewModel>;
