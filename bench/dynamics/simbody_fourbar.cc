// The massive four-bar in Simbody 3.7: crank and rocker on Pin mobilizers to Ground, the
// coupler on a Pin to the crank, the loop closed at C by Constraint::PointOnLine (the rocker's
// C on the line through the coupler's C along z: two equations, the planar closure without the
// redundant z of a Ball). Uniform slender bars along their body x axis, gravity -9.81 y.
// Compiled with NDEBUG undefined (see CMakeLists.txt) for Debian's libsimbody-dev.
#include "simbody_fourbar.h"

#include <link.h>

#include <cmath>
#include <cstring>
#include <memory>

#include <Simbody.h>

#include "handwritten_dynamics.h"

namespace bench_dynamics {

using namespace SimTK;

struct SimbodyFourbar::Impl {
  MultibodySystem system;
  SimbodyMatterSubsystem matter{system};
  GeneralForceSubsystem forces{system};
  MobilizedBody::Pin crank, coupler, rocker;
  State initial;
};

namespace {

Body::Rigid SlenderBar(double rho, double length) {
  const double m = rho * length;
  // About the body origin (one end): Izz = Iyy = m L^2 / 3, Ixx = 0 (a line along x).
  return Body::Rigid(MassProperties(m, Vec3(length / 2, 0, 0),
                                    Inertia(0, m * length * length / 3, m * length * length / 3)));
}

std::unique_ptr<Integrator> MakeIntegrator(SimbodyIntegrator which, const MultibodySystem& system) {
  switch (which) {
    case SimbodyIntegrator::kRungeKuttaMerson:
      return std::make_unique<RungeKuttaMersonIntegrator>(system);
    case SimbodyIntegrator::kRungeKuttaFeldberg:
      return std::make_unique<RungeKuttaFeldbergIntegrator>(system);
    case SimbodyIntegrator::kCPodes:
      return std::make_unique<CPodesIntegrator>(system, CPodes::BDF, CPodes::Newton);
  }
  return nullptr;
}

}  // namespace

const char* Name(SimbodyIntegrator integrator) {
  switch (integrator) {
    case SimbodyIntegrator::kRungeKuttaMerson: return "RKMerson";
    case SimbodyIntegrator::kRungeKuttaFeldberg: return "RKFeldberg";
    case SimbodyIntegrator::kCPodes: return "CPodes";
  }
  return "?";
}

SimbodyFourbar::SimbodyFourbar() : impl_(new Impl) {
  const FourbarParams<double> p;
  Impl& s = *impl_;
  Force::Gravity(s.forces, s.matter, -YAxis, p.g);
  s.crank = MobilizedBody::Pin(s.matter.Ground(), Transform(Vec3(0)), SlenderBar(p.rho, p.a),
                               Transform(Vec3(0)));
  s.coupler = MobilizedBody::Pin(s.crank, Transform(Vec3(p.a, 0, 0)), SlenderBar(p.rho, p.b),
                                 Transform(Vec3(0)));
  s.rocker = MobilizedBody::Pin(s.matter.Ground(), Transform(Vec3(p.d, 0, 0)),
                                SlenderBar(p.rho, p.c), Transform(Vec3(0)));
  Constraint::PointOnLine(s.coupler, UnitVec3(ZAxis), Vec3(p.b, 0, 0), s.rocker, Vec3(p.c, 0, 0));
  s.system.realizeTopology();
  s.initial = s.system.getDefaultState();
  // Released from rest at theta = 90 deg, open assembly: the closed form gives the others.
  const double q0 = M_PI / 2;
  FourbarKinematics<double> k;
  Kinematics(p, q0, &k);
  const double th2 = std::atan2(k.s2, k.c2), th3 = std::atan2(k.s3, k.c3);
  s.crank.setOneQ(s.initial, 0, q0);
  s.coupler.setOneQ(s.initial, 0, th2 - q0);
  s.rocker.setOneQ(s.initial, 0, th3);
  s.system.realize(s.initial, Stage::Position);
  s.system.projectQ(s.initial, 1e-14);
}

SimbodyFourbar::~SimbodyFourbar() { delete impl_; }

SimbodyRun SimbodyFourbar::Simulate(SimbodyIntegrator which, double accuracy, double t_end) const {
  SimbodyRun run;
  State state = impl_->initial;
  auto integ = MakeIntegrator(which, impl_->system);
  integ->setAccuracy(accuracy);
  TimeStepper ts(impl_->system, *integ);
  ts.initialize(state);
  impl_->system.realize(integ->getState(), Stage::Dynamics);
  run.energy0 = impl_->system.calcEnergy(integ->getState());
  const Integrator::SuccessfulStepStatus status = ts.stepTo(t_end);
  const State& end = integ->getState();
  impl_->system.realize(end, Stage::Dynamics);
  run.theta = impl_->crank.getOneQ(end, 0);
  run.energy_end = impl_->system.calcEnergy(end);
  run.steps = integ->getNumStepsTaken();
  run.realizations = integ->getNumRealizations();
  run.ok = status == Integrator::ReachedReportTime && std::abs(end.getTime() - t_end) < 1e-12;
  return run;
}

void SimbodyFourbar::EnergyDrift(SimbodyIntegrator which, double accuracy,
                                 const std::vector<double>& times,
                                 std::vector<double>* drift) const {
  State state = impl_->initial;
  auto integ = MakeIntegrator(which, impl_->system);
  integ->setAccuracy(accuracy);
  TimeStepper ts(impl_->system, *integ);
  ts.initialize(state);
  impl_->system.realize(integ->getState(), Stage::Dynamics);
  const double e0 = impl_->system.calcEnergy(integ->getState());
  drift->clear();
  for (double t : times) {
    if (t > 0) ts.stepTo(t);
    impl_->system.realize(integ->getState(), Stage::Dynamics);
    drift->push_back(impl_->system.calcEnergy(integ->getState()) - e0);
  }
}

std::string SimbodyFourbar::LibraryPath() {
  std::string path;
  dl_iterate_phdr(
      [](struct dl_phdr_info* info, size_t, void* data) {
        if (info->dlpi_name != nullptr && std::strstr(info->dlpi_name, "SimTKsimbody") != nullptr)
          *static_cast<std::string*>(data) = info->dlpi_name;
        return 0;
      },
      &path);
  return path;
}

}  // namespace bench_dynamics
