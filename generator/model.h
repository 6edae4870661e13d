// The mechanism model as the generator sees it: parameters, links with named points,
// joints, inputs, requested outputs and the assembly guess, read from a model file
// (models/README.md documents the format) and validated. Geometry is kept as GiNaC
// expressions in the parameter symbols, so that the derivation stays symbolic in the
// parameters and the generated Params struct can change them at run time.
//
// Every error is a ModelError carrying the file, line and column of the offending YAML
// node; mechgen prints it as `file:line:column: message` and writes nothing.
#pragma once

#include <ginac/ginac.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace mechgen {

/// A position in the model file, 1-based; line 0 means "the whole file".
struct SourceMark {
  int line = 0;
  int column = 0;
};

/// A bad model: what is wrong, where, and what to change.
class ModelError : public std::runtime_error {
 public:
  ModelError(const std::string& file, SourceMark mark, const std::string& message);
  const std::string& file() const { return file_; }
  SourceMark mark() const { return mark_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  SourceMark mark_;
  std::string message_;
};

struct Parameter {
  std::string name;
  double value = 0;
  std::string doc;
  GiNaC::symbol symbol;
  SourceMark mark;
};

/// A point fixed on a link, in the link's local frame (x along the link's axis).
struct LinkPoint {
  std::string name;
  GiNaC::ex x, y;
  SourceMark mark;
};

struct Link {
  std::string name;
  bool ground = false;
  std::vector<LinkPoint> points;
  SourceMark mark;
  int FindPoint(const std::string& point) const;
};

/// A point of a link: the link index and the point index within it.
struct PointRef {
  int link = -1;
  int point = -1;
  bool operator==(const PointRef& o) const { return link == o.link && point == o.point; }
};

/// Joint kinds. Lower pairs now; gears, rolling contact and cams add kinds (and their
/// auxiliary equations) in topology.cc and loop_equations.cc.
enum class JointType {
  kRevolute,   ///< pin: point `a` of one link coincides with point `b` of the other.
  kPrismatic,  ///< slider: point `b` moves along the line through guide point `a` at
               ///< `angle` (in the guide link's frame); the slider link keeps the angle
               ///< theta_guide + relative_angle. Displacement s: b = a + s (cos, sin).
};

struct Joint {
  std::string name;
  JointType type = JointType::kRevolute;
  PointRef a;  ///< revolute: first point; prismatic: the guide point (line origin).
  PointRef b;  ///< revolute: second point; prismatic: the slider point.
  GiNaC::ex angle = 0;           ///< prismatic: line direction in the guide link's frame.
  GiNaC::ex relative_angle = 0;  ///< prismatic: slider link angle minus guide link angle.
  SourceMark mark;
};

/// A driven joint: its variable is one of the generalized coordinates q.
struct Input {
  int joint = -1;
  double min = 0, max = 0;  ///< default sweep range
  SourceMark mark;
};

struct Outputs {
  int order = 2;                 ///< 0: positions, 1: + K, 2: + L
  std::vector<PointRef> points;  ///< points of interest
  bool scene = true;             ///< emit EvalScene (every link point, for drawing)
  SourceMark mark;
};

/// A value of the assembly guess: a coordinate name and its value.
struct GuessValue {
  std::string coordinate;
  double value = 0;
  SourceMark mark;
};

struct Model {
  std::string file;  ///< the path it was read from (errors name it)
  std::string name;  ///< C++ identifier, namespace mech::<name>
  std::string title;
  std::string description;
  std::vector<Parameter> params;
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<Input> inputs;
  SourceMark inputs_mark;
  Outputs outputs;
  std::vector<GuessValue> guess;
  int ground = -1;

  std::string PointName(PointRef r) const;  ///< "link.point"
  [[noreturn]] void Fail(SourceMark mark, const std::string& message) const;
};

/// Reads and validates a model file (syntax, names, references). Topological checks
/// (connectivity, mobility against inputs) are made by BuildTopology().
/// \param name_override if not empty, replaces the model's `name`.
Model LoadModel(const std::string& path, const std::string& name_override = "");

/// The same from the text of a model; `path` only names it in error messages.
Model LoadModelFromString(const std::string& text, const std::string& path,
                          const std::string& name_override = "");

}  // namespace mechgen
