// The dynamics instantiated once for the model view (issue 43: MinimalDynamics<ViewModel>,
// Kinetostatics<ViewModel>, runtime/view/dynamics.cc) against the same source instantiated for
// each generated model's type: the right-hand side of the equation of motion at several states
// and a short integrated trajectory (every sample, the summary's counts), with the reactions of
// the kinetostatics along it, compared to the bit. The oracle is the fixed-size instantiation,
// which tests/dynamics holds against energy conservation, closed forms and a second method;
// the view's functions call the same generated code and the runtime's arithmetic on the
// bounded dynamic types is the fixed-size code of each size (products coefficient by
// coefficient, the inertia's LDLT and Phi_phi's conditioning on fixed-size copies), so nothing
// may differ, not even in the last bit. Models: a four-bar with massive links (the one-pass
// M::Rhs stages), the slider-crank with a motor (M::Solve stages, switching loads, reactions;
// its friction joint viscous only: Coulomb friction through the view is compared byte for byte
// on tests/dynamics' incline by simulate_friction_test.sh) and the five-bar robot (two inputs: the
// inertia a 2 x 2 LDLT). The simulation analysis' checks (analysis/simulate.h: Check, and Run's
// refusals, which read the same Prepare) through the view against the fixed-size model's and
// the messages the simulate command prints. Part of model_test (no executable of its own).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "view_test_util.h"

#include "mechgen/analysis/view_analysis.h"  // the simulation analysis for the view: mechgen_runtime_view
#include "mechgen/core/view_runtime.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"
#include "mechgen/position/design.h"

#ifdef MECHGEN_HAVE_fourbar_massive
#include "fourbar_massive.h"
namespace mech::fourbar_massive { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_slider_crank_motor
#include "slider_crank_motor.h"
namespace mech::slider_crank_motor { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_fivebar_robot
#include "fivebar_robot.h"
namespace mech::fivebar_robot { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_engine_single
#include "engine_single.h"
namespace mech::engine_single { const mechgen::ModelView& View(); }
#endif

namespace mechgen::dynamics {
namespace {

using view_test::SameBits;

template <class SampleA, class SampleB>
void ExpectSameSample(const SampleA& a, const SampleB& b, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_TRUE(SameBits("t", a.t, b.t));
  EXPECT_TRUE(SameBits("q", a.q, b.q));
  EXPECT_TRUE(SameBits("qd", a.qd, b.qd));
  EXPECT_TRUE(SameBits("qdd", a.qdd, b.qdd));
  EXPECT_TRUE(SameBits("Q", a.Q, b.Q));
  EXPECT_TRUE(SameBits("phi", a.phi, b.phi));
  EXPECT_TRUE(SameBits("K", a.K, b.K));
  EXPECT_TRUE(SameBits("T", a.T, b.T));
  EXPECT_TRUE(SameBits("V", a.V, b.V));
  EXPECT_TRUE(SameBits("E", a.E, b.E));
  EXPECT_TRUE(SameBits("W", a.W, b.W));
  EXPECT_TRUE(SameBits("P_nc", a.P_nc, b.P_nc));
  EXPECT_TRUE(SameBits("rcond", a.rcond, b.rcond));
  EXPECT_TRUE(SameBits("det", a.det, b.det));
}

// The right-hand side at states around the assembly (speeds of both signs, a time), then a
// run of t_end seconds sampled every sample_dt, through MinimalDynamics<M> and
// MinimalDynamics<ViewModel>, with both integrators.
template <class M, template <int> class Method>
void ExpectViewDynamicsSame(const ModelView& view, double t_end, double sample_dt) {
  ASSERT_TRUE(ViewCompatible(view));
  ASSERT_EQ(view.nq, M::kNq);
  ASSERT_EQ(view.nphi, M::kNphi);
  using Fixed = MinimalDynamics<M, Method>;
  using Dynamic = MinimalDynamics<ViewModel, Method>;
  const ViewModel model(view);
  MinimalOptions options;
  options.sample_dt = sample_dt;
  Fixed fixed(typename Fixed::Params(), options);
  Dynamic dynamic(model, ModelCalls<ViewModel>::DefaultParams(model), options);
  constexpr int kNq = M::kNq;
  typename Fixed::VecQ q0;
  for (int i = 0; i < kNq; ++i) q0(i) = M::kAssemblyQ[i];
  const typename Dynamic::VecQ q0_view = q0;
  ASSERT_TRUE(fixed.Initialize(q0));
  ASSERT_TRUE(dynamic.Initialize(q0_view));
  EXPECT_EQ(fixed.StagesByRhs(), dynamic.StagesByRhs());
  EXPECT_EQ(fixed.StagesByTrig(), dynamic.StagesByTrig());

  // The right-hand side: (qd, qdd, P_nc) at (t, (q, qd, W)).
  for (int k = 0; k < 6; ++k) {
    typename Fixed::State y;
    for (int i = 0; i < kNq; ++i) {
      y(i) = q0(i) + 0.01 * (k - 2) * (i + 1);
      y(kNq + i) = (k % 2 == 0 ? 1.5 : -0.7) * (k + 1) * (i % 2 == 0 ? 1 : -1);
    }
    y(2 * kNq) = 0.25 * k;
    const double t = 0.05 * k;
    const typename Dynamic::State y_view = y;
    typename Fixed::State dy;
    typename Dynamic::State dy_view;
    const bool ok = fixed.Derivative(t, y, &dy);
    ASSERT_EQ(ok, DerivativeOf(&dynamic, t, y_view, &dy_view)) << "state " << k;
    if (ok) {
      EXPECT_TRUE(SameBits(("dy at state " + std::to_string(k)).c_str(), dy, dy_view));
    }
    typename Fixed::SampleT s;
    typename Dynamic::SampleT s_view;
    ASSERT_EQ(fixed.Evaluate(t, y, &s), EvaluateAt(&dynamic, t, y_view, &s_view)) << "state " << k;
    ExpectSameSample(s, s_view, "Evaluate at state " + std::to_string(k));
  }

  // A short trajectory from the assembly, with the kinetostatics along it.
  typename Fixed::VecQ qd0;
  for (int i = 0; i < kNq; ++i) qd0(i) = i % 2 == 0 ? 2.0 : -1.0;
  const typename Dynamic::VecQ qd0_view = qd0;
  Kinetostatics<M> kineto(typename Fixed::Params{});
  Kinetostatics<ViewModel> kineto_view(model, ModelCalls<ViewModel>::DefaultParams(model));
  ASSERT_TRUE(kineto.Initialize(q0));
  ASSERT_TRUE(kineto_view.Initialize(q0_view));
  std::vector<typename Fixed::SampleT> samples;
  std::vector<typename Dynamic::SampleT> samples_view;
  std::vector<KinetostaticsRow<M>> rows;
  std::vector<KinetostaticsRow<ViewModel>> rows_view;
  auto observer = [&](const typename Fixed::SampleT& s) {
    samples.push_back(s);
    rows.emplace_back();
    kineto.Evaluate(s.t, s.q, s.qd, s.qdd, &rows.back());
    return true;
  };
  ViewSampleFn<Dynamic> observer_view = [&](const typename Dynamic::SampleT& s) {
    samples_view.push_back(s);
    rows_view.emplace_back();
    kineto_view.Evaluate(s.t, s.q, s.qd, s.qdd, &rows_view.back());
    return true;
  };
  MinimalSummary a, b;
  typename Fixed::SampleT last;
  typename Dynamic::SampleT last_view;
  fixed.Simulate(0.0, q0, qd0, t_end, observer, &a, &last);
  SimulateFree(&dynamic, 0.0, q0_view, qd0_view, t_end, observer_view, &b, &last_view);
  EXPECT_EQ(a.status, Status::kSuccess) << FormatSummary(a);
  EXPECT_EQ(FormatSummary(a), FormatSummary(b));  // every count and figure, as printed
  EXPECT_EQ(a.integrator.steps, b.integrator.steps);
  EXPECT_EQ(a.integrator.rhs_evaluations, b.integrator.rhs_evaluations);
  EXPECT_EQ(a.switch_restarts, b.switch_restarts);
  EXPECT_TRUE(SameBits("max_energy_error", a.max_energy_error, b.max_energy_error));
  ASSERT_EQ(samples.size(), samples_view.size());
  EXPECT_GE(samples.size(), 5u);
  for (size_t k = 0; k < samples.size(); ++k) {
    ExpectSameSample(samples[k], samples_view[k], "sample " + std::to_string(k));
    EXPECT_EQ(rows[k].status, rows_view[k].status) << "sample " << k;
    EXPECT_TRUE(SameBits("condition", rows[k].condition, rows_view[k].condition)) << "sample " << k;
    EXPECT_TRUE(SameBits("drive", rows[k].statics.drive, rows_view[k].statics.drive)) << "sample " << k;
    if constexpr (Kinetostatics<M>::kMayHaveReactions) {
      EXPECT_TRUE(SameBits("R", rows[k].statics.R, rows_view[k].statics.R)) << "sample " << k;
    }
  }
  ExpectSameSample(last, last_view, "last");
}

#ifdef MECHGEN_HAVE_fourbar_massive
TEST(ViewDynamics, SameAsFixedFourbarMassive) {
  ExpectViewDynamicsSame<mech::fourbar_massive::Model, Dopri5>(mech::fourbar_massive::View(), 0.5, 0.01);
  ExpectViewDynamicsSame<mech::fourbar_massive::Model, Dop853>(mech::fourbar_massive::View(), 0.5, 0);
}
#endif
#ifdef MECHGEN_HAVE_slider_crank_motor
TEST(ViewDynamics, SameAsFixedSliderCrankMotor) {
  ExpectViewDynamicsSame<mech::slider_crank_motor::Model, Dopri5>(mech::slider_crank_motor::View(), 0.5, 0.01);
  ExpectViewDynamicsSame<mech::slider_crank_motor::Model, Dop853>(mech::slider_crank_motor::View(), 0.2, 0);
}
#endif
#ifdef MECHGEN_HAVE_fivebar_robot
TEST(ViewDynamics, SameAsFixedFivebarRobot) {
  // (It falls under its weight into a dead point at t = 0.09 s.)
  ExpectViewDynamicsSame<mech::fivebar_robot::Model, Dopri5>(mech::fivebar_robot::View(), 0.06, 0.002);
  ExpectViewDynamicsSame<mech::fivebar_robot::Model, Dop853>(mech::fivebar_robot::View(), 0.06, 0);
}
#endif

// The design sensitivities of the dynamics (the machines' --design: ModelCalls' DynamicsDesign
// and ShakingDesign) through the view against the fixed-size model's at states around a turn
// of the first input (the positions by the generated solve from the assembly, the same phi for
// both), every member to the bit. dc is each side's own EvalDesignDerivatives (ModelCalls'
// Design: the view's on its buffer), so the view's chain is compared whole, as the machines
// call it.
template <class M>
void ExpectViewDynamicsDesignSame(const ModelView& view) {
  ASSERT_TRUE(ViewCompatible(view));
  using CF = ModelCalls<M>;
  using CV = ModelCalls<ViewModel>;
  const M fixed{};
  const ViewModel model(view);
  ASSERT_TRUE(CV::HasDynamicsDesign(model));
  ASSERT_EQ(CV::HasShakingDesign(model), CF::HasShakingDesign(fixed));
  ASSERT_TRUE(CV::HasDesign(model));
  ASSERT_EQ(view.num_design, M::kNumDesign);
  const typename ModelTypes<M>::Params p{};
  const ViewParams p_view = CV::DefaultParams(model);
  typename ModelTypes<M>::VecPhi phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  double largest = 0;
  for (int k = 0; k < 5; ++k) {
    SCOPED_TRACE("state " + std::to_string(k));
    typename ModelTypes<M>::VecQ q, qd, qdd;
    for (int i = 0; i < M::kNq; ++i) {
      q(i) = M::kAssemblyQ[i] + 1.3 * k * (i + 1);
      qd(i) = (k % 2 == 0 ? 150.0 : -40.0) * (k + 1);
      qdd(i) = 900.0 * (k - 2);
    }
    const double t = 0.01 * k;
    const auto solved = CF::Solve(fixed, p, q, &phi, CF::DefaultModes(fixed), 50, 1e-12);
    ASSERT_EQ(solved.status, decltype(solved.status)::kConverged);
    typename ModelTypes<M>::Coefficients c;
    CF::Coeffs(fixed, p, q, phi, &c);
    typename M::template DesignDerivativesT<double> dc;
    M::Design(p, q, phi, &dc);
    typename CF::template DynamicsDesignOut<> dd;
    CF::DynamicsDesign(fixed, p, q, phi, qd, t, c, dc, &dd);

    const typename ModelTypes<ViewModel>::VecQ q_view = q, qd_view = qd, qdd_view = qdd;
    const typename ModelTypes<ViewModel>::VecPhi phi_view = phi;
    typename ModelTypes<ViewModel>::Coefficients c_view;
    CV::Coeffs(model, p_view, q_view, phi_view, &c_view);
    position::DesignOf<ViewModel> dc_view;
    CV::Design(model, p_view, q_view, phi_view, &dc_view);
    CV::DynamicsDesignResult dd_view;
    CV::DynamicsDesign(model, p_view, q_view, phi_view, qd_view, t, c_view, dc_view, &dd_view);
    EXPECT_TRUE(SameBits("dI_dp", dd.dI_dp, dd_view.dI_dp));
    EXPECT_TRUE(SameBits("ddI_dq_dp", dd.ddI_dq_dp, dd_view.ddI_dq_dp));
    EXPECT_TRUE(SameBits("dh_dp", dd.dh_dp, dd_view.dh_dp));
    EXPECT_TRUE(SameBits("dQ_dp", dd.dQ_dp, dd_view.dQ_dp));
    EXPECT_TRUE(SameBits("dT_dp", dd.dT_dp, dd_view.dT_dp));
    EXPECT_TRUE(SameBits("dV_dp", dd.dV_dp, dd_view.dV_dp));
    largest = std::max({largest, dd.dI_dp.cwiseAbs().maxCoeff(), dd.dh_dp.cwiseAbs().maxCoeff()});
    if constexpr (HasShaking<M>::value) {
      typename CF::template ShakingDesignForce<> dF;
      typename CF::template ShakingDesignMoment<> dM;
      CF::ShakingDesign(fixed, p, q, phi, qd, qdd, c, dc, &dF, &dM);
      typename CV::template ShakingDesignForce<> dF_view;
      typename CV::template ShakingDesignMoment<> dM_view;
      CV::ShakingDesign(model, p_view, q_view, phi_view, qd_view, qdd_view, c_view, dc_view, &dF_view, &dM_view);
      EXPECT_TRUE(SameBits("dF_dp", dF, dF_view));
      EXPECT_TRUE(SameBits("dM_dp", dM, dM_view));
      largest = std::max(largest, dF.cwiseAbs().maxCoeff());
    }
  }
  EXPECT_GT(largest, 1e-3);  // (not a comparison of zeros)
}

#ifdef MECHGEN_HAVE_engine_single
TEST(ViewDynamicsDesign, SameAsFixedEngineSingle) {
  ExpectViewDynamicsDesignSame<mech::engine_single::Model>(mech::engine_single::View());
}
#endif

// The simulation analysis' Check (analysis/simulate.h) says, for each request that Run refuses,
// the line the simulate command prints (tools/simulate_main.cc's messages, written out here),
// the same through the view as on the fixed-size model (the model's inputs, names and friction
// read through ModelCalls on each side), and nothing for requests Run goes on with; Run through
// the view prints "<tool>: error: " and that text, exits 2 and writes no CSV.
#ifdef MECHGEN_HAVE_fivebar_robot
TEST(ViewSimulateCheck, SaysWhatRunRefuses) {
  const mech::fivebar_robot::Model fixed{};
  const ViewModel model(mech::fivebar_robot::View());
  const std::string table = ::testing::TempDir() + "view_simulate_check_law.csv";
  const std::string missing = ::testing::TempDir() + "view_simulate_check_missing.csv";
  std::remove(missing.c_str());
  {
    std::ofstream out(table);
    out << "t,q\n0,2.3\n0.5,2.4\n";
  }
  auto drive = [](const std::string& text, const std::string& name, const std::string& kind,
                  std::vector<double> values, const std::string& file = "") {
    return analysis::SimulateDrive{text, name, kind, std::move(values), file};
  };
  struct Case {
    const char* what;
    analysis::SimulateRequest request;
    std::string error;  // empty: Run goes on
    bool prefix = false;  // error is the message's beginning
  };
  std::vector<Case> cases;
  cases.push_back({"defaults", {}, ""});
  {
    analysis::SimulateRequest r;
    r.q0 = {1};
    r.q0_text = "1";
    cases.push_back({"q0", r, "--q0: bad value '1': expected 2 value(s), one per input"});
  }
  {
    analysis::SimulateRequest r;
    r.qd0 = {1, 2, 3};
    r.qd0_text = "1,2,3";
    cases.push_back({"qd0", r, "--qd0: bad value '1,2,3': expected 2 value(s), one per input"});
  }
  {
    analysis::SimulateRequest r;
    r.params.sets.push_back("nosuch=1");
    cases.push_back({"set", r, "--set 'nosuch=1': no parameter 'nosuch' in the model (parameters: ", true});
  }
  {
    analysis::SimulateRequest r;
    r.friction = "on";
    cases.push_back({"friction", r, "--friction on: the model has no friction joints (`friction:`)"});
  }
  {
    analysis::SimulateRequest r;
    r.drives.push_back(drive("theta_nope=speed:1", "theta_nope", "speed", {1}));
    cases.push_back({"unknown input", r,
                     "--drive: bad value 'theta_nope=speed:1': the model has no input 'theta_nope' (its inputs: "
                     "theta_prox1, theta_prox2)"});
  }
  {
    analysis::SimulateRequest r;
    r.drives.push_back(drive("theta_prox2=speed:1", "theta_prox2", "speed", {1}));
    r.drives.push_back(drive("theta_prox2=speed:2", "theta_prox2", "speed", {2}));
    cases.push_back({"driven twice", r, "--drive: bad value 'theta_prox2=speed:2': input 'theta_prox2' is driven twice"});
  }
  {
    analysis::SimulateRequest r;
    for (int i = 0; i < 3; ++i) r.drives.push_back(drive("theta_prox1=speed:1", "theta_prox1", "speed", {1}));
    cases.push_back({"too many drives", r, "3 --drive options for a model with 2 input(s)"});
  }
  {
    analysis::SimulateRequest r;
    r.drives.push_back(drive("x", "theta_prox1", "table", {}, missing));
    cases.push_back({"missing table", r, "--drive: 'x': cannot read " + missing});
  }
  {
    analysis::SimulateRequest r;
    r.drives.push_back(drive("x", "theta_prox1", "table", {}, table));
    r.drives.push_back(drive("y", "theta_prox2", "move", {0.5, 0, 0.3}));
    cases.push_back({"driven", r, ""});
    r.friction = "on";  // (every input driven, but the robot has no friction joints)
    cases.push_back({"driven, friction on", r, "--friction on: the model has no friction joints (`friction:`)"});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string view_error = analysis::Check(model, c.request);
    EXPECT_EQ(view_error, analysis::Check(fixed, c.request));
    EXPECT_EQ(c.prefix ? view_error.substr(0, c.error.size()) : view_error, c.error);
    if (c.error.empty()) continue;
    analysis::SimulateOutputs outputs;
    outputs.tool = "t";
    outputs.csv = ::testing::TempDir() + "view_simulate_check.csv";
    std::remove(outputs.csv.c_str());
    ::testing::internal::CaptureStderr();
    const int status = analysis::Run(model, c.request, outputs);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "t: error: " + view_error + "\n");
    EXPECT_EQ(status, 2);
    EXPECT_FALSE(std::ifstream(outputs.csv).good());
  }
  std::remove(table.c_str());
}
#endif

// design (the trajectory sensitivities) through the view as on the fixed-size model (issue 46: the
// view's generated EvalDynamicsJacobian): Check reads the model's `design` section and the
// options design excludes, the same text either way; nothing is handed to not_through_view.
// (The runs themselves, byte for byte: tests/design/simulate_design_view_test.sh.)
#ifdef MECHGEN_HAVE_engine_single
TEST(ViewSimulateCheck, DesignThroughTheViewAsOnTheFixedSizeModel) {
  const mech::engine_single::Model fixed{};
  const ViewModel model(mech::engine_single::View());
  analysis::SimulateRequest request;
  request.design = true;
#if MECHGEN_SIMULATE_HAS_SENSITIVITY
  ASSERT_TRUE(HasDynamicsDesign<mech::engine_single::Model>::value);
  EXPECT_TRUE(ModelCalls<ViewModel>::HasDynamicsJacobian(model));
  EXPECT_TRUE(ModelCalls<ViewModel>::HasDynamicsDesignProduct(model));
  EXPECT_EQ(analysis::Check(fixed, request), "");
  EXPECT_EQ(analysis::Check(model, request), "");
  request.stop_at_speed_zero = true;
  EXPECT_EQ(analysis::Check(fixed, request),
            "--design: not with --stop-at-speed-zero (the sensitivities of the free motion only)");
  EXPECT_EQ(analysis::Check(model, request), analysis::Check(fixed, request));
  request.drives.push_back({"theta_crank=speed:1", "theta_crank", "speed", {1}, ""});
  EXPECT_EQ(analysis::Check(fixed, request), "--design: not with --drive (the sensitivities of the free motion only)");
  EXPECT_EQ(analysis::Check(model, request), analysis::Check(fixed, request));
  analysis::SimulateOutputs outputs;
  outputs.csv = ::testing::TempDir() + "view_simulate_design.csv";
  std::remove(outputs.csv.c_str());
  bool asked = false;
  outputs.not_through_view = [&asked](const std::string&, const std::string&) {
    asked = true;
    return 120;
  };
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(analysis::Run(model, request, outputs), 2);  // (the usage error: --drive)
  ::testing::internal::GetCapturedStderr();
  EXPECT_FALSE(asked);
  EXPECT_FALSE(std::ifstream(outputs.csv).good());
#else
  EXPECT_EQ(analysis::Check(model, request), analysis::Check(fixed, request));
#endif
}
#endif

}  // namespace
}  // namespace mechgen::dynamics
