// Graph analysis of the link–joint network. See topology.h.
#include "analysis/topology.h"

#include <algorithm>
#include <deque>
#include <sstream>

#include "joints/joint_kind.h"

namespace mechgen {

std::string Loop::Text(const Model& m) const {
  std::ostringstream os;
  for (size_t i = 0; i < links.size(); ++i) {
    os << m.links[links[i]].name;
    if (i < joints.size()) os << " -" << m.joints[joints[i]].name << "- ";
  }
  return os.str();
}

namespace {

// Weighted union–find over links: theta[l] = theta[root] + off[l].
struct RotationSets {
  std::vector<int> parent;
  std::vector<GiNaC::ex> off;
  explicit RotationSets(int n) : parent(n), off(n, GiNaC::ex(0)) {
    for (int i = 0; i < n; ++i) parent[i] = i;
  }
  int Find(int l) {
    if (parent[l] == l) return l;
    const int root = Find(parent[l]);
    if (parent[l] != root) {
      off[l] = off[l] + off[parent[l]];
      parent[l] = root;
    }
    return root;
  }
};

}  // namespace

Topology BuildTopology(const Model& m) {
  Topology t;
  const int n = static_cast<int>(m.links.size());

  // ---- rotation groups: theta_slider = theta_guide + relative_angle ----
  RotationSets sets(n);
  for (size_t k = 0; k < m.joints.size(); ++k) {
    const Joint& j = m.joints[k];
    if (j.type() != JointType::kPrismatic) continue;
    ++t.num_prismatic;
    const GiNaC::ex& relative_angle = j.Data<PrismaticData>().relative_angle;
    const int g = j.link_a, s = j.link_b;
    const int rg = sets.Find(g), rs = sets.Find(s);
    if (rg == rs) {
      // Already parallel through other sliders: the relative angles must agree.
      const GiNaC::ex mismatch = (sets.off[s] - sets.off[g] - relative_angle).expand();
      if (!mismatch.is_zero() && t.inconsistent_slider < 0) t.inconsistent_slider = static_cast<int>(k);
      continue;
    }
    sets.parent[rs] = rg;
    sets.off[rs] = sets.off[g] + relative_angle - sets.off[s];
  }
  // Group representative: the ground if the group holds it, else its first link.
  t.group.assign(n, -1);
  t.offset.assign(n, 0);
  std::vector<int> root_group(n, -1);
  for (int l = 0; l < n; ++l) {
    const int root = sets.Find(l);
    if (root_group[root] < 0) {
      root_group[root] = static_cast<int>(t.rep.size());
      t.rep.push_back(l);
    }
    t.group[l] = root_group[root];
  }
  for (int l = 0; l < n; ++l)
    if (l == m.ground) t.rep[t.group[l]] = l;
  t.ground_group = t.group[m.ground];
  for (int l = 0; l < n; ++l) {
    sets.Find(l);
    const int rep = t.rep[t.group[l]];
    t.offset[l] = (sets.off[l] - sets.off[rep]).expand();
  }

  // ---- spanning tree over the lower pairs, breadth first from the ground, joints in
  // declaration order. A higher pair (gear, rack, cam) cannot place a link: it is always a
  // cut joint, closing a loop with its one equation. ----
  t.parent_joint.assign(n, -1);
  std::vector<bool> seen(n, false), is_tree(m.joints.size(), false);
  std::deque<int> queue{m.ground};
  seen[m.ground] = true;
  while (!queue.empty()) {
    const int u = queue.front();
    queue.pop_front();
    t.order.push_back(u);
    for (size_t k = 0; k < m.joints.size(); ++k) {
      const Joint& j = m.joints[k];
      if (!j.IsLowerPair() || !j.Joins(u)) continue;
      const int v = j.OtherLink(u);
      if (seen[v]) continue;
      seen[v] = true;
      is_tree[k] = true;
      t.parent_joint[v] = static_cast<int>(k);
      queue.push_back(v);
    }
  }
  for (int l = 0; l < n; ++l)
    if (!seen[l]) t.unconnected.push_back(l);
  for (size_t k = 0; k < m.joints.size(); ++k)
    (is_tree[k] ? t.tree_joints : t.cut_joints).push_back(static_cast<int>(k));

  // ---- fundamental loops: cut joint + tree paths to the common ancestor ----
  auto path_to_ground = [&](int l) {
    std::vector<int> path{l};
    while (t.parent_joint[l] >= 0) {
      l = m.joints[t.parent_joint[l]].OtherLink(l);
      path.push_back(l);
    }
    return path;
  };
  for (int c : t.cut_joints) {
    const Joint& j = m.joints[c];
    std::vector<int> pa = path_to_ground(j.link_a), pb = path_to_ground(j.link_b);
    // Strip the common tail (ancestors shared by both paths) but keep the meeting link.
    while (pa.size() > 1 && pb.size() > 1 && pa[pa.size() - 2] == pb[pb.size() - 2]) {
      pa.pop_back();
      pb.pop_back();
    }
    Loop loop;
    loop.cut_joint = c;
    // a ... meeting link ... b, then the cut joint back to a.
    loop.links = pa;
    for (size_t i = 0; i + 1 < pa.size(); ++i) loop.joints.push_back(t.parent_joint[pa[i]]);
    for (int i = static_cast<int>(pb.size()) - 2; i >= 0; --i) {
      loop.joints.push_back(t.parent_joint[pb[i]]);
      loop.links.push_back(pb[i]);
    }
    loop.joints.push_back(c);
    loop.links.push_back(j.link_a);
    // Start the loop at the ground if it holds it (else at its first link in the file),
    // as a reader would trace it; joints[i] still joins links[i] and links[i + 1].
    loop.links.pop_back();
    const auto start = std::find(loop.links.begin(), loop.links.end(), m.ground) != loop.links.end()
                           ? std::find(loop.links.begin(), loop.links.end(), m.ground)
                           : std::min_element(loop.links.begin(), loop.links.end());
    const auto shift = start - loop.links.begin();
    std::rotate(loop.links.begin(), start, loop.links.end());
    std::rotate(loop.joints.begin(), loop.joints.begin() + shift, loop.joints.end());
    loop.links.push_back(loop.links.front());
    t.loops.push_back(loop);
  }

  // ---- mobility ----
  // Grübler–Kutzbach: lower pairs (revolute, prismatic, rolling without slip) remove 2
  // degrees of freedom, higher pairs (gear, rack, cam contact) 1. Loop criterion: the
  // variables (angles, slides, contact parameters) minus the equations: 2 per lower-pair
  // cut joint, 1 per higher pair, and the no-slip equation of every rolling joint.
  // A slot joint (pin in slot) removes 1: a half joint, counted with j2; its slide is a
  // variable, and a cut slot closes its loop with 2 equations like a lower pair.
  int j1 = 0, j2 = 0, slides = 0;
  for (const Joint& j : m.joints) (j.IsLowerPair() && j.type() != JointType::kSlot ? j1 : j2) += 1;
  for (const Joint& j : m.joints) slides += j.type() == JointType::kSlot;
  // Every joint coordinate but a slider's displacement is a contact parameter (roll: s or
  // psi, contour cam: u), and comes with one more equation (no slip, the second contact row).
  for (const Joint& j : m.joints)
    t.num_contact += KindOf(j).Coordinate(m, j).has_value() && j.type() != JointType::kPrismatic &&
                     j.type() != JointType::kSlot;
  t.num_variables = (t.num_groups() - 1) + t.num_prismatic + slides + t.num_contact;
  t.num_equations = 0;
  for (int c : t.cut_joints) t.num_equations += m.joints[c].IsLowerPair() ? 2 : 1;
  t.num_equations += t.num_contact;
  t.grubler_mobility = 3 * (n - 1) - 2 * j1 - j2;
  t.loop_mobility = t.num_variables - t.num_equations;
  std::ostringstream os;
  if (j2 == 0)
    os << "3(n - 1) - 2 j1 = 3*(" << n << " - 1) - 2*" << j1;
  else
    os << "3(n - 1) - 2 j1 - j2 = 3*(" << n << " - 1) - 2*" << j1 << " - " << j2;
  os << " = " << t.grubler_mobility;
  t.grubler_text = os.str();
  const bool lower_only = j2 == 0 && t.num_contact == 0;
  t.loop_text = std::to_string(t.num_variables) + " variables - " +
                (lower_only ? "2*" + std::to_string(t.loops.size()) + " loops"
                            : std::to_string(t.num_equations) + " equations") +
                " = " + std::to_string(t.loop_mobility);

  return t;
}

}  // namespace mechgen
