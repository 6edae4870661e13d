// One description per generated function: its name, documentation, arguments (types with
// sizes and nullability), the statement programs that fill its outputs, and how the
// templates expose it (a static member of `Model`, explicit instantiations). The templates
// (templates/mechanism.{h,cc}.mustache) render the declaration, the definition, the extern
// declarations, the explicit instantiations and the `Model` wrapper from this alone, and
// emit.cc derives the preamble of the body from it: `using std::f;` for each math function
// the body calls and `(void)arg;` for each argument it does not use.
//
// Adding a generated function is one builder returning a FunctionSpec (codegen/functions.h)
// and one line in BuildFunctions that appends it.
#pragma once

#include <string>
#include <vector>

#include "symbolic/program.h"

namespace mechgen {

struct Argument {
  enum class Direction { kIn, kOut, kInOut };
  std::string type;  ///< C++ type in terms of the function's template scalar (FunctionSpec::scalar)
  std::string name;
  Direction direction = Direction::kIn;
  std::string doc;             ///< what it is ("Inputs", "dPhi/dphi")
  std::string size;            ///< "dim kNq", "kNc x kNphi" (empty: a scalar or a struct)
  bool nullable = false;       ///< may be nullptr (said in the documentation)
  std::string default_value;   ///< in the declaration ("nullptr", "20"), empty: none
  std::string member_default;  ///< in the Model wrapper when it differs ("kDefaultModes")
};

/// An output struct of the generated header (codegen/output_spec.h).
enum class OutputStruct { kNone, kStatics, kDynamics, kExcess, kShaking, kKinematics, kRhs, kRhsConstants, kDesign, kStaticsDesign, kDynamicsDesign };

struct FunctionSpec {
  std::string name;                ///< EvalPhi, CamLaw_<joint>, ...
  /// The output struct whose presence this function decides: the struct exists exactly where
  /// the function is generated (EvalStatics: Statics, ...; kNone: none).
  OutputStruct fills = OutputStruct::kNone;
  std::vector<std::string> doc;    ///< \brief and notes, one line each (without " * ")
  std::vector<std::string> notes;  ///< after the arguments (\note ...)
  std::string scalar = "Scalar";   ///< the template parameter: template <typename Scalar>
  std::string returns = "void";    ///< return type (in terms of `scalar`)
  std::vector<Argument> args;
  /// The body: programs emitted one after the other, each with its own common
  /// subexpressions (a block of SolvePositions must not share values with the next).
  std::vector<Program> body;
  bool count_ops = true;     ///< a "// Total ops" line (programs of expressions)
  int extra_calls = 0;       ///< math calls in its raw lines, added to the count
  std::string ops_note;      ///< said after its count in the header's summary ("per Newton iteration")
  bool reindent = false;     ///< indent the body by its braces (nested control flow)
  std::string model_member;  ///< name of the static member of `Model` that calls it ("": none)
  bool instantiate = true;   ///< compiled for double and float in <model>.cc
  /// adapted in the model view (<model>_view.cc, ModelView's pointer of model_member); false for a
  /// function only the fixed-size runtime calls (none today: every Model function has its pointer).
  bool in_view = true;
  /// declared `inline`: a hint to the compiler to inline it at its call sites (EvalRhs, in an
  /// integrator's stage loop; a large function called from several places is not otherwise).
  bool inline_hint = false;
  /// PrepareRhs: how many parameter-only constants it fills (RhsConstants::c, codegen/output_spec.h).
  int constants = 0;
  /// EvalSwitchModes: how many switching items it gives a mode of (Sizes::kNumSwitches).
  int switches = 0;
  /// EvalDesignChecks: the names of its margins (Sizes::kNumDesignChecks, kDesignCheckNames).
  std::vector<std::string> design_checks;
  /// Lines of `Model` (constexpr tables that describe its output), after the drawing's.
  std::string model_constants;
};

inline Argument Arg(const std::string& type,
                    const std::string& name,
                    Argument::Direction direction,
                    const std::string& doc,
                    const std::string& size = "",
                    bool nullable = false,
                    const std::string& default_value = "") {
  Argument a;
  a.type = type;
  a.name = name;
  a.direction = direction;
  a.doc = doc;
  a.size = size;
  a.nullable = nullable;
  a.default_value = default_value;
  return a;
}

/// p, q, phi: the arguments of every evaluation at a configuration.
inline std::vector<Argument> AtConfiguration() {
  using Dir = Argument::Direction;
  return {Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."),
          Arg("const Vec<Scalar, Sizes::kNq>&", "q", Dir::kIn, "Inputs", "dim kNq"),
          Arg("const Vec<Scalar, Sizes::kNphi>&", "phi", Dir::kIn, "Dependent variables", "dim kNphi")};
}

}  // namespace mechgen
