// See hoist.h.
#include "codegen/hoist.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <stdexcept>

namespace mechgen {
namespace {

using GiNaC::ex;
using GiNaC::is_a;

void Symbols(const ex& e, ExSet* out) {
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (is_a<GiNaC::symbol>(*it)) out->insert(*it);
}

bool Only(const ex& e, const ExSet& allowed) {
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (is_a<GiNaC::symbol>(*it) && !allowed.count(*it)) return false;
  return true;
}

// A number, a symbol, or a symbol times -1: nothing to gain from a constant.
bool Trivial(const ex& e) {
  if (is_a<GiNaC::numeric>(e) || is_a<GiNaC::symbol>(e)) return true;
  if (is_a<GiNaC::mul>(e) && e.nops() == 2) {
    const ex a = e.op(0), b = e.op(1);
    if (is_a<GiNaC::symbol>(a) && b.is_equal(-1)) return true;
    if (is_a<GiNaC::symbol>(b) && a.is_equal(-1)) return true;
  }
  return false;
}

struct MapBy : GiNaC::map_function {
  explicit MapBy(const std::function<ex(const ex&)>& f) : f_(f) {}
  ex operator()(const ex& e) override { return f_(e); }
  const std::function<ex(const ex&)>& f_;
};

// Whether `name` occurs as a whole identifier in `text`.
bool Mentions(const std::string& text, const std::string& name) {
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (size_t pos = text.find(name); pos != std::string::npos; pos = text.find(name, pos + 1)) {
    const bool before = pos > 0 && word(text[pos - 1]);
    const bool after = pos + name.size() < text.size() && word(text[pos + name.size()]);
    if (!before && !after) return true;
  }
  return false;
}

}  // namespace

static ex ReducePolynomial(const ex& e,
                           const std::vector<std::pair<ex, ex>>& sin_cos,
                           const ExSet& params,
                           size_t* terms);

// The symbols of `x` that are not parameters (the state: sin and cos of the angles, speeds),
// in the order of ExSet, as GiNaC's collect and is_polynomial take them.
static GiNaC::lst StateSymbols(const ex& x, const ExSet& params) {
  ExSet all;
  Symbols(x, &all);
  GiNaC::lst state;
  for (const ex& s : all)
    if (!params.count(s)) state.append(s);
  return state;
}

ex ReduceTrig(const ex& e, const std::vector<std::pair<ex, ex>>& sin_cos, const ExSet& params, size_t* terms) {
  // Not a polynomial in them (a square root, a non-integer power): left as it is.
  try {
    return ReducePolynomial(e, sin_cos, params, terms);
  } catch (const std::exception&) {
    *terms = static_cast<size_t>(-1);
    return e;
  }
}

static ex ReducePolynomial(const ex& e,
                           const std::vector<std::pair<ex, ex>>& sin_cos,
                           const ExSet& params,
                           size_t* terms) {
  GiNaC::exmap to, from;
  std::vector<std::pair<GiNaC::symbol, GiNaC::symbol>> sc;
  for (const auto& [s, c] : sin_cos) {
    GiNaC::symbol ss("reduce_sin"), cs("reduce_cos");
    to[s] = ss;
    to[c] = cs;
    from[ss] = s;
    from[cs] = c;
    sc.emplace_back(ss, cs);
  }
  ex x = e.subs(to).expand();
  // Only a polynomial in the state (a rational function, a damper's 1/length, is left as
  // it is: GiNaC's collect is defined for polynomials only).
  if (!x.is_polynomial(StateSymbols(x, params))) throw std::domain_error("not a polynomial in the state");
  // sin^n = sin^(n-2) (1 - cos^2) until no sin is squared.
  for (int pass = 0; pass < 16; ++pass) {
    bool changed = false;
    for (const auto& [s, c] : sc) {
      if (x.degree(s) < 2) continue;
      x = x.subs(GiNaC::pow(s, 2) == 1 - GiNaC::pow(c, 2), GiNaC::subs_options::algebraic).expand();
      changed = true;
    }
    if (!changed) break;
  }
  const GiNaC::lst vars = StateSymbols(x, params);
  if (vars.nops() > 0) x = GiNaC::collect(x, vars, true);
  *terms = is_a<GiNaC::add>(x) ? x.nops() : 1;
  return x.subs(from);
}

namespace {

std::vector<ex> Terms(const ex& e) {
  std::vector<ex> t;
  if (is_a<GiNaC::add>(e))
    for (size_t i = 0; i < e.nops(); ++i) t.push_back(e.op(i));
  else if (!e.is_zero())
    t.push_back(e);
  return t;
}

// The sum of the terms of `a` that occur in `b` times `sign` (each term of b matched once).
ex Shared(const ex& a, const ex& b, int sign) {
  const std::vector<ex> tb = Terms(b.expand());
  std::vector<bool> taken(tb.size(), false);
  ex g = 0;
  for (const ex& t : Terms(a.expand()))
    for (size_t i = 0; i < tb.size(); ++i)
      if (!taken[i] && (t - sign * tb[i]).expand().is_zero()) {
        taken[i] = true;
        g += t;
        break;
      }
  return g;
}

}  // namespace

ex UseAngleDifferences(const ex& e, const ExSet& params, std::vector<AngleDifference>* diffs) {
  ex x = e.expand();
  bool changed = false;
  for (AngleDifference& d : *diffs) {
    if (!(x.has(d.sin_x) || x.has(d.cos_x)) || !(x.has(d.sin_y) || x.has(d.cos_y))) continue;
    GiNaC::symbol sx("diff_sin_x"), cx("diff_cos_x"), sy("diff_sin_y"), cy("diff_cos_y");
    GiNaC::exmap to, from;
    to[d.sin_x] = sx;
    to[d.cos_x] = cx;
    to[d.sin_y] = sy;
    to[d.cos_y] = cy;
    for (const auto& [a, b] : to) from[b] = a;
    ex p = x.subs(to).expand();
    if (!p.is_polynomial(GiNaC::lst{sx, cx, sy, cy})) continue;
    // A common term of the two coefficients is free of all four (each coefficient is free
    // of the two it was taken on): subtracting it times the pair removes exactly those terms.
    const ex gc = Shared(p.coeff(cx, 1).coeff(cy, 1), p.coeff(sx, 1).coeff(sy, 1), 1);
    const ex gs = Shared(p.coeff(sx, 1).coeff(cy, 1), p.coeff(cx, 1).coeff(sy, 1), -1);
    if (gc.is_zero() && gs.is_zero()) continue;
    p = (p - gc * (cx * cy + sx * sy) + gc * d.cos_d - gs * (sx * cy - cx * sy) + gs * d.sin_d).expand();
    d.cos_used |= !gc.is_zero();
    d.sin_used |= !gs.is_zero();
    x = p.subs(from);
    changed = true;
  }
  if (!changed) return e;
  // Collected as ReduceTrig leaves it: one parameter coefficient per monomial of the state.
  const GiNaC::lst vars = StateSymbols(x, params);
  return vars.nops() > 0 ? GiNaC::collect(x, vars, true) : x;
}

std::vector<ex> HoistParameters(const ExSet& params,
                                const std::string& access,
                                CxxPrinter* printer,
                                std::vector<Program>* body) {
  ExSet param_like = params;
  GiNaC::exmap value_of;                            // a parameter-like local -> its value in the parameters
  std::map<ex, ex, GiNaC::ex_is_less> constant_of;  // value -> its symbol
  auto pure = [&](const ex& e) { return e.subs(value_of); };
  auto constant = [&](const ex& e) -> ex {
    const ex v = pure(e);
    auto it = constant_of.find(v);
    if (it == constant_of.end()) {
      it = constant_of.emplace(v, GiNaC::symbol("hoisted")).first;
      param_like.insert(it->second);
      value_of[it->second] = v;
    }
    return it->second;
  };
  std::function<ex(const ex&)> hoist = [&](const ex& e) -> ex {
    if (is_a<GiNaC::numeric>(e) || is_a<GiNaC::symbol>(e)) return e;
    if (Only(e, param_like)) return Trivial(e) ? e : constant(e);
    if (is_a<GiNaC::add>(e) || is_a<GiNaC::mul>(e)) {
      const bool sum = is_a<GiNaC::add>(e);
      ex fixed = sum ? 0 : 1, rest = sum ? 0 : 1;
      for (size_t i = 0; i < e.nops(); ++i) {
        const ex o = e.op(i);
        if (Only(o, param_like))
          fixed = sum ? fixed + o : fixed * o;
        else
          rest = sum ? rest + hoist(o) : rest * hoist(o);
      }
      if (!Trivial(fixed)) fixed = constant(fixed);
      return sum ? fixed + rest : fixed * rest;
    }
    MapBy by(hoist);
    return e.map(by);
  };
  for (Program& program : *body)
    for (Statement& s : program) {
      if (s.kind != Statement::Kind::kDefine && s.kind != Statement::Kind::kStore) continue;
      s.value = hoist(s.value);
      if (s.kind == Statement::Kind::kDefine && Only(s.value, param_like)) {
        param_like.insert(s.symbol);
        value_of[s.symbol] = pure(s.value);
      }
    }
  std::vector<std::pair<std::string, std::pair<ex, ex>>> sorted;  // key, (value, symbol)
  for (const auto& [value, sym] : constant_of) sorted.push_back({printer->Key(value), {value, sym}});
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<ex> values;
  for (size_t i = 0; i < sorted.size(); ++i) {
    printer->Name(sorted[i].second.second, access + "[" + std::to_string(i) + "]");
    values.push_back(sorted[i].second.first);
  }
  // Locals nothing reads any more (their uses became constants): dropped, unless a raw line
  // (a solver's check) names them.
  std::string raw;
  for (const Program& program : *body)
    for (const Statement& s : program)
      if (s.kind == Statement::Kind::kRaw) raw += s.target + "\n";
  ExSet used;
  for (auto p = body->rbegin(); p != body->rend(); ++p) {
    Program kept;
    for (auto it = p->rbegin(); it != p->rend(); ++it) {
      const Statement& s = *it;
      if (s.kind == Statement::Kind::kDefine) {
        if (!used.count(s.symbol) && !Mentions(raw, s.target)) continue;
        Symbols(s.value, &used);
      } else if (s.kind == Statement::Kind::kStore) {
        Symbols(s.value, &used);
      }
      kept.push_back(s);
    }
    p->assign(kept.rbegin(), kept.rend());
  }
  return values;
}

}  // namespace mechgen
