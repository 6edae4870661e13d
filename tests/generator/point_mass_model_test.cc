// Point masses in the model reader (`point_masses:` of a link; issue 26): the combined body the
// front end makes of a link's own mass and its point masses against the parallel-axis theorem
// written out here, a point mass making a massless link massive, a link without point masses
// left as written, and each bad point mass an error at its file:line:column saying what to
// change.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "model/model.h"
#include "model/reader.h"
#include "report/equivalent.h"
#include "symbolic/dynamics.h"
#include "symbolic/table.h"

namespace mechgen {
namespace {

double Value(const GiNaC::ex& e, const Model& m) {
  return GiNaC::ex_to<GiNaC::numeric>(e.subs(m.Defaults()).evalf()).to_double();
}

// A four-bar whose crank and coupler lines are {CRANK} and {COUPLER}.
std::string Fourbar(const std::string& crank, const std::string& coupler, const std::string& outputs = "") {
  return "name: s\n"
         "parameters: {a: 1.0, b: 3.5, c: 3.0, d: 4.0, mh: 2.0}\n"
         "links:\n"
         "  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}\n"
         "  crank:   " + crank + "\n"
         "  coupler: " + coupler + "\n"
         "  rocker:  {points: {D: [0, 0], C: [c, 0]}, mass: 1}\n"
         "joints:\n"
         "  A: {revolute: [ground.A, crank.A]}\n"
         "  B: {revolute: [crank.B, coupler.B]}\n"
         "  C: {revolute: [coupler.C, rocker.C]}\n"
         "  D: {revolute: [rocker.D, ground.D]}\n"
         "inputs:\n"
         "  - {joint: A}\n"
         "gravity: [0, -9.81]\n"
         "assembly: {theta_crank: 1.57, theta_coupler: 0.5, theta_rocker: 1.9}\n" + outputs;
}
const std::string kCoupler = "{points: {B: [0, 0], C: [b, 0]}}";

// The error of loading and deriving `text`: "line:column: message" (or "" when it loads).
std::string ErrorOf(const std::string& text) {
  try {
    const Model m = LoadModelFromString(text, "t.yaml");
    const Analysis a = Validate(m);
    const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    const SymbolicTable t(m, k);
    if (m.outputs.Has(Quantity::kDynamics)) DynamicsTable(m, k, t);
  } catch (const ModelError& e) {
    return std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ": " + e.message();
  }
  return "";
}

// "line:column:" of `marker` in `text` (plus `skip` characters).
std::string At(const std::string& text, const std::string& marker, size_t skip = 0) {
  const size_t at = text.find(marker);
  EXPECT_NE(at, std::string::npos) << marker;
  const size_t where = at + skip;
  const size_t line_start = text.rfind('\n', where == 0 ? 0 : where - 1);
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(where), '\n')) + 1;
  const size_t column = line_start == std::string::npos ? where + 1 : where - line_start;
  return std::to_string(line) + ":" + std::to_string(column) + ":";
}

// `text`'s error starts at `marker` and says `what`.
void ExpectError(const std::string& text, const std::string& marker, const std::string& what, size_t skip = 0) {
  const std::string e = ErrorOf(text);
  EXPECT_EQ(e.rfind(At(text, marker, skip), 0), 0u) << e;
  EXPECT_NE(e.find(what), std::string::npos) << e;
}

TEST(PointMasses, CombineWithTheLinksOwnMassByTheParallelAxisTheorem) {
  // The crank's own mass 1 at (0.5, 0) with J 0.1, a counterweight of 0.5 at (-0.2, 0.1) (no
  // inertia) and a head of mh = 2 at B = (1, 0) with its own J 0.03.
  const Model m = LoadModelFromString(
      Fourbar("{points: {A: [0, 0], B: [a, 0]}, mass: 1, center: [a/2, 0], inertia: 0.1,\n"
              "            point_masses: {w: {at: [-0.2, 0.1], mass: 0.5}, head: {at: B, mass: mh, inertia: 0.03}}}",
              kCoupler),
      "ok.yaml");
  const Link& crank = m.links[1];
  ASSERT_EQ(crank.point_masses.size(), 2u);
  EXPECT_EQ(crank.point_masses[0].name, "w");
  EXPECT_EQ(crank.point_masses[0].at, "");
  EXPECT_EQ(crank.point_masses[1].at, "B");
  // By hand: M, G = sum m r / M, J_G = sum (J + m |r - G|^2).
  const double ms[] = {1, 0.5, 2}, xs[] = {0.5, -0.2, 1}, ys[] = {0, 0.1, 0}, Js[] = {0.1, 0, 0.03};
  double M = 0, Gx = 0, Gy = 0, J = 0;
  for (int i = 0; i < 3; ++i) M += ms[i], Gx += ms[i] * xs[i], Gy += ms[i] * ys[i];
  Gx /= M;
  Gy /= M;
  for (int i = 0; i < 3; ++i) J += Js[i] + ms[i] * (std::pow(xs[i] - Gx, 2) + std::pow(ys[i] - Gy, 2));
  ASSERT_TRUE(crank.mass.given);
  EXPECT_NEAR(Value(crank.mass.mass, m), M, 1e-14);
  EXPECT_NEAR(Value(crank.mass.center_x, m), Gx, 1e-14);
  EXPECT_NEAR(Value(crank.mass.center_y, m), Gy, 1e-14);
  EXPECT_NEAR(Value(crank.mass.inertia, m), J, 1e-14);
  // Symbolic in the parameters: the head's mass mh is in the centre and the inertia.
  const GiNaC::symbol& mh = m.params[4].symbol;
  EXPECT_TRUE(crank.mass.center_x.has(mh));
  EXPECT_TRUE(crank.mass.inertia.has(mh));
  // The report's equivalent masses read the combined body.
  const auto eq = EquivalentLinks(m);
  ASSERT_FALSE(eq.empty());
  EXPECT_EQ(eq[0].link, "crank");
  EXPECT_NEAR(eq[0].m, M, 1e-14);
  EXPECT_NEAR(eq[0].J, J, 1e-14);
  EXPECT_NEAR(eq[0].Gx, Gx, 1e-14);
  // And say what they combine.
  std::ostringstream report;
  WriteEquivalentLinks(m, false, report);
  EXPECT_NE(report.str().find("  crank: m = 3.5, "), std::string::npos) << report.str();
  EXPECT_NE(report.str().find("(m, J_G and G include its point masses: w m = 0.5 at (-0.2, 0.1), head m = 2 at "
                              "crank.B with J = 0.03)\n"),
            std::string::npos)
      << report.str();
}

TEST(PointMasses, APointMassMakesAMasslessLinkMassiveAndIsItsBody) {
  const std::string text =
      Fourbar("{points: {A: [0, 0], B: [a, 0]}}",
              "{points: {B: [0, 0], C: [b, 0], P: [b/2, 0.3]},\n"
              "            point_masses: {payload: {at: P, mass: mh, inertia: 0.2}}}",
              "outputs: {quantities: [dynamics, shaking]}\n");
  EXPECT_EQ(ErrorOf(text), "");
  const Model m = LoadModelFromString(text, "ok.yaml");
  const Link& coupler = m.links[2];
  ASSERT_TRUE(coupler.mass.given);
  // One body alone: the point itself, its mass and its own inertia, exactly (no division).
  EXPECT_TRUE(coupler.mass.center_x.is_equal(coupler.points[2].x));
  EXPECT_TRUE(coupler.mass.center_y.is_equal(coupler.points[2].y));
  EXPECT_TRUE(coupler.mass.mass.is_equal(m.params[4].symbol));
  EXPECT_NEAR(Value(coupler.mass.inertia, m), 0.2, 1e-15);
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(m, k);
  const DynamicsTable d(m, k, t);
  EXPECT_EQ(d.massive, (std::vector<bool>{false, false, true, true}));
  // Alone on the model's only otherwise massless moving links, it is what the dynamics needs.
  const std::string only = Fourbar("{points: {A: [0, 0], B: [a, 0]}, point_masses: {h: {at: B, mass: 1}}}", kCoupler,
                                   "outputs: {quantities: [dynamics]}\n");
  std::string no_rocker_mass = only;
  no_rocker_mass.replace(no_rocker_mass.find(", mass: 1}\njoints"), 9, "");
  EXPECT_EQ(ErrorOf(no_rocker_mass), "");
}

TEST(PointMasses, ALinkWithoutPointMassesKeepsItsMassAsWritten) {
  const Model m = LoadModelFromString(
      Fourbar("{points: {A: [0, 0], B: [a, 0]}, mass: 1 + mh, center: [a/2, 0.1], inertia: mh/12}", kCoupler),
      "ok.yaml");
  const Link& crank = m.links[1];
  EXPECT_TRUE(crank.point_masses.empty());
  EXPECT_NEAR(Value(crank.mass.mass, m), 3.0, 1e-15);
  EXPECT_NEAR(Value(crank.mass.center_y, m), 0.1, 1e-15);
  EXPECT_NEAR(Value(crank.mass.inertia, m), 2.0 / 12, 1e-15);
  EXPECT_FALSE(m.links[2].mass.given);
}

TEST(PointMasses, ErrorsNameTheirPlaceAndWhatToChange) {
  const std::string bar = "{points: {A: [0, 0], B: [a, 0]}, point_masses: ";
  auto with = [&](const std::string& pm) { return Fourbar(bar + pm + "}", kCoupler); };
  std::string t;
  t = with("{h: {at: Q, mass: 1}}");
  ExpectError(t, "Q, mass", "link 'crank' has no point 'Q'; its points are: A, B");
  t = with("{h: {at: coupler.B, mass: 1}}");
  ExpectError(t, "coupler.B, mass", "write the point's name alone");
  t = with("{h: {at: [1, 2, 3], mass: 1}}");
  ExpectError(t, "[1, 2, 3]", "at: [x, y] must have two coordinates");
  t = with("{h: {at: {x: 1}, mass: 1}}");
  ExpectError(t, "{x: 1}", "must name a point of 'crank' (A, B) or give [x, y]");
  t = with("{h: {at: B, mass: -mh}}");
  ExpectError(t, "-mh",
              "mass of point mass 'h' of link 'crank' is negative at the parameters' defaults; give a mass >= 0");
  t = with("{h: {at: B, mass: 1, inertia: -0.1}}");
  ExpectError(t, "-0.1", "moment of inertia of point mass 'h' of link 'crank' is negative");
  t = with("{h: {at: B, mass: 1, J: 0.1}}");
  ExpectError(t, "J: 0.1", "unknown key 'J' in point mass 'h' of link 'crank'; expected one of: at, inertia, mass");
  t = with("{h: {mass: 1}}");
  ExpectError(t, "{mass: 1}", "point mass 'h' of link 'crank' needs at:");
  t = with("{h: {at: B}}");
  ExpectError(t, "{at: B}", "needs mass: m; add it");
  t = with("{h: {at: B, mass: }}");
  ExpectError(t, "mass: }", "has no value", 6);
  t = with("[B, 1]");
  ExpectError(t, "[B, 1]", "point_masses of link 'crank' must be a mapping");
  t = with("{h: 2}");
  ExpectError(t, "2}}", "point mass 'h' of link 'crank' must be a mapping: {at:");
  t = with("{int: {at: B, mass: 1}}");
  ExpectError(t, "int:", "C++ keyword");
  // Two bodies without mass: no centre.
  t = Fourbar("{points: {A: [0, 0], B: [a, 0]}, mass: 0, point_masses: {h: {at: B, mass: 0}}}", kCoupler);
  ExpectError(t, "point_masses:", "total mass of 0 at the parameters' defaults");
  // The ground does not move.
  t = Fourbar("{points: {A: [0, 0], B: [a, 0]}}", kCoupler);
  t.replace(t.find("D: [d, 0]}}"), 11, "D: [d, 0]}, point_masses: {h: {at: D, mass: 1}}}");
  ExpectError(t, "point_masses:", "the ground link 'ground' cannot carry point masses (it does not move)");
  // A centre of mass still needs the link's own mass, point masses or not.
  t = with("{h: {at: B, mass: 1}}, center: [0, 0]");
  ExpectError(t, "[0, 0]}\n  coupler", "has a centre of mass or inertia but no mass");
}

}  // namespace
}  // namespace mechgen
