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

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <sstream>

#include "fourbar.h"
#include "function_fourbar.h"
#include "mechgen/synthesis/burmester.h"
#include "mechgen/synthesis/freudenstein.h"
#include "mechgen/synthesis/function.h"
#include "mechgen/synthesis/motion.h"
#include "mechgen/synthesis/optimize.h"
#include "mechgen/synthesis/output.h"
#include "mechgen/synthesis/projection.h"
#include "mechgen/synthesis/report.h"
#include "mechgen/synthesis/task.h"
#include "synth_fourbar.h"
#include "mechgen/core/view_runtime.h"
#include "mechgen/synthesis/view_synthesis.h"  // the synthesis layer for the view: mechgen_runtime_view_synthesis

namespace mech::synth_fourbar {
const mechgen::ModelView& View();
}

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
  EXPECT_EQ(ParseError(head + "variables: {a: [2, 1]}\n"), "bad_task.yaml:4:16: error: variable a: min must be below max");
  EXPECT_EQ(ParseError(head + "variables: {a: [0, 1]}\ntiming: {angles: [10deg]}\n"),
            "bad_task.yaml:5:18: error: timing.angles: expected 2 angles (one per target)");
  EXPECT_EQ(ParseError(head + "variables: {a: [0, 1]}\nconstrains: {}\n").substr(0, 59),
            "bad_task.yaml:5:1: error: unknown key 'constrains' in the t");
  EXPECT_EQ(ParseError("synthesis: motion\n"),
            "bad_task.yaml:1:12: error: synthesis: 'motion' is not supported; this version does `path` (function and "
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
            "bad_task.yaml:6:3: error: variable 'zeta' is not one of the model's design parameters (a, b, c, d, xi, eta); add "
            "it to the model's `design:` list");
}

// ---- The written model file read back, assembled as the sweep does (issues 44 and 45) -----

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A number of the model file: a plain number, or one times deg (the model's `360*deg`).
double ModelNumber(const YAML::Node& n) {
  std::string s = n.Scalar();
  double scale = 1;
  if (s.size() > 4 && s.compare(s.size() - 4, 4, "*deg") == 0) s.resize(s.size() - 4), scale = M_PI / 180;
  return std::stod(s) * scale;
}

// The written model file read back as the generator and the sweep see it: its parameters, its
// assembly (the input and every dependent coordinate, by name) and the input's range.
template <class M>
struct WrittenModel {
  typename M::template ParamsT<double> p;
  Eigen::Matrix<double, M::kNq, 1> q;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  double lo = 0, hi = 0;
  explicit WrittenModel(const std::string& text) {
    const YAML::Node root = YAML::Load(text);
    for (const char* n : M::template ParamsT<double>::kNames) {
      const YAML::Node e = root["parameters"][n];
      *p.Find(n) = ModelNumber(e.IsMap() ? e["value"] : e);
    }
    q(0) = ModelNumber(root["assembly"][M::kQNames[0]]);
    for (int i = 0; i < M::kNphi; ++i) phi(i) = ModelNumber(root["assembly"][M::kPhiNames[static_cast<size_t>(i)]]);
    lo = ModelNumber(root["inputs"][0]["range"][0]);
    hi = ModelNumber(root["inputs"][0]["range"][1]);
  }
};

// The written model assembled as the sweep assembles a model (PositionSolver::AssembleDefault:
// at its assembly input and values, on the branch sign det Phi_phi has there): converged, on
// the synthesis' mode (M::kDefaultModes, the modes PositionSolver finds back), and from there
// by continuation (steps of at most 10 deg) through the motion `motion` (the targets' inputs
// in the written model's terms), at_target(k, state) at each; then the sweep's way over the
// written range (to its start, then 1 deg steps to its end), every step converged.
template <class M>
void ExpectSweepable(const std::string& text, const std::vector<double>& motion,
                     const std::function<void(size_t, const mechgen::position::State<M>&)>& at_target,
                     const std::array<int, M::kNumBlocks>& synthesis_modes = M::kDefaultModes) {
  const WrittenModel<M> w(text);
  double det = 0;
  M::DetPhiPhi(w.p, w.q, w.phi, &det);
  ASSERT_NE(det, 0);
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), w.p);
  mechgen::position::Summary summary;
  ASSERT_EQ(solver.Assemble(w.q, w.phi, det > 0 ? 1 : -1, &summary), mechgen::position::Status::kConverged)
      << mechgen::position::FormatSummary(summary);
  std::array<int, M::kNumBlocks> modes{};
  ASSERT_TRUE(solver.modes(&modes));
  EXPECT_EQ(modes, synthesis_modes);
  // The generator's rule (the root nearest the assembly values, block by block): they are the
  // root of the synthesis' modes, the other mode's root lies far.
  Eigen::Matrix<double, M::kNphi, 1> phi = w.phi, other = w.phi;
  ASSERT_EQ(M::Solve(w.p, w.q, &phi, synthesis_modes).status, decltype(M::Solve(w.p, w.q, &phi, synthesis_modes).status)::kConverged);
  EXPECT_LT((phi - w.phi).norm(), 1e-12);
  std::array<int, M::kNumBlocks> flipped = synthesis_modes;
  flipped[0] = -flipped[0];
  M::Solve(w.p, w.q, &other, flipped);
  EXPECT_GT((other - w.phi).norm(), 1e-3);
  // The motion through the targets.
  const double shift = w.q(0) - motion[0];
  for (size_t k = 0; k < motion.size(); ++k) {
    const double from = solver.state().q(0), to = motion[k] + shift;
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(to - from) / (10 * M_PI / 180))));
    for (int s = 1; s <= steps; ++s) {
      Eigen::Matrix<double, M::kNq, 1> qs;
      qs(0) = from + (to - from) * s / steps;
      ASSERT_EQ(solver.MoveTo(qs, &summary), mechgen::position::Status::kConverged) << "target " << k + 1;
    }
    at_target(k, solver.state());
  }
  // The sweep over the written range.
  mechgen::position::PositionSolver<M> sweep(mechgen::position::Options(), w.p);
  ASSERT_EQ(sweep.Assemble(w.q, w.phi, det > 0 ? 1 : -1, nullptr), mechgen::position::Status::kConverged);
  Eigen::Matrix<double, M::kNq, 1> qs;
  qs(0) = w.lo;
  ASSERT_EQ(sweep.MoveTo(qs, nullptr), mechgen::position::Status::kConverged);
  const int steps = static_cast<int>(std::ceil((w.hi - w.lo) / (M_PI / 180)));
  for (int s = 1; s <= steps; ++s) {
    qs(0) = w.lo + (w.hi - w.lo) * s / steps;
    ASSERT_EQ(sweep.MoveTo(qs, nullptr), mechgen::position::Status::kConverged) << "sweep at " << qs(0);
  }
}

// ExpectSweepable with the point `point` at each target within 1e-9 of `expected` (the
// synthesis' own points).
template <class M>
void ExpectSweepable(const std::string& text, const std::vector<double>& motion, int point,
                     const std::vector<Eigen::Vector2d>& expected,
                     const std::array<int, M::kNumBlocks>& synthesis_modes = M::kDefaultModes) {
  ExpectSweepable<M>(
      text, motion,
      [&](size_t k, const mechgen::position::State<M>& state) {
        EXPECT_LT((Eigen::Vector2d(state.r_P(0, point), state.r_P(1, point)) - expected[k]).norm(), 1e-9)
            << "target " << k + 1;
      },
      synthesis_modes);
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
TEST(PathSynthesis, CandidatesAreJudgedByThePositionSolversOneThreshold) {
  // Issue 28's leftover (done in path.h: SolveOnMode / Regular, read by the path, function,
  // motion and exact checks): a configuration is regular when 1/cond_1(Phi_phi) >= kMinRcond,
  // the position solver's own default (Options::min_rcond). By hand: A = [[1, 1], [1, 1 + e]]
  // has ||A||_1 = 2 + e and A^-1 = [[1 + e, -1], [-1, 1]] / e, ||A^-1||_1 = (2 + e) / e, so
  // 1/cond_1 = e / (2 + e)^2: regular just above the threshold, not just below, on the
  // fixed-size matrix and on one whose size is known at run time only (the model view's).
  EXPECT_EQ(mechgen::position::Options().min_rcond, mechgen::kMinRcond);
  for (double e : {3.9e-6, 3.99e-6, 4.01e-6, 4.1e-6, 1e-3, 1e-9}) {
    const double rcond = e / ((2 + e) * (2 + e));
    Eigen::Matrix2d A;
    A << 1, 1, 1, 1 + e;
    // (The view's own matrix type: its ConditionAndDeterminantDynamic is compiled once, in
    // mechgen_runtime_view, not here.)
    const mechgen::ModelTypes<mechgen::ViewModel>::MatCPhi B = A;
    EXPECT_EQ(Regular(A), rcond >= mechgen::kMinRcond) << "e = " << e << ", 1/cond_1 = " << rcond;
    EXPECT_EQ(Regular(B), rcond >= mechgen::kMinRcond) << "e = " << e << ", 1/cond_1 = " << rcond;
  }
}

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

// ---- Function generation (synthesis/function.h) ----

// The shipped four-bar's rocker angle at the crank angle t2, by hand (not the generated
// solve): C is where the circles |C - B| = b and |C - D| = c meet, on the open assembly's
// side: theta4 = beta - gamma, beta the direction of D->B, gamma at D by the cosine law.
double HandTheta4(double a, double b, double c, double d, double t2) {
  const double bx = a * std::cos(t2) - d, by = a * std::sin(t2);
  const double e2 = bx * bx + by * by;
  const double gamma = std::acos((c * c + e2 - b * b) / (2 * c * std::sqrt(e2)));
  return std::atan2(by, bx) - gamma;
}

std::string Deg(double rad) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.17gdeg", rad * 180 / M_PI);
  return buffer;
}

// A function task on fourbar with the pairs (t2, HandTheta4(t2) + shift_i) written into a file.
BoundFunction<mech::fourbar::Model> FunctionTaskOf(const std::vector<double>& t2, const std::vector<double>& shift,
                                                   bool freudenstein, int restarts,
                                                   const mech::fourbar::Model::ParamsT<double>& base = {}) {
  std::string yaml = "synthesis: function\nmodel: fourbar.yaml\noutput: theta_rocker\npairs:\n";
  for (size_t i = 0; i < t2.size(); ++i)
    yaml += "  - [" + Deg(t2[i]) + ", " + Deg(HandTheta4(1.0, 3.5, 3.0, 4.0, t2[i]) + (shift.empty() ? 0.0 : shift[i])) + "]\n";
  if (freudenstein) yaml += "freudenstein: {crank: a, coupler: b, rocker: c, ground: d}\n";
  yaml += "variables: {a: [0.5, 6], b: [0.5, 6], c: [0.5, 6]}\nsearch: {restarts: " + std::to_string(restarts) + "}\n";
  const std::string path = ::testing::TempDir() + "/function_task.yaml";
  std::ofstream(path) << yaml;
  FunctionTask task;
  std::string error;
  EXPECT_TRUE(ParseFunctionTask(path, &task, &error)) << error;
  BoundFunction<mech::fourbar::Model> b;
  EXPECT_TRUE(BindFunctionTask<mech::fourbar::Model>(task, base, &b, &error)) << error;
  return b;
}

constexpr double kDeg = M_PI / 180;

TEST(FunctionSynthesis, ThreeHandSolvedPairsExactlyByFreudenstein) {
  const auto b = FunctionTaskOf({40 * kDeg, 90 * kDeg, 140 * kDeg}, {}, /*freudenstein=*/true, /*restarts=*/0);
  const FunctionResult r = SynthesizeFunction(b, 1);
  ASSERT_TRUE(r.exact.ok) << r.exact.why;
  for (double e : r.exact.residual) EXPECT_LT(std::abs(e), 1e-12);
  EXPECT_NEAR(r.exact.a, 1.0, 1e-12);
  EXPECT_NEAR(r.exact.b, 3.5, 1e-12);
  EXPECT_NEAR(r.exact.c, 3.0, 1e-12);
  // The exact answer through the generated solve: the rocker at the hand-solved angles.
  FunctionEvaluator<mech::fourbar::Model> eval(b);
  const FunctionCandidate exact = eval.Check({r.exact.a, r.exact.b, r.exact.c});
  ASSERT_TRUE(exact.feasible()) << exact.defect;
  for (double e : exact.residual) EXPECT_LT(std::abs(e), 1e-12);
  ASSERT_TRUE(r.best.feasible()) << r.best.defect;
  for (double e : r.best.residual) EXPECT_LT(std::abs(e), 1e-12);
}

// The generated Jacobian of a function task's residuals (n_r of them) at x against central
// differences of the residuals (h = 1e-6, 1e-7 relative).
void CheckFunctionJacobian(FunctionResiduals<mech::fourbar::Model>* cost, const std::vector<double>& x, int n_r) {
  const size_t n = x.size(), m = static_cast<size_t>(n_r);
  std::vector<double> r(m), rp(m), rm(m), jac(m * n);
  const double* params[1] = {x.data()};
  double* jacs[1] = {jac.data()};
  ASSERT_TRUE(cost->Evaluate(params, r.data(), jacs));
  const double h = 1e-6;
  for (size_t j = 0; j < n; ++j) {
    std::vector<double> xp = x, xm = x;
    xp[j] += h, xm[j] -= h;
    const double* pp[1] = {xp.data()};
    const double* pm[1] = {xm.data()};
    ASSERT_TRUE(cost->Evaluate(pp, rp.data(), nullptr));
    ASSERT_TRUE(cost->Evaluate(pm, rm.data(), nullptr));
    for (size_t i = 0; i < m; ++i) {
      const double fd = (rp[i] - rm[i]) / (2 * h);
      EXPECT_NEAR(jac[i * n + j], fd, 1e-7 * std::max(1.0, std::abs(fd))) << "residual " << i << " var " << j;
    }
  }
}

// The error of a function task with free start angles (three lengths, two angles) is
// stationary at x: each central difference of it (h = 1e-5 for a length, 1e-6 for an angle)
// below `bound`.
void ExpectStationary(FunctionEvaluator<mech::fourbar::Model>* eval, const std::vector<double>& x, double bound) {
  for (size_t j = 0; j < 5; ++j) {
    const double h = j < 3 ? 1e-5 : 1e-6;
    std::vector<double> xp = x, xm = x;
    xp[j] += h, xm[j] -= h;
    const double g = (eval->Check(xp).error - eval->Check(xm).error) / (2 * h);
    EXPECT_LT(std::abs(g), bound) << "dE/dx" << j;
  }
}

TEST(FunctionSynthesis, JacobianAgainstCentralDifferences) {
  auto b = FunctionTaskOf({30 * kDeg, 60 * kDeg, 90 * kDeg, 120 * kDeg, 150 * kDeg}, {}, false, 0);
  FunctionEvaluator<mech::fourbar::Model> eval(b);
  FunctionResiduals<mech::fourbar::Model> cost(&eval);
  CheckFunctionJacobian(&cost, {1.2, 3.3, 3.1}, 5);
}

TEST(FunctionSynthesis, FedBackPairsOfAKnownFourBarFoundByTheOptimiser) {
  // Seven pairs of the shipped four-bar (hand formula); no exact stage; the model's values
  // moved away: LM from the model's values and the global stage (four DE runs) find it again.
  std::vector<double> t2;
  for (int k = 0; k < 7; ++k) t2.push_back((30 + 20 * k) * kDeg);
  mech::fourbar::Model::ParamsT<double> base;
  base.a = 1.4, base.b = 3.0, base.c = 3.6;
  const auto b = FunctionTaskOf(t2, {}, /*freudenstein=*/false, /*restarts=*/4, base);
  const FunctionResult r = SynthesizeFunction(b, 3);
  ASSERT_TRUE(r.best.feasible()) << r.best.defect;
  EXPECT_LT(r.best.error, 1e-20);
  EXPECT_NEAR(r.best.x[0], 1.0, 1e-9);
  EXPECT_NEAR(r.best.x[1], 3.5, 1e-9);
  EXPECT_NEAR(r.best.x[2], 3.0, 1e-9);
  EXPECT_GT(r.evaluations, 0);
  // With the exact stage: least squares of Freudenstein's equation on consistent pairs is exact.
  // Starts outside the bounds are moved inside: the model's values far out, no random starts.
  mech::fourbar::Model::ParamsT<double> far = base;
  far.a = 50, far.b = 0.01, far.c = 9;
  const FunctionResult clamped = SynthesizeFunction(FunctionTaskOf(t2, {}, false, 0, far), 3);
  for (size_t j = 0; j < 3; ++j) {
    EXPECT_GE(clamped.best.x[j], 0.5);
    EXPECT_LE(clamped.best.x[j], 6.0);
  }
  const FunctionResult e = SynthesizeFunction(FunctionTaskOf(t2, {}, true, 0, base), 3);
  ASSERT_TRUE(e.exact.ok) << e.exact.why;
  EXPECT_NEAR(e.exact.a, 1.0, 1e-12);
  EXPECT_NEAR(e.exact.b, 3.5, 1e-12);
  EXPECT_NEAR(e.exact.c, 3.0, 1e-12);
}

TEST(FunctionSynthesis, LeastSquaresOfTheAnglesBeatsThatOfTheEquationAndIsStationary) {
  // Pairs no four-bar meets (the rocker's angles shifted by +-0.4 deg alternately): the exact
  // stage's least squares (of Freudenstein's equation) is not the least squares of the
  // angles; LM on the angles ends lower, at a point where the error's gradient (central
  // differences of E, not the Jacobian LM used) vanishes.
  std::vector<double> t2, shift;
  for (int k = 0; k < 6; ++k) {
    t2.push_back((40 + 18 * k) * kDeg);
    shift.push_back((k % 2 == 0 ? 0.4 : -0.4) * kDeg);
  }
  const auto b = FunctionTaskOf(t2, shift, true, 2);
  const FunctionResult r = SynthesizeFunction(b, 5);
  ASSERT_TRUE(r.exact.ok) << r.exact.why;
  ASSERT_TRUE(r.best.feasible()) << r.best.defect;
  FunctionEvaluator<mech::fourbar::Model> eval(b);
  const FunctionCandidate exact = eval.Check({r.exact.a, r.exact.b, r.exact.c});
  ASSERT_TRUE(exact.feasible());
  EXPECT_LT(r.best.error, exact.error * (1 - 1e-6));
  const double h = 1e-5;
  for (int j = 0; j < 3; ++j) {
    std::vector<double> xp = r.best.x, xm = r.best.x;
    xp[static_cast<size_t>(j)] += h, xm[static_cast<size_t>(j)] -= h;
    const double g = (eval.Check(xp).error - eval.Check(xm).error) / (2 * h);
    EXPECT_LT(std::abs(g), 1e-9) << "dE/d" << b.task.variables[static_cast<size_t>(j)].name;
  }
}

TEST(FunctionSynthesis, TaskErrorsSayWhereAndWhat) {
  const std::string path = ::testing::TempDir() + "/bad_function.yaml";
  std::ofstream(path) << "synthesis: function\noutput: theta_rockr\npairs: [[0, 1], [1, 2], [2, 3]]\nvariables: {a: [0, 1]}\n";
  FunctionTask task;
  std::string error;
  ASSERT_TRUE(ParseFunctionTask(path, &task, &error)) << error;
  BoundFunction<mech::fourbar::Model> b;
  EXPECT_FALSE(BindFunctionTask<mech::fourbar::Model>(task, {}, &b, &error));
  EXPECT_EQ(error, path + ":2:9: error: output 'theta_rockr' is not one of the model's dependent variables (theta_coupler, theta_rocker)");
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\npairs: [[0, 1], [1, 2], [2, 3]]\n"
                         "freudenstein: {crank: a, coupler: b, rocker: c, ground: d}\nvariables: {a: [0, 1]}\n";
  EXPECT_FALSE(ParseFunctionTask(path, &task, &error));
  EXPECT_EQ(error, path + ":4:15: error: freudenstein: 'b' must be one of the variables (the exact method sets it)");
  std::string kind_error;
  EXPECT_EQ(TaskKind(path, &kind_error), "function");
}

// ---- Function generation over a range (issue 28, second part) ----

// The classic: y = log10(x) on [1, 2], the crank over 60 deg from 90 deg, the rocker over 60
// deg from 20 deg (models/fourbar.yaml's frame: ground d = 4 along +x).
std::string Log10Task(int points, const std::string& extra, const std::string& search = "{restarts: 0}",
                      const std::string& variables = "{a: [0.5, 20], b: [0.5, 20], c: [0.5, 20]}") {
  return "synthesis: function\nmodel: fourbar.yaml\noutput: theta_rocker\n"
         "function: {expression: \"log10(x)\", x: [1, 2], input: [90deg, 150deg], output: [20deg, 80deg], points: " +
         std::to_string(points) + "}\nfreudenstein: {crank: a, coupler: b, rocker: c, ground: d}\nvariables: " + variables +
         "\n" + extra + "search: " + search + "\n";
}

BoundFunction<mech::fourbar::Model> BindFunctionYaml(const std::string& yaml, const std::string& name = "log10_task.yaml") {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << yaml;
  FunctionTask task;
  std::string error;
  EXPECT_TRUE(ParseFunctionTask(path, &task, &error)) << error;
  BoundFunction<mech::fourbar::Model> b;
  EXPECT_TRUE(BindFunctionTask<mech::fourbar::Model>(task, {}, &b, &error)) << error;
  return b;
}

// y of the four-bar (a, b, c, d = 4) at x: its rocker by hand (HandTheta4) mapped back through
// the task's linear scales (start angles in0, out0).
double HandY(double a, double b, double c, double x, double in0 = 90 * M_PI / 180, double out0 = 20 * M_PI / 180) {
  const double span = 60 * M_PI / 180;
  const double t4 = HandTheta4(a, b, c, 4.0, in0 + span * (x - 1));
  return std::log10(2.0) * (t4 - out0) / span;
}

TEST(FunctionSynthesis, Log10ThreeChebyshevPointsExactAndStructuralErrorByHand) {
  const auto b = BindFunctionYaml(Log10Task(3, ""));
  ASSERT_EQ(b.n, 3);
  for (int j = 1; j <= 3; ++j)  // Chebyshev spacing: 1.5 - 0.5 cos((2j - 1) pi / 6)
    EXPECT_NEAR(b.task.x[static_cast<size_t>(j - 1)], 1.5 - 0.5 * std::cos((2 * j - 1) * M_PI / 6), 1e-15);
  const FunctionResult r = SynthesizeFunction(b, 1);
  ASSERT_TRUE(r.exact.ok) << r.exact.why;
  for (double e : r.exact.residual) EXPECT_LT(std::abs(e), 1e-12);
  ASSERT_TRUE(r.best.feasible()) << r.best.defect;
  const double a = r.exact.a, bb = r.exact.b, c = r.exact.c;
  // y at the accuracy points, by hand from the synthesized lengths: log10(x_i) to 1e-12.
  for (double x : b.task.x) EXPECT_NEAR(HandY(a, bb, c, x), std::log10(x), 1e-12) << "x = " << x;
  // The structural error elsewhere: the library's (generated solve) against the hand formula
  // at every sample, and its largest.
  FunctionEvaluator<mech::fourbar::Model> eval(b);
  const StructuralError e = eval.Structural({a, bb, c});
  ASSERT_TRUE(e.assembles);
  ASSERT_EQ(e.samples, 201);
  double worst = 0;
  for (size_t k = 0; k < e.xs.size(); ++k) {
    const double hand = HandY(a, bb, c, e.xs[k]) - std::log10(e.xs[k]);
    EXPECT_NEAR(e.dy[k], hand, 1e-12) << "x = " << e.xs[k];
    worst = std::max(worst, std::abs(hand));
  }
  EXPECT_NEAR(e.max_y, worst, 1e-12);
  EXPECT_GT(worst, 1e-5);  // three points: not exact between them
  // The best (LM from the exact start cannot do better than zero at the points) is it.
  for (double res : r.best.residual) EXPECT_LT(std::abs(res), 1e-12);
  EXPECT_NEAR(r.structural.max_y, worst, 1e-9);
}

TEST(FunctionSynthesis, JacobianWithFreeStartAnglesAgainstCentralDifferences) {
  const auto b = BindFunctionYaml(Log10Task(5, "free_start: {input: [60deg, 120deg], output: [0deg, 40deg]}\n"));
  ASSERT_EQ(b.nx, 5);
  FunctionEvaluator<mech::fourbar::Model> eval(b);
  FunctionResiduals<mech::fourbar::Model> cost(&eval);
  CheckFunctionJacobian(&cost, {3.5, 8.0, 4.0, 88 * kDeg, 21 * kDeg}, 5);
}

TEST(FunctionSynthesis, FreeStartAnglesReduceTheError) {
  // Five Chebyshev points: with the start angles fixed no four-bar meets them (three lengths,
  // five equations); with both start angles free (five unknowns, seeded by Freudenstein's
  // least squares on a grid of start angles) the error at the points and the structural error
  // over the range (both by hand from the lengths and start angles found) end lower, at a
  // point where the error's gradient (central differences) vanishes.
  const auto fixed = BindFunctionYaml(Log10Task(5, ""), "fixed.yaml");
  const auto free =
      BindFunctionYaml(Log10Task(5, "free_start: {input: [30deg, 150deg], output: [-60deg, 60deg]}\n"), "free.yaml");
  const FunctionResult rf = SynthesizeFunction(fixed, 1);
  const FunctionResult rs = SynthesizeFunction(free, 1);
  ASSERT_TRUE(rf.best.feasible()) << rf.best.defect;
  ASSERT_TRUE(rs.best.feasible()) << rs.best.defect;
  EXPECT_EQ(rs.exact_grid, 144);
  EXPECT_GT(rf.best.error, 1e-9);
  EXPECT_LT(rs.best.error, 0.5 * rf.best.error);
  auto worst = [](const std::vector<double>& x, double in0, double out0) {
    double w = 0;
    for (int k = 0; k <= 200; ++k) {
      const double xk = 1 + k / 200.0;
      w = std::max(w, std::abs(HandY(x[0], x[1], x[2], xk, in0, out0) - std::log10(xk)));
    }
    return w;
  };
  const double wf = worst(rf.best.x, 90 * kDeg, 20 * kDeg);
  const double ws = worst(rs.best.x, rs.best.x[3], rs.best.x[4]);
  EXPECT_NEAR(rf.structural.max_y, wf, 1e-9);
  EXPECT_NEAR(rs.structural.max_y, ws, 1e-9);
  EXPECT_LT(ws, wf);
  // The error at the points by hand: the sum of squared angle errors.
  double e = 0;
  for (size_t i = 0; i < free.task.x.size(); ++i) {
    const double dy = HandY(rs.best.x[0], rs.best.x[1], rs.best.x[2], free.task.x[i], rs.best.x[3], rs.best.x[4]) -
                      std::log10(free.task.x[i]);
    e += std::pow(dy * 60 * kDeg / std::log10(2.0), 2);
  }
  EXPECT_NEAR(rs.best.error, e, 1e-12);
  FunctionEvaluator<mech::fourbar::Model> eval(free);
  ExpectStationary(&eval, rs.best.x, 1e-9);
}

TEST(FunctionSynthesis, FitOverTheRangeLowersTheStructuralErrorsRms) {
  // The same log10 task with free start angles, fitted at its five Chebyshev points or over
  // the range (`fit: range`: the structural error at 101 samples): the range fit's mean square
  // structural error over those samples (by hand from the lengths and start angles found) is
  // lower, its error is that sum (by hand), and it is stationary (central differences).
  const std::string free_start = "free_start: {input: [30deg, 150deg], output: [-60deg, 60deg]}\n";
  const auto points = BindFunctionYaml(Log10Task(5, free_start), "fit_points.yaml");
  std::string yaml = Log10Task(5, free_start);
  yaml.replace(yaml.find("points: 5}"), 10, "points: 5, samples: 100, fit: range}");
  const auto range = BindFunctionYaml(yaml, "fit_range.yaml");
  ASSERT_TRUE(range.task.fit_range);
  ASSERT_EQ(range.n, 101);
  ASSERT_EQ(range.task.exact_input.size(), 5u);
  const FunctionResult rp = SynthesizeFunction(points, 1);
  const FunctionResult rr = SynthesizeFunction(range, 1);
  ASSERT_TRUE(rp.best.feasible()) << rp.best.defect;
  ASSERT_TRUE(rr.best.feasible()) << rr.best.defect;
  auto squares = [](const std::vector<double>& x) {  // sum of squared output-angle errors, 101 samples
    double e = 0;
    for (int k = 0; k <= 100; ++k) {
      const double xk = 1 + k / 100.0;
      const double dy = HandY(x[0], x[1], x[2], xk, x[3], x[4]) - std::log10(xk);
      e += std::pow(dy * 60 * kDeg / std::log10(2.0), 2);
    }
    return e;
  };
  EXPECT_NEAR(rr.best.error, squares(rr.best.x), 1e-12);
  EXPECT_LT(squares(rr.best.x), squares(rp.best.x));
  FunctionEvaluator<mech::fourbar::Model> eval(range);
  ExpectStationary(&eval, rr.best.x, 1e-8);
}

TEST(FunctionSynthesis, GlobalStageCountsEvaluationsAndIsTheSameForAnyThreadCount) {
  // No exact stage and the model's values far from an answer: the global stage (four seeded
  // DE runs and their LM) finds the three-point answer; 1 and 2 threads give the same bits.
  const std::string yaml =
      "synthesis: function\nmodel: fourbar.yaml\noutput: theta_rocker\n"
      "function: {expression: \"log10(x)\", x: [1, 2], input: [90deg, 150deg], output: [20deg, 80deg], points: 3}\n"
      "variables: {a: [0.5, 20], b: [0.5, 20], c: [0.5, 20]}\nsearch: {restarts: 4, evaluations: 6000}\n";
  const auto b = BindFunctionYaml(yaml, "global.yaml");
  const FunctionResult one = SynthesizeFunction(b, 7, 1);
  const FunctionResult two = SynthesizeFunction(b, 7, 2);
  ASSERT_TRUE(one.best.feasible()) << one.best.defect;
  EXPECT_EQ(one.best.x, two.best.x);
  EXPECT_EQ(one.evaluations, two.evaluations);
  EXPECT_EQ(one.best.start, two.best.start);
  EXPECT_GT(one.global_evaluations, 0);
  EXPECT_LE(one.global_evaluations, 6000);
  EXPECT_EQ(one.runs, 4);
  EXPECT_LT(one.best.error, 1e-20);
  for (double x : b.task.x) EXPECT_NEAR(HandY(one.best.x[0], one.best.x[1], one.best.x[2], x), std::log10(x), 1e-9);
}

// The transmission angle (between BC and DC) of fourbar at the crank angle t2, by hand.
double HandMu(double a, double b, double c, double d, double t2) {
  const double e2 = a * a + d * d - 2 * a * d * std::cos(t2);
  return std::acos((b * b + c * c - e2) / (2 * b * c));
}

TEST(FunctionSynthesis, PathConstraintsAppliedToFunctionTasks) {
  // The three-point log10 answer (links about 3.57, 8.10, 4.04, 4) is not Grashof: under
  // crank_rotates it is a defect of size s + l - p - q (by hand); its transmission angle over
  // the motion from the first point to the last, against the hand formula.
  const auto plain = BindFunctionYaml(Log10Task(3, ""), "plain.yaml");
  const FunctionResult r = SynthesizeFunction(plain, 1);
  ASSERT_TRUE(r.exact.ok);
  const double a = r.exact.a, bb = r.exact.b, c = r.exact.c, d = 4;
  std::array<double, 4> len = {a, bb, c, d};
  std::sort(len.begin(), len.end());
  const double excess = len[0] + len[3] - len[1] - len[2];
  ASSERT_GT(excess, 0);
  const auto rot = BindFunctionYaml(Log10Task(3, "crank: crank\nconstraints: {crank_rotates: true}\n"), "rot.yaml");
  FunctionEvaluator<mech::fourbar::Model> er(rot);
  const FunctionCandidate cr = er.Check({a, bb, c});
  EXPECT_FALSE(cr.feasible());
  EXPECT_EQ(cr.defect, "the crank cannot turn fully: not Grashof");
  EXPECT_GE(cr.violation, excess - 1e-12);
  // Transmission angle: over the accuracy points' input range (hand: fine sampling).
  double lo = 10, hi = -10;
  for (int k = 0; k <= 6000; ++k) {
    const double t2 = rot.task.input[0] + (rot.task.input[2] - rot.task.input[0]) * k / 6000;
    lo = std::min(lo, HandMu(a, bb, c, d, t2)), hi = std::max(hi, HandMu(a, bb, c, d, t2));
  }
  const auto mu = BindFunctionYaml(Log10Task(3, "constraints: {transmission_angle: [" + Deg(lo + 0.05) + ", 170deg]}\n"), "mu.yaml");
  FunctionEvaluator<mech::fourbar::Model> em(mu);
  const FunctionCandidate cm = em.Check({a, bb, c});
  EXPECT_NEAR(cm.mu_min, lo, 2e-3);
  EXPECT_NEAR(cm.mu_max, hi, 2e-3);
  EXPECT_FALSE(cm.feasible());
  EXPECT_EQ(cm.defect, "the transmission angle falls below its bound");
  EXPECT_NEAR(cm.violation, lo + 0.05 - cm.mu_min, 1e-12);
  // Searched under Grashof with the crank turning fully: a feasible answer, checked by hand.
  const auto g = BindFunctionYaml(
      Log10Task(3, "crank: crank\nconstraints: {crank_rotates: true}\n", "{restarts: 4, evaluations: 8000}"), "grashof.yaml");
  const FunctionResult rg = SynthesizeFunction(g, 3);
  ASSERT_TRUE(rg.best.feasible()) << rg.best.defect;
  std::array<double, 4> lg = {rg.best.x[0], rg.best.x[1], rg.best.x[2], d};
  std::sort(lg.begin(), lg.end());
  EXPECT_LE(lg[0] + lg[3], lg[1] + lg[2]);
  EXPECT_TRUE(lg[0] == rg.best.x[0] || lg[0] == d);
}

// The extrema of g over [1, 2], by hand: 20000 even steps split into runs of one sign, in each
// the largest |g| refined by ternary search between its neighbours (the values; *at: where).
std::vector<double> HandExtrema(const std::function<double(double)>& g, std::vector<double>* at = nullptr) {
  const int N = 20000;
  std::vector<double> v(N + 1), out;
  for (int k = 0; k <= N; ++k) v[static_cast<size_t>(k)] = g(1 + 1.0 * k / N);
  for (int k = 0; k <= N;) {
    int end = k, best = k;
    while (end <= N && (v[static_cast<size_t>(end)] >= 0) == (v[static_cast<size_t>(k)] >= 0)) {
      if (std::abs(v[static_cast<size_t>(end)]) > std::abs(v[static_cast<size_t>(best)])) best = end;
      ++end;
    }
    double lo = 1 + 1.0 * std::max(best - 1, 0) / N, hi = 1 + 1.0 * std::min(best + 1, N) / N;
    for (int it = 0; it < 100; ++it) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (std::abs(g(m1)) < std::abs(g(m2))) lo = m1;
      else hi = m2;
    }
    double x = 0.5 * (lo + hi), e = g(x);
    if (std::abs(v[static_cast<size_t>(best)]) >= std::abs(e)) x = 1 + 1.0 * best / N, e = v[static_cast<size_t>(best)];
    out.push_back(e);
    if (at != nullptr) at->push_back(x);
    k = end;
  }
  return out;
}

// Equal ripple by hand: n alternating extrema (runs of one sign alternate by construction),
// their magnitudes within `rel` of the largest; returns the largest.
double ExpectEqualRipple(const std::vector<double>& ext, size_t n, double rel) {
  EXPECT_EQ(ext.size(), n);
  double lo = 1e300, hi = 0;
  for (double e : ext) lo = std::min(lo, std::abs(e)), hi = std::max(hi, std::abs(e));
  EXPECT_LE(hi - lo, rel * hi) << "extrema from " << lo << " to " << hi;
  return hi;
}

TEST(FunctionSynthesis, MinimaxEqualisesTheStructuralErrorsExtrema) {
  // log10 on [1, 2], the start angles fixed (a, b, c vary: four alternating extrema of the
  // error at the optimum). The Remez exchange from the Chebyshev-spacing answer: the error of
  // the four-bar it gives, evaluated by hand (circle intersection) on 20001 points and its
  // extrema located by ternary search, has four extrema of alternating sign and equal
  // magnitude (to 1e-7), the largest below the Chebyshev-spacing answer's largest (by hand
  // too), and equal to what the library reports (1e-12).
  const auto pts = BindFunctionYaml(Log10Task(3, ""), "mm_points.yaml");
  std::string yaml = Log10Task(3, "");
  yaml.replace(yaml.find("points: 3}"), 10, "points: 3, fit: minimax}");
  const auto mm = BindFunctionYaml(yaml, "mm_minimax.yaml");
  ASSERT_TRUE(mm.task.fit_minimax);
  const FunctionResult rp = SynthesizeFunction(pts, 1);
  const FunctionResult rm = SynthesizeFunction(mm, 1);
  ASSERT_TRUE(rp.best.feasible()) << rp.best.defect;
  ASSERT_TRUE(rm.best.feasible()) << rm.best.defect;
  ASSERT_TRUE(rm.minimax.converged) << rm.minimax.why;
  ASSERT_TRUE(rm.minimax.used) << rm.minimax.why;
  const std::vector<double>& xp = rp.best.x;
  const std::vector<double>& xm = rm.best.x;
  const auto ep = HandExtrema([&](double x) { return HandY(xp[0], xp[1], xp[2], x) - std::log10(x); });
  std::vector<double> at;
  const auto em = HandExtrema([&](double x) { return HandY(xm[0], xm[1], xm[2], x) - std::log10(x); }, &at);
  const double worst_m = ExpectEqualRipple(em, 4, 1e-7);
  double worst_p = 0;
  for (double e : ep) worst_p = std::max(worst_p, std::abs(e));
  EXPECT_LT(worst_m, worst_p);
  const double to_y = std::log10(2.0) / (60 * kDeg);
  EXPECT_NEAR(rm.minimax.max_angle * to_y, worst_m, 1e-12);
  EXPECT_NEAR(rm.minimax.start_max * to_y, worst_p, 1e-12);
  // The library's extrema are the hand ones; its accuracy points (three zeros) are zeros by hand.
  ASSERT_EQ(rm.minimax.ref_e.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(rm.minimax.ref_e[k] * to_y, em[k], 1e-12);
    EXPECT_NEAR(rm.minimax.ref_x[k], at[k], 1e-5);
  }
  ASSERT_EQ(rm.minimax.zeros.size(), 3u);
  for (double z : rm.minimax.zeros) EXPECT_LT(std::abs(HandY(xm[0], xm[1], xm[2], z) - std::log10(z)), 1e-12);
  std::printf("log10 on [1, 2], a b c: largest |error| in y: Chebyshev spacing %.6g, minimax %.6g (%d exchanges)\n",
              worst_p, worst_m, rm.minimax.exchanges);
}

TEST(FunctionSynthesis, MinimaxForXSquaredAndWithFreeStartAngles) {
  // y = x^2 on [1, 2] (input 270 -> 330 deg, output 240 -> 300 deg; a, b, c vary): four
  // alternating extrema of equal magnitude by hand (1e-7), the largest below the Chebyshev
  // spacing's (by hand). log10 with five unknowns (a, b, c and both start angles): the largest
  // error by hand below the five Chebyshev points' answer's, five equal extrema, a local
  // minimax by hand (Lawson's iteration and the reduced exchange, below). The report gives the
  // largest error as found by hand.
  const std::string free_start = "free_start: {input: [30deg, 150deg], output: [-60deg, 60deg]}\n";
  for (const std::string& fn : {std::string("x^2"), std::string("log10(x)")}) {
    const bool log10 = fn == "log10(x)";
    std::string yaml = Log10Task(log10 ? 5 : 3, log10 ? free_start : "");
    yaml.replace(yaml.find("log10(x)"), 8, fn);
    if (!log10) yaml.replace(yaml.find("input: [90deg, 150deg], output: [20deg, 80deg]"), 46, "input: [270deg, 330deg], output: [240deg, 300deg]");
    const auto pts = BindFunctionYaml(yaml, "mm2_points.yaml");
    yaml.replace(yaml.find("points: "), 9, yaml.substr(yaml.find("points: "), 9) + ", fit: minimax");
    const auto mm = BindFunctionYaml(yaml, "mm2_minimax.yaml");
    ASSERT_TRUE(mm.task.fit_minimax);
    const FunctionResult rp = SynthesizeFunction(pts, 1);
    const FunctionResult rm = SynthesizeFunction(mm, 1);
    ASSERT_TRUE(rp.best.feasible()) << rp.best.defect;
    ASSERT_TRUE(rm.best.feasible()) << rm.best.defect;
    // log10 with free start angles: its least squares at five points has four sign changes, not
    // five; Lawson's iteration then ends with five near-equal extrema (the sixth does not
    // appear: a direction of the five variables the error hardly sees), and the reduced
    // exchange on those five equalises them.
    if (log10) {
      EXPECT_GT(rm.minimax.lawson, 0);
    }
    ASSERT_TRUE(rm.minimax.converged) << fn << ": " << rm.minimax.why;
    ASSERT_TRUE(rm.minimax.used) << rm.minimax.why;
    const double y0 = log10 ? 0.0 : 1.0, dy = log10 ? std::log10(2.0) : 3.0;
    auto f = [&](double x) { return log10 ? std::log10(x) : x * x; };
    auto error = [&](const std::vector<double>& v, double x) {  // by hand, in y
      const double in0 = v.size() > 3 ? v[3] : (log10 ? 90 : 270) * kDeg, out0 = v.size() > 3 ? v[4] : (log10 ? 20 : 240) * kDeg;
      const double t4 = HandTheta4(v[0], v[1], v[2], 4.0, in0 + 60 * kDeg * (x - 1));
      return WrapPi(t4 - out0 - 60 * kDeg * (f(x) - y0) / dy) * dy / (60 * kDeg);
    };
    const std::vector<double>& xp = rp.best.x;
    const std::vector<double>& xm = rm.best.x;
    const auto ep = HandExtrema([&](double x) { return error(xp, x); });
    const auto em = HandExtrema([&](double x) { return error(xm, x); });
    double worst_m = 0;
    for (double e : em) worst_m = std::max(worst_m, std::abs(e));
    if (!log10) ExpectEqualRipple(em, static_cast<size_t>(mm.nx + 1), 1e-7);
    double worst_p = 0;
    for (double e : ep) worst_p = std::max(worst_p, std::abs(e));
    EXPECT_LT(worst_m, worst_p) << fn;
    EXPECT_NEAR(rm.minimax.max_angle * dy / (60 * kDeg), worst_m, 1e-12) << fn;
    const std::string report = FunctionReport(mm, rm, 1);
    EXPECT_NE(report.find("minimax (Remez exchange of the accuracy points): "), std::string::npos) << report;
    if (log10) {
      EXPECT_NE(report.find("a reduced exchange on 5 extrema"), std::string::npos) << report;
    }
    EXPECT_NE(report.find("largest |structural error| over the range (extrema located): " + Short(worst_m, 6) + " in y"),
              std::string::npos) << report;
    std::printf("%s on [1, 2], %d unknowns: largest |error| in y: Chebyshev spacing %.6g, minimax %.6g (%d exchanges)\n",
                fn.c_str(), mm.nx, worst_p, worst_m, rm.minimax.exchanges);
    if (log10) {
      // Five equal extrema for five variables (not six): a local minimax all the same. By hand:
      // the extrema's gradients (central differences of the hand error) are dependent (their
      // smallest singular value below 1e-3 of the largest), and no step lowers the largest
      // error: along each variable, along the null direction of those gradients (where the
      // change is of second order), and along 40 random directions, each both ways at 1e-5
      // and 1e-3 of the variable's scale.
      ASSERT_EQ(rm.minimax.reference, 5);
      ExpectEqualRipple(em, 5, 1e-7);
      std::vector<double> at;
      HandExtrema([&](double x) { return error(xm, x); }, &at);
      ASSERT_EQ(at.size(), 5u);
      Eigen::Matrix<double, 5, 5> G;
      for (int j = 0; j < 5; ++j) {
        const double h = 1e-6 * std::max(1.0, std::abs(xm[static_cast<size_t>(j)]));
        std::vector<double> vp = xm, vm = xm;
        vp[static_cast<size_t>(j)] += h, vm[static_cast<size_t>(j)] -= h;
        for (int k = 0; k < 5; ++k)
          G(k, j) = (error(vp, at[static_cast<size_t>(k)]) - error(vm, at[static_cast<size_t>(k)])) / (2 * h);
      }
      Eigen::JacobiSVD<Eigen::Matrix<double, 5, 5>> svd(G, Eigen::ComputeFullV);
      EXPECT_LT(svd.singularValues()(4), 1e-3 * svd.singularValues()(0)) << svd.singularValues().transpose();
      std::vector<Eigen::Matrix<double, 5, 1>> dirs;
      for (int j = 0; j < 5; ++j) dirs.push_back(Eigen::Matrix<double, 5, 1>::Unit(j));
      dirs.push_back(svd.matrixV().col(4));
      std::mt19937 rng(44);
      std::normal_distribution<double> normal;
      for (int r = 0; r < 40; ++r) {
        Eigen::Matrix<double, 5, 1> d;
        for (int j = 0; j < 5; ++j) d(j) = normal(rng);
        dirs.push_back(d.normalized());
      }
      for (const auto& d : dirs)
        for (double step : {-1e-3, -1e-5, 1e-5, 1e-3}) {
          std::vector<double> v = xm;
          for (int j = 0; j < 5; ++j)
            v[static_cast<size_t>(j)] += step * d(j) * std::max(1.0, std::abs(xm[static_cast<size_t>(j)]));
          double w = 0;
          for (double e : HandExtrema([&](double x) { return error(v, x); })) w = std::max(w, std::abs(e));
          EXPECT_GT(w, worst_m) << "step " << step << " along " << d.transpose();
        }
      std::printf("log10 with free start angles: the extrema's gradients' singular values %s\n",
                  [&] {
                    std::ostringstream o;
                    o << svd.singularValues().transpose();
                    return o.str();
                  }()
                      .c_str());
    }
  }
}

TEST(FunctionSynthesis, MinimaxMeetsTheConstraints) {
  // y = x^2 on [1, 2] (input 270 -> 330 deg, output 240 -> 300 deg; a, b, c vary, d = 4): the
  // equal-ripple four-bar is not Grashof (by hand: s + l > p + q). With `grashof: true` the
  // minimax stage exchanges again with Grashof active. Oracles, all by hand (circle
  // intersection on 20001 points, extrema by ternary search; the lengths sorted): the answer is
  // Grashof with s + l = p + q (to 1e-8), its error has three alternating extrema of equal
  // magnitude (three variables less one condition; 1e-7), its largest is no smaller than the
  // unconstrained one's and smaller than the constrained accuracy points' answer's, and no
  // step along the Grashof surface or into it (four tangent directions, one inward, 1e-4)
  // lowers it: a constrained minimax.
  auto task = [](const std::string& extra, const std::string& search, bool minimax) {
    std::string yaml = Log10Task(3, extra, search);
    yaml.replace(yaml.find("log10(x)"), 8, "x^2");
    yaml.replace(yaml.find("input: [90deg, 150deg], output: [20deg, 80deg]"), 46,
                 "input: [270deg, 330deg], output: [240deg, 300deg]");
    if (minimax) yaml.replace(yaml.find("points: 3}"), 10, "points: 3, fit: minimax}");
    return yaml;
  };
  auto error = [](const std::array<double, 3>& v, double x) {  // by hand, in y
    const double t4 = HandTheta4(v[0], v[1], v[2], 4.0, 270 * kDeg + 60 * kDeg * (x - 1));
    return WrapPi(t4 - 240 * kDeg - 60 * kDeg * (x * x - 1) / 3) * 3 / (60 * kDeg);
  };
  auto worst = [&](const std::array<double, 3>& v) {
    double w = 0;
    for (double e : HandExtrema([&](double x) { return error(v, x); })) w = std::max(w, std::abs(e));
    return w;
  };
  auto grashof = [](const std::array<double, 3>& v) {  // p + q - s - l by hand
    std::array<double, 4> l = {v[0], v[1], v[2], 4.0};
    std::sort(l.begin(), l.end());
    return l[1] + l[2] - l[0] - l[3];
  };
  const std::string grashof_task = "constraints: {grashof: true}\n", search = "{restarts: 4, evaluations: 8000}";
  const FunctionResult ru = SynthesizeFunction(BindFunctionYaml(task("", "{restarts: 0}", true), "cu.yaml"), 1);
  const FunctionResult rp = SynthesizeFunction(BindFunctionYaml(task(grashof_task, search, false), "cp.yaml"), 1);
  const auto bc = BindFunctionYaml(task(grashof_task, search, true), "cc.yaml");
  const FunctionResult rc = SynthesizeFunction(bc, 1);
  ASSERT_TRUE(ru.minimax.converged && ru.minimax.used) << ru.minimax.why;
  ASSERT_TRUE(rp.best.feasible()) << rp.best.defect;
  ASSERT_TRUE(rc.best.feasible()) << rc.best.defect;
  const std::array<double, 3> xu = {ru.best.x[0], ru.best.x[1], ru.best.x[2]};
  const std::array<double, 3> xp = {rp.best.x[0], rp.best.x[1], rp.best.x[2]};
  const std::array<double, 3> xc = {rc.best.x[0], rc.best.x[1], rc.best.x[2]};
  EXPECT_LT(grashof(xu), -1e-3);  // the unconstrained optimum breaks the constraint
  EXPECT_EQ(rc.minimax.constraint, "not Grashof (s + l > p + q)");
  ASSERT_TRUE(rc.minimax.constrained_converged) << rc.minimax.why;
  ASSERT_TRUE(rc.minimax.used) << rc.minimax.why;
  EXPECT_GE(grashof(xc), 0);
  EXPECT_LT(grashof(xc), 1e-8);
  const auto ec = HandExtrema([&](double x) { return error(xc, x); });
  const double worst_c = ExpectEqualRipple(ec, 3, 1e-7), worst_u = worst(xu), worst_p = worst(xp);
  EXPECT_GE(worst_c, worst_u);
  EXPECT_LT(worst_c, worst_p);
  EXPECT_NEAR(rc.minimax.max_angle * 3 / (60 * kDeg), worst_c, 1e-12);
  EXPECT_LE(rc.minimax.unconstrained_max * 3 / (60 * kDeg), worst_c);
  // The Grashof margin's gradient by hand (the roles of the sorted lengths at xc), and steps
  // along its surface and into the Grashof side.
  std::array<double, 4> l = {xc[0], xc[1], xc[2], 4.0};
  std::array<int, 4> order = {0, 1, 2, 3};
  std::sort(order.begin(), order.end(),
            [&](int i, int j) { return l[static_cast<size_t>(i)] < l[static_cast<size_t>(j)]; });
  Eigen::Vector3d g = Eigen::Vector3d::Zero();  // of p + q - s - l
  const std::array<double, 4> role = {-1, 1, 1, -1};
  for (size_t k = 0; k < 4; ++k)
    if (order[k] < 3) g(order[k]) = role[k];
  const Eigen::Vector3d u = g.unitOrthogonal(), w = g.cross(u).normalized();
  for (const Eigen::Vector3d& t : {Eigen::Vector3d(u), Eigen::Vector3d(-u), Eigen::Vector3d(w), Eigen::Vector3d(-w),
                                   Eigen::Vector3d(g.normalized())}) {
    const std::array<double, 3> v = {xc[0] + 1e-4 * t(0), xc[1] + 1e-4 * t(1), xc[2] + 1e-4 * t(2)};
    EXPECT_GE(grashof(v), -1e-12);
    EXPECT_GT(worst(v), worst_c) << t.transpose();
  }
  const std::string report = FunctionReport(bc, rc, 1);
  const std::string said = "breaks a constraint (not Grashof (s + l > p + q); its largest |error| " +
                           Short(rc.minimax.unconstrained_max * 3 / (60 * kDeg), 6);
  EXPECT_NE(report.find(said), std::string::npos) << report;
  std::printf(
      "x^2 on [1, 2], a b c, Grashof: largest |error| in y: unconstrained minimax %.6g (not Grashof, p + q - s - l "
      "%.4g), constrained accuracy points %.6g, constrained minimax %.6g (%d exchanges)\n",
      worst_u, grashof(xu), worst_p, worst_c, rc.minimax.exchanges);
}

// The free-start x^2 task of the equal-ripple tests: y = x^2 on [1, 2], input 60 deg from in0,
// output 60 deg from out0, a, b, c in [0.5, 20] (d = 4) and both start angles free.
std::string XSquaredFreeStartTask(const std::string& extra, const std::string& fit = ", fit: minimax") {
  std::string yaml = Log10Task(5, "free_start: {input: [230deg, 300deg], output: [200deg, 280deg]}\n" + extra);
  yaml.replace(yaml.find("log10(x)"), 8, "x^2");
  yaml.replace(yaml.find("input: [90deg, 150deg], output: [20deg, 80deg]"), 46,
               "input: [270deg, 330deg], output: [240deg, 300deg]");
  yaml.replace(yaml.find("points: 5}"), 10, "points: 5" + fit + "}");
  return yaml;
}

// The x^2 task's error in y by hand (circle intersection) for v = (a, b, c, in0, out0).
double XSquaredError(const std::vector<double>& v, double x) {
  const double t4 = HandTheta4(v[0], v[1], v[2], 4.0, v[3] + 60 * kDeg * (x - 1));
  return WrapPi(t4 - v[4] - 60 * kDeg * (x * x - 1) / 3) * 3 / (60 * kDeg);
}

double XSquaredWorst(const std::vector<double>& v) {
  double w = 0;
  for (double e : HandExtrema([&](double x) { return XSquaredError(v, x); })) w = std::max(w, std::abs(e));
  return w;
}

TEST(FunctionSynthesis, MinimaxWithFreeStartAnglesReachesSixEqualExtrema) {
  // y = x^2 on [1, 2] with a, b, c and both start angles free (five variables): Chebyshev's
  // criterion asks for six alternating extrema of equal magnitude. Five accuracy points (the
  // seed: the four-bar exact at the five Chebyshev points, whose error has six sign runs) and
  // the exchange on six. Oracles by hand (circle intersection on 20001 points, extrema by
  // ternary search): six extrema, alternating, equal to 1e-9 relative; the largest below the
  // five accuracy points' answer's; and no step of the five variables lowers it (along each,
  // along 40 random directions, both ways at 1e-6, 1e-5 and 1e-3 of the scale: the first-order
  // change of the largest error is positive in every direction at an equal-ripple optimum).
  // An independent Remez exchange (hand error, central-difference Jacobian, seeded from the
  // exact five-point four-bar; outside the project) ended at 1.64534e-4 rad of output.
  const auto pts = BindFunctionYaml(XSquaredFreeStartTask("", ""), "fs_points.yaml");
  const auto mm = BindFunctionYaml(XSquaredFreeStartTask(""), "fs_minimax.yaml");
  ASSERT_EQ(mm.nx, 5);
  const FunctionResult rp = SynthesizeFunction(pts, 1);
  const FunctionResult rm = SynthesizeFunction(mm, 1);
  ASSERT_TRUE(rp.best.feasible()) << rp.best.defect;
  ASSERT_TRUE(rm.best.feasible()) << rm.best.defect;
  ASSERT_TRUE(rm.minimax.converged) << rm.minimax.why;
  ASSERT_TRUE(rm.minimax.used) << rm.minimax.why;
  EXPECT_EQ(rm.minimax.reference, 6);
  const std::vector<double>& xm = rm.best.x;
  std::vector<double> at;
  const auto em = HandExtrema([&](double x) { return XSquaredError(xm, x); }, &at);
  const double worst_m = ExpectEqualRipple(em, 6, 1e-9);
  for (size_t k = 1; k < em.size(); ++k) EXPECT_LT(em[k] * em[k - 1], 0) << "extrema " << k - 1 << ", " << k;
  const double worst_p = XSquaredWorst(rp.best.x);
  EXPECT_LT(worst_m, worst_p);
  EXPECT_NEAR(rm.minimax.max_angle * 3 / (60 * kDeg), worst_m, 1e-12);
  EXPECT_NEAR(rm.minimax.max_angle, 1.64534e-4, 1e-9);
  std::vector<Eigen::Matrix<double, 5, 1>> dirs;
  for (int j = 0; j < 5; ++j) dirs.push_back(Eigen::Matrix<double, 5, 1>::Unit(j));
  std::mt19937 rng(44);
  std::normal_distribution<double> normal;
  for (int r = 0; r < 40; ++r) {
    Eigen::Matrix<double, 5, 1> d;
    for (int j = 0; j < 5; ++j) d(j) = normal(rng);
    dirs.push_back(d.normalized());
  }
  for (const auto& d : dirs)
    for (double step : {-1e-3, -1e-5, -1e-6, 1e-6, 1e-5, 1e-3}) {
      std::vector<double> v = xm;
      for (int j = 0; j < 5; ++j) v[static_cast<size_t>(j)] += step * d(j) * std::max(1.0, std::abs(xm[static_cast<size_t>(j)]));
      EXPECT_GT(XSquaredWorst(v), worst_m) << "step " << step << " along " << d.transpose();
    }
  const std::string report = FunctionReport(mm, rm, 1);
  EXPECT_EQ(report.find("a reduced exchange"), std::string::npos) << report;
  std::printf("x^2 on [1, 2], a b c and free start angles: largest |error| in y: five Chebyshev points %.6g, minimax "
              "%.10g on six extrema (%d exchanges, %d Lawson steps); a b c %.6g %.6g %.6g, in0 %.6g deg, out0 %.6g deg\n",
              worst_p, worst_m, rm.minimax.exchanges, rm.minimax.lawson, xm[0], xm[1], xm[2], xm[3] / kDeg, xm[4] / kDeg);
}

TEST(FunctionSynthesis, MinimaxWithAVariableOnItsBoundDescendsBelowWhereTheExchangeEnded) {
  // The task of MinimaxWithFreeStartAnglesReachesSixEqualExtrema with out0 <= 240 deg: its
  // equal-ripple optimum (out0 = 241.82 deg) is outside. The exchange ends on the bound with
  // four equal extrema (the reduced exchange), fewer than the four free variables ask for
  // (five); the stage then takes the minimax within the bounds by linear programs (BoundMinimax)
  // and along the curve of four equal extrema (CurveMinimax). By hand (circle intersection on
  // 20001 points, extrema by ternary search): out0 on the bound, the answer's largest error the
  // reported one, below where the exchange ended and above the unbounded optimum (4.713566e-4,
  // six extrema). That it is a minimax on the bound: MinimaxWithAVariableOnItsBoundIsAMinimax
  // OnTheBound (KKT by hand).
  std::string yaml = XSquaredFreeStartTask("");
  yaml.replace(yaml.find("output: [200deg, 280deg]"), 24, "output: [200deg, 240deg]");
  const auto mm = BindFunctionYaml(yaml, "fd_minimax.yaml");
  const FunctionResult rm = SynthesizeFunction(mm, 1);
  ASSERT_TRUE(rm.best.feasible()) << rm.best.defect;
  ASSERT_TRUE(rm.minimax.used) << rm.minimax.why;
  EXPECT_TRUE(rm.minimax.bound_stage);
  EXPECT_EQ(rm.minimax.bounds, "the output's start angle at its upper bound");
  EXPECT_EQ(rm.minimax.reference, 4);
  EXPECT_EQ(rm.minimax.bound_reference, 5);
  EXPECT_GT(rm.minimax.bound_steps, 0);
  const std::vector<double>& xm = rm.best.x;
  EXPECT_LE(xm[4], 240 * kDeg);
  EXPECT_GT(xm[4], 240 * kDeg - 1e-9);
  const double worst = XSquaredWorst(xm), to_y = 3 / (60 * kDeg);
  EXPECT_NEAR(rm.minimax.max_angle * to_y, worst, 1e-12);
  EXPECT_LT(worst, rm.minimax.bound_start_max * to_y);
  EXPECT_GT(worst, 4.7135e-4);
  const std::string report = FunctionReport(mm, rm, 1);
  EXPECT_NE(report.find("the exchange ended on 4 extrema"), std::string::npos) << report;
}

TEST(FunctionSynthesis, MinimaxWithAVariableOnItsBoundIsAMinimaxOnTheBound) {
  // The task of MinimaxWithFreeStartAnglesReachesSixEqualExtrema with out0 <= 240 deg: its
  // equal-ripple optimum (out0 = 241.82 deg) is outside. The exchange ends on the bound with
  // four equal extrema (the reduced exchange), fewer than the four free variables ask for
  // (five); the stage then takes the minimax within the bounds by linear programs and, as its
  // error has four extrema at the level (not five), the minimum of the level along the curve
  // where they stay equal (a local minimax on the bound whose four signed gradients over the
  // free variables are dependent: four extrema and the bound, not a vertex of five and the
  // bound). Oracles by hand (the four-bar's error
  // by circle intersection on 20001 points, extrema by ternary search), whatever the number of
  // extrema at the answer: out0 on the bound; the extrema at the largest magnitude equal; the
  // KKT conditions (central differences of the hand error at those extrema): a combination of
  // their signed gradients, weights positive and summing to one, plus a positive multiple of
  // the bound's normal vanishes (least squares, relative residual below 1e-5); and no feasible
  // step lowers the largest error: along each free variable both ways, into the box (out0
  // lowered), and along 40 random directions with out0 not raised, at 1e-6, 1e-5 and 1e-3 of
  // the scale. The stage's own weights and bound multiplier (generated gradients) agree with
  // those by hand to 1e-4 (the multiplier in rad of output, times dy/dphi).
  std::string yaml = XSquaredFreeStartTask("");
  yaml.replace(yaml.find("output: [200deg, 280deg]"), 24, "output: [200deg, 240deg]");
  const auto mm = BindFunctionYaml(yaml, "fb_minimax.yaml");
  ASSERT_EQ(mm.nx, 5);
  const FunctionResult rm = SynthesizeFunction(mm, 1);
  ASSERT_TRUE(rm.best.feasible()) << rm.best.defect;
  ASSERT_TRUE(rm.minimax.used) << rm.minimax.why;
  EXPECT_TRUE(rm.minimax.bound_stage);
  EXPECT_EQ(rm.minimax.bounds, "the output's start angle at its upper bound");
  EXPECT_EQ(rm.minimax.reference, 4);
  EXPECT_EQ(rm.minimax.bound_reference, 5);
  const std::vector<double>& xm = rm.best.x;
  const double bound = 240 * kDeg;
  EXPECT_LE(xm[4], bound);
  EXPECT_GT(xm[4], bound - 1e-9);
  std::vector<double> at;
  const auto em = HandExtrema([&](double x) { return XSquaredError(xm, x); }, &at);
  double worst = 0;
  for (double e : em) worst = std::max(worst, std::abs(e));
  const double to_y = 3 / (60 * kDeg);
  EXPECT_NEAR(rm.minimax.max_angle * to_y, worst, 1e-12);
  EXPECT_GT(worst, 4.7135e-4);
  EXPECT_LE(worst, rm.minimax.bound_start_max * to_y * (1 + 1e-12));
  std::vector<size_t> act;
  for (size_t k = 0; k < em.size(); ++k)
    if (std::abs(em[k]) >= (1 - 1e-6) * worst) act.push_back(k);
  if (rm.minimax.bounds_converged) ExpectEqualRipple(em, 5, 1e-9);
  // Every local maximum of |error| above half the largest, by hand (same-sign neighbours too).
  std::string peaks;
  {
    const int N = 20000;
    auto g = [&](int k) { return XSquaredError(xm, 1 + 1.0 * k / N); };
    for (int k = 0; k <= N; ++k) {
      const double v = std::abs(g(k));
      if (v > 0.5 * worst && (k == 0 || v >= std::abs(g(k - 1))) && (k == N || v >= std::abs(g(k + 1))))
        peaks += " (" + std::to_string(1 + 1.0 * k / N) + ", " + std::to_string(g(k) / worst) + ")";
    }
  }
  // KKT by hand: sum_k w_k sigma_k grad e_k + mu e_out0 = 0, sum w_k = 1 (least squares).
  const Eigen::Index na = static_cast<Eigen::Index>(act.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(6, na + 1);
  for (int j = 0; j < 5; ++j) {
    const double h = 1e-6 * std::max(1.0, std::abs(xm[static_cast<size_t>(j)]));
    std::vector<double> vp = xm, vm = xm;
    vp[static_cast<size_t>(j)] += h, vm[static_cast<size_t>(j)] -= h;
    for (Eigen::Index k = 0; k < na; ++k) {
      const size_t i = act[static_cast<size_t>(k)];
      K(j, k) = (em[i] >= 0 ? 1 : -1) * (XSquaredError(vp, at[i]) - XSquaredError(vm, at[i])) / (2 * h);
    }
  }
  K(4, na) = 1;  // the bound's normal: out0 <= 240 deg
  for (Eigen::Index k = 0; k < na; ++k) K(5, k) = 1;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(6);
  rhs(5) = 1;
  const Eigen::VectorXd w = K.colPivHouseholderQr().solve(rhs);
  const double kkt = (K.topRows(5) * w).norm() / K.topRows(5).colwise().norm().maxCoeff();
  EXPECT_LT(kkt, 1e-5) << w.transpose();
  for (Eigen::Index k = 0; k < na; ++k) EXPECT_GT(w(k), 0) << "extremum " << k << ": " << w.transpose();
  EXPECT_GT(w(na), 0) << w.transpose();
  EXPECT_TRUE(rm.minimax.curve);
  EXPECT_TRUE(rm.minimax.curve_converged) << rm.minimax.bound_why;
  ASSERT_EQ(rm.minimax.kkt_weights.size(), static_cast<size_t>(na));
  for (Eigen::Index k = 0; k < na; ++k) EXPECT_NEAR(rm.minimax.kkt_weights[static_cast<size_t>(k)], w(k), 1e-4);
  ASSERT_EQ(rm.minimax.bound_multipliers.size(), 5u);
  EXPECT_NEAR(rm.minimax.bound_multipliers[4] * to_y, w(na), 1e-4);
  std::vector<Eigen::Matrix<double, 5, 1>> dirs;
  for (int j = 0; j < 4; ++j) {
    dirs.push_back(Eigen::Matrix<double, 5, 1>::Unit(j));
    dirs.push_back(-Eigen::Matrix<double, 5, 1>::Unit(j));
  }
  dirs.push_back(-Eigen::Matrix<double, 5, 1>::Unit(4));
  std::mt19937 rng(44);
  std::normal_distribution<double> normal;
  for (int r = 0; r < 40; ++r) {
    Eigen::Matrix<double, 5, 1> d;
    for (int j = 0; j < 5; ++j) d(j) = normal(rng);
    d(4) = r % 2 == 0 ? 0.0 : -std::abs(d(4));  // along the bound, or into the box
    dirs.push_back(d.normalized());
  }
  int lower = 0;
  for (const auto& d : dirs)
    for (double step : {1e-6, 1e-5, 1e-3}) {
      std::vector<double> v = xm;
      for (int j = 0; j < 5; ++j) v[static_cast<size_t>(j)] += step * d(j) * std::max(1.0, std::abs(xm[static_cast<size_t>(j)]));
      ASSERT_LE(v[4], bound);
      const bool raised = XSquaredWorst(v) > worst;
      lower += raised ? 0 : 1;
      EXPECT_TRUE(raised) << "step " << step << " along " << d.transpose();
    }
  const std::string report = FunctionReport(mm, rm, 1);
  EXPECT_NE(report.find("the exchange ended on 4 extrema"), std::string::npos) << report;
  const size_t line = report.find("the exchange ended on");
  EXPECT_NE(report.find("steps along the curve of 4 equal extrema", line), std::string::npos) << report;
  if (line != std::string::npos) std::printf("%s", report.substr(line, report.find('\n', line) + 1 - line).c_str());
  std::printf("x^2 on [1, 2], free start angles, out0 <= 240 deg: the exchange ended on the bound at %.6g on four extrema; "
              "%d linear-programming steps, then %.10g on %zu extrema at the level (exchange on five %s; a b c %.6g %.6g %.6g, in0 %.8g "
              "deg, out0 %.10g deg); KKT weights %s (relative residual %.3g); %d feasible steps of %zu lowered it; |error| "
              "peaks (x, e/level):%s\n",
              rm.minimax.bound_start_max * to_y, rm.minimax.bound_steps, worst, act.size(),
              rm.minimax.bounds_converged ? "converged" : rm.minimax.bound_why.c_str(), xm[0], xm[1], xm[2], xm[3] / kDeg,
              xm[4] / kDeg, [&] {
                std::ostringstream o;
                o << w.transpose();
                return o.str();
              }().c_str(), kkt, lower, 3 * dirs.size(), peaks.c_str());
}

TEST(FunctionSynthesis, MinimaxMeetsTheTransmissionAngleBound) {
  // y = x^2 on [1, 2] (input 270 -> 330 deg, output 240 -> 300 deg; a, b, c vary, d = 4): the
  // equal-ripple four-bar's transmission angle falls to 60.45 deg over the range (by hand).
  // With `transmission_angle: [65deg, 150deg]` the minimax stage exchanges again with the bound
  // active over the range. Oracles, all by hand (circle intersection and the cosine law on
  // 20001 points, extrema by ternary search): the answer's smallest transmission angle over the
  // range is the bound (to 1e-8 rad, not below it), its error has three alternating extrema
  // of equal magnitude (three variables less one condition; 1e-9), its largest is above the
  // unconstrained one's, and no step of 1e-4 along the bound's surface (the two directions
  // orthogonal to the hand gradient of the smallest angle, both ways) or into the allowed side
  // lowers it: a constrained minimax. A bound that is not active (50 deg) leaves the
  // equal-ripple answer: four equal extrema at the unconstrained largest error.
  auto task = [](const std::string& extra, const std::string& search) {
    std::string yaml = Log10Task(3, extra, search);
    yaml.replace(yaml.find("log10(x)"), 8, "x^2");
    yaml.replace(yaml.find("input: [90deg, 150deg], output: [20deg, 80deg]"), 46,
                 "input: [270deg, 330deg], output: [240deg, 300deg]");
    yaml.replace(yaml.find("points: 3}"), 10, "points: 3, fit: minimax}");
    return yaml;
  };
  auto error = [](const std::array<double, 3>& v, double x) {  // by hand, in y
    const double t4 = HandTheta4(v[0], v[1], v[2], 4.0, 270 * kDeg + 60 * kDeg * (x - 1));
    return WrapPi(t4 - 240 * kDeg - 60 * kDeg * (x * x - 1) / 3) * 3 / (60 * kDeg);
  };
  auto worst = [&](const std::array<double, 3>& v) {
    double w = 0;
    for (double e : HandExtrema([&](double x) { return error(v, x); })) w = std::max(w, std::abs(e));
    return w;
  };
  auto mu_min = [](const std::array<double, 3>& v) {  // the smallest transmission angle over the range, by hand
    const int N = 20000;
    int best = 0;
    double m = 1e300;
    auto mu = [&](double t) { return HandMu(v[0], v[1], v[2], 4.0, 270 * kDeg + 60 * kDeg * t); };
    for (int k = 0; k <= N; ++k)
      if (mu(1.0 * k / N) < m) m = mu(1.0 * k / N), best = k;
    double lo = 1.0 * std::max(best - 1, 0) / N, hi = 1.0 * std::min(best + 1, N) / N;
    for (int it = 0; it < 100; ++it) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (mu(m1) < mu(m2)) hi = m2;
      else lo = m1;
    }
    return std::min(m, mu(0.5 * (lo + hi)));
  };
  const std::string search = "{restarts: 4, evaluations: 8000}";
  const FunctionResult ru = SynthesizeFunction(BindFunctionYaml(task("", "{restarts: 0}"), "tu.yaml"), 1);
  ASSERT_TRUE(ru.minimax.converged && ru.minimax.used) << ru.minimax.why;
  const std::array<double, 3> xu = {ru.best.x[0], ru.best.x[1], ru.best.x[2]};
  const double worst_u = worst(xu);
  EXPECT_LT(mu_min(xu), 61 * kDeg);
  EXPECT_GT(mu_min(xu), 60 * kDeg);
  // Not active: the same equal ripple.
  const FunctionResult rl =
      SynthesizeFunction(BindFunctionYaml(task("constraints: {transmission_angle: [50deg, 150deg]}\n", search), "tl.yaml"), 1);
  ASSERT_TRUE(rl.minimax.converged && rl.minimax.used) << rl.minimax.why;
  EXPECT_EQ(rl.minimax.constraint, "");
  const std::array<double, 3> xl = {rl.best.x[0], rl.best.x[1], rl.best.x[2]};
  EXPECT_NEAR(ExpectEqualRipple(HandExtrema([&](double x) { return error(xl, x); }), 4, 1e-9), worst_u, 1e-9 * worst_u);
  // Active.
  const auto bc = BindFunctionYaml(task("constraints: {transmission_angle: [65deg, 150deg]}\n", search), "tc.yaml");
  const FunctionResult rc = SynthesizeFunction(bc, 1);
  ASSERT_TRUE(rc.best.feasible()) << rc.best.defect;
  EXPECT_EQ(rc.minimax.constraint, "the transmission angle falls below its bound");
  ASSERT_TRUE(rc.minimax.constrained_converged) << rc.minimax.why;
  ASSERT_TRUE(rc.minimax.used) << rc.minimax.why;
  const std::array<double, 3> xc = {rc.best.x[0], rc.best.x[1], rc.best.x[2]};
  EXPECT_GE(mu_min(xc), 65 * kDeg - 1e-12);
  EXPECT_LT(mu_min(xc), 65 * kDeg + 1e-8);
  const auto ec = HandExtrema([&](double x) { return error(xc, x); });
  for (size_t k = 1; k < ec.size(); ++k) EXPECT_LT(ec[k] * ec[k - 1], 0);
  const double worst_c = ExpectEqualRipple(ec, 3, 1e-9);
  EXPECT_GT(worst_c, worst_u);
  EXPECT_NEAR(rc.minimax.max_angle * 3 / (60 * kDeg), worst_c, 1e-12);
  Eigen::Vector3d g;
  for (int j = 0; j < 3; ++j) {
    std::array<double, 3> vp = xc, vm = xc;
    vp[static_cast<size_t>(j)] += 1e-6, vm[static_cast<size_t>(j)] -= 1e-6;
    g(j) = (mu_min(vp) - mu_min(vm)) / 2e-6;
  }
  const Eigen::Vector3d u = g.unitOrthogonal(), w = g.cross(u).normalized();
  for (const Eigen::Vector3d& t : {Eigen::Vector3d(u), Eigen::Vector3d(-u), Eigen::Vector3d(w), Eigen::Vector3d(-w),
                                   Eigen::Vector3d(g.normalized())}) {
    const std::array<double, 3> v = {xc[0] + 1e-4 * t(0), xc[1] + 1e-4 * t(1), xc[2] + 1e-4 * t(2)};
    EXPECT_GT(worst(v), worst_c) << t.transpose();
  }
  const std::string report = FunctionReport(bc, rc, 1);
  EXPECT_NE(report.find("breaks a constraint (the transmission angle falls below its bound; its largest |error| " +
                        Short(rc.minimax.unconstrained_max * 3 / (60 * kDeg), 6)),
            std::string::npos)
      << report;
  std::printf("x^2 on [1, 2], a b c, transmission angle >= 65 deg: unconstrained minimax %.6g (smallest angle %.4f deg), "
              "constrained minimax %.6g (smallest angle %.10g deg; a b c %.6g %.6g %.6g; %d exchanges)\n",
              worst_u, mu_min(xu) / kDeg, worst_c, mu_min(xc) / kDeg, xc[0], xc[1], xc[2], rc.minimax.exchanges);
}

TEST(FunctionSynthesis, FreeStartAnglesWithPairs) {
  // Seven pairs of the shipped four-bar (hand formula) at 40, 60, ..., 160 deg, all inputs
  // written 10 deg higher and all outputs 7 deg lower: no four-bar with its ground along +x
  // meets them as written; with the start angles free (the first pair's) the search finds the
  // four-bar and the start angles that undo the shifts: a, b, c = 1, 3.5, 3 and the first
  // pair at (40 deg, its rocker angle by hand), to 1e-9.
  std::string yaml = "synthesis: function\nmodel: fourbar.yaml\noutput: theta_rocker\npairs:\n";
  for (int k = 0; k < 7; ++k) {
    const double t2 = (40 + 20 * k) * kDeg;
    yaml += "  - [" + Deg(t2 + 10 * kDeg) + ", " + Deg(HandTheta4(1.0, 3.5, 3.0, 4.0, t2) - 7 * kDeg) + "]\n";
  }
  yaml += "free_start: {input: [20deg, 60deg], output: [80deg, 140deg]}\n"
          "freudenstein: {crank: a, coupler: b, rocker: c, ground: d}\n"
          "variables: {a: [0.5, 6], b: [0.5, 6], c: [0.5, 6]}\nsearch: {restarts: 0}\n";
  const auto fixed = BindFunctionYaml(std::string(yaml).erase(yaml.find("free_start"), yaml.find("freudenstein") - yaml.find("free_start")), "pairs_fixed.yaml");
  const auto b = BindFunctionYaml(yaml, "pairs_free.yaml");
  ASSERT_EQ(b.nx, 5);
  EXPECT_NEAR(b.task.in_start, 50 * kDeg, 1e-15);
  const FunctionResult rf = SynthesizeFunction(fixed, 1);
  const FunctionResult r = SynthesizeFunction(b, 1);
  ASSERT_TRUE(r.best.feasible()) << r.best.defect;
  EXPECT_GT(rf.best.error, 1e-6);  // as written: not met
  EXPECT_LT(r.best.error, 1e-18);
  const std::vector<double> expected = {1.0, 3.5, 3.0, 40 * kDeg, HandTheta4(1.0, 3.5, 3.0, 4.0, 40 * kDeg)};
  for (size_t j = 0; j < 5; ++j) EXPECT_NEAR(r.best.x[j], expected[j], 1e-9) << j;
}

TEST(FunctionSynthesis, StartAnglesWrittenIntoTheModelMeetTheTasksPairs) {
  // log10 with four Chebyshev points and free start angles (five unknowns: met exactly) on function_fourbar, whose input
  // and output angles read alpha and beta less than the lines AB and DC: the start angles
  // found are written into alpha and beta, and the model file alone (its values read back
  // from the written text) meets the task's pairs as written (the input and output angles the
  // task file gives, not the start angles found): by the generated model's own solve and by
  // hand (circle intersection at AB = q + alpha, less beta), to 1e-9.
  using FM = mech::function_fourbar::Model;
  const std::string path = ::testing::TempDir() + "/offsets.yaml";
  std::ofstream(path) << "synthesis: function\nmodel: function_fourbar.yaml\noutput: theta_rocker\n"
                         "function: {expression: \"log10(x)\", x: [1, 2], input: [90deg, 150deg], output: [20deg, 80deg], "
                         "points: 4}\nfree_start: {input: [30deg, 150deg], output: [-60deg, 60deg], parameters: [alpha, beta]}\n"
                         "freudenstein: {crank: a, coupler: b, rocker: c, ground: d}\n"
                         "variables: {a: [0.5, 20], b: [0.5, 20], c: [0.5, 20]}\nsearch: {restarts: 0}\n";
  FunctionTask task;
  std::string error;
  ASSERT_TRUE(ParseFunctionTask(path, &task, &error)) << error;
  BoundFunction<FM> b;
  ASSERT_TRUE(BindFunctionTask<FM>(task, {}, &b, &error)) << error;
  const FunctionResult r = SynthesizeFunction(b, 1);
  ASSERT_TRUE(r.best.feasible()) << r.best.defect;
  std::vector<std::string> names;
  std::vector<double> values;
  FunctionModelParameters(b, r.best, &names, &values);
  ASSERT_EQ(names, (std::vector<std::string>{"a", "b", "c", "alpha", "beta"}));
  EXPECT_GT(std::abs(r.best.x[3] - 90 * kDeg), 1e-3);  // the start angles did move
  std::ifstream in(std::string(MECHGEN_SYNTHESIS_TASKS) + "/../models/function_fourbar.yaml");
  std::stringstream text;
  text << in.rdbuf();
  FM::ParamsT<double> wp;
  for (size_t k = 0; k < names.size(); ++k) *wp.Find(names[k].c_str()) = values[k];
  std::string written;
  WrittenAssembly assembly;
  ASSERT_TRUE(WriteSynthesizedModel<FM>(text.str(), wp, names, FunctionWrittenInputs(b, r.best), &written, &assembly, &error))
      << error;
  // With the offsets written the model's inputs at the pairs are the task's own; the model file
  // assembles as the sweep does and its output meets every pair by continuation.
  const std::vector<double> inputs = FunctionWrittenInputs(b, r.best);
  for (size_t i = 0; i < inputs.size(); ++i) EXPECT_NEAR(inputs[i], task.input[i], 1e-12) << "pair " << i + 1;
  ExpectSweepable<FM>(written, inputs, [&](size_t k, const mechgen::position::State<FM>& state) {
    EXPECT_LT(std::abs(WrapPi(state.phi(b.output) - task.psi[k])), 1e-9) << "pair " << k + 1;
  });
  const YAML::Node params = YAML::Load(written)["parameters"];
  FM::ParamsT<double> p;
  for (const char* name : {"a", "b", "c", "d", "alpha", "beta"}) *p.Find(name) = params[name]["value"].as<double>();
  double largest = 0;
  for (size_t i = 0; i < task.input.size(); ++i) {
    const double q = task.input[i], psi = task.psi[i];  // as the task file gives them
    Eigen::Matrix<double, 1, 1> qv;
    qv(0) = q;
    Eigen::Matrix<double, FM::kNphi, 1> phi;
    for (int j = 0; j < FM::kNphi; ++j) phi(j) = FM::kAssemblyPhi[static_cast<size_t>(j)];
    const auto report = FM::Solve(p, qv, &phi, FM::kDefaultModes);
    ASSERT_EQ(report.status, decltype(report.status)::kConverged);
    const double generated = WrapPi(phi(b.output) - psi);
    const double hand = WrapPi(HandTheta4(p.a, p.b, p.c, p.d, q + p.alpha) - p.beta - psi);
    EXPECT_LT(std::abs(generated), 1e-9) << "pair " << i + 1;
    EXPECT_LT(std::abs(hand), 1e-9) << "pair " << i + 1;
    largest = std::max(largest, std::abs(hand));
  }
  std::printf("four points, start angles in the model (alpha %.6g deg, beta %.6g deg): largest pair error %.3g rad\n",
              p.alpha / kDeg, p.beta / kDeg, largest);
  // A parameter the model does not have, or one of the variables: FILE:LINE:COLUMN.
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\n"
                         "function: {expression: \"log10(x)\", x: [1, 2], input: [0, 1], output: [0, 1], points: 3}\n"
                         "free_start: {input: [0, 1], output: [0, 1], parameters: [alpha, gamma]}\nvariables: {a: [1, 2]}\n";
  ASSERT_TRUE(ParseFunctionTask(path, &task, &error)) << error;
  EXPECT_FALSE(BindFunctionTask<FM>(task, {}, &b, &error));
  EXPECT_EQ(error, path + ":4:57: error: free_start.parameters: no parameter 'gamma' in the model (parameters: a, b, c, d, alpha, beta)");
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\n"
                         "function: {expression: \"log10(x)\", x: [1, 2], input: [0, 1], output: [0, 1], points: 3}\n"
                         "free_start: {input: [0, 1], output: [0, 1], parameters: [a, beta]}\nvariables: {a: [1, 2]}\n";
  ASSERT_TRUE(ParseFunctionTask(path, &task, &error)) << error;
  EXPECT_FALSE(BindFunctionTask<FM>(task, {}, &b, &error));
  EXPECT_EQ(error, path + ":4:57: error: free_start.parameters: 'a' is one of the variables; the start angles set it (remove "
                          "it from variables:)");
}

TEST(FunctionSynthesis, RangeTaskErrorsSayWhereAndWhat) {
  const std::string path = ::testing::TempDir() + "/bad_range.yaml";
  FunctionTask task;
  std::string error;
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\n"
                         "function: {expression: \"log10(x) +* 2\", x: [1, 2], input: [0, 1], output: [0, 1], points: 3}\n"
                         "variables: {a: [0, 1]}\n";
  EXPECT_FALSE(ParseFunctionTask(path, &task, &error));
  EXPECT_EQ(error, path + ":3:35: error: function.expression: unexpected '*'");
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\npairs: [[0, 1], [1, 2], [2, 3]]\n"
                         "free_start: {input: [0, 1], output: [2, 1]}\nvariables: {a: [0, 1]}\n";
  EXPECT_FALSE(ParseFunctionTask(path, &task, &error));
  EXPECT_EQ(error, path + ":4:37: error: free_start.output: min must be below max");
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\n"
                         "function: {expression: \"log10(x)\", x: [-1, 2], input: [0, 1], output: [0, 1], points: 3}\n"
                         "variables: {a: [0, 1]}\n";
  EXPECT_FALSE(ParseFunctionTask(path, &task, &error));
  EXPECT_EQ(error.substr(0, path.size() + 13), path + ":3:24: error:");
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\n"
                         "function: {expression: \"log10(x)\", x: [1, 2], input: [0, 1], output: [0, 1], points: 3}\n"
                         "variables: {a: [0, 1]}\nconstraints: {order: true}\n";
  EXPECT_FALSE(ParseFunctionTask(path, &task, &error));
  EXPECT_EQ(error, path + ":5:22: error: order: only for path tasks with free timing (prescribed angles fix the order)");
}

// ---- Motion generation (synthesis/burmester.h) ----

// A placed four-bar (pivot A, ground at theta0) by hand: B on the crank, C where the circles
// about B (b) and D (c) meet on the open assembly's side (left of B -> D), the coupler's angle
// that of BC, its point P at (xi, eta) in the frame at B along BC. The pose is (P, angle).
struct HandFourBar {
  double a = 1, b = 3.5, c = 3, d = 4, xi = 1.5, eta = 1, x0 = 0.3, y0 = -0.2, theta0 = 0.25;
  int side = 1;  ///< +1: C to the left of B -> D (the open assembly), -1: to the right (its mirror)
  Eigen::Vector2d A() const { return {x0, y0}; }
  Eigen::Vector2d D() const { return A() + d * Eigen::Vector2d(std::cos(theta0), std::sin(theta0)); }
  Eigen::Vector2d B(double q) const { return A() + a * Eigen::Vector2d(std::cos(q), std::sin(q)); }
  Eigen::Vector2d C(double q) const {
    const Eigen::Vector2d e = D() - B(q);
    const double L = e.norm(), s = (b * b - c * c + L * L) / (2 * L), h = side * std::sqrt(b * b - s * s);
    return B(q) + s * e / L + h * Eigen::Vector2d(-e.y(), e.x()) / L;
  }
  Pose PoseAt(double q) const {
    const Eigen::Vector2d u = (C(q) - B(q)) / b, n(-u.y(), u.x());
    const Eigen::Vector2d P = B(q) + xi * u + eta * n;
    return {P.x(), P.y(), std::atan2(u.y(), u.x())};
  }
  // The dyads in the body frame of pose q0.
  Eigen::Vector2d BodyPoint(double q0, const Eigen::Vector2d& world) const {
    const Pose p = PoseAt(q0);
    const Eigen::Vector2d r = world - Eigen::Vector2d(p.x, p.y);
    return {std::cos(p.angle) * r.x() + std::sin(p.angle) * r.y(), -std::sin(p.angle) * r.x() + std::cos(p.angle) * r.y()};
  }
};

std::vector<Pose> PosesOf(const HandFourBar& f, const std::vector<double>& q) {
  std::vector<Pose> poses;
  for (double qi : q) poses.push_back(f.PoseAt(qi));
  return poses;
}

TEST(MotionSynthesis, ThreePosesEveryCirclePointHasItsCentre) {
  const HandFourBar f;
  const std::vector<double> q = {20 * kDeg, 75 * kDeg, 140 * kDeg};
  const auto poses = PosesOf(f, q);
  Dyad d;
  // The original crank's circle point gives back the crank pivot A.
  ASSERT_TRUE(CentreOfCirclePoint(poses, f.BodyPoint(q[0], f.B(q[0])), &d));
  EXPECT_LT((d.M - f.A()).norm(), 1e-12);
  EXPECT_NEAR(d.radius, f.a, 1e-12);
  // Any circle point: its three positions on a circle about its centre (the distance form).
  for (const Eigen::Vector2d& k : {Eigen::Vector2d(0.7, -2.1), Eigen::Vector2d(-3.0, 0.4), Eigen::Vector2d(5.0, 5.0)}) {
    ASSERT_TRUE(CentreOfCirclePoint(poses, k, &d));
    EXPECT_LT(d.residual, 1e-12 * std::max(1.0, d.radius));
  }
}

TEST(MotionSynthesis, FourPoseCurvesPassThroughTheOriginalDyads) {
  const HandFourBar f;
  const std::vector<double> q = {20 * kDeg, 60 * kDeg, 110 * kDeg, 170 * kDeg};
  const auto poses = PosesOf(f, q);
  const Eigen::Vector2d base(0.4321, -0.1234);
  const auto curve = FourPoseCurve(poses, base, 720);
  ASSERT_GT(curve.size(), 100u);
  for (const CurvePoint& cp : curve) EXPECT_LT(cp.dyad.residual, 1e-12 * std::max(1.0, cp.dyad.radius)) << "ray " << cp.ray;
  // The curve through the original circle points, with their centres A and D: traced from a
  // base 1.7 to the left of each, its ray 0 (along +x) meets it at s = 1.7.
  for (const auto& [world, pivot] : {std::pair{f.B(q[0]), f.A()}, std::pair{f.C(q[0]), f.D()}}) {
    const Eigen::Vector2d k = f.BodyPoint(q[0], world);
    double best = kInf;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const CurvePoint& cp : FourPoseCurve(poses, k - Eigen::Vector2d(1.7, 0), 8)) {
      if (cp.ray != 0) continue;
      const double gap = (cp.dyad.k - k).norm();
      if (gap < best) best = gap, centre = cp.dyad.M;
    }
    EXPECT_LT(best, 1e-10) << "the original circle point is not on the circle-point curve";
    EXPECT_LT((centre - pivot).norm(), 1e-10) << "its centre is not the original pivot";
  }
}

TEST(MotionSynthesis, FivePosesBurmesterPointsContainTheOriginalDyads) {
  const HandFourBar f;
  const std::vector<double> q = {20 * kDeg, 60 * kDeg, 100 * kDeg, 150 * kDeg, 200 * kDeg};
  const auto poses = PosesOf(f, q);
  const std::vector<Dyad> points = BurmesterPoints(poses);
  ASSERT_GE(points.size(), 2u);
  EXPECT_LE(points.size(), 4u);
  for (const Dyad& d : points) EXPECT_LT(d.residual, 1e-12 * std::max(1.0, d.radius));
  const Dyad* crank = nullptr;
  const Dyad* rocker = nullptr;
  for (const Dyad& d : points) {
    if ((d.M - f.A()).norm() < 1e-9 && (d.k - f.BodyPoint(q[0], f.B(q[0]))).norm() < 1e-9) crank = &d;
    if ((d.M - f.D()).norm() < 1e-9 && (d.k - f.BodyPoint(q[0], f.C(q[0]))).norm() < 1e-9) rocker = &d;
  }
  ASSERT_NE(crank, nullptr) << "the crank's dyad (A, B) is not among the Burmester points";
  ASSERT_NE(rocker, nullptr) << "the rocker's dyad (D, C) is not among the Burmester points";
  // The pair as a four-bar, run by the generated synth_fourbar: at each pose's crank angle its
  // coupler point is the pose's point and its coupler turned by the pose's angle.
  const FourBarFromDyads fb = FourBarOfDyads(poses, *crank, *rocker);
  mech::synth_fourbar::Model::ParamsT<double> p;
  p.a = fb.a, p.b = fb.b, p.c = fb.c, p.d = fb.d, p.xi = fb.xi, p.eta = fb.eta, p.x0 = fb.x0, p.y0 = fb.y0,
  p.theta0 = fb.theta0;
  using M = mech::synth_fourbar::Model;
  for (size_t j = 0; j < poses.size(); ++j) {
    Eigen::Matrix<double, M::kNq, 1> qv;
    qv(0) = fb.crank_angle[j];
    Eigen::Matrix<double, M::kNphi, 1> phi;
    for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[static_cast<size_t>(i)];
    const auto report = M::Solve(p, qv, &phi, M::kDefaultModes);
    ASSERT_EQ(report.status, decltype(report.status)::kConverged);
    M::CoefficientsT<double> co;
    M::Coeffs(p, qv, phi, &co);
    EXPECT_NEAR(co.r_P(0, 0), poses[j].x, 1e-9) << "pose " << j;
    EXPECT_NEAR(co.r_P(1, 0), poses[j].y, 1e-9) << "pose " << j;
    EXPECT_NEAR(WrapPi(phi(0) - poses[j].angle), 0.0, 1e-9) << "pose " << j;  // theta_coupler
  }
}

TEST(MotionSynthesis, FivePoseTaskGivesAFourBarTheModelRunsThroughThePoses) {
  const HandFourBar f;
  const std::vector<double> q = {20 * kDeg, 60 * kDeg, 100 * kDeg, 150 * kDeg, 200 * kDeg};
  std::string yaml = "synthesis: motion\npoint: coupler.P\ncoupler_angle: theta_coupler\nposes:\n";
  for (const Pose& p : PosesOf(f, q)) yaml += "  - [" + Num(p.x) + ", " + Num(p.y) + ", " + Num(p.angle) + "]\n";
  yaml += "parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}\n";
  const std::string path = ::testing::TempDir() + "/motion_task.yaml";
  std::ofstream(path) << yaml;
  MotionTask task;
  std::string error;
  ASSERT_TRUE(ParseMotionTask(path, &task, &error)) << error;
  MotionResult r;
  ASSERT_TRUE(SynthesizeMotion<mech::synth_fourbar::Model>(task, {}, &r, &error)) << error;
  ASSERT_GE(r.chosen, 0) << MotionReport(task, r);
  const MotionCandidate& c = r.candidates[static_cast<size_t>(r.chosen)];
  EXPECT_LT(c.worst_point, 1e-9);
  EXPECT_LT(c.worst_angle, 1e-9);
  // The original four-bar (crank at A, rocker at D) is among the pairs and passes.
  bool original = false;
  for (const MotionCandidate& m : r.candidates)
    original = original || (m.ok && std::abs(m.fourbar.a - f.a) < 1e-9 && std::abs(m.fourbar.b - f.b) < 1e-9 &&
                            std::abs(m.fourbar.c - f.c) < 1e-9 && std::abs(m.fourbar.d - f.d) < 1e-9 &&
                            std::abs(m.fourbar.xi - f.xi) < 1e-9 && std::abs(m.fourbar.eta - f.eta) < 1e-9);
  EXPECT_TRUE(original) << MotionReport(task, r);
  // The one written is the passing pair with the smallest link ratio.
  for (const MotionCandidate& m : r.candidates) {
    if (!m.ok) continue;
    EXPECT_GE(m.ratio, c.ratio);
  }
  // Its model file assembles as the sweep does on the synthesis' branch and runs through the
  // poses' points (issue 44: every command's output runs in every other command).
  using M = mech::synth_fourbar::Model;
  M::ParamsT<double> p;
  const FourBarFromDyads& fb = c.fourbar;
  const double values[9] = {fb.a, fb.b, fb.c, fb.d, fb.xi, fb.eta, fb.x0, fb.y0, fb.theta0};
  for (size_t k = 0; k < 9; ++k) *p.Find(task.parameters[k].c_str()) = values[k];
  std::array<int, M::kNumBlocks> modes = M::kDefaultModes;  // the pair's mode: the model's or its mirror
  modes[0] = c.mode;
  std::string text;
  WrittenAssembly written;
  ASSERT_TRUE(WriteSynthesizedModel<M>(ReadFile(Tasks("../models/synth_fourbar.yaml")), p, task.parameters,
                                       MotionInputs(fb), &text, &written, &error, &modes))
      << error;
  std::vector<Eigen::Vector2d> points;
  for (const Pose& pose : PosesOf(f, q)) points.emplace_back(pose.x, pose.y);
  ExpectSweepable<M>(text, MotionInputs(fb), 0, points, modes);
}

// The mirror assembly mode (issue 28's "refused, not re-assembled"): five poses of the placed
// four-bar with C to the right of B -> D (hand formulas), which the model reaches only on its
// other mode (crank at 30, 70, 120, 170, 220 deg: at 20, 60, 100, 150, 200 deg the traced
// curve misses the rocker's Burmester point, see docs/synthesis.md). The original four-bar passes on the mirror mode, its pose errors below 1e-9; the
// model file is written on that mode (its hints the mirror root, the modes the runtime finds
// back there the mirror's) and runs through the poses' points (ExpectSweepable). Six such
// poses by least squares: the mirror mode chosen at pose 1 and every pose by hand to 1e-9.
TEST(MotionSynthesis, MirrorAssemblyModeIsReassembledNotRefused) {
  using M = mech::synth_fourbar::Model;
  HandFourBar f;
  f.side = -1;
  std::array<int, M::kNumBlocks> mirror = M::kDefaultModes;
  mirror[0] = -mirror[0];
  for (const std::vector<double>& q : {std::vector<double>{30 * kDeg, 70 * kDeg, 120 * kDeg, 170 * kDeg, 220 * kDeg},
                                       std::vector<double>{20 * kDeg, 55 * kDeg, 95 * kDeg, 140 * kDeg, 185 * kDeg, 230 * kDeg}}) {
    std::string yaml = "synthesis: motion\npoint: coupler.P\ncoupler_angle: theta_coupler\nposes:\n";
    const std::vector<Pose> poses = PosesOf(f, q);
    for (const Pose& p : poses) yaml += "  - [" + Num(p.x) + ", " + Num(p.y) + ", " + Num(p.angle) + "]\n";
    yaml += "parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}\n";
    const std::string path = ::testing::TempDir() + "/motion_mirror_task.yaml";
    std::ofstream(path) << yaml;
    MotionTask task;
    std::string error;
    ASSERT_TRUE(ParseMotionTask(path, &task, &error)) << error;
    MotionResult r;
    ASSERT_TRUE(SynthesizeMotion<M>(task, {}, &r, &error)) << error;
    ASSERT_GE(r.chosen, 0) << MotionReport(task, r);
    const std::string report = MotionReport(task, r);
    bool original = false;
    for (const MotionCandidate& m : r.candidates) {
      const bool same = std::abs(m.fourbar.a - f.a) < 1e-9 && std::abs(m.fourbar.b - f.b) < 1e-9 &&
                        std::abs(m.fourbar.c - f.c) < 1e-9 && std::abs(m.fourbar.d - f.d) < 1e-9 &&
                        std::abs(m.fourbar.xi - f.xi) < 1e-9 && std::abs(m.fourbar.eta - f.eta) < 1e-9;
      if (!same || !m.ok) continue;
      original = true;
      EXPECT_EQ(m.mode, mirror[0]);
      EXPECT_LT(m.worst_point, 1e-9);
    }
    EXPECT_TRUE(original) << report;
    EXPECT_NE(report.find("passes on the mirror mode"), std::string::npos) << report;
    const MotionCandidate& c = r.candidates[static_cast<size_t>(r.chosen)];
    const FourBarFromDyads& fb = c.fourbar;
    // Every pose by hand on the chosen four-bar's side (C right of B -> D for the mirror mode).
    HandFourBar g;
    g.a = fb.a, g.b = fb.b, g.c = fb.c, g.d = fb.d, g.xi = fb.xi, g.eta = fb.eta, g.x0 = fb.x0, g.y0 = fb.y0;
    g.theta0 = fb.theta0, g.side = c.mode == mirror[0] ? -1 : 1;
    for (size_t j = 0; j < poses.size(); ++j) {
      const Pose h = g.PoseAt(fb.crank_angle[j]);
      EXPECT_NEAR(h.x, poses[j].x, 1e-9) << "pose " << j + 1;
      EXPECT_NEAR(h.y, poses[j].y, 1e-9) << "pose " << j + 1;
    }
    M::ParamsT<double> p;
    const double values[9] = {fb.a, fb.b, fb.c, fb.d, fb.xi, fb.eta, fb.x0, fb.y0, fb.theta0};
    for (size_t k = 0; k < 9; ++k) *p.Find(task.parameters[k].c_str()) = values[k];
    std::array<int, M::kNumBlocks> modes = M::kDefaultModes;
    modes[0] = c.mode;
    std::string text;
    WrittenAssembly written;
    ASSERT_TRUE(WriteSynthesizedModel<M>(ReadFile(Tasks("../models/synth_fourbar.yaml")), p, task.parameters,
                                         MotionInputs(fb), &text, &written, &error, &modes))
        << error;
    std::vector<Eigen::Vector2d> points;
    for (const Pose& pose : poses) points.emplace_back(pose.x, pose.y);
    ExpectSweepable<M>(text, MotionInputs(fb), 0, points, modes);
  }
}

TEST(MotionSynthesis, SixPosesByLeastSquaresReproducedByHand) {
  // Six poses of the placed four-bar: the Burmester points of five of them seed the least
  // squares over all six; the four-bar written reproduces all six poses (hand formulas, not
  // the generated solve) to 1e-9.
  const HandFourBar f;
  const std::vector<double> q = {20 * kDeg, 55 * kDeg, 95 * kDeg, 140 * kDeg, 185 * kDeg, 230 * kDeg};
  std::string yaml = "synthesis: motion\npoint: coupler.P\ncoupler_angle: theta_coupler\nposes:\n";
  const std::vector<Pose> poses = PosesOf(f, q);
  for (const Pose& p : poses) yaml += "  - [" + Num(p.x) + ", " + Num(p.y) + ", " + Num(p.angle) + "]\n";
  yaml += "parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}\n"
          "seed_poses: [1, 2, 4, 5, 6]\n";
  const std::string path = ::testing::TempDir() + "/motion6_task.yaml";
  std::ofstream(path) << yaml;
  MotionTask task;
  std::string error;
  ASSERT_TRUE(ParseMotionTask(path, &task, &error)) << error;
  EXPECT_EQ(task.seed_poses, (std::vector<int>{0, 1, 3, 4, 5}));
  MotionResult r;
  ASSERT_TRUE(SynthesizeMotion<mech::synth_fourbar::Model>(task, {}, &r, &error)) << error;
  ASSERT_GE(r.chosen, 0) << MotionReport(task, r);
  EXPECT_GT(r.evaluations, 0);
  const MotionCandidate& c = r.candidates[static_cast<size_t>(r.chosen)];
  EXPECT_LT(c.error, 1e-18);
  const FourBarFromDyads& fb = c.fourbar;
  HandFourBar g;
  g.a = fb.a, g.b = fb.b, g.c = fb.c, g.d = fb.d, g.xi = fb.xi, g.eta = fb.eta, g.x0 = fb.x0, g.y0 = fb.y0, g.theta0 = fb.theta0;
  const double offset = g.PoseAt(fb.crank_angle[0]).angle - poses[0].angle;
  for (size_t j = 0; j < poses.size(); ++j) {
    const Pose h = g.PoseAt(fb.crank_angle[j]);
    EXPECT_NEAR(h.x, poses[j].x, 1e-9) << "pose " << j + 1;
    EXPECT_NEAR(h.y, poses[j].y, 1e-9) << "pose " << j + 1;
    EXPECT_NEAR(WrapPi(h.angle - offset - poses[j].angle), 0.0, 1e-9) << "pose " << j + 1;
  }
  // The default seed poses: the first, the last and three between.
  yaml.erase(yaml.find("seed_poses"));
  std::ofstream(path) << yaml;
  ASSERT_TRUE(ParseMotionTask(path, &task, &error)) << error;
  EXPECT_EQ(task.seed_poses, (std::vector<int>{0, 1, 3, 4, 5}));  // round(k * 5 / 4): 0, 1, 3 (2.5 up), 4, 5
  // Six poses one of which no four-bar meets (pose 4 moved by 1e-3): the least squares' error
  // is positive and no larger than the Burmester seed's own (LM does not make it worse).
  std::string moved = "synthesis: motion\npoint: coupler.P\ncoupler_angle: theta_coupler\nposes:\n";
  for (size_t j = 0; j < poses.size(); ++j)
    moved += "  - [" + Num(poses[j].x + (j == 3 ? 1e-3 : 0.0)) + ", " + Num(poses[j].y) + ", " + Num(poses[j].angle) + "]\n";
  moved += "parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}\n"
           "seed_poses: [1, 2, 3, 5, 6]\n";
  std::ofstream(path) << moved;
  ASSERT_TRUE(ParseMotionTask(path, &task, &error)) << error;
  ASSERT_TRUE(SynthesizeMotion<mech::synth_fourbar::Model>(task, {}, &r, &error)) << error;
  ASSERT_GE(r.chosen, 0) << MotionReport(task, r);
  const MotionCandidate& m = r.candidates[static_cast<size_t>(r.chosen)];
  EXPECT_GT(m.error, 0);
  EXPECT_LT(m.error, 1e-6);           // the seed (exact at five poses) misses pose 4 by 1e-3: 1e-6
  EXPECT_LT(m.worst_point, 1e-3);
}

TEST(MotionSynthesis, GlobalStageOverFivePoseSubsets) {
  // Seven poses of the placed four-bar (the crank at 20, 60, 100, 150, 200, 250, 300 deg), the
  // seventh moved by (0.3, -0.15) and 0.1 rad: no four-bar meets all seven. The default seed
  // poses (1, 3, 4, 6, 7) hold the moved one, and the least squares from their Burmester
  // points' pairs ends in a basin the global stage (`search: {subsets: 21}`: all 21 five-pose
  // subsets) beats. Oracles by hand (circle intersection at each four-bar's crank angles, the
  // body's angle offset the mean of the angle errors, which is where the least squares puts
  // it): the errors the library reports are the hand ones (1e-9 relative), the global one below
  // a fifth of the seeds' alone; the subsets are the 21 of seven poses, each once, the seed
  // poses' first.
  const HandFourBar f;
  const std::vector<double> q = {20 * kDeg, 60 * kDeg, 100 * kDeg, 150 * kDeg, 200 * kDeg, 250 * kDeg, 300 * kDeg};
  std::vector<Pose> poses = PosesOf(f, q);
  poses[6].x += 0.3, poses[6].y -= 0.15, poses[6].angle += 0.1;
  std::string yaml = "synthesis: motion\npoint: coupler.P\ncoupler_angle: theta_coupler\nposes:\n";
  for (const Pose& p : poses) yaml += "  - [" + Num(p.x) + ", " + Num(p.y) + ", " + Num(p.angle) + "]\n";
  yaml += "parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}\n";
  auto run = [&](const std::string& extra, MotionTask* task, MotionResult* r) {
    const std::string path = ::testing::TempDir() + "/motion7_task.yaml";
    std::ofstream(path) << yaml + extra;
    std::string error;
    ASSERT_TRUE(ParseMotionTask(path, task, &error)) << error;
    ASSERT_TRUE(SynthesizeMotion<mech::synth_fourbar::Model>(*task, {}, r, &error)) << error;
    ASSERT_GE(r->chosen, 0) << MotionReport(*task, *r);
  };
  MotionTask ts, tg, td;
  MotionResult rs, rg, rd;
  run("search: {subsets: 0}\n", &ts, &rs);
  run("search: {subsets: 21}\n", &tg, &rg);
  // The default (21) takes every subset of seven poses: the same subsets and answer.
  run("", &td, &rd);
  EXPECT_EQ(td.subsets, 21);
  EXPECT_EQ(rd.subsets, rg.subsets);
  EXPECT_EQ(rd.candidates[static_cast<size_t>(rd.chosen)].error, rg.candidates[static_cast<size_t>(rg.chosen)].error);
  EXPECT_EQ(ts.seed_poses, (std::vector<int>{0, 2, 3, 5, 6}));
  EXPECT_EQ(tg.subsets, 21);
  ASSERT_EQ(rg.subsets.size(), 21u);
  EXPECT_EQ(rg.subsets[0], ts.seed_poses);
  std::set<std::vector<int>> distinct(rg.subsets.begin(), rg.subsets.end());
  EXPECT_EQ(distinct.size(), 21u);
  for (const auto& s : rg.subsets) {
    ASSERT_EQ(s.size(), 5u);
    for (size_t k = 1; k < 5; ++k) EXPECT_LT(s[k - 1], s[k]);
    EXPECT_LT(s[4], 7);
  }
  // The least-squares error by hand.
  const double L = burmester_internal::Scale(poses);
  auto hand_error = [&](const MotionResult& r) {
    const MotionCandidate& c = r.candidates[static_cast<size_t>(r.chosen)];
    const FourBarFromDyads& fb = c.fourbar;
    HandFourBar g;
    g.a = fb.a, g.b = fb.b, g.c = fb.c, g.d = fb.d, g.xi = fb.xi, g.eta = fb.eta, g.x0 = fb.x0, g.y0 = fb.y0, g.theta0 = fb.theta0;
    g.side = c.mode == r.model_mode ? 1 : -1;
    double points = 0, mean = 0;
    std::vector<double> da;
    for (size_t j = 0; j < poses.size(); ++j) {
      const Pose h = g.PoseAt(fb.crank_angle[j]);
      points += std::pow(h.x - poses[j].x, 2) + std::pow(h.y - poses[j].y, 2);
      da.push_back(WrapPi(h.angle - poses[j].angle - (g.PoseAt(fb.crank_angle[0]).angle - poses[0].angle)));
      mean += da.back() / static_cast<double>(poses.size());
    }
    double angles = 0;
    for (double d : da) angles += L * L * (d - mean) * (d - mean);
    return points + angles;
  };
  const double es = rs.candidates[static_cast<size_t>(rs.chosen)].error, eg = rg.candidates[static_cast<size_t>(rg.chosen)].error;
  EXPECT_NEAR(hand_error(rs), es, 1e-9 * es);
  EXPECT_NEAR(hand_error(rg), eg, 1e-9 * eg);
  EXPECT_LT(eg, 0.2 * es);
  const std::string report = MotionReport(tg, rg);
  EXPECT_NE(report.find("global stage (search.subsets 21): the Burmester points of 20 more five-pose subsets"),
            std::string::npos)
      << report;
  std::printf("seven poses, the seventh moved: seed poses 1 3 4 6 7 alone: %zu Burmester points, error %.8g; with all 21 "
              "subsets: %zu points, error %.8g (%lld residual evaluations)\n",
              rs.points.size(), es, rg.points.size(), eg, rg.evaluations);
  // Fewer subsets than there are: evenly spread over the lexicographic order, the seed poses' skipped.
  EXPECT_EQ(motion_internal::FivePoseSubsets(7, 3, {0, 1, 2, 3, 4}),
            (std::vector<std::vector<int>>{{0, 1, 3, 4, 6}, {0, 3, 4, 5, 6}}));  // ranks 7, 14 (rank 0 is the seed)
  EXPECT_EQ(motion_internal::FivePoseSubsets(6, 100, {}).size(), 6u);
  // Bad values: FILE:LINE:COLUMN: error:.
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"search: {subsets: -1}\n", ":13:19: error: subsets: expected an integer in [0, 100000], got -1"},
           {"search: {subsets: 2.5}\n", ":13:19: error: subsets: expected an integer"}}) {
    const std::string path = ::testing::TempDir() + "/motion7_bad.yaml";
    std::ofstream(path) << yaml + text;  // the search on line 13
    MotionTask t;
    std::string error;
    EXPECT_FALSE(ParseMotionTask(path, &t, &error));
    EXPECT_NE(error.find(path + says), std::string::npos) << error;
  }
}

// The refind task with the ground length d free and a ground region in its constraints.
BoundPath<mech::fourbar::Model> RegionTask(const std::string& region, const std::string& name) {
  std::ifstream in(Tasks("fourbar_refind.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("variables:\n"), 11, "variables:\n  d: [2, 6]\n");
  yaml.replace(yaml.find("constraints:\n"), 13, "constraints:\n  ground_region: " + region + "\n");
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << yaml;
  return Bind<mech::fourbar::Model>(path);
}

TEST(PathSynthesis, GroundPivotsInARegion) {
  using M = mech::fourbar::Model;
  // The pivots are A = (0, 0) and D = (d, 0) (models/fourbar.yaml); the unconstrained optimum
  // is the shipped four-bar, d = 4.
  {
    const auto b = RegionTask("{pivots: [ground.D], rectangle: [[-1, -1], [3.5, 1]]}", "region_rect.yaml");
    ASSERT_TRUE(b.task.constraints.has_region);
    PathEvaluator<M> eval(b);
    // d = 4 (the unconstrained answer): D is 0.5 right of the rectangle, the violation by hand.
    const Candidate c = eval.Evaluate({4.0, 1.0, 3.5, 3.0, 1.5, 1.0});
    EXPECT_FALSE(c.feasible());
    EXPECT_EQ(c.defect, "ground point ground.D outside ground_region");
    EXPECT_NEAR(c.violation, 0.5, 1e-12);
    const SearchResult s = Synthesize(b, 1, 2);
    ASSERT_TRUE(s.best.best.feasible()) << s.best.best.defect;
    const double d = s.best.best.x[0];
    EXPECT_LE(d, 3.5);
    EXPECT_NEAR(d, 3.5, 1e-9) << "the constrained optimum is on the boundary";
    EXPECT_GT(s.best.best.error, 1e-6);  // the targets are the d = 4 four-bar's
  }
  {
    // A circle about (2, 0) of radius 1.9 holds A (0, 0)? No: |A - (2, 0)| = 2 > 1.9; every
    // ground point (no pivots named: A and D) must be inside: a defect of 0.1 for A at d = 4
    // (|D - (2, 0)| = 2: another 0.1).
    const auto b = RegionTask("{circle: {centre: [2, 0], radius: 1.9}}", "region_circle.yaml");
    PathEvaluator<M> eval(b);
    const Candidate c = eval.Evaluate({4.0, 1.0, 3.5, 3.0, 1.5, 1.0});
    EXPECT_NEAR(c.violation, 0.2, 1e-12);
    // A circle holding both at d = 4: the shipped four-bar found again, the pivots inside.
    const auto in = RegionTask("{circle: {centre: [2, 0], radius: 2.5}}", "region_in.yaml");
    const SearchResult s = Synthesize(in, 1, 2);
    ASSERT_TRUE(s.best.best.feasible()) << s.best.best.defect;
    EXPECT_LT(s.best.best.error, 1e-16);
    EXPECT_LE(std::abs(s.best.best.x[0] - 2), 2.5);
  }
  // Errors: a pivot that is not a ground point, both shapes.
  std::string error;
  PathTask task;
  const std::string path = ::testing::TempDir() + "/region_bad.yaml";
  std::ofstream(path) << "synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1]]\nvariables: {a: [0, 1]}\n"
                         "constraints:\n  ground_region: {pivots: [crank.B], rectangle: [[0, 0], [1, 1]]}\n";
  ASSERT_TRUE(ParseTask(path, &task, &error)) << error;
  BoundPath<M> b;
  EXPECT_FALSE(BindPathTask<M>(task, {}, &b, &error));
  EXPECT_EQ(error, path + ":6:18: error: ground_region: 'crank.B' is not a point of the model's ground link (ground.A, ground.D)");
  std::ofstream(path) << "synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1]]\nvariables: {a: [0, 1]}\n"
                         "constraints:\n  ground_region: {rectangle: [[0, 0], [1, 1]], circle: {centre: [0, 0], radius: 1}}\n";
  EXPECT_FALSE(ParseTask(path, &task, &error));
  EXPECT_EQ(error, path + ":6:18: error: ground_region: give either rectangle: [[xmin, ymin], [xmax, ymax]] or circle: {centre: [x, y], radius: r}");
}

TEST(PathSynthesis, LinkRatioConstraint) {
  // The shipped four-bar (links 1, 3.5, 3, 4: the longest over the shortest is 4) on its own
  // coupler points: a defect under link_ratio 3.9, none under 4.1.
  std::ifstream in(Tasks("fourbar_refind.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  for (const double ratio : {3.9, 4.1}) {
    std::string yaml = text.str();
    yaml.replace(yaml.find("constraints:\n"), 13, "constraints:\n  link_ratio: " + Num(ratio) + "\n");
    const std::string path = ::testing::TempDir() + "/ratio_task.yaml";
    std::ofstream(path) << yaml;
    const auto b = Bind<mech::fourbar::Model>(path);
    ASSERT_TRUE(b.task.constraints.has_ratio);
    PathEvaluator<mech::fourbar::Model> eval(b);
    const Candidate c = eval.Evaluate({1.0, 3.5, 3.0, 1.5, 1.0});
    if (ratio < 4) {
      EXPECT_FALSE(c.feasible());
      EXPECT_EQ(c.defect, "the longest link over the shortest above link_ratio");
      EXPECT_NEAR(c.violation, 4.0 - 3.9, 1e-12);
    } else {
      EXPECT_TRUE(c.feasible()) << c.defect;
    }
  }
}


// ---- The global stage (issue 28's benchmark quality) ----

// Case 4 of the benchmarks (six points on an arc, prescribed timing, crank the shortest) at a
// small budget: every seed ends with a mechanism, and what makes it one is checked by hand
// (the crank the shortest of the four lengths, s + l <= p + q, the error from the hand
// formulas of the placed four-bar, the runtime's continuation); the same bits for 1 and 2
// threads.
TEST(PathSynthesis, ArcWithTheCrankShortestFeasibleForEverySeed) {
  using M = mech::synth_fourbar::Model;
  std::ifstream in(Tasks("../benchmarks/case4_arc.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("evaluations: 50000"), 18, "evaluations: 8000");
  yaml.replace(yaml.find("restarts: 4"), 11, "restarts: 2");
  const std::string path = ::testing::TempDir() + "/arc_small.yaml";
  std::ofstream(path) << yaml;
  const auto b = Bind<M>(path);
  ASSERT_TRUE(b.task.constraints.crank_shortest);
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const SearchResult s = Synthesize(b, seed, 1);
    const Candidate& c = s.best.best;
    ASSERT_TRUE(c.feasible()) << "seed " << seed << ": " << c.defect;
    EXPECT_LE(s.evaluations, 8000);
    HandFourBar f;
    f.a = c.x[0], f.b = c.x[1], f.c = c.x[2], f.d = c.x[3], f.xi = c.x[4], f.eta = c.x[5];
    f.x0 = c.x[6], f.y0 = c.x[7], f.theta0 = c.x[8];
    std::array<double, 4> len = {f.a, f.b, f.c, f.d};
    std::sort(len.begin(), len.end());
    EXPECT_EQ(len[0], f.a) << "seed " << seed << ": the crank is not the shortest";
    EXPECT_LE(len[0] + len[3], len[1] + len[2]) << "seed " << seed << ": not Grashof";
    double error = 0;
    for (int i = 0; i < b.n; ++i) {
      const Pose p = f.PoseAt(b.task.timing.angles[static_cast<size_t>(i)] + f.theta0);
      error += std::pow(p.x - b.task.tx[static_cast<size_t>(i)], 2) + std::pow(p.y - b.task.ty[static_cast<size_t>(i)], 2);
    }
    EXPECT_NEAR(c.error, error, 1e-9 * (1 + error)) << "seed " << seed;
    EXPECT_LT(c.error, 10.0) << "seed " << seed;  // the global best basin ~1.4, the start ~160
    PathEvaluator<M> eval(b);
    EXPECT_EQ(ContinuationCheck(&eval, c), "") << "seed " << seed;
  }
  const SearchResult one = Synthesize(b, 3, 1), two = Synthesize(b, 3, 2);
  EXPECT_EQ(one.evaluations, two.evaluations);
  ASSERT_EQ(one.best.best.x.size(), two.best.best.x.size());
  EXPECT_EQ(0, std::memcmp(one.best.best.x.data(), two.best.best.x.data(), one.best.best.x.size() * sizeof(double)));
}

// `placement:` fits the frame's x, y and angle in closed form: targets of a four-bar placed by
// hand at (0.7, -0.3, 0.5 rad), timing measured from the frame's angle; from a wrong
// placement, Place gives back the hand one (Procrustes is exact when the shape is right) and
// the evaluation's error vanishes; a placement that does not move the model rigidly, and one
// whose angle is not the timing's reference, are refused with the file's place.
TEST(PathSynthesis, PlacementFittedInClosedForm) {
  using M = mech::synth_fourbar::Model;
  HandFourBar f;
  f.x0 = 0.7, f.y0 = -0.3, f.theta0 = 0.5;
  const std::vector<double> angles = {0.0, 40.0, 80.0, 120.0, 160.0};
  std::string targets;
  for (double a : angles) {
    const Pose p = f.PoseAt(a * M_PI / 180 + f.theta0);
    char buf[100];
    std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", targets.empty() ? "" : ", ", p.x, p.y);
    targets += buf;
  }
  auto task = [&](const std::string& angle) {
    return "synthesis: path\npoint: coupler.P\ntargets: [" + targets + "]\n" +
           "timing: {angles: [0deg, 40deg, 80deg, 120deg, 160deg], offset: 0, relative_to: " + angle + "}\n" +
           "variables: {a: [0.5, 2], b: [1, 6], c: [1, 6], d: [1, 6], xi: [-4, 4], eta: [-4, 4], x0: [-5, 5], "
           "y0: [-5, 5], theta0: [0, 6.283185307179586]}\n"
           "placement: {x: x0, y: y0, angle: " + angle + "}\n";
  };
  const std::string path = ::testing::TempDir() + "/placed.yaml";
  std::ofstream(path) << task("theta0");
  const auto b = Bind<M>(path);
  ASSERT_EQ(b.place_angle, 8);
  PathEvaluator<M> eval(b);
  std::vector<double> x = {f.a, f.b, f.c, f.d, f.xi, f.eta, 4.0, 4.0, 3.0};
  ASSERT_TRUE(eval.Place(&x));
  EXPECT_NEAR(x[6], 0.7, 1e-9);
  EXPECT_NEAR(x[7], -0.3, 1e-9);
  EXPECT_NEAR(x[8], 0.5, 1e-9);
  const Candidate c = eval.Evaluate({f.a, f.b, f.c, f.d, f.xi, f.eta, -2.0, 1.0, 5.0});
  EXPECT_LT(c.error, 1e-18);
  EXPECT_NEAR(c.x[8], 0.5, 1e-9);
  // Not rigid: d changes the shape, not the frame.
  std::ofstream(path) << task("d");
  PathTask t;
  std::string error;
  ASSERT_TRUE(ParseTask(path, &t, &error)) << error;
  BoundPath<M> bad;
  EXPECT_FALSE(BindPathTask<M>(t, M::ParamsT<double>(), &bad, &error));
  EXPECT_EQ(error.substr(0, path.size() + 5), path + ":6:12");
  EXPECT_NE(error.find("do not place the model rigidly"), std::string::npos) << error;
  // The timing not measured from the placement's angle.
  std::string yaml = task("theta0");
  yaml.replace(yaml.find("relative_to: theta0"), 19, "relative_to: x0");
  std::ofstream(path) << yaml;
  EXPECT_FALSE(ParseTask(path, &t, &error));
  EXPECT_EQ(error.substr(0, path.size() + 5), path + ":6:12");
  EXPECT_NE(error.find("needs prescribed timing measured from its angle"), std::string::npos) << error;
}

// ---- The written model file runs in every command (issues 44 and 45) ----------------------

// Benchmark case 4's answer for seed 1 (`mechgen synthesize` before issue 44's fix): with the
// model's original assembly hints (theta_crank 90 deg, theta_coupler 30 deg, theta_rocker
// 110 deg) the sweep's assembly lands on the other branch and refuses it (wrong_branch); the
// written model's hints, the configuration at the first target, assemble it on the synthesis'
// branch and reproduce its points at every target.
TEST(PathSynthesis, WrittenModelAssemblesOnTheSynthesizedBranch) {
  using M = mech::synth_fourbar::Model;
  const auto b = Bind<M>(Tasks("../benchmarks/case4_arc.yaml"));
  PathEvaluator<M> eval(b);
  const Candidate c = eval.Evaluate({1.9748852351199608, 2.0472110527769622, 33.625362478716788, 33.696395699571063,
                                     12.254499329872713, 5.0637295466570418, 10.45036373872942, -5.2579486796834223, 0});
  ASSERT_TRUE(c.feasible()) << c.defect;
  EXPECT_NEAR(c.error, 1.619423478, 1e-8);
  ASSERT_EQ(ContinuationCheck(&eval, c), "");
  const auto p = eval.ParamsOf(c.x);
  {
    mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), p);
    EXPECT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kWrongBranch);  // the original hints
  }
  const std::string model = ReadFile(Tasks("../models/synth_fourbar.yaml"));
  std::vector<std::string> names;
  for (const Variable& v : b.task.variables) names.push_back(v.name);
  std::string text, error;
  WrittenAssembly written;
  ASSERT_TRUE(WriteSynthesizedModel<M>(model, p, names, MotionInputs(b, c), &text, &written, &error)) << error;
  EXPECT_TRUE(written.set.empty());
  EXPECT_FALSE(written.range_written);  // the crank turns fully: the model's [0, 360 deg] stays
  EXPECT_EQ(written.continuation, "");
  EXPECT_NEAR(written.q, 30 * M_PI / 180, 1e-15);
  // Only values changed: the same lines, the assembly's three values the configuration's.
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), std::count(model.begin(), model.end(), '\n'));
  const WrittenModel<M> w(text);
  for (size_t j = 0; j < names.size(); ++j) EXPECT_EQ(*WrittenModel<M>(text).p.Find(names[j].c_str()), c.x[j]) << names[j];
  EXPECT_EQ(w.q(0), written.q);
  std::vector<Eigen::Vector2d> points;
  typename PathEvaluator<M>::VecPhi phi;
  typename PathEvaluator<M>::Coeffs co;
  for (double q : MotionInputs(b, c)) {
    ASSERT_TRUE(eval.PointAt(p, q, &phi, &co));
    points.emplace_back(co.r_P(0, b.point), co.r_P(1, b.point));
  }
  ExpectSweepable<M>(text, MotionInputs(b, c), b.point, points);
}

// A crank that cannot turn fully (a Grashof double rocker: the coupler the shortest link, a =
// 3, b = 2, c = 3.5, d = 4; at 120 deg |BD| = 6.08 > b + c): the model's range [0, 360 deg],
// which the generator refuses for it and the sweep cannot pass, is narrowed to the motion
// through the targets (60, 75, 90 deg measured from the frame's angle 0.3); a model file
// without an `assembly:` section gets one; an input without `range:` gets one, a flow-style
// `assembly:` its missing coordinates; the assembly and the points as above.
TEST(PathSynthesis, WrittenModelOfACrankThatDoesNotTurnFully) {
  using M = mech::synth_fourbar::Model;
  std::string model = ReadFile(Tasks("../models/synth_fourbar.yaml"));
  model.erase(model.find("assembly:"));
  M::ParamsT<double> p;
  *p.Find("a") = 3, *p.Find("b") = 2, *p.Find("c") = 3.5, *p.Find("d") = 4, *p.Find("theta0") = 0.3;
  const std::vector<double> motion = {0.3 + 60 * kDeg, 0.3 + 75 * kDeg, 0.3 + 90 * kDeg};
  std::vector<Eigen::Vector2d> points;
  for (double q : motion) {
    Eigen::Matrix<double, 1, 1> qv;
    qv(0) = q;
    Eigen::Vector2d phi(M::kAssemblyPhi[0], M::kAssemblyPhi[1]);
    ASSERT_EQ(M::Solve(p, qv, &phi, M::kDefaultModes).status, mech::synth_fourbar::SolveStatus::kConverged);
    M::CoefficientsT<double> co;
    M::Coeffs(p, qv, phi, &co);
    points.emplace_back(co.r_P(0, 0), co.r_P(1, 0));
  }
  std::string text, error;
  WrittenAssembly written;
  ASSERT_TRUE(WriteSynthesizedModel<M>(model, p, {"a", "b", "c", "d", "theta0"}, motion, &text, &written, &error)) << error;
  ASSERT_TRUE(written.range_written);
  EXPECT_EQ(written.continuation, "");
  const WrittenModel<M> w(text);
  EXPECT_EQ(w.lo, motion.front());
  EXPECT_EQ(w.hi, motion.back());
  EXPECT_EQ(w.q(0), motion.front());
  ExpectSweepable<M>(text, motion, 0, points);
  // The same written into other spellings of the sections: an input without `range:` (block
  // style), an `assembly:` in flow style naming one coordinate, quoted.
  std::string other = model;
  other.replace(other.find("  - {joint: A, range: [0, 360*deg]}"), 35, "  - joint: A");
  other += "assembly: {theta_coupler: '30*deg'}\n";
  std::string text2;
  WrittenAssembly written2;
  ASSERT_TRUE(WriteSynthesizedModel<M>(other, p, {"a", "b", "c", "d", "theta0"}, motion, &text2, &written2, &error)) << error;
  EXPECT_NE(text2.find("  - range: ["), std::string::npos) << text2;
  EXPECT_NE(text2.find("assembly: {theta_crank: "), std::string::npos) << text2;
  EXPECT_EQ(WrittenModel<M>(text2).phi, w.phi);
  EXPECT_EQ(WrittenModel<M>(text2).lo, w.lo);
  ExpectSweepable<M>(text2, motion, 0, points);
  // The model's own range is not swept on that branch: the reason the range was narrowed.
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), p);
  ASSERT_EQ(solver.Assemble(w.q, w.phi, 0, nullptr), mechgen::position::Status::kConverged);
  Eigen::Matrix<double, 1, 1> q;
  q(0) = 120 * kDeg;
  EXPECT_NE(solver.MoveTo(q, nullptr), mechgen::position::Status::kConverged);
}

// `--set x0=0.5 --set y0=-0.25` (fixed parameters, not variables): the search runs with them
// and the written model carries them (before issue 45 it kept x0 = y0 = 0 and missed every
// target by |(0.5, -0.25)| = 0.56). The shipped four-bar's coupler points moved by (0.5, -0.25)
// are found again, and the written model reproduces them to 1e-9.
TEST(PathSynthesis, ParametersSetOnTheCommandLineAreWrittenIntoTheModel) {
  using M = mech::synth_fourbar::Model;
  std::string yaml = ReadFile(Tasks("fourbar_refind.yaml"));
  PathTask refind;
  std::string error;
  ASSERT_TRUE(ParseTask(Tasks("fourbar_refind.yaml"), &refind, &error)) << error;
  std::string targets;
  for (size_t i = 0; i < refind.tx.size(); ++i) {
    char buf[100];
    std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", i ? ", " : "", refind.tx[i] + 0.5, refind.ty[i] - 0.25);
    targets += buf;
  }
  const std::string path = ::testing::TempDir() + "/refind_moved.yaml";
  std::ofstream(path) << "synthesis: path\npoint: coupler.P\ncrank: crank\ntargets: [" + targets +
                             "]\ntiming: free\nvariables: {a: [0.2, 2], b: [1, 6], c: [1, 6], xi: [-4, 4], eta: [-4, 4]}\n"
                             "constraints: {crank_shortest: true, order: true}\nsearch: {evaluations: 6000, restarts: 2}\n";
  PathTask task;
  ASSERT_TRUE(ParseTask(path, &task, &error)) << error;
  M::ParamsT<double> base;
  *base.Find("x0") = 0.5, *base.Find("y0") = -0.25;
  BoundPath<M> b;
  ASSERT_TRUE(BindPathTask<M>(task, base, &b, &error)) << error;
  const SearchResult s = Synthesize(b, 1, 2);
  const Candidate& c = s.best.best;
  ASSERT_TRUE(c.feasible()) << c.defect;
  for (int i = 0; i < b.n; ++i) ASSERT_LT(c.distance[static_cast<size_t>(i)], 1e-9) << "target " << i + 1;
  std::vector<std::string> names;
  for (const Variable& v : task.variables) names.push_back(v.name);
  EXPECT_EQ(SetParametersText<M>(base, names), "x0 = 0.5 (the model's 0), y0 = -0.25 (the model's 0)");
  PathEvaluator<M> eval(b);
  std::string text;
  WrittenAssembly written;
  ASSERT_TRUE(WriteSynthesizedModel<M>(ReadFile(Tasks("../models/synth_fourbar.yaml")), eval.ParamsOf(c.x), names,
                                       MotionInputs(b, c), &text, &written, &error))
      << error;
  EXPECT_EQ(written.set, (std::vector<std::string>{"x0", "y0"}));
  const WrittenModel<M> w(text);
  EXPECT_EQ(*WrittenModel<M>(text).p.Find("x0"), 0.5);
  EXPECT_EQ(*WrittenModel<M>(text).p.Find("y0"), -0.25);
  std::vector<Eigen::Vector2d> targets_in_order;
  std::vector<double> q;
  std::vector<int> order;
  MotionOrder(b, c, &q, &order);
  for (int i : order) targets_in_order.emplace_back(task.tx[static_cast<size_t>(i)], task.ty[static_cast<size_t>(i)]);
  ExpectSweepable<M>(text, MotionInputs(b, c), b.point, targets_in_order);
  EXPECT_NE(WrittenModelText<M>(written, eval.ParamsOf(c.x)).find("parameters set on the command line: x0 = 0.5, y0 = -0.25"),
            std::string::npos);
}

// A function's expression nested 100 000 deep (parentheses, a function's argument, signs,
// powers) once overflowed the stack: the reader stops at 64 levels (the model reader's bound)
// with the place and the reason; 64 levels still read.
TEST(FunctionSynthesis, ExpressionNestingIsBounded) {
  const std::string deep = std::string(100000, '(') + "x" + std::string(100000, ')');
  std::string calls, powers;
  for (int k = 0; k < 20000; ++k) calls += "sin(", powers += "x^(";
  calls += "x" + std::string(20000, ')');
  powers += "x" + std::string(20000, ')');
  for (const std::string& text : {deep, std::string(100000, '-') + "x", calls, powers}) {
    Expression e;
    int column = 0;
    std::string error;
    EXPECT_FALSE(e.Parse(text, &column, &error)) << text.substr(0, 20);
    EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
    if (text == deep) {
      EXPECT_EQ(column, 65);  // the 65th (
    }
  }
  Expression e;
  int column = 0;
  std::string error;
  ASSERT_TRUE(e.Parse(std::string(64, '(') + "x" + std::string(64, ')'), &column, &error)) << error;
  EXPECT_EQ(e(0.25), 0.25);
  // Through the task file: located, `error:`.
  const std::string path = ::testing::TempDir() + "/deep.yaml";
  std::ofstream(path) << "synthesis: function\noutput: theta_rocker\n"
                         "function: {expression: \"" + deep + "\", x: [1, 2], input: [0, 1], output: [0, 1], points: 3}\n"
                         "variables: {a: [0, 1]}\n";
  FunctionTask task;
  EXPECT_FALSE(ParseFunctionTask(path, &task, &error));
  EXPECT_EQ(error, path + ":3:89: error: function.expression: parentheses, function calls, signs or powers nested deeper "
                          "than 64 levels");
}

// A task path that is a directory (once an uncaught std::ios_base::failure), a device, or no
// file: `FILE: error: ...`, for every kind of task.
TEST(PathSynthesis, TaskPathThatIsNoFile) {
  const std::string dir = ::testing::TempDir();
  std::string error;
  PathTask task;
  EXPECT_FALSE(ParseTask(dir, &task, &error));
  EXPECT_EQ(error, dir + ": error: the path is a directory, not a task file; give the path of a .yaml file");
  error.clear();
  EXPECT_EQ(TaskKind(dir, &error), "");
  EXPECT_EQ(error, dir + ": error: the path is a directory, not a task file; give the path of a .yaml file");
  FunctionTask ftask;
  EXPECT_FALSE(ParseFunctionTask("/dev/null", &ftask, &error));
  EXPECT_EQ(error, "/dev/null: error: the path is not a regular file (a device, a pipe or a socket); give the path of a "
                   ".yaml file");
  MotionTask mtask;
  EXPECT_FALSE(ParseMotionTask(dir + "/no_such_task.yaml", &mtask, &error));
  EXPECT_EQ(error, dir + "/no_such_task.yaml: error: cannot open the task file (no such file); check the path");
}

// Benchmark case 5 as published (case5_ellipse_published.yaml: the ellipse's points rounded to
// 5 digits, as Nguyen-Van et al. used them): their best design (x_best_HCDJ_Case5.txt of their
// repository, sy-nguyen-van/DE_Jaya_Synthesis_Four_Bar_Mechanisms; ground 79.999856, crank
// 8.1232008, coupler 50.870344, rocker 42.360533, the coupler point (-10.853763, 0.091433127),
// the frame at (7.5379031, -0.52254141, 4.0121195 rad), the crank at their ten angles from the
// ground line) on the model's assembly mode gives their objective, 4.2014343e-4 by their
// formula (Objf5.m, evaluated in Python; recorded 4.2014375e-4), and on the exact ellipse
// (case5_ellipse.yaml) 4.2439500e-4 (issue 44's 4.2440e-4); it passes the defect checks, and
// free timing (each point projected onto the curve) can only lower it.
TEST(PathSynthesis, PublishedCase5DesignGivesThePublishedError) {
  using M = mech::synth_fourbar::Model;
  const std::vector<double> x = {8.1232008, 50.870344, 42.360533, 79.999856, -10.853763, 0.091433127,
                                 7.5379031, -0.52254141, 4.0121195};
  const std::vector<double> teta2 = {2.3428599, 3.0535127, 3.7417464, 4.4255457, 5.1086716,
                                     5.7983829, 0.21286893, 0.91658554, 1.6304135, 2.3428152};
  for (const auto& [file, expected] : {std::pair<std::string, double>{"case5_ellipse_published.yaml", 4.2014342906726944e-4},
                                       std::pair<std::string, double>{"case5_ellipse.yaml", 4.24395004645483e-4}}) {
    const auto b = Bind<M>(Tasks("../benchmarks/" + file));
    ASSERT_EQ(b.n, 10);
    PathEvaluator<M> eval(b);
    const auto p = eval.ParamsOf(x);
    typename PathEvaluator<M>::VecPhi phi;
    typename PathEvaluator<M>::Coeffs co;
    double error = 0;
    for (int i = 0; i < b.n; ++i) {
      ASSERT_TRUE(eval.PointAt(p, x[8] + teta2[static_cast<size_t>(i)], &phi, &co)) << file << " target " << i + 1;
      error += std::pow(co.r_P(0, b.point) - b.task.tx[static_cast<size_t>(i)], 2) +
               std::pow(co.r_P(1, b.point) - b.task.ty[static_cast<size_t>(i)], 2);
    }
    EXPECT_NEAR(error, expected, 1e-12) << file;
    const Candidate c = eval.Evaluate(x);
    EXPECT_TRUE(c.feasible()) << file << ": " << c.defect;
    EXPECT_LE(c.error, error * (1 + 1e-9)) << file;
  }
}

// Variable projection (synthesis/projection.h, issue 44). The reduced evaluation solves the
// placement, scale x rotation and coupler point by least squares in closed form; recomputed
// here by the generated model (PathEvaluator::Check at the full design it gives), its error
// and residuals agree to 1e-9, and its linear part is optimal: no move of the crank pivot, the
// coupler point, the scale (all four links at once) or the frame's angle (the inputs with it)
// lowers the generated model's error (central differences of the error vanish against its
// size; with a link at its bound, the scale's slope points outward). Case 3: prescribed timing
// from a free offset, all six linear unknowns free.
TEST(PathSynthesis, ProjectionSolvesTheLinearPartOfTheFullObjective) {
  using M = mech::synth_fourbar::Model;
  const auto b = Bind<M>(Tasks("../benchmarks/case3_closed18.yaml"));
  ASSERT_TRUE(b.task.search.projection);
  Projection pr;
  std::string error;
  ASSERT_TRUE(BindProjection(b, &pr, &error)) << error;
  EXPECT_EQ(pr.dim, 4);  // three log ratios and the offset
  ProjectedEvaluator<M> eval(b, pr);
  PathEvaluator<M> full(b);
  SplitMix64 rng(5);
  int checked = 0, bounded = 0;
  for (int k = 0; k < 400 && checked < 12; ++k) {
    std::vector<double> x(4);
    for (int j = 0; j < 4; ++j) x[static_cast<size_t>(j)] = pr.lo[static_cast<size_t>(j)] + rng.Uniform() * (pr.hi[static_cast<size_t>(j)] - pr.lo[static_cast<size_t>(j)]);
    const ProjectedCandidate c = eval.Evaluate(x);
    if (!c.feasible()) continue;
    ++checked;
    Candidate g = c.full;
    full.Check(full.ParamsOf(g.x), &g);
    ASSERT_TRUE(g.feasible()) << g.defect;
    EXPECT_NEAR(g.error, c.error, 1e-9 * (1 + c.error));
    for (int i = 0; i < b.n; ++i)
      EXPECT_NEAR(g.distance[static_cast<size_t>(i)],
                  std::hypot(c.residual[static_cast<size_t>(2 * i)], c.residual[static_cast<size_t>(2 * i + 1)]), 1e-9);
    // Stationary in the linear unknowns.
    const double h = 1e-5;
    auto moved = [&](int which, double by) {
      Candidate m = c.full;
      auto at = [&](const char* name) -> double& {
        for (size_t j = 0; j < b.task.variables.size(); ++j)
          if (b.task.variables[j].name == name) return m.x[j];
        throw std::runtime_error(name);
      };
      if (which == 0) at("x0") += by;
      if (which == 1) at("y0") += by;
      if (which == 2) at("xi") += by;
      if (which == 3) at("eta") += by;
      if (which == 4)
        for (const char* l : {"a", "b", "c", "d", "xi", "eta"}) at(l) *= 1 + by;  // the scale about A
      if (which == 5) {  // the rotation about A: the ground's angle and the inputs with it
        at("theta0") += by;
        for (double& q : m.q) q += by;
      }
      full.Check(full.ParamsOf(m.x), &m);
      return m.error;
    };
    // A link at its upper bound holds the scale there: moving out would lower the error (a
    // slope <= 0, Karush-Kuhn-Tucker), the other five stay stationary.
    bool at_bound = false;
    for (int j = 0; j < 4; ++j) at_bound = at_bound || c.full.x[static_cast<size_t>(j)] >= b.task.variables[static_cast<size_t>(j)].hi * (1 - 1e-12);
    bounded += at_bound;
    for (int w = 0; w < 6; ++w) {
      const double slope = (moved(w, h) - moved(w, -h)) / (2 * h), tol = 1e-5 * (1 + std::sqrt(c.error));
      if (w == 4 && at_bound) {
        EXPECT_LT(slope, tol) << "at draw " << k;
      } else {
        EXPECT_LT(std::abs(slope), tol) << "unknown " << w << " at draw " << k;
      }
    }
  }
  EXPECT_EQ(checked, 12);
  EXPECT_GT(bounded, 0);      // both kinds of draw were seen
  EXPECT_LT(bounded, checked);
}

// The projected search reaches issue 44's targets in a few seeds: case 2 (prescribed timing,
// the frame fixed) its minimum 7.4157e-7 (< 8e-7) every time; case 4 (the arc, crank shortest)
// below 1.2163 with Grashof met strictly by the lengths (hand: s + l < p + q) and the crank
// the shortest; case 1 (a line, free timing) an exact design (< 1e-20). Each result is the
// generated model's check (feasible, the continuation passed).
TEST(PathSynthesis, ProjectionReachesThePublishedRecords) {
  using M = mech::synth_fourbar::Model;
  for (int seed = 1; seed <= 3; ++seed) {
    SearchResult s;
    std::string error;
    ASSERT_TRUE(SynthesizePath(Bind<M>(Tasks("../benchmarks/case2_timed.yaml")), seed, 1, &s, &error)) << error;
    ASSERT_TRUE(s.best.best.feasible()) << s.best.best.defect;
    EXPECT_LT(s.best.best.error, 8e-7) << "seed " << seed;
    EXPECT_GT(s.best.best.error, 7.4e-7);  // the minimum (10 equations, 6 unknowns)
    EXPECT_LE(s.evaluations, 5000);
  }
  {
    const auto b = Bind<M>(Tasks("../benchmarks/case4_arc.yaml"));
    SearchResult s;
    std::string error;
    ASSERT_TRUE(SynthesizePath(b, 1, 1, &s, &error)) << error;
    const Candidate& c = s.best.best;
    ASSERT_TRUE(c.feasible()) << c.defect;
    PathEvaluator<M> eval(b);
    EXPECT_EQ(ContinuationCheck(&eval, c), "");
    EXPECT_LT(c.error, 1.2163);
    EXPECT_LE(s.evaluations, 50000);
    std::array<double, 4> len = {c.x[0], c.x[1], c.x[2], c.x[3]};  // a (crank), b, c, d
    EXPECT_LT(len[0], std::min({len[1], len[2], len[3]}));
    std::sort(len.begin(), len.end());
    EXPECT_LT(len[0] + len[3], len[1] + len[2]);
  }
  {
    SearchResult s;
    std::string error;
    ASSERT_TRUE(SynthesizePath(Bind<M>(Tasks("../benchmarks/case1_line.yaml")), 1, 1, &s, &error)) << error;
    ASSERT_TRUE(s.best.best.feasible()) << s.best.best.defect;
    EXPECT_LT(s.best.best.error, 1e-20);
    EXPECT_LE(s.evaluations, 100000);
  }
}

// A model that is not the four-bar of synth_fourbar's roles is refused at the task's place.
TEST(PathSynthesis, ProjectionNeedsTheFourBarsRoles) {
  const std::string path = ::testing::TempDir() + "/projection_task.yaml";
  std::ofstream(path) << "synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1], [2, 1]]\ntiming: free\n"
                         "variables: {a: [0, 5], b: [0, 5]}\nsearch:\n  projection: true\n";
  PathTask task;
  std::string error;
  ASSERT_TRUE(ParseTask(path, &task, &error)) << error;
  BoundPath<mech::fourbar::Model> b;
  ASSERT_TRUE(BindPathTask<mech::fourbar::Model>(task, {}, &b, &error)) << error;
  SearchResult s;
  EXPECT_FALSE(SynthesizePath(b, 1, 1, &s, &error));
  EXPECT_EQ(error.substr(error.find("projection_task.yaml")),
            "projection_task.yaml:7:15: error: projection: the model has no parameter 'x0'; it needs the four-bar's a, b, c, "
            "d, xi, eta, x0, y0, theta0 (tests/synthesis/models/synth_fourbar.yaml)");
}

// ---- The model view (issue 43): the synthesis layer instantiated once for ViewModel
// (synthesis/view_synthesis.h) against the same templates on the generated fixed-size
// synth_fourbar, one task of each kind the view runs, in one process: the same bytes (reports,
// written model files, SVG, CSV) and the same numbers to the bit (the view calls the same
// generated functions; Phi_phi's condition on a fixed-size copy,
// ConditionAndDeterminantDynamic). The oracle is the fixed-size instantiation, which the tests
// above check against hand formulas, central differences and PHCpack.

std::string ViewTaskFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A motion task through both instantiations: the same candidates and report, the same model
// file and report lines.
void ExpectViewMotionSame(const std::vector<double>& q, const std::string& extra) {
  using M = mech::synth_fourbar::Model;
  const mechgen::ViewModel view(mech::synth_fourbar::View());
  const HandFourBar f;
  std::string yaml = "synthesis: motion\npoint: coupler.P\ncoupler_angle: theta_coupler\nposes:\n";
  for (const Pose& p : PosesOf(f, q)) yaml += "  - [" + Num(p.x) + ", " + Num(p.y) + ", " + Num(p.angle) + "]\n";
  yaml += "parameters: {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}\n" +
          extra;
  MotionTask task;
  std::string error;
  ASSERT_TRUE(ParseMotionTask(ViewTaskFile("view_motion.yaml", yaml), &task, &error)) << error;
  MotionResult fixed, through_view;
  ASSERT_TRUE(SynthesizeMotion<M>(task, {}, &fixed, &error)) << error;
  ASSERT_TRUE(SynthesizeMotion(view, task, mechgen::ModelCalls<mechgen::ViewModel>::DefaultParams(view), &through_view,
                               &error))
      << error;
  ASSERT_GE(fixed.chosen, 0);
  EXPECT_EQ(fixed.chosen, through_view.chosen);
  EXPECT_EQ(fixed.evaluations, through_view.evaluations);
  EXPECT_EQ(MotionReport(task, fixed), MotionReport(task, through_view));
  // The written model file and its report lines.
  const FourBarFromDyads& fb = fixed.candidates[static_cast<size_t>(fixed.chosen)].fourbar;
  const double values[9] = {fb.a, fb.b, fb.c, fb.d, fb.xi, fb.eta, fb.x0, fb.y0, fb.theta0};
  M::ParamsT<double> p;
  mechgen::ViewParams vp = mechgen::ModelCalls<mechgen::ViewModel>::DefaultParams(view);
  for (size_t k = 0; k < 9; ++k) {
    *p.Find(task.parameters[k].c_str()) = values[k];
    *mechgen::ModelCalls<mechgen::ViewModel>::FindParameter(view, &vp, task.parameters[k].c_str()) = values[k];
  }
  mechgen::ModelCalls<mechgen::ViewModel>::ParametersSet(view, &vp);
  std::array<int, M::kNumBlocks> modes = M::kDefaultModes;
  modes[0] = fixed.candidates[static_cast<size_t>(fixed.chosen)].mode;
  mechgen::ModelCalls<mechgen::ViewModel>::Modes view_modes = mechgen::ModelCalls<mechgen::ViewModel>::DefaultModes(view);
  view_modes[0] = modes[0];
  const std::string model = ReadFile(Tasks("../models/synth_fourbar.yaml"));
  std::string text_fixed, text_view;
  WrittenAssembly w_fixed, w_view;
  ASSERT_TRUE(WriteSynthesizedModel<M>(model, p, task.parameters, MotionInputs(fb), &text_fixed, &w_fixed, &error, &modes))
      << error;
  ASSERT_TRUE(WriteSynthesizedModel(view, model, vp, task.parameters, MotionInputs(fb), &text_view, &w_view, &error,
                                    &view_modes))
      << error;
  EXPECT_EQ(text_fixed, text_view);
  EXPECT_EQ(WrittenModelText<M>(w_fixed, p), WrittenModelText(view, w_view, vp));
}

TEST(ViewSynthesis, MotionFiveAndSixPosesSameBytesAsTheFixedSizeModel) {
  // Five poses: the Burmester pairs; six: the least squares on the design derivatives.
  ExpectViewMotionSame({20 * kDeg, 60 * kDeg, 100 * kDeg, 150 * kDeg, 200 * kDeg}, "");
  ExpectViewMotionSame({20 * kDeg, 55 * kDeg, 95 * kDeg, 140 * kDeg, 185 * kDeg, 230 * kDeg},
                       "seed_poses: [1, 2, 4, 5, 6]\n");
}

TEST(ViewSynthesis, PathGenerationSameSearchSameBytesAsTheFixedSizeModel) {
  using M = mech::synth_fourbar::Model;
  const mechgen::ViewModel view(mech::synth_fourbar::View());
  PathTask task;
  std::string error;
  // The shipped four-bar's coupler points (free timing, its constraints), a small budget, 2 threads.
  ASSERT_TRUE(ParseTask(Tasks("fourbar_refind.yaml"), &task, &error)) << error;
  task.search.evaluations = 3000;
  BoundPath<M> b_fixed;
  BoundPath<mechgen::ViewModel> b_view;
  ASSERT_TRUE(BindPathTask<M>(task, {}, &b_fixed, &error)) << error;
  ASSERT_TRUE(BindPathTask(view, task, mechgen::ModelCalls<mechgen::ViewModel>::DefaultParams(view), &b_view, &error))
      << error;
  SearchResult s_fixed, s_view;
  ASSERT_TRUE(SynthesizePath(b_fixed, 7, 2, &s_fixed, &error)) << error;
  ASSERT_TRUE(SynthesizePath(b_view, 7, 2, &s_view, &error)) << error;
  const Candidate& c = s_fixed.best.best;
  ASSERT_TRUE(c.feasible()) << c.defect;
  EXPECT_EQ(c.x, s_view.best.best.x);  // to the bit
  EXPECT_EQ(c.q, s_view.best.best.q);
  EXPECT_EQ(c.error, s_view.best.best.error);
  EXPECT_EQ(s_fixed.evaluations, s_view.evaluations);
  PathEvaluator<M> e_fixed(b_fixed);
  PathEvaluator<mechgen::ViewModel> e_view(b_view);
  EXPECT_EQ(ContinuationCheck(&e_fixed, c), ContinuationCheck(&e_view, s_view.best.best));
  EXPECT_EQ(Report(&e_fixed, s_fixed, "", 7, 2, 0, 0, "synth_fourbar.yaml"),
            Report(&e_view, s_view, "", 7, 2, 0, 0, "synth_fourbar.yaml"));
  EXPECT_EQ(CurveSvg(&e_fixed, c), CurveSvg(&e_view, s_view.best.best));
  std::vector<std::string> names;
  for (const Variable& v : task.variables) names.push_back(v.name);
  const std::string model = ReadFile(Tasks("../models/synth_fourbar.yaml"));
  std::string text_fixed, text_view;
  WrittenAssembly w_fixed, w_view;
  ASSERT_TRUE(WriteSynthesizedModel<M>(model, e_fixed.ParamsOf(c.x), names, MotionInputs(b_fixed, c), &text_fixed,
                                       &w_fixed, &error))
      << error;
  ASSERT_TRUE(WriteSynthesizedModel(view, model, e_view.ParamsOf(s_view.best.best.x), names,
                                    MotionInputs(b_view, s_view.best.best), &text_view, &w_view, &error))
      << error;
  EXPECT_EQ(text_fixed, text_view);
}

TEST(ViewSynthesis, ExactSynthesisSameBytesAsTheFixedSizeModel) {
  using M = mech::synth_fourbar::Model;
  const mechgen::ViewModel view(mech::synth_fourbar::View());
  ExactTask task;
  std::string error;
  ASSERT_TRUE(ParseExactTask(Tasks("../benchmarks/problem7_exact.yaml"), &task, &error)) << error;
  BoundExact<M> b_fixed;
  BoundExact<mechgen::ViewModel> b_view;
  ASSERT_TRUE(BindExactTask<M>(task, {}, &b_fixed, &error)) << error;
  ASSERT_TRUE(BindExactTask(view, task, mechgen::ModelCalls<mechgen::ViewModel>::DefaultParams(view), &b_view, &error))
      << error;
  const std::string model = ReadFile(Tasks("../models/synth_fourbar.yaml"));
  std::vector<std::pair<std::string, std::string>> m_fixed, m_view;
  const ExactRun r_fixed = RunExactTask(b_fixed, model, "synth_fourbar", &m_fixed);
  const ExactRun r_view = RunExactTask(b_view, model, "synth_fourbar", &m_view);
  ASSERT_EQ(r_fixed.real, 15);
  EXPECT_EQ(ExactCsv(r_fixed, "synth_fourbar", "problem7_exact.yaml"), ExactCsv(r_view, "synth_fourbar", "problem7_exact.yaml"));
  EXPECT_EQ(m_fixed, m_view);
}


// The synthesis analysis (analysis/synthesize.h): Check(model, request) says what is wrong with
// a request in the words Run prints (hand-written below), the same for the fixed-size model and
// the view; Run through the view ends there with the exit status and writes nothing. A request
// that fits: Check says nothing.
TEST(ViewSynthesis, CheckSaysWhatRunRefusesTheSameForTheFixedSizeModelAndTheView) {
  using M = mech::synth_fourbar::Model;
  using mechgen::analysis::SynthesizeRequest;
  const mechgen::ViewModel view(mech::synth_fourbar::View());
  SynthesizeRequest good;
  good.task_path = Tasks("fourbar_refind.yaml");
  good.model_path = Tasks("../models/synth_fourbar.yaml");
  good.out_dir = ::testing::TempDir() + "/view_check_out";
  EXPECT_EQ(mechgen::analysis::Check(M(), good), "");
  EXPECT_EQ(mechgen::analysis::Check(view, good), "");
  struct Case {
    SynthesizeRequest request;
    std::string error;  // Check's text
    int status;         // Run's exit status
    std::string printed;  // Run's standard error
  };
  std::vector<Case> cases;
  {
    SynthesizeRequest r = good;
    r.model_path.clear();
    const std::string e = "--model: the model file is needed (run as `mechgen synthesize MODEL ...`)";
    cases.push_back({r, e, 2, "check: error: " + e + "\n"});
  }
  {
    SynthesizeRequest r = good;
    r.params.sets = {"a=oops"};
    const std::string e = "--set 'a=oops': bad value 'oops' for 'a': expected a finite number (an angle may end in deg)";
    cases.push_back({r, e, 2, "check: error: " + e + "\n"});
  }
  {
    SynthesizeRequest r = good;
    r.model_path = ::testing::TempDir() + "/no_such_dir/synth_fourbar.yaml";
    const std::string e = "cannot read the model file " + r.model_path;
    cases.push_back({r, e, 1, "check: error: " + e + "\n"});
  }
  {
    SynthesizeRequest r = good;
    r.task_path = ViewTaskFile("view_check_bad.yaml",
                               "synthesis: path\npoint: coupler.P\ntargets: [[0, 0], [1, 1]]\nvariables: {a: [2, 1]}\n");
    const std::string e = r.task_path + ":4:16: error: variable a: min must be below max";
    cases.push_back({r, e, 1, e + "\n"});
  }
  mechgen::analysis::SynthesizeOutputs outputs;
  outputs.tool = "check";
  for (const Case& c : cases) {
    EXPECT_EQ(mechgen::analysis::Check(M(), c.request), c.error);
    EXPECT_EQ(mechgen::analysis::Check(view, c.request), c.error);
    ::testing::internal::CaptureStderr();
    const int status = mechgen::analysis::Run(view, c.request, outputs);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), c.printed);
    EXPECT_EQ(status, c.status) << c.error;
    EXPECT_FALSE(std::ifstream(good.out_dir + "/report.txt").good()) << c.error;
  }
}

}  // namespace
