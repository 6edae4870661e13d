// The model front end and the joint kinds: the reader's key tables against the keys
// models/README.md documents (both ways), unknown keys, outputs as a set of quantities,
// the joint-kind registry, structured provenance of Phi rows, tree-joint placements and
// the validation stage.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "analysis/validate.h"
#include "joints/joint_kind.h"
#include "model/model.h"
#include "model/reader.h"

namespace mechgen {
namespace {

const std::string kModels = std::string(MECHGEN_SOURCE_DIR) + "/models/";

// README's key tables: "### `<section>` keys" followed by rows "| `key` | yes|no | ... |".
std::map<std::string, std::map<std::string, bool>> ReadmeKeyTables() {
  std::ifstream in(kModels + "README.md");
  EXPECT_TRUE(in) << "cannot read models/README.md";
  const std::regex heading(R"(^###\s+`([^`]+)`\s+keys\s*$)");
  const std::regex row(R"(^\|\s*`([^`]+)`\s*\|\s*(yes|no)\s*\|.*\|\s*$)");
  std::map<std::string, std::map<std::string, bool>> out;
  std::string line, section;
  std::smatch match;
  while (std::getline(in, line)) {
    if (std::regex_match(line, match, heading)) {
      section = match[1];
      EXPECT_EQ(out.count(section), 0u) << "README lists the keys of '" << section << "' twice";
      out[section];
    } else if (line.rfind("#", 0) == 0) {
      section.clear();
    } else if (!section.empty() && std::regex_match(line, match, row)) {
      EXPECT_TRUE(out[section].emplace(match[1], match[2] == "yes").second)
          << "README lists key '" << match[1] << "' of '" << section << "' twice";
    }
  }
  return out;
}

TEST(ModelKeys, EveryAcceptedKeyIsInTheReadmeAndNoOther) {
  const auto readme = ReadmeKeyTables();
  std::set<std::string> sections;
  for (const KeyTable* table : AllKeyTables()) {
    sections.insert(table->section);
    const auto it = readme.find(table->section);
    ASSERT_NE(it, readme.end()) << "models/README.md has no \"### `" << table->section << "` keys\" table";
    std::map<std::string, bool> code;
    for (const Key& k : table->keys) code.emplace(k.name, k.required);
    for (const auto& [key, required] : code) {
      const auto r = it->second.find(key);
      if (r == it->second.end()) {
        ADD_FAILURE() << "the reader accepts '" << key << "' in " << table->section << ", README does not list it";
        continue;
      }
      EXPECT_EQ(r->second, required) << table->section << "." << key << ": required in the reader and README differ";
    }
    for (const auto& [key, required] : it->second)
      EXPECT_EQ(code.count(key), 1u) << "README lists '" << key << "' in " << table->section
                                     << ", the reader rejects it";
  }
  for (const auto& [section, keys] : readme)
    EXPECT_EQ(sections.count(section), 1u) << "README has a key table for '" << section << "', the reader none";
  // The reader's tables hold every section and every joint kind.
  for (const char* s : {"model", "parameter", "link", "joint", "input", "outputs", "law segment", "contour", "revolute",
                        "prismatic", "roll", "gear", "rack", "cam", "slot"})
    EXPECT_EQ(sections.count(s), 1u) << s;
}

// A slider-crank whose prismatic joint's body can be replaced.
std::string SliderCrank(const std::string& slide, const std::string& outputs = "") {
  return "name: sc\nlinks:\n"
         "  g: {ground: true, points: {O: [0, 0], S: [0, 0.4]}}\n"
         "  c: {points: {O: [0, 0], B: [1, 0]}}\n"
         "  r: {points: {B: [0, 0], C: [3, 0]}}\n"
         "  s: {points: {C: [0, 0]}}\n"
         "joints:\n"
         "  O: {revolute: [g.O, c.O]}\n"
         "  B: {revolute: [c.B, r.B]}\n"
         "  C: {revolute: [r.C, s.C]}\n"
         "  P: {prismatic: " + slide + "}\n"
         "inputs:\n  - {joint: O}\n" + outputs;
}

TEST(ModelKeys, AnUnknownKeyOfAJointKindIsAnErrorAtItsPlace) {
  try {
    LoadModelFromString(SliderCrank("{guide: g.S, slider: s.C, angel: 0}"), "typo.yaml");
    FAIL() << "the misspelt key was accepted";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.message(),
              "unknown key 'angel' in prismatic joint 'P'; expected one of: angle, guide, relative_angle, slider");
    EXPECT_EQ(e.mark().line, 11);
    EXPECT_EQ(e.mark().column, 44);
  }
}

TEST(Outputs, OrderIsShorthandForTheSetOfQuantities) {
  const std::string slide = "{guide: g.S, slider: s.C}";
  const Model by_default = LoadModelFromString(SliderCrank(slide), "a.yaml");
  EXPECT_EQ(by_default.outputs.quantities, (std::set<Quantity>{Quantity::kK, Quantity::kL, Quantity::kScene}));
  EXPECT_EQ(by_default.outputs.order, 2);
  const Model order1 = LoadModelFromString(SliderCrank(slide, "outputs: {order: 1, scene: false}\n"), "b.yaml");
  EXPECT_EQ(order1.outputs.quantities, (std::set<Quantity>{Quantity::kK}));
  EXPECT_EQ(order1.outputs.order, 1);
  EXPECT_FALSE(order1.outputs.scene);
  const Model set = LoadModelFromString(SliderCrank(slide, "outputs: {quantities: [scene, K]}\n"), "c.yaml");
  EXPECT_EQ(set.outputs.quantities, (std::set<Quantity>{Quantity::kK, Quantity::kScene}));
  EXPECT_EQ(set.outputs.order, 1);
  EXPECT_TRUE(set.outputs.scene);
  const Model none = LoadModelFromString(SliderCrank(slide, "outputs: {quantities: []}\n"), "d.yaml");
  EXPECT_EQ(none.outputs.order, 0);
  EXPECT_FALSE(none.outputs.scene);
  const struct {
    const char* outputs;
    const char* error;
  } bad[] = {
      {"outputs: {quantities: [L]}\n", "L needs K"},
      {"outputs: {quantities: [K, K]}\n", "quantity 'K' is listed twice"},
      {"outputs: {quantities: [K, M]}\n", "unknown quantity 'M'"},
      {"outputs: {order: 2, quantities: [K]}\n", "not both"},
  };
  for (const auto& b : bad) {
    try {
      LoadModelFromString(SliderCrank(slide, b.outputs), "bad.yaml");
      ADD_FAILURE() << b.outputs << " was accepted";
    } catch (const ModelError& e) {
      EXPECT_NE(e.message().find(b.error), std::string::npos) << e.what();
      EXPECT_EQ(e.mark().line, 14) << e.what();
    }
  }
}

TEST(JointKinds, TheRegistryHoldsEveryKindOnceInTypeOrder) {
  const JointType types[] = {JointType::kRevolute, JointType::kPrismatic, JointType::kRoll, JointType::kGear,
                             JointType::kRack,     JointType::kCam,       JointType::kSlot};
  ASSERT_EQ(JointKinds().size(), 7u);
  for (JointType t : types) {
    EXPECT_EQ(KindOf(t).type(), t);
    EXPECT_EQ(FindKind(KindOf(t).Keys().section), &KindOf(t));
    EXPECT_EQ(KindOf(t).IsLowerPair(), t == JointType::kRevolute || t == JointType::kPrismatic ||
                                           t == JointType::kRoll || t == JointType::kSlot);
  }
  EXPECT_EQ(FindKind("hinge"), nullptr);
}

TEST(JointKinds, DescriptionsCoordinatesAndReactionComponents) {
  const Model m = LoadModelFromString(SliderCrank("{guide: g.S, slider: s.C}"), "sc.yaml");
  const Joint& pin = m.joints[0];
  const Joint& slide = m.joints[3];
  EXPECT_EQ(KindOf(pin).Describe(m, pin), "revolute g.O = c.O");
  EXPECT_EQ(KindOf(slide).Describe(m, slide), "prismatic g.S guides s.C");
  EXPECT_FALSE(KindOf(pin).Coordinate(m, pin).has_value());
  ASSERT_TRUE(KindOf(slide).Coordinate(m, slide).has_value());
  EXPECT_EQ(KindOf(slide).Coordinate(m, slide)->name, "s_P");
  EXPECT_EQ(KindOf(pin).ReactionComponents(m, pin).size(), 2u);    // Fx, Fy
  EXPECT_EQ(KindOf(slide).ReactionComponents(m, slide).size(), 3u);  // N, T, M
  // The lower pairs' ends: the points each joint holds on each of its links.
  EXPECT_EQ(m.PointName(slide.End(slide.link_a)), "g.S");
  EXPECT_EQ(m.PointName(slide.End(slide.link_b)), "s.C");
}

// Each kind's reaction equations (JointKind::Reaction, CoulombFriction, RelativeMotion), at
// numbers, against the hand formulas of Paul §5: a pin passes its force on; a slider on a
// line at absolute angle a has N = F.(-sin a, cos a), T = F.(cos a, sin a) plus the forces
// along the line that act apart from F, and its moment; a meshing pair of teeth its force from its row's multiplier
// (MeshForce).
TEST(JointKinds, ReactionComponentsFromTheUnknownsByHand) {
  const Model m = LoadModelFromString(SliderCrank("{guide: g.S, slider: s.C, angle: 0.3}"), "sc.yaml");
  const Joint& pin = m.joints[0];
  const Joint& slide = m.joints[3];
  const double guide_theta = 0.5, a = guide_theta + 0.3;  // the line's absolute angle
  std::vector<Frame> frames(m.links.size());
  frames[slide.link_a].theta = guide_theta;
  frames[slide.link_b].theta = 1.25;
  frames[pin.link_b].theta = 0.75;
  JointReaction r;
  r.F = {GiNaC::ex(2.5), GiNaC::ex(-1.5)};
  r.M = 0.125;
  r.along = 4;
  auto value = [](const GiNaC::ex& e) { return GiNaC::ex_to<GiNaC::numeric>(e.evalf()).to_double(); };
  std::string why;
  const std::vector<GiNaC::ex> at_pin = KindOf(pin).Reaction(m, pin, frames, r, &why);
  ASSERT_EQ(at_pin.size(), KindOf(pin).ReactionComponents(m, pin).size());
  EXPECT_EQ(value(at_pin[0]), 2.5);
  EXPECT_EQ(value(at_pin[1]), -1.5);
  const std::vector<GiNaC::ex> at_slide = KindOf(slide).Reaction(m, slide, frames, r, &why);
  ASSERT_EQ(at_slide.size(), KindOf(slide).ReactionComponents(m, slide).size());
  EXPECT_NEAR(value(at_slide[0]), -2.5 * std::sin(a) - 1.5 * std::cos(a), 1e-15);
  EXPECT_NEAR(value(at_slide[1]), 2.5 * std::cos(a) - 1.5 * std::sin(a) + 4, 1e-15);
  EXPECT_EQ(value(at_slide[2]), 0.125);
  EXPECT_EQ(KindOf(pin).Reacts(), ReactionForm::kForce);
  EXPECT_EQ(KindOf(slide).Reacts(), ReactionForm::kForceAndMoment);

  // Friction: a pin's circle mu r |F| against theta_b - theta_a, a slider's mu |N| against s.
  Friction f;
  f.coefficient = 0.2;
  f.pin_radius = 0.01;
  const JointFriction at_pin_f = KindOf(pin).CoulombFriction(m, pin, f, frames, r);
  EXPECT_NEAR(value(at_pin_f.normal), std::hypot(2.5, 1.5), 1e-15);
  EXPECT_NEAR(value(at_pin_f.gain), 0.002, 1e-18);
  ASSERT_EQ(pin.link_a, slide.link_a);  // the ground, at theta 0.5 here
  EXPECT_EQ(value(KindOf(pin).RelativeMotion(m, pin, frames, 0)), 0.25);
  const JointFriction at_slide_f = KindOf(slide).CoulombFriction(m, slide, f, frames, r);
  EXPECT_NEAR(value(at_slide_f.normal), std::abs(-2.5 * std::sin(a) - 1.5 * std::cos(a)), 1e-15);
  EXPECT_EQ(value(at_slide_f.gain), 0.2);
  EXPECT_EQ(value(KindOf(slide).RelativeMotion(m, slide, frames, 0.375)), 0.375);

  // A meshing pair of teeth (gear, rack): from the mesh row's multiplier lambda, the force on
  // the second member at the pitch point is -lambda along t (e turned +90 deg) plus the
  // separating part |lambda| tan(pressure angle) along e; N = |F|, T = F.t = -lambda.
  EXPECT_EQ(KindOf(JointType::kGear).Reacts(), ReactionForm::kContact);
  EXPECT_EQ(KindOf(JointType::kRack).Reacts(), ReactionForm::kContact);
  EXPECT_EQ(KindOf(JointType::kCam).Reacts(), ReactionForm::kContact);
  EXPECT_EQ(KindOf(JointType::kSlot).Reacts(), ReactionForm::kForce);
  EXPECT_EQ(KindOf(JointType::kRoll).Reacts(), ReactionForm::kForce);
  for (const double lambda : {7.0, -7.0}) {
    const double e_angle = 0.3, pressure = 20 * M_PI / 180;
    JointReaction mesh;
    MeshForce({GiNaC::ex(std::cos(e_angle)), GiNaC::ex(std::sin(e_angle))}, {GiNaC::ex(1.5), GiNaC::ex(2.5)},
              GiNaC::ex(pressure), GiNaC::ex(lambda), &mesh);
    const double tx = -std::sin(e_angle), ty = std::cos(e_angle), sep = std::abs(lambda) * std::tan(pressure);
    const double Fx = -lambda * tx + sep * std::cos(e_angle), Fy = -lambda * ty + sep * std::sin(e_angle);
    ASSERT_EQ(mesh.components.size(), 4u);
    EXPECT_NEAR(value(mesh.F[0]), Fx, 1e-14);
    EXPECT_NEAR(value(mesh.F[1]), Fy, 1e-14);
    EXPECT_EQ(value(mesh.at[0]), 1.5);
    EXPECT_EQ(value(mesh.at[1]), 2.5);
    EXPECT_NEAR(value(mesh.components[2]), std::hypot(Fx, Fy), 1e-14);  // N: along the line of action
    EXPECT_NEAR(value(mesh.components[3]), -lambda, 1e-14);             // T
    EXPECT_NEAR(std::atan2(std::abs(Fx * std::cos(e_angle) + Fy * std::sin(e_angle)), std::abs(Fx * tx + Fy * ty)),
                pressure, 1e-14);
  }
}

TEST(Provenance, EveryPhiRowNamesItsJointLoopAndComponent) {
  for (const char* name : {"fourbar", "slider_crank", "rolling_wheel", "planetary", "cam_contour", "cam_flat"}) {
    const Model m = LoadModel(kModels + name + ".yaml");
    const Analysis a = Validate(m);
    const Kinematics k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    ASSERT_EQ(k.Phi_rows.size(), k.Phi.size()) << name;
    ASSERT_EQ(k.Phi_source.size(), k.Phi.size()) << name;
    for (size_t i = 0; i < k.Phi_rows.size(); ++i) {
      const RowSource& r = k.Phi_rows[i];
      EXPECT_EQ(r.Text(m), k.Phi_source[i]) << name;
      if (r.loop >= 0) {
        EXPECT_EQ(a.topology.loops[r.loop].cut_joint, r.joint) << name << " row " << i;
      } else {  // only a rolling tree joint's no-slip row lies on no loop
        EXPECT_EQ(m.joints[r.joint].type(), JointType::kRoll) << name << " row " << i;
        EXPECT_EQ(r.component, RowComponent::kNoSlip) << name << " row " << i;
      }
    }
    // Tree joints: each moving link placed once, by its parent joint, on the link across it.
    std::set<int> placed;
    for (const Placement& p : k.placements) {
      EXPECT_EQ(a.topology.parent_joint[p.child], p.joint) << name;
      EXPECT_EQ(m.joints[p.joint].OtherLink(p.child), p.parent) << name;
      EXPECT_TRUE(placed.insert(p.child).second) << name;
    }
    EXPECT_EQ(placed.size(), m.links.size() - 1) << name;
  }
  // The four-bar's rows by hand: loop 1 closed at joint C... whichever the tree cut, x then y.
  const Model fb = LoadModel(kModels + "fourbar.yaml");
  const Analysis a = Validate(fb);
  const Kinematics k = DeriveKinematics(fb, a.topology, &a.coordinates, &a.cams);
  ASSERT_EQ(k.Phi_rows.size(), 2u);
  EXPECT_EQ(k.Phi_rows[0].component, RowComponent::kX);
  EXPECT_EQ(k.Phi_rows[1].component, RowComponent::kY);
  EXPECT_EQ(k.Phi_source[0], "loop 1, joint " + fb.joints[k.Phi_rows[0].joint].name + ", x");
}

TEST(Validation, JointNumbersAreCheckedAtTheParametersDefaults) {
  const std::string wheel = R"(name: w
parameters: {r: -1}
links:
  ground: {ground: true, points: {G: [0, 0]}}
  wheel:  {points: {C: [0, 0]}}
joints:
  roll: {roll: {wheel: wheel.C, radius: r, on: ground.G}}
inputs:
  - {joint: roll}
)";
  const Model m = LoadModelFromString(wheel, "w.yaml");  // reading accepts it: r is an expression
  try {
    Validate(m);
    FAIL() << "a negative wheel radius was accepted";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.message(), "the wheel radius must be positive");
    EXPECT_EQ(e.mark().line, 7);
    EXPECT_EQ(e.mark().column, 41);
  }
}

}  // namespace
}  // namespace mechgen
