/**
 * \file machines/engine/crank_dynamics.h
 * The one-DOF crank dynamics of a reciprocating machine with cylinder gas forces (Paul
 * §6.8.3–6.8.4 and §6.9.1): run-up transients and the periodic steady state with a flywheel.
 *
 * The equation is the generated one of the model, I(θ) θ̈ + ½ I'(θ) θ̇² = Q(θ, θ̇, t), with the
 * gas forces added to Q by virtual work from the generated velocity coefficients: the gas
 * pushes piston j along its cylinder axis, away from the cylinder head, with the force
 * p_j A_j (p_j the gauge pressure, A_j the piston area), and the piston's slide s_j (one of the
 * model's dependent coordinates, measured outward from the crank along the axis) has
 * ds_j/dθ = K(s_j), so
 *     Q_gas(θ) = -Σ_j p_j(θ - phase_j) A_j K(s_j)(θ)        (N m on the crank, CCW +).
 * The pressure of cylinder j is a function of its own cycle angle θ - phase_j (phase_j: the
 * crank angle of its firing top dead centre), periodic over the cycle (4π for four-stroke,
 * 2π for two-stroke engines).
 *
 * GasDriven<M, Source> is MinimalDynamics (dynamics/forward.h) on the model M with Q_gas added
 * to its Q (and to P_nc, so that the energy balance T - W_nc stays an invariant) by the load
 * GasLoad<Source>, which each simulation holds by value (no shared state: simulations with
 * different gas laws run at once on several threads). Compiled and checked by tests/engine
 * (the steady cycle against the load) and used by <model>_engine (runtime/tools/engine_main.cc).
 *
 * FindSteadyCycle() finds the periodic steady state by shooting on the crank speed at the
 * start of a cycle: F(ω0) = ω(θ0 + Θ) - ω0 = 0 by the secant method (the map is nearly
 * linear: a cycle multiplies a speed perturbation by about exp(-c Θ / (I ω)) for a viscous
 * load c), then samples that cycle at equal time steps: ω_max, ω_min, their mean and the time
 * mean, C_s = (ω_max - ω_min) / ω_mean, and I(θ), T(θ) for Wittenbauer's diagram.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/dynamics/forward.h"

namespace mechgen::engine {

/// The cylinders of an engine model and their pressure law: the source of Q_gas.
/// Law: anything with `double Pressure(double cycle_angle) const` (gauge pressure, Pa, at the
/// cycle angle in rad, taken modulo the cycle).
template <class Law, int kMaxCylinders = 16>
struct GasTorque {
  struct Cylinder {
    int slide = -1;      ///< index in phi of the piston's slide s_j (outward along the axis)
    double area = 0;     ///< piston area A_j (m^2)
    double phase = 0;    ///< crank angle of the cylinder's firing top dead centre (rad)
  };
  const Law* law = nullptr;
  double cycle = 4 * kPi;  ///< the cycle's crank angle (rad): 4π four-stroke, 2π two-stroke
  std::array<Cylinder, kMaxCylinders> cylinders{};
  int count = 0;

  /// The cycle angle of cylinder j at crank angle theta, in [0, cycle).
  double CycleAngle(int j, double theta) const {
    double a = std::fmod(theta - cylinders[j].phase, cycle);
    if (a < 0) a += cycle;
    return a;
  }
  /// p_j (Pa, gauge) at crank angle theta.
  double Pressure(int j, double theta) const { return law->Pressure(CycleAngle(j, theta)); }
  /// Q_gas (N m on the crank, CCW +) at crank angle theta, from the velocity coefficients K
  /// (kNphi x 1) of that configuration.
  template <class KMatrix>
  double Torque(double theta, const KMatrix& K) const {
    double Q = 0;
    for (int j = 0; j < count; ++j) Q -= Pressure(j, theta) * cylinders[j].area * K(cylinders[j].slide, 0);
    return Q;
  }
};

/// The generalized force of Source (Source::Torque(theta, K), e.g. a GasTorque) on the one
/// input of a crank model: the Load of dynamics::MinimalDynamics. The source is held by value,
/// so each simulation has its own (two simulations with different gas laws can run at once).
template <class Source>
struct GasLoad {
  Source source;
  template <class VecQ, class MatK>
  void operator()(double /*t*/, const VecQ& q, const VecQ& /*qd*/, const MatK& K, VecQ* Q) const {
    static_assert(VecQ::RowsAtCompileTime == 1 || VecQ::RowsAtCompileTime == Eigen::Dynamic,
                  "GasLoad: one-DOF crank models only");  // (a view's: its one input at run time)
    (*Q)(0) = source.Torque(q(0), K);
  }
};

/// The minimal dynamics of crank model M with the gas torque of Source added to its Q (and to
/// P_nc, so that the energy balance T - W_nc stays an invariant). Construct with
/// (params, options, GasLoad<Source>{gas}).
template <class M, class Source, template <int> class Method = dynamics::Dopri5>
using GasDriven = dynamics::MinimalDynamics<M, Method, GasLoad<Source>>;

/// One sample of a steady cycle.
struct CyclePoint {
  double t = 0, theta = 0, omega = 0;
  double I = 0;  ///< generalized inertia I(θ) (kg m^2), flywheel included
  double T = 0;  ///< kinetic energy ½ I ω² (J)
};

struct SteadyCycleOptions {
  double theta0 = 0;          ///< crank angle where the cycle starts (rad)
  double cycle = 4 * kPi;     ///< its length (rad)
  double omega_guess = 0;     ///< the first guess of ω at theta0 (rad/s), > 0
  int max_shots = 20;         ///< secant iterations
  double tolerance = 1e-10;   ///< |ω(θ0 + Θ) - ω0| <= tolerance ω0
  int samples = 1440;         ///< samples of the final cycle (equal time steps)
  dynamics::IntegratorOptions integrator;
  SteadyCycleOptions() {
    integrator.rtol = 1e-11;
    integrator.atol = 1e-12;
  }
};

struct SteadyCycle {
  bool ok = false;
  std::string message;       ///< why not, with the figures
  int shots = 0;             ///< cycles simulated by the shooting
  double omega0 = 0;         ///< ω at theta0 on the periodic orbit (rad/s)
  double residual = 0;       ///< |ω(θ0 + Θ) - ω0| / ω0 of the last shot
  double period = 0;         ///< the cycle's duration (s)
  double omega_max = 0, omega_min = 0;
  double omega_mean_time = 0;  ///< Θ / period: the time mean of ω
  double omega_mean_mid = 0;   ///< (ω_max + ω_min) / 2
  double Cs = 0;               ///< (ω_max - ω_min) / omega_mean_time
  double theta_at_max = 0, theta_at_min = 0;
  std::vector<CyclePoint> points;
};

/// The periodic steady state of sim's model (a GasDriven model with a stabilizing load: a
/// speed-dependent load torque makes the mean speed a stable fixed point; with a constant load
/// equal to the mean gas torque every mean speed is periodic and the shooting reports so).
template <class Sim>
SteadyCycle FindSteadyCycle(Sim* sim, const SteadyCycleOptions& o) {
  using VecQ = typename Sim::VecQ;
  SteadyCycle out;
  char buf[256];
  if (!(o.omega_guess > 0) || !(o.cycle > 0)) {
    out.message = "FindSteadyCycle: omega_guess and cycle must be > 0";
    return out;
  }
  auto q0 = Sized<VecQ>(sim->Nq());
  q0(0) = o.theta0;
  if (!sim->Initialize(q0)) {
    out.message = "FindSteadyCycle: the model does not assemble at theta0";
    return out;
  }
  const double theta_end = o.theta0 + o.cycle;
  auto shoot = [&](double omega0, double* omega1, double* t1) -> bool {
    auto q = Sized<VecQ>(sim->Nq()), qd = Sized<VecQ>(sim->Nq());
    q(0) = o.theta0;
    qd(0) = omega0;
    sim->Initialize(q);
    dynamics::MinimalSummary summary;
    typename Sim::SampleT last;
    // A generous time bound: the cycle at a tenth of the starting speed.
    const double t_bound = 10 * o.cycle / omega0;
    sim->Simulate(0.0, q, qd, t_bound, [](const auto&) { return true; },
                  [&](double, const VecQ& qq, const VecQ&, const auto&) { return qq(0) - theta_end; },
                  &summary, &last);
    ++out.shots;
    if (summary.status != dynamics::Status::kStoppedByEvent || summary.event != dynamics::Event::kUser) {
      std::snprintf(buf, sizeof(buf),
                    "FindSteadyCycle: a cycle from omega0 = %.6g rad/s did not complete (%s): the "
                    "crank stalled or the integration failed",
                    omega0, dynamics::FormatSummary(summary).c_str());
      out.message = buf;
      return false;
    }
    *omega1 = last.qd(0);
    *t1 = last.t;
    return true;
  };
  double w0 = o.omega_guess, w1, t1;
  if (!shoot(w0, &w1, &t1)) return out;
  double F0 = w1 - w0;
  double wa = w0 * (1 + 1e-3), wb, tb;
  if (!shoot(wa, &wb, &tb)) return out;
  double Fa = wb - wa;
  double w = wa, F = Fa, t_cycle = tb;
  for (int k = 0; k < o.max_shots && std::abs(F) > o.tolerance * w; ++k) {
    const double slope = (Fa - F0) / (wa - w0);
    if (!(std::abs(slope) > 1e-14)) {
      std::snprintf(buf, sizeof(buf),
                    "FindSteadyCycle: the cycle-to-cycle speed map is neutral (dF/domega0 = %.3g): "
                    "the load does not fix the mean speed; give it a speed-dependent part",
                    slope);
      out.message = buf;
      return out;
    }
    const double w_new = wa - Fa / slope;
    if (!(w_new > 0)) {
      std::snprintf(buf, sizeof(buf),
                    "FindSteadyCycle: no periodic cycle with a positive speed (secant step to "
                    "%.6g rad/s): the load exceeds what the engine delivers",
                    w_new);
      out.message = buf;
      return out;
    }
    w0 = wa;
    F0 = Fa;
    wa = w_new;
    double wn, tn;
    if (!shoot(wa, &wn, &tn)) return out;
    Fa = wn - wa;
    w = wa;
    F = Fa;
    t_cycle = tn;
  }
  out.omega0 = w;
  out.residual = std::abs(F) / w;
  if (!(out.residual <= o.tolerance)) {
    std::snprintf(buf, sizeof(buf),
                  "FindSteadyCycle: no periodic cycle after %d shots: |omega(theta0 + cycle) - "
                  "omega0| / omega0 = %.3g > %.3g",
                  out.shots, out.residual, o.tolerance);
    out.message = buf;
    return out;
  }
  // Sample the periodic cycle.
  out.period = t_cycle;
  dynamics::MinimalOptions opts = sim->options();
  opts.sample_dt = t_cycle / o.samples;
  Sim sampler(sim->model(), sim->params(), opts, sim->load());
  auto q = Sized<VecQ>(sim->Nq()), qd = Sized<VecQ>(sim->Nq());
  q(0) = o.theta0;
  qd(0) = out.omega0;
  sampler.Initialize(q);
  out.points.reserve(o.samples + 2);
  dynamics::MinimalSummary summary;
  sampler.Simulate(
      0.0, q, qd, t_cycle,
      [&](const auto& s) {
        CyclePoint p;
        p.t = s.t;
        p.theta = s.q(0);
        p.omega = s.qd(0);
        p.T = s.T;
        p.I = p.omega != 0 ? 2 * s.T / (p.omega * p.omega) : 0;
        out.points.push_back(p);
        return true;
      },
      &summary);
  if (!summary.IsSolutionUsable() || out.points.size() < 3) {
    out.message = "FindSteadyCycle: sampling the periodic cycle failed: " + dynamics::FormatSummary(summary);
    return out;
  }
  out.omega_max = -1e300;
  out.omega_min = 1e300;
  for (const auto& p : out.points) {
    if (p.omega > out.omega_max) {
      out.omega_max = p.omega;
      out.theta_at_max = p.theta;
    }
    if (p.omega < out.omega_min) {
      out.omega_min = p.omega;
      out.theta_at_min = p.theta;
    }
  }
  out.omega_mean_time = o.cycle / t_cycle;
  out.omega_mean_mid = 0.5 * (out.omega_max + out.omega_min);
  out.Cs = (out.omega_max - out.omega_min) / out.omega_mean_time;
  out.ok = true;
  return out;
}

}  // namespace mechgen::engine
