// <model>_simulate: the forward dynamics of one generated mechgen model (issue 15).
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this generic file per model
// whose outputs ask for `dynamics`, with -DMECHGEN_MODEL_INCLUDE="<name>.h"
// -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It assembles the mechanism at the model's assembly
// configuration (or --q0), starts from rest (or --qd0) and integrates the equation of motion
// I(q) qdd + 1/2 I'(q) qd^2 = Q(t, q, qd) by the minimal method (mechgen/dynamics/forward.h)
// until --t-end, or until the speed is periodic (steady state: the time of one revolution of the
// first input changes by less than --steady-tol between revolutions, twice in a row; an angle
// input only), or until an event stops it. Writes a CSV (one row every --dt seconds; its columns
// declared once below with their units and signs and written by the one CSV writer, io/csv.h,
// every number so that it reads back to the same double; the file written whole or not at
// all, io/output_file.h: a CSV that cannot be written exits 1 with one line):
//   t [s], each input q [rad or m], its speed q_dot, acceleration q_ddot, the kinetic energy
//   T, potential V, E = T + V, W_nc = the work of the non-conservative forces since t = 0 [J],
//   Q_<input> = the generalized applied force (loads, motor curves, dampers, weights, springs;
//   a torque [N m] for an angle input, CCW +, a force [N] for a slide), then, when the model has
//   reactions, each reaction component of the generated kinetostatics at the simulated motion
//   (inertia forces included; the force of the joint's first link on its second, fixed frame)
//   and |F| of each revolute joint (F_<joint>_mag).
// Plot it with runtime/tools/plot_dynamics.gnuplot. Example:
//   slider_crank_motor_simulate --t-end 10 --dt 0.002 --csv out/motor.csv
//   gnuplot -e "csv='out/motor.csv'; png='out/motor.png'" runtime/tools/plot_dynamics.gnuplot
// With --drive (motion generators, Paul 8.4.4; mechgen/dynamics/prescribed.h) some inputs follow
// a law of time and the others are free; the CSV then also has, per driven input, the actuator
// force lambda_<input> that keeps it on its law (a torque [N m] on the input link, CCW +, or a
// force [N] along the slide), W_act = its work since t = 0, the balance E - W_nc - W_act (constant
// along an exact motion) and rcond = 1/cond_1(Phi_phi) (the run stops, exit 1, where it falls
// below 1e-6: a singular configuration, never integrated through). Example, the five-bar robot
// with its first motor at 2 rad/s and the second holding still (inverse dynamics when every
// input is driven):
//   fivebar_robot_simulate --drive theta_prox1=speed:2 --drive theta_prox2=speed:0 --t-end 0.5
// Exit status: 0 when the run reached --t-end or a steady state (or stopped at the speed
// through zero with --stop-at-speed-zero); 1 when it ended on a failure (a dead point, the
// position solver, a singular inertia, the integrator), with the reason on stderr; 2 for a
// usage error. A model generated without `dynamics` builds into a stub that says so (exit 2).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "mechgen/dynamics/prescribed.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/output_file.h"
#include "mechgen/statics/traits.h"
#include "mechgen/table/columns.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

namespace {

constexpr double kDegToRad = 0.017453292519943295;
constexpr double kTwoPi = 6.283185307179586;

// "1.5" -> 1.5; "90deg" -> pi/2. False if malformed.
bool ParseValue(const std::string& text, double* value) {
  std::string number = text;
  double factor = 1;
  if (number.size() > 3 && number.compare(number.size() - 3, 3, "deg") == 0) {
    number.resize(number.size() - 3);
    factor = kDegToRad;
  }
  char* end = nullptr;
  *value = std::strtod(number.c_str(), &end) * factor;
  return !number.empty() && end != nullptr && *end == '\0' && std::isfinite(*value);
}

// One --drive NAME=LAW: the input's index and its law.
struct DriveSpec {
  std::string text;  // as given, for messages
  std::string name;
  std::string kind;  // speed, move, cycloidal, table
  std::vector<double> values;
  std::string file;
};

struct Args {
  double t_end = 10;
  double dt = 0.001;
  double rtol = 1e-8;
  double atol = 1e-10;
  std::string method = "dopri5";
  std::vector<double> q0, qd0;
  std::string csv;
  double steady_tol = 1e-4;
  bool steady = true;
  bool energy_projection = false;
  bool stop_at_speed_zero = false;
  bool quiet = false;
  int max_steps = 1000000;
  std::vector<DriveSpec> drives;
};

void Usage(const char* program) {
  std::printf(
      "usage: %s [options]\n"
      "Simulates the model's motion (minimal method, Paul 6.6.1) and writes a CSV.\n"
      "  --t-end T            end time in s (default 10)\n"
      "  --dt DT              CSV row spacing in s (default 0.001)\n"
      "  --q0 V[,V...]        initial inputs (rad, or e.g. 90deg; default: the assembly)\n"
      "  --qd0 V[,V...]       initial speeds (rad/s or m/s; default 0: from rest)\n"
      "  --method M           dopri5 (default) or dop853\n"
      "  --rtol R --atol A    integrator tolerances (default 1e-8, 1e-10)\n"
      "  --steady-tol S       stop at a periodic steady state: the revolution time of the first\n"
      "                       input changes by < S relative, twice in a row (default 1e-4)\n"
      "  --no-steady          run to --t-end regardless\n"
      "  --energy-projection  keep T + V - W_nc at its initial value (long conservative runs)\n"
      "  --stop-at-speed-zero stop where the first input's speed changes sign\n"
      "  --max-steps N        integrator steps before giving up (default 1e6)\n"
      "  --drive NAME=LAW     a motion generator: input NAME (as in the CSV header) follows LAW,\n"
      "                       the other inputs are free; repeat for several. LAW is one of\n"
      "                         speed:W            constant speed W (rad/s, or e.g. 90deg) from\n"
      "                                            the input's initial value\n"
      "                         move:Q1:T0:T1      rest to rest from the initial value to Q1 between\n"
      "                                            T0 and T1 s, 3-4-5 polynomial\n"
      "                         cycloidal:Q1:T0:T1 the same, cycloidal\n"
      "                         table:FILE         the clamped cubic spline through the rows t,q of\n"
      "                                            a CSV file (a header line is skipped)\n"
      "                       The CSV gets lambda_NAME, the actuator force that the law needs.\n"
      "  --csv FILE           write the CSV there (default: <model>_simulate.csv)\n"
      "  --quiet              no summary on stdout\n",
      program);
}

bool ParseList(const std::string& text, std::vector<double>* values) {
  values->clear();
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos
                                                                            : comma - start);
    double v = 0;
    if (!ParseValue(item, &v)) return false;
    values->push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return true;
}

// NAME=speed:W | move:Q1:T0:T1 | cycloidal:Q1:T0:T1 | table:FILE. The name is checked
// against the model later.
bool ParseDrive(const std::string& text, std::vector<DriveSpec>* drives) {
  DriveSpec d;
  d.text = text;
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  d.name = text.substr(0, eq);
  const std::string law = text.substr(eq + 1);
  const size_t colon = law.find(':');
  if (colon == std::string::npos) return false;
  d.kind = law.substr(0, colon);
  const std::string rest = law.substr(colon + 1);
  if (d.kind == "table") {
    d.file = rest;
    if (d.file.empty()) return false;
  } else {
    std::string list = rest;
    std::replace(list.begin(), list.end(), ':', ',');
    if (!ParseList(list, &d.values)) return false;
    if (d.kind == "speed") {
      if (d.values.size() != 1) return false;
    } else if (d.kind == "move" || d.kind == "cycloidal") {
      if (d.values.size() != 3 || !(d.values[2] > d.values[1])) return false;
    } else {
      return false;
    }
  }
  drives->push_back(d);
  return true;
}

// 0: ok, 1: --help, 2: error.
int ParseArgs(int argc, char** argv, Args* a) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&](std::string* out) {
      if (i + 1 >= argc) return false;
      *out = argv[++i];
      return true;
    };
    auto number = [&](double* out) {
      std::string text;
      return next(&text) && ParseValue(text, out);
    };
    std::string text;
    bool ok = true;
    if (arg == "--help" || arg == "-h") return 1;
    if (arg == "--t-end") ok = number(&a->t_end) && a->t_end > 0;
    else if (arg == "--dt") ok = number(&a->dt) && a->dt > 0;
    else if (arg == "--rtol") ok = number(&a->rtol) && a->rtol > 0;
    else if (arg == "--atol") ok = number(&a->atol) && a->atol > 0;
    else if (arg == "--steady-tol") ok = number(&a->steady_tol) && a->steady_tol > 0;
    else if (arg == "--no-steady") a->steady = false;
    else if (arg == "--energy-projection") a->energy_projection = true;
    else if (arg == "--stop-at-speed-zero") a->stop_at_speed_zero = true;
    else if (arg == "--quiet") a->quiet = true;
    else if (arg == "--max-steps") {
      double v = 0;
      ok = number(&v) && v >= 1 && v <= 2e9;
      a->max_steps = static_cast<int>(v);
    }
    else if (arg == "--method") ok = next(&a->method) && (a->method == "dopri5" || a->method == "dop853");
    else if (arg == "--q0") ok = next(&text) && ParseList(text, &a->q0);
    else if (arg == "--qd0") ok = next(&text) && ParseList(text, &a->qd0);
    else if (arg == "--csv") ok = next(&a->csv);
    else if (arg == "--drive") ok = next(&text) && ParseDrive(text, &a->drives);
    else {
      std::fprintf(stderr, "error: unknown option '%s' (see --help)\n", arg.c_str());
      return 2;
    }
    if (!ok) {
      std::fprintf(stderr, "error: bad or missing value for %s (see --help)\n", arg.c_str());
      return 2;
    }
  }
  return 0;
}

// The rows t,q of a CSV file (a first line that is not two numbers is a header). False with
// a message naming the file and line.
bool ReadTable(const std::string& path, std::vector<double>* t, std::vector<double>* q,
               std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read " + path;
    return false;
  }
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<double> values;
    if (!ParseList(line, &values) || values.size() != 2) {
      if (number == 1) continue;  // a header
      *error = path + ":" + std::to_string(number) + ": expected two numbers t,q";
      return false;
    }
    t->push_back(values[0]);
    q->push_back(values[1]);
  }
  if (t->size() < 2) {
    *error = path + ": a table needs at least two rows t,q";
    return false;
  }
  return true;
}

// ---- output: the CSV's column table (table/columns.h), written by io/csv.h -----------------

// One CSV row: a sample and the reactions of the generated kinetostatics at it (nullptr when
// withheld: the row's reaction cells are then empty).
template <class SampleT>
struct CsvRow {
  const SampleT* s = nullptr;
  const double* R = nullptr;
};

// The columns every run has: t, each input, its speed and acceleration, then T, V, E, W_nc
// (and W_act when driven).
template <class M, class SampleT, bool kDriven>
void AddMotionColumns(mechgen::table::Builder<CsvRow<SampleT>>* add) {
  using Row = CsvRow<SampleT>;
  constexpr int kNq = M::kNq;
  auto unit = [](int i, const char* per) {
    return std::string(M::kQIsAngle[i] ? "rad" : "m") + per;
  };
  add->Number("t", "s", "time", [](const Row& r) { return double(r.s->t); });
  for (int i = 0; i < kNq; ++i)
    add->Number(M::kQNames[i], unit(i, ""), "input", [i](const Row& r) { return r.s->q(i); });
  for (int i = 0; i < kNq; ++i)
    add->Number(std::string(M::kQNames[i]) + "_dot", unit(i, "/s"), "input speed",
                [i](const Row& r) { return r.s->qd(i); });
  for (int i = 0; i < kNq; ++i)
    add->Number(std::string(M::kQNames[i]) + "_ddot", unit(i, "/s^2"), "input acceleration",
                [i](const Row& r) { return r.s->qdd(i); });
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
void AddForceColumns(mechgen::table::Builder<CsvRow<SampleT>>* add) {
  using Row = CsvRow<SampleT>;
  for (int i = 0; i < M::kNq; ++i)
    add->Number(std::string("Q_") + M::kQNames[i], M::kQIsAngle[i] ? "N m" : "N",
                "generalized applied force (loads, motors, dampers, weights, springs): a torque "
                "CCW + for an angle input, a force along +q for a slide",
                [i](const Row& r) { return r.s->Q(i); });
}

// Each reaction component of the generated kinetostatics at the simulated motion (empty cells
// where withheld).
template <class M, class SampleT>
void AddReactionColumns(mechgen::table::Builder<CsvRow<SampleT>>* add) {
  using Row = CsvRow<SampleT>;
  constexpr int kNumReactions = mechgen::statics::internal::NumReactions<M>::value;
  if constexpr (kNumReactions > 0) {
    for (int k = 0; k < kNumReactions; ++k)
      add->Number(M::kReactionNames[k], M::kReactionNames[k][0] == 'M' ? "N m" : "N",
                  "reaction with the inertia forces: the force of the joint's first link on its "
                  "second, fixed frame",
                  [k](const Row& r) {
                    return r.R != nullptr ? r.R[k] : std::numeric_limits<double>::quiet_NaN();
                  })
          .missing = "";
  }
}

// The revolute joints among the reactions, F_<joint>_x followed by F_<joint>_y: (index of the
// x component, joint).
template <class M>
std::vector<std::pair<int, std::string>> RevoluteMagnitudes() {
  std::vector<std::pair<int, std::string>> magnitudes;
  constexpr int kNumReactions = mechgen::statics::internal::NumReactions<M>::value;
  if constexpr (kNumReactions > 0) {
    for (int r = 0; r + 1 < kNumReactions; ++r) {
      const std::string a = M::kReactionNames[r], b = M::kReactionNames[r + 1];
      if (a.size() > 4 && a.compare(0, 2, "F_") == 0 && a.compare(a.size() - 2, 2, "_x") == 0 &&
          b == a.substr(0, a.size() - 2) + "_y") {
        magnitudes.emplace_back(r, a.substr(2, a.size() - 4));
      }
    }
  }
  return magnitudes;
}

// The CSV of a run with every input free: t, q, q_dot, q_ddot, T, V, E, W_nc, Q, the
// reactions and |F| of each revolute joint.
template <class M, class SampleT>
mechgen::table::Columns<CsvRow<SampleT>> FreeColumns() {
  using Row = CsvRow<SampleT>;
  mechgen::table::Columns<Row> columns;
  mechgen::table::Builder<Row> add(&columns);
  AddMotionColumns<M, SampleT, false>(&add);
  AddForceColumns<M, SampleT>(&add);
  AddReactionColumns<M, SampleT>(&add);
  for (const auto& m : RevoluteMagnitudes<M>()) {
    const int x = m.first;
    add.Number("F_" + m.second + "_mag", "N", "|force| at the revolute joint",
               [x](const Row& r) {
                 return r.R != nullptr ? std::hypot(r.R[x], r.R[x + 1])
                                       : std::numeric_limits<double>::quiet_NaN();
               })
        .missing = "";
  }
  return columns;
}

// The CSV of a run with NP inputs driven: t, q, q_dot, q_ddot, T, V, E, W_nc, W_act, Q,
// lambda per driven input, balance, rcond, the reactions.
template <class M, class SampleT, int NP>
mechgen::table::Columns<CsvRow<SampleT>> DrivenColumns(const std::array<int, NP>& prescribed) {
  using Row = CsvRow<SampleT>;
  mechgen::table::Columns<Row> columns;
  mechgen::table::Builder<Row> add(&columns);
  AddMotionColumns<M, SampleT, true>(&add);
  AddForceColumns<M, SampleT>(&add);
  for (int i = 0; i < NP; ++i) {
    const int k = prescribed[i];
    add.Number(std::string("lambda_") + M::kQNames[k], M::kQIsAngle[k] ? "N m" : "N",
               "actuator force that keeps the input on its law: a torque on the input link CCW +, "
               "or a force along the slide",
               [i](const Row& r) { return r.s->lambda(i); });
  }
  add.Number("balance", "J", "E - W_nc - W_act (constant along an exact motion)",
             [](const Row& r) { return double(r.s->Balance()); });
  add.Number("rcond", "1", "1/cond_1(Phi_phi) (the run stops below 1e-6)",
             [](const Row& r) { return double(r.s->rcond); });
  AddReactionColumns<M, SampleT>(&add);
  return columns;
}

// Commits the CSV (io/output_file.h: whole or absent); false with one line on stderr.
bool CommitCsv(mechgen::OutputFile* csv) {
  std::string error;
  if (csv->Commit(&error)) return true;
  std::fprintf(stderr, "error: %s\n", error.c_str());
  return false;
}

// The standard output flushed; false with one line on stderr when it cannot be written.
bool FlushStdout() {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return true;
  std::fprintf(stderr, "error: cannot write the standard output\n");
  return false;
}

// The inputs' initial values and speeds from the model's assembly, --q0 and --qd0. 0 or the
// usage error's exit status.
template <class M, class VecQ>
int InitialState(const Args& args, VecQ* q0, VecQ* qd0) {
  constexpr int kNq = M::kNq;
  qd0->setZero();
  for (int i = 0; i < kNq; ++i) (*q0)(i) = M::kAssemblyQ[i];
  if (!args.q0.empty()) {
    if (static_cast<int>(args.q0.size()) != kNq) {
      std::fprintf(stderr, "error: --q0 needs %d value(s)\n", kNq);
      return 2;
    }
    for (int i = 0; i < kNq; ++i) (*q0)(i) = args.q0[i];
  }
  if (!args.qd0.empty()) {
    if (static_cast<int>(args.qd0.size()) != kNq) {
      std::fprintf(stderr, "error: --qd0 needs %d value(s)\n", kNq);
      return 2;
    }
    for (int i = 0; i < kNq; ++i) (*qd0)(i) = args.qd0[i];
  }
  return 0;
}

template <class M, template <int> class Method>
int Run(const Args& args) {
  using Sim = mechgen::dynamics::MinimalDynamics<M, Method>;
  using VecQ = typename Sim::VecQ;
  using SampleT = typename Sim::SampleT;
  constexpr int kNumReactions = mechgen::statics::internal::NumReactions<M>::value;
  const typename M::template ParamsT<double> params;

  VecQ q0, qd0;
  if (const int status = InitialState<M>(args, &q0, &qd0); status != 0) return status;

  mechgen::dynamics::MinimalOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  options.energy_projection = args.energy_projection;
  options.stop_at_speed_zero = args.stop_at_speed_zero;
  Sim sim(params, options);
  if (!sim.Initialize(q0)) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs\n", M::kName);
    return 1;
  }
  mechgen::dynamics::Kinetostatics<M> kineto(params);
  kineto.Initialize(q0);

  const std::string csv_path = args.csv.empty() ? std::string(M::kName) + "_simulate.csv" : args.csv;
  // The CSV, written to a temporary file and renamed when whole (io/output_file.h).
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  const auto columns = FreeColumns<M, SampleT>();
  const auto magnitudes = RevoluteMagnitudes<M>();
  mechgen::WriteCsvHeader(columns, csv.stream());

  // Steady state: times at which the first input passes q0 + 2 pi k (angle inputs).
  const bool angle = M::kQIsAngle[0];
  double last_crossing = std::numeric_limits<double>::quiet_NaN(), last_period = 0;
  int stable = 0, revolutions = 0;
  bool steady_reached = false;
  double prev_t = 0, prev_q = q0(0), steady_period = 0;
  double max_reaction = 0;

  auto observer = [&](const SampleT& s) {
    // The row is written inside the branch that holds the kinetostatics it points into.
    CsvRow<SampleT> row{&s, nullptr};
    if constexpr (kNumReactions > 0) {
      mechgen::dynamics::KinetostaticsRow<M> k;
      kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k);
      if (k.status == mechgen::dynamics::KinetostaticsStatus::kOk) {
        row.R = k.statics.R.data();
        for (const auto& m : magnitudes)
          max_reaction =
              std::max(max_reaction, std::hypot(k.statics.R(m.first), k.statics.R(m.first + 1)));
      }
      mechgen::WriteCsvRow(columns, row, csv.stream());
    } else {
      mechgen::WriteCsvRow(columns, row, csv.stream());
    }
    if (angle && args.steady && s.t > 0) {
      // Crossings of q0 + 2 pi k, either direction, by linear interpolation between rows.
      const double k_prev = std::floor((prev_q - q0(0)) / kTwoPi);
      const double k_now = std::floor((s.q(0) - q0(0)) / kTwoPi);
      if (k_now != k_prev) {
        const double level = q0(0) + kTwoPi * std::max(k_now, k_prev);
        const double t_cross = prev_t + (s.t - prev_t) * (level - prev_q) / (s.q(0) - prev_q);
        if (!std::isnan(last_crossing)) {
          const double period = t_cross - last_crossing;
          ++revolutions;
          if (last_period > 0 && std::abs(period - last_period) <= args.steady_tol * period) {
            if (++stable >= 2) {
              steady_reached = true;
              steady_period = period;
            }
          } else {
            stable = 0;
          }
          last_period = period;
        }
        last_crossing = t_cross;
      }
    }
    prev_t = s.t;
    prev_q = s.q(0);
    return !steady_reached;
  };

  mechgen::dynamics::MinimalSummary summary;
  SampleT last;
  sim.Simulate(0.0, q0, qd0, args.t_end, observer, &summary, &last);
  if (!CommitCsv(&csv)) return 1;
  const bool failure = mechgen::dynamics::IsFailure(summary.status);
  if (!args.quiet) {
    std::printf("%s: %s\n", M::kName, mechgen::dynamics::FormatSummary(summary).c_str());
    if (steady_reached) {
      std::printf("steady state at t = %.6g s: revolution time %.6g s (mean speed %.6g rad/s)\n",
                  summary.t_end, steady_period, kTwoPi / steady_period);
    } else if (angle && args.steady) {
      std::printf("no periodic steady state detected (%d revolutions)\n", revolutions);
    }
    std::printf("end: t = %.6g s, %s = %.6g, %s_dot = %.6g; E - W_nc drift %.3g J; max |F| %.6g N\n",
                summary.t_end, M::kQNames[0], last.q(0), M::kQNames[0], last.qd(0),
                summary.max_energy_error, max_reaction);
    std::string png = csv_path;
    if (png.size() > 4 && png.compare(png.size() - 4, 4, ".csv") == 0) png.resize(png.size() - 4);
    png += ".png";
    std::printf("wrote %s (%d rows); plot: gnuplot -e \"csv='%s'; png='%s'\" plot_dynamics.gnuplot\n",
                csv_path.c_str(), summary.samples, csv_path.c_str(), png.c_str());
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s: %s\n", M::kName,
                 mechgen::dynamics::ToString(summary.status), summary.t_end, summary.message);
    return 1;
  }
  return 0;
}

// The run with NP of the inputs driven (--drive): PrescribedDynamics.
template <class M, template <int> class Method, int NP>
int RunDriven(const Args& args) {
  namespace dyn = mechgen::dynamics;
  constexpr int kNq = M::kNq;
  using Drive = dyn::AnyDrive<NP>;
  using Sim = dyn::PrescribedDynamics<M, NP, Drive, dyn::NoForce, Method>;
  using VecQ = typename Sim::VecQ;
  using VecF = typename Sim::VecF;
  using SampleT = typename Sim::SampleT;
  constexpr int kNf = Sim::kNf;
  constexpr int kNumReactions = mechgen::statics::internal::NumReactions<M>::value;
  const typename M::template ParamsT<double> params;

  VecQ q0, qd0;
  if (const int status = InitialState<M>(args, &q0, &qd0); status != 0) return status;
  std::array<int, NP> prescribed{};
  std::array<dyn::AnyLaw, NP> laws;
  for (int i = 0; i < NP; ++i) {
    const DriveSpec& d = args.drives[i];
    int k = -1;
    for (int j = 0; j < kNq; ++j)
      if (d.name == M::kQNames[j]) k = j;
    if (k < 0) {
      std::string names;
      for (int j = 0; j < kNq; ++j) names += std::string(j ? ", " : "") + M::kQNames[j];
      std::fprintf(stderr, "error: --drive %s: the model has no input '%s' (its inputs: %s)\n",
                   d.text.c_str(), d.name.c_str(), names.c_str());
      return 2;
    }
    for (int j = 0; j < i; ++j) {
      if (prescribed[j] == k) {
        std::fprintf(stderr, "error: --drive %s: input '%s' is driven twice\n", d.text.c_str(),
                     d.name.c_str());
        return 2;
      }
    }
    prescribed[i] = k;
    if (d.kind == "speed") {
      laws[i] = dyn::ConstantSpeedLaw{q0(k), d.values[0], 0.0};
    } else if (d.kind == "move" || d.kind == "cycloidal") {
      laws[i] = dyn::RestToRestLaw{q0(k), d.values[0], d.values[1], d.values[2],
                                   d.kind == "move" ? dyn::RestToRestLaw::Profile::kPoly345
                                                    : dyn::RestToRestLaw::Profile::kCycloidal};
    } else {
      std::vector<double> t, q;
      std::string error;
      if (!ReadTable(d.file, &t, &q, &error)) {
        std::fprintf(stderr, "error: --drive %s: %s\n", d.text.c_str(), error.c_str());
        return 2;
      }
      dyn::TableLaw law(std::move(t), std::move(q));
      if (!law.IsValid()) {
        std::fprintf(stderr,
                     "error: --drive %s: the times of %s must increase strictly and every value "
                     "be finite\n",
                     d.text.c_str(), d.file.c_str());
        return 2;
      }
      laws[i] = std::move(law);
    }
  }

  dyn::PrescribedOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  Sim sim(params, prescribed, Drive(laws), dyn::NoForce(), options);
  VecF qf0, qdf0;
  for (int i = 0; i < kNf; ++i) {
    qf0(i) = q0(sim.free()[i]);
    qdf0(i) = qd0(sim.free()[i]);
  }
  if (!sim.Initialize(0.0, qf0)) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs and the drives' t = 0\n",
                 M::kName);
    return 1;
  }
  mechgen::dynamics::Kinetostatics<M> kineto(params);
  kineto.Initialize(q0);

  const std::string csv_path = args.csv.empty() ? std::string(M::kName) + "_simulate.csv" : args.csv;
  // The CSV, written to a temporary file and renamed when whole (io/output_file.h).
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  const auto columns = DrivenColumns<M, SampleT, NP>(prescribed);
  mechgen::WriteCsvHeader(columns, csv.stream());
  auto observer = [&](const SampleT& s) {
    // The row is written inside the branch that holds the kinetostatics it points into.
    CsvRow<SampleT> row{&s, nullptr};
    if constexpr (kNumReactions > 0) {
      mechgen::dynamics::KinetostaticsRow<M> k;
      kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &k);
      if (k.status == mechgen::dynamics::KinetostaticsStatus::kOk) row.R = k.statics.R.data();
      mechgen::WriteCsvRow(columns, row, csv.stream());
    } else {
      mechgen::WriteCsvRow(columns, row, csv.stream());
    }
    return true;
  };
  dyn::PrescribedSummary summary;
  SampleT last;
  sim.Simulate(0.0, qf0, qdf0, args.t_end, observer, &summary, &last);
  if (!CommitCsv(&csv)) return 1;
  const bool failure = dyn::IsFailure(summary.status);
  if (!args.quiet) {
    std::printf("%s (%d of %d inputs driven): %s\n", M::kName, NP, kNq,
                dyn::FormatSummary(summary).c_str());
    for (int i = 0; i < NP; ++i)
      std::printf("end: lambda_%s = %.6g\n", M::kQNames[prescribed[i]], last.lambda(i));
    std::printf("wrote %s (%d rows)\n", csv_path.c_str(), summary.samples);
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s (1/cond(Phi_phi) = %.3g): %s\n",
                 M::kName, dyn::ToString(summary.status), summary.t_end, last.rcond,
                 summary.message);
    return 1;
  }
  return 0;
}

// RunDriven with NP = the number of --drive options (1 ... kNq).
template <class M, template <int> class Method, int NP = 1>
int DispatchDriven(const Args& args) {
  if constexpr (NP > M::kNq) {
    std::fprintf(stderr, "error: %d --drive options for a model with %d input(s)\n",
                 static_cast<int>(args.drives.size()), M::kNq);
    return 2;
  } else {
    if (static_cast<int>(args.drives.size()) == NP) return RunDriven<M, Method, NP>(args);
    return DispatchDriven<M, Method, NP + 1>(args);
  }
}

template <class M>
int Main(const Args& args) {
  if constexpr (!mechgen::dynamics::internal::HasDynamics<M>::value) {
    (void)args;
    std::fprintf(stderr,
                 "%s: this model was generated without `dynamics` (add it to outputs.quantities)\n",
                 M::kName);
    return 2;
  } else {
    if (!args.drives.empty()) {
      return args.method == "dop853" ? DispatchDriven<M, mechgen::dynamics::Dop853>(args)
                                     : DispatchDriven<M, mechgen::dynamics::Dopri5>(args);
    }
    return args.method == "dop853" ? Run<M, mechgen::dynamics::Dop853>(args)
                                   : Run<M, mechgen::dynamics::Dopri5>(args);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  const int parsed = ParseArgs(argc, argv, &args);
  if (parsed == 1) {
    Usage(argv[0]);
    return 0;
  }
  if (parsed != 0) return 2;
  return Main<MECHGEN_MODEL_NAMESPACE::Model>(args);
}
