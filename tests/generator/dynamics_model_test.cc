// The dynamics sections of the model reader (issue 15): `dynamics` in the quantities, loads of
// time and speed, `tables`, `dampers`, viscous friction; each error at its file:line:column
// with what to change, and what the reader makes of a valid table.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "model/model.h"
#include "report/equivalent.h"
#include "symbolic/dynamics.h"
#include "symbolic/table.h"

namespace mechgen {
namespace {

void ExpectError(const std::string& text, const std::string& where, const std::string& what) {
  try {
    const Model m = LoadModelFromString(text, "bad.yaml");
    const Analysis a = Validate(m);
    const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    const SymbolicTable t(m, k);
    const DynamicsTable d(m, k, t);
    ADD_FAILURE() << "no error; expected " << where << ": " << what;
  } catch (const ModelError& e) {
    EXPECT_EQ(std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column), where) << e.message();
    EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
  }
}

// Lines 1-15; what the tests append starts at line 16.
const char* kBase = R"(name: s
parameters: {a: 1.0, b: 3.5, c: 3.0, d: 4.0}
links:
  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}, mass: 1, center: [a/2, 0], inertia: 0.1}
  coupler: {points: {B: [0, 0], C: [b, 0]}}
  rocker:  {points: {D: [0, 0], C: [c, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  B: {revolute: [crank.B, coupler.B]}
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
inputs:
  - {joint: A}
assembly: {theta_crank: 1.57, theta_coupler: 0.5, theta_rocker: 1.9}
)";
const std::string kDyn = "outputs: {quantities: [dynamics]}\n";

TEST(DynamicsModel, ErrorsNameTheirPlaceAndWhatToChange) {
  const std::string base = kBase;
  // Tables: non-increasing x, sizes, too few points, unknown table, a table outside a load.
  ExpectError(base + "tables:\n  f: {x: [0, 2, 2], y: [0, 1, 2]}\n" + kDyn, "17:17", "x must increase strictly");
  ExpectError(base + "tables:\n  f: {x: [0, 1, 2], y: [0, 1]}\n" + kDyn, "17:24", "y has 2 values and x 3");
  ExpectError(base + "tables:\n  f: {x: [0], y: [0]}\n" + kDyn, "17:10", "at least 2");
  ExpectError(base + "tables:\n  f: {x: [0, 1], y: [0, 1]}\nloads:\n  m: {torque: g(theta_crank_dot), on: crank}\n" + kDyn,
              "19:15", "'g' is not a function of the expression language");
  ExpectError(base + "loads:\n  m: {torque: g(theta_crank_dot), on: crank}\n" + kDyn, "17:15", "the model has no tables");
  ExpectError(base + "tables:\n  f: {x: [0, 1], y: [0, 1]}\nsprings:\n  k: {torsional: B, stiffness: f(1)}\n" + kDyn,
              "19:32", "'f' is not a function");
  // A table's name becomes the C++ function Table_<name> and a function of the expressions.
  ExpectError(base + "tables:\n  sin: {x: [0, 1], y: [0, 1]}\n" + kDyn, "17:3",
              "table name 'sin' is a function of the expression language");
  ExpectError(base + "tables:\n  deg: {x: [0, 1], y: [0, 1]}\n" + kDyn, "17:3",
              "table name 'deg' is a name of the expression language");
  ExpectError(base + "tables:\n  int: {x: [0, 1], y: [0, 1]}\n" + kDyn, "17:3", "is a C++ keyword");
  ExpectError(base + "tables:\n  a: {x: [0, 1], y: [0, 1]}\n" + kDyn, "17:3", "is a parameter's name");
  // Accelerations are reserved; time and speed need the dynamics.
  ExpectError(base + "loads:\n  m: {torque: 2*theta_crank_ddot, on: crank}\n" + kDyn, "17:17", "reserved (accelerations)");
  ExpectError(base + "loads:\n  m: {torque: 1 + t, on: crank}\noutputs: {quantities: [K, forces]}\n", "17:19",
              "add dynamics to the outputs' quantities");
  // Dampers.
  ExpectError(base + "dampers:\n  x: {between: [crank.B, rocker.C], coefficient: -1}\n" + kDyn, "17:50", "negative");
  ExpectError(base + "dampers:\n  x: {joint: E, coefficient: 1}\n" + kDyn, "17:14", "unknown joint 'E'");
  ExpectError(base + "dampers:\n  x: {joint: A, between: [crank.B, rocker.C], coefficient: 1}\n" + kDyn, "17:6",
              "exactly one of");
  ExpectError(base + "dampers:\n  x: {joint: A, coefficient: 1}\noutputs: {quantities: [K, L]}\n", "17:3",
              "dampers act in the dynamics only");
  ExpectError(base + "dampers:\n  x: {joint: A, damping: 1}\n" + kDyn, "17:17", "unknown key 'damping'");
  // Friction needs a coefficient or a viscous one.
  ExpectError(base + "friction:\n  B: {pin_radius: 0.1}\n" + kDyn, "17:6", "coefficient: mu (Coulomb) or viscous");
  // The dynamics needs a mass.
  std::string massless = base;
  const std::string crank = "  crank:   {points: {A: [0, 0], B: [a, 0]}, mass: 1, center: [a/2, 0], inertia: 0.1}";
  massless.replace(massless.find(crank), crank.size(), "  crank:   {points: {A: [0, 0], B: [a, 0]}}");
  ExpectError(massless + kDyn, "16:10", "dynamics needs a moving link with mass");
  ExpectError(massless + "outputs: {quantities: [shaking]}\n", "16:10", "shaking needs a moving link with mass");
  ExpectError(base + "outputs: {quantities: [shake]}\n", "16:24", "the quantities are K, L, scene, forces, potential, "
                                                                "dynamics and shaking");
}

// `shaking` implies the dynamics it reads the accelerations from (and so K, L, forces, potential),
// and derives one column per link: zero for the ground and the massless links.
TEST(DynamicsModel, ShakingImpliesTheDynamics) {
  const Model m = LoadModelFromString(std::string(kBase) + "outputs: {quantities: [shaking]}\n", "ok.yaml");
  for (Quantity q : {Quantity::kK, Quantity::kL, Quantity::kForces, Quantity::kPotential, Quantity::kDynamics,
                     Quantity::kShaking})
    EXPECT_TRUE(m.outputs.Has(q)) << static_cast<int>(q);
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(m, k);
  const DynamicsTable d(m, k, t);
  ASSERT_TRUE(d.shaking);
  ASSERT_EQ(d.F_link.size(), 4u);
  EXPECT_EQ(d.massive, (std::vector<bool>{false, true, false, false}));
  for (int l : {0, 2, 3}) EXPECT_TRUE(d.F_link[l][0].is_zero() && d.F_link[l][1].is_zero() && d.M_link[l].is_zero());
  EXPECT_FALSE(d.F[0].is_zero());
  // Without `shaking` nothing of it is derived.
  const Model plain = LoadModelFromString(std::string(kBase) + kDyn, "ok.yaml");
  const Analysis pa = Validate(plain);
  const Kinematics pk = DeriveKinematics(plain, pa.topology, &pa.coordinates, &pa.cams);
  const SymbolicTable pt(plain, pk);
  EXPECT_FALSE(DynamicsTable(plain, pk, pt).shaking);
}

TEST(DynamicsModel, TablesInterpolateAndClamp) {
  const Model m = LoadModelFromString(std::string(kBase) +
                                          "tables:\n  f: {x: [0, 1, 3], y: [2, 4, 0], doc: a curve}\n"
                                          "loads:\n  m: {torque: f(theta_crank_dot) + t, on: crank}\n" + kDyn,
                                      "ok.yaml");
  ASSERT_EQ(m.tables.size(), 1u);
  EXPECT_EQ(m.tables[0].doc, "a curve");
  // Hand values: (0, 2) - (1, 4) - (3, 0), clamped.
  EXPECT_DOUBLE_EQ(EvalTable(m.tables[0], -1.0, 0), 2.0);
  EXPECT_DOUBLE_EQ(EvalTable(m.tables[0], 0.5, 0), 3.0);
  EXPECT_DOUBLE_EQ(EvalTable(m.tables[0], 2.0, 0), 2.0);
  EXPECT_DOUBLE_EQ(EvalTable(m.tables[0], 2.0, 1), -2.0);
  EXPECT_DOUBLE_EQ(EvalTable(m.tables[0], 5.0, 0), 0.0);
  EXPECT_DOUBLE_EQ(EvalTable(m.tables[0], 5.0, 1), 0.0);
  // The load reads the table of the crank's speed, and time.
  ASSERT_EQ(m.loads.size(), 1u);
  EXPECT_TRUE(m.loads[0].torque.has(mtable(0, 0, m.velocity_refs.at("theta_crank_dot"))));
  EXPECT_TRUE(m.loads[0].torque.has(m.velocity_refs.at("t")));
}

// Paul §6.3.1 by hand for the uniform bars of models/fourbar_massive.yaml (rho = 2 kg/m):
// a bar of length L has m = 2 L, J_G = m L^2/12, k^2 = L^2/12, G at L/2 from each pin, so
// through a pin (a = L/2): b = k^2/a = L/6, m_A = m b/(a+b) = m/4, m_B = 3m/4, B at
// 2L/3 from the pin; the statically equivalent masses are m/2 at each pin, with
// J = m L^2/4 about G: the error is m L^2/4 - m L^2/12 = m L^2/6 (+200% of J_G).
TEST(DynamicsModel, EquivalentLinksOfTheMassiveFourBar) {
  const Model m = LoadModel(std::string(MECHGEN_SOURCE_DIR) + "/models/fourbar_massive.yaml");
  const auto links = EquivalentLinks(m);
  ASSERT_EQ(links.size(), 3u);
  const double lengths[] = {1.0, 3.5, 3.0};
  for (int i = 0; i < 3; ++i) {
    const double L = lengths[i], mass = 2 * L;
    const EquivalentLink& e = links[i];
    SCOPED_TRACE(e.link);
    EXPECT_NEAR(e.m, mass, 1e-14);
    EXPECT_NEAR(e.J, mass * L * L / 12, 1e-12);
    EXPECT_NEAR(e.k2, L * L / 12, 1e-12);
    ASSERT_EQ(e.dynamic.size(), 2u);
    for (const EquivalentPoint& q : e.dynamic) {
      EXPECT_NEAR(q.a, L / 2, 1e-12);
      EXPECT_NEAR(q.b, L / 6, 1e-12);
      EXPECT_NEAR(q.m_A, mass / 4, 1e-12);
      EXPECT_NEAR(q.m_B, 3 * mass / 4, 1e-12);
      // B on the link's axis at L/6 beyond G (2L/3 from the pin it is paired with).
      EXPECT_NEAR(q.By, 0.0, 1e-12);
      EXPECT_NEAR(std::abs(q.Bx - L / 2), L / 6, 1e-12);
    }
    ASSERT_TRUE(e.has_static);
    EXPECT_NEAR(e.m1, mass / 2, 1e-12);
    EXPECT_NEAR(e.m2, mass / 2, 1e-12);
    EXPECT_NEAR(e.J_static, mass * L * L / 4, 1e-12);
    EXPECT_NEAR(e.J_error, mass * L * L / 6, 1e-12);
  }
  // An off-axis centre of mass has no two-joint-point replacement; a link without mass none at all.
  const Model off = LoadModelFromString(std::string(kBase).replace(std::string(kBase).find("center: [a/2, 0]"), 16,
                                                                   "center: [a/2, 0.1]") +
                                            kDyn,
                                        "off.yaml");
  const auto o = EquivalentLinks(off);
  ASSERT_EQ(o.size(), 1u);
  EXPECT_FALSE(o[0].has_static);
  EXPECT_NE(o[0].static_note.find("not on the segment"), std::string::npos);
  // Through A = (0, 0), G = (0.5, 0.1): a = |G|, b = k^2/a with k^2 = 0.1/1.
  ASSERT_EQ(o[0].dynamic.size(), 2u);
  const double a = std::hypot(0.5, 0.1);
  EXPECT_NEAR(o[0].dynamic[0].a, a, 1e-12);
  EXPECT_NEAR(o[0].dynamic[0].b, 0.1 / a, 1e-12);
  EXPECT_NEAR(o[0].dynamic[0].Bx, 0.5 + 0.5 / a * (0.1 / a), 1e-12);
  EXPECT_NEAR(o[0].dynamic[0].By, 0.1 + 0.1 / a * (0.1 / a), 1e-12);
}

}  // namespace
}  // namespace mechgen
