// Block-triangular ordering and dyad recognition. See blocks.h.
#include "symbolic/blocks.h"

#include "model/expression_functions.h"
#include "symbolic/dyads.h"

#include <algorithm>
#include <string>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>

namespace mechgen {
namespace {

using GiNaC::ex;

// Phi = rest + R(u) p with p and rest free of u, or nothing.
struct RotationSplit {
  Vec2 p, rest;
};

// cos and sin of u + r (r free of u; a slot's or a point's constant angle on the link of
// angle u) expanded into cos u, sin u: cos(u + r) = cos u cos r - sin u sin r, and so on.
struct ExpandAngleSums : GiNaC::map_function {
  explicit ExpandAngleSums(const GiNaC::symbol& u) : u(u) {}
  ex operator()(const ex& e) override {
    if (!e.has(u)) return e;
    if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1) {
      const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
      if (name == "cos" || name == "sin") {
        const ex arg = e.op(0).expand();
        if (arg.degree(u) == 1 && arg.ldegree(u) >= 0) {
          const ex c = arg.coeff(u, 1), r = arg.coeff(u, 0);
          if (!r.is_zero() && !r.has(u) && (c.is_equal(1) || c.is_equal(-1))) {
            const ex cu = GiNaC::cos(u), su = c * GiNaC::sin(u);  // cos(c u), sin(c u)
            return name == "cos" ? cu * GiNaC::cos(r) - su * GiNaC::sin(r) : su * GiNaC::cos(r) + cu * GiNaC::sin(r);
          }
        }
      }
    }
    return e.map(*this);
  }
  const GiNaC::symbol& u;
};

ex ExpandAngles(const ex& e, const GiNaC::symbol& u) {
  ExpandAngleSums f(u);
  return f(e);
}

std::optional<RotationSplit> SplitRotation(const Vec2& phi, const GiNaC::symbol& u) {
  GiNaC::symbol C("C"), S("S");
  GiNaC::exmap m;
  m[GiNaC::cos(u)] = C;
  m[GiNaC::sin(u)] = S;
  ex e[2];
  for (int a = 0; a < 2; ++a) {
    e[a] = ExpandAngles(phi[a], u).expand().subs(m);
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
      const ex g = ExpandAngles(f, c.symbol).expand().subs(m);
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

// Both closed-form solutions of a block at `values` (known coordinates and parameters),
// from the one formulation the generated code prints (dyads.h); picks the assembly mode
// nearest the current values of its unknowns and stores the solution in *values, so that
// later blocks see it. A block with no real solution there (the loop cannot close at the
// model's assembly inputs) sets *no_solution to the reason.
// The designer's names of a block: the link an unknown angle turns ("link 'rod'"; the
// coordinate's name for another unknown) and the joints whose loop equations the block solves.
std::string LinkOf(const Model& m, const Kinematics& k, int col) {
  for (size_t l = 0; l < k.frames.size() && l < m.links.size(); ++l)
    if (k.frames[l].theta.is_equal(k.phi[col].symbol)) return "link '" + m.links[l].name + "'";
  return "'" + k.phi[col].name + "'";
}
std::string JointsOf(const Model& m, const Kinematics& k, const Block& b) {
  std::vector<int> joints;
  for (int r : b.rows) {
    const int j = r < static_cast<int>(k.Phi_rows.size()) ? k.Phi_rows[r].joint : -1;
    if (j >= 0 && std::find(joints.begin(), joints.end(), j) == joints.end()) joints.push_back(j);
  }
  std::string s;
  for (size_t i = 0; i < joints.size(); ++i)
    s += (i == 0 ? "" : i + 1 == joints.size() ? " and " : ", ") + m.joints[joints[i]].name;
  return (joints.size() == 1 ? "joint " : "joints ") + s;
}

std::string LinksOf(const Model& m, const Kinematics& k, const Block& b) {
  std::string s;
  for (size_t i = 0; i < b.cols.size(); ++i)
    s += (i == 0 ? "" : i + 1 == b.cols.size() ? " and " : ", ") + LinkOf(m, k, b.cols[i]);
  return s;
}

void ChooseMode(const Model& m, const Kinematics& k, Block* b, int index, GiNaC::exmap* values,
                std::string* no_solution) {
  // Two slides (Cramer) have one solution and leave the assembly guess as it was.
  if (b->solve == BlockSolve::kNewton || b->solve == BlockSolve::kSS) return;
  const ClosedForm form = FormulateClosedForm(k, *b, index);
  std::map<DyadLocal, double> locals;
  std::map<int, double> solution;
  const DyadStep* failed = nullptr;
  if (b->solve == BlockSolve::kLinear) {
    // (a cam law has no numeric value here: the guess stays)
    if (EvaluateClosedForm(form, *values, 1, &locals, &solution, &failed) && std::isfinite(solution[b->cols[0]]))
      (*values)[k.phi[b->cols[0]].symbol] = solution[b->cols[0]];
    return;
  }
  double best = INFINITY;
  std::map<int, double> chosen;
  for (const int c : b->cols) chosen[c] = Eval(k.phi[c].symbol, *values);
  const std::map<int, double> guess = chosen;
  for (int sigma : {1, -1}) {
    locals.clear();
    solution.clear();
    failed = nullptr;
    const bool ok = EvaluateClosedForm(form, *values, sigma, &locals, &solution, &failed);
    if (!ok) {
      // The requirement that failed: h2 >= 0 (RRR), disc >= 0 (RRP), |cos_arg| <= 1 (one angle).
      GiNaC::exmap at = *values;
      for (const DyadStep& s : form.steps)
        if (s.kind == DyadStep::Kind::kLocal && locals.count(s.local) && GiNaC::is_a<GiNaC::symbol>(s.symbol))
          at[s.symbol] = locals.at(s.local);
      const double measure = Eval(failed->value, at);
      if (b->solve == BlockSolve::kRR && !failed->singular && std::isfinite(measure)) {
        // The links a (angle u) and b (angle v) hang from two points d apart: they meet
        // when |ra - rb| <= d <= ra + rb.
        const double ra = std::sqrt(locals[DyadLocal::kRa2]), rb = std::sqrt(locals[DyadLocal::kRb2]);
        const double d = std::sqrt(locals[DyadLocal::kD2]);
        const std::string la = LinkOf(m, k, b->cols[b->iu]), lb = LinkOf(m, k, b->cols[1 - b->iu]);
        const std::string pair = la + " (" + G(ra) + ") and " + lb + " (" + G(rb) + ")";
        *no_solution = d > ra + rb
                           ? pair + " cannot reach each other to close " + JointsOf(m, k, *b) + ": the points they turn about are " +
                                 G(d) + " apart, more than " + G(ra) + " + " + G(rb) + " = " + G(ra + rb) +
                                 "; together they need at least " + G(d)
                           : pair + " cannot close " + JointsOf(m, k, *b) + ": the points they turn about are only " + G(d) +
                                 " apart, less than |" + G(ra) + " - " + G(rb) + "| = " + G(std::abs(ra - rb)) +
                                 "; the difference of their lengths must be at most " + G(d);
        *no_solution += " (no real solution, the two circles do not meet: radii " + G(ra) + " and " + G(rb) + ", centres " +
                        G(d) + " apart)";
      }
      if (b->solve == BlockSolve::kRS && std::isfinite(measure) && locals.count(DyadLocal::kQuadA) && locals[DyadLocal::kQuadA] != 0)
        *no_solution = LinkOf(m, k, b->cols[b->iu]) + " cannot reach the line of its slide to close " + JointsOf(m, k, *b) +
                       "; lengthen it or move the line (no real solution, the circle and the line do not meet: "
                       "discriminant " + G(measure) + " < 0)";
      if (b->solve == BlockSolve::kAngle && std::isfinite(locals[DyadLocal::kC0]) && std::isfinite(locals[DyadLocal::kRho]) &&
          std::abs(locals[DyadLocal::kC0]) > locals[DyadLocal::kRho])
        // rho = sqrt(c1^2 + c2^2) is how far the link reaches across the line the loop
        // closes on (its length when it is a plain bar), |c0| how far it must reach.
        *no_solution = LinkOf(m, k, b->cols[0]) + " (" + G(locals[DyadLocal::kRho]) + ") cannot reach across to close " +
                       JointsOf(m, k, *b) + "; it needs at least " + G(std::abs(locals[DyadLocal::kC0])) +
                       ": lengthen it or shorten what it spans (no real solution, c0 + c1 cos u + c2 sin u = 0 needs "
                       "|c0| <= sqrt(c1^2 + c2^2), but |c0| = " +
                       G(std::abs(locals[DyadLocal::kC0])) + " > " + G(locals[DyadLocal::kRho]) + ")";
      continue;
    }
    // A slide solved from a quadratic with no s^2 term has no second root to choose.
    if (b->solve == BlockSolve::kRS && !(locals.count(DyadLocal::kQuadA) && locals[DyadLocal::kQuadA] != 0)) continue;
    double dist = 0;
    for (const int c : b->cols)
      dist += k.phi[c].is_angle ? AngleDistance(solution[c], guess.at(c)) : std::abs(solution[c] - guess.at(c));
    if (dist < best) {
      best = dist;
      b->default_mode = sigma;
      for (const int c : b->cols)
        chosen[c] = k.phi[c].is_angle ? guess.at(c) + std::remainder(solution[c] - guess.at(c), 2 * M_PI) : solution[c];
    }
  }
  for (const int c : b->cols) (*values)[k.phi[c].symbol] = chosen[c];
}


// ---- Reach over the declared input ranges ---------------------------------------------

// An expression compiled for evaluation in double over numbered slots (the generator's
// symbols: parameters, inputs, unknowns, the closed forms' locals): thousands of
// evaluations per model, where GiNaC's subs and evalf would take seconds.
class Compiled {
 public:
  using Slots = std::map<ex, int, GiNaC::ex_is_less>;
  // Returns false (and compiles nothing) for what it does not know (a cam law's function).
  bool Compile(const ex& e, const Slots& slots) {
    ok_ = true;
    root_ = Node(e, slots);
    return ok_;
  }
  double operator()(const std::vector<double>& v) const { return root_(v); }

 private:
  using Fn = std::function<double(const std::vector<double>&)>;
  Fn Fail() {
    ok_ = false;
    return [](const std::vector<double>&) { return std::nan(""); };
  }
  Fn Node(const ex& e, const Slots& slots) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(e);
      const double d = n.is_real() ? n.to_double() : std::nan("");
      return [d](const std::vector<double>&) { return d; };
    }
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      const auto it = slots.find(e);
      if (it == slots.end()) return Fail();
      const int i = it->second;
      return [i](const std::vector<double>& v) { return v[i]; };
    }
    if (GiNaC::is_a<GiNaC::constant>(e)) {
      const ex n = e.evalf();
      if (!GiNaC::is_a<GiNaC::numeric>(n)) return Fail();
      const double d = GiNaC::ex_to<GiNaC::numeric>(n).to_double();
      return [d](const std::vector<double>&) { return d; };
    }
    std::vector<Fn> ops;
    for (size_t i = 0; i < e.nops(); ++i) ops.push_back(Node(e.op(i), slots));
    if (!ok_) return Fail();
    if (GiNaC::is_a<GiNaC::add>(e))
      return [ops](const std::vector<double>& v) {
        double sum = 0;
        for (const Fn& f : ops) sum += f(v);
        return sum;
      };
    if (GiNaC::is_a<GiNaC::mul>(e))
      return [ops](const std::vector<double>& v) {
        double product = 1;
        for (const Fn& f : ops) product *= f(v);
        return product;
      };
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const Fn b = ops[0], x = ops[1];
      if (e.op(1).is_equal(GiNaC::numeric(1, 2))) return [b](const std::vector<double>& v) { return std::sqrt(b(v)); };
      return [b, x](const std::vector<double>& v) { return std::pow(b(v), x(v)); };
    }
    if (!GiNaC::is_a<GiNaC::function>(e)) return Fail();
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    using Unary = double (*)(double);
    static const std::map<std::string, Unary> unary = {
        {"sin", [](double x) { return std::sin(x); }},   {"cos", [](double x) { return std::cos(x); }},
        {"tan", [](double x) { return std::tan(x); }},   {"asin", [](double x) { return std::asin(x); }},
        {"acos", [](double x) { return std::acos(x); }}, {"atan", [](double x) { return std::atan(x); }},
        {"exp", [](double x) { return std::exp(x); }},   {"log", [](double x) { return std::log(x); }},
        {"abs", [](double x) { return std::abs(x); }}};
    if (ops.size() == 1 && unary.count(name)) {
      const Unary f = unary.at(name);
      const Fn a = ops[0];
      return [f, a](const std::vector<double>& v) { return f(a(v)); };
    }
    // The expression language's piecewise functions (model/expression_functions.h).
    if (ops.size() == 1 && (name == "mstep" || name == "msign")) {
      const Unary f = name == "mstep" ? [](double x) { return StepValue(x); } : [](double x) { return SignValue(x); };
      const Fn a = ops[0];
      return [f, a](const std::vector<double>& v) { return f(a(v)); };
    }
    if (ops.size() == 2 && (name == "mmin" || name == "mmax" || name == "mmod")) {
      using Binary = double (*)(double, double);
      const Binary f = name == "mmin"   ? [](double a, double b) { return MinValue(a, b); }
                       : name == "mmax" ? [](double a, double b) { return MaxValue(a, b); }
                                        : [](double x, double p) { return p > 0 ? ModValue(x, p) : std::nan(""); };
      const Fn a = ops[0], b = ops[1];
      return [f, a, b](const std::vector<double>& v) { return f(a(v), b(v)); };
    }
    if (ops.size() == 2 && name == "atan2") {
      const Fn y = ops[0], x = ops[1];
      return [y, x](const std::vector<double>& v) { return std::atan2(y(v), x(v)); };
    }
    if (ops.size() == 2 && name == "stable_half") {  // -(B + sign(B) sq) / 2
      const Fn b = ops[0], sq = ops[1];
      return [b, sq](const std::vector<double>& v) {
        const double B = b(v), S = sq(v);
        return -(B + (B >= 0 ? S : -S)) / 2;
      };
    }
    if (ops.size() == 5 && name == "quadratic_root") {  // (A, B, C, qq, mode)
      return [ops](const std::vector<double>& v) {
        const double A = ops[0](v), B = ops[1](v), C = ops[2](v), Q = ops[3](v), M = ops[4](v);
        return ((M > 0) == (B >= 0)) ? (Q != 0 ? C / Q : 0.0) : Q / A;
      };
    }
    return Fail();
  }

  bool ok_ = true;
  Fn root_;
};

// The closed-form blocks compiled in solve order, evaluated at inputs q on the default
// modes. Blocks after a Newton block that read its unknowns, and blocks with a function the
// evaluator does not know (a cam law), are left out, with everything that reads theirs.
class ReachModel {
 public:
  ReachModel(const Model& m, const Kinematics& k, const std::vector<Block>& blocks) : k_(k), blocks_(blocks) {
    Compiled::Slots slots;
    auto slot = [&](const ex& symbol) {
      const auto it = slots.find(symbol);
      if (it != slots.end()) return it->second;
      const int i = static_cast<int>(values_.size());
      slots[symbol] = i;
      values_.push_back(std::nan(""));
      return i;
    };
    for (const Parameter& p : m.params) values_[slot(p.symbol)] = p.value;
    for (const Coordinate& c : k.q) q_slots_.push_back(slot(c.symbol));
    for (const Coordinate& c : k.phi) phi_slots_.push_back(slot(c.symbol));
    values_[slot(ScalarEpsilon())] = std::numeric_limits<double>::epsilon();
    values_[slot(ScalarNorm2Max())] = kNorm2MaxDouble;
    values_[slot(ScalarNorm2Min())] = kNorm2MinDouble;
    std::vector<bool> known(k.phi.size(), false);
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      if (b.solve == BlockSolve::kNewton) continue;
      BlockCode code;
      code.index = static_cast<int>(bi);
      code.form = FormulateClosedForm(k, b, code.index);
      values_[slot(code.form.mode)] = b.default_mode;
      bool ok = true;
      // The unknowns it reads must come from blocks evaluated here.
      for (const DyadStep& st : code.form.steps)
        for (size_t c = 0; c < k.phi.size(); ++c)
          for (const ex& e : {st.value, st.x, st.y, st.slack})
            if (!known[c] && std::find(b.cols.begin(), b.cols.end(), static_cast<int>(c)) == b.cols.end() &&
                e.has(k.phi[c].symbol))
              ok = false;
      auto compile = [&](const ex& e, Compiled* out) { ok = ok && out->Compile(e, slots); };
      for (size_t si = 0; si < code.form.steps.size(); ++si) {
        if (!ok) break;
        const DyadStep& st = code.form.steps[si];
        Step step;
        step.step = static_cast<int>(si);  // an index: BlockCode is copied when code_ grows
        switch (st.kind) {
          case DyadStep::Kind::kLocal:
            if (!GiNaC::is_a<GiNaC::symbol>(st.symbol) || st.symbol.is_equal(st.value)) continue;
            compile(st.value, &step.value);
            step.target = slot(st.symbol);
            break;
          case DyadStep::Kind::kRequire:
            compile(st.value, &step.value);
            if (!st.slack.is_zero()) compile(st.slack, &step.slack);
            if (st.has_clamped) step.target = slot(st.clamped);
            break;
          case DyadStep::Kind::kAngle:
            compile(st.y, &step.y);
            compile(st.x, &step.x);
            compile(st.value, &step.value);
            step.target = phi_slots_[st.col];
            break;
          case DyadStep::Kind::kValue:
            compile(st.value, &step.value);
            step.target = phi_slots_[st.col];
            break;
        }
        code.steps.push_back(step);
      }
      if (ok && code.form.has_branch) {
        code.has_branch = true;
        compile(code.form.branch_num, &code.branch_num);
        compile(code.form.branch_den, &code.branch_den);
      }
      if (!ok) continue;
      for (int c : b.cols) known[c] = true;
      code_.push_back(std::move(code));
    }
  }

  bool Empty() const { return code_.empty(); }

  // After Closes(q) returned true: the smallest relative discriminant of the blocks with two
  // modes (SolveReport::branch_measure, in [0, 1]; 1 if none) and its block.
  double BranchMeasure(int* block) const {
    double smallest = 1;
    *block = -1;
    for (const BlockCode& code : code_) {
      if (!code.has_branch) continue;
      const double den = code.branch_den(values_);
      const double measure = den > 0 ? std::min(1.0, std::max(0.0, code.branch_num(values_) / den)) : 0.0;
      if (*block < 0 || measure < smallest) {
        smallest = measure;
        *block = code.index;
      }
    }
    return smallest;
  }

  // Evaluates the blocks at q; false at the first requirement that fails (*block, *what).
  bool Closes(const std::vector<double>& q, int* block, std::string* what) {
    for (size_t i = 0; i < q.size(); ++i) values_[q_slots_[i]] = q[i];
    for (const BlockCode& code : code_) {
      for (const Step& s : code.steps) {
        const DyadStep& st = code.form.steps[s.step];
        switch (st.kind) {
          case DyadStep::Kind::kLocal:
            values_[s.target] = s.value(values_);
            break;
          case DyadStep::Kind::kRequire: {
            const double d = s.value(values_);
            const double slack = st.slack.is_zero() ? 0.0 : s.slack(values_);
            const bool ok = st.require == DyadStep::Require::kNonNegative    ? d >= -slack
                            : st.require == DyadStep::Require::kAbsAtMostOne ? std::abs(d) <= 1 + slack
                            : st.require == DyadStep::Require::kPositive     ? d > 0
                                                                             : d != 0;
            if (!ok) {
              *block = code.index;
              *what = st.what;
              return false;
            }
            if (st.has_clamped)
              values_[s.target] = st.require == DyadStep::Require::kNonNegative ? std::max(d, 0.0)
                                                                                : std::max(-1.0, std::min(d, 1.0));
            break;
          }
          case DyadStep::Kind::kAngle:
            values_[s.target] = std::atan2(s.y(values_), s.x(values_)) + s.value(values_);
            break;
          case DyadStep::Kind::kValue:
            values_[s.target] = s.value(values_);
            break;
        }
      }
    }
    return true;
  }

 private:
  struct Step {
    int step = -1;  ///< index into the form's steps
    Compiled value, x, y, slack;
    int target = -1;
  };
  struct BlockCode {
    int index = 0;
    ClosedForm form;
    std::vector<Step> steps;
    bool has_branch = false;
    Compiled branch_num, branch_den;
  };
  const Kinematics& k_;
  const std::vector<Block>& blocks_;
  std::vector<double> values_;
  std::vector<int> q_slots_, phi_slots_;
  std::vector<BlockCode> code_;
};

// Every closed-form block must close over each input's declared range (the others at
// their assembly values) at the parameters' defaults, on the default modes: walked from
// the assembly input to each end of the range; where it stops closing is found by
// bisection and reported at the input's range. A change point is not the end of the reach:
// a block's two modes meet at an isolated input (its relative discriminant, the branch
// measure, touches 0 and the loop closes on both sides; or its circle centres coincide
// there, and it closes again just beyond). Those are recorded in the block's change_points.
void CheckReach(const Model& m, const Kinematics& k, std::vector<Block>* blocks) {
  ReachModel reach(m, k, *blocks);
  if (reach.Empty()) return;
  constexpr int kSamples = 720;
  // A relative discriminant this small at its minimum: the modes meet (to rounding: the
  // measure is sin^2 of an angle, so 1e-12 is a configuration within 1e-6 rad of the point).
  constexpr double kTouch = 1e-12;
  auto record = [&](int input, int block, double at, ChangePoint::Kind kind) {
    if (block < 0) return;
    for (const ChangePoint& c : (*blocks)[block].change_points)
      if (c.input == input && std::abs(c.value - at) < 1e-9 * (1 + std::abs(at))) return;
    (*blocks)[block].change_points.push_back({input, at, kind});
  };
  for (int i = 0; i < k.nq(); ++i) {
    const double lo = std::min(k.q_min[i], k.q_max[i]), hi = std::max(k.q_min[i], k.q_max[i]);
    if (!(hi > lo) || !std::isfinite(hi - lo)) continue;
    std::vector<double> q = k.assembly_q;
    const double start = std::min(hi, std::max(lo, k.assembly_q[i]));
    int block = -1;
    std::string what;
    q[i] = start;
    if (!reach.Closes(q, &block, &what)) continue;  // the assembly's own check reports it
    auto measure_at = [&](double at, int* b) {
      q[i] = at;
      int failed = -1;
      std::string w;
      if (!reach.Closes(q, &failed, &w)) {
        *b = failed;
        return 0.0;
      }
      return reach.BranchMeasure(b);
    };
    for (const double end : {hi, lo}) {
      const double h = (hi - lo) / kSamples;
      double good = start;
      const int n = static_cast<int>(std::ceil(std::abs(end - start) / h));
      // The last two samples that closed and their branch measures.
      double at1 = start, at2 = NAN, m1 = NAN, m2 = NAN;
      int b1 = -1;
      m1 = measure_at(start, &b1);
      for (int s = 1; s <= n; ++s) {
        const double at = s == n ? end : start + (end > start ? h : -h) * s;
        q[i] = at;
        if (reach.Closes(q, &block, &what)) {
          int b0 = -1;
          const double m0 = reach.BranchMeasure(&b0);
          // A local minimum of the measure at the previous sample: refined (golden section
          // between its neighbours); touching 0 there is a change point.
          if (b1 >= 0 && std::isfinite(m2) && m1 <= m2 && m1 <= m0 && m1 < 1e-3) {
            double a = at2, c = at;
            const double g = (std::sqrt(5.0) - 1) / 2;
            double x1 = c - g * (c - a), x2 = a + g * (c - a);
            int bx = -1;
            double f1 = measure_at(x1, &bx), f2 = measure_at(x2, &bx);
            for (int it = 0; it < 100 && std::abs(c - a) > 1e-13 * (1 + std::abs(a)); ++it) {
              if (f1 <= f2) {
                c = x2;
                x2 = x1;
                f2 = f1;
                x1 = c - g * (c - a);
                f1 = measure_at(x1, &bx);
              } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + g * (c - a);
                f2 = measure_at(x2, &bx);
              }
            }
            double at_min = f1 <= f2 ? x1 : x2, f_min = std::min(f1, f2);
            if (m1 <= f_min) {
              at_min = at1;
              f_min = m1;
            }
            if (f_min < kTouch) {
              // Nearest a whole sample when that is where it is (0 and 180 deg by hand).
              record(i, b1, std::abs(at_min - at1) < 1e-6 * h ? at1 : at_min, ChangePoint::Kind::kModesMeet);
            }
          }
          // The end of the range at a change point: the measure 0 there and the loop closing
          // beyond it (else it is the limit of the reach, a dead point, ending the range).
          if (s == n && b0 >= 0 && m0 < kTouch) {
            int b3 = -1;
            std::string w3;
            q[i] = at + (end > start ? 1 : -1) * 1e-6 * h;
            if (reach.Closes(q, &b3, &w3)) record(i, b0, at, ChangePoint::Kind::kModesMeet);
          }
          at2 = at1;
          m2 = m1;
          at1 = at;
          m1 = m0;
          b1 = b0;
          good = at;
          continue;
        }
        // Bisection between the last input that closes and this one.
        double bad = at;
        for (int it = 0; it < 60 && std::abs(bad - good) > 1e-12 * (1 + std::abs(good)); ++it) {
          q[i] = (good + bad) / 2;
          int b2 = -1;
          std::string w2;
          if (reach.Closes(q, &b2, &w2)) {
            good = q[i];
          } else {
            bad = q[i];
            block = b2;
            what = w2;
          }
        }
        // An isolated input where a dyad's circle centres coincide (the dyad can turn about
        // them: a change point of the linkage, e.g. a rhombus folded flat), with the loop
        // closing again just beyond: not the end of the reach.
        {
          int b3 = -1;
          std::string w3;
          q[i] = bad + (end > start ? 1 : -1) * 1e-6 * h;
          const bool closes_beyond = reach.Closes(q, &b3, &w3);
          if (closes_beyond && what == kCentresCoincide) {
            record(i, block, std::abs(bad - at) < 1e-9 * (1 + std::abs(at)) ? at : (good + bad) / 2,
                   ChangePoint::Kind::kCentresCoincide);
            at2 = NAN;
            m2 = NAN;
            b1 = -1;
            good = q[i];
            continue;
          }
        }
        const Input& in = m.inputs[i];
        const bool angle = k.q[i].is_angle;
        m.Fail(in.range_mark.line > 0 ? in.range_mark : in.mark,
               "input '" + k.q[i].name + "' is driven over [" + Number(k.q_min[i], angle) + ", " +
                   Number(k.q_max[i], angle) + "], but block " + std::to_string(block) + " (" +
                   (*blocks)[block].Describe(k) + ") stops closing at " + k.q[i].name + " = " + Number(good, angle) +
                   " (from the assembly at " + Number(start, angle) + "; " + what + " beyond it: " +
                   LinksOf(m, k, (*blocks)[block]) + " cannot close " + JointsOf(m, k, (*blocks)[block]) +
                   " there) with the parameters' default values; narrow the range or change the lengths");
      }
    }
  }
  for (Block& b : *blocks)
    std::sort(b.change_points.begin(), b.change_points.end(),
              [](const ChangePoint& x, const ChangePoint& y) { return std::tie(x.input, x.value) < std::tie(y.input, y.value); });
}
}  // namespace

std::vector<std::string> ChangePointNotes(const Kinematics& k, const std::vector<Block>& blocks) {
  std::vector<std::string> notes;
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    for (int input = 0; input < k.nq(); ++input) {
      std::string at;
      bool coincide = false;
      int count = 0;
      for (const ChangePoint& c : b.change_points) {
        if (c.input != input) continue;
        at += std::string(count ? ", " : "") + Number(c.value, k.q[input].is_angle);
        coincide |= c.kind == ChangePoint::Kind::kCentresCoincide;
        ++count;
      }
      if (count == 0) continue;
      const std::string mode = (b.default_mode > 0 ? "+" : "-") + std::to_string(std::abs(b.default_mode));
      const std::string other = (b.default_mode > 0 ? "-" : "+") + std::to_string(std::abs(b.default_mode));
      notes.push_back(
          "input '" + k.q[input].name + "' passes " + (count == 1 ? "a change point" : "change points") + " of block " +
          std::to_string(bi) + " (" + b.Describe(k) + ") at " + k.q[input].name + " = " + at +
          (k.nq() > 1 ? " (the other inputs at their assembly values)" : "") + ": " +
          (coincide ? "its two circle centres coincide there (the dyad can turn about them) or its two modes meet"
                    : "its two assembly modes meet there (the linkage folds flat)") +
          ". The generated SolvePositions keeps mode " + mode +
          ", which past " + (count == 1 ? "it" : "each of them") +
          " names the other branch of the linkage (its report's branch_measure falls to 0 "
          "there" + (coincide ? ", and it returns kSingular exactly where the centres coincide" : "") +
          "); a motion that stays on its smooth branch goes on in mode " + other +
          " (the runtime's PositionSolver::PassSingularity with Crossing::kFollowTangent).");
    }
  }
  return notes;
}

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
    const bool matched = augment(r);
    if (!matched && k.Phi_rows[r].joint < 0) {
      const Input& in = m.inputs[k.Phi_rows[r].input];
      m.Fail(in.mark, "input " + k.q[k.Phi_rows[r].input].name + " cannot drive the linkage: " + m.PointName(in.point) +
                          "'s coordinate moves with no dependent coordinate the other inputs leave free (its driving "
                          "constraint '" + k.Phi_source[r] + "' is structurally singular); drive a point that the "
                          "other inputs do not already place, or another coordinate");
    }
    if (!matched)
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
    ChooseMode(m, k, &b, static_cast<int>(blocks.size()), &values, &no_solution);
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
  // Named assembly modes: each block's mode nearest the mode's guess (over the assembly's),
  // chosen as the default's, block after block.
  for (const NamedMode& mode : m.assembly_modes) {
    GiNaC::exmap at;
    for (const Parameter& p : m.params) at[p.symbol] = p.value;
    std::map<std::string, double> guess;
    for (const GuessValue& g : mode.guess) guess[g.coordinate] = g.value;
    auto value = [&](const Coordinate& c, double otherwise) { return guess.count(c.name) ? guess[c.name] : otherwise; };
    std::string where;
    for (int i = 0; i < k.nq(); ++i) {
      at[k.q[i].symbol] = value(k.q[i], k.assembly_q[i]);
      where += (i ? ", " : "") + k.q[i].name + " = " + Number(value(k.q[i], k.assembly_q[i]), k.q[i].is_angle);
    }
    for (int i = 0; i < n; ++i) at[k.phi[i].symbol] = value(k.phi[i], k.assembly_phi[i]);
    for (size_t i = 0; i < blocks.size(); ++i) {
      Block b = blocks[i];
      std::string no_solution;
      ChooseMode(m, k, &b, static_cast<int>(i), &at, &no_solution);
      if (!no_solution.empty())
        m.Fail(mode.mark, "assembly mode '" + mode.name + "' cannot be assembled (" + where + ") with the parameters' "
                          "default values: block " + std::to_string(i) + " (" + b.Describe(k) + "): " + no_solution +
                          "; change its values or the lengths");
      blocks[i].named_modes.push_back(b.default_mode);
    }
  }
  if (strategy == Strategy::kBlocks) CheckReach(m, k, &blocks);
  return blocks;
}

}  // namespace mechgen
