// Structure analysis, checked against hand derivations: Grashof classes of a table of
// four-bars (Paul appendix A), mobility of a table of topologies (Grübler–Kutzbach and the
// loop criterion, including a structure and an over-constrained chain), the input-range
// check, and the solve order (blocks) of the multi-loop models derived by hand.
#include <gtest/gtest.h>

#include <sstream>

#include "analysis/grashof.h"
#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "analysis/validate.h"
#include "model/model.h"
#include "symbolic/blocks.h"

namespace mechgen {
namespace {

// A four-bar with ground AD = d, input crank AB = a, coupler BC = b, rocker DC = c.
std::string FourBar(double a, double b, double c, double d, const std::string& range = "[0, 360*deg]",
                    const std::string& input = "A") {
  std::ostringstream os;
  os << "name: fb\nparameters: {a: " << a << ", b: " << b << ", c: " << c << ", d: " << d << "}\n"
     << "links:\n"
     << "  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}\n"
     << "  crank:   {points: {A: [0, 0], B: [a, 0]}}\n"
     << "  coupler: {points: {B: [0, 0], C: [b, 0]}}\n"
     << "  rocker:  {points: {D: [0, 0], C: [c, 0]}}\n"
     << "joints:\n"
     << "  A: {revolute: [ground.A, crank.A]}\n"
     << "  B: {revolute: [crank.B, coupler.B]}\n"
     << "  C: {revolute: [coupler.C, rocker.C]}\n"
     << "  D: {revolute: [rocker.D, ground.D]}\n"
     << "inputs:\n  - {joint: " << input << ", range: " << range << "}\n";
  return os.str();
}

struct GrashofCase {
  double a, b, c, d;
  const char* type;   // a part of the expected class
  const char* range;  // a crank range the loop reaches (worked out by hand from |BD|)
};

TEST(Grashof, TableOfFourBars) {
  const GrashofCase cases[] = {
      {1, 3.5, 3, 4, "crank-rocker: 'crank'", "[0, 360*deg]"},  // s + l = 5 < 6.5, crank shortest
      {2, 3, 3.5, 1, "double-crank", "[0, 360*deg]"},           // ground shortest: drag link
      {3, 1, 3.5, 2.5, "double-rocker", "[60*deg, 100*deg]"},   // coupler shortest; |BD| in [2.5, 4.5] for 53..109 deg
      {2, 3, 2, 3, "change point", "[10*deg, 170*deg]"},        // parallelogram: s + l = p + q
      {1, 2, 3, 4, "change point", "[10*deg, 350*deg]"},        // s + l = 1 + 4 = 2 + 3
      {3, 2.5, 2, 4, "non-Grashof", "[-70*deg, 70*deg]"},       // s + l = 6 > 5.5; |BD| <= 4.5 for |theta| <= 78.6 deg
  };
  for (const auto& c : cases) {
    const Model m = LoadModelFromString(FourBar(c.a, c.b, c.c, c.d, c.range), "grashof.yaml");
    const auto loops = ClassifyFourBars(m, BuildTopology(m));
    ASSERT_EQ(loops.size(), 1u);
    EXPECT_NE(loops[0].type.find(c.type), std::string::npos)
        << c.a << " " << c.b << " " << c.c << " " << c.d << ": " << loops[0].Text();
  }
}

TEST(Grashof, ARockerDrivenThroughAFullTurnIsAnError) {
  // Driven at the rocker's pivot D, the crank-rocker's rocker (c = 3) only swings.
  try {
    const Model m = LoadModelFromString(FourBar(1, 3.5, 3, 4, "[0, 360*deg]", "D"), "rocker.yaml");
    Validate(m);
    FAIL() << "a full turn of the rocker was accepted";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.mark().line, 14);  // the input's line
    EXPECT_NE(e.message().find("link 'rocker' cannot reach"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("crank-rocker"), std::string::npos) << e.what();
  }
  // The crank of the same linkage turns fully: no error.
  const Model ok = LoadModelFromString(FourBar(1, 3.5, 3, 4), "crank.yaml");
  EXPECT_NO_THROW(Validate(ok));
}

struct MobilityCase {
  const char* name;
  const char* links;   // YAML of links
  const char* joints;  // YAML of joints
  int grubler;         // 3 (n - 1) - 2 j1, by hand
  const char* error;   // expected error text, or "" if it generates
};

std::string Topo(const MobilityCase& c, const std::string& inputs) {
  return std::string("name: t\nlinks:\n") + c.links + "joints:\n" + c.joints + "inputs:\n" + inputs;
}

TEST(Mobility, TableOfTopologies) {
  const MobilityCase cases[] = {
      {"fourbar",
       "  g: {ground: true, points: {A: [0, 0], D: [4, 0]}}\n  c: {points: {A: [0, 0], B: [1, 0]}}\n"
       "  k: {points: {B: [0, 0], C: [3.5, 0]}}\n  r: {points: {D: [0, 0], C: [3, 0]}}\n",
       "  A: {revolute: [g.A, c.A]}\n  B: {revolute: [c.B, k.B]}\n  C: {revolute: [k.C, r.C]}\n  D: {revolute: [r.D, g.D]}\n",
       1, ""},
      {"triangle (a structure)",
       "  g: {ground: true, points: {A: [0, 0], C: [2, 0]}}\n  l1: {points: {A: [0, 0], B: [1, 0]}}\n"
       "  l2: {points: {B: [0, 0], C: [1, 0]}}\n",
       "  A: {revolute: [g.A, l1.A]}\n  B: {revolute: [l1.B, l2.B]}\n  C: {revolute: [l2.C, g.C]}\n",
       0, "cannot move: mobility 0"},
      {"four links, six pins (over-constrained)",
       "  g: {ground: true, points: {A: [0, 0], D: [4, 0]}}\n  c: {points: {A: [0, 0], B: [1, 0], E: [0, 1]}}\n"
       "  k: {points: {B: [0, 0], C: [3.5, 0], F: [1, 1]}}\n  r: {points: {D: [0, 0], C: [3, 0], G: [1, 0]}}\n",
       "  A: {revolute: [g.A, c.A]}\n  B: {revolute: [c.B, k.B]}\n  C: {revolute: [k.C, r.C]}\n"
       "  D: {revolute: [r.D, g.D]}\n  E: {revolute: [c.E, r.G]}\n  F: {revolute: [k.F, g.D]}\n",
       -3, "structure and over-constrained"},
      {"slider-crank",
       "  g: {ground: true, points: {O: [0, 0], S: [0, 0.4]}}\n  c: {points: {O: [0, 0], B: [1, 0]}}\n"
       "  r: {points: {B: [0, 0], C: [3, 0]}}\n  s: {points: {C: [0, 0]}}\n",
       "  O: {revolute: [g.O, c.O]}\n  B: {revolute: [c.B, r.B]}\n  C: {revolute: [r.C, s.C]}\n"
       "  P: {prismatic: {guide: g.S, slider: s.C}}\n",
       1, ""},
  };
  for (const auto& c : cases) {
    const std::string text = Topo(c, "  - {joint: A}\n");
    const std::string text_slider = Topo(c, "  - {joint: O}\n");
    const std::string& use = std::string(c.name) == "slider-crank" ? text_slider : text;
    const Model m = LoadModelFromString(use, std::string(c.name) + ".yaml");
    if (std::string(c.error).empty()) {
      const Topology t = BuildTopology(m);
      EXPECT_EQ(t.grubler_mobility, c.grubler) << c.name;
      EXPECT_EQ(t.loop_mobility, c.grubler) << c.name;
    } else {
      try {
        Validate(m);
        FAIL() << c.name << " was accepted";
      } catch (const ModelError& e) {
        EXPECT_NE(e.message().find(c.error), std::string::npos) << c.name << ": " << e.what();
        EXPECT_NE(e.message().find("= " + std::to_string(c.grubler) + ")"), std::string::npos)
            << c.name << ": the message shows the Grübler count: " << e.what();
      }
    }
  }
}

// The solve order of the multi-loop models, derived by hand from their loops.
std::vector<std::vector<std::string>> Order(const std::string& model) {
  const Model m = LoadModel(std::string(MECHGEN_SOURCE_DIR) + "/models/" + model + ".yaml");
  const Kinematics k = DeriveKinematics(m, BuildTopology(m));
  std::vector<std::vector<std::string>> out;
  for (const Block& b : OrderBlocks(m, k)) {
    out.emplace_back();
    for (int c : b.cols) out.back().push_back(k.phi[c].name);
  }
  return out;
}

using Names = std::vector<std::vector<std::string>>;

TEST(SolveOrder, WattSixBarIsTwoDyadsInSeries) {
  // Loop 1 (O2 B C O4) fixes coupler and rocker from the crank; loop 2 (O4 E F O6) then
  // fixes link5 and output from the rocker.
  EXPECT_EQ(Order("watt_sixbar"), (Names{{"theta_coupler", "theta_rocker"}, {"theta_link5", "theta_output"}}));
}

TEST(SolveOrder, StephensonIIIIsAFourBarThenADyad) {
  EXPECT_EQ(Order("stephenson_sixbar"), (Names{{"theta_coupler", "theta_rocker"}, {"theta_link5", "theta_output"}}));
}

TEST(SolveOrder, StronglyCoupledStephensonIsOneBlock) {
  // T2 hangs on the crank and on T1 through a and b: both loops hold T1 and T2, so
  // neither can be solved before the other.
  EXPECT_EQ(Order("stephenson_coupled"), (Names{{"theta_T2", "theta_a", "theta_b", "theta_T1"}}));
}

TEST(SolveOrder, QuickReturnIsSlotThenLinkThenRam) {
  // Loop 1 gives the rocker and the block's slide from the crank; the ram line's
  // normal projection of loop 2 gives the link alone; its other projection the ram.
  EXPECT_EQ(Order("quick_return"), (Names{{"theta_rocker", "s_slot"}, {"theta_link"}, {"s_stroke"}}));
}

}  // namespace
}  // namespace mechgen
