// The right-hand side's Jacobians and the third-order coefficients. See jacobian.h.
#include "symbolic/jacobian.h"

#include <algorithm>

#include "symbolic/block_system.h"
#include "symbolic/design.h"
#include "symbolic/motion.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using Columns = std::vector<std::vector<ex>>;  // [row or unknown][column]

std::string N(int i) { return std::to_string(i); }

}  // namespace

ThirdOrderCoefficients::ThirdOrderCoefficients(const SymbolicTable& t, SlotSymbols* slots) : nq_(t.nq()) {
  const Kinematics& k = t.kinematics();
  const std::vector<Block>& blocks = t.blocks;
  const int nq = k.nq(), nphi = k.nphi();
  // K and L of EvalCoefficients (L's index j + nq k with j <= k: the same symbol for either order).
  auto K = [slots](int i, int j) { return (*slots)(Slot::Kind::kK, i, j); };
  auto L = [slots, nq](int i, int j, int kk) {
    return (*slots)(Slot::Kind::kL, i, std::min(j, kk) + nq * std::max(j, kk));
  };
  const Motion along(k, K, L);
  std::vector<int> js, ks, ls;  // the sorted triples j <= k <= l
  std::vector<std::string> suffix;
  for (int j = 0; j < nq; ++j)
    for (int kk = j; kk < nq; ++kk)
      for (int l = kk; l < nq; ++l) {
        js.push_back(j), ks.push_back(kk), ls.push_back(l);
        suffix.push_back(N(j) + "_" + N(kk) + "_" + N(l));
      }
  const size_t nt = suffix.size();
  M_.assign(nphi, std::vector<ex>(nt, 0));
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    BlockSystem system(b, static_cast<int>(bi), k, &program);
    Columns R(b.rows.size(), std::vector<ex>(nt));
    for (size_t r = 0; r < b.rows.size(); ++r) {
      const int row = b.rows[r];
      for (size_t c = 0; c < nt; ++c) {
        const int j = js[c], kk = ks[c], l = ls[c];
        // f_r(j, k) = Along_k Along_j Phi_r + sum_i Phi_phi(r, i) L(i, j, k), K and L held ...
        ex f = along.Along(along.Along(k.Phi[row], j), kk);
        for (int i = 0; i < nphi; ++i)
          if (!k.Phi_phi(row, i).is_zero()) f += k.Phi_phi(row, i) * L(i, j, kk);
        // ... its total derivative along q_l without the unknown M: through q_l and phi (Along),
        // and through K (K(i, j') -> L(i, j', l)) ...
        ex s = along.Along(f, l);
        for (int i = 0; i < nphi; ++i)
          for (int jj = 0; jj < nq; ++jj) {
            const ex g = f.diff(GiNaC::ex_to<GiNaC::symbol>(K(i, jj)));
            if (!g.is_zero()) s += g * L(i, jj, l);
          }
        // ... and the earlier blocks' M (known): Phi_phi(r, c) M(c) for c before this block.
        for (size_t pb = 0; pb < bi; ++pb)
          for (int col : blocks[pb].cols)
            if (!k.Phi_phi(row, col).is_zero()) s += k.Phi_phi(row, col) * M_[col][c];
        R[r][c] = s;
      }
    }
    const Columns X = system.Solve(R, "M", suffix, &program);
    for (size_t i = 0; i < b.cols.size(); ++i)
      for (size_t c = 0; c < nt; ++c) M_[b.cols[i]][c] = X[i][c];
  }
}

int ThirdOrderCoefficients::Triple(int j, int k, int l) const {
  int a[3] = {j, k, l};
  std::sort(a, a + 3);
  int index = 0;
  for (int x = 0; x < nq_; ++x)
    for (int y = x; y < nq_; ++y)
      for (int z = y; z < nq_; ++z, ++index)
        if (x == a[0] && y == a[1] && z == a[2]) return index;
  return -1;
}

GiNaC::ex ThirdOrderCoefficients::operator()(int i, int j, int k, int l) const { return M_[i][Triple(j, k, l)]; }

DynamicsJacobian::DynamicsJacobian(const Model& m, const SymbolicTable& t, const DynamicsTable& dyn) {
  const Kinematics& k = t.kinematics();
  const int nq = k.nq(), nphi = k.nphi();
  if (!dyn.any) return;
  if (!t.requested.K || !t.requested.L) {
    why_not = "the model does not derive K and L";
    return;
  }
  for (const Statement& s : dyn.program)
    if (s.kind != Statement::Kind::kDefine) {
      why_not = "a block of more than " + std::to_string(kMaxSymbolicSolve) + " unknowns is solved by an LU";
      return;
    }
  const SlotSymbols& reads = dyn.applied->slots;
  for (const auto& [sym, slot] : reads.all())
    if (slot.kind == Slot::Kind::kPhid || slot.kind == Slot::Kind::kQdd) {
      why_not = "the dynamics read a quantity whose derivative along the state is not derived";
      return;
    }
  possible = true;
  const ThirdOrderCoefficients M(t, &slots);
  program = M.program;

  // Directions d: q_l for d = l < nq, qd_l for d = nq + l.
  ForwardSeeds seeds;
  seeds.n = 2 * nq;
  for (int l = 0; l < nq; ++l) seeds.suffix.push_back("dq" + N(l));
  for (int l = 0; l < nq; ++l) seeds.suffix.push_back("dqd" + N(l));
  std::vector<GiNaC::symbol> q;
  for (const Coordinate& c : k.q) q.push_back(c.symbol);
  seeds.explicit_partial = [q, nq](const ex& v, int d) { return d < nq ? v.diff(q[d]) : ex(0); };
  seeds.min_shared = 2;  // a partial one direction reads (qd's) is not named
  auto along_q = [&](auto&& of_l) {
    std::vector<ex> v(2 * nq, 0);
    for (int l = 0; l < nq; ++l) v[l] = of_l(l);
    return v;
  };
  for (int i = 0; i < nphi; ++i) {
    seeds.derivative[k.phi[i].symbol] = along_q([&](int l) { return slots(Slot::Kind::kK, i, l); });
    seeds.order.push_back(k.phi[i].symbol);
  }
  for (const auto& [sym, read] : reads.all()) {
    // A named copy: a lambda may not capture a structured binding in C++17 (GCC accepts it,
    // clang rejects it).
    const Slot& slot = read;
    std::vector<ex> v(2 * nq, 0);
    switch (slot.kind) {
      case Slot::Kind::kK:
        v = along_q([&](int l) { return slots(Slot::Kind::kL, slot.i, std::min(slot.j, l) + nq * std::max(slot.j, l)); });
        break;
      case Slot::Kind::kL:
        v = along_q([&](int l) { return M(slot.i, slot.j % nq, slot.j / nq, l); });
        break;
      case Slot::Kind::kPhiPhi:
        v = along_q([&](int l) {
          const ex e = k.Phi_phi(slot.i, slot.j);
          ex s = e.diff(q[l]);
          for (int i = 0; i < nphi; ++i) s += e.diff(k.phi[i].symbol) * slots(Slot::Kind::kK, i, l);
          return s;
        });
        break;
      case Slot::Kind::kQd: v[nq + slot.i] = 1; break;
      default: break;  // t and the given friction loads are held
    }
    seeds.derivative[sym] = v;
    seeds.order.push_back(sym);
  }
  std::vector<ex> outputs = dyn.h;
  outputs.insert(outputs.end(), dyn.Q.begin(), dyn.Q.end());
  const std::vector<std::vector<ex>> D = ForwardOverProgram(&seeds, dyn.program, outputs, "djac_chain_", &program);
  dh_dq.assign(nq, std::vector<ex>(nq)), dQ_dq = dh_dqd = dQ_dqd = dh_dq;
  for (int j = 0; j < nq; ++j)
    for (int l = 0; l < nq; ++l) {
      dh_dq[j][l] = D[j][l];
      dh_dqd[j][l] = D[j][nq + l];
      dQ_dq[j][l] = D[nq + j][l];
      dQ_dqd[j][l] = D[nq + j][nq + l];
    }
  // A cam's law function gives the lift's derivatives up to the third; M reads the third.
  std::vector<ex> stored;
  for (const Statement& s : program)
    if (s.kind == Statement::Kind::kDefine) stored.push_back(s.value);
  for (const ex& e : stored)
    if (MaxCamLawOrder(e) > 3) {
      possible = false;
      why_not = "it would need a cam law's fourth derivative";
      return;
    }
  (void)m;
}

}  // namespace mechgen
