// Coordinates, frames, closure equations and points. See kinematics.h.
#include "analysis/kinematics.h"

#include <map>

#include "analysis/validate.h"

namespace mechgen {

std::string RowSource::Text(const Model& m) const {
  if (joint < 0) {
    const Input& in = m.inputs[input];
    return "input " + PointInputName(m, in) + ", drive of " + m.PointName(in.point) + ", " + ComponentText(component);
  }
  return (loop >= 0 ? "loop " + std::to_string(loop + 1) + ", " : std::string()) + "joint " + m.joints[joint].name +
         ", " + ComponentText(component);
}

int InputCoordinate(const Model& m, const Topology& t, const CoordinateTable& table, const Input& in) {
  switch (in.kind) {
    case Input::Kind::kAngle:
      return table.of_group[t.group[in.link]];
    case Input::Kind::kPointX:
    case Input::Kind::kPointY:
      return -1;
    case Input::Kind::kJoint:
      break;
  }
  const Joint& j = m.joints[in.joint];
  if (j.type() == JointType::kPrismatic || j.type() == JointType::kSlot) return table.of_joint[in.joint];
  const int moving = j.link_a == m.ground ? j.link_b : j.link_a;
  return table.of_group[t.group[moving]];
}

std::string PointInputName(const Model& m, const Input& in) {
  const std::string& point = m.links[in.point.link].points[in.point.point].name;
  return std::string(in.kind == Input::Kind::kPointX ? "x_" : "y_") + m.links[in.point.link].name + "_" + point;
}

CoordinateTable BuildCoordinates(const Model& m, const Topology& t) {
  CoordinateTable c;
  const int n = static_cast<int>(m.links.size());
  c.of_group.assign(t.num_groups(), -1);
  c.of_joint.assign(m.joints.size(), -1);
  // One angle per rotation group, one coordinate per joint that has one.
  for (int g = 0; g < t.num_groups(); ++g) {
    if (g == t.ground_group) continue;
    const std::string& link = m.links[t.rep[g]].name;
    Coordinate co{"theta_" + link, "absolute angle of link '" + link + "'", true,
                  GiNaC::symbol("theta_" + link, "\\theta_{\\mathrm{" + link + "}}")};
    for (int l = 0; l < n; ++l)
      if (t.group[l] == g && l != t.rep[g]) co.what += ", and of '" + m.links[l].name + "' (slides on it)";
    c.of_group[g] = static_cast<int>(c.all.size());
    c.all.push_back(co);
  }
  for (size_t j = 0; j < m.joints.size(); ++j) {
    // Constructed for every joint, with or without a coordinate: its default symbol keeps
    // the symbols' serial numbers (and so generated/'s term order) as they have been.
    Coordinate co;
    const std::optional<JointCoordinate> jc = KindOf(m.joints[j]).Coordinate(m, m.joints[j]);
    if (!jc) continue;
    co = {jc->name, jc->what, jc->is_angle, GiNaC::symbol(jc->name, jc->latex)};
    c.of_joint[j] = static_cast<int>(c.all.size());
    c.all.push_back(co);
  }
  return c;
}


Kinematics DeriveKinematics(const Model& m, const Topology& t, const CoordinateTable* coordinates,
                            const CamAnalysis* cams) {
  Kinematics k;
  const int n = static_cast<int>(m.links.size());

  // ---- coordinates: one angle per rotation group, the joints' own (s, psi, u) ----
  CoordinateTable table = coordinates ? *coordinates : BuildCoordinates(m, t);
  std::vector<Coordinate>& all = table.all;
  std::vector<GiNaC::ex> group_theta(t.num_groups(), GiNaC::ex(0));
  std::vector<GiNaC::ex> joint_s(m.joints.size(), GiNaC::ex(0));
  for (int g = 0; g < t.num_groups(); ++g)
    if (table.of_group[g] >= 0) group_theta[g] = all[table.of_group[g]].symbol;
  for (size_t j = 0; j < m.joints.size(); ++j)
    if (table.of_joint[j] >= 0) joint_s[j] = all[table.of_joint[j]].symbol;
  // Inputs become q (in declaration order), the rest phi.
  std::vector<bool> driven(all.size(), false);
  for (const Input& in : m.inputs) {
    const int c = InputCoordinate(m, t, table, in);
    if (c < 0) {
      // A point's x or y: a new coordinate, tied to the linkage by its driving constraint below.
      const std::string name = PointInputName(m, in), xy = in.kind == Input::Kind::kPointX ? "x" : "y";
      const std::string& link = m.links[in.point.link].name;
      const std::string& point = m.links[in.point.link].points[in.point.point].name;
      k.q.push_back({name, xy + " of point '" + m.PointName(in.point) + "' in the fixed frame (driven)", false,
                     GiNaC::symbol(name, xy + "_{\\mathrm{" + link + "." + point + "}}")});
    } else {
      if (in.kind == Input::Kind::kAngle) all[c].what += " (driven)";
      else if (m.joints[in.joint].type() != JointType::kPrismatic && m.joints[in.joint].type() != JointType::kSlot)
        all[c].what += " (driven at joint '" + m.joints[in.joint].name + "')";
      driven[c] = true;
      k.q.push_back(all[c]);
    }
    k.q_min.push_back(in.min);
    k.q_max.push_back(in.max);
  }
  for (size_t c = 0; c < all.size(); ++c)
    if (!driven[c]) k.phi.push_back(all[c]);

  // ---- frames through the spanning tree ----
  k.frames.assign(n, Frame{});
  for (int l : t.order) {
    if (l == m.ground) continue;
    const int jn = t.parent_joint[l];
    const Joint& j = m.joints[jn];
    const int parent = j.OtherLink(l);
    const GiNaC::ex theta = group_theta[t.group[l]] + t.offset[l];
    k.frames[l] = KindOf(j).PlaceChild(m, j, parent, k.frames[parent], theta, joint_s[jn]);
    k.placements.push_back({jn, parent, l});
  }

  // ---- closure equations: the cut joints' rows loop by loop, and the no-slip equation
  // of every rolling tree joint ----
  auto add_rows = [&](int joint, bool cut, int loop) {
    std::vector<JointEquation> rows = KindOf(m.joints[joint]).Equations(m, joint, cut, k.frames, joint_s);
    const int group = static_cast<int>(k.Phi.size());
    for (JointEquation& r : rows) {
      // Products of sums (r1 (th1 - thc)) print with a sign GiNaC picks by its
      // run-dependent term order: the header's equation text must be the same on every run.
      if (!r.pair) r.value = r.value.expand();
      k.Phi_group.push_back(r.pair ? group : static_cast<int>(k.Phi.size()));
      k.Phi.push_back(r.value);
      k.Phi_rows.push_back({joint, loop, r.component});
      k.Phi_source.push_back(k.Phi_rows.back().Text(m));
    }
  };
  for (size_t li = 0; li < t.loops.size(); ++li) add_rows(t.loops[li].cut_joint, true, static_cast<int>(li));
  for (int j : t.tree_joints) add_rows(j, false, -1);
  // The driving constraints of point inputs (Paul: a coordinate that is no joint's is
  // generalized by one more equation): x_P(phi) - q = 0; a point's x and y are one pair.
  for (int i = 0; i < k.nq(); ++i) {
    const Input& in = m.inputs[i];
    if (!in.IsPoint()) continue;
    const Vec2 r = PointPosition(m, in.point, k.frames[in.point.link]);
    const int xy = in.kind == Input::Kind::kPointX ? 0 : 1;
    int group = static_cast<int>(k.Phi.size());
    for (int i2 = 0; i2 < i; ++i2)
      if (m.inputs[i2].IsPoint() && m.inputs[i2].point == in.point)
        for (size_t row = 0; row < k.Phi_rows.size(); ++row)
          if (k.Phi_rows[row].input == i2) group = k.Phi_group[row];
    k.Phi_group.push_back(group);
    k.Phi.push_back((r[xy] - k.q[i].symbol).expand());
    RowSource source;
    source.component = xy == 0 ? RowComponent::kX : RowComponent::kY;
    source.input = i;
    k.Phi_rows.push_back(source);
    k.Phi_source.push_back(source.Text(m));
  }
  k.Phi_phi = GiNaC::matrix(k.nc(), k.nphi());
  k.Phi_q = GiNaC::matrix(k.nc(), k.nq());
  for (int i = 0; i < k.nc(); ++i) {
    for (int j = 0; j < k.nphi(); ++j) k.Phi_phi(i, j) = k.Phi[i].diff(k.phi[j].symbol);
    for (int j = 0; j < k.nq(); ++j) k.Phi_q(i, j) = k.Phi[i].diff(k.q[j].symbol);
  }

  // ---- cams ----
  CamAnalysis built;
  if (!cams) built = AnalyzeCams(m);
  const CamAnalysis& c = cams ? *cams : built;
  k.cam_laws = c.laws;
  k.cam_geometry = c.geometry;
  k.cam_summary = c.summary;
  k.cam_contours = c.contours;

  // ---- points ----
  auto position = [&](const PointRef& r) {
    if (r.contact_joint < 0) return PointPosition(m, r, k.frames[r.link]);
    const Joint& j = m.joints[r.contact_joint];
    return ContactPosition(m, j, k.frames[j.link_a], joint_s[r.contact_joint]);
  };
  for (const PointRef& r : m.outputs.points) {
    k.points.push_back(position(r));
    k.point_names.push_back(m.PointName(r));
  }
  if (m.outputs.Has(Quantity::kScene)) {
    for (int l = 0; l < n; ++l)
      for (size_t p = 0; p < m.links[l].points.size(); ++p) {
        const PointRef r{l, static_cast<int>(p)};
        k.scene.push_back(PointPosition(m, r, k.frames[l]));
        k.scene_names.push_back(m.PointName(r));
        k.scene_link.push_back(l);
      }
    // Contact points of rolling joints, drawn with the wheel.
    for (size_t j = 0; j < m.joints.size(); ++j) {
      if (m.joints[j].type() != JointType::kRoll) continue;
      const PointRef r{m.joints[j].link_b, -1, static_cast<int>(j)};
      k.scene.push_back(position(r));
      k.scene_names.push_back(m.PointName(r));
      k.scene_link.push_back(r.link);
    }
  }

  // ---- assembly guess (the validation stage checked its names) ----
  std::map<std::string, double> guess;
  for (const GuessValue& g : m.guess) guess[g.coordinate] = g.value;
  for (int i = 0; i < k.nq(); ++i)
    k.assembly_q.push_back(guess.count(k.q[i].name) ? guess[k.q[i].name] : k.q_min[i]);
  for (const Coordinate& co : k.phi) k.assembly_phi.push_back(guess.count(co.name) ? guess[co.name] : 0.0);
  return k;
}

}  // namespace mechgen
