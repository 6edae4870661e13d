/**
 * \file io/table.h
 * The one terminal table of every tool: a short fixed-width table for people of the columns
 * of a column table (table/columns.h) that have a table name, numbers with 4 decimals,
 * angles in degrees, a NaN as the column's `missing` cell ("-" when that is empty). The rows
 * to show are the caller's (TableRowIndices(): a few spread evenly over a sweep).
 * Allocates; runs after the computation.
 */
#pragma once

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/table/columns.h"

namespace mechgen {

/// The cell of column c in row r as printed in the table: text columns as they are, numbers
/// with 4 decimals, angles in degrees.
template <class Row>
std::string TableCell(const table::Column<Row>& c, const Row& r) {
  if (c.text) return c.text(r);
  const double x = c.value(r);
  if (x != x) return c.missing.empty() ? std::string("-") : c.missing;
  return internal::FormatNumber(c.angle ? internal::ToDegrees(x) : x, "%.4f");
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

/// Prints the given rows, all of them: a header line of table names, a unit line ("[deg]"
/// for angles), then one line per row; each cell right-aligned in a column at least 10 wide.
/// Nothing when `rows` is empty.
template <class Row>
void PrintTableRows(const table::Columns<Row>& all_columns, const std::vector<Row>& rows,
                    std::ostream& out) {
  if (rows.empty()) return;
  std::vector<const table::Column<Row>*> columns;
  for (const table::Column<Row>& c : all_columns)
    if (!c.table_name.empty()) columns.push_back(&c);
  std::vector<std::string> names, units;
  for (const table::Column<Row>* c : columns) {
    names.push_back(c->table_name);
    units.push_back(c->angle ? "[deg]" : "");
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
  for (const Row& row : rows) {
    std::vector<std::string> cells;
    for (const table::Column<Row>* c : columns) cells.push_back(TableCell(*c, row));
    print_row(cells);
  }
}

/// Prints `count` rows spread evenly over `rows` (TableRowIndices()) with PrintTableRows().
template <class Row>
void PrintTable(const table::Columns<Row>& columns, const std::vector<Row>& rows, int count,
                std::ostream& out) {
  std::vector<Row> shown;
  for (size_t i : TableRowIndices(rows.size(), count)) shown.push_back(rows[i]);
  PrintTableRows(columns, shown, out);
}

}  // namespace mechgen
