// The solve structure of Phi(q, phi) = 0 over phi (Paul §4.2, §4.3): a block-triangular
// ordering of the equations, so that weakly coupled loops are solved one after another and
// strongly coupled loops together, and the recognition of blocks that are dyads with a
// closed-form position solution (circle–circle, circle–line, line–line intersections).
//
// Ordering: a maximum matching of equations to unknowns (from the sparsity of Phi_phi),
// then the strongly connected components of the dependency graph between unknowns, in
// dependency order (Tarjan) — the Dulmage–Mendelsohn fine decomposition of a square,
// structurally regular Phi_phi.
#pragma once

#include <string>
#include <vector>

#include "analysis/kinematics.h"

namespace mechgen {

/// How a block's positions are found.
enum class BlockSolve {
  kNewton,  ///< Newton–Raphson on the block (no closed form recognized)
  kRR,      ///< two angles u, v: R(u) a + R(v) b = w (circle–circle; dyad RRR)
  kRS,      ///< angle u and displacement s: R(u) a(s) = w(s), a and w affine in s
            ///< (circle–line; dyads RRP and RPR)
  kSS,      ///< two displacements: w + s0 e0 + s1 e1 = 0 (line–line; dyad PRP)
  kAngle,   ///< one angle u: c0 + c1 cos u + c2 sin u = 0, u = atan2(c2, c1) ± acos(-c0 / rho)
  kLinear,  ///< one unknown x: c0 + c1 x = 0
};

struct Block {
  std::vector<int> rows;  ///< rows of Phi
  std::vector<int> cols;  ///< indices into phi, solved by this block
  BlockSolve solve = BlockSolve::kNewton;
  // Closed forms, in the block's own unknowns x = phi(cols):
  //   kRR: R(u) a + R(v) b + w0 = 0            (u = cols[iu], v = the other)
  //   kRS: R(u) a(s) + w0(s) = 0, a, w0 affine in s
  //   kSS: w0 + s0 e0 + s1 e1 = 0
  int iu = 0;               ///< position in cols of the angle u (kRR, kRS)
  Vec2 a, b, w0, e0, e1;    ///< vectors as above (free of the block's unknowns unless noted)
  GiNaC::ex c0, c1, c2;     ///< kAngle, kLinear coefficients
  int default_mode = 1;     ///< assembly-mode sign matching the model's assembly guess
  std::vector<int> named_modes;  ///< per Model::assembly_modes: its mode of this block
  std::string Describe(const Kinematics& k) const;  ///< "rows 0-1 -> theta_coupler, theta_rocker: closed form (RRR dyad)"
};

/// How the generated code is organized.
enum class Strategy {
  kBlocks,      ///< block-triangular order, closed-form dyads (the default)
  kMonolithic,  ///< one block: Newton over all loops with a dense LU (for comparison)
};

/// Orders Phi into blocks. Fails (ModelError) if Phi_phi is structurally singular: some
/// unknown appears in no equation it can be solved from.
std::vector<Block> OrderBlocks(const Model& m, const Kinematics& k, Strategy strategy = Strategy::kBlocks);

}  // namespace mechgen
