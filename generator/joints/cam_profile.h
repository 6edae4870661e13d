// Disk cams given by the follower's law (Paul §1.4, the CAMKIN program): the law as
// segments (dwell, rise, return; cycloidal, harmonic and 3-4-5 polynomial motions), the
// symbolic function that stands for it in Phi, and the cam's derived geometry: pressure
// angle and radius of curvature of the pitch curve and of the profile along the cycle.
//
// In the equations the law is the GiNaC function camlaw(i, d, x): the d-th derivative of
// cam i's follower lift at cam angle x (from the law's start). GiNaC differentiates it as
// camlaw(i, d + 1, x), so Phi_q, K and L need no branches; the generated code evaluates
// it with CamLaw_<joint>(p, x, d) (codegen/cam_functions.cc), which picks the segment of x modulo 2 pi and returns
// that segment's symbolically differentiated expression.
#pragma once

#include <ginac/ginac.h>

#include <array>
#include <string>
#include <vector>

#include "joints/joint_kind.h"
#include "model/model.h"
#include "symbolic/program.h"

namespace mechgen {

DECLARE_FUNCTION_3P(camlaw)
/// camcontour(i, c, d, u): the d-th u-derivative of coordinate c (0: x, 1: y) of the
/// spline contour of cam i at contact parameter u; GiNaC differentiates it as
/// camcontour(i, c, d + 1, u). The generated code evaluates it with
/// Contour_<joint>(p, u, c, d) over tables of the spline's knots and coefficients.
DECLARE_FUNCTION_4P(camcontour)

/// The follower law of one cam joint, segment by segment, in the law's own angle x.
struct CamLaw {
  int joint = -1;
  std::string cxx_name;              ///< CamLaw_<joint>
  std::vector<GiNaC::ex> begin;      ///< start angle of each segment (the first is 0)
  std::vector<GiNaC::ex> duration;
  std::vector<std::array<GiNaC::ex, 4>> lift;  ///< per segment: lift and its x-derivatives 1..3
  std::vector<std::string> what;     ///< "rise 120*deg, cycloidal, lift h"
  std::vector<double> begin_value;   ///< begin at the parameters' defaults
};

/// The law of cam joint `j` (the validation stage has checked that it spans one turn and
/// brings the follower back: CheckCamLaw in analysis/validate.h).
CamLaw BuildCamLaw(const Model& m, const Joint& j);

/// The law's d-th derivative at x (radians, any turn), at the parameters' defaults.
double EvalCamLaw(const Model& m, const CamLaw& law, double x, int d);

/// A cam's geometry along the cycle, in terms of the cam angle x relative to the carrier.
struct CamGeometry {
  GiNaC::symbol x{"x"};
  Program program;  ///< statements of EvalCam_<joint> (stores out->...)
  /// The expressions stored, for the generator's own checks.
  GiNaC::ex y, pressure_angle, rho_pitch, rho_profile;
};

/// Pressure angle and radii of curvature of cam joint `j` (see models/README.md).
CamGeometry DeriveCamGeometry(const Model& m, const Joint& j);

/// Samples the cam's geometry over one turn at the parameters' defaults; fails
/// (ModelError at the roller) if the roller is larger than the pitch curve's radius of
/// curvature where it is convex (undercutting), or a flat-faced profile has a cusp.
/// Fills the summary line for the report and the generated header.
std::string CheckCam(const Model& m, const Joint& j, const CamLaw& law, const CamGeometry& g);

/// A cam given by its contour (CamData::contour) in the cam's frame: expressions in u, or a
/// periodic cubic spline through points, parametrized by chord length.
struct CamContour {
  int joint = -1;
  std::string cxx_name;  ///< Contour_<joint> (splines)
  /// Splines: knots u_0 = 0 < ... < u_N = period; per coordinate c and segment k the
  /// coefficients a + b t + c t^2 + d t^3, t = u - u_k.
  std::vector<double> knots;
  std::vector<std::array<double, 4>> coef[2];
  std::string summary;  ///< for the report and the generated header
};

/// Checks the contour of cam joint `j` at the parameters' defaults (ModelError at the
/// contour or its points: fewer than 4 points, repeated or self-intersecting points, a
/// contour that does not close around the cam's pivot or runs clockwise, a roller that
/// undercuts a concave stretch, a flat face on a non-convex contour) and fits the spline.
CamContour BuildCamContour(const Model& m, const Joint& j);

/// The d-th u-derivative of the contour of cam joint `j` in the cam's frame (symbolic).
Vec2 ContourPoint(const Joint& j, const GiNaC::ex& u, int d);

/// The spline's value (c: coordinate, d: derivative order, any u: periodic).
double EvalSpline(const CamContour& c, int coordinate, int d, double u);

/// The symbols of the law's segment expressions (CamLaw::lift): t, the angle from the
/// segment's start over its duration, and beta, the duration (CamLaw_<joint>'s locals,
/// codegen/cam_functions.cc).
const GiNaC::symbol& CamLawT();
const GiNaC::symbol& CamLawBeta();

}  // namespace mechgen
