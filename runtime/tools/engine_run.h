// The engine command around the engine analyses (mechgen/analysis/engine.h: Check, Run): the
// parsed options (engine_args.h) are the analysis's EngineRequest and where its CSVs go. The
// per-model tool <model>_engine (engine_main.cc) runs analysis::Run on the generated model's
// type (fixed sizes); mechgen_view engine (view/engine.cc) on the model view, instantiated
// once in mechgen_runtime_view (runtime/view/analysis.cc). Nothing here depends on the model.
#pragma once

#include "engine_args.h"
#include "mechgen/analysis/engine_request.h"

namespace mechgen::engine_tool {

/// Where the options send the engine's CSVs.
inline analysis::EngineOutputs Outputs(const Arguments& a) {
  analysis::EngineOutputs outputs;
  outputs.tool = a.tool;
  outputs.csv = a.csv;
  outputs.loop_csv = a.loop_csv;
  outputs.sweep_csv = a.sweep_csv;
  outputs.witt_csv = a.witt_csv;
  return outputs;
}

}  // namespace mechgen::engine_tool
