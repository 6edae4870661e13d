/**
 * \file core/view_sized.h
 * SizedViewModel<kNq, kNphi>: a ViewModel whose input and loop sizes are fixed at compile time
 * (nc = nphi), the way Ceres' SizedCostFunction fixes a CostFunction's: the same view, the same
 * function pointers, but q, phi, Phi, Phi_phi, K and L are fixed-size Eigen matrices, so that the
 * runtime's templates instantiated for it (the continuation step, the statics) run the fixed-size
 * arithmetic of a generated model's instantiation instead of loops of run-time length. Its
 * Coefficients is a plain struct (SizedCoefficients) laid out as the generated struct of a model
 * of these sizes, which the view's Coeffs writes in place: the continuation step reads Phi_phi,
 * K and L at fixed offsets, not through maps of a buffer, and HasK, HasL and CoeffsHavePhi are
 * constants (Fits: a model whose coefficients lack one runs on the ViewModel instantiation). The
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

#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "mechgen/core/view_model.h"

namespace mechgen {

/// A view of a model with kNq inputs and kNphi dependent coordinates and constraints.
template <int kNqFixed, int kNphiFixed>
struct SizedViewModel : ViewModel {
  static constexpr int kNq = kNqFixed;
  static constexpr int kNphi = kNphiFixed;
  static constexpr int kNc = kNphiFixed;
  /// Whether `model` has these sizes (a SizedViewModel of another is not valid), and the
  /// coefficients this instantiation holds at compile time: Phi, Phi_phi, K and L, at the
  /// offsets of SizedCoefficients (the generated struct's layout at these sizes; the points,
  /// where the model has them, right after L).
  static bool Fits(const ViewModel& model);
  explicit SizedViewModel(const ViewModel& model) : ViewModel(model) {}
};

namespace internal {
/// The storage of SizedCoefficients, a standard-layout struct (its members' offsets are those
/// the view's layout must have).
template <int kNqFixed, int kNphiFixed>
struct SizedCoefficientsStorage {
  Eigen::Matrix<double, kNphiFixed, 1> Phi;
  Eigen::Matrix<double, kNphiFixed, kNphiFixed> Phi_phi;
  Eigen::Matrix<double, kNphiFixed, kNqFixed> K;
  Eigen::Matrix<double, kNphiFixed, kNqFixed * kNqFixed> L;
  /// r_P, K_P and L_P at the view's number of points, one after the other (those it has).
  alignas(kViewBufferAlignment) std::array<double, 2 * ModelView::kMaxPoints * (1 + kNqFixed + kNqFixed * kNqFixed)> points;
};
}  // namespace internal
/// The Coefficients of a SizedViewModel: the generated struct of a model of these sizes as a
/// plain struct (Phi, Phi_phi, K and L fixed-size members; the points, of the view's count,
/// maps of the storage after them), the same layout as the generated one, so that the view's
/// Coeffs writes it in place (its `data()`) and the continuation step reads K and L at fixed
/// offsets on the stack, not through maps of a buffer. (A model of these sizes whose layout
/// differs, e.g. without L, runs on the ViewModel instantiation: SizedViewModel::Fits.)
template <int kNqFixed, int kNphiFixed>
struct SizedCoefficients : internal::SizedCoefficientsStorage<kNqFixed, kNphiFixed> {
  using Storage = internal::SizedCoefficientsStorage<kNqFixed, kNphiFixed>;
  static_assert(std::is_standard_layout_v<Storage>, "the offsets of the view's layout");
  SizedCoefficients() = default;
  SizedCoefficients(const SizedCoefficients&) = delete;
  SizedCoefficients& operator=(const SizedCoefficients&) = delete;
  Eigen::Map<const Eigen::Matrix<double, 2, Eigen::Dynamic>> r_P{nullptr, 2, 0};
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, kNqFixed>> K_P{nullptr, 0, kNqFixed};
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, kNqFixed * kNqFixed>> L_P{nullptr, 0, kNqFixed * kNqFixed};
  /// The struct as the view's Coefficients buffer (its members at the view's offsets).
  double* data() { return this->Phi.data(); }
  const double* data() const { return this->Phi.data(); }
  /// The offset of each member in doubles (the view's offsets must equal these).
  static int PhiOffset() { return static_cast<int>(offsetof(Storage, Phi) / sizeof(double)); }
  static int PhiPhiOffset() { return static_cast<int>(offsetof(Storage, Phi_phi) / sizeof(double)); }
  static int KOffset() { return static_cast<int>(offsetof(Storage, K) / sizeof(double)); }
  static int LOffset() { return static_cast<int>(offsetof(Storage, L) / sizeof(double)); }
  static int PointsOffset() { return static_cast<int>(offsetof(Storage, points) / sizeof(double)); }
  /// The point maps of `model`'s points, one after the other in `points` (SizedViewModel::Fits);
  /// those the model lacks stay empty.
  MECHGEN_ALWAYS_INLINE void MapPoints(const ViewModel& model) {
    const ViewModel::CoefficientsLayout& l = model.coefficients;
    const int np = model.have.num_points;
    const double* at = this->points.data();
    // (A Map is trivially destructible: placed anew over the empty one.)
    if (l.r_P >= 0) {
      new (&r_P) decltype(r_P)(at, 2, np);
      at += 2 * np;
    }
    if (l.K_P >= 0) {
      new (&K_P) decltype(K_P)(at, 2 * np, kNqFixed);
      at += 2 * np * kNqFixed;
    }
    if (l.L_P >= 0) new (&L_P) decltype(L_P)(at, 2 * np, kNqFixed * kNqFixed);
  }
};

template <int kNqFixed, int kNphiFixed>
bool SizedViewModel<kNqFixed, kNphiFixed>::Fits(const ViewModel& model) {
  using C = SizedCoefficients<kNqFixed, kNphiFixed>;
  const ViewModel::Have& h = model.have;
  const ViewModel::CoefficientsLayout& l = model.coefficients;
  if (h.nq != kNq || h.nphi != kNphi || h.nc != kNc || !h.K || !h.L || !h.coeffs_phi) return false;
  if (l.Phi != C::PhiOffset() || l.Phi_phi != C::PhiPhiOffset() || l.K != C::KOffset() || l.L != C::LOffset()) {
    return false;
  }
  // The points where the model has them: r_P, K_P, L_P in that order after L. (Without points
  // the maps are empty wherever they lie.)
  const int np = h.num_points, r = C::PointsOffset();
  if (np > 0) {
    int next = r;
    for (auto [offset, size] : {std::pair{l.r_P, 2 * np}, {l.K_P, 2 * np * kNq}, {l.L_P, 2 * np * kNq * kNq}}) {
      if (offset < 0) continue;
      if (offset != next) return false;
      next += size;
    }
  }
  // The view writes its whole struct (l.size doubles, padding included) from data().
  return l.size - r <= static_cast<int>(std::tuple_size<decltype(C::Storage::points)>::value);
}

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
  using Coefficients = SizedCoefficients<kNqFixed, kNphiFixed>;
};
template <int kNqFixed, int kNphiFixed, class Scalar>
struct ModelFeatures<SizedViewModel<kNqFixed, kNphiFixed>, Scalar> : ModelFeatures<ViewModel, Scalar> {
  using Coefficients = SizedCoefficients<kNqFixed, kNphiFixed>;
};
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
  // (Fits: a sized view has K, L, and Phi and Phi_phi in its coefficients.)
  static constexpr bool HasK(const ViewModel&) { return true; }
  static constexpr bool HasL(const ViewModel&) { return true; }
  static constexpr bool CoeffsHavePhi(const ViewModel&) { return true; }

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
  // (Coeffs and StaticsCoefficients fill the plain SizedCoefficients, where ModelCalls<ViewModel>'s
  // fill a buffer and place maps on it; the rest forwards to the view's <Call>Flat: what each
  // call does is written there once.)
  static void Coeffs(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                     typename T::Coefficients* c, const Trig* trig = nullptr) {
    c->MapPoints(m);
    // (The view writes Coefficients whole: nothing to initialize.)
    m.view->Coeffs(p.data(), q.data(), phi.data(), c->data(),
                   trig != nullptr && HasTrig(m) ? trig->buffer.data() : nullptr);
  }
  /// The coefficients of a position::State (Phi 0), as ModelCalls<ViewModel>::StaticsCoefficients.
  template <class State>
  static void StaticsCoefficients(const M& m, const State& s, typename T::Coefficients* c) {
    c->MapPoints(m);
    c->Phi.setZero();
    c->Phi_phi = s.Phi_phi;
    c->K = s.K;
    c->L = s.L;
    double* const at = c->data();  // (the offsets are from the struct's start)
    const ViewModel::CoefficientsLayout& l = m.coefficients;
    auto put = [at](int offset, bool has, const auto& x) {
      if (offset >= 0) {
        if (has) {
          internal::CopyEntries(x.data(), x.size(), at + offset);
        } else {
          internal::FillEntries(at + offset, x.size(), 0.0);
        }
      }
    };
    put(l.r_P, HasPoints(m), s.r_P);
    put(l.K_P, HasPointVelocities(m), s.K_P);
    put(l.L_P, HasPointAccelerations(m), s.L_P);
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
    ForcesFlat(m, p, q.data(), phi.data(), c.data(), out, f != nullptr ? f->data() : nullptr,
               qd != nullptr ? qd->data() : nullptr);
  }
  static bool ForcesChecked(const M& m, const ViewParams& p, const typename T::VecQ& q,
                            const typename T::VecPhi& phi, const typename T::Coefficients& c,
                            typename T::Statics* out, const typename T::VecF* f, const typename T::VecQ* qd,
                            double* reaction_norm) {
    return ForcesCheckedFlat(m, p, q.data(), phi.data(), c.data(), out, f != nullptr ? f->data() : nullptr,
                             qd != nullptr ? qd->data() : nullptr, reaction_norm);
  }
  static void Stiffness(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                        const typename T::Coefficients& c, typename T::Statics* out) {
    StiffnessFlat(m, p, q.data(), phi.data(), c.data(), out);
  }
  static void Design(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                     internal::ViewDesignDerivatives* out) {
    DesignFlat(m, p, q.data(), phi.data(), out);
  }
  static void StaticsDesign(const M& m, const ViewParams& p, const typename T::VecQ& q, const typename T::VecPhi& phi,
                            const typename T::Coefficients& c, const internal::ViewDesignDerivatives& dc,
                            internal::ViewStaticsDesign* out) {
    StaticsDesignFlat(m, p, q.data(), phi.data(), c.data(), dc, out);
  }
};

}  // namespace mechgen
