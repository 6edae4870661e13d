// Dynamics: generalized inertia, its derivative, the centripetal terms, the applied forces
// at (t, q, qd) and the energies. See dynamics.h.
#include "symbolic/dynamics.h"

#include <stdexcept>

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
  StaticsOptions inertia = Dynamic(true);
  inertia.bodies = applied.get();  // the bodies' coefficients once
  kinetostatics = std::make_unique<StaticsTable>(m, k, t, inertia);
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
      for (const MassKinematics& mk : a.masses)  // each link's dot product named: m (K.K) + J K K
        s += mk.mass * named("KK" + N(mk.link) + "_" + N(j) + "_" + N(kk),
                             mk.K_G[j][0] * mk.K_G[kk][0] + mk.K_G[j][1] * mk.K_G[kk][1]) +
             mk.inertia * mk.K_theta[j] * mk.K_theta[kk];
      I[j + nq * kk] = I[kk + nq * j] = named("I_" + N(j) + "_" + N(kk), s);
    }
  for (int j = 0; j < nq; ++j)
    for (int kk = 0; kk < nq; ++kk)
      for (int l = kk; l < nq; ++l) {
        ex s = 0;
        for (const MassKinematics& mk : a.masses) {
          const Vec2& L = mk.L_G[kk + nq * l];
          s += mk.mass * named("KL" + N(mk.link) + "_" + N(j) + "_" + N(kk) + "_" + N(l),
                               mk.K_G[j][0] * L[0] + mk.K_G[j][1] * L[1]) +
               mk.inertia * mk.K_theta[j] * mk.L_theta[kk + nq * l];
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
  for (int j = 0; j < nq; ++j) P_nc += a.Q_nc[j] * a.qd[j];  // the non-conservative forces' own work

  // ---- the excess-coordinate formulation ----
  StaticsOptions xo = Dynamic(false);
  xo.excess = true;
  excess_applied = std::make_unique<StaticsTable>(m, k, t, xo);
  const StaticsTable& x = *excess_applied;
  const int nphi = k.nphi(), nx = nq + nphi, nc = k.nc();
  std::vector<GiNaC::symbol> xs;
  for (const Coordinate& c : k.q) xs.push_back(c.symbol);
  for (const Coordinate& c : k.phi) xs.push_back(c.symbol);
  std::vector<ex> xd = x.qd;
  xd.insert(xd.end(), x.phid.begin(), x.phid.end());
  excess_program = x.program;
  auto xnamed = [&](const std::string& name, const ex& e) -> ex {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;
    ex sym;
    excess_program.push_back(Define(name, e, &sym));
    return sym;
  };
  // Per massive link: dr_G/dx_a, dtheta/dx_a, and the quadratic velocity terms of r_G.
  M.assign(nx * nx, 0);
  excess_h.assign(nx, 0);
  std::vector<std::vector<Vec2>> J(m.links.size());  // per link, per a
  std::vector<std::vector<ex>> Jth(m.links.size());
  for (const MassiveLink& body : t.bodies) {
    const int l = body.link;
    const Vec2& rG = body.r_G;
    const std::string tag = N(l);
    Vec2 quad{0, 0};  // sum_bc d2r_G/dx_b dx_c xd_b xd_c
    for (int a2 = 0; a2 < nx; ++a2) {
      const Vec2 d{rG[0].diff(xs[a2]), rG[1].diff(xs[a2])};
      J[l].push_back({xnamed("JG" + tag + "_x_" + N(a2), d[0]), xnamed("JG" + tag + "_y_" + N(a2), d[1])});
      Jth[l].push_back(body.theta.diff(xs[a2]));
      // Each second derivative once: d2/dx_a dx_b = d2/dx_b dx_a.
      for (int b = a2; b < nx; ++b)
        for (int c = 0; c < 2; ++c) quad[c] += (b == a2 ? 1 : 2) * d[c].diff(xs[b]) * xd[a2] * xd[b];
    }
    const Vec2 qn = {xnamed("aqG" + tag + "_x", quad[0]), xnamed("aqG" + tag + "_y", quad[1])};
    for (int a2 = 0; a2 < nx; ++a2) {
      excess_h[a2] += body.mass * (J[l][a2][0] * qn[0] + J[l][a2][1] * qn[1]);
      for (int b = 0; b < nx; ++b)
        M[a2 + nx * b] += body.mass * (J[l][a2][0] * J[l][b][0] + J[l][a2][1] * J[l][b][1]) + body.inertia * Jth[l][a2] * Jth[l][b];
    }
  }
  excess_T = 0;
  for (int a2 = 0; a2 < nx; ++a2)
    for (int b = 0; b < nx; ++b) excess_T += M[a2 + nx * b] * xd[a2] * xd[b] / 2;
  g.assign(nx, 0);
  for (int a2 = 0; a2 < nx; ++a2) g[a2] = x.g[a2];
  Phi_x.assign(nc * nx, 0);
  gamma.assign(nc, 0);
  for (int r = 0; r < nc; ++r) {
    for (int a2 = 0; a2 < nx; ++a2) Phi_x[r + nc * a2] = a2 < nq ? k.Phi_q(r, a2) : k.Phi_phi(r, a2 - nq);
    ex s = 0;
    for (int a2 = 0; a2 < nx; ++a2) {
      const ex d = k.Phi[r].diff(xs[a2]);
      for (int b = a2; b < nx; ++b) s += (b == a2 ? 1 : 2) * d.diff(xs[b]) * xd[a2] * xd[b];
    }
    gamma[r] = -s;
  }
  excess_V = x.V;

  // ---- the shaking force and moment, from the kinetostatics' accelerations ----
  shaking = m.outputs.Has(Quantity::kShaking);
  if (!shaking) return;
  const StaticsTable& ks = *kinetostatics;
  shaking_program = ks.program;
  const size_t nl = m.links.size();
  F_link.assign(nl, Vec2{0, 0});
  r_G.assign(nl, Vec2{0, 0});
  M_link.assign(nl, 0);
  massive.assign(nl, false);
  Vec2 moment_of_mass{0, 0};
  for (const MassKinematics& mk : ks.masses) {
    const int l = mk.link;
    const std::string tag = N(l);
    ex rx, ry;
    shaking_program.push_back(Define("rG" + tag + "_x", mk.r_G[0], &rx));
    shaking_program.push_back(Define("rG" + tag + "_y", mk.r_G[1], &ry));
    const ex ax = mk.a_G[0], ay = mk.a_G[1], alpha = mk.alpha;
    massive[l] = true;
    r_G[l] = {rx, ry};
    F_link[l] = {-mk.mass * ax, -mk.mass * ay};
    M_link[l] = rx * F_link[l][1] - ry * F_link[l][0] - mk.inertia * alpha;
    for (int c = 0; c < 2; ++c) {
      F[c] += F_link[l][c];
      moment_of_mass[c] += mk.mass * r_G[l][c];
    }
    M_total += M_link[l];
    mass_total += mk.mass;
  }
  // Named, so that 1/mass is the reciprocal of a local (not of a sum, which the emitter names).
  ex total;
  shaking_program.push_back(Define("mass_total", mass_total, &total));
  mass_total = total;
  for (int c = 0; c < 2; ++c) r_C[c] = moment_of_mass[c] / mass_total;
}

}  // namespace mechgen
