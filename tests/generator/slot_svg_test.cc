// Issue 24: mechgen/io/svg.h draws the slot joint (generator/joints/slot.cc): the groove in
// the slotted link and the pin in it, from the generated drawing description
// (generator/codegen/drawing.cc: the slot's point and the pin, the line's angle).
//
// Two test models of tests/kinematics/models/ swept over a crank turn, their SVG read back:
//  - slot_whitworth: crank a = 1 about A = (0, 0), the rocker about D = (0, d), d = 0.4, its
//    slot the line from D through H = (1, 1) of the rocker (45 deg in its frame);
//  - slot_oscillating_block: the same with D = (d, 0), d = 2.5, the slot along the rocker
//    (angle 0).
// Oracle, by hand: the pin B is at distance |B - D| from D, which over a turn of the crank
// ranges over [|a - d|, a + d] (reached at the sampled crank angles 90 and 270 deg, resp. 180
// and 0 deg); so the groove, drawn in the rocker's own frame, runs along the line's direction
// from (a - d) to (a + d) away from D, and the pin is the crank's point (a, 0) in its frame.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "mechgen/io/svg.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "slot_oscillating_block.h"
#include "slot_whitworth.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

// The number in attribute `name` of the first element at or after `from` that has it.
double Attribute(const std::string& svg, size_t from, const std::string& name) {
  const size_t at = svg.find(" " + name + "=\"", from);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(svg.c_str() + at + name.size() + 3, nullptr);
}

// The part of the mechanism group (the first configuration, drawn in each link's frame)
// that belongs to link `link`: its group's elements.
std::string LinkGroups(const std::string& svg, const std::string& link) {
  const size_t mechanism = svg.find("<g id=\"mechanism\">");
  std::string out;
  for (size_t at = svg.find("<g data-link=\"" + link + "\"", mechanism); at != std::string::npos;
       at = svg.find("<g data-link=\"" + link + "\"", at + 1))
    out += svg.substr(at, svg.find("</g>", at) - at);
  return out;
}

template <class M>
std::string SweptSvg(std::vector<mechgen::SweepRecord<M>>* records, double* scale) {
  using VecQ = typename mechgen::ModelTypes<M>::VecQ;
  mechgen::position::PositionSolver<M> solver;
  EXPECT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  const double q0 = solver.state().q(0);
  EXPECT_EQ(mechgen::Sweep(&solver, VecQ::Constant(q0), VecQ::Constant(q0 + 2 * kPi), 360, VecQ::Constant(1),
                           VecQ::Constant(0), records),
            0);
  std::ostringstream svg;
  mechgen::WriteSvg<M>(solver.params(), *records, mechgen::SvgOptions(), svg);
  const std::string text = svg.str();
  *scale = Attribute(text, 0, "data-scale");
  return text;
}

// The groove of the rocker and the pin of the crank, against the hand oracle above. `u` is
// the slot's direction in the rocker's frame (D at its origin).
void ExpectSlotDrawn(const std::string& svg, double scale, double a, double d, double ux, double uy) {
  ASSERT_TRUE(std::isfinite(scale) && scale > 0) << svg.substr(0, 400);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  const double px = 0.006 / scale;  // the drawing's coordinates have 2 decimals (pixels)

  const std::string rocker = LinkGroups(svg, "rocker");
  const size_t slot = rocker.find("<line class=\"slot\"");
  ASSERT_NE(slot, std::string::npos) << "no slot drawn on the rocker:\n" << rocker;
  // Pixels in the link's frame, y down: model x = x_px / scale, y = -y_px / scale.
  const double x1 = Attribute(rocker, slot, "x1") / scale, y1 = -Attribute(rocker, slot, "y1") / scale;
  const double x2 = Attribute(rocker, slot, "x2") / scale, y2 = -Attribute(rocker, slot, "y2") / scale;
  const double near = std::abs(a - d), far = a + d;
  EXPECT_NEAR(x1, near * ux, px);
  EXPECT_NEAR(y1, near * uy, px);
  EXPECT_NEAR(x2, far * ux, px);
  EXPECT_NEAR(y2, far * uy, px);
  // Wide enough for the pin (radius 4 px) with a white inside.
  EXPECT_GT(Attribute(rocker, slot, "stroke-width"), 8);
  EXPECT_NE(rocker.find("stroke=\"white\"", slot), std::string::npos);

  const std::string crank = LinkGroups(svg, "crank");
  const size_t pin = crank.find("<circle class=\"slot-pin\"");
  ASSERT_NE(pin, std::string::npos) << "no pin drawn on the crank:\n" << crank;
  EXPECT_NEAR(Attribute(crank, pin, "cx") / scale, a, px);
  EXPECT_NEAR(-Attribute(crank, pin, "cy") / scale, 0, px);
  // The pin is drawn once (on the pin's link), the slot once per drawing of the rocker.
  EXPECT_EQ(crank.find("class=\"slot\""), std::string::npos);
  EXPECT_EQ(rocker.find("slot-pin"), std::string::npos);
}

TEST(SlotSvg, WhitworthSlotThroughTwoPoints) {
  using M = mech::slot_whitworth::Model;
  static_assert(M::kDrawJointKind[2] == mechgen::internal::kDrawSlot, "the joint `slot` is drawn as a slot");
  std::vector<mechgen::SweepRecord<M>> records;
  double scale = 0;
  const std::string svg = SweptSvg<M>(&records, &scale);
  for (const auto& r : records) ASSERT_TRUE(r.state.valid);
  ExpectSlotDrawn(svg, scale, 1.0, 0.4, std::sqrt(0.5), std::sqrt(0.5));
}

TEST(SlotSvg, OscillatingBlockSlotAtAnAngle) {
  using M = mech::slot_oscillating_block::Model;
  static_assert(M::kDrawJointKind[2] == mechgen::internal::kDrawSlot, "the joint `slot` is drawn as a slot");
  std::vector<mechgen::SweepRecord<M>> records;
  double scale = 0;
  const std::string svg = SweptSvg<M>(&records, &scale);
  for (const auto& r : records) ASSERT_TRUE(r.state.valid);
  ExpectSlotDrawn(svg, scale, 1.0, 2.5, 1.0, 0.0);
}

}  // namespace
