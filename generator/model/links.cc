// The `links` section: each link's points in its own frame; one link is the ground
// (LinkKeys).
#include <set>

#include "model/reader.h"

namespace mechgen {

const KeyTable& LinkKeys() {
  static const KeyTable table{"link",
                              {{"ground", "true for the fixed frame (exactly one link; default false)", false},
                               {"points", "{NAME: [x, y]}: the link's points in its frame (expressions)", true},
                               {"mass", "the link's mass (expression; default: massless)", false},
                               {"center", "[x, y]: its centre of mass in the link's frame (default [0, 0]; needs mass)", false},
                               {"inertia", "its moment of inertia about the centre of mass (default 0; needs mass)", false}}};
  return table;
}

void ReadLinks(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) m.Fail({1, 1}, "the model has no 'links'; add a links: section with a ground link");
  std::set<std::string> point_names_checked;
  for (const auto& [name, spec] : r.Entries(node, "links")) {
    Link l;
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
