/**
 * \file statics/columns.h
 * The columns of a statics sweep (table/columns.h, like sweep/columns.h for the kinematics):
 * each column's name, unit, meaning and the value it takes from a StaticsRecord are defined
 * together in StaticsColumns<M>(); WriteStaticsCsv() writes every column with the one CSV
 * writer (io/csv.h: numbers that round-trip), PrintStaticsTable() the ones with a table name
 * with the one printer (io/table.h). Building the table allocates; it runs after the sweep.
 *
 * With friction, two directions of motion of each input (statics/solve.h DriveAnalysis):
 * "plus" and "minus" are the input running in +q_j and in -q_j (continuous curves, T_minus
 * <= T0 <= T_plus); "forward" is the motion along sign(T0), the actuator driving the load,
 * and "backward" the motion against it, the load driving the machine (efficiencies and
 * self-locking are defined on these two).
 *
 * Columns, in order (q_j, phi_i the coordinate names, R_k = Model::kReactionNames, J the
 * joints of the reactions; "_plus", "_minus" become "_plus_<q_j>", "_minus_<q_j>" for the
 * reactions of models with several inputs):
 *   q_j, phi_i                       the configuration (rad, model length)
 *   drive_<q_j>                      T0: the driving torque (N m) or force (N) without friction
 *   drive_<q_j>_plus, drive_<q_j>_minus         with friction: the driving torque or force
 *                                    to run the input in +q_j / in -q_j
 *   efficiency_<q_j>_fwd, efficiency_<q_j>_back T0 / T_fwd and T_back / T0
 *   self_locking_<q_j>               1 where T_back T0 <= 0 (a dead zone), else 0
 *   R_k                              the reactions without friction (contract convention:
 *                                    force of the joint's first link on its second, fixed
 *                                    frame; N_J, T_J, M_J at a prismatic joint)
 *   F_<J>_mag                        |force| at joint J: hypot(F_J_x, F_J_y), hypot(N_J, T_J)
 *                                    at a prismatic joint, |F_J| at a gear or cam
 *   F_<J>_mag_plus, F_<J>_mag_minus  the same with friction, the input running in +q / -q
 *   bearing_<J>_x, bearing_<J>_y     at each revolute joint J with the ground (a bearing, models
 *                                    with a drawing: Model::kDrawJointLink*): the force of the
 *                                    ground on the moving link, fixed frame, without friction
 *                                    (F_J or -F_J by the joint's link order); their polar
 *                                    diagram is runtime/tools/plot_bearings.gnuplot's
 *   V                                potential energy of springs and gravity (models with it)
 *   stiffness (stiffness_<q_j>_<q_k>, j <= k, with several inputs)   -dQ/dq, friction excluded
 *   mechanical_advantage             one input with points: 1 / |K_P| of the first point
 *   status, cond, evaluations        the row's status (converged, singular, did_not_converge,
 *                                    or the position step's failure), cond_1 Phi_phi, and the
 *                                    generated statics evaluations of the row
 *   ddrive_<q_j>/d<p>, dR_k/d<p>, dV/d<p>   with --design (EvalStaticsDesign): per design
 *                                    parameter p, the derivatives without friction, q held
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
#include <limits>
#include <ostream>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mechgen/io/csv.h"
#include "mechgen/io/table.h"
#include "mechgen/statics/sweep.h"
#include "mechgen/table/columns.h"

namespace mechgen::statics {

/// The force components of one joint among the reactions (indices into R, -1 if absent).
struct ReactionJoint {
  std::string joint;
  int x = -1, y = -1;  ///< F_J_x, F_J_y (revolute)
  int n = -1, t = -1;  ///< N_J, T_J (prismatic, slot, roll, gear, rack; cam: N_J)
  int scalar = -1;     ///< F_J (a scalar force component; the higher pairs now give F_J_x, F_J_y)
};

/// Groups the reaction names of M by joint: "F_<J>_x"/"F_<J>_y", "N_<J>"/"T_<J>", "F_<J>";
/// moments ("M_<J>") are not forces and are left out. In the order of first appearance.
template <class M>
std::vector<ReactionJoint> ReactionJoints(const M& model) {
  using C = ModelCalls<M>;
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
    for (int i = 0; i < C::NumReactions(model); ++i) {
      const std::string name = C::ReactionName(model, i);
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
  } else {
    (void)model;
  }
  return joints;
}
template <class M>
std::vector<ReactionJoint> ReactionJoints() {
  return ReactionJoints<M>(M());
}

namespace internal {
/// Whether M names the joint of each reaction and the links of each joint: a model with
/// reactions (kHasStaticsR: Model::kReactionJoint) and a drawing (kHasDrawing:
/// Model::kDrawJointLinkA, kDrawJointLinkB), read from its flags.
template <class M>
struct HasJointLinks
    : std::bool_constant<mechgen::HasStaticsR<M>::value && mechgen::HasDrawing<M>::value> {};
}  // namespace internal

/// A revolute joint with the ground (a bearing): its reaction components and the sign that
/// turns them into the force of the ground on the moving link.
struct GroundBearing {
  std::string joint;  ///< the joint's name, J
  std::string link;   ///< the moving link the ground carries there
  int x = -1, y = -1;  ///< F_J_x, F_J_y in R
  double sign = 1;     ///< +1: the ground is the joint's first link (R is its force); -1: second
};

/// The ground bearings of M, in the order of the reactions; empty for a model that does not
/// name its joints' links (hand-written models without a drawing).
template <class M>
std::vector<GroundBearing> GroundBearings(const M& model) {
  using C = ModelCalls<M>;
  std::vector<GroundBearing> bearings;
  if constexpr (StaticsFeatures<M>::kHasReactions && internal::HasJointLinks<M>::value) {
    if (!C::HasJointLinks(model)) return bearings;
    const int n = C::NumReactions(model), ground = C::GroundLink(model);
    for (int i = 0; i < n; ++i) {
      const std::string name = C::ReactionName(model, i);
      const bool x = name.size() > 4 && name.compare(0, 2, "F_") == 0 &&
                     name.compare(name.size() - 2, 2, "_x") == 0;
      if (!x || i + 1 >= n) continue;
      const std::string joint = name.substr(2, name.size() - 4);
      if (std::string(C::ReactionName(model, i + 1)) != "F_" + joint + "_y") continue;
      const int j = C::ReactionJoint(model, i);
      const int a = C::DrawJointLinkA(model, j), b = C::DrawJointLinkB(model, j);
      if (a != ground && b != ground) continue;
      GroundBearing g;
      g.joint = joint;
      g.link = C::LinkName(model, a == ground ? b : a);
      g.x = i;
      g.y = i + 1;
      g.sign = a == ground ? 1.0 : -1.0;
      bearings.push_back(g);
    }
  } else {
    (void)model;
  }
  return bearings;
}
template <class M>
std::vector<GroundBearing> GroundBearings() {
  return GroundBearings<M>(M());
}

/// |force| at a joint from reactions R (NaN when any component is NaN).
template <class VecR>
double ReactionMagnitude(const ReactionJoint& j, const VecR& R) {
  auto at = [&R](int i) { return i >= 0 ? R(i) : 0.0; };
  if (j.scalar >= 0) return std::abs(R(j.scalar));
  if (j.x >= 0 || j.y >= 0) return std::hypot(at(j.x), at(j.y));
  return std::hypot(at(j.n), at(j.t));
}

/// One column of a statics sweep's output (a NaN value is "no value": an empty CSV cell, "-"
/// in the printed table).
template <class M>
using StaticsColumn = table::Column<StaticsRecord<M>>;

/// The column table of model M's statics sweeps (see the file comment); with `design` (a model
/// with EvalStaticsDesign, Options::design), also for each design parameter p (kDesignNames)
/// d drive_<q_j>/d<p>, dR_k/d<p>, dV/d<p> without friction, q held.
template <class M>
std::vector<StaticsColumn<M>> StaticsColumns(const M& model, bool design = false) {
  using C = ModelCalls<M>;
  const int nq = C::Nq(model);
  static_assert(StaticsFeatures<M>::kHasStatics, "the model has no statics");
  using F = StaticsFeatures<M>;
  using R = StaticsRecord<M>;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<StaticsColumn<M>> columns;
  table::Builder<R> add(&columns, "");
  auto usable = [](const Solution<M>& s) { return s.summary.status == Status::kConverged; };
  const bool one_input = nq == 1;
  auto suffix = [one_input, &model](const char* way, int j) {
    return std::string("_") + way + (one_input ? "" : std::string("_") + C::QName(model, j));
  };
  // The generalized force's unit along input j: a torque for an angle, a force for a slide.
  auto force_unit = [&model](int j) { return std::string(C::QIsAngle(model, j) ? "N m" : "N"); };
  auto length_unit = [](bool angle) { return std::string(angle ? "rad" : "model length"); };
  const char* const kReactionConvention =
      "force of the joint's first link on its second, fixed frame (N_J normal, T_J along a "
      "prismatic joint, M_J its moment), without friction";

  for (int j = 0; j < nq; ++j)
    table::Shown(add.Number(C::QName(model, j), length_unit(C::QIsAngle(model, j)), "input",
                            [j](const R& r) { return r.kinematics.q(j); }),
                 C::QName(model, j));
  for (int i = 0; i < C::Nphi(model); ++i)
    add.Number(C::PhiName(model, i), length_unit(C::PhiIsAngle(model, i)), "dependent coordinate",
               [i](const R& r) {
                 return r.kinematics.state.valid ? r.kinematics.state.phi(i) : kNaN;
               });
  for (int j = 0; j < nq; ++j) {
    const std::string q = C::QName(model, j);
    table::Shown(add.Number("drive_" + q, force_unit(j),
                            "T0: the driving force on the input without friction, along +q",
                            [j, usable](const R& r) {
                              return usable(r.frictionless) ? r.frictionless.statics.drive(j)
                                                            : kNaN;
                            }),
                 "drive_" + q);
    if constexpr (F::kHasFriction) {
      if (C::HasFriction(model)) {
      table::Shown(add.Number("drive_" + q + "_plus", force_unit(j),
                              "T_plus: with friction, the driving force to run the input in +" +
                                  q + " (" + q + " increasing); >= T0",
                              [j](const R& r) {
                                return r.drives[j].status == Status::kConverged
                                           ? r.drives[j].drive_plus
                                           : kNaN;
                              }),
                   "drive_" + q + "_plus");
      table::Shown(add.Number("drive_" + q + "_minus", force_unit(j),
                              "T_minus: with friction, the driving force to run the input in -" +
                                  q + " (" + q + " decreasing); <= T0",
                              [j](const R& r) {
                                return r.drives[j].status == Status::kConverged
                                           ? r.drives[j].drive_minus
                                           : kNaN;
                              }),
                   "drive_" + q + "_minus");
      add.Number("efficiency_" + q + "_fwd", "1",
                 "T0 / T_fwd, forward: the motion along sign(T0), the actuator driving the "
                 "load (T_fwd is T_plus where T0 >= 0, else T_minus)",
                 [j](const R& r) {
                   return r.drives[j].status == Status::kConverged
                              ? r.drives[j].efficiency_forward
                              : kNaN;
                 });
      add.Number("efficiency_" + q + "_back", "1",
                 "T_back / T0, backward: the motion against sign(T0), the load driving the "
                 "machine (none where T0 = 0)",
                 [j](const R& r) {
                   return r.drives[j].status == Status::kConverged
                              ? r.drives[j].efficiency_backward
                              : kNaN;
                 });
      table::Shown(add.Number("self_locking_" + q, "1",
                              "1 where T_back T0 <= 0 (a dead zone), else 0",
                              [j](const R& r) {
                                return r.drives[j].status == Status::kConverged
                                           ? (r.drives[j].self_locking ? 1.0 : 0.0)
                                           : kNaN;
                              }),
                   "locked");
      }
    }
  }
  const std::vector<ReactionJoint> joints = ReactionJoints<M>(model);
  if constexpr (F::kHasReactions) {
    for (int i = 0; i < C::NumReactions(model); ++i)
      add.Number(C::ReactionName(model, i), C::ReactionName(model, i)[0] == 'M' ? "N m" : "N",
                 kReactionConvention, [i, usable](const R& r) {
                   return usable(r.frictionless) ? r.frictionless.statics.R(i) : kNaN;
                 });
    for (const ReactionJoint& joint : joints)
      table::Shown(add.Number("F_" + joint.joint + "_mag", "N",
                              "|force| at the joint without friction",
                              [joint, usable](const R& r) {
                                return usable(r.frictionless)
                                           ? ReactionMagnitude(joint, r.frictionless.statics.R)
                                           : kNaN;
                              }),
                   "|F_" + joint.joint + "|");
    if constexpr (F::kHasFriction) {
      for (int j = 0; j < nq && C::HasFriction(model); ++j) {
        for (const ReactionJoint& joint : joints) {
          for (const double way : {+1.0, -1.0}) {
            add.Number("F_" + joint.joint + "_mag" + suffix(way > 0 ? "plus" : "minus", j),
                       "N",
                       std::string("|force| at the joint with friction, the input ") +
                           C::QName(model, j) + " running in " + (way > 0 ? "+" : "-") +
                           C::QName(model, j),
                       [joint, j, way, usable](const R& r) {
                         const Solution<M>& s = Moving(r, j, way);
                         return usable(s) ? ReactionMagnitude(joint, s.statics.R) : kNaN;
                       });
          }
        }
      }
    }
  }
  if constexpr (F::kHasReactions) {  // (a model without reactions has no Statics::R)
    for (const GroundBearing& g : GroundBearings<M>(model)) {
      for (const int axis : {0, 1}) {
        add.Number("bearing_" + g.joint + (axis ? "_y" : "_x"), "N",
                   std::string("force of the ground on ") + g.link + " at the bearing " + g.joint +
                       ", fixed frame " + (axis ? "y" : "x") + ", without friction",
                   [g, axis, usable](const R& r) {
                     return usable(r.frictionless)
                                ? g.sign * r.frictionless.statics.R(axis ? g.y : g.x) + 0.0  // no -0
                                : kNaN;
                   });
      }
    }
  }
  if constexpr (F::kHasPotential) {
    if (C::HasPotential(model))
    table::Shown(add.Number("V", "J", "potential energy of springs and gravity",
                            [usable](const R& r) {
                              return usable(r.frictionless) ? double(r.frictionless.statics.V)
                                                            : kNaN;
                            }),
                 "V");
  }
  if constexpr (F::kHasStiffness) {
    for (int j = 0; j < nq && C::HasStiffness(model); ++j)
      for (int k = j; k < nq; ++k)
        add.Number(one_input ? std::string("stiffness")
                             : std::string("stiffness_") + C::QName(model, j) + "_" + C::QName(model, k),
                   force_unit(j) + "/" + (C::QIsAngle(model, k) ? "rad" : "model length"),
                   "-dQ_j/dq_k, friction excluded", [j, k, usable](const R& r) {
                     return usable(r.frictionless) ? r.frictionless.statics.stiffness(j, k)
                                                   : kNaN;
                   });
  }
  if constexpr ((M::kNq == 1 || C::kView) && ModelFeatures<M>::kHasPointVelocities) {
    if (nq == 1 && C::HasPointVelocities(model))
    table::Shown(add.Number("mechanical_advantage",
                            C::QIsAngle(model, 0) ? "rad/model length" : "1",
                            "1 / |K_P| of the first point (inf at a toggle)",
                            [](const R& r) { return r.mechanical_advantage; }),
                 "MA");
  }
  table::Shown(add.Text("status",
                        "converged, singular, did_not_converge, or the position step's failure",
                        [](const R& r) { return std::string(RowStatus(r)); }),
               "status");
  add.Number("cond", "1", "cond_1 Phi_phi",
             [](const R& r) { return r.frictionless.summary.condition; });
  add.Text("evaluations", "generated statics evaluations of the row",
           [](const R& r) { return std::to_string(r.evaluations); });
  if constexpr (F::kHasDesign) {
    const int num_design = design && C::HasStaticsDesign(model) ? C::NumDesign(model) : 0;
    for (int d = 0; d < num_design; ++d) {
      const std::string p = C::DesignName(model, d);
      if constexpr (HasStaticsQ<M>::value)
        for (int j = 0; j < nq; ++j)
          add.Number("ddrive_" + std::string(C::QName(model, j)) + "/d" + p,
                     std::string(C::QIsAngle(model, j) ? "N m" : "N") + " per unit of " + p,
                     "sensitivity of the driving torque or force without friction (q held)",
                     [j, d](const R& r) { return r.design.ddrive_dp(j, d); });
      if constexpr (HasStaticsR<M>::value)
        for (int k = 0; k < C::NumReactions(model); ++k)
          add.Number("d" + std::string(C::ReactionName(model, k)) + "/d" + p, "N or N m per unit of " + p,
                     "sensitivity of the reaction without friction (q held)",
                     [k, d](const R& r) { return r.design.dR_dp(k, d); });
      if constexpr (HasStaticsV<M>::value)
        if (C::HasPotential(model))
          add.Number("dV/d" + p, "J per unit of " + p, "sensitivity of the potential energy (q held)",
                     [d](const R& r) { return r.design.dV_dp(d); });
    }
  } else {
    (void)design;
  }
  return columns;
}

/// StaticsColumns() of a generated model M (its empty tag).
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
std::vector<StaticsColumn<M>> StaticsColumns(bool design = false) {
  return StaticsColumns<M>(M(), design);
}

/// The names of StaticsColumns<M>(), in order.
template <class M>
std::vector<std::string> StaticsCsvColumns(const M& model, bool design = false) {
  return table::ColumnNames(StaticsColumns<M>(model, design));
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
std::vector<std::string> StaticsCsvColumns(bool design = false) {
  return StaticsCsvColumns<M>(M(), design);
}

/// A CSV cell: the text, the number, or empty for no value (NaN).
template <class M>
std::string StaticsCsvCell(const StaticsColumn<M>& c, const StaticsRecord<M>& r) {
  return ::mechgen::CsvCell(c, r);
}

/// The sign convention of a statics sweep's CSV (its first comment line, io/csv.h CsvAbout()).
inline constexpr const char* kStaticsSigns =
    "drive_<q> is the torque (CCW +) or force (along +q) the actuator applies to its input for "
    "equilibrium, -Q; with friction drive_<q>_plus and drive_<q>_minus are that torque or "
    "force with the input running in +q and in -q (friction opposes the motion: "
    "drive_<q>_minus <= drive_<q> <= drive_<q>_plus), forward is the motion along "
    "sign(drive_<q>) (the actuator drives the load) and backward the motion against it (the "
    "load drives the machine); reactions are the force (and moment) of each joint's first link on its "
    "second, fixed frame; angles CCW + from the fixed x axis";

/// Writes the header line and one line per record (io/csv.h; with options.describe, the
/// comment lines before the header).
template <class M>
void WriteStaticsCsv(const M& model, const std::vector<StaticsRecord<M>>& records, std::ostream& out,
                     const CsvOptions& options = CsvOptions(), bool design = false) {
  ::mechgen::WriteCsv(StaticsColumns<M>(model, design), records, out, options);
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
void WriteStaticsCsv(const std::vector<StaticsRecord<M>>& records, std::ostream& out,
                     const CsvOptions& options = CsvOptions(), bool design = false) {
  WriteStaticsCsv<M>(M(), records, out, options, design);
}

/// Prints `rows` records spread evenly over the sweep, the first and the last included
/// (io/table.h: the columns with a table name; angles in degrees, "-" for no value).
template <class M>
void PrintStaticsTable(const M& model, const std::vector<StaticsRecord<M>>& records, int rows, std::ostream& out) {
  ::mechgen::PrintTable(StaticsColumns<M>(model), records, rows, out);
}
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
void PrintStaticsTable(const std::vector<StaticsRecord<M>>& records, int rows, std::ostream& out) {
  PrintStaticsTable<M>(M(), records, rows, out);
}

}  // namespace mechgen::statics
