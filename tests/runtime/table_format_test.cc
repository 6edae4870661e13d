// The printed table's rows and the number formatting (issue 13): --table N shows N rows
// evenly spaced from the first to the last, both included; no number is printed as -0.
// Oracles: hand-counted indices, the exact real spacing r (n - 1) / (N - 1), and the text
// of plain printf.
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "handwritten_fourbar.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/format.h"
#include "mechgen/io/table.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"

namespace {

using mechgen::TableRowIndices;
using mechgen::internal::FormatNumber;
using Indices = std::vector<size_t>;

TEST(TableRowIndices, HandCountedCases) {
  // A 360-step crank turn (361 rows): 9 rows every 45 deg, the last (360 deg) included.
  EXPECT_EQ(TableRowIndices(361, 9), (Indices{0, 45, 90, 135, 180, 225, 270, 315, 360}));
  // 8 rows: 360 / 7 = 51.43 apart, rounded to the nearest row.
  EXPECT_EQ(TableRowIndices(361, 8), (Indices{0, 51, 103, 154, 206, 257, 309, 360}));
  // 101 rows, 8 shown: 100 / 7 = 14.29 apart (the former picking gave 0, 12, 25, 37, ...).
  EXPECT_EQ(TableRowIndices(101, 8), (Indices{0, 14, 29, 43, 57, 71, 86, 100}));
  EXPECT_EQ(TableRowIndices(5, 5), (Indices{0, 1, 2, 3, 4}));
  EXPECT_EQ(TableRowIndices(5, 3), (Indices{0, 2, 4}));
  EXPECT_EQ(TableRowIndices(5, 2), (Indices{0, 4}));
  EXPECT_EQ(TableRowIndices(5, 1), (Indices{0}));
  EXPECT_EQ(TableRowIndices(5, 100), (Indices{0, 1, 2, 3, 4}));  // all rows, once each
  EXPECT_EQ(TableRowIndices(2, 9), (Indices{0, 1}));
  EXPECT_EQ(TableRowIndices(1, 9), (Indices{0}));
  EXPECT_TRUE(TableRowIndices(0, 9).empty());
  EXPECT_TRUE(TableRowIndices(10, 0).empty());
  EXPECT_TRUE(TableRowIndices(10, -3).empty());
  // The largest sweep (10^7 steps) and sizes where (n - 1) r would overflow 64 bits.
  EXPECT_EQ(TableRowIndices(10000001, 3), (Indices{0, 5000000, 10000000}));
  const size_t big = (size_t(1) << 62) + 1;
  EXPECT_EQ(TableRowIndices(big, 3), (Indices{0, size_t(1) << 61, size_t(1) << 62}));
}

TEST(TableRowIndices, EvenlySpacedWithFirstAndLast) {
  for (size_t n = 1; n <= 130; ++n) {
    for (int rows = 1; rows <= 140; ++rows) {
      const Indices indices = TableRowIndices(n, rows);
      const size_t count = std::min<size_t>(static_cast<size_t>(rows), n);
      ASSERT_EQ(indices.size(), count) << n << " " << rows;
      EXPECT_EQ(indices.front(), 0u);
      if (count > 1) {
        EXPECT_EQ(indices.back(), n - 1) << n << " " << rows;
      }
      for (size_t r = 0; r < count; ++r) {
        if (r > 0) {
          EXPECT_LT(indices[r - 1], indices[r]) << n << " " << rows;
        }
        if (count > 1) {
          const long double exact = (long double)(n - 1) * r / (count - 1);
          EXPECT_LE(std::fabs((long double)indices[r] - exact), 0.5L) << n << " " << rows << " " << r;
        }
      }
    }
  }
}

TEST(FormatNumber, NeverNegativeZero) {
  EXPECT_EQ(FormatNumber(-0.0), "0");
  EXPECT_EQ(FormatNumber(0.0), "0");
  EXPECT_EQ(FormatNumber(-0.0, "%.4f"), "0.0000");
  EXPECT_EQ(FormatNumber(-1e-9, "%.4f"), "0.0000");  // printf: "-0.0000"
  EXPECT_EQ(FormatNumber(-4e-5, "%.4f"), "0.0000");
  EXPECT_EQ(FormatNumber(-0.0, "%.3e"), "0.000e+00");
  EXPECT_EQ(FormatNumber(-0.0, "%g"), "0");
  EXPECT_EQ(FormatNumber(-1e-9, "%.2f"), "0.00");
  // Everything else as printf prints it.
  for (const double x : {-1.5, -6e-5, -1e-300, -4.9e-324, -0.5, -1e9, 2.0, 1e-300}) {
    for (const char* format : {"%.12g", "%.4f", "%.3g", "%.6g", "%.2f", "%g"}) {
      char expected[64];
      std::snprintf(expected, sizeof(expected), format, x);
      const std::string text = expected;
      if (text.find_first_of("123456789") == std::string::npos) continue;  // a rounded zero
      EXPECT_EQ(FormatNumber(x, format), text) << x << " " << format;
    }
  }
  EXPECT_EQ(FormatNumber(-1e-9, "%.12g"), "-1e-09");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::quiet_NaN(), "%.4f"), "nan");
}

// The table and the CSV of a record holding negative zeros and tiny negatives.
TEST(FormatNumber, TableAndCsvPrintNoNegativeZero) {
  using M = mech::handwritten_fourbar::Model;
  mechgen::position::PositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<mechgen::SweepRecord<M>> records;
  ASSERT_EQ(mechgen::Sweep(&solver, mechgen::ModelTypes<M>::VecQ::Constant(0.0), mechgen::ModelTypes<M>::VecQ::Constant(1.0), 2,
                           mechgen::ModelTypes<M>::VecQ::Constant(0.0), mechgen::ModelTypes<M>::VecQ::Constant(0.0), &records),
            0);
  records[0].q(0) = -0.0;
  records[0].state.phi(0) = -1e-9;  // -5.7e-8 deg: "-0.0000" in the table before
  records[0].state.K(0, 0) = -0.0;
  std::ostringstream table, csv;
  mechgen::PrintTable(records, 3, table);
  mechgen::WriteCsv(records, csv);
  EXPECT_EQ(table.str().find("-0.0000"), std::string::npos) << table.str();
  EXPECT_NE(table.str().find(" 0.0000 "), std::string::npos) << table.str();
  // qd = 0 everywhere: velocities and accelerations are 0 or -0 (x * -0) in every row.
  const std::string text = csv.str();
  EXPECT_EQ(text.find(",-0,"), std::string::npos) << text;
  EXPECT_EQ(text.find("\n-0,"), std::string::npos) << text;
  EXPECT_NE(text.find("\n0,"), std::string::npos) << text;
}

}  // namespace
