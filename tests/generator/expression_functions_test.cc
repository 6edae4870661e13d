// The piecewise functions of the expression language (issue 26): step, sign, min, max, clamp
// and mod as the reader evaluates them (exact numbers and floats) on both sides of every
// switch point, against hand values; their symbolic derivatives against central finite
// differences away from the switch points; and a load that jumps where a velocity is 0,
// refused at the function's name when the model has statics. The generated C++ helpers are
// checked against the same hand values in tests/statics/shaper_test.cc.
#include "model/expression_functions.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "model/model.h"
#include "model/reader.h"

namespace mechgen {
namespace {

std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A model with parameters x, y, z at the given values and a derived parameter f = `expr`.
std::string ModelWith(const std::string& expr, double x, double y, double z) {
  return "name: e\nparameters:\n  x: " + Num(x) + "\n  y: " + Num(y) + "\n  z: " + Num(z) + "\n  f: {derived: \"" +
         expr +
         "\"}\n"
         "links:\n  ground: {ground: true, points: {O: [0, 0]}}\n  crank: {points: {O: [0, 0], B: [1, 0]}}\n"
         "joints:\n  O: {revolute: [ground.O, crank.O]}\ninputs:\n  - {joint: O}\n";
}

double ToDouble(const GiNaC::ex& e) {
  const GiNaC::ex v = e.evalf();
  EXPECT_TRUE(GiNaC::is_a<GiNaC::numeric>(v)) << e;
  return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double() : NAN;
}

// f's value two ways: the numbers written into the expression (GiNaC evaluates exact
// rationals as it reads them) and the parameters x, y, z (symbols, evaluated in floats).
void ExpectValue(const std::string& f, double x, double y, double z, double expected) {
  // The names x, y, z (alone, not the x of max) replaced by their numbers.
  std::string literal;
  auto word = [&](size_t i) { return i < f.size() && (std::isalnum(static_cast<unsigned char>(f[i])) || f[i] == '_'); };
  for (size_t i = 0; i < f.size(); ++i) {
    const bool alone = (i == 0 || !word(i - 1)) && !word(i + 1);
    if (alone && (f[i] == 'x' || f[i] == 'y' || f[i] == 'z'))
      literal += "(" + Num(f[i] == 'x' ? x : f[i] == 'y' ? y : z) + ")";
    else
      literal += f[i];
  }
  for (const std::string& text : {f, literal}) {
    const Model m = LoadModelFromString(ModelWith(text, x, y, z), "e.yaml");
    ASSERT_EQ(m.derived.size(), 1u);
    const double got = ToDouble(m.derived[0].value.subs(m.Defaults()));
    EXPECT_NEAR(got, expected, 1e-15 * std::max(1.0, std::abs(expected))) << text << " at x=" << x << " y=" << y;
  }
}

// Hand values (the definitions of models/README.md), for each side of each switch point.
TEST(PiecewiseFunctions, ValuesOnBothSidesOfEverySwitch) {
  const double e = 1e-12;
  for (const auto& [x, v] : {std::pair<double, double>{-2, 0}, {-e, 0}, {0, 1}, {e, 1}, {3, 1}})
    ExpectValue("step(x)", x, 0, 0, v);
  for (const auto& [x, v] : {std::pair<double, double>{-2, -1}, {-e, -1}, {0, 0}, {e, 1}, {3, 1}})
    ExpectValue("sign(x)", x, 0, 0, v);
  for (const auto& [x, y] : {std::pair<double, double>{0.5, 0.5 + e}, {0.5, 0.5}, {0.5 + e, 0.5}, {-3, 2}, {2, -3}}) {
    ExpectValue("min(x, y)", x, y, 0, x < y ? x : y);
    ExpectValue("max(x, y)", x, y, 0, x > y ? x : y);
  }
  for (double x : {-1.0, -0.2 - e, -0.2, -0.2 + e, 0.1, 0.3 - e, 0.3, 0.3 + e, 1.0})
    ExpectValue("clamp(x, y, z)", x, -0.2, 0.3, x < -0.2 ? -0.2 : x > 0.3 ? 0.3 : x);
  // mod: by std::fmod (exact), shifted into [0, p).
  for (double p : {2 * M_PI, 3.0, 0.25}) {
    for (double x : {-7.5, -p - e, -p, -p + e, -e, 0.0, e, p - e, p, p + e, 2.5 * p, 13.0}) {
      double r = std::fmod(x, p);
      if (r < 0) r += p;
      if (r >= p) r -= p;
      ExpectValue("mod(x, y)", x, p, 0, r);
    }
  }
  // The value at a switch point is exactly the documented one, also for mod's jump.
  ExpectValue("mod(x, y)", 6, 3, 0, 0);
  ExpectValue("mod(x, y)", -6, 3, 0, 0);
}

// d/dx of an expression with every function, by GiNaC, against central differences of its
// value, at random points at least 1e-3 from every switch point (where it is smooth).
TEST(PiecewiseFunctions, DerivativesMatchFiniteDifferencesAwayFromTheSwitches) {
  const std::string f =
      "min(x^2, y) + max(x, 2*y)*sign(x - z) + clamp(3*x, -y, y) + z*mod(5*x, y + 1) + step(x - y)*x^3 + "
      "mod(x*y, z + 2)*min(y, 3*x)";
  const Model m = LoadModelFromString(ModelWith(f, 0.3, 0.7, 0.1), "e.yaml");
  const GiNaC::ex e = m.derived[0].value;
  const GiNaC::symbol& x = m.params[0].symbol;
  const GiNaC::symbol& y = m.params[1].symbol;
  const GiNaC::symbol& z = m.params[2].symbol;
  const GiNaC::ex dx = e.diff(x), dy = e.diff(y);
  EXPECT_TRUE(HasPiecewise(dx, "mstep")) << dx;  // min, max and clamp differentiate by branch
  std::mt19937 rng(26);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 150; ++trial) {
    const double X = u(rng), Y = std::abs(u(rng)) + 0.1, Z = u(rng) * 0.5;
    auto near_int = [](double v) { return std::abs(v - std::round(v)); };
    // Distances to the switch points, in the units of the function's argument.
    const double gaps[] = {std::abs(X * X - Y),
                           std::abs(X - 2 * Y),
                           std::abs(X - Z),
                           std::abs(3 * X + Y),
                           std::abs(3 * X - Y),
                           std::abs(X - Y),
                           std::abs(Y - 3 * X),
                           near_int(5 * X / (Y + 1)) * (Y + 1),
                           near_int(X * Y / (Z + 2)) * (Z + 2)};
    bool smooth = true;
    for (double g : gaps) smooth = smooth && g > 1e-3;
    if (!smooth) continue;
    ++checked;
    auto value = [&](double a, double b, double c) {
      GiNaC::exmap at;
      at[x] = a;
      at[y] = b;
      at[z] = c;
      return ToDouble(e.subs(at));
    };
    GiNaC::exmap at;
    at[x] = X;
    at[y] = Y;
    at[z] = Z;
    const double h = 1e-6;
    const double fd_x = (value(X + h, Y, Z) - value(X - h, Y, Z)) / (2 * h);
    const double fd_y = (value(X, Y + h, Z) - value(X, Y - h, Z)) / (2 * h);
    // Central differences of a smooth function: error O(h^2 f''') + O(eps f / h) ~ 1e-9.
    EXPECT_NEAR(ToDouble(dx.subs(at)), fd_x, 1e-6 * std::max(1.0, std::abs(fd_x))) << "x=" << X << " y=" << Y;
    EXPECT_NEAR(ToDouble(dy.subs(at)), fd_y, 1e-6 * std::max(1.0, std::abs(fd_y))) << "x=" << X << " y=" << Y;
  }
  EXPECT_GE(checked, 100);
}

// The error of reading and deriving `text` as "line:column: message" ("" if none).
std::string ErrorOf(const std::string& text) {
  try {
    const Model m = LoadModelFromString(text, "bad.yaml");
    Validate(m);
  } catch (const ModelError& e) {
    return std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ": " + e.message();
  }
  return "";
}

// Lines 1-15; what a test appends starts at line 16.
const char* kDynamicModel = R"(name: s
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

TEST(PiecewiseFunctions, AJumpInAVelocityIsAnErrorAtTheFunctionWithStatics) {
  const std::string base = kDynamicModel;
  const std::string dyn = "outputs: {quantities: [dynamics]}\n";
  // `dynamics` brings `forces`: EvalStatics would hold the crank at rest.
  const std::string step = ErrorOf(base + "loads:\n  cut: {torque: \"-5*step(theta_rocker_dot)\", on: crank}\n" + dyn);
  EXPECT_EQ(step.rfind("17:21: torque of load 'cut': step(theta_rocker_dot) jumps where the velocity in it is 0", 0),
            0u)
      << step;
  EXPECT_NE(step.find("switch the load with the coordinates instead"), std::string::npos) << step;
  // In a force, inside other functions, in a plain (unquoted) scalar; sign and mod too.
  const std::string sign2 = ErrorOf(
      base + "loads:\n  cut: {force: [0, 2 + 3*cos(theta_crank)*sign(1 + theta_crank_dot)], at: crank.B}\n" + dyn);
  EXPECT_EQ(sign2.rfind("17:43: y of load 'cut': sign(1 + theta_crank_dot) jumps", 0), 0u) << sign2;
  const std::string mod = ErrorOf(base + "loads:\n  cut: {torque: \"mod(theta_crank_dot*2, 3)\", on: crank}\n" + dyn);
  EXPECT_EQ(mod.rfind("17:18: torque of load 'cut': mod(theta_crank_dot*2, 3) jumps", 0), 0u) << mod;
  // Continuous in the velocities (evaluated at rest: their limit of a slow motion), jumps in
  // the coordinates, and time: all fine.
  EXPECT_EQ(ErrorOf(base +
                    "loads:\n  drag: {torque: \"-2*theta_crank_dot + min(theta_crank_dot, 1) - "
                    "abs(theta_rocker_dot)\", on: crank}\n" +
                    dyn),
            "");
  EXPECT_EQ(ErrorOf(base +
                    "loads:\n  cut: {torque: \"-5*step(mod(theta_crank, 2*Pi) - Pi)*sign(t - 1)\", on: crank}\n" + dyn),
            "");
}

}  // namespace
}  // namespace mechgen
