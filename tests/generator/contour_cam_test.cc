// Cams given by their contour (Paul §1.4.3): the contact parameter u_contact is a
// coordinate and the roller's centre lies on the contour's offset. cam_contour gives an
// eccentric circle by expressions, cam_spline samples the same circle with 36 points
// (a periodic cubic spline); both against the closed form of the follower's displacement
// s = e cos(theta) + sqrt((R + rr)^2 - e^2 sin(theta)^2) and its derivatives. Bad contour
// data through the command line: file:line:column errors.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "cam_contour.h"
#include "cam_spline.h"
#include "model/model.h"

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// The eccentric circular cam (circle radius R centred at distance e from the pivot, along
// the follower's line at theta = 0) with a roller rr on a radial translating follower:
// s, ds/dtheta, d2s/dtheta2.
std::array<double, 3> Eccentric(double e, double R, double rr, double th) {
  const double A = (R + rr) * (R + rr), sn = std::sin(th), cs = std::cos(th);
  const double W = std::sqrt(A - e * e * sn * sn), f = sn * cs;
  return {e * cs + W, -e * sn - e * e * f / W,
          -e * cs - e * e * (std::cos(2 * th) / W + e * e * f * f / (W * W * W))};
}

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Worst {
  double s = 0, v = 0, a = 0;
};

// Sweeps one turn by continuation from the assembly guess; returns the worst errors of
// s, K and L against the closed form.
template <class M>
Worst Sweep(const typename M::template ParamsT<double>& p, double e, double R, double rr, int n) {
  Eigen::Matrix<double, M::kNq, 1> q;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  typename M::template CoefficientsT<double> c;
  Worst w;
  for (int k = 0; k <= n; ++k) {
    q(0) = 2 * kPi * k / n;
    const auto report = M::Solve(p, q, &phi);
    EXPECT_EQ(report.status, decltype(report.status)::kConverged) << "q = " << q(0);
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(p, q, phi, &Phi);
    EXPECT_LT(Phi.template lpNorm<Eigen::Infinity>(), 1e-12) << "q = " << q(0);
    M::Coeffs(p, q, phi, &c);
    const auto s = Eccentric(e, R, rr, q(0));
    w.s = std::max(w.s, std::abs(phi(0) - s[0]));
    w.v = std::max(w.v, std::abs(c.K(0, 0) - s[1]));
    w.a = std::max(w.a, std::abs(c.L(0, 0) - s[2]));
    EXPECT_NEAR(c.r_P(0, 0), 0.0, 1e-14);
    EXPECT_NEAR(c.r_P(1, 0), phi(0), 1e-14);
  }
  return w;
}

TEST(ContourCam, EccentricCircleByExpressionsMatchesTheClosedForm) {
  using M = mech::cam_contour::Model;
  M::ParamsT<double> p;
  const Worst w = Sweep<M>(p, p.e, p.R, p.rr, 1440);
  EXPECT_LT(w.s, 1e-12);
  EXPECT_LT(w.v, 1e-12);
  EXPECT_LT(w.a, 1e-11);
}

TEST(ContourCam, ExpressionContourFollowsItsParameters) {
  using M = mech::cam_contour::Model;
  M::ParamsT<double> p;
  p.e = 0.5, p.R = 1.3, p.rr = 0.1;
  const Worst w = Sweep<M>(p, p.e, p.R, p.rr, 720);
  EXPECT_LT(w.s, 1e-12);
  EXPECT_LT(w.v, 1e-12);
  EXPECT_LT(w.a, 1e-11);
}

TEST(ContourCam, ContactPointLiesOnTheCircleAlongTheNormal) {
  using M = mech::cam_contour::Model;
  M::ParamsT<double> p;
  Eigen::Matrix<double, 1, 1> q;
  Eigen::Matrix<double, 2, 1> phi(M::kAssemblyPhi[0], M::kAssemblyPhi[1]);
  for (int k = 0; k <= 36; ++k) {
    q(0) = 2 * kPi * k / 36;
    ASSERT_EQ(M::Solve(p, q, &phi).status, mech::cam_contour::SolveStatus::kConverged);
    // Roller centre (0, s) in the cam's frame, minus the circle's centre (0, e): along
    // the normal at u, i.e. at the angle u.
    const double th = q(0), s = phi(0), u = phi(1);
    const double cx = s * std::sin(th), cy = s * std::cos(th) - p.e;  // R(-th) (0, s) - (0, e)
    EXPECT_NEAR(std::remainder(std::atan2(cy, cx) - u, 2 * kPi), 0.0, 1e-12);
    EXPECT_NEAR(std::hypot(cx, cy), p.R + p.rr, 1e-12);
  }
}

// The spline through 36 points of the unit circle (every 10 deg, chord h = 2 sin(5 deg) =
// 0.174): an interpolating periodic cubic spline's position error is O(h^4) (h^4 / 384 *
// |x''''| = 2.4e-6 for the circle), its tangent's O(h^3) and its curvature's O(h^2)
// (h^2 / 12 = 2.5e-3 relative). The follower's s depends on the contour's position,
// ds/dtheta on its normal, d2s/dtheta2 on its curvature as well. Measured worst errors over a turn at
// e = 0.3, R = 1, rr = 0.25: s 2.5e-6, K 5.3e-5, L 3.8e-3, each near its estimate; the bounds
// below leave a margin of about 2.
TEST(ContourCam, SplineThroughCirclePointsApproachesTheClosedForm) {
  using M = mech::cam_spline::Model;
  M::ParamsT<double> p;
  const Worst w = Sweep<M>(p, 0.3, 1.0, p.rr, 1440);
  std::printf("spline vs closed form: s %.3g, K %.3g, L %.3g\n", w.s, w.v, w.a);
  EXPECT_LT(w.s, 5e-6);
  EXPECT_LT(w.v, 1e-4);
  EXPECT_LT(w.a, 8e-3);
  EXPECT_GT(w.s, 1e-8);  // really the spline, not an exact circle
}

// A flat face (perpendicular to the follower's line, through C) on the same circle: the
// face touches the circle's top, s = e cos(theta) + R, at u = 90 deg - theta. The derived
// equations vanish there, and K = -Phi_phi^-1 Phi_q gives ds/dtheta = -e sin(theta).
TEST(ContourCam, FlatFaceOnTheContourIsTangent) {
  std::string text = Slurp(fs::path(MECHGEN_SOURCE_DIR) / "models" / "cam_contour.yaml");
  text.replace(text.find("roller: rr"), 10, "face: 0");
  const mechgen::Model m = mechgen::LoadModelFromString(text, "flat.yaml");
  const mechgen::Kinematics k = mechgen::DeriveKinematics(m, mechgen::BuildTopology(m));
  ASSERT_EQ(k.nphi(), 2);
  ASSERT_EQ(k.nc(), 2);
  ASSERT_EQ(k.phi[1].name, "u_contact");
  const double e = 0.3, R = 1.0;
  for (double th : {0.0, 0.4, 1.3, 2.5, 3.9, 5.6}) {
    GiNaC::exmap at;
    for (const auto& p : m.params) at[p.symbol] = p.value;
    at[k.q[0].symbol] = th;
    at[k.phi[0].symbol] = e * std::cos(th) + R;
    at[k.phi[1].symbol] = kPi / 2 - th;
    auto num = [&](const GiNaC::ex& x) { return GiNaC::ex_to<GiNaC::numeric>(x.subs(at).evalf()).to_double(); };
    for (const GiNaC::ex& row : k.Phi) EXPECT_NEAR(num(row), 0.0, 1e-14) << th;
    const double a = num(k.Phi_phi(0, 0)), b = num(k.Phi_phi(0, 1)), c = num(k.Phi_phi(1, 0)), d = num(k.Phi_phi(1, 1));
    const double f = num(k.Phi_q(0, 0)), g = num(k.Phi_q(1, 0)), det = a * d - b * c;
    ASSERT_GT(std::abs(det), 1e-6) << th;
    EXPECT_NEAR(-(d * f - b * g) / det, -e * std::sin(th), 1e-13) << th;  // K(s_slide)
    EXPECT_NEAR(-(a * g - c * f) / det, -1.0, 1e-13) << th;               // K(u_contact)
  }
}

// ---- bad contours through the command line ----------------------------------------
struct Run {
  int exit_code = -1;
  std::string output;
};
Run Mechgen(const std::string& args) {
  const std::string cmd = std::string(MECHGEN_EXE) + " " + args + " 2>&1";
  Run r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs `mechgen generate` on `model` (models/<model>.yaml) with `edits` and expects a
// one-line error at `line`:`column` mentioning `what`, exit 1, no files.
void ExpectContourError(const std::string& base, const std::vector<std::pair<std::string, std::string>>& edits,
                        const std::string& line_col, const std::string& what) {
  std::string text = Slurp(fs::path(MECHGEN_SOURCE_DIR) / "models" / (base + ".yaml"));
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const fs::path dir = fs::temp_directory_path() / ("mechgen_contour_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  const fs::path model = dir / "bad_contour.yaml";
  std::ofstream(model) << text;
  const Run r = Mechgen("generate " + model.string() + " --out-dir " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(model.string() + ":" + line_col + ": error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_TRUE(fs::is_empty(dir / "out"));
  fs::remove_all(dir);
}

// The spline model's points, from its file: the lines "          - [x, y]".
std::vector<std::string> PointLines() {
  const std::string text = Slurp(fs::path(MECHGEN_SOURCE_DIR) / "models" / "cam_spline.yaml");
  std::vector<std::string> lines;
  size_t at = 0;
  while ((at = text.find("          - [", at)) != std::string::npos) {
    const size_t end = text.find('\n', at);
    lines.push_back(text.substr(at, end + 1 - at));
    at = end;
  }
  return lines;
}

std::string Join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l;
  return s;
}

TEST(ContourCamErrors, FewerThanFourPoints) {
  const auto pts = PointLines();
  ASSERT_EQ(pts.size(), 36u);
  ExpectContourError("cam_spline", {{Join(pts), pts[0] + pts[12] + pts[24]}}, "27:9",
                     "has 3 distinct point(s); a periodic cubic spline needs at least 4");
}

TEST(ContourCamErrors, SelfIntersectingPoints) {
  auto pts = PointLines();
  const std::string all = Join(pts);
  std::swap(pts[10], pts[11]);
  ExpectContourError("cam_spline", {{all, Join(pts)}}, "39:13", "intersects itself");
}

TEST(ContourCamErrors, PointsThatDoNotCloseAroundThePivot) {
  const auto pts = PointLines();
  ExpectContourError("cam_spline",
                     {{Join(pts), "          - [2, 2]\n          - [3, 2]\n          - [3, 3]\n          - [2, 3]\n"}},
                     "27:9", "does not close once around the cam's pivot");
}

TEST(ContourCamErrors, ClockwisePoints) {
  auto pts = PointLines();
  const std::string all = Join(pts);
  std::reverse(pts.begin(), pts.end());
  ExpectContourError("cam_spline", {{all, Join(pts)}}, "27:9", "runs clockwise");
}

TEST(ContourCamErrors, ExpressionsThatDoNotClose) {
  ExpectContourError("cam_contour", {{"x: R*cos(u)", "x: R*cos(u) + 0.01*u"}}, "26:16", "is not closed");
}

// A five-lobed contour r = 1 + 0.12 cos(5u): concave between the lobes with radius of
// curvature down to 0.37 (at u = 0.62), less than a roller of 0.7.
TEST(ContourCamErrors, RollerUndercutsAConcaveContour) {
  ExpectContourError("cam_contour",
                     {{"x: R*cos(u), y: e + R*sin(u)", "x: (R + 0.12*cos(5*u))*cos(u), y: (R + 0.12*cos(5*u))*sin(u)"},
                      {"rr: {value: 0.25", "rr: {value: 0.7"}},
                     "25:15", "larger than the contour's radius of curvature");
}

}  // namespace
