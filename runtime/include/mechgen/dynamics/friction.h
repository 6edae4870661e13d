/**
 * \file dynamics/friction.h
 * Coulomb friction in the free simulation (forward.h MinimalDynamics), with stick and slip:
 * the friction joints of the model's `friction:` section (the friction circle mu r |F| at a
 * pin, mu |N| at a slide; models/README.md, Statics), their normal forces from the generated
 * EvalKinetostatics (the reactions with the inertia forces, which depend on qdd).
 *
 * Slip (the input moving, or leaving rest, in the direction e = +-1; kNq = 1): each friction
 * joint J opposes its relative motion,
 *     f_J = -gain_J normal_J(qdd, f) sign(K_rel_J e),
 *     I qdd = Q(f = 0) - h + K_rel^T f,
 * an implicit equation in (qdd, f) since the normal forces depend on both. SlipLoads() solves
 * it by fixed-point iteration from f = 0: qdd from the f before, then EvalKinetostatics at
 * (qdd, f) for the normal forces and the next f, until max |f_k - f_(k-1)| <= tolerance
 * max |f_k| (or all f are 0). The iteration contracts when the friction's share of the
 * inertia is small (mu r |dF/dqdd| |K_rel| < I: every practical bearing); where it does not
 * (friction near jamming, Painleve's paradox of rigid bodies) it fails with a status, never
 * a value. The direction e is the slip mode's, held for the whole slip: the friction load is
 * smooth along it, extended past the speed's zero, which the event loop locates.
 *
 * At rest (qd = 0, the speed's zero reached, or stuck): Q0 = Q(t, q, qd = 0, f = 0) is the
 * applied generalized force, and the friction bound
 *     B = sum_J gain_J normal_J |K_rel_J|
 * is computed from the reactions at rest (EvalKinetostatics at qd = qdd = 0, the friction
 * loads of an impending slip in e = sign(Q0) iterated on them as the statics does). The
 * motion sticks when |Q0| <= B; else it slips in e = sign(Q0), provided the slip's own
 * acceleration points that way (e qdd_slip > 0; a slip that would at once stop again is no
 * slip: the chattering the event loop would otherwise make of a force at the bound). While
 * stuck, qd = qdd = 0 and the friction loads hold Q0: f = f_bound |Q0| / B (one joint: exactly
 * -Q0 / K_rel; several: each at the same fraction of its bound, one choice among the
 * statically indeterminate ones).
 *
 * Several inputs (kNq > 1, Mixed()): each joint has its own mode (JointModes): slipping with
 * the sign dir_J of its relative velocity K_rel_J qd (held while it slips: f_J = -gain_J
 * normal_J dir_J), or stuck, holding the one input its relative motion is (K_rel_J = k e_i):
 * q_i held (qd_i = qdd_i = 0), the other inputs free, I_ff qdd_f = b_f with b = Q - h + the
 * slipping joints' K_rel^T f, and the holding load f_J = (I_i. qdd - b_i) / k, within the
 * bound gain_J normal_J. The loads, the holding ones included, are iterated on the
 * kinetostatics as Slip() does. The decision where a joint reaches relative rest (forward.h,
 * DecideJoints) is made for it and every stuck joint together: all stuck, then released one
 * at a time (the largest |f_J| / bound_J > 1 first, slipping against its holding load) until
 * all hold, a released one whose slip would at once stop (dir_J K_rel_J qdd <= 0) stuck for
 * good. Not simulated: the stick of a joint whose relative velocity combines several inputs
 * (a status naming the joint).
 *
 * Driven (Prescribed(), every input driven: q, qd, qdd given): f_J = -gain_J normal_J
 * sign(K_rel_J qd) iterated on the kinetostatics at the motion; 0 at a joint's relative rest,
 * where it is indeterminate within +-gain_J normal_J (the actuator holds the whole load).
 *
 * Units and signs: f_J is the friction torque on the joint's second link by its first (a pin,
 * N m, counter-clockwise +) or the friction force on the slider along the slide's +u (N), as
 * the generated statics' friction loads (statics/types.h). Nothing allocates; nothing throws.
 */
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/statics/traits.h"

namespace mechgen::dynamics {

/// Coulomb friction of the free simulation (MinimalOptions::coulomb).
struct CoulombOptions {
  /// Simulate the model's Coulomb friction (its friction joints with a coefficient, at the
  /// run's parameters). No effect on a model without Coulomb friction (every gain 0) or with
  /// a caller's Load (whose forces the reactions would miss: MinimalSummary::message says so).
  /// PrescribedOptions::coulomb: the same for a driven run (max_iterations, tolerance).
  bool enabled = true;
  /// The slip's fixed-point iteration: at most max_iterations kinetostatic evaluations;
  /// converged when max |f_k - f_(k-1)| <= tolerance max |f_k|.
  int max_iterations = 60;
  double tolerance = 1e-14;
  /// Chattering guard: a stick-slip transition within min_interval (s) of the one before
  /// counts as chattering; after max_chattering of them, or after max_transitions
  /// transitions in all, the run ends (Status::kFrictionFailed) with a message.
  double min_interval = 1e-9;
  int max_chattering = 20;
  int max_transitions = 1000000;

  bool IsValid() const {
    return max_iterations >= 2 && tolerance > 0 && tolerance < 1e-3 && min_interval >= 0 &&
           std::isfinite(min_interval) && max_chattering >= 1 && max_transitions >= 1;
  }
};

namespace internal {
/// The most friction joints of a model: its count, or for the model view (a count known at run
/// time only, Eigen::Dynamic) the bound of its types (ModelTypes<ViewModel>::kMaxFriction).
template <class M, int N>
struct MaxFrictionOf : std::integral_constant<int, N> {};
template <class M>
struct MaxFrictionOf<M, Eigen::Dynamic> : std::integral_constant<int, ModelTypes<M>::kMaxFriction> {};
/// A zero vector of type V: of its fixed size, or empty where the size is known at run time
/// only (the model view's; sized where it is assigned).
template <class V>
V ZeroOrEmpty() {
  if constexpr (V::SizeAtCompileTime != Eigen::Dynamic) {
    return V::Zero();
  } else {
    return V();
  }
}
}  // namespace internal

/// What the free simulation knows of a model's Coulomb friction. For the model view
/// (ModelCalls<M>::kView) kNumFriction is Eigen::Dynamic (the view's KinetoNumFriction() at
/// run time, at most kMaxFriction) and kHasFriction says that it may have some.
template <class M, bool = HasDynamics<M>::value>
struct CoulombFeatures {
  static constexpr int kNumFriction = 0;
  static constexpr int kMaxFriction = 0;
  static constexpr bool kHasFriction = false;
};
template <class M>
struct CoulombFeatures<M, true> {
  static constexpr int kNumFriction = statics::StaticsFeatures<M>::kNumFriction;
  static constexpr int kMaxFriction = internal::MaxFrictionOf<M, kNumFriction>::value;
  /// Friction joints and the generated EvalKinetostatics taking their loads.
  static constexpr bool kHasFriction = kNumFriction > 0 || kNumFriction == Eigen::Dynamic;
};

/// The friction of one evaluation (Sample::friction of a free simulation); kMax bounds a
/// run-time count (kNumFriction = Eigen::Dynamic: the model view's).
template <int kNumFriction, int kMax = kNumFriction>
struct FrictionState {
  using VecF = Eigen::Matrix<double, kNumFriction, 1, 0, kMax, 1>;
  VecF f = internal::ZeroOrEmpty<VecF>();  ///< the friction loads (see the file comment for units and signs)
  double Q_friction = 0;  ///< their generalized force K_rel^T f (kNq = 1)
  double bound = 0;       ///< at rest: B, the largest |Q_friction| static friction holds
  int iterations = 0;     ///< kinetostatic evaluations made
};

/**
 * The modes of the friction joints of a model with several inputs (kNq > 1, see the file
 * comment): joint J slips with its relative velocity's sign dir[J] (+1 or -1, held while it
 * slips), or it is stuck, holding input held[J] at rest (a joint whose relative velocity is
 * k[J] times that input's speed alone, K_rel row J = k[J] e_held).
 */
template <int kNumFriction>
struct JointModes {
  std::array<bool, kNumFriction> stuck{};
  std::array<double, kNumFriction> dir{};
  std::array<int, kNumFriction> held{};
  std::array<double, kNumFriction> k{};
  bool AnyStuck() const {
    for (bool b : stuck)
      if (b) return true;
    return false;
  }
};

namespace internal {
/// K_rel^T f of one input (K_rel: a column of the friction joints' entries): Eigen's inner
/// product of a generated model's fixed sizes; for the model view's bounded dynamic K_rel and f
/// the same product on fixed-size copies of the view's count (Eigen's unrolled reduction adds
/// the entries pairwise, its reduction of a run-time length in order: from three joints on the
/// sums would round otherwise), so that both give the same bits.
template <int k = 1, class MatKrel, class VecF>
double FrictionForceOfOneInput(const MatKrel& K_rel, const VecF& f) {
  if constexpr (MatKrel::RowsAtCompileTime != Eigen::Dynamic) {
    return (K_rel.transpose() * f)(0);
  } else if constexpr (k <= MatKrel::MaxRowsAtCompileTime) {
    if (f.rows() != k) return FrictionForceOfOneInput<k + 1>(K_rel, f);
    const Eigen::Matrix<double, k, 1> K = K_rel.col(0);
    const Eigen::Matrix<double, k, 1> fk = f;
    return (K.transpose() * fk)(0);
  } else {
    return K_rel.col(0).dot(f);
  }
}
}  // namespace internal

/**
 * CoulombFriction<M>: the slip's friction loads and the decision at rest, at one
 * configuration (q, phi, c) of a model with kNq = 1 (see the file comment); Prescribed() for
 * a driven motion and Mixed() for several inputs, any kNq. The model is reached through
 * ModelCalls<M> (core/model_calls.h): a generated model's empty tag, or the model view
 * (its friction joints and inputs counted at run time; Mixed() on fixed-size copies of its
 * inputs' count, MixedDynamic).
 */
template <class M>
class CoulombFriction {
 public:
  using Calls = ModelCalls<M>;
  static constexpr int kNq = M::kNq;
  static constexpr int kNumFriction = CoulombFeatures<M>::kNumFriction;
  static constexpr int kMaxFriction = CoulombFeatures<M>::kMaxFriction;
  using Params = typename ModelTypes<M>::Params;
  using Coefficients = typename ModelTypes<M>::Coefficients;
  using Statics = typename Calls::template KinetostaticsOut<M>;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  using State = FrictionState<kNumFriction, kMaxFriction>;
  using VecF = typename State::VecF;

  /// The friction joints (kNumFriction, the view's at run time).
  static int Count(const M& model) {
    if constexpr (kNumFriction != Eigen::Dynamic) {
      (void)model;
      return kNumFriction;
    } else {
      return Calls::KinetoNumFriction(model);
    }
  }
  /// Zero inputs, and zero loads of every friction joint, at the model's sizes.
  static VecQ ZeroQ(const M& model) {
    if constexpr (kNq != Eigen::Dynamic) {
      (void)model;
      return VecQ::Zero();
    } else {
      return VecQ::Zero(Calls::Nq(model));
    }
  }
  static VecF ZeroF(const M& model) {
    if constexpr (kNumFriction != Eigen::Dynamic) {
      (void)model;
      return VecF::Zero();
    } else {
      return VecF::Zero(Count(model));
    }
  }
  /// The kinetostatics at (t, q, qd, qdd) with the friction loads f (nullptr: none).
  static void Kineto(const M& model, const Params& p, const VecQ& q, const VecPhi& phi, const VecQ& qd,
                     const VecQ& qdd, double t, const Coefficients& c, Statics* st, const VecF* f) {
    Calls::Kinetostatics(model, p, q, phi, qd, qdd, t, c, st, f);
  }

  /// Every gain_J (mu r, mu) at p, from one evaluation at (q, phi): is any Coulomb friction there?
  static bool AnyGain(const M& model, const Params& p, const VecQ& q, const VecPhi& phi, const Coefficients& c) {
    const int nf = Count(model);
    if (nf == 0) return false;  // (a view without friction joints)
    Statics st;
    const VecQ zero = ZeroQ(model);
    Kineto(model, p, q, phi, zero, zero, 0.0, c, &st, nullptr);
    for (int J = 0; J < nf; ++J)
      if (st.gain(J) != 0) return true;
    return false;
  }

  /**
   * \brief The slip's qdd and friction loads in direction e (+1 or -1) at (t, q, qd):
   * Q_minus_h = Q(f = 0) - h and I from the generated EvalDynamics there.
   * \return false when the iteration does not converge or a value is not finite.
   */
  static bool Slip(const M& model,
                   const CoulombOptions& o,
                   const Params& p,
                   const VecQ& q,
                   const VecPhi& phi,
                   const VecQ& qd,
                   double t,
                   const Coefficients& c,
                   double I,
                   double Q_minus_h,
                   double e,
                   VecQ* qdd,
                   State* s) {
    Statics st;
    const int nf = Count(model);
    VecF f = ZeroF(model);
    (*qdd)(0) = Q_minus_h / I;
    s->iterations = 0;
    for (int k = 0; k < o.max_iterations; ++k) {
      Kineto(model, p, q, phi, qd, *qdd, t, c, &st, &f);
      ++s->iterations;
      VecF f_next = ZeroF(model);
      for (int J = 0; J < nf; ++J) f_next(J) = -st.gain(J) * st.normal(J) * Sign(st.K_rel(J, 0) * e);
      if (!f_next.allFinite()) return false;
      const double change = (f_next - f).cwiseAbs().maxCoeff();
      const double size = f_next.cwiseAbs().maxCoeff();
      f = f_next;
      const double Q_f = internal::FrictionForceOfOneInput(st.K_rel, f);
      (*qdd)(0) = (Q_minus_h + Q_f) / I;
      if (!std::isfinite((*qdd)(0))) return false;
      if (change <= o.tolerance * size) {
        s->f = f;
        s->Q_friction = Q_f;
        s->bound = std::numeric_limits<double>::quiet_NaN();
        return true;
      }
    }
    return false;
  }

  /**
   * \brief At rest at (t, q) (qd = 0): the bound B from the reactions at rest, for an
   * impending slip in e = sign(Q0) (Q0 = Q(t, q, 0, f = 0)); s->f the loads at the bound.
   * \return false when the iteration does not converge or a value is not finite.
   */
  static bool Bound(const M& model,
                    const CoulombOptions& o,
                    const Params& p,
                    const VecQ& q,
                    const VecPhi& phi,
                    double t,
                    const Coefficients& c,
                    double Q0,
                    State* s) {
    Statics st;
    const int nf = Count(model);
    VecF f = ZeroF(model);
    const VecQ zero = ZeroQ(model);
    const double e = Q0 > 0 ? 1.0 : -1.0;  // Q0 = 0: either way (B does not depend on it
                                           // at one friction joint)
    s->iterations = 0;
    for (int k = 0; k < o.max_iterations; ++k) {
      Kineto(model, p, q, phi, zero, zero, t, c, &st, &f);
      ++s->iterations;
      VecF f_next = ZeroF(model);
      double B = 0;
      for (int J = 0; J < nf; ++J) {
        f_next(J) = -st.gain(J) * st.normal(J) * Sign(st.K_rel(J, 0) * e);
        B += st.gain(J) * st.normal(J) * std::abs(st.K_rel(J, 0));
      }
      if (!f_next.allFinite() || !std::isfinite(B)) return false;
      const double change = (f_next - f).cwiseAbs().maxCoeff();
      f = f_next;
      if (change <= o.tolerance * f.cwiseAbs().maxCoeff()) {
        s->f = f;
        s->bound = B;
        s->Q_friction = internal::FrictionForceOfOneInput(st.K_rel, f);
        return true;
      }
    }
    return false;
  }

  /// The loads that hold Q0 while stuck, from the bound's state b (|Q0| <= b.bound).
  static void Holding(double Q0, const State& b, State* s) {
    *s = b;
    if (b.bound > 0) {
      s->f = b.f * (std::abs(Q0) / b.bound);
    } else {
      s->f.setZero();
    }
    s->Q_friction = -Q0;
  }

  /**
   * \brief A prescribed motion (q, qd, qdd all given: every input driven): the friction loads
   * f_J = -gain_J normal_J(f) sign(K_rel_J qd) iterated on the kinetostatics at (q, qd, qdd, f)
   * from f = 0 until max |f_k - f_(k-1)| <= tolerance max |f_k| (the statics' iteration;
   * qdd does not change). At zero relative velocity (K_rel_J qd = 0 exactly, e.g. a drive at
   * rest) the joint's friction is statically indeterminate in [-gain_J N_J, gain_J N_J]: it
   * is taken 0 there (the actuator holds the whole load). *Q_f = K_rel^T f, the friction's
   * generalized force; *st the kinetostatics with the converged loads.
   * \return false when the iteration does not converge or a value is not finite.
   */
  static bool Prescribed(const M& model,
                         const CoulombOptions& o,
                         const Params& p,
                         const VecQ& q,
                         const VecPhi& phi,
                         const VecQ& qd,
                         const VecQ& qdd,
                         double t,
                         const Coefficients& c,
                         VecF* f,
                         VecQ* Q_f,
                         int* iterations) {
    Statics st;
    const int nf = Count(model);
    *f = ZeroF(model);
    *iterations = 0;
    for (int k = 0; k < o.max_iterations; ++k) {
      Kineto(model, p, q, phi, qd, qdd, t, c, &st, f);
      ++*iterations;
      VecF f_next = ZeroF(model);
      for (int J = 0; J < nf; ++J)
        f_next(J) = -st.gain(J) * st.normal(J) * Sign(st.K_rel.row(J).dot(qd));
      if (!f_next.allFinite()) return false;
      const double change = (f_next - *f).cwiseAbs().maxCoeff();
      *f = f_next;
      if (change <= o.tolerance * f->cwiseAbs().maxCoeff()) {
        if constexpr (kNq != Eigen::Dynamic) {
          *Q_f = st.K_rel.transpose() * *f;
        } else if (Calls::Nq(model) == 1) {
          // (one input: the fixed-size inner product's sums, FrictionForceOfOneInput)
          Q_f->resize(1);
          (*Q_f)(0) = internal::FrictionForceOfOneInput(st.K_rel, *f);
        } else {
          // Several inputs through the view: each entry a coefficient-based sum over the
          // joints (Times); from three friction joints on its last bit may differ from the
          // fixed-size product's (no such model is shipped).
          *Q_f = Times(st.K_rel.transpose(), *f);
        }
        return Q_f->allFinite();
      }
    }
    return false;
  }

  /**
   * \brief Several inputs (kNq > 1) in the modes m at (t, q, qd): the stuck joints' inputs
   * held (qd and qdd 0 there), every other input free; I qdd = Q - h + K_rel^T f with
   * f_J = -gain_J normal_J dir[J] at a slipping joint and the holding load at a stuck one
   * (f_J = (I_i. qdd - b_i) / k[J], i = held[J], b = Q - h + the slipping joints' K_rel^T f),
   * iterated on the kinetostatics at (q, qd, qdd, f) as Slip() does. *bound: gain_J normal_J
   * of every joint (a stuck joint holds while |f_J| <= bound_J). *K_rel: the joints' rows.
   * \return false when the iteration does not converge, the free inputs' inertia is not
   * positive definite or a value is not finite.
   */
  template <class MatI, class MatKrel>
  static bool Mixed(const M& model,
                    const CoulombOptions& o,
                    const Params& p,
                    const VecQ& q,
                    const VecPhi& phi,
                    const VecQ& qd,
                    double t,
                    const Coefficients& c,
                    const MatI& I,
                    const VecQ& Q_minus_h,
                    const JointModes<kMaxFriction>& m,
                    VecQ* qdd,
                    VecF* f,
                    VecF* bound,
                    MatKrel* K_rel,
                    int* iterations) {
    if constexpr (kNq != Eigen::Dynamic) {
      return MixedOf<kNq>(model, o, p, q, phi, qd, t, c, I, Q_minus_h, m, qdd, f, bound, K_rel, iterations);
    } else {
      return MixedDynamic<2>(model, o, p, q, phi, qd, t, c, I, Q_minus_h, m, qdd, f, bound, K_rel, iterations);
    }
  }

  /// Joint J's row of K_rel is k e_i (one input's speed alone, any other entry exactly 0):
  /// *input = i, *k = that entry; false otherwise.
  template <class MatKrel>
  static bool InputJoint(const MatKrel& K_rel, int J, int* input, double* k) {
    *input = -1;
    for (int i = 0; i < static_cast<int>(K_rel.cols()); ++i) {
      if (K_rel(J, i) == 0) continue;
      if (*input >= 0) return false;
      *input = i;
      *k = K_rel(J, i);
    }
    return *input >= 0 && std::isfinite(*k);
  }

  static double Sign(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

 private:
  /// Mixed() of the view's model (its inputs known at run time) on MixedOf<k> of its count k:
  /// the inputs' arithmetic (the reduced inertia's LDLT, its solves, I_i. qdd) on fixed-size
  /// k-vectors, as the fixed-size instantiation's.
  template <int k, class MatI, class MatKrel>
  static bool MixedDynamic(const M& model, const CoulombOptions& o, const Params& p, const VecQ& q,
                           const VecPhi& phi, const VecQ& qd, double t, const Coefficients& c, const MatI& I,
                           const VecQ& Q_minus_h, const JointModes<kMaxFriction>& m, VecQ* qdd, VecF* f,
                           VecF* bound, MatKrel* K_rel, int* iterations) {
    if constexpr (k <= ModelTypes<M>::kMaxQ) {
      if (Calls::Nq(model) != k)
        return MixedDynamic<k + 1>(model, o, p, q, phi, qd, t, c, I, Q_minus_h, m, qdd, f, bound, K_rel, iterations);
      return MixedOf<k>(model, o, p, q, phi, qd, t, c, I, Q_minus_h, m, qdd, f, bound, K_rel, iterations);
    } else {
      return false;  // (more inputs than a view has)
    }
  }

  /// MixedOf()'s reduced inertia: I with a held input's row and column replaced by the
  /// identity's (*held: which inputs a stuck joint holds).
  template <int n>
  static Eigen::Matrix<double, n, n> ReducedInertia(const Eigen::Matrix<double, n, n>& I,
                                                    const JointModes<kMaxFriction>& m, int nf,
                                                    std::array<bool, n>* held) {
    Eigen::Matrix<double, n, n> A = I;
    for (int J = 0; J < nf; ++J)
      if (m.stuck[J]) (*held)[m.held[J]] = true;
    for (int i = 0; i < n; ++i) {
      if (!(*held)[i]) continue;
      A.row(i).setZero();
      A.col(i).setZero();
      A(i, i) = 1;
    }
    return A;
  }
  /// One iteration's accelerations of MixedOf(): b = Q - h plus the slipping joints' friction
  /// loads K_rel_J^T f_J (st: the last kinetostatics, nullptr before the first), qdd from the
  /// reduced inertia (ldlt) with the held inputs at rest.
  template <int n>
  static void MixedAccelerations(const Eigen::LDLT<Eigen::Matrix<double, n, n>>& ldlt,
                                 const Eigen::Matrix<double, n, 1>& Q_minus_h, const std::array<bool, n>& held,
                                 const JointModes<kMaxFriction>& m, int nf, const Statics* st, const VecF& f,
                                 Eigen::Matrix<double, n, 1>* b, Eigen::Matrix<double, n, 1>* qdd) {
    *b = Q_minus_h;
    if (st != nullptr)
      for (int J = 0; J < nf; ++J)
        if (!m.stuck[J]) *b += st->K_rel.row(J).transpose() * f(J);
    Eigen::Matrix<double, n, 1> rhs = *b;
    for (int i = 0; i < n; ++i)
      if (held[i]) rhs(i) = 0;
    *qdd = ldlt.solve(rhs);
    for (int i = 0; i < n; ++i)
      if (held[i]) (*qdd)(i) = 0;
  }

  /// Mixed() on n = Nq inputs (kNq; the view's count: see MixedDynamic). For a generated
  /// model VecN is VecQ and every copy below is of the same type.
  template <int n, class MatI, class MatKrel>
  static bool MixedOf(const M& model, const CoulombOptions& o, const Params& p, const VecQ& q, const VecPhi& phi,
                      const VecQ& qd, double t, const Coefficients& c, const MatI& I_in, const VecQ& Q_minus_h_in,
                      const JointModes<kMaxFriction>& m, VecQ* qdd_out, VecF* f, VecF* bound, MatKrel* K_rel,
                      int* iterations) {
    using VecN = Eigen::Matrix<double, n, 1>;
    using MatN = Eigen::Matrix<double, n, n>;
    const int nf = Count(model);
    const MatN I = I_in;
    const VecN Q_minus_h = Q_minus_h_in;
    std::array<bool, n> held{};
    const Eigen::LDLT<MatN> ldlt(ReducedInertia<n>(I, m, nf, &held));
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0)) return false;
    Statics st;
    if constexpr (kNumFriction == Eigen::Dynamic) {
      f->setZero(nf);
      bound->resize(nf);
    } else {
      f->setZero();
    }
    *iterations = 0;
    bool have_K = false;
    VecN qdd;
    VecQ qdd_q = ZeroQ(model);
    for (int k = 0; k < o.max_iterations; ++k) {
      VecN b;
      MixedAccelerations<n>(ldlt, Q_minus_h, held, m, nf, have_K ? &st : nullptr, *f, &b, &qdd);
      VecF f_now = *f;
      for (int J = 0; J < nf; ++J)
        if (m.stuck[J]) f_now(J) = (I.row(m.held[J]).dot(qdd) - b(m.held[J])) / m.k[J];
      qdd_q = qdd;
      Kineto(model, p, q, phi, qd, qdd_q, t, c, &st, &f_now);
      ++*iterations;
      have_K = true;
      VecF f_next = f_now;
      for (int J = 0; J < nf; ++J) {
        (*bound)(J) = st.gain(J) * st.normal(J);
        if (!m.stuck[J]) f_next(J) = -(*bound)(J) * m.dir[J];
      }
      if (!f_next.allFinite() || !qdd.allFinite()) return false;
      const double change = (f_next - *f).cwiseAbs().maxCoeff();
      *f = f_next;
      if (k > 0 && change <= o.tolerance * f->cwiseAbs().maxCoeff()) {
        *qdd_out = qdd_q;
        *K_rel = st.K_rel;
        return true;
      }
    }
    *qdd_out = qdd_q;
    return false;
  }
};

}  // namespace mechgen::dynamics
