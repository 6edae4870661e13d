/**
 * \file synthesis/report.h
 * The synthesized mechanism described (issue 28): the text report (error per target, the
 * defect checks with the runtime's continuation, ContinuationCheck in synthesis/optimize.h,
 * the transmission-angle range, the search).
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mechgen/core/constants.h"
#include "mechgen/synthesis/optimize.h"
#include "mechgen/synthesis/output.h"

namespace mechgen::synthesis {

/// The text report of a search.
template <class M>
std::string Report(PathEvaluator<M>* eval, const SearchResult& s, const std::string& continuation, uint64_t seed,
                   int threads, double wall_seconds, double cpu_seconds, const std::string& model_path) {
  const BoundPath<M>& b = eval->bound();
  const PathTask& t = b.task;
  const Candidate& c = s.best.best;
  std::string r = "mechgen synthesize: path generation\n";
  r += "model: " + model_path + " (" + std::string(ModelCalls<M>::Name(eval->model())) + "), task: " + t.file + ", point " + t.point + "\n";
  r += "targets: " + std::to_string(b.n) + ", timing: " +
       (t.timing.free ? std::string("free") : std::string("prescribed") + (t.timing.offset_free ? " (offset free)" : "")) + "\n";
  r += "search: seed " + std::to_string(seed) + ", threads " + std::to_string(threads) + ", " +
       std::to_string(t.search.restarts) +
       (t.search.projection
            ? " runs of differential evolution + Levenberg-Marquardt on the link ratios and the timing, the placement, scale, "
              "rotation and coupler point by linear least squares (variable projection)\n"
            : " runs of differential evolution + Levenberg-Marquardt (Ceres, generated Jacobian)\n");
  r += "evaluations: " + std::to_string(s.evaluations) +
       (t.search.projection ? " (a reduced evaluation counts 1, a Jacobian its reduced variables, a full check 1, its continuation 1)"
                            : " (a Jacobian counts 1 + its parameters)") +
       ", position solves " +
       std::to_string(s.solves) + ", wall " + Short(wall_seconds, 4) + " s, cpu " + Short(cpu_seconds, 4) + " s\n";
  std::vector<double> errors;
  for (const RunResult& run : s.runs)
    if (run.best.feasible()) errors.push_back(run.best.error);
  std::sort(errors.begin(), errors.end());
  if (!errors.empty())
    r += "runs: " + std::to_string(errors.size()) + " of " + std::to_string(s.runs.size()) + " feasible; error best " +
         Short(errors.front(), 6) + ", median " + Short(errors[errors.size() / 2], 6) + ", worst " + Short(errors.back(), 6) + "\n";
  r += "\nerror (sum of squared distances): " + Short(c.error, 10) + " (global stage " + Short(s.best.global.error, 10) + ")\n";
  r += "target        x                y           distance      input angle [deg]\n";
  for (int i = 0; i < b.n; ++i) {
    char line[200];
    std::snprintf(line, sizeof line, "%4d  %15.9g  %15.9g  %12.4g  %12.6f\n", i + 1, t.tx[static_cast<size_t>(i)],
                  t.ty[static_cast<size_t>(i)], c.distance[static_cast<size_t>(i)], ToDegrees(c.q[static_cast<size_t>(i)]));
    r += line;
  }
  r += "\ndefect checks:\n";
  r += std::string("  constraints and assembly (every target on the model's mode, the motion between them without a dead point): ") +
       (c.feasible() ? "ok" : "FAILED: " + c.defect) + "\n";
  r += "  continuation through the targets (PositionSolver, the branch kept): " +
       (continuation.empty() ? std::string("ok") : "FAILED: " + continuation) + "\n";
  if (t.constraints.order) r += std::string("  targets in input order: ") + (c.feasible() ? "ok" : "see above") + "\n";
  if (std::isfinite(c.mu_min))
    r += "  transmission angle over the motion: [" + Short(ToDegrees(c.mu_min), 5) + ", " + Short(ToDegrees(c.mu_max), 5) +
         "] deg" + (t.constraints.has_mu ? " (bounds [" + Short(ToDegrees(t.constraints.mu_lo), 5) + ", " +
                                               Short(ToDegrees(t.constraints.mu_hi), 5) + "])"
                                         : std::string()) + "\n";
  r += "\nparameters:\n";
  for (size_t j = 0; j < t.variables.size(); ++j)
    r += "  " + t.variables[j].name + " = " + Num(c.x[j]) + "\n";
  return r;
}

/// "x0 = 0.5 (the model's 0), ...": the parameters of p other than `variables` whose values
/// differ from the model's (set by --set or --params: the search ran with them, and the
/// written model file carries them); "" when none does.
template <class M>
std::string SetParametersText(const M& model, const typename ModelTypes<M>::Params& p,
                              const std::vector<std::string>& variables) {
  using C = ModelCalls<M>;
  typename ModelTypes<M>::Params value = p, defaults = C::DefaultParams(model);
  std::string text;
  for (int i = 0; i < C::NumFreeParameters(model); ++i) {
    const char* n = C::FreeParameterName(model, i);
    if (std::find(variables.begin(), variables.end(), n) != variables.end()) continue;
    if (*C::FindParameter(model, &value, n) == *C::FindParameter(model, &defaults, n)) continue;
    text += (text.empty() ? "" : ", ") + std::string(n) + " = " + Num(*C::FindParameter(model, &value, n)) +
            " (the model's " + Num(*C::FindParameter(model, &defaults, n)) + ")";
  }
  return text;
}
/// The same on a generated model's type.
template <class M>
std::string SetParametersText(const typename M::template ParamsT<double>& p, const std::vector<std::string>& variables) {
  return SetParametersText(M(), p, variables);
}

/// What the written model file holds besides the variables (WriteSynthesizedModel): the
/// parameters set, the assembly configuration and the input's range, for the report.
template <class M>
std::string WrittenModelText(const M& model, const WrittenAssembly& w, const typename ModelTypes<M>::Params& p) {
  using C = ModelCalls<M>;
  std::string r = "\nthe model file: the values above";
  if (!w.set.empty()) {
    r += ", and the parameters set on the command line: ";
    typename ModelTypes<M>::Params value = p;
    for (size_t k = 0; k < w.set.size(); ++k)
      r += (k ? ", " : "") + w.set[k] + " = " + Num(*C::FindParameter(model, &value, w.set[k].c_str()));
  }
  r += "\n  assembly: " + std::string(C::QName(model, 0)) + " = " + Short(w.q, 10);
  for (int i = 0; i < C::Nphi(model); ++i)
    r += ", " + std::string(C::PhiName(model, i)) + " = " + Short(w.phi[static_cast<size_t>(i)], 10);
  r += " (the first target on the synthesis' mode; branch " + std::string(w.branch > 0 ? "+1" : "-1") +
       " = sign det Phi_phi, on which the sweep assembles)\n";
  r += "  input range: [" + Short(w.range_lo, 10) + ", " + Short(w.range_hi, 10) + "]" +
       (w.range_written ? " (the motion through the targets: the continuation cannot sweep the model's own range)"
                        : " (the model's own)") +
       "\n";
  if (!w.continuation.empty()) r += "  WARNING: the runtime's continuation does not sweep it: " + w.continuation + "\n";
  return r;
}
/// The same on a generated model's type.
template <class M>
std::string WrittenModelText(const WrittenAssembly& w, const typename M::template ParamsT<double>& p) {
  return WrittenModelText(M(), w, p);
}

}  // namespace mechgen::synthesis
