// The builders of the generated functions: each reads quantities from the symbolic table
// (symbolic/table.h) and returns the description of one function (function_spec.h):
// where each quantity is stored, its arguments and documentation. No C++ text of the
// math lives here, only the statements' targets and the control flow of the solvers.
//
// To add a generated function: write one builder below that returns a FunctionSpec, and
// append it in BuildFunctions. The templates render it (declaration, definition, extern
// declarations and instantiations, the Model member) without further change.
#pragma once

#include <vector>

#include "codegen/cxx_code.h"
#include "codegen/function_spec.h"
#include "analysis/kinematics.h"
#include "model/model.h"
#include "symbolic/design.h"
#include "symbolic/dynamics.h"
#include "symbolic/jacobian.h"
#include "symbolic/statics.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"

namespace mechgen {

/// Gives every symbol of the model's expressions its C++ spelling: q(i), phi(i), p.<name>,
/// the cam laws and contours.
void NameModelSymbols(const Model& m, const Kinematics& k, CxxPrinter* printer);

/// EvalPhi: Phi, Phi_phi, Phi_q.
FunctionSpec EvalPhiSpec(const SymbolicTable& t);
/// EvalCoefficients: Phi, Phi_phi, K, L, r_P, K_P, L_P (as requested).
FunctionSpec EvalCoefficientsSpec(const SymbolicTable& t);
/// EvalDetPhiPhi: det Phi_phi as the product of the blocks' determinants.
FunctionSpec EvalDetPhiPhiSpec(const SymbolicTable& t);
/// EvalTransmissionAngles: mu of each four-bar loop on the ground.
FunctionSpec EvalTransmissionAnglesSpec(const std::vector<TransmissionAngle>& angles);
/// SolvePositions: block by block, closed-form dyads (symbolic/dyads.h) or Newton–Raphson
/// (codegen/positions.cc). *trig_done[i]: phi(i)'s sin and cos come from its closed form.
FunctionSpec SolvePositionsSpec(const SymbolicTable& t, CxxPrinter* printer, std::vector<bool>* trig_done);
/// SolvePositionsTrig (Model::SolveTrig): SolvePositions' closed forms writing only sin and cos of the angles to *trig
/// (no atan2). *possible is false (and the spec empty) unless every block is a closed form
/// that gives each of its angles' direction cosines and every phi is an angle; ShareTrig
/// then checks that nothing else reads an angle (else BuildFunctions drops it).
FunctionSpec SolveTrigSpec(const SymbolicTable& t, CxxPrinter* printer, bool* possible);
/// EvalKinematics (Model::Kinematics): K, L (where the model asks for L) and Phi_phi, its body
/// here; ShareTrig puts SolvePositionsTrig's blocks before it, and BuildFunctions keeps it only
/// where SolvePositionsTrig exists. An empty spec (no name) where the model asks for no K.
FunctionSpec EvalKinematicsSpec(const SymbolicTable& t);
/// K's and L's programs (L's empty where the model asks for no L): what the one-pass functions
/// fused with SolvePositionsTrig (EvalKinematics, EvalRhs) start from.
Program VelocityPrograms(const SymbolicTable& t);
/// The stores of out->K and out->L (with `with_L`): EvalKinematics' and EvalRhs'.
Program CoefficientStores(const SymbolicTable& t, bool with_L);
/// The stores of out->Phi_phi: EvalKinematics' and EvalRhs'.
Program PhiPhiStores(const SymbolicTable& t);
/// EvalScene: every named point of every link.
FunctionSpec EvalSceneSpec(const Kinematics& k);
/// CamLaw_<joint>, EvalCam_<joint> and Contour_<joint> (codegen/cam_functions.cc).
FunctionSpec CamLawSpec(const Model& m, const CamLaw& law, CxxPrinter* printer);
FunctionSpec EvalCamSpec(const Model& m, const CamLaw& law, const CamGeometry& g);
FunctionSpec ContourSpec(const Model& m, const CamContour& c);
/// Table_<name>(x, d): a `tables:` entry's value or slope (codegen/cam_functions.cc).
FunctionSpec TableSpec(const Model& m, int index);

/// EvalStatics (codegen/statics_functions.cc): Q, drive, V, reactions, friction (as requested).
FunctionSpec EvalStaticsSpec(const Model& m, const StaticsTable& st, CxxPrinter* printer);
/// EvalAppliedLoads (codegen/applied_loads.cc): each load's and spring's point and vector for a
/// force diagram, with its Model constants; an empty spec (no name) without a scene or loads.
FunctionSpec EvalAppliedLoadsSpec(const Model& m, const Kinematics& k, const StaticsTable& st, CxxPrinter* printer);
/// EvalStiffness: d2V/dq2 and -dQ/dq (potential with L).
FunctionSpec EvalStiffnessSpec(const Model& m, const StaticsTable& st, CxxPrinter* printer);
/// The statements of EvalStatics' body for a statics table (also EvalKinetostatics').
Program StaticsBody(const Model& m, const StaticsTable& st, CxxPrinter* printer);
/// EvalDynamics (codegen/statics_functions.cc): I, dI_dq, C, h, Q, T, V, P_nc.
FunctionSpec EvalDynamicsSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer);
/// EvalRhs: the equation of motion's right-hand side at (t, q, qd) in one pass (its body is
/// K, L, I, h, Q, T, V, P_nc, Phi_phi here; ShareTrig puts SolvePositionsTrig's blocks before
/// it, and BuildFunctions keeps it only where SolvePositionsTrig exists).
FunctionSpec EvalRhsSpec(const Model& m, const SymbolicTable& t, const DynamicsTable& dt, CxxPrinter* printer);
/// Moves EvalRhs' parameter-only subexpressions into RhsConstants (hoist.h) and builds
/// PrepareRhs, which fills them (its `constants` sizes RhsConstants, codegen/output_spec.h).
void HoistRhsConstants(const Model& m, CxxPrinter* printer, FunctionSpec* rhs, FunctionSpec* prepare);
/// EvalKinetostatics: the statics with the inertia forces, into the Statics struct.
FunctionSpec EvalKinetostaticsSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer);
/// EvalExcess: the excess-coordinate formulation's M, h, g, Phi_x, Phi, gamma, T, V.
FunctionSpec EvalExcessSpec(const Model& m, const Kinematics& k, const DynamicsTable& dt, CxxPrinter* printer);
/// EvalShaking (with the `shaking` quantity): the shaking force and moment, per link, the
/// centres of mass (the Shaking struct: codegen/output_spec.h).
FunctionSpec EvalShakingSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer);
/// EvalDesignDerivatives (codegen/design_functions.cc, with a `design` section): dphi/dp, the
/// points' dr_P/dp, dK/dp, dL/dp (the DesignDerivatives struct: codegen/output_spec.h).
FunctionSpec EvalDesignDerivativesSpec(const DesignTable& dt, const SymbolicTable& t);
/// EvalDesignChecks (codegen/design_functions.cc): the design checks' margins and their d/dp.
FunctionSpec EvalDesignChecksSpec(const DesignTable& dt);
/// EvalStaticsDesign (codegen/design_functions.cc): d/dp of Q, drive, V and the reactions (the
/// StaticsDesign struct), reading EvalDesignDerivatives' output.
FunctionSpec EvalStaticsDesignSpec(const Model& m, const StaticsTable& st, const DesignStatics& ds,
                                   CxxPrinter* printer);
/// EvalDynamicsDesign (codegen/design_functions.cc): d/dp of I, dI/dq, h, Q, T, V at (t, q, qd)
/// (the DynamicsDesign struct), reading EvalDesignDerivatives' output.
FunctionSpec EvalDynamicsDesignSpec(const Model& m, const DynamicsTable& dyn, const DesignDynamics& dd,
                                    CxxPrinter* printer);
/// EvalDynamicsDesignProduct (codegen/design_functions.cc, generated with EvalDynamicsDesign):
/// mu^T (dQ/dp - dh/dp - (dI/dp) qdd) at (t, q, qd) by reverse mode, the adjoint's product
/// (dynamics/adjoint.h).
FunctionSpec EvalDynamicsDesignProductSpec(const Model& m, const DynamicsTable& dyn, const DesignTable& dt,
                                           const DesignDynamicsProduct& dp, CxxPrinter* printer);
/// EvalShakingDesign (codegen/design_functions.cc, with `shaking`): d/dp of the shaking force
/// and moment at (q, qd, qdd) (nullable outputs dF_dp, dM_dp).
FunctionSpec EvalShakingDesignSpec(const DynamicsTable& dyn, const DesignShaking& ds, CxxPrinter* printer);
/// EvalDynamicsJacobian (codegen/design_functions.cc, generated exactly with EvalDynamicsDesign):
/// dQ/dq, dh/dq, dQ/dqd, dh/dqd at (t, q, qd) (nullable outputs), the third-order coefficients
/// dL/dq on the way (symbolic/jacobian.h).
FunctionSpec EvalDynamicsJacobianSpec(const Model& m, const DynamicsTable& dyn, const DynamicsJacobian& dj,
                                      CxxPrinter* printer);
/// Drops the kDefine statements whose symbol no later statement reads.
void PruneUnusedDefines(Program* program);
/// A body over a statics table's program, finished as EvalStatics' is (codegen/statics_functions.cc):
/// the unused locals pruned, the friction loads read, the sums raised to powers named.
Program FinishAppliedProgram(Program P, const StaticsTable& st, CxxPrinter* printer);

/// The switching items of a program's values (mstep, msign, mmin, mmax, mmod and table calls,
/// a table's slope as its value's item), each once (codegen/switch_functions.cc).
std::vector<GiNaC::ex> SwitchItems(const Program& program);
/// EvalSwitchModes (the `Model::SwitchModes` member): the mode of each switching item of the
/// dynamics' applied loads Q; an empty spec (no name) where Q has none. Its `switches` is
/// kNumSwitches.
FunctionSpec EvalSwitchModesSpec(const Model& m, const DynamicsTable& dt, CxxPrinter* printer);

/// sin and cos shared between SolvePositions and EvalCoefficients (the Trig<Scalar>
/// argument): rewrites both specs' programs, and those of `takers` (EvalStatics, EvalDynamics, ...)
/// that take a Trig argument too. Each of `fused` (EvalKinematicsSpec, EvalRhsSpec; nullptr:
/// none) gets SolveTrig's blocks put before its body, which then reads the angles' sin and cos
/// from them (its body is cleared where it reads an angle otherwise).
void ShareTrig(const Kinematics& k,
               const std::vector<bool>& trig_done,
               CxxPrinter* printer,
               FunctionSpec* coefficients,
               FunctionSpec* positions,
               const std::vector<FunctionSpec*>& takers = {},
               FunctionSpec* solve_trig = nullptr,
               bool* solve_trig_possible = nullptr,
               const std::vector<FunctionSpec*>& fused = {});

/// Every generated function of the model, in the order of the header.
std::vector<FunctionSpec> BuildFunctions(const Model& m,
                                         const Kinematics& k,
                                         const SymbolicTable& t,
                                         const std::vector<TransmissionAngle>& transmission,
                                         CxxPrinter* printer,
                                         const StaticsTable* statics = nullptr,
                                         const DynamicsTable* dynamics = nullptr,
                                         const DesignTable* design = nullptr);

}  // namespace mechgen
