// Drivers that are not joint coordinates (issue 26), on the test model
// tests/kinematics/models/tool_point_drivers.yaml: a five-bar robot driven by its tool point's
// x and y (the motor angles become dependent coordinates through the driving constraints
// r_C(phi) - q = 0), an oscillating block driven by its pin's slide in the slot, and a
// crank-rocker four-bar driven by its coupler's absolute angle.
// Oracles, independent of the generator:
//  - the five-bar's closed-form inverse kinematics (each leg: the circle of its proximal link
//    about its motor meets the circle of its distal link about the tool), along a straight
//    line of the tool; K against central differences of it, L against central differences
//    of the generated K; the tool's K_P the identity;
//  - the force along x and y the tool needs to hold the bars' weights: the derivatives of
//    their potential energy, computed from the closed form, by central differences; the
//    pins' reactions: every bar's free body balances (forces and moments) with them, its
//    weight and, on dist1 at C, that force;
//  - the workspace boundary (a leg stretched, |AC| = a + b): the generated solve's branch
//    measure and det Phi_phi vanish there, beyond it no assembly; a sweep of the runtime along
//    a line that leaves the workspace stops there with kSingular;
//  - the slot driven by its slide s = |HP|: the crank angle from the triangle K P H (law of
//    cosines), the rocker's from the pin's position; K against central differences;
//  - the four-bar driven by its coupler's angle: the crank's from |C - N| = c (a circle about
//    the pivot M meets a circle about N shifted by the coupler), K against differences, the
//    couple on the coupler against the derivative of its potential, its bars' free bodies.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "tool_point_drivers.h"

namespace {

using M = mech::tool_point_drivers::Model;
using Status = mech::tool_point_drivers::SolveStatus;
constexpr int kNq = 4, kNphi = 8;
using VecQ = Eigen::Matrix<double, kNq, 1>;
using VecPhi = Eigen::Matrix<double, kNphi, 1>;
constexpr double kPi = 3.14159265358979323846;

double Wrap(double a) { return std::remainder(a, 2 * kPi); }

// The five-bar's phi (theta_prox1, theta_dist1, theta_dist2, theta_prox2) with its tool at
// (x, y): B left of A -> C, D right of E -> C (the model's working mode).
std::array<double, 4> FiveBarInverse(const M::ParamsT<double>& p, double x, double y) {
  const double a = p.a, b = p.b, f = p.f;
  const double d1 = std::hypot(x, y);
  const double prox1 = std::atan2(y, x) + std::acos((a * a + d1 * d1 - b * b) / (2 * a * d1));
  const double bx = a * std::cos(prox1), by = a * std::sin(prox1);
  const double d2 = std::hypot(x - f, y);
  const double prox2 = std::atan2(y, x - f) - std::acos((a * a + d2 * d2 - b * b) / (2 * a * d2));
  const double dx = f + a * std::cos(prox2), dy = a * std::sin(prox2);
  return {prox1, std::atan2(y - by, x - bx), std::atan2(y - dy, x - dx), prox2};
}

// The oscillating block's (theta_crank, theta_rocker) at slide s = |HP|: crank pivot K = (1, 0),
// rocker pivot H = (1 + h, 0), P above the ground line.
std::array<double, 2> SlotInverse(const M::ParamsT<double>& p, double s) {
  const double r = p.r, h = p.h;
  const double crank = std::acos((r * r + h * h - s * s) / (2 * r * h));
  const double px = 1 + r * std::cos(crank), py = r * std::sin(crank);
  return {crank, std::atan2(py, px - (1 + h))};
}

// The four-bar's (theta_crank4, theta_rocker4) with its coupler at angle t3: pivots M = (3, 0),
// N = (3.4, 0), crank 0.1, coupler 0.35, rocker 0.3; the crank on the side of the model's
// assembly (the root + acos).
std::array<double, 2> CouplerInverse(double t3) {
  const double a = 0.1, b = 0.35, c = 0.3, d = 0.4;
  const double wx = d - b * std::cos(t3), wy = -b * std::sin(t3), w = std::hypot(wx, wy);
  const double crank = std::atan2(wy, wx) + std::acos((a * a + w * w - c * c) / (2 * a * w));
  const double cx = 3 + a * std::cos(crank) + b * std::cos(t3), cy = a * std::sin(crank) + b * std::sin(t3);
  return {crank, std::atan2(cy, cx - 3.4)};
}

// The bars' potential energy in gravity g along -y (uniform bars, centres mid-length).
double Potential(const M::ParamsT<double>& p, double x, double y) {
  const std::array<double, 4> t = FiveBarInverse(p, x, y);
  const double a = p.a, b = p.b;
  const double y_prox1 = a / 2 * std::sin(t[0]), y_prox2 = a / 2 * std::sin(t[3]);
  const double y_dist1 = a * std::sin(t[0]) + b / 2 * std::sin(t[1]);
  const double y_dist2 = a * std::sin(t[3]) + b / 2 * std::sin(t[2]);
  return p.g * p.rho * (a * (y_prox1 + y_prox2) + b * (y_dist1 + y_dist2));
}

VecPhi Exact(const M::ParamsT<double>& p, const VecQ& q) {
  const std::array<double, 4> t = FiveBarInverse(p, q(0), q(1));
  const std::array<double, 2> s = SlotInverse(p, q(2));
  const std::array<double, 2> c = CouplerInverse(q(3));
  VecPhi phi;
  phi << t[0], t[1], t[2], t[3], s[0], s[1], c[0], c[1];
  return phi;
}

VecPhi AssemblyPhi() {
  VecPhi phi;
  for (int i = 0; i < kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  return phi;
}

// The inputs at fraction k / n of the default range (the tool on a straight line).
VecQ Along(int k, int n) {
  VecQ q;
  for (int j = 0; j < kNq; ++j) q(j) = M::kQMin[j] + (M::kQMax[j] - M::kQMin[j]) * k / n;
  return q;
}

// The tool at (x, y), the slide at 0.25, the coupler at 45 deg (or as given).
VecQ Q(double x, double y, double s = 0.25, double coupler = 45 * kPi / 180) {
  VecQ q;
  q << x, y, s, coupler;
  return q;
}

// Solves at q from the guess; fails the test unless the solve converges.
VecPhi Solved(const M::ParamsT<double>& p, const VecQ& q, VecPhi guess) {
  const auto report = M::Solve(p, q, &guess);
  EXPECT_EQ(report.status, Status::kConverged) << q.transpose();
  return guess;
}

// The generated statics (the driving forces, the reactions) at a solved configuration.
M::StaticsT<double> StaticsAt(const M::ParamsT<double>& p, const VecQ& q, const VecPhi& phi) {
  M::CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  M::StaticsT<double> s;
  M::Forces(p, q, phi, c, &s);
  return s;
}

TEST(Drivers, FiveBarToolAlongALineIsTheClosedFormInverseKinematics) {
  const M::ParamsT<double> p;
  ASSERT_STREQ(M::kQNames[0], "x_dist1_C");
  ASSERT_STREQ(M::kQNames[1], "y_dist1_C");
  ASSERT_STREQ(M::kQNames[2], "s_slot");
  ASSERT_STREQ(M::kQNames[3], "theta_coupler4");
  ASSERT_STREQ(M::kPhiNames[6], "theta_crank4");
  ASSERT_STREQ(M::kPhiNames[0], "theta_prox1");
  ASSERT_STREQ(M::kPhiNames[3], "theta_prox2");
  ASSERT_STREQ(M::kPointNames[0], "dist1.C");
  ASSERT_STREQ(M::kPointNames[1], "dist2.C");
  const int kSamples = 200;
  VecPhi phi = AssemblyPhi();
  for (int k = 0; k <= kSamples; ++k) {
    // The default range: the straight line of the tool from (-0.1, 0.25) to (0.3, 0.35), the
    // slide from 0.17 to 0.33 and the coupler from 40 to 55 deg at the same time.
    const VecQ q = Along(k, kSamples);
    phi = Solved(p, q, phi);
    const VecPhi exact = Exact(p, q);
    for (int i = 0; i < kNphi; ++i) EXPECT_NEAR(Wrap(phi(i) - exact(i)), 0, 1e-12) << i << " at " << q.transpose();

    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    // The tool is where it is driven, on both legs; its K_P the identity in (x, y).
    for (int point = 0; point < 2; ++point) {
      EXPECT_NEAR(c.r_P(0, point), q(0), 1e-12);
      EXPECT_NEAR(c.r_P(1, point), q(1), 1e-12);
      for (int a = 0; a < 2; ++a)
        for (int j = 0; j < kNq; ++j) EXPECT_NEAR(c.K_P(2 * point + a, j), a == j ? 1.0 : 0.0, 1e-12);
    }
    // K against central differences of the closed form (error ~ h^2 |phi'''| + eps/h).
    const double h = 1e-5;
    for (int j = 0; j < kNq; ++j) {
      VecQ plus = q, minus = q;
      plus(j) += h;
      minus(j) -= h;
      const VecPhi dp = Exact(p, plus), dm = Exact(p, minus);
      for (int i = 0; i < kNphi; ++i) {
        const double fd = Wrap(dp(i) - dm(i)) / (2 * h);
        EXPECT_NEAR(c.K(i, j), fd, 1e-7 * (1 + std::abs(fd))) << "K(" << i << ", " << j << ") at " << q.transpose();
      }
      // L(i, l + kNq j) = d K(i, l) / d q_j against central differences of the generated K.
      M::CoefficientsT<double> cp, cm;
      M::Coeffs(p, plus, Solved(p, plus, phi), &cp);
      M::Coeffs(p, minus, Solved(p, minus, phi), &cm);
      for (int i = 0; i < kNphi; ++i)
        for (int l = 0; l < kNq; ++l) {
          const double fd = (cp.K(i, l) - cm.K(i, l)) / (2 * h);
          EXPECT_NEAR(c.L(i, l + kNq * j), fd, 1e-6 * (1 + std::abs(fd))) << "L(" << i << ", " << l << ", " << j << ")";
        }
    }
  }
}

TEST(Drivers, ForceAtTheToolIsTheDerivativeOfThePotential) {
  const M::ParamsT<double> p;
  VecPhi phi = AssemblyPhi();
  for (int k = 0; k <= 20; ++k) {
    const VecQ q = Along(k, 20);
    phi = Solved(p, q, phi);
    const M::StaticsT<double> s = StaticsAt(p, q, phi);
    // The force along x (along y) that holds the bars: dV/dx (dV/dy); nothing along the
    // massless block's slot.
    const double h = 1e-5;
    const double fx = (Potential(p, q(0) + h, q(1)) - Potential(p, q(0) - h, q(1))) / (2 * h);
    const double fy = (Potential(p, q(0), q(1) + h) - Potential(p, q(0), q(1) - h)) / (2 * h);
    EXPECT_NEAR(s.drive(0), fx, 1e-7 * (1 + std::abs(fx))) << q.transpose();
    EXPECT_NEAR(s.drive(1), fy, 1e-7 * (1 + std::abs(fy))) << q.transpose();
    EXPECT_NEAR(s.drive(2), 0, 1e-12);
    // The couple on the four-bar's coupler that holds its weight: dV/dtheta_coupler4, V = m4 g
    // y_G, y_G = 0.1 sin(theta_crank4) + 0.175 sin(theta_coupler4).
    auto v4 = [&](double t3) { return p.m4 * p.g * (0.1 * std::sin(CouplerInverse(t3)[0]) + 0.175 * std::sin(t3)); };
    const double couple = (v4(q(3) + h) - v4(q(3) - h)) / (2 * h);
    EXPECT_NEAR(s.drive(3), couple, 1e-7 * (1 + std::abs(couple))) << q.transpose();
    EXPECT_GT(std::abs(couple), 0.01);
    for (int j = 0; j < kNq; ++j) EXPECT_EQ(s.drive(j), -s.Q(j));
    // The weights pull the tool down: it must be held up.
    EXPECT_GT(s.drive(1), 0.5 * p.g * p.rho * (p.a + p.b));
  }
}

double Cross(const Eigen::Vector2d& r, const Eigen::Vector2d& f) { return r(0) * f(1) - r(1) * f(0); }

TEST(Drivers, ReactionsBalanceEveryLinkWithTheForceAtTheTool) {
  // Free bodies of the four bars: the weights at their centres, the pins' forces (F_J: of
  // J's first link on its second), and on dist1 at C the actuator's force (drive(0), drive(1)).
  // The same for the four-bar, with the couple drive(3) on its coupler.
  ASSERT_EQ(M::kNumReactions, 18);
  const char* names[] = {"F_A_x", "F_A_y", "F_B_x", "F_B_y", "F_C_x", "F_C_y", "F_D_x", "F_D_y", "F_E_x", "F_E_y",
                         "F_M_x", "F_M_y", "F_B4_x", "F_B4_y", "F_C4_x", "F_C4_y", "F_N_x", "F_N_y"};
  for (int i = 0; i < 18; ++i) ASSERT_STREQ(M::kReactionNames[i], names[i]);
  const M::ParamsT<double> p;
  VecPhi phi = AssemblyPhi();
  for (int k = 0; k <= 20; ++k) {
    const VecQ q = Along(k, 20);
    phi = Solved(p, q, phi);
    const M::StaticsT<double> s = StaticsAt(p, q, phi);
    const std::array<double, 4> t = FiveBarInverse(p, q(0), q(1));
    const Eigen::Vector2d A(0, 0), E(p.f, 0), C(q(0), q(1));
    const Eigen::Vector2d B(p.a * std::cos(t[0]), p.a * std::sin(t[0]));
    const Eigen::Vector2d D = E + Eigen::Vector2d(p.a * std::cos(t[3]), p.a * std::sin(t[3]));
    const Eigen::Vector2d w_prox(0, -p.rho * p.a * p.g), w_dist(0, -p.rho * p.b * p.g);
    const Eigen::Vector2d F_A(s.R(0), s.R(1)), F_B(s.R(2), s.R(3)), F_C(s.R(4), s.R(5)), F_D(s.R(6), s.R(7)),
        F_E(s.R(8), s.R(9)), drive(s.drive(0), s.drive(1));
    struct Body {
      const char* link;
      Eigen::Vector2d force;
      double moment;  // about the origin
    };
    const std::array<double, 2> t4 = CouplerInverse(q(3));
    const Eigen::Vector2d Mp(3, 0), Np(3.4, 0), B4 = Mp + 0.1 * Eigen::Vector2d(std::cos(t4[0]), std::sin(t4[0]));
    const Eigen::Vector2d C4 = B4 + 0.35 * Eigen::Vector2d(std::cos(q(3)), std::sin(q(3)));
    const Eigen::Vector2d w4(0, -p.m4 * p.g), F_M(s.R(10), s.R(11)), F_B4(s.R(12), s.R(13)), F_C4(s.R(14), s.R(15)),
        F_N(s.R(16), s.R(17));
    const Body bodies[] = {
        {"crank4", F_M - F_B4, Cross(Mp, F_M) - Cross(B4, F_B4)},
        {"coupler4", F_B4 - F_C4 + w4, Cross(B4, F_B4) - Cross(C4, F_C4) + Cross((B4 + C4) / 2, w4) + s.drive(3)},
        {"rocker4", F_C4 - F_N, Cross(C4, F_C4) - Cross(Np, F_N)},
        {"prox1", F_A - F_B + w_prox, Cross(A, F_A) - Cross(B, F_B) + Cross((A + B) / 2, w_prox)},
        {"dist1", F_B - F_C + w_dist + drive,
         Cross(B, F_B) - Cross(C, F_C) + Cross((B + C) / 2, w_dist) + Cross(C, drive)},
        {"dist2", F_C - F_D + w_dist, Cross(C, F_C) - Cross(D, F_D) + Cross((D + C) / 2, w_dist)},
        {"prox2", F_D - F_E + w_prox, Cross(D, F_D) - Cross(E, F_E) + Cross((E + D) / 2, w_prox)},
    };
    for (const Body& b : bodies) {
      EXPECT_NEAR(b.force(0), 0, 1e-10) << b.link << " at " << q.transpose();
      EXPECT_NEAR(b.force(1), 0, 1e-10) << b.link << " at " << q.transpose();
      EXPECT_NEAR(b.moment, 0, 1e-10) << b.link << " at " << q.transpose();
    }
    // Not all zero: the ground carries the weights less what the tool's actuator holds.
    EXPECT_NEAR(F_A(1) - F_E(1) + drive(1), 2 * p.rho * p.g * (p.a + p.b), 1e-10);
    EXPECT_NEAR(F_M(1) - F_N(1), p.m4 * p.g, 1e-10);
  }
}

TEST(Drivers, FiveBarWorkspaceBoundaryIsSingular) {
  const M::ParamsT<double> p;
  const double reach = p.a + p.b;  // the left leg stretched: B on A -> C
  const double dir = 70 * kPi / 180;
  VecPhi phi = AssemblyPhi();
  phi = Solved(p, Q(-0.1, 0.25), phi);
  auto at = [&](double radius) { return Q(radius * std::cos(dir), radius * std::sin(dir)); };
  // Inside: regular, and det Phi_phi is the product of the three dyads' (|a x b|), of which the
  // left leg's a b sin(theta_dist1 - theta_prox1) goes to 0 as the leg stretches.
  double det_inside = 0;
  VecPhi inside = phi;
  for (double radius : {0.45, 0.54, 0.549}) {
    inside = Solved(p, at(radius), inside);
    M::DetPhiPhi(p, at(radius), inside, &det_inside);
    const double leg = p.a * p.b * std::sin(inside(1) - inside(0));
    EXPECT_GT(std::abs(leg), 1e-3) << radius;
  }
  // On the boundary: the two modes of the left leg meet (branch measure 0), det Phi_phi 0.
  VecPhi edge = inside;
  const auto report = M::Solve(p, at(reach), &edge);
  ASSERT_EQ(report.status, Status::kConverged);
  EXPECT_EQ(report.branch_block, 0);
  EXPECT_LT(report.branch_measure, 1e-12);
  double det_edge = 1;
  M::DetPhiPhi(p, at(reach), edge, &det_edge);
  EXPECT_LT(std::abs(det_edge), 1e-6 * std::abs(det_inside));
  EXPECT_NEAR(Wrap(edge(0) - dir), 0, 1e-6);  // prox1 and dist1 along A -> C
  EXPECT_NEAR(Wrap(edge(1) - dir), 0, 1e-6);
  // Beyond: the left leg's dyad has no real solution.
  VecPhi beyond = inside;
  const auto out = M::Solve(p, at(reach + 1e-3), &beyond);
  EXPECT_EQ(out.status, Status::kNotAssemblable);
  EXPECT_EQ(out.block, 0);
}

TEST(Drivers, SweepAlongALineStopsSingularAtTheWorkspaceBoundary) {
  mechgen::position::PositionSolver<M> solver;
  mechgen::position::Summary summary;
  ASSERT_EQ(solver.AssembleDefault(&summary), mechgen::position::Status::kConverged);
  const M::ParamsT<double> p;
  // y = 0.3: the left leg reaches x = sqrt((a + b)^2 - 0.09).
  const double x_edge = std::sqrt(std::pow(p.a + p.b, 2) - 0.09);
  std::vector<mechgen::SweepRecord<M>> records;
  const int steps = 100;
  mechgen::Sweep(&solver, Q(0.1, 0.3), Q(0.6, 0.3), steps, Q(1, 0, 0, 0), Q(0, 0, 0, 0), &records);
  ASSERT_EQ(static_cast<int>(records.size()), steps + 1);
  int stop = -1;
  for (int i = 0; i <= steps && stop < 0; ++i) {
    const auto& r = records[i];
    if (r.summary.status == mechgen::position::Status::kSingular) {
      stop = i;
      break;
    }
    ASSERT_EQ(r.summary.status, mechgen::position::Status::kConverged) << i;
    EXPECT_LT(r.q(0), x_edge);
    const VecPhi exact = Exact(p, r.q);
    for (int c = 0; c < kNphi; ++c) EXPECT_NEAR(Wrap(r.state.phi(c) - exact(c)), 0, 1e-9) << i;
  }
  // The row whose input is the first beyond the edge stops there, at its last valid
  // configuration just before the edge; the rest are not run.
  const int first_beyond = static_cast<int>(std::ceil((x_edge - 0.1) / 0.5 * steps));
  ASSERT_EQ(stop, first_beyond);
  EXPECT_TRUE(records[stop].state.valid);
  EXPECT_LT(records[stop].state.q(0), x_edge);
  EXPECT_GT(records[stop].state.q(0), x_edge - 1e-3);
  for (int i = stop + 1; i <= steps; ++i) EXPECT_EQ(records[i].summary.status, mechgen::position::Status::kNotRun);
}

TEST(Drivers, SlotDrivenByItsSlideIsTheTriangle) {
  const M::ParamsT<double> p;
  VecPhi phi = AssemblyPhi();
  const VecQ base = Q(0.1, 0.3);
  for (int k = 0; k <= 160; ++k) {
    VecQ q = base;
    q(2) = 0.17 + 0.16 * k / 160;
    phi = Solved(p, q, phi);
    const std::array<double, 2> exact = SlotInverse(p, q(2));
    EXPECT_NEAR(Wrap(phi(4) - exact[0]), 0, 1e-12) << q(2);
    EXPECT_NEAR(Wrap(phi(5) - exact[1]), 0, 1e-12) << q(2);
    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    // The pin P (point 2) is s from the rocker's pivot H along the rocker.
    const double px = c.r_P(0, 2), py = c.r_P(1, 2);
    EXPECT_NEAR(std::hypot(px - (1 + p.h), py), q(2), 1e-12);
    EXPECT_NEAR(std::hypot(px - 1, py), p.r, 1e-12);
    const double h = 1e-6;
    const std::array<double, 2> plus = SlotInverse(p, q(2) + h), minus = SlotInverse(p, q(2) - h);
    for (int i = 0; i < 2; ++i) {
      const double fd = Wrap(plus[i] - minus[i]) / (2 * h);
      EXPECT_NEAR(c.K(4 + i, 2), fd, 1e-7 * (1 + std::abs(fd))) << q(2);
      EXPECT_EQ(c.K(4 + i, 0), 0.0);
      EXPECT_EQ(c.K(4 + i, 1), 0.0);
      EXPECT_EQ(c.K(4 + i, 3), 0.0);
    }
  }
}

}  // namespace
