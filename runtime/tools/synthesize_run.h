// The synthesize command around the synthesis analysis (mechgen/analysis/synthesize.h: Check,
// Run): the parsed options (synthesize_args.h) are the analysis's SynthesizeRequest, the model
// file named by `mechgen synthesize MODEL` (argv[0]) when --model does not name it. The
// per-model tool <model>_synthesize (synthesize_main.cc) runs analysis::Run on the generated
// model's type (fixed sizes); mechgen_view synthesize (view/synthesize.cc) on the model view,
// instantiated once in mechgen_runtime_view_synthesis (runtime/view/synthesis.cc,
// synthesis/view_synthesis.h). Nothing here depends on the model. What each kind does, what it
// writes and the exit statuses: synthesize_main.cc.
#pragma once

#include <string>

#include "mechgen/analysis/synthesize_request.h"
#include "synthesize_args.h"

namespace mechgen::synthesize_tool {

/// The request the options are; `argv0` the program's argv[0]: `mechgen synthesize MODEL`
/// names the model file when --model does not (neither: Run's usage error).
inline analysis::SynthesizeRequest Request(const Arguments& arguments, const std::string& argv0) {
  analysis::SynthesizeRequest request = arguments;
  const std::string prefix = "mechgen synthesize ";
  if (request.model_path.empty() && argv0.rfind(prefix, 0) == 0) request.model_path = argv0.substr(prefix.size());
  return request;
}

/// How the analysis's messages name the command.
inline analysis::SynthesizeOutputs Outputs(const Arguments& arguments) {
  analysis::SynthesizeOutputs outputs;
  outputs.tool = arguments.tool;
  return outputs;
}

}  // namespace mechgen::synthesize_tool
