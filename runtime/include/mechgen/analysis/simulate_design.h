/**
 * \file analysis/simulate_design.h
 * The simulation's design run (SimulateRequest::design): the free motion with its trajectory
 * sensitivities (dynamics/sensitivity.h: the forward sensitivity equations), on a generated
 * model's fixed sizes or through the model view (its model's generated EvalDynamicsJacobian;
 * without it Run refuses it: analysis/simulate.h). Run (analysis/simulate.h) calls it after
 * Prepare's checks (a `design` section; not with drives, friction on, energy projection or a
 * stop at speed zero; the parameters, q0, qd0); a program that runs Run (the per-model tool,
 * tools/simulate_main.cc; the view: runtime/view/analysis_simulate_design.cc) includes this header,
 * which needs Ceres' headers (without them design is a usage error and this header is not
 * needed).
 */
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "mechgen/analysis/simulate.h"

#if MECHGEN_SIMULATE_HAS_SENSITIVITY
#include "mechgen/dynamics/sensitivity.h"
#include "mechgen/io/format.h"

namespace mechgen::analysis::simulate_internal {

// The free motion with its trajectory sensitivities: the CSV has t, each input, its speed and
// acceleration, d<q>/d<p> and d<q>_dot/d<p> for every input q and design parameter p (q's
// unit, or q's unit per second, per unit of p, p in the model file's units) and rcond =
// 1/cond_1(Phi_phi).
template <class M, template <int> class Method>
int RunDesign(const M& model, const SimulateRequest& args, const SimulateOutputs& out, const Prepared<M>& p) {
  using C = ModelCalls<M>;
  using Sim = mechgen::dynamics::TrajectorySensitivity<M, Method>;
  using VecQ = typename Sim::VecQ;
  using SampleT = typename Sim::SampleT;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model), np = C::NumDesign(model);
  const typename ModelTypes<M>::Params& params = p.params;
  const VecQ &q0 = p.q0, &qd0 = p.qd0;
  mechgen::dynamics::SensitivityOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  Sim sim(model, params, options);
  if (!sim.Initialize(q0)) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs\n", name);
    return 1;
  }
  const std::string csv_path = CsvPath(out, name);
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  using Row = CsvRow<SampleT>;
  mechgen::table::Columns<Row> columns;
  mechgen::table::Builder<Row> add(&columns);
  auto unit = [&model](int i, const char* per) { return std::string(C::QIsAngle(model, i) ? "rad" : "m") + per; };
  AddInputColumns<M, SampleT>(&add, model);
  for (int i = 0; i < nq; ++i)
    for (int d = 0; d < np; ++d)
      add.Number(std::string("d") + C::QName(model, i) + "/d" + C::DesignName(model, d),
                 unit(i, " per unit of ") + C::DesignName(model, d), "trajectory sensitivity dq/dp",
                 [i, d](const Row& r) { return r.s->S(i, d); });
  for (int i = 0; i < nq; ++i)
    for (int d = 0; d < np; ++d)
      add.Number(std::string("d") + C::QName(model, i) + "_dot/d" + C::DesignName(model, d),
                 unit(i, "/s per unit of ") + C::DesignName(model, d), "trajectory sensitivity dqd/dp",
                 [i, d](const Row& r) { return r.s->Sd(i, d); });
  add.Number("rcond", "1", "1/cond_1(Phi_phi) (1 without a closed loop)",
             [](const Row& r) { return r.s->rcond; });
  mechgen::WriteCsvHeader(columns, csv.stream(), SimulateCsvOptions(name, "free motion with trajectory sensitivities"));
  SampleT last;
  auto observer = [&](const SampleT& s) {
    mechgen::WriteCsvRow(columns, Row{&s, nullptr}, csv.stream());
    last = s;
    return true;
  };
  mechgen::dynamics::SensitivitySummary summary;
  sim.Simulate(0.0, q0, qd0, args.t_end, observer, &summary);
  if (!CommitCsv(&csv)) return 1;
  const bool failure = mechgen::dynamics::IsFailure(summary.status);
  if (!out.quiet) {
    if (const std::string changed = tools::ChangedModelParameters(model, params); !changed.empty())
      std::printf("parameters set: %s\n", changed.c_str());
    std::printf("%s: %s\n", name, mechgen::dynamics::FormatSummary(summary).c_str());
    if (summary.samples > 0) {
      std::printf("end: t = %.6g s, %s = %.9g %s; d%s/dp:", last.t, C::QName(model, 0), last.q(0),
                  C::QIsAngle(model, 0) ? "rad" : "m", C::QName(model, 0));
      for (int d = 0; d < np; ++d)
        std::printf(" %s %.6g%s", C::DesignName(model, d), last.S(0, d), d + 1 < np ? "," : "");
      std::printf("\n");
    }
    std::printf("wrote %s (%d rows)\n", csv_path.c_str(), summary.samples);
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s: %s\n", name,
                 mechgen::dynamics::ToString(summary.status), summary.t_end, summary.message);
    return 1;
  }
  return 0;
}

/**
 * \brief The free motion's trajectory sensitivities from (q0, qd0) over [0, t_end] with
 * `options` (Method's integrator, sampled every options.sample_dt): every sample appended to
 * *samples (the study's first order of a simulation metric, study/run.h), on a generated model
 * or through the view (a view without the generated EvalDynamicsJacobian: *why, no run).
 * \return false with *why where it does not run or fails (the summary's status in the text).
 */
template <class M, template <int> class Method>
bool SensitivitySamples(const M& model,
                        const typename ModelTypes<M>::Params& params,
                        const typename ModelTypes<M>::VecQ& q0,
                        const typename ModelTypes<M>::VecQ& qd0,
                        double t_end,
                        const mechgen::dynamics::SensitivityOptions& options,
                        std::vector<mechgen::dynamics::SensitivitySample<M>>* samples,
                        std::string* why) {
  using Sim = mechgen::dynamics::TrajectorySensitivity<M, Method>;
  if (!Sim::SupportedBy(model, why)) return false;
  Sim sim(model, params, options);
  if (!sim.Initialize(q0)) {
    *why = "the trajectory sensitivities: the nominal does not assemble at q0";
    return false;
  }
  mechgen::dynamics::SensitivitySummary summary;
  sim.Simulate(
      0.0, q0, qd0, t_end,
      [samples](const mechgen::dynamics::SensitivitySample<M>& s) {
        samples->push_back(s);
        return true;
      },
      &summary);
  if (mechgen::dynamics::IsFailure(summary.status)) {
    *why = std::string("the trajectory sensitivities failed: ") + mechgen::dynamics::ToString(summary.status) +
           " at t = " + mechgen::internal::FormatNumber(summary.t_end, "%g");
    return false;
  }
  return true;
}

}  // namespace mechgen::analysis::simulate_internal

#endif  // MECHGEN_SIMULATE_HAS_SENSITIVITY
