// EvalStatics: the statics of symbolic/statics.h stored into the generated Statics struct.
#include <algorithm>
#include <functional>
#include <map>
#include <tuple>
#include <set>

#include "codegen/functions.h"
#include "codegen/hoist.h"
#include "codegen/sha256.h"
#include "codegen/slot_spelling.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using Dir = Argument::Direction;

std::string N(int i) { return std::to_string(i); }
std::string Idx(int i, int j) { return "(" + N(i) + ", " + N(j) + ")"; }

void CollectSymbols(const ex& e, std::set<ex, GiNaC::ex_is_less>* out) {
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it)) out->insert(*it);
}

// A sum's sign as the printed text fixes it: the term whose coefficient-free text sorts first
// has a positive coefficient. (GiNaC normalizes the sign of a sum raised to an integer power
// by its leading term in its own order, which changes from run to run: a load such as
// P0 h / (h + a + b - s) would print as either sign.)
bool NeedsFlip(const ex& sum, CxxPrinter* printer) {
  std::string best;
  bool negative = false, first = true;
  for (size_t i = 0; i < sum.nops(); ++i) {
    const ex t = sum.op(i);
    ex core = t;
    bool neg = false;
    if (GiNaC::is_a<GiNaC::numeric>(t)) {
      core = 1;
      neg = GiNaC::ex_to<GiNaC::numeric>(t).is_negative();
    } else if (GiNaC::is_a<GiNaC::mul>(t)) {
      ex c = 1;
      for (size_t j = 0; j < t.nops(); ++j)
        if (GiNaC::is_a<GiNaC::numeric>(t.op(j))) c *= t.op(j);
      core = t / c;
      neg = GiNaC::ex_to<GiNaC::numeric>(c).is_negative();
    }
    const std::string& key = printer->Key(core);
    if (first || key < best) {
      best = key;
      negative = neg;
      first = false;
    }
  }
  return negative;
}

// Every sum raised to an integer power becomes a named local of a fixed sign, defined before
// the statement that first needs it, so that the text is the same on every run: the sums
// are rewritten from the inside out, each named after a hash of its own text (not after
// the order GiNaC visits them in, which changes from run to run) and defined inner sums
// first, then in the order of their text.
void NameSumPowers(Program* program, CxxPrinter* printer) {
  struct Sum {
    ex symbol;
    int depth = 0;
  };
  std::map<std::string, Sum> named;  // canonical text -> its local
  for (const Statement& s : *program)  // the locals' names, for printing the sums' text
    if (s.kind == Statement::Kind::kDefine) printer->Name(s.symbol, s.target);
  Program out;
  for (Statement s : *program) {
    if (s.kind == Statement::Kind::kDefine || s.kind == Statement::Kind::kStore) {
      std::vector<std::tuple<int, std::string, Statement>> before;
      struct Rewrite : GiNaC::map_function {
        std::function<ex(const ex&)> f;
        ex operator()(const ex& e) override { return f(e); }
      } rewrite;
      rewrite.f = [&](const ex& e) -> ex {
        const ex r = e.map(rewrite);
        if (!GiNaC::is_a<GiNaC::power>(r) || !GiNaC::is_a<GiNaC::add>(r.op(0)) ||
            !GiNaC::is_a<GiNaC::numeric>(r.op(1)) || !GiNaC::ex_to<GiNaC::numeric>(r.op(1)).is_integer())
          return r;
        // The expanded sum: GiNaC's unexpanded products of sums carry a sign picked by whichever
        // term it saw first (run-dependent), the expanded form does not.
        const ex expanded = r.op(0).expand();
        const bool flip = NeedsFlip(expanded, printer);
        const ex base = flip ? (-expanded).expand() : expanded;
        const std::string text = printer->Print(base);
        auto it = named.find(text);
        if (it == named.end()) {
          int depth = 0;
          for (const auto& [t, other] : named)
            if (base.has(other.symbol)) depth = std::max(depth, other.depth + 1);
          std::string name = "sum_" + Sha256Hex(text).substr(0, 8);
          for (const auto& [t, other] : named)
            if (printer->Print(other.symbol) == name) name += "_" + N(static_cast<int>(named.size()));
          ex sym;
          Statement def = Define(name, base, &sym);
          printer->Name(sym, name);
          it = named.emplace(text, Sum{sym, depth}).first;
          before.emplace_back(depth, text, def);
        }
        const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(r.op(1));
        return (flip && n.is_odd() ? -1 : 1) * GiNaC::pow(it->second.symbol, n);
      };
      s.value = rewrite(s.value);
      std::sort(before.begin(), before.end(), [](const auto& x, const auto& y) {
        return std::get<0>(x) != std::get<0>(y) ? std::get<0>(x) < std::get<0>(y) : std::get<1>(x) < std::get<1>(y);
      });
      for (const auto& [depth, text, def] : before) out.push_back(def);
    }
    out.push_back(s);
  }
  *program = out;
}

}  // namespace

// Drops the named locals that no later statement reads (a reaction the model did not ask
// for, a multiplier no requested force needs): an unused local is a warning in the
// generated code.
void PruneUnusedDefines(Program* program) {
  std::set<ex, GiNaC::ex_is_less> used;
  Program kept;
  for (auto it = program->rbegin(); it != program->rend(); ++it) {
    const Statement& s = *it;
    if (s.kind == Statement::Kind::kDefine) {
      if (!used.count(s.symbol)) continue;
      CollectSymbols(s.value, &used);
    } else if (s.kind == Statement::Kind::kStore) {
      CollectSymbols(s.value, &used);
    }
    kept.push_back(s);
  }
  program->assign(kept.rbegin(), kept.rend());
}

FunctionSpec EvalStaticsSpec(const Model& m, const StaticsTable& st, CxxPrinter* printer) {
  FunctionSpec f;
  f.name = "EvalStatics";
  f.fills = OutputStruct::kStatics;
  f.model_member = "Forces";  // (the struct is Statics)
  f.doc = {"\\brief Statics by virtual work (Paul ch. 5) at a closed configuration: what the model asked of",
           "Q (generalized forces of the loads, springs, weights and the given friction loads),",
           "drive = -Q (what each input's actuator applies for equilibrium), V and its derivatives,",
           "the joint reactions (kReactionNames) and the friction joints' normal forces."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn,
                       "EvalCoefficients() at this (q, phi): K, L and Phi_phi are read from it."));
  f.args.push_back(Arg("Statics<Scalar>*", "out", Dir::kOut, "Statics; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "friction loads f (kFrictionJoints): the friction torque of link_a on link_b at a revolute "
                       "joint (counter-clockwise +), the friction force on the slider along +u at a prismatic one; "
                       "nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  f.args.push_back(Arg("const typename NonDeduced<Trig<Scalar>>::type*", "trig", Dir::kIn,
                       "sin and cos of q and phi from SolvePositions() at this (q, phi), or nullptr: they are "
                       "computed here.",
                       "", false, "nullptr"));
  f.notes = {"\\note Everything is linear in the friction loads; the runtime iterates them on the normal",
             "forces (mechgen/statics). Near a dead point (Phi_phi singular) the multipliers, and so the",
             "reactions and the drive of a non-input load path, grow without bound: check the conditioning."};
  if (st.at_speed == nullptr) {
    // The loads that read time (no velocity): taken at t = 0 here.
    for (const auto& [load, reads] : m.at_rest_loads)
      f.notes.push_back("\\note At rest: the " + load + " is taken with " + reads +
                        (reads.find(',') == std::string::npos ? " = 0" : " all 0") + " (its value in a slow motion).");
    f.body = {StaticsBody(m, st, printer)};
    return f;
  }
  // What reads a velocity: taken at the velocities given (the statics along a motion at that
  // speed: the kinetostatics without the inertia forces), at rest without them.
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNq>>::type*", "velocities", Dir::kIn,
                       "input velocities qd (the dependent ones K qd) at which the loads that read a velocity, "
                       "the dampers and the viscous joint friction (kStaticsAtSpeed) are taken, t = 0; nullptr: "
                       "at rest (qd = 0).",
                       "dim kNq", true, "nullptr"));
  for (const auto& [load, reads] : m.at_rest_loads)
    f.notes.push_back("\\note At rest: the " + load + " is taken with " + reads +
                      (reads.find(',') == std::string::npos ? " = 0" : " all 0") + " (its value in a slow motion)" +
                      (reads.find("_dot") == std::string::npos ? "." : ", at `velocities` where they are given."));
  for (const Damper& d : m.dampers)
    f.notes.push_back("\\note Velocities: the damper '" + d.name + "' acts at `velocities` (not at rest).");
  for (const Friction& fr : m.friction)
    if (!fr.viscous.is_zero())
      f.notes.push_back("\\note Velocities: the viscous friction at joint " + m.joints[fr.joint].name +
                        " acts at `velocities` (not at rest).");
  NameSlots(st.slots, printer);  // the table at rest's, which EvalStiffness and the others read
  Program P = StaticsBody(m, *st.at_speed, printer);
  // The velocities the body reads as qd(j): the argument's, or 0 (at rest).
  P.insert(P.begin(), {Raw("Vec<Scalar, Sizes::kNq> qd;"),
                       Raw("if (velocities != nullptr) qd = *velocities; else qd.setZero();")});
  f.body = {P};
  const std::string n = N(static_cast<int>(st.speed_items.size()));
  std::string items;
  for (const std::string& item : st.speed_items) items += std::string(items.empty() ? "" : ", ") + "\"" + item + "\"";
  f.model_constants =
      "  /// What EvalStatics (Model::Forces) takes at its argument `velocities`, and at rest without it:\n"
      "  /// the loads that read a velocity (with the velocities they read), the dampers and the viscous\n"
      "  /// joint friction.\n"
      "  static constexpr int kNumStaticsAtSpeed = " + n + ";\n"
      "  static constexpr std::array<const char*, kNumStaticsAtSpeed> kStaticsAtSpeed{ " + items + " };\n";
  return f;
}

namespace {

// Prunes the unused locals, reads the friction loads the rest uses (from the argument, or
// 0), and names the sums raised to powers (deterministic text).
Program Finish(Program P, const StaticsTable& st, CxxPrinter* printer) {
  PruneUnusedDefines(&P);
  // The friction loads the remaining statements read (a friction joint whose force enters
  // nothing that was asked for is not read), each from the argument or 0.
  std::set<ex, GiNaC::ex_is_less> used;
  for (const Statement& s : P)
    if (s.kind == Statement::Kind::kDefine || s.kind == Statement::Kind::kStore) CollectSymbols(s.value, &used);
  Program prologue;
  for (const auto& [sym, slot] : st.slots.all())
    if (slot.kind == Slot::Kind::kFriction && used.count(sym))
      prologue.push_back(Raw("const Scalar " + SlotSpelling(slot) + " = friction != nullptr ? (*friction)(" +
                             std::to_string(slot.i) + ") : Scalar(0);"));
  P.insert(P.begin(), prologue.begin(), prologue.end());
  NameSumPowers(&P, printer);
  return P;
}

}  // namespace

Program FinishAppliedProgram(Program P, const StaticsTable& st, CxxPrinter* printer) { return Finish(P, st, printer); }

Program StaticsBody(const Model& m, const StaticsTable& st, CxxPrinter* printer) {
  const int nq = static_cast<int>(m.inputs.size());
  NameSlots(st.slots, printer);
  Program P = st.program;
  if (st.forces)
    for (int j = 0; j < nq; ++j) {
      P.push_back(Store("out->Q(" + N(j) + ")", st.Q[j]));
      P.push_back(Store("out->drive(" + N(j) + ")", st.drive[j]));
    }
  if (st.potential) {
    P.push_back(Store("out->V", st.V));
    for (int j = 0; j < nq; ++j) P.push_back(Store("out->dV_dq(" + N(j) + ")", st.dV_dq[j]));
  }
  for (size_t i = 0; i < st.R.size(); ++i) P.push_back(Store("out->R(" + N(static_cast<int>(i)) + ")", st.R[i]));
  for (size_t i = 0; i < st.normal.size(); ++i) {
    P.push_back(Store("out->normal(" + N(static_cast<int>(i)) + ")", st.normal[i]));
    P.push_back(Store("out->gain(" + N(static_cast<int>(i)) + ")", st.gain[i]));
    for (int j = 0; j < nq; ++j) P.push_back(Store("out->K_rel" + Idx(static_cast<int>(i), j), st.K_rel[i][j]));
  }
  return Finish(P, st, printer);
}

FunctionSpec EvalStiffnessSpec(const Model& m, const StaticsTable& st, CxxPrinter* printer) {
  const int nq = static_cast<int>(m.inputs.size());
  FunctionSpec f;
  f.name = "EvalStiffness";
  f.model_member = "Stiffness";
  f.doc = {"\\brief The second derivatives of the statics along the motion (Paul §6.5.2): d2V/dq2 and the",
           "stiffness -dQ/dq (friction excluded). An equilibrium (Q = 0) is stable where the stiffness is",
           "positive definite. Apart from EvalStatics: the derivatives of the springs' and loads' expressions",
           "are long, and only the search for equilibria needs them."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn,
                       "EvalCoefficients() at this (q, phi): K and L are read from it."));
  f.args.push_back(Arg("Statics<Scalar>*", "out", Dir::kOut, "Statics: d2V_dq2 and stiffness are set; not nullptr."));
  Program P;
  for (size_t i = 0; i < st.d2V_dq2.size(); ++i)
    P.push_back(Store("out->d2V_dq2" + Idx(static_cast<int>(i) % nq, static_cast<int>(i) / nq), st.d2V_dq2[i]));
  for (size_t i = 0; i < st.stiffness_q.size(); ++i)
    P.push_back(Store("out->stiffness" + Idx(static_cast<int>(i) % nq, static_cast<int>(i) / nq), st.stiffness_q[i]));
  NameSumPowers(&P, printer);
  f.body = {P};
  return f;
}

}  // namespace mechgen

namespace mechgen {

FunctionSpec EvalDynamicsSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer) {
  const int nq = static_cast<int>(m.inputs.size());
  const StaticsTable& a = *dt.applied;
  NameSlots(a.slots, printer);
  FunctionSpec f;
  f.name = "EvalDynamics";
  f.fills = OutputStruct::kDynamics;
  f.model_member = "Dynamics";
  f.doc = {"\\brief The generalized equation of motion (Paul ch. 6) at a closed configuration and velocity:",
           "I(q) qdd + h(q, qd) = Q(t, q, qd), h = C (qd (x) qd) (one DOF: I qdd + I'/2 qd^2 = Q), with the",
           "kinetic energy T, the potential energy V and the power P_nc of the non-conservative forces."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities dq/dt", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn,
                       "EvalCoefficients() at this (q, phi): K and L are read from it."));
  f.args.push_back(Arg("Dynamics<Scalar>*", "out", Dir::kOut, "Dynamics; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads f (kFrictionJoints), as in EvalStatics(); nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  f.args.push_back(Arg("const typename NonDeduced<Trig<Scalar>>::type*", "trig", Dir::kIn,
                       "sin and cos of q and phi from SolvePositions() at this (q, phi), or nullptr: they are "
                       "computed here.",
                       "", false, "nullptr"));
  f.notes = {"\\note The accelerations: qdd = I^-1 (Q - h); I is positive definite where the mechanism can move",
             "(it loses rank only where every massive link stands still, at a dead point of a massless chain)."};
  Program P = dt.program;
  for (int j = 0; j < nq; ++j)
    for (int k = 0; k < nq; ++k) P.push_back(Store("out->I" + Idx(j, k), dt.I[j + nq * k]));
  for (int j = 0; j < nq; ++j)
    for (int kl = 0; kl < nq * nq; ++kl) P.push_back(Store("out->dI_dq" + Idx(j, kl), dt.dI_dq[j + nq * kl]));
  for (int j = 0; j < nq; ++j)
    for (int kl = 0; kl < nq * nq; ++kl) P.push_back(Store("out->C" + Idx(j, kl), dt.C[j + nq * kl]));
  for (int j = 0; j < nq; ++j) P.push_back(Store("out->h(" + N(j) + ")", dt.h[j]));
  for (int j = 0; j < nq; ++j) P.push_back(Store("out->Q(" + N(j) + ")", dt.Q[j]));
  P.push_back(Store("out->T", dt.T));
  P.push_back(Store("out->V", dt.V));
  P.push_back(Store("out->P_nc", dt.P_nc));
  f.body = {Finish(P, a, printer)};
  return f;
}

FunctionSpec EvalRhsSpec(const Model& m, const SymbolicTable& t, const DynamicsTable& dt, CxxPrinter* printer) {
  const Kinematics& k = t.kinematics();
  const int nq = k.nq(), nphi = k.nphi();
  const StaticsTable& a = *dt.applied;
  NameSlots(a.slots, printer);
  FunctionSpec f;
  f.name = "EvalRhs";
  f.fills = OutputStruct::kRhs;
  f.model_member = "Rhs";
  f.returns = "SolveReport<Scalar>";
  f.reindent = true;
  // Inlined where it is called (an integrator's inner loop): not compiled into <model>.cc,
  // and declared inline (GCC does not inline a function of its size called from several
  // places otherwise: a call, the outputs through memory, ~10% of a four-bar's right-hand side).
  f.instantiate = false;
  f.inline_hint = true;
  f.doc = {"\\brief The right-hand side of the equation of motion at a state (t, q, qd), in one pass:",
           "SolvePositionsTrig() (the closed forms' direction cosines, no angle), K and L, then I, h, Q",
           "(Paul §6.4, §6.6.1: qdd = I^-1 (Q - h)), with what a simulation samples (K, T, V, P_nc, Phi_phi).",
           "Nothing else of EvalCoefficients() (no residual, no points) and of EvalDynamics() (no C, dI_dq)",
           "is computed: the fast path of an integrator's stages. The same statuses and branch_measure as",
           "SolvePositionsTrig(); *trig holds finite values when the report says kConverged, and so does *out",
           "except at a dead point (Phi_phi singular to rounding: its determinant 0, branch_measure 0 for a dyad),",
           "where K and L do not exist: check Phi_phi's conditioning first (the runtime does)."};
  f.args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  f.args.push_back(Arg("const RhsConstants<Scalar>&", "rc", Dir::kIn,
                       "What depends on the parameters only: PrepareRhs(p) (again after p changes)."));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "q", Dir::kIn, "Inputs", "dim kNq"));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities dq/dt", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("const std::array<int, Sizes::kNumBlocks>&", "modes", Dir::kIn,
                       "Assembly mode of each block (Model::kDefaultModes: the model's assembly)", "dim kNumBlocks"));
  f.args.push_back(Arg("Trig<Scalar>*", "trig", Dir::kOut, "sin and cos of q and phi at the solution; not nullptr."));
  f.args.push_back(Arg("Rhs<Scalar>*", "out", Dir::kOut, "Rhs; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads f (kFrictionJoints), as in EvalStatics(); nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  // EvalCoefficients' K and L (and Phi_phi's named entries) in place of what EvalDynamics
  // reads from its Coefficients argument.
  GiNaC::exmap from_c;
  for (const auto& [sym, slot] : a.slots.all()) {
    if (slot.kind == Slot::Kind::kK)
      from_c[sym] = t.K[slot.i][slot.j];
    else if (slot.kind == Slot::Kind::kL)
      from_c[sym] = t.L(slot.i, slot.j % nq, slot.j / nq);
    else if (slot.kind == Slot::Kind::kPhiPhi)
      from_c[sym] = t.Phi_phi_named(slot.i, slot.j);
  }
  Program P = VelocityPrograms(t);
  GiNaC::exmap inlined;  // the dynamics' locals in terms of K, L, the angles and the parameters
  for (Statement s : dt.program) {
    if (s.kind == Statement::Kind::kDefine || s.kind == Statement::Kind::kStore) s.value = s.value.subs(from_c);
    if (s.kind == Statement::Kind::kDefine) inlined[s.symbol] = s.value.subs(inlined);
    P.push_back(s);
  }
  // Each output as a polynomial in K, L and the angles' sin and cos reduced by
  // sin^2 + cos^2 = 1 (hoist.h), where that stays small; else through the locals.
  ExSet params;
  for (const Parameter& prm : m.params) params.insert(prm.symbol);
  std::vector<std::pair<ex, ex>> sin_cos;
  std::vector<std::string> angle_names;  // q<j>, phi<i>: as the generated sin_q0, cos_phi1
  for (int j = 0; j < nq; ++j)
    if (k.q[j].is_angle) {
      sin_cos.emplace_back(GiNaC::sin(k.q[j].symbol), GiNaC::cos(k.q[j].symbol));
      angle_names.push_back("q" + N(j));
    }
  for (int i = 0; i < nphi; ++i)
    if (k.phi[i].is_angle) {
      sin_cos.emplace_back(GiNaC::sin(k.phi[i].symbol), GiNaC::cos(k.phi[i].symbol));
      angle_names.push_back("phi" + N(i));
    }
  // cos(x - y) and sin(x - y) of each pair of angles (x after y), defined where an output
  // reads them (hoist.h: UseAngleDifferences), before everything else of the dynamics.
  std::vector<AngleDifference> diffs;
  std::vector<Statement> diff_defines;
  for (size_t y = 0; y < sin_cos.size(); ++y)
    for (size_t x = y + 1; x < sin_cos.size(); ++x) {
      AngleDifference d;
      d.sin_x = sin_cos[x].first;
      d.cos_x = sin_cos[x].second;
      d.sin_y = sin_cos[y].first;
      d.cos_y = sin_cos[y].second;
      const std::string name = angle_names[x] + "_minus_" + angle_names[y];
      diff_defines.push_back(Define("cos_" + name, d.cos_x * d.cos_y + d.sin_x * d.sin_y, &d.cos_d));
      diff_defines.push_back(Define("sin_" + name, d.sin_x * d.cos_y - d.cos_x * d.sin_y, &d.sin_d));
      diffs.push_back(d);
    }
  auto output = [&](const ex& value) {
    const ex v = value.subs(from_c);
    size_t terms = 0;
    const ex reduced = ReduceTrig(v.subs(inlined), sin_cos, params, &terms);
    return terms <= 48 ? UseAngleDifferences(reduced, params, &diffs) : v;
  };
  // I and C as locals; h = C (qd (x) qd) and T = 1/2 qd^T I qd from them.
  auto local = [&](const std::string& name, const ex& value) -> ex {
    const ex v = output(value);
    if (GiNaC::is_a<GiNaC::symbol>(v)) return v;
    ex sym;
    P.push_back(Define(name, v, &sym));
    return sym;
  };
  const std::vector<ex>& qd = a.qd;
  std::vector<ex> I(nq * nq), C(nq * nq * nq);
  for (int j = 0; j < nq; ++j)
    for (int kk = 0; kk < nq; ++kk) I[j + nq * kk] = local("I_eom_" + N(j) + "_" + N(kk), dt.I[j + nq * kk]);
  for (int j = 0; j < nq; ++j)
    for (int kl = 0; kl < nq * nq; ++kl)
      C[j + nq * kl] = local("C_eom_" + N(j) + "_" + N(kl % nq) + "_" + N(kl / nq), dt.C[j + nq * kl]);
  // K before the dynamics' stores, Phi_phi last (this order measured ~3% faster than K next to
  // Phi_phi at the end: bench/dynamics Rhs/Generated).
  const Program k_stores = CoefficientStores(t, false);
  P.insert(P.end(), k_stores.begin(), k_stores.end());
  ex T = 0;
  for (int j = 0; j < nq; ++j)
    for (int kk = 0; kk < nq; ++kk) {
      P.push_back(Store("out->I" + Idx(j, kk), I[j + nq * kk]));
      T += I[j + nq * kk] * qd[j] * qd[kk] / 2;
    }
  for (int j = 0; j < nq; ++j) {
    ex h = 0;
    for (int kk = 0; kk < nq; ++kk)
      for (int l = 0; l < nq; ++l) h += C[j + nq * (kk + nq * l)] * qd[kk] * qd[l];
    P.push_back(Store("out->h(" + N(j) + ")", h));
  }
  for (int j = 0; j < nq; ++j) P.push_back(Store("out->Q(" + N(j) + ")", output(dt.Q[j])));
  P.push_back(Store("out->T", T));
  P.push_back(Store("out->V", output(dt.V)));
  P.push_back(Store("out->P_nc", output(dt.P_nc)));
  const Program phi_phi_stores = PhiPhiStores(t);
  P.insert(P.end(), phi_phi_stores.begin(), phi_phi_stores.end());
  Program used_diffs;
  for (size_t i = 0; i < diffs.size(); ++i) {
    if (diffs[i].cos_used) used_diffs.push_back(diff_defines[2 * i]);
    if (diffs[i].sin_used) used_diffs.push_back(diff_defines[2 * i + 1]);
  }
  P.insert(P.begin(), used_diffs.begin(), used_diffs.end());
  f.body = {Finish(P, a, printer)};
  return f;
}

void HoistRhsConstants(const Model& m, CxxPrinter* printer, FunctionSpec* rhs, FunctionSpec* prepare) {
  ExSet params;
  for (const Parameter& prm : m.params) params.insert(prm.symbol);
  const std::vector<ex> values = HoistParameters(params, "rc.c", printer, &rhs->body);
  const std::string n = N(static_cast<int>(values.size()));
  prepare->constants = static_cast<int>(values.size());
  prepare->name = "PrepareRhs";
  prepare->fills = OutputStruct::kRhsConstants;
  prepare->model_member = "Prepare";
  prepare->doc = {"\\brief The constants EvalRhs() reads: what depends on the parameters only, computed once",
                  "(call it again after changing a parameter)."};
  prepare->args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  prepare->args.push_back(Arg("RhsConstants<Scalar>*", "rc", Dir::kOut, "The constants; not nullptr."));
  Program P;
  for (size_t i = 0; i < values.size(); ++i) P.push_back(Store("rc->c[" + N(static_cast<int>(i)) + "]", values[i]));
  prepare->body = {P};
}

FunctionSpec EvalKinetostaticsSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer) {
  const StaticsTable& st = *dt.kinetostatics;
  FunctionSpec f;
  f.name = "EvalKinetostatics";
  f.model_member = "Kinetostatics";
  f.doc = {"\\brief Kinetostatics, or inverse dynamics (Paul §6.7): the statics of EvalStatics() with d'Alembert's",
           "inertia forces -m a_G at every centre of mass and couples -J alpha added to the loads, for a",
           "prescribed motion (q, qd, qdd) at time t: Q = Q_applied(t, q, qd) - (I qdd + h), drive = -Q (what",
           "each input's actuator applies for this motion), and the reactions including the inertia forces."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities", "dim kNq"));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qdd", Dir::kIn, "Input accelerations", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn,
                       "EvalCoefficients() at this (q, phi): K, L and Phi_phi are read from it."));
  f.args.push_back(Arg("Statics<Scalar>*", "out", Dir::kOut,
                       "Statics (Q, drive, V, dV_dq, R, and normal, gain, K_rel of the friction joints); not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads f (kFrictionJoints), as in EvalStatics(); nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  f.args.push_back(Arg("const typename NonDeduced<Trig<Scalar>>::type*", "trig", Dir::kIn,
                       "sin and cos of q and phi from SolvePositions() at this (q, phi), or nullptr: they are "
                       "computed here.",
                       "", false, "nullptr"));
  f.notes = {"\\note stiffness and d2V_dq2 of the Statics struct are not set here (EvalStiffness())."};
  f.body = {StaticsBody(m, st, printer)};
  return f;
}

FunctionSpec EvalExcessSpec(const Model& /*m*/, const Kinematics& k, const DynamicsTable& dt, CxxPrinter* printer) {
  const StaticsTable& x = *dt.excess_applied;
  NameSlots(x.slots, printer);
  const int nx = k.nq() + k.nphi(), nc = k.nc();
  FunctionSpec f;
  f.name = "EvalExcess";
  f.fills = OutputStruct::kExcess;
  f.model_member = "ExcessDynamics";
  f.doc = {"\\brief The excess-coordinate formulation (Paul §6.6.2) on x = (q, phi): M xdd + h = g + Phi_x^T lambda",
           "with Phi_x xdd = gamma, at any (q, phi) (closed or not: the integrator stabilizes Phi = 0)."};
  f.args = AtConfiguration();
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities", "dim kNq"));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNphi>&", "phid", Dir::kIn, "Dependent velocities", "dim kNphi"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("Excess<Scalar>*", "out", Dir::kOut, "Excess; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads f (kFrictionJoints), as in EvalStatics(); nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  Program P = dt.excess_program;
  for (int a = 0; a < nx; ++a)
    for (int b = 0; b < nx; ++b) P.push_back(Store("out->M" + Idx(a, b), dt.M[a + nx * b]));
  for (int a = 0; a < nx; ++a) P.push_back(Store("out->h(" + N(a) + ")", dt.excess_h[a]));
  for (int a = 0; a < nx; ++a) P.push_back(Store("out->g(" + N(a) + ")", dt.g[a]));
  for (int r = 0; r < nc; ++r)
    for (int a = 0; a < nx; ++a) P.push_back(Store("out->Phi_x" + Idx(r, a), dt.Phi_x[r + nc * a]));
  for (int r = 0; r < nc; ++r) P.push_back(Store("out->Phi(" + N(r) + ")", k.Phi[r]));
  for (int r = 0; r < nc; ++r) P.push_back(Store("out->gamma(" + N(r) + ")", dt.gamma[r]));
  P.push_back(Store("out->T", dt.excess_T));
  P.push_back(Store("out->V", dt.excess_V));
  f.body = {Finish(P, x, printer)};
  return f;
}

}  // namespace mechgen

namespace mechgen {

FunctionSpec EvalShakingSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer) {
  const StaticsTable& st = *dt.kinetostatics;
  NameSlots(st.slots, printer);
  FunctionSpec f;
  f.name = "EvalShaking";
  f.fills = OutputStruct::kShaking;
  f.model_member = "Shaking";
  f.doc = {"\\brief The shaking force and moment (Paul ch. 7) for a prescribed motion (q, qd, qdd): the resultant",
           "F = -sum m a_G of the moving links' inertia forces and its moment about the origin O,",
           "M = -sum (r_G x m a_G + J alpha), with a_G = K_G qdd + qd^T L_G qd and alpha = K_theta qdd + qd^T",
           "L_theta qd; per link, the masses' centres and the total centre of mass (see the Shaking struct)."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities", "dim kNq"));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qdd", Dir::kIn, "Input accelerations", "dim kNq"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn,
                       "EvalCoefficients() at this (q, phi): K and L are read from it."));
  f.args.push_back(Arg("Shaking<Scalar>*", "out", Dir::kOut, "Shaking; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Trig<Scalar>>::type*", "trig", Dir::kIn,
                       "sin and cos of q and phi from SolvePositions() at this (q, phi), or nullptr: they are "
                       "computed here.",
                       "", false, "nullptr"));
  f.notes = {"\\note Without loads and gravity, (F, M) is all the frame feels from the moving links (the",
             "ground joints' reactions and the input actuators' reaction torques and forces); a shaking-force",
             "balanced linkage has F = 0, its total centre of mass r_C standing still."};
  Program P = dt.shaking_program;
  const int nl = static_cast<int>(m.links.size());
  P.push_back(Store("out->F(0)", dt.F[0]));
  P.push_back(Store("out->F(1)", dt.F[1]));
  P.push_back(Store("out->M", dt.M_total));
  for (int l = 0; l < nl; ++l) {
    P.push_back(Store("out->F_link" + Idx(0, l), dt.F_link[l][0]));
    P.push_back(Store("out->F_link" + Idx(1, l), dt.F_link[l][1]));
    P.push_back(Store("out->M_link(" + N(l) + ")", dt.M_link[l]));
    if (dt.massive[l]) {
      P.push_back(Store("out->r_G" + Idx(0, l), dt.r_G[l][0]));
      P.push_back(Store("out->r_G" + Idx(1, l), dt.r_G[l][1]));
    }
  }
  P.push_back(Store("out->mass", dt.mass_total));
  P.push_back(Store("out->r_C(0)", dt.r_C[0]));
  P.push_back(Store("out->r_C(1)", dt.r_C[1]));
  for (int l = 0; l < nl; ++l)
    if (!dt.massive[l]) P.push_back(Raw("out->r_G.col(" + N(l) + ").setConstant(std::numeric_limits<Scalar>::quiet_NaN());"));
  f.body = {Finish(P, st, printer)};
  return f;
}

}  // namespace mechgen
