/**
 * \file analysis/engine.h
 * The engine command's analyses (issue 43: one analysis layer for every tool): the cycle at
 * constant speed (cycle: the cycle CSV, the harmonics), the flywheel it needs (flywheel: the
 * energy loop, the C_s sweep, the Wittenbauer diagram; --design: the sensitivities) and the
 * run-up from idle (runup), asked for by an EngineRequest (analysis/engine_request.h),
 * written to EngineOutputs. Check(model, request) says what is wrong with the request on this
 * model; Run(model, request, outputs) computes, prints and writes the CSVs (each whole or
 * absent) from their column tables below (table/columns.h). One source for the per-model tool
 * <model>_engine (tools/engine_main.cc, M the generated model's type, fixed sizes) and for the
 * model view (M = ViewModel: runtime/view/analysis.cc, declared in analysis/view_analysis.h;
 * `mechgen_view engine`; its cycle and simulations compiled once in mechgen_runtime_view:
 * mechgen/machines/view_machines.h, runtime/view/machines.cc; flywheel --design's samples too:
 * RunCycleDesign). What it computes, its CSVs, signs and exit statuses: tools/engine_main.cc.
 *
 * --params/--set read the model's parameter table (analysis/view_params.h).
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "mechgen/analysis/engine_columns.h"
#include "mechgen/analysis/engine_request.h"
#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/io/format.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/machines/engine/couples.h"
#include "mechgen/machines/engine/cycle.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/gas.h"
#include "mechgen/machines/engine/harmonics.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/output_file.h"
#include "mechgen/table/columns.h"

namespace mechgen::analysis {
namespace engine_internal {

namespace eng = mechgen::engine;
namespace dyn = mechgen::dynamics;
constexpr double kPi = 3.14159265358979323846;

// The engine, its gas and its cycle at constant speed: mechgen/machines/engine/cycle.h (the
// same code as `mechgen study` with `analysis: engine`).
using eng::Engine;
using Law = eng::PressureLaw;
using Gas = eng::CycleGas;
template <class M>
using Point = eng::CrankPoint<M>;
template <class M>
using Params = typename ModelTypes<M>::Params;

/// Periodic linear interpolation of samples y over [0, cycle).
inline double Interp(const std::vector<double>& y, double cycle, double x) {
  const int n = static_cast<int>(y.size());
  double u = std::fmod(x, cycle) / cycle * n;
  if (u < 0) u += n;
  const int k = std::min(static_cast<int>(u), n - 1);
  const double f = u - k;
  return y[k] * (1 - f) + y[(k + 1) % n] * f;
}

// ---- the request: analysis/engine_request.h ---------------------------------------------------

using Args = EngineRequest;
namespace tools = mechgen::tools;

inline bool ReadTable(const std::string& path, double cycle, eng::PressureTable* t, std::string* error) {
  return eng::ReadPressureTable(path, cycle, t, error,
                                [](const std::string& s, double* x) { return tools::ParseField(s, x); });
}

/// Opened output files, committed together at the end (each whole or absent:
/// io/output_file.h); the CSVs are written by io/csv.h from the column tables below.
struct Outputs {
  std::vector<std::unique_ptr<mechgen::OutputFile>> files;
  std::ostream* Open(const std::string& path, std::string* error) {
    files.push_back(std::make_unique<mechgen::OutputFile>());
    if (!files.back()->Open(path, error)) return nullptr;
    return &files.back()->stream();
  }
  /// Every file closed (each write checked) before any is renamed into place: one that
  /// cannot be written leaves all the destinations as they were.
  bool Commit(std::string* error) {
    for (auto& f : files)
      if (!f->Close(error)) return false;
    for (auto& f : files)
      if (!f->Commit(error)) return false;
    return true;
  }
};

inline int Fail(const std::string& message) {
  std::fprintf(stderr, "engine: error: %s\n", message.c_str());
  return 1;
}

/// 0, or 1 with one line on stderr when the standard output cannot be written.
inline int FlushStdout() {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return 0;
  return Fail("cannot write the standard output");
}

// ---- the CSVs' column tables (table/columns.h) ----------------------------------------------

/// The cycle CSV's and the energy loop CSV's: analysis/engine_columns.h (the study reads them too).
template <class M>
mechgen::table::Columns<Point<M>> CycleColumns(const M& model, const Engine& e) {
  return EngineCycleColumns(model, e);
}
using LoopRow = EngineLoopRow;
inline mechgen::table::Columns<LoopRow> LoopColumns() { return EngineLoopColumns(); }

/// One row of the C_s against J_fly CSV.
struct CsRow {
  double J_fly = 0, Cs_energy_loop = 0, Cs_simulated = 0;
};
inline mechgen::table::Columns<CsRow> CsColumns() {
  mechgen::table::Columns<CsRow> columns;
  mechgen::table::Builder<CsRow> add(&columns);
  add.Number("J_fly", "kg m^2", "flywheel inertia", [](const CsRow& r) { return r.J_fly; });
  add.Number("Cs_energy_loop", "1", "(w_max - w_min)/w_mean from the energy loop",
             [](const CsRow& r) { return r.Cs_energy_loop; });
  add.Number("Cs_simulated", "1", "(w_max - w_min)/w_mean of the simulated steady cycle",
             [](const CsRow& r) { return r.Cs_simulated; });
  return columns;
}

/// One row of the Wittenbauer CSV: a point of the steady cycle.
using WittenbauerRow = eng::CyclePoint;
inline mechgen::table::Columns<WittenbauerRow> WittenbauerColumns() {
  using R = WittenbauerRow;
  mechgen::table::Columns<R> columns;
  mechgen::table::Builder<R> add(&columns);
  add.Number("theta_deg", "deg", "crank angle", [](const R& r) { return internal::ToDegrees(r.theta); });
  add.Number("t", "s", "time", [](const R& r) { return double(r.t); });
  add.Number("omega", "rad/s", "crank speed", [](const R& r) { return double(r.omega); });
  add.Number("I", "kg m^2", "generalized inertia I(theta)", [](const R& r) { return double(r.I); });
  add.Number("T_kin", "J", "kinetic energy", [](const R& r) { return double(r.T); });
  return columns;
}

/// One row of the run-up CSV.
struct RunupRow {
  double t, theta, omega, T_gas, T_load;
};
inline mechgen::table::Columns<RunupRow> RunupColumns() {
  using R = RunupRow;
  mechgen::table::Columns<R> columns;
  mechgen::table::Builder<R> add(&columns);
  add.Number("t", "s", "time", [](const R& r) { return r.t; });
  add.Number("theta_deg", "deg", "crank angle", [](const R& r) { return internal::ToDegrees(r.theta); });
  add.Number("omega", "rad/s", "crank speed", [](const R& r) { return r.omega; });
  add.Number("rpm", "1/min", "crank speed", [](const R& r) { return r.omega * 60 / (2 * kPi); });
  add.Number("T_gas", "N m", "gas torque on the crank, CCW +", [](const R& r) { return r.T_gas; });
  add.Number("T_load", "N m", "load torque on the crank, CCW + (negative: it brakes)",
             [](const R& r) { return r.T_load; });
  return columns;
}

/// The comment lines of every engine CSV (io/csv.h): the tool, the model, what the file
/// holds and the signs, then every column's unit and meaning.
inline mechgen::CsvOptions EngineCsvOptions(const char* name, const char* what) {
  return mechgen::Described(mechgen::CsvAbout(
      std::string(name) + "_engine", name, what,
      "torques on the crank CCW +; F_O: the frame on the crank; pin: the crank on the rod "
      "(x, y) and the rod on the crank pin (u, v); wrist: the rod on the piston; thrust, shake "
      "and rocking couple: on the frame; fixed frame x, y"));
}

}  // namespace engine_internal

/**
 * \brief The engine's cycle at the crank speed omega (rad/s) in `samples` crank angles under
 * the gas law (machines/engine/cycle.h's RunCycle: the rows of the cycle table, CycleColumns)
 * and its energy loop about the mean torque (EngineEnergyLoop: the loop table's rows,
 * EngineLoopColumns), with no I/O: the engine command's `flywheel` and the study's `analysis:
 * engine` (study/run.h) read these. False with *error when the cycle failed (*energy then
 * holds that message) or its loop did (*energy the loop's, with its message).
 */
template <class M>
bool EvaluateEngineCycle(const M& model, const typename ModelTypes<M>::Params& p, const engine::Engine& e,
                         const engine::CycleGas& gas, double omega, int samples,
                         std::vector<engine::CrankPoint<M>>* pts, engine::EngineEnergy* energy, std::string* error) {
  *energy = engine::EngineEnergy();
  // (unqualified: the view's, compiled once, found by its arguments: machines/view_machines.h)
  if (!RunCycle(model, p, e, gas, omega, samples, pts, error)) {
    energy->message = *error;
    return false;
  }
  *energy = engine::EngineEnergyLoop(*pts, e);
  if (!energy->ok()) {
    *error = energy->message;
    return false;
  }
  return true;
}

namespace engine_internal {

// ---- subcommands --------------------------------------------------------------------------

template <class M>
int Cycle(const M& model, const Args& a, const EngineOutputs& out, const Params<M>& p, const Engine& e, const Gas& gas) {
  using Point = Point<M>;
  const char* const name = ModelCalls<M>::Name(model);
  const double omega = a.rpm * 2 * kPi / 60;
  std::vector<Point> pts;
  std::string error;
  if (!RunCycle(model, p, e, gas, omega, a.samples, &pts, &error)) return Fail(error);
  Outputs outs;
  std::ostream* o = outs.Open(out.csv, &error);
  if (o == nullptr) return Fail(error);
  mechgen::WriteCsv(CycleColumns(model, e), pts, *o, EngineCsvOptions(name, "cycle at constant crank speed"));
  double max_check = 0, scale = 0;
  for (const Point& pt : pts) {
    max_check = std::max(max_check, std::abs(pt.drive + pt.T_total));
    scale = std::max(scale, std::abs(pt.T_total));
  }
  std::vector<double> T(pts.size()), T1(pts.size());
  double Tmax = -1e300, Tmin = 1e300;
  for (size_t i = 0; i < pts.size(); ++i) {
    T[i] = pts[i].T_total;
    T1[i] = pts[i].T1;
    Tmax = std::max(Tmax, T[i]);
    Tmin = std::min(Tmin, T[i]);
  }
  // The mean and the orders up to 8 times the crank speed (machines/engine/harmonics.h).
  const int count = (e.strokes == 4 ? 16 : 8) + 1;
  std::vector<eng::Harmonic> h(count), hg(1);
  const auto hs = eng::Analyze(T.data(), static_cast<int>(T.size()), e.cycle, 0.0, count, h.data());
  if (hs != eng::HarmonicsStatus::kOk) return Fail(std::string("harmonics: ") + eng::ToString(hs));
  std::vector<double> Tg(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) Tg[i] = pts[i].T_gas;
  eng::Analyze(Tg.data(), static_cast<int>(Tg.size()), e.cycle, 0.0, 1, hg.data());
  const double mean = h[0].a, mean_gas = hg[0].a;
  if (!outs.Commit(&error)) return Fail(error);
  std::printf("%s cycle at %.6g rpm (%d samples over %d deg), %d cylinder(s), %d-stroke\n", name,
              a.rpm, a.samples, e.strokes == 4 ? 720 : 360, e.n, e.strokes);
  std::printf("  mean torque %.6g N m (gas %.6g; inertia's mean %.3g), power %.6g kW\n", mean, mean_gas,
              mean - mean_gas, mean * omega / 1000);
  std::printf("  T_total max %.6g, min %.6g N m; max/mean %.4g; (max - min)/mean %.4g\n", Tmax, Tmin,
              Tmax / mean, (Tmax - Tmin) / mean);
  std::printf("  harmonics of T_total (order = multiple of the crank speed; amplitude N m):\n");
  for (int m = 1; m < count; ++m)
    if (h[m].amplitude > 1e-6 * std::max(1.0, std::abs(mean)))
      std::printf("    order %4.1f  %12.6g  (A cos(order theta - phi), phi %7.2f deg)\n", h[m].order,
                  h[m].amplitude, internal::ToDegrees(h[m].phase));
  std::printf("  power smoothing (Paul 6.8.5): k cylinders evenly spaced, each cylinder 1's torque\n"
              "  (its gas + its own inertia torque) shifted by cycle/k:\n");
  std::printf("    k   mean (N m)   max/mean   (max - min)/mean\n");
  for (int k = 1; k <= std::max(e.n, a.smoothing); ++k) {
    double mx = -1e300, mn = 1e300, sum = 0;
    const int n = static_cast<int>(pts.size());
    for (int i = 0; i < n; ++i) {
      double t = 0;
      for (int m = 0; m < k; ++m) t += Interp(T1, e.cycle, pts[i].theta - m * e.cycle / k);
      mx = std::max(mx, t);
      mn = std::min(mn, t);
      sum += t;
    }
    const double mk = sum / n;
    std::printf("    %-3d %11.5g %10.4g %14.4g\n", k, mk, mx / mk, (mx - mn) / mk);
  }
  if (ModelCalls<M>::HasShaking(model)) {
    // Orders 1 (primary), 2 (secondary), 4, 6 of the shaking force and moment (they repeat
    // every revolution at constant speed).
    const int per = e.strokes == 4 ? 2 : 1, cnt = 6 * per + 1;
    std::vector<double> fx(pts.size()), fy(pts.size()), mz(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      fx[i] = pts[i].shake_x;
      fy[i] = pts[i].shake_y;
      mz[i] = pts[i].shake_M;
    }
    std::vector<eng::Harmonic> hx(cnt), hy(cnt), hm(cnt);
    const int np = static_cast<int>(pts.size());
    eng::Analyze(fx.data(), np, e.cycle, 0.0, cnt, hx.data());
    eng::Analyze(fy.data(), np, e.cycle, 0.0, cnt, hy.data());
    eng::Analyze(mz.data(), np, e.cycle, 0.0, cnt, hm.data());
    std::printf("  shaking force on the frame F = -sum m a_G (N) and moment about O (N m), generated:\n");
    std::printf("    order   |F_x|         |F_y|         |M|\n");
    for (int order : {1, 2, 4, 6})
      std::printf("    %-5d %12.6g  %12.6g  %12.6g\n", order, hx[order * per].amplitude, hy[order * per].amplitude,
                  hm[order * per].amplitude);
    // The rocking couple (M_x, M_y): per order the largest magnitude over a turn (couples.h).
    std::vector<double> rx(pts.size()), ry(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      rx[i] = pts[i].rock_x;
      ry[i] = pts[i].rock_y;
    }
    std::vector<eng::Harmonic> hrx(cnt), hry(cnt);
    eng::Analyze(rx.data(), np, e.cycle, 0.0, cnt, hrx.data());
    eng::Analyze(ry.data(), np, e.cycle, 0.0, cnt, hry.data());
    double amp[2];
    for (int order : {1, 2}) {
      const eng::Harmonic &x = hrx[order * per], &y = hry[order * per];
      amp[order - 1] = mechgen::engine::CoupleOrderAmplitude(x.a, x.b, y.a, y.b);
    }
    Params<M> pz = p;
    const auto axial = mechgen::engine::LinkAxialPositions(model, pz);
    std::printf("  rocking couple about the cylinders' middle (z = %.6g m), max over a turn: primary %.6g N m, "
                "secondary %.6g N m\n",
                axial.z_mean, amp[0], amp[1]);
  }
  std::printf("  check: generated kinetostatics' drive + T_total, max %.3g N m (of %.3g)\n", max_check, scale);
  std::printf("  wrote %s\n", out.csv.c_str());
  return FlushStdout();
}

/// flywheel --design: d/dp of the figures of the energy loop of T_total, for the design
/// parameters of the model (its `design` section), the pressure trace p_j(theta) held:
/// dT_total/dp and dI/dp at each sample (mechgen/machines/engine/cycle.h, RunCycleDesign: the
/// generated EvalDesignDerivatives and EvalDynamicsDesign at the constant speed), then the
/// energy loop differentiated exactly (energy_loop.h, ExcessEnergyDerivative): dT_mean, d(dE),
/// dI = d(dE)/(C_s w^2), and dJ_fly = dI - d mean I(theta)/dp (+ 1 for J_fly itself, which the
/// variable part leaves out).
template <class M>
int PrintFlywheelDesign(const M& model, const Args& a, const Params<M>& p, const Engine& e, const Gas& gas,
                        const mechgen::flywheel::EnergyLoop& loop, const mechgen::flywheel::EnergyLoopOptions& lo_opt,
                        double omega, double I_req, double J_fly) {
  using C = ModelCalls<M>;
  const int n = loop.n, np = C::NumDesign(model);
  std::vector<double> dT, dI;  // sample k, parameter d at k np + d
  std::string error;
  // (unqualified: the view's, compiled once, found by its arguments)
  if (!RunCycleDesign(model, p, e, gas, omega, n, &dT, &dI, &error)) return Fail("--design: " + error);
  std::printf("  design sensitivities (the pressure trace held) of T_mean = %.17g N m, dE = %.17g J, "
              "I = %.17g kg m^2, J_fly = %.17g kg m^2, per unit of each parameter:\n",
              loop.mean_torque, loop.delta_E, I_req, J_fly);
  std::printf("    %-10s %16s %16s %16s %16s\n", "p", "dT_mean/dp", "d(dE)/dp", "dI/dp", "dJ_fly/dp");
  std::vector<double> column(static_cast<size_t>(n)), dE(static_cast<size_t>(n));
  for (int d = 0; d < np; ++d) {
    double mean_dI = 0;
    for (int k = 0; k < n; ++k) {
      const size_t at = static_cast<size_t>(k) * np + d;
      column[static_cast<size_t>(k)] = dT[at];
      mean_dI += dI[at] / n;
    }
    const auto dl = mechgen::flywheel::ExcessEnergyDerivative(column.data(), loop, 0.0, lo_opt, dE.data());
    const double dI_req = dl.delta_E / (a.cs * omega * omega);
    const char* const design_name = C::DesignName(model, d);
    const bool is_J_fly = std::string(design_name) == "J_fly";
    const double dJ = dI_req - (mean_dI - (is_J_fly ? 1.0 : 0.0));
    std::printf("    %-10s %16.9g %16.9g %16.9g %16.9g\n", design_name, dl.mean_torque, dl.delta_E, dI_req, dJ);
  }
  return 0;
}

template <class M>
int Flywheel(const M& model, const Args& a, const EngineOutputs& out, const Params<M>& p0, const Engine& e, const Gas& gas) {
  using C = ModelCalls<M>;
  using Sim = eng::GasDriven<M, Gas>;
  const char* const name = C::Name(model);
  const double omega = a.rpm * 2 * kPi / 60;
  std::vector<Point<M>> pts;
  std::string error;
  // The cycle and its energy loop about the mean (mechgen/machines/engine/cycle.h,
  // flywheel/energy_loop.h: the mean torque line is the load; E at the samples, the extremes
  // refined between them).
  eng::EngineEnergy energy;
  if (!EvaluateEngineCycle(model, p0, e, gas, omega, a.samples, &pts, &energy, &error)) return Fail(error);
  const int n = static_cast<int>(pts.size());
  const double dth = e.cycle / n;
  const auto& loop = energy.loop;
  const std::vector<double>& E = energy.E;
  mechgen::flywheel::EnergyLoopOptions lo_opt;
  lo_opt.remove_mean = true;
  const double mean = loop.mean_torque;
  const double dE = loop.delta_E, dEg = energy.loop_gas.delta_E;
  const double I_req = mechgen::flywheel::RequiredInertia(dE, a.cs, omega);
  const double I_recip = energy.I_recip;  // the mean of the variable part
  const double J_fly = I_req - I_recip;
  if (!std::isfinite(J_fly))
    return Fail("the flywheel dE/(C_s w^2) for dE = " + tools::FormatNumber(dE) + " J, C_s = " +
                tools::FormatNumber(a.cs) + " at " + tools::FormatNumber(a.rpm) + " rpm is beyond the range of numbers");
  if (!(J_fly > 0))
    return Fail("the reciprocating parts alone give C_s below the prescribed one: no flywheel needed");
  // --design: the sensitivities of these figures, printed first (they do not depend on the
  // simulated checks below).
  if (a.design && PrintFlywheelDesign(model, a, p0, e, gas, loop, lo_opt, omega, I_req, J_fly) != 0) return 1;
  // Simulation with that flywheel against c_load = mean / omega.
  auto simulate = [&](double J, eng::SteadyCycle* sc) {
    Params<M> p = p0;
    *C::FindParameter(model, &p, "J_fly") = J;
    *C::FindParameter(model, &p, "T_load") = 0;
    *C::FindParameter(model, &p, "c_load") = mean / omega;
    for (int j = 0; j < e.n; ++j) *C::FindParameter(model, &p, ("p_gas_" + std::to_string(j + 1)).c_str()) = 0;
    C::ParametersSet(model, &p);
    dyn::MinimalOptions mo;
    mo.integrator.rtol = 1e-10;
    mo.integrator.atol = 1e-10;
    Sim sim(model, p, mo, {gas});
    eng::SteadyCycleOptions so;
    so.cycle = e.cycle;
    so.omega_guess = omega;
    so.samples = a.samples;
    so.tolerance = 1e-9;
    *sc = FindSteadyCycle(&sim, so);  // (the view's compiled once: machines/view_machines.h)
    return sc->ok;
  };
  eng::SteadyCycle sc;
  if (!simulate(J_fly, &sc)) return Fail(sc.message);
  // Sweep of C_s against J_fly.
  Outputs outs;
  std::ostream* lo = outs.Open(out.loop_csv, &error);
  if (lo == nullptr) return Fail(error);
  std::vector<LoopRow> loop_rows;
  for (int i = 0; i <= n; ++i) loop_rows.push_back({dth * i, pts[i % n].T_total, mean, i < n ? E[i] : 0.0});
  mechgen::WriteCsv(LoopColumns(), loop_rows, *lo, EngineCsvOptions(name, "flywheel: energy loop"));
  std::ostream* so = outs.Open(out.sweep_csv, &error);
  if (so == nullptr) return Fail(error);
  std::vector<std::array<double, 3>> sweep;
  std::vector<CsRow> cs_rows;
  for (double f : {0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0}) {
    const double J = f * J_fly;
    eng::SteadyCycle s;
    if (!simulate(J, &s)) return Fail("sweep at J_fly = " + std::to_string(J) + ": " + s.message);
    sweep.push_back({J, dE / ((J + I_recip) * omega * omega), s.Cs});
    cs_rows.push_back({J, sweep.back()[1], s.Cs});
  }
  mechgen::WriteCsv(CsColumns(), cs_rows, *so, EngineCsvOptions(name, "flywheel: C_s against J_fly"));
  std::ostream* wo = outs.Open(out.witt_csv, &error);
  if (wo == nullptr) return Fail(error);
  mechgen::WriteCsv(WittenbauerColumns(), sc.points, *wo,
                    EngineCsvOptions(name, "flywheel: Wittenbauer, the simulated steady cycle"));
  if (!outs.Commit(&error)) return Fail(error);
  const double cs_gas_only = dEg / (I_req * omega * omega);
  std::printf("%s flywheel at %.6g rpm (omega %.6g rad/s), prescribed C_s = %.6g\n", name, a.rpm,
              omega, a.cs);
  std::printf("  mean torque %.6g N m (the load: c_load = %.6g N m s/rad)\n", mean, mean / omega);
  std::printf("  energy loop: dE = %.6g J (gas torque only: %.6g J)\n", dE, dEg);
  std::printf("  required I = dE/(C_s omega^2) = %.6g kg m^2; reciprocating parts' mean %.6g; J_fly = %.6g kg m^2\n",
              I_req, I_recip, J_fly);
  std::printf("  simulated steady cycle with that J_fly: C_s = %.6g (%+.2f %% of prescribed), omega %.6g..%.6g rad/s,"
              " mean %.6g, %d shots\n",
              sc.Cs, 100 * (sc.Cs / a.cs - 1), sc.omega_min, sc.omega_max, sc.omega_mean_time, sc.shots);
  std::printf("  neglecting I(theta) (gas torque only, constant I): C_s = %.6g (%+.2f %% of simulated)\n",
              cs_gas_only, 100 * (cs_gas_only / sc.Cs - 1));
  std::printf("  C_s against J_fly (energy loop / simulated):\n");
  for (const auto& s : sweep) std::printf("    J_fly %10.5g   %10.5g   %10.5g\n", s[0], s[1], s[2]);
  std::printf("  wrote %s, %s, %s\n", out.loop_csv.c_str(), out.sweep_csv.c_str(), out.witt_csv.c_str());
  return FlushStdout();
}

template <class M>
int Runup(const M& model, const Args& a, const EngineOutputs& out, const Params<M>& p0, const Engine& e, const Gas& gas) {
  using C = ModelCalls<M>;
  using Sim = eng::GasDriven<M, Gas>;
  using VecQ = typename Sim::VecQ;
  const double omega = a.rpm * 2 * kPi / 60;
  std::vector<Point<M>> pts;
  std::string error;
  if (!RunCycle(model, p0, e, gas, omega, std::min(a.samples, 720), &pts, &error)) return Fail(error);
  double mean_gas = 0;
  for (const Point<M>& pt : pts) mean_gas += pt.T_gas / pts.size();
  Params<M> p = p0;
  const double T_load = *C::FindParameter(model, &p, "T_load");
  const double c_load = (mean_gas - T_load) / omega;
  if (!(c_load > 0)) return Fail("the mean gas torque does not exceed T_load: the engine cannot run at --rpm");
  *C::FindParameter(model, &p, "c_load") = c_load;
  for (int j = 0; j < e.n; ++j) *C::FindParameter(model, &p, ("p_gas_" + std::to_string(j + 1)).c_str()) = 0;
  C::ParametersSet(model, &p);
  dyn::MinimalOptions mo;
  mo.integrator.rtol = 1e-8;
  mo.integrator.atol = 1e-10;
  // Samples fine enough to time the cycles (720 per cycle at the target speed); the CSV
  // gets one row every --dt.
  mo.sample_dt = std::min(a.dt, e.cycle / omega / 720);
  // Steady when the cycle-mean speed changed by less than --steady-tol of the last one over
  // two successive cycles (the simulator's detection, dynamics/simulator.h: cycles of the
  // crank angle from 0, e.cycle each).
  mo.steady.enabled = true;
  mo.steady.coordinate = 0;
  mo.steady.cycle = e.cycle;
  mo.steady.tolerance = a.steady_tol;
  mo.steady.consecutive = 2;
  Sim sim(model, p, mo, {gas});
  auto q = Sized<VecQ>(1), qd = Sized<VecQ>(1);
  q(0) = 0;
  qd(0) = (a.idle_rpm > 0 ? a.idle_rpm : a.rpm / 4) * 2 * kPi / 60;
  if (!sim.Initialize(q)) return Fail("the model does not assemble at theta = 0");
  std::vector<RunupRow> rows;
  // Each cycle's mean speed and the time it ended, as the simulator's detection reports them.
  std::vector<double> cycle_end, means;
  double next_row = 0;
  dyn::MinimalSummary summary;
  auto observer = [&](const typename Sim::SampleT& s) {
        if (s.t >= next_row - 1e-12 * a.t_end) {
          const double tg = gas.Torque(s.q(0), s.K);
          rows.push_back({s.t, s.q(0), s.qd(0), tg, -(T_load + c_load * s.qd(0))});
          next_row += a.dt;
        }
        if (summary.steady.cycles > static_cast<int>(means.size())) {
          cycle_end.push_back(summary.steady.t_crossing);
          means.push_back(summary.steady.mean_speed);
        }
        return true;
  };
  if constexpr (C::kView) {  // (the view's simulation, compiled once: machines/view_machines.h)
    dyn::ViewSampleFn<Sim> fn = observer;
    SimulateGasDriven(&sim, 0.0, q, qd, a.t_end, fn, &summary);
  } else {
    sim.Simulate(0.0, q, qd, a.t_end, observer, &summary);
  }
  const bool steady = summary.steady.steady;
  if (!summary.IsSolutionUsable()) return Fail("the run-up failed: " + dyn::FormatSummary(summary));
  if (means.empty()) return Fail("the run-up did not complete two cycles before --t-end");
  const double final_mean = means.back();
  double t99 = -1;
  for (size_t i = 0; i < means.size(); ++i)
    if (std::abs(means[i] - final_mean) <= 0.01 * final_mean) {
      t99 = cycle_end[i];
      break;
    }
  Outputs outs;
  std::ostream* o = outs.Open(out.csv, &error);
  if (o == nullptr) return Fail(error);
  mechgen::WriteCsv(RunupColumns(), rows, *o, EngineCsvOptions(C::Name(model), "run-up"));
  if (!outs.Commit(&error)) return Fail(error);
  std::printf("%s run-up from %.6g rpm against T_load %.6g N m + c_load %.6g N m s/rad (target %.6g rpm)\n",
              C::Name(model), qd(0) * 60 / (2 * kPi), T_load, c_load, a.rpm);
  std::printf("  %s at t = %.4g s after %d cycles: cycle mean speed %.6g rad/s (%.6g rpm)\n",
              steady ? "steady" : "not yet steady (--t-end)", rows.back().t, summary.steady.crossings, final_mean,
              final_mean * 60 / (2 * kPi));
  std::printf("  within 1 %% of the final speed from t = %.4g s\n", t99);
  std::printf("  mean gas torque %.6g N m, load at the final speed %.6g N m\n", mean_gas,
              T_load + c_load * final_mean);
  std::printf("  wrote %s\n", out.csv.c_str());
  return FlushStdout();
}

/// Reads the request against the model: the parameters (printed when set and `print`), the
/// engine (ReadEngine), the pressure table and the law. The error's text, empty when it fits;
/// *status the exit status it ends with (2 a usage error: the parameters, the table, the law;
/// 1 the model is no engine).
template <class M>
std::string Prepare(const M& model, const EngineRequest& a, bool print, Params<M>* p, Engine* e,
                    eng::PolytropicWiebeCycle* wiebe, eng::PressureTable* table, Law* law, int* status) {
  using C = ModelCalls<M>;
  std::string error;
  *status = tools::kExitUsage;
  *p = C::DefaultParams(model);
  if (!tools::ApplyModelParameters(a.params, model, p, &error)) return error;
  if (print) {
    if (const std::string changed = tools::ChangedModelParameters(model, *p); !changed.empty())
      std::printf("parameters set: %s\n", changed.c_str());
  }
  *status = 1;
  if (!ReadEngine(model, p, e, &error)) return error;
  if constexpr (C::kView) {  // (a generated model's tool is compiled only where it can)
    if (!eng::CanRunEngineCycle(model))
      return "the engine needs a model with `dynamics` and `forces` (reactions, no Coulomb friction), a "
             "position solve and one input (the crank)";
  }
  *status = tools::kExitUsage;
  if (!a.table.empty() && !ReadTable(a.table, e->cycle, table, &error)) return error;
  if (!eng::InitPressureLaw(*e, a.wiebe, a.table.empty() ? nullptr : table, wiebe, law, &error)) return error;
  *status = 0;
  return "";
}

/// What Prepare reads from a request and a model, for Check and Run alike.
template <class M>
struct Prepared {
  Params<M> p;
  Engine e;
  eng::PolytropicWiebeCycle wiebe;
  eng::PressureTable table;
  Law law;
  int status = 0;  ///< the exit status an error ends with (Prepare's)
};
template <class M>
std::string Prepare(const M& model, const EngineRequest& a, bool print, Prepared<M>* r) {
  return Prepare(model, a, print, &r->p, &r->e, &r->wiebe, &r->table, &r->law, &r->status);
}

}  // namespace engine_internal

/// What is wrong with `request` on `model` (one line), empty when Run can go on: the
/// parameters, the engine read from them (bore, r, l, strokes, ...), the pressure table and
/// the law's parameters.
template <class M>
std::string Check(const M& model, const EngineRequest& request) {
  engine_internal::Prepared<M> r;
  return engine_internal::Prepare(model, request, false, &r);
}

/**
 * \brief The engine command's analysis `request.command` (cycle, flywheel, runup) on `model`.
 * \tparam M  A generated engine model (the per-model tool) or mechgen::ViewModel.
 * \return The exit status (0, 1, 2: tools/engine_main.cc).
 */
template <class M>
int Run(const M& model, const EngineRequest& request, const EngineOutputs& outputs) {
  using namespace engine_internal;
  Prepared<M> r;
  if (const std::string error = Prepare(model, request, true, &r); !error.empty())
    return r.status == tools::kExitUsage ? tools::UsageError(outputs.tool, error) : Fail(error);
  const Gas gas = MakeGas(model, &r.p, r.e, &r.law);
  if (request.command == "cycle") return Cycle(model, request, outputs, r.p, r.e, gas);
  if (request.command == "flywheel") return Flywheel(model, request, outputs, r.p, r.e, gas);
  return Runup(model, request, outputs, r.p, r.e, gas);
}

}  // namespace mechgen::analysis
