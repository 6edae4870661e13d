/**
 * \file sweep/motion_summary.h
 * The motion summary of a one-input sweep: what a machine designer reads off a cam chart or
 * a displacement diagram, for every dependent coordinate of the model (a slide s_<joint>: a
 * slider's or a slot's translation; an angle theta_<link>: a rocker's or a coupler's):
 *  - its extreme positions (min, max) and the input values where they occur, and the stroke
 *    (max - min; the swing of an angle);
 *  - for a sweep over one full turn of an angle input (a constant-speed crank), the input
 *    intervals over which the coordinate rises (min -> max, in the sweep's direction) and
 *    falls (max -> min), and the time ratio: the longer over the shorter (the quick-return
 *    ratio, >= 1), when the coordinate has exactly one maximum and one minimum per turn;
 *  - an angle that turns fully (a crank, a coupler of a double crank) is said so, without
 *    extremes;
 *  - the range of each transmission angle mu_<J> the model has (sampled at the rows).
 * Extremes between two rows, where the velocity coefficient K = d phi/d q changes sign, are
 * refined: the root of the cubic (Hermite) through both rows' K and L = dK/dq between them
 * (O(h^4) for a row spacing h), and there the quintic through both rows' phi, K and L
 * (O(h^6)). The extremes at the ends of a range
 * that is not a full turn are the end rows.
 * MotionSummaryBuilder<M> takes the rows as a sweep streams them (SweepRows()), keeping one
 * row per coordinate; Finish() gives the MotionSummary, PrintMotionSummary() prints it with
 * units (the model's length units; angles in rad and deg). Allocation: the coordinate list,
 * once, and Finish().
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "mechgen/core/constants.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen {

/// A value of a coordinate and the input where it occurs.
struct SweepExtreme {
  double value = std::numeric_limits<double>::quiet_NaN();
  double q = std::numeric_limits<double>::quiet_NaN();
  bool refined = false;  ///< between two rows (K changed sign), not a row's own value
};

/// The motion of one dependent coordinate over a sweep.
struct CoordinateMotion {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string name;
  bool is_angle = false;
  bool turns_fully = false;  ///< an angle that makes full turns (no extremes)
  SweepExtreme min, max;
  int maxima = 0, minima = 0;  ///< turning points (K changes sign), ends of a full turn included
  /// Full turn of the input with one maximum and one minimum: the input interval from the
  /// minimum to the maximum (in the sweep's direction) and back, and their ratio (the
  /// longer over the shorter, >= 1). NaN otherwise.
  double rising = kNaN, falling = kNaN, time_ratio = kNaN;
  /// Full turn of the input: the change of a coordinate that does not come back (a slide
  /// or an angle that is not periodic in one turn: a planetary's arm, a contour parameter);
  /// 0 otherwise.
  double net_change = 0;
  double stroke() const { return max.value - min.value; }
};

/// The range of a transmission angle over the sweep (rows only).
struct TransmissionRange {
  std::string name;
  SweepExtreme min, max;
};

struct MotionSummary {
  bool one_input = false;     ///< a one-input model (else nothing is summarized)
  std::string input_name;
  bool input_is_angle = false;
  double q_begin = 0, q_end = 0;
  bool full_turn = false;     ///< an angle input over exactly one turn
  int rows = 0, failed = 0;   ///< rows seen; rows that did not converge (not summarized)
  std::vector<CoordinateMotion> coordinates;
  std::vector<TransmissionRange> transmission;
};

namespace internal {

// The extreme between two rows (q0, y0, k0, l0) and (q1, y1, k1, l1) (k = dy/dq, l = dk/dq)
// where k0 and k1 have opposite signs (or one is 0): where the cubic Hermite interpolant of k
// (through k0, l0 and k1, l1) vanishes (by bisection: it changes sign on [q0, q1]), O(h^4)
// for a row spacing h, and the quintic Hermite interpolant of y (through y, k, l at both
// rows) there, O(h^6) (the cubic through y, k without l: O(h^4)).
inline SweepExtreme HermiteExtreme(double q0, double y0, double k0, double l0, double q1,
                                   double y1, double k1, double l1) {
  const double h = q1 - q0;
  auto hermite = [h](double t, double a0, double d0, double a1, double d1) {
    const double t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * a0 + (t3 - 2 * t2 + t) * h * d0 + (-2 * t3 + 3 * t2) * a1 +
           (t3 - t2) * h * d1;
  };
  double t = 0;
  if (k0 == 0) {
    t = 0;
  } else if (k1 == 0) {
    t = 1;
  } else if (std::isfinite(l0) && std::isfinite(l1)) {
    double lo = 0, hi = 1;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      const double k = hermite(mid, k0, l0, k1, l1);
      if ((k > 0) == (k0 > 0) && k != 0) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
    t = 0.5 * (lo + hi);
  } else {  // no L: where the linear interpolant of k vanishes
    t = k0 / (k0 - k1);
  }
  SweepExtreme e;
  if (std::isfinite(l0) && std::isfinite(l1)) {
    // The quintic Hermite interpolant of y through y, k = y' and l = y'' at both rows.
    const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
    e.value = (1 - 10 * t3 + 15 * t4 - 6 * t5) * y0 + (t - 6 * t3 + 8 * t4 - 3 * t5) * h * k0 +
              0.5 * (t2 - 3 * t3 + 3 * t4 - t5) * h * h * l0 +
              0.5 * (t3 - 2 * t4 + t5) * h * h * l1 + (-4 * t3 + 7 * t4 - 3 * t5) * h * k1 +
              (10 * t3 - 15 * t4 + 6 * t5) * y1;
  } else {
    e.value = hermite(t, y0, k0, y1, k1);
  }
  e.q = q0 + t * h;
  e.refined = t > 0 && t < 1;
  return e;
}

}  // namespace internal

/// Collects a one-input sweep's rows (in order) into its MotionSummary.
/// For a model of several inputs it collects nothing (MotionSummary::one_input false).
template <class M>
class MotionSummaryBuilder {
 public:
  /// q_begin, q_end: the sweep's range of the (first) input. model: the solver's (an empty
  /// tag for a generated M).
  MotionSummaryBuilder(double q_begin, double q_end, const M& model = M()) {
    using C = ModelCalls<M>;
    nphi_ = C::Nphi(model);
    s_.one_input = C::Nq(model) == 1;
    s_.input_name = C::QName(model, 0);
    s_.input_is_angle = C::QIsAngle(model, 0);
    s_.q_begin = q_begin;
    s_.q_end = q_end;
    s_.full_turn = s_.input_is_angle && std::abs(std::abs(q_end - q_begin) - 2 * kPi) <= 1e-9;
    s_.coordinates.resize(static_cast<size_t>(nphi_));
    for (int i = 0; i < nphi_; ++i) {
      s_.coordinates[static_cast<size_t>(i)].name = C::PhiName(model, i);
      s_.coordinates[static_cast<size_t>(i)].is_angle = C::PhiIsAngle(model, i);
    }
    for (int t = 0; t < C::NumTransmissionAngles(model); ++t) {
      TransmissionRange range;
      range.name = std::string("mu_") + C::TransmissionJoint(model, t);
      s_.transmission.push_back(range);
    }
    first_.resize(static_cast<size_t>(nphi_));
    prev_.resize(static_cast<size_t>(nphi_));
  }

  /// The next row of the sweep. A row that did not converge breaks the chain (no extreme is
  /// looked for across it).
  void Add(const SweepRecord<M>& r) {
    if (!s_.one_input) return;
    ++s_.rows;
    if (r.summary.status != position::Status::kConverged || !r.state.valid) {
      ++s_.failed;
      have_prev_ = false;
      return;
    }
    const double q = r.state.q(0);
    for (int i = 0; i < nphi_; ++i) {
      const size_t k = static_cast<size_t>(i);
      Sample now{q, r.state.phi(i), r.state.K(i, 0), r.state.L(i, 0)};
      // K within its error bound of zero (and of rounding) is zero: a turning point on a row
      // (at the ends of a full turn: the same configuration twice) counts once, on the
      // interval it ends, whatever the sign of the noise.
      if (std::abs(now.k) <= r.state.K_error + 8 * kEps * (1 + std::abs(now.y))) now.k = 0;
      CoordinateMotion& c = s_.coordinates[k];
      if (s_.rows == 1) first_[k] = now;
      if (have_prev_) {
        const Sample& p = prev_[k];
        // Turning points between the rows, by the sign of dphi/dq along the sweep (a zero at
        // a row is counted once: on the interval it ends).
        const double dir = q >= p.q ? 1 : -1;
        const double k0 = dir * p.k, k1 = dir * now.k;
        if ((k0 > 0 && k1 <= 0) || (k0 < 0 && k1 >= 0)) {
          const SweepExtreme e =
              internal::HermiteExtreme(p.q, p.y, p.k, p.l, now.q, now.y, now.k, now.l);
          if (k0 > 0) {
            ++c.maxima;
            last_max_[k] = e.q;
            Consider(e, &c);
          } else {
            ++c.minima;
            last_min_[k] = e.q;
            Consider(e, &c);
          }
        }
      }
      Consider(SweepExtreme{now.y, q, false}, &c);
      prev_[k] = now;
    }
    for (size_t t = 0; t < s_.transmission.size(); ++t) {
      Consider(SweepExtreme{r.mu(static_cast<int>(t)), q, false}, &s_.transmission[t]);
    }
    have_prev_ = true;
  }

  /// The summary of the rows added so far.
  MotionSummary Finish() const {
    MotionSummary s = s_;
    if (!s.one_input) return s;
    const double span = std::abs(s.q_end - s.q_begin);
    for (size_t k = 0; k < s.coordinates.size(); ++k) {
      CoordinateMotion& c = s.coordinates[k];
      const double net = prev_[k].y - first_[k].y;  // over the sweep (a full turn: 0 or 2 pi n)
      if (c.is_angle && (c.stroke() >= 2 * kPi - 1e-9 ||
                         (s.full_turn && s.failed == 0 && std::abs(net) > kPi))) {
        c.turns_fully = true;
        c.min = c.max = SweepExtreme();
        continue;
      }
      if (s.full_turn && s.failed == 0 &&
          std::abs(net) > 1e-9 * (1 + std::abs(first_[k].y))) {
        c.net_change = net;  // does not come back in one turn of the input
        continue;
      }
      if (s.full_turn && s.failed == 0 && c.maxima == 1 && c.minima == 1) {
        const double dir = s.q_end >= s.q_begin ? 1 : -1;
        double rise = std::fmod(dir * (last_max_.at(k) - last_min_.at(k)), span);
        if (rise < 0) rise += span;
        c.rising = rise;
        c.falling = span - rise;
        c.time_ratio = std::max(c.rising, c.falling) / std::min(c.rising, c.falling);
      }
    }
    return s;
  }

 private:
  static constexpr double kPi = 3.14159265358979323846;
  static constexpr double kEps = std::numeric_limits<double>::epsilon();
  struct Sample {
    double q = 0, y = 0, k = 0, l = 0;  // input, coordinate, K, L (dK/dq)
  };
  template <class Range>
  static void Consider(const SweepExtreme& e, Range* r) {
    if (!std::isfinite(e.value)) return;
    if (!(r->min.value <= e.value)) r->min = e;
    if (!(r->max.value >= e.value)) r->max = e;
  }

  MotionSummary s_;
  std::vector<Sample> first_, prev_;
  int nphi_ = 0;
  std::array<double, ModelTypes<M>::kMaxPhi> last_max_{}, last_min_{};
  bool have_prev_ = false;
};

/// Prints the summary (nothing for a model of several inputs): one block per coordinate, then
/// the transmission angles. Lengths in the
/// model's length units, angles in rad and deg, inputs as the sweep's table shows them (deg
/// for an angle).
inline void PrintMotionSummary(const MotionSummary& s, std::ostream& out) {
  if (!s.one_input) return;
  char buffer[512];
  auto input = [&](double q) {
    char b[64];
    if (s.input_is_angle) {
      std::snprintf(b, sizeof(b), "%s = %.6f deg", s.input_name.c_str(), ToDegrees(q));
    } else {
      std::snprintf(b, sizeof(b), "%s = %.9g", s.input_name.c_str(), q);
    }
    return std::string(b);
  };
  auto value = [&](double v, bool angle) {
    char b[96];
    if (angle) {
      std::snprintf(b, sizeof(b), "%.12g rad (%.6f deg)", v, ToDegrees(v));
    } else {
      std::snprintf(b, sizeof(b), "%.12g", v);
    }
    return std::string(b);
  };
  auto interval = [&](double dq) {
    char b[64];
    if (s.input_is_angle) {
      std::snprintf(b, sizeof(b), "%.6f deg", ToDegrees(dq));
    } else {
      std::snprintf(b, sizeof(b), "%.9g", dq);
    }
    return std::string(b);
  };
  out << "motion summary (" << (s.full_turn ? "one full turn of " : "over the range of ")
      << s.input_name << "; lengths in model units; extremes between rows refined where the "
      << "cubic through the rows' K = dphi/d" << s.input_name << " and L = dK/d" << s.input_name
      << " vanishes)";
  if (s.failed > 0) out << ": " << s.failed << " row(s) did not converge and are left out";
  out << "\n";
  if (s.coordinates.empty()) out << "  no dependent coordinate (no closed loop)\n";
  for (const CoordinateMotion& c : s.coordinates) {
    if (c.turns_fully) {
      out << "  " << c.name << ": turns fully\n";
      continue;
    }
    if (!std::isfinite(c.min.value)) {
      out << "  " << c.name << ": no converged row\n";
      continue;
    }
    const char* kind = c.is_angle ? "swing" : "stroke";
    out << "  " << c.name << " (" << (c.is_angle ? "angle" : "slide") << "): " << kind << " "
        << value(c.stroke(), c.is_angle) << "\n";
    out << "    min " << value(c.min.value, c.is_angle) << " at " << input(c.min.q) << "\n";
    out << "    max " << value(c.max.value, c.is_angle) << " at " << input(c.max.q) << "\n";
    if (std::isfinite(c.time_ratio)) {
      std::snprintf(buffer, sizeof(buffer), "%.9g", c.time_ratio);
      out << "    rises over " << interval(c.rising) << " of " << s.input_name << ", falls over "
          << interval(c.falling) << ": time ratio " << buffer << "\n";
    } else if (c.net_change != 0) {
      out << "    does not come back in one turn of " << s.input_name << " (changes by "
          << value(c.net_change, c.is_angle) << ")\n";
    } else if (s.full_turn && s.failed == 0 && c.maxima + c.minima > 0) {
      out << "    " << c.maxima << " maxima and " << c.minima
          << " minima per turn: no single time ratio\n";
    }
  }
  for (const TransmissionRange& t : s.transmission) {
    if (!std::isfinite(t.min.value)) continue;
    out << "  transmission angle " << t.name << " (sampled at the rows): min "
        << value(t.min.value, true) << " at " << input(t.min.q) << ", max "
        << value(t.max.value, true) << " at " << input(t.max.q) << "\n";
  }
}

}  // namespace mechgen
