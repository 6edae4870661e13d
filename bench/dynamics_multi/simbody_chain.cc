// See simbody_chain.h. Compiled with NDEBUG undefined for Debian's libsimbody-dev (CMakeLists.txt).
#include "simbody_chain.h"

#include <cmath>
#include <vector>

#include <Simbody.h>

namespace bench_multi {

using namespace SimTK;

namespace {
constexpr double kA = 1.0, kB = 3.5, kC = 3.0, kD = 4.0, kRho = 2.0, kG = 9.81;

Body::Rigid UniformBar(double length) {
  const double m = kRho * length;
  return Body::Rigid(MassProperties(m, Vec3(length / 2, 0, 0),
                                    Inertia(0, m * length * length / 3, m * length * length / 3)));
}
}  // namespace

struct SimbodyChain::Impl {
  MultibodySystem system;
  SimbodyMatterSubsystem matter{system};
  GeneralForceSubsystem forces{system};
  MobilizedBody::Pin crank;
  std::vector<MobilizedBody::Pin> couplers, rockers;
  State initial, work;
  std::vector<State> states;
};

SimbodyChain::SimbodyChain(int n) : impl_(new Impl) {
  Impl& s = *impl_;
  Force::Gravity(s.forces, s.matter, -YAxis, kG);
  s.crank = MobilizedBody::Pin(s.matter.Ground(), Transform(Vec3(0)), UniformBar(kA), Transform(Vec3(0)));
  MobilizedBody parent = s.crank;
  for (int i = 1; i <= n; ++i) {
    // The parent's pin B is at (a, 0) of its frame (the crank's tip, or the rocker's B).
    MobilizedBody::Pin coupler(parent, Transform(Vec3(kA, 0, 0)), UniformBar(kB), Transform(Vec3(0)));
    MobilizedBody::Pin rocker(s.matter.Ground(), Transform(Vec3(kD * i, 0, 0)), UniformBar(kC),
                              Transform(Vec3(0)));
    Constraint::PointOnLine(coupler, UnitVec3(ZAxis), Vec3(kB, 0, 0), rocker, Vec3(kC, 0, 0));
    s.couplers.push_back(coupler);
    s.rockers.push_back(rocker);
    parent = rocker;
  }
  s.system.realizeTopology();
  s.initial = s.system.getDefaultState();
  // Assembled by hand at theta_crank = 90 deg, each loop's C on the side of the model's
  // assembly (left of B -> O_i), then projected.
  double th_parent = M_PI / 2;
  double Bx = 0, By = kA;
  s.crank.setOneQ(s.initial, 0, th_parent);
  for (int i = 1; i <= n; ++i) {
    const double Ox = kD * i, Oy = 0;
    const double dx = Ox - Bx, dy = Oy - By, dist = std::sqrt(dx * dx + dy * dy);
    const double along = (kB * kB - kC * kC + dist * dist) / (2 * dist);
    const double h = std::sqrt(std::max(0.0, kB * kB - along * along));
    const double Cx = Bx + along * dx / dist - h * dy / dist, Cy = By + along * dy / dist + h * dx / dist;
    const double th_coupler = std::atan2(Cy - By, Cx - Bx), th_rocker = std::atan2(Cy - Oy, Cx - Ox);
    s.couplers[i - 1].setOneQ(s.initial, 0, th_coupler - th_parent);
    s.rockers[i - 1].setOneQ(s.initial, 0, th_rocker);
    th_parent = th_rocker;
    Bx = Ox + kA * std::cos(th_rocker);
    By = Oy + kA * std::sin(th_rocker);
  }
  s.system.realize(s.initial, Stage::Position);
  s.system.projectQ(s.initial, 1e-14);
}

SimbodyChain::~SimbodyChain() { delete impl_; }

void SimbodyChain::RecordStates(int count) {
  State state = impl_->initial;
  RungeKuttaMersonIntegrator integ(impl_->system);
  integ.setAccuracy(1e-8);
  TimeStepper ts(impl_->system, integ);
  ts.initialize(state);
  impl_->work = impl_->initial;
  impl_->states.clear();
  for (int k = 0; k < count; ++k) {
    ts.stepTo((k + 0.5) / count);
    impl_->states.push_back(integ.getState());
  }
}

double SimbodyChain::Rhs(int k) {
  Impl& s = *impl_;
  const State& from = s.states[k % s.states.size()];
  s.work.setTime(from.getTime());
  s.work.updQ() = from.getQ();
  s.work.updU() = from.getU();
  s.system.realize(s.work, Stage::Acceleration);
  return s.crank.getOneUDot(s.work, 0);
}

}  // namespace bench_multi
