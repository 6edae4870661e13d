// Design sensitivities (issue 27): the derivatives of the kinematic quantities with respect
// to the model's design parameters p_d (`design:`, model/design.cc), derived symbolically.
//
// The design parameters are treated as further inputs: with x = (q, p, phi), the loop
// closure Phi(q, p, phi) = 0 gives, column by column and block by block in the solve order
// (the forward substitution of K, symbolic/table.h, with the same block systems),
//   Phi_phi dphi/dp_d = -Phi_p_d                                   (positions),
//   Phi_phi dK(:, j)/dp_d = -D_d(dPhi/dq_j along the motion)        (velocity coefficients),
//   Phi_phi dL(:, j, k)/dp_d = -D_d(d2Phi/dq_j dq_k along the motion) (centripetal coefficients),
// where D_d is the total derivative with respect to p_d: through p_d itself, through phi
// (dphi/dp_d) and through the coefficients the expression holds as named locals (K through
// dK/dp_d, L through dL/dp_d), the unknown block's own term left on the left-hand side. So
// only partial derivatives of Phi are taken and each block's Phi_phi is set up once for
// all of K, L and their design derivatives. A point r_P(q, p, phi) follows: dr_P/dp_d =
// D_d r_P, dK_P/dp_d = D_d K_P, dL_P/dp_d = D_d L_P.
#pragma once

#include <ginac/ginac.h>

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "analysis/grashof.h"
#include "analysis/topology.h"
#include "model/model.h"
#include "symbolic/dynamics.h"
#include "symbolic/program.h"
#include "symbolic/slot.h"
#include "symbolic/statics.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"

namespace mechgen {

/// A design check (EvalDesignChecks): a signed margin of the parameters, >= 0 where the design
/// is acceptable, with its derivatives: for synthesis, as a constraint.
struct DesignCheck {
  std::string name;  ///< "grashof_loop0", "length_crank_loop0"
  std::string what;  ///< a sentence for the header
  GiNaC::ex margin;  ///< in the parameters' symbols
  std::vector<GiNaC::ex> d;  ///< d margin / dp_d
};

struct DesignTable {
  /// Derives what the table has (positions, K and L as requested, the points) with respect
  /// to m.design's parameters, and the design checks of the four-bar loops (`four_bars` of
  /// topology `topo`, may be null). Empty (nd() == 0) without a design section.
  DesignTable(const Model& m, const SymbolicTable& t, const Topology* topo = nullptr,
              const std::vector<FourBarLoop>* four_bars = nullptr,
              const std::vector<TransmissionAngle>* transmission = nullptr);

  /// Per four-bar loop: each link's length (> 0) and Grashof's margin (p + q) - (s + l), >= 0
  /// for a Grashof loop (a link turns fully), with s, l, p, q taken as the parameters' defaults
  /// order them (valid while that order holds).
  std::vector<DesignCheck> checks;
  /// Locals the checks' margins read (a cam's law values at a fixed angle), before them.
  Program checks_program;

  int nd() const { return static_cast<int>(p.size()); }
  bool has_K = false, has_L = false;
  std::vector<GiNaC::symbol> p;    ///< the design parameters' symbols
  std::vector<std::string> names;  ///< their names

  /// The body that computes all of them: each block's Phi_phi set up once, then K, dphi/dp,
  /// dK/dp, L and dL/dp by forward substitution over the blocks.
  Program program;
  /// K_value[i][j], L_value[i][j + nq k]: K and L as this program computes them (its locals, or
  /// expressions of them), for the adjoint's reverse sweep (DesignDynamicsProduct).
  std::vector<std::vector<GiNaC::ex>> K_value, L_value;
  /// dphi_dp[i][d] = dphi_i/dp_d.
  std::vector<std::vector<GiNaC::ex>> dphi_dp;
  /// dK_dp[i][j + nq d] = dK(i, j)/dp_d (has_K).
  std::vector<std::vector<GiNaC::ex>> dK_dp;
  /// dL_dp[i][j + nq k + nq^2 d] = dL(i, j, k)/dp_d (has_L), symmetric in j, k.
  std::vector<std::vector<GiNaC::ex>> dL_dp;
  /// Per requested point and axis (0: x, 1: y): dr_P/dp_d [d], dK_P/dp_d [j + nq d],
  /// dL_P/dp_d [j + nq k + nq^2 d].
  std::vector<std::array<std::vector<GiNaC::ex>, 2>> dr_P_dp, dK_P_dp, dL_P_dp;
  /// dmu_dp[i][d] = d mu_i/dp_d of each transmission angle mu = atan2(|cross|, dot):
  /// sign(cross) (dot dcross - cross ddot) / (cross^2 + dot^2) (undefined at a toggle, cross = 0).
  std::vector<std::vector<GiNaC::ex>> dmu_dp;
};

/// The highest derivative order d of a cam law camlaw(i, d, x) in e (-1: none).
int MaxCamLawOrder(const GiNaC::ex& e);

/// Forward mode over a straight-line program, symbolically, in n directions (the design
/// parameters; the inputs q and their velocities qd, symbolic/jacobian.h): D_d v = explicit_partial(v, d) +
/// sum over the symbols x that v reads and that `derivative` has: dv/dx D_d x, in `order`.
struct ForwardSeeds {
  int n = 0;
  std::vector<std::string> suffix;  ///< per direction: the derivative locals are d_<target>_<suffix>
  std::function<GiNaC::ex(const GiNaC::ex& v, int d)> explicit_partial;
  std::map<GiNaC::ex, std::vector<GiNaC::ex>, GiNaC::ex_is_less> derivative;  ///< D_d x per symbol x
  std::vector<GiNaC::ex> order;  ///< the symbols of `derivative` in the order they were made
  /// A partial dv/dx is named once (a local chain_prefix<i>) where n > 1, it is not one factor and
  /// at least this many directions of x are not zero.
  int min_shared = 1;
};
/// The derivative locals of `program` (appended to *locals, after which they read the program's
/// own) and D_d of each output; `seeds` gains the program's locals.
std::vector<std::vector<GiNaC::ex>> ForwardOverProgram(ForwardSeeds* seeds, const Program& program,
                                                       const std::vector<GiNaC::ex>& outputs,
                                                       const std::string& chain_prefix, Program* locals);

/// A straight-line program's locals and some expressions of them, differentiated with respect
/// to the design parameters (forward mode over the program, symbolically): D_d v = dv/dp_d + sum
/// over what v reads of dv/dx D_d x, x running over phi (dphi/dp read from EvalDesignDerivatives'
/// output), the coefficients K and L (dK/dp, dL/dp read from there too), Phi_phi (its expression
/// differentiated in p and phi) and the locals before it; the arguments (qd, qdd, t) and the
/// given friction loads are held. Not possible for a program with an LU (a large block).
struct ProgramDesign {
  bool possible = false;
  std::string why_not;
  SlotSymbols slots;   ///< what the derivatives read of EvalDesignDerivatives' output
  Program program;     ///< the derivative locals, after the program's own (which they read)
  std::vector<std::vector<GiNaC::ex>> d;  ///< per output expression: its D_d, d = 0..nd-1
};
ProgramDesign DifferentiateProgram(const Kinematics& k, const DesignTable& dt, const Program& program,
                                   const SlotSymbols& reads, const std::vector<GiNaC::ex>& outputs,
                                   const std::string& chain_prefix);

/// The statics' design sensitivities (EvalStaticsDesign): d/dp_d of Q, the drive, V and the
/// reactions at a closed configuration, q held and the given friction loads held
/// (DifferentiateProgram over the statics program).
struct DesignStatics {
  DesignStatics(const Model& m, const Kinematics& k, const StaticsTable& st, const DesignTable& dt);

  /// False (with the reason) where the statics program is not straight-line (a large block's
  /// reactions by an LU) or there is nothing to differentiate.
  bool possible = false;
  std::string why_not;
  /// What the derivatives read of EvalDesignDerivatives' output (slot.h: kDphiDp, kDKDp, kDLDp).
  SlotSymbols slots;
  /// The derivative locals, after the statics program's own (which they read).
  Program program;
  std::vector<std::vector<GiNaC::ex>> dQ, ddrive;  ///< nq x nd (forces)
  std::vector<GiNaC::ex> dV;                       ///< nd (potential)
  std::vector<std::vector<GiNaC::ex>> dR;          ///< per reaction component x nd
};

/// The dynamics' design sensitivities (EvalDynamicsDesign): d/dp_d of I, dI/dq (I' for one DOF),
/// h, Q, T and V at (t, q, qd), those held (DifferentiateProgram over the dynamics program).
struct DesignDynamics {
  DesignDynamics(const Model& m, const Kinematics& k, const DynamicsTable& dyn, const DesignTable& dt);
  bool possible = false;
  std::string why_not;
  SlotSymbols slots;
  Program program;
  std::vector<std::vector<GiNaC::ex>> dI;      ///< I[j + nq k] x nd
  std::vector<std::vector<GiNaC::ex>> ddI_dq;  ///< dI_dq[j + nq (k + nq l)] x nd
  std::vector<std::vector<GiNaC::ex>> dh, dQ;  ///< nq x nd
  std::vector<GiNaC::ex> dT, dV;               ///< nd
};

/// The adjoint's vector-Jacobian product (EvalDynamicsDesignProduct, dynamics/adjoint.h): the
/// gradient with respect to p of y = mu^T (Q - h - I qdd) at (t, q, qd), mu and qdd held, by
/// reverse mode over the dynamics program (symbolically: each local's adjoint named once, the
/// locals swept from the last), then over the design table's program of K, L (and Phi_phi) from
/// (q, phi, p) seeded with their adjoints: phi's total adjoint zbar_phi and the explicit ones,
/// d/dp_d y = (explicit) + sum_i zbar_phi_i dphi_i/dp_d, dphi/dp = -Phi_phi^-1 dPhi/dp (the
/// adjoint of the position constraints). The sweeps are one pass whatever N is; only dphi/dp and
/// the last dot products have N columns, where EvalDynamicsDesign carries N directions through
/// every local. Where the design table's program is not straight-line (an LU), the first sweep's
/// adjoints are dotted with dK/dp and dL/dp instead (read in `slots`).
struct DesignDynamicsProduct {
  DesignDynamicsProduct(const Kinematics& k, const DynamicsTable& dyn, const DesignTable& dt);
  bool possible = false;
  std::string why_not;
  SlotSymbols slots;            ///< what it reads of EvalDesignDerivatives' output
  std::vector<GiNaC::ex> mu, qdd;  ///< the weights and the accelerations (arguments), nq each
  Program program;              ///< the adjoint locals, after the dynamics program's own
  std::vector<GiNaC::ex> grad;  ///< d y/dp_d, d = 0..nd-1
};

}  // namespace mechgen

namespace mechgen {

/// The shaking force and moment's design sensitivities (EvalShakingDesign, with `shaking`):
/// d/dp_d of F = -sum m a_G and M = sum (r_G x F_link - J alpha) about O at (q, qd, qdd), those
/// held (DifferentiateProgram over the shaking program, its locals pruned first to what F and
/// M read: the reactions of the kinetostatics are not differentiated).
struct DesignShaking {
  DesignShaking(const Kinematics& k, const DynamicsTable& dyn, const DesignTable& dt);
  bool possible = false;
  std::string why_not;
  SlotSymbols slots;
  Program program;  ///< the pruned shaking program followed by its derivative locals
  std::vector<std::vector<GiNaC::ex>> dF;  ///< 2 x nd (x, y)
  std::vector<GiNaC::ex> dM;               ///< nd
};

}  // namespace mechgen
