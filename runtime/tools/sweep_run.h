// The sweep command around the sweep analysis (mechgen/analysis/sweep.h: Check, Run): the
// parsed options (sweep_args.h) are the analysis's SweepRequest and where its outputs go. The
// per-model tool <model>_sweep (sweep_main.cc) runs analysis::Run on the generated model's
// type (fixed sizes); mechgen_view sweep (view/sweep.cc) on the model view, instantiated once
// in mechgen_runtime_view (runtime/view/analysis.cc). Nothing here depends on the model.
#pragma once

#include "mechgen/analysis/sweep_request.h"
#include "sweep_args.h"

namespace mechgen::sweep_tool {

// Exit statuses (models/README.md, "Exit statuses of the sweep"; analysis/sweep_request.h):
constexpr int kExitConverged = analysis::kSweepConverged;    // every row converged; the outputs written
constexpr int kExitError = analysis::kSweepError;            // model or output error: nothing written
constexpr int kExitRowsFailed = analysis::kSweepRowsFailed;  // the outputs written, some rows did not converge
// kExitUsage = 2 (sweep_args.h): bad arguments, nothing written (one line on stderr).
static_assert(kExitUsage == analysis::kSweepUsage);

/// Where the options send the sweep's outputs; `assembler_name` names the solver's assembler in
/// the summary line ("Ceres", "Levenberg-Marquardt").
inline analysis::SweepOutputs Outputs(const Arguments& arguments,
                                      const char* assembler_name = "Levenberg-Marquardt") {
  analysis::SweepOutputs outputs;
  outputs.tool = arguments.tool;
  outputs.csv_path = arguments.csv_path;
  outputs.svg_path = arguments.svg_path;
  outputs.animate = !arguments.no_animation;
  outputs.assembler_name = assembler_name;
  return outputs;
}

}  // namespace mechgen::sweep_tool
