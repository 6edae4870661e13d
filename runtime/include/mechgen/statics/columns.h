/**
 * \file statics/columns.h
 * The one column table of a statics sweep (like sweep/columns.h for the kinematics): each
 * column's name and the value it takes from a StaticsRecord are defined together in
 * StaticsColumns<M>(); WriteStaticsCsv() writes every column, PrintStaticsTable() the ones
 * with a table name. Building the table allocates; it runs after the sweep.
 *
 * Columns, in order (q_j, phi_i the coordinate names, R_k = Model::kReactionNames, J the
 * joints of the reactions; "_fwd", "_back" become "_fwd_<q_j>", "_back_<q_j>" for the
 * reactions of models with several inputs):
 *   q_j, phi_i                       the configuration (rad, model length)
 *   drive_<q_j>                      T0: the driving torque (N m) or force (N) without friction
 *   drive_<q_j>_fwd, drive_<q_j>_back           with friction: the actuator drives the load
 *                                    (motion along sign T0) / the load drives it back
 *   efficiency_<q_j>_fwd, efficiency_<q_j>_back T0 / T_fwd and T_back / T0
 *   self_locking_<q_j>               1 where T_back T0 <= 0 (a dead zone), else 0
 *   R_k                              the reactions without friction (contract convention:
 *                                    force of the joint's first link on its second, fixed
 *                                    frame; N_J, T_J, M_J at a prismatic joint)
 *   F_<J>_mag                        |force| at joint J: hypot(F_J_x, F_J_y), hypot(N_J, T_J)
 *                                    at a prismatic joint, |F_J| at a gear or cam
 *   F_<J>_mag_fwd, F_<J>_mag_back    the same with friction, forward / backward
 *   V                                potential energy of springs and gravity (models with it)
 *   stiffness (stiffness_<q_j>_<q_k>, j <= k, with several inputs)   -dQ/dq, friction excluded
 *   mechanical_advantage             one input with points: 1 / |K_P| of the first point
 *   status, cond, evaluations        the row's status (converged, singular, did_not_converge,
 *                                    or the position step's failure), cond_1 Phi_phi, and the
 *                                    generated statics evaluations of the row
 * A value cell is empty when its solution is not usable (a singular row: reactions and
 * drives are unbounded there, so no number is printed; a friction iteration that did not
 * converge: its columns) or undefined (efficiency_<q>_back where T0 = 0 up to rounding);
 * cond is printed whenever the configuration was evaluated. mechanical_advantage is "inf" at
 * a toggle (K_P = 0 up to rounding).
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/statics/sweep.h"

namespace mechgen::statics {

/// The force components of one joint among the reactions (indices into R, -1 if absent).
struct ReactionJoint {
  std::string joint;
  int x = -1, y = -1;  ///< F_J_x, F_J_y (revolute)
  int n = -1, t = -1;  ///< N_J, T_J (prismatic)
  int scalar = -1;     ///< F_J (gear, rack, cam contact force)
};

/// Groups the reaction names of M by joint: "F_<J>_x"/"F_<J>_y", "N_<J>"/"T_<J>", "F_<J>";
/// moments ("M_<J>") are not forces and are left out. In the order of first appearance.
template <class M>
std::vector<ReactionJoint> ReactionJoints() {
  std::vector<ReactionJoint> joints;
  if constexpr (StaticsFeatures<M>::kHasReactions) {
    auto find = [&joints](const std::string& name) -> ReactionJoint& {
      for (ReactionJoint& j : joints)
        if (j.joint == name) return j;
      joints.push_back(ReactionJoint());
      joints.back().joint = name;
      return joints.back();
    };
    auto ends_with = [](const std::string& s, const char* tail) {
      const std::string t(tail);
      return s.size() > t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0;
    };
    for (int i = 0; i < StaticsFeatures<M>::kNumReactions; ++i) {
      const std::string name = M::kReactionNames[i];
      if (name.size() < 3 || name[1] != '_') continue;
      const char kind = name[0];
      const std::string rest = name.substr(2);
      if (kind == 'F' && ends_with(rest, "_x")) {
        find(rest.substr(0, rest.size() - 2)).x = i;
      } else if (kind == 'F' && ends_with(rest, "_y")) {
        find(rest.substr(0, rest.size() - 2)).y = i;
      } else if (kind == 'F') {
        find(rest).scalar = i;
      } else if (kind == 'N') {
        find(rest).n = i;
      } else if (kind == 'T') {
        find(rest).t = i;
      }
    }
  }
  return joints;
}

/// |force| at a joint from reactions R (NaN when any component is NaN).
template <class VecR>
double ReactionMagnitude(const ReactionJoint& j, const VecR& R) {
  auto at = [&R](int i) { return i >= 0 ? R(i) : 0.0; };
  if (j.scalar >= 0) return std::abs(R(j.scalar));
  if (j.x >= 0 || j.y >= 0) return std::hypot(at(j.x), at(j.y));
  return std::hypot(at(j.n), at(j.t));
}

/// One column of a statics sweep's output.
template <class M>
struct StaticsColumn {
  std::string name;        ///< the CSV header
  std::string table_name;  ///< in the printed table; empty: CSV only
  bool angle = false;      ///< radians (degrees in the table)
  const char* csv_format = "%.12g";
  /// The value (NaN: no value, an empty CSV cell).
  std::function<double(const StaticsRecord<M>&)> value;
  /// A text column (status); value is then unused.
  std::function<std::string(const StaticsRecord<M>&)> text;
};

/// The column table of model M's statics sweeps (see the file comment).
template <class M>
std::vector<StaticsColumn<M>> StaticsColumns() {
  static_assert(StaticsFeatures<M>::kHasStatics, "the model has no statics");
  using F = StaticsFeatures<M>;
  using R = StaticsRecord<M>;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<StaticsColumn<M>> columns;
  auto add = [&columns](std::string name, std::string table_name, bool angle,
                        std::function<double(const R&)> value, const char* format = "%.12g") {
    StaticsColumn<M> c;
    c.name = std::move(name);
    c.table_name = std::move(table_name);
    c.angle = angle;
    c.csv_format = format;
    c.value = std::move(value);
    columns.push_back(std::move(c));
  };
  auto usable = [](const Solution<M>& s) { return s.summary.status == Status::kConverged; };
  const bool one_input = M::kNq == 1;
  auto suffix = [one_input](const char* way, int j) {
    return std::string("_") + way + (one_input ? "" : std::string("_") + M::kQNames[j]);
  };

  for (int j = 0; j < M::kNq; ++j)
    add(M::kQNames[j], M::kQNames[j], M::kQIsAngle[j], [j](const R& r) { return r.kinematics.q(j); });
  for (int i = 0; i < M::kNphi; ++i)
    add(M::kPhiNames[i], "", M::kPhiIsAngle[i], [i](const R& r) {
      return r.kinematics.state.valid ? r.kinematics.state.phi(i) : kNaN;
    });
  for (int j = 0; j < M::kNq; ++j) {
    const std::string q = M::kQNames[j];
    add("drive_" + q, "drive_" + q, false, [j, usable](const R& r) {
      return usable(r.frictionless) ? r.frictionless.statics.drive(j) : kNaN;
    });
    if constexpr (F::kHasFriction) {
      add("drive_" + q + "_fwd", "drive_" + q + "_fwd", false, [j](const R& r) {
        return r.drives[j].status == Status::kConverged ? r.drives[j].drive_forward : kNaN;
      });
      add("drive_" + q + "_back", "drive_" + q + "_back", false, [j](const R& r) {
        return r.drives[j].status == Status::kConverged ? r.drives[j].drive_backward : kNaN;
      });
      add("efficiency_" + q + "_fwd", "", false, [j](const R& r) {
        return r.drives[j].status == Status::kConverged ? r.drives[j].efficiency_forward : kNaN;
      });
      add("efficiency_" + q + "_back", "", false, [j](const R& r) {
        return r.drives[j].status == Status::kConverged ? r.drives[j].efficiency_backward : kNaN;
      });
      add("self_locking_" + q, "locked", false, [j](const R& r) {
        return r.drives[j].status == Status::kConverged ? (r.drives[j].self_locking ? 1.0 : 0.0)
                                                        : kNaN;
      }, "%g");
    }
  }
  const std::vector<ReactionJoint> joints = ReactionJoints<M>();
  if constexpr (F::kHasReactions) {
    for (int i = 0; i < F::kNumReactions; ++i)
      add(M::kReactionNames[i], "", false, [i, usable](const R& r) {
        return usable(r.frictionless) ? r.frictionless.statics.R(i) : kNaN;
      });
    for (const ReactionJoint& joint : joints)
      add("F_" + joint.joint + "_mag", "|F_" + joint.joint + "|", false,
          [joint, usable](const R& r) {
            return usable(r.frictionless) ? ReactionMagnitude(joint, r.frictionless.statics.R)
                                          : kNaN;
          });
    if constexpr (F::kHasFriction) {
      for (int j = 0; j < M::kNq; ++j) {
        for (const ReactionJoint& joint : joints) {
          add("F_" + joint.joint + "_mag" + suffix("fwd", j), "", false,
              [joint, j, usable](const R& r) {
                return usable(r.forward[j]) ? ReactionMagnitude(joint, r.forward[j].statics.R)
                                            : kNaN;
              });
          add("F_" + joint.joint + "_mag" + suffix("back", j), "", false,
              [joint, j, usable](const R& r) {
                return usable(r.backward[j]) ? ReactionMagnitude(joint, r.backward[j].statics.R)
                                             : kNaN;
              });
        }
      }
    }
  }
  if constexpr (F::kHasPotential) {
    add("V", "V", false,
        [usable](const R& r) { return usable(r.frictionless) ? double(r.frictionless.statics.V) : kNaN; });
  }
  if constexpr (F::kHasStiffness) {
    for (int j = 0; j < M::kNq; ++j)
      for (int k = j; k < M::kNq; ++k)
        add(one_input ? std::string("stiffness")
                      : std::string("stiffness_") + M::kQNames[j] + "_" + M::kQNames[k],
            "", false, [j, k, usable](const R& r) {
              return usable(r.frictionless) ? r.frictionless.statics.stiffness(j, k) : kNaN;
            });
  }
  if constexpr (M::kNq == 1 && ModelFeatures<M>::kHasPointVelocities) {
    add("mechanical_advantage", "MA", false, [](const R& r) { return r.mechanical_advantage; });
  }
  StaticsColumn<M> status;
  status.name = status.table_name = "status";
  status.text = [](const R& r) { return std::string(RowStatus(r)); };
  columns.push_back(status);
  add("cond", "", false, [](const R& r) { return r.frictionless.summary.condition; }, "%.6g");
  StaticsColumn<M> evaluations;
  evaluations.name = "evaluations";
  evaluations.text = [](const R& r) { return std::to_string(r.evaluations); };
  columns.push_back(evaluations);
  return columns;
}

/// The names of StaticsColumns<M>(), in order.
template <class M>
std::vector<std::string> StaticsCsvColumns() {
  std::vector<std::string> names;
  for (const StaticsColumn<M>& c : StaticsColumns<M>()) names.push_back(c.name);
  return names;
}

/// A CSV cell: the text, the number, or empty for no value (NaN).
template <class M>
std::string StaticsCsvCell(const StaticsColumn<M>& c, const StaticsRecord<M>& r) {
  if (c.text) return c.text(r);
  const double x = c.value(r);
  return std::isnan(x) ? std::string() : ::mechgen::internal::FormatNumber(x, c.csv_format);
}

/// Writes the header line and one line per record.
template <class M>
void WriteStaticsCsv(const std::vector<StaticsRecord<M>>& records, std::ostream& out) {
  const std::vector<StaticsColumn<M>> columns = StaticsColumns<M>();
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i].name;
  out << '\n';
  for (const StaticsRecord<M>& r : records) {
    for (size_t i = 0; i < columns.size(); ++i)
      out << (i ? "," : "") << StaticsCsvCell(columns[i], r);
    out << '\n';
  }
}

/// Prints `rows` records spread evenly over the sweep (the columns with a table name;
/// angles in degrees, "-" for no value).
template <class M>
void PrintStaticsTable(const std::vector<StaticsRecord<M>>& records, int rows, std::ostream& out) {
  if (records.empty() || rows <= 0) return;
  std::vector<StaticsColumn<M>> columns = StaticsColumns<M>();
  columns.erase(std::remove_if(columns.begin(), columns.end(),
                               [](const StaticsColumn<M>& c) { return c.table_name.empty(); }),
                columns.end());
  std::vector<size_t> width;
  for (const StaticsColumn<M>& c : columns) width.push_back(std::max<size_t>(c.table_name.size(), 10));
  auto print_row = [&](const std::vector<std::string>& cells) {
    std::string line;
    for (size_t c = 0; c < cells.size(); ++c) {
      std::string cell = cells[c];
      if (cell.size() < width[c]) cell.insert(0, width[c] - cell.size(), ' ');
      line += (c ? "  " : "") + cell;
    }
    out << line << '\n';
  };
  std::vector<std::string> names, units;
  for (const StaticsColumn<M>& c : columns) {
    names.push_back(c.table_name);
    units.push_back(c.angle ? "[deg]" : "");
  }
  print_row(names);
  print_row(units);
  const int n = static_cast<int>(records.size());
  rows = std::min(rows, std::max(n - 1, 1));
  for (int k = 0; k < rows; ++k) {
    const StaticsRecord<M>& r = records[static_cast<size_t>((n - 1) * k / rows)];
    std::vector<std::string> cells;
    for (const StaticsColumn<M>& c : columns) {
      if (c.text) {
        cells.push_back(c.text(r));
        continue;
      }
      const double x = c.value(r);
      cells.push_back(std::isnan(x) ? "-"
                                    : ::mechgen::internal::FormatNumber(
                                          x * (c.angle ? ::mechgen::internal::kRadToDeg : 1), "%.4f"));
    }
    print_row(cells);
  }
}

}  // namespace mechgen::statics
