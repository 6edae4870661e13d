// <model>_statics: the statics command of one generated mechgen model (issue 14).
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this one generic file per model
// whose outputs ask for `forces`, with -DMECHGEN_MODEL_INCLUDE="<name>.h"
// -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It assembles the mechanism at the model's assembly
// configuration, sweeps the inputs along a straight line (by default every input over the
// model's kQMin..kQMax) staying on that assembly mode, and at every configuration reports
// the driving forces (without friction and, with friction, forward and backward), the
// reactions, V, the mechanical advantage and a status per row; optionally the dead zones
// (self-locking intervals) and the equilibrium positions along the range. Writes a CSV file,
// a short table and an SVG drawing with the reaction vectors. Plot the CSV with
// runtime/tools/plot_statics.gnuplot. Example:
//   slider_crank_friction_statics --steps 720 --csv out/scf.csv --svg out/scf.svg --dead-zones
//   gnuplot -e "csv='out/scf.csv'; png='out/scf.png'" runtime/tools/plot_statics.gnuplot
// A model generated without `forces` builds into a stub that says so (exit status 2).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mechgen/io/output_file.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/svg.h"
#include "mechgen/statics/sweep.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

namespace {

constexpr double kDegToRad = 0.017453292519943295;

// "1.5" -> 1.5 (model units, radians for angles); "90deg" -> pi/2. False if malformed.
bool ParseValue(const std::string& text, double* value) {
  std::string number = text;
  double factor = 1;
  if (number.size() > 3 && number.compare(number.size() - 3, 3, "deg") == 0) {
    number.resize(number.size() - 3);
    factor = kDegToRad;
  }
  char* end = nullptr;
  *value = std::strtod(number.c_str(), &end);
  *value *= factor;
  return !number.empty() && end != nullptr && *end == '\0' && std::isfinite(*value);
}

// "i:min:max" with i an input index or name -> (index, min, max).
template <class M>
bool ParseRange(const std::string& text, int* index, double* min, double* max,
                std::string* error) {
  const size_t a = text.find(':');
  const size_t b = a == std::string::npos ? a : text.find(':', a + 1);
  if (b == std::string::npos) {
    *error = "--range " + text + ": expected input:min:max";
    return false;
  }
  const std::string name = text.substr(0, a);
  *index = -1;
  for (int j = 0; j < M::kNq; ++j)
    if (name == M::kQNames[j] || name == std::to_string(j)) *index = j;
  if (*index < 0) {
    *error = "--range " + text + ": no input named '" + name + "'; inputs are";
    for (const char* q : M::kQNames) *error += std::string(" ") + q;
    return false;
  }
  if (!ParseValue(text.substr(a + 1, b - a - 1), min) || !ParseValue(text.substr(b + 1), max)) {
    *error = "--range " + text + ": min and max must be numbers (append 'deg' for degrees)";
    return false;
  }
  return true;
}

template <class M>
std::string Describe(int j, double value) {
  char buffer[64];
  if (M::kQIsAngle[j]) {
    std::snprintf(buffer, sizeof(buffer), "%.4f deg", value / kDegToRad);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  }
  return buffer;
}

template <class M>
int Run(int argc, char** argv) {
  namespace statics = mechgen::statics;
  using Types = mechgen::ModelTypes<M>;
  CLI::App app{std::string("Statics of the mechgen model '") + M::kName +
               "' along a motion: driving forces (with friction forward and backward), "
               "reactions, V, mechanical advantage, dead zones, equilibria; CSV, table, SVG."};
  int steps = 360;
  std::vector<std::string> ranges;
  std::string csv_path, svg_path;
  int table_rows = 8, snapshots = 4, samples = 360;
  bool animate = false, dead_zones = false, equilibria = false;
  double max_condition = statics::Options().max_condition;
  app.add_option("--steps", steps, "number of steps (rows = steps + 1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--range", ranges,
                 "input:min:max, input by name or index; values in model units (radians), "
                 "or with a 'deg' suffix (e.g. theta_crank:0:180deg). Default: the model's "
                 "range of every input");
  app.add_option("--csv", csv_path, "write every row to this CSV file (plot it with "
                                    "runtime/tools/plot_statics.gnuplot)");
  app.add_option("--svg", svg_path, "write the mechanism with its reaction vectors at a few "
                                    "configurations to this SVG file");
  app.add_option("--snapshots", snapshots, "configurations drawn in the SVG")
      ->check(CLI::PositiveNumber);
  app.add_flag("--animate", animate, "add the animated copy of the sweep to the SVG");
  app.add_option("--table", table_rows, "print this many rows to stdout (0: none)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--dead-zones", dead_zones,
               "scan each input's range for self-locking intervals (T_back T0 <= 0)");
  app.add_flag("--equilibria", equilibria,
               "find the configurations where Q = 0 along the range, with their stability");
  app.add_option("--samples", samples, "samples of the dead-zone and equilibrium scans")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-condition", max_condition,
                 "forces are withheld (status singular) where cond_1(Phi_phi) exceeds this")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  typename Types::VecQ q_begin = Eigen::Map<const typename Types::VecQ>(M::kQMin.data());
  typename Types::VecQ q_end = Eigen::Map<const typename Types::VecQ>(M::kQMax.data());
  for (const std::string& text : ranges) {
    int j = 0;
    double min = 0, max = 0;
    std::string error;
    if (!ParseRange<M>(text, &j, &min, &max, &error)) {
      std::cerr << "error: " << error << "\n";
      return 2;
    }
    q_begin(j) = min;
    q_end(j) = max;
  }
  statics::Options options;
  options.max_condition = max_condition;
  std::string error;
  if (!options.IsValid(&error)) {
    std::cerr << "error: " << error << "\n";
    return 2;
  }

  mechgen::position::CeresPositionSolver<M> solver;
  mechgen::position::Summary assembly;
  if (solver.AssembleDefault(&assembly) != mechgen::position::Status::kConverged) {
    std::cerr << "error: cannot assemble " << M::kName << " at its assembly configuration: "
              << mechgen::position::FormatSummary(assembly) << "\n";
    return 3;
  }
  const auto assembled = solver.state();
  std::printf("mechgen statics of '%s': assembled (branch %+d); ", M::kName, assembly.branch);
  for (int j = 0; j < M::kNq; ++j) {
    std::printf("%s%s %s -> %s", j ? ", " : "", M::kQNames[j], Describe<M>(j, q_begin(j)).c_str(),
                Describe<M>(j, q_end(j)).c_str());
  }
  std::printf(" in %d steps; %d friction joint(s), %d reaction component(s)\n\n", steps,
              statics::StaticsFeatures<M>::kNumFriction,
              statics::StaticsFeatures<M>::kNumReactions);

  std::vector<statics::StaticsRecord<M>> records;
  const auto start = std::chrono::steady_clock::now();
  const int failures = statics::StaticsSweep(options, &solver, q_begin, q_end, steps, &records);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (table_rows > 0) {
    statics::PrintStaticsTable(records, table_rows, std::cout);
    std::cout << "\n";
  }
  const int rows = static_cast<int>(records.size());
  int singular = 0, evaluations = 0;
  for (const auto& r : records) {
    singular += r.status == statics::Status::kSingular;
    evaluations += r.evaluations;
  }
  std::printf("%d/%d rows converged, %d singular (forces withheld); %.1f statics evaluations "
              "per row; %.2f us/row (position, coefficients and statics)\n",
              rows - failures, rows, singular, double(evaluations) / std::max(rows, 1),
              1e6 * seconds / std::max(rows, 1));
  for (int j = 0; j < M::kNq; ++j) {
    double largest = 0;
    for (const auto& r : records)
      if (r.drives[j].status == statics::Status::kConverged)
        largest = std::max({largest, std::abs(r.drives[j].drive),
                            std::abs(r.drives[j].drive_forward)});
    std::printf("  max |drive_%s| = %.6g\n", M::kQNames[j], largest);
  }
  if (failures > 0) {
    int shown = 0;
    for (const auto& r : records) {
      if (r.status == statics::Status::kConverged || shown++ >= 3) continue;
      std::printf("  %s = %s: %s (%s)\n", M::kQNames[0],
                  Describe<M>(0, r.kinematics.q(0)).c_str(), statics::RowStatus(r),
                  r.frictionless.summary.reason);
    }
  }

  statics::ScanOptions scan;
  scan.samples = samples;
  if (dead_zones && !statics::StaticsFeatures<M>::kHasFriction) {
    std::printf("dead zones: none, the model has no friction (self-locking needs friction)\n");
  } else if (dead_zones) {
    for (int j = 0; j < M::kNq; ++j) {
      if (q_begin(j) == q_end(j)) continue;
      solver.AssembleDefault(nullptr);
      solver.MoveTo(assembled.q, nullptr);
      std::vector<statics::DeadZone> zones;
      statics::ScanSummary summary;
      statics::FindDeadZones(options, scan, &solver, j, q_begin(j), q_end(j), &zones, &summary);
      std::printf("dead zones of %s (self-locking: the load cannot drive it back): %zu (%s%s%s)\n",
                  M::kQNames[j], zones.size(), statics::ToString(summary.status),
                  summary.reason[0] ? ": " : "", summary.reason);
      for (const statics::DeadZone& z : zones) {
        std::printf("  %s%s .. %s%s\n", Describe<M>(j, z.begin).c_str(),
                    z.begin_located ? "" : " (range end)", Describe<M>(j, z.end).c_str(),
                    z.end_located ? "" : " (range end)");
      }
    }
  }
  if (equilibria) {
    solver.AssembleDefault(nullptr);
    std::vector<statics::Equilibrium<M>> found;
    statics::ScanSummary summary;
    statics::FindEquilibria(options, scan, &solver, q_begin, q_end, &found, &summary);
    std::printf("equilibrium positions (Q = 0 along the line): %zu (%s%s%s)\n", found.size(),
                statics::ToString(summary.status), summary.reason[0] ? ": " : "", summary.reason);
    for (const statics::Equilibrium<M>& e : found) {
      std::printf("  ");
      for (int j = 0; j < M::kNq; ++j)
        std::printf("%s%s = %s", j ? ", " : "", M::kQNames[j], Describe<M>(j, e.q(j)).c_str());
      std::printf(": stiffness %.6g, %s\n", e.stiffness,
                  std::isnan(e.stiffness) ? "stability unknown"
                                          : (e.stable ? "stable" : "unstable"));
    }
  }

  // Each output whole or absent (io/output_file.h: a temporary file renamed on success), both
  // closed, every write checked, before either is renamed into place; a failed write (a full
  // disk, /dev/full) exits 1 with one line.
  mechgen::OutputFile csv, svg;
  auto failed = [&error]() {
    std::cerr << "error: " << error << "\n";
    return 1;
  };
  if (!csv_path.empty()) {
    if (!csv.Open(csv_path, &error)) return failed();
    statics::WriteStaticsCsv(records, csv.stream());
  }
  if (!svg_path.empty()) {
    if (!svg.Open(svg_path, &error)) return failed();
    mechgen::SvgOptions svg_options;
    svg_options.animate = animate;
    svg_options.snapshots = snapshots;
    svg_options.title = std::string("mechgen statics: ") + M::kName;
    statics::WriteStaticsSvg(solver.params(), records, svg_options, svg.stream());
  }
  if ((!csv_path.empty() && !csv.Close(&error)) || (!svg_path.empty() && !svg.Close(&error)) ||
      (!csv_path.empty() && !csv.Commit(&error)) || (!svg_path.empty() && !svg.Commit(&error))) {
    return failed();
  }
  if (!csv_path.empty()) {
    std::printf("wrote %s (%d rows x %zu columns)\n", csv_path.c_str(), rows,
                statics::StaticsCsvColumns<M>().size());
  }
  if (!svg_path.empty()) std::printf("wrote %s\n", svg_path.c_str());
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.flush()) {
    std::cerr << "error: cannot write the standard output\n";
    return 1;
  }
  return 0;
}

// The statics command for a model with statics, a stub for one without (a template, so
// that the branch not taken is not instantiated).
template <class M>
int Main(int argc, char** argv) {
  if constexpr (mechgen::statics::StaticsFeatures<M>::kHasStatics) {
    return Run<M>(argc, argv);
  } else {
    (void)argc;
    (void)argv;
    std::cerr << "error: the model '" << M::kName
              << "' was generated without statics; add `forces` to its outputs' quantities\n";
    return 2;
  }
}

}  // namespace

int main(int argc, char** argv) { return Main<MECHGEN_MODEL_NAMESPACE::Model>(argc, argv); }
