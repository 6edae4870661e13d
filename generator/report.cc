// The model report. See report.h.
#include "report.h"

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
GiNaC::matrix Simplified(const GiNaC::matrix& a, const Kinematics& k) {
  GiNaC::exmap pythagoras;
  for (const auto* coords : {&k.q, &k.phi})
    for (const Coordinate& c : *coords)
      if (c.is_angle) pythagoras[GiNaC::pow(GiNaC::sin(c.symbol), 2)] = 1 - GiNaC::pow(GiNaC::cos(c.symbol), 2);
  GiNaC::matrix out(a.rows(), a.cols());
  for (unsigned i = 0; i < a.rows(); ++i)
    for (unsigned j = 0; j < a.cols(); ++j)
      out(i, j) = GiNaC::factor(GiNaC::normal(a(i, j).expand().subs(pythagoras, GiNaC::subs_options::algebraic).expand()));
  return out;
}

}  // namespace

void WriteReport(const Model& m, const Topology& t, const std::vector<FourBarLoop>& four_bars,
                 const Kinematics& k, const Derivation& d,
                 const EmittedModel& e, ReportFormat f, std::ostream& os) {
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
      switch (j.type) {
        case JointType::kRevolute: os << "revolute " << m.PointName(j.a) << " = " << m.PointName(j.b); break;
        case JointType::kPrismatic: os << "prismatic " << m.PointName(j.a) << " guides " << m.PointName(j.b); break;
        case JointType::kRoll:
          os << "rolling, wheel " << m.PointName(j.b) << " radius " << j.radius << " on the "
             << (j.on_line ? "line through " : j.internal ? "inside of the circle about " : "circle about ")
             << m.PointName(j.a);
          if (!j.on_line) os << " radius " << j.radius2;
          break;
        case JointType::kGear:
          os << (j.internal ? "internal" : "external") << " gear pair " << m.links[j.a.link].name << " (r " << j.radius
             << ") / " << m.links[j.b.link].name << " (r " << j.radius2 << "), carrier " << m.links[j.carrier].name;
          break;
        case JointType::kRack:
          os << "rack and pinion, pinion " << m.links[j.a.link].name << " (r " << j.radius << "), rack "
             << m.links[j.b.link].name << " on '" << m.joints[j.other_joint].name << "'";
          break;
        case JointType::kCam:
          os << "cam " << m.links[j.a.link].name << ", follower " << m.links[j.b.link].name << " on '"
             << m.joints[j.other_joint].name << "'";
          break;
      }
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
  if (!tex) {
    os << "Generated code: " << d.strategy << "\n";
    os << "Operation counts: EvalPhi " << e.phi_ops.Text() << "; EvalCoefficients "
       << e.coefficient_ops.Text() << "; EvalScene " << e.scene_ops.Text() << "\n";
  }
}

}  // namespace mechgen
