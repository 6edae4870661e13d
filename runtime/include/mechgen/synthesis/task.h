/**
 * \file synthesis/task.h
 * A dimensional-synthesis task (issue 28) as written in its YAML file beside the model (the
 * format: docs/synthesis.md). Model-independent: ParseTask() reads and checks the file's
 * own structure (kinds, numbers, sizes); BindPathTask() (synthesis/path.h) then checks the
 * names against the generated model. Every error says FILE:LINE:COLUMN: error: and what to change.
 * Needs yaml-cpp (link yaml-cpp).
 */
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mechgen/io/format.h"
#include "mechgen/io/yaml_strict.h"

namespace mechgen::synthesis {

/// A bounded design variable: a model parameter (one of the model's `design` names).
struct Variable {
  std::string name;
  double lo = 0, hi = 0;
  int line = 0, column = 0;  ///< where it is in the task file (1-based), for later errors
};

/// The timing of path generation: the input angle at each precision point.
struct Timing {
  bool free = true;                ///< every point's input angle is a variable of its own
  std::vector<double> angles;      ///< prescribed: q_i = offset + angles[i] (+ p[relative_to])
  bool offset_free = false;        ///< the offset is a variable (in [0, 2 pi))
  double offset = 0;               ///< else this value (rad)
  std::string relative_to;         ///< a parameter (the frame's angle) added to every q_i; "" none
  int line = 0, column = 0;
};

/// Constraints; each checked on every candidate (a violation is a defect, see path.h).
struct Constraints {
  bool grashof = false;         ///< s + l <= p + q of the four-bar loop
  bool crank_rotates = false;   ///< the input link turns fully: Grashof, input or ground the shortest
  bool crank_shortest = false;  ///< Grashof with the input link the shortest (crank-rocker)
  bool order = false;           ///< free timing: targets reached in increasing input angle within one turn
  bool has_mu = false;          ///< transmission angle bounds over the motion
  double mu_lo = 0, mu_hi = M_PI;
  bool has_lengths = false;     ///< every link length of the four-bar loop in [lo, hi]
  double length_lo = 0, length_hi = std::numeric_limits<double>::infinity();
  bool has_ratio = false;       ///< longest / shortest link of the four-bar loop at most ratio_max
  double ratio_max = std::numeric_limits<double>::infinity();
  /// Ground pivots in a region: each named point of the ground link (the model's scene points;
  /// none named: all of the ground's) inside the rectangle [lo, hi] or the circle about lo.
  bool has_region = false, region_rectangle = false;
  std::vector<std::string> region_pivots;
  double region_lo[2] = {0, 0}, region_hi[2] = {0, 0}, region_radius = 0;
  int region_line = 0, region_column = 0;
};

/// The search's budget.
struct Search {
  long long evaluations = 20000;  ///< global stage, all restarts together
  int restarts = 8;               ///< independent seeded runs (on the threads)
  int population = 0;             ///< per restart; 0: 10 x the number of variables (at least 20)
  int curve_samples = 360;        ///< free timing: the curve sampled at this many input angles
  int local_starts = 3;           ///< the local stage from this many of each run's best candidates
  double local_share = 0.3;       ///< the share of each run's budget kept for the local stage
  /// Path tasks on the four-bar (synthesis/projection.h): the parts that enter linearly (the
  /// frame's placement, scale x rotation, the coupler point) solved by least squares for each
  /// candidate, the search over the link ratios and the timing only (variable projection).
  bool projection = false;
  int projection_line = 0, projection_column = 0;
};

/// The frame's placement (path tasks with prescribed timing): three variables x, y, angle that
/// place the whole model rigidly (every point r = (x, y) + R(angle) r_local) and the timing
/// measured from the angle (timing.relative_to = angle). The global stage then fits them to
/// the targets in closed form (path.h, PathEvaluator::Place) instead of searching them.
struct Placement {
  std::string x, y, angle;   ///< "" when no placement is given
  int line = 0, column = 0;
};

/// Path generation (function and motion generation: later kinds of the same file).
struct PathTask {
  std::string file;          ///< the task file's path, for messages
  std::string model;         ///< `model:` (relative to the task file), "" if not given
  std::string point;         ///< one of the model's points ("coupler.P")
  std::string crank_link;    ///< the input link (for the crank constraints), "" if none asked
  std::vector<double> tx, ty;  ///< the precision points
  Timing timing;
  std::vector<Variable> variables;
  Constraints constraints;
  Search search;
  Placement placement;
  int point_line = 0, point_column = 0, crank_line = 0, crank_column = 0;
};

namespace task_internal {

/// "FILE:LINE:COLUMN: error: " of a place in a task file (the model and study files' form);
/// "FILE: error: " when yaml-cpp gives no place (a null mark).
inline std::string Where(const std::string& file, const YAML::Mark& m) {
  if (m.line < 0 || m.column < 0) return file + ": error: ";
  return file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1) + ": error: ";
}

struct Error {
  std::string message;
};

// A finite number, an angle may end in "deg" (degrees, converted to radians).
inline double Number(const std::string& file, const YAML::Node& n, const std::string& what, bool angle = false) {
  if (!n.IsScalar())
    throw Error{Where(file, n.Mark()) + what + ": expected a number" + (angle ? " (an angle may end in deg)" : "")};
  std::string text = n.Scalar();
  const bool degrees = angle && text.size() > 3 && text.compare(text.size() - 3, 3, "deg") == 0;
  if (degrees) text = text.substr(0, text.size() - 3);
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end == begin || *end != '\0' || !std::isfinite(v))
    throw Error{Where(file, n.Mark()) + what + ": bad number '" + n.Scalar() + "'" +
                (angle ? " (expected e.g. 30deg or 0.5236)" : " (expected a finite number)")};
  return degrees ? mechgen::internal::FromDegrees(v) : v;
}

inline bool Bool(const std::string& file, const YAML::Node& n, const std::string& what) {
  if (n.IsScalar() && (n.Scalar() == "true" || n.Scalar() == "false")) return n.Scalar() == "true";
  throw Error{Where(file, n.Mark()) + what + ": expected true or false"};
}

inline long long Count(const std::string& file, const YAML::Node& n, const std::string& what, long long lo,
                       long long hi) {
  const double v = Number(file, n, what);
  if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
    throw Error{Where(file, n.Mark()) + what + ": expected an integer in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "], got " + n.Scalar()};
  return static_cast<long long>(v);
}

inline void Pair(const std::string& file, const YAML::Node& n, const std::string& what, bool angle, double* lo,
                 double* hi, bool ordered = true) {
  if (!n.IsSequence() || n.size() != 2)
    throw Error{Where(file, n.Mark()) + what + ": expected [min, max]"};
  *lo = Number(file, n[0], what, angle);
  *hi = Number(file, n[1], what, angle);
  if (ordered && !(*lo < *hi))
    throw Error{Where(file, n.Mark()) + what + ": min must be below max"};
}

inline void Known(const std::string& file, const YAML::Node& map, const std::vector<std::string>& keys,
                  const std::string& what) {
  for (auto it = map.begin(); it != map.end(); ++it) {
    const std::string key = it->first.Scalar();
    bool ok = false;
    std::string list;
    for (const std::string& k : keys) {
      ok = ok || key == k;
      list += (list.empty() ? "" : ", ") + k;
    }
    if (!ok) throw Error{Where(file, it->first.Mark()) + "unknown key '" + key + "' in " + what + " (expected: " + list + ")"};
  }
}

inline YAML::Node Required(const std::string& file, const YAML::Node& map, const std::string& key,
                           const std::string& hint) {
  const YAML::Node n = map[key];
  if (!n) throw Error{Where(file, map.Mark()) + "missing '" + key + "': " + hint};
  return n;
}

/// The task's `variables:` ({name: [min, max], ...}: the model's design parameters to vary, in
/// the file's order) into *variables; throws Error at the place of a bad one. `example`: the
/// bounds the message shows. Every kind of task reads its variables here.
inline void ReadVariables(const std::string& path, const YAML::Node& root, const std::string& example,
                          std::vector<Variable>* variables) {
  const YAML::Node vars = Required(path, root, "variables", "the design parameters to vary with bounds, " + example);
  if (!vars.IsMap() || vars.size() == 0)
    throw Error{Where(path, vars.Mark()) + "variables: expected {name: [min, max], ...} of the model's design parameters"};
  for (auto it = vars.begin(); it != vars.end(); ++it) {
    Variable v;
    v.name = it->first.Scalar();
    v.line = it->first.Mark().line + 1;
    v.column = it->first.Mark().column + 1;
    Pair(path, it->second, "variable " + v.name, /*angle=*/true, &v.lo, &v.hi);
    for (const Variable& w : *variables)
      if (w.name == v.name) throw Error{Where(path, it->first.Mark()) + "variable " + v.name + " given twice"};
    variables->push_back(v);
  }
}

/// The largest task file read (the model reader's limit too): a task is a short text.
constexpr size_t kMaxTaskBytes = size_t{1} << 20;

/// The task file's text: false and *error ("FILE: error: ...") for a path that does not exist,
/// a directory, anything that is not a regular file (a device, a pipe: never read), a file
/// that cannot be read or is larger than kMaxTaskBytes (at most one byte more is read).
inline bool ReadTaskText(const std::string& path, std::string* text, std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found)
    return *error = path + ": error: cannot open the task file (no such file); check the path", false;
  if (ec) return *error = path + ": error: cannot open the task file (" + ec.message() + "); check the path", false;
  if (fs::is_directory(st))
    return *error = path + ": error: the path is a directory, not a task file; give the path of a .yaml file", false;
  if (!fs::is_regular_file(st))
    return *error = path + ": error: the path is not a regular file (a device, a pipe or a socket); give the path of a "
                           ".yaml file",
           false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return *error = path + ": error: cannot open the task file (permission denied?); check the path", false;
  std::string bytes(kMaxTaskBytes + 1, '\0');
  in.read(&bytes[0], static_cast<std::streamsize>(bytes.size()));
  if (in.bad()) return *error = path + ": error: cannot read the task file", false;
  bytes.resize(static_cast<size_t>(in.gcount()));
  if (bytes.size() > kMaxTaskBytes)
    return *error = path + ": error: is larger than " + std::to_string(kMaxTaskBytes >> 20) +
                    " MiB, the limit for a task file; a task is a short text",
           false;
  *text = std::move(bytes);
  return true;
}

/// A task file's root, the one reading every kind of task shares (ReadTaskText, then YAML):
/// false and *error when the file cannot be read, is not YAML (FILE:LINE:COLUMN) or is not a
/// mapping (`expected`: its keys).
inline bool LoadTaskRoot(const std::string& path, const std::string& expected, YAML::Node* root, std::string* error) {
  std::string text;
  if (!ReadTaskText(path, &text, error)) return false;
  try {
    *root = mechgen::io::LoadStrict(text);  // one document, no key twice in a mapping
  } catch (const YAML::Exception& e) {
    return *error = Where(path, e.mark) + "not valid YAML: " + e.msg, false;
  }
  if (!root->IsMap()) return *error = path + ":1:1: error: expected a mapping with " + expected, false;
  return true;
}

/// A task's `constraints:` (path and function tasks; docs/synthesis.md) into *c. `has_crank`:
/// the task names its input link; `free_timing`: `order` is allowed (path tasks, free timing).
inline void ReadConstraints(const std::string& path, const YAML::Node& cons, bool has_crank, bool free_timing,
                            Constraints* c) {
  if (!cons.IsMap()) throw Error{Where(path, cons.Mark()) + "constraints: expected a mapping"};
  Known(path, cons,
        {"grashof", "crank_rotates", "crank_shortest", "order", "transmission_angle", "link_lengths", "link_ratio",
         "ground_region"},
        "constraints");
  if (cons["grashof"]) c->grashof = Bool(path, cons["grashof"], "grashof");
  if (cons["crank_rotates"]) c->crank_rotates = Bool(path, cons["crank_rotates"], "crank_rotates");
  if (cons["crank_shortest"]) c->crank_shortest = Bool(path, cons["crank_shortest"], "crank_shortest");
  if (cons["order"]) c->order = Bool(path, cons["order"], "order");
  if (const YAML::Node mu = cons["transmission_angle"]) {
    c->has_mu = true;
    Pair(path, mu, "transmission_angle", true, &c->mu_lo, &c->mu_hi);
  }
  if (const YAML::Node len = cons["link_lengths"]) {
    c->has_lengths = true;
    Pair(path, len, "link_lengths", false, &c->length_lo, &c->length_hi);
  }
  if (const YAML::Node ratio = cons["link_ratio"]) {
    c->has_ratio = true;
    c->ratio_max = Number(path, ratio, "link_ratio (the longest link over the shortest, at most)");
    if (!(c->ratio_max >= 1)) throw Error{Where(path, ratio.Mark()) + "link_ratio: expected a number >= 1"};
  }
  if (const YAML::Node g = cons["ground_region"]) {
    // {pivots: [ground.A, ground.D], rectangle: [[xmin, ymin], [xmax, ymax]]} or
    // {pivots: [...], circle: {centre: [x, y], radius: r}}: each named point of the model's
    // ground link (its scene points; without pivots: every point of the ground link) inside.
    if (!g.IsMap()) throw Error{Where(path, g.Mark()) + "ground_region: expected {pivots: [ground.A, ...], rectangle: [[xmin, ymin], [xmax, ymax]]} or {circle: {centre: [x, y], radius: r}}"};
    Known(path, g, {"pivots", "rectangle", "circle"}, "ground_region");
    c->has_region = true;
    c->region_line = g.Mark().line + 1;
    c->region_column = g.Mark().column + 1;
    if (const YAML::Node pv = g["pivots"]) {
      if (!pv.IsSequence() || pv.size() == 0)
        throw Error{Where(path, pv.Mark()) + "ground_region.pivots: expected the ground's points, e.g. [ground.A, ground.D]"};
      for (const YAML::Node& one : pv) {
        if (!one.IsScalar()) throw Error{Where(path, one.Mark()) + "a pivot: expected a point of the ground link, e.g. ground.A"};
        c->region_pivots.push_back(one.Scalar());
      }
    }
    const YAML::Node rect = g["rectangle"], circle = g["circle"];
    if (static_cast<bool>(rect) == static_cast<bool>(circle))
      throw Error{Where(path, g.Mark()) + "ground_region: give either rectangle: [[xmin, ymin], [xmax, ymax]] or circle: {centre: [x, y], radius: r}"};
    if (rect) {
      if (!rect.IsSequence() || rect.size() != 2 || !rect[0].IsSequence() || rect[0].size() != 2 || !rect[1].IsSequence() ||
          rect[1].size() != 2)
        throw Error{Where(path, rect.Mark()) + "ground_region.rectangle: expected [[xmin, ymin], [xmax, ymax]]"};
      c->region_rectangle = true;
      c->region_lo[0] = Number(path, rect[0][0], "xmin");
      c->region_lo[1] = Number(path, rect[0][1], "ymin");
      c->region_hi[0] = Number(path, rect[1][0], "xmax");
      c->region_hi[1] = Number(path, rect[1][1], "ymax");
      if (!(c->region_lo[0] < c->region_hi[0] && c->region_lo[1] < c->region_hi[1]))
        throw Error{Where(path, rect.Mark()) + "ground_region.rectangle: min must be below max in x and in y"};
    } else {
      if (!circle.IsMap()) throw Error{Where(path, circle.Mark()) + "ground_region.circle: expected {centre: [x, y], radius: r}"};
      Known(path, circle, {"centre", "radius"}, "ground_region.circle");
      const YAML::Node centre = Required(path, circle, "centre", "the circle's centre [x, y]");
      if (!centre.IsSequence() || centre.size() != 2)
        throw Error{Where(path, centre.Mark()) + "ground_region.circle.centre: expected [x, y]"};
      c->region_lo[0] = Number(path, centre[0], "centre x");
      c->region_lo[1] = Number(path, centre[1], "centre y");
      c->region_radius = Number(path, Required(path, circle, "radius", "the circle's radius"), "radius");
      if (!(c->region_radius > 0)) throw Error{Where(path, circle["radius"].Mark()) + "ground_region.circle.radius: expected a number > 0"};
    }
  }
  if ((c->crank_rotates || c->crank_shortest) && !has_crank)
    throw Error{Where(path, cons.Mark()) + "crank_rotates/crank_shortest need `crank: <input link>` in the task"};
  if (c->order && !free_timing)
    throw Error{Where(path, cons["order"].Mark()) +
                "order: only for path tasks with free timing (prescribed angles fix the order)"};
}

/// A task's `search:` into *s. Function tasks take the same keys.
inline void ReadSearch(const std::string& path, const YAML::Node& s, bool function_task, Search* search) {
  if (!s.IsMap()) throw Error{Where(path, s.Mark()) + "search: expected a mapping"};
  if (function_task) {
    Known(path, s, {"evaluations", "restarts", "population", "curve_samples", "local_starts", "local_share"},
          "search (function task)");
  } else {
    Known(path, s, {"evaluations", "restarts", "population", "curve_samples", "local_starts", "local_share", "projection"},
          "search");
  }
  if (s["projection"]) {
    search->projection = Bool(path, s["projection"], "projection");
    search->projection_line = s["projection"].Mark().line + 1;
    search->projection_column = s["projection"].Mark().column + 1;
  }
  if (s["local_starts"]) search->local_starts = static_cast<int>(Count(path, s["local_starts"], "local_starts", 1, 1000));
  if (s["local_share"]) {
    search->local_share = Number(path, s["local_share"], "local_share");
    if (!(search->local_share >= 0 && search->local_share <= 0.9))
      throw Error{Where(path, s["local_share"].Mark()) + "local_share: expected a number in [0, 0.9]"};
  }
  if (s["evaluations"]) search->evaluations = Count(path, s["evaluations"], "evaluations", 100, 1000000000LL);
  // A function task may have no global stage (restarts: 0: its exact and model starts only).
  if (s["restarts"]) search->restarts = static_cast<int>(Count(path, s["restarts"], "restarts", function_task ? 0 : 1, 10000));
  if (s["population"]) search->population = static_cast<int>(Count(path, s["population"], "population", 0, 100000));
  if (s["curve_samples"])
    search->curve_samples = static_cast<int>(Count(path, s["curve_samples"], "curve_samples", 8, 100000));
}

}  // namespace task_internal

/// Reads the task file; false and *error (one message: FILE:LINE:COLUMN: what to change) on
/// the first problem. Nothing else is done with a task that fails here.
inline bool ParseTask(const std::string& path, PathTask* task, std::string* error) {
  using namespace task_internal;
  *task = PathTask();
  task->file = path;
  YAML::Node root;
  if (!LoadTaskRoot(path, "`synthesis: path`, `point`, `targets`, `variables`", &root, error)) return false;
  try {
    // `kind: exact` (synthesis/exact.h, ParseExactTask) is a task of its own keys; the search
    // is the default kind.
    if (const YAML::Node k = root["kind"]) {
      if (!k.IsScalar() || k.Scalar() != "search")
        throw Error{Where(path, k.Mark()) + "kind: '" + (k.IsScalar() ? k.Scalar() : std::string("?")) +
                    "' is not a kind of path task; expected search (the default: differential evolution and "
                    "Levenberg-Marquardt) or exact (five points with both pivots given: every solution by homotopy "
                    "continuation, docs/synthesis.md)"};
    }
    Known(path, root, {"synthesis", "kind", "model", "point", "crank", "targets", "timing", "variables", "constraints",
               "search", "placement"},
          "the task");
    const YAML::Node kind = Required(path, root, "synthesis", "the kind of task (path; function and motion are planned)");
    if (!kind.IsScalar() || kind.Scalar() != "path")
      throw Error{Where(path, kind.Mark()) + "synthesis: '" + (kind.IsScalar() ? kind.Scalar() : std::string("?")) +
                  "' is not supported; this version does `path` (function and motion generation are planned)"};
    if (const YAML::Node m = root["model"]) {
      if (!m.IsScalar()) throw Error{Where(path, m.Mark()) + "model: expected a file name"};
      task->model = m.Scalar();
    }
    const YAML::Node point = Required(path, root, "point", "the model's output point that traces the path, e.g. coupler.P");
    if (!point.IsScalar()) throw Error{Where(path, point.Mark()) + "point: expected a point name such as coupler.P"};
    task->point = point.Scalar();
    task->point_line = point.Mark().line + 1;
    task->point_column = point.Mark().column + 1;
    if (const YAML::Node c = root["crank"]) {
      if (!c.IsScalar()) throw Error{Where(path, c.Mark()) + "crank: expected the input link's name"};
      task->crank_link = c.Scalar();
      task->crank_line = c.Mark().line + 1;
      task->crank_column = c.Mark().column + 1;
    }
    const YAML::Node targets = Required(path, root, "targets", "the precision points, [[x, y], ...]");
    if (!targets.IsSequence() || targets.size() < 2)
      throw Error{Where(path, targets.Mark()) + "targets: expected at least two points [[x, y], ...]"};
    for (const YAML::Node& t : targets) {
      if (!t.IsSequence() || t.size() != 2) throw Error{Where(path, t.Mark()) + "a target: expected [x, y]"};
      task->tx.push_back(Number(path, t[0], "target x"));
      task->ty.push_back(Number(path, t[1], "target y"));
    }
    const int n = static_cast<int>(task->tx.size());
    if (const YAML::Node timing = root["timing"]) {
      task->timing.line = timing.Mark().line + 1;
      task->timing.column = timing.Mark().column + 1;
      if (timing.IsScalar() && timing.Scalar() == "free") {
        task->timing.free = true;
      } else if (timing.IsMap()) {
        Known(path, timing, {"angles", "offset", "relative_to"}, "timing");
        task->timing.free = false;
        const YAML::Node angles = Required(path, timing, "angles", "the input angle at each target, e.g. [30deg, 45deg]");
        if (!angles.IsSequence() || static_cast<int>(angles.size()) != n)
          throw Error{Where(path, angles.Mark()) + "timing.angles: expected " + std::to_string(n) +
                      " angles (one per target)"};
        for (const YAML::Node& a : angles) task->timing.angles.push_back(Number(path, a, "timing angle", true));
        if (const YAML::Node off = timing["offset"]) {
          if (off.IsScalar() && off.Scalar() == "free") {
            task->timing.offset_free = true;
          } else {
            task->timing.offset = Number(path, off, "timing.offset (a number or free)", true);
          }
        }
        if (const YAML::Node rel = timing["relative_to"]) {
          if (!rel.IsScalar()) throw Error{Where(path, rel.Mark()) + "timing.relative_to: expected a parameter name"};
          task->timing.relative_to = rel.Scalar();
        }
      } else {
        throw Error{Where(path, timing.Mark()) + "timing: expected `free` or {angles: [...], offset: 0|free}"};
      }
    }
    ReadVariables(path, root, "{a: [0, 60], ...}", &task->variables);
    if (const YAML::Node cons = root["constraints"]) {
      ReadConstraints(path, cons, !task->crank_link.empty(), task->timing.free, &task->constraints);
    }
    if (const YAML::Node s = root["search"]) ReadSearch(path, s, /*function_task=*/false, &task->search);
    if (const YAML::Node pl = root["placement"]) {
      if (!pl.IsMap()) throw Error{Where(path, pl.Mark()) + "placement: expected {x: x0, y: y0, angle: theta0}"};
      Known(path, pl, {"x", "y", "angle"}, "placement");
      Placement& p = task->placement;
      p.line = pl.Mark().line + 1;
      p.column = pl.Mark().column + 1;
      for (const char* key : {"x", "y", "angle"}) {
        const YAML::Node v = Required(path, pl, key, "the variable that places the frame");
        if (!v.IsScalar()) throw Error{Where(path, v.Mark()) + "placement." + key + ": expected a variable's name"};
        bool found = false;
        for (const Variable& var : task->variables) found = found || var.name == v.Scalar();
        if (!found)
          throw Error{Where(path, v.Mark()) + "placement." + key + ": '" + v.Scalar() + "' is not one of the task's variables"};
        (key[0] == 'x' ? p.x : key[0] == 'y' ? p.y : p.angle) = v.Scalar();
      }
      if (task->timing.free || task->timing.relative_to != p.angle)
        throw Error{Where(path, pl.Mark()) + "placement: needs prescribed timing measured from its angle (timing: {angles: "
                    "[...], relative_to: " + p.angle + "})"};
    }
  } catch (const Error& e) {
    *error = e.message;
    return false;
  } catch (const YAML::Exception& e) {
    *error = Where(path, e.mark) + e.msg;
    return false;
  }
  return true;
}

}  // namespace mechgen::synthesis
