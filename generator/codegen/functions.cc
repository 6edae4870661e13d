// Builders of the generated functions. See functions.h.
#include "codegen/functions.h"

#include "codegen/drawing.h"
#include "model/expression_functions.h"

#include <cctype>
#include <set>
#include <stdexcept>

namespace mechgen {
namespace {

using GiNaC::ex;
using Dir = Argument::Direction;

std::string N(int i) { return std::to_string(i); }
std::string Idx(int i, int j) { return "(" + N(i) + ", " + N(j) + ")"; }

// Trigonometric sharing (the Trig<Scalar> argument of SolvePositions and EvalCoefficients).
// A coordinate's sin and cos as the symbols sin_<q|phi><i>, cos_<q|phi><i>.
struct TrigName {
  std::string sin, cos, sin_ref, cos_ref, arg;  // local names, trig->... members, q(i)/phi(i)
  ex sin_symbol, cos_symbol;
};

TrigName NameTrig(bool is_q, int i, CxxPrinter* printer) {
  TrigName t;
  const std::string kind = is_q ? "q" : "phi";
  t.sin = "sin_" + kind + N(i);
  t.cos = "cos_" + kind + N(i);
  t.sin_ref = "trig->sin_" + kind + "(" + N(i) + ")";
  t.cos_ref = "trig->cos_" + kind + "(" + N(i) + ")";
  t.arg = kind + "(" + N(i) + ")";
  GiNaC::symbol s(t.sin), c(t.cos);
  printer->Name(s, t.sin);
  printer->Name(c, t.cos);
  t.sin_symbol = s;
  t.cos_symbol = c;
  return t;
}

// Replaces sin(x) and cos(x) of the angle coordinates in `program`'s values by the symbols
// of NameTrig; returns which were used (per coordinate: sin, cos), q first, then phi.
std::vector<std::pair<bool, bool>> SubstituteTrig(const Kinematics& k,
                                                  const std::vector<TrigName>& names,
                                                  Program* program,
                                                  bool include_phi) {
  std::vector<const Coordinate*> coords;
  for (const Coordinate& c : k.q) coords.push_back(&c);
  for (const Coordinate& c : k.phi) coords.push_back(&c);
  if (!include_phi) coords.resize(k.q.size());
  GiNaC::exmap map;
  std::vector<std::pair<ex, ex>> trig(coords.size());  // sin(x), cos(x)
  for (size_t i = 0; i < coords.size(); ++i) {
    if (!coords[i]->is_angle) continue;
    trig[i] = {GiNaC::sin(coords[i]->symbol), GiNaC::cos(coords[i]->symbol)};
    map[trig[i].first] = names[i].sin_symbol;
    map[trig[i].second] = names[i].cos_symbol;
  }
  std::vector<std::pair<bool, bool>> used(k.q.size() + k.phi.size(), {false, false});
  for (Statement& s : *program) {
    if (s.kind != Statement::Kind::kDefine && s.kind != Statement::Kind::kStore) continue;
    for (size_t i = 0; i < coords.size(); ++i) {
      if (!coords[i]->is_angle) continue;
      used[i].first = used[i].first || s.value.has(trig[i].first);
      used[i].second = used[i].second || s.value.has(trig[i].second);
    }
    s.value = s.value.subs(map);
  }
  return used;
}

// The helpers of the expression language's piecewise functions (model/expression_functions.h)
// that the functions in `fs` call, in the order step, sign, min, max, mod: a model that uses
// none has none (and its header stays as it was).
std::vector<FunctionSpec> PiecewiseHelpers(const std::vector<FunctionSpec>& fs) {
  std::set<std::string> used;
  for (const FunctionSpec& f : fs)
    for (const Program& p : f.body)
      for (const Statement& s : p)
        if (s.kind == Statement::Kind::kDefine || s.kind == Statement::Kind::kStore)
          for (const char* n : {"mstep", "msign", "mmin", "mmax", "mmod"})
            if (!used.count(n) && HasPiecewise(s.value, n)) used.insert(n);
  std::vector<FunctionSpec> out;
  auto helper = [&](const std::string& name, const std::string& doc, std::vector<Argument> args,
                    const std::vector<std::string>& lines) {
    FunctionSpec f;
    f.name = name;
    f.returns = "Scalar";
    f.instantiate = false;
    f.count_ops = false;
    f.doc = {doc};
    f.args = std::move(args);
    Program P;
    for (const std::string& l : lines) P.push_back(Raw(l));
    f.body = {P};
    out.push_back(f);
  };
  auto x = [](const std::string& n, const std::string& doc) { return Arg("const Scalar&", n, Dir::kIn, doc); };
  // Comparisons of Scalar with Scalar: ceres::Jet compares its values (.a), so a Jet gets
  // the derivative of the branch taken (step and sign: 0).
  if (used.count("mstep"))
    helper("ExprStep", "\\brief step(x) of the model's expressions: 1 for x >= 0 (step(0) = 1), 0 for x < 0.",
           {x("x", "The argument.")}, {"return x >= Scalar(0) ? Scalar(1) : Scalar(0);"});
  if (used.count("msign"))
    helper("ExprSign", "\\brief sign(x) of the model's expressions: 1 for x > 0, -1 for x < 0, 0 at 0.",
           {x("x", "The argument.")},
           {"return x > Scalar(0) ? Scalar(1) : (x < Scalar(0) ? Scalar(-1) : Scalar(0));"});
  if (used.count("mmin"))
    helper("ExprMin", "\\brief min(a, b) of the model's expressions (and clamp(x, a, b) = min(max(x, a), b)): a where a <= b.",
           {x("a", "The first argument."), x("b", "The second argument.")}, {"return a <= b ? a : b;"});
  if (used.count("mmax"))
    helper("ExprMax", "\\brief max(a, b) of the model's expressions: a where a >= b.",
           {x("a", "The first argument."), x("b", "The second argument.")}, {"return a >= b ? a : b;"});
  if (used.count("mmod"))
    helper("ExprMod", "\\brief mod(x, p) of the model's expressions: x - p floor(x/p), in [0, p) for p > 0.",
           {x("x", "The argument."), x("p", "The period, > 0.")},
           {"Scalar r = x - p * floor(x / p);", "// Rounding: x just below a multiple of p gives r = p (or just below 0).",
            "if (r < Scalar(0)) r += p;", "if (r >= p) r -= p;", "return r;"});
  return out;
}

}  // namespace

void NameModelSymbols(const Model& m, const Kinematics& k, CxxPrinter* printer) {
  for (int i = 0; i < k.nq(); ++i) printer->Name(k.q[i].symbol, "q(" + N(i) + ")");
  for (int i = 0; i < k.nphi(); ++i) printer->Name(k.phi[i].symbol, "phi(" + N(i) + ")");
  for (const Parameter& p : m.params) printer->Name(p.symbol, "p." + p.name);
  for (const CamLaw& law : k.cam_laws) printer->NameCamLaw(m.joints[law.joint].Data<CamData>().index, law.cxx_name);
  for (const CamGeometry& g : k.cam_geometry) printer->Name(g.x, "x");
  for (const CamContour& c : k.cam_contours) printer->NameCamContour(m.joints[c.joint].Data<CamData>().index, c.cxx_name);
  for (size_t i = 0; i < m.tables.size(); ++i) printer->NameTable(static_cast<int>(i), "Table_" + m.tables[i].name);
}

FunctionSpec EvalPhiSpec(const SymbolicTable& t) {
  const Kinematics& k = t.kinematics();
  FunctionSpec f;
  f.name = "EvalPhi";
  f.model_member = "Phi";
  f.doc = {"\\brief Constraint residual and its Jacobians."};
  f.args = AtConfiguration();
  f.args.push_back(
      Arg("Out<Vec<Scalar, Sizes::kNc>>", "Phi", Dir::kOut, "Phi(q, phi); zero when the loops close", "dim kNc", true));
  f.args.push_back(Arg("Out<Mat<Scalar, Sizes::kNc, Sizes::kNphi>>", "Phi_phi", Dir::kOut, "dPhi/dphi", "kNc x kNphi",
                       true, "nullptr"));
  f.args.push_back(
      Arg("Out<Mat<Scalar, Sizes::kNc, Sizes::kNq>>", "Phi_q", Dir::kOut, "dPhi/dq", "kNc x kNq", true, "nullptr"));
  Program P;
  if (t.sparse_Phi_phi) P.push_back(Raw("if (Phi_phi != nullptr) Phi_phi->setZero();"));
  if (t.sparse_Phi_q) P.push_back(Raw("if (Phi_q != nullptr) Phi_q->setZero();"));
  for (int i = 0; i < k.nc(); ++i) P.push_back(Store("(*Phi)(" + N(i) + ")", k.Phi[i], "Phi"));
  for (int i = 0; i < k.nc(); ++i)
    for (int j = 0; j < k.nphi(); ++j)
      if (!t.sparse_Phi_phi || !k.Phi_phi(i, j).is_zero())
        P.push_back(Store("(*Phi_phi)" + Idx(i, j), k.Phi_phi(i, j), "Phi_phi"));
  for (int i = 0; i < k.nc(); ++i)
    for (int j = 0; j < k.nq(); ++j)
      if (!t.sparse_Phi_q || !k.Phi_q(i, j).is_zero())
        P.push_back(Store("(*Phi_q)" + Idx(i, j), k.Phi_q(i, j), "Phi_q"));
  f.body = {P};
  return f;
}

FunctionSpec EvalCoefficientsSpec(const SymbolicTable& t) {
  const Kinematics& k = t.kinematics();
  const int nq = k.nq(), nphi = k.nphi(), nc = k.nc();
  FunctionSpec f;
  f.name = "EvalCoefficients";
  f.model_member = "Coeffs";
  f.doc = {"\\brief Everything the model requested at a closed configuration: K, L and the points,",
           "with the residual Phi and Phi_phi there."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("Coefficients<Scalar>*", "out", Dir::kOut, "Coefficients; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Trig<Scalar>>::type*", "trig", Dir::kIn,
                       "sin and cos of q and phi from SolvePositions() at this (q, phi), or nullptr: they are "
                       "computed here.",
                       "", false, "nullptr"));
  f.notes = {"\\note Phi_phi must be regular at (q, phi): check its conditioning first (the runtime does)."};
  Program P;
  for (size_t pt = 0; pt < t.r_P.size(); ++pt)
    for (int a = 0; a < 2; ++a) P.push_back(Store("out->r_P" + Idx(a, static_cast<int>(pt)), t.r_P[pt][a]));
  // Phi and Phi_phi from the same evaluation, for the caller's closure and conditioning
  // checks: Phi_phi's entries are the named ones of the blocks' closed forms where they
  // exist (stored after the blocks are set up), the expressions elsewhere.
  for (int i = 0; i < nc; ++i) P.push_back(Store("out->Phi(" + N(i) + ")", k.Phi[i]));
  auto store_phi_phi = [&]() {
    if (t.sparse_Phi_phi) P.push_back(Raw("out->Phi_phi.setZero();"));
    for (int i = 0; i < nc; ++i)
      for (int j = 0; j < nphi; ++j)
        if (!t.sparse_Phi_phi || !k.Phi_phi(i, j).is_zero())
          P.push_back(Store("out->Phi_phi" + Idx(i, j), t.Phi_phi_named(i, j)));
  };
  if (!t.requested.K) {
    store_phi_phi();
    f.body = {P};
    return f;
  }
  P.insert(P.end(), t.k_program.begin(), t.k_program.end());
  store_phi_phi();
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j) P.push_back(Store("out->K" + Idx(i, j), t.K[i][j]));
  for (size_t pt = 0; pt < t.K_P.size(); ++pt)
    for (int a = 0; a < 2; ++a)
      for (int j = 0; j < nq; ++j)
        P.push_back(Store("out->K_P" + Idx(2 * static_cast<int>(pt) + a, j), t.K_P[pt][a][j]));
  if (t.requested.L) {
    P.insert(P.end(), t.l_program.begin(), t.l_program.end());
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk) P.push_back(Store("out->L" + Idx(i, j + nq * kk), t.L(i, j, kk)));
    for (size_t pt = 0; pt < t.L_P.size(); ++pt)
      for (int a = 0; a < 2; ++a)
        for (int j = 0; j < nq; ++j)
          for (int kk = 0; kk < nq; ++kk)
            P.push_back(Store("out->L_P" + Idx(2 * static_cast<int>(pt) + a, j + nq * kk), t.L_P[pt][a][j + nq * kk]));
  }
  f.body = {P};
  return f;
}

Program VelocityPrograms(const SymbolicTable& t) {
  Program P = t.k_program;
  P.insert(P.end(), t.l_program.begin(), t.l_program.end());
  return P;
}

Program CoefficientStores(const SymbolicTable& t, bool with_L) {
  const Kinematics& k = t.kinematics();
  const int nq = k.nq(), nphi = k.nphi();
  Program P;
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j) P.push_back(Store("out->K" + Idx(i, j), t.K[i][j]));
  if (with_L)
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk) P.push_back(Store("out->L" + Idx(i, j + nq * kk), t.L(i, j, kk)));
  return P;
}

Program PhiPhiStores(const SymbolicTable& t) {
  const Kinematics& k = t.kinematics();
  Program P;
  for (int i = 0; i < k.nc(); ++i)
    for (int j = 0; j < k.nphi(); ++j) P.push_back(Store("out->Phi_phi" + Idx(i, j), t.Phi_phi_named(i, j)));
  return P;
}

FunctionSpec EvalKinematicsSpec(const SymbolicTable& t) {
  FunctionSpec f;
  if (!t.requested.K) return f;
  f.name = "EvalKinematics";
  f.fills = OutputStruct::kKinematics;
  f.model_member = "Kinematics";
  f.returns = "SolveReport<Scalar>";
  f.reindent = true;
  // As EvalRhs: inlined where it is called (a loop over configurations), not compiled into
  // <model>.cc (no compile time in the models that never call it).
  f.instantiate = false;
  f.inline_hint = true;
  f.doc = {"\\brief The kinematics at inputs q in one pass: SolvePositionsTrig() (the closed forms' direction",
           "cosines, no angle), then K (and L with kHasL) and Phi_phi from them (Paul ch. 4). Nothing else",
           "of EvalCoefficients() (no residual, no points) is computed. The same statuses and branch_measure as",
           "SolvePositionsTrig(); *trig holds finite values when the report says kConverged, and so does *out",
           "except at a dead point (Phi_phi singular to rounding: its determinant 0, branch_measure 0 for a dyad),",
           "where K and L do not exist: check Phi_phi's conditioning first (the runtime does)."};
  f.args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "q", Dir::kIn, "Inputs", "dim kNq"));
  f.args.push_back(Arg("const std::array<int, Sizes::kNumBlocks>&", "modes", Dir::kIn,
                       "Assembly mode of each block (Model::kDefaultModes: the model's assembly)", "dim kNumBlocks"));
  f.args.push_back(Arg("Trig<Scalar>*", "trig", Dir::kOut, "sin and cos of q and phi at the solution; not nullptr."));
  f.args.push_back(Arg("Kinematics<Scalar>*", "out", Dir::kOut, "Kinematics; not nullptr."));
  f.notes = {"\\note Check Phi_phi's conditioning before using K and L (the runtime does): near a dead point",
             "they grow without bound."};
  Program P = VelocityPrograms(t);
  for (const Program& stores : {CoefficientStores(t, t.requested.L), PhiPhiStores(t)})
    P.insert(P.end(), stores.begin(), stores.end());
  PruneUnusedDefines(&P);
  f.body = {P};
  return f;
}

FunctionSpec EvalDetPhiPhiSpec(const SymbolicTable& t) {
  FunctionSpec f;
  f.name = "EvalDetPhiPhi";
  f.model_member = "DetPhiPhi";
  f.doc = {"\\brief det Phi_phi: zero where the mechanism is singular (a dead point, a change point),",
           "as the product of the blocks' determinants. Its sign is the assembly branch of a loop."};
  f.args = AtConfiguration();
  f.args.push_back(Arg("Scalar*", "det_Phi_phi", Dir::kOut, "det Phi_phi; not nullptr."));
  Program P = t.det_program;
  P.push_back(Store("*det_Phi_phi", t.det_Phi_phi));
  f.body = {P};
  return f;
}

FunctionSpec EvalTransmissionAnglesSpec(const std::vector<TransmissionAngle>& angles) {
  FunctionSpec f;
  f.name = "EvalTransmissionAngles";
  f.model_member = "TransmissionAngles";
  f.doc = {"\\brief Transmission angle mu of each four-bar loop: the angle between the coupler and",
           "the output link at their joint, in [0, pi]. mu = 0 or pi is a toggle of the output",
           "(Phi_phi loses rank there: the loop's determinant is b c sin mu up to sign); 90 deg",
           "transmits force best, and designs usually keep mu within 40..140 deg."};
  for (size_t i = 0; i < angles.size(); ++i)
    f.doc.push_back("  mu(" + N(static_cast<int>(i)) + "): " + angles[i].Text());
  f.args = AtConfiguration();
  f.args.push_back(Arg("Vec<Scalar, Sizes::kNumTransmissionAngles>*", "mu", Dir::kOut,
                       "Transmission angles; not nullptr.", "dim kNumTransmissionAngles"));
  Program P;
  for (size_t i = 0; i < angles.size(); ++i) {
    // Named first, so that atan2 gets two plain values (and no sum sits under abs).
    ex cross, dot;
    P.push_back(Define("cross_" + N(static_cast<int>(i)), angles[i].cross, &cross));
    P.push_back(Define("dot_" + N(static_cast<int>(i)), angles[i].dot, &dot));
    P.push_back(Store("(*mu)(" + N(static_cast<int>(i)) + ")", GiNaC::atan2(GiNaC::abs(cross), dot)));
  }
  f.body = {P};
  return f;
}

FunctionSpec EvalSceneSpec(const Kinematics& k) {
  FunctionSpec f;
  f.name = "EvalScene";
  f.model_member = "Scene";
  f.doc = {"\\brief Positions of every named point of every link, for drawing (kScenePointNames)."};
  f.args = AtConfiguration();
  f.args.push_back(Arg("Mat<Scalar, 2, Sizes::kNumScenePoints>*", "r", Dir::kOut,
                       "r.col(s) = point s in the fixed frame; not nullptr.", "2 x kNumScenePoints"));
  Program P;
  for (size_t s = 0; s < k.scene.size(); ++s)
    for (int a = 0; a < 2; ++a) P.push_back(Store("(*r)" + Idx(a, static_cast<int>(s)), k.scene[s][a]));
  f.body = {P};
  return f;
}

// The Trig<Scalar> argument: SolvePositions hoists sin and cos of its angle inputs out of the
// blocks and hands out sin and cos of every angle (closed-form dyads from their own dot and
// cross products, others by a call); EvalCoefficients takes them instead of calling sin and
// cos again (it calls them itself when trig is nullptr).
void ShareTrig(const Kinematics& k,
               const std::vector<bool>& trig_done,
               CxxPrinter* printer,
               FunctionSpec* coefficients,
               FunctionSpec* positions,
               const std::vector<FunctionSpec*>& takers,
               FunctionSpec* solve_trig,
               bool* solve_trig_possible,
               const std::vector<FunctionSpec*>& fused) {
  std::vector<TrigName> names;
  for (int i = 0; i < k.nq(); ++i) names.push_back(NameTrig(true, i, printer));
  for (int i = 0; i < k.nphi(); ++i) names.push_back(NameTrig(false, i, printer));
  const int nq = k.nq();

  // EvalCoefficients (and EvalStatics): every angle coordinate.
  auto take_trig = [&](FunctionSpec* spec) {
    Program& coeffs = spec->body.front();
    const auto used = SubstituteTrig(k, names, &coeffs, true);
    Program prologue, given, called;
    for (size_t i = 0; i < names.size(); ++i) {
      const TrigName& t = names[i];
      if (used[i].first) {
        prologue.push_back(Raw("Scalar " + t.sin + ";"));
        given.push_back(Raw("  " + t.sin + " = " + t.sin_ref + ";"));
        called.push_back(Raw("  " + t.sin + " = sin(" + t.arg + ");"));
        ++spec->extra_calls;
      }
      if (used[i].second) {
        prologue.push_back(Raw("Scalar " + t.cos + ";"));
        given.push_back(Raw("  " + t.cos + " = " + t.cos_ref + ";"));
        called.push_back(Raw("  " + t.cos + " = cos(" + t.arg + ");"));
        ++spec->extra_calls;
      }
    }
    if (!given.empty()) {
      prologue.push_back(Raw("if (trig != nullptr) {"));
      prologue.insert(prologue.end(), given.begin(), given.end());
      prologue.push_back(Raw("} else {"));
      prologue.insert(prologue.end(), called.begin(), called.end());
      prologue.push_back(Raw("}"));
      coeffs.insert(coeffs.begin(), prologue.begin(), prologue.end());
    }
  };
  take_trig(coefficients);
  for (FunctionSpec* spec : takers) take_trig(spec);

  // SolvePositions: the inputs' sin and cos once, before the blocks (body[0] is its
  // prologue, then one program per block, then its epilogue).
  std::vector<std::pair<bool, bool>> q_used(nq, {false, false});
  for (Program& block : positions->body) {
    const auto u = SubstituteTrig(k, names, &block, false);
    for (int j = 0; j < nq; ++j) {
      q_used[j].first = q_used[j].first || u[j].first;
      q_used[j].second = q_used[j].second || u[j].second;
    }
  }
  Program& head = positions->body.front();
  for (int j = 0; j < nq; ++j) {
    if (q_used[j].first) head.push_back(Raw("const Scalar " + names[j].sin + " = sin(" + names[j].arg + ");"));
    if (q_used[j].second) head.push_back(Raw("const Scalar " + names[j].cos + " = cos(" + names[j].arg + ");"));
    positions->extra_calls += q_used[j].first + q_used[j].second;
  }
  // The inputs' sin and cos go to *trig at once, before the blocks read a parameter (a store
  // through trig may alias the parameters): stored at the end, they were held (spilled) across
  // every call the blocks make (atan2). The sin and cos of the angles no block gave are
  // written at the end.
  Program q_stores, tail;
  for (int j = 0; j < nq; ++j) {
    if (!k.q[j].is_angle) continue;
    const TrigName& t = names[j];
    q_stores.push_back(Raw("  " + t.sin_ref + " = " + (q_used[j].first ? t.sin : "sin(" + t.arg + ")") + ";"));
    q_stores.push_back(Raw("  " + t.cos_ref + " = " + (q_used[j].second ? t.cos : "cos(" + t.arg + ")") + ";"));
  }
  for (int i = 0; i < k.nphi(); ++i) {
    if (!k.phi[i].is_angle || trig_done[i]) continue;
    const TrigName& t = names[nq + i];
    tail.push_back(Raw("  " + t.sin_ref + " = sin(" + t.arg + ");"));
    tail.push_back(Raw("  " + t.cos_ref + " = cos(" + t.arg + ");"));
  }
  for (Program* stores : {&q_stores, &tail}) {
    if (stores->empty()) continue;
    stores->insert(stores->begin(), Raw("if (trig != nullptr) {"));
    stores->push_back(Raw("}"));
  }
  head.insert(head.end(), q_stores.begin(), q_stores.end());
  if (!tail.empty()) positions->body.insert(positions->body.end() - 1, tail);

  if (solve_trig == nullptr || solve_trig_possible == nullptr || !*solve_trig_possible) return;
  // SolveTrig: sin and cos of the inputs once before the blocks; a later block reads an
  // earlier block's angles through the direction cosines that block wrote to *trig. It is
  // kept only if no statement of it, of EvalCoefficients or of a taker reads an angle
  // other than through its sin and cos (their phi argument is then not read given trig).
  auto reads_phi = [&](const Program& program, bool check_raw) {
    for (const Statement& s : program) {
      if (s.kind == Statement::Kind::kRaw) {
        if (!check_raw) continue;
        for (size_t pos = s.target.find("phi("); pos != std::string::npos; pos = s.target.find("phi(", pos + 1)) {
          const char before = pos == 0 ? ' ' : s.target[pos - 1];
          if (!(std::isalnum(static_cast<unsigned char>(before)) || before == '_' || before == '>')) return true;
        }
        continue;
      }
      for (const Coordinate& c : k.phi)
        if (s.value.has(c.symbol)) return true;
    }
    return false;
  };
  for (const Program& program : coefficients->body)
    if (reads_phi(program, false)) *solve_trig_possible = false;
  for (const FunctionSpec* spec : takers)
    for (const Program& program : spec->body)
      if (reads_phi(program, false)) *solve_trig_possible = false;
  std::vector<std::pair<bool, bool>> used(nq + k.nphi(), {false, false});
  std::vector<Program> blocks(solve_trig->body.begin() + 1, solve_trig->body.end() - 1);
  std::vector<std::vector<std::pair<bool, bool>>> block_used;
  for (Program& block : blocks) {
    block_used.push_back(SubstituteTrig(k, names, &block, true));
    if (reads_phi(block, true)) *solve_trig_possible = false;
    for (size_t j = 0; j < used.size(); ++j) {
      used[j].first = used[j].first || block_used.back()[j].first;
      used[j].second = used[j].second || block_used.back()[j].second;
    }
  }
  if (!*solve_trig_possible) return;
  std::set<std::string> defined;  // the sin and cos locals SolveTrig defines at function scope
  std::vector<Program> body;
  body.push_back(solve_trig->body.front());
  for (int j = 0; j < nq; ++j) {
    if (used[j].first) body.front().push_back(Raw("const Scalar " + names[j].sin + " = sin(" + names[j].arg + ");"));
    if (used[j].second) body.front().push_back(Raw("const Scalar " + names[j].cos + " = cos(" + names[j].arg + ");"));
    if (used[j].first) defined.insert(names[j].sin);
    if (used[j].second) defined.insert(names[j].cos);
    solve_trig->extra_calls += used[j].first + used[j].second;
  }
  // Each block solves its angles' sin and cos into the function's locals sin_phi<i>,
  // cos_phi<i> (declared before the block, SolveTrigSpec), which later blocks read by name.
  std::vector<bool> solved(k.nphi(), false);
  for (const Program& block : blocks)
    for (int i = 0; i < k.nphi(); ++i)
      for (const Statement& s : block)
        if (s.kind == Statement::Kind::kRaw && s.target.rfind(names[nq + i].cos + " = ", 0) == 0) solved[i] = true;
  for (int i = 0; i < k.nphi(); ++i) {
    if (!solved[i]) continue;
    defined.insert(names[nq + i].sin);
    defined.insert(names[nq + i].cos);
  }
  body.insert(body.end(), blocks.begin(), blocks.end());
  // The stores to *trig, at the end (SolveTrig: after the last block; EvalKinematics, EvalRhs: after their
  // body, so that no store through trig comes between the parameters' loads and their uses).
  Program end;
  for (int i = 0; i < k.nphi(); ++i) {
    if (!solved[i]) continue;
    const TrigName& t = names[nq + i];
    end.push_back(Raw(t.sin_ref + " = " + t.sin + ";"));
    end.push_back(Raw(t.cos_ref + " = " + t.cos + ";"));
  }
  const Program& epilogue = solve_trig->body.back();
  // The one-pass functions (EvalKinematics, EvalRhs): SolveTrig without its return and its
  // stores, the inputs' sin and cos the blocks did not name, then the function's own body (K,
  // L, the dynamics), then SolveTrig's stores and return. One is not generated (its body
  // cleared) if its body reads an angle other than through its sin and cos.
  for (FunctionSpec* spec : fused) {
    if (spec == nullptr || spec->body.empty()) continue;
    Program motion = spec->body.front();
    const auto u = SubstituteTrig(k, names, &motion, true);
    if (reads_phi(motion, false)) {
      spec->body.clear();
      continue;
    }
    std::vector<Program> one_pass = body;
    std::set<std::string> named = defined;
    Program inputs, stores = end, ret;
    for (int j = 0; j < nq; ++j) {
      if (!k.q[j].is_angle) continue;
      const TrigName& t = names[j];
      // A sin or cos of an input the blocks did not use: called once here when the
      // body reads it too (then stored from the local), else called in the store.
      for (int is_cos = 0; is_cos < 2; ++is_cos) {
        const bool in_blocks = is_cos ? used[j].second : used[j].first;
        const bool in_motion = is_cos ? u[j].second : u[j].first;
        const std::string& local = is_cos ? t.cos : t.sin;
        const std::string& ref = is_cos ? t.cos_ref : t.sin_ref;
        const std::string call = (is_cos ? "cos(" : "sin(") + t.arg + ")";
        if (!in_blocks && in_motion) {
          inputs.push_back(Raw("const Scalar " + local + " = " + call + ";"));
          named.insert(local);
        }
        stores.push_back(Raw(ref + " = " + (named.count(local) ? local : call) + ";"));
        if (!in_blocks) ++spec->extra_calls;
      }
    }
    for (const Statement& s : epilogue)
      (s.kind == Statement::Kind::kRaw && s.target.rfind("return", 0) == 0 ? ret : stores).push_back(s);
    for (size_t i = 0; i < names.size(); ++i) {
      const TrigName& t = names[i];
      // Every angle of phi is solved by a block (SolveTrig exists); the inputs are above.
      if ((u[i].first && !named.count(t.sin)) || (u[i].second && !named.count(t.cos)))
        throw std::logic_error(spec->name + " reads " + t.sin + " or " + t.cos + ", which SolveTrig does not name");
    }
    if (!inputs.empty()) one_pass.push_back(inputs);
    one_pass.push_back(motion);
    one_pass.push_back(stores);
    one_pass.push_back(ret);
    spec->body = one_pass;
    spec->extra_calls += solve_trig->extra_calls;
  }
  for (int j = 0; j < nq; ++j) {
    if (!k.q[j].is_angle) continue;
    const TrigName& t = names[j];
    end.push_back(Raw(t.sin_ref + " = " + (used[j].first ? t.sin : "sin(" + t.arg + ")") + ";"));
    end.push_back(Raw(t.cos_ref + " = " + (used[j].second ? t.cos : "cos(" + t.arg + ")") + ";"));
    if (!used[j].first) ++solve_trig->extra_calls;
    if (!used[j].second) ++solve_trig->extra_calls;
  }
  end.insert(end.end(), epilogue.begin(), epilogue.end());
  body.push_back(end);
  solve_trig->body = body;
}

std::vector<FunctionSpec> BuildFunctions(const Model& m,
                                         const Kinematics& k,
                                         const SymbolicTable& t,
                                         const std::vector<TransmissionAngle>& transmission,
                                         CxxPrinter* printer,
                                         const StaticsTable* statics,
                                         const DynamicsTable* dynamics,
                                         const DesignTable* design) {
  NameModelSymbols(m, k, printer);
  std::vector<FunctionSpec> out;
  // Cams: the law's function and the cam's geometry; splines' contour functions.
  for (size_t c = 0; c < k.cam_laws.size(); ++c) {
    out.push_back(CamLawSpec(m, k.cam_laws[c], printer));
    out.push_back(EvalCamSpec(m, k.cam_laws[c], k.cam_geometry[c]));
  }
  for (const CamContour& c : k.cam_contours)
    if (m.joints[c.joint].Data<CamData>().contour == CamData::Contour::kSpline) out.push_back(ContourSpec(m, c));
  for (size_t i = 0; i < m.tables.size(); ++i) out.push_back(TableSpec(m, static_cast<int>(i)));
  out.push_back(EvalPhiSpec(t));
  FunctionSpec coefficients = EvalCoefficientsSpec(t);
  std::vector<bool> trig_done;
  FunctionSpec positions = SolvePositionsSpec(t, printer, &trig_done);
  FunctionSpec statics_spec;
  const bool has_statics = statics != nullptr && statics->layout.any;
  if (has_statics) statics_spec = EvalStaticsSpec(m, *statics, printer);
  std::vector<FunctionSpec*> takers;
  if (has_statics) takers.push_back(&statics_spec);
  const bool has_dynamics = dynamics != nullptr && dynamics->any;
  FunctionSpec dynamics_spec, kinetostatics_spec, rhs_spec, shaking_spec;
  const bool has_shaking = has_dynamics && dynamics->shaking;
  if (has_dynamics) {
    dynamics_spec = EvalDynamicsSpec(m, *dynamics, printer);
    rhs_spec = EvalRhsSpec(m, t, *dynamics, printer);
    kinetostatics_spec = EvalKinetostaticsSpec(m, *dynamics, printer);
    takers.push_back(&dynamics_spec);
    takers.push_back(&kinetostatics_spec);
  }
  if (has_shaking) {
    shaking_spec = EvalShakingSpec(m, *dynamics, printer);
    takers.push_back(&shaking_spec);
  }
  bool solve_trig_possible = false;
  FunctionSpec solve_trig = SolveTrigSpec(t, printer, &solve_trig_possible);
  FunctionSpec kinematics_spec = EvalKinematicsSpec(t);
  ShareTrig(k, trig_done, printer, &coefficients, &positions, takers, &solve_trig, &solve_trig_possible,
            {&kinematics_spec, has_dynamics ? &rhs_spec : nullptr});
  out.push_back(coefficients);
  if (has_statics) out.push_back(statics_spec);
  if (has_dynamics) {
    out.push_back(dynamics_spec);
    out.push_back(kinetostatics_spec);
    out.push_back(EvalExcessSpec(m, k, *dynamics, printer));
  }
  if (has_shaking) out.push_back(shaking_spec);
  if (has_statics && (!statics->d2V_dq2.empty() || !statics->stiffness_q.empty())) out.push_back(EvalStiffnessSpec(m, *statics, printer));
  if (design != nullptr && design->nd() > 0) {
    // What the design section's quantities ask for (default: all the outputs have).
    out.push_back(EvalDesignDerivativesSpec(*design, t));
    if (m.design.checks && !design->checks.empty()) out.push_back(EvalDesignChecksSpec(*design));
    if (has_statics && m.design.statics) {
      const DesignStatics ds(m, k, *statics, *design);
      if (ds.possible) out.push_back(EvalStaticsDesignSpec(m, *statics, ds, printer));
    }
    if (has_dynamics && m.design.dynamics) {
      const DesignDynamics dd(m, k, *dynamics, *design);
      // The shaking derivatives: generated exactly with the dynamics' (kHasShaking && kHasDynamicsDesign).
      const DesignShaking dsh(k, *dynamics, *design);
      if (dd.possible && (!has_shaking || dsh.possible)) {
        out.push_back(EvalDynamicsDesignSpec(m, *dynamics, dd, printer));
        const DesignDynamicsProduct dp(k, *dynamics, *design);
        if (dp.possible) out.push_back(EvalDynamicsDesignProductSpec(m, *dynamics, *design, dp, printer));
        if (has_shaking) out.push_back(EvalShakingDesignSpec(*dynamics, dsh, printer));
        // The right-hand side's Jacobians for the trajectory sensitivities: generated with the
        // dynamics' design derivatives (kHasDynamicsDesign), which need the same straight-line
        // program; not where they would need a cam law's fourth derivative (the runtime then
        // differentiates by Jets: dynamics/sensitivity.h).
        const DynamicsJacobian dj(m, t, *dynamics);
        if (dj.possible) out.push_back(EvalDynamicsJacobianSpec(m, *dynamics, dj, printer));
      }
    }
  }
  out.push_back(EvalDetPhiPhiSpec(t));
  if (!transmission.empty()) out.push_back(EvalTransmissionAnglesSpec(transmission));
  out.push_back(positions);
  if (solve_trig_possible) out.push_back(solve_trig);
  if (solve_trig_possible && !kinematics_spec.body.empty()) out.push_back(kinematics_spec);
  if (has_dynamics && solve_trig_possible && !rhs_spec.body.empty()) {
    FunctionSpec prepare;
    HoistRhsConstants(m, printer, &rhs_spec, &prepare);
    out.push_back(prepare);
    out.push_back(rhs_spec);
  }
  if (has_dynamics) {  // the switching items of Q: only where there are some
    FunctionSpec switches = EvalSwitchModesSpec(m, *dynamics, printer);
    if (!switches.name.empty()) out.push_back(switches);
  }
  if (m.outputs.scene && !k.scene.empty()) out.push_back(EvalSceneSpec(k));
  if (FunctionSpec f = has_statics ? EvalAppliedLoadsSpec(m, k, *statics, printer) : FunctionSpec(); !f.name.empty()) out.push_back(f);
  for (const FunctionSpec& f : DrawingFunctions(m, k, printer)) out.push_back(f);
  const std::vector<FunctionSpec> helpers = PiecewiseHelpers(out);
  out.insert(out.begin(), helpers.begin(), helpers.end());
  return out;
}

}  // namespace mechgen
