// Statics by virtual work (Paul ch. 5): the generalized forces of the loads, springs,
// gravity and friction, the driving forces that hold the mechanism in equilibrium, the
// potential energy, and the joint reactions, derived symbolically from the same
// coordinates, frames and rows as the kinematics.
//
// With x = (q, phi) and g_a the generalized applied force on x_a (the virtual work of the
// loads per unit dx_a, minus dV/dx_a), the equilibrium of the unconstrained coordinates is
//   g + Phi_x^T lambda + [drive; 0] = 0,
// so lambda = -Phi_phi^-T g_phi (one multiplier per row of Phi) and
//   Q_j = g_q,j + sum_i K(i, j) g_phi,i,   drive_j = -Q_j
// (Paul §5.3: Q_j = sum F.K_P,j + sum T K_theta,j - dV/dq_j). The multipliers are the forces
// at the cut joints (a revolute row r_a - r_b carries the force lambda on link a and
// -lambda on link b). A tree joint's reaction balances everything that acts on the links it
// carries (its subtree: loads, weights, springs, friction, actuators, and the cut joints'
// forces that enter the subtree), and a prismatic joint's moment balances the moments on
// the links it guides. The generated function (codegen/statics_functions.cc) reads K, L and
// Phi_phi from EvalCoefficients at the same configuration.
//
// Conventions (the generated header repeats them): reactions are the force of the joint's
// first link (Joint::link_a) on its second (link_b), in the fixed frame; a prismatic joint's
// N (along n = (-sin a, cos a)), T (along u = (cos a, sin a)), a = the line's absolute
// angle, at the slider point, and M (moment about the slider point), all of the guide on
// the slider; torques counter-clockwise positive. A slot's and a rolling joint's force at the
// pin or the contact point; a higher pair's contact force as a vector from its rows'
// multipliers (JointKind::Contact; models/README.md, Reactions).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "analysis/kinematics.h"
#include "model/model.h"
#include "symbolic/bodies.h"
#include "symbolic/program.h"
#include "symbolic/slot.h"
#include "symbolic/table.h"

namespace mechgen {

/// The reaction components and friction joints a model's statics emits, in order.
struct StaticsLayout {
  struct Component {
    int joint = -1;
    std::string name;  ///< "F_A_x", "N_slide", ...
    std::string what;  ///< one line for the header
  };
  std::vector<Component> reactions;  ///< of the joints in outputs.reactions, in that order
  std::vector<int> friction;         ///< joints with friction, in the model's order
  /// True if the model asks for any statics quantity.
  bool any = false;
  static StaticsLayout Of(const Model& m);
};

class StaticsTable;

/// What a StaticsTable derives beyond the statics (the dynamics builds on the same machinery).
struct StaticsOptions {
  /// Loads at (t, q, qd): the loads' t and <coordinate>_dot are the arguments t and qd(j) (the
  /// dependent velocities through c.K), dampers and viscous joint friction act. Otherwise t and
  /// the velocities are 0 (EvalStatics).
  bool dynamic = false;
  /// d'Alembert's inertia forces -m a_G at every centre of mass and couples -J alpha
  /// (kinetostatics, Paul §6.7); the accelerations read qdd(j). Implies `dynamic`.
  bool inertia = false;
  /// Derive the reactions (and the friction joints' normal forces) as m.outputs asks.
  bool reactions = true;
  /// The excess-coordinate formulation (with `dynamic`): the dependent coordinates' velocities
  /// are the arguments phid(i), not K qd; no centres of mass (EvalExcess reads `g`).
  bool excess = false;
  /// A dynamic table whose slots and bodies' coefficients (masses and their locals) this one
  /// reads instead of deriving them again (the kinetostatics reads the applied forces' table).
  const StaticsTable* bodies = nullptr;
  /// The statics at given velocities (EvalStatics' `velocities`): as `dynamic` (the loads'
  /// <coordinate>_dot are qd(j), the dependent ones through c.K; dampers and viscous joint
  /// friction act) but at t = 0, without the bodies' coefficients and with the statics' own
  /// outputs (Q, drive, V, dV/dq, the reactions, the friction joints' values). Implies `dynamic`.
  bool at_speed = false;
};

class StaticsTable {
 public:
  /// Derives what m.outputs asks (forces, potential, reactions); throws ModelError where a
  /// reaction cannot be derived (a higher pair whose multiplier is not its contact force
  /// alone: a gear's or law cam's axis a cut joint; JointKind::Contact says why).
  StaticsTable(const Model& m, const Kinematics& k, const SymbolicTable& t, const StaticsOptions& options = {});

  StaticsOptions options;
  /// The dynamic modes' arguments: qd(j), qdd(j) (inertia mode), t.
  std::vector<GiNaC::ex> qd, qdd;
  GiNaC::ex time;
  std::vector<MassKinematics> masses;  ///< the dynamic modes: every moving link with mass

  StaticsLayout layout;
  bool forces = false, potential = false, stiffness = false;

  /// The symbols the expressions read besides q, phi and p, with their meaning (slot.h):
  /// K(i, j), L(i, j + nq k), Phi_phi(r, c) of EvalCoefficients' output, the arguments qd(j),
  /// qdd(j), phid(i), t, and the friction loads; only the printer spells them.
  SlotSymbols slots;
  /// Named locals (the bodies' coefficients, the applied forces g, the multipliers, the
  /// subtree sums), in order; the first body_statements are the bodies' coefficients.
  Program program;
  size_t body_statements = 0;

  std::vector<GiNaC::ex> g;          ///< nq + nphi: the applied generalized forces on x = (q, phi) (named)
  std::vector<GiNaC::ex> phid;       ///< the excess mode's dependent velocities
  std::vector<GiNaC::ex> Q;          ///< nq: generalized forces (with the friction loads)
  std::vector<GiNaC::ex> drive;      ///< nq: -Q, named
  GiNaC::ex V;                       ///< potential energy (springs, gravity)
  std::vector<GiNaC::ex> dV_dq;      ///< nq
  std::vector<GiNaC::ex> Q_nc;       ///< nq, dynamic modes: Q + dV/dq, the non-conservative forces' part
  std::vector<GiNaC::ex> d2V_dq2;    ///< nq x nq (j + nq k), needs L
  std::vector<GiNaC::ex> stiffness_q;  ///< nq x nq: -dQ_j/dq_k along the motion, frictionless, needs L
  std::vector<GiNaC::ex> R;          ///< per layout.reactions component
  std::vector<GiNaC::ex> normal, gain;           ///< per friction joint
  std::vector<std::vector<GiNaC::ex>> K_rel;     ///< per friction joint, nq
  std::vector<std::string> notes;    ///< sentences for the generated header (conventions per joint)
  /// The plain statics of a model whose loads read a velocity (a load of <coordinate>_dot, a
  /// damper, viscous joint friction): the same statics at given velocities (StaticsOptions::
  /// at_speed), the body of EvalStatics, whose `velocities` nullptr is the machine at rest.
  /// Null otherwise (EvalStatics is this table's, at rest).
  std::shared_ptr<const StaticsTable> at_speed;
  /// With at_speed: what reads a velocity, for the header and the runtime's note
  /// (Model::kStaticsAtSpeed): "force of load 'cut' (s_stroke_dot)", "damper 'pump'",
  /// "viscous friction at joint O".
  std::vector<std::string> speed_items;

  /// An applied load or a spring as a force diagram draws it (forces.cc, from the items it
  /// makes; expressions in q, phi and p, at rest in the static modes). `at`: a force load's
  /// point of application, a torque load's link at its pivot (its first revolute joint, one
  /// with the ground first; else its frame's origin), a linear spring's end a, a torsional
  /// spring's joint; `b`: a linear spring's end b (else `at`); `F`: a force load's force, a
  /// linear spring's force on its end a (towards b under tension), else 0; `value`: a torque
  /// load's torque or a torsional spring's on the joint's second link (counter-clockwise +),
  /// a linear spring's tension (+ pulling its ends together), a force load's 0. A weight (a
  /// moving link with mass under the model's gravity, its point masses included): `at` = `b`
  /// its centre of mass, `F` its weight m g, `value` |m g|.
  struct Mark {
    enum class Kind { kForce, kTorque, kSpring, kTorsionalSpring, kWeight };
    Kind kind = Kind::kForce;
    std::string name;
    Vec2 at{0, 0}, b{0, 0}, F{0, 0};
    GiNaC::ex value = 0;
  };
  std::vector<Mark> marks;  ///< the model's loads, then its springs, then its weights, in its order

 private:
  // The stages, in order (statics_stage.h): each reads what the ones before derived.
  struct Stage;
  void DeriveArguments(Stage& st);      // statics.cc
  void DeriveAppliedForces(Stage& st);  // forces.cc: the items, g and V
  void DeriveDrive(Stage& st);          // forces.cc: Q, the drive and the actuators' items
  void DerivePotential(Stage& st);      // forces.cc
  void DeriveReactions(Stage& st);      // reactions.cc
};

}  // namespace mechgen
