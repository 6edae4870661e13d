// Shared helpers of the tests in tests/kinematics/: an independent Newton solver for the
// positions phi(q), sweeps over the input ranges, and finite differences of positions.
//
// These helpers are the *oracle path* of the kinematics tests. They use only the generated
// constraint function (EvalPhi: Phi and Phi_phi) to find positions; they never use the
// generated K, L, K_P or L_P, which are the quantities under test. Everything is generic
// over the generated traits struct `mech::<name>::Model` (sizes, names, functions).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace mechtest {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

template <class M>
using VecQ = Eigen::Matrix<double, M::kNq, 1>;
template <class M>
using VecPhi = Eigen::Matrix<double, M::kNphi, 1>;
template <class M>
using ParamsD = typename M::template ParamsT<double>;
template <class M>
using CoeffsD = typename M::template CoefficientsT<double>;

/// Scientific notation, for RecordProperty (std::to_string prints 1e-12 as 0.000000).
inline std::string Sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", x);
  return buf;
}

/// x wrapped to (-pi, pi]: compares angles that may differ by whole turns.
inline double WrapAngle(double x) { return std::remainder(x, kTwoPi); }

/// phi_a - phi_b with the angular coordinates wrapped (displacements are left alone).
template <class M>
VecPhi<M> PhiDifference(const VecPhi<M>& phi_a, const VecPhi<M>& phi_b) {
  VecPhi<M> d = phi_a - phi_b;
  for (int i = 0; i < M::kNphi; ++i) {
    if (M::kPhiIsAngle[i]) d(i) = WrapAngle(d(i));
  }
  return d;
}

/// Result of SolvePhi().
struct NewtonResult {
  bool converged = false;
  int iterations = 0;
  double residual = NAN;  ///< ||Phi(q, phi)||_inf at the returned phi
};

/**
 * Solves Phi(q, phi) = 0 for phi by Newton's method on the generated EvalPhi (Phi and
 * Phi_phi only), starting from *phi. Iterates until the Newton step is at rounding level
 * (||dphi||_inf <= 1e-15 (1 + ||phi||_inf)), then takes one more step, so phi is accurate to
 * a few ulps (||Phi|| ~ 1e-15) -- the accuracy the finite-difference step sizes assume.
 * Newton converges quadratically here: steps of the sweeps are <= 0.5 deg from a solved
 * configuration, and finite-difference offsets are <= 2e-4.
 */
template <class M>
NewtonResult SolvePhi(const ParamsD<M>& p, const VecQ<M>& q, VecPhi<M>* phi) {
  NewtonResult result;
  Eigen::Matrix<double, M::kNc, 1> Phi;
  Eigen::Matrix<double, M::kNc, M::kNphi> Phi_phi;
  int extra_steps = 0;
  for (int it = 0; it < 50; ++it) {
    M::Phi(p, q, *phi, &Phi, &Phi_phi);
    const VecPhi<M> dphi = Phi_phi.fullPivLu().solve(Phi);
    *phi -= dphi;
    result.iterations = it + 1;
    if (!dphi.allFinite()) break;
    if (dphi.template lpNorm<Eigen::Infinity>() <=
        1e-15 * (1.0 + phi->template lpNorm<Eigen::Infinity>())) {
      if (++extra_steps >= 1) {
        result.converged = true;
        break;
      }
    }
  }
  M::Phi(p, q, *phi, &Phi);
  result.residual = Phi.template lpNorm<Eigen::Infinity>();
  result.converged = result.converged && result.residual < 1e-13;
  return result;
}

/// A solved configuration.
template <class M>
struct Config {
  VecQ<M> q;
  VecPhi<M> phi;
};

/**
 * Follows the branch of *c from c->q to q_target in steps of at most max_step (rad) in
 * ||dq||_inf, solving at each step from the previous solution (natural continuation).
 * Returns false if a solve fails.
 */
template <class M>
bool Track(const ParamsD<M>& p,
           const VecQ<M>& q_target,
           Config<M>* c,
           double max_step = 0.5 * kPi / 180.0) {
  const VecQ<M> q0 = c->q;
  const double dist = (q_target - q0).template lpNorm<Eigen::Infinity>();
  const int n = std::max(1, static_cast<int>(std::ceil(dist / max_step)));
  for (int k = 1; k <= n; ++k) {
    c->q = q0 + (q_target - q0) * (static_cast<double>(k) / n);
    if (!SolvePhi<M>(p, c->q, &c->phi).converged) return false;
  }
  return true;
}

/// The model's assembly configuration, solved from its kAssemblyPhi guess.
template <class M>
Config<M> SolvedAssembly(const ParamsD<M>& p, bool* ok) {
  Config<M> c;
  for (int j = 0; j < M::kNq; ++j) c.q(j) = M::kAssemblyQ[j];
  for (int i = 0; i < M::kNphi; ++i) c.phi(i) = M::kAssemblyPhi[i];
  *ok = SolvePhi<M>(p, c.q, &c.phi).converged;
  return c;
}

/**
 * Solved configurations over the model's default input range, on its assembly branch.
 * One input: n_per_dof points over [kQMin, kQMax) (a full crank turn for the shipped
 * one-input models), reached by continuation from the assembly configuration.
 * Two inputs: an n_per_dof x n_per_dof grid over [kQMin, kQMax] (boustrophedon order, so
 * each grid point is tracked from its neighbour).
 * More inputs: n_per_dof uniform random points in the box (fixed seed), tracked in turn.
 * Returns an empty vector if a solve fails.
 */
template <class M>
std::vector<Config<M>> SweepConfigs(const ParamsD<M>& p, int n_per_dof) {
  std::vector<Config<M>> out;
  bool ok = false;
  Config<M> c = SolvedAssembly<M>(p, &ok);
  if (!ok) return {};
  if constexpr (M::kNq == 1) {
    const bool full_turn = M::kQIsAngle[0] && (M::kQMax[0] - M::kQMin[0]) >= kTwoPi - 1e-12;
    const double span = M::kQMax[0] - M::kQMin[0];
    for (int k = 0; k < n_per_dof; ++k) {
      VecQ<M> q;
      q(0) = M::kQMin[0] + span * k / (full_turn ? n_per_dof : n_per_dof - 1);
      if (!Track<M>(p, q, &c)) return {};
      out.push_back(c);
    }
  } else if constexpr (M::kNq == 2) {
    for (int r = 0; r < n_per_dof; ++r) {
      for (int s = 0; s < n_per_dof; ++s) {
        const int col = (r % 2 == 0) ? s : n_per_dof - 1 - s;
        VecQ<M> q;
        q(0) = M::kQMin[0] + (M::kQMax[0] - M::kQMin[0]) * r / (n_per_dof - 1);
        q(1) = M::kQMin[1] + (M::kQMax[1] - M::kQMin[1]) * col / (n_per_dof - 1);
        if (!Track<M>(p, q, &c)) return {};
        out.push_back(c);
      }
    }
  } else {
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < n_per_dof; ++k) {
      VecQ<M> q;
      for (int j = 0; j < M::kNq; ++j) q(j) = M::kQMin[j] + (M::kQMax[j] - M::kQMin[j]) * u(gen);
      if (!Track<M>(p, q, &c)) return {};
      out.push_back(c);
    }
  }
  return out;
}

/// Number of "positions" FD differentiates: phi, then the x, y of each point of interest.
template <class M>
constexpr int kNumPositions = M::kNphi + 2 * M::kNumPoints;
template <class M>
using VecPos = Eigen::Matrix<double, kNumPositions<M>, 1>;

/// Positions at q: phi solved by Newton from `start` (same branch), and the points of
/// interest r_P evaluated at that phi, stacked as [phi; x_0; y_0; x_1; ...] -- the layout of
/// the rows of [K; K_P] and [L; L_P].
template <class M>
VecPos<M> PositionsAt(const ParamsD<M>& p, const VecQ<M>& q, const VecPhi<M>& start, bool* ok) {
  VecPhi<M> phi = start;
  *ok = SolvePhi<M>(p, q, &phi).converged && *ok;
  CoeffsD<M> coeffs;
  M::Coeffs(p, q, phi, &coeffs);
  VecPos<M> out;
  out.template head<M::kNphi>() = phi;
  for (int m = 0; m < M::kNumPoints; ++m) {
    out(M::kNphi + 2 * m) = coeffs.r_P(0, m);
    out(M::kNphi + 2 * m + 1) = coeffs.r_P(1, m);
  }
  return out;
}

/// Central first differences of the positions: column j ~ d pos / d q_j, error O(h^2).
template <class M>
Eigen::Matrix<double, kNumPositions<M>, M::kNq> FirstDifferences(const ParamsD<M>& p,
                                                                 const Config<M>& c,
                                                                 double h,
                                                                 bool* ok) {
  Eigen::Matrix<double, kNumPositions<M>, M::kNq> D;
  for (int j = 0; j < M::kNq; ++j) {
    VecQ<M> qp = c.q, qm = c.q;
    qp(j) += h;
    qm(j) -= h;
    D.col(j) = (PositionsAt<M>(p, qp, c.phi, ok) - PositionsAt<M>(p, qm, c.phi, ok)) / (2 * h);
  }
  return D;
}

/// Central second differences of the positions: column j + kNq*k ~ d^2 pos / dq_j dq_k
/// = [f(+j+k) - f(+j-k) - f(-j+k) + f(-j-k)] / (4 h^2), error O(h^2) + O(eps/h^2).
/// (For j == k this is the three-point rule with step 2h.)
template <class M>
Eigen::Matrix<double, kNumPositions<M>, M::kNq * M::kNq> SecondDifferences(const ParamsD<M>& p,
                                                                           const Config<M>& c,
                                                                           double h,
                                                                           bool* ok) {
  Eigen::Matrix<double, kNumPositions<M>, M::kNq * M::kNq> D;
  for (int j = 0; j < M::kNq; ++j) {
    for (int k = 0; k < M::kNq; ++k) {
      auto at = [&](double sj, double sk) {
        VecQ<M> q = c.q;
        q(j) += sj * h;
        q(k) += sk * h;
        return PositionsAt<M>(p, q, c.phi, ok);
      };
      D.col(j + M::kNq * k) = (at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1)) / (4 * h * h);
    }
  }
  return D;
}

/// [K; K_P] stacked like the positions of PositionsAt().
template <class M>
Eigen::Matrix<double, kNumPositions<M>, M::kNq> StackedK(const CoeffsD<M>& c) {
  Eigen::Matrix<double, kNumPositions<M>, M::kNq> out;
  out.template topRows<M::kNphi>() = c.K;
  out.template bottomRows<2 * M::kNumPoints>() = c.K_P;
  return out;
}

/// [L; L_P] stacked like the positions of PositionsAt().
template <class M>
Eigen::Matrix<double, kNumPositions<M>, M::kNq * M::kNq> StackedL(const CoeffsD<M>& c) {
  Eigen::Matrix<double, kNumPositions<M>, M::kNq * M::kNq> out;
  out.template topRows<M::kNphi>() = c.L;
  out.template bottomRows<2 * M::kNumPoints>() = c.L_P;
  return out;
}

/// Row names of the stacked matrices, for failure messages.
template <class M>
std::string PositionName(int row) {
  if (row < M::kNphi) return M::kPhiNames[row];
  const int m = (row - M::kNphi) / 2;
  return std::string(M::kPointNames[m]) + ((row - M::kNphi) % 2 == 0 ? ".x" : ".y");
}

/// Index of a scene point by name ("link.point"), -1 if absent.
template <class M>
int ScenePointIndex(const std::string& name) {
  for (int s = 0; s < M::kNumScenePoints; ++s) {
    if (name == M::kScenePointNames[s]) return s;
  }
  return -1;
}

}  // namespace mechtest
