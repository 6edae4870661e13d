// Template filling and file writing. See emit.h.
#include "emit.h"

#include <kainjow/mustache.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#ifndef MECHGEN_VERSION
#define MECHGEN_VERSION "0.0.0"
#endif

namespace mechgen {
namespace {

namespace mus = kainjow::mustache;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read template " + path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::string Number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

template <typename T, typename F>
std::string Join(const std::vector<T>& v, F f) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + f(v[i]);
  return s;
}

std::string Quote(const std::string& s) { return "\"" + s + "\""; }

// Data for the templates, remembering every key so that a template naming a value the
// generator does not provide is an error instead of an empty string.
class TemplateData {
 public:
  void Set(const std::string& key, const std::string& value) {
    keys_.insert(key);
    data_.set(key, value);
  }
  void Set(const std::string& key, bool value) {
    keys_.insert(key);
    data_.set(key, value ? mus::data::type::bool_true : mus::data::type::bool_false);
  }
  void Set(const std::string& key, int value) { Set(key, std::to_string(value)); }
  void SetList(const std::string& key, const std::vector<std::map<std::string, std::string>>& items,
               const std::set<std::string>& item_keys) {
    keys_.insert(key);
    for (const auto& k : item_keys) keys_.insert(k);
    mus::data list{mus::data::type::list};
    for (const auto& item : items) {
      mus::data obj{mus::data::type::object};
      for (const auto& [k, v] : item) obj.set(k, v);
      list.push_back(obj);
    }
    data_.set(key, list);
  }
  std::string Render(const std::string& path) const {
    const std::string text = ReadFile(path);
    static const std::regex tag(R"(\{\{\{?\s*[#^/&]?\s*([A-Za-z_][A-Za-z0-9_]*)\s*\}?\}\})");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), tag); it != std::sregex_iterator(); ++it) {
      const std::string key = (*it)[1];
      if (!keys_.count(key))
        throw std::runtime_error(path + ": placeholder '" + key + "' has no value in mechgen");
    }
    mus::mustache tmpl(text);
    if (!tmpl.is_valid()) throw std::runtime_error(path + ": " + tmpl.error_message());
    tmpl.set_custom_escape([](const std::string& s) { return s; });
    const std::string out = tmpl.render(data_);
    if (!tmpl.is_valid()) throw std::runtime_error(path + ": " + tmpl.error_message());
    return out;
  }

 private:
  mus::data data_{mus::data::type::object};
  std::set<std::string> keys_;
};

std::vector<std::map<std::string, std::string>> Lines(const std::string& text) {
  std::vector<std::map<std::string, std::string>> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
    out.push_back({{"line", line}});
  }
  while (!out.empty() && out.back().at("line").empty()) out.pop_back();
  return out;
}

std::string BodyText(const Body& b, const std::string& preamble) {
  std::ostringstream os;
  os << "  // Total ops: " << b.ops.Text() << "; intermediate terms: " << b.num_temps << "\n";
  os << preamble;
  os << b.text;
  std::string s = os.str();
  if (!s.empty() && s.back() == '\n') s.pop_back();
  return s;
}

// Indents by brace depth (the position solver nests loops and blocks).
std::string Reindent(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  int depth = 1;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos) {
      out += "\n";
      continue;
    }
    line = line.substr(first);
    std::string code = line.substr(0, line.find("//"));
    if (!code.empty() && code[0] == '}') --depth;
    out += std::string(2 * depth, ' ') + line + "\n";
    for (char c : code) depth += c == '{' ? 1 : c == '}' ? -1 : 0;
    if (!code.empty() && code[0] == '}') ++depth;
  }
  return out;
}

}  // namespace

EmittedModel Emit(const Model& m, const Topology& t, const Kinematics& k, const Derivation& d,
                  const std::vector<TransmissionAngle>& transmission, CxxPrinter* printer,
                  const std::string& templates_dir) {
  EmittedModel out;
  const std::string math = "  using std::abs;\n  using std::atan2;\n  using std::cos;\n  using std::pow;\n"
                           "  using std::sin;\n  using std::sqrt;\n";
  const Body phi = EmitProgram(d.phi, printer);
  Body coeffs = EmitProgram(d.coefficients, printer);
  coeffs.ops.calls += d.coefficient_trig_calls;  // sin and cos in its prologue (when trig is nullptr)
  const Body scene = EmitProgram(d.scene, printer);
  const Body det = EmitProgram(d.det, printer);
  const Body mu = EmitProgram(TransmissionProgram(transmission), printer);
  Body positions;
  for (const Program& block : d.positions) {
    const Body b = EmitProgram(block, printer);
    positions.text += b.text;
    positions.ops += b.ops;
    positions.num_temps += b.num_temps;
  }
  positions.text = Reindent(positions.text);
  positions.ops.calls += d.position_trig_calls;
  out.phi_ops = phi.ops;
  out.coefficient_ops = coeffs.ops;
  out.scene_ops = scene.ops;
  out.transmission_ops = mu.ops;

  TemplateData data;
  std::string upper = m.name;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  data.Set("version", std::string(MECHGEN_VERSION));
  data.Set("model_file", std::filesystem::path(m.file).filename().string());
  data.Set("name", m.name);
  data.Set("NAME", upper);
  data.Set("title", m.title.empty() ? m.name : m.title);
  data.SetList("description", Lines(m.description), {"line"});
  data.Set("num_links", static_cast<int>(m.links.size()));
  data.Set("num_moving_links", static_cast<int>(m.links.size()) - 1);
  data.Set("num_joints", static_cast<int>(m.joints.size()));
  data.Set("num_loops", static_cast<int>(t.loops.size()));
  data.Set("mobility", t.loop_mobility);
  std::vector<std::map<std::string, std::string>> loops, qdoc, phidoc, rows, pdoc, params, inst;
  for (size_t i = 0; i < t.loops.size(); ++i)
    loops.push_back({{"index", std::to_string(i + 1)}, {"text", t.loops[i].Text(m)}});
  data.SetList("loops", loops, {"index", "text"});
  for (int i = 0; i < k.nq(); ++i)
    qdoc.push_back({{"index", std::to_string(i)}, {"name", k.q[i].name}, {"what", k.q[i].what}});
  for (int i = 0; i < k.nphi(); ++i)
    phidoc.push_back({{"index", std::to_string(i)}, {"name", k.phi[i].name}, {"what", k.phi[i].what}});
  data.SetList("q_doc", qdoc, {"index", "name", "what"});
  data.SetList("phi_doc", phidoc, {"index", "name", "what"});
  for (int i = 0; i < k.nc(); ++i) {
    CxxPrinter plain;  // GiNaC's own term order varies between runs: print ours
    for (const CamLaw& law : k.cam_laws) plain.NameCamLaw(m.joints[law.joint].Data<CamData>().index, law.cxx_name);
    for (const CamContour& c : k.cam_contours) plain.NameCamContour(m.joints[c.joint].Data<CamData>().index, c.cxx_name);
    for (const auto& c : k.q) plain.Name(c.symbol, c.name);
    for (const auto& c : k.phi) plain.Name(c.symbol, c.name);
    for (const auto& p : m.params) plain.Name(p.symbol, p.name);
    std::string text = plain.Print(k.Phi[i]);
    text = std::regex_replace(text, std::regex(R"(Scalar\(([^()]*)\))"), "$1");
    rows.push_back({{"index", std::to_string(i)}, {"text", text + "   [" + k.Phi_source[i] + "]"}});
  }
  data.SetList("phi_rows", rows, {"index", "text"});
  data.Set("nq", k.nq());
  data.Set("nphi", k.nphi());
  data.Set("nc", k.nc());
  data.Set("order", m.outputs.order);
  static const char* kOrderText[] = {"positions", "positions, velocity coefficients K",
                                     "positions, velocity coefficients K, centripetal coefficients L"};
  data.Set("order_text", std::string(kOrderText[m.outputs.order]));
  for (const auto& n : k.point_names) pdoc.push_back({{"name", n}});
  data.SetList("points_doc", pdoc, {"name"});
  data.Set("solve_strategy", d.strategy);
  data.Set("op_counts", "EvalPhi " + phi.ops.Text() + "; SolvePositions " + positions.ops.Text() +
                            " (per Newton iteration for Newton blocks); EvalCoefficients " + coeffs.ops.Text() +
                            (m.outputs.scene ? "; EvalScene " + scene.ops.Text() : "") +
                            (transmission.empty() ? "" : "; EvalTransmissionAngles " + mu.ops.Text()));
  data.Set("numeric_solve", d.numeric_solve);
  data.Set("num_points", static_cast<int>(k.points.size()));
  data.Set("num_scene_points", static_cast<int>(k.scene.size()));
  for (const Parameter& p : m.params)
    params.push_back({{"name", p.name}, {"value", Number(p.value)}, {"comment", p.doc}});
  data.SetList("params", params, {"name", "value", "comment"});
  const int order = m.outputs.order;
  const bool has_points = !k.points.empty();
  data.Set("has_K", order >= 1);
  data.Set("has_L", order >= 2);
  data.Set("has_points", has_points);
  data.Set("has_K_P", has_points && order >= 1);
  data.Set("has_L_P", has_points && order >= 2);
  data.Set("has_scene", m.outputs.scene && !k.scene.empty());
  const std::string unused = "  (void)p;\n  (void)q;\n  (void)phi;\n";
  data.Set("phi_body", BodyText(phi, math + unused));
  data.Set("coefficients_body", BodyText(coeffs, math + unused + "  (void)out;\n  (void)trig;\n"));
  data.Set("scene_body", BodyText(scene, math + unused));
  data.Set("det_body", BodyText(det, math + unused));
  data.Set("has_transmission", !transmission.empty());
  data.Set("num_transmission", static_cast<int>(transmission.size()));
  data.Set("transmission_body", BodyText(mu, math + unused));
  std::vector<std::map<std::string, std::string>> mu_doc;
  for (size_t i = 0; i < transmission.size(); ++i)
    mu_doc.push_back({{"index", std::to_string(i)}, {"text", transmission[i].Text()}});
  data.SetList("transmission_doc", mu_doc, {"index", "text"});
  data.Set("transmission_joints", Join(transmission, [](const TransmissionAngle& a) { return Quote(a.joint); }));
  data.Set("positions_body", BodyText(positions, math + "  using std::acos;\n  using std::floor;\n" +
                                                     "  Vec<Scalar, Sizes::kNphi>& phi = *phi_io;\n  int iterations = 0;\n" +
                                                     "  // tolerance <= 0: 1e-12 (model units), 1e-5 for float\n" +
                                                     "  const Scalar tol = tolerance > Scalar(0) ? tolerance : Scalar(sizeof(Scalar) <= 4 ? 1e-5 : 1e-12);\n  (void)tol;\n" +
                                                     unused + "  (void)modes;\n  (void)max_iterations;\n  (void)tolerance;\n  (void)trig;\n") +
                                "\n  return {SolveStatus::kConverged, -1, iterations, Scalar(0)};");
  // Cams: the law's function and the cam's geometry (pressure angle, curvature, profile).
  std::string cams;
  std::vector<std::map<std::string, std::string>> cam_doc;
  for (size_t c = 0; c < k.cam_laws.size(); ++c) {
    const Joint& j = m.joints[k.cam_laws[c].joint];
    cams += EmitCamLaw(m, k.cam_laws[c], printer) + "\n";
    const Body g = EmitProgram(k.cam_geometry[c].program, printer);
    cams += "/**\n * \\brief Cam '" + j.name +
            "' at cam angle x (the cam's angle relative to the carrier, radians): the\n"
            " * follower's coordinate y = start + law(x - phase) and its x-derivatives, the pressure angle,\n"
            " * the radii of curvature of the pitch curve and of the profile, and the contact point on\n"
            " * the profile in the cam's frame (see CamState).\n */\n"
            "template <typename Scalar>\nvoid EvalCam_" + j.name +
            "(const Params<Scalar>& p, const Scalar& x, CamState<Scalar>* out) {\n" +
            BodyText(g, math + "  (void)p;\n") + "\n}\n";
    if (c + 1 < k.cam_laws.size()) cams += "\n";
    for (const auto& l : Lines(k.cam_summary[c])) cam_doc.push_back(l);
  }
  std::string contours;
  for (const CamContour& c : k.cam_contours) {
    if (m.joints[c.joint].Data<CamData>().contour == CamData::Contour::kSpline) contours += EmitCamContour(m, c) + "\n";
    for (const auto& l : Lines(c.summary)) cam_doc.push_back(l);
  }
  data.Set("contour_functions", contours);
  data.Set("has_cams", !cams.empty());
  data.Set("cam_functions", cams);
  data.SetList("cam_doc", cam_doc, {"line"});
  std::vector<std::map<std::string, std::string>> blocks_doc;
  for (size_t i = 0; i < d.blocks.size(); ++i)
    blocks_doc.push_back({{"index", std::to_string(i)}, {"text", d.blocks[i].Describe(k)}});
  data.SetList("blocks_doc", blocks_doc, {"index", "text"});
  data.Set("num_blocks", static_cast<int>(d.blocks.size()));
  data.Set("default_modes", Join(d.blocks, [](const Block& b) { return std::to_string(b.default_mode); }));
  data.Set("block_closed_form", Join(d.blocks, [](const Block& b) {
             return std::string(b.solve == BlockSolve::kNewton ? "false" : "true");
           }));
  auto names = [](const std::vector<Coordinate>& v) { return Join(v, [](const Coordinate& c) { return Quote(c.name); }); };
  auto angles = [](const std::vector<Coordinate>& v) {
    return Join(v, [](const Coordinate& c) { return std::string(c.is_angle ? "true" : "false"); });
  };
  auto numbers = [](const std::vector<double>& v) { return Join(v, [](double x) { return Number(x); }); };
  data.Set("q_names", names(k.q));
  data.Set("phi_names", names(k.phi));
  data.Set("q_is_angle", angles(k.q));
  data.Set("phi_is_angle", angles(k.phi));
  data.Set("point_names", Join(k.point_names, Quote));
  data.Set("link_names", Join(m.links, [](const Link& l) { return Quote(l.name); }));
  data.Set("ground_index", m.ground);
  data.Set("scene_point_names", Join(k.scene_names, Quote));
  data.Set("scene_point_links", Join(k.scene_link, [](int l) { return std::to_string(l); }));
  data.Set("assembly_q", numbers(k.assembly_q));
  data.Set("assembly_phi", numbers(k.assembly_phi));
  data.Set("q_min", numbers(k.q_min));
  data.Set("q_max", numbers(k.q_max));
  for (const char* s : {"double", "float"}) inst.push_back({{"scalar", s}});
  data.SetList("instances", inst, {"scalar"});

  out.header = data.Render(templates_dir + "/mechanism.h.mustache");
  out.source = data.Render(templates_dir + "/mechanism.cc.mustache");
  return out;
}

bool WriteFiles(const std::string& dir, const std::string& name, const EmittedModel& e,
                std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    *error = "cannot create directory " + dir + ": " + ec.message();
    return false;
  }
  const std::pair<std::string, const std::string*> files[] = {{name + ".h", &e.header},
                                                              {name + ".cc", &e.source}};
  std::vector<fs::path> temps;
  for (const auto& [file, text] : files) {
    const fs::path tmp = fs::path(dir) / (file + ".tmp");
    std::ofstream os(tmp, std::ios::binary);
    os << *text;
    os.close();
    if (!os) {
      *error = "cannot write " + tmp.string();
      for (const auto& t : temps) fs::remove(t, ec);
      fs::remove(tmp, ec);
      return false;
    }
    temps.push_back(tmp);
  }
  for (size_t i = 0; i < temps.size(); ++i) {
    fs::rename(temps[i], fs::path(dir) / files[i].first, ec);
    if (ec) {
      *error = "cannot rename " + temps[i].string() + ": " + ec.message();
      return false;
    }
  }
  return true;
}

}  // namespace mechgen
