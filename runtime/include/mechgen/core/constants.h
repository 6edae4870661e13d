/**
 * \file core/constants.h
 * Mathematical constants of the runtime (standard C++17: no POSIX M_PI).
 */
#pragma once

namespace mechgen {

/// π to double precision; the one definition the runtime headers use.
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace mechgen
