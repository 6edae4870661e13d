/**
 * \file analysis/flywheel_columns.h
 * The flywheel sizing's column table (table/columns.h): one row per sample of the machine's
 * cycle at its mean speed (machines/flywheel/machine_cycle.h's CyclePoint), the mean torque
 * line and, with --design, dT_req/d<p>. The flywheel command's energy-loop CSV is written from
 * it (analysis/flywheel.h); a study with `analysis: flywheel` reads its metrics from the same
 * columns by name (study/run.h). Apart from analysis/flywheel.h so that the study reads it
 * without the command.
 */
#pragma once

#include <string>
#include <vector>

#include "mechgen/core/constants.h"
#include "mechgen/machines/flywheel/machine_cycle.h"
#include "mechgen/table/columns.h"

namespace mechgen::analysis {

/// One row of the energy loop: a sample of the cycle and the mean torque line.
struct FlywheelLoopRow {
  flywheel::CyclePoint point;
  double T_mean = 0;
  const double* dT_req_dp = nullptr;  ///< --design: dT_req/dp_d for each design parameter
};

/// The energy loop's columns: theta, theta_deg, T_req, T_mean, E, T_static; with `dynamics`
/// T_inertia, T_speed, I; cond; then dT_req/d<p> for each name of `design` (the design
/// parameters, in the model's order: FlywheelLoopRow::dT_req_dp's).
inline table::Columns<FlywheelLoopRow> FlywheelLoopColumns(bool dynamics, const std::vector<std::string>& design) {
  using LoopRow = FlywheelLoopRow;
  table::Columns<LoopRow> columns;
  table::Builder<LoopRow> add(&columns);
  add.Number("theta", "rad", "input angle (CCW +), one cycle from theta0, the end not repeated",
             [](const LoopRow& r) { return r.point.theta; });
  add.Number("theta_deg", "deg", "the same in degrees",
             [](const LoopRow& r) { return mechgen::ToDegrees(r.point.theta); });
  add.Number("T_req", "N m",
             "driving torque a motor turning the input at the constant speed must apply (on the "
             "input link, CCW +): T_static + T_inertia + T_speed",
             [](const LoopRow& r) { return r.point.T_req; });
  add.Number("T_mean", "N m", "its mean over the cycle: the constant motor torque of a steady cycle",
             [](const LoopRow& r) { return r.T_mean; });
  add.Number("E", "J",
             "excess energy: the integral of T_mean - T_req from theta0 (the energy the flywheel "
             "stores; E_max - E_min = dE)",
             [](const LoopRow& r) { return r.point.E; });
  add.Number("T_static", "N m",
             "the statics part: loads, weights, springs and Coulomb friction for motion in +theta",
             [](const LoopRow& r) { return r.point.T_static; });
  if (dynamics) {
    add.Number("T_inertia", "N m", "the inertia torque 1/2 I'(theta) w^2 at the constant speed",
               [](const LoopRow& r) { return r.point.T_inertia; });
    add.Number("T_speed", "N m",
               "what the speed-dependent loads (dampers, viscous friction, speed tables) need at w",
               [](const LoopRow& r) { return r.point.T_speed; });
    add.Number("I", "kg m^2", "the machine's generalized inertia I(theta) about the input (no flywheel)",
               [](const LoopRow& r) { return r.point.I; });
  }
  add.Number("cond", "1", "cond_1(Phi_phi) of the configuration",
             [](const LoopRow& r) { return r.point.condition; });
  for (size_t d = 0; d < design.size(); ++d)
    add.Number("dT_req/d" + design[d], "N m per unit of " + design[d],
               "design sensitivity of T_req (cycle_design.h)",
               [d](const LoopRow& r) { return r.dT_req_dp[d]; });
  return columns;
}

}  // namespace mechgen::analysis
