// Transmission angles. See transmission.h.
#include "symbolic/transmission.h"

#include <algorithm>

#include "analysis/grashof.h"
#include "joints/joint_kind.h"

namespace mechgen {
namespace {

PointRef End(const Joint& j, int link) { return j.End(link); }

}  // namespace

std::string TransmissionAngle::Text() const {
  return "at joint " + joint + " between coupler '" + coupler + "' and output '" + output + "' (loop " +
         std::to_string(loop + 1) + ", driven by '" + driver + "')";
}

std::vector<TransmissionAngle> FindTransmissionAngles(const Model& m, const Topology& t, const Kinematics& k,
                                                      const std::vector<Block>& blocks) {
  // When a link's angle is known: inputs first (-1), then the blocks in solve order.
  auto solve_rank = [&](int link) {
    const std::string coord = "theta_" + m.links[t.rep[t.group[link]]].name;
    for (const Coordinate& c : k.q)
      if (c.name == coord) return -1;
    for (size_t b = 0; b < blocks.size(); ++b)
      for (int c : blocks[b].cols)
        if (k.phi[c].name == coord) return static_cast<int>(b);
    return static_cast<int>(blocks.size());
  };
  std::vector<TransmissionAngle> out;
  for (size_t li = 0; li < t.loops.size(); ++li) {
    const Loop& loop = t.loops[li];
    if (!IsFourBarLoop(m, loop)) continue;
    const int g = static_cast<int>(std::find(loop.links.begin(), loop.links.begin() + 4, m.ground) - loop.links.begin());
    if (g >= 4) continue;
    // joints[i] joins links[i] and links[i + 1]; the ground is links[g], a and b are the
    // ground-adjacent links, c the coupler.
    const int a = loop.links[(g + 1) % 4], c = loop.links[(g + 2) % 4], b = loop.links[(g + 3) % 4];
    const bool a_drives = solve_rank(a) <= solve_rank(b);
    const int driver = a_drives ? a : b, output = a_drives ? b : a;
    // The coupler–output joint, the coupler–driver joint and the output's ground pivot.
    const int j_out = loop.joints[a_drives ? (g + 2) % 4 : (g + 1) % 4];
    const int j_drv = loop.joints[a_drives ? (g + 1) % 4 : (g + 2) % 4];
    const int j_pivot = loop.joints[a_drives ? (g + 3) % 4 : g];
    TransmissionAngle ta;
    ta.loop = static_cast<int>(li);
    ta.joint = m.joints[j_out].name;
    ta.driver = m.links[driver].name;
    ta.coupler = m.links[c].name;
    ta.output = m.links[output].name;
    // u: along the coupler from the joint to its other end; v: along the output link from
    // the joint to its ground pivot; each from its own link's frame, so that mu is the
    // angle between the two links' directions (exact even where the loop is not closed).
    const Vec2 Cc = PointPosition(m, End(m.joints[j_out], c), k.frames[c]);
    const Vec2 Bc = PointPosition(m, End(m.joints[j_drv], c), k.frames[c]);
    const Vec2 Co = PointPosition(m, End(m.joints[j_out], output), k.frames[output]);
    const Vec2 Do = PointPosition(m, End(m.joints[j_pivot], output), k.frames[output]);
    const GiNaC::ex ux = Bc[0] - Cc[0], uy = Bc[1] - Cc[1], vx = Do[0] - Co[0], vy = Do[1] - Co[1];
    ta.cross = ux * vy - uy * vx;
    ta.dot = ux * vx + uy * vy;
    ta.u2 = ux * ux + uy * uy;
    ta.v2 = vx * vx + vy * vy;
    out.push_back(ta);
  }
  return out;
}

}  // namespace mechgen
