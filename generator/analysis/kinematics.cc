// Coordinates, frames, closure equations and points. See kinematics.h.
#include "kinematics.h"

#include <map>

namespace mechgen {

Kinematics DeriveKinematics(const Model& m, const Topology& t) {
  Kinematics k;
  const int n = static_cast<int>(m.links.size());

  // ---- coordinates: one angle per rotation group, one displacement per slider ----
  std::vector<GiNaC::ex> group_theta(t.num_groups(), GiNaC::ex(0));
  std::vector<GiNaC::ex> joint_s(m.joints.size(), GiNaC::ex(0));
  std::vector<Coordinate> all;
  std::vector<int> coord_of_group(t.num_groups(), -1), coord_of_joint(m.joints.size(), -1);
  for (int g = 0; g < t.num_groups(); ++g) {
    if (g == t.ground_group) continue;
    const std::string& link = m.links[t.rep[g]].name;
    Coordinate c{"theta_" + link, "absolute angle of link '" + link + "'", true,
                 GiNaC::symbol("theta_" + link, "\\theta_{\\mathrm{" + link + "}}")};
    for (int l = 0; l < n; ++l)
      if (t.group[l] == g && l != t.rep[g])
        c.what += ", and of '" + m.links[l].name + "' (slides on it)";
    coord_of_group[g] = static_cast<int>(all.size());
    group_theta[g] = c.symbol;
    all.push_back(c);
  }
  for (size_t j = 0; j < m.joints.size(); ++j) {
    const Joint& jt = m.joints[j];
    const std::string& name = jt.name;
    Coordinate c;
    if (jt.type == JointType::kPrismatic) {
      c = {"s_" + name,
           "displacement of slider '" + name + "' (" + m.PointName(jt.b) + " from " + m.PointName(jt.a) +
               " along the line)",
           false, GiNaC::symbol("s_" + name, "s_{\\mathrm{" + name + "}}")};
    } else if (jt.type == JointType::kRoll && jt.on_line) {
      c = {"s_" + name,
           "contact point of rolling joint '" + name + "' from " + m.PointName(jt.a) + " along the line",
           false, GiNaC::symbol("s_" + name, "s_{\\mathrm{" + name + "}}")};
    } else if (jt.type == JointType::kRoll) {
      c = {"psi_" + name,
           "contact angle of rolling joint '" + name + "' about " + m.PointName(jt.a) + ", in the frame of '" +
               m.links[jt.a.link].name + "'",
           true, GiNaC::symbol("psi_" + name, "\\psi_{\\mathrm{" + name + "}}")};
    } else if (jt.type == JointType::kCam && jt.contour != Joint::Contour::kNone) {
      c = {"u_" + name,
           "contact parameter of cam '" + name + "' on the contour of '" + m.links[jt.a.link].name + "'" +
               (jt.contour == Joint::Contour::kSpline ? " (chord length along the spline)" : " (u of x(u), y(u))"),
           false, GiNaC::symbol("u_" + name, "u_{\\mathrm{" + name + "}}")};
    } else {
      continue;
    }
    coord_of_joint[j] = static_cast<int>(all.size());
    joint_s[j] = c.symbol;
    all.push_back(c);
  }
  // Inputs become q (in declaration order), the rest phi.
  std::vector<bool> driven(all.size(), false);
  for (const Input& in : m.inputs) {
    const Joint& j = m.joints[in.joint];
    int c;
    if (j.type == JointType::kPrismatic) {
      c = coord_of_joint[in.joint];
    } else {
      const int moving = j.a.link == m.ground ? j.b.link : j.a.link;
      c = coord_of_group[t.group[moving]];
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
    const int parent = j.a.link == l ? j.b.link : j.a.link;
    const GiNaC::ex theta = group_theta[t.group[l]] + t.offset[l];
    k.frames[l] = PlaceChild(m, j, parent, k.frames[parent], theta, joint_s[jn]);
  }

  // ---- closure equations: two per lower-pair loop, one per higher-pair loop, and the
  // no-slip equation of every rolling joint (also when it is a tree joint) ----
  auto add_rows = [&](int joint, bool cut, const std::string& where) {
    const auto rows = JointEquations(m, joint, cut, k.frames, joint_s);
    const int group = static_cast<int>(k.Phi.size());
    for (const JointEquation& r : rows) {
      k.Phi_group.push_back(r.pair ? group : static_cast<int>(k.Phi.size()));
      k.Phi.push_back(r.value);
      k.Phi_source.push_back(where + "joint " + m.joints[joint].name + ", " + r.what);
    }
  };
  for (size_t li = 0; li < t.loops.size(); ++li)
    add_rows(t.loops[li].cut_joint, true, "loop " + std::to_string(li + 1) + ", ");
  for (int j : t.tree_joints)
    if (m.joints[j].type == JointType::kRoll) add_rows(j, false, "");
  k.Phi_phi = GiNaC::matrix(k.nc(), k.nphi());
  k.Phi_q = GiNaC::matrix(k.nc(), k.nq());
  for (int i = 0; i < k.nc(); ++i) {
    for (int j = 0; j < k.nphi(); ++j) k.Phi_phi(i, j) = k.Phi[i].diff(k.phi[j].symbol);
    for (int j = 0; j < k.nq(); ++j) k.Phi_q(i, j) = k.Phi[i].diff(k.q[j].symbol);
  }

  // ---- cams: the law's segments (checked to close the cycle) and the cam's geometry
  // (checked for undercutting) ----
  for (const Joint& j : m.joints) {
    if (j.type != JointType::kCam) continue;
    if (j.contour != Joint::Contour::kNone) {
      k.cam_contours.push_back(BuildCamContour(m, j));
      continue;
    }
    k.cam_laws.push_back(BuildCamLaw(m, j));
    k.cam_geometry.push_back(DeriveCamGeometry(m, j));
    k.cam_summary.push_back(CheckCam(m, j, k.cam_laws.back(), k.cam_geometry.back()));
  }

  // ---- points ----
  auto position = [&](const PointRef& r) {
    if (r.contact_joint < 0) return PointPosition(m, r, k.frames[r.link]);
    const Joint& j = m.joints[r.contact_joint];
    return ContactPosition(m, j, k.frames[j.a.link], joint_s[r.contact_joint]);
  };
  for (const PointRef& r : m.outputs.points) {
    k.points.push_back(position(r));
    k.point_names.push_back(m.PointName(r));
  }
  if (m.outputs.scene) {
    for (int l = 0; l < n; ++l)
      for (size_t p = 0; p < m.links[l].points.size(); ++p) {
        const PointRef r{l, static_cast<int>(p)};
        k.scene.push_back(PointPosition(m, r, k.frames[l]));
        k.scene_names.push_back(m.PointName(r));
        k.scene_link.push_back(l);
      }
    // Contact points of rolling joints, drawn with the wheel.
    for (size_t j = 0; j < m.joints.size(); ++j) {
      if (m.joints[j].type != JointType::kRoll) continue;
      const PointRef r{m.joints[j].b.link, -1, static_cast<int>(j)};
      k.scene.push_back(position(r));
      k.scene_names.push_back(m.PointName(r));
      k.scene_link.push_back(r.link);
    }
  }

  // ---- assembly guess ----
  std::map<std::string, double> guess;
  for (const GuessValue& g : m.guess) {
    bool known = false;
    for (const Coordinate& c : all) known |= c.name == g.coordinate;
    if (!known) {
      std::string list;
      for (const Coordinate& c : all) list += (list.empty() ? "" : ", ") + c.name;
      m.Fail(g.mark, "assembly: unknown coordinate '" + g.coordinate + "'; the coordinates are: " +
                         list);
    }
    guess[g.coordinate] = g.value;
  }
  for (int i = 0; i < k.nq(); ++i)
    k.assembly_q.push_back(guess.count(k.q[i].name) ? guess[k.q[i].name] : k.q_min[i]);
  for (const Coordinate& c : k.phi) k.assembly_phi.push_back(guess.count(c.name) ? guess[c.name] : 0.0);
  return k;
}

}  // namespace mechgen
