// The velocity coefficients K = -Phi_phi^-1 Phi_q and centripetal coefficients
// L = dK/dq (Paul §4.5), the points' coefficients, and the statement programs of the
// generated functions (EvalPhi, EvalCoefficients, EvalScene, SolvePositions).
//
// Everything follows the block order of blocks.h: Phi_phi is block lower triangular, so
// K and L are found block by block (forward substitution), each block's small system
// solved in closed form (adjugate over determinant) up to kMaxSymbolicSolve unknowns and
// by a fixed-size LU above. Positions are solved block by block too: closed-form dyads,
// or Newton–Raphson on the block.
//
// L comes from differentiating Phi_phi K + Phi_q = 0 along the motion: with
// x = (q, phi) and V = dx/dq = [I; K],
//   Phi_phi L(:, j, k) = -gamma(:, j, k),  gamma_i(j, k) = sum_ab d2Phi_i/dx_a dx_b V_aj V_bk,
// so only second partial derivatives of Phi are taken, never derivatives of K.
#pragma once

#include <string>
#include <vector>

#include "blocks.h"
#include "cxx_code.h"
#include "analysis/kinematics.h"

namespace mechgen {

/// Largest block solved in closed form (adjugate / determinant, then CSE); larger blocks
/// are emitted as a fixed-size LU solve of the generated matrices.
constexpr int kMaxSymbolicSolve = 3;

struct Derivation {
  std::vector<Block> blocks;
  Program phi;           ///< EvalPhi: Phi, Phi_phi, Phi_q
  Program coefficients;  ///< EvalCoefficients: K, L, r_P, K_P, L_P (as requested)
  Program scene;         ///< EvalScene
  std::vector<Program> positions;  ///< SolvePositions, one program per block
  Program det;           ///< EvalDetPhiPhi: det Phi_phi as the product of the blocks' determinants
  std::vector<bool> trig_done;     ///< per phi: SolvePositions writes its sin and cos from a closed form
  int coefficient_trig_calls = 0;
  int position_trig_calls = 0;     ///< sin/cos of the inputs, before SolvePositions's blocks  ///< sin/cos calls of EvalCoefficients's prologue (Raw lines, not counted by the printer)
  bool numeric_solve = false;  ///< some block uses Eigen's LU
  std::string strategy;  ///< one sentence for the generated header and the report
};

/// Builds the programs; `printer` gets names for q, phi and the parameters.
Derivation Derive(const Model& m, const Kinematics& k, CxxPrinter* printer, Strategy strategy = Strategy::kBlocks);

/// K = -Phi_phi^-1 Phi_q as expressions in q, phi and p (for the report; small systems).
GiNaC::matrix SymbolicK(const Kinematics& k);

}  // namespace mechgen
