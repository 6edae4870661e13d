// The `design` section (issue 27): the free parameters the generated code differentiates its
// outputs with respect to (EvalDesignDerivatives: dphi/dp, the points' dr_P/dp, dK/dp, ...).
//   design: [a, b, c]                  # short form
//   design: {parameters: [a, b, c]}
//   design: {parameters: all}          # every free parameter, in file order
//   design: {parameters: [a, b], quantities: [positions, checks]}
//                                      # only these derivatives (default: every one the
//                                      # outputs have: positions, checks, statics, dynamics)
// A derived parameter cannot be one (it follows the free ones it is made of: name those), nor a
// parameter inside a cam's law (see ReadDesign).
#include <map>
#include <string>
#include <vector>

#include "model/reader.h"

namespace mechgen {

const KeyTable& DesignKeys() {
  static const KeyTable table{
      "design",
      {{"parameters", "[name, ...] or all: the free parameters to differentiate with respect to", true},
       {"quantities",
        "[positions, checks, statics, dynamics]: the derivatives to emit (default: every one the outputs have; "
        "positions always)",
        false}}};
  return table;
}

namespace {

std::string FreeParameterList(const Model& m) {
  std::string list;
  for (const Parameter& p : m.params) list += (list.empty() ? "" : ", ") + p.name;
  return list.empty() ? "(none)" : list;
}

// The free parameters (index -> the cam joint's name) inside a cam's law (a segment's lift or
// duration) or its contour's period.
std::map<int, std::string> HiddenInCams(const Model& m) {
  std::map<int, std::string> hidden;
  for (const Joint& j : m.joints) {
    if (j.type() != JointType::kCam) continue;
    const CamData& c = j.Data<CamData>();
    std::vector<GiNaC::ex> inside{c.contour == CamData::Contour::kExpressions ? c.contour_period : GiNaC::ex(0)};
    for (const CamSegment& s : c.law) {
      inside.push_back(s.duration);
      inside.push_back(s.lift);
    }
    for (size_t i = 0; i < m.params.size(); ++i)
      for (const GiNaC::ex& e : inside)
        if (e.has(m.params[i].symbol)) hidden.emplace(static_cast<int>(i), j.name);
  }
  return hidden;
}

// `quantities: [...]`: which derivatives to emit, each one the outputs have.
void ReadDesignQuantities(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node.IsSequence() || node.size() == 0)
    r.Fail(node, "design quantities must be a non-empty list of positions, checks, statics, dynamics");
  m.design.checks = m.design.statics = m.design.dynamics = false;
  for (const auto& item : node) {
    const std::string name = r.Scalar(item, "design quantity");
    const Outputs& o = m.outputs;
    if (name == "positions") continue;  // always: the others are built on them
    if (name == "checks") {
      m.design.checks = true;
    } else if (name == "statics") {
      if (!o.Has(Quantity::kForces) && !o.Has(Quantity::kPotential))
        r.Fail(item, "design quantity 'statics' needs forces or potential in outputs.quantities");
      m.design.statics = true;
    } else if (name == "dynamics") {
      if (!o.Has(Quantity::kDynamics))
        r.Fail(item, "design quantity 'dynamics' needs dynamics in outputs.quantities");
      m.design.dynamics = true;
    } else {
      r.Fail(item, "unknown design quantity '" + name + "'; the quantities are positions, checks, statics, dynamics");
    }
  }
}

}  // namespace

void ReadDesign(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  m.design.mark = MarkOf(node);
  // A cam's law is a function the generated code calls (CamLaw_<joint>, its segments picked by
  // the angle): a parameter inside a segment's lift or duration is out of reach of the symbolic
  // derivative. Everything else of a cam is in Phi as written and is differentiated like any
  // other length: its start (base circle, roller and offset through it), phase, roller radius,
  // face angle, the follower's guide, and a contour given by expressions in u (a spline's points
  // are numbers). The contour's period is refused too: the contour must close over it, so it is
  // not free of the expressions.
  const auto hidden = HiddenInCams(m);
  // (yaml-cpp's Node::operator= writes through to the node it refers to: rebind with reset.)
  YAML::Node list;
  list.reset(node);
  if (node.IsMap()) {
    list.reset();
    for (const auto& [key, value] : r.Entries(node, "design", &DesignKeys())) {
      if (key == "parameters") list.reset(value);
      if (key == "quantities") ReadDesignQuantities(r, value);
    }
    if (!list) r.Fail(node, "design needs parameters: [name, ...] (or parameters: all)");
  }
  if (list.IsScalar() && r.Scalar(list, "design parameters") == "all") {
    // Every free parameter the derivation reaches: those inside a cam's law are left out.
    for (size_t i = 0; i < m.params.size(); ++i)
      if (!hidden.count(static_cast<int>(i))) m.design.params.push_back(static_cast<int>(i));
    if (m.design.params.empty())
      r.Fail(list, m.params.empty()
                       ? "design: all names no parameter: the model has no free parameters; add parameters or remove design"
                       : "design: all names no parameter: every free parameter is inside a cam's law; remove design");
    return;
  }
  if (!list.IsSequence())
    r.Fail(list, "design parameters must be a list of parameter names ([a, b]) or all");
  if (list.size() == 0) r.Fail(list, "design parameters is empty; name at least one parameter or remove design");
  for (const auto& item : list) {
    const std::string name = r.Scalar(item, "design parameter");
    int index = -1;
    for (size_t i = 0; i < m.params.size(); ++i)
      if (m.params[i].name == name) index = static_cast<int>(i);
    if (index < 0) {
      for (const DerivedParameter& d : m.derived)
        if (d.name == name)
          r.Fail(item, "design parameter '" + name +
                           "' is derived (it follows the free parameters of its expression); name those instead: " +
                           FreeParameterList(m));
      r.Fail(item, "design: unknown parameter '" + name + "'; the free parameters are " + FreeParameterList(m));
    }
    if (const auto it = hidden.find(index); it != hidden.end())
      r.Fail(item, "design parameter '" + name + "' is inside the law of cam '" + it->second +
                       "' (a segment's lift or duration, or the contour's period: the generated law function hides "
                       "it from the derivation); the cam's start, phase, roller, offset and links can be design "
                       "parameters");
    for (int other : m.design.params)
      if (other == index) r.Fail(item, "design parameter '" + name + "' is listed twice");
    m.design.params.push_back(index);
  }
}

}  // namespace mechgen
