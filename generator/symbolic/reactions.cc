// The joints' reactions (a stage of StaticsTable, statics_stage.h): what every joint kind
// shares. The multipliers Phi_phi^T lambda = -g_phi block by block; the unknowns at each
// joint (JointReaction, joints/joint_kind.h): a cut joint's force from its rows'
// multipliers (a higher pair's contact force as its kind makes it from them,
// JointKind::Contact), a tree joint's from the balance of the subtree it carries, a moment
// from the links the joint keeps from turning; the table of components, each value as the joint's
// kind makes it (JointKind::Reaction, joints/<kind>.cc); the friction joints' normal forces
// (JointKind::CoulombFriction) and relative velocities.
#include <functional>
#include <set>
#include <stdexcept>

#include "symbolic/linalg.h"
#include "symbolic/statics_stage.h"

namespace mechgen {

using GiNaC::ex;
using statics_detail::CoordinateOfJoint;
using statics_detail::Cross;
using statics_detail::Item;
using statics_detail::N;

void StaticsTable::DeriveReactions(Stage& st) {
  const Model& m = st.m;
  const Kinematics& k = st.k;
  const SymbolicTable& t = st.t;
  const int nq = st.nq, nc = st.nc;
  // ---- reactions ----
  std::set<int> needed(m.outputs.reactions.begin(), m.outputs.reactions.end());
  needed.insert(layout.friction.begin(), layout.friction.end());
  if (needed.empty() || !options.reactions) return;
  // A point input's driving constraint has a multiplier of its own (the actuator's force, also
  // an item on the point's link for the tree joints' balances), so the joints' are as without it.
  for (const Input& in : m.inputs)
    if (in.IsPoint() && !layout.friction.empty())
      m.Fail(m.friction.front().mark, "friction is not derived yet for a model driven by a point's coordinate "
                                      "(input " + PointInputName(m, in) + "); drive joints, or leave friction out");

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
      ex s = -st.gs[nq + c];
      for (int r = 0; r < nc; ++r)
        if (solved[r]) s -= st.PhiPhi(r, c) * lam[r];
      rhs[a] = s;
    }
    if (n <= kMaxSymbolicSolve) {
      GiNaC::matrix JT(n, n);
      for (int a = 0; a < n; ++a)
        for (int bb = 0; bb < n; ++bb) JT(a, bb) = st.PhiPhi(b.rows[bb], b.cols[a]);
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
            program.push_back(Store(J + "(" + N(a) + ", " + N(bb) + ")", st.PhiPhi(b.rows[bb], b.cols[a])));
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
  for (int i = 0; i < nc; ++i)
    if (k.Phi_rows[i].joint >= 0) rows_of[k.Phi_rows[i].joint].push_back(i);

  // Each joint's force on link_b (by link_a) and the point it acts at; prismatic moments; a
  // contact's couple (with its force taken off its line) and components.
  std::vector<Vec2> F(m.joints.size(), Vec2{0, 0}), F_at(m.joints.size(), Vec2{0, 0});
  std::vector<bool> have_F(m.joints.size(), false), have_M(m.joints.size(), false);
  std::vector<ex> M(m.joints.size(), 0), couple(m.joints.size(), 0);
  std::vector<std::vector<ex>> components(m.joints.size());
  std::vector<ex> var(m.joints.size(), 0);  // every joint's coordinate
  for (size_t jn = 0; jn < m.joints.size(); ++jn)
    if (const Coordinate* s = CoordinateOfJoint(m, k, static_cast<int>(jn))) var[jn] = s->symbol;
  auto fail = [&](int joint, const std::string& why) {
    const SourceMark mark = m.outputs.reactions_mark.line ? m.outputs.reactions_mark : m.friction.front().mark;
    m.Fail(mark, "the reaction at joint '" + m.joints[joint].name + "' cannot be derived: " + why);
  };
  int asking = -1;  // the joint whose reaction is being derived (for the errors)
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
    for (const Item& it : st.items)
      if (S.count(it.link) && (it.along_joint < 0 || tree_of_joint[it.along_joint] >= 0)) add(it.F, it.at, it.couple);
    for (size_t jn = 0; jn < m.joints.size(); ++jn) {
      const Joint& j = m.joints[jn];
      if (static_cast<int>(jn) == skip || S.count(j.link_a) == S.count(j.link_b)) continue;
      const ReactionForm form = KindOf(j).Reacts();
      force_of(static_cast<int>(jn));
      const double sign = S.count(j.link_b) ? 1 : -1;
      add({sign * F[jn][0], sign * F[jn][1]}, F_at[jn], sign * couple[jn]);
      if (about && form == ReactionForm::kForceAndMoment) {
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
    const ReactionForm form = KindOf(j).Reacts();
    const std::string base = (form == ReactionForm::kForceAndMoment ? "R_" : "F_") + j.name;
    if (form == ReactionForm::kContact) {  // a higher pair (always cut): its kind's force from its rows' multipliers
      if (tree_of_joint[jn] >= 0) throw std::logic_error("mechgen bug: higher pair '" + j.name + "' in the tree");
      ContactInput in{k.frames, var, {}, std::vector<bool>(m.joints.size(), false)};
      for (int row : rows_of[jn]) in.multipliers.push_back(lam[row]);
      for (size_t o = 0; o < m.joints.size(); ++o) in.in_tree[o] = tree_of_joint[o] >= 0;
      JointReaction r;
      std::string why;
      if (!KindOf(j).Contact(m, j, in, &r, &why)) {
        if (asking == jn) fail(jn, why);
        fail(asking, "it needs the contact force of " + std::string(KindOf(j).Keys().section) + " joint '" + j.name +
                         "', and " + why);
      }
      program.push_back(Define(base + "_x", r.F[0], &F[jn][0]));
      program.push_back(Define(base + "_y", r.F[1], &F[jn][1]));
      F_at[jn] = r.at;
      if (!r.M.is_zero()) program.push_back(Define("M_" + j.name, r.M, &couple[jn]));
      // The components read the named force.
      components[jn] = r.components;
      for (ex& c : components[jn]) {
        if (c.is_equal(r.F[0]))
          c = F[jn][0];
        else if (c.is_equal(r.F[1]))
          c = F[jn][1];
      }
      have_F[jn] = true;
      return;
    }
    F_at[jn] = KindOf(j).ReactionPoint(m, j, k.frames, var[jn]);
    if (tree_of_joint[jn] < 0) {  // a cut joint: its rows' multipliers
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
    } else {  // the slider's side of the rotation group: links reached over the other joints that keep
              // their links from turning (prismatic)
      std::vector<int> stack{j.link_b};
      while (!stack.empty()) {
        const int l = stack.back();
        stack.pop_back();
        if (!S.insert(l).second) continue;
        for (size_t o = 0; o < m.joints.size(); ++o)
          if (static_cast<int>(o) != jn && KindOf(m.joints[o]).Reacts() == ReactionForm::kForceAndMoment &&
              m.joints[o].Joins(l))
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
    asking = jn;
    const ReactionForm form = KindOf(m.joints[jn]).Reacts();
    if (form == ReactionForm::kForceAndMoment)
      moment_of(jn);
    else
      force_of(jn);
  }
  // The unknowns at a joint, from which its kind makes its components and its friction.
  auto unknowns = [&](int jn) {
    JointReaction r;
    r.F = F[jn];
    r.at = F_at[jn];
    r.M = KindOf(m.joints[jn]).Reacts() == ReactionForm::kContact ? couple[jn] : M[jn];
    for (int row : rows_of[jn]) r.multipliers.push_back(lam[row]);
    r.components = components[jn];
    return r;
  };
  for (size_t i = 0; i < m.outputs.reactions.size(); ++i) {
    const int jn = m.outputs.reactions[i];
    const Joint& j = m.joints[jn];
    JointReaction r = unknowns(jn);
    // Along a tree joint's line: the friction force and the actuator's (its subtree's balance
    // above leaves them out: they act apart from it; a cut joint's multipliers hold them).
    if (tree_of_joint[jn] >= 0) {
      for (size_t f = 0; f < layout.friction.size(); ++f)
        if (layout.friction[f] == jn) r.along += st.fr[f];
      for (int q = 0; q < nq; ++q)
        if (m.inputs[q].joint == jn) r.along += drive[q];
    }
    std::string why;
    const std::vector<ex> values = KindOf(j).Reaction(m, j, k.frames, r, &why);
    if (values.empty()) fail(jn, why);
    if (values.size() != KindOf(j).ReactionComponents(m, j).size())
      throw std::logic_error("mechgen bug: joint '" + j.name + "' gives a value per component of another count");
    R.insert(R.end(), values.begin(), values.end());
  }
  for (size_t i = 0; i < layout.friction.size(); ++i) {
    const int jn = layout.friction[i];
    const Joint& j = m.joints[jn];
    const JointKind& kind = KindOf(j);
    const JointFriction f = kind.CoulombFriction(m, j, m.friction[i], k.frames, unknowns(jn));
    normal.push_back(f.normal);
    gain.push_back(f.gain);
    const Coordinate* s = CoordinateOfJoint(m, k, jn);
    const ex rel = kind.RelativeMotion(m, j, k.frames, s ? ex(s->symbol) : ex(0));
    std::vector<ex> kr(nq);
    for (int q = 0; q < nq; ++q) kr[q] = st.Along(rel, q);
    K_rel.push_back(kr);
  }
}

}  // namespace mechgen
