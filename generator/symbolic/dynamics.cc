// Dynamics: generalized inertia, its derivative, the centripetal terms, the applied forces
// at (t, q, qd) and the energies. See dynamics.h.
#include "symbolic/dynamics.h"

namespace mechgen {
namespace {

using GiNaC::ex;

std::string N(int i) { return std::to_string(i); }

StaticsOptions Dynamic(bool inertia) {
  StaticsOptions o;
  o.dynamic = true;
  o.inertia = inertia;
  o.reactions = inertia;
  return o;
}

bool Asked(const Model& m) { return m.outputs.Has(Quantity::kDynamics); }

}  // namespace

DynamicsTable::DynamicsTable(const Model& m, const Kinematics& k, const SymbolicTable& t)
    : any(Asked(m)) {
  if (!any) return;
  applied = std::make_unique<StaticsTable>(m, k, t, Dynamic(false));
  kinetostatics = std::make_unique<StaticsTable>(m, k, t, Dynamic(true));
  const StaticsTable& a = *applied;
  const int nq = k.nq();
  program = a.program;
  auto named = [&](const std::string& name, const ex& e) -> ex {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;
    ex sym;
    program.push_back(Define(name, e, &sym));
    return sym;
  };
  // I(j, k) and C(j, k, l) (symmetric in j, k and in k, l respectively).
  I.assign(nq * nq, 0);
  C.assign(nq * nq * nq, 0);
  for (int j = 0; j < nq; ++j)
    for (int kk = j; kk < nq; ++kk) {
      ex s = 0;
      for (const MassKinematics& mk : a.masses)
        s += mk.mass * (mk.K_G[j][0] * mk.K_G[kk][0] + mk.K_G[j][1] * mk.K_G[kk][1]) +
             mk.inertia * mk.K_theta[j] * mk.K_theta[kk];
      I[j + nq * kk] = I[kk + nq * j] = named("I_" + N(j) + "_" + N(kk), s);
    }
  for (int j = 0; j < nq; ++j)
    for (int kk = 0; kk < nq; ++kk)
      for (int l = kk; l < nq; ++l) {
        ex s = 0;
        for (const MassKinematics& mk : a.masses) {
          const Vec2& L = mk.L_G[kk + nq * l];
          s += mk.mass * (mk.K_G[j][0] * L[0] + mk.K_G[j][1] * L[1]) + mk.inertia * mk.K_theta[j] * mk.L_theta[kk + nq * l];
        }
        C[j + nq * (kk + nq * l)] = C[j + nq * (l + nq * kk)] =
            named("C_" + N(j) + "_" + N(kk) + "_" + N(l), s);
      }
  dI_dq.assign(nq * nq * nq, 0);
  for (int j = 0; j < nq; ++j)
    for (int kk = 0; kk < nq; ++kk)
      for (int l = 0; l < nq; ++l) dI_dq[j + nq * (kk + nq * l)] = C[j + nq * (kk + nq * l)] + C[kk + nq * (j + nq * l)];
  h.assign(nq, 0);
  T = 0;
  for (int j = 0; j < nq; ++j)
    for (int kk = 0; kk < nq; ++kk) {
      T += I[j + nq * kk] * a.qd[j] * a.qd[kk] / 2;
      for (int l = 0; l < nq; ++l) h[j] += C[j + nq * (kk + nq * l)] * a.qd[kk] * a.qd[l];
    }
  Q = a.Q;
  V = a.V;
  P_nc = 0;
  for (int j = 0; j < nq; ++j) P_nc += (Q[j] + a.dV_dq[j]) * a.qd[j];
}

}  // namespace mechgen
