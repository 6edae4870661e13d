/**
 * \file position/input_step.h
 * The one check of a motion's steps against the position solver's limit
 * (Options::max_input_step), made by every analysis before it moves the inputs.
 */
#pragma once

#include <cmath>

#include "mechgen/position/types.h"

namespace mechgen::position {

/// The check every analysis makes before it moves the inputs from q_begin to q_end in `steps`
/// equal steps (a sweep's --range, a statics scan, a flywheel's cycle, a study's range): a step
/// longer than Options::max_input_step would make every row kInvalidInput, a units mistake to
/// refuse before anything runs. The first input whose step does not fit (or is not finite),
/// with the figures a message gives; input -1 when every step fits.
struct InputStepCheck {
  int input = -1;
  double step = 0;       ///< that input's step, |q_end - q_begin| / steps (inf on overflow)
  double limit = 0;      ///< Options::max_input_step
  double min_steps = 0;  ///< the fewest steps that fit: ceil(|q_end - q_begin| / limit)
  bool ok() const { return input < 0; }
};

/// CheckInputSteps over inputs 0..nq-1 of q_begin and q_end (anything indexable by int).
template <class VecA, class VecB>
InputStepCheck CheckInputSteps(const VecA& q_begin, const VecB& q_end, int nq, double steps,
                               const Options& options = Options()) {
  InputStepCheck check;
  check.limit = options.max_input_step;
  for (int j = 0; j < nq; ++j) {
    const double span = std::abs(q_end[j] - q_begin[j]), step = span / steps;
    if (!(step <= check.limit)) {
      check.input = j;
      check.step = step;
      check.min_steps = std::ceil(span / check.limit);
      return check;
    }
  }
  return check;
}

}  // namespace mechgen::position
