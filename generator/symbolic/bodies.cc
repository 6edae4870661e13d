// The bodies and their coefficients along the motion. See bodies.h.
#include "symbolic/bodies.h"

namespace mechgen {
namespace {

using GiNaC::ex;

std::string N(int i) { return std::to_string(i); }

}  // namespace

std::vector<MassiveLink> MassiveLinks(const Model& m, const Kinematics& k) {
  std::vector<MassiveLink> bodies;
  for (size_t l = 0; l < m.links.size(); ++l) {
    const MassProperties& mp = m.links[l].mass;
    if (!mp.given || m.links[l].ground) continue;
    MassiveLink b;
    b.link = static_cast<int>(l);
    b.mass = mp.mass;
    b.inertia = mp.inertia;
    const Vec2 rc = Rotate(k.frames[l].theta, mp.center_x, mp.center_y);
    b.r_G = {k.frames[l].x + rc[0], k.frames[l].y + rc[1]};
    b.theta = k.frames[l].theta;
    bodies.push_back(b);
  }
  return bodies;
}

std::vector<MassKinematics> BodyCoefficients(const std::vector<MassiveLink>& bodies, const Motion& mo, Program* program) {
  auto local = [&](const std::string& name, const ex& e) -> ex {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;
    ex sym;
    program->push_back(Define(name, e, &sym));
    return sym;
  };
  const int nq = mo.nq();
  std::vector<MassKinematics> out;
  for (const MassiveLink& b : bodies) {
    MassKinematics mk;
    mk.link = b.link;
    mk.r_G = b.r_G;
    const std::string tag = N(b.link);
    mk.mass = local("mass_" + tag, b.mass);
    mk.inertia = local("inertia_" + tag, b.inertia);
    for (int j = 0; j < nq; ++j) {
      mk.K_G.push_back({local("KG" + tag + "_x_" + N(j), mo.Along(b.r_G[0], j)),
                        local("KG" + tag + "_y_" + N(j), mo.Along(b.r_G[1], j))});
      mk.K_theta.push_back(local("Kth" + tag + "_" + N(j), mo.Along(b.theta, j)));
    }
    mk.L_G.assign(nq * nq, Vec2{0, 0});
    mk.L_theta.assign(nq * nq, 0);
    for (int j = 0; j < nq; ++j)
      for (int k = j; k < nq; ++k) {
        const std::string jk = N(j) + "_" + N(k);
        const Vec2 LG = {local("LG" + tag + "_x_" + jk, mo.Second(b.r_G[0], j, k)),
                         local("LG" + tag + "_y_" + jk, mo.Second(b.r_G[1], j, k))};
        const ex Lth = local("Lth" + tag + "_" + jk, mo.Second(b.theta, j, k));
        mk.L_G[j + nq * k] = mk.L_G[k + nq * j] = LG;
        mk.L_theta[j + nq * k] = mk.L_theta[k + nq * j] = Lth;
      }
    out.push_back(mk);
  }
  return out;
}

}  // namespace mechgen
