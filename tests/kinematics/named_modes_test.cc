// Named assembly modes (issue 13): tests/kinematics/models/fourbar_named_modes.yaml is
// models/fourbar.yaml with `assembly_modes: {open: {}, crossed: {...}}`. Its generated
// kNamedModes must be the modes of the shipped fourbar (open) and fourbar_crossed, and
// solving with them must give those models' positions; ModesByName finds them by name only.
#include <gtest/gtest.h>

#include <cmath>

#include "fourbar.h"
#include "fourbar_crossed.h"
#include "fourbar_named_modes.h"

namespace {

using N = mech::fourbar_named_modes::Model;
using Open = mech::fourbar::Model;
using Crossed = mech::fourbar_crossed::Model;
constexpr double kPi = 3.14159265358979323846;

TEST(NamedModes, AreTheShippedAssembliesByName) {
  static_assert(N::kNumNamedModes == 2, "open and crossed");
  EXPECT_STREQ(N::kModeNames[0], "open");
  EXPECT_STREQ(N::kModeNames[1], "crossed");
  EXPECT_EQ(N::kNamedModes[0], Open::kDefaultModes);
  EXPECT_EQ(N::kNamedModes[1], Crossed::kDefaultModes);
  EXPECT_NE(N::kNamedModes[0], N::kNamedModes[1]);
  EXPECT_EQ(N::kDefaultModes, Open::kDefaultModes);  // `assembly` stays the default
  std::array<int, N::kNumBlocks> modes{};
  ASSERT_TRUE(N::ModesByName("crossed", &modes));
  EXPECT_EQ(modes, Crossed::kDefaultModes);
  ASSERT_TRUE(N::ModesByName("open", &modes));
  EXPECT_EQ(modes, Open::kDefaultModes);
  for (const char* wrong : {"", "cross", "crossed_", "Open", "opens"}) {
    std::array<int, N::kNumBlocks> untouched{};
    untouched.fill(7);
    EXPECT_FALSE(N::ModesByName(wrong, &untouched)) << wrong;
    for (int m : untouched) EXPECT_EQ(m, 7) << wrong;
  }
}

TEST(NamedModes, SolveOnEachNamedModeGivesThatAssembly) {
  const N::ParamsT<double> p;
  for (int k = 0; k < 360; ++k) {
    const Eigen::Matrix<double, 1, 1> q(2 * kPi * k / 360);
    Eigen::Vector2d open(N::kAssemblyPhi[0], N::kAssemblyPhi[1]), crossed = open;
    Eigen::Vector2d open_ref = open, crossed_ref = open;
    ASSERT_EQ(N::Solve(p, q, &open, N::kNamedModes[0]).status, mech::fourbar_named_modes::SolveStatus::kConverged);
    ASSERT_EQ(N::Solve(p, q, &crossed, N::kNamedModes[1]).status, mech::fourbar_named_modes::SolveStatus::kConverged);
    ASSERT_EQ(Open::Solve(Open::ParamsT<double>(), q, &open_ref).status, mech::fourbar::SolveStatus::kConverged);
    ASSERT_EQ(Crossed::Solve(Crossed::ParamsT<double>(), q, &crossed_ref).status,
              mech::fourbar_crossed::SolveStatus::kConverged);
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(std::remainder(open(i) - open_ref(i), 2 * kPi), 0, 1e-12) << q(0);
      EXPECT_NEAR(std::remainder(crossed(i) - crossed_ref(i), 2 * kPi), 0, 1e-12) << q(0);
    }
    // The two assemblies differ (C above and below the line BD).
    EXPECT_GT(std::abs(std::remainder(open(1) - crossed(1), 2 * kPi)), 1e-3) << q(0);
  }
}

}  // namespace
