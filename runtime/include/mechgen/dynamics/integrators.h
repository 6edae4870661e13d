/**
 * \file dynamics/integrators.h
 * Adaptive explicit Runge–Kutta integrators with dense output, for the equations of motion of
 * mechgen's dynamics (forward.h, excess.h) and for any small fixed-size ODE y' = f(t, y).
 *
 *  - Dopri5<N>: Dormand–Prince 5(4), 7 stages (FSAL, 6 evaluations per step), the 5th-order
 *    solution propagated, the 4th-order one only for the error estimate; dense output of
 *    order 4 by the continuous extension of Hairer's dopri5.f (the "dense output of Shampine
 *    (1986)", coefficients d1..d7), which needs no extra evaluation.
 *  - Dop853<N>: Dormand–Prince 8(5,3) (Hairer, Nørsett, Wanner, Solving Ordinary Differential
 *    Equations I, 2nd ed., Springer 1993, §II.10; Hairer's dop853.f): 12 stages (FSAL, 12
 *    evaluations per step), error estimated from the 5th and 3rd order embedded formulas as in
 *    dop853.f (err5^2 / sqrt(err5^2 + 0.01 err3^2)); dense output of order 7 with 3 extra
 *    evaluations per step, done only when a dense value is asked for in that step. The
 *    coefficients below are those of dop853.f as transcribed in SciPy's
 *    scipy/integrate/_ivp/dop853_coefficients.py (same digits).
 *
 * Step-size control (Hairer's): the error norm is the RMS of e_i / (atol + rtol max(|y_i|,
 * |y_new,i|)); a step is accepted when it is <= 1; the new step is
 * h * clamp(safety * err^(-1/(p+1)) * err_prev^beta, 1/fac_shrink, fac_grow), with
 * p + 1 = 5 (Dopri5) or 8 (Dop853), Lund stabilization beta = 0.04 (Dopri5), 0 (Dop853).
 * The first step is Hairer's hinit estimate when Options::h_initial is 0.
 *
 * The right-hand side is any callable `bool f(double t, const State& y, State* dy)`; false
 * means "not evaluable here" (e.g. the position solver failed at a dead point): the step is
 * rejected and retried with h / 4, and the integration ends with kRhsFailed when h underflows
 * h_min. Nothing allocates (fixed-size Eigen, no std::function); nothing throws.
 *
 * Use: an Integrator object holds the state of one integration. Start() evaluates f at the
 * initial point; each Step() makes one accepted step (never past t_stop); Dense() evaluates
 * the continuous extension anywhere in [t_prev(), t()]. Integrate() runs to t_end with an
 * observer called after every accepted step (events, sampling, projections).
 *
 * Energy-keeping long runs: see forward.h (MinimalOptions::energy_projection): after each
 * accepted step the velocity is projected onto the energy level E0 + W_nc (W_nc the integrated
 * work of the non-conservative forces). Projection was chosen over an implicit symplectic
 * Gauss–Legendre method because each stage of the minimal method solves the positions with
 * the generated solver; an implicit method would nest that inside a Newton iteration on the
 * stages, losing the cheap explicit step, while the projection costs one energy evaluation per
 * step, keeps the explicit pairs and their dense output, and is exact for a conservative
 * one-DOF machine (E determines |qd| at a given q).
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "mechgen/core/invalid_option.h"
#include "mechgen/core/model_calls.h"

namespace mechgen::dynamics {

/// Why an integration (or one step) ended.
enum class IntegratorStatus {
  kRunning,         ///< Step() made an accepted step, t() < t_stop
  kSuccess,         ///< t() == t_end (t_stop) reached
  kStoppedByUser,   ///< the observer returned false (an event the caller stops on)
  kMaxSteps,        ///< steps + rejected >= Options::max_steps
  kStepTooSmall,    ///< the step fell below h_min: |h| < max(h_min, 16 eps |t|)
  kRhsFailed,       ///< f returned false (or a non-finite value) down to h_min
  kInvalidOptions,  ///< Options::IsValid() false, or Start() not called
  kNotRun,
};

inline const char* ToString(IntegratorStatus s) {
  switch (s) {
    case IntegratorStatus::kRunning:
      return "running";
    case IntegratorStatus::kSuccess:
      return "success";
    case IntegratorStatus::kStoppedByUser:
      return "stopped_by_user";
    case IntegratorStatus::kMaxSteps:
      return "max_steps";
    case IntegratorStatus::kStepTooSmall:
      return "step_too_small";
    case IntegratorStatus::kRhsFailed:
      return "rhs_failed";
    case IntegratorStatus::kInvalidOptions:
      return "invalid_options";
    case IntegratorStatus::kNotRun:
      return "not_run";
  }
  return "unknown";
}

struct IntegratorOptions {
  /// Local error per step: RMS_i e_i / (atol + rtol max(|y_i|, |y_new,i|)) <= 1.
  double rtol = 1e-8;
  double atol = 1e-10;
  /// First step; 0: Hairer's automatic estimate from f(t0, y0) and one more evaluation.
  double h_initial = 0;
  /// |h| <= h_max (also the first step's bound); inf: no bound.
  double h_max = std::numeric_limits<double>::infinity();
  /// The integration fails (kStepTooSmall / kRhsFailed) when |h| < h_min.
  double h_min = 0;
  /// Accepted + rejected steps before kMaxSteps.
  int max_steps = 1000000;
  /// h_new = h * clamp(safety * err^(-1/(p+1)) ..., 1/fac_shrink, fac_grow).
  double safety = 0.9;
  double fac_shrink = 5.0;  ///< at most a factor 5 smaller per step (Hairer: 1/fac1 = 5)
  double fac_grow = 10.0;   ///< at most a factor 10 larger per step (Hairer: 1/fac2 = 10 / 6)

  bool IsValid(std::string* error) const {
    auto fail = [error](const char* field, double value, const char* rule) {
      return InvalidOption(error, "IntegratorOptions", field, value, rule);
    };
    if (!(rtol >= 0) || !std::isfinite(rtol)) return fail("rtol", rtol, "0 <= rtol < inf");
    if (!(atol >= 0) || !std::isfinite(atol)) return fail("atol", atol, "0 <= atol < inf");
    if (!(rtol > 0 || atol > 0)) return fail("atol", atol, "rtol > 0 or atol > 0");
    if (!(h_initial >= 0) || !std::isfinite(h_initial))
      return fail("h_initial", h_initial, "0 <= h_initial < inf");
    if (!(h_max > 0)) return fail("h_max", h_max, "h_max > 0");
    if (!(h_min >= 0) || !(h_min < h_max)) return fail("h_min", h_min, "0 <= h_min < h_max");
    if (max_steps < 1) return fail("max_steps", max_steps, "max_steps >= 1");
    if (!(safety > 0 && safety < 1)) return fail("safety", safety, "0 < safety < 1");
    if (!(fac_shrink > 1)) return fail("fac_shrink", fac_shrink, "fac_shrink > 1");
    if (!(fac_grow > 1)) return fail("fac_grow", fac_grow, "fac_grow > 1");
    return true;
  }
};

struct IntegratorSummary {
  IntegratorStatus status = IntegratorStatus::kNotRun;
  int steps = 0;             ///< accepted steps
  int rejected = 0;          ///< rejected steps (error too large or f failed)
  int rhs_evaluations = 0;   ///< calls of f, dense-output stages included
  int dense_evaluations = 0; ///< Dense() calls
  double t = std::numeric_limits<double>::quiet_NaN();       ///< where it ended
  double h_last = std::numeric_limits<double>::quiet_NaN();  ///< the last accepted step
  const char* message = "";                                   ///< static text on failure

  bool IsSolutionUsable() const {
    return status == IntegratorStatus::kSuccess || status == IntegratorStatus::kStoppedByUser;
  }
};

inline std::string FormatSummary(const IntegratorSummary& s) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer),
                "%s at t = %.9g: %d steps, %d rejected, %d rhs evaluations, last h = %.3g%s%s",
                ToString(s.status), s.t, s.steps, s.rejected, s.rhs_evaluations, s.h_last,
                s.message[0] != 0 ? "; " : "", s.message);
  return buffer;
}

namespace internal {

/// Dormand–Prince 5(4) tableau and Hairer's dense output (dopri5.f).
struct Dopri5Tableau {
  static constexpr int kStages = 7;       // the 7th is the FSAL evaluation at (t + h, y_new)
  static constexpr int kOrder = 5;
  static constexpr int kErrorExponentDen = 5;
  static constexpr double kBeta = 0.04;
  static constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
  static constexpr double a21 = 1.0 / 5;
  static constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
  static constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
  static constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                          a54 = -212.0 / 729;
  static constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247,
                          a64 = 49.0 / 176, a65 = -5103.0 / 18656;
  static constexpr double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192,
                          a75 = -2187.0 / 6784, a76 = 11.0 / 84;
  // e = b5 - b4 (error estimate coefficients).
  static constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920,
                          e5 = -17253.0 / 339200, e6 = 22.0 / 525, e7 = -1.0 / 40;
  // Dense output (dopri5.f, CONTD5).
  static constexpr double d1 = -12715105075.0 / 11282082432.0,
                          d3 = 87487479700.0 / 32700410799.0,
                          d4 = -10690763975.0 / 1880347072.0,
                          d5 = 701980252875.0 / 199316789632.0,
                          d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;
};

/// DOP853 coefficients (Hairer's dop853.f; the digits of SciPy's dop853_coefficients.py).
/// Stages 0..11 make the step, stage 12 is f(t + h, y_new) (FSAL), 13..15 the dense output.
struct Dop853Tableau {
  static constexpr int kStages = 12;
  static constexpr int kExtended = 16;
  static constexpr double C[16] = {0.0,
                                   0.526001519587677318785587544488e-01,
                                   0.789002279381515978178381316732e-01,
                                   0.118350341907227396726757197510,
                                   0.281649658092772603273242802490,
                                   0.333333333333333333333333333333,
                                   0.25,
                                   0.307692307692307692307692307692,
                                   0.651282051282051282051282051282,
                                   0.6,
                                   0.857142857142857142857142857142,
                                   1.0,
                                   1.0,
                                   0.1,
                                   0.2,
                                   0.777777777777777777777777777778};
  // A[s][j], j < s; rows 12 (= B) to 15.
  static constexpr double A[16][16] = {
      {},
      {5.26001519587677318785587544488e-2},
      {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2},
      {2.95875854768068491816892993775e-2, 0, 8.87627564304205475450678981324e-2},
      {2.41365134159266685502369798665e-1, 0, -8.84549479328286085344864962717e-1,
       9.24834003261792003115737966543e-1},
      {3.7037037037037037037037037037e-2, 0, 0, 1.70828608729473871279604482173e-1,
       1.25467687566822425016691814123e-1},
      {3.7109375e-2, 0, 0, 1.70252211019544039314978060272e-1,
       6.02165389804559606850219397283e-2, -1.7578125e-2},
      {3.70920001185047927108779319836e-2, 0, 0, 1.70383925712239993810214054705e-1,
       1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
       8.27378916381402288758473766002e-3},
      {6.24110958716075717114429577812e-1, 0, 0, -3.36089262944694129406857109825,
       -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
       2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1},
      {4.77662536438264365890433908527e-1, 0, 0, -2.48811461997166764192642586468,
       -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
       1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
       -2.03312017085086261358222928593e-2},
      {-9.3714243008598732571704021658e-1, 0, 0, 5.18637242884406370830023853209,
       1.09143734899672957818500254654, -8.14978701074692612513997267357,
       -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
       2.49360555267965238987089396762, -3.0467644718982195003823669022},
      {2.27331014751653820792359768449, 0, 0, -1.05344954667372501984066689879e1,
       -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
       2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
       -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
       6.43392746015763530355970484046e-1},
      {5.42937341165687622380535766363e-2, 0, 0, 0, 0, 4.45031289275240888144113950566,
       1.89151789931450038304281599044, -5.8012039600105847814672114227,
       3.1116436695781989440891606237e-1, -1.52160949662516078556178806805e-1,
       2.01365400804030348374776537501e-1, 4.47106157277725905176885569043e-2},
      {5.61675022830479523392909219681e-2, 0, 0, 0, 0, 0, 2.53500210216624811088794765333e-1,
       -2.46239037470802489917441475441e-1, -1.24191423263816360469010140626e-1,
       1.5329179827876569731206322685e-1, 8.20105229563468988491666602057e-3,
       7.56789766054569976138603589584e-3, -8.298e-3},
      {3.18346481635021405060768473261e-2, 0, 0, 0, 0, 2.83009096723667755288322961402e-2,
       5.35419883074385676223797384372e-2, -5.49237485713909884646569340306e-2, 0, 0,
       -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4,
       -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1},
      {-4.28896301583791923408573538692e-1, 0, 0, 0, 0, -4.69762141536116384314449447206,
       7.68342119606259904184240953878, 4.06898981839711007970213554331,
       3.56727187455281109270669543021e-1, 0, 0, 0, -1.39902416515901462129418009734e-3,
       2.9475147891527723389556272149, -9.15095847217987001081870187138}};
  // 3rd-order error: E3 = B - bhh (bhh1, bhh2, bhh3 at stages 0, 8, 11).
  static constexpr double kBhh1 = 0.244094488188976377952755905512,
                          kBhh2 = 0.733846688281611857341361741547,
                          kBhh3 = 0.220588235294117647058823529412e-1;
  // 5th-order error coefficients E5 (stages 0..11).
  static constexpr double E5[12] = {0.1312004499419488073250102996e-1,
                                    0,
                                    0,
                                    0,
                                    0,
                                    -0.1225156446376204440720569753e1,
                                    -0.4957589496572501915214079952,
                                    0.1664377182454986536961530415e1,
                                    -0.3503288487499736816886487290,
                                    0.3341791187130174790297318841,
                                    0.8192320648511571246570742613e-1,
                                    -0.2235530786388629525884427845e-1};
  // Dense output D (4 x 16): the polynomial's coefficients 4..7.
  static constexpr double D[4][16] = {
      {-0.84289382761090128651353491142e1, 0, 0, 0, 0, 0.56671495351937776962531783590,
       -0.30689499459498916912797304727e1, 0.23846676565120698287728149680e1,
       0.21170345824450282767155149946e1, -0.87139158377797299206789907490,
       0.22404374302607882758541771650e1, 0.63157877876946881815570249290,
       -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e2,
       -0.91946323924783554000451984436e1, -0.44360363875948939664310572000e1},
      {0.10427508642579134603413151009e2, 0, 0, 0, 0, 0.24228349177525818288430175319e3,
       0.16520045171727028198505394887e3, -0.37454675472269020279518312152e3,
       -0.22113666853125306036270938578e2, 0.77334326684722638389603898808e1,
       -0.30674084731089398182061213626e2, -0.93321305264302278729567221706e1,
       0.15697238121770843886131091075e2, -0.31139403219565177677282850411e2,
       -0.93529243588444783865713862664e1, 0.35816841486394083752465898540e2},
      {0.19985053242002433820987653617e2, 0, 0, 0, 0, -0.38703730874935176555105901742e3,
       -0.18917813819516756882830838328e3, 0.52780815920542364900561016686e3,
       -0.11573902539959630126141871134e2, 0.68812326946963000169666922661e1,
       -0.10006050966910838403183860980e1, 0.77771377980534432092869265740,
       -0.27782057523535084065932004339e1, -0.60196695231264120758267380846e2,
       0.84320405506677161018159903784e2, 0.11992291136182789328035130030e2},
      {-0.25693933462703749003312586129e2, 0, 0, 0, 0, -0.15418974869023643374053993627e3,
       -0.23152937917604549567536039109e3, 0.35763911791061412378285349910e3,
       0.93405324183624310003907691704e2, -0.37458323136451633156875139351e2,
       0.10409964950896230045147246184e3, 0.29840293426660503123344363579e2,
       -0.43533456590011143754432175058e2, 0.96324553959188282948394950600e2,
       -0.39177261675615439165231486172e2, -0.14972683625798562581422125276e3}};
};

template <class State>
bool AllFinite(const State& y) {
  return y.allFinite();
}

/// The largest state of Dynamic size N (a simulation through the model view, issue 43: the
/// minimal method's (q, qd, W) and the driven one's, at most 2 ModelView::kMaxQ + 2 = 18).
inline constexpr int kMaxDynamicState = 32;
/// The integrators' state: fixed-size, or bounded by kMaxDynamicState (no allocation).
template <int N>
using IntegratorState = Eigen::Matrix<double, N, 1, 0, N == Eigen::Dynamic ? kMaxDynamicState : N, 1>;
/// A zero state of a fixed size; an empty one of a Dynamic size (assigned before it is read).
template <class State>
State ZeroState() {
  if constexpr (State::SizeAtCompileTime != Eigen::Dynamic) {
    return State::Zero();
  } else {
    return State();
  }
}

}  // namespace internal

/**
 * Shared step-size control and bookkeeping of the two pairs (CRTP: Method provides
 * Attempt(f, h, &y_new, &f_new, &err) -> bool and DenseAt(theta, &y)).
 */
template <int N, class Method>
class AdaptiveRungeKutta {
 public:
  /// Eigen::Matrix<double, N, 1>; N may be Eigen::Dynamic (the state's size then that of y0).
  using State = internal::IntegratorState<N>;

  explicit AdaptiveRungeKutta(const IntegratorOptions& options = IntegratorOptions())
      : options_(options) {}

  const IntegratorOptions& options() const { return options_; }
  void set_options(const IntegratorOptions& options) { options_ = options; }

  /// Starts at (t0, y0) towards t_end (the direction of integration is sign(t_end - t0)).
  /// Evaluates f(t0, y0) (and, with h_initial = 0, one more f for the first step).
  template <class Rhs>
  IntegratorStatus Start(Rhs& f, double t0, const State& y0, double t_end) {
    summary_ = IntegratorSummary();
    std::string error;
    if (!options_.IsValid(&error) || !std::isfinite(t0) || !std::isfinite(t_end) ||
        !internal::AllFinite(y0)) {
      summary_.message = "invalid options, t0, t_end or y0";
      return Finish(IntegratorStatus::kInvalidOptions);
    }
    t_ = t_prev_ = t0;
    y_ = y_prev_ = y0;
    t_end_ = t_end;
    direction_ = t_end >= t0 ? 1.0 : -1.0;
    err_prev_ = 1e-4;
    dense_ready_ = false;
    started_ = true;
    if (!Eval(f, t_, y_, &f_)) {
      summary_.message = "f(t0, y0) failed";
      return Finish(IntegratorStatus::kRhsFailed);
    }
    f_prev_ = f_;
    h_ = options_.h_initial > 0 ? std::min(options_.h_initial, options_.h_max)
                                : InitialStep(f);
    summary_.status = IntegratorStatus::kRunning;
    return summary_.status;
  }

  /// One accepted step, not past t_stop (between t() and t_end of Start(); default t_end).
  /// Returns kRunning after a step that did not reach t_end, kSuccess when it did, or a
  /// failure status.
  template <class Rhs>
  IntegratorStatus Step(Rhs& f, double t_stop = std::numeric_limits<double>::quiet_NaN()) {
    if (!started_) return Finish(IntegratorStatus::kInvalidOptions);
    if (summary_.status != IntegratorStatus::kRunning) return summary_.status;
    if (std::isnan(t_stop)) t_stop = t_end_;
    if (direction_ * (t_stop - t_) <= 0) return Finish(IntegratorStatus::kSuccess);
    for (;;) {
      if (summary_.steps + summary_.rejected >= options_.max_steps)
        return Finish(IntegratorStatus::kMaxSteps);
      double h = 0;
      bool last = false;
      const IntegratorStatus next = NextStep(t_stop, &h, &last);
      if (next != IntegratorStatus::kRunning) return next;
      double err = 0;
      const bool ok = static_cast<Method*>(this)->Attempt(f, h, &y_new_, &f_new_, &err);
      if (!ok || !std::isfinite(err)) {
        if (!Retry(h, last)) return Finish(IntegratorStatus::kRhsFailed);
        continue;
      }
      rhs_failed_ = false;
      if (err <= 1.0) return AcceptStep(h, err, last, t_stop);
      RejectStep(h, err);
    }
  }

  /// The continuous extension at t in [t_prev(), t()] (the last accepted step).
  template <class Rhs>
  bool Dense(Rhs& f, double t, State* y) {
    ++summary_.dense_evaluations;
    if (h_used_ == 0 || t == t_) {
      *y = y_;
      return true;
    }
    if (t == t_prev_) {
      *y = y_prev_;
      return true;
    }
    if (!dense_ready_) {
      if (!static_cast<Method*>(this)->PrepareDense(f)) return false;
      dense_ready_ = true;
    }
    static_cast<Method*>(this)->DenseAt((t - t_prev_) / h_used_, y);
    return true;
  }

  /// Replaces the current state (after a projection, or an event that changes the state)
  /// and re-evaluates f there (one evaluation). The dense output of the last step is kept:
  /// it interpolates the step as computed, before the change (y_new_, f_new_).
  template <class Rhs>
  bool Reset(Rhs& f, const State& y) {
    y_ = y;
    State dy;
    if (!Eval(f, t_, y_, &dy)) return false;
    f_ = dy;
    return true;
  }

  /// Undoes the last accepted step: back to (t_prev(), y_prev()) with f there, the step
  /// counted as rejected and the dense output gone (a step that crossed a switching point
  /// of f is redone up to it: Step(f, t_switch)). Once per accepted step.
  void Rewind() {
    if (h_used_ == 0) return;
    t_ = t_prev_;
    y_ = y_prev_;
    f_ = f_prev_;
    h_used_ = 0;
    dense_ready_ = false;
    --summary_.steps;
    ++summary_.rejected;
    summary_.t = t_;
    summary_.status = IntegratorStatus::kRunning;
  }

  /// Starts afresh at (t, y), keeping the counts: f evaluated there (not the first-same-as-last
  /// stage of the step before, which belongs to the other side of a switching point of f), the
  /// step-size controller's memory cleared, the next step |h| (at most h_max). The dense output
  /// of the step before is gone (Dense() gives y). false when f fails there.
  template <class Rhs>
  bool Restart(Rhs& f, double t, const State& y, double h) {
    t_ = t_prev_ = t;
    y_ = y_prev_ = y;
    if (!Eval(f, t_, y_, &f_)) return false;
    f_prev_ = f_;
    h_used_ = 0;
    dense_ready_ = false;
    err_prev_ = 1e-4;
    reject_last_ = false;
    h_ = std::min(std::abs(h), options_.h_max);
    summary_.t = t_;
    summary_.status = direction_ * (t_end_ - t_) <= 0 ? IntegratorStatus::kSuccess : IntegratorStatus::kRunning;
    return true;
  }

  double t() const { return t_; }
  double t_prev() const { return t_prev_; }
  const State& y() const { return y_; }
  const State& y_prev() const { return y_prev_; }
  const State& dy() const { return f_; }   ///< f(t(), y())
  double h_next() const { return h_; }
  const IntegratorSummary& summary() const { return summary_; }

 protected:
  template <class Rhs>
  bool Eval(Rhs& f, double t, const State& y, State* dy) {
    ++summary_.rhs_evaluations;
    return f(t, y, dy) && internal::AllFinite(*dy);
  }

  IntegratorStatus Finish(IntegratorStatus s) {
    summary_.status = s;
    summary_.t = t_;
    return s;
  }

  // ---- Step()'s parts ----
  /// The signed step h towards t_stop (last: it reaches t_stop); kRunning, or Finish()'s status
  /// where the step fell below the minimal one.
  IntegratorStatus NextStep(double t_stop, double* h_out, bool* last) {
    const double eps = std::numeric_limits<double>::epsilon();
    double h = std::min(std::abs(h_), options_.h_max);
    *last = false;
    if (h >= std::abs(t_stop - t_) * (1 - 4 * eps)) {
      h = std::abs(t_stop - t_);
      *last = true;
    }
    const double h_floor = std::max(options_.h_min, 16 * eps * std::abs(t_));
    if (h < h_floor && !*last) {
      summary_.message = rhs_failed_ ? "f failed down to the minimal step"
                                     : "the step fell below the minimal step";
      return Finish(rhs_failed_ ? IntegratorStatus::kRhsFailed : IntegratorStatus::kStepTooSmall);
    }
    *h_out = h * direction_;
    return IntegratorStatus::kRunning;
  }
  /// After an attempt whose f failed (or whose error is not finite): a quarter of the step
  /// next; false (the message set) where it was the last step to the end point and minimal.
  bool Retry(double h, bool last) {
    const double eps = std::numeric_limits<double>::epsilon();
    rhs_failed_ = true;
    ++summary_.rejected;
    h_ = h / 4;
    if (last && std::abs(h) < std::max(options_.h_min, 16 * eps * std::abs(t_))) {
      summary_.message = "f failed at the end point";
      return false;
    }
    return true;
  }
  /// The attempt of step h with error err <= 1 accepted: Lund-stabilized (PI) growth of the
  /// next step; kRunning, or kSuccess at t_end.
  IntegratorStatus AcceptStep(double h, double err, bool last, double t_stop) {
    const double p1 = Method::kErrorExponentDen;
    double fac = err > 0 ? options_.safety * std::pow(err, -1.0 / p1) * std::pow(err_prev_, Method::kBeta)
                         : options_.fac_grow;
    fac = std::min(options_.fac_grow, std::max(1.0 / options_.fac_shrink, fac));
    if (reject_last_) fac = std::min(fac, 1.0);
    err_prev_ = std::max(err, 1e-4);
    reject_last_ = false;
    t_prev_ = t_;
    // (Assign: Eigen's assignment at a fixed size; at the view's bounded Dynamic one a resize
    // and a few stores, where Eigen's dynamic-size assignment is a call of its packet loops.)
    ::mechgen::Assign(&y_prev_, y_);
    ::mechgen::Assign(&f_prev_, f_);
    h_used_ = h;
    t_ = last ? t_stop : t_ + h;
    ::mechgen::Assign(&y_, y_new_);
    ::mechgen::Assign(&f_, f_new_);
    dense_ready_ = false;
    ++summary_.steps;
    summary_.h_last = h;
    summary_.t = t_;
    h_ = h * fac;
    const bool at_end = direction_ * (t_end_ - t_) <= 0;
    return at_end ? Finish(IntegratorStatus::kSuccess) : IntegratorStatus::kRunning;
  }
  /// The attempt of step h with error err > 1 rejected: a shorter step next.
  void RejectStep(double h, double err) {
    const double p1 = Method::kErrorExponentDen;
    ++summary_.rejected;
    reject_last_ = true;
    const double fac = std::max(1.0 / options_.fac_shrink, options_.safety * std::pow(err, -1.0 / p1));
    h_ = h * fac;
  }

  /// Hairer's hinit: h0 from |y| / |f|, then h1 from an estimate of the second derivative.
  template <class Rhs>
  double InitialStep(Rhs& f) {
    const double order = Method::kErrorExponentDen;
    double dnf = 0, dny = 0;
    for (int i = 0; i < y_.size(); ++i) {
      const double sk = options_.atol + options_.rtol * std::abs(y_(i));
      dnf += (f_(i) / sk) * (f_(i) / sk);
      dny += (y_(i) / sk) * (y_(i) / sk);
    }
    double h = (dnf <= 1e-10 || dny <= 1e-10) ? 1e-6 : std::sqrt(dny / dnf) * 0.01;
    h = std::min(h, options_.h_max);
    h = std::min(h, std::abs(t_end_ - t_));
    if (h <= 0) return 1e-6;
    const State y1 = y_ + direction_ * h * f_;
    State f1;
    if (!Eval(f, t_ + direction_ * h, y1, &f1)) return h * 1e-3;
    double der2 = 0;
    for (int i = 0; i < y_.size(); ++i) {
      const double sk = options_.atol + options_.rtol * std::abs(y_(i));
      der2 += ((f1(i) - f_(i)) / sk) * ((f1(i) - f_(i)) / sk);
    }
    der2 = std::sqrt(der2) / h;
    const double der12 = std::max(std::abs(der2), std::sqrt(dnf));
    const double h1 = der12 <= 1e-15 ? std::max(1e-6, h * 1e-3)
                                     : std::pow(0.01 / der12, 1.0 / order);
    return std::min({100 * h, h1, options_.h_max});
  }

  /// N, or the state's size where N is Dynamic.
  double Size() const { return N != Eigen::Dynamic ? double(N) : double(y_.size()); }

  /// The error's scale at entry i: atol + rtol max(|y_i|, |y_new_i|).
  double ErrorScale(Eigen::Index i, double y_new_i) const {
    return options_.atol + options_.rtol * std::max(std::abs(y_(i)), std::abs(y_new_i));
  }
  /// The sum of (e / ErrorScale)^2 (its RMS the step's error).
  double ScaledSquares(const State& e, const State& y_new) const {
    double s = 0;
    for (int i = 0; i < e.size(); ++i) {
      const double sk = ErrorScale(i, y_new(i));
      s += (e(i) / sk) * (e(i) / sk);
    }
    return s;
  }

  IntegratorOptions options_;
  IntegratorSummary summary_;
  double t_ = 0, t_prev_ = 0, t_end_ = 0, h_ = 0, h_used_ = 0, direction_ = 1;
  double err_prev_ = 1e-4;
  bool reject_last_ = false, rhs_failed_ = false, dense_ready_ = false, started_ = false;
  State y_ = internal::ZeroState<State>(), y_prev_ = internal::ZeroState<State>(),
        f_ = internal::ZeroState<State>(), f_prev_ = internal::ZeroState<State>(),
        y_new_ = internal::ZeroState<State>(), f_new_ = internal::ZeroState<State>();
};

/// Dormand–Prince 5(4) with Hairer's dense output (see the file comment).
template <int N>
class Dopri5 : public AdaptiveRungeKutta<N, Dopri5<N>> {
  using Base = AdaptiveRungeKutta<N, Dopri5<N>>;
  friend Base;
  using T = internal::Dopri5Tableau;

 public:
  using State = typename Base::State;
  static constexpr int kErrorExponentDen = T::kErrorExponentDen;
  static constexpr double kBeta = T::kBeta;
  static constexpr int kOrder = 5;
  using Base::Base;

 private:
  // Each stage's state, the new state and the error as one loop over the entries each, into
  // the member ys_ and *y_new (no temporary State of a run-time size per stage; the view's
  // bounded state pays its size once). Per entry the same operations in the same order as
  // the vector expressions y + h * (a_1 k1 + a_2 k2 + ...): the same bits.
  // A Dynamic state (the view's) of the sizes of one, two or three inputs' (q, qd, W) runs
  // the loops at that size known at compile time (unrolled, as a generated model's are); any
  // other at its run-time size. The same operations on every entry either way.
  template <class Rhs>
  bool Attempt(Rhs& f, double h, State* y_new, State* f_new, double* err) {
    if constexpr (N == Eigen::Dynamic) {
      switch (this->y_.size()) {
        case 3:
          return AttemptSized<3>(f, h, y_new, f_new, err);
        case 5:
          return AttemptSized<5>(f, h, y_new, f_new, err);
        case 7:
          return AttemptSized<7>(f, h, y_new, f_new, err);
        default:
          break;
      }
    }
    return AttemptSized<N>(f, h, y_new, f_new, err);
  }
  /// Attempt() with the state's size kSize (N, or a Dynamic state's size at this call).
  template <int kSize, class Rhs>
  bool AttemptSized(Rhs& f, double h, State* y_new, State* f_new, double* err) {
    const State& y = this->y_;
    const State& k1 = this->f_;
    const double t = this->t_;
    const Eigen::Index n = kSize == Eigen::Dynamic ? y.size() : kSize;
    ys_.resize(n);
    y_new->resize(n);
    const double h21 = h * T::a21;
    for (Eigen::Index i = 0; i < n; ++i) ys_(i) = y(i) + h21 * k1(i);
    if (!this->Eval(f, t + T::c2 * h, ys_, &k2_)) return false;
    for (Eigen::Index i = 0; i < n; ++i) ys_(i) = y(i) + h * (T::a31 * k1(i) + T::a32 * k2_(i));
    if (!this->Eval(f, t + T::c3 * h, ys_, &k3_)) return false;
    for (Eigen::Index i = 0; i < n; ++i) {
      ys_(i) = y(i) + h * (T::a41 * k1(i) + T::a42 * k2_(i) + T::a43 * k3_(i));
    }
    if (!this->Eval(f, t + T::c4 * h, ys_, &k4_)) return false;
    for (Eigen::Index i = 0; i < n; ++i) {
      ys_(i) = y(i) + h * (T::a51 * k1(i) + T::a52 * k2_(i) + T::a53 * k3_(i) + T::a54 * k4_(i));
    }
    if (!this->Eval(f, t + T::c5 * h, ys_, &k5_)) return false;
    for (Eigen::Index i = 0; i < n; ++i) {
      ys_(i) = y(i) + h * (T::a61 * k1(i) + T::a62 * k2_(i) + T::a63 * k3_(i) + T::a64 * k4_(i) +
                           T::a65 * k5_(i));
    }
    if (!this->Eval(f, t + h, ys_, &k6_)) return false;
    bool finite = true;
    for (Eigen::Index i = 0; i < n; ++i) {
      (*y_new)(i) = y(i) + h * (T::a71 * k1(i) + T::a73 * k3_(i) + T::a74 * k4_(i) + T::a75 * k5_(i) +
                                T::a76 * k6_(i));
      finite = finite && std::isfinite((*y_new)(i));
    }
    if (!finite) return false;
    if (!this->Eval(f, t + h, *y_new, f_new)) return false;
    // The error estimate and its scaled squares (ScaledSquares()'s sum, fused).
    double s = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double e = h * (T::e1 * k1(i) + T::e3 * k3_(i) + T::e4 * k4_(i) + T::e5 * k5_(i) +
                            T::e6 * k6_(i) + T::e7 * (*f_new)(i));
      const double sk = this->ErrorScale(i, (*y_new)(i));
      s += (e / sk) * (e / sk);
    }
    *err = std::sqrt(s / this->Size());
    // Keep the stages of this attempt for the dense output, if it is accepted.
    ::mechgen::Assign(&s1_, k1);
    return true;
  }

  template <class Rhs>
  bool PrepareDense(Rhs& /*f*/) {
    const double h = this->h_used_;
    const State ydiff = this->y_new_ - this->y_prev_;
    const State bspl = h * s1_ - ydiff;
    r2_ = ydiff;
    r3_ = bspl;
    r4_ = ydiff - h * this->f_new_ - bspl;
    r5_ = h * (T::d1 * s1_ + T::d3 * k3_ + T::d4 * k4_ + T::d5 * k5_ + T::d6 * k6_ +
               T::d7 * this->f_new_);
    return true;
  }

  void DenseAt(double theta, State* y) const {
    const double theta1 = 1 - theta;
    *y = this->y_prev_ + theta * (r2_ + theta1 * (r3_ + theta * (r4_ + theta1 * r5_)));
  }

  State k2_ = internal::ZeroState<State>(), k3_ = internal::ZeroState<State>(),
        k4_ = internal::ZeroState<State>(), k5_ = internal::ZeroState<State>(),
        k6_ = internal::ZeroState<State>(), s1_ = internal::ZeroState<State>();
  State r2_ = internal::ZeroState<State>(), r3_ = internal::ZeroState<State>(),
        r4_ = internal::ZeroState<State>(), r5_ = internal::ZeroState<State>();
  State ys_ = internal::ZeroState<State>();  ///< Attempt(): the state of the stage being evaluated
};

/// Dormand–Prince 8(5,3), DOP853, with its 7th-order dense output (see the file comment).
template <int N>
class Dop853 : public AdaptiveRungeKutta<N, Dop853<N>> {
  using Base = AdaptiveRungeKutta<N, Dop853<N>>;
  friend Base;
  using T = internal::Dop853Tableau;

 public:
  using State = typename Base::State;
  static constexpr int kErrorExponentDen = 8;
  static constexpr double kBeta = 0.0;
  static constexpr int kOrder = 8;
  using Base::Base;

 private:
  template <class Rhs>
  bool Attempt(Rhs& f, double h, State* y_new, State* f_new, double* err) {
    const State& y = this->y_;
    const double t = this->t_;
    k_[0] = this->f_;
    for (int s = 1; s < T::kStages; ++s) {
      State dy = T::A[s][0] * k_[0];
      for (int j = 1; j < s; ++j)
        if (T::A[s][j] != 0) dy += T::A[s][j] * k_[j];
      if (!this->Eval(f, t + T::C[s] * h, y + h * dy, &k_[s])) return false;
    }
    State b = T::A[12][0] * k_[0];
    for (int j = 5; j < T::kStages; ++j) b += T::A[12][j] * k_[j];
    *y_new = y + h * b;
    if (!internal::AllFinite(*y_new)) return false;
    if (!this->Eval(f, t + h, *y_new, f_new)) return false;
    k_[12] = *f_new;
    State e5 = T::E5[0] * k_[0];
    for (int j = 5; j < T::kStages; ++j) e5 += T::E5[j] * k_[j];
    const State e3 = b - T::kBhh1 * k_[0] - T::kBhh2 * k_[8] - T::kBhh3 * k_[11];
    const double err5 = this->ScaledSquares(e5, *y_new);
    const double err3 = this->ScaledSquares(e3, *y_new);
    double denom = err5 + 0.01 * err3;
    if (denom <= 0) denom = 1;
    *err = std::abs(h) * err5 / std::sqrt(denom * this->Size());
    return true;
  }

  template <class Rhs>
  bool PrepareDense(Rhs& f) {
    const double h = this->h_used_;
    const double t = this->t_prev_;
    k_[12] = this->f_new_;  // f at the end of the step as computed (before any Reset())
    for (int s = 13; s < T::kExtended; ++s) {
      State dy = T::A[s][0] * k_[0];
      for (int j = 1; j < s; ++j)
        if (T::A[s][j] != 0) dy += T::A[s][j] * k_[j];
      if (!this->Eval(f, t + T::C[s] * h, this->y_prev_ + h * dy, &k_[s])) return false;
    }
    const State dy = this->y_new_ - this->y_prev_;
    F_[0] = dy;
    F_[1] = h * k_[0] - dy;
    F_[2] = 2 * dy - h * (this->f_new_ + k_[0]);
    for (int r = 0; r < 4; ++r) {
      State s = T::D[r][0] * k_[0];
      for (int j = 5; j < T::kExtended; ++j) s += T::D[r][j] * k_[j];
      F_[3 + r] = h * s;
    }
    return true;
  }

  void DenseAt(double x, State* y) const {
    // y_prev + x (F0 + (1-x) (F1 + x (F2 + (1-x) (F3 + x (F4 + (1-x) (F5 + x F6))))))
    State acc = F_[6] * x;
    acc = (acc + F_[5]) * (1 - x);
    acc = (acc + F_[4]) * x;
    acc = (acc + F_[3]) * (1 - x);
    acc = (acc + F_[2]) * x;
    acc = (acc + F_[1]) * (1 - x);
    acc = (acc + F_[0]) * x;
    *y = this->y_prev_ + acc;
  }

  State k_[16];
  State F_[7];
};

/**
 * \brief Integrates y' = f(t, y) from (t0, y0) to t_end with `Integrator` (Dopri5<N> or
 * Dop853<N>), calling `observer(integrator)` after every accepted step; the observer returns
 * false to stop (kStoppedByUser). Use integrator.Dense() inside the observer for values at
 * requested times.
 * \param[out] y_end  The state at the end (t_end, or where it stopped). May be nullptr.
 * \param[out] summary  Counters and status; not nullptr.
 */
template <class Integrator, class Rhs, class Observer>
bool Integrate(Integrator* integrator, Rhs& f, double t0, const typename Integrator::State& y0,
               double t_end, Observer&& observer, typename Integrator::State* y_end,
               IntegratorSummary* summary) {
  IntegratorStatus s = integrator->Start(f, t0, y0, t_end);
  while (s == IntegratorStatus::kRunning) {
    s = integrator->Step(f);
    if (s != IntegratorStatus::kRunning && s != IntegratorStatus::kSuccess) break;
    if (!observer(*integrator)) {
      s = IntegratorStatus::kStoppedByUser;
      break;
    }
  }
  *summary = integrator->summary();
  summary->status = s;
  if (y_end != nullptr) *y_end = integrator->y();
  return summary->IsSolutionUsable();
}

/// The same without an observer.
template <class Integrator, class Rhs>
bool Integrate(Integrator* integrator, Rhs& f, double t0, const typename Integrator::State& y0,
               double t_end, typename Integrator::State* y_end, IntegratorSummary* summary) {
  return Integrate(integrator, f, t0, y0, t_end, [](Integrator&) { return true; }, y_end,
                   summary);
}

}  // namespace mechgen::dynamics
