// The bodies: the moving links with mass. Each body's centre of mass r_G and angle theta are
// expressions in (q, phi) and the parameters, derived once here (SymbolicTable::bodies) and
// read by the statics (weights), the dynamics (inertia, kinetostatics, excess coordinates)
// and the shaking force. Along a motion (motion.h, with K and L from wherever the caller
// keeps them) they have the velocity and centripetal coefficients
//   K_G,j = dr_G/dq_j,  L_G(j + nq k) = d2r_G/dq_j dq_k,  K_theta,j,  L_theta(j + nq k),
// which BodyCoefficients() names as locals of a statement program.
#pragma once

#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "joints/joint_kind.h"
#include "model/model.h"
#include "symbolic/motion.h"
#include "symbolic/program.h"

namespace mechgen {

/// A moving link with mass.
struct MassiveLink {
  int link = -1;
  GiNaC::ex mass, inertia;  ///< the model's expressions (kg, kg m^2 about G)
  Vec2 r_G;                 ///< centre of mass in the fixed frame
  GiNaC::ex theta;          ///< the link's angle
};

/// Every moving link with mass, in the model's order.
std::vector<MassiveLink> MassiveLinks(const Model& m, const Kinematics& k);

/// A body along the motion: r_G, K_G,j, L_G(j + nq k), K_theta, L_theta (symmetric in j, k),
/// mass and inertia as named locals of the program BodyCoefficients() appends to.
struct MassKinematics {
  int link = -1;
  Vec2 r_G;  ///< the body's r_G (an expression, not a local)
  GiNaC::ex mass, inertia;
  std::vector<Vec2> K_G, L_G;
  std::vector<GiNaC::ex> K_theta, L_theta;
  /// Kinetostatics (StaticsOptions::inertia): the named accelerations a_G and alpha.
  Vec2 a_G{0, 0};
  GiNaC::ex alpha = 0;
};

/// Each body's coefficients along `mo`: mass_<l> and inertia_<l> (named unless a number or a
/// symbol, so that I = m (K_x^2 + K_y^2) + J K_theta^2 is not expanded into products of each
/// term), KG<l>_x_<j>, KG<l>_y_<j>, Kth<l>_<j> (Motion::Along), and LG<l>_x_<j>_<k>,
/// LG<l>_y_<j>_<k>, Lth<l>_<j>_<k> for j <= k (Motion::Second), appended to *program.
std::vector<MassKinematics> BodyCoefficients(const std::vector<MassiveLink>& bodies, const Motion& mo, Program* program);

}  // namespace mechgen
