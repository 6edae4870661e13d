/**
 * \file position/internal/coefficients.h
 * K, L and the points of a closed configuration: from Model::Coeffs, or K = -Phi_phi^{-1}
 * Phi_q and L from the derivatives of Phi_phi and Phi_q along the motion (NumericalL: one
 * evaluation of Phi in dual numbers, or central differences for a large model) when the model
 * lacks them. After a closed-form Model::Solve that handed out the sin and cos of its angles
 * (Model::TrigT), Phi, Phi_phi, Phi_q and L come from Model::Coeffs in dual numbers seeded
 * with them instead: no sin or cos is called (PhiDerivatives::kFromTrig).
 * Part of PositionSolver (position/solver.h, which includes this file after the class).
 */
#pragma once

#include "mechgen/position/solver.h"

namespace mechgen::position {

template <class M, class Assembler>
struct PositionSolver<M, Assembler>::PhiDerivatives {
  // A[i] = dPhi_phi/dx_i, B[i] = dPhi_q/dx_i, x = (q, phi); empty unless kDualL.
  static constexpr int kCount = kDualL ? kDualN : 0;
  std::array<MatCPhi, kCount> A;
  std::array<MatCQ, kCount> B;
  // Or (A and B unused): the sin and cos of the angles from the Model::Solve that gave phi,
  // with which Model::Coeffs evaluates Phi and Phi_phi without calling sin or cos. Then
  // EvalPhiWithDerivatives() takes Phi_q from Model::Coeffs in Dual<kNq> (one direction per
  // input q_k), and NumericalL() the second derivatives Phi''(v_j, v_k) along the motion
  // v_k = (e_k, K e_k) from Model::Coeffs in HyperDual<kNq>: two evaluations of a few
  // dozen operations instead of Model::Phi in Dual<kNq + kNphi> with its sin and cos. For a
  // model whose coefficients have Phi and neither K nor L, with at most 4 inputs (HyperDual's
  // kNq^2 second derivatives). (Coeffs reads each angle's sin and cos from trig, and the
  // coordinates themselves where they enter otherwise: both carry their derivatives.)
  using Trig = typename internal::TrigOf<M>::type;
  static constexpr bool kFromTrig = kDualL && Features::kHasTrig && Features::kCoeffsHavePhi &&
                                    !Features::kHasK && M::kNq <= 4;
  const Trig* trig = nullptr;
  // The sin and cos of trig in Scalar (Dual or HyperDual): angle input q_k moving along w_q
  // (column k: direction k) and angle phi_j along w_phi, on straight lines:
  // sin(x0 + w t) = s + c w t - s (w t)^2 / 2 + ..., cos likewise; set() writes the
  // derivatives. Entries of displacement coordinates are left 0 (Scalar's default):
  // Model::Solve does not write them, Model::Coeffs does not read them.
  template <class Scalar, class SetSlope>
  static typename internal::TrigOf<M, Scalar>::type Seed(const Trig& t, SetSlope set) {
    typename internal::TrigOf<M, Scalar>::type r;
    for (int k = 0; k < M::kNq; ++k) {
      if (!M::kQIsAngle[static_cast<size_t>(k)]) continue;
      r.sin_q(k) = Scalar(t.sin_q(k));
      r.cos_q(k) = Scalar(t.cos_q(k));
      set(&r.sin_q(k), &r.cos_q(k), k, true);
    }
    for (int j = 0; j < M::kNphi; ++j) {
      if (!M::kPhiIsAngle[static_cast<size_t>(j)]) continue;
      r.sin_phi(j) = Scalar(t.sin_phi(j));
      r.cos_phi(j) = Scalar(t.cos_phi(j));
      set(&r.sin_phi(j), &r.cos_phi(j), j, false);
    }
    return r;
  }
};

template <class M, class Assembler>
void PositionSolver<M, Assembler>::EvalPhiWithDerivatives(
    const VecQ& q, const VecPhi& phi, VecC* Phi, MatCPhi* Phi_phi, MatCQ* Phi_q,
    PhiDerivatives* d, const typename internal::TrigOf<M>::type* trig) const {
  if constexpr (PhiDerivatives::kFromTrig) {
    if (trig != nullptr) {
      // Phi and Phi_phi (the values) and Phi_q (the derivatives of Phi) from Model::Coeffs in
      // Dual<kNq>: q_k along e_k, phi fixed.
      using D = internal::Dual<M::kNq>;
      using TD = ModelTypes<M, D>;
      const typename TD::Params p = params_.template Cast<D>();
      typename TD::VecQ qd;
      typename TD::VecPhi phid;
      for (int k = 0; k < M::kNq; ++k) qd(k) = D::Variable(q(k), k);
      for (int j = 0; j < M::kNphi; ++j) phid(j) = D(phi(j));
      const auto trig_d = PhiDerivatives::template Seed<D>(
          *trig, [](D* sin_x, D* cos_x, int k, bool is_q) {
            if (!is_q) return;  // phi fixed
            sin_x->d[k] = cos_x->v;
            cos_x->d[k] = -sin_x->v;
          });
      typename TD::Coefficients c;
      M::template Coeffs<D>(p, qd, phid, &c, &trig_d);
      for (int r = 0; r < M::kNc; ++r) {
        (*Phi)(r) = c.Phi(r).v;
        for (int k = 0; k < M::kNq; ++k) (*Phi_q)(r, k) = c.Phi(r).d[k];
        for (int j = 0; j < M::kNphi; ++j) (*Phi_phi)(r, j) = c.Phi_phi(r, j).v;
      }
      d->trig = trig;
      return;
    }
  } else {
    (void)trig;
  }
  if constexpr (kDualL) {
    using D = internal::Dual<kDualN>;
    using TD = ModelTypes<M, D>;
    const typename TD::Params p = params_.template Cast<D>();
    typename TD::VecQ qd;
    typename TD::VecPhi phid;
    for (int k = 0; k < M::kNq; ++k) qd(k) = D::Variable(q(k), k);
    for (int j = 0; j < M::kNphi; ++j) phid(j) = D::Variable(phi(j), M::kNq + j);
    typename TD::VecC Phi_d;
    typename TD::MatCPhi A_d;
    typename TD::MatCQ B_d;
    M::template Phi<D>(p, qd, phid, &Phi_d, &A_d, &B_d);
    for (int r = 0; r < M::kNc; ++r) {
      (*Phi)(r) = Phi_d(r).v;
      for (int c = 0; c < M::kNphi; ++c) {
        (*Phi_phi)(r, c) = A_d(r, c).v;
        for (int i = 0; i < kDualN; ++i) d->A[static_cast<size_t>(i)](r, c) = A_d(r, c).d[i];
      }
      for (int c = 0; c < M::kNq; ++c) {
        (*Phi_q)(r, c) = B_d(r, c).v;
        for (int i = 0; i < kDualN; ++i) d->B[static_cast<size_t>(i)](r, c) = B_d(r, c).d[i];
      }
    }
  } else {
    (void)d;
    Calls::Phi(model_, params_, q, phi, Phi, Phi_phi, Phi_q);
  }
}

template <class M, class Assembler>
void PositionSolver<M, Assembler>::NumericalL(const VecQ& q, const VecPhi& phi, const Factorization& f,
                                   const typename T::MatK& K, typename T::MatL* L,
                                   const PhiDerivatives* d) const {
  // K = -Phi_phi^{-1} Phi_q  =>  dK/dq_k = -Phi_phi^{-1} (D_k Phi_phi K + D_k Phi_q), where
  // D_k is the total derivative along the motion (dq, dphi) = (e_k, K e_k). Uses the step's
  // factorization of Phi_phi.
  if constexpr (PhiDerivatives::kFromTrig) {
    if (d != nullptr && d->trig != nullptr) {
      // D_k Phi_phi K e_j + D_k Phi_q e_j = Phi''(v_k, v_j): the second derivatives of Phi from
      // Model::Coeffs in HyperDual<kNq>, every coordinate on the line x + sum_k v_k t_k.
      using H = internal::HyperDual<M::kNq>;
      using TH = ModelTypes<M, H>;
      const typename TH::Params p = params_.template Cast<H>();
      typename TH::VecQ qh;
      typename TH::VecPhi phih;
      for (int k = 0; k < M::kNq; ++k) {
        qh(k) = H(q(k));
        qh(k).d[k] = 1;
      }
      for (int j = 0; j < M::kNphi; ++j) {
        phih(j) = H(phi(j));
        for (int k = 0; k < M::kNq; ++k) phih(j).d[k] = K(j, k);
      }
      const auto trig_h = PhiDerivatives::template Seed<H>(
          *d->trig, [&K](H* sin_x, H* cos_x, int i, bool is_q) {
            double w[M::kNq];  // the coordinate's direction along t
            for (int k = 0; k < M::kNq; ++k) w[k] = is_q ? (k == i ? 1.0 : 0.0) : K(i, k);
            const double s = sin_x->v, c = cos_x->v;
            for (int k = 0; k < M::kNq; ++k) {
              sin_x->d[k] = c * w[k];
              cos_x->d[k] = -s * w[k];
              for (int l = 0; l < M::kNq; ++l) {
                sin_x->dd[k][l] = -s * w[k] * w[l];
                cos_x->dd[k][l] = -c * w[k] * w[l];
              }
            }
          });
      typename TH::Coefficients c;
      M::template Coeffs<H>(p, qh, phih, &c, &trig_h);
      for (int k = 0; k < M::kNq; ++k) {
        MatCQ second;
        for (int r = 0; r < M::kNc; ++r) {
          for (int j = 0; j < M::kNq; ++j) second(r, j) = c.Phi(r).dd[k][j];
        }
        L->template middleCols<M::kNq>(M::kNq * k) = -f.Solve(second);
      }
      return;
    }
  }
  if constexpr (kDualL) {
    // Exact to rounding: D_k = d/dq_k + sum_j K(j, k) d/dphi_j of the dual evaluation.
    PhiDerivatives own;
    if (d == nullptr) {
      VecC Phi;
      MatCPhi A;
      MatCQ B;
      EvalPhiWithDerivatives(q, phi, &Phi, &A, &B, &own);
      d = &own;
    }
    for (int k = 0; k < M::kNq; ++k) {
      MatCPhi dA = d->A[static_cast<size_t>(k)];
      MatCQ dB = d->B[static_cast<size_t>(k)];
      for (int j = 0; j < M::kNphi; ++j) {
        dA += K(j, k) * d->A[static_cast<size_t>(M::kNq + j)];
        dB += K(j, k) * d->B[static_cast<size_t>(M::kNq + j)];
      }
      L->template middleCols<M::kNq>(M::kNq * k) = -f.Solve(MatCQ(dA * K + dB));
    }
  } else {
    // By central differences: h = cbrt(eps) ~ 6e-6 balances truncation O(h^2) and rounding
    // O(eps/h): both ~ 1e-11 relative.
    (void)d;
    const double h = std::cbrt(std::numeric_limits<double>::epsilon());
    if constexpr (M::kNq == Eigen::Dynamic) L->resize(nphi(), nq() * nq());
    for (int k = 0; k < nq(); ++k) {
      VecQ dq = VecQ::Zero(nq());
      dq(k) = h;
      const VecPhi dphi = K.col(k) * h;
      MatCPhi A_plus, A_minus;
      MatCQ B_plus, B_minus;
      Calls::Phi(model_, params_, VecQ(q + dq), VecPhi(phi + dphi), nullptr, &A_plus, &B_plus);
      Calls::Phi(model_, params_, VecQ(q - dq), VecPhi(phi - dphi), nullptr, &A_minus, &B_minus);
      const MatCPhi dA = (A_plus - A_minus) / (2 * h);
      const MatCQ dB = (B_plus - B_minus) / (2 * h);
      MiddleCols<M::kNq>(*L, nq() * k, nq()) = -f.Solve(MatCQ(dA * K + dB));
    }
  }
}

template <class M, class Assembler>
bool PositionSolver<M, Assembler>::CopyCoefficients(const typename T::Coefficients& c,
                                         const Factorization& f, const MatCQ* Phi_q,
                                         State<M>* s, const PhiDerivatives* d) const {
  (void)c;
  (void)d;
  // (For a generated M each `if` below is constant; the view decides at run time.)
  // (Assign: Eigen's assignment for a generated M; for the view a loop over the entries.)
  if constexpr (Features::kHasK) {
    if (Calls::HasK(model_)) Assign(&s->K, c.K);
  }
  // Phi_phi with K and L from the same evaluation (State::Phi_phi; the statics read the three).
  if constexpr (kPhiFromCoeffs) {
    if (PhiFromCoeffs()) Assign(&s->Phi_phi, c.Phi_phi);
  }
  if constexpr (!Features::kHasK || Calls::kView) {
    if (!Calls::HasK(model_)) {
      MatCQ B;
      if (Phi_q == nullptr) {
        Calls::Phi(model_, params_, s->q, s->phi, nullptr, nullptr, &B);
        Phi_q = &B;
      }
      s->K = -f.Solve(*Phi_q);
    }
  }
  if constexpr (Features::kHasL) {
    if (Calls::HasL(model_)) Assign(&s->L, c.L);
  }
  if constexpr (!Features::kHasL || Calls::kView) {
    if (!Calls::HasL(model_)) NumericalL(s->q, s->phi, f, s->K, &s->L, d);
  }
  bool finite = internal::Finite(s->K) && internal::Finite(s->L);
  if constexpr (Features::kHasPoints) {
    if (Calls::HasPoints(model_)) {
      Assign(&s->r_P, c.r_P);
      finite = finite && internal::Finite(s->r_P);
    }
  }
  if constexpr (Features::kHasPointVelocities) {
    if (Calls::HasPointVelocities(model_)) Assign(&s->K_P, c.K_P);
  }
  if constexpr (Features::kHasPointAccelerations) {
    if (Calls::HasPointAccelerations(model_)) Assign(&s->L_P, c.L_P);
  }
  ErrorBounds(f, s);
  return finite;
}

template <class M, class Assembler>
void PositionSolver<M, Assembler>::ErrorBounds(const Factorization& f, State<M>* s) const {
  // First-order propagation (position/solver.h, "Accuracy"). u: unit roundoff; n: kNphi;
  // kappa = cond_1(Phi_phi); ||Phi_phi^{-1}||_1 = kappa / ||Phi_phi||_1. Scale: the second
  // and third derivatives of Phi are taken as bounded by ||Phi_phi||_1 (link lengths: a
  // revolute chain's Phi sums l (cos, sin) terms), and the rounding of Phi as
  // 4 n u ||Phi_phi||_1 (1 + ||phi||_inf).
  constexpr double u = std::numeric_limits<double>::epsilon() / 2;
  const double n = nphi();
  const double kappa = s->condition;
  const double norm_A = f.norm1();  // ||Phi_phi||_1 (= kappa / inverse_norm, without the division)
  const double norm_phi = internal::InfNorm(s->phi);  // ||phi||_inf
  const double rho = s->residual_norm + 4 * n * u * norm_A * (1 + norm_phi);
  // phi: the residual through Phi_phi^{-1} (1-norms; ||r||_1 <= n ||r||_inf), plus its own
  // rounding.
  s->phi_error = s->inverse_norm * n * rho + u * norm_phi;
  // K = -Phi_phi^{-1} Phi_q at a phi off by phi_error: Phi_phi and Phi_q change by
  // ~ ||Phi_phi||_1 phi_error, amplified by ||Phi_phi^{-1}||_1; plus the solve's rounding.
  const double norm_K = internal::SmallNorm1(s->K);
  const double delta = s->phi_error + n * u;
  s->K_error = kappa * delta * (1 + norm_K);
  // L = -Phi_phi^{-1} (Phi'' (K, K) + ...): the same for its terms, with K's error entering
  // twice (kappa^2 phi_error ~ u kappa^3, the leading term next to a singularity).
  const double norm_L = internal::SmallNorm1(s->L);
  s->L_error = kappa * (delta * (norm_L + (1 + norm_K) * (1 + norm_K)) +
                        2 * s->K_error * (1 + norm_K));
}

}  // namespace mechgen::position
