/**
 * \file io/table.h
 * A short fixed-width table of a sweep for people: the columns of the sweep's column table
 * (sweep/columns.h) that have a table name (q, phi, K, L, the points, the status), angles in
 * degrees, at a few records spread over the sweep. Allocates; runs after the sweep.
 */
#pragma once

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/sweep/columns.h"

namespace mechgen {

/// The cell of column c in record r as printed in the table: text columns as they are,
/// numbers with 4 decimals, angles in degrees.
template <class M>
std::string TableCell(const SweepColumn<M>& c, const SweepRecord<M>& r) {
  if (c.text) return c.text(r);
  return internal::FormatNumber(c.value(r) * (c.angle ? internal::kRadToDeg : 1), "%.4f");
}

/// The indices of the `rows` records PrintTable() shows out of `n`: evenly spaced from the
/// first record to the last, both included (index round(r (n - 1) / (rows - 1))), e.g. 0,
/// 45, ..., 360 deg for 9 rows of a 360-step crank turn; all n when rows >= n; the first
/// alone when rows == 1. Strictly increasing. Empty when n == 0 or rows <= 0.
inline std::vector<size_t> TableRowIndices(size_t n, int rows) {
  std::vector<size_t> indices;
  if (n == 0 || rows <= 0) return indices;
  const size_t count = std::min(static_cast<size_t>(rows), n);
  indices.reserve(count);
  if (count == 1) {
    indices.push_back(0);
    return indices;
  }
  // (n - 1) r / (count - 1) = q r + rem r / (count - 1), rounded half up; in integers, without
  // overflow (rem < count - 1 <= INT_MAX, r < count).
  const size_t span = count - 1, q = (n - 1) / span, rem = (n - 1) % span;
  for (size_t r = 0; r < count; ++r) indices.push_back(q * r + (2 * rem * r + span) / (2 * span));
  return indices;
}

/// Prints the given records, all of them: a header line of table names, a unit line
/// ("[deg]" for angles), then one line per record.
template <class M>
void PrintTableRows(const std::vector<SweepRecord<M>>& records, std::ostream& out) {
  if (records.empty()) return;
  std::vector<SweepColumn<M>> columns = SweepColumns<M>();
  columns.erase(std::remove_if(columns.begin(), columns.end(),
                               [](const SweepColumn<M>& c) { return c.table_name.empty(); }),
                columns.end());
  std::vector<std::string> names, units;
  for (const SweepColumn<M>& c : columns) {
    names.push_back(c.table_name);
    units.push_back(c.angle ? "[deg]" : "");
  }
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
  for (const SweepRecord<M>& record : records) {
    std::vector<std::string> cells;
    for (const SweepColumn<M>& c : columns) cells.push_back(TableCell(c, record));
    print_row(cells);
  }
}

/// Prints `rows` records spread evenly over the sweep (TableRowIndices()) with
/// PrintTableRows().
template <class M>
void PrintTable(const std::vector<SweepRecord<M>>& records, int rows, std::ostream& out) {
  std::vector<SweepRecord<M>> shown;
  for (size_t i : TableRowIndices(records.size(), rows)) shown.push_back(records[i]);
  PrintTableRows(shown, out);
}

}  // namespace mechgen
