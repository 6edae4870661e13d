/**
 * \file table/columns.h
 * The one column table of every tool's output: a column is its name, its unit, what it means
 * (with its sign convention), its header in the printed table and the getter of its value
 * from one output row, all defined together. The CSV writer (io/csv.h) writes every column of
 * a table, the terminal printer (io/table.h) the columns that have a table name, so the two
 * cannot drift apart; a new quantity is one column. The tables themselves are declared where
 * their rows are: sweep/columns.h (kinematic sweeps), statics/columns.h (statics sweeps), and
 * the simulate and engine tools (runtime/tools/).
 * Depends on the standard library only (the lowest output layer: io/ builds on it).
 * Building a table allocates (names, std::function); it runs outside any solver's loop.
 */
#pragma once

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace mechgen::table {

/// One column of an output whose rows are of type Row.
template <class Row>
struct Column {
  /// The CSV header, e.g. "K_theta_coupler_theta_crank".
  std::string name;
  /// The unit of the value as written to the CSV: "rad", "m", "N m", "N", "J", "s", "1"
  /// (dimensionless), "model length" (a model's own length unit), ""  for a text column.
  std::string unit;
  /// What the value is, with its sign convention where it has one.
  std::string description;
  /// The header in the printed table, e.g. "K_theta_coupler"; empty: the column is in the
  /// CSV only.
  std::string table_name;
  /// The value is an angle in radians (printed in degrees in the table).
  bool angle = false;
  /// The cell of a value that is NaN (no value: a withheld force, a failed step): "nan", or
  /// "" (an empty CSV cell, "-" in the printed table).
  std::string missing = "nan";
  /// The numeric value of the column in a row.
  std::function<double(const Row&)> value;
  /// For a text column (status, iterations): the cell itself; value is then unused.
  std::function<std::string(const Row&)> text;
};

/// A column table: its columns in output order.
template <class Row>
using Columns = std::vector<Column<Row>>;

/**
 * \brief Builds a column table one column at a time (the tables' declarations read as a list:
 * `add.Number("q", "rad", "the input", getter)`).
 */
template <class Row>
class Builder {
 public:
  explicit Builder(Columns<Row>* columns, std::string missing = "nan")
      : columns_(columns), missing_(std::move(missing)) {}

  /// A numeric column (CSV only; Shown() puts it in the printed table).
  Column<Row>& Number(std::string name, std::string unit, std::string description,
                      std::function<double(const Row&)> value) {
    Column<Row> c;
    c.name = std::move(name);
    c.unit = std::move(unit);
    c.description = std::move(description);
    c.angle = c.unit == "rad";
    c.missing = missing_;
    c.value = std::move(value);
    columns_->push_back(std::move(c));
    return columns_->back();
  }
  /// A text column (a status, a count written as an integer).
  Column<Row>& Text(std::string name, std::string description,
                    std::function<std::string(const Row&)> text) {
    Column<Row> c;
    c.name = std::move(name);
    c.description = std::move(description);
    c.missing = missing_;
    c.text = std::move(text);
    columns_->push_back(std::move(c));
    return columns_->back();
  }

 private:
  Columns<Row>* columns_;
  std::string missing_;
};

/// Puts column c in the printed table under table_name; returns c.
template <class Row>
Column<Row>& Shown(Column<Row>& c, std::string table_name) {
  c.table_name = std::move(table_name);
  return c;
}

/**
 * \brief The first column name that occurs twice in `columns`, or "" when all are unique.
 * The generator rejects models whose names would collide (a link `rocker_dot` next to a
 * link `rocker`: `theta_rocker_dot` twice); the tools check again at startup, so that a
 * header from an older generator or written by hand cannot produce an ambiguous CSV.
 */
template <class Row>
std::string DuplicateColumnName(const Columns<Row>& columns) {
  std::vector<const std::string*> names;
  names.reserve(columns.size());
  for (const Column<Row>& c : columns) names.push_back(&c.name);
  std::sort(names.begin(), names.end(),
            [](const std::string* a, const std::string* b) { return *a < *b; });
  for (size_t i = 1; i < names.size(); ++i)
    if (*names[i] == *names[i - 1]) return *names[i];
  return "";
}

/// The names of the columns, in order (the CSV header's cells).
template <class Row>
std::vector<std::string> ColumnNames(const Columns<Row>& columns) {
  std::vector<std::string> names;
  names.reserve(columns.size());
  for (const Column<Row>& c : columns) names.push_back(c.name);
  return names;
}

}  // namespace mechgen::table
