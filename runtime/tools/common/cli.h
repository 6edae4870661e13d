// The command-line layer of every mechgen tool on CLI11 (numbers.h holds the checks).
// Every tool (<model>_sweep, _statics, _simulate, _engine, mechgen_balance) declares its
// options on a CLI::App with the helpers below and parses with Parse():
//  - `--opt=value` and `--opt value` both work (CLI11);
//  - a number option takes a finite number inside its stated range (CLI11's own number
//    checks let nan and inf through, and its range check prints DBL_MAX in full): Number();
//  - a count takes an integer inside its bounds: Count();
//  - --help lists each option's limits and exits 0;
//  - any usage error prints one line "<tool>: error: ..." on stderr and exits 2.
// Header-only; include it in one translation unit of a tool.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "numbers.h"
#include "params.h"

namespace mechgen::tools {

/// A CLI11 validator: a finite number in `range` (with a "deg" suffix in radians when
/// allow_degrees); rewrites the text as %.17g so that CLI11 converts exactly that value.
inline CLI::Validator NumberValidator(const NumberRange& range, bool allow_degrees = false) {
  return CLI::Validator(
      [range, allow_degrees](std::string& text) -> std::string {
        double v = 0;
        if (ParseNumber(text, &v, allow_degrees) && range.Contains(v)) {
          char buffer[40];
          std::snprintf(buffer, sizeof(buffer), "%.17g", v);
          text = buffer;
          return {};
        }
        return "bad value " + Quote(text) + ": expected " + range.Describe();
      },
      range.Describe(), "");
}

/// A CLI11 validator: an integer in [lo, hi] (also written as "720.0" or "1e3"); rewrites
/// the text as the integer.
inline CLI::Validator CountValidator(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        long long v = 0;
        std::string error;
        if (CheckCount("", text, lo, hi, &v, &error)) {
          text = std::to_string(v);
          return {};
        }
        return "bad value " + Quote(text) + ": expected " + DescribeCount(lo, hi);
      },
      DescribeCount(lo, hi), "");
}

/// A CLI11 validator: comma-separated numbers, each in `range`.
inline CLI::Validator NumberListValidator(const NumberRange& range, bool allow_degrees) {
  return CLI::Validator(
      [range, allow_degrees](std::string& text) -> std::string {
        std::vector<double> values;
        std::string error;
        if (CheckNumberList("", text, range, allow_degrees, &values, &error)) return {};
        return error.substr(2);  // without the empty option's ": "
      },
      "V[,V...], each " + range.Describe(), "");
}

/// A number option bound to *value (its default shown by --help), checked by
/// NumberValidator(range).
template <class T>
CLI::Option* Number(CLI::App* app, const std::string& name, T* value, const NumberRange& range,
                    const std::string& help) {
  return app->add_option(name, *value, help)
      ->check(NumberValidator(range))
      ->capture_default_str();
}

/// A count option bound to *value (its default shown by --help), in [lo, hi].
template <class T>
CLI::Option* Count(CLI::App* app, const std::string& name, T* value, long long lo, long long hi,
                   const std::string& help) {
  return app->add_option(name, *value, help)->transform(CountValidator(lo, hi))->capture_default_str();
}

/// --params FILE and --set name=value (repeatable): the model's parameters at run time
/// (common/params.h applies them).
inline void AddParameterOptions(CLI::App* app, ParameterOptions* options) {
  app->add_option("--params", options->file,
                  "a file of parameter values, one `name = value` per line (# comments), in the "
                  "model's units; applied before --set");
  app->add_option("--set", options->sets,
                  "name=value: a parameter of the model at run time, in the model's units (an angle "
                  "may end in deg); repeatable; no recompilation")
      ->allow_extra_args(false);  // one value per --set: a word after it is not taken
}

/// Parses the command line. Returns -1 to go on; otherwise the exit status to end with:
/// 0 after --help (printed on stdout), kExitUsage after a usage error (one line on stderr,
/// "<tool>: error: <what>").
inline int Parse(CLI::App* app, int argc, char** argv, const std::string& tool) {
  try {
    app->parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    const std::string help = app->help("", CLI::AppFormatMode::Normal);
    std::cout << help << (help.empty() || help.back() != '\n' ? "\n" : "");
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    const std::string help = app->help("", CLI::AppFormatMode::All);
    std::cout << help << (help.empty() || help.back() != '\n' ? "\n" : "");
    return 0;
  } catch (const CLI::ParseError& e) {
    return UsageError(tool, e.what());
  }
  return -1;
}

}  // namespace mechgen::tools
