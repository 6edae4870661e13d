// The applied forces and the potential energy (stages of StaticsTable, statics_stage.h):
// loads, weights, d'Alembert's inertia forces, springs, dampers and friction as items on
// the links and their generalized forces g on x = (q, phi); Q = g_q + K^T g_phi, the drive
// and the actuators' items (for the reactions); V and its derivatives along the motion.
#include <stdexcept>

#include "symbolic/statics_stage.h"

namespace mechgen {

using GiNaC::ex;
using statics_detail::CoordinateOfJoint;
using statics_detail::Item;
using statics_detail::N;
using statics_detail::PrismaticLine;

void StaticsTable::DeriveAppliedForces(Stage& st) {
  const Model& m = st.m;
  const Kinematics& k = st.k;
  const SymbolicTable& t = st.t;
  const int nq = st.nq, nx = st.nx;
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
  // Time and the velocities: the arguments in the dynamic modes, 0 in the statics (the statics
  // at given velocities: t = 0, `time`).
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
    refs[sym] = st.Ddt(refs.at(m.coordinate_refs.at(coordinate)));
  }

  // ---- the applied forces: items (a force at a point and/or a couple on one link) ----
  // Each item's force is kept twice: as named locals for the values (a spring's length and
  // tension computed once) and as expressions for the derivatives along the motion
  // (stiffness, d2V/dq2).
  auto& items = st.items;
  auto& items_expr = st.items_expr;
  auto& conservative = st.conservative;
  marks.clear();
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
      it.at = st.Position(l.at);
    } else {
      it.couple = l.torque.subs(refs);
    }
    add_item(it, it, false);
    // The picture's mark: the item's own point and vector (a couple at its link's pivot).
    Mark mark;
    mark.name = l.name;
    if (l.kind == Load::Kind::kForce) {
      mark.at = mark.b = it.at;
      mark.F = it.F;
    } else {
      mark.kind = Mark::Kind::kTorque;
      PointRef pivot;
      for (int ground_first = 1; ground_first >= 0 && pivot.link < 0; --ground_first)
        for (const Joint& j : m.joints)
          if (pivot.link < 0 && j.type() == JointType::kRevolute && j.Joins(l.link) &&
              (!ground_first || m.links[j.OtherLink(l.link)].ground))
            pivot = j.End(l.link);
      const Frame& fr = k.frames[l.link];
      mark.at = mark.b = pivot.link >= 0 ? st.Position(pivot) : Vec2{fr.x, fr.y};
      mark.value = it.couple;
    }
    marks.push_back(mark);
  }
  V = 0;
  // The weights' marks come after the springs' (the loads' and springs' columns keep their
  // places): "W_<link>" at G, m g, |m g|. The weight acts on the link as one item at its
  // combined centre; the picture draws where its masses are: a link with point masses
  // (links.cc combined them) gets "W_<link>" for its own mass at its own centre, when it has
  // one, and "W_<link>_<point mass>" at each point mass. The same forces: their virtual work
  // is the combined weight's.
  std::vector<Mark> weight_marks;
  const ex g_norm = GiNaC::sqrt(m.gravity_x * m.gravity_x + m.gravity_y * m.gravity_y);
  auto weight_mark = [&](const std::string& name, const ex& mass, const Vec2& at) {
    Mark mark;
    mark.kind = Mark::Kind::kWeight;
    mark.name = name;
    mark.at = mark.b = at;
    mark.F = {mass * m.gravity_x, mass * m.gravity_y};
    mark.value = mass * g_norm;
    weight_marks.push_back(mark);
  };
  if (m.has_gravity)
    for (const MassiveLink& b : t.bodies) {
      V += -b.mass * (m.gravity_x * b.r_G[0] + m.gravity_y * b.r_G[1]);
      Item it;
      it.link = b.link;
      it.F = {b.mass * m.gravity_x, b.mass * m.gravity_y};
      it.at = b.r_G;
      add_item(it, it, true);
      const Link& link = m.links[b.link];
      if (link.point_masses.empty()) {
        weight_mark("W_" + link.name, b.mass, it.at);
        continue;
      }
      // The link's own mass and centre: the combined body less its point masses (exact: the
      // combined mass is their sum, its centre their first moment over it).
      const MassProperties& all = link.mass;
      ex own = all.mass, own_x = all.mass * all.center_x, own_y = all.mass * all.center_y;
      for (const PointMass& pm : link.point_masses) {
        own -= pm.mass;
        own_x -= pm.mass * pm.x;
        own_y -= pm.mass * pm.y;
      }
      own = GiNaC::normal(own);
      const Frame& fr = k.frames[b.link];
      auto fixed = [&](const ex& x, const ex& y) {
        const Vec2 r = Rotate(fr.theta, x, y);
        return Vec2{fr.x + r[0], fr.y + r[1]};
      };
      if (!own.is_zero())
        weight_mark("W_" + link.name, own, fixed(GiNaC::normal(own_x / own), GiNaC::normal(own_y / own)));
      for (const PointMass& pm : link.point_masses)
        weight_mark("W_" + link.name + "_" + pm.name, pm.mass, fixed(pm.x, pm.y));
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
      Mark mark;
      mark.kind = Mark::Kind::kTorsionalSpring;
      mark.name = s.name;
      mark.at = mark.b = st.Position(j.End(j.link_b));
      mark.value = on_b.couple;
      marks.push_back(mark);
    } else {
      const Vec2 ra = st.Position(s.a), rb = st.Position(s.b);
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
      // The picture's mark: the items' expressions (not the locals of this table's program).
      Mark mark;
      mark.kind = Mark::Kind::kSpring;
      mark.name = s.name;
      mark.at = ra;
      mark.b = rb;
      mark.F = on_a_e.F;
      mark.value = s.preload + s.stiffness * stretch;
      marks.push_back(mark);
    }
  }
  marks.insert(marks.end(), weight_marks.begin(), weight_marks.end());
  // Dampers (dynamic modes): a linear one's force c dl/dt pulls its ends together while it
  // extends; a torsional one's torque -c (omega_b - omega_a) acts on the joint's second link.
  if (options.dynamic)
    for (const Damper& d : m.dampers) {
      if (d.torsional) {
        const Joint& j = m.joints[d.joint];
        ex torque;
        program.push_back(Define("damper_" + d.name + "_torque",
                                 -d.coefficient * st.Ddt(k.frames[j.link_b].theta - k.frames[j.link_a].theta), &torque));
        Item on_b, on_a;
        on_b.link = j.link_b;
        on_b.couple = torque;
        on_a.link = j.link_a;
        on_a.couple = -torque;
        add_item(on_b, on_b, false);
        add_item(on_a, on_a, false);
      } else {
        const Vec2 ra = st.Position(d.a), rb = st.Position(d.b);
        ex dx, dy, l, t;
        program.push_back(Define("damper_" + d.name + "_dx", rb[0] - ra[0], &dx));
        program.push_back(Define("damper_" + d.name + "_dy", rb[1] - ra[1], &dy));
        program.push_back(Define("damper_" + d.name + "_length", GiNaC::sqrt(dx * dx + dy * dy), &l));
        // Force per unit (dx, dy): c (dl/dt) / l = c (dx dx' + dy dy') / l^2.
        program.push_back(Define("damper_" + d.name + "_t",
                                 d.coefficient * (dx * st.Ddt(rb[0] - ra[0]) + dy * st.Ddt(rb[1] - ra[1])) / (l * l), &t));
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
  auto& gf = st.gf;
  auto& fr = st.fr;
  for (size_t i = 0; i < layout.friction.size(); ++i) {
    const Joint& j = m.joints[layout.friction[i]];
    Item on_b, on_a;
    on_b.link = j.link_b;
    on_a.link = j.link_a;
    on_b.does_work = on_a.does_work = false;
    const Coordinate* s = CoordinateOfJoint(m, k, layout.friction[i]);
    const ex rel = KindOf(j).RelativeMotion(m, j, k.frames, s ? ex(s->symbol) : ex(0));
    // Viscous friction (dynamic modes) adds -c d(rel)/dt to the given Coulomb load.
    if (options.dynamic && !m.friction[i].viscous.is_zero()) {
      ex f;
      program.push_back(Define("friction_viscous_" + N(static_cast<int>(i)), fr[i] - m.friction[i].viscous * st.Ddt(rel), &f));
      fr[i] = f;
    }
    for (int a = 0; a < nx; ++a) gf[a] += fr[i] * rel.diff(st.motion.x(a));
    if (j.type() == JointType::kRevolute) {
      on_b.couple = fr[i];
      on_a.couple = -fr[i];
    } else {
      Vec2 u, n;
      PrismaticLine(k, j, &u, &n);
      on_b.at = on_a.at = st.Position(j.End(j.link_b));
      on_b.F = {fr[i] * u[0], fr[i] * u[1]};
      on_a.F = {-fr[i] * u[0], -fr[i] * u[1]};
      on_b.along_joint = on_a.along_joint = layout.friction[i];
    }
    items.push_back(on_b);
    items.push_back(on_a);
  }

  // ---- Q and the driving forces ----
  auto& gs = st.gs;  // named g_a, the generalized applied force on x_a
  for (int a = 0; a < nx; ++a) {
    ex g = gf[a];
    for (const Item& it : items)
      if (it.does_work) g += st.Work(it, a);
    if (g.is_zero()) continue;
    program.push_back(Define("g_" + N(a), g, &gs[a]));
  }
  this->g = gs;
}

void StaticsTable::DeriveDrive(Stage& st) {
  const Model& m = st.m;
  const Kinematics& k = st.k;
  const int nq = st.nq, nphi = st.nphi;
  auto& items = st.items;
  const auto& gs = st.gs;
  Q.assign(nq, 0);
  drive.assign(nq, 0);
  std::vector<ex> Qs(nq);
  for (int j = 0; j < nq; ++j) {
    ex s = gs[j];
    for (int i = 0; i < nphi; ++i) s += st.Kc[i][j] * gs[nq + i];
    program.push_back(Define("Q_" + N(j), s, &Qs[j]));
    Q[j] = Qs[j];
    drive[j] = -Qs[j];
  }
  // The actuators: a couple on the input's moving link (revolute) or a force pair along the line.
  for (int j = 0; j < nq; ++j) {
    const Input& input = m.inputs[j];
    if (input.IsPoint()) {
      // A force along x (or y) at the driven point, its reaction on the ground.
      const Vec2 at = st.Position(input.point);
      const int xy = input.kind == Input::Kind::kPointX ? 0 : 1;
      Item on_p, on_g;
      on_p.link = input.point.link;
      on_p.F = {xy == 0 ? -Qs[j] : ex(0), xy == 1 ? -Qs[j] : ex(0)};
      on_p.at = at;
      on_g.link = m.ground;
      on_g.F = {xy == 0 ? Qs[j] : ex(0), xy == 1 ? Qs[j] : ex(0)};
      on_g.at = at;
      items.push_back(on_p);
      items.push_back(on_g);
      continue;
    }
    if (input.kind == Input::Kind::kAngle) {  // a couple on the link, against the ground
      Item on_l, on_g;
      on_l.link = input.link;
      on_l.couple = -Qs[j];
      on_g.link = m.ground;
      on_g.couple = Qs[j];
      items.push_back(on_l);
      items.push_back(on_g);
      continue;
    }
    const Joint& in = m.joints[input.joint];
    if (in.type() == JointType::kSlot || in.type() == JointType::kPrismatic) {
      // A force along the slide on link_b (the pin, the slider), its reaction on link_a.
      Vec2 u, n, at;
      if (in.type() == JointType::kSlot) {
        const SlotData& d = in.Data<SlotData>();
        u = SlotDirection(m, d, k.frames[in.link_a].theta);
        at = st.Position(d.pin);
      } else {
        PrismaticLine(k, in, &u, &n);
        at = st.Position(in.End(in.link_b));
      }
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
}

void StaticsTable::DerivePotential(Stage& st) {
  const SymbolicTable& t = st.t;
  const int nq = st.nq, nphi = st.nphi, nx = st.nx;
  // ---- potential energy and its derivatives along the motion ----
  // dV/dq_j = -(virtual work of the springs and weights along q_j); the second derivatives
  // from the expressions: d/dq_k of sum_a w_a V(a, j) = sum_a (d w_a/dq_k) V(a, j) +
  // sum_i w_phi_i L(i, j, k), w the virtual work per unit dx (V = [I; K]).
  auto along_motion = [&](const std::vector<Item>& list, const std::vector<bool>& pick, int j) {
    ex s = 0;
    for (size_t i = 0; i < pick.size(); ++i) {  // the applied items only (friction and actuators come after)
      if (!pick[i]) continue;
      s += st.Work(list[i], j);
      for (int r = 0; r < nphi; ++r) s += st.Work(list[i], nq + r) * st.Kc[r][j];
    }
    return s;
  };
  auto derivative = [&](const std::vector<bool>& pick, int j, int kk) {
    ex s = 0;
    for (int a = 0; a < nx; ++a) {
      ex w = 0;
      for (size_t i = 0; i < st.items_expr.size(); ++i)
        if (pick[i]) w += st.Work(st.items_expr[i], a);
      if (w.is_zero()) continue;
      const ex d = st.Along(w, kk);
      s += a < nq ? (a == j ? d : ex(0)) : d * st.Kc[a - nq][j];
      if (a >= nq) s += w * st.motion.L(a - nq, j, kk);
    }
    return s;
  };
  // Each mode derives what its function reads: dV/dq the statics and the kinetostatics (the
  // `potential` quantity), Q_nc the applied forces' table (EvalDynamics' P_nc), d2V/dq2 the
  // statics; the excess formulation none of them (it reads g and V).
  const bool applied_forces = options.dynamic && !options.inertia && !options.excess && !options.at_speed;
  if (potential && !applied_forces && !options.excess) {
    dV_dq.resize(nq);
    for (int j = 0; j < nq; ++j) dV_dq[j] = -along_motion(st.items, st.conservative, j);
  }
  if (applied_forces) {  // Q + dV/dq: the virtual work of the loads, dampers and friction
    std::vector<bool> non_conservative(st.conservative.size());
    for (size_t i = 0; i < st.conservative.size(); ++i) non_conservative[i] = !st.conservative[i];
    Q_nc.resize(nq);
    for (int j = 0; j < nq; ++j) {
      ex w = along_motion(st.items, non_conservative, j);
      for (int a = 0; a < nx; ++a) w += st.gf[a] * st.motion.V(a, j);
      Q_nc[j] = w;
    }
  }
  if (potential && t.requested.L && !options.dynamic) {
    d2V_dq2.resize(nq * nq);
    for (int j = 0; j < nq; ++j)
      for (int kk = 0; kk < nq; ++kk) d2V_dq2[j + nq * kk] = -derivative(st.conservative, j, kk);
  }
  if (options.dynamic) stiffness = false;
  if (stiffness) {
    const std::vector<bool> all(st.items_expr.size(), true);
    stiffness_q.resize(nq * nq);
    for (int j = 0; j < nq; ++j)
      for (int kk = 0; kk < nq; ++kk) stiffness_q[j + nq * kk] = -derivative(all, j, kk);
  }
}

}  // namespace mechgen
