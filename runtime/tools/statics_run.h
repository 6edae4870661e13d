// The statics command around the statics analysis (mechgen/analysis/statics.h: Check, Run): the
// parsed options (statics_args.h) are the analysis's StaticsRequest, where its outputs go and
// the pictures of --plots, which gnuplot draws from the command's own CSV after the analysis
// wrote it. The per-model tool <model>_statics (statics_main.cc) runs analysis::Run on the
// generated model's type (fixed sizes); mechgen_view statics (view/statics.cc) on the model
// view, instantiated once in mechgen_runtime_view (runtime/view/analysis.cc). Nothing here
// depends on the model.
#pragma once

#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>

#include "common/gnuplot.h"
#include "common/numbers.h"
#include "mechgen/analysis/statics_request.h"
#include "statics_args.h"

namespace mechgen::statics_tool {

/// The outputs of the command and its pictures (--plots PREFIX): PREFIX_drive.<format>
/// (plot_statics.gnuplot: the driving forces, with friction to run in +q and -q, and the
/// reaction magnitudes against the first input) and PREFIX_bearings.<format>
/// (plot_bearings.gnuplot: the polar diagram of each ground bearing's load), drawn by gnuplot
/// (found on PATH) with the plot scripts of runtime/tools (common/gnuplot.h: where they are
/// looked up) from the CSV (PREFIX.csv unless --csv names it).
class Command {
 public:
  explicit Command(const Arguments& args) : args_(args) {
    outputs_.tool = args.tool;
    outputs_.csv_path = args.csv_path;
    outputs_.svg_path = args.svg_path;
    outputs_.animate = args.animate;
    outputs_.snapshots = args.snapshots;
    if (!args.plots_prefix.empty() && outputs_.csv_path.empty()) outputs_.csv_path = args.plots_prefix + ".csv";
  }

  const analysis::StaticsOutputs& outputs() const { return outputs_; }

  /// Before anything is computed or written (analysis::Run's `prepare`): gnuplot and the
  /// scripts found, and paths gnuplot's quoted strings can carry. -1 to go on, else the exit
  /// status (a usage error 2, no gnuplot or no scripts 1, with one line on stderr).
  int Prepare() {
    if (args_.plots_prefix.empty()) return -1;
    for (const std::string& path : {args_.plots_prefix, outputs_.csv_path}) {
      if (path.find_first_of("'\n") != std::string::npos)
        return tools::UsageError(args_.tool, tools::BadValue("--plots", path, "a path without ' or a line break"));
    }
    gnuplot_ = tools::FindOnPath("gnuplot");
    if (gnuplot_.empty()) {
      std::cerr << "error: --plots: gnuplot not found on PATH (install gnuplot, or leave out "
                   "--plots)\n";
      return 1;
    }
    scripts_ = tools::FindPlotScripts({kPlotScripts[0], kPlotScripts[1]});
    if (scripts_.empty()) {
      std::cerr << "error: --plots: " << tools::PlotScriptsNotFound({kPlotScripts[0], kPlotScripts[1]}) << "\n";
      return 1;
    }
    return -1;
  }

  /// After the analysis returned `status` (its outputs written when 0): the pictures, then the
  /// standard output checked. The command's exit status.
  int Finish(int status, const analysis::StaticsPlotFacts& facts) {
    if (status != 0 || args_.plots_prefix.empty()) return status;
    const std::string& prefix = args_.plots_prefix;
    const std::string& format = args_.plot_format;
    std::string error;
    std::fflush(stdout);
    const std::string drive = prefix + "_drive." + format;
    if (!tools::RunGnuplot(gnuplot_, scripts_ / kPlotScripts[0], outputs_.csv_path, format, drive, &error))
      return Failed(error);
    std::printf("wrote %s (driving forces and reaction magnitudes against %s)\n", drive.c_str(),
                facts.first_input.c_str());
    if (!facts.bearings) {
      std::printf("%s\n", facts.no_bearings.c_str());
    } else {
      const std::string bearings = prefix + "_bearings." + format;
      if (!tools::RunGnuplot(gnuplot_, scripts_ / kPlotScripts[1], outputs_.csv_path, format, bearings, &error))
        return Failed(error);
      std::printf("wrote %s (polar diagram of the ground bearings' loads: the force of the "
                  "ground on the moving link, fixed frame)\n",
                  bearings.c_str());
    }
    if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.flush()) {
      std::cerr << "error: cannot write the standard output\n";
      return 1;
    }
    return 0;
  }

  /// Runs `run` (analysis::Run on the model, given the outputs, Prepare and the facts to
  /// fill) and draws the pictures: the command's exit status.
  int operator()(const std::function<int(const analysis::StaticsOutputs&, const std::function<int()>&,
                                         analysis::StaticsPlotFacts*)>& run) {
    analysis::StaticsPlotFacts facts;
    const int status = run(outputs_, [this] { return Prepare(); }, &facts);
    return Finish(status, facts);
  }

 private:
  // The pictures of --plots: gnuplot (found on PATH) runs these plot scripts of runtime/tools/
  // on the command's own CSV (common/gnuplot.h: where the scripts are looked up).
  static constexpr const char* kPlotScripts[] = {"plot_statics.gnuplot", "plot_bearings.gnuplot"};

  static int Failed(const std::string& error) {
    std::cerr << "error: " << error << "\n";
    return 1;
  }

  const Arguments& args_;
  analysis::StaticsOutputs outputs_;
  std::filesystem::path gnuplot_, scripts_;
};

}  // namespace mechgen::statics_tool
