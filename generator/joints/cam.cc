// Disk cam and follower (Paul §1.4). The follower is held by its own joint to the carrier
// (prismatic: translating, revolute: oscillating); the cam turns on a revolute joint to the
// same carrier. The profile is given by the follower's law (segments of dwell, rise and
// return) or by the cam's contour (expressions in u, or a periodic spline through points).
//   coordinate:  none (law), or u_<joint>, the contact parameter on the contour
//   cut joint:   law: y_follower - start - law(th_cam - th_carrier - phase) = 0, one row;
//                contour: the roller's centre on the contour's offset (x, y), or the
//                contact point on the face and the face tangent to the contour (two rows)
//   reaction:    the contact force of the cam on the follower, F_x, F_y, and N along the
//                profile's outward normal (a flat face: along the face's normal), from the
//                rows' multipliers (Contact below)
// The law's and the contour's maths (segments, pressure angle, curvature, spline) are in
// generator/cam.{h,cc}.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "joints/cam_profile.h"
#include "joints/joint_kind.h"
#include "model/expression_functions.h"

namespace mechgen {

const KeyTable& LawSegmentKeys() {
  static const KeyTable table{"law segment",
                              {{"dwell", "cam angle of a dwell (positive; one of dwell, rise, return)", false},
                               {"rise", "cam angle of a rise (positive)", false},
                               {"return", "cam angle of a return (positive)", false},
                               {"lift", "the rise's or return's travel (not for a dwell)", false},
                               {"motion", "cycloidal, harmonic or poly345 (not for a dwell)", false}}};
  return table;
}

const KeyTable& ContourKeys() {
  static const KeyTable table{"contour",
                              {{"x", "x(u) in the cam's frame (with y)", false},
                               {"y", "y(u) in the cam's frame (with x)", false},
                               {"period", "u's range (default 2 pi; with x and y)", false},
                               {"points", "[[x, y], ...]: a periodic cubic spline, counter-clockwise (instead of x, y)",
                                false}}};
  return table;
}

namespace {

// A cam's contour: {x: <x(u)>, y: <y(u)>, period: <u's range, default 2 pi>} in the
// cam's frame, or {points: [[x, y], ...]} (a periodic cubic spline, counter-clockwise).
void ReadContour(SectionReader& r, const YAML::Node& node, const std::string& name, CamData* c) {
  c->contour_mark = MarkOf(node);
  const std::string what = "contour of cam '" + name + "'";
  bool has_x = false, has_y = false, has_points = false, has_period = false;
  for (const auto& [key, value] : r.Entries(node, what, &ContourKeys())) {
    if (key == "x") c->contour_x = r.Expression(value, what + ", x", &c->contour_u), has_x = true;
    if (key == "y") c->contour_y = r.Expression(value, what + ", y", &c->contour_u), has_y = true;
    if (key == "period") {
      c->contour_period = r.Expression(value, what + ", period");
      c->period_mark = MarkOf(value);
      has_period = true;
    }
    if (key == "points") {
      if (!value.IsSequence())
        r.Fail(value, what + ": points must be a list of [x, y] pairs, counter-clockwise around the cam's pivot");
      for (const YAML::Node& pt : value) {
        if (!pt.IsSequence() || pt.size() != 2) r.Fail(pt, what + ": each point must be a pair [x, y]");
        c->contour_points.push_back({r.Number(pt[0], what + ", x"), r.Number(pt[1], what + ", y")});
        c->contour_point_marks.push_back(MarkOf(pt));
      }
      has_points = true;
    }
  }
  if (has_points) {
    if (has_x || has_y || has_period)
      r.Fail(node, what + ": give either points: [[x, y], ...] or the expressions x: and y: (with period:), not both");
    c->contour = CamData::Contour::kSpline;
    return;
  }
  if (!has_x || !has_y)
    r.Fail(node, what + " needs x: and y: (expressions in the contour parameter u and the parameters) or points:");
  if (!has_period) c->contour_period = 2 * GiNaC::Pi;
  c->contour_text = "x(u) = " + r.Scalar(node["x"], what) + ", y(u) = " + r.Scalar(node["y"], what);
  c->contour = CamData::Contour::kExpressions;
}

// The cam's follower law: a list of {dwell: angle} / {rise|return: angle, lift: h,
// motion: cycloidal|harmonic|poly345}.
std::vector<CamSegment> ReadLaw(SectionReader& r, const YAML::Node& node, const std::string& joint) {
  if (!node.IsSequence() || node.size() == 0)
    r.Fail(node, "law of cam '" + joint + "' must be a list of segments: - {dwell: 90*deg} "
                 "- {rise: 120*deg, lift: h, motion: cycloidal} ...");
  std::vector<CamSegment> out;
  for (const auto& item : node) {
    CamSegment seg;
    seg.mark = MarkOf(item);
    bool has_lift = false, has_kind = false;
    for (const auto& [key, value] : r.Entries(item, "law segment", &LawSegmentKeys())) {
      if (key == "dwell" || key == "rise" || key == "return") {
        if (has_kind) r.Fail(value, "a law segment is one of dwell, rise or return, not two");
        has_kind = true;
        seg.kind = key == "dwell"  ? CamSegment::Kind::kDwell
                   : key == "rise" ? CamSegment::Kind::kRise
                                   : CamSegment::Kind::kReturn;
        seg.duration = r.Expression(value, key + " angle");
        seg.duration_mark = MarkOf(value);
      } else if (key == "lift") {
        seg.lift = r.Expression(value, "lift");
        has_lift = true;
      } else {
        const std::string mo = r.Scalar(value, "motion");
        if (mo == "cycloidal") seg.motion = CamSegment::Motion::kCycloidal;
        else if (mo == "harmonic") seg.motion = CamSegment::Motion::kHarmonic;
        else if (mo == "poly345") seg.motion = CamSegment::Motion::kPoly345;
        else r.Fail(value, "unknown motion '" + mo + "'; use cycloidal, harmonic or poly345");
      }
    }
    if (!has_kind) r.Fail(item, "a law segment needs dwell:, rise: or return: with its cam angle");
    if (seg.kind == CamSegment::Kind::kDwell) {
      if (has_lift || seg.motion != CamSegment::Motion::kNone)
        r.Fail(item, "a dwell has no lift and no motion; give only {dwell: angle}");
    } else {
      if (!has_lift) r.Fail(item, "a rise or return needs lift: (the follower's travel)");
      if (seg.motion == CamSegment::Motion::kNone)
        r.Fail(item, "a rise or return needs motion: cycloidal, harmonic or poly345");
    }
    out.push_back(seg);
  }
  return out;
}

const char* SegmentKey(CamSegment::Kind k) {
  return k == CamSegment::Kind::kDwell ? "dwell" : k == CamSegment::Kind::kRise ? "rise" : "return";
}

class Cam : public JointKind {
 public:
  JointType type() const override { return JointType::kCam; }

  const KeyTable& Keys() const override {
    static const KeyTable table{
        "cam",
        {{"cam", "the cam link (it needs a revolute joint to the follower's carrier)", true},
         {"follower", "the follower's joint to the carrier: prismatic (translating) or revolute (oscillating)", true},
         {"point", "follower.P: the roller's centre, the knife-edge's tip, or a point of the flat face", true},
         {"roller", "roller radius (default 0: knife-edge; not with face)", false},
         {"face", "a flat face through `point` at this angle in the follower's frame (not with roller)", false},
         {"start", "the follower coordinate at zero lift (with law)", false},
         {"phase", "cam angle (relative to the carrier) where the law starts (default 0)", false},
         {"law", "the follower's law: a list of segments (with start; or contour)", false},
         {"contour", "the cam's profile in its frame (instead of start and law)", false}}};
    return table;
  }

  void Read(SectionReader& r, const YAML::Node& body, Joint* j) const override {
    const std::string& name = j->name;
    CamData c;
    bool has_cam = false, has_follower = false, has_point = false, has_start = false, has_law = false;
    bool has_roller = false, has_face = false;
    for (const auto& [key, value] : r.Entries(body, "cam '" + name + "'", &Keys())) {
      if (key == "cam") j->link_a = r.LinkIndex(value, "joint '" + name + "'"), has_cam = true;
      if (key == "follower")
        c.follower_name = r.Scalar(value, "follower"), c.follower_mark = MarkOf(value), has_follower = true;
      if (key == "point") c.point = r.Point(value, "point of '" + name + "'"), has_point = true;
      if (key == "roller") {
        c.roller = r.Expression(value, "roller radius");
        c.roller_mark = MarkOf(value);
        has_roller = true;
      }
      if (key == "face") c.face_angle = r.Expression(value, "face angle"), c.flat_face = has_face = true;
      if (key == "start") c.start = r.Expression(value, "start of '" + name + "'"), has_start = true;
      if (key == "phase") c.phase = r.Expression(value, "phase of '" + name + "'");
      if (key == "law") c.law = ReadLaw(r, value, name), c.law_mark = MarkOf(value), has_law = true;
      if (key == "contour") ReadContour(r, value, name, &c);
    }
    if (c.contour != CamData::Contour::kNone) {
      if (has_law || has_start)
        r.Fail(body, "cam '" + name + "': a cam is given either by its follower's law (start:, law:) or by its "
                     "contour (contour:), not both");
      has_law = has_start = true;
    }
    if (!has_cam || !has_follower || !has_point || !has_start || !has_law)
      r.Fail(body, "cam '" + name + "' needs cam: <cam link>, follower: <the follower's joint to the carrier>, "
                   "point: follower.P (roller centre, knife tip or a point of the face), start: <follower "
                   "coordinate at zero lift> and law: [segments]");
    if (has_roller && has_face)
      r.Fail(body, "cam '" + name + "': a follower is either a roller (roller: r) or flat-faced (face: angle)");
    int cams = 0;
    for (const Joint& o : r.model().joints) cams += o.type() == JointType::kCam;
    c.index = cams;
    j->link_b = c.point.link;
    j->data = c;
  }

  void Resolve(SectionReader& r, int joint) const override {
    Model& m = r.model();
    Joint& j = m.joints[joint];
    CamData& c = j.Data<CamData>();
    c.follower_joint = m.FindJoint(c.follower_name);
    if (c.follower_joint < 0) m.Fail(c.follower_mark, "joint '" + j.name + "': unknown joint '" + c.follower_name + "'");
    const Joint& o = m.joints[c.follower_joint];
    // The follower's joint to the carrier.
    const int f = c.point.link;
    if (o.type() == JointType::kPrismatic) {
      if (o.link_b != f)
        m.Fail(c.follower_mark, "cam '" + j.name + "': the follower '" + m.links[f].name + "' must be the slider of '" +
                                    o.name + "' (a translating follower)");
      c.carrier = o.link_a;
    } else if (o.type() == JointType::kRevolute) {
      if (!o.Joins(f))
        m.Fail(c.follower_mark, "cam '" + j.name + "': joint '" + o.name + "' does not hold the follower '" +
                                    m.links[f].name + "' (an oscillating follower's pivot)");
      c.carrier = o.OtherLink(f);
    } else {
      m.Fail(c.follower_mark, "cam '" + j.name + "': follower must name a prismatic joint (translating follower) or a "
                              "revolute joint (oscillating follower)");
    }
    if (c.carrier == j.link_a)
      m.Fail(c.follower_mark,
             "cam '" + j.name + "': the follower's joint must attach it to the link carrying the cam, not the cam");
    for (size_t k = 0; k < m.joints.size(); ++k) {
      const Joint& p = m.joints[k];
      if (p.type() == JointType::kRevolute && p.Joins(j.link_a) && p.Joins(c.carrier)) c.pivot = static_cast<int>(k);
    }
    if (c.pivot < 0)
      m.Fail(c.follower_mark, "cam '" + j.name + "': the cam '" + m.links[j.link_a].name +
                                  "' needs a revolute joint to the follower's carrier '" + m.links[c.carrier].name + "'");
  }

  void Check(const Model& m, const Joint& j) const override {
    const CamData& c = j.Data<CamData>();
    if (!(ValueAtDefaults(m, c.roller, c.roller_mark, "roller radius") >= 0))
      m.Fail(c.roller_mark, "the roller radius must not be negative");
    for (const CamSegment& s : c.law) {
      const std::string key = SegmentKey(s.kind);
      if (!(ValueAtDefaults(m, s.duration, s.duration_mark, key + " angle") > 0))
        m.Fail(s.duration_mark, key + " angle must be positive (a cam angle such as 90*deg)");
    }
    // An oscillating follower: its pivot must not be the cam's axis (the follower point would
    // keep one distance from the cam's centre: no profile could lift it), and a roller's or
    // knife-edge's point must not be its pivot (turning the follower would not move it).
    const Joint& o = m.joints[c.follower_joint];
    if (o.type() == JointType::kRevolute && c.pivot >= 0) {
      auto at = [&](PointRef r, double* x, double* y) {
        const LinkPoint& p = m.links[r.link].points[r.point];
        *x = ValueAtDefaults(m, p.x, p.mark, "x of " + m.PointName(r));
        *y = ValueAtDefaults(m, p.y, p.mark, "y of " + m.PointName(r));
      };
      double px, py, cx, cy, fx, fy, tx, ty;
      at(o.End(c.carrier), &px, &py);
      at(m.joints[c.pivot].End(c.carrier), &cx, &cy);
      at(o.End(c.point.link), &fx, &fy);
      at(c.point, &tx, &ty);
      const double scale = std::max({1.0, std::abs(px), std::abs(py), std::abs(cx), std::abs(cy)});
      if (std::hypot(px - cx, py - cy) <= 1e-12 * scale)
        m.Fail(c.follower_mark, "cam '" + j.name + "': the follower's pivot (joint '" + o.name +
                                    "') is the cam's axis (joint '" + m.joints[c.pivot].name +
                                    "') at the parameters' defaults, so the follower point keeps one distance from "
                                    "the cam's centre and no profile can move it; pivot the follower elsewhere");
      // (A flat face may pass through its pivot: its point only names the face's line.)
      if (!c.flat_face && std::hypot(fx - tx, fy - ty) <= 1e-12 * std::max({1.0, std::abs(fx), std::abs(fy)}))
        m.Fail(c.follower_mark, "cam '" + j.name + "': the follower point " + m.PointName(c.point) +
                                    " is the follower's pivot (joint '" + o.name +
                                    "') at the parameters' defaults, so turning the follower does not move it; "
                                    "give the follower arm a length");
    }
    if (c.contour == CamData::Contour::kExpressions) {  // (the default period, 2 pi, passes)
      const std::string what = "contour of cam '" + j.name + "'";
      if (!(ValueAtDefaults(m, c.contour_period, c.period_mark, what + ", period") > 0))
        m.Fail(c.period_mark, what + ": the period must be positive");
    }
  }

  bool IsLowerPair() const override { return false; }

  std::optional<JointCoordinate> Coordinate(const Model& m, const Joint& j) const override {
    const CamData& c = j.Data<CamData>();
    if (c.contour == CamData::Contour::kNone) return std::nullopt;
    return JointCoordinate{"u_" + j.name,
                           "contact parameter of cam '" + j.name + "' on the contour of '" + m.links[j.link_a].name +
                               "'" +
                               (c.contour == CamData::Contour::kSpline ? " (chord length along the spline)"
                                                                       : " (u of x(u), y(u))"),
                           "u_{\\mathrm{" + j.name + "}}", false};
  }

  std::vector<JointEquation> Equations(const Model& m, int joint, bool, const std::vector<Frame>& frames,
                                       const std::vector<GiNaC::ex>& var) const override {
    const Joint& j = m.joints[joint];
    const CamData& c = j.Data<CamData>();
    const Frame& fa = frames[j.link_a];
    const Frame& fb = frames[j.link_b];
    const GiNaC::ex& s = var[joint];
    if (c.contour != CamData::Contour::kNone) {
      // Contour cam (Paul §1.4.3), contact parameter u = s: the contour point X(u) and
      // tangent T(u) (cam's frame), turned by the cam's angle.
      const Vec2 X = ContourPoint(j, s, 0), T = ContourPoint(j, s, 1);
      const Vec2 P = PointPosition(m, c.point, fb);
      if (!c.flat_face) {
        // Roller centre P = cam origin + R(th_cam) (X + rho n), n = (T_y, -T_x) / |T|:
        // the outward normal of a counter-clockwise contour.
        const GiNaC::ex inv = pow(T[0] * T[0] + T[1] * T[1], GiNaC::numeric(-1, 2));
        const Vec2 w = Rotate(fa.theta, X[0] + c.roller * T[1] * inv, X[1] - c.roller * T[0] * inv);
        return {{fa.x + w[0] - P[0], RowComponent::kContourX, false}, {fa.y + w[1] - P[1], RowComponent::kContourY, false}};
      }
      // Flat face through P at face_angle in the follower's frame (normal nf): the
      // contact point on it, the contour's tangent along it.
      const GiNaC::ex a = fb.theta + c.face_angle;
      const Vec2 Xw = Rotate(fa.theta, X[0], X[1]), Tw = Rotate(fa.theta, T[0], T[1]);
      return {{-sin(a) * (fa.x + Xw[0] - P[0]) + cos(a) * (fa.y + Xw[1] - P[1]), RowComponent::kFaceContact, false},
              {-sin(a) * Tw[0] + cos(a) * Tw[1], RowComponent::kFaceTangent, false}};
    }
    // y_follower - start - law(th_cam - th_carrier - phase) = 0
    const Joint& fj = m.joints[c.follower_joint];
    const GiNaC::ex tc = frames[c.carrier].theta;
    const GiNaC::ex y = fj.type() == JointType::kPrismatic ? var[c.follower_joint] : fb.theta - tc;
    return {{y - c.start - camlaw(c.index, 0, fa.theta - tc - c.phase), RowComponent::kCamLaw, false}};
  }

  std::string Describe(const Model& m, const Joint& j) const override {
    const CamData& c = j.Data<CamData>();
    return "cam " + m.links[j.link_a].name + ", follower " + m.links[j.link_b].name + " on '" +
           m.joints[c.follower_joint].name + "'";
  }

  std::vector<ReactionComponent> ReactionComponents(const Model& m, const Joint& j) const override {
    const CamData& c = j.Data<CamData>();
    const std::string on = "contact force of '" + m.links[j.link_a].name + "' on '" + m.links[j.link_b].name + "'";
    const std::string where =
        c.flat_face ? " (its line through the contact point)" : " (its line through " + m.PointName(c.point) + ")";
    return {{"F_" + j.name + "_x", on + where + ", x"},
            {"F_" + j.name + "_y", on + ", y"},
            {"N_" + j.name, on + " along the profile's outward normal (> 0: the cam pushes the follower)"}};
  }

  // The contact force F on the follower at a point P of it (a couple M on it where the force's
  // line misses P) does the virtual work of the rows' multipliers over every motion of the cam
  // and the follower (Paul §5). Contour: the rows are a point of the cam (the roller's centre
  // on the offset contour, or the contact point) against the follower's, so F = -lambda.
  // Law, y the follower's coordinate (slide or angle relative to the carrier), psi the cam's
  // angle relative to the carrier, L' = dlaw/dpsi, v = dP/dy, d = P - cam axis:
  //   F.v + [y is an angle] M = lambda,   d x F + M = lambda L'
  // with M = 0 (roller, knife edge: F along the pitch curve's normal w = L' (k x v) + d, so
  // F = lambda w / (w.v)) or F = f n_face (flat face).
  bool Contact(
      const Model& m, const Joint& j, const ContactInput& in, JointReaction* r, std::string* why) const override {
    const CamData& c = j.Data<CamData>();
    const int joint = static_cast<int>(&j - m.joints.data());
    const Frame& fa = in.frames[j.link_a];
    const Frame& fb = in.frames[j.link_b];
    const GiNaC::ex face = fb.theta + c.face_angle;
    const Vec2 n_face{-sin(face), cos(face)};
    auto dot = [](const Vec2& a, const Vec2& b) { return a[0] * b[0] + a[1] * b[1]; };
    auto cross = [](const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; };
    const Vec2 P = PointPosition(m, c.point, fb);
    if (c.contour != CamData::Contour::kNone) {
      const GiNaC::ex& u = in.var[joint];
      const Vec2 X = ContourPoint(j, u, 0), T = ContourPoint(j, u, 1);
      if (!c.flat_face) {  // rows: the offset contour's point - P
        const GiNaC::ex inv = pow(T[0] * T[0] + T[1] * T[1], GiNaC::numeric(-1, 2));
        const Vec2 n = Rotate(fa.theta, T[1] * inv, -T[0] * inv);
        r->F = {-in.multipliers.at(0), -in.multipliers.at(1)};
        r->at = P;
        r->components = {r->F[0], r->F[1], dot(r->F, n)};
      } else {  // first row: n_face . (contact point - P); the second (tangency) carries no force
        const Vec2 x = Rotate(fa.theta, X[0], X[1]);
        r->F = {-in.multipliers.at(0) * n_face[0], -in.multipliers.at(0) * n_face[1]};
        r->at = {fa.x + x[0], fa.y + x[1]};
        r->components = {r->F[0], r->F[1], -in.multipliers.at(0) * msign(dot(x, n_face))};
      }
      r->M = 0;
      return true;
    }
    for (int k : {c.pivot, c.follower_joint})
      if (!in.in_tree[k]) {
        *why = "joint '" + m.joints[k].name +
               "' (the cam's pivot or the follower's joint) closes a loop, so the "
               "law's row's multiplier is not the contact force alone; mechgen derives a law cam's force where both "
               "place their links in the spanning tree";
        return false;
      }
    const GiNaC::ex lambda = in.multipliers.at(0);
    const Vec2 O = PointPosition(m, m.joints[c.pivot].End(j.link_a), fa);
    const Vec2 d{P[0] - O[0], P[1] - O[1]};
    const GiNaC::ex L1 = camlaw(c.index, 1, fa.theta - in.frames[c.carrier].theta - c.phase);
    const Joint& o = m.joints[c.follower_joint];
    Vec2 v;
    int turns = 0;  // 1: the follower turns with y
    if (o.type() == JointType::kPrismatic) {
      v = LineDirection(o.Data<PrismaticData>(), in.frames[o.link_a].theta);
    } else {
      const Vec2 pivot = PointPosition(m, o.End(j.link_b), fb);
      v = {-(P[1] - pivot[1]), P[0] - pivot[0]};
      turns = 1;
    }
    if (!c.flat_face) {
      const Vec2 w{-L1 * v[1] + d[0], L1 * v[0] + d[1]};
      const GiNaC::ex k = lambda / dot(w, v);
      r->F = {k * w[0], k * w[1]};
      r->M = 0;
      r->components = {r->F[0], r->F[1], k * sqrt(dot(w, w))};
    } else {
      const GiNaC::ex f = lambda * (1 - turns * L1) / (dot(n_face, v) - turns * cross(d, n_face));
      r->F = {f * n_face[0], f * n_face[1]};
      r->M = lambda * L1 - cross(d, r->F);
      // The cam lies on the side of the face its axis is on: the outward normal is -+ n_face.
      r->components = {r->F[0], r->F[1], f * msign(dot(d, n_face))};
    }
    r->at = P;
    return true;
  }
};

}  // namespace

const JointKind& CamKind() {
  static const Cam kind;
  return kind;
}

}  // namespace mechgen
