// The model format as users write it (issue 13): the exact function list of the expression
// language, derived parameters, separate namespaces for joints, links and parameters, a
// revolute joint over several links, the slot joint and named assembly modes. Oracles: the
// README's own text, closed forms computed here with <cmath>, and the same mechanism
// written the old way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "joints/joint_kind.h"
#include "symbolic/blocks.h"
#include "model/model.h"
#include "model/reader.h"

namespace mechgen {
namespace {

const std::string kReadme = std::string(MECHGEN_SOURCE_DIR) + "/models/README.md";

double Value(const GiNaC::ex& e, const Model& m) {
  return GiNaC::ex_to<GiNaC::numeric>(e.subs(m.Defaults()).evalf()).to_double();
}

// The error of loading `text`: "line:column: message" (or "" when it loads).
std::string ErrorOf(const std::string& text) {
  try {
    const Model m = LoadModelFromString(text, "t.yaml");
    Validate(m);
  } catch (const ModelError& e) {
    return std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ": " + e.message();
  }
  return "";
}

// "line:column:" of the first character of `marker` in `text` (searched from `from`): where
// the test knows the error must point.
std::string At(const std::string& text, const std::string& marker, size_t skip = 0) {
  const size_t at = text.find(marker);
  EXPECT_NE(at, std::string::npos) << marker;
  const size_t where = at + skip;
  const size_t line_start = text.rfind('\n', where == 0 ? 0 : where - 1);
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(where), '\n')) + 1;
  const size_t column = line_start == std::string::npos ? where + 1 : where - line_start;
  return std::to_string(line) + ":" + std::to_string(column) + ":";
}

TEST(ExpressionFunctions, TheReadmeListsExactlyTheAcceptedFunctions) {
  // The grammar's two lines:
  //   function   := sin cos ... (one argument)
  //               | atan2 (y, x) | min max (a, b) | ...
  // each group "names (arguments)" gives the names and, by its commas, their arity.
  std::ifstream in(kReadme);
  ASSERT_TRUE(in);
  const std::regex first(R"M(^function\s*:=\s*(.*)\(one argument\)\s*$)M");
  const std::regex group(R"M(\|?\s*([a-z0-9 ]+?)\s*\(([^()]*)\))M");
  std::string line;
  std::smatch match;
  bool found = false;
  while (std::getline(in, line)) {
    if (!std::regex_match(line, match, first)) continue;
    found = true;
    std::map<std::string, int> readme;
    std::istringstream one(match[1].str());
    for (std::string w; one >> w;) EXPECT_TRUE(readme.emplace(w, 1).second) << w;
    ASSERT_TRUE(std::getline(in, line));
    for (auto it = std::sregex_iterator(line.begin(), line.end(), group); it != std::sregex_iterator(); ++it) {
      const int arity = static_cast<int>(std::count((*it)[2].first, (*it)[2].second, ',')) + 1;
      std::istringstream names((*it)[1].str());
      for (std::string w; names >> w;) EXPECT_TRUE(readme.emplace(w, arity).second) << w;
    }
    std::map<std::string, int> code(ExpressionFunctions().begin(), ExpressionFunctions().end());
    EXPECT_EQ(readme, code);
  }
  EXPECT_TRUE(found) << "no 'function := ... (one argument)' line in models/README.md";
}

const char* kFourbar = R"M(name: fb
parameters:
  a: 1.0
  b: 3.5
  c: 3.0
  d: 4.0
links:
  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}}
  coupler: {points: {B: [0, 0], C: [b, 0]}}
  rocker:  {points: {D: [0, 0], C: [c, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  B: {revolute: [crank.B, coupler.B]}
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
inputs:
  - {joint: A}
)M";

std::string Replaced(std::string text, const std::string& find, const std::string& replace) {
  const size_t at = text.find(find);
  EXPECT_NE(at, std::string::npos) << find;
  if (at != std::string::npos) text.replace(at, find.size(), replace);
  return text;
}

TEST(ExpressionFunctions, InverseTrigonometryInRangesAndPoints) {
  // The issue's range limit 2 acos(3/5), and a point placed by atan2 and asin.
  const Model m = LoadModelFromString(
      Replaced(Replaced(kFourbar, "  - {joint: A}", "  - {joint: A, range: [\"atan2(-3, 4)\", 2*acos(3/5)]}"),
               "C: [c, 0]", "C: [\"c*cos(atan2(a, d)) + 0*asin(a/d)\", \"c*sin(atan2(a, d))\"]"),
      "t.yaml");
  EXPECT_NEAR(m.inputs[0].max, 2 * std::acos(0.6), 1e-15);
  EXPECT_NEAR(m.inputs[0].min, std::atan2(-3.0, 4.0), 1e-15);
  EXPECT_NEAR(Value(m.links[3].points[1].x, m), 3.0 * std::cos(std::atan2(1.0, 4.0)), 1e-15);
  EXPECT_NEAR(Value(m.links[3].points[1].y, m), 3.0 * std::sin(std::atan2(1.0, 4.0)), 1e-15);
}

TEST(ExpressionFunctions, DomainErrorsAndUnknownFunctionsPointAtTheExpression) {
  const std::string acos_text = Replaced(kFourbar, "C: [b, 0]", "C: [b*acos(a + 1), 0]");
  const std::string acos_error = ErrorOf(acos_text);
  EXPECT_EQ(acos_error.rfind(At(acos_text, "b*acos"), 0), 0u) << acos_error;
  EXPECT_NE(acos_error.find("acos of a number beyond [-1, 1]"), std::string::npos) << acos_error;
  EXPECT_NE(ErrorOf(Replaced(kFourbar, "C: [b, 0]", "C: [\"b + atan2(0, a - 1)\", 0]")).find("atan2(0, 0)"),
            std::string::npos);
  const std::string unknown_text = Replaced(kFourbar, "C: [b, 0]", "C: [b + acosh(a), 0]");
  const std::string unknown = ErrorOf(unknown_text);
  EXPECT_EQ(unknown.rfind(At(unknown_text, "acosh"), 0), 0u) << unknown;
  EXPECT_NE(unknown.find("'acosh' is not a function of the expression language (abs acos asin atan atan2 clamp cos "
                         "exp log max min mod sign sin sqrt step tan)"),
            std::string::npos)
      << unknown;
}

// ---- derived parameters ----

const char* kTriangle = R"M(name: tri
parameters:
  a: 3.0
  b: 4.0
  c: {derived: "sqrt(a^2 + b^2)", doc: hypotenuse}
  gamma: {derived: "atan2(b, a)"}
  r: {derived: c/2}
links:
  frame: {ground: true, points: {O: [0, 0], P: [c*cos(gamma), c*sin(gamma)]}}
  crank: {points: {O: [0, 0], B: [r, 0]}}
joints:
  O: {revolute: [frame.O, crank.O]}
inputs:
  - {joint: O}
)M";

TEST(DerivedParameters, AreInlinedInTheFreeParametersAndFollowThemAtRunTime) {
  const Model m = LoadModelFromString(kTriangle, "tri.yaml");
  ASSERT_EQ(m.params.size(), 2u);  // Params keeps a and b only
  EXPECT_EQ(m.params[0].name, "a");
  EXPECT_EQ(m.params[1].name, "b");
  ASSERT_EQ(m.derived.size(), 3u);
  EXPECT_EQ(m.derived[0].doc, "hypotenuse");
  // frame.P = (a, b) for every a, b: c cos(atan2(b, a)) = a. At the defaults and after a
  // change of the lengths (what the generated code does with a new Params).
  const LinkPoint& P = m.links[0].points[1];
  const LinkPoint& B = m.links[1].points[1];
  for (const auto& [a, b] : {std::pair<double, double>{3, 4}, {5, 12}, {1, -2}}) {
    GiNaC::exmap at;
    at[m.params[0].symbol] = a;
    at[m.params[1].symbol] = b;
    auto num = [&](const GiNaC::ex& e) { return GiNaC::ex_to<GiNaC::numeric>(e.subs(at).evalf()).to_double(); };
    EXPECT_NEAR(num(P.x), a, 1e-14);
    EXPECT_NEAR(num(P.y), b, 1e-14);
    EXPECT_NEAR(num(B.x), std::hypot(a, b) / 2, 1e-14);
    // Nothing but the free parameters' symbols is left in them.
    for (const GiNaC::ex& e : {P.x, P.y, B.x}) EXPECT_TRUE(GiNaC::is_a<GiNaC::numeric>(e.subs(at).evalf())) << e;
  }
  EXPECT_EQ(ErrorOf(kTriangle), "");
}

TEST(DerivedParameters, ForwardReferencesSelfReferencesAndBothKeysAreErrorsAtTheName) {
  const std::string forward = Replaced(kTriangle, "sqrt(a^2 + b^2)", "sqrt(a^2 + r^2)");
  EXPECT_EQ(ErrorOf(forward),
            At(forward, "r^2)") + " derived parameter 'c': cannot read 'sqrt(a^2 + r^2)' as an expression: 'r' is a parameter defined "
            "further down (line 7); a derived parameter may use only the parameters above it: move it below 'r'; see "
            "Expressions in models/README.md");
  const std::string self = Replaced(kTriangle, "sqrt(a^2 + b^2)", "c + 1");
  EXPECT_EQ(ErrorOf(self).rfind(At(self, "c + 1"), 0), 0u) << ErrorOf(self);
  EXPECT_NE(ErrorOf(Replaced(kTriangle, "sqrt(a^2 + b^2)", "c + 1")).find("'c' is the parameter being defined"),
            std::string::npos);
  // A cycle a derived parameter cannot even write: r -> c -> r.
  EXPECT_NE(ErrorOf(Replaced(kTriangle, "sqrt(a^2 + b^2)", "2*r")).find("defined further down"), std::string::npos);
  const std::string both_text = Replaced(kTriangle, "{derived: c/2}", "{value: 1, derived: c/2}");
  const std::string both = ErrorOf(both_text);
  EXPECT_EQ(both.rfind(At(both_text, "c/2"), 0), 0u) << both;
  EXPECT_NE(both.find("has both value and derived"), std::string::npos) << both;
  // Checked at the defaults like any expression.
  EXPECT_NE(ErrorOf(Replaced(kTriangle, "sqrt(a^2 + b^2)", "sqrt(a - b)")).find("square root of a negative number"),
            std::string::npos);
  // A plain parameter's value must still be a number, and the error says how to derive one.
  EXPECT_NE(ErrorOf(Replaced(kTriangle, "  b: 4.0", "  b: 2*a")).find("is written b: {derived: <expression>}"),
            std::string::npos);
}

// ---- one namespace per kind of name ----

TEST(Namespaces, AJointALinkAndAParameterMayShareAName) {
  // The issue's case: a slider joint `ram` and the link `ram` it guides (and a parameter).
  const std::string text = R"M(name: shaper
parameters: {ram: 3.2, crank: 1.0}
links:
  ground: {ground: true, points: {O: [0, 0], G: [0, 0.4]}}
  crank:  {points: {O: [0, 0], B: [crank, 0]}}
  rod:    {points: {B: [0, 0], C: [ram, 0]}}
  ram:    {points: {C: [0, 0]}}
joints:
  O:   {revolute: [ground.O, crank.O]}
  B:   {revolute: [crank.B, rod.B]}
  C:   {revolute: [rod.C, ram.C]}
  ram: {prismatic: {guide: ground.G, slider: ram.C}}
inputs:
  - {joint: O}
assembly: {s_ram: 3}
)M";
  EXPECT_EQ(ErrorOf(text), "");
  const Model m = LoadModelFromString(text, "shaper.yaml");
  EXPECT_EQ(m.FindJoint("ram"), 3);
  EXPECT_EQ(m.links[3].name, "ram");
}

TEST(Namespaces, AContactPointThatWouldNameALinkPointTooIsAnError) {
  const std::string text = R"M(name: wheel
links:
  ground: {ground: true, points: {O: [0, 0]}}
  roll:   {points: {C: [0, 0], contact: [0, -1]}}
joints:
  roll: {roll: {wheel: roll.C, radius: 1, on: ground.O}}
inputs:
  - {joint: roll}
)M";
  const std::string e = ErrorOf(text);
  EXPECT_EQ(e.rfind(At(text, "contact: [0, -1]"), 0), 0u) << e;
  EXPECT_NE(e.find("'roll.contact' would name both"), std::string::npos) << e;
}

// ---- a revolute joint over several links ----

// A Stephenson-like six-bar: a four-bar whose crank pin B also carries link5, which drives
// the output rocker about E. `pin` is the joints' text for B.
std::string SixBar(const std::string& pin) {
  return R"M(name: six
parameters: {a: 1.0, b: 3.5, c: 3.0, d: 4.0, e: 3.0, f: 2.5}
links:
  ground:  {ground: true, points: {A: [0, 0], D: [d, 0], E: [1, -3]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}}
  coupler: {points: {B: [0, 0], C: [b, 0]}}
  rocker:  {points: {D: [0, 0], C: [c, 0]}}
  link5:   {points: {B: [0, 0], F: [e, 0]}}
  output:  {points: {E: [0, 0], F: [f, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
)M" + pin + R"M(
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
  E: {revolute: [output.E, ground.E]}
  F: {revolute: [link5.F, output.F]}
inputs:
  - {joint: A}
)M";
}

TEST(PinOverSeveralLinks, IsThePinsOfTheOldWorkaroundRowForRow) {
  const Model pin = LoadModelFromString(SixBar("  B: {revolute: [crank.B, coupler.B, link5.B]}"), "pin.yaml");
  // The workaround the issue's users wrote: a second joint at the same point.
  const Model old = LoadModelFromString(
      SixBar("  B: {revolute: [crank.B, coupler.B]}\n  B_link5: {revolute: [crank.B, link5.B]}"), "old.yaml");
  ASSERT_EQ(pin.joints.size(), old.joints.size());
  EXPECT_EQ(pin.joints[2].name, "B_link5");
  EXPECT_EQ(pin.joints[1].link_b, 2);
  EXPECT_EQ(pin.joints[2].link_b, 4);
  const Analysis pa = Validate(pin), oa = Validate(old);
  EXPECT_EQ(pa.topology.grubler_mobility, 1);
  EXPECT_EQ(pa.topology.grubler_text, oa.topology.grubler_text);
  const Kinematics pk = DeriveKinematics(pin, pa.topology, &pa.coordinates);
  const Kinematics ok = DeriveKinematics(old, oa.topology, &oa.coordinates);
  ASSERT_EQ(pk.nc(), ok.nc());
  ASSERT_EQ(pk.nphi(), ok.nphi());
  EXPECT_EQ(pk.Phi_source, ok.Phi_source);  // rows named by the pair's joint: "joint B_link5, x"
  // The same equations: evaluated at arbitrary coordinates, matched by name.
  auto at = [](const Kinematics& k, const Model& m, double t) {
    GiNaC::exmap v = m.Defaults();
    for (size_t i = 0; i < k.q.size(); ++i) v[k.q[i].symbol] = 0.3 + t;
    for (size_t i = 0; i < k.phi.size(); ++i) v[k.phi[i].symbol] = 0.7 * (i + 1) + t;
    return v;
  };
  for (double t : {0.0, 0.4, 1.9}) {
    const GiNaC::exmap pv = at(pk, pin, t), ov = at(ok, old, t);
    for (int i = 0; i < pk.nc(); ++i)
      EXPECT_NEAR(GiNaC::ex_to<GiNaC::numeric>(pk.Phi[i].subs(pv).evalf()).to_double(),
                  GiNaC::ex_to<GiNaC::numeric>(ok.Phi[i].subs(ov).evalf()).to_double(), 1e-14)
          << pk.Phi_source[i];
  }
  EXPECT_EQ(KindOf(pin.joints[2]).Describe(pin, pin.joints[2]),
            "revolute crank.B = link5.B (pin 'B' over crank, coupler, link5)");
}

TEST(PinOverSeveralLinks, ErrorsPointAtTheElement) {
  const std::string twice = SixBar("  B: {revolute: [crank.B, coupler.B, crank.A]}");
  EXPECT_EQ(ErrorOf(twice).rfind(At(twice, "coupler.B, crank.A", 11), 0), 0u) << ErrorOf(twice);
  EXPECT_NE(ErrorOf(twice).find("lists link 'crank' twice"), std::string::npos);
  // The pin to link5 would be B_link5: a joint of that name, below or above, is an error.
  const std::string below =
      SixBar("  B: {revolute: [crank.B, coupler.B, link5.B]}\n  B_link5: {revolute: [crank.A, link5.F]}");
  EXPECT_EQ(ErrorOf(below).rfind(At(below, "B_link5:"), 0), 0u) << ErrorOf(below);
  EXPECT_NE(ErrorOf(below).find("is the name of a pin of a revolute joint over several links"), std::string::npos);
  const std::string above =
      SixBar("  B_link5: {revolute: [crank.A, link5.F]}\n  B: {revolute: [crank.B, coupler.B, link5.B]}");
  EXPECT_EQ(ErrorOf(above).rfind(At(above, "link5.B]"), 0), 0u) << ErrorOf(above);
  EXPECT_NE(ErrorOf(above).find("rename that joint"), std::string::npos);
  const std::string one = SixBar("  B: {revolute: [crank.B]}");
  EXPECT_NE(ErrorOf(one).find("takes two or more link points"), std::string::npos) << ErrorOf(one);
}

// ---- the slot joint: reading and its errors (its kinematics: tests/kinematics/slot_joint_test.cc) ----

std::string SlotModel(const std::string& slot, const std::string& input = "A") {
  return R"M(name: sl
parameters: {a: 1.0, d: 2.5, h: 0}
links:
  ground: {ground: true, points: {A: [0, 0], D: [d, 0]}}
  crank:  {points: {A: [0, 0], B: [a, 0]}}
  rocker: {points: {D: [0, 0], H: [h, 0], E: [3, 1]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  D: {revolute: [ground.D, rocker.D]}
  slot: {slot: )M" + slot + R"M(}
inputs:
  - {joint: )M" + input + "}\n";
}

TEST(SlotJointReading, CoordinatesMobilityAndErrors) {
  const Model m = LoadModelFromString(SlotModel("{slot: rocker.D, pin: crank.B, through: rocker.E}"), "s.yaml");
  const Analysis a = Validate(m);
  EXPECT_EQ(a.topology.grubler_mobility, 1);  // 3 (3 - 1) - 2*2 - 1
  EXPECT_EQ(a.topology.loop_mobility, 1);     // theta_crank, theta_rocker, s_slot - 2 rows
  EXPECT_EQ(KindOf(m.joints[2]).Coordinate(m, m.joints[2])->name, "s_slot");
  EXPECT_EQ(m.PointName(m.joints[2].End(m.joints[2].link_a)), "rocker.D");
  EXPECT_EQ(m.PointName(m.joints[2].End(m.joints[2].link_b)), "crank.B");
  struct Case {
    std::string slot, input, at;
    size_t skip;
    std::string message;
  };
  const Case cases[] = {
      {"{slot: rocker.D}", "A", "{slot: rocker.D}", 0, "needs slot: link.point"},
      {"{slot: rocker.D, pin: crank.B, angle: 0, through: rocker.E}", "A", "rocker.E}", 0, "both angle and through"},
      {"{slot: rocker.D, pin: crank.B, through: crank.A}", "A", "crank.A}}", 0, "must be a point of the slotted link"},
      {"{slot: rocker.D, pin: crank.B, through: rocker.D}", "A", "rocker.D}}", 0, "the slot point itself"},
      {"{slot: rocker.D, pin: crank.B, through: rocker.H}", "A", "rocker.H}", 0, "give no direction"},
      {"{slot: rocker.D, pin: crank.B, width: 1}", "A", "width", 0, "unknown key 'width'"},
  };
  for (const Case& c : cases) {
    const std::string text = SlotModel(c.slot, c.input);
    const std::string e = ErrorOf(text);
    EXPECT_EQ(e.rfind(At(text, c.at, c.skip), 0), 0u) << c.slot << ": " << e;
    EXPECT_NE(e.find(c.message), std::string::npos) << c.slot << ": " << e;
  }
}

TEST(SlotJointReading, ASlotIsDrivenByItsSlide) {
  // Issue 26: the pin's slide is q, the crank's and the rocker's angles are phi (the
  // kinematics: tests/kinematics/drivers_test.cc).
  const Model m = LoadModelFromString(SlotModel("{slot: rocker.D, pin: crank.B}", "slot"), "s.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  ASSERT_EQ(k.nq(), 1);
  EXPECT_EQ(k.q[0].name, "s_slot");
  EXPECT_FALSE(k.q[0].is_angle);
  EXPECT_EQ(m.inputs[0].max, 1.0);  // a slide's default range [0, 1]
  ASSERT_EQ(k.nphi(), 2);
  EXPECT_EQ(k.phi[0].name, "theta_crank");
  EXPECT_EQ(k.phi[1].name, "theta_rocker");
}

// ---- inputs that are no joint's coordinate (issue 26; their kinematics:
// tests/kinematics/drivers_test.cc) ----

// The error of loading, validating and ordering `text` into blocks, as ErrorOf.
std::string BlocksErrorOf(const std::string& text) {
  try {
    const Model m = LoadModelFromString(text, "t.yaml");
    const Analysis a = Validate(m);
    const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    OrderBlocks(m, k);
  } catch (const ModelError& e) {
    return std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ": " + e.message();
  }
  return "";
}

TEST(DriverReading, APointsCoordinateAddsItsDrivingConstraint) {
  // The four-bar driven by x of its coupler point C: q = x_coupler_C, every angle is phi, and
  // Phi gets the row b cos(theta_coupler) + a cos(theta_crank) - x_coupler_C.
  const std::string text = Replaced(kFourbar, "  - {joint: A}", "  - {point: coupler.C, coordinate: x, "
                                                                "range: [3.5, 4.5]}") + "assembly: {theta_crank: 90*deg, theta_coupler: 30*deg, "
                                              "theta_rocker: 110*deg, x_coupler_C: 4}\n";
  const Model m = LoadModelFromString(text, "t.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  ASSERT_EQ(k.nq(), 1);
  EXPECT_EQ(k.q[0].name, "x_coupler_C");
  EXPECT_FALSE(k.q[0].is_angle);
  EXPECT_EQ(k.assembly_q[0], 4.0);
  ASSERT_EQ(k.nphi(), 3);
  ASSERT_EQ(k.nc(), 3);
  EXPECT_EQ(k.Phi_source[2], "input x_coupler_C, drive of coupler.C, x");
  GiNaC::exmap at = m.Defaults();
  at[k.q[0].symbol] = 4.0;
  for (int i = 0; i < 3; ++i) at[k.phi[i].symbol] = 0.1 * (i + 1);
  // theta_crank = 0.1, theta_coupler = 0.2 (phi in the coordinates' order).
  EXPECT_NEAR(Value(k.Phi[2].subs(at), m), 1.0 * std::cos(0.1) + 3.5 * std::cos(0.2) - 4.0, 1e-15);
  EXPECT_TRUE((k.Phi_q(2, 0) + 1).is_zero());
  const std::vector<Block> blocks = OrderBlocks(m, k);
  EXPECT_FALSE(blocks.empty());
  // A coupler's angle drives it as well (q = theta_coupler, the crank's angle is phi).
  const Model ma = LoadModelFromString(Replaced(kFourbar, "  - {joint: A}", "  - {angle: coupler}"), "t.yaml");
  const Analysis aa = Validate(ma);
  const Kinematics ka = DeriveKinematics(ma, aa.topology, &aa.coordinates, &aa.cams);
  ASSERT_EQ(ka.nq(), 1);
  EXPECT_EQ(ka.q[0].name, "theta_coupler");
  EXPECT_TRUE(ka.q[0].is_angle);
  EXPECT_EQ(ka.nc(), 2);
  EXPECT_EQ(ka.phi[0].name, "theta_crank");
}

TEST(DriverReading, BadDriversAreErrorsAtTheInput) {
  struct Case {
    std::string inputs, at;
    size_t skip;
    std::string message;
  };
  const Case cases[] = {
      {"{point: coupler.Q, coordinate: x, range: [0, 1]}", "coupler.Q", 0, "link 'coupler' has no point 'Q'"},
      {"{point: rotor.C, coordinate: x, range: [0, 1]}", "rotor.C", 0, "unknown link 'rotor'"},
      {"{point: coupler.C, range: [0, 1]}", "{point:", 0, "needs coordinate: x or coordinate: y"},
      {"{point: coupler.C, coordinate: z, range: [0, 1]}", "z, range", 0, "coordinate must be x or y"},
      {"{point: coupler.C, coordinate: x}", "{point:", 0, "needs range: [min, max]"},
      {"{joint: A, point: coupler.C}", "coupler.C}", 0, "has both 'joint' and 'point'"},
      {"{angle: ground}", "ground}", 0, "is the ground, whose angle is fixed"},
      {"{angle: rotor}", "rotor}", 0, "rotor"},
      {"{point: ground.D, coordinate: y, range: [0, 1]}", "ground.D, coordinate", 0, "is a point of the ground"},
      {"{joint: A, coordinate: x}", "x}", 0, "coordinate is a point input's"},
      {"{joint: B}", "B}", 0, "connects two moving links; drive a revolute joint attached to the ground, a prismatic "
                              "joint, or the absolute angle of one of its links (angle: coupler)"},
      {"{point: coupler.C, coordinate: x, range: [0, 1]}\n  - {point: coupler.C, coordinate: x, range: [0, 2]}",
       "coupler.C, coordinate: x, range: [0, 2]", 0, "input point 'coupler.C' is driven twice"},
      {"{angle: crank}\n  - {angle: crank}", "crank}\n", 19, "input angle 'crank' is driven twice"},
      {"{joint: A}\n  - {point: coupler.C, coordinate: x, range: [3.5, 4.5]}", "- {joint: A}", 0,
       "2 input(s) declared but the mechanism has 1 degree(s) of freedom"},
  };
  for (const Case& c : cases) {
    const std::string text = Replaced(kFourbar, "{joint: A}", c.inputs);
    const std::string e = ErrorOf(text);
    EXPECT_EQ(e.rfind(At(text, c.at, c.skip), 0), 0u) << c.inputs << ": " << e;
    EXPECT_NE(e.find(c.message), std::string::npos) << c.inputs << ": " << e;
  }
  // A point the linkage does not move with its dependent coordinates (the crank's pivot):
  // its driving constraint holds no unknown; the error is at that input.
  const std::string pivot = Replaced(kFourbar, "{joint: A}", "{point: crank.A, coordinate: x, range: [0, 1]}");
  const std::string e = BlocksErrorOf(pivot);
  EXPECT_EQ(e.rfind(At(pivot, "{point:"), 0), 0u) << e;
  EXPECT_NE(e.find("input x_crank_A cannot drive the linkage"), std::string::npos) << e;
}

// ---- named assembly modes (their generated code: tests/kinematics/named_modes_test.cc) ----

TEST(NamedModesReading, EachModeIsChosenNearItsValuesAndOneThatCannotCloseIsAnError) {
  const std::string text = Replaced(kFourbar, "  - {joint: A}", "  - {joint: A, range: [0, 10*deg]}") +
                           "assembly: {theta_coupler: 30*deg, theta_rocker: 110*deg}\n"
                           "assembly_modes:\n  up: {}\n  down: {theta_coupler: -60*deg, theta_rocker: -138*deg}\n";
  const Model m = LoadModelFromString(text, "m.yaml");
  ASSERT_EQ(m.assembly_modes.size(), 2u);
  EXPECT_EQ(m.assembly_modes[1].name, "down");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates);
  const std::vector<Block> blocks = OrderBlocks(m, k);
  ASSERT_EQ(blocks.size(), 1u);
  ASSERT_EQ(blocks[0].named_modes.size(), 2u);
  EXPECT_EQ(blocks[0].named_modes[0], blocks[0].default_mode);   // {}: the assembly's own
  EXPECT_EQ(blocks[0].named_modes[1], -blocks[0].default_mode);  // the other root
  // a = 2.8: at theta_crank = 180 deg |BD| = 6.8 > b + c = 6.5, the loop cannot close there.
  const std::string bad = Replaced(Replaced(text, "  a: 1.0", "  a: 2.8"), "  down: {", "  down: {theta_crank: Pi, ");
  const Model mb = LoadModelFromString(bad, "bad.yaml");
  const Analysis ab = Validate(mb);
  const Kinematics kb = DeriveKinematics(mb, ab.topology, &ab.coordinates);
  try {
    (void)OrderBlocks(mb, kb);
    ADD_FAILURE() << "no error for a mode that cannot be assembled";
  } catch (const ModelError& e) {
    EXPECT_EQ(std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ":", At(bad, "down:"));
    EXPECT_NE(e.message().find("assembly mode 'down' cannot be assembled (theta_crank = 180 deg)"), std::string::npos)
        << e.message();
    EXPECT_NE(e.message().find("centres 6.8 apart"), std::string::npos) << e.message();
  }
}

TEST(NamedModesReading, TheExampleModelNamesFourbarsOpenAndCrossedRoots) {
  // tests/kinematics/models/fourbar_named_modes.yaml: open {} is the assembly's own (the
  // shipped fourbar: block 0 mode 1, models/README.md), crossed the other root.
  const Model m = LoadModel(std::string(MECHGEN_SOURCE_DIR) + "/tests/kinematics/models/fourbar_named_modes.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates);
  const std::vector<Block> blocks = OrderBlocks(m, k);
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].default_mode, 1);
  EXPECT_EQ(blocks[0].named_modes, (std::vector<int>{1, -1}));
}

}  // namespace
}  // namespace mechgen
