/**
 * \file dynamics/witness/switches.h
 * The switch witness of the loads (dynamics/simulator.h): a `step`, `sign` or `mod` of a
 * load changing its branch. Its value is a decision, the vector of the loads' modes
 * (M::SwitchModes); after a step whose end has other modes than its start, the earliest
 * change is bracketed by bisection on that vector (LocateChange) to [ta, tb]: ta with the old
 * modes, tb with the new ones.
 */
#pragma once

#include <algorithm>

#include "mechgen/dynamics/witness/locate.h"

namespace mechgen::dynamics::witness {

/**
 * The earliest change of the modes in (t_start, t]: `modes_at(double t, Modes*)` (false: not
 * evaluated) on the dense output; modes_now at t_start, modes_end at t (different). *ta, *tb:
 * the bracket to `tolerance`, *modes_b: the modes at *tb. A mode of zero width at the switch
 * (sign(x) = 0 where x is 0 to the last bit): the modes one bracket further on are taken as
 * the new side's where they differ from both. false when the modes could not be evaluated.
 */
template <class Modes, class ModesAt>
bool LocateSwitch(double t_start, double t, double tolerance, const Modes& modes_now, const Modes& modes_end,
                  ModesAt&& modes_at, double* ta, double* tb, Modes* modes_b) {
  *ta = t_start;
  *tb = t;
  *modes_b = modes_end;
  const bool located = LocateChange(ta, tb, tolerance, [&](double tm) {
    Modes mm{};
    if (!modes_at(tm, &mm)) return Side::kFailed;
    if (mm == modes_now) return Side::kBefore;
    *modes_b = mm;
    return Side::kAfter;
  });
  if (located && *tb < t) {
    const double tc = std::min(t, *tb + (*tb - *ta));
    Modes mc{};
    if (modes_at(tc, &mc) && mc != *modes_b && mc != modes_now) {
      *tb = tc;
      *modes_b = mc;
    }
  }
  return located;
}

}  // namespace mechgen::dynamics::witness
