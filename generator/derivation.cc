// Derivation of K, L and the point coefficients. See derivation.h.
#include "derivation.h"

namespace mechgen {
namespace {

using GiNaC::ex;

std::string Idx(int i, int j) { return "(" + std::to_string(i) + ", " + std::to_string(j) + ")"; }

Statement Store(const std::string& target, const ex& value, const std::string& guard = "") {
  Statement s;
  s.kind = Statement::Kind::kStore;
  s.target = target;
  s.value = value;
  s.guard = guard;
  return s;
}

Statement Raw(const std::string& line) {
  Statement s;
  s.kind = Statement::Kind::kRaw;
  s.target = line;
  return s;
}

// A named local: const Scalar name = value; returns its symbol through *sym.
Statement Define(const std::string& name, const ex& value, ex* sym) {
  Statement s;
  s.kind = Statement::Kind::kDefine;
  s.target = name;
  s.value = value;
  s.symbol = GiNaC::symbol(name);
  *sym = s.symbol;
  return s;
}

// Inverse of a small matrix of symbols by the adjugate: entries cofactor / det.
GiNaC::matrix AdjugateInverse(const GiNaC::matrix& a, const ex& inv_det) {
  const unsigned n = a.rows();
  GiNaC::matrix inv(n, n);
  if (n == 1) {
    inv(0, 0) = inv_det;
    return inv;
  }
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = 0; j < n; ++j) {
      GiNaC::matrix minor(n - 1, n - 1);
      for (unsigned r = 0, mr = 0; r < n; ++r) {
        if (r == j) continue;
        for (unsigned c = 0, mc = 0; c < n; ++c) {
          if (c == i) continue;
          minor(mr, mc++) = a(r, c);
        }
        ++mr;
      }
      const ex cof = ((i + j) % 2 ? -1 : 1) * minor.determinant(GiNaC::determinant_algo::laplace);
      inv(i, j) = cof * inv_det;
    }
  return inv;
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

Derivation Derive(const Model& m, const Kinematics& k, CxxPrinter* printer) {
  Derivation d;
  const int nq = k.nq(), nphi = k.nphi(), nc = k.nc();
  for (int i = 0; i < nq; ++i) printer->Name(k.q[i].symbol, "q(" + std::to_string(i) + ")");
  for (int i = 0; i < nphi; ++i) printer->Name(k.phi[i].symbol, "phi(" + std::to_string(i) + ")");
  for (const Parameter& p : m.params) printer->Name(p.symbol, "p." + p.name);

  // ---- EvalPhi ----
  for (int i = 0; i < nc; ++i) d.phi.push_back(Store("(*Phi)(" + std::to_string(i) + ")", k.Phi[i], "Phi"));
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nphi; ++j)
      d.phi.push_back(Store("(*Phi_phi)" + Idx(i, j), k.Phi_phi(i, j), "Phi_phi"));
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nq; ++j) d.phi.push_back(Store("(*Phi_q)" + Idx(i, j), k.Phi_q(i, j), "Phi_q"));

  // ---- EvalScene ----
  for (size_t s = 0; s < k.scene.size(); ++s)
    for (int a = 0; a < 2; ++a)
      d.scene.push_back(Store("(*r)" + Idx(a, static_cast<int>(s)), k.scene[s][a]));

  // ---- EvalCoefficients ----
  const int order = m.outputs.order;
  Program& P = d.coefficients;
  for (size_t pt = 0; pt < k.points.size(); ++pt)
    for (int a = 0; a < 2; ++a) P.push_back(Store("out->r_P" + Idx(a, static_cast<int>(pt)), k.points[pt][a]));
  d.numeric_solve = order >= 1 && nphi > kMaxSymbolicSolve;
  if (order == 0) {
    d.strategy = "none (positions only: no K or L requested).";
    return d;
  }
  // x = (q, phi); V = dx/dq = [I; K] with K as symbols defined below.
  std::vector<ex> x;
  for (const auto& c : k.q) x.push_back(c.symbol);
  for (const auto& c : k.phi) x.push_back(c.symbol);
  GiNaC::matrix K(nphi, nq), inv;
  const std::string kNphi = "Sizes::kNphi", kNq = "Sizes::kNq";
  if (!d.numeric_solve) {
    d.strategy = "Phi_phi (" + std::to_string(nphi) + "x" + std::to_string(nphi) +
                 ") inverted in closed form (adjugate over determinant), shared by K and L.";
    GiNaC::matrix J(nphi, nphi);
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nphi; ++j)
        P.push_back(Define("Phi_phi_" + std::to_string(i) + "_" + std::to_string(j), k.Phi_phi(i, j), &J(i, j)));
    // det is named before it is inverted: GiNaC normalizes the sign of a sum raised to
    // an integer power by its (run-dependent) leading term, which would make the output
    // differ between runs. A symbol's power has no such freedom.
    ex det, inv_det;
    P.push_back(Define("det_Phi_phi", J.determinant(GiNaC::determinant_algo::laplace), &det));
    P.push_back(Define("inv_det_Phi_phi", 1 / det, &inv_det));
    inv = AdjugateInverse(J, inv_det);
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j) {
        ex s = 0;
        for (int r = 0; r < nc; ++r) s += inv(i, r) * k.Phi_q(r, j);
        P.push_back(Define("K_" + std::to_string(i) + "_" + std::to_string(j), -s, &K(i, j)));
      }
  } else {
    d.strategy = "Phi_phi (" + std::to_string(nphi) + "x" + std::to_string(nphi) +
                 ") factored numerically (fixed-size Eigen PartialPivLU), shared by K and L.";
    P.push_back(Raw("Mat<Scalar, " + kNphi + ", " + kNphi + "> Phi_phi_m;"));
    P.push_back(Raw("Mat<Scalar, " + kNphi + ", " + kNq + "> Phi_q_m;"));
    for (int i = 0; i < nc; ++i) {
      for (int j = 0; j < nphi; ++j) P.push_back(Store("Phi_phi_m" + Idx(i, j), k.Phi_phi(i, j)));
      for (int j = 0; j < nq; ++j) P.push_back(Store("Phi_q_m" + Idx(i, j), k.Phi_q(i, j)));
    }
    P.push_back(Raw("const Eigen::PartialPivLU<Mat<Scalar, " + kNphi + ", " + kNphi + ">> lu(Phi_phi_m);"));
    P.push_back(Raw("const Mat<Scalar, " + kNphi + ", " + kNq + "> K_m = -lu.solve(Phi_q_m);"));
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j) {
        GiNaC::symbol s("K_m" + Idx(i, j));
        printer->Name(s, "K_m" + Idx(i, j));
        K(i, j) = s;
      }
  }
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j) P.push_back(Store("out->K" + Idx(i, j), K(i, j)));
  // V(a, j) = dx_a / dq_j
  auto V = [&](int a, int j) -> ex { return a < nq ? ex(a == j ? 1 : 0) : K(a - nq, j); };
  auto along = [&](const ex& f, int j) {  // sum_a df/dx_a V(a, j)
    ex s = 0;
    for (size_t a = 0; a < x.size(); ++a) s += f.diff(GiNaC::ex_to<GiNaC::symbol>(x[a])) * V(a, j);
    return s;
  };
  // Point velocity coefficients.
  std::vector<std::array<std::vector<ex>, 2>> point_K(k.points.size());
  for (size_t pt = 0; pt < k.points.size(); ++pt)
    for (int a = 0; a < 2; ++a)
      for (int j = 0; j < nq; ++j) {
        point_K[pt][a].push_back(along(k.points[pt][a], j));
        P.push_back(Store("out->K_P" + Idx(2 * static_cast<int>(pt) + a, j), point_K[pt][a][j]));
      }
  if (order < 2) return d;

  // ---- L: Phi_phi L(:, j, k) = -gamma(:, j, k), for j <= k (L is symmetric in j, k) ----
  std::vector<std::vector<std::vector<ex>>> L(nphi, std::vector<std::vector<ex>>(nq, std::vector<ex>(nq)));
  std::vector<std::vector<std::vector<ex>>> gamma(nc, std::vector<std::vector<ex>>(nq, std::vector<ex>(nq)));
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nq; ++j) {
      const ex dj = along(k.Phi[i], j);
      for (int kk = j; kk < nq; ++kk) gamma[i][j][kk] = along(dj, kk);
    }
  if (!d.numeric_solve) {
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j)
        for (int kk = j; kk < nq; ++kk) {
          ex s = 0;
          for (int r = 0; r < nc; ++r) s += inv(i, r) * gamma[r][j][kk];
          P.push_back(Define("L_" + std::to_string(i) + "_" + std::to_string(j) + "_" + std::to_string(kk), -s, &L[i][j][kk]));
        }
  } else {
    P.push_back(Raw("Mat<Scalar, " + kNphi + ", " + kNq + " * " + kNq + "> gamma_m;"));
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk)
          P.push_back(Store("gamma_m" + Idx(i, j + nq * kk), gamma[i][std::min(j, kk)][std::max(j, kk)]));
    P.push_back(Raw("const Mat<Scalar, " + kNphi + ", " + kNq + " * " + kNq + "> L_m = -lu.solve(gamma_m);"));
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j)
        for (int kk = j; kk < nq; ++kk) {
          GiNaC::symbol s("L_m" + Idx(i, j + nq * kk));
          printer->Name(s, "L_m" + Idx(i, j + nq * kk));
          L[i][j][kk] = s;
        }
  }
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j)
      for (int kk = 0; kk < nq; ++kk)
        P.push_back(Store("out->L" + Idx(i, j + nq * kk), L[i][std::min(j, kk)][std::max(j, kk)]));
  // Point centripetal coefficients: d/dq_k of (dr/dx V(:, j)) = its partials along V(:, k)
  // plus dr/dphi L(:, j, k).
  for (size_t pt = 0; pt < k.points.size(); ++pt)
    for (int a = 0; a < 2; ++a)
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk) {
          const int lo = std::min(j, kk), hi = std::max(j, kk);
          ex s = along(point_K[pt][a][lo], hi);
          for (int i = 0; i < nphi; ++i) s += k.points[pt][a].diff(k.phi[i].symbol) * L[i][lo][hi];
          P.push_back(Store("out->L_P" + Idx(2 * static_cast<int>(pt) + a, j + nq * kk), s));
        }
  return d;
}

}  // namespace mechgen
