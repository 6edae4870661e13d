// The `outputs` section: the set of quantities the generated code computes, and the points
// of interest (OutputKeys). `order: 0|1|2` is shorthand for the quantities {}, {K}, {K, L};
// `scene: true|false` adds or drops EvalScene.
#include <set>
#include <string>

#include "model/reader.h"

namespace mechgen {

const KeyTable& OutputKeys() {
  static const KeyTable table{
      "outputs",
      {{"order", "shorthand: 0 positions, 1 + velocity coefficients K, 2 + centripetal coefficients L (default 2)",
        false},
       {"quantities", "[K, L, scene, forces, potential, dynamics, shaking]: the requested quantities, instead of order and "
        "scene",
        false},
       {"reactions", "[joint, ...]: joints whose reactions are emitted (statics; needs forces)", false},
       {"points", "[link.P, <rolling joint>.contact, ...]: points of interest (r_P, K_P, L_P as requested)", false},
       {"scene", "emit EvalScene (every link point, for drawing; default true)", false}}};
  return table;
}

const char* QuantityName(Quantity q) {
  switch (q) {
    case Quantity::kK: return "K";
    case Quantity::kL: return "L";
    case Quantity::kScene: return "scene";
    case Quantity::kForces: return "forces";
    case Quantity::kPotential: return "potential";
    case Quantity::kDynamics: return "dynamics";
    case Quantity::kShaking: return "shaking";
  }
  return "";
}

std::string QuantityList(const std::set<Quantity>& quantities) {
  std::string list;
  for (Quantity q : quantities) list += (list.empty() ? "" : " ") + std::string(QuantityName(q));
  return list;
}

void ReadOutputs(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  Outputs& out = m.outputs;
  if (!node) return;
  out.mark = MarkOf(node);
  bool has_order = false, has_scene = false, has_quantities = false;
  YAML::Node quantities;
  for (const auto& [key, value] : r.Entries(node, "outputs", &OutputKeys())) {
    if (key == "order") {
      const std::string o = r.Scalar(value, "order");
      if (o != "0" && o != "1" && o != "2")
        r.Fail(value, "order must be 0 (positions), 1 (+ velocity coefficients K) or 2 (+ "
                      "centripetal coefficients L)");
      out.quantities.erase(Quantity::kK);
      out.quantities.erase(Quantity::kL);
      if (o != "0") out.quantities.insert(Quantity::kK);
      if (o == "2") out.quantities.insert(Quantity::kL);
      has_order = true;
    } else if (key == "quantities") {
      quantities = value;
      has_quantities = true;
    } else if (key == "reactions") {
      if (!value.IsSequence()) r.Fail(value, "reactions must be a list of joint names");
      out.reactions_mark = MarkOf(value);
      for (const auto& jn : value) {
        const std::string name = r.Scalar(jn, "reaction joint");
        const int j = m.FindJoint(name);
        if (j < 0) r.Fail(jn, "reactions: unknown joint '" + name + "'");
        for (int other : out.reactions)
          if (other == j) r.Fail(jn, "joint '" + name + "' is listed twice in reactions");
        out.reactions.push_back(j);
      }
    } else if (key == "points") {
      if (!value.IsSequence()) r.Fail(value, "points must be a list of link.point names");
      for (const auto& pn : value) {
        PointRef p = r.ContactPoint(pn);
        if (p.contact_joint < 0) p = r.Point(pn, "output point");
        for (const auto& other : out.points)
          if (other == p) r.Fail(pn, "point '" + m.PointName(p) + "' is listed twice");
        out.points.push_back(p);
      }
    } else {
      const std::string s = r.Scalar(value, "scene");
      if (s != "true" && s != "false") r.Fail(value, "scene must be true or false");
      if (s == "true") out.quantities.insert(Quantity::kScene);
      else out.quantities.erase(Quantity::kScene);
      has_scene = true;
    }
  }
  if (has_quantities) {
    if (has_order || has_scene)
      r.Fail(quantities, "give the outputs either as quantities: [...] or by order: and scene:, not both");
    if (!quantities.IsSequence()) r.Fail(quantities, "quantities must be a list such as [K, L, scene]");
    out.quantities.clear();
    for (const auto& item : quantities) {
      const std::string q = r.Scalar(item, "quantity");
      Quantity which = Quantity::kK;
      bool known = false;
      for (Quantity k : {Quantity::kK, Quantity::kL, Quantity::kScene, Quantity::kForces, Quantity::kPotential,
                         Quantity::kDynamics, Quantity::kShaking})
        if (q == QuantityName(k)) which = k, known = true;
      if (!known)
        r.Fail(item, "unknown quantity '" + q +
                         "'; the quantities are K, L, scene, forces, potential, dynamics and shaking");
      if (!out.quantities.insert(which).second) r.Fail(item, "quantity '" + q + "' is listed twice");
    }
    // The shaking force and moment read the centres of mass' accelerations, which the
    // dynamics derives (its kinetostatics' d'Alembert forces).
    if (out.Has(Quantity::kShaking)) out.quantities.insert(Quantity::kDynamics);
    // The dynamics reads the centres of mass' velocity and centripetal coefficients, and
    // builds on the statics' applied forces and potential (its Statics struct holds the
    // kinetostatics).
    if (out.Has(Quantity::kDynamics))
      for (Quantity q : {Quantity::kK, Quantity::kL, Quantity::kForces, Quantity::kPotential}) out.quantities.insert(q);
    if (out.Has(Quantity::kL) && !out.Has(Quantity::kK))
      r.Fail(quantities, "L needs K (the centripetal coefficients are computed from the velocity coefficients); "
                         "add K");
  }
  if (out.Has(Quantity::kForces) && !out.Has(Quantity::kK))
    m.Fail(out.mark, "forces need K (the generalized forces are the loads' virtual work through the velocity "
                       "coefficients); add K");
  if (!out.reactions.empty() && !out.Has(Quantity::kForces))
    m.Fail(out.reactions_mark, "reactions need forces (the reactions balance the loads and the driving forces); add "
                               "forces to quantities");
  if ((out.Has(Quantity::kForces) || out.Has(Quantity::kPotential)) && !out.Has(Quantity::kDynamics) &&
      m.loads.empty() && m.springs.empty() && !m.has_gravity && m.friction.empty())
    m.Fail(out.mark, "forces and potential need something to act: add gravity, loads, springs or friction");
  if (!m.friction.empty() && !out.Has(Quantity::kForces))
    m.Fail(m.friction.front().mark, "friction needs forces in the outputs' quantities (the friction forces act "
                                    "through the reactions)");
  if (out.Has(Quantity::kDynamics)) {
    bool massive = false;
    for (const Link& l : m.links) massive = massive || (!l.ground && l.mass.given);
    if (!massive)
      m.Fail(out.mark, std::string(out.Has(Quantity::kShaking) ? "shaking" : "dynamics") +
                           " needs a moving link with mass: give a link mass: (and center:, inertia:) or point_masses:");
  }
  out.order = out.Order();
  out.scene = out.Has(Quantity::kScene);
}

}  // namespace mechgen
