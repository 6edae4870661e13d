/**
 * \file io/format.h
 * Number formatting shared by the CSV, the printed table and the SVG: FormatNumber() with a
 * printf format (the printed table, the SVG), FormatRoundTrip() for data files (the CSVs).
 */
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

#include "mechgen/core/constants.h"

namespace mechgen::internal {

/// "nan" for NaN, else x printed with format; never a negative zero: -0.0, and a small
/// negative number that prints as zero ("-0", "-0.0000", "-0.00e+00"), print without the
/// sign.
inline std::string FormatNumber(double x, const char* format = "%.12g") {
  if (std::isnan(x)) return "nan";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, x);
  if (buffer[0] == '-') {
    bool zero = false, only_zero = true;
    for (const char* c = buffer + 1; *c != '\0' && only_zero; ++c) {
      zero = zero || *c == '0';
      only_zero = *c == '0' || *c == '.' || *c == 'e' || *c == 'E' || *c == '+' || *c == '-';
    }
    if (zero && only_zero) return buffer + 1;
  }
  return buffer;
}

/// x as the shortest text that reads back (strtod, std::from_chars) to the same double, bit
/// for bit: the fewest significant digits (at most 17) that round-trip, in printf %g's
/// layout (std::to_chars, general format; an integer below 2^53 is written in full), e.g.
/// "0.1", "0.3333333333333333", "5e-12", "1e+300", "5e-324", "100000"; "nan" for NaN,
/// "inf"/"-inf". The one exception is negative zero, written "0" like FormatNumber() does
/// (the outputs never print "-0"): it reads back as +0, equal in value. The CSV writer
/// (io/csv.h) writes every number with it. No allocation but the result, no locale.
inline std::string FormatRoundTrip(double x) {
  if (std::isnan(x)) return "nan";
  if (x == 0) return "0";
  char buffer[64];
  const std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), x, std::chars_format::general);
  if (r.ec != std::errc()) return FormatNumber(x, "%.17g");  // cannot happen: 64 > 24 chars
  return std::string(buffer, r.ptr);
}

/// Angles in degrees: the one conversion (core/constants.h), named here too for the writers.
using ::mechgen::FromDegrees;
using ::mechgen::kDegToRad;
using ::mechgen::ToDegrees;


}  // namespace mechgen::internal
