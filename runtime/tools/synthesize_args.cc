// The synthesize command's options with CLI11 (synthesize_args.h). Independent of the model.
#include "synthesize_args.h"

#include <algorithm>
#include <limits>
#include <string>
#include <thread>

#include "common/cli.h"

namespace mechgen::synthesize_tool {

int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments) {
  Arguments& a = *arguments;
  a.tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{"Dimensional synthesis (path, function or motion generation: the task file's `synthesis:`) of the model " +
               model_name +
               ": seeded differential evolution (path and function tasks; Freudenstein's equation for function "
               "tasks, Burmester's points for motion), then Levenberg-Marquardt on the generated design derivatives; "
               "`kind: exact` path tasks: every four-bar through five points with both pivots given, by homotopy "
               "continuation (--seed, --threads, --evaluations do not apply). "
               "Exit 0 done, 1 bad task file or output, 2 usage error, 3 no feasible mechanism."};
  a.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--task", a.task_path, "the synthesis task file (YAML, docs/synthesis.md)")->required();
  tools::Count(&app, "--seed", &a.seed, 0, std::numeric_limits<long long>::max(),
               "the random seed: the same seed, the same result for any --threads");
  tools::Count(&app, "--threads", &a.threads, 1, 1024, "threads for the restarts (default: all cores)");
  tools::Count(&app, "--evaluations", &a.evaluations, 0, 1000000000LL,
               "the global stage's budget, overriding the task's search.evaluations (0: the task's)");
  app.add_option("--out", a.out_dir, "the directory to write the model file, path.svg and report.txt into")
      ->capture_default_str();
  app.add_option("--model", a.model_path,
                 "the model file this program was compiled from (default: from `mechgen synthesize MODEL`)");
  tools::AddParameterOptions(&app, &a.params);
  return tools::Parse(&app, argc, argv, a.tool);
}

}  // namespace mechgen::synthesize_tool
