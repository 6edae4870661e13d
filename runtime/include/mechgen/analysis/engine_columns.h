/**
 * \file analysis/engine_columns.h
 * The engine command's column tables (table/columns.h): the cycle at constant speed (one row
 * per crank angle, machines/engine/cycle.h's CrankPoint) and the energy loop of T_total about
 * its mean (the flywheel's loop CSV). The command writes its CSVs from them
 * (analysis/engine.h); a study with `analysis: engine` reads its metrics from the same columns
 * by name (study/run.h). Apart from analysis/engine.h so that the study reads them without the
 * command.
 */
#pragma once

#include <cmath>
#include <string>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/machines/engine/cycle.h"
#include "mechgen/table/columns.h"

namespace mechgen::analysis {

/// The cycle CSV's columns (one row per crank angle; tools/engine_main.cc for the columns and
/// signs): the torques, each cylinder's gauge pressure and wall thrust, the main bearing, the
/// crank pins and wrist pins, with the model's shaking outputs the shaking force, moment and
/// rocking couple. `e`: the engine read from the model (ReadEngine: its cylinders, reactions).
template <class M>
table::Columns<engine::CrankPoint<M>> EngineCycleColumns(const M& model, const engine::Engine& e) {
  using Point = engine::CrankPoint<M>;
  table::Columns<Point> columns;
  table::Builder<Point> add(&columns);
  add.Number("theta_deg", "deg", "crank angle", [](const Point& pt) { return mechgen::ToDegrees(pt.theta); });
  add.Number("T_gas", "N m", "gas torque on the crank, CCW +",
             [](const Point& pt) { return pt.T_gas; });
  add.Number("T_inertia", "N m", "inertia torque -1/2 I'(theta) omega^2 on the crank, CCW +",
             [](const Point& pt) { return pt.T_inertia; });
  add.Number("T_total", "N m", "T_gas + T_inertia, CCW +",
             [](const Point& pt) { return pt.T_total; });
  for (int j = 0; j < e.n; ++j) {
    const std::string k = std::to_string(j + 1);
    add.Number("p_" + k, "Pa", "gauge gas pressure of cylinder " + k,
               [j](const Point& pt) { return pt.p[j]; });
    add.Number("thrust_" + k, "N",
               "force of piston " + k + " on the cylinder wall along n = (-sin beta, cos beta)",
               [j](const Point& pt) { return pt.thrust[j]; });
  }
  const int R_O = e.R_O;
  add.Number("F_O_x", "N", "main bearing: force of the frame on the crank, x",
             [R_O](const Point& pt) { return pt.R[R_O]; });
  add.Number("F_O_y", "N", "main bearing: force of the frame on the crank, y",
             [R_O](const Point& pt) { return pt.R[R_O + 1]; });
  for (int j = 0; j < e.n; ++j) {
    const std::string k = std::to_string(j + 1);
    const int B = e.R_B[j], C = e.R_C[j];
    const double gamma = e.gamma[j];
    // rod on crank = -(crank on rod), in the crank's frame (u along the throw).
    auto u = [B, gamma](const Point& pt) {
      const double a = pt.theta + gamma;
      return -(pt.R[B] * std::cos(a) + pt.R[B + 1] * std::sin(a));
    };
    auto v = [B, gamma](const Point& pt) {
      const double a = pt.theta + gamma;
      return -(-pt.R[B] * std::sin(a) + pt.R[B + 1] * std::cos(a));
    };
    add.Number("pin_" + k + "_x", "N", "crank pin: force of the crank on rod " + k + ", x",
               [B](const Point& pt) { return pt.R[B]; });
    add.Number("pin_" + k + "_y", "N", "crank pin: force of the crank on rod " + k + ", y",
               [B](const Point& pt) { return pt.R[B + 1]; });
    add.Number("pin_" + k + "_u", "N",
               "force of rod " + k + " on the crank pin along the throw, outward", u);
    add.Number("pin_" + k + "_v", "N",
               "force of rod " + k + " on the crank pin 90 deg ahead of the throw", v);
    add.Number("wrist_" + k + "_x", "N", "wrist pin: force of rod " + k + " on the piston, x",
               [C](const Point& pt) { return pt.R[C]; });
    add.Number("wrist_" + k + "_y", "N", "wrist pin: force of rod " + k + " on the piston, y",
               [C](const Point& pt) { return pt.R[C + 1]; });
  }
  if (ModelCalls<M>::HasShaking(model)) {
    add.Number("shake_F_x", "N", "shaking force on the frame -sum m a_G, x",
               [](const Point& pt) { return pt.shake_x; });
    add.Number("shake_F_y", "N", "shaking force on the frame -sum m a_G, y",
               [](const Point& pt) { return pt.shake_y; });
    add.Number("shake_M", "N m", "shaking moment on the frame about O, CCW +",
               [](const Point& pt) { return pt.shake_M; });
    add.Number("M_rock_x", "N m",
               "rocking couple on the frame about the cylinders' middle, x (z along the shaft)",
               [](const Point& pt) { return pt.rock_x; });
    add.Number("M_rock_y", "N m", "rocking couple on the frame about the cylinders' middle, y",
               [](const Point& pt) { return pt.rock_y; });
  }
  return columns;
}

/// One row of the energy loop CSV: a crank angle, T_total there, its mean and E.
struct EngineLoopRow {
  double theta = 0, T_total = 0, T_mean = 0, E = 0;
};
inline table::Columns<EngineLoopRow> EngineLoopColumns() {
  using LoopRow = EngineLoopRow;
  table::Columns<LoopRow> columns;
  table::Builder<LoopRow> add(&columns);
  add.Number("theta_deg", "deg", "crank angle", [](const LoopRow& r) { return mechgen::ToDegrees(r.theta); });
  add.Number("T_total", "N m", "crank torque at constant speed, CCW +",
             [](const LoopRow& r) { return r.T_total; });
  add.Number("T_mean", "N m", "its mean (the load)", [](const LoopRow& r) { return r.T_mean; });
  add.Number("E", "J", "excess energy: the integral of T_total - T_mean from theta = 0",
             [](const LoopRow& r) { return r.E; });
  return columns;
}

}  // namespace mechgen::analysis
