// mechgen_view [--name TEXT] COMMAND MODEL.so [the command's options]: a command of any model through the
// runtime compiled once (issue 43). MODEL.so is a shared object built from a generated model's
// <name>.cc and <name>_view.cc with -DMECHGEN_VIEW_ENTRY, e.g.
//   g++ -O2 -shared -fPIC -fno-gnu-unique -DMECHGEN_VIEW_ENTRY -I<dir of name.h> -Iruntime/include
//       -I/usr/include/eigen3 fourbar.cc fourbar_view.cc -o fourbar.so
// (what `mechgen <command> MODEL` builds into its cache and runs this program on). It loads the
// object (dlopen), takes its view from the entry point mechgen_model_view()
// (mechgen::kModelViewEntry), refuses a view of another layout or size or one beyond the
// runtime's maxima (exit 1), and runs the command (view/commands.h) with the options after the
// object; the command's messages name it `<model>_<command>_view`, or TEXT (`mechgen sweep
// MODEL`, as the per-model program's do when mechgen runs it). Exit statuses are the
// per-model tool's; 1 also for an object that cannot be loaded, 2 for an unknown command.
#include <dlfcn.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "mechgen/core/view_model.h"
#include "view/commands.h"

namespace {

constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

std::string CommandNames() {
  std::string names;
  for (const mechgen::view_tool::Command& c : mechgen::view_tool::kCommands)
    names += std::string(names.empty() ? "" : "|") + c.name;
  return names;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::printf("usage: mechgen_view %s MODEL.so [the command's options]\n"
                "  MODEL.so: a generated model's <name>.cc and <name>_view.cc built with -DMECHGEN_VIEW_ENTRY\n"
                "  (mechgen <command> MODEL builds it and runs this program); `mechgen_view COMMAND MODEL.so "
                "--help` lists the command's options\n",
                CommandNames().c_str());
    return 0;
  }
  // --name TEXT: how the command's messages name it.
  std::string name;
  if (argc >= 3 && std::strcmp(argv[1], "--name") == 0) {
    name = argv[2];
    argv[2] = argv[0];
    argv += 2;
    argc -= 2;
  }
  const mechgen::view_tool::Command* command = nullptr;
  if (argc >= 2)
    for (const mechgen::view_tool::Command& c : mechgen::view_tool::kCommands)
      if (std::strcmp(argv[1], c.name) == 0) command = &c;
  if (command == nullptr) {
    std::fprintf(stderr, "mechgen_view: error: %s%s: the first argument is the command (%s), then MODEL.so\n",
                 argc >= 2 ? "unknown command " : "no command", argc >= 2 ? argv[1] : "", CommandNames().c_str());
    return kExitUsage;
  }
  if (argc < 3 || std::string(argv[2]).empty() || argv[2][0] == '-') {
    std::fprintf(stderr,
                 "mechgen_view: error: after the command, the model's shared object (MODEL.so, built with "
                 "-DMECHGEN_VIEW_ENTRY); then the %s command's options\n",
                 command->name);
    return kExitUsage;
  }
  const std::string path = argv[2];
  // RTLD_LOCAL: two models loaded in one process keep their own symbols.
  void* handle = dlopen(path.find('/') == std::string::npos ? ("./" + path).c_str() : path.c_str(),
                        RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    std::fprintf(stderr, "error: cannot load %s: %s\n", path.c_str(), dlerror());
    return kExitError;
  }
  const auto entry = reinterpret_cast<mechgen::ModelViewEntry>(dlsym(handle, mechgen::kModelViewEntry));
  const mechgen::ModelView* view = entry != nullptr ? entry() : nullptr;
  if (view == nullptr) {
    std::fprintf(stderr, "error: %s has no %s(): build it with -DMECHGEN_VIEW_ENTRY\n", path.c_str(),
                 mechgen::kModelViewEntry);
    return kExitError;
  }
  if (view->layout == mechgen::kModelViewLayout && view->size == static_cast<int>(sizeof(mechgen::ModelView)) &&
      !view->fits_maxima) {
    std::fprintf(stderr,
                 "error: the model %s exceeds the maxima of the runtime compiled once "
                 "(mechgen::ModelView::kMax*: inputs, coordinates, points, ...); use its own tool "
                 "%s_%s\n",
                 view->name, view->name, command->name);
    return kExitError;
  }
  if (!mechgen::ViewCompatible(*view)) {
    std::fprintf(stderr,
                 "error: %s holds a model view of layout %d, size %d; this program reads layout %d, "
                 "size %d: generate and build the model again with this mechgen\n",
                 path.c_str(), view->layout, view->size, mechgen::kModelViewLayout,
                 static_cast<int>(sizeof(mechgen::ModelView)));
    return kExitError;
  }
  // The command's options after the object, as <name>_<command> takes them.
  std::vector<char*> args;
  const std::string tool = !name.empty() ? name : std::string(view->name) + "_" + command->name + "_view";
  args.push_back(const_cast<char*>(tool.c_str()));
  for (int i = 3; i < argc; ++i) args.push_back(argv[i]);
  // (The object stays loaded until exit: the view's strings are in it.)
  return command->run(*view, static_cast<int>(args.size()), args.data());
}
