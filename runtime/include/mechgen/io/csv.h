/**
 * \file io/csv.h
 * A sweep as CSV: one header line, one line per record, one cell per column of the sweep's
 * column table (sweep/columns.h; names and values defined there together). Angles in
 * radians. Allocates (outside the solver's loop): WriteCsv() after a sweep, or
 * WriteCsvHeader() and WriteCsvRow() from SweepRows()'s callback, one row at a time.
 */
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/sweep/columns.h"

namespace mechgen {

/// The cell of column c in record r as written to the CSV.
template <class M>
std::string CsvCell(const SweepColumn<M>& c, const SweepRecord<M>& r) {
  return c.text ? c.text(r) : internal::FormatNumber(c.value(r), c.csv_format);
}

/// The CSV header: the names of SweepColumns<M>(), in order.
template <class M>
std::vector<std::string> CsvColumns() {
  std::vector<std::string> names;
  for (const SweepColumn<M>& c : SweepColumns<M>()) names.push_back(c.name);
  return names;
}

/// The CSV cells of one record, in the order of CsvColumns().
template <class M>
std::vector<std::string> CsvValues(const SweepRecord<M>& r) {
  std::vector<std::string> cells;
  for (const SweepColumn<M>& c : SweepColumns<M>()) cells.push_back(CsvCell(c, r));
  return cells;
}

/// Writes the header line: the column names, comma-separated.
template <class M>
void WriteCsvHeader(const std::vector<SweepColumn<M>>& columns, std::ostream& out) {
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i].name;
  out << '\n';
}

/// Writes the line of one record (streaming: SweepRows() hands out one record at a time).
template <class M>
void WriteCsvRow(const std::vector<SweepColumn<M>>& columns, const SweepRecord<M>& r,
                 std::ostream& out) {
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << CsvCell(columns[i], r);
  out << '\n';
}

/// Writes the header line and one line per record.
template <class M>
void WriteCsv(const std::vector<SweepRecord<M>>& records, std::ostream& out) {
  const std::vector<SweepColumn<M>> columns = SweepColumns<M>();
  WriteCsvHeader(columns, out);
  for (const SweepRecord<M>& r : records) WriteCsvRow(columns, r, out);
}

}  // namespace mechgen
