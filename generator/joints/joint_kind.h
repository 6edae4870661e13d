// The equations of each joint type, in one place: how a tree joint places its child
// link, and which closure equations a cut joint adds to Phi (Paul §1.1, §1.2). Gears,
// rolling contact and cams add their cases here.
#pragma once

#include <array>
#include <vector>

#include "model.h"

namespace mechgen {

/// A link's pose in the fixed frame: origin (x, y) and absolute angle theta (CCW from +x).
struct Frame {
  GiNaC::ex x = 0, y = 0, theta = 0;
};

using Vec2 = std::array<GiNaC::ex, 2>;

/// Position in the fixed frame of point `ref` of a link whose frame is `f`.
Vec2 PointPosition(const Model& m, PointRef ref, const Frame& f);

/// Tree joint `j` between `parent` (placed, frame `fp`) and `child`, whose absolute angle
/// is `child_theta`; `s` is the joint's displacement variable (prismatic only).
Frame PlaceChild(const Model& m, const Joint& j, int parent, const Frame& fp,
                 const GiNaC::ex& child_theta, const GiNaC::ex& s);

/// One scalar equation of Phi and where it comes from.
struct JointEquation {
  GiNaC::ex value;
  std::string what;  ///< "x", "y", "no slip", "gear mesh", "cam law"
  bool pair = false; ///< the x or y projection of a vector closure (dyad recognition)
};

/// The equations joint `joint` adds to Phi. A cut lower pair closes its loop with its two
/// vector projections (x, y); a rolling joint adds its no-slip equation whether it is a cut
/// or a tree joint; a higher pair (gear, rack, cam) adds its one equation.
/// \param frames  every link's frame; \param var  every joint's variable (s, psi; 0 if none).
std::vector<JointEquation> JointEquations(const Model& m, int joint, bool cut, const std::vector<Frame>& frames,
                                          const std::vector<GiNaC::ex>& var);

/// The contact point of rolling joint `j` in the fixed frame: on the line or circle of the
/// base link (frame `base`) at contact parameter `v`.
Vec2 ContactPosition(const Model& m, const Joint& j, const Frame& base, const GiNaC::ex& v);

}  // namespace mechgen
