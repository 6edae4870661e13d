// The piecewise functions of the expression language (models/README.md, "Expressions"):
// step(x), sign(x), min(a, b), max(a, b), clamp(x, a, b) = min(max(x, a), b) and mod(x, p).
// In GiNaC they are the functions mstep, msign, mmin, mmax and mmod (GiNaC has a step of its
// own; these are ours: their value at the switch points, their derivatives and their C++).
// Their values in double are defined once here; the generated C++ (codegen/functions.cc,
// ExprStep ... ExprMod) follows the same definitions.
#pragma once

#include <ginac/ginac.h>

namespace mechgen {

DECLARE_FUNCTION_1P(mstep)
DECLARE_FUNCTION_1P(msign)
DECLARE_FUNCTION_2P(mmin)
DECLARE_FUNCTION_2P(mmax)
DECLARE_FUNCTION_2P(mmod)

/// step(x): 1 for x >= 0 (so step(0) = 1), 0 for x < 0. Derivative 0 (x != 0).
double StepValue(double x);
/// sign(x): 1, 0 or -1. Derivative 0 (x != 0).
double SignValue(double x);
/// min(a, b): a where a <= b, else b; d/da = step(b - a), d/db = 1 - step(b - a).
double MinValue(double a, double b);
/// max(a, b): a where a >= b, else b; d/da = step(a - b), d/db = 1 - step(a - b).
double MaxValue(double a, double b);
/// mod(x, p) for p > 0: x - p floor(x/p) in [0, p); d/dx = 1, d/dp = (mod(x, p) - x)/p
/// (= -floor(x/p)); it jumps from p to 0 where x crosses a multiple of p.
double ModValue(double x, double p);

/// GiNaC's reader with the language's names: step, sign, min, max, mod and clamp (read as
/// mmin(mmax(x, a), b)) mapped to the functions above.
const GiNaC::prototype_table& ExpressionReader();

/// Whether `e` holds one of the functions above (name: "mstep", ...; empty: any of them).
bool HasPiecewise(const GiNaC::ex& e, const std::string& name = "");

}  // namespace mechgen
