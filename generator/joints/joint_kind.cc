// Joint equations. See joints.h.
#include "joints.h"

#include "cam.h"

namespace mechgen {
namespace {

Vec2 Rotate(const GiNaC::ex& theta, const GiNaC::ex& x, const GiNaC::ex& y) {
  return {cos(theta) * x - sin(theta) * y, sin(theta) * x + cos(theta) * y};
}

// Direction of a prismatic joint's line: angle in the guide link's frame + its theta.
Vec2 LineDirection(const Joint& j, const Frame& guide) {
  return {cos(guide.theta + j.angle), sin(guide.theta + j.angle)};
}

// Rolling joint geometry on the base link (frame `base`, contact parameter v): the unit
// vector e from the base point toward the wheel's centre and the centre's distance from
// the base point along it, on top of the contact point's offset.
//   line:   contact Q = G + v u, centre C = Q + r n (n: u turned +90 deg, the wheel's side)
//   circle: contact Q = O + R e(theta_b + v), centre C = O + (R +- r) e(theta_b + v)
Vec2 RollCentreOffset(const Joint& j, const GiNaC::ex& theta_base, const GiNaC::ex& v) {
  if (j.on_line) {
    const GiNaC::ex a = theta_base + j.angle;
    return {v * cos(a) - j.radius * sin(a), v * sin(a) + j.radius * cos(a)};
  }
  const GiNaC::ex d = j.internal ? j.radius2 - j.radius : j.radius2 + j.radius;
  return {d * cos(theta_base + v), d * sin(theta_base + v)};
}

}  // namespace

Vec2 ContactPosition(const Model& m, const Joint& j, const Frame& base, const GiNaC::ex& v) {
  const Vec2 a = PointPosition(m, j.a, base);
  if (j.on_line) {
    const GiNaC::ex ang = base.theta + j.angle;
    return {a[0] + v * cos(ang), a[1] + v * sin(ang)};
  }
  return {a[0] + j.radius2 * cos(base.theta + v), a[1] + j.radius2 * sin(base.theta + v)};
}

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
  if (j.type == JointType::kRoll) {
    if (child_is_b) {  // parent is the base: the wheel's centre is placed on it
      const Vec2 d = RollCentreOffset(j, fp.theta, s);
      w = {w[0] + d[0], w[1] + d[1]};
    } else {  // parent is the wheel: the base point lies back from the centre
      const Vec2 d = RollCentreOffset(j, child_theta, s);
      w = {w[0] - d[0], w[1] - d[1]};
    }
  }
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

std::vector<JointEquation> JointEquations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                          const std::vector<GiNaC::ex>& var) {
  const Joint& j = m.joints[joint];
  const Frame& fa = frames[j.a.link];
  const Frame& fb = frames[j.b.link];
  const GiNaC::ex& s = var[joint];
  std::vector<JointEquation> rows;
  auto pair = [&](const Vec2& d) {
    rows.push_back({d[0], "x", true});
    rows.push_back({d[1], "y", true});
  };
  switch (j.type) {
    case JointType::kRevolute: {  // r_a - r_b = 0
      const Vec2 ra = PointPosition(m, j.a, fa), rb = PointPosition(m, j.b, fb);
      if (cut) pair({ra[0] - rb[0], ra[1] - rb[1]});
      break;
    }
    case JointType::kPrismatic: {  // r_a + s u - r_b = 0
      const Vec2 ra = PointPosition(m, j.a, fa), rb = PointPosition(m, j.b, fb);
      const Vec2 u = LineDirection(j, fa);
      if (cut) pair({ra[0] + s * u[0] - rb[0], ra[1] + s * u[1] - rb[1]});
      break;
    }
    case JointType::kRoll: {
      // Contact: the wheel's centre on its line or circle (r_a + d(v) - r_b = 0).
      if (cut) {
        const Vec2 ra = PointPosition(m, j.a, fa), rb = PointPosition(m, j.b, fb);
        const Vec2 d = RollCentreOffset(j, fa.theta, s);
        pair({ra[0] + d[0] - rb[0], ra[1] + d[1] - rb[1]});
      }
      // No slip: equal arc lengths on both contours since phase. Line: the contact runs
      // v = phase - r (theta_w - theta_b). Circle of radius R, contact angle psi (in the
      // base's frame): R psi +- r (psi + theta_b - theta_w) = phase (+ outside, - inside).
      const GiNaC::ex rel = fb.theta - fa.theta;
      if (j.on_line)
        rows.push_back({s + j.radius * rel - j.phase, "no slip", false});
      else
        rows.push_back({j.radius2 * s + (j.internal ? -1 : 1) * j.radius * (s - rel) - j.phase, "no slip", false});
      break;
    }
    case JointType::kGear: {  // r1 (th1 - thc) +- r2 (th2 - thc) = phase
      const GiNaC::ex tc = frames[j.carrier].theta;
      rows.push_back({j.radius * (fa.theta - tc) + (j.internal ? -1 : 1) * j.radius2 * (fb.theta - tc) - j.phase,
                      j.internal ? "internal gear mesh" : "gear mesh", false});
      break;
    }
    case JointType::kRack:  // s + r (th_pinion - th_guide) = phase
      rows.push_back({var[j.other_joint] + j.radius * (fa.theta - frames[j.carrier].theta) - j.phase,
                      "rack mesh", false});
      break;
    case JointType::kCam: {  // y_follower - start - law(th_cam - th_carrier - phase) = 0
      if (j.contour != Joint::Contour::kNone) {
        // Contour cam (Paul §1.4.3), contact parameter u = s: the contour point X(u) and
        // tangent T(u) (cam's frame), turned by the cam's angle.
        const Vec2 X = ContourPoint(j, s, 0), T = ContourPoint(j, s, 1);
        const Vec2 P = PointPosition(m, j.follower_point, fb);
        if (!j.flat_face) {
          // Roller centre P = cam origin + R(th_cam) (X + rho n), n = (T_y, -T_x) / |T|:
          // the outward normal of a counter-clockwise contour.
          const GiNaC::ex inv = pow(T[0] * T[0] + T[1] * T[1], GiNaC::numeric(-1, 2));
          const Vec2 c = Rotate(fa.theta, X[0] + j.roller * T[1] * inv, X[1] - j.roller * T[0] * inv);
          rows.push_back({fa.x + c[0] - P[0], "contour contact, x", false});
          rows.push_back({fa.y + c[1] - P[1], "contour contact, y", false});
        } else {
          // Flat face through P at face_angle in the follower's frame (normal nf): the
          // contact point on it, the contour's tangent along it.
          const GiNaC::ex a = fb.theta + j.face_angle;
          const Vec2 Xw = Rotate(fa.theta, X[0], X[1]), Tw = Rotate(fa.theta, T[0], T[1]);
          rows.push_back({-sin(a) * (fa.x + Xw[0] - P[0]) + cos(a) * (fa.y + Xw[1] - P[1]), "contact on the face", false});
          rows.push_back({-sin(a) * Tw[0] + cos(a) * Tw[1], "face tangent to the contour", false});
        }
        break;
      }
      const Joint& fj = m.joints[j.other_joint];
      const GiNaC::ex tc = frames[j.carrier].theta;
      const GiNaC::ex y = fj.type == JointType::kPrismatic ? var[j.other_joint] : fb.theta - tc;
      rows.push_back({y - j.start - camlaw(j.cam_index, 0, fa.theta - tc - j.phase), "cam law", false});
      break;
    }
  }
  // Products of sums (r1 (th1 - thc)) print with a sign GiNaC picks by its run-dependent
  // term order: the header's equation text must be the same on every run.
  for (JointEquation& r : rows)
    if (!r.pair) r.value = r.value.expand();
  return rows;
}

}  // namespace mechgen
