// The descriptions of the output structs. See output_spec.h.
#include "codegen/output_spec.h"

namespace mechgen {
namespace {

// The function that decides the struct's presence, or nullptr where it is not generated.
const FunctionSpec* Filling(const std::vector<FunctionSpec>& functions, OutputStruct output) {
  for (const FunctionSpec& f : functions)
    if (f.fills == output) return &f;
  return nullptr;
}

bool Generated(const std::vector<FunctionSpec>& functions, OutputStruct output) {
  return Filling(functions, output) != nullptr;
}

OutputMember Member(const std::string& type,
                    const std::string& names,
                    std::vector<std::string> doc,
                    const std::string& size = "",
                    const std::string& flag = "",
                    bool present = true) {
  OutputMember m;
  m.type = type;
  m.names = names;
  m.doc = std::move(doc);
  m.size = size;
  m.flag = flag;
  m.present = present;
  return m;
}

OutputMember Unit(OutputMember m, const std::string& unit, const std::string& sign = "") {
  m.unit = unit;
  m.sign = sign;
  return m;
}

OutputSpec Output(const std::string& name, bool present, const std::string& flag_doc, std::vector<std::string> doc) {
  OutputSpec o;
  o.name = name;
  o.alias = name + "T";
  o.flag = {"kHas" + name, flag_doc, present};
  o.doc = std::move(doc);
  return o;
}

const char* kVecNq = "Vec<Scalar, Sizes::kNq>";
const char* kMatNqNq = "Mat<Scalar, Sizes::kNq, Sizes::kNq>";
const char* kMatNqNq2 = "Mat<Scalar, Sizes::kNq, Sizes::kNq * Sizes::kNq>";
const char* kVecNx = "Vec<Scalar, Sizes::kNq + Sizes::kNphi>";

// Statics (EvalStatics, EvalKinetostatics, EvalStiffness): only the members the model asked for.
OutputSpec Statics(const Model& m, const SymbolicTable& t, const std::vector<FunctionSpec>& functions) {
  const StaticsLayout layout = StaticsLayout::Of(m);
  const bool forces = m.outputs.Has(Quantity::kForces), potential = m.outputs.Has(Quantity::kPotential);
  const bool has_L = t.requested.L;
  OutputSpec o = Output("Statics", Generated(functions, OutputStruct::kStatics),
                        "Statics, StaticsT, EvalStatics (Model::Forces): forces, potential or reactions.",
                        {"What EvalStatics() fills (statics by virtual work, Paul ch. 5). Units follow the model's",
                         "(SI: N, N m, J). A generalized force of an angle input is a torque (per radian), of a slide",
                         "input a force. Only the members the model asked for exist."});
  const bool any = o.present();
  o.member_flags = {
      {"kHasStaticsQ", "Statics::Q and drive (the `forces` quantity).", any && forces},
      {"kHasStaticsStiffness", "Statics::stiffness, set by EvalStiffness (Model::Stiffness).",
       any && forces && potential && has_L},
      {"kHasStaticsV", "Statics::V and dV_dq (the `potential` quantity).", any && potential},
      {"kHasStaticsD2V", "Statics::d2V_dq2, set by EvalStiffness (Model::Stiffness).", any && potential && has_L},
      {"kHasStaticsR", "Statics::R (kReactionNames): reactions.", any && !layout.reactions.empty()},
      {"kHasStaticsFriction", "Statics::normal, gain, K_rel (kFrictionJoints): Coulomb friction.",
       any && !layout.friction.empty()},
  };
  const auto& f = o.member_flags;
  // Inputs that are no joint's (issue 26) say what their actuator is; other models' text stays.
  std::vector<std::string> drive_doc = {
      "drive(j) = -Q(j): what input j's actuator applies for static equilibrium: the torque on the",
      "input's moving link ({sign}, reacting on the ground) or the force on its slider", "along the line."};
  for (const Input& in : m.inputs)
    if (in.kind != Input::Kind::kJoint || m.joints[in.joint].type() == JointType::kSlot) {
      drive_doc = {"drive(j) = -Q(j): what input j's actuator applies for static equilibrium: the torque on the",
                   "input's moving link or the driven link ({sign}, reacting on the ground), the force on its",
                   "slider along the line or on a slot's pin along the slot, or for a driven point's x (y) the",
                   "force along +x (+y) on that point (reacting on the ground)."};
      break;
    }
  o.members = {
      Unit(Member(kVecNq, "Q",
                  {"Q(j): generalized force of the loads, springs, weights and given friction loads on q_j",
                   "(virtual work: Q_j = sum F.K_P,j + sum T K_theta,j - dV/dq_j)."},
                  "kNq", f[0].name, f[0].value),
           "N m or N"),
      Unit(
          Member(kVecNq, "drive", drive_doc, "kNq", f[0].name, f[0].value),
          "N m or N", "counter-clockwise +"),
      Unit(Member(kMatNqNq, "stiffness",
                  {"stiffness(j, k) = -dQ_j/dq_k along the motion, friction excluded (d2V/dq2 for a conservative",
                   "model): an equilibrium (Q = 0) is stable where it is positive definite. Set by",
                   "EvalStiffness(), not EvalStatics()."},
                  "kNq x kNq", f[1].name, f[1].value),
           "N m, N or N/m"),
      Unit(Member("Scalar", "V", {"V: potential energy of the springs and the weights."}, "", f[2].name, f[2].value),
           "J"),
      Unit(Member(kVecNq, "dV_dq", {"dV_dq(j) = dV/dq_j along the motion."}, "kNq", f[2].name, f[2].value), "N m or N"),
      Unit(Member(kMatNqNq, "d2V_dq2", {"d2V_dq2(j, k) = d2V/dq_j dq_k along the motion; set by EvalStiffness()."},
                  "kNq x kNq", f[3].name, f[3].value),
           "N m, N or N/m"),
      Unit(Member("Vec<Scalar, Sizes::kNumReactions>", "R",
                  {"R(i): reaction component Model::kReactionNames[i]: the force (moment) of the joint's first link",
                   "on its second, {sign}."},
                  "kNumReactions", f[4].name, f[4].value),
           "N or N m", "fixed frame"),
      Unit(Member("Vec<Scalar, Sizes::kNumFriction>", "normal",
                  {"normal(i): the force friction acts with at kFrictionJoints[i]: |F| at a revolute joint, |N| at",
                   "a prismatic joint."},
                  "kNumFriction", f[5].name, f[5].value),
           "N"),
      Unit(Member("Vec<Scalar, Sizes::kNumFriction>", "gain",
                  {"gain(i): mu r (revolute: the friction circle's radius) or mu (prismatic): the friction load's",
                   "magnitude is gain(i) normal(i)."},
                  "kNumFriction", f[5].name, f[5].value),
           "m or 1"),
      Unit(Member("Mat<Scalar, Sizes::kNumFriction, Sizes::kNq>", "K_rel",
                  {"K_rel(i, j): the joint's relative velocity per unit qd_j: d(theta_b - theta_a)/dq_j (revolute)",
                   "or ds/dq_j (prismatic); friction opposes it."},
                  "kNumFriction x kNq", f[5].name, f[5].value),
           "1, 1/m or m"),
  };
  return o;
}

OutputSpec Dynamics(const std::vector<FunctionSpec>& functions) {
  OutputSpec o =
      Output("Dynamics", Generated(functions, OutputStruct::kDynamics),
             "Dynamics, DynamicsT, EvalDynamics, EvalKinetostatics (Paul ch. 6): `dynamics`.",
             {"What EvalDynamics() fills (Paul ch. 6): the generalized equation of motion",
              "  I(q) qdd + h(q, qd) = Q(t, q, qd),   h_j = sum_kl C(j, k + kNq l) qd_k qd_l",
              "(one DOF: I qdd + 1/2 I' qd^2 = Q, C = I'/2). Units follow the model's (SI: kg m^2, N m, J, W)."});
  o.members = {
      Unit(Member(kMatNqNq, "I",
                  {"I(j, k) = sum over the massive links of m K_G,j . K_G,k + J_G K_theta,j K_theta,k: the",
                   "generalized inertia."},
                  "kNq x kNq"),
           "kg m^2, kg m or kg"),
      Unit(Member(kMatNqNq2, "dI_dq", {"dI_dq(j, k + kNq*l) = dI(j, k)/dq_l along the motion."}, "kNq x kNq^2"),
           "kg m^2, kg m or kg"),
      Unit(Member(kMatNqNq2, "C", {"C(j, k + kNq*l) = sum m K_G,j . L_G,kl + J K_theta,j L_theta,kl."}, "kNq x kNq^2"),
           "kg m^2, kg m or kg"),
      Unit(Member(kVecNq, "h", {"h = C (qd (x) qd): the centripetal and Coriolis terms."}, "kNq"), "N m or N"),
      Unit(Member(kVecNq, "Q",
                  {"Q(j): generalized applied force on q_j at (t, q, qd): loads (with their time and velocity",
                   "dependence, tables), weights, springs, dampers, viscous joint friction and the given Coulomb",
                   "friction loads."},
                  "kNq"),
           "N m or N"),
      Unit(Member("Scalar", "T", {"T = 1/2 qd^T I qd: the kinetic energy."}), "J"),
      Unit(Member("Scalar", "V", {"V: the potential energy of the springs and the weights (0 if none)."}), "J"),
      Unit(Member("Scalar", "P_nc",
                  {"P_nc = (Q + dV/dq) . qd: the power of the non-conservative forces (d(T + V)/dt = P_nc)."}),
           "W"),
  };
  return o;
}

OutputSpec Excess(const std::vector<FunctionSpec>& functions) {
  OutputSpec o = Output("Excess", Generated(functions, OutputStruct::kExcess),
                        "Excess, ExcessT, EvalExcess (Model::ExcessDynamics, Paul §6.6.2): `dynamics`.",
                        {"What EvalExcess() fills: the excess-coordinate formulation (Paul §6.6.2) on x = (q, phi),",
                         "n = kNq + kNphi:  M xdd + h = g + Phi_x^T lambda,  Phi_x xdd = gamma."});
  o.members = {
      Unit(Member("Mat<Scalar, Sizes::kNq + Sizes::kNphi, Sizes::kNq + Sizes::kNphi>", "M",
                  {"M(a, b) = sum m dr_G/dx_a . dr_G/dx_b + J dtheta/dx_a dtheta/dx_b."}, "n x n"),
           "kg, kg m or kg m^2"),
      Unit(Member(kVecNx, "h", {"h(a) = sum m dr_G/dx_a . (sum_bc d2r_G/dx_b dx_c xd_b xd_c)."}, "n"), "N or N m"),
      Unit(Member(kVecNx, "g",
                  {"g(a): the applied generalized force on x_a at (t, x, xd) (loads, weights, springs, dampers,",
                   "viscous and the given Coulomb friction)."},
                  "n"),
           "N or N m"),
      Unit(Member("Mat<Scalar, Sizes::kNc, Sizes::kNq + Sizes::kNphi>", "Phi_x", {"Phi_x = [Phi_q  Phi_phi]."},
                  "kNc x n"),
           "1 or m"),
      Unit(Member("Vec<Scalar, Sizes::kNc>", "Phi", {"Phi(q, phi): the residual."}, "kNc"), "m or 1"),
      Unit(Member("Vec<Scalar, Sizes::kNc>", "gamma", {"gamma = -sum_bc d2Phi/dx_b dx_c xd_b xd_c: Phi_x xdd = gamma."},
                  "kNc"),
           "m/s^2 or 1/s^2"),
      Unit(Member("Scalar", "T, V", {"T = 1/2 xd^T M xd, V: the kinetic and potential energies."}), "J"),
  };
  return o;
}

OutputSpec Shaking(const std::vector<FunctionSpec>& functions) {
  OutputSpec o =
      Output("Shaking", Generated(functions, OutputStruct::kShaking),
             "Shaking, ShakingT, EvalShaking (Model::Shaking; Paul ch. 7): `shaking`.",
             {"What EvalShaking() fills (Paul ch. 7): the shaking force and moment, the resultant of the moving",
              "links' d'Alembert inertia forces -m a_G (at each centre of mass G) and couples -J alpha. Units",
              "follow the model's (SI: N, N m, kg, m). Sign convention: F and M are what the moving links exert ON",
              "THE FRAME (ground) through the ground joints' reactions and the input actuators' reactions, when no",
              "loads and no gravity act: Newton for the moving links gives (frame on links) + loads = sum m a_G, so",
              "(links on frame) = F + the loads' resultant (and M + the loads' moment about O). M is about the",
              "fixed frame's origin O, counter-clockwise +, with the planar cross product r x F = r_x F_y - r_y F_x;",
              "about another point P it is M - r_P x F. Columns are indexed like Model::kLinkNames."});
  o.members = {
      Unit(Member("Vec<Scalar, 2>", "F", {"F = -sum_i m_i a_Gi: the shaking force ({unit})."}, "2"), "N"),
      Unit(Member("Scalar", "M",
                  {"M = -sum_i (r_Gi x m_i a_Gi + J_i alpha_i): the shaking moment about O ({unit}, {sign})."}),
           "N m", "CCW +"),
      Unit(Member("Mat<Scalar, 2, Sizes::kNumLinks>", "F_link",
                  {"F_link.col(l) = -m_l a_Gl: link l's share of F; 0 for the ground and massless links."},
                  "2 x kNumLinks"),
           "N"),
      Unit(Member("Vec<Scalar, Sizes::kNumLinks>", "M_link",
                  {"M_link(l) = r_Gl x F_link.col(l) - J_l alpha_l: link l's share of M; 0 for the ground and massless",
                   "links."},
                  "kNumLinks"),
           "N m"),
      Unit(Member("Mat<Scalar, 2, Sizes::kNumLinks>", "r_G",
                  {"r_G.col(l): link l's centre of mass in the fixed frame ({unit}); NaN for the ground and massless",
                   "links."},
                  "2 x kNumLinks"),
           "m"),
      Unit(Member(
               "Scalar", "mass",
               {"The moving links' total mass ({unit}) and their common centre of mass r_C (m): F = -mass d2r_C/dt2."}),
           "kg"),
      Unit(Member("Vec<Scalar, 2>", "r_C", {}), "m"),
  };
  return o;
}

// Kinematics (EvalKinematics): SolvePositionsTrig's direction cosines with K, L and Phi_phi in one pass.
OutputSpec KinematicsOutput(const SymbolicTable& t, const std::vector<FunctionSpec>& functions) {
  OutputSpec o = Output("Kinematics", Generated(functions, OutputStruct::kKinematics),
                        "Kinematics, KinematicsT, EvalKinematics (Model::Kinematics: SolveTrig, K, L in one pass).",
                        {"What EvalKinematics() fills at inputs q: the velocity (and centripetal) coefficients with",
                         "Phi_phi, the same definitions and units as Coefficients' (no residual, no points)."});
  o.members = {
      Unit(Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq>", "K",
                  {"K(i, j) = dphi_i/dq_j ({unit}): the velocity coefficients (phid = K qd)."}, "kNphi x kNq"),
           "1, m or 1/m"),
      Unit(Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq * Sizes::kNq>", "L",
                  {"L(i, j + kNq*k) = d K(i, j) / d q_k ({unit}): the centripetal coefficients",
                   "(phidd = K qdd + L (qd (x) qd); with kHasL)."},
                  "kNphi x kNq^2", "kHasL", t.requested.L),
           "K's unit per unit of q_k"),
      Unit(Member("Mat<Scalar, Sizes::kNc, Sizes::kNphi>", "Phi_phi",
                  {"dPhi/dphi at the solution ({unit}): its conditioning tells a dead point."}, "kNc x kNphi"),
           "m or 1"),
  };
  return o;
}

OutputSpec Rhs(const std::vector<FunctionSpec>& functions) {
  OutputSpec o =
      Output("Rhs", Generated(functions, OutputStruct::kRhs),
             "Rhs, RhsT, EvalRhs (Model::Rhs: SolveTrig, K, L, I, h, Q in one pass).",
             {"What EvalRhs() fills: the equation of motion I(q) qdd + h(q, qd) = Q(t, q, qd) at a state, with",
              "what a simulation samples there. The same definitions and units as Dynamics."});
  o.members = {
      Unit(Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq>", "K",
                  {"K(i, j) = dphi_i/dq_j: the velocity coefficients (phid = K qd)."}, "kNphi x kNq"),
           "1, m or 1/m"),
      Unit(Member(kMatNqNq, "I", {"I: the generalized inertia."}, "kNq x kNq"), "kg m^2, kg m or kg"),
      Unit(Member(kVecNq, "h", {"h = C (qd (x) qd): the centripetal and Coriolis terms."}, "kNq"), "N m or N"),
      Unit(Member(kVecNq, "Q", {"Q: the generalized applied forces at (t, q, qd)."}, "kNq"), "N m or N"),
      Unit(Member("Scalar", "T, V, P_nc", {"T = 1/2 qd^T I qd, V, and the power P_nc of the non-conservative forces."}),
           "J, J, W"),
      Unit(Member("Mat<Scalar, Sizes::kNc, Sizes::kNphi>", "Phi_phi",
                  {"dPhi/dphi at the solution: its conditioning tells a dead point."}, "kNc x kNphi"),
           "m or 1"),
  };
  return o;
}

OutputSpec RhsConstants(const std::vector<FunctionSpec>& functions) {
  const FunctionSpec* prepare = Filling(functions, OutputStruct::kRhsConstants);
  const int n = prepare ? prepare->constants : 0;
  OutputSpec o = Output("RhsConstants", Generated(functions, OutputStruct::kRhsConstants),
                        "RhsConstants, RhsConstantsT, PrepareRhs (Model::Prepare): EvalRhs' constants.",
                        {"What EvalRhs() reads that depends on the parameters only (masses, their products with",
                         "lengths, inverse squared lengths, ...): PrepareRhs() fills it once per parameter set."});
  o.members = {
      Unit(Member("std::array<Scalar, " + std::to_string(n) + ">", "c", {}), "mixed: products of the parameters")};
  return o;
}

// The generated function that Model exposes as `member`, or nullptr where it is not generated.
const FunctionSpec* ModelMember(const std::vector<FunctionSpec>& functions, const std::string& member) {
  for (const FunctionSpec& f : functions)
    if (f.model_member == member) return &f;
  return nullptr;
}

// DesignDerivatives (EvalDesignDerivatives, with a `design` section): the derivatives of the
// kinematic quantities with respect to the design parameters (symbolic/design.h).
OutputSpec DesignOutput(const Model& m, const SymbolicTable& t, const std::vector<FunctionSpec>& functions) {
  OutputSpec o = Output("DesignDerivatives", Generated(functions, OutputStruct::kDesign),
                        "DesignDerivatives, DesignDerivativesT, EvalDesignDerivatives (Model::Design): `design`.",
                        {"What EvalDesignDerivatives() fills: the derivatives of the positions, K, L and the points",
                         "with respect to the design parameters p_d (kDesignNames[d], Params members), the other",
                         "parameters and the inputs q held: dphi/dp = -Phi_phi^-1 dPhi/dp, and so on (Paul's",
                         "K and L, differentiated). Units: the quantity's per unit of p_d."});
  // Which members exist follows from Sizes (no flags of their own): dr_P_dp where kNumPoints > 0,
  // dK_dp where kOrder >= 1, dL_dp where kOrder == 2, the points' where both hold.
  const bool points = !t.r_P.empty(), K = t.requested.K, L = t.requested.L;
  o.members = {
      Unit(Member("Mat<Scalar, Sizes::kNphi, Sizes::kNumDesign>", "dphi_dp", {"dphi_dp(i, d) = dphi_i/dp_d ({unit})."},
                  "kNphi x kNumDesign"),
           "rad or m per unit of p_d"),
      Unit(Member("Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNumDesign>", "dr_P_dp",
                  {"dr_P_dp(2m + a, d) = d r_P(a, m)/dp_d, a = 0: x, 1: y ({unit})."}, "2 kNumPoints x kNumDesign", "", points),
           "m per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq * Sizes::kNumDesign>", "dK_dp",
                  {"dK_dp(i, j + kNq*d) = dK(i, j)/dp_d ({unit})."}, "kNphi x kNq kNumDesign", "", K),
           "K's unit per unit of p_d"),
      Unit(Member("Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNq * Sizes::kNumDesign>", "dK_P_dp",
                  {"dK_P_dp(2m + a, j + kNq*d) = dK_P(2m + a, j)/dp_d ({unit})."}, "2 kNumPoints x kNq kNumDesign", "",
                  K && points),
           "K_P's unit per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq * Sizes::kNq * Sizes::kNumDesign>", "dL_dp",
                  {"dL_dp(i, j + kNq*k + kNq^2*d) = dL(i, j + kNq*k)/dp_d ({unit})."}, "kNphi x kNq^2 kNumDesign", "", L),
           "L's unit per unit of p_d"),
      Unit(Member("Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNq * Sizes::kNq * Sizes::kNumDesign>", "dL_P_dp",
                  {"dL_P_dp(2m + a, j + kNq*k + kNq^2*d) = dL_P(2m + a, j + kNq*k)/dp_d ({unit})."},
                  "2 kNumPoints x kNq^2 kNumDesign", "", L && points),
           "L_P's unit per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNumTransmissionAngles, Sizes::kNumDesign>", "dmu_dp",
                  {"dmu_dp(i, d) = d mu_i/dp_d of the transmission angles (EvalTransmissionAngles), NaN at a",
                   "toggle ({unit})."},
                  "kNumTransmissionAngles x kNumDesign", "", m.design.any() && ModelMember(functions, "TransmissionAngles") != nullptr),
           "rad per unit of p_d"),
  };
  return o;
}

// StaticsDesign (EvalStaticsDesign: a design section and statics).
OutputSpec StaticsDesignOutput(const Model& m, const std::vector<FunctionSpec>& functions) {
  const StaticsLayout layout = StaticsLayout::Of(m);
  OutputSpec o = Output("StaticsDesign", Generated(functions, OutputStruct::kStaticsDesign),
                        "StaticsDesign, StaticsDesignT, EvalStaticsDesign (Model::StaticsDesign): `design` and statics.",
                        {"What EvalStaticsDesign() fills: the derivatives of the statics (Statics) with respect to the",
                         "design parameters p_d (kDesignNames[d]), q and the given friction loads held."});
  const bool forces = m.outputs.Has(Quantity::kForces), potential = m.outputs.Has(Quantity::kPotential);
  o.members = {
      Unit(Member("Mat<Scalar, Sizes::kNq, Sizes::kNumDesign>", "dQ_dp", {"dQ_dp(j, d) = dQ_j/dp_d ({unit})."},
                  "kNq x kNumDesign", "", forces),
           "N m or N per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNq, Sizes::kNumDesign>", "ddrive_dp",
                  {"ddrive_dp(j, d) = d drive_j/dp_d = -dQ_dp(j, d) ({unit})."}, "kNq x kNumDesign", "", forces),
           "N m or N per unit of p_d"),
      Unit(Member("Vec<Scalar, Sizes::kNumDesign>", "dV_dp", {"dV_dp(d) = dV/dp_d ({unit})."}, "kNumDesign", "",
                  potential),
           "J per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNumReactions, Sizes::kNumDesign>", "dR_dp",
                  {"dR_dp(i, d) = dR_i/dp_d, R as in Statics ({unit})."}, "kNumReactions x kNumDesign", "",
                  !layout.reactions.empty()),
           "N or N m per unit of p_d"),
  };
  return o;
}

// DynamicsDesign (EvalDynamicsDesign: a design section and dynamics).
OutputSpec DynamicsDesignOutput(const std::vector<FunctionSpec>& functions) {
  OutputSpec o = Output("DynamicsDesign", Generated(functions, OutputStruct::kDynamicsDesign),
                        "DynamicsDesign, DynamicsDesignT, EvalDynamicsDesign (Model::DynamicsDesign): `design` and dynamics.",
                        {"What EvalDynamicsDesign() fills: the derivatives of the equation of motion (Dynamics) with",
                         "respect to the design parameters p_d (kDesignNames[d]), t, q, qd and the given friction loads held."});
  o.members = {
      Unit(Member("Mat<Scalar, Sizes::kNq, Sizes::kNq * Sizes::kNumDesign>", "dI_dp",
                  {"dI_dp(j, k + kNq*d) = dI(j, k)/dp_d ({unit})."}, "kNq x kNq kNumDesign"),
           "I's unit per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNq, Sizes::kNq * Sizes::kNq * Sizes::kNumDesign>", "ddI_dq_dp",
                  {"ddI_dq_dp(j, k + kNq*l + kNq^2*d) = d dI_dq(j, k + kNq*l)/dp_d (one DOF: dI'/dp) ({unit})."},
                  "kNq x kNq^2 kNumDesign"),
           "I's unit per unit of q and of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNq, Sizes::kNumDesign>", "dh_dp", {"dh_dp(j, d) = dh_j/dp_d ({unit})."},
                  "kNq x kNumDesign"),
           "N m or N per unit of p_d"),
      Unit(Member("Mat<Scalar, Sizes::kNq, Sizes::kNumDesign>", "dQ_dp", {"dQ_dp(j, d) = dQ_j/dp_d ({unit})."},
                  "kNq x kNumDesign"),
           "N m or N per unit of p_d"),
      Unit(Member("Vec<Scalar, Sizes::kNumDesign>", "dT_dp, dV_dp", {"dT/dp_d and dV/dp_d ({unit})."}, "kNumDesign"),
           "J per unit of p_d"),
  };
  return o;
}

// Whether function f takes the Trig argument (sin and cos of the angles, handed out or taken).
bool TakesTrig(const FunctionSpec* f) {
  if (f == nullptr) return false;
  for (const Argument& a : f->args)
    if (a.name == "trig") return true;
  return false;
}

}  // namespace

ModelFlags ModelFlagsOf(const Model& m, const SymbolicTable& t, const std::vector<FunctionSpec>& functions) {
  const bool K = t.requested.K, L = t.requested.L, points = !t.kinematics().points.empty();
  const FunctionSpec* solve = ModelMember(functions, "Solve");
  ModelFlags f;
  f.coeffs_phi = {"kHasCoeffsPhi",
                  "Coefficients::Phi and Phi_phi: the residual and Jacobian EvalCoefficients evaluated K and L with.",
                  true};  // every generated Coefficients has them (templates/mechanism.h.mustache)
  f.K = {"kHasK", "Coefficients::K: the velocity coefficients.", K};
  f.L = {"kHasL", "Coefficients::L: the centripetal coefficients.", L};
  f.points = {"kHasPoints", "Coefficients::r_P: the points' positions (kPointNames).", points};
  f.point_velocities = {"kHasPointVelocities", "Coefficients::K_P: the points' velocity coefficients.",
                        points && K};
  f.point_accelerations = {"kHasPointAccelerations", "Coefficients::L_P: the points' centripetal coefficients.",
                           points && L};
  f.solve = {"kHasSolve", "Solve (SolvePositions), kNumBlocks, kDefaultModes, kBlockClosedForm.", solve != nullptr};
  f.named_modes = {"kHasNamedModes",
                   "kNumNamedModes, kModeNames, kNamedModes, ModesByName: the model's named assembly modes.",
                   !m.assembly_modes.empty()};
  f.trig = {"kHasTrig", "TrigT: Solve hands out sin and cos of the angles (its last argument), Coeffs takes them.",
            TakesTrig(solve) && TakesTrig(ModelMember(functions, "Coeffs"))};
  f.solve_trig = {"kHasSolveTrig", "SolveTrig (SolvePositionsTrig): every block a closed form.",
                  ModelMember(functions, "SolveTrig") != nullptr};
  f.transmission_angles = {"kHasTransmissionAngles",
                           "TransmissionAngles (EvalTransmissionAngles): kNumTransmissionAngles > 0.",
                           ModelMember(functions, "TransmissionAngles") != nullptr};
  f.switch_modes = {"kHasSwitchModes", "SwitchModes (EvalSwitchModes), kNumSwitches: switching items of the loads.",
                    ModelMember(functions, "SwitchModes") != nullptr};
  f.drawing = {"kHasDrawing", "Drawing (EvalDrawing), kNumDrawJoints, kNumDrawValues, kDrawJoint*: a scene to draw.",
               ModelMember(functions, "Drawing") != nullptr};
  f.cam_profile = {"kHasCamProfile", "CamProfile (EvalCamProfile): cams to draw.",
                   ModelMember(functions, "CamProfile") != nullptr};
  f.applied_loads = {"kHasAppliedLoads",
                     "AppliedLoads (EvalAppliedLoads), kNumAppliedLoads, kAppliedLoad*: the loads and springs to draw.",
                     ModelMember(functions, "AppliedLoads") != nullptr};
  return f;
}

std::vector<std::string> RenderedDoc(const OutputMember& member) {
  std::vector<std::string> doc = member.doc;
  for (std::string& line : doc)
    for (const auto& [mark, value] : {std::pair<std::string, const std::string*>{"{unit}", &member.unit},
                                      std::pair<std::string, const std::string*>{"{sign}", &member.sign}})
      for (size_t at = line.find(mark); at != std::string::npos; at = line.find(mark, at + value->size()))
        line.replace(at, mark.size(), *value);
  if (!member.size.empty() && !doc.empty()) doc.back() += "  (" + member.size + ")";
  return doc;
}

std::vector<OutputSpec> OutputSpecs(const Model& m,
                                    const SymbolicTable& t,
                                    const std::vector<FunctionSpec>& functions) {
  return {Statics(m, t, functions), Dynamics(functions), Excess(functions),
          Shaking(functions),       KinematicsOutput(t, functions), Rhs(functions),      RhsConstants(functions),
          DesignOutput(m, t, functions), StaticsDesignOutput(m, functions), DynamicsDesignOutput(functions)};
}

std::vector<OutputSpec> ViewStructSpecs(const Model& m,
                                        const SymbolicTable& t,
                                        const std::vector<FunctionSpec>& functions) {
  const ModelFlags f = ModelFlagsOf(m, t, functions);
  OutputSpec coefficients = Output("Coefficients", true, "", {});
  coefficients.members = {
      Member("Vec<Scalar, Sizes::kNc>", "Phi", {}),
      Member("Mat<Scalar, Sizes::kNc, Sizes::kNphi>", "Phi_phi", {}),
      Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq>", "K", {}, "", f.K.name, f.K.value),
      Member("Mat<Scalar, Sizes::kNphi, Sizes::kNq * Sizes::kNq>", "L", {}, "", f.L.name, f.L.value),
      Member("Mat<Scalar, 2, Sizes::kNumPoints>", "r_P", {}, "", f.points.name, f.points.value),
      Member("Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNq>", "K_P", {}, "", f.point_velocities.name,
             f.point_velocities.value),
      Member("Mat<Scalar, 2 * Sizes::kNumPoints, Sizes::kNq * Sizes::kNq>", "L_P", {}, "", f.point_accelerations.name,
             f.point_accelerations.value),
  };
  OutputSpec trig = Output("Trig", true, "", {});
  trig.members = {Member(kVecNq, "sin_q, cos_q", {}), Member("Vec<Scalar, Sizes::kNphi>", "sin_phi, cos_phi", {})};
  std::vector<OutputSpec> specs = {coefficients, trig};
  for (OutputSpec& o : OutputSpecs(m, t, functions)) specs.push_back(std::move(o));
  return specs;
}

}  // namespace mechgen
