// The table of the tools' option parsers (tool_args.h). Adding a tool whose
// runtime/tools/<tool>_args.h declares
//   namespace mechgen::<tool>_tool {
//   int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments*);
//   }
// takes its #include below, one line in kParsers ({"<tool>", Parse<<tool>_tool::Arguments,
// <tool>_tool::ParseArguments>}) and its <tool>_args.cc in MECHGEN_TOOL_ARGS_SOURCES
// (generator/CMakeLists.txt). A parser with more model-independent arguments (the sweep's
// --steps bound) gets a small function of its own, as the sweep's below.
#include "driver/tool_args.h"

#include <string>
#include <vector>

#include "engine_args.h"
#include "flywheel_args.h"
#include "simulate_args.h"
#include "statics_args.h"
#include "study_args.h"
#include "sweep_args.h"
#include "synthesize_args.h"

namespace mechgen {
namespace {

using ParseFn = int (*)(int argc, char** argv, const std::string& model_name);

// A parser of the usual form, its Arguments thrown away: only the verdict matters here.
template <class Arguments, int (*ParseArguments)(int, char**, const std::string&, Arguments*)>
int Parse(int argc, char** argv, const std::string& model_name) {
  Arguments arguments;
  return ParseArguments(argc, argv, model_name, &arguments);
}

int ParseSweep(int argc, char** argv, const std::string& model_name) {
  sweep_tool::Arguments arguments;
  return sweep_tool::ParseArguments(argc, argv, model_name, sweep_tool::kMaxSteps, &arguments);
}

// The flywheel's bound on its check's samples is the simulator's (flywheel_args.h).
int ParseFlywheel(int argc, char** argv, const std::string& model_name) {
  flywheel_tool::Arguments arguments;
  return flywheel_tool::ParseArguments(argc, argv, model_name, flywheel_tool::kMaxCheckSamples, &arguments);
}

// Whether the model has a design section is the engine tool's check (after the compile):
// here --design is let through.
int ParseEngine(int argc, char** argv, const std::string& model_name) {
  engine_tool::Arguments arguments;
  return engine_tool::ParseArguments(argc, argv, model_name, /*model_has_design=*/true, &arguments);
}

struct ToolParser {
  const char* tool;
  ParseFn parse;
};

constexpr ToolParser kParsers[] = {
    {"sweep", ParseSweep},
    {"simulate", Parse<simulate_tool::Arguments, simulate_tool::ParseArguments>},
    {"statics", Parse<statics_tool::Arguments, statics_tool::ParseArguments>},
    {"flywheel", ParseFlywheel},
    {"engine", ParseEngine},
    {"study", Parse<study_tool::Arguments, study_tool::ParseArguments>},
    {"synthesize", Parse<synthesize_tool::Arguments, synthesize_tool::ParseArguments>},
};

ParseFn Find(const std::string& tool) {
  for (const ToolParser& p : kParsers)
    if (tool == p.tool) return p.parse;
  return nullptr;
}

}  // namespace

int ParseToolOptions(const std::string& tool, const std::string& argv0, const std::string& model_name,
                     const std::vector<std::string>& args) {
  const ParseFn parse = Find(tool);
  if (parse == nullptr) return -1;
  std::vector<std::string> words = {argv0};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(&w[0]);
  argv.push_back(nullptr);
  return parse(static_cast<int>(words.size()), argv.data(), model_name);
}

}  // namespace mechgen
