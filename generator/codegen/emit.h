// Emission: renders the function descriptions (function_spec.h) and the model's sizes,
// names and documentation into templates/mechanism.{h,cc}.mustache and the model view
// (mechgen/core/model_view.h) into templates/mechanism_view.cc.mustache, and writes <name>.h,
// <name>.cc and <name>_view.cc, all or none (written to temporaries, then renamed).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "codegen/cxx_code.h"
#include "codegen/function_spec.h"
#include "analysis/kinematics.h"
#include "model/model.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"
#include "analysis/topology.h"

namespace mechgen {

struct EmittedModel {
  std::string header, source;            ///< file contents
  std::string view;                      ///< <name>_view.cc: the model view
  std::map<std::string, OpCounts> ops;   ///< per generated function (after CSE)
  OpCounts Ops(const std::string& function) const {
    const auto it = ops.find(function);
    return it == ops.end() ? OpCounts{} : it->second;
  }
};

/// The C++ body of one function: "// Total ops", `using std::f;` for the math functions
/// it calls, `(void)arg;` for the arguments it does not use, then its programs.
std::string RenderBody(const FunctionSpec& f, CxxPrinter* printer, OpCounts* ops);

/// Renders the three files. Fails (std::runtime_error) when a template names a value the
/// generator does not provide, or is malformed.
EmittedModel Emit(const Model& m, const Topology& t, const Kinematics& k, const SymbolicTable& table,
                  const std::vector<TransmissionAngle>& transmission, const std::vector<FunctionSpec>& functions,
                  CxxPrinter* printer, const std::string& templates_dir);

/// Writes the three files into `dir`, all or none; returns false with *error set.
bool WriteFiles(const std::string& dir, const std::string& name, const EmittedModel& e,
                std::string* error);

}  // namespace mechgen
