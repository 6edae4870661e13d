/**
 * \file core/invalid_option.h
 * The message of an options struct's IsValid() (position::Options, statics::Options, ...):
 * "<Type>::<field> = <value>. Violated constraint: <rule>", written once here. Out of line and
 * cold (core/inline.h): every solve checks its options first, and the formatting, inlined
 * there, was a rare branch of the hot function (four snprintf calls in statics::Solve).
 */
#pragma once

#include <cstdio>
#include <string>

#include "mechgen/core/inline.h"

namespace mechgen {

/// false, with the message in *error where error is not nullptr.
MECHGEN_COLD_PATH inline bool InvalidOption(std::string* error, const char* type, const char* field, double value,
                                            const char* rule) {
  if (error != nullptr) {
    char buffer[160];
    std::snprintf(buffer, sizeof(buffer), "%s::%s = %g. Violated constraint: %s", type, field, value, rule);
    *error = buffer;
  }
  return false;
}

}  // namespace mechgen
