// Joint kinds behind one interface (Paul §1.1, §1.2). Each kind is one file in this folder
// (revolute.cc, prismatic.cc, roll.cc, gear.cc, rack.cc, cam.cc, slot.cc) that says which keys it
// reads and parses them into its data (model.h: RevoluteData, ...), which coordinate it adds
// (s, psi, u), how it places a child link when it is a tree joint, which rows it adds to
// Phi when it is a cut joint (and a rolling joint's no-slip row always), how the report
// describes it, which reaction components it transmits and their values in the force
// analysis' unknowns (statics, issue 14; symbolic/reactions.cc keeps only what is common),
// and the relative motion its Coulomb friction opposes.
//
// A new joint kind: add its data to JointData (model.h) and its JointType, write
// joints/<kind>.cc implementing JointKind, register it in JointKinds() (joint_kind.cc), and
// list its keys in models/README.md (model_keys_test checks that).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "model/model.h"
#include "model/reader.h"

namespace mechgen {

/// A link's pose in the fixed frame: origin (x, y) and absolute angle theta (CCW from +x).
struct Frame {
  GiNaC::ex x = 0, y = 0, theta = 0;
};

using Vec2 = std::array<GiNaC::ex, 2>;

/// Position in the fixed frame of point `ref` of a link whose frame is `f`.
Vec2 PointPosition(const Model& m, PointRef ref, const Frame& f);

/// (x, y) turned by theta.
Vec2 Rotate(const GiNaC::ex& theta, const GiNaC::ex& x, const GiNaC::ex& y);

/// The frame of a link at angle `child_theta` whose point `child_point` lies at `w` (the
/// last step of every lower pair's placement).
Frame FrameThrough(const Model& m, PointRef child_point, const Vec2& w, const GiNaC::ex& child_theta);

/// Which scalar of a joint's equations a Phi row is.
enum class RowComponent {
  kX,                 ///< x projection of a vector closure
  kY,                 ///< y projection of a vector closure
  kNoSlip,            ///< rolling: equal arcs on both contours
  kGearMesh,          ///< external gear pair
  kInternalGearMesh,  ///< internal gear pair
  kRackMesh,          ///< rack and pinion
  kCamLaw,            ///< cam given by its follower's law
  kContourX,          ///< contour cam, roller: the centre on the contour's offset, x
  kContourY,          ///< ... y
  kFaceContact,       ///< contour cam, flat face: the contact point on the face
  kFaceTangent,       ///< ... the face tangent to the contour
};

/// The text the generated headers and the report print for a component ("x", "no slip").
const char* ComponentText(RowComponent c);

/// One scalar equation of Phi from a joint.
struct JointEquation {
  GiNaC::ex value;
  RowComponent component = RowComponent::kX;
  bool pair = false;  ///< the x or y projection of a vector closure (dyad recognition)
};

/// The coordinate a joint adds to the model (a slide s, a contact angle psi, a contour
/// parameter u): its name (s_<joint>), a sentence for the header, its LaTeX name.
struct JointCoordinate {
  std::string name, what, latex;
  bool is_angle = false;
};

/// A force or moment component a joint transmits between its two links (statics, issue 14):
/// e.g. a revolute pin's Fx, Fy; a slider's normal force N and moment M; a gear's or cam's
/// contact force along the common normal. Named as the generated code will name it.
struct ReactionComponent {
  std::string name;  ///< "F_<joint>_x", "N_<joint>", ...
  std::string what;  ///< a sentence for the header
};

/// How a joint transmits its reaction (statics, issue 14; symbolic/reactions.cc derives the
/// unknowns, the kind makes its components of them).
enum class ReactionForm {
  kForce,           ///< a force at the joint's point (revolute, slot: the pin; roll: the contact point)
  kForceAndMoment,  ///< a force at the joint's point and a moment about it (prismatic: no relative rotation)
  kContact,         ///< a higher pair (gear, rack, cam): its contact force made from its rows' multipliers
                    ///< (JointKind::Contact); it is always a cut joint
};

/// The unknowns of the force analysis at one joint, from which its kind makes its reaction
/// components (JointKind::Reaction).
struct JointReaction {
  Vec2 F{0, 0};         ///< force of link_a on link_b at `at` (every form)
  Vec2 at{0, 0};        ///< where F acts (JointKind::ReactionPoint; a contact's own point)
  GiNaC::ex M = 0;      ///< moment of link_a on link_b about `at` (kForceAndMoment; a flat-faced law cam's couple)
  GiNaC::ex along = 0;  ///< forces along the joint's line that act apart from F (a tree slider's friction and actuator)
  std::vector<GiNaC::ex> multipliers;  ///< the multipliers of the joint's Phi rows, in row order
  std::vector<GiNaC::ex> components;   ///< kContact: the values of ReactionComponents() (JointKind::Contact)
};

/// What a higher pair's contact force is made from (JointKind::Contact): every link's frame,
/// every joint's coordinate (0 if none), the multipliers of its rows and which joints place
/// a link in the spanning tree.
struct ContactInput {
  const std::vector<Frame>& frames;
  const std::vector<GiNaC::ex>& var;
  std::vector<GiNaC::ex> multipliers;
  std::vector<bool> in_tree;  ///< per joint
};

/// Coulomb friction at a joint: the friction load is gain normal, against `relative`.
struct JointFriction {
  GiNaC::ex normal;  ///< the force friction acts with (>= 0)
  GiNaC::ex gain;    ///< mu r (revolute: the friction circle's radius) or mu (prismatic)
};

class JointKind {
 public:
  virtual ~JointKind() = default;

  virtual JointType type() const = 0;
  /// The keys under the kind's key (`prismatic: {guide: ..., ...}`); section() is the
  /// kind's key in the model file. A kind written as a list (revolute) has no keys.
  virtual const KeyTable& Keys() const = 0;
  /// Reads the kind's body into j->data and sets j->link_a, j->link_b.
  virtual void Read(SectionReader& r, const YAML::Node& body, Joint* j) const = 0;
  /// Resolves references to other joints once every joint is read (rack: its slide;
  /// cam: its follower's joint).
  virtual void Resolve(SectionReader& r, int joint) const;
  /// Checks the joint's numbers at the parameters' defaults (radii positive, ...); the
  /// validation stage calls it.
  virtual void Check(const Model& m, const Joint& j) const;

  /// Lower pairs (revolute, prismatic, roll) can place a link in the spanning tree.
  virtual bool IsLowerPair() const = 0;
  /// The coordinate the joint adds, if any.
  virtual std::optional<JointCoordinate> Coordinate(const Model& m, const Joint& j) const;
  /// Tree joint `j` between `parent` (placed, frame `fp`) and its other link, whose
  /// absolute angle is `child_theta`; `s` is the joint's coordinate (0 if none). Lower
  /// pairs only.
  virtual Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp,
                           const GiNaC::ex& child_theta, const GiNaC::ex& s) const;
  /// The rows the joint adds to Phi. A cut lower pair closes its loop with its two vector
  /// projections (x, y); a rolling joint adds its no-slip row whether it is a cut or a
  /// tree joint; a higher pair adds its one row (a contour cam two).
  /// \param frames every link's frame; \param var every joint's coordinate (0 if none).
  virtual std::vector<JointEquation> Equations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                               const std::vector<GiNaC::ex>& var) const = 0;
  /// One line for the report: "revolute ground.A = crank.A".
  virtual std::string Describe(const Model& m, const Joint& j) const = 0;

  /// Statics (issue 14) attaches here: the reaction components the joint transmits, each
  /// becoming an unknown of the force analysis with the joint's Phi rows (cut joint) or
  /// placement (tree joint) as its direction. Friction (a Coulomb coefficient per joint
  /// kind, acting against the relative motion of the joint's coordinate) will be a key of
  /// the kind and a term in these components. Not used by the kinematics.
  virtual std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const = 0;
  /// How the joint transmits its reaction (default: a higher pair's contact force).
  virtual ReactionForm Reacts() const { return ReactionForm::kContact; }
  /// Where the force of a kForce or kForceAndMoment joint acts (default: the joint's point on
  /// link_b; roll: the contact point); `s` is the joint's coordinate (0 if none).
  virtual Vec2 ReactionPoint(const Model& m,
                             const Joint& j,
                             const std::vector<Frame>& frames,
                             const GiNaC::ex& s) const;
  /// A higher pair (kContact): its contact force on link_b by link_a as a vector, r->F at
  /// r->at (plus a couple r->M where the force is taken at a point off its line), and
  /// r->components, from the multipliers of its rows (Paul §5: their virtual work equals the
  /// contact force's over every virtual motion of the links). False, with *why set, where
  /// the multipliers are not the contact force (a cam's or gear's axis a cut joint).
  virtual bool Contact(
      const Model& m, const Joint& j, const ContactInput& in, JointReaction* r, std::string* why) const;
  /// The values of ReactionComponents(), in their order, from the unknowns `r` at the joint;
  /// \param frames every link's frame. Empty, with *why set, where the kind cannot give them
  /// (the default: a contact's r.components).
  virtual std::vector<GiNaC::ex> Reaction(const Model& m, const Joint& j, const std::vector<Frame>& frames,
                                          const JointReaction& r, std::string* why) const;
  /// The relative motion Coulomb friction opposes (revolute: theta_b - theta_a; prismatic:
  /// its slide s), from every link's frame and the joint's coordinate `s` (0 if none).
  /// Friction is modelled at revolute and prismatic joints only (model/statics.cc).
  virtual GiNaC::ex RelativeMotion(const Model& m, const Joint& j, const std::vector<Frame>& frames,
                                   const GiNaC::ex& s) const;
  /// Coulomb friction with coefficient data `f` at the joint whose unknowns are `r`.
  virtual JointFriction CoulombFriction(const Model& m, const Joint& j, const Friction& f,
                                        const std::vector<Frame>& frames, const JointReaction& r) const;
};

/// Every joint kind, in JointType order (the registry).
const std::vector<const JointKind*>& JointKinds();
const JointKind& KindOf(JointType type);
inline const JointKind& KindOf(const Joint& j) { return KindOf(j.type()); }
/// The kind whose key is `key` ("revolute", ...), or nullptr.
const JointKind* FindKind(const std::string& key);

// The kinds (one file each).
const JointKind& RevoluteKind();
const JointKind& PrismaticKind();
const JointKind& RollKind();
const JointKind& GearKind();
const JointKind& RackKind();
const JointKind& CamKind();
const JointKind& SlotKind();

/// A revolute joint over n > 2 links, `head.name: {revolute: [a.P, b.Q, c.R, ...]}`: n - 1
/// pins sharing the first point, named `J` (first and second link) and `J_<link>` for each
/// further link, each marked at its list element (revolute.cc). Errors: a link listed twice.
std::vector<Joint> ReadPinOverLinks(SectionReader& r, const YAML::Node& body, const Joint& head);

/// The unit vector u along a slot joint's line when its slotted link is at angle `theta`
/// (slot.cc).
Vec2 SlotDirection(const Model& m, const SlotData& d, const GiNaC::ex& theta);

/// The unit vector u along a prismatic joint's line (its angle in the guide's frame plus
/// the guide's absolute angle `guide_theta`; prismatic.cc).
Vec2 LineDirection(const PrismaticData& d, const GiNaC::ex& guide_theta);

/// The force of a meshing pair of teeth on the second member (gear pair, rack and pinion),
/// acting at the pitch point `pitch` on the first member's pitch circle, e the unit vector from
/// that circle's centre to the pitch point, with pressure angle `pressure`, from the
/// multiplier `lambda` of the mesh row (whose gradient is minus the relative motion of the
/// second member along t there): F.t = -lambda along t = e turned +90 deg, and the
/// separating part |lambda| tan(pressure) along e; components F_x, F_y, N (along the line of
/// action, |lambda| / cos(pressure)) and T (= F.t) (gear.cc).
void MeshForce(const Vec2& e, const Vec2& pitch, const GiNaC::ex& pressure, const GiNaC::ex& lambda, JointReaction* r);

/// The components of MeshForce for joint `j`, `centre` naming where e starts (gear.cc).
std::vector<ReactionComponent> MeshComponents(const Model& m, const Joint& j, const std::string& centre);

/// A pressure angle must lie in [0, 90 deg) at the parameters' defaults (gear.cc).
void CheckPressureAngle(const Model& m, const Joint& j, const GiNaC::ex& angle, const SourceMark& mark);

/// The revolute joint link `gear` turns on relative to `carrier`: the one joining them, else
/// its revolute joint to a link that turns on the carrier by a revolute joint (the sun of a
/// planetary train, pinned to the ground under the carrier arm); -1 if none (gear.cc).
int AxisJoint(const Model& m, int gear, int carrier);

/// The contact point of rolling joint `j` in the fixed frame: on the line or circle of the
/// base link (frame `base`) at contact parameter `v` (roll.cc).
Vec2 ContactPosition(const Model& m, const Joint& j, const Frame& base, const GiNaC::ex& v);

}  // namespace mechgen
