// The dynamics sections (Paul ch. 6): `tables` (piecewise-linear functions for the loads, e.g.
// a motor's torque-speed curve) and `dampers` (TableKeys, DamperKeys); the check that loads
// reading time or velocities come with the `dynamics` quantity. Viscous joint friction is
// read with the friction (statics.cc).
#include <algorithm>
#include <cmath>

#include "joints/joint_kind.h"
#include "model/reader.h"

namespace mechgen {

namespace {

GiNaC::ex mtable_deriv(const GiNaC::ex& i, const GiNaC::ex& d, const GiNaC::ex& x, unsigned param) {
  if (param != 2) return 0;  // the table's index and the order are integers, not variables
  // The slope of a piecewise-linear function is piecewise constant: its derivative is 0
  // (between the knots, where it exists).
  return d.is_zero() ? mtable(i, 1, x) : GiNaC::ex(0);
}

}  // namespace

REGISTER_FUNCTION(mtable, derivative_func(mtable_deriv).latex_name("\\mathrm{table}"))

double EvalTable(const Table& t, double x, int d) {
  const size_t n = t.x.size();
  if (x <= t.x.front()) return d == 0 ? t.y.front() : 0.0;
  if (x >= t.x.back()) return d == 0 ? t.y.back() : 0.0;
  const size_t k = static_cast<size_t>(std::upper_bound(t.x.begin(), t.x.end(), x) - t.x.begin()) - 1;
  const double slope = (t.y[k + 1] - t.y[k]) / (t.x[k + 1] - t.x[k]);
  (void)n;
  return d == 0 ? t.y[k] + slope * (x - t.x[k]) : slope;
}

const KeyTable& TableKeys() {
  static const KeyTable table{
      "table",
      {{"x", "[x0, x1, ...]: the abscissae, strictly increasing (numbers; at least 2)", true},
       {"y", "[y0, y1, ...]: the values at x (numbers; as many as x)", true},
       {"doc", "one line, copied into the generated header", false}}};
  return table;
}

const KeyTable& DamperKeys() {
  static const KeyTable table{
      "damper",
      {{"between", "[link1.P, link2.Q]: a linear damper's two ends", false},
       {"joint", "a revolute joint: a torsional damper there (instead of between)", false},
       {"coefficient", "c: N s/m (linear) or N m s/rad (torsional), >= 0", true}}};
  return table;
}

void ReadTables(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, spec] : r.Entries(node, "tables")) {
    Table t;
    t.name = name;
    t.mark = r.KeyMark(spec);
    CheckName(m, name, NameRole::kTable, t.mark);
    for (const Parameter& p : m.params)
      if (p.name == name) m.Fail(t.mark, "table name '" + name + "' is a parameter's name; rename one");
    if (!spec.IsMap()) r.Fail(spec, "table '" + name + "' must be {x: [x0, x1, ...], y: [y0, y1, ...]}");
    for (const auto& entry : r.Entries(spec, "table '" + name + "'", &TableKeys())) (void)entry;
    const YAML::Node& s = spec;
    const std::string what = "table '" + name + "'";
    if (!s["x"]) r.Fail(spec, what + " needs x: [x0, x1, ...]");
    if (!s["y"]) r.Fail(spec, what + " needs y: [y0, y1, ...]");
    const YAML::Node& xs = s["x"];
    const YAML::Node& ys = s["y"];
    if (!xs.IsSequence() || xs.size() < 2) r.Fail(xs, what + ": x must be a list of at least 2 numbers");
    if (!ys.IsSequence()) r.Fail(ys, what + ": y must be a list of numbers, one per x");
    if (ys.size() != xs.size())
      r.Fail(ys, what + ": y has " + std::to_string(ys.size()) + " values and x " + std::to_string(xs.size()) +
                     "; give one y per x");
    for (size_t i = 0; i < xs.size(); ++i) {
      t.x.push_back(r.Number(xs[i], "x of " + what));
      if (i > 0 && !(t.x[i] > t.x[i - 1]))
        r.Fail(xs[i], what + ": x must increase strictly; x[" + std::to_string(i) + "] is not larger than x[" +
                          std::to_string(i - 1) + "]");
    }
    for (size_t i = 0; i < ys.size(); ++i) t.y.push_back(r.Number(ys[i], "y of " + what));
    if (s["doc"]) {
      t.doc = r.Scalar(s["doc"], "doc");
      const std::string why = FreeTextProblem(t.doc, false);
      if (!why.empty()) r.Fail(s["doc"], "doc " + why + ", and is copied into the generated header's comments; remove it");
    }
    m.tables.push_back(t);
  }
}

void ReadDampers(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, spec] : r.Entries(node, "dampers")) {
    Damper d;
    d.name = name;
    d.mark = r.KeyMark(spec);
    if (!IsIdentifier(name)) m.Fail(d.mark, "damper name '" + name + "' must be an identifier (letters, digits, _)");
    if (!spec.IsMap())
      r.Fail(spec, "damper '" + name + "' must be {between: [a.P, b.Q], coefficient: c} or {joint: J, coefficient: c}");
    for (const auto& entry : r.Entries(spec, "damper '" + name + "'", &DamperKeys())) (void)entry;
    const YAML::Node& s = spec;
    const std::string what = "damper '" + name + "'";
    if (static_cast<bool>(s["between"]) == static_cast<bool>(s["joint"]))
      r.Fail(spec, what + " needs exactly one of between: [link1.P, link2.Q] (linear) or joint: <revolute joint>");
    if (!s["coefficient"]) r.Fail(spec, what + " needs coefficient: c");
    d.coefficient = r.Expression(s["coefficient"], "coefficient of " + what);
    if (r.Number(s["coefficient"], "coefficient of " + what) < 0)
      r.Fail(s["coefficient"], "coefficient of " + what + " is negative; give c >= 0");
    if (s["between"]) {
      const YAML::Node& b = s["between"];
      if (!b.IsSequence() || b.size() != 2) r.Fail(b, what + ": between must be [link1.P, link2.Q]");
      d.a = r.Point(b[0], what);
      d.b = r.Point(b[1], what);
      if (d.a.link == d.b.link) r.Fail(b, what + " joins two points of one link: it never changes length; join two links");
      const std::string together = AlwaysTogether(m, d.a, d.b);
      if (!together.empty())
        r.Fail(b, what + " joins " + m.PointName(d.a) + " and " + m.PointName(d.b) + ", which are always at one "
                      "place (" + together + "): it has no length and no direction; join two points that move "
                      "apart, or use a torsional damper at the joint (joint: J)");
    } else {
      d.torsional = true;
      const std::string jn = r.Scalar(s["joint"], what);
      d.joint = m.FindJoint(jn);
      if (d.joint < 0) r.Fail(s["joint"], what + ": unknown joint '" + jn + "'; a torsional damper sits at a revolute joint");
      if (m.joints[d.joint].type() != JointType::kRevolute)
        r.Fail(s["joint"], what + ": joint '" + jn + "' is not revolute; a torsional damper sits at a revolute joint");
    }
    m.dampers.push_back(d);
  }
}

void CheckDynamicRefs(const Model& m) {
  const bool dynamic = m.outputs.Has(Quantity::kDynamics);
  if (!dynamic && !m.velocity_refs.empty())
    m.Fail(m.velocity_ref_mark, "load: '" + m.velocity_ref_name +
                                    "' is reserved for the dynamics (time t and velocities <coordinate>_dot); a static "
                                    "load depends on the parameters and the coordinates only (add dynamics to the "
                                    "outputs' quantities for a load of time or speed)");
  if (m.outputs.Has(Quantity::kForces) && m.at_rest_jump_mark.line)
    m.Fail(m.at_rest_jump_mark,
           m.at_rest_jump_load + ": " + m.at_rest_jump_call +
               " jumps where the velocity in it is 0, and the statics (EvalStatics: `forces`, which `dynamics` "
               "brings) holds the machine at rest, where such a load has no value (it would be taken on one side of "
               "its jump or dropped); switch the load with the coordinates instead, e.g. F*step(...) of the input "
               "angle over the working stroke (see Expressions in models/README.md)");
  if (!dynamic && !m.dampers.empty())
    m.Fail(m.dampers.front().mark, "dampers act in the dynamics only; add dynamics to the outputs' quantities");
}

}  // namespace mechgen
