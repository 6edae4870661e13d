// The symbolic table, the one formulation of the dyads and the function descriptions:
//  - the closed forms, evaluated by the generator itself (the same steps the generated
//    SolvePositions prints), close the loop and agree with the four-bar's law of cosines;
//  - K and L of an arbitrary expression, asked of the table, match finite differences of
//    that expression along the motion;
//  - a new generated function is one description: the templates render its declaration,
//    extern declarations, explicit instantiations and Model member;
//  - SHA-256 against the FIPS 180-2 examples, and the preamble names the model's hash.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "codegen/emit.h"
#include "codegen/functions.h"
#include "codegen/sha256.h"
#include "analysis/kinematics.h"
#include "model/model.h"
#include "symbolic/dyads.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"
#include "analysis/topology.h"

namespace mechgen {
namespace {

const std::string kSource = MECHGEN_SOURCE_DIR;

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

double Num(const GiNaC::ex& e, const GiNaC::exmap& v) {
  const GiNaC::ex n = e.subs(v).evalf();
  return GiNaC::is_a<GiNaC::numeric>(n) ? GiNaC::ex_to<GiNaC::numeric>(n).to_double() : std::nan("");
}

double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

struct Pipeline {
  Model m;
  Topology t;
  Kinematics k;
  explicit Pipeline(const std::string& model)
      : m(LoadModel(kSource + "/models/" + model + ".yaml")), t(BuildTopology(m)), k(DeriveKinematics(m, t)) {}
  GiNaC::exmap At(const std::vector<double>& q) const {
    GiNaC::exmap v;
    for (const Parameter& p : m.params) v[p.symbol] = p.value;
    for (size_t i = 0; i < q.size(); ++i) v[k.q[i].symbol] = q[i];
    return v;
  }
  // phi at q from the blocks' closed forms in the given modes (all blocks closed form).
  bool Solve(const SymbolicTable& table, const std::vector<double>& q, int mode, GiNaC::exmap* v) const {
    *v = At(q);
    for (size_t bi = 0; bi < table.blocks.size(); ++bi) {
      const ClosedForm f = FormulateClosedForm(k, table.blocks[bi], static_cast<int>(bi));
      std::map<DyadLocal, double> locals;
      std::map<int, double> solution;
      const DyadStep* failed = nullptr;
      if (!EvaluateClosedForm(f, *v, mode, &locals, &solution, &failed)) return false;
      for (const auto& [col, value] : solution) (*v)[k.phi[col].symbol] = value;
    }
    return true;
  }
};

// Paul's four-bar: C on the circles about B (radius b) and D (radius c); the rocker's angle
// is the direction of DB plus or minus the angle at D of triangle BCD (law of cosines).
TEST(Dyads, FourBarModesAreTheLawOfCosinesBranches) {
  const Pipeline p("fourbar");
  const SymbolicTable table(p.m, p.k);
  ASSERT_EQ(table.blocks.size(), 1u);
  ASSERT_EQ(table.blocks[0].solve, BlockSolve::kRR);
  const double a = 1, b = 3.5, c = 3, d = 4;
  for (double theta : {0.0, 0.4, 1.3, 2.0, 3.1, 4.4, 5.9}) {
    const double bx = a * std::cos(theta), by = a * std::sin(theta);
    const double f = std::hypot(bx - d, by), db = std::atan2(by, bx - d);
    const double gamma = std::acos((c * c + f * f - b * b) / (2 * c * f));
    double rocker[2];
    for (int mode : {1, -1}) {
      GiNaC::exmap v;
      ASSERT_TRUE(p.Solve(table, {theta}, mode, &v)) << theta;
      for (const GiNaC::ex& row : p.k.Phi) EXPECT_NEAR(Num(row, v), 0, 1e-12) << theta << " mode " << mode;
      rocker[mode > 0 ? 0 : 1] = Num(p.k.phi[1].symbol, v);
    }
    // The two modes are the two branches db + gamma and db - gamma (in some order).
    const double e1 = std::abs(Wrap(rocker[0] - (db + gamma))) + std::abs(Wrap(rocker[1] - (db - gamma)));
    const double e2 = std::abs(Wrap(rocker[0] - (db - gamma))) + std::abs(Wrap(rocker[1] - (db + gamma)));
    EXPECT_LT(std::min(e1, e2), 1e-12) << theta;
  }
  // The model's assembly (open: C above the ground at theta_crank = 90 deg) is mode +1.
  EXPECT_EQ(table.blocks[0].default_mode, 1);
  GiNaC::exmap v;
  ASSERT_TRUE(p.Solve(table, {M_PI / 2}, table.blocks[0].default_mode, &v));
  EXPECT_GT(a * 1 + b * std::sin(Num(p.k.phi[0].symbol, v)), 0);
}

// A circle the line cannot reach: the requirement fails and names its discriminant.
TEST(Dyads, RequirementFailsWhereTheLoopCannotClose) {
  const Pipeline p("fourbar");
  const SymbolicTable table(p.m, p.k);
  const ClosedForm f = FormulateClosedForm(p.k, table.blocks[0], 0);
  GiNaC::exmap v = p.At({M_PI});
  for (const Parameter& par : p.m.params)
    if (par.name == "d") v[par.symbol] = 8.0;  // |BD| = 9 > b + c = 6.5
  std::map<DyadLocal, double> locals;
  std::map<int, double> solution;
  const DyadStep* failed = nullptr;
  EXPECT_FALSE(EvaluateClosedForm(f, v, 1, &locals, &solution, &failed));
  ASSERT_NE(failed, nullptr);
  EXPECT_EQ(failed->kind, DyadStep::Kind::kRequire);
  EXPECT_LT(locals.at(DyadLocal::kH2), 0);
  EXPECT_TRUE(solution.empty());
}

TEST(Dyads, SliderCrankBothModesCloseTheLoop) {
  const Pipeline p("slider_crank");
  const SymbolicTable table(p.m, p.k);
  for (double theta : {0.0, 1.0, 2.5, 4.0}) {
    double slide[2];
    for (int mode : {1, -1}) {
      GiNaC::exmap v;
      ASSERT_TRUE(p.Solve(table, {theta}, mode, &v));
      for (const GiNaC::ex& row : p.k.Phi) EXPECT_NEAR(Num(row, v), 0, 1e-12);
      for (int i = 0; i < p.k.nphi(); ++i)
        if (!p.k.phi[i].is_angle) slide[mode > 0 ? 0 : 1] = Num(p.k.phi[i].symbol, v);
    }
    EXPECT_GT(std::abs(slide[0] - slide[1]), 1e-3) << "the modes are the two branches";
  }
}

// Evaluates a program's named locals at v (statement by statement, as the generated code).
void Evaluate(const Program& program, GiNaC::exmap* v) {
  for (const Statement& s : program)
    if (s.kind == Statement::Kind::kDefine) (*v)[s.symbol] = Num(s.value, *v);
}

// K and L of an expression that is not a model output (a made-up function of the coupler's
// and rocker's angles) from the table, against central differences along the motion.
TEST(SymbolicTable, VelocityAndCentripetalCoefficientsOfAnyExpression) {
  const Pipeline p("fourbar");
  const SymbolicTable table(p.m, p.k);
  const GiNaC::ex u = p.k.phi[0].symbol, w = p.k.phi[1].symbol, q = p.k.q[0].symbol;
  const GiNaC::ex f = 3 * GiNaC::cos(w) + GiNaC::sin(u) * GiNaC::sin(q) + u * u;
  const std::vector<GiNaC::ex> K_f = table.VelocityCoefficients(f);
  const std::vector<GiNaC::ex> L_f = table.CentripetalCoefficients(f, K_f);
  ASSERT_EQ(K_f.size(), 1u);
  ASSERT_EQ(L_f.size(), 1u);
  for (double theta : {0.3, 1.7, 3.0, 5.2}) {
    GiNaC::exmap v;
    ASSERT_TRUE(p.Solve(table, {theta}, 1, &v));
    Evaluate(table.k_program, &v);
    Evaluate(table.l_program, &v);
    auto f_at = [&](double t) {
      GiNaC::exmap at;
      EXPECT_TRUE(p.Solve(table, {t}, 1, &at));
      return Num(f, at);
    };
    const double h = 1e-4, h2 = 1e-3;
    const double dk = (f_at(theta + h) - f_at(theta - h)) / (2 * h);
    const double dl = (f_at(theta + h2) - 2 * f_at(theta) + f_at(theta - h2)) / (h2 * h2);
    EXPECT_NEAR(Num(K_f[0], v), dk, 1e-6) << theta;
    EXPECT_NEAR(Num(L_f[0], v), dl, 1e-4) << theta;
    // The model's own K is the coefficient of its angles: K of phi(i) is K(i, :).
    EXPECT_NEAR(Num(table.VelocityCoefficients(w)[0], v), Num(table.K[1][0], v), 1e-14);
  }
}

// A new generated function is one description (and its builder): here the rate of the
// coupler's angle, K of theta_coupler, asked of the table. The templates render the rest.
TEST(FunctionSpec, ANewFunctionIsOneDescription) {
  const Pipeline p("fourbar");
  const SymbolicTable table(p.m, p.k);
  const auto transmission = FindTransmissionAngles(p.m, p.t, p.k, table.blocks);
  CxxPrinter printer;
  std::vector<FunctionSpec> functions = BuildFunctions(p.m, p.k, table, transmission, &printer);

  FunctionSpec f;
  f.name = "EvalCouplerRate";
  f.model_member = "CouplerRate";
  f.doc = {"\\brief d theta_coupler / d q."};
  f.args = AtConfiguration();
  f.args.push_back(Arg("Vec<Scalar, Sizes::kNq>*", "K_coupler", Argument::Direction::kOut, "K of theta_coupler",
                       "dim kNq"));
  f.args.push_back(Arg("int", "unused", Argument::Direction::kIn, "Not read by the body."));
  Program body = table.k_program;
  const std::vector<GiNaC::ex> K = table.VelocityCoefficients(p.k.phi[0].symbol);
  body.push_back(Store("(*K_coupler)(0)", K[0]));
  f.body = {body};
  functions.push_back(f);

  const EmittedModel e = Emit(p.m, p.t, p.k, table, transmission, functions, &printer, kSource + "/templates");
  const std::string& h = e.header;
  EXPECT_NE(h.find("void EvalCouplerRate(const Params<Scalar>& p,\n"
                   "                     const Vec<Scalar, Sizes::kNq>& q,"),
            std::string::npos);
  EXPECT_NE(h.find("                     int unused) {"), std::string::npos);
  EXPECT_NE(h.find(" * \\param[out] K_coupler  K of theta_coupler (dim kNq)."), std::string::npos);
  EXPECT_NE(h.find("extern template void EvalCouplerRate<double>(const Params<double>&,"), std::string::npos);
  EXPECT_NE(h.find("extern template void EvalCouplerRate<float>(const Params<float>&,"), std::string::npos);
  EXPECT_NE(h.find("  static void CouplerRate(const Params<Scalar>& p,"), std::string::npos);
  EXPECT_NE(h.find("    EvalCouplerRate(p, q, phi, K_coupler, unused);"), std::string::npos);
  EXPECT_NE(e.source.find("template void EvalCouplerRate<double>(const Params<double>&,"), std::string::npos);
  // The preamble from the description: the unused argument is voided, the used ones are not,
  // and only the math functions the body calls are brought in.
  const std::string body_text = h.substr(h.find("int unused) {"), h.find("\n}\n", h.find("int unused) {")) -
                                                                       h.find("int unused) {"));
  EXPECT_NE(body_text.find("(void)unused;"), std::string::npos) << body_text;
  EXPECT_EQ(body_text.find("(void)p;"), std::string::npos) << body_text;
  EXPECT_NE(body_text.find("using std::sin;"), std::string::npos) << body_text;
  EXPECT_EQ(body_text.find("using std::sqrt;"), std::string::npos) << body_text;
  EXPECT_NE(body_text.find("(*K_coupler)(0) = K_0_0;"), std::string::npos) << body_text;
}

TEST(Sha256, FipsExamples) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256Hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, GeneratedPreambleNamesTheModelsHash) {
  const std::string hash = Sha256Hex(Read(kSource + "/models/fourbar.yaml"));
  EXPECT_NE(Read(kSource + "/generated/fourbar.h").find("from fourbar.yaml (sha256 " + hash + ")"), std::string::npos);
  EXPECT_NE(Read(kSource + "/generated/fourbar.cc").find("from fourbar.yaml (sha256 " + hash + ")"), std::string::npos);
}

}  // namespace
}  // namespace mechgen
