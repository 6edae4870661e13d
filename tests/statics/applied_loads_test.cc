// The applied loads and springs of the force diagram (EvalAppliedLoads, Model::AppliedLoads;
// drawn by statics/svg.h) against oracles that do not use the generator's statics:
//   - each load's point, vector or torque and each spring's ends and tension from the model's
//     numbers by the test's own geometry, at several crank angles: models/fourbar_loaded.yaml
//     (a coupler force at P, a rocker torque, a preloaded spring E-P) and the test model
//     models/sprung_slider_crank.yaml (a force in the rod's frame, a torque growing with the
//     crank angle drawn at the rod's first pin, a slider force, a torsional and a linear
//     spring); a spring's tension F0 + k (|r_b - r_a| - l0); fourbar_loaded's weights (gravity
//     [0, -g]): m g down at each link's hand centre of mass; the test model's weights where
//     its masses are (a link with point masses drawn mass by mass: the rod's own mass at its
//     middle and a lamp at C, a block alone on the massless slider);
//   - virtual work: the generated Q equals the work of the drawn loads, springs and weights
//     per unit of crank angle, their points and angles differenced over a small motion (the
//     spring by -tension dl/dq, the torsional spring by its torque times the crank's
//     rotation): the drawn set is complete;
//   - the SVG written by WriteStaticsSvg, parsed: at every snapshot (its q read from its
//     group) each load's and weight's arrow starts at its hand point (the picture's own pixel
//     mapping) and is its force long at the picture's force scale, the spring's zig-zag runs from E to P,
//     the torque's arc starts below D (the test model: the torsional spring's dashed arc turns
//     with its torque's sign); every label carries its magnitude and unit, and no two
//     labels of any snapshots overlap (boxes at 0.62 em a character, the placer's estimate).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fourbar_loaded.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/svg.h"
#include "mechgen/statics/sweep.h"
#include "sprung_slider_crank.h"
#include "statics_test_util.h"

namespace {

using mechtest::statics::IndexOf;
using mechtest::statics::kDeg;
using mechtest::statics::Near;

struct V2 {
  double x, y;
};
V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.y + b.y}; }
V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.y - b.y}; }
V2 operator*(double s, V2 a) { return {s * a.x, s * a.y}; }
double Norm(V2 a) { return std::hypot(a.x, a.y); }
V2 Rot(double t, V2 a) { return {std::cos(t) * a.x - std::sin(t) * a.y, std::sin(t) * a.x + std::cos(t) * a.y}; }

constexpr double kTol = 1e-12;  // the same formulas, rounded differently
constexpr double kH = 1e-6;     // central differences: truncation ~1e-12, rounding ~1e-10 relative
constexpr double kFdTol = 1e-7;

template <class M>
using Applied = Eigen::Matrix<double, 7, M::kNumAppliedLoads>;

template <class M>
bool At(const typename M::template ParamsT<double>& p, double q, Eigen::Matrix<double, M::kNphi, 1>* phi,
        Applied<M>* A) {
  if (!mechtest::statics::SolveAt<M>(p, q, phi)) return false;
  const Eigen::Matrix<double, M::kNq, 1> qv = Eigen::Matrix<double, M::kNq, 1>::Constant(q);
  M::AppliedLoads(p, qv, *phi, A);
  return true;
}

template <class M>
double GeneratedQ(const typename M::template ParamsT<double>& p, double q, const Eigen::Matrix<double, M::kNphi, 1>& phi) {
  const Eigen::Matrix<double, M::kNq, 1> qv = Eigen::Matrix<double, M::kNq, 1>::Constant(q);
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, qv, phi, &c);
  typename M::template StaticsT<double> st;
  M::Forces(p, qv, phi, c, &st);
  return st.Q(0);
}

// ---- models/fourbar_loaded.yaml ----
namespace fl = mech::fourbar_loaded;
using FL = fl::Model;

struct FourbarHand {
  V2 P, E, D;
  double theta_coupler;
};
FourbarHand Hand(const FL::ParamsT<double>& p, double q, const Eigen::Matrix<double, FL::kNphi, 1>& phi) {
  const double tc = phi(IndexOf(FL::kPhiNames, "theta_coupler"));
  const V2 B{p.a * std::cos(q), p.a * std::sin(q)};
  return {B + Rot(tc, {p.xi, p.eta}), {p.xE, p.yE}, {p.d, 0}, tc};
}

TEST(AppliedLoads, FourbarLoadedNamesKindsUnits) {
  // The loads, the spring, then the weights of the three moving links (gravity [0, -g]).
  ASSERT_EQ(FL::kNumAppliedLoads, 6);
  const char* names[] = {"coupler_force", "rocker_torque", "spring", "W_crank", "W_coupler", "W_rocker"};
  const int kinds[] = {0, 1, 2, 4, 4, 4};
  const char* units[] = {"N", "N m", "N", "N", "N", "N"};
  for (int i = 0; i < 6; ++i) {
    EXPECT_STREQ(FL::kAppliedLoadNames[i], names[i]);
    EXPECT_EQ(FL::kAppliedLoadKind[i], kinds[i]);
    EXPECT_STREQ(FL::kAppliedLoadUnits[i], units[i]);
  }
}

TEST(AppliedLoads, FourbarLoadedAgainstHandValues) {
  FL::ParamsT<double> p;
  int checked = 0;
  for (double deg = 0; deg < 360; deg += 15) {
    const double q = deg * kDeg;
    Eigen::Matrix<double, FL::kNphi, 1> phi;
    Applied<FL> A;
    ASSERT_TRUE(At<FL>(p, q, &phi, &A)) << deg;
    const FourbarHand h = Hand(p, q, phi);
    const std::string at = " at " + std::to_string(deg) + " deg";
    // The coupler force at P, in the fixed frame.
    EXPECT_TRUE(Near(A(0, 0), h.P.x, kTol, 1, "coupler_force x" + at));
    EXPECT_TRUE(Near(A(1, 0), h.P.y, kTol, 1, "coupler_force y" + at));
    EXPECT_TRUE(Near(A(2, 0), h.P.x, kTol, 1, "coupler_force x_b" + at));
    EXPECT_TRUE(Near(A(4, 0), p.Fx, kTol, p.Fx, "coupler_force F_x" + at));
    EXPECT_TRUE(Near(A(5, 0), p.Fy, kTol, p.Fy, "coupler_force F_y" + at));
    EXPECT_EQ(A(6, 0), 0.0);
    // The rocker torque at the rocker's ground pivot D.
    EXPECT_TRUE(Near(A(0, 1), h.D.x, kTol, 1, "rocker_torque x" + at));
    EXPECT_TRUE(Near(A(1, 1), h.D.y, kTol, 1, "rocker_torque y" + at));
    EXPECT_EQ(A(4, 1), 0.0);
    EXPECT_EQ(A(5, 1), 0.0);
    EXPECT_TRUE(Near(A(6, 1), p.Tr, kTol, p.Tr, "rocker_torque" + at));
    // The spring from E to P: tension F0 + k (|P - E| - L0), its force on E towards P.
    const double l = Norm(h.P - h.E), tension = p.F0 + p.k * (l - p.L0);
    const V2 on_E = (tension / l) * (h.P - h.E);
    EXPECT_TRUE(Near(A(0, 2), h.E.x, kTol, 1, "spring a x" + at));
    EXPECT_TRUE(Near(A(1, 2), h.E.y, kTol, 1, "spring a y" + at));
    EXPECT_TRUE(Near(A(2, 2), h.P.x, kTol, 1, "spring b x" + at));
    EXPECT_TRUE(Near(A(3, 2), h.P.y, kTol, 1, "spring b y" + at));
    EXPECT_TRUE(Near(A(6, 2), tension, kTol, tension, "spring tension" + at));
    EXPECT_TRUE(Near(A(4, 2), on_E.x, kTol, tension, "spring force on E, x" + at));
    EXPECT_TRUE(Near(A(5, 2), on_E.y, kTol, tension, "spring force on E, y" + at));
    ++checked;
  }
  EXPECT_EQ(checked, 24);
}

// The centres of mass of fourbar_loaded by hand (each at mid-length of its bar, models/
// fourbar_loaded.yaml): the crank's, the coupler's from B along BC, the rocker's from D along DC.
struct FourbarCentres {
  V2 G[3];
  double m[3];
};
FourbarCentres Centres(const FL::ParamsT<double>& p, double q, const Eigen::Matrix<double, FL::kNphi, 1>& phi) {
  const double tc = phi(IndexOf(FL::kPhiNames, "theta_coupler")), tr = phi(IndexOf(FL::kPhiNames, "theta_rocker"));
  const V2 B{p.a * std::cos(q), p.a * std::sin(q)}, D{p.d, 0};
  return {{(0.5 * p.a) * V2{std::cos(q), std::sin(q)}, B + (0.5 * p.b) * V2{std::cos(tc), std::sin(tc)},
           D + (0.5 * p.c) * V2{std::cos(tr), std::sin(tr)}},
          {p.m1, p.m2, p.m3}};
}

// Each weight: at its link's hand centre of mass, the force (0, -m g), the value m g.
TEST(AppliedLoads, FourbarLoadedWeightsAgainstHandValues) {
  FL::ParamsT<double> p;
  int checked = 0;
  for (double deg = 0; deg < 360; deg += 15) {
    const double q = deg * kDeg;
    Eigen::Matrix<double, FL::kNphi, 1> phi;
    Applied<FL> A;
    ASSERT_TRUE(At<FL>(p, q, &phi, &A)) << deg;
    const FourbarCentres c = Centres(p, q, phi);
    for (int b = 0; b < 3; ++b) {
      const int l = 3 + b;
      const double W = c.m[b] * p.g;
      const std::string at = std::string(" ") + FL::kAppliedLoadNames[l] + " at " + std::to_string(deg) + " deg";
      EXPECT_TRUE(Near(A(0, l), c.G[b].x, kTol, 10, "G x" + at));
      EXPECT_TRUE(Near(A(1, l), c.G[b].y, kTol, 10, "G y" + at));
      EXPECT_EQ(A(2, l), A(0, l)) << at;
      EXPECT_EQ(A(3, l), A(1, l)) << at;
      EXPECT_TRUE(Near(A(4, l), 0, kTol, W, "F_x" + at));
      EXPECT_TRUE(Near(A(5, l), -W, kTol, W, "F_y" + at));
      EXPECT_TRUE(Near(A(6, l), W, kTol, W, "|m g|" + at));
    }
    ++checked;
  }
  EXPECT_EQ(checked, 24);
}

// Q is the virtual work of everything the picture draws: the coupler force and the three
// weights (force times their drawn points' velocity coefficients), the rocker torque (times
// d theta_rocker/dq) and the spring (-tension dl/dq), all differenced from the drawn columns.
// An independent oracle that the drawn set is complete: without the weights the sum misses
// Q by their work.
TEST(AppliedLoads, FourbarLoadedQIsTheWorkOfAllDrawnLoads) {
  FL::ParamsT<double> p;
  const int i_rocker = IndexOf(FL::kPhiNames, "theta_rocker");
  ASSERT_GE(i_rocker, 0);
  int weights_matter = 0;
  for (double deg = 10; deg < 360; deg += 25) {
    const double q = deg * kDeg;
    Eigen::Matrix<double, FL::kNphi, 1> phi, phi_plus, phi_minus;
    Applied<FL> A, Ap, Am;
    ASSERT_TRUE(At<FL>(p, q, &phi, &A));
    ASSERT_TRUE(At<FL>(p, q + kH, &phi_plus, &Ap));
    ASSERT_TRUE(At<FL>(p, q - kH, &phi_minus, &Am));
    auto d = [&](int row, int col) { return (Ap(row, col) - Am(row, col)) / (2 * kH); };
    double loads = 0, weights = 0;
    for (int l = 0; l < FL::kNumAppliedLoads; ++l) {
      const double force_work = A(4, l) * d(0, l) + A(5, l) * d(1, l);
      switch (FL::kAppliedLoadKind[l]) {
        case 0:  // the coupler force
          loads += force_work;
          break;
        case 4:  // a weight
          weights += force_work;
          break;
        case 1:  // the rocker torque
          loads += A(6, l) * (phi_plus(i_rocker) - phi_minus(i_rocker)) / (2 * kH);
          break;
        case 2: {  // the spring
          auto length = [l](const Applied<FL>& X) { return std::hypot(X(2, l) - X(0, l), X(3, l) - X(1, l)); };
          loads += -A(6, l) * (length(Ap) - length(Am)) / (2 * kH);
          break;
        }
        default:
          ADD_FAILURE() << "kind " << FL::kAppliedLoadKind[l];
      }
    }
    const double Q = GeneratedQ<FL>(p, q, phi);
    EXPECT_TRUE(Near(Q, loads + weights, kFdTol, std::abs(Q) + 100, "Q at " + std::to_string(deg) + " deg"));
    if (std::abs(weights) > 1e-3 * (std::abs(Q) + 100)) ++weights_matter;
  }
  EXPECT_GE(weights_matter, 10);  // of 15 angles: the weights' work is not negligible
}

// ---- tests/statics/models/sprung_slider_crank.yaml ----
namespace ssc = mech::sprung_slider_crank;
using SC = ssc::Model;

TEST(AppliedLoads, SprungSliderCrankAgainstHandValues) {
  // The loads, the springs, then the weights: the rod's own and its lamp's apart (a link with
  // point masses is drawn mass by mass), the massless slider's block alone.
  ASSERT_EQ(SC::kNumAppliedLoads, 8);
  const char* names[] = {"rod_force", "rod_torque", "push", "twist", "pull", "W_rod", "W_rod_lamp", "W_slider_block"};
  const int kinds[] = {0, 1, 0, 3, 2, 4, 4, 4};
  const char* units[] = {"N", "N m", "N", "N m", "N", "N", "N", "N"};
  for (int i = 0; i < 8; ++i) {
    EXPECT_STREQ(SC::kAppliedLoadNames[i], names[i]);
    EXPECT_EQ(SC::kAppliedLoadKind[i], kinds[i]);
    EXPECT_STREQ(SC::kAppliedLoadUnits[i], units[i]);
  }
  SC::ParamsT<double> p;
  const int i_rod = IndexOf(SC::kPhiNames, "theta_rod"), i_s = IndexOf(SC::kPhiNames, "s_slide");
  ASSERT_GE(i_rod, 0);
  ASSERT_GE(i_s, 0);
  int checked = 0;
  for (double deg = 0; deg < 360; deg += 20) {
    const double q = deg * kDeg;
    Eigen::Matrix<double, SC::kNphi, 1> phi;
    Applied<SC> A;
    ASSERT_TRUE(At<SC>(p, q, &phi, &A)) << deg;
    const std::string at = " at " + std::to_string(deg) + " deg";
    const double tr = phi(i_rod);
    const V2 pA{p.a * std::cos(q), p.a * std::sin(q)}, pB{phi(i_s), 0}, pE{p.xE, p.yE};
    const V2 pC = pA + p.c * V2{std::cos(tr), std::sin(tr)};
    ASSERT_TRUE(Near(Norm(pB - pA), p.b, 1e-12, 1, "closure" + at));
    // The rod force: (Fu, Fn) in the rod's frame, at C.
    const V2 F = Rot(tr, {p.Fu, p.Fn});
    EXPECT_TRUE(Near(A(0, 0), pC.x, kTol, 1, "rod_force x" + at));
    EXPECT_TRUE(Near(A(1, 0), pC.y, kTol, 1, "rod_force y" + at));
    EXPECT_TRUE(Near(A(4, 0), F.x, kTol, 12, "rod_force F_x" + at));
    EXPECT_TRUE(Near(A(5, 0), F.y, kTol, 12, "rod_force F_y" + at));
    // The rod torque T1 q, at the rod's first pin A (it has no joint with the ground).
    EXPECT_TRUE(Near(A(0, 1), pA.x, kTol, 1, "rod_torque x" + at));
    EXPECT_TRUE(Near(A(1, 1), pA.y, kTol, 1, "rod_torque y" + at));
    EXPECT_TRUE(Near(A(6, 1), p.T1 * q, kTol, 10, "rod_torque" + at));
    // The push on the slider at B.
    EXPECT_TRUE(Near(A(0, 2), pB.x, kTol, 1, "push x" + at));
    EXPECT_TRUE(Near(A(4, 2), -p.P, kTol, p.P, "push F_x" + at));
    EXPECT_EQ(A(5, 2), 0.0);
    // The torsional spring at O: the torque on the crank (the joint's second link).
    EXPECT_TRUE(Near(A(0, 3), 0, kTol, 1, "twist x" + at));
    EXPECT_TRUE(Near(A(1, 3), 0, kTol, 1, "twist y" + at));
    EXPECT_TRUE(Near(A(6, 3), -p.kt * (q - p.theta0), kTol, 10, "twist torque" + at));
    // The linear spring from E to B.
    const double l = Norm(pB - pE), tension = p.F0 + p.k * (l - p.L0);
    const V2 on_E = (tension / l) * (pB - pE);
    EXPECT_TRUE(Near(A(0, 4), pE.x, kTol, 1, "pull a x" + at));
    EXPECT_TRUE(Near(A(1, 4), pE.y, kTol, 1, "pull a y" + at));
    EXPECT_TRUE(Near(A(2, 4), pB.x, kTol, 1, "pull b x" + at));
    EXPECT_TRUE(Near(A(3, 4), pB.y, kTol, 1, "pull b y" + at));
    EXPECT_TRUE(Near(A(6, 4), tension, kTol, tension, "pull tension" + at));
    EXPECT_TRUE(Near(A(4, 4), on_E.x, kTol, tension, "pull force on E, x" + at));
    EXPECT_TRUE(Near(A(5, 4), on_E.y, kTol, tension, "pull force on E, y" + at));
    // The weights, m g down: the rod's own at its middle, the lamp at C, the block at B.
    const V2 mid = pA + (p.b / 2) * V2{std::cos(tr), std::sin(tr)};
    const V2 where[] = {mid, pC, pB};
    const double mass[] = {p.m_rod, p.m_lamp, p.m_block};
    for (int w = 0; w < 3; ++w) {
      const int col = 5 + w;
      const std::string name = std::string(SC::kAppliedLoadNames[col]) + at;
      EXPECT_TRUE(Near(A(0, col), where[w].x, kTol, 1, name + " x"));
      EXPECT_TRUE(Near(A(1, col), where[w].y, kTol, 1, name + " y"));
      EXPECT_EQ(A(4, col), 0.0) << name;
      EXPECT_TRUE(Near(A(5, col), -mass[w] * p.g, kTol, mass[w] * p.g, name + " F_y"));
      EXPECT_TRUE(Near(A(6, col), mass[w] * p.g, kTol, mass[w] * p.g, name + " |m g|"));
    }
    ++checked;
  }
  EXPECT_EQ(checked, 18);
}

// Q is the virtual work of the drawn loads and springs per unit crank angle: each force
// times its point's velocity coefficient, each torque times its link's (the rod's angle and
// the crank's, q), the spring's tension times -dl/dq, all differenced from the drawn points.
TEST(AppliedLoads, SprungSliderCrankQIsTheWorkOfTheDrawnLoads) {
  SC::ParamsT<double> p;
  int weighty = 0;  // angles where the weights' work is not negligible
  const int i_rod = IndexOf(SC::kPhiNames, "theta_rod");
  for (double deg = 10; deg < 360; deg += 25) {
    const double q = deg * kDeg;
    Eigen::Matrix<double, SC::kNphi, 1> phi, phi_plus, phi_minus;
    Applied<SC> A, Ap, Am;
    ASSERT_TRUE(At<SC>(p, q, &phi, &A));
    ASSERT_TRUE(At<SC>(p, q + kH, &phi_plus, &Ap));
    ASSERT_TRUE(At<SC>(p, q - kH, &phi_minus, &Am));
    auto d = [&](int row, int col) { return (Ap(row, col) - Am(row, col)) / (2 * kH); };
    double work = 0;
    for (int l : {0, 2}) work += A(4, l) * d(0, l) + A(5, l) * d(1, l);  // the forces
    work += A(6, 1) * (phi_plus(i_rod) - phi_minus(i_rod)) / (2 * kH);  // the rod torque
    work += A(6, 3) * 1.0;                                              // the twist on the crank
    auto length = [](const Applied<SC>& X) { return std::hypot(X(2, 4) - X(0, 4), X(3, 4) - X(1, 4)); };
    work += -A(6, 4) * (length(Ap) - length(Am)) / (2 * kH);  // the spring pulls its ends together
    // The weights, each at its own point: the rod's and its lamp's drawn apart, the one
    // weight of the combined rod in Q.
    double weights = 0;
    for (int l = 5; l < 8; ++l) weights += A(4, l) * d(0, l) + A(5, l) * d(1, l);
    work += weights;
    const double Q = GeneratedQ<SC>(p, q, phi);
    EXPECT_TRUE(Near(Q, work, kFdTol, std::abs(Q) + 10, "Q at " + std::to_string(deg) + " deg"));
    if (std::abs(weights) > 0.1) ++weighty;
  }
  EXPECT_GE(weighty, 10);  // of 15 angles
}

// ---- the picture ----
double Attr(const std::string& element, const std::string& name) {
  const std::regex re(" " + name + "=\"([^\"]+)\"");
  std::smatch m;
  if (!std::regex_search(element, m, re)) {
    ADD_FAILURE() << "no " << name << " in " << element;
    return std::nan("");
  }
  return std::stod(m[1]);
}

TEST(AppliedLoads, FourbarLoadedForceDiagram) {
  using namespace mechgen;
  FL::ParamsT<double> p;
  position::PositionSolver<FL> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<statics::StaticsRecord<FL>> records;
  const ModelTypes<FL>::VecQ q0 = ModelTypes<FL>::VecQ::Constant(0.0);
  const ModelTypes<FL>::VecQ q1 = ModelTypes<FL>::VecQ::Constant(2 * M_PI);
  ASSERT_EQ(statics::StaticsSweep(statics::Options(), &solver, q0, q1, 72, &records), 0);
  std::ostringstream svg;
  SvgOptions options;
  options.snapshots = 6;
  options.animate = false;
  statics::WriteStaticsSvg(solver.params(), records, options, svg);
  const std::string text = svg.str();
  // The picture's mapping: pixel x = (x - x_min) scale, y = (y_max - y) scale + 30.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex("<svg [^>]*>")));
  const std::string root = m[0];
  const double x_min = Attr(root, "data-x-min"), y_max = Attr(root, "data-y-max"), scale = Attr(root, "data-scale");
  auto X = [&](double x) { return (x - x_min) * scale; };
  auto Y = [&](double y) { return (y_max - y) * scale + 30; };
  ASSERT_TRUE(std::regex_search(text, m, std::regex("<g id=\"reactions\" data-force-scale=\"([^\"]+)\">")));
  const double per_newton = std::stod(m[1]);  // pixels
  ASSERT_GT(per_newton, 0);
  EXPECT_NE(text.find("applied loads, springs and weights: forces as arrows at the force scale"), std::string::npos);
  EXPECT_NE(text.find("labels of all snapshots moved apart so that none overlap"), std::string::npos);
  const double px = 0.006;  // the 0.01 px rounding of the written coordinates
  EXPECT_NE(text.find("weights (W_ and the link's name): m g as arrows from the centres of mass"), std::string::npos);
  const std::regex group_re("<g class=\"snapshot\" data-q=\"([^\"]+)\">\n([\\s\\S]*?)\n</g>");
  int groups = 0;
  int weight_labels[3] = {0, 0, 0};  // snapshots whose weight label found room
  for (auto g = std::sregex_iterator(text.begin(), text.end(), group_re); g != std::sregex_iterator(); ++g) {
    ++groups;
    const double q = std::stod((*g)[1]);
    const std::string body = (*g)[2];
    Eigen::Matrix<double, FL::kNphi, 1> phi;
    ASSERT_TRUE(mechtest::statics::SolveAt<FL>(p, q, &phi));
    const FourbarHand h = Hand(p, q, phi);
    // The coupler force: from P, (Fx, Fy) at the force scale (y down in pixels).
    std::smatch e;
    ASSERT_TRUE(std::regex_search(body, e, std::regex("<line class=\"load\"[^>]*>"))) << body;
    const std::string load = e[0];
    EXPECT_NEAR(Attr(load, "x1"), X(h.P.x), px);
    EXPECT_NEAR(Attr(load, "y1"), Y(h.P.y), px);
    EXPECT_NEAR(Attr(load, "x2") - Attr(load, "x1"), per_newton * p.Fx, 2 * px);
    EXPECT_NEAR(Attr(load, "y2") - Attr(load, "y1"), -per_newton * p.Fy, 2 * px);
    char magnitude[64];
    std::snprintf(magnitude, sizeof(magnitude), "coupler_force %.4g N", std::hypot(p.Fx, p.Fy));
    // The spring: a zig-zag from E to P, labelled with its tension.
    ASSERT_TRUE(std::regex_search(body, e, std::regex("<polyline class=\"spring\"[^>]* points=\"([^\"]+)\"")));
    std::vector<double> xy;
    std::string points = e[1];
    for (char& ch : points)
      if (ch == ',') ch = ' ';
    std::istringstream in(points);
    for (double v; in >> v;) xy.push_back(v);
    ASSERT_GE(xy.size(), 8u);
    EXPECT_NEAR(xy[0], X(h.E.x), px);
    EXPECT_NEAR(xy[1], Y(h.E.y), px);
    EXPECT_NEAR(xy[xy.size() - 2], X(h.P.x), px);
    EXPECT_NEAR(xy[xy.size() - 1], Y(h.P.y), px);
    const double tension = p.F0 + p.k * (Norm(h.P - h.E) - p.L0);
    char spring[64];
    std::snprintf(spring, sizeof(spring), "spring %.4g N (tension)", tension);
    // The weights: from each link's hand centre of mass, m g straight down at the force scale.
    {
      const FourbarCentres c = Centres(p, q, phi);
      const std::regex weight_re("<line class=\"weight\"[^>]*>");
      std::vector<std::string> weights;
      for (auto w = std::sregex_iterator(body.begin(), body.end(), weight_re); w != std::sregex_iterator(); ++w)
        weights.push_back((*w)[0]);
      ASSERT_EQ(weights.size(), 3u) << body;
      for (int b = 0; b < 3; ++b) {
        EXPECT_NEAR(Attr(weights[b], "x1"), X(c.G[b].x), px);
        EXPECT_NEAR(Attr(weights[b], "y1"), Y(c.G[b].y), px);
        EXPECT_NEAR(Attr(weights[b], "x2"), Attr(weights[b], "x1"), px);
        EXPECT_NEAR(Attr(weights[b], "y2") - Attr(weights[b], "y1"), per_newton * c.m[b] * p.g, 2 * px);
        EXPECT_NEAR(Attr(weights[b], "data-value"), c.m[b] * p.g, 1e-12 * c.m[b] * p.g);
        char weight[64];
        std::snprintf(weight, sizeof(weight), "W_%s %.4g N", b == 0 ? "crank" : b == 1 ? "coupler" : "rocker",
                      c.m[b] * p.g);
        if (body.find(std::string(">") + weight + "<") != std::string::npos) ++weight_labels[b];
      }
    }
    // The rocker torque: an arc starting below D (16 px), counter-clockwise as drawn.
    ASSERT_TRUE(std::regex_search(body, e, std::regex("<path class=\"torque\"[^>]* d=\"M([^,]+),([^ ]+) A16,16 0 1 0 ")));
    EXPECT_NEAR(std::stod(e[1]), X(h.D.x), px);
    EXPECT_NEAR(std::stod(e[2]), Y(h.D.y) + 16, px);
    // Labels: the load's and the spring's unless left out for room (the legend says so);
    // the first snapshot places its labels before any other, so it has them all.
    if (groups == 1) {
      EXPECT_NE(body.find(magnitude), std::string::npos) << magnitude;
      EXPECT_NE(body.find(spring), std::string::npos) << spring;
      EXPECT_NE(body.find("rocker_torque 15 N m"), std::string::npos);
    }
  }
  EXPECT_EQ(groups, 6);
  for (int b = 0; b < 3; ++b) EXPECT_GE(weight_labels[b], 1) << "weight " << b << " never labelled";
  // No two labels overlap: their boxes at 0.62 em a character.
  struct Box {
    double x0, y0, x1, y1;
    std::string text;
  };
  std::vector<Box> boxes;
  const std::regex label_re("<text class=\"[a-z_]+\" x=\"([^\"]+)\" y=\"([^\"]+)\"[^>]* font-size=\"([^\"]+)\"[^>]*>([^<]*)</text>");
  for (auto t = std::sregex_iterator(text.begin(), text.end(), label_re); t != std::sregex_iterator(); ++t) {
    const double x = std::stod((*t)[1]), y = std::stod((*t)[2]), size = std::stod((*t)[3]);
    const std::string s = (*t)[4];
    boxes.push_back({x, y - size, x + 0.62 * size * static_cast<double>(s.size()), y + 0.25 * size, s});
  }
  EXPECT_GT(boxes.size(), 6u * 4u);  // at least the input, the load, the spring and the torque of each
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j) {
      const Box &a = boxes[i], &b = boxes[j];
      const bool apart = a.x1 <= b.x0 + 1e-9 || b.x1 <= a.x0 + 1e-9 || a.y1 <= b.y0 + 1e-9 || b.y1 <= a.y0 + 1e-9;
      EXPECT_TRUE(apart) << "'" << a.text << "' overlaps '" << b.text << "'";
    }
}

// The test model's picture: the torsional spring at O as a dashed arc whose direction is its
// torque's sign (-kt (q - theta0) on the crank), the rod torque T1 q as a solid arc at A where
// it is not zero, both loads' arrows (the rod force in the rod's frame) and the spring's
// zig-zag from E to B.
TEST(AppliedLoads, SprungSliderCrankForceDiagram) {
  using namespace mechgen;
  SC::ParamsT<double> p;
  position::PositionSolver<SC> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<statics::StaticsRecord<SC>> records;
  const ModelTypes<SC>::VecQ q0 = ModelTypes<SC>::VecQ::Constant(0.0);
  const ModelTypes<SC>::VecQ q1 = ModelTypes<SC>::VecQ::Constant(2 * M_PI);
  ASSERT_EQ(statics::StaticsSweep(statics::Options(), &solver, q0, q1, 72, &records), 0);
  std::ostringstream svg;
  SvgOptions options;
  options.snapshots = 4;
  options.animate = false;
  statics::WriteStaticsSvg(solver.params(), records, options, svg);
  const std::string text = svg.str();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex("<svg [^>]*>")));
  const std::string root = m[0];
  const double x_min = Attr(root, "data-x-min"), y_max = Attr(root, "data-y-max"), scale = Attr(root, "data-scale");
  auto X = [&](double x) { return (x - x_min) * scale; };
  auto Y = [&](double y) { return (y_max - y) * scale + 30; };
  ASSERT_TRUE(std::regex_search(text, m, std::regex("<g id=\"reactions\" data-force-scale=\"([^\"]+)\">")));
  const double per_newton = std::stod(m[1]);
  const double px = 0.006;
  const int i_rod = IndexOf(SC::kPhiNames, "theta_rod"), i_s = IndexOf(SC::kPhiNames, "s_slide");
  const std::regex group_re("<g class=\"snapshot\" data-q=\"([^\"]+)\">\n([\\s\\S]*?)\n</g>");
  int groups = 0, torques = 0;
  for (auto g = std::sregex_iterator(text.begin(), text.end(), group_re); g != std::sregex_iterator(); ++g) {
    ++groups;
    const double q = std::stod((*g)[1]);
    const std::string body = (*g)[2];
    Eigen::Matrix<double, SC::kNphi, 1> phi;
    ASSERT_TRUE(mechtest::statics::SolveAt<SC>(p, q, &phi));
    const double tr = phi(i_rod);
    const V2 pA{p.a * std::cos(q), p.a * std::sin(q)}, pB{phi(i_s), 0}, pE{p.xE, p.yE};
    const V2 pC = pA + p.c * V2{std::cos(tr), std::sin(tr)}, F = Rot(tr, {p.Fu, p.Fn});
    // The torsional spring: from below O, counter-clockwise (sweep 0) for a positive torque.
    const double twist = -p.kt * (q - p.theta0);
    std::smatch e;
    ASSERT_TRUE(std::regex_search(body, e, std::regex("<path class=\"torsion\" data-at=\"([^\"]+)\" data-value=\"([^\"]+)\" "
                                                      "d=\"M([^,]+),([^ ]+) A16,16 0 1 ([01]) [^\"]*\"[^>]*stroke-dasharray")))
        << body;
    EXPECT_NEAR(std::stod(e[2]), twist, 1e-12 * 10);
    EXPECT_NEAR(std::stod(e[3]), X(0), px);
    EXPECT_NEAR(std::stod(e[4]), Y(0) + 16, px);
    EXPECT_EQ(std::string(e[5]), twist > 0 ? "0" : "1");
    // The rod torque at A, where it is not zero.
    if (std::abs(p.T1 * q) > 1e-9) {
      ASSERT_TRUE(std::regex_search(body, e, std::regex("<path class=\"torque\"[^>]* d=\"M([^,]+),([^ ]+) A16,16 0 1 ([01]) ")));
      EXPECT_NEAR(std::stod(e[1]), X(pA.x), px);
      EXPECT_NEAR(std::stod(e[2]), Y(pA.y) + 16, px);
      EXPECT_EQ(std::string(e[3]), "0");  // T1 q > 0 on (0, 2 pi]
      ++torques;
    }
    // The two force loads: the rod force from C, the push from B.
    const std::regex load_re("<line class=\"load\"[^>]*>");
    std::vector<std::string> loads;
    for (auto l = std::sregex_iterator(body.begin(), body.end(), load_re); l != std::sregex_iterator(); ++l)
      loads.push_back((*l)[0]);
    ASSERT_EQ(loads.size(), 2u) << body;
    EXPECT_NEAR(Attr(loads[0], "x1"), X(pC.x), px);
    EXPECT_NEAR(Attr(loads[0], "y1"), Y(pC.y), px);
    EXPECT_NEAR(Attr(loads[0], "x2") - Attr(loads[0], "x1"), per_newton * F.x, 2 * px);
    EXPECT_NEAR(Attr(loads[0], "y2") - Attr(loads[0], "y1"), -per_newton * F.y, 2 * px);
    EXPECT_NEAR(Attr(loads[1], "x1"), X(pB.x), px);
    EXPECT_NEAR(Attr(loads[1], "x2") - Attr(loads[1], "x1"), -per_newton * p.P, 2 * px);
    EXPECT_NEAR(Attr(loads[1], "y2"), Attr(loads[1], "y1"), px);
    // The spring from E to B.
    ASSERT_TRUE(std::regex_search(body, e, std::regex("<polyline class=\"spring\"[^>]* data-value=\"([^\"]+)\"")));
    EXPECT_NEAR(std::stod(e[1]), p.F0 + p.k * (Norm(pB - pE) - p.L0), 1e-9);
    // The weights where their masses are: the rod's own at its middle, the lamp at C, the
    // block at B; m g down at the force scale.
    const V2 where[] = {pA + (p.b / 2) * V2{std::cos(tr), std::sin(tr)}, pC, pB};
    const double mass[] = {p.m_rod, p.m_lamp, p.m_block};
    const std::regex weight_re("<line class=\"weight\"[^>]*>");
    std::vector<std::string> weights;
    for (auto w = std::sregex_iterator(body.begin(), body.end(), weight_re); w != std::sregex_iterator(); ++w)
      weights.push_back((*w)[0]);
    ASSERT_EQ(weights.size(), 3u) << body;
    for (int w = 0; w < 3; ++w) {
      EXPECT_NEAR(Attr(weights[w], "x1"), X(where[w].x), px) << w;
      EXPECT_NEAR(Attr(weights[w], "y1"), Y(where[w].y), px) << w;
      EXPECT_NEAR(Attr(weights[w], "x2"), Attr(weights[w], "x1"), px) << w;
      EXPECT_NEAR(Attr(weights[w], "y2") - Attr(weights[w], "y1"), per_newton * mass[w] * p.g, 2 * px) << w;
      EXPECT_NEAR(Attr(weights[w], "data-value"), mass[w] * p.g, 1e-12 * mass[w] * p.g) << w;
    }
  }
  EXPECT_EQ(groups, 4);
  EXPECT_GE(torques, 3);
}

}  // namespace
