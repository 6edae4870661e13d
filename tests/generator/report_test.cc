// `mechgen report`, end to end, against oracles that do not share its code:
//  - its formulas (K and L block by block, the blocks' determinants, L's right-hand sides,
//    the points' r_P, K_P, L_P), read back from the plain text with GiNaC's own parser and
//    evaluated at a configuration the generated solver found, against central finite
//    differences of the generated positions (phi and r_P) over q;
//  - its statement of the branch against the sign of the generated det Phi_phi at the
//    assembly guess (what the runtime's Assembler requires);
//  - the same bytes from separate processes (GiNaC's term order changes between them);
//  - --latex --standalone compiled by pdflatex for every shipped model and for names that
//    used to break it (skipped where pdflatex is not installed).
#include <ginac/ginac.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fivebar.h"
#include "fourbar.h"
#include "geared_fivebar.h"
#include "quick_return.h"
#include "slider_crank.h"
#include "stephenson_coupled.h"
#include "watt_sixbar.h"

namespace fs = std::filesystem;

namespace {

const fs::path kSource = MECHGEN_SOURCE_DIR;

struct Result {
  int exit_code = -1;
  std::string out;  // stdout only
};

Result RunCommand(const std::string& cmd) {
  Result r;
  FILE* pipe = popen((cmd + " 2>/dev/null").c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

Result Report(const std::string& model, const std::string& flags = "") {
  return RunCommand(std::string(MECHGEN_EXE) + " report " + flags + " " + (kSource / "models" / (model + ".yaml")).string());
}

std::vector<std::string> ShippedModels() {
  std::vector<std::string> models;
  std::istringstream in(MECHGEN_SHIPPED_MODELS);
  for (std::string m; std::getline(in, m, ',');)
    if (!m.empty()) models.push_back(m);
  return models;
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() / ("mechgen_report_test_" + std::to_string(::getpid()) + "_" +
                                         std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

// ---- the plain-text report, read back ----

// Its parameters ("  a = 1   (crank AB)" under "Parameters") and its formulas
// ("  K_0_0 = ...   [note]") in the order printed: later ones use earlier names.
struct ParsedReport {
  std::map<std::string, double> params;
  std::vector<std::pair<std::string, std::string>> formulas;
  std::string text;
};

ParsedReport Parse(const std::string& text) {
  ParsedReport r;
  r.text = text;
  static const std::regex formula(
      R"(^  (det_block\d+|K_\d+_\d+|L_rhs_\d+_\d+_\d+|L_\d+_\d+_\d+|r_\d+_[xy]|K_P\d+_[xy]_\d+|L_P\d+_[xy]_\d+_\d+|dphi_\d+_[A-Za-z_][A-Za-z0-9_]*) = (.*?)(   \[.*\])?$)");
  static const std::regex param(R"(^  ([A-Za-z_][A-Za-z0-9_]*) = ([-+0-9.eE]+)(   \(.*\))?$)");
  std::istringstream in(text);
  bool in_params = false;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != ' ') in_params = line.rfind("Parameters", 0) == 0;
    std::smatch m;
    if (in_params && std::regex_match(line, m, param))
      r.params[m[1]] = std::strtod(m[2].str().c_str(), nullptr);
    else if (std::regex_match(line, m, formula))
      r.formulas.emplace_back(m[1], m[2]);
  }
  return r;
}

// Every formula evaluated at (params, q, phi) in order; a name a formula uses before it is
// defined, or one the report does not define, is a parse error (strict parser).
std::map<std::string, double> Evaluate(const ParsedReport& r, const std::map<std::string, double>& coordinates) {
  std::map<std::string, double> values = r.params;
  for (const auto& [name, v] : coordinates) values[name] = v;
  for (const auto& [name, expression] : r.formulas) {
    GiNaC::symtab table;
    GiNaC::exmap at;
    for (const auto& [n, v] : values) {
      const GiNaC::symbol s(n);
      table[n] = s;
      at[s] = v;
    }
    GiNaC::parser reader(table, /*strict=*/true);
    GiNaC::ex e;
    try {
      e = reader(expression);
    } catch (const std::exception& ex) {
      ADD_FAILURE() << name << " = " << expression << ": " << ex.what();
      continue;
    }
    const GiNaC::ex v = e.subs(at).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v)) {
      ADD_FAILURE() << name << " = " << expression << " does not evaluate to a number: " << v;
      continue;
    }
    values[name] = GiNaC::ex_to<GiNaC::numeric>(v).to_double();
  }
  return values;
}

// ---- the oracle: finite differences of the generated positions ----

template <class M>
using VecQ = Eigen::Matrix<double, M::kNq, 1>;
template <class M>
using VecPhi = Eigen::Matrix<double, M::kNphi, 1>;

template <class M>
VecPhi<M> Positions(const typename M::template ParamsT<double>& p, const VecQ<M>& q, const VecPhi<M>& seed) {
  VecPhi<M> phi = seed;
  const auto s = M::Solve(p, q, &phi);
  EXPECT_EQ(static_cast<int>(s.status), 0) << "at q = " << q.transpose();
  return phi;
}

// Everything as one vector: phi, then the points' coordinates (r_m_x, r_m_y).
template <class M>
Eigen::VectorXd State(const typename M::template ParamsT<double>& p, const VecQ<M>& q, const VecPhi<M>& seed) {
  const VecPhi<M> phi = Positions<M>(p, q, seed);
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  Eigen::VectorXd s(M::kNphi + 2 * M::kNumPoints);
  s.head(M::kNphi) = phi;
  for (int m = 0; m < M::kNumPoints; ++m) s.segment(M::kNphi + 2 * m, 2) = c.r_P.col(m);
  return s;
}

template <class M>
class ReportFormulas : public ::testing::Test {};
using Models = ::testing::Types<mech::fourbar::Model, mech::slider_crank::Model, mech::fivebar::Model,
                                mech::quick_return::Model, mech::watt_sixbar::Model,
                                mech::stephenson_coupled::Model, mech::geared_fivebar::Model>;
TYPED_TEST_SUITE(ReportFormulas, Models);

TYPED_TEST(ReportFormulas, MatchFiniteDifferencesOfTheGeneratedPositions) {
  using M = TypeParam;
  const Result out = Report(M::kName);
  ASSERT_EQ(out.exit_code, 0) << out.out;
  const ParsedReport r = Parse(out.out);
  const typename M::template ParamsT<double> p;
  constexpr int nq = M::kNq, nphi = M::kNphi, np = M::kNumPoints;

  // Off the assembly by 0.1 in every input (a generic configuration), solved.
  VecQ<M> q;
  VecPhi<M> phi;
  for (int j = 0; j < nq; ++j) q(j) = M::kAssemblyQ[j] + 0.1;
  for (int i = 0; i < nphi; ++i) phi(i) = M::kAssemblyPhi[i];
  phi = Positions<M>(p, q, phi);
  std::map<std::string, double> at;
  for (int j = 0; j < nq; ++j) at[M::kQNames[j]] = q(j);
  for (int i = 0; i < nphi; ++i) at[M::kPhiNames[i]] = phi(i);
  const std::map<std::string, double> v = Evaluate(r, at);
  auto value = [&](const std::string& name) {
    const auto it = v.find(name);
    EXPECT_NE(it, v.end()) << "the report has no " << name << "\n" << r.text;
    return it == v.end() ? NAN : it->second;
  };
  auto N = [](int i) { return std::to_string(i); };


  // First and second central differences of (phi, r_P) over q.
  const double h1 = 1e-5, h2 = 1e-3;
  const Eigen::VectorXd s0 = State<M>(p, q, phi);
  for (int m = 0; m < np; ++m)
    for (int a = 0; a < 2; ++a)
      EXPECT_NEAR(value("r_" + N(m) + "_" + (a ? "y" : "x")), s0(nphi + 2 * m + a), 1e-12);
  for (int j = 0; j < nq; ++j) {
    VecQ<M> qp = q, qm = q;
    qp(j) += h1;
    qm(j) -= h1;
    const Eigen::VectorXd d = (State<M>(p, qp, phi) - State<M>(p, qm, phi)) / (2 * h1);
    for (int i = 0; i < nphi; ++i)
      EXPECT_NEAR(value("K_" + N(i) + "_" + N(j)), d(i), 1e-7 * (1 + std::abs(d(i)))) << M::kPhiNames[i];
    for (int m = 0; m < np; ++m)
      for (int a = 0; a < 2; ++a)
        EXPECT_NEAR(value("K_P" + N(m) + "_" + (a ? "y" : "x") + "_" + N(j)), d(nphi + 2 * m + a),
                    1e-7 * (1 + std::abs(d(nphi + 2 * m + a))));
  }
  for (int j = 0; j < nq; ++j)
    for (int k = j; k < nq; ++k) {
      Eigen::VectorXd d2;
      if (j == k) {
        VecQ<M> qp = q, qm = q;
        qp(j) += h2;
        qm(j) -= h2;
        d2 = (State<M>(p, qp, phi) - 2 * s0 + State<M>(p, qm, phi)) / (h2 * h2);
      } else {
        auto at_q = [&](double sj, double sk) {
          VecQ<M> x = q;
          x(j) += sj * h2;
          x(k) += sk * h2;
          return State<M>(p, x, phi);
        };
        d2 = (at_q(1, 1) - at_q(1, -1) - at_q(-1, 1) + at_q(-1, -1)) / (4 * h2 * h2);
      }
      const std::string jk = N(j) + "_" + N(k);
      for (int i = 0; i < nphi; ++i)
        EXPECT_NEAR(value("L_" + N(i) + "_" + jk), d2(i), 2e-5 * (1 + std::abs(d2(i)))) << M::kPhiNames[i];
      for (int m = 0; m < np; ++m)
        for (int a = 0; a < 2; ++a)
          EXPECT_NEAR(value("L_P" + N(m) + "_" + (a ? "y" : "x") + "_" + jk), d2(nphi + 2 * m + a),
                      2e-5 * (1 + std::abs(d2(nphi + 2 * m + a))));
    }

  // The design sensitivities dphi/dp (a model with a design section) against central
  // differences of the generated positions over each design parameter.
  if constexpr (M::kHasDesignDerivatives) {
    for (int d = 0; d < M::kNumDesign; ++d) {
      auto pp = p, pm = p;
      const double pd = *pp.Find(M::kDesignNames[d]), h = 1e-6 * std::max(1.0, std::abs(pd));
      *pp.Find(M::kDesignNames[d]) = pd + h;
      *pm.Find(M::kDesignNames[d]) = pd - h;
      const VecPhi<M> dphi = (Positions<M>(pp, q, phi) - Positions<M>(pm, q, phi)) / (2 * h);
      for (int i = 0; i < nphi; ++i)
        EXPECT_NEAR(value("dphi_" + N(i) + "_" + M::kDesignNames[d]), dphi(i), 1e-7 * (1 + std::abs(dphi(i))))
            << M::kPhiNames[i] << " / " << M::kDesignNames[d];
    }
  }

  // det Phi_phi: the blocks' determinants multiply to the generated one (up to the sign of
  // the block order's permutation).
  double product = 1;
  for (int b = 0; b < M::kNumBlocks; ++b) product *= value("det_block" + N(b));
  double det = 0;
  M::DetPhiPhi(p, q, phi, &det);
  EXPECT_NEAR(std::abs(product), std::abs(det), 1e-9 * (1 + std::abs(det)));

  // The branch the report names is sign(det Phi_phi) at the assembly guess.
  VecQ<M> qa;
  VecPhi<M> pa;
  for (int j = 0; j < nq; ++j) qa(j) = M::kAssemblyQ[j];
  for (int i = 0; i < nphi; ++i) pa(i) = M::kAssemblyPhi[i];
  double det_a = 0;
  M::DetPhiPhi(p, qa, pa, &det_a);
  const std::string branch = std::string("print as 'branch ") + (det_a > 0 ? "+1'" : "-1'");
  EXPECT_NE(r.text.find(branch), std::string::npos) << "expected '" << branch << "' in\n" << r.text;
}

// ---- the same bytes every run ----

TEST(Report, SameBytesFromSeparateProcesses) {
  // GiNaC orders terms by hashes that differ between processes: three runs each, in plain
  // text and as a LaTeX document, of models with dyads, floats in their equations (the
  // coupled Stephenson six-bar), a Newton block, cam laws and a spline contour.
  for (const std::string model : {"fourbar", "fivebar", "stephenson_coupled", "quick_return", "cam_roller",
                                  "cam_spline", "geared_fivebar"}) {
    for (const std::string flags : {"", "--latex --standalone"}) {
      const Result first = Report(model, flags);
      ASSERT_EQ(first.exit_code, 0) << model;
      ASSERT_GT(first.out.size(), 1000u) << model;
      for (int run = 1; run < 3; ++run) EXPECT_EQ(Report(model, flags).out, first.out) << model << " " << flags;
    }
  }
}

// ---- models/README.md ----

TEST(ModelsReadme, TheFirstExampleIsAModelThatReportsAndMatchesFourbar) {
  // The example at the top of models/README.md, as written: every point it uses is defined,
  // and it is the shipped four-bar (the same equations and K).
  std::ifstream in(kSource / "models" / "README.md");
  std::stringstream readme;
  readme << in.rdbuf();
  const std::string text = readme.str();
  const size_t begin = text.find("```yaml\nname: fourbar");
  ASSERT_NE(begin, std::string::npos);
  const size_t body = begin + 8, end = text.find("```", body);
  ASSERT_NE(end, std::string::npos);
  TempDir dir;
  const fs::path model = dir.path() / "example.yaml";
  std::ofstream(model) << text.substr(body, end - body);
  const Result example = RunCommand(std::string(MECHGEN_EXE) + " report " + model.string());
  ASSERT_EQ(example.exit_code, 0) << example.out;
  const Result shipped = Report("fourbar");
  ASSERT_EQ(shipped.exit_code, 0);
  auto from = [](const std::string& s, const std::string& what) { return s.substr(s.find(what)); };
  EXPECT_EQ(from(example.out, "Loop-closure equations"), from(shipped.out, "Loop-closure equations"));
}

// ---- LaTeX ----

bool HavePdflatex() { return std::system("pdflatex --version > /dev/null 2>&1") == 0; }

// Compiles `tex` with pdflatex in a fresh directory; returns the log on failure.
std::string CompileFailure(const std::string& tex) {
  TempDir dir;
  std::ofstream(dir.path() / "report.tex") << tex;
  const std::string cmd = "cd '" + dir.path().string() +
                          "' && pdflatex -no-shell-escape -interaction=nonstopmode -halt-on-error report.tex "
                          "> /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream log_in(dir.path() / "report.log");
  std::stringstream log;
  log << log_in.rdbuf();
  if (rc != 0 || !fs::exists(dir.path() / "report.pdf")) return "pdflatex failed:\n" + log.str();
  // A character the fonts do not have is only a warning in the log.
  if (log.str().find("Missing character") != std::string::npos) return "missing characters:\n" + log.str();
  return "";
}

TEST(ReportLatex, StandaloneDocumentCompilesForEveryShippedModel) {
  if (!HavePdflatex()) GTEST_SKIP() << "pdflatex is not installed (Debian: texlive-latex-base)";
  ASSERT_FALSE(ShippedModels().empty());
  for (const std::string& model : ShippedModels()) {
    const Result r = Report(model, "--latex --standalone");
    ASSERT_EQ(r.exit_code, 0) << model;
    EXPECT_NE(r.out.find("\\documentclass"), std::string::npos) << model;
    EXPECT_EQ(CompileFailure(r.out), "") << model;
  }
}

TEST(ReportLatex, NamesWithUnderscoresAndCamLawsPrintAsMath) {
  // Parameters the reader allows but LaTeX's subscripts did not: a multi-letter name with an
  // underscore, and one with two (r_2_3 was a double-subscript error).
  TempDir dir;
  const fs::path model = dir.path() / "names.yaml";
  std::ofstream(model) << R"(name: names
parameters:
  a: 1.0
  coupler_len: 3.5
  rocker_link: 3.0
  r_2_3: 4.0
links:
  ground:  {ground: true, points: {A: [0, 0], D: [r_2_3, 0]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}}
  coupler: {points: {B: [0, 0], C: [coupler_len, 0]}}
  rocker:  {points: {D: [0, 0], C: [rocker_link, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  B: {revolute: [crank.B, coupler.B]}
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
inputs:
  - {joint: A}
assembly: {theta_coupler: 30*deg, theta_rocker: 110*deg}
)";
  const Result r = RunCommand(std::string(MECHGEN_EXE) + " report --latex --standalone " + model.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\\mathrm{rocker\\_link}"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\\mathrm{coupler\\_len}"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("r_{\\mathrm{2\\_3}}"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("rocker_link"), std::string::npos) << "an unescaped underscore\n" << r.out;
  // A cam law by its joint's name, not GiNaC's internal \mathrm{law}(...).
  const Result cam = Report("cam_roller", "--latex --standalone");
  ASSERT_EQ(cam.exit_code, 0);
  EXPECT_EQ(cam.out.find("\\mathrm{law}"), std::string::npos) << cam.out;
  EXPECT_NE(cam.out.find("\\mathrm{lift}_{"), std::string::npos) << cam.out;
  if (!HavePdflatex()) GTEST_SKIP() << "pdflatex is not installed (Debian: texlive-latex-base)";
  EXPECT_EQ(CompileFailure(r.out), "");
}

}  // namespace
