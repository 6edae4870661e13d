// Rolling without slip: a circle of `radius` centred at `wheel` (the wheel's link) rolls
// on the line through `on` at `line_angle`, or on the circle of `on_radius` centred at `on`
// (outside, or inside if `inside`), both on the base link.
//   model file:  R: {roll: {wheel: w.C, radius: r, on: g.G, line_angle: 0, phase: 0}}
//   coordinate:  s_<joint> (the contact point from `on` along the line) or psi_<joint>
//                (the contact point's angle about `on`, in the base's frame)
//   rows:        contact (x, y; only as a cut joint) + no slip (always)
//   reaction:    the force of the base on the wheel at the contact point: F_x, F_y, N along
//                the common normal n (into the wheel), T along t (n = t turned +90 deg)
#include "joints/joint_kind.h"

#include <sstream>
#include <string>

namespace mechgen {
namespace {

// The wheel's centre from the base point, on top of the contact parameter v (base angle
// theta_base):
//   line:   contact Q = G + v u, centre C = Q + r n (n: u turned +90 deg, the wheel's side)
//   circle: contact Q = O + R e(theta_b + v), centre C = O + (R +- r) e(theta_b + v)
Vec2 RollCentreOffset(const RollData& d, const GiNaC::ex& theta_base, const GiNaC::ex& v) {
  if (d.on_line) {
    const GiNaC::ex a = theta_base + d.line_angle;
    return {v * cos(a) - d.radius * sin(a), v * sin(a) + d.radius * cos(a)};
  }
  const GiNaC::ex dist = d.inside ? d.on_radius - d.radius : d.on_radius + d.radius;
  return {dist * cos(theta_base + v), dist * sin(theta_base + v)};
}

class Roll : public JointKind {
 public:
  JointType type() const override { return JointType::kRoll; }

  const KeyTable& Keys() const override {
    static const KeyTable table{
        "roll",
        {{"wheel", "link.C: the wheel's centre", true},
         {"radius", "the wheel's radius r (positive)", true},
         {"on", "link.P: a point of the line, or the centre of the circle rolled on", true},
         {"line_angle", "the line's direction in the base link's frame (default 0; not with on_radius)", false},
         {"on_radius", "rolls on the circle of this radius about `on` instead of a line", false},
         {"inside", "true: inside the circle (needs on_radius; default false)", false},
         {"phase", "the constant of the no-slip relation (default 0)", false}}};
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    RollData d;
    bool has_wheel = false, has_on = false, has_radius = false, has_on_radius = false, has_line_angle = false,
         has_inside = false;
    for (const auto& [key, value] : r.Entries(body, "rolling joint '" + name + "'", &Keys())) {
      if (key == "wheel") d.wheel = r.Point(value, "wheel of '" + name + "'"), has_wheel = true;
      if (key == "on") d.on = r.Point(value, "on of '" + name + "'"), has_on = true;
      if (key == "radius") {
        d.radius = r.Expression(value, "radius of '" + name + "'"), has_radius = true;
        d.radius_mark = MarkOf(value);
      }
      if (key == "line_angle") d.line_angle = r.Expression(value, "line_angle of '" + name + "'"), has_line_angle = true;
      if (key == "on_radius") {
        d.on_radius = r.Expression(value, "on_radius of '" + name + "'"), has_on_radius = true;
        d.on_radius_mark = MarkOf(value);
      }
      if (key == "inside") d.inside = r.Bool(value, "inside"), has_inside = true;
      if (key == "phase") d.phase = r.Expression(value, "phase of '" + name + "'");
    }
    if (!has_wheel || !has_on || !has_radius)
      r.Fail(body, "rolling joint '" + name + "' needs wheel: link.C (the wheel's centre), radius: r, and "
                   "on: link.P (a point of the line, or the centre of the circle with on_radius: R)");
    if (has_on_radius && has_line_angle)
      r.Fail(body, "rolling joint '" + name + "': give line_angle (a line) or on_radius (a circle), not both");
    if (has_inside && !has_on_radius) r.Fail(body, "rolling joint '" + name + "': inside needs on_radius (a circle)");
    d.on_line = !has_on_radius;
    j->link_a = d.on.link;
    j->link_b = d.wheel.link;
    j->data = d;
  }

  void Check(const Model& m, const Joint& j) const override {
    const RollData& d = j.Data<RollData>();
    const double r = ValueAtDefaults(m, d.radius, d.radius_mark, "radius");
    if (!(r > 0)) m.Fail(d.radius_mark, "the wheel radius must be positive");
    if (d.on_line) return;
    const double R = ValueAtDefaults(m, d.on_radius, d.on_radius_mark, "on_radius");
    if (!(R > 0)) m.Fail(d.on_radius_mark, "on_radius must be positive");
    if (d.inside && !(R > r))
      m.Fail(d.on_radius_mark, "a wheel rolling inside a circle must be smaller than it (radius " + std::to_string(r) +
                                   " >= on_radius " + std::to_string(R) + ")");
  }

  bool IsLowerPair() const override { return true; }

  std::optional<JointCoordinate> Coordinate(const Model& m, const Joint& j) const override {
    const RollData& d = j.Data<RollData>();
    if (d.on_line)
      return JointCoordinate{"s_" + j.name,
                             "contact point of rolling joint '" + j.name + "' from " + m.PointName(d.on) +
                                 " along the line",
                             "s_{\\mathrm{" + j.name + "}}", false};
    return JointCoordinate{"psi_" + j.name,
                           "contact angle of rolling joint '" + j.name + "' about " + m.PointName(d.on) +
                               ", in the frame of '" + m.links[j.link_a].name + "'",
                           "\\psi_{\\mathrm{" + j.name + "}}", true};
  }

  Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp, const GiNaC::ex& child_theta,
                   const GiNaC::ex& s) const override {
    const RollData& d = j.Data<RollData>();
    const bool child_is_b = j.link_a == parent;
    Vec2 w = PointPosition(m, child_is_b ? d.on : d.wheel, fp);
    if (child_is_b) {  // parent is the base: the wheel's centre is placed on it
      const Vec2 off = RollCentreOffset(d, fp.theta, s);
      w = {w[0] + off[0], w[1] + off[1]};
    } else {  // parent is the wheel: the base point lies back from the centre
      const Vec2 off = RollCentreOffset(d, child_theta, s);
      w = {w[0] - off[0], w[1] - off[1]};
    }
    return FrameThrough(m, child_is_b ? d.wheel : d.on, w, child_theta);
  }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>& var) const override {
    const Joint& j = m.joints[joint];
    const RollData& d = j.Data<RollData>();
    const Frame& fa = frames[j.link_a];
    const Frame& fb = frames[j.link_b];
    const GiNaC::ex& s = var[joint];
    std::vector<JointEquation> rows;
    // Contact: the wheel's centre on its line or circle (r_on + d(v) - r_wheel = 0).
    if (cut) {
      const Vec2 ra = PointPosition(m, d.on, fa), rb = PointPosition(m, d.wheel, fb);
      const Vec2 off = RollCentreOffset(d, fa.theta, s);
      rows.push_back({ra[0] + off[0] - rb[0], RowComponent::kX, true});
      rows.push_back({ra[1] + off[1] - rb[1], RowComponent::kY, true});
    }
    // No slip: equal arc lengths on both contours since phase. Line: the contact runs
    // v = phase - r (theta_w - theta_b). Circle of radius R, contact angle psi (in the
    // base's frame): R psi +- r (psi + theta_b - theta_w) = phase (+ outside, - inside).
    const GiNaC::ex rel = fb.theta - fa.theta;
    if (d.on_line)
      rows.push_back({s + d.radius * rel - d.phase, RowComponent::kNoSlip, false});
    else
      rows.push_back({d.on_radius * s + (d.inside ? -1 : 1) * d.radius * (s - rel) - d.phase, RowComponent::kNoSlip,
                      false});
    return rows;
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const RollData& d = j.Data<RollData>();
    std::ostringstream os;
    os << "rolling, wheel " << m.PointName(d.wheel) << " radius " << d.radius << " on the "
       << (d.on_line ? "line through " : d.inside ? "inside of the circle about " : "circle about ")
       << m.PointName(d.on);
    if (!d.on_line) os << " radius " << d.on_radius;
    return os.str();
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    const std::string on =
        "force of '" + m.links[j.link_a].name + "' on '" + m.links[j.link_b].name + "' at the contact point";
    return {{"F_" + j.name + "_x", on + ", x"},
            {"F_" + j.name + "_y", on + ", y"},
            {"N_" + j.name, on + " along the common normal n, from the base into the wheel"},
            {"T_" + j.name, on + " along the common tangent t, n = t turned +90 deg (the no-slip friction)"}};
  }

  // A force at the contact point (as a cut joint: its contact rows' multipliers, the force at
  // the wheel's centre, which with the no-slip row's couple r T is the same force at the
  // contact; as a tree joint: the balance of the links it carries).
  ReactionForm Reacts() const override { return ReactionForm::kForce; }

  Vec2 ReactionPoint(const Model& m,
                     const Joint& j,
                     const std::vector<Frame>& frames,
                     const GiNaC::ex& s) const override {
    return ContactPosition(m, j, frames[j.link_a], s);
  }

  std::vector<GiNaC::ex> Reaction(const Model& m,
                                  const Joint& j,
                                  const std::vector<Frame>& frames,
                                  const JointReaction& r,
                                  std::string*) const override {
    const RollData& d = j.Data<RollData>();
    Vec2 n;
    if (d.on_line) {
      const GiNaC::ex a = frames[j.link_a].theta + d.line_angle;
      n = {-sin(a), cos(a)};
    } else {  // along the radius through the contact point, outwards (inwards inside the circle)
      const Vec2 o = PointPosition(m, d.on, frames[j.link_a]);
      const GiNaC::ex k = (d.inside ? -1 : 1) / d.on_radius;
      n = {(r.at[0] - o[0]) * k, (r.at[1] - o[1]) * k};
    }
    return {r.F[0], r.F[1], r.F[0] * n[0] + r.F[1] * n[1], r.F[0] * n[1] - r.F[1] * n[0]};
  }
};

}  // namespace

Vec2 ContactPosition(const Model& m, const Joint& j, const Frame& base, const GiNaC::ex& v) {
  const RollData& d = j.Data<RollData>();
  const Vec2 a = PointPosition(m, d.on, base);
  if (d.on_line) {
    const GiNaC::ex ang = base.theta + d.line_angle;
    return {a[0] + v * cos(ang), a[1] + v * sin(ang)};
  }
  return {a[0] + d.on_radius * cos(base.theta + v), a[1] + d.on_radius * sin(base.theta + v)};
}

const JointKind& RollKind() {
  static const Roll kind;
  return kind;
}

}  // namespace mechgen
