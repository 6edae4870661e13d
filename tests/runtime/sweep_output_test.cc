// The sweep's transmission-angle columns (SweepRecord::mu, CSV mu_<joint>): along a full
// crank turn of the generated four-bars, mu at every row against the law of cosines in the
// triangle coupler–rocker–diagonal (delta^2 = a^2 + d^2 - 2 a d cos q, cos mu =
// (b^2 + c^2 - delta^2) / (2 b c)); the CSV carries the same numbers; a model without
// four-bar loops (the slider-crank) has no such column.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fourbar.h"
#include "fourbar_crossed.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/svg.h"
#include "mechgen/io/table.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"
#include "slider_crank.h"

namespace mechgen::position {
namespace {

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  return cells;
}

template <class M>
void CheckMuColumns() {
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  using VecQ = typename ModelTypes<M>::VecQ;
  std::vector<SweepRecord<M>> records;
  ASSERT_EQ(Sweep(&solver, VecQ::Constant(0.0), VecQ::Constant(2 * M_PI), 360, VecQ::Constant(1.0),
                  VecQ::Zero(), &records),
            0);
  static_assert(SweepRecord<M>::kNumMu == 1);
  const auto& p = solver.params();
  std::ostringstream csv;
  WriteCsv(records, csv);
  std::istringstream lines(csv.str());
  std::string line;
  std::getline(lines, line);
  const std::vector<std::string> header = Split(line);
  ASSERT_EQ(header.back(), "mu_C");
  for (const SweepRecord<M>& r : records) {
    const double q = r.state.q(0);
    const double delta2 = p.a * p.a + p.d * p.d - 2 * p.a * p.d * std::cos(q);
    const double cos_mu = (p.b * p.b + p.c * p.c - delta2) / (2 * p.b * p.c);
    EXPECT_NEAR(std::cos(r.mu(0)), cos_mu, 1e-12) << "q = " << q;
    ASSERT_TRUE(std::getline(lines, line));
    const std::vector<std::string> cells = Split(line);
    ASSERT_EQ(cells.size(), header.size());
    EXPECT_NEAR(std::stod(cells.back()), r.mu(0), 1e-11) << line;
  }
}

TEST(SweepTransmissionAngle, FourBarOpen) { CheckMuColumns<mech::fourbar::Model>(); }
TEST(SweepTransmissionAngle, FourBarCrossed) { CheckMuColumns<mech::fourbar_crossed::Model>(); }

TEST(SweepTransmissionAngle, SliderCrankHasNone) {
  using M = mech::slider_crank::Model;
  static_assert(SweepRecord<M>::kNumMu == 0);
  for (const std::string& column : CsvColumns<M>()) EXPECT_NE(column.rfind("mu_", 0), 0u) << column;
}

}  // namespace
}  // namespace mechgen::position
