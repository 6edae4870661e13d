/**
 * \file analysis/simulate_design.h
 * The simulation's design run (SimulateRequest::design): the free motion with its trajectory
 * sensitivities (dynamics/sensitivity.h: the forward sensitivity equations, ceres::Jet), on a
 * generated model's fixed sizes only (issue 46 replaces the Jets; through the model view Run
 * refuses it: analysis/simulate.h). Run (analysis/simulate.h) calls it after Prepare's checks
 * (a `design` section; not with drives, friction on, energy projection or a stop at speed
 * zero; the parameters, q0, qd0); a program that runs Run on a generated model (the per-model
 * tool, tools/simulate_main.cc) includes this header, which needs Ceres' headers (without
 * them design is a usage error and this header is not needed).
 */
#pragma once

#include <cstdio>
#include <string>

#include "mechgen/analysis/simulate.h"

#if MECHGEN_SIMULATE_HAS_SENSITIVITY
#include "mechgen/dynamics/sensitivity.h"

namespace mechgen::analysis::simulate_internal {

// The free motion with its trajectory sensitivities: the CSV has t, each input, its speed and
// acceleration, d<q>/d<p> and d<q>_dot/d<p> for every input q and design parameter p (q's
// unit, or q's unit per second, per unit of p, p in the model file's units) and rcond =
// 1/cond_1(Phi_phi).
template <class M, template <int> class Method>
int RunDesign(const M& model, const SimulateRequest& args, const SimulateOutputs& out, const Prepared<M>& p) {
  static_assert(!ModelCalls<M>::kView, "the trajectory sensitivities are a generated model's (fixed sizes)");
  (void)model;
  using Sim = mechgen::dynamics::TrajectorySensitivity<M, Method>;
  using VecQ = typename Sim::VecQ;
  using SampleT = typename Sim::SampleT;
  constexpr int kNq = M::kNq, kNp = M::kNumDesign;
  const typename M::template ParamsT<double>& params = p.params;
  const VecQ &q0 = p.q0, &qd0 = p.qd0;
  mechgen::dynamics::SensitivityOptions options;
  options.integrator.rtol = args.rtol;
  options.integrator.atol = args.atol;
  options.integrator.max_steps = args.max_steps;
  options.sample_dt = args.dt;
  Sim sim(params, options);
  if (!sim.Initialize(q0)) {
    std::fprintf(stderr, "error: %s does not assemble at the initial inputs\n", M::kName);
    return 1;
  }
  const std::string csv_path = CsvPath(out, M::kName);
  mechgen::OutputFile csv;
  std::string error;
  if (!csv.Open(csv_path, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  using Row = CsvRow<SampleT>;
  mechgen::table::Columns<Row> columns;
  mechgen::table::Builder<Row> add(&columns);
  auto unit = [](int i, const char* per) { return std::string(M::kQIsAngle[i] ? "rad" : "m") + per; };
  AddInputColumns<M, SampleT>(&add);
  for (int i = 0; i < kNq; ++i)
    for (int d = 0; d < kNp; ++d)
      add.Number(std::string("d") + M::kQNames[i] + "/d" + M::kDesignNames[d],
                 unit(i, " per unit of ") + M::kDesignNames[d], "trajectory sensitivity dq/dp",
                 [i, d](const Row& r) { return r.s->S(i, d); });
  for (int i = 0; i < kNq; ++i)
    for (int d = 0; d < kNp; ++d)
      add.Number(std::string("d") + M::kQNames[i] + "_dot/d" + M::kDesignNames[d],
                 unit(i, "/s per unit of ") + M::kDesignNames[d], "trajectory sensitivity dqd/dp",
                 [i, d](const Row& r) { return r.s->Sd(i, d); });
  add.Number("rcond", "1", "1/cond_1(Phi_phi) (1 without a closed loop)",
             [](const Row& r) { return r.s->rcond; });
  mechgen::WriteCsvHeader(columns, csv.stream(),
                          SimulateCsvOptions(M::kName, "free motion with trajectory sensitivities"));
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
    if (const std::string changed = tools::ChangedParameters(params); !changed.empty())
      std::printf("parameters set: %s\n", changed.c_str());
    std::printf("%s: %s\n", M::kName, mechgen::dynamics::FormatSummary(summary).c_str());
    if (summary.samples > 0) {
      std::printf("end: t = %.6g s, %s = %.9g %s; d%s/dp:", last.t, M::kQNames[0], last.q(0),
                  M::kQIsAngle[0] ? "rad" : "m", M::kQNames[0]);
      for (int d = 0; d < kNp; ++d) std::printf(" %s %.6g%s", M::kDesignNames[d], last.S(0, d), d + 1 < kNp ? "," : "");
      std::printf("\n");
    }
    std::printf("wrote %s (%d rows)\n", csv_path.c_str(), summary.samples);
  }
  if (!FlushStdout()) return 1;
  if (failure) {
    std::fprintf(stderr, "%s: the simulation failed: %s at t = %.9g s: %s\n", M::kName,
                 mechgen::dynamics::ToString(summary.status), summary.t_end, summary.message);
    return 1;
  }
  return 0;
}

}  // namespace mechgen::analysis::simulate_internal

#endif  // MECHGEN_SIMULATE_HAS_SENSITIVITY
