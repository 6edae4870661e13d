// Statics by virtual work: generalized forces, driving forces, potential energy, joint
// reactions. See statics.h.
#include "symbolic/statics.h"

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

#include "joints/joint_kind.h"
#include "symbolic/linalg.h"
#include "symbolic/motion.h"

namespace mechgen {
namespace {

using GiNaC::ex;

std::string N(int i) { return std::to_string(i); }

ex Cross(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }

// Something that acts on one link: a force at a point and/or a couple.
struct Item {
  int link = -1;
  Vec2 F{0, 0};
  Vec2 at{0, 0};
  ex couple = 0;
  /// False for a pair whose virtual work is taken apart (friction: f times the joint's
  /// relative motion; the guide's point under a slider is a material point of the guide,
  /// which `at`, the slider's point, is not as a function of the coordinates).
  bool does_work = true;
  /// The prismatic joint whose friction or actuator force this is (-1: none). A cut
  /// prismatic joint's rows carry the force along its line too (s is one of the
  /// coordinates its rows close), so its multipliers already hold these forces.
  int along_joint = -1;
};

// The joint's coordinate symbol (s, psi, u), if it has one.
const Coordinate* CoordinateOfJoint(const Model& m, const Kinematics& k, int joint) {
  const auto c = KindOf(m.joints[joint]).Coordinate(m, m.joints[joint]);
  if (!c) return nullptr;
  for (const Coordinate& x : k.q)
    if (x.name == c->name) return &x;
  for (const Coordinate& x : k.phi)
    if (x.name == c->name) return &x;
  return nullptr;
}

// A prismatic joint's unit vectors along its line (u) and normal to it (n = u turned by 90 deg).
void PrismaticLine(const Kinematics& k, const Joint& j, Vec2* u, Vec2* n) {
  *u = LineDirection(j.Data<PrismaticData>(), k.frames[j.link_a].theta);
  *n = {-(*u)[1], (*u)[0]};
}

}  // namespace

StaticsLayout StaticsLayout::Of(const Model& m) {
  StaticsLayout l;
  l.any = m.outputs.Has(Quantity::kForces) || m.outputs.Has(Quantity::kPotential) || !m.outputs.reactions.empty();
  for (int j : m.outputs.reactions) {
    const Joint& joint = m.joints[j];
    const std::string by = "'" + m.links[joint.link_a].name + "' on '" + m.links[joint.link_b].name + "'";
    // The joint kind names its components; a slider's force along its line (T) is the
    // statics' own: the actuator's and friction's, between N and M.
    for (const ReactionComponent& c : KindOf(joint).ReactionComponents(m, joint)) {
      if (joint.type() == JointType::kPrismatic && c.name[0] == 'M')
        l.reactions.push_back(
            {j, "T_" + joint.name, "force of " + by + " along the line u = (cos a, sin a): actuator and friction"});
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
  if (options.inertia) options.dynamic = true;
  layout = StaticsLayout::Of(m);
  if (!layout.any) return;
  forces = m.outputs.Has(Quantity::kForces);
  potential = m.outputs.Has(Quantity::kPotential);
  stiffness = forces && potential && t.requested.L;  // for the stability of equilibria
  const int nq = k.nq(), nphi = k.nphi(), nc = k.nc(), nx = nq + nphi;

  // ---- the slots read from EvalCoefficients' output and the arguments ----
  using Kind = Slot::Kind;
  std::vector<std::vector<ex>> Kc(nphi, std::vector<ex>(nq));
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < nq; ++j) Kc[i][j] = slots(Kind::kK, i, j);
  auto phi_phi = [&](int r, int c) -> ex { return k.Phi_phi(r, c).is_zero() ? ex(0) : slots(Kind::kPhiPhi, r, c); };
  auto L = [&](int i, int j, int kk) -> ex { return slots(Kind::kL, i, j + nq * kk); };
  std::vector<ex> fr;
  for (size_t i = 0; i < layout.friction.size(); ++i) fr.push_back(slots(Kind::kFriction, static_cast<int>(i)));

  // The derivative along the motion with K and L read from the coefficients.
  const Motion mo(k, [&](int i, int j) { return Kc[i][j]; }, L);
  auto along = [&](const ex& f, int j) { return mo.Along(f, j); };
  // The dynamic modes: the coordinates' velocities xdot = (qd, K qd) and d/dt of f(x).
  std::vector<ex> xdot;
  auto ddt = [&](const ex& f) { return mo.Rate(f, xdot); };

  if (options.dynamic) {
    for (int j = 0; j < nq; ++j) qd.push_back(slots(Kind::kQd, j));
    if (options.inertia)
      for (int j = 0; j < nq; ++j) qdd.push_back(slots(Kind::kQdd, j));
    time = slots(Kind::kTime);
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
    if (!options.excess) masses = BodyCoefficients(t.bodies, mo, &program);
  }

  // ---- the loads' expressions in the coordinates ----
  GiNaC::exmap refs;
  for (const auto& [name, sym] : m.coordinate_refs) {
    bool found = false;
    for (size_t l = 0; l < m.links.size() && !found; ++l)
      if (name == "theta_" + m.links[l].name) {
        refs[sym] = k.frames[l].theta;
        found = true;
      }
    for (size_t j = 0; j < m.joints.size() && !found; ++j)
      if (const Coordinate* c = CoordinateOfJoint(m, k, static_cast<int>(j)); c && c->name == name) {
        refs[sym] = c->symbol;
        found = true;
      }
    // The reader offers only the model's own coordinates (model/statics.cc).
    if (!found) throw std::logic_error("mechgen bug: load coordinate '" + name + "' is not a coordinate");
  }
  // Time and the velocities: the arguments in the dynamic modes, 0 in the statics.
  for (const auto& [name, sym] : m.velocity_refs) {
    if (!options.dynamic) {
      refs[sym] = 0;
      continue;
    }
    if (name == "t") {
      refs[sym] = time;
      continue;
    }
    const std::string coordinate = name.substr(0, name.size() - 4);  // without "_dot"
    refs[sym] = ddt(refs.at(m.coordinate_refs.at(coordinate)));
  }

  // ---- the applied forces: items (a force at a point and/or a couple on one link) ----
  // Each item's force is kept twice: as named locals for the values (a spring's length and
  // tension computed once) and as expressions for the derivatives along the motion
  // (stiffness, d2V/dq2).
  auto position = [&](PointRef r) { return PointPosition(m, r, k.frames[r.link]); };
  std::vector<Item> items;       // everything but the joints' forces and the actuators
  std::vector<Item> items_expr;  // the same as expressions (frictionless items only)
  std::vector<bool> conservative;  // per item: a spring or a weight (part of V)
  auto add_item = [&](const Item& named_item, const Item& expr_item, bool is_conservative) {
    items.push_back(named_item);
    items_expr.push_back(expr_item);
    conservative.push_back(is_conservative);
  };
  for (const Load& l : m.loads) {
    Item it;
    it.link = l.link;
    if (l.kind == Load::Kind::kForce) {
      Vec2 F = {l.fx.subs(refs), l.fy.subs(refs)};
      if (l.link_frame) F = Rotate(k.frames[l.link].theta, F[0], F[1]);
      it.F = F;
      it.at = position(l.at);
    } else {
      it.couple = l.torque.subs(refs);
    }
    add_item(it, it, false);
  }
  V = 0;
  if (m.has_gravity)
    for (const MassiveLink& b : t.bodies) {
      V += -b.mass * (m.gravity_x * b.r_G[0] + m.gravity_y * b.r_G[1]);
      Item it;
      it.link = b.link;
      it.F = {b.mass * m.gravity_x, b.mass * m.gravity_y};
      it.at = b.r_G;
      add_item(it, it, true);
    }
  // Kinetostatics: d'Alembert's inertia forces, -m a_G at G and -J alpha, with
  // a_G = sum_j K_G,j qdd_j + sum_jk L_G,jk qd_j qd_k (the same for the angle).
  if (options.inertia)
    for (MassKinematics& mk : masses) {
      Vec2 a{0, 0};
      ex alpha = 0;
      for (int j = 0; j < nq; ++j) {
        a[0] += mk.K_G[j][0] * qdd[j];
        a[1] += mk.K_G[j][1] * qdd[j];
        alpha += mk.K_theta[j] * qdd[j];
        for (int kk = 0; kk < nq; ++kk) {
          a[0] += mk.L_G[j + nq * kk][0] * qd[j] * qd[kk];
          a[1] += mk.L_G[j + nq * kk][1] * qd[j] * qd[kk];
          alpha += mk.L_theta[j + nq * kk] * qd[j] * qd[kk];
        }
      }
      const std::string tag = N(mk.link);
      ex ax, ay, al;
      program.push_back(Define("aG" + tag + "_x", a[0], &ax));
      program.push_back(Define("aG" + tag + "_y", a[1], &ay));
      program.push_back(Define("alpha" + tag, alpha, &al));
      mk.a_G = {ax, ay};
      mk.alpha = al;
      Item it;
      it.link = mk.link;
      it.F = {-mk.mass * ax, -mk.mass * ay};
      it.at = mk.r_G;
      it.couple = -mk.inertia * al;
      add_item(it, it, false);
    }
  for (const Spring& s : m.springs) {
    if (s.torsional) {
      const Joint& j = m.joints[s.joint];
      const ex delta = k.frames[j.link_b].theta - k.frames[j.link_a].theta - s.free_angle;
      V += s.stiffness * delta * delta / 2;
      Item on_b, on_a;
      on_b.link = j.link_b;
      on_b.couple = -s.stiffness * delta;
      on_a.link = j.link_a;
      on_a.couple = s.stiffness * delta;
      add_item(on_b, on_b, true);
      add_item(on_a, on_a, true);
    } else {
      const Vec2 ra = position(s.a), rb = position(s.b);
      const ex dx = rb[0] - ra[0], dy = rb[1] - ra[1];
      const ex l = GiNaC::sqrt(dx * dx + dy * dy);
      const ex stretch = l - s.free_length;
      // The tension pulls each end towards the other: t = tension / length per unit of (dx, dy).
      ex l_named, t_named, dx_named, dy_named;
      program.push_back(Define("dx_" + s.name, dx, &dx_named));
      program.push_back(Define("dy_" + s.name, dy, &dy_named));
      program.push_back(Define("length_" + s.name, GiNaC::sqrt(dx_named * dx_named + dy_named * dy_named), &l_named));
      program.push_back(Define("t_" + s.name, (s.preload + s.stiffness * (l_named - s.free_length)) / l_named, &t_named));
      const ex stretch_named = l_named - s.free_length;
      V += s.preload * stretch_named + s.stiffness * stretch_named * stretch_named / 2;
      const ex t_expr = (s.preload + s.stiffness * stretch) / l;
      Item on_a, on_b, on_a_e, on_b_e;
      on_a.link = on_b.link = s.a.link;
      on_b.link = s.b.link;
      on_a.at = on_a_e.at = ra;
      on_b.at = on_b_e.at = rb;
      on_a_e.link = s.a.link;
      on_b_e.link = s.b.link;
      on_a.F = {t_named * dx_named, t_named * dy_named};
      on_b.F = {-t_named * dx_named, -t_named * dy_named};
      on_a_e.F = {t_expr * dx, t_expr * dy};
      on_b_e.F = {-t_expr * dx, -t_expr * dy};
      add_item(on_a, on_a_e, true);
      add_item(on_b, on_b_e, true);
    }
  }
  // Dampers (dynamic modes): a linear one's force c dl/dt pulls its ends together while it
  // extends; a torsional one's torque -c (omega_b - omega_a) acts on the joint's second link.
  if (options.dynamic)
    for (const Damper& d : m.dampers) {
      if (d.torsional) {
        const Joint& j = m.joints[d.joint];
        ex torque;
        program.push_back(Define("damper_" + d.name + "_torque",
                                 -d.coefficient * ddt(k.frames[j.link_b].theta - k.frames[j.link_a].theta), &torque));
        Item on_b, on_a;
        on_b.link = j.link_b;
        on_b.couple = torque;
        on_a.link = j.link_a;
        on_a.couple = -torque;
        add_item(on_b, on_b, false);
        add_item(on_a, on_a, false);
      } else {
        const Vec2 ra = position(d.a), rb = position(d.b);
        ex dx, dy, l, t;
        program.push_back(Define("damper_" + d.name + "_dx", rb[0] - ra[0], &dx));
        program.push_back(Define("damper_" + d.name + "_dy", rb[1] - ra[1], &dy));
        program.push_back(Define("damper_" + d.name + "_length", GiNaC::sqrt(dx * dx + dy * dy), &l));
        // Force per unit (dx, dy): c (dl/dt) / l = c (dx dx' + dy dy') / l^2.
        program.push_back(Define("damper_" + d.name + "_t",
                                 d.coefficient * (dx * ddt(rb[0] - ra[0]) + dy * ddt(rb[1] - ra[1])) / (l * l), &t));
        Item on_a, on_b;
        on_a.link = d.a.link;
        on_b.link = d.b.link;
        on_a.at = ra;
        on_b.at = rb;
        on_a.F = {t * dx, t * dy};
        on_b.F = {-t * dx, -t * dy};
        add_item(on_a, on_a, false);
        add_item(on_b, on_b, false);
      }
    }
  // Friction loads: a couple pair at a revolute joint, a force pair along a prismatic line;
  // their virtual work is f times the joint's relative motion (gf).
  std::vector<ex> gf(nx, 0);
  for (size_t i = 0; i < layout.friction.size(); ++i) {
    const Joint& j = m.joints[layout.friction[i]];
    Item on_b, on_a;
    on_b.link = j.link_b;
    on_a.link = j.link_a;
    on_b.does_work = on_a.does_work = false;
    const ex rel = j.type() == JointType::kRevolute ? k.frames[j.link_b].theta - k.frames[j.link_a].theta
                                                     : ex(CoordinateOfJoint(m, k, layout.friction[i])->symbol);
    // Viscous friction (dynamic modes) adds -c d(rel)/dt to the given Coulomb load.
    if (options.dynamic && !m.friction[i].viscous.is_zero()) {
      ex f;
      program.push_back(Define("friction_viscous_" + N(static_cast<int>(i)), fr[i] - m.friction[i].viscous * ddt(rel), &f));
      fr[i] = f;
    }
    for (int a = 0; a < nx; ++a) gf[a] += fr[i] * rel.diff(mo.x(a));
    if (j.type() == JointType::kRevolute) {
      on_b.couple = fr[i];
      on_a.couple = -fr[i];
    } else {
      Vec2 u, n;
      PrismaticLine(k, j, &u, &n);
      on_b.at = on_a.at = position(j.End(j.link_b));
      on_b.F = {fr[i] * u[0], fr[i] * u[1]};
      on_a.F = {-fr[i] * u[0], -fr[i] * u[1]};
      on_b.along_joint = on_a.along_joint = layout.friction[i];
    }
    items.push_back(on_b);
    items.push_back(on_a);
  }
  // The virtual work of an item per unit dx_a: F . d(at)/dx_a + couple d(theta)/dx_a.
  auto work = [&](const Item& it, int a) {
    const GiNaC::symbol& x = mo.x(a);
    ex w = it.couple * k.frames[it.link].theta.diff(x);
    if (!it.F[0].is_zero() || !it.F[1].is_zero()) w += it.F[0] * it.at[0].diff(x) + it.F[1] * it.at[1].diff(x);
    return w;
  };

  // ---- Q and the driving forces ----
  std::vector<ex> gs(nx, 0);  // named g_a, the generalized applied force on x_a
  for (int a = 0; a < nx; ++a) {
    ex g = gf[a];
    for (const Item& it : items)
      if (it.does_work) g += work(it, a);
    if (g.is_zero()) continue;
    program.push_back(Define("g_" + N(a), g, &gs[a]));
  }
  this->g = gs;
  Q.assign(nq, 0);
  drive.assign(nq, 0);
  std::vector<ex> Qs(nq);
  for (int j = 0; j < nq; ++j) {
    ex s = gs[j];
    for (int i = 0; i < nphi; ++i) s += Kc[i][j] * gs[nq + i];
    program.push_back(Define("Q_" + N(j), s, &Qs[j]));
    Q[j] = Qs[j];
    drive[j] = -Qs[j];
  }
  // The actuators: a couple on the input's moving link (revolute) or a force pair along the line.
  for (int j = 0; j < nq; ++j) {
    const Joint& in = m.joints[m.inputs[j].joint];
    if (in.type() == JointType::kPrismatic) {
      Vec2 u, n;
      PrismaticLine(k, in, &u, &n);
      const Vec2 at = position(in.End(in.link_b));
      Item on_b, on_a;
      on_b.link = in.link_b;
      on_b.F = {-Qs[j] * u[0], -Qs[j] * u[1]};
      on_b.at = at;
      on_a.link = in.link_a;
      on_a.F = {Qs[j] * u[0], Qs[j] * u[1]};
      on_a.at = at;
      on_b.along_joint = on_a.along_joint = m.inputs[j].joint;
      items.push_back(on_b);
      items.push_back(on_a);
    } else {
      const int moving = m.links[in.link_a].ground ? in.link_b : in.link_a;
      Item on_m, on_g;
      on_m.link = moving;
      on_m.couple = -Qs[j];
      on_g.link = in.OtherLink(moving);
      on_g.couple = Qs[j];
      items.push_back(on_m);
      items.push_back(on_g);
    }
  }

  // ---- potential energy and its derivatives along the motion ----
  // dV/dq_j = -(virtual work of the springs and weights along q_j); the second derivatives
  // from the expressions: d/dq_k of sum_a w_a V(a, j) = sum_a (d w_a/dq_k) V(a, j) +
  // sum_i w_phi_i L(i, j, k), w the virtual work per unit dx (V = [I; K]).
  auto along_motion = [&](const std::vector<Item>& list, const std::vector<bool>& pick, int j) {
    ex s = 0;
    for (size_t i = 0; i < pick.size(); ++i) {  // the applied items only (friction and actuators come after)
      if (!pick[i]) continue;
      s += work(list[i], j);
      for (int r = 0; r < nphi; ++r) s += work(list[i], nq + r) * Kc[r][j];
    }
    return s;
  };
  auto derivative = [&](const std::vector<bool>& pick, int j, int kk) {
    ex s = 0;
    for (int a = 0; a < nx; ++a) {
      ex w = 0;
      for (size_t i = 0; i < items_expr.size(); ++i)
        if (pick[i]) w += work(items_expr[i], a);
      if (w.is_zero()) continue;
      const ex d = along(w, kk);
      s += a < nq ? (a == j ? d : ex(0)) : d * Kc[a - nq][j];
      if (a >= nq) s += w * mo.L(a - nq, j, kk);
    }
    return s;
  };
  if (potential || options.dynamic) {
    dV_dq.resize(nq);
    for (int j = 0; j < nq; ++j) dV_dq[j] = -along_motion(items, conservative, j);
    if (options.dynamic) {  // Q + dV/dq: the virtual work of the loads, dampers and friction
      std::vector<bool> non_conservative(conservative.size());
      for (size_t i = 0; i < conservative.size(); ++i) non_conservative[i] = !conservative[i];
      Q_nc.resize(nq);
      for (int j = 0; j < nq; ++j) {
        ex w = along_motion(items, non_conservative, j);
        for (int a = 0; a < nx; ++a) w += gf[a] * mo.V(a, j);
        Q_nc[j] = w;
      }
    }
    if (t.requested.L && !options.dynamic) {
      d2V_dq2.resize(nq * nq);
      for (int j = 0; j < nq; ++j)
        for (int kk = 0; kk < nq; ++kk) d2V_dq2[j + nq * kk] = -derivative(conservative, j, kk);
    }
  }
  if (options.dynamic) stiffness = false;
  if (stiffness) {
    const std::vector<bool> all(items_expr.size(), true);
    stiffness_q.resize(nq * nq);
    for (int j = 0; j < nq; ++j)
      for (int kk = 0; kk < nq; ++kk) stiffness_q[j + nq * kk] = -derivative(all, j, kk);
  }

  // ---- reactions ----
  std::set<int> needed(m.outputs.reactions.begin(), m.outputs.reactions.end());
  needed.insert(layout.friction.begin(), layout.friction.end());
  if (needed.empty() || !options.reactions) return;

  // Multipliers: Phi_phi^T lambda = -g_phi, block by block in reverse order (Phi_phi is
  // block lower triangular, so its transpose is block upper triangular).
  std::vector<ex> lam(nc, 0);
  std::vector<bool> solved(nc, false);
  for (int bi = static_cast<int>(t.blocks.size()) - 1; bi >= 0; --bi) {
    const Block& b = t.blocks[bi];
    const int n = static_cast<int>(b.cols.size());
    std::vector<ex> rhs(n);
    for (int a = 0; a < n; ++a) {
      const int c = b.cols[a];
      ex s = -gs[nq + c];
      for (int r = 0; r < nc; ++r)
        if (solved[r]) s -= phi_phi(r, c) * lam[r];
      rhs[a] = s;
    }
    if (n <= kMaxSymbolicSolve) {
      GiNaC::matrix JT(n, n);
      for (int a = 0; a < n; ++a)
        for (int bb = 0; bb < n; ++bb) JT(a, bb) = phi_phi(b.rows[bb], b.cols[a]);
      ex det, inv_det;
      program.push_back(Define("detT_block" + N(bi), JT.determinant(GiNaC::determinant_algo::laplace), &det));
      program.push_back(Define("inv_detT_block" + N(bi), 1 / det, &inv_det));
      const GiNaC::matrix inv = AdjugateInverse(JT, inv_det);
      for (int a = 0; a < n; ++a) {
        const ex e = rhs[a].expand();
        if (GiNaC::is_a<GiNaC::add>(e)) program.push_back(Define("lambda_rhs_" + N(b.cols[a]), e, &rhs[a]));
        else rhs[a] = e;
      }
      for (int bb = 0; bb < n; ++bb) {
        ex s = 0;
        for (int a = 0; a < n; ++a) s += inv(bb, a) * rhs[a];
        program.push_back(Define("lambda_" + N(b.rows[bb]), s, &lam[b.rows[bb]]));
      }
    } else {
      const std::string J = "JT_block" + N(bi), lu = "luT_block" + N(bi), rv = "lambda_rhs_block" + N(bi),
                        sol = "lambda_block" + N(bi);
      program.push_back(Linear(Statement::Kind::kMatrix, J, n, n, {}, /*zero=*/true));
      for (int a = 0; a < n; ++a)
        for (int bb = 0; bb < n; ++bb)
          if (!k.Phi_phi(b.rows[bb], b.cols[a]).is_zero())
            program.push_back(Store(J + "(" + N(a) + ", " + N(bb) + ")", phi_phi(b.rows[bb], b.cols[a])));
      program.push_back(Linear(Statement::Kind::kLuFactor, lu, n, n, {J}));
      program.push_back(Linear(Statement::Kind::kMatrix, rv, n, 1));
      for (int a = 0; a < n; ++a) program.push_back(Store(rv + "(" + N(a) + ", 0)", -rhs[a]));  // LU solve negates
      Statement solve = Linear(Statement::Kind::kLuSolve, sol, n, 1, {lu, rv});
      for (int bb = 0; bb < n; ++bb) {
        GiNaC::symbol s(sol + "(" + N(bb) + ", 0)");
        solve.names.emplace_back(s, sol + "(" + N(bb) + ", 0)");
        lam[b.rows[bb]] = s;
      }
      program.push_back(solve);
    }
    for (int r : b.rows) solved[r] = true;
  }

  // Tree joints and the subtrees they carry.
  std::vector<int> tree_of_joint(m.joints.size(), -1);  // index into placements
  std::vector<std::vector<int>> children(m.links.size());
  for (size_t i = 0; i < k.placements.size(); ++i) {
    tree_of_joint[k.placements[i].joint] = static_cast<int>(i);
    children[k.placements[i].parent].push_back(k.placements[i].child);
  }
  std::vector<std::vector<int>> rows_of(m.joints.size());
  for (int i = 0; i < nc; ++i) rows_of[k.Phi_rows[i].joint].push_back(i);

  // Each joint's force on link_b (by link_a) and the point it acts at; prismatic moments.
  std::vector<Vec2> F(m.joints.size(), Vec2{0, 0}), F_at(m.joints.size(), Vec2{0, 0});
  std::vector<bool> have_F(m.joints.size(), false), have_M(m.joints.size(), false);
  std::vector<ex> M(m.joints.size(), 0);
  auto fail = [&](int joint, const std::string& why) {
    const SourceMark mark = m.outputs.reactions_mark.line ? m.outputs.reactions_mark : m.friction.front().mark;
    m.Fail(mark, "the reaction at joint '" + m.joints[joint].name + "' cannot be derived: " + why);
  };
  auto joint_point = [&](int jn) -> Vec2 {
    const Joint& j = m.joints[jn];
    return position(j.End(j.link_b));
  };
  // A tree joint's force needs only the cut joints' (multipliers), so this recursion is
  // one level deep.
  std::function<void(int)> force_of;
  std::function<void(int)> moment_of;
  // Sum of the forces (and moments about `about`, if given) acting on the links of S from
  // outside S, the joint `skip` excepted.
  auto sum_on = [&](const std::set<int>& S, int skip, const Vec2* about, Vec2* force, ex* moment) {
    *force = {0, 0};
    *moment = 0;
    auto add = [&](const Vec2& f, const Vec2& at, const ex& couple) {
      (*force)[0] += f[0];
      (*force)[1] += f[1];
      if (about) *moment += Cross({at[0] - (*about)[0], at[1] - (*about)[1]}, f) + couple;
    };
    for (const Item& it : items)
      if (S.count(it.link) && (it.along_joint < 0 || tree_of_joint[it.along_joint] >= 0)) add(it.F, it.at, it.couple);
    for (size_t jn = 0; jn < m.joints.size(); ++jn) {
      const Joint& j = m.joints[jn];
      if (static_cast<int>(jn) == skip || S.count(j.link_a) == S.count(j.link_b)) continue;
      const bool lower = j.type() == JointType::kRevolute || j.type() == JointType::kPrismatic;
      if (!lower)
        fail(skip, std::string("it needs the contact force of ") + KindOf(j).Keys().section + " joint '" + j.name +
                       "' as a vector, which mechgen derives only as the joint's multiplier; ask for reactions at "
                       "revolute and prismatic joints whose links do not carry a gear, rack, cam or rolling contact");
      force_of(static_cast<int>(jn));
      const double sign = S.count(j.link_b) ? 1 : -1;
      add({sign * F[jn][0], sign * F[jn][1]}, F_at[jn], 0);
      if (about && j.type() == JointType::kPrismatic) {
        if (!have_M[jn]) {
          if (tree_of_joint[jn] >= 0)
            fail(skip, "the moments of prismatic joints '" + m.joints[skip].name + "' and '" + j.name +
                           "' depend on each other; mechgen does not solve that case");
          moment_of(static_cast<int>(jn));
        }
        *moment += sign * M[jn];
      }
    }
  };
  auto subtree = [&](int root) {
    std::set<int> S;
    std::vector<int> stack{root};
    while (!stack.empty()) {
      const int l = stack.back();
      stack.pop_back();
      S.insert(l);
      for (int c : children[l]) stack.push_back(c);
    }
    return S;
  };
  force_of = [&](int jn) {
    if (have_F[jn]) return;
    const Joint& j = m.joints[jn];
    F_at[jn] = joint_point(jn);
    const std::string base = (j.type() == JointType::kPrismatic ? "R_" : "F_") + j.name;
    if (tree_of_joint[jn] < 0) {  // a cut joint: its rows' multipliers
      if (j.type() != JointType::kRevolute && j.type() != JointType::kPrismatic) return;
      int rx = -1, ry = -1;
      for (int r : rows_of[jn]) {
        if (k.Phi_rows[r].component == RowComponent::kX) rx = r;
        if (k.Phi_rows[r].component == RowComponent::kY) ry = r;
      }
      program.push_back(Define(base + "_x", -lam[rx], &F[jn][0]));
      program.push_back(Define(base + "_y", -lam[ry], &F[jn][1]));
    } else {
      const Placement& pl = k.placements[tree_of_joint[jn]];
      const std::set<int> S = subtree(pl.child);
      Vec2 f;
      ex unused;
      sum_on(S, jn, nullptr, &f, &unused);
      // The parent's force on the child balances the subtree; F is the force on link_b.
      const double sign = pl.child == j.link_b ? -1 : 1;
      program.push_back(Define(base + "_x", sign * f[0], &F[jn][0]));
      program.push_back(Define(base + "_y", sign * f[1], &F[jn][1]));
    }
    have_F[jn] = true;
  };
  moment_of = [&](int jn) {
    if (have_M[jn]) return;
    const Joint& j = m.joints[jn];
    force_of(jn);
    const Vec2 P = F_at[jn];
    std::set<int> S;
    int sign_to_b = 1;
    if (tree_of_joint[jn] >= 0) {
      const Placement& pl = k.placements[tree_of_joint[jn]];
      S = subtree(pl.child);
      sign_to_b = pl.child == j.link_b ? 1 : -1;
    } else {  // the slider's side of the rotation group: links reached over the other prismatic joints
      std::vector<int> stack{j.link_b};
      while (!stack.empty()) {
        const int l = stack.back();
        stack.pop_back();
        if (!S.insert(l).second) continue;
        for (size_t o = 0; o < m.joints.size(); ++o)
          if (static_cast<int>(o) != jn && m.joints[o].type() == JointType::kPrismatic && m.joints[o].Joins(l))
            stack.push_back(m.joints[o].OtherLink(l));
      }
      if (S.count(j.link_a)) fail(jn, "its prismatic joints close a loop of their own");
    }
    Vec2 f;
    ex moment;
    sum_on(S, jn, &P, &f, &moment);
    program.push_back(Define("M_" + j.name, -sign_to_b * moment, &M[jn]));
    have_M[jn] = true;
  };
  for (int jn : needed) {
    const Joint& j = m.joints[jn];
    if (j.type() == JointType::kRevolute) force_of(jn);
    else if (j.type() == JointType::kPrismatic) moment_of(jn);
    else if (tree_of_joint[jn] >= 0)
      fail(jn, "a rolling joint in the spanning tree: its contact force is not derived yet");
  }
  for (const StaticsLayout::Component& c : layout.reactions) {
    const Joint& j = m.joints[c.joint];
    if (j.type() == JointType::kRevolute) {
      R.push_back(c.name.back() == 'x' ? F[c.joint][0] : F[c.joint][1]);
    } else if (j.type() == JointType::kPrismatic) {
      Vec2 u, n;
      PrismaticLine(k, j, &u, &n);
      if (c.name[0] == 'N') R.push_back(F[c.joint][0] * n[0] + F[c.joint][1] * n[1]);
      else if (c.name[0] == 'T') {
        // Along the line: the friction force and the actuator's (a tree joint's balance above
        // leaves them out: they act apart from it).
        ex T = F[c.joint][0] * u[0] + F[c.joint][1] * u[1];
        if (tree_of_joint[c.joint] >= 0) {  // a cut joint's multipliers hold them already
          for (size_t i = 0; i < layout.friction.size(); ++i)
            if (layout.friction[i] == c.joint) T += fr[i];
          for (int j = 0; j < nq; ++j)
            if (m.inputs[j].joint == c.joint) T += drive[j];
        }
        R.push_back(T);
      }
      else R.push_back(M[c.joint]);
    } else {
      // A higher pair: the multiplier of its row (its contact force, in the row's scale).
      if (rows_of[c.joint].size() != 1) fail(c.joint, "a contour cam's contact is not derived yet");
      R.push_back(lam[rows_of[c.joint][0]]);
    }
  }
  for (size_t i = 0; i < layout.friction.size(); ++i) {
    const int jn = layout.friction[i];
    const Joint& j = m.joints[jn];
    const Friction& f = m.friction[i];
    if (j.type() == JointType::kRevolute) {
      normal.push_back(GiNaC::sqrt(F[jn][0] * F[jn][0] + F[jn][1] * F[jn][1]));
      gain.push_back(f.coefficient * f.pin_radius);
      const ex rel = k.frames[j.link_b].theta - k.frames[j.link_a].theta;
      std::vector<ex> kr(nq);
      for (int q = 0; q < nq; ++q) kr[q] = along(rel, q);
      K_rel.push_back(kr);
    } else {
      Vec2 u, n;
      PrismaticLine(k, j, &u, &n);
      normal.push_back(GiNaC::abs(F[jn][0] * n[0] + F[jn][1] * n[1]));
      gain.push_back(f.coefficient);
      const Coordinate* s = CoordinateOfJoint(m, k, jn);
      std::vector<ex> kr(nq);
      for (int q = 0; q < nq; ++q) kr[q] = along(s->symbol, q);
      K_rel.push_back(kr);
    }
  }
}

}  // namespace mechgen
