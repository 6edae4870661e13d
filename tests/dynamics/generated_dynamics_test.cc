// The generated dynamics (EvalDynamics, EvalKinetostatics; issue 15, Paul ch. 6) of
// models/fourbar_massive.yaml, models/slider_crank_motor.yaml and the test models pendulum.yaml
// (kNphi = 0) and slider_crank_torque.yaml, against oracles written here from the models' text:
//  - the centres of mass and link angles come from the scene points (EvalScene of the solved
//    positions) and the mass data of the model files, written out below by hand;
//  - I(q) = 2 T(q, qd = 1) with T = sum 1/2 m |v_G|^2 + 1/2 J w^2, the velocities by central
//    differences (fourth order) of those positions along the motion; dI/dq by central
//    differences of that I; C = dI/dq / 2 (one DOF), h = C qd^2, T = 1/2 I qd^2;
//  - V = sum m g y_G by hand, Q = -dV/dq by central differences (plus the crank torque M of the
//    slider-crank), P_nc = (Q + dV/dq) qd;
//  - the motor-driven slider-crank: Q against the virtual work of the motor's table (interpolated
//    here), the gas force, the damper (c (dl/dq)^2 qd), the viscous bearing and the weights;
//  - tests/dynamics/models/damped_fourbar.yaml: Q of a torsional damper, viscous joint friction, a
//    linear damper, a load of time and a load of a dependent velocity against their virtual work
//    written out here with the links' velocity coefficients by differences; the same loads in
//    the excess-coordinate g against the virtual work per unit dx;
//  - tests/dynamics/models/fivebar_massive.yaml (two inputs): the 2 x 2 I by polarization of T,
//    dI/dq by differences of it, C against the Christoffel symbols of I,
//    C(j, k, l) = (dI_jk/dq_l + dI_jl/dq_k - dI_kl/dq_j) / 2, Q = -dV/dq;
//  - the excess-coordinate formulation: M by polarization of the kinetic energy, h and gamma by
//    second differences along x(t) = x + xd t, Phi_x by differences of Phi, g = -dV/dx;
//  - the kinetostatics: every moving link of the four-bar and of the pendulum obeys Newton–Euler
//    (sum F = m a_G, sum M_G = J alpha) with the generated reactions and driving torque, the
//    accelerations by second differences of the positions along q(t) = q0 + qd t + qdd t^2 / 2.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "damped_fourbar.h"
#include "fivebar_massive.h"
#include "fourbar_massive.h"
#include "pendulum.h"
#include "slider_crank_motor.h"
#include "slider_crank_torque.h"

namespace {

// One moving link's mass data and how to find its centre of mass and angle from the scene.
struct Body {
  int link;  // index into kLinkNames
  double m, J;
  std::function<void(const Eigen::MatrixXd& scene, Eigen::Vector2d* rG, double* theta)> where;
};

template <class M>
int ScenePoint(const char* name) {
  for (int i = 0; i < M::kNumScenePoints; ++i)
    if (std::strcmp(M::kScenePointNames[i], name) == 0) return i;
  ADD_FAILURE() << "no scene point " << name;
  return 0;
}

// A bar between scene points a and b (uniform: G at the fraction f from a).
template <class M>
Body Bar(int link, const char* a, const char* b, double m, double J, double f = 0.5) {
  const int ia = ScenePoint<M>(a), ib = ScenePoint<M>(b);
  return {link, m, J, [ia, ib, f](const Eigen::MatrixXd& s, Eigen::Vector2d* rG, double* th) {
            const Eigen::Vector2d A = s.col(ia), B = s.col(ib);
            *rG = A + f * (B - A);
            *th = std::atan2(B.y() - A.y(), B.x() - A.x());
          }};
}

template <class M>
struct Harness {
  using P = typename M::template ParamsT<double>;
  using Vq = Eigen::Matrix<double, M::kNq, 1>;
  using Vphi = Eigen::Matrix<double, M::kNphi, 1>;
  P p;
  std::vector<Body> bodies;
  double g = 0;  // gravity along -y
  Vphi guess;

  Harness() {
    for (int i = 0; i < M::kNphi; ++i) guess(i) = M::kAssemblyPhi[i];
  }
  Vphi Solve(double q) {
    Vq qq;
    qq(0) = q;
    Vphi phi = guess;
    const auto report = M::Solve(p, qq, &phi);
    EXPECT_EQ(report.status, decltype(report.status)::kConverged);
    return phi;
  }
  Eigen::MatrixXd Scene(double q) {
    Vq qq;
    qq(0) = q;
    const Vphi phi = Solve(q);
    Eigen::Matrix<double, 2, M::kNumScenePoints> r;
    M::Scene(p, qq, phi, &r);
    return r;
  }
  // The scene at any (q, phi), closed or not (the excess-coordinate formulation's x).
  Eigen::MatrixXd SceneAt(const Vq& q, const Vphi& phi) {
    Eigen::Matrix<double, 2, M::kNumScenePoints> r;
    M::Scene(p, q, phi, &r);
    return r;
  }
  // Centres of mass and angles of every body at q.
  void Where(double q, std::vector<Eigen::Vector2d>* rG, std::vector<double>* th) {
    const Eigen::MatrixXd s = Scene(q);
    rG->resize(bodies.size());
    th->resize(bodies.size());
    for (size_t b = 0; b < bodies.size(); ++b) bodies[b].where(s, &(*rG)[b], &(*th)[b]);
  }
  // Fourth-order central difference of the positions along q: d/dq (r_G, theta) at q.
  void Rates(double q, std::vector<Eigen::Vector2d>* v, std::vector<double>* w, double h = 1e-3) {
    std::vector<Eigen::Vector2d> r[4];
    std::vector<double> t[4];
    const double at[4] = {q - 2 * h, q - h, q + h, q + 2 * h};
    for (int i = 0; i < 4; ++i) Where(at[i], &r[i], &t[i]);
    v->resize(bodies.size());
    w->resize(bodies.size());
    for (size_t b = 0; b < bodies.size(); ++b) {
      (*v)[b] = (r[0][b] - 8 * r[1][b] + 8 * r[2][b] - r[3][b]) / (12 * h);
      (*w)[b] = (t[0][b] - 8 * t[1][b] + 8 * t[2][b] - t[3][b]) / (12 * h);
    }
  }
  double InertiaOracle(double q) {
    std::vector<Eigen::Vector2d> v;
    std::vector<double> w;
    Rates(q, &v, &w);
    double I = 0;
    for (size_t b = 0; b < bodies.size(); ++b) I += bodies[b].m * v[b].squaredNorm() + bodies[b].J * w[b] * w[b];
    return I;
  }
  double dInertiaOracle(double q, double h = 1e-3) {
    return (InertiaOracle(q - 2 * h) - 8 * InertiaOracle(q - h) + 8 * InertiaOracle(q + h) - InertiaOracle(q + 2 * h)) /
           (12 * h);
  }
  double PotentialOracle(double q) {
    std::vector<Eigen::Vector2d> r;
    std::vector<double> t;
    Where(q, &r, &t);
    double V = 0;
    for (size_t b = 0; b < bodies.size(); ++b) V += bodies[b].m * g * r[b].y();
    return V;
  }
  double dPotentialOracle(double q, double h = 1e-3) {
    return (PotentialOracle(q - 2 * h) - 8 * PotentialOracle(q - h) + 8 * PotentialOracle(q + h) -
            PotentialOracle(q + 2 * h)) /
           (12 * h);
  }
  typename M::template DynamicsT<double> Dynamics(double q, double qd, double t = 0) {
    Vq qq, qqd;
    qq(0) = q;
    qqd(0) = qd;
    const Vphi phi = Solve(q);
    typename M::template CoefficientsT<double> c;
    M::Coeffs(p, qq, phi, &c);
    typename M::template DynamicsT<double> d;
    M::Dynamics(p, qq, phi, qqd, t, c, &d);
    return d;
  }
};

Harness<mech::fourbar_massive::Model> FourBar() {
  using M = mech::fourbar_massive::Model;
  Harness<M> h;
  const double rho = h.p.rho, a = h.p.a, b = h.p.b, c = h.p.c;
  h.g = h.p.g;
  h.bodies = {Bar<M>(1, "crank.A", "crank.B", rho * a, rho * a * a * a / 12),
              Bar<M>(2, "coupler.B", "coupler.C", rho * b, rho * b * b * b / 12),
              Bar<M>(3, "rocker.D", "rocker.C", rho * c, rho * c * c * c / 12)};
  return h;
}

Harness<mech::pendulum::Model> Pendulum() {
  using M = mech::pendulum::Model;
  Harness<M> h;
  h.g = h.p.g;
  h.bodies = {Bar<M>(1, "arm.O", "arm.P", h.p.m, h.p.J, h.p.lc / h.p.l)};
  return h;
}

Harness<mech::slider_crank_torque::Model> SliderCrank() {
  using M = mech::slider_crank_torque::Model;
  Harness<M> h;
  const auto& p = h.p;
  const int C = ScenePoint<M>("slider.C");
  h.bodies = {Bar<M>(1, "crank.O", "crank.B", p.m1, p.J1), Bar<M>(2, "rod.B", "rod.C", p.m2, p.m2 * p.b * p.b / 12),
              Body{3, p.m3, 0.001, [C](const Eigen::MatrixXd& s, Eigen::Vector2d* rG, double* th) {
                     *rG = s.col(C);
                     *th = 0;  // the slider keeps the guide's angle
                   }}};
  return h;
}

// I, dI/dq, C, h, T, V, Q, P_nc of one model over a turn of its input.
template <class M>
void CheckEquationOfMotion(Harness<M> h, double q0, double q1, double extra_Q) {
  for (int i = 0; i <= 12; ++i) {
    const double q = q0 + (q1 - q0) * i / 12.0, qd = 1.7 - 0.3 * i;
    const auto d = h.Dynamics(q, qd, 0.25);
    const double I = h.InertiaOracle(q), dI = h.dInertiaOracle(q);
    const double scale = std::max(1.0, std::abs(I));
    SCOPED_TRACE("q = " + std::to_string(q));
    EXPECT_NEAR(d.I(0, 0), I, 1e-8 * scale);
    EXPECT_NEAR(d.dI_dq(0, 0), dI, 1e-6 * scale);
    EXPECT_NEAR(d.C(0, 0), dI / 2, 1e-6 * scale);
    EXPECT_NEAR(d.h(0), dI / 2 * qd * qd, 1e-6 * scale * qd * qd);
    EXPECT_NEAR(d.T, I * qd * qd / 2, 1e-8 * scale * qd * qd);
    const double V = h.PotentialOracle(q), dV = h.dPotentialOracle(q);
    const double fscale = std::max(1.0, std::abs(dV) + std::abs(extra_Q));
    EXPECT_NEAR(d.V, V, 1e-9 * std::max(1.0, std::abs(V)));
    EXPECT_NEAR(d.Q(0), -dV + extra_Q, 1e-7 * fscale);
    EXPECT_NEAR(d.P_nc, extra_Q * qd, 1e-7 * fscale * std::abs(qd) + 1e-12);
  }
}

TEST(GeneratedDynamics, FourBarInertiaAndForcesAgainstFiniteDifferences) {
  CheckEquationOfMotion(FourBar(), 0.1, 6.2, 0.0);
}

TEST(GeneratedDynamics, PendulumWithoutDependentCoordinates) {
  static_assert(mech::pendulum::Model::kNphi == 0, "a pendulum has no loop");
  auto h = Pendulum();
  CheckEquationOfMotion(h, -3.0, 3.0, 0.0);
  // Closed forms: I = J + m lc^2, constant; V = m g lc sin(theta).
  const auto d = h.Dynamics(0.4, 2.0);
  EXPECT_NEAR(d.I(0, 0), h.p.J + h.p.m * h.p.lc * h.p.lc, 1e-14);
  EXPECT_NEAR(d.dI_dq(0, 0), 0.0, 1e-14);
  EXPECT_NEAR(d.Q(0), -h.p.m * h.p.g * h.p.lc * std::cos(0.4), 1e-13);
}

TEST(GeneratedDynamics, SliderCrankUnderAConstantTorque) {
  auto h = SliderCrank();
  CheckEquationOfMotion(h, 0.0, 6.2, h.p.M);
}

TEST(GeneratedDynamics, FloatInstantiationAgreesWithDouble) {
  using M = mech::fourbar_massive::Model;
  auto h = FourBar();
  const double q = 1.2, qd = -0.8;
  const auto d = h.Dynamics(q, qd);
  Eigen::Matrix<float, 1, 1> qf, qdf;
  qf(0) = static_cast<float>(q);
  qdf(0) = static_cast<float>(qd);
  const auto pf = h.p.template Cast<float>();
  Eigen::Matrix<float, M::kNphi, 1> phi = h.Solve(q).template cast<float>();
  M::CoefficientsT<float> c;
  M::Coeffs(pf, qf, phi, &c);
  M::DynamicsT<float> df;
  M::Dynamics(pf, qf, phi, qdf, 0.0f, c, &df);
  EXPECT_NEAR(df.I(0, 0), d.I(0, 0), 1e-4 * std::abs(d.I(0, 0)));
  EXPECT_NEAR(df.Q(0), d.Q(0), 1e-4 * std::abs(d.Q(0)) + 1e-3);
}

// ---- kinetostatics: Newton–Euler of every link with the generated reactions ----

struct Pin {
  int reaction;        // index of F_J_x in R (F_J_y follows)
  int link_a, link_b;  // R is the force of link_a on link_b
  const char* point;   // a scene point at the pin
};

template <class M>
void CheckNewtonEuler(Harness<M> h, const std::vector<Pin>& pins, int input_link) {
  using Vq = Eigen::Matrix<double, 1, 1>;
  for (int i = 0; i < 8; ++i) {
    const double q0 = 0.3 + 0.75 * i, qd = 1.5 - 0.4 * i, qdd = -2.0 + 0.7 * i;
    SCOPED_TRACE("q = " + std::to_string(q0));
    // Accelerations of the bodies along q(t) = q0 + qd t + qdd t^2 / 2 (fourth-order second differences).
    const double dt = 1e-3;
    std::vector<Eigen::Vector2d> r[5];
    std::vector<double> th[5];
    for (int s = -2; s <= 2; ++s) {
      const double t = s * dt;
      h.Where(q0 + qd * t + qdd * t * t / 2, &r[s + 2], &th[s + 2]);
    }
    Vq q, vqd, vqdd;
    q(0) = q0;
    vqd(0) = qd;
    vqdd(0) = qdd;
    const auto phi = h.Solve(q0);
    typename M::template CoefficientsT<double> c;
    M::Coeffs(h.p, q, phi, &c);
    typename M::template StaticsT<double> st;
    M::Kinetostatics(h.p, q, phi, vqd, vqdd, 0.0, c, &st);
    const Eigen::MatrixXd scene = h.Scene(q0);
    double scale = 1;
    for (int k = 0; k < M::kNumReactions; ++k) scale = std::max(scale, std::abs(st.R(k)));
    for (size_t b = 0; b < h.bodies.size(); ++b) {
      const Body& body = h.bodies[b];
      const Eigen::Vector2d a = (-r[0][b] + 16 * r[1][b] - 30 * r[2][b] + 16 * r[3][b] - r[4][b]) / (12 * dt * dt);
      const double alpha = (-th[0][b] + 16 * th[1][b] - 30 * th[2][b] + 16 * th[3][b] - th[4][b]) / (12 * dt * dt);
      const Eigen::Vector2d G = r[2][b];
      Eigen::Vector2d F(0, -body.m * h.g);
      double MG = 0;
      for (const Pin& pin : pins) {
        const double sign = pin.link_b == body.link ? 1 : pin.link_a == body.link ? -1 : 0;
        if (sign == 0) continue;
        const Eigen::Vector2d f = sign * Eigen::Vector2d(st.R(pin.reaction), st.R(pin.reaction + 1));
        const Eigen::Vector2d arm = scene.col(ScenePoint<M>(pin.point)) - G;
        F += f;
        MG += arm.x() * f.y() - arm.y() * f.x();
      }
      if (body.link == input_link) MG += st.drive(0);  // the actuator's torque on the input link
      const Eigen::Vector2d residual = F - body.m * a;
      EXPECT_NEAR(residual.x(), 0.0, 1e-6 * scale) << M::kLinkNames[body.link];
      EXPECT_NEAR(residual.y(), 0.0, 1e-6 * scale) << M::kLinkNames[body.link];
      EXPECT_NEAR(MG - body.J * alpha, 0.0, 1e-6 * scale) << M::kLinkNames[body.link];
    }
  }
}

TEST(GeneratedKinetostatics, FourBarLinksObeyNewtonEulerWithTheReactions) {
  using M = mech::fourbar_massive::Model;
  static_assert(M::kNumReactions == 8, "F_A, F_B, F_C, F_D");
  // A: ground -> crank, B: crank -> coupler, C: coupler -> rocker, D: rocker -> ground.
  CheckNewtonEuler(FourBar(),
                   {{0, 0, 1, "crank.A"}, {2, 1, 2, "crank.B"}, {4, 2, 3, "rocker.C"}, {6, 3, 0, "rocker.D"}}, 1);
}

TEST(GeneratedKinetostatics, PendulumPinForce) { CheckNewtonEuler(Pendulum(), {{0, 0, 1, "arm.O"}}, 1); }

TEST(GeneratedKinetostatics, DriveIsTheInverseDynamics) {
  // drive = I qdd + h - Q_applied with I, I' from the energy oracle (slider-crank: Q_applied = M).
  using M = mech::slider_crank_torque::Model;
  auto h = SliderCrank();
  for (int i = 0; i < 6; ++i) {
    const double q0 = 0.2 + i, qd = 3.0 - i, qdd = 1.5 - 0.5 * i;
    Eigen::Matrix<double, 1, 1> q, vqd, vqdd;
    q(0) = q0;
    vqd(0) = qd;
    vqdd(0) = qdd;
    const auto phi = h.Solve(q0);
    M::CoefficientsT<double> c;
    M::Coeffs(h.p, q, phi, &c);
    M::StaticsT<double> st;
    M::Kinetostatics(h.p, q, phi, vqd, vqdd, 0.0, c, &st);
    const double I = h.InertiaOracle(q0), dI = h.dInertiaOracle(q0);
    EXPECT_NEAR(st.drive(0), I * qdd + dI / 2 * qd * qd - h.p.M,
                1e-6 * (1 + std::abs(I * qdd) + std::abs(dI * qd * qd)));
    EXPECT_NEAR(st.Q(0), -st.drive(0), 1e-12);
  }
}

// ---- the motor-driven slider-crank: loads of speed, a table, a damper, viscous friction ----

// The model's motor_curve, interpolated here (clamped outside its range).
double MotorCurve(double w) {
  const double x[] = {0, 20, 40, 60, 80, 100, 110, 120, 130, 135, 140, 145, 150, 153, 157.0796};
  const double y[] = {23.077, 26.129, 30.037, 35.152, 41.942, 50.691, 55.405, 59.185,
                      59.344, 56.453, 50.356, 40.198, 25.735, 15.325, 0};
  if (w <= x[0]) return y[0];
  if (w >= x[14]) return y[14];
  int k = 0;
  while (w >= x[k + 1]) ++k;
  return y[k] + (y[k + 1] - y[k]) * (w - x[k]) / (x[k + 1] - x[k]);
}

TEST(GeneratedDynamics, MotorDrivenSliderCrankForcesAgainstVirtualWork) {
  using M = mech::slider_crank_motor::Model;
  Harness<M> h;
  const auto& p = h.p;
  h.g = p.g;
  const int C = ScenePoint<M>("piston.C");
  h.bodies = {Bar<M>(1, "crank.O", "crank.B", p.m1, p.J_fly, 0.0),
              Bar<M>(2, "rod.B", "rod.C", p.m2, p.m2 * p.b * p.b / 12),
              Body{3, p.m3, 0.001, [C](const Eigen::MatrixXd& s, Eigen::Vector2d* rG, double* th) {
                     *rG = s.col(C);
                     *th = 0;
                   }}};
  auto xC = [&](double q) { return h.Scene(q)(0, C); };
  for (int i = 0; i < 10; ++i) {
    const double q = 0.2 + 0.6 * i, qd = -20.0 + 19.0 * i;  // speeds from -20 to 151 rad/s
    SCOPED_TRACE("q = " + std::to_string(q) + ", qd = " + std::to_string(qd));
    const double dh = 1e-4;
    const double dx = (xC(q + dh) - xC(q - dh)) / (2 * dh);
    const double x = xC(q);
    const double l = p.xH - x;  // the damper's length from H to the piston
    const double dl = -dx;
    const double gas = -p.P0 * p.h / (p.h + p.a + p.b - x);
    const double Q = MotorCurve(qd) + gas * dx - p.c * dl * dl * qd - p.cO * qd - h.dPotentialOracle(q);
    (void)l;
    const auto d = h.Dynamics(q, qd, 1.0);
    EXPECT_NEAR(d.Q(0), Q, 1e-6 * (1 + std::abs(Q)));
    EXPECT_NEAR(d.P_nc, (Q + h.dPotentialOracle(q)) * qd, 1e-6 * (1 + std::abs(Q * qd)));
    EXPECT_NEAR(d.I(0, 0), h.InertiaOracle(q), 1e-8 * h.InertiaOracle(q));
  }
  // The table itself, with its clamping.
  EXPECT_NEAR(mech::slider_crank_motor::Table_motor_curve(-5.0, 0), 23.077, 1e-12);
  EXPECT_NEAR(mech::slider_crank_motor::Table_motor_curve(200.0, 0), 0.0, 1e-12);
  EXPECT_NEAR(mech::slider_crank_motor::Table_motor_curve(132.5, 0), (59.344 + 56.453) / 2, 1e-12);
  EXPECT_NEAR(mech::slider_crank_motor::Table_motor_curve(132.5, 1), (56.453 - 59.344) / 5, 1e-12);
}

// ---- the excess-coordinate formulation ----

TEST(GeneratedExcess, FourBarAgainstDifferencesOfEnergyAndConstraints) {
  using M = mech::fourbar_massive::Model;
  constexpr int n = M::kNq + M::kNphi;
  auto h = FourBar();
  using Vx = Eigen::Matrix<double, n, 1>;
  auto split = [](const Vx& x, Eigen::Matrix<double, 1, 1>* q, Eigen::Matrix<double, 2, 1>* phi) {
    (*q)(0) = x(0);
    *phi = x.tail<2>();
  };
  // Centres of mass at any x.
  auto where = [&](const Vx& x, std::vector<Eigen::Vector2d>* r, std::vector<double>* th) {
    Eigen::Matrix<double, 1, 1> q;
    Eigen::Matrix<double, 2, 1> phi;
    split(x, &q, &phi);
    const Eigen::MatrixXd s = h.SceneAt(q, phi);
    r->resize(h.bodies.size());
    th->resize(h.bodies.size());
    for (size_t b = 0; b < h.bodies.size(); ++b) h.bodies[b].where(s, &(*r)[b], &(*th)[b]);
  };
  auto kinetic = [&](const Vx& x, const Vx& xd) {  // fourth-order differences along x + xd t
    const double e = 1e-3;
    std::vector<Eigen::Vector2d> r[4];
    std::vector<double> t[4];
    const double at[4] = {-2 * e, -e, e, 2 * e};
    for (int i = 0; i < 4; ++i) where(x + at[i] * xd, &r[i], &t[i]);
    double T = 0;
    for (size_t b = 0; b < h.bodies.size(); ++b) {
      const Eigen::Vector2d v = (r[0][b] - 8 * r[1][b] + 8 * r[2][b] - r[3][b]) / (12 * e);
      const double w = (t[0][b] - 8 * t[1][b] + 8 * t[2][b] - t[3][b]) / (12 * e);
      T += 0.5 * h.bodies[b].m * v.squaredNorm() + 0.5 * h.bodies[b].J * w * w;
    }
    return T;
  };
  auto residual = [&](const Vx& x) {
    Eigen::Matrix<double, 1, 1> q;
    Eigen::Matrix<double, 2, 1> phi;
    split(x, &q, &phi);
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(h.p, q, phi, &Phi);
    return Phi;
  };
  for (int i = 0; i < 4; ++i) {
    // Not on the constraint manifold: the formulation holds at any x.
    Vx x(0.4 + i, 0.5 - 0.1 * i, 1.9 + 0.05 * i), xd(1.0 - 0.4 * i, 0.3, -0.7 + 0.2 * i);
    Eigen::Matrix<double, 1, 1> q, qd;
    Eigen::Matrix<double, 2, 1> phi, phid;
    split(x, &q, &phi);
    split(xd, &qd, &phid);
    M::ExcessT<double> ex;
    M::ExcessDynamics(h.p, q, phi, qd, phid, 0.0, &ex);
    // M by polarization of T(x, xd).
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const Vx ea = Vx::Unit(a), eb = Vx::Unit(b);
        const double Mab = a == b ? 2 * kinetic(x, ea) : kinetic(x, ea + eb) - kinetic(x, ea) - kinetic(x, eb);
        EXPECT_NEAR(ex.M(a, b), Mab, 1e-7) << a << ", " << b;
      }
    EXPECT_NEAR(ex.T, kinetic(x, xd), 1e-7);
    // h(a) = sum m dr_G/dx_a . (the acceleration of G along x + xd t); g = -dV/dx.
    const double e = 1e-3;
    std::vector<Eigen::Vector2d> r[5];
    std::vector<double> th[5];
    for (int s = -2; s <= 2; ++s) where(x + s * e * xd, &r[s + 2], &th[s + 2]);
    for (int a = 0; a < n; ++a) {
      std::vector<Eigen::Vector2d> ra[4];
      std::vector<double> ta[4];
      const double at[4] = {-2 * e, -e, e, 2 * e};
      for (int k = 0; k < 4; ++k) where(x + at[k] * Vx::Unit(a), &ra[k], &ta[k]);
      double ha = 0, ga = 0;
      for (size_t b = 0; b < h.bodies.size(); ++b) {
        const Eigen::Vector2d J = (ra[0][b] - 8 * ra[1][b] + 8 * ra[2][b] - ra[3][b]) / (12 * e);
        const Eigen::Vector2d acc = (-r[0][b] + 16 * r[1][b] - 30 * r[2][b] + 16 * r[3][b] - r[4][b]) / (12 * e * e);
        ha += h.bodies[b].m * J.dot(acc);
        ga += -h.bodies[b].m * h.g * J.y();
      }
      EXPECT_NEAR(ex.h(a), ha, 1e-6 * (1 + std::abs(ha))) << a;
      EXPECT_NEAR(ex.g(a), ga, 1e-7 * (1 + std::abs(ga))) << a;
      // Phi_x by differences of Phi.
      const Eigen::Matrix<double, M::kNc, 1> dPhi =
          (residual(x - 2 * e * Vx::Unit(a)) - 8 * residual(x - e * Vx::Unit(a)) + 8 * residual(x + e * Vx::Unit(a)) -
           residual(x + 2 * e * Vx::Unit(a))) /
          (12 * e);
      for (int rr = 0; rr < M::kNc; ++rr) EXPECT_NEAR(ex.Phi_x(rr, a), dPhi(rr), 1e-8);
    }
    // gamma = -d2Phi/dt2 along x + xd t; Phi itself.
    const Eigen::Matrix<double, M::kNc, 1> d2 =
        (-residual(x - 2 * e * xd) + 16 * residual(x - e * xd) - 30 * residual(x) + 16 * residual(x + e * xd) -
         residual(x + 2 * e * xd)) /
        (12 * e * e);
    for (int rr = 0; rr < M::kNc; ++rr) {
      EXPECT_NEAR(ex.gamma(rr), -d2(rr), 1e-6);
      EXPECT_NEAR(ex.Phi(rr), residual(x)(rr), 1e-14);
    }
    EXPECT_NEAR(
        ex.V,
        [&] {
          std::vector<Eigen::Vector2d> rr;
          std::vector<double> tt;
          where(x, &rr, &tt);
          double V = 0;
          for (size_t b = 0; b < h.bodies.size(); ++b) V += h.bodies[b].m * h.g * rr[b].y();
          return V;
        }(),
        1e-10);
  }
}

// The motor-driven slider-crank's kinetostatics: every link in Newton–Euler balance with the
// generated reactions (pins O, B, C; the slide's N, T, M), the motor's torque (the table, at
// qd), the viscous bearing torque, the gas force and the damper's force written out here.
TEST(GeneratedKinetostatics, MotorDrivenSliderCrankWithSpeedLoads) {
  using M = mech::slider_crank_motor::Model;
  static_assert(M::kNumReactions == 9, "F_O, F_B, F_C, N_slide, T_slide, M_slide");
  Harness<M> h;
  const auto& p = h.p;
  h.g = p.g;
  const int iO = ScenePoint<M>("crank.O"), iB = ScenePoint<M>("crank.B"), iC = ScenePoint<M>("piston.C"),
            iH = ScenePoint<M>("ground.H");
  h.bodies = {Bar<M>(1, "crank.O", "crank.B", p.m1, p.J_fly, 0.0),
              Bar<M>(2, "rod.B", "rod.C", p.m2, p.m2 * p.b * p.b / 12),
              Body{3, p.m3, 0.001, [iC](const Eigen::MatrixXd& s, Eigen::Vector2d* rG, double* th) {
                     *rG = s.col(iC);
                     *th = 0;
                   }}};
  for (int i = 0; i < 6; ++i) {
    const double q0 = 0.4 + i, qd = 30.0 + 20 * i, qdd = 40.0 - 15 * i;
    SCOPED_TRACE("q = " + std::to_string(q0));
    const double dt = 1e-4;
    std::vector<Eigen::Vector2d> r[5];
    std::vector<double> th[5];
    for (int s2 = -2; s2 <= 2; ++s2) {
      const double t = s2 * dt;
      h.Where(q0 + qd * t + qdd * t * t / 2, &r[s2 + 2], &th[s2 + 2]);
    }
    Eigen::Matrix<double, 1, 1> q, vqd, vqdd;
    q(0) = q0;
    vqd(0) = qd;
    vqdd(0) = qdd;
    const auto phi = h.Solve(q0);
    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    M::StaticsT<double> st;
    M::Kinetostatics(p, q, phi, vqd, vqdd, 0.0, c, &st);
    const Eigen::MatrixXd s = h.Scene(q0);
    const Eigen::Vector2d O = s.col(iO), B = s.col(iB), C = s.col(iC), H = s.col(iH);
    const Eigen::Vector2d FO(st.R(0), st.R(1)), FB(st.R(2), st.R(3)), FC(st.R(4), st.R(5));
    const double N = st.R(6), T = st.R(7), Mslide = st.R(8);
    // The piston's speed along x by differences, for the damper.
    const double vC = (r[3][2].x() - r[1][2].x()) / (2 * dt);
    const Eigen::Vector2d u = (C - H).normalized();
    const double ldot = vC * u.x();
    const Eigen::Vector2d damper = -p.c * ldot * u;  // on the piston
    const Eigen::Vector2d gas(-p.P0 * p.h / (p.h + p.a + p.b - C.x()), 0);
    const double motor = MotorCurve(qd), viscous = -p.cO * qd;
    auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
    double scale = 1;
    for (int k = 0; k < M::kNumReactions; ++k) scale = std::max(scale, std::abs(st.R(k)));
    for (size_t b = 0; b < 3; ++b) {
      const Body& body = h.bodies[b];
      const Eigen::Vector2d a = (-r[0][b] + 16 * r[1][b] - 30 * r[2][b] + 16 * r[3][b] - r[4][b]) / (12 * dt * dt);
      const double alpha = (-th[0][b] + 16 * th[1][b] - 30 * th[2][b] + 16 * th[3][b] - th[4][b]) / (12 * dt * dt);
      const Eigen::Vector2d G = r[2][b];
      Eigen::Vector2d F(0, -body.m * p.g);
      double MG = 0;
      if (b == 0) {  // crank: O (ground on crank), -B, the motor, the bearing, the actuator's drive
        F += FO - FB;
        MG += cross(O - G, FO) - cross(B - G, FB) + motor + viscous + st.drive(0);
      } else if (b == 1) {  // rod: B, -C
        F += FB - FC;
        MG += cross(B - G, FB) - cross(C - G, FC);
      } else {  // piston: C, the guide's N (along +y) and T (along +x), M; gas; damper
        F += FC + Eigen::Vector2d(T, N) + gas + damper;
        MG += Mslide;
      }
      const Eigen::Vector2d residual = F - body.m * a;
      EXPECT_NEAR(residual.x(), 0.0, 1e-5 * scale) << M::kLinkNames[body.link];
      EXPECT_NEAR(residual.y(), 0.0, 1e-5 * scale) << M::kLinkNames[body.link];
      EXPECT_NEAR(MG - body.J * alpha, 0.0, 1e-5 * scale) << M::kLinkNames[body.link];
    }
    EXPECT_NEAR(T, 0.0, 1e-6 * scale);  // no actuator or friction along the slide
  }
}

// ---- dampers, viscous friction, loads of time and of a dependent velocity ----

TEST(GeneratedDynamics, DampersAndLoadsOfTimeAndSpeedAgainstVirtualWork) {
  using M = mech::damped_fourbar::Model;
  Harness<M> h;
  const auto& p = h.p;
  const int iA = ScenePoint<M>("crank.A"), iB = ScenePoint<M>("crank.B"), iC = ScenePoint<M>("coupler.C"),
            iD = ScenePoint<M>("rocker.D"), iP = ScenePoint<M>("coupler.P"), iE = ScenePoint<M>("ground.E");
  // Link angles and the damper's length at q, from the scene.
  auto angles = [&](double q, double* t1, double* t2, double* t3, double* l) {
    const Eigen::MatrixXd s = h.Scene(q);
    const Eigen::Vector2d A = s.col(iA), B = s.col(iB), C = s.col(iC), D = s.col(iD), P = s.col(iP), E = s.col(iE);
    *t1 = std::atan2(B.y() - A.y(), B.x() - A.x());
    *t2 = std::atan2(C.y() - B.y(), C.x() - B.x());
    *t3 = std::atan2(C.y() - D.y(), C.x() - D.x());
    *l = (P - E).norm();
  };
  for (int i = 0; i < 8; ++i) {
    const double q = 0.3 + 0.75 * i, qd = -2.0 + 0.9 * i, t = 0.37 * i;
    SCOPED_TRACE("q = " + std::to_string(q));
    const double e = 1e-4;
    double a1, a2, a3, al, b1, b2, b3, bl;
    angles(q - e, &a1, &a2, &a3, &al);
    angles(q + e, &b1, &b2, &b3, &bl);
    auto wrap = [](double x) { return std::remainder(x, 6.283185307179586); };
    const double K1 = wrap(b1 - a1) / (2 * e), K2 = wrap(b2 - a2) / (2 * e), K3 = wrap(b3 - a3) / (2 * e),
                 Kl = (bl - al) / (2 * e);
    // Virtual work per unit dq: each load times the velocity coefficient it works through.
    const double Q = -p.cB * (K2 - K1) * qd * (K2 - K1)   // torsional damper at B
                     - p.cC * (K3 - K2) * qd * (K3 - K2)  // viscous friction at C
                     - p.cE * Kl * qd * Kl                // linear damper E-P
                     + p.T0 * std::sin(p.w * t) * K3      // the harmonic torque on the rocker
                     - p.kr * K3 * qd * K3;               // the rocker's drag
    const auto d = h.Dynamics(q, qd, t);
    EXPECT_NEAR(d.Q(0), Q, 1e-7 * (1 + std::abs(Q)));
    EXPECT_NEAR(d.V, 0.0, 1e-14);
    EXPECT_NEAR(d.P_nc, Q * qd, 1e-7 * (1 + std::abs(Q * qd)));
    // The excess-coordinate g at the same (closed) configuration and velocities: its virtual
    // work along the motion, g . (dx/dq), is Q.
    Eigen::Matrix<double, 1, 1> vq, vqd;
    vq(0) = q;
    vqd(0) = qd;
    const auto phi = h.Solve(q);
    Eigen::Matrix<double, 2, 1> phid(K2 * qd, K3 * qd);
    M::ExcessT<double> ex;
    M::ExcessDynamics(p, vq, phi, vqd, phid, t, &ex);
    EXPECT_NEAR(ex.g(0) + ex.g(1) * K2 + ex.g(2) * K3, Q, 1e-7 * (1 + std::abs(Q)));
  }
}

// ---- two degrees of freedom ----

TEST(GeneratedDynamics, FiveBarTwoInputsAgainstEnergyAndChristoffelSymbols) {
  using M = mech::fivebar_massive::Model;
  static_assert(M::kNq == 2, "two inputs");
  using V2 = Eigen::Matrix<double, 2, 1>;
  M::ParamsT<double> p;
  // Each body: mass, J, the scene points of its frame's origin and axis point, G in its frame.
  struct Link {
    double m, J;
    const char *origin, *axis;
    double cx, cy;
  };
  const Link links[] = {{1.0, 0.1, "crank1.A", "crank1.B", 0.4, 0.05},
                        {2.5, 1.3, "link1.B", "link1.C", 1.2, -0.1},
                        {2.0, 0.7, "link2.D", "link2.C", 1.0, 0.15},
                        {1.2, 0.12, "crank2.E", "crank2.D", 0.5, 0.0}};
  Eigen::Matrix<double, M::kNphi, 1> guess;
  for (int i = 0; i < M::kNphi; ++i) guess(i) = M::kAssemblyPhi[i];
  auto where = [&](const V2& q, std::vector<Eigen::Vector2d>* r, std::vector<double>* th) {
    Eigen::Matrix<double, M::kNphi, 1> phi = guess;
    EXPECT_EQ(M::Solve(p, q, &phi).status, mech::fivebar_massive::SolveStatus::kConverged);
    Eigen::Matrix<double, 2, M::kNumScenePoints> s;
    M::Scene(p, q, phi, &s);
    r->clear();
    th->clear();
    for (const Link& l : links) {
      const Eigen::Vector2d O = s.col(ScenePoint<M>(l.origin)), X = s.col(ScenePoint<M>(l.axis));
      const double t = std::atan2(X.y() - O.y(), X.x() - O.x());
      r->push_back(O +
                   Eigen::Vector2d(std::cos(t) * l.cx - std::sin(t) * l.cy, std::sin(t) * l.cx + std::cos(t) * l.cy));
      th->push_back(t);
    }
  };
  auto kinetic = [&](const V2& q, const V2& qd) {
    const double e = 1e-3;
    std::vector<Eigen::Vector2d> r[4];
    std::vector<double> t[4];
    const double at[4] = {-2 * e, -e, e, 2 * e};
    for (int i = 0; i < 4; ++i) where(q + at[i] * qd, &r[i], &t[i]);
    double T = 0;
    for (size_t b = 0; b < 4; ++b) {
      const Eigen::Vector2d v = (r[0][b] - 8 * r[1][b] + 8 * r[2][b] - r[3][b]) / (12 * e);
      const double w = (t[0][b] - 8 * t[1][b] + 8 * t[2][b] - t[3][b]) / (12 * e);
      T += 0.5 * links[b].m * v.squaredNorm() + 0.5 * links[b].J * w * w;
    }
    return T;
  };
  auto inertia = [&](const V2& q) {
    Eigen::Matrix2d I;
    const V2 e0 = V2::Unit(0), e1 = V2::Unit(1);
    I(0, 0) = 2 * kinetic(q, e0);
    I(1, 1) = 2 * kinetic(q, e1);
    I(0, 1) = I(1, 0) = kinetic(q, e0 + e1) - kinetic(q, e0) - kinetic(q, e1);
    return I;
  };
  auto potential = [&](const V2& q) {
    std::vector<Eigen::Vector2d> r;
    std::vector<double> t;
    where(q, &r, &t);
    double V = 0;
    for (size_t b = 0; b < 4; ++b) V += links[b].m * p.g * r[b].y();
    return V;
  };
  for (int i = 0; i < 4; ++i) {
    const V2 q(1.4 + 0.25 * i, 1.2 - 0.2 * i), qd(0.8 - 0.5 * i, -0.3 + 0.4 * i);
    SCOPED_TRACE("case " + std::to_string(i));
    Eigen::Matrix<double, M::kNphi, 1> phi = guess;
    ASSERT_EQ(M::Solve(p, q, &phi).status, mech::fivebar_massive::SolveStatus::kConverged);
    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    M::DynamicsT<double> d;
    M::Dynamics(p, q, phi, qd, 0.0, c, &d);
    const Eigen::Matrix2d I = inertia(q);
    const double h = 1e-3;
    Eigen::Matrix2d dI[2];  // dI[l] = dI/dq_l
    for (int l = 0; l < 2; ++l) {
      const V2 e = V2::Unit(l);
      dI[l] = (inertia(q - 2 * h * e) - 8 * inertia(q - h * e) + 8 * inertia(q + h * e) - inertia(q + 2 * h * e)) /
              (12 * h);
    }
    for (int j = 0; j < 2; ++j) {
      for (int k = 0; k < 2; ++k) {
        EXPECT_NEAR(d.I(j, k), I(j, k), 1e-7) << j << k;
        for (int l = 0; l < 2; ++l) {
          EXPECT_NEAR(d.dI_dq(j, k + 2 * l), dI[l](j, k), 1e-5) << j << k << l;
          const double christoffel = 0.5 * (dI[l](j, k) + dI[k](j, l) - dI[j](k, l));
          EXPECT_NEAR(d.C(j, k + 2 * l), christoffel, 1e-5) << j << k << l;
        }
      }
      double hj = 0;
      for (int k = 0; k < 2; ++k)
        for (int l = 0; l < 2; ++l) hj += 0.5 * (dI[l](j, k) + dI[k](j, l) - dI[j](k, l)) * qd(k) * qd(l);
      EXPECT_NEAR(d.h(j), hj, 1e-5) << j;
      const V2 e = V2::Unit(j);
      const double dV =
          (potential(q - 2 * h * e) - 8 * potential(q - h * e) + 8 * potential(q + h * e) - potential(q + 2 * h * e)) /
          (12 * h);
      EXPECT_NEAR(d.Q(j), -dV, 1e-6) << j;
    }
    EXPECT_NEAR(d.T, 0.5 * qd.dot(I * qd), 1e-7);
    EXPECT_NEAR(d.V, potential(q), 1e-9);
    EXPECT_NEAR(d.P_nc, 0.0, 1e-9);
  }
}

}  // namespace
