/**
 * \file core/model_view.h
 * The type-erased description of one generated model (issue 43): what a runtime compiled once,
 * before any model exists, reads of a model instead of its type M (core/model_traits.h).
 *
 * The generator emits it per model as <name>_view.cc (templates/mechanism_view.cc.mustache):
 * `const mechgen::ModelView& mech::<name>::View()`, and with MECHGEN_VIEW_ENTRY defined also
 * the C entry point kModelViewEntry for dlopen. The view holds
 *  - the model's sizes, names, constants and its 31 `kHas*` flags (ViewFlags), read from the
 *    generated header's Model;
 *  - the parameter table (ViewParameter): the free parameters, then the derived ones, with
 *    their defaults; FindParameter finds one by name, fill_derived computes the derived ones;
 *  - one function pointer per function of the generated Model (Phi, Coeffs, Solve, ...), and
 *    beside Forces the statics' reads of its results (StaticsChecks, ForcesChecked), generated,
 *    nullptr where the model lacks it (where its kHas* flag is false), on flat arrays of double:
 *    the parameters p in the table's order (the free ones are read, p[0, num_free_params)), q,
 *    phi, qd, ... as arrays of their sizes, every matrix column-major, and each struct
 *    (Coefficients, Trig, Statics, ...) as one buffer whose members ViewLayout describes (name,
 *    rows, cols, offset), so that a reader finds a member by its name (FindMember), never by its
 *    C++ spelling. Each function behaves as the generated one does on the structs its buffers
 *    hold: an output buffer is read in before the call, so what the function does not write
 *    keeps the buffer's value (Stiffness after Forces in one Statics buffer), and a buffer is to
 *    be initialized once before its first use; except the outputs written whole, whose buffer
 *    is neither read nor needs initializing: Coeffs' Coefficients and the trig of Solve and
 *    SolveTrig (0 for the displacements, whose sin and cos they do not compute). A pointer the
 *    generated function accepts as nullptr may be nullptr here.
 *
 * The generated functions stay as they are (fixed-size Eigen, templates on the scalar); the view
 * calls them for double on its arrays: a struct's buffer aligned for the struct (the runtime's
 * are: ViewModel's kViewBufferAlignment) is taken as the struct itself where the struct lies in
 * it member by member, with nothing copied in or out; the other arrays are copied into the
 * fixed-size types and the results out (the same arithmetic either way: the results agree to
 * the bit). Everything here is constant-initialized, allocates
 * nothing and needs the C++17 standard library only: no Eigen, so that a product or a program that
 * dlopens a model can read it.
 *
 * Maxima: a runtime compiled once bounds its state by the constants of ModelView (kMaxQ, ...).
 * Each view says whether its model fits them (fits_maxima); compiled with MECHGEN_VIEW_ENTRY (a
 * model for that runtime) it static_asserts it. They cover every model of this tree with a
 * margin (the largest figure in each comment), not the benchmarks' long chains, whose fixed-size
 * code and view (fits_maxima false) still compile into their libraries.
 */
#pragma once

#include <cstring>
#include <type_traits>

namespace mechgen {

/// Changes whenever ModelView's layout does: a view compiled against another layout is refused
/// (ModelView::layout, ModelView::size).
inline constexpr int kModelViewLayout = 4;

/// The C entry point of a model compiled with MECHGEN_VIEW_ENTRY (one fixed name: one model per
/// shared object; statically linked models are reached through mech::<name>::View()).
inline constexpr const char* kModelViewEntry = "mechgen_model_view";
struct ModelView;
using ModelViewEntry = const ModelView* (*)();

/// Why Solve (SolveTrig, Kinematics, Rhs) stopped: the generated SolveStatus, value for value.
enum class ViewSolveStatus : int { kConverged = 0, kNotAssemblable = 1, kDidNotConverge = 2, kSingular = 3 };

/// The generated SolveReport<double>, member for member (its documentation is in every
/// generated header).
struct ViewSolveReport {
  ViewSolveStatus status = ViewSolveStatus::kConverged;
  int block = -1;
  int iterations = 0;
  double measure = 0;
  double branch_measure = 1;
  int branch_block = -1;
};

/// The structs the functions exchange as flat buffers; the generated struct of the same name.
enum class ViewStruct : int {
  kCoefficients,  ///< Coeffs' output, the other functions' `c`
  kTrig,          ///< sin and cos of q and phi (Solve, SolveTrig, Coeffs, ...)
  kStatics,
  kDynamics,
  kExcess,
  kShaking,
  kKinematics,
  kRhs,
  kRhsConstants,
  kDesignDerivatives,
  kStaticsDesign,
  kDynamicsDesign,
  kCount
};

/// One member of a struct in its buffer: rows x cols doubles (a scalar 1 x 1), column-major,
/// from buffer[offset].
struct ViewMember {
  const char* name = nullptr;
  int rows = 0;
  int cols = 0;
  int offset = 0;
};

/// A struct's buffer: its size in doubles and its members in the generated struct's order, each
/// at its offset in the generated struct (the buffer is laid out as the struct is, padding
/// included, so that the view's functions may take it as the struct itself). A struct the model
/// lacks has name nullptr, size 0 and no members.
struct ViewLayout {
  const char* name = nullptr;
  int size = 0;
  int num_members = 0;
  const ViewMember* members = nullptr;
};

/// The member `name` of `layout`, or nullptr if the struct has no such member (a model that did
/// not ask for it: Statics::R without reactions, Coefficients::L at order 1).
inline const ViewMember* FindMember(const ViewLayout& layout, const char* name) {
  for (int i = 0; i < layout.num_members; ++i)
    if (std::strcmp(layout.members[i].name, name) == 0) return &layout.members[i];
  return nullptr;
}

/// A parameter of the model: its name as in the model file and its default. Derived parameters
/// (`derived:` in the model) follow the free ones; their defaults are their definitions at the
/// free parameters' defaults (evaluated exactly by the generator, then rounded), and
/// ModelView::fill_derived recomputes them from the free ones.
struct ViewParameter {
  const char* name = nullptr;
  double default_value = 0;
  bool derived = false;
};

/// The model's kHas* flags under their names in the generated Model (core/model_traits.h lists
/// what each says).
struct ViewFlags {
  bool kHasCoeffsPhi = false;
  bool kHasK = false;
  bool kHasL = false;
  bool kHasPoints = false;
  bool kHasPointVelocities = false;
  bool kHasPointAccelerations = false;
  bool kHasSolve = false;
  bool kHasNamedModes = false;
  bool kHasTrig = false;
  bool kHasSolveTrig = false;
  bool kHasTransmissionAngles = false;
  bool kHasSwitchModes = false;
  bool kHasDrawing = false;
  bool kHasCamProfile = false;
  bool kHasAppliedLoads = false;
  bool kHasStatics = false;
  bool kHasStaticsQ = false;
  bool kHasStaticsStiffness = false;
  bool kHasStaticsV = false;
  bool kHasStaticsD2V = false;
  bool kHasStaticsR = false;
  bool kHasStaticsFriction = false;
  bool kHasDynamics = false;
  bool kHasExcess = false;
  bool kHasShaking = false;
  bool kHasKinematics = false;
  bool kHasRhs = false;
  bool kHasRhsConstants = false;
  bool kHasDesignDerivatives = false;
  bool kHasStaticsDesign = false;
  bool kHasDynamicsDesign = false;
};

/// One generated model, type-erased. Arrays of names and values have the length of the size
/// that names them (q_names: nq; reaction_names: num_reactions; ...); a pointer to an empty
/// array may be nullptr.
struct ModelView {
  // ---- Maxima of a runtime compiled once (ModelView::fits_maxima; in the comments the largest
  //      figure of the models in this tree, shipped and tests': the benchmarks' chains of 32 and
  //      more loops exceed them) ----
  static constexpr int kMaxQ = 8;                   ///< inputs q (7: contacts; shipped 2)
  static constexpr int kMaxPhi = 48;                ///< dependent variables phi, rows of Phi (32: chain16)
  static constexpr int kMaxPoints = 64;             ///< points of interest (32: a Pyslvs example)
  static constexpr int kMaxLinks = 64;              ///< links with the ground (34: chain16)
  static constexpr int kMaxJoints = 64;             ///< joints (25: engine_v8)
  static constexpr int kMaxScenePoints = 128;       ///< scene points (42: engine_v8)
  static constexpr int kMaxBlocks = 32;             ///< blocks of the solve order (16: chain16)
  static constexpr int kMaxParams = 160;            ///< parameters, free and derived (54: engine_v8)
  static constexpr int kMaxReactions = 160;         ///< reaction components (65: contacts)
  static constexpr int kMaxFriction = 16;           ///< joints with Coulomb friction (4)
  static constexpr int kMaxSwitches = 16;           ///< switching items of the loads (4: punch_press)
  static constexpr int kMaxDesign = 32;             ///< design parameters (18)
  static constexpr int kMaxDesignChecks = 32;       ///< design checks (12: watt_sixbar)
  static constexpr int kMaxTransmissionAngles = 32; ///< transmission angles (16: chain16)
  static constexpr int kMaxDrawValues = 32;         ///< EvalDrawing's values (8: engine_v8)
  static constexpr int kMaxAppliedLoads = 32;       ///< applied loads, springs and weights (9: engine_v8)
  static constexpr int kMaxLoads = 32;              ///< the model's loads (9)
  static constexpr int kMaxNamedModes = 16;         ///< named assembly modes (2)
  static constexpr int kMaxChangePoints = 16;       ///< change points in the inputs' ranges (3)
  /// Doubles in each struct's buffer (ViewStruct order): every member at the maxima above where
  /// that stays small, else about four times the largest buffer in the tree (in the comment; at
  /// the maxima above DesignDerivatives alone would take 3.3 MB).
  static constexpr int kMaxStructSize[static_cast<int>(ViewStruct::kCount)] = {
      4096,                          // Coefficients (1,126: chain16)
      2 * (kMaxQ + kMaxPhi),         // Trig: sin_q, cos_q, sin_phi, cos_phi
      // Statics: Q, drive, stiffness, V, dV_dq, d2V_dq2, R, normal, gain, K_rel
      3 * kMaxQ + 2 * kMaxQ * kMaxQ + 1 + kMaxReactions + kMaxFriction * (2 + kMaxQ),
      // Dynamics: I, dI_dq, C, h, Q, T, V, P_nc
      kMaxQ * kMaxQ + 2 * kMaxQ * kMaxQ * kMaxQ + 2 * kMaxQ + 3,
      2560,                          // Excess (629: engine_v8)
      6 + 5 * kMaxLinks,             // Shaking: F, M, F_link, M_link, r_G, mass, r_C
      4096,                          // Kinematics (1,088: chain16)
      // Rhs: K, I, h, Q, T, V, P_nc, Phi_phi
      kMaxPhi * kMaxQ + kMaxQ * kMaxQ + 2 * kMaxQ + 3 + kMaxPhi * kMaxPhi,
      256,                           // RhsConstants: c (37: published_andrews)
      2048,                          // DesignDerivatives (364: design_fivebar_massive)
      1024,                          // StaticsDesign (88: fourbar_loaded)
      1024,                          // DynamicsDesign (234: design_fivebar_massive)
  };

  // ---- Identity ----
  int layout = 0;            ///< kModelViewLayout of the view's compile
  int size = 0;              ///< sizeof(ModelView) of the view's compile
  const char* name = nullptr;   ///< the model's name (mech::<name>)
  const char* version = nullptr;  ///< the mechgen version that generated it
  /// Whether the model fits the maxima above (sizes, parameters and every struct's buffer): a
  /// runtime compiled once refuses a view without it (the entry point static_asserts it).
  bool fits_maxima = false;

  // ---- Sizes (the generated Sizes and Model constants; 0 where the model has none) ----
  int nq = 0;                ///< kNq: inputs q
  int nphi = 0;              ///< kNphi: dependent variables phi
  int nc = 0;                ///< kNc: rows of Phi (== nphi)
  int num_loops = 0;
  int mobility = 0;
  int order = 0;             ///< kOrder: 0 positions, 1 + K, 2 + L
  int num_points = 0;        ///< kNumPoints
  int num_links = 0;         ///< kNumLinks (with the ground)
  int num_joints = 0;        ///< the model's joints
  int num_scene_points = 0;  ///< kNumScenePoints
  int num_blocks = 0;        ///< kNumBlocks
  int num_transmission_angles = 0;
  int num_reactions = 0;     ///< kNumReactions (with statics)
  int num_friction = 0;      ///< kNumFriction (with statics)
  int num_statics_at_speed = 0;  ///< kNumStaticsAtSpeed: what in the statics reads a velocity
  int num_loads = 0;         ///< the model's loads
  int num_switches = 0;      ///< kNumSwitches (with SwitchModes)
  int num_design = 0;        ///< kNumDesign (with a design section)
  int num_design_checks = 0; ///< kNumDesignChecks
  int num_draw_joints = 0;   ///< kNumDrawJoints (with a drawing)
  int num_draw_values = 0;   ///< kNumDrawValues
  int num_applied_loads = 0; ///< kNumAppliedLoads (with AppliedLoads)
  int num_named_modes = 0;   ///< kNumNamedModes
  int num_change_points = 0; ///< kNumChangePoints
  int ground_link = 0;       ///< kGroundLink

  // ---- Names and constants ----
  const char* const* q_names = nullptr;
  const char* const* phi_names = nullptr;
  const bool* q_is_angle = nullptr;    ///< true: radians, false: a displacement
  const bool* phi_is_angle = nullptr;
  const double* q_min = nullptr;       ///< kQMin: default sweep range of each input
  const double* q_max = nullptr;       ///< kQMax
  const double* assembly_q = nullptr;  ///< kAssemblyQ
  const double* assembly_phi = nullptr;  ///< kAssemblyPhi
  const char* const* point_names = nullptr;
  const char* const* link_names = nullptr;
  const char* const* joint_names = nullptr;
  const char* const* scene_point_names = nullptr;
  const int* scene_point_links = nullptr;
  const int* default_modes = nullptr;       ///< kDefaultModes (num_blocks)
  const bool* block_closed_form = nullptr;  ///< kBlockClosedForm (num_blocks)
  const char* const* mode_names = nullptr;  ///< kModeNames (num_named_modes)
  const int* named_modes = nullptr;         ///< kNamedModes, mode i's blocks from named_modes[i * num_blocks]
  const int* change_point_inputs = nullptr;  ///< kChangePointInput (num_change_points)
  const int* change_point_blocks = nullptr;  ///< kChangePointBlock
  const double* change_point_q = nullptr;    ///< kChangePointQ
  const char* const* transmission_joints = nullptr;
  const char* const* reaction_names = nullptr;   ///< kReactionNames
  const int* reaction_joints = nullptr;          ///< kReactionJoint (index into joint_names)
  const char* const* friction_joints = nullptr;  ///< kFrictionJoints
  const bool* friction_prismatic = nullptr;      ///< kFrictionPrismatic
  /// kStaticsAtSpeed (num_statics_at_speed): the loads that read a velocity, the dampers and the
  /// viscous friction, which Forces takes at `velocities` ("damper 'pump'", ...).
  const char* const* statics_at_speed = nullptr;
  const char* const* load_names = nullptr;       ///< kLoadNames (num_loads)
  const char* const* design_names = nullptr;     ///< kDesignNames (num_design)
  const char* const* design_check_names = nullptr;  ///< kDesignCheckNames
  const int* draw_joint_kind = nullptr;      ///< kDrawJointKind (num_draw_joints), kDrawJoint*:
  const int* draw_joint_link_a = nullptr;
  const int* draw_joint_link_b = nullptr;
  const int* draw_joint_point_a = nullptr;
  const int* draw_joint_point_b = nullptr;
  const int* draw_joint_value = nullptr;
  const char* const* applied_load_names = nullptr;  ///< kAppliedLoadNames (num_applied_loads)
  const int* applied_load_kind = nullptr;
  const char* const* applied_load_units = nullptr;

  ViewFlags flags;

  // ---- Parameters ----
  int num_params = 0;       ///< free and derived
  int num_free_params = 0;  ///< the free ones (Params members), first in the table
  const ViewParameter* params = nullptr;
  /// p[num_free_params, num_params) from p[0, num_free_params): the derived parameters'
  /// definitions (the generated functions inline them; this is for printing and checking).
  void (*fill_derived)(double* p) = nullptr;

  // ---- Struct buffers (ViewStruct order) ----
  ViewLayout structs[static_cast<int>(ViewStruct::kCount)] = {};

  // ---- The generated Model's functions on flat arrays (nullptr where the model lacks one, and
  //      all of them where it does not fit the maxima) ----
  // Sizes: Phi nc; Phi_phi nc x nphi; Phi_q nc x nq; modes num_blocks (int); trig, c, dc, rc,
  // out: the struct's buffer; friction num_friction; scene 2 x num_scene_points; frames
  // 3 x num_links; values num_draw_values; applied loads 7 x num_applied_loads; mu
  // num_transmission_angles; margin num_design_checks, dmargin_dp num_design_checks x
  // num_design; dF_dp 2 x num_design, dM_dp num_design; switch modes num_switches (int).
  void (*Phi)(const double* p, const double* q, const double* phi, double* Phi, double* Phi_phi,
              double* Phi_q) = nullptr;
  void (*Coeffs)(const double* p, const double* q, const double* phi, double* out, const double* trig) = nullptr;
  void (*DetPhiPhi)(const double* p, const double* q, const double* phi, double* det_Phi_phi) = nullptr;
  ViewSolveReport (*Solve)(const double* p, const double* q, double* phi_io, const int* modes, int max_iterations,
                           double tolerance, double* trig) = nullptr;
  ViewSolveReport (*SolveTrig)(const double* p, const double* q, const int* modes, double* trig) = nullptr;
  ViewSolveReport (*Kinematics)(const double* p, const double* q, const int* modes, double* trig,
                                double* out) = nullptr;
  void (*TransmissionAngles)(const double* p, const double* q, const double* phi, double* mu) = nullptr;
  void (*Scene)(const double* p, const double* q, const double* phi, double* r) = nullptr;
  void (*Drawing)(const double* p, const double* q, const double* phi, double* frames, double* values) = nullptr;
  void (*CamProfile)(const double* p, int joint, double t, double* r) = nullptr;
  void (*AppliedLoads)(const double* p, const double* q, const double* phi, double* out) = nullptr;
  /// velocities (nq; nullptr: at rest): the input speeds at which the loads that read a
  /// velocity (statics_at_speed) are taken; a model with none ignores it.
  void (*Forces)(const double* p, const double* q, const double* phi, const double* c, double* out,
                 const double* friction, const double* trig, const double* velocities) = nullptr;
  /// The reads statics::Solve makes of a Statics buffer `statics` after Forces, on the
  /// generated struct's fixed sizes (straight-line code, as a generated model's own statics
  /// make them): returns whether every value statics::internal::AllFinite reads is finite (Q,
  /// drive; V and dV_dq with the potential; R; normal: what Forces fills), and writes max_i |R_i|
  /// (the fixed-size R's cwiseAbs().maxCoeff()) into *reaction_norm where that is not nullptr
  /// and the model has reactions. With Forces.
  bool (*StaticsChecks)(const double* statics, double* reaction_norm) = nullptr;
  /// Forces, then StaticsChecks of what it wrote, in one call (statics::Solve after each
  /// evaluation). With Forces.
  bool (*ForcesChecked)(const double* p, const double* q, const double* phi, const double* c, double* out,
                        const double* friction, const double* trig, const double* velocities,
                        double* reaction_norm) = nullptr;
  void (*Stiffness)(const double* p, const double* q, const double* phi, const double* c, double* out) = nullptr;
  void (*Dynamics)(const double* p, const double* q, const double* phi, const double* qd, double t, const double* c,
                   double* out, const double* friction, const double* trig) = nullptr;
  void (*Kinetostatics)(const double* p, const double* q, const double* phi, const double* qd, const double* qdd,
                        double t, const double* c, double* out, const double* friction, const double* trig) = nullptr;
  void (*ExcessDynamics)(const double* p, const double* q, const double* phi, const double* qd, const double* phid,
                         double t, double* out, const double* friction) = nullptr;
  void (*Shaking)(const double* p, const double* q, const double* phi, const double* qd, const double* qdd,
                  const double* c, double* out, const double* trig) = nullptr;
  void (*SwitchModes)(const double* p, const double* q, const double* phi, const double* qd, double t,
                      const double* c, int* modes) = nullptr;
  void (*Prepare)(const double* p, double* rc) = nullptr;
  ViewSolveReport (*Rhs)(const double* p, const double* rc, const double* q, const double* qd, double t,
                         const int* modes, double* trig, double* out, const double* friction) = nullptr;
  void (*Design)(const double* p, const double* q, const double* phi, double* out) = nullptr;
  void (*DesignChecks)(const double* p, double* margin, double* dmargin_dp) = nullptr;
  void (*StaticsDesign)(const double* p, const double* q, const double* phi, const double* c, const double* dc,
                        double* out) = nullptr;
  void (*DynamicsDesign)(const double* p, const double* q, const double* phi, const double* qd, double t,
                         const double* c, const double* dc, double* out, const double* friction) = nullptr;
  void (*ShakingDesign)(const double* p, const double* q, const double* phi, const double* qd, const double* qdd,
                        const double* c, const double* dc, double* dF_dp, double* dM_dp) = nullptr;
  /// mu^T (dQ/dp - dh/dp - (dI/dp) qdd) (num_design; the adjoint's lambda^T f_p,
  /// dynamics/adjoint.h): with DynamicsDesign where the dynamics program is straight-line.
  void (*DynamicsDesignProduct)(const double* p, const double* q, const double* phi, const double* qd, double t,
                                const double* c, const double* qdd, const double* mu, double* product,
                                const double* friction) = nullptr;
  /// dQ/dq, dh/dq, dQ/dqd, dh/dqd (nq x nq each, any may be nullptr; the trajectory
  /// sensitivities, dynamics/sensitivity.h): with DynamicsDesign where no cam law's fourth
  /// derivative is needed.
  void (*DynamicsJacobian)(const double* p, const double* q, const double* phi, const double* qd, double t,
                           const double* c, double* dQ_dq, double* dh_dq, double* dQ_dqd, double* dh_dqd,
                           const double* friction) = nullptr;

  /// The layout of struct `s`.
  constexpr const ViewLayout& Layout(ViewStruct s) const { return structs[static_cast<int>(s)]; }
};

// A plain aggregate of numbers and pointers: constant-initialized in each view, copied as bytes.
static_assert(std::is_aggregate_v<ModelView> && std::is_trivially_copyable_v<ModelView> &&
                  std::is_trivially_destructible_v<ModelView>,
              "ModelView is a plain aggregate");

/// The index of the parameter `name` in view.params (free or derived), or -1.
inline int FindParameter(const ModelView& view, const char* name) {
  for (int i = 0; i < view.num_params; ++i)
    if (std::strcmp(view.params[i].name, name) == 0) return i;
  return -1;
}

/// The defaults of every parameter, free and derived, into p[0, view.num_params).
inline void DefaultParameters(const ModelView& view, double* p) {
  for (int i = 0; i < view.num_params; ++i) p[i] = view.params[i].default_value;
}

}  // namespace mechgen

/// Declares mech::<name>::View(), defined in the generated <name>_view.cc (the generated header
/// does not declare it, so that a product that does not compile the view is unchanged).
#define MECHGEN_DECLARE_MODEL_VIEW(name) \
  namespace mech::name {                 \
  const ::mechgen::ModelView& View();    \
  }
