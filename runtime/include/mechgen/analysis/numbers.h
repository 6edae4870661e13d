// The command-line layer of every mechgen tool, without CLI11: reading a number or a count
// from an option's text, checking it finite and in its documented range, and the one-line
// usage error. runtime/tools/common/cli.h puts these on CLI11 options; sweep_main.cc, which
// `mechgen sweep` compiles without CLI11, uses this part alone for its --range values.
//
// The contract every tool keeps (issue 24): an option's value is a finite number inside the
// range its --help states (nan, inf and numbers that overflow are refused), a count is an
// integer inside its bounds, and a usage error ends the tool with exit status 2 and one line
// on stderr,
//   <tool>: error: --x: bad value '<text>': expected <what>
// with the text quoted (control characters as \xNN, a long text by its length) and the
// bounds printed with %g, never as a 309-digit number. Header-only; every function inline.
// In the analysis layer (mechgen/analysis/) because the analyses' checks of a request against
// a model (inputs.h, view_params.h) write their messages with it; runtime/tools/common/numbers.h
// forwards here.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "mechgen/io/format.h"

namespace mechgen::tools {

/// Exit status of a usage error: bad options, nothing computed or written.
constexpr int kExitUsage = 2;

/// The limits the per-model tools share (their --help states them). Model units: rad for an
/// angle input, the model's length (m) for a slide; per second for speeds.
/// A position: 1e4 rad is ~1600 turns; beyond it sin and cos of the input keep few digits.
constexpr double kMaxPosition = 1e4;
/// A speed (rad/s or m/s): 1e5 rad/s is ~1e6 rpm.
constexpr double kMaxSpeed = 1e5;
/// An acceleration (rad/s^2 or m/s^2).
constexpr double kMaxAcceleration = 1e10;
/// Time stepping: at most this many steps over a run's time span (t + dt > t all the way:
/// 1e8 steps leave dt ~1e8 ulp of the span; the CSV stays bounded).
constexpr double kMaxTimeSteps = 1e8;

/// A number for a message: %g (never a 309-digit expansion of DBL_MAX), "-0" as "0".
inline std::string FormatNumber(double value) {
  if (value == 0) value = 0;  // -0 -> 0
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", value);
  return buffer;
}

/// 'text' for a message: control characters as \xNN, a text longer than 40 characters by its
/// length only.
inline std::string Quote(const std::string& text) {
  if (text.size() > 40) return "(a " + std::to_string(text.size()) + "-character value)";
  std::string quoted = "'";
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\x%02X", c);
      quoted += buffer;
    } else {
      quoted += ch;
    }
  }
  return quoted + "'";
}

/// The tool's name for messages: the last part of argv[0] ("fourbar_sweep"); argv[0] as
/// given when it has a blank (`mechgen sweep <model.yaml>` passes "mechgen sweep ...").
inline std::string ToolName(const char* argv0) {
  std::string name = argv0 != nullptr ? argv0 : "mechgen";
  if (name.find(' ') != std::string::npos) return name.substr(0, name.find(' ', 8));
  const size_t slash = name.find_last_of('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

/// Prints "<tool>: error: <message>" as one line on stderr (line breaks in the message
/// become blanks, a message longer than 300 characters is cut); returns kExitUsage.
inline int UsageError(const std::string& tool, std::string message) {
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  if (message.size() > 300) message = message.substr(0, 300) + "...";
  std::cerr << tool << ": error: " << message << "\n";
  return kExitUsage;
}

/// "--x: bad value '<text>': expected <expected>".
inline std::string BadValue(const std::string& option, const std::string& text,
                            const std::string& expected) {
  return option + ": bad value " + Quote(text) + ": expected " + expected;
}

/// The range a number option accepts: [lo, hi], an end open when its flag says so; an
/// infinite end means unbounded on that side (the value itself is always finite).
struct NumberRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  bool Contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  /// "a finite number", "a number > 0", "a number in [1e-14, 0.1]", ...
  std::string Describe() const {
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (!has_lo && !has_hi) return "a finite number";
    if (!has_hi) return std::string("a number ") + (lo_open ? "> " : ">= ") + FormatNumber(lo);
    if (!has_lo) return std::string("a number ") + (hi_open ? "< " : "<= ") + FormatNumber(hi);
    return std::string("a number in ") + (lo_open ? "(" : "[") + FormatNumber(lo) + ", " +
           FormatNumber(hi) + (hi_open ? ")" : "]");
  }
};

/// Any finite number.
inline NumberRange Finite() { return NumberRange(); }
/// A finite number > 0 (at most hi when given).
inline NumberRange Positive(double hi = std::numeric_limits<double>::infinity()) {
  return NumberRange{0, hi, true, false};
}
/// A finite number >= 0 (at most hi when given).
inline NumberRange NonNegative(double hi = std::numeric_limits<double>::infinity()) {
  return NumberRange{0, hi, false, false};
}
/// [lo, hi].
inline NumberRange Between(double lo, double hi) { return NumberRange{lo, hi, false, false}; }
/// |v| <= bound.
inline NumberRange Magnitude(double bound) { return NumberRange{-bound, bound, false, false}; }

/// Reads a whole text as a finite number (no blanks around it; nan, inf and overflowing
/// numbers refused). With allow_degrees a "deg" suffix converts degrees to radians
/// ("90deg" -> pi/2). False if the text is not such a number.
inline bool ParseNumber(const std::string& text, double* value, bool allow_degrees = false) {
  std::string number = text;
  const bool degrees = allow_degrees && number.size() > 3 && number.compare(number.size() - 3, 3, "deg") == 0;
  if (degrees) number.resize(number.size() - 3);
  if (number.empty() || std::isspace(static_cast<unsigned char>(number[0]))) return false;
  char* end = nullptr;
  const double v = std::strtod(number.c_str(), &end);
  // The whole text: strtod stops at a NUL byte inside it ("1\0005" is not 1).
  if (end != number.c_str() + number.size() || !std::isfinite(v)) return false;
  *value = degrees ? mechgen::internal::FromDegrees(v) : v;
  return std::isfinite(*value);
}

/// A field of a data file (CSV) as a finite number: ParseNumber() of the text without the
/// blanks (space, tab, carriage return) around it.
inline bool ParseField(const std::string& text, double* value) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return false;
  const size_t end = text.find_last_not_of(" \t\r");
  return ParseNumber(text.substr(begin, end - begin + 1), value);
}

/// A number option's text checked against its range: false with the message
/// "--x: bad value '...': expected ..." in *error.
inline bool CheckNumber(const std::string& option, const std::string& text,
                        const NumberRange& range, double* value, std::string* error,
                        bool allow_degrees = false) {
  double v = 0;
  if (ParseNumber(text, &v, allow_degrees) && range.Contains(v)) {
    *value = v;
    return true;
  }
  *error = BadValue(option, text, range.Describe());
  return false;
}

/// "an integer from lo to hi".
inline std::string DescribeCount(long long lo, long long hi) {
  return "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
}

/// A count option's text: an integer ("720") or a number with an integer value ("720.0",
/// "1e3") in [lo, hi]; false with the message in *error otherwise.
inline bool CheckCount(const std::string& option, const std::string& text, long long lo,
                       long long hi, long long* value, std::string* error) {
  double v = 0;
  errno = 0;
  char* end = nullptr;
  const long long as_integer =
      text.empty() || std::isspace(static_cast<unsigned char>(text[0]))
          ? 0
          : std::strtoll(text.c_str(), &end, 10);
  bool ok = false;
  long long result = 0;
  if (end != nullptr && end != text.c_str() && *end == '\0' && errno != ERANGE) {
    ok = as_integer >= lo && as_integer <= hi;
    result = as_integer;  // exact, also beyond 2^53
  } else if (ParseNumber(text, &v) && v == std::floor(v)) {
    // [-2^63, 2^63): the doubles a long long holds; then the bounds, compared exactly.
    ok = v >= -9223372036854775808.0 && v < 9223372036854775808.0;
    if (ok) {
      result = static_cast<long long>(v);
      ok = result >= lo && result <= hi;
    }
  }
  if (!ok) {
    *error = BadValue(option, text, DescribeCount(lo, hi));
    return false;
  }
  *value = result;
  return true;
}

/// Comma-separated finite numbers (each with an optional "deg" suffix when allow_degrees),
/// each in `range`, at least one; false with the message in *error otherwise.
inline bool CheckNumberList(const std::string& option, const std::string& text,
                            const NumberRange& range, bool allow_degrees,
                            std::vector<double>* values, std::string* error) {
  values->clear();
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    double v = 0;
    if (!ParseNumber(item, &v, allow_degrees) || !range.Contains(v)) {
      *error = BadValue(option, text,
                        "comma-separated numbers, each " + range.Describe() +
                            (allow_degrees ? " (or with a 'deg' suffix)" : ""));
      return false;
    }
    values->push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return true;
}

/// Time stepping that can advance: a step dt over a span t_end gives at most max_rows rows,
/// so that t + dt != t all the way (max_rows far below 2^52) and the output stays bounded.
/// False with the message (for --dt) otherwise.
inline bool CheckTimeStep(const std::string& option, const std::string& text, double dt,
                          double t_end, double max_rows, std::string* error) {
  if (dt * max_rows >= t_end) return true;
  *error = BadValue(option, text,
                    "at least the time span / " + FormatNumber(max_rows) + " = " +
                        FormatNumber(t_end / max_rows) + " s (at most " +
                        FormatNumber(max_rows) + " steps)");
  return false;
}

}  // namespace mechgen::tools
