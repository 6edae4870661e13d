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
 *
 * Only for a model with `dynamics`, `forces` (statics, no Coulomb friction), a Solve and one
 * input: CanRunEngineCycle<M>.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "mechgen/core/model_traits.h"
#include "mechgen/machines/engine/couples.h"
#include "mechgen/machines/engine/crank_dynamics.h"
#include "mechgen/machines/engine/gas.h"
#include "mechgen/machines/flywheel/energy_loop.h"
#include "mechgen/statics/traits.h"

namespace mechgen::engine {

constexpr int kMaxCylinders = 16;

/// Whether RunCycle can be compiled for M: dynamics, statics with reactions and without Coulomb
/// friction (the kinetostatics), a position Solve, one input (the crank). Whether M is an engine is read at
/// run time (ReadEngine).
template <class M>
constexpr bool CanRunEngineCycle() {
  if constexpr (HasDynamics<M>::value && statics::StaticsFeatures<M>::kHasStatics && HasStaticsR<M>::value &&
                ModelFeatures<M>::kHasSolve) {
    return M::kNq == 1 && !statics::StaticsFeatures<M>::kHasFriction;
  } else {
    return false;
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
int PhiIndex(const std::string& name) {
  for (int i = 0; i < M::kNphi; ++i)
    if (name == M::kPhiNames[i]) return i;
  return -1;
}
template <class M>
int ReactionIndex(const std::string& name) {
  for (int i = 0; i < M::kNumReactions; ++i)
    if (name == M::kReactionNames[i]) return i;
  return -1;
}
}  // namespace cycle_internal

/// The engine of the model M from its parameters *p (by name) into *e; false and *error when
/// M is not an engine model of tools/make_engine.py.
template <class M, class Params>
bool ReadEngine(Params* p, Engine* e, std::string* error) {
  using cycle_internal::PhiIndex;
  using cycle_internal::ReactionIndex;
  auto get = [&](const std::string& name, double* v) {
    double* x = p->Find(name.c_str());
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
  e->R_O = ReactionIndex<M>("F_O_x");
  for (int j = 0; j < kMaxCylinders; ++j) {
    const std::string k = std::to_string(j + 1);
    const int s = PhiIndex<M>("s_slide_" + k);
    if (s < 0) break;
    e->slide[j] = s;
    e->rod[j] = PhiIndex<M>("theta_rod_" + k);
    e->R_B[j] = ReactionIndex<M>("F_B_" + k + "_x");
    e->R_C[j] = ReactionIndex<M>("F_C_" + k + "_x");
    e->R_N[j] = ReactionIndex<M>("N_slide_" + k);
    e->p_gas[j] = p->Find(("p_gas_" + k).c_str());
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
    a.push_back(x * (Engine::kPi / 180));
    p.push_back(y);
  }
  std::string why;
  if (!t->Set(a, p, cycle, &why)) {
    *error = path + ": " + why;
    return false;
  }
  return true;
}

/// The gas torque of the engine's cylinders under `law` (phase_j from *p).
template <class Params>
CycleGas MakeGas(Params* p, const Engine& e, const PressureLaw* law) {
  CycleGas g;
  g.law = law;
  g.cycle = e.cycle;
  g.count = e.n;
  for (int j = 0; j < e.n; ++j) {
    g.cylinders[j].slide = e.slide[j];
    g.cylinders[j].area = e.area;
    g.cylinders[j].phase = *p->Find(("phase_" + std::to_string(j + 1)).c_str());
  }
  return g;
}

/// One crank angle at constant speed.
template <class M>
struct CrankPoint {
  double theta = 0, T_gas = 0, T_inertia = 0, T_total = 0, I = 0, drive = 0;
  double T1 = 0;   ///< cylinder 1 alone: its gas torque + its own inertia torque
  double I1 = 0;   ///< cylinder 1's share of I(theta)
  std::array<double, kMaxCylinders> p{}, thrust{};
  std::array<double, M::kNumReactions> R{};
  double shake_x = 0, shake_y = 0, shake_M = 0;  ///< generated shaking force and moment about O
  double rock_x = 0, rock_y = 0;  ///< rocking couple about the cylinders' middle (couples.h)
};

/// The positions at theta from *phi (warm start), K and L there.
template <class M, class Params>
bool CrankPositions(const Params& p, double theta, Eigen::Matrix<double, M::kNphi, 1>* phi,
                    typename M::template CoefficientsT<double>* c) {
  Eigen::Matrix<double, M::kNq, 1> q;
  q(0) = theta;
  const auto report = M::Solve(p, q, phi);
  if (report.status != decltype(report.status)::kConverged) return false;
  M::Coeffs(p, q, *phi, c);
  return true;
}

namespace cycle_internal {
/// Cylinder j's generalized inertia and its derivative, from the generated phi, K, L (the rod
/// by its centre of mass and K_theta, the piston along its slide).
template <class M>
void CylinderInertia(const Engine& e, int j, double theta, const Eigen::Matrix<double, M::kNphi, 1>& phi,
                     const typename M::template CoefficientsT<double>& c, double* I, double* dI) {
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
template <class MM, class Params, class VecQ, class VecPhi>
void FillShaking(const Params& p, const VecQ& q, const VecPhi& phi, const VecQ& qd, const VecQ& qdd,
                 const typename MM::template CoefficientsT<double>& c, const LinkAxial<MM::kNumLinks>& axial,
                 CrankPoint<MM>* pt) {
  if constexpr (MM::kHasShaking) {
    typename MM::template ShakingT<double> sh;
    MM::Shaking(p, q, phi, qd, qdd, c, &sh);
    pt->shake_x = sh.F(0);
    pt->shake_y = sh.F(1);
    pt->shake_M = sh.M;
    const Eigen::Vector2d rock = RockingCouple(sh, axial);
    pt->rock_x = rock(0);
    pt->rock_y = rock(1);
  } else {
    (void)p, (void)q, (void)phi, (void)qd, (void)qdd, (void)c, (void)axial, (void)pt;
  }
}
}  // namespace cycle_internal

/// The cycle at constant speed omega, `samples` crank angles from theta = 0 over the engine's
/// cycle (T_load and c_load off: the crank held at omega by a dynamometer absorbing T_total).
/// false and *error when the positions fail at an angle or the rocking couple cannot be formed.
template <class M, class Params>
bool RunCycle(const Params& p0, const Engine& e, const CycleGas& gas, double omega, int samples,
              std::vector<CrankPoint<M>>* out, std::string* error) {
  using VecQ = Eigen::Matrix<double, M::kNq, 1>;
  using VecPhi = Eigen::Matrix<double, M::kNphi, 1>;
  Params p = p0;
  *p.Find("T_load") = 0;
  *p.Find("c_load") = 0;
  // The links' axial positions for the rocking couple (rod_j, piston_j at z_j; the crank at the
  // mean, the reference point).
  const auto axial = LinkAxialPositions<M>(p);
  if (M::kHasShaking && !axial.ok()) {
    *error = std::string("rocking couple: ") + ToString(axial.status);
    return false;
  }
  VecPhi phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  out->assign(samples, CrankPoint<M>());
  for (int i = 0; i < samples; ++i) {
    CrankPoint<M>& pt = (*out)[i];
    pt.theta = e.cycle * i / samples;
    typename M::template CoefficientsT<double> c;
    if (!CrankPositions<M>(p, pt.theta, &phi, &c)) {
      char buf[160];
      std::snprintf(buf, sizeof(buf), "the positions failed at theta = %.3f deg", pt.theta / (Engine::kPi / 180));
      *error = buf;
      return false;
    }
    VecQ q, qd, qdd;
    q(0) = pt.theta;
    qd(0) = omega;
    qdd(0) = 0;
    typename M::template DynamicsT<double> d;
    M::Dynamics(p, q, phi, qd, 0.0, c, &d);
    pt.I = d.I(0, 0);
    pt.T_inertia = -d.h(0);
    pt.T_gas = gas.Torque(pt.theta, c.K);
    pt.T_total = pt.T_gas + pt.T_inertia;
    for (int j = 0; j < e.n; ++j) {
      pt.p[j] = gas.Pressure(j, pt.theta);
      *p.Find(("p_gas_" + std::to_string(j + 1)).c_str()) = pt.p[j];
    }
    typename M::template StaticsT<double> st;
    M::Kinetostatics(p, q, phi, qd, qdd, 0.0, c, &st);
    pt.drive = st.drive(0);
    for (int k = 0; k < M::kNumReactions; ++k) pt.R[k] = st.R(k);
    for (int j = 0; j < e.n; ++j) pt.thrust[j] = -st.R(e.R_N[j]);
    cycle_internal::FillShaking<M>(p, q, phi, qd, qdd, c, axial, &pt);
    double I1, dI1;
    cycle_internal::CylinderInertia<M>(e, 0, pt.theta, phi, c, &I1, &dI1);
    pt.I1 = I1;
    pt.T1 = -pt.p[0] * e.area * c.K(e.slide[0], 0) - 0.5 * dI1 * omega * omega;
  }
  return true;
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
