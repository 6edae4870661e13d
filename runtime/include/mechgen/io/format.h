/**
 * \file io/format.h
 * Number formatting shared by the CSV, the printed table and the SVG.
 */
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace mechgen::internal {

/// "nan" for NaN, else x printed with format.
inline std::string FormatNumber(double x, const char* format = "%.12g") {
  if (std::isnan(x)) return "nan";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, x);
  return buffer;
}

constexpr double kRadToDeg = 57.29577951308232;

}  // namespace mechgen::internal
