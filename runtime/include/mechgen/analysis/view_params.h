// The parameter options (--params FILE, --set name=value; analysis/params.h) on a model reached
// through its view (core/view_model.h): the view's table names the free parameters and the
// derived ones, and fill_derived recomputes the derived after the free ones are set. The
// messages are those of a generated model's tool, word for word.
//
// ApplyModelParameters and ChangedModelParameters take the model (a generated Model, or a
// ViewModel) so that a tool's source written once (tools/<tool>_run.h) serves both.
#pragma once

#include <string>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/view_model.h"
#include "mechgen/analysis/params.h"

namespace mechgen::tools {
namespace params_internal {

/// The model view's parameters as the functions of params.h read a parameter table.
struct ViewTable {
  const ModelView* view;
  ViewParams* params;
  std::string NameList() const {
    std::string list;
    for (int i = 0; i < view->num_free_params; ++i) list += (list.empty() ? "" : ", ") + std::string(view->params[i].name);
    return list.empty() ? "(none)" : list;
  }
  bool IsDerived(const std::string& name) const {
    const int i = FindParameter(*view, name.c_str());
    return i >= view->num_free_params;
  }
  double* Find(const std::string& name) const {
    const int i = FindParameter(*view, name.c_str());
    return i >= 0 && i < view->num_free_params ? &params->values[static_cast<size_t>(i)] : nullptr;
  }
  void Finish() const {
    if (view->fill_derived != nullptr) view->fill_derived(params->data());
  }
};

}  // namespace params_internal

/// --params then each --set onto the model's parameters (a generated model's Params, or a
/// view's table); false and *error (one line) on the first problem.
template <class M>
bool ApplyModelParameters(const ParameterOptions& options, const M& model, typename ModelTypes<M>::Params* params,
                          std::string* error) {
  if constexpr (ModelCalls<M>::kView) {
    return params_internal::Apply(options, params_internal::ViewTable{model.view, params}, error);
  } else {
    (void)model;
    return ApplyParameters(options, params, error);
  }
}

/// The free parameters that differ from the model's defaults, as ChangedParameters prints them.
template <class M>
std::string ChangedModelParameters(const M& model, const typename ModelTypes<M>::Params& params) {
  if constexpr (ModelCalls<M>::kView) {
    const ModelView& v = *model.view;
    std::string text;
    for (int i = 0; i < v.num_free_params; ++i)
      params_internal::AppendChanged(&text, v.params[i].name, params.values[static_cast<size_t>(i)],
                                     v.params[i].default_value);
    return text;
  } else {
    (void)model;
    return ChangedParameters(params);
  }
}

}  // namespace mechgen::tools
