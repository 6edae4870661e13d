// The report's deterministic printer. See expr_printer.h.
#include "report/expr_printer.h"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "joints/cam_profile.h"

namespace mechgen {

// The canonical tree (see the header).
struct Node {
  enum Kind { kNum, kSym, kAdd, kMul, kPow, kFunc } kind = kNum;
  GiNaC::numeric num;          // kNum: the value; kMul: the coefficient
  std::string text, tex;       // kSym: the names; kFunc: the function's names
  std::vector<Node> ops;       // kAdd: terms; kMul: factors (no numbers); kPow: base, exponent; kFunc: arguments
  std::string key;             // the text, for sorting
};

struct ReportPrinterImpl {
  const ReportPrinter& p;

  static Node Num(const GiNaC::numeric& n) {
    Node x;
    x.kind = Node::kNum;
    x.num = n;
    return x;
  }
  static bool IsNegative(const Node& n) {
    if (n.kind == Node::kNum) return n.num.is_real() && n.num < 0;
    if (n.kind == Node::kMul) return n.num.is_real() && n.num < 0;
    if (n.kind == Node::kAdd) return !n.ops.empty() && IsNegative(n.ops[0]);
    return false;
  }
  static std::string Lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }
  static int Rank(const Node& n) {
    switch (n.kind) {
      case Node::kNum: return 0;
      case Node::kSym: return 1;
      case Node::kPow: return Rank(n.ops[0]) == 1 ? 1 : Rank(n.ops[0]) + 1;
      case Node::kFunc: return 3;
      case Node::kMul: return 4;
      case Node::kAdd: return 5;
    }
    return 6;
  }

  // ---- building the canonical tree ----
  Node Negate(const Node& n) const {
    if (n.kind == Node::kNum) return Num(-n.num);
    if (n.kind == Node::kMul) {
      Node m = n;
      m.num = -n.num;
      return Finish(m);
    }
    if (n.kind == Node::kAdd) {
      Node a;
      a.kind = Node::kAdd;
      for (const Node& t : n.ops) a.ops.push_back(Negate(t));
      return MakeAdd(a.ops);
    }
    Node m;
    m.kind = Node::kMul;
    m.num = -1;
    m.ops = {n};
    return Finish(m);
  }

  Node Finish(Node n) const {
    n.key = Text(n);
    return n;
  }

  Node MakeAdd(const std::vector<Node>& terms) const {
    std::vector<Node> flat;
    GiNaC::numeric constant = 0;
    for (const Node& t : terms) {
      if (t.kind == Node::kAdd) {
        for (const Node& u : t.ops) {
          if (u.kind == Node::kNum) constant += u.num;
          else flat.push_back(u);
        }
      } else if (t.kind == Node::kNum) {
        constant += t.num;
      } else {
        flat.push_back(t);
      }
    }
    // Sorted by the term without its coefficient, then by the coefficient.
    auto monomial = [this](const Node& t) {
      if (t.kind != Node::kMul) return t.key;
      Node m = t;
      m.num = 1;
      return Text(m);
    };
    std::vector<std::pair<std::string, Node>> keyed;
    for (const Node& t : flat) keyed.emplace_back(monomial(t) + "\x01" + t.key, t);
    std::stable_sort(keyed.begin(), keyed.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    Node a;
    a.kind = Node::kAdd;
    for (auto& k : keyed) a.ops.push_back(k.second);
    if (!constant.is_zero()) a.ops.push_back(Num(constant));
    if (a.ops.empty()) return Num(0);
    if (a.ops.size() == 1) return a.ops[0];
    return Finish(a);
  }

  Node MakeMul(const std::vector<Node>& factors, GiNaC::numeric coeff) const {
    std::vector<Node> flat;
    for (const Node& f : factors) {
      if (f.kind == Node::kNum) {
        coeff *= f.num;
      } else if (f.kind == Node::kMul) {
        coeff *= f.num;
        flat.insert(flat.end(), f.ops.begin(), f.ops.end());
      } else if (f.kind == Node::kAdd && IsNegative(f)) {
        coeff = -coeff;
        flat.push_back(Negate(f));
      } else {
        flat.push_back(f);
      }
    }
    if (coeff.is_zero()) return Num(0);
    std::stable_sort(flat.begin(), flat.end(), [](const Node& a, const Node& b) {
      const int ra = Rank(a), rb = Rank(b);
      if (ra != rb) return ra < rb;
      const std::string la = Lower(a.key), lb = Lower(b.key);
      return la != lb ? la < lb : a.key < b.key;
    });
    if (flat.empty()) return Num(coeff);
    if (flat.size() == 1 && coeff == 1) return flat[0];
    Node m;
    m.kind = Node::kMul;
    m.num = coeff;
    m.ops = flat;
    return Finish(m);
  }

  Node MakePow(const Node& base, const Node& exponent) const {
    Node b = base;
    GiNaC::numeric sign = 1;
    if (b.kind == Node::kAdd && IsNegative(b) && exponent.kind == Node::kNum && exponent.num.is_integer()) {
      b = Negate(b);
      if (exponent.num.is_odd()) sign = -1;
    }
    Node pw;
    pw.kind = Node::kPow;
    pw.ops = {b, exponent};
    pw = Finish(pw);
    return sign == 1 ? pw : MakeMul({pw}, sign);
  }

  Node MakeFunc(const std::string& text, const std::string& tex, std::vector<Node> args, int parity) const {
    // parity: 1 odd, 2 even, 0 neither (about the first argument).
    bool flip = false;
    if (parity != 0 && args.size() == 1 && IsNegative(args[0])) {
      args[0] = Negate(args[0]);
      flip = parity == 1;
    }
    Node f;
    f.kind = Node::kFunc;
    f.text = text;
    f.tex = tex;
    f.ops = std::move(args);
    f = Finish(f);
    return flip ? MakeMul({f}, -1) : f;
  }

  static std::string Primes(int d) { return std::string(static_cast<size_t>(std::max(0, d)), '\''); }

  Node Build(const GiNaC::ex& e) const {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return Num(GiNaC::ex_to<GiNaC::numeric>(e));
    if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::constant>(e)) {
      Node s;
      s.kind = Node::kSym;
      const auto it = p.names_.find(e);
      if (it != p.names_.end()) {
        s.text = it->second.first;
        s.tex = it->second.second;
      } else if (GiNaC::is_a<GiNaC::constant>(e)) {
        s.text = "Pi";
        s.tex = "\\pi";
        if (!(e == GiNaC::Pi)) {
          std::ostringstream os;
          os << e;
          s.text = s.tex = os.str();
        }
      } else {
        s.text = GiNaC::ex_to<GiNaC::symbol>(e).get_name();
        s.tex = ReportPrinter::TexName(s.text);
      }
      return Finish(s);
    }
    if (GiNaC::is_a<GiNaC::add>(e)) {
      std::vector<Node> terms;
      for (size_t i = 0; i < e.nops(); ++i) terms.push_back(Build(e.op(i)));
      return MakeAdd(terms);
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {
      std::vector<Node> factors;
      for (size_t i = 0; i < e.nops(); ++i) factors.push_back(Build(e.op(i)));
      return MakeMul(factors, 1);
    }
    if (GiNaC::is_a<GiNaC::power>(e)) return MakePow(Build(e.op(0)), Build(e.op(1)));
    if (GiNaC::is_a<GiNaC::function>(e)) {
      const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
      auto small_int = [&](size_t i) {
        return GiNaC::is_a<GiNaC::numeric>(e.op(i)) ? GiNaC::ex_to<GiNaC::numeric>(e.op(i)).to_int() : -1;
      };
      // Cam laws, contours and tables: by name, their derivative order as primes.
      if (name == "camlaw" || name == "mtable") {
        const auto& names = name == "camlaw" ? p.cam_laws_ : p.tables_;
        const auto it = names.find(small_int(0));
        const std::string who = it != names.end() ? it->second : std::to_string(small_int(0));
        const int d = small_int(1);
        if (name == "camlaw")
          return MakeFunc("lift_" + who + Primes(d), "\\mathrm{lift}_{" + ReportPrinter::TexName(who) + "}" + Primes(d),
                          {Build(e.op(2))}, 0);
        return MakeFunc(who + Primes(d), ReportPrinter::TexName(who) + Primes(d), {Build(e.op(2))}, 0);
      }
      if (name == "camcontour") {
        const auto it = p.cam_contours_.find(small_int(0));
        const std::string who = it != p.cam_contours_.end() ? it->second : std::to_string(small_int(0));
        const std::string xy = small_int(1) == 0 ? "x" : "y";
        const int d = small_int(2);
        return MakeFunc("contour" + xy + "_" + who + Primes(d),
                        "\\mathrm{contour}_{" + xy + "," + ReportPrinter::TexName(who) + "}" + Primes(d),
                        {Build(e.op(3))}, 0);
      }
      // The expression language's piecewise functions by their names in the model
      // (model/expression_functions.h).
      static const std::map<std::string, std::string> piecewise = {
          {"mstep", "step"}, {"msign", "sign"}, {"mmin", "min"}, {"mmax", "max"}, {"mmod", "mod"}};
      if (const auto it = piecewise.find(name); it != piecewise.end()) {
        std::vector<Node> args;
        for (size_t i = 0; i < e.nops(); ++i) args.push_back(Build(e.op(i)));
        const std::string tex = it->second == "min" || it->second == "max" ? "\\" + it->second
                                                                          : "\\operatorname{" + it->second + "}";
        return MakeFunc(it->second, tex, args, 0);
      }
      static const std::set<std::string> odd = {"sin", "tan", "asin", "atan", "sinh", "tanh"};
      static const std::set<std::string> even = {"cos", "abs", "cosh"};
      static const std::set<std::string> known = {"sin", "cos", "tan", "asin", "acos", "atan",
                                                  "sinh", "cosh", "tanh", "exp", "log"};
      std::vector<Node> args;
      for (size_t i = 0; i < e.nops(); ++i) args.push_back(Build(e.op(i)));
      static const std::map<std::string, std::string> arc = {{"asin", "\\arcsin"}, {"acos", "\\arccos"},
                                                             {"atan", "\\arctan"}};
      const std::string tex = arc.count(name)     ? arc.at(name)
                              : known.count(name) ? "\\" + name
                              : name == "abs"     ? "\\operatorname{abs}"
                              : name == "atan2"   ? "\\operatorname{atan2}"
                                                  : "\\operatorname{" + ReportPrinter::TexText(name) + "}";
      return MakeFunc(name, tex, args, odd.count(name) ? 1 : even.count(name) ? 2 : 0);
    }
    // Anything else (not expected in the report's expressions): GiNaC's own text.
    std::ostringstream os;
    os << GiNaC::dflt << e;
    Node s;
    s.kind = Node::kSym;
    s.text = os.str();
    std::ostringstream ts;
    ts << GiNaC::latex << e;
    s.tex = ts.str();
    return Finish(s);
  }

  // ---- printing ----
  // Both formats share the structure; `tex` picks the spelling. A product's or a number's
  // sign is printed by the caller (sums) or in front.
  // A rational whose denominator is 2^a 5^b with b >= 1 (a decimal the model wrote, see
  // report.cc's Rationalize) as that decimal; other fractions as fractions.
  static std::string Decimal(const GiNaC::numeric& n) {
    GiNaC::numeric den = n.denom();
    int twos = 0, fives = 0;
    while (GiNaC::mod(den, 2).is_zero()) {
      den = den / 2;
      ++twos;
    }
    while (GiNaC::mod(den, 5).is_zero()) {
      den = den / 5;
      ++fives;
    }
    if (den != 1 || fives == 0) return "";
    const int places = std::max(twos, fives);
    const GiNaC::numeric scaled = GiNaC::abs(n) * GiNaC::pow(GiNaC::numeric(10), GiNaC::numeric(places));
    std::ostringstream digits;
    digits << scaled;  // an integer
    std::string d = digits.str();
    if (static_cast<int>(d.size()) <= places) d = std::string(static_cast<size_t>(places) - d.size() + 1, '0') + d;
    return (n < 0 ? "-" : "") + d.substr(0, d.size() - places) + "." + d.substr(d.size() - places);
  }

  static std::string NumText(const GiNaC::numeric& n, bool tex) {
    std::ostringstream os;
    if (n.is_rational() && !n.is_integer()) {
      const std::string decimal = Decimal(n);
      if (!decimal.empty()) return decimal;
      if (tex)
        os << "\\frac{" << n.numer() << "}{" << n.denom() << "}";
      else
        os << n.numer() << "/" << n.denom();
      return os.str();
    }
    os << GiNaC::dflt << GiNaC::ex(n);
    return os.str();
  }

  // Magnitude of a term (its sign stripped) for use in a sum or in front of a minus sign.
  std::string Abs(const Node& n, bool tex) const {
    if (n.kind == Node::kNum) return NumText(GiNaC::abs(n.num), tex);
    if (n.kind == Node::kMul) {
      Node m = n;
      m.num = GiNaC::abs(n.num);
      return Unsigned(m, tex);
    }
    return Unsigned(n, tex);
  }

  std::string Wrap(const std::string& s, bool tex) const {
    return tex ? "\\left(" + s + "\\right)" : "(" + s + ")";
  }

  // An operand of a product or a power's base: parenthesized unless it binds tighter.
  std::string Factor(const Node& n, bool tex, bool as_base) const {
    const bool atom = n.kind == Node::kSym || n.kind == Node::kFunc ||
                      (n.kind == Node::kNum && n.num.is_integer() && n.num >= 0) ||
                      (n.kind == Node::kPow && !as_base && !IsSqrt(n));
    if (n.kind == Node::kPow && IsSqrt(n)) return Unsigned(n, tex);
    return atom ? Unsigned(n, tex) : Wrap(Signed(n, tex), tex);
  }

  static bool IsSqrt(const Node& n) {
    return n.kind == Node::kPow && n.ops[1].kind == Node::kNum && n.ops[1].num == GiNaC::numeric(1, 2);
  }

  std::string Signed(const Node& n, bool tex) const { return (IsNegative(n) && n.kind != Node::kAdd ? "-" : "") + (n.kind == Node::kAdd ? Unsigned(n, tex) : Abs(n, tex)); }

  std::string Unsigned(const Node& n, bool tex) const {
    switch (n.kind) {
      case Node::kNum:
        return NumText(n.num, tex);
      case Node::kSym:
        return tex ? n.tex : n.text;
      case Node::kFunc: {
        std::string args;
        for (size_t i = 0; i < n.ops.size(); ++i) args += (i ? (tex ? ", " : ",") : "") + Signed(n.ops[i], tex);
        return (tex ? n.tex : n.text) + Wrap(args, tex);
      }
      case Node::kPow: {
        const Node& b = n.ops[0];
        const Node& x = n.ops[1];
        if (IsSqrt(n)) return tex ? "\\sqrt{" + Signed(b, tex) + "}" : "sqrt(" + Signed(b, tex) + ")";
        if (x.kind == Node::kNum && x.num.is_real() && x.num < 0) {  // 1/b^-x
          Node m;
          m.kind = Node::kMul;
          m.num = 1;
          m.ops = {n};
          return Unsigned(m, tex);
        }
        const bool plain_exp = x.kind == Node::kNum && x.num.is_integer() && x.num >= 0;
        if (tex) return Factor(b, tex, true) + "^{" + Signed(x, tex) + "}";
        return Factor(b, tex, true) + "^" + (plain_exp ? Unsigned(x, tex) : Wrap(Signed(x, tex), tex));
      }
      case Node::kAdd: {
        std::string s;
        for (size_t i = 0; i < n.ops.size(); ++i) {
          const bool neg = IsNegative(n.ops[i]);
          if (i == 0)
            s += neg ? "-" : "";
          else
            s += tex ? (neg ? " - " : " + ") : (neg ? "-" : "+");
          s += Abs(n.ops[i], tex);
        }
        return s;
      }
      case Node::kMul: {
        // Coefficient |num| = a / b (caller prints the sign); negative integer powers go below.
        std::vector<std::string> top, bottom;
        const GiNaC::numeric c = n.num;
        if (c.is_rational() && !c.is_integer() && !Decimal(c).empty()) {
          top.push_back(Decimal(c));
        } else if (c.is_rational()) {
          if (c.numer() != 1) top.push_back(NumText(c.numer(), tex));
          if (c.denom() != 1) bottom.push_back(NumText(c.denom(), tex));
        } else if (c != 1) {
          top.push_back(Factor(Num(c), tex, false));
        }
        for (const Node& f : n.ops) {
          if (f.kind == Node::kPow && f.ops[1].kind == Node::kNum && f.ops[1].num.is_real() && f.ops[1].num < 0) {
            const GiNaC::numeric e = -f.ops[1].num;
            if (e == 1) {
              bottom.push_back(Factor(f.ops[0], tex, false));
            } else {
              Node inv = MakePow(f.ops[0], Num(e));
              bottom.push_back(Factor(inv, tex, false));
            }
          } else {
            top.push_back(Factor(f, tex, false));
          }
        }
        const std::string sep = tex ? " " : "*";
        auto join = [&](const std::vector<std::string>& v) {
          std::string s;
          for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
          return s.empty() ? std::string("1") : s;
        };
        if (bottom.empty()) return join(top);
        if (tex) {
          // A \frac's numerator needs no parentheses around a lone sum.
          std::vector<const Node*> tops;
          for (const Node& f : n.ops)
            if (!(f.kind == Node::kPow && f.ops[1].kind == Node::kNum && f.ops[1].num.is_real() && f.ops[1].num < 0))
              tops.push_back(&f);
          if (top.size() == 1 && tops.size() == 1 && tops[0]->kind == Node::kAdd)
            return "\\frac{" + Signed(*tops[0], tex) + "}{" + join(bottom) + "}";
          return "\\frac{" + join(top) + "}{" + join(bottom) + "}";
        }
        return join(top) + "/" + (bottom.size() > 1 ? "(" + join(bottom) + ")" : join(bottom));
      }
    }
    return "";
  }

  std::string Text(const Node& n) const { return Signed(n, false); }
};

ReportPrinter::ReportPrinter(const Model& m, bool latex) : latex_(latex) {
  for (const Joint& j : m.joints)
    if (j.type() == JointType::kCam) {
      const CamData& c = j.Data<CamData>();
      if (c.contour == CamData::Contour::kNone)
        cam_laws_[c.index] = j.name;
      else
        cam_contours_[c.index] = j.name;
    }
  for (size_t i = 0; i < m.tables.size(); ++i) tables_[static_cast<int>(i)] = m.tables[i].name;
}

void ReportPrinter::Name(const GiNaC::ex& s, const std::string& text, const std::string& tex) {
  names_[s] = {text, tex};
}

std::string ReportPrinter::Print(const GiNaC::ex& e) const {
  ReportPrinterImpl impl{*this};
  const Node n = impl.Build(e);
  return impl.Signed(n, latex_);
}

size_t ReportPrinter::Width(const GiNaC::ex& e) const {
  ReportPrinterImpl impl{*this};
  return impl.Build(e).key.size();
}

std::vector<std::string> ReportPrinter::PrintLines(const GiNaC::ex& e, size_t width) const {
  ReportPrinterImpl impl{*this};
  const Node n = impl.Build(e);
  const std::string whole = impl.Signed(n, latex_);
  if (n.key.size() <= width) return {whole};
  // The sum to break, and what goes before and after it.
  const Node* sum = nullptr;
  std::string before, after;
  if (n.kind == Node::kAdd) {
    sum = &n;
  } else if (n.kind == Node::kMul) {
    // c * (sum) * rest / den: the sum broken, the rest as a fraction in front.
    int sums = 0;
    for (const Node& f : n.ops) sums += f.kind == Node::kAdd;
    for (const Node& f : n.ops)
      if (f.kind == Node::kAdd && sums == 1) sum = &f;
    if (sum != nullptr) {
      Node rest = n;
      rest.ops.clear();
      for (const Node& f : n.ops)
        if (&f != sum) rest.ops.push_back(f);
      const bool negative = ReportPrinterImpl::IsNegative(rest);
      rest.num = GiNaC::abs(rest.num);
      const std::string r = rest.ops.empty() ? impl.NumText(rest.num, latex_) : impl.Unsigned(rest, latex_);
      before = std::string(negative ? "-" : "") + (r == "1" ? "" : r + " ") + (latex_ ? "\\Bigl(" : "(");
      after = latex_ ? "\\Bigr)" : ")";
    }
  }
  if (sum == nullptr || sum->kind != Node::kAdd) return {whole};
  std::vector<std::string> lines;
  std::string line = before;
  size_t used = before.empty() ? 0 : n.key.size() - sum->key.size();
  for (size_t i = 0; i < sum->ops.size(); ++i) {
    const Node& t = sum->ops[i];
    const bool neg = ReportPrinterImpl::IsNegative(t);
    const std::string term = impl.Abs(t, latex_);
    if (used > 0 && used + t.key.size() > width) {
      lines.push_back(line);
      line.clear();
      used = 0;
    }
    line += (i == 0 ? (neg ? "-" : "") : (neg ? " - " : " + ")) + term;
    used += t.key.size() + 3;
  }
  lines.push_back(line + after);
  return lines;
}

std::string ReportPrinter::TexText(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    switch (ch) {
      case '_': out += "\\_"; break;
      case '%': out += "\\%"; break;
      case '&': out += "\\&"; break;
      case '#': out += "\\#"; break;
      case '$': out += "\\$"; break;
      case '{': out += "\\{"; break;
      case '}': out += "\\}"; break;
      case '~': out += "\\textasciitilde{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '\\': out += "\\textbackslash{}"; break;
      case '<': out += "\\textless{}"; break;
      case '>': out += "\\textgreater{}"; break;
      case '|': out += "\\textbar{}"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string ReportPrinter::TexName(const std::string& name) {
  static const std::set<std::string> greek = {
      "alpha", "beta",  "gamma",   "delta", "epsilon", "zeta",  "eta",   "theta", "iota",  "kappa",
      "lambda", "mu",   "nu",      "xi",    "pi",      "rho",   "sigma", "tau",   "upsilon", "phi",
      "chi",   "psi",   "omega",   "Gamma", "Delta",   "Theta", "Lambda", "Xi",   "Pi",    "Sigma",
      "Upsilon", "Phi", "Psi",     "Omega", "varphi",  "vartheta", "varepsilon"};
  const size_t us = name.find('_');
  const std::string base = name.substr(0, us);
  const std::string rest = us == std::string::npos ? "" : name.substr(us + 1);
  const bool is_greek = greek.count(base) > 0;
  const bool one_letter = base.size() == 1 && std::isalpha(static_cast<unsigned char>(base[0]));
  if (!is_greek && !one_letter) return "\\mathrm{" + TexText(name) + "}";
  const std::string b = is_greek ? "\\" + base : base;
  if (us == std::string::npos) return b;
  return b + "_{\\mathrm{" + TexText(rest) + "}}";
}

}  // namespace mechgen
