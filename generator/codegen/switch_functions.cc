// EvalSwitchModes: the piecewise-constant modes of the switching items of the applied loads
// (the dynamics' Q), so that an integrator can locate where a load jumps or kinks and restart
// there (runtime/include/mechgen/dynamics/forward.h). See functions.h.
#include <algorithm>
#include <cstdio>
#include <set>

#include "codegen/functions.h"
#include "codegen/slot_spelling.h"
#include "model/expression_functions.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using Dir = Argument::Direction;

std::string N(int i) { return std::to_string(i); }

std::string Num17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// Whether `e` is a switching item: a piecewise function of the expression language
/// (model/expression_functions.h) or a table call (model.h), by the GiNaC function's serial.
bool IsSwitch(const ex& e) {
  return is_ex_the_function(e, mstep) || is_ex_the_function(e, msign) || is_ex_the_function(e, mmin) ||
         is_ex_the_function(e, mmax) || is_ex_the_function(e, mmod) || is_ex_the_function(e, mtable);
}

/// The item `e` stands for: a table's slope (d = 1) switches where its value kinks, so both
/// are the item mtable(i, 0, x).
ex Canonical(const ex& e) {
  if (is_ex_the_function(e, mtable)) return mtable(e.op(0), 0, e.op(2));
  return e;
}

void Collect(const ex& e, std::set<ex, GiNaC::ex_is_less>* items) {
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (IsSwitch(*it)) items->insert(Canonical(*it));
}

}  // namespace

std::vector<GiNaC::ex> SwitchItems(const Program& program) {
  std::set<ex, GiNaC::ex_is_less> items;
  for (const Statement& s : program)
    if (s.kind == Statement::Kind::kDefine || s.kind == Statement::Kind::kStore) Collect(s.value, &items);
  return {items.begin(), items.end()};
}

FunctionSpec EvalSwitchModesSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer) {
  const int nq = static_cast<int>(m.inputs.size());
  const StaticsTable& a = *dt.applied;
  NameSlots(a.slots, printer);
  // Q and the locals it reads.
  Program P = dt.program;
  for (int j = 0; j < nq; ++j) P.push_back(Store("Q_" + N(j), dt.Q[j]));
  PruneUnusedDefines(&P);
  std::vector<ex> items = SwitchItems(P);
  FunctionSpec f;
  if (items.empty()) return f;
  for (const Statement& s : P)  // the locals' names, for the items' text
    if (s.kind == Statement::Kind::kDefine) printer->Name(s.symbol, s.target);
  // A fixed order: by the items' printed text (GiNaC's own order changes from run to run).
  std::stable_sort(items.begin(), items.end(),
                   [printer](const ex& x, const ex& y) { return printer->Key(x) < printer->Key(y); });
  f.name = "EvalSwitchModes";
  f.model_member = "SwitchModes";
  f.instantiate = false;
  f.count_ops = false;
  f.switches = static_cast<int>(items.size());
  f.doc = {"\\brief The switching items of the applied loads Q (step, sign, min, max, mod and table calls,",
           "each once) and the piecewise-constant mode of each at a state: Q is smooth while no mode changes.",
           "  step(x): 1 for x >= 0, else 0; sign(x): sign of x (1, 0, -1); min(a, b): 0 where a <= b (a",
           "  taken), else 1; max(a, b): 0 where a >= b, else 1; mod(x, p): floor(x/p) as ExprMod takes it;",
           "  a table of x: the number of its points x_k <= x (its segment).",
           "Items (kNumSwitches):"};
  // The applied program's locals that the items' arguments read (the rest is pruned), the
  // arguments stored into x, then the modes from them.
  Program body = dt.program;
  int num_x = 0;
  for (const ex& e : items) num_x += is_ex_the_function(e, mstep) || is_ex_the_function(e, msign) ||
                                             is_ex_the_function(e, mtable) ? 1 : 2;
  body.insert(body.begin(), Raw("Scalar x[" + N(num_x) + "];"));
  int next_x = 0;
  std::vector<std::string> lines;
  for (size_t i = 0; i < items.size(); ++i) {
    const ex& e = items[i];
    const std::string k = N(static_cast<int>(i));
    const std::string x0 = "x[" + N(next_x) + "]", x1 = "x[" + N(next_x + 1) + "]";
    next_x += is_ex_the_function(e, mstep) || is_ex_the_function(e, msign) || is_ex_the_function(e, mtable) ? 1 : 2;
    const std::string out = "(*modes)[" + k + "] = ";
    std::string what;
    if (is_ex_the_function(e, mtable)) {
      const int t = GiNaC::ex_to<GiNaC::numeric>(e.op(0)).to_int();
      body.push_back(Store(x0, e.op(2)));
      std::string xs;
      for (size_t j = 0; j < m.tables[t].x.size(); ++j) xs += (j ? ", " : "") + Num17(m.tables[t].x[j]);
      lines.push_back("{");
      lines.push_back("static constexpr double kX[] = {" + xs + "};");
      lines.push_back("int n = 0;");
      lines.push_back("for (double xk : kX) n += " + x0 + " >= Scalar(xk) ? 1 : 0;");
      lines.push_back(out + "n;");
      lines.push_back("}");
      what = "table '" + m.tables[t].name + "'";
    } else if (is_ex_the_function(e, mstep)) {
      body.push_back(Store(x0, e.op(0)));
      lines.push_back(out + x0 + " >= Scalar(0) ? 1 : 0;");
      what = "step";
    } else if (is_ex_the_function(e, msign)) {
      body.push_back(Store(x0, e.op(0)));
      lines.push_back(out + x0 + " > Scalar(0) ? 1 : (" + x0 + " < Scalar(0) ? -1 : 0);");
      what = "sign";
    } else if (is_ex_the_function(e, mmin)) {
      body.push_back(Store(x0, e.op(0)));
      body.push_back(Store(x1, e.op(1)));
      lines.push_back(out + x0 + " <= " + x1 + " ? 0 : 1;");
      what = "min";
    } else if (is_ex_the_function(e, mmax)) {
      body.push_back(Store(x0, e.op(0)));
      body.push_back(Store(x1, e.op(1)));
      lines.push_back(out + x0 + " >= " + x1 + " ? 0 : 1;");
      what = "max";
    } else {  // mmod: the floor that ExprMod's value takes (its rounding corrections included)
      body.push_back(Store(x0, e.op(0)));
      body.push_back(Store(x1, e.op(1)));
      lines.push_back("{");
      lines.push_back("Scalar n = floor(" + x0 + " / " + x1 + ");");
      lines.push_back("const Scalar r = " + x0 + " - " + x1 + " * n;");
      lines.push_back("if (r < Scalar(0)) n -= Scalar(1);");
      lines.push_back("if (r >= " + x1 + ") n += Scalar(1);");
      lines.push_back(out + "static_cast<int>(n);");
      lines.push_back("}");
      what = "mod";
    }
    f.doc.push_back("  " + k + ": " + what + " (" + printer->Key(e) + ")");
  }
  for (const std::string& l : lines) body.push_back(Raw(l));
  body = FinishAppliedProgram(body, a, printer);
  f.reindent = true;
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities dq/dt", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s)"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn,
                       "EvalCoefficients() at this (q, phi): K and L are read from it."));
  f.args.push_back(Arg("std::array<int, Sizes::kNumSwitches>*", "modes", Dir::kOut,
                       "The mode of each item; not nullptr.", "dim kNumSwitches"));
  f.body = {body};
  return f;
}

}  // namespace mechgen
