// Dynamically and statically equivalent links (Paul §6.3.1) for `mechgen report`: each link
// with mass replaced by point masses a user can check by hand, at the parameters' defaults.
//  - Dynamically equivalent two-point masses: through each joint point A of the link, at the
//    distance a from the centre of mass G, the second point B lies on the line AG beyond G at
//    b = k^2 / a (k^2 = J_G / m, the radius of gyration squared); m_A = m b / (a + b),
//    m_B = m a / (a + b). Same mass, same centre of mass, same J_G.
//  - Statically equivalent two-joint-point replacement: masses at two joint points P1, P2 with
//    the link's mass and centre of mass (G must lie on P1P2): m_1 = m d_2 / (d_1 + d_2),
//    m_2 = m d_1 / (d_1 + d_2), d_i = |P_i - G|; their moment of inertia about G is
//    m d_1 d_2, which differs from J_G by the inertia error m d_1 d_2 - J_G.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "model/model.h"

namespace mechgen {

struct EquivalentPoint {
  std::string through;  ///< the joint point A ("link.point")
  double a = 0, b = 0;  ///< |A - G| and k^2 / a
  double Bx = 0, By = 0;  ///< B in the link's frame
  double m_A = 0, m_B = 0;
};

struct EquivalentLink {
  std::string link;
  double m = 0, J = 0, k2 = 0, Gx = 0, Gy = 0;
  std::vector<EquivalentPoint> dynamic;  ///< one per joint point at a distance from G
  /// The statically equivalent replacement at the first two joint points (if G lies on them).
  bool has_static = false;
  std::string P1, P2, static_note;
  double m1 = 0, m2 = 0, J_static = 0, J_error = 0;
};

/// Every moving link with mass, at the parameters' defaults.
std::vector<EquivalentLink> EquivalentLinks(const Model& m);

/// The report's section (plain text; LaTeX comments if `latex`). Nothing if no link has mass.
void WriteEquivalentLinks(const Model& m, bool latex, std::ostream& os);

}  // namespace mechgen
