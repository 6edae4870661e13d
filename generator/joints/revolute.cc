// Revolute joint (pin): point a of one link coincides with point b of the other.
//   model file:  A: {revolute: [link1.P, link2.Q]}, or over several links
//                A: {revolute: [link1.P, link2.Q, link3.R]}: one pin per link after the
//                first, A (P = Q) and A_link3 (P = R) (ReadPinOverLinks)
//   coordinate:  none (the links' angles are the coordinates)
//   cut joint:   r_a - r_b = 0, two rows (x, y)
//   reaction:    F_x, F_y, the force of link a on link b at the pin (fixed frame); friction
//                the couple mu r |F| against theta_b - theta_a
#include "joints/joint_kind.h"

namespace mechgen {
namespace {

class Revolute : public JointKind {
 public:
  JointType type() const override { return JointType::kRevolute; }

  const KeyTable& Keys() const override {
    static const KeyTable table{"revolute", {}};  // a list of two points, no keys
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    if (!body.IsSequence() || body.size() != 2)
      r.Fail(body, "revolute joint '" + name + "' takes two or more link points: [link1.P, link2.Q, ...]");
    RevoluteData d;
    d.a = r.Point(body[0], "joint '" + name + "'");
    d.b = r.Point(body[1], "joint '" + name + "'");
    j->link_a = d.a.link;
    j->link_b = d.b.link;
    j->data = d;
  }

  bool IsLowerPair() const override { return true; }

  Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp, const GiNaC::ex& child_theta,
                   const GiNaC::ex&) const override {
    const RevoluteData& d = j.Data<RevoluteData>();
    const bool child_is_b = j.link_a == parent;
    return FrameThrough(m, child_is_b ? d.b : d.a, PointPosition(m, child_is_b ? d.a : d.b, fp), child_theta);
  }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>&) const override {
    const Joint& j = m.joints[joint];
    const RevoluteData& d = j.Data<RevoluteData>();
    if (!cut) return {};
    const Vec2 ra = PointPosition(m, d.a, frames[j.link_a]), rb = PointPosition(m, d.b, frames[j.link_b]);
    return {{ra[0] - rb[0], RowComponent::kX, true}, {ra[1] - rb[1], RowComponent::kY, true}};
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const RevoluteData& d = j.Data<RevoluteData>();
    return "revolute " + m.PointName(d.a) + " = " + m.PointName(d.b) +
           (d.pin.empty() ? "" : " (pin '" + d.pin + "' over " + d.pin_links + ")");
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    const std::string on = "force of '" + m.links[j.link_a].name + "' on '" + m.links[j.link_b].name + "' at the pin, ";
    return {{"F_" + j.name + "_x", on + "x"}, {"F_" + j.name + "_y", on + "y"}};
  }

  // The force on the pin, in the fixed frame.
  ReactionForm Reacts() const override { return ReactionForm::kForce; }

  std::vector<GiNaC::ex> Reaction(const Model&, const Joint&, const std::vector<Frame>&, const JointReaction& r,
                                  std::string*) const override {
    return {r.F[0], r.F[1]};
  }

  // Friction turns the links against each other: a couple of gain |F| opposing theta_b - theta_a.
  GiNaC::ex RelativeMotion(const Model&, const Joint& j, const std::vector<Frame>& frames,
                           const GiNaC::ex&) const override {
    return frames[j.link_b].theta - frames[j.link_a].theta;
  }

  JointFriction CoulombFriction(const Model&, const Joint&, const Friction& f, const std::vector<Frame>&,
                                const JointReaction& r) const override {
    return {GiNaC::sqrt(r.F[0] * r.F[0] + r.F[1] * r.F[1]), f.coefficient * f.pin_radius};
  }
};

}  // namespace

std::vector<Joint> ReadPinOverLinks(SectionReader& r, const YAML::Node& body, const Joint& head) {
  const Model& m = r.model();
  const std::string& name = head.name;
  std::vector<PointRef> points;
  std::string links;
  for (size_t k = 0; k < body.size(); ++k) {
    const PointRef p = r.Point(body[k], "joint '" + name + "'");
    for (const PointRef& q : points)
      if (q.link == p.link)
        r.Fail(body[k], "revolute joint '" + name + "' lists link '" + m.links[p.link].name +
                            "' twice; a pin joins each of its links once");
    points.push_back(p);
    links += (links.empty() ? "" : ", ") + m.links[p.link].name;
  }
  std::vector<Joint> out;
  for (size_t k = 1; k < points.size(); ++k) {
    Joint j = head;
    if (k > 1) {
      j.name = name + "_" + m.links[points[k].link].name;
      j.mark = MarkOf(body[k]);
    }
    RevoluteData d;
    d.a = points[0];
    d.b = points[k];
    d.pin = name;
    d.pin_links = links;
    j.link_a = d.a.link;
    j.link_b = d.b.link;
    j.data = d;
    out.push_back(j);
  }
  return out;
}

const JointKind& RevoluteKind() {
  static const Revolute kind;
  return kind;
}

}  // namespace mechgen
