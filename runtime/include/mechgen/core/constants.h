/**
 * \file core/constants.h
 * Constants of the runtime (standard C++17: no POSIX M_PI), each defined once and read
 * everywhere.
 */
#pragma once

namespace mechgen {

/// π to double precision; the one definition the runtime headers use.
inline constexpr double kPi = 3.14159265358979323846;

/// Angles in degrees, the one conversion of every output and input (the tools' messages,
/// tables and CSVs, the "deg" suffix of the command lines, model, study and task files, the
/// reports): kDegToRad is pi/180 rounded to the nearest double (kPi / 180 and M_PI / 180 give
/// the same double). ToDegrees divides by it (one correctly rounded operation: of x 180/pi it
/// is the nearest double more often than x * double(180/pi) or x * 180 / pi, about 11 % of
/// doubles misrounded against 23 %), FromDegrees multiplies by it; both exact for 0 and keep
/// NaN (tests/runtime/table_format_test.cc, against extended precision).
inline constexpr double kDegToRad = 0.017453292519943295;
static_assert(kDegToRad == kPi / 180, "pi/180 rounds to kDegToRad");
constexpr double ToDegrees(double radians) { return radians / kDegToRad; }
constexpr double FromDegrees(double degrees) { return degrees * kDegToRad; }

/// The singular-configuration threshold: a configuration is singular (a dead point) where
/// 1/cond_1(Phi_phi) < kMinRcond. There K already loses ~ 6 digits (bench/stability/README.md)
/// and forces grow like 1/sigma_min(Phi_phi). The position solver refuses such a
/// configuration (position::Options::min_rcond), the statics and kinetostatics withhold their
/// forces there (max_condition = kMaxCondition), the simulations stop there
/// (MinimalOptions::min_rcond, PrescribedOptions::min_rcond).
inline constexpr double kMinRcond = 1e-6;
/// cond_1(Phi_phi) above which a configuration is singular: 1 / kMinRcond (= 1e6 exactly).
inline constexpr double kMaxCondition = 1 / kMinRcond;
static_assert(kMaxCondition == 1e6, "1 / kMinRcond rounds to 1e6");

}  // namespace mechgen
