// Reading and validating model files. The format is documented in models/README.md.
#include "model.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace mechgen {
namespace {

std::string Format(const std::string& file, SourceMark mark, const std::string& message) {
  std::ostringstream os;
  os << file;
  if (mark.line > 0) os << ":" << mark.line << ":" << mark.column;
  os << ": error: " << message;
  return os.str();
}

SourceMark MarkOf(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return {};
  return {m.line + 1, m.column + 1};
}

bool IsIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// Names of the expression language, and C++ keywords (parameters become struct members).
const std::set<std::string>& ReservedNames() {
  static const std::set<std::string> names = {
      "deg", "Pi", "pi", "sin", "cos", "tan", "sqrt", "atan2", "exp", "log", "abs", "pow", "I",
      "Euler", "Catalan", "Scalar", "Cast", "alignas", "auto", "bool", "break", "case", "catch",
      "char", "class", "const", "constexpr", "continue", "default", "delete", "do", "double",
      "else", "enum", "explicit", "extern", "false", "float", "for", "friend", "goto", "if",
      "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "nullptr", "operator",
      "private", "protected", "public", "register", "return", "short", "signed", "sizeof",
      "static", "struct", "switch", "template", "this", "throw", "true", "try", "typedef",
      "typename", "union", "unsigned", "using", "virtual", "void", "volatile", "while"};
  return names;
}

class Reader {
 public:
  explicit Reader(Model* model) : m_(*model) {}

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& message) const {
    m_.Fail(MarkOf(node), message);
  }

  // The keys of a mapping node, in document order, with duplicates and unknown keys
  // reported. yaml-cpp keeps every duplicate key, so they can be caught here.
  std::vector<std::pair<std::string, YAML::Node>> Entries(const YAML::Node& map,
                                                          const std::string& what,
                                                          const std::set<std::string>& allowed =
                                                              {}) const {
    if (!map.IsMap()) Fail(map, what + " must be a mapping (key: value)");
    std::vector<std::pair<std::string, YAML::Node>> out;
    std::set<std::string> seen;
    for (auto it = map.begin(); it != map.end(); ++it) {
      if (!it->first.IsScalar()) Fail(it->first, what + ": keys must be plain names");
      const std::string key = it->first.as<std::string>();
      if (!seen.insert(key).second)
        Fail(it->first, "duplicate name '" + key + "' in " + what + "; names must be unique");
      if (!allowed.empty() && !allowed.count(key)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        Fail(it->first, "unknown key '" + key + "' in " + what + "; expected one of: " + list);
      }
      out.emplace_back(key, it->second);
      keymarks_[it->second.Mark().pos] = MarkOf(it->first);
    }
    return out;
  }

  std::string Scalar(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) Fail(node, what + " must be a single value");
    return node.as<std::string>();
  }

  // An expression in the parameters (and `deg` = pi/180): geometry, angles, ranges; with
  // `u`, also in a cam contour's parameter u.
  GiNaC::ex Expression(const YAML::Node& node, const std::string& what,
                       const GiNaC::symbol* u = nullptr) const {
    const std::string text = Scalar(node, what);
    GiNaC::symtab table;
    for (const auto& p : m_.params) table[p.name] = p.symbol;
    table["deg"] = GiNaC::Pi / 180;
    if (u) table["u"] = *u;
    GiNaC::parser reader(table, /*strict=*/true);
    GiNaC::ex e;
    try {
      e = reader(text);
    } catch (const std::exception& err) {
      std::string why = err.what();
      Fail(node, what + ": cannot read '" + text + "' as an expression (" + why + "); use " +
                     (u ? "u, " : "") + "numbers, parameter names, + - * / ^, sin cos sqrt, and deg");
    }
    if (!e.info(GiNaC::info_flags::real) && e.has(GiNaC::I))
      Fail(node, what + ": '" + text + "' is not real");
    return e;
  }

  // A number: an expression evaluated at the parameters' default values.
  double Number(const YAML::Node& node, const std::string& what) const {
    GiNaC::ex e = Expression(node, what);
    GiNaC::exmap defaults;
    for (const auto& p : m_.params) defaults[p.symbol] = p.value;
    e = e.subs(defaults).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(e) || !GiNaC::ex_to<GiNaC::numeric>(e).is_real())
      Fail(node, what + " must evaluate to a real number");
    const double v = GiNaC::ex_to<GiNaC::numeric>(e).to_double();
    if (!std::isfinite(v)) Fail(node, what + " is not finite");
    return v;
  }

  // "link.point" -> PointRef.
  PointRef Point(const YAML::Node& node, const std::string& what) const {
    const std::string text = Scalar(node, what);
    const auto dot = text.find('.');
    if (dot == std::string::npos)
      Fail(node, what + ": '" + text + "' must name a link point as link.point");
    const std::string link = text.substr(0, dot), point = text.substr(dot + 1);
    for (size_t i = 0; i < m_.links.size(); ++i) {
      if (m_.links[i].name != link) continue;
      const int k = m_.links[i].FindPoint(point);
      if (k < 0) {
        std::string list;
        for (const auto& pt : m_.links[i].points) list += (list.empty() ? "" : ", ") + pt.name;
        Fail(node, what + ": link '" + link + "' has no point '" + point +
                       "'; its points are: " + list);
      }
      return {static_cast<int>(i), k};
    }
    std::string list;
    for (const auto& l : m_.links) list += (list.empty() ? "" : ", ") + l.name;
    Fail(node, what + ": unknown link '" + link + "'; the links are: " + list);
  }

  // "<rolling joint>.contact": the contact point of a rolling joint; else link = -1.
  PointRef ContactPoint(const YAML::Node& node) const {
    if (!node.IsScalar()) return {};
    const std::string text = node.as<std::string>();
    const auto dot = text.find('.');
    if (dot == std::string::npos || text.substr(dot + 1) != "contact") return {};
    for (size_t k = 0; k < m_.joints.size(); ++k)
      if (m_.joints[k].name == text.substr(0, dot) && m_.joints[k].type == JointType::kRoll)
        return {m_.joints[k].b.link, -1, static_cast<int>(k)};
    return {};
  }

  SourceMark KeyMark(const YAML::Node& value) const {
    auto it = keymarks_.find(value.Mark().pos);
    return it == keymarks_.end() ? MarkOf(value) : it->second;
  }

  void ReadParameters(const YAML::Node& node) {
    if (!node) return;
    for (const auto& [name, value] : Entries(node, "parameters")) {
      Parameter p;
      p.name = name;
      p.mark = KeyMark(value);
      if (!IsIdentifier(name) || ReservedNames().count(name))
        m_.Fail(p.mark, "parameter name '" + name +
                            "' must be a C++ identifier and neither a C++ keyword nor a name of the " +
                            "expression language (deg, Pi, sin, cos, sqrt, ...); rename it");
      YAML::Node v = value;
      if (value.IsMap()) {
        auto entries = Entries(value, "parameter '" + name + "'", {"value", "doc"});
        v = YAML::Node();
        for (auto& [k, n] : entries) {
          if (k == "value") v = n;
          if (k == "doc") p.doc = Scalar(n, "doc");
        }
        if (!v) Fail(value, "parameter '" + name + "' needs a value");
      }
      const std::string text = Scalar(v, "parameter '" + name + "'");
      char* end = nullptr;
      p.value = std::strtod(text.c_str(), &end);
      if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(p.value))
        Fail(v, "parameter '" + name + "' must be a number, not '" + text +
                    "' (parameter defaults are plain numbers; use expressions in geometry)");
      p.symbol = GiNaC::symbol(name);
      m_.params.push_back(p);
    }
  }

  void ReadLinks(const YAML::Node& node) {
    if (!node) m_.Fail({}, "the model has no 'links'; add a links: section with a ground link");
    std::set<std::string> point_names_checked;
    for (const auto& [name, spec] : Entries(node, "links")) {
      Link l;
      l.name = name;
      l.mark = KeyMark(spec);
      if (!IsIdentifier(name))
        m_.Fail(l.mark, "link name '" + name + "' must be an identifier (letters, digits, _)");
      if (!spec.IsMap()) Fail(spec, "link '" + name + "' must be a mapping with points:");
      for (const auto& [key, value] : Entries(spec, "link '" + name + "'", {"ground", "points"})) {
        if (key == "ground") {
          const std::string g = Scalar(value, "ground");
          if (g != "true" && g != "false") Fail(value, "ground must be true or false");
          l.ground = g == "true";
        } else {
          for (const auto& [pname, xy] : Entries(value, "points of link '" + name + "'")) {
            LinkPoint pt;
            pt.name = pname;
            pt.mark = KeyMark(xy);
            if (!IsIdentifier(pname))
              m_.Fail(pt.mark, "point name '" + pname + "' must be an identifier");
            if (!xy.IsSequence() || xy.size() != 2)
              Fail(xy, "point '" + name + "." + pname + "' must be [x, y] in the link's frame");
            pt.x = Expression(xy[0], "x of " + name + "." + pname);
            pt.y = Expression(xy[1], "y of " + name + "." + pname);
            l.points.push_back(pt);
          }
        }
      }
      if (l.points.empty())
        m_.Fail(l.mark, "link '" + name + "' has no points; give it the points its joints use");
      if (l.ground) {
        if (m_.ground >= 0)
          m_.Fail(l.mark, "two ground links ('" + m_.links[m_.ground].name + "' and '" + name +
                              "'); keep one, and put all fixed points on it");
        m_.ground = static_cast<int>(m_.links.size());
      }
      m_.links.push_back(l);
    }
    if (m_.ground < 0)
      Fail(node, "no ground link; mark the fixed frame with 'ground: true'");
  }

  // A link by name -> its index.
  int LinkIndex(const YAML::Node& node, const std::string& what) const {
    const std::string text = Scalar(node, what);
    for (size_t i = 0; i < m_.links.size(); ++i)
      if (m_.links[i].name == text) return static_cast<int>(i);
    std::string list;
    for (const auto& l : m_.links) list += (list.empty() ? "" : ", ") + l.name;
    Fail(node, what + ": unknown link '" + text + "'; the links are: " + list);
  }

  bool Bool(const YAML::Node& node, const std::string& what) const {
    const std::string v = Scalar(node, what);
    if (v != "true" && v != "false") Fail(node, what + " must be true or false");
    return v == "true";
  }

  // A cam's contour: {x: <x(u)>, y: <y(u)>, period: <u's range, default 2 pi>} in the
  // cam's frame, or {points: [[x, y], ...]} (a periodic cubic spline, counter-clockwise).
  void ReadContour(const YAML::Node& node, Joint* j) const {
    j->contour_mark = MarkOf(node);
    const std::string what = "contour of cam '" + j->name + "'";
    bool has_x = false, has_y = false, has_points = false, has_period = false;
    for (const auto& [key, value] : Entries(node, what, {"x", "y", "period", "points"})) {
      if (key == "x") j->contour_x = Expression(value, what + ", x", &j->contour_u), has_x = true;
      if (key == "y") j->contour_y = Expression(value, what + ", y", &j->contour_u), has_y = true;
      if (key == "period") {
        j->contour_period = Expression(value, what + ", period");
        if (!(Number(value, what + ", period") > 0)) Fail(value, what + ": the period must be positive");
        has_period = true;
      }
      if (key == "points") {
        if (!value.IsSequence())
          Fail(value, what + ": points must be a list of [x, y] pairs, counter-clockwise around the cam's pivot");
        for (const YAML::Node& pt : value) {
          if (!pt.IsSequence() || pt.size() != 2) Fail(pt, what + ": each point must be a pair [x, y]");
          j->contour_points.push_back({Number(pt[0], what + ", x"), Number(pt[1], what + ", y")});
          j->contour_point_marks.push_back(MarkOf(pt));
        }
        has_points = true;
      }
    }
    if (has_points) {
      if (has_x || has_y || has_period)
        Fail(node, what + ": give either points: [[x, y], ...] or the expressions x: and y: (with period:), not both");
      j->contour = Joint::Contour::kSpline;
      return;
    }
    if (!has_x || !has_y)
      Fail(node, what + " needs x: and y: (expressions in the contour parameter u and the parameters) or points:");
    if (!has_period) j->contour_period = 2 * GiNaC::Pi;
    j->contour_text = "x(u) = " + Scalar(node["x"], what) + ", y(u) = " + Scalar(node["y"], what);
    j->contour = Joint::Contour::kExpressions;
  }

  // The cam's follower law: a list of {dwell: angle} / {rise|return: angle, lift: h,
  // motion: cycloidal|harmonic|poly345}.
  std::vector<CamSegment> ReadLaw(const YAML::Node& node, const std::string& joint) const {
    if (!node.IsSequence() || node.size() == 0)
      Fail(node, "law of cam '" + joint + "' must be a list of segments: - {dwell: 90*deg} "
                 "- {rise: 120*deg, lift: h, motion: cycloidal} ...");
    std::vector<CamSegment> out;
    for (const auto& item : node) {
      CamSegment seg;
      seg.mark = MarkOf(item);
      bool has_lift = false, has_kind = false;
      for (const auto& [key, value] : Entries(item, "law segment", {"dwell", "rise", "return", "lift", "motion"})) {
        if (key == "dwell" || key == "rise" || key == "return") {
          if (has_kind) Fail(value, "a law segment is one of dwell, rise or return, not two");
          has_kind = true;
          seg.kind = key == "dwell" ? CamSegment::Kind::kDwell
                     : key == "rise" ? CamSegment::Kind::kRise
                                     : CamSegment::Kind::kReturn;
          seg.duration = Expression(value, key + " angle");
          if (!(Number(value, key + " angle") > 0))
            Fail(value, key + " angle must be positive (a cam angle such as 90*deg)");
        } else if (key == "lift") {
          seg.lift = Expression(value, "lift");
          has_lift = true;
        } else {
          const std::string mo = Scalar(value, "motion");
          if (mo == "cycloidal") seg.motion = CamSegment::Motion::kCycloidal;
          else if (mo == "harmonic") seg.motion = CamSegment::Motion::kHarmonic;
          else if (mo == "poly345") seg.motion = CamSegment::Motion::kPoly345;
          else Fail(value, "unknown motion '" + mo + "'; use cycloidal, harmonic or poly345");
        }
      }
      if (!has_kind) Fail(item, "a law segment needs dwell:, rise: or return: with its cam angle");
      if (seg.kind == CamSegment::Kind::kDwell) {
        if (has_lift || seg.motion != CamSegment::Motion::kNone)
          Fail(item, "a dwell has no lift and no motion; give only {dwell: angle}");
      } else {
        if (!has_lift) Fail(item, "a rise or return needs lift: (the follower's travel)");
        if (seg.motion == CamSegment::Motion::kNone)
          Fail(item, "a rise or return needs motion: cycloidal, harmonic or poly345");
      }
      out.push_back(seg);
    }
    return out;
  }

  void ReadJoints(const YAML::Node& node) {
    if (!node) m_.Fail({}, "the model has no 'joints'");
    struct Pending {
      size_t joint;
      YAML::Node node;
      std::string name;
    };
    std::vector<Pending> pending;  // joint references, resolved once all joints are read
    int cams = 0;
    for (const auto& [name, spec] : Entries(node, "joints")) {
      Joint j;
      j.name = name;
      j.mark = KeyMark(spec);
      if (!IsIdentifier(name)) m_.Fail(j.mark, "joint name '" + name + "' must be an identifier");
      auto entries = Entries(spec, "joint '" + name + "'", {"revolute", "prismatic", "roll", "gear", "rack", "cam"});
      if (entries.size() != 1)
        Fail(spec, "joint '" + name + "' must have exactly one kind: revolute, prismatic, roll, gear, rack or cam");
      const auto& [kind, body] = entries[0];
      const std::string jn = "joint '" + name + "'";
      if (kind == "revolute") {
        j.type = JointType::kRevolute;
        if (!body.IsSequence() || body.size() != 2)
          Fail(body, "revolute joint '" + name + "' takes two link points: [link1.P, link2.P]");
        j.a = Point(body[0], "joint '" + name + "'");
        j.b = Point(body[1], "joint '" + name + "'");
      } else if (kind == "prismatic") {
        j.type = JointType::kPrismatic;
        bool has_guide = false, has_slider = false;
        for (const auto& [key, value] : Entries(body, "prismatic joint '" + name + "'",
                                                {"guide", "slider", "angle", "relative_angle"})) {
          if (key == "guide") j.a = Point(value, "guide of '" + name + "'"), has_guide = true;
          if (key == "slider") j.b = Point(value, "slider of '" + name + "'"), has_slider = true;
          if (key == "angle") j.angle = Expression(value, "angle of '" + name + "'");
          if (key == "relative_angle")
            j.relative_angle = Expression(value, "relative_angle of '" + name + "'");
        }
        if (!has_guide || !has_slider)
          Fail(body, "prismatic joint '" + name +
                         "' needs guide: link.point (a point on the line) and slider: link.point");
      } else if (kind == "roll") {
        j.type = JointType::kRoll;
        bool has_wheel = false, has_on = false, has_radius = false, has_on_radius = false,
             has_line_angle = false, has_inside = false;
        for (const auto& [key, value] : Entries(body, "rolling joint '" + name + "'",
                                                {"wheel", "radius", "on", "line_angle", "on_radius", "inside", "phase"})) {
          if (key == "wheel") j.b = Point(value, "wheel of '" + name + "'"), has_wheel = true;
          if (key == "on") j.a = Point(value, "on of '" + name + "'"), has_on = true;
          if (key == "radius") j.radius = Expression(value, "radius of '" + name + "'"), has_radius = true;
          if (key == "line_angle") j.angle = Expression(value, "line_angle of '" + name + "'"), has_line_angle = true;
          if (key == "on_radius")
            j.radius2 = Expression(value, "on_radius of '" + name + "'"), has_on_radius = true;
          if (key == "inside") j.internal = Bool(value, "inside"), has_inside = true;
          if (key == "phase") j.phase = Expression(value, "phase of '" + name + "'");
        }
        if (!has_wheel || !has_on || !has_radius)
          Fail(body, "rolling joint '" + name + "' needs wheel: link.C (the wheel's centre), radius: r, and "
                     "on: link.P (a point of the line, or the centre of the circle with on_radius: R)");
        if (has_on_radius && has_line_angle)
          Fail(body, "rolling joint '" + name + "': give line_angle (a line) or on_radius (a circle), not both");
        if (has_inside && !has_on_radius) Fail(body, "rolling joint '" + name + "': inside needs on_radius (a circle)");
        j.on_line = !has_on_radius;
        if (!(Number(body["radius"], "radius") > 0)) Fail(body["radius"], "the wheel radius must be positive");
        if (has_on_radius) {
          const double R = Number(body["on_radius"], "on_radius"), r = Number(body["radius"], "radius");
          if (!(R > 0)) Fail(body["on_radius"], "on_radius must be positive");
          if (j.internal && !(R > r))
            Fail(body["on_radius"], "a wheel rolling inside a circle must be smaller than it (radius " +
                                        std::to_string(r) + " >= on_radius " + std::to_string(R) + ")");
        }
      } else if (kind == "gear") {
        j.type = JointType::kGear;
        j.carrier = m_.ground;
        bool has_gears = false, has_radii = false;
        for (const auto& [key, value] : Entries(body, "gear pair '" + name + "'",
                                                {"gears", "radii", "carrier", "internal", "phase"})) {
          if (key == "gears") {
            if (!value.IsSequence() || value.size() != 2)
              Fail(value, "gears: takes the two gear links: [link1, link2]");
            j.a = {LinkIndex(value[0], jn), 0};
            j.b = {LinkIndex(value[1], jn), 0};
            has_gears = true;
          }
          if (key == "radii") {
            if (!value.IsSequence() || value.size() != 2) Fail(value, "radii: takes the two pitch radii: [r1, r2]");
            j.radius = Expression(value[0], "pitch radius");
            j.radius2 = Expression(value[1], "pitch radius");
            for (int i = 0; i < 2; ++i)
              if (!(Number(value[i], "pitch radius") > 0)) Fail(value[i], "a pitch radius must be positive");
            has_radii = true;
          }
          if (key == "carrier") j.carrier = LinkIndex(value, jn);
          if (key == "internal") j.internal = Bool(value, "internal");
          if (key == "phase") j.phase = Expression(value, "phase of '" + name + "'");
        }
        if (!has_gears || !has_radii)
          Fail(body, "gear pair '" + name + "' needs gears: [link1, link2] and radii: [r1, r2]");
        if (j.carrier == j.a.link || j.carrier == j.b.link)
          Fail(body, "gear pair '" + name + "': the carrier holds both gears' axes and is neither gear");
      } else if (kind == "rack") {
        j.type = JointType::kRack;
        bool has_pinion = false, has_radius = false, has_slide = false;
        for (const auto& [key, value] : Entries(body, "rack and pinion '" + name + "'",
                                                {"pinion", "radius", "slide", "phase"})) {
          if (key == "pinion") j.a = {LinkIndex(value, jn), 0}, has_pinion = true;
          if (key == "radius") j.radius = Expression(value, "radius of '" + name + "'"), has_radius = true;
          if (key == "slide") pending.push_back({m_.joints.size(), value, Scalar(value, "slide")}), has_slide = true;
          if (key == "phase") j.phase = Expression(value, "phase of '" + name + "'");
        }
        if (!has_pinion || !has_radius || !has_slide)
          Fail(body, "rack and pinion '" + name + "' needs pinion: link, radius: r and slide: <the rack's prismatic joint>");
      } else {
        j.type = JointType::kCam;
        j.cam_index = cams++;
        bool has_cam = false, has_follower = false, has_point = false, has_start = false, has_law = false;
        bool has_roller = false, has_face = false;
        for (const auto& [key, value] :
             Entries(body, "cam '" + name + "'",
                     {"cam", "follower", "point", "roller", "face", "start", "phase", "law", "contour"})) {
          if (key == "cam") j.a = {LinkIndex(value, jn), 0}, has_cam = true;
          if (key == "follower") pending.push_back({m_.joints.size(), value, Scalar(value, "follower")}), has_follower = true;
          if (key == "point") j.follower_point = Point(value, "point of '" + name + "'"), has_point = true;
          if (key == "roller") {
            j.roller = Expression(value, "roller radius");
            j.roller_mark = MarkOf(value);
            if (!(Number(value, "roller radius") >= 0)) Fail(value, "the roller radius must not be negative");
            has_roller = true;
          }
          if (key == "face") j.face_angle = Expression(value, "face angle"), j.flat_face = has_face = true;
          if (key == "start") j.start = Expression(value, "start of '" + name + "'"), has_start = true;
          if (key == "phase") j.phase = Expression(value, "phase of '" + name + "'");
          if (key == "law") j.law = ReadLaw(value, name), j.law_mark = MarkOf(value), has_law = true;
          if (key == "contour") ReadContour(value, &j);
        }
        if (j.contour != Joint::Contour::kNone) {
          if (has_law || has_start)
            Fail(body, "cam '" + name + "': a cam is given either by its follower's law (start:, law:) or by its "
                       "contour (contour:), not both");
          has_law = has_start = true;
        }
        if (!has_cam || !has_follower || !has_point || !has_start || !has_law)
          Fail(body, "cam '" + name + "' needs cam: <cam link>, follower: <the follower's joint to the carrier>, "
                     "point: follower.P (roller centre, knife tip or a point of the face), start: <follower "
                     "coordinate at zero lift> and law: [segments]");
        if (has_roller && has_face)
          Fail(body, "cam '" + name + "': a follower is either a roller (roller: r) or flat-faced (face: angle)");
        j.b = {j.follower_point.link, 0};
      }
      if (j.a.link == j.b.link)
        m_.Fail(j.mark, "joint '" + name + "' connects link '" + m_.links[j.a.link].name +
                            "' to itself; a joint must connect two different links");
      m_.joints.push_back(j);
    }
    for (const Pending& p : pending) {
      Joint& j = m_.joints[p.joint];
      int other = -1;
      for (size_t k = 0; k < m_.joints.size(); ++k)
        if (m_.joints[k].name == p.name) other = static_cast<int>(k);
      if (other < 0) Fail(p.node, "joint '" + j.name + "': unknown joint '" + p.name + "'");
      const Joint& o = m_.joints[other];
      j.other_joint = other;
      if (j.type == JointType::kRack) {
        if (o.type != JointType::kPrismatic)
          Fail(p.node, "rack '" + j.name + "': slide must name the rack's prismatic joint");
        j.b = {o.b.link, 0};
        j.carrier = o.a.link;
        if (j.a.link == j.b.link) Fail(p.node, "rack '" + j.name + "': the pinion cannot be the rack");
        continue;
      }
      // Cam: the follower's joint to the carrier.
      const int f = j.follower_point.link;
      if (o.type == JointType::kPrismatic) {
        if (o.b.link != f)
          Fail(p.node, "cam '" + j.name + "': the follower '" + m_.links[f].name + "' must be the slider of '" +
                           o.name + "' (a translating follower)");
        j.carrier = o.a.link;
      } else if (o.type == JointType::kRevolute) {
        if (o.a.link != f && o.b.link != f)
          Fail(p.node, "cam '" + j.name + "': joint '" + o.name + "' does not hold the follower '" +
                           m_.links[f].name + "' (an oscillating follower's pivot)");
        j.carrier = o.a.link == f ? o.b.link : o.a.link;
      } else {
        Fail(p.node, "cam '" + j.name + "': follower must name a prismatic joint (translating follower) or a "
                     "revolute joint (oscillating follower)");
      }
      if (j.carrier == j.a.link)
        Fail(p.node, "cam '" + j.name + "': the follower's joint must attach it to the link carrying the cam, not the cam");
      bool pivoted = false;
      for (const Joint& r : m_.joints)
        pivoted |= r.type == JointType::kRevolute && ((r.a.link == j.a.link && r.b.link == j.carrier) ||
                                                      (r.b.link == j.a.link && r.a.link == j.carrier));
      if (!pivoted)
        Fail(p.node, "cam '" + j.name + "': the cam '" + m_.links[j.a.link].name +
                         "' needs a revolute joint to the follower's carrier '" + m_.links[j.carrier].name + "'");
    }
  }

  void ReadInputs(const YAML::Node& node) {
    if (!node) m_.Fail({}, "the model has no 'inputs'; list the driven joints");
    m_.inputs_mark = MarkOf(node);
    if (!node.IsSequence()) Fail(node, "inputs must be a list: - {joint: A, range: [0, 360*deg]}");
    std::set<int> used;
    for (const auto& item : node) {
      Input in;
      in.mark = MarkOf(item);
      bool has_range = false;
      for (const auto& [key, value] : Entries(item, "input", {"joint", "range"})) {
        if (key == "joint") {
          const std::string jn = Scalar(value, "joint");
          for (size_t k = 0; k < m_.joints.size(); ++k)
            if (m_.joints[k].name == jn) in.joint = static_cast<int>(k);
          if (in.joint < 0) Fail(value, "input: unknown joint '" + jn + "'");
          if (!used.insert(in.joint).second)
            Fail(value, "joint '" + jn + "' is driven twice; list each input once");
          const Joint& j = m_.joints[in.joint];
          if (!j.IsLowerPair())
            Fail(value, "joint '" + jn + "' is a gear, rack or cam pair and cannot be driven; drive a " +
                            "revolute or prismatic joint of one of its links");
          if ((j.type == JointType::kRevolute || j.type == JointType::kRoll) && j.a.link != m_.ground &&
              j.b.link != m_.ground)
            Fail(value, "input joint '" + jn +
                            "' connects two moving links; drive a revolute joint attached to " +
                            "the ground, or a prismatic joint");
        } else {
          if (!value.IsSequence() || value.size() != 2)
            Fail(value, "range must be [min, max]");
          in.min = Number(value[0], "range min");
          in.max = Number(value[1], "range max");
          has_range = true;
        }
      }
      if (in.joint < 0) Fail(item, "input needs joint: <joint name>");
      if (!has_range) {
        const bool angle = m_.joints[in.joint].type != JointType::kPrismatic;
        in.min = 0;
        in.max = angle ? 2 * M_PI : 1;
      }
      m_.inputs.push_back(in);
    }
  }

  void ReadOutputs(const YAML::Node& node) {
    if (!node) return;
    m_.outputs.mark = MarkOf(node);
    for (const auto& [key, value] : Entries(node, "outputs", {"order", "points", "scene"})) {
      if (key == "order") {
        const std::string o = Scalar(value, "order");
        if (o != "0" && o != "1" && o != "2")
          Fail(value, "order must be 0 (positions), 1 (+ velocity coefficients K) or 2 (+ "
                      "centripetal coefficients L)");
        m_.outputs.order = o[0] - '0';
      } else if (key == "points") {
        if (!value.IsSequence()) Fail(value, "points must be a list of link.point names");
        for (const auto& pn : value) {
          PointRef r = ContactPoint(pn);
          if (r.contact_joint < 0) r = Point(pn, "output point");
          for (const auto& other : m_.outputs.points)
            if (other == r) Fail(pn, "point '" + m_.PointName(r) + "' is listed twice");
          m_.outputs.points.push_back(r);
        }
      } else {
        const std::string s = Scalar(value, "scene");
        if (s != "true" && s != "false") Fail(value, "scene must be true or false");
        m_.outputs.scene = s == "true";
      }
    }
  }

  void ReadAssembly(const YAML::Node& node) {
    if (!node) return;
    for (const auto& [name, value] : Entries(node, "assembly")) {
      GuessValue g;
      g.coordinate = name;
      g.mark = KeyMark(value);
      g.value = Number(value, "assembly value of '" + name + "'");
      m_.guess.push_back(g);
    }
  }

 private:
  Model& m_;
  mutable std::map<int, SourceMark> keymarks_;  // value position -> mark of its key
};

}  // namespace

ModelError::ModelError(const std::string& file, SourceMark mark, const std::string& message)
    : std::runtime_error(Format(file, mark, message)),
      file_(file),
      mark_(mark),
      message_(message) {}

int Link::FindPoint(const std::string& point) const {
  for (size_t i = 0; i < points.size(); ++i)
    if (points[i].name == point) return static_cast<int>(i);
  return -1;
}

std::string Model::PointName(PointRef r) const {
  if (r.contact_joint >= 0) return joints[r.contact_joint].name + ".contact";
  return links[r.link].name + "." + links[r.link].points[r.point].name;
}

void Model::Fail(SourceMark mark, const std::string& message) const {
  throw ModelError(file, mark, message);
}

Model LoadModel(const std::string& path, const std::string& name_override) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path, {}, "cannot open the model file");
  std::ostringstream text;
  text << in.rdbuf();
  return LoadModelFromString(text.str(), path, name_override);
}

Model LoadModelFromString(const std::string& text, const std::string& path,
                          const std::string& name_override) {
  Model m;
  m.file = path;
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    m.Fail({e.mark.line + 1, e.mark.column + 1}, "YAML syntax: " + e.msg);
  }
  if (!root || !root.IsMap()) m.Fail({1, 1}, "a model file is a YAML mapping (name:, links:, ...)");
  Reader r(&m);
  const auto entries = r.Entries(root, "the model",
                                 {"name", "title", "description", "parameters", "links", "joints",
                                  "inputs", "outputs", "assembly"});
  const YAML::Node& const_root = root;  // const lookups never insert keys
  auto get = [&](const std::string& key) { return const_root[key]; };
  try {
    if (YAML::Node n = get("name")) {
      m.name = r.Scalar(n, "name");
      if (!IsIdentifier(m.name)) r.Fail(n, "name must be a C++ identifier (the namespace)");
    }
    if (!name_override.empty()) m.name = name_override;
    if (m.name.empty()) m.Fail({1, 1}, "the model has no name; add name: <identifier>");
    if (YAML::Node n = get("title")) m.title = r.Scalar(n, "title");
    if (YAML::Node n = get("description")) m.description = r.Scalar(n, "description");
    r.ReadParameters(get("parameters"));
    r.ReadLinks(get("links"));
    r.ReadJoints(get("joints"));
    r.ReadInputs(get("inputs"));
    r.ReadOutputs(get("outputs"));
    r.ReadAssembly(get("assembly"));
  } catch (const YAML::Exception& e) {  // e.g. a conversion yaml-cpp refuses
    m.Fail({e.mark.line + 1, e.mark.column + 1}, e.msg);
  }
  // Names must not collide across parameters, links and joints: they become C++ names.
  std::map<std::string, SourceMark> names;
  auto claim = [&](const std::string& n, SourceMark mark, const char* what) {
    if (!names.emplace(n, mark).second)
      m.Fail(mark, std::string(what) + " name '" + n +
                       "' is already used by a parameter, link or joint; rename one");
  };
  for (const auto& p : m.params) claim(p.name, p.mark, "parameter");
  for (const auto& l : m.links) claim(l.name, l.mark, "link");
  for (const auto& j : m.joints) claim(j.name, j.mark, "joint");
  return m;
}

}  // namespace mechgen
