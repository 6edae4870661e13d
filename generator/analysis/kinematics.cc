// Coordinates, frames, closure equations and points. See kinematics.h.
#include "analysis/kinematics.h"

#include <map>

#include "analysis/validate.h"

namespace mechgen {

std::string RowSource::Text(const Model& m) const {
  return (loop >= 0 ? "loop " + std::to_string(loop + 1) + ", " : std::string()) + "joint " + m.joints[joint].name +
         ", " + ComponentText(component);
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
    const Joint& j = m.joints[in.joint];
    int c;
    if (j.type() == JointType::kPrismatic) {
      c = table.of_joint[in.joint];
    } else {
      const int moving = j.link_a == m.ground ? j.link_b : j.link_a;
      c = table.of_group[t.group[moving]];
      all[c].what += " (driven at joint '" + j.name + "')";
    }
    driven[c] = true;
    k.q.push_back(all[c]);
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
