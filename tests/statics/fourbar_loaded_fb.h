// The free-body description of models/fourbar_loaded.yaml, written from the model's text
// (not from the generator): links ground, crank, coupler, rocker; pins A (ground-crank,
// driven), B (crank-coupler), C (coupler-rocker), D (rocker-ground, in the model's order:
// the force of the rocker on the ground); the coupler force (Fx, Fy) at P, the torque T on
// the rocker, the spring E-P (k, L0, F0), the weights m_i (0, -g) at the links' midpoints.
// Used by the statics tests and by the benchmark's baseline (4).
#pragma once

#include <cmath>

#include "free_body.h"

namespace mechtest::fb {

template <typename Params>
struct FourbarLoadedFb {
  FreeBodySystem s;
  int ground, crank, coupler, rocker;
  int pA, pB, pC, pD, pE, pP, pG1, pG2, pG3;
  int jA, jB, jC, jD;
  int coupler_force, rocker_torque, spring;

  explicit FourbarLoadedFb(const Params& p) {
    ground = s.AddLink("ground", true);
    crank = s.AddLink("crank");
    coupler = s.AddLink("coupler");
    rocker = s.AddLink("rocker");
    pA = s.AddPoint(Vec2(0, 0));
    pB = s.AddPoint();
    pC = s.AddPoint();
    pD = s.AddPoint(Vec2(p.d, 0));
    pE = s.AddPoint(Vec2(p.xE, p.yE));
    pP = s.AddPoint();
    pG1 = s.AddPoint();
    pG2 = s.AddPoint();
    pG3 = s.AddPoint();
    jA = s.AddRevolute("A", ground, crank, pA, /*driven=*/true);
    jB = s.AddRevolute("B", crank, coupler, pB);
    jC = s.AddRevolute("C", coupler, rocker, pC);
    jD = s.AddRevolute("D", rocker, ground, pD);
    coupler_force = s.AddForce(coupler, pP, Vec2(p.Fx, p.Fy));
    rocker_torque = s.AddTorque(rocker, p.Tr);
    const Vec2 gravity(0, -p.g);
    s.AddWeight(crank, pG1, p.m1, gravity);
    s.AddWeight(coupler, pG2, p.m2, gravity);
    s.AddWeight(rocker, pG3, p.m3, gravity);
    spring = s.AddSpring(ground, pE, coupler, pP, p.k, p.L0, p.F0);
  }

  /// The points at the absolute angles of crank, coupler and rocker.
  void Place(const Params& p, double th1, double th2, double th3) {
    const Vec2 u1(std::cos(th1), std::sin(th1)), u2(std::cos(th2), std::sin(th2));
    const Vec2 u3(std::cos(th3), std::sin(th3));
    const Vec2 n2(-u2.y(), u2.x());
    const Vec2 B = p.a * u1;
    s.SetPoint(pB, B);
    s.SetPoint(pC, B + p.b * u2);
    s.SetPoint(pP, B + p.xi * u2 + p.eta * n2);
    s.SetPoint(pG1, 0.5 * p.a * u1);
    s.SetPoint(pG2, B + 0.5 * p.b * u2);
    s.SetPoint(pG3, Vec2(p.d, 0) + 0.5 * p.c * u3);
  }

  /// Potential energy of the spring and of gravity (m g y of each centre of mass).
  double Potential(const Params& p) const {
    return s.SpringEnergy() +
           p.g * (p.m1 * s.point(pG1).y() + p.m2 * s.point(pG2).y() + p.m3 * s.point(pG3).y());
  }
};

}  // namespace mechtest::fb
