/**
 * \file study/spec.h
 * A design study as written in its file (docs/studies.md): the parameters that vary and how
 * (grid, list, Latin hypercube, Monte-Carlo from normal or uniform distributions given as
 * nominal +- tolerance, seeded), the analysis run per sample (a kinematic sweep or statics
 * over a motion, the machine's cycle and flywheel, an engine's cycle and flywheel, or a
 * simulation of the free motion), the
 * metrics kept per sample, joint clearances and whether to compare the
 * first-order tolerance analysis with the Monte-Carlo. Read with yaml-cpp; every error is
 * "FILE:LINE:COLUMN: error: what is wrong; what to write instead". Model-independent: the
 * names (parameters, columns, points, checks) are checked against the model by the study's
 * runner (study/run.h), which reports them at the places kept here.
 */
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/io/yaml_strict.h"
#include "mechgen/machines/engine/gas.h"

namespace mechgen::study {

/// The most samples a study takes (count: of lhs and monte_carlo; a grid's product of value
/// counts, a list's length).
constexpr uint64_t kMaxSamples = 100000000;
/// The largest study file read (a list of 10^6 values is ~20 MB).
constexpr uint64_t kMaxStudyBytes = uint64_t(64) << 20;

/// Where a node of the study file is, for messages ("file:line:column").
struct Place {
  int line = 0, column = 0;  ///< 1-based; 0: unknown
};

enum class Method { kGrid, kList, kLatinHypercube, kMonteCarlo };
enum class Distribution { kNone, kUniform, kNormal };
enum class Analysis { kSweep, kStatics, kFlywheel, kSimulate, kPositions, kEngine };
enum class MetricKind {
  kMax,
  kMin,
  kRms,
  kAt,                    // of an output column over the motion / at one step
  kMinTransmissionAngle,  // min over steps and loops of min(mu, pi - mu)
  kPeakDrive,             // max |drive| of the first input (statics)
  kPeakBearing,           // max |reaction force| over the joints (statics)
  kPathDeviation,         // max |r_P - r_P,nominal| over the steps
  kFailures,              // rows that did not converge (simulate: samples not reached)
  kDesignMargin,          // the smallest design-check margin (or one check's)
  kFlywheelInertia,       // flywheel: the inertia to add for a C_s (machines/flywheel)
  kMeanTorque,            // flywheel: the mean required driving torque over the cycle
  kPeakTorque,            // flywheel: the largest |required driving torque| over the cycle
  kEnergyFluctuation,     // flywheel: the energy loop's Delta E
  kSpeedFluctuation,      // engine: C_s with the model's own flywheel J_fly
};

/// Whether a metric of kind k reads the cycle of the flywheel or the engine analysis.
inline bool IsFlywheelMetric(MetricKind k) {
  return k == MetricKind::kFlywheelInertia || k == MetricKind::kMeanTorque || k == MetricKind::kPeakTorque ||
         k == MetricKind::kEnergyFluctuation || k == MetricKind::kSpeedFluctuation;
}

/// A parameter that varies.
struct ParameterSpec {
  std::string name;
  Place place;
  std::vector<double> values;  ///< grid or list: the values it takes
  Distribution distribution = Distribution::kNone;
  bool has_nominal = false;  ///< else the model's default
  double nominal = 0;
  /// uniform: the half-width (nominal +- tolerance); normal: 3 sigma.
  double tolerance = 0;
  double sigma() const { return distribution == Distribution::kNormal ? tolerance / 3 : tolerance / std::sqrt(3.0); }
};

/// A metric kept per sample.
struct MetricSpec {
  std::string name;  ///< its CSV column
  MetricKind kind = MetricKind::kMax;
  std::string column;  ///< kMax, kMin, kRms, kAt: the output column (sweep, statics or simulate CSV name)
  int step = -1;       ///< kAt: the row 0..steps
  std::string point;   ///< kPathDeviation: the point (as in the sweep's columns, e.g. coupler.P)
  std::string check;   ///< kDesignMargin: one check's name; empty: the smallest margin
  double C_s = 0;      ///< kFlywheelInertia: the coefficient of speed fluctuation
  Place place;
};

/// A joint clearance: a radial clearance of the joint taken as an effective change of the
/// length `parameter` by +-radial, in whichever direction is worst for each metric.
struct ClearanceSpec {
  std::string joint;
  std::string parameter;
  double radial = 0;
  Place place;
};

/// analysis: simulate with drive: one input moved by a law of time (dynamics/prescribed.h, as
/// `<model>_simulate --drive NAME=LAW`): speed (q = q0 + W t), move or cycloidal (rest to rest
/// from q0 to Q1 over [T0, T1]).
struct DriveSpec {
  std::string input;   ///< empty: no drive (a free run)
  std::string law;     ///< speed, move, cycloidal
  std::vector<double> values;  ///< speed: {W}; move, cycloidal: {Q1, T0, T1}
  Place place;
};

/// analysis: engine: the pressure law of every cylinder, as `<engine>_engine` takes it (--table,
/// or the polytropic cycle with a Wiebe heat release whose bore, stroke and rod come from each
/// sample's design: machines/engine/cycle.h).
struct GasSpec {
  std::string table;  ///< an indicator diagram (CSV 'angle_deg,p_gauge_Pa'), resolved; empty: the law
  engine::PolytropicWiebeParams wiebe;  ///< the law's parameters (the tool's defaults)
  Place place;
};

/// The whole study.
struct StudySpec {
  std::string path;
  std::string text;  ///< the study file's bytes (the shards' key)
  Method method = Method::kMonteCarlo;
  uint64_t count = 0;  ///< samples (lhs, monte_carlo); grid and list: derived
  uint64_t seed = 1;
  Analysis analysis = Analysis::kSweep;
  int steps = 360;
  double omega = 0;  ///< flywheel: the mean speed (rad/s)
  double rpm = 0;    ///< engine: the crank speed (1/min)
  GasSpec gas;       ///< engine: the pressure law
  /// simulate: the free motion from t = 0 to t_end (s), sampled every t_end / steps, from the
  /// inputs q0 and speeds qd0 (empty: the model's assembly inputs, at rest).
  double t_end = 0;
  std::vector<double> q0, qd0;
  Place q0_place, qd0_place;
  DriveSpec drive;  ///< simulate: the driven input and its law (none: the free motion)
  /// positions: the first input's values, one row each (empty: range and steps, as a sweep).
  std::vector<double> at;
  bool has_range = false;  ///< else the model's range of the first input
  double q_begin = 0, q_end = 0;
  Place range_place;  ///< range: (else steps:, else analysis:)
  std::vector<ParameterSpec> parameters;
  std::vector<MetricSpec> metrics;
  std::vector<ClearanceSpec> clearances;
  bool tolerance = false;  ///< the first-order vs Monte-Carlo report
  /// A point whose path every sample keeps (the envelope: first-order and Monte-Carlo sigma of
  /// its x and y at every row); empty: none.
  std::string envelope;
  Place envelope_place;
  Place analysis_place;
  /// rows: all (the default): a CSV row per sample (with --csv); rows: none: the statistics
  /// alone (the summary, --summary-csv, the tolerance and envelope tables): no row per sample
  /// is formatted or written, and --csv is refused.
  bool rows = true;
  Place rows_place;
  int histogram_bins = 40;  ///< histogram_bins: the bins of each metric's histogram (--summary-csv)
};

namespace spec_internal {

inline Place PlaceOf(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.is_null() ? Place() : Place{m.line + 1, m.column + 1};
}

struct Failure {
  Place place;
  std::string message;
};

[[noreturn]] inline void Fail(const YAML::Node& n, const std::string& message) { throw Failure{PlaceOf(n), message}; }

// A number: a YAML scalar, optionally ending in "deg" (an angle in degrees, in radians here).
inline double Number(const YAML::Node& n, const std::string& what) {
  if (!n.IsScalar()) Fail(n, what + ": expected a number");
  std::string text = n.Scalar();
  const bool degrees = text.size() > 3 && text.compare(text.size() - 3, 3, "deg") == 0;
  if (degrees) {
    text.resize(text.size() - 3);
    while (!text.empty() && (text.back() == ' ' || text.back() == '*')) text.pop_back();
  }
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x))
    Fail(n, what + ": '" + n.Scalar() + "' is not a finite number (an angle may end in deg)");
  return degrees ? mechgen::internal::FromDegrees(x) : x;
}

inline long long Integer(const YAML::Node& n, const std::string& what, long long lo, long long hi) {
  if (!n.IsScalar()) Fail(n, what + ": expected an integer");
  char* end = nullptr;
  const long long x = std::strtoll(n.Scalar().c_str(), &end, 10);
  if (n.Scalar().empty() || *end != '\0' || x < lo || x > hi)
    Fail(n,
         what + ": '" + n.Scalar() + "' is not an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return x;
}

// The text with its control characters as \xNN (for a message on one line).
inline std::string Printable(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const unsigned char u = static_cast<unsigned char>(ch);
    if (u < 0x20 || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02x", u);
      out += hex;
    } else {
      out += ch;
    }
  }
  return out;
}

inline std::string Text(const YAML::Node& n, const std::string& what) {
  if (!n.IsScalar() || n.Scalar().empty()) Fail(n, what + ": expected a name");
  return n.Scalar();
}

inline void OnlyKeys(const YAML::Node& map, const std::vector<std::string>& allowed, const std::string& what) {
  for (const auto& kv : map) {
    const std::string key = kv.first.as<std::string>();
    bool ok = false;
    for (const std::string& a : allowed) ok = ok || key == a;
    if (!ok) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      Fail(kv.first, "unknown key '" + key + "' in " + what + " (allowed: " + list + ")");
    }
  }
}

}  // namespace spec_internal

/// Whether every value a parameter of distribution p can take about `nominal` is a finite
/// double: the uniform's nominal +- tolerance, the normal's nominal +- 9 sigma (= 3 tolerance;
/// the largest quantile of study/random.h's uniforms, (0.5 / 2^53), is 8.3 sigma).
inline bool SpreadFits(const ParameterSpec& p, double nominal) {
  const double reach = p.distribution == Distribution::kNormal ? 3 * p.tolerance : p.tolerance;
  return std::isfinite(reach) && std::isfinite(std::abs(nominal) + reach);
}
/// What SpreadFits refuses, in words.
inline std::string SpreadProblem(const ParameterSpec& p) {
  return std::string(p.distribution == Distribution::kNormal
                         ? "nominal +- 9 sigma (the reach of the samples)"
                         : "nominal +- tolerance") +
         " overflows a double: the samples would be inf or nan; give a smaller tolerance or nominal";
}

namespace spec_internal {

inline ParameterSpec Parameter(const YAML::Node& key, const YAML::Node& n, Method method) {
  ParameterSpec p;
  p.name = key.as<std::string>();
  p.place = PlaceOf(key);
  const std::string what = "parameter '" + p.name + "'";
  if (!n.IsMap())
    Fail(n, what + ": expected a map such as {values: [1, 2]} or {distribution: normal, tolerance: 0.01}");
  OnlyKeys(n, {"values", "range", "count", "distribution", "nominal", "tolerance", "sigma"}, what);
  if (method == Method::kGrid || method == Method::kList) {
    if (n["values"]) {
      if (!n["values"].IsSequence() || n["values"].size() == 0)
        Fail(n["values"], what + ": values: expected a list of numbers");
      for (const auto& v : n["values"]) p.values.push_back(Number(v, what + " values"));
    } else if (n["range"] && method == Method::kGrid) {
      const YAML::Node r = n["range"];
      if (!r.IsSequence() || r.size() != 2) Fail(r, what + ": range: expected [low, high]");
      if (!n["count"]) Fail(n, what + ": a range needs count: (the number of values, >= 2)");
      const double lo = Number(r[0], what + " range"), hi = Number(r[1], what + " range");
      if (!std::isfinite(hi - lo))
        Fail(r, what + ": range: the width high - low overflows a double; give a narrower range");
      const long long count = Integer(n["count"], what + " count", 2, 1000000);
      for (long long k = 0; k < count; ++k) p.values.push_back(lo + (hi - lo) * double(k) / double(count - 1));
    } else {
      Fail(n, what + ": a " + std::string(method == Method::kGrid ? "grid" : "list") + " study needs values: [...]" +
                  (method == Method::kGrid ? " or range: [low, high] with count:" : ""));
    }
    for (const char* k : {"distribution", "nominal", "tolerance", "sigma"})
      if (n[k]) Fail(n[k], what + ": " + k + " belongs to a lhs or monte_carlo study, not to a grid or list");
    return p;
  }
  if (n["values"] || n["count"])
    Fail(n["values"] ? n["values"] : n["count"],
         what + ": values and count belong to a grid or list study; give distribution: and tolerance:");
  const std::string dist = n["distribution"] ? Text(n["distribution"], what + " distribution") : "normal";
  if (dist == "normal") {
    p.distribution = Distribution::kNormal;
  } else if (dist == "uniform") {
    p.distribution = Distribution::kUniform;
  } else {
    Fail(n["distribution"], what + ": distribution '" + dist + "': expected normal or uniform");
  }
  if (n["range"]) {
    const YAML::Node r = n["range"];
    if (p.distribution != Distribution::kUniform)
      Fail(r, what +
                  ": range: [low, high] is for distribution: uniform; a normal takes nominal: and tolerance: (3 sigma) "
                  "or sigma:");
    if (!r.IsSequence() || r.size() != 2) Fail(r, what + ": range: expected [low, high]");
    const double lo = Number(r[0], what + " range"), hi = Number(r[1], what + " range");
    if (!(hi > lo)) Fail(r, what + ": range: expected low < high");
    if (!std::isfinite(hi - lo))
      Fail(r, what + ": range: the width high - low overflows a double; give a narrower range");
    if (n["nominal"] || n["tolerance"] || n["sigma"])
      Fail(r, what + ": give range: or nominal: with tolerance:, not both");
    p.has_nominal = true;
    p.nominal = lo / 2 + hi / 2;  // (lo + hi) / 2 without overflow
    p.tolerance = (hi - lo) / 2;
    if (!SpreadFits(p, p.nominal)) Fail(r, what + ": " + SpreadProblem(p));
    return p;
  }
  if (n["nominal"]) {
    p.has_nominal = true;
    p.nominal = Number(n["nominal"], what + " nominal");
  }
  if (n["tolerance"] && n["sigma"]) Fail(n["sigma"], what + ": give tolerance: or sigma:, not both");
  if (n["sigma"]) {
    if (p.distribution != Distribution::kNormal)
      Fail(n["sigma"], what + ": sigma: is for a normal; a uniform takes tolerance: (its half-width)");
    p.tolerance = 3 * Number(n["sigma"], what + " sigma");
  } else if (n["tolerance"]) {
    p.tolerance = Number(n["tolerance"], what + " tolerance");
  } else {
    Fail(n, what + ": needs tolerance: (normal: 3 sigma; uniform: the half-width) or sigma:");
  }
  const YAML::Node spread = n["tolerance"] ? n["tolerance"] : n["sigma"];
  if (!(p.tolerance > 0)) Fail(spread, what + ": the tolerance must be > 0");
  if (!SpreadFits(p, p.nominal)) Fail(spread, what + ": " + SpreadProblem(p));
  return p;
}

inline MetricSpec Metric(const YAML::Node& n, int steps) {
  MetricSpec m;
  m.place = PlaceOf(n);
  if (!n.IsMap() || !n["kind"]) Fail(n, "a metric: expected a map with kind:, e.g. {kind: max, column: coupler.P.y}");
  OnlyKeys(n, {"name", "kind", "column", "step", "point", "check", "C_s"}, "a metric");
  const std::string kind = Text(n["kind"], "metric kind");
  struct K {
    const char* name;
    MetricKind kind;
    const char* needs;
  };
  static const K kinds[] = {{"max", MetricKind::kMax, "column"},
                            {"min", MetricKind::kMin, "column"},
                            {"rms", MetricKind::kRms, "column"},
                            {"at", MetricKind::kAt, "column"},
                            {"min_transmission_angle", MetricKind::kMinTransmissionAngle, ""},
                            {"peak_drive", MetricKind::kPeakDrive, ""},
                            {"peak_bearing", MetricKind::kPeakBearing, ""},
                            {"path_deviation", MetricKind::kPathDeviation, "point"},
                            {"failures", MetricKind::kFailures, ""},
                            {"design_margin", MetricKind::kDesignMargin, ""},
                            {"flywheel_inertia", MetricKind::kFlywheelInertia, ""},
                            {"mean_torque", MetricKind::kMeanTorque, ""},
                            {"peak_torque", MetricKind::kPeakTorque, ""},
                            {"energy_fluctuation", MetricKind::kEnergyFluctuation, ""},
                            {"speed_fluctuation", MetricKind::kSpeedFluctuation, ""}};
  const K* found = nullptr;
  for (const K& k : kinds)
    if (kind == k.name) found = &k;
  if (found == nullptr) {
    std::string list;
    for (const K& k : kinds) list += (list.empty() ? "" : ", ") + std::string(k.name);
    Fail(n["kind"], "unknown metric kind '" + kind + "' (kinds: " + list + ")");
  }
  m.kind = found->kind;
  const std::string needs = found->needs;
  for (const char* key : {"column", "point"}) {
    if (n[key] && needs != key) Fail(n[key], "a metric of kind " + kind + " takes no " + key + ":");
    if (!n[key] && needs == key) Fail(n, "a metric of kind " + kind + " needs " + key + ":");
  }
  if (n["column"]) m.column = Text(n["column"], "metric column");
  if (n["point"]) m.point = Text(n["point"], "metric point");
  if (m.kind == MetricKind::kAt) {
    if (!n["step"]) Fail(n, "a metric of kind at needs step: (a row, 0.." + std::to_string(steps) + ")");
    m.step = static_cast<int>(Integer(n["step"], "metric step", 0, steps));
  } else if (n["step"]) {
    Fail(n["step"], "only a metric of kind at takes step:");
  }
  if (n["check"]) {
    if (m.kind != MetricKind::kDesignMargin) Fail(n["check"], "only a metric of kind design_margin takes check:");
    m.check = Text(n["check"], "metric check");
  }
  if (m.kind == MetricKind::kFlywheelInertia) {
    if (!n["C_s"]) Fail(n, "a metric of kind flywheel_inertia needs C_s: (the coefficient of speed fluctuation, e.g. 0.02)");
    m.C_s = Number(n["C_s"], "metric C_s");
    if (!(m.C_s > 0 && m.C_s < 1)) Fail(n["C_s"], "C_s: expected a coefficient of speed fluctuation in (0, 1)");
  } else if (n["C_s"]) {
    Fail(n["C_s"], "only a metric of kind flywheel_inertia takes C_s:");
  }
  if (n["name"]) {
    m.name = Text(n["name"], "metric name");
    // The name is a CSV column (and a '#' line's first word): no separator, quote, line break or
    // other control character, no space at either end (the header is not quoted).
    for (const char ch : m.name)
      if (ch == ',' || ch == '"' || static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
        Fail(n["name"], "metric name '" + Printable(m.name) +
                            "': a CSV column name cannot hold a comma, a double quote, a line break or a control "
                            "character; use letters, digits and _ . - for instance");
    if (m.name.front() == ' ' || m.name.back() == ' ' || m.name.front() == '#')
      Fail(n["name"], "metric name '" + Printable(m.name) + "': no space at either end and no '#' first");
  } else {
    switch (m.kind) {
      case MetricKind::kAt:
        m.name = m.column + "_at_" + std::to_string(m.step);
        break;
      case MetricKind::kMax:
      case MetricKind::kMin:
      case MetricKind::kRms:
        m.name = kind + "_" + m.column;
        break;
      case MetricKind::kPathDeviation:
        m.name = "path_deviation_" + m.point;
        break;
      case MetricKind::kDesignMargin:
        m.name = m.check.empty() ? "design_margin" : "margin_" + m.check;
        break;
      default:
        m.name = kind;
    }
  }
  return m;
}

}  // namespace spec_internal

/// Reads the study file `path` into *spec; false and *error ("path:line:column: error: ...",
/// one line) on the first problem.
inline bool ReadStudy(const std::string& path, StudySpec* spec, std::string* error) {
  using namespace spec_internal;
  *spec = StudySpec();
  spec->path = path;
  auto at = [&path](Place p) {
    return path + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": error: ";
  };
  // The file's bytes, read once (the shards' key reads them too): a regular file, bounded.
  {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) {
      *error = path + ": error: cannot read the study file (" + (ec ? ec.message() : "no such file") +
               "); check the path";
      return false;
    }
    if (fs::is_directory(st)) {
      *error = path + ": error: is a directory, not a study file; give the path of a .yaml file";
      return false;
    }
    if (!fs::is_regular_file(st)) {
      *error = path + ": error: is not a regular file (a device, a pipe or a socket); give the path of a .yaml file";
      return false;
    }
    std::ifstream in(path, std::ios::binary);
    // At most one byte more than the limit: a file that grows while read is bounded too.
    const uint64_t size = fs::file_size(path, ec);
    std::string text(static_cast<size_t>(std::min<uint64_t>(ec ? kMaxStudyBytes : size, kMaxStudyBytes) + 1), '\0');
    if (in) in.read(&text[0], static_cast<std::streamsize>(text.size()));
    if (!in && !in.eof()) {
      *error = path + ": error: cannot read the study file (permission denied?); check the path";
      return false;
    }
    const size_t room = text.size();
    text.resize(static_cast<size_t>(in.gcount()));
    if (text.size() == room && room <= kMaxStudyBytes) {
      *error = path + ": error: the study file grew while it was read; run again when it is written";
      return false;
    }
    if (text.size() > kMaxStudyBytes) {
      *error = path + ": error: is larger than " + std::to_string(kMaxStudyBytes >> 20) +
               " MiB, the limit for a study file";
      return false;
    }
    spec->text = std::move(text);
  }
  YAML::Node root;
  try {
    root = io::LoadStrict(spec->text);  // one document, no key twice in a mapping
  } catch (const YAML::Exception& e) {
    *error = at(Place{e.mark.line + 1, e.mark.column + 1}) + e.msg;
    return false;
  }
  try {
    if (!root.IsMap()) Fail(root, "a study file is a map (method:, parameters:, metrics:, ...; docs/studies.md)");
    OnlyKeys(root,
             {"model", "method", "count", "seed", "analysis", "steps", "range", "omega", "rpm", "gas", "t_end", "q0",
              "qd0", "drive", "at", "parameters", "metrics", "clearance", "tolerance", "envelope", "rows",
              "histogram_bins"},
             "the study");
    const std::string method = root["method"] ? Text(root["method"], "method") : "";
    if (method == "grid")
      spec->method = Method::kGrid;
    else if (method == "list")
      spec->method = Method::kList;
    else if (method == "lhs")
      spec->method = Method::kLatinHypercube;
    else if (method == "monte_carlo")
      spec->method = Method::kMonteCarlo;
    else
      Fail(root["method"] ? root["method"] : root, "method: expected grid, list, lhs or monte_carlo");
    const bool random = spec->method == Method::kLatinHypercube || spec->method == Method::kMonteCarlo;
    if (random) {
      if (!root["count"]) Fail(root, "a " + method + " study needs count: (the number of samples)");
      spec->count = static_cast<uint64_t>(Integer(root["count"], "count", 2, static_cast<long long>(kMaxSamples)));
    } else if (root["count"]) {
      Fail(root["count"],
           "count: is for lhs and monte_carlo; a " + method + " study has as many samples as its values give");
    }
    if (root["seed"]) spec->seed = static_cast<uint64_t>(Integer(root["seed"], "seed", 0, (1LL << 62)));
    spec->analysis_place = PlaceOf(root["analysis"] ? root["analysis"] : root);
    const std::string analysis = root["analysis"] ? Text(root["analysis"], "analysis") : "sweep";
    if (analysis == "sweep")
      spec->analysis = Analysis::kSweep;
    else if (analysis == "statics")
      spec->analysis = Analysis::kStatics;
    else if (analysis == "flywheel")
      spec->analysis = Analysis::kFlywheel;
    else if (analysis == "simulate")
      spec->analysis = Analysis::kSimulate;
    else if (analysis == "positions")
      spec->analysis = Analysis::kPositions;
    else if (analysis == "engine")
      spec->analysis = Analysis::kEngine;
    else
      Fail(root["analysis"],
           "analysis: '" + analysis + "': expected sweep, statics, flywheel, simulate, positions or engine");
    if (spec->analysis == Analysis::kEngine) {
      if (!root["rpm"]) Fail(root["analysis"], "analysis: engine needs rpm: (the crank speed, 1/min)");
      spec->rpm = Number(root["rpm"], "rpm");
      if (!(spec->rpm > 0 && spec->rpm <= 1e5)) Fail(root["rpm"], "rpm: expected a crank speed > 0 and <= 1e5 (1/min)");
      if (root["range"]) Fail(root["range"], "range: the engine analysis runs the engine's cycle (no range:)");
      spec->gas.place = PlaceOf(root["gas"] ? root["gas"] : root["analysis"]);
      if (const YAML::Node g = root["gas"]) {
        if (!g.IsMap())
          Fail(g, "gas: expected a map, {table: FILE} or the law's parameters, e.g. {heat: 800, burn_start: -15deg}");
        OnlyKeys(g,
                 {"table", "cr", "p_intake", "p_ambient", "n", "burn_start", "burn_duration", "wiebe_a", "wiebe_m",
                  "heat"},
                 "gas");
        engine::PolytropicWiebeParams& w = spec->gas.wiebe;
        struct Key {
          const char* name;
          double* value;
          double lo, hi;
          bool lo_open;
          const char* unit;
        };
        const double two_turns = mechgen::internal::FromDegrees(720);  // a four-stroke cycle
        const Key keys[] = {{"cr", &w.compression_ratio, 0, 1000, true, ""},
                            {"p_intake", &w.p_intake, 0, 1e9, true, " Pa"},
                            {"p_ambient", &w.p_ambient, 0, 1e9, true, " Pa"},
                            {"n", &w.n, 0, 10, true, ""},
                            {"burn_start", &w.burn_start, -two_turns, two_turns, false, " rad (e.g. -15deg)"},
                            {"burn_duration", &w.burn_duration, 0, two_turns, true, " rad (e.g. 60deg)"},
                            {"wiebe_a", &w.wiebe_a, 0, 100, true, ""},
                            {"wiebe_m", &w.wiebe_m, 0, 100, false, ""},
                            {"heat", &w.heat, 0, 1e9, false, " J per cylinder and cycle"}};
        for (const Key& k : keys) {
          if (!g[k.name]) continue;
          if (g["table"]) Fail(g[k.name], std::string("gas: ") + k.name + ": give table: or the law's parameters, not both");
          const double x = Number(g[k.name], std::string("gas ") + k.name);
          if (!((k.lo_open ? x > k.lo : x >= k.lo) && x <= k.hi))
            Fail(g[k.name], std::string("gas: ") + k.name + ": expected a value in " + (k.lo_open ? "(" : "[") +
                                std::to_string(k.lo) + ", " + std::to_string(k.hi) + "]" + k.unit);
          *k.value = x;
        }
        if (g["table"]) {
          spec->gas.table = Text(g["table"], "gas table");
          spec->gas.place = PlaceOf(g["table"]);
          // Relative to the study file's directory.
          if (spec->gas.table[0] != '/') {
            const size_t slash = path.find_last_of('/');
            if (slash != std::string::npos) spec->gas.table = path.substr(0, slash + 1) + spec->gas.table;
          }
        }
      }
    } else {
      for (const char* key : {"rpm", "gas"})
        if (root[key]) Fail(root[key], std::string(key) + ": is for analysis: engine");
    }
    if (spec->analysis == Analysis::kFlywheel) {
      if (!root["omega"]) Fail(root["analysis"], "analysis: flywheel needs omega: (the mean speed, rad/s)");
      spec->omega = Number(root["omega"], "omega");
      if (!(spec->omega > 0)) Fail(root["omega"], "omega: the mean speed must be > 0 (rad/s)");
      if (root["range"]) Fail(root["range"], "range: the flywheel analysis runs the model's cycle (no range:)");
    } else if (root["omega"]) {
      Fail(root["omega"], "omega: is for analysis: flywheel");
    }
    if (spec->analysis == Analysis::kSimulate) {
      if (!root["t_end"]) Fail(root["analysis"], "analysis: simulate needs t_end: (the simulated time, s)");
      spec->t_end = Number(root["t_end"], "t_end");
      if (!(spec->t_end > 0 && spec->t_end <= 1e6)) Fail(root["t_end"], "t_end: expected a time > 0 and <= 1e6 s");
      if (root["range"]) Fail(root["range"], "range: a simulation starts at q0: (no range:)");
      for (const char* key : {"q0", "qd0"}) {
        const YAML::Node n = root[key];
        if (!n) continue;
        if (!n.IsSequence() || n.size() == 0) Fail(n, std::string(key) + ": expected a list, one value per input");
        std::vector<double>& v = std::string(key) == "q0" ? spec->q0 : spec->qd0;
        for (const auto& x : n) {
          v.push_back(Number(x, key));
          if (!(std::abs(v.back()) <= 1e6)) Fail(x, std::string(key) + ": expected a finite value, |value| <= 1e6");
        }
        (std::string(key) == "q0" ? spec->q0_place : spec->qd0_place) = PlaceOf(n);
      }
      if (const YAML::Node d = root["drive"]) {
        const char* form = "drive: expected {INPUT: {speed: W}}, {INPUT: {move: [Q1, T0, T1]}} or "
                           "{INPUT: {cycloidal: [Q1, T0, T1]}} (one driven input)";
        if (!d.IsMap() || d.size() != 1) Fail(d, form);
        const auto kv = *d.begin();
        spec->drive.input = Text(kv.first, "drive input");
        spec->drive.place = PlaceOf(kv.first);
        const YAML::Node law = kv.second;
        if (!law.IsMap() || law.size() != 1) Fail(law, form);
        OnlyKeys(law, {"speed", "move", "cycloidal"}, "a drive's law");
        const auto lv = *law.begin();
        spec->drive.law = lv.first.as<std::string>();
        if (spec->drive.law == "speed") {
          spec->drive.values.push_back(Number(lv.second, "drive speed"));
          if (!(std::abs(spec->drive.values[0]) <= 1e5)) Fail(lv.second, "drive speed: expected |W| <= 1e5");
        } else {
          if (!lv.second.IsSequence() || lv.second.size() != 3)
            Fail(lv.second, "drive " + spec->drive.law + ": expected [Q1, T0, T1] (the end value, 0 <= T0 < T1)");
          for (const auto& x : lv.second) spec->drive.values.push_back(Number(x, "drive " + spec->drive.law));
          if (!(std::abs(spec->drive.values[0]) <= 1e6 && spec->drive.values[1] >= 0 &&
                spec->drive.values[2] > spec->drive.values[1]))
            Fail(lv.second, "drive " + spec->drive.law + ": expected |Q1| <= 1e6 and 0 <= T0 < T1");
        }
      }
    } else {
      if (root["drive"]) Fail(root["drive"], "drive: is for analysis: simulate");
      for (const char* key : {"t_end", "q0", "qd0"})
        if (root[key]) Fail(root[key], std::string(key) + ": is for analysis: simulate");
    }
    if (root["steps"]) spec->steps = static_cast<int>(Integer(root["steps"], "steps", 1, 1000000));
    spec->range_place = PlaceOf(root["steps"] ? root["steps"] : root["analysis"] ? root["analysis"] : root);
    if (const YAML::Node a = root["at"]) {
      if (spec->analysis != Analysis::kPositions) Fail(a, "at: is for analysis: positions");
      if (!a.IsSequence() || a.size() == 0 || a.size() > 1000001)
        Fail(a, "at: expected a list of the first input's values, e.g. [0, 30deg, 60deg]");
      if (root["steps"] || root["range"])
        Fail(a, "at: lists the input's values; give at: or range: with steps:, not both");
      for (const auto& x : a) spec->at.push_back(Number(x, "at"));
      spec->steps = static_cast<int>(spec->at.size()) - 1;  // the rows: 0 .. steps
    }
    if (root["range"]) {
      const YAML::Node r = root["range"];
      if (!r.IsSequence() || r.size() != 2)
        Fail(r, "range: expected [begin, end] of the first input (an angle may end in deg)");
      spec->has_range = true;
      spec->range_place = PlaceOf(r);
      spec->q_begin = Number(r[0], "range");
      spec->q_end = Number(r[1], "range");
    }
    const YAML::Node params = root["parameters"];
    if (!params || !params.IsMap() || params.size() == 0)
      Fail(params ? params : root,
           "parameters: expected a map of the parameters that vary, e.g. {a: {distribution: normal, tolerance: 0.01}}");
    for (const auto& kv : params) spec->parameters.push_back(Parameter(kv.first, kv.second, spec->method));
    // A grid's samples: the product of the value counts, checked as it grows (four parameters of
    // 65536 values are 2^64 samples: 0 in uint64_t arithmetic).
    if (spec->method == Method::kGrid) {
      uint64_t product = 1;
      std::string factors;
      for (const ParameterSpec& p : spec->parameters) {
        const uint64_t m = p.values.size();
        factors += (factors.empty() ? "" : " x ") + std::to_string(m);
        if (product > kMaxSamples / m)
          throw Failure{p.place, "a grid of " + factors + (&p == &spec->parameters.back() ? "" : " x ...") +
                                     " values is more than " + std::to_string(kMaxSamples) +
                                     " samples, the most a study takes; give fewer values (or a monte_carlo or lhs "
                                     "study with count:)"};
        product *= m;
      }
    }
    if (spec->method == Method::kList && !spec->parameters.empty() &&
        spec->parameters[0].values.size() > kMaxSamples)
      throw Failure{spec->parameters[0].place, "a list of more than " + std::to_string(kMaxSamples) +
                                                   " samples, the most a study takes"};
    for (size_t i = 0; i < spec->parameters.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if (spec->parameters[i].name == spec->parameters[j].name)
          throw Failure{spec->parameters[i].place, "parameter '" + spec->parameters[i].name + "' twice"};
    if (spec->method == Method::kList)
      for (const ParameterSpec& p : spec->parameters)
        if (p.values.size() != spec->parameters[0].values.size())
          throw Failure{p.place, "a list study takes the i-th value of every parameter: '" + p.name + "' has " +
                                     std::to_string(p.values.size()) + " values, '" + spec->parameters[0].name + "' " +
                                     std::to_string(spec->parameters[0].values.size())};
    const YAML::Node metrics = root["metrics"];
    if (!metrics || !metrics.IsSequence() || metrics.size() == 0)
      Fail(metrics ? metrics : root,
           "metrics: expected a list, e.g. [{kind: max, column: coupler.P.y}, {kind: failures}]");
    for (const auto& m : metrics) spec->metrics.push_back(Metric(m, spec->steps));
    for (const MetricSpec& m : spec->metrics) {
      if (spec->analysis == Analysis::kSimulate && m.kind != MetricKind::kMax && m.kind != MetricKind::kMin &&
          m.kind != MetricKind::kRms && m.kind != MetricKind::kAt && m.kind != MetricKind::kFailures &&
          m.kind != MetricKind::kDesignMargin && m.kind != MetricKind::kPeakBearing &&
          m.kind != MetricKind::kPeakDrive)
        throw Failure{m.place,
                      "with analysis: simulate the metrics are max, min, rms and at of a column of the "
                      "simulation's CSV, peak_bearing, peak_drive (with drive:), failures and design_margin"};
      if (spec->analysis == Analysis::kSimulate && m.kind == MetricKind::kPeakDrive && spec->drive.input.empty())
        throw Failure{m.place,
                      "peak_drive of a simulation is the largest |lambda| of a driven input: give drive: "
                      "(e.g. {theta: {speed: 10}})"};
      if (spec->analysis == Analysis::kPositions &&
          (m.kind == MetricKind::kPeakDrive || m.kind == MetricKind::kPeakBearing))
        throw Failure{m.place, "analysis: positions has no forces (use analysis: statics or simulate)"};
      const bool cycle = IsFlywheelMetric(m.kind);
      if (m.kind == MetricKind::kSpeedFluctuation && spec->analysis != Analysis::kEngine)
        throw Failure{m.place, "a metric of kind speed_fluctuation needs analysis: engine"};
      if (cycle && spec->analysis != Analysis::kFlywheel && spec->analysis != Analysis::kEngine)
        throw Failure{m.place, "a metric of this kind needs analysis: flywheel or engine"};
      // (max, min, rms and at read a column of the cycle's CSV by name: study/run.h)
      const bool of_column = m.kind == MetricKind::kMax || m.kind == MetricKind::kMin || m.kind == MetricKind::kRms ||
                             m.kind == MetricKind::kAt;
      if (!cycle && !of_column && spec->analysis == Analysis::kFlywheel && m.kind != MetricKind::kDesignMargin &&
          m.kind != MetricKind::kFailures)
        throw Failure{m.place,
                      "with analysis: flywheel the metrics are flywheel_inertia, mean_torque, peak_torque, "
                      "energy_fluctuation, max, min, rms and at of a column of the energy loop's CSV (`mechgen "
                      "flywheel --csv`), failures and design_margin"};
      if (!cycle && !of_column && spec->analysis == Analysis::kEngine && m.kind != MetricKind::kDesignMargin &&
          m.kind != MetricKind::kFailures)
        throw Failure{m.place,
                      "with analysis: engine the metrics are mean_torque, peak_torque, energy_fluctuation, "
                      "flywheel_inertia, speed_fluctuation, max, min, rms and at of a column of the engine's cycle "
                      "CSV or energy loop CSV (`mechgen engine cycle`, `flywheel`), failures and design_margin"};
    }
    if ((spec->analysis == Analysis::kFlywheel || spec->analysis == Analysis::kSimulate ||
         spec->analysis == Analysis::kEngine) &&
        root["envelope"])
      Fail(root["envelope"], "envelope: needs a motion of the input (analysis: sweep or statics)");
    if (spec->analysis == Analysis::kFlywheel && spec->steps < 4)
      Fail(root["steps"], "steps: the flywheel's cycle needs at least 4 samples");
    if (spec->analysis == Analysis::kEngine && spec->steps < 16)
      Fail(root["steps"], "steps: the engine's cycle needs at least 16 samples (as the engine tool's --samples)");
    for (size_t i = 0; i < spec->metrics.size(); ++i) {
      for (size_t j = 0; j < i; ++j)
        if (spec->metrics[i].name == spec->metrics[j].name)
          throw Failure{spec->metrics[i].place, "two metrics named '" + spec->metrics[i].name + "'; give one a name:"};
      for (const ParameterSpec& p : spec->parameters)
        if (spec->metrics[i].name == p.name || spec->metrics[i].name == "status" || spec->metrics[i].name == "sample")
          throw Failure{spec->metrics[i].place,
                        "a metric named '" + spec->metrics[i].name + "' collides with a column; give it another name:"};
    }
    if (const YAML::Node c = root["clearance"]) {
      if (!c.IsMap()) Fail(c, "clearance: expected a map {JOINT: {parameter: LENGTH, radial: C}}");
      for (const auto& kv : c) {
        ClearanceSpec k;
        k.joint = kv.first.as<std::string>();
        k.place = PlaceOf(kv.first);
        const std::string what = "clearance of joint '" + k.joint + "'";
        if (!kv.second.IsMap() || !kv.second["parameter"] || !kv.second["radial"])
          Fail(kv.second, what + ": expected {parameter: LENGTH, radial: C}");
        OnlyKeys(kv.second, {"parameter", "radial"}, what);
        k.parameter = Text(kv.second["parameter"], what + " parameter");
        k.radial = Number(kv.second["radial"], what + " radial");
        if (!(k.radial > 0)) Fail(kv.second["radial"], what + ": radial must be > 0");
        spec->clearances.push_back(k);
      }
    }
    if (const YAML::Node e = root["envelope"]) {
      if (!e.IsMap() || !e["point"]) Fail(e, "envelope: expected {point: POINT}, e.g. {point: coupler.P}");
      OnlyKeys(e, {"point"}, "envelope");
      spec->envelope = Text(e["point"], "envelope point");
      spec->envelope_place = PlaceOf(e);
    }
    spec->rows_place = PlaceOf(root["rows"] ? root["rows"] : root);
    if (const YAML::Node r = root["rows"]) {
      if (!r.IsScalar() || (r.Scalar() != "all" && r.Scalar() != "none"))
        Fail(r, "rows: expected all (a CSV row per sample, the default) or none (the statistics alone)");
      spec->rows = r.Scalar() == "all";
    }
    if (root["histogram_bins"])
      spec->histogram_bins = static_cast<int>(Integer(root["histogram_bins"], "histogram_bins", 1, 10000));
    if (const YAML::Node t = root["tolerance"]) {
      if (!t.IsScalar() || (t.Scalar() != "true" && t.Scalar() != "false"))
        Fail(t, "tolerance: expected true or false");
      spec->tolerance = t.Scalar() == "true";
      if (spec->tolerance && spec->method != Method::kMonteCarlo)
        Fail(t, "tolerance: true compares the first-order analysis with a Monte-Carlo: it needs method: monte_carlo");
    }
  } catch (const Failure& f) {
    *error = at(f.place) + f.message;
    return false;
  } catch (const YAML::Exception& e) {
    *error = at(Place{e.mark.line + 1, e.mark.column + 1}) + e.msg;
    return false;
  }
  return true;
}

/// The number of samples the study has (grid: the product of the value counts).
inline uint64_t SampleCount(const StudySpec& s) {
  if (s.method == Method::kList) return s.parameters.empty() ? 0 : s.parameters[0].values.size();
  if (s.method == Method::kGrid) {
    uint64_t n = 1;
    for (const ParameterSpec& p : s.parameters) n *= p.values.size();
    return n;
  }
  return s.count;
}

}  // namespace mechgen::study
