// The position solver instantiated once for the model view (issue 43: PositionSolver<ViewModel>,
// core/view_model.h) against the same source instantiated for each generated model's type:
// assembly and a sweep of the inputs over the model's default range (kQMin..kQMax) through
// both, every status, branch, mode and number compared to the bit. The oracle is the
// fixed-size instantiation, which tests/runtime/model_test.cc holds against closed forms and
// finite differences; the view's functions call the same generated code, and the runtime's
// arithmetic on the bounded dynamic types is the fixed-size code of each size, so nothing may
// differ, not even in the last bit. Part of model_test (no executable of its own).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "view_test_util.h"

#include "mechgen/core/view_runtime.h"
#include "mechgen/analysis/view_analysis.h"  // the sweep analysis for the view: mechgen_runtime_view
#include "sweep_run.h"  // runtime/tools: the sweep command's options as the analysis's request
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/motion_summary.h"
#include "mechgen/sweep/sweep.h"

#ifdef MECHGEN_HAVE_fourbar
#include "fourbar.h"
namespace mech::fourbar { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_slider_crank
#include "slider_crank.h"
namespace mech::slider_crank { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_watt_sixbar
#include "watt_sixbar.h"
namespace mech::watt_sixbar { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_stephenson_sixbar
#include "stephenson_sixbar.h"
namespace mech::stephenson_sixbar { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_fivebar
#include "fivebar.h"
namespace mech::fivebar { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_cam_roller
#include "cam_roller.h"
namespace mech::cam_roller { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_quick_return
#include "quick_return.h"
namespace mech::quick_return { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_stephenson_coupled
#include "stephenson_coupled.h"
namespace mech::stephenson_coupled { const mechgen::ModelView& View(); }
#endif
#ifdef MECHGEN_HAVE_engine_inline4
#include "engine_inline4.h"
namespace mech::engine_inline4 { const mechgen::ModelView& View(); }
#endif

namespace mechgen::position {
namespace {

using view_test::SameBits;

template <class M>
void ExpectSameState(const State<M>& a, const State<ViewModel>& b, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.branch, b.branch);
  EXPECT_EQ(a.sigma_exact, b.sigma_exact);
  EXPECT_TRUE(SameBits("q", a.q, b.q));
  EXPECT_TRUE(SameBits("phi", a.phi, b.phi));
  EXPECT_TRUE(SameBits("K", a.K, b.K));
  EXPECT_TRUE(SameBits("Phi_phi", a.Phi_phi, b.Phi_phi));
  EXPECT_TRUE(SameBits("L", a.L, b.L));
  EXPECT_TRUE(SameBits("r_P", a.r_P, b.r_P));
  EXPECT_TRUE(SameBits("K_P", a.K_P, b.K_P));
  EXPECT_TRUE(SameBits("L_P", a.L_P, b.L_P));
  EXPECT_TRUE(SameBits("singular_direction", a.singular_direction, b.singular_direction));
  EXPECT_TRUE(SameBits("largest_direction", a.largest_direction, b.largest_direction));
  EXPECT_TRUE(SameBits("residual_norm", a.residual_norm, b.residual_norm));
  EXPECT_TRUE(SameBits("condition", a.condition, b.condition));
  EXPECT_TRUE(SameBits("sigma_min", a.sigma_min, b.sigma_min));
  EXPECT_TRUE(SameBits("sigma_max", a.sigma_max, b.sigma_max));
  EXPECT_TRUE(SameBits("phi_error", a.phi_error, b.phi_error));
  EXPECT_TRUE(SameBits("K_error", a.K_error, b.K_error));
  EXPECT_TRUE(SameBits("L_error", a.L_error, b.L_error));
  EXPECT_TRUE(SameBits("inverse_norm", a.inverse_norm, b.inverse_norm));
}

void ExpectSameSummary(const Summary& a, const Summary& b, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.substeps, b.substeps);
  EXPECT_EQ(a.rejected_substeps, b.rejected_substeps);
  EXPECT_EQ(a.branch, b.branch);
  EXPECT_EQ(a.used_assembler, b.used_assembler);
  EXPECT_STREQ(a.reason, b.reason);
  EXPECT_TRUE(SameBits("residual_norm", a.residual_norm, b.residual_norm));
  EXPECT_TRUE(SameBits("condition", a.condition, b.condition));
  EXPECT_TRUE(SameBits("sigma_min", a.sigma_min, b.sigma_min));
}

// Assembly at the model's default, then 720 steps over kQMin..kQMax (every input at once) and
// back to the middle, through PositionSolver<M> and PositionSolver<ViewModel>.
template <class M>
void ExpectViewSolverSame(const ModelView& view) {
  ASSERT_TRUE(ViewCompatible(view));
  ASSERT_EQ(view.nq, M::kNq);
  ASSERT_EQ(view.nphi, M::kNphi);
  PositionSolver<M> fixed;
  PositionSolver<ViewModel> dynamic{ViewModel(view)};
  Summary a, b;
  EXPECT_EQ(fixed.AssembleDefault(&a), Status::kConverged);
  EXPECT_EQ(dynamic.AssembleDefault(&b), Status::kConverged);
  ExpectSameSummary(a, b, "assembly");
  ExpectSameState(fixed.state(), dynamic.state(), "assembly");
  typename PositionSolver<M>::Modes modes_a{};
  typename PositionSolver<ViewModel>::Modes modes_b{};
  ASSERT_EQ(fixed.modes(&modes_a), dynamic.modes(&modes_b));
  for (int i = 0; i < static_cast<int>(modes_a.size()); ++i) EXPECT_EQ(modes_a[i], modes_b[i]) << "block " << i;

  constexpr int kSteps = 720;
  int converged = 0;
  for (int i = 0; i <= kSteps + kSteps / 2; ++i) {
    const double t = i <= kSteps ? double(i) / kSteps : 1.0 - double(i - kSteps) / kSteps;
    typename ModelTypes<M>::VecQ q;
    ModelTypes<ViewModel>::VecQ qv(view.nq);
    for (int k = 0; k < M::kNq; ++k) {
      q(k) = M::kQMin[k] + t * (M::kQMax[k] - M::kQMin[k]);
      qv(k) = q(k);
    }
    const Status sa = fixed.MoveTo(q, &a);
    const Status sb = dynamic.MoveTo(qv, &b);
    EXPECT_EQ(sa, sb);
    converged += sa == Status::kConverged;
    const std::string where = "step " + std::to_string(i);
    ExpectSameSummary(a, b, where);
    ExpectSameState(fixed.state(), dynamic.state(), where);
    if (::testing::Test::HasFailure()) return;  // the first difference says it all
  }
  EXPECT_GT(converged, kSteps / 2);  // a sweep, not a row of refusals

  // Steps long enough to be split (Subdivide(): halves, Newton on the whole system, FindModes()
  // again): from the middle to each end of the range and back.
  for (int i = 0; i < 4; ++i) {
    const double t = (i % 2 == 0) ? (i == 0 ? 0.0 : 1.0) : 0.5;
    typename ModelTypes<M>::VecQ q;
    ModelTypes<ViewModel>::VecQ qv(view.nq);
    for (int k = 0; k < M::kNq; ++k) qv(k) = q(k) = M::kQMin[k] + t * (M::kQMax[k] - M::kQMin[k]);
    EXPECT_EQ(fixed.MoveTo(q, &a), dynamic.MoveTo(qv, &b));
    const std::string where = "jump " + std::to_string(i);
    ExpectSameSummary(a, b, where);
    ExpectSameState(fixed.state(), dynamic.state(), where);
  }
}

// The sweep (SweepRows, its columns, the CSV writer, the motion summary) of the model's default
// range in 360 steps at qd = 1, qdd = 0.5 through both instantiations: the same CSV bytes and
// the same motion summary.
template <class M>
void ExpectViewSweepSame(const ModelView& view) {
  using TM = ModelTypes<M>;
  using TV = ModelTypes<ViewModel>;
  const ViewModel model(view);
  PositionSolver<M> fixed;
  ViewPositionSolver dynamic(model);
  ASSERT_EQ(fixed.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(dynamic.AssembleDefault(nullptr), Status::kConverged);
  const typename TM::VecQ q0 = Eigen::Map<const typename TM::VecQ>(M::kQMin.data());
  const typename TM::VecQ q1 = Eigen::Map<const typename TM::VecQ>(M::kQMax.data());
  const typename TV::VecQ v0 = Eigen::Map<const TV::VecQ>(view.q_min, view.nq);
  const typename TV::VecQ v1 = Eigen::Map<const TV::VecQ>(view.q_max, view.nq);
  constexpr int kSteps = 360;
  const auto fixed_columns = SweepColumns<M>();
  const auto view_columns = SweepColumns<ViewModel>(model);
  ASSERT_EQ(table::ColumnNames(fixed_columns), table::ColumnNames(view_columns));
  std::ostringstream fixed_csv, view_csv;
  const CsvOptions about = Described(CsvAbout(std::string(M::kName) + "_sweep", M::kName, "kinematic sweep", kSweepSigns));
  WriteCsvHeader(fixed_columns, fixed_csv, about);
  WriteCsvHeader(view_columns, view_csv, about);
  MotionSummaryBuilder<M> fixed_summary(q0(0), q1(0));
  MotionSummaryBuilder<ViewModel> view_summary(v0(0), v1(0), model);
  const int fixed_failures = SweepRows(&fixed, q0, q1, kSteps, TM::VecQ::Constant(1.0), TM::VecQ::Constant(0.5),
                                       SweepOptions(), [&](int, const SweepRecord<M>& r) {
                                         WriteCsvRow(fixed_columns, r, fixed_csv);
                                         fixed_summary.Add(r);
                                       });
  ViewRowFn row = [&](int, const SweepRecord<ViewModel>& r) {
    WriteCsvRow(view_columns, r, view_csv);
    view_summary.Add(r);
  };
  const int view_failures = SweepRows(&dynamic, v0, v1, kSteps, TV::VecQ::Constant(view.nq, 1.0),
                                      TV::VecQ::Constant(view.nq, 0.5), SweepOptions(), row);
  EXPECT_EQ(fixed_failures, view_failures);
  const std::string a = fixed_csv.str(), b = view_csv.str();
  EXPECT_EQ(std::count(a.begin(), a.end(), '\n'), std::count(b.begin(), b.end(), '\n'));
  EXPECT_GT(std::count(a.begin(), a.end(), '\n'), kSteps);
  if (a != b) {  // the first line that differs
    std::istringstream sa(a), sb(b);
    std::string la, lb;
    while (std::getline(sa, la) && std::getline(sb, lb) && la == lb) {
    }
    ADD_FAILURE() << "the CSVs differ:\n" << la << "\n" << lb;
  }
  std::ostringstream fixed_text, view_text;
  PrintMotionSummary(fixed_summary.Finish(), fixed_text);
  PrintMotionSummary(view_summary.Finish(), view_text);
  EXPECT_EQ(fixed_text.str(), view_text.str());
  if (M::kNq == 1) {
    EXPECT_NE(fixed_text.str().find("motion summary"), std::string::npos);
  }
}

// The whole sweep command through the view (the sweep analysis analysis::Run<ViewModel>,
// mechgen/analysis/sweep.h, in mechgen_runtime_view) against the per-model tool
// build/models/<name>_sweep (analysis::Run<Model, CeresAssembler>): the same CSV file, byte for byte, for the default sweep and
// for a range with input speed and acceleration.
std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
// (Unused where the build has no per-model sweep tools: the sanitizer stage.)
[[maybe_unused]] void ExpectViewToolSame(const ModelView& view, const std::string& tool,
                                         const std::vector<std::string>& options) {
  const std::string dir = ::testing::TempDir();
  const std::string fixed_csv = dir + "view_tool_" + view.name + "_fixed.csv";
  const std::string view_csv = dir + "view_tool_" + view.name + "_view.csv";
  std::remove(fixed_csv.c_str());
  std::remove(view_csv.c_str());
  std::string command = "'" + tool + "' --table 0 --csv '" + fixed_csv + "'";
  sweep_tool::Arguments arguments;
  arguments.tool = std::string(view.name) + "_sweep_view";
  arguments.table = 0;
  arguments.csv_path = view_csv;
  for (size_t i = 0; i < options.size(); i += 2) {
    while (i < options.size() && options[i] == "--design") {  // (a flag: no value)
      command += " --design";
      arguments.design = true;
      ++i;
    }
    if (i + 1 >= options.size()) break;
    command += " " + options[i] + " " + options[i + 1];
    if (options[i] == "--steps") arguments.steps = std::stoll(options[i + 1]);
    if (options[i] == "--range") arguments.ranges.push_back(options[i + 1]);
    if (options[i] == "--qd") arguments.qd_text.push_back(options[i + 1]);
    if (options[i] == "--qdd") arguments.qdd_text.push_back(options[i + 1]);
  }
  command += " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::string a = ReadFile(fixed_csv);
  EXPECT_GT(a.size(), 1000u);
  // The view as mechgen runs it (a model of one input and two dependent coordinates on the
  // runtime sized so, core/view_sized.h), and on the instantiation for a view of any shape.
  for (const bool sized : {true, false}) {
    std::remove(view_csv.c_str());
    ViewModel model(view);
    model.sized = sized;
    ASSERT_EQ(analysis::Run(model, arguments, sweep_tool::Outputs(arguments)), sweep_tool::kExitConverged);
    EXPECT_TRUE(a == ReadFile(view_csv)) << fixed_csv << " and " << view_csv << " differ (sized " << sized << ")";
  }
}
// --design on a model without a design section is the per-model tool's usage error (exit 2),
// before anything is written.
TEST(ViewSweepTool, RefusesDesignWithoutADesignSection) {
#ifdef MECHGEN_HAVE_quick_return
  const std::string csv = ::testing::TempDir() + "view_tool_refused.csv";
  std::remove(csv.c_str());
  sweep_tool::Arguments arguments;
  arguments.csv_path = csv;
  arguments.design = true;
  EXPECT_EQ(analysis::Run(ViewModel(mech::quick_return::View()), arguments, sweep_tool::Outputs(arguments)),
            sweep_tool::kExitUsage);
  EXPECT_NE(analysis::Check(ViewModel(mech::quick_return::View()), arguments).find("has no design section"),
            std::string::npos);
  EXPECT_FALSE(std::ifstream(csv).good());
#endif
}
#if defined(MECHGEN_HAVE_fourbar) && defined(MECHGEN_FOURBAR_SWEEP)
TEST(ViewSweepTool, SameCsvAsTheToolFourbar) {
  ExpectViewToolSame(mech::fourbar::View(), MECHGEN_FOURBAR_SWEEP, {});
  ExpectViewToolSame(mech::fourbar::View(), MECHGEN_FOURBAR_SWEEP,
                     {"--steps", "100", "--range", "theta_crank:10deg:200deg", "--qd", "3", "--qdd", "-2"});
  ExpectViewToolSame(mech::fourbar::View(), MECHGEN_FOURBAR_SWEEP,
                     {"--design", "--steps", "100", "--range", "theta_crank:10deg:200deg", "--qd", "3"});
}
#endif
#if defined(MECHGEN_HAVE_slider_crank) && defined(MECHGEN_SLIDER_CRANK_SWEEP)
TEST(ViewSweepTool, SameCsvAsTheToolSliderCrank) {
  ExpectViewToolSame(mech::slider_crank::View(), MECHGEN_SLIDER_CRANK_SWEEP, {});
  ExpectViewToolSame(mech::slider_crank::View(), MECHGEN_SLIDER_CRANK_SWEEP, {"--steps", "77", "--qd", "2"});
  ExpectViewToolSame(mech::slider_crank::View(), MECHGEN_SLIDER_CRANK_SWEEP, {"--design", "--steps", "77"});
}
#endif

// The design derivatives through the view (ModelCalls<ViewModel>::Design, position::EvalDesign,
// the sweep's --design) against the fixed-size M::Design, which tests/design holds against Jets
// and differences: the view's Design calls the same generated code, so every member must agree
// to the bit, and so must the design checks (M::DesignChecks) and the --design CSV.
template <class M>
void ExpectDesignMembersSame(const position::DesignOf<M>& a, const position::DesignOf<ViewModel>& b,
                             const std::string& where) {
  SCOPED_TRACE(where);
  using F = ModelFeatures<M>;
  EXPECT_TRUE(SameBits("dphi_dp", a.dphi_dp, b.dphi_dp));
  if constexpr (F::kHasPoints) {
    EXPECT_TRUE(SameBits("dr_P_dp", a.dr_P_dp, b.dr_P_dp));
  } else {
    EXPECT_EQ(b.dr_P_dp.size(), 0);
  }
  if constexpr (F::kHasK) {
    EXPECT_TRUE(SameBits("dK_dp", a.dK_dp, b.dK_dp));
  } else {
    EXPECT_EQ(b.dK_dp.size(), 0);
  }
  if constexpr (F::kHasK && F::kHasPoints) {
    EXPECT_TRUE(SameBits("dK_P_dp", a.dK_P_dp, b.dK_P_dp));
  }
  if constexpr (F::kHasL) {
    EXPECT_TRUE(SameBits("dL_dp", a.dL_dp, b.dL_dp));
  } else {
    EXPECT_EQ(b.dL_dp.size(), 0);
  }
  if constexpr (F::kHasL && F::kHasPoints) {
    EXPECT_TRUE(SameBits("dL_P_dp", a.dL_P_dp, b.dL_P_dp));
  }
  if constexpr (F::kNumTransmissionAngles > 0) {
    EXPECT_TRUE(SameBits("dmu_dp", a.dmu_dp, b.dmu_dp));
  } else {
    EXPECT_EQ(b.dmu_dp.size(), 0);
  }
}
// (set, value): a parameter set in both before the sweep (nullptr: the defaults).
template <class M>
void ExpectViewDesignSame(const ModelView& view, const char* set = nullptr, double value = 0) {
  using C = ModelCalls<ViewModel>;
  using TM = ModelTypes<M>;
  using TV = ModelTypes<ViewModel>;
  const ViewModel model(view);
  ASSERT_TRUE(C::HasDesign(model));
  ASSERT_EQ(C::NumDesign(model), M::kNumDesign);
  for (int d = 0; d < M::kNumDesign; ++d) EXPECT_STREQ(C::DesignName(model, d), M::kDesignNames[d]);
  ASSERT_EQ(C::NumDesignChecks(model), M::kNumDesignChecks);
  for (int i = 0; i < M::kNumDesignChecks; ++i) EXPECT_STREQ(C::DesignCheckName(model, i), M::kDesignCheckNames[i]);
  typename TM::Params pa;
  ViewParams pb = C::DefaultParams(model);
  if (set != nullptr) {
    ASSERT_NE(pa.Find(set), nullptr);
    *pa.Find(set) = value;
    *C::FindParameter(model, &pb, set) = value;
    C::ParametersSet(model, &pb);
  }
  // The design checks, with and without their derivatives.
  if constexpr (M::kNumDesignChecks > 0) {
    typename ModelCalls<M>::DesignMargins ma;
    typename ModelCalls<M>::DesignMarginsDp da;
    C::DesignMargins mb, mb_alone;
    C::DesignMarginsDp db;
    ModelCalls<M>::DesignChecks(M(), pa, &ma, &da);
    C::DesignChecks(model, pb, &mb, &db);
    C::DesignChecks(model, pb, &mb_alone);
    EXPECT_TRUE(SameBits("margin", ma, mb));
    EXPECT_TRUE(SameBits("margin alone", ma, mb_alone));
    EXPECT_TRUE(SameBits("dmargin_dp", da, db));
    EXPECT_TRUE(da.allFinite());
  }

  // A sweep with --design through both: every row's derivatives and the CSV with the design
  // columns.
  PositionSolver<M> fixed(M(), Options(), pa);
  ViewPositionSolver dynamic(model, Options(), pb);
  ASSERT_EQ(fixed.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(dynamic.AssembleDefault(nullptr), Status::kConverged);
  const typename TM::VecQ q0 = Eigen::Map<const typename TM::VecQ>(M::kQMin.data());
  const typename TM::VecQ q1 = Eigen::Map<const typename TM::VecQ>(M::kQMax.data());
  const typename TV::VecQ v0 = Eigen::Map<const TV::VecQ>(view.q_min, view.nq);
  const typename TV::VecQ v1 = Eigen::Map<const TV::VecQ>(view.q_max, view.nq);
  auto fixed_columns = SweepColumns<M>();
  auto view_columns = SweepColumns<ViewModel>(model);
  AppendDesignColumns<M>(&fixed_columns);
  AppendDesignColumns<ViewModel>(model, &view_columns);
  ASSERT_EQ(table::ColumnNames(fixed_columns), table::ColumnNames(view_columns));
  ASSERT_GT(view_columns.size(), SweepColumns<ViewModel>(model).size() + M::kNumDesign * M::kNphi - 1);
  SweepOptions options;
  options.design = true;
  constexpr int kSteps = 90;
  std::vector<SweepRecord<M>> fixed_rows;
  std::vector<SweepRecord<ViewModel>> view_rows;
  std::ostringstream fixed_csv, view_csv;
  const int fixed_failures = SweepRows(&fixed, q0, q1, kSteps, TM::VecQ::Constant(1.0), TM::VecQ::Constant(0.5),
                                       options, [&](int, const SweepRecord<M>& r) {
                                         WriteCsvRow(fixed_columns, r, fixed_csv);
                                         fixed_rows.push_back(r);
                                       });
  ViewRowFn row = [&](int, const SweepRecord<ViewModel>& r) {
    WriteCsvRow(view_columns, r, view_csv);
    view_rows.push_back(r);  // (a copy: the design's maps on the copy's own buffer)
  };
  const int view_failures = SweepRows(&dynamic, v0, v1, kSteps, TV::VecQ::Constant(view.nq, 1.0),
                                      TV::VecQ::Constant(view.nq, 0.5), options, row);
  EXPECT_EQ(fixed_failures, view_failures);
  ASSERT_EQ(fixed_rows.size(), view_rows.size());
  int with_design = 0, without = 0;
  for (size_t i = 0; i < fixed_rows.size(); ++i) {
    ExpectDesignMembersSame<M>(fixed_rows[i].design, view_rows[i].design, "row " + std::to_string(i));
    // derivatives exactly where the row has a configuration (NaN after a stop)
    EXPECT_EQ(fixed_rows[i].design.dphi_dp.allFinite(), fixed_rows[i].state.valid) << i;
    EXPECT_EQ(view_rows[i].design.dphi_dp.array().isNaN().all(), !view_rows[i].state.valid) << i;
    (fixed_rows[i].state.valid ? with_design : without) += 1;
    if (::testing::Test::HasFailure()) return;  // the first difference says it all
  }
  EXPECT_GT(with_design, 10);
  if (set != nullptr) {
    EXPECT_GT(without, 0);  // (the stop: rows of NaN derivatives)
  }
  EXPECT_TRUE(fixed_csv.str() == view_csv.str()) << "the --design CSVs differ";

  // At a few of the sweep's configurations, Design called directly: the view's into a value
  // never placed on its layout (ModelCalls<ViewModel>::Design places it), the generated M::Design
  // into a NaN-filled one.
  for (const size_t i : {size_t{0}, fixed_rows.size() / 3, fixed_rows.size() / 2}) {
    if (!fixed_rows[i].state.valid) continue;
    position::DesignOf<M> a = position::NanDesign<M>();
    M::Design(pa, fixed_rows[i].state.q, fixed_rows[i].state.phi, &a);
    position::DesignOf<ViewModel> b;
    ASSERT_EQ(b.size, 0);
    C::Design(model, pb, view_rows[i].state.q, view_rows[i].state.phi, &b);
    EXPECT_EQ(b.view, &view);
    ExpectDesignMembersSame<M>(a, b, "Design at row " + std::to_string(i));
    EXPECT_TRUE(a.dphi_dp.allFinite());
    // and a state that is not valid: NaN (position::EvalDesign)
    position::State<ViewModel> invalid = view_rows[i].state;
    invalid.valid = false;
    position::EvalDesign<ViewModel>(model, pb, invalid, &b);
    EXPECT_TRUE(b.dphi_dp.array().isNaN().all());
    EXPECT_EQ(b.dphi_dp.size(), M::kNphi * M::kNumDesign);
  }
}
#ifdef MECHGEN_HAVE_fourbar
TEST(ViewDesign, SameAsFixedSize_fourbar) {
  ExpectViewDesignSame<mech::fourbar::Model>(mech::fourbar::View());
  // non-Grashof: the sweep stops at the crank's dead point, the later rows NaN
  ExpectViewDesignSame<mech::fourbar::Model>(mech::fourbar::View(), "a", 2.8);
}
#endif
#ifdef MECHGEN_HAVE_slider_crank
TEST(ViewDesign, SameAsFixedSize_slider_crank) {
  ExpectViewDesignSame<mech::slider_crank::Model>(mech::slider_crank::View());
}
#endif
#ifdef MECHGEN_HAVE_watt_sixbar
TEST(ViewDesign, SameAsFixedSize_watt_sixbar) {
  ExpectViewDesignSame<mech::watt_sixbar::Model>(mech::watt_sixbar::View());
}
#endif

#define MECHGEN_VIEW_SOLVER_TEST(name)                                  \
  TEST(ViewPositionSolver, SameAsFixedSize_##name) {                    \
    ExpectViewSolverSame<mech::name::Model>(mech::name::View());         \
  }                                                                     \
  TEST(ViewSweep, SameCsvAsFixedSize_##name) {                          \
    ExpectViewSweepSame<mech::name::Model>(mech::name::View());          \
  }
#ifdef MECHGEN_HAVE_fourbar
MECHGEN_VIEW_SOLVER_TEST(fourbar)
#endif
#ifdef MECHGEN_HAVE_slider_crank
MECHGEN_VIEW_SOLVER_TEST(slider_crank)
#endif
#ifdef MECHGEN_HAVE_watt_sixbar
MECHGEN_VIEW_SOLVER_TEST(watt_sixbar)
#endif
#ifdef MECHGEN_HAVE_stephenson_sixbar
MECHGEN_VIEW_SOLVER_TEST(stephenson_sixbar)
#endif
#ifdef MECHGEN_HAVE_fivebar
MECHGEN_VIEW_SOLVER_TEST(fivebar)
#endif
#ifdef MECHGEN_HAVE_cam_roller
MECHGEN_VIEW_SOLVER_TEST(cam_roller)
#endif
#ifdef MECHGEN_HAVE_quick_return
MECHGEN_VIEW_SOLVER_TEST(quick_return)
#endif
// A coupled block (4 x 4, Newton in the generated Solve and in the assembly): its assembly
// runs NewtonAssembler's damped steps, whose LU solve on the view's dynamic sizes once rounded
// otherwise than the fixed-size one (internal::SolvePartialPivLU), and Newton from a start a few
// ulp away does not return to the same bits.
#ifdef MECHGEN_HAVE_stephenson_coupled
MECHGEN_VIEW_SOLVER_TEST(stephenson_coupled)
#endif
// The per-model sweep tool assembles with Ceres (CeresAssembler), the view with NewtonAssembler
// (no Ceres in the runtime compiled once). On stephenson_coupled the two minimizers stop a few
// ulp apart (measured: 5 and 4 iterations, phi 2e-16 apart), and the Newton polish of the
// assembly does not bring the two starts to the same bits (the solver's Newton is not a fixed
// point to the bit at the rounding floor); every later step starts from its predecessor, so the
// whole sweep keeps that difference. The arithmetic cannot be the same (Ceres' DENSE_QR trust
// region against the runtime's own Levenberg-Marquardt), so the oracle is perturbation theory:
// phi, solved from Phi = 0 to rounding, lies within a few eps cond(Phi_phi) ||phi||_inf of the
// other solution; K = -Phi_phi^{-1} Phi_q evaluated at it, the same; L, solved once more from
// terms in K (K's error through Phi_phi^{-1} again), within a few eps cond^2 ||L||_inf. Statuses,
// branches and iteration counts are the same (the difference is below every test they meet).
// Measured over this sweep (the CSVs of both tools): phi 0.19 eps cond ||phi||, K 0.95 eps cond
// ||K||, L 0.39 eps cond^2 ||L||, r_P 0.18 eps cond ||r_P||, against the factor 4 below.
#ifdef MECHGEN_HAVE_stephenson_coupled
template <class A, class B>
::testing::AssertionResult Within(const char* what, const A& a, const B& b, double bound_over_norm) {
  double norm = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) norm = std::max(norm, std::abs(a(i)));
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double d = std::abs(a(i) - b(i));
    if (!(d <= bound_over_norm * norm)) {
      return ::testing::AssertionFailure() << what << "(" << i << "): " << a(i) << " vs " << b(i) << ", " << d
                                           << " > " << bound_over_norm << " x " << norm;
    }
  }
  return ::testing::AssertionSuccess();
}
TEST(ViewSweep, CloseToCeresAssembly_stephenson_coupled) {
  using M = mech::stephenson_coupled::Model;
  using TM = ModelTypes<M>;
  using TV = ModelTypes<ViewModel>;
  const ModelView& view = mech::stephenson_coupled::View();
  const ViewModel model(view);
  CeresPositionSolver<M> ceres;
  ViewPositionSolver dynamic(model);
  Summary a, b;
  ASSERT_EQ(ceres.AssembleDefault(&a), Status::kConverged);
  ASSERT_EQ(dynamic.AssembleDefault(&b), Status::kConverged);
  constexpr int kSteps = 360;
  std::vector<SweepRecord<M>> fixed_rows;
  std::vector<SweepRecord<ViewModel>> view_rows;
  const typename TM::VecQ q0 = Eigen::Map<const typename TM::VecQ>(M::kQMin.data());
  const typename TM::VecQ q1 = Eigen::Map<const typename TM::VecQ>(M::kQMax.data());
  const typename TV::VecQ v0 = Eigen::Map<const TV::VecQ>(view.q_min, view.nq);
  const typename TV::VecQ v1 = Eigen::Map<const TV::VecQ>(view.q_max, view.nq);
  SweepRows(&ceres, q0, q1, kSteps, TM::VecQ::Constant(1.0), TM::VecQ::Constant(0.5), SweepOptions(),
            [&](int, const SweepRecord<M>& r) { fixed_rows.push_back(r); });
  ViewRowFn row = [&](int, const SweepRecord<ViewModel>& r) { view_rows.push_back(r); };
  SweepRows(&dynamic, v0, v1, kSteps, TV::VecQ::Constant(view.nq, 1.0), TV::VecQ::Constant(view.nq, 0.5),
            SweepOptions(), row);
  ASSERT_EQ(fixed_rows.size(), view_rows.size());
  constexpr double eps = std::numeric_limits<double>::epsilon();
  int converged = 0;
  for (size_t i = 0; i < fixed_rows.size(); ++i) {
    SCOPED_TRACE("row " + std::to_string(i));
    const auto& x = fixed_rows[i];
    const auto& y = view_rows[i];
    ASSERT_EQ(x.summary.status, y.summary.status);
    EXPECT_EQ(x.summary.iterations, y.summary.iterations);
    EXPECT_EQ(x.state.branch, y.state.branch);
    if (x.summary.status != Status::kConverged) continue;
    ++converged;
    const double cond = x.state.condition;
    ASSERT_TRUE(std::isfinite(cond));
    EXPECT_TRUE(Within("phi", x.state.phi, y.state.phi, 4 * eps * cond));
    EXPECT_TRUE(Within("K", x.state.K, y.state.K, 4 * eps * cond));
    EXPECT_TRUE(Within("L", x.state.L, y.state.L, 4 * eps * cond * cond));
    EXPECT_TRUE(Within("r_P", x.state.r_P, y.state.r_P, 4 * eps * cond));
  }
  EXPECT_EQ(converged, kSteps + 1);
}
#endif
// 8 x 8 Phi_phi: Newton's steps by PartialPivLU (above the closed-form inverses' 4 x 4) in the
// assembly and the continuation.
#ifdef MECHGEN_HAVE_engine_inline4
MECHGEN_VIEW_SOLVER_TEST(engine_inline4)
#endif

}  // namespace
}  // namespace mechgen::position
