// `mechgen study MODEL --study STUDY.yaml [--threads N] [--csv F] [--tolerance-csv F]`: a design
// study of one generated model (issue 29; the format: docs/studies.md). Compiled once per model
// by generator/driver/tool_command.cc (like the sweep), with -DMECHGEN_MODEL_INCLUDE and
// -DMECHGEN_MODEL_NAMESPACE, linked with yaml-cpp and threads.
//
// Draws every sample's parameter values (study/samples.h), runs the analysis of each on N
// threads (study/run.h: one compiled model, per-thread solver and rows), writes one CSV row per
// sample in sample order (the same bytes for any N), prints a summary of each metric and, with
// `tolerance: true`, the first-order tolerance analysis from the generated sensitivities beside
// the Monte-Carlo's figures. Progress on stderr (rate, time left) for studies longer than ~2 s.
// Exit status: 0 done (every sample ok), 3 done but some samples failed (their status column),
// 2 bad arguments or a bad study file (one line: file:line:column), 1 the study does not fit the
// model or an output cannot be written (nothing written).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "common/cli.h"
#include "common/numbers.h"
#include "mechgen/io/output_file.h"
#include "mechgen/study/run.h"
#include "mechgen/study/samples.h"
#include "mechgen/study/tolerance.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

namespace {

using Model = MECHGEN_MODEL_NAMESPACE::Model;
namespace study = mechgen::study;
namespace tools = mechgen::tools;

std::string G17(double x) {
  if (std::isnan(x)) return "nan";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

const char* MethodName(study::Method m) {
  switch (m) {
    case study::Method::kGrid:
      return "grid";
    case study::Method::kList:
      return "list";
    case study::Method::kLatinHypercube:
      return "lhs";
    case study::Method::kMonteCarlo:
      return "monte_carlo";
  }
  return "";
}

// The CSV: '#' lines (what wrote it, then each column's unit and meaning), the header, a row
// per sample.
void WriteCsv(const study::Study<Model>& s,
              const std::vector<double>& values,
              const std::vector<study::SampleResult>& results,
              std::ostream& out) {
  const study::StudySpec& spec = s.spec();
  const size_t n = spec.parameters.size();
  out << "# mechgen study, model " << Model::kName << ": " << spec.path << ", method " << MethodName(spec.method)
      << ", " << results.size() << " samples, seed " << spec.seed << ", analysis "
      << (spec.analysis == study::Analysis::kStatics ? "statics" : "sweep") << " in " << spec.steps << " steps\n";
  out << "# sample [1]: the sample's index, 0-based, in the study's order\n";
  for (const study::ParameterSpec& p : spec.parameters)
    out << "# " << p.name << " [model units]: the model's parameter " << p.name << "\n";
  for (size_t k = 0; k < spec.metrics.size(); ++k)
    out << "# " << spec.metrics[k].name << " [" << s.Unit(k) << "]: " << s.Description(k) << "\n";
  out << "# status [text]: ok, rows_failed (some rows did not converge), not_assembled\n";
  out << "sample";
  for (const study::ParameterSpec& p : spec.parameters) out << "," << p.name;
  for (const study::MetricSpec& m : spec.metrics) out << "," << m.name;
  out << ",status\n";
  std::string line;
  for (size_t i = 0; i < results.size(); ++i) {
    line = std::to_string(i);
    for (size_t k = 0; k < n; ++k) line += "," + G17(values[i * n + k]);
    for (double v : results[i].metrics) line += "," + G17(v);
    line += ",";
    line += results[i].status;
    line += "\n";
    out << line;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{std::string("A design study of the mechgen model '") + Model::kName +
               "': parameters varied on a grid, a list, a Latin hypercube or by Monte-Carlo, an analysis per "
               "sample, metrics per sample in a CSV, and the first-order tolerance analysis beside the "
               "Monte-Carlo (docs/studies.md)."};
  app.footer(
      "Exit status: 0 done, 3 done but some samples failed (status column), 2 bad arguments or a bad "
      "study file, 1 the study does not fit the model or an output cannot be written.");
  std::string study_path, csv_path, tolerance_path, envelope_path;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  bool quiet = false;
  app.add_option("--study", study_path, "the study file (YAML; docs/studies.md)")->required();
  tools::Count(&app, "--threads", &threads, 1, 1024, "threads over the samples (default: the cores)");
  app.add_option("--csv", csv_path, "write one row per sample to this CSV file");
  app.add_option("--tolerance-csv", tolerance_path,
                 "write the tolerance analysis (first order beside Monte-Carlo) to this CSV file");
  app.add_option("--envelope-csv", envelope_path,
                 "write the envelope of the study's point (envelope: {point: P}) to this CSV file: per row its "
                 "nominal place and the first-order and Monte-Carlo sigma of x and y");
  app.add_flag("--quiet", quiet, "no progress line on stderr");
  if (const int parsed = tools::Parse(&app, argc, argv, tool); parsed >= 0) return parsed;

  study::StudySpec spec;
  std::string error;
  if (!study::ReadStudy(study_path, &spec, &error)) {
    std::cerr << error << "\n";
    return tools::kExitUsage;
  }
  study::Study<Model> s;
  if (!s.Prepare(spec, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  if (!tolerance_path.empty() && !spec.tolerance)
    return tools::UsageError(tool, "--tolerance-csv: the study does not ask for it (tolerance: true)");
  if (!envelope_path.empty() && spec.envelope.empty())
    return tools::UsageError(tool, "--envelope-csv: the study names no point (envelope: {point: P})");
  mechgen::OutputFile csv, tolerance_csv, envelope_csv;
  if ((!csv_path.empty() && !csv.Open(csv_path, &error)) ||
      (!tolerance_path.empty() && !tolerance_csv.Open(tolerance_path, &error)) ||
      (!envelope_path.empty() && !envelope_csv.Open(envelope_path, &error))) {
    std::cerr << "error: " << error << "\n";
    return 1;
  }
  const std::vector<double> values = study::DrawSamples(spec, s.nominal());
  const uint64_t count = study::SampleCount(spec);
  std::printf("mechgen study of '%s': %s, %s, %llu samples of %zu parameters, %s over %d steps, %d threads\n",
              Model::kName, spec.path.c_str(), MethodName(spec.method), static_cast<unsigned long long>(count),
              spec.parameters.size(), spec.analysis == study::Analysis::kStatics ? "statics" : "kinematic sweep",
              spec.steps, threads);
  std::vector<study::SampleResult> results;
  const auto start = std::chrono::steady_clock::now();
  bool printed = false;
  auto progress = [&](uint64_t done) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (quiet || t < 2 || done == 0) return;
    const double rate = done / t;
    std::fprintf(stderr, "\rstudy: %llu/%llu samples, %.0f/s, %.0f s left   ", static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(count), rate, (count - done) / rate);
    printed = true;
  };
  s.Run(values, threads, &results, progress);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (printed) std::fprintf(stderr, "\n");

  // Summary: per status, per metric.
  uint64_t ok = 0, rows_failed = 0, not_assembled = 0;
  for (const study::SampleResult& r : results) {
    const std::string st = r.status;
    ok += st == "ok";
    rows_failed += st == "rows_failed";
    not_assembled += st == "not_assembled";
  }
  std::printf(
      "%llu ok, %llu with failed rows, %llu not assembled; %.3g s (%.3g samples/s, %.3g ms per sample per thread)\n\n",
      static_cast<unsigned long long>(ok), static_cast<unsigned long long>(rows_failed),
      static_cast<unsigned long long>(not_assembled), seconds, count / seconds,
      1e3 * seconds * threads / std::max<uint64_t>(count, 1));
  std::vector<std::vector<double>> per_metric(spec.metrics.size());
  for (size_t k = 0; k < spec.metrics.size(); ++k) {
    per_metric[k].reserve(results.size());
    for (const study::SampleResult& r : results) per_metric[k].push_back(r.metrics[k]);
  }
  std::printf("%-28s %-14s %14s %14s %14s %14s\n", "metric", "unit", "nominal", "mean", "sigma", "min .. max");
  for (size_t k = 0; k < spec.metrics.size(); ++k) {
    const study::Moments m = study::MomentsOf(per_metric[k]);
    double lo = INFINITY, hi = -INFINITY;
    for (double v : per_metric[k])
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    std::printf("%-28s %-14s %14.6g %14.6g %14.6g %14.6g .. %.6g\n", spec.metrics[k].name.c_str(), s.Unit(k).c_str(),
                s.Value(k, s.nominal_rows()).value, m.mean, m.sigma, lo, hi);
  }

  // Tolerance analysis: first order at the nominal beside the Monte-Carlo of the ok samples.
  const size_t n = spec.parameters.size();
  std::vector<double> sigma(n), tol(n), clearance(n, 0.0);
  for (size_t p = 0; p < n; ++p) {
    sigma[p] = spec.parameters[p].sigma();
    tol[p] = spec.parameters[p].tolerance;
    for (const study::ClearanceSpec& c : spec.clearances)
      if (c.parameter == spec.parameters[p].name) clearance[p] += c.radial;
  }
  std::string tolerance_text;
  if (spec.tolerance) {
    std::printf(
        "\ntolerance analysis: first order at the nominal (generated design derivatives) beside the "
        "Monte-Carlo of the %llu ok samples (95 %% intervals)\n",
        static_cast<unsigned long long>(ok));
    std::printf("%-24s %12s %12s %12s %12s %12s %12s %25s  %s\n", "metric", "nominal", "fo_sigma", "fo_worst",
                "clearance", "mc_mean", "mc_sigma", "mc_sigma_95", "verdict");
    tolerance_text =
        "# mechgen study tolerance analysis, model " + std::string(Model::kName) + ": " + spec.path +
        "\n# fo_sigma: first-order root-sum-square sqrt(sum (dm/dp sigma_p)^2); fo_worst: sum |dm/dp| t_p (t: the "
        "tolerance); clearance: sum |dm/dp| c over the joint clearances (worst direction); mc_*: the Monte-Carlo "
        "of the ok samples, with 95 % intervals; units: the metric's\n"
        "metric,unit,nominal,fo_sigma,fo_worst,clearance,mc_n,mc_mean,mc_mean_low,mc_mean_high,mc_sigma,mc_sigma_low,"
        "mc_sigma_high,verdict\n";
    for (size_t k = 0; k < spec.metrics.size(); ++k) {
      std::vector<double> ok_values;
      for (const study::SampleResult& r : results)
        if (std::string(r.status) == "ok") ok_values.push_back(r.metrics[k]);
      const study::Moments m = study::MomentsOf(ok_values);
      std::string why;
      const std::vector<double> g = s.Gradient(k, &why);
      const study::FirstOrder f = study::FirstOrderOf(g, sigma, tol, clearance);
      std::string verdict = study::Verdict(f, m);
      if (!f.complete) {
        std::string missing;
        for (size_t p = 0; p < n; ++p)
          if (s.design_index()[p] < 0) missing += (missing.empty() ? "" : ", ") + spec.parameters[p].name;
        verdict = "no first-order figure: " + (!why.empty() ? why : "not a design parameter of the model: " + missing);
      }
      if (ok < count)
        verdict += " (" + std::to_string(count - ok) + " of " + std::to_string(count) +
                   " samples failed and are not in the Monte-Carlo: a change the first order cannot see)";
      char interval[64];
      std::snprintf(interval, sizeof(interval), "[%.5g, %.5g]", m.sigma_low, m.sigma_high);
      std::printf("%-24s %12.6g %12.5g %12.5g %12.5g %12.6g %12.5g %25s  %s\n", spec.metrics[k].name.c_str(),
                  s.Value(k, s.nominal_rows()).value, f.rss, f.worst, f.complete ? f.clearance : NAN, m.mean, m.sigma,
                  interval, verdict.c_str());
      tolerance_text += spec.metrics[k].name + "," + s.Unit(k) + "," + G17(s.Value(k, s.nominal_rows()).value) + "," +
                        G17(f.rss) + "," + G17(f.worst) + "," + G17(f.complete ? f.clearance : NAN) + "," +
                        std::to_string(m.n) + "," + G17(m.mean) + "," + G17(m.mean_low) + "," + G17(m.mean_high) + "," +
                        G17(m.sigma) + "," + G17(m.sigma_low) + "," + G17(m.sigma_high) + ",\"" + verdict + "\"\n";
    }
  }

  // The envelope: per row, the point's nominal place, first-order sigma (and worst case) of x
  // and y from dr_P/dp, and the Monte-Carlo's sigma with its interval, over the ok samples.
  std::string envelope_text;
  if (!spec.envelope.empty()) {
    const int rows = spec.steps + 1;
    const bool random = spec.method == study::Method::kMonteCarlo;
    envelope_text = "# mechgen study envelope of " + spec.envelope + ", model " + Model::kName + ": " + spec.path +
                    "\n# per row of the motion: the input " + Model::kQNames[0] +
                    " (rad or model length), the point's nominal x and y (model length), the first-order sigma "
                    "and worst case of x and y from the generated dr_P/dp (as tolerance.csv), the Monte-Carlo's "
                    "sigma of x and y over the ok samples with 95 % intervals\n"
                    "row," +
                    std::string(Model::kQNames[0]) +
                    ",x_nominal,y_nominal,fo_sigma_x,fo_sigma_y,fo_worst_x,"
                    "fo_worst_y,mc_n,mc_sigma_x,mc_sigma_x_low,mc_sigma_x_high,mc_sigma_y,mc_sigma_y_low,"
                    "mc_sigma_y_high\n";
    const std::vector<double> nominal_path = s.Path(s.nominal_rows());
    int compared = 0, inside = 0, worst_row = -1;
    double worst_ratio = 1;
    for (int i = 0; i < rows; ++i) {
      std::string line = std::to_string(i) + "," + G17(s.nominal_rows().kinematics[i].q(0)) + "," +
                         G17(nominal_path[2 * i]) + "," + G17(nominal_path[2 * i + 1]);
      study::FirstOrder f[2];
      study::Moments m[2];
      for (int axis = 0; axis < 2; ++axis) {
        f[axis] = study::FirstOrderOf(s.PathGradient(i, axis), sigma, tol, clearance);
        std::vector<double> v;
        v.reserve(results.size());
        for (const study::SampleResult& r : results)
          if (std::string(r.status) == "ok") v.push_back(r.path[2 * i + axis]);
        m[axis] = study::MomentsOf(v);
        if (random && f[axis].complete && m[axis].n >= 2 && m[axis].sigma > 0) {
          ++compared;
          inside += f[axis].rss >= m[axis].sigma_low && f[axis].rss <= m[axis].sigma_high;
          const double ratio = std::max(f[axis].rss / m[axis].sigma, m[axis].sigma / f[axis].rss);
          if (ratio > worst_ratio) worst_ratio = ratio, worst_row = i;
        }
      }
      line += "," + G17(f[0].rss) + "," + G17(f[1].rss) + "," + G17(f[0].worst) + "," + G17(f[1].worst) + "," +
              std::to_string(m[0].n) + "," + G17(m[0].sigma) + "," + G17(m[0].sigma_low) + "," + G17(m[0].sigma_high) +
              "," + G17(m[1].sigma) + "," + G17(m[1].sigma_low) + "," + G17(m[1].sigma_high) + "\n";
      envelope_text += line;
    }
    if (compared > 0)
      std::printf(
          "\nenvelope of %s: the first-order sigma of x and y is inside the Monte-Carlo's 95 %% interval at %d "
          "of %d (row, axis); the largest ratio between the two, %.4g, at row %d (%s = %.6g)\n",
          spec.envelope.c_str(), inside, compared, worst_ratio, worst_row, Model::kQNames[0],
          worst_row >= 0 ? s.nominal_rows().kinematics[worst_row].q(0) : NAN);
  }

  if (!csv_path.empty()) WriteCsv(s, values, results, csv.stream());
  if (!envelope_path.empty()) envelope_csv.stream() << envelope_text;
  if (!tolerance_path.empty()) tolerance_csv.stream() << tolerance_text;
  if ((!csv_path.empty() && !csv.Close(&error)) || (!tolerance_path.empty() && !tolerance_csv.Close(&error)) ||
      (!envelope_path.empty() && !envelope_csv.Close(&error)) || (!csv_path.empty() && !csv.Commit(&error)) ||
      (!tolerance_path.empty() && !tolerance_csv.Commit(&error)) ||
      (!envelope_path.empty() && !envelope_csv.Commit(&error))) {
    std::cerr << "error: " << error << "\n";
    return 1;
  }
  if (!csv_path.empty())
    std::printf("\nwrote %s (%llu rows x %zu columns)\n", csv_path.c_str(), static_cast<unsigned long long>(count),
                spec.parameters.size() + spec.metrics.size() + 2);
  if (!tolerance_path.empty()) std::printf("wrote %s\n", tolerance_path.c_str());
  if (!envelope_path.empty()) std::printf("wrote %s\n", envelope_path.c_str());
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "error: cannot write the standard output\n";
    return 1;
  }
  return ok == count ? 0 : 3;
}
