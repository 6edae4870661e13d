// `mechgen sweep <model.yaml> [sweep options...]`: the sweep command of any model file, with
// no CMake project. Generates the model's code, compiles the sweep driver
// (runtime/tools/sweep_main.cc, Ceres-free: -DMECHGEN_SWEEP_NO_CERES) against it with the
// system's C++ compiler, keeps the program in a cache keyed by everything it was built from,
// and runs it with the options that follow the model: the same options, table, CSV and SVG
// as the <model>_sweep of mechgen_add_model().
//
// The cache: $MECHGEN_CACHE_DIR, else $XDG_CACHE_HOME/mechgen, else $HOME/.cache/mechgen; in
// it sweep/<key>/ per model, key = SHA-256 of the model file's bytes, the mechgen program's
// bytes, the templates, the driver's source, the runtime headers, the compiler (its path,
// size and time) and the flags. An entry is built in sweep/tmp/ and renamed into place
// whole (rename(2) is atomic), so an interrupted or failed build leaves no entry, and two
// runs at once at worst both compile (the first rename wins). The CLI11 part of the driver
// (runtime/tools/sweep_args.cc, the same for every model) is compiled once into
// sweep/args-<key>.o. Each cached program and object has its size and SHA-256 recorded
// beside it when it is built (<file>.sha256); it is checked before each use (the program
// through the descriptor that is then executed), and one that does not match (truncated,
// overwritten) is said so on stderr and built again, never run.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace mechgen {

/// What `mechgen sweep` was asked.
struct SweepCommand {
  std::string model_path;
  /// Passed to the driver unchanged (everything after the model, a leading "--" dropped).
  std::vector<std::string> driver_args;
  std::string templates;  ///< for the generation
  std::string cache_dir;  ///< empty: the default (see above)
  bool no_cache = false;  ///< build in a temporary directory, run, delete; the cache untouched
  bool rebuild = false;   ///< build again and replace the cached entry
  bool verbose = false;   ///< the cache's place, the commands and their times on stderr
};

/// Generates the code of `model_path` into the existing directory `out_dir` (<name>.h and
/// <name>.cc). Returns 0 and sets *model_name, or prints the error (file:line:column for a
/// model error) and returns the exit status.
using GenerateFn = std::function<int(const std::string& model_path, const std::string& out_dir,
                                     std::string* model_name)>;

/// Runs the command: on success this process becomes the driver (exec), so its exit status
/// is the driver's (0, 3 some rows failed, 2 bad arguments, 1 model or output error); returns
/// only on an error of its own (printed as "mechgen: error: ..."), with the exit status: that
/// of `generate` for a model error, 1 otherwise (no compiler, a failed compile, no cache
/// directory). With no_cache it runs the driver as a child and returns its status.
int RunSweep(const SweepCommand& command, const GenerateFn& generate);

/// Splits `mechgen sweep ...` (argv[first] is the first argument after "sweep") into
/// mechgen's own part (its options and the model: argv[first, *model_end)) and the driver's
/// arguments (after the model; a "--" right after it dropped). mechgen's options come before
/// the model; those listed in `options_with_value` take the next argument. *model_end =
/// argc when there is no model (the parse then reports it).
void SplitSweepArguments(int argc, const char* const* argv, int first,
                         const std::vector<std::string>& options_with_value, int* model_end,
                         std::vector<std::string>* driver_args);

}  // namespace mechgen
