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

#include <array>
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

/// A point of a link: the link index and the point index within it. A rolling joint's
/// contact point (`<joint>.contact`, on no link) has contact_joint set; `link` is then the
/// rolling link and `point` -1.
struct PointRef {
  int link = -1;
  int point = -1;
  int contact_joint = -1;
  bool operator==(const PointRef& o) const {
    return link == o.link && point == o.point && contact_joint == o.contact_joint;
  }
};

/// Joint kinds. Lower pairs (revolute, prismatic, roll) may place a link in the spanning
/// tree; higher pairs (gear, rack, cam) never do: each closes a loop with one equation
/// (joints.cc has every kind's equations).
enum class JointType {
  kRevolute,   ///< pin: point `a` of one link coincides with point `b` of the other.
  kPrismatic,  ///< slider: point `b` moves along the line through guide point `a` at
               ///< `angle` (in the guide link's frame); the slider link keeps the angle
               ///< theta_guide + relative_angle. Displacement s: b = a + s (cos, sin).
  kRoll,       ///< rolling without slip: a circle of `radius` centred at point `b` (the
               ///< wheel) rolls on the line through `a` at `angle` (on_line) or on the
               ///< circle of `radius2` centred at `a` (outside, or inside if `internal`).
               ///< Contact variable: s (line) or psi (circle); equations: contact (2 when
               ///< a cut) + no slip (1).
  kGear,       ///< gear pair: links a.link, b.link with pitch radii `radius`, `radius2`,
               ///< axes on `carrier`: r1 (th1 - thc) +- r2 (th2 - thc) = phase (+ external,
               ///< - internal: b is the ring).
  kRack,       ///< rack and pinion: pinion a.link (pitch radius `radius`), the rack is the
               ///< slider of prismatic joint `other_joint`: s + r (th_pinion - th_guide) = phase.
  kCam,        ///< disk cam a.link and follower b.link given by the follower's law:
               ///< y_follower = start + law(th_cam - th_carrier - phase) (cam.h), or by
               ///< the cam's contour (Joint::contour; contact parameter u_<joint>, two
               ///< equations: the roller's centre on the contour's offset, or the face
               ///< tangent to the contour).
};

/// One segment of a cam's follower law (dwell, rise, return) over `duration` of cam angle.
struct CamSegment {
  enum class Kind { kDwell, kRise, kReturn };
  enum class Motion { kNone, kCycloidal, kHarmonic, kPoly345 };
  Kind kind = Kind::kDwell;
  Motion motion = Motion::kNone;
  GiNaC::ex duration = 0;  ///< cam angle of the segment (radians)
  GiNaC::ex lift = 0;      ///< rise or return height (displacement, or angle if oscillating)
  SourceMark mark;
};

struct Joint {
  std::string name;
  JointType type = JointType::kRevolute;
  PointRef a;  ///< revolute: first point; prismatic: the guide point (line origin);
               ///< roll: the line's point or the circle's centre (the base link);
               ///< gear, rack, cam: a.link is the first gear, the pinion, the cam.
  PointRef b;  ///< revolute: second point; prismatic: the slider point; roll: the
               ///< wheel's centre; gear: b.link the second gear; rack: the rack link;
               ///< cam: the follower link.
  GiNaC::ex angle = 0;           ///< prismatic: line direction in the guide link's frame; roll: the line's.
  GiNaC::ex relative_angle = 0;  ///< prismatic: slider link angle minus guide link angle.
  // Higher pairs and rolling.
  GiNaC::ex radius = 0;   ///< roll: wheel radius; gear: r1; rack: pinion radius
  GiNaC::ex radius2 = 0;  ///< roll on a circle: its radius; gear: r2
  bool on_line = false;   ///< roll: on a line (else on a circle)
  bool internal = false;  ///< roll: inside the circle; gear: b is an internal (ring) gear
  GiNaC::ex phase = 0;    ///< roll, gear, rack: the constant of the no-slip relation; cam: law start angle
  int carrier = -1;       ///< gear, cam: the link holding both axes (default: ground)
  int other_joint = -1;   ///< rack: the rack's prismatic joint; cam: the follower's joint
  // Cams.
  int cam_index = -1;            ///< cam: index among the model's cams
  PointRef follower_point;       ///< cam: roller centre, knife-edge tip, or a point of the face
  bool flat_face = false;        ///< cam: flat-faced follower (else roller / knife-edge)
  GiNaC::ex face_angle = 0;      ///< cam: face direction in the follower's frame
  GiNaC::ex roller = 0;          ///< cam: roller radius (0: knife-edge)
  GiNaC::ex start = 0;           ///< cam: follower coordinate at zero lift
  std::vector<CamSegment> law;   ///< cam: the follower law, segments in order from `phase`
  // Contour cams (a profile instead of a law; contact parameter u_<joint> is a coordinate).
  enum class Contour { kNone, kExpressions, kSpline };
  Contour contour = Contour::kNone;  ///< cam: the profile is a contour in the cam's frame
  GiNaC::ex contour_x, contour_y;    ///< kExpressions: x(u), y(u) in the cam's frame
  GiNaC::symbol contour_u{"u"};      ///< kExpressions: the contour's parameter in them
  GiNaC::ex contour_period = 0;      ///< kExpressions: u runs over [0, period) (default 2 pi)
  std::vector<std::array<double, 2>> contour_points;  ///< kSpline: the points, counter-clockwise
  std::vector<SourceMark> contour_point_marks;
  std::string contour_text;          ///< kExpressions: "x(u) = ..., y(u) = ..." as written
  SourceMark contour_mark;
  SourceMark law_mark, roller_mark;
  SourceMark mark;
  /// Lower pairs can place a link in the spanning tree.
  bool IsLowerPair() const {
    return type == JointType::kRevolute || type == JointType::kPrismatic || type == JointType::kRoll;
  }
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
