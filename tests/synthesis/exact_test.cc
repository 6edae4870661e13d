// Exact path synthesis by homotopy continuation (issue 44; synthesis/exact_path.h), against
// oracles independent of it:
//   - PHCpack (Debian's `phc`, polyhedral homotopies: another method, another program) on the
//     same polynomial system: the same number of isolated solutions, and each of its regular
//     solutions among ours;
//   - the generated kinematics of tests/synthesis/models/synth_fourbar.yaml: every real
//     solution, built as that four-bar, passes through the five points at its crank angles;
//   - a four-bar whose own coupler points are the task: found again among the real solutions;
//   - Morgan and Wampler's count (J. Mech. Des. 112:544, 1990): 36 for generic data.
// Without `phc` on the PATH at configure time the PHCpack comparisons are skipped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <utility>
#include <vector>
#include <sstream>
#include <string>

#include "mechgen/synthesis/exact_path.h"
#include "synth_fourbar.h"

namespace {

using namespace mechgen::synthesis;
using homotopy::Complex;
using Model = mech::synth_fourbar::Model;

// Problem 7 of Morgan and Wampler: the pivots (0, 0) and (1, 0), five points.
FivePointTask Problem7() {
  FivePointTask t;
  t.crank_pivot = {0, 0};
  t.rocker_pivot = {1, 0};
  t.points = {{{0.50, 1.06}, {-0.83, -0.27}, {-0.34, 0.22}, {-0.13, 0.43}, {0.22, 0.78}}};
  return t;
}

// Data with no special structure (fixed digits).
FivePointTask Generic() {
  FivePointTask t;
  t.crank_pivot = {0.6715302078397394, -0.13446586418989326};
  t.rocker_pivot = {0.524560164915884, -0.9957878932977786};
  t.points = {{{-0.7312715117751976, 0.6948674738744653},
               {0.5275492379532281, -0.4898619485211566},
               {-0.009129825816118098, -0.10101787042252375},
               {0.3031859454455259, 0.5774467022710263},
               {-0.8122808264515302, -0.9433050469559874}}};
  return t;
}

// The same equations as exact_path.h's header states them, in PHCpack's input format (its
// variables x, xb, y, yb, q1..q4 for Q_j, r1..r4 for Q̄_j), on the same scaled data.
std::string PhcSystem(const FivePointTask& t) {
  const Complex A(t.crank_pivot[0], t.crank_pivot[1]), D(t.rocker_pivot[0], t.rocker_pivot[1]);
  const double scale = std::abs(D - A);
  auto c = [](Complex z) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%+.17g%+.17g*i)", z.real(), z.imag());
    return std::string(buf);
  };
  auto r = [](double v) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "(%+.17g)", v);
    return std::string(buf);
  };
  std::ostringstream s;
  s << "12\n";
  Complex u[5], v[5];
  for (int j = 0; j < 5; ++j) {
    const Complex P(t.points[static_cast<size_t>(j)][0], t.points[static_cast<size_t>(j)][1]);
    u[j] = (P - A) / scale;
    v[j] = (P - D) / scale;
  }
  for (int j = 1; j <= 4; ++j) {
    const std::string q = "q" + std::to_string(j), qb = "r" + std::to_string(j);
    s << c(std::conj(u[j])) << "*x*" << q << " + " << c(u[j]) << "*xb*" << qb << " - " << c(std::conj(u[0]))
      << "*x - " << c(u[0]) << "*xb + " << r(std::norm(u[j]) - std::norm(u[0])) << ";\n";
    s << c(std::conj(v[j])) << "*y*" << q << " + " << c(v[j]) << "*yb*" << qb << " - " << c(std::conj(v[0]))
      << "*y - " << c(v[0]) << "*yb + " << r(std::norm(v[j]) - std::norm(v[0])) << ";\n";
    s << q << "*" << qb << " - 1;\n";
  }
  return s.str();
}

struct PhcResult {
  int regular = -1;
  std::vector<homotopy::VecN<12>> solutions;  // the regular ones, in our variable order
};

// Runs `phc -b` (blackbox: root count, start system, continuation) and reads its output file.
bool RunPhc(const FivePointTask& t, PhcResult* out) {
  const std::string dir = testing::TempDir();
  const std::string in = dir + "/exact_phc_in.txt", res = dir + "/exact_phc_out.txt";
  std::ofstream(in) << PhcSystem(t);
  std::remove(res.c_str());
  const std::string cmd = std::string(MECHGEN_PHC) + " -b " + in + " " + res + " > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) return false;
  std::ifstream f(res);
  std::string line;
  const std::map<std::string, int> index = {{"x", 0},  {"xb", 1}, {"y", 2},  {"yb", 3}, {"q1", 4},  {"r1", 5},
                                            {"q2", 6}, {"r2", 7}, {"q3", 8}, {"r3", 9}, {"q4", 10}, {"r4", 11}};
  // The last "THE SOLUTIONS" list is the refined one; each solution's "== err : ... ==" line
  // ends with its kind ("real regular", "regular", "singular", ...).
  std::vector<std::string> lines;
  while (std::getline(f, line)) lines.push_back(line);
  size_t last = 0;
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind("THE SOLUTIONS", 0) == 0) last = i;
  homotopy::VecN<12> z = homotopy::VecN<12>::Zero();
  for (size_t i = last; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l.rfind("Number of regular solutions", 0) == 0) out->regular = std::atoi(l.substr(l.find(':') + 1).c_str());
    std::istringstream in_line(l);
    std::string name, colon;
    double re = 0, im = 0;
    if (in_line >> name >> colon >> re >> im && colon == ":" && index.count(name)) z(index.at(name)) = Complex(re, im);
    if (l.rfind("== err", 0) == 0 && l.find("regular") != std::string::npos) out->solutions.push_back(z);
  }
  return out->regular >= 0;
}

bool PhcAvailable() { return std::string(MECHGEN_PHC).size() > 0; }

// Where the generated four-bar puts its coupler point at the crank angle q on assembly mode m.
bool CouplerPoint(const Model::ParamsT<double>& p, double q, int mode, double* x, double* y) {
  Eigen::Matrix<double, Model::kNq, 1> qv;
  qv(0) = q;
  Eigen::Matrix<double, Model::kNphi, 1> phi;
  for (int i = 0; i < Model::kNphi; ++i) phi(i) = Model::kAssemblyPhi[static_cast<size_t>(i)];
  std::array<int, Model::kNumBlocks> modes = Model::kDefaultModes;
  modes[0] = mode;
  const auto report = Model::Solve(p, qv, &phi, modes);
  if (report.status != decltype(report.status)::kConverged) return false;
  Model::CoefficientsT<double> c;
  Model::Coeffs(p, qv, phi, &c);
  const int point = 0;  // coupler.P, the model's only output point
  *x = c.r_P(0, point);
  *y = c.r_P(1, point);
  return true;
}

Model::ParamsT<double> ParamsOf(const ExactFourBar& bar) {
  Model::ParamsT<double> p;
  p.a = bar.a, p.b = bar.b, p.c = bar.c, p.d = bar.d, p.xi = bar.xi, p.eta = bar.eta;
  p.x0 = bar.x0, p.y0 = bar.y0, p.theta0 = bar.theta0;
  return p;
}

// Every real solution as the generated four-bar: each point reached at its crank angle on one
// of the two assembly modes, to 1e-8 of the task's size; one mode for all five exactly when
// the solution says it is on one branch.
void CheckRealSolutionsWithTheGeneratedKinematics(const FivePointTask& t, const ExactPathResult& r) {
  const double tol = 1e-8 * (1 + r.scale);
  for (size_t s = 0; s < r.real.size(); ++s) {
    const ExactFourBar& bar = r.real[s];
    const auto p = ParamsOf(bar);
    std::array<int, 5> mode{};
    for (int j = 0; j < 5; ++j) {
      for (int m : {1, -1}) {
        double x = 0, y = 0;
        if (CouplerPoint(p, bar.crank[static_cast<size_t>(j)], m, &x, &y) &&
            std::hypot(x - t.points[static_cast<size_t>(j)][0], y - t.points[static_cast<size_t>(j)][1]) <= tol)
          mode[static_cast<size_t>(j)] = m;
      }
      EXPECT_NE(mode[static_cast<size_t>(j)], 0) << "real solution " << s << ": point " << j << " not reached on either mode";
    }
    bool one_mode = true;
    for (int j = 1; j < 5; ++j) one_mode = one_mode && mode[static_cast<size_t>(j)] == mode[0];
    EXPECT_EQ(one_mode, bar.same_branch) << "real solution " << s;
  }
}

// Problem 7's solutions, solved once for the tests below.
const ExactPathResult& Problem7Result() {
  static const ExactPathResult r = SolveFivePointsWithPivots(Problem7());
  return r;
}

TEST(ExactSynthesis, FivePointsWithPivotsAgainstPhcpackAndMorganWampler) {
  // Generic data have Morgan and Wampler's 36. Problem 7's are not generic for this
  // formulation: three of the 36 go to infinity there (a crank of infinite length with Q_j -> 1:
  // a slider dyad), in PHCpack as in ours (its three failed paths diverge).
  const std::vector<std::pair<FivePointTask, int>> cases = {{Problem7(), 33}, {Generic(), 36}};
  for (size_t k = 0; k < cases.size(); ++k) {
    const FivePointTask& t = cases[k].first;
    const ExactPathResult generic = k == 0 ? ExactPathResult() : SolveFivePointsWithPivots(t);
    const ExactPathResult& r = k == 0 ? Problem7Result() : generic;
    EXPECT_EQ(r.paths, 256);
    EXPECT_EQ(r.num_solutions, cases[k].second) << "case " << k;
    EXPECT_EQ(r.solutions.failed, 0);
    EXPECT_EQ(r.solutions.singular, 0);
    EXPECT_EQ(r.solutions.duplicates, 0);
    EXPECT_EQ(r.num_solutions + r.solutions.at_infinity, 256);
    CheckRealSolutionsWithTheGeneratedKinematics(t, r);
    if (!PhcAvailable()) continue;
    PhcResult phc;
    ASSERT_TRUE(RunPhc(t, &phc)) << "phc -b failed";
    EXPECT_EQ(r.num_solutions, phc.regular) << "case " << k;
    ASSERT_EQ(static_cast<int>(phc.solutions.size()), phc.regular);
    for (const auto& z : phc.solutions) {
      double best = HUGE_VAL;
      for (const auto& ours : r.solutions.finite) best = std::min(best, (ours - z).cwiseAbs().maxCoeff());
      EXPECT_LE(best, 1e-7 * (1 + z.cwiseAbs().maxCoeff())) << "case " << k << ": a regular solution of phc's not among ours";
    }
  }
  if (!PhcAvailable()) GTEST_SKIP() << "phc (Debian's phcpack) not found at configure time: counts not compared";
}

TEST(ExactSynthesis, RecoversAFourBarFromItsOwnCouplerPoints) {
  // The model's default four-bar (a = 1, b = 3.5, c = 3, d = 4, P at (1.5, 1) on BC), moved.
  Model::ParamsT<double> p;
  p.x0 = 0.3, p.y0 = -0.2, p.theta0 = 0.25;
  const std::array<double, 5> crank{0.3, 1.2, 2.0, 3.1, 4.4};
  FivePointTask t;
  t.crank_pivot = {p.x0, p.y0};
  t.rocker_pivot = {p.x0 + p.d * std::cos(p.theta0), p.y0 + p.d * std::sin(p.theta0)};
  for (int j = 0; j < 5; ++j)
    ASSERT_TRUE(CouplerPoint(p, crank[static_cast<size_t>(j)], Model::kDefaultModes[0], &t.points[static_cast<size_t>(j)][0],
                             &t.points[static_cast<size_t>(j)][1]));
  const ExactPathResult r = SolveFivePointsWithPivots(t);
  CheckRealSolutionsWithTheGeneratedKinematics(t, r);
  int found = 0;
  for (const ExactFourBar& bar : r.real) {
    const double err = std::max({std::abs(bar.a - p.a), std::abs(bar.b - p.b), std::abs(bar.c - p.c), std::abs(bar.d - p.d),
                                 std::abs(bar.xi - p.xi), std::abs(bar.eta - p.eta)});
    if (err > 1e-8) continue;
    ++found;
    for (int j = 0; j < 5; ++j)
      EXPECT_NEAR(std::remainder(bar.crank[static_cast<size_t>(j)] - crank[static_cast<size_t>(j)], 6.283185307179586), 0, 1e-9);
    EXPECT_TRUE(bar.same_branch);
    EXPECT_EQ(bar.direction, 1);  // the crank angles above increase
    EXPECT_TRUE(bar.grashof);     // 1 + 4 <= 3 + 3.5
    EXPECT_TRUE(bar.crank_turns);  // the crank is the shortest link
    EXPECT_TRUE(bar.defect_free());
  }
  EXPECT_EQ(found, 1);
}

TEST(ExactSynthesis, SameBytesOnEveryRun) {
  const ExactPathResult& a = Problem7Result();
  const ExactPathResult b = SolveFivePointsWithPivots(Problem7());
  ASSERT_EQ(a.solutions.finite.size(), b.solutions.finite.size());
  for (size_t i = 0; i < a.solutions.finite.size(); ++i)
    EXPECT_EQ(0, std::memcmp(a.solutions.finite[i].data(), b.solutions.finite[i].data(), sizeof(Complex) * 12));
}

}  // namespace
