// One description per output struct of the generated header: its members (type, name,
// size, documentation, unit and sign convention, each a field), the Model flag that says whether the
// model has it, the Model alias, and when each is present. The template
// (templates/mechanism.h.mustache) renders the struct, its `kHas*` flag and its `*T` alias
// from this alone; every model gets every flag (false where the output is absent), so that
// the runtime reads what a model has instead of detecting it.
//
// Adding an output struct is one entry in OutputSpecs() (and the function that fills it,
// codegen/functions.h).
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

/// A member's documentation as the header prints it: the doc with its unit and sign
/// substituted, the size after the last line.
std::vector<std::string> RenderedDoc(const OutputMember& member);

/// Every output struct of the model's header in the header's order (Statics, Dynamics,
/// Excess, Shaking, Rhs, RhsConstants), present or not; `functions` are the generated
/// functions (an output is present where the function that fills it is generated).
std::vector<OutputSpec> OutputSpecs(const Model& m, const SymbolicTable& t, const std::vector<FunctionSpec>& functions);

}  // namespace mechgen
