// `mechgen sweep|statics|simulate|engine|flywheel|synthesize|study <model.yaml> [tool options...]`:
// the commands of any model file, with no CMake project. Generates the model's code, compiles
// the tool's driver (runtime/tools/<tool>_main.cc; Ceres-free, the runtime's Newton assembler,
// except synthesize's Levenberg–Marquardt) against it with the system's C++ compiler, keeps the
// program in a cache keyed by everything it was built from, and runs it with the options that
// follow the model: the same options, tables, CSV and pictures as the <model>_<tool> of
// mechgen_add_model() for the tools it builds. A model without what the tool
// needs (statics, flywheel: `forces`; simulate, engine: `dynamics`) is said so before anything is
// compiled.
//
// The cache: $MECHGEN_CACHE_DIR, else $XDG_CACHE_HOME/mechgen, else $HOME/.cache/mechgen; in
// it <tool>/<key>/ per model, key = SHA-256 of the model file's bytes, the mechgen program's
// bytes, the templates, the drivers' sources (runtime/tools/), the runtime headers, the
// compiler (its path, size and time) and the flags. An entry is built in <tool>/tmp/ and
// renamed into place whole (rename(2) is atomic), so an interrupted or failed build leaves no
// entry, and two runs at once at worst both compile (the first rename wins). Each tool's
// CLI11 part (runtime/tools/<tool>_args.cc, the same for every model) is compiled once into
// <tool>/args-<key>.o. Each cached program and object has its size and SHA-256 recorded
// beside it when it is built (<file>.sha256); it is checked before each use (the program
// through the descriptor that is then executed), and one that does not match (truncated,
// overwritten) is said so on stderr and built again, never run.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace mechgen {

/// The commands `mechgen <tool> MODEL` runs: "sweep", "statics", "simulate", "engine", "flywheel",
/// "synthesize", "study".
const std::vector<std::string>& ToolNames();

/// What the analysis of `tool` gives, for `mechgen --help` ("" for no such tool).
std::string ToolSummary(const std::string& tool);

/// The quantity `tool` needs among the model's (`mechgen generate --print-quantities`): "forces"
/// for statics and flywheel, "dynamics" for simulate and engine, "" for a tool that needs none
/// or no such tool. The one table of it: the driver checks it before compiling, `mechgen generate
/// --print-tools` and the manifest (--manifest) give it to mechgen_add_model()
/// (cmake/MechgenAddModel.cmake).
std::string ToolQuantity(const std::string& tool);

/// The tools (of ToolNames(), in that order) whose quantity is among `quantities`.
std::vector<std::string> ToolsFor(const std::vector<std::string>& quantities);

/// What `mechgen <tool>` was asked.
struct ToolCommand {
  std::string tool;  ///< one of ToolNames()
  std::string model_path;
  /// Passed to the driver unchanged (everything after the model, a leading "--" dropped).
  std::vector<std::string> driver_args;
  std::string templates;  ///< for the generation
  std::string cache_dir;  ///< empty: the default (see above)
  bool no_cache = false;  ///< build in a temporary directory, run, delete; the cache untouched
  bool rebuild = false;   ///< build again and replace the cached entry
  bool verbose = false;   ///< the cache's place, the commands and their times on stderr
};

/// What the generation of a model gave the driver.
struct GeneratedModel {
  std::string name;                     ///< the namespace mech::<name>, the files <name>.h/.cc
  std::vector<std::string> quantities;  ///< as `mechgen generate --print-quantities` lists them
};

/// Generates the code of `model_path` into the existing directory `out_dir` (<name>.h and
/// <name>.cc). Returns 0 and fills *model, or prints the error (file:line:column for a model
/// error) and returns the exit status.
using GenerateFn = std::function<int(const std::string& model_path, const std::string& out_dir,
                                     GeneratedModel* model)>;

/// Runs the command. First the driver's options are parsed by the tool's own parser where
/// mechgen holds it (tool_args.h): --help returns 0 (the help on stdout), a usage error 2 (one
/// line "mechgen <tool>: error: ..."), with nothing generated or compiled and the cache
/// untouched. Then, on success, this process becomes the driver (exec), so its exit status is
/// the driver's (see each tool's --help: 0 done, 2 bad arguments, ...); returns only on an
/// error of its own (printed as "mechgen: error: ..."), with the exit status: that of
/// `generate` for a model error, 1 otherwise (the model lacks what the tool needs, no
/// compiler, a failed compile, no cache directory). With no_cache it runs the driver as a
/// child and returns its status. A SIGINT, SIGTERM or SIGHUP while it builds is passed on to
/// the compilers' process groups; their temporary directory is removed and the process ends
/// by that signal (exit status 128 + signal), with no cache entry made.
int RunTool(const ToolCommand& command, const GenerateFn& generate);

/// Splits `mechgen <tool> ...` (argv[first] is the first argument after the tool) into
/// mechgen's own part (its options and the model: argv[first, *model_end)) and the driver's
/// arguments (after the model; a "--" right after it dropped). mechgen's options come before
/// the model; those listed in `options_with_value` take the next argument. *model_end =
/// argc when there is no model (the parse then reports it).
void SplitToolArguments(int argc, const char* const* argv, int first,
                         const std::vector<std::string>& options_with_value, int* model_end,
                         std::vector<std::string>* driver_args);

}  // namespace mechgen
