// The link–joint graph of a model (Paul appendix D): rotation groups (links that a
// prismatic joint keeps parallel share one angle), a spanning tree grown from the ground,
// the fundamental loops closed by the remaining (cut) joints, and the mobility by
// Grübler–Kutzbach and by the loop mobility criterion, checked against the inputs.
#pragma once

#include <string>
#include <vector>

#include "model/model.h"

namespace mechgen {

/// One independent loop: the cut joint that closes it and the tree path between its ends.
struct Loop {
  int cut_joint = -1;
  std::vector<int> links;   ///< links around the loop, starting and ending at a cut end
  std::vector<int> joints;  ///< joints around the loop, joints[i] between links[i], links[i+1]
  std::string Text(const Model& m) const;  ///< "ground -A- crank -B- coupler ..."
};

struct Topology {
  /// Rotation groups: link l has angle theta[group[l]] + offset[l]; the ground's group
  /// has angle 0. rep[g] is the link whose name the group's angle takes.
  std::vector<int> group;
  std::vector<GiNaC::ex> offset;
  std::vector<int> rep;
  int ground_group = -1;

  std::vector<int> parent_joint;  ///< per link: the tree joint to its parent; -1 for ground
  std::vector<int> order;         ///< links in breadth-first order from the ground
  std::vector<int> tree_joints, cut_joints;
  std::vector<Loop> loops;

  int num_prismatic = 0;
  int num_contact = 0;         ///< rolling joints and contour cams (each has a contact parameter)
  int num_variables = 0;       ///< (groups - 1) + prismatic joints + contact parameters
  int num_equations = 0;       ///< 2 per lower-pair cut, 1 per higher pair, 1 per contact parameter
  int grubler_mobility = 0;    ///< 3 (n - 1) - 2 j1 - j2
  int loop_mobility = 0;       ///< variables - equations
  std::string grubler_text;    ///< the formula with the numbers
  std::string loop_text;       ///< "3 variables - 2*1 loops = 1"

  /// What the validation stage reports (BuildTopology itself does not fail): links no
  /// lower pair connects to the ground, and the first prismatic joint whose relative
  /// angle contradicts other sliders' (-1 if none).
  std::vector<int> unconnected;
  int inconsistent_slider = -1;

  int num_groups() const { return static_cast<int>(rep.size()); }
};

/// Builds the topology. It does not fail: disconnected links, inconsistent sliders and a
/// mobility that does not match the declared inputs are the validation stage's errors
/// (Validate() in analysis/validate.h).
Topology BuildTopology(const Model& m);

}  // namespace mechgen
