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

// Whether a step of the form reads the symbol (norm2_max, norm2_min: defined only where read,
// an unused local being a warning in the generated code).
bool Reads(const ClosedForm& f, const GiNaC::symbol& x) {
  for (const DyadStep& s : f.steps)
    for (const ex& e : {s.value, s.slack, s.x, s.y})
      if (e.has(x)) return true;
  return false;
}

// The definitions of the range of a dyad's squared lengths (ScalarNorm2Max, dyads.h) that the
// forms read.
void DefineNorm2Bounds(const std::vector<ClosedForm>& forms, Program* P) {
  bool max = false, min = false;
  for (const ClosedForm& f : forms) {
    max |= Reads(f, ScalarNorm2Max());
    min |= Reads(f, ScalarNorm2Min());
  }
  if (max) P->push_back(Raw(kNorm2MaxDefinition));
  if (min) P->push_back(Raw(kNorm2MinDefinition));
}

// The statements of one closed-form block (see dyads.h for the forms). *trig_done[i] is
// set for each angle phi(i) whose sin and cos the block writes to *trig from its own
// solution (no trigonometric call). trig_only (SolveTrig): no angle is computed, the
// block writes its sin and cos to *trig unconditionally and checks them for finiteness
// instead (every angle of the block must have its DyadTrig).
void ClosedFormPositions(const ClosedForm& f,
                         int bi,
                         Program* P,
                         CxxPrinter* printer,
                         std::vector<bool>* trig_done,
                         bool trig_only = false) {
  printer->Name(f.mode, "Scalar(modes[" + N(bi) + "])");
  printer->Name(ScalarEpsilon(), "epsilon");
  printer->Name(ScalarNorm2Max(), "norm2_max");
  printer->Name(ScalarNorm2Min(), "norm2_min");
  auto text = [&](const ex& e) { return printer->Print(e); };
  auto phi_ref = [&](int i) { return "phi(" + N(i) + ")"; };
  // The angles that end the form (every form's last steps: nothing after them reads phi) are
  // printed last, after the branch measure and the direction cosines: those read the locals
  // only, so the atan2 calls come after every other use of the locals, which then need not be
  // kept (spilled) across the calls (with the inputs' sin and cos stored first, ShareTrig():
  // the four-bar's SolvePositions has 37 stack loads and stores where it had 94).
  size_t angles_from = f.steps.size();
  while (angles_from > 0 && f.steps[angles_from - 1].kind == DyadStep::Kind::kAngle) --angles_from;
  auto angle = [&](const DyadStep& s) {
    P->push_back(Raw(phi_ref(s.col) + " = AngleNear(atan2(" + text(s.y) + ", " + text(s.x) + ")" +
                     (s.value.is_zero() ? "" : " + " + text(s.value)) + ", " + phi_ref(s.col) + ");"));
  };
  // Nothing the checks let through may come out NaN or inf (a non-finite input or parameter,
  // an overflow): x - x is 0 exactly for finite x only.
  auto check_finite = [&](const DyadStep& s) {
    const std::string x = phi_ref(s.col);
    P->push_back(Raw("if (!(" + x + " - " + x + " == Scalar(0))) return {SolveStatus::kSingular, " + N(bi) +
                     ", iterations, " + x + "};"));
  };
  bool pending_store = false;
  for (size_t i = 0; i < angles_from; ++i) {
    const DyadStep& s = f.steps[i];
    if (pending_store && s.kind != DyadStep::Kind::kValue) {
      P->push_back(Raw(""));  // flush the stores before the next statements read phi
      pending_store = false;
    }
    switch (s.kind) {
      case DyadStep::Kind::kLocal:
        if (!GiNaC::is_a<GiNaC::symbol>(s.symbol) || s.symbol.is_equal(s.value)) break;  // a number or symbol already
        if (trig_only && s.angle_only) break;  // no angle is computed
        {
          Statement d;
          d.kind = Statement::Kind::kDefine;
          d.target = DyadLocalName(s.local) + f.suffix;
          d.value = s.value;
          d.symbol = s.symbol;
          P->push_back(d);
          printer->Name(s.symbol, d.target);  // raw lines below print it
        }
        break;
      case DyadStep::Kind::kRequire: {
        const std::string v = text(s.value);
        const bool slack = !s.slack.is_zero();
        std::string cond;
        switch (s.require) {
          case DyadStep::Require::kNonNegative:
            cond = "!(" + v + " >= Scalar(0))";
            if (slack) cond += " && !(" + v + " >= -(" + text(s.slack) + "))";
            break;
          case DyadStep::Require::kAbsAtMostOne:
            cond = "!(abs(" + v + ") <= Scalar(1))";
            if (slack) cond += " && !(abs(" + v + ") <= Scalar(1) + " + text(s.slack) + ")";
            break;
          case DyadStep::Require::kPositive:
            cond = "!(" + v + " > Scalar(0))";
            break;
          case DyadStep::Require::kNonZero:
            cond = v + " == Scalar(0)";
            break;
        }
        const std::string status = s.singular ? "kSingular" : "kNotAssemblable";
        P->push_back(Raw("if (" + cond + ") return {SolveStatus::" + status + ", " + N(bi) + ", iterations, " +
                         text(s.measure) + "};"));
        if (s.has_clamped) {
          // Within rounding of the range: clamped into it (the touching configuration).
          const std::string c = DyadLocalName(s.clamped_local) + f.suffix;
          if (s.require == DyadStep::Require::kNonNegative)
            P->push_back(Raw("const Scalar " + c + " = " + v + " > Scalar(0) ? " + v + " : Scalar(0);"));
          else
            P->push_back(Raw("const Scalar " + c + " = " + v + " > Scalar(1) ? Scalar(1) : (" + v +
                             " < Scalar(-1) ? Scalar(-1) : " + v + ");"));
          printer->Name(s.clamped, c);
        }
        break;
      }
      case DyadStep::Kind::kAngle:
        if (!trig_only) angle(s);
        break;
      case DyadStep::Kind::kValue:
        P->push_back(Store(phi_ref(s.col), s.value));
        pending_store = true;
        break;
    }
  }
  if (pending_store) P->push_back(Raw(""));
  for (size_t i = 0; i < angles_from && !trig_only; ++i)
    if (f.steps[i].kind == DyadStep::Kind::kAngle || f.steps[i].kind == DyadStep::Kind::kValue)
      check_finite(f.steps[i]);
  // The form's last angles and their checks, after everything else the block prints.
  auto last_angles = [&] {
    if (trig_only) return;
    for (size_t i = angles_from; i < f.steps.size(); ++i) angle(f.steps[i]);
    for (size_t i = angles_from; i < f.steps.size(); ++i) check_finite(f.steps[i]);
  };
  // 1 / norm2 of each direction (a parameter only for a dyad's link lengths: EvalRhs
  // computes it once per parameter set), for the direction cosines and for the branch
  // measure below when its denominator is the directions' norms: then the branch measure
  // multiplies by the inverses instead of dividing (one division less per block), and
  // SolvePositions and SolvePositionsTrig compute it the same way (the same bits). Trig
  // only: always; SolvePositions: when they serve the branch measure (else only inside
  // `if (trig != nullptr)` below).
  ex norms = 1;
  for (const DyadTrig& t : f.trig) norms *= t.norm2;
  const bool shared_inverses = trig_only || (f.has_branch && f.branch_den_positive && !f.trig.empty() &&
                                             !f.branch_den.is_equal(GiNaC::ex(1)) &&
                                             (f.branch_den - norms).expand().is_zero());
  ex inverse_norms = 1;
  if (shared_inverses)
    for (const DyadTrig& t : f.trig) {
      ex inv;
      P->push_back(Define(t.inv_name + f.suffix, 1 / t.denom, &inv));
      printer->Name(inv, t.inv_name + f.suffix);
      inverse_norms *= t.on_axis() ? inv * inv : inv;  // 1/norm2 = (1/a_x)^2 on an axis
    }
  // dot * inverse, dot in parentheses when it is a sum.
  auto scaled = [&](const ex& dot, const std::string& inv) {
    const std::string d = text(dot);
    return (GiNaC::is_a<GiNaC::add>(dot) ? "(" + d + ")" : d) + " * " + inv;
  };
  if (f.has_branch) {
    // The branch-point signal: the smallest relative discriminant over the blocks.
    const std::string name = "branch" + f.suffix;
    const std::string num = text(f.branch_num);
    std::string value;
    if (f.branch_den.is_equal(GiNaC::ex(1)))
      value = num;
    else if (shared_inverses && f.branch_den_positive && !f.trig.empty() && (f.branch_den - norms).expand().is_zero()) {
      ex branch;  // the denominator is the directions' norms: their inverses, no division
      P->push_back(Define(name, f.branch_num * inverse_norms, &branch));
      printer->Name(branch, name);
    } else if (f.branch_den_positive)
      value = "(" + num + ") / (" + text(f.branch_den) + ")";
    else {
      const std::string den = text(f.branch_den);
      value = "(" + den + ") > Scalar(0) ? (" + num + ") / (" + den + ") : Scalar(0)";
    }
    if (!value.empty()) P->push_back(Raw("const Scalar " + name + " = " + value + ";"));
    P->push_back(Raw("if (" + name + " < branch_measure) {"));
    P->push_back(Raw("  branch_measure = " + name + ";"));
    P->push_back(Raw("  branch_block = " + N(bi) + ";"));
    P->push_back(Raw("}"));
  }
  if (f.trig.empty()) {
    last_angles();
    return;
  }
  if (trig_only) {
    // Into the function's locals cos_phi<i>, sin_phi<i> (declared by SolveTrigSpec before
    // the block), not through *trig: a store through the pointer may alias the parameters,
    // which the compiler would then load again, and reading it back waits on the store.
    // SolvePositionsTrig and EvalRhs store them to *trig at their end.
    std::vector<std::string> values;
    for (const DyadTrig& t : f.trig) {
      const std::string c = "cos_phi" + N(t.col), s = "sin_phi" + N(t.col);
      P->push_back(Raw(c + " = " + scaled(t.dot, t.inv_name + f.suffix) + ";"));
      P->push_back(Raw(s + " = " + scaled(t.cross, t.inv_name + f.suffix) + ";"));
      values.push_back(c);
      values.push_back(s);
      (*trig_done)[t.col] = true;
    }
    // As SolvePositions' check of its angles: nothing non-finite comes out as converged.
    // A form whose checks bound what they let through (finite_by_checks) needs no test here.
    if (f.finite_by_checks) return;
    // One test on the sum of the x - x (0 exactly when every x is finite, else NaN); the
    // measure reported is the first non-finite value, as one test per value gave.
    std::string sum, first;
    for (const std::string& x : values) sum += (sum.empty() ? "" : " + ") + ("(" + x + " - " + x + ")");
    for (size_t i = 0; i + 1 < values.size(); ++i)
      first += "!(" + values[i] + " - " + values[i] + " == Scalar(0)) ? " + values[i] + " : ";
    first += values.back();
    P->push_back(Raw("if (!(" + sum + " == Scalar(0))) return {SolveStatus::kSingular, " + N(bi) +
                     ", iterations, " + first + "};"));
    return;
  }
  P->push_back(Raw("if (trig != nullptr) {"));
  if (!shared_inverses)
    for (const DyadTrig& t : f.trig) {
      const std::string denom = text(t.denom);
      P->push_back(Raw("  const Scalar " + t.inv_name + f.suffix + " = Scalar(1) / " +
                       (GiNaC::is_a<GiNaC::symbol>(t.denom) ? denom : "(" + denom + ")") + ";"));
    }
  for (const DyadTrig& t : f.trig) {
    P->push_back(Raw("  trig->cos_phi(" + N(t.col) + ") = " + scaled(t.dot, t.inv_name + f.suffix) + ";"));
    P->push_back(Raw("  trig->sin_phi(" + N(t.col) + ") = " + scaled(t.cross, t.inv_name + f.suffix) + ";"));
    (*trig_done)[t.col] = true;
  }
  P->push_back(Raw("}"));
  last_angles();
}

// Newton–Raphson on one block: residual and Jacobian of its rows over its unknowns.
void NewtonPositions(const Kinematics& k, const Block& b, int bi, Program* P) {
  const int n = static_cast<int>(b.cols.size());
  const std::string t = "_b" + N(bi), sz = N(n);
  P->push_back(Raw("Vec<Scalar, " + sz + "> r" + t + ";"));
  P->push_back(Raw("Mat<Scalar, " + sz + ", " + sz + "> J" + t + " = Mat<Scalar, " + sz + ", " + sz + ">::Zero();"));
  P->push_back(Raw("for (int iteration = 0;; ++iteration) {"));
  for (int r = 0; r < n; ++r) P->push_back(Store("  r" + t + "(" + N(r) + ")", k.Phi[b.rows[r]]));
  P->push_back(Raw("  Scalar norm" + t + " = Scalar(0);"));
  // The largest |residual|, NaN if any is NaN (a NaN never compares greater, so the max
  // alone would skip it and call a NaN residual converged).
  P->push_back(Raw("  for (int i = 0; i < " + sz + " && norm" + t + " == norm" + t + "; ++i) if (!(abs(r" + t +
                   "(i)) <= norm" + t + ")) norm" + t + " = abs(r" + t + "(i));"));
  // Converged: stop at this iterate (no step after the residual test has passed, so an
  // exactly singular Jacobian at a converged configuration is never solved with).
  P->push_back(Raw("  if (norm" + t + " <= tol) break;"));
  P->push_back(Raw("  if (iteration == max_iterations || !(norm" + t + " - norm" + t +
                   " == Scalar(0))) return {SolveStatus::kDidNotConverge, " + N(bi) + ", iterations, norm" + t + "};"));
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      if (!k.Phi_phi(b.rows[r], b.cols[c]).is_zero())
        P->push_back(Store("  J" + t + "(" + N(r) + ", " + N(c) + ")", k.Phi_phi(b.rows[r], b.cols[c])));
  P->push_back(Raw("  ++iterations;"));
  P->push_back(Raw("  const Vec<Scalar, " + sz + "> delta" + t + " = J" + t + ".partialPivLu().solve(r" + t + ");"));
  for (int c = 0; c < n; ++c) P->push_back(Raw("  phi(" + N(b.cols[c]) + ") -= delta" + t + "(" + N(c) + ");"));
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
           "Newton–Raphson from the given phi for the other blocks. Solves into a local copy: *phi_io",
           "changes only when the report says kConverged, and then holds finite values only. The",
           "report's branch_measure says how close a closed-form block is to a branch point (see",
           "SolveReport)."};
  f.args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "q", Dir::kIn, "Inputs", "dim kNq"));
  f.args.push_back(Arg("Vec<Scalar, Sizes::kNphi>*", "phi_io", Dir::kInOut,
                       "In: the starting guess (a predictor) and, for angles found in closed form, the reference "
                       "they are kept continuous with. Out: the solution, when the report says kConverged; unchanged "
                       "otherwise",
                       "dim kNphi"));
  Argument modes = Arg("const std::array<int, Sizes::kNumBlocks>&", "modes", Dir::kIn,
                       "Assembly mode of each block (ignored for Newton blocks)", "dim kNumBlocks");
  modes.member_default = "kDefaultModes";
  f.args.push_back(modes);
  f.args.push_back(
      Arg("int", "max_iterations", Dir::kIn, "Newton blocks: at most this many iterations.", "", false, "20"));
  f.args.push_back(Arg("const Scalar&", "tolerance", Dir::kIn,
                       "Newton blocks stop at the first iterate with |Phi_block|_inf <= tolerance; "
                       "tolerance <= 0 means 1e-12, 1e-5 for float.",
                       "", false, "Scalar(0)"));
  f.args.push_back(Arg("Out<Trig<Scalar>>", "trig", Dir::kOut,
                       "sin and cos of the angle coordinates at the solution (for EvalCoefficients()), when the "
                       "report says kConverged",
                       "", true, "nullptr"));
  bool newton = false;
  for (const Block& b : t.blocks) newton |= b.solve == BlockSolve::kNewton;
  // Solved into a local copy, written back on success only. No blocks (no loop: kNphi = 0, e.g. a
  // pendulum): nothing reads phi (its argument is then void-cast).
  Program prologue;
  if (!t.blocks.empty()) prologue.push_back(Raw("Vec<Scalar, Sizes::kNphi> phi = *phi_io;"));
  prologue.push_back(Raw("int iterations = 0;"));
  if (newton) {
    prologue.push_back(Raw("// tolerance <= 0: 1e-12 (model units), 1e-5 for float"));
    prologue.push_back(
        Raw("const Scalar tol = tolerance > Scalar(0) ? tolerance : Scalar(sizeof(Scalar) <= 4 ? 1e-5 : 1e-12);"));
  }
  f.body.push_back(prologue);
  trig_done->assign(k.phi.size(), false);
  bool branch = false;
  std::vector<ClosedForm> forms;
  for (size_t bi = 0; bi < t.blocks.size(); ++bi) {
    const Block& b = t.blocks[bi];
    // Each block is its own program: its values depend on the phi the blocks before it
    // wrote, so no subexpression may be shared across blocks.
    Program P;
    P.push_back(Raw("{  // block " + N(static_cast<int>(bi)) + ": " + b.Describe(k)));
    if (b.solve == BlockSolve::kNewton) {
      NewtonPositions(k, b, static_cast<int>(bi), &P);
    } else {
      const ClosedForm form = FormulateClosedForm(k, b, static_cast<int>(bi));
      branch |= form.has_branch;
      forms.push_back(form);
      ClosedFormPositions(form, static_cast<int>(bi), &P, printer, trig_done);
    }
    P.push_back(Raw("}"));
    f.body.push_back(P);
  }
  if (branch) {
    // The machine epsilon of Scalar (float, else double's), for the rounding slack of the
    // closed forms' discriminants.
    f.body.front().push_back(
        Raw("const Scalar epsilon = Scalar(sizeof(Scalar) <= 4 ? 1.1920928955078125e-07 : 2.220446049250313e-16);"));
    f.body.front().push_back(Raw("Scalar branch_measure = Scalar(1);"));
    f.body.front().push_back(Raw("int branch_block = -1;"));
  }
  DefineNorm2Bounds(forms, &f.body.front());  // the range of a dyad's squared lengths
  f.body.push_back({Raw(""), Raw(t.blocks.empty() ? "" : "*phi_io = phi;"),
                    Raw(branch ? "return {SolveStatus::kConverged, -1, iterations, Scalar(0), branch_measure, "
                                 "branch_block};"
                               : "return {SolveStatus::kConverged, -1, iterations, Scalar(0)};")});
  return f;
}

FunctionSpec SolveTrigSpec(const SymbolicTable& t, CxxPrinter* printer, bool* possible) {
  const Kinematics& k = t.kinematics();
  FunctionSpec f;
  *possible = false;
  if (t.blocks.empty()) return f;
  for (const Coordinate& c : k.phi)
    if (!c.is_angle) return f;
  std::vector<ClosedForm> forms;
  for (size_t bi = 0; bi < t.blocks.size(); ++bi) {
    const Block& b = t.blocks[bi];
    if (b.solve == BlockSolve::kNewton) return f;
    forms.push_back(FormulateClosedForm(k, b, static_cast<int>(bi)));
    // Every angle of the block from its own dot and cross products.
    for (const DyadStep& s : forms.back().steps) {
      if (s.kind == DyadStep::Kind::kValue) return f;
      if (s.kind != DyadStep::Kind::kAngle) continue;
      bool has = false;
      for (const DyadTrig& tr : forms.back().trig) has |= tr.col == s.col;
      if (!has) return f;
    }
  }
  f.name = "SolvePositionsTrig";
  f.model_member = "SolveTrig";
  f.returns = "SolveReport<Scalar>";
  f.reindent = true;
  f.doc = {"\\brief sin and cos of every angle at inputs q, as SolvePositions() would give them in *trig, without",
           "computing the angles themselves (no atan2): the closed forms' direction cosines, for",
           "EvalCoefficients() and the functions taking a Trig argument, which then do not read their phi",
           "argument. The same blocks, modes, statuses, measures and branch_measure as SolvePositions(); *trig",
           "holds finite values when the report says kConverged (and is meaningless otherwise). Generated only",
           "when every block is a closed form giving its angles' direction cosines and nothing downstream",
           "reads an angle other than through its sin and cos."};
  f.args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "q", Dir::kIn, "Inputs", "dim kNq"));
  f.args.push_back(Arg("const std::array<int, Sizes::kNumBlocks>&", "modes", Dir::kIn,
                       "Assembly mode of each block (Model::kDefaultModes: the model's assembly)", "dim kNumBlocks"));
  f.args.push_back(Arg("Trig<Scalar>*", "trig", Dir::kOut,
                       "sin and cos of q and phi at the solution, when the report says kConverged; not nullptr."));
  Program prologue;
  prologue.push_back(Raw("int iterations = 0;"));
  f.body.push_back(prologue);
  std::vector<bool> trig_done(k.phi.size(), false);
  bool branch = false;
  for (size_t bi = 0; bi < t.blocks.size(); ++bi) {
    Program P;
    // The direction cosines the block solves, read by later blocks and stored to *trig at
    // the end: the function's locals (ClosedFormPositions(), trig_only).
    std::string locals;
    for (const DyadTrig& tr : forms[bi].trig)
      locals += (locals.empty() ? "" : ", ") + ("cos_phi" + N(tr.col) + ", sin_phi" + N(tr.col));
    if (!locals.empty()) P.push_back(Raw("Scalar " + locals + ";"));
    P.push_back(Raw("{  // block " + N(static_cast<int>(bi)) + ": " + t.blocks[bi].Describe(k)));
    branch |= forms[bi].has_branch;
    ClosedFormPositions(forms[bi], static_cast<int>(bi), &P, printer, &trig_done, true);
    P.push_back(Raw("}"));
    f.body.push_back(P);
  }
  if (branch) {
    f.body.front().push_back(
        Raw("const Scalar epsilon = Scalar(sizeof(Scalar) <= 4 ? 1.1920928955078125e-07 : 2.220446049250313e-16);"));
    f.body.front().push_back(Raw("Scalar branch_measure = Scalar(1);"));
    f.body.front().push_back(Raw("int branch_block = -1;"));
  }
  DefineNorm2Bounds(forms, &f.body.front());
  f.body.push_back({Raw(""), Raw(branch ? "return {SolveStatus::kConverged, -1, iterations, Scalar(0), branch_measure, "
                                          "branch_block};"
                                        : "return {SolveStatus::kConverged, -1, iterations, Scalar(0)};")});
  *possible = true;
  return f;
}

}  // namespace mechgen
