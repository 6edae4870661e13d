// Topology: loops found from the link-joint graph, rotation groups of sliders, and the
// mobility by Grübler–Kutzbach and by the loop criterion, on shipped models.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "model/model.h"

namespace mechgen {
namespace {

const std::string kModels = std::string(MECHGEN_SOURCE_DIR) + "/models/";

TEST(Topology, FourBarHasOneLoopThroughAllJoints) {
  const Model m = LoadModel(kModels + "fourbar.yaml");
  const Topology t = BuildTopology(m);
  ASSERT_EQ(t.loops.size(), 1u);
  EXPECT_EQ(t.loops[0].joints.size(), 4u);
  EXPECT_EQ(t.loops[0].links.front(), t.loops[0].links.back());
  EXPECT_EQ(t.grubler_mobility, 1);
  EXPECT_EQ(t.loop_mobility, 1);
  EXPECT_EQ(t.tree_joints.size(), 3u);
  EXPECT_EQ(t.cut_joints.size(), 1u);
}

TEST(Topology, SliderSharesTheAngleOfItsGuide) {
  const Model m = LoadModel(kModels + "inverted_slider_crank.yaml");
  const Topology t = BuildTopology(m);
  int rocker = -1, block = -1;
  for (size_t i = 0; i < m.links.size(); ++i) {
    if (m.links[i].name == "rocker") rocker = static_cast<int>(i);
    if (m.links[i].name == "block") block = static_cast<int>(i);
  }
  EXPECT_EQ(t.group[rocker], t.group[block]);
  EXPECT_EQ(t.num_groups(), 3);  // ground, crank, rocker+block
  EXPECT_EQ(t.num_variables, 3);  // theta_crank, theta_rocker, s_slot
  const Kinematics k = DeriveKinematics(m, t);
  ASSERT_EQ(k.phi.size(), 2u);
  EXPECT_EQ(k.phi[0].name, "theta_rocker");
  EXPECT_EQ(k.phi[1].name, "s_slot");
  EXPECT_FALSE(k.phi[1].is_angle);
}

TEST(Topology, FiveBarHasTwoDegreesOfFreedom) {
  const Model m = LoadModel(kModels + "fivebar.yaml");
  const Topology t = BuildTopology(m);
  EXPECT_EQ(t.grubler_mobility, 2);
  EXPECT_EQ(t.loop_mobility, 2);
  EXPECT_EQ(t.loops.size(), 1u);
  EXPECT_EQ(t.loops[0].joints.size(), 5u);
}

TEST(Kinematics, FourBarLoopEquationVanishesAtAKnownAssembly) {
  // theta = 90 deg: B = (0, 1); C from the circle intersection computed by hand.
  const Model m = LoadModel(kModels + "fourbar.yaml");
  const Kinematics k = DeriveKinematics(m, BuildTopology(m));
  const double Bx = 0, By = 1, Dx = 4, Dy = 0, b = 3.5, c = 3.0;
  const double dx = Dx - Bx, dy = Dy - By, dist = std::hypot(dx, dy);
  const double along = (b * b - c * c + dist * dist) / (2 * dist), h = std::sqrt(b * b - along * along);
  const double Cx = Bx + along * dx / dist - h * dy / dist, Cy = By + along * dy / dist + h * dx / dist;
  GiNaC::exmap at;
  for (const Parameter& p : m.params) at[p.symbol] = p.value;
  at[k.q[0].symbol] = M_PI / 2;
  at[k.phi[0].symbol] = std::atan2(Cy - By, Cx - Bx);
  at[k.phi[1].symbol] = std::atan2(Cy - Dy, Cx - Dx);
  for (const GiNaC::ex& row : k.Phi) {
    const double v = GiNaC::ex_to<GiNaC::numeric>(row.subs(at).evalf()).to_double();
    EXPECT_NEAR(v, 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace mechgen
