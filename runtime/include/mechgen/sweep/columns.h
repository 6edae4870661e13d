/**
 * \file sweep/columns.h
 * The columns of a sweep (table/columns.h: name, unit, meaning and the value taken from a
 * SweepRecord, defined together) in SweepColumns<M>(); the CSV writer (io/csv.h) writes
 * every column, the printed table (io/table.h) the columns that have a table name, so the
 * two cannot drift apart. A new quantity is one column here. WriteCsv(), PrintTable() and
 * the rest below apply the one writer and printer to a sweep's records.
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
 * DesignColumns<M>() (a model with a design section, the sweep's --design) adds, for each
 * design parameter p: d<phi_i>/d<p>, dK_<phi_i>_<q_j>/d<p>, d<P>.x/d<p>, d<P>.y/d<p>,
 * dmu_<J>/d<p>.
 * Values are in model units and radians, every number written to round-trip (io/format.h,
 * FormatRoundTrip); the printed table shows angle columns in degrees. A failed step's
 * values are "nan". Building the table allocates (names, std::function); it runs after the
 * sweep.
 */
#pragma once

#include <initializer_list>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mechgen/io/csv.h"
#include "mechgen/io/table.h"
#include "mechgen/sweep/sweep.h"
#include "mechgen/table/columns.h"

namespace mechgen {

/// One column of a sweep's output.
template <class M>
using SweepColumn = table::Column<SweepRecord<M>>;

using table::DuplicateColumnName;

/**
 * \brief The design-sensitivity columns of model M (a design section: ModelCalls<M>::HasDesign),
 *        appended to *columns: for each design parameter p (kDesignNames) the derivatives of the
 *        dependent coordinates, of K (with K), of the points (with points) and of the
 *        transmission angles (with them), q held. CSV only; NaN where the step failed
 *        (SweepRecord::design). Nothing for a model without a design section.
 */
template <class M>
void AppendDesignColumns(const M& model, std::vector<SweepColumn<M>>* columns) {
  using C = ModelCalls<M>;  // (sizes and names: constant for a generated M, the view's for a ViewModel)
  using F = ModelFeatures<M>;
  if constexpr (HasDesignDerivatives<M>::value) {
    if (!C::HasDesign(model)) return;
    using R = SweepRecord<M>;
    table::Builder<R> add(columns);
    const int nq = C::Nq(model), nphi = C::Nphi(model);
    auto per = [&model](bool angle, int d) {
      return std::string(angle ? "rad" : "model length") + " per unit of " + C::DesignName(model, d);
    };
    for (int d = 0; d < C::NumDesign(model); ++d) {
      const std::string p = C::DesignName(model, d);
      for (int i = 0; i < nphi; ++i)
        add.Number("d" + std::string(C::PhiName(model, i)) + "/d" + p, per(C::PhiIsAngle(model, i), d),
                   "sensitivity of the dependent coordinate to the design parameter (q held)",
                   [i, d](const R& r) { return r.design.dphi_dp(i, d); })
            .angle = false;
      if constexpr (F::kHasK) {  // (dK_dp: a model with K)
        if (C::HasK(model))
          for (int i = 0; i < nphi; ++i)
            for (int j = 0; j < nq; ++j)
              add.Number("dK_" + std::string(C::PhiName(model, i)) + "_" + C::QName(model, j) + "/d" + p,
                         "K's unit per unit of " + p, "sensitivity of the first-order coefficient dphi/dq",
                         [i, j, d, nq](const R& r) { return r.design.dK_dp(i, j + nq * d); })
                  .angle = false;
      }
      if constexpr (F::kHasPoints) {  // (dr_P_dp: a model with points)
        if (C::HasPoints(model))
          for (int m = 0; m < C::NumPoints(model); ++m)
            for (int a = 0; a < 2; ++a)
              add.Number("d" + std::string(C::PointName(model, m)) + (a ? ".y" : ".x") + "/d" + p,
                         "model length per unit of " + p, "sensitivity of the point in the fixed frame",
                         [m, a, d](const R& r) { return r.design.dr_P_dp(2 * m + a, d); });
      }
      if constexpr (F::kNumTransmissionAngles != 0) {  // (dmu_dp: a model with transmission angles)
        for (int i = 0; i < C::NumTransmissionAngles(model); ++i)
          add.Number("dmu_" + std::string(C::TransmissionJoint(model, i)) + "/d" + p, "rad per unit of " + p,
                     "sensitivity of the transmission angle (q held)",
                     [i, d](const R& r) { return r.design.dmu_dp(i, d); })
              .angle = false;
      }
    }
  } else {
    (void)model, (void)columns;
  }
}
/// AppendDesignColumns of a generated model M (its empty tag).
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
void AppendDesignColumns(std::vector<SweepColumn<M>>* columns) {
  AppendDesignColumns<M>(M(), columns);
}

/**
 * \brief The column table of model M's sweeps (see the file comment for the order).
 * With one input, the table names of K and L carry the dependent variable only
 * ("K_phi"); with several, "K_phi/q" and "L_phi/q_j,q_k".
 */
template <class M>
std::vector<SweepColumn<M>> SweepColumns(const M& model = M()) {
  using F = ModelFeatures<M>;
  using C = ModelCalls<M>;  // (sizes and names: constant for a generated M, the view's for a ViewModel)
  const int nq = C::Nq(model), nphi = C::Nphi(model), np = C::NumPoints(model);
  using R = SweepRecord<M>;
  std::vector<SweepColumn<M>> columns;
  table::Builder<R> add(&columns);
  const bool one_input = nq == 1;
  auto unit = [](bool angle, const char* per_second = "") {
    return std::string(angle ? "rad" : "model length") + per_second;
  };
  // The unit of a coefficient d^n phi_i / dq^n: phi_i's unit over the inputs' units.
  auto ratio = [&model](int i, std::initializer_list<int> inputs) {
    std::string u = C::PhiIsAngle(model, i) ? "rad" : "model length";
    for (int j : inputs) u += std::string("/") + (C::QIsAngle(model, j) ? "rad" : "model length");
    return u;
  };
  const std::string kAxis[2] = {"x", "y"};

  // Positions and the coefficients: also in the printed table.
  for (int j = 0; j < nq; ++j)
    table::Shown(add.Number(C::QName(model, j), unit(C::QIsAngle(model, j)), "input (driven coordinate)",
                            [j](const R& r) { return r.q(j); }),
                 C::QName(model, j));
  for (int i = 0; i < nphi; ++i)
    table::Shown(add.Number(C::PhiName(model, i), unit(C::PhiIsAngle(model, i)),
                            "dependent coordinate (angles CCW + from the x axis)",
                            [i](const R& r) { return r.state.phi(i); }),
                 C::PhiName(model, i));
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j)
      table::Shown(add.Number(std::string("K_") + C::PhiName(model, i) + "_" + C::QName(model, j),
                              ratio(i, {j}), "first-order coefficient dphi/dq",
                              [i, j](const R& r) { return r.state.K(i, j); }),
                   std::string("K_") + C::PhiName(model, i) +
                       (one_input ? "" : std::string("/") + C::QName(model, j)))
          .angle = false;
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j)
      for (int k = j; k < nq; ++k)
        table::Shown(
            add.Number(std::string("L_") + C::PhiName(model, i) + "_" + C::QName(model, j) + "_" +
                           C::QName(model, k),
                       ratio(i, {j, k}), "second-order coefficient d2phi/dq_j dq_k",
                       [i, j, k, nq](const R& r) { return r.state.L(i, j + nq * k); }),
            std::string("L_") + C::PhiName(model, i) +
                (one_input ? "" : std::string("/") + C::QName(model, j) + "," + C::QName(model, k)))
            .angle = false;
  if constexpr (F::kHasPoints) {
    if (C::HasPoints(model))
      for (int p = 0; p < np; ++p)
        for (int a = 0; a < 2; ++a)
          table::Shown(add.Number(std::string(C::PointName(model, p)) + "." + kAxis[a], "model length",
                                  "point " + kAxis[a] + " in the fixed frame",
                                  [p, a](const R& r) { return r.state.r_P(a, p); }),
                       std::string(C::PointName(model, p)) + "." + kAxis[a]);
  }
  // Velocities and accelerations: CSV only.
  for (int j = 0; j < nq; ++j)
    add.Number(std::string(C::QName(model, j)) + "_dot", unit(C::QIsAngle(model, j), "/s"),
               "input speed (given)", [j](const R& r) { return r.motion.qd(j); })
        .angle = false;
  for (int j = 0; j < nq; ++j)
    add.Number(std::string(C::QName(model, j)) + "_ddot", unit(C::QIsAngle(model, j), "/s^2"),
               "input acceleration (given)", [j](const R& r) { return r.motion.qdd(j); })
        .angle = false;
  for (int i = 0; i < nphi; ++i)
    add.Number(std::string(C::PhiName(model, i)) + "_dot", unit(C::PhiIsAngle(model, i), "/s"),
               "dependent velocity K qd", [i](const R& r) { return r.motion.phid(i); })
        .angle = false;
  for (int i = 0; i < nphi; ++i)
    add.Number(std::string(C::PhiName(model, i)) + "_ddot", unit(C::PhiIsAngle(model, i), "/s^2"),
               "dependent acceleration K qdd + qd' L qd",
               [i](const R& r) { return r.motion.phidd(i); })
        .angle = false;
  if constexpr (F::kHasPointVelocities) {
    if (C::HasPointVelocities(model))
      for (int p = 0; p < np; ++p)
        for (int a = 0; a < 2; ++a)
          add.Number(std::string(C::PointName(model, p)) + ".v" + kAxis[a], "model length/s",
                     "point velocity, fixed frame", [p, a](const R& r) { return r.motion.v_P(a, p); });
  }
  if constexpr (F::kHasPointAccelerations) {
    if (C::HasPointAccelerations(model))
      for (int p = 0; p < np; ++p)
        for (int a = 0; a < 2; ++a)
          add.Number(std::string(C::PointName(model, p)) + ".a" + kAxis[a], "model length/s^2",
                     "point acceleration, fixed frame",
                     [p, a](const R& r) { return r.motion.a_P(a, p); });
  }
  // How the step went; the status also in the printed table.
  table::Shown(add.Text("status", "the position step's status (converged, or why not)",
                        [](const R& r) { return std::string(position::ToString(r.summary.status)); }),
               "status");
  add.Text("iterations", "Newton iterations of the step",
           [](const R& r) { return std::to_string(r.summary.iterations); });
  add.Number("residual", "model length", "||Phi||_inf at the solution",
             [](const R& r) { return r.summary.residual_norm; });
  add.Number("cond", "1", "cond_1 Phi_phi", [](const R& r) { return r.summary.condition; });
  add.Number("sigma_min", "1", "smallest singular value of Phi_phi (distance to singularity)",
             [](const R& r) { return r.state.sigma_min; });
  for (int i = 0; i < nphi; ++i)
    add.Number(std::string("singular_") + C::PhiName(model, i), "1",
               "unit right singular vector of sigma_min (the singular direction)",
               [i](const R& r) { return r.state.singular_direction(i); });
  // How far the row's values may be from the exact ones (State::phi_error, K_error,
  // L_error: eps cond, eps cond^2, eps cond^3 next to a singular configuration).
  add.Number("phi_error", "1", "relative error bound of phi (eps cond)",
             [](const R& r) { return r.state.phi_error; });
  add.Number("K_error", "1", "relative error bound of K (eps cond^2)",
             [](const R& r) { return r.state.K_error; });
  add.Number("L_error", "1", "relative error bound of L (eps cond^3)",
             [](const R& r) { return r.state.L_error; });
  if constexpr (SweepRecord<M>::kNumMu != 0) {
    for (int t = 0; t < C::NumTransmissionAngles(model); ++t)
      add.Number(std::string("mu_") + C::TransmissionJoint(model, t), "rad",
                 "transmission angle at the joint, in [0, pi]",
                 [t](const R& r) { return r.mu(t); });
  }
  return columns;
}

/// The CSV header: the names of SweepColumns<M>(), in order.
template <class M>
std::vector<std::string> CsvColumns() {
  return table::ColumnNames(SweepColumns<M>());
}

/// The CSV cells of one record, in the order of CsvColumns().
template <class M>
std::vector<std::string> CsvValues(const SweepRecord<M>& r) {
  std::vector<std::string> cells;
  for (const SweepColumn<M>& c : SweepColumns<M>()) cells.push_back(CsvCell(c, r));
  return cells;
}

/// The sign convention of a sweep's CSV (its first comment line, io/csv.h CsvAbout()).
inline constexpr const char* kSweepSigns =
    "angles CCW + from the fixed x axis; points, velocities and accelerations in the fixed "
    "frame; K = d phi/d q, L = d2 phi/d q_j d q_k";

/// Writes the header line and one line per record (io/csv.h; with options.describe, the
/// comment lines before the header).
template <class M>
void WriteCsv(const std::vector<SweepRecord<M>>& records, std::ostream& out,
              const CsvOptions& options = CsvOptions()) {
  WriteCsv(SweepColumns<M>(), records, out, options);
}

/// Prints the given records, all of them (io/table.h, PrintTableRows()).
template <class M>
void PrintTableRows(const std::vector<SweepRecord<M>>& records, std::ostream& out) {
  PrintTableRows(SweepColumns<M>(), records, out);
}

/// Prints `rows` records spread evenly over the sweep (TableRowIndices()).
template <class M>
void PrintTable(const std::vector<SweepRecord<M>>& records, int rows, std::ostream& out) {
  PrintTable(SweepColumns<M>(), records, rows, out);
}

}  // namespace mechgen
