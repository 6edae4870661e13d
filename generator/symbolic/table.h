// The symbolic quantities of a model, derived once and apart from printing: Phi, Phi_phi,
// Phi_q (from the kinematics), the block order, the velocity coefficients K = -Phi_phi^-1
// Phi_q and centripetal coefficients L = dK/dq (Paul §4.5), the requested points r_P with
// their K_P and L_P, and det Phi_phi per block. Later quantities read them from here; the
// generated functions (codegen/functions.h) only choose where each one is stored.
//
// Everything follows the block order of blocks.h: Phi_phi is block lower triangular, so
// K and L are found block by block (forward substitution), each block's small system
// solved in closed form (adjugate over determinant) up to kMaxSymbolicSolve unknowns and
// by a fixed-size LU above. K and L are symbols: the locals that `k_program` and
// `l_program` define (statement programs, evaluated once by the generated code).
//
// L comes from differentiating Phi_phi K + Phi_q = 0 along the motion: with
// x = (q, phi) and V = dx/dq = [I; K],
//   Phi_phi L(:, j, k) = -gamma(:, j, k),  gamma_i(j, k) = sum_ab d2Phi_i/dx_a dx_b V_aj V_bk,
// so only second partial derivatives of Phi are taken, never derivatives of K. The same
// derivative along the motion gives K and L of any expression in (q, phi) (motion.h, with
// this table's K and L or with the slots a generated function reads): the points' here, the
// massive links' centres of mass and angles (`bodies`, bodies.h) wherever they are read.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "analysis/kinematics.h"
#include "symbolic/block_system.h"
#include "symbolic/blocks.h"
#include "symbolic/bodies.h"
#include "symbolic/motion.h"
#include "symbolic/program.h"

namespace mechgen {

/// What the table derives (outputs.order today: 0 positions, 1 + K, 2 + L).
struct Requested {
  bool K = true, L = true;
};

class SymbolicTable {
 public:
  /// Derives everything `m.outputs` requests. `k` must outlive the table (it is read, not copied).
  SymbolicTable(const Model& m, const Kinematics& k, Strategy strategy = Strategy::kBlocks);

  const Kinematics& kinematics() const { return k_; }
  int nq() const { return k_.nq(); }
  int nphi() const { return k_.nphi(); }

  // ---- Quantities ----
  std::vector<Block> blocks;  ///< the solve order
  Requested requested;
  bool sparse_Phi_phi = false, sparse_Phi_q = false;  ///< some entry is structurally zero
  bool numeric_solve = false;                         ///< some block uses Eigen's LU (K and L, or Newton's method)
  int largest_block = 0;
  std::string strategy;  ///< one sentence for the generated header and the report

  /// Set-up of each block's Phi_phi (closed form: named entries, det, 1/det; LU: the
  /// factorization), then K block by block. K(i, j) = d phi_i / d q_j.
  Program k_program;
  std::vector<std::vector<GiNaC::ex>> K;  ///< nphi x nq, in terms of k_program's locals
  /// Phi_phi with the closed-form blocks' entries replaced by their named locals (valid
  /// after k_program; it shares them).
  GiNaC::matrix Phi_phi_named;
  /// L block by block (after k_program), for the input pairs j <= k.
  Program l_program;
  std::vector<std::pair<int, int>> pairs;       ///< (j, k), j <= k
  std::vector<std::vector<GiNaC::ex>> L_pairs;  ///< nphi x pairs
  /// L(i, j + nq k) = d K(i, j) / d q_k (symmetric in j, k).
  GiNaC::ex L(int i, int j, int k) const { return L_pairs[i][PairIndex(j, k)]; }

  /// Requested points: r_P[m][a], K_P[m][a][j], L_P[m][a][j + nq k].
  std::vector<std::array<GiNaC::ex, 2>> r_P;
  std::vector<std::array<std::vector<GiNaC::ex>, 2>> K_P, L_P;

  /// The moving links with mass: r_G and theta in (q, phi) (bodies.h; their coefficients
  /// along the motion come from BodyCoefficients with the K and L the caller reads).
  std::vector<MassiveLink> bodies;

  /// det Phi_phi as the product of the blocks' determinants in the model's own row and
  /// column order: `det_program` defines det_block<i>, `det_Phi_phi` is their product.
  Program det_program;
  GiNaC::ex det_Phi_phi;

  // ---- Operations later quantities use ----
  /// The derivative along the motion (motion.h) with this table's K and L (named locals of
  /// k_program and l_program).
  Motion motion() const;
  /// sum_a df/dx_a V(a, j): the derivative of f(q, phi) along the motion with q_j.
  GiNaC::ex Along(const GiNaC::ex& f, int j) const;
  /// K_f(j) = df/dq_j along the motion (needs K).
  std::vector<GiNaC::ex> VelocityCoefficients(const GiNaC::ex& f) const;
  /// L_f(j + nq k) = d2f/dq_j dq_k along the motion, from K_f (needs K and L).
  std::vector<GiNaC::ex> CentripetalCoefficients(const GiNaC::ex& f, const std::vector<GiNaC::ex>& K_f) const;

 private:
  int PairIndex(int j, int k) const;
  void OrderAndDescribe(const Model& m, Strategy strategy);
  void FindSparsity();
  void SolveVelocityCoefficients(std::vector<BlockSystem>* systems);
  void SolveCentripetalCoefficients(std::vector<BlockSystem>* systems);
  void PointCoefficients();
  void BlockDeterminants();

  const Kinematics& k_;
};

/// K = -Phi_phi^-1 Phi_q as expressions in q, phi and p (for the report; small systems).
GiNaC::matrix SymbolicK(const Kinematics& k);

}  // namespace mechgen
