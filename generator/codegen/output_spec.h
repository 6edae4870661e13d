// One description per output struct of the generated header: its members (type, name,
// size, documentation, unit and sign convention, each a field), the Model flag that says whether the
// model has it, the Model alias, and when each is present. The template
// (templates/mechanism.h.mustache) renders the struct, its `kHas*` flag and its `*T` alias
// from this alone; every model gets every flag (false where the output is absent), so that
// the runtime reads what a model has instead of detecting it. The same kind of flag says
// what else the model has (ModelFlags: Coefficients' optional members, Model's optional
// functions).
//
// Adding an output struct is one entry in OutputSpecs() (and the function that fills it,
// codegen/functions.h); an optional function of Model, one flag in ModelFlags (and the line
// in core/model_traits.h that reads it).
#pragma once

#include <string>
#include <vector>

#include "codegen/function_spec.h"
#include "model/model.h"
#include "symbolic/statics.h"
#include "symbolic/table.h"

namespace mechgen {

/// One member (or several of one type and one documentation) of an output struct.
struct OutputMember {
  std::string type;   ///< C++ type in terms of Scalar and Sizes ("Vec<Scalar, Sizes::kNq>")
  std::string names;  ///< "Q", or "T, V, P_nc" for several of one type
  /// The meaning; "{unit}" and "{sign}" stand for the two fields below where the text says
  /// them (RenderedDoc). Empty: the previous member's doc covers it.
  std::vector<std::string> doc;
  /// The SI unit: "N", "kg m^2", "1" (dimensionless); a quantity per generalized coordinate
  /// gives its alternatives ("N m or N": per angle or per slide input).
  std::string unit;
  std::string sign;  ///< its sign convention ("CCW +"), empty where the definition fixes it
  std::string size;  ///< "kNq", "kNq x kNq^2" (said after the doc; empty: a scalar or said in the doc)
  std::string flag;  ///< the Model flag that says it exists (empty: whenever its struct does)
  bool present = true;
};

/// A flag of Model: `static constexpr bool name = value;` with its documentation.
struct OutputFlag {
  std::string name;
  std::string doc;
  bool value = false;
};

struct OutputSpec {
  std::string name;              ///< the struct: Statics, Dynamics, ...
  std::string alias;             ///< Model's alias template: StaticsT, ...
  std::vector<std::string> doc;  ///< what fills it, units, conventions
  std::vector<OutputMember> members;
  OutputFlag flag;                       ///< kHasStatics, ...: the struct, its alias and its functions exist
  std::vector<OutputFlag> member_flags;  ///< one per optional group of members (kHasStaticsR, ...)
  bool present() const { return flag.value; }
};

/// What a model has besides its output structs, one flag each (every generated header declares
/// all of them, false where absent, after the output flags' heading; the runtime reads them,
/// core/model_traits.h): the optional members of Coefficients, and the optional functions of
/// Model with the constants that go with them. The Coefficients struct of the header has its
/// optional members exactly where these flags say (emit.cc renders both from this).
struct ModelFlags {
  // Members of Coefficients (EvalCoefficients).
  OutputFlag coeffs_phi;           ///< kHasCoeffsPhi: Phi and Phi_phi
  OutputFlag K;                    ///< kHasK
  OutputFlag L;                    ///< kHasL
  OutputFlag points;               ///< kHasPoints: r_P
  OutputFlag point_velocities;     ///< kHasPointVelocities: K_P
  OutputFlag point_accelerations;  ///< kHasPointAccelerations: L_P
  // Functions of Model (and their constants).
  OutputFlag solve;                ///< kHasSolve: Solve, kNumBlocks, kDefaultModes, kBlockClosedForm
  OutputFlag named_modes;          ///< kHasNamedModes: kNamedModes, kModeNames, ModesByName
  OutputFlag trig;                 ///< kHasTrig: TrigT, the trig arguments of Solve and Coeffs
  OutputFlag solve_trig;           ///< kHasSolveTrig: SolveTrig
  OutputFlag transmission_angles;  ///< kHasTransmissionAngles: TransmissionAngles
  OutputFlag switch_modes;         ///< kHasSwitchModes: SwitchModes, kNumSwitches
  OutputFlag drawing;              ///< kHasDrawing: Drawing, kNumDrawJoints, kDrawJoint*
  OutputFlag cam_profile;          ///< kHasCamProfile: CamProfile
  OutputFlag applied_loads;        ///< kHasAppliedLoads: AppliedLoads, kNumAppliedLoads, kAppliedLoad*
  /// All of them in the header's order.
  std::vector<const OutputFlag*> All() const {
    return {&coeffs_phi, &K,    &L,          &points,     &point_velocities,    &point_accelerations, &solve,
            &named_modes, &trig, &solve_trig, &transmission_angles, &switch_modes, &drawing, &cam_profile,
            &applied_loads};
  }
};

/// The model's flags (ModelFlags) from the model, what the table holds and which functions
/// are generated.
ModelFlags ModelFlagsOf(const Model& m, const SymbolicTable& t, const std::vector<FunctionSpec>& functions);

/// A member's documentation as the header prints it: the doc with its unit and sign
/// substituted, the size after the last line.
std::vector<std::string> RenderedDoc(const OutputMember& member);

/// Every output struct of the model's header in the header's order (Statics, Dynamics,
/// Excess, Shaking, Kinematics, Rhs, RhsConstants), present or not; `functions` are the generated
/// functions (an output is present where the function that fills it is generated).
std::vector<OutputSpec> OutputSpecs(const Model& m, const SymbolicTable& t, const std::vector<FunctionSpec>& functions);

/// The structs of the model view (runtime/include/mechgen/core/model_view.h: ViewStruct, in its
/// order, each named as its enumerator without the k): Coefficients and Trig (whose text the
/// header template holds; members and presence only), then OutputSpecs. The view lays out each
/// present member of each present struct in one buffer.
std::vector<OutputSpec> ViewStructSpecs(const Model& m,
                                        const SymbolicTable& t,
                                        const std::vector<FunctionSpec>& functions);

}  // namespace mechgen
