// C++ printing and common-subexpression elimination. See cxx_code.h.
#include "codegen/cxx_code.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace mechgen {
namespace {

using GiNaC::ex;

bool IsLeaf(const ex& e) {
  return GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::numeric>(e) ||
         GiNaC::is_a<GiNaC::constant>(e);
}

// The numeric coefficient of a product (1 if none).
GiNaC::numeric Coefficient(const ex& e) {
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    const ex last = e.op(e.nops() - 1);
    if (GiNaC::is_a<GiNaC::numeric>(last)) return GiNaC::ex_to<GiNaC::numeric>(last);
  }
  if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e);
  return 1;
}

// The subexpressions CSE looks at: a product with a coefficient c exposes c * rest as
// its one child, so that 2*a*b and -a*b share a*b.
std::vector<ex> Children(const ex& e) {
  std::vector<ex> kids;
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    const GiNaC::numeric c = Coefficient(e);
    if (c != 1) {
      kids.push_back(e / c);
      return kids;
    }
  }
  if (GiNaC::is_a<GiNaC::power>(e)) {
    kids.push_back(e.op(0));
    if (!GiNaC::is_a<GiNaC::numeric>(e.op(1))) kids.push_back(e.op(1));
    return kids;
  }
  for (size_t i = 0; i < e.nops(); ++i)
    if (!IsLeaf(e.op(i))) kids.push_back(e.op(i));
  return kids;
}

bool IsIntegerPower(const ex& e) {
  return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
         GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_integer();
}

}  // namespace

std::string OpCounts::Text() const {
  std::ostringstream os;
  os << Total() << " (adds " << adds << ", muls " << muls << ", divs " << divs << ", calls "
     << calls << ")";
  return os.str();
}

OpCounts& OpCounts::operator+=(const OpCounts& o) {
  adds += o.adds;
  muls += o.muls;
  divs += o.divs;
  calls += o.calls;
  return *this;
}

void CxxPrinter::Name(const GiNaC::ex& s, const std::string& name) { names_[s] = name; }

const std::string& CxxPrinter::Key(const GiNaC::ex& e) {
  auto it = keys_.find(e);
  if (it != keys_.end()) return it->second;
  return keys_.emplace(e, Print(e)).first->second;
}

std::string CxxPrinter::PrintNumber(const GiNaC::numeric& n) const {
  if (!n.is_real()) throw std::logic_error("complex number in generated code");
  if (n.is_integer() && GiNaC::abs(n) < GiNaC::numeric(1000000000)) {
    return "Scalar(" + std::to_string(n.to_long()) + ")";
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", n.to_double());
  std::string s = buf;
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return "Scalar(" + s + ")";
}

// The terms of a sum, each printed without its sign, in our order (by text): GiNaC's own
// order follows hash values that vary between runs.
std::vector<CxxPrinter::Term> CxxPrinter::AddTerms(const GiNaC::ex& e, OpCounts* ops) {
  std::vector<Term> terms;
  for (size_t i = 0; i < e.nops(); ++i) {
    const GiNaC::ex t = e.op(i);
    bool neg = Coefficient(t) < 0;
    std::string text = Print(neg ? GiNaC::ex(-t) : t, ops);
    if (GiNaC::is_a<GiNaC::mul>(t) && text[0] == '-') {  // a sum inside it turned round (Print's mul)
      text.erase(0, 1);
      neg = !neg;
    }
    terms.push_back({std::move(text), neg});
  }
  std::sort(terms.begin(), terms.end(), [](const Term& a, const Term& b) {
    return a.text != b.text ? a.text < b.text : a.negative < b.negative;
  });
  return terms;
}

std::string CxxPrinter::JoinTerms(std::vector<Term> terms, OpCounts* ops) {
  std::string s;
  for (size_t i = 0; i < terms.size(); ++i) {
    if (i == 0)
      s = terms[i].negative ? "-" + terms[i].text : terms[i].text;
    else
      s += (terms[i].negative ? " - " : " + ") + terms[i].text;
  }
  if (ops) ops->adds += static_cast<int>(terms.size()) - 1;
  return s;
}

// A factor of a product or the base of a power: parenthesized unless atomic.
std::string CxxPrinter::PrintFactor(const GiNaC::ex& e, OpCounts* ops) {
  const std::string s = Print(e, ops);
  const bool operator_function =
      GiNaC::is_a<GiNaC::function>(e) && (GiNaC::ex_to<GiNaC::function>(e).get_name() == "stable_half" ||
                                          GiNaC::ex_to<GiNaC::function>(e).get_name() == "quadratic_root");
  if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e) ||
      (GiNaC::is_a<GiNaC::numeric>(e) && GiNaC::ex_to<GiNaC::numeric>(e) < 0) ||
      GiNaC::is_a<GiNaC::power>(e) || operator_function)
    return "(" + s + ")";
  return s;
}

std::string CxxPrinter::Print(const GiNaC::ex& e, OpCounts* ops) {
  using GiNaC::ex_to;
  using GiNaC::is_a;
  if (is_a<GiNaC::numeric>(e)) return PrintNumber(ex_to<GiNaC::numeric>(e));
  if (is_a<GiNaC::symbol>(e)) {
    auto it = names_.find(e);
    if (it == names_.end())
      throw std::logic_error("mechgen bug: no C++ name for symbol " +
                             ex_to<GiNaC::symbol>(e).get_name());
    return it->second;
  }
  if (is_a<GiNaC::constant>(e)) return PrintNumber(ex_to<GiNaC::numeric>(e.evalf()));

  if (is_a<GiNaC::add>(e)) return JoinTerms(AddTerms(e, ops), ops);

  if (is_a<GiNaC::mul>(e)) {
    const GiNaC::numeric c = Coefficient(e);
    bool negate = c < 0;
    std::vector<std::string> num, den;
    for (size_t i = 0; i < e.nops(); ++i) {
      const ex f = e.op(i);
      if (is_a<GiNaC::numeric>(f)) continue;  // the coefficient
      if (IsIntegerPower(f) && ex_to<GiNaC::numeric>(f.op(1)) < 0) {
        den.push_back(PrintFactor(GiNaC::pow(f.op(0), -f.op(1)), ops));
      } else if (is_a<GiNaC::add>(f)) {
        // GiNaC scales a sum inside a product so that the first of its terms, in GiNaC's own
        // order, has a positive coefficient; that order follows hash values that change from
        // run to run, so one run holds -1/2*(-a + b) and the next 1/2*(a - b). Printed with the
        // first term in our order positive, both are 1/2*(a - b): the same bytes on every run
        // (and the same value: negating a sum's terms is exact).
        std::vector<Term> terms = AddTerms(f, ops);
        if (!terms.empty() && terms.front().negative) {
          for (Term& t : terms) t.negative = !t.negative;
          negate = !negate;
        }
        num.push_back("(" + JoinTerms(std::move(terms), ops) + ")");
      } else {
        num.push_back(PrintFactor(f, ops));
      }
    }
    std::sort(num.begin(), num.end());
    std::sort(den.begin(), den.end());
    std::string s;
    const GiNaC::numeric ac = GiNaC::abs(c);
    if (ac != 1 || num.empty()) num.insert(num.begin(), PrintNumber(ac));
    for (size_t i = 0; i < num.size(); ++i) s += (i ? "*" : "") + num[i];
    if (ops) ops->muls += static_cast<int>(num.size()) - 1;
    if (!den.empty()) {
      std::string d;
      for (size_t i = 0; i < den.size(); ++i) d += (i ? "*" : "") + den[i];
      s += "/" + (den.size() > 1 ? "(" + d + ")" : d);
      if (ops) {
        ops->divs += 1;
        ops->muls += static_cast<int>(den.size()) - 1;
      }
    }
    return negate ? "-" + s : s;
  }

  if (is_a<GiNaC::power>(e)) {
    const ex base = e.op(0), expo = e.op(1);
    if (is_a<GiNaC::numeric>(expo)) {
      const GiNaC::numeric n = ex_to<GiNaC::numeric>(expo);
      if (n.is_integer()) {
        const long k = n.to_long();
        const std::string b = PrintFactor(base, ops);
        std::string s = b;
        for (long i = 1; i < std::labs(k); ++i) s += "*" + b;
        if (ops) ops->muls += static_cast<int>(std::labs(k) - 1);
        if (k < 0) {
          if (ops) ops->divs += 1;
          return "Scalar(1)/" + (std::labs(k) > 1 ? "(" + s + ")" : s);
        }
        return s;
      }
      if (n == GiNaC::numeric(1, 2) || n == GiNaC::numeric(-1, 2)) {
        if (ops) ops->calls += 1;
        const std::string s = "sqrt(" + Print(base, ops) + ")";
        if (n < 0) {
          if (ops) ops->divs += 1;
          return "Scalar(1)/" + s;
        }
        return s;
      }
    }
    if (ops) ops->calls += 1;
    return "pow(" + Print(base, ops) + ", " + Print(expo, ops) + ")";
  }

  if (is_a<GiNaC::function>(e)) {
    std::string name = ex_to<GiNaC::function>(e).get_name();
    if (name == "camlaw") {
      const auto it = cam_laws_.find(ex_to<GiNaC::numeric>(e.op(0)).to_int());
      if (it == cam_laws_.end()) throw std::logic_error("mechgen bug: no C++ name for a cam law");
      if (ops) ops->calls += 1;
      return it->second + "(p, " + Print(e.op(2), ops) + ", " + std::to_string(ex_to<GiNaC::numeric>(e.op(1)).to_int()) + ")";
    }
    if (name == "mtable") {
      const auto it = tables_.find(ex_to<GiNaC::numeric>(e.op(0)).to_int());
      if (it == tables_.end()) throw std::logic_error("mechgen bug: no C++ name for a table");
      if (ops) ops->calls += 1;
      return it->second + "(" + Print(e.op(2), ops) + ", " + std::to_string(ex_to<GiNaC::numeric>(e.op(1)).to_int()) + ")";
    }
    if (name == "camcontour") {
      const auto it = cam_contours_.find(ex_to<GiNaC::numeric>(e.op(0)).to_int());
      if (it == cam_contours_.end()) throw std::logic_error("mechgen bug: no C++ name for a cam contour");
      if (ops) ops->calls += 1;
      return it->second + "(p, " + Print(e.op(3), ops) + ", " + std::to_string(ex_to<GiNaC::numeric>(e.op(1)).to_int()) +
             ", " + std::to_string(ex_to<GiNaC::numeric>(e.op(2)).to_int()) + ")";
    }
    if (name == "stable_half") {  // -(B + sign(B) sq) / 2
      const std::string b = Print(e.op(0), ops), sq = Print(e.op(1), ops);
      if (ops) ops->adds += 1, ops->divs += 1;
      return "-(" + b + " + (" + b + " >= Scalar(0) ? " + sq + " : -" + sq + ")) / Scalar(2)";
    }
    if (name == "quadratic_root") {  // (A, B, C, qq, mode): qq / A or C / qq, by the mode's sign
      const std::string a = Print(e.op(0), ops), b = Print(e.op(1), ops), c = Print(e.op(2), ops),
                        qq = Print(e.op(3), ops), mode = Print(e.op(4), ops);
      if (ops) ops->divs += 1;
      return "((" + mode + " > Scalar(0)) == (" + b + " >= Scalar(0))) ? (" + qq + " != Scalar(0) ? " + c + " / " + qq +
             " : Scalar(0)) : " + qq + " / " + a;
    }
    // The expression language's piecewise functions (model/expression_functions.h): the
    // generated header's helpers ExprStep ... ExprMod (codegen/functions.cc).
    static const std::map<std::string, std::string> kPiecewise = {
        {"mstep", "ExprStep"}, {"msign", "ExprSign"}, {"mmin", "ExprMin"}, {"mmax", "ExprMax"}, {"mmod", "ExprMod"}};
    if (const auto it = kPiecewise.find(name); it != kPiecewise.end()) {
      std::string s = it->second + "(";
      for (size_t i = 0; i < e.nops(); ++i) s += (i ? ", " : "") + Print(e.op(i), ops);
      if (ops) ops->calls += 1;
      return s + ")";
    }
    if (name == "arctan") name = "atan";
    if (name == "arcsin") name = "asin";
    if (name == "arccos") name = "acos";
    static const char* kAllowed[] = {"sin", "cos", "tan", "atan", "asin", "acos",
                                     "atan2", "exp", "log", "abs", "sqrt"};
    bool ok = false;
    for (const char* a : kAllowed) ok |= name == a;
    if (!ok) throw std::runtime_error("function '" + name + "' cannot be emitted as C++");
    std::string s = name + "(";
    for (size_t i = 0; i < e.nops(); ++i) s += (i ? ", " : "") + Print(e.op(i), ops);
    if (ops) ops->calls += 1;
    return s + ")";
  }
  throw std::runtime_error("cannot emit expression of this kind as C++");
}

namespace {

class Cse {
 public:
  explicit Cse(CxxPrinter* printer) : printer_(*printer) {}

  void Count(const ex& e) {
    if (IsLeaf(e)) return;
    if (++count_[e] > 1) return;
    for (const ex& k : Children(e)) Count(k);
  }

  // The expression with repeated subexpressions replaced by temporaries; new
  // temporaries' definitions are appended to *lines.
  ex Reduce(const ex& e, std::vector<std::string>* lines, OpCounts* ops) {
    if (IsLeaf(e)) return e;
    auto it = memo_.find(e);
    if (it != memo_.end()) return it->second;
    std::vector<ex> kids = Children(e);
    std::sort(kids.begin(), kids.end(),
              [&](const ex& a, const ex& b) { return printer_.Key(a) < printer_.Key(b); });
    for (const ex& k : kids) Reduce(k, lines, ops);
    ex rebuilt;
    if (GiNaC::is_a<GiNaC::mul>(e) && Coefficient(e) != 1) {
      rebuilt = Coefficient(e) * Lookup(e / Coefficient(e));
    } else if (GiNaC::is_a<GiNaC::power>(e)) {
      ex base = Lookup(e.op(0));
      // x^n is printed as x*x*...: make a compound base a temporary first.
      if (IsIntegerPower(e) && !IsLeaf(base)) base = MakeTemp(e.op(0), base, lines, ops);
      rebuilt = GiNaC::pow(base, Lookup(e.op(1)));
    } else {
      rebuilt = e.map(lookup_);
    }
    // A negated or scaled symbol costs nothing to repeat: no temporary for it.
    const bool scaled_leaf = GiNaC::is_a<GiNaC::mul>(rebuilt) && rebuilt.nops() == 2 &&
                             IsLeaf(rebuilt.op(0)) && IsLeaf(rebuilt.op(1));
    if (count_[e] >= 2 && !scaled_leaf) return MakeTemp(e, rebuilt, lines, ops);
    memo_[e] = rebuilt;
    return rebuilt;
  }

  int num_temps() const { return next_; }

 private:
  struct LookupMap : GiNaC::map_function {
    explicit LookupMap(Cse* s) : self(s) {}
    Cse* self;
    ex operator()(const ex& e) override { return self->Lookup(e); }
  };

  ex Lookup(const ex& e) const {
    if (IsLeaf(e)) return e;
    return memo_.at(e);
  }

  ex MakeTemp(const ex& original, const ex& value, std::vector<std::string>* lines,
              OpCounts* ops) {
    const std::string name = "_tmp" + std::to_string(next_++);
    GiNaC::symbol tmp(name);
    lines->push_back("const Scalar " + name + " = " + printer_.Print(value, ops) + ";");
    printer_.Name(tmp, name);
    memo_[original] = tmp;
    return tmp;
  }

  CxxPrinter& printer_;
  std::map<ex, int, GiNaC::ex_is_less> count_;
  std::map<ex, ex, GiNaC::ex_is_less> memo_;
  int next_ = 0;
  LookupMap lookup_{this};
};

}  // namespace

Body EmitProgram(const Program& input, CxxPrinter* printer, const std::string& indent) {
  // Expanded sums of products are GiNaC's one canonical form that does not depend on
  // its run-dependent term order (an unexpanded sum inside a product gets its sign
  // normalized by whichever term GiNaC sees first), so every value is expanded first.
  Program program = input;
  auto has_value = [](const Statement& s) {
    return s.kind == Statement::Kind::kDefine || s.kind == Statement::Kind::kStore;
  };
  for (Statement& s : program)
    if (has_value(s)) s.value = s.value.expand();
  Cse cse(printer);
  for (const Statement& s : program) {
    if (s.kind == Statement::Kind::kDefine) printer->Name(s.symbol, s.target);
    for (const auto& [symbol, name] : s.names) printer->Name(symbol, name);
    if (has_value(s)) cse.Count(s.value);
  }

  Body body;
  std::vector<std::string> lines;
  // Stores are held back and flushed, grouped by guard, before the next raw line.
  std::vector<std::pair<std::string, std::string>> stores;  // guard, line
  auto flush = [&]() {
    std::vector<std::string> guards;
    for (const auto& [g, l] : stores)
      if (std::find(guards.begin(), guards.end(), g) == guards.end()) guards.push_back(g);
    for (const std::string& g : guards) {
      if (!g.empty()) lines.push_back("if (" + g + " != nullptr) {");
      for (const auto& [gg, l] : stores)
        if (gg == g) lines.push_back((g.empty() ? "" : "  ") + l);
      if (!g.empty()) lines.push_back("}");
    }
    stores.clear();
  };
  for (const Statement& s : program) {
    switch (s.kind) {
      case Statement::Kind::kRaw:
        flush();
        lines.push_back(s.target);
        break;
      case Statement::Kind::kDefine: {
        const ex v = cse.Reduce(s.value, &lines, &body.ops);
        lines.push_back("const Scalar " + s.target + " = " + printer->Print(v, &body.ops) + ";");
        break;
      }
      case Statement::Kind::kStore: {
        const ex v = cse.Reduce(s.value, &lines, &body.ops);
        stores.emplace_back(s.guard, s.target + " = " + printer->Print(v, &body.ops) + ";");
        break;
      }
      case Statement::Kind::kMatrix: {
        flush();
        const std::string type = "Mat<Scalar, " + std::to_string(s.rows) + ", " + std::to_string(s.cols) + ">";
        lines.push_back(type + " " + s.target + (s.zero ? " = " + type + "::Zero();" : ";"));
        break;
      }
      case Statement::Kind::kLuFactor:
        flush();
        lines.push_back("const Eigen::PartialPivLU<Mat<Scalar, " + std::to_string(s.rows) + ", " +
                        std::to_string(s.rows) + ">> " + s.target + "(" + s.args.at(0) + ");");
        break;
      case Statement::Kind::kLuSolve:
        flush();
        lines.push_back("const Mat<Scalar, " + std::to_string(s.rows) + ", " + std::to_string(s.cols) + "> " + s.target +
                        " = -" + s.args.at(0) + ".solve(" + s.args.at(1) + ");");
        break;
      case Statement::Kind::kLuDeterminant:
        flush();
        lines.push_back("const Scalar " + s.target + " = " + s.args.at(0) + ".partialPivLu().determinant();");
        break;
    }
  }
  flush();
  body.num_temps = cse.num_temps();
  for (const std::string& l : lines) body.text += (l.empty() ? "" : indent + l) + "\n";
  return body;
}

}  // namespace mechgen
