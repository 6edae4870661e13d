// The generated four-bar driven by the installed Ceres-free runtime: Newton assembly from
// the model's guess, a short MoveTo sweep over a full crank turn, a sweep with its CSV.
// Checks at every step the loop closure ||Phi(q, phi)||_inf (evaluated here, not by the
// solver) and K against the central difference of two more solved positions; exits 0 when
// all hold.
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "fourbar.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/sweep.h"

#if defined(CERES_PUBLIC_CERES_H_) || defined(CERES_PUBLIC_JET_H_)
#error "the Ceres-free runtime included Ceres"
#endif

int main() {
  using M = mech::fourbar::Model;
  using VecQ = mechgen::ModelTypes<M>::VecQ;
  using mechgen::position::Status;
  mechgen::position::PositionSolver<M> solver, probe;  // NewtonAssembler: no Ceres
  mechgen::position::Summary summary;
  if (solver.AssembleDefault(&summary) != Status::kConverged ||
      probe.AssembleDefault(nullptr) != Status::kConverged) {
    std::printf("assembly failed: %s\n", mechgen::position::FormatSummary(summary).c_str());
    return 1;
  }
  const double kPi = 3.14159265358979323846, h = 1e-5;
  double max_residual = 0, max_k_error = 0;
  for (int i = 0; i <= 72; ++i) {
    const double q = 2 * kPi * i / 72;
    if (solver.MoveTo(VecQ::Constant(q), &summary) != Status::kConverged) {
      std::printf("MoveTo(%g) failed: %s\n", q, mechgen::position::FormatSummary(summary).c_str());
      return 1;
    }
    mechgen::ModelTypes<M>::VecC Phi;
    M::Phi<double>(solver.params(), solver.state().q, solver.state().phi, &Phi);
    max_residual = std::fmax(max_residual, Phi.lpNorm<Eigen::Infinity>());
    if (probe.MoveTo(VecQ::Constant(q + h), nullptr) != Status::kConverged) return 1;
    const auto phi_plus = probe.state().phi;
    if (probe.MoveTo(VecQ::Constant(q - h), nullptr) != Status::kConverged) return 1;
    const auto phi_minus = probe.state().phi;
    const double error =
        (solver.state().K.col(0) - (phi_plus - phi_minus) / (2 * h)).cwiseAbs().maxCoeff();
    max_k_error = std::fmax(max_k_error, error);
  }
  std::vector<mechgen::SweepRecord<M>> records;
  const int failures = mechgen::Sweep(&solver, VecQ::Constant(0.0), VecQ::Constant(kPi), 36,
                                      VecQ::Constant(1.0), VecQ::Zero(), &records);
  std::ostringstream csv;
  mechgen::WriteCsv(records, csv);
  std::printf("Ceres-free consumer: max |Phi|_inf = %.3g, max |K - FD| = %.3g, sweep failures %d, "
              "CSV %zu bytes\n",
              max_residual, max_k_error, failures, csv.str().size());
  return max_residual <= 1e-10 && max_k_error <= 1e-7 && failures == 0 && csv.str().size() > 1000
             ? 0
             : 1;
}
