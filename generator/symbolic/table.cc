// The symbolic table: K, L, the points' coefficients and the blocks' determinants. See table.h.
#include "symbolic/table.h"

#include <algorithm>

#include "symbolic/block_system.h"
#include "symbolic/linalg.h"

namespace mechgen {
namespace {

using GiNaC::ex;

std::string N(int i) { return std::to_string(i); }
std::string Idx(int i, int j) { return "(" + N(i) + ", " + N(j) + ")"; }

// Sign of the permutation that takes Phi_phi to its block order (rows and columns).
int PermutationSign(const std::vector<Block>& blocks, int n) {
  std::vector<int> rows, cols;
  for (const Block& b : blocks) {
    rows.insert(rows.end(), b.rows.begin(), b.rows.end());
    cols.insert(cols.end(), b.cols.begin(), b.cols.end());
  }
  auto sign = [n](std::vector<int> p) {
    int s = 1;
    for (int i = 0; i < n; ++i)
      while (p[i] != i) {
        std::swap(p[i], p[p[i]]);
        s = -s;
      }
    return s;
  };
  return sign(rows) * sign(cols);
}

}  // namespace

GiNaC::matrix SymbolicK(const Kinematics& k) {
  const int n = k.nphi();
  const ex det = k.Phi_phi.determinant(GiNaC::determinant_algo::laplace);
  const GiNaC::matrix inv = AdjugateInverse(k.Phi_phi, 1 / det);
  GiNaC::matrix K(n, k.nq());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k.nq(); ++j) {
      ex s = 0;
      for (int m = 0; m < n; ++m) s += inv(i, m) * k.Phi_q(m, j);
      K(i, j) = -s;
    }
  return K;
}


SymbolicTable::SymbolicTable(const Model& m, const Kinematics& k, Strategy strategy) : k_(k) {
  requested.K = m.outputs.order >= 1;
  requested.L = m.outputs.order >= 2;
  OrderAndDescribe(m, strategy);
  FindSparsity();
  Phi_phi_named = k.Phi_phi;
  r_P.resize(k.points.size());
  for (size_t pt = 0; pt < k.points.size(); ++pt) r_P[pt] = {k.points[pt][0], k.points[pt][1]};
  bodies = MassiveLinks(m, k);
  std::vector<BlockSystem> systems;
  if (requested.K) {
    SolveVelocityCoefficients(&systems);
    if (requested.L) SolveCentripetalCoefficients(&systems);
    PointCoefficients();
  }
  BlockDeterminants();
}

void SymbolicTable::OrderAndDescribe(const Model& m, Strategy strategy) {
  blocks = OrderBlocks(m, k_, strategy);
  for (const Block& b : blocks) largest_block = std::max(largest_block, static_cast<int>(b.cols.size()));
  numeric_solve = largest_block > kMaxSymbolicSolve;  // an LU for K and L (and Eigen/LU)
  for (const Block& b : blocks) numeric_solve |= b.solve == BlockSolve::kNewton;  // Newton's LU
  if (strategy == Strategy::kMonolithic)
    this->strategy = "monolithic (mechgen --strategy monolithic): one Newton solve over all " + N(nphi()) +
                     " unknowns and K, L by one dense LU of Phi_phi; large systems need "
                     "EIGEN_STACK_ALLOCATION_LIMIT raised (fixed-size matrices on the stack).";
  else
    this->strategy = "Phi_phi is block lower triangular with " + N(static_cast<int>(blocks.size())) +
                     " block(s) of at most " + N(largest_block) + " unknowns; each block's system is solved " +
                     (numeric_solve ? "in closed form up to " + N(kMaxSymbolicSolve) + " unknowns, by a fixed-size LU above"
                                    : "in closed form (adjugate over determinant)") +
                     ", and K and L by forward substitution over the blocks.";
}

// The Jacobians are sparse in multi-loop mechanisms: only their non-zero entries are
// stored, after a setZero().
void SymbolicTable::FindSparsity() {
  for (int i = 0; i < k_.nc(); ++i) {
    for (int j = 0; j < nphi(); ++j) sparse_Phi_phi |= k_.Phi_phi(i, j).is_zero();
    for (int j = 0; j < nq(); ++j) sparse_Phi_q |= k_.Phi_q(i, j).is_zero();
  }
}

// K block by block: Phi_phi(rows, cols) K(cols, :) = -(Phi_q(rows, :) + Phi_phi(rows,
// earlier cols) K(earlier cols, :)).
void SymbolicTable::SolveVelocityCoefficients(std::vector<BlockSystem>* systems) {
  K.assign(nphi(), std::vector<ex>(nq()));
  std::vector<std::string> q_suffix;
  for (int j = 0; j < nq(); ++j) q_suffix.push_back(N(j));
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    systems->emplace_back(b, static_cast<int>(bi), k_, &k_program);
    std::vector<std::vector<ex>> R(b.rows.size(), std::vector<ex>(nq()));
    for (size_t r = 0; r < b.rows.size(); ++r)
      for (int j = 0; j < nq(); ++j) {
        ex s = k_.Phi_q(b.rows[r], j);
        for (size_t pb = 0; pb < bi; ++pb)
          for (int c : blocks[pb].cols) s += k_.Phi_phi(b.rows[r], c) * K[c][j];
        R[r][j] = s;
      }
    const auto X = systems->back().Solve(R, "K", q_suffix, &k_program);
    for (size_t i = 0; i < b.cols.size(); ++i)
      for (int j = 0; j < nq(); ++j) K[b.cols[i]][j] = X[i][j];
  }
  for (const BlockSystem& s : *systems)
    if (s.closed_form)
      for (size_t r = 0; r < s.block.rows.size(); ++r)
        for (size_t c = 0; c < s.block.cols.size(); ++c) Phi_phi_named(s.block.rows[r], s.block.cols[c]) = s.J(r, c);
}

// L: Phi_phi L(:, j, k) = -gamma(:, j, k), j <= k (L is symmetric in j, k).
void SymbolicTable::SolveCentripetalCoefficients(std::vector<BlockSystem>* systems) {
  std::vector<std::string> pair_suffix;
  for (int j = 0; j < nq(); ++j)
    for (int kk = j; kk < nq(); ++kk) {
      pairs.emplace_back(j, kk);
      pair_suffix.push_back(N(j) + "_" + N(kk));
    }
  L_pairs.assign(nphi(), std::vector<ex>(pairs.size()));
  const Motion mo = motion();
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    std::vector<std::vector<ex>> R(b.rows.size(), std::vector<ex>(pairs.size()));
    for (size_t r = 0; r < b.rows.size(); ++r)
      for (size_t pj = 0; pj < pairs.size(); ++pj) {
        ex s = mo.Along(mo.Along(k_.Phi[b.rows[r]], pairs[pj].first), pairs[pj].second);
        for (size_t pb = 0; pb < bi; ++pb)
          for (int c : blocks[pb].cols) s += k_.Phi_phi(b.rows[r], c) * L_pairs[c][pj];
        R[r][pj] = s;
      }
    const auto X = (*systems)[bi].Solve(R, "L", pair_suffix, &l_program);
    for (size_t i = 0; i < b.cols.size(); ++i)
      for (size_t pj = 0; pj < pairs.size(); ++pj) L_pairs[b.cols[i]][pj] = X[i][pj];
  }
}

int SymbolicTable::PairIndex(int j, int k) const {
  const int lo = std::min(j, k), hi = std::max(j, k);
  for (size_t pj = 0; pj < pairs.size(); ++pj)
    if (pairs[pj].first == lo && pairs[pj].second == hi) return static_cast<int>(pj);
  return -1;
}

Motion SymbolicTable::motion() const {
  return Motion(
      k_, [this](int i, int j) { return K[i][j]; }, [this](int i, int j, int k) { return L(i, j, k); });
}

ex SymbolicTable::Along(const ex& f, int j) const { return motion().Along(f, j); }

std::vector<ex> SymbolicTable::VelocityCoefficients(const ex& f) const { return motion().VelocityCoefficients(f); }

std::vector<ex> SymbolicTable::CentripetalCoefficients(const ex& f, const std::vector<ex>& K_f) const {
  return motion().CentripetalCoefficients(f, K_f);
}

void SymbolicTable::PointCoefficients() {
  K_P.resize(r_P.size());
  L_P.resize(r_P.size());
  const Motion mo = motion();
  for (size_t pt = 0; pt < r_P.size(); ++pt)
    for (int a = 0; a < 2; ++a) {
      K_P[pt][a] = mo.VelocityCoefficients(r_P[pt][a]);
      if (requested.L) L_P[pt][a] = mo.CentripetalCoefficients(r_P[pt][a], K_P[pt][a]);
    }
}

// det Phi_phi: the product of the blocks' determinants, each in closed form up to
// kMaxSymbolicSolve unknowns and by an LU above.
void SymbolicTable::BlockDeterminants() {
  ex product = 1;
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    const int n = static_cast<int>(b.cols.size());
    GiNaC::matrix J(n, n);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) J(r, c) = k_.Phi_phi(b.rows[r], b.cols[c]);
    const std::string det_name = "det_block" + N(static_cast<int>(bi));
    if (n <= kMaxSymbolicSolve) {
      ex det;
      det_program.push_back(Define(det_name, J.determinant(GiNaC::determinant_algo::laplace), &det));
      product *= det;
    } else {
      const std::string name = "J_block" + N(static_cast<int>(bi));
      det_program.push_back(Linear(Statement::Kind::kMatrix, name, n, n, {}, /*zero=*/true));
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          if (!J(r, c).is_zero()) det_program.push_back(Store(name + Idx(r, c), J(r, c)));
      Statement det = Linear(Statement::Kind::kLuDeterminant, det_name, n, n, {name});
      GiNaC::symbol s(det_name);
      det.names.emplace_back(s, det_name);
      det_program.push_back(det);
      product *= s;
    }
  }
  // The sign of det Phi_phi depends on the row and column order: it is reported for the
  // model's own order (rows of Phi, columns of phi), i.e. with the permutations' signs.
  det_Phi_phi = product * PermutationSign(blocks, nphi());
}

}  // namespace mechgen
