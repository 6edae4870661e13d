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
}

TEST(ReachCheck, ShippedModelsPass) {
  for (const char* name : {"fourbar.yaml", "slider_crank.yaml", "inverted_slider_crank.yaml", "quick_return.yaml",
                           "stephenson_sixbar.yaml", "watt_sixbar.yaml", "fivebar.yaml", "geared_fivebar.yaml",
                           "planetary.yaml"})
    EXPECT_EQ(Generate(Read(name)), "") << name;
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
