// The five-bar robot in Simbody 3.7: prox1 and prox2 on Pin mobilizers to Ground at A and E,
// dist1 and dist2 on Pins at B and D, the loop closed at C by Constraint::PointOnLine (dist2's
// C on the line through dist1's C along z: the planar closure, as bench/dynamics' four-bar).
// Gravity -g y; the motors' PD torques by a Force::Custom on the two motor mobilities.
// Compiled with NDEBUG undefined (see CMakeLists.txt) for Debian's libsimbody-dev.
#include "simbody_fivebar.h"

#include <link.h>

#include <cmath>
#include <cstring>
#include <memory>

#include <Simbody.h>

#include "robot_cycle.h"

namespace bench_multi {

using namespace SimTK;

namespace {

// A bar along its body x axis: mass m, centre xg, inertia J about the centre (z).
Body::Rigid Bar(double m, double xg, double J) {
  const double Io = J + m * xg * xg;
  return Body::Rigid(MassProperties(m, Vec3(xg, 0, 0), Inertia(0, Io, Io)));
}

class MotorTorques : public Force::Custom::Implementation {
 public:
  MotorTorques(const RobotParams& p, const MobilizedBody::Pin& m1, const MobilizedBody::Pin& m2)
      : p_(p), m1_(m1), m2_(m2) {}
  void calcForce(const State& s, Vector_<SpatialVec>&, Vector_<Vec3>&, Vector& mobility) const override {
    const double q[2] = {m1_.getOneQ(s, 0), m2_.getOneQ(s, 0)};
    const double qd[2] = {m1_.getOneU(s, 0), m2_.getOneU(s, 0)};
    double tau[2];
    Torques(p_, s.getTime(), q, qd, tau);
    m1_.applyOneMobilityForce(s, 0, tau[0], mobility);
    m2_.applyOneMobilityForce(s, 0, tau[1], mobility);
  }
  Real calcPotentialEnergy(const State&) const override { return 0; }

 private:
  RobotParams p_;
  MobilizedBody::Pin m1_, m2_;
};

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

struct SimbodyFivebar::Impl {
  RobotParams p;
  MultibodySystem system;
  SimbodyMatterSubsystem matter{system};
  GeneralForceSubsystem forces{system};
  MobilizedBody::Pin prox1, dist1, prox2, dist2;
  State initial;
  State work;  ///< Rhs(): t, q, u set from a recorded state
  std::vector<State> states;
};

SimbodyFivebar::SimbodyFivebar() : impl_(new Impl) {
  Impl& s = *impl_;
  const RobotParams& p = s.p;
  Force::Gravity(s.forces, s.matter, -YAxis, p.g);
  const double mprox = p.rho * p.a, mdist = p.rho * p.b;
  s.prox1 = MobilizedBody::Pin(s.matter.Ground(), Transform(Vec3(0)),
                               Bar(mprox, p.a / 2, mprox * p.a * p.a / 12), Transform(Vec3(0)));
  s.dist1 = MobilizedBody::Pin(s.prox1, Transform(Vec3(p.a, 0, 0)),
                               Bar(p.MassDist1(), p.CenterDist1(), p.InertiaDist1()), Transform(Vec3(0)));
  s.prox2 = MobilizedBody::Pin(s.matter.Ground(), Transform(Vec3(p.f, 0, 0)),
                               Bar(mprox, p.a / 2, mprox * p.a * p.a / 12), Transform(Vec3(0)));
  s.dist2 = MobilizedBody::Pin(s.prox2, Transform(Vec3(p.a, 0, 0)),
                               Bar(mdist, p.b / 2, mdist * p.b * p.b / 12), Transform(Vec3(0)));
  Constraint::PointOnLine(s.dist1, UnitVec3(ZAxis), Vec3(p.b, 0, 0), s.dist2, Vec3(p.b, 0, 0));
  Force::Custom(s.forces, new MotorTorques(p, s.prox1, s.prox2));
  s.system.realizeTopology();
  s.initial = s.system.getDefaultState();
  double q[2], qd[2], th1, th2;
  Commanded(p, 0.0, q, qd);
  DistalAngles(p, q, &th1, &th2);
  s.prox1.setOneQ(s.initial, 0, q[0]);
  s.dist1.setOneQ(s.initial, 0, th1 - q[0]);
  s.prox2.setOneQ(s.initial, 0, q[1]);
  s.dist2.setOneQ(s.initial, 0, th2 - q[1]);
  s.system.realize(s.initial, Stage::Position);
  s.system.projectQ(s.initial, 1e-14);
}

SimbodyFivebar::~SimbodyFivebar() { delete impl_; }

SimbodyRobotRun SimbodyFivebar::Simulate(SimbodyIntegrator which, double accuracy, double t_end,
                                         bool restart_at_breaks) const {
  SimbodyRobotRun run;
  State state = impl_->initial;
  auto integ = MakeIntegrator(which, impl_->system);
  integ->setAccuracy(accuracy);
  TimeStepper ts(impl_->system, *integ);
  ts.initialize(state);
  Integrator::SuccessfulStepStatus status = Integrator::ReachedReportTime;
  if (restart_at_breaks) {
    for (double t_break : kCycleBreaks) {
      if (t_break >= t_end) break;
      status = ts.stepTo(t_break);
      if (status != Integrator::ReachedReportTime) break;
      run.steps += integ->getNumStepsTaken();
      run.realizations += integ->getNumRealizations();
      state = integ->getState();
      ts.initialize(state);  // counters start again
    }
  }
  if (status == Integrator::ReachedReportTime) status = ts.stepTo(t_end);
  const State& end = integ->getState();
  run.q[0] = impl_->prox1.getOneQ(end, 0);
  run.q[1] = impl_->prox2.getOneQ(end, 0);
  run.steps += integ->getNumStepsTaken();
  run.realizations += integ->getNumRealizations();
  run.ok = status == Integrator::ReachedReportTime && std::abs(end.getTime() - t_end) < 1e-12;
  return run;
}

void SimbodyFivebar::RecordStates(int n, double t_end) {
  State state = impl_->initial;
  RungeKuttaMersonIntegrator integ(impl_->system);
  integ.setAccuracy(1e-8);
  TimeStepper ts(impl_->system, integ);
  ts.initialize(state);
  impl_->work = impl_->initial;
  impl_->states.clear();
  for (int k = 0; k < n; ++k) {
    ts.stepTo(t_end * (k + 0.5) / n);
    impl_->states.push_back(integ.getState());
  }
}

double SimbodyFivebar::Rhs(int k) {
  Impl& s = *impl_;
  const State& from = s.states[k % s.states.size()];
  State& work = s.work;
  work.setTime(from.getTime());
  work.updQ() = from.getQ();
  work.updU() = from.getU();
  s.system.realize(work, Stage::Acceleration);
  return s.prox1.getOneUDot(work, 0);
}

std::string SimbodyFivebar::LibraryPath() {
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

}  // namespace bench_multi
