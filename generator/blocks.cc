// Block-triangular ordering and dyad recognition. See blocks.h.
#include "blocks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>

namespace mechgen {
namespace {

using GiNaC::ex;

// Phi = rest + R(u) p with p and rest free of u, or nothing.
struct RotationSplit {
  Vec2 p, rest;
};

std::optional<RotationSplit> SplitRotation(const Vec2& phi, const GiNaC::symbol& u) {
  GiNaC::symbol C("C"), S("S");
  GiNaC::exmap m;
  m[GiNaC::cos(u)] = C;
  m[GiNaC::sin(u)] = S;
  ex e[2];
  for (int a = 0; a < 2; ++a) {
    e[a] = phi[a].expand().subs(m);
    if (e[a].has(u)) return std::nullopt;  // u also appears otherwise (cos(u + alpha), u * ...)
    if (e[a].degree(C) > 1 || e[a].degree(S) > 1 || e[a].coeff(C, 1).has(S)) return std::nullopt;
  }
  const ex ac = e[0].coeff(C, 1), as = e[0].coeff(S, 1), bc = e[1].coeff(C, 1), bs = e[1].coeff(S, 1);
  // R(u) (p0, p1) = (p0 cos u - p1 sin u, p0 sin u + p1 cos u)
  if (!(ac - bs).expand().is_zero() || !(as + bc).expand().is_zero()) return std::nullopt;
  RotationSplit r;
  r.p = {ac, bc};
  r.rest = {e[0].coeff(C, 0).coeff(S, 0), e[1].coeff(C, 0).coeff(S, 0)};
  if ((r.p[0].is_zero() && r.p[1].is_zero())) return std::nullopt;
  return r;
}

bool AffineIn(const ex& e, const GiNaC::symbol& s) { return e.expand().degree(s) <= 1; }

// Recognizes the closed forms of a two-equation block whose rows are the x and y
// projections of one closure equation.
void Recognize(const Kinematics& k, Block* b) {
  if (b->rows.size() == 1) {
    const Coordinate& c = k.phi[b->cols[0]];
    const ex f = k.Phi[b->rows[0]].expand();
    // Linear in its unknown (a gear mesh, a cam law, a no-slip condition): c0 + c1 x = 0.
    if (f.degree(c.symbol) == 1 && !f.coeff(c.symbol, 1).has(c.symbol) && !f.coeff(c.symbol, 0).has(c.symbol)) {
      b->solve = BlockSolve::kLinear;
      b->c0 = f.coeff(c.symbol, 0);
      b->c1 = f.coeff(c.symbol, 1);
      return;
    }
    if (c.is_angle) {
      GiNaC::symbol C("C"), S("S");
      GiNaC::exmap m;
      m[GiNaC::cos(c.symbol)] = C;
      m[GiNaC::sin(c.symbol)] = S;
      const ex g = f.subs(m);
      if (g.has(c.symbol) || g.degree(C) > 1 || g.degree(S) > 1 || g.coeff(C, 1).has(S)) return;
      b->solve = BlockSolve::kAngle;
      b->c0 = g.coeff(C, 0).coeff(S, 0);
      b->c1 = g.coeff(C, 1);
      b->c2 = g.coeff(S, 1);
    } else {
      if (f.degree(c.symbol) != 1) return;
      b->solve = BlockSolve::kLinear;
      b->c0 = f.coeff(c.symbol, 0);
      b->c1 = f.coeff(c.symbol, 1);
    }
    return;
  }
  if (b->rows.size() != 2) return;
  const Vec2 phi = {k.Phi[b->rows[0]], k.Phi[b->rows[1]]};
  const Coordinate& c0 = k.phi[b->cols[0]];
  const Coordinate& c1 = k.phi[b->cols[1]];
  // Two equations linear in both unknowns (coupled gear meshes of a planetary train): by
  // Cramer's rule, as the line-line dyad below.
  if (c0.is_angle || c1.is_angle || k.Phi_group[b->rows[0]] != k.Phi_group[b->rows[1]]) {
    Vec2 e0, e1, w0;
    bool linear = true;
    for (int a = 0; a < 2 && linear; ++a) {
      const ex f = phi[a].expand();
      if (f.degree(c0.symbol) > 1 || f.degree(c1.symbol) > 1) linear = false;
      e0[a] = f.coeff(c0.symbol, 1);
      e1[a] = f.coeff(c1.symbol, 1);
      w0[a] = f.coeff(c0.symbol, 0).coeff(c1.symbol, 0);
      for (const ex& e : {e0[a], e1[a], w0[a]})
        if (e.has(c0.symbol) || e.has(c1.symbol)) linear = false;
    }
    if (linear) {
      b->solve = BlockSolve::kSS;
      b->e0 = e0;
      b->e1 = e1;
      b->w0 = w0;
      return;
    }
    // Different closures: no dyad of one vector equation.
    if (k.Phi_group[b->rows[0]] != k.Phi_group[b->rows[1]]) return;
  }
  for (int iu = 0; iu < 2; ++iu) {
    const Coordinate& u = iu == 0 ? c0 : c1;
    const Coordinate& x = iu == 0 ? c1 : c0;
    if (!u.is_angle) continue;
    const auto split = SplitRotation(phi, u.symbol);
    if (!split) continue;
    if (x.is_angle) {
      if (split->p[0].has(x.symbol) || split->p[1].has(x.symbol)) continue;
      const auto second = SplitRotation(split->rest, x.symbol);
      if (!second) continue;
      b->solve = BlockSolve::kRR;
      b->iu = iu;
      b->a = split->p;
      b->b = second->p;
      b->w0 = second->rest;
      return;
    }
    if (AffineIn(split->p[0], x.symbol) && AffineIn(split->p[1], x.symbol) &&
        AffineIn(split->rest[0], x.symbol) && AffineIn(split->rest[1], x.symbol)) {
      b->solve = BlockSolve::kRS;
      b->iu = iu;
      b->a = split->p;
      b->w0 = split->rest;
      return;
    }
  }
  if (!c0.is_angle && !c1.is_angle) {
    Vec2 e0, e1, w0;
    for (int a = 0; a < 2; ++a) {
      const ex f = phi[a].expand();
      if (f.degree(c0.symbol) > 1 || f.degree(c1.symbol) > 1) return;
      e0[a] = f.coeff(c0.symbol, 1);
      e1[a] = f.coeff(c1.symbol, 1);
      w0[a] = f.coeff(c0.symbol, 0).coeff(c1.symbol, 0);
      if (e0[a].has(c1.symbol) || e1[a].has(c0.symbol)) return;
    }
    b->solve = BlockSolve::kSS;
    b->e0 = e0;
    b->e1 = e1;
    b->w0 = w0;
  }
}

double Eval(const ex& e, const GiNaC::exmap& values) {
  const ex v = e.subs(values).evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(v)) return std::nan("");
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string Number(double v, bool angle) {
  char buf[48];
  std::snprintf(buf, sizeof buf, angle ? "%.6g deg" : "%.6g", angle ? v * 180 / M_PI : v);
  return buf;
}

double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

// Both closed-form solutions of a block at `values` (known coordinates and parameters);
// picks the assembly mode nearest the current values of its unknowns and stores the
// solution in *values, so that later blocks see it. A block with no real solution there
// (the loop cannot close at the model's assembly inputs) sets *no_solution to the reason.
void ChooseMode(const Kinematics& k, Block* b, GiNaC::exmap* values, std::string* no_solution) {
  if (b->solve == BlockSolve::kNewton || b->solve == BlockSolve::kSS) return;
  if (b->solve == BlockSolve::kLinear) {
    const double x = -Eval(b->c0, *values) / Eval(b->c1, *values);
    if (std::isfinite(x)) (*values)[k.phi[b->cols[0]].symbol] = x;  // (a cam law has no numeric value here)
    return;
  }
  if (b->solve == BlockSolve::kAngle) {
    const GiNaC::symbol u = k.phi[b->cols[0]].symbol;
    const double guess = Eval(u, *values);
    const double c0 = Eval(b->c0, *values), c1 = Eval(b->c1, *values), c2 = Eval(b->c2, *values);
    const double rho = std::hypot(c1, c2), delta = std::atan2(c2, c1);
    double best = INFINITY, best_u = guess;
    if (std::isfinite(c0) && std::isfinite(rho) && std::abs(c0) > rho)
      *no_solution = "no real solution, c0 + c1 cos u + c2 sin u = 0 needs |c0| <= sqrt(c1^2 + c2^2), but |c0| = " + G(std::abs(c0)) +
                     " > " + G(rho);
    for (int sigma : {1, -1}) {
      if (!(std::abs(c0) <= rho)) continue;
      const double su = delta + sigma * std::acos(-c0 / rho);
      if (AngleDistance(su, guess) < best) {
        best = AngleDistance(su, guess);
        b->default_mode = sigma;
        best_u = guess + std::remainder(su - guess, 2 * M_PI);
      }
    }
    (*values)[u] = best_u;
    return;
  }
  const GiNaC::symbol u = k.phi[b->cols[b->iu]].symbol, x = k.phi[b->cols[1 - b->iu]].symbol;
  const double u_guess = Eval(u, *values), x_guess = Eval(x, *values);
  double best = INFINITY;
  double best_u = u_guess, best_x = x_guess;
  for (int sigma : {1, -1}) {
    double su = NAN, sx = NAN;
    if (b->solve == BlockSolve::kRR) {
      const double ax = Eval(b->a[0], *values), ay = Eval(b->a[1], *values);
      const double bx = Eval(b->b[0], *values), by = Eval(b->b[1], *values);
      const double wx = -Eval(b->w0[0], *values), wy = -Eval(b->w0[1], *values);
      const double d2 = wx * wx + wy * wy, ra2 = ax * ax + ay * ay, rb2 = bx * bx + by * by;
      const double kk = (ra2 - rb2 + d2) / (2 * d2), h2 = ra2 / d2 - kk * kk;
      if (std::isfinite(h2) && h2 < 0)
        *no_solution = "no real solution, the two circles do not meet: radii " + G(std::sqrt(ra2)) + " and " +
                       G(std::sqrt(rb2)) + ", centres " + G(std::sqrt(d2)) + " apart";
      if (!(h2 >= 0)) continue;
      const double mx = kk * wx - sigma * std::sqrt(h2) * wy, my = kk * wy + sigma * std::sqrt(h2) * wx;
      su = std::atan2(my, mx) - std::atan2(ay, ax);
      sx = std::atan2(wy - my, wx - mx) - std::atan2(by, bx);
    } else {
      GiNaC::exmap without_x = *values;
      without_x.erase(x);
      const ex f = (b->a[0] * b->a[0] + b->a[1] * b->a[1] - b->w0[0] * b->w0[0] - b->w0[1] * b->w0[1]).expand();
      const double A = Eval(f.coeff(x, 2), without_x), B = Eval(f.coeff(x, 1), without_x),
                   C = Eval(f.coeff(x, 0), without_x);
      const double disc = B * B - 4 * A * C;
      if (A != 0 && std::isfinite(disc) && disc < 0)
        *no_solution = "no real solution, the circle and the line do not meet (discriminant " + G(disc) + " < 0)";
      if (A == 0 || !(disc >= 0)) continue;
      sx = (-B + sigma * std::sqrt(disc)) / (2 * A);
      GiNaC::exmap at = without_x;
      at[x] = sx;
      su = std::atan2(-Eval(b->w0[1], at), -Eval(b->w0[0], at)) - std::atan2(Eval(b->a[1], at), Eval(b->a[0], at));
    }
    const double dist = AngleDistance(su, u_guess) +
                        (k.phi[b->cols[1 - b->iu]].is_angle ? AngleDistance(sx, x_guess) : std::abs(sx - x_guess));
    if (dist < best) {
      best = dist;
      b->default_mode = sigma;
      best_u = u_guess + std::remainder(su - u_guess, 2 * M_PI);
      best_x = k.phi[b->cols[1 - b->iu]].is_angle ? x_guess + std::remainder(sx - x_guess, 2 * M_PI) : sx;
    }
  }
  (*values)[u] = best_u;
  (*values)[x] = best_x;
}

}  // namespace

std::string Block::Describe(const Kinematics& k) const {
  std::string s = "rows";
  for (int r : rows) s += " " + std::to_string(r);
  s += " -> ";
  for (size_t i = 0; i < cols.size(); ++i) s += (i ? ", " : "") + k.phi[cols[i]].name;
  switch (solve) {
    case BlockSolve::kNewton:
      return s + ": Newton-Raphson on the " + std::to_string(cols.size()) + "x" + std::to_string(cols.size()) + " block";
    case BlockSolve::kRR:
      return s + ": closed form, two angles (RRR dyad, circle-circle), mode " + std::to_string(default_mode);
    case BlockSolve::kRS:
      return s + ": closed form, angle and slide (RRP/RPR dyad, circle-line), mode " + std::to_string(default_mode);
    case BlockSolve::kSS:
      if (k.phi[cols[0]].is_angle || k.phi[cols[1]].is_angle) return s + ": closed form, linear 2x2 (Cramer)";
      return s + ": closed form, two slides (PRP dyad, line-line)";
    case BlockSolve::kAngle:
      return s + ": closed form, one angle (acos), mode " + std::to_string(default_mode);
    case BlockSolve::kLinear:
      return s + ": closed form, linear";
  }
  return s;
}

std::vector<Block> OrderBlocks(const Model& m, const Kinematics& k, Strategy strategy) {
  const int n = k.nphi();
  if (k.nc() != n)
    m.Fail(m.inputs_mark, "the loop equations (" + std::to_string(k.nc()) + ") do not match the unknowns (" +
                              std::to_string(n) + "); the mechanism has redundant constraints");
  std::vector<std::vector<int>> row_cols(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (!k.Phi_phi(i, j).is_zero()) row_cols[i].push_back(j);

  // Maximum matching rows -> unknowns (augmenting paths).
  std::vector<int> col_row(n, -1), row_col(n, -1);
  for (int r = 0; r < n; ++r) {
    std::vector<bool> seen(n, false);
    std::function<bool(int)> augment = [&](int row) {
      for (int c : row_cols[row]) {
        if (seen[c]) continue;
        seen[c] = true;
        if (col_row[c] < 0 || augment(col_row[c])) {
          col_row[c] = row;
          row_col[row] = c;
          return true;
        }
      }
      return false;
    };
    if (!augment(r))
      m.Fail(m.inputs_mark, "the loop equations cannot be solved for the unknowns (Phi_phi is structurally "
                            "singular at equation '" + k.Phi_source[r] + "'); check the inputs and joints");
  }

  // Tarjan's strongly connected components over unknowns; unknown c depends on every
  // unknown of the row matched to it. Components come out dependencies first.
  std::vector<int> index(n, -1), low(n, 0), stack;
  std::vector<bool> on_stack(n, false);
  int counter = 0;
  std::vector<std::vector<int>> components;
  std::function<void(int)> visit = [&](int c) {
    index[c] = low[c] = counter++;
    stack.push_back(c);
    on_stack[c] = true;
    for (int d : row_cols[col_row[c]]) {
      if (index[d] < 0) {
        visit(d);
        low[c] = std::min(low[c], low[d]);
      } else if (on_stack[d]) {
        low[c] = std::min(low[c], index[d]);
      }
    }
    if (low[c] == index[c]) {
      std::vector<int> comp;
      int d;
      do {
        d = stack.back();
        stack.pop_back();
        on_stack[d] = false;
        comp.push_back(d);
      } while (d != c);
      std::sort(comp.begin(), comp.end());
      components.push_back(comp);
    }
  };
  for (int c = 0; c < n; ++c)
    if (index[c] < 0) visit(c);
  if (strategy == Strategy::kMonolithic) {
    std::vector<int> all(n);
    for (int c = 0; c < n; ++c) all[c] = c;
    components = {all};
  }

  std::vector<Block> blocks;
  GiNaC::exmap values;
  for (const Parameter& p : m.params) values[p.symbol] = p.value;
  for (int i = 0; i < k.nq(); ++i) values[k.q[i].symbol] = k.assembly_q[i];
  for (int i = 0; i < n; ++i) values[k.phi[i].symbol] = k.assembly_phi[i];
  for (const auto& comp : components) {
    Block b;
    b.cols = comp;
    for (int c : comp) b.rows.push_back(col_row[c]);
    std::sort(b.rows.begin(), b.rows.end());
    if (strategy == Strategy::kBlocks) {
      // GiNaC's degree() throws on a non-integer power of an unknown (a contour cam's
      // normal, 1 / sqrt(x'(u)^2 + y'(u)^2)): no closed form, Newton's method.
      const Block plain = b;
      try {
        Recognize(k, &b);
      } catch (const std::runtime_error&) {
        b = plain;
      }
    }
    std::string no_solution;
    ChooseMode(k, &b, &values, &no_solution);
    if (no_solution.empty() &&
        (b.solve == BlockSolve::kRR || b.solve == BlockSolve::kRS || b.solve == BlockSolve::kAngle)) {
      // Solved at the assembly configuration: its Jacobian must be regular there. |det| is
      // compared with the product of the columns' norms (Hadamard's bound, so 1 means
      // orthogonal columns), and for one angle (c0 + c1 cos u + c2 sin u) with
      // sqrt(c1^2 + c2^2): 0 is a link of zero length (its angle moves nothing) or a dead
      // point exactly at the assembly input, where no branch can be chosen.
      const int n = static_cast<int>(b.cols.size());
      double J[2][2] = {{0, 0}, {0, 0}}, norms = 1;
      bool finite = true;
      for (int c = 0; c < n; ++c) {
        double norm2 = 0;
        for (int r = 0; r < n; ++r) {
          J[r][c] = Eval(k.Phi_phi(b.rows[r], b.cols[c]), values);
          finite &= std::isfinite(J[r][c]);
          norm2 += J[r][c] * J[r][c];
        }
        norms *= std::sqrt(norm2);
      }
      if (b.solve == BlockSolve::kAngle) norms = std::hypot(Eval(b.c1, values), Eval(b.c2, values));
      const double det = n == 1 ? J[0][0] : J[0][0] * J[1][1] - J[0][1] * J[1][0];
      if (finite && !(std::abs(det) > 1e-9 * norms))
        no_solution = "its Jacobian is singular there (det = " + G(det) + ", relative " +
                      G(norms > 0 ? std::abs(det) / norms : 0.0) +
                      "): a link of zero length, or a dead point exactly at the assembly input";
    }
    if (!no_solution.empty()) {
      // The loop cannot close at the model's own assembly inputs with the parameters'
      // default values: the generated code would work, but nothing the model describes
      // can be assembled. Reported at the assembly guess of an input (or the inputs).
      SourceMark mark = m.inputs_mark;
      bool at_guess = false;
      std::string at;
      for (int i = 0; i < k.nq(); ++i) {
        at += (i ? ", " : "") + k.q[i].name + " = " + Number(k.assembly_q[i], k.q[i].is_angle);
        for (const GuessValue& g : m.guess)
          if (g.coordinate == k.q[i].name && !at_guess) {
            mark = g.mark;
            at_guess = true;
          }
      }
      m.Fail(mark, "the loops cannot be assembled at the assembly configuration (" + at +
                       ") with the parameters' default values: block " + std::to_string(blocks.size()) + " (" +
                       b.Describe(k) + "): " + no_solution + "; change the assembly inputs or the lengths");
    }
    blocks.push_back(b);
  }
  return blocks;
}

}  // namespace mechgen
