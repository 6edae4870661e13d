// mechgen_sweep_view MODEL.so [sweep options]: the sweep command of any model, through the
// runtime compiled once (issue 43). MODEL.so is a shared object built from a generated model's
// <name>.cc and <name>_view.cc with -DMECHGEN_VIEW_ENTRY, e.g.
//   g++ -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I<dir of name.h> -Iruntime/include
//       -I/usr/include/eigen3 fourbar.cc fourbar_view.cc -o fourbar.so
// It loads the object (dlopen), takes its view from the entry point mechgen_model_view()
// (mechgen::kModelViewEntry), refuses a view of another layout or size (exit 1), and runs
// RunSweep<ViewModel> (sweep_run.h, the source of every <model>_sweep tool) on the runtime
// instantiated for the view (mechgen_runtime_view). The options are the sweep tool's
// (sweep_args.h); what the view does not do yet (--svg, --mode, --design, --params/--set) is a
// usage error. Exit statuses as <model>_sweep's; 1 also for an object that cannot be loaded.
#include <dlfcn.h>

#include <cstdio>
#include <string>
#include <vector>

#include "mechgen/core/view_runtime.h"
#include "sweep_args.h"
#include "sweep_run.h"

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]).empty() || argv[1][0] == '-') {
    std::fprintf(stderr,
                 "mechgen_sweep_view: error: the first argument is the model's shared object "
                 "(MODEL.so, built with -DMECHGEN_VIEW_ENTRY); then the sweep's options\n");
    return mechgen::sweep_tool::kExitUsage;
  }
  const std::string path = argv[1];
  // RTLD_LOCAL: two models loaded in one process keep their own symbols.
  void* handle = dlopen(path.find('/') == std::string::npos ? ("./" + path).c_str() : path.c_str(),
                        RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    std::fprintf(stderr, "error: cannot load %s: %s\n", path.c_str(), dlerror());
    return mechgen::sweep_tool::kExitError;
  }
  const auto entry = reinterpret_cast<mechgen::ModelViewEntry>(dlsym(handle, mechgen::kModelViewEntry));
  const mechgen::ModelView* view = entry != nullptr ? entry() : nullptr;
  if (view == nullptr) {
    std::fprintf(stderr, "error: %s has no %s(): build it with -DMECHGEN_VIEW_ENTRY\n", path.c_str(),
                 mechgen::kModelViewEntry);
    return mechgen::sweep_tool::kExitError;
  }
  if (view->layout == mechgen::kModelViewLayout && view->size == static_cast<int>(sizeof(mechgen::ModelView)) &&
      !view->fits_maxima) {
    std::fprintf(stderr,
                 "error: the model %s exceeds the maxima of the runtime compiled once "
                 "(mechgen::ModelView::kMax*: inputs, coordinates, points, ...); use its own tool "
                 "%s_sweep\n",
                 view->name, view->name);
    return mechgen::sweep_tool::kExitError;
  }
  if (!mechgen::ViewCompatible(*view)) {
    std::fprintf(stderr,
                 "error: %s holds a model view of layout %d, size %d; this program reads layout %d, "
                 "size %d: generate and build the model again with this mechgen\n",
                 path.c_str(), view->layout, view->size, mechgen::kModelViewLayout,
                 static_cast<int>(sizeof(mechgen::ModelView)));
    return mechgen::sweep_tool::kExitError;
  }
  // The sweep's options after the object, as <name>_sweep takes them.
  std::vector<char*> args;
  const std::string tool = std::string(view->name) + "_sweep_view";
  args.push_back(const_cast<char*>(tool.c_str()));
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  mechgen::sweep_tool::Arguments arguments;
  const int parsed = mechgen::sweep_tool::ParseArguments(static_cast<int>(args.size()), args.data(), view->name,
                                                         mechgen::sweep_tool::kMaxSteps, &arguments);
  if (parsed >= 0) return parsed;
  const int status = mechgen::sweep_tool::RunSweep(mechgen::ViewModel(*view), arguments);
  // (The object stays loaded until exit: the view's strings are in it.)
  return status;
}
