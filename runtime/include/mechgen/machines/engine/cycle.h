/**
 * \file machines/engine/cycle.h
 * The cycle of a reciprocating engine model made by tools/make_engine.py at constant crank
 * speed (Paul §6.8 DYREC) and its energy loop (§6.9.2): what `<engine>_engine cycle` and
 * `<engine>_engine flywheel` compute for one design (runtime/tools/engine_main.cc) and what
 * `mechgen study` with `analysis: engine` computes per sample (study/run.h): one code for both.
 *
 * The engine is read from the model's parameters by name (ReadEngine: bore, r, l, strokes,
 * J_fly, phase_j, p_gas_j, gamma_j, beta_j, m_rod, l_G, J_rod, m_pis, T_load, c_load), its
 * coordinates (s_slide_j, theta_rod_j) and reactions (F_O, F_B_j, F_C_j, N_slide_j) by name.
 * One pressure law for every cylinder (gas.h): the parametric polytropic cycle with a Wiebe heat
 * release, whose volume follows the design's bore, stroke 2 r and rod l (InitPressureLaw), or an
 * indicator diagram (ReadPressureTable), cylinder j at the cycle angle theta - phase_j.
 *
 * RunCycle: per crank angle theta = cycle i / samples at constant speed omega the gas torque
 * T_gas = -sum p_j A ds_j/dtheta, the inertia torque T_inertia = -1/2 I'(theta) omega^2 (the
 * generated dynamics' h at thetadd = 0), T_total = T_gas + T_inertia (N m on the crank, CCW +),
 * the generalized inertia I(theta), the pressures, side thrusts, reactions (the generated
 * kinetostatics with p_gas_j set) and, for a model with `shaking`, the shaking force, moment and
 * rocking couple (couples.h). EngineEnergyLoop: the energy loop of T_total about its mean
 * (flywheel/energy_loop.h), dE, the mean of I(theta) and of its variable part; the flywheel for
 * a C_s is then J_fly = dE/(C_s omega^2) - (mean I - J_fly of the model).
 * RunCycleDesign: d/dp of T_total and I at those samples for the model's design parameters
 * (`flywheel --design`; the energy loop's derivatives from them: flywheel/energy_loop.h).
 *
 * Only for a model with `dynamics`, `forces` (statics, no Coulomb friction), a Solve and one
 * input: CanRunEngineCycle<M>() at compile time for a generated model, CanRunEngineCycle(model)
 * at run time (a model reached through its view, issue 43).
 *
 * One source, two instantiations: every function reaches its model through ModelCalls<M>
 * (core/model_calls.h), for a generated model (the per-model tool, the study; the overloads
 * without a model argument) and for mechgen::ViewModel (mechgen_view engine; runtime/view/
 * machines.cc), with the same arithmetic in the same order.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/core/model_view.h"
#include "mechgen/machines/engine/couples.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/gas.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/position/design.h"
#include "mechgen/statics/traits.h"

namespace mechgen::engine {

constexpr int kMaxCylinders = 16;

/// Whether RunCycle can be compiled for M: dynamics, statics with reactions and without Coulomb
/// friction (the kinetostatics), a position Solve, one input (the crank). Whether M is an engine is read at
/// run time (ReadEngine).
template <class M>
constexpr bool CanRunEngineCycle() {
  if constexpr (ModelCalls<M>::kView) {
    return true;  // at run time: CanRunEngineCycle(model)
  } else if constexpr (HasDynamics<M>::value && statics::StaticsFeatures<M>::kHasStatics && HasStaticsR<M>::value &&
                ModelFeatures<M>::kHasSolve) {
    return M::kNq == 1 && !statics::StaticsFeatures<M>::kHasFriction;
  } else {
    return false;
  }
}

/// The same at run time for `model` (a generated model: CanRunEngineCycle<M>()).
template <class M>
bool CanRunEngineCycle(const M& model) {
  using C = ModelCalls<M>;
  if constexpr (!CanRunEngineCycle<M>()) {
    (void)model;
    return false;
  } else {
    return C::HasDynamics(model) && C::HasStatics(model) && C::HasReactions(model) && C::HasSolve(model) &&
           C::Nq(model) == 1 && !C::HasFriction(model);
  }
}

/// One pressure law for all cylinders: the parametric cycle or a table.
struct PressureLaw {
  const PolytropicWiebeCycle* wiebe = nullptr;
  const PressureTable* table = nullptr;
  double Pressure(double a) const { return wiebe != nullptr ? wiebe->Pressure(a) : table->Pressure(a); }
};
using CycleGas = GasTorque<PressureLaw, kMaxCylinders>;

/// The engine as the model's names describe it.
struct Engine {
  static constexpr double kPi = 3.14159265358979323846;
  int n = 0;
  double bore = 0, area = 0, r = 0, l = 0, cycle = 4 * kPi, J_fly = 0;
  int strokes = 4;
  std::array<int, kMaxCylinders> slide{}, rod{}, R_B{}, R_C{}, R_N{};
  std::array<double, kMaxCylinders> gamma{}, beta{};
  std::array<double*, kMaxCylinders> p_gas{};
  int R_O = -1;
  double m_rod = 0, l_G = 0, J_rod = 0, m_pis = 0;
};

namespace cycle_internal {
template <class M>
int PhiIndex(const M& model, const std::string& name) {
  for (int i = 0; i < ModelCalls<M>::Nphi(model); ++i)
    if (name == ModelCalls<M>::PhiName(model, i)) return i;
  return -1;
}
template <class M>
int ReactionIndex(const M& model, const std::string& name) {
  for (int i = 0; i < ModelCalls<M>::NumReactions(model); ++i)
    if (name == ModelCalls<M>::ReactionName(model, i)) return i;
  return -1;
}
}  // namespace cycle_internal

/// The engine of `model` from its parameters *p (by name) into *e; false and *error when the
/// model is not an engine model of tools/make_engine.py.
template <class M>
bool ReadEngine(const M& model, typename ModelTypes<M>::Params* p, Engine* e, std::string* error) {
  auto PhiIndex = [&model](const std::string& name) { return cycle_internal::PhiIndex(model, name); };
  auto ReactionIndex = [&model](const std::string& name) { return cycle_internal::ReactionIndex(model, name); };
  auto get = [&](const std::string& name, double* v) {
    double* x = ModelCalls<M>::FindParameter(model, p, name.c_str());
    if (x == nullptr) {
      *error = "the model has no parameter '" + name + "': not an engine model of tools/make_engine.py";
      return false;
    }
    *v = *x;
    return true;
  };
  double strokes = 0, unused = 0;
  if (!get("bore", &e->bore) || !get("r", &e->r) || !get("l", &e->l) || !get("strokes", &strokes) ||
      !get("J_fly", &e->J_fly) || !get("m_rod", &e->m_rod) || !get("l_G", &e->l_G) ||
      !get("J_rod", &e->J_rod) || !get("m_pis", &e->m_pis) || !get("T_load", &unused) || !get("c_load", &unused))
    return false;
  if (strokes != 2 && strokes != 4) {
    *error = "the model's parameter strokes must be 2 or 4";
    return false;
  }
  e->strokes = static_cast<int>(strokes);
  e->cycle = e->strokes == 4 ? 4 * Engine::kPi : 2 * Engine::kPi;
  e->area = Engine::kPi * e->bore * e->bore / 4;
  e->R_O = ReactionIndex("F_O_x");
  for (int j = 0; j < kMaxCylinders; ++j) {
    const std::string k = std::to_string(j + 1);
    const int s = PhiIndex("s_slide_" + k);
    if (s < 0) break;
    e->slide[j] = s;
    e->rod[j] = PhiIndex("theta_rod_" + k);
    e->R_B[j] = ReactionIndex("F_B_" + k + "_x");
    e->R_C[j] = ReactionIndex("F_C_" + k + "_x");
    e->R_N[j] = ReactionIndex("N_slide_" + k);
    e->p_gas[j] = ModelCalls<M>::FindParameter(model, p, ("p_gas_" + k).c_str());
    if (e->rod[j] < 0 || e->R_B[j] < 0 || e->R_C[j] < 0 || e->R_N[j] < 0 || e->p_gas[j] == nullptr ||
        e->R_O < 0) {
      *error = "cylinder " + k + " lacks theta_rod_" + k + ", p_gas_" + k +
               " or the reactions F_O, F_B_" + k + ", F_C_" + k + ", N_slide_" + k;
      return false;
    }
    if (!get("gamma_" + k, &e->gamma[j]) || !get("beta_" + k, &e->beta[j]) || !get("phase_" + k, &unused))
      return false;
    e->n = j + 1;
  }
  if (e->n == 0) {
    *error = "the model has no cylinder (no coordinate s_slide_1)";
    return false;
  }
  return true;
}
/// The same for a generated model M (an empty tag).
template <class M, class Params>
bool ReadEngine(Params* p, Engine* e, std::string* error) {
  return ReadEngine(M(), p, e, error);
}

/// The pressure law of the engine e: `table` if not null, else the parametric cycle of `w` with
/// the engine's strokes, bore, stroke 2 r and rod l (initialized into *wiebe). false and *error
/// when the law's parameters do not fit together (PolytropicWiebeCycle::Init).
inline bool InitPressureLaw(const Engine& e, PolytropicWiebeParams w, const PressureTable* table,
                            PolytropicWiebeCycle* wiebe, PressureLaw* law, std::string* error) {
  *law = PressureLaw();
  if (table != nullptr) {
    law->table = table;
    return true;
  }
  w.strokes = e.strokes;
  w.bore = e.bore;
  w.stroke = 2 * e.r;
  w.rod_length = e.l;
  if (!wiebe->Init(w, error)) return false;
  law->wiebe = wiebe;
  return true;
}

/// An indicator diagram from a CSV file: rows 'angle_deg,p_gauge_Pa' over the cycle (rad) (a
/// header line and lines starting with # are skipped).
template <class ParseField>
bool ReadPressureTable(const std::string& path, double cycle, PressureTable* t, std::string* error,
                       ParseField parse_field) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read the pressure table " + path;
    return false;
  }
  std::vector<double> a, p;
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty() || line[0] == '#') continue;
    const size_t comma = line.find(',');
    double x = 0, y = 0;
    if (comma == std::string::npos || !parse_field(line.substr(0, comma), &x) ||
        !parse_field(line.substr(comma + 1), &y)) {
      if (a.empty() && row == 1) continue;  // a header
      *error = path + ":" + std::to_string(row) + ": expected 'angle_deg,p_gauge_Pa'";
      return false;
    }
    a.push_back(FromDegrees(x));
    p.push_back(y);
  }
  std::string why;
  if (!t->Set(a, p, cycle, &why)) {
    *error = path + ": " + why;
    return false;
  }
  return true;
}

namespace cycle_internal {
/// The gas torque of the engine's cylinders under `law`, phase_j by find("phase_j").
template <class Find>
CycleGas MakeGasBy(const Engine& e, const PressureLaw* law, Find find) {
  CycleGas g;
  g.law = law;
  g.cycle = e.cycle;
  g.count = e.n;
  for (int j = 0; j < e.n; ++j) {
    g.cylinders[j].slide = e.slide[j];
    g.cylinders[j].area = e.area;
    g.cylinders[j].phase = *find(("phase_" + std::to_string(j + 1)).c_str());
  }
  return g;
}
}  // namespace cycle_internal

/// The gas torque of the engine's cylinders under `law` (phase_j from *p) of `model`.
template <class M>
CycleGas MakeGas(const M& model, typename ModelTypes<M>::Params* p, const Engine& e, const PressureLaw* law) {
  return cycle_internal::MakeGasBy(e, law, [&](const char* name) { return ModelCalls<M>::FindParameter(model, p, name); });
}
/// The same on a generated model's Params (Params::Find).
template <class Params>
CycleGas MakeGas(Params* p, const Engine& e, const PressureLaw* law) {
  return cycle_internal::MakeGasBy(e, law, [p](const char* name) { return p->Find(name); });
}

namespace cycle_internal {
/// The reactions a CrankPoint holds: M's, or the most a view may have.
template <class M, bool = ModelCalls<M>::kView>
struct ReactionCount : std::integral_constant<int, M::kNumReactions> {};
template <class M>
struct ReactionCount<M, true> : std::integral_constant<int, ModelView::kMaxReactions> {};
}  // namespace cycle_internal

/// One crank angle at constant speed.
template <class M>
struct CrankPoint {
  double theta = 0, T_gas = 0, T_inertia = 0, T_total = 0, I = 0, drive = 0;
  double T1 = 0;   ///< cylinder 1 alone: its gas torque + its own inertia torque
  double I1 = 0;   ///< cylinder 1's share of I(theta)
  std::array<double, kMaxCylinders> p{}, thrust{};
  /// The reactions (the model's, in its order; for a view the first NumReactions entries).
  std::array<double, cycle_internal::ReactionCount<M>::value> R{};
  double shake_x = 0, shake_y = 0, shake_M = 0;  ///< generated shaking force and moment about O
  double rock_x = 0, rock_y = 0;  ///< rocking couple about the cylinders' middle (couples.h)
};

/// The positions of `model` at theta from *phi (warm start; the generated Solve's default modes,
/// iterations and tolerance), K and L there.
template <class M>
bool CrankPositions(const M& model, const typename ModelTypes<M>::Params& p, double theta,
                    typename ModelTypes<M>::VecPhi* phi, typename ModelTypes<M>::Coefficients* c) {
  using C = ModelCalls<M>;
  auto q = Sized<typename ModelTypes<M>::VecQ>(C::Nq(model));
  q(0) = theta;
  const auto report = C::Solve(model, p, q, phi, C::DefaultModes(model), 20, 0.0);
  if (report.status != decltype(report.status)::kConverged) return false;
  C::Coeffs(model, p, q, *phi, c);
  return true;
}
/// The same for a generated model M (an empty tag).
template <class M, class Params>
bool CrankPositions(const Params& p, double theta, Eigen::Matrix<double, M::kNphi, 1>* phi,
                    typename M::template CoefficientsT<double>* c) {
  return CrankPositions(M(), p, theta, phi, c);
}

namespace cycle_internal {
/// Cylinder j's generalized inertia and its derivative, from the generated phi, K, L (the rod
/// by its centre of mass and K_theta, the piston along its slide).
template <class VecPhi, class Coefficients>
void CylinderInertia(const Engine& e, int j, double theta, const VecPhi& phi, const Coefficients& c, double* I,
                     double* dI) {
  const double a = theta + e.gamma[j];
  const double f = phi(e.rod[j]), Kf = c.K(e.rod[j], 0), Lf = c.L(e.rod[j], 0);
  const double Ks = c.K(e.slide[j], 0), Ls = c.L(e.slide[j], 0);
  const double KGx = -e.r * std::sin(a) - e.l_G * Kf * std::sin(f);
  const double KGy = e.r * std::cos(a) + e.l_G * Kf * std::cos(f);
  const double LGx = -e.r * std::cos(a) - e.l_G * (Lf * std::sin(f) + Kf * Kf * std::cos(f));
  const double LGy = -e.r * std::sin(a) + e.l_G * (Lf * std::cos(f) - Kf * Kf * std::sin(f));
  *I = e.m_pis * Ks * Ks + e.m_rod * (KGx * KGx + KGy * KGy) + e.J_rod * Kf * Kf;
  *dI = 2 * (e.m_pis * Ks * Ls + e.m_rod * (KGx * LGx + KGy * LGy) + e.J_rod * Kf * Lf);
}

/// The generated shaking force and moment into *pt, and the rocking couple about the middle of
/// the cylinders from the links' axial positions (a model without `shaking`: zeros).
template <class M, class VecQ, class VecPhi, class Axial>
void FillShaking(const M& model, const typename ModelTypes<M>::Params& p, const VecQ& q, const VecPhi& phi,
                 const VecQ& qd, const VecQ& qdd, const typename ModelTypes<M>::Coefficients& c, const Axial& axial,
                 CrankPoint<M>* pt) {
  using C = ModelCalls<M>;
  if constexpr (C::kView || HasShaking<M>::value) {
    if (!C::HasShaking(model)) return;
    typename C::template ShakingOut<M> sh;
    C::Shaking(model, p, q, phi, qd, qdd, c, &sh);
    pt->shake_x = sh.F(0);
    pt->shake_y = sh.F(1);
    pt->shake_M = sh.M;
    const Eigen::Vector2d rock = RockingCouple(sh, axial);
    pt->rock_x = rock(0);
    pt->rock_y = rock(1);
  } else {
    (void)model, (void)p, (void)q, (void)phi, (void)qd, (void)qdd, (void)c, (void)axial, (void)pt;
  }
}
}  // namespace cycle_internal

/// The cycle at constant speed omega, `samples` crank angles from theta = 0 over the engine's
/// cycle (T_load and c_load off: the crank held at omega by a dynamometer absorbing T_total).
/// false and *error when the positions fail at an angle or the rocking couple cannot be formed.
template <class M>
bool RunCycle(const M& model, const typename ModelTypes<M>::Params& p0, const Engine& e, const CycleGas& gas,
              double omega, int samples, std::vector<CrankPoint<M>>* out, std::string* error) {
  using C = ModelCalls<M>;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  typename ModelTypes<M>::Params p = p0;
  auto param = [&](const std::string& name) { return C::FindParameter(model, &p, name.c_str()); };
  *param("T_load") = 0;
  *param("c_load") = 0;
  C::ParametersSet(model, &p);
  // The links' axial positions for the rocking couple (rod_j, piston_j at z_j; the crank at the
  // mean, the reference point).
  const auto axial = LinkAxialPositions(model, p);
  if (C::HasShaking(model) && !axial.ok()) {
    *error = std::string("rocking couple: ") + ToString(axial.status);
    return false;
  }
  const int nq = C::Nq(model), nphi = C::Nphi(model), num_reactions = C::NumReactions(model);
  auto phi = Sized<VecPhi>(nphi);
  for (int i = 0; i < nphi; ++i) phi(i) = C::AssemblyPhi(model)[i];
  out->assign(samples, CrankPoint<M>());
  for (int i = 0; i < samples; ++i) {
    CrankPoint<M>& pt = (*out)[i];
    pt.theta = e.cycle * i / samples;
    typename ModelTypes<M>::Coefficients c;
    if (!CrankPositions(model, p, pt.theta, &phi, &c)) {
      char buf[160];
      std::snprintf(buf, sizeof(buf), "the positions failed at theta = %.3f deg", ToDegrees(pt.theta));
      *error = buf;
      return false;
    }
    auto q = Sized<VecQ>(nq), qd = Sized<VecQ>(nq), qdd = Sized<VecQ>(nq);
    q(0) = pt.theta;
    qd(0) = omega;
    qdd(0) = 0;
    typename C::template DynamicsOut<M> d;
    C::Dynamics(model, p, q, phi, qd, 0.0, c, &d, nullptr);
    pt.I = d.I(0, 0);
    pt.T_inertia = -d.h(0);
    pt.T_gas = gas.Torque(pt.theta, c.K);
    pt.T_total = pt.T_gas + pt.T_inertia;
    for (int j = 0; j < e.n; ++j) {
      pt.p[j] = gas.Pressure(j, pt.theta);
      *param("p_gas_" + std::to_string(j + 1)) = pt.p[j];
    }
    C::ParametersSet(model, &p);
    typename C::template KinetostaticsOut<M> st;
    C::Kinetostatics(model, p, q, phi, qd, qdd, 0.0, c, &st, nullptr);
    pt.drive = st.drive(0);
    for (int k = 0; k < num_reactions; ++k) pt.R[k] = st.R(k);
    for (int j = 0; j < e.n; ++j) pt.thrust[j] = -st.R(e.R_N[j]);
    cycle_internal::FillShaking(model, p, q, phi, qd, qdd, c, axial, &pt);
    double I1, dI1;
    cycle_internal::CylinderInertia(e, 0, pt.theta, phi, c, &I1, &dI1);
    pt.I1 = I1;
    pt.T1 = -pt.p[0] * e.area * c.K(e.slide[0], 0) - 0.5 * dI1 * omega * omega;
  }
  return true;
}
/// The same for a generated model M (an empty tag).
template <class M, class Params>
bool RunCycle(const Params& p0, const Engine& e, const CycleGas& gas, double omega, int samples,
              std::vector<CrankPoint<M>>* out, std::string* error) {
  return RunCycle(M(), p0, e, gas, omega, samples, out, error);
}

/// The design sensitivities of RunCycle's T_total and I at its samples (`<engine>_engine flywheel
/// --design`), the pressure trace p_j(theta) held: for the design parameters d < np
/// (ModelCalls<M>::NumDesign), at theta_k = cycle k / samples (the positions continued from the
/// assembly, as RunCycle), dT_total/dp_d = -sum_j p_j A dK_slide_j/dp_d - dh/dp_d (the gas torque
/// is linear in K: GasTorque::Torque of dK/dp_d; EvalDesignDerivatives and EvalDynamicsDesign
/// at the constant speed omega through ModelCalls<M>) into (*dT)[k np + d], dI/dp_d into
/// (*dI)[k np + d]. A model without the dynamics' design derivatives (a generated one at compile
/// time, a view's at run time), or positions that fail: false and *error (one line).
template <class M>
bool RunCycleDesign(const M& model, const typename ModelTypes<M>::Params& p, const Engine& e, const CycleGas& gas,
                    double omega, int samples, std::vector<double>* dT, std::vector<double>* dI, std::string* error) {
  using C = ModelCalls<M>;
  if constexpr (!HasDynamicsDesign<M>::value) {
    (void)model, (void)p, (void)e, (void)gas, (void)omega, (void)samples, (void)dT, (void)dI;
    *error = "the model has no design derivatives of its dynamics";
    return false;
  } else {
    if (!C::HasDesign(model) || !C::HasDynamicsDesign(model)) {  // (a view's, at run time)
      *error = "the model has no design derivatives of its dynamics";
      return false;
    }
    using VecQ = typename ModelTypes<M>::VecQ;
    const int np = C::NumDesign(model), nq = C::Nq(model);
    dT->assign(static_cast<size_t>(samples) * np, 0.0);
    dI->assign(static_cast<size_t>(samples) * np, 0.0);
    auto phi = Sized<typename ModelTypes<M>::VecPhi>(C::Nphi(model));
    for (int i = 0; i < C::Nphi(model); ++i) phi(i) = C::AssemblyPhi(model)[i];
    for (int k = 0; k < samples; ++k) {
      const double theta = e.cycle * k / samples;
      typename ModelTypes<M>::Coefficients c;
      if (!CrankPositions(model, p, theta, &phi, &c)) {
        *error = "the positions failed";
        return false;
      }
      auto q = Sized<VecQ>(nq), qd = Sized<VecQ>(nq);
      q(0) = theta;
      qd(0) = omega;
      position::DesignOf<M> dc;
      C::Design(model, p, q, phi, &dc);
      typename C::template DynamicsDesignOut<M> dd;
      C::DynamicsDesign(model, p, q, phi, qd, 0.0, c, dc, &dd);
      for (int d = 0; d < np; ++d) {
        const size_t at = static_cast<size_t>(k) * np + d;
        (*dT)[at] = gas.Torque(theta, dc.dK_dp.middleCols(d, 1)) - dd.dh_dp(0, d);
        (*dI)[at] = dd.dI_dp(0, d);
      }
    }
    return true;
  }
}

/// The energy loop of a cycle (RunCycle's points): of T_total and of T_gas about their means
/// (the mean torque line is the load), the excess energy E of T_total at the samples, the mean
/// of I(theta), T_total's extremes.
struct EngineEnergy {
  flywheel::EnergyLoop loop;      ///< of T_total: mean_torque, delta_E (J)
  flywheel::EnergyLoop loop_gas;  ///< of T_gas alone
  std::vector<double> E;          ///< T_total's excess energy at the samples (J)
  double mean_I = 0;              ///< mean of I(theta) over the cycle (kg m^2)
  double I_recip = 0;             ///< mean_I - J_fly: the mean of the variable part
  double T_max = 0, T_min = 0;    ///< T_total's extremes over the samples (N m)
  std::string message;            ///< empty: usable (both loops, a positive mean torque)
  bool ok() const { return message.empty(); }
};

template <class Point>
EngineEnergy EngineEnergyLoop(const std::vector<Point>& pts, const Engine& e) {
  EngineEnergy out;
  const int n = static_cast<int>(pts.size());
  std::vector<double> T(n), Tg(n), Eg(n);
  out.E.assign(n, 0.0);
  out.T_max = -1e300;
  out.T_min = 1e300;
  for (int i = 0; i < n; ++i) {
    T[i] = pts[i].T_total;
    Tg[i] = pts[i].T_gas;
    out.mean_I += pts[i].I / n;
    out.T_max = std::max(out.T_max, T[i]);
    out.T_min = std::min(out.T_min, T[i]);
  }
  flywheel::EnergyLoopOptions lo_opt;
  lo_opt.remove_mean = true;
  out.loop = flywheel::ExcessEnergy(T.data(), n, e.cycle, 0.0, lo_opt, out.E.data());
  out.loop_gas = flywheel::ExcessEnergy(Tg.data(), n, e.cycle, 0.0, lo_opt, Eg.data());
  out.I_recip = out.mean_I - e.J_fly;
  if (!out.loop.IsUsable())
    out.message = std::string("energy loop: ") + flywheel::ToString(out.loop.status);
  else if (!out.loop_gas.IsUsable())
    out.message = std::string("energy loop (gas): ") + flywheel::ToString(out.loop_gas.status);
  else if (!(out.loop.mean_torque > 0))
    out.message = "the mean torque is not positive: no load to size a flywheel against";
  return out;
}

}  // namespace mechgen::engine
