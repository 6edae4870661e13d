/**
 * \file core/constants.h
 * Constants of the runtime (standard C++17: no POSIX M_PI), each defined once and read
 * everywhere.
 */
#pragma once

namespace mechgen {

/// π to double precision; the one definition the runtime headers use.
inline constexpr double kPi = 3.14159265358979323846;

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
