// Slot joint (pin in slot, the RP joint of other linkage tools): point `pin` of one link
// slides along a line fixed in another link and turns freely about it. The line passes
// through `slot` (a point of the slotted link) at `angle` in that link's frame, or through
// `slot` and `through` (a second point of the slotted link). It removes one degree of
// freedom (Grübler: a half joint, counted with j2) and adds the slide as a coordinate:
//   model file:  J: {slot: {slot: link1.G, pin: link2.P, angle: a}}   (or through: link1.H)
//   coordinate:  s_<joint>, the pin's distance from G along the line
//   cut joint:   r_G + s u - r_P = 0, two rows (x, y); u = R(theta_slotted) u_local
//   reaction:    F_x, F_y, the force of the slotted link on the pin (fixed frame), N along
//                n = u turned +90 deg (across the slot), T along u (the driving force if an input)
// Unlike a prismatic joint, the two links keep their own angles (the block link and the
// two joints of the old workaround, in one).
#include "joints/joint_kind.h"

namespace mechgen {

Vec2 SlotDirection(const Model& m, const SlotData& d, const GiNaC::ex& theta) {
  if (d.through.link < 0) return {cos(theta + d.angle), sin(theta + d.angle)};
  const LinkPoint& g = m.links[d.slot.link].points[d.slot.point];
  const LinkPoint& h = m.links[d.through.link].points[d.through.point];
  const GiNaC::ex dx = h.x - g.x, dy = h.y - g.y;
  const GiNaC::ex length = sqrt(dx * dx + dy * dy);
  return Rotate(theta, dx / length, dy / length);
}

namespace {

class Slot : public JointKind {
 public:
  JointType type() const override { return JointType::kSlot; }

  const KeyTable& Keys() const override {
    static const KeyTable table{"slot",
                                {{"slot", "link1.G: a point of the slot's line, on the slotted link", true},
                                 {"pin", "link2.P: the pin that slides (and turns) in the slot", true},
                                 {"angle", "the line's direction in the slotted link's frame (default 0)", false},
                                 {"through", "link1.H: a second point of the line, instead of angle", false}}};
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    SlotData d;
    bool has_slot = false, has_pin = false, has_angle = false;
    YAML::Node through;
    for (const auto& [key, value] : r.Entries(body, "slot joint '" + name + "'", &Keys())) {
      if (key == "slot") d.slot = r.Point(value, "slot of '" + name + "'"), has_slot = true;
      if (key == "pin") d.pin = r.Point(value, "pin of '" + name + "'"), has_pin = true;
      if (key == "angle") d.angle = r.Expression(value, "angle of '" + name + "'"), has_angle = true;
      if (key == "through") d.through = r.Point(value, "through of '" + name + "'"), through = value;
    }
    if (!has_slot || !has_pin)
      r.Fail(body, "slot joint '" + name + "' needs slot: link.point (a point of the slot's line) and pin: link.point");
    if (d.through.link >= 0) {
      if (has_angle) r.Fail(through, "slot joint '" + name + "' has both angle and through; give one");
      if (d.through.link != d.slot.link)
        r.Fail(through, "through of '" + name + "' must be a point of the slotted link '" +
                            r.model().links[d.slot.link].name + "'");
      if (d.through.point == d.slot.point)
        r.Fail(through, "through of '" + name + "' is the slot point itself; give a second point of the line");
      d.through_mark = MarkOf(through);
    }
    j->link_a = d.slot.link;
    j->link_b = d.pin.link;
    j->data = d;
  }

  void Check(const Model& m, const Joint& j) const override {
    const SlotData& d = j.Data<SlotData>();
    if (d.through.link < 0) return;
    const LinkPoint& g = m.links[d.slot.link].points[d.slot.point];
    const LinkPoint& h = m.links[d.through.link].points[d.through.point];
    const GiNaC::ex l2 = (h.x - g.x) * (h.x - g.x) + (h.y - g.y) * (h.y - g.y);
    if (ValueAtDefaults(m, l2, d.through_mark, "through of '" + j.name + "'") == 0)
      m.Fail(d.through_mark, "slot joint '" + j.name + "': " + m.PointName(d.through) + " coincides with " +
                                 m.PointName(d.slot) + " at the parameters' defaults, so they give no direction; "
                                 "move one, or give angle instead");
  }

  bool IsLowerPair() const override { return true; }

  std::optional<JointCoordinate> Coordinate(const Model& m, const Joint& j) const override {
    const SlotData& d = j.Data<SlotData>();
    return JointCoordinate{"s_" + j.name,
                           "slide of pin '" + j.name + "' (" + m.PointName(d.pin) + " from " + m.PointName(d.slot) +
                               " along the slot)",
                           "s_{\\mathrm{" + j.name + "}}", false};
  }

  Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp, const GiNaC::ex& child_theta,
                   const GiNaC::ex& s) const override {
    const SlotData& d = j.Data<SlotData>();
    const bool child_is_pin = j.link_a == parent;
    if (child_is_pin) {  // the slotted link is placed: pin = G + s u(theta_slotted)
      const Vec2 g = PointPosition(m, d.slot, fp), u = SlotDirection(m, d, fp.theta);
      return FrameThrough(m, d.pin, {g[0] + s * u[0], g[1] + s * u[1]}, child_theta);
    }
    // The pin's link is placed: G = pin - s u(theta_child).
    const Vec2 p = PointPosition(m, d.pin, fp), u = SlotDirection(m, d, child_theta);
    return FrameThrough(m, d.slot, {p[0] - s * u[0], p[1] - s * u[1]}, child_theta);
  }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>& var) const override {
    if (!cut) return {};
    const Joint& j = m.joints[joint];
    const SlotData& d = j.Data<SlotData>();
    const Frame& fa = frames[j.link_a];
    const GiNaC::ex& s = var[joint];
    const Vec2 g = PointPosition(m, d.slot, fa), p = PointPosition(m, d.pin, frames[j.link_b]);
    const Vec2 u = SlotDirection(m, d, fa.theta);
    return {{g[0] + s * u[0] - p[0], RowComponent::kX, true}, {g[1] + s * u[1] - p[1], RowComponent::kY, true}};
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const SlotData& d = j.Data<SlotData>();
    return "slot " + m.PointName(d.pin) + " slides in the slot through " + m.PointName(d.slot) +
           (d.through.link >= 0 ? " and " + m.PointName(d.through) : std::string());
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    const std::string on = "force of '" + m.links[j.link_a].name + "' on '" + m.links[j.link_b].name + "' at the pin";
    return {{"F_" + j.name + "_x", on + ", x"},
            {"F_" + j.name + "_y", on + ", y"},
            {"N_" + j.name, on + " across the slot, along n = u turned +90 deg (u along the slot)"},
            {"T_" + j.name, on + " along the slot u (the driving force if the slot is an input; no friction)"}};
  }

  // A force at the pin, which turns freely in the slot; as a cut joint its rows' multipliers.
  ReactionForm Reacts() const override { return ReactionForm::kForce; }

  std::vector<GiNaC::ex> Reaction(const Model& m,
                                  const Joint& j,
                                  const std::vector<Frame>& frames,
                                  const JointReaction& r,
                                  std::string*) const override {
    // F and the force along the slot that acts apart from it (a tree slot's actuator).
    const Vec2 u = SlotDirection(m, j.Data<SlotData>(), frames[j.link_a].theta);
    return {r.F[0] + r.along * u[0], r.F[1] + r.along * u[1], -r.F[0] * u[1] + r.F[1] * u[0],
            r.F[0] * u[0] + r.F[1] * u[1] + r.along};
  }
};

}  // namespace

const JointKind& SlotKind() {
  static const Slot kind;
  return kind;
}

}  // namespace mechgen
