// Rack and pinion: the pinion (pitch radius r) turns on the rack's guide; the rack is the
// slider of a prismatic joint.
//   model file:  K: {rack: {pinion: p, radius: r, slide: <the rack's prismatic joint>, phase: 0}}
//   coordinate:  none (it uses the slide's s)
//   cut joint:   s + r (th_pinion - th_guide) = phase, one row
//   reaction:    the tooth force of the pinion on the rack at the pitch point r n from the
//                pinion's axis (n = the slide's u turned +90 deg: the side the row's sign
//                puts the pinion on), along the line of action (pressure angle, default 20 deg)
#include "joints/joint_kind.h"

#include <sstream>

namespace mechgen {
namespace {

class Rack : public JointKind {
 public:
  JointType type() const override { return JointType::kRack; }

  const KeyTable& Keys() const override {
    static const KeyTable table{"rack",
                                {{"pinion", "the pinion link", true},
                                 {"radius", "the pinion's pitch radius", true},
                                 {"slide", "the prismatic joint whose slider is the rack", true},
                                 {"phase", "the constant of the mesh relation (default 0)", false},
                                 {"pressure_angle", "the teeth's pressure angle (default 20*deg; statics)", false}}};
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    RackData d;
    bool has_pinion = false, has_radius = false, has_slide = false;
    for (const auto& [key, value] : r.Entries(body, "rack and pinion '" + name + "'", &Keys())) {
      if (key == "pinion") j->link_a = r.LinkIndex(value, "joint '" + name + "'"), has_pinion = true;
      if (key == "radius") d.radius = r.Expression(value, "radius of '" + name + "'"), has_radius = true;
      if (key == "slide") d.slide_name = r.Scalar(value, "slide"), d.slide_mark = MarkOf(value), has_slide = true;
      if (key == "phase") d.phase = r.Expression(value, "phase of '" + name + "'");
      if (key == "pressure_angle") {
        d.pressure_angle = r.Expression(value, "pressure_angle of '" + name + "'");
        d.pressure_mark = MarkOf(value);
      }
    }
    if (!has_pinion || !has_radius || !has_slide)
      r.Fail(body, "rack and pinion '" + name + "' needs pinion: link, radius: r and slide: <the rack's prismatic joint>");
    j->data = d;
  }

  void Resolve(SectionReader& r, int joint) const override {
    Model& m = r.model();
    Joint& j = m.joints[joint];
    RackData& d = j.Data<RackData>();
    d.slide = m.FindJoint(d.slide_name);
    if (d.slide < 0) m.Fail(d.slide_mark, "joint '" + j.name + "': unknown joint '" + d.slide_name + "'");
    const Joint& o = m.joints[d.slide];
    if (o.type() != JointType::kPrismatic)
      m.Fail(d.slide_mark, "rack '" + j.name + "': slide must name the rack's prismatic joint");
    j.link_b = o.link_b;
    d.carrier = o.link_a;
    if (j.link_a == j.link_b) m.Fail(d.slide_mark, "rack '" + j.name + "': the pinion cannot be the rack");
  }

  bool IsLowerPair() const override { return false; }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>& var) const override {
    const Joint& j = m.joints[joint];
    const RackData& d = j.Data<RackData>();
    return {{var[d.slide] + d.radius * (frames[j.link_a].theta - frames[d.carrier].theta) - d.phase,
             RowComponent::kRackMesh, false}};
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const RackData& d = j.Data<RackData>();
    std::ostringstream os;
    os << "rack and pinion, pinion " << m.links[j.link_a].name << " (r " << d.radius << "), rack "
       << m.links[j.link_b].name << " on '" << m.joints[d.slide].name << "'";
    return os.str();
  }

  void Check(const Model& m, const Joint& j) const override {
    const RackData& d = j.Data<RackData>();
    CheckPressureAngle(m, j, d.pressure_angle, d.pressure_mark);
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    return MeshComponents(m, j, "the pinion's axis (e = n, the slide's u turned +90 deg)");
  }

  // The row's gradient, ds + r d(th_pinion - th_guide), is the rack's motion along u relative
  // to the pinion's tooth at the pitch point P = axis + r n (n = u turned +90 deg), = minus
  // that motion along t = n turned +90 deg = -u: MeshForce with e = n.
  bool Contact(
      const Model& m, const Joint& j, const ContactInput& in, JointReaction* r, std::string* why) const override {
    const RackData& d = j.Data<RackData>();
    const int axis = AxisJoint(m, j.link_a, d.carrier);
    if (axis < 0) {
      *why = "the pinion '" + m.links[j.link_a].name + "' of rack '" + j.name +
             "' has no revolute joint to the rack's guide '" + m.links[d.carrier].name + "'";
      return false;
    }
    for (int k : {axis, d.slide})
      if (!in.in_tree[k]) {
        *why = "joint '" + m.joints[k].name +
               "' (the pinion's axis or the rack's slide) closes a loop, so the mesh "
               "row's multiplier is not the tooth force alone; mechgen derives rack forces where both place their "
               "links in the spanning tree";
        return false;
      }
    const Vec2 centre = PointPosition(m, m.joints[axis].End(j.link_a), in.frames[j.link_a]);
    const Vec2 u = LineDirection(m.joints[d.slide].Data<PrismaticData>(), in.frames[d.carrier].theta);
    const Vec2 n{-u[1], u[0]};
    MeshForce(n, {centre[0] + d.radius * n[0], centre[1] + d.radius * n[1]}, d.pressure_angle, in.multipliers.at(0), r);
    return true;
  }
};

}  // namespace

const JointKind& RackKind() {
  static const Rack kind;
  return kind;
}

}  // namespace mechgen
