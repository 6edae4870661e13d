// Dynamics of machines with few degrees of freedom (Paul ch. 6), derived symbolically from
// the same coordinates and the same applied-force machinery as the statics (statics.h):
// the generalized inertia I(q) = sum m K_G^T K_G + J K_theta K_theta over the massive moving
// links, its derivative dI/dq, the centripetal terms C (h = C (qd (x) qd)), the generalized
// applied forces Q(t, q, qd) (the statics' virtual work with t, the velocities, dampers and
// viscous friction), the kinetic and potential energies and the power of the
// non-conservative forces. The equation of motion is I qdd + h = Q (Paul §6.4; one DOF:
// I qdd + I'/2 qd^2 = Q).
//
// With a_G = sum_k K_G,k qdd_k + sum_kl L_G,kl qd_k qd_l, the generalized inertia force on q_j
// is sum m K_G,j . a_G + J K_theta,j alpha, hence
//   I(j, k) = sum m K_G,j . K_G,k + J K_theta,j K_theta,k,
//   C(j, k, l) = sum m K_G,j . L_G,kl + J K_theta,j L_theta,kl,
//   dI(j, k)/dq_l = C(j, k, l) + C(k, j, l).
// Everything reads K and L from EvalCoefficients (c.K, c.L), as the statics does.
//
// The excess-coordinate formulation (Paul §6.6.2) works on x = (q, phi) directly:
// M = sum m dr_G/dx^T dr_G/dx + J dtheta/dx^T dtheta/dx, the quadratic velocity terms from
// the second partial derivatives of r_G, the applied forces g on x, and the constraints'
// Phi_x and gamma = -sum d2Phi/dx_b dx_c xd_b xd_c.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "analysis/kinematics.h"
#include "model/model.h"
#include "symbolic/program.h"
#include "symbolic/statics.h"
#include "symbolic/table.h"

namespace mechgen {

class DynamicsTable {
 public:
  /// Derives the dynamics if m.outputs asks for it (`any` says so).
  DynamicsTable(const Model& m, const Kinematics& k, const SymbolicTable& t);

  bool any = false;
  /// The applied forces at (t, q, qd) and the centres of mass' kinematics (named locals in
  /// applied.program; its `names` are the symbols read from the arguments).
  std::unique_ptr<StaticsTable> applied;
  /// Kinetostatics: the statics with d'Alembert's inertia forces (qdd(j) read too).
  std::unique_ptr<StaticsTable> kinetostatics;
  /// applied.program followed by the named I and C entries.
  Program program;

  std::vector<GiNaC::ex> I;      ///< nq x nq, I[j + nq k]
  std::vector<GiNaC::ex> dI_dq;  ///< dI_dq[j + nq (k + nq l)] = dI(j, k)/dq_l
  std::vector<GiNaC::ex> C;      ///< C[j + nq (k + nq l)]
  std::vector<GiNaC::ex> h;      ///< nq
  std::vector<GiNaC::ex> Q;      ///< nq
  GiNaC::ex T, V, P_nc;

  // ---- the excess-coordinate formulation (x = (q, phi), n = nq + nphi) ----
  /// The applied forces on x at (t, x, xd) (phid(i) read as the dependent velocities); its
  /// `names` are the symbols read from the arguments.
  std::unique_ptr<StaticsTable> excess_applied;
  Program excess_program;
  std::vector<GiNaC::ex> M;         ///< n x n, M[a + n b]
  std::vector<GiNaC::ex> excess_h;  ///< n
  std::vector<GiNaC::ex> g;         ///< n
  std::vector<GiNaC::ex> Phi_x;     ///< nc x n, Phi_x[r + nc a] (expressions in q, phi)
  std::vector<GiNaC::ex> gamma;     ///< nc
  GiNaC::ex excess_T, excess_V;

  // ---- the shaking force and moment (Paul ch. 7), if m.outputs asks for `shaking` ----
  /// With the kinetostatics' centre-of-mass accelerations a_G (named aG<l>_x, aG<l>_y, alpha<l>
  /// in kinetostatics->program, from K_G, L_G, K_theta, L_theta and qd, qdd), per link l (every
  /// link of the model, in its order; zero for the ground and the massless links):
  ///   F_link = -m a_G,  M_link = r_G x F_link - J alpha  (about the origin O, CCW +),
  /// F = sum F_link, M = sum M_link, and the total mass and centre of mass r_C.
  bool shaking = false;
  Program shaking_program;                  ///< kinetostatics->program and the r_G locals
  std::vector<Vec2> F_link, r_G;            ///< per link (r_G unused where !massive)
  std::vector<GiNaC::ex> M_link;            ///< per link
  std::vector<bool> massive;                ///< per link: a moving link with mass
  Vec2 F{0, 0}, r_C{0, 0};
  GiNaC::ex M_total = 0, mass_total = 0;
};

}  // namespace mechgen
