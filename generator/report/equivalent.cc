// Dynamically and statically equivalent links. See equivalent.h.
#include "report/equivalent.h"

#include <cmath>
#include <cstdio>

namespace mechgen {
namespace {

double Value(const Model& m, const GiNaC::ex& e) {
  const GiNaC::ex v = e.subs(m.Defaults()).evalf();
  return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double() : NAN;
}

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::vector<EquivalentLink> EquivalentLinks(const Model& m) {
  std::vector<EquivalentLink> out;
  for (size_t l = 0; l < m.links.size(); ++l) {
    const Link& link = m.links[l];
    if (link.ground || !link.mass.given) continue;
    EquivalentLink e;
    e.link = link.name;
    e.m = Value(m, link.mass.mass);
    e.J = Value(m, link.mass.inertia);
    e.Gx = Value(m, link.mass.center_x);
    e.Gy = Value(m, link.mass.center_y);
    e.k2 = e.m > 0 ? e.J / e.m : 0;
    // The link's joint points (lower pairs), in the order of the joints.
    std::vector<int> points;
    for (const Joint& j : m.joints) {
      if (!j.IsLowerPair() || !j.Joins(static_cast<int>(l))) continue;
      const PointRef r = j.End(static_cast<int>(l));
      if (r.link != static_cast<int>(l) || r.point < 0) continue;
      bool seen = false;
      for (int p : points) seen |= p == r.point;
      if (!seen) points.push_back(r.point);
    }
    std::vector<double> px, py;
    for (int p : points) {
      px.push_back(Value(m, link.points[p].x));
      py.push_back(Value(m, link.points[p].y));
    }
    for (size_t i = 0; i < points.size(); ++i) {
      const double dx = e.Gx - px[i], dy = e.Gy - py[i], a = std::hypot(dx, dy);
      if (!(a > 0) || !(e.m > 0)) continue;  // A at G: no line AG
      EquivalentPoint q;
      q.through = link.name + "." + link.points[points[i]].name;
      q.a = a;
      q.b = e.k2 / a;
      q.Bx = e.Gx + dx / a * q.b;
      q.By = e.Gy + dy / a * q.b;
      q.m_A = e.m * q.b / (a + q.b);
      q.m_B = e.m * a / (a + q.b);
      e.dynamic.push_back(q);
    }
    if (points.size() >= 2 && e.m > 0) {
      e.P1 = link.name + "." + link.points[points[0]].name;
      e.P2 = link.name + "." + link.points[points[1]].name;
      const double ux = px[1] - px[0], uy = py[1] - py[0], L = std::hypot(ux, uy);
      const double d1 = std::hypot(e.Gx - px[0], e.Gy - py[0]), d2 = std::hypot(e.Gx - px[1], e.Gy - py[1]);
      const double off = L > 0 ? std::abs(ux * (e.Gy - py[0]) - uy * (e.Gx - px[0])) / L : 0;
      const double along = L > 0 ? (ux * (e.Gx - px[0]) + uy * (e.Gy - py[0])) / (L * L) : -1;
      if (L > 0 && off <= 1e-12 * L && along >= 0 && along <= 1) {
        e.has_static = true;
        e.m1 = e.m * d2 / (d1 + d2);
        e.m2 = e.m * d1 / (d1 + d2);
        e.J_static = e.m1 * d1 * d1 + e.m2 * d2 * d2;  // = m d1 d2
        e.J_error = e.J_static - e.J;
      } else {
        e.static_note = "the centre of mass is not on the segment " + e.P1 + " " + e.P2 +
                        ": no two-joint-point replacement";
      }
    }
    out.push_back(e);
  }
  return out;
}

void WriteEquivalentLinks(const Model& m, bool latex, std::ostream& os) {
  const std::vector<EquivalentLink> links = EquivalentLinks(m);
  if (links.empty()) return;
  const std::string c = latex ? "% " : "";
  os << c << "Dynamically equivalent links (Paul §6.3.1), at the parameters' defaults (G and B in the link's frame):\n";
  for (const EquivalentLink& e : links) {
    os << c << "  " << e.link << ": m = " << G(e.m) << ", J_G = " << G(e.J) << ", k^2 = J_G/m = " << G(e.k2)
       << ", G = (" << G(e.Gx) << ", " << G(e.Gy) << ")\n";
    for (const Link& l : m.links) {
      if (l.name != e.link || l.point_masses.empty()) continue;
      os << c << "    (m, J_G and G include its point masses";
      for (const PointMass& pm : l.point_masses) {
        os << (&pm == &l.point_masses.front() ? ": " : ", ") << pm.name << " m = " << G(Value(m, pm.mass)) << " at "
           << (pm.at.empty() ? "(" + G(Value(m, pm.x)) + ", " + G(Value(m, pm.y)) + ")" : l.name + "." + pm.at);
        const double J = Value(m, pm.inertia);
        if (J != 0) os << " with J = " << G(J);
      }
      os << ")\n";
    }
    for (const EquivalentPoint& q : e.dynamic)
      os << c << "    through " << q.through << " (a = " << G(q.a) << "): B on AG beyond G at b = k^2/a = " << G(q.b)
         << ", B = (" << G(q.Bx) << ", " << G(q.By) << "); m_A = m b/(a+b) = " << G(q.m_A)
         << ", m_B = m a/(a+b) = " << G(q.m_B) << "\n";
    if (e.has_static)
      os << c << "    statically equivalent at " << e.P1 << ", " << e.P2 << ": m = " << G(e.m1) << ", " << G(e.m2)
         << "; their J about G = " << G(e.J_static) << ", inertia error " << (e.J_error >= 0 ? "+" : "")
         << G(e.J_error) << (e.J > 0 ? " (" + G(100 * e.J_error / e.J) + "% of J_G)" : std::string()) << "\n";
    else if (!e.static_note.empty())
      os << c << "    " << e.static_note << "\n";
  }
}

}  // namespace mechgen
