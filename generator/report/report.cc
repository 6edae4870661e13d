// The model report. See report.h.
#include "report/report.h"

#include "joints/joint_kind.h"
#include "report/equivalent.h"

namespace mechgen {
namespace {

std::string Show(const GiNaC::ex& e, ReportFormat f) {
  std::ostringstream os;
  if (f == ReportFormat::kLatex)
    os << GiNaC::latex << e;
  else
    os << GiNaC::dflt << e;
  return os.str();
}

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

GiNaC::matrix Simplified(const GiNaC::matrix& a, const Kinematics& k) {
  GiNaC::matrix out(a.rows(), a.cols());
  for (unsigned i = 0; i < a.rows(); ++i)
    for (unsigned j = 0; j < a.cols(); ++j) out(i, j) = Simplified(a(i, j), k);
  return out;
}

}  // namespace

void WriteReport(const Model& m, const Topology& t, const std::vector<FourBarLoop>& four_bars,
                 const Kinematics& k, const SymbolicTable& d,
                 const std::vector<TransmissionAngle>& transmission, const EmittedModel& e, ReportFormat f, std::ostream& os) {
  const bool tex = f == ReportFormat::kLatex;
  const std::string eq_open = tex ? "\\[ " : "  ", eq_close = tex ? " \\]" : "";
  os << (tex ? "% " : "") << "mechgen report: " << m.name << " (" << m.file << ")\n";
  if (!m.title.empty()) os << (tex ? "% " : "") << m.title << "\n";
  os << (tex ? "% " : "") << "\n";
  if (!tex) {
    os << "Links (" << m.links.size() << "):\n";
    for (const Link& l : m.links) {
      os << "  " << l.name << (l.ground ? " (ground)" : "") << ":";
      for (const LinkPoint& p : l.points) os << " " << p.name << "=(" << p.x << ", " << p.y << ")";
      os << "\n";
    }
    os << "Joints (" << m.joints.size() << "):\n";
    for (const Joint& j : m.joints) {
      os << "  " << j.name << ": ";
      os << KindOf(j).Describe(m, j);
      os << "\n";
    }
    os << "Independent loops (" << t.loops.size() << "), closed by the cut joints of a spanning tree:\n";
    for (size_t i = 0; i < t.loops.size(); ++i) os << "  " << i + 1 << ": " << t.loops[i].Text(m) << "\n";
    os << "Mobility: Grübler–Kutzbach " << t.grubler_text << "; loop criterion " << t.loop_text << "; inputs "
       << m.inputs.size() << "\n";
    for (const FourBarLoop& f : four_bars) os << "Grashof: " << f.Text() << "\n";
    for (const std::string& c : k.cam_summary) os << "Cam: " << c << "\n";
    for (const CamContour& c : k.cam_contours) os << "Cam: " << c.summary << "\n";
    os << "Inputs and the loops they drive (through the solve order):\n";
    for (size_t i = 0; i < m.inputs.size(); ++i) {
      // Block b is driven by q_i if its rows contain q_i or an unknown of a driven block.
      os << "  q(" << i << ") " << k.q[i].name << " drives block(s)";
      std::vector<bool> driven_col(k.nphi(), false);
      for (size_t b = 0; b < d.blocks.size(); ++b) {
        bool uses = false;
        for (int r : d.blocks[b].rows) {
          uses |= !k.Phi_q(r, static_cast<int>(i)).is_zero();
          for (int c = 0; c < k.nphi(); ++c) uses |= driven_col[c] && !k.Phi_phi(r, c).is_zero();
        }
        if (!uses) continue;
        for (int c : d.blocks[b].cols) driven_col[c] = true;
        os << " " << b;
      }
      os << "\n";
    }
    os << "Solve order (block lower-triangular Phi_phi):\n";
    for (size_t b = 0; b < d.blocks.size(); ++b) os << "  block " << b << ": " << d.blocks[b].Describe(k) << "\n";
    os << "Coordinates:\n";
    for (int i = 0; i < k.nq(); ++i) os << "  q(" << i << ")   " << k.q[i].name << ": " << k.q[i].what << "\n";
    for (int i = 0; i < k.nphi(); ++i)
      os << "  phi(" << i << ") " << k.phi[i].name << ": " << k.phi[i].what << "\n";
    os << "Loop-closure equations Phi(q, phi) = 0:\n";
  }
  if (tex) os << "% Loop-closure equations\n";
  for (int i = 0; i < k.nc(); ++i)
    os << eq_open << (tex ? "\\Phi_{" : "Phi(") << i << (tex ? "} = " : ") = ") << Show(k.Phi[i], f)
       << (tex ? " = 0" : "") << eq_close << (tex ? "  % " : "   [") << k.Phi_source[i] << (tex ? "" : "]")
       << "\n";
  auto matrix = [&](const char* name, const GiNaC::matrix& a) {
    if (tex) {
      os << "\\[ " << name << " = \\begin{pmatrix}";
      for (unsigned i = 0; i < a.rows(); ++i) {
        for (unsigned j = 0; j < a.cols(); ++j) os << (j ? " & " : " ") << Show(a(i, j), f);
        os << (i + 1 < a.rows() ? " \\\\" : " ");
      }
      os << "\\end{pmatrix} \\]\n";
    } else {
      os << name << ":\n";
      for (unsigned i = 0; i < a.rows(); ++i)
        for (unsigned j = 0; j < a.cols(); ++j)
          os << "  (" << i << "," << j << ") " << Show(a(i, j), f) << "\n";
    }
  };
  matrix(tex ? "\\Phi_\\phi" : "Phi_phi = dPhi/dphi", k.Phi_phi);
  matrix(tex ? "\\Phi_q" : "Phi_q = dPhi/dq", k.Phi_q);
  if (k.nphi() <= kMaxSymbolicSolve) {
    if (!tex) os << "Velocity coefficients K = dphi/dq = -Phi_phi^-1 Phi_q (phid = K qd):\n";
    matrix(tex ? "K = -\\Phi_\\phi^{-1}\\Phi_q" : "K", Simplified(SymbolicK(k), k));
  } else if (!tex) {
    os << "K = -Phi_phi^-1 Phi_q is solved numerically (Phi_phi is " << k.nphi() << "x" << k.nphi() << ").\n";
  }
  // Singular configurations: det Phi_phi = 0, the product of the blocks' determinants
  // (up to the sign of the block permutation), each printed where it is small enough.
  if (!tex) os << "Singular configurations (dead points, change points; EvalDetPhiPhi): det Phi_phi = 0, where\n";
  else os << "% Singular configurations (EvalDetPhiPhi): det Phi_phi = 0\n";
  for (size_t b = 0; b < d.blocks.size(); ++b) {
    const Block& blk = d.blocks[b];
    const unsigned n = static_cast<unsigned>(blk.cols.size());
    std::string cols;
    for (int c : blk.cols) cols += (cols.empty() ? "" : ", ") + k.phi[c].name;
    // Up to 6 x 6 (Laplace: at most 720 products, fewer in a sparse block) the expression is
    // printed; the generated code evaluates blocks above kMaxSymbolicSolve by LU.
    constexpr unsigned kMaxPrinted = 6;
    if (n > kMaxPrinted) {
      os << (tex ? "% " : "  ") << "block " << b << " (" << cols << "): the determinant of its " << n << "x" << n
         << " Jacobian (evaluated by LU in the generated code; too large to print)\n";
      continue;
    }
    GiNaC::matrix J(n, n);
    for (unsigned r = 0; r < n; ++r)
      for (unsigned c = 0; c < n; ++c) J(r, c) = k.Phi_phi(blk.rows[r], blk.cols[c]);
    const GiNaC::ex det = Simplified(J.determinant(GiNaC::determinant_algo::laplace), k);
    if (tex)
      os << "\\[ \\det \\Phi_{\\phi}^{(" << b << ")} = " << Show(det, f) << " \\]  % block " << b << ": " << cols << "\n";
    else
      os << "  block " << b << " (" << cols << "): det = " << Show(det, f)
         << (GiNaC::is_a<GiNaC::numeric>(det) ? "  (constant: never singular)" : "") << "\n";
  }
  // Transmission angles of the four-bar loops.
  for (size_t i = 0; i < transmission.size(); ++i) {
    const TransmissionAngle& a = transmission[i];
    // |u|, |v| are the lengths of the coupler and the output link (constants): the
    // positive root of a square is its base (lengths are positive).
    auto length = [&](const GiNaC::ex& squared) {
      const GiNaC::ex e = Simplified(squared, k);
      if (GiNaC::is_a<GiNaC::power>(e) && e.op(1) == 2) return e.op(0);
      return GiNaC::sqrt(e);
    };
    const GiNaC::ex cos_mu = Simplified(a.dot, k) / (length(a.u2) * length(a.v2));
    std::string range;
    for (const FourBarLoop& fb : four_bars)
      if (fb.loop == a.loop && fb.has_mu) range = fb.MuText();
    if (tex) {
      os << "\\[ \\cos\\mu_{" << i << "} = " << Show(cos_mu, f) << " \\]  % transmission angle " << a.Text()
         << (range.empty() ? "" : "; " + range) << "\n";
    } else {
      os << "Transmission angle mu(" << i << ") " << a.Text() << " (EvalTransmissionAngles):\n"
         << "  cos mu = " << Show(cos_mu, f) << "\n";
      if (!range.empty()) os << "  " << range << "\n";
    }
  }
  WriteEquivalentLinks(m, tex, os);
  if (!tex) {
    os << "Generated code: " << d.strategy << "\n";
    os << "Operation counts: EvalPhi " << e.Ops("EvalPhi").Text() << "; EvalCoefficients "
       << e.Ops("EvalCoefficients").Text() << "; EvalScene " << e.Ops("EvalScene").Text() << "\n";
  }
}

}  // namespace mechgen
