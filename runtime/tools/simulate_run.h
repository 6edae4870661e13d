// The simulate command around the simulation analysis (mechgen/analysis/simulate.h: Check,
// Run): the parsed options (simulate_args.h) are the analysis's SimulateRequest, and where its
// CSV and summary go. The per-model tool <model>_simulate (simulate_main.cc) runs
// analysis::Run on the generated model's type (fixed sizes; --design there:
// analysis/simulate_design.h); mechgen_view simulate (view/simulate.cc) on the model view,
// instantiated once in mechgen_runtime_view (runtime/view/analysis_simulate.cc; --design's
// trajectory sensitivities in analysis_simulate_design.cc). Through the view, --design on a
// model without the generated EvalDynamicsJacobian (a cam law's fourth derivative) is refused by
// common/not_through_view.h: a usage error naming the per-model tool that has it (its Jets), or
// for mechgen the fallback to that tool, before anything is computed or written. Nothing here
// depends on the model.
#pragma once

#include <string>

#include "common/not_through_view.h"
#include "mechgen/analysis/simulate_request.h"
#include "simulate_args.h"

namespace mechgen::simulate_tool {

/// Where the options send the simulation's CSV and summary, and how the command refuses what
/// the analysis does not do on the model (through the view: --design without the generated
/// EvalDynamicsJacobian).
inline analysis::SimulateOutputs Outputs(const Arguments& a) {
  analysis::SimulateOutputs outputs;
  outputs.tool = a.tool;
  outputs.csv = a.csv;
  outputs.quiet = a.quiet;
  outputs.not_through_view = [tool = a.tool](const std::string& what, const std::string& model) {
    return tools::NotThroughView(tool, what, model, "simulate");
  };
  return outputs;
}

}  // namespace mechgen::simulate_tool
