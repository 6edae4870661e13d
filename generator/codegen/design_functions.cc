// EvalDesignDerivatives: the design sensitivities of symbolic/design.h, stored into the
// DesignDerivatives struct (codegen/output_spec.cc).
#include "codegen/functions.h"
#include "codegen/slot_spelling.h"

namespace mechgen {
namespace {

std::string N(int i) { return std::to_string(i); }
std::string Idx(int i, int j) { return "(" + N(i) + ", " + N(j) + ")"; }

}  // namespace

FunctionSpec EvalDesignDerivativesSpec(const DesignTable& dt, const SymbolicTable& t) {
  using Dir = Argument::Direction;
  const int nq = t.nq(), nphi = t.nphi(), nd = dt.nd();
  FunctionSpec f;
  f.name = "EvalDesignDerivatives";
  f.fills = OutputStruct::kDesign;
  f.model_member = "Design";
  f.doc = {"\\brief Design sensitivities at a closed configuration: the derivatives of phi, the points, K and L",
           "(as the model has them) with respect to the design parameters kDesignNames, q held.",
           "Each block's Phi_phi is set up once: dphi/dp = -Phi_phi^-1 dPhi/dp, and K, L differentiated",
           "by the same forward substitution over the blocks."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("DesignDerivatives<Scalar>*", "out", Dir::kOut, "DesignDerivatives; not nullptr."));
  f.notes = {"\\note Phi_phi must be regular at (q, phi): near a singular configuration the derivatives grow like",
             "1/sigma_min(Phi_phi); check its conditioning first (the runtime does, with EvalCoefficients)."};
  Program P = dt.program;
  for (int i = 0; i < nphi; ++i)
    for (int d = 0; d < nd; ++d) P.push_back(Store("out->dphi_dp" + Idx(i, d), dt.dphi_dp[i][d]));
  if (dt.has_K)
    for (int i = 0; i < nphi; ++i)
      for (int c = 0; c < nq * nd; ++c) P.push_back(Store("out->dK_dp" + Idx(i, c), dt.dK_dp[i][c]));
  if (dt.has_L)
    for (int i = 0; i < nphi; ++i)
      for (int c = 0; c < nq * nq * nd; ++c) P.push_back(Store("out->dL_dp" + Idx(i, c), dt.dL_dp[i][c]));
  for (size_t pt = 0; pt < dt.dr_P_dp.size(); ++pt)
    for (int a = 0; a < 2; ++a) {
      const int row = 2 * static_cast<int>(pt) + a;
      for (int d = 0; d < nd; ++d) P.push_back(Store("out->dr_P_dp" + Idx(row, d), dt.dr_P_dp[pt][a][d]));
      if (dt.has_K)
        for (int c = 0; c < nq * nd; ++c) P.push_back(Store("out->dK_P_dp" + Idx(row, c), dt.dK_P_dp[pt][a][c]));
      if (dt.has_L)
        for (int c = 0; c < nq * nq * nd; ++c)
          P.push_back(Store("out->dL_P_dp" + Idx(row, c), dt.dL_P_dp[pt][a][c]));
    }
  for (size_t i = 0; i < dt.dmu_dp.size(); ++i)
    for (int d = 0; d < nd; ++d) P.push_back(Store("out->dmu_dp" + Idx(static_cast<int>(i), d), dt.dmu_dp[i][d]));
  PruneUnusedDefines(&P);
  f.body = {P};
  return f;
}

FunctionSpec EvalDesignChecksSpec(const DesignTable& dt) {
  using Dir = Argument::Direction;
  FunctionSpec f;
  f.name = "EvalDesignChecks";
  f.model_member = "DesignChecks";
  f.doc = {"\\brief The design checks as signed margins of the parameters (>= 0 where the design is",
           "acceptable) and their derivatives with respect to the design parameters: constraints for",
           "synthesis. The generator checks the same at the parameters' defaults."};
  for (size_t i = 0; i < dt.checks.size(); ++i)
    f.doc.push_back("  margin(" + N(static_cast<int>(i)) + ") " + dt.checks[i].name + ": " + dt.checks[i].what);
  f.args.push_back(Arg("const Params<Scalar>&", "p", Dir::kIn, "Parameters."));
  f.args.push_back(Arg("Vec<Scalar, Sizes::kNumDesignChecks>*", "margin", Dir::kOut, "the margins; not nullptr.",
                       "dim kNumDesignChecks"));
  f.args.push_back(Arg("Out<Mat<Scalar, Sizes::kNumDesignChecks, Sizes::kNumDesign>>", "dmargin_dp", Dir::kOut,
                       "d margin(i) / dp_d", "kNumDesignChecks x kNumDesign", true, "nullptr"));
  for (const DesignCheck& c : dt.checks) f.design_checks.push_back(c.name);
  Program P = dt.checks_program;
  for (size_t i = 0; i < dt.checks.size(); ++i) {
    P.push_back(Store("(*margin)(" + N(static_cast<int>(i)) + ")", dt.checks[i].margin));
    for (int d = 0; d < dt.nd(); ++d)
      P.push_back(Store("(*dmargin_dp)" + Idx(static_cast<int>(i), d), dt.checks[i].d[d], "dmargin_dp"));
  }
  PruneUnusedDefines(&P);  // a cam's geometry locals the margin does not read
  f.body = {P};
  return f;
}

FunctionSpec EvalStaticsDesignSpec(const Model& m, const StaticsTable& st, const DesignStatics& ds,
                                   CxxPrinter* printer) {
  using Dir = Argument::Direction;
  const int nd = static_cast<int>(m.design.params.size());
  FunctionSpec f;
  f.name = "EvalStaticsDesign";
  f.fills = OutputStruct::kStaticsDesign;
  f.model_member = "StaticsDesign";
  f.doc = {"\\brief Design sensitivities of the statics at a closed configuration: d/dp of Q, the drive, V and",
           "the reactions for the design parameters kDesignNames, q held and the given friction loads held",
           "(EvalStatics differentiated statement by statement; phi, K and L through EvalDesignDerivatives)."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn, "EvalCoefficients() at this (q, phi)."));
  f.args.push_back(Arg("const DesignDerivatives<Scalar>&", "dc", Dir::kIn, "EvalDesignDerivatives() at this (q, phi)."));
  f.args.push_back(Arg("StaticsDesign<Scalar>*", "out", Dir::kOut, "StaticsDesign; not nullptr."));
  if (st.layout.friction.size() > 0)
    f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                         "the friction loads EvalStatics was given (kFrictionJoints), held; nullptr: none.",
                         "dim kNumFriction", true, "nullptr"));
  f.notes = {"\\note The friction loads are held: with Coulomb friction iterated on the normal forces, the",
             "derivative of the converged friction loads is not included. Near a dead point the derivatives",
             "grow like the reactions: check the conditioning first."};
  NameSlots(st.slots, printer);
  NameSlots(ds.slots, printer);
  Program P = st.program;
  P.insert(P.end(), ds.program.begin(), ds.program.end());
  for (int j = 0; j < static_cast<int>(ds.dQ.size()); ++j)
    for (int d = 0; d < nd; ++d) {
      P.push_back(Store("out->dQ_dp" + Idx(j, d), ds.dQ[j][d]));
      P.push_back(Store("out->ddrive_dp" + Idx(j, d), ds.ddrive[j][d]));
    }
  for (int d = 0; d < static_cast<int>(ds.dV.size()); ++d) P.push_back(Store("out->dV_dp(" + N(d) + ")", ds.dV[d]));
  for (size_t i = 0; i < ds.dR.size(); ++i)
    for (int d = 0; d < nd; ++d) P.push_back(Store("out->dR_dp" + Idx(static_cast<int>(i), d), ds.dR[i][d]));
  f.body = {FinishAppliedProgram(P, st, printer)};
  return f;
}

FunctionSpec EvalDynamicsDesignSpec(const Model& m, const DynamicsTable& dyn, const DesignDynamics& dd,
                                    CxxPrinter* printer) {
  using Dir = Argument::Direction;
  const int nq = static_cast<int>(m.inputs.size()), nd = static_cast<int>(m.design.params.size());
  FunctionSpec f;
  f.name = "EvalDynamicsDesign";
  f.fills = OutputStruct::kDynamicsDesign;
  f.model_member = "DynamicsDesign";
  f.doc = {"\\brief Design sensitivities of the equation of motion at (t, q, qd): d/dp of I, dI/dq, h, Q, T",
           "and V for the design parameters kDesignNames, t, q, qd and the given friction loads held",
           "(EvalDynamics differentiated statement by statement; phi, K and L through EvalDesignDerivatives)."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities dq/dt", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn, "EvalCoefficients() at this (q, phi)."));
  f.args.push_back(Arg("const DesignDerivatives<Scalar>&", "dc", Dir::kIn, "EvalDesignDerivatives() at this (q, phi)."));
  f.args.push_back(Arg("DynamicsDesign<Scalar>*", "out", Dir::kOut, "DynamicsDesign; not nullptr."));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads (kFrictionJoints) as EvalDynamics() was given them, held; nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  const StaticsTable& a = *dyn.applied;
  NameSlots(a.slots, printer);
  NameSlots(dd.slots, printer);
  Program P = dyn.program;
  P.insert(P.end(), dd.program.begin(), dd.program.end());
  for (int d = 0; d < nd; ++d) {
    for (int jk = 0; jk < nq * nq; ++jk) P.push_back(Store("out->dI_dp" + Idx(jk % nq, jk / nq + nq * d), dd.dI[jk][d]));
    for (int jkl = 0; jkl < nq * nq * nq; ++jkl)
      P.push_back(Store("out->ddI_dq_dp" + Idx(jkl % nq, jkl / nq + nq * nq * d), dd.ddI_dq[jkl][d]));
    for (int j = 0; j < nq; ++j) {
      P.push_back(Store("out->dh_dp" + Idx(j, d), dd.dh[j][d]));
      P.push_back(Store("out->dQ_dp" + Idx(j, d), dd.dQ[j][d]));
    }
    P.push_back(Store("out->dT_dp(" + N(d) + ")", dd.dT[d]));
    P.push_back(Store("out->dV_dp(" + N(d) + ")", dd.dV[d]));
  }
  f.body = {FinishAppliedProgram(P, a, printer)};
  return f;
}

FunctionSpec EvalDynamicsDesignProductSpec(const Model& m, const DynamicsTable& dyn, const DesignTable& dt,
                                           const DesignDynamicsProduct& dp, CxxPrinter* printer) {
  using Dir = Argument::Direction;
  const int nq = static_cast<int>(m.inputs.size()), nd = static_cast<int>(m.design.params.size());
  FunctionSpec f;
  f.name = "EvalDynamicsDesignProduct";
  f.model_member = "DynamicsDesignProduct";
  f.doc = {"\\brief The product mu^T (dQ/dp - dh/dp - (dI/dp) qdd) at (t, q, qd) for given mu and qdd: one number",
           "per design parameter of kDesignNames, t, q, qd, qdd and the given friction loads held (with",
           "qdd = I^-1 (Q - h) and mu = I^-1 lambda, lambda^T f_p: the adjoint's vector-Jacobian product,",
           "dynamics/adjoint.h). Reverse mode, one pass for all N: EvalDynamics' program swept backward from",
           "that scalar, then the program of K and L from (q, phi, p) from their adjoints; phi's adjoint dotted",
           "with dphi/dp = -Phi_phi^-1 dPhi/dp (derived here as EvalDesignDerivatives derives it; where that",
           "program has an LU, the first sweep's adjoints are dotted with dK/dp and dL/dp instead)."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities dq/dt", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn, "EvalCoefficients() at this (q, phi)."));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qdd", Dir::kIn, "Input accelerations, held", "dim kNq"));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "mu", Dir::kIn,
                       "The weights of the equation of motion's rows (generalized forces' adjoint)", "dim kNq"));
  f.args.push_back(Arg("Vec<Scalar, Sizes::kNumDesign>*", "product", Dir::kOut,
                       "product(d) = mu^T (dQ/dp_d - dh/dp_d - (dI/dp_d) qdd); not nullptr", "dim kNumDesign"));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads (kFrictionJoints) as EvalDynamics() was given them, held; nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  const StaticsTable& a = *dyn.applied;
  NameSlots(a.slots, printer);
  for (int j = 0; j < nq; ++j) {
    printer->Name(dp.mu[j], "mu(" + N(j) + ")");
    printer->Name(dp.qdd[j], "qdd(" + N(j) + ")");
  }
  // The design table's program (K, L and dphi/dp from (q, phi, p): what the second sweep reads;
  // pruned to it), and where the product falls back to the forward mode's dK/dp and dL/dp (an LU
  // in that program), those in the places of the slots it reads.
  Program P = dt.program;
  for (const auto& [sym, slot] : dp.slots.all()) {
    Statement s;
    s.kind = Statement::Kind::kDefine;
    s.symbol = sym;
    s.target = "design_" + slot.SymbolName();
    switch (slot.kind) {
      case Slot::Kind::kDphiDp: s.value = dt.dphi_dp[slot.i][slot.j]; break;
      case Slot::Kind::kDKDp: s.value = dt.dK_dp[slot.i][slot.j]; break;
      case Slot::Kind::kDLDp: s.value = dt.dL_dp[slot.i][slot.j]; break;
      default: continue;
    }
    P.push_back(s);
  }
  P.insert(P.end(), dyn.program.begin(), dyn.program.end());
  P.insert(P.end(), dp.program.begin(), dp.program.end());
  for (int d = 0; d < nd; ++d) P.push_back(Store("(*product)(" + N(d) + ")", dp.grad[d]));
  f.body = {FinishAppliedProgram(P, a, printer)};
  return f;
}

}  // namespace mechgen

namespace mechgen {

FunctionSpec EvalShakingDesignSpec(const DynamicsTable& dyn, const DesignShaking& ds, CxxPrinter* printer) {
  using Dir = Argument::Direction;
  const int nd = static_cast<int>(ds.dM.size());
  FunctionSpec f;
  f.name = "EvalShakingDesign";
  f.model_member = "ShakingDesign";
  f.doc = {"\\brief Design sensitivities of the shaking force and moment (EvalShaking, Paul ch. 7) at (q, qd, qdd):",
           "d/dp of F = -sum m a_G and of M about O for the design parameters kDesignNames, q, qd and qdd held",
           "(EvalShaking differentiated statement by statement; phi, K and L through EvalDesignDerivatives).",
           "Generated exactly where the model has both kHasShaking and kHasDynamicsDesign."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities", "dim kNq"));
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qdd", Dir::kIn, "Input accelerations", "dim kNq"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn, "EvalCoefficients() at this (q, phi)."));
  f.args.push_back(Arg("const DesignDerivatives<Scalar>&", "dc", Dir::kIn, "EvalDesignDerivatives() at this (q, phi)."));
  f.args.push_back(Arg("Out<Mat<Scalar, 2, Sizes::kNumDesign>>", "dF_dp", Dir::kOut,
                       "dF_dp(a, d) = d F(a)/dp_d of Shaking::F, a = 0: x, 1: y (N per unit of p_d)",
                       "2 x kNumDesign", true));
  f.args.push_back(Arg("Out<Vec<Scalar, Sizes::kNumDesign>>", "dM_dp", Dir::kOut,
                       "dM_dp(d) = dM/dp_d of Shaking::M about O (N m per unit of p_d, CCW +)", "dim kNumDesign", true,
                       "nullptr"));
  f.notes = {"\\note Near a dead point the derivatives grow like 1/sigma_min(Phi_phi), as K and L do: check the",
             "conditioning first."};
  const StaticsTable& st = *dyn.kinetostatics;
  NameSlots(st.slots, printer);
  NameSlots(ds.slots, printer);
  Program P = ds.program;
  for (int d = 0; d < nd; ++d) {
    P.push_back(Store("(*dF_dp)" + Idx(0, d), ds.dF[0][d], "dF_dp"));
    P.push_back(Store("(*dF_dp)" + Idx(1, d), ds.dF[1][d], "dF_dp"));
    P.push_back(Store("(*dM_dp)(" + N(d) + ")", ds.dM[d], "dM_dp"));
  }
  f.body = {FinishAppliedProgram(P, st, printer)};
  return f;
}

}  // namespace mechgen

namespace mechgen {

FunctionSpec EvalDynamicsJacobianSpec(const Model& m, const DynamicsTable& dyn, const DynamicsJacobian& dj,
                                      CxxPrinter* printer) {
  using Dir = Argument::Direction;
  const int nq = static_cast<int>(m.inputs.size());
  FunctionSpec f;
  f.name = "EvalDynamicsJacobian";
  f.model_member = "DynamicsJacobian";
  f.doc = {"\\brief The Jacobians of the equation of motion's terms along the state at (t, q, qd): dQ/dq, dh/dq,",
           "dQ/dqd and dh/dqd, t and the given friction loads held (EvalDynamics differentiated statement by",
           "statement along q and qd; phi through K, K through L, L through the third-order coefficients",
           "dL/dq derived here). With Dynamics::dI_dq they give the right-hand side's Jacobians",
           "f_x = I^-1 (dQ/dx - dh/dx - (dI/dx) qdd), x = q, qd (the trajectory sensitivities).",
           "Generated with EvalDynamicsDesign (kHasDynamicsDesign) where no cam law's fourth derivative is needed."};
  f.args = AtConfiguration();
  f.args[2].doc = "Dependent variables solving Phi(q, phi) = 0";
  f.args.push_back(Arg("const Vec<Scalar, Sizes::kNq>&", "qd", Dir::kIn, "Input velocities dq/dt", "dim kNq"));
  f.args.push_back(Arg("const Scalar&", "t", Dir::kIn, "Time (s), for loads that depend on it"));
  f.args.push_back(Arg("const Coefficients<Scalar>&", "c", Dir::kIn, "EvalCoefficients() at this (q, phi)."));
  const char* what[4][2] = {{"dQ_dq", "dQ_dq(j, l) = dQ_j/dq_l along the motion (N m or N per unit of q_l)"},
                            {"dh_dq", "dh_dq(j, l) = dh_j/dq_l along the motion (N m or N per unit of q_l)"},
                            {"dQ_dqd", "dQ_dqd(j, l) = dQ_j/dqd_l (N m or N per unit of qd_l)"},
                            {"dh_dqd", "dh_dqd(j, l) = dh_j/dqd_l (N m or N per unit of qd_l)"}};
  for (const auto& w : what)
    f.args.push_back(Arg("Out<Mat<Scalar, Sizes::kNq, Sizes::kNq>>", w[0], Dir::kOut, w[1], "kNq x kNq", true,
                         "nullptr"));
  f.args.push_back(Arg("const typename NonDeduced<Vec<Scalar, Sizes::kNumFriction>>::type*", "friction", Dir::kIn,
                       "Coulomb friction loads (kFrictionJoints) as EvalDynamics() was given them, held; nullptr: none.",
                       "dim kNumFriction", true, "nullptr"));
  f.notes = {"\\note Near a dead point the derivatives grow like 1/sigma_min(Phi_phi)^2, as dL/dq does: check the",
             "conditioning first."};
  const StaticsTable& a = *dyn.applied;
  NameSlots(a.slots, printer);
  NameSlots(dj.slots, printer);
  Program P = dyn.program;
  P.insert(P.end(), dj.program.begin(), dj.program.end());
  const std::vector<std::vector<GiNaC::ex>>* out[4] = {&dj.dQ_dq, &dj.dh_dq, &dj.dQ_dqd, &dj.dh_dqd};
  for (int o = 0; o < 4; ++o)
    for (int j = 0; j < nq; ++j)
      for (int l = 0; l < nq; ++l)
        P.push_back(Store("(*" + std::string(what[o][0]) + ")" + Idx(j, l), (*out[o])[j][l], what[o][0]));
  f.body = {FinishAppliedProgram(P, a, printer)};
  return f;
}

}  // namespace mechgen
