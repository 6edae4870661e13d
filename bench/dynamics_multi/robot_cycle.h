// The five-bar robot of models/fivebar_robot.yaml in a pick-and-place cycle
// under PD control, written without mechgen or Simbody headers (both sides of the benchmark
// include it; the Simbody translation unit is compiled apart).
//
// Robot: motors at A = (0, 0) and E = (f, 0) drive the proximal links AB = ED = a
// (q = (theta_prox1, theta_prox2), absolute, CCW); distal links BC = DC = b meet at the tool C
// carrying the payload mp; uniform bars of density rho; gravity g along -y.
// Cycle (1 s): the tool goes from P1 = (-0.05, 0.36) to P2 = (0.25, 0.42) along a lifted path
// in 0.4 s (3-4-5 law), dwells 0.1 s, returns in 0.4 s, dwells 0.1 s. The commanded joint
// angles q_ref(t) and speeds come from the inverse kinematics (elbows out); each motor applies
//   tau_i = kp (q_ref,i - q_i) + kd (qd_ref,i - qd_i).
#pragma once

#include <cmath>

namespace bench_multi {

struct RobotParams {
  double f = 0.2, a = 0.25, b = 0.30, rho = 2.0, mp = 0.3, g = 9.81;
  double kp = 60.0, kd = 2.0;  // N m/rad, N m s/rad
  // dist1's centre of mass (from B along BC) and inertia about it, the payload lumped in.
  double MassDist1() const { return rho * b + mp; }
  double CenterDist1() const { return (rho * b * b / 2 + mp * b) / MassDist1(); }
  double InertiaDist1() const {
    const double xg = CenterDist1();
    return rho * b * b * b / 12 + rho * b * (xg - b / 2) * (xg - b / 2) + mp * (b - xg) * (b - xg);
  }
};

/// The times in the first cycle where the set point's law changes piece (the 3-4-5 moves' ends:
/// its jerk jumps there, so the PD torques' second derivative does): an integrator that knows
/// them restarts there instead of stepping across ("Breaks" variants of the benchmark).
constexpr double kCycleBreaks[] = {0.4, 0.5, 0.9};

/// The path parameter s in [0, 1] of the cycle at t (periodic, 1 s) and its derivatives.
inline void CycleLaw(double t, double* s, double* sd, double* sdd) {
  double u = t - std::floor(t);
  double sign = 1, base = 0;
  if (u >= 0.4 && u < 0.5) {
    *s = 1;
    *sd = *sdd = 0;
    return;
  }
  if (u >= 0.9) {
    *s = 0;
    *sd = *sdd = 0;
    return;
  }
  if (u >= 0.5) {
    u -= 0.5;
    sign = -1;
    base = 1;
  }
  const double T = 0.4, x = u / T, x2 = x * x, x3 = x2 * x;
  *s = base + sign * x3 * (10 - 15 * x + 6 * x2);
  *sd = sign / T * 30 * x2 * (1 - 2 * x + x2);
  *sdd = sign / (T * T) * 60 * x * (1 - 3 * x + 2 * x2);
}

/// The tool point's commanded position, velocity and acceleration at t.
inline void ToolPath(double t, double r[2], double v[2], double acc[2]) {
  double s, sd, sdd;
  CycleLaw(t, &s, &sd, &sdd);
  const double x0 = -0.05, dx = 0.30, y0 = 0.36, dy = 0.06, H = 0.04;
  const double slope = dy + 4 * H * (1 - 2 * s);
  r[0] = x0 + dx * s;
  r[1] = y0 + dy * s + 4 * H * s * (1 - s);
  v[0] = dx * sd;
  v[1] = slope * sd;
  acc[0] = dx * sdd;
  acc[1] = slope * sdd - 8 * H * sd * sd;
}

/// One arm's inverse kinematics (pivot O, elbow side sign): angle and speed.
inline void ArmInverse(const RobotParams& p, double ox, double sign, const double C[2],
                       const double Cd[2], double* th, double* thd) {
  const double rx = C[0] - ox, ry = C[1], d = std::sqrt(rx * rx + ry * ry);
  const double alpha = std::acos((p.a * p.a + d * d - p.b * p.b) / (2 * p.a * d));
  *th = std::atan2(ry, rx) + sign * alpha;
  const double ux = rx - p.a * std::cos(*th), uy = ry - p.a * std::sin(*th);  // C - B
  const double den = p.a * (-ux * std::sin(*th) + uy * std::cos(*th));
  *thd = (ux * Cd[0] + uy * Cd[1]) / den;
}

/// q_ref(t), qd_ref(t).
inline void Commanded(const RobotParams& p, double t, double q[2], double qd[2]) {
  double r[2], v[2], acc[2];
  ToolPath(t, r, v, acc);
  ArmInverse(p, 0.0, +1, r, v, &q[0], &qd[0]);
  ArmInverse(p, p.f, -1, r, v, &q[1], &qd[1]);
}

/// The motors' torques.
inline void Torques(const RobotParams& p, double t, const double q[2], const double qd[2],
                    double tau[2]) {
  double qr[2], qdr[2];
  Commanded(p, t, qr, qdr);
  for (int i = 0; i < 2; ++i) tau[i] = p.kp * (qr[i] - q[i]) + p.kd * (qdr[i] - qd[i]);
}

/// The forward kinematics: the distal links' absolute angles for motor angles q (C above BD).
inline void DistalAngles(const RobotParams& p, const double q[2], double* th_dist1,
                         double* th_dist2) {
  const double Bx = p.a * std::cos(q[0]), By = p.a * std::sin(q[0]);
  const double Dx = p.f + p.a * std::cos(q[1]), Dy = p.a * std::sin(q[1]);
  const double wx = Dx - Bx, wy = Dy - By, w = std::sqrt(wx * wx + wy * wy);
  const double h = std::sqrt(p.b * p.b - w * w / 4);
  const double Cx = (Bx + Dx) / 2 - h * wy / w, Cy = (By + Dy) / 2 + h * wx / w;
  *th_dist1 = std::atan2(Cy - By, Cx - Bx);
  *th_dist2 = std::atan2(Cy - Dy, Cx - Dx);
}

}  // namespace bench_multi
