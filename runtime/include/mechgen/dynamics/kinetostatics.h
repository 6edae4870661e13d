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
#include "mechgen/core/model_traits.h"
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
  using Statics = typename M::template StaticsT<double>;
  KinetostaticsStatus status = KinetostaticsStatus::kNotRun;
  double t = kNaN;
  Eigen::Matrix<double, M::kNq, 1> q = Eigen::Matrix<double, M::kNq, 1>::Constant(kNaN);
  Eigen::Matrix<double, M::kNq, 1> qd = q, qdd = q;
  Eigen::Matrix<double, M::kNphi, 1> phi = Eigen::Matrix<double, M::kNphi, 1>::Constant(kNaN);
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
  static constexpr int kNq = M::kNq, kNphi = M::kNphi;
  using Params = typename M::template ParamsT<double>;
  using Coefficients = typename M::template CoefficientsT<double>;
  using VecQ = Eigen::Matrix<double, kNq, 1>;
  using VecPhi = Eigen::Matrix<double, kNphi, 1>;
  using Modes = std::array<int, M::kNumBlocks>;
  using Row = KinetostaticsRow<M>;

  explicit Kinetostatics(const Params& p, const KinetostaticsOptions& options = KinetostaticsOptions())
      : p_(p), options_(options) {
    for (int i = 0; i < kNphi; ++i) phi_(i) = M::kAssemblyPhi[i];
  }

  /// Starts the continuation at q0 from phi_guess on `modes`. false if it does not assemble.
  bool Initialize(const VecQ& q0, const VecPhi& phi_guess, const Modes& modes = M::kDefaultModes) {
    modes_ = modes;
    phi_ = phi_guess;
    q_ = q0;
    return Solve(q0, &phi_);
  }
  bool Initialize(const VecQ& q0) {
    VecPhi guess;
    for (int i = 0; i < kNphi; ++i) guess(i) = M::kAssemblyPhi[i];
    return Initialize(q0, guess);
  }

  /// The Coulomb friction loads of the model's friction joints (kFrictionJoints; see
  /// statics/types.h), a vector of size 0 for a model without.
  using VecF = Eigen::Matrix<double, statics::StaticsFeatures<M>::kNumFriction, 1>;

  /// The kinetostatics at (t, q, qd, qdd), positions warm-started from the last row; with the
  /// given Coulomb friction loads (e.g. a free simulation's Sample::friction), else none.
  KinetostaticsStatus Evaluate(double t, const VecQ& q, const VecQ& qd, const VecQ& qdd, Row* row,
                               const VecF* friction = nullptr) {
    row->t = t;
    row->q = q;
    row->qd = qd;
    row->qdd = qdd;
    VecPhi phi = phi_ + K_ * (q - q_);
    if (!Solve(q, &phi)) {
      row->status = KinetostaticsStatus::kPositionFailed;
      return row->status;
    }
    row->phi = phi;
    Coefficients c;
    M::template Coeffs<double>(p_, q, phi, &c);
    double cond = 1;
    if constexpr (kNphi > 0) {
      double det = 0;
      ConditionAndDeterminant(c.Phi_phi, &cond, &det);
      K_ = c.K;
    }
    q_ = q;
    phi_ = phi;
    row->condition = cond;
    if constexpr (statics::StaticsFeatures<M>::kHasFriction) {
      M::template Kinetostatics<double>(p_, q, phi, qd, qdd, t, c, &row->statics, friction);
    } else {
      (void)friction;
      M::template Kinetostatics<double>(p_, q, phi, qd, qdd, t, c, &row->statics);
    }
    row->reaction_norm = ReactionNorm(row->statics);
    const bool finite = row->statics.drive.allFinite();
    if (!(cond <= options_.max_condition) || !finite) {
      row->status = KinetostaticsStatus::kSingular;
      row->statics.drive.setConstant(Row::kNaN);
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
      const auto report = M::template Solve<double>(p_, q, phi, modes_, options_.max_solver_iterations,
                                                    options_.solver_tolerance);
      return report.status == decltype(report.status)::kConverged && phi->allFinite();
    }
  }

  template <class S>
  static double ReactionNorm(const S& s) {
    if constexpr (statics::StaticsFeatures<M>::kNumReactions > 0) {
      return s.R.cwiseAbs().maxCoeff();
    } else {
      (void)s;
      return Row::kNaN;
    }
  }
  template <class S>
  static void WithholdReactions(S* s) {
    if constexpr (statics::StaticsFeatures<M>::kNumReactions > 0) s->R.setConstant(Row::kNaN);
    s->Q.setConstant(Row::kNaN);
  }

  Params p_;
  KinetostaticsOptions options_;
  Modes modes_ = M::kDefaultModes;
  VecQ q_ = VecQ::Zero();
  VecPhi phi_ = VecPhi::Zero();
  Eigen::Matrix<double, kNphi, kNq> K_ = Eigen::Matrix<double, kNphi, kNq>::Zero();
};

}  // namespace mechgen::dynamics
