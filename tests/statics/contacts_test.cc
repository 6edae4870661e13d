// Reactions at higher pairs and at a slot (issue 26): the generated statics of
// tests/statics/models/contacts.yaml (a gear train with an external and an internal mesh, a
// disk cam with a translating roller follower, one with an oscillating flat-faced follower,
// the quick-return shaper with the crank's pin in a slot of the rocker, a rack and pinion, a
// wheel rolling on a line, a cam given by its contour) over a turn of every input, against
// oracles that do not use the generator's statics:
//   - the free-body equilibrium (forces and moments) of every moving link with the generated
//     reactions, the drives and the loads, the points placed by this file's own geometry;
//   - hand solutions: the gear train's tooth forces from the ring's and the idler's moment
//     balances (|T| = torque / pitch radius, N = torque / base radius, the separating part
//     |T| tan of the pressure angle), the cams' contact forces from the follower's balance and
//     the contact's kinematics (the force normal to the relative sliding velocity; the flat
//     face's contact point where the relative velocity lies along the face), by central
//     differences of the generated position solver, and the shaper's bearing O2 from the
//     ram's, the two-force link's and the rocker's balances (Paul §5).
#include "contacts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "statics_test_util.h"

namespace {

using M = mech::contacts::Model;
using P = M::ParamsT<double>;
using mechtest::statics::IndexOf;
using mechtest::statics::kDeg;
using mechtest::statics::Near;
using Phi = Eigen::Matrix<double, M::kNphi, 1>;
using Qv = Eigen::Matrix<double, M::kNq, 1>;
using V = Eigen::Vector2d;

double Cross(const V& a, const V& b) { return a.x() * b.y() - a.y() * b.x(); }
V Dir(double a) { return {std::cos(a), std::sin(a)}; }
V Perp(const V& a) { return {-a.y(), a.x()}; }  // turned +90 deg

// Forces here are O(1..1e4) N from O(1) geometry; the generated code rounds at ~1e-14
// relative. Exact relations: 1e-9 relative to the force scale. Relations through central
// differences of the positions (h = 1e-6: truncation ~1e-12, rounding ~1e-10): 1e-6.
constexpr double kTol = 1e-9;
constexpr double kFdTol = 1e-6;
constexpr double kH = 1e-6;

class ContactReactions : public ::testing::Test {
 protected:
  P p;
  Phi phi;
  mech::contacts::Statics<double> st;

  void SetUp() override {
    for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  }

  int I(const char* name) const {
    const int i = IndexOf(M::kPhiNames, name);
    EXPECT_GE(i, 0) << name;
    return i;
  }
  double R(const std::string& name) const {
    const int i = IndexOf(M::kReactionNames, name);
    EXPECT_GE(i, 0) << name;
    return i >= 0 ? st.R(i) : NAN;
  }
  V F(const std::string& joint) const { return {R("F_" + joint + "_x"), R("F_" + joint + "_y")}; }

  // Solves from *guess (continuation); the statics at q.
  bool Solve(const Qv& q, Phi* guess) const {
    const auto report = M::Solve(p, q, guess);
    return report.status == std::decay_t<decltype(report.status)>::kConverged;
  }
  bool Eval(const Qv& q) {
    if (!Solve(q, &phi)) return false;
    mech::contacts::Coefficients<double> c;
    mech::contacts::EvalCoefficients(p, q, phi, &c);
    mech::contacts::EvalStatics(p, q, phi, c, &st);
    return true;
  }
  // d phi(i) / d q(k) by central differences of the position solver.
  double Rate(const Qv& q, int k, int i) const {
    Qv a = q, b = q;
    a(k) += kH;
    b(k) -= kH;
    Phi pa = phi, pb = phi;
    EXPECT_TRUE(Solve(a, &pa) && Solve(b, &pb));
    return (pa(i) - pb(i)) / (2 * kH);
  }

  // The inputs at step i of a turn (each input its own phase; the crank over its range).
  static Qv Inputs(int i) {
    Qv q;
    q << (3 + i) * kDeg, (7 + i) * kDeg, (1 + i) * kDeg, (-29.5 + i) * kDeg, (2 + i) * kDeg, (4 + i) * kDeg,
        (6 + i) * kDeg;
    return q;
  }
};

TEST_F(ContactReactions, GearTrainEveryGearInEquilibriumAndTheToothForcesByHand) {
  const V G1(-10, 0), G2 = G1 + (p.r1 + p.r2) * Dir(30 * kDeg), G3 = G2 + (p.r3 - p.r2) * Dir(-40 * kDeg);
  const V W1(3, -5), W2(2, 1);
  const int i2 = I("theta_gear2"), i3 = I("theta_ring3");
  // The pitch points: on gear1's circle towards gear2; on gear2's circle away from the ring's centre.
  const V e12 = (G2 - G1).normalized(), e23 = (G2 - G3).normalized();
  const V P12 = G1 + p.r1 * e12, P23 = G2 + p.r2 * e23;
  const double pa12 = 20 * kDeg, pa23 = p.pa23;
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V M1 = G1 + p.r1 * Dir(q(0)), M2 = G2 + p.r2 * Perp(Dir(phi(i2)));
    (void)i3;
    const V FG1 = F("G1"), FG2 = F("G2"), FG3 = F("G3"), F12 = F("m12"), F23 = F("m23");
    const double drive = st.drive(0);
    const double scale = std::max({F12.norm(), F23.norm(), std::abs(drive)});
    const std::string at = " at step " + std::to_string(s);
    // Free bodies: gear1 (ground, mesh, load, drive), gear2 (ground, two meshes, load), ring3.
    EXPECT_TRUE(Near((FG1 - F12 + W1).norm(), 0, kTol, scale, "gear1 forces" + at));
    EXPECT_TRUE(Near(drive + Cross(P12 - G1, -F12) + Cross(M1 - G1, W1), 0, kTol, scale, "gear1 moment" + at));
    EXPECT_TRUE(Near((FG2 + F12 - F23 + W2).norm(), 0, kTol, scale, "gear2 forces" + at));
    EXPECT_TRUE(
        Near(Cross(P12 - G2, F12) + Cross(P23 - G2, -F23) + Cross(M2 - G2, W2), 0, kTol, scale, "gear2 moment" + at));
    EXPECT_TRUE(Near((FG3 + F23).norm(), 0, kTol, scale, "ring3 forces" + at));
    EXPECT_TRUE(Near(p.T3 + Cross(P23 - G3, F23), 0, kTol, scale, "ring3 moment" + at));
    // By hand: the ring's moment gives m23's tangential force, the idler's gives m12's, and
    // gear1's the drive; each tooth force lies along its line of action, separating the gears.
    const double T23 = -p.T3 / p.r3, T12 = Cross(M2 - G2, W2) / p.r2 - T23;
    EXPECT_TRUE(Near(R("T_m23"), T23, kTol, scale, "T_m23 = -T3 / r3" + at));
    EXPECT_TRUE(Near(R("N_m23"), p.T3 / (p.r3 * std::cos(pa23)), kTol, scale, "N_m23 = T3 / r_base" + at));
    EXPECT_TRUE(Near(R("T_m12"), T12, kTol, scale, "T_m12" + at));
    EXPECT_TRUE(Near(R("N_m12"), std::abs(T12) / std::cos(pa12), kTol, scale, "N_m12" + at));
    EXPECT_TRUE(Near(drive, p.r1 * T12 - Cross(M1 - G1, W1), kTol, scale, "drive = r1 T_m12 - load moment" + at));
    for (const auto& [Fm, e, pa, name] :
         {std::make_tuple(F12, e12, pa12, "m12"), std::make_tuple(F23, e23, pa23, "m23")}) {
      EXPECT_TRUE(Near(Fm.dot(Perp(e)), R(std::string("T_") + name), kTol, scale, std::string(name) + " T = F.t" + at));
      EXPECT_TRUE(Near(Fm.dot(e), Fm.norm() * std::sin(pa), kTol, scale,
                       std::string(name) + " separating part |F| sin(pressure angle)" + at));
      EXPECT_TRUE(Near(Fm.norm(), R(std::string("N_") + name), kTol, scale, std::string(name) + " N = |F|" + at));
    }
  }
}

TEST_F(ContactReactions, TranslatingRollerFollowerInEquilibriumWithTheForceNormalToTheSliding) {
  const V CA(10, 0), u(0, 1), n(-1, 0), WA(5, -40);
  const int is = I("s_slideA");
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V C = V(10 + p.e, phi(is)), T = C + u;
    const V Fc = F("contactA"), FO = F("OA");
    const double Ns = R("N_slideA"), Ts = R("T_slideA"), Ms = R("M_slideA"), drive = st.drive(1);
    const double scale = std::max({Fc.norm(), std::abs(drive), 40.0});
    const std::string at = " at step " + std::to_string(s);
    // Free bodies: the cam (bearing, contact, drive) and the follower (contact through the
    // roller's centre C, the guide's N, T at C and M about it, the load at T).
    EXPECT_TRUE(Near((FO - Fc).norm(), 0, kTol, scale, "cam forces" + at));
    EXPECT_TRUE(Near(drive + Cross(C - CA, -Fc), 0, kTol, scale, "cam moment" + at));
    EXPECT_TRUE(Near((Fc + Ns * n + Ts * u + WA).norm(), 0, kTol, scale, "follower forces" + at));
    EXPECT_TRUE(Near(Ms + Cross(T - C, WA), 0, kTol, scale, "follower moment" + at));
    EXPECT_TRUE(Near(Ts, 0, kTol, scale, "no actuator or friction along the guide" + at));
    // By hand: frictionless, the force is normal to the roller's sliding relative to the cam,
    // v_rel = ds/dpsi u - k x (C - CA), and the follower's balance along u gives F.u = 40 N.
    const V v_rel = Rate(q, 1, is) * u - Perp(C - CA);
    const V w = Perp(v_rel);
    const V hand = -WA.dot(u) / w.dot(u) * w;
    EXPECT_TRUE(Near((Fc - hand).norm(), 0, kFdTol, scale, "contact force, hand" + at));
    EXPECT_TRUE(Near(R("N_contactA"), Fc.norm(), kTol, scale, "N = |F|, pushing" + at));
  }
}

TEST_F(ContactReactions, OscillatingFlatFaceInEquilibriumWithItsContactPointFromTheKinematics) {
  const V CB(20, 0), AB(20 + p.dB, 0);
  const int it = I("theta_followerB");
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V uf = Dir(phi(it)), nf = Perp(uf);
    const V Fc = F("contactB"), FO = F("OB"), FA = F("AB");
    const double drive = st.drive(2);
    const double scale = std::max({Fc.norm(), std::abs(drive), p.TB});
    const std::string at = " at step " + std::to_string(s);
    // The contact point on the face, C = AB + c uf, where the relative velocity of the cam's
    // and the face's points lies along the face: (C - CB) x nf = w_f (C - AB) x nf, w_f the
    // follower's angular velocity per unit cam angle (central differences).
    const double wf = Rate(q, 2, it);
    const double c = Cross(AB - CB, nf) / (wf - 1);
    const V C = AB + c * uf;
    // Free bodies: the follower (pivot, contact at C, the torque -TB), the cam.
    EXPECT_TRUE(Near((FA + Fc).norm(), 0, kTol, scale, "follower forces" + at));
    EXPECT_TRUE(Near(Cross(C - AB, Fc) - p.TB, 0, kFdTol, scale, "follower moment about its pivot" + at));
    EXPECT_TRUE(Near((FO - Fc).norm(), 0, kTol, scale, "cam forces" + at));
    EXPECT_TRUE(Near(drive + Cross(C - CB, -Fc), 0, kFdTol, scale, "cam moment about its axis" + at));
    // By hand: along the face's normal, f = TB / c, pushing the face away from the cam.
    EXPECT_TRUE(Near(Fc.dot(uf), 0, kTol, scale, "no force along the face" + at));
    EXPECT_TRUE(Near((Fc - p.TB / c * nf).norm(), 0, kFdTol, scale, "contact force, hand" + at));
    EXPECT_TRUE(Near(R("N_contactB"), Fc.norm(), kTol, scale, "N = |F|, pushing" + at));
  }
}

TEST_F(ContactReactions, ShaperWithASlotBearingO2ByHandAndEveryLinkInEquilibrium) {
  const V O4(0, 0), O2(0, p.d), ux(1, 0), uy(0, 1), cut(p.Fc, 0);
  const int ir = I("theta_rocker"), il = I("theta_link"), isA = I("s_A");
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V A = O2 + p.r * Dir(q(3)), u = Dir(phi(ir)), n = Perp(u), B = p.L * u, e = Dir(phi(il)), C = B + p.l * e;
    const std::string at = " at step " + std::to_string(s);
    ASSERT_TRUE(Near((A - phi(isA) * u).norm(), 0, 1e-12, 1, "the pin on the slot" + at));
    const V FO2 = F("O2"), FA = F("A"), FO4 = F("O4"), FB = F("B"), FC = F("C");
    const double Ns = R("N_stroke"), Ts = R("T_stroke"), Ms = R("M_stroke"), drive = st.drive(3);
    const double scale = std::max({FO2.norm(), FC.norm(), std::abs(drive), p.Fc});
    // By hand: the link BC carries f e (a two-force member); the ram's balance along x gives f,
    // the rocker's moments about O4 the slot's normal force N_A (of the rocker on the pin, along
    // n), and the crank's balance the ground's force at O2: -N_A n.
    const double f = -p.Fc / e.x();
    const double NA = -f * Cross(B, e) / phi(isA);
    EXPECT_TRUE(Near((FO2 + NA * n).norm(), 0, kTol, scale, "ground bearing O2, hand" + at));
    EXPECT_TRUE(Near(R("N_A"), NA, kTol, scale, "slot's normal force, hand" + at));
    EXPECT_TRUE(Near(R("T_A"), 0, kTol, scale, "no force along the frictionless slot" + at));
    EXPECT_TRUE(Near(drive, -Cross(A - O2, NA * n), kTol, scale, "drive, hand" + at));
    // Free bodies of the crank, the rocker, the link and the ram.
    EXPECT_TRUE(Near((FO2 + FA).norm(), 0, kTol, scale, "crank forces" + at));
    EXPECT_TRUE(Near(drive + Cross(A - O2, FA), 0, kTol, scale, "crank moment" + at));
    EXPECT_TRUE(Near((FO4 - FA - FB).norm(), 0, kTol, scale, "rocker forces" + at));
    EXPECT_TRUE(Near(Cross(A - O4, -FA) + Cross(B - O4, -FB), 0, kTol, scale, "rocker moment" + at));
    EXPECT_TRUE(Near((FB - FC).norm(), 0, kTol, scale, "link forces" + at));
    EXPECT_TRUE(Near(Cross(C - B, -FC), 0, kTol, scale, "link moment" + at));
    EXPECT_TRUE(Near((FC + Ns * uy + Ts * ux + cut).norm(), 0, kTol, scale, "ram forces" + at));
    EXPECT_TRUE(Near(Ms, 0, kTol, scale, "ram moment (every force at C)" + at));
  }
}

TEST_F(ContactReactions, RackAndPinionInEquilibriumWithTheToothForceByHand) {
  const V K(30, 0), u(1, 0), n(0, 1), WK(-50, 8), pitch(30, p.rk), Tlocal(0.5, 0.1);
  const int is = I("s_rslide");
  const double pa = 20 * kDeg;
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V S = V(30, p.rk) + phi(is) * u, T = S + Tlocal;
    const V FK = F("K"), Fm = F("mesh");
    const double Ns = R("N_rslide"), Ts = R("T_rslide"), Ms = R("M_rslide"), drive = st.drive(4);
    const double scale = std::max({Fm.norm(), std::abs(drive), 50.0});
    const std::string at = " at step " + std::to_string(s);
    // The rack slides with s = -rk theta (the mesh row), so the pitch point lies on the pinion's
    // circle at rk n; the rack's balance along u gives F.u = 50 N, the separating part F.n = 50 tan 20 deg.
    EXPECT_TRUE(Near((Fm - V(50, 50 * std::tan(pa))).norm(), 0, kTol, scale, "tooth force, hand" + at));
    EXPECT_TRUE(Near(R("T_mesh"), -50, kTol, scale, "T along t = -u" + at));
    EXPECT_TRUE(Near(R("N_mesh"), 50 / std::cos(pa), kTol, scale, "N = T / cos(pressure angle)" + at));
    EXPECT_TRUE(Near((FK - Fm).norm(), 0, kTol, scale, "pinion forces" + at));
    EXPECT_TRUE(Near(drive + Cross(pitch - K, -Fm), 0, kTol, scale, "pinion moment" + at));
    EXPECT_TRUE(Near((Fm + Ns * n + Ts * u + WK).norm(), 0, kTol, scale, "rack forces" + at));
    EXPECT_TRUE(Near(Ms + Cross(pitch - S, Fm) + Cross(T - S, WK), 0, kTol, scale, "rack moment" + at));
  }
}

TEST_F(ContactReactions, WheelRollingAsATreeJointInEquilibriumAtItsContactPoint) {
  const V WW(3, -10);
  const int is = I("s_roll");
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V Qc(40 + phi(is), 0), C = Qc + V(0, p.rw), P = C + p.rw * Perp(Perp(Perp(Dir(q(5)))));  // (0, -rw) turned
    const V Fr = F("roll");
    const double drive = st.drive(5), scale = std::max(std::abs(drive), 10.0);
    const std::string at = " at step " + std::to_string(s);
    EXPECT_TRUE(Near(phi(is), -p.rw * q(5), kTol, 1, "no slip" + at));
    EXPECT_TRUE(Near((Fr + WW).norm(), 0, kTol, scale, "wheel forces" + at));
    EXPECT_TRUE(Near(drive + Cross(P - Qc, WW), 0, kTol, scale, "wheel moment about the contact point" + at));
    EXPECT_TRUE(Near(R("N_roll"), 10, kTol, scale, "N along the normal (0, 1)" + at));
    EXPECT_TRUE(Near(R("T_roll"), -3, kTol, scale, "T along the line (1, 0)" + at));
  }
}

TEST_F(ContactReactions, ContourCamInEquilibriumWithTheForceThroughTheCircleCentre) {
  const V EC(50, 0), u(0, 1), n(-1, 0), WC(1, -20);
  const int is = I("s_slideC");
  for (int s = 0; s < 360; s += 5) {
    const Qv q = Inputs(s);
    ASSERT_TRUE(Eval(q)) << s;
    const V C = EC + phi(is) * u, T = C + u, Z = EC + p.ec * Perp(Dir(q(6)));  // the circle's centre
    const V Fc = F("contactC"), FO = F("OC");
    const double Ns = R("N_slideC"), Ts = R("T_slideC"), Ms = R("M_slideC"), drive = st.drive(6);
    const double scale = std::max({Fc.norm(), std::abs(drive), 20.0});
    const std::string at = " at step " + std::to_string(s);
    // Frictionless on a circle: along the radius through the roller's centre, F.u = 20 N.
    const V hand = 20 / (C - Z).dot(u) * (C - Z);
    EXPECT_TRUE(Near((Fc - hand).norm(), 0, kTol, scale, "contact force, hand" + at));
    EXPECT_TRUE(Near(R("N_contactC"), Fc.norm(), kTol, scale, "N = |F|, pushing" + at));
    EXPECT_TRUE(Near((FO - Fc).norm(), 0, kTol, scale, "cam forces" + at));
    EXPECT_TRUE(Near(drive + Cross(C - EC, -Fc), 0, kTol, scale, "cam moment" + at));
    EXPECT_TRUE(Near((Fc + Ns * n + Ts * u + WC).norm(), 0, kTol, scale, "follower forces" + at));
    EXPECT_TRUE(Near(Ms + Cross(T - C, WC), 0, kTol, scale, "follower moment" + at));
  }
}

}  // namespace
