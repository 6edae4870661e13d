// The model report. See report.h.
#include "report/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>

#include "joints/cam_profile.h"
#include "joints/joint_kind.h"
#include "report/equivalent.h"
#include "report/expr_printer.h"
#include "symbolic/linalg.h"
#include "symbolic/motion.h"

namespace mechgen {
namespace {

// For display: sin^2 t + cos^2 t = 1 for every angle coordinate, then one fraction.
// Factors sin(u - v) and cos(u - v) out of a polynomial in the sines and cosines of the
// angle coordinates, as Paul writes them (det Phi_phi of a four-bar = b c sin(theta3 - theta4)):
// with s_i = sin(theta_i), c_i = cos(theta_i) as plain symbols, exact polynomial division by
// s_u c_v - c_u s_v and c_u c_v + s_u s_v. Anything else is returned as it was.
GiNaC::ex ContractAngleDifferences(const GiNaC::ex& p, const Kinematics& k) {
  std::vector<GiNaC::symbol> theta, s, c;
  for (const auto* coords : {&k.q, &k.phi})
    for (const Coordinate& co : *coords)
      if (co.is_angle) {
        theta.push_back(co.symbol);
        s.emplace_back("s_" + co.name);
        c.emplace_back("c_" + co.name);
      }
  GiNaC::exmap to_poly, back;
  for (size_t i = 0; i < theta.size(); ++i) {
    to_poly[GiNaC::sin(theta[i])] = s[i];
    to_poly[GiNaC::cos(theta[i])] = c[i];
    back[s[i]] = GiNaC::sin(theta[i]);
    back[c[i]] = GiNaC::cos(theta[i]);
  }
  GiNaC::ex P = p.expand().subs(to_poly).expand();
  for (const GiNaC::symbol& t : theta)
    if (P.has(t)) return p;  // theta outside sin(theta) and cos(theta)
  GiNaC::ex factors = 1;
  for (bool found = true; found;) {
    found = false;
    for (size_t i = 0; i < theta.size() && !found; ++i)
      for (size_t j = i + 1; j < theta.size() && !found; ++j) {
        const std::pair<GiNaC::ex, GiNaC::ex> forms[] = {
            {s[i] * c[j] - c[i] * s[j], GiNaC::sin(theta[i] - theta[j])},
            {c[i] * c[j] + s[i] * s[j], GiNaC::cos(theta[i] - theta[j])}};
        for (const auto& [form, value] : forms) {
          GiNaC::ex quotient;
          bool divides = false;
          try {
            divides = !P.is_zero() && GiNaC::divide(P, form, quotient);
          } catch (const std::invalid_argument&) {  // not a polynomial over the rationals
            return p;
          }
          if (divides) {
            P = quotient.expand();
            factors *= value;
            found = true;
            break;
          }
        }
      }
  }
  return GiNaC::factor(P.subs(back)) * factors;
}

GiNaC::ex Simplified(const GiNaC::ex& e, const Kinematics& k) {
  GiNaC::exmap pythagoras;
  for (const auto* coords : {&k.q, &k.phi})
    for (const Coordinate& c : *coords)
      if (c.is_angle) pythagoras[GiNaC::pow(GiNaC::sin(c.symbol), 2)] = 1 - GiNaC::pow(GiNaC::cos(c.symbol), 2);
  const GiNaC::ex n = GiNaC::normal(e.expand().subs(pythagoras, GiNaC::subs_options::algebraic).expand());
  const GiNaC::ex nd = GiNaC::numer_denom(n);
  return ContractAngleDifferences(nd.op(0), k) / ContractAngleDifferences(nd.op(1), k);
}



std::string N(int i) { return std::to_string(i); }

// The shortest decimal that reads back as v.
std::string Exact(double v) {
  char buf[40];
  for (int prec = 1; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    const bool exponent = std::string(buf).find('e') != std::string::npos;
    if (std::strtod(buf, nullptr) == v && (!exponent || std::abs(v) < 1e-5 || std::abs(v) >= 1e16)) break;
  }
  return buf;
}

// Simplified where that stays small: a polynomial in sines and cosines (the usual case);
// anything with roots or other functions (a roller's offset, cam laws) as it is.
GiNaC::ex Tidy(const GiNaC::ex& e, const Kinematics& k) {
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (GiNaC::is_a<GiNaC::power>(*it) && !(GiNaC::is_a<GiNaC::numeric>(it->op(1)) &&
                                             GiNaC::ex_to<GiNaC::numeric>(it->op(1)).is_integer()))
      return e;
    if (GiNaC::is_a<GiNaC::function>(*it) && !is_ex_the_function(*it, GiNaC::sin) && !is_ex_the_function(*it, GiNaC::cos))
      return e;
  }
  return Simplified(e, k);
}

// A float written in the model (a literal like 1.5) as the exact rational of its shortest
// decimal: simplification and expansion then give the same result in any term order
// (float arithmetic in GiNaC's run-dependent order does not).
struct Rationalize : GiNaC::map_function {
  GiNaC::ex operator()(const GiNaC::ex& e) override {
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(e);
      if (n.is_rational() || !n.is_real()) return e;
      const double v = n.to_double();
      if (!std::isfinite(v)) return e;
      std::string text = Exact(v);
      GiNaC::numeric sign = 1;
      if (!text.empty() && text[0] == '-') {
        sign = -1;
        text = text.substr(1);
      }
      int exponent = 0;
      const size_t ep = text.find_first_of("eE");
      if (ep != std::string::npos) {
        exponent = std::atoi(text.c_str() + ep + 1);
        text = text.substr(0, ep);
      }
      const size_t dot = text.find('.');
      if (dot != std::string::npos) {
        exponent -= static_cast<int>(text.size() - dot - 1);
        text.erase(dot, 1);
      }
      const GiNaC::numeric digits(text.c_str());
      return sign * digits * GiNaC::pow(GiNaC::numeric(10), GiNaC::numeric(exponent));
    }
    return e.map(*this);
  }
};

GiNaC::ex Exactly(const GiNaC::ex& e) {
  Rationalize r;
  return r(e);
}

// The kinematics with exact numbers (see Rationalize).
Kinematics ExactKinematics(const Kinematics& kin) {
  Kinematics k = kin;
  for (GiNaC::ex& e : k.Phi) e = Exactly(e);
  for (unsigned i = 0; i < k.Phi_phi.rows(); ++i)
    for (unsigned j = 0; j < k.Phi_phi.cols(); ++j) k.Phi_phi(i, j) = Exactly(k.Phi_phi(i, j));
  for (unsigned i = 0; i < k.Phi_q.rows(); ++i)
    for (unsigned j = 0; j < k.Phi_q.cols(); ++j) k.Phi_q(i, j) = Exactly(k.Phi_q(i, j));
  for (Vec2& p : k.points)
    for (GiNaC::ex& e : p) e = Exactly(e);
  return k;
}

// Numbers for camlaw and camcontour at the parameters' defaults (the branch's det).
struct NumericCams : GiNaC::map_function {
  NumericCams(const Model& m, const Kinematics& k) : m(m), k(k) {}
  const Model& m;
  const Kinematics& k;
  bool failed = false;
  GiNaC::ex operator()(const GiNaC::ex& e) override {
    const bool law = is_ex_the_function(e, camlaw), contour = is_ex_the_function(e, camcontour);
    if (!law && !contour) return e.map(*this);
    const GiNaC::ex arg = e.op(law ? 2 : 3).map(*this).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(arg)) {
      failed = true;
      return e;
    }
    const double x = GiNaC::ex_to<GiNaC::numeric>(arg).to_double();
    const int index = GiNaC::ex_to<GiNaC::numeric>(e.op(0)).to_int();
    int joint = -1;
    for (size_t j = 0; j < m.joints.size(); ++j)
      if (m.joints[j].type() == JointType::kCam && m.joints[j].Data<CamData>().index == index) joint = static_cast<int>(j);
    if (law) {
      const int d = GiNaC::ex_to<GiNaC::numeric>(e.op(1)).to_int();
      for (const CamLaw& l : k.cam_laws)
        if (l.joint == joint) return EvalCamLaw(m, l, x, d);
    } else {
      const int c = GiNaC::ex_to<GiNaC::numeric>(e.op(1)).to_int(), d = GiNaC::ex_to<GiNaC::numeric>(e.op(2)).to_int();
      for (const CamContour& cc : k.cam_contours)
        if (cc.joint == joint) return EvalSpline(cc, c, d, x);
    }
    failed = true;
    return e;
  }
};

// sign(det Phi_phi) at the assembly guess with the parameters' defaults, the branch the
// runtime's Assembler requires (PositionSolver::AssembleFromGuess); 0 if it cannot be
// evaluated here (a table) or is zero.
int AssemblyBranch(const Model& m, const Kinematics& k) {
  GiNaC::exmap at = m.Defaults();
  for (int i = 0; i < k.nq(); ++i) at[k.q[i].symbol] = k.assembly_q[i];
  for (int i = 0; i < k.nphi(); ++i) at[k.phi[i].symbol] = k.assembly_phi[i];
  const int n = k.nphi();
  std::vector<double> a(static_cast<size_t>(n) * n);
  NumericCams cams(m, k);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const GiNaC::ex v = cams(k.Phi_phi(r, c).subs(at)).subs(at).evalf();
      if (cams.failed || !GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real()) return 0;
      a[r * n + c] = GiNaC::ex_to<GiNaC::numeric>(v).to_double();
    }
  // det by Gaussian elimination with partial pivoting.
  double det = 1, scale = 0;
  for (double v : a) scale = std::max(scale, std::abs(v));
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[piv * n + c])) piv = r;
    if (!(std::abs(a[piv * n + c]) > 1e-12 * scale)) return 0;
    if (piv != c) {
      for (int j = 0; j < n; ++j) std::swap(a[c * n + j], a[piv * n + j]);
      det = -det;
    }
    det *= a[c * n + c];
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      for (int j = c; j < n; ++j) a[r * n + j] -= f * a[c * n + j];
    }
  }
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

// Where the report writes: prose, headings, equations and matrices in either format.
class Writer {
 public:
  static constexpr size_t kLineWidth = 95;  ///< plain-text characters per LaTeX line (a rough page width)
  Writer(std::ostream& os, const ReportPrinter& pr) : os_(os), pr_(pr), tex_(pr.latex()) {}
  bool tex() const { return tex_; }
  std::string P(const GiNaC::ex& e) const { return pr_.Print(e); }

  void Heading(const std::string& title) {
    if (tex_)
      os_ << "\n\\subsection*{" << ReportPrinter::TexText(title) << "}\n";
    else
      os_ << title << ":\n";
  }
  /// A line of prose (indented in text).
  void Line(const std::string& text, int indent = 1) {
    if (tex_)
      os_ << "\\noindent " << std::string(indent > 1 ? "\\quad " : "") << ReportPrinter::TexText(text) << "\\par\n";
    else
      os_ << std::string(2 * indent, ' ') << text << "\n";
  }
  /// lhs = e, with a note: "  lhs = e   [note]" or "\[ lhs_tex = e \quad\text{(note)} \]".
  void Equation(const std::string& lhs, const std::string& lhs_tex, const GiNaC::ex& e, const std::string& note = "",
                const std::string& rhs_suffix_tex = "") {
    if (tex_) {
      const std::string tag = note.empty() ? "" : " \\qquad\\text{(" + ReportPrinter::TexText(note) + ")}";
      const std::vector<std::string> lines = pr_.PrintLines(e, kLineWidth);
      if (lines.size() == 1) {
        os_ << "\\[ " << (lhs_tex.empty() ? "" : lhs_tex + " = ") << lines[0] << rhs_suffix_tex << tag << " \\]\n";
      } else {
        // A long formula broken between the terms of its sum.
        os_ << "\\begin{multline*}\n" << (lhs_tex.empty() ? "" : lhs_tex + " = ");
        for (size_t i = 0; i < lines.size(); ++i) os_ << (i ? " \\\\\n  " : "") << lines[i];
        os_ << rhs_suffix_tex << tag << "\n\\end{multline*}\n";
      }
    } else {
      os_ << "  " << lhs << " = " << P(e);
      if (!note.empty()) os_ << "   [" << note << "]";
      os_ << "\n";
    }
  }
  void Matrix(const std::string& name, const std::string& name_tex, const GiNaC::matrix& a) {
    size_t widest = 0;
    for (unsigned i = 0; i < a.rows(); ++i)
      for (unsigned j = 0; j < a.cols(); ++j) widest = std::max(widest, pr_.Width(a(i, j)));
    if (tex_ && widest * a.cols() > kLineWidth) {  // too wide for a page: entry by entry
      for (unsigned i = 0; i < a.rows(); ++i)
        for (unsigned j = 0; j < a.cols(); ++j)
          if (!a(i, j).is_zero())
            Equation("", "\\left(" + name_tex + "\\right)_{" + std::to_string(i) + "," + std::to_string(j) + "}", a(i, j));
      if (a.rows() * a.cols() > 0) Line("(entries not shown are zero)", 0);
      return;
    }
    if (tex_) {
      os_ << "\\[ " << name_tex << " = \\begin{pmatrix}";
      for (unsigned i = 0; i < a.rows(); ++i) {
        for (unsigned j = 0; j < a.cols(); ++j) os_ << (j ? " & " : " ") << P(a(i, j));
        os_ << (i + 1 < a.rows() ? " \\\\" : " ");
      }
      os_ << "\\end{pmatrix} \\]\n";
    } else {
      os_ << name << ":\n";
      for (unsigned i = 0; i < a.rows(); ++i)
        for (unsigned j = 0; j < a.cols(); ++j) os_ << "  (" << i << "," << j << ") " << P(a(i, j)) << "\n";
    }
  }
  std::ostream& raw() { return os_; }

 private:
  std::ostream& os_;
  const ReportPrinter& pr_;
  bool tex_;
};

// K, L and the points' coefficients with the report's own symbols: K_i_j, L_i_j_k (the
// generated code's locals), block by block as symbolic/table.h derives them.
struct Coefficients {
  std::vector<std::vector<GiNaC::symbol>> K;  // nphi x nq
  std::vector<std::pair<int, int>> pairs;     // (j, k), j <= k
  std::vector<std::vector<GiNaC::symbol>> L;  // nphi x pairs
  const Kinematics& k;

  explicit Coefficients(const Kinematics& kin) : k(kin) {
    K.resize(k.nphi());
    for (int i = 0; i < k.nphi(); ++i)
      for (int j = 0; j < k.nq(); ++j) K[i].emplace_back("K_" + N(i) + "_" + N(j));
    for (int j = 0; j < k.nq(); ++j)
      for (int kk = j; kk < k.nq(); ++kk) pairs.emplace_back(j, kk);
    L.resize(k.nphi());
    for (int i = 0; i < k.nphi(); ++i)
      for (const auto& [j, kk] : pairs) L[i].emplace_back("L_" + N(i) + "_" + N(j) + "_" + N(kk));
  }
  void NameAll(ReportPrinter* pr) const {
    for (int i = 0; i < k.nphi(); ++i) {
      for (int j = 0; j < k.nq(); ++j) pr->Name(K[i][j], K[i][j].get_name(), "K_{" + N(i) + "," + N(j) + "}");
      for (size_t pj = 0; pj < pairs.size(); ++pj)
        pr->Name(L[i][pj], L[i][pj].get_name(),
                 "L_{" + N(i) + "," + N(pairs[pj].first) + N(pairs[pj].second) + "}");
    }
  }
  int Pair(int j, int kk) const {
    const int lo = std::min(j, kk), hi = std::max(j, kk);
    for (size_t p = 0; p < pairs.size(); ++p)
      if (pairs[p].first == lo && pairs[p].second == hi) return static_cast<int>(p);
    return -1;
  }
  // The derivative along the motion (symbolic/motion.h) in these symbols.
  Motion motion() const {
    return Motion(
        k, [this](int i, int j) -> GiNaC::ex { return K[i][j]; },
        [this](int i, int j, int kk) -> GiNaC::ex { return L[i][Pair(j, kk)]; });
  }
  GiNaC::ex Along(const GiNaC::ex& f, int j) const { return motion().Along(f, j); }
};

std::string ColsText(const Kinematics& k, const Block& b) {
  std::string s;
  for (int c : b.cols) s += (s.empty() ? "" : ", ") + std::string("phi(") + N(c) + ") " + k.phi[c].name;
  return s;
}
std::string RowsText(const Block& b) {
  std::string s;
  for (int r : b.rows) s += (s.empty() ? "" : " ") + N(r);
  return s;
}

// One block's system: its Jacobian J, det and inverse (adjugate / det, simplified).
struct BlockInverse {
  GiNaC::matrix J, adj, inv;  // inv = adj / det
  GiNaC::ex det;
};

BlockInverse InvertBlock(const Kinematics& k, const Block& b) {
  const unsigned n = static_cast<unsigned>(b.cols.size());
  BlockInverse out;
  out.J = GiNaC::matrix(n, n);
  for (unsigned r = 0; r < n; ++r)
    for (unsigned c = 0; c < n; ++c) out.J(r, c) = k.Phi_phi(b.rows[r], b.cols[c]);
  out.det = out.J.determinant(GiNaC::determinant_algo::laplace);
  out.adj = Adjugate(out.J);
  out.inv = GiNaC::matrix(n, n);
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = 0; j < n; ++j) out.inv(i, j) = out.adj(i, j) / out.det;
  return out;
}

}  // namespace

void WriteReport(const Model& m, const Topology& t, const std::vector<FourBarLoop>& four_bars,
                 const Kinematics& kinematics, const SymbolicTable& d,
                 const std::vector<TransmissionAngle>& transmission, const EmittedModel& e, ReportFormat f,
                 std::ostream& os) {
  const Kinematics k = ExactKinematics(kinematics);
  const bool tex = f != ReportFormat::kText;
  ReportPrinter printer(m, tex);
  Coefficients co(k);
  co.NameAll(&printer);
  Writer w(os, printer);
  auto esc = [](const std::string& s) { return ReportPrinter::TexText(s); };

  // ---- Title ----
  if (f == ReportFormat::kLatexDocument) {
    os << "% mechgen report --latex --standalone: compiles with pdflatex (Debian: texlive-latex-base)\n"
       << "\\documentclass[10pt]{article}\n"
       << "\\usepackage[T1]{fontenc}\n"
       << "\\usepackage{amsmath}\n"
       << "\\usepackage[a4paper,margin=15mm]{geometry}\n"
       << "\\allowdisplaybreaks\n"
       << "\\setlength{\\parskip}{2pt}\n"
       << "\\begin{document}\n"
       << "\\section*{mechgen report: " << esc(m.name) << "}\n";
    if (!m.title.empty()) os << "\\noindent " << esc(m.title) << "\\par\n";
    os << "\\noindent Model file: \\texttt{" << esc(m.file) << "}\\par\n";
  } else if (tex) {
    os << "% mechgen report: " << m.name << " (" << m.file << "); needs \\usepackage{amsmath}\n";
    if (!m.title.empty()) os << "% " << m.title << "\n";
  } else {
    os << "mechgen report: " << m.name << " (" << m.file << ")\n";
    if (!m.title.empty()) os << m.title << "\n";
    os << "\n";
  }

  // ---- Parameters, links, joints, loops, mobility ----
  w.Heading("Parameters (" + N(static_cast<int>(m.params.size())) + "), their defaults");
  for (const Parameter& p : m.params)
    w.Line(p.name + " = " + Exact(p.value) + (p.doc.empty() ? "" : "   (" + p.doc + ")"));
  w.Heading("Links (" + N(static_cast<int>(m.links.size())) + ")");
  for (const Link& l : m.links) {
    std::string s = l.name + (l.ground ? " (ground)" : "") + ":";
    for (const LinkPoint& p : l.points) s += " " + p.name + "=(" + printer.Print(p.x) + ", " + printer.Print(p.y) + ")";
    if (tex) {
      // Points as formulas.
      os << "\\noindent " << esc(l.name) << (l.ground ? " (ground)" : "") << ":";
      for (const LinkPoint& p : l.points)
        os << " " << esc(p.name) << " $= (" << printer.Print(p.x) << ", " << printer.Print(p.y) << ")$";
      os << "\\par\n";
    } else {
      w.Line(s);
    }
  }
  w.Heading("Joints (" + N(static_cast<int>(m.joints.size())) + ")");
  for (const Joint& j : m.joints) w.Line(j.name + ": " + KindOf(j).Describe(m, j));
  w.Heading("Independent loops (" + N(static_cast<int>(t.loops.size())) + "), closed by the cut joints of a spanning tree");
  for (size_t i = 0; i < t.loops.size(); ++i) w.Line(N(static_cast<int>(i) + 1) + ": " + t.loops[i].Text(m));
  if (!tex) {
    os << "Mobility: Grübler–Kutzbach " << t.grubler_text << "; loop criterion " << t.loop_text << "; inputs "
       << m.inputs.size() << "\n";
    for (const FourBarLoop& fb : four_bars) os << "Grashof: " << fb.Text() << "\n";
    for (const std::string& c : k.cam_summary) os << "Cam: " << c << "\n";
    for (const CamContour& c : k.cam_contours) os << "Cam: " << c.summary << "\n";
  } else {
    w.Heading("Mobility");
    w.Line("Grübler–Kutzbach " + t.grubler_text + "; loop criterion " + t.loop_text + "; inputs " +
           N(static_cast<int>(m.inputs.size())));
    for (const FourBarLoop& fb : four_bars) w.Line("Grashof: " + fb.Text());
    for (const std::string& c : k.cam_summary) w.Line("Cam: " + c);
    for (const CamContour& c : k.cam_contours) w.Line("Cam: " + c.summary);
  }
  // The cam laws as the equations name them.
  if (!k.cam_laws.empty()) {
    w.Heading("Cam laws in the equations (lift_<joint>(x): the follower's lift at cam angle x from the law's start, "
              "primes its x-derivatives; CamLaw_<joint> in the generated code)");
    for (const CamLaw& l : k.cam_laws) {
      std::string s = "lift_" + m.joints[l.joint].name + "(x), periodic in x over 2 pi:";
      for (size_t i = 0; i < l.what.size(); ++i)
        s += std::string(i ? ";" : "") + " from x = " + printer.Print(l.begin[i]) + ": " + l.what[i];
      w.Line(s);
    }
  }
  if (!k.cam_contours.empty())
    w.Line("contourx_<joint>(u), contoury_<joint>(u): the cam's spline contour at parameter u (Contour_<joint> in the "
           "generated code), primes its u-derivatives",
           0);

  // ---- Inputs, solve order, coordinates ----
  w.Heading("Inputs and the loops they drive (through the solve order)");
  for (size_t i = 0; i < m.inputs.size(); ++i) {
    std::string s = "q(" + N(static_cast<int>(i)) + ") " + k.q[i].name + " drives block(s)";
    std::vector<bool> driven_col(k.nphi(), false);
    for (size_t b = 0; b < d.blocks.size(); ++b) {
      bool uses = false;
      for (int r : d.blocks[b].rows) {
        uses |= !k.Phi_q(r, static_cast<int>(i)).is_zero();
        for (int c = 0; c < k.nphi(); ++c) uses |= driven_col[c] && !k.Phi_phi(r, c).is_zero();
      }
      if (!uses) continue;
      for (int c : d.blocks[b].cols) driven_col[c] = true;
      s += " " + N(static_cast<int>(b));
    }
    w.Line(s);
  }
  w.Heading("Solve order (block lower-triangular Phi_phi)");
  for (size_t b = 0; b < d.blocks.size(); ++b) w.Line("block " + N(static_cast<int>(b)) + ": " + d.blocks[b].Describe(k));
  // Modes and branch: the same assembly named two ways.
  {
    std::string modes;
    for (size_t b = 0; b < d.blocks.size(); ++b) {
      const BlockSolve s = d.blocks[b].solve;
      if (s == BlockSolve::kRR || s == BlockSolve::kRS || s == BlockSolve::kAngle)
        modes += (modes.empty() ? "" : ", ") + std::string("block ") + N(static_cast<int>(b)) + " mode " +
                 N(d.blocks[b].default_mode);
    }
    const int branch = AssemblyBranch(m, k);
    std::string s = "Assembly: ";
    s += modes.empty() ? "no block has two closed-form solutions (no modes)" : modes + " (Model::kDefaultModes)";
    if (branch != 0)
      s += "; at the assembly guess sign(det Phi_phi) = " + std::string(branch > 0 ? "+1" : "-1") +
           ", what the sweep and PositionSolver print as 'branch " + (branch > 0 ? "+1" : "-1") +
           "': the same assembly" + (modes.empty() ? "" : " (a mode is one block's root, the branch the sign of det Phi_phi over all blocks)");
    w.Line(s, 0);
    // Named assembly modes (`assembly_modes`): each one's modes, as Model::kNamedModes holds them.
    for (size_t i = 0; i < m.assembly_modes.size(); ++i) {
      std::string line = "Assembly mode '" + m.assembly_modes[i].name + "' (Model::kNamedModes[" +
                         N(static_cast<int>(i)) + "]): ";
      for (size_t b = 0; b < d.blocks.size(); ++b)
        line += (b ? ", " : "") + std::string("block ") + N(static_cast<int>(b)) + " mode " +
                N(d.blocks[b].named_modes[i]);
      w.Line(line, 0);
    }
  }
  w.Heading("Coordinates (q: inputs, with their default sweep range; phi: unknowns)");
  for (int i = 0; i < k.nq(); ++i) {
    const bool angle = k.q[i].is_angle;
    const double scale = angle ? 180 / M_PI : 1;
    auto shown = [&](double v) {  // degrees to 10 digits (a conversion, not the model's number)
      if (!angle) return Exact(v);
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.10g", v * scale);
      return std::string(std::strcmp(buf, "-0") == 0 ? "0" : buf);
    };
    w.Line("q(" + N(i) + ")   " + k.q[i].name + ": " + k.q[i].what + "; range [" + shown(k.q_min[i]) + ", " +
           shown(k.q_max[i]) + "]" + (angle ? " deg" : ""));
  }
  for (int i = 0; i < k.nphi(); ++i) w.Line("phi(" + N(i) + ") " + k.phi[i].name + ": " + k.phi[i].what);

  // ---- Phi, Phi_phi, Phi_q ----
  w.Heading("Loop-closure equations Phi(q, phi) = 0");
  for (int i = 0; i < k.nc(); ++i)
    w.Equation("Phi(" + N(i) + ")", "\\Phi_{" + N(i) + "}", k.Phi[i], k.Phi_source[i], " = 0");
  w.Matrix("Phi_phi = dPhi/dphi", "\\Phi_\\phi", k.Phi_phi);
  w.Matrix("Phi_q = dPhi/dq", "\\Phi_q", k.Phi_q);

  // ---- K and L block by block ----
  const int nq = k.nq();
  constexpr size_t kInlineDet = 40;  // plain-text characters
  std::vector<BlockInverse> inverses;
  for (const Block& b : d.blocks) inverses.push_back(InvertBlock(k, b));
  // Per block: numerator -> numerator / det, simplified (det inlined or named, see below).
  std::vector<std::function<GiNaC::ex(const GiNaC::ex&)>> fractions(d.blocks.size());
  if (d.requested.K) {
    w.Heading("Velocity coefficients K = dphi/dq (phid = K qd), block by block as the generated code computes them");
    w.Line("Block b solves Phi_phi(rows, cols) K(cols, :) = -(Phi_q(rows, :) + Phi_phi(rows, earlier cols) K(earlier cols, :)), "
           "i.e. K(cols, :) = -Phi_phi(rows, cols)^-1 (...), the inverse as adjugate / det (fractions below). "
           "K_i_j is K(i, j) = d phi(i)/d q(j); a later block's formula uses the earlier blocks' K_i_j as they are.",
           0);
    for (size_t bi = 0; bi < d.blocks.size(); ++bi) {
      const Block& b = d.blocks[bi];
      const BlockInverse& inv = inverses[bi];
      const unsigned n = static_cast<unsigned>(b.cols.size());
      const std::string bn = N(static_cast<int>(bi));
      w.Line("Block " + bn + ": rows " + RowsText(b) + " of Phi -> " + ColsText(k, b) +
                 (static_cast<int>(n) > kMaxSymbolicSolve
                      ? " (the generated code solves this block's systems by a fixed-size LU; the closed form here is the same solution)"
                      : ""),
             0);
      const GiNaC::ex det = Simplified(inv.det, k);
      w.Equation("det_block" + bn, "\\det \\Phi_\\phi^{(" + bn + ")}", det);
      // A long determinant is written once, above, and named below (det_block<b>, as in
      // the generated code); a short one is inlined and cancels where it can.
      const bool named = printer.Width(det) > kInlineDet;
      GiNaC::ex over = 1 / inv.det;
      if (named) {
        const GiNaC::symbol det_symbol("det_block" + bn);
        printer.Name(det_symbol, "det_block" + bn, "\\det \\Phi_\\phi^{(" + bn + ")}");
        over = 1 / GiNaC::ex(det_symbol);
      }
      auto fraction = [named, over, &k](const GiNaC::ex& numerator) {
        return named ? Simplified(numerator, k) * over : Simplified(numerator * over, k);
      };
      fractions[bi] = fraction;
      GiNaC::matrix invs(n, n);
      for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) invs(i, j) = fraction(inv.adj(i, j));
      w.Matrix("  Phi_phi(rows " + RowsText(b) + ", cols)^-1 (row i: cols[i], column j: rows[j])",
               "\\left(\\Phi_\\phi^{(" + bn + ")}\\right)^{-1}", invs);
      for (unsigned i = 0; i < n; ++i)
        for (int j = 0; j < nq; ++j) {
          GiNaC::ex sum = 0;
          for (unsigned r = 0; r < n; ++r) {
            GiNaC::ex rhs = k.Phi_q(b.rows[r], j);
            for (size_t pb = 0; pb < bi; ++pb)
              for (int c : d.blocks[pb].cols) rhs += k.Phi_phi(b.rows[r], c) * co.K[c][j];
            sum += inv.adj(i, r) * rhs;
          }
          const int c = b.cols[i];
          w.Equation(co.K[c][j].get_name(), "K_{" + N(c) + "," + N(j) + "}", fraction(-sum),
                     "d " + k.phi[c].name + " / d " + k.q[j].name);
        }
    }
  }
  if (d.requested.L) {
    w.Heading("Centripetal coefficients L (phidd = K qdd + sum_jk L(:, j, k) qd_j qd_k), block by block");
    w.Line("Block b solves Phi_phi(rows, cols) L(cols, j, k) = -L_rhs(rows, j, k), the right-hand side "
           "L_rhs_r_j_k = gamma_r(j, k) + Phi_phi(r, earlier cols) L(earlier cols, j, k) named first as in the "
           "generated code; gamma_r(j, k) is the second derivative of Phi(r) along the motion, "
           "sum_ab d2Phi_r/dx_a dx_b V_aj V_bk with x = (q, phi), V = [I; K] (in K_i_j). "
           "L_i_j_k is L(i, j, k) = d K(i, j) / d q(k), j <= k (symmetric).",
           0);
    for (size_t bi = 0; bi < d.blocks.size(); ++bi) {
      const Block& b = d.blocks[bi];
      const BlockInverse& inv = inverses[bi];
      const unsigned n = static_cast<unsigned>(b.cols.size());
      w.Line("Block " + N(static_cast<int>(bi)) + ": rows " + RowsText(b) + " of Phi -> " + ColsText(k, b), 0);
      for (size_t pj = 0; pj < co.pairs.size(); ++pj) {
        const auto [j, kk] = co.pairs[pj];
        const std::string jk = N(j) + "_" + N(kk);
        std::vector<GiNaC::ex> rhs_symbol;
        for (unsigned r = 0; r < n; ++r) {
          GiNaC::ex rhs = co.Along(co.Along(k.Phi[b.rows[r]], j), kk);
          for (size_t pb = 0; pb < bi; ++pb)
            for (int c : d.blocks[pb].cols) rhs += k.Phi_phi(b.rows[r], c) * co.L[c][pj];
          const std::string name = "L_rhs_" + N(b.rows[r]) + "_" + jk;
          const GiNaC::symbol sym(name);
          printer.Name(sym, name, "\\gamma_{" + N(b.rows[r]) + "," + N(j) + N(kk) + "}" +
                                      (bi > 0 ? "^{+}" : ""));
          rhs_symbol.push_back(sym);
          w.Equation(name, "\\gamma_{" + N(b.rows[r]) + "," + N(j) + N(kk) + "}" + (bi > 0 ? "^{+}" : ""),
                     Tidy(rhs, k));
        }
        for (unsigned i = 0; i < n; ++i) {
          GiNaC::ex sum = 0;
          for (unsigned r = 0; r < n; ++r) sum += inv.adj(i, r) * rhs_symbol[r];
          const int c = b.cols[i];
          w.Equation(co.L[c][pj].get_name(), "L_{" + N(c) + "," + N(j) + N(kk) + "}", fractions[bi](-sum),
                     "d2 " + k.phi[c].name + " / d " + k.q[j].name + " d " + k.q[kk].name);
        }
      }
    }
  }

  // ---- Design sensitivities dphi/dp (the design section) ----
  if (m.design.any()) {
    w.Heading("Design sensitivities dphi/dp (EvalDesignDerivatives), block by block with the same inverses as K");
    w.Line("Block b solves Phi_phi(rows, cols) dphi(cols)/dp = -(dPhi(rows)/dp + Phi_phi(rows, earlier cols) "
           "dphi(earlier cols)/dp), q held: the design parameters as further inputs. dphi_i_p is d phi(i) / d p. "
           "dK/dp, dL/dp and the points' derivatives follow by the same forward substitution (see the generated code).",
           0);
    std::vector<std::vector<GiNaC::ex>> dphi(k.nphi(), std::vector<GiNaC::ex>(m.design.params.size()));
    for (int i = 0; i < k.nphi(); ++i)
      for (size_t dd = 0; dd < m.design.params.size(); ++dd) {
        const std::string name = "dphi_" + N(i) + "_" + m.params[m.design.params[dd]].name;
        const GiNaC::symbol sym(name);
        printer.Name(sym, name, "\\partial\\phi_{" + N(i) + "}/\\partial " + m.params[m.design.params[dd]].name);
        dphi[i][dd] = sym;
      }
    for (size_t bi = 0; bi < d.blocks.size(); ++bi) {
      const Block& b = d.blocks[bi];
      const BlockInverse& inv = inverses[bi];
      const unsigned n = static_cast<unsigned>(b.cols.size());
      w.Line("Block " + N(static_cast<int>(bi)) + ": rows " + RowsText(b) + " of Phi -> " + ColsText(k, b), 0);
      for (size_t dd = 0; dd < m.design.params.size(); ++dd) {
        const Parameter& par = m.params[m.design.params[dd]];
        for (unsigned i = 0; i < n; ++i) {
          GiNaC::ex sum = 0;
          for (unsigned r = 0; r < n; ++r) {
            GiNaC::ex rhs = k.Phi[b.rows[r]].diff(par.symbol);
            for (size_t pb = 0; pb < bi; ++pb)
              for (int c : d.blocks[pb].cols) rhs += k.Phi_phi(b.rows[r], c) * dphi[c][dd];
            sum += inv.adj(i, r) * rhs;
          }
          const int c = b.cols[i];
          w.Equation(GiNaC::ex_to<GiNaC::symbol>(dphi[c][dd]).get_name(),
                     "\\partial\\phi_{" + N(c) + "}/\\partial " + par.name, fractions[bi] ? fractions[bi](-sum)
                                                                                        : Simplified(-sum / inv.det, k),
                     "d " + k.phi[c].name + " / d " + par.name);
        }
      }
    }
  }

  // ---- Points ----
  if (!k.points.empty()) {
    w.Heading("Requested points: r_P, K_P = d r_P/dq, L_P (rdd_P = K_P qdd + sum_jk L_P(:, j, k) qd_j qd_k)");
    for (size_t pt = 0; pt < k.points.size(); ++pt) {
      const std::string name = k.point_names[pt], pn = N(static_cast<int>(pt));
      w.Line("Point " + pn + ": " + name, 0);
      for (int a = 0; a < 2; ++a) {
        const std::string xy = a == 0 ? "x" : "y";
        const GiNaC::ex r = k.points[pt][a];
        w.Equation("r_" + pn + "_" + xy, "r_{" + pn + "," + xy + "}", r.expand());
        if (!d.requested.K) continue;
        std::vector<GiNaC::ex> KP;
        for (int j = 0; j < nq; ++j) {
          KP.push_back(co.Along(r, j).expand());
          w.Equation("K_P" + pn + "_" + xy + "_" + N(j), "K_{P" + pn + "," + xy + "," + N(j) + "}", KP[j]);
        }
        if (!d.requested.L) continue;
        for (const auto& [j, kk] : co.pairs) {
          GiNaC::ex l = co.Along(KP[j], kk);
          for (int i = 0; i < k.nphi(); ++i) l += r.diff(k.phi[i].symbol) * co.L[i][co.Pair(j, kk)];
          w.Equation("L_P" + pn + "_" + xy + "_" + N(j) + "_" + N(kk),
                     "L_{P" + pn + "," + xy + "," + N(j) + N(kk) + "}", l.expand());
        }
      }
    }
  }

  // ---- Singular configurations ----
  w.Heading("Singular configurations (dead points, change points; EvalDetPhiPhi): det Phi_phi = 0, the product of the blocks' determinants, where");
  for (size_t b = 0; b < d.blocks.size(); ++b) {
    const Block& blk = d.blocks[b];
    const unsigned n = static_cast<unsigned>(blk.cols.size());
    std::string cols;
    for (int c : blk.cols) cols += (cols.empty() ? "" : ", ") + k.phi[c].name;
    constexpr unsigned kMaxPrinted = 6;
    if (n > kMaxPrinted) {
      w.Line("block " + N(static_cast<int>(b)) + " (" + cols + "): the determinant of its " + N(static_cast<int>(n)) + "x" +
             N(static_cast<int>(n)) + " Jacobian (evaluated by LU in the generated code; too large to print)");
      continue;
    }
    const GiNaC::ex det = Simplified(inverses[b].det, k);
    const bool constant = GiNaC::is_a<GiNaC::numeric>(det);
    if (tex)
      w.Equation("", "\\det \\Phi_{\\phi}^{(" + N(static_cast<int>(b)) + ")}", det,
                 "block " + N(static_cast<int>(b)) + ": " + cols + (constant ? "; constant: never singular" : ""));
    else
      os << "  block " << b << " (" << cols << "): det = " << printer.Print(det)
         << (constant ? "  (constant: never singular)" : "") << "\n";
  }

  // ---- Transmission angles ----
  for (size_t i = 0; i < transmission.size(); ++i) {
    const TransmissionAngle& a = transmission[i];
    auto length = [&](const GiNaC::ex& squared) {
      const GiNaC::ex sq = Simplified(squared, k);
      if (GiNaC::is_a<GiNaC::power>(sq) && sq.op(1) == 2) return sq.op(0);
      return GiNaC::sqrt(sq);
    };
    const GiNaC::ex cos_mu = Simplified(Exactly(a.dot), k) / (length(Exactly(a.u2)) * length(Exactly(a.v2)));
    std::string range;
    for (const FourBarLoop& fb : four_bars)
      if (fb.loop == a.loop && fb.has_mu) range = fb.MuText();
    if (tex) {
      w.Heading("Transmission angle mu(" + N(static_cast<int>(i)) + ")");
      w.Line(a.Text() + (range.empty() ? "" : "; " + range), 0);
      w.Equation("", "\\cos\\mu_{" + N(static_cast<int>(i)) + "}", cos_mu);
    } else {
      os << "Transmission angle mu(" << i << ") " << a.Text() << " (EvalTransmissionAngles):\n"
         << "  cos mu = " << printer.Print(cos_mu) << "\n";
      if (!range.empty()) os << "  " << range << "\n";
    }
  }
  if (tex) {
    std::ostringstream eq;
    WriteEquivalentLinks(m, false, eq);
    std::istringstream lines(eq.str());
    bool first = true;
    for (std::string line; std::getline(lines, line);) {
      if (first) {
        w.Heading(line.substr(0, line.size() - (line.back() == ':' ? 1 : 0)));
        first = false;
      } else {
        const size_t lead = line.find_first_not_of(' ');
        w.Line(line.substr(lead == std::string::npos ? 0 : lead), lead != std::string::npos && lead > 2 ? 2 : 1);
      }
    }
  } else {
    WriteEquivalentLinks(m, false, os);
  }
  if (!tex) {
    os << "Generated code: " << d.strategy << "\n";
    os << "Operation counts: EvalPhi " << e.Ops("EvalPhi").Text() << "; EvalCoefficients "
       << e.Ops("EvalCoefficients").Text() << "; EvalScene " << e.Ops("EvalScene").Text() << "\n";
  } else {
    w.Heading("Generated code");
    w.Line(d.strategy, 0);
  }
  if (f == ReportFormat::kLatexDocument) os << "\\end{document}\n";
}

}  // namespace mechgen
