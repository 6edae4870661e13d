// <model>_sweep: the sweep command of one generated mechgen model.
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this one generic file per model
// with -DMECHGEN_MODEL_INCLUDE="<name>.h" -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It
// assembles the mechanism at the model's assembly configuration, sweeps the inputs along a
// straight line (by default every input over the model's kQMin..kQMax) staying on that
// assembly mode, and writes a CSV file, a short table and an SVG drawing with the traced
// point paths. Example:
//   fourbar_sweep --steps 360 --csv out/fourbar.csv --svg out/fourbar.svg --table 8
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mechgen/io/csv.h"
#include "mechgen/io/svg.h"
#include "mechgen/io/table.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/sweep/sweep.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

namespace {

using Model = MECHGEN_MODEL_NAMESPACE::Model;
using Types = mechgen::ModelTypes<Model>;

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
  for (int j = 0; j < Model::kNq; ++j)
    if (name == Model::kQNames[j] || name == std::to_string(j)) *index = j;
  if (*index < 0) {
    *error = "--range " + text + ": no input named '" + name + "'; inputs are";
    for (const char* q : Model::kQNames) *error += std::string(" ") + q;
    return false;
  }
  if (!ParseValue(text.substr(a + 1, b - a - 1), min) || !ParseValue(text.substr(b + 1), max)) {
    *error = "--range " + text + ": min and max must be numbers (append 'deg' for degrees)";
    return false;
  }
  return true;
}

// Opens `path` for writing, creating its parent directory.
bool OpenOutput(const std::string& path, std::ofstream* file) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  file->open(path);
  if (!*file) std::cerr << "error: cannot write " << path << "\n";
  return static_cast<bool>(*file);
}

std::string Describe(int j, double value) {
  char buffer[64];
  if (Model::kQIsAngle[j]) {
    std::snprintf(buffer, sizeof(buffer), "%g deg", value / kDegToRad);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%g", value);
  }
  return buffer;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{std::string("Sweep the inputs of the mechgen model '") + Model::kName +
               "', staying on its assembly mode; write CSV, a table and an SVG drawing."};
  int steps = 360;
  std::vector<std::string> ranges;
  std::vector<std::string> qd_text, qdd_text;
  std::string csv_path, svg_path;
  int table_rows = 8;
  bool no_animation = false;
  app.add_option("--steps", steps, "number of steps (rows = steps + 1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--range", ranges,
                 "input:min:max, input by name or index; values in model units (radians), "
                 "or with a 'deg' suffix (e.g. theta_crank:0:180deg). Default: the model's "
                 "range of every input");
  app.add_option("--qd", qd_text, "input speed(s), one value or one per input (default 1)");
  app.add_option("--qdd", qdd_text, "input acceleration(s), one value or one per input (default 0)");
  app.add_option("--csv", csv_path, "write every row to this CSV file");
  app.add_option("--svg", svg_path, "write a drawing with the traced point paths to this SVG file");
  app.add_option("--table", table_rows, "print this many rows to stdout (0: none)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--no-animation", no_animation, "SVG without the SMIL animation");
  CLI11_PARSE(app, argc, argv);

  // Path of the sweep and the input motion.
  Types::VecQ q_begin = Eigen::Map<const Types::VecQ>(Model::kQMin.data());
  Types::VecQ q_end = Eigen::Map<const Types::VecQ>(Model::kQMax.data());
  for (const std::string& text : ranges) {
    int j = 0;
    double min = 0, max = 0;
    std::string error;
    if (!ParseRange(text, &j, &min, &max, &error)) {
      std::cerr << "error: " << error << "\n";
      return 2;
    }
    q_begin(j) = min;
    q_end(j) = max;
  }
  auto parse_vector = [](const std::vector<std::string>& text, double fallback,
                         const char* option, Types::VecQ* out) {
    out->setConstant(fallback);
    if (text.empty()) return true;
    if (text.size() != 1 && text.size() != static_cast<size_t>(Model::kNq)) {
      std::cerr << "error: " << option << " takes 1 or " << Model::kNq << " values\n";
      return false;
    }
    for (int j = 0; j < Model::kNq; ++j) {
      if (!ParseValue(text[text.size() == 1 ? 0 : static_cast<size_t>(j)], &(*out)(j))) {
        std::cerr << "error: " << option << " values must be numbers\n";
        return false;
      }
    }
    return true;
  };
  Types::VecQ qd, qdd;
  if (!parse_vector(qd_text, 1.0, "--qd", &qd) || !parse_vector(qdd_text, 0.0, "--qdd", &qdd)) {
    return 2;
  }

  // Assembly at the model's assembly configuration, then the sweep.
  // Ceres assembles (position/ceres_adapter.h): the tool behaves as before the runtime's
  // Ceres-free core; products that only continue can use PositionSolver<Model> without it.
  mechgen::position::CeresPositionSolver<Model> solver;
  mechgen::position::Summary assembly;
  if (solver.AssembleDefault(&assembly) != mechgen::position::Status::kConverged) {
    std::cerr << "error: cannot assemble " << Model::kName << " at its assembly configuration: "
              << mechgen::position::FormatSummary(assembly) << "\n";
    return 3;
  }
  std::printf("mechgen sweep of '%s': assembled (branch %+d, |Phi|_inf = %.1e); ", Model::kName,
              assembly.branch, assembly.residual_norm);
  for (int j = 0; j < Model::kNq; ++j) {
    std::printf("%s%s %s -> %s", j ? ", " : "", Model::kQNames[j],
                Describe(j, q_begin(j)).c_str(), Describe(j, q_end(j)).c_str());
  }
  std::printf(" in %d steps\n\n", steps);

  std::vector<mechgen::SweepRecord<Model>> records;
  const auto start = std::chrono::steady_clock::now();
  const int failures = mechgen::Sweep(&solver, q_begin, q_end, steps, qd, qdd, &records);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (table_rows > 0) {
    mechgen::PrintTable(records, table_rows, std::cout);
    std::cout << "\n";
  }
  double max_residual = 0, max_condition = 0;
  int iterations = 0, fallbacks = 0;
  for (const auto& r : records) {
    iterations += r.summary.iterations;
    fallbacks += r.summary.used_assembler;
    if (r.summary.status != mechgen::position::Status::kConverged) continue;
    max_residual = std::max(max_residual, r.summary.residual_norm);
    max_condition = std::max(max_condition, r.summary.condition);
  }
  const int rows = static_cast<int>(records.size());
  std::printf("%d/%d configurations converged; max |Phi|_inf = %.1e, max cond(Phi_phi) = %.3g, "
              "%.2f Newton iterations/step%s; %.2f us/step (incl. velocities, accelerations)\n",
              rows - failures, rows, max_residual, max_condition, double(iterations) / rows,
              fallbacks ? " (Ceres fallback used)" : "", 1e6 * seconds / rows);
  if (failures > 0) {
    int shown = 0;
    for (const auto& r : records) {
      if (r.summary.status == mechgen::position::Status::kConverged || shown++ >= 3) continue;
      std::printf("  %s = %s: %s\n", Model::kQNames[0], Describe(0, r.q(0)).c_str(),
                  mechgen::position::FormatSummary(r.summary).c_str());
    }
  }

  if (!csv_path.empty()) {
    std::ofstream file;
    if (!OpenOutput(csv_path, &file)) return 4;
    mechgen::WriteCsv(records, file);
    std::printf("wrote %s (%d rows x %zu columns)\n", csv_path.c_str(), rows,
                mechgen::CsvColumns<Model>().size());
  }
  if (!svg_path.empty()) {
    std::ofstream file;
    if (!OpenOutput(svg_path, &file)) return 4;
    mechgen::SvgOptions options;
    options.animate = !no_animation;
    options.title = std::string("mechgen: ") + Model::kName;
    mechgen::WriteSvg(solver.params(), records, options, file);
    std::printf("wrote %s (%s)\n", svg_path.c_str(),
                options.animate ? "animated; open it in a web browser" : "still");
  }
  return 0;
}
