// The model's parameters at run time, for every tool (issue 25): `--params FILE` then
// `--set name=value` (repeatable, applied in order, so a --set overrides the file). Units are
// the model file's (lengths in its length unit, angles in radians or with a `deg` suffix as
// in the model language). Names are checked against the generated Params::kNames; an unknown
// name lists them, and a derived parameter (Params::kDerivedNames: it follows the parameters
// it is defined by) names itself as derived. No recompilation: the generated code takes its
// parameters at run time. The options themselves are declared by tools/common/cli.h
// (AddParameterOptions); this part needs no CLI11, so that the sweep's model-independent
// CLI11 object (sweep_args.cc) can carry them.
//
// FILE: one `name = value` (or `name: value`) per line; `#` starts a comment; blank lines are
// skipped. An error names FILE:LINE.
#pragma once

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "mechgen/analysis/numbers.h"

namespace mechgen::tools {

/// What the command line asked for the parameters.
struct ParameterOptions {
  std::string file;               ///< --params FILE (empty: none)
  std::vector<std::string> sets;  ///< --set name=value, in order
};

namespace params_internal {

inline std::string Trim(const std::string& text) {
  const size_t b = text.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const size_t e = text.find_last_not_of(" \t\r");
  return text.substr(b, e - b + 1);
}

/// The parameters of a generated model (its Params: kNames, kDerivedNames, Find) as the
/// functions below read a parameter table; analysis/view_params.h has the model view's.
template <class P>
struct GeneratedTable {
  P* params;
  std::string NameList() const {
    std::string list;
    for (const char* n : P::kNames) list += (list.empty() ? "" : ", ") + std::string(n);
    return list.empty() ? "(none)" : list;
  }
  bool IsDerived(const std::string& name) const {
    for (const char* d : P::kDerivedNames)
      if (name == d) return true;
    return false;
  }
  double* Find(const std::string& name) const { return params->Find(name.c_str()); }
  void Finish() const {}
};

// table.Find(name) = value text; false and *error (without a location) if it cannot be.
template <class Table>
bool Set(const std::string& name, const std::string& value_text, const Table& table, std::string* error) {
  if (table.IsDerived(name)) {
    *error = "'" + name + "' is a derived parameter (defined in the model by the parameters above it); set "
             "those instead (parameters: " + table.NameList() + ")";
    return false;
  }
  // A NUL byte would end the name early for Find ("a\0b" is not "a").
  double* target = name.find('\0') == std::string::npos ? table.Find(name) : nullptr;
  if (target == nullptr) {
    *error = "no parameter " + Quote(name) + " in the model (parameters: " + table.NameList() + ")";
    return false;
  }
  double value = 0;
  if (!ParseNumber(value_text, &value, /*allow_degrees=*/true)) {
    *error = "bad value " + Quote(value_text) + " for '" + name + "': expected a finite number (an angle may end in deg)";
    return false;
  }
  *target = value;
  return true;
}

/// Applies `name=value` to the table; false and *error (one line) if it cannot.
template <class Table>
bool SetParameter(const std::string& assignment, const Table& table, std::string* error) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) {
    *error = "--set " + Quote(assignment) + ": expected name=value (parameters: " + table.NameList() + ")";
    return false;
  }
  std::string why;
  if (!Set(Trim(assignment.substr(0, eq)), Trim(assignment.substr(eq + 1)), table, &why)) {
    *error = "--set " + Quote(assignment) + ": " + why;
    return false;
  }
  return true;
}

/// Applies the parameter file `path` to the table; false and *error ("path:line: ...") if it
/// cannot be read or a line is wrong (then the table may be partly set: the caller stops).
template <class Table>
bool ReadParameterFile(const std::string& path, const Table& table, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "--params: cannot read " + Quote(path);
    return false;
  }
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const size_t hash = line.find('#');
    const std::string text = Trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (text.empty()) continue;
    const size_t sep = text.find_first_of("=:");
    std::string why;
    if (sep == std::string::npos) {
      why = "expected `name = value`, got " + Quote(text);
    } else if (Set(Trim(text.substr(0, sep)), Trim(text.substr(sep + 1)), table, &why)) {
      continue;
    }
    *error = path + ":" + std::to_string(number) + ": " + why;
    return false;
  }
  if (in.bad()) {
    *error = "--params: cannot read " + Quote(path);
    return false;
  }
  return true;
}

/// The file, then each --set in order, onto the table; false and *error (one line) on the
/// first problem.
template <class Table>
bool Apply(const ParameterOptions& options, const Table& table, std::string* error) {
  if (!options.file.empty() && !ReadParameterFile(options.file, table, error)) return false;
  for (const std::string& s : options.sets)
    if (!SetParameter(s, table, error)) return false;
  table.Finish();
  return true;
}

}  // namespace params_internal

/// Applies `name=value` to *params; false and *error (one line) if it cannot.
template <class P>
bool SetParameter(const std::string& assignment, P* params, std::string* error) {
  return params_internal::SetParameter(assignment, params_internal::GeneratedTable<P>{params}, error);
}

/// Applies the parameter file `path` to *params; false and *error ("path:line: ...") if it
/// cannot be read or a line is wrong (then *params may be partly set: the caller stops).
template <class P>
bool ReadParameterFile(const std::string& path, P* params, std::string* error) {
  return params_internal::ReadParameterFile(path, params_internal::GeneratedTable<P>{params}, error);
}

/// The file, then each --set in order, onto *params; false and *error (one line) on the first
/// problem.
template <class P>
bool ApplyParameters(const ParameterOptions& options, P* params, std::string* error) {
  return params_internal::Apply(options, params_internal::GeneratedTable<P>{params}, error);
}

namespace params_internal {
/// Appends "name = now (default was)" to a ChangedParameters text when now differs from was.
inline void AppendChanged(std::string* text, const char* name, double now, double was) {
  if (now == was) return;
  *text += (text->empty() ? "" : ", ") + std::string(name) + " = " + FormatNumber(now) + " (default " +
           FormatNumber(was) + ")";
}
}  // namespace params_internal

/// "a = 0.12 (default 0.1), mu = 0.15 (default 0.1)": the parameters that differ from the
/// model's defaults, for the tools' summaries; empty when none does.
template <class P>
std::string ChangedParameters(const P& params) {
  P defaults;
  P current = params;
  std::string text;
  for (const char* n : P::kNames) params_internal::AppendChanged(&text, n, *current.Find(n), *defaults.Find(n));
  return text;
}

}  // namespace mechgen::tools
