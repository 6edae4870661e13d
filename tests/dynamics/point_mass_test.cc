// Point masses (`point_masses:` of a link; issue 26, "Masses where they are") against oracles
// that do not go through them:
//  - tests/dynamics/models/fourbar_point_masses.yaml (a counterweight without inertia beside
//    the crank's own mass, a payload with inertia on an otherwise massless coupler, two masses
//    beside the rocker's own) against fourbar_point_masses_folded.yaml, the same machine with
//    each link's masses folded into one body by hand (total mass, centre, parallel-axis theorem
//    in its derived parameters): the statics (Q, drive, V, dV/dq, stiffness, reactions), the
//    dynamics (I, dI/dq, C, h, Q, T, V, P_nc), the kinetostatics (drive, reactions), the
//    excess-coordinate M, h, g, the one-pass right-hand side and the shaking force agree to
//    1e-12 at several configurations, at the defaults and after changing the point masses'
//    parameters at run time (the combined body is symbolic in them);
//  - the same four-bar's kinetostatic reactions and driving torque against Newton–Euler of each
//    link with its particles (own mass, point masses) one by one, their accelerations from the
//    links' angular velocities and accelerations (K, L): no combined body in the oracle;
//  - tests/dynamics/models/pendulum_point_mass.yaml (a massless arm with a head of mass m and
//    own inertia J at its tip, distance l) against the closed form: I = m l^2 + J, the weight's
//    generalized force -m g l cos(theta), the pin reaction m a_G + m g (up), the kinetostatic
//    torque I thetadd + m g l cos(theta), and the shaking force and moment -m a_G,
//    -(r_G x m a_G + J thetadd).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <utility>
#include <vector>

#include "fourbar_point_masses.h"
#include "fourbar_point_masses_folded.h"
#include "pendulum_point_mass.h"

namespace {

using Point = mech::fourbar_point_masses::Model;
using Folded = mech::fourbar_point_masses_folded::Model;

// |a - b| <= tol (1 + |b|) elementwise, with the name of what is compared.
template <class A, class B>
void ExpectClose(const A& a, const B& b, const char* what, double tol = 1e-12) {
  const Eigen::MatrixXd x = Eigen::MatrixXd(a), y = Eigen::MatrixXd(b);
  ASSERT_EQ(x.rows(), y.rows()) << what;
  ASSERT_EQ(x.cols(), y.cols()) << what;
  for (int i = 0; i < x.rows(); ++i)
    for (int j = 0; j < x.cols(); ++j)
      EXPECT_NEAR(x(i, j), y(i, j), tol * (1 + std::abs(y(i, j)))) << what << "(" << i << ", " << j << ")";
}

void ExpectClose(double a, double b, const char* what, double tol = 1e-12) {
  EXPECT_NEAR(a, b, tol * (1 + std::abs(b))) << what;
}

// Every output of model M at (q, qd, qdd) with the positions solved near the assembly.
template <class M>
struct Outputs {
  typename M::template StaticsT<double> statics, kinetostatics;
  typename M::template DynamicsT<double> dynamics;
  typename M::template ExcessT<double> excess;
  typename M::template ShakingT<double> shaking;
};

template <class M>
Outputs<M> Evaluate(const typename M::template ParamsT<double>& p, double q0, double qd0, double qdd0) {
  Eigen::Matrix<double, M::kNq, 1> q, qd, qdd;
  q(0) = q0;
  qd(0) = qd0;
  qdd(0) = qdd0;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  const auto report = M::Solve(p, q, &phi);
  EXPECT_EQ(report.status, decltype(report.status)::kConverged);
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  Outputs<M> o;
  M::Forces(p, q, phi, c, &o.statics);
  M::Stiffness(p, q, phi, c, &o.statics);
  M::Dynamics(p, q, phi, qd, 0.0, c, &o.dynamics);
  M::Kinetostatics(p, q, phi, qd, qdd, 0.0, c, &o.kinetostatics);
  const Eigen::Matrix<double, M::kNphi, 1> phid = c.K * qd;
  M::ExcessDynamics(p, q, phi, qd, phid, 0.0, &o.excess);
  M::Shaking(p, q, phi, qd, qdd, c, &o.shaking);
  return o;
}

// The one-pass right-hand side (its parameter-only terms from Prepare) at (q, qd).
template <class M>
typename M::template RhsT<double> EvaluateRhs(const typename M::template ParamsT<double>& p, double q0, double qd0) {
  Eigen::Matrix<double, M::kNq, 1> q, qd;
  q(0) = q0;
  qd(0) = qd0;
  typename M::template RhsConstantsT<double> rc;
  M::Prepare(p, &rc);
  typename M::template TrigT<double> trig;
  typename M::template RhsT<double> out;
  const auto report = M::Rhs(p, rc, q, qd, 0.0, M::kDefaultModes, &trig, &out);
  EXPECT_EQ(report.status, decltype(report.status)::kConverged);
  return out;
}

// The same parameter values in both models (the folded one has the same free parameters).
template <class P, class F>
void CopyParams(P from, F* to) {
  for (const char* name : {"a",  "b",  "c",  "d",  "g",  "m1", "J1", "mw", "wx", "wy", "px",
                           "py", "mp", "Jp", "m3", "J3", "mc", "Jc", "mk", "kx", "ky"}) {
    double* dst = to->Find(name);
    ASSERT_NE(dst, nullptr) << name;
    *dst = *from.Find(name);
  }
}

void CompareAt(const Point::ParamsT<double>& p, double q, double qd, double qdd) {
  SCOPED_TRACE("theta_crank = " + std::to_string(q));
  Folded::ParamsT<double> pf;
  CopyParams(p, &pf);
  const auto a = Evaluate<Point>(p, q, qd, qdd);
  const auto b = Evaluate<Folded>(pf, q, qd, qdd);
  // The weights do work: the test can fail.
  ASSERT_GT(b.statics.R.norm(), 1.0);
  ASSERT_GT(b.kinetostatics.R.norm(), 1.0);
  ExpectClose(a.statics.Q, b.statics.Q, "statics Q");
  ExpectClose(a.statics.drive, b.statics.drive, "statics drive");
  ExpectClose(a.statics.V, b.statics.V, "V");
  ExpectClose(a.statics.dV_dq, b.statics.dV_dq, "dV_dq");
  ExpectClose(a.statics.d2V_dq2, b.statics.d2V_dq2, "d2V_dq2");
  ExpectClose(a.statics.stiffness, b.statics.stiffness, "stiffness");
  ExpectClose(a.statics.R, b.statics.R, "statics R");
  ExpectClose(a.dynamics.I, b.dynamics.I, "I");
  ExpectClose(a.dynamics.dI_dq, b.dynamics.dI_dq, "dI_dq");
  ExpectClose(a.dynamics.C, b.dynamics.C, "C");
  ExpectClose(a.dynamics.h, b.dynamics.h, "h");
  ExpectClose(a.dynamics.Q, b.dynamics.Q, "dynamics Q");
  ExpectClose(a.dynamics.T, b.dynamics.T, "T");
  ExpectClose(a.dynamics.V, b.dynamics.V, "dynamics V");
  ExpectClose(a.dynamics.P_nc, b.dynamics.P_nc, "P_nc");
  ExpectClose(a.kinetostatics.drive, b.kinetostatics.drive, "kinetostatic drive");
  ExpectClose(a.kinetostatics.Q, b.kinetostatics.Q, "kinetostatic Q");
  ExpectClose(a.kinetostatics.R, b.kinetostatics.R, "kinetostatic R");
  ExpectClose(a.excess.M, b.excess.M, "excess M");
  ExpectClose(a.excess.h, b.excess.h, "excess h");
  ExpectClose(a.excess.g, b.excess.g, "excess g");
  const auto ra = EvaluateRhs<Point>(p, q, qd);
  const auto rb = EvaluateRhs<Folded>(pf, q, qd);
  ExpectClose(ra.I, rb.I, "Rhs I");
  ExpectClose(ra.h, rb.h, "Rhs h");
  ExpectClose(ra.Q, rb.Q, "Rhs Q");
  ExpectClose(ra.T, rb.T, "Rhs T");
  ExpectClose(ra.I, b.dynamics.I, "Rhs I against EvalDynamics");
  ExpectClose(a.shaking.F, b.shaking.F, "shaking F");
  ExpectClose(a.shaking.M, b.shaking.M, "shaking M");
  ExpectClose(a.shaking.F_link, b.shaking.F_link, "F_link");
  ExpectClose(a.shaking.M_link, b.shaking.M_link, "M_link");
  ExpectClose(a.shaking.r_G.rightCols(3), b.shaking.r_G.rightCols(3), "r_G");
  ExpectClose(a.shaking.mass, b.shaking.mass, "mass");
  ExpectClose(a.shaking.r_C, b.shaking.r_C, "r_C");
  // The kinetostatics is not the statics: the inertia forces are in.
  EXPECT_GT((a.kinetostatics.R - a.statics.R).norm(), 1e-3 * a.statics.R.norm());
}

TEST(PointMasses, FourbarAgreesWithTheMassesFoldedByHand) {
  const Point::ParamsT<double> p;
  for (double q : {0.3, 1.2, 2.5, 4.0, 5.5}) CompareAt(p, q, 2.0 - 0.3 * q, 0.7 * q - 1.5);
}

TEST(PointMasses, FourbarFollowsThePointMassesParametersAtRunTime) {
  Point::ParamsT<double> p;
  p.mw = 0.4;
  p.wx = -0.55;
  p.mp = 7.0;
  p.Jp = 0.05;
  p.py = -0.3;
  p.mk = 2.1;
  p.ky = 0.35;
  p.Jc = 0.0;
  p.m1 = 0.0;  // the crank is its counterweight alone: the combined centre divides by mw only
  for (double q : {0.9, 3.3, 5.0}) CompareAt(p, q, -1.5, 0.4);
  // The combined body's mass and centre move with them (shaking's per-link report).
  const auto a = Evaluate<Point>(p, 0.9, 0, 0);
  EXPECT_NEAR(a.shaking.mass, p.mw + p.mp + p.m3 + p.mc + p.mk, 1e-12);
  const double th = 0.9;  // the crank is the input: its centre is the counterweight's place
  EXPECT_NEAR(a.shaking.r_G(0, 1), p.wx * std::cos(th) - p.wy * std::sin(th), 1e-12);
  EXPECT_NEAR(a.shaking.r_G(1, 1), p.wx * std::sin(th) + p.wy * std::cos(th), 1e-12);
}

// A particle of a link: mass, own inertia, place in the link's frame.
struct Particle {
  double m, J, x, y;
};

// Newton–Euler of one link with its particles taken one by one (no combined body): the link's
// frame origin O at r_O with acceleration a_O, angle th, speed w, acceleration al; `forces` act
// at points given in the fixed frame, `torque` is a couple. Returns the residuals
// (sum F - sum m a, sum M_O - sum (rho x m a + J al)) in three numbers.
Eigen::Vector3d LinkBalance(const std::vector<Particle>& particles,
                            const Eigen::Vector2d& r_O,
                            const Eigen::Vector2d& a_O,
                            double th,
                            double w,
                            double al,
                            double g,
                            const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& forces,
                            double torque) {
  auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  Eigen::Vector2d F = Eigen::Vector2d::Zero();
  double M = torque;
  for (const auto& [at, f] : forces) {
    F += f;
    M += cross(at - r_O, f);
  }
  for (const Particle& k : particles) {
    const Eigen::Vector2d rho(std::cos(th) * k.x - std::sin(th) * k.y, std::sin(th) * k.x + std::cos(th) * k.y);
    const Eigen::Vector2d a = a_O + al * Eigen::Vector2d(-rho.y(), rho.x()) - w * w * rho;
    const Eigen::Vector2d weight(0, -k.m * g);
    F += weight - k.m * a;
    M += cross(rho, weight - k.m * a) - k.J * al;
  }
  return {F.x(), F.y(), M};
}

// The kinetostatic reactions and driving torque of the four-bar with point masses balance every
// link with each particle's own d'Alembert force (the link's own mass, each point mass), the
// accelerations from the link angles' velocity and centripetal coefficients K, L: an oracle
// without the combined body.
TEST(PointMasses, FourbarKinetostaticsBalanceEveryParticle) {
  Point::ParamsT<double> changed;
  changed.mp = 6.5;
  changed.wy = -0.4;
  changed.mk = 3.0;
  for (const Point::ParamsT<double>& p : {Point::ParamsT<double>(), changed}) {
    const std::vector<Particle> crank = {{p.m1, p.J1, p.a / 2, 0}, {p.mw, 0, p.wx, p.wy}};
    const std::vector<Particle> coupler = {{p.mp, p.Jp, p.px, p.py}};
    const std::vector<Particle> rocker = {{p.m3, p.J3, p.c / 2, 0.1}, {p.mc, p.Jc, p.c, 0}, {p.mk, 0, p.kx, p.ky}};
    for (double q0 : {0.4, 1.9, 3.1, 4.6}) {
      SCOPED_TRACE("theta_crank = " + std::to_string(q0));
      Eigen::Matrix<double, 1, 1> q, qd, qdd;
      q(0) = q0;
      qd(0) = 1.5 + 0.2 * q0;
      qdd(0) = -2.0 + 0.5 * q0;
      Eigen::Vector2d phi(Point::kAssemblyPhi[0], Point::kAssemblyPhi[1]);
      ASSERT_EQ(Point::Solve(p, q, &phi).status, mech::fourbar_point_masses::SolveStatus::kConverged);
      Point::CoefficientsT<double> c;
      Point::Coeffs(p, q, phi, &c);
      Point::StaticsT<double> s;
      Point::Kinetostatics(p, q, phi, qd, qdd, 0.0, c, &s);
      const Eigen::Vector2d w2 = c.K * qd(0), al2 = c.K * qdd(0) + c.L * qd(0) * qd(0);
      const double th1 = q0, w1 = qd(0), al1 = qdd(0);
      const Eigen::Vector2d A(0, 0), D(p.d, 0);
      const Eigen::Vector2d B(p.a * std::cos(th1), p.a * std::sin(th1));
      const Eigen::Vector2d a_B = al1 * Eigen::Vector2d(-B.y(), B.x()) - w1 * w1 * B;
      const Eigen::Vector2d C = D + p.c * Eigen::Vector2d(std::cos(phi(1)), std::sin(phi(1)));
      const Eigen::Vector2d R_A = s.R.segment<2>(0), R_B = s.R.segment<2>(2), R_C = s.R.segment<2>(4),
                            R_D = s.R.segment<2>(6);
      // A: ground on crank; B: crank on coupler; C: coupler on rocker; D: rocker on ground.
      const double scale = s.R.norm() + std::abs(s.drive(0));
      ASSERT_GT(scale, 10.0);
      const Eigen::Vector3d e1 =
          LinkBalance(crank, A, Eigen::Vector2d::Zero(), th1, w1, al1, p.g, {{A, R_A}, {B, -R_B}}, s.drive(0));
      const Eigen::Vector3d e2 = LinkBalance(coupler, B, a_B, phi(0), w2(0), al2(0), p.g, {{B, R_B}, {C, -R_C}}, 0);
      const Eigen::Vector3d e3 =
          LinkBalance(rocker, D, Eigen::Vector2d::Zero(), phi(1), w2(1), al2(1), p.g, {{C, R_C}, {D, -R_D}}, 0);
      EXPECT_LT(e1.norm(), 1e-12 * scale) << e1.transpose();
      EXPECT_LT(e2.norm(), 1e-12 * scale) << e2.transpose();
      EXPECT_LT(e3.norm(), 1e-12 * scale) << e3.transpose();
    }
  }
}

TEST(PointMasses, PendulumOfAMasslessArmIsItsHeadInClosedForm) {
  using M = mech::pendulum_point_mass::Model;
  for (const bool changed : {false, true}) {
    M::ParamsT<double> p;
    if (changed) {
      p.l = 1.3;
      p.mh = 0.8;
      p.Jh = 0.4;
    }
    const double l = p.l, m = p.mh, J = p.Jh, g = p.g, I = m * l * l + J;
    for (double th : {-2.5, -1.0, 0.0, 0.7, 2.0}) {
      SCOPED_TRACE("theta_arm = " + std::to_string(th));
      const double thd = 1.7 - 0.5 * th, thdd = -0.8 + 0.3 * th;
      const auto o = Evaluate<M>(p, th, thd, thdd);
      const double c = std::cos(th), s = std::sin(th);
      const double ax = l * (-s * thdd - c * thd * thd), ay = l * (c * thdd - s * thd * thd);
      ExpectClose(o.dynamics.I(0, 0), I, "I");
      ExpectClose(o.dynamics.C(0, 0), 0.0, "C");
      ExpectClose(o.dynamics.Q(0), -m * g * l * c, "Q");
      ExpectClose(o.dynamics.T, 0.5 * I * thd * thd, "T");
      ExpectClose(o.dynamics.V, m * g * l * s, "V");
      ExpectClose(o.statics.drive(0), m * g * l * c, "static drive");
      ExpectClose(o.statics.R(0), 0.0, "static R_x");
      ExpectClose(o.statics.R(1), m * g, "static R_y");
      ExpectClose(o.kinetostatics.drive(0), I * thdd + m * g * l * c, "kinetostatic drive");
      ExpectClose(o.kinetostatics.R(0), m * ax, "kinetostatic R_x");
      ExpectClose(o.kinetostatics.R(1), m * ay + m * g, "kinetostatic R_y");
      ExpectClose(o.shaking.mass, m, "mass");
      ExpectClose(o.shaking.r_G(0, 1), l * c, "r_G x");
      ExpectClose(o.shaking.r_G(1, 1), l * s, "r_G y");
      ExpectClose(o.shaking.F(0), -m * ax, "shaking F_x");
      ExpectClose(o.shaking.F(1), -m * ay, "shaking F_y");
      ExpectClose(o.shaking.M, -(l * c * m * ay - l * s * m * ax + J * thdd), "shaking M");
    }
  }
}

}  // namespace
