// Speed against accuracy of position, velocity-coefficient (K) and centripetal-coefficient
// (L) analysis, per model and per method (issue 6; bench/accuracy/README.md).
//
// Every method walks the configurations of the model's reference file
// (tests/reference/data/<model>.csv, 50 digits) in order, one configuration per Step():
//   closed_form          hand-derived positions, K, L (four-bar: tests/runtime/
//                        handwritten_fourbar.h; slider-crank: below)
//   runtime              mechgen::position::CeresPositionSolver::MoveTo (second-order predictor, Newton
//                        on the generated Phi/Phi_phi, stop at ||Phi|| <= 1e-10) + generated K, L;
//                        where it stops with kSingular (cond_1(Phi_phi) >= 1 / min_rcond) the
//                        row counts as refused and the next rows re-assemble on the same branch
//   dyads                the generated Model::Solve (SolvePositions: blocks in order, closed-form
//                        dyads on the model's assembly modes, Newton on blocks without one) from
//                        the previous phi, then generated EvalCoefficients
//   monolithic           the `--strategy monolithic` emission: predictor phi + K dq, its
//                        Model::Solve (one Newton on all of Phi, stop at |Phi| <= 1e-12 then one
//                        more step), its EvalCoefficients (K and L by one dense LU of Phi_phi)
//   newton_symbolic      our lean loop: predictor phi + K dq, Newton on generated EvalPhi until
//                        the step |dphi| <= 1e-9 (one more iteration than a residual test),
//                        then generated EvalCoefficients (symbolically solved K, L)
//   newton_numeric       the same positions; K by a fixed-size LU solve of the generated
//                        Phi_phi, Phi_q; L by the same solve of -(dPhi_phi/dq K + dPhi_q/dq),
//                        the derivatives by a ceres::Jet<double, 1> pass through EvalPhi
//   ceres_analytic / ceres_autodiff / ceres_numeric
//                        Ceres LM (one problem reused, warm start) with the generated Phi_phi,
//                        with AutoDiffCostFunction, with NumericDiffCostFunction (central);
//                        then generated K, L at Ceres's phi
//   fd_h<h>              K, L by central differences of Newton positions at q -+ h
//   ode_rk4, ode_rk4_newton10
//                        Paul's differential-equation method (§4.4.2): phi' = K(q, phi)
//                        integrated by RK4 from one configuration to the next, without and
//                        with a Newton correction every 10 configurations
//   float_newton         the lean loop in single precision (EvalPhi<float>, EvalCoefficients<float>)
//   float_dyads          dyads in single precision (Model::Solve<float>, EvalCoefficients<float>)
// `accuracy_bench --errors_dir=DIR` first writes DIR/<model>_sweep.csv (errors per
// configuration and method, with cond_1(Phi_phi)) and DIR/<model>_errors.csv (max errors per
// method); then Google Benchmark times one Step() per iteration (the walk goes back and
// forth over the rows): "<model>/<method>". "cost/<variant>/{lean,runtime}" time the
// fourbar variants of bench/accuracy/models (positions only, + K, + L, + point).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <ceres/ceres.h>

#include "handwritten_fourbar.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "reference_data.h"

#include "fourbar.h"
#include "fourbar_k.h"
#include "fourbar_kl.h"
#include "fourbar_klp.h"
#include "fourbar_pos.h"
#include "fourbar_toggle.h"
#include "slider_crank.h"
#include "watt_sixbar.h"
// The monolithic emissions (bench/accuracy/CMakeLists.txt) and the N-chains at
// MECHGEN_ACCURACY_CHAINS = X(2)X(4)... (accuracy_chain_headers.h, written by CMake).
#include "accuracy_chain_headers.h"
#include "fourbar_monolithic.h"
#include "fourbar_toggle_monolithic.h"
#include "slider_crank_monolithic.h"
#include "watt_sixbar_monolithic.h"

namespace {

using mechgen::reference::Data;

// ---------------------------------------------------------------------------------------
// Scalar-generic pieces.

template <class M, class S>
using VecQ = Eigen::Matrix<S, M::kNq, 1>;
template <class M, class S>
using VecPhi = Eigen::Matrix<S, M::kNphi, 1>;
template <class M, class S>
using MatK = Eigen::Matrix<S, M::kNphi, M::kNq>;
template <class M, class S>
using MatL = Eigen::Matrix<S, M::kNphi, M::kNq * M::kNq>;

// Newton on the generated Phi at fixed q, stopping when the step |dphi|_inf <= step_tol
// (the error after that step is ~|dphi|^2: at the rounding floor for 1e-9 in double).
template <class M, class S>
bool Newton(const typename M::template ParamsT<S>& p, const VecQ<M, S>& q, VecPhi<M, S>* phi,
            S step_tol, int max_iterations = 12) {
  Eigen::Matrix<S, M::kNc, 1> Phi;
  Eigen::Matrix<S, M::kNc, M::kNphi> A;
  for (int it = 0; it < max_iterations; ++it) {
    M::template Phi<S>(p, q, *phi, &Phi, &A, nullptr);
    VecPhi<M, S> dphi;
    if constexpr (M::kNphi <= 4) {
      dphi = A.inverse() * Phi;
    } else {
      dphi = Eigen::PartialPivLU<Eigen::Matrix<S, M::kNc, M::kNphi>>(A).solve(Phi);
    }
    *phi -= dphi;
    const S step = dphi.template lpNorm<Eigen::Infinity>();
    if (!(step == step)) return false;
    if (step <= step_tol) return true;
  }
  return false;
}

// What a method produces at one configuration.
template <class M>
struct Config {
  VecPhi<M, double> phi;
  MatK<M, double> K;
  MatL<M, double> L;
  bool refused = false;  ///< the method declined to give a result here (runtime: kSingular)
};

template <class M>
class Method {
 public:
  using T = mechgen::ModelTypes<M>;
  virtual ~Method() = default;
  /// Starts at q0 with a converged phi0.
  virtual void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) = 0;
  /// Moves to q; false on failure.
  virtual bool Step(const typename T::VecQ& q, Config<M>* out) = 0;
};

template <class M>
using MethodFactory = std::function<std::unique_ptr<Method<M>>()>;

// Generated K and L at (q, phi).
template <class M>
void GeneratedKL(const typename M::template ParamsT<double>& p, const VecQ<M, double>& q,
                 const VecPhi<M, double>& phi, Config<M>* out) {
  typename M::template CoefficientsT<double> c;
  M::template Coeffs<double>(p, q, phi, &c);
  out->phi = phi;
  out->K = c.K;
  out->L = c.L;
}

// ---- runtime -----------------------------------------------------------------------------
template <class M>
class Runtime : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    mechgen::position::Summary s;
    solver_.Assemble(q0, phi0, 0, &s);
    stopped_ = false;
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    mechgen::position::Summary s;
    bool ok = false;
    if (!stopped_) {
      const mechgen::position::Status status = solver_.MoveTo(q, &s);
      ok = status == mechgen::position::Status::kConverged;
      stopped_ = status == mechgen::position::Status::kSingular;
      branch_ = solver_.state().branch;
    } else {  // after a singular stop: assemble again on the branch followed so far
      ok = solver_.Assemble(q, solver_.state().phi, branch_, &s) == mechgen::position::Status::kConverged;
      stopped_ = !ok;
    }
    out->refused = stopped_;
    out->phi = solver_.state().phi;
    out->K = solver_.state().K;
    out->L = solver_.state().L;
    return ok;
  }

 private:
  mechgen::position::CeresPositionSolver<M> solver_;
  bool stopped_ = false;
  int branch_ = 0;
};

// ---- the generated position solver: closed-form dyads (block order) ---------------------------
template <class M>
class Dyads : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  void Start(const typename T::VecQ&, const typename T::VecPhi& phi0) override { phi_ = phi0; }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    // phi_ is the start of Newton blocks and the reference closed-form angles stay near.
    const auto report = M::template Solve<double>(p_, q, &phi_);
    GeneratedKL<M>(p_, q, phi_, out);
    return report.status == decltype(report.status)::kConverged;
  }

 private:
  typename T::Params p_;
  typename T::VecPhi phi_;
};

template <class M>
class FloatDyads : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  void Start(const typename T::VecQ&, const typename T::VecPhi& phi0) override {
    phi_ = phi0.template cast<float>();
  }
  bool Step(const typename T::VecQ& qd, Config<M>* out) override {
    const VecQ<M, float> q = qd.template cast<float>();
    const auto report = M::template Solve<float>(p_, q, &phi_);
    typename M::template CoefficientsT<float> c;
    M::template Coeffs<float>(p_, q, phi_, &c);
    out->phi = phi_.template cast<double>();
    out->K = c.K.template cast<double>();
    out->L = c.L.template cast<double>();
    return report.status == decltype(report.status)::kConverged;
  }

 private:
  typename M::template ParamsT<float> p_;
  VecPhi<M, float> phi_;
};

// ---- the monolithic emission: one Newton on all of Phi, K and L by one dense LU -------------
// MM is the same model generated with --strategy monolithic (same sizes and layouts).
template <class M, class MM>
class Monolithic : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  static_assert(MM::kNphi == M::kNphi && MM::kNq == M::kNq, "not the same model");
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    q_ = q0;
    phi_ = phi0;
    typename MM::template CoefficientsT<double> c;
    MM::template Coeffs<double>(p_, q0, phi0, &c);
    K_ = c.K;
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    phi_ += K_ * (q - q_);
    const auto report = MM::template Solve<double>(p_, q, &phi_);
    typename MM::template CoefficientsT<double> c;
    MM::template Coeffs<double>(p_, q, phi_, &c);
    out->phi = phi_;
    out->K = c.K;
    out->L = c.L;
    q_ = q;
    K_ = c.K;
    return report.status == decltype(report.status)::kConverged;
  }

 private:
  typename MM::template ParamsT<double> p_;
  typename T::VecQ q_;
  typename T::VecPhi phi_;
  typename T::MatK K_;
};

// ---- lean Newton continuation, symbolic or numeric K and L ---------------------------------
template <class M, bool kNumericKL>
class LeanNewton : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    q_ = q0;
    phi_ = phi0;
    Config<M> c;
    Coefficients(q0, phi0, &c);
    K_ = c.K;
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    typename T::VecPhi phi = phi_ + K_ * (q - q_);
    const bool ok = Newton<M, double>(p_, q, &phi, 1e-9);
    Coefficients(q, phi, out);
    q_ = q;
    phi_ = phi;
    K_ = out->K;
    return ok;
  }

 private:
  void Coefficients(const typename T::VecQ& q, const typename T::VecPhi& phi, Config<M>* out) {
    if constexpr (!kNumericKL) {
      GeneratedKL<M>(p_, q, phi, out);
    } else {
      typename T::MatCPhi A;
      typename T::MatCQ B;
      M::template Phi<double>(p_, q, phi, nullptr, &A, &B);
      const Eigen::PartialPivLU<typename T::MatCPhi> lu(A);
      out->phi = phi;
      out->K = -lu.solve(B);
      // Total derivative of Phi_phi and Phi_q along (dq, dphi) = (e_k, K e_k), exactly, by
      // one forward-mode (Jet) pass per input.
      using J = ceres::Jet<double, 1>;
      const typename M::template ParamsT<J> pj = p_.template Cast<J>();
      for (int k = 0; k < M::kNq; ++k) {
        VecQ<M, J> qj;
        VecPhi<M, J> phij;
        for (int j = 0; j < M::kNq; ++j) qj(j) = J(q(j), 0), qj(j).v[0] = j == k ? 1 : 0;
        for (int i = 0; i < M::kNphi; ++i) phij(i) = J(phi(i)), phij(i).v[0] = out->K(i, k);
        Eigen::Matrix<J, M::kNc, M::kNphi> Aj;
        Eigen::Matrix<J, M::kNc, M::kNq> Bj;
        M::template Phi<J>(pj, qj, phij, nullptr, &Aj, &Bj);
        typename T::MatCPhi dA;
        typename T::MatCQ dB;
        for (int r = 0; r < M::kNc; ++r) {
          for (int c = 0; c < M::kNphi; ++c) dA(r, c) = Aj(r, c).v[0];
          for (int c = 0; c < M::kNq; ++c) dB(r, c) = Bj(r, c).v[0];
        }
        for (int j = 0; j < M::kNq; ++j)
          out->L.col(j + M::kNq * k) = -lu.solve(typename T::VecC(dA * out->K.col(j) + dB.col(j)));
      }
    }
  }

  typename T::Params p_;
  typename T::VecQ q_;
  typename T::VecPhi phi_;
  typename T::MatK K_;
};

// ---- Ceres ------------------------------------------------------------------------------
enum class CeresKind { kAnalytic, kAutoDiff, kNumeric };

template <class M, CeresKind kKind>
class Ceres : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  Ceres() : options_(mechgen::position::LevenbergMarquardtOptions(100)) {
    ceres::CostFunction* cost = nullptr;
    if constexpr (kKind == CeresKind::kAnalytic) {
      cost = new mechgen::position::PhiCostFunction<M>(&p_, &q_);
    } else if constexpr (kKind == CeresKind::kAutoDiff) {
      cost = new ceres::AutoDiffCostFunction<mechgen::position::PhiAutoDiffFunctor<M>, M::kNc, M::kNphi>(
          new mechgen::position::PhiAutoDiffFunctor<M>(&p_, &q_));
    } else {
      cost = new ceres::NumericDiffCostFunction<mechgen::position::PhiAutoDiffFunctor<M>, ceres::CENTRAL,
                                                M::kNc, M::kNphi>(
          new mechgen::position::PhiAutoDiffFunctor<M>(&p_, &q_));
    }
    problem_.AddResidualBlock(cost, nullptr, phi_.data());
  }
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    q_ = q0;
    phi_ = phi0;
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    q_ = q;
    ceres::Solver::Summary summary;
    ceres::Solve(options_, &problem_, &summary);
    GeneratedKL<M>(p_, q_, phi_, out);
    return summary.termination_type == ceres::CONVERGENCE;
  }

 private:
  typename T::Params p_;
  typename T::VecQ q_ = T::VecQ::Zero();
  typename T::VecPhi phi_ = T::VecPhi::Zero();
  ceres::Problem problem_;
  ceres::Solver::Options options_;
};

// ---- finite differences of positions ------------------------------------------------------
template <class M>
class FiniteDifferences : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  explicit FiniteDifferences(double h) : h_(h) {}
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    q_ = q0;
    phi_ = phi0;
    K_.setZero();
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    typename T::VecPhi phi = phi_ + K_ * (q - q_);
    bool ok = Newton<M, double>(p_, q, &phi, 1e-9);
    out->phi = phi;
    // K(:, j) = (phi(q + h e_j) - phi(q - h e_j)) / 2h; L(:, j + nq k) by the 2nd difference
    // (j == k) or the 4-point mixed difference.
    auto at = [&](const typename T::VecQ& dq) {
      typename T::VecPhi x = phi + K_ * dq;
      ok = Newton<M, double>(p_, typename T::VecQ(q + dq), &x, 1e-9) && ok;
      return x;
    };
    for (int j = 0; j < M::kNq; ++j) {
      typename T::VecQ e = T::VecQ::Zero();
      e(j) = h_;
      const typename T::VecPhi plus = at(e), minus = at(-e);
      out->K.col(j) = (plus - minus) / (2 * h_);
      out->L.col(j + M::kNq * j) = (plus - 2 * phi + minus) / (h_ * h_);
      for (int k = 0; k < j; ++k) {
        typename T::VecQ f = T::VecQ::Zero();
        f(k) = h_;
        const typename T::VecPhi pp = at(e + f), pm = at(e - f), mp = at(-e + f), mm = at(-e - f);
        out->L.col(j + M::kNq * k) = (pp - pm - mp + mm) / (4 * h_ * h_);
        out->L.col(k + M::kNq * j) = out->L.col(j + M::kNq * k);
      }
    }
    q_ = q;
    phi_ = phi;
    K_ = out->K;
    return ok;
  }

 private:
  double h_;
  typename T::Params p_;
  typename T::VecQ q_;
  typename T::VecPhi phi_;
  typename T::MatK K_;
};

// ---- Paul's differential-equation method --------------------------------------------------
template <class M>
class Ode : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  explicit Ode(int correct_every) : correct_every_(correct_every) {}
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    q_ = q0;
    phi_ = phi0;
    steps_ = 0;
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    // RK4 for dphi/ds = K(q(s), phi(s)) dq, q(s) = q_ + s (q - q_), s in [0, 1].
    const typename T::VecQ dq = q - q_;
    typename T::Coefficients c;
    auto f = [&](const typename T::VecQ& qq, const typename T::VecPhi& ph) {
      M::template Coeffs<double>(p_, qq, ph, &c);
      return typename T::VecPhi(c.K * dq);
    };
    const typename T::VecPhi k1 = f(q_, phi_);
    const typename T::VecPhi k2 = f(q_ + 0.5 * dq, phi_ + 0.5 * k1);
    const typename T::VecPhi k3 = f(q_ + 0.5 * dq, phi_ + 0.5 * k2);
    const typename T::VecPhi k4 = f(q, phi_ + k3);
    phi_ += (k1 + 2 * k2 + 2 * k3 + k4) / 6;
    q_ = q;
    bool ok = phi_.allFinite();
    if (correct_every_ > 0 && ++steps_ % correct_every_ == 0) {
      ok = Newton<M, double>(p_, q, &phi_, 1e-9) && ok;
    }
    GeneratedKL<M>(p_, q, phi_, out);
    return ok;
  }

 private:
  int correct_every_;
  int steps_ = 0;
  typename T::Params p_;
  typename T::VecQ q_;
  typename T::VecPhi phi_;
};

// ---- single precision -------------------------------------------------------------------
template <class M>
class FloatNewton : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    q_ = q0.template cast<float>();
    phi_ = phi0.template cast<float>();
    typename M::template CoefficientsT<float> c;
    M::template Coeffs<float>(p_, q_, phi_, &c);
    K_ = c.K;
  }
  bool Step(const typename T::VecQ& qd, Config<M>* out) override {
    const VecQ<M, float> q = qd.template cast<float>();
    VecPhi<M, float> phi = phi_ + K_ * (q - q_);
    // 1e-4: the error after the last step is ~1e-8, below float's rounding (6e-8).
    const bool ok = Newton<M, float>(p_, q, &phi, 1e-4f, 8);
    typename M::template CoefficientsT<float> c;
    M::template Coeffs<float>(p_, q, phi, &c);
    out->phi = phi.template cast<double>();
    out->K = c.K.template cast<double>();
    out->L = c.L.template cast<double>();
    q_ = q;
    phi_ = phi;
    K_ = c.K;
    return ok;
  }

 private:
  typename M::template ParamsT<float> p_;
  VecQ<M, float> q_;
  VecPhi<M, float> phi_;
  MatK<M, float> K_;
};

// ---- hand-derived closed forms --------------------------------------------------------------
template <class M>
struct ClosedFormTraits {
  static constexpr bool kHas = false;
};

// Four-bar: circle–circle intersection and Paul's K, L (tests/runtime/handwritten_fourbar.h).
template <class M>
class FourbarClosedForm : public Method<M> {
 public:
  using T = mechgen::ModelTypes<M>;
  FourbarClosedForm() {
    const typename T::Params g;
    p_.a = g.a, p_.b = g.b, p_.c = g.c, p_.d = g.d, p_.xi = g.xi, p_.eta = g.eta;
  }
  void Start(const typename T::VecQ& q0, const typename T::VecPhi& phi0) override {
    // The branch whose angles match phi0.
    branch_ = +1;
    typename T::VecPhi phi;
    mech::handwritten_fourbar::ClosedFormPosition(p_, q0(0), +1, &phi);
    if (std::fabs(std::remainder(phi(0) - phi0(0), 2 * M_PI)) > 1e-6) branch_ = -1;
    phi_ = phi0;
  }
  bool Step(const typename T::VecQ& q, Config<M>* out) override {
    typename T::VecPhi phi;
    const bool ok = mech::handwritten_fourbar::ClosedFormPosition(p_, q(0), branch_, &phi);
    for (int i = 0; i < 2; ++i)  // continuous angles, as the references are
      phi(i) = phi_(i) + std::remainder(phi(i) - phi_(i), 2 * M_PI);
    mech::handwritten_fourbar::Coefficients<double> c;
    mech::handwritten_fourbar::EvalCoefficients(p_, mech::handwritten_fourbar::Vec<double, 1>(q),
                                                phi, &c);
    out->phi = phi;
    out->K = c.K;
    out->L = c.L;
    phi_ = phi;
    return ok;
  }

 private:
  mech::handwritten_fourbar::Params<double> p_;
  int branch_ = 1;
  typename T::VecPhi phi_;
};
template <>
struct ClosedFormTraits<mech::fourbar::Model> {
  static constexpr bool kHas = true;
  using Method = FourbarClosedForm<mech::fourbar::Model>;
};
template <>
struct ClosedFormTraits<mech::fourbar_toggle::Model> {
  static constexpr bool kHas = true;
  using Method = FourbarClosedForm<mech::fourbar_toggle::Model>;
};

// Offset slider-crank (models/slider_crank.yaml): a sin q + b sin th = e, s = a cos q + b cos th.
class SliderCrankClosedForm : public Method<mech::slider_crank::Model> {
 public:
  void Start(const T::VecQ&, const T::VecPhi&) override {}
  bool Step(const T::VecQ& qv, Config<mech::slider_crank::Model>* out) override {
    const double a = p_.a, b = p_.b, e = p_.e, q = qv(0);
    const double sq = std::sin(q), cq = std::cos(q);
    const double th = std::asin((e - a * sq) / b);
    const double st = std::sin(th), ct = std::cos(th);
    const double k = -a * cq / (b * ct);                    // dth/dq
    const double l = (a * sq + b * st * k * k) / (b * ct);  // d2th/dq2
    out->phi << th, a * cq + b * ct;
    out->K << k, -a * sq - b * st * k;
    out->L << l, -a * cq - b * ct * k * k - b * st * l;
    return std::isfinite(th);
  }

 private:
  T::Params p_;
};
template <>
struct ClosedFormTraits<mech::slider_crank::Model> {
  static constexpr bool kHas = true;
  using Method = SliderCrankClosedForm;
};

// ---------------------------------------------------------------------------------------
// The methods of a model.
template <class M, class MM>
std::vector<std::pair<std::string, MethodFactory<M>>> Methods() {
  std::vector<std::pair<std::string, MethodFactory<M>>> m;
  if constexpr (ClosedFormTraits<M>::kHas) {
    m.push_back({"closed_form", [] { return std::make_unique<typename ClosedFormTraits<M>::Method>(); }});
  }
  m.push_back({"dyads", [] { return std::make_unique<Dyads<M>>(); }});
  m.push_back({"monolithic", [] { return std::make_unique<Monolithic<M, MM>>(); }});
  m.push_back({"runtime", [] { return std::make_unique<Runtime<M>>(); }});
  m.push_back({"newton_symbolic", [] { return std::make_unique<LeanNewton<M, false>>(); }});
  m.push_back({"newton_numeric", [] { return std::make_unique<LeanNewton<M, true>>(); }});
  m.push_back({"ceres_analytic", [] { return std::make_unique<Ceres<M, CeresKind::kAnalytic>>(); }});
  m.push_back({"ceres_autodiff", [] { return std::make_unique<Ceres<M, CeresKind::kAutoDiff>>(); }});
  m.push_back({"ceres_numeric", [] { return std::make_unique<Ceres<M, CeresKind::kNumeric>>(); }});
  for (const char* h : {"1e-2", "1e-3", "1e-4", "1e-5", "1e-6"}) {
    const double hv = std::atof(h);
    m.push_back({std::string("fd_h") + h, [hv] { return std::make_unique<FiniteDifferences<M>>(hv); }});
  }
  m.push_back({"ode_rk4", [] { return std::make_unique<Ode<M>>(0); }});
  m.push_back({"ode_rk4_newton10", [] { return std::make_unique<Ode<M>>(10); }});
  m.push_back({"float_newton", [] { return std::make_unique<FloatNewton<M>>(); }});
  m.push_back({"float_dyads", [] { return std::make_unique<FloatDyads<M>>(); }});
  return m;
}

// The inputs of a reference walk and a converged start (the runtime's assembly, continued to
// the first row). Without a reference file: the model's range in 720 steps.
template <class M>
struct Walk {
  std::vector<typename mechgen::ModelTypes<M>::VecQ> q;
  typename mechgen::ModelTypes<M>::VecPhi phi0;
  bool ok = false;
};

template <class M>
Walk<M> MakeWalk(const Data* data) {
  using T = mechgen::ModelTypes<M>;
  Walk<M> w;
  if (data != nullptr) {
    for (const auto& row : data->rows) w.q.push_back(Eigen::Map<const typename T::VecQ>(row.q.data()));
  } else {
    const typename T::VecQ lo = Eigen::Map<const typename T::VecQ>(M::kQMin.data());
    const typename T::VecQ hi = Eigen::Map<const typename T::VecQ>(M::kQMax.data());
    for (int k = 0; k <= 720; ++k) w.q.push_back(lo + (hi - lo) * (k / 720.0));
  }
  mechgen::position::Options options;
  options.tolerance = 1e-13;
  mechgen::position::CeresPositionSolver<M> solver(options);
  mechgen::position::Summary s;
  w.ok = solver.AssembleDefault(&s) == mechgen::position::Status::kConverged &&
         solver.MoveTo(w.q.front(), &s) == mechgen::position::Status::kConverged;
  w.phi0 = solver.state().phi;
  return w;
}

// ---- the error study ----------------------------------------------------------------------
template <class M, class MM>
void WriteErrors(const std::string& model, const std::string& dir) {
  Data data;
  std::string error;
  if (!data.Load(std::string(MECHGEN_REFERENCE_DATA_DIR) + "/" + model + ".csv", &error)) {
    std::fprintf(stderr, "accuracy_bench: %s: no reference (%s); errors skipped\n", model.c_str(),
                 error.c_str());
    return;
  }
  const Walk<M> walk = MakeWalk<M>(&data);
  if (!walk.ok) {
    std::fprintf(stderr, "accuracy_bench: %s: assembly failed\n", model.c_str());
    return;
  }
  const auto methods = Methods<M, MM>();
  const size_t n = data.rows.size();
  std::vector<std::vector<double>> err(methods.size(), std::vector<double>(3 * n, NAN));
  std::vector<int> refused(methods.size(), 0);
  double refused_cond = INFINITY;  // the smallest reference cond at a refused row
  for (size_t m = 0; m < methods.size(); ++m) {
    auto method = methods[m].second();
    method->Start(walk.q.front(), walk.phi0);
    Config<M> c;
    for (size_t r = 0; r < n; ++r) {
      c.refused = false;
      method->Step(walk.q[r], &c);
      if (c.refused) {  // no result: a gap in the sweep, counted, not an error
        ++refused[m];
        refused_cond = std::min(refused_cond, data.rows[r].cond);
        continue;
      }
      err[m][3 * r] = data.PhiError(data.rows[r], c.phi);
      err[m][3 * r + 1] = data.KError(data.rows[r], c.K);
      err[m][3 * r + 2] = data.LError(data.rows[r], c.L);
    }
  }
  const std::string sweep_path = dir + "/" + model + "_sweep.csv";
  FILE* f = std::fopen(sweep_path.c_str(), "w");
  std::fprintf(f, "# %s: error of each method against the 50-digit reference at each configuration\n",
               model.c_str());
  std::fprintf(f, "# pos: max |dphi| (rad; lengths / l_max), K, L: max |d| / max(1, |ref|) (reference_data.h)\n");
  std::fprintf(f, "q0_deg,cond");
  for (const auto& m : methods)
    std::fprintf(f, ",%s:pos,%s:K,%s:L", m.first.c_str(), m.first.c_str(), m.first.c_str());
  std::fprintf(f, "\n");
  for (size_t r = 0; r < n; ++r) {
    std::fprintf(f, "%.17g,%.6g", data.rows[r].q[0] * 180 / M_PI, data.rows[r].cond);
    for (size_t m = 0; m < methods.size(); ++m)
      for (int k = 0; k < 3; ++k) std::fprintf(f, ",%.3e", err[m][3 * r + k]);
    std::fprintf(f, "\n");
  }
  std::fclose(f);
  const std::string sum_path = dir + "/" + model + "_errors.csv";
  f = std::fopen(sum_path.c_str(), "w");
  double max_cond = 0;
  for (const auto& row : data.rows) max_cond = std::max(max_cond, row.cond);
  std::fprintf(f, "# %s: max error over %zu configurations (max cond_1(Phi_phi) %.3g); refused: rows"
               " without a result (runtime: kSingular), smallest cond there %.3g\n",
               model.c_str(), n, max_cond, refused_cond);
  std::fprintf(f, "method,max_pos,max_K,max_L,refused\n");
  for (size_t m = 0; m < methods.size(); ++m) {
    double e[3] = {0, 0, 0};
    for (size_t r = 0; r < n; ++r)
      for (int k = 0; k < 3; ++k) {
        const double v = err[m][3 * r + k];
        if (std::isnan(v)) continue;  // a refused row
        e[k] = std::isfinite(v) ? std::max(e[k], v) : INFINITY;
      }
    std::fprintf(f, "%s,%.3e,%.3e,%.3e,%d\n", methods[m].first.c_str(), e[0], e[1], e[2], refused[m]);
  }
  std::fclose(f);
  std::fprintf(stderr, "accuracy_bench: wrote %s, %s\n", sweep_path.c_str(), sum_path.c_str());
}

// ---- timings --------------------------------------------------------------------------------
template <class M, class MM>
void RegisterTimings(const std::string& model) {
  Data data;
  std::string error;
  const bool have = data.Load(std::string(MECHGEN_REFERENCE_DATA_DIR) + "/" + model + ".csv", &error);
  auto walk = std::make_shared<Walk<M>>(MakeWalk<M>(have ? &data : nullptr));
  if (!walk->ok) return;
  for (const auto& [name, factory] : Methods<M, MM>()) {
    benchmark::RegisterBenchmark((model + "/" + name).c_str(), [walk, factory = factory](benchmark::State& state) {
      auto method = factory();
      method->Start(walk->q.front(), walk->phi0);
      Config<M> c;
      const long n = static_cast<long>(walk->q.size());
      long k = 1;
      for (auto _ : state) {
        // Back and forth over the rows: 0, 1, ..., n-1, n-2, ..., 1, 0, 1, ...
        const long period = 2 * (n - 1);
        const long i = k % period < n ? k % period : period - k % period;
        ++k;
        method->Step(walk->q[static_cast<size_t>(i)], &c);
        benchmark::DoNotOptimize(c);
      }
    });
  }
}

// The cost of asking for more: Newton + (whatever the variant emits), and the runtime.
template <class M>
void RegisterCost(const std::string& variant) {
  using T = mechgen::ModelTypes<M>;
  using F = mechgen::ModelFeatures<M>;
  benchmark::RegisterBenchmark(("cost/" + variant + "/lean").c_str(), [](benchmark::State& state) {
    const typename T::Params p;
    typename T::VecQ q = T::VecQ::Constant(0.0);
    mechgen::position::CeresPositionSolver<M> solver;  // the start at q = 0, on the model's branch
    mechgen::position::Summary s;
    solver.AssembleDefault(&s);
    solver.MoveTo(q, &s);
    typename T::VecPhi phi = solver.state().phi;
    typename T::VecPhi phi_prev = phi;
    const double dq = 0.5 * M_PI / 180;
    long k = 0;
    for (auto _ : state) {
      q(0) = k++ * dq;
      // Predictor: linear extrapolation of the last two solutions (needs no K).
      typename T::VecPhi guess = 2 * phi - phi_prev;
      phi_prev = phi;
      Newton<M, double>(p, q, &guess, 1e-9);
      phi = guess;
      if constexpr (F::kHasK || F::kHasL || F::kHasPoints) {
        typename T::Coefficients c;
        M::template Coeffs<double>(p, q, phi, &c);
        benchmark::DoNotOptimize(c);
      }
      benchmark::DoNotOptimize(phi);
    }
  });
  benchmark::RegisterBenchmark(("cost/" + variant + "/runtime").c_str(), [](benchmark::State& state) {
    mechgen::position::CeresPositionSolver<M> solver;
    mechgen::position::Summary s;
    solver.AssembleDefault(&s);
    solver.MoveTo(T::VecQ::Zero(), &s);
    long k = 1;
    for (auto _ : state) {
      solver.MoveTo(T::VecQ::Constant(k++ * 0.5 * M_PI / 180), &s);
      benchmark::DoNotOptimize(solver.state());
    }
  });
}

template <class M, class MM>
void AddModel(const std::string& name, const std::string& errors_dir) {
  if (!errors_dir.empty()) WriteErrors<M, MM>(name, errors_dir);
  RegisterTimings<M, MM>(name);
}

}  // namespace

int main(int argc, char** argv) {
  std::string errors_dir;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], "--errors_dir=", 13) == 0) {
      errors_dir = argv[i] + 13;
    } else {
      args.push_back(argv[i]);
    }
  }
  AddModel<mech::fourbar::Model, mech::fourbar_monolithic::Model>("fourbar", errors_dir);
  AddModel<mech::slider_crank::Model, mech::slider_crank_monolithic::Model>("slider_crank", errors_dir);
  AddModel<mech::fourbar_toggle::Model, mech::fourbar_toggle_monolithic::Model>("fourbar_toggle",
                                                                                 errors_dir);
  AddModel<mech::watt_sixbar::Model, mech::watt_sixbar_monolithic::Model>("watt_sixbar", errors_dir);
  // The chains are named chain<N> in the results, as their references (tests/reference/data).
#define X(n) \
  AddModel<mech::chain_##n::Model, mech::chain_##n##_monolithic::Model>("chain" #n, errors_dir);
  MECHGEN_ACCURACY_CHAINS
#undef X
  RegisterCost<mech::fourbar_pos::Model>("fourbar_pos");
  RegisterCost<mech::fourbar_k::Model>("fourbar_k");
  RegisterCost<mech::fourbar_kl::Model>("fourbar_kl");
  RegisterCost<mech::fourbar_klp::Model>("fourbar_klp");
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
