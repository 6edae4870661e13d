// The `links` section: each link's points in its own frame; one link is the ground
// (LinkKeys).
#include <set>

#include "model/reader.h"

namespace mechgen {

const KeyTable& LinkKeys() {
  static const KeyTable table{"link",
                              {{"ground", "true for the fixed frame (exactly one link; default false)", false},
                               {"points", "{NAME: [x, y]}: the link's points in its frame (expressions)", true}}};
  return table;
}

void ReadLinks(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) m.Fail({}, "the model has no 'links'; add a links: section with a ground link");
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
