/**
 * \file dynamics/witness/steady_state.h
 * The steady-state witness of the simulator (dynamics/simulator.h): fed each sample's
 * coordinate, it fires when the motion has become periodic.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "mechgen/core/constants.h"

namespace mechgen::dynamics {


/**
 * Steady-state detection: the one definition of "the motion has become periodic" that the
 * free, driven and engine simulations share (the simulate tool's stop at a steady state, the
 * engine's run-up).
 *
 * Cycles of coordinate q_c = q(coordinate): the levels q_c(t0) + k cycle (k integer). A
 * crossing is a sample at which q_c has passed into another interval between levels (either
 * direction) through a level other than the one last crossed; its time is interpolated
 * linearly between that sample and the one before, at the level passed (of the two levels
 * around the move, the one with the larger k). Passing the last crossed level again does not
 * count, and the start's level q_c(t0) counts as crossed at t0 (but not as a crossing): an
 * oscillation about a level completes no cycle, and a motion that starts backwards does not
 * pass its start level at once. Cycle n lies between two successive
 * crossings (two adjacent levels: q_c has advanced one cycle); its duration is P_n and its
 * mean speed w_n = cycle / P_n (the mean of |q_c dot| over it when q_c moves one way). The
 * start is not a crossing: the first timed cycle ends at the second crossing.
 *
 * Steady after cycle n when the last N = consecutive changes of the mean speed are all
 * smaller than tolerance times the latest mean speed:
 *     |w_i - w_(i-1)| < tolerance w_n   for i = n - N + 1, ..., n.
 * (This is the engine run-up's check as it was, N = 2, which this detector replaced without
 * moving a number; the simulate tool's old check compared successive periods, |P_n - P_(n-1)|
 * <= tolerance P_n, which differs from this one at second order in the tolerance.)
 * Reported in the summary's SteadyStateSummary: crossings and cycles counted, the last
 * period, mean speed and relative change |w_n - w_(n-1)| / w_n, and the time of the sample at
 * which the motion was found steady. Nothing allocates.
 */
struct SteadyStateOptions {
  static constexpr int kMaxConsecutive = 16;
  bool enabled = false;
  int coordinate = 0;        ///< which q (an index into the sample's q)
  double cycle = 2 * kPi;    ///< the advance of q_c per cycle (2 pi: a revolution; 4 pi: a
                             ///< four-stroke engine's cycle)
  double tolerance = 1e-4;   ///< relative, in (0, 0.5]
  int consecutive = 2;       ///< N, in [1, kMaxConsecutive]

  /// The options make sense for a sample q of kNq coordinates.
  bool IsValid(int kNq) const {
    return coordinate >= 0 && coordinate < kNq && std::isfinite(cycle) && cycle > 0 &&
           std::isfinite(tolerance) && tolerance > 0 && tolerance <= 0.5 && consecutive >= 1 &&
           consecutive <= kMaxConsecutive;
  }
};

/// What the steady-state detection saw (all NaN or 0 when it was not enabled).
struct SteadyStateSummary {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool steady = false;        ///< the run was found steady (and stopped there)
  int crossings = 0;          ///< levels q_c(t0) + k cycle passed
  int cycles = 0;             ///< cycles timed: crossings - 1 (0 before the second crossing)
  double t_crossing = kNaN;   ///< time of the last crossing (s)
  double period = kNaN;       ///< P_n: the duration of the last cycle (s)
  double mean_speed = kNaN;   ///< w_n = cycle / P_n (rad/s for an angle)
  double last_change = kNaN;  ///< |w_n - w_(n-1)| / w_n (NaN before two cycles)
  double t_steady = kNaN;     ///< the time of the sample at which the run was found steady
};

/// The detector of SteadyStateOptions, fed one sample (t, q_c) at a time.
class SteadyStateDetector {
 public:
  /// A run from (t0, q_c(t0)).
  void Start(const SteadyStateOptions& o, double t0, double q0) {
    o_ = o;
    origin_ = q0;
    prev_t_ = t0;
    prev_q_ = q0;
    k_ = 0;
    k_last_ = 0;
    prev_mean_ = SteadyStateSummary::kNaN;
    count_ = 0;
  }
  /// The sample (t, q_c) after the previous one; updates *s. True when it shows the motion
  /// steady (s->steady is then set).
  bool Add(double t, double q, SteadyStateSummary* s) {
    if (!std::isfinite(q)) return false;
    const double k_now = Interval(q);
    bool steady = false;
    const double k_level = std::max(k_now, k_);
    if (k_now != k_ && k_level != k_last_) {
      const double level = origin_ + o_.cycle * k_level;
      const double t_cross = prev_t_ + (t - prev_t_) * (level - prev_q_) / (q - prev_q_);
      if (s->crossings > 0 && t_cross > s->t_crossing) {
        const double period = t_cross - s->t_crossing;
        const double mean = o_.cycle / period;
        ++s->cycles;
        s->period = period;
        s->mean_speed = mean;
        if (s->cycles >= 2) {
          // The last N changes, newest first.
          for (int i = std::min(count_, SteadyStateOptions::kMaxConsecutive - 1); i > 0; --i)
            changes_[i] = changes_[i - 1];
          changes_[0] = std::abs(mean - prev_mean_);
          count_ = std::min(count_ + 1, SteadyStateOptions::kMaxConsecutive);
          s->last_change = changes_[0] / mean;
          if (count_ >= o_.consecutive) {
            steady = true;
            for (int i = 0; i < o_.consecutive; ++i) steady = steady && changes_[i] < o_.tolerance * mean;
          }
        }
        prev_mean_ = mean;
      }
      ++s->crossings;
      s->t_crossing = t_cross;
      k_last_ = k_level;
    }
    k_ = k_now;
    prev_t_ = t;
    prev_q_ = q;
    if (steady) {
      s->steady = true;
      s->t_steady = t;
    }
    return steady;
  }

 private:
  /// k with origin + k cycle <= q < origin + (k + 1) cycle, by the same comparisons against
  /// the levels that a crossing's interpolation uses.
  double Interval(double q) const {
    double k = std::floor((q - origin_) / o_.cycle);
    if (q >= origin_ + o_.cycle * (k + 1)) {
      k += 1;
    } else if (q < origin_ + o_.cycle * k) {
      k -= 1;
    }
    return k;
  }

  SteadyStateOptions o_;
  double origin_ = 0, prev_t_ = 0, prev_q_ = 0;
  double k_ = 0;       ///< the interval q_c was in at the last sample
  double k_last_ = 0;  ///< the level crossed last (its k); the start's level to begin with
  double prev_mean_ = SteadyStateSummary::kNaN;
  std::array<double, SteadyStateOptions::kMaxConsecutive> changes_{};
  int count_ = 0;  ///< changes held in changes_
};

}  // namespace mechgen::dynamics
