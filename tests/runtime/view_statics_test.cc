// The statics instantiated once for the model view (issue 43: statics/ for ViewModel, in
// mechgen_runtime_view) against the same source instantiated for each generated model's type:
// the statics sweep of the model's default range (every row's frictionless, forward and
// backward solutions, drive analyses, evaluations, status and CSV line), the dead-zone scan and
// the equilibrium scan, compared to the bit. The oracle is the fixed-size instantiation, which
// tests/statics and tests/runtime/statics_*_test hold against free bodies, virtual work and
// hand solutions; the view's Forces and Stiffness call the same generated code and the
// runtime's arithmetic on the bounded types is the fixed-size code of each size, so nothing may
// differ. The models: the shipped ones with forces that model_test links (a slider-crank with
// Coulomb friction and self-locking, a four-bar with springs and gravity, a press, a motor-
// driven slider-crank whose loads read a velocity, a two-input five-bar robot). Part of
// model_test (no executable of its own).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "view_test_util.h"

#include "mechgen/core/view_runtime.h"  // statics/ for ViewModel: mechgen_runtime_view
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/sweep.h"
#include "mechgen/analysis/view_analysis.h"  // the statics analysis for the view: mechgen_runtime_view
#include "statics_run.h"  // runtime/tools: the statics command around it

#ifdef MECHGEN_HAVE_slider_crank_friction
#include "slider_crank_friction.h"
MECHGEN_DECLARE_MODEL_VIEW(slider_crank_friction)
#endif
#ifdef MECHGEN_HAVE_fourbar_loaded
#include "fourbar_loaded.h"
MECHGEN_DECLARE_MODEL_VIEW(fourbar_loaded)
#endif
#ifdef MECHGEN_HAVE_slider_crank_press
#include "slider_crank_press.h"
MECHGEN_DECLARE_MODEL_VIEW(slider_crank_press)
#endif
#ifdef MECHGEN_HAVE_slider_crank_motor
#include "slider_crank_motor.h"
MECHGEN_DECLARE_MODEL_VIEW(slider_crank_motor)
#endif
#ifdef MECHGEN_HAVE_fivebar_robot
#include "fivebar_robot.h"
MECHGEN_DECLARE_MODEL_VIEW(fivebar_robot)
#endif
#ifdef MECHGEN_HAVE_fourbar
#include "fourbar.h"
MECHGEN_DECLARE_MODEL_VIEW(fourbar)
#endif

namespace mechgen::statics {
namespace {

using view_test::SameBits;

// Every member of a fixed-size solution against the view's (those the model has; the view's
// others are empty).
template <class M>
void ExpectSameSolution(const Solution<M>& a, const Solution<ViewModel>& b, const std::string& where) {
  SCOPED_TRACE(where);
  using F = StaticsFeatures<M>;
  EXPECT_EQ(a.summary.status, b.summary.status);
  EXPECT_EQ(a.summary.iterations, b.summary.iterations);
  EXPECT_STREQ(a.summary.reason, b.summary.reason);
  EXPECT_TRUE(SameBits("last_change", a.summary.last_change, b.summary.last_change));
  EXPECT_TRUE(SameBits("condition", a.summary.condition, b.summary.condition));
  EXPECT_TRUE(SameBits("reaction_norm", a.summary.reaction_norm, b.summary.reaction_norm));
  EXPECT_TRUE(SameBits("direction", a.direction, b.direction));
  EXPECT_TRUE(SameBits("friction", a.friction, b.friction));
  EXPECT_TRUE(SameBits("Q", a.statics.Q, b.statics.Q));
  EXPECT_TRUE(SameBits("drive", a.statics.drive, b.statics.drive));
  if constexpr (F::kHasPotential) {
    EXPECT_TRUE(SameBits("V", a.statics.V, double(b.statics.V)));
    EXPECT_TRUE(SameBits("dV_dq", a.statics.dV_dq, b.statics.dV_dq));
  } else {
    EXPECT_EQ(b.statics.dV_dq.size(), 0);
  }
  if constexpr (F::kHasD2V) {
    EXPECT_TRUE(SameBits("d2V_dq2", a.statics.d2V_dq2, b.statics.d2V_dq2));
  }
  if constexpr (F::kHasStiffness) {
    EXPECT_TRUE(SameBits("stiffness", a.statics.stiffness, b.statics.stiffness));
  } else {
    EXPECT_EQ(b.statics.stiffness.size(), 0);
  }
  if constexpr (F::kHasReactions) {
    EXPECT_TRUE(SameBits("R", a.statics.R, b.statics.R));
  } else {
    EXPECT_EQ(b.statics.R.size(), 0);
  }
  if constexpr (F::kHasFriction) {
    EXPECT_TRUE(SameBits("normal", a.statics.normal, b.statics.normal));
    EXPECT_TRUE(SameBits("gain", a.statics.gain, b.statics.gain));
    EXPECT_TRUE(SameBits("K_rel", a.statics.K_rel, b.statics.K_rel));
  } else {
    EXPECT_EQ(b.statics.normal.size(), 0);
  }
}

void ExpectSameDrive(const DriveAnalysis& a, const DriveAnalysis& b, const std::string& where) {
  SCOPED_TRACE(where);
  EXPECT_EQ(a.input, b.input);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.self_locking, b.self_locking);
  EXPECT_TRUE(SameBits("drive", a.drive, b.drive));
  EXPECT_TRUE(SameBits("drive_forward", a.drive_forward, b.drive_forward));
  EXPECT_TRUE(SameBits("drive_backward", a.drive_backward, b.drive_backward));
  EXPECT_TRUE(SameBits("drive_plus", a.drive_plus, b.drive_plus));
  EXPECT_TRUE(SameBits("drive_minus", a.drive_minus, b.drive_minus));
  EXPECT_TRUE(SameBits("efficiency_forward", a.efficiency_forward, b.efficiency_forward));
  EXPECT_TRUE(SameBits("efficiency_backward", a.efficiency_backward, b.efficiency_backward));
}

// The statics sweep of the default range (360 steps; at the input velocities qd when given)
// through both instantiations: every row's solutions and drive analyses to the bit, the same
// CSV (StaticsColumns through the model and through its view), and the table's column names.
// With `design` (a model with EvalStaticsDesign): Options::design, the design derivatives
// (position and statics: the view's Design and StaticsDesign) of every row to the bit, and
// the design columns in the CSV.
template <class M>
void ExpectViewStaticsSweepSame(const ModelView& view, double speed = std::nan(""), bool design = false) {
  using TM = ModelTypes<M>;
  using TV = ModelTypes<ViewModel>;
  ASSERT_TRUE(ViewCompatible(view));
  const ViewModel model(view);
  ASSERT_TRUE(ModelCalls<ViewModel>::HasStatics(model));
  EXPECT_EQ(ModelCalls<ViewModel>::NumReactions(model), StaticsFeatures<M>::kNumReactions);
  EXPECT_EQ(ModelCalls<ViewModel>::NumFriction(model), StaticsFeatures<M>::kNumFriction);
  position::PositionSolver<M> fixed;
  ViewPositionSolver dynamic(model);
  ASSERT_EQ(fixed.AssembleDefault(nullptr), position::Status::kConverged);
  ASSERT_EQ(dynamic.AssembleDefault(nullptr), position::Status::kConverged);
  const typename TM::VecQ q0 = Eigen::Map<const typename TM::VecQ>(M::kQMin.data());
  const typename TM::VecQ q1 = Eigen::Map<const typename TM::VecQ>(M::kQMax.data());
  const TV::VecQ v0 = Eigen::Map<const TV::VecQ>(view.q_min, view.nq);
  const TV::VecQ v1 = Eigen::Map<const TV::VecQ>(view.q_max, view.nq);
  typename TM::VecQ qd_fixed = TM::VecQ::Constant(speed);
  TV::VecQ qd_view = TV::VecQ::Constant(view.nq, speed);
  const bool at_speed = !std::isnan(speed);
  EXPECT_EQ(SpeedNote<M>(at_speed ? &qd_fixed : nullptr), SpeedNote<ViewModel>(model, at_speed ? &qd_view : nullptr));
  const auto fixed_columns = StaticsColumns<M>(design);
  const auto view_columns = StaticsColumns<ViewModel>(model, design);
  ASSERT_EQ(table::ColumnNames(fixed_columns), table::ColumnNames(view_columns));
  if (design) {
    EXPECT_TRUE(ModelCalls<ViewModel>::HasStaticsDesign(model));
    EXPECT_GT(view_columns.size(), StaticsColumns<ViewModel>(model).size() + ModelCalls<M>::NumDesign(M()) - 1);
  }
  Options options;
  options.design = design;
  std::vector<std::string> fixed_units, view_units;
  for (const auto& c : fixed_columns) fixed_units.push_back(c.unit + "|" + c.table_name + "|" + c.description);
  for (const auto& c : view_columns) view_units.push_back(c.unit + "|" + c.table_name + "|" + c.description);
  EXPECT_EQ(fixed_units, view_units);
  EXPECT_EQ(ReactionJoints<M>().size(), ReactionJoints<ViewModel>(model).size());
  EXPECT_EQ(GroundBearings<M>().size(), GroundBearings<ViewModel>(model).size());

  constexpr int kSteps = 360;
  std::vector<StaticsRecord<M>> fixed_rows;
  const int fixed_failures = StaticsSweep(options, &fixed, q0, q1, kSteps, &fixed_rows, SweepOptions(),
                                          at_speed ? &qd_fixed : nullptr);
  std::ostringstream fixed_csv, view_csv;
  WriteCsv(fixed_columns, fixed_rows, fixed_csv);
  WriteCsvHeader(view_columns, view_csv);
  int rows = 0, converged = 0, with_friction = 0, with_design = 0;
  ViewStaticsRowFn row = [&](int i, const StaticsRecord<ViewModel>& b) {
    ASSERT_LT(static_cast<size_t>(i), fixed_rows.size());
    const StaticsRecord<M>& a = fixed_rows[static_cast<size_t>(i)];
    const std::string where = "row " + std::to_string(i);
    ++rows;
    converged += a.status == Status::kConverged;
    EXPECT_EQ(a.status, b.status) << where;
    EXPECT_EQ(a.evaluations, b.evaluations) << where;
    EXPECT_TRUE(SameBits("mechanical_advantage", a.mechanical_advantage, b.mechanical_advantage)) << where;
    ExpectSameSolution(a.frictionless, b.frictionless, where + " frictionless");
    for (int j = 0; j < M::kNq; ++j) {
      const std::string input = where + " input " + std::to_string(j);
      ExpectSameDrive(a.drives[j], b.drives[j], input);
      ExpectSameSolution(a.forward[j], b.forward[j], input + " forward");
      ExpectSameSolution(a.backward[j], b.backward[j], input + " backward");
      with_friction += a.forward[j].summary.iterations > 1;
    }
    if constexpr (StaticsFeatures<M>::kHasDesign) {
      if (design) {
        using F = StaticsFeatures<M>;
        EXPECT_TRUE(SameBits("dQ_dp", a.design.dQ_dp, b.design.dQ_dp)) << where;
        EXPECT_TRUE(SameBits("ddrive_dp", a.design.ddrive_dp, b.design.ddrive_dp)) << where;
        if constexpr (F::kHasPotential) {
          EXPECT_TRUE(SameBits("dV_dp", a.design.dV_dp, b.design.dV_dp)) << where;
        }
        if constexpr (F::kHasReactions) {
          EXPECT_TRUE(SameBits("dR_dp", a.design.dR_dp, b.design.dR_dp)) << where;
        }
        EXPECT_TRUE(SameBits("dphi_dp", a.kinematics.design.dphi_dp, b.kinematics.design.dphi_dp)) << where;
        EXPECT_TRUE(SameBits("dK_dp", a.kinematics.design.dK_dp, b.kinematics.design.dK_dp)) << where;
        // derivatives exactly where the frictionless statics converged (NaN elsewhere)
        EXPECT_EQ(a.design.ddrive_dp.allFinite(), a.frictionless.summary.status == Status::kConverged) << where;
        with_design += b.design.ddrive_dp.allFinite();
      }
    }
    WriteCsvRow(view_columns, b, view_csv);
  };
  const int view_failures = StaticsSweepRows(options, &dynamic, v0, v1, kSteps, SweepOptions(),
                                             at_speed ? &qd_view : nullptr, row);
  if (design) {
    EXPECT_GT(with_design, kSteps / 2);
  }
  EXPECT_EQ(fixed_failures, view_failures);
  EXPECT_EQ(rows, kSteps + 1);
  EXPECT_GT(converged, kSteps / 2);  // forces, not a row of refusals
  if constexpr (StaticsFeatures<M>::kHasFriction) {
    EXPECT_GT(with_friction, kSteps / 2);  // the friction iterated
  }
  const std::string a = fixed_csv.str(), b = view_csv.str();
  EXPECT_GT(std::count(a.begin(), a.end(), '\n'), kSteps);
  if (a != b) {  // the first line that differs
    std::istringstream sa(a), sb(b);
    std::string la, lb;
    while (std::getline(sa, la) && std::getline(sb, lb) && la == lb) {
    }
    ADD_FAILURE() << "the CSVs differ:\n" << la << "\n" << lb;
  }
}

// The dead-zone scan of the first input over its default range and the equilibrium scan along
// the default line, through both instantiations: the same zones and equilibria, to the bit.
template <class M>
void ExpectViewScansSame(const ModelView& view) {
  using TM = ModelTypes<M>;
  using TV = ModelTypes<ViewModel>;
  const ViewModel model(view);
  position::PositionSolver<M> fixed;
  ViewPositionSolver dynamic(model);
  ASSERT_EQ(fixed.AssembleDefault(nullptr), position::Status::kConverged);
  ASSERT_EQ(dynamic.AssembleDefault(nullptr), position::Status::kConverged);
  ScanOptions scan;
  scan.samples = 180;
  std::vector<DeadZone> zones_a, zones_b;
  ScanSummary sa, sb;
  EXPECT_EQ(FindDeadZones(Options(), scan, &fixed, 0, M::kQMin[0], M::kQMax[0], &zones_a, &sa),
            FindDeadZones(Options(), scan, &dynamic, 0, view.q_min[0], view.q_max[0], &zones_b, &sb));
  EXPECT_EQ(sa.evaluations, sb.evaluations);
  EXPECT_EQ(sa.unusable_samples, sb.unusable_samples);
  ASSERT_EQ(zones_a.size(), zones_b.size());
  if constexpr (StaticsFeatures<M>::kHasFriction) {
    EXPECT_FALSE(zones_a.empty());  // a scan that found something
  }
  for (size_t i = 0; i < zones_a.size(); ++i) {
    EXPECT_TRUE(SameBits("zone begin", zones_a[i].begin, zones_b[i].begin)) << i;
    EXPECT_TRUE(SameBits("zone end", zones_a[i].end, zones_b[i].end)) << i;
    EXPECT_EQ(zones_a[i].begin_located, zones_b[i].begin_located) << i;
    EXPECT_EQ(zones_a[i].end_located, zones_b[i].end_located) << i;
  }
  ASSERT_EQ(fixed.AssembleDefault(nullptr), position::Status::kConverged);
  ASSERT_EQ(dynamic.AssembleDefault(nullptr), position::Status::kConverged);
  const typename TM::VecQ q0 = Eigen::Map<const typename TM::VecQ>(M::kQMin.data());
  const typename TM::VecQ q1 = Eigen::Map<const typename TM::VecQ>(M::kQMax.data());
  const TV::VecQ v0 = Eigen::Map<const TV::VecQ>(view.q_min, view.nq);
  const TV::VecQ v1 = Eigen::Map<const TV::VecQ>(view.q_max, view.nq);
  std::vector<Equilibrium<M>> found_a;
  std::vector<Equilibrium<ViewModel>> found_b;
  EXPECT_EQ(FindEquilibria(Options(), scan, &fixed, q0, q1, &found_a, &sa),
            FindEquilibria(Options(), scan, &dynamic, v0, v1, &found_b, &sb));
  EXPECT_EQ(sa.evaluations, sb.evaluations);
  ASSERT_EQ(found_a.size(), found_b.size());
  for (size_t i = 0; i < found_a.size(); ++i) {
    EXPECT_TRUE(SameBits("equilibrium q", found_a[i].q, found_b[i].q)) << i;
    EXPECT_TRUE(SameBits("equilibrium Q", found_a[i].Q, found_b[i].Q)) << i;
    EXPECT_TRUE(SameBits("equilibrium stiffness", found_a[i].stiffness, found_b[i].stiffness)) << i;
    EXPECT_EQ(found_a[i].iterations, found_b[i].iterations) << i;
  }
}

#ifdef MECHGEN_HAVE_slider_crank_friction
TEST(ViewStatics, SameAsFixedSize_slider_crank_friction) {
  ExpectViewStaticsSweepSame<mech::slider_crank_friction::Model>(mech::slider_crank_friction::View());
  ExpectViewScansSame<mech::slider_crank_friction::Model>(mech::slider_crank_friction::View());
}
#endif
#ifdef MECHGEN_HAVE_fourbar_loaded
TEST(ViewStatics, SameAsFixedSize_fourbar_loaded) {
  ExpectViewStaticsSweepSame<mech::fourbar_loaded::Model>(mech::fourbar_loaded::View());
  ExpectViewScansSame<mech::fourbar_loaded::Model>(mech::fourbar_loaded::View());
  // --design: the statics' design derivatives (a design section over every length and load)
  ExpectViewStaticsSweepSame<mech::fourbar_loaded::Model>(mech::fourbar_loaded::View(), std::nan(""), true);
  ExpectViewStaticsSweepSame<mech::fourbar_loaded::Model>(mech::fourbar_loaded::View(), -2.5, true);
}
#endif
#ifdef MECHGEN_HAVE_slider_crank_press
TEST(ViewStatics, SameAsFixedSize_slider_crank_press) {
  ExpectViewStaticsSweepSame<mech::slider_crank_press::Model>(mech::slider_crank_press::View());
}
#endif
#ifdef MECHGEN_HAVE_slider_crank_motor
TEST(ViewStatics, SameAsFixedSize_slider_crank_motor) {
  static_assert(StaticsFeatures<mech::slider_crank_motor::Model>::kReadsSpeed);
  ExpectViewStaticsSweepSame<mech::slider_crank_motor::Model>(mech::slider_crank_motor::View());
  ExpectViewStaticsSweepSame<mech::slider_crank_motor::Model>(mech::slider_crank_motor::View(), 12.5);
}
#endif
#ifdef MECHGEN_HAVE_fivebar_robot
TEST(ViewStatics, SameAsFixedSize_fivebar_robot) {
  ExpectViewStaticsSweepSame<mech::fivebar_robot::Model>(mech::fivebar_robot::View());
}
#endif

// A view's Statics is its buffer with each member a map of it (core/view_model.h): a copy maps
// its own buffer (the source solved again afterwards leaves the copy as it was, bit for bit),
// and a copy over a value placed on another view's layout follows the source's (sizes and
// entries). Oracle: the fixed-size Solve at the same two configurations.
#if defined(MECHGEN_HAVE_slider_crank_friction) && defined(MECHGEN_HAVE_fourbar_loaded)
TEST(ViewStatics, CopyMapsItsOwnBuffer) {
  using M = mech::slider_crank_friction::Model;
  using VM = ViewModel;
  using VT = ModelTypes<VM>;
  const VM model(mech::slider_crank_friction::View());
  const VT::Params pv = ModelCalls<VM>::DefaultParams(model);
  const M::ParamsT<double> p;
  position::PositionSolver<M> fixed_solver;
  position::PositionSolver<VM> view_solver(model);
  ASSERT_EQ(fixed_solver.AssembleDefault(nullptr), position::Status::kConverged);
  ASSERT_EQ(view_solver.AssembleDefault(nullptr), position::Status::kConverged);
  auto solve_both = [&](double q, Solution<M>* a, Solution<VM>* b) {
    const typename ModelTypes<M>::VecQ qa = ModelTypes<M>::VecQ::Constant(q);
    const VT::VecQ qb = VT::VecQ::Constant(1, q);
    ASSERT_EQ(fixed_solver.MoveTo(qa, nullptr), position::Status::kConverged);
    ASSERT_EQ(view_solver.MoveTo(qb, nullptr), position::Status::kConverged);
    typename ModelTypes<M>::Coefficients ca;
    VT::Coefficients cb;
    ModelCalls<M>::Coeffs(M(), p, fixed_solver.state().q, fixed_solver.state().phi, &ca);
    ModelCalls<VM>::Coeffs(model, pv, view_solver.state().q, view_solver.state().phi, &cb);
    // moving forward: the friction iteration writes every member Forces has
    Solve<M>(M(), Options(), p, fixed_solver.state().q, fixed_solver.state().phi, ca,
             ModelTypes<M>::VecQ::Ones(), a);
    Solve<VM>(model, Options(), pv, view_solver.state().q, view_solver.state().phi, cb, VT::VecQ::Ones(1), b);
  };
  const double q0 = M::kAssemblyQ[0];
  Solution<M> a0, a1;
  Solution<VM> b0(model), b1(model);
  solve_both(q0 + 0.1, &a0, &b0);
  ASSERT_EQ(b0.summary.status, Status::kConverged);
  const Solution<VM> copy = b0;
  const double* const begin = copy.statics.buffer.data();
  const double* const end = begin + copy.statics.buffer.size();
  for (const double* x : {copy.statics.Q.data(), copy.statics.drive.data(), copy.statics.R.data(),
                          copy.statics.normal.data(), copy.statics.gain.data(), copy.statics.K_rel.data()}) {
    EXPECT_TRUE(x >= begin && x < end);
  }
  solve_both(q0 + 0.7, &a1, &b1);
  b0 = b1;  // the original now holds another configuration's values
  ExpectSameSolution<M>(a1, b0, "copy assigned");
  ExpectSameSolution<M>(a0, copy, "copy, its source solved again");
  EXPECT_NE(copy.statics.drive(0), b0.statics.drive(0));
  // Over a value placed on another view (fewer reactions, no friction): the source's layout.
  const VM other(mech::fourbar_loaded::View());
  Solution<VM> c(other);
  ASSERT_NE(c.statics.R.size(), copy.statics.R.size());
  c = copy;
  ExpectSameSolution<M>(a0, c, "copy over another view's");
  EXPECT_EQ(c.statics.view, copy.statics.view);
}
#endif

// The view's Forces and Stiffness on one Statics buffer behave as the generated functions on one
// Statics struct (core/model_view.h): what a function writes is its value, what it does not
// write keeps the buffer's (the adapters copy only the members a function names, and do not read
// those it writes whole: codegen/emit.cc, Flatten). Oracle: Model::Forces and Model::Stiffness on
// a fixed-size struct started at the same sentinel, member by member; the coefficients' buffer
// holds NaN in every member but those the functions read, which a copy of the others would not
// notice but a read would spread.
#ifdef MECHGEN_HAVE_fourbar_loaded
TEST(ViewStatics, BufferKeepsWhatAFunctionDoesNotWrite_fourbar_loaded) {
  using M = mech::fourbar_loaded::Model;
  const ModelView& view = mech::fourbar_loaded::View();
  M::ParamsT<double> p;
  std::vector<double> pv(static_cast<size_t>(view.num_params));
  DefaultParameters(view, pv.data());
  Eigen::Matrix<double, M::kNq, 1> q;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNq; ++i) q(i) = M::kAssemblyQ[i] + 0.3;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  ASSERT_EQ(M::Solve(p, q, &phi).status, mech::fourbar_loaded::SolveStatus::kConverged);
  M::CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  const ViewLayout& cl = view.Layout(ViewStruct::kCoefficients);
  std::vector<double> cb(static_cast<size_t>(cl.size), std::nan(""));
  auto put_c = [&](const char* name, const double* x) {
    const ViewMember* m = FindMember(cl, name);
    ASSERT_NE(m, nullptr) << name;
    std::copy(x, x + m->rows * m->cols, cb.begin() + m->offset);
  };
  put_c("Phi_phi", c.Phi_phi.data());  // (EvalStatics and EvalStiffness read K, L, Phi_phi)
  put_c("K", c.K.data());
  put_c("L", c.L.data());
  constexpr double kSentinel = 12345.678;
  M::StaticsT<double> fixed;
  fixed.Q.setConstant(kSentinel);
  fixed.drive.setConstant(kSentinel);
  fixed.stiffness.setConstant(kSentinel);
  fixed.V = kSentinel;
  fixed.dV_dq.setConstant(kSentinel);
  fixed.d2V_dq2.setConstant(kSentinel);
  fixed.R.setConstant(kSentinel);
  const ViewLayout& sl = view.Layout(ViewStruct::kStatics);
  std::vector<double> sb(static_cast<size_t>(sl.size), kSentinel);
  auto expect = [&](const char* step, const char* name, const double* x) {
    const ViewMember* m = FindMember(sl, name);
    ASSERT_NE(m, nullptr) << name;
    for (int i = 0; i < m->rows * m->cols; ++i) {
      EXPECT_TRUE(SameBits(name, x[i], sb[static_cast<size_t>(m->offset + i)])) << step << " " << name << " " << i;
    }
  };
  auto expect_all = [&](const char* step) {
    expect(step, "Q", fixed.Q.data());
    expect(step, "drive", fixed.drive.data());
    expect(step, "stiffness", fixed.stiffness.data());
    expect(step, "V", &fixed.V);
    expect(step, "dV_dq", fixed.dV_dq.data());
    expect(step, "d2V_dq2", fixed.d2V_dq2.data());
    expect(step, "R", fixed.R.data());
  };
  // Stiffness first (Forces' members keep the sentinel), then Forces (stiffness keeps its value).
  M::Stiffness(p, q, phi, c, &fixed);
  view.Stiffness(pv.data(), q.data(), phi.data(), cb.data(), sb.data());
  expect_all("Stiffness");
  EXPECT_EQ(fixed.Q(0), kSentinel);
  EXPECT_NE(fixed.stiffness(0, 0), kSentinel);
  M::Forces(p, q, phi, c, &fixed);
  view.Forces(pv.data(), q.data(), phi.data(), cb.data(), sb.data(), nullptr, nullptr, nullptr);
  expect_all("Forces");
  EXPECT_NE(fixed.Q(0), kSentinel);
  EXPECT_TRUE(std::isfinite(fixed.R(0)));
}
#endif

// The statics command through the view: its options, the analysis, its pictures.
int RunStatics(const ViewModel& model, const statics_tool::Arguments& arguments) {
  statics_tool::Command command(arguments);
  return command([&](const analysis::StaticsOutputs& outputs, const std::function<int()>& prepare,
                     analysis::StaticsPlotFacts* facts) {
    return analysis::Run(model, arguments, outputs, prepare, facts);
  });
}

// A model without statics is refused through the view (the per-model tool is a stub that says
// so), and so are --design on a model without a design section and a bad --set, before anything
// is written (exit 2).
TEST(ViewStaticsTool, RefusesWhatTheViewLacks) {
#ifdef MECHGEN_HAVE_fourbar
  statics_tool::Arguments arguments;
  arguments.csv_path = ::testing::TempDir() + "view_statics_refused.csv";
  std::remove(arguments.csv_path.c_str());
  EXPECT_EQ(RunStatics(ViewModel(mech::fourbar::View()), arguments), statics_tool::kExitUsage);
  EXPECT_FALSE(std::ifstream(arguments.csv_path).good());
#endif
#ifdef MECHGEN_HAVE_slider_crank_friction
  const ViewModel model(mech::slider_crank_friction::View());
  for (int k = 1; k < 3; ++k) {
    statics_tool::Arguments arguments;
    arguments.csv_path = ::testing::TempDir() + "view_statics_refused.csv";
    std::remove(arguments.csv_path.c_str());
    if (k == 1) arguments.design = true;
    if (k == 2) arguments.params.sets.push_back("nosuch=1");  // (--set itself goes through the view)
    EXPECT_EQ(RunStatics(model, arguments), statics_tool::kExitUsage) << k;
    EXPECT_FALSE(analysis::Check(model, arguments).empty()) << k;
    EXPECT_FALSE(std::ifstream(arguments.csv_path).good()) << k;
  }
#endif
}

// The statics command of a model of one input and two dependent coordinates, as mechgen runs
// it (on the runtime sized to that shape, core/view_sized.h) and on the instantiation for a view
// of any shape: the same CSV, byte for byte, with friction (forward and backward, dead zones,
// equilibria, at speed), springs and gravity, and the design derivatives; the same exit status
// and output.
std::string StaticsCsv(const ModelView& view, bool sized, statics_tool::Arguments arguments, int* status,
                       std::string* printed) {
  ViewModel model(view);
  model.sized = sized;
  arguments.csv_path = ::testing::TempDir() + "view_statics_sized.csv";
  arguments.table = 3;
  std::remove(arguments.csv_path.c_str());
  ::testing::internal::CaptureStdout();
  *status = RunStatics(model, arguments);
  *printed = ::testing::internal::GetCapturedStdout();
  std::ifstream in(arguments.csv_path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
void ExpectSizedSame(const ModelView& view, const statics_tool::Arguments& arguments, const char* what) {
  ASSERT_TRUE(ViewSized12::Fits(ViewModel(view))) << view.name;
  int status_sized = -1, status_any = -1;
  std::string printed_sized, printed_any;
  const std::string a = StaticsCsv(view, true, arguments, &status_sized, &printed_sized);
  const std::string b = StaticsCsv(view, false, arguments, &status_any, &printed_any);
  EXPECT_EQ(status_sized, status_any) << what;
  EXPECT_GT(std::count(a.begin(), a.end(), '\n'), 40) << what;
  EXPECT_TRUE(a == b) << view.name << " " << what << ": the CSVs differ";
  // The printed summary but for the timing figure (us/row).
  auto untimed = [](std::string text) {
    for (size_t at = text.find(" us/row"); at != std::string::npos; at = text.find(" us/row", at + 1)) {
      size_t begin = at;
      while (begin > 0 && (std::isdigit(static_cast<unsigned char>(text[begin - 1])) || text[begin - 1] == '.')) --begin;
      text.replace(begin, at - begin, "T");
      at = begin + 1;
    }
    return text;
  };
  EXPECT_EQ(untimed(printed_sized), untimed(printed_any)) << what;
}
TEST(ViewStaticsTool, SizedRuntimeSameAsAnyShape) {
#ifdef MECHGEN_HAVE_slider_crank_friction
  {
    statics_tool::Arguments arguments;
    arguments.steps = 120;
    arguments.dead_zones = arguments.equilibria = true;
    arguments.samples = 72;
    ExpectSizedSame(mech::slider_crank_friction::View(), arguments, "dead zones, equilibria");
    arguments = statics_tool::Arguments();
    arguments.steps = 90;
    arguments.speed = 2 * 3.14159265358979323846;
    arguments.ranges.push_back("theta_crank:10deg:300deg");
    ExpectSizedSame(mech::slider_crank_friction::View(), arguments, "at speed");
  }
#endif
#ifdef MECHGEN_HAVE_fourbar_loaded
  {
    statics_tool::Arguments arguments;
    arguments.steps = 100;
    arguments.equilibria = true;
    arguments.samples = 90;
    ExpectSizedSame(mech::fourbar_loaded::View(), arguments, "equilibria");
    arguments = statics_tool::Arguments();
    arguments.steps = 80;
    arguments.design = true;
    ExpectSizedSame(mech::fourbar_loaded::View(), arguments, "design");
  }
#endif
}

}  // namespace
}  // namespace mechgen::statics
