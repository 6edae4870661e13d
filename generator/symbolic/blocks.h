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

/// Where an input's declared range passes a change point of a block: its two assembly
/// modes meet at an isolated input (the linkage folds flat, e.g. a parallelogram at 0 and
/// 180 deg), and the loop closes on both sides. The generated solve keeps a block's mode
/// through it, which past the point is the other branch of the linkage; a smooth motion
/// through it (the runtime's PassSingularity with Crossing::kFollowTangent) changes mode.
struct ChangePoint {
  enum class Kind {
    kModesMeet,        ///< the relative discriminant (SolveReport::branch_measure) touches 0
    kCentresCoincide,  ///< an RRR dyad's circle centres coincide: it is not determined there
  };
  int input = 0;       ///< index into q
  double value = 0;    ///< the input there (model units, radians for an angle)
  Kind kind = Kind::kModesMeet;
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
  /// Change points within the inputs' declared ranges (at the parameters' defaults, the
  /// other inputs at their assembly values), by input and value.
  std::vector<ChangePoint> change_points;
  std::string Describe(const Kinematics& k) const;  ///< "rows 0-1 -> theta_coupler, theta_rocker: closed form (RRR dyad)"
};

/// One sentence per block with change points, for the generator to print: which input
/// reaches them and where, and which branch the model's modes name past them.
std::vector<std::string> ChangePointNotes(const Kinematics& k, const std::vector<Block>& blocks);

/// How the generated code is organized.
enum class Strategy {
  kBlocks,      ///< block-triangular order, closed-form dyads (the default)
  kMonolithic,  ///< one block: Newton over all loops with a dense LU (for comparison)
};

/// Orders Phi into blocks. Fails (ModelError) if Phi_phi is structurally singular: some
/// unknown appears in no equation it can be solved from.
std::vector<Block> OrderBlocks(const Model& m, const Kinematics& k, Strategy strategy = Strategy::kBlocks);

}  // namespace mechgen
