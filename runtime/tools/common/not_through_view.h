// What a command does not do through the model view yet (issue 43): one refusal for every
// <command>_run.h, so that `mechgen <command> MODEL` can fall back to the per-model program.
//
// Run by hand (mechgen_view COMMAND MODEL.so ...), a refusal is a usage error: one line
// "<tool>: error: <what>; <model>_<command> has it" (the study: "`mechgen study` on the model's
// file has it"), exit 2, nothing written. Run by
// `mechgen <command> MODEL` (which sets MECHGEN_VIEW_FALLBACK=1 in mechgen_view's environment),
// it prints nothing and exits kExitNotThroughView, before anything is computed or written:
// mechgen then builds and runs the per-model program with the same arguments.
#pragma once

#include <cstdlib>
#include <cstring>
#include <string>

#include "numbers.h"

namespace mechgen::tools {

/// mechgen_view's exit status for "not through the view": mechgen runs the per-model program.
constexpr int kExitNotThroughView = 120;
/// Set (to 1) by mechgen in mechgen_view's environment: refusals exit kExitNotThroughView.
constexpr const char* kViewFallbackVariable = "MECHGEN_VIEW_FALLBACK";

/// The refusal of `what` (e.g. "--design: the design derivatives") by `tool` through the view
/// of the model `model` for `command` ("sweep"): the exit status to end with.
inline int NotThroughView(const std::string& tool, const std::string& what, const std::string& model,
                          const std::string& command) {
  const char* fallback = std::getenv(kViewFallbackVariable);
  if (fallback != nullptr && std::strcmp(fallback, "1") == 0) return kExitNotThroughView;
  // The per-model program that has it: <model>_<command> (mechgen_add_model), except the
  // study's, which only `mechgen study` builds (in its cache; no CMake target is named so).
  const std::string where = command == "study" ? "`mechgen study` on the model's file has it (its per-model program)"
                                               : model + "_" + command + " has it";
  return UsageError(tool, what + " not reached through the model view yet; " + where);
}

}  // namespace mechgen::tools
