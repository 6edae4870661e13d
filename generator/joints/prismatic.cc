// Prismatic joint (slider): point `slider` moves along the line through `guide` at `angle`
// in the guide link's frame; the slider link keeps the angle theta_guide + relative_angle
// (topology.cc groups such links under one angle).
//   model file:  P: {prismatic: {guide: link1.G, slider: link2.S, angle: a, relative_angle: b}}
//   coordinate:  s_<joint>, the slider point's displacement from the guide point
//   cut joint:   r_guide + s u - r_slider = 0, two rows (x, y)
//   reaction:    N (along n = u turned by 90 deg), T (along u: the actuator's and friction's
//                force) and M (about the slider point), of the guide on the slider; friction
//                the force mu |N| along u against s
#include "joints/joint_kind.h"

namespace mechgen {

Vec2 LineDirection(const PrismaticData& d, const GiNaC::ex& guide_theta) {
  return {cos(guide_theta + d.angle), sin(guide_theta + d.angle)};
}

namespace {

class Prismatic : public JointKind {
 public:
  JointType type() const override { return JointType::kPrismatic; }

  const KeyTable& Keys() const override {
    static const KeyTable table{"prismatic",
                                {{"guide", "link1.G: a point of the line, on the guide link", true},
                                 {"slider", "link2.S: the point that slides on the line", true},
                                 {"angle", "the line's direction in the guide link's frame (default 0)", false},
                                 {"relative_angle", "slider link angle minus guide link angle (default 0)", false}}};
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    PrismaticData d;
    bool has_guide = false, has_slider = false;
    for (const auto& [key, value] : r.Entries(body, "prismatic joint '" + name + "'", &Keys())) {
      if (key == "guide") d.guide = r.Point(value, "guide of '" + name + "'"), has_guide = true;
      if (key == "slider") d.slider = r.Point(value, "slider of '" + name + "'"), has_slider = true;
      if (key == "angle") d.angle = r.Expression(value, "angle of '" + name + "'");
      if (key == "relative_angle") d.relative_angle = r.Expression(value, "relative_angle of '" + name + "'");
    }
    if (!has_guide || !has_slider)
      r.Fail(body, "prismatic joint '" + name + "' needs guide: link.point (a point on the line) and slider: link.point");
    j->link_a = d.guide.link;
    j->link_b = d.slider.link;
    j->data = d;
  }

  bool IsLowerPair() const override { return true; }

  std::optional<JointCoordinate> Coordinate(const Model& m, const Joint& j) const override {
    const PrismaticData& d = j.Data<PrismaticData>();
    return JointCoordinate{"s_" + j.name,
                           "displacement of slider '" + j.name + "' (" + m.PointName(d.slider) + " from " +
                               m.PointName(d.guide) + " along the line)",
                           "s_{\\mathrm{" + j.name + "}}", false};
  }

  Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp, const GiNaC::ex& child_theta,
                   const GiNaC::ex& s) const override {
    const PrismaticData& d = j.Data<PrismaticData>();
    const bool child_is_b = j.link_a == parent;
    Vec2 w = PointPosition(m, child_is_b ? d.guide : d.slider, fp);
    if (child_is_b) {  // parent guides, child slides: slider = guide + s u
      const Vec2 u = LineDirection(d, fp.theta);
      w = {w[0] + s * u[0], w[1] + s * u[1]};
    } else {  // parent slides, child guides: guide = slider - s u(theta_child)
      const Vec2 u = LineDirection(d, child_theta);
      w = {w[0] - s * u[0], w[1] - s * u[1]};
    }
    return FrameThrough(m, child_is_b ? d.slider : d.guide, w, child_theta);
  }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>& var) const override {
    if (!cut) return {};
    const Joint& j = m.joints[joint];
    const PrismaticData& d = j.Data<PrismaticData>();
    const Frame& fa = frames[j.link_a];
    const GiNaC::ex& s = var[joint];
    const Vec2 ra = PointPosition(m, d.guide, fa), rb = PointPosition(m, d.slider, frames[j.link_b]);
    const Vec2 u = LineDirection(d, fa.theta);
    return {{ra[0] + s * u[0] - rb[0], RowComponent::kX, true}, {ra[1] + s * u[1] - rb[1], RowComponent::kY, true}};
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const PrismaticData& d = j.Data<PrismaticData>();
    return "prismatic " + m.PointName(d.guide) + " guides " + m.PointName(d.slider);
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    const std::string by = "'" + m.links[j.link_a].name + "' on '" + m.links[j.link_b].name + "'";
    return {{"N_" + j.name, "normal force of " + by + " along n = (-sin a, cos a), a = the line's angle"},
            {"T_" + j.name, "force of " + by + " along the line u = (cos a, sin a): actuator and friction"},
            {"M_" + j.name, "moment of " + by + " about the slider point, counter-clockwise"}};
  }

  // The force at the slider point and the moment about it: the guide keeps the slider's angle.
  ReactionForm Reacts() const override { return ReactionForm::kForceAndMoment; }

  // N = F.n, T = F.u (and the forces along the line that act apart from F), M.
  std::vector<GiNaC::ex> Reaction(const Model&, const Joint& j, const std::vector<Frame>& frames,
                                  const JointReaction& r, std::string*) const override {
    const Vec2 u = LineDirection(j.Data<PrismaticData>(), frames[j.link_a].theta), n = {-u[1], u[0]};
    return {r.F[0] * n[0] + r.F[1] * n[1], r.F[0] * u[0] + r.F[1] * u[1] + r.along, r.M};
  }

  // Friction acts along the line, gain mu |N|, against the slide s.
  GiNaC::ex RelativeMotion(const Model&, const Joint&, const std::vector<Frame>&, const GiNaC::ex& s) const override {
    return s;
  }

  JointFriction CoulombFriction(const Model&, const Joint& j, const Friction& f, const std::vector<Frame>& frames,
                                const JointReaction& r) const override {
    const Vec2 u = LineDirection(j.Data<PrismaticData>(), frames[j.link_a].theta), n = {-u[1], u[0]};
    return {GiNaC::abs(r.F[0] * n[0] + r.F[1] * n[1]), f.coefficient};
  }
};

}  // namespace

const JointKind& PrismaticKind() {
  static const Prismatic kind;
  return kind;
}

}  // namespace mechgen
