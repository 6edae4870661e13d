// The Jacobians of the equation of motion's right-hand side with respect to the state (issue
// 46): for the trajectory sensitivities (runtime dynamics/sensitivity.h), f_q and f_qd of
// qdd = f(t, q, qd) = I^-1 (Q - h) are
//   f_x = I^-1 (dQ/dx - dh/dx - (dI/dx) qdd),  x = q, qd,
// with dI/dq = Dynamics::dI_dq already generated; here are dQ/dq, dh/dq, dQ/dqd and dh/dqd,
// derived as the design sensitivities are (symbolic/design.h): the dynamics program differentiated
// statement by statement (ForwardOverProgram), q taking the place of a design parameter. Along
// q_l, what the program reads moves as
//   phi_i -> K(i, l),  K(i, j) -> L(i, j, l),  L(i, j, k) -> M(i, j, k, l),
//   Phi_phi(r, c) -> its partial in q_l plus its partials in phi times K(:, l),
// and along qd_l only qd_l itself moves (qd(l) -> 1; K, L, phi, t and the given friction loads
// do not depend on qd).
//
// M(i, j, k, l) = dL(i, j, k)/dq_l = d3phi_i/dq_j dq_k dq_l, the third-order coefficients,
// symmetric in j, k, l (derived once per sorted triple j <= k <= l), come from differentiating
// L's defining equation along the motion, as L comes from K's (symbolic/table.h): with
//   f_r(j, k) = g_r(j, k) + sum_c Phi_phi(r, c) L(c, j, k) = 0,  g_r(j, k) = Along_k Along_j Phi_r
// (K held in the outer Along), its total derivative along q_l is
//   Along_l f_r + sum_{i j'} df_r/dK(i, j') L(i, j', l) + sum_c Phi_phi(r, c) M(c, j, k, l) = 0
// (K and L held in Along_l), solved block by block in the solve order with each block's Phi_phi
// set up once (BlockSystem, the forward substitution of K and L). K and L are read from
// EvalCoefficients' output (slots c.K, c.L), so only partial derivatives of Phi are taken.
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "symbolic/dynamics.h"
#include "symbolic/program.h"
#include "symbolic/slot.h"
#include "symbolic/table.h"

namespace mechgen {

/// M(i, j, k, l) = dL(i, j, k)/dq_l as locals of `program`, reading K and L through `slots`.
struct ThirdOrderCoefficients {
  ThirdOrderCoefficients(const SymbolicTable& t, SlotSymbols* slots);
  Program program;
  /// M(i, j, k, l) in any order of j, k, l.
  GiNaC::ex operator()(int i, int j, int k, int l) const;

 private:
  int nq_ = 0;
  std::vector<std::vector<GiNaC::ex>> M_;  ///< [i][triple j <= k <= l]
  int Triple(int j, int k, int l) const;
};

/// EvalDynamicsJacobian's quantities: d/dq and d/dqd of h and Q at (t, q, qd), the given
/// friction loads held. Possible where the dynamics program is straight-line (as for
/// DesignDynamics) and L is derived.
struct DynamicsJacobian {
  DynamicsJacobian(const Model& m, const SymbolicTable& t, const DynamicsTable& dyn);
  bool possible = false;
  std::string why_not;
  /// What the derivatives read besides the dynamics program's own slots (K, L).
  SlotSymbols slots;
  /// M's locals, then the derivative locals (after the dynamics program, which they read).
  Program program;
  /// [j][l]: dh_j/dq_l, dQ_j/dq_l, dh_j/dqd_l, dQ_j/dqd_l.
  std::vector<std::vector<GiNaC::ex>> dh_dq, dQ_dq, dh_dqd, dQ_dqd;
};

}  // namespace mechgen
