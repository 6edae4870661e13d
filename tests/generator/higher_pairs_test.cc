// Gears, rolling contact and cams (Paul §1.3, §1.4), end to end: the shipped models
// geared_fivebar, planetary, rolling_wheel, cardan, cam_roller and cam_flat against
// closed-form oracles written here independently of the generator (the gear ratio, the
// Willis formula, the cycloid and hypocycloid, the cam laws' own derivatives, the pressure
// angle and radius of curvature of the cams), loop closure over full cycles with the
// generated SolvePositions, the model format's new joint kinds and mobility (Grübler with
// higher pairs), and bad cam data: a clear file:line:column error, exit 1, no output.
//
// K and L against finite differences, Jets, float, no allocation and a warning-clean
// standalone header run on these models automatically in tests/kinematics (they are in
// MECHGEN_SHIPPED_MODELS).
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
#include "analysis/validate.h"
#include "cam_flat.h"
#include "cam_roller.h"
#include "cardan.h"
#include "geared_fivebar.h"
#include "model/model.h"
#include "planetary.h"
#include "rolling_wheel.h"

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// ---- a one-input sweep with the generated position solver --------------------------
template <class M>
struct State {
  typename M::template ParamsT<double> p;
  Eigen::Matrix<double, M::kNq, 1> q;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  typename M::template CoefficientsT<double> c;
};

// Calls f(state) at n points over one turn of the input, solved by continuation from the
// model's assembly guess; checks |Phi| at each.
template <class M, class F>
void Sweep(const typename M::template ParamsT<double>& p, int n, F f, double turns = 1.0) {
  State<M> s;
  s.p = p;
  for (int i = 0; i < M::kNphi; ++i) s.phi(i) = M::kAssemblyPhi[i];
  for (int k = 0; k <= n; ++k) {
    s.q(0) = M::kAssemblyQ[0] + turns * 2 * kPi * k / n;
    const auto report = M::Solve(s.p, s.q, &s.phi);
    ASSERT_EQ(report.status, decltype(report.status)::kConverged) << "q = " << s.q(0);
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(s.p, s.q, s.phi, &Phi);
    ASSERT_LT(Phi.template lpNorm<Eigen::Infinity>(), 1e-12) << "q = " << s.q(0);
    M::Coeffs(s.p, s.q, s.phi, &s.c);
    f(s);
  }
}

// ---- gears -------------------------------------------------------------------------
TEST(Gears, GearedFivebarCranksTurnAtTheGearRatio) {
  using M = mech::geared_fivebar::Model;
  M::ParamsT<double> p;
  int checked = 0;
  Sweep<M>(p, 720, [&](const State<M>& s) {
    // phi = (theta_link1, theta_link2, theta_crank2)? find theta_crank2 by name.
    int i2 = -1;
    for (int i = 0; i < M::kNphi; ++i)
      if (std::string(M::kPhiNames[i]) == "theta_crank2") i2 = i;
    ASSERT_GE(i2, 0);
    // External mesh on the ground: r1 theta1 + r2 theta2 = 0.
    EXPECT_NEAR(s.phi(i2), -p.r1 / p.r2 * s.q(0), 1e-12);
    EXPECT_NEAR(s.c.K(i2, 0), -p.r1 / p.r2, 1e-14);
    EXPECT_NEAR(s.c.L(i2, 0), 0.0, 1e-14);
    ++checked;
  });
  EXPECT_EQ(checked, 721);
}

// Willis: (w_sun - w_arm) / (w_ring - w_arm) = -rr / rs; ring fixed (w_ring = 0).
void CheckWillis(const mech::planetary::Model::ParamsT<double>& p) {
  using M = mech::planetary::Model;
  const double arm = p.rs / (p.rs + p.rr);               // w_arm / w_sun
  const double planet = arm - (p.rr / p.rp) * arm;       // w_planet / w_sun (planet-ring mesh)
  Sweep<M>(p, 360, [&](const State<M>& s) {
    ASSERT_EQ(std::string(M::kPhiNames[0]), "theta_arm");
    ASSERT_EQ(std::string(M::kPhiNames[1]), "theta_planet");
    const double w_sun = 1.0, w_arm = s.c.K(0, 0), w_planet = s.c.K(1, 0);
    EXPECT_NEAR((w_sun - w_arm) / (0.0 - w_arm), -p.rr / p.rs, 1e-12);
    EXPECT_NEAR(w_arm, arm, 1e-14);
    EXPECT_NEAR(w_planet, planet, 1e-13);
    // The sun-planet mesh relative to the arm: rs (w_sun - w_arm) = -rp (w_planet - w_arm).
    EXPECT_NEAR(p.rs * (w_sun - w_arm), -p.rp * (w_planet - w_arm), 1e-13);
    EXPECT_NEAR(s.phi(0), arm * s.q(0), 1e-12);
    EXPECT_NEAR(s.c.L(0, 0), 0.0, 1e-14);
    EXPECT_NEAR(s.c.L(1, 0), 0.0, 1e-14);
    // The planet's point M stays on its pitch circle about P = (rs + rp) e(theta_arm).
    const double px = (p.rs + p.rp) * std::cos(s.phi(0)), py = (p.rs + p.rp) * std::sin(s.phi(0));
    EXPECT_NEAR(std::hypot(s.c.r_P(0, 0) - px, s.c.r_P(1, 0) - py), p.rp, 1e-12);
  });
}

TEST(Gears, PlanetaryTrainMatchesWillis) { CheckWillis({}); }

TEST(Gears, PlanetaryTrainMatchesWillisForOtherRadii) {
  mech::planetary::Model::ParamsT<double> p;
  p.rs = 1.3;
  p.rp = 0.35;
  p.rr = p.rs + 2 * p.rp;
  CheckWillis(p);
}

// ---- rolling contact ---------------------------------------------------------------
TEST(Rolling, WheelOnALineTracesACycloid) {
  using M = mech::rolling_wheel::Model;
  M::ParamsT<double> p;
  p.r = 0.7;
  Sweep<M>(p, 720, [&](const State<M>& s) {
    const double t = -s.q(0), r = p.r;  // the wheel turns back as it rolls forward
    // r_P(., 0) = wheel.P, r_P(., 1) = roll.contact
    EXPECT_NEAR(s.c.r_P(0, 0), r * (t - std::sin(t)), 1e-12);
    EXPECT_NEAR(s.c.r_P(1, 0), r * (1 - std::cos(t)), 1e-12);
    EXPECT_NEAR(s.c.r_P(0, 1), r * t, 1e-12);
    EXPECT_NEAR(s.c.r_P(1, 1), 0.0, 1e-14);
    // d/dq of the cycloid (dt/dq = -1) and its second derivative.
    EXPECT_NEAR(s.c.K_P(0, 0), -r * (1 - std::cos(t)), 1e-12);
    EXPECT_NEAR(s.c.K_P(1, 0), -r * std::sin(t), 1e-12);
    EXPECT_NEAR(s.c.L_P(0, 0), r * std::sin(t), 1e-12);
    EXPECT_NEAR(s.c.L_P(1, 0), r * std::cos(t), 1e-12);
    // No slip: the contact point moves at r per radian.
    EXPECT_NEAR(s.c.K(0, 0), -r, 1e-14);
  });
}

TEST(Rolling, RimPointAtTheContactIsInstantaneouslyAtRest) {
  using M = mech::rolling_wheel::Model;
  M::ParamsT<double> p;
  Eigen::Matrix<double, 1, 1> q, phi;
  q << 2 * kPi;
  phi << 0;
  ASSERT_EQ(M::Solve(p, q, &phi).status, mech::rolling_wheel::SolveStatus::kConverged);
  M::CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  EXPECT_NEAR(c.K_P(0, 0), 0.0, 1e-14);
  EXPECT_NEAR(c.K_P(1, 0), 0.0, 1e-14);
  EXPECT_NEAR(c.r_P(0, 0), c.r_P(0, 1), 1e-12);  // wheel.P is the contact point
}

void CheckHypocycloid(double r, double R) {
  using M = mech::cardan::Model;
  M::ParamsT<double> p;
  p.r = r;
  p.R = R;
  Sweep<M>(p, 720, [&](const State<M>& s) {
    const double psi = s.phi(0);
    EXPECT_NEAR(psi, -r / (R - r) * s.q(0), 1e-12);  // no slip inside: (R - r) psi = -r theta
    const double k = (R - r) / r;
    EXPECT_NEAR(s.c.r_P(0, 0), (R - r) * std::cos(psi) + r * std::cos(k * psi), 1e-12);
    EXPECT_NEAR(s.c.r_P(1, 0), (R - r) * std::sin(psi) - r * std::sin(k * psi), 1e-12);
    EXPECT_NEAR(std::hypot(s.c.r_P(0, 1), s.c.r_P(1, 1)), R, 1e-12);  // contact on the circle
    // K_P: d/dq = dpsi/dq d/dpsi.
    const double dpsi = -r / (R - r);
    EXPECT_NEAR(s.c.K_P(0, 0), dpsi * (-(R - r) * std::sin(psi) - r * k * std::sin(k * psi)), 1e-12);
    EXPECT_NEAR(s.c.K_P(1, 0), dpsi * ((R - r) * std::cos(psi) - r * k * std::cos(k * psi)), 1e-12);
  });
}

TEST(Rolling, CardanCircleRimPointMovesOnAStraightLine) {
  using M = mech::cardan::Model;
  M::ParamsT<double> p;  // R = 2 r
  double xmin = 1e9, xmax = -1e9;
  Sweep<M>(p, 720, [&](const State<M>& s) {
    EXPECT_NEAR(s.c.r_P(1, 0), 0.0, 1e-12);
    EXPECT_NEAR(s.c.K_P(1, 0), 0.0, 1e-12);
    EXPECT_NEAR(s.c.L_P(1, 0), 0.0, 1e-12);
    xmin = std::min(xmin, s.c.r_P(0, 0));
    xmax = std::max(xmax, s.c.r_P(0, 0));
  });
  EXPECT_NEAR(xmin, -p.R, 1e-9);  // a full stroke along the diameter
  EXPECT_NEAR(xmax, p.R, 1e-9);
  CheckHypocycloid(1.0, 2.0);
}

TEST(Rolling, HypocycloidForOtherRadiusRatios) {
  CheckHypocycloid(1.0, 3.0);   // deltoid
  CheckHypocycloid(0.5, 2.0);   // astroid
  CheckHypocycloid(0.7, 2.3);
}

// ---- cams: the laws, hand-coded ---------------------------------------------------
enum class Motion { kDwell, kCycloidal, kHarmonic, kPoly345 };
struct Segment {
  Motion motion;
  double beta, h;  // duration; signed lift (return < 0)
};
// y(x), y'(x), y''(x) of a dwell-rise-dwell-return law at law angle x.
std::array<double, 3> Law(const std::vector<Segment>& law, double x) {
  x -= 2 * kPi * std::floor(x / (2 * kPi));
  double start = 0, level = 0;
  for (size_t i = 0; i < law.size(); ++i) {
    const Segment& s = law[i];
    if (x < start + s.beta || i + 1 == law.size()) {
      const double t = (x - start) / s.beta, b = s.beta, h = s.h;
      switch (s.motion) {
        case Motion::kDwell: return {level, 0, 0};
        case Motion::kCycloidal:
          return {level + h * (t - std::sin(2 * kPi * t) / (2 * kPi)), h * (1 - std::cos(2 * kPi * t)) / b,
                  h * 2 * kPi * std::sin(2 * kPi * t) / (b * b)};
        case Motion::kHarmonic:
          return {level + h * (1 - std::cos(kPi * t)) / 2, h * kPi / 2 * std::sin(kPi * t) / b,
                  h * kPi * kPi / 2 * std::cos(kPi * t) / (b * b)};
        case Motion::kPoly345:
          return {level + h * (10 * t * t * t - 15 * t * t * t * t + 6 * t * t * t * t * t),
                  h * (30 * t * t - 60 * t * t * t + 30 * t * t * t * t) / b,
                  h * (60 * t - 180 * t * t + 120 * t * t * t) / (b * b)};
      }
    }
    start += s.beta;
    level += s.h;
  }
  return {0, 0, 0};
}
constexpr double kDeg = kPi / 180;

TEST(Cams, RollerFollowerDisplacementVelocityAndAccelerationCoefficients) {
  using M = mech::cam_roller::Model;
  M::ParamsT<double> p;
  const std::vector<Segment> law = {{Motion::kDwell, 60 * kDeg, 0},
                                    {Motion::kCycloidal, 120 * kDeg, p.h},
                                    {Motion::kDwell, 30 * kDeg, 0},
                                    {Motion::kPoly345, 150 * kDeg, -p.h}};
  const double s0 = std::sqrt((p.rb + p.rr) * (p.rb + p.rr) - p.e * p.e);
  double worst = 0;
  Sweep<M>(p, 1440, [&](const State<M>& s) {
    const auto y = Law(law, s.q(0) - p.phase);
    EXPECT_NEAR(s.phi(0), s0 + y[0], 1e-12);
    EXPECT_NEAR(s.c.K(0, 0), y[1], 1e-12);
    EXPECT_NEAR(s.c.L(0, 0), y[2], 1e-11);
    EXPECT_NEAR(s.c.r_P(0, 0), p.e, 1e-14);
    EXPECT_NEAR(s.c.r_P(1, 0), s0 + y[0], 1e-12);
    worst = std::max(worst, std::abs(y[2]));
  });
  EXPECT_GT(worst, 1.0);  // the law really accelerates the follower
}

TEST(Cams, RollerCamPressureAngleAndRadiusOfCurvature) {
  using M = mech::cam_roller::Model;
  M::ParamsT<double> p;
  const std::vector<Segment> law = {{Motion::kDwell, 60 * kDeg, 0},
                                    {Motion::kCycloidal, 120 * kDeg, p.h},
                                    {Motion::kDwell, 30 * kDeg, 0},
                                    {Motion::kPoly345, 150 * kDeg, -p.h}};
  const double s0 = std::sqrt((p.rb + p.rr) * (p.rb + p.rr) - p.e * p.e);
  double max_alpha = 0;
  for (int i = 0; i < 720; ++i) {
    const double x = 2 * kPi * (i + 0.25) / 720;
    const auto y = Law(law, x - p.phase);
    const double s = s0 + y[0], ds = y[1], dds = y[2];
    mech::cam_roller::CamState<double> st;
    mech::cam_roller::EvalCam_contact(p, x, &st);
    EXPECT_NEAR(st.y, s, 1e-12);
    EXPECT_NEAR(st.y_x, ds, 1e-12);
    EXPECT_NEAR(st.y_xx, dds, 1e-11);
    // The roller centre C = (e, s) seen from the cam (turned back by x) moves along the
    // pitch curve with the tangent (s, s' - e) (in the fixed frame's directions); the
    // pressure angle is the normal's angle from the follower's line: tan a = |s' - e| / s.
    EXPECT_NEAR(st.pressure_angle, std::atan(std::abs(ds - p.e) / s), 1e-12) << "x = " << x;
    max_alpha = std::max(max_alpha, st.pressure_angle);
    // Pitch curve X(x) = R(-x) (e, s) and its derivatives, by hand.
    const double c = std::cos(x), sn = std::sin(x);
    const double X1 = p.e * c + s * sn, Y1 = -p.e * sn + s * c;
    const double dX = -p.e * sn + ds * sn + s * c, dY = -p.e * c + ds * c - s * sn;
    const double ddX = -p.e * c + dds * sn + 2 * ds * c - s * sn, ddY = p.e * sn + dds * c - 2 * ds * sn - s * c;
    const double rho = -std::pow(dX * dX + dY * dY, 1.5) / (dX * ddY - dY * ddX);
    EXPECT_NEAR(st.rho_pitch, rho, 1e-10 * std::max(1.0, std::abs(rho)));
    EXPECT_NEAR(st.rho_profile, rho - p.rr, 1e-10 * std::max(1.0, std::abs(rho)));
    // The contact point is a roller radius from the pitch point, toward the cam.
    EXPECT_NEAR(std::hypot(st.contact(0) - X1, st.contact(1) - Y1), p.rr, 1e-12);
    EXPECT_LT(std::hypot(st.contact(0), st.contact(1)), std::hypot(X1, Y1));
    if (y[1] == 0 && y[0] == 0) EXPECT_NEAR(std::hypot(st.contact(0), st.contact(1)), p.rb, 1e-12);  // base circle
  }
  EXPECT_GT(max_alpha, 20 * kDeg);
  EXPECT_LT(max_alpha, 35 * kDeg);
}

TEST(Cams, OscillatingFlatFacedFollowerAgainstItsLaw) {
  using M = mech::cam_flat::Model;
  M::ParamsT<double> p;
  const std::vector<Segment> law = {{Motion::kDwell, 50 * kDeg, 0},
                                    {Motion::kHarmonic, 130 * kDeg, p.lift},
                                    {Motion::kDwell, 40 * kDeg, 0},
                                    {Motion::kCycloidal, 140 * kDeg, -p.lift}};
  const double psi0 = std::asin(p.rb / p.d);
  Sweep<M>(p, 1440, [&](const State<M>& s) {
    const auto y = Law(law, s.q(0) - p.phase);
    EXPECT_NEAR(s.phi(0), psi0 + y[0], 1e-12);
    EXPECT_NEAR(s.c.K(0, 0), y[1], 1e-12);
    EXPECT_NEAR(s.c.L(0, 0), y[2], 1e-11);
  });
  for (int i = 0; i < 720; ++i) {
    const double x = 2 * kPi * (i + 0.25) / 720;
    const auto y = Law(law, x - p.phase);
    const double psi = psi0 + y[0], w = y[1], dw = y[2];
    mech::cam_flat::CamState<double> st;
    mech::cam_flat::EvalCam_contact(p, x, &st);
    // The face through the pivot A at angle psi is at h = d sin(psi) from the cam's
    // centre; its normal turns at phi' = psi' - 1 in the cam's frame, so the profile's
    // radius of curvature is rho = h + (h'' phi' - h' phi'') / phi'^3.
    const double h = p.d * std::sin(psi), dh = p.d * std::cos(psi) * w,
                 ddh = p.d * (-std::sin(psi) * w * w + std::cos(psi) * dw);
    const double f1 = w - 1, f2 = dw;
    const double rho = h + (ddh * f1 - dh * f2) / (f1 * f1 * f1);
    EXPECT_NEAR(st.rho_profile, rho, 1e-11) << "x = " << x;
    EXPECT_GT(st.rho_profile, 0);
    // A face through the pivot: the contact force is normal to the face, the contact
    // point moves normal to the face too: pressure angle 0.
    EXPECT_NEAR(st.pressure_angle, 0.0, 1e-12);
    // The contact point lies on the face at d cos(psi) / (1 - psi') from the pivot (the
    // instant centre of the cam and the follower on OA).
    const double ax = p.d * std::cos(x), ay = -p.d * std::sin(x);  // A in the cam's frame
    EXPECT_NEAR(std::hypot(st.contact(0) - ax, st.contact(1) - ay), p.d * std::cos(psi) / (1 - w), 1e-11);
    EXPECT_NEAR(std::hypot(st.contact(0), st.contact(1)) >= h - 1e-12, true, 0);
  }
}

// ---- model format, topology and errors --------------------------------------------
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

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs `mechgen generate` on the cam_roller model with `edits` (text replacements) and
// expects a one-line error at `line`:`column` mentioning `what`, exit 1, no files.
void ExpectCamError(const std::vector<std::pair<std::string, std::string>>& edits, int line,
                    const std::string& what) {
  std::string text = Slurp(fs::path(MECHGEN_SOURCE_DIR) / "models" / "cam_roller.yaml");
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const fs::path dir = fs::temp_directory_path() / ("mechgen_cam_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  const fs::path model = dir / "bad_cam.yaml";
  std::ofstream(model) << text;
  const Run r = Mechgen("generate " + model.string() + " --out-dir " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(model.string() + ":" + std::to_string(line) + ":"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_TRUE(fs::is_empty(dir / "out"));
  fs::remove_all(dir);
}

TEST(CamErrors, SegmentsThatDoNotSpanOneTurn) {
  ExpectCamError({{"{dwell: 30*deg}", "{dwell: 40*deg}"}}, 31, "spans 370.0 deg of cam angle, not 360 deg");
}

TEST(CamErrors, RiseAndReturnThatDoNotMatch) {
  ExpectCamError({{"{return: 150*deg, lift: h,", "{return: 150*deg, lift: 0.7*h,"}}, 31,
                 "does not close the cycle");
}

// A fast rise (40 deg for the lift 0.8) makes the pitch curve's nose sharp: 0.40 at 97 deg.
TEST(CamErrors, RollerLargerThanThePitchCurvesRadiusOfCurvature) {
  ExpectCamError({{"{rise: 120*deg", "{rise: 40*deg"},
                  {"{dwell: 30*deg}", "{dwell: 110*deg}"},
                  {"rr:    {value: 0.25", "rr:    {value: 0.5"}},
                 27, "is larger than the pitch curve's radius of curvature");
}

TEST(CamErrors, UnknownMotionAndMissingLift) {
  ExpectCamError({{"motion: cycloidal", "motion: parabolic"}}, 32, "unknown motion 'parabolic'");
  ExpectCamError({{"{rise: 120*deg, lift: h, motion: cycloidal}", "{rise: 120*deg, motion: cycloidal}"}}, 32,
                 "needs lift");
}

mechgen::Model Load(const std::string& text) { return mechgen::LoadModelFromString(text, "test.yaml"); }

TEST(HigherPairs, GrueblerCountsGearsAndCamsAsOneConstraint) {
  const mechgen::Model planetary = mechgen::LoadModel(std::string(MECHGEN_SOURCE_DIR) + "/models/planetary.yaml");
  const mechgen::Topology t = mechgen::BuildTopology(planetary);
  EXPECT_EQ(t.grubler_mobility, 1);  // 3 (4 - 1) - 2*3 - 2
  EXPECT_EQ(t.loop_mobility, 1);     // 3 angles - 2 gear equations
  EXPECT_EQ(t.loops.size(), 2u);
  EXPECT_NE(t.grubler_text.find("- j2"), std::string::npos);
  for (int c : t.cut_joints) EXPECT_FALSE(planetary.joints[c].IsLowerPair() && planetary.joints[c].name != "P");
}

TEST(HigherPairs, AGearCannotPlaceALink) {
  const std::string text = R"(name: g
links:
  ground: {ground: true, points: {A: [0, 0]}}
  a: {points: {A: [0, 0]}}
  b: {points: {A: [0, 0]}}
joints:
  A: {revolute: [ground.A, a.A]}
  mesh: {gear: {gears: [a, b], radii: [1, 2]}}
inputs:
  - {joint: A}
)";
  const mechgen::Model m = Load(text);
  try {
    mechgen::Validate(m);
    FAIL() << "link b is held only by a gear";
  } catch (const mechgen::ModelError& e) {
    EXPECT_NE(e.message().find("'b' is not connected"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("gears and cams cannot place a link"), std::string::npos) << e.message();
  }
}

TEST(HigherPairs, RackAndPinionEquation) {
  const mechgen::Model m = Load(R"(name: rack
parameters: {r: 0.5}
links:
  ground: {ground: true, points: {O: [0, 0], G: [0, -r]}}
  pinion: {points: {O: [0, 0]}}
  rack:   {points: {C: [0, 0]}}
joints:
  O: {revolute: [ground.O, pinion.O]}
  slide: {prismatic: {guide: ground.G, slider: rack.C, angle: 0}}
  mesh: {rack: {pinion: pinion, radius: r, slide: slide}}
inputs:
  - {joint: O}
)");
  const mechgen::Topology t = mechgen::BuildTopology(m);
  EXPECT_EQ(t.grubler_mobility, 1);  // 3*2 - 2*2 - 1
  const mechgen::Kinematics k = mechgen::DeriveKinematics(m, t);
  ASSERT_EQ(k.nc(), 1);
  ASSERT_EQ(k.nphi(), 1);
  // s + r theta = 0: K = -r.
  const GiNaC::ex K = -k.Phi_q(0, 0) / k.Phi_phi(0, 0);
  GiNaC::exmap at;
  at[m.params[0].symbol] = 0.5;
  EXPECT_EQ(K.subs(at), GiNaC::ex(GiNaC::numeric(-1, 2)));
}

TEST(HigherPairs, DrivingAGearIsRefused) {
  try {
    Load(R"(name: g
links:
  ground: {ground: true, points: {A: [0, 0], B: [3, 0]}}
  a: {points: {A: [0, 0]}}
  b: {points: {B: [0, 0]}}
joints:
  A: {revolute: [ground.A, a.A]}
  B: {revolute: [ground.B, b.B]}
  mesh: {gear: {gears: [a, b], radii: [1, 2]}}
inputs:
  - {joint: mesh}
)");
    FAIL();
  } catch (const mechgen::ModelError& e) {
    EXPECT_NE(e.message().find("cannot be driven"), std::string::npos) << e.message();
    EXPECT_EQ(e.mark().line, 11);
  }
}

}  // namespace
