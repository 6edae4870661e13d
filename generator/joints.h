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

/// Cut joint `j` closing a loop: its two scalar closure equations, given the frames of
/// the links at its ends (fa for j.a.link, fb for j.b.link).
std::vector<GiNaC::ex> ClosureEquations(const Model& m, const Joint& j, const Frame& fa,
                                        const Frame& fb, const GiNaC::ex& s);

}  // namespace mechgen
