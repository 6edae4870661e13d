// The derivative along the motion, written once. With x = (q, phi) and V = dx/dq = [I; K],
// an expression f(q, phi) changes with q_j as
//   K_f(j) = sum_a df/dx_a V(a, j)                                   (Along),
// and its second derivative is
//   L_f(j, k) = sum_ab d2f/dx_a dx_b V(a, j) V(b, k) + sum_i df/dphi_i L(i, j, k).
// K and L come from where the caller keeps them: the table's own named locals (K and L of
// EvalCoefficients, the points), or the slots c.K, c.L that the statics and dynamics read
// from EvalCoefficients' output (symbolic/slot.h). A Motion is only the rule; it holds no
// quantity.
#pragma once

#include <ginac/ginac.h>

#include <functional>
#include <vector>

#include "analysis/kinematics.h"

namespace mechgen {

class Motion {
 public:
  using KFn = std::function<GiNaC::ex(int i, int j)>;
  using LFn = std::function<GiNaC::ex(int i, int j, int k)>;  ///< called with j <= k
  /// `K(i, j)` and `L(i, j, k)` give the coefficients of phi_i (L may be empty when only
  /// first derivatives are taken).
  Motion(const Kinematics& k, KFn K, LFn L = {});
  /// Over other inputs than the model's q: `inputs` are the independent variables (the
  /// model's q, then design parameters, symbolic/design.h), `phi` the dependent ones, and
  /// K(i, j) = dphi_i/d input_j.
  Motion(std::vector<GiNaC::symbol> inputs, const std::vector<GiNaC::symbol>& phi, KFn K, LFn L = {});

  int nq() const { return nq_; }
  int nx() const { return static_cast<int>(x_.size()); }
  /// x_a: q then phi.
  const GiNaC::symbol& x(int a) const { return x_[a]; }
  /// V(a, j) = dx_a/dq_j: 1 or 0 for a < nq, K(a - nq, j) after.
  GiNaC::ex V(int a, int j) const;
  /// L(i, j, k) of phi_i, in either order of j and k.
  GiNaC::ex L(int i, int j, int k) const;

  /// df/dq_j along the motion: sum_a df/dx_a V(a, j).
  GiNaC::ex Along(const GiNaC::ex& f, int j) const;
  /// K_f(j) = Along(f, j) for every j.
  std::vector<GiNaC::ex> VelocityCoefficients(const GiNaC::ex& f) const;
  /// L_f(j + nq k) = d/dq_k of K_f(j): Along(K_f(j), k) + sum_i df/dphi_i L(i, j, k), from K_f
  /// (the nested form: K_f's expressions are differentiated again).
  std::vector<GiNaC::ex> CentripetalCoefficients(const GiNaC::ex& f, const std::vector<GiNaC::ex>& K_f) const;
  /// d2f/dq_j dq_k along the motion from the second partial derivatives of f (the expanded
  /// form: sum_ab d2f/dx_a dx_b V(a, j) V(b, k) + sum_i df/dphi_i L(i, j, k)).
  GiNaC::ex Second(const GiNaC::ex& f, int j, int k) const;
  /// df/dt = sum_a df/dx_a xdot_a for the velocities xdot of x.
  GiNaC::ex Rate(const GiNaC::ex& f, const std::vector<GiNaC::ex>& xdot) const;

 private:
  int nq_ = 0;
  std::vector<GiNaC::symbol> x_;
  KFn K_;
  LFn L_;
};

}  // namespace mechgen
