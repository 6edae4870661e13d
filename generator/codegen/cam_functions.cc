// Builders of the cam functions of the generated header: CamLaw_<joint> (the follower law,
// segment by segment), EvalCam_<joint> (the cam's geometry at a cam angle) and
// Contour_<joint> (a spline contour's tables). See functions.h.
#include <cstdio>

#include "codegen/functions.h"

namespace mechgen {
namespace {

using Dir = Argument::Direction;

std::string Num17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

FunctionSpec CamLawSpec(const Model& m, const CamLaw& law, CxxPrinter* printer) {
  const Joint& j = m.joints[law.joint];
  printer->Name(CamLawT(), "t");
  printer->Name(CamLawBeta(), "beta");
  FunctionSpec f;
  f.name = law.cxx_name;
  f.returns = "Scalar";
  f.instantiate = false;
  f.count_ops = false;
  f.doc = {"\\brief Follower law of cam '" + j.name + "': the d-th derivative (d = 0..3) of the follower's lift",
           "with respect to the law's angle x (the cam's angle relative to the carrier minus the",
           "phase), x taken modulo 2 pi. Segments:"};
  for (size_t k = 0; k < law.what.size(); ++k) f.doc.push_back("  " + std::to_string(k) + ": " + law.what[k]);
  f.args = {Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."),
            Arg("const Scalar&", "x_in", Dir::kIn, "The law's angle (radians, any turn)."),
            Arg("int", "d", Dir::kIn, "Order of the derivative.")};
  Program P = {Raw("const Scalar two_pi = Scalar(6.283185307179586);"),
               Raw("const Scalar x = x_in - two_pi * floor(x_in / two_pi);")};
  for (size_t k = 0; k < law.what.size(); ++k) {
    const std::string what = std::to_string(k) + ": " + law.what[k];
    if (k + 1 == law.what.size())
      P.push_back(Raw("{  // " + what));
    else
      P.push_back(Raw("if (x < " + printer->Print((law.begin[k] + law.duration[k]).expand()) + ") {  // " + what));
    if (j.Data<CamData>().law[k].kind == CamSegment::Kind::kDwell) {
      P.push_back(Raw("  return d == 0 ? " + printer->Print(law.lift[k][0].expand()) + " : Scalar(0);"));
    } else {
      P.push_back(Raw("  const Scalar beta = " + printer->Print(law.duration[k].expand()) + ";"));
      P.push_back(Raw("  const Scalar t = (x - " + printer->Print(law.begin[k].expand()) + ") / beta;"));
      P.push_back(Raw("  switch (d) {"));
      for (int d = 0; d < 4; ++d)
        P.push_back(Raw(std::string("    ") + (d < 3 ? "case " + std::to_string(d) + ":" : std::string("default:")) +
                        " return " + printer->Print(law.lift[k][d].expand()) + ";"));
      P.push_back(Raw("  }"));
    }
    P.push_back(Raw("}"));
  }
  f.body = {P};
  return f;
}

FunctionSpec EvalCamSpec(const Model& m, const CamLaw& law, const CamGeometry& g) {
  const Joint& j = m.joints[law.joint];
  FunctionSpec f;
  f.name = "EvalCam_" + j.name;
  f.instantiate = false;
  f.doc = {"\\brief Cam '" + j.name + "' at cam angle x (the cam's angle relative to the carrier, radians): the",
           "follower's coordinate y = start + law(x - phase) and its x-derivatives, the pressure angle,",
           "the radii of curvature of the pitch curve and of the profile, and the contact point on",
           "the profile in the cam's frame (see CamState)."};
  f.args = {Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."),
            Arg("const Scalar&", "x", Dir::kIn, "Cam angle relative to the carrier (radians)."),
            Arg("CamState<Scalar>*", "out", Dir::kOut, "The cam's state; not nullptr.")};
  f.body = {g.program};
  return f;
}

FunctionSpec ContourSpec(const Model& m, const CamContour& c) {
  const Joint& j = m.joints[c.joint];
  const size_t n = c.knots.size() - 1;
  FunctionSpec f;
  f.name = c.cxx_name;
  f.returns = "Scalar";
  f.instantiate = false;
  f.count_ops = false;
  f.doc = {"\\brief Contour of cam '" + j.name + "' in the cam's frame: the periodic cubic spline through its",
           std::to_string(n) + " points, parametrized by chord length (period " + Num17(c.knots[n]) + "). Returns the",
           "d-th u-derivative (d = 0..3; 0 beyond) of coordinate c (0: x, 1: y) at u (any u: periodic)."};
  f.args = {Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."),
            Arg("const Scalar&", "u_in", Dir::kIn, "Contact parameter (any u: periodic)."),
            Arg("int", "c", Dir::kIn, "Coordinate (0: x, 1: y)."),
            Arg("int", "d", Dir::kIn, "Order of the derivative.")};
  Program P = {Raw("static constexpr int kSegments = " + std::to_string(n) + ";")};
  std::string knots = "static constexpr double kKnots[kSegments + 1] = {";
  for (size_t i = 0; i <= n; ++i) {
    if (i % 4 == 0) {
      P.push_back(Raw(knots));
      knots = "    ";
    } else {
      knots += " ";
    }
    knots += Num17(c.knots[i]) + (i < n ? "," : "};");
  }
  P.push_back(Raw(knots));
  P.push_back(Raw("// a + b t + c t^2 + d t^3 with t = u - kKnots[k], per coordinate and segment k."));
  P.push_back(Raw("static constexpr double kCoef[2][kSegments][4] = {"));
  for (int k = 0; k < 2; ++k) {
    P.push_back(Raw(k ? "}, {" : "{"));
    for (size_t i = 0; i < n; ++i) {
      std::string row = "    {";
      for (int a = 0; a < 4; ++a) row += (a ? ", " : "") + Num17(c.coef[k][i][a]);
      P.push_back(Raw(row + (i + 1 < n ? "}," : "}")));
    }
  }
  P.push_back(Raw("}};"));
  for (const char* line :
       {"const Scalar period = Scalar(kKnots[kSegments]);",
        "const Scalar u = u_in - period * floor(u_in / period);",
        "int k = 0, hi = kSegments;  // kKnots[k] <= u < kKnots[hi]",
        "while (hi - k > 1) {",
        "  const int mid = (k + hi) / 2;",
        "  if (u < Scalar(kKnots[mid])) {",
        "    hi = mid;",
        "  } else {",
        "    k = mid;",
        "  }",
        "}",
        "const double* a = kCoef[c][k];",
        "const Scalar t = u - Scalar(kKnots[k]);",
        "switch (d) {",
        "  case 0: return Scalar(a[0]) + t * (Scalar(a[1]) + t * (Scalar(a[2]) + t * Scalar(a[3])));",
        "  case 1: return Scalar(a[1]) + t * (Scalar(2 * a[2]) + t * Scalar(3 * a[3]));",
        "  case 2: return Scalar(2 * a[2]) + t * Scalar(6 * a[3]);",
        "  case 3: return Scalar(6 * a[3]);",
        "  default: return Scalar(0);",
        "}"})
    P.push_back(Raw(line));
  f.body = {P};
  return f;
}

}  // namespace mechgen

namespace mechgen {

FunctionSpec TableSpec(const Model& m, int index) {
  const Table& t = m.tables[index];
  const std::string n = std::to_string(t.x.size());
  FunctionSpec f;
  f.name = "Table_" + t.name;
  f.returns = "Scalar";
  f.instantiate = false;
  f.count_ops = false;
  f.doc = {"\\brief Table '" + t.name + "'" + (t.doc.empty() ? std::string() : ": " + t.doc) +
               ". Piecewise linear through its " + n + " points (x_i, y_i); outside [x_0, x_" +
               std::to_string(t.x.size() - 1) + "] the end values hold (slope 0)."};
  f.args = {Arg("const Scalar&", "x", Dir::kIn, "The argument."),
            Arg("int", "d", Dir::kIn, "0: the value, 1: the slope dy/dx.")};
  std::string xs, ys;
  for (size_t i = 0; i < t.x.size(); ++i) {
    xs += (i ? ", " : "") + Num17(t.x[i]);
    ys += (i ? ", " : "") + Num17(t.y[i]);
  }
  f.body = {{Raw("static constexpr int kN = " + n + ";"), Raw("static constexpr double kX[kN] = {" + xs + "};"),
             Raw("static constexpr double kY[kN] = {" + ys + "};"),
             Raw("if (!(x > Scalar(kX[0]))) return d == 0 ? Scalar(kY[0]) : Scalar(0);"),
             Raw("if (!(x < Scalar(kX[kN - 1]))) return d == 0 ? Scalar(kY[kN - 1]) : Scalar(0);"),
             Raw("int k = 0;"), Raw("while (k + 2 < kN && !(x < Scalar(kX[k + 1]))) ++k;"),
             Raw("const Scalar slope = Scalar((kY[k + 1] - kY[k]) / (kX[k + 1] - kX[k]));"),
             Raw("return d == 0 ? Scalar(kY[k]) + slope * (x - Scalar(kX[k])) : slope;")}};
  return f;
}

}  // namespace mechgen
