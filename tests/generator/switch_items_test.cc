// The switching items of a program's values (codegen/switch_functions.cc, issue 26): collected
// by the GiNaC functions' serials (not by printed text), each once, a table's slope as its
// value's item, nested items each, expressions without piecewise functions none; by hand
// counts of the expressions built here.
#include <gtest/gtest.h>

#include <ginac/ginac.h>

#include "codegen/functions.h"
#include "model/expression_functions.h"
#include "model/model.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using GiNaC::symbol;

Program Of(const std::vector<ex>& values) {
  Program P;
  for (size_t i = 0; i < values.size(); ++i) P.push_back(Store("out(" + std::to_string(i) + ")", values[i]));
  return P;
}

TEST(SwitchItems, EachItemOnceByMeaning) {
  const symbol x("x"), y("y"), v("v");
  // step(x - 1) twice (in two stores), its derivative-like product, sign(y), clamp(v, 0, 1) =
  // min(max(v, 0), 1) (two items), mod(x, 2) inside a step (two items), a table's value and
  // slope at the same argument (one item) and at another (one more).
  const ex clamp = mmin(mmax(v, 0), 1);
  const std::vector<ex> values = {
      3 * mstep(x - 1) + GiNaC::sin(x),
      mstep(x - 1) * y + msign(y),
      clamp * x,
      mstep(2 - mmod(x, 2)),
      mtable(0, 0, v) + mtable(0, 1, v) * x + mtable(0, 0, 2 * v),
  };
  const std::vector<ex> items = SwitchItems(Of(values));
  EXPECT_EQ(items.size(), 1u + 1u + 2u + 2u + 2u);
  int tables = 0, steps = 0;
  for (const ex& e : items) {
    if (is_ex_the_function(e, mtable)) {
      ++tables;
      EXPECT_TRUE(e.op(1).is_zero()) << e;  // the slope's item is the value's
    }
    if (is_ex_the_function(e, mstep)) ++steps;
  }
  EXPECT_EQ(tables, 2);
  EXPECT_EQ(steps, 2);
}

TEST(SwitchItems, SmoothExpressionsHaveNone) {
  const symbol x("x"), y("y");
  // abs, atan2, sqrt, exp: smooth (or not piecewise in the language's sense): no item.
  EXPECT_TRUE(SwitchItems(Of({GiNaC::abs(x) + GiNaC::atan2(y, x), GiNaC::sqrt(x * x + 1) * GiNaC::exp(y)})).empty());
  // A Define's value counts like a store's.
  Program P;
  ex local;
  P.push_back(Define("a", msign(x), &local));
  P.push_back(Store("out(0)", local * y));
  EXPECT_EQ(SwitchItems(P).size(), 1u);
}

}  // namespace
}  // namespace mechgen
