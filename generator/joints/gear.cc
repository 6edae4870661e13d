// Gear pair: two gears with pitch radii r1, r2 whose axes both sit on the carrier (the
// ground, or a planetary train's arm); external, or internal (the second gear is the ring).
//   model file:  G: {gear: {gears: [g1, g2], radii: [r1, r2], carrier: arm, internal: false, phase: 0}}
//   coordinate:  none
//   cut joint:   r1 (th1 - thc) +- r2 (th2 - thc) = phase, one row (+ external, - internal)
//   reaction:    the tooth force of gear 1 on gear 2 at the pitch point, along the line of
//                action (pressure angle, default 20 deg): F_x, F_y, N (along the line of
//                action) and T (tangential, transmitted), from the row's multiplier
#include "joints/joint_kind.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace mechgen {
namespace {

class Gear : public JointKind {
 public:
  JointType type() const override { return JointType::kGear; }

  const KeyTable& Keys() const override {
    static const KeyTable table{
        "gear",
        {{"gears", "[link1, link2]: the two gear links", true},
         {"radii", "[r1, r2]: their pitch radii (positive)", true},
         {"carrier", "the link holding both axes (default: the ground)", false},
         {"internal", "true: the second gear is an internal (ring) gear (default false)", false},
         {"phase", "the constant of the mesh relation (default 0)", false},
         {"pressure_angle", "the teeth's pressure angle (default 20*deg; statics)", false}}};
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    const std::string jn = "joint '" + name + "'";
    GearData d;
    d.carrier = r.model().ground;
    bool has_gears = false, has_radii = false;
    for (const auto& [key, value] : r.Entries(body, "gear pair '" + name + "'", &Keys())) {
      if (key == "gears") {
        if (!value.IsSequence() || value.size() != 2) r.Fail(value, "gears: takes the two gear links: [link1, link2]");
        j->link_a = r.LinkIndex(value[0], jn);
        j->link_b = r.LinkIndex(value[1], jn);
        has_gears = true;
      }
      if (key == "radii") {
        if (!value.IsSequence() || value.size() != 2) r.Fail(value, "radii: takes the two pitch radii: [r1, r2]");
        for (int i = 0; i < 2; ++i) {
          d.radius[i] = r.Expression(value[i], "pitch radius");
          d.radius_mark[i] = MarkOf(value[i]);
        }
        has_radii = true;
      }
      if (key == "carrier") d.carrier = r.LinkIndex(value, jn);
      if (key == "internal") d.internal = r.Bool(value, "internal");
      if (key == "phase") d.phase = r.Expression(value, "phase of '" + name + "'");
      if (key == "pressure_angle") {
        d.pressure_angle = r.Expression(value, "pressure_angle of '" + name + "'");
        d.pressure_mark = MarkOf(value);
      }
    }
    if (!has_gears || !has_radii)
      r.Fail(body, "gear pair '" + name + "' needs gears: [link1, link2] and radii: [r1, r2]");
    if (d.carrier == j->link_a || d.carrier == j->link_b)
      r.Fail(body, "gear pair '" + name + "': the carrier holds both gears' axes and is neither gear");
    j->data = d;
  }

  void Check(const Model& m, const Joint& j) const override {
    const GearData& d = j.Data<GearData>();
    CheckPressureAngle(m, j, d.pressure_angle, d.pressure_mark);
    double r[2];
    for (int i = 0; i < 2; ++i) {
      r[i] = ValueAtDefaults(m, d.radius[i], d.radius_mark[i], "pitch radius");
      if (!(r[i] > 0)) m.Fail(d.radius_mark[i], "a pitch radius must be positive");
    }
    // An internal pair: the second gear is the ring, larger than the gear inside it.
    if (d.internal && !(r[1] > r[0]))
      m.Fail(d.radius_mark[1], "gear pair '" + j.name + "' is internal, so '" + m.links[j.link_b].name +
                                   "' is the ring and its pitch radius must exceed '" + m.links[j.link_a].name +
                                   "''s (" + Text(r[1]) + " <= " + Text(r[0]) + "); swap the gears or the radii");
    // Each gear's axis: its revolute joint to the carrier, where it has one. Both axes at one
    // point of the carrier (coincident centres): no pair of pitch circles can mesh there.
    double axis[2][2];
    for (int i = 0; i < 2; ++i) {
      const int gear = i == 0 ? j.link_a : j.link_b;
      int found = -1;
      for (size_t k = 0; k < m.joints.size(); ++k) {
        const Joint& o = m.joints[k];
        if (o.type() == JointType::kRevolute && o.Joins(gear) && o.Joins(d.carrier)) found = static_cast<int>(k);
      }
      if (found < 0) return;
      const PointRef at = m.joints[found].End(d.carrier);
      const LinkPoint& p = m.links[at.link].points[at.point];
      axis[i][0] = ValueAtDefaults(m, p.x, p.mark, "x of " + m.PointName(at));
      axis[i][1] = ValueAtDefaults(m, p.y, p.mark, "y of " + m.PointName(at));
    }
    const double distance = std::hypot(axis[0][0] - axis[1][0], axis[0][1] - axis[1][1]);
    if (distance <= 1e-12 * std::max(1.0, r[0] + r[1]))
      m.Fail(j.mark, "gear pair '" + j.name + "': the axes of '" + m.links[j.link_a].name + "' and '" +
                         m.links[j.link_b].name + "' coincide on '" + m.links[d.carrier].name +
                         "' at the parameters' defaults, so their pitch circles (radii " + Text(r[0]) + " and " +
                         Text(r[1]) + ") cannot mesh; place the axes " + Text(d.internal ? r[1] - r[0] : r[0] + r[1]) +
                         " apart");
  }

  static std::string Text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }

  bool IsLowerPair() const override { return false; }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>&) const override {
    const Joint& j = m.joints[joint];
    const GearData& d = j.Data<GearData>();
    const GiNaC::ex tc = frames[d.carrier].theta;
    return {{d.radius[0] * (frames[j.link_a].theta - tc) + (d.internal ? -1 : 1) * d.radius[1] * (frames[j.link_b].theta - tc) -
                 d.phase,
             d.internal ? RowComponent::kInternalGearMesh : RowComponent::kGearMesh, false}};
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const GearData& d = j.Data<GearData>();
    std::ostringstream os;
    os << (d.internal ? "internal" : "external") << " gear pair " << m.links[j.link_a].name << " (r " << d.radius[0]
       << ") / " << m.links[j.link_b].name << " (r " << d.radius[1] << "), carrier " << m.links[d.carrier].name;
    return os.str();
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    return MeshComponents(m, j, "the centre of '" + m.links[j.link_a].name + "'");
  }

  // The row's gradient is minus the relative motion along t of gear 2's tooth at the pitch
  // point (both axes on the carrier): r1 d(th1 - thc) +- r2 d(th2 - thc) (Paul §5).
  bool Contact(
      const Model& m, const Joint& j, const ContactInput& in, JointReaction* r, std::string* why) const override {
    const GearData& d = j.Data<GearData>();
    Vec2 centre[2];
    for (int i = 0; i < 2; ++i) {
      const int gear = i == 0 ? j.link_a : j.link_b;
      const int axis = AxisJoint(m, gear, d.carrier);
      if (axis < 0) {
        *why = "gear '" + m.links[gear].name + "' of gear pair '" + j.name +
               "' has no revolute joint to the carrier '" + m.links[d.carrier].name +
               "' (its axis, where the tooth force's direction starts)";
        return false;
      }
      if (!in.in_tree[axis]) {
        *why = "the axis of gear '" + m.links[gear].name + "' (joint '" + m.joints[axis].name +
               "') closes a loop, so the mesh row's multiplier is not the tooth force alone; mechgen derives gear "
               "forces where both gears' axes place their links in the spanning tree";
        return false;
      }
      const PointRef at = m.joints[axis].End(gear);
      centre[i] = PointPosition(m, at, in.frames[gear]);
    }
    // The pitch point on gear 1's pitch circle, on the line of centres (beyond gear 1's centre
    // from the ring's for an internal pair).
    const GiNaC::ex dx = centre[1][0] - centre[0][0], dy = centre[1][1] - centre[0][1];
    const GiNaC::ex inv = (d.internal ? -1 : 1) * pow(dx * dx + dy * dy, GiNaC::numeric(-1, 2));
    const Vec2 e{dx * inv, dy * inv};
    MeshForce(e, {centre[0][0] + d.radius[0] * e[0], centre[0][1] + d.radius[0] * e[1]}, d.pressure_angle,
              in.multipliers.at(0), r);
    return true;
  }
};

}  // namespace

void MeshForce(const Vec2& e, const Vec2& pitch, const GiNaC::ex& pressure, const GiNaC::ex& lambda, JointReaction* r) {
  const Vec2 t{-e[1], e[0]};
  const GiNaC::ex separating = abs(lambda) * tan(pressure);
  r->F = {-lambda * t[0] + separating * e[0], -lambda * t[1] + separating * e[1]};
  r->at = pitch;
  r->M = 0;
  r->components = {r->F[0], r->F[1], abs(lambda) / cos(pressure), -lambda};
}

std::vector<ReactionComponent> MeshComponents(const Model& m, const Joint& j, const std::string& centre) {
  const std::string on = "tooth force of '" + m.links[j.link_a].name + "' on '" + m.links[j.link_b].name + "'";
  return {{"F_" + j.name + "_x", on + " at the pitch point, x"},
          {"F_" + j.name + "_y", on + " at the pitch point, y"},
          {"N_" + j.name, on + " along the line of action (>= 0; |T| / cos of the pressure angle)"},
          {"T_" + j.name, on + " along t: e turned +90 deg, e from " + centre +
                              " to the pitch point (the transmitted part; the separating part |T| tan of the "
                              "pressure angle acts along e)"}};
}

void CheckPressureAngle(const Model& m, const Joint& j, const GiNaC::ex& angle, const SourceMark& mark) {
  const double a = ValueAtDefaults(m, angle, mark.line ? mark : j.mark, "pressure_angle");
  if (!(a >= 0 && a < M_PI / 2))
    m.Fail(mark.line ? mark : j.mark, "joint '" + j.name +
                                          "': the pressure angle must be at least 0 and below 90 deg "
                                          "(20*deg is usual)");
}

int AxisJoint(const Model& m, int gear, int carrier) {
  auto pin = [&](int k, int a, int b) {
    const Joint& o = m.joints[k];
    return o.type() == JointType::kRevolute && o.Joins(a) && o.Joins(b) && a != b;
  };
  for (size_t k = 0; k < m.joints.size(); ++k)
    if (pin(static_cast<int>(k), gear, carrier)) return static_cast<int>(k);
  for (size_t k = 0; k < m.joints.size(); ++k) {
    const Joint& o = m.joints[k];
    if (o.type() != JointType::kRevolute || !o.Joins(gear)) continue;
    const int other = o.OtherLink(gear);
    for (size_t c = 0; c < m.joints.size(); ++c)
      if (pin(static_cast<int>(c), other, carrier)) return static_cast<int>(k);
  }
  return -1;
}

const JointKind& GearKind() {
  static const Gear kind;
  return kind;
}

}  // namespace mechgen
