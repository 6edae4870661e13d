// Path synthesis (issue 28) against oracles independent of it:
//   - the local stage's Jacobian (the generated dr_P/dp and K_P) against central differences
//     of its own residuals (positions solved again at p +- h, q +- h);
//   - the shipped four-bar's own coupler points (computed by hand formulas in Python, in
//     tasks/fourbar_refind.yaml) fed back: the synthesis passes through them to ~1e-10;
//   - determinism: the same seed gives the same bytes with 1 and 2 threads;
//   - the model file written back reads back (yaml-cpp) with exactly the new values, and the
//     generated model at those values passes through the targets;
//   - the task file's errors: FILE:LINE:COLUMN.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "fourbar.h"
#include "mechgen/synthesis/freudenstein.h"
#include "mechgen/synthesis/optimize.h"
#include "mechgen/synthesis/output.h"
#include "mechgen/synthesis/report.h"
#include "mechgen/synthesis/task.h"
#include "synth_fourbar.h"

namespace {

using namespace mechgen::synthesis;

std::string Tasks(const std::string& name) { return std::string(MECHGEN_SYNTHESIS_TASKS) + "/" + name; }

template <class M>
BoundPath<M> Bind(const std::string& file) {
  PathTask task;
  std::string error;
  EXPECT_TRUE(ParseTask(file, &task, &error)) << error;
  BoundPath<M> b;
  EXPECT_TRUE(BindPathTask<M>(task, typename M::template ParamsT<double>(), &b, &error)) << error;
  return b;
}

// The residuals at (x, timing) through the cost function (no Jacobian).
template <class M>
bool Residuals(PathResiduals<M>& cost, const std::vector<double>& x, const std::vector<double>& t,
               std::vector<double>* r) {
  const double* params[2] = {x.data(), t.data()};
  r->assign(static_cast<size_t>(cost.num_residuals()), 0.0);
  return cost.Evaluate(params, r->data(), nullptr);
}

template <class M>
void CheckJacobian(const BoundPath<M>& b, std::vector<double> x, std::vector<double> t) {
  PathEvaluator<M> eval(b);
  const int nt = static_cast<int>(t.size());
  PathResiduals<M> cost(&eval, nt);
  const int nr = cost.num_residuals(), nv = static_cast<int>(x.size());
  std::vector<double> r(static_cast<size_t>(nr)), jx(static_cast<size_t>(nr * nv)), jt(static_cast<size_t>(nr * std::max(nt, 1)));
  const double* params[2] = {x.data(), t.data()};
  double* jac[2] = {jx.data(), jt.data()};
  ASSERT_TRUE(cost.Evaluate(params, r.data(), jac));
  const double h = 1e-6;
  std::vector<double> rp, rm;
  for (int j = 0; j < nv; ++j) {
    std::vector<double> xp = x, xm = x;
    xp[static_cast<size_t>(j)] += h, xm[static_cast<size_t>(j)] -= h;
    ASSERT_TRUE(Residuals(cost, xp, t, &rp));
    ASSERT_TRUE(Residuals(cost, xm, t, &rm));
    for (int i = 0; i < nr; ++i) {
      const double fd = (rp[static_cast<size_t>(i)] - rm[static_cast<size_t>(i)]) / (2 * h);
      EXPECT_NEAR(jx[static_cast<size_t>(i * nv + j)], fd, 1e-7 * std::max(1.0, std::abs(fd)))
          << "d r" << i << " / d " << b.task.variables[static_cast<size_t>(j)].name;
    }
  }
  for (int k = 0; k < nt; ++k) {
    std::vector<double> tp = t, tm = t;
    tp[static_cast<size_t>(k)] += h, tm[static_cast<size_t>(k)] -= h;
    ASSERT_TRUE(Residuals(cost, x, tp, &rp));
    ASSERT_TRUE(Residuals(cost, x, tm, &rm));
    for (int i = 0; i < nr; ++i) {
      const double fd = (rp[static_cast<size_t>(i)] - rm[static_cast<size_t>(i)]) / (2 * h);
      EXPECT_NEAR(jt[static_cast<size_t>(i * nt + k)], fd, 1e-7 * std::max(1.0, std::abs(fd))) << "d r" << i << " / d t" << k;
    }
  }
}

TEST(PathSynthesis, JacobianFreeTimingAgainstCentralDifferences) {
  const auto b = Bind<mech::fourbar::Model>(Tasks("fourbar_refind.yaml"));
  // Away from the defaults, the timing anywhere on the crank's turn.
  CheckJacobian(b, {1.1, 3.3, 3.2, 1.2, 0.7}, {0.1, 0.8, 1.5, 2.2, 2.9, 3.6, 4.3, 5.0, 5.7});
}

TEST(PathSynthesis, JacobianPrescribedTimingRelativeToTheFrame) {
  // Every one of the nine parameters, the frame's angle among them (q_i = offset + angle_i +
  // theta0: theta0's column carries K_P too), the offset a variable.
  const auto b = Bind<mech::synth_fourbar::Model>(Tasks("jacobian_placed.yaml"));
  CheckJacobian(b, {1.1, 3.3, 3.2, 4.2, 1.2, 0.7, 0.3, -0.4, 0.25}, {0.35});
}

TEST(PathSynthesis, RefindsTheFourBarsOwnCouplerPoints) {
  const auto b = Bind<mech::fourbar::Model>(Tasks("fourbar_refind.yaml"));
  const SearchResult s = Synthesize(b, 1, 2);
  const Candidate& c = s.best.best;
  ASSERT_TRUE(c.feasible()) << c.defect;
  for (int i = 0; i < b.n; ++i) EXPECT_LT(c.distance[static_cast<size_t>(i)], 1e-10) << "target " << i + 1;
  // The mechanism found is the shipped one (ground held: no cognate): a, b, c, xi, eta.
  const std::vector<double> expected = {1.0, 3.5, 3.0, 1.5, 1.0};
  for (size_t j = 0; j < expected.size(); ++j) EXPECT_NEAR(c.x[j], expected[j], 1e-8) << b.task.variables[j].name;
  EXPECT_GT(s.evaluations, 0);
  EXPECT_LE(s.best.global.error, 1e3);
}

TEST(PathSynthesis, SameBytesForOneAndTwoThreads) {
  const auto b = Bind<mech::fourbar::Model>(Tasks("fourbar_refind.yaml"));
  const SearchResult one = Synthesize(b, 7, 1), two = Synthesize(b, 7, 2);
  ASSERT_EQ(one.runs.size(), two.runs.size());
  EXPECT_EQ(one.evaluations, two.evaluations);
  for (size_t r = 0; r < one.runs.size(); ++r) {
    const Candidate &u = one.runs[r].best, &v = two.runs[r].best;
    ASSERT_EQ(u.x.size(), v.x.size());
    EXPECT_EQ(0, std::memcmp(u.x.data(), v.x.data(), u.x.size() * sizeof(double))) << "run " << r;
    EXPECT_EQ(0, std::memcmp(u.q.data(), v.q.data(), u.q.size() * sizeof(double))) << "run " << r;
    EXPECT_EQ(0, std::memcmp(&u.error, &v.error, sizeof(double))) << "run " << r;
  }
}

TEST(PathSynthesis, ModelFileWrittenBackReadsBackExactly) {
  std::ifstream in(std::string(MECHGEN_MODELS_DIR) + "/fourbar.yaml");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const std::vector<std::string> names = {"a", "xi", "eta"};
  const std::vector<double> values = {0.1 + 0.2, -1.0 / 3.0, 2.5e-7};
  std::string out, error;
  ASSERT_TRUE(RewriteParameters(text, names, values, &out, &error)) << error;
  const YAML::Node root = YAML::Load(out);
  for (size_t k = 0; k < names.size(); ++k)
    EXPECT_EQ(root["parameters"][names[k]]["value"].as<double>(), values[k]) << names[k];
  EXPECT_EQ(root["parameters"]["b"]["value"].as<double>(), 3.5);  // the others untouched
  EXPECT_EQ(root["parameters"]["a"]["doc"].as<std::string>(), "crank AB");
  // Only the three values changed: the same number of lines, the same comments.
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), std::count(text.begin(), text.end(), '\n'));
}

std::string ParseError(const std::string& yaml) {
  const std::string path = ::testing::TempDir() + "/bad_task.yaml";
  std::ofstream(path) << yaml;
  PathTask task;
  std::string error;
  EXPECT_FALSE(ParseTask(path, &task, &error));
  return error.substr(error.find("bad_task.yaml"));
}

TEST(PathSynthesis, TaskErrorsSayWhereAndWhat) {
  const std::string head = "synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1]]\n";
  EXPECT_EQ(ParseError(head + "variables: {a: [2, 1]}\n"), "bad_task.yaml:4:16: variable a: min must be below max");
  EXPECT_EQ(ParseError(head + "variables: {a: [0, 1]}\ntiming: {angles: [10deg]}\n"),
            "bad_task.yaml:5:18: timing.angles: expected 2 angles (one per target)");
  EXPECT_EQ(ParseError(head + "variables: {a: [0, 1]}\nconstrains: {}\n").substr(0, 52),
            "bad_task.yaml:5:1: unknown key 'constrains' in the t");
  EXPECT_EQ(ParseError("synthesis: motion\n"),
            "bad_task.yaml:1:12: synthesis: 'motion' is not supported; this version does `path` (function and "
            "motion generation are planned)");
  // Bound to the model: a name it does not have.
  const std::string path = ::testing::TempDir() + "/bad_task.yaml";
  std::ofstream(path) << head + "variables:\n  a: [0, 1]\n  zeta: [0, 1]\n";
  PathTask task;
  std::string error;
  ASSERT_TRUE(ParseTask(path, &task, &error)) << error;
  BoundPath<mech::fourbar::Model> b;
  EXPECT_FALSE(BindPathTask<mech::fourbar::Model>(task, {}, &b, &error));
  EXPECT_EQ(error.substr(error.find("bad_task.yaml")),
            "bad_task.yaml:6:3: variable 'zeta' is not one of the model's design parameters (a, b, c, d, xi, eta); add "
            "it to the model's `design:` list");
}

// ---- Freudenstein's equation (function generation, exact) --------------------------------

// The shipped four-bar's output angle (theta_rocker) at theta_crank, by the generated solve on
// the given assembly mode; NaN if it does not assemble.
double Rocker(const mech::fourbar::Params<double>& p, double theta2, int mode) {
  Eigen::Matrix<double, 1, 1> q;
  q(0) = theta2;
  Eigen::Vector2d phi(0.5, 1.9);
  const auto report = mech::fourbar::Model::Solve(p, q, &phi, {mode});
  return report.status == mech::fourbar::SolveStatus::kConverged ? phi(1) : std::nan("");
}

TEST(Freudenstein, ThreePairsOfTheShippedFourBarGiveItBack) {
  const mech::fourbar::Params<double> p;  // a 1, b 3.5, c 3, d 4
  const std::vector<double> t2 = {40 * M_PI / 180, 100 * M_PI / 180, 200 * M_PI / 180};
  std::vector<double> t4;
  for (double t : t2) t4.push_back(Rocker(p, t, 1));
  const FreudensteinResult r = Freudenstein(t2, t4, 4.0);
  ASSERT_TRUE(r.ok) << r.why;
  EXPECT_NEAR(r.a, 1.0, 1e-12);
  EXPECT_NEAR(r.b, 3.5, 1e-12);
  EXPECT_NEAR(r.c, 3.0, 1e-12);
  for (double res : r.residual) EXPECT_LE(std::abs(res), 1e-12);
}

TEST(Freudenstein, ThreePrescribedPairsAreMetByTheSynthesizedFourBar) {
  // A function generator: the output at 100, 110, 125 deg while the input turns 30, 60, 90 deg.
  const std::vector<double> t2 = {30 * M_PI / 180, 60 * M_PI / 180, 90 * M_PI / 180};
  const std::vector<double> t4 = {100 * M_PI / 180, 110 * M_PI / 180, 125 * M_PI / 180};
  const FreudensteinResult r = Freudenstein(t2, t4, 4.0);
  ASSERT_TRUE(r.ok) << r.why;
  for (double res : r.residual) EXPECT_LE(std::abs(res), 1e-12);
  // The oracle: the generated model with these lengths, solved at the three inputs, gives the
  // three outputs to 1e-12 on one assembly mode for all three (no branch change between them).
  mech::fourbar::Params<double> p;
  p.a = r.a, p.b = r.b, p.c = r.c, p.d = r.d;
  int modes_meeting_all = 0;
  for (int mode : {1, -1}) {
    bool all = true;
    for (size_t i = 0; i < t2.size(); ++i)
      all = all && std::abs(std::remainder(Rocker(p, t2[i], mode) - t4[i], 2 * M_PI)) <= 1e-12;
    modes_meeting_all += all;
  }
  EXPECT_EQ(modes_meeting_all, 1) << "a = " << r.a << ", b = " << r.b << ", c = " << r.c;
}

TEST(Freudenstein, LeastSquaresForMorePairs) {
  const mech::fourbar::Params<double> p;
  std::vector<double> t2, t4;
  for (int k = 0; k < 7; ++k) {
    t2.push_back((15 + 50 * k) * M_PI / 180);
    t4.push_back(Rocker(p, t2.back(), 1));
  }
  const FreudensteinResult exact = Freudenstein(t2, t4, 4.0);
  ASSERT_TRUE(exact.ok) << exact.why;
  EXPECT_NEAR(exact.a, 1.0, 1e-12);
  EXPECT_NEAR(exact.b, 3.5, 1e-12);
  EXPECT_NEAR(exact.c, 3.0, 1e-12);
  // Perturbed outputs: no exact solution; the least-squares K makes the residual orthogonal
  // to the columns d(residual)/dK = (cos t4, -cos t2, 1) (the normal equations).
  for (size_t i = 0; i < t4.size(); ++i) t4[i] += 0.01 * std::sin(3.0 * static_cast<double>(i));
  const FreudensteinResult ls = Freudenstein(t2, t4, 4.0);
  double g0 = 0, g1 = 0, g2 = 0, rr = 0;
  for (size_t i = 0; i < t2.size(); ++i) {
    const double res = ls.residual[i];
    g0 += res * std::cos(t4[i]), g1 -= res * std::cos(t2[i]), g2 += res, rr += res * res;
  }
  EXPECT_GT(rr, 1e-8);  // not exact
  EXPECT_LE(std::abs(g0) + std::abs(g1) + std::abs(g2), 1e-14);
}

TEST(Freudenstein, RefusesPairsNoFourBarMeets) {
  // (90, 90), (0, 90), (90, 0) deg: K3 = 1, K2 = 1, K1 = -1 by hand: no crank length d/K1 > 0.
  const std::vector<double> t2 = {M_PI / 2, 0, M_PI / 2}, t4 = {M_PI / 2, M_PI / 2, 0};
  const FreudensteinResult r = Freudenstein(t2, t4, 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_NEAR(r.K(0), -1, 1e-15);
  EXPECT_NEAR(r.K(1), 1, 1e-15);
  EXPECT_NEAR(r.K(2), 1, 1e-15);
  EXPECT_FALSE(Freudenstein({0, 1}, {0, 1}, 1.0).ok);  // two pairs
}

// A constructed defect: a non-Grashof four-bar (a 3, b 2, c 2.5, d 4: s + l = 6 > p + q =
// 5.5; by hand |BD|^2 = 25 - 24 cos(theta) <= (b + c)^2 limits the crank to |theta| <= 78.6
// deg) reaches both targets on its assembly mode, at 10 and 350 deg, but the prescribed
// motion from the first to the second turns the crank through 180 deg, where the loop does
// not close: refused by the candidate's check and by the runtime's continuation. The same
// targets at 10 and -10 deg (the crank turning back through 0) are accepted.
TEST(PathSynthesis, DeadPointBetweenTargetsIsADefect) {
  using M = mech::fourbar::Model;
  M::ParamsT<double> p;
  p.a = 3, p.b = 2, p.c = 2.5;
  for (const char* angles : {"[10deg, 350deg]", "[10deg, -10deg]"}) {
    const std::string path = ::testing::TempDir() + "/dead_point.yaml";
    // The targets: the coupler point at 10 and -10 deg (350 deg is the same configuration).
    PathTask probe;
    std::string error;
    std::ofstream(path) << "synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1]]\n"
                        << "timing: {angles: " << angles << "}\nvariables: {a: [2.9, 3.1], b: [1.9, 2.1]}\n";
    ASSERT_TRUE(ParseTask(path, &probe, &error)) << error;
    BoundPath<M> b;
    ASSERT_TRUE(BindPathTask<M>(probe, p, &b, &error)) << error;
    PathEvaluator<M> eval(b);
    Eigen::Vector2d phi;
    M::CoefficientsT<double> co;
    for (int i = 0; i < 2; ++i) {
      ASSERT_TRUE(eval.PointAt(p, (i == 0 ? 10 : -10) * M_PI / 180, &phi, &co));
      b.task.tx[static_cast<size_t>(i)] = co.r_P(0, 0);
      b.task.ty[static_cast<size_t>(i)] = co.r_P(1, 0);
    }
    EXPECT_FALSE(eval.PointAt(p, M_PI, &phi, &co));  // the hand bound: no loop at 180 deg
    const Candidate c = eval.Evaluate({3.0, 2.0});
    EXPECT_LT(c.error, 1e-24);  // both targets reached exactly
    const bool through_180 = std::string(angles) == "[10deg, 350deg]";
    if (through_180) {
      EXPECT_FALSE(c.feasible());
      EXPECT_NE(c.defect.find("leaves its assembly branch"), std::string::npos) << c.defect;
      EXPECT_NE(ContinuationCheck(&eval, c), "");
    } else {
      EXPECT_TRUE(c.feasible()) << c.defect;
      EXPECT_EQ(ContinuationCheck(&eval, c), "");
    }
  }
}

}  // namespace
