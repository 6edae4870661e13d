// Issue 12, degenerate geometry and reach, checked by the generator at the parameters'
// defaults (the models are the shipped ones with one value changed):
//   - every closed-form block must close over each input's declared range: the error is
//     at the range (file:line:column) and names the input value where the loop stops
//     closing, compared here with the closed form of that limit (an oracle by hand);
//   - a range within reach passes, also when it ends just short of the limit;
//   - gear pairs: coincident axes on the carrier, and an internal pair whose ring is not
//     larger than its gear, are errors at the pair or the ring's radius;
//   - cams: an oscillating follower pivoted on the cam's axis, and a roller or knife-edge at
//     the follower's own pivot, are errors at the cam's follower.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "model/model.h"
#include "symbolic/table.h"

namespace {

std::string Read(const std::string& name) {
  std::ifstream in(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Runs the generator's front end and symbolic stage; returns "" or the error as
// "line:column: message".
std::string Generate(const std::string& text) {
  try {
    const mechgen::Model m = mechgen::LoadModelFromString(text, "test.yaml");
    const mechgen::Analysis a = mechgen::Validate(m);
    const mechgen::Kinematics k = mechgen::DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    const mechgen::SymbolicTable t(m, k);
    return "";
  } catch (const mechgen::ModelError& e) {
    return std::to_string(e.mark().line) + ":" + std::to_string(e.mark().column) + ": " + e.message();
  }
}

// The line and column of `needle` in `text` (1-based), as the error should give them.
std::string Where(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  const size_t line_start = text.rfind('\n', at) + 1;
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + at, '\n')) + 1;
  return std::to_string(line) + ":" + std::to_string(at - line_start + 1) + ": ";
}

double StopsAt(const std::string& error) {
  std::smatch m;
  if (!std::regex_search(error, m, std::regex("stops closing at [a-z_]+ = ([-0-9.e+]+) deg"))) return NAN;
  return std::stod(m[1]);
}

TEST(ReachCheck, SliderCrankWhoseRodCannotReachTheLine) {
  // Offset e = 2.5, crank 1, rod 3.2: the rod reaches the slide's line while
  // e - a sin(theta) <= b, i.e. down to sin(theta) = (e - b) / a = -0.7: theta = 180 deg +
  // asin(0.7) = 224.427 deg from the assembly at 90 deg.
  const std::string text =
      Replace(Read("slider_crank.yaml"), "e: {value: 0.4", "e: {value: 2.5");
  const std::string error = Generate(text);
  ASSERT_NE(error, "");
  EXPECT_EQ(error.rfind(Where(text, "[0, 360*deg]"), 0), 0u) << error;
  EXPECT_NE(error.find("input 'theta_crank' is driven over [0 deg, 360 deg]"), std::string::npos) << error;
  EXPECT_NE(error.find("block 0"), std::string::npos) << error;
  EXPECT_NEAR(StopsAt(error), 180 + std::asin(0.7) * 180 / M_PI, 1e-3) << error;
  // Within reach: a range that ends before the limit.
  EXPECT_EQ(Generate(Replace(text, "[0, 360*deg]", "[0, 224*deg]")), "");
  EXPECT_NE(Generate(Replace(text, "[0, 360*deg]", "[0, 225*deg]")), "");
}

TEST(ReachCheck, SixBarWhoseSecondLoopCannotReach) {
  // Stephenson six-bar with its output pivot moved to x = 5.5: the four-bar (block 0) turns
  // fully, the second dyad (block 1) cannot follow it all the way round.
  const std::string text = Replace(Read("stephenson_sixbar.yaml"), "x6: {value: 3.5", "x6: {value: 5.5");
  const std::string error = Generate(text);
  ASSERT_NE(error, "");
  EXPECT_NE(error.find("block 1"), std::string::npos) << error;
  EXPECT_NE(error.find("the two circles do not meet"), std::string::npos) << error;
  EXPECT_EQ(error.rfind(Where(text, "[0, 360*deg]"), 0), 0u) << error;
  // In the model's terms: the links of that block and the joint they close.
  EXPECT_NE(error.find("beyond it: link '"), std::string::npos) << error;
  EXPECT_NE(error.find(" cannot close joint"), std::string::npos) << error;
}

TEST(ReachCheck, ShippedModelsPass) {
  for (const char* name : {"fourbar.yaml", "slider_crank.yaml", "inverted_slider_crank.yaml", "quick_return.yaml",
                           "stephenson_sixbar.yaml", "watt_sixbar.yaml", "fivebar.yaml", "geared_fivebar.yaml",
                           "planetary.yaml"})
    EXPECT_EQ(Generate(Read(name)), "") << name;
}

// The change points of block 0 along input 0 as (value in deg, kind), from the symbolic
// stage; error set when the model does not generate.
std::vector<std::pair<double, mechgen::ChangePoint::Kind>> ChangePoints(const std::string& text, std::string* error,
                                                                         std::vector<std::string>* notes = nullptr) {
  std::vector<std::pair<double, mechgen::ChangePoint::Kind>> out;
  try {
    const mechgen::Model m = mechgen::LoadModelFromString(text, "test.yaml");
    const mechgen::Analysis a = mechgen::Validate(m);
    const mechgen::Kinematics k = mechgen::DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    const mechgen::SymbolicTable t(m, k);
    for (const mechgen::ChangePoint& c : t.blocks.at(0).change_points)
      if (c.input == 0) out.emplace_back(c.value * 180 / M_PI, c.kind);
    if (notes) *notes = mechgen::ChangePointNotes(k, t.blocks);
  } catch (const mechgen::ModelError& e) {
    *error = e.message();
  }
  return out;
}

std::string ReadTestModel(const std::string& name) {
  std::ifstream in(std::string(MECHGEN_SOURCE_DIR) + "/tests/kinematics/models/" + name);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ChangePoints, ParallelogramTurnsFullyThroughItsChangePoints) {
  // Crank a = rocker = 1, coupler = ground = 3: the two circles of the dyad (about B,
  // radius 3, and about D, radius 1) touch where B lies on the line AD, i.e. at
  // theta_crank = 0 (internally, |BD| = 3 - 1) and 180 deg (externally, |BD| = 3 + 1), and
  // at 360 deg (= 0). Nowhere else: |BD|^2 = 10 - 6 cos(theta) is strictly between 4 and 16.
  const std::string text = ReadTestModel("parallelogram.yaml");
  std::string error;
  std::vector<std::string> notes;
  const auto points = ChangePoints(text, &error, &notes);
  ASSERT_EQ(error, "");
  ASSERT_EQ(points.size(), 3u);
  const double expected[] = {0, 180, 360};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(points[i].first, expected[i], 1e-6) << i;
    EXPECT_EQ(points[i].second, mechgen::ChangePoint::Kind::kModesMeet) << i;
  }
  // The printed note says where and which mode the model's solve keeps past them.
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("input 'theta_crank' passes change points of block 0"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("0 deg, 180 deg, 360 deg"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("keeps mode +1"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("goes on in mode -1"), std::string::npos) << notes[0];
  // A range that stops short of them has none; one that reaches 180 deg from below has one.
  EXPECT_TRUE(ChangePoints(Replace(text, "[0, 360*deg]", "[10*deg, 170*deg]"), &error).empty());
  EXPECT_EQ(error, "");
  // Between samples it is refined; a tangency is a double root (the measure ~ (t - 180)^2
  // computed with an absolute error ~ epsilon), found to ~ sqrt(epsilon) rad = 1e-6 deg.
  const auto one = ChangePoints(Replace(text, "[0, 360*deg]", "[10*deg, 200.3*deg]"), &error);
  EXPECT_EQ(error, "");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0].first, 180, 1e-5);
  // (A loop that stops closing, without closing again beyond, is still refused: the
  // ReachCheck tests above.)
}

TEST(ChangePoints, RhombusWhoseDyadCentresCoincideIsAccepted) {
  // All four links 1 long: at theta_crank = 0 (and 360 deg) the crank's tip B lies on the
  // rocker's pivot D, the dyad's two circle centres coincide (it can turn about them), and
  // the loop closes again just beyond: a change point, not the end of the reach (this was
  // refused: "stops closing at theta_crank = 360 deg ... the two circle centres coincide").
  // At 180 deg |BD| = 2 = 1 + 1: the circles touch.
  const std::string text = Replace(ReadTestModel("parallelogram.yaml"), "d: {value: 3.0", "d: {value: 1.0");
  EXPECT_EQ(Generate(text), "");
  std::string error;
  const auto points = ChangePoints(text, &error);
  ASSERT_EQ(error, "");
  ASSERT_EQ(points.size(), 3u);
  EXPECT_NEAR(points[0].first, 0, 1e-6);
  EXPECT_EQ(points[0].second, mechgen::ChangePoint::Kind::kCentresCoincide);
  EXPECT_NEAR(points[1].first, 180, 1e-6);
  EXPECT_NEAR(points[2].first, 360, 1e-6);
  EXPECT_EQ(points[2].second, mechgen::ChangePoint::Kind::kCentresCoincide);
}

TEST(ChangePoints, ARangeEndingAtTheLimitOfItsReachHasNone) {
  // The offset slider-crank of ReachCheck.SliderCrankWhoseRodCannotReachTheLine driven up to
  // its limit 180 deg + asin(0.7) exactly: the measure is 0 at the end, but the loop does not
  // close beyond it (a dead point of the rod, not a change point).
  const std::string text = Replace(Replace(Read("slider_crank.yaml"), "e: {value: 0.4", "e: {value: 2.5"),
                                   "[0, 360*deg]", "[0, 180*deg + asin(0.7)]");
  std::string error;
  EXPECT_TRUE(ChangePoints(text, &error).empty());
  EXPECT_EQ(error, "");
}

TEST(ChangePoints, ShippedModelsHaveNone) {
  // None of the shipped linkages passes a change point within its range (the generator
  // prints a note for every one it finds).
  for (const char* name : {"fourbar.yaml", "slider_crank.yaml", "inverted_slider_crank.yaml", "quick_return.yaml",
                           "stephenson_sixbar.yaml", "watt_sixbar.yaml", "fivebar.yaml", "fourbar_crossed.yaml"}) {
    std::string error;
    EXPECT_TRUE(ChangePoints(Read(name), &error).empty()) << name;
    EXPECT_EQ(error, "") << name;
  }
}

TEST(GearCheck, CoincidentAxesOnTheCarrier) {
  // The geared five-bar's second crank pivoted at A, where the first one is.
  const std::string text =
      Replace(Read("geared_fivebar.yaml"), "E: [r1 + r2, 0]", "E: [0, 0]");
  const std::string error = Generate(text);
  EXPECT_NE(error.find("the axes of 'crank1' and 'crank2' coincide on 'ground'"), std::string::npos) << error;
  EXPECT_EQ(error.rfind(Where(text, "mesh:"), 0), 0u) << error;
}

TEST(GearCheck, InternalRingNotLargerThanItsGear) {
  const std::string text = Replace(Read("planetary.yaml"), "rr: {value: 2.0", "rr: {value: 0.4");
  const std::string error = Generate(text);
  EXPECT_NE(error.find("is internal, so 'ground' is the ring"), std::string::npos) << error;
  EXPECT_EQ(error.rfind(Where(text, "rr], carrier: arm, internal"), 0), 0u) << error;
}

TEST(CamCheck, OscillatingFollowerPivotedOnTheCamAxis) {
  const std::string text = Replace(Read("cam_flat.yaml"), "A: [d, 0]}}", "A: [0, 0]}}");
  const std::string error = Generate(text);
  EXPECT_NE(error.find("the follower's pivot (joint 'A') is the cam's axis (joint 'O')"), std::string::npos) << error;
  EXPECT_EQ(error.rfind(Where(text, "A\n      point"), 0), 0u) << error;
}

TEST(CamCheck, RollerOnTheFollowersPivot) {
  // The oscillating follower with a roller at its own pivot A: turning it moves nothing.
  const std::string roller = Replace(Read("cam_flat.yaml"), "face: 0", "roller: 0.1");
  const std::string error = Generate(roller);
  EXPECT_NE(error.find("the follower point follower.A is the follower's pivot (joint 'A')"), std::string::npos)
      << error;
  // At the arm's end F instead, that check passes (whatever else the variant meets).
  const std::string at_f = Generate(Replace(roller, "point: follower.A", "point: follower.F"));
  EXPECT_EQ(at_f.find("is the follower's pivot"), std::string::npos) << at_f;
}

}  // namespace
