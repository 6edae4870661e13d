/**
 * \file core/view_sized.h
 * SizedViewModel<kNq, kNphi>: a ViewModel whose input and loop sizes are fixed at compile time
 * (nc = nphi), the way Ceres' SizedCostFunction fixes a CostFunction's: the same view, the same
 * function pointers, but q, phi, Phi, Phi_phi, K and L are fixed-size Eigen matrices, so that the
 * runtime's templates instantiated for it (the continuation step, the statics) run the fixed-size
 * arithmetic of a generated model's instantiation instead of loops of run-time length. The
 * points, reactions and friction keep the view's bounded sizes.
 *
 * mechgen_runtime_view instantiates the position solver, the sweep and the statics sweep once
 * for the commonest shape of the shipped models (one input, two dependent coordinates: the
 * four-bars and slider-cranks, 14 of 27; extern in core/view_runtime.h), and analysis::Run sends
 * the sweep and the statics of a view of that shape there (RunSized, runtime/view/
 * analysis_sized.cc); any other shape, and every other analysis, runs the ViewModel
 * instantiation. One source, instantiated for both.
 */
#pragma once

#include <Eigen/Core>

#include "mechgen/core/view_model.h"

namespace mechgen {

/// A view of a model with kNq inputs and kNphi dependent coordinates and constraints.
template <int kNqFixed, int kNphiFixed>
struct SizedViewModel : ViewModel {
  static constexpr int kNq = kNqFixed;
  static constexpr int kNphi = kNphiFixed;
  static constexpr int kNc = kNphiFixed;
  /// Whether `model` has these sizes (a SizedViewModel of another is not valid).
  static bool Fits(const ViewModel& model) {
    return model.have.nq == kNq && model.have.nphi == kNphi && model.have.nc == kNc;
  }
  explicit SizedViewModel(const ViewModel& model) : ViewModel(model) {}
};

/// The view's types with q, phi, Phi and their derivatives at fixed sizes.
template <int kNqFixed, int kNphiFixed, class Scalar>
struct ModelTypes<SizedViewModel<kNqFixed, kNphiFixed>, Scalar> : ModelTypes<ViewModel, Scalar> {
  using Base = ModelTypes<ViewModel, Scalar>;
  static constexpr int D = Eigen::Dynamic;
  static constexpr int kNq = kNqFixed, kNphi = kNphiFixed, kNc = kNphiFixed;
  /// As a generated model's: the maxima are the sizes (the points keep the view's).
  static constexpr int kMaxQ = kNq, kMaxPhi = kNphi;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using VecC = Eigen::Matrix<double, kNc, 1>;
  using VecQQ = Eigen::Matrix<double, kNq * kNq, 1>;
  using MatCPhi = Eigen::Matrix<double, kNc, kNphi>;
  using MatCQ = Eigen::Matrix<double, kNc, kNq>;
  using MatK = Eigen::Matrix<double, kNphi, kNq>;
  using MatL = Eigen::Matrix<double, kNphi, kNq * kNq>;
  using MatKP = Eigen::Matrix<double, D, kNq, 0, 2 * Base::kMaxPoints, kNq>;
  using MatLP = Eigen::Matrix<double, D, kNq * kNq, 0, 2 * Base::kMaxPoints, kNq * kNq>;
  using MatQQ = Eigen::Matrix<double, kNq, kNq>;
  using MatFQ = Eigen::Matrix<double, D, kNq, 0, Base::kMaxFriction, kNq>;
};
template <int kNqFixed, int kNphiFixed, class Scalar>
struct ModelFeatures<SizedViewModel<kNqFixed, kNphiFixed>, Scalar> : ModelFeatures<ViewModel, Scalar> {};
namespace internal {
template <int kNqFixed, int kNphiFixed, class Scalar>
struct TrigOf<SizedViewModel<kNqFixed, kNphiFixed>, Scalar, true> : TrigOf<ViewModel, Scalar, true> {};
template <int kNqFixed, int kNphiFixed>
struct BlockCount<SizedViewModel<kNqFixed, kNphiFixed>, true> : BlockCount<ViewModel, true> {};
template <int kNqFixed, int kNphiFixed>
struct DesignDerivativesOf<SizedViewModel<kNqFixed, kNphiFixed>, true> : DesignDerivativesOf<ViewModel, true> {};
template <int kNqFixed, int kNphiFixed>
struct StaticsDesignOf<SizedViewModel<kNqFixed, kNphiFixed>, true> : StaticsDesignOf<ViewModel, true> {};
}  // namespace internal

/// The view's calls at the fixed sizes: the sizes constant, and the calls of the continuation
/// step and the statics (Phi, Coeffs, Solve, Forces, ForcesChecked, Stiffness, the design
/// derivatives, ...) taking the fixed-size matrices (their storage is the view's packed
/// column-major layout, as the bounded matrices' is). The rest is the view's: a call not listed
/// here that takes q or phi (the scene of a drawing, the dynamics') gets them converted to the
/// view's bounded types, a copy off the continuation step.
template <int kNqFixed, int kNphiFixed>
struct ModelCalls<SizedViewModel<kNqFixed, kNphiFixed>> : ModelCalls<ViewModel> {
  using M = SizedViewModel<kNqFixed, kNphiFixed>;
  using T = ModelTypes<M>;

  static constexpr int Nq(const ViewModel&) { return kNqFixed; }
  static constexpr int Nphi(const ViewModel&) { return kNphiFixed; }
  static constexpr int Nc(const ViewModel&) { return kNphiFixed; }

  static void Phi(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                  typename T::VecC* Phi, typename T::MatCPhi* Phi_phi, typename T::MatCQ* Phi_q) {
    m.view->Phi(p.data(), q.data(), phi.data(), Phi != nullptr ? Phi->data() : nullptr,
                Phi_phi != nullptr ? Phi_phi->data() : nullptr, Phi_q != nullptr ? Phi_q->data() : nullptr);
  }
  /// Phi at expressions (q + dq, ...): evaluated into the fixed-size types first.
  template <class Q, class P>
  static void Phi(const M& m, const ViewParams& p, const Q& q, const P& phi, typename T::VecC* Phi,
                  typename T::MatCPhi* Phi_phi, typename T::MatCQ* Phi_q) {
    ModelCalls::Phi(m, p, typename T::VecQ(q), typename T::VecPhi(phi), Phi, Phi_phi, Phi_q);
  }
  static void DetPhiPhi(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                        double* det) {
    m.view->DetPhiPhi(p.data(), q.data(), phi.data(), det);
  }
  // (The rest forwards to the view's <Call>Flat: what each call does is written there once.)
  static void Coeffs(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                     typename T::Coefficients* c, const Trig* trig = nullptr) {
    CoeffsFlat(m, p, q.data(), phi.data(), c, trig);
  }
  template <class Mu>
  static void TransmissionAngles(const M& m, const ViewParams& p, const typename T::VecQ& q,
                                 const typename T::VecPhi& phi, Mu* mu) {
    TransmissionAnglesFlat(m, p, q.data(), phi.data(), mu);
  }
  static ViewSolveReport Solve(const M& m, const ViewParams& p, const typename T::VecQ& q, typename T::VecPhi* phi,
                               const Modes& modes, int max_iterations, double tolerance, Trig* trig = nullptr) {
    return SolveFlat(m, p, q.data(), phi->data(), modes, max_iterations, tolerance, trig);
  }
  static ViewSolveReport SolveTrig(const M& m, const ViewParams& p, const typename T::VecQ& q, const Modes& modes,
                                   Trig* trig) {
    return m.view->SolveTrig(p.data(), q.data(), modes.data(), trig->buffer.data());
  }
  static void Forces(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                     const typename T::Coefficients& c, typename T::Statics* out, const typename T::VecF* f,
                     const typename T::VecQ* qd) {
    ForcesFlat(m, p, q.data(), phi.data(), c, out, f != nullptr ? f->data() : nullptr,
               qd != nullptr ? qd->data() : nullptr);
  }
  static bool ForcesChecked(const M& m, const ViewParams& p, const typename T::VecQ& q,
                            const typename T::VecPhi& phi, const typename T::Coefficients& c,
                            typename T::Statics* out, const typename T::VecF* f, const typename T::VecQ* qd,
                            double* reaction_norm) {
    return ForcesCheckedFlat(m, p, q.data(), phi.data(), c, out, f != nullptr ? f->data() : nullptr,
                             qd != nullptr ? qd->data() : nullptr, reaction_norm);
  }
  static void Stiffness(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                        const typename T::Coefficients& c, typename T::Statics* out) {
    StiffnessFlat(m, p, q.data(), phi.data(), c, out);
  }
  static void Design(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                     internal::ViewDesignDerivatives* out) {
    DesignFlat(m, p, q.data(), phi.data(), out);
  }
  static void StaticsDesign(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                            const typename T::Coefficients& c, const internal::ViewDesignDerivatives& dc,
                            internal::ViewStaticsDesign* out) {
    StaticsDesignFlat(m, p, q.data(), phi.data(), c, dc, out);
  }
};

}  // namespace mechgen
