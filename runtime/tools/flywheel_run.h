// The flywheel command around the flywheel analysis (mechgen/analysis/flywheel.h: Check, Run):
// the parsed options (flywheel_args.h) are the analysis's FlywheelRequest and its CSV, and the
// pictures (--png, --svg), which gnuplot draws with plot_energy_loop.gnuplot from the CSV the
// analysis wrote (a temporary one when --csv is not given). The per-model tool
// <model>_flywheel (flywheel_main.cc) runs analysis::Run on the generated model's type (fixed
// sizes); mechgen_view flywheel (view/flywheel.cc) on the model view, instantiated once in
// mechgen_runtime_view (runtime/view/analysis.cc). Nothing here depends on the model.
#pragma once

#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "common/gnuplot.h"
#include "common/numbers.h"
#include "flywheel_args.h"
#include "mechgen/analysis/flywheel_request.h"

namespace mechgen::flywheel_tool {

/// The command: the analysis's outputs, then its pictures.
class Command {
 public:
  explicit Command(const Arguments& a) {
    outputs_.tool = a.tool;
    outputs_.csv_path = a.csv_path;
    if (!a.png_path.empty()) pictures_.push_back({"png", a.png_path});
    if (!a.svg_path.empty()) pictures_.push_back({"svg", a.svg_path});
    outputs_.picture = !pictures_.empty();
  }

  const analysis::FlywheelOutputs& outputs() const { return outputs_; }

  /// Before anything is computed or written (analysis::Run's `prepare`): gnuplot on the PATH
  /// and plot_energy_loop.gnuplot (common/gnuplot.h) for each picture. -1 to go on, else 1
  /// with one line on stderr.
  int Prepare() {
    for (const auto& picture : pictures_) {
      std::string error;
      if (!FindPlotter(picture.first, &error)) {
        std::cerr << "error: " << error << "\n";
        return 1;
      }
    }
    return -1;
  }

  /// After the analysis returned `status` with `result`: the pictures drawn from its CSV (a
  /// picture that fails: one line, exit status 1), the temporary CSV removed, the standard
  /// output checked. The command's exit status.
  int Finish(int status, const analysis::FlywheelResult& result) {
    if (!result.written) return status;
    for (const auto& [kind, path] : pictures_) {
      std::string error;
      if (tools::RunGnuplot(gnuplot_, script_, result.csv, kind, path, &error)) {
        std::printf("wrote %s\n", path.c_str());
      } else {
        std::cerr << "error: " << error << "\n";
        status = 1;
      }
    }
    if (!result.temporary.empty()) std::remove(result.temporary.c_str());
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      std::cerr << "error: cannot write the standard output\n";
      return 1;
    }
    return status;
  }

  /// Runs `run` (analysis::Run on the model, given the outputs, Prepare and the result to
  /// fill) and draws the pictures: the command's exit status.
  int operator()(const std::function<int(const analysis::FlywheelOutputs&, const std::function<int()>&,
                                         analysis::FlywheelResult*)>& run) {
    analysis::FlywheelResult result;
    const int status = run(outputs_, [this] { return Prepare(); }, &result);
    return Finish(status, result);
  }

 private:
  bool FindPlotter(const std::string& kind, std::string* error) {
    gnuplot_ = tools::FindOnPath("gnuplot");
    if (gnuplot_.empty()) {
      *error = "gnuplot is not on the PATH: no --" + kind + " picture (install gnuplot, or leave out --" + kind + ")";
      return false;
    }
    const std::filesystem::path scripts = tools::FindPlotScripts({"plot_energy_loop.gnuplot"});
    if (scripts.empty()) {
      *error = tools::PlotScriptsNotFound({"plot_energy_loop.gnuplot"});
      return false;
    }
    script_ = scripts / "plot_energy_loop.gnuplot";
    return true;
  }

  analysis::FlywheelOutputs outputs_;
  std::vector<std::pair<std::string, std::string>> pictures_;  // kind, path
  std::filesystem::path gnuplot_, script_;
};

}  // namespace mechgen::flywheel_tool
