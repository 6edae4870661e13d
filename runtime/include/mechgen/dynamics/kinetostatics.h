/**
 * \file dynamics/kinetostatics.h
 * Kinetostatics, or inverse dynamics (Paul §6.7): for a prescribed motion q(t), qd(t), qdd(t)
 * of a generated model with dynamics, the driving force of each input and every joint
 * reaction, inertia forces included (the generated EvalKinetostatics: the statics with
 * d'Alembert's forces -m a_G and moments -J alpha added to the loads). Over a cycle of a
 * constant-speed drive these are the bearing loads a designer sizes the bearings with.
 *
 * A configuration where Phi_phi is (nearly) singular is a dead point: there the reactions
 * grow like 1 / sigma_min(Phi_phi), so a row with cond_1(Phi_phi) > max_condition has status
 * kSingular, its drive and reactions withheld (NaN) and the figures (condition, the largest
 * reaction) reported, as the statics sweep does. Nothing allocates; nothing throws.
 *
 * Signs and units: those of the generated Statics (models/README.md): drive = the actuator's
 * torque on the input link (CCW +) or force along the slide; R in kReactionNames order, the
 * force of the joint's first link on its second, fixed frame. Q = Q_applied - (I qdd + h),
 * drive = -Q.
 */
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/statics/traits.h"

namespace mechgen::dynamics {

enum class KinetostaticsStatus {
  kOk,              ///< cond_1(Phi_phi) <= max_condition, every value finite
  kSingular,        ///< cond_1(Phi_phi) > max_condition (a dead point): drive and R withheld
  kPositionFailed,  ///< M::Solve failed at q (the loop does not close, or Newton failed)
  kNotRun,
};

inline const char* ToString(KinetostaticsStatus s) {
  switch (s) {
    case KinetostaticsStatus::kOk:
      return "ok";
    case KinetostaticsStatus::kSingular:
      return "singular";
    case KinetostaticsStatus::kPositionFailed:
      return "position_failed";
    case KinetostaticsStatus::kNotRun:
      return "not_run";
  }
  return "unknown";
}

struct KinetostaticsOptions {
  /// Singular (a dead point) when cond_1(Phi_phi) > max_condition (as the statics runtime).
  double max_condition = kMaxCondition;  // 1 / kMinRcond (core/constants.h)
  int max_solver_iterations = 20;
  double solver_tolerance = 0;
};

/// One row of a kinetostatic analysis.
template <class M>
struct KinetostaticsRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  using Statics = typename ModelCalls<M>::template KinetostaticsOut<M>;
  KinetostaticsStatus status = KinetostaticsStatus::kNotRun;
  double t = kNaN;
  /// (NaN at a generated model's fixed sizes; empty at the view's until set.)
  typename ModelTypes<M>::VecQ q = NaNs<typename ModelTypes<M>::VecQ>();
  typename ModelTypes<M>::VecQ qd = q, qdd = q;
  typename ModelTypes<M>::VecPhi phi = NaNs<typename ModelTypes<M>::VecPhi>();
  Statics statics;  ///< drive, Q, R (kReactionNames), ... of the generated EvalKinetostatics
  double condition = kNaN;      ///< cond_1(Phi_phi) (1 for kNphi = 0)
  double reaction_norm = kNaN;  ///< max_i |R_i|, computed even when singular (the figure)
};

/// Summary of a cycle.
struct KinetostaticsSummary {
  int rows = 0;
  int singular_rows = 0;
  int failed_rows = 0;
  double max_abs_drive = 0;     ///< over the usable rows
  double max_reaction = 0;      ///< max |R_i| over the usable rows
  double drive_work = 0;        ///< integral of drive . qd dt (trapezoid over the rows)
  bool IsSolutionUsable() const { return rows > 0 && singular_rows == 0 && failed_rows == 0; }
};

/**
 * Kinetostatics<M>: Evaluate() one configuration, Cycle() a prescribed motion sampled at
 * rows + 1 equally spaced times (positions continued from row to row, so the assembly mode
 * of Initialize() is kept).
 */
template <class M>
class Kinetostatics {
 public:
  /// The model's sizes, constants and functions (core/model_calls.h): constant for a generated
  /// M, the view's (at run time) for ViewModel.
  using Calls = ModelCalls<M>;
  using Types = ModelTypes<M>;
  static constexpr int kNq = M::kNq, kNphi = M::kNphi;
  using Params = typename Types::Params;
  using Coefficients = typename Types::Coefficients;
  using VecQ = typename Types::VecQ;
  using VecPhi = typename Types::VecPhi;
  using MatK = typename Types::MatK;
  using Modes = typename Calls::Modes;
  using Row = KinetostaticsRow<M>;
  /// Whether Statics::R may exist (the view's model: at run time, Calls::KinetoNumReactions).
  static constexpr bool kMayHaveReactions = [] {
    if constexpr (Calls::kView) {
      return true;
    } else {
      return Calls::KinetoNumReactions(M()) > 0;
    }
  }();

  /// (A generated M only: a ViewModel names its view.)
  template <class Model = M, std::enable_if_t<!ModelCalls<Model>::kView, int> = 0>
  explicit Kinetostatics(const Params& p, const KinetostaticsOptions& options = KinetostaticsOptions())
      : Kinetostatics(M(), p, options) {}
  /// The kinetostatics of `model` (a ViewModel; for a generated M an empty tag).
  Kinetostatics(const M& model, const Params& p, const KinetostaticsOptions& options = KinetostaticsOptions())
      : model_(model), p_(p), options_(options), modes_(Calls::DefaultModes(model)) {
    const int nq = Calls::Nq(model), nphi = Calls::Nphi(model);
    q_ = Sized<VecQ>(nq);
    q_.setZero();
    phi_ = Sized<VecPhi>(nphi);
    K_ = Sized<MatK>(nphi, nq);
    K_.setZero();
    for (int i = 0; i < nphi; ++i) phi_(i) = Calls::AssemblyPhi(model)[i];
  }

  /// Starts the continuation at q0 from phi_guess on `modes` (the model's default ones). false
  /// if it does not assemble.
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess) {
    return Initialize(q0, phi_guess, Calls::DefaultModes(model_));
  }
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess, const Modes& modes) {
    modes_ = modes;
    phi_ = phi_guess;
    q_ = q0;
    return Solve(q0, &phi_);
  }
  bool Initialize(const VecQ& q0) {
    const int nphi = Calls::Nphi(model_);
    auto guess = Sized<VecPhi>(nphi);
    for (int i = 0; i < nphi; ++i) guess(i) = Calls::AssemblyPhi(model_)[i];
    return Initialize(q0, guess);
  }

  /// The Coulomb friction loads of the model's friction joints (kFrictionJoints; see
  /// statics/types.h), a vector of size 0 for a model without.
  using VecF = typename Calls::template VecKinetoFriction<M>;

  /// The kinetostatics at (t, q, qd, qdd), positions warm-started from the last row; with the
  /// given Coulomb friction loads (e.g. a free simulation's Sample::friction), else none.
  KinetostaticsStatus Evaluate(double t, const VecQ& q, const VecQ& qd, const VecQ& qdd, Row* row,
                               const VecF* friction = nullptr) {
    row->t = t;
    row->q = q;
    row->qd = qd;
    row->qdd = qdd;
    VecPhi phi = phi_ + Times(K_, VecQ(q - q_));
    if (!Solve(q, &phi)) {
      row->status = KinetostaticsStatus::kPositionFailed;
      return row->status;
    }
    row->phi = phi;
    Coefficients c;
    Calls::Coeffs(model_, p_, q, phi, &c);
    double cond = 1;
    if constexpr (kNphi != 0) {
      if (Calls::Nphi(model_) > 0) {
        double det = 0;
        ConditionAndDeterminant(c.Phi_phi, &cond, &det);
        K_ = c.K;
      }
    }
    q_ = q;
    phi_ = phi;
    row->condition = cond;
    Calls::Kinetostatics(model_, p_, q, phi, qd, qdd, t, c, &row->statics, friction);
    row->reaction_norm = ReactionNorm(row->statics);
    const bool finite = row->statics.drive.allFinite();
    if (!(cond <= options_.max_condition) || !finite) {
      row->status = KinetostaticsStatus::kSingular;
      row->statics.drive.setConstant(Row::kNaN);  // (empty at the view's sizes: resized before)
      WithholdReactions(&row->statics);
      return row->status;
    }
    row->status = KinetostaticsStatus::kOk;
    return row->status;
  }

  /**
   * \brief A prescribed motion over [t0, t1] at rows + 1 times.
   * \param[in] motion    void(double t, VecQ* q, VecQ* qd, VecQ* qdd).
   * \param[in] observer  bool(const Row&): every row; false stops.
   */
  template <class Motion, class Observer>
  KinetostaticsSummary Cycle(Motion&& motion, double t0, double t1, int rows, Observer&& observer) {
    KinetostaticsSummary s;
    double prev_power = 0, prev_t = t0;
    for (int k = 0; k <= rows; ++k) {
      const double t = t0 + (t1 - t0) * k / std::max(rows, 1);
      VecQ q, qd, qdd;
      motion(t, &q, &qd, &qdd);
      Row row;
      const KinetostaticsStatus st = Evaluate(t, q, qd, qdd, &row);
      ++s.rows;
      if (st == KinetostaticsStatus::kOk) {
        s.max_abs_drive = std::max(s.max_abs_drive, row.statics.drive.cwiseAbs().maxCoeff());
        s.max_reaction = std::max(s.max_reaction, row.reaction_norm);
        const double power = row.statics.drive.dot(qd);
        if (k > 0) s.drive_work += 0.5 * (power + prev_power) * (t - prev_t);
        prev_power = power;
      } else if (st == KinetostaticsStatus::kSingular) {
        ++s.singular_rows;
      } else {
        ++s.failed_rows;
      }
      prev_t = t;
      if (!observer(row)) break;
    }
    return s;
  }

  /// A constant speed w from q0: q = q0 + w t (each input), qd = w, qdd = 0.
  static auto ConstantSpeed(const VecQ& q0, const VecQ& w) {
    return [q0, w](double t, VecQ* q, VecQ* qd, VecQ* qdd) {
      *q = q0 + w * t;
      *qd = w;
      qdd->setZero();
    };
  }

 private:
  bool Solve(const VecQ& q, VecPhi* phi) {
    if constexpr (kNphi == 0) {
      (void)q;
      (void)phi;
      return true;
    } else {
      if (Calls::Nphi(model_) == 0) return true;  // (a view without loops)
      const auto report =
          Calls::Solve(model_, p_, q, phi, modes_, options_.max_solver_iterations, options_.solver_tolerance);
      return report.status == decltype(report.status)::kConverged && phi->allFinite();
    }
  }

  template <class S>
  double ReactionNorm(const S& s) const {
    if constexpr (kMayHaveReactions) {
      if (Calls::KinetoNumReactions(model_) > 0) return s.R.cwiseAbs().maxCoeff();
    }
    (void)s;
    return Row::kNaN;
  }
  template <class S>
  void WithholdReactions(S* s) const {
    if constexpr (kMayHaveReactions) s->R.setConstant(Row::kNaN);
    s->Q.setConstant(Row::kNaN);
  }

  M model_;
  Params p_;
  KinetostaticsOptions options_;
  Modes modes_;
  VecQ q_;
  VecPhi phi_;
  MatK K_;
};

}  // namespace mechgen::dynamics
