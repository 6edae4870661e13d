// The joint kinds' registry and what they share. See joint_kind.h.
#include "joints/joint_kind.h"

#include <stdexcept>

namespace mechgen {

Vec2 Rotate(const GiNaC::ex& theta, const GiNaC::ex& x, const GiNaC::ex& y) {
  return {cos(theta) * x - sin(theta) * y, sin(theta) * x + cos(theta) * y};
}

Vec2 PointPosition(const Model& m, PointRef ref, const Frame& f) {
  const LinkPoint& p = m.links[ref.link].points[ref.point];
  const Vec2 r = Rotate(f.theta, p.x, p.y);
  return {f.x + r[0], f.y + r[1]};
}

Frame FrameThrough(const Model& m, PointRef child_point, const Vec2& w, const GiNaC::ex& child_theta) {
  Frame fc;
  fc.theta = child_theta;
  const LinkPoint& cp = m.links[child_point.link].points[child_point.point];
  const Vec2 r = Rotate(child_theta, cp.x, cp.y);
  fc.x = w[0] - r[0];
  fc.y = w[1] - r[1];
  return fc;
}

const char* ComponentText(RowComponent c) {
  switch (c) {
    case RowComponent::kX: return "x";
    case RowComponent::kY: return "y";
    case RowComponent::kNoSlip: return "no slip";
    case RowComponent::kGearMesh: return "gear mesh";
    case RowComponent::kInternalGearMesh: return "internal gear mesh";
    case RowComponent::kRackMesh: return "rack mesh";
    case RowComponent::kCamLaw: return "cam law";
    case RowComponent::kContourX: return "contour contact, x";
    case RowComponent::kContourY: return "contour contact, y";
    case RowComponent::kFaceContact: return "contact on the face";
    case RowComponent::kFaceTangent: return "face tangent to the contour";
  }
  return "";
}

void JointKind::Resolve(SectionReader&, int) const {}

void JointKind::Check(const Model&, const Joint&) const {}

std::optional<JointCoordinate> JointKind::Coordinate(const Model&, const Joint&) const { return std::nullopt; }

Vec2 JointKind::ReactionPoint(const Model& m,
                              const Joint& j,
                              const std::vector<Frame>& frames,
                              const GiNaC::ex&) const {
  const PointRef p = j.End(j.link_b);
  return PointPosition(m, p, frames[p.link]);
}

bool JointKind::Contact(const Model&, const Joint& j, const ContactInput&, JointReaction*, std::string*) const {
  throw std::logic_error("mechgen bug: joint '" + j.name + "' is not a higher pair");
}

std::vector<GiNaC::ex> JointKind::Reaction(
    const Model&, const Joint& j, const std::vector<Frame>&, const JointReaction& r, std::string*) const {
  // A higher pair: the components its Contact() made.
  if (r.components.empty()) throw std::logic_error("mechgen bug: joint '" + j.name + "' has no contact components");
  return r.components;
}

GiNaC::ex JointKind::RelativeMotion(const Model&, const Joint& j, const std::vector<Frame>&, const GiNaC::ex&) const {
  throw std::logic_error("mechgen bug: friction at joint '" + j.name + "', whose kind models none");
}

JointFriction JointKind::CoulombFriction(const Model&, const Joint& j, const mechgen::Friction&,
                                         const std::vector<Frame>&, const JointReaction&) const {
  throw std::logic_error("mechgen bug: friction at joint '" + j.name + "', whose kind models none");
}

Frame JointKind::PlaceChild(const Model&, const Joint& j, int, const Frame&, const GiNaC::ex&,
                            const GiNaC::ex&) const {
  throw std::logic_error("mechgen bug: joint '" + j.name + "' is a higher pair and cannot place a link");
}

const std::vector<const JointKind*>& JointKinds() {
  // In JointType order; a new kind is registered here.
  static const std::vector<const JointKind*> kinds = {&RevoluteKind(), &PrismaticKind(), &RollKind(), &GearKind(),
                                                      &RackKind(),     &CamKind(),       &SlotKind()};
  return kinds;
}

const JointKind& KindOf(JointType type) { return *JointKinds()[static_cast<size_t>(type)]; }

const JointKind* FindKind(const std::string& key) {
  for (const JointKind* k : JointKinds())
    if (key == k->Keys().section) return k;
  return nullptr;
}

}  // namespace mechgen
