// The sweep command's options with CLI11 (sweep_args.h). Independent of the model.
#include "sweep_args.h"

#include <string>

#include "common/cli.h"

namespace mechgen::sweep_tool {

int ParseArguments(int argc, char** argv, const std::string& model_name, long long max_steps,
                   Arguments* arguments) {
  Arguments& a = *arguments;
  a.tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{"Sweep the inputs of the mechgen model '" + model_name +
               "', staying on its assembly mode; write CSV, a table and an SVG drawing. Exit "
               "status: 0 all rows converged, 3 some did not (counts on stderr), 2 bad "
               "arguments (one line on stderr), 1 model or output error."};
  tools::Count(&app, "--steps", &a.steps, 1, max_steps, "number of steps (rows = steps + 1)");
  app.add_option("--range", a.ranges,
                 "input:min:max, input by name or index; values in model units (radians), "
                 "or with a 'deg' suffix (e.g. theta_crank:0:180deg), min and max in "
                 "[-1e4, 1e4]. Default: the model's range of every input");
  app.add_option("--qd", a.qd_text,
                 "input speed(s), one value or one per input, |value| <= 1e5 (default 1)");
  app.add_option("--qdd", a.qdd_text,
                 "input acceleration(s), one value or one per input, |value| <= 1e10 (default "
                 "0)");
  app.add_option("--csv", a.csv_path,
                 "write every row to this CSV file (streamed; written whole or not at all)");
  app.add_option("--svg", a.svg_path,
                 "write a drawing with the traced point paths to this SVG file");
  tools::Count(&app, "--table", &a.table, 0, max_steps + 1,
               "print this many rows to stdout, evenly spaced from the first row to the last "
               "(0: none)");
  app.add_flag("--no-animation", a.no_animation, "SVG without the SMIL animation");
  app.add_flag("--design", a.design,
               "add the CSV columns d<output>/d<parameter>: the derivatives of the dependent coordinates, K "
               "and the points with respect to the model's design parameters (its `design` section)");
  app.add_option("--mode", a.mode,
                 "assemble in this named assembly mode of the model (its assembly_modes:) "
                 "instead of the model's assembly");
  app.add_option("--at-singular", a.at_singular,
                 "at a singular configuration: stop (the rest of the rows not_run), follow (a change "
                 "point, e.g. a parallelogram folding flat: go on along the same curve, the branch "
                 "it was on), switch (a change point: onto the other curve) or reverse (a dead "
                 "point: the input turns back)")
      ->check(CLI::IsMember({"stop", "follow", "switch", "reverse"}))
      ->capture_default_str();
  tools::AddParameterOptions(&app, &a.params);
  return tools::Parse(&app, argc, argv, a.tool);
}

}  // namespace mechgen::sweep_tool
