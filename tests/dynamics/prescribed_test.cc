// Motion generators (Paul §8.4.4; mechgen/dynamics/prescribed.h) against independent oracles:
//  - the motion laws against their closed forms and finite differences;
//  - one-DOF results recovered: the two-input five-bar (fivebar_massive) with crank2 held by a
//    driver moves like the one-DOF four-bar of the same geometry with D a ground pivot
//    (fivebar_locked_fourbar, another model, simulated by MinimalDynamics), and the holding
//    torque equals the moment about E of the four-bar's reaction at D (its generated
//    kinetostatics with inertia forces) and of crank2's weight, by hand;
//  - with a moving driver, the work balance: T + V - W_act = E0, W_act the integrated power
//    lambda . qd_p of the actuator (and with dampers W_nc too);
//  - the five-bar robot: inverse dynamics of a commanded tool-point trajectory (the
//    coordinates by a hand inverse kinematics) equals the generated kinetostatics' drive,
//    its actuator work equals the change of potential energy, and forward dynamics under those
//    torques reproduces the trajectory;
//  - the robot's inertia matrix M(q) against finite differences of the kinetic energy of a
//    hand forward kinematics, symmetric and positive definite over the workspace;
//  - a commanded motion through a singular configuration (the distal links stretched): the
//    run stops before it with Status::kDeadPoint and the figures, at the time a hand
//    computation of the stretched configuration gives.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "damped_fourbar.h"
#include "fivebar_locked_fourbar.h"
#include "fivebar_massive.h"
#include "fivebar_robot.h"
#include "fivebar_spring_damper.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/prescribed.h"

namespace {

namespace dyn = mechgen::dynamics;
using dyn::ConstantSpeedLaw;
using dyn::Dop853;
using dyn::MakeDrive;
using dyn::MotionState;
using dyn::PrescribedDynamics;
using dyn::PrescribedOptions;
using dyn::PrescribedSummary;
using dyn::RestToRestLaw;
using dyn::SplineLaw;
using dyn::Status;
using V1 = Eigen::Matrix<double, 1, 1>;
using V2 = Eigen::Vector2d;
using V0 = Eigen::Matrix<double, 0, 1>;
constexpr double kPi = 3.14159265358979323846;

double Cross(const V2& a, const V2& b) { return a.x() * b.y() - a.y() * b.x(); }

// ---------------------------------------------------------------- motion laws

TEST(Prescribed, ClampedSplineReproducesACubicWithRestEnds) {
  // q = 3 t^2 - 2 t^3 has q'(0) = q'(1) = 0: the clamped spline through its samples is itself.
  const std::array<double, 6> t{0.0, 0.15, 0.4, 0.5, 0.8, 1.0};
  std::array<double, 6> q{};
  for (int i = 0; i < 6; ++i) q[i] = 3 * t[i] * t[i] - 2 * t[i] * t[i] * t[i];
  const SplineLaw<6> law(t, q);
  ASSERT_TRUE(law.IsValid());
  for (double s : {0.0, 0.07, 0.33, 0.4, 0.61, 0.95, 1.0}) {
    const MotionState m = law(s);
    EXPECT_NEAR(m.q, 3 * s * s - 2 * s * s * s, 1e-13) << s;
    EXPECT_NEAR(m.qd, 6 * s - 6 * s * s, 1e-12) << s;
    EXPECT_NEAR(m.qdd, 6 - 12 * s, 1e-11) << s;
  }
  // At rest beyond the ends.
  EXPECT_NEAR(law(1.5).q, 1.0, 1e-14);
  EXPECT_NEAR(law(1.5).qd, 0.0, 1e-12);
  EXPECT_NEAR(law(-1.0).q, 0.0, 1e-14);
  // A natural spline through a straight line is the line (and continues it outside).
  const SplineLaw<4> line({0.0, 1.0, 1.5, 3.0}, {2.0, 5.0, 6.5, 11.0}, SplineLaw<4>::Ends::kNatural);
  for (double s : {-0.5, 0.3, 1.2, 2.9, 4.0}) {
    EXPECT_NEAR(line(s).q, 2 + 3 * s, 1e-12);
    EXPECT_NEAR(line(s).qd, 3.0, 1e-12);
    EXPECT_NEAR(line(s).qdd, 0.0, 1e-12);
  }
  EXPECT_FALSE(SplineLaw<3>({0.0, 1.0, 1.0}, {0.0, 1.0, 2.0}).IsValid());
}

TEST(Prescribed, TableLawIsTheClampedCubicOfItsRows) {
  // The run-time sized table (the simulate command's table:FILE) through samples of the same
  // cubic q = 3 t^2 - 2 t^3 (rest at both ends): the cubic itself, and the AnyDrive that carries
  // it hands out the same values.
  std::vector<double> t{0.0, 0.2, 0.45, 0.7, 1.0}, q;
  for (double s : t) q.push_back(3 * s * s - 2 * s * s * s);
  const mechgen::dynamics::TableLaw law(t, q);
  ASSERT_TRUE(law.IsValid());
  const mechgen::dynamics::AnyDrive<1> drive({mechgen::dynamics::AnyLaw(law)});
  for (double s : {0.0, 0.1, 0.45, 0.52, 0.99, 1.0}) {
    EXPECT_NEAR(law(s).q, 3 * s * s - 2 * s * s * s, 1e-13) << s;
    EXPECT_NEAR(law(s).qd, 6 * s - 6 * s * s, 1e-12) << s;
    EXPECT_NEAR(law(s).qdd, 6 - 12 * s, 1e-11) << s;
    Eigen::Matrix<double, 1, 1> qp, qdp, qddp;
    drive(s, &qp, &qdp, &qddp);
    EXPECT_EQ(qp(0), law(s).q);
    EXPECT_EQ(qddp(0), law(s).qdd);
  }
  // Refused tables: one row, repeated times, a value that is not finite, unequal lengths.
  using mechgen::dynamics::TableLaw;
  EXPECT_FALSE(TableLaw({0.0}, {1.0}).IsValid());
  EXPECT_FALSE(TableLaw({0.0, 1.0, 1.0}, {0.0, 1.0, 2.0}).IsValid());
  EXPECT_FALSE(TableLaw({0.0, 1.0}, {0.0, std::nan("")}).IsValid());
  EXPECT_FALSE(TableLaw({0.0, 1.0, 2.0}, {0.0, 1.0}).IsValid());
  EXPECT_EQ(TableLaw({0.0}, {1.0})(0.5).q, 1.0);
}

TEST(Prescribed, RestToRestLawsAgainstFiniteDifferences) {
  for (auto profile : {RestToRestLaw::Profile::kPoly345, RestToRestLaw::Profile::kCycloidal}) {
    const RestToRestLaw law{0.3, 1.7, 0.5, 1.3, profile};
    EXPECT_EQ(law(0.2).q, 0.3);
    EXPECT_EQ(law(2.0).q, 1.7);
    EXPECT_NEAR(law(0.9).q, 1.0, 1e-15);  // odd symmetry about the midpoint
    const double h = 1e-4;
    for (double t : {0.55, 0.7, 0.9, 1.1, 1.29}) {
      const double fd1 = (law(t + h).q - law(t - h).q) / (2 * h);
      const double fd2 = (law(t + h).q - 2 * law(t).q + law(t - h).q) / (h * h);
      EXPECT_NEAR(law(t).qd, fd1, 1e-6) << t;
      EXPECT_NEAR(law(t).qdd, fd2, 1e-4) << t;
    }
    EXPECT_NEAR(law(0.5 + 1e-9).qdd, 0.0, 1e-6);  // acceleration continuous at the ends
    EXPECT_NEAR(law(1.3 - 1e-9).qd, 0.0, 1e-6);
  }
}

// ---------------------------------------------------------------- one DOF recovered

TEST(Prescribed, FivebarWithCrank2HeldMovesLikeTheFourbar) {
  using FB = mech::fivebar_massive::Model;
  using L4 = mech::fivebar_locked_fourbar::Model;
  const double th4 = kPi / 2;  // the locked pivot D = (2, 1) of fivebar_locked_fourbar.yaml
  auto drive = MakeDrive(ConstantSpeedLaw{th4, 0.0, 0.0});
  PrescribedOptions o;
  o.integrator.rtol = 1e-12;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.05;
  PrescribedDynamics<FB, 1, decltype(drive), dyn::NoForce, Dop853> five(FB::ParamsT<double>(), {1},
                                                                         drive, dyn::NoForce(), o);
  const double q0 = kPi / 2, qd0 = 1.5, t_end = 2.0;
  ASSERT_TRUE(five.Initialize(0.0, V1(q0)));
  std::vector<dyn::PrescribedSample<FB, 1>> rows;
  PrescribedSummary summary;
  ASSERT_TRUE(five.Simulate(0.0, V1(q0), V1(qd0), t_end,
                            [&](const auto& s) {
                              rows.push_back(s);
                              return true;
                            },
                            &summary))
      << dyn::FormatSummary(summary);
  ASSERT_EQ(rows.size(), 41u);

  dyn::MinimalOptions mo;
  mo.integrator = o.integrator;
  mo.sample_dt = o.sample_dt;
  dyn::MinimalDynamics<L4, Dop853> four(L4::ParamsT<double>(), mo);
  ASSERT_TRUE(four.Initialize(V1(q0)));
  std::vector<dyn::Sample<L4>> ref;
  dyn::MinimalSummary ms;
  ASSERT_TRUE(four.Simulate(0.0, V1(q0), V1(qd0), t_end,
                            [&](const auto& s) {
                              ref.push_back(s);
                              return true;
                            },
                            &ms))
      << dyn::FormatSummary(ms);
  ASSERT_EQ(ref.size(), rows.size());

  // crank2 (of fivebar_massive.yaml): m = 1.2, centre (0.5, 0), a4 = 1, E = (2, 0).
  const double m4 = 1.2, g = 9.81;
  const V2 u4(std::cos(th4), std::sin(th4));
  double swing = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& s = rows[i];
    SCOPED_TRACE("t = " + std::to_string(s.t));
    EXPECT_NEAR(s.t, ref[i].t, 1e-12);
    EXPECT_NEAR(s.q(1), th4, 0.0);
    EXPECT_EQ(s.qd(1), 0.0);
    EXPECT_NEAR(s.q(0), ref[i].q(0), 1e-8);
    EXPECT_NEAR(s.qd(0), ref[i].qd(0), 1e-7);
    EXPECT_NEAR(s.qdd(0), ref[i].qdd(0), 1e-6);
    swing = std::max(swing, std::abs(s.q(0) - q0));
    // The four-bar's kinetostatics at the five-bar's motion: no drive needed at A (crank1 is
    // free), and the reaction at D gives the torque that holds crank2.
    L4::ParamsT<double> p4;
    Eigen::Matrix<double, L4::kNphi, 1> phi;
    for (int k = 0; k < L4::kNphi; ++k) phi(k) = ref[i].phi(k);
    ASSERT_EQ(L4::Solve(p4, V1(s.q(0)), &phi).status, mech::fivebar_locked_fourbar::SolveStatus::kConverged);
    L4::CoefficientsT<double> c;
    L4::Coeffs(p4, V1(s.q(0)), phi, &c);
    L4::StaticsT<double> st;
    L4::Kinetostatics(p4, V1(s.q(0)), phi, V1(s.qd(0)), V1(s.qdd(0)), s.t, c, &st);
    EXPECT_NEAR(st.drive(0), 0.0, 1e-7);
    const V2 F_D(st.R(0), st.R(1));  // force of link2 on the ground (= the locked crank2)
    const double holding = -(Cross(u4 * 1.0, F_D) + Cross(u4 * 0.5, V2(0, -m4 * g)));
    EXPECT_NEAR(s.lambda(0), holding, 1e-7 * (1 + std::abs(holding)));
    EXPECT_EQ(s.W_act, 0.0);  // the held crank does no work
  }
  EXPECT_GT(swing, 0.3);  // it moved
  EXPECT_LT(summary.max_energy_error, 1e-9);
}

TEST(Prescribed, MovingDriverKeepsTheWorkBalance) {
  using FB = mech::fivebar_massive::Model;
  // crank2 through via points (a clamped spline: from rest to rest), crank1 free.
  const SplineLaw<5> law({0.0, 0.3, 0.7, 1.0, 1.4}, {kPi / 2, 1.9, 2.2, 1.8, 1.4});
  auto drive = MakeDrive(law);
  PrescribedOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.01;
  PrescribedDynamics<FB, 1, decltype(drive), dyn::NoForce, Dop853> sim(FB::ParamsT<double>(), {1},
                                                                        drive, dyn::NoForce(), o);
  ASSERT_TRUE(sim.Initialize(0.0, V1(kPi / 2)));
  double E0 = std::numeric_limits<double>::quiet_NaN(), max_err = 0, max_W = 0;
  PrescribedSummary summary;
  dyn::PrescribedSample<FB, 1> last;
  ASSERT_TRUE(sim.Simulate(0.0, V1(kPi / 2), V1(0.0), 1.6,
                           [&](const auto& s) {
                             if (std::isnan(E0)) E0 = s.E;
                             max_err = std::max(max_err, std::abs(s.E - s.W_act - E0));
                             max_W = std::max(max_W, std::abs(s.W_act));
                             EXPECT_NEAR(s.q(1), law(s.t).q, 1e-15);
                             EXPECT_NEAR(s.P_act, s.lambda(0) * law(s.t).qd, 1e-9 * (1 + std::abs(s.P_act)));
                             return true;
                           },
                           &summary, &last))
      << dyn::FormatSummary(summary);
  EXPECT_GT(max_W, 1.0);  // the driver did work
  EXPECT_LT(max_err, 1e-8 * max_W);
  EXPECT_NEAR(last.qd(1), 0.0, 1e-15);
}

TEST(Prescribed, InverseDynamicsWithDampersMatchesKinetostaticsAndTheWork) {
  // Every coordinate prescribed (kNp = kNq): the actuator force of a damped one-DOF
  // machine along a rest-to-rest move, against the generated kinetostatics' drive; the
  // actuator's work equals Delta(T + V) - W_nc (the dampers' work).
  namespace df = mech::damped_fourbar;
  using DF = df::Model;
  auto drive = MakeDrive(RestToRestLaw{1.0, 3.5, 0.0, 0.8, RestToRestLaw::Profile::kCycloidal});
  PrescribedOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.02;
  PrescribedDynamics<DF, 1, decltype(drive), dyn::NoForce, Dop853> inv(DF::ParamsT<double>(), {0},
                                                                        drive, dyn::NoForce(), o);
  ASSERT_TRUE(inv.Initialize(0.0, V0()));
  double E0 = std::numeric_limits<double>::quiet_NaN(), max_err = 0, max_lambda = 0;
  int rows = 0;
  PrescribedSummary summary;
  dyn::PrescribedSample<DF, 1> last;
  ASSERT_TRUE(inv.Simulate(0.0, V0(), V0(), 1.0,
                           [&](const auto& s) {
                             if (std::isnan(E0)) E0 = s.E;
                             ++rows;
                             max_err = std::max(max_err, std::abs(s.Balance() - E0));
                             DF::ParamsT<double> p;
                             Eigen::Matrix<double, DF::kNphi, 1> phi = s.phi;
                             DF::CoefficientsT<double> c;
                             DF::Coeffs(p, s.q, phi, &c);
                             DF::StaticsT<double> st;
                             DF::Kinetostatics(p, s.q, phi, s.qd, s.qdd, s.t, c, &st);
                             EXPECT_NEAR(s.lambda(0), st.drive(0), 1e-9 * (1 + std::abs(st.drive(0))));
                             max_lambda = std::max(max_lambda, std::abs(s.lambda(0)));
                             return true;
                           },
                           &summary, &last))
      << dyn::FormatSummary(summary);
  EXPECT_EQ(rows, 51);
  EXPECT_GT(max_lambda, 1.0);
  EXPECT_LT(std::abs(last.W_nc), 1e3);
  EXPECT_LT(last.W_nc, -1e-3);  // the dampers took energy
  EXPECT_LT(max_err, 1e-8 * (std::abs(last.W_act) + std::abs(last.W_nc)));
}

// ---------------------------------------------------------------- springs and dampers

TEST(Prescribed, FivebarSpringsAndDampersAgainstAHandComputation) {
  // fivebar_spring_damper = fivebar_massive + a spring and a damper between B and D, a
  // torsional spring at E and a torsional damper at C. Oracles: the springs' potential and the
  // dampers' power by hand (the geometry by circle intersection, speeds by central
  // differences along qd); the gravity part from fivebar_massive.
  using SD = mech::fivebar_spring_damper::Model;
  using FB = mech::fivebar_massive::Model;
  const double f = 2, a1 = 1, a2 = 2.5, a3 = 2, a4 = 1, k = 40, L0 = 2.2, cL = 3, kt = 5, cC = 0.5;
  auto geometry = [&](const V2& q, double* l, double* th1, double* th2) {
    const V2 B = a1 * V2(std::cos(q(0)), std::sin(q(0)));
    const V2 D = V2(f, 0) + a4 * V2(std::cos(q(1)), std::sin(q(1)));
    const V2 w = D - B;
    const double d = w.norm(), along = (a2 * a2 - a3 * a3 + d * d) / (2 * d);
    const double h = std::sqrt(a2 * a2 - along * along);
    const V2 C = B + along * w / d + h * V2(-w.y(), w.x()) / d;  // above BD: the assembly
    *l = d;
    *th1 = std::atan2(C.y() - B.y(), C.x() - B.x());
    *th2 = std::atan2(C.y() - D.y(), C.x() - D.x());
  };
  auto potential = [&](const V2& q) {
    double l, t1, t2;
    geometry(q, &l, &t1, &t2);
    return 0.5 * k * (l - L0) * (l - L0) + 0.5 * kt * (kPi / 2 - q(1)) * (kPi / 2 - q(1));
  };
  for (int i = 0; i < 4; ++i) {
    SCOPED_TRACE("case " + std::to_string(i));
    const V2 q(1.4 + 0.25 * i, 1.2 - 0.2 * i), qd(0.8 - 0.5 * i, -0.3 + 0.4 * i);
    Eigen::Matrix<double, 2, 1> phi(0.9, 1.8);
    ASSERT_EQ(SD::Solve(SD::ParamsT<double>(), q, &phi).status, mech::fivebar_spring_damper::SolveStatus::kConverged);
    SD::CoefficientsT<double> c;
    SD::Coeffs(SD::ParamsT<double>(), q, phi, &c);
    SD::DynamicsT<double> d;
    SD::Dynamics(SD::ParamsT<double>(), q, phi, qd, 0.0, c, &d);
    FB::CoefficientsT<double> cf;
    FB::Coeffs(FB::ParamsT<double>(), q, phi, &cf);
    FB::DynamicsT<double> df;
    FB::Dynamics(FB::ParamsT<double>(), q, phi, qd, 0.0, cf, &df);
    double l, t1, t2;
    geometry(q, &l, &t1, &t2);
    EXPECT_NEAR(phi(0), t1, 1e-12);
    EXPECT_NEAR(phi(1), t2, 1e-12);
    EXPECT_NEAR(d.V - df.V, potential(q), 1e-10);
    EXPECT_NEAR((d.I - df.I).norm(), 0.0, 1e-12);  // springs and dampers add no inertia
    const double e = 1e-5;
    double lp, t1p, t2p, lm, t1m, t2m;
    geometry(q + e * qd, &lp, &t1p, &t2p);
    geometry(q - e * qd, &lm, &t1m, &t2m);
    const double ldot = (lp - lm) / (2 * e), w_rel = ((t2p - t1p) - (t2m - t1m)) / (2 * e);
    const double P_hand = -cL * ldot * ldot - cC * w_rel * w_rel;
    EXPECT_LT(P_hand, -1e-3);
    EXPECT_NEAR(d.P_nc, P_hand, 1e-7 * (1 + std::abs(P_hand)));
    const double dVdt = (potential(q + e * qd) - potential(q - e * qd)) / (2 * e);
    EXPECT_NEAR((d.Q - df.Q).dot(qd), -dVdt + P_hand, 1e-7 * (1 + std::abs(dVdt)));
  }
}

TEST(Prescribed, FivebarSpringsAndDampersWithADriverKeepTheWorkBalance) {
  using SD = mech::fivebar_spring_damper::Model;
  auto drive = MakeDrive(RestToRestLaw{kPi / 2, 130 * kPi / 180, 0.0, 0.6});
  PrescribedOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.01;
  PrescribedDynamics<SD, 1, decltype(drive), dyn::NoForce, Dop853> sim(SD::ParamsT<double>(), {1},
                                                                        drive, dyn::NoForce(), o);
  ASSERT_TRUE(sim.Initialize(0.0, V1(kPi / 2)));
  PrescribedSummary summary;
  dyn::PrescribedSample<SD, 1> first, last;
  bool have_first = false;
  double max_err = 0;
  ASSERT_TRUE(sim.Simulate(0.0, V1(kPi / 2), V1(0.0), 2.0,
                           [&](const auto& s) {
                             if (!have_first) {
                               first = s;
                               have_first = true;
                             }
                             max_err = std::max(max_err, std::abs(s.Balance() - first.Balance()));
                             return true;
                           },
                           &summary, &last))
      << dyn::FormatSummary(summary);
  const double scale = std::abs(last.W_nc) + std::abs(last.W_act);
  EXPECT_LT(last.W_nc, -0.1);  // the dampers took energy
  EXPECT_GT(std::abs(last.W_act), 0.1);
  EXPECT_LT(max_err, 1e-8 * scale);
}

// ---------------------------------------------------------------- the five-bar robot

using Robot = mech::fivebar_robot::Model;
// fivebar_robot.yaml's defaults.
constexpr double kF = 0.2, kA = 0.25, kB = 0.30, kRho = 2.0, kMp = 0.3, kG = 9.81;

// The commanded tool point: a pick-and-place move from (-0.05, 0.36) to (0.25, 0.42) in 0.4 s,
// rest to rest (the 3-4-5 law s(t) along the path) with a lift of 0.04 m at mid-course, then
// at rest.
struct ToolPath {
  void operator()(double t, V2* r, V2* v, V2* a) const {
    const RestToRestLaw s{0.0, 1.0, 0.0, 0.4, RestToRestLaw::Profile::kPoly345};
    const MotionState m = s(t);
    const double x0 = -0.05, dx = 0.30, y0 = 0.36, dy = 0.06, H = 0.04;
    const double slope = dy + 4 * H * (1 - 2 * m.q);  // dy/ds
    *r = V2(x0 + dx * m.q, y0 + dy * m.q + 4 * H * m.q * (1 - m.q));
    *v = V2(dx * m.qd, slope * m.qd);
    *a = V2(dx * m.qdd, slope * m.qdd - 8 * H * m.qd * m.qd);
  }
};

// The hand inverse kinematics of one arm: pivot O, proximal a, distal b, tool point C (with
// velocity and acceleration): the crank angle with the elbow on side `sign` (+1: B counter-
// clockwise from OC), its speed and acceleration from |C - B| = b differentiated twice.
void ArmInverse(const V2& O, double sign, const V2& C, const V2& Cd, const V2& Cdd, double* th,
                double* thd, double* thdd) {
  const V2 r = C - O;
  const double d = r.norm();
  const double alpha = std::acos((kA * kA + d * d - kB * kB) / (2 * kA * d));
  *th = std::atan2(r.y(), r.x()) + sign * alpha;
  const V2 er(std::cos(*th), std::sin(*th)), et(-std::sin(*th), std::cos(*th));
  const V2 u = C - O - kA * er;  // C - B
  const double den = kA * u.dot(et);
  *thd = u.dot(Cd) / den;
  const V2 ud = Cd - kA * *thd * et;
  *thdd = (ud.squaredNorm() + u.dot(Cdd) + kA * *thd * *thd * u.dot(er)) / den;
}

// q(t), qd(t), qdd(t) of the robot for the tool path (left elbow out, right elbow out).
struct RobotMotion {
  void operator()(double t, V2* q, V2* qd, V2* qdd) const {
    V2 r, v, a;
    ToolPath()(t, &r, &v, &a);
    ArmInverse(V2(0, 0), +1, r, v, a, &(*q)(0), &(*qd)(0), &(*qdd)(0));
    ArmInverse(V2(kF, 0), -1, r, v, a, &(*q)(1), &(*qd)(1), &(*qdd)(1));
  }
};

// The hand forward kinematics: B, D from q, C the intersection of the distal circles above BD.
void RobotPoints(const V2& q, V2* B, V2* C, V2* D) {
  *B = kA * V2(std::cos(q(0)), std::sin(q(0)));
  *D = V2(kF, 0) + kA * V2(std::cos(q(1)), std::sin(q(1)));
  const V2 m = 0.5 * (*B + *D), w = *D - *B;
  const double half = 0.5 * w.norm();
  const double h = std::sqrt(kB * kB - half * half);
  *C = m + h * V2(-w.y(), w.x()) / w.norm();
}

TEST(Prescribed, RobotInverseThenForwardReproducesTheToolPath) {
  using Inverse = PrescribedDynamics<Robot, 2, RobotMotion, dyn::NoForce, Dop853>;
  PrescribedOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.01;
  Inverse inv(Robot::ParamsT<double>(), {0, 1}, RobotMotion(), dyn::NoForce(), o);
  ASSERT_TRUE(inv.Initialize(0.0, V0()));
  const double t_end = 0.5;
  std::vector<dyn::PrescribedSample<Robot, 2>> rows;
  PrescribedSummary summary;
  ASSERT_TRUE(inv.Simulate(0.0, V0(), V0(), t_end,
                           [&](const auto& s) {
                             rows.push_back(s);
                             return true;
                           },
                           &summary))
      << dyn::FormatSummary(summary);
  ASSERT_EQ(rows.size(), 51u);
  Robot::ParamsT<double> p;
  double max_tau = 0;
  for (const auto& s : rows) {
    SCOPED_TRACE("t = " + std::to_string(s.t));
    // The assembled configuration is the commanded one: the tool point (generated) on the path.
    Robot::CoefficientsT<double> c;
    Robot::Coeffs(p, s.q, s.phi, &c);
    V2 r, v, a;
    ToolPath()(s.t, &r, &v, &a);
    EXPECT_NEAR((c.r_P.col(0) - r).norm(), 0.0, 1e-12);
    // The torques against the generated kinetostatics (d'Alembert's forces in the statics).
    Robot::StaticsT<double> st;
    Robot::Kinetostatics(p, s.q, s.phi, s.qd, s.qdd, s.t, c, &st);
    EXPECT_NEAR(s.lambda(0), st.drive(0), 1e-9 * (1 + st.drive.norm()));
    EXPECT_NEAR(s.lambda(1), st.drive(1), 1e-9 * (1 + st.drive.norm()));
    max_tau = std::max(max_tau, s.lambda.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(max_tau, 0.5);
  // Rest to rest: the motors' work is the change of the potential energy.
  const auto& end = rows.back();
  EXPECT_NEAR(end.T, 0.0, 1e-20);
  EXPECT_GT(end.V - rows.front().V, 0.5);  // the payload was lifted
  EXPECT_NEAR(end.W_act, end.V - rows.front().V, 1e-9);

  // Forward: the same model, no coordinate prescribed, the motors' torques as the caller's
  // forces F(t) = lambda(t) of the inverse problem.
  struct Torques {
    Inverse* inverse;
    void operator()(double t, const V2&, const V2&, V2* F) const {
      dyn::PrescribedSample<Robot, 2> s;
      const bool ok = inverse->Evaluate(t, Eigen::Matrix<double, 3, 1>::Zero(), &s);
      *F = ok ? V2(s.lambda) : V2::Constant(std::numeric_limits<double>::quiet_NaN());
    }
  };
  Inverse helper(Robot::ParamsT<double>(), {0, 1}, RobotMotion(), dyn::NoForce(), o);
  ASSERT_TRUE(helper.Initialize(0.0, V0()));
  auto none = MakeDrive();
  using Forward = PrescribedDynamics<Robot, 0, decltype(none), Torques, Dop853>;
  Forward fwd(Robot::ParamsT<double>(), {}, none, Torques{&helper}, o);
  V2 q0, qd0, qdd0;
  RobotMotion()(0.0, &q0, &qd0, &qdd0);
  ASSERT_TRUE(fwd.Initialize(0.0, q0));
  double max_dev = 0, max_dq = 0;
  dyn::PrescribedSample<Robot, 0> last;
  ASSERT_TRUE(fwd.Simulate(0.0, q0, qd0, t_end,
                           [&](const auto& s) {
                             V2 r, v, a, B, C, D, q, qd, qdd;
                             ToolPath()(s.t, &r, &v, &a);
                             RobotPoints(s.q, &B, &C, &D);
                             max_dev = std::max(max_dev, (C - r).norm());
                             RobotMotion()(s.t, &q, &qd, &qdd);
                             max_dq = std::max(max_dq, (s.q - q).cwiseAbs().maxCoeff());
                             return true;
                           },
                           &summary, &last))
      << dyn::FormatSummary(summary);
  EXPECT_LT(max_dev, 1e-7);  // metres
  EXPECT_LT(max_dq, 1e-6);   // rad
  EXPECT_NEAR(last.W_F, end.W_act, 1e-7);
  EXPECT_LT(summary.max_energy_error, 1e-8);
}

TEST(Prescribed, RobotInertiaAgainstTheKineticEnergyOfAHandModel) {
  // Each body: mass, J about G, and G, theta from the hand kinematics.
  const double mb1 = kRho * kB + kMp;
  const double xg1 = (kRho * kB * kB / 2 + kMp * kB) / mb1;
  const double J1 = kRho * kB * kB * kB / 12 + kRho * kB * std::pow(xg1 - kB / 2, 2) +
                    kMp * std::pow(kB - xg1, 2);
  const double m[4] = {kRho * kA, mb1, kRho * kB, kRho * kA};
  const double J[4] = {kRho * kA * kA * kA / 12, J1, kRho * kB * kB * kB / 12, kRho * kA * kA * kA / 12};
  auto bodies = [&](const V2& q, V2 G[4], double th[4]) {
    V2 B, C, D;
    RobotPoints(q, &B, &C, &D);
    const V2 E(kF, 0);
    th[0] = q(0);
    th[1] = std::atan2(C.y() - B.y(), C.x() - B.x());
    th[2] = std::atan2(C.y() - D.y(), C.x() - D.x());
    th[3] = q(1);
    G[0] = 0.5 * B;
    G[1] = B + (xg1 / kB) * (C - B);
    G[2] = 0.5 * (D + C);
    G[3] = 0.5 * (E + D);
  };
  auto kinetic = [&](const V2& q, const V2& qd) {
    const double e = 1e-4, at[4] = {-2 * e, -e, e, 2 * e};
    V2 G[4][4];
    double th[4][4];
    for (int i = 0; i < 4; ++i) bodies(q + at[i] * qd, G[i], th[i]);
    double T = 0;
    for (int b = 0; b < 4; ++b) {
      const V2 v = (G[0][b] - 8 * G[1][b] + 8 * G[2][b] - G[3][b]) / (12 * e);
      const double w = (th[0][b] - 8 * th[1][b] + 8 * th[2][b] - th[3][b]) / (12 * e);
      T += 0.5 * m[b] * v.squaredNorm() + 0.5 * J[b] * w * w;
    }
    return T;
  };
  Robot::ParamsT<double> p;
  int checked = 0;
  for (double x = -0.05; x <= 0.25 + 1e-9; x += 0.075) {
    for (double y = 0.30; y <= 0.45 + 1e-9; y += 0.05) {
      V2 q, qd, qdd;
      ArmInverse(V2(0, 0), +1, V2(x, y), V2::Zero(), V2::Zero(), &q(0), &qd(0), &qdd(0));
      ArmInverse(V2(kF, 0), -1, V2(x, y), V2::Zero(), V2::Zero(), &q(1), &qd(1), &qdd(1));
      Eigen::Matrix<double, 2, 1> phi;
      for (int i = 0; i < 2; ++i) phi(i) = Robot::kAssemblyPhi[i];
      ASSERT_EQ(Robot::Solve(p, q, &phi).status, mech::fivebar_robot::SolveStatus::kConverged);
      Robot::CoefficientsT<double> c;
      Robot::Coeffs(p, q, phi, &c);
      ASSERT_NEAR((c.r_P.col(0) - V2(x, y)).norm(), 0.0, 1e-12);  // the same assembly mode
      Robot::DynamicsT<double> d;
      Robot::Dynamics(p, q, phi, V2(0.7, -0.4), 0.0, c, &d);
      const V2 e0 = V2::Unit(0), e1 = V2::Unit(1);
      Eigen::Matrix2d I;
      I(0, 0) = 2 * kinetic(q, e0);
      I(1, 1) = 2 * kinetic(q, e1);
      I(0, 1) = I(1, 0) = kinetic(q, e0 + e1) - kinetic(q, e0) - kinetic(q, e1);
      const double scale = I.norm();
      EXPECT_LT((d.I - I).norm(), 1e-8 * scale) << x << " " << y;
      EXPECT_EQ(d.I(0, 1), d.I(1, 0));
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(d.I);
      EXPECT_GT(eig.eigenvalues()(0), 1e-3 * scale) << x << " " << y;
      EXPECT_NEAR(d.T, 0.5 * V2(0.7, -0.4).dot(I * V2(0.7, -0.4)), 1e-8 * scale);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 20);
}

TEST(Prescribed, RobotDrivenIntoAStretchedConfigurationStopsBeforeIt) {
  // Both motors prescribed at constant speeds opening the arms: |BD| grows to 2 b, where the
  // distal links are stretched and Phi_phi is singular. The hand time of that configuration:
  // bisection on |B(t) - D(t)| = 2 b.
  const double w1 = 1.0, w2 = -1.0, q10 = 135 * kPi / 180, q20 = 45 * kPi / 180;
  auto drive = MakeDrive(ConstantSpeedLaw{q10, w1, 0.0}, ConstantSpeedLaw{q20, w2, 0.0});
  auto bd = [&](double t) {
    const V2 B = kA * V2(std::cos(q10 + w1 * t), std::sin(q10 + w1 * t));
    const V2 D = V2(kF, 0) + kA * V2(std::cos(q20 + w2 * t), std::sin(q20 + w2 * t));
    return (D - B).norm();
  };
  double lo = 0, hi = 0.5;
  ASSERT_LT(bd(lo), 2 * kB);
  ASSERT_GT(bd(hi), 2 * kB);
  for (int i = 0; i < 200; ++i) ((bd(0.5 * (lo + hi)) < 2 * kB) ? lo : hi) = 0.5 * (lo + hi);
  const double t_star = lo;
  PrescribedOptions o;
  o.integrator.rtol = 1e-9;
  o.integrator.atol = 1e-10;
  o.sample_dt = 0.01;
  o.min_rcond = 1e-3;
  PrescribedDynamics<Robot, 2, decltype(drive), dyn::NoForce, Dop853> sim(
      Robot::ParamsT<double>(), {0, 1}, drive, dyn::NoForce(), o);
  ASSERT_TRUE(sim.Initialize(0.0, V0()));
  PrescribedSummary summary;
  dyn::PrescribedSample<Robot, 2> last;
  double t_max = 0;
  const bool usable = sim.Simulate(0.0, V0(), V0(), 2.0,
                                   [&](const auto& s) {
                                     t_max = std::max(t_max, s.t);
                                     EXPECT_LE(bd(s.t), 2 * kB);
                                     return true;
                                   },
                                   &summary, &last);
  EXPECT_FALSE(usable);
  EXPECT_EQ(summary.status, Status::kDeadPoint) << dyn::FormatSummary(summary);
  EXPECT_EQ(summary.event, dyn::Event::kDeadPoint);
  // The figures: where and how singular.
  EXPECT_LT(summary.t_end, t_star);
  EXPECT_GT(summary.t_end, t_star - 1e-3);
  EXPECT_NEAR(last.t, summary.t_end, 1e-12);
  EXPECT_NEAR(last.rcond, o.min_rcond, 1e-2 * o.min_rcond);
  EXPECT_LE(t_max, summary.t_end + 1e-12);
  // By hand at the stop: the distal links nearly aligned (angle BCD near pi).
  V2 B, C, D;
  RobotPoints(last.q, &B, &C, &D);
  const double bcd = std::acos((B - C).dot(D - C) / ((B - C).norm() * (D - C).norm()));
  EXPECT_GT(bcd, kPi - 0.02);
  EXPECT_LT(bcd, kPi);
  EXPECT_GT(summary.max_abs_lambda, 0.0);
  EXPECT_TRUE(std::isnan(last.lambda(0)) && std::isnan(last.lambda(1)));  // withheld there
  EXPECT_TRUE(std::string(summary.message).find("singular") != std::string::npos);
}

TEST(Prescribed, SingularConfigurationWithTheDefaultThresholdStopsQuickly) {
  // The same opening motion with the default min_rcond = 1e-6: the torques grow like
  // 1/sigma_min, the steps collapse before 1/cond reaches 1e-6; the approach rule ends the run
  // with kDeadPoint before the stretched configuration, after a bounded number of steps.
  const double q10 = 135 * kPi / 180, q20 = 45 * kPi / 180;
  auto drive = MakeDrive(ConstantSpeedLaw{q10, 1.0, 0.0}, ConstantSpeedLaw{q20, -1.0, 0.0});
  PrescribedOptions o;
  o.sample_dt = 0.01;
  PrescribedDynamics<Robot, 2, decltype(drive)> sim(Robot::ParamsT<double>(), {0, 1}, drive,
                                                    dyn::NoForce(), o);
  ASSERT_TRUE(sim.Initialize(0.0, V0()));
  PrescribedSummary summary;
  dyn::PrescribedSample<Robot, 2> last;
  std::vector<dyn::PrescribedSample<Robot, 2>> samples;
  EXPECT_FALSE(sim.Simulate(0.0, V0(), V0(), 2.0,
                            [&](const auto& s) {
                              samples.push_back(s);
                              return true;
                            },
                            &summary, &last));
  EXPECT_EQ(summary.status, Status::kDeadPoint) << dyn::FormatSummary(summary);
  EXPECT_EQ(summary.event, dyn::Event::kDeadPoint);
  EXPECT_LT(summary.integrator.steps, 2000) << dyn::FormatSummary(summary);
  EXPECT_LT(last.rcond, o.approach_rcond);
  V2 B, C, D;
  RobotPoints(last.q, &B, &C, &D);
  EXPECT_LE((D - B).norm(), 2 * kB);
  EXPECT_GT((D - B).norm(), 2 * kB * (1 - 1e-5));  // at the stretched configuration
  // The motors' torques there grow like 1/sigma_min(Phi_phi) (they were 2.5e19 N m): the
  // sample where the run stopped withholds them (NaN), as the statics does; every sample
  // before has them, finite, and the summary's largest |lambda| is the largest of those.
  ASSERT_GE(samples.size(), 3u);
  EXPECT_EQ(samples.back().t, last.t);
  EXPECT_TRUE(std::isnan(last.lambda(0)) && std::isnan(last.lambda(1)));
  EXPECT_TRUE(std::isnan(samples.back().lambda(0)) && std::isnan(samples.back().P_act));
  double max_lambda = 0;
  for (size_t i = 0; i + 1 < samples.size(); ++i) {
    ASSERT_TRUE(samples[i].lambda.allFinite()) << "t = " << samples[i].t;
    max_lambda = std::max(max_lambda, samples[i].lambda.cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(summary.max_abs_lambda, max_lambda);
  EXPECT_LT(summary.max_abs_lambda, 1e6) << dyn::FormatSummary(summary);
}

TEST(Prescribed, FreeRobotThrownOpenStopsAtTheStretchedConfiguration) {
  // No driver, no torque: the robot's motors thrown apart (qd = (+w, -w)) stretch the distal
  // links; both the minimal method of forward.h and PrescribedDynamics with kNp = 0 must stop
  // there with kDeadPoint (never integrate through it), the hand geometry at the stop
  // confirming the stretched configuration.
  const double q10 = 135 * kPi / 180, q20 = 45 * kPi / 180, w = 4.0;
  const V2 q0(q10, q20), qd0(w, -w);
  {
    auto none = MakeDrive();
    PrescribedOptions o;
    o.sample_dt = 0.005;
    PrescribedDynamics<Robot, 0, decltype(none)> sim(Robot::ParamsT<double>(), {}, none, dyn::NoForce(), o);
    ASSERT_TRUE(sim.Initialize(0.0, q0));
    PrescribedSummary summary;
    dyn::PrescribedSample<Robot, 0> last;
    double max_bd = 0;
    EXPECT_FALSE(sim.Simulate(0.0, q0, qd0, 1.0,
                              [&](const auto& s) {
                                V2 B, C, D;
                                RobotPoints(s.q, &B, &C, &D);
                                max_bd = std::max(max_bd, (D - B).norm());
                                return true;
                              },
                              &summary, &last));
    EXPECT_EQ(summary.status, Status::kDeadPoint) << dyn::FormatSummary(summary);
    EXPECT_LE(max_bd, 2 * kB);
    V2 B, C, D;
    RobotPoints(last.q, &B, &C, &D);
    EXPECT_GT((D - B).norm(), 2 * kB * (1 - 1e-4)) << dyn::FormatSummary(summary);
    EXPECT_LT(summary.integrator.steps, 5000);
  }
  {
    dyn::MinimalOptions o;
    o.sample_dt = 0.005;
    dyn::MinimalDynamics<Robot> sim(Robot::ParamsT<double>(), o);
    ASSERT_TRUE(sim.Initialize(q0));
    dyn::MinimalSummary summary;
    dyn::Sample<Robot> last;
    EXPECT_FALSE(sim.Simulate(0.0, q0, qd0, 1.0, [](const auto&) { return true; }, &summary, &last));
    EXPECT_EQ(summary.status, Status::kDeadPoint) << dyn::FormatSummary(summary);
    V2 B, C, D;
    RobotPoints(last.q, &B, &C, &D);
    EXPECT_GT((D - B).norm(), 2 * kB * (1 - 1e-4)) << dyn::FormatSummary(summary);
    EXPECT_LE((D - B).norm(), 2 * kB);
  }
}

TEST(Prescribed, InvalidIndicesAreRefused) {
  using FB = mech::fivebar_massive::Model;
  auto drive = MakeDrive(ConstantSpeedLaw{1.0, 0.0, 0.0});
  PrescribedDynamics<FB, 1, decltype(drive)> bad(FB::ParamsT<double>(), {2}, drive);
  EXPECT_FALSE(bad.Initialize(0.0, V1(kPi / 2)));
  PrescribedSummary summary;
  EXPECT_FALSE(bad.Simulate(0.0, V1(kPi / 2), V1(0.0), 1.0, [](const auto&) { return true; }, &summary));
  EXPECT_EQ(summary.status, Status::kInvalidInput);
}

TEST(Prescribed, EvaluateAtASingularConfigurationWithholdsTheActuatorForces) {
  // Both motors driven to the stretched configuration's inputs (found by bisection on the
  // hand geometry |D - B| = 2 b): 1/cond_1(Phi_phi) there is below min_rcond, and Evaluate()
  // gives lambda NaN instead of a huge number; a regular configuration nearby has them.
  const double q10 = 135 * kPi / 180, q20 = 45 * kPi / 180;
  auto bd = [&](double s) {
    const V2 B = kA * V2(std::cos(q10 + s), std::sin(q10 + s));
    const V2 D = V2(kF, 0) + kA * V2(std::cos(q20 - s), std::sin(q20 - s));
    return (D - B).norm();
  };
  double lo = 0, hi = 0.5;
  ASSERT_LT(bd(lo), 2 * kB);
  ASSERT_GT(bd(hi), 2 * kB);
  for (int i = 0; i < 200; ++i) ((bd(0.5 * (lo + hi)) < 2 * kB) ? lo : hi) = 0.5 * (lo + hi);
  auto at = [&](double s) {
    return MakeDrive(ConstantSpeedLaw{q10 + s, 0.0, 0.0}, ConstantSpeedLaw{q20 - s, 0.0, 0.0});
  };
  using Sim = PrescribedDynamics<Robot, 2, decltype(at(0.0))>;
  {
    Sim sim(Robot::ParamsT<double>(), {0, 1}, at(lo - 0.05), dyn::NoForce(), PrescribedOptions());
    ASSERT_TRUE(sim.Initialize(0.0, V0()));
    typename Sim::SampleT s;
    ASSERT_TRUE(sim.Evaluate(0.0, Sim::State::Zero(), &s));
    EXPECT_GT(s.rcond, PrescribedOptions().min_rcond);
    EXPECT_TRUE(s.lambda.allFinite());
  }
  {
    // Assembled near it, then evaluated at it (the warm start keeps the branch).
    Sim sim(Robot::ParamsT<double>(), {0, 1}, at(lo), dyn::NoForce(), PrescribedOptions());
    if (!sim.Initialize(0.0, V0())) GTEST_SKIP() << "does not assemble at the stretched inputs";
    typename Sim::SampleT s;
    if (!sim.Evaluate(0.0, Sim::State::Zero(), &s)) GTEST_SKIP() << "no evaluation there";
    EXPECT_LT(s.rcond, PrescribedOptions().min_rcond);
    EXPECT_TRUE(std::isnan(s.lambda(0)) && std::isnan(s.lambda(1)));
  }
}

TEST(Prescribed, ASampleGridThatCannotAdvanceIsRefused) {
  // sample_dt so small that t + sample_dt == t: refused with a status before any step, not a
  // loop without end; likewise a grid of more than max_samples samples.
  auto drive = MakeDrive(ConstantSpeedLaw{135 * kPi / 180, 0.1, 0.0},
                         ConstantSpeedLaw{45 * kPi / 180, 0.0, 0.0});
  for (double dt : {1e-300, 1e-17}) {
    PrescribedOptions o;
    o.sample_dt = dt;
    PrescribedDynamics<Robot, 2, decltype(drive)> sim(Robot::ParamsT<double>(), {0, 1}, drive,
                                                      dyn::NoForce(), o);
    ASSERT_TRUE(sim.Initialize(0.0, V0()));
    PrescribedSummary summary;
    int samples = 0;
    EXPECT_FALSE(sim.Simulate(0.0, V0(), V0(), 1.0,
                              [&](const auto&) {
                                ++samples;
                                return true;
                              },
                              &summary));
    EXPECT_EQ(summary.status, Status::kInvalidInput) << dt;
    EXPECT_EQ(samples, 0);
    EXPECT_EQ(summary.integrator.steps, 0);
  }
  PrescribedOptions o;
  o.sample_dt = 1e-3;
  o.max_samples = 999;  // 1000 samples asked for
  PrescribedDynamics<Robot, 2, decltype(drive)> sim(Robot::ParamsT<double>(), {0, 1}, drive,
                                                    dyn::NoForce(), o);
  ASSERT_TRUE(sim.Initialize(0.0, V0()));
  PrescribedSummary summary;
  EXPECT_FALSE(sim.Simulate(0.0, V0(), V0(), 1.0, [](const auto&) { return true; }, &summary));
  EXPECT_EQ(summary.status, Status::kInvalidInput);
}

}  // namespace
