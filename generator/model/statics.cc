// The statics sections (Paul ch. 5): `gravity`, `loads`, `springs` and `friction`
// (LoadKeys, SpringKeys, FrictionKeys). The links' mass properties are read with the links
// (links.cc). Loads may depend on the coordinates: their expressions read the coordinates'
// names as placeholder symbols (Model::coordinate_refs) that the statics derivation
// (symbolic/statics.h) replaces by the coordinates themselves.
#include <regex>
#include <sstream>

#include "joints/joint_kind.h"
#include "model/expression_functions.h"
#include "model/reader.h"

namespace mechgen {

const KeyTable& LoadKeys() {
  static const KeyTable table{
      "load",
      {{"force", "[Fx, Fy]: a force (expressions of parameters and coordinates)", false},
       {"at", "link.P: the force's point of application", false},
       {"frame", "fixed (default) or link: the frame of the force's components", false},
       {"torque", "a torque on a link, counter-clockwise positive (expression)", false},
       {"on", "the link the torque acts on", false}}};
  return table;
}

const KeyTable& SpringKeys() {
  static const KeyTable table{
      "spring",
      {{"between", "[link1.P, link2.Q]: a linear spring's two ends", false},
       {"torsional", "a revolute joint: a torsional spring there (instead of between)", false},
       {"stiffness", "k: N/m (linear) or N m/rad (torsional)", true},
       {"free_length", "linear: the length at which the tension is the preload (default 0)", false},
       {"preload", "linear: the tension at the free length (default 0)", false},
       {"free_angle", "torsional: theta_b - theta_a at which the torque is zero (default 0)", false}}};
  return table;
}

const KeyTable& FrictionKeys() {
  static const KeyTable table{
      "friction",
      {{"coefficient", "Coulomb coefficient mu (>= 0; default 0: viscous friction only)", false},
       {"pin_radius", "revolute: the pin's radius r (friction circle radius mu r); needs coefficient", false},
       {"viscous", "viscous coefficient c (dynamics): torque c omega_rel (N m s/rad) or force c v_rel (N s/m)", false}}};
  return table;
}

namespace {

// The names a load may use for the coordinates: the absolute angle of every link and the
// joints' own coordinates. Created only when a model has loads (new symbols would change
// GiNaC's term order, and so the bytes generated for models without loads).
void MakeCoordinateRefs(Model& m) {
  if (!m.coordinate_refs.empty()) return;
  for (const Link& l : m.links) m.coordinate_refs.emplace("theta_" + l.name, GiNaC::symbol("theta_" + l.name));
  for (const Joint& j : m.joints)
    if (const auto c = KindOf(j).Coordinate(m, j)) m.coordinate_refs.emplace(c->name, GiNaC::symbol(c->name));
}

// Notes (in the model) the first load that jumps where a velocity is 0: step, sign or mod of
// an argument that holds a velocity <coordinate>_dot. At rest (the statics) it has no value:
// its limits as the velocity goes to 0 from either side differ. A load continuous in the
// velocities (c*theta_dot, a table of a speed, min, max, abs) has the limit of a slow motion
// there, its value at zero velocity. CheckDynamicRefs refuses the first one with `forces`.
void NoteJumpAtRest(const SectionReader& r, const YAML::Node& node, const std::string& text, const std::string& what,
                    const GiNaC::ex& e) {
  Model& m = r.model();
  bool jumps = false;
  for (auto it = e.preorder_begin(); it != e.preorder_end() && !jumps; ++it) {
    if (!is_ex_the_function(*it, mstep) && !is_ex_the_function(*it, msign) && !is_ex_the_function(*it, mmod)) continue;
    for (const auto& [name, sym] : m.velocity_refs) jumps = jumps || (name != "t" && it->has(sym));
  }
  if (!jumps) return;
  m.at_rest_jump_load = what;
  m.at_rest_jump_mark = MarkOf(node);
  m.at_rest_jump_call = "";
  // The call as written: the first step(, sign( or mod( whose argument names a velocity.
  static const std::regex call(R"((^|[^A-Za-z0-9_])(step|sign|mod)\s*\()");
  static const std::regex velocity(R"((^|[^A-Za-z0-9_])[A-Za-z_][A-Za-z0-9_]*_dot($|[^A-Za-z0-9_]))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), call); it != std::sregex_iterator(); ++it) {
    const size_t start = static_cast<size_t>(it->position(2));
    size_t close = static_cast<size_t>(it->position(0) + it->length(0));
    int depth = 1;
    for (; close < text.size() && depth > 0; ++close) depth += text[close] == '(' ? 1 : text[close] == ')' ? -1 : 0;
    const std::string written = text.substr(start, close - start);
    if (!std::regex_search(written, velocity)) continue;
    m.at_rest_jump_mark = r.MarkAt(node, text, start);
    m.at_rest_jump_call = written;
    return;
  }
  std::ostringstream os;
  os << e;
  m.at_rest_jump_call = os.str();
}

GiNaC::ex LoadExpression(SectionReader& r, const YAML::Node& node, const std::string& what) {
  Model& m = r.model();
  MakeCoordinateRefs(m);
  // The expression language of every expression (checked, at most 64 parentheses, ...),
  // with the coordinates' names besides the parameters.
  GiNaC::symtab coordinates;
  for (const auto& [name, sym] : m.coordinate_refs) coordinates[name] = sym;
  // Time and velocities (the dynamics): t and <coordinate>_dot; accelerations are reserved.
  static const std::regex reserved(R"((^|[^A-Za-z0-9_])(t|[A-Za-z_][A-Za-z0-9_]*_d?dot)(?=$|[^A-Za-z0-9_]))");
  const std::string text = r.Scalar(node, what);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), reserved); it != std::sregex_iterator(); ++it) {
    const std::smatch& match = *it;
    SourceMark at = MarkOf(node);  // the name's own column (a plain scalar on one line)
    if (node.Tag() != "!" && text.find('\n') == std::string::npos)
      at.column += static_cast<int>(match.position(2));
    const std::string name = match[2].str();
    if (name.size() > 5 && name.compare(name.size() - 5, 5, "_ddot") == 0)
      m.Fail(at, what + ": '" + name + "' is reserved (accelerations); a load depends on the parameters, the "
                        "coordinates, time t and the velocities <coordinate>_dot only");
    // The names of time and every coordinate's velocity, created at their first use (new
    // symbols would change GiNaC's term order for models without them).
    if (m.velocity_refs.empty()) {
      m.velocity_refs.emplace("t", GiNaC::symbol("t"));
      for (const auto& [c, sym] : m.coordinate_refs) m.velocity_refs.emplace(c + "_dot", GiNaC::symbol(c + "_dot"));
    }
    if (!m.velocity_ref_mark.line) {
      m.velocity_ref_mark = at;
      m.velocity_ref_name = name;
    }
  }
  for (const auto& [name, sym] : m.velocity_refs) coordinates[name] = sym;
  r.AllowTables(true);
  const GiNaC::ex e = r.Expression(node, what, coordinates);
  r.AllowTables(false);
  if (!m.at_rest_jump_mark.line) NoteJumpAtRest(r, node, text, what, e);
  std::string reads;  // the velocities (then t) it reads, in name order
  for (const auto& [name, sym] : m.velocity_refs)
    if (name != "t" && e.has(sym)) reads += (reads.empty() ? "" : ", ") + name;
  if (const auto t = m.velocity_refs.find("t"); t != m.velocity_refs.end() && e.has(t->second))
    reads += std::string(reads.empty() ? "" : ", ") + "t";
  if (!reads.empty()) m.at_rest_loads.emplace_back(what, reads);
  return e;
}

}  // namespace

std::string AlwaysTogether(const Model& m, const PointRef& a, const PointRef& b) {
  if (a.link < 0 || b.link < 0 || a.contact_joint >= 0 || b.contact_joint >= 0) return "";
  // Union-find over every link point: a revolute joint's two points are one; so are two points
  // of one link whose coordinates are the same expressions.
  std::vector<int> first(m.links.size() + 1, 0);
  for (size_t l = 0; l < m.links.size(); ++l) first[l + 1] = first[l] + static_cast<int>(m.links[l].points.size());
  std::vector<int> parent(static_cast<size_t>(first.back()));
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  auto index = [&](const PointRef& p) { return first[p.link] + p.point; };
  std::vector<std::string> joints;  // the revolute joints that join a's class to b's
  for (const Joint& j : m.joints) {
    if (j.type() != JointType::kRevolute) continue;
    const RevoluteData& d = j.Data<RevoluteData>();
    if (d.a.link < 0 || d.b.link < 0) continue;
    parent[find(index(d.a))] = find(index(d.b));
  }
  for (size_t l = 0; l < m.links.size(); ++l) {
    const std::vector<LinkPoint>& pts = m.links[l].points;
    for (size_t i = 0; i < pts.size(); ++i)
      for (size_t k = i + 1; k < pts.size(); ++k)
        if ((pts[i].x - pts[k].x).expand().is_zero() && (pts[i].y - pts[k].y).expand().is_zero())
          parent[find(first[l] + static_cast<int>(i))] = find(first[l] + static_cast<int>(k));
  }
  if (find(index(a)) != find(index(b))) return "";
  for (const Joint& j : m.joints) {
    if (j.type() != JointType::kRevolute) continue;
    const RevoluteData& d = j.Data<RevoluteData>();
    if (d.a.link >= 0 && find(index(d.a)) == find(index(a))) joints.push_back(j.name);
  }
  std::string list;
  for (size_t i = 0; i < joints.size(); ++i)
    list += (i == 0 ? "" : i + 1 == joints.size() ? " and " : ", ") + joints[i];
  return joints.size() == 1 ? "the revolute joint " + list + " keeps them together"
                            : "the revolute joints " + list + " keep them together";
}

void ReadGravity(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  if (!node.IsSequence() || node.size() != 2)
    r.Fail(node, "gravity must be [gx, gy]: the acceleration of gravity in the fixed frame, e.g. [0, -9.81]");
  m.has_gravity = true;
  m.gravity_mark = MarkOf(node);
  m.gravity_x = r.Expression(node[0], "gravity x");
  m.gravity_y = r.Expression(node[1], "gravity y");
  r.Number(node[0], "gravity x");
  r.Number(node[1], "gravity y");
}

void ReadLoads(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, spec] : r.Entries(node, "loads")) {
    Load l;
    l.name = name;
    l.mark = r.KeyMark(spec);
    if (!IsIdentifier(name)) m.Fail(l.mark, "load name '" + name + "' must be an identifier (letters, digits, _)");
    if (!spec.IsMap())
      r.Fail(spec, "load '" + name + "' must be {force: [Fx, Fy], at: link.P} or {torque: T, on: link}");
    const YAML::Node& s = spec;
    for (const auto& entry : r.Entries(spec, "load '" + name + "'", &LoadKeys())) (void)entry;
    const bool force = static_cast<bool>(s["force"]), torque = static_cast<bool>(s["torque"]);
    if (force == torque)
      r.Fail(spec, "load '" + name + "' needs exactly one of force: [Fx, Fy] (with at: link.P) or torque: T (with on: link)");
    if (force) {
      l.kind = Load::Kind::kForce;
      if (!s["at"]) r.Fail(spec, "load '" + name + "': a force needs at: link.P, its point of application");
      if (s["on"]) r.Fail(s["on"], "load '" + name + "': on: is for torques; a force takes at: link.P");
      l.at = r.Point(s["at"], "load '" + name + "'");
      l.link = l.at.link;
      const YAML::Node& f = s["force"];
      if (!f.IsSequence() || f.size() != 2) r.Fail(f, "load '" + name + "': force must be [Fx, Fy]");
      l.fx = LoadExpression(r, f[0], "x of load '" + name + "'");
      l.fy = LoadExpression(r, f[1], "y of load '" + name + "'");
      if (s["frame"]) {
        const std::string fr = r.Scalar(s["frame"], "frame");
        if (fr != "fixed" && fr != "link")
          r.Fail(s["frame"], "frame must be fixed (the force's components in the fixed frame) or link (in the link's frame)");
        l.link_frame = fr == "link";
      }
    } else {
      l.kind = Load::Kind::kTorque;
      if (!s["on"]) r.Fail(spec, "load '" + name + "': a torque needs on: <link>");
      if (s["at"] || s["frame"]) r.Fail(s["at"] ? s["at"] : s["frame"], "load '" + name + "': a torque takes on: <link> only");
      l.link = r.LinkIndex(s["on"], "load '" + name + "'");
      l.torque = LoadExpression(r, s["torque"], "torque of load '" + name + "'");
    }
    if (m.links[l.link].ground)
      m.Fail(l.mark, "load '" + name + "' acts on the ground link, which does not move: it does no work; put it on a moving link");
    m.loads.push_back(l);
  }
}

void ReadSprings(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, spec] : r.Entries(node, "springs")) {
    Spring sp;
    sp.name = name;
    sp.mark = r.KeyMark(spec);
    if (!IsIdentifier(name)) m.Fail(sp.mark, "spring name '" + name + "' must be an identifier (letters, digits, _)");
    if (!spec.IsMap()) r.Fail(spec, "spring '" + name + "' must be a mapping: {between: [a.P, b.Q], stiffness: k, ...}");
    for (const auto& entry : r.Entries(spec, "spring '" + name + "'", &SpringKeys())) (void)entry;
    const YAML::Node& s = spec;
    if (static_cast<bool>(s["between"]) == static_cast<bool>(s["torsional"]))
      r.Fail(spec, "spring '" + name + "' needs exactly one of between: [link1.P, link2.Q] (linear) or torsional: <revolute joint>");
    const std::string what = "spring '" + name + "'";
    if (!s["stiffness"])
      r.Fail(spec, what + " needs stiffness: k (N/m for a linear spring, N m/rad for a torsional one); add it");
    sp.stiffness = r.Expression(s["stiffness"], "stiffness of " + what);
    if (r.Number(s["stiffness"], "stiffness of " + what) < 0)
      r.Fail(s["stiffness"], "stiffness of " + what + " is negative; give k >= 0");
    if (s["between"]) {
      const YAML::Node& b = s["between"];
      if (!b.IsSequence() || b.size() != 2) r.Fail(b, what + ": between must be [link1.P, link2.Q]");
      sp.a = r.Point(b[0], what);
      sp.b = r.Point(b[1], what);
      if (sp.a.link == sp.b.link) r.Fail(b, what + " joins two points of one link: it never changes length; join two links");
      const std::string together = AlwaysTogether(m, sp.a, sp.b);
      if (!together.empty())
        r.Fail(b, what + " joins " + m.PointName(sp.a) + " and " + m.PointName(sp.b) + ", which are always at one "
                      "place (" + together + "): it has no length and no direction; join two points that move "
                      "apart, or use a torsional spring at the joint");
      if (s["free_angle"]) r.Fail(s["free_angle"], what + ": free_angle is for torsional springs; a linear spring takes free_length");
      if (s["free_length"]) {
        sp.free_length = r.Expression(s["free_length"], "free length of " + what);
        if (r.Number(s["free_length"], "free length of " + what) < 0)
          r.Fail(s["free_length"], "free length of " + what + " is negative; give l0 >= 0");
      }
      if (s["preload"]) {
        sp.preload = r.Expression(s["preload"], "preload of " + what);
        r.Number(s["preload"], "preload of " + what);
      }
    } else {
      sp.torsional = true;
      const std::string jn = r.Scalar(s["torsional"], what);
      sp.joint = m.FindJoint(jn);
      if (sp.joint < 0) r.Fail(s["torsional"], what + ": unknown joint '" + jn + "'; a torsional spring sits at a revolute joint");
      if (m.joints[sp.joint].type() != JointType::kRevolute)
        r.Fail(s["torsional"], what + ": joint '" + jn + "' is not revolute; a torsional spring sits at a revolute joint");
      if (s["free_length"] || s["preload"])
        r.Fail(s["free_length"] ? s["free_length"] : s["preload"],
               what + ": free_length and preload are for linear springs; a torsional spring takes free_angle");
      if (s["free_angle"]) {
        sp.free_angle = r.Expression(s["free_angle"], "free angle of " + what);
        r.Number(s["free_angle"], "free angle of " + what);
      }
    }
    m.springs.push_back(sp);
  }
}

void ReadFriction(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, spec] : r.Entries(node, "friction")) {
    Friction f;
    f.mark = r.KeyMark(spec);
    f.joint = m.FindJoint(name);
    if (f.joint < 0) m.Fail(f.mark, "friction: unknown joint '" + name + "'; friction is given per joint, by its name");
    const JointType type = m.joints[f.joint].type();
    if (type != JointType::kRevolute && type != JointType::kPrismatic)
      m.Fail(f.mark, "friction at joint '" + name + "': Coulomb friction is modelled at revolute and prismatic joints only");
    if (!spec.IsMap()) r.Fail(spec, "friction at '" + name + "' must be {coefficient: mu, pin_radius: r} (revolute) or {coefficient: mu} (prismatic)");
    for (const auto& entry : r.Entries(spec, "friction at '" + name + "'", &FrictionKeys())) (void)entry;
    const YAML::Node& s = spec;
    const std::string what = "friction at '" + name + "'";
    if (!s["coefficient"] && !s["viscous"])
      r.Fail(spec, what + " needs coefficient: mu (Coulomb) or viscous: c (dynamics), or both");
    if (s["coefficient"]) {
      f.coefficient = r.Expression(s["coefficient"], "coefficient of " + what);
      if (r.Number(s["coefficient"], "coefficient of " + what) < 0)
        r.Fail(s["coefficient"], "coefficient of " + what + " is negative; give mu >= 0");
    }
    if (!s["coefficient"]) {
      if (s["pin_radius"]) r.Fail(s["pin_radius"], what + ": pin_radius comes with coefficient: mu (Coulomb friction)");
    } else if (type == JointType::kRevolute) {
      if (!s["pin_radius"]) r.Fail(spec, what + ": a revolute joint needs pin_radius: r (the friction circle's radius is mu r)");
      f.pin_radius = r.Expression(s["pin_radius"], "pin radius of " + what);
      if (r.Number(s["pin_radius"], "pin radius of " + what) < 0)
        r.Fail(s["pin_radius"], "pin radius of " + what + " is negative; give r >= 0");
    } else if (s["pin_radius"]) {
      r.Fail(s["pin_radius"], what + ": pin_radius is for revolute joints; a prismatic joint's friction acts on its normal force");
    }
    if (s["viscous"]) {
      f.viscous = r.Expression(s["viscous"], "viscous coefficient of " + what);
      if (r.Number(s["viscous"], "viscous coefficient of " + what) < 0)
        r.Fail(s["viscous"], "viscous coefficient of " + what + " is negative");
    }
    m.friction.push_back(f);
  }
}

}  // namespace mechgen
