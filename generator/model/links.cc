// The `links` section: each link's points in its own frame; one link is the ground
// (LinkKeys). A link's point masses (PointMassKeys) are combined here with its own mass into
// the one rigid body every analysis reads (Link::mass).
#include <optional>
#include <set>

#include "model/reader.h"

namespace mechgen {

const KeyTable& PointMassKeys() {
  static const KeyTable table{"point mass",
                              {{"at", "a point of the link (its name) or [x, y] in the link's frame", true},
                               {"mass", "the point mass (expression, >= 0)", true},
                               {"inertia", "its own moment of inertia about its point (default 0)", false}}};
  return table;
}

namespace {

// The link's point masses (`point_masses: {NAME: {at: P | [x, y], mass: m, inertia: J}}`),
// read once the link's points are known.
std::vector<PointMass> ReadPointMasses(SectionReader& r, const Link& l, const YAML::Node& node) {
  Model& m = r.model();
  if (l.ground)
    m.Fail(r.KeyMark(node), "the ground link '" + l.name +
                                "' cannot carry point masses (it does not move); remove point_masses:");
  std::vector<PointMass> out;
  for (const auto& [name, spec] : r.Entries(node, "point_masses of link '" + l.name + "'")) {
    PointMass pm;
    pm.name = name;
    pm.mark = r.KeyMark(spec);
    CheckName(m, name, NameRole::kPoint, pm.mark);
    const std::string what = "point mass '" + name + "' of link '" + l.name + "'";
    if (!spec.IsMap()) r.Fail(spec, what + " must be a mapping: {at: <point of '" + l.name + "'> or [x, y], mass: m}");
    for (const auto& [key, value] : r.Entries(spec, what, &PointMassKeys())) {
      if (key == "at") {
        if (value.IsSequence()) {
          if (value.size() != 2) r.Fail(value, what + ": at: [x, y] must have two coordinates in the link's frame");
          pm.x = r.Expression(value[0], "x of " + what);
          pm.y = r.Expression(value[1], "y of " + what);
          r.Number(value[0], "x of " + what);
          r.Number(value[1], "y of " + what);
          continue;
        }
        std::string points;
        for (const LinkPoint& p : l.points) points += (points.empty() ? "" : ", ") + p.name;
        if (!value.IsScalar())
          r.Fail(value,
                 what + ": at: must name a point of '" + l.name + "' (" + points + ") or give [x, y] in its frame");
        pm.at = r.Scalar(value, what + ": at");
        if (pm.at.find('.') != std::string::npos)
          r.Fail(value, what + ": at: '" + pm.at + "' names no point of '" + l.name +
                            "'; write the point's name alone (a point mass sits on the link it is listed under: " +
                            points + ") or give [x, y] in the link's frame");
        const int k = l.FindPoint(pm.at);
        if (k < 0)
          r.Fail(value, what + ": link '" + l.name + "' has no point '" + pm.at + "'; its points are: " + points +
                            " (or give [x, y] in the link's frame)");
        pm.x = l.points[k].x;
        pm.y = l.points[k].y;
      } else if (key == "mass") {
        pm.mass = r.Expression(value, "mass of " + what);
        if (r.Number(value, "mass of " + what) < 0)
          r.Fail(value, "mass of " + what + " is negative at the parameters' defaults; give a mass >= 0");
      } else {
        pm.inertia = r.Expression(value, "moment of inertia of " + what);
        if (r.Number(value, "moment of inertia of " + what) < 0)
          r.Fail(value, "moment of inertia of " + what + " is negative; give J >= 0 about the point mass");
      }
    }
    const YAML::Node& cspec = spec;  // const lookups never insert keys
    if (!cspec["at"])
      r.Fail(spec, what + " needs at: <a point of '" + l.name + "'> or [x, y] in its frame; add it");
    if (!cspec["mass"]) r.Fail(spec, what + " needs mass: m; add it");
    out.push_back(pm);
  }
  return out;
}

// The link's own mass (if given) and its point masses as one rigid body: total mass
// M = sum m_k, centre G = sum m_k r_k / M, and the moment of inertia about G by the
// parallel-axis theorem, J_G = sum J_k + sum m_k |r_k - G|^2, written as
// sum J_k + (1/M) sum_{k<l} m_k m_l |r_k - r_l|^2 (the same by Lagrange's identity; a sum of
// non-negative terms, no difference of large ones). One body alone (a point mass on a
// massless link) is that body, with no division.
MassProperties CombinedBody(SectionReader& r, const Link& l, const YAML::Node& node) {
  using GiNaC::ex;
  struct Body {
    ex m, x, y, J;
  };
  std::vector<Body> bodies;
  if (l.mass.given) bodies.push_back({l.mass.mass, l.mass.center_x, l.mass.center_y, l.mass.inertia});
  for (const PointMass& pm : l.point_masses) bodies.push_back({pm.mass, pm.x, pm.y, pm.inertia});
  MassProperties out;
  out.given = true;
  out.mark = l.mass.given ? l.mass.mark : r.KeyMark(node);
  if (bodies.size() == 1) {
    out.mass = bodies[0].m;
    out.center_x = bodies[0].x;
    out.center_y = bodies[0].y;
    out.inertia = bodies[0].J;
    return out;
  }
  ex M = 0, Sx = 0, Sy = 0, J = 0, pairs = 0;
  for (size_t k = 0; k < bodies.size(); ++k) {
    M += bodies[k].m;
    Sx += bodies[k].m * bodies[k].x;
    Sy += bodies[k].m * bodies[k].y;
    J += bodies[k].J;
    for (size_t i = k + 1; i < bodies.size(); ++i)
      pairs += bodies[k].m * bodies[i].m *
               (GiNaC::pow(bodies[k].x - bodies[i].x, 2) + GiNaC::pow(bodies[k].y - bodies[i].y, 2));
  }
  if (!(ValueAtDefaults(r.model(), M, out.mark, "the total mass of link '" + l.name + "'") > 0))
    r.model().Fail(r.KeyMark(node), "link '" + l.name + "' with its point masses has a total mass of 0 at the "
                                    "parameters' defaults, so its centre of mass is undefined; give one of them a "
                                    "positive mass (or remove the massless ones)");
  out.mass = M;
  out.center_x = Sx / M;
  out.center_y = Sy / M;
  out.inertia = J + pairs / M;
  return out;
}

}  // namespace

const KeyTable& LinkKeys() {
  static const KeyTable table{"link",
                              {{"ground", "true for the fixed frame (exactly one link; default false)", false},
                               {"points", "{NAME: [x, y]}: the link's points in its frame (expressions)", true},
                               {"mass", "the link's mass (expression; default: massless)", false},
                               {"center", "[x, y]: its centre of mass in the link's frame (default [0, 0]; needs mass)", false},
                               {"inertia", "its moment of inertia about the centre of mass (default 0; needs mass)", false},
                               {"point_masses", "{NAME: {at: P or [x, y], mass: m, inertia: J}}: masses at its points",
                                false}}};
  return table;
}

void ReadLinks(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) m.Fail({1, 1}, "the model has no 'links'; add a links: section with a ground link");
  std::set<std::string> point_names_checked;
  for (const auto& [name, spec] : r.Entries(node, "links")) {
    Link l;
    std::optional<YAML::Node> point_masses;  // a copy shares the node (assignment would not)
    l.name = name;
    l.mark = r.KeyMark(spec);
    CheckName(m, name, NameRole::kLink, l.mark);
    if (!spec.IsMap()) r.Fail(spec, "link '" + name + "' must be a mapping with points:");
    for (const auto& [key, value] : r.Entries(spec, "link '" + name + "'", &LinkKeys())) {
      if (key == "ground") {
        const std::string g = r.Scalar(value, "ground");
        if (g != "true" && g != "false") r.Fail(value, "ground must be true or false");
        l.ground = g == "true";
      } else if (key == "mass") {
        l.mass.given = true;
        l.mass.mark = r.KeyMark(value);
        l.mass.mass = r.Expression(value, "mass of link '" + name + "'");
        if (r.Number(value, "mass of link '" + name + "'") < 0)
          r.Fail(value, "mass of link '" + name + "' is negative at the parameters' defaults; give a mass >= 0");
      } else if (key == "center") {
        if (!value.IsSequence() || value.size() != 2)
          r.Fail(value, "center of link '" + name + "' must be [x, y] in the link's frame");
        l.mass.center_x = r.Expression(value[0], "x of the centre of mass of '" + name + "'");
        l.mass.center_y = r.Expression(value[1], "y of the centre of mass of '" + name + "'");
        r.Number(value[0], "x of the centre of mass of '" + name + "'");
        r.Number(value[1], "y of the centre of mass of '" + name + "'");
      } else if (key == "inertia") {
        l.mass.inertia = r.Expression(value, "moment of inertia of link '" + name + "'");
        if (r.Number(value, "moment of inertia of link '" + name + "'") < 0)
          r.Fail(value, "moment of inertia of link '" + name + "' is negative; give J >= 0 about the centre of mass");
      } else if (key == "point_masses") {
        point_masses.emplace(value);  // read once the points are known
      } else {
        for (const auto& [pname, xy] : r.Entries(value, "points of link '" + name + "'")) {
          LinkPoint pt;
          pt.name = pname;
          pt.mark = r.KeyMark(xy);
          CheckName(m, pname, NameRole::kPoint, pt.mark);
          if (!xy.IsSequence() || xy.size() != 2)
            r.Fail(xy, "point '" + name + "." + pname + "' must be [x, y] in the link's frame");
          pt.x = r.Expression(xy[0], "x of " + name + "." + pname);
          pt.y = r.Expression(xy[1], "y of " + name + "." + pname);
          l.points.push_back(pt);
        }
      }
    }
    const YAML::Node& cspec = spec;  // const lookups never insert keys
    if (!l.mass.given && (cspec["center"] || cspec["inertia"]))
      r.Fail(cspec["center"] ? cspec["center"] : cspec["inertia"],
             "link '" + name + "' has a centre of mass or inertia but no mass; add mass: <value>");
    if (l.ground && l.mass.given)
      r.Fail(cspec["mass"], "the ground link '" + name + "' cannot have a mass (it does not move); remove mass:");
    if (l.points.empty())
      m.Fail(l.mark, "link '" + name + "' has no points; give it the points its joints use");
    if (point_masses) {
      l.point_masses = ReadPointMasses(r, l, *point_masses);
      if (!l.point_masses.empty()) l.mass = CombinedBody(r, l, *point_masses);
    }
    if (l.ground) {
      if (m.ground >= 0)
        m.Fail(l.mark, "two ground links ('" + m.links[m.ground].name + "' and '" + name +
                            "'); keep one, and put all fixed points on it");
      m.ground = static_cast<int>(m.links.size());
    }
    m.links.push_back(l);
  }
  if (m.ground < 0)
    r.Fail(node, "no ground link; mark the fixed frame with 'ground: true'");
}

}  // namespace mechgen
