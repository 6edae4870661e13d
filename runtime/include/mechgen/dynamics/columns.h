/**
 * \file dynamics/columns.h
 * The columns of a simulation (table/columns.h, like sweep/columns.h and statics/columns.h):
 * each column's name, unit, meaning and the value it takes from a simulation's sample (and the
 * reactions of the generated kinetostatics there) are defined together. FreeColumns() is the
 * table of a run with every input free (MinimalDynamics, forward.h), DrivenColumns() of a run
 * with inputs driven by laws (PrescribedDynamics, prescribed.h). `<model>_simulate` writes
 * them with the one CSV writer (io/csv.h); a study with `analysis: simulate` reads its metrics
 * from FreeColumns() by the same names (study/run.h). Building a table allocates; it runs
 * before the simulation, not in it.
 *
 * Columns of a free run, in order: t (s); each input q, q_dot, q_ddot (rad or m, per s, per
 * s^2); T, V, E = T + V, W_nc (J); Q_<q> (N m or N); with Coulomb friction friction_<joint>
 * and stuck; the reactions with the inertia forces (kinetostatics: the force and moment of
 * each joint's first link on its second, fixed frame) and F_<joint>_mag at each revolute
 * joint (several inputs: stuck_<joint> per friction joint in place of stuck). A driven run has
 * W_act, lambda_<q> per driven input, balance and rcond, then with Coulomb friction (every
 * input driven) friction_<joint>, before the reactions.
 */
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/core/model_calls.h"
#include "mechgen/dynamics/friction.h"
#include "mechgen/statics/traits.h"
#include "mechgen/table/columns.h"

namespace mechgen::dynamics {

// One CSV row: a sample and the reactions of the generated kinetostatics at it (nullptr when
// withheld: the row's reaction cells are then empty).
template <class SampleT>
struct CsvRow {
  const SampleT* s = nullptr;
  const double* R = nullptr;
};

// t, each input, its speed and acceleration: the first columns of every run.
// (Each function reads the model through ModelCalls<M> (core/model_calls.h): `model` is a
// generated model's empty tag, or the ViewModel of the simulation through the view.)
template <class M, class SampleT>
void AddInputColumns(table::Builder<CsvRow<SampleT>>* add, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  using Calls = ModelCalls<M>;
  const int nq = Calls::Nq(model);
  auto unit = [&model](int i, const char* per) {
    return std::string(Calls::QIsAngle(model, i) ? "rad" : "m") + per;
  };
  add->Number("t", "s", "time", [](const Row& r) { return double(r.s->t); });
  for (int i = 0; i < nq; ++i)
    add->Number(Calls::QName(model, i), unit(i, ""), "input", [i](const Row& r) { return r.s->q(i); });
  for (int i = 0; i < nq; ++i)
    add->Number(std::string(Calls::QName(model, i)) + "_dot", unit(i, "/s"), "input speed",
                [i](const Row& r) { return r.s->qd(i); });
  for (int i = 0; i < nq; ++i)
    add->Number(std::string(Calls::QName(model, i)) + "_ddot", unit(i, "/s^2"), "input acceleration",
                [i](const Row& r) { return r.s->qdd(i); });
}

// The columns every run has: the inputs' (AddInputColumns), then T, V, E, W_nc (and W_act
// when driven).
template <class M, class SampleT, bool kDriven>
void AddMotionColumns(table::Builder<CsvRow<SampleT>>* add, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  AddInputColumns<M, SampleT>(add, model);
  add->Number("T", "J", "kinetic energy", [](const Row& r) { return double(r.s->T); });
  add->Number("V", "J", "potential energy (springs, gravity)",
              [](const Row& r) { return double(r.s->V); });
  add->Number("E", "J", "T + V", [](const Row& r) { return double(r.s->E); });
  if constexpr (!kDriven) {
    add->Number("W_nc", "J", "work of the non-conservative forces since t = 0",
                [](const Row& r) { return double(r.s->W); });
  } else {
    add->Number("W_nc", "J", "work of the non-conservative forces since t = 0",
                [](const Row& r) { return double(r.s->W_nc); });
    add->Number("W_act", "J", "work of the actuators since t = 0",
                [](const Row& r) { return double(r.s->W_act); });
  }
}

// Q_<input>: the generalized applied force.
template <class M, class SampleT>
void AddForceColumns(table::Builder<CsvRow<SampleT>>* add, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  using Calls = ModelCalls<M>;
  for (int i = 0; i < Calls::Nq(model); ++i)
    add->Number(std::string("Q_") + Calls::QName(model, i), Calls::QIsAngle(model, i) ? "N m" : "N",
                "generalized applied force (loads, motors, dampers, weights, springs, joint "
                "friction): a torque CCW + for an angle input, a force along +q for a slide",
                [i](const Row& r) { return r.s->Q(i); });
}

// Each reaction component of the generated kinetostatics at the simulated motion (empty cells
// where withheld).
template <class M, class SampleT>
void AddReactionColumns(table::Builder<CsvRow<SampleT>>* add, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  using Calls = ModelCalls<M>;
  const int num_reactions = Calls::KinetoNumReactions(model);
  for (int k = 0; k < num_reactions; ++k)
    add->Number(Calls::KinetoReactionName(model, k), Calls::KinetoReactionName(model, k)[0] == 'M' ? "N m" : "N",
                "reaction with the inertia forces: the force of the joint's first link on its "
                "second, fixed frame",
                [k](const Row& r) {
                  return r.R != nullptr ? r.R[k] : std::numeric_limits<double>::quiet_NaN();
                })
        .missing = "";
}

// The revolute joints among the reactions, F_<joint>_x followed by F_<joint>_y: (index of the
// x component, joint).
template <class M>
std::vector<std::pair<int, std::string>> RevoluteMagnitudes(const M& model = M()) {
  using Calls = ModelCalls<M>;
  std::vector<std::pair<int, std::string>> magnitudes;
  const int num_reactions = Calls::KinetoNumReactions(model);
  for (int r = 0; r + 1 < num_reactions; ++r) {
    const std::string a = Calls::KinetoReactionName(model, r), b = Calls::KinetoReactionName(model, r + 1);
    if (a.size() > 4 && a.compare(0, 2, "F_") == 0 && a.compare(a.size() - 2, 2, "_x") == 0 &&
        b == a.substr(0, a.size() - 2) + "_y") {
      magnitudes.emplace_back(r, a.substr(2, a.size() - 4));
    }
  }
  return magnitudes;
}

// |F| of each revolute joint among the reactions (F_<joint>_mag, N; empty where withheld): the
// bearing loads of every run, free or driven.
template <class M, class SampleT>
void AddMagnitudeColumns(table::Builder<CsvRow<SampleT>>* add, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  for (const auto& m : RevoluteMagnitudes<M>(model)) {
    const int x = m.first;
    add->Number("F_" + m.second + "_mag", "N", "|force| at the revolute joint (inertia forces included)",
                [x](const Row& r) {
                  return r.R != nullptr ? std::hypot(r.R[x], r.R[x + 1])
                                        : std::numeric_limits<double>::quiet_NaN();
                })
        .missing = "";
  }
}

// Coulomb friction of a free run (Sim::kHasCoulomb): friction_<joint> per friction joint and
// the stuck flag.
template <class M, class SampleT, bool kHasCoulomb>
void AddFrictionColumns(table::Builder<CsvRow<SampleT>>* add, bool coulomb, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  using Calls = ModelCalls<M>;
  if (!coulomb) return;
  if constexpr (kHasCoulomb) {
    const int num_friction = Calls::KinetoNumFriction(model);
    if (num_friction == 0) return;  // (a view without friction joints: a generated one's kHasCoulomb is false)
    for (int J = 0; J < num_friction; ++J) {
      const bool prismatic = Calls::FrictionPrismatic(model, J);
      add->Number(std::string("friction_") + Calls::FrictionJoint(model, J), prismatic ? "N" : "N m",
                  prismatic ? "Coulomb friction force on the slider along the slide's +u"
                            : "Coulomb friction torque on the joint's second link by its first, CCW +",
                  [J](const Row& r) { return r.s->friction(J); });
    }
    if (Calls::Nq(model) == 1) {
      add->Number("stuck", "1", "1: held at rest by static friction (q_dot = q_ddot = 0); 0: moving",
                  [](const Row& r) { return r.s->stuck ? 1.0 : 0.0; });
    } else {
      // Several inputs: each joint's own flag (a stuck joint holds its input at rest).
      for (int J = 0; J < num_friction; ++J)
        add->Number(std::string("stuck_") + Calls::FrictionJoint(model, J), "1",
                    "1: the joint held at relative rest by static friction (its input's speed 0); 0: slipping",
                    [J](const Row& r) { return r.s->joint_stuck[J] ? 1.0 : 0.0; });
    }
  }
}

// Coulomb friction of a driven run (PrescribedDynamics::kHasDrivenFriction): friction_<joint>
// per friction joint, included in lambda.
template <class M, class SampleT>
void AddDrivenFrictionColumns(table::Builder<CsvRow<SampleT>>* add, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  using Calls = ModelCalls<M>;
  for (int J = 0; J < Calls::KinetoNumFriction(model); ++J) {
    const bool prismatic = Calls::FrictionPrismatic(model, J);
    add->Number(std::string("friction_") + Calls::FrictionJoint(model, J), prismatic ? "N" : "N m",
                prismatic ? "Coulomb friction force on the slider along the slide's +u, opposing the driven "
                            "relative motion (0 at relative rest); in lambda"
                          : "Coulomb friction torque on the joint's second link by its first, CCW +, opposing "
                            "the driven relative motion (0 at relative rest); in lambda",
                [J](const Row& r) { return r.s->friction(J); });
  }
}

// The CSV of a run with every input free: t, q, q_dot, q_ddot, T, V, E, W_nc, Q, the
// friction loads and stuck flag (when the run simulates Coulomb friction), the reactions and
// |F| of each revolute joint.
template <class M, class SampleT, bool kHasCoulomb>
table::Columns<CsvRow<SampleT>> FreeColumns(bool coulomb, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  table::Columns<Row> columns;
  table::Builder<Row> add(&columns);
  AddMotionColumns<M, SampleT, false>(&add, model);
  AddForceColumns<M, SampleT>(&add, model);
  if constexpr (kHasCoulomb) AddFrictionColumns<M, SampleT, kHasCoulomb>(&add, coulomb, model);
  AddReactionColumns<M, SampleT>(&add, model);
  AddMagnitudeColumns<M, SampleT>(&add, model);
  return columns;
}

// The CSV of a run with inputs driven (prescribed: their indices, std::array or a list of a
// run-time length): t, q, q_dot, q_ddot, T, V, E, W_nc, W_act, Q, lambda per driven input,
// balance, rcond, the reactions and |F| of each revolute joint.
template <class M, class SampleT, class Indices>
table::Columns<CsvRow<SampleT>> DrivenColumns(const Indices& prescribed, bool coulomb = false, const M& model = M()) {
  using Row = CsvRow<SampleT>;
  using Calls = ModelCalls<M>;
  table::Columns<Row> columns;
  table::Builder<Row> add(&columns);
  AddMotionColumns<M, SampleT, true>(&add, model);
  AddForceColumns<M, SampleT>(&add, model);
  for (int i = 0; i < static_cast<int>(prescribed.size()); ++i) {
    const int k = prescribed[i];
    add.Number(std::string("lambda_") + Calls::QName(model, k), Calls::QIsAngle(model, k) ? "N m" : "N",
               "actuator force that keeps the input on its law: a torque on the input link CCW +, "
               "or a force along the slide; empty: withheld at a singular configuration",
               [i](const Row& r) { return r.s->lambda(i); })
        .missing = "";
  }
  add.Number("balance", "J", "E - W_nc - W_act (constant along an exact motion)",
             [](const Row& r) { return double(r.s->Balance()); });
  add.Number("rcond", "1", "1/cond_1(Phi_phi) (the run stops below 1e-6)",
             [](const Row& r) { return double(r.s->rcond); });
  if (coulomb) AddDrivenFrictionColumns<M, SampleT>(&add, model);
  AddReactionColumns<M, SampleT>(&add, model);
  AddMagnitudeColumns<M, SampleT>(&add, model);
  return columns;
}
}  // namespace mechgen::dynamics
