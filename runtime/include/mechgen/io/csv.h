/**
 * \file io/csv.h
 * The one CSV writer of every tool: a column table (table/columns.h) and its rows as CSV. One
 * header line of the column names, then one line per row, one cell per column. Numbers are
 * written so that they read back to the same double (FormatRoundTrip(): the shortest text
 * that round-trips, at most 17 significant digits); a NaN value is the column's `missing`
 * cell ("nan", or empty for "no value"); text columns as they are. With
 * CsvOptions::describe (every tool turns it on: Described()), '#' comment lines come before
 * the header: first "# <about>", which tool wrote the file, for which model, and the sign
 * convention of its forces (CsvAbout()); then one line per column, in the header's order,
 * "# name [unit]: description" ("[text]" for a text column; DescribeColumns()). Readers skip
 * them as comments: gnuplot by default (its `columnheaders` is the first line that is not a
 * comment), pandas with comment='#', awk and shell with `grep -v '^#'`.
 * Streaming: WriteCsvHeader() once, then WriteCsvRow() per row as the rows are computed;
 * WriteCsv() for rows held in a vector. Allocates (outside the solvers' loops).
 */
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/table/columns.h"

namespace mechgen {

/// How WriteCsvHeader() starts the file.
struct CsvOptions {
  /// Before the header line: the line `about` (when not empty), then one comment line per
  /// column, "# name [unit]: description".
  bool describe = false;
  /// The first comment line with describe (without its "# "): what wrote the file (CsvAbout()).
  std::string about;
};

/// The first comment line of a tool's CSV: "<tool>, model <model>: <what>. Signs: <signs>"
/// (the sign convention of the file's forces and angles: who acts on whom, which way is +;
/// nothing after <what> when `signs` is empty).
inline std::string CsvAbout(const std::string& tool, const std::string& model,
                            const std::string& what, const std::string& signs) {
  std::string about = tool + ", model " + model + ": " + what;
  if (!signs.empty()) about += ". Signs: " + signs;
  return about;
}

/// The options of every tool's CSV: described columns after the line `about`.
inline CsvOptions Described(std::string about) {
  CsvOptions options;
  options.describe = true;
  options.about = std::move(about);
  return options;
}

namespace internal {
/// `text` on one comment line: line breaks become spaces.
inline std::string OneLine(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}
}  // namespace internal

/// The cell of column c in row r as written to the CSV.
template <class Row>
std::string CsvCell(const table::Column<Row>& c, const Row& r) {
  if (c.text) return c.text(r);
  const double x = c.value(r);
  return x != x ? c.missing : internal::FormatRoundTrip(x);
}

/// One line per column, "# name [unit]: description" ("[text]" for a text column).
template <class Row>
void DescribeColumns(const table::Columns<Row>& columns, std::ostream& out) {
  for (const table::Column<Row>& c : columns) {
    out << "# " << c.name << " [" << (c.text ? std::string("text") : c.unit) << "]";
    if (!c.description.empty()) out << ": " << internal::OneLine(c.description);
    out << '\n';
  }
}

/// Writes the header line: the column names, comma-separated (after the column descriptions
/// with options.describe).
template <class Row>
void WriteCsvHeader(const table::Columns<Row>& columns, std::ostream& out,
                    const CsvOptions& options = CsvOptions()) {
  if (options.describe) {
    if (!options.about.empty()) out << "# " << internal::OneLine(options.about) << '\n';
    DescribeColumns(columns, out);
  }
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
