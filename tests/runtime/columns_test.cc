// The sweep's one column table (sweep/columns.h) against the writer it replaced: the CSV and
// the printed table of several generated models (one and two inputs, with and without
// transmission angles and points) must be byte-identical to what the former output.h wrote
// from its two hand-synchronised lists (copied below, unchanged but for names and for the
// numbers' round-trip format of issue 24, as the oracle, extended by the error-bound columns
// added since); and the table's columns are
// exactly the table-named columns of the CSV, with the same values (angles converted to degrees).
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fivebar.h"
#include "fourbar.h"
#include "fourbar_crossed.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/table.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"
#include "slider_crank.h"
#include "test_util.h"

namespace mechgen {
namespace {

// ---- The former output.h (commit 7cb3d25), the oracle --------------------------------
/// The CSV header and the values of one record, in the same order.
template <class M>
std::vector<std::string> OldCsvColumns() {
  using F = ModelFeatures<M>;
  std::vector<std::string> c;
  for (const char* q : M::kQNames) c.push_back(q);
  for (const char* phi : M::kPhiNames) c.push_back(phi);
  for (const char* phi : M::kPhiNames)
    for (const char* q : M::kQNames) c.push_back(std::string("K_") + phi + "_" + q);
  for (const char* phi : M::kPhiNames)
    for (int j = 0; j < M::kNq; ++j)
      for (int k = j; k < M::kNq; ++k)
        c.push_back(std::string("L_") + phi + "_" + M::kQNames[j] + "_" + M::kQNames[k]);
  if constexpr (F::kHasPoints) {
    for (const char* p : M::kPointNames) {
      c.push_back(std::string(p) + ".x");
      c.push_back(std::string(p) + ".y");
    }
  }
  for (const char* q : M::kQNames) c.push_back(std::string(q) + "_dot");
  for (const char* q : M::kQNames) c.push_back(std::string(q) + "_ddot");
  for (const char* phi : M::kPhiNames) c.push_back(std::string(phi) + "_dot");
  for (const char* phi : M::kPhiNames) c.push_back(std::string(phi) + "_ddot");
  if constexpr (F::kHasPointVelocities) {
    for (const char* p : M::kPointNames) {
      c.push_back(std::string(p) + ".vx");
      c.push_back(std::string(p) + ".vy");
    }
  }
  if constexpr (F::kHasPointAccelerations) {
    for (const char* p : M::kPointNames) {
      c.push_back(std::string(p) + ".ax");
      c.push_back(std::string(p) + ".ay");
    }
  }
  for (const char* s : {"status", "iterations", "residual", "cond", "sigma_min"}) c.push_back(s);
  for (const char* phi : M::kPhiNames) c.push_back(std::string("singular_") + phi);
  // Added since (issue 12): the error bounds the conditioning implies.
  for (const char* s : {"phi_error", "K_error", "L_error"}) c.push_back(s);
  if constexpr (SweepRecord<M>::kNumMu > 0) {
    for (const char* joint : M::kTransmissionJoints) c.push_back(std::string("mu_") + joint);
  }
  return c;
}

template <class M>
std::vector<std::string> OldCsvValues(const SweepRecord<M>& r) {
  using F = ModelFeatures<M>;
  // Every number as it reads back bit for bit (issue 24; io/format.h, tested in
  // table_format_test.cc), where the former writer had 12, 6 or 3 significant digits.
  auto FormatNumber = [](double x) { return mechgen::internal::FormatRoundTrip(x); };
  std::vector<std::string> v;
  const position::State<M>& s = r.state;
  const position::Motion<M>& m = r.motion;
  for (int j = 0; j < M::kNq; ++j) v.push_back(FormatNumber(r.q(j)));
  for (int i = 0; i < M::kNphi; ++i) v.push_back(FormatNumber(s.phi(i)));
  for (int i = 0; i < M::kNphi; ++i)
    for (int j = 0; j < M::kNq; ++j) v.push_back(FormatNumber(s.K(i, j)));
  for (int i = 0; i < M::kNphi; ++i)
    for (int j = 0; j < M::kNq; ++j)
      for (int k = j; k < M::kNq; ++k) v.push_back(FormatNumber(s.L(i, j + M::kNq * k)));
  if constexpr (F::kHasPoints) {
    for (int p = 0; p < M::kNumPoints; ++p) {
      v.push_back(FormatNumber(s.r_P(0, p)));
      v.push_back(FormatNumber(s.r_P(1, p)));
    }
  }
  for (int j = 0; j < M::kNq; ++j) v.push_back(FormatNumber(m.qd(j)));
  for (int j = 0; j < M::kNq; ++j) v.push_back(FormatNumber(m.qdd(j)));
  for (int i = 0; i < M::kNphi; ++i) v.push_back(FormatNumber(m.phid(i)));
  for (int i = 0; i < M::kNphi; ++i) v.push_back(FormatNumber(m.phidd(i)));
  if constexpr (F::kHasPointVelocities) {
    for (int p = 0; p < M::kNumPoints; ++p) {
      v.push_back(FormatNumber(m.v_P(0, p)));
      v.push_back(FormatNumber(m.v_P(1, p)));
    }
  }
  if constexpr (F::kHasPointAccelerations) {
    for (int p = 0; p < M::kNumPoints; ++p) {
      v.push_back(FormatNumber(m.a_P(0, p)));
      v.push_back(FormatNumber(m.a_P(1, p)));
    }
  }
  v.push_back(position::ToString(r.summary.status));
  v.push_back(std::to_string(r.summary.iterations));
  v.push_back(FormatNumber(r.summary.residual_norm));
  v.push_back(FormatNumber(r.summary.condition));
  v.push_back(FormatNumber(s.sigma_min));
  for (int i = 0; i < M::kNphi; ++i) v.push_back(FormatNumber(s.singular_direction(i)));
  // Added since (issue 12).
  for (double e : {s.phi_error, s.K_error, s.L_error}) v.push_back(FormatNumber(e));
  for (int i = 0; i < SweepRecord<M>::kNumMu; ++i) v.push_back(FormatNumber(r.mu(i)));
  return v;
}

/// Writes the header line and one line per record.
template <class M>
void OldWriteCsv(const std::vector<SweepRecord<M>>& records, std::ostream& out) {
  auto write_line = [&out](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
    out << '\n';
  };
  write_line(OldCsvColumns<M>());
  for (const SweepRecord<M>& r : records) write_line(OldCsvValues(r));
}

/// Prints `rows` records spread evenly over the sweep: q, phi, K, L and the points, angles in
/// degrees. With one input, K and L columns are named by the dependent variable only.
template <class M>
void OldPrintTable(const std::vector<SweepRecord<M>>& records, int rows, std::ostream& out) {
  if (records.empty() || rows <= 0) return;
  using F = ModelFeatures<M>;
  std::vector<std::string> names;
  std::vector<std::string> units;
  auto add = [&](std::string name, const char* unit) {
    names.push_back(std::move(name));
    units.push_back(unit);
  };
  for (int j = 0; j < M::kNq; ++j) add(M::kQNames[j], M::kQIsAngle[j] ? "[deg]" : "");
  for (int i = 0; i < M::kNphi; ++i) add(M::kPhiNames[i], M::kPhiIsAngle[i] ? "[deg]" : "");
  const bool one_input = M::kNq == 1;
  for (int i = 0; i < M::kNphi; ++i)
    for (int j = 0; j < M::kNq; ++j)
      add(std::string("K_") + M::kPhiNames[i] + (one_input ? "" : std::string("/") + M::kQNames[j]),
          "");
  for (int i = 0; i < M::kNphi; ++i)
    for (int j = 0; j < M::kNq; ++j)
      for (int k = j; k < M::kNq; ++k)
        add(std::string("L_") + M::kPhiNames[i] +
                (one_input ? "" : std::string("/") + M::kQNames[j] + "," + M::kQNames[k]),
            "");
  if constexpr (F::kHasPoints) {
    for (const char* p : M::kPointNames) {
      add(std::string(p) + ".x", "");
      add(std::string(p) + ".y", "");
    }
  }
  add("status", "");
  std::vector<size_t> width(names.size());
  for (size_t c = 0; c < names.size(); ++c) width[c] = std::max<size_t>(names[c].size(), 10);
  auto print_row = [&](const std::vector<std::string>& cells) {
    std::string line;
    for (size_t c = 0; c < cells.size(); ++c) {
      std::string cell = cells[c];
      if (cell.size() < width[c]) cell.insert(0, width[c] - cell.size(), ' ');
      line += (c ? "  " : "") + cell;
    }
    out << line << '\n';
  };
  print_row(names);
  print_row(units);
  const int n = static_cast<int>(records.size());
  rows = std::min(rows, n);
  for (int r = 0; r < rows; ++r) {
    // Evenly spaced from the first row to the last, both shown (issue 13; the former writer
    // left the last out and truncated: (n - 1) r / rows): the nearest to r (n - 1) / (rows - 1).
    const int index =
        rows == 1 ? 0 : static_cast<int>(std::floor((n - 1) * double(r) / (rows - 1) + 0.5));
    const SweepRecord<M>& rec = records[static_cast<size_t>(index)];
    const position::State<M>& s = rec.state;
    std::vector<std::string> cells;
    auto number = [&](double x) { return mechgen::internal::FormatNumber(x, "%.4f"); };
    for (int j = 0; j < M::kNq; ++j)
      cells.push_back(number(M::kQIsAngle[j] ? mechgen::internal::ToDegrees(rec.q(j)) : rec.q(j)));
    for (int i = 0; i < M::kNphi; ++i)
      cells.push_back(number(M::kPhiIsAngle[i] ? mechgen::internal::ToDegrees(s.phi(i)) : s.phi(i)));
    for (int i = 0; i < M::kNphi; ++i)
      for (int j = 0; j < M::kNq; ++j) cells.push_back(number(s.K(i, j)));
    for (int i = 0; i < M::kNphi; ++i)
      for (int j = 0; j < M::kNq; ++j)
        for (int k = j; k < M::kNq; ++k) cells.push_back(number(s.L(i, j + M::kNq * k)));
    if constexpr (F::kHasPoints) {
      for (int p = 0; p < M::kNumPoints; ++p) {
        cells.push_back(number(s.r_P(0, p)));
        cells.push_back(number(s.r_P(1, p)));
      }
    }
    cells.push_back(position::ToString(rec.summary.status));
    print_row(cells);
  }
}

// ---- end of the former output.h ---------------------------------------------------------

std::vector<std::string> Split(const std::string& line, char separator) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, separator)) cells.push_back(cell);
  return cells;
}

std::vector<std::string> Words(const std::string& line) {
  std::vector<std::string> words;
  std::istringstream in(line);
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

template <class M>
std::vector<SweepRecord<M>> SomeSweep(int steps) {
  position::CeresPositionSolver<M> solver;
  EXPECT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<SweepRecord<M>> records;
  Sweep(&solver, position::testing::QMin<M>(), position::testing::QMax<M>(), steps,
        ModelTypes<M>::VecQ::Constant(1.0), ModelTypes<M>::VecQ::Constant(0.5), &records);
  return records;
}

template <class M>
void CheckAgainstFormerWriter() {
  const std::vector<SweepRecord<M>> records = SomeSweep<M>(40);
  std::ostringstream now, before;
  WriteCsv(records, now);
  OldWriteCsv(records, before);
  EXPECT_EQ(now.str(), before.str());
  EXPECT_EQ(CsvColumns<M>(), OldCsvColumns<M>());
  std::ostringstream table_now, table_before;
  PrintTable(records, 7, table_now);
  OldPrintTable(records, 7, table_before);
  EXPECT_EQ(table_now.str(), table_before.str());
}

TEST(SweepColumns, CsvAndTableAsTheFormerWriterFourBar) { CheckAgainstFormerWriter<mech::fourbar::Model>(); }
TEST(SweepColumns, CsvAndTableAsTheFormerWriterFourBarCrossed) {
  CheckAgainstFormerWriter<mech::fourbar_crossed::Model>();
}
TEST(SweepColumns, CsvAndTableAsTheFormerWriterSliderCrank) {
  CheckAgainstFormerWriter<mech::slider_crank::Model>();
}
TEST(SweepColumns, CsvAndTableAsTheFormerWriterFiveBar) {
  static_assert(mech::fivebar::Model::kNq == 2);
  CheckAgainstFormerWriter<mech::fivebar::Model>();
}

TEST(SweepColumns, TableColumnsAreTheTableNamedCsvColumnsWithTheSameValues) {
  using M = mech::fourbar::Model;
  const std::vector<SweepRecord<M>> records = SomeSweep<M>(8);
  const std::vector<SweepColumn<M>> columns = SweepColumns<M>();
  std::ostringstream csv, table;
  WriteCsv(records, csv);
  PrintTable(records, 9, table);
  std::istringstream csv_lines(csv.str()), table_lines(table.str());
  std::string line;
  std::getline(csv_lines, line);
  const std::vector<std::string> csv_header = Split(line, ',');
  std::getline(table_lines, line);
  const std::vector<std::string> table_header = Words(line);
  std::getline(table_lines, line);  // units
  ASSERT_EQ(csv_header.size(), columns.size());
  std::vector<size_t> in_table;  // CSV column of each table column
  for (size_t c = 0; c < columns.size(); ++c) {
    EXPECT_EQ(csv_header[c], columns[c].name);
    if (!columns[c].table_name.empty()) in_table.push_back(c);
  }
  ASSERT_EQ(table_header.size(), in_table.size());
  EXPECT_GE(in_table.size(), 1u + M::kNphi + 2u * M::kNumPoints);
  // 9 rows of 9 records: every record, in order.
  for (size_t row = 0; row < 9; ++row) {
    ASSERT_TRUE(std::getline(csv_lines, line));
    const std::vector<std::string> csv_cells = Split(line, ',');
    ASSERT_TRUE(std::getline(table_lines, line));
    const std::vector<std::string> table_cells = Words(line);
    ASSERT_EQ(table_cells.size(), in_table.size());
    for (size_t t = 0; t < in_table.size(); ++t) {
      const SweepColumn<M>& c = columns[in_table[t]];
      EXPECT_EQ(table_header[t], c.table_name);
      if (c.text) {
        EXPECT_EQ(table_cells[t], csv_cells[in_table[t]]);
      } else {
        const double scale = c.angle ? 180 / M_PI : 1;
        EXPECT_NEAR(std::stod(table_cells[t]), std::stod(csv_cells[in_table[t]]) * scale, 5.1e-5)
            << c.name;
      }
    }
  }
}

// Unique column names (issue 12): the generator refuses models whose names would collide
// (csv_column_names_test.sh); the tools check again with DuplicateColumnName(), which must
// find a duplicate wherever it is and nothing in the shipped models' tables.
template <class M>
std::set<std::string> NameSet() {
  std::set<std::string> names;
  for (const SweepColumn<M>& c : SweepColumns<M>()) names.insert(c.name);
  return names;
}
TEST(SweepColumns, NamesAreUniqueAndDuplicatesAreFound) {
  EXPECT_EQ(DuplicateColumnName(SweepColumns<mech::fourbar::Model>()), "");
  EXPECT_EQ(DuplicateColumnName(SweepColumns<mech::fourbar_crossed::Model>()), "");
  EXPECT_EQ(DuplicateColumnName(SweepColumns<mech::slider_crank::Model>()), "");
  EXPECT_EQ(DuplicateColumnName(SweepColumns<mech::fivebar::Model>()), "");
  // The set of names is as large as the table (an independent count).
  EXPECT_EQ(NameSet<mech::fivebar::Model>().size(), SweepColumns<mech::fivebar::Model>().size());
  const std::vector<SweepColumn<mech::fourbar::Model>> columns =
      SweepColumns<mech::fourbar::Model>();
  for (size_t i : {size_t(0), columns.size() / 2, columns.size() - 1}) {
    std::vector<SweepColumn<mech::fourbar::Model>> twice = columns;
    SweepColumn<mech::fourbar::Model> copy = columns[i];
    twice.insert(twice.begin() + static_cast<long>((i * 7) % columns.size()), copy);
    EXPECT_EQ(DuplicateColumnName(twice), columns[i].name);
  }
}

}  // namespace
}  // namespace mechgen
