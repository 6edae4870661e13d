// The drawing description of a model (mechgen/io/svg.h draws from it): per joint its kind,
// links, scene points and the values its shape needs (a slider's line angle, pitch radii, a
// roller's radius), EvalDrawing (every link's frame and those values at a configuration) and
// EvalCamProfile (a cam's profile in its own frame). Emitted with the scene (`scene: true`).
#pragma once

#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "codegen/cxx_code.h"
#include "codegen/function_spec.h"
#include "model/model.h"

namespace mechgen {

/// EvalDrawing and, for models with cams, EvalCamProfile; none without a scene.
std::vector<FunctionSpec> DrawingFunctions(const Model& m, const Kinematics& k, CxxPrinter* printer);

/// The number of values EvalDrawing writes (at least 1).
int NumDrawValues(const Model& m);

/// The constexpr tables of `Model` (kDrawJoint*), one declaration a line, indented for the
/// struct; empty without a scene.
std::string DrawingConstants(const Model& m, const Kinematics& k);

}  // namespace mechgen
