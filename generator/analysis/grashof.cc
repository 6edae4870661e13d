// Four-bar classification and input-range check. See grashof.h.
#include "analysis/grashof.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace mechgen {
namespace {

struct P2 {
  double x = 0, y = 0;
};

double Num(const GiNaC::ex& e, const GiNaC::exmap& defaults) {
  const GiNaC::ex v = e.subs(defaults).evalf();
  return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double() : NAN;
}

P2 Local(const Model& m, PointRef r, const GiNaC::exmap& d) {
  const LinkPoint& p = m.links[r.link].points[r.point];
  return {Num(p.x, d), Num(p.y, d)};
}

double Dist(P2 a, P2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// The point of joint j on link `link`.
PointRef End(const Joint& j, int link) { return j.End(link); }

std::string Deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f deg", rad * 180 / M_PI);
  return buf;
}

}  // namespace

std::string FourBarLoop::Text() const {
  std::ostringstream os;
  os << "loop " << loop + 1 << " (";
  for (int i = 0; i < 4; ++i) os << (i ? ", " : "") << links[i] << " " << lengths[i];
  os << "): s + l = " << s + l << (s + l < p + q - 1e-12 ? " < " : s + l > p + q + 1e-12 ? " > " : " = ")
     << "p + q = " << p + q << ", " << type;
  return os.str();
}

std::string FourBarLoop::MuText() const {
  if (!has_mu) return "";
  return "over input " + mu_input + "'s range: mu from " + Deg(mu_min) + " (at " + Deg(q_at_mu_min) + ") to " +
         Deg(mu_max) + " (at " + Deg(q_at_mu_max) + ")";
}

bool IsFourBarLoop(const Model& m, const Loop& loop) {
  if (loop.joints.size() != 4) return false;
  for (int j : loop.joints)
    if (m.joints[j].type() != JointType::kRevolute) return false;
  return true;
}

void CheckFourBarRange(const Model& m, const FourBarLoop& f) {
  // A zero-length link (for the ground: coincident pivots) leaves three links: the loop is a
  // rigid triangle or cannot close, and Grashof's classification means nothing.
  for (int i = 0; i < 4; ++i) {
    if (!(f.lengths[i] <= 1e-12 * std::max(1.0, f.l))) continue;
    SourceMark mark;
    for (const Link& l : m.links)
      if (l.name == f.links[i]) mark = l.mark;
    std::ostringstream loop;
    loop << "loop " << f.loop + 1 << " (";
    for (int k = 0; k < 4; ++k) loop << (k ? ", " : "") << f.links[k] << " " << f.lengths[k];
    m.Fail(mark, "link '" + f.links[i] + "' has zero length in " + loop.str() +
                     "): its two joints coincide at the parameters' defaults, so the loop is not a four-bar " +
                     "(a rigid triangle, or no loop at all); give the joints distinct points");
  }
  if (f.unreachable_input < 0) return;
  const Input& in = m.inputs[f.unreachable_input];
  m.Fail(in.mark, "input joint '" + m.joints[in.joint].name + "' is driven over [" + Deg(in.min) + ", " + Deg(in.max) +
                      "], but " + f.Text() + ": link '" + m.links[f.unreachable_link].name + "' cannot reach " +
                      Deg(f.unreachable_q) + " (the loop cannot close there); narrow the range or change the lengths");
}

std::vector<FourBarLoop> ClassifyFourBars(const Model& m, const Topology& t) {
  GiNaC::exmap defaults;
  for (const Parameter& p : m.params) defaults[p.symbol] = p.value;
  std::vector<FourBarLoop> out;
  for (size_t li = 0; li < t.loops.size(); ++li) {
    const Loop& loop = t.loops[li];
    if (!IsFourBarLoop(m, loop)) continue;
    FourBarLoop f;
    f.loop = static_cast<int>(li);
    // Link i of the loop lies between joints[i-1] and joints[i].
    int ground_pos = -1;
    for (int i = 0; i < 4; ++i) {
      const int link = loop.links[i];
      const Joint& before = m.joints[loop.joints[(i + 3) % 4]];
      const Joint& after = m.joints[loop.joints[i]];
      f.links[i] = m.links[link].name;
      f.lengths[i] = Dist(Local(m, End(before, link), defaults), Local(m, End(after, link), defaults));
      if (link == m.ground) ground_pos = i;
    }
    std::vector<double> sorted(f.lengths, f.lengths + 4);
    std::sort(sorted.begin(), sorted.end());
    f.s = sorted[0];
    f.l = sorted[3];
    f.p = sorted[1];
    f.q = sorted[2];
    const double scale = std::max(1.0, f.l);
    const double margin = (f.p + f.q) - (f.s + f.l);
    int shortest = 0;
    for (int i = 1; i < 4; ++i)
      if (f.lengths[i] < f.lengths[shortest]) shortest = i;
    if (f.s <= 1e-12 * scale) {  // CheckFourBarRange reports it
      f.type = "degenerate: link '" + f.links[shortest] + "' has zero length (its two joints coincide)";
    } else if (std::abs(margin) <= 1e-12 * scale) {
      f.type = "change point (Grashof-neutral: the loop can fold flat)";
    } else if (margin < 0) {
      f.type = "non-Grashof triple-rocker: no link turns fully";
    } else if (ground_pos < 0) {
      f.type = "Grashof, floating (no ground link in the loop)";
    } else if (shortest == ground_pos) {
      f.type = "Grashof double-crank (drag link)";
    } else if ((shortest + 2) % 4 == ground_pos) {
      f.type = "Grashof double-rocker (the coupler turns fully)";
    } else {
      f.type = "Grashof crank-rocker: '" + f.links[shortest] + "' can turn fully";
    }
    // The declared range of a driven link of this loop must stay within its reach.
    if (ground_pos < 0) {
      out.push_back(f);
      continue;
    }
    for (const Input& in : m.inputs) {
      if (in.kind != Input::Kind::kJoint) continue;  // a link's angle or a point's coordinate: not a crank's range
      const Joint& ij = m.joints[in.joint];
      if (ij.type() != JointType::kRevolute) continue;
      const int pos_in_loop = static_cast<int>(std::find(loop.joints.begin(), loop.joints.end(), in.joint) - loop.joints.begin());
      if (pos_in_loop >= 4) continue;
      // joints[i] joins links[i] and links[i + 1]; the ground is links[g].
      const int g = ground_pos;
      int driven_pos, far_joint_pos, other_pivot_pos;
      if (pos_in_loop == g) {  // ground -> links[g + 1]
        driven_pos = (g + 1) % 4;
        far_joint_pos = (g + 1) % 4;
        other_pivot_pos = (g + 3) % 4;
      } else if (pos_in_loop == (g + 3) % 4) {  // links[g - 1] -> ground
        driven_pos = (g + 3) % 4;
        far_joint_pos = (g + 2) % 4;
        other_pivot_pos = g;
      } else {
        continue;
      }
      const int driven = loop.links[driven_pos];
      const P2 pivot = Local(m, End(ij, m.ground), defaults);
      const P2 other_pivot = Local(m, End(m.joints[loop.joints[other_pivot_pos]], m.ground), defaults);
      const P2 crank_pin = Local(m, End(m.joints[loop.joints[far_joint_pos]], driven), defaults);
      const P2 crank_base = Local(m, End(ij, driven), defaults);
      const double rx = crank_pin.x - crank_base.x, ry = crank_pin.y - crank_base.y;
      // The two other links (coupler and rocker) reach |b - c| to b + c from the rocker's pivot.
      double b = -1, c = -1;
      for (int i = 0; i < 4; ++i) {
        if (i == g || i == driven_pos) continue;
        (b < 0 ? b : c) = f.lengths[i];
      }
      const int samples = 3600;
      const bool first_input = !f.has_mu;
      if (first_input) {
        f.has_mu = true;
        f.mu_input = ij.name;
        f.mu_min = INFINITY;
        f.mu_max = -INFINITY;
      }
      for (int k = 0; k <= samples; ++k) {
        const double qv = in.min + (in.max - in.min) * k / samples;
        const P2 pin{pivot.x + std::cos(qv) * rx - std::sin(qv) * ry, pivot.y + std::sin(qv) * rx + std::cos(qv) * ry};
        const double dd = Dist(pin, other_pivot);
        if (first_input && b > 0 && c > 0) {
          const double mu = std::acos(std::clamp((b * b + c * c - dd * dd) / (2 * b * c), -1.0, 1.0));
          if (mu < f.mu_min) f.mu_min = mu, f.q_at_mu_min = qv;
          if (mu > f.mu_max) f.mu_max = mu, f.q_at_mu_max = qv;
        }
        if (f.unreachable_input < 0 && (dd > b + c + 1e-12 * scale || dd < std::abs(b - c) - 1e-12 * scale)) {
          f.unreachable_input = static_cast<int>(&in - m.inputs.data());
          f.unreachable_link = driven;
          f.unreachable_q = qv;
        }
      }
      if (first_input && !(f.mu_min <= f.mu_max)) f.has_mu = false;  // a zero-length coupler or output
    }
    out.push_back(f);
  }
  return out;
}

}  // namespace mechgen
