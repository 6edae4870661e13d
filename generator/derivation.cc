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

namespace {

std::string N(int i) { return std::to_string(i); }

// Solves J X = -R for one block, appending the statements to *P. J (n x n) and R (n x m)
// are expressions; the result X (n x m) comes back as symbols (named locals in closed
// form, entries of an Eigen matrix after a numeric LU). `tag` makes names unique.
struct BlockSolver {
  const Block& block;
  int index;
  bool closed_form;
  GiNaC::matrix J;    // closed form: the block of Phi_phi as named entries
  GiNaC::matrix inv;  // closed form: J^-1 in terms of named entries
  std::vector<bool> inv_named;  // closed form: entry (r, c) named yet
  std::string lu;     // numeric: the LU's name

  BlockSolver(const Block& b, int i, const Kinematics& k, Program* P, CxxPrinter* printer)
      : block(b), index(i), closed_form(static_cast<int>(b.cols.size()) <= kMaxSymbolicSolve) {
    const int n = static_cast<int>(b.cols.size());
    if (closed_form) {
      J = GiNaC::matrix(n, n);
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          P->push_back(Define("Phi_phi_" + N(b.rows[r]) + "_" + N(b.cols[c]), k.Phi_phi(b.rows[r], b.cols[c]), &J(r, c)));
      // det is named before it is inverted: GiNaC normalizes the sign of a sum raised to
      // an integer power by its (run-dependent) leading term, which would make the output
      // differ between runs. A symbol's power has no such freedom.
      ex det, inv_det;
      P->push_back(Define("det_block" + N(i), J.determinant(GiNaC::determinant_algo::laplace), &det));
      P->push_back(Define("inv_det_block" + N(i), 1 / det, &inv_det));
      inv = AdjugateInverse(J, inv_det);
      inv_named.assign(n * n, false);
    } else {
      const std::string sz = N(n);
      lu = "lu_block" + N(i);
      P->push_back(Raw("Mat<Scalar, " + sz + ", " + sz + "> J_block" + N(i) + ";"));
      P->push_back(Raw("J_block" + N(i) + ".setZero();"));  // large blocks are sparse
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          if (!k.Phi_phi(b.rows[r], b.cols[c]).is_zero())
            P->push_back(Store("J_block" + N(i) + Idx(r, c), k.Phi_phi(b.rows[r], b.cols[c])));
      P->push_back(Raw("const Eigen::PartialPivLU<Mat<Scalar, " + sz + ", " + sz + ">> " + lu + "(J_block" + N(i) + ");"));
    }
    (void)printer;
  }

  // X = -J^-1 R; names X entries prefix_<col>_<suffix j>.
  std::vector<std::vector<ex>> Solve(const std::vector<std::vector<ex>>& R, const std::string& prefix,
                                     const std::vector<std::string>& suffix, Program* P, CxxPrinter* printer) {
    const int n = static_cast<int>(block.cols.size()), m = static_cast<int>(suffix.size());
    std::vector<std::vector<ex>> X(n, std::vector<ex>(m));
    if (closed_form) {
      // Right-hand sides are named first: a sum times the inverse would be expanded into
      // many more products (and GiNaC's sign normalization of sums inside products depends
      // on its run-dependent term order).
      std::vector<std::vector<ex>> Rn(n, std::vector<ex>(m));
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
            P->push_back(Define("Phi_phi_inv_" + N(block.cols[r]) + "_" + N(block.rows[c]), inv(r, c), &inv(r, c)));
        }
      for (int r = 0; r < n; ++r)
        for (int j = 0; j < m; ++j) {
          const ex e = R[r][j].expand();
          if (GiNaC::is_a<GiNaC::add>(e))
            P->push_back(Define(prefix + "_rhs_" + N(block.rows[r]) + "_" + suffix[j], e, &Rn[r][j]));
          else
            Rn[r][j] = e;
        }
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
          ex s = 0;
          for (int r = 0; r < n; ++r) s += inv(i, r) * Rn[r][j];
          P->push_back(Define(prefix + "_" + N(block.cols[i]) + "_" + suffix[j], -s, &X[i][j]));
        }
      return X;
    }
    const std::string rhs = prefix + "_rhs_block" + N(index), sol = prefix + "_block" + N(index);
    const std::string shape = "Mat<Scalar, " + N(n) + ", " + N(m) + ">";
    P->push_back(Raw(shape + " " + rhs + ";"));
    for (int r = 0; r < n; ++r)
      for (int j = 0; j < m; ++j) P->push_back(Store(rhs + Idx(r, j), R[r][j]));
    P->push_back(Raw("const " + shape + " " + sol + " = -" + lu + ".solve(" + rhs + ");"));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        GiNaC::symbol s(sol + Idx(i, j));
        printer->Name(s, sol + Idx(i, j));
        X[i][j] = s;
      }
    return X;
  }
};

// The statements of SolvePositions for one closed-form block (see blocks.h for the forms).
// *trig_done[i] is set for each angle phi(i) whose sin and cos the block writes to *trig
// from its own solution (no trigonometric call).
void ClosedFormPositions(const Kinematics& k, const Block& b, int bi, Program* P, CxxPrinter* printer,
                         std::vector<bool>* trig_done) {
  const std::string t = "_b" + N(bi);
  // A named local, or the value itself when it is a number or a symbol already.
  auto define = [&](const std::string& name, const ex& value) {
    if (GiNaC::is_a<GiNaC::numeric>(value) || GiNaC::is_a<GiNaC::symbol>(value)) return value;
    ex sym;
    P->push_back(Define(name + t, value, &sym));
    printer->Name(sym, name + t);  // raw lines below print it
    return sym;
  };
  auto text = [&](const ex& e) { return printer->Print(e); };
  auto phi_ref = [&](int i) { return "phi(" + N(i) + ")"; };
  auto fail = [&](const std::string& cond, const std::string& measure) {
    P->push_back(Raw("if (" + cond + ") return {SolveStatus::kNotAssemblable, " + N(bi) + ", iterations, " + measure + "};"));
  };
  auto raw_symbol = [&](const std::string& name) {
    GiNaC::symbol s(name + t);
    printer->Name(s, name + t);
    return ex(s);
  };
  if (b.solve == BlockSolve::kRR) {
    // R(u) a + R(v) b = w: the tip m = R(u) a lies on the circles |m| = |a|, |w - m| = |b|.
    const int u = b.cols[b.iu], v = b.cols[1 - b.iu];
    const ex ax = define("ax", b.a[0]), ay = define("ay", b.a[1]);
    const ex bx = define("bx", b.b[0]), by = define("by", b.b[1]);
    const ex wx = define("wx", -b.w0[0]), wy = define("wy", -b.w0[1]);
    const ex ra2 = define("ra2", ax * ax + ay * ay), rb2 = define("rb2", bx * bx + by * by);
    const ex d2 = define("d2", wx * wx + wy * wy);
    const ex inv_d2 = define("inv_d2", 1 / d2);
    const ex kk = define("k", GiNaC::numeric(1, 2) + (ra2 - rb2) * inv_d2 / 2);
    define("h2", ra2 * inv_d2 - kk * kk);
    // h2 < 0: the two circles do not meet, the loop cannot close (NaN also fails).
    fail("!(h2" + t + " >= Scalar(0))", "h2" + t);
    P->push_back(Raw("const Scalar h" + t + " = Scalar(modes[" + N(bi) + "]) * sqrt(h2" + t + ");"));
    const ex h = raw_symbol("h");
    const ex mx = define("mx", kk * wx - h * wy), my = define("my", kk * wy + h * wx);
    // u: the angle from a to m, v: from b to w - m, each one atan2 of (cross, dot).
    const ex cu = define("cross_u", ax * my - ay * mx), du = define("dot_u", ax * mx + ay * my);
    const ex cv = define("cross_v", bx * (wy - my) - by * (wx - mx)), dv = define("dot_v", bx * (wx - mx) + by * (wy - my));
    P->push_back(Raw(phi_ref(u) + " = AngleNear(atan2(" + text(cu) + ", " + text(du) + "), " + phi_ref(u) + ");"));
    P->push_back(Raw(phi_ref(v) + " = AngleNear(atan2(" + text(cv) + ", " + text(dv) + "), " + phi_ref(v) + ");"));
    // m = R(u) a and w - m = R(v) b: a.m = |a|^2 cos u, a x m = |a|^2 sin u, and so for v.
    P->push_back(Raw("if (trig != nullptr) {"));
    P->push_back(Raw("  const Scalar inv_ra2" + t + " = Scalar(1) / " + text(ra2) + ";"));
    P->push_back(Raw("  const Scalar inv_rb2" + t + " = Scalar(1) / " + text(rb2) + ";"));
    P->push_back(Raw("  trig->cos_phi(" + N(u) + ") = " + text(du) + " * inv_ra2" + t + ";"));
    P->push_back(Raw("  trig->sin_phi(" + N(u) + ") = " + text(cu) + " * inv_ra2" + t + ";"));
    P->push_back(Raw("  trig->cos_phi(" + N(v) + ") = " + text(dv) + " * inv_rb2" + t + ";"));
    P->push_back(Raw("  trig->sin_phi(" + N(v) + ") = " + text(cv) + " * inv_rb2" + t + ";"));
    P->push_back(Raw("}"));
    (*trig_done)[u] = (*trig_done)[v] = true;
    return;
  }
  if (b.solve == BlockSolve::kAngle) {
    // c0 + c1 cos u + c2 sin u = 0: rho cos(u - delta) = -c0.
    const int u = b.cols[0];
    const ex c0 = define("c0", b.c0), c1 = define("c1", b.c1), c2 = define("c2", b.c2);
    const ex rho = define("rho", GiNaC::sqrt(c1 * c1 + c2 * c2));
    define("cos_arg", -c0 / rho);
    fail("!(abs(cos_arg" + t + ") <= Scalar(1))", "Scalar(1) - abs(cos_arg" + t + ")");
    P->push_back(Raw(phi_ref(u) + " = AngleNear(atan2(" + text(c2) + ", " + text(c1) + ") + Scalar(modes[" + N(bi) +
                     "]) * acos(cos_arg" + t + "), " + phi_ref(u) + ");"));
    return;
  }
  if (b.solve == BlockSolve::kLinear) {
    const ex c1 = define("c1", b.c1);
    if (!GiNaC::is_a<GiNaC::numeric>(c1)) fail(text(c1) + " == Scalar(0)", text(c1));
    P->push_back(Store(phi_ref(b.cols[0]), -b.c0 / c1));
    P->push_back(Raw(""));
    return;
  }
  if (b.solve == BlockSolve::kRS) {
    const int u = b.cols[b.iu], x = b.cols[1 - b.iu];
    const GiNaC::symbol s = k.phi[x].symbol;
    // |a(s)|^2 = |w0(s)|^2: A s^2 + B s + C = 0
    const ex f = (b.a[0] * b.a[0] + b.a[1] * b.a[1] - b.w0[0] * b.w0[0] - b.w0[1] * b.w0[1]).expand();
    const ex A = f.coeff(s, 2), B = f.coeff(s, 1), C = f.coeff(s, 0);
    const std::string Bt = text(define("B", B)), Ct = text(define("C", C));
    if (A.is_zero()) {
      fail(Bt + " == Scalar(0)", Bt);
      P->push_back(Raw("const Scalar s" + t + " = -" + Ct + " / " + Bt + ";"));
    } else {
      const std::string At = text(define("A", A));
      P->push_back(Raw("const Scalar disc" + t + " = " + Bt + " * " + Bt + " - Scalar(4) * " + At + " * " + Ct + ";"));
      // disc < 0: the circle and the line do not meet.
      fail("!(disc" + t + " >= Scalar(0))", "disc" + t);
      P->push_back(Raw("const Scalar sq" + t + " = sqrt(disc" + t + ");"));
      // The root of the requested sign without cancellation: q = -(B + sign(B) sq) / 2,
      // roots q / A and C / q; mode +1 is (-B + sq) / 2A.
      P->push_back(Raw("const Scalar qq" + t + " = -(" + Bt + " + (" + Bt + " >= Scalar(0) ? sq" + t + " : -sq" + t + ")) / Scalar(2);"));
      P->push_back(Raw("const Scalar s" + t + " = ((modes[" + N(bi) + "] > 0) == (" + Bt + " >= Scalar(0))) ? (qq" + t +
                       " != Scalar(0) ? " + Ct + " / qq" + t + " : Scalar(0)) : qq" + t + " / " + At + ";"));
    }
    const ex sv = raw_symbol("s");
    GiNaC::exmap at;
    at[s] = sv;
    const ex ax = define("ax", b.a[0].subs(at)), ay = define("ay", b.a[1].subs(at));
    const ex wx = define("wx", -b.w0[0].subs(at)), wy = define("wy", -b.w0[1].subs(at));
    P->push_back(Raw(phi_ref(x) + " = s" + t + ";"));
    // u: the angle from a to w, one atan2 of (cross, dot).
    const ex cu = define("cross_u", ax * wy - ay * wx), du = define("dot_u", ax * wx + ay * wy);
    P->push_back(Raw(phi_ref(u) + " = AngleNear(atan2(" + text(cu) + ", " + text(du) + "), " + phi_ref(u) + ");"));
    // R(u) a = w: a.w = |a|^2 cos u, a x w = |a|^2 sin u.
    P->push_back(Raw("if (trig != nullptr) {"));
    P->push_back(Raw("  const Scalar inv_a2" + t + " = Scalar(1) / (" + text(ax * ax + ay * ay) + ");"));
    P->push_back(Raw("  trig->cos_phi(" + N(u) + ") = " + text(du) + " * inv_a2" + t + ";"));
    P->push_back(Raw("  trig->sin_phi(" + N(u) + ") = " + text(cu) + " * inv_a2" + t + ";"));
    P->push_back(Raw("}"));
    (*trig_done)[u] = true;
    return;
  }
  // kSS: w0 + s0 e0 + s1 e1 = 0 by Cramer's rule.
  const ex e0x = define("e0x", b.e0[0]), e0y = define("e0y", b.e0[1]);
  const ex e1x = define("e1x", b.e1[0]), e1y = define("e1y", b.e1[1]);
  const ex w0x = define("w0x", b.w0[0]), w0y = define("w0y", b.w0[1]);
  define("det", e0x * e1y - e0y * e1x);
  fail("det" + t + " == Scalar(0)", "det" + t);  // parallel slides
  const ex inv = define("inv_det", 1 / raw_symbol("det"));
  P->push_back(Store("phi(" + N(b.cols[0]) + ")", (-w0x * e1y + w0y * e1x) * inv));
  P->push_back(Store("phi(" + N(b.cols[1]) + ")", (-e0x * w0y + e0y * w0x) * inv));
  P->push_back(Raw(""));  // flush the stores before later blocks read phi
}

// Trigonometric sharing (the Trig<Scalar> argument of SolvePositions and EvalCoefficients).
// A coordinate's sin and cos as the symbols sin_<q|phi><i>, cos_<q|phi><i>.
struct TrigName {
  std::string sin, cos, sin_ref, cos_ref, arg;  // local names, trig->... members, q(i)/phi(i)
  ex sin_symbol, cos_symbol;
};

TrigName NameTrig(bool is_q, int i, CxxPrinter* printer) {
  TrigName t;
  const std::string kind = is_q ? "q" : "phi";
  t.sin = "sin_" + kind + N(i);
  t.cos = "cos_" + kind + N(i);
  t.sin_ref = "trig->sin_" + kind + "(" + N(i) + ")";
  t.cos_ref = "trig->cos_" + kind + "(" + N(i) + ")";
  t.arg = kind + "(" + N(i) + ")";
  GiNaC::symbol s(t.sin), c(t.cos);
  printer->Name(s, t.sin);
  printer->Name(c, t.cos);
  t.sin_symbol = s;
  t.cos_symbol = c;
  return t;
}

// Replaces sin(x) and cos(x) of the angle coordinates in `program`'s values by the symbols
// of NameTrig; returns which were used (per coordinate: sin, cos), q first, then phi.
std::vector<std::pair<bool, bool>> SubstituteTrig(const Kinematics& k, const std::vector<TrigName>& names,
                                                  Program* program, bool include_phi) {
  std::vector<const Coordinate*> coords;
  for (const Coordinate& c : k.q) coords.push_back(&c);
  for (const Coordinate& c : k.phi) coords.push_back(&c);
  if (!include_phi) coords.resize(k.q.size());
  GiNaC::exmap map;
  std::vector<std::pair<ex, ex>> trig(coords.size());  // sin(x), cos(x)
  for (size_t i = 0; i < coords.size(); ++i) {
    if (!coords[i]->is_angle) continue;
    trig[i] = {GiNaC::sin(coords[i]->symbol), GiNaC::cos(coords[i]->symbol)};
    map[trig[i].first] = names[i].sin_symbol;
    map[trig[i].second] = names[i].cos_symbol;
  }
  std::vector<std::pair<bool, bool>> used(k.q.size() + k.phi.size(), {false, false});
  for (Statement& s : *program) {
    if (s.kind == Statement::Kind::kRaw) continue;
    for (size_t i = 0; i < coords.size(); ++i) {
      if (!coords[i]->is_angle) continue;
      used[i].first = used[i].first || s.value.has(trig[i].first);
      used[i].second = used[i].second || s.value.has(trig[i].second);
    }
    s.value = s.value.subs(map);
  }
  return used;
}

// Newton–Raphson on one block: residual and Jacobian of its rows over its unknowns.
void NewtonPositions(const Kinematics& k, const Block& b, int bi, Program* P) {
  const int n = static_cast<int>(b.cols.size());
  const std::string t = "_b" + N(bi), sz = N(n);
  P->push_back(Raw("Vec<Scalar, " + sz + "> r" + t + ";"));
  P->push_back(Raw("Mat<Scalar, " + sz + ", " + sz + "> J" + t + " = Mat<Scalar, " + sz + ", " + sz + ">::Zero();"));
  P->push_back(Raw("for (int iteration = 0;; ++iteration) {"));
  for (int r = 0; r < n; ++r) {
    P->push_back(Store("  r" + t + "(" + N(r) + ")", k.Phi[b.rows[r]]));
    for (int c = 0; c < n; ++c)
      if (!k.Phi_phi(b.rows[r], b.cols[c]).is_zero())
        P->push_back(Store("  J" + t + Idx(r, c), k.Phi_phi(b.rows[r], b.cols[c])));
  }
  P->push_back(Raw("  Scalar norm" + t + " = Scalar(0);"));
  P->push_back(Raw("  for (int i = 0; i < " + sz + "; ++i) if (abs(r" + t + "(i)) > norm" + t + ") norm" + t + " = abs(r" + t + "(i));"));
  P->push_back(Raw("  const bool closed" + t + " = norm" + t + " <= tol;"));
  P->push_back(Raw("  if (!closed" + t + " && (iteration == max_iterations || !(norm" + t + " == norm" + t + "))) return {SolveStatus::kDidNotConverge, " + N(bi) + ", iterations, norm" + t + "};"));
  P->push_back(Raw("  ++iterations;"));
  P->push_back(Raw("  const Vec<Scalar, " + sz + "> delta" + t + " = J" + t + ".partialPivLu().solve(r" + t + ");"));
  for (int c = 0; c < n; ++c) P->push_back(Raw("  phi(" + N(b.cols[c]) + ") -= delta" + t + "(" + N(c) + ");"));
  // Once the residual test passes, the step just taken is a last polish (quadratic
  // convergence): positions are then accurate to rounding, not just to the tolerance
  // times cond(Phi_phi).
  P->push_back(Raw("  if (closed" + t + ") break;"));
  P->push_back(Raw("}"));
}

}  // namespace

namespace {

Derivation DeriveWithoutTrigSharing(const Model& m, const Kinematics& k, CxxPrinter* printer, Strategy strategy) {
  Derivation d;
  d.trig_done.assign(k.phi.size(), false);
  const int nq = k.nq(), nphi = k.nphi(), nc = k.nc();
  for (int i = 0; i < nq; ++i) printer->Name(k.q[i].symbol, "q(" + std::to_string(i) + ")");
  for (int i = 0; i < nphi; ++i) printer->Name(k.phi[i].symbol, "phi(" + std::to_string(i) + ")");
  for (const Parameter& p : m.params) printer->Name(p.symbol, "p." + p.name);
  for (const CamLaw& law : k.cam_laws) printer->NameCamLaw(m.joints[law.joint].Data<CamData>().index, law.cxx_name);
  for (const CamGeometry& g : k.cam_geometry) printer->Name(g.x, "x");
  for (const CamContour& c : k.cam_contours) printer->NameCamContour(m.joints[c.joint].Data<CamData>().index, c.cxx_name);
  d.blocks = OrderBlocks(m, k, strategy);
  const auto& blocks = d.blocks;

  // ---- EvalPhi: the Jacobians are sparse in multi-loop mechanisms, so only their
  // non-zero entries are stored after a setZero() ----
  bool sparse_phi_phi = false, sparse_phi_q = false;
  for (int i = 0; i < nc; ++i) {
    for (int j = 0; j < nphi; ++j) sparse_phi_phi |= k.Phi_phi(i, j).is_zero();
    for (int j = 0; j < nq; ++j) sparse_phi_q |= k.Phi_q(i, j).is_zero();
  }
  if (sparse_phi_phi) d.phi.push_back(Raw("if (Phi_phi != nullptr) Phi_phi->setZero();"));
  if (sparse_phi_q) d.phi.push_back(Raw("if (Phi_q != nullptr) Phi_q->setZero();"));
  for (int i = 0; i < nc; ++i) d.phi.push_back(Store("(*Phi)(" + std::to_string(i) + ")", k.Phi[i], "Phi"));
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nphi; ++j)
      if (!sparse_phi_phi || !k.Phi_phi(i, j).is_zero())
        d.phi.push_back(Store("(*Phi_phi)" + Idx(i, j), k.Phi_phi(i, j), "Phi_phi"));
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nq; ++j)
      if (!sparse_phi_q || !k.Phi_q(i, j).is_zero())
        d.phi.push_back(Store("(*Phi_q)" + Idx(i, j), k.Phi_q(i, j), "Phi_q"));

  // ---- EvalScene ----
  for (size_t s = 0; s < k.scene.size(); ++s)
    for (int a = 0; a < 2; ++a)
      d.scene.push_back(Store("(*r)" + Idx(a, static_cast<int>(s)), k.scene[s][a]));

  // ---- SolvePositions and EvalDetPhiPhi, block by block ----
  ex det_product = 1;
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    // Each block is its own program: its values depend on the phi the blocks before it
    // wrote, so no subexpression may be shared across blocks.
    d.positions.emplace_back();
    Program& PP = d.positions.back();
    PP.push_back(Raw("{  // block " + N(static_cast<int>(bi)) + ": " + b.Describe(k)));
    if (b.solve == BlockSolve::kNewton)
      NewtonPositions(k, b, static_cast<int>(bi), &PP);
    else
      ClosedFormPositions(k, b, static_cast<int>(bi), &PP, printer, &d.trig_done);
    PP.push_back(Raw("}"));
    const int n = static_cast<int>(b.cols.size());
    GiNaC::matrix J(n, n);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) J(r, c) = k.Phi_phi(b.rows[r], b.cols[c]);
    if (n <= kMaxSymbolicSolve) {
      ex det;
      d.det.push_back(Define("det_block" + N(static_cast<int>(bi)), J.determinant(GiNaC::determinant_algo::laplace), &det));
      det_product *= det;
    } else {
      const std::string name = "J_block" + N(static_cast<int>(bi));
      d.det.push_back(Raw("Mat<Scalar, " + N(n) + ", " + N(n) + "> " + name + " = Mat<Scalar, " + N(n) + ", " + N(n) + ">::Zero();"));
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          if (!J(r, c).is_zero()) d.det.push_back(Store(name + Idx(r, c), J(r, c)));
      d.det.push_back(Raw("const Scalar det_block" + N(static_cast<int>(bi)) + " = " + name + ".partialPivLu().determinant();"));
      GiNaC::symbol s("det_block" + N(static_cast<int>(bi)));
      printer->Name(s, "det_block" + N(static_cast<int>(bi)));
      det_product *= s;
    }
  }
  // The sign of det Phi_phi depends on the row and column order: it is reported for the
  // model's own order (rows of Phi, columns of phi), i.e. with the permutations' signs.
  d.det.push_back(Store("*det_Phi_phi", det_product * PermutationSign(blocks, nphi)));

  // ---- EvalCoefficients ----
  const int order = m.outputs.order;
  Program& P = d.coefficients;
  for (size_t pt = 0; pt < k.points.size(); ++pt)
    for (int a = 0; a < 2; ++a) P.push_back(Store("out->r_P" + Idx(a, static_cast<int>(pt)), k.points[pt][a]));
  int largest = 0;
  for (const Block& b : blocks) largest = std::max(largest, static_cast<int>(b.cols.size()));
  d.numeric_solve = largest > kMaxSymbolicSolve;  // an LU for K and L (and Eigen/LU)
  for (const Block& b : blocks) d.numeric_solve |= b.solve == BlockSolve::kNewton;  // Newton's LU
  if (strategy == Strategy::kMonolithic)
    d.strategy = "monolithic (mechgen --strategy monolithic): one Newton solve over all " + N(nphi) +
                 " unknowns and K, L by one dense LU of Phi_phi; large systems need "
                 "EIGEN_STACK_ALLOCATION_LIMIT raised (fixed-size matrices on the stack).";
  else d.strategy = "Phi_phi is block lower triangular with " + N(static_cast<int>(blocks.size())) +
               " block(s) of at most " + N(largest) + " unknowns; each block's system is solved " +
               (d.numeric_solve ? "in closed form up to " + N(kMaxSymbolicSolve) + " unknowns, by a fixed-size LU above"
                                : "in closed form (adjugate over determinant)") +
               ", and K and L by forward substitution over the blocks.";
  // Phi and Phi_phi from the same evaluation, for the caller's closure and conditioning
  // checks: Phi_phi's entries are the named ones of the blocks' closed forms where they
  // exist (stored after the blocks are set up), the expressions elsewhere.
  for (int i = 0; i < nc; ++i) P.push_back(Store("out->Phi(" + N(i) + ")", k.Phi[i]));
  auto store_phi_phi = [&](const std::vector<BlockSolver>* solvers) {
    GiNaC::matrix named = k.Phi_phi;
    if (solvers != nullptr)
      for (const BlockSolver& s : *solvers)
        if (s.closed_form)
          for (size_t r = 0; r < s.block.rows.size(); ++r)
            for (size_t c = 0; c < s.block.cols.size(); ++c)
              named(s.block.rows[r], s.block.cols[c]) = s.J(r, c);
    if (sparse_phi_phi) P.push_back(Raw("out->Phi_phi.setZero();"));
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < nphi; ++j)
        if (!sparse_phi_phi || !k.Phi_phi(i, j).is_zero()) P.push_back(Store("out->Phi_phi" + Idx(i, j), named(i, j)));
  };
  if (order == 0) {
    store_phi_phi(nullptr);
    return d;
  }

  // x = (q, phi); V = dx/dq = [I; K], K filled block by block as symbols.
  std::vector<ex> x;
  for (const auto& c : k.q) x.push_back(c.symbol);
  for (const auto& c : k.phi) x.push_back(c.symbol);
  std::vector<std::vector<ex>> K(nphi, std::vector<ex>(nq));
  std::vector<std::string> q_suffix;
  for (int j = 0; j < nq; ++j) q_suffix.push_back(N(j));
  std::vector<BlockSolver> solvers;
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    solvers.emplace_back(b, static_cast<int>(bi), k, &P, printer);
    // R = Phi_q(rows, :) + Phi_phi(rows, earlier cols) K(earlier cols, :)
    std::vector<std::vector<ex>> R(b.rows.size(), std::vector<ex>(nq));
    for (size_t r = 0; r < b.rows.size(); ++r)
      for (int j = 0; j < nq; ++j) {
        ex s = k.Phi_q(b.rows[r], j);
        for (size_t pb = 0; pb < bi; ++pb)
          for (int c : blocks[pb].cols) s += k.Phi_phi(b.rows[r], c) * K[c][j];
        R[r][j] = s;
      }
    const auto X = solvers.back().Solve(R, "K", q_suffix, &P, printer);
    for (size_t i = 0; i < b.cols.size(); ++i)
      for (int j = 0; j < nq; ++j) K[b.cols[i]][j] = X[i][j];
  }
  store_phi_phi(&solvers);
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j) P.push_back(Store("out->K" + Idx(i, j), K[i][j]));
  auto V = [&](int a, int j) -> ex { return a < nq ? ex(a == j ? 1 : 0) : K[a - nq][j]; };
  auto along = [&](const ex& f, int j) {  // sum_a df/dx_a V(a, j)
    ex s = 0;
    for (size_t a = 0; a < x.size(); ++a) s += f.diff(GiNaC::ex_to<GiNaC::symbol>(x[a])) * V(static_cast<int>(a), j);
    return s;
  };
  std::vector<std::array<std::vector<ex>, 2>> point_K(k.points.size());
  for (size_t pt = 0; pt < k.points.size(); ++pt)
    for (int a = 0; a < 2; ++a)
      for (int j = 0; j < nq; ++j) {
        point_K[pt][a].push_back(along(k.points[pt][a], j));
        P.push_back(Store("out->K_P" + Idx(2 * static_cast<int>(pt) + a, j), point_K[pt][a][j]));
      }
  if (order < 2) return d;

  // ---- L: Phi_phi L(:, j, k) = -gamma(:, j, k), j <= k (L is symmetric in j, k) ----
  std::vector<std::pair<int, int>> pairs;
  std::vector<std::string> pair_suffix;
  for (int j = 0; j < nq; ++j)
    for (int kk = j; kk < nq; ++kk) {
      pairs.emplace_back(j, kk);
      pair_suffix.push_back(N(j) + "_" + N(kk));
    }
  std::vector<std::vector<ex>> L(nphi, std::vector<ex>(pairs.size()));
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    std::vector<std::vector<ex>> R(b.rows.size(), std::vector<ex>(pairs.size()));
    for (size_t r = 0; r < b.rows.size(); ++r)
      for (size_t pj = 0; pj < pairs.size(); ++pj) {
        ex s = along(along(k.Phi[b.rows[r]], pairs[pj].first), pairs[pj].second);
        for (size_t pb = 0; pb < bi; ++pb)
          for (int c : blocks[pb].cols) s += k.Phi_phi(b.rows[r], c) * L[c][pj];
        R[r][pj] = s;
      }
    const auto X = solvers[bi].Solve(R, "L", pair_suffix, &P, printer);
    for (size_t i = 0; i < b.cols.size(); ++i)
      for (size_t pj = 0; pj < pairs.size(); ++pj) L[b.cols[i]][pj] = X[i][pj];
  }
  auto pair_index = [&](int j, int kk) {
    const int lo = std::min(j, kk), hi = std::max(j, kk);
    for (size_t pj = 0; pj < pairs.size(); ++pj)
      if (pairs[pj].first == lo && pairs[pj].second == hi) return static_cast<int>(pj);
    return -1;
  };
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j)
      for (int kk = 0; kk < nq; ++kk) P.push_back(Store("out->L" + Idx(i, j + nq * kk), L[i][pair_index(j, kk)]));
  // Point centripetal coefficients: d/dq_k of (dr/dx V(:, j)) = its partials along V(:, k)
  // plus dr/dphi L(:, j, k).
  for (size_t pt = 0; pt < k.points.size(); ++pt)
    for (int a = 0; a < 2; ++a)
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk) {
          const int lo = std::min(j, kk), hi = std::max(j, kk);
          ex s = along(point_K[pt][a][lo], hi);
          for (int i = 0; i < nphi; ++i) s += k.points[pt][a].diff(k.phi[i].symbol) * L[i][pair_index(lo, hi)];
          P.push_back(Store("out->L_P" + Idx(2 * static_cast<int>(pt) + a, j + nq * kk), s));
        }
  return d;
}

// The Trig<Scalar> argument: SolvePositions hoists sin and cos of its angle inputs out of the
// blocks and hands out sin and cos of every angle (closed-form dyads from their own dot and
// cross products, others by a call); EvalCoefficients takes them instead of calling sin and
// cos again (it calls them itself when trig is nullptr).
void ShareTrig(const Kinematics& k, CxxPrinter* printer, Derivation* d) {
  std::vector<TrigName> names;
  for (int i = 0; i < k.nq(); ++i) names.push_back(NameTrig(true, i, printer));
  for (int i = 0; i < k.nphi(); ++i) names.push_back(NameTrig(false, i, printer));
  const int nq = k.nq();

  // EvalCoefficients: every angle coordinate.
  const auto used = SubstituteTrig(k, names, &d->coefficients, true);
  Program prologue, given, called;
  for (size_t i = 0; i < names.size(); ++i) {
    const TrigName& t = names[i];
    if (used[i].first) {
      prologue.push_back(Raw("Scalar " + t.sin + ";"));
      given.push_back(Raw("  " + t.sin + " = " + t.sin_ref + ";"));
      called.push_back(Raw("  " + t.sin + " = sin(" + t.arg + ");"));
      ++d->coefficient_trig_calls;
    }
    if (used[i].second) {
      prologue.push_back(Raw("Scalar " + t.cos + ";"));
      given.push_back(Raw("  " + t.cos + " = " + t.cos_ref + ";"));
      called.push_back(Raw("  " + t.cos + " = cos(" + t.arg + ");"));
      ++d->coefficient_trig_calls;
    }
  }
  if (!given.empty()) {
    prologue.push_back(Raw("if (trig != nullptr) {"));
    prologue.insert(prologue.end(), given.begin(), given.end());
    prologue.push_back(Raw("} else {"));
    prologue.insert(prologue.end(), called.begin(), called.end());
    prologue.push_back(Raw("}"));
    d->coefficients.insert(d->coefficients.begin(), prologue.begin(), prologue.end());
  }

  // SolvePositions: the inputs' sin and cos once, before the blocks.
  std::vector<std::pair<bool, bool>> q_used(nq, {false, false});
  for (Program& block : d->positions) {
    const auto u = SubstituteTrig(k, names, &block, false);
    for (int j = 0; j < nq; ++j) {
      q_used[j].first = q_used[j].first || u[j].first;
      q_used[j].second = q_used[j].second || u[j].second;
    }
  }
  Program head, tail;
  for (int j = 0; j < nq; ++j) {
    if (q_used[j].first) head.push_back(Raw("const Scalar " + names[j].sin + " = sin(" + names[j].arg + ");"));
    if (q_used[j].second) head.push_back(Raw("const Scalar " + names[j].cos + " = cos(" + names[j].arg + ");"));
    d->position_trig_calls += q_used[j].first + q_used[j].second;
  }
  tail.push_back(Raw("if (trig != nullptr) {"));
  for (int j = 0; j < nq; ++j) {
    if (!k.q[j].is_angle) continue;
    const TrigName& t = names[j];
    tail.push_back(Raw("  " + t.sin_ref + " = " + (q_used[j].first ? t.sin : "sin(" + t.arg + ")") + ";"));
    tail.push_back(Raw("  " + t.cos_ref + " = " + (q_used[j].second ? t.cos : "cos(" + t.arg + ")") + ";"));
  }
  for (int i = 0; i < k.nphi(); ++i) {
    if (!k.phi[i].is_angle || d->trig_done[i]) continue;
    const TrigName& t = names[nq + i];
    tail.push_back(Raw("  " + t.sin_ref + " = sin(" + t.arg + ");"));
    tail.push_back(Raw("  " + t.cos_ref + " = cos(" + t.arg + ");"));
  }
  tail.push_back(Raw("}"));
  d->positions.insert(d->positions.begin(), head);
  d->positions.push_back(tail);
}

}  // namespace

Derivation Derive(const Model& m, const Kinematics& k, CxxPrinter* printer, Strategy strategy) {
  Derivation d = DeriveWithoutTrigSharing(m, k, printer, strategy);
  ShareTrig(k, printer, &d);
  return d;
}

}  // namespace mechgen
