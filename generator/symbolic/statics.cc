// Statics by virtual work: the layout, the stages in order (statics_stage.h) and the first
// of them, the arguments. See statics.h.
#include "symbolic/statics.h"

#include <set>

#include "joints/joint_kind.h"
#include "symbolic/statics_stage.h"

namespace mechgen {

using GiNaC::ex;

namespace statics_detail {

const Coordinate* CoordinateOfJoint(const Model& m, const Kinematics& k, int joint) {
  const auto c = KindOf(m.joints[joint]).Coordinate(m, m.joints[joint]);
  if (!c) return nullptr;
  for (const Coordinate& x : k.q)
    if (x.name == c->name) return &x;
  for (const Coordinate& x : k.phi)
    if (x.name == c->name) return &x;
  return nullptr;
}

void PrismaticLine(const Kinematics& k, const Joint& j, Vec2* u, Vec2* n) {
  *u = LineDirection(j.Data<PrismaticData>(), k.frames[j.link_a].theta);
  *n = {-(*u)[1], (*u)[0]};
}

}  // namespace statics_detail

StaticsTable::Stage::Stage(const Model& model, const Kinematics& kin, const SymbolicTable& table,
                           SlotSymbols* slot_symbols)
    : m(model),
      k(kin),
      t(table),
      slots(*slot_symbols),
      nq(kin.nq()),
      nphi(kin.nphi()),
      nc(kin.nc()),
      nx(kin.nq() + kin.nphi()),
      Kc(kin.nphi(), std::vector<ex>(kin.nq())),
      motion(
          kin, [this](int i, int j) { return Kc[i][j]; },
          [this](int i, int j, int kk) { return slots(Slot::Kind::kL, i, j + nq * kk); }),
      gf(nx, 0),
      gs(nx, 0) {}

ex StaticsTable::Stage::PhiPhi(int r, int c) const {
  return k.Phi_phi(r, c).is_zero() ? ex(0) : slots(Slot::Kind::kPhiPhi, r, c);
}

ex StaticsTable::Stage::Work(const Item& it, int a) const {
  const GiNaC::symbol& x = motion.x(a);
  ex w = it.couple * k.frames[it.link].theta.diff(x);
  if (!it.F[0].is_zero() || !it.F[1].is_zero()) w += it.F[0] * it.at[0].diff(x) + it.F[1] * it.at[1].diff(x);
  return w;
}

StaticsLayout StaticsLayout::Of(const Model& m) {
  StaticsLayout l;
  l.any = m.outputs.Has(Quantity::kForces) || m.outputs.Has(Quantity::kPotential) || !m.outputs.reactions.empty();
  for (int j : m.outputs.reactions) {
    const Joint& joint = m.joints[j];
    // The joint kind names its components (joints/<kind>.cc).
    for (const ReactionComponent& c : KindOf(joint).ReactionComponents(m, joint)) {
      l.reactions.push_back({j, c.name, joint.IsLowerPair() ? c.what
                                                            : c.what + " (the multiplier of the joint's row: its generalized "
                                                                       "force on each coordinate x is F dPhi_row/dx)"});
    }
  }
  for (const Friction& f : m.friction) l.friction.push_back(f.joint);
  return l;
}

StaticsTable::StaticsTable(const Model& m, const Kinematics& k, const SymbolicTable& t, const StaticsOptions& opt)
    : options(opt) {
  if (options.inertia || options.at_speed) options.dynamic = true;
  layout = StaticsLayout::Of(m);
  if (!layout.any) return;
  forces = m.outputs.Has(Quantity::kForces);
  potential = m.outputs.Has(Quantity::kPotential);
  stiffness = forces && potential && t.requested.L;  // for the stability of equilibria
  // The stages each mode reads (the excess formulation reads g and V only: no Q on q, no
  // actuators, no reactions), each derived once.
  Stage st(m, k, t, &slots);
  DeriveArguments(st);
  DeriveAppliedForces(st);
  if (!options.excess) DeriveDrive(st);
  DerivePotential(st);
  DeriveReactions(st);
  // The plain statics of a model whose loads read a velocity: the same at given velocities
  // (EvalStatics' `velocities`; without them the machine at rest, as this table).
  if (options.dynamic || !forces) return;
  for (const auto& [load, reads] : m.at_rest_loads)
    if (reads.find("_dot") != std::string::npos) speed_items.push_back(load + " (" + reads + ")");
  for (const Damper& d : m.dampers) speed_items.push_back("damper '" + d.name + "'");
  for (const Friction& f : m.friction)
    if (!f.viscous.is_zero()) speed_items.push_back("viscous friction at joint " + m.joints[f.joint].name);
  if (speed_items.empty()) return;
  StaticsOptions at_speed_options;
  at_speed_options.at_speed = true;
  at_speed = std::make_shared<const StaticsTable>(m, k, t, at_speed_options);
}

void StaticsTable::DeriveArguments(Stage& st) {
  const int nq = st.nq, nphi = st.nphi, nx = st.nx;
  const SymbolicTable& t = st.t;
  // ---- the slots read from EvalCoefficients' output and the arguments ----
  using Kind = Slot::Kind;
  // The bodies' coefficients derived once: a table that shares them starts from its slots.
  if (options.bodies != nullptr) slots = options.bodies->slots;
  auto& Kc = st.Kc;
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j) Kc[i][j] = slots(Kind::kK, i, j);
  for (size_t i = 0; i < layout.friction.size(); ++i) st.fr.push_back(slots(Kind::kFriction, static_cast<int>(i)));
  // The dynamic modes: the coordinates' velocities xdot = (qd, K qd).
  auto& xdot = st.xdot;

  if (options.dynamic) {
    for (int j = 0; j < nq; ++j) qd.push_back(slots(Kind::kQd, j));
    if (options.inertia)
      for (int j = 0; j < nq; ++j) qdd.push_back(slots(Kind::kQdd, j));
    time = options.at_speed ? ex(0) : slots(Kind::kTime);
    if (options.excess)
      for (int i = 0; i < nphi; ++i) phid.push_back(slots(Kind::kPhid, i));
    for (int a = 0; a < nx; ++a) {
      if (a < nq) {
        xdot.push_back(qd[a]);
        continue;
      }
      if (options.excess) {
        xdot.push_back(phid[a - nq]);
        continue;
      }
      ex v = 0;
      for (int j = 0; j < nq; ++j) v += Kc[a - nq][j] * qd[j];
      xdot.push_back(v);
    }
    if (options.bodies != nullptr) {
      const StaticsTable& b = *options.bodies;
      masses = b.masses;
      program.assign(b.program.begin(), b.program.begin() + b.body_statements);
    } else if (!options.excess && !options.at_speed) {
      masses = BodyCoefficients(t.bodies, st.motion, &program);
    }
    body_statements = program.size();
  }
}

}  // namespace mechgen
