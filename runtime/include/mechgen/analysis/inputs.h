// The inputs' options every tool that moves the inputs shares: `--range input:min:max`
// (sweep, statics) read against the model's inputs, and the one message for a range whose
// steps are longer than the position solver accepts (position::CheckInputSteps).
#pragma once

#include <cmath>
#include <string>

#include "mechgen/analysis/numbers.h"

#include "mechgen/core/model_calls.h"
#include "mechgen/position/input_step.h"

namespace mechgen::tools {

/// "i:min:max" with i an input's name or index -> (index, min, max) in model units (radians for
/// angles; "90deg" allowed). False with the message (naming the inputs) when it is not one.
template <class M>
bool ParseRange(const M& model, const std::string& text, int* index, double* min, double* max,
                std::string* error) {
  using C = ModelCalls<M>;
  const size_t a = text.find(':');
  const size_t b = a == std::string::npos ? a : text.find(':', a + 1);
  if (b == std::string::npos) {
    *error = BadValue("--range", text, "input:min:max");
    return false;
  }
  const std::string name = text.substr(0, a);
  *index = -1;
  for (int j = 0; j < C::Nq(model); ++j)
    if (name == C::QName(model, j) || name == std::to_string(j)) *index = j;
  if (*index < 0) {
    *error = BadValue("--range", text, "input:min:max") + "; no input named " + Quote(name) + "; inputs are";
    for (int j = 0; j < C::Nq(model); ++j) *error += std::string(" ") + C::QName(model, j);
    return false;
  }
  if (!ParseNumber(text.substr(a + 1, b - a - 1), min, /*allow_degrees=*/true) ||
      !ParseNumber(text.substr(b + 1), max, /*allow_degrees=*/true) || !(std::abs(*min) <= kMaxPosition) ||
      !(std::abs(*max) <= kMaxPosition)) {
    *error = BadValue("--range", text,
                      "input:min:max with min and max in [-1e4, 1e4] (append 'deg' for "
                      "degrees)");
    return false;
  }
  return true;
}

/// The usage error's text for --range steps that do not fit (check.ok() false), e.g.
/// "--range: theta_crank moves 1e+04 per step, more than the solver's limit of 1000; use more
/// --steps or a shorter range".
template <class M>
std::string RangeStepError(const M& model, const position::InputStepCheck& check) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.3g", check.step);
  return std::string("--range: ") + ModelCalls<M>::QName(model, check.input) + " moves " + buffer +
         " per step, more than the solver's limit of " + FormatNumber(check.limit) +
         "; use more --steps or a shorter range";
}

}  // namespace mechgen::tools
