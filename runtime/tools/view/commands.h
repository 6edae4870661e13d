// The commands of mechgen_view (view/main.cc), each the model-dependent part of a per-model
// tool (<model>_sweep, <model>_statics, ...) run on the runtime instantiated once for the model
// view (mechgen_runtime_view, core/view_runtime.h). Each takes the loaded model's view and the
// command's own arguments (argv[0] the program's name as the command's messages print it) and
// returns the per-model tool's exit status.
#pragma once

#include "mechgen/core/model_view.h"

namespace mechgen {
namespace view_tool {

/// A command of mechgen_view: its name and its function.
struct Command {
  const char* name;
  int (*run)(const ModelView& view, int argc, char** argv);
};

int Sweep(const ModelView& view, int argc, char** argv);  // view/sweep.cc
int Statics(const ModelView& view, int argc, char** argv);  // view/statics.cc
int Simulate(const ModelView& view, int argc, char** argv);  // view/simulate.cc
int Engine(const ModelView& view, int argc, char** argv);  // view/engine.cc
int Flywheel(const ModelView& view, int argc, char** argv);  // view/flywheel.cc
int Study(const ModelView& view, int argc, char** argv);  // view/study.cc
int Synthesize(const ModelView& view, int argc, char** argv);  // view/synthesize.cc

/// The commands, in the order `mechgen_view --help` lists them.
inline constexpr Command kCommands[] = {
    {"sweep", Sweep},
    {"statics", Statics},
    {"simulate", Simulate},
    {"engine", Engine},
    {"flywheel", Flywheel},
    {"study", Study},
    {"synthesize", Synthesize},
};

}  // namespace view_tool
}  // namespace mechgen
