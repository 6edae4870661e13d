// The SolvePositions builder: the blocks of the solve order one after the other, each a
// closed form printed from its one formulation (symbolic/dyads.h) or Newton–Raphson on the
// block. See functions.h.
#include "codegen/functions.h"
#include "symbolic/dyads.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using Dir = Argument::Direction;

std::string N(int i) { return std::to_string(i); }

// The statements of one closed-form block (see dyads.h for the forms). *trig_done[i] is
// set for each angle phi(i) whose sin and cos the block writes to *trig from its own
// solution (no trigonometric call).
void ClosedFormPositions(const ClosedForm& f, int bi, Program* P, CxxPrinter* printer, std::vector<bool>* trig_done) {
  printer->Name(f.mode, "Scalar(modes[" + N(bi) + "])");
  auto text = [&](const ex& e) { return printer->Print(e); };
  auto phi_ref = [&](int i) { return "phi(" + N(i) + ")"; };
  bool pending_store = false;
  for (const DyadStep& s : f.steps) {
    if (pending_store && s.kind != DyadStep::Kind::kValue) {
      P->push_back(Raw(""));  // flush the stores before the next statements read phi
      pending_store = false;
    }
    switch (s.kind) {
      case DyadStep::Kind::kLocal:
        if (!GiNaC::is_a<GiNaC::symbol>(s.symbol) || s.symbol.is_equal(s.value)) break;  // a number or symbol already
        {
          Statement d;
          d.kind = Statement::Kind::kDefine;
          d.target = s.name + f.suffix;
          d.value = s.value;
          d.symbol = s.symbol;
          P->push_back(d);
          printer->Name(s.symbol, d.target);  // raw lines below print it
        }
        break;
      case DyadStep::Kind::kRequire: {
        const std::string v = text(s.value);
        const std::string cond = s.require == DyadStep::Require::kNonNegative    ? "!(" + v + " >= Scalar(0))"
                                 : s.require == DyadStep::Require::kAbsAtMostOne ? "!(abs(" + v + ") <= Scalar(1))"
                                                                                 : v + " == Scalar(0)";
        P->push_back(Raw("if (" + cond + ") return {SolveStatus::kNotAssemblable, " + N(bi) + ", iterations, " +
                         text(s.measure) + "};"));
        break;
      }
      case DyadStep::Kind::kAngle:
        P->push_back(Raw(phi_ref(s.col) + " = AngleNear(atan2(" + text(s.y) + ", " + text(s.x) + ")" +
                         (s.value.is_zero() ? "" : " + " + text(s.value)) + ", " + phi_ref(s.col) + ");"));
        break;
      case DyadStep::Kind::kValue:
        P->push_back(Store(phi_ref(s.col), s.value));
        pending_store = true;
        break;
    }
  }
  if (pending_store) P->push_back(Raw(""));
  if (f.trig.empty()) return;
  P->push_back(Raw("if (trig != nullptr) {"));
  for (const DyadTrig& t : f.trig) {
    const std::string norm2 = text(t.norm2);
    P->push_back(Raw("  const Scalar " + t.inv_name + f.suffix + " = Scalar(1) / " +
                     (GiNaC::is_a<GiNaC::symbol>(t.norm2) ? norm2 : "(" + norm2 + ")") + ";"));
  }
  for (const DyadTrig& t : f.trig) {
    P->push_back(Raw("  trig->cos_phi(" + N(t.col) + ") = " + text(t.dot) + " * " + t.inv_name + f.suffix + ";"));
    P->push_back(Raw("  trig->sin_phi(" + N(t.col) + ") = " + text(t.cross) + " * " + t.inv_name + f.suffix + ";"));
    (*trig_done)[t.col] = true;
  }
  P->push_back(Raw("}"));
}

// Newton–Raphson on one block: residual and Jacobian of its rows over its unknowns.
void NewtonPositions(const Kinematics& k, const Block& b, int bi, Program* P) {
  const int n = static_cast<int>(b.cols.size());
  const std::string t = "_b" + N(bi), sz = N(n);
  P->push_back(Raw("Vec<Scalar, " + sz + "> r" + t + ";"));
  P->push_back(Raw("Mat<Scalar, " + sz + ", " + sz + "> J" + t + " = Mat<Scalar, " + sz + ", " + sz + ">::Zero();"));
  P->push_back(Raw("for (int iteration = 0;; ++iteration) {"));
  for (int r = 0; r < n; ++r) {
    P->push_back(Store("  r" + t + "(" + N(r) + ")", k.Phi[b.rows[r]]));
    for (int c = 0; c < n; ++c)
      if (!k.Phi_phi(b.rows[r], b.cols[c]).is_zero())
        P->push_back(Store("  J" + t + "(" + N(r) + ", " + N(c) + ")", k.Phi_phi(b.rows[r], b.cols[c])));
  }
  P->push_back(Raw("  Scalar norm" + t + " = Scalar(0);"));
  P->push_back(Raw("  for (int i = 0; i < " + sz + "; ++i) if (abs(r" + t + "(i)) > norm" + t + ") norm" + t +
                   " = abs(r" + t + "(i));"));
  P->push_back(Raw("  const bool closed" + t + " = norm" + t + " <= tol;"));
  P->push_back(Raw("  if (!closed" + t + " && (iteration == max_iterations || !(norm" + t + " == norm" + t +
                   "))) return {SolveStatus::kDidNotConverge, " + N(bi) + ", iterations, norm" + t + "};"));
  P->push_back(Raw("  ++iterations;"));
  P->push_back(Raw("  const Vec<Scalar, " + sz + "> delta" + t + " = J" + t + ".partialPivLu().solve(r" + t + ");"));
  for (int c = 0; c < n; ++c) P->push_back(Raw("  phi(" + N(b.cols[c]) + ") -= delta" + t + "(" + N(c) + ");"));
  // Once the residual test passes, the step just taken is a last polish (quadratic
  // convergence): positions are then accurate to rounding, not just to the tolerance
  // times cond(Phi_phi).
  P->push_back(Raw("  if (closed" + t + ") break;"));
  P->push_back(Raw("}"));
}

}  // namespace

FunctionSpec SolvePositionsSpec(const SymbolicTable& t, CxxPrinter* printer, std::vector<bool>* trig_done) {
  const Kinematics& k = t.kinematics();
  FunctionSpec f;
  f.name = "SolvePositions";
  f.model_member = "Solve";
  f.returns = "SolveReport<Scalar>";
  f.reindent = true;
  f.ops_note = "per Newton iteration for Newton blocks";
  f.doc = {"\\brief Positions phi at inputs q, block by block in the solve order: closed-form dyads",
           "on the branch `modes[block]` (+1 or -1; Model::kDefaultModes is the model's assembly),",
           "Newton–Raphson from the given phi for the other blocks."};
  f.args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "q", Dir::kIn, "Inputs", "dim kNq"));
  f.args.push_back(Arg("Vec<Scalar, Sizes::kNphi>*", "phi_io", Dir::kInOut,
                       "In: the starting guess (a predictor) and, for angles found in closed form, the reference "
                       "they are kept continuous with. Out: the solution, when the report says kConverged",
                       "dim kNphi"));
  Argument modes = Arg("const std::array<int, Sizes::kNumBlocks>&", "modes", Dir::kIn,
                       "Assembly mode of each block (ignored for Newton blocks)", "dim kNumBlocks");
  modes.member_default = "kDefaultModes";
  f.args.push_back(modes);
  f.args.push_back(
      Arg("int", "max_iterations", Dir::kIn, "Newton blocks: at most this many iterations.", "", false, "20"));
  f.args.push_back(Arg("const Scalar&", "tolerance", Dir::kIn,
                       "Newton blocks stop when |Phi_block|_inf <= tolerance (then take one more step); "
                       "tolerance <= 0 means 1e-12, 1e-5 for float.",
                       "", false, "Scalar(0)"));
  f.args.push_back(Arg("Out<Trig<Scalar>>", "trig", Dir::kOut,
                       "sin and cos of the angle coordinates at the solution (for EvalCoefficients()), when the "
                       "report says kConverged",
                       "", true, "nullptr"));
  bool newton = false;
  for (const Block& b : t.blocks) newton |= b.solve == BlockSolve::kNewton;
  // No blocks (no loop: kNphi = 0, e.g. a pendulum): nothing reads phi (its argument is then void-cast).
  Program prologue;
  if (!t.blocks.empty()) prologue.push_back(Raw("Vec<Scalar, Sizes::kNphi>& phi = *phi_io;"));
  prologue.push_back(Raw("int iterations = 0;"));
  if (newton) {
    prologue.push_back(Raw("// tolerance <= 0: 1e-12 (model units), 1e-5 for float"));
    prologue.push_back(
        Raw("const Scalar tol = tolerance > Scalar(0) ? tolerance : Scalar(sizeof(Scalar) <= 4 ? 1e-5 : 1e-12);"));
  }
  f.body.push_back(prologue);
  trig_done->assign(k.phi.size(), false);
  for (size_t bi = 0; bi < t.blocks.size(); ++bi) {
    const Block& b = t.blocks[bi];
    // Each block is its own program: its values depend on the phi the blocks before it
    // wrote, so no subexpression may be shared across blocks.
    Program P;
    P.push_back(Raw("{  // block " + N(static_cast<int>(bi)) + ": " + b.Describe(k)));
    if (b.solve == BlockSolve::kNewton)
      NewtonPositions(k, b, static_cast<int>(bi), &P);
    else
      ClosedFormPositions(FormulateClosedForm(k, b, static_cast<int>(bi)), static_cast<int>(bi), &P, printer,
                          trig_done);
    P.push_back(Raw("}"));
    f.body.push_back(P);
  }
  f.body.push_back({Raw(""), Raw("return {SolveStatus::kConverged, -1, iterations, Scalar(0)};")});
  return f;
}

}  // namespace mechgen
