/**
 * \file io/format.h
 * Number formatting shared by the CSV, the printed table and the SVG.
 */
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

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

constexpr double kRadToDeg = 57.29577951308232;

}  // namespace mechgen::internal
