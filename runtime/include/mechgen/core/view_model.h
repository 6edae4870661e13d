/**
 * \file core/view_model.h
 * ViewModel: the model type M of the runtime's templates instantiated once for every model
 * (issue 43), a handle on one model's ModelView (core/model_view.h).
 *
 * Its sizes are Eigen::Dynamic at compile time (ModelTypes<ViewModel>: bounded dynamic
 * matrices, Eigen::Matrix<double, Dynamic, ..., Max, Max> with the maxima of ModelView: state
 * on the stack, nothing allocates) and the view's at run time; ModelCalls<ViewModel> reads the
 * view and calls its function pointers on the matrices' storage (column-major and packed, as
 * the view's flat arrays are). The parameters are a fixed array of ModelView::kMaxParams
 * doubles in the view's table order. Coefficients is a struct of bounded matrices that the
 * view's buffer is copied into by member name (FindMember, once per ViewModel). The view's
 * functions call the generated fixed-size code: the same arithmetic as the fixed-size
 * instantiation, so the runtime's results agree to the bit where its own arithmetic does.
 *
 * ModelFeatures<ViewModel> says what a view may have (everything the runtime reads through
 * ModelCalls); ModelCalls<ViewModel>::Has*() what this one has.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <limits>
#include <new>

#include <Eigen/Core>

#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/core/model_view.h"

namespace mechgen {

/// The alignment of the view's struct buffers: at least the generated structs' (fixed-size Eigen
/// members), so that the view's functions take a buffer as the struct itself, with nothing
/// copied in or out (core/view_buffers.h, InPlace; a buffer aligned less is copied).
inline constexpr std::size_t kViewBufferAlignment = EIGEN_MAX_STATIC_ALIGN_BYTES > 16 ? EIGEN_MAX_STATIC_ALIGN_BYTES : 16;

/// The parameters of a ViewModel: every parameter, free and derived, in the view's table
/// order (the view's functions read the free ones).
struct ViewParams {
  std::array<double, ModelView::kMaxParams> values{};
  const double* data() const { return values.data(); }
  double* data() { return values.data(); }
};

/// One model reached through its view. Copyable (a pointer and the offsets of the
/// Coefficients members); the view must outlive it.
struct ViewModel {
  static constexpr int kNq = Eigen::Dynamic;
  static constexpr int kNphi = Eigen::Dynamic;
  static constexpr int kNc = Eigen::Dynamic;
  static constexpr int kNumPoints = Eigen::Dynamic;
  static constexpr int kNumScenePoints = Eigen::Dynamic;
  // What a view may have (model_traits.h reads these flags): everything; ModelCalls<ViewModel>
  // says at run time what this one has.
  static constexpr bool kHasCoeffsPhi = true, kHasK = true, kHasL = true, kHasPoints = true,
                        kHasPointVelocities = true, kHasPointAccelerations = true, kHasSolve = true,
                        kHasNamedModes = true, kHasTrig = true, kHasSolveTrig = true,
                        kHasTransmissionAngles = true, kHasSwitchModes = true, kHasDrawing = true,
                        kHasCamProfile = true, kHasAppliedLoads = true, kHasStatics = true,
                        kHasStaticsQ = true, kHasStaticsStiffness = true, kHasStaticsV = true,
                        kHasStaticsD2V = true, kHasStaticsR = true, kHasStaticsFriction = true,
                        kHasDynamics = true, kHasExcess = true, kHasShaking = true, kHasKinematics = true,
                        kHasRhs = true, kHasRhsConstants = true, kHasDesignDerivatives = true,
                        kHasStaticsDesign = true, kHasDynamicsDesign = true;

  /// Offsets of a struct's members in its buffer, -1 where the model lacks the member.
  struct CoefficientsLayout {
    int Phi = -1, Phi_phi = -1, K = -1, L = -1, r_P = -1, K_P = -1, L_P = -1;
    int size = 0;
  };

  explicit ViewModel(const ModelView& v) : view(&v) {
    const ViewLayout& c = v.Layout(ViewStruct::kCoefficients);
    auto offset = [&c](const char* name) {
      const ViewMember* m = FindMember(c, name);
      return m != nullptr ? m->offset : -1;
    };
    coefficients.Phi = offset("Phi");
    coefficients.Phi_phi = offset("Phi_phi");
    coefficients.K = offset("K");
    coefficients.L = offset("L");
    coefficients.r_P = offset("r_P");
    coefficients.K_P = offset("K_P");
    coefficients.L_P = offset("L_P");
    coefficients.size = c.size;
  }

  const ModelView* view;
  /// Whether an analysis may run this view on the runtime's instantiation sized to its shape
  /// (core/view_sized.h: one input and two dependent coordinates), where there is one; false:
  /// on the ViewModel instantiation (the tests compare the two).
  bool sized = true;
  /// What ModelCalls<ViewModel> answers most often, read from the view once (the view does not
  /// change): its sizes and what it has, each one load instead of the view's pointer, its flag
  /// and the function pointer that the flag goes with, on every call of a continuation step
  /// and a statics iteration.
  struct Have {
    int nq = 0, nphi = 0, nc = 0, num_points = 0;
    bool K = false, L = false, points = false, point_velocities = false, point_accelerations = false,
         coeffs_phi = false, solve = false, trig = false, statics = false,
         solve_trig = false, rhs = false;
    int num_reactions = 0, num_friction = 0;
  };
  Have have = HaveOf(*view);
  static Have HaveOf(const ModelView& v) {
    Have h;
    h.nq = v.nq;
    h.nphi = v.nphi;
    h.nc = v.nc;
    h.num_points = v.num_points;
    h.K = v.flags.kHasK;
    h.L = v.flags.kHasL;
    h.points = v.num_points > 0 && v.flags.kHasPoints;
    h.point_velocities = h.points && v.flags.kHasPointVelocities;
    h.point_accelerations = h.points && v.flags.kHasPointAccelerations;
    h.coeffs_phi = v.flags.kHasCoeffsPhi;
    h.solve = v.flags.kHasSolve && v.Solve != nullptr;
    h.trig = h.solve && v.flags.kHasTrig;
    h.statics = v.flags.kHasStatics && v.flags.kHasStaticsQ && v.Forces != nullptr && v.StaticsChecks != nullptr &&
                v.ForcesChecked != nullptr;
    h.num_reactions = h.statics && v.flags.kHasStaticsR ? v.num_reactions : 0;
    h.num_friction = h.statics && v.flags.kHasStaticsFriction ? v.num_friction : 0;
    h.solve_trig = h.trig && v.flags.kHasSolveTrig && v.SolveTrig != nullptr;
    h.rhs = v.flags.kHasRhs && v.flags.kHasRhsConstants && v.Rhs != nullptr && v.Prepare != nullptr;
    return h;
  }
  CoefficientsLayout coefficients;
  // ---- Statics: the layouts of its structs ----
  /// The statics' counts are the view's (ModelCalls<ViewModel>::NumReactions, NumFriction).
  static constexpr int kNumReactions = Eigen::Dynamic;
  /// The design parameters' count is the view's (ModelCalls<ViewModel>::NumDesign).
  static constexpr int kNumDesign = Eigen::Dynamic;
  static constexpr int kNumFriction = Eigen::Dynamic;
  /// Offsets of the Statics members in its buffer (ViewStruct::kStatics), -1 where the model
  /// lacks the member.
  struct StaticsLayout {
    int Q = -1, drive = -1, V = -1, dV_dq = -1, d2V_dq2 = -1, stiffness = -1, R = -1, normal = -1, gain = -1,
        K_rel = -1;
    int size = 0;
  };
  StaticsLayout statics = StaticsLayoutOf(*view);
  static StaticsLayout StaticsLayoutOf(const ModelView& v) {
    const ViewLayout& s = v.Layout(ViewStruct::kStatics);
    auto offset = [&s](const char* name) {
      const ViewMember* m = FindMember(s, name);
      return m != nullptr ? m->offset : -1;
    };
    StaticsLayout l;
    l.Q = offset("Q");
    l.drive = offset("drive");
    l.V = offset("V");
    l.dV_dq = offset("dV_dq");
    l.d2V_dq2 = offset("d2V_dq2");
    l.stiffness = offset("stiffness");
    l.R = offset("R");
    l.normal = offset("normal");
    l.gain = offset("gain");
    l.K_rel = offset("K_rel");
    l.size = s.size;
    return l;
  }

  // ---- Dynamics: the layouts of its structs ----
  /// Offsets of the members the dynamics read (dynamics/) in the view's Dynamics, Rhs,
  /// RhsConstants and Statics buffers (Kinetostatics' output), -1 where the model lacks one.
  struct DynamicsLayouts {
    struct Dynamics {
      int I = -1, h = -1, Q = -1, T = -1, V = -1, P_nc = -1, dI_dq = -1, size = 0;
    } dynamics;
    struct Rhs {
      int K = -1, I = -1, h = -1, Q = -1, T = -1, V = -1, P_nc = -1, Phi_phi = -1, size = 0;
    } rhs;
    int rhs_constants_size = 0;
    int trig_sin_phi = -1, trig_cos_phi = -1;  ///< in the Trig buffer
    struct Kinetostatics {
      int Q = -1, drive = -1, R = -1, normal = -1, gain = -1, K_rel = -1, size = 0;
    } kinetostatics;
    explicit DynamicsLayouts(const ModelView* v) {
      auto offset = [](const ViewLayout& l, const char* name) {
        const ViewMember* m = FindMember(l, name);
        return m != nullptr ? m->offset : -1;
      };
      const ViewLayout& d = v->Layout(ViewStruct::kDynamics);
      dynamics = {offset(d, "I"), offset(d, "h"),    offset(d, "Q"),     offset(d, "T"),
                  offset(d, "V"), offset(d, "P_nc"), offset(d, "dI_dq"), d.size};
      const ViewLayout& r = v->Layout(ViewStruct::kRhs);
      rhs = {offset(r, "K"), offset(r, "I"),    offset(r, "h"),       offset(r, "Q"), offset(r, "T"),
             offset(r, "V"), offset(r, "P_nc"), offset(r, "Phi_phi"), r.size};
      rhs_constants_size = v->Layout(ViewStruct::kRhsConstants).size;
      trig_sin_phi = offset(v->Layout(ViewStruct::kTrig), "sin_phi");
      trig_cos_phi = offset(v->Layout(ViewStruct::kTrig), "cos_phi");
      const ViewLayout& k = v->Layout(ViewStruct::kStatics);
      kinetostatics = {offset(k, "Q"),    offset(k, "drive"), offset(k, "R"), offset(k, "normal"),
                       offset(k, "gain"), offset(k, "K_rel"), k.size};
    }
  };
  DynamicsLayouts dynamics_layouts{view};  // (after view: initialized from it)
};

/// Whether a view's layout and size are those this runtime was compiled against (a view from
/// a shared object compiled elsewhere is refused otherwise), and its model fits the maxima the
/// runtime's bounded types hold (ModelView::fits_maxima).
inline bool ViewCompatible(const ModelView& v) {
  return v.layout == kModelViewLayout && v.size == static_cast<int>(sizeof(ModelView)) && v.fits_maxima;
}

template <class Scalar>
struct ModelTypes<ViewModel, Scalar> {
  static_assert(std::is_same_v<Scalar, double>, "a view computes in double");
  static constexpr int D = Eigen::Dynamic;
  static constexpr int kNq = D, kNphi = D, kNc = D, kNumPoints = D, kNumScenePoints = D;
  static constexpr int kMaxQ = ModelView::kMaxQ;
  static constexpr int kMaxPhi = ModelView::kMaxPhi;
  static constexpr int kMaxPoints = ModelView::kMaxPoints;
  static constexpr int kMaxScenePoints = ModelView::kMaxScenePoints;
  using ScalarType = double;
  using Params = ViewParams;
  using VecQ = Eigen::Matrix<double, D, 1, 0, kMaxQ, 1>;
  using VecPhi = Eigen::Matrix<double, D, 1, 0, kMaxPhi, 1>;
  using VecC = Eigen::Matrix<double, D, 1, 0, kMaxPhi, 1>;
  using VecQQ = Eigen::Matrix<double, D, 1, 0, kMaxQ * kMaxQ, 1>;
  using MatCPhi = Eigen::Matrix<double, D, D, 0, kMaxPhi, kMaxPhi>;
  using MatCQ = Eigen::Matrix<double, D, D, 0, kMaxPhi, kMaxQ>;
  using MatK = Eigen::Matrix<double, D, D, 0, kMaxPhi, kMaxQ>;
  using MatL = Eigen::Matrix<double, D, D, 0, kMaxPhi, kMaxQ * kMaxQ>;
  using MatRP = Eigen::Matrix<double, 2, D, 0, 2, kMaxPoints>;
  using MatKP = Eigen::Matrix<double, D, D, 0, 2 * kMaxPoints, kMaxQ>;
  using MatLP = Eigen::Matrix<double, D, D, 0, 2 * kMaxPoints, kMaxQ * kMaxQ>;
  using MatScene = Eigen::Matrix<double, 2, D, 0, 2, kMaxScenePoints>;
  /// The generated Coefficients: the view's buffer, and each member a map of it at the view's
  /// sizes (set by ModelCalls<ViewModel>::Coeffs; empty where the model lacks the member). Not
  /// copyable: the maps point into the object's own buffer.
  struct Coefficients {
    using Map = Eigen::Map<const Eigen::MatrixXd>;
    Coefficients() = default;
    Coefficients(const Coefficients&) = delete;
    Coefficients& operator=(const Coefficients&) = delete;
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kCoefficients)]> buffer;
    Map Phi{nullptr, 0, 1}, Phi_phi{nullptr, 0, 0}, K{nullptr, 0, 0}, L{nullptr, 0, 0}, r_P{nullptr, 2, 0},
        K_P{nullptr, 0, 0}, L_P{nullptr, 0, 0};
  };
  // ---- Statics: its types ----
  static constexpr int kMaxReactions = ModelView::kMaxReactions;
  static constexpr int kMaxFriction = ModelView::kMaxFriction;
  using MatQQ = Eigen::Matrix<double, D, D, 0, kMaxQ, kMaxQ>;               ///< d2V_dq2, stiffness
  using VecR = Eigen::Matrix<double, D, 1, 0, kMaxReactions, 1>;           ///< R
  using VecF = Eigen::Matrix<double, D, 1, 0, kMaxFriction, 1>;            ///< normal, gain, f
  using MatFQ = Eigen::Matrix<double, D, D, 0, kMaxFriction, kMaxQ>;       ///< K_rel
  /// The generated StaticsT<double> at the view's sizes: the view's Statics buffer, and each
  /// member a map of it (placed on the view's layout by ModelCalls<ViewModel>::SetNaNStatics,
  /// which statics::internal::SetNaN calls; empty where the model lacks the member, V then NaN).
  /// The view's Forces and Stiffness write the buffer itself: nothing is copied in or out per
  /// call. Copyable: a copy maps its own buffer (the entries in use copied; over a value placed
  /// on the same view's layout, the entries only).
  struct Statics {
    using VecMap = Eigen::Map<Eigen::VectorXd>;
    using MatMap = Eigen::Map<Eigen::MatrixXd>;
    /// V: its entry of the buffer, NaN where the model has none (read as a double).
    struct Entry {
      const double* at = nullptr;
      operator double() const { return at != nullptr ? *at : std::numeric_limits<double>::quiet_NaN(); }
    };
    Statics() = default;
    Statics(const Statics& other) { CopyFrom(other); }
    Statics& operator=(const Statics& other) {
      if (this != &other) CopyFrom(other);
      return *this;
    }
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kStatics)]> buffer;
    const ModelView* view = nullptr;  ///< the view whose layout the members follow (nullptr: none)
    int size = 0;                     ///< the entries in use, buffer[0, size)
    VecMap Q{nullptr, 0}, drive{nullptr, 0};
    Entry V;
    VecMap dV_dq{nullptr, 0};
    MatMap d2V_dq2{nullptr, 0, 0}, stiffness{nullptr, 0, 0};
    VecMap R{nullptr, 0}, normal{nullptr, 0}, gain{nullptr, 0};
    MatMap K_rel{nullptr, 0, 0};

   private:
    void CopyFrom(const Statics& other) {
      ::mechgen::internal::CopyEntries(other.buffer.data(), other.size, buffer.data());
      if (view == other.view && size == other.size) return;  // (the maps already placed so)
      view = other.view;
      size = other.size;
      auto at = [this, &other](const double* x) { return x != nullptr ? buffer.data() + (x - other.buffer.data()) : nullptr; };
      // (A Map is trivially destructible: placed anew over the old one.)
      for (auto member : {&Statics::Q, &Statics::drive, &Statics::dV_dq, &Statics::R, &Statics::normal, &Statics::gain}) {
        const VecMap& x = other.*member;
        new (&(this->*member)) VecMap(at(x.data()), x.size());
      }
      for (auto member : {&Statics::d2V_dq2, &Statics::stiffness, &Statics::K_rel}) {
        const MatMap& x = other.*member;
        new (&(this->*member)) MatMap(at(x.data()), x.rows(), x.cols());
      }
      V.at = at(other.V.at);
    }
  };

  // ---- Dynamics: its types ----
  /// The generated Dynamics, Rhs, RhsConstants and Statics (Kinetostatics' output) as the
  /// dynamics read them: the view's buffer, and the members copied out of it at the view's
  /// sizes after each call (ModelCalls<ViewModel>::Dynamics, ...).
  using VecReactions = Eigen::Matrix<double, D, 1, 0, ModelView::kMaxReactions, 1>;
  using VecFriction = Eigen::Matrix<double, D, 1, 0, ModelView::kMaxFriction, 1>;
  using MatFrictionQ = Eigen::Matrix<double, D, D, 0, ModelView::kMaxFriction, kMaxQ>;
  struct DynamicsOut {
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kDynamics)]> buffer;
    MatQQ I;
    VecQ h, Q;
    double T = 0, V = 0, P_nc = 0;
  };
  /// Rhs: the view's buffer, and its matrices maps of it at the view's sizes (set by
  /// ModelCalls<ViewModel>::Rhs: nothing copied out; Q is added to in place, as the
  /// generated struct's). A copy's maps point into the copy's own buffer.
  struct RhsOut {
    using MatMap = Eigen::Map<Eigen::MatrixXd>;
    using VecMap = Eigen::Map<Eigen::VectorXd>;
    RhsOut() = default;
    RhsOut(const RhsOut& other) : buffer(other.buffer) { PlaceLike(other); }
    RhsOut& operator=(const RhsOut& other) {
      if (this != &other) {
        buffer = other.buffer;
        PlaceLike(other);
      }
      return *this;
    }
    /// The maps at other's offsets and sizes in this buffer (null where other's are).
    void PlaceLike(const RhsOut& other) {
      auto at = [&](const double* data) { return data == nullptr ? nullptr : buffer.data() + (data - other.buffer.data()); };
      new (&K) MatMap(at(other.K.data()), other.K.rows(), other.K.cols());
      new (&I) MatMap(at(other.I.data()), other.I.rows(), other.I.cols());
      new (&h) VecMap(at(other.h.data()), other.h.size());
      new (&Q) VecMap(at(other.Q.data()), other.Q.size());
      new (&Phi_phi) MatMap(at(other.Phi_phi.data()), other.Phi_phi.rows(), other.Phi_phi.cols());
      T = other.T;
      V = other.V;
      P_nc = other.P_nc;
    }
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kRhs)]> buffer;
    MatMap K{nullptr, 0, 0}, I{nullptr, 0, 0};
    VecMap h{nullptr, 0}, Q{nullptr, 0};
    double T = 0, V = 0, P_nc = 0;
    MatMap Phi_phi{nullptr, 0, 0};
  };
  struct RhsConstantsOut {
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kRhsConstants)]> buffer;
  };
  struct KinetostaticsOut {
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kStatics)]> buffer;
    VecQ Q, drive;
    VecReactions R;
    VecFriction normal, gain;
    MatFrictionQ K_rel;
  };
};

/// What a view may have: every feature the runtime reads at compile time is possible, and
/// ModelCalls<ViewModel> says at run time which this view has.
template <class Scalar>
struct ModelFeatures<ViewModel, Scalar> {
  using Coefficients = typename ModelTypes<ViewModel, Scalar>::Coefficients;
  static constexpr bool kHasK = true;
  static constexpr bool kHasL = true;
  static constexpr bool kHasPoints = true;
  static constexpr bool kHasPointVelocities = true;
  static constexpr bool kHasPointAccelerations = true;
  static constexpr bool kHasScene = true;
  static constexpr bool kCoeffsHavePhi = true;
  static constexpr bool kHasSolve = true;
  static constexpr bool kHasTrig = true;
  static constexpr int kNumTransmissionAngles = Eigen::Dynamic;
  static constexpr int kNumSwitches = Eigen::Dynamic;
  /// Not at compile time: ModelCalls<ViewModel>::LoopFree() at run time.
  static constexpr bool kLoopFree = false;
};

namespace internal {
/// The sin and cos buffer of a view's Solve and Coeffs (ViewStruct::kTrig).
struct ViewTrig {
  alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kTrig)]> buffer;
};
template <class Scalar>
struct TrigOf<ViewModel, Scalar, true> {
  using type = ViewTrig;
  static constexpr bool value = true;
};
template <>
struct BlockCount<ViewModel, true> {
  static constexpr int value = ModelView::kMaxBlocks;
};
}  // namespace internal

// ---- Design (a `design:` section): the structs of the view's Design and StaticsDesign ----
namespace internal {
/// Places the members of S (a struct below) on view v's layout of S::kStruct: each member an
/// Eigen::Map of s->buffer at the layout's rows x cols (found by name; empty where the model
/// lacks the member, e.g. dK_dp without K), s->size the layout's size. The entries are not
/// touched.
template <class S>
void PlaceViewStruct(const ModelView& v, S* s) {
  using Map = typename S::Map;
  const ViewLayout& l = v.Layout(S::kStruct);
  s->view = &v;
  s->size = l.size;
  const auto members = S::Members();
  for (size_t i = 0; i < members.size(); ++i) {
    const ViewMember* m = FindMember(l, S::kNames[i]);
    if (m != nullptr) {
      new (&(s->*members[i])) Map(s->buffer.data() + m->offset, m->rows, m->cols);  // (trivially destructible)
    } else {
      new (&(s->*members[i])) Map(nullptr, 0, 0);
    }
  }
}
/// *to = from: the entries in use (from.size) copied, and to's members mapped on to's own
/// buffer at from's offsets and sizes (already so where both follow the same view's layout: a
/// sweep's record copied over the previous row's).
template <class S>
void CopyViewStruct(const S& from, S* to) {
  using Map = typename S::Map;
  CopyEntries(from.buffer.data(), from.size, to->buffer.data());
  if (to->view == from.view && to->size == from.size) return;
  to->view = from.view;
  to->size = from.size;
  for (auto member : S::Members()) {
    const Map& a = from.*member;
    double* const data = a.data() != nullptr ? to->buffer.data() + (a.data() - from.buffer.data()) : nullptr;
    new (&(to->*member)) Map(data, a.rows(), a.cols());
  }
}
/// The view's DesignDerivatives (position::DesignOf<ViewModel>): its buffer
/// (ViewStruct::kDesignDerivatives) and each member of the generated struct a map of it at the
/// view's sizes, as ModelTypes<ViewModel>::Coefficients; empty until placed on a view's layout
/// (position::SetNanDesign, ModelCalls<ViewModel>::Design). Copyable, unlike Coefficients (a
/// sweep copies its records): a copy maps its own buffer, and copies the entries in use only
/// (none for a model without a design section).
struct ViewDesignDerivatives {
  using Map = Eigen::Map<Eigen::MatrixXd>;
  static constexpr ViewStruct kStruct = ViewStruct::kDesignDerivatives;
  static constexpr std::array<const char*, 7> kNames{"dphi_dp", "dr_P_dp", "dK_dp", "dK_P_dp",
                                                     "dL_dp",   "dL_P_dp", "dmu_dp"};
  static std::array<Map ViewDesignDerivatives::*, 7> Members() {
    using D = ViewDesignDerivatives;
    return {&D::dphi_dp, &D::dr_P_dp, &D::dK_dp, &D::dK_P_dp, &D::dL_dp, &D::dL_P_dp, &D::dmu_dp};
  }
  ViewDesignDerivatives() = default;
  ViewDesignDerivatives(const ViewDesignDerivatives& other) { CopyViewStruct(other, this); }
  ViewDesignDerivatives& operator=(const ViewDesignDerivatives& other) {
    if (this != &other) CopyViewStruct(other, this);
    return *this;
  }
  alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(kStruct)]> buffer;
  const ModelView* view = nullptr;  ///< the view whose layout the members follow (nullptr: none)
  int size = 0;                     ///< the entries in use, buffer[0, size)
  Map dphi_dp{nullptr, 0, 0}, dr_P_dp{nullptr, 0, 0}, dK_dp{nullptr, 0, 0}, dK_P_dp{nullptr, 0, 0},
      dL_dp{nullptr, 0, 0}, dL_P_dp{nullptr, 0, 0}, dmu_dp{nullptr, 0, 0};
};
/// The view's StaticsDesign (statics::StaticsDesignOf<ViewModel>), as ViewDesignDerivatives
/// (dV_dp a num_design x 1 map).
struct ViewStaticsDesign {
  using Map = Eigen::Map<Eigen::MatrixXd>;
  static constexpr ViewStruct kStruct = ViewStruct::kStaticsDesign;
  static constexpr std::array<const char*, 4> kNames{"dQ_dp", "ddrive_dp", "dV_dp", "dR_dp"};
  static std::array<Map ViewStaticsDesign::*, 4> Members() {
    using D = ViewStaticsDesign;
    return {&D::dQ_dp, &D::ddrive_dp, &D::dV_dp, &D::dR_dp};
  }
  ViewStaticsDesign() = default;
  ViewStaticsDesign(const ViewStaticsDesign& other) { CopyViewStruct(other, this); }
  ViewStaticsDesign& operator=(const ViewStaticsDesign& other) {
    if (this != &other) CopyViewStruct(other, this);
    return *this;
  }
  alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(kStruct)]> buffer;
  const ModelView* view = nullptr;
  int size = 0;
  Map dQ_dp{nullptr, 0, 0}, ddrive_dp{nullptr, 0, 0}, dV_dp{nullptr, 0, 0}, dR_dp{nullptr, 0, 0};
};
template <>
struct DesignDerivativesOf<ViewModel, true> {
  using type = ViewDesignDerivatives;
};
template <>
struct StaticsDesignOf<ViewModel, true> {
  using type = ViewStaticsDesign;
};
}  // namespace internal

template <>
struct ModelCalls<ViewModel> {
  static constexpr bool kView = true;
  using M = ViewModel;
  using T = ModelTypes<ViewModel>;
  using Trig = internal::ViewTrig;
  using Modes = std::array<int, ModelView::kMaxBlocks>;

  static int Nq(const M& m) { return m.have.nq; }
  static int Nphi(const M& m) { return m.have.nphi; }
  static int Nc(const M& m) { return m.have.nc; }
  static int NumPoints(const M& m) { return m.have.num_points; }
  static int NumBlocks(const M& m) { return HasSolve(m) ? m.view->num_blocks : 1; }
  static bool QIsAngle(const M& m, int i) { return m.view->q_is_angle[i]; }
  static bool PhiIsAngle(const M& m, int i) { return m.view->phi_is_angle[i]; }
  static const double* AssemblyQ(const M& m) { return m.view->assembly_q; }
  static const double* QMin(const M& m) { return m.view->q_min; }
  static const double* QMax(const M& m) { return m.view->q_max; }
  static const double* AssemblyPhi(const M& m) { return m.view->assembly_phi; }
  static bool BlockClosedForm(const M& m, int b) { return HasSolve(m) && m.view->block_closed_form[b]; }
  static Modes DefaultModes(const M& m) {
    Modes modes{};
    if (HasSolve(m)) std::copy(m.view->default_modes, m.view->default_modes + m.view->num_blocks, modes.begin());
    return modes;
  }
  static int NumNamedModes(const M& m) { return m.view->flags.kHasNamedModes ? m.view->num_named_modes : 0; }
  static const char* ModeName(const M& m, int i) { return m.view->mode_names[i]; }
  static void NamedModes(const M& m, int i, Modes* modes) {
    const int n = m.view->num_blocks;
    std::copy(m.view->named_modes + i * n, m.view->named_modes + (i + 1) * n, modes->begin());
  }
  /// Every parameter's default, the derived ones included.
  static ViewParams DefaultParams(const M& m) {
    ViewParams p;
    DefaultParameters(*m.view, p.data());
    return p;
  }

  static const char* Name(const M& m) { return m.view->name; }
  static const char* QName(const M& m, int j) { return m.view->q_names[j]; }
  static const char* PhiName(const M& m, int i) { return m.view->phi_names[i]; }
  static const char* PointName(const M& m, int p) { return m.view->point_names[p]; }
  static int NumTransmissionAngles(const M& m) {
    return m.view->flags.kHasTransmissionAngles && m.view->TransmissionAngles != nullptr
               ? m.view->num_transmission_angles
               : 0;
  }
  static const char* TransmissionJoint(const M& m, int t) { return m.view->transmission_joints[t]; }

  // (ViewModel::Have: read from the view once.)
  static bool HasK(const M& m) { return m.have.K; }
  static bool HasL(const M& m) { return m.have.L; }
  static bool HasPoints(const M& m) { return m.have.points; }
  static bool HasPointVelocities(const M& m) { return m.have.point_velocities; }
  static bool HasPointAccelerations(const M& m) { return m.have.point_accelerations; }
  static bool CoeffsHavePhi(const M& m) { return m.have.coeffs_phi; }
  static bool HasSolve(const M& m) { return m.have.solve; }
  static bool HasTrig(const M& m) { return m.have.trig; }
  static bool LoopFree(const M& m) { return m.have.nc == 0; }

  static void Phi(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi, T::VecC* Phi,
                  T::MatCPhi* Phi_phi, T::MatCQ* Phi_q) {
    const ModelView& v = *m.view;
    if (Phi != nullptr) Phi->resize(v.nc);
    if (Phi_phi != nullptr) Phi_phi->resize(v.nc, v.nphi);
    if (Phi_q != nullptr) Phi_q->resize(v.nc, v.nq);
    v.Phi(p.data(), q.data(), phi.data(), Phi != nullptr ? Phi->data() : nullptr,
          Phi_phi != nullptr ? Phi_phi->data() : nullptr, Phi_q != nullptr ? Phi_q->data() : nullptr);
  }
  static void DetPhiPhi(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi, double* det) {
    m.view->DetPhiPhi(p.data(), q.data(), phi.data(), det);
  }
  /// Phi at expressions (q + dq, ...): evaluated into the bounded types first.
  template <class Q, class P>
  static void Phi(const M& m, const ViewParams& p, const Q& q, const P& phi, T::VecC* Phi, T::MatCPhi* Phi_phi,
                  T::MatCQ* Phi_q) {
    ModelCalls::Phi(m, p, T::VecQ(q), T::VecPhi(phi), Phi, Phi_phi, Phi_q);
  }
  /// Each member of c a map of its buffer at the view's sizes; where the model lacks it, empty
  /// as Coefficients() leaves it (every member placed, whichever: over a Coefficients() just
  /// made, the compiler then drops that one's stores).
  static void MapCoefficients(const M& m, T::Coefficients* c) {
    const ViewModel::CoefficientsLayout& l = m.coefficients;
    double* const buffer = c->buffer.data();
    const int nq = m.have.nq, nphi = m.have.nphi, nc = m.have.nc, np = m.have.num_points;
    using Map = T::Coefficients::Map;
    // (A Map is trivially destructible: placed anew over the old one.)
    auto get = [buffer](int offset, Map* x, int rows, int cols, int rows_none, int cols_none) {
      if (offset >= 0) {
        new (x) Map(buffer + offset, rows, cols);
      } else {
        new (x) Map(nullptr, rows_none, cols_none);
      }
    };
    get(l.Phi, &c->Phi, nc, 1, 0, 1);
    get(l.Phi_phi, &c->Phi_phi, nc, nphi, 0, 0);
    get(l.K, &c->K, nphi, nq, 0, 0);
    get(l.L, &c->L, nphi, nq * nq, 0, 0);
    get(l.r_P, &c->r_P, 2, np, 2, 0);
    get(l.K_P, &c->K_P, 2 * np, nq, 0, 0);
    get(l.L_P, &c->L_P, 2 * np, nq * nq, 0, 0);
  }
  // (Each call with q and phi given as the view's flat arrays, <Call>Flat, is the one place of
  // what the call does; the typed call forwards to it, and so do SizedViewModel's,
  // core/view_sized.h.)
  static void Coeffs(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                     T::Coefficients* c, const Trig* trig = nullptr) {
    CoeffsFlat(m, p, q.data(), phi.data(), c, trig);
  }
  static void CoeffsFlat(const M& m, const ViewParams& p, const double* q, const double* phi, T::Coefficients* c,
                         const Trig* trig) {
    MapCoefficients(m, c);  // (before the call: see MapCoefficients)
    // (The view writes Coefficients whole: the buffer is not read, nothing to initialize.)
    m.view->Coeffs(p.data(), q, phi, c->buffer.data(), trig != nullptr && HasTrig(m) ? trig->buffer.data() : nullptr);
  }
  template <class Mu>
  static void TransmissionAngles(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi, Mu* mu) {
    TransmissionAnglesFlat(m, p, q.data(), phi.data(), mu);
  }
  template <class Mu>
  static void TransmissionAnglesFlat(const M& m, const ViewParams& p, const double* q, const double* phi, Mu* mu) {
    const int n = NumTransmissionAngles(m);
    mu->resize(n);
    if (n > 0) m.view->TransmissionAngles(p.data(), q, phi, mu->data());
  }
  static ViewSolveReport Solve(const M& m, const ViewParams& p, const T::VecQ& q, T::VecPhi* phi,
                               const Modes& modes, int max_iterations, double tolerance, Trig* trig = nullptr) {
    return SolveFlat(m, p, q.data(), phi->data(), modes, max_iterations, tolerance, trig);
  }
  static ViewSolveReport SolveFlat(const M& m, const ViewParams& p, const double* q, double* phi, const Modes& modes,
                                   int max_iterations, double tolerance, Trig* trig) {
    // (The view writes trig whole, 0 for the displacements: nothing to initialize.)
    const bool with_trig = trig != nullptr && HasTrig(m);
    return m.view->Solve(p.data(), q, phi, modes.data(), max_iterations, tolerance,
                         with_trig ? trig->buffer.data() : nullptr);
  }

  // ---- Statics (statics/): the loads, reactions and their functions ----
  /// The view's Forces always takes the input velocities (a model whose statics read none
  /// ignores them).
  static constexpr bool kDeclaresAtSpeed = true;
  // What this view's statics have (its flags; the sizes of ModelTypes<ViewModel>::Statics).
  static bool HasStatics(const M& m) { return m.have.statics; }
  static int NumReactions(const M& m) { return m.have.num_reactions; }
  static int NumFriction(const M& m) { return m.have.num_friction; }
  static bool HasReactions(const M& m) { return NumReactions(m) > 0; }
  static bool HasFriction(const M& m) { return NumFriction(m) > 0; }
  static bool HasPotential(const M& m) { return HasStatics(m) && m.statics.V >= 0 && m.statics.dV_dq >= 0; }
  static bool HasD2V(const M& m) { return HasStatics(m) && m.statics.d2V_dq2 >= 0 && m.view->Stiffness != nullptr; }
  static bool HasStiffness(const M& m) {
    return HasStatics(m) && m.statics.stiffness >= 0 && m.view->Stiffness != nullptr;
  }
  static int NumStaticsAtSpeed(const M& m) { return HasStatics(m) ? m.view->num_statics_at_speed : 0; }
  static bool ReadsSpeed(const M& m) { return NumStaticsAtSpeed(m) > 0; }
  static const char* StaticsAtSpeed(const M& m, int i) { return m.view->statics_at_speed[i]; }
  static const char* ReactionName(const M& m, int i) { return m.view->reaction_names[i]; }
  static int ReactionJoint(const M& m, int i) { return m.view->reaction_joints[i]; }
  static const char* FrictionJoint(const M& m, int i) { return m.view->friction_joints[i]; }
  static bool HasJointLinks(const M& m) {
    return HasReactions(m) && m.view->flags.kHasDrawing && m.view->reaction_joints != nullptr &&
           m.view->draw_joint_link_a != nullptr;
  }
  static int DrawJointLinkA(const M& m, int j) { return m.view->draw_joint_link_a[j]; }
  static int DrawJointLinkB(const M& m, int j) { return m.view->draw_joint_link_b[j]; }
  static int GroundLink(const M& m) { return m.view->ground_link; }
  static const char* LinkName(const M& m, int l) { return m.view->link_names[l]; }

  /// *s placed on this view's Statics layout (where it is not yet), every entry NaN: each member
  /// a map of s->buffer at the sizes the model has (Q, drive nq; dV_dq with the potential;
  /// d2V_dq2, stiffness nq x nq with Stiffness; R NumReactions; normal, gain, K_rel
  /// NumFriction (x nq)), empty where it lacks one (V then NaN). statics::internal::SetNaN.
  static void SetNaNStatics(const M& m, T::Statics* s) {
    if (s->view != m.view) PlaceStatics(m, s);
    internal::FillEntries(s->buffer.data(), s->size, std::numeric_limits<double>::quiet_NaN());
  }
  static void PlaceStatics(const M& m, T::Statics* s) {
    const ViewModel::StaticsLayout& l = m.statics;
    double* const b = s->buffer.data();
    const int nq = Nq(m), nr = NumReactions(m), nf = NumFriction(m);
    using VecMap = T::Statics::VecMap;
    using MatMap = T::Statics::MatMap;
    // (A Map is trivially destructible: placed anew over the old one.)
    auto vec = [b](VecMap* x, int offset, int n) { new (x) VecMap(offset >= 0 ? b + offset : nullptr, offset >= 0 ? n : 0); };
    auto mat = [b](MatMap* x, int offset, int rows, int cols) {
      new (x) MatMap(offset >= 0 ? b + offset : nullptr, offset >= 0 ? rows : 0, offset >= 0 ? cols : 0);
    };
    s->view = m.view;
    s->size = l.size;
    vec(&s->Q, l.Q, nq);
    vec(&s->drive, l.drive, nq);
    s->V.at = HasPotential(m) ? b + l.V : nullptr;
    vec(&s->dV_dq, l.dV_dq, HasPotential(m) ? nq : 0);
    mat(&s->d2V_dq2, l.d2V_dq2, HasD2V(m) ? nq : 0, nq);
    mat(&s->stiffness, l.stiffness, HasStiffness(m) ? nq : 0, nq);
    vec(&s->R, l.R, nr);
    vec(&s->normal, l.normal, nf);
    vec(&s->gain, l.gain, nf);
    mat(&s->K_rel, l.K_rel, nf, nq);
  }
  /// statics::internal::AllFinite of *s placed on this view's layout, and max |R| into
  /// *reaction_norm where that is not nullptr (and the model has reactions): the view's
  /// StaticsChecks, the generated struct's own reads at its fixed sizes.
  static bool StaticsChecks(const M& m, const T::Statics& s, double* reaction_norm) {
    return m.view->StaticsChecks(s.buffer.data(), reaction_norm);
  }
  /// Model::Forces through the view, into *out's buffer (placed on this view first where it is
  /// not yet, SetNaNStatics): the view's function reads what it does not write, which keeps its
  /// value, as in the generated struct. f: the friction loads (NumFriction) or nullptr; qd: the
  /// input velocities or nullptr (at rest; a model whose statics read none ignores them).
  static void Forces(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                     const T::Coefficients& c, T::Statics* out, const T::VecF* f, const T::VecQ* qd) {
    ForcesFlat(m, p, q.data(), phi.data(), c.buffer.data(), out, f != nullptr ? f->data() : nullptr,
               qd != nullptr ? qd->data() : nullptr);
  }
  /// (c: the coefficients in the view's layout of its Coefficients, as the typed calls hold them.)
  static void ForcesFlat(const M& m, const ViewParams& p, const double* q, const double* phi, const double* c,
                         T::Statics* out, const double* f, const double* qd) {
    if (out->view != m.view) SetNaNStatics(m, out);
    m.view->Forces(p.data(), q, phi, c, out->buffer.data(), HasFriction(m) ? f : nullptr, nullptr, qd);
  }
  /// Forces, then StaticsChecks of what it wrote, in the view's one call (ForcesChecked: the
  /// reads wait on the evaluation's results inside the generated code, as a generated model's
  /// own statics do). Returns statics::internal::AllFinite of *out.
  static bool ForcesChecked(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                            const T::Coefficients& c, T::Statics* out, const T::VecF* f, const T::VecQ* qd,
                            double* reaction_norm) {
    return ForcesCheckedFlat(m, p, q.data(), phi.data(), c.buffer.data(), out, f != nullptr ? f->data() : nullptr,
                             qd != nullptr ? qd->data() : nullptr, reaction_norm);
  }
  static bool ForcesCheckedFlat(const M& m, const ViewParams& p, const double* q, const double* phi, const double* c,
                                T::Statics* out, const double* f, const double* qd, double* reaction_norm) {
    if (out->view != m.view) SetNaNStatics(m, out);
    return m.view->ForcesChecked(p.data(), q, phi, c, out->buffer.data(), HasFriction(m) ? f : nullptr,
                                 nullptr, qd, reaction_norm);
  }
  /// The coefficients from a position::State (Phi_phi, K, L and the points; Phi 0) into c's
  /// buffer and its maps, as Coeffs sets them (ModelCalls<M>::StaticsCoefficients).
  template <class State>
  static void StaticsCoefficients(const M& m, const State& s, T::Coefficients* c) {
    const ViewModel::CoefficientsLayout& l = m.coefficients;
    double* const buffer = c->buffer.data();
    internal::FillEntries(buffer, l.size, 0.0);
    auto put = [buffer](int offset, const auto& x) {
      if (offset >= 0) internal::CopyEntries(x.data(), x.size(), buffer + offset);
    };
    put(l.Phi_phi, s.Phi_phi);
    if (HasK(m)) put(l.K, s.K);
    if (HasL(m)) put(l.L, s.L);
    if (HasPoints(m)) put(l.r_P, s.r_P);
    if (HasPointVelocities(m)) put(l.K_P, s.K_P);
    if (HasPointAccelerations(m)) put(l.L_P, s.L_P);
    MapCoefficients(m, c);
  }
  /// Model::Stiffness through the view (d2V_dq2 and stiffness), where the model has it.
  static void Stiffness(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                        const T::Coefficients& c, T::Statics* out) {
    StiffnessFlat(m, p, q.data(), phi.data(), c.buffer.data(), out);
  }
  static void StiffnessFlat(const M& m, const ViewParams& p, const double* q, const double* phi, const double* c,
                            T::Statics* out) {
    if (m.view->Stiffness == nullptr) return;
    if (out->view != m.view) SetNaNStatics(m, out);
    m.view->Stiffness(p.data(), q, phi, c, out->buffer.data());
  }
  // ---- Design (a `design:` section): the design derivatives (position/design.h), the
  //      statics' (statics/sweep.h) and the design checks, through the view ----
  static bool HasDesign(const M& m) { return m.view->flags.kHasDesignDerivatives && m.view->Design != nullptr; }
  static int NumDesign(const M& m) { return HasDesign(m) ? m.view->num_design : 0; }
  static const char* DesignName(const M& m, int d) { return m.view->design_names[d]; }
  static int NumDesignChecks(const M& m) {
    return HasDesign(m) && m.view->DesignChecks != nullptr ? m.view->num_design_checks : 0;
  }
  static const char* DesignCheckName(const M& m, int i) { return m.view->design_check_names[i]; }
  static bool HasStaticsDesign(const M& m) {
    return HasStatics(m) && HasDesign(m) && m.view->flags.kHasStaticsDesign && m.view->StaticsDesign != nullptr;
  }
  /// *d (internal::ViewDesignDerivatives or ViewStaticsDesign) placed on this view's layout
  /// (where it is not yet) with every entry NaN: a step that failed, or where the derivatives
  /// were not asked for (position::SetNanDesign, statics::SetNanStaticsDesign).
  template <class S>
  static void SetNaN(const M& m, S* d) {
    if (d->view != m.view) internal::PlaceViewStruct(*m.view, d);
    internal::FillEntries(d->buffer.data(), d->size, std::numeric_limits<double>::quiet_NaN());
  }
  /// The view's Design into *out. The view reads *out's buffer in before the call (what the
  /// function does not write keeps its value, as in the generated struct): one not yet placed on
  /// this view is set to NaN first.
  static void Design(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                     internal::ViewDesignDerivatives* out) {
    DesignFlat(m, p, q.data(), phi.data(), out);
  }
  static void DesignFlat(const M& m, const ViewParams& p, const double* q, const double* phi,
                         internal::ViewDesignDerivatives* out) {
    if (out->view != m.view) SetNaN(m, out);
    m.view->Design(p.data(), q, phi, out->buffer.data());
  }
  /// The view's StaticsDesign into *out from the coefficients c and the design derivatives dc
  /// (Design's, at the same configuration).
  static void StaticsDesign(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                            const T::Coefficients& c, const internal::ViewDesignDerivatives& dc,
                            internal::ViewStaticsDesign* out) {
    StaticsDesignFlat(m, p, q.data(), phi.data(), c.buffer.data(), dc, out);
  }
  static void StaticsDesignFlat(const M& m, const ViewParams& p, const double* q, const double* phi, const double* c,
                                const internal::ViewDesignDerivatives& dc, internal::ViewStaticsDesign* out) {
    if (out->view != m.view) SetNaN(m, out);
    m.view->StaticsDesign(p.data(), q, phi, c, dc.buffer.data(), out->buffer.data());
  }
  /// The view's DesignChecks: the margins (NumDesignChecks) and, where dmargin_dp is not
  /// nullptr, their derivatives (NumDesignChecks x NumDesign); both sized (and zeroed: the view
  /// reads its outputs in) here.
  using DesignMargins = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, ModelView::kMaxDesignChecks, 1>;
  using DesignMarginsDp =
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, ModelView::kMaxDesignChecks, ModelView::kMaxDesign>;
  static void DesignChecks(const M& m, const ViewParams& p, DesignMargins* margin,
                           DesignMarginsDp* dmargin_dp = nullptr) {
    const int n = NumDesignChecks(m);
    margin->setZero(n);
    if (dmargin_dp != nullptr) dmargin_dp->setZero(n, NumDesign(m));
    if (n > 0) m.view->DesignChecks(p.data(), margin->data(), dmargin_dp != nullptr ? dmargin_dp->data() : nullptr);
  }

  // ---- Dynamics (dynamics/, machines/): inertia, right-hand side, kinetostatics ----
  template <class X = M>
  using DynamicsOut = T::DynamicsOut;
  template <class X = M>
  using RhsOut = T::RhsOut;
  template <class X = M>
  using RhsConstantsOut = T::RhsConstantsOut;
  template <class X = M>
  using KinetostaticsOut = T::KinetostaticsOut;
  template <class X = M>
  using VecKinetoFriction = T::VecFriction;

  static bool HasDynamics(const M& m) { return m.view->flags.kHasDynamics && m.view->Dynamics != nullptr; }
  static bool HasSolveTrig(const M& m) { return m.have.solve_trig; }
  static bool HasRhs(const M& m) { return m.have.rhs; }
  /// The modes of the switching items: the first NumSwitches(m) entries (the others stay 0).
  using SwitchModesArray = std::array<int, ModelView::kMaxSwitches>;
  static int NumSwitches(const M& m) {
    return m.view->flags.kHasSwitchModes && m.view->SwitchModes != nullptr ? m.view->num_switches : 0;
  }
  static bool HasKinetostatics(const M& m) {
    return m.view->flags.kHasStatics && m.view->flags.kHasStaticsQ && m.view->Kinetostatics != nullptr;
  }
  static int KinetoNumReactions(const M& m) {
    return HasKinetostatics(m) && m.view->flags.kHasStaticsR ? m.view->num_reactions : 0;
  }
  static int KinetoNumFriction(const M& m) {
    return HasKinetostatics(m) && m.view->flags.kHasStaticsFriction ? m.view->num_friction : 0;
  }
  static const char* KinetoReactionName(const M& m, int k) { return m.view->reaction_names[k]; }

  static double TrigSinPhi(const M& m, const Trig& trig, int i) {
    return trig.buffer[m.dynamics_layouts.trig_sin_phi + i];
  }
  static double TrigCosPhi(const M& m, const Trig& trig, int i) {
    return trig.buffer[m.dynamics_layouts.trig_cos_phi + i];
  }
  /// The model's entries of `from` into *to (not the buffer's ModelView maximum: a right-hand
  /// side keeps its stage's sin and cos at every call, LastEvaluation in dynamics/forward.h).
  static void CopyTrig(const M& m, const Trig& from, Trig* to) {
    internal::CopyEntries(from.buffer.data(), m.view->Layout(ViewStruct::kTrig).size, to->buffer.data());
  }

  /// The view's Dynamics (sin and cos of the last solve where it has them and nphi > 0, as the
  /// fixed-size call), its I, h, Q, T, V, P_nc copied out.
  static void Dynamics(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi, const T::VecQ& qd,
                       double t, const T::Coefficients& c, T::DynamicsOut* d, const Trig* trig) {
    const ModelView& v = *m.view;
    const ViewModel::DynamicsLayouts::Dynamics& l = m.dynamics_layouts.dynamics;
    double* const b = d->buffer.data();
    internal::FillEntries(b, l.size, 0.0);
    const bool with_trig = trig != nullptr && HasTrig(m) && v.nphi > 0;
    v.Dynamics(p.data(), q.data(), phi.data(), qd.data(), t, c.buffer.data(), b, nullptr,
               with_trig ? trig->buffer.data() : nullptr);
    const int nq = v.nq;
    d->I = Eigen::Map<const Eigen::MatrixXd>(b + l.I, nq, nq);
    d->h = Eigen::Map<const Eigen::VectorXd>(b + l.h, nq);
    d->Q = Eigen::Map<const Eigen::VectorXd>(b + l.Q, nq);
    d->T = b[l.T];
    d->V = b[l.V];
    d->P_nc = b[l.P_nc];
  }
  static ViewSolveReport SolveTrig(const M& m, const ViewParams& p, const T::VecQ& q, const Modes& modes,
                                   Trig* trig) {
    // (The view writes trig whole: nothing to initialize.)
    return m.view->SolveTrig(p.data(), q.data(), modes.data(), trig->buffer.data());
  }
  static void Prepare(const M& m, const ViewParams& p, T::RhsConstantsOut* rc) {
    internal::FillEntries(rc->buffer.data(), m.dynamics_layouts.rhs_constants_size, 0.0);
    m.view->Prepare(p.data(), rc->buffer.data());
  }
  static ViewSolveReport Rhs(const M& m, const ViewParams& p, const T::RhsConstantsOut& rc, const T::VecQ& q,
                             const T::VecQ& qd, double t, const Modes& modes, Trig* trig, T::RhsOut* r) {
    return Rhs(m, p, rc, q.data(), qd.data(), t, modes, trig, r);
  }
  /// The same with q and qd as the view's nq entries each at q and qd (a simulation's state
  /// read in place: the minimal method's right-hand side copies nothing out of it).
  MECHGEN_ALWAYS_INLINE static ViewSolveReport Rhs(const M& m, const ViewParams& p, const T::RhsConstantsOut& rc,
                                                   const double* q, const double* qd, double t, const Modes& modes,
                                                   Trig* trig, T::RhsOut* r) {
    PlaceRhs(m, r);
    return RhsPlaced(m, p, rc, q, qd, t, modes, trig, r);
  }
  /// r's members as maps of its buffer at m's offsets and sizes (a Map is trivially
  /// destructible: placed anew over the last ones). Rhs() places them at every call; an r kept
  /// with its model (a simulation's) once, and then RhsPlaced().
  MECHGEN_ALWAYS_INLINE static void PlaceRhs(const M& m, T::RhsOut* r) {
    const ViewModel::DynamicsLayouts::Rhs& l = m.dynamics_layouts.rhs;
    double* const b = r->buffer.data();
    const int nq = m.have.nq, nphi = m.have.nphi;
    using MatMap = T::RhsOut::MatMap;
    using VecMap = T::RhsOut::VecMap;
    new (&r->K) MatMap(b + l.K, nphi, nq);
    new (&r->I) MatMap(b + l.I, nq, nq);
    new (&r->h) VecMap(b + l.h, nq);
    new (&r->Q) VecMap(b + l.Q, nq);
    new (&r->Phi_phi) MatMap(b + l.Phi_phi, nphi, nphi);
  }
  /// Rhs() into an r whose maps PlaceRhs(m, r) placed (or a copy of such an r: RhsOut's copy
  /// places its own): the call, and T, V and P_nc read out.
  MECHGEN_ALWAYS_INLINE static ViewSolveReport RhsPlaced(const M& m, const ViewParams& p, const T::RhsConstantsOut& rc,
                                                         const double* q, const double* qd, double t,
                                                         const Modes& modes, Trig* trig, T::RhsOut* r) {
    const ViewModel::DynamicsLayouts::Rhs& l = m.dynamics_layouts.rhs;
    double* const b = r->buffer.data();
    // The buffer is not initialized: the generated Rhs stores every entry of its struct (the
    // fixed-size instantiation reads its RhsT, left uninitialized, after the same call), or
    // returns a status other than kConverged, after which nothing is read.
    const ViewSolveReport report =
        m.view->Rhs(p.data(), rc.buffer.data(), q, qd, t, modes.data(), trig->buffer.data(), b, nullptr);
    r->T = b[l.T];
    r->V = b[l.V];
    r->P_nc = b[l.P_nc];
    return report;
  }
  /// The view's SwitchModes into the first NumSwitches(m) entries of *modes.
  template <class SwitchModesT>
  static void SwitchModes(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                          const T::VecQ& qd, double t, const T::Coefficients& c, SwitchModesT* modes) {
    m.view->SwitchModes(p.data(), q.data(), phi.data(), qd.data(), t, c.buffer.data(), modes->data());
  }
  /// The view's Kinetostatics (friction may be nullptr), its Q, drive, R, normal, gain, K_rel
  /// copied out.
  static void Kinetostatics(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                            const T::VecQ& qd, const T::VecQ& qdd, double t, const T::Coefficients& c,
                            T::KinetostaticsOut* out, const T::VecFriction* friction) {
    const ModelView& v = *m.view;
    const ViewModel::DynamicsLayouts::Kinetostatics& l = m.dynamics_layouts.kinetostatics;
    double* const b = out->buffer.data();
    internal::FillEntries(b, l.size, 0.0);
    const int nf = KinetoNumFriction(m);
    v.Kinetostatics(p.data(), q.data(), phi.data(), qd.data(), qdd.data(), t, c.buffer.data(), b,
                    friction != nullptr && nf > 0 ? friction->data() : nullptr, nullptr);
    const int nq = v.nq, nr = KinetoNumReactions(m);
    auto vec = [b](int offset, int n) { return Eigen::Map<const Eigen::VectorXd>(b + (offset >= 0 ? offset : 0), n); };
    out->Q = vec(l.Q, l.Q >= 0 ? nq : 0);
    out->drive = vec(l.drive, l.drive >= 0 ? nq : 0);
    out->R = vec(l.R, l.R >= 0 ? nr : 0);
    out->normal = vec(l.normal, l.normal >= 0 ? nf : 0);
    out->gain = vec(l.gain, l.gain >= 0 ? nf : 0);
    out->K_rel = Eigen::Map<const Eigen::MatrixXd>(b + (l.K_rel >= 0 ? l.K_rel : 0), l.K_rel >= 0 ? nf : 0, nq);
  }

  // ---- Simulation: Coulomb friction and the driven motion (dynamics/friction.h, forward.h,
  // prescribed.h; mechgen_view simulate --friction, --drive) ----
  /// Whether friction joint i is a slide (its load a force, N) or a pin (a torque, N m).
  static bool FrictionPrismatic(const M& m, int i) { return m.view->friction_prismatic[i]; }

  // ---- Machines (engine, flywheel): what machines/ reads beyond the layers above ----
  /// A free parameter of the view's table by its name in *p, nullptr where the model has none
  /// (or it is a derived one); after setting some, ParametersSet(m, p) brings the derived ones
  /// up to date (the view's fill_derived), as the generated expressions read them.
  static double* FindParameter(const M& m, ViewParams* p, const char* name) {
    const int i = ::mechgen::FindParameter(*m.view, name);
    return i >= 0 && i < m.view->num_free_params ? &p->values[static_cast<size_t>(i)] : nullptr;
  }
  static void ParametersSet(const M& m, ViewParams* p) {
    if (m.view->fill_derived != nullptr) m.view->fill_derived(p->data());
  }
  static int NumLinks(const M& m) { return m.view->num_links; }
  static bool HasShaking(const M& m) { return m.view->flags.kHasShaking && m.view->Shaking != nullptr; }
  /// The view's Shaking: its buffer, and F, M, F_link, M_link copied out (2 x num_links).
  struct ShakingResult {
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kShaking)]> buffer;
    Eigen::Vector2d F;
    double M = 0;
    Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, ModelView::kMaxLinks> F_link;
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, ModelView::kMaxLinks, 1> M_link;
  };
  template <class X = M>
  using ShakingOut = ShakingResult;
  template <class X = M>
  static void Shaking(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi, const T::VecQ& qd,
                      const T::VecQ& qdd, const T::Coefficients& c, ShakingResult* out) {
    const ModelView& v = *m.view;
    const ViewLayout& l = v.Layout(ViewStruct::kShaking);
    double* const b = out->buffer.data();
    std::fill_n(b, l.size, 0.0);
    v.Shaking(p.data(), q.data(), phi.data(), qd.data(), qdd.data(), c.buffer.data(), b, nullptr);
    auto at = [&l, b](const char* name) {
      const ViewMember* member = FindMember(l, name);
      return b + (member != nullptr ? member->offset : 0);
    };
    const int nl = v.num_links;
    out->F = Eigen::Map<const Eigen::Vector2d>(at("F"));
    out->M = *at("M");
    out->F_link = Eigen::Map<const Eigen::MatrixXd>(at("F_link"), 2, nl);
    out->M_link = Eigen::Map<const Eigen::VectorXd>(at("M_link"), nl);
  }

  // ---- Design sensitivities of the dynamics (machines/: engine and flywheel --design): the
  //      view's DynamicsDesign and ShakingDesign (ViewStruct::kDynamicsDesign). Both read dc,
  //      the view's DesignDerivatives buffer at the same (q, phi): any result of the Design
  //      section's call with its `buffer` (those calls are not in this section); the friction
  //      loads are none (the machines refuse Coulomb friction). ----
  static bool HasDynamicsDesign(const M& m) {
    return m.view->flags.kHasDynamicsDesign && m.view->DynamicsDesign != nullptr;
  }
  static bool HasShakingDesign(const M& m) {
    return HasDynamicsDesign(m) && m.view->flags.kHasShaking && m.view->ShakingDesign != nullptr;
  }
  /// The view's DynamicsDesign: its buffer, and each member a map of it at the view's sizes
  /// (nq x nq num_design, nq x nq^2 num_design, nq x num_design twice, num_design twice; set by
  /// DynamicsDesign: nothing copied). Not copyable: the maps point into the object's own buffer.
  struct DynamicsDesignResult {
    using MatMap = Eigen::Map<const Eigen::MatrixXd>;
    using VecMap = Eigen::Map<const Eigen::VectorXd>;
    DynamicsDesignResult() = default;
    DynamicsDesignResult(const DynamicsDesignResult&) = delete;
    DynamicsDesignResult& operator=(const DynamicsDesignResult&) = delete;
    alignas(kViewBufferAlignment) std::array<double, ModelView::kMaxStructSize[static_cast<int>(ViewStruct::kDynamicsDesign)]> buffer;
    MatMap dI_dp{nullptr, 0, 0}, ddI_dq_dp{nullptr, 0, 0}, dh_dp{nullptr, 0, 0}, dQ_dp{nullptr, 0, 0};
    VecMap dT_dp{nullptr, 0}, dV_dp{nullptr, 0};
  };
  template <class X = M>
  using DynamicsDesignOut = DynamicsDesignResult;
  /// d/dp of the shaking force (2 x num_design) and moment (num_design), bounded.
  template <class X = M>
  using ShakingDesignForce = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, ModelView::kMaxDesign>;
  template <class X = M>
  using ShakingDesignMoment = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, ModelView::kMaxDesign, 1>;
  /// The view's DynamicsDesign at (t, q, qd); dc: the view's DesignDerivatives at (q, phi).
  template <class X = M, class DesignOut>
  static void DynamicsDesign(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                             const T::VecQ& qd, double t, const T::Coefficients& c, const DesignOut& dc,
                             DynamicsDesignResult* out) {
    const ModelView& v = *m.view;
    const ViewLayout& l = v.Layout(ViewStruct::kDynamicsDesign);
    double* const b = out->buffer.data();
    internal::FillEntries(b, l.size, 0.0);
    v.DynamicsDesign(p.data(), q.data(), phi.data(), qd.data(), t, c.buffer.data(), dc.buffer.data(), b, nullptr);
    auto at = [&l, b](const char* name) {
      const ViewMember* member = FindMember(l, name);
      return b + (member != nullptr ? member->offset : 0);
    };
    const int nq = v.nq, nd = v.num_design;
    using MatMap = DynamicsDesignResult::MatMap;
    using VecMap = DynamicsDesignResult::VecMap;
    // (A Map is trivially destructible: placed anew over the old one.)
    new (&out->dI_dp) MatMap(at("dI_dp"), nq, nq * nd);
    new (&out->ddI_dq_dp) MatMap(at("ddI_dq_dp"), nq, nq * nq * nd);
    new (&out->dh_dp) MatMap(at("dh_dp"), nq, nd);
    new (&out->dQ_dp) MatMap(at("dQ_dp"), nq, nd);
    new (&out->dT_dp) VecMap(at("dT_dp"), nd);
    new (&out->dV_dp) VecMap(at("dV_dp"), nd);
  }
  /// The view's ShakingDesign at (q, qd, qdd); dF_dp or dM_dp may be nullptr (else resized to
  /// the view's num_design).
  template <class X = M, class DesignOut>
  static void ShakingDesign(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi,
                            const T::VecQ& qd, const T::VecQ& qdd, const T::Coefficients& c, const DesignOut& dc,
                            ShakingDesignForce<X>* dF_dp, ShakingDesignMoment<X>* dM_dp) {
    const ModelView& v = *m.view;
    if (dF_dp != nullptr) dF_dp->setZero(2, v.num_design);
    if (dM_dp != nullptr) dM_dp->setZero(v.num_design);
    v.ShakingDesign(p.data(), q.data(), phi.data(), qd.data(), qdd.data(), c.buffer.data(), dc.buffer.data(),
                    dF_dp != nullptr ? dF_dp->data() : nullptr, dM_dp != nullptr ? dM_dp->data() : nullptr);
  }

  // ---- Trajectory sensitivities (dynamics/sensitivity.h, adjoint.h): the view's
  //      DynamicsJacobian and DynamicsDesignProduct (nullptr where the model lacks them: the
  //      sensitivities refuse such a view), dI/dq of its Dynamics ----
  static constexpr int kMaxDesign = ModelView::kMaxDesign;
  template <class X = M>
  using DesignDerivativesOut = internal::ViewDesignDerivatives;
  static bool HasDynamicsJacobian(const M& m) { return HasDynamicsDesign(m) && m.view->DynamicsJacobian != nullptr; }
  static bool HasDynamicsDesignProduct(const M& m) {
    return HasDynamicsDesign(m) && m.view->DynamicsDesignProduct != nullptr;
  }
  /// The view's DynamicsJacobian: each output sized nq x nq and zeroed (the view reads its
  /// outputs in), then filled.
  template <class MatQQ>
  static void DynamicsJacobian(const M& m,
                               const ViewParams& p,
                               const T::VecQ& q,
                               const T::VecPhi& phi,
                               const T::VecQ& qd,
                               double t,
                               const T::Coefficients& c,
                               MatQQ* dQ_dq,
                               MatQQ* dh_dq,
                               MatQQ* dQ_dqd,
                               MatQQ* dh_dqd) {
    const int nq = m.view->nq;
    for (MatQQ* x : {dQ_dq, dh_dq, dQ_dqd, dh_dqd}) x->setZero(nq, nq);
    m.view->DynamicsJacobian(p.data(), q.data(), phi.data(), qd.data(), t, c.buffer.data(), dQ_dq->data(),
                             dh_dq->data(), dQ_dqd->data(), dh_dqd->data(), nullptr);
  }
  /// The view's DynamicsDesignProduct: *product sized num_design and zeroed, then filled.
  template <class VecP>
  static void DynamicsDesignProduct(const M& m,
                                    const ViewParams& p,
                                    const T::VecQ& q,
                                    const T::VecPhi& phi,
                                    const T::VecQ& qd,
                                    double t,
                                    const T::Coefficients& c,
                                    const T::VecQ& qdd,
                                    const T::VecQ& mu,
                                    VecP* product) {
    product->setZero(m.view->num_design);
    m.view->DynamicsDesignProduct(p.data(), q.data(), phi.data(), qd.data(), t, c.buffer.data(), qdd.data(), mu.data(),
                                  product->data(), nullptr);
  }
  /// *to = from: its buffer copied, its maps placed on this view's layout.
  static void CopyCoefficients(const M& m, const T::Coefficients& from, T::Coefficients* to) {
    MapCoefficients(m, to);
    internal::CopyEntries(from.buffer.data(), m.view->Layout(ViewStruct::kCoefficients).size, to->buffer.data());
  }
  /// dI/dq of the view's Dynamics output d (after Dynamics): a map of its buffer, nq x nq^2 (its
  /// offset found once, in ViewModel's DynamicsLayouts: this is read at every evaluation of the
  /// sensitivities' partials).
  template <class X = M>
  static Eigen::Map<const Eigen::MatrixXd> DynamicsDIdq(const M& m, const T::DynamicsOut& d) {
    const int at = m.dynamics_layouts.dynamics.dI_dq, nq = m.have.nq;
    return Eigen::Map<const Eigen::MatrixXd>(d.buffer.data() + (at >= 0 ? at : 0), nq, nq * nq);
  }

  // ---- Synthesis (synthesis/): the parameter table's names, the scene's ground points ----
  /// The free parameters (the first num_free_params of the view's table), by index.
  static int NumFreeParameters(const M& m) { return m.view->num_free_params; }
  static const char* FreeParameterName(const M& m, int i) { return m.view->params[i].name; }
  /// The scene: every named point of every link (none where the view has no Scene).
  static int NumScenePoints(const M& m) { return m.view->Scene != nullptr ? m.view->num_scene_points : 0; }
  static const char* ScenePointName(const M& m, int k) { return m.view->scene_point_names[k]; }
  static int ScenePointLink(const M& m, int k) { return m.view->scene_point_links[k]; }
  static void Scene(const M& m, const ViewParams& p, const T::VecQ& q, const T::VecPhi& phi, T::MatScene* r) {
    r->resize(2, NumScenePoints(m));
    if (NumScenePoints(m) > 0) m.view->Scene(p.data(), q.data(), phi.data(), r->data());
  }
};

}  // namespace mechgen
