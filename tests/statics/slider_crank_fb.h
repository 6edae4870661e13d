// The free-body description of the centred slider-crank of models/slider_crank_press.yaml
// and models/slider_crank_friction.yaml, written from the models' text: crank O-B = a
// (driven at O), rod B-C = b, the slider (ram, piston) at C on the line y = 0 (guide angle 0);
// pins O [ground, crank], B [crank, rod], C [rod, slider], the prismatic `slide` (guide
// ground, slider at C). A force on the slider at C; optional weights at the crank's and the
// rod's midpoints and at C.
#pragma once

#include <cmath>

#include "free_body.h"

namespace mechtest::fb {

struct SliderCrankFb {
  FreeBodySystem s;
  int ground, crank, rod, slider;
  int pO, pB, pC, pG1, pG2;
  int jO, jB, jC, jS;
  int slider_force;
  double a, b;

  /// masses (m1, m2, m3) and g: weights along -y; g = 0 for none.
  SliderCrankFb(double a_, double b_, double g = 0, double m1 = 0, double m2 = 0, double m3 = 0)
      : a(a_), b(b_) {
    ground = s.AddLink("ground", true);
    crank = s.AddLink("crank");
    rod = s.AddLink("rod");
    slider = s.AddLink("slider");
    pO = s.AddPoint(Vec2(0, 0));
    pB = s.AddPoint();
    pC = s.AddPoint();
    pG1 = s.AddPoint();
    pG2 = s.AddPoint();
    jO = s.AddRevolute("O", ground, crank, pO, /*driven=*/true);
    jB = s.AddRevolute("B", crank, rod, pB);
    jC = s.AddRevolute("C", rod, slider, pC);
    jS = s.AddPrismatic("slide", ground, slider, pC, 0.0);
    slider_force = s.AddForce(slider, pC);
    if (g != 0) {
      s.AddWeight(crank, pG1, m1, Vec2(0, -g));
      s.AddWeight(rod, pG2, m2, Vec2(0, -g));
      s.AddWeight(slider, pC, m3, Vec2(0, -g));
    }
  }

  /// The points at crank angle q, rod angle th_rod and slider position s (C = (s, 0)).
  void Place(double q, double th_rod, double s_slide) {
    const Vec2 B(a * std::cos(q), a * std::sin(q));
    s.SetPoint(pB, B);
    s.SetPoint(pC, Vec2(s_slide, 0));
    s.SetPoint(pG1, 0.5 * B);
    s.SetPoint(pG2, B + 0.5 * b * Vec2(std::cos(th_rod), std::sin(th_rod)));
  }
};

/// The centred slider-crank in closed form (C to the right of B): s and K_s = ds/dq.
inline double SliderS(double a, double b, double q) {
  const double sq = std::sin(q);
  return a * std::cos(q) + std::sqrt(b * b - a * a * sq * sq);
}
inline double SliderKs(double a, double b, double q) {
  const double sq = std::sin(q), cq = std::cos(q);
  return -a * sq - a * a * sq * cq / std::sqrt(b * b - a * a * sq * sq);
}
/// The rod's angle: sin th_rod = -a sin q / b, C to the right of B.
inline double SliderRodAngle(double a, double b, double q) {
  return std::asin(-a * std::sin(q) / b);
}

}  // namespace mechtest::fb
