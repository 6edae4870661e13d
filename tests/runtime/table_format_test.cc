// The printed table's rows and the number formatting (issue 13): --table N shows N rows
// evenly spaced from the first to the last, both included; no number is printed as -0.
// Oracles: hand-counted indices, the exact real spacing r (n - 1) / (N - 1), and the text
// of plain printf. And (issue 24) every number the one CSV writer (io/csv.h) writes reads
// back with strtod to the same double, bit for bit (oracle: the bits of the double written).
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"
#include "mechgen/table/columns.h"

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

// The one conversion of angles to and from degrees (io/format.h): exact where pi's multiples
// are, and the nearest double to x 180/pi more often than the former x * (180/pi), against
// that product in extended precision (where long double has more digits than double).
TEST(Degrees, ExactAtPiAndNearerThanMultiplying) {
  using mechgen::internal::FromDegrees;
  using mechgen::internal::kDegToRad;
  using mechgen::internal::ToDegrees;
  EXPECT_EQ(kDegToRad, M_PI / 180);
  EXPECT_EQ(ToDegrees(M_PI), 180.0);
  EXPECT_EQ(ToDegrees(-M_PI / 2), -90.0);
  EXPECT_EQ(ToDegrees(4 * M_PI), 720.0);
  EXPECT_EQ(FromDegrees(180), M_PI);
  EXPECT_EQ(FromDegrees(-90), -M_PI / 2);
  EXPECT_EQ(ToDegrees(0.0), 0.0);
  EXPECT_EQ(FromDegrees(0.0), 0.0);
  EXPECT_TRUE(std::isnan(ToDegrees(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_TRUE(std::isnan(FromDegrees(std::numeric_limits<double>::quiet_NaN())));
  if (std::numeric_limits<long double>::digits <= std::numeric_limits<double>::digits + 8) return;
  const long double pi = 3.141592653589793238462643383279502884L;
  int nearest = 0, nearest_multiplying = 0;
  const int n = 200000;
  for (int i = 1; i <= n; ++i) {
    const double x = i * 1e-4;  // 0.0001 .. 20 rad
    const double exact = static_cast<double>(static_cast<long double>(x) * 180 / pi);
    nearest += ToDegrees(x) == exact;
    nearest_multiplying += x * 57.29577951308232 == exact;
    EXPECT_LE(std::abs(ToDegrees(x) - exact), 2 * std::numeric_limits<double>::epsilon() * exact) << x;
  }
  EXPECT_GT(nearest, nearest_multiplying);
  EXPECT_GT(nearest, n * 85 / 100);
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

// ---- Round trip (issue 24) ---------------------------------------------------------------

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// Significant digits of a number's text: the digits of its mantissa without leading zeros.
int SignificantDigits(const std::string& text) {
  int digits = 0;
  bool leading = true;
  for (char c : text) {
    if (c == 'e' || c == 'E') break;
    if (c < '0' || c > '9') continue;
    if (c == '0' && leading) continue;
    leading = false;
    ++digits;
  }
  return digits;
}

// The values that printf with 10 or 12 digits does not keep, the extremes of double, the
// subnormals, and 20000 doubles of deterministic pseudo-random bits (every exponent).
std::vector<double> HardValues() {
  constexpr double kDenorm = std::numeric_limits<double>::denorm_min();
  std::vector<double> values = {
      0.1, 0.2, 0.3, 0.1 + 0.2, 1.0 / 3, 2.0 / 3, -1.0 / 7, 5e-12, -5e-12, 1e300, -1e300,
      1e-300, M_PI, -M_E, 1e-5, 1e-4, 1e5, 1e16, 1e17, 1e22, 1e23, 123456.789, 9007199254740992.0,
      9007199254740994.0, 4503599627370497.5, DBL_MAX, -DBL_MAX, DBL_MIN, -DBL_MIN, kDenorm,
      -kDenorm, 3 * kDenorm, DBL_MIN - kDenorm /* the largest subnormal */, DBL_EPSILON,
      std::nextafter(1.0, 2.0), std::nextafter(1.0, 0.0), 0.49999999999999994,
      2.2250738585072011e-308, 1.7976931348623157e308, 5e-324, 6.02214076e23};
  uint64_t state = 0x9E3779B97F4A7C15ull;
  while (values.size() < 20000) {
    // splitmix64
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    double x;
    std::memcpy(&x, &z, sizeof(x));
    if (std::isfinite(x)) values.push_back(x);
  }
  return values;
}

TEST(FormatRoundTrip, ReadsBackBitForBitInAtMost17Digits) {
  int lost_by_12_digits = 0;
  for (double x : HardValues()) {
    const std::string text = mechgen::internal::FormatRoundTrip(x);
    char* end = nullptr;
    const double y = std::strtod(text.c_str(), &end);
    ASSERT_EQ(*end, '\0') << text;
    EXPECT_TRUE(SameBits(x, y)) << text << " for " << FormatNumber(x, "%.17g");
    EXPECT_LE(SignificantDigits(text), 17) << text;
    EXPECT_EQ(text.find(','), std::string::npos) << text;  // a CSV cell, whatever the locale
    lost_by_12_digits += std::strtod(FormatNumber(x, "%.12g").c_str(), nullptr) != x;
  }
  // What the former "%.12g" lost: nearly every value (the test would be idle otherwise).
  EXPECT_GT(lost_by_12_digits, 19000);
}

TEST(FormatRoundTrip, ShortTextForShortValuesAndSpecials) {
  using mechgen::internal::FormatRoundTrip;
  EXPECT_EQ(FormatRoundTrip(0.1), "0.1");
  EXPECT_EQ(FormatRoundTrip(0.5), "0.5");
  EXPECT_EQ(FormatRoundTrip(-2.0), "-2");
  EXPECT_EQ(FormatRoundTrip(5e-12), "5e-12");
  EXPECT_EQ(FormatRoundTrip(1e300), "1e+300");
  EXPECT_EQ(FormatRoundTrip(1.0 / 3), "0.3333333333333333");
  EXPECT_EQ(FormatRoundTrip(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(FormatRoundTrip(std::numeric_limits<double>::denorm_min()), "5e-324");
  EXPECT_EQ(FormatRoundTrip(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatRoundTrip(-std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatRoundTrip(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatRoundTrip(-std::numeric_limits<double>::infinity()), "-inf");
  // The outputs never print "-0" (issue 13): negative zero is written "0", reads back as +0
  // (equal in value; the one value whose sign bit is not kept).
  EXPECT_EQ(FormatRoundTrip(-0.0), "0");
  EXPECT_EQ(FormatRoundTrip(0.0), "0");
}

// The CSV writer over a column table of the hard values: every numeric cell reads back bit
// for bit; a NaN is the column's missing cell; text cells as given.
struct HardRow {
  double x = 0;
  int index = 0;
};

TEST(CsvWriter, EveryNumberReadsBackBitForBit) {
  mechgen::table::Columns<HardRow> columns;
  mechgen::table::Builder<HardRow> add(&columns);
  add.Number("x", "1", "the value", [](const HardRow& r) { return r.x; });
  add.Number("minus_x", "1", "its negative", [](const HardRow& r) { return -r.x; });
  add.Number("withheld", "1", "NaN: an empty cell", [](const HardRow&) {
       return std::numeric_limits<double>::quiet_NaN();
     }).missing = "";
  add.Text("index", "row index", [](const HardRow& r) { return std::to_string(r.index); });
  std::vector<HardRow> rows;
  for (double x : HardValues()) rows.push_back({x, static_cast<int>(rows.size())});
  rows.push_back({-0.0, static_cast<int>(rows.size())});
  std::ostringstream out;
  mechgen::WriteCsv(columns, rows, out);
  std::istringstream in(out.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "x,minus_x,withheld,index");
  size_t n = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(n, rows.size());
    const HardRow& r = rows[n];
    const size_t a = line.find(','), b = line.find(',', a + 1), c = line.find(',', b + 1);
    ASSERT_NE(c, std::string::npos) << line;
    const double x = std::strtod(line.substr(0, a).c_str(), nullptr);
    const double minus_x = std::strtod(line.substr(a + 1, b - a - 1).c_str(), nullptr);
    if (r.x == 0) {  // -0.0 and 0.0: "0"
      EXPECT_EQ(line.substr(0, b), "0,0") << line;
    } else {
      EXPECT_TRUE(SameBits(x, r.x)) << line;
      EXPECT_TRUE(SameBits(minus_x, -r.x)) << line;
    }
    EXPECT_EQ(line.substr(b + 1, c - b - 1), "") << line;
    EXPECT_EQ(line.substr(c + 1), std::to_string(r.index)) << line;
    ++n;
  }
  EXPECT_EQ(n, rows.size());
}

// With CsvOptions::describe, '#' lines before the header state each column's unit and
// meaning; the header and the rows are those without.
TEST(CsvWriter, DescribedHeaderStatesUnitsAndMeanings) {
  mechgen::table::Columns<HardRow> columns;
  mechgen::table::Builder<HardRow> add(&columns);
  add.Number("T", "N m", "torque on the crank, CCW +", [](const HardRow& r) { return r.x; });
  add.Text("status", "how the step went", [](const HardRow&) { return std::string("ok"); });
  const std::vector<HardRow> rows = {{0.25, 0}};
  std::ostringstream plain, described;
  mechgen::WriteCsv(columns, rows, plain);
  mechgen::WriteCsv(columns, rows, described,
                    mechgen::Described(mechgen::CsvAbout("press_statics", "press", "statics sweep",
                                                         "torques CCW +")));
  EXPECT_EQ(plain.str(), "T,status\n0.25,ok\n");
  EXPECT_EQ(described.str(),
            "# press_statics, model press: statics sweep. Signs: torques CCW +\n"
            "# T [N m]: torque on the crank, CCW +\n# status [text]: how the step went\n" +
                plain.str());
  // Without `about` only the column lines; a line break in a description stays on its line.
  columns[0].description = "torque\non the crank";
  mechgen::CsvOptions options;
  options.describe = true;
  std::ostringstream bare;
  mechgen::WriteCsv(columns, rows, bare, options);
  EXPECT_EQ(bare.str(),
            "# T [N m]: torque on the crank\n# status [text]: how the step went\n" + plain.str());
}

// A sweep's CSV (sweep/columns.h through io/csv.h) as the sweep tool writes it, with its
// comment lines: the first names the tool, the model and the signs, then one unit line per
// column in the header's order; every numeric cell after them is its column's value bit for
// bit.
TEST(CsvWriter, SweepCsvReadsBackBitForBit) {
  using M = mech::handwritten_fourbar::Model;
  using VecQ = mechgen::ModelTypes<M>::VecQ;
  mechgen::position::PositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), mechgen::position::Status::kConverged);
  std::vector<mechgen::SweepRecord<M>> records;
  ASSERT_EQ(mechgen::Sweep(&solver, VecQ::Constant(0.0), VecQ::Constant(1.0), 37,
                           VecQ::Constant(1.3), VecQ::Constant(-0.7), &records),
            0);
  const std::vector<mechgen::SweepColumn<M>> columns = mechgen::SweepColumns<M>();
  std::ostringstream out;
  mechgen::WriteCsv(records, out,
                    mechgen::Described(mechgen::CsvAbout("handwritten_fourbar_sweep", M::kName,
                                                         "kinematic sweep", mechgen::kSweepSigns)));
  std::istringstream in(out.str());
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, std::string("# handwritten_fourbar_sweep, model handwritten_fourbar: kinematic "
                              "sweep. Signs: ") +
                      mechgen::kSweepSigns);
  for (const mechgen::SweepColumn<M>& c : columns) {
    ASSERT_TRUE(std::getline(in, line));
    const std::string unit = c.text ? "text" : c.unit;
    EXPECT_FALSE(unit.empty()) << c.name;
    EXPECT_EQ(line.rfind("# " + c.name + " [" + unit + "]: ", 0), 0u) << line;
  }
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line.find('#'), std::string::npos) << line;  // the header
  EXPECT_EQ(line.substr(0, line.find(',')), M::kQNames[0]);
  int checked = 0;
  for (const mechgen::SweepRecord<M>& r : records) {
    ASSERT_TRUE(std::getline(in, line));
    std::vector<std::string> cells;
    std::stringstream split(line);
    std::string cell;
    while (std::getline(split, cell, ',')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), columns.size()) << line;
    for (size_t c = 0; c < columns.size(); ++c) {
      if (columns[c].text) continue;
      const double value = columns[c].value(r);
      const double read = std::strtod(cells[c].c_str(), nullptr);
      if (value == 0) {
        EXPECT_EQ(cells[c], "0") << columns[c].name;
      } else {
        EXPECT_TRUE(SameBits(read, value)) << columns[c].name << ": " << cells[c];
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 38 * 20);
}

}  // namespace
