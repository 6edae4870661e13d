// The `design` section (issue 27): its three forms read the parameters in the order given,
// every mistake is an error at its line and column saying what to change, and a model
// without it gets no EvalDesignDerivatives. Oracles: the model texts written here, and the
// symbolic derivative of the four-bar's loop differentiated by hand (GiNaC checks the
// difference is zero at random points, not against the code under test's own form).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "codegen/functions.h"
#include "joints/cam_profile.h"
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

// ---- The closed-form blocks' reach as design checks ----

std::string ShippedText(const std::string& name) {
  std::ifstream in(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The model text with parameter `name`'s default set to `value` ("  name: {value: ...").
std::string WithDefault(const std::string& text, const std::string& name, double value) {
  const std::string key = "\n  " + name + ":";
  const size_t at = text.find(key, text.find("\nparameters:"));
  EXPECT_NE(at, std::string::npos) << name;
  const size_t v = text.find("value:", at) + 6, end = text.find_first_of(",}", v);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, " %.17g", value);
  return text.substr(0, v) + buffer + text.substr(end);
}

// The reach checks of a model (by name) as functions of the parameters: margin and d/dp.
struct ReachChecks {
  Model m;
  std::vector<DesignCheck> checks;
  double Value(const std::string& name, const GiNaC::exmap& at, int d = -1) const {
    for (const DesignCheck& c : checks)
      if (c.name == name)
        return GiNaC::ex_to<GiNaC::numeric>((d < 0 ? c.margin : c.d[d]).subs(at).evalf()).to_double();
    ADD_FAILURE() << "no check " << name;
    return NAN;
  }
};

ReachChecks ChecksOf(const std::string& text) {
  ReachChecks r{LoadModelFromString(text, "r.yaml"), {}};
  const Analysis a = Validate(r.m);
  const Kinematics k = DeriveKinematics(r.m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(r.m, k);
  r.checks = DesignTable(r.m, t).checks;
  return r;
}

// What the generator says of the model at its defaults: "" where every block closes over the
// input's range, else its model error.
std::string GeneratorError(const std::string& text) {
  try {
    const Model m = LoadModelFromString(text, "r.yaml");
    const Analysis a = Validate(m);
    const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    const SymbolicTable t(m, k);
  } catch (const ModelError& e) {
    return e.message();
  }
  return "";
}

GiNaC::exmap At(const Model& m, const std::map<std::string, double>& values) {
  GiNaC::exmap at = m.Defaults();
  for (const Parameter& p : m.params)
    if (values.count(p.name)) at[p.symbol] = values.at(p.name);
  return at;
}

// The offset slider-crank (crank a, rod b, offset e; its rod's block is one angle): the rod
// reaches the slide all round iff b >= a + |e|, by hand: margins b - a + e and b - a - e, their
// derivatives (-1, 1, +-1). The generator's own check over the crank's range (sampled, then
// bisected: independent of the margins) fires exactly where a margin is negative.
TEST(DesignChecks, SliderCrankReachIsTheHandFormulaAndTheGeneratorsRangeCheck) {
  const std::string text = ShippedText("slider_crank");
  const ReachChecks r = ChecksOf(text);
  ASSERT_EQ(r.checks.size(), 2u);
  EXPECT_EQ(r.checks[0].name, "reach_max_block0");
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(0.2, 3.0), s(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    const double a = u(gen), b = u(gen), e = s(gen);
    const GiNaC::exmap at = At(r.m, {{"a", a}, {"b", b}, {"e", e}});
    EXPECT_NEAR(r.Value("reach_max_block0", at) + r.Value("reach_min_block0", at), 2 * (b - a), 1e-14);
    EXPECT_NEAR(std::min(r.Value("reach_max_block0", at), r.Value("reach_min_block0", at)), b - a - std::abs(e), 1e-14);
    for (const char* name : {"reach_max_block0", "reach_min_block0"}) {
      EXPECT_NEAR(r.Value(name, at, 0), -1, 1e-15);  // d/da
      EXPECT_NEAR(r.Value(name, at, 1), 1, 1e-15);   // d/db
    }
    EXPECT_NEAR(std::abs(r.Value("reach_max_block0", at, 2)), 1, 1e-15);  // d/de
    EXPECT_NEAR(r.Value("reach_max_block0", at, 2), -r.Value("reach_min_block0", at, 2), 1e-15);
  }
  // b = a + |e| -+ 1e-3 at a = 1, e = 0.4.
  for (const double b : {1.4 - 1e-3, 1.4 + 1e-3}) {
    const std::string error = GeneratorError(WithDefault(text, "b", b));
    const double margin = std::min(r.Value("reach_max_block0", At(r.m, {{"b", b}})),
                                   r.Value("reach_min_block0", At(r.m, {{"b", b}})));
    EXPECT_EQ(margin < 0, !error.empty()) << "b = " << b << ": margin " << margin << ", " << error;
    if (!error.empty()) EXPECT_NE(error.find("stops closing"), std::string::npos) << error;
  }
}

// The four-bar's coupler and rocker (an RRR dyad hanging from D and from the crank's B, |DB|
// from d - a to d + a): margins (b + c)^2 - (a + d)^2 and (d - a)^2 - (b - c)^2 by hand; the
// generator's range check fires exactly where one is negative (d moved across each zero).
TEST(DesignChecks, FourBarReachIsTheHandFormulaAndTheGeneratorsRangeCheck) {
  const std::string text = ShippedText("fourbar");
  const ReachChecks r = ChecksOf(text);
  std::mt19937 gen(6);
  std::uniform_real_distribution<double> u(0.5, 4.0);
  for (int trial = 0; trial < 5; ++trial) {
    const double a = u(gen), b = u(gen), c = u(gen), d = u(gen);
    const GiNaC::exmap at = At(r.m, {{"a", a}, {"b", b}, {"c", c}, {"d", d}});
    const double far = (b + c) * (b + c) - (a + d) * (a + d), near = (d - a) * (d - a) - (b - c) * (b - c);
    EXPECT_NEAR(r.Value("reach_far_block0", at), far, 1e-12 * std::max(1.0, std::abs(far)));
    EXPECT_NEAR(r.Value("reach_near_block0", at), near, 1e-12 * std::max(1.0, std::abs(near)));
    const double dfar[4] = {-2 * (a + d), 2 * (b + c), 2 * (b + c), -2 * (a + d)};
    const double dnear[4] = {-2 * (d - a), -2 * (b - c), 2 * (b - c), 2 * (d - a)};
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(r.Value("reach_far_block0", at, k), dfar[k], 1e-12 * std::max(1.0, std::abs(dfar[k])));
      EXPECT_NEAR(r.Value("reach_near_block0", at, k), dnear[k], 1e-12 * std::max(1.0, std::abs(dnear[k])));
    }
  }
  // a = 1, b = 3.5, c = 3: far is 0 at d = 5.5, near at d = 1.5.
  for (const double d : {5.5 - 1e-3, 5.5 + 1e-3, 1.5 - 1e-3, 1.5 + 1e-3}) {
    const std::string error = GeneratorError(WithDefault(text, "d", d));
    const GiNaC::exmap at = At(r.m, {{"d", d}});
    const double margin = std::min(r.Value("reach_far_block0", at), r.Value("reach_near_block0", at));
    EXPECT_EQ(margin < 0, !error.empty()) << "d = " << d << ": margin " << margin << ", " << error;
  }
}

// ---- A cam's curvature margin ----

// cam_roller (design: all = e, rb, rr, phase): its margin curvature_contact, the pitch curve's
// radius of curvature less the roller where it is smallest at the defaults, evaluated here with
// the law's values (EvalCamLaw) at other parameters. Oracles: the generator's own sampled
// minimum at the defaults and with the base circle moved (the cam's summary line, CheckCam),
// central differences of the margin; the phase does not move it.
TEST(DesignChecks, CamCurvatureMarginIsTheGeneratorsSampledMinimum) {
  const std::string text = ShippedText("cam_roller") + "\ndesign: all\n";
  const Model m = LoadModelFromString(text, "c.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(m, k);
  const DesignTable dt(m, t);
  ASSERT_EQ(dt.checks.size(), 1u);
  ASSERT_EQ(dt.checks[0].name, "curvature_contact");
  const CamLaw& law = k.cam_laws.at(0);
  struct LawValues : GiNaC::map_function {
    const Model& m;
    const CamLaw& law;
    LawValues(const Model& model, const CamLaw& l) : m(model), law(l) {}
    GiNaC::ex operator()(const GiNaC::ex& e) override {
      const GiNaC::ex mapped = e.map(*this);
      if (GiNaC::is_a<GiNaC::function>(mapped) && GiNaC::ex_to<GiNaC::function>(mapped).get_name() == "camlaw")
        return EvalCamLaw(m, law, GiNaC::ex_to<GiNaC::numeric>(mapped.op(2).evalf()).to_double(),
                          GiNaC::ex_to<GiNaC::numeric>(mapped.op(1)).to_int());
      return mapped;
    }
  } values(m, law);
  // The checks' locals (the cam's geometry at the law angle) substituted in order.
  GiNaC::exmap locals;
  for (const Statement& st : dt.checks_program)
    if (st.kind == Statement::Kind::kDefine) locals[st.symbol] = st.value.subs(locals);
  auto margin = [&](const std::map<std::string, double>& set, int d = -1) {
    GiNaC::exmap at = m.Defaults();
    for (const Parameter& p : m.params)
      if (set.count(p.name)) at[p.symbol] = set.at(p.name);
    const GiNaC::ex e = (d < 0 ? dt.checks[0].margin : dt.checks[0].d[d]).subs(locals).subs(at);
    return GiNaC::ex_to<GiNaC::numeric>(values(e).evalf()).to_double();
  };
  // The summary's "min radius of curvature of the pitch curve where convex X at ..." (sampled
  // every 0.5 deg: at most ~1e-4 above the refined minimum).
  const std::string& summary = k.cam_summary.at(0);
  const size_t at = summary.find("where convex ");
  ASSERT_NE(at, std::string::npos) << summary;
  const double sampled = std::stod(summary.substr(at + 13));
  const double m0 = margin({});
  EXPECT_LE(m0, sampled - 0.25 + 1e-12);
  EXPECT_GT(m0, sampled - 0.25 - 1e-4);
  EXPECT_GT(m0, 0);
  // The derivatives against central differences of the margin (e, rb, rr, phase; phase 0:
  // turning the law turns the cam, not its shape).
  const char* names[4] = {"e", "rb", "rr", "phase"};
  const double defaults[4] = {0.3, 1.0, 0.25, 0.1};
  for (int d = 0; d < 4; ++d) {
    const double h = 1e-6;
    const double diff = (margin({{names[d], defaults[d] + h}}) - margin({{names[d], defaults[d] - h}})) / (2 * h);
    EXPECT_NEAR(margin({}, d), diff, 1e-7) << names[d];
  }
  EXPECT_EQ(margin({}, 3), 0.0);
  // The zero in the base circle rb (smaller: tighter), bracketed and bisected.
  // Away from the defaults the margin holds the law angle u*: against the generator's own
  // sampled minimum of the model with the base circle moved (an upper bound of the minimum,
  // exact to second order in the change).
  for (const double rb : {0.9, 1.1}) {
    const Model moved = LoadModelFromString(WithDefault(text, "rb", rb), "c.yaml");
    const Analysis b = Validate(moved);
    const Kinematics km = DeriveKinematics(moved, b.topology, &b.coordinates, &b.cams);
    const std::string& line = km.cam_summary.at(0);
    const double sampled_there = std::stod(line.substr(line.find("where convex ") + 13));
    EXPECT_NEAR(margin({{"rb", rb}}), sampled_there - 0.25, 1e-3) << "rb = " << rb;
  }
  // With only these parameters the margin does not reach 0 (rb + rr > e bounds rb below; the
  // pitch curve grows with the roller): at the smallest base circle it is still positive, as
  // the generator, which accepts that cam.
  EXPECT_GT(margin({{"rb", 0.06}}), 0);
  EXPECT_EQ(GeneratorError(WithDefault(text, "rb", 0.06)), "");
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
