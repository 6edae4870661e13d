// The mechanism model as the generator sees it: parameters, links with named points,
// joints, inputs, requested outputs and the assembly guess, read from a model file
// (models/README.md documents the format; generator/model/ reads it section by section).
// Geometry is kept as GiNaC
// expressions in the parameter symbols, so that the derivation stays symbolic in the
// parameters and the generated Params struct can change them at run time.
//
// Every error is a ModelError carrying the file, line and column of the offending YAML
// node; mechgen prints it as `file:line:column: message` and writes nothing.
#pragma once

#include <ginac/ginac.h>

#include <array>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <variant>
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

/// A derived parameter (`name: {derived: <expression>}` in `parameters`): an expression of
/// the parameters above it, free or derived. It is no member of Params: every expression
/// that names it reads its expression instead (in the free parameters' symbols), so it
/// follows the free parameters when they change at run time.
struct DerivedParameter {
  std::string name;
  GiNaC::ex value;  ///< in the free parameters' symbols only
  std::string doc;
  SourceMark mark;
};

/// A point fixed on a link, in the link's local frame (x along the link's axis).
struct LinkPoint {
  std::string name;
  GiNaC::ex x, y;
  SourceMark mark;
};

/// A link's mass properties (statics: its weight; dynamics: its inertia). Massless if
/// `mass` is not given and it carries no point masses.
struct MassProperties {
  bool given = false;
  GiNaC::ex mass = 0;                ///< kg (or the model's mass unit)
  GiNaC::ex center_x = 0, center_y = 0;  ///< centre of mass in the link's frame
  GiNaC::ex inertia = 0;             ///< moment of inertia about the centre of mass
  SourceMark mark;
};

/// A point mass on a link (`point_masses:`): a lamp head, a payload, a counterweight, the pin
/// of a slider; a particle of `mass` at (x, y) in the link's frame with its own moment of
/// inertia `inertia` about itself (0 if not given).
struct PointMass {
  std::string name;
  std::string at;   ///< the link's point it sits at, as written ("" if given as [x, y])
  GiNaC::ex x = 0, y = 0;
  GiNaC::ex mass = 0;
  GiNaC::ex inertia = 0;
  SourceMark mark;
};

struct Link {
  std::string name;
  bool ground = false;
  std::vector<LinkPoint> points;
  /// The link's rigid body as every analysis reads it: its own `mass`, `center`, `inertia`
  /// combined with its point masses (total mass, common centre, moment of inertia about it by
  /// the parallel-axis theorem; links.cc). Without point masses, the link's own keys as written.
  MassProperties mass;
  std::vector<PointMass> point_masses;  ///< as written (already combined into `mass`)
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

/// Joint kinds, in the order of JointData's alternatives. Lower pairs (revolute,
/// prismatic, roll) may place a link in the spanning tree; higher pairs (gear, rack, cam)
/// never do: each closes a loop. Each kind's keys, coordinate, placement, equations and
/// description live in its own file, generator/joints/<kind>.cc (joints/joint_kind.h).
enum class JointType { kRevolute, kPrismatic, kRoll, kGear, kRack, kCam, kSlot };

/// Pin: point `a` (on Joint::link_a) coincides with point `b` (on link_b). A pin over
/// several links (`J: {revolute: [a.P, b.Q, c.R]}`) is read as one joint per link after the
/// first, each pinning that link's point to the first one: `J` (a.P = b.Q), `J_c` (a.P = c.R).
struct RevoluteData {
  PointRef a, b;
  std::string pin;  ///< over several links: the pin's name as written (`J`), else ""
  std::string pin_links;  ///< over several links: "a, b, c"
};

/// Slider: point `slider` (on link_b) moves along the line through `guide` (on link_a) at
/// `angle` in the guide link's frame; the slider link keeps the angle
/// theta_guide + relative_angle. Displacement s: slider = guide + s (cos, sin).
struct PrismaticData {
  PointRef guide, slider;
  GiNaC::ex angle = 0;
  GiNaC::ex relative_angle = 0;
};

/// Rolling without slip: a circle of `radius` centred at `wheel` (on link_b) rolls on the
/// line through `on` (on link_a, the base) at `line_angle`, or on the circle of
/// `on_radius` centred at `on` (outside, or inside if `inside`).
struct RollData {
  PointRef on, wheel;
  GiNaC::ex radius = 0;
  GiNaC::ex line_angle = 0;
  GiNaC::ex on_radius = 0;
  bool on_line = true;
  bool inside = false;
  GiNaC::ex phase = 0;  ///< the constant of the no-slip relation
  SourceMark radius_mark, on_radius_mark;
};

/// Gear pair: gears link_a, link_b with pitch radii radius[0], radius[1], both axes on
/// `carrier`; internal: link_b is the ring.
struct GearData {
  GiNaC::ex radius[2] = {0, 0};
  int carrier = -1;  ///< the link holding both axes (default: ground)
  bool internal = false;
  GiNaC::ex phase = 0;
  GiNaC::ex pressure_angle = 20 * GiNaC::Pi / 180;  ///< of the teeth (the contact force's direction; statics)
  SourceMark radius_mark[2];
  SourceMark pressure_mark;
};

/// Rack and pinion: pinion link_a (pitch radius `radius`); the rack (link_b) is the slider
/// of prismatic joint `slide`, whose guide is `carrier`.
struct RackData {
  GiNaC::ex radius = 0;
  int slide = -1;
  int carrier = -1;
  GiNaC::ex phase = 0;
  GiNaC::ex pressure_angle = 20 * GiNaC::Pi / 180;  ///< of the teeth (the contact force's direction; statics)
  SourceMark pressure_mark;
  std::string slide_name;  ///< as written (resolved once every joint is read)
  SourceMark slide_mark;
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
  SourceMark duration_mark;
};

/// Disk cam link_a and follower link_b given by the follower's law:
/// y_follower = start + law(th_cam - th_carrier - phase) (joints/cam_profile.h), or by the cam's contour
/// (contact parameter u_<joint>, two equations: the roller's centre on the contour's
/// offset, or the face tangent to the contour).
struct CamData {
  int index = -1;          ///< index among the model's cams (camlaw(index, ...))
  int follower_joint = -1; ///< the follower's prismatic or revolute joint to the carrier
  int carrier = -1;        ///< the link holding the cam's pivot and the follower's joint
  int pivot = -1;          ///< the cam's revolute joint to the carrier
  PointRef point;          ///< roller centre, knife-edge tip, or a point of the face
  bool flat_face = false;  ///< flat-faced follower (else roller / knife-edge)
  GiNaC::ex face_angle = 0;  ///< face direction in the follower's frame
  GiNaC::ex roller = 0;      ///< roller radius (0: knife-edge)
  GiNaC::ex start = 0;       ///< follower coordinate at zero lift
  GiNaC::ex phase = 0;       ///< law start angle
  std::vector<CamSegment> law;  ///< the follower law, segments in order from `phase`
  // Contour cams (a profile instead of a law; contact parameter u_<joint> is a coordinate).
  enum class Contour { kNone, kExpressions, kSpline };
  Contour contour = Contour::kNone;
  GiNaC::ex contour_x, contour_y;    ///< kExpressions: x(u), y(u) in the cam's frame
  GiNaC::symbol contour_u{"u"};      ///< kExpressions: the contour's parameter in them
  GiNaC::ex contour_period = 0;      ///< kExpressions: u runs over [0, period) (default 2 pi)
  std::vector<std::array<double, 2>> contour_points;  ///< kSpline: the points, counter-clockwise
  std::vector<SourceMark> contour_point_marks;
  std::string contour_text;          ///< kExpressions: "x(u) = ..., y(u) = ..." as written
  std::string follower_name;         ///< as written (resolved once every joint is read)
  SourceMark contour_mark, period_mark, law_mark, roller_mark, follower_mark;
};

/// Pin in a slot: point `pin` (on link_b) slides along the line through `slot` (on link_a)
/// at `angle` in link_a's frame, or through `slot` and `through` (a second point of link_a);
/// both links keep their own angles. Slide s: pin = slot + s u.
struct SlotData {
  PointRef slot, pin;
  PointRef through;  ///< link -1: the line is given by `angle`
  GiNaC::ex angle = 0;
  SourceMark through_mark;
};

/// A joint's kind-specific data; the alternatives follow JointType's order.
using JointData = std::variant<RevoluteData, PrismaticData, RollData, GearData, RackData, CamData, SlotData>;

/// A joint: the header every kind shares (name, the two links it joins, where it is in
/// the file) and its kind's data.
struct Joint {
  std::string name;
  int link_a = -1;  ///< revolute: a's link; prismatic: the guide; roll: the base;
                    ///< gear: the first gear; rack: the pinion; cam: the cam
  int link_b = -1;  ///< revolute: b's link; prismatic: the slider; roll: the wheel;
                    ///< gear: the second gear; rack: the rack; cam: the follower
  JointData data;
  SourceMark mark;

  JointType type() const { return static_cast<JointType>(data.index()); }
  template <class T>
  const T& Data() const { return std::get<T>(data); }
  template <class T>
  T& Data() { return std::get<T>(data); }
  /// Lower pairs can place a link in the spanning tree (a slot too: it has its slide, though
  /// Grübler counts it as a half joint).
  bool IsLowerPair() const {
    return type() == JointType::kRevolute || type() == JointType::kPrismatic || type() == JointType::kRoll ||
           type() == JointType::kSlot;
  }
  bool Joins(int link) const { return link_a == link || link_b == link; }
  int OtherLink(int link) const { return link_a == link ? link_b : link_a; }
  /// A lower pair's point on `link` (one of its two links): revolute a or b, prismatic
  /// guide or slider, roll on or wheel, slot slot or pin.
  PointRef End(int link) const;
};

/// An input: one of the generalized coordinates q (Paul: any independent set of coordinates
/// can be generalized). A driven joint's own variable (a ground pivot's or a rolling link's
/// absolute angle, a slide, a pin's slide in its slot), a link's absolute angle (`angle:`),
/// or a point's x or y in the fixed frame (`point:`, `coordinate:`): the latter is no
/// coordinate of the linkage, so it adds the driving constraint x_P(phi) - q = 0 to Phi
/// (kinematics.cc) and every joint's variable becomes a dependent coordinate.
struct Input {
  enum class Kind { kJoint, kAngle, kPointX, kPointY };
  Kind kind = Kind::kJoint;
  int joint = -1;   ///< kJoint: the driven joint (-1 otherwise)
  int link = -1;    ///< kAngle: the link whose absolute angle is q
  PointRef point;   ///< kPointX, kPointY: the driven point
  bool IsPoint() const { return kind == Kind::kPointX || kind == Kind::kPointY; }
  double min = 0, max = 0;  ///< default sweep range
  SourceMark mark;
  SourceMark range_mark;  ///< its range: [min, max] (line 0 when the range is the default)
};

/// A quantity the generated code can compute, beyond the positions (always computed).
enum class Quantity {
  kK,      ///< velocity coefficients K = dphi/dq (and the points' K_P)
  kL,      ///< centripetal coefficients L (and the points' L_P); needs K
  kScene,  ///< EvalScene: every link point, for drawing
  kForces,     ///< statics: the generalized forces Q of the loads and the driving forces (needs K)
  kPotential,  ///< statics: the potential energy V of springs and gravity and its derivatives
  kDynamics,   ///< dynamics (Paul ch. 6): EvalDynamics, EvalKinetostatics, EvalExcess; implies K and L
  kShaking,    ///< shaking force and moment on the frame (Paul ch. 7): EvalShaking; implies dynamics
};

/// The quantity's name in the model file (`quantities: [...]`): K, L, scene, forces, ...
const char* QuantityName(Quantity q);
/// The names of `quantities` in the order of Quantity, separated by blanks: what
/// `mechgen generate --print-quantities` prints and the build's manifest records.
std::string QuantityList(const std::set<Quantity>& quantities);

/// What the generated code computes: the requested quantities and the points of interest.
/// `order: 0|1|2` in the model file is shorthand for {}, {K}, {K, L}.
struct Outputs {
  std::set<Quantity> quantities{Quantity::kK, Quantity::kL, Quantity::kScene};
  std::vector<PointRef> points;  ///< points of interest (positions, K_P, L_P as requested)
  std::vector<int> reactions;    ///< joints whose reactions are emitted (statics; needs kForces)
  SourceMark mark, reactions_mark;
  /// Derived from `quantities` (filled by the reader) for the emitters that branch on the
  /// order: 0 positions, 1 + K, 2 + L.
  int order = 2;
  bool scene = true;  ///< derived: quantities holds kScene
  bool Has(Quantity q) const { return quantities.count(q) > 0; }
  /// The order that `quantities` amounts to (K and L only come in this nesting).
  int Order() const { return Has(Quantity::kL) ? 2 : Has(Quantity::kK) ? 1 : 0; }
};

/// The design parameters (`design:`, issue 27): the free parameters the generated code
/// differentiates its outputs with respect to (EvalDesignDerivatives), in the order given.
struct Design {
  std::vector<int> params;  ///< indices into Model::params
  SourceMark mark;
  /// Which derivatives are emitted (`quantities:`; default every one the outputs have): the
  /// positions' (EvalDesignDerivatives: dphi/dp, the points', and dK/dp, dL/dp as the outputs'
  /// order has K and L) always; the design checks (EvalDesignChecks), the statics'
  /// (EvalStaticsDesign) and the dynamics' (EvalDynamicsDesign, with the shaking's) as asked.
  bool checks = true, statics = true, dynamics = true;
  bool any() const { return !params.empty(); }
};

/// A value of the assembly guess: a coordinate name and its value.
struct GuessValue {
  std::string coordinate;
  double value = 0;
  SourceMark mark;
};

/// A named assembly mode (`assembly_modes: {open: {...}, crossed: {...}}`): coordinate values
/// near it, over the `assembly` guess (the values it does not give are the assembly's).
struct NamedMode {
  std::string name;
  std::vector<GuessValue> guess;
  SourceMark mark;
};

/// An applied load (statics, Paul ch. 5): a force at a link point, or a torque on a link.
/// Its values are expressions of the parameters and of the coordinates (read through
/// Model::coordinate_refs, resolved by the statics derivation).
struct Load {
  std::string name;
  enum class Kind { kForce, kTorque };
  Kind kind = Kind::kForce;
  PointRef at;              ///< force: its point of application
  bool link_frame = false;  ///< force: components in the link's frame (else the fixed frame)
  int link = -1;            ///< torque: the link it acts on (force: at.link)
  GiNaC::ex fx = 0, fy = 0;  ///< force components
  GiNaC::ex torque = 0;      ///< torque, counter-clockwise positive
  SourceMark mark;
};

/// A spring: linear between two link points (tension F0 + k (l - l0), V = F0 (l - l0) +
/// k (l - l0)^2 / 2) or torsional at a revolute joint (torque on link_b by link_a
/// -k (theta_b - theta_a - free angle), V = k (...)^2 / 2).
struct Spring {
  std::string name;
  bool torsional = false;
  PointRef a, b;  ///< linear: its two ends
  int joint = -1; ///< torsional: the revolute joint
  GiNaC::ex stiffness = 0, free_length = 0, preload = 0, free_angle = 0;
  SourceMark mark;
};

/// Coulomb friction at a revolute joint (friction circle: coefficient x pin radius) or a
/// prismatic joint (on the normal force); `viscous` is read for the dynamics.
struct Friction {
  int joint = -1;
  GiNaC::ex coefficient = 0, pin_radius = 0, viscous = 0;
  SourceMark mark;
};

/// A viscous damper (dynamics, Paul ch. 6): linear between two link points (force
/// coefficient * dl/dt along the line, resisting extension) or torsional at a revolute joint
/// (torque -coefficient (omega_b - omega_a) on the joint's second link, the opposite on its first).
struct Damper {
  std::string name;
  bool torsional = false;
  PointRef a, b;   ///< linear: its two ends
  int joint = -1;  ///< torsional: the revolute joint
  GiNaC::ex coefficient = 0;
  SourceMark mark;
};

/// A piecewise-linear function of one argument (`tables:`), usable in load expressions as
/// name(expr): x strictly increasing, at least 2 points, the end values held outside.
/// In expressions it is the GiNaC function mtable(index, d, x) (d = 0: value, 1: slope).
struct Table {
  std::string name;
  std::vector<double> x, y;
  std::string doc;
  SourceMark mark;
};

DECLARE_FUNCTION_3P(mtable)
/// The value (d = 0) or slope (d = 1) of table `t` at x, clamped outside [x0, xn].
double EvalTable(const Table& t, double x, int d);

struct Model {
  std::string file;  ///< the path it was read from (errors name it)
  std::string name;  ///< C++ identifier, namespace mech::<name>
  std::string title;
  std::string description;
  std::vector<Parameter> params;
  std::vector<DerivedParameter> derived;  ///< in file order; each uses only those above it
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<Input> inputs;
  SourceMark inputs_mark;
  Outputs outputs;
  Design design;
  std::vector<GuessValue> guess;
  std::vector<NamedMode> assembly_modes;  ///< named assembly modes, in file order
  // Statics (generator/model/statics.cc): gravity, loads, springs, friction.
  bool has_gravity = false;
  GiNaC::ex gravity_x = 0, gravity_y = 0;
  SourceMark gravity_mark;
  std::vector<Load> loads;
  std::vector<Spring> springs;
  std::vector<Friction> friction;
  // Dynamics (generator/model/dynamics.cc): dampers, tables, and the time and velocities the
  // loads may read (created when a load uses them; only with the `dynamics` quantity).
  std::vector<Damper> dampers;
  std::vector<Table> tables;
  std::map<std::string, GiNaC::symbol> velocity_refs;  ///< "t" and "<coordinate>_dot"
  SourceMark velocity_ref_mark;                        ///< the first use (an error without dynamics)
  std::string velocity_ref_name;                       ///< its name as written
  /// The first load that jumps where a velocity is 0 (step, sign or mod of an argument with
  /// a velocity): it has no value at rest, so no statics (an error with `forces`,
  /// CheckDynamicRefs). Its mark (the function's name), the load and the call as written.
  SourceMark at_rest_jump_mark;
  std::string at_rest_jump_load, at_rest_jump_call;
  /// The loads that read time or a velocity (continuously: the jumps are refused above), in
  /// model order: the load as the errors name it ("torque of load 'load'") and the names it
  /// reads ("theta_crank_dot, t"). The statics evaluates them at rest (velocities 0, t = 0): the
  /// generator says so (a note on stderr and in EvalStatics' documentation).
  std::vector<std::pair<std::string, std::string>> at_rest_loads;
  /// The coordinates' names a load may use (theta_<link>, s_<joint>, psi_<joint>,
  /// u_<joint>), as placeholder symbols the statics derivation replaces by the coordinates.
  std::map<std::string, GiNaC::symbol> coordinate_refs;
  int ground = -1;

  std::string PointName(PointRef r) const;  ///< "link.point"
  int FindJoint(const std::string& name) const;  ///< its index, or -1
  GiNaC::exmap Defaults() const;  ///< every parameter symbol -> its default value
  [[noreturn]] void Fail(SourceMark mark, const std::string& message) const;
};

/// Reads a model file (syntax, keys, names, references); the checks on numbers at the
/// parameters' defaults (mobility, ranges, cams, ...) are the validation stage's,
/// Validate() in analysis/validate.h.
/// \param name_override if not empty, replaces the model's `name`.
Model LoadModel(const std::string& path, const std::string& name_override = "");

/// The same from the text of a model; `path` only names it in error messages.
Model LoadModelFromString(const std::string& text, const std::string& path,
                          const std::string& name_override = "");

}  // namespace mechgen
