// The `design` section (issue 27): its three forms read the parameters in the order given,
// every mistake is an error at its line and column saying what to change, and a model
// without it gets no EvalDesignDerivatives. Oracles: the model texts written here, and the
// symbolic derivative of the four-bar's loop differentiated by hand (GiNaC checks the
// difference is zero at random points, not against the code under test's own form).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "codegen/functions.h"
#include "model/model.h"
#include "symbolic/design.h"
#include "symbolic/table.h"

namespace mechgen {
namespace {

const std::string kFourBar = R"(name: t
parameters:
  a: 1.0
  b: 3.5
  c: 3.0
  d: 4.0
  half_d: {derived: d/2}
links:
  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}}
  coupler: {points: {B: [0, 0], C: [b, 0], P: [half_d, 1]}}
  rocker:  {points: {D: [0, 0], C: [c, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  B: {revolute: [crank.B, coupler.B]}
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
inputs:
  - {joint: A, range: [0, 360*deg]}
outputs:
  points: [coupler.P]
assembly: {theta_crank: 90*deg, theta_coupler: 30*deg, theta_rocker: 110*deg}
)";

std::string With(const std::string& design) { return kFourBar + design + "\n"; }

std::string ErrorOf(const std::string& text) {
  try {
    LoadModelFromString(text, "t.yaml");
  } catch (const ModelError& e) {
    return std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ": " + e.message();
  }
  return "";
}

std::vector<std::string> Names(const Model& m) {
  std::vector<std::string> out;
  for (int i : m.design.params) out.push_back(m.params[i].name);
  return out;
}

TEST(DesignSection, ShortLongAndAllFormsReadTheParametersInOrder) {
  EXPECT_EQ(Names(LoadModelFromString(With("design: [c, a]"), "t.yaml")), (std::vector<std::string>{"c", "a"}));
  EXPECT_EQ(Names(LoadModelFromString(With("design: {parameters: [b]}"), "t.yaml")), std::vector<std::string>{"b"});
  EXPECT_EQ(Names(LoadModelFromString(With("design: {parameters: all}"), "t.yaml")),
            (std::vector<std::string>{"a", "b", "c", "d"}));  // the free ones: half_d is derived
  EXPECT_FALSE(LoadModelFromString(kFourBar, "t.yaml").design.any());
}

TEST(DesignSection, MistakesAreErrorsAtTheirPlace) {
  const int line = 1 + static_cast<int>(std::count(kFourBar.begin(), kFourBar.end(), '\n'));
  const std::string at = std::to_string(line) + ":";
  EXPECT_EQ(ErrorOf(With("design: [a, e]")),
            at + "13: design: unknown parameter 'e'; the free parameters are a, b, c, d");
  EXPECT_EQ(ErrorOf(With("design: [half_d]")),
            at + "10: design parameter 'half_d' is derived (it follows the free parameters of its expression); "
                 "name those instead: a, b, c, d");
  EXPECT_EQ(ErrorOf(With("design: [a, b, a]")), at + "16: design parameter 'a' is listed twice");
  EXPECT_EQ(ErrorOf(With("design: []")), at + "9: design parameters is empty; name at least one parameter or remove design");
  EXPECT_EQ(ErrorOf(With("design: a")), at + "9: design parameters must be a list of parameter names ([a, b]) or all");
  EXPECT_EQ(ErrorOf(With("design: {params: [a]}")).substr(0, at.size()), at);
  EXPECT_NE(ErrorOf(With("design: {params: [a]}")).find("params"), std::string::npos);
}

// A cam's law (its segments' lifts and durations) is a function of the generated code: a
// parameter inside it is refused when named and left out of `all`; the cam's start (base circle,
// roller, offset), phase and roller radius are in Phi as written and are design parameters.
// Oracle: cam_roller.yaml's own text (h is the only parameter of its law).
TEST(DesignSection, ACamsLawParametersAreRefusedTheRestAccepted) {
  const std::string cam = std::string(MECHGEN_SOURCE_DIR) + "/models/cam_roller.yaml";
  Model m = LoadModel(cam);  // loads without a design section
  EXPECT_FALSE(m.design.any());
  std::ifstream in(cam);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(Names(LoadModelFromString(text + "\ndesign: all\n", "c.yaml")),
            (std::vector<std::string>{"e", "rb", "rr", "phase"}));
  EXPECT_EQ(Names(LoadModelFromString(text + "\ndesign: [rr, phase]\n", "c.yaml")),
            (std::vector<std::string>{"rr", "phase"}));
  const std::string e = ErrorOf(text + "\ndesign: [e, h]\n");
  EXPECT_NE(e.find("design parameter 'h' is inside the law of cam 'contact'"), std::string::npos) << e;
  EXPECT_EQ(e.substr(e.find(':') + 1, 3), "13:") << e;  // at h, the list's second item
}

// The table's dphi/dp of the four-bar against the loop differentiated by hand:
// b n3 dtheta_3 - c n4 dtheta_4 = -w, so dtheta_3 = (w . u4)/(b sin(t3 - t4)), with
// w = u2, u3, -u4, -e_x for a, b, c, d. Compared at random (theta_2, theta_3, theta_4): the
// identity holds for any angles (the derivation never used the loop's closure for dphi/dp).
TEST(DesignTable, FourBarDphiDpIsTheHandFormula) {
  const Model m = LoadModelFromString(With("design: [a, b, c, d]"), "t.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(m, k);
  const DesignTable dt(m, t);
  ASSERT_EQ(dt.nd(), 4);
  // Substitute the program's locals into the results (the program is straight-line here).
  GiNaC::exmap locals;
  for (const Statement& s : dt.program)
    if (s.kind == Statement::Kind::kDefine) locals[s.symbol] = s.value.subs(locals);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 5; ++trial) {
    const double t2 = u(gen), t3 = u(gen), t4 = u(gen);
    GiNaC::exmap at = m.Defaults();
    at[k.q[0].symbol] = t2;
    at[k.phi[0].symbol] = t3;
    at[k.phi[1].symbol] = t4;
    const double c2 = std::cos(t2), s2 = std::sin(t2), c3 = std::cos(t3), s3 = std::sin(t3), c4 = std::cos(t4),
                 s4 = std::sin(t4), s34 = std::sin(t3 - t4);
    const double w[4][2] = {{c2, s2}, {c3, s3}, {-c4, -s4}, {-1, 0}};
    for (int d = 0; d < 4; ++d) {
      const double dt3 = (w[d][0] * c4 + w[d][1] * s4) / (3.5 * s34), dt4 = (w[d][0] * c3 + w[d][1] * s3) / (3.0 * s34);
      auto value = [&](const GiNaC::ex& e) {
        return GiNaC::ex_to<GiNaC::numeric>(e.subs(locals).subs(at).evalf()).to_double();
      };
      EXPECT_NEAR(value(dt.dphi_dp[0][d]), dt3, 1e-12 * std::max(1.0, std::abs(dt3))) << d;
      EXPECT_NEAR(value(dt.dphi_dp[1][d]), dt4, 1e-12 * std::max(1.0, std::abs(dt4))) << d;
    }
  }
}

TEST(DesignTable, NoDesignSectionNoFunction) {
  const Model m = LoadModelFromString(kFourBar, "t.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(m, k);
  const DesignTable dt(m, t);
  EXPECT_EQ(dt.nd(), 0);
  CxxPrinter printer;
  for (const FunctionSpec& f : BuildFunctions(m, k, t, {}, &printer, nullptr, nullptr, &dt))
    EXPECT_NE(f.name, "EvalDesignDerivatives");
}

}  // namespace
}  // namespace mechgen
