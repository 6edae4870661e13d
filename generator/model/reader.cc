// The model reader: the top level of a model file, the helpers every section reads with,
// and LoadModel. Each section has its own file in this folder (parameters.cc, links.cc,
// joints.cc, inputs.cc, outputs.cc, assembly.cc); the format is documented in
// models/README.md.
#include "model/reader.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "joints/joint_kind.h"

namespace mechgen {

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

bool KeyTable::Accepts(const std::string& key) const {
  for (const Key& k : keys)
    if (key == k.name) return true;
  return false;
}

const KeyTable& ModelKeys() {
  static const KeyTable table{"model",
                              {{"name", "C++ identifier: the namespace mech::<name> (or --name)", true},
                               {"title", "one line, copied into the generated header", false},
                               {"description", "free text, copied into the generated header", false},
                               {"parameters", "named numbers: the generated Params struct", false},
                               {"links", "the links and their points; one is the ground", true},
                               {"joints", "the joints between the links", true},
                               {"inputs", "the driven joints, in the order of q", true},
                               {"gravity", "[gx, gy]: gravity in the fixed frame (statics, dynamics)", false},
                               {"loads", "forces at link points and torques on links", false},
                               {"springs", "linear springs between link points, torsional at revolute joints", false},
                               {"friction", "Coulomb friction per revolute or prismatic joint", false},
                               {"outputs", "what the generated code computes", false},
                               {"assembly", "coordinate values near the wanted assembly mode", false}}};
  return table;
}

std::vector<const KeyTable*> AllKeyTables() {
  std::vector<const KeyTable*> out = {&ModelKeys(),  &ParameterKeys(), &LinkKeys(),      &JointKeys(),
                                      &InputKeys(),  &OutputKeys(),    &LawSegmentKeys(), &ContourKeys(),
                                      &LoadKeys(),   &SpringKeys(),     &FrictionKeys()};
  for (const JointKind* k : JointKinds()) out.push_back(&k->Keys());
  return out;
}

double ValueAtDefaults(const Model& m, const GiNaC::ex& expr, SourceMark mark, const std::string& what) {
  const GiNaC::ex e = expr.subs(m.Defaults()).evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(e) || !GiNaC::ex_to<GiNaC::numeric>(e).is_real())
    m.Fail(mark, what + " must evaluate to a real number");
  const double v = GiNaC::ex_to<GiNaC::numeric>(e).to_double();
  if (!std::isfinite(v)) m.Fail(mark, what + " is not finite");
  return v;
}

void SectionReader::Fail(const YAML::Node& node, const std::string& message) const { m_.Fail(MarkOf(node), message); }

std::vector<std::pair<std::string, YAML::Node>> SectionReader::Entries(const YAML::Node& map, const std::string& what,
                                                                       const KeyTable* table) const {
  if (!map.IsMap()) Fail(map, what + " must be a mapping (key: value)");
  std::vector<std::pair<std::string, YAML::Node>> out;
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (!it->first.IsScalar()) Fail(it->first, what + ": keys must be plain names");
    const std::string key = it->first.as<std::string>();
    if (!seen.insert(key).second) Fail(it->first, "duplicate name '" + key + "' in " + what + "; names must be unique");
    if (table && !table->Accepts(key)) {
      std::set<std::string> sorted;
      for (const Key& k : table->keys) sorted.insert(k.name);
      std::string list;
      for (const auto& a : sorted) list += (list.empty() ? "" : ", ") + a;
      Fail(it->first, "unknown key '" + key + "' in " + what + "; expected one of: " + list);
    }
    out.emplace_back(key, it->second);
    keymarks_[it->second.Mark().pos] = MarkOf(it->first);
  }
  return out;
}

std::string SectionReader::Scalar(const YAML::Node& node, const std::string& what) const {
  if (!node.IsScalar()) Fail(node, what + " must be a single value");
  return node.as<std::string>();
}

bool SectionReader::Bool(const YAML::Node& node, const std::string& what) const {
  const std::string v = Scalar(node, what);
  if (v != "true" && v != "false") Fail(node, what + " must be true or false");
  return v == "true";
}

GiNaC::ex SectionReader::Expression(const YAML::Node& node, const std::string& what, const GiNaC::symbol* u) const {
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
    Fail(node, what + ": cannot read '" + text + "' as an expression (" + why + "); use " + (u ? "u, " : "") +
                   "numbers, parameter names, + - * / ^, sin cos sqrt, and deg");
  }
  if (!e.info(GiNaC::info_flags::real) && e.has(GiNaC::I)) Fail(node, what + ": '" + text + "' is not real");
  return e;
}

double SectionReader::Number(const YAML::Node& node, const std::string& what) const {
  return ValueAtDefaults(m_, Expression(node, what), MarkOf(node), what);
}

PointRef SectionReader::Point(const YAML::Node& node, const std::string& what) const {
  const std::string text = Scalar(node, what);
  const auto dot = text.find('.');
  if (dot == std::string::npos) Fail(node, what + ": '" + text + "' must name a link point as link.point");
  const std::string link = text.substr(0, dot), point = text.substr(dot + 1);
  for (size_t i = 0; i < m_.links.size(); ++i) {
    if (m_.links[i].name != link) continue;
    const int k = m_.links[i].FindPoint(point);
    if (k < 0) {
      std::string list;
      for (const auto& pt : m_.links[i].points) list += (list.empty() ? "" : ", ") + pt.name;
      Fail(node, what + ": link '" + link + "' has no point '" + point + "'; its points are: " + list);
    }
    return {static_cast<int>(i), k};
  }
  std::string list;
  for (const auto& l : m_.links) list += (list.empty() ? "" : ", ") + l.name;
  Fail(node, what + ": unknown link '" + link + "'; the links are: " + list);
}

PointRef SectionReader::ContactPoint(const YAML::Node& node) const {
  if (!node.IsScalar()) return {};
  const std::string text = node.as<std::string>();
  const auto dot = text.find('.');
  if (dot == std::string::npos || text.substr(dot + 1) != "contact") return {};
  for (size_t k = 0; k < m_.joints.size(); ++k)
    if (m_.joints[k].name == text.substr(0, dot) && m_.joints[k].type() == JointType::kRoll)
      return {m_.joints[k].link_b, -1, static_cast<int>(k)};
  return {};
}

int SectionReader::LinkIndex(const YAML::Node& node, const std::string& what) const {
  const std::string text = Scalar(node, what);
  for (size_t i = 0; i < m_.links.size(); ++i)
    if (m_.links[i].name == text) return static_cast<int>(i);
  std::string list;
  for (const auto& l : m_.links) list += (list.empty() ? "" : ", ") + l.name;
  Fail(node, what + ": unknown link '" + text + "'; the links are: " + list);
}

SourceMark SectionReader::KeyMark(const YAML::Node& value) const {
  auto it = keymarks_.find(value.Mark().pos);
  return it == keymarks_.end() ? MarkOf(value) : it->second;
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
  SectionReader r(&m);
  const auto entries = r.Entries(root, "the model", &ModelKeys());
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
    ReadParameters(r, get("parameters"));
    ReadLinks(r, get("links"));
    ReadJoints(r, get("joints"));
    ReadInputs(r, get("inputs"));
    ReadGravity(r, get("gravity"));
    ReadLoads(r, get("loads"));
    ReadSprings(r, get("springs"));
    ReadFriction(r, get("friction"));
    ReadOutputs(r, get("outputs"));
    ReadAssembly(r, get("assembly"));
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
