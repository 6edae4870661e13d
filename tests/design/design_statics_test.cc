// The generated statics and dynamics sensitivities (EvalStaticsDesign, EvalDynamicsDesign,
// issue 27). The statics: of the loaded four-bar
// (a spring, a force and a torque, weights, four pin reactions; every parameter a design
// parameter: lengths, spring constants, loads, masses) against two oracles independent of it:
//   - the generated EvalCoefficients and EvalStatics instantiated with ceres::Jet<double, N>
//     (p seeded, phi carrying dphi/dp from Jets of EvalPhi): forward-mode automatic
//     differentiation of the values code;
//   - Richardson-extrapolated central differences of EvalStatics at positions solved by
//     Newton's method at p +- h, p +- h/2.
// The dynamics: the massive four-bar (bars of mass rho per length, gravity; design parameters
// a, b, c, d, rho, g), EvalDynamics' I, dI/dq, h, Q, T and V at a crank speed, against the same
// two oracles; and its shaking force and moment (EvalShakingDesign) at a crank speed and
// acceleration, the same way.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "design_engine_single.h"
#include "design_fourbar_loaded.h"
#include "design_fourbar_massive.h"
#include "design_test_util.h"
#include "kinematics_test_util.h"

namespace {

using M = mech::design_fourbar_loaded::Model;
using mechtest::Config;
using ParamsD = M::ParamsT<double>;
constexpr int kNd = M::kNumDesign, kNphi = M::kNphi, kNq = M::kNq;

double Rel(double v) { return std::max(1.0, std::abs(v)); }

std::vector<Config<M>> Configs(const ParamsD& p) {
  const std::vector<Config<M>> all = mechtest::SweepConfigs<M>(p, 72);
  std::vector<Config<M>> out;
  for (size_t i = 0; i < all.size(); i += 6) out.push_back(all[i]);
  return out;
}

struct Generated {
  M::CoefficientsT<double> c;
  M::DesignDerivativesT<double> dc;
  M::StaticsT<double> s;
  M::StaticsDesignT<double> ds;
};

Generated Evaluate(const ParamsD& p, const Config<M>& x) {
  Generated g;
  M::Coeffs(p, x.q, x.phi, &g.c);
  M::Design(p, x.q, x.phi, &g.dc);
  M::Forces(p, x.q, x.phi, g.c, &g.s);
  M::StaticsDesign(p, x.q, x.phi, g.c, g.dc, &g.ds);
  return g;
}

TEST(DesignStatics, AgreesWithJetsOfTheGeneratedStatics) {
  static_assert(M::kHasStaticsDesign && M::kNumReactions > 0);
  using Jet = ceres::Jet<double, kNd>;
  const ParamsD p;
  double worst = 0;
  int compared = 0;
  for (const auto& x : Configs(p)) {
    const Generated g = Evaluate(p, x);
    const Eigen::Matrix<double, kNphi, kNd> dphi_dp = designtest::JetDphiDp<M>(p, x.q, x.phi);
    // The values code in Jets carrying d/dp.
    const auto pk = designtest::SeededParams<M, Jet>(p);
    const Eigen::Matrix<Jet, kNq, 1> qk = x.q.cast<Jet>();
    const Eigen::Matrix<Jet, kNphi, 1> phik = designtest::PhiJets<M, Jet>(x.phi, dphi_dp);
    M::CoefficientsT<Jet> cj;
    M::Coeffs(pk, qk, phik, &cj);
    M::StaticsT<Jet> sj;
    M::Forces(pk, qk, phik, cj, &sj);
    auto compare = [&](double ref, double got, const std::string& what) {
      const double e = std::abs(got - ref) / Rel(ref);
      worst = std::max(worst, e);
      ++compared;
      EXPECT_LE(e, 1e-12) << what << " at " << x.q(0) << ": " << got << " vs " << ref;
    };
    for (int d = 0; d < kNd; ++d) {
      const std::string by = std::string(" /d ") + M::kDesignNames[d];
      for (int j = 0; j < kNq; ++j) {
        compare(sj.Q(j).v(d), g.ds.dQ_dp(j, d), "dQ" + by);
        compare(sj.drive(j).v(d), g.ds.ddrive_dp(j, d), "ddrive" + by);
      }
      compare(sj.V.v(d), g.ds.dV_dp(d), "dV" + by);
      for (int i = 0; i < M::kNumReactions; ++i)
        compare(sj.R(i).v(d), g.ds.dR_dp(i, d), std::string("d") + M::kReactionNames[i] + by);
    }
  }
  EXPECT_GT(compared, 1000);
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

TEST(DesignStatics, AgreesWithRichardsonDifferences) {
  const ParamsD p0;
  double worst = 0;
  const auto configs = Configs(p0);
  for (size_t ci = 0; ci < configs.size(); ci += 3) {
    const Config<M>& x = configs[ci];
    const Generated g = Evaluate(p0, x);
    for (int d = 0; d < kNd; ++d) {
      ParamsD p = p0;
      const double v0 = *p.Find(M::kDesignNames[d]), h = 1e-4 * Rel(v0);
      auto at = [&](double delta) {
        ParamsD q = p0;
        *q.Find(M::kDesignNames[d]) = v0 + delta;
        Config<M> y = x;
        EXPECT_TRUE(mechtest::SolvePhi<M>(q, y.q, &y.phi).converged);
        M::CoefficientsT<double> c;
        M::Coeffs(q, y.q, y.phi, &c);
        M::StaticsT<double> s;
        M::Forces(q, y.q, y.phi, c, &s);
        return s;
      };
      const auto a = at(h), b = at(-h), a2 = at(h / 2), b2 = at(-h / 2);
      auto D = [&](double fa, double fb, double fa2, double fb2) { return (4 * (fa2 - fb2) / h - (fa - fb) / (2 * h)) / 3; };
      auto compare = [&](double ref, double got, const std::string& what) {
        const double e = std::abs(got - ref) / Rel(ref);
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-7) << what << " /d " << M::kDesignNames[d] << ": " << got << " vs " << ref;
      };
      compare(D(a.Q(0), b.Q(0), a2.Q(0), b2.Q(0)), g.ds.dQ_dp(0, d), "dQ");
      compare(D(a.V, b.V, a2.V, b2.V), g.ds.dV_dp(d), "dV");
      for (int i = 0; i < M::kNumReactions; ++i)
        compare(D(a.R(i), b.R(i), a2.R(i), b2.R(i)), g.ds.dR_dp(i, d), std::string("d") + M::kReactionNames[i]);
    }
  }
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

// ---- The dynamics ----

namespace dyn {

using MD = mech::design_fourbar_massive::Model;
using ParamsM = MD::ParamsT<double>;
constexpr int kN = MD::kNumDesign;
constexpr double kQd = 1.3, kT = 0.0;

// Everything EvalDynamics gives, as one vector: I, dI_dq, h, Q, T, V (one DOF).
template <class S>
Eigen::Matrix<S, 6, 1> Flat(const typename MD::template DynamicsT<S>& y) {
  Eigen::Matrix<S, 6, 1> v;
  v << y.I(0, 0), y.dI_dq(0, 0), y.h(0), y.Q(0), y.T, y.V;
  return v;
}

Eigen::Matrix<double, 6, kN> Generated(const ParamsM& p, const Config<MD>& x) {
  MD::CoefficientsT<double> c;
  MD::Coeffs(p, x.q, x.phi, &c);
  MD::DesignDerivativesT<double> dc;
  MD::Design(p, x.q, x.phi, &dc);
  MD::DynamicsDesignT<double> dd;
  MD::DynamicsDesign(p, x.q, x.phi, Eigen::Matrix<double, 1, 1>(kQd), kT, c, dc, &dd);
  Eigen::Matrix<double, 6, kN> g;
  for (int d = 0; d < kN; ++d)
    g.col(d) << dd.dI_dp(0, d), dd.ddI_dq_dp(0, d), dd.dh_dp(0, d), dd.dQ_dp(0, d), dd.dT_dp(d), dd.dV_dp(d);
  return g;
}

Eigen::Matrix<double, 6, 1> Values(const ParamsM& p, const Config<MD>& x) {
  MD::CoefficientsT<double> c;
  MD::Coeffs(p, x.q, x.phi, &c);
  MD::DynamicsT<double> y;
  MD::Dynamics(p, x.q, x.phi, Eigen::Matrix<double, 1, 1>(kQd), kT, c, &y);
  return Flat<double>(y);
}

const char* kWhat[6] = {"dI", "dI'", "dh", "dQ", "dT", "dV"};

TEST(DesignDynamics, AgreesWithJetsOfTheGeneratedDynamics) {
  static_assert(MD::kHasDynamicsDesign);
  using Jet = ceres::Jet<double, kN>;
  const ParamsM p;
  const auto all = mechtest::SweepConfigs<MD>(p, 72);
  double worst = 0;
  for (size_t ci = 0; ci < all.size(); ci += 6) {
    const Config<MD>& x = all[ci];
    MD::DesignDerivativesT<double> dc;
    MD::Design(p, x.q, x.phi, &dc);  // dphi/dp, checked against Jets of EvalPhi in design_derivatives_test
    const auto pk = designtest::SeededParams<MD, Jet>(p);
    const Eigen::Matrix<Jet, 1, 1> qk = x.q.cast<Jet>();
    const Eigen::Matrix<Jet, MD::kNphi, 1> phik = designtest::PhiJets<MD, Jet>(x.phi, dc.dphi_dp);
    MD::CoefficientsT<Jet> cj;
    MD::Coeffs(pk, qk, phik, &cj);
    MD::DynamicsT<Jet> yj;
    MD::Dynamics(pk, qk, phik, Eigen::Matrix<Jet, 1, 1>(Jet(kQd)), Jet(kT), cj, &yj);
    const Eigen::Matrix<Jet, 6, 1> ref = Flat<Jet>(yj);
    const Eigen::Matrix<double, 6, kN> g = Generated(p, x);
    for (int r = 0; r < 6; ++r)
      for (int d = 0; d < kN; ++d) {
        const double e = std::abs(g(r, d) - ref(r).v(d)) / Rel(ref(r).v(d));
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-12) << kWhat[r] << " /d " << MD::kDesignNames[d] << " at " << x.q(0);
      }
  }
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

TEST(DesignDynamics, AgreesWithRichardsonDifferences) {
  const ParamsM p0;
  const auto all = mechtest::SweepConfigs<MD>(p0, 72);
  double worst = 0;
  for (size_t ci = 0; ci < all.size(); ci += 18) {
    const Config<MD>& x = all[ci];
    const Eigen::Matrix<double, 6, kN> g = Generated(p0, x);
    for (int d = 0; d < kN; ++d) {
      ParamsM p = p0;
      const double v0 = *p.Find(MD::kDesignNames[d]), h = 1e-4 * Rel(v0);
      auto at = [&](double delta) {
        ParamsM q = p0;
        *q.Find(MD::kDesignNames[d]) = v0 + delta;
        Config<MD> y = x;
        EXPECT_TRUE(mechtest::SolvePhi<MD>(q, y.q, &y.phi).converged);
        return Values(q, y);
      };
      const Eigen::Matrix<double, 6, 1> D =
          (4 * (at(h / 2) - at(-h / 2)) / h - (at(h) - at(-h)) / (2 * h)) / 3;
      for (int r = 0; r < 6; ++r) {
        const double e = std::abs(g(r, d) - D(r)) / Rel(D(r));
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-7) << kWhat[r] << " /d " << MD::kDesignNames[d] << ": " << g(r, d) << " vs " << D(r);
      }
    }
  }
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}


// ---- The shaking force and moment (EvalShakingDesign) ----
// F and M of EvalShaking at a crank speed and acceleration, their d/dp against Jets of the
// generated EvalCoefficients and EvalShaking and against Richardson differences.
namespace shake {

constexpr double kQdd = -0.7;

Eigen::Matrix<double, 3, kN> Generated(const ParamsM& p, const Config<MD>& x) {
  static_assert(MD::kHasShaking && MD::kHasDynamicsDesign);
  MD::CoefficientsT<double> c;
  MD::Coeffs(p, x.q, x.phi, &c);
  MD::DesignDerivativesT<double> dc;
  MD::Design(p, x.q, x.phi, &dc);
  Eigen::Matrix<double, 2, kN> dF_dp = Eigen::Matrix<double, 2, kN>::Constant(std::nan(""));
  Eigen::Matrix<double, kN, 1> dM_dp = Eigen::Matrix<double, kN, 1>::Constant(std::nan(""));
  const Eigen::Matrix<double, 1, 1> qd(kQd), qdd(kQdd);
  MD::ShakingDesign(p, x.q, x.phi, qd, qdd, c, dc, &dF_dp, &dM_dp);
  // Each output alone (the other nullptr) gives the same.
  Eigen::Matrix<double, 2, kN> dF_alone;
  Eigen::Matrix<double, kN, 1> dM_alone;
  MD::ShakingDesign(p, x.q, x.phi, qd, qdd, c, dc, &dF_alone);
  MD::ShakingDesign<double>(p, x.q, x.phi, qd, qdd, c, dc, nullptr, &dM_alone);
  EXPECT_EQ(dF_alone, dF_dp);
  EXPECT_EQ(dM_alone, dM_dp);
  Eigen::Matrix<double, 3, kN> g;
  g << dF_dp, dM_dp.transpose();
  return g;
}

template <class S>
Eigen::Matrix<S, 3, 1> Values(const typename MD::template ParamsT<S>& p, const Eigen::Matrix<S, 1, 1>& q,
                              const Eigen::Matrix<S, MD::kNphi, 1>& phi) {
  typename MD::template CoefficientsT<S> c;
  MD::Coeffs(p, q, phi, &c);
  typename MD::template ShakingT<S> y;
  MD::Shaking(p, q, phi, Eigen::Matrix<S, 1, 1>(S(kQd)), Eigen::Matrix<S, 1, 1>(S(kQdd)), c, &y);
  Eigen::Matrix<S, 3, 1> v;
  v << y.F(0), y.F(1), y.M;
  return v;
}

const char* kShakeWhat[3] = {"dF_x", "dF_y", "dM"};

TEST(DesignShaking, AgreesWithJetsOfTheGeneratedShaking) {
  using Jet = ceres::Jet<double, kN>;
  const ParamsM p;
  const auto all = mechtest::SweepConfigs<MD>(p, 72);
  double worst = 0;
  int compared = 0;
  for (size_t ci = 0; ci < all.size(); ci += 4) {
    const Config<MD>& x = all[ci];
    MD::DesignDerivativesT<double> dc;
    MD::Design(p, x.q, x.phi, &dc);
    const auto pk = designtest::SeededParams<MD, Jet>(p);
    const Eigen::Matrix<Jet, 1, 1> qk = x.q.cast<Jet>();
    const Eigen::Matrix<Jet, MD::kNphi, 1> phik =
        designtest::PhiJets<MD, Jet>(x.phi, designtest::JetDphiDp<MD>(p, x.q, x.phi));
    const Eigen::Matrix<Jet, 3, 1> ref = Values<Jet>(pk, qk, phik);
    const Eigen::Matrix<double, 3, kN> g = Generated(p, x);
    for (int r = 0; r < 3; ++r)
      for (int d = 0; d < kN; ++d) {
        const double e = std::abs(g(r, d) - ref(r).v(d)) / Rel(ref(r).v(d));
        worst = std::max(worst, e);
        ++compared;
        EXPECT_LE(e, 1e-12) << kShakeWhat[r] << " /d " << MD::kDesignNames[d] << " at " << x.q(0) << ": " << g(r, d)
                            << " vs " << ref(r).v(d);
      }
  }
  EXPECT_EQ(compared, 18 * 3 * kN);
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

TEST(DesignShaking, AgreesWithRichardsonDifferences) {
  const ParamsM p0;
  const auto all = mechtest::SweepConfigs<MD>(p0, 72);
  double worst = 0, largest = 0;
  for (size_t ci = 0; ci < all.size(); ci += 9) {
    const Config<MD>& x = all[ci];
    const Eigen::Matrix<double, 3, kN> g = Generated(p0, x);
    for (int d = 0; d < kN; ++d) {
      const double v0 = *ParamsM().Find(MD::kDesignNames[d]), h = 1e-4 * Rel(v0);
      auto at = [&](double delta) {
        ParamsM q = p0;
        *q.Find(MD::kDesignNames[d]) = v0 + delta;
        Config<MD> y = x;
        EXPECT_TRUE(mechtest::SolvePhi<MD>(q, y.q, &y.phi).converged);
        return Values<double>(q, y.q, y.phi);
      };
      const Eigen::Matrix<double, 3, 1> D = (4 * (at(h / 2) - at(-h / 2)) / h - (at(h) - at(-h)) / (2 * h)) / 3;
      for (int r = 0; r < 3; ++r) {
        const double e = std::abs(g(r, d) - D(r)) / Rel(D(r));
        worst = std::max(worst, e);
        largest = std::max(largest, std::abs(D(r)));
        EXPECT_LE(e, 1e-7) << kShakeWhat[r] << " /d " << MD::kDesignNames[d] << ": " << g(r, d) << " vs " << D(r);
      }
    }
  }
  EXPECT_GT(largest, 1.0);  // the derivatives are not all trivially zero
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

}  // namespace shake

// ---- An engine (engine_single with `design: {parameters: all}`: 18 parameters, the gas law's
// among them): statics, dynamics and shaking derivatives against Jets of the generated values ----
namespace engine {

using ME = mech::design_engine_single::Model;
using ParamsE = ME::ParamsT<double>;
constexpr int kNe = ME::kNumDesign;

TEST(DesignEngine, StaticsDynamicsAndShakingAgreeWithJets) {
  static_assert(ME::kHasStaticsDesign && ME::kHasDynamicsDesign && ME::kHasShaking);
  using Jet = ceres::Jet<double, kNe>;
  const ParamsE p;
  const auto all = mechtest::SweepConfigs<ME>(p, 144);
  double worst = 0;
  int compared = 0;
  const Eigen::Matrix<double, 1, 1> qd(31.4), qdd(-5.0);
  const double t = 0.01;
  for (size_t ci = 0; ci < all.size(); ci += 6) {
    const Config<ME>& x = all[ci];
    ME::CoefficientsT<double> c;
    ME::Coeffs(p, x.q, x.phi, &c);
    ME::DesignDerivativesT<double> dc;
    ME::Design(p, x.q, x.phi, &dc);
    ME::StaticsDesignT<double> ds;
    ME::StaticsDesign(p, x.q, x.phi, c, dc, &ds);
    ME::DynamicsDesignT<double> dd;
    ME::DynamicsDesign(p, x.q, x.phi, qd, t, c, dc, &dd);
    Eigen::Matrix<double, 2, kNe> dF_dp;
    Eigen::Matrix<double, kNe, 1> dM_dp;
    ME::ShakingDesign(p, x.q, x.phi, qd, qdd, c, dc, &dF_dp, &dM_dp);

    const auto pk = designtest::SeededParams<ME, Jet>(p);
    const Eigen::Matrix<Jet, 1, 1> qk = x.q.cast<Jet>();
    const Eigen::Matrix<Jet, ME::kNphi, 1> phik =
        designtest::PhiJets<ME, Jet>(x.phi, designtest::JetDphiDp<ME>(p, x.q, x.phi));
    ME::CoefficientsT<Jet> cj;
    ME::Coeffs(pk, qk, phik, &cj);
    ME::StaticsT<Jet> sj;
    ME::Forces(pk, qk, phik, cj, &sj);
    ME::DynamicsT<Jet> yj;
    ME::Dynamics(pk, qk, phik, Eigen::Matrix<Jet, 1, 1>(Jet(qd(0))), Jet(t), cj, &yj);
    ME::ShakingT<Jet> hj;
    ME::Shaking(pk, qk, phik, Eigen::Matrix<Jet, 1, 1>(Jet(qd(0))), Eigen::Matrix<Jet, 1, 1>(Jet(qdd(0))), cj, &hj);
    auto compare = [&](const Jet& ref, double got, int d, const std::string& what) {
      const double e = std::abs(got - ref.v(d)) / Rel(ref.v(d));
      worst = std::max(worst, e);
      ++compared;
      EXPECT_LE(e, 1e-12) << what << " /d " << ME::kDesignNames[d] << " at " << x.q(0) << ": " << got << " vs "
                          << ref.v(d);
    };
    for (int d = 0; d < kNe; ++d) {
      compare(sj.Q(0), ds.dQ_dp(0, d), d, "statics dQ");
      compare(sj.V, ds.dV_dp(d), d, "statics dV");
      for (int i = 0; i < ME::kNumReactions; ++i)
        compare(sj.R(i), ds.dR_dp(i, d), d, std::string("d") + ME::kReactionNames[i]);
      compare(yj.I(0, 0), dd.dI_dp(0, d), d, "dI");
      compare(yj.dI_dq(0, 0), dd.ddI_dq_dp(0, d), d, "dI'");
      compare(yj.h(0), dd.dh_dp(0, d), d, "dh");
      compare(yj.Q(0), dd.dQ_dp(0, d), d, "dynamics dQ");
      compare(yj.T, dd.dT_dp(d), d, "dT");
      compare(yj.V, dd.dV_dp(d), d, "dynamics dV");
      compare(hj.F(0), dF_dp(0, d), d, "dF_x");
      compare(hj.F(1), dF_dp(1, d), d, "dF_y");
      compare(hj.M, dM_dp(d), d, "dM");
    }
  }
  EXPECT_GT(compared, 5000);
  RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

}  // namespace engine

}  // namespace dyn

}  // namespace
