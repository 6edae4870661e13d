// The C++ printer and the common-subexpression elimination: literals, powers and signs
// print as Scalar-generic C++, repeated subexpressions become one temporary, and the text
// does not depend on GiNaC's run-dependent term order.
#include <gtest/gtest.h>

#include "codegen/cxx_code.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using GiNaC::symbol;

TEST(CxxPrinter, LiteralsPowersAndCalls) {
  symbol x("x"), y("y");
  CxxPrinter p;
  p.Name(x, "q(0)");
  p.Name(y, "p.a");
  EXPECT_EQ(p.Print(ex(3)), "Scalar(3)");
  EXPECT_EQ(p.Print(ex(GiNaC::numeric(1, 2))), "Scalar(0.5)");
  EXPECT_EQ(p.Print(GiNaC::pow(x, 2)), "q(0)*q(0)");
  EXPECT_EQ(p.Print(GiNaC::pow(x, -1)), "Scalar(1)/q(0)");
  EXPECT_EQ(p.Print(GiNaC::sqrt(x)), "sqrt(q(0))");
  EXPECT_EQ(p.Print(GiNaC::sin(x) * y), "p.a*sin(q(0))");
  EXPECT_EQ(p.Print(-GiNaC::cos(x)), "-cos(q(0))");
  EXPECT_EQ(p.Print(y - x), "p.a - q(0)");
  EXPECT_EQ(p.Print(x - y), "-p.a + q(0)");
  EXPECT_EQ(p.Print(2 * x / y), "Scalar(2)*q(0)/p.a");
  OpCounts ops;
  p.Print(y * GiNaC::sin(x) + GiNaC::cos(x), &ops);
  EXPECT_EQ(ops.adds, 1);
  EXPECT_EQ(ops.muls, 1);
  EXPECT_EQ(ops.calls, 2);
}

TEST(Cse, RepeatedSubexpressionsBecomeOneTemporary) {
  symbol x("x"), y("y");
  CxxPrinter p;
  p.Name(x, "x");
  p.Name(y, "y");
  Program prog;
  Statement a;
  a.target = "out0";
  a.value = GiNaC::sin(x) * y + 1;
  Statement b = a;
  b.target = "out1";
  b.value = GiNaC::sin(x) * y * 2;
  prog = {a, b};
  const Body body = EmitProgram(prog, &p);
  EXPECT_EQ(body.num_temps, 1) << body.text;
  EXPECT_NE(body.text.find("const Scalar _tmp0 = sin(x)*y;"), std::string::npos) << body.text;
  EXPECT_NE(body.text.find("out0 = Scalar(1) + _tmp0;"), std::string::npos) << body.text;
  EXPECT_NE(body.text.find("out1 = Scalar(2)*_tmp0;"), std::string::npos) << body.text;
}

TEST(Cse, GuardsGroupStores) {
  symbol x("x");
  CxxPrinter p;
  p.Name(x, "x");
  Statement a;
  a.target = "(*A)(0)";
  a.value = GiNaC::cos(x);
  a.guard = "A";
  Statement b = a;
  b.target = "(*B)(0)";
  b.guard = "B";
  const Body body = EmitProgram({a, b}, &p);
  EXPECT_NE(body.text.find("if (A != nullptr) {\n    (*A)(0) = _tmp0;\n  }"), std::string::npos) << body.text;
  EXPECT_NE(body.text.find("if (B != nullptr) {"), std::string::npos) << body.text;
}

}  // namespace
}  // namespace mechgen
