// Design sensitivities: derivatives of positions, K, L and the points with respect to the
// design parameters. See design.h.
#include "symbolic/design.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "joints/cam_profile.h"
#include "symbolic/block_system.h"
#include "symbolic/motion.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using Columns = std::vector<std::vector<ex>>;  // [row or unknown][column]

std::string N(int i) { return std::to_string(i); }

// X = -J^-1 R over the columns of R that are not all zero (a design parameter that no row of
// a block depends on, directly or through earlier blocks, has a zero column: no local is
// defined for it).
Columns SolveNonzero(BlockSystem* system, const Columns& R, const std::string& prefix,
                     const std::vector<std::string>& suffix, Program* P) {
  const size_t n = R.size(), m = suffix.size();
  std::vector<size_t> keep;
  for (size_t j = 0; j < m; ++j) {
    bool zero = true;
    for (size_t r = 0; r < n; ++r) zero &= R[r][j].expand().is_zero();
    if (!zero) keep.push_back(j);
  }
  Columns X(n, std::vector<ex>(m, 0));
  if (keep.empty()) return X;
  Columns Rk(n, std::vector<ex>(keep.size()));
  std::vector<std::string> sk;
  for (size_t c = 0; c < keep.size(); ++c) {
    sk.push_back(suffix[keep[c]]);
    for (size_t r = 0; r < n; ++r) Rk[r][c] = R[r][keep[c]];
  }
  const Columns Xk = system->Solve(Rk, prefix, sk, P);
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < keep.size(); ++c) X[i][keep[c]] = Xk[i][c];
  return X;
}

// Sum over earlier blocks' unknowns c of Phi_phi(row, c) X[c][col].
ex EarlierBlocks(const Kinematics& k, const std::vector<Block>& blocks, size_t bi, int row, const Columns& X, size_t col) {
  ex s = 0;
  for (size_t pb = 0; pb < bi; ++pb)
    for (int c : blocks[pb].cols) s += k.Phi_phi(row, c) * X[c][col];
  return s;
}

// e as A + B cos(q) + C sin(q) with A, B, C free of q (sin^2 = 1 - cos^2 used): false where
// e is not of that form (q inside another function, a product of cos and sin, ...).
bool LinearInCosSin(const ex& e, const GiNaC::symbol& q, ex* A, ex* B, ex* C) {
  const GiNaC::symbol X("X"), Y("Y");
  ex f = e.subs(GiNaC::lst{GiNaC::cos(q) == X, GiNaC::sin(q) == Y});
  if (f.has(q)) return false;
  f = f.expand();
  for (int i = 0; i < 8 && f.degree(Y) >= 2; ++i)
    f = f.subs(GiNaC::pow(Y, 2) == 1 - GiNaC::pow(X, 2), GiNaC::subs_options::algebraic).expand();
  if (f.degree(X) > 1 || f.degree(Y) > 1 || f.ldegree(X) < 0 || f.ldegree(Y) < 0) return false;
  if (!f.coeff(X, 1).coeff(Y, 1).is_zero()) return false;
  *A = f.coeff(X, 0).coeff(Y, 0);
  *B = f.coeff(X, 1).coeff(Y, 0);
  *C = f.coeff(X, 0).coeff(Y, 1);
  return !A->has(X) && !A->has(Y) && !B->has(Y) && !C->has(X);
}

// The closed-form blocks' reach over the input's range, where its extremes are known in
// closed form: a block whose requirement depends on the configuration only through one input
// angle q that turns a full turn (its range at least 2 pi), as A + B cos q + C sin q, its
// extremes A +- sqrt(B^2 + C^2). Which blocks qualify:
//   - RRR (kRR, R(u) a + R(v) b + w0 = 0, the circles of radii |a|, |b| centres |w0| apart
//     meet iff (|a| - |b|)^2 <= |w0|^2 <= (|a| + |b|)^2): |a|, |b| free of the configuration and
//     |w0|^2 linear in cos q, sin q — the dyad hangs from a ground point and a point of the
//     input link (a four-bar's coupler and rocker driven by its crank). Two margins, in length^2:
//     (|a| + |b|)^2 - max |w0|^2 and min |w0|^2 - (|a| - |b|)^2, both >= 0 iff the input turns
//     fully (for a four-bar this is the crank's condition; Grashof's margin says only that some
//     link turns fully);
//   - one angle (kAngle, c0 + c1 cos u + c2 sin u = 0, solvable iff |c0| <= rho =
//     sqrt(c1^2 + c2^2)): rho free of the configuration, c0 linear in cos q, sin q (a
//     slider-crank's rod: e = a sin q + b sin u). rho >= max |c0| = |A| + sqrt(B^2 + C^2) as two
//     smooth margins, rho - (A + sqrt(B^2 + C^2)) and rho + (A - sqrt(B^2 + C^2)) (the rod's
//     length less the crank and the offset to either side).
// Not: a block fed by an earlier block's unknowns (its extremes follow that block's motion, no
// closed form: the Watt six-bar's second dyad), by two inputs, or by an input of a partial
// range; RRP/RPR (kRS: its discriminant is quadratic in cos q, sin q), PRP and linear blocks
// (no discriminant), Newton blocks.
void AddReachChecks(const Model& m, const Kinematics& k, const std::vector<Block>& blocks,
                    std::vector<DesignCheck>* checks) {
  auto free_of_phi = [&k](const ex& e) {
    for (const Coordinate& c : k.phi)
      if (e.has(c.symbol)) return false;
    return true;
  };
  // The one input e depends on (it must turn fully), or -1.
  auto one_full_input = [&](const ex& e) {
    int found = -1;
    for (int j = 0; j < k.nq(); ++j)
      if (e.has(k.q[j].symbol)) {
        if (found >= 0) return -1;
        found = j;
      }
    if (found < 0 || !k.q[found].is_angle) return -1;
    const Input& in = m.inputs[found];
    return in.max - in.min >= 2 * M_PI - 1e-9 ? found : -1;
  };
  auto free_of_q = [&k](const ex& e) {
    for (const Coordinate& c : k.q)
      if (e.has(c.symbol)) return false;
    return true;
  };
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    const std::string tag = "block" + N(static_cast<int>(bi));
    const std::string what = b.Describe(k);
    if (b.solve == BlockSolve::kRR) {
      const ex ra2 = (b.a[0] * b.a[0] + b.a[1] * b.a[1]).expand(), rb2 = (b.b[0] * b.b[0] + b.b[1] * b.b[1]).expand();
      const ex d2 = b.w0[0] * b.w0[0] + b.w0[1] * b.w0[1];
      if (!free_of_phi(ra2) || !free_of_phi(rb2) || !free_of_q(ra2) || !free_of_q(rb2) || !free_of_phi(d2)) continue;
      const int j = one_full_input(d2);
      ex A, B, C;
      if (j < 0 || !LinearInCosSin(d2, k.q[j].symbol, &A, &B, &C)) continue;
      const ex R = GiNaC::sqrt(B * B + C * C), ra = GiNaC::sqrt(ra2), rb = GiNaC::sqrt(rb2);
      checks->push_back({"reach_far_" + tag,
                         "(|a| + |b|)^2 - max |w0|^2 over a turn of " + k.q[j].name + " (>= 0: the dyad's links reach "
                             "its farthest pivot distance) of " + tag + ", " + what,
                         GiNaC::pow(ra + rb, 2) - (A + R), {}});
      checks->push_back({"reach_near_" + tag,
                         "min |w0|^2 - (|a| - |b|)^2 over a turn of " + k.q[j].name + " (>= 0: the dyad closes at "
                             "its nearest pivot distance) of " + tag + ", " + what,
                         A - R - GiNaC::pow(ra - rb, 2), {}});
    } else if (b.solve == BlockSolve::kAngle) {
      const ex rho2 = (b.c1 * b.c1 + b.c2 * b.c2).expand();
      if (!free_of_phi(rho2) || !free_of_q(rho2) || !free_of_phi(b.c0)) continue;
      const int j = one_full_input(b.c0);
      ex A, B, C;
      if (j < 0 || !LinearInCosSin(b.c0, k.q[j].symbol, &A, &B, &C)) continue;
      // rho >= max |c0| as two smooth margins (no |A|: differentiable where A = 0).
      const ex rho = GiNaC::sqrt(rho2), R = GiNaC::sqrt(B * B + C * C);
      checks->push_back({"reach_max_" + tag,
                         "sqrt(c1^2 + c2^2) - max c0 over a turn of " + k.q[j].name +
                             " (>= 0 with reach_min: c0 + c1 cos u + c2 sin u = 0 solvable all round) of " + tag + ", " +
                             what,
                         rho - (A + R), {}});
      checks->push_back({"reach_min_" + tag,
                         "sqrt(c1^2 + c2^2) + min c0 over a turn of " + k.q[j].name + " of " + tag + ", " + what,
                         rho + (A - R), {}});
    }
  }
}

// A cam's radius of curvature (rho_pitch of a roller's pitch curve where it is convex, less
// the roller; rho_profile of a flat face's profile) at cam angle x, at the parameters'
// defaults: the geometry's locals substituted, the law's values from EvalCamLaw.
double CamCurvatureAt(const Model& m, const CamLaw& law, const CamGeometry& g, const ex& rho, double x) {
  GiNaC::exmap at = m.Defaults();
  at[g.x] = x;
  struct LawValues : GiNaC::map_function {
    const Model& m;
    const CamLaw& law;
    LawValues(const Model& model, const CamLaw& l) : m(model), law(l) {}
    ex operator()(const ex& e) override {
      const ex mapped = e.map(*this);
      if (GiNaC::is_a<GiNaC::function>(mapped) &&
          GiNaC::ex_to<GiNaC::function>(mapped).get_serial() == camlaw_SERIAL::serial) {
        const ex arg = mapped.op(2).evalf();
        if (GiNaC::is_a<GiNaC::numeric>(arg) && GiNaC::is_a<GiNaC::numeric>(mapped.op(1)))
          return EvalCamLaw(m, law, GiNaC::ex_to<GiNaC::numeric>(arg).to_double(),
                            GiNaC::ex_to<GiNaC::numeric>(mapped.op(1)).to_int());
      }
      return mapped;
    }
  } values(m, law);
  const ex v = values(rho.subs(at)).evalf();
  return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double() : NAN;
}

// A cam's curvature margin (undercut), as the generator checks it at the defaults
// (joints/cam_profile.h, CheckCam): a roller follower's pitch curve, where convex, must curve
// no tighter than the roller (rho_pitch - r_roller >= 0); a flat face's profile must have a
// positive radius of curvature. The minimum over the cam angle has no closed form (the law's
// segments are cycloidal, harmonic, polynomial): the margin is the radius of curvature at the
// law angle u* where it is smallest at the defaults (sampled as CheckCam does, then refined by
// golden sections), a function of the parameters with u* held — its value there is the
// minimum at the defaults and its derivative the minimum's (the envelope theorem: at an
// interior minimum x* moves only to second order; at a segment joint, fixed in the law's
// angle, x* does not move), and elsewhere an upper bound of the minimum, exact to second
// order in the change of the parameters (valid while the minimum stays at that place of the
// law, like Grashof's margin with the defaults' order). The law angle u* = x* - phase, and the
// cam's rotation x is set to 0 elsewhere (a radius of curvature does not depend on it), so the
// margin does not depend on the phase (turning the law turns the cam, not its shape). A
// knife-edge has no check.
void AddCamChecks(const Model& m, const Kinematics& k, const std::vector<GiNaC::symbol>& p,
                  std::vector<DesignCheck>* checks, Program* program) {
  const int nd = static_cast<int>(p.size());
  for (size_t c = 0; c < k.cam_laws.size() && c < k.cam_geometry.size(); ++c) {
    const CamLaw& law = k.cam_laws[c];
    const CamGeometry& g = k.cam_geometry[c];
    const Joint& j = m.joints[law.joint];
    const CamData& cd = j.Data<CamData>();
    const GiNaC::exmap defaults = m.Defaults();
    const ex rr_ex = cd.roller.subs(defaults).evalf();
    const double rr = GiNaC::is_a<GiNaC::numeric>(rr_ex) ? GiNaC::ex_to<GiNaC::numeric>(rr_ex).to_double() : 0;
    if (!cd.flat_face && !(rr > 0)) continue;
    GiNaC::exmap locals;
    for (const Statement& s : g.program)
      if (s.kind == Statement::Kind::kDefine) locals[s.symbol] = s.value.subs(locals);
    const ex rho_direct = (cd.flat_face ? g.rho_profile : g.rho_pitch);
    const ex rho = rho_direct.subs(locals);
    auto f = [&](double x) {
      const double r = CamCurvatureAt(m, law, g, rho, x);
      return cd.flat_face || r > 0 ? r : INFINITY;  // a roller: where the pitch curve is convex
    };
    const int n = 720;
    double best = INFINITY, x_best = 0;
    for (int i = 0; i < n; ++i) {
      const double x = 2 * M_PI * (i + 0.5) / n, v = f(x);
      if (v < best - 1e-9) best = v, x_best = x;
    }
    if (!std::isfinite(best)) continue;
    double lo = x_best - 2 * M_PI / n, hi = x_best + 2 * M_PI / n;
    const double r = (std::sqrt(5.0) - 1) / 2;
    double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo), f1 = f(x1), f2 = f(x2);
    for (int it = 0; it < 60; ++it)
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - r * (hi - lo), f1 = f(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + r * (hi - lo), f2 = f(x2);
      }
    double x_star = (lo + hi) / 2;
    if (!(f(x_star) <= best)) x_star = x_best;
    const ex phase = cd.phase.subs(defaults).evalf();
    const double u_star = x_star - (GiNaC::is_a<GiNaC::numeric>(phase) ? GiNaC::ex_to<GiNaC::numeric>(phase).to_double() : 0);
    // Rounded to 1e-9 rad: the header's text must not depend on the last bits of the search.
    const ex u = GiNaC::numeric(static_cast<long>(std::llround(u_star * 1e9)), 1000000000L);
    // The geometry's locals as locals of EvalDesignChecks (substituted into one expression,
    // the emitted text came out different from run to run), at the law angle u* and with the
    // cam's own rotation x at 0 (a radius of curvature does not depend on it: no phase is
    // left), each followed by its derivatives (forward mode over the locals, in their order).
    const GiNaC::symbol U("U");
    auto at_u = [&](const ex& e) {
      return e.subs(camlaw(cd.index, GiNaC::wild(0), g.x - cd.phase) == camlaw(cd.index, GiNaC::wild(0), U))
          .subs(g.x == 0)
          .subs(U == u);
    };
    bool law_at_u = true;
    auto check_law = [&](const ex& e) {
      for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
        if (GiNaC::is_a<GiNaC::function>(*it) && GiNaC::ex_to<GiNaC::function>(*it).get_serial() == camlaw_SERIAL::serial)
          law_at_u &= it->op(2).is_equal(u);
    };
    const std::string tag = "cam_" + j.name + "_";
    Program local;
    std::vector<ex> order;                       // the locals, in order
    std::map<ex, std::vector<ex>, GiNaC::ex_is_less> dlocal;  // their derivatives (named)
    GiNaC::exmap renamed;
    auto total = [&](const ex& v) {
      std::vector<ex> D(nd);
      for (int d = 0; d < nd; ++d) D[d] = v.diff(p[d]);
      for (const ex& x : order) {
        if (!v.has(x)) continue;
        const ex gx = v.diff(GiNaC::ex_to<GiNaC::symbol>(x));
        for (int d = 0; d < nd; ++d)
          if (!dlocal[x][d].is_zero()) D[d] += gx * dlocal[x][d];
      }
      return D;
    };
    for (const Statement& st : g.program) {
      if (st.kind != Statement::Kind::kDefine) continue;
      const ex value = at_u(st.value).subs(renamed);
      check_law(value);
      ex named;
      local.push_back(Define(tag + st.target, value, &named));
      renamed[st.symbol] = named;
      const std::vector<ex> D = total(value);
      order.push_back(named);
      std::vector<ex> dn(nd, 0);
      for (int d = 0; d < nd; ++d)
        if (!D[d].is_zero()) local.push_back(Define("d_" + tag + st.target + "_" + N(d), D[d], &dn[d]));
      dlocal[named] = dn;
    }
    const ex margin = at_u(rho_direct).subs(renamed) - (cd.flat_face ? ex(0) : cd.roller);
    check_law(margin);
    if (!law_at_u) continue;
    program->insert(program->end(), local.begin(), local.end());
    const std::vector<ex> dmargin = total(margin);
    char at[32];
    std::snprintf(at, sizeof at, "%.6f", u_star);
    checks->push_back(
        {"curvature_" + j.name,
         std::string(cd.flat_face ? "the profile's radius of curvature" : "the pitch curve's radius of curvature less the roller") +
             " of cam '" + j.name + "' at law angle " + at + " rad, where it is smallest at the defaults (>= 0: no undercut)",
         margin, dmargin});
  }
}

}  // namespace

DesignTable::DesignTable(const Model& m, const SymbolicTable& t, const Topology* topo,
                         const std::vector<FourBarLoop>* four_bars,
                         const std::vector<TransmissionAngle>* transmission) {
  if (!m.design.any()) return;
  const Kinematics& k = t.kinematics();
  const std::vector<Block>& blocks = t.blocks;
  const int nq = k.nq(), nphi = k.nphi();
  for (int index : m.design.params) {
    p.push_back(m.params[index].symbol);
    names.push_back(m.params[index].name);
  }
  const int n_d = nd();
  has_K = t.requested.K;
  has_L = t.requested.L;

  std::vector<GiNaC::symbol> q_symbols, phi_symbols;
  for (const Coordinate& c : k.q) q_symbols.push_back(c.symbol);
  for (const Coordinate& c : k.phi) phi_symbols.push_back(c.symbol);

  std::vector<std::string> q_suffix, p_suffix, qp_suffix;
  for (int j = 0; j < nq; ++j) q_suffix.push_back(N(j));
  for (int d = 0; d < n_d; ++d) {
    p_suffix.push_back(names[d]);
    for (int j = 0; j < nq; ++j) qp_suffix.push_back(N(j) + "_" + names[d]);
  }
  std::vector<std::pair<int, int>> pairs;  // (j, k), j <= k
  std::vector<std::string> pair_suffix, pair_p_suffix;
  for (int j = 0; j < nq; ++j)
    for (int kk = j; kk < nq; ++kk) {
      pairs.emplace_back(j, kk);
      pair_suffix.push_back(N(j) + "_" + N(kk));
    }
  const size_t np = pairs.size();
  for (int d = 0; d < n_d; ++d)
    for (size_t pj = 0; pj < np; ++pj) pair_p_suffix.push_back(pair_suffix[pj] + "_" + names[d]);
  auto pair_index = [&pairs](int j, int kk) {
    const std::pair<int, int> key(std::min(j, kk), std::max(j, kk));
    return static_cast<size_t>(std::find(pairs.begin(), pairs.end(), key) - pairs.begin());
  };

  // ---- Each block's Phi_phi set up once; K and dphi/dp by forward substitution ----
  Columns K(nphi, std::vector<ex>(nq, 0));
  dphi_dp.assign(nphi, std::vector<ex>(n_d, 0));
  std::vector<BlockSystem> systems;
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    systems.emplace_back(b, static_cast<int>(bi), k, &program);
    const size_t nr = b.rows.size();
    if (has_K) {
      Columns R(nr, std::vector<ex>(nq));
      for (size_t r = 0; r < nr; ++r)
        for (int j = 0; j < nq; ++j) R[r][j] = k.Phi_q(b.rows[r], j) + EarlierBlocks(k, blocks, bi, b.rows[r], K, j);
      // The same statements as EvalCoefficients' K (SymbolicTable::SolveVelocityCoefficients).
      const Columns X = systems.back().Solve(R, "K", q_suffix, &program);
      for (size_t i = 0; i < b.cols.size(); ++i)
        for (int j = 0; j < nq; ++j) K[b.cols[i]][j] = X[i][j];
    }
    Columns R(nr, std::vector<ex>(n_d));
    for (size_t r = 0; r < nr; ++r)
      for (int d = 0; d < n_d; ++d)
        R[r][d] = k.Phi[b.rows[r]].diff(p[d]) + EarlierBlocks(k, blocks, bi, b.rows[r], dphi_dp, d);
    const Columns X = SolveNonzero(&systems.back(), R, "dphi_dp", p_suffix, &program);
    for (size_t i = 0; i < b.cols.size(); ++i)
      for (int d = 0; d < n_d; ++d) dphi_dp[b.cols[i]][d] = X[i][d];
  }

  // The motion over q, with this program's K and L.
  Columns L(nphi, std::vector<ex>(np, 0));  // L[i][pair]: this program's locals
  const Motion along_q(q_symbols, phi_symbols, [&K](int i, int j) { return K[i][j]; },
                       [&L, &pair_index](int i, int j, int kk) { return L[i][pair_index(j, kk)]; });
  Columns dL(nphi, std::vector<ex>(np * n_d, 0));  // dL[i][pair + np d]
  dK_dp.assign(nphi, std::vector<ex>(nq * n_d, 0));
  // D_d f for every d: the total derivative with respect to p_d, through p_d, phi and the K
  // (and, with `through_L`, L) locals f holds. f's partial derivative along each variable is
  // the same for every p_d: it is named once (a local) where it is not a single factor.
  int chain_locals = 0;
  auto name_once = [&](const ex& g) -> ex {
    if (n_d < 2 || GiNaC::is_a<GiNaC::symbol>(g) || GiNaC::is_a<GiNaC::numeric>(g)) return g;
    ex named;
    program.push_back(Define("dchain_" + N(chain_locals++), g, &named));
    return named;
  };
  auto total = [&](const ex& f, bool through_K, bool through_L) {
    std::vector<ex> out(n_d);
    for (int d = 0; d < n_d; ++d) out[d] = f.diff(p[d]);
    auto chain = [&](const ex& v, const std::vector<ex>& dv_dp, int stride, int offset) {
      if (!GiNaC::is_a<GiNaC::symbol>(v)) return;
      const ex g = f.diff(GiNaC::ex_to<GiNaC::symbol>(v));
      if (g.is_zero()) return;
      const ex gn = name_once(g);
      for (int d = 0; d < n_d; ++d) out[d] += gn * dv_dp[offset + stride * d];
    };
    for (int i = 0; i < nphi; ++i) {
      chain(phi_symbols[i], dphi_dp[i], 1, 0);
      if (through_K)
        for (int j = 0; j < nq; ++j) chain(K[i][j], dK_dp[i], nq, j);
      if (through_L)
        for (size_t pj = 0; pj < np; ++pj) chain(L[i][pj], dL[i], static_cast<int>(np), static_cast<int>(pj));
    }
    return out;
  };

  // ---- dK/dp: Phi_phi dK(:, j)/dp_d = -(d/dp_d of dPhi/dq_j with K held) ----
  if (has_K)
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      Columns R(b.rows.size(), std::vector<ex>(nq * n_d));
      for (size_t r = 0; r < b.rows.size(); ++r) {
        for (int j = 0; j < nq; ++j) {
          const std::vector<ex> D = total(along_q.Along(k.Phi[b.rows[r]], j), false, false);
          for (int d = 0; d < n_d; ++d)
            R[r][j + nq * d] = D[d] + EarlierBlocks(k, blocks, bi, b.rows[r], dK_dp, j + nq * d);
        }
      }
      const Columns X = SolveNonzero(&systems[bi], R, "dK_dp", qp_suffix, &program);
      for (size_t i = 0; i < b.cols.size(); ++i)
        for (int c = 0; c < nq * n_d; ++c) dK_dp[b.cols[i]][c] = X[i][c];
    }

  // ---- L (as EvalCoefficients' l_program) and dL/dp ----
  if (has_L) {
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      Columns R(b.rows.size(), std::vector<ex>(np));
      for (size_t r = 0; r < b.rows.size(); ++r)
        for (size_t pj = 0; pj < np; ++pj)
          R[r][pj] = along_q.Along(along_q.Along(k.Phi[b.rows[r]], pairs[pj].first), pairs[pj].second) +
                     EarlierBlocks(k, blocks, bi, b.rows[r], L, pj);
      const Columns X = systems[bi].Solve(R, "L", pair_suffix, &program);
      for (size_t i = 0; i < b.cols.size(); ++i)
        for (size_t pj = 0; pj < np; ++pj) L[b.cols[i]][pj] = X[i][pj];
    }
    // d2Phi_r/dq_j dq_k = g_r + sum_c Phi_phi(r, c) L_c = 0 with g_r = Along_k Along_j Phi_r (K
    // held): its total derivative has sum_c Phi_phi(r, c) dL_c/dp_d and D_d of the rest, L held.
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      Columns R(b.rows.size(), std::vector<ex>(np * n_d));
      for (size_t r = 0; r < b.rows.size(); ++r) {
        const int row = b.rows[r];
        for (size_t pj = 0; pj < np; ++pj) {
          ex f = along_q.Along(along_q.Along(k.Phi[row], pairs[pj].first), pairs[pj].second);
          for (int c = 0; c < nphi; ++c) f += k.Phi_phi(row, c) * L[c][pj];
          const std::vector<ex> D = total(f, /*through_K=*/true, /*through_L=*/false);
          for (int d = 0; d < n_d; ++d) R[r][pj + np * d] = D[d] + EarlierBlocks(k, blocks, bi, row, dL, pj + np * d);
        }
      }
      const Columns X = SolveNonzero(&systems[bi], R, "dL_dp", pair_p_suffix, &program);
      for (size_t i = 0; i < b.cols.size(); ++i)
        for (size_t c = 0; c < np * n_d; ++c) dL[b.cols[i]][c] = X[i][c];
    }
    dL_dp.assign(nphi, std::vector<ex>(nq * nq * n_d, 0));
    for (int i = 0; i < nphi; ++i)
      for (int d = 0; d < n_d; ++d)
        for (int j = 0; j < nq; ++j)
          for (int kk = 0; kk < nq; ++kk) dL_dp[i][j + nq * kk + nq * nq * d] = dL[i][pair_index(j, kk) + np * d];
  }

  K_value = K;
  L_value.assign(nphi, std::vector<ex>(nq * nq, 0));
  if (has_L)
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk) L_value[i][j + nq * kk] = L[i][pair_index(j, kk)];

  // ---- The points ----
  dr_P_dp.resize(t.r_P.size());
  dK_P_dp.resize(t.r_P.size());
  dL_P_dp.resize(t.r_P.size());
  for (size_t pt = 0; pt < t.r_P.size(); ++pt)
    for (int a = 0; a < 2; ++a) {
      const ex& r = t.r_P[pt][a];
      dr_P_dp[pt][a] = total(r, false, false);
      if (has_K) {
        dK_P_dp[pt][a].assign(nq * n_d, 0);
        for (int j = 0; j < nq; ++j) {
          const std::vector<ex> D = total(along_q.Along(r, j), /*through_K=*/true, false);
          for (int d = 0; d < n_d; ++d) dK_P_dp[pt][a][j + nq * d] = D[d];
        }
      }
      if (has_L) {
        dL_P_dp[pt][a].assign(nq * nq * n_d, 0);
        for (int j = 0; j < nq; ++j)
          for (int kk = j; kk < nq; ++kk) {
            const std::vector<ex> D = total(along_q.Second(r, j, kk), /*through_K=*/true, /*through_L=*/true);
            for (int d = 0; d < n_d; ++d) {
              dL_P_dp[pt][a][j + nq * kk + nq * nq * d] = D[d];
              dL_P_dp[pt][a][kk + nq * j + nq * nq * d] = D[d];
            }
          }
      }
    }
  // ---- The transmission angles ----
  if (transmission != nullptr)
    for (size_t i = 0; i < transmission->size(); ++i) {
      const TransmissionAngle& ta = (*transmission)[i];
      ex cross, dot;
      program.push_back(Define("cross_" + N(static_cast<int>(i)), ta.cross, &cross));
      program.push_back(Define("dot_" + N(static_cast<int>(i)), ta.dot, &dot));
      const std::vector<ex> dcross = total(ta.cross, false, false), ddot = total(ta.dot, false, false);
      ex scale;
      program.push_back(Define("dmu_scale_" + N(static_cast<int>(i)),
                               cross / (GiNaC::abs(cross) * (cross * cross + dot * dot)), &scale));
      std::vector<ex> row;
      for (int d = 0; d < n_d; ++d) row.push_back(scale * (dot * dcross[d] - cross * ddot[d]));
      dmu_dp.push_back(row);
    }
  // ---- Design checks: the four-bar loops' link lengths and Grashof margins ----
  if (topo != nullptr && four_bars != nullptr)
    for (size_t fi = 0; fi < four_bars->size(); ++fi) {
      const FourBarLoop& f = (*four_bars)[fi];
      const Loop& loop = topo->loops[f.loop];
      const std::string tag = "loop" + N(static_cast<int>(fi));
      ex length[4];
      for (int i = 0; i < 4; ++i) {
        const int link = loop.links[i];
        const PointRef a = m.joints[loop.joints[(i + 3) % 4]].End(link), b = m.joints[loop.joints[i]].End(link);
        const LinkPoint& pa = m.links[link].points[a.point];
        const LinkPoint& pb = m.links[link].points[b.point];
        length[i] = GiNaC::sqrt(GiNaC::pow(pb.x - pa.x, 2) + GiNaC::pow(pb.y - pa.y, 2));
        checks.push_back({"length_" + f.links[i] + "_" + tag,
                          "the length of link '" + f.links[i] + "' between its joints in four-bar " + tag + " (> 0)",
                          length[i], {}});
      }
      // s, l, p, q as the defaults order them (ties by position in the loop).
      int order[4] = {0, 1, 2, 3};
      std::stable_sort(order, order + 4, [&f](int x, int y) { return f.lengths[x] < f.lengths[y]; });
      checks.push_back({"grashof_" + tag,
                        "Grashof's margin (p + q) - (s + l) of four-bar " + tag + ", s = '" + f.links[order[0]] +
                            "', l = '" + f.links[order[3]] + "' as at the defaults: >= 0 where a link turns fully",
                        length[order[1]] + length[order[2]] - length[order[0]] - length[order[3]], {}});
    }
  AddReachChecks(m, k, blocks, &checks);
  AddCamChecks(m, k, p, &checks, &checks_program);
  for (DesignCheck& c : checks)
    if (c.d.empty())  // (a cam's margin comes with its derivatives, through its locals)
      for (int d = 0; d < n_d; ++d) c.d.push_back(c.margin.diff(p[d]));
  // A cam's law function (CamLaw_<joint>) gives the lift's derivatives up to the third: a
  // design derivative that needs a higher one cannot be generated (none does where the cam
  // angle is an input or a dependent angle: K reads the first, L the second, dL/dp the third).
  std::vector<ex> stored;
  for (const Statement& s : program)
    if (s.kind == Statement::Kind::kDefine) stored.push_back(s.value);
  for (const auto* table : {&dphi_dp, &dK_dp, &dL_dp})
    for (const std::vector<ex>& row : *table) stored.insert(stored.end(), row.begin(), row.end());
  for (const auto* table : {&dr_P_dp, &dK_P_dp, &dL_P_dp})
    for (const auto& point : *table)
      for (const std::vector<ex>& axis : point) stored.insert(stored.end(), axis.begin(), axis.end());
  for (const ex& e : stored)
    if (MaxCamLawOrder(e) > 3)
      m.Fail(m.design.mark,
             "design derivatives would need a cam law's fourth derivative; remove design or the parameters that move "
             "the cam's angle");
}

int MaxCamLawOrder(const GiNaC::ex& e) {
  int most = -1;
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::function>(*it) && GiNaC::ex_to<GiNaC::function>(*it).get_serial() == camlaw_SERIAL::serial &&
        GiNaC::is_a<GiNaC::numeric>(it->op(1)))
      most = std::max(most, GiNaC::ex_to<GiNaC::numeric>(it->op(1)).to_int());
  return most;
}

}  // namespace mechgen

// ---- The statics' design sensitivities ----

namespace mechgen {

ProgramDesign DifferentiateProgram(const Kinematics& k, const DesignTable& dt, const Program& program,
                                   const SlotSymbols& reads, const std::vector<GiNaC::ex>& outputs,
                                   const std::string& chain_prefix) {
  using GiNaC::ex;
  ProgramDesign out;
  const int nq = k.nq(), nd = dt.nd();
  if (nd == 0) return out;
  for (const Statement& s : program)
    if (s.kind != Statement::Kind::kDefine) {
      out.why_not = "a block of more than " + std::to_string(kMaxSymbolicSolve) + " unknowns is solved by an LU";
      return out;
    }
  for (const auto& [sym, slot] : reads.all())
    if ((slot.kind == Slot::Kind::kK && dt.dK_dp.empty()) || (slot.kind == Slot::Kind::kL && dt.dL_dp.empty()) ||
        slot.kind == Slot::Kind::kPhid) {
      out.why_not = "it reads a quantity whose design derivative the model does not derive";
      return out;
    }
  out.possible = true;
  // d/dp_d of each symbol the program reads, as an expression (absent or zero: held), and the
  // symbols in the order they were made.
  std::map<ex, std::vector<ex>, GiNaC::ex_is_less> derivative;
  std::vector<ex> order;
  for (int i = 0; i < k.nphi(); ++i) {
    std::vector<ex> v;
    // Structurally zero where no row of Phi depends on p_d (a mass, a load): not read.
    for (int d = 0; d < nd; ++d)
      v.push_back(dt.dphi_dp[i][d].is_zero() ? ex(0) : out.slots(Slot::Kind::kDphiDp, i, d));
    derivative[k.phi[i].symbol] = v;
    order.push_back(k.phi[i].symbol);
  }
  // An expression of (q, phi, p): its total derivative, phi through dphi/dp.
  auto explicit_total = [&](const ex& e, int d) {
    ex s = e.diff(dt.p[d]);
    for (int i = 0; i < k.nphi(); ++i) {
      const ex ei = e.diff(k.phi[i].symbol);
      if (!ei.is_zero()) s += ei * derivative[k.phi[i].symbol][d];
    }
    return s;
  };
  for (const auto& [sym, slot] : reads.all()) {
    std::vector<ex> v(nd, 0);
    for (int d = 0; d < nd; ++d) switch (slot.kind) {
        case Slot::Kind::kK:
          if (!dt.dK_dp[slot.i][slot.j + nq * d].is_zero())
            v[d] = out.slots(Slot::Kind::kDKDp, slot.i, slot.j + nq * d);
          break;
        case Slot::Kind::kL:
          if (!dt.dL_dp[slot.i][slot.j + nq * nq * d].is_zero())
            v[d] = out.slots(Slot::Kind::kDLDp, slot.i, slot.j + nq * nq * d);
          break;
        case Slot::Kind::kPhiPhi: v[d] = explicit_total(k.Phi_phi(slot.i, slot.j), d); break;
        default: break;  // the arguments (qd, qdd, t) and the given friction loads are held
      }
    derivative[sym] = v;
    order.push_back(sym);
  }
  ForwardSeeds seeds;
  seeds.n = nd;
  seeds.suffix = dt.names;
  seeds.explicit_partial = [&dt](const ex& v, int d) { return v.diff(dt.p[d]); };
  seeds.derivative = std::move(derivative);
  seeds.order = std::move(order);
  out.d = ForwardOverProgram(&seeds, program, outputs, chain_prefix, &out.program);
  return out;
}

std::vector<std::vector<GiNaC::ex>> ForwardOverProgram(ForwardSeeds* seeds, const Program& program,
                                                       const std::vector<GiNaC::ex>& outputs,
                                                       const std::string& chain_prefix, Program* locals_out) {
  using GiNaC::ex;
  const int nd = seeds->n;
  auto& derivative = seeds->derivative;
  auto& order = seeds->order;
  // D_d v for every d; each partial that several d share named once (where it is not one factor).
  int locals = 0;
  auto total = [&](const ex& v) {
    std::vector<ex> D(nd);
    for (int d = 0; d < nd; ++d) D[d] = seeds->explicit_partial(v, d);
    // In the order the variables were made (a set ordered by GiNaC's hashes would differ from
    // run to run: the generated text must not).
    for (const ex& x : order) {
      if (!v.has(x)) continue;
      const auto it = derivative.find(x);
      if (it == derivative.end()) continue;
      int nonzero = 0;
      for (const ex& dx : it->second) nonzero += !dx.is_zero();
      if (nonzero == 0) continue;
      ex g = v.diff(GiNaC::ex_to<GiNaC::symbol>(x));
      if (g.is_zero()) continue;
      if (nd > 1 && nonzero >= seeds->min_shared && !GiNaC::is_a<GiNaC::symbol>(g) && !GiNaC::is_a<GiNaC::numeric>(g)) {
        ex named;
        locals_out->push_back(Define(chain_prefix + std::to_string(locals++), g, &named));
        g = named;
      }
      for (int d = 0; d < nd; ++d) D[d] += g * it->second[d];
    }
    return D;
  };
  for (const Statement& s : program) {
    const std::vector<ex> D = total(s.value);
    std::vector<ex> named(nd, 0);
    for (int d = 0; d < nd; ++d)
      if (!D[d].is_zero()) locals_out->push_back(Define("d_" + s.target + "_" + seeds->suffix[d], D[d], &named[d]));
    derivative[s.symbol] = named;
    order.push_back(s.symbol);
  }
  std::vector<std::vector<ex>> d;
  for (const ex& o : outputs) d.push_back(total(o));
  return d;
}

DesignStatics::DesignStatics(const Model& m, const Kinematics& k, const StaticsTable& st, const DesignTable& dt) {
  const int nq = k.nq();
  if (dt.nd() == 0 || !st.layout.any) return;
  std::vector<GiNaC::ex> outputs;
  if (st.forces) {
    outputs.insert(outputs.end(), st.Q.begin(), st.Q.end());
    outputs.insert(outputs.end(), st.drive.begin(), st.drive.end());
  }
  if (st.potential) outputs.push_back(st.V);
  outputs.insert(outputs.end(), st.R.begin(), st.R.end());
  ProgramDesign pd = DifferentiateProgram(k, dt, st.program, st.slots, outputs, "dstatics_chain_");
  possible = pd.possible;
  why_not = pd.why_not;
  if (!possible) return;
  slots = pd.slots;
  program = pd.program;
  size_t at = 0;
  if (st.forces) {
    for (int j = 0; j < nq; ++j) dQ.push_back(pd.d[at++]);
    for (int j = 0; j < nq; ++j) ddrive.push_back(pd.d[at++]);
  }
  if (st.potential) dV = pd.d[at++];
  while (at < pd.d.size()) dR.push_back(pd.d[at++]);
  (void)m;
}

DesignDynamics::DesignDynamics(const Model& m, const Kinematics& k, const DynamicsTable& dyn, const DesignTable& dt) {
  const int nq = k.nq();
  if (dt.nd() == 0 || !dyn.any) return;
  std::vector<GiNaC::ex> outputs = dyn.I;
  outputs.insert(outputs.end(), dyn.dI_dq.begin(), dyn.dI_dq.end());
  outputs.insert(outputs.end(), dyn.h.begin(), dyn.h.end());
  outputs.insert(outputs.end(), dyn.Q.begin(), dyn.Q.end());
  outputs.push_back(dyn.T);
  outputs.push_back(dyn.V);
  ProgramDesign pd = DifferentiateProgram(k, dt, dyn.program, dyn.applied->slots, outputs, "ddynamics_chain_");
  possible = pd.possible;
  why_not = pd.why_not;
  if (!possible) return;
  slots = pd.slots;
  program = pd.program;
  size_t at = 0;
  for (int i = 0; i < nq * nq; ++i) dI.push_back(pd.d[at++]);
  for (int i = 0; i < nq * nq * nq; ++i) ddI_dq.push_back(pd.d[at++]);
  for (int j = 0; j < nq; ++j) dh.push_back(pd.d[at++]);
  for (int j = 0; j < nq; ++j) dQ.push_back(pd.d[at++]);
  dT = pd.d[at++];
  dV = pd.d[at++];
  (void)m;
}

namespace {

// Reverse mode over a straight-line program (kDefine statements only), symbolically: the
// adjoints of `inputs` and of the explicit parameters p for the scalar y (an expression of the
// program's locals, the inputs and p), the locals swept from the last, each nonzero adjoint
// named once (<prefix><n>, appended to *adjoint). The symbols are visited by number (inputs,
// then locals in program order), so the text does not depend on GiNaC's hashes.
struct ReverseResult {
  std::vector<GiNaC::ex> bar_inputs;  ///< named locals (or 0)
  std::vector<GiNaC::ex> bar_p;       ///< sums of named locals' products
};
ReverseResult ReverseOverProgram(const Program& program, const std::vector<GiNaC::ex>& inputs,
                                 const std::vector<GiNaC::symbol>& p, const GiNaC::ex& y, const std::string& prefix,
                                 Program* adjoint) {
  using GiNaC::ex;
  const int nd = static_cast<int>(p.size());
  std::map<ex, int, GiNaC::ex_is_less> index;
  std::vector<ex> symbol_of;
  auto add = [&](const ex& x) {
    if (index.emplace(x, static_cast<int>(symbol_of.size())).second) symbol_of.push_back(x);
  };
  for (const ex& x : inputs) add(x);
  for (const Statement& s : program) add(s.symbol);
  std::vector<ex> bar(symbol_of.size(), ex(0));
  ReverseResult out;
  out.bar_p.assign(nd, ex(0));
  auto propagate = [&](const ex& e, const ex& b) {
    std::set<int> read;
    for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (GiNaC::is_a<GiNaC::symbol>(*it)) {
        const auto f = index.find(*it);
        if (f != index.end()) read.insert(f->second);
      }
    for (int x : read) {
      const ex g = e.diff(GiNaC::ex_to<GiNaC::symbol>(symbol_of[x]));
      if (!g.is_zero()) bar[x] += b * g;
    }
    for (int d = 0; d < nd; ++d) {
      if (!e.has(p[d])) continue;
      const ex g = e.diff(p[d]);
      if (!g.is_zero()) out.bar_p[d] += b * g;
    }
  };
  int locals = 0;
  auto name = [&](const ex& v) {
    if (GiNaC::is_a<GiNaC::symbol>(v) || GiNaC::is_a<GiNaC::numeric>(v)) return v;
    ex sym;
    adjoint->push_back(Define(prefix + std::to_string(locals++), v, &sym));
    return sym;
  };
  propagate(y, 1);
  for (auto it = program.rbegin(); it != program.rend(); ++it) {
    const int x = index.at(it->symbol);
    if (bar[x].is_zero()) continue;
    propagate(it->value, name(bar[x]));
  }
  for (size_t x = 0; x < inputs.size(); ++x) out.bar_inputs.push_back(bar[x].is_zero() ? ex(0) : name(bar[x]));
  return out;
}

bool StraightLine(const Program& program) {
  for (const Statement& s : program)
    if (s.kind != Statement::Kind::kDefine) return false;
  return true;
}

}  // namespace

DesignDynamicsProduct::DesignDynamicsProduct(const Kinematics& k, const DynamicsTable& dyn, const DesignTable& dt) {
  using GiNaC::ex;
  const int nq = k.nq(), nphi = k.nphi(), nd = dt.nd();
  if (nd == 0 || !dyn.any) return;
  if (!StraightLine(dyn.program)) {
    why_not = "a block of more than " + std::to_string(kMaxSymbolicSolve) + " unknowns is solved by an LU";
    return;
  }
  const SlotSymbols& reads = dyn.applied->slots;
  for (const auto& [sym, slot] : reads.all())
    if ((slot.kind == Slot::Kind::kK && dt.dK_dp.empty()) || (slot.kind == Slot::Kind::kL && dt.dL_dp.empty()) ||
        slot.kind == Slot::Kind::kPhid) {
      why_not = "it reads a quantity whose design derivative the model does not derive";
      return;
    }
  possible = true;
  for (int j = 0; j < nq; ++j) {
    mu.push_back(GiNaC::symbol("mu_" + std::to_string(j)));
    qdd.push_back(GiNaC::symbol("qdd_" + std::to_string(j)));
  }
  ex y = 0;
  for (int j = 0; j < nq; ++j) {
    ex row = dyn.Q[j] - dyn.h[j];
    for (int l = 0; l < nq; ++l) row -= dyn.I[j + nq * l] * qdd[l];
    y += mu[j] * row;
  }
  // The dynamics program's inputs with a design derivative: phi, then the slots K, L, Phi_phi.
  std::vector<ex> inputs;
  std::vector<const Slot*> input_slot;
  for (int i = 0; i < nphi; ++i) {
    inputs.push_back(k.phi[i].symbol);
    input_slot.push_back(nullptr);
  }
  for (const auto& [sym, slot] : reads.all())
    if (slot.kind == Slot::Kind::kK || slot.kind == Slot::Kind::kL || slot.kind == Slot::Kind::kPhiPhi) {
      inputs.push_back(sym);
      input_slot.push_back(&slot);
    }
  const ReverseResult first = ReverseOverProgram(dyn.program, inputs, dt.p, y, "ybar_", &program);
  grad = first.bar_p;
  // Then K, L and Phi_phi as the design table's program computes them from (q, phi, p), swept
  // backward too (z = their adjoints dotted with them, phi's explicit adjoint added), so that
  // phi's total adjoint meets dphi/dp = -Phi_phi^-1 dPhi/dp (nphi x N) alone: no dK/dp, dL/dp.
  // Where that program is not straight-line (an LU), their adjoints are dotted with dK/dp and
  // dL/dp (EvalDesignDerivatives' forward mode, read in the slots' places).
  if (StraightLine(dt.program)) {
    ex z = 0;
    for (size_t x = 0; x < inputs.size(); ++x) {
      if (first.bar_inputs[x].is_zero()) continue;
      if (input_slot[x] == nullptr) {
        z += first.bar_inputs[x] * inputs[x];
        continue;
      }
      const Slot& slot = *input_slot[x];
      switch (slot.kind) {
        case Slot::Kind::kK: z += first.bar_inputs[x] * dt.K_value[slot.i][slot.j]; break;
        case Slot::Kind::kL: z += first.bar_inputs[x] * dt.L_value[slot.i][slot.j]; break;
        case Slot::Kind::kPhiPhi: z += first.bar_inputs[x] * k.Phi_phi(slot.i, slot.j); break;
        default: break;
      }
    }
    std::vector<ex> phis;
    for (int i = 0; i < nphi; ++i) phis.push_back(k.phi[i].symbol);
    const ReverseResult second = ReverseOverProgram(dt.program, phis, dt.p, z, "zbar_", &program);
    for (int d = 0; d < nd; ++d) {
      grad[d] += second.bar_p[d];
      for (int i = 0; i < nphi; ++i)
        if (!second.bar_inputs[i].is_zero() && !dt.dphi_dp[i][d].is_zero())
          grad[d] += second.bar_inputs[i] * dt.dphi_dp[i][d];
    }
    return;
  }
  auto explicit_total = [&](const ex& e, int d) {
    ex s = e.diff(dt.p[d]);
    for (int i = 0; i < nphi; ++i) {
      const ex ei = e.diff(k.phi[i].symbol);
      if (!ei.is_zero() && !dt.dphi_dp[i][d].is_zero()) s += ei * slots(Slot::Kind::kDphiDp, i, d);
    }
    return s;
  };
  for (int d = 0; d < nd; ++d)
    for (size_t x = 0; x < inputs.size(); ++x) {
      const ex b = first.bar_inputs[x];
      if (b.is_zero()) continue;
      if (input_slot[x] == nullptr) {
        if (!dt.dphi_dp[x][d].is_zero()) grad[d] += b * slots(Slot::Kind::kDphiDp, static_cast<int>(x), d);
        continue;
      }
      const Slot& slot = *input_slot[x];
      switch (slot.kind) {
        case Slot::Kind::kK:
          if (!dt.dK_dp[slot.i][slot.j + nq * d].is_zero())
            grad[d] += b * slots(Slot::Kind::kDKDp, slot.i, slot.j + nq * d);
          break;
        case Slot::Kind::kL:
          if (!dt.dL_dp[slot.i][slot.j + nq * nq * d].is_zero())
            grad[d] += b * slots(Slot::Kind::kDLDp, slot.i, slot.j + nq * nq * d);
          break;
        case Slot::Kind::kPhiPhi: grad[d] += b * explicit_total(k.Phi_phi(slot.i, slot.j), d); break;
        default: break;
      }
    }
}

}  // namespace mechgen

// ---- The shaking force and moment's design sensitivities ----

namespace mechgen {

namespace {

// The program's kDefine statements that `outputs` read (directly or through other locals);
// every other kind of statement is kept.
Program PruneFor(const Program& program, const std::vector<GiNaC::ex>& outputs) {
  std::set<GiNaC::ex, GiNaC::ex_is_less> used;
  auto collect = [&used](const GiNaC::ex& e) {
    for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (GiNaC::is_a<GiNaC::symbol>(*it)) used.insert(*it);
  };
  for (const GiNaC::ex& o : outputs) collect(o);
  std::vector<const Statement*> kept;
  for (auto it = program.rbegin(); it != program.rend(); ++it) {
    if (it->kind == Statement::Kind::kDefine && !used.count(it->symbol)) continue;
    if (it->kind == Statement::Kind::kDefine || it->kind == Statement::Kind::kStore) collect(it->value);
    kept.push_back(&*it);
  }
  Program out;
  for (auto it = kept.rbegin(); it != kept.rend(); ++it) out.push_back(**it);
  return out;
}

}  // namespace

DesignShaking::DesignShaking(const Kinematics& k, const DynamicsTable& dyn, const DesignTable& dt) {
  if (dt.nd() == 0 || !dyn.any || !dyn.shaking) return;
  const std::vector<GiNaC::ex> outputs{dyn.F[0], dyn.F[1], dyn.M_total};
  const Program pruned = PruneFor(dyn.shaking_program, outputs);
  ProgramDesign pd = DifferentiateProgram(k, dt, pruned, dyn.kinetostatics->slots, outputs, "dshaking_chain_");
  possible = pd.possible;
  why_not = pd.why_not;
  if (!possible) return;
  slots = pd.slots;
  program = pruned;
  program.insert(program.end(), pd.program.begin(), pd.program.end());
  dF = {pd.d[0], pd.d[1]};
  dM = pd.d[2];
}

}  // namespace mechgen
