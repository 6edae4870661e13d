// The stages of StaticsTable (statics.h), and what they share while they derive one table:
// the slots read from EvalCoefficients' output, the derivative along the motion with them,
// the applied items and the generalized applied forces. Each stage is a member function of
// StaticsTable in its own file:
//   statics.cc    the arguments: K, friction, qd, qdd, t, phid slots; the bodies' coefficients
//   forces.cc     the applied forces (loads, weights, inertia forces, springs, dampers,
//                 friction), g, Q and the drive; the potential energy's derivatives and the stiffness
//   reactions.cc  the multipliers, the unknowns at each joint and the table of reactions (each
//                 joint kind's own equations: JointKind::Reaction, joints/<kind>.cc), the
//                 friction joints' normal forces
// Internal to symbolic/: nothing outside includes it.
#pragma once

#include <string>
#include <vector>

#include "joints/joint_kind.h"
#include "symbolic/motion.h"
#include "symbolic/statics.h"

namespace mechgen {
namespace statics_detail {

inline std::string N(int i) { return std::to_string(i); }

inline GiNaC::ex Cross(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }

// Something that acts on one link: a force at a point and/or a couple.
struct Item {
  int link = -1;
  Vec2 F{0, 0};
  Vec2 at{0, 0};
  GiNaC::ex couple = 0;
  /// False for a pair whose virtual work is taken apart (friction: f times the joint's
  /// relative motion; the guide's point under a slider is a material point of the guide,
  /// which `at`, the slider's point, is not as a function of the coordinates).
  bool does_work = true;
  /// The prismatic joint whose friction or actuator force this is (-1: none). A cut
  /// prismatic joint's rows carry the force along its line too (s is one of the
  /// coordinates its rows close), so its multipliers already hold these forces.
  int along_joint = -1;
};

/// The joint's coordinate symbol (s, psi, u), if it has one.
const Coordinate* CoordinateOfJoint(const Model& m, const Kinematics& k, int joint);
/// A prismatic joint's unit vectors along its line (u) and normal to it (n = u turned by 90 deg).
void PrismaticLine(const Kinematics& k, const Joint& j, Vec2* u, Vec2* n);

}  // namespace statics_detail

struct StaticsTable::Stage {
  using Item = statics_detail::Item;
  Stage(const Model& model, const Kinematics& kin, const SymbolicTable& table, SlotSymbols* slot_symbols);

  const Model& m;
  const Kinematics& k;
  const SymbolicTable& t;
  SlotSymbols& slots;
  const int nq, nphi, nc, nx;
  std::vector<std::vector<GiNaC::ex>> Kc;  ///< the slots K(i, j)
  std::vector<GiNaC::ex> fr;               ///< the friction loads (slots, with their viscous part)
  Motion motion;                           ///< along the motion with Kc and the slots L
  std::vector<GiNaC::ex> xdot;             ///< the dynamic modes: the velocities of x = (q, phi)
  std::vector<Item> items;                 ///< everything but the joints' forces (and, until Q, the actuators)
  std::vector<Item> items_expr;            ///< the applied items as expressions (for the derivatives)
  std::vector<bool> conservative;          ///< per applied item: a spring or a weight (part of V)
  std::vector<GiNaC::ex> gf;               ///< the friction loads' generalized forces on x
  std::vector<GiNaC::ex> gs;               ///< g_a, named: the generalized applied force on x_a

  /// The slot Phi_phi(r, c), 0 where it is structurally zero.
  GiNaC::ex PhiPhi(int r, int c) const;
  GiNaC::ex Along(const GiNaC::ex& f, int j) const { return motion.Along(f, j); }
  GiNaC::ex Ddt(const GiNaC::ex& f) const { return motion.Rate(f, xdot); }
  Vec2 Position(PointRef r) const { return PointPosition(m, r, k.frames[r.link]); }
  /// The virtual work of an item per unit dx_a: F . d(at)/dx_a + couple d(theta)/dx_a.
  GiNaC::ex Work(const Item& it, int a) const;
};

}  // namespace mechgen
