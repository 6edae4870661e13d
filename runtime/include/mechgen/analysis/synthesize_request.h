/**
 * \file analysis/synthesize_request.h
 * What a dimensional synthesis is asked for (analysis/synthesize.h runs it): the task file, the
 * model file it writes the synthesized model from, where the outputs go, the search's seed,
 * threads and budget and the model's parameters, with their defaults, independent of the model,
 * so that the command line's parser (tools/synthesize_args.cc, CLI11) fills one without
 * compiling anything model-dependent. The counts are checked by whoever fills it (the parser:
 * --seed, --threads, --evaluations); what needs the task file and the model (the task's kind,
 * its errors with FILE:LINE:COLUMN, its point and parameters on the model, the design section,
 * the parameters, the model file) Check(model, request) in analysis/synthesize.h.
 */
#pragma once

#include <string>

#include "mechgen/analysis/params.h"

namespace mechgen::analysis {

/// A synthesis task (the task file's `synthesis:` path, function or motion; `kind: exact`) on
/// the model.
struct SynthesizeRequest {
  std::string task_path;                  ///< the task file (docs/synthesis.md)
  std::string out_dir = "synthesis_out";  ///< where the outputs are written (created if needed)
  /// The model file the model was generated from: the synthesized model is its text with the
  /// values changed. Empty: a usage error (the command fills it from `mechgen synthesize MODEL`).
  std::string model_path;
  unsigned long long seed = 1;  ///< the random seed: the same seed, the same result for any threads
  int threads = 1;              ///< threads for the global stage's restarts and the exact paths
  long long evaluations = 0;    ///< the global stage's budget (0: the task's search.evaluations)
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// How the synthesis's messages name the command (its outputs go to request.out_dir).
struct SynthesizeOutputs {
  std::string tool = "synthesize";  ///< the command's name in errors and progress lines
};

}  // namespace mechgen::analysis
