// The options of `mechgen <tool> MODEL [options]` answered before anything is generated or
// compiled: each tool's command line is parsed by its own model-independent parser
// (runtime/tools/<tool>_args.cc, the code the tool itself runs first), linked into mechgen,
// so that --help and a usage error need no model, no compiler and no cache. A tool whose
// parser is not in the table (tool_args.cc) is parsed only by its driver, after the compile.
#pragma once

#include <string>
#include <vector>

namespace mechgen {

/// Parses `args` (the options after the model) with `tool`'s own parser, its argv[0] being
/// `argv0` (the tool's name in messages) and `model_name` the model in its --help. Returns -1
/// to go on (the options parse, or the tool has no parser here), else the exit status to end
/// with: 0 after --help (printed on stdout), 2 after a usage error (one line
/// "<tool>: error: ..." on stderr). Checks that need the model (an input's or a parameter's
/// name, a count per input) are left to the tool.
int ParseToolOptions(const std::string& tool, const std::string& argv0, const std::string& model_name,
                     const std::vector<std::string>& args);

}  // namespace mechgen
