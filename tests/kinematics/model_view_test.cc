// The model view (issue 43, mechgen/core/model_view.h) of every shipped model against the
// model's own fixed-size header: its sizes, names, constants and flags against Model's, its
// functions present exactly where Model has them (detected here from the header, not from
// the flags), and each function's every output, called through the view on flat arrays,
// equal to the bit to the fixed-size function's at several configurations and at defaults
// and perturbed parameters (the view copies and calls: the same arithmetic). The buffers of
// the structs are read by member name through the view's layout; the comparisons name each
// member of the generated struct by hand. The parameter table against Params (names,
// defaults, Find), and the derived parameters against the model files' definitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#define MECHTEST_MODEL_VIEWS
#include "all_models.h"
#include "kinematics_test_util.h"
#include "mechgen/core/view_model.h"
#include "mechgen/core/view_sized.h"
#include "mechgen/statics/solve.h"

namespace {

using mechgen::ModelView;
using mechgen::ViewLayout;
using mechgen::ViewStruct;

template <class M>
const ModelView& ViewOfModel() {
  return ViewOf(static_cast<const M*>(nullptr));
}

// Whether M has the constant or function `Name` (from the header itself).
#define DETECT(Name)                      \
  template <class M, class = void>        \
  struct Has_##Name : std::false_type {}; \
  template <class M>                      \
  struct Has_##Name<M, std::void_t<decltype(M::Name)>> : std::true_type {};
DETECT(kReactionNames)
DETECT(kNumSwitches)
DETECT(kDesignNames)
DETECT(kNumDrawJoints)
DETECT(kNumAppliedLoads)
DETECT(kNumNamedModes)
DETECT(kNumChangePoints)
DETECT(kStaticsAtSpeed)
#undef DETECT
#define DETECT_FUNCTION(Name)               \
  template <class M, class = void>          \
  struct HasFn_##Name : std::false_type {}; \
  template <class M>                        \
  struct HasFn_##Name<M, std::void_t<decltype(&M::template Name<double>)>> : std::true_type {};
DETECT_FUNCTION(Phi)
DETECT_FUNCTION(Coeffs)
DETECT_FUNCTION(DetPhiPhi)
DETECT_FUNCTION(Solve)
DETECT_FUNCTION(SolveTrig)
DETECT_FUNCTION(Kinematics)
DETECT_FUNCTION(TransmissionAngles)
DETECT_FUNCTION(Scene)
DETECT_FUNCTION(Drawing)
DETECT_FUNCTION(CamProfile)
DETECT_FUNCTION(AppliedLoads)
DETECT_FUNCTION(Forces)
DETECT_FUNCTION(Stiffness)
DETECT_FUNCTION(Dynamics)
DETECT_FUNCTION(Kinetostatics)
DETECT_FUNCTION(ExcessDynamics)
DETECT_FUNCTION(Shaking)
DETECT_FUNCTION(SwitchModes)
DETECT_FUNCTION(Prepare)
DETECT_FUNCTION(Rhs)
DETECT_FUNCTION(Design)
DETECT_FUNCTION(DesignChecks)
DETECT_FUNCTION(StaticsDesign)
DETECT_FUNCTION(DynamicsDesign)
DETECT_FUNCTION(ShakingDesign)
#undef DETECT_FUNCTION

// The bits of x (NaN where the fixed-size function gives NaN, e.g. a massless link's r_G).
uint64_t Bits(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

void ExpectNames(const char* const* view, const char* const* model, int n, const char* what) {
  for (int i = 0; i < n; ++i) EXPECT_STREQ(view[i], model[i]) << what << "[" << i << "]";
}
template <class T, size_t N>
void ExpectArray(const T* view, const std::array<T, N>& model, const char* what) {
  for (size_t i = 0; i < N; ++i) EXPECT_EQ(view[i], model[i]) << what << "[" << i << "]";
}

// The struct members compared (struct, member), so that a test can require every member of
// every struct a model has to have been compared.
std::set<std::pair<std::string, std::string>>& Compared() {
  static std::set<std::pair<std::string, std::string>> compared;
  return compared;
}

// The buffer `flat` of a view struct against the fixed-size struct's member `value`: the member
// found by name, its shape, every entry bit for bit.
template <int R, int C, int O, int MR, int MC>
void ExpectMember(const ViewLayout& layout,
                  const std::vector<double>& flat,
                  const char* name,
                  const Eigen::Matrix<double, R, C, O, MR, MC>& value) {
  const mechgen::ViewMember* m = mechgen::FindMember(layout, name);
  ASSERT_NE(m, nullptr) << layout.name << " has no member " << name;
  Compared().insert({layout.name, name});
  ASSERT_EQ(m->rows, R) << layout.name << "::" << name;
  ASSERT_EQ(m->cols, C) << layout.name << "::" << name;
  ASSERT_LE(m->offset + R * C, layout.size);
  for (int j = 0; j < C; ++j)
    for (int i = 0; i < R; ++i)
      EXPECT_EQ(Bits(flat[m->offset + i + R * j]), Bits(value(i, j)))
          << layout.name << "::" << name << "(" << i << ", " << j << "): view " << flat[m->offset + i + R * j]
          << ", fixed " << value(i, j);
}
void ExpectMember(const ViewLayout& layout, const std::vector<double>& flat, const char* name, double value) {
  const Eigen::Matrix<double, 1, 1> m = Eigen::Matrix<double, 1, 1>::Constant(value);
  ExpectMember(layout, flat, name, m);
}
template <size_t N>
void ExpectMember(const ViewLayout& layout,
                  const std::vector<double>& flat,
                  const char* name,
                  const std::array<double, N>& value) {
  const Eigen::Matrix<double, static_cast<int>(N), 1> m =
      Eigen::Map<const Eigen::Matrix<double, static_cast<int>(N), 1>>(value.data());
  ExpectMember(layout, flat, name, m);
}
// The member `name` of a view struct's buffer `flat` into the fixed-size struct's member `value`
// (found by name).
template <int R, int C, int O, int MR, int MC>
void GetMember(const ViewLayout& layout,
               const std::vector<double>& flat,
               const char* name,
               Eigen::Matrix<double, R, C, O, MR, MC>* value) {
  const mechgen::ViewMember* m = mechgen::FindMember(layout, name);
  ASSERT_NE(m, nullptr) << layout.name << " has no member " << name;
  ASSERT_EQ(m->rows * m->cols, R * C) << layout.name << "::" << name;
  for (int i = 0; i < R * C; ++i) value->data()[i] = flat[static_cast<size_t>(m->offset + i)];
}
void GetMember(const ViewLayout& layout, const std::vector<double>& flat, const char* name, double* value) {
  const mechgen::ViewMember* m = mechgen::FindMember(layout, name);
  ASSERT_NE(m, nullptr) << layout.name << " has no member " << name;
  *value = flat[static_cast<size_t>(m->offset)];
}
// A plain array (an argument, not a struct) against a fixed-size matrix.
template <class Derived>
void ExpectFlat(const std::vector<double>& flat, const Eigen::MatrixBase<Derived>& value, const char* what) {
  ASSERT_EQ(static_cast<Eigen::Index>(flat.size()), value.size()) << what;
  for (Eigen::Index j = 0; j < value.cols(); ++j)
    for (Eigen::Index i = 0; i < value.rows(); ++i)
      EXPECT_EQ(Bits(flat[i + value.rows() * j]), Bits(value(i, j)))
          << what << "(" << i << ", " << j << "): view " << flat[i + value.rows() * j] << ", fixed " << value(i, j);
}
template <class Report>
void ExpectSameReport(const mechgen::ViewSolveReport& v, const Report& fixed, const char* what) {
  EXPECT_EQ(static_cast<int>(v.status), static_cast<int>(fixed.status)) << what;
  EXPECT_EQ(v.block, fixed.block) << what;
  EXPECT_EQ(v.iterations, fixed.iterations) << what;
  EXPECT_EQ(Bits(v.measure), Bits(fixed.measure)) << what;
  EXPECT_EQ(Bits(v.branch_measure), Bits(fixed.branch_measure)) << what;
  EXPECT_EQ(v.branch_block, fixed.branch_block) << what;
}

// A buffer of a struct, every entry `fill` (the fixed-size struct is filled alike, so that the
// members a function does not write compare equal too).
std::vector<double> Buffer(const ModelView& v, ViewStruct s, double fill) {
  return std::vector<double>(static_cast<size_t>(v.Layout(s).size), fill);
}

constexpr double kFill = 0.8125;  // exact in binary; no function's output

template <class M>
class ModelViewTest : public ::testing::Test {};
TYPED_TEST_SUITE(ModelViewTest, mechtest::AllModels, mechtest::ModelNames);

TYPED_TEST(ModelViewTest, SizesNamesConstantsAndFlagsAreTheModels) {
  using M = TypeParam;
  const ModelView& v = ViewOfModel<M>();
  EXPECT_EQ(v.layout, mechgen::kModelViewLayout);
  EXPECT_EQ(v.size, static_cast<int>(sizeof(ModelView)));
  EXPECT_STREQ(v.name, M::kName);
  EXPECT_EQ(v.nq, M::kNq);
  EXPECT_EQ(v.nphi, M::kNphi);
  EXPECT_EQ(v.nc, M::kNc);
  EXPECT_EQ(v.num_loops, M::kNumLoops);
  EXPECT_EQ(v.mobility, M::kMobility);
  EXPECT_EQ(v.order, M::kOrder);
  EXPECT_EQ(v.num_points, M::kNumPoints);
  EXPECT_EQ(v.num_links, M::kNumLinks);
  EXPECT_EQ(v.num_scene_points, M::kNumScenePoints);
  EXPECT_EQ(v.num_blocks, M::kNumBlocks);
  EXPECT_EQ(v.num_transmission_angles, M::kNumTransmissionAngles);
  EXPECT_EQ(v.ground_link, M::kGroundLink);
  ExpectNames(v.q_names, M::kQNames.data(), M::kNq, "q_names");
  ExpectNames(v.phi_names, M::kPhiNames.data(), M::kNphi, "phi_names");
  ExpectArray(v.q_is_angle, M::kQIsAngle, "q_is_angle");
  ExpectArray(v.phi_is_angle, M::kPhiIsAngle, "phi_is_angle");
  ExpectArray(v.q_min, M::kQMin, "q_min");
  ExpectArray(v.q_max, M::kQMax, "q_max");
  ExpectArray(v.assembly_q, M::kAssemblyQ, "assembly_q");
  ExpectArray(v.assembly_phi, M::kAssemblyPhi, "assembly_phi");
  ExpectNames(v.point_names, M::kPointNames.data(), M::kNumPoints, "point_names");
  ExpectNames(v.link_names, M::kLinkNames.data(), M::kNumLinks, "link_names");
  ExpectNames(v.scene_point_names, M::kScenePointNames.data(), M::kNumScenePoints, "scene_point_names");
  ExpectArray(v.scene_point_links, M::kScenePointLink, "scene_point_links");
  ExpectArray(v.default_modes, M::kDefaultModes, "default_modes");
  ExpectArray(v.block_closed_form, M::kBlockClosedForm, "block_closed_form");
  ExpectNames(v.transmission_joints, M::kTransmissionJoints.data(), M::kNumTransmissionAngles, "transmission_joints");
  if constexpr (Has_kReactionNames<M>::value) {
    EXPECT_EQ(v.num_reactions, M::kNumReactions);
    EXPECT_EQ(v.num_friction, M::kNumFriction);
    ExpectNames(v.reaction_names, M::kReactionNames.data(), M::kNumReactions, "reaction_names");
    ExpectArray(v.reaction_joints, M::kReactionJoint, "reaction_joints");
    ASSERT_EQ(v.num_joints, static_cast<int>(M::kJointNames.size()));
    ExpectNames(v.joint_names, M::kJointNames.data(), v.num_joints, "joint_names");
    ExpectNames(v.friction_joints, M::kFrictionJoints.data(), M::kNumFriction, "friction_joints");
    ExpectArray(v.friction_prismatic, M::kFrictionPrismatic, "friction_prismatic");
    ASSERT_EQ(v.num_loads, static_cast<int>(M::kLoadNames.size()));
    ExpectNames(v.load_names, M::kLoadNames.data(), v.num_loads, "load_names");
  } else {
    EXPECT_EQ(v.num_reactions, 0);
    EXPECT_EQ(v.num_friction, 0);
  }
  if constexpr (Has_kNumSwitches<M>::value) {
    EXPECT_EQ(v.num_switches, M::kNumSwitches);
  } else {
    EXPECT_EQ(v.num_switches, 0);
  }
  if constexpr (Has_kDesignNames<M>::value) {
    EXPECT_EQ(v.num_design, M::kNumDesign);
    EXPECT_EQ(v.num_design_checks, M::kNumDesignChecks);
    ExpectNames(v.design_names, M::kDesignNames.data(), M::kNumDesign, "design_names");
    ExpectNames(v.design_check_names, M::kDesignCheckNames.data(), M::kNumDesignChecks, "design_check_names");
  } else {
    EXPECT_EQ(v.num_design, 0);
  }
  if constexpr (Has_kNumDrawJoints<M>::value) {
    EXPECT_EQ(v.num_draw_joints, M::kNumDrawJoints);
    EXPECT_EQ(v.num_draw_values, M::kNumDrawValues);
    ExpectArray(v.draw_joint_kind, M::kDrawJointKind, "draw_joint_kind");
    ExpectArray(v.draw_joint_link_a, M::kDrawJointLinkA, "draw_joint_link_a");
    ExpectArray(v.draw_joint_link_b, M::kDrawJointLinkB, "draw_joint_link_b");
    ExpectArray(v.draw_joint_point_a, M::kDrawJointPointA, "draw_joint_point_a");
    ExpectArray(v.draw_joint_point_b, M::kDrawJointPointB, "draw_joint_point_b");
    ExpectArray(v.draw_joint_value, M::kDrawJointValue, "draw_joint_value");
  } else {
    EXPECT_EQ(v.num_draw_joints, 0);
  }
  if constexpr (Has_kNumAppliedLoads<M>::value) {
    EXPECT_EQ(v.num_applied_loads, M::kNumAppliedLoads);
    ExpectNames(v.applied_load_names, M::kAppliedLoadNames.data(), M::kNumAppliedLoads, "applied_load_names");
    ExpectArray(v.applied_load_kind, M::kAppliedLoadKind, "applied_load_kind");
    ExpectNames(v.applied_load_units, M::kAppliedLoadUnits.data(), M::kNumAppliedLoads, "applied_load_units");
  } else {
    EXPECT_EQ(v.num_applied_loads, 0);
  }
  if constexpr (Has_kNumNamedModes<M>::value) {
    ASSERT_EQ(v.num_named_modes, M::kNumNamedModes);
    ExpectNames(v.mode_names, M::kModeNames.data(), M::kNumNamedModes, "mode_names");
    for (int i = 0; i < M::kNumNamedModes; ++i)
      for (int b = 0; b < M::kNumBlocks; ++b) EXPECT_EQ(v.named_modes[i * M::kNumBlocks + b], M::kNamedModes[i][b]);
  } else {
    EXPECT_EQ(v.num_named_modes, 0);
  }
  if constexpr (Has_kNumChangePoints<M>::value) {
    ASSERT_EQ(v.num_change_points, M::kNumChangePoints);
    ExpectArray(v.change_point_inputs, M::kChangePointInput, "change_point_inputs");
    ExpectArray(v.change_point_blocks, M::kChangePointBlock, "change_point_blocks");
    ExpectArray(v.change_point_q, M::kChangePointQ, "change_point_q");
  } else {
    EXPECT_EQ(v.num_change_points, 0);
  }
  // Every flag, under its own name.
  // clang-format off
#define FLAG(F) EXPECT_EQ(v.flags.F, M::F) << #F
  FLAG(kHasCoeffsPhi); FLAG(kHasK); FLAG(kHasL); FLAG(kHasPoints); FLAG(kHasPointVelocities);
  FLAG(kHasPointAccelerations); FLAG(kHasSolve); FLAG(kHasNamedModes); FLAG(kHasTrig); FLAG(kHasSolveTrig);
  FLAG(kHasTransmissionAngles); FLAG(kHasSwitchModes); FLAG(kHasDrawing); FLAG(kHasCamProfile);
  FLAG(kHasAppliedLoads); FLAG(kHasStatics); FLAG(kHasStaticsQ); FLAG(kHasStaticsStiffness); FLAG(kHasStaticsV);
  FLAG(kHasStaticsD2V); FLAG(kHasStaticsR); FLAG(kHasStaticsFriction); FLAG(kHasDynamics); FLAG(kHasExcess);
  FLAG(kHasShaking); FLAG(kHasKinematics); FLAG(kHasRhs); FLAG(kHasRhsConstants); FLAG(kHasDesignDerivatives);
  FLAG(kHasStaticsDesign); FLAG(kHasDynamicsDesign);
#undef FLAG
  // A function exactly where Model has it.
#define FUNCTION(F) EXPECT_EQ(v.F != nullptr, HasFn_##F<M>::value) << #F
  FUNCTION(Phi); FUNCTION(Coeffs); FUNCTION(DetPhiPhi); FUNCTION(Solve); FUNCTION(SolveTrig); FUNCTION(Kinematics);
  FUNCTION(TransmissionAngles); FUNCTION(Scene); FUNCTION(Drawing); FUNCTION(CamProfile); FUNCTION(AppliedLoads);
  FUNCTION(Forces); FUNCTION(Stiffness); FUNCTION(Dynamics); FUNCTION(Kinetostatics); FUNCTION(ExcessDynamics);
  FUNCTION(Shaking); FUNCTION(SwitchModes); FUNCTION(Prepare); FUNCTION(Rhs); FUNCTION(Design); FUNCTION(DesignChecks);
  FUNCTION(StaticsDesign); FUNCTION(DynamicsDesign); FUNCTION(ShakingDesign);
#undef FUNCTION
  // clang-format on
  // And the flags that name a function say so too.
  EXPECT_EQ(v.Solve != nullptr, M::kHasSolve);
  EXPECT_EQ(v.SolveTrig != nullptr, M::kHasSolveTrig);
  EXPECT_EQ(v.Kinematics != nullptr, M::kHasKinematics);
  EXPECT_EQ(v.Forces != nullptr, M::kHasStatics);
  EXPECT_EQ(v.Dynamics != nullptr, M::kHasDynamics);
  EXPECT_EQ(v.ExcessDynamics != nullptr, M::kHasExcess);
  EXPECT_EQ(v.Shaking != nullptr, M::kHasShaking);
  EXPECT_EQ(v.Rhs != nullptr, M::kHasRhs);
  EXPECT_EQ(v.Prepare != nullptr, M::kHasRhsConstants);
  EXPECT_EQ(v.Design != nullptr, M::kHasDesignDerivatives);
  EXPECT_EQ(v.StaticsDesign != nullptr, M::kHasStaticsDesign);
  EXPECT_EQ(v.DynamicsDesign != nullptr, M::kHasDynamicsDesign);
  EXPECT_EQ(v.TransmissionAngles != nullptr, M::kHasTransmissionAngles);
  EXPECT_EQ(v.SwitchModes != nullptr, M::kHasSwitchModes);
  EXPECT_EQ(v.Drawing != nullptr, M::kHasDrawing);
  EXPECT_EQ(v.CamProfile != nullptr, M::kHasCamProfile);
  EXPECT_EQ(v.AppliedLoads != nullptr, M::kHasAppliedLoads);
  // The maxima of a runtime compiled once hold every shipped model, and the view says so.
  bool fits = M::kNq <= ModelView::kMaxQ && M::kNphi <= ModelView::kMaxPhi && M::kNumPoints <= ModelView::kMaxPoints &&
              M::kNumLinks <= ModelView::kMaxLinks && v.num_joints <= ModelView::kMaxJoints &&
              M::kNumScenePoints <= ModelView::kMaxScenePoints && M::kNumBlocks <= ModelView::kMaxBlocks &&
              v.num_params <= ModelView::kMaxParams && v.num_reactions <= ModelView::kMaxReactions &&
              v.num_friction <= ModelView::kMaxFriction && v.num_design <= ModelView::kMaxDesign &&
              v.num_design_checks <= ModelView::kMaxDesignChecks &&
              M::kNumTransmissionAngles <= ModelView::kMaxTransmissionAngles;
  for (int s = 0; s < static_cast<int>(ViewStruct::kCount); ++s)
    fits = fits && v.structs[s].size <= ModelView::kMaxStructSize[s];
  EXPECT_TRUE(fits);
  EXPECT_TRUE(v.fits_maxima);
}

// Each struct's layout: members in order from 0, each rows x cols, none overlapping the one
// before, at most the padding of an alignment after it (the generated struct's own layout, so that
// the struct may lie on the buffer), the size past the last; and the structs a model has exactly
// where their flags (Coefficients and Trig: always) say.
TYPED_TEST(ModelViewTest, StructLayoutsAreTheStructsAndPresentWhereTheFlagsSay) {
  using M = TypeParam;
  const ModelView& v = ViewOfModel<M>();
  // clang-format off
  const bool present[] = {true, true, M::kHasStatics, M::kHasDynamics, M::kHasExcess, M::kHasShaking,
                          M::kHasKinematics, M::kHasRhs, M::kHasRhsConstants, M::kHasDesignDerivatives,
                          M::kHasStaticsDesign, M::kHasDynamicsDesign};
  // clang-format on
  static_assert(sizeof(present) / sizeof(present[0]) == static_cast<size_t>(ViewStruct::kCount));
  for (int s = 0; s < static_cast<int>(ViewStruct::kCount); ++s) {
    const ViewLayout& l = v.structs[s];
    EXPECT_EQ(l.name != nullptr, present[s]) << s;
    constexpr int kPadding = static_cast<int>(EIGEN_MAX_STATIC_ALIGN_BYTES / sizeof(double));  // (at most, in doubles)
    int offset = 0;  // the end of the member before
    for (int i = 0; i < l.num_members; ++i) {
      EXPECT_GE(l.members[i].offset, offset) << l.name << "::" << l.members[i].name;
      EXPECT_LT(l.members[i].offset, offset + std::max(kPadding, 1)) << l.name << "::" << l.members[i].name;
      EXPECT_GE(l.members[i].rows, 0);
      EXPECT_GE(l.members[i].cols, 0);
      offset = l.members[i].offset + l.members[i].rows * l.members[i].cols;
    }
    EXPECT_GE(l.size, offset) << (l.name ? l.name : "absent");
    EXPECT_LT(l.size, offset + std::max(kPadding, 1)) << (l.name ? l.name : "absent");
  }
  EXPECT_EQ(mechgen::FindMember(v.Layout(ViewStruct::kCoefficients), "no_such_member"), nullptr);
  EXPECT_EQ(mechgen::FindMember(v.Layout(ViewStruct::kCoefficients), "K") != nullptr, M::kHasK);
  EXPECT_EQ(mechgen::FindMember(v.Layout(ViewStruct::kCoefficients), "L") != nullptr, M::kHasL);
  EXPECT_EQ(mechgen::FindMember(v.Layout(ViewStruct::kCoefficients), "r_P") != nullptr, M::kHasPoints);
}

// The parameter table: the free parameters are Params' members in order, with Params' defaults,
// found by name; the derived ones follow, named as kDerivedNames, and fill_derived gives their
// tabled defaults from the free ones.
TYPED_TEST(ModelViewTest, ParameterTableIsParams) {
  using M = TypeParam;
  using P = mechtest::ParamsD<M>;
  const ModelView& v = ViewOfModel<M>();
  ASSERT_EQ(v.num_free_params, static_cast<int>(P::kNames.size()));
  ASSERT_EQ(v.num_params, static_cast<int>(P::kNames.size() + P::kDerivedNames.size()));
  P defaults;
  for (int i = 0; i < v.num_params; ++i) {
    const mechgen::ViewParameter& par = v.params[i];
    EXPECT_EQ(mechgen::FindParameter(v, par.name), i) << par.name;
    if (i < v.num_free_params) {
      EXPECT_STREQ(par.name, P::kNames[i]);
      EXPECT_FALSE(par.derived) << par.name;
      const double* member = defaults.Find(par.name);
      ASSERT_NE(member, nullptr) << par.name;
      EXPECT_EQ(Bits(par.default_value), Bits(*member)) << par.name;
    } else {
      EXPECT_STREQ(par.name, P::kDerivedNames[i - v.num_free_params]);
      EXPECT_TRUE(par.derived) << par.name;
      EXPECT_EQ(defaults.Find(par.name), nullptr) << par.name << " is no Params member";
    }
  }
  EXPECT_EQ(mechgen::FindParameter(v, "no_such_parameter"), -1);
  std::vector<double> p(static_cast<size_t>(v.num_params), 0.0);
  mechgen::DefaultParameters(v, p.data());
  std::vector<double> filled = p;
  for (int i = v.num_free_params; i < v.num_params; ++i) filled[i] = NAN;
  ASSERT_NE(v.fill_derived, nullptr);
  v.fill_derived(filled.data());
  for (int i = 0; i < v.num_params; ++i) {
    // The table's default of a derived parameter is its definition evaluated exactly by the
    // generator (GiNaC), then rounded; fill_derived evaluates it in double: a few roundings
    // of a short expression apart (the largest relative difference of the shipped ones is
    // checked against 1e-14).
    if (i < v.num_free_params)
      EXPECT_EQ(Bits(filled[i]), Bits(p[i])) << v.params[i].name << " (free: left as it is)";
    else
      EXPECT_NEAR(filled[i], p[i], 1e-14 * (1.0 + std::abs(p[i]))) << v.params[i].name;
  }
}

// The derived parameters against the model files' definitions, written again here
// (models/engine_single.yaml, models/fourbar_balanced.yaml), at other free parameters.
TEST(ModelView, DerivedParametersFollowTheModelFilesDefinitions) {
  {
    const ModelView& v = mech::engine_single::View();
    std::vector<double> p(static_cast<size_t>(v.num_params));
    mechgen::DefaultParameters(v, p.data());
    const int bore = mechgen::FindParameter(v, "bore"), area = mechgen::FindParameter(v, "A_pis");
    ASSERT_GE(bore, 0);
    ASSERT_GE(area, v.num_free_params);
    p[bore] = 0.093;
    v.fill_derived(p.data());
    EXPECT_NEAR(p[area], mechtest::kPi * 0.093 * 0.093 / 4, 1e-17);  // A_pis: Pi*bore^2/4
  }
  {
    const ModelView& v = mech::fourbar_balanced::View();
    std::vector<double> p(static_cast<size_t>(v.num_params));
    mechgen::DefaultParameters(v, p.data());
    auto at = [&v, &p](const char* name) -> double& {
      const int i = mechgen::FindParameter(v, name);
      EXPECT_GE(i, 0) << name;
      return p[static_cast<size_t>(i)];
    };
    at("m3") *= 1.1;
    at("a") *= 0.9;
    v.fill_derived(p.data());
    const double m3 = at("m3"), a = at("a"), b = at("b"), c = at("c"), x3 = at("x3"), y3 = at("y3");
    const double m2b = at("m2b"), m4b = at("m4b"), mc2 = at("mc2"), balance = at("balance");
    const double W2x = m3 * a * (x3 / b - 1) - m2b * a / 2, W2y = m3 * a * y3 / b;
    const double W4x = -m3 * c * x3 / b - m4b * c / 2;
    EXPECT_NEAR(at("W2x"), W2x, 1e-13 * (1 + std::abs(W2x)));
    EXPECT_NEAR(at("W2y"), W2y, 1e-13 * (1 + std::abs(W2y)));
    EXPECT_NEAR(at("W4x"), W4x, 1e-13 * (1 + std::abs(W4x)));
    EXPECT_NEAR(at("r2"), std::sqrt(W2x * W2x + W2y * W2y) / mc2, 1e-13);
    EXPECT_NEAR(at("g2"), std::atan2(W2y, W2x), 1e-13);
    EXPECT_NEAR(at("M2"), m2b + balance * mc2, 1e-13);
  }
}

// Params from the view's flat array p, and the same numbers as a Params set member by member
// by name (Params::Find): the defaults, each free parameter scaled by its own factor.
template <class M>
void Parameters(const ModelView& v, double perturb, std::vector<double>* flat, mechtest::ParamsD<M>* params) {
  flat->assign(static_cast<size_t>(v.num_params), 0.0);
  mechgen::DefaultParameters(v, flat->data());
  for (int i = 0; i < v.num_free_params; ++i) {
    (*flat)[i] *= 1.0 + perturb * (1 + i % 7);
    *params->Find(v.params[i].name) = (*flat)[i];
  }
  v.fill_derived(flat->data());
}

template <class M, class S>
S Filled() {
  static_assert(sizeof(S) >= sizeof(double), "a struct of doubles");
  S s;
  // Every member the same value, as the view's buffer (Buffer): a function that leaves a
  // member alone leaves kFill on both sides.
  std::vector<double> raw(sizeof(S) / sizeof(double), kFill);
  static_assert(sizeof(S) % sizeof(double) == 0);
  std::memcpy(static_cast<void*>(&s), raw.data(), sizeof(S));
  return s;
}

// An output the view writes whole (Solve's and SolveTrig's trig): the fixed-size function's
// result with 0 where it left the filled value (kFill, no function's output): the entries it
// does not write, which the view starts at 0 instead of reading them from its buffer.
template <int R, int C, int O, int MR, int MC>
Eigen::Matrix<double, R, C, O, MR, MC> Unwritten0(Eigen::Matrix<double, R, C, O, MR, MC> x) {
  for (int i = 0; i < x.size(); ++i)
    if (Bits(x.data()[i]) == Bits(kFill)) x.data()[i] = 0.0;
  return x;
}

template <class M>
std::vector<double> Vector(const Eigen::Matrix<double, Eigen::Dynamic, 1>& x) {
  return std::vector<double>(x.data(), x.data() + x.size());
}

// Every function of the view against the fixed-size function, bit for bit, every output.
template <class M>
void CompareAt(const ModelView& v,
               const std::vector<double>& p,
               const mechtest::ParamsD<M>& params,
               const typename mechtest::Config<M>& config) {
  using Coefficients = typename M::template CoefficientsT<double>;
  using VecQ = mechtest::VecQ<M>;
  using VecPhi = mechtest::VecPhi<M>;
  const VecQ& q = config.q;
  const VecPhi& phi = config.phi;
  const std::vector<double> qf(q.data(), q.data() + M::kNq), phif(phi.data(), phi.data() + M::kNphi);
  VecQ qd, qdd;
  for (int j = 0; j < M::kNq; ++j) qd(j) = 1.25 - 0.5 * j, qdd(j) = -0.75 + 0.25 * j;
  const std::vector<double> qdf(qd.data(), qd.data() + M::kNq), qddf(qdd.data(), qdd.data() + M::kNq);
  const double t = 0.375;
  const ViewLayout& coeff_layout = v.Layout(ViewStruct::kCoefficients);

  // Phi, Phi_phi, Phi_q; and Phi alone (the others nullptr).
  {
    Eigen::Matrix<double, M::kNc, 1> Phi;
    Eigen::Matrix<double, M::kNc, M::kNphi> Phi_phi;
    Eigen::Matrix<double, M::kNc, M::kNq> Phi_q;
    M::Phi(params, q, phi, &Phi, &Phi_phi, &Phi_q);
    std::vector<double> a(M::kNc), b(M::kNc * M::kNphi), c(M::kNc * M::kNq), alone(M::kNc);
    v.Phi(p.data(), qf.data(), phif.data(), a.data(), b.data(), c.data());
    ExpectFlat(a, Phi, "Phi");
    ExpectFlat(b, Phi_phi, "Phi_phi");
    ExpectFlat(c, Phi_q, "Phi_q");
    v.Phi(p.data(), qf.data(), phif.data(), alone.data(), nullptr, nullptr);
    ExpectFlat(alone, Phi, "Phi alone");
    double det = 0, det_view = 0;
    M::DetPhiPhi(params, q, phi, &det);
    v.DetPhiPhi(p.data(), qf.data(), phif.data(), &det_view);
    EXPECT_EQ(Bits(det_view), Bits(det)) << "DetPhiPhi";
  }
  // Solve from a guess off the solution (so that Newton blocks iterate), with trig.
  using Trig = typename M::template TrigT<double>;
  VecPhi guess = phi;
  for (int i = 0; i < M::kNphi; ++i) guess(i) += 1e-3 * (i % 3 - 1);
  std::vector<double> trig_view = Buffer(v, ViewStruct::kTrig, kFill);
  Trig trig = Filled<M, Trig>();
  if constexpr (M::kHasSolve) {
    VecPhi solved = guess;
    const auto report = M::Solve(params, q, &solved, M::kDefaultModes, 20, 0.0, &trig);
    std::vector<double> solved_view(guess.data(), guess.data() + M::kNphi);
    const mechgen::ViewSolveReport r =
        v.Solve(p.data(), qf.data(), solved_view.data(), M::kDefaultModes.data(), 20, 0.0, trig_view.data());
    ExpectSameReport(r, report, "Solve");
    ExpectFlat(solved_view, solved, "Solve: phi");
    const ViewLayout& tl = v.Layout(ViewStruct::kTrig);
    ExpectMember(tl, trig_view, "sin_q", Unwritten0(trig.sin_q));
    ExpectMember(tl, trig_view, "cos_q", Unwritten0(trig.cos_q));
    ExpectMember(tl, trig_view, "sin_phi", Unwritten0(trig.sin_phi));
    ExpectMember(tl, trig_view, "cos_phi", Unwritten0(trig.cos_phi));
    // Without trig, and with few iterations and a tolerance.
    VecPhi again = guess;
    std::vector<double> again_view(guess.data(), guess.data() + M::kNphi);
    const auto report2 = M::Solve(params, q, &again, M::kDefaultModes, 2, 1e-9, nullptr);
    const mechgen::ViewSolveReport r2 =
        v.Solve(p.data(), qf.data(), again_view.data(), M::kDefaultModes.data(), 2, 1e-9, nullptr);
    ExpectSameReport(r2, report2, "Solve (2 iterations)");
    ExpectFlat(again_view, again, "Solve (2 iterations): phi");
  }
  // Coeffs, without trig and with Solve's.
  Coefficients coeffs = Filled<M, Coefficients>();
  std::vector<double> coeffs_view = Buffer(v, ViewStruct::kCoefficients, kFill);
  for (int with_trig = 0; with_trig < 2; ++with_trig) {
    if (with_trig && !M::kHasTrig) continue;
    coeffs = Filled<M, Coefficients>();
    coeffs_view = Buffer(v, ViewStruct::kCoefficients, kFill);
    if constexpr (M::kHasTrig) {
      M::Coeffs(params, q, phi, &coeffs, with_trig ? &trig : nullptr);
    } else {
      M::Coeffs(params, q, phi, &coeffs);
    }
    v.Coeffs(p.data(), qf.data(), phif.data(), coeffs_view.data(), with_trig ? trig_view.data() : nullptr);
    SCOPED_TRACE(with_trig ? "Coeffs with trig" : "Coeffs");
    ExpectMember(coeff_layout, coeffs_view, "Phi", coeffs.Phi);
    ExpectMember(coeff_layout, coeffs_view, "Phi_phi", coeffs.Phi_phi);
    if constexpr (M::kHasK) ExpectMember(coeff_layout, coeffs_view, "K", coeffs.K);
    if constexpr (M::kHasL) ExpectMember(coeff_layout, coeffs_view, "L", coeffs.L);
    if constexpr (M::kHasPoints) ExpectMember(coeff_layout, coeffs_view, "r_P", coeffs.r_P);
    if constexpr (M::kHasPointVelocities) ExpectMember(coeff_layout, coeffs_view, "K_P", coeffs.K_P);
    if constexpr (M::kHasPointAccelerations) ExpectMember(coeff_layout, coeffs_view, "L_P", coeffs.L_P);
  }
  if constexpr (M::kHasSolveTrig) {
    Trig st = Filled<M, Trig>();
    std::vector<double> st_view = Buffer(v, ViewStruct::kTrig, kFill);
    const auto report = M::SolveTrig(params, q, M::kDefaultModes, &st);
    const mechgen::ViewSolveReport r = v.SolveTrig(p.data(), qf.data(), M::kDefaultModes.data(), st_view.data());
    ExpectSameReport(r, report, "SolveTrig");
    const ViewLayout& tl = v.Layout(ViewStruct::kTrig);
    ExpectMember(tl, st_view, "sin_q", Unwritten0(st.sin_q));
    ExpectMember(tl, st_view, "cos_q", Unwritten0(st.cos_q));
    ExpectMember(tl, st_view, "sin_phi", Unwritten0(st.sin_phi));
    ExpectMember(tl, st_view, "cos_phi", Unwritten0(st.cos_phi));
  }
  if constexpr (M::kHasKinematics) {
    using K = typename M::template KinematicsT<double>;
    Trig st = Filled<M, Trig>();
    K out = Filled<M, K>();
    std::vector<double> st_view = Buffer(v, ViewStruct::kTrig, kFill),
                        out_view = Buffer(v, ViewStruct::kKinematics, kFill);
    const auto report = M::Kinematics(params, q, M::kDefaultModes, &st, &out);
    const mechgen::ViewSolveReport r =
        v.Kinematics(p.data(), qf.data(), M::kDefaultModes.data(), st_view.data(), out_view.data());
    ExpectSameReport(r, report, "Kinematics");
    const ViewLayout& l = v.Layout(ViewStruct::kKinematics);
    ExpectMember(v.Layout(ViewStruct::kTrig), st_view, "sin_phi", st.sin_phi);
    ExpectMember(v.Layout(ViewStruct::kTrig), st_view, "cos_phi", st.cos_phi);
    ExpectMember(l, out_view, "K", out.K);
    if constexpr (M::kHasL) ExpectMember(l, out_view, "L", out.L);
    ExpectMember(l, out_view, "Phi_phi", out.Phi_phi);
  }
  if constexpr (M::kHasTransmissionAngles) {
    Eigen::Matrix<double, M::kNumTransmissionAngles, 1> mu;
    std::vector<double> mu_view(M::kNumTransmissionAngles);
    M::TransmissionAngles(params, q, phi, &mu);
    v.TransmissionAngles(p.data(), qf.data(), phif.data(), mu_view.data());
    ExpectFlat(mu_view, mu, "TransmissionAngles");
  }
  {
    Eigen::Matrix<double, 2, M::kNumScenePoints> r;
    std::vector<double> r_view(2 * M::kNumScenePoints);
    M::Scene(params, q, phi, &r);
    v.Scene(p.data(), qf.data(), phif.data(), r_view.data());
    ExpectFlat(r_view, r, "Scene");
  }
  if constexpr (M::kHasDrawing) {
    Eigen::Matrix<double, 3, M::kNumLinks> frames;
    Eigen::Matrix<double, M::kNumDrawValues, 1> values;
    std::vector<double> frames_view(3 * M::kNumLinks), values_view(M::kNumDrawValues);
    M::Drawing(params, q, phi, &frames, &values);
    v.Drawing(p.data(), qf.data(), phif.data(), frames_view.data(), values_view.data());
    ExpectFlat(frames_view, frames, "Drawing: frames");
    ExpectFlat(values_view, values, "Drawing: values");
  }
  if constexpr (M::kHasCamProfile && Has_kNumDrawJoints<M>::value) {
    int cams = 0;
    for (int j = 0; j < M::kNumDrawJoints; ++j) {
      if (M::kDrawJointKind[j] != 5) continue;  // a cam joint (index into the model's joints)
      ++cams;
      for (double x : {0.25, 0.625}) {
        Eigen::Matrix<double, 2, 1> r;
        std::vector<double> r_view(2);
        M::CamProfile(params, j, x, &r);
        v.CamProfile(p.data(), j, x, r_view.data());
        ExpectFlat(r_view, r, "CamProfile");
      }
    }
    EXPECT_GT(cams, 0);
  }
  if constexpr (M::kHasAppliedLoads) {
    Eigen::Matrix<double, 7, M::kNumAppliedLoads> out;
    std::vector<double> out_view(7 * M::kNumAppliedLoads);
    M::AppliedLoads(params, q, phi, &out);
    v.AppliedLoads(p.data(), qf.data(), phif.data(), out_view.data());
    ExpectFlat(out_view, out, "AppliedLoads");
  }
  // The friction loads the statics and dynamics take (none where the model has no friction).
  std::vector<double> friction_view;
  Eigen::Matrix<double, Eigen::Dynamic, 1> friction_dyn;
  if constexpr (Has_kReactionNames<M>::value) {
    friction_dyn.resize(M::kNumFriction);
    for (int i = 0; i < M::kNumFriction; ++i) friction_dyn(i) = 0.5 + 0.25 * i;
    friction_view = Vector<M>(friction_dyn);
  }
  if constexpr (M::kHasStatics) {
    using S = typename M::template StaticsT<double>;
    const Eigen::Matrix<double, M::kNumFriction, 1> friction = friction_dyn;
    const bool with_friction = M::kNumFriction > 0;
    const ViewLayout& l = v.Layout(ViewStruct::kStatics);
    auto compare = [&l](const std::vector<double>& flat, const S& s) {
      if constexpr (M::kHasStaticsQ) {
        ExpectMember(l, flat, "Q", s.Q);
        ExpectMember(l, flat, "drive", s.drive);
      }
      if constexpr (M::kHasStaticsStiffness) ExpectMember(l, flat, "stiffness", s.stiffness);
      if constexpr (M::kHasStaticsV) {
        ExpectMember(l, flat, "V", s.V);
        ExpectMember(l, flat, "dV_dq", s.dV_dq);
      }
      if constexpr (M::kHasStaticsD2V) ExpectMember(l, flat, "d2V_dq2", s.d2V_dq2);
      if constexpr (M::kHasStaticsR) ExpectMember(l, flat, "R", s.R);
      if constexpr (M::kHasStaticsFriction) {
        ExpectMember(l, flat, "normal", s.normal);
        ExpectMember(l, flat, "gain", s.gain);
        ExpectMember(l, flat, "K_rel", s.K_rel);
      }
    };
    S s = Filled<M, S>();
    std::vector<double> s_view = Buffer(v, ViewStruct::kStatics, kFill);
    // A model whose statics read a velocity (kStaticsAtSpeed) takes them at qd, and its view
    // too; the others' views ignore the velocities.
    if constexpr (Has_kStaticsAtSpeed<M>::value) {
      M::Forces(params, q, phi, coeffs, &s, with_friction ? &friction : nullptr, M::kHasTrig ? &trig : nullptr, &qd);
    } else if constexpr (M::kHasTrig) {
      M::Forces(params, q, phi, coeffs, &s, with_friction ? &friction : nullptr, &trig);
    } else {
      M::Forces(params, q, phi, coeffs, &s, with_friction ? &friction : nullptr);
    }
    v.Forces(p.data(), qf.data(), phif.data(), coeffs_view.data(), s_view.data(),
             with_friction ? friction_view.data() : nullptr, M::kHasTrig ? trig_view.data() : nullptr, qdf.data());
    {
      SCOPED_TRACE("Forces");
      compare(s_view, s);
    }
    if constexpr (Has_kStaticsAtSpeed<M>::value) {
      EXPECT_EQ(v.num_statics_at_speed, M::kNumStaticsAtSpeed);
      for (int i = 0; i < M::kNumStaticsAtSpeed; ++i) EXPECT_STREQ(v.statics_at_speed[i], M::kStaticsAtSpeed[static_cast<size_t>(i)]);
    } else {
      EXPECT_EQ(v.num_statics_at_speed, 0);
    }
    if constexpr (HasFn_Stiffness<M>::value) {
      M::Stiffness(params, q, phi, coeffs, &s);
      v.Stiffness(p.data(), qf.data(), phif.data(), coeffs_view.data(), s_view.data());
      SCOPED_TRACE("Stiffness after Forces");
      compare(s_view, s);
    }
    if constexpr (M::kHasDynamics) {
      S k = Filled<M, S>();
      std::vector<double> k_view = Buffer(v, ViewStruct::kStatics, kFill);
      if constexpr (M::kHasTrig) {
        M::Kinetostatics(params, q, phi, qd, qdd, t, coeffs, &k, with_friction ? &friction : nullptr, &trig);
      } else {
        M::Kinetostatics(params, q, phi, qd, qdd, t, coeffs, &k, with_friction ? &friction : nullptr);
      }
      v.Kinetostatics(p.data(), qf.data(), phif.data(), qdf.data(), qddf.data(), t, coeffs_view.data(), k_view.data(),
                      with_friction ? friction_view.data() : nullptr, M::kHasTrig ? trig_view.data() : nullptr);
      SCOPED_TRACE("Kinetostatics");
      compare(k_view, k);
    }
  }
  if constexpr (M::kHasDynamics) {
    using D = typename M::template DynamicsT<double>;
    const Eigen::Matrix<double, M::kNumFriction, 1> friction = friction_dyn;
    const bool with_friction = M::kNumFriction > 0;
    D d = Filled<M, D>();
    std::vector<double> d_view = Buffer(v, ViewStruct::kDynamics, kFill);
    if constexpr (M::kHasTrig) {
      M::Dynamics(params, q, phi, qd, t, coeffs, &d, with_friction ? &friction : nullptr, &trig);
    } else {
      M::Dynamics(params, q, phi, qd, t, coeffs, &d, with_friction ? &friction : nullptr);
    }
    v.Dynamics(p.data(), qf.data(), phif.data(), qdf.data(), t, coeffs_view.data(), d_view.data(),
               with_friction ? friction_view.data() : nullptr, M::kHasTrig ? trig_view.data() : nullptr);
    const ViewLayout& l = v.Layout(ViewStruct::kDynamics);
    SCOPED_TRACE("Dynamics");
    ExpectMember(l, d_view, "I", d.I);
    ExpectMember(l, d_view, "dI_dq", d.dI_dq);
    ExpectMember(l, d_view, "C", d.C);
    ExpectMember(l, d_view, "h", d.h);
    ExpectMember(l, d_view, "Q", d.Q);
    ExpectMember(l, d_view, "T", d.T);
    ExpectMember(l, d_view, "V", d.V);
    ExpectMember(l, d_view, "P_nc", d.P_nc);
  }
  if constexpr (M::kHasExcess) {
    using E = typename M::template ExcessT<double>;
    const Eigen::Matrix<double, M::kNumFriction, 1> friction = friction_dyn;
    const bool with_friction = M::kNumFriction > 0;
    VecPhi phid;
    for (int i = 0; i < M::kNphi; ++i) phid(i) = 0.5 - 0.125 * i;
    const std::vector<double> phidf(phid.data(), phid.data() + M::kNphi);
    E e = Filled<M, E>();
    std::vector<double> e_view = Buffer(v, ViewStruct::kExcess, kFill);
    M::ExcessDynamics(params, q, phi, qd, phid, t, &e, with_friction ? &friction : nullptr);
    v.ExcessDynamics(p.data(), qf.data(), phif.data(), qdf.data(), phidf.data(), t, e_view.data(),
                     with_friction ? friction_view.data() : nullptr);
    const ViewLayout& l = v.Layout(ViewStruct::kExcess);
    SCOPED_TRACE("ExcessDynamics");
    ExpectMember(l, e_view, "M", e.M);
    ExpectMember(l, e_view, "h", e.h);
    ExpectMember(l, e_view, "g", e.g);
    ExpectMember(l, e_view, "Phi_x", e.Phi_x);
    ExpectMember(l, e_view, "Phi", e.Phi);
    ExpectMember(l, e_view, "gamma", e.gamma);
    ExpectMember(l, e_view, "T", e.T);
    ExpectMember(l, e_view, "V", e.V);
  }
  if constexpr (M::kHasShaking) {
    using Sh = typename M::template ShakingT<double>;
    Sh s = Filled<M, Sh>();
    std::vector<double> s_view = Buffer(v, ViewStruct::kShaking, kFill);
    if constexpr (M::kHasTrig) {
      M::Shaking(params, q, phi, qd, qdd, coeffs, &s, &trig);
    } else {
      M::Shaking(params, q, phi, qd, qdd, coeffs, &s);
    }
    v.Shaking(p.data(), qf.data(), phif.data(), qdf.data(), qddf.data(), coeffs_view.data(), s_view.data(),
              M::kHasTrig ? trig_view.data() : nullptr);
    const ViewLayout& l = v.Layout(ViewStruct::kShaking);
    SCOPED_TRACE("Shaking");
    ExpectMember(l, s_view, "F", s.F);
    ExpectMember(l, s_view, "M", s.M);
    ExpectMember(l, s_view, "F_link", s.F_link);
    ExpectMember(l, s_view, "M_link", s.M_link);
    ExpectMember(l, s_view, "r_G", s.r_G);
    ExpectMember(l, s_view, "mass", s.mass);
    ExpectMember(l, s_view, "r_C", s.r_C);
  }
  if constexpr (M::kHasSwitchModes) {
    std::array<int, M::kNumSwitches> modes;
    modes.fill(7);
    std::vector<int> modes_view(M::kNumSwitches, 7);
    M::SwitchModes(params, q, phi, qd, t, coeffs, &modes);
    v.SwitchModes(p.data(), qf.data(), phif.data(), qdf.data(), t, coeffs_view.data(), modes_view.data());
    for (int i = 0; i < M::kNumSwitches; ++i) EXPECT_EQ(modes_view[i], modes[i]) << "SwitchModes " << i;
  }
  if constexpr (M::kHasRhs) {
    using RC = typename M::template RhsConstantsT<double>;
    using R = typename M::template RhsT<double>;
    RC rc = Filled<M, RC>();
    std::vector<double> rc_view = Buffer(v, ViewStruct::kRhsConstants, kFill);
    M::Prepare(params, &rc);
    v.Prepare(p.data(), rc_view.data());
    ExpectMember(v.Layout(ViewStruct::kRhsConstants), rc_view, "c", rc.c);
    Trig st = Filled<M, Trig>();
    R out = Filled<M, R>();
    std::vector<double> st_view = Buffer(v, ViewStruct::kTrig, kFill), out_view = Buffer(v, ViewStruct::kRhs, kFill);
    const Eigen::Matrix<double, M::kNumFriction, 1> friction = friction_dyn;
    const bool with_friction = M::kNumFriction > 0;
    const auto report = M::Rhs(params, rc, q, qd, t, M::kDefaultModes, &st, &out, with_friction ? &friction : nullptr);
    const mechgen::ViewSolveReport r =
        v.Rhs(p.data(), rc_view.data(), qf.data(), qdf.data(), t, M::kDefaultModes.data(), st_view.data(),
              out_view.data(), with_friction ? friction_view.data() : nullptr);
    ExpectSameReport(r, report, "Rhs");
    const ViewLayout& l = v.Layout(ViewStruct::kRhs);
    SCOPED_TRACE("Rhs");
    ExpectMember(v.Layout(ViewStruct::kTrig), st_view, "sin_phi", st.sin_phi);
    ExpectMember(l, out_view, "K", out.K);
    ExpectMember(l, out_view, "I", out.I);
    ExpectMember(l, out_view, "h", out.h);
    ExpectMember(l, out_view, "Q", out.Q);
    ExpectMember(l, out_view, "T", out.T);
    ExpectMember(l, out_view, "V", out.V);
    ExpectMember(l, out_view, "P_nc", out.P_nc);
    ExpectMember(l, out_view, "Phi_phi", out.Phi_phi);
  }
  if constexpr (HasFn_DesignChecks<M>::value) {
    Eigen::Matrix<double, M::kNumDesignChecks, 1> margin;
    Eigen::Matrix<double, M::kNumDesignChecks, M::kNumDesign> dmargin;
    std::vector<double> margin_view(M::kNumDesignChecks), dmargin_view(M::kNumDesignChecks * M::kNumDesign);
    M::DesignChecks(params, &margin, &dmargin);
    v.DesignChecks(p.data(), margin_view.data(), dmargin_view.data());
    ExpectFlat(margin_view, margin, "DesignChecks: margin");
    ExpectFlat(dmargin_view, dmargin, "DesignChecks: dmargin_dp");
  }
  if constexpr (M::kHasDesignDerivatives) {
    using DD = typename M::template DesignDerivativesT<double>;
    DD dd = Filled<M, DD>();
    std::vector<double> dd_view = Buffer(v, ViewStruct::kDesignDerivatives, kFill);
    M::Design(params, q, phi, &dd);
    v.Design(p.data(), qf.data(), phif.data(), dd_view.data());
    const ViewLayout& l = v.Layout(ViewStruct::kDesignDerivatives);
    {
      SCOPED_TRACE("Design");
      // The members the header has (their own presence follows the sizes: codegen/output_spec.cc).
      for (int i = 0; i < l.num_members; ++i) EXPECT_NE(l.members[i].name, nullptr);
      ExpectMember(l, dd_view, "dphi_dp", dd.dphi_dp);
      if constexpr (M::kNumPoints > 0) ExpectMember(l, dd_view, "dr_P_dp", dd.dr_P_dp);
      if constexpr (M::kHasK) ExpectMember(l, dd_view, "dK_dp", dd.dK_dp);
      if constexpr (M::kHasL) ExpectMember(l, dd_view, "dL_dp", dd.dL_dp);
      if constexpr (M::kHasK && M::kNumPoints > 0) ExpectMember(l, dd_view, "dK_P_dp", dd.dK_P_dp);
      if constexpr (M::kHasL && M::kNumPoints > 0) ExpectMember(l, dd_view, "dL_P_dp", dd.dL_P_dp);
      if constexpr (M::kHasTransmissionAngles) ExpectMember(l, dd_view, "dmu_dp", dd.dmu_dp);
    }
    if constexpr (M::kHasStaticsDesign) {
      using SD = typename M::template StaticsDesignT<double>;
      SD sd = Filled<M, SD>();
      std::vector<double> sd_view = Buffer(v, ViewStruct::kStaticsDesign, kFill);
      M::StaticsDesign(params, q, phi, coeffs, dd, &sd);
      v.StaticsDesign(p.data(), qf.data(), phif.data(), coeffs_view.data(), dd_view.data(), sd_view.data());
      const ViewLayout& sl = v.Layout(ViewStruct::kStaticsDesign);
      SCOPED_TRACE("StaticsDesign");
      if constexpr (M::kHasStaticsQ) {
        ExpectMember(sl, sd_view, "dQ_dp", sd.dQ_dp);
        ExpectMember(sl, sd_view, "ddrive_dp", sd.ddrive_dp);
      }
      if constexpr (M::kHasStaticsV) ExpectMember(sl, sd_view, "dV_dp", sd.dV_dp);
      if constexpr (M::kHasStaticsR) ExpectMember(sl, sd_view, "dR_dp", sd.dR_dp);
    }
    if constexpr (M::kHasDynamicsDesign) {
      using DyD = typename M::template DynamicsDesignT<double>;
      const Eigen::Matrix<double, M::kNumFriction, 1> friction = friction_dyn;
      const bool with_friction = M::kNumFriction > 0;
      DyD dy = Filled<M, DyD>();
      std::vector<double> dy_view = Buffer(v, ViewStruct::kDynamicsDesign, kFill);
      M::DynamicsDesign(params, q, phi, qd, t, coeffs, dd, &dy, with_friction ? &friction : nullptr);
      v.DynamicsDesign(p.data(), qf.data(), phif.data(), qdf.data(), t, coeffs_view.data(), dd_view.data(),
                       dy_view.data(), with_friction ? friction_view.data() : nullptr);
      const ViewLayout& dl = v.Layout(ViewStruct::kDynamicsDesign);
      SCOPED_TRACE("DynamicsDesign");
      ExpectMember(dl, dy_view, "dI_dp", dy.dI_dp);
      ExpectMember(dl, dy_view, "ddI_dq_dp", dy.ddI_dq_dp);
      ExpectMember(dl, dy_view, "dh_dp", dy.dh_dp);
      ExpectMember(dl, dy_view, "dQ_dp", dy.dQ_dp);
      ExpectMember(dl, dy_view, "dT_dp", dy.dT_dp);
      ExpectMember(dl, dy_view, "dV_dp", dy.dV_dp);
    }
    if constexpr (HasFn_ShakingDesign<M>::value) {
      Eigen::Matrix<double, 2, M::kNumDesign> dF;
      Eigen::Matrix<double, M::kNumDesign, 1> dM;
      std::vector<double> dF_view(2 * M::kNumDesign), dM_view(M::kNumDesign);
      M::ShakingDesign(params, q, phi, qd, qdd, coeffs, dd, &dF, &dM);
      v.ShakingDesign(p.data(), qf.data(), phif.data(), qdf.data(), qddf.data(), coeffs_view.data(), dd_view.data(),
                      dF_view.data(), dM_view.data());
      ExpectFlat(dF_view, dF, "ShakingDesign: dF_dp");
      ExpectFlat(dM_view, dM, "ShakingDesign: dM_dp");
    }
  }
}

// Three configurations on the assembly branch (the assembly and two inputs through the
// range), at the defaults and at parameters scaled by up to 0.7e-4 each.
TYPED_TEST(ModelViewTest, EveryFunctionGivesTheFixedSizeFunctionsOutputsToTheBit) {
  using M = TypeParam;
  const ModelView& v = ViewOfModel<M>();
  Compared().clear();
  for (double perturb : {0.0, 1e-5}) {
    SCOPED_TRACE("parameters scaled by " + std::to_string(perturb) + " per index");
    std::vector<double> p;
    mechtest::ParamsD<M> params;
    Parameters<M>(v, perturb, &p, &params);
    bool ok = false;
    mechtest::Config<M> c = mechtest::SolvedAssembly<M>(params, &ok);
    ASSERT_TRUE(ok) << M::kName << ": the assembly configuration does not solve";
    std::vector<mechtest::Config<M>> configs = {c};
    for (double s : {0.3, 0.7}) {
      mechtest::VecQ<M> target;
      for (int j = 0; j < M::kNq; ++j) target(j) = M::kQMin[j] + s * (M::kQMax[j] - M::kQMin[j]);
      mechtest::Config<M> d = c;
      if (mechtest::Track<M>(params, target, &d)) configs.push_back(d);
    }
    EXPECT_GE(configs.size(), 2u);
    for (size_t i = 0; i < configs.size(); ++i) {
      SCOPED_TRACE("configuration " + std::to_string(i));
      CompareAt<M>(v, p, params, configs[i]);
    }
  }
  // Every member of every struct the model has was compared.
  for (const ViewLayout& l : v.structs)
    for (int i = 0; i < l.num_members; ++i)
      EXPECT_EQ(Compared().count({l.name, l.members[i].name}), 1u)
          << l.name << "::" << l.members[i].name << " was not compared";
}

// The view's parameters at their defaults (and Params alike), the assembly configuration and
// input speeds of 0.625 each, as flat arrays; ok false where the assembly does not solve.
template <class M>
struct AtAssembly {
  explicit AtAssembly(const ModelView& v) {
    Parameters<M>(v, 0.0, &p, &params);
    const mechtest::Config<M> config = mechtest::SolvedAssembly<M>(params, &ok);
    q.assign(config.q.data(), config.q.data() + M::kNq);
    phi.assign(config.phi.data(), config.phi.data() + M::kNphi);
    qd.assign(static_cast<size_t>(M::kNq), 0.625);
  }
  std::vector<double> p;
  mechtest::ParamsD<M> params;
  bool ok = false;
  std::vector<double> q, phi, qd;
};

// ModelView::StaticsChecks states the rule of the fixed-size statics' checks again, in the
// generated code (codegen/emit.cc): which members statics::internal::AllFinite reads, and max |R|
// (statics::Solve's reaction_norm). On the buffer Forces fills at the assembly, with a NaN, then
// +inf, then -inf put in each entry in turn, the view's verdict and max |R| are those of the
// fixed-size path's own checks (statics::internal::AllFinite and MaxAbs on the generated struct
// holding the same entries), to the bit; and ForcesChecked writes what Forces writes and returns
// StaticsChecks of it.
TYPED_TEST(ModelViewTest, StaticsChecksAreTheFixedSizeStaticsChecks) {
  using M = TypeParam;
  const ModelView& v = ViewOfModel<M>();
  EXPECT_EQ(v.StaticsChecks != nullptr, v.Forces != nullptr);
  EXPECT_EQ(v.ForcesChecked != nullptr, v.Forces != nullptr);
  if constexpr (M::kHasStatics) {
    ASSERT_NE(v.ForcesChecked, nullptr);
    using S = typename M::template StaticsT<double>;
    const AtAssembly<M> at(v);
    ASSERT_TRUE(at.ok) << M::kName << ": the assembly configuration does not solve";
    const std::vector<double> friction(static_cast<size_t>(v.num_friction), 0.375);
    const double* const f = v.num_friction > 0 ? friction.data() : nullptr;
    std::vector<double> c = Buffer(v, ViewStruct::kCoefficients, kFill);
    v.Coeffs(at.p.data(), at.q.data(), at.phi.data(), c.data(), nullptr);
    std::vector<double> forces = Buffer(v, ViewStruct::kStatics, kFill), checked = forces;
    v.Forces(at.p.data(), at.q.data(), at.phi.data(), c.data(), forces.data(), f, nullptr, at.qd.data());
    double norm = kFill, norm_alone = kFill;
    const bool finite =
        v.ForcesChecked(at.p.data(), at.q.data(), at.phi.data(), c.data(), checked.data(), f, nullptr,
                        at.qd.data(), &norm);
    for (size_t i = 0; i < forces.size(); ++i)
      EXPECT_EQ(Bits(checked[i]), Bits(forces[i])) << "ForcesChecked [" << i << "]";
    EXPECT_TRUE(finite) << "the statics at the assembly";
    EXPECT_EQ(v.StaticsChecks(forces.data(), &norm_alone), finite);
    EXPECT_EQ(Bits(norm), Bits(norm_alone));
    EXPECT_TRUE(v.StaticsChecks(forces.data(), nullptr));

    // The fixed-size path's checks of the struct holding the buffer's entries.
    const ViewLayout& l = v.Layout(ViewStruct::kStatics);
    auto fixed = [&l](const std::vector<double>& flat, double* reaction_norm) {
      S s = Filled<M, S>();
      if constexpr (M::kHasStaticsQ) {
        GetMember(l, flat, "Q", &s.Q);
        GetMember(l, flat, "drive", &s.drive);
      }
      if constexpr (M::kHasStaticsStiffness) GetMember(l, flat, "stiffness", &s.stiffness);
      if constexpr (M::kHasStaticsV) {
        GetMember(l, flat, "V", &s.V);
        GetMember(l, flat, "dV_dq", &s.dV_dq);
      }
      if constexpr (M::kHasStaticsD2V) GetMember(l, flat, "d2V_dq2", &s.d2V_dq2);
      if constexpr (M::kHasStaticsR) GetMember(l, flat, "R", &s.R);
      if constexpr (M::kHasStaticsFriction) {
        GetMember(l, flat, "normal", &s.normal);
        GetMember(l, flat, "gain", &s.gain);
        GetMember(l, flat, "K_rel", &s.K_rel);
      }
      *reaction_norm = kFill;  // (statics::Solve: written with reactions only)
      if constexpr (mechgen::statics::StaticsFeatures<M>::kHasReactions)
        if (mechgen::ModelCalls<M>::HasReactions(M())) *reaction_norm = mechgen::statics::internal::MaxAbs(s.R);
      return mechgen::statics::internal::AllFinite<M>(M(), s);
    };
    double norm_fixed = 0;
    EXPECT_TRUE(fixed(forces, &norm_fixed));
    EXPECT_EQ(Bits(norm_alone), Bits(norm_fixed));
    int rejected = 0;
    for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                       -std::numeric_limits<double>::infinity()}) {
      for (size_t i = 0; i < forces.size(); ++i) {
        std::vector<double> b = forces;
        b[i] = bad;
        double norm_view = kFill;
        const bool expected = fixed(b, &norm_fixed);
        const bool got = v.StaticsChecks(b.data(), &norm_view);
        EXPECT_EQ(got, expected) << "entry " << i << " = " << bad;
        EXPECT_EQ(Bits(norm_view), Bits(norm_fixed)) << "entry " << i << " = " << bad << ": view " << norm_view
                                                     << ", fixed " << norm_fixed;
        rejected += got ? 0 : 1;
      }
    }
    // (At least Q and drive, three times: a check that rejects something.)
    EXPECT_GE(rejected, 3 * 2 * M::kNq);
  }
}

// A struct's buffer aligned for the struct is taken as the struct itself (view_buffers.h,
// InPlace), one aligned less is copied in and out: the same bits either way. Solve (trig written
// whole), Coeffs, Forces (its output read in: what it does not write keeps the buffer's value)
// and Rhs, each on buffers at a 16-byte boundary and one double past it, both filled alike.
TYPED_TEST(ModelViewTest, BuffersInPlaceAndCopiedGiveTheSameBits) {
  using M = TypeParam;
  const ModelView& v = ViewOfModel<M>();
  const AtAssembly<M> at(v);
  ASSERT_TRUE(at.ok) << M::kName << ": the assembly configuration does not solve";
  // Each struct's buffer twice, from an aligned start (operator new: 16 bytes) and 8 bytes on.
  struct Pair {
    Pair(const ModelView& v, ViewStruct s) : n(static_cast<size_t>(v.Layout(s).size)), storage(2 * n + 1, kFill) {}
    double* aligned() { return storage.data(); }
    double* shifted() { return storage.data() + n + 1; }
    void Expect(const char* what) {
      ASSERT_EQ(reinterpret_cast<std::uintptr_t>(aligned()) % 16, 0u);
      for (size_t i = 0; i < n; ++i) EXPECT_EQ(Bits(aligned()[i]), Bits(shifted()[i])) << what << " [" << i << "]";
    }
    size_t n;
    std::vector<double> storage;
  };
  Pair trig(v, ViewStruct::kTrig), c(v, ViewStruct::kCoefficients);
  if constexpr (M::kHasSolve) {
    for (double* t : {trig.aligned(), trig.shifted()}) {
      std::vector<double> phi_io = at.phi;
      v.Solve(at.p.data(), at.q.data(), phi_io.data(), M::kDefaultModes.data(), 20, 0.0, t);
    }
    trig.Expect("Solve: trig");
  }
  v.Coeffs(at.p.data(), at.q.data(), at.phi.data(), c.aligned(), M::kHasTrig ? trig.aligned() : nullptr);
  v.Coeffs(at.p.data(), at.q.data(), at.phi.data(), c.shifted(), M::kHasTrig ? trig.shifted() : nullptr);
  c.Expect("Coeffs");
  if (v.Forces != nullptr) {
    Pair s(v, ViewStruct::kStatics);
    const std::vector<double> friction(static_cast<size_t>(v.num_friction), 0.375);
    for (int shifted = 0; shifted < 2; ++shifted) {
      v.Forces(at.p.data(), at.q.data(), at.phi.data(), shifted ? c.shifted() : c.aligned(),
               shifted ? s.shifted() : s.aligned(),
               v.num_friction > 0 ? friction.data() : nullptr, M::kHasTrig ? (shifted ? trig.shifted() : trig.aligned()) : nullptr,
               at.qd.data());
    }
    s.Expect("Forces");
  }
  if constexpr (M::kHasRhs) {
    Pair rc(v, ViewStruct::kRhsConstants), out(v, ViewStruct::kRhs), st(v, ViewStruct::kTrig);
    for (int shifted = 0; shifted < 2; ++shifted) {
      double* const rcb = shifted ? rc.shifted() : rc.aligned();
      v.Prepare(at.p.data(), rcb);
      v.Rhs(at.p.data(), rcb, at.q.data(), at.qd.data(), 0.25, M::kDefaultModes.data(),
            shifted ? st.shifted() : st.aligned(), shifted ? out.shifted() : out.aligned(), nullptr);
    }
    rc.Expect("Prepare");
    st.Expect("Rhs: trig");
    out.Expect("Rhs");
  }
}

// SizedViewModel<1, 2> (core/view_sized.h), the runtime instantiated for the four-bars and
// slider-cranks: every model of one input and two dependent coordinates whose coefficients have
// Phi, Phi_phi, K and L runs on it (Fits: its plain SizedCoefficients has the generated struct's
// layout, the points after L), no model of another shape does; and its Coeffs, written in place,
// and StaticsCoefficients from a state give the view's Coeffs' buffer to the bit (which
// EveryFunctionGivesTheFixedSizeFunctionsOutputsToTheBit holds to the fixed-size M::Coeffs).
// (The sized calls in one function, not one per model: compiled once.)
void ExpectSizedCoefficients(const ModelView& v, const std::vector<double>& p_in, const std::vector<double>& q_in,
                             const std::vector<double>& phi_in) {
  using Sized = mechgen::SizedViewModel<1, 2>;
  using SizedCalls = mechgen::ModelCalls<Sized>;
  using Types = mechgen::ModelTypes<Sized>;
  const Sized sized{mechgen::ViewModel(v)};
  mechgen::ViewParams p;
  std::copy(p_in.begin(), p_in.end(), p.values.begin());
  const Types::VecQ q = Eigen::Map<const Types::VecQ>(q_in.data());
  const Types::VecPhi phi = Eigen::Map<const Types::VecPhi>(phi_in.data());
  std::vector<double> expected = Buffer(v, ViewStruct::kCoefficients, kFill);
  v.Coeffs(p.data(), q.data(), phi.data(), expected.data(), nullptr);
  const ViewLayout& layout = v.Layout(ViewStruct::kCoefficients);
  auto expect = [&layout, &expected](const char* name, const auto& x, const std::string& how, bool zero = false) {
    const mechgen::ViewMember* m = mechgen::FindMember(layout, name);
    if (m == nullptr) return;
    ASSERT_EQ(x.rows(), m->rows) << how << name;
    ASSERT_EQ(x.cols(), m->cols) << how << name;
    for (int j = 0; j < m->cols; ++j)
      for (int i = 0; i < m->rows; ++i)
        EXPECT_EQ(Bits(x(i, j)), Bits(zero ? 0.0 : expected[static_cast<size_t>(m->offset + i + m->rows * j)]))
            << how << name << "(" << i << ", " << j << ")";
  };
  auto expect_all = [&expect](const Types::Coefficients& c, const std::string& how) {
    expect("Phi_phi", c.Phi_phi, how);
    expect("K", c.K, how);
    expect("L", c.L, how);
    expect("r_P", c.r_P, how);
    expect("K_P", c.K_P, how);
    expect("L_P", c.L_P, how);
  };
  Types::Coefficients c;
  c.points.fill(kFill);
  SizedCalls::Coeffs(sized, p, q, phi, &c);
  expect("Phi", c.Phi, "Coeffs: ");
  expect_all(c, "Coeffs: ");
  // From the coefficients a position state holds (Phi 0: the state has none), as the statics
  // row takes them (its CSV through the sized view against the ViewModel's: tests/runtime,
  // ViewStaticsTool.SizedRuntimeSameAsAnyShape).
  struct FromState {
    Types::MatCPhi Phi_phi;
    Types::MatK K;
    Types::MatL L;
    Types::MatRP r_P;
    Types::MatKP K_P;
    Types::MatLP L_P;
  } state{c.Phi_phi, c.K, c.L, c.r_P, c.K_P, c.L_P};
  Types::Coefficients from_state;
  from_state.points.fill(kFill);
  SizedCalls::StaticsCoefficients(sized, state, &from_state);
  expect("Phi", from_state.Phi, "StaticsCoefficients: ", true);
  expect_all(from_state, "StaticsCoefficients: ");
}
TYPED_TEST(ModelViewTest, SizedViewFitsItsShapeAndGivesTheFixedSizeCoefficients) {
  using M = TypeParam;
  const ModelView& v = ViewOfModel<M>();
  const bool shape = M::kNq == 1 && M::kNphi == 2 && M::kNc == 2;
  const bool fits = mechgen::SizedViewModel<1, 2>::Fits(mechgen::ViewModel(v));
  EXPECT_EQ(fits, shape && M::kHasK && M::kHasL && M::kHasCoeffsPhi) << M::kName;
  if (!fits) return;
  const AtAssembly<M> at(v);
  ASSERT_TRUE(at.ok) << M::kName << ": the assembly configuration does not solve";
  ExpectSizedCoefficients(v, at.p, at.q, at.phi);
}

// ModelCalls<ViewModel>::CopyTrig, what a simulation's right-hand side keeps of each stage's sin
// and cos (dynamics/forward.h, LastEvaluation): the model's entries of the view's Trig buffer and
// no more. After the view's Solve at the assembly, the copy's sin and cos of every phi as the
// dynamics read them (TrigSinPhi, TrigCosPhi) are the fixed-size M::Solve's, to the bit (0 where
// that writes none, as the view's Solve leaves them); every entry of the model's Trig struct is
// copied; the buffer past it keeps what the copy held.
TYPED_TEST(ModelViewTest, CopyTrigKeepsTheModelsSinAndCosOnly) {
  using M = TypeParam;
  if constexpr (M::kHasTrig && M::kHasSolve) {
    using Calls = mechgen::ModelCalls<mechgen::ViewModel>;
    const ModelView& v = ViewOfModel<M>();
    const mechgen::ViewModel model(v);
    const AtAssembly<M> at(v);
    ASSERT_TRUE(at.ok) << M::kName << ": the assembly configuration does not solve";
    typename M::template TrigT<double> trig = Filled<M, typename M::template TrigT<double>>();
    mechtest::VecPhi<M> phi = Eigen::Map<const mechtest::VecPhi<M>>(at.phi.data());
    const mechtest::VecQ<M> q = Eigen::Map<const mechtest::VecQ<M>>(at.q.data());
    M::Solve(at.params, q, &phi, M::kDefaultModes, 20, 0.0, &trig);

    mechgen::internal::ViewTrig from, to;
    from.buffer.fill(kFill);
    to.buffer.fill(std::numeric_limits<double>::quiet_NaN());
    std::vector<double> phi_view = at.phi;
    v.Solve(at.p.data(), at.q.data(), phi_view.data(), M::kDefaultModes.data(), 20, 0.0, from.buffer.data());
    Calls::CopyTrig(model, from, &to);
    // (Unwritten0: 0 where the fixed-size solve writes nothing, a coordinate that is no angle.)
    const auto sin_phi = Unwritten0(trig.sin_phi), cos_phi = Unwritten0(trig.cos_phi);
    for (int i = 0; i < M::kNphi; ++i) {
      EXPECT_EQ(Bits(Calls::TrigSinPhi(model, to, i)), Bits(sin_phi(i))) << "sin_phi " << i;
      EXPECT_EQ(Bits(Calls::TrigCosPhi(model, to, i)), Bits(cos_phi(i))) << "cos_phi " << i;
    }
    const size_t size = static_cast<size_t>(v.Layout(ViewStruct::kTrig).size);
    ASSERT_LE(size, to.buffer.size());
    EXPECT_GE(size * sizeof(double), sizeof(trig)) << "the Trig struct's entries";
    for (size_t k = 0; k < to.buffer.size(); ++k) {
      if (k < size) {
        EXPECT_EQ(Bits(to.buffer[k]), Bits(from.buffer[k])) << "entry " << k;
      } else {
        EXPECT_TRUE(std::isnan(to.buffer[k])) << "entry " << k << " past the model's " << size;
      }
    }
  }
}

}  // namespace
