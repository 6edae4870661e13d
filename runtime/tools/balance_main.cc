// mechgen_balance: balancing and flywheel sizing that need no mechanism model (issue 16).
//
//   mechgen_balance table [--csv] [--rotating-ratio R] [--layout NAME]... [--engine FILE]...
//       The primary/secondary shaking force and moment table of multi-cylinder engines
//       (mechgen/machines/balancing/engine_balance.h): max over a turn in units of m r w^2 (primary) and
//       m r w^2 (r/l) (secondary), moments times the cylinder spacing a. --engine: a layout of
//       your own, one cylinder a line: throw angle [deg], bank angle [deg], z [spacings].
//   mechgen_balance layouts
//       The preset layouts as CSV, one cylinder a row: throw and bank angles [deg] and z
//       [spacings]. tools/make_engine.py --preset takes the same names for the same layouts.
//   mechgen_balance rotor --csv FILE --radius R [--left ZL --right ZR]
//       Rigid-rotor balancing (mechgen/machines/balancing/rotor.h, Paul §7.1). FILE has one unbalance a
//       line: m [kg], r [m], angle [deg], z [m] (comma-separated; '#' comments and a header
//       line "m,r,angle_deg,z" allowed). With --left/--right: two-plane dynamic balancing, the
//       correction masses at radius R (or --left-radius/--right-radius) in the planes z = ZL,
//       ZR; without: static balancing in one plane. Prints the corrections and the residual.
//   mechgen_balance flywheel --areas "295,-685,40,-340,960,-270" --scale S --rpm N
//                            (--inertia I | --mass M --gyration K | --cs C)
//   mechgen_balance flywheel --torque-csv FILE [--cycle-deg 360] [--remove-mean]
//                            [--energy-csv OUT] --rpm N (...)
//       Flywheel sizing by the energy-loop method (mechgen/machines/flywheel/energy_loop.h, Paul §6.9.2):
//       dE from the loop areas of a turning-moment diagram (S = J per unit area, or
//       --torque-scale [N m per unit] with --angle-scale [deg per unit]) or from a sampled
//       excess torque (FILE: angle_deg, torque [N m] (T_d - T_l), or angle_deg, T_d, T_l,
//       equally spaced over one cycle); then C_s = dE/(I w^2) for a flywheel I, or the
//       I = dE/(C_s w^2) for a coefficient of fluctuation of speed C_s. --energy-csv writes
//       angle_deg, excess_torque, E over the cycle (the energy loop, for a chart).
//   mechgen_balance wittenbauer --csv FILE [--design --rpm N --cs C] [--diagram-csv OUT]
//       Wittenbauer's diagram (Paul §6.9.3): from samples (angle_deg, I, T) of a machine's
//       generalized inertia and kinetic energy, w_max and w_min (the rays from the origin tangent
//       to the T(I) curve); with --design, from (angle_deg, I_m, E), the machine's own inertia
//       and the excess work, the flywheel I_f and T0 whose tangents of slopes w_max^2/2 and
//       w_min^2/2 meet at the origin, compared with the energy-loop flywheel.
// Options (the command-line layer of every mechgen tool, runtime/tools/common/): `--opt=value`
// and `--opt value`; every number finite and inside the range --help lists (nan and inf are
// refused, never read as "not given").
// Exit status 0 on success; 2 on a usage error (an unknown option or subcommand, a bad or
// missing option value, options that do not go together), 1 on bad input data (a file that
// cannot be read or holds bad rows) or a failed computation; either way one line
// "mechgen_balance: error: ..." on stderr and nothing on stdout.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/cli.h"
#include "mechgen/machines/balancing/engine_balance.h"
#include "mechgen/machines/balancing/rotor.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/format.h"
#include "mechgen/io/output_file.h"
#include "mechgen/table/columns.h"

namespace {

namespace bal = mechgen::balancing;
namespace fw = mechgen::flywheel;

// Writes text to path whole or not at all (io/output_file.h: a temporary file renamed when
// every write and the close succeeded); false with the reason in *error.
bool WriteWhole(const std::string& path, const std::string& text, std::string* error) {
  mechgen::OutputFile file;
  if (!file.Open(path, error)) return false;
  file.stream() << text;
  return file.Commit(error);
}
constexpr double kPi = 3.14159265358979323846;

std::string Format(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, x);
  return buffer;
}

// Degrees in [0, 360).
double Degrees(double rad) {
  double d = std::fmod(mechgen::ToDegrees(rad), 360.0);
  if (d < 0) d += 360;
  if (d >= 360 - 5e-13) d = 0;
  return d;
}

bool ParseNumber(const std::string& text, double* value) {
  return mechgen::tools::ParseField(text, value);
}

// Comma-separated numbers; false (and the offending field in *error) if one is not a number.
bool ParseList(const std::string& text, std::vector<double>* values, std::string* error) {
  values->clear();
  std::stringstream in(text);
  std::string field;
  while (std::getline(in, field, ',')) {
    double x = 0;
    if (!ParseNumber(field, &x)) {
      *error = "'" + field + "' is not a number";
      return false;
    }
    values->push_back(x);
  }
  if (values->empty()) {
    *error = "no numbers";
    return false;
  }
  return true;
}

// The numeric rows of a CSV file (comments '#', blank lines and a first non-numeric header
// line skipped), each with `min_columns`..`max_columns` fields.
bool ReadCsv(const std::string& path,
             int min_columns,
             int max_columns,
             std::vector<std::vector<double>>* rows,
             std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open";
    return false;
  }
  std::string line;
  int number = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::vector<double> row;
    std::string why;
    if (!ParseList(line, &row, &why)) {
      double x = 0;
      if (first && !ParseNumber(line.substr(0, line.find(',')), &x)) {  // a header line
        first = false;
        continue;
      }
      *error = path + ":" + std::to_string(number) + ": " + why;
      return false;
    }
    first = false;
    if (static_cast<int>(row.size()) < min_columns || static_cast<int>(row.size()) > max_columns) {
      *error = path + ":" + std::to_string(number) + ": expected " + std::to_string(min_columns) +
               (max_columns > min_columns ? " to " + std::to_string(max_columns) : std::string()) + " numbers, found " +
               std::to_string(row.size());
      return false;
    }
    rows->push_back(row);
  }
  if (rows->empty()) {
    *error = path + ": no data rows";
    return false;
  }
  return true;
}

constexpr const char* kTool = "mechgen_balance";

// Bad input data or a failed computation: one line, exit status 1.
int Fail(const std::string& message) {
  std::cerr << kTool << ": error: " << message << '\n';
  return 1;
}

// A usage error (options): one line, exit status 2.
int Usage(const std::string& message) { return mechgen::tools::UsageError(kTool, message); }

// ---- table ----
int RunTable(bool csv,
             double rotating_ratio,
             const std::vector<std::string>& names,
             const std::vector<std::string>& engine_files) {
  if (!(rotating_ratio >= 0)) return Usage("--rotating-ratio must be >= 0");
  const auto all = bal::EngineLayouts();
  std::vector<bal::EngineLayout> chosen;
  // A layout from a file: throw_deg, bank_deg, z a cylinder; named after the file. The names
  // live in `file_names` (stable: reserved) for the table's const char*.
  std::vector<std::string> file_names;
  file_names.reserve(engine_files.size());
  for (const std::string& path : engine_files) {
    std::vector<std::vector<double>> rows;
    std::string error;
    if (!ReadCsv(path, 3, 3, &rows, &error)) return Fail(error);
    if (static_cast<int>(rows.size()) > bal::kMaxCylinders)
      return Fail(path + ": " + std::to_string(rows.size()) + " cylinders, at most " +
                  std::to_string(bal::kMaxCylinders));
    std::string name = path.substr(path.find_last_of('/') + 1);
    name = name.substr(0, name.find('.'));
    file_names.push_back(name);
    bal::EngineLayout e;
    e.name = file_names.back().c_str();
    e.description = "from a file";
    for (const auto& row : rows) e.cylinders[e.count++] = {mechgen::FromDegrees(row[0]), mechgen::FromDegrees(row[1]), row[2]};
    chosen.push_back(e);
  }
  for (const std::string& name : names) {
    const bal::EngineLayout* e = bal::FindLayout(all, name);
    if (e == nullptr) {
      std::string known;
      for (const bal::EngineLayout& x : all) known += std::string(" ") + x.name;
      return Usage("--layout: bad value " + mechgen::tools::Quote(name) +
                   ": no such layout; layouts are" + known);
    }
    chosen.push_back(*e);
  }
  if (names.empty() && engine_files.empty()) chosen.assign(all.begin(), all.end());
  std::ostringstream out;
  bal::PrintBalanceTable(chosen, out, csv, rotating_ratio,
                         mechgen::Described(std::string(kTool) +
                                            " table: the balance table of engine layouts, two-mass approximation"
                                            ", rotating mass ratio " +
                                            mechgen::internal::FormatRoundTrip(rotating_ratio) +
                                            ". Signs: " + bal::kBalanceSigns));
  std::cout << out.str();
  return 0;
}

int RunLayouts() {
  const auto all = bal::EngineLayouts();
  std::ostringstream out;
  mechgen::WriteCsv(bal::LayoutCylinderColumns(), bal::LayoutCylinderRows(all), out,
                    mechgen::Described(std::string(kTool) +
                                       " layouts: the preset engine layouts, one cylinder a row (the names and "
                                       "the cylinders' numbers of tools/make_engine.py --preset)"));
  std::cout << out.str();
  return 0;
}

// ---- rotor ----
// Numeric options start as NaN: "not given".
constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
bool Given(double x) { return !std::isnan(x); }

struct RotorArgs {
  std::string csv;
  double radius = kUnset, left_radius = kUnset, right_radius = kUnset;
  double left = kUnset, right = kUnset;
};

int RunRotor(const RotorArgs& a) {
  std::vector<std::vector<double>> rows;
  std::string error;
  if (!ReadCsv(a.csv, 4, 4, &rows, &error)) return Fail(error);
  std::vector<bal::Unbalance> u;
  for (const auto& row : rows) u.push_back({row[0], row[1], mechgen::FromDegrees(row[2]), row[3]});
  const bool two_planes = Given(a.left) || Given(a.right);
  if (two_planes && !(Given(a.left) && Given(a.right)))
    return Usage("two-plane balancing needs both --left and --right (the planes' z)");
  const double r_left = Given(a.left_radius) ? a.left_radius : a.radius;
  const double r_right = Given(a.right_radius) ? a.right_radius : a.radius;
  const bal::RotorBalance b =
      two_planes ? bal::BalanceTwoPlanes(u.data(), static_cast<int>(u.size()), a.left, a.right, r_left, r_right)
                 : bal::BalanceStatic(u.data(), static_cast<int>(u.size()), r_left);
  if (b.status == bal::RotorStatus::kBadUnbalance)
    return Fail(a.csv + ": unbalance " + std::to_string(b.index + 1) + ": " + bal::ToString(b.status));
  if (b.status == bal::RotorStatus::kZeroRadius)
    return Usage(std::string(bal::ToString(b.status)) + " (--radius, or --left-radius and --right-radius)");
  if (b.status == bal::RotorStatus::kNotFinite) return Fail(a.csv + ": " + bal::ToString(b.status));
  if (b.status != bal::RotorStatus::kOk) return Fail(bal::ToString(b.status));
  const bal::UnbalanceSums residual = bal::Residual(u.data(), static_cast<int>(u.size()), b, two_planes);
  if (!(std::isfinite(std::abs(residual.U)) && std::isfinite(std::abs(residual.M))))
    return Fail(a.csv + ": " + bal::ToString(bal::RotorStatus::kNotFinite));
  std::ostringstream out;
  out << "rotor: " << u.size() << " unbalances from " << a.csv << "\n";
  out << "  static unbalance U = sum m r e^(i angle): " << Format("%.6g", std::abs(b.before.U)) << " kg m at "
      << Format("%.4f", Degrees(std::arg(b.before.U))) << " deg\n";
  out << "  moment M = sum m r z e^(i angle) about z = 0: " << Format("%.6g", std::abs(b.before.M)) << " kg m^2 at "
      << Format("%.4f", Degrees(std::arg(b.before.M))) << " deg\n";
  auto plane = [&](const char* name, const bal::Correction& c) {
    out << "  " << name << " plane z = " << Format("%.6g", c.z) << " m: " << Format("%.6g", c.mass)
        << " kg at r = " << Format("%.6g", c.radius) << " m, angle " << Format("%.4f", Degrees(c.angle))
        << " deg (m r = " << Format("%.6g", c.mr) << " kg m)\n";
  };
  if (two_planes) {
    out << "two-plane (dynamic) balancing:\n";
    plane("left ", b.left);
    plane("right", b.right);
  } else {
    out << "static balancing (one plane; the couple is not balanced):\n";
    plane("correction", b.left);
  }
  out << "residual after the corrections: |U| = " << Format("%.3g", std::abs(residual.U))
      << " kg m, |M| = " << Format("%.3g", std::abs(residual.M)) << " kg m^2"
      << (two_planes ? "" : " (the couple remains)") << "\n";
  std::cout << out.str();
  return 0;
}

// ---- flywheel ----

// The rows and columns of the energy-loop CSV (table/columns.h, written by io/csv.h).
struct EnergyRow {
  double angle_deg, excess_torque, E;
};
mechgen::table::Columns<EnergyRow> EnergyColumns() {
  mechgen::table::Columns<EnergyRow> columns;
  mechgen::table::Builder<EnergyRow> add(&columns);
  add.Number("angle_deg", "deg", "angle of the machine's shaft",
             [](const EnergyRow& r) { return r.angle_deg; });
  add.Number("excess_torque", "N m", "T_d - T_l: driving minus load torque (less its mean with --remove-mean)",
             [](const EnergyRow& r) { return r.excess_torque; });
  add.Number("E", "J", "excess energy: the integral of excess_torque from the first angle",
             [](const EnergyRow& r) { return r.E; });
  return columns;
}

struct FlywheelArgs {
  std::string areas, torque_csv, energy_csv;
  double scale = kUnset, torque_scale = kUnset, angle_scale = kUnset;
  double cycle_deg = 360;
  bool remove_mean = false;
  double rpm = kUnset, inertia = kUnset, mass = kUnset, gyration = kUnset, cs = kUnset;
};

int RunFlywheel(const FlywheelArgs& a) {
  std::ostringstream out;
  if (a.areas.empty() == a.torque_csv.empty()) return Usage("give exactly one of --areas and --torque-csv");
  if (!(a.rpm > 0)) return Usage("--rpm (the mean speed) must be > 0");
  const bool by_inertia = Given(a.inertia) || Given(a.mass) || Given(a.gyration);
  if (by_inertia == Given(a.cs)) return Usage("give either the flywheel (--inertia, or --mass and --gyration) or --cs");
  if (Given(a.inertia) && (Given(a.mass) || Given(a.gyration)))
    return Usage("give --inertia or --mass with --gyration, not both");
  if (Given(a.mass) != Given(a.gyration)) return Usage("--mass and --gyration go together");
  for (const auto& [name, x] : {std::pair<const char*, double>{"--inertia", a.inertia},
                                {"--mass", a.mass},
                                {"--gyration", a.gyration},
                                {"--cs", a.cs}})
    if (Given(x) && !(x > 0)) return Usage(std::string(name) + " must be > 0");
  if (!a.energy_csv.empty() && a.torque_csv.empty()) return Usage("--energy-csv needs --torque-csv");
  double delta_E = 0;
  std::string energy_text;  // written last: nothing is written unless everything succeeded
  if (!a.areas.empty()) {
    std::vector<double> areas;
    std::string error;
    if (!ParseList(a.areas, &areas, &error)) return Usage("--areas: " + error);
    const bool by_scales = Given(a.torque_scale) || Given(a.angle_scale);
    if (by_scales == Given(a.scale))
      return Usage(
          "give the diagram's scale: --scale (J per unit area) or --torque-scale with "
          "--angle-scale");
    if (by_scales && !(a.torque_scale > 0 && a.angle_scale > 0))
      return Usage("--torque-scale and --angle-scale go together (both > 0)");
    if (!by_scales && !(a.scale > 0)) return Usage("--scale must be > 0");
    const double scale = by_scales ? a.torque_scale * a.angle_scale * mechgen::kDegToRad : a.scale;
    const fw::AreaLoop loop = fw::DeltaEFromAreas(areas.data(), static_cast<int>(areas.size()));
    if (loop.status == fw::LoopStatus::kNotSteady)
      return Usage("--areas: the loop does not close (sum of the areas = " + Format("%.6g", loop.closure) +
                  ", must be 0: not a steady cycle)");
    if (loop.status == fw::LoopStatus::kNonFinite)
      return Usage("--areas: their running sums are beyond the range of numbers (give the areas in a larger unit "
                   "and scale them with --scale)");
    if (loop.status != fw::LoopStatus::kOk) return Usage(std::string("--areas: ") + fw::ToString(loop.status));
    out << "energy loop from " << areas.size() << " areas; energy after each:";
    double s = 0;
    out << " 0";
    for (double x : areas) out << ' ' << Format("%.6g", s += x);
    out << "\n  largest after area " << loop.after_max << " (" << Format("%.6g", loop.max) << "), smallest after area "
        << loop.after_min << " (" << Format("%.6g", loop.min) << ")\n";
    delta_E = loop.delta * scale;
    if (!std::isfinite(delta_E))
      return Usage("--areas with the diagram's scale: dE = " + Format("%.6g", loop.delta) + " area units x " +
                   Format("%.6g", scale) + " J per unit is beyond the range of numbers");
    out << "  dE = " << Format("%.6g", loop.delta) << " area units x " << Format("%.6g", scale)
        << " J per unit = " << Format("%.6g", delta_E) << " J\n";
  } else {
    std::vector<std::vector<double>> rows;
    std::string error;
    if (!ReadCsv(a.torque_csv, 2, 3, &rows, &error)) return Fail(error);
    if (!(a.cycle_deg > 0)) return Usage("--cycle-deg must be > 0");
    const double theta0 = rows[0][0];
    // The last row may repeat the first one's angle plus a cycle: dropped.
    if (rows.size() > 1 && std::abs(rows.back()[0] - theta0 - a.cycle_deg) < 1e-9 * a.cycle_deg) rows.pop_back();
    const int n = static_cast<int>(rows.size());
    if (n < 4) return Fail(a.torque_csv + ": need at least 4 samples over the cycle");
    const double step = a.cycle_deg / n;
    std::vector<double> dT(n);
    for (int k = 0; k < n; ++k) {
      if (rows[k].size() != rows[0].size())
        return Fail(a.torque_csv + ": row " + std::to_string(k + 1) + " has a different number of columns");
      if (std::abs(rows[k][0] - (theta0 + k * step)) > 1e-6 * step)
        return Fail(a.torque_csv + ": the angles must be equally spaced over --cycle-deg " + Format("%g", a.cycle_deg) +
                    " (expected " + Format("%.6g", theta0 + k * step) + " deg at data row " + std::to_string(k + 1) +
                    ", found " + Format("%.6g", rows[k][0]) + ")");
      dT[k] = rows[k].size() == 3 ? rows[k][1] - rows[k][2] : rows[k][1];
    }
    fw::EnergyLoopOptions o;
    o.remove_mean = a.remove_mean;
    std::vector<double> E(n);
    const fw::EnergyLoop loop = fw::ExcessEnergy(dT.data(), n, mechgen::FromDegrees(a.cycle_deg), mechgen::FromDegrees(theta0), o, E.data());
    if (loop.status == fw::LoopStatus::kNotSteady)
      return Fail(a.torque_csv + ": not a steady cycle: the mean excess torque is " + Format("%.6g", loop.mean_torque) +
                  " N m (use --remove-mean to take the load as the mean torque)");
    if (loop.status != fw::LoopStatus::kOk) return Fail(a.torque_csv + ": " + fw::ToString(loop.status));
    delta_E = loop.delta_E;
    out << "energy loop from " << n << " torque samples over " << Format("%g", a.cycle_deg)
        << " deg (mean excess torque " << Format("%.6g", loop.mean_torque) << " N m"
        << (a.remove_mean ? ", removed" : "") << ")\n";
    out << "  E_max = " << Format("%.6g", loop.E_max) << " J at " << Format("%.3f", mechgen::ToDegrees(loop.theta_max))
        << " deg, E_min = " << Format("%.6g", loop.E_min) << " J at " << Format("%.3f", mechgen::ToDegrees(loop.theta_min))
        << " deg\n";
    out << "  dE = " << Format("%.6g", delta_E) << " J\n";
    if (!a.energy_csv.empty()) {
      std::vector<EnergyRow> energy;
      for (int k = 0; k < n; ++k)
        energy.push_back({theta0 + k * step, dT[k] - (a.remove_mean ? loop.mean_torque : 0.0), E[k]});
      energy.push_back({theta0 + a.cycle_deg, dT[0] - (a.remove_mean ? loop.mean_torque : 0.0), loop.cycle_work});
      std::ostringstream csv;
      mechgen::WriteCsv(EnergyColumns(), energy, csv,
                        mechgen::Described(std::string(kTool) + " flywheel, from the torque table " + a.torque_csv +
                                           ": energy loop. Signs: excess_torque = T_d - T_l, the driving torque on the "
                                           "shaft minus the load's, + along the rotation"));
      energy_text = csv.str();
      out << "  energy loop written to " << a.energy_csv << " (angle_deg, excess_torque [N m], E [J])\n";
    }
  }
  const double omega = fw::RpmToRadPerSecond(a.rpm);
  out << "mean speed " << Format("%g", a.rpm) << " rpm = " << Format("%.6g", omega) << " rad/s\n";
  // What the figures below come from: only options (--areas), or a file too (--torque-csv):
  // a result that cannot mean anything is a usage error, or a failure located at the file.
  auto refuse = [&](const std::string& why) {
    return a.areas.empty() ? Fail(a.torque_csv + ": " + why) : Usage(why);
  };
  if (by_inertia) {
    const double I = Given(a.inertia) ? a.inertia : a.mass * a.gyration * a.gyration;
    if (!(I > 0 && std::isfinite(I)))
      return Usage("--mass x --gyration^2 = " + Format("%.6g", I) + " kg m^2: not a positive inertia (it underflows)");
    const double cs = fw::SpeedFluctuation(delta_E, I, omega);
    // A C_s of 2 or more puts w_min = w (1 - C_s/2) at or below 0: the machine stops, and the
    // linear estimate C_s = dE/(I w^2) no longer holds.
    if (!(cs < 2))
      return refuse("the flywheel I = " + Format("%.6g", I) + " kg m^2 is too small for dE = " + Format("%.6g", delta_E) +
                    " J at " + Format("%g", a.rpm) + " rpm: dE/(I w^2) " +
                    (std::isfinite(cs) ? "= " + Format("%.6g", cs) + " >= 2"
                                       : std::string("is beyond the range of numbers")) +
                    ", the speed would fall to zero");
    out << "flywheel I = " << Format("%.6g", I) << " kg m^2: C_s = dE/(I w^2) = " << Format("%.6g", cs) << " (speed "
        << Format("%.6g", a.rpm * (1 - cs / 2)) << " to " << Format("%.6g", a.rpm * (1 + cs / 2)) << " rpm)\n";
  } else {
    const double I = fw::RequiredInertia(delta_E, a.cs, omega);
    if (!std::isfinite(I))
      return refuse("the inertia dE/(C_s w^2) for dE = " + Format("%.6g", delta_E) + " J, C_s = " + Format("%.6g", a.cs) +
                    " at " + Format("%g", a.rpm) + " rpm is beyond the range of numbers");
    out << "C_s = " << Format("%.6g", a.cs) << ": required I = dE/(C_s w^2) = " << Format("%.6g", I) << " kg m^2\n";
  }
  if (!a.energy_csv.empty()) {
    std::string error;
    if (!WriteWhole(a.energy_csv, energy_text, &error)) return Fail(error);
  }
  std::cout << out.str();
  return 0;
}

// ---- wittenbauer ----

// The rows and columns of the Wittenbauer diagram CSV (with --design: the machine's samples
// plus the flywheel found).
struct DiagramRow {
  double angle_deg, I, T;
};
mechgen::table::Columns<DiagramRow> DiagramColumns(bool design) {
  mechgen::table::Columns<DiagramRow> columns;
  mechgen::table::Builder<DiagramRow> add(&columns);
  add.Number("angle_deg", "deg", "angle of the machine's shaft",
             [](const DiagramRow& r) { return r.angle_deg; });
  add.Number("I", "kg m^2",
             design ? "generalized inertia with the flywheel, I_m + I_f" : "generalized inertia",
             [](const DiagramRow& r) { return r.I; });
  add.Number("T", "J", design ? "kinetic energy, E + T0" : "kinetic energy",
             [](const DiagramRow& r) { return r.T; });
  return columns;
}
struct WittenbauerArgs {
  std::string csv, diagram_csv;
  bool design = false;
  double rpm = kUnset, cs = kUnset;
};

int RunWittenbauer(const WittenbauerArgs& a) {
  std::vector<std::vector<double>> rows;
  std::string error;
  if (!ReadCsv(a.csv, 3, 3, &rows, &error)) return Fail(error);
  const int n = static_cast<int>(rows.size());
  if (n < 2) return Fail(a.csv + ": need at least 2 samples");
  std::vector<double> angle(n), I(n), T(n);
  for (int k = 0; k < n; ++k) angle[k] = rows[k][0], I[k] = rows[k][1], T[k] = rows[k][2];
  std::ostringstream out;
  const double to_rpm = 60 / (2 * kPi);
  if (a.design) {
    if (!(a.rpm > 0)) return Usage("--design needs --rpm (the mean speed) > 0");
    if (!(a.cs > 0 && a.cs < 2)) return Usage("--design needs --cs, 0 < C_s < 2");
    const double omega = fw::RpmToRadPerSecond(a.rpm);
    const double omega_max = omega * (1 + a.cs / 2), omega_min = omega * (1 - a.cs / 2);
    // Columns: angle, I_m (machine), E (excess work from the first sample).
    const fw::WittenbauerDesign d = fw::DesignByWittenbauer(I.data(), T.data(), n, omega_max, omega_min);
    if (d.status == fw::WittenbauerStatus::kNonPositive)
      return Fail(a.csv + ": the machine's inertia I_m (column 2) must be >= 0");
    if (d.status != fw::WittenbauerStatus::kOk && d.status != fw::WittenbauerStatus::kNoFlywheelNeeded)
      return Fail(a.csv + ": bad samples or speeds");
    if (!(std::isfinite(d.I_flywheel) && std::isfinite(d.T0)))
      return Fail(a.csv + ": the flywheel I_f or T0 is beyond the range of numbers for these samples at " +
                  Format("%g", a.rpm) + " rpm");
    double E_max = T[0], E_min = T[0], I_mean = 0;
    for (int k = 0; k < n; ++k) {
      E_max = std::max(E_max, T[k]);
      E_min = std::min(E_min, T[k]);
      I_mean += I[k] / n;
    }
    out << "Wittenbauer design from " << n << " samples of (I_m, E) in " << a.csv << "\n";
    out << "  speeds " << Format("%.6g", omega_min * to_rpm) << " to " << Format("%.6g", omega_max * to_rpm)
        << " rpm (C_s = " << Format("%.6g", a.cs) << " about " << Format("%g", a.rpm) << " rpm)\n";
    out << "  tangent of slope w_max^2/2 = " << Format("%.6g", d.slope_max) << " touches at "
        << Format("%.6g", angle[d.k_max]) << " deg; of slope w_min^2/2 = " << Format("%.6g", d.slope_min) << " at "
        << Format("%.6g", angle[d.k_min]) << " deg\n";
    if (d.status == fw::WittenbauerStatus::kNoFlywheelNeeded) {
      out << "  no flywheel needed: the machine alone stays within these speeds (I_f = " << Format("%.6g", d.I_flywheel)
          << " kg m^2 < 0)\n";
    } else {
      out << "  flywheel I_f = " << Format("%.6g", d.I_flywheel) << " kg m^2, kinetic energy at "
          << Format("%.6g", angle[0]) << " deg T0 = " << Format("%.6g", d.T0) << " J\n";
    }
    const double I_loop = fw::RequiredInertia(E_max - E_min, a.cs, omega) - I_mean;
    if (!std::isfinite(I_loop) || !std::isfinite(I_mean))
      return Fail(a.csv + ": the energy loop's flywheel (E_max - E_min)/(C_s w^2) - mean I_m is beyond the range of "
                          "numbers");
    out << "  energy loop (I_m taken as its mean " << Format("%.6g", I_mean)
        << " kg m^2): I_f = " << Format("%.6g", I_loop) << " kg m^2 ("
        << (d.I_flywheel != 0 ? Format("%+.3g", 100 * (I_loop - d.I_flywheel) / std::abs(d.I_flywheel)) + "%"
                              : Format("%+.3g", I_loop - d.I_flywheel) + " kg m^2")
        << " against Wittenbauer)\n";
    for (int k = 0; k < n; ++k) I[k] += d.I_flywheel, T[k] += d.T0;
  } else {
    const fw::WittenbauerSpeeds w = fw::Wittenbauer(I.data(), T.data(), n);
    if (w.status == fw::WittenbauerStatus::kNonPositive)
      return Fail(a.csv + ": the inertia I (column 2) and kinetic energy T (column 3) must be > 0");
    if (w.status != fw::WittenbauerStatus::kOk) return Fail(a.csv + ": bad samples");
    if (!(std::isfinite(w.omega_max) && std::isfinite(w.omega_min) && w.omega_max + w.omega_min > 0))
      return Fail(a.csv + ": the speeds sqrt(2 T/I) are beyond the range of numbers");
    const double mid = 0.5 * (w.omega_max + w.omega_min);
    out << "Wittenbauer diagram of " << n << " samples of (I, T) in " << a.csv << "\n";
    out << "  w_max = " << Format("%.6g", w.omega_max) << " rad/s (" << Format("%.6g", w.omega_max * to_rpm)
        << " rpm) at " << Format("%.6g", angle[w.k_max]) << " deg, w_min = " << Format("%.6g", w.omega_min)
        << " rad/s (" << Format("%.6g", w.omega_min * to_rpm) << " rpm) at " << Format("%.6g", angle[w.k_min])
        << " deg\n";
    out << "  C_s = (w_max - w_min)/w_mid = " << Format("%.6g", (w.omega_max - w.omega_min) / mid) << "\n";
  }
  std::string diagram;
  if (!a.diagram_csv.empty()) {
    std::vector<DiagramRow> diagram_rows;
    for (int k = 0; k < n; ++k) diagram_rows.push_back({angle[k], I[k], T[k]});
    std::ostringstream csv;
    mechgen::WriteCsv(DiagramColumns(a.design), diagram_rows, csv,
                      mechgen::Described(std::string(kTool) + " wittenbauer, from the samples " + a.csv +
                                         (a.design ? ": Wittenbauer diagram with the flywheel found"
                                                   : ": Wittenbauer diagram")));
    std::string error;
    if (!WriteWhole(a.diagram_csv, csv.str(), &error)) return Fail(error);
    out << "  diagram (I, T) written to " << a.diagram_csv << "\n";
  }
  std::cout << out.str();
  return 0;
}

}  // namespace

// The limits of the options (--help lists them): SI units; a C_s = (w_max - w_min) / w_mean
// is below 2 for any motion that keeps turning.
constexpr double kMinRpm = 1e-3;       // below it w^2 (and so dE/(C_s w^2)) runs off the numbers
constexpr double kMaxRpm = 1e6;
constexpr double kMaxLength = 1e6;      // m
constexpr double kMaxMass = 1e9;        // kg
constexpr double kMaxInertia = 1e12;    // kg m^2
constexpr double kMaxScale = 1e12;      // J per unit area, N m per unit
constexpr double kMaxCycleDeg = 1e5;    // deg
// C_s from the smallest the flywheel tools size for (energy_loop.h: kMinSpeedFluctuation) to 2.
const mechgen::tools::NumberRange kCsRange{fw::kMinSpeedFluctuation, 2, false, true};

int main(int argc, char** argv) {
  namespace tools = mechgen::tools;
  CLI::App app{
      "mechgen_balance: engine balance table, rigid-rotor balancing, flywheel sizing "
      "by the energy loop (no mechanism model needed)."};
  app.footer(
      "Exit status: 0 done, 2 a usage error (an option, a value outside its range, options "
      "that do not go together), 1 bad data in a file or a failed computation; one line "
      "'mechgen_balance: error: ...' on stderr either way.");
  app.require_subcommand(1);

  bool csv = false;
  double rotating_ratio = 0;
  std::vector<std::string> layouts;
  CLI::App* table = app.add_subcommand("table",
                                       "primary/secondary shaking force and moment of "
                                       "multi-cylinder engine layouts");
  table->add_flag("--csv", csv, "CSV instead of the text table");
  table->add_option("--rotating-ratio", rotating_ratio,
                    "rotating mass per cylinder at the crank pin, over the reciprocating mass")
      ->check(tools::NumberValidator(tools::NonNegative(1e3)));
  table->add_option("--layout", layouts, "only these layouts (default: all presets)");
  std::vector<std::string> engine_files;
  table->add_option("--engine", engine_files,
                    "a layout of your own: a CSV file, one cylinder a line: throw angle [deg], "
                    "bank angle [deg], z [cylinder spacings] (named after the file)");

  CLI::App* layouts_command =
      app.add_subcommand("layouts", "the preset engine layouts (throw and bank angles, z) as CSV");

  RotorArgs rotor_args;
  CLI::App* rotor = app.add_subcommand("rotor", "static or two-plane balancing of a rigid rotor");
  rotor->add_option("--csv", rotor_args.csv, "unbalances: m [kg], r [m], angle [deg], z [m] a line")->required();
  rotor->add_option("--radius", rotor_args.radius, "correction radius [m] (both planes)")
      ->check(tools::NumberValidator(tools::Positive(kMaxLength)));
  rotor->add_option("--left-radius", rotor_args.left_radius, "correction radius, left plane [m]")
      ->check(tools::NumberValidator(tools::Positive(kMaxLength)));
  rotor->add_option("--right-radius", rotor_args.right_radius, "correction radius, right plane [m]")
      ->check(tools::NumberValidator(tools::Positive(kMaxLength)));
  rotor->add_option("--left", rotor_args.left, "left correction plane z [m] (two-plane balancing)")
      ->check(tools::NumberValidator(tools::Magnitude(kMaxLength)));
  rotor->add_option("--right", rotor_args.right, "right correction plane z [m]")
      ->check(tools::NumberValidator(tools::Magnitude(kMaxLength)));

  FlywheelArgs fly;
  CLI::App* flywheel = app.add_subcommand("flywheel", "flywheel sizing by the energy-loop method");
  flywheel->add_option("--areas", fly.areas,
                       "signed loop areas of the turning-moment diagram in order, e.g. "
                       "\"295,-685,40,-340,960,-270\"");
  flywheel->add_option("--scale", fly.scale, "J per unit area of the diagram")
      ->check(tools::NumberValidator(tools::Positive(kMaxScale)));
  flywheel->add_option("--torque-scale", fly.torque_scale, "N m per unit of the torque axis")
      ->check(tools::NumberValidator(tools::Positive(kMaxScale)));
  flywheel->add_option("--angle-scale", fly.angle_scale, "deg per unit of the angle axis")
      ->check(tools::NumberValidator(tools::Positive(kMaxCycleDeg)));
  flywheel->add_option("--torque-csv", fly.torque_csv,
                       "sampled excess torque: angle_deg, T_d - T_l [N m] (or angle_deg, T_d, T_l)");
  flywheel->add_option("--cycle-deg", fly.cycle_deg, "the cycle of --torque-csv [deg] (720: four-stroke)")
      ->check(tools::NumberValidator(tools::Positive(kMaxCycleDeg)))
      ->capture_default_str();
  flywheel->add_option("--energy-csv", fly.energy_csv,
                       "write the excess energy E over the cycle (with --torque-csv) to this CSV");
  flywheel->add_flag("--remove-mean", fly.remove_mean,
                     "take the load as the mean torque (subtract the mean of the excess torque)");
  flywheel->add_option("--rpm", fly.rpm, "mean speed [rev/min]")
      ->required()
      ->check(tools::NumberValidator(tools::Between(kMinRpm, kMaxRpm)));
  flywheel->add_option("--inertia", fly.inertia, "flywheel inertia [kg m^2] -> C_s")
      ->check(tools::NumberValidator(tools::Positive(kMaxInertia)));
  flywheel->add_option("--mass", fly.mass, "rotating mass [kg] (with --gyration) -> C_s")
      ->check(tools::NumberValidator(tools::Positive(kMaxMass)));
  flywheel->add_option("--gyration", fly.gyration, "radius of gyration [m]")
      ->check(tools::NumberValidator(tools::Positive(kMaxLength)));
  flywheel->add_option("--cs", fly.cs, "coefficient of fluctuation of speed -> required inertia")
      ->check(mechgen::tools::NumberValidator(kCsRange));

  WittenbauerArgs wit;
  CLI::App* wittenbauer = app.add_subcommand("wittenbauer",
                                             "Wittenbauer's diagram: speeds from (I, T), or with --design the flywheel "
                                             "from the machine's (I_m, E)");
  wittenbauer
      ->add_option("--csv", wit.csv,
                   "samples over a cycle: angle_deg, I [kg m^2], T [J]; with --design: "
                   "angle_deg, I_m [kg m^2], E [J] (excess work from the first sample)")
      ->required();
  wittenbauer->add_flag("--design", wit.design, "find the flywheel and T0 for --rpm and --cs");
  wittenbauer->add_option("--rpm", wit.rpm, "mean speed [rev/min] (--design)")
      ->check(tools::NumberValidator(tools::Between(kMinRpm, kMaxRpm)));
  wittenbauer->add_option("--cs", wit.cs, "coefficient of fluctuation of speed (--design)")
      ->check(mechgen::tools::NumberValidator(kCsRange));
  wittenbauer->add_option("--diagram-csv", wit.diagram_csv,
                          "write the diagram's points (angle_deg, I, T; with the flywheel for "
                          "--design) for runtime/tools/plot_wittenbauer.gnuplot");

  if (const int parsed = tools::Parse(&app, argc, argv, kTool); parsed >= 0)
    return parsed;
  if (table->parsed()) return RunTable(csv, rotating_ratio, layouts, engine_files);
  if (layouts_command->parsed()) return RunLayouts();
  if (rotor->parsed()) return RunRotor(rotor_args);
  if (flywheel->parsed()) return RunFlywheel(fly);
  if (wittenbauer->parsed()) return RunWittenbauer(wit);
  return Usage("a subcommand is required: table, layouts, rotor, flywheel or wittenbauer");
}
