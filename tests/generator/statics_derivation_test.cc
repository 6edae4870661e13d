// The statics derivation (symbolic/statics.h) on many topologies, at 50 digits:
//  - every shipped model made of revolute and prismatic joints whose blocks are closed forms
//    (one and several loops, cut
//    and tree prismatic joints, one and two inputs) gets weights, a force and a torque on
//    every moving link, a linear spring, a torsional spring and friction at every joint; its
//    configuration is solved by Newton's method in CLN arithmetic, and with the derived
//    reactions, driving forces and friction loads every moving link is in equilibrium (sum
//    of forces and of moments zero) -- the free-body balance is written here, apart from the
//    derivation (which balances subtrees and solves for multipliers), and the input link's
//    moment balance checks the driving torque (the virtual work of the loads);
//  - the statics sections' errors: file:line:column and what to change.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "joints/joint_kind.h"
#include "model/model.h"
#include "symbolic/statics.h"
#include "symbolic/table.h"

namespace mechgen {
namespace {

using GiNaC::ex;
using GiNaC::numeric;

const std::string kModels = std::string(MECHGEN_SOURCE_DIR) + "/models/";

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A shipped model with loads on every moving link, a spring, a torsional spring (at the
// first revolute joint between two moving links) and friction at every joint; reactions
// at every joint.
std::string Loaded(const std::string& model) {
  YAML::Node root = YAML::Load(Slurp(kModels + model + ".yaml"));
  YAML::Node links = root["links"];
  std::string ground, last_moving, last_point, ground_point;
  int i = 0;
  YAML::Node loads, springs, friction, reactions;
  for (auto it = links.begin(); it != links.end(); ++it, ++i) {
    const std::string name = it->first.as<std::string>();
    YAML::Node spec = it->second;
    const std::string first = spec["points"].begin()->first.as<std::string>();
    if (spec["ground"] && spec["ground"].as<std::string>() == "true") {
      ground = name;
      ground_point = first;
      continue;
    }
    spec["mass"] = std::to_string(1.0 + 0.25 * i);
    spec["center"].push_back(std::to_string(0.1 * i));
    spec["center"].push_back("-0.05");
    spec["inertia"] = "0.1";
    YAML::Node force;
    force["force"].push_back(std::to_string(0.5 + i));
    force["force"].push_back(std::to_string(-1.5 + 0.3 * i));
    force["at"] = name + "." + first;
    if (i % 2) force["frame"] = "link";
    loads["f_" + name] = force;
    YAML::Node torque;
    torque["torque"] = std::to_string(0.7 - 0.2 * i) + " + 0.1*sin(theta_" + name + ")";
    torque["on"] = name;
    loads["t_" + name] = torque;
    last_moving = name;
    for (auto pt = spec["points"].begin(); pt != spec["points"].end(); ++pt) last_point = pt->first.as<std::string>();
  }
  YAML::Node spring;
  spring["between"].push_back(ground + "." + ground_point);
  spring["between"].push_back(last_moving + "." + last_point);
  spring["stiffness"] = "3.5";
  spring["free_length"] = "0.5";
  spring["preload"] = "0.25";
  springs["spring"] = spring;
  bool torsional = false;
  for (auto it = root["joints"].begin(); it != root["joints"].end(); ++it) {
    const std::string name = it->first.as<std::string>();
    reactions.push_back(name);
    YAML::Node f;
    f["coefficient"] = "0.15";
    if (it->second["revolute"]) {
      f["pin_radius"] = "0.05";
      const std::string a = it->second["revolute"][0].as<std::string>(), b = it->second["revolute"][1].as<std::string>();
      if (!torsional && a.rfind(ground + ".", 0) != 0 && b.rfind(ground + ".", 0) != 0) {
        YAML::Node t;
        t["torsional"] = name;
        t["stiffness"] = "2.0";
        t["free_angle"] = "0.3";
        springs["twist"] = t;
        torsional = true;
      }
    }
    friction[name] = f;
  }
  root["gravity"].push_back("0");
  root["gravity"].push_back("-9.81");
  root["loads"] = loads;
  root["springs"] = springs;
  root["friction"] = friction;
  root["outputs"] = YAML::Node();
  root["outputs"]["quantities"].push_back("K");
  root["outputs"]["quantities"].push_back("L");
  root["outputs"]["quantities"].push_back("forces");
  root["outputs"]["quantities"].push_back("potential");
  root["outputs"]["reactions"] = reactions;
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

struct Evaluated {
  GiNaC::exmap at;  // every symbol -> its value
  ex operator()(const ex& e) const { return e.subs(at).evalf(); }
};

double D(const ex& e) { return GiNaC::ex_to<numeric>(e.evalf()).to_double(); }

// Solves Phi(q, phi) = 0 for phi by Newton's method at the current GiNaC Digits.
void SolvePhi(const Kinematics& k, GiNaC::exmap* at) {
  for (int it = 0; it < 60; ++it) {
    GiNaC::matrix J(k.nphi(), k.nphi()), r(k.nphi(), 1);
    for (int i = 0; i < k.nc(); ++i) {
      r(i, 0) = k.Phi[i].subs(*at).evalf();
      for (int j = 0; j < k.nphi(); ++j) J(i, j) = k.Phi_phi(i, j).subs(*at).evalf();
    }
    const GiNaC::matrix dx = J.inverse().mul(r);
    for (int j = 0; j < k.nphi(); ++j) (*at)[k.phi[j].symbol] = ((*at)[k.phi[j].symbol] - dx(j, 0)).evalf();
  }
}

class StaticsAt50Digits : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { GiNaC::Digits = 50; }
  void TearDown() override { GiNaC::Digits = 17; }
};

TEST_P(StaticsAt50Digits, EveryLinkIsInEquilibriumWithTheDriveAndTheReactions) {
  const std::string text = Loaded(GetParam());
  const Model m = LoadModelFromString(text, GetParam() + "_loaded.yaml");
  const Analysis a = Validate(m);
  const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
  const SymbolicTable t(m, k);
  const StaticsTable st(m, k, t);
  const int nq = k.nq(), nphi = k.nphi();
  ASSERT_EQ(st.R.size(), st.layout.reactions.size());

  // The configuration: inputs a little off the assembly, phi solved at 50 digits.
  GiNaC::exmap base = m.Defaults();
  for (int j = 0; j < nq; ++j) base[k.q[j].symbol] = numeric(k.assembly_q[j]) + numeric(3, 10) * (j + 1);
  for (int j = 0; j < nphi; ++j) base[k.phi[j].symbol] = numeric(k.assembly_phi[j]);
  for (int sweep = 0; sweep < 3; ++sweep) {  // move in small steps from the assembly
    GiNaC::exmap at = base;
    SolvePhi(k, &at);
    base = at;
  }
  Evaluated E{base};
  for (int i = 0; i < k.nc(); ++i) ASSERT_LT(std::abs(D(E(k.Phi[i]))), 1e-40) << "Phi does not close";
  // K from Phi_phi K = -Phi_q; the symbols the statics read.
  GiNaC::matrix Jp(nphi, nphi), Jq(nphi, nq);
  for (int i = 0; i < nphi; ++i) {
    for (int j = 0; j < nphi; ++j) Jp(i, j) = E(k.Phi_phi(i, j));
    for (int j = 0; j < nq; ++j) Jq(i, j) = E(k.Phi_q(i, j));
  }
  const GiNaC::matrix K = Jp.inverse().mul(Jq).mul_scalar(-1);
  std::vector<numeric> f;
  for (const auto& [sym, slot] : st.slots.all()) {
    const int i = slot.i, j = slot.j;
    if (slot.kind == Slot::Kind::kK) E.at[sym] = K(i, j);
    else if (slot.kind == Slot::Kind::kPhiPhi) E.at[sym] = Jp(i, j);
    else if (slot.kind == Slot::Kind::kFriction) {
      E.at[sym] = numeric(i % 2 ? -3 : 2, 7) * (i + 1);  // arbitrary friction loads
      f.push_back(GiNaC::ex_to<numeric>(E.at[sym]));
    }
  }
  for (const Statement& s : st.program) {
    ASSERT_EQ(s.kind, Statement::Kind::kDefine) << GetParam() << ": a block above closed form";
    E.at[s.symbol] = E(s.value);
  }

  // Free bodies: every moving link, every force and couple that acts on it.
  const int nl = static_cast<int>(m.links.size());
  std::vector<ex> Fx(nl, 0), Fy(nl, 0), Mz(nl, 0);  // moments about the origin
  auto force = [&](int l, const Vec2& at, const ex& fx, const ex& fy) {
    Fx[l] += fx;
    Fy[l] += fy;
    Mz[l] += E(at[0]) * fy - E(at[1]) * fx;
  };
  auto couple = [&](int l, const ex& c) { Mz[l] += c; };
  auto point = [&](PointRef r) { return PointPosition(m, r, k.frames[r.link]); };
  std::map<int, int> reaction_index;
  for (size_t i = 0; i < st.layout.reactions.size(); ++i)
    if (!reaction_index.count(st.layout.reactions[i].joint)) reaction_index[st.layout.reactions[i].joint] = static_cast<int>(i);
  for (size_t jn = 0; jn < m.joints.size(); ++jn) {
    const Joint& j = m.joints[jn];
    const int r = reaction_index.at(static_cast<int>(jn));
    if (j.type() == JointType::kRevolute) {
      const ex fx = E(st.R[r]), fy = E(st.R[r + 1]);
      const Vec2 at = point(j.End(j.link_b));
      force(j.link_b, at, fx, fy);
      force(j.link_a, at, -fx, -fy);
    } else {
      const ex alpha = E(k.frames[j.link_a].theta + j.Data<PrismaticData>().angle);
      const ex N = E(st.R[r]), T = E(st.R[r + 1]), M = E(st.R[r + 2]);
      const ex fx = (-N * GiNaC::sin(alpha) + T * GiNaC::cos(alpha)).evalf();
      const ex fy = (N * GiNaC::cos(alpha) + T * GiNaC::sin(alpha)).evalf();
      const Vec2 at = point(j.End(j.link_b));
      force(j.link_b, at, fx, fy);
      force(j.link_a, at, -fx, -fy);
      couple(j.link_b, M);
      couple(j.link_a, -M);
    }
  }
  for (size_t i = 0; i < st.layout.friction.size(); ++i) {
    const Joint& j = m.joints[st.layout.friction[i]];
    if (j.type() == JointType::kRevolute) {  // prismatic: inside T
      couple(j.link_b, f[i]);
      couple(j.link_a, -f[i]);
    }
  }
  for (int q = 0; q < nq; ++q) {
    const Joint& in = m.joints[m.inputs[q].joint];
    if (in.type() == JointType::kRevolute) {  // prismatic: inside T
      const int moving = m.links[in.link_a].ground ? in.link_b : in.link_a;
      couple(moving, E(st.drive[q]));
      couple(in.OtherLink(moving), -E(st.drive[q]));
    }
  }
  GiNaC::exmap coords;  // the loads' coordinate names
  for (const auto& [name, sym] : m.coordinate_refs)
    for (int l = 0; l < nl; ++l)
      if (name == "theta_" + m.links[l].name) coords[sym] = k.frames[l].theta;
  for (const Load& l : m.loads) {
    if (l.kind == Load::Kind::kTorque) {
      couple(l.link, E(l.torque.subs(coords)));
      continue;
    }
    Vec2 F = {l.fx.subs(coords), l.fy.subs(coords)};
    if (l.link_frame) F = Rotate(k.frames[l.link].theta, F[0], F[1]);
    force(l.link, point(l.at), E(F[0]), E(F[1]));
  }
  for (int l = 0; l < nl; ++l) {
    const MassProperties& mp = m.links[l].mass;
    if (!mp.given) continue;
    const Vec2 c = Rotate(k.frames[l].theta, mp.center_x, mp.center_y);
    force(l, {k.frames[l].x + c[0], k.frames[l].y + c[1]}, E(m.gravity_x * mp.mass), E(m.gravity_y * mp.mass));
  }
  for (const Spring& s : m.springs) {
    if (s.torsional) {
      const Joint& j = m.joints[s.joint];
      const ex tau = E(-s.stiffness * (k.frames[j.link_b].theta - k.frames[j.link_a].theta - s.free_angle));
      couple(j.link_b, tau);
      couple(j.link_a, -tau);
      continue;
    }
    const Vec2 ra = point(s.a), rb = point(s.b);
    const ex dx = E(rb[0] - ra[0]), dy = E(rb[1] - ra[1]);
    const ex l = GiNaC::sqrt(dx * dx + dy * dy).evalf();
    const ex tension = E(s.preload + s.stiffness * (l - s.free_length));
    force(s.a.link, ra, (tension * dx / l).evalf(), (tension * dy / l).evalf());
    force(s.b.link, rb, (-tension * dx / l).evalf(), (-tension * dy / l).evalf());
  }
  double scale = 1;
  for (size_t i = 0; i < st.R.size(); ++i) scale = std::max(scale, std::abs(D(E(st.R[i]))));
  for (int l = 0; l < nl; ++l) {
    if (m.links[l].ground) continue;
    EXPECT_LT(std::abs(D(Fx[l])), 1e-35 * scale) << GetParam() << ": link " << m.links[l].name << ", sum Fx";
    EXPECT_LT(std::abs(D(Fy[l])), 1e-35 * scale) << GetParam() << ": link " << m.links[l].name << ", sum Fy";
    EXPECT_LT(std::abs(D(Mz[l])), 1e-35 * scale) << GetParam() << ": link " << m.links[l].name << ", sum M";
  }
}

INSTANTIATE_TEST_SUITE_P(LowerPairModels, StaticsAt50Digits,
                         ::testing::Values("fourbar", "fourbar_crossed", "slider_crank", "inverted_slider_crank",
                                           "quick_return", "fivebar", "watt_sixbar", "stephenson_sixbar"),
                         [](const auto& info) { return info.param; });

// ---- errors ----

void ExpectError(const std::string& text, const std::string& where, const std::string& what) {
  try {
    const Model m = LoadModelFromString(text, "bad.yaml");
    const Analysis a = Validate(m);
    const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    const SymbolicTable t(m, k);
    const StaticsTable st(m, k, t);
    ADD_FAILURE() << "no error; expected " << where << ": " << what;
  } catch (const ModelError& e) {
    EXPECT_EQ(std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column), where) << e.message();
    EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
  }
}

const char* kBase = R"(name: s
parameters: {a: 1.0, b: 3.5, c: 3.0, d: 4.0}
links:
  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}}
  coupler: {points: {B: [0, 0], C: [b, 0]}}
  rocker:  {points: {D: [0, 0], C: [c, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  B: {revolute: [crank.B, coupler.B]}
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
inputs:
  - {joint: A}
assembly: {theta_crank: 1.57, theta_coupler: 0.5, theta_rocker: 1.9}
)";

TEST(StaticsErrors, EachNamesItsPlaceAndWhatToChange) {
  const std::string base = kBase;
  ExpectError(base + "loads:\n  f: {force: [1, 0], at: coupler.Q}\n", "17:26", "has no point 'Q'");
  ExpectError(base + "loads:\n  f: {force: [1, 0], torque: 2, at: coupler.B}\n", "17:6", "exactly one of force");
  ExpectError(base + "loads:\n  f: {torque: 2, on: ground}\n", "17:3", "acts on the ground link");
  ExpectError(base + "loads:\n  f: {force: [1, s_A], at: coupler.B}\n", "17:18", "unknown name 's_A'");
  ExpectError(base + "loads:\n  f: {force: [1, 2*t], at: coupler.B}\n", "17:20", "reserved for the dynamics");
  ExpectError(base + "loads:\n  f: {torque: theta_crank_dot, on: coupler}\n", "17:15", "reserved for the dynamics");
  ExpectError(base + "loads:\n  f: {force: [1, 0], at: coupler.B, frame: body}\n", "17:44", "fixed");
  ExpectError(base + "springs:\n  k: {torsional: A, stiffness: -1}\n", "17:32", "negative");
  ExpectError(base + "springs:\n  k: {between: [crank.A, crank.B], stiffness: 1}\n", "17:16", "one link");
  ExpectError(base + "friction:\n  B: {coefficient: 0.1}\n", "17:6", "pin_radius");
  ExpectError(base + "friction:\n  X: {coefficient: 0.1}\n", "17:3", "unknown joint 'X'");
  ExpectError(base + "gravity: [0, -9.81]\noutputs: {quantities: [forces]}\n", "17:10", "forces need K");
  ExpectError(base + "outputs: {reactions: [A]}\n", "16:22", "reactions need forces");
  ExpectError(base + "outputs: {quantities: [K, forces]}\n", "16:10", "need something to act");
  std::string massive = base;
  const std::string crank = "  crank:   {points: {A: [0, 0], B: [a, 0]}}";
  massive.replace(massive.find(crank), crank.size(), "  crank:   {points: {A: [0, 0], B: [a, 0]}, center: [0, 0]}");
  ExpectError(massive, "5:53", "no mass");
}

}  // namespace
}  // namespace mechgen
