// The drawing description of a model. See drawing.h.
#include "codegen/drawing.h"

#include <algorithm>

#include "joints/cam_profile.h"
#include "joints/joint_kind.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using Dir = Argument::Direction;

std::string N(int i) { return std::to_string(i); }

bool HasScene(const Model& m, const Kinematics& k) { return m.outputs.scene && !k.scene.empty(); }

// The scene index of point `r`, -1 if it is not a scene point.
int SceneIndex(const Model& m, const Kinematics& k, const PointRef& r) {
  if (r.link < 0) return -1;
  const std::string name = m.PointName(r);
  for (size_t s = 0; s < k.scene_names.size(); ++s)
    if (k.scene_names[s] == name) return static_cast<int>(s);
  return -1;
}

// The point of `link` at a revolute joint with `carrier` (a gear's axis), else at its first
// revolute joint (a sun gear pinned to the ground, meshing relative to the arm), or none.
PointRef AxisPoint(const Model& m, int link, int carrier) {
  for (const Joint& j : m.joints)
    if (j.type() == JointType::kRevolute && j.Joins(link) && j.OtherLink(link) == carrier) return j.End(link);
  for (const Joint& j : m.joints)
    if (j.type() == JointType::kRevolute && j.Joins(link)) return j.End(link);
  return {};
}

// The values a joint's shape needs, in the fixed frame where they are directions.
std::vector<ex> JointValues(const Model& m, const Kinematics& k, const Joint& j) {
  switch (j.type()) {
    case JointType::kRevolute: return {};
    case JointType::kPrismatic: return {j.Data<PrismaticData>().angle + k.frames[j.link_a].theta};
    case JointType::kRoll: {
      const RollData& d = j.Data<RollData>();
      return {d.radius, d.on_line ? ex(0) : d.on_radius, d.on_line ? d.line_angle + k.frames[j.link_a].theta : ex(0)};
    }
    case JointType::kGear: {
      const GearData& d = j.Data<GearData>();
      return {d.radius[0], d.radius[1]};
    }
    case JointType::kRack: return {j.Data<RackData>().radius};
    case JointType::kCam: {
      const CamData& d = j.Data<CamData>();
      return {d.roller, d.flat_face ? d.face_angle + k.frames[j.link_b].theta : ex(0)};
    }
    case JointType::kSlot: {
      // The slot's line in the fixed frame: `angle` in the slotted link's frame, or the
      // direction from `slot` to `through` (slot.cc, SlotDirection).
      const SlotData& d = j.Data<SlotData>();
      if (d.through.link < 0) return {d.angle + k.frames[j.link_a].theta};
      const LinkPoint& g = m.links[d.slot.link].points[d.slot.point];
      const LinkPoint& h = m.links[d.through.link].points[d.through.point];
      return {atan2(h.y - g.y, h.x - g.x) + k.frames[j.link_a].theta};
    }
  }
  return {};
}

// Scene points of a joint: (a, b) as DrawingConstants documents them.
std::pair<int, int> JointPoints(const Model& m, const Kinematics& k, const Joint& j) {
  switch (j.type()) {
    case JointType::kRevolute: {
      const RevoluteData& d = j.Data<RevoluteData>();
      return {SceneIndex(m, k, d.a), SceneIndex(m, k, d.b)};
    }
    case JointType::kPrismatic: {
      const PrismaticData& d = j.Data<PrismaticData>();
      return {SceneIndex(m, k, d.guide), SceneIndex(m, k, d.slider)};
    }
    case JointType::kRoll: {
      const RollData& d = j.Data<RollData>();
      return {SceneIndex(m, k, d.on), SceneIndex(m, k, d.wheel)};
    }
    case JointType::kGear: {
      const GearData& d = j.Data<GearData>();
      const int carrier = d.carrier >= 0 ? d.carrier : m.ground;
      return {SceneIndex(m, k, AxisPoint(m, j.link_a, carrier)), SceneIndex(m, k, AxisPoint(m, j.link_b, carrier))};
    }
    case JointType::kRack: {
      const RackData& d = j.Data<RackData>();
      const int carrier = d.carrier >= 0 ? d.carrier : m.ground;
      return {SceneIndex(m, k, AxisPoint(m, j.link_a, carrier)), -1};
    }
    case JointType::kCam: {
      const CamData& d = j.Data<CamData>();
      const int pivot = d.pivot >= 0 ? SceneIndex(m, k, m.joints[d.pivot].End(j.link_a)) : -1;
      return {pivot, SceneIndex(m, k, d.point)};
    }
    case JointType::kSlot: {
      const SlotData& d = j.Data<SlotData>();
      return {SceneIndex(m, k, d.slot), SceneIndex(m, k, d.pin)};
    }
  }
  return {-1, -1};
}

template <typename F>
std::string JoinInts(const std::vector<Joint>& joints, F f) {
  std::string s;
  for (size_t i = 0; i < joints.size(); ++i) s += (i ? ", " : "") + N(f(joints[i]));
  return s;
}

}  // namespace

int NumDrawValues(const Model& m) {
  Kinematics none;
  none.frames.resize(m.links.size());
  size_t n = 0;
  for (const Joint& j : m.joints) n += JointValues(m, none, j).size();
  return std::max<int>(1, static_cast<int>(n));
}

std::string DrawingConstants(const Model& m, const Kinematics& k) {
  if (!HasScene(m, k)) return "";
  const std::string nj = N(static_cast<int>(m.joints.size()));
  std::vector<int> first;
  int v = 0;
  for (const Joint& j : m.joints) {
    first.push_back(v);
    v += static_cast<int>(JointValues(m, k, j).size());
  }
  std::string s;
  s += "  /// Drawing (mechgen/io/svg.h), per joint in the model's order: its kind (0 revolute, 1 prismatic,\n"
       "  /// 2 roll, 3 gear, 4 rack, 5 cam), its two links (Joint::link_a, link_b), its two scene points\n"
       "  /// (-1: none; revolute: a, b; prismatic: guide, slider; roll: base point, wheel centre; gear: the\n"
       "  /// two gears' axes; rack: the pinion's axis; cam: the cam's pivot, the follower's point), and\n"
       "  /// the first of its values in EvalDrawing's `values` (prismatic: the line's angle in the fixed\n"
       "  /// frame; roll: radius, base radius (0: a line), base line's angle; gear: both pitch radii;\n"
       "  /// rack: the pinion's pitch radius; cam: roller radius, flat face's angle).\n";
  // Said only where it applies, so that the headers of models without slots keep their bytes.
  bool slots = false;
  for (const Joint& j : m.joints) slots = slots || j.type() == JointType::kSlot;
  if (slots)
    s += "  /// Slot joints are kind 6: scene points the slot's point and the pin; value: the slot's\n"
         "  /// line's angle in the fixed frame.\n";
  s += "  static constexpr int kNumDrawJoints = " + nj + ";\n";
  s += "  static constexpr int kNumDrawValues = " + N(NumDrawValues(m)) + ";\n";
  s += "  static constexpr std::array<int, " + nj + "> kDrawJointKind{ " +
       JoinInts(m.joints, [](const Joint& j) { return static_cast<int>(j.type()); }) + " };\n";
  s += "  static constexpr std::array<int, " + nj + "> kDrawJointLinkA{ " +
       JoinInts(m.joints, [](const Joint& j) { return j.link_a; }) + " };\n";
  s += "  static constexpr std::array<int, " + nj + "> kDrawJointLinkB{ " +
       JoinInts(m.joints, [](const Joint& j) { return j.link_b; }) + " };\n";
  s += "  static constexpr std::array<int, " + nj + "> kDrawJointPointA{ " +
       JoinInts(m.joints, [&](const Joint& j) { return JointPoints(m, k, j).first; }) + " };\n";
  s += "  static constexpr std::array<int, " + nj + "> kDrawJointPointB{ " +
       JoinInts(m.joints, [&](const Joint& j) { return JointPoints(m, k, j).second; }) + " };\n";
  std::string firsts;
  for (size_t i = 0; i < first.size(); ++i) firsts += (i ? ", " : "") + N(first[i]);
  s += "  static constexpr std::array<int, " + nj + "> kDrawJointValue{ " + firsts + " };\n";
  return s;
}

std::vector<FunctionSpec> DrawingFunctions(const Model& m, const Kinematics& k, CxxPrinter* printer) {
  std::vector<FunctionSpec> out;
  if (!HasScene(m, k)) return out;
  FunctionSpec f;
  f.name = "EvalDrawing";
  f.model_member = "Drawing";
  f.instantiate = false;
  f.doc = {"\\brief What a drawing needs besides the scene points: every link's frame and the joints'",
           "values (Model::kDrawJointValue)."};
  f.args = AtConfiguration();
  f.args.push_back(Arg("Mat<Scalar, 3, Sizes::kNumLinks>*", "frames", Dir::kOut,
                       "frames.col(l) = link l's origin x, y and angle theta in the fixed frame; not nullptr.",
                       "3 x kNumLinks"));
  f.args.push_back(Arg("Vec<Scalar, " + N(NumDrawValues(m)) + ">*", "values", Dir::kOut,
                       "The joints' values (Model::kDrawJointValue); not nullptr.", "dim kNumDrawValues"));
  Program P;
  for (size_t l = 0; l < m.links.size(); ++l) {
    const Frame& fr = k.frames[l];
    const ex parts[3] = {fr.x, fr.y, fr.theta};
    for (int a = 0; a < 3; ++a)
      P.push_back(Store("(*frames)(" + N(a) + ", " + N(static_cast<int>(l)) + ")", parts[a]));
  }
  int v = 0;
  for (const Joint& j : m.joints)
    for (const ex& e : JointValues(m, k, j)) P.push_back(Store("(*values)(" + N(v++) + ")", e));
  if (v == 0) P.push_back(Store("(*values)(0)", 0));
  f.body = {P};
  out.push_back(f);

  bool cams = false;
  for (const Joint& j : m.joints) cams = cams || j.type() == JointType::kCam;
  if (!cams) return out;
  FunctionSpec c;
  c.name = "EvalCamProfile";
  c.model_member = "CamProfile";
  c.instantiate = false;
  c.count_ops = false;
  c.reindent = true;
  c.doc = {"\\brief A point of the profile of cam joint `joint` in the cam's frame, at t in [0, 1) along",
           "the profile (counter-clockwise once round; law cams: the contact point at cam angle 2 pi t)."};
  c.args = {Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."),
            Arg("int", "joint", Dir::kIn, "The cam joint (index into the model's joints)."),
            Arg("const Scalar&", "t", Dir::kIn, "Where along the profile, in [0, 1)."),
            Arg("Mat<Scalar, 2, 1>*", "r", Dir::kOut, "The profile's point in the cam's frame; not nullptr.")};
  Program C;
  GiNaC::symbol u("u_draw");
  printer->Name(u, "u");
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    const Joint& j = m.joints[ji];
    if (j.type() != JointType::kCam) continue;
    const CamData& d = j.Data<CamData>();
    C.push_back(Raw("if (joint == " + N(static_cast<int>(ji)) + ") {  // " + j.name));
    if (d.contour == CamData::Contour::kNone) {
      C.push_back(Raw("CamState<Scalar> s;"));
      C.push_back(Raw("EvalCam_" + j.name + "(p, Scalar(6.283185307179586) * t, &s);"));
      C.push_back(Raw("*r = s.contact;"));
    } else {
      ex period = 0;
      for (const CamContour& cc : k.cam_contours)
        if (cc.joint == static_cast<int>(ji))
          period = d.contour == CamData::Contour::kSpline ? ex(cc.knots.back()) : d.contour_period;
      if (period.is_zero()) period = 2 * GiNaC::Pi;
      C.push_back(Raw("const Scalar u = " + printer->Print(period) + " * t;"));
      const Vec2 pt = ContourPoint(j, u, 0);
      C.push_back(Raw("(*r)(0) = " + printer->Print(pt[0]) + ";"));
      C.push_back(Raw("(*r)(1) = " + printer->Print(pt[1]) + ";"));
    }
    C.push_back(Raw("return;"));
    C.push_back(Raw("}"));
  }
  C.push_back(Raw("r->setZero();"));
  c.body = {C};
  out.push_back(c);
  return out;
}

}  // namespace mechgen
