/**
 * \file sweep/columns.h
 * The one column table of a sweep: each column's name and the value it takes from a
 * SweepRecord are defined together, in SweepColumns<M>(). The CSV writer (io/csv.h) writes
 * every column; the printed table (io/table.h) prints the columns that have a table name,
 * so the two cannot drift apart. A new quantity is one Add() here.
 *
 * Columns, in order (q_j, phi_i the model's coordinate names, P the point names):
 *   q_j, phi_i, K_<phi_i>_<q_j>, L_<phi_i>_<q_j>_<q_k> (j <= k; L is symmetric in j, k),
 *   P.x, P.y, q_j_dot, q_j_ddot, phi_i_dot, phi_i_ddot, P.vx, P.vy, P.ax, P.ay,
 *   status, iterations, residual (||Phi||_inf), cond (cond_1 Phi_phi),
 *   sigma_min (smallest singular value of Phi_phi: the distance to singularity),
 *   singular_<phi_i> (its unit right singular vector: the singular direction),
 *   phi_error, K_error, L_error (the error bounds the conditioning implies: State),
 *   mu_<J> (the transmission angle at joint J of each four-bar loop on the ground, in
 *   [0, pi]; 0 or pi where that loop toggles; models with such loops only).
 * Values are in model units and radians; the printed table shows angle columns in degrees.
 * Building the table allocates (names, std::function); it runs after the sweep.
 */
#pragma once

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/sweep/sweep.h"

namespace mechgen {

/// One column of a sweep's output.
template <class M>
struct SweepColumn {
  /// The CSV header, e.g. "K_theta_coupler_theta_crank".
  std::string name;
  /// The header in the printed table (PrintTable), e.g. "K_theta_coupler"; empty: the column
  /// is in the CSV only.
  std::string table_name;
  /// The value is an angle in radians (printed in degrees in the table).
  bool angle = false;
  /// printf format of the value in the CSV ("%.12g" for positions and coefficients).
  const char* csv_format = "%.12g";
  /// The numeric value of the column in a record (NaN when the step failed).
  std::function<double(const SweepRecord<M>&)> value;
  /// For a text column (status, iterations): the cell itself; value is then unused.
  std::function<std::string(const SweepRecord<M>&)> text;
};

/**
 * \brief The column table of model M's sweeps (see the file comment for the order).
 * With one input, the table names of K and L carry the dependent variable only
 * ("K_phi"); with several, "K_phi/q" and "L_phi/q_j,q_k".
 */
template <class M>
std::vector<SweepColumn<M>> SweepColumns() {
  using F = ModelFeatures<M>;
  using R = SweepRecord<M>;
  std::vector<SweepColumn<M>> columns;
  auto add = [&columns](std::string name, std::string table_name, bool angle,
                        std::function<double(const R&)> value, const char* format = "%.12g") {
    SweepColumn<M> c;
    c.name = std::move(name);
    c.table_name = std::move(table_name);
    c.angle = angle;
    c.csv_format = format;
    c.value = std::move(value);
    columns.push_back(std::move(c));
  };
  auto add_text = [&columns](std::string name, std::string table_name,
                             std::function<std::string(const R&)> text) {
    SweepColumn<M> c;
    c.name = std::move(name);
    c.table_name = std::move(table_name);
    c.text = std::move(text);
    columns.push_back(std::move(c));
  };
  const bool one_input = M::kNq == 1;
  const std::string kPoint[2] = {".x", ".y"};

  // Positions and the coefficients: also in the printed table.
  for (int j = 0; j < M::kNq; ++j)
    add(M::kQNames[j], M::kQNames[j], M::kQIsAngle[j], [j](const R& r) { return r.q(j); });
  for (int i = 0; i < M::kNphi; ++i)
    add(M::kPhiNames[i], M::kPhiNames[i], M::kPhiIsAngle[i],
        [i](const R& r) { return r.state.phi(i); });
  for (int i = 0; i < M::kNphi; ++i)
    for (int j = 0; j < M::kNq; ++j)
      add(std::string("K_") + M::kPhiNames[i] + "_" + M::kQNames[j],
          std::string("K_") + M::kPhiNames[i] + (one_input ? "" : std::string("/") + M::kQNames[j]),
          false, [i, j](const R& r) { return r.state.K(i, j); });
  for (int i = 0; i < M::kNphi; ++i)
    for (int j = 0; j < M::kNq; ++j)
      for (int k = j; k < M::kNq; ++k)
        add(std::string("L_") + M::kPhiNames[i] + "_" + M::kQNames[j] + "_" + M::kQNames[k],
            std::string("L_") + M::kPhiNames[i] +
                (one_input ? "" : std::string("/") + M::kQNames[j] + "," + M::kQNames[k]),
            false, [i, j, k](const R& r) { return r.state.L(i, j + M::kNq * k); });
  if constexpr (F::kHasPoints) {
    for (int p = 0; p < M::kNumPoints; ++p)
      for (int a = 0; a < 2; ++a)
        add(M::kPointNames[p] + kPoint[a], M::kPointNames[p] + kPoint[a], false,
            [p, a](const R& r) { return r.state.r_P(a, p); });
  }
  // Velocities and accelerations: CSV only.
  for (int j = 0; j < M::kNq; ++j)
    add(std::string(M::kQNames[j]) + "_dot", "", false, [j](const R& r) { return r.motion.qd(j); });
  for (int j = 0; j < M::kNq; ++j)
    add(std::string(M::kQNames[j]) + "_ddot", "", false,
        [j](const R& r) { return r.motion.qdd(j); });
  for (int i = 0; i < M::kNphi; ++i)
    add(std::string(M::kPhiNames[i]) + "_dot", "", false,
        [i](const R& r) { return r.motion.phid(i); });
  for (int i = 0; i < M::kNphi; ++i)
    add(std::string(M::kPhiNames[i]) + "_ddot", "", false,
        [i](const R& r) { return r.motion.phidd(i); });
  if constexpr (F::kHasPointVelocities) {
    const std::string kVelocity[2] = {".vx", ".vy"};
    for (int p = 0; p < M::kNumPoints; ++p)
      for (int a = 0; a < 2; ++a)
        add(M::kPointNames[p] + kVelocity[a], "", false,
            [p, a](const R& r) { return r.motion.v_P(a, p); });
  }
  if constexpr (F::kHasPointAccelerations) {
    const std::string kAcceleration[2] = {".ax", ".ay"};
    for (int p = 0; p < M::kNumPoints; ++p)
      for (int a = 0; a < 2; ++a)
        add(M::kPointNames[p] + kAcceleration[a], "", false,
            [p, a](const R& r) { return r.motion.a_P(a, p); });
  }
  // How the step went; the status also in the printed table.
  add_text("status", "status",
           [](const R& r) { return std::string(position::ToString(r.summary.status)); });
  add_text("iterations", "", [](const R& r) { return std::to_string(r.summary.iterations); });
  add("residual", "", false, [](const R& r) { return r.summary.residual_norm; }, "%.3g");
  add("cond", "", false, [](const R& r) { return r.summary.condition; }, "%.6g");
  add("sigma_min", "", false, [](const R& r) { return r.state.sigma_min; }, "%.6g");
  for (int i = 0; i < M::kNphi; ++i)
    add(std::string("singular_") + M::kPhiNames[i], "", false,
        [i](const R& r) { return r.state.singular_direction(i); }, "%.6g");
  // How far the row's values may be from the exact ones (State::phi_error, K_error,
  // L_error: eps cond, eps cond^2, eps cond^3 next to a singular configuration).
  add("phi_error", "", false, [](const R& r) { return r.state.phi_error; }, "%.3g");
  add("K_error", "", false, [](const R& r) { return r.state.K_error; }, "%.3g");
  add("L_error", "", false, [](const R& r) { return r.state.L_error; }, "%.3g");
  if constexpr (SweepRecord<M>::kNumMu > 0) {
    for (int t = 0; t < SweepRecord<M>::kNumMu; ++t)
      add(std::string("mu_") + M::kTransmissionJoints[t], "", false,
          [t](const R& r) { return r.mu(t); });
  }
  return columns;
}

/**
 * \brief The first column name that occurs twice in `columns`, or "" when all are unique.
 * The generator rejects models whose names would collide (a link `rocker_dot` next to a
 * link `rocker`: `theta_rocker_dot` twice); the tools check again at startup, so that a
 * header from an older generator or written by hand cannot produce an ambiguous CSV.
 */
template <class M>
std::string DuplicateColumnName(const std::vector<SweepColumn<M>>& columns) {
  std::vector<const std::string*> names;
  names.reserve(columns.size());
  for (const SweepColumn<M>& c : columns) names.push_back(&c.name);
  std::sort(names.begin(), names.end(),
            [](const std::string* a, const std::string* b) { return *a < *b; });
  for (size_t i = 1; i < names.size(); ++i)
    if (*names[i] == *names[i - 1]) return *names[i];
  return "";
}

}  // namespace mechgen
