/**
 * \file dynamics/energy.h
 * The energy integral of a one-DOF machine (Paul §6.5): when the generalized force depends on
 * the position only (weights, springs, constant or position-dependent loads: no dampers, no
 * motor curve of the speed, no time), I(q) qdd + 1/2 I'(q) qd^2 = Q(q) integrates once to
 *   1/2 I(q) qd^2 = T0 + W(q),   W(q) = integral from q0 to q of Q(s) ds
 * (= V(q0) - V(q) for a conservative machine), so that the speed is a function of the position,
 *   |qd|(q) = sqrt(2 (T0 + W(q)) / I(q)),
 * and the time from q0 to q1 is the quadrature t = integral dq / |qd| (no ODE solver; with
 * q = q0 + (q1 - q0) s^2, smooth when q0 is a turning point). A swing
 * between turning points q_lo < q_hi (T0 + W = 0 there) has the period
 *   P = 2 integral_{q_lo}^{q_hi} dq / |qd|,
 * computed with q = (q_lo + q_hi)/2 - (q_hi - q_lo)/2 cos u, which removes the inverse square
 * root singularities at the ends (the integrand is smooth in u), by Gauss–Legendre panels.
 * A check of the simulation, and a quick answer for conservative machines.
 *
 * Positions are solved by M::Solve, continued from the last solved configuration (quadrature
 * nodes are visited in order of q). W is accumulated by 8-point Gauss–Legendre panels of at
 * most Options::max_panel. Q is evaluated by M::Dynamics at qd = 0, t = 0. kNq = 1 only.
 * Allocation-free; nothing throws.
 */
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_traits.h"

namespace mechgen::dynamics {

struct EnergyOptions {
  /// Width of the Gauss–Legendre panels of W (input units: rad or m).
  double max_panel = 0.02;
  /// Turning points: scan steps of this width, then bisection to turning_tolerance.
  double scan_step = 0.01;
  double turning_tolerance = 1e-14;
  int max_solver_iterations = 20;
};

namespace internal {
// 8-point Gauss–Legendre on [-1, 1].
constexpr double kGL8x[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                             -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                             0.7966664774136267,  0.9602898564975363};
constexpr double kGL8w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                             0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                             0.2223810344533745, 0.1012285362903763};
}  // namespace internal

template <class M>
class EnergyIntegral {
 public:
  static_assert(M::kNq == 1, "the energy integral is for one-DOF machines");
  static constexpr int kNphi = M::kNphi;
  using Params = typename M::template ParamsT<double>;
  using Coefficients = typename M::template CoefficientsT<double>;
  using Dyn = typename M::template DynamicsT<double>;
  using Vec1 = Eigen::Matrix<double, 1, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using Modes = std::array<int, M::kNumBlocks>;

  explicit EnergyIntegral(const Params& p, const EnergyOptions& options = EnergyOptions())
      : p_(p), options_(options) {}

  /// The motion through (q0, qd0); phi_guess and modes pick the assembly. false if it does not
  /// assemble there.
  bool Initialize(double q0, double qd0, const VecPhi& phi_guess,
                  const Modes& modes = M::kDefaultModes) {
    modes_ = modes;
    q0_ = q0;
    phi_last_ = phi_guess;
    q_last_ = q0;
    K_last_.setZero();
    double I = 0, Q = 0;
    if (!Evaluate(q0, &I, &Q)) return false;
    phi0_ = phi_last_;
    K0_ = K_last_;
    T0_ = 0.5 * I * qd0 * qd0;
    return true;
  }
  bool Initialize(double q0, double qd0) {
    VecPhi guess;
    for (int i = 0; i < kNphi; ++i) guess(i) = M::kAssemblyPhi[i];
    return Initialize(q0, qd0, guess);
  }

  double T0() const { return T0_; }

  /// W(q) = integral from q0 to q of Q (position-dependent part). false if positions fail.
  bool Work(double q, double* W) {
    Restart();
    return Accumulate(q0_, q, W);
  }

  /// Kinetic energy T(q) = T0 + W(q) and |qd|(q) (0 where T <= 0: not reached).
  bool Speed(double q, double* qd_abs, double* T = nullptr) {
    double W = 0, I = 0, Q = 0;
    if (!Work(q, &W) || !Evaluate(q, &I, &Q)) return false;
    const double kinetic = T0_ + W;
    if (T != nullptr) *T = kinetic;
    *qd_abs = kinetic > 0 ? std::sqrt(2 * kinetic / I) : 0.0;
    return true;
  }

  /// Time from q0 to q1 along the motion (|qd| > 0 on the way: no turning point in between;
  /// false otherwise), by Gauss–Legendre panels of dq / |qd|.
  bool Time(double q1, double* t) {
    // q = q0 + (q1 - q0) s^2: smooth in s even when q0 is a turning point (T ~ (q - q0) there).
    Restart();
    const double span = q1 - q0_;
    const int panels = std::max(4, static_cast<int>(std::ceil(std::abs(span) / options_.max_panel)));
    const double h = 1.0 / panels;
    double W = 0, sum = 0;
    double q_prev = q0_;
    for (int k = 0; k < panels; ++k) {
      for (int i = 0; i < 8; ++i) {
        const double sn = h * (k + 0.5 * (1 + internal::kGL8x[i]));
        const double q = q0_ + span * sn * sn;
        double dW = 0, I = 0, Q = 0;
        if (!Accumulate(q_prev, q, &dW)) return false;
        W += dW;
        q_prev = q;
        if (!Evaluate(q, &I, &Q)) return false;
        const double kinetic = T0_ + W;
        if (!(kinetic > 0)) return false;
        sum += 0.5 * h * internal::kGL8w[i] * 2 * std::abs(span) * sn / std::sqrt(2 * kinetic / I);
      }
    }
    *t = sum;
    return true;
  }

  /// The turning points around q0: T0 + W(q) = 0, scanning at most `span` each way.
  bool TurningPoints(double span, double* q_lo, double* q_hi) {
    return Turning(-1, span, q_lo) && Turning(+1, span, q_hi);
  }

  /// Period of the swing between the turning points (false when it revolves within `span`).
  bool SwingPeriod(double span, int panels, double* period, double* q_lo = nullptr,
                   double* q_hi = nullptr) {
    double lo = 0, hi = 0;
    if (!TurningPoints(span, &lo, &hi)) return false;
    if (q_lo != nullptr) *q_lo = lo;
    if (q_hi != nullptr) *q_hi = hi;
    const double mid = 0.5 * (lo + hi), r = 0.5 * (hi - lo);
    // W is accumulated from q0 to the first node, then node to node (q increases with u).
    Restart();
    double W = 0, q_prev = q0_, sum = 0;
    const double du = kPi / panels;
    for (int k = 0; k < panels; ++k) {
      for (int i = 0; i < 8; ++i) {
        const double u = du * (k + 0.5 * (1 + internal::kGL8x[i]));
        const double q = mid - r * std::cos(u);
        double dW = 0, I = 0, Q = 0;
        if (!Accumulate(q_prev, q, &dW)) return false;
        W += dW;
        q_prev = q;
        if (!Evaluate(q, &I, &Q)) return false;
        const double kinetic = T0_ + W;
        if (!(kinetic > 0)) return false;
        sum += 0.5 * du * internal::kGL8w[i] * r * std::sin(u) / std::sqrt(2 * kinetic / I);
      }
    }
    *period = 2 * sum;
    return true;
  }

 private:
  void Restart() {
    q_last_ = q0_;
    phi_last_ = phi0_;
    K_last_ = K0_;
  }

  /// I(q) and Q(q) (qd = 0, t = 0); positions continued from the last solved configuration.
  bool Evaluate(double q, double* I, double* Q) {
    const Vec1 qv(q);
    VecPhi phi = phi_last_ + K_last_ * (q - q_last_);
    if constexpr (kNphi > 0) {
      const auto report = M::template Solve<double>(p_, qv, &phi, modes_,
                                                    options_.max_solver_iterations, 0.0);
      if (report.status != decltype(report.status)::kConverged || !phi.allFinite()) return false;
    }
    Coefficients c;
    M::template Coeffs<double>(p_, qv, phi, &c);
    Dyn d;
    M::template Dynamics<double>(p_, qv, phi, Vec1(0.0), 0.0, c, &d);
    if constexpr (kNphi > 0) K_last_ = c.K;
    phi_last_ = phi;
    q_last_ = q;
    *I = d.I(0, 0);
    *Q = d.Q(0);
    return std::isfinite(*I) && std::isfinite(*Q) && *I > 0;
  }

  /// W from a to b by 8-point Gauss–Legendre panels (positions continued along the way).
  bool Accumulate(double a, double b, double* W) {
    *W = 0;
    if (a == b) return true;
    const int panels = std::max(1, static_cast<int>(std::ceil(std::abs(b - a) / options_.max_panel)));
    const double h = (b - a) / panels;
    for (int k = 0; k < panels; ++k) {
      for (int i = 0; i < 8; ++i) {
        const double q = a + k * h + 0.5 * h * (1 + internal::kGL8x[i]);
        double I = 0, Q = 0;
        if (!Evaluate(q, &I, &Q)) return false;
        *W += 0.5 * h * internal::kGL8w[i] * Q;
      }
    }
    // Leave the continuation at b.
    double I = 0, Q = 0;
    return Evaluate(b, &I, &Q);
  }

  bool Turning(int direction, double span, double* q_turn) {
    Restart();
    double W = 0, q = q0_;
    const double step = direction * options_.scan_step;
    for (double travelled = 0; travelled < span; travelled += options_.scan_step) {
      double dW = 0;
      if (!Accumulate(q, q + step, &dW)) return false;
      if (T0_ + W + dW <= 0) {
        // Bisection on [q, q + step] for T0 + W(s) = 0.
        double a = q, b = q + step;
        while (std::abs(b - a) > options_.turning_tolerance &&
               std::abs(b - a) > 4 * std::numeric_limits<double>::epsilon() * std::abs(a)) {
          const double m = 0.5 * (a + b);
          Restart();
          double W_m = 0;
          if (!Accumulate(q0_, m, &W_m)) return false;
          (T0_ + W_m > 0 ? a : b) = m;
        }
        *q_turn = 0.5 * (a + b);
        return true;
      }
      W += dW;
      q += step;
    }
    return false;
  }

  Params p_;
  EnergyOptions options_;
  Modes modes_ = M::kDefaultModes;
  double q0_ = 0, T0_ = 0, q_last_ = 0;
  VecPhi phi0_ = VecPhi::Zero(), phi_last_ = VecPhi::Zero();
  Eigen::Matrix<double, kNphi, 1> K0_ = VecPhi::Zero(), K_last_ = VecPhi::Zero();
};

}  // namespace mechgen::dynamics
