// EvalAppliedLoads: the applied loads, springs and weights of the statics (StaticsTable::marks, made
// in symbolic/forces.cc with the items whose virtual work gives Q) at a configuration, for a
// force diagram (mechgen/statics/svg.h), with the Model constants that name them. Emitted
// only for a model with a scene and statics and at least one load, spring or weight.
#include "codegen/functions.h"

namespace mechgen {
namespace {

using Dir = Argument::Direction;
using Kind = StaticsTable::Mark::Kind;

std::string N(int i) { return std::to_string(i); }

std::string Join(const std::vector<StaticsTable::Mark>& marks, std::string (*f)(const StaticsTable::Mark&)) {
  std::string s;
  for (size_t i = 0; i < marks.size(); ++i) s += (i ? ", " : "") + f(marks[i]);
  return s;
}

bool Emitted(const Model& m, const Kinematics& k, const StaticsTable& st) {
  return m.outputs.scene && !k.scene.empty() && st.layout.any && !st.marks.empty();
}

}  // namespace

FunctionSpec EvalAppliedLoadsSpec(const Model& m, const Kinematics& k, const StaticsTable& st, CxxPrinter* printer) {
  FunctionSpec f;
  if (!Emitted(m, k, st)) return f;
  const int n = static_cast<int>(st.marks.size());
  f.name = "EvalAppliedLoads";
  f.model_member = "AppliedLoads";
  f.instantiate = false;
  f.doc = {"\\brief The applied loads, springs and weights at a configuration, as a force diagram draws them",
           "(Model::kAppliedLoadNames, kAppliedLoadKind, kAppliedLoadUnits): column i of *out is",
           "(x, y, x_b, y_b, F_x, F_y, value) in the fixed frame, as EvalStatics() takes them:",
           "  force load (kind 0): (x, y) its point of application, (F_x, F_y) its force (N), value 0;",
           "  torque load (kind 1): (x, y) its link's pivot (first revolute joint, to the ground first;",
           "    else the link's origin), value its torque (N m, counter-clockwise +), F 0;",
           "  linear spring (kind 2): (x, y) and (x_b, y_b) its ends a and b, value its tension",
           "    F0 + k (l - l0) (N, + pulling the ends together), (F_x, F_y) its force on end a;",
           "  torsional spring (kind 3): (x, y) its joint, value its torque on the joint's second link",
           "    -k (theta_b - theta_a - free angle) (N m, counter-clockwise +), F 0;",
           "  weight (kind 4, \"W_<link>\"): (x, y) the link's centre of mass (its point masses",
           "    included), (F_x, F_y) its weight m g (N), value |m g|.",
           "(x_b, y_b) = (x, y) but for a linear spring. Loads that read velocities or time are taken at",
           "rest, as in EvalStatics()."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("Mat<Scalar, 7, " + N(n) + ">*", "out", Dir::kOut,
                       "out->col(i) = load, spring or weight i (kAppliedLoadNames); not nullptr.",
                       "7 x kNumAppliedLoads"));
  Program P;
  for (int i = 0; i < n; ++i) {
    const StaticsTable::Mark& mark = st.marks[i];
    const GiNaC::ex column[7] = {mark.at[0], mark.at[1], mark.b[0], mark.b[1], mark.F[0], mark.F[1], mark.value};
    for (int r = 0; r < 7; ++r) P.push_back(Store("(*out)(" + N(r) + ", " + N(i) + ")", column[r]));
  }
  f.body = {FinishAppliedProgram(P, st, printer)};
  f.model_constants =
      "  /// The applied loads, springs and weights of EvalAppliedLoads (Model::AppliedLoads), the\n"
      "  /// model's loads, then its springs, then its links' weights: name, kind (0 force load, 1\n"
      "  /// torque load, 2 linear spring, 3 torsional spring, 4 weight) and the unit of its force or\n"
      "  /// torque.\n"
      "  static constexpr int kNumAppliedLoads = " + N(n) + ";\n"
      "  static constexpr std::array<const char*, kNumAppliedLoads> kAppliedLoadNames{ " +
      Join(st.marks, [](const StaticsTable::Mark& a) { return "\"" + a.name + "\""; }) + " };\n"
      "  static constexpr std::array<int, kNumAppliedLoads> kAppliedLoadKind{ " +
      Join(st.marks, [](const StaticsTable::Mark& a) { return N(static_cast<int>(a.kind)); }) + " };\n"
      "  static constexpr std::array<const char*, kNumAppliedLoads> kAppliedLoadUnits{ " +
      Join(st.marks,
           [](const StaticsTable::Mark& a) {
             return std::string(a.kind == Kind::kTorque || a.kind == Kind::kTorsionalSpring ? "\"N m\"" : "\"N\"");
           }) +
      " };\n";
  return f;
}

}  // namespace mechgen
