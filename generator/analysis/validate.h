// The validation stage: every check of a model that is not about its syntax, run once after
// reading, on numbers at the parameters' defaults. A ModelError names the file, line and
// column and what to change; mechgen then writes nothing.
//
// The checks, in the order they run (a model with several faults reports the first):
//   1. each joint's own numbers (joints/<kind>.cc, JointKind::Check): radii, roller, angles
//   2. topology (topology.cc computes, this reports): sliders that fix one angle twice,
//      links not connected to the ground, mobility <= 0, inputs != mobility, two inputs on
//      one angle, an input that cannot turn; then zero-length links (all pins at one point)
//   3. four-bar loops (grashof.cc): a zero-length link (coincident pivots), a driven link's
//      range the loop cannot reach
//   4. cams: the law closes the cycle (here), no undercut or cusp (joints/cam_profile.cc, CheckCam), the
//      contour's checks (joints/cam_profile.cc, BuildCamContour: they share its sampling and spline fit)
//   5. the assembly guess names coordinates
//   5b. the sweep's CSV column names derived from the coordinates are unique
//   (6. the closed-form blocks' assembly check stays in blocks.cc (ChooseMode, the codegen
//       part); it needs the derivation's blocks and belongs here once they are built before
//       validation, after step 5.)
#pragma once

#include <vector>

#include "analysis/grashof.h"
#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "model/model.h"

namespace mechgen {

/// What validation computed on the way, for the stages after it.
struct Analysis {
  Topology topology;
  std::vector<FourBarLoop> four_bars;
  CoordinateTable coordinates;
  CamAnalysis cams;
};

/// Runs every check (ModelError on the first that fails).
Analysis Validate(const Model& m);

/// Step 2: the topology's errors.
void CheckTopology(const Model& m, const Topology& t);

/// Step 2b: a moving link whose joints are all revolute (no higher pair uses its angle) and
/// all at one point at the parameters' defaults: a zero-length link, whose angle is in no
/// equation, or, driven, moves nothing (ModelError at its last joint's point).
void CheckZeroLengthLinks(const Model& m);

/// Step 2b: a rack whose pinion has a zero pitch radius at the defaults (ModelError at
/// the joint).
void CheckZeroRadii(const Model& m);

/// Step 4 for a cam given by its law: the segments span one turn and the rises add up to
/// the returns (ModelError at the law).
void CheckCamLaw(const Model& m, const Joint& j);

/// Step 5b: the names the sweep's CSV derives from the coordinates (<c>_dot, K_<phi>_<q>,
/// ...) are unique: ModelError at the link or joint to rename (a link 'rocker_dot' next to
/// 'rocker' gives 'theta_rocker_dot' twice).
void CheckCsvColumnNames(const Model& m, const Topology& t, const CoordinateTable& table);

/// Step 4: builds every cam's law (checked by CheckCamLaw), geometry (undercut and cusp:
/// CheckCam in joints/cam_profile.cc) and contour (BuildCamContour checks it as it fits the spline), cam by
/// cam in file order.
CamAnalysis AnalyzeCams(const Model& m);

}  // namespace mechgen
