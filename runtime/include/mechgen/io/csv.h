/**
 * \file io/csv.h
 * The one CSV writer of every tool: a column table (table/columns.h) and its rows as CSV. One
 * header line of the column names, then one line per row, one cell per column. Numbers are
 * written so that they read back to the same double (FormatRoundTrip(): the shortest text
 * that round-trips, at most 17 significant digits); a NaN value is the column's `missing`
 * cell ("nan", or empty for "no value"); text columns as they are. Optionally
 * (CsvOptions::describe) '#' comment lines before the header state each column's unit and
 * meaning with its sign convention (DescribeColumns()).
 * Streaming: WriteCsvHeader() once, then WriteCsvRow() per row as the rows are computed;
 * WriteCsv() for rows held in a vector. Allocates (outside the solvers' loops).
 */
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/table/columns.h"

namespace mechgen {

/// How WriteCsvHeader() starts the file.
struct CsvOptions {
  /// Before the header line, one comment line per column: "# name [unit]: description".
  bool describe = false;
};

/// The cell of column c in row r as written to the CSV.
template <class Row>
std::string CsvCell(const table::Column<Row>& c, const Row& r) {
  if (c.text) return c.text(r);
  const double x = c.value(r);
  return x != x ? c.missing : internal::FormatRoundTrip(x);
}

/// One line per column, "# name [unit]: description" (no brackets for a text column).
template <class Row>
void DescribeColumns(const table::Columns<Row>& columns, std::ostream& out) {
  for (const table::Column<Row>& c : columns) {
    out << "# " << c.name;
    if (!c.unit.empty()) out << " [" << c.unit << "]";
    if (!c.description.empty()) out << ": " << c.description;
    out << '\n';
  }
}

/// Writes the header line: the column names, comma-separated (after the column descriptions
/// with options.describe).
template <class Row>
void WriteCsvHeader(const table::Columns<Row>& columns, std::ostream& out,
                    const CsvOptions& options = CsvOptions()) {
  if (options.describe) DescribeColumns(columns, out);
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i].name;
  out << '\n';
}

/// Writes the line of one row.
template <class Row>
void WriteCsvRow(const table::Columns<Row>& columns, const Row& r, std::ostream& out) {
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << CsvCell(columns[i], r);
  out << '\n';
}

/// Writes the header line and one line per row.
template <class Row>
void WriteCsv(const table::Columns<Row>& columns, const std::vector<Row>& rows, std::ostream& out,
              const CsvOptions& options = CsvOptions()) {
  WriteCsvHeader(columns, out, options);
  for (const Row& r : rows) WriteCsvRow(columns, r, out);
}

}  // namespace mechgen
