// Joint equations. See joints.h.
#include "joints.h"

namespace mechgen {
namespace {

Vec2 Rotate(const GiNaC::ex& theta, const GiNaC::ex& x, const GiNaC::ex& y) {
  return {cos(theta) * x - sin(theta) * y, sin(theta) * x + cos(theta) * y};
}

// Direction of a prismatic joint's line: angle in the guide link's frame + its theta.
Vec2 LineDirection(const Joint& j, const Frame& guide) {
  return {cos(guide.theta + j.angle), sin(guide.theta + j.angle)};
}

}  // namespace

Vec2 PointPosition(const Model& m, PointRef ref, const Frame& f) {
  const LinkPoint& p = m.links[ref.link].points[ref.point];
  const Vec2 r = Rotate(f.theta, p.x, p.y);
  return {f.x + r[0], f.y + r[1]};
}

Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp,
                 const GiNaC::ex& child_theta, const GiNaC::ex& s) {
  const bool child_is_b = j.a.link == parent;
  const PointRef pref = child_is_b ? j.a : j.b, cref = child_is_b ? j.b : j.a;
  Frame fc;
  fc.theta = child_theta;
  // World position the child's joint point must take.
  Vec2 w = PointPosition(m, pref, fp);
  if (j.type == JointType::kPrismatic) {
    // Slider point b = guide point a + s u, with u along the line of the guide link.
    if (child_is_b) {  // parent guides, child slides
      const Vec2 u = LineDirection(j, fp);
      w = {w[0] + s * u[0], w[1] + s * u[1]};
    } else {  // parent slides, child guides: a = b - s u(theta_child)
      Frame guide;
      guide.theta = child_theta;
      const Vec2 u = LineDirection(j, guide);
      w = {w[0] - s * u[0], w[1] - s * u[1]};
    }
  }
  const LinkPoint& cp = m.links[cref.link].points[cref.point];
  const Vec2 r = Rotate(child_theta, cp.x, cp.y);
  fc.x = w[0] - r[0];
  fc.y = w[1] - r[1];
  return fc;
}

std::vector<GiNaC::ex> ClosureEquations(const Model& m, const Joint& j, const Frame& fa,
                                        const Frame& fb, const GiNaC::ex& s) {
  const Vec2 ra = PointPosition(m, j.a, fa), rb = PointPosition(m, j.b, fb);
  switch (j.type) {
    case JointType::kRevolute:  // r_a - r_b = 0
      return {ra[0] - rb[0], ra[1] - rb[1]};
    case JointType::kPrismatic: {  // r_a + s u - r_b = 0
      const Vec2 u = LineDirection(j, fa);
      return {ra[0] + s * u[0] - rb[0], ra[1] + s * u[1] - rb[1]};
    }
  }
  return {};
}

}  // namespace mechgen
