// Loop closure and rigid geometry of every shipped model over full sweeps of its inputs
// (720 points over a crank turn; a 25 x 25 grid for the five-bar):
//  * Phi(q, phi) ~ 0 at the configurations solved by the test-local Newton iteration;
//  * the scene points of EvalScene (an output independent of Phi) form rigid links: every
//    pair of points of one link keeps its body distance, every triple its signed area
//    (so a mirrored link is caught), and ground points stay at their body coordinates;
//  * the two points joined by each revolute joint coincide, and each slider point lies on
//    its guide line at the displacement of its coordinate;
//  * continuation over one full crank turn returns to the starting configuration.
// The body coordinates and joints below are transcribed from models/<name>.yaml.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

using mechtest::Config;
using mechtest::ParamsD;

// Newton is iterated to rounding level (||Phi|| ~ 1e-15); 1e-12 is the brief's bound.
constexpr double kPhiTol = 1e-12;
// Scene points are O(5) values computed with a few flops each: rounding ~1e-15.
constexpr double kGeomTol = 1e-12;

struct BodyPoint {
  std::string name;  // scene point "link.point"
  double x, y;       // body coordinates (the ground's are fixed-frame coordinates)
};
struct ModelGeometry {
  std::vector<BodyPoint> points;
  std::vector<std::pair<std::string, std::string>> revolutes;
};

template <class M>
struct Geometry;

template <class P>
ModelGeometry FourbarGeometry(const P& p) {
  return {{{"ground.A", 0, 0},
           {"ground.D", p.d, 0},
           {"crank.A", 0, 0},
           {"crank.B", p.a, 0},
           {"coupler.B", 0, 0},
           {"coupler.C", p.b, 0},
           {"coupler.P", p.xi, p.eta},
           {"rocker.D", 0, 0},
           {"rocker.C", p.c, 0}},
          {{"ground.A", "crank.A"},
           {"crank.B", "coupler.B"},
           {"coupler.C", "rocker.C"},
           {"rocker.D", "ground.D"}}};
}
template <>
struct Geometry<mech::fourbar::Model> {
  template <class P>
  static ModelGeometry Get(const P& p) {
    return FourbarGeometry(p);
  }
};
template <>
struct Geometry<mech::fourbar_crossed::Model> {
  template <class P>
  static ModelGeometry Get(const P& p) {
    return FourbarGeometry(p);
  }
};
template <>
struct Geometry<mech::slider_crank::Model> {
  template <class P>
  static ModelGeometry Get(const P& p) {
    return {{{"ground.O", 0, 0},
             {"ground.S", 0, p.e},
             {"crank.O", 0, 0},
             {"crank.B", p.a, 0},
             {"rod.B", 0, 0},
             {"rod.C", p.b, 0},
             {"slider.C", 0, 0}},
            {{"ground.O", "crank.O"}, {"crank.B", "rod.B"}, {"rod.C", "slider.C"}}};
  }
};
template <>
struct Geometry<mech::inverted_slider_crank::Model> {
  template <class P>
  static ModelGeometry Get(const P& p) {
    return {{{"ground.A", 0, 0},
             {"ground.D", p.d, 0},
             {"crank.A", 0, 0},
             {"crank.B", p.a, 0},
             {"rocker.D", 0, 0},
             {"rocker.E", 3, 0},
             {"block.B", 0, 0}},
            {{"ground.A", "crank.A"}, {"crank.B", "block.B"}, {"ground.D", "rocker.D"}}};
  }
};
template <>
struct Geometry<mech::fivebar::Model> {
  template <class P>
  static ModelGeometry Get(const P& p) {
    return {{{"ground.A", 0, 0},
             {"ground.E", p.f, 0},
             {"crank1.A", 0, 0},
             {"crank1.B", p.a1, 0},
             {"link1.B", 0, 0},
             {"link1.C", p.a2, 0},
             {"link2.D", 0, 0},
             {"link2.C", p.a3, 0},
             {"crank2.E", 0, 0},
             {"crank2.D", p.a4, 0}},
            {{"ground.A", "crank1.A"},
             {"crank1.B", "link1.B"},
             {"link1.C", "link2.C"},
             {"link2.D", "crank2.D"},
             {"crank2.E", "ground.E"}}};
  }
};

std::string LinkOf(const std::string& point) { return point.substr(0, point.find('.')); }
double Cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  return u.x() * v.y() - u.y() * v.x();
}

template <class M>
class LoopClosureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sweep_ = mechtest::SweepConfigs<M>(p_, mechtest::kSamplesPerDof<M>);
    ASSERT_FALSE(sweep_.empty()) << "the test-local Newton sweep failed";
  }
  Eigen::Matrix<double, 2, M::kNumScenePoints> Scene(const Config<M>& c) const {
    Eigen::Matrix<double, 2, M::kNumScenePoints> r;
    M::Scene(p_, c.q, c.phi, &r);
    return r;
  }
  ParamsD<M> p_;
  std::vector<Config<M>> sweep_;
};
TYPED_TEST_SUITE(LoopClosureTest, mechtest::PaulModels, mechtest::ModelNames);

TYPED_TEST(LoopClosureTest, PhiVanishesAtSolvedConfigurations) {
  using M = TypeParam;
  for (const auto& c : this->sweep_) {
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(this->p_, c.q, c.phi, &Phi);
    EXPECT_LT(Phi.template lpNorm<Eigen::Infinity>(), kPhiTol) << "q = " << c.q.transpose();
  }
}

// Every body point of the model is a scene point, and vice versa.
TYPED_TEST(LoopClosureTest, ScenePointsAreTheModelsBodyPoints) {
  using M = TypeParam;
  const ModelGeometry g = Geometry<M>::Get(this->p_);
  ASSERT_EQ(g.points.size(), static_cast<size_t>(M::kNumScenePoints));
  for (const auto& bp : g.points) {
    const int s = mechtest::ScenePointIndex<M>(bp.name);
    ASSERT_GE(s, 0) << bp.name;
    EXPECT_EQ(std::string(M::kLinkNames[M::kScenePointLink[s]]), LinkOf(bp.name)) << bp.name;
  }
}

TYPED_TEST(LoopClosureTest, LinksKeepTheirShapeOverTheSweep) {
  using M = TypeParam;
  const ModelGeometry g = Geometry<M>::Get(this->p_);
  int pairs_checked = 0;
  for (const auto& c : this->sweep_) {
    const auto r = this->Scene(c);
    ASSERT_TRUE(r.allFinite());
    for (size_t i = 0; i < g.points.size(); ++i) {
      const auto& pi = g.points[i];
      const Eigen::Vector2d ri = r.col(mechtest::ScenePointIndex<M>(pi.name));
      const Eigen::Vector2d bi(pi.x, pi.y);
      if (LinkOf(pi.name) == M::kLinkNames[M::kGroundLink]) {
        EXPECT_NEAR((ri - bi).norm(), 0.0, kGeomTol) << pi.name << " must not move";
      }
      for (size_t j = i + 1; j < g.points.size(); ++j) {
        const auto& pj = g.points[j];
        if (LinkOf(pj.name) != LinkOf(pi.name)) continue;
        const Eigen::Vector2d rj = r.col(mechtest::ScenePointIndex<M>(pj.name));
        const Eigen::Vector2d bj(pj.x, pj.y);
        EXPECT_NEAR((rj - ri).norm(), (bj - bi).norm(), kGeomTol)
            << "|" << pi.name << " " << pj.name << "| at q = " << c.q.transpose();
        ++pairs_checked;
        for (size_t k = j + 1; k < g.points.size(); ++k) {
          const auto& pk = g.points[k];
          if (LinkOf(pk.name) != LinkOf(pi.name)) continue;
          const Eigen::Vector2d rk = r.col(mechtest::ScenePointIndex<M>(pk.name));
          const Eigen::Vector2d bk(pk.x, pk.y);
          EXPECT_NEAR(Cross(rj - ri, rk - ri), Cross(bj - bi, bk - bi), kGeomTol)
              << "signed area " << pi.name << " " << pj.name << " " << pk.name;
        }
      }
    }
  }
  EXPECT_GT(pairs_checked, 0);
}

TYPED_TEST(LoopClosureTest, RevoluteJointPointsCoincide) {
  using M = TypeParam;
  const ModelGeometry g = Geometry<M>::Get(this->p_);
  for (const auto& c : this->sweep_) {
    const auto r = this->Scene(c);
    for (const auto& [a, b] : g.revolutes) {
      const int ia = mechtest::ScenePointIndex<M>(a), ib = mechtest::ScenePointIndex<M>(b);
      ASSERT_GE(ia, 0) << a;
      ASSERT_GE(ib, 0) << b;
      EXPECT_NEAR((r.col(ia) - r.col(ib)).norm(), 0.0, kGeomTol)
          << a << " vs " << b << " at q = " << c.q.transpose();
    }
  }
}

// Prismatic joints: the slider point is on its guide line, at its coordinate's displacement.
TYPED_TEST(LoopClosureTest, SliderPointsLieOnTheirGuides) {
  using M = TypeParam;
  if constexpr (std::is_same_v<M, mech::slider_crank::Model>) {
    // slide: guide ground.S, direction +x (angle 0); s_slide = phi(1).
    for (const auto& c : this->sweep_) {
      const auto r = this->Scene(c);
      const Eigen::Vector2d C = r.col(mechtest::ScenePointIndex<M>("slider.C"));
      const Eigen::Vector2d S = r.col(mechtest::ScenePointIndex<M>("ground.S"));
      EXPECT_NEAR(C.y(), S.y(), kGeomTol);
      EXPECT_NEAR(C.x() - S.x(), c.phi(1), kGeomTol);
      const Eigen::Vector2d rodC = r.col(mechtest::ScenePointIndex<M>("rod.C"));
      EXPECT_NEAR(rodC.y(), this->p_.e, kGeomTol) << "the rod end is on the line y = e";
    }
  } else if constexpr (std::is_same_v<M, mech::inverted_slider_crank::Model>) {
    // slot: guide rocker.D along the rocker's x axis (angle 0); s_slot = phi(1).
    for (const auto& c : this->sweep_) {
      const auto r = this->Scene(c);
      const Eigen::Vector2d B = r.col(mechtest::ScenePointIndex<M>("block.B"));
      const Eigen::Vector2d D = r.col(mechtest::ScenePointIndex<M>("rocker.D"));
      const Eigen::Vector2d E = r.col(mechtest::ScenePointIndex<M>("rocker.E"));
      const Eigen::Vector2d u = (E - D).normalized();
      EXPECT_NEAR(Cross(u, B - D), 0.0, kGeomTol) << "block.B off the rocker line";
      EXPECT_NEAR(u.dot(B - D), c.phi(1), kGeomTol) << "block.B not at s_slot along the rocker";
    }
  } else {
    GTEST_SKIP() << M::kName << " has no prismatic joint";
  }
}

// One full crank turn by continuation returns to the start (same branch, angles modulo a
// turn): the assembly mode is never switched on the way. Done in both directions.
TYPED_TEST(LoopClosureTest, FullCrankTurnReturnsToStart) {
  using M = TypeParam;
  if constexpr (M::kNq == 1) {
    bool ok = false;
    const Config<M> start = mechtest::SolvedAssembly<M>(this->p_, &ok);
    ASSERT_TRUE(ok);
    for (const double dir : {+1.0, -1.0}) {
      Config<M> c = start;
      mechtest::VecQ<M> target = start.q;
      target(0) += dir * mechtest::kTwoPi;
      ASSERT_TRUE(mechtest::Track<M>(this->p_, target, &c));
      const auto d = mechtest::PhiDifference<M>(c.phi, start.phi);
      EXPECT_LT(d.template lpNorm<Eigen::Infinity>(), kGeomTol)
          << "after a turn in direction " << dir << ": phi = " << c.phi.transpose()
          << ", start phi = " << start.phi.transpose();
    }
  } else {
    GTEST_SKIP() << M::kName << " has two inputs over limited ranges";
  }
}

}  // namespace
