// One block of Phi_phi set up for solving Phi_phi(rows, cols) X = -R block by block (the
// forward substitution of K, L and the design derivatives, symbolic/table.h and design.h):
// in closed form up to kMaxSymbolicSolve unknowns (its entries, det, 1/det and the adjugate
// inverse's entries named as locals), by a fixed-size LU above. The set-up statements go to
// the program given to the constructor; each Solve appends its own.
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "symbolic/blocks.h"
#include "symbolic/linalg.h"
#include "symbolic/program.h"

namespace mechgen {

/// Largest block solved in closed form (adjugate / determinant, then CSE); larger blocks
/// are emitted as a fixed-size LU solve of the generated matrices.
constexpr int kMaxSymbolicSolve = 3;

namespace internal {
inline std::string N(int i) { return std::to_string(i); }
inline std::string Idx(int i, int j) { return "(" + N(i) + ", " + N(j) + ")"; }
}  // namespace internal

struct BlockSystem {
  const Block& block;
  int index;
  bool closed_form;
  GiNaC::matrix J;              // closed form: the block of Phi_phi as named entries
  GiNaC::matrix inv;            // closed form: J^-1 in terms of named entries
  std::vector<bool> inv_named;  // closed form: entry (r, c) named yet
  std::string lu;               // numeric: the LU's name

  BlockSystem(const Block& b, int i, const Kinematics& k, Program* P)
      : block(b), index(i), closed_form(static_cast<int>(b.cols.size()) <= kMaxSymbolicSolve) {
    const int n = static_cast<int>(b.cols.size());
    if (closed_form) {
      J = GiNaC::matrix(n, n);
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          P->push_back(Define("Phi_phi_" + internal::N(b.rows[r]) + "_" + internal::N(b.cols[c]), k.Phi_phi(b.rows[r], b.cols[c]), &J(r, c)));
      // det is named before it is inverted: GiNaC normalizes the sign of a sum raised to
      // an integer power by its (run-dependent) leading term, which would make the output
      // differ between runs. A symbol's power has no such freedom.
      GiNaC::ex det, inv_det;
      P->push_back(Define("det_block" + internal::N(i), J.determinant(GiNaC::determinant_algo::laplace), &det));
      P->push_back(Define("inv_det_block" + internal::N(i), 1 / det, &inv_det));
      inv = AdjugateInverse(J, inv_det);
      inv_named.assign(n * n, false);
    } else {
      const std::string name = "J_block" + internal::N(i);
      lu = "lu_block" + internal::N(i);
      P->push_back(Linear(Statement::Kind::kMatrix, name, n, n, {}, /*zero=*/true));  // large blocks are sparse
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          if (!k.Phi_phi(b.rows[r], b.cols[c]).is_zero())
            P->push_back(Store(name + internal::Idx(r, c), k.Phi_phi(b.rows[r], b.cols[c])));
      P->push_back(Linear(Statement::Kind::kLuFactor, lu, n, n, {name}));
    }
  }

  // X = -J^-1 R; names X entries prefix_<col>_<suffix j>.
  std::vector<std::vector<GiNaC::ex>> Solve(const std::vector<std::vector<GiNaC::ex>>& R, const std::string& prefix,
                                     const std::vector<std::string>& suffix, Program* P) {
    const int n = static_cast<int>(block.cols.size()), m = static_cast<int>(suffix.size());
    std::vector<std::vector<GiNaC::ex>> X(n, std::vector<GiNaC::ex>(m));
    if (closed_form) {
      // Right-hand sides are named first: a sum times the inverse would be expanded into
      // many more products (and GiNaC's sign normalization of sums inside products depends
      // on its run-dependent term order).
      std::vector<std::vector<GiNaC::ex>> Rn(n, std::vector<GiNaC::ex>(m));
      // The inverse's entries are named: K and L (one column per input pair) share them.
      // An entry is named where it is first used: its column's right-hand sides can all
      // be zero (a planetary train's ring mesh has no Phi_q), and an unused local is a
      // warning in the generated code.
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
          bool used = false;
          for (int j = 0; j < m; ++j) used |= !R[c][j].expand().is_zero();
          if (!used || inv_named[r * n + c]) continue;
          inv_named[r * n + c] = true;
          if (!GiNaC::is_a<GiNaC::symbol>(inv(r, c)) && !GiNaC::is_a<GiNaC::numeric>(inv(r, c)))
            P->push_back(Define("Phi_phi_inv_" + internal::N(block.cols[r]) + "_" + internal::N(block.rows[c]), inv(r, c), &inv(r, c)));
        }
      for (int r = 0; r < n; ++r)
        for (int j = 0; j < m; ++j) {
          const GiNaC::ex e = R[r][j].expand();
          if (GiNaC::is_a<GiNaC::add>(e))
            P->push_back(Define(prefix + "_rhs_" + internal::N(block.rows[r]) + "_" + suffix[j], e, &Rn[r][j]));
          else
            Rn[r][j] = e;
        }
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
          GiNaC::ex s = 0;
          for (int r = 0; r < n; ++r) s += inv(i, r) * Rn[r][j];
          P->push_back(Define(prefix + "_" + internal::N(block.cols[i]) + "_" + suffix[j], -s, &X[i][j]));
        }
      return X;
    }
    const std::string rhs = prefix + "_rhs_block" + internal::N(index), sol = prefix + "_block" + internal::N(index);
    P->push_back(Linear(Statement::Kind::kMatrix, rhs, n, m));
    for (int r = 0; r < n; ++r)
      for (int j = 0; j < m; ++j) P->push_back(Store(rhs + internal::Idx(r, j), R[r][j]));
    Statement solve = Linear(Statement::Kind::kLuSolve, sol, n, m, {lu, rhs});
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        GiNaC::symbol s(sol + internal::Idx(i, j));
        solve.names.emplace_back(s, sol + internal::Idx(i, j));
        X[i][j] = s;
      }
    P->push_back(solve);
    return X;
  }
};


}  // namespace mechgen
