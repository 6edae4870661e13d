// `mechgen study MODEL --study STUDY.yaml [--threads N] [--csv F] [--tolerance-csv F]`: a design
// study of one generated model (issue 29; the format: docs/studies.md). Compiled once per model
// by generator/driver/tool_command.cc (like the sweep), with -DMECHGEN_MODEL_INCLUDE and
// -DMECHGEN_MODEL_NAMESPACE, linked with yaml-cpp and threads.
//
// Draws every sample's parameter values (study/samples.h), runs the analysis of each on N
// threads (study/run.h: one compiled model, per-thread solver and rows), writes one CSV row per
// sample in sample order (the same bytes for any N), prints a summary of each metric and, with
// `tolerance: true`, the first-order tolerance analysis from the generated sensitivities beside
// the Monte-Carlo's figures. Progress on stderr (rate, time left) for studies longer than ~2 s.
// Exit status: 0 done (every sample ok), 3 done but some samples failed (their status column),
// 2 bad arguments or a bad study file (one line: file:line:column), 1 the study does not fit the
// model or an output cannot be written (nothing written).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/numbers.h"
#include "common/params.h"
#include "study_args.h"
#ifndef MECHGEN_STUDY_ARGS_SEPARATE
#include "study_args.cc"
#endif
#include "mechgen/io/output_file.h"
#include "mechgen/study/run.h"
#include "mechgen/study/samples.h"
#include "mechgen/study/shards.h"
#include "mechgen/study/tolerance.h"

#ifdef MECHGEN_STUDY_MPI
#define OMPI_SKIP_MPICXX 1  // the C interface only (no C++ bindings to compile or link)
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

namespace {

using Model = MECHGEN_MODEL_NAMESPACE::Model;
namespace study = mechgen::study;
namespace tools = mechgen::tools;
namespace study_tool = mechgen::study_tool;

std::string G17(double x) {
  if (std::isnan(x)) return "nan";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

const char* MethodName(study::Method m) {
  switch (m) {
    case study::Method::kGrid:
      return "grid";
    case study::Method::kList:
      return "list";
    case study::Method::kLatinHypercube:
      return "lhs";
    case study::Method::kMonteCarlo:
      return "monte_carlo";
  }
  return "";
}

const char* AnalysisName(study::Analysis a) {
  return a == study::Analysis::kStatics    ? "statics"
         : a == study::Analysis::kFlywheel ? "flywheel"
         : a == study::Analysis::kSimulate  ? "simulate"
         : a == study::Analysis::kPositions ? "positions"
         : a == study::Analysis::kEngine    ? "engine"
                                            : "sweep";
}

// The CSV: '#' lines (what wrote it, then each column's unit and meaning), the header, a row
// per sample.
void WriteCsv(const study::Study<Model>& s,
              const std::vector<double>& values,
              const std::vector<study::SampleResult>& results,
              std::ostream& out) {
  const study::StudySpec& spec = s.spec();
  const size_t n = spec.parameters.size();
  out << "# mechgen study, model " << Model::kName << ": " << spec.path << ", method " << MethodName(spec.method)
      << ", " << results.size() << " samples, seed " << spec.seed << ", analysis "
      << AnalysisName(spec.analysis) << " in " << spec.steps << " steps";
  if (spec.analysis == study::Analysis::kSimulate) out << " to t_end " << G17(spec.t_end) << " s";
  if (spec.analysis == study::Analysis::kEngine) {
    out << " at " << G17(spec.rpm) << " rpm, gas ";
    if (spec.gas.table.empty()) {
      const auto& w = spec.gas.wiebe;
      out << "polytropic-Wiebe (cr " << G17(w.compression_ratio) << ", p_intake " << G17(w.p_intake) << " Pa, p_ambient "
          << G17(w.p_ambient) << " Pa, n " << G17(w.n) << ", burn_start " << G17(w.burn_start) << " rad, burn_duration "
          << G17(w.burn_duration) << " rad, wiebe_a " << G17(w.wiebe_a) << ", wiebe_m " << G17(w.wiebe_m) << ", heat "
          << G17(w.heat) << " J)";
    } else {
      out << "table " << spec.gas.table;
    }
  }
  if (!spec.drive.input.empty()) {
    out << ", " << spec.drive.input << " driven (" << spec.drive.law;
    for (double v : spec.drive.values) out << " " << G17(v);
    out << ")";
  }
  const std::string changed = tools::ChangedParameters(s.base());
  if (!changed.empty()) out << "; the model's parameters set by --params/--set: " << changed;
  out << "\n";
  out << "# sample [1]: the sample's index, 0-based, in the study's order\n";
  for (const study::ParameterSpec& p : spec.parameters)
    out << "# " << p.name << " [model units]: the model's parameter " << p.name << "\n";
  for (size_t k = 0; k < spec.metrics.size(); ++k)
    out << "# " << spec.metrics[k].name << " [" << s.Unit(k) << "]: " << s.Description(k) << "\n";
  out << "# status [text]: ok, rows_failed (some rows did not converge), not_assembled, cycle_failed (flywheel, engine), "
         "simulation_failed (simulate: the run ended before t_end)\n";
  out << "sample";
  for (const study::ParameterSpec& p : spec.parameters) out << "," << p.name;
  for (const study::MetricSpec& m : spec.metrics) out << "," << m.name;
  out << ",status\n";
  std::string line;
  for (size_t i = 0; i < results.size(); ++i) {
    line = std::to_string(i);
    for (size_t k = 0; k < n; ++k) line += "," + G17(values[i * n + k]);
    for (double v : results[i].metrics) line += "," + G17(v);
    line += ",";
    line += results[i].status;
    line += "\n";
    out << line;
  }
}

// The ranks of an MPI run (docs/studies.md, "Across machines"). Compiled with
// -DMECHGEN_STUDY_MPI (`mechgen study` does when it finds an MPI C++ compiler), MPI is started
// only when a launcher (mpirun, mpiexec, srun) started this process: a plain run is serial and
// never touches MPI. Rank 0 decides (the chunks to run, whether to go on) and every rank
// follows its decision; the other ranks send their samples to rank 0 and print nothing.
class Ranks {
 public:
  // Whether a launcher started this process, and as how many ranks (0: unknown).
  static bool Launched(long* size) {
    *size = 0;
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"})
      if (const char* v = std::getenv(name)) {
        *size = std::strtol(v, nullptr, 10);
        return true;
      }
    return std::getenv("PMIX_RANK") != nullptr;
  }
  Ranks(int* argc, char*** argv) {
    long launched_size = 0;
    const bool launched = Launched(&launched_size);
#ifdef MECHGEN_STUDY_MPI
    if (launched) {
      MPI_Init(argc, argv);
      started_ = true;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
#else
    (void)argc, (void)argv;
    serial_under_launcher_ = launched && launched_size > 1;
#endif
    if (rank_ > 0) {  // only rank 0 speaks
      if (std::freopen("/dev/null", "w", stdout) == nullptr) std::fclose(stdout);
      if (std::freopen("/dev/null", "w", stderr) == nullptr) std::fclose(stderr);
    }
  }
  ~Ranks() {
#ifdef MECHGEN_STUDY_MPI
    if (started_) MPI_Finalize();
#endif
  }
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  // Several ranks were launched, but this program has no MPI: each would run the whole study.
  bool serial_under_launcher() const { return serial_under_launcher_; }

  // Rank 0's value on every rank.
  int Agree(int value) const {
#ifdef MECHGEN_STUDY_MPI
    if (size_ > 1) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
    return value;
  }
  void Agree(std::vector<uint64_t>* values) const {
#ifdef MECHGEN_STUDY_MPI
    if (size_ <= 1) return;
    uint64_t n = values->size();
    MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    values->resize(n);
    if (n > 0) MPI_Bcast(values->data(), static_cast<int>(n), MPI_UINT64_T, 0, MPI_COMM_WORLD);
#else
    (void)values;
#endif
  }
  // Returns when every rank has called it (times the gather apart from the wait for the slowest rank).
  void Barrier() const {
#ifdef MECHGEN_STUDY_MPI
    if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
  }
  // Rank r > 0 sends `data`; rank 0 receives rank r's into *data (its size set by the caller).
  void Send(const std::vector<double>& data) const { Transfer(const_cast<double*>(data.data()), data.size(), 0, true); }
  void Receive(int from, std::vector<double>* data) const { Transfer(data->data(), data->size(), from, false); }

 private:
  void Transfer(double* data, uint64_t n, int peer, bool send) const {
#ifdef MECHGEN_STUDY_MPI
    // In pieces of at most 2^26 doubles (an MPI count is an int).
    constexpr uint64_t kPiece = uint64_t(1) << 26;
    for (uint64_t at = 0; at < n; at += kPiece) {
      const int m = static_cast<int>(std::min(kPiece, n - at));
      if (send)
        MPI_Send(data + at, m, MPI_DOUBLE, peer, 7, MPI_COMM_WORLD);
      else
        MPI_Recv(data + at, m, MPI_DOUBLE, peer, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
#else
    (void)data, (void)n, (void)peer, (void)send;
#endif
  }
  int rank_ = 0, size_ = 1;
  bool started_ = false;
  bool serial_under_launcher_ = false;
};

// The chunks of `list` that rank r of `ranks` runs: a contiguous part of it.
std::vector<uint64_t> PartOf(const std::vector<uint64_t>& list, int r, int ranks) {
  const uint64_t n = list.size();
  return std::vector<uint64_t>(list.begin() + n * r / ranks, list.begin() + n * (r + 1) / ranks);
}

}  // namespace

namespace {

int RunStudy(const Ranks& ranks, int argc, char** argv) {
  study_tool::Arguments arguments;
  if (const int parsed = study_tool::ParseArguments(argc, argv, Model::kName, &arguments); parsed >= 0) return parsed;
  const std::string& tool = arguments.tool;
  const std::string &study_path = arguments.study_path, &csv_path = arguments.csv_path,
                    &tolerance_path = arguments.tolerance_path, &envelope_path = arguments.envelope_path;
  std::string shards_path = arguments.shards_path;
  const int threads = arguments.threads;
  const bool quiet = arguments.quiet, no_shards = arguments.no_shards;
  const long long chunk_size = arguments.chunk_size, stop_after = arguments.stop_after;
  if (ranks.serial_under_launcher())
    return tools::UsageError(tool,
                             "started by an MPI launcher as one of several ranks, but this study driver was compiled "
                             "without MPI (each rank would run the whole study): install libopenmpi-dev and run "
                             "`mechgen study --rebuild ...` once, or run it without mpirun");
  // The model's parameters before the study's (--params, then --set), checked before the study.
  study::Study<Model>::Params base;
  std::string params_error;
  if (!tools::ApplyParameters(arguments.params, &base, &params_error)) return tools::UsageError(tool, params_error);

  study::StudySpec spec;
  std::string error;
  if (!study::ReadStudy(study_path, &spec, &error)) {
    std::cerr << error << "\n";
    return tools::kExitUsage;
  }
  study::Study<Model> s;
  s.SetBase(base);
  if (!s.Prepare(spec, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  if (!tolerance_path.empty() && !spec.tolerance)
    return tools::UsageError(tool, "--tolerance-csv: the study does not ask for it (tolerance: true)");
  if (!envelope_path.empty() && spec.envelope.empty())
    return tools::UsageError(tool, "--envelope-csv: the study names no point (envelope: {point: P})");
  mechgen::OutputFile csv, tolerance_csv, envelope_csv;
  if (ranks.Agree(ranks.rank() == 0 && ((!csv_path.empty() && !csv.Open(csv_path, &error)) ||
                                        (!tolerance_path.empty() && !tolerance_csv.Open(tolerance_path, &error)) ||
                                        (!envelope_path.empty() && !envelope_csv.Open(envelope_path, &error))))) {
    std::cerr << "error: " << error << "\n";
    return 1;
  }
  // The samples are drawn as their chunks are run (end to end in chunks: a study of 10^8
  // samples stopped after one chunk holds that chunk alone).
  const study::SampleSource source(spec, s.nominal());
  const uint64_t count = source.count();
  const study::Chunks chunks{count, chunk_size > 0 ? static_cast<uint64_t>(chunk_size) : study::DefaultChunkSize(count)};
  const uint64_t width = s.Width();
  // The shards: rank 0 opens (or checks) the directory first, then the others (on a shared
  // file system they find its study.key; on their own disks they make one).
  if (shards_path.empty() && !no_shards && !csv_path.empty()) shards_path = csv_path + ".shards";
  const study::ShardDirectory shards(shards_path, s.Key(spec.text, source, chunks.size), chunks, width);
  if (!shards_path.empty()) {
    if (ranks.Agree(ranks.rank() == 0 && !shards.Open(&error))) {
      std::cerr << "error: " << error << "\n";
      return 1;
    }
    if (ranks.rank() > 0 && !shards.Open(&error)) shards_path.clear();  // keeps none of its own
  }
  // The results of each chunk, held only for the chunks read or run here.
  std::vector<std::vector<study::SampleResult>> by_chunk(chunks.number());
  auto hold = [&](uint64_t c) { by_chunk[c].resize(chunks.end(c) - chunks.begin(c)); };
  auto slot = [&](uint64_t i) { return &by_chunk[i / chunks.size][i % chunks.size]; };
  // Rank 0 checks the shards there are; the chunks without one are run, split across the ranks.
  std::vector<uint64_t> todo, kept;
  uint64_t resumed = 0;
  std::vector<double> part;
  if (ranks.rank() == 0) {
    for (uint64_t c = 0; c < chunks.number(); ++c) {
      const uint64_t n = chunks.end(c) - chunks.begin(c);
      part.resize(n * width);
      if (!shards_path.empty() && shards.Read(c, part.data())) {
        kept.push_back(c);
        resumed += n;
      } else {
        todo.push_back(c);
      }
    }
  }
  ranks.Agree(&todo);
  const size_t chunks_left = todo.size();
  bool stopped = false;
  if (stop_after > 0) {
    uint64_t take = 0, samples = 0;
    while (take < todo.size() && samples < static_cast<uint64_t>(stop_after))
      samples += chunks.end(todo[take]) - chunks.begin(todo[take]), ++take;
    stopped = take < todo.size();
    todo.resize(take);
  }
  // The shards' contents, read when this run ends the study (a stopped run needs none).
  if (ranks.rank() == 0 && !stopped)
    for (uint64_t c : kept) {
      const uint64_t n = chunks.end(c) - chunks.begin(c);
      part.resize(n * width);
      if (!shards.Read(c, part.data())) {
        std::cerr << "error: the shard of chunk " << c << " in " << shards_path << " changed while the study ran\n";
        return 1;
      }
      hold(c);
      for (uint64_t i = 0; i < n; ++i) by_chunk[c][i] = s.Unpack(&part[i * width]);
    }
  std::vector<double>().swap(part);
  uint64_t run_samples = 0;  // by every rank
  for (uint64_t c : todo) run_samples += chunks.end(c) - chunks.begin(c);
  const std::vector<uint64_t> mine = PartOf(todo, ranks.rank(), ranks.size());
  uint64_t my_samples = 0;
  for (uint64_t c : mine) my_samples += chunks.end(c) - chunks.begin(c);
  std::printf("mechgen study of '%s': %s, %s, %llu samples of %zu parameters, %s over %d steps, %d threads",
              Model::kName, spec.path.c_str(), MethodName(spec.method), static_cast<unsigned long long>(count),
              spec.parameters.size(),
              spec.analysis == study::Analysis::kSweep ? "kinematic sweep" : AnalysisName(spec.analysis),
              spec.steps, threads);
  if (ranks.size() > 1) std::printf(" on each of %d ranks", ranks.size());
  std::printf("\n");
  if (const std::string changed = tools::ChangedParameters(base); !changed.empty())
    std::printf("the model's parameters set by --params/--set: %s\n", changed.c_str());
  if (resumed > 0)
    std::printf("resumed: %llu samples from the shards in %s; %zu of %llu chunks left\n",
                static_cast<unsigned long long>(resumed), shards_path.c_str(), chunks_left,
                static_cast<unsigned long long>(chunks.number()));
  const auto start = std::chrono::steady_clock::now();
  bool printed = false;
  auto progress = [&](uint64_t done) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (quiet || t < 2 || done == 0) return;
    const double rate = done / t;
    std::fprintf(stderr, "\rstudy: %llu/%llu samples%s, %.0f/s, %.0f s left   ",
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(my_samples),
                 ranks.size() > 1 ? " of rank 0" : "", rate, (my_samples - done) / rate);
    printed = true;
  };
  // Each chunk's shard as soon as it is done (from the thread that finished it).
  std::mutex shard_mutex;
  std::string shard_error;
  auto chunk_done = [&](uint64_t c) {
    if (shards_path.empty()) return;
    const uint64_t n = chunks.end(c) - chunks.begin(c);
    std::vector<double> part(n * width);
    for (uint64_t i = 0; i < n; ++i) s.Pack(by_chunk[c][i], &part[i * width]);
    std::string why;
    if (!shards.Write(c, part.data(), &why)) {
      std::lock_guard<std::mutex> lock(shard_mutex);
      if (shard_error.empty()) shard_error = why;
    }
  };
  for (uint64_t c : mine) hold(c);
  s.RunChunks([&source](uint64_t i, double* out) { source.Draw(i, out); }, chunks, mine, threads, slot, chunk_done,
              progress);
  // Rank 0 gathers the others' samples, rank by rank, in the order of their chunks.
  const auto gather_start = std::chrono::steady_clock::now();
  // Every rank done with its part first: the gather's own cost (pack, transfer, unpack) is then
  // timed apart from the wait for the slowest rank.
  ranks.Barrier();
  const auto transfer_start = std::chrono::steady_clock::now();
  if (ranks.size() > 1) {
    if (ranks.rank() > 0) {
      std::vector<double> data(my_samples * width);
      uint64_t at = 0;
      for (uint64_t c : mine)
        for (uint64_t i = chunks.begin(c); i < chunks.end(c); ++i, at += width) s.Pack(*slot(i), &data[at]);
      ranks.Send(data);
    } else {
      for (int r = 1; r < ranks.size(); ++r) {
        const std::vector<uint64_t> theirs = PartOf(todo, r, ranks.size());
        uint64_t n = 0;
        for (uint64_t c : theirs) n += chunks.end(c) - chunks.begin(c);
        std::vector<double> data(n * width);
        ranks.Receive(r, &data);
        uint64_t at = 0;
        for (uint64_t c : theirs) {
          hold(c);
          for (uint64_t i = chunks.begin(c); i < chunks.end(c); ++i, at += width) *slot(i) = s.Unpack(&data[at]);
        }
      }
    }
  }
  if (ranks.size() > 1)
    std::printf("rank 0 ran %llu samples in %.3g s, waited %.3g s for the other ranks, then gathered %llu from %d "
                "ranks in %.3g s\n",
                static_cast<unsigned long long>(my_samples),
                std::chrono::duration<double>(gather_start - start).count(),
                std::chrono::duration<double>(transfer_start - gather_start).count(),
                static_cast<unsigned long long>(run_samples - my_samples), ranks.size() - 1,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - transfer_start).count());
  if (!shard_error.empty()) std::cerr << "warning: " << shard_error << " (the study goes on; it cannot resume from it)\n";
  if (stopped) {
    std::printf("stopped by --stop-after: %llu of %llu samples are in the shards in %s; run the same command again "
                "to resume\n",
                static_cast<unsigned long long>(resumed + run_samples),
                static_cast<unsigned long long>(count), shards_path.empty() ? "(none: --no-shards)" : shards_path.c_str());
    return 4;
  }
  if (ranks.rank() > 0) return 0;  // rank 0 writes the outputs and says the exit status
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The whole study, in sample order, for the outputs.
  std::vector<study::SampleResult> results;
  results.reserve(count);
  for (std::vector<study::SampleResult>& chunk : by_chunk) {
    for (study::SampleResult& r : chunk) results.push_back(std::move(r));
    std::vector<study::SampleResult>().swap(chunk);
  }
  const size_t parameters = spec.parameters.size();
  std::vector<double> values(count * parameters);
  for (uint64_t i = 0; i < count; ++i) source.Draw(i, &values[i * parameters]);
  if (printed) std::fprintf(stderr, "\n");

  // Summary: per status, per metric.
  uint64_t ok = 0, rows_failed = 0, not_assembled = 0;
  for (const study::SampleResult& r : results) {
    const std::string st = r.status;
    ok += st == "ok";
    rows_failed += st == "rows_failed";
    not_assembled += st == "not_assembled" || st == "cycle_failed";
  }
  std::printf(
      "%llu ok, %llu with failed rows, %llu not assembled (or their cycle failed); %.3g s (%.3g samples/s, %.3g ms per sample per thread)\n\n",
      static_cast<unsigned long long>(ok), static_cast<unsigned long long>(rows_failed),
      static_cast<unsigned long long>(not_assembled), seconds, run_samples / seconds,
      1e3 * seconds * threads * ranks.size() / std::max<uint64_t>(run_samples, 1));
  std::vector<std::vector<double>> per_metric(spec.metrics.size());
  for (size_t k = 0; k < spec.metrics.size(); ++k) {
    per_metric[k].reserve(results.size());
    for (const study::SampleResult& r : results) per_metric[k].push_back(r.metrics[k]);
  }
  std::printf("%-28s %-14s %14s %14s %14s %14s\n", "metric", "unit", "nominal", "mean", "sigma", "min .. max");
  for (size_t k = 0; k < spec.metrics.size(); ++k) {
    const study::Moments m = study::MomentsOf(per_metric[k]);
    double lo = INFINITY, hi = -INFINITY;
    for (double v : per_metric[k])
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    std::printf("%-28s %-14s %14.6g %14.6g %14.6g %14.6g .. %.6g\n", spec.metrics[k].name.c_str(), s.Unit(k).c_str(),
                s.Value(k, s.nominal_rows()).value, m.mean, m.sigma, lo, hi);
  }

  // Tolerance analysis: first order at the nominal beside the Monte-Carlo of the ok samples.
  const size_t n = spec.parameters.size();
  std::vector<double> sigma(n), tol(n), clearance(n, 0.0);
  for (size_t p = 0; p < n; ++p) {
    sigma[p] = spec.parameters[p].sigma();
    tol[p] = spec.parameters[p].tolerance;
    for (const study::ClearanceSpec& c : spec.clearances)
      if (c.parameter == spec.parameters[p].name) clearance[p] += c.radial;
  }
  std::string tolerance_text;
  if (spec.tolerance) {
    // Every metric's figures first: the verdicts are decided together (their number corrects
    // each one's level, study/tolerance.h).
    const size_t metrics = spec.metrics.size();
    std::vector<study::Moments> moments(metrics);
    std::vector<study::FirstOrder> first(metrics);
    std::vector<std::string> why(metrics);
    study::VerdictOptions options;
    options.family = 0;
    for (size_t k = 0; k < metrics; ++k) {
      std::vector<double> ok_values;
      for (const study::SampleResult& r : results)
        if (std::string(r.status) == "ok") ok_values.push_back(r.metrics[k]);
      moments[k] = study::MomentsOf(ok_values);
      first[k] = study::FirstOrderOf(s.Gradient(k, &why[k]), sigma, tol, clearance);
      options.family += first[k].complete && moments[k].n >= 2;
    }
    double level = NAN, z = NAN;
    study::CorrectedLevel(options, &level, &z);
    std::printf(
        "\ntolerance analysis: first order at the nominal (generated design derivatives) beside the Monte-Carlo of "
        "the %llu ok samples (mc_sigma_se: the standard error of its sigma, from the sample kurtosis; 95 %% "
        "intervals)\nverdict: the ratio R = fo_sigma / mc_sigma with its interval at %.4g %% each (Sidak: %g %% for "
        "the %d verdict%s together); agrees: the interval inside [%g, %g]; DISAGREES: R outside it and the interval "
        "excludes 1; else inconclusive\n",
        static_cast<unsigned long long>(ok), 100 * level, 100 * (1 - options.alpha), options.family,
        options.family == 1 ? "" : "s", 1 - options.delta, 1 + options.delta);
    std::printf("%-24s %12s %12s %12s %12s %12s %12s %10s %25s  %s\n", "metric", "nominal", "fo_sigma", "fo_worst",
                "clearance", "mc_mean", "mc_sigma", "mc_sigma_se", "mc_sigma_95", "verdict");
    char band[64];
    std::snprintf(band, sizeof(band), "[%g, %g]", 1 - options.delta, 1 + options.delta);
    char level_text[160];
    std::snprintf(level_text, sizeof(level_text),
                  "# ratio: fo_sigma / mc_sigma, ratio_low/high its interval at %.6g %% (Sidak: %g %% for the %d "
                  "verdict%s together)",
                  100 * level, 100 * (1 - options.alpha), options.family, options.family == 1 ? "" : "s");
    tolerance_text =
        "# mechgen study tolerance analysis, model " + std::string(Model::kName) + ": " + spec.path +
        "\n# fo_sigma: first-order root-sum-square sqrt(sum (dm/dp sigma_p)^2); fo_worst: sum |dm/dp| t_p (t: the "
        "tolerance); clearance: sum |dm/dp| c over the joint clearances (worst direction); mc_*: the Monte-Carlo "
        "of the ok samples, with 95 % intervals; mc_sigma_se: the standard error of mc_sigma from the sample "
        "kurtosis mc_kurtosis; units: the metric's\n" +
        std::string(level_text) +
        "; quadratic_share: the share of the metric's variance over the samples that its quadratic terms in the "
        "standardized parameters explain beyond the linear ones; linear_fit_sigma: the sigma of a linear fit to the "
        "samples; decision: agrees (the interval inside " +
        band + "), DISAGREES (the ratio outside it and the interval excluding 1), inconclusive, none (no figure)\n"
        "metric,unit,nominal,fo_sigma,fo_worst,clearance,mc_n,mc_mean,mc_mean_low,mc_mean_high,mc_sigma,mc_sigma_low,"
        "mc_sigma_high,mc_sigma_se,mc_kurtosis,ratio,ratio_low,ratio_high,quadratic_share,linear_fit_sigma,decision,"
        "verdict\n";
    for (size_t k = 0; k < metrics; ++k) {
      const study::Moments& m = moments[k];
      const study::FirstOrder& f = first[k];
      // The curvature over the ok samples (the others NaN: left out), only where it is read.
      study::Curvature curvature;
      if (f.complete && m.n >= 2) {
        std::vector<double> y(results.size());
        for (size_t i = 0; i < results.size(); ++i)
          y[i] = std::string(results[i].status) == "ok" ? results[i].metrics[k] : NAN;
        curvature = study::CurvatureOf(y, values, s.nominal(), sigma);
      }
      const study::Decision decision = study::Decide(f, m, curvature, options);
      std::string verdict = decision.text;
      if (!f.complete) {
        std::string missing;
        for (size_t p = 0; p < n; ++p)
          if (s.design_index()[p] < 0) missing += (missing.empty() ? "" : ", ") + spec.parameters[p].name;
        verdict =
            "no first-order figure: " + (!why[k].empty() ? why[k] : "not a design parameter of the model: " + missing);
      }
      if (ok < count)
        verdict += " (" + std::to_string(count - ok) + " of " + std::to_string(count) +
                   " samples failed and are not in the Monte-Carlo: a change the first order cannot see)";
      char interval[64];
      std::snprintf(interval, sizeof(interval), "[%.5g, %.5g]", m.sigma_low, m.sigma_high);
      std::printf("%-24s %12.6g %12.5g %12.5g %12.5g %12.6g %12.5g %10.2g %25s  %s\n", spec.metrics[k].name.c_str(),
                  s.Value(k, s.nominal_rows()).value, f.rss, f.worst, f.complete ? f.clearance : NAN, m.mean, m.sigma,
                  m.sigma_se, interval, verdict.c_str());
      tolerance_text += spec.metrics[k].name + "," + s.Unit(k) + "," + G17(s.Value(k, s.nominal_rows()).value) + "," +
                        G17(f.rss) + "," + G17(f.worst) + "," + G17(f.complete ? f.clearance : NAN) + "," +
                        std::to_string(m.n) + "," + G17(m.mean) + "," + G17(m.mean_low) + "," + G17(m.mean_high) + "," +
                        G17(m.sigma) + "," + G17(m.sigma_low) + "," + G17(m.sigma_high) + "," + G17(m.sigma_se) + "," +
                        G17(m.kurtosis) + "," + G17(decision.ratio) + "," + G17(decision.ratio_low) + "," +
                        G17(decision.ratio_high) + "," + G17(curvature.share) + "," + G17(curvature.linear_sigma) +
                        "," + study::OutcomeName(decision.outcome) + ",\"" + verdict + "\"\n";
    }
  }

  // The envelope: per row, the point's nominal place, first-order sigma (and worst case) of x
  // and y from dr_P/dp, and the Monte-Carlo's sigma with its interval, over the ok samples.
  std::string envelope_text;
  if (!spec.envelope.empty()) {
    const int rows = spec.steps + 1;
    const bool random = spec.method == study::Method::kMonteCarlo;
    envelope_text = "# mechgen study envelope of " + spec.envelope + ", model " + Model::kName + ": " + spec.path +
                    "\n# per row of the motion: the input " + Model::kQNames[0] +
                    " (rad or model length), the point's nominal x and y (model length), the first-order sigma "
                    "and worst case of x and y from the generated dr_P/dp (as tolerance.csv), the Monte-Carlo's "
                    "sigma of x and y over the ok samples with 95 % intervals\n"
                    "row," +
                    std::string(Model::kQNames[0]) +
                    ",x_nominal,y_nominal,fo_sigma_x,fo_sigma_y,fo_worst_x,"
                    "fo_worst_y,mc_n,mc_sigma_x,mc_sigma_x_low,mc_sigma_x_high,mc_sigma_y,mc_sigma_y_low,"
                    "mc_sigma_y_high\n";
    const std::vector<double> nominal_path = s.Path(s.nominal_rows());
    // First every (row, axis)'s figures, then their verdicts decided together (as the metrics').
    std::vector<study::FirstOrder> f(2 * rows);
    std::vector<study::Moments> m(2 * rows);
    study::VerdictOptions options;
    options.family = 0;
    for (int i = 0; i < rows; ++i)
      for (int axis = 0; axis < 2; ++axis) {
        f[2 * i + axis] = study::FirstOrderOf(s.PathGradient(i, axis), sigma, tol, clearance);
        std::vector<double> v;
        v.reserve(results.size());
        for (const study::SampleResult& r : results)
          if (std::string(r.status) == "ok") v.push_back(r.path[2 * i + axis]);
        m[2 * i + axis] = study::MomentsOf(v);
        options.family += random && f[2 * i + axis].complete && m[2 * i + axis].n >= 2 && m[2 * i + axis].sigma > 0;
      }
    int compared = 0, agrees = 0, inconclusive = 0, disagrees = 0, worst_row = -1;
    double worst_ratio = 1;
    for (int i = 0; i < rows; ++i) {
      std::string line = std::to_string(i) + "," + G17(s.nominal_rows().kinematics[i].q(0)) + "," +
                         G17(nominal_path[2 * i]) + "," + G17(nominal_path[2 * i + 1]);
      for (int axis = 0; axis < 2; ++axis) {
        const study::FirstOrder& fa = f[2 * i + axis];
        const study::Moments& ma = m[2 * i + axis];
        if (random && fa.complete && ma.n >= 2 && ma.sigma > 0) {
          ++compared;
          const study::Outcome o = study::Decide(fa, ma, study::Curvature(), options).outcome;
          agrees += o == study::Outcome::kAgrees;
          inconclusive += o == study::Outcome::kInconclusive;
          disagrees += o == study::Outcome::kDisagrees;
          const double ratio = fa.rss > 0 ? std::max(fa.rss / ma.sigma, ma.sigma / fa.rss) : 0;  // 0: none
          if (ratio > worst_ratio) worst_ratio = ratio, worst_row = i;
        }
      }
      line += "," + G17(f[2 * i].rss) + "," + G17(f[2 * i + 1].rss) + "," + G17(f[2 * i].worst) + "," +
              G17(f[2 * i + 1].worst) + "," + std::to_string(m[2 * i].n) + "," + G17(m[2 * i].sigma) + "," +
              G17(m[2 * i].sigma_low) + "," + G17(m[2 * i].sigma_high) + "," + G17(m[2 * i + 1].sigma) + "," +
              G17(m[2 * i + 1].sigma_low) + "," + G17(m[2 * i + 1].sigma_high) + "\n";
      envelope_text += line;
    }
    if (compared > 0) {
      double level = NAN, z = NAN;
      study::CorrectedLevel(options, &level, &z);
      std::printf(
          "\nenvelope of %s: the first-order sigma of x and y against the Monte-Carlo's at %d (row, axis), each at "
          "%.4g %% (Sidak: %g %% for all together): agrees within %g %% at %d, inconclusive at %d, DISAGREES at %d; "
          "the largest ratio between the two, %.4g, at row %d (%s = %.6g)\n",
          spec.envelope.c_str(), compared, 100 * level, 100 * (1 - options.alpha), 100 * options.delta, agrees,
          inconclusive, disagrees, worst_ratio, worst_row, Model::kQNames[0],
          worst_row >= 0 ? s.nominal_rows().kinematics[worst_row].q(0) : NAN);
    }
  }

  if (!csv_path.empty()) WriteCsv(s, values, results, csv.stream());
  if (!envelope_path.empty()) envelope_csv.stream() << envelope_text;
  if (!tolerance_path.empty()) tolerance_csv.stream() << tolerance_text;
  if ((!csv_path.empty() && !csv.Close(&error)) || (!tolerance_path.empty() && !tolerance_csv.Close(&error)) ||
      (!envelope_path.empty() && !envelope_csv.Close(&error)) || (!csv_path.empty() && !csv.Commit(&error)) ||
      (!tolerance_path.empty() && !tolerance_csv.Commit(&error)) ||
      (!envelope_path.empty() && !envelope_csv.Commit(&error))) {
    std::cerr << "error: " << error << "\n";
    return 1;
  }
  if (!shards_path.empty()) shards.Remove();
  if (!csv_path.empty())
    std::printf("\nwrote %s (%llu rows x %zu columns)\n", csv_path.c_str(), static_cast<unsigned long long>(count),
                spec.parameters.size() + spec.metrics.size() + 2);
  if (!tolerance_path.empty()) std::printf("wrote %s\n", tolerance_path.c_str());
  if (!envelope_path.empty()) std::printf("wrote %s\n", envelope_path.c_str());
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "error: cannot write the standard output\n";
    return 1;
  }
  return ok == count ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  const Ranks ranks(&argc, &argv);
  const int status = RunStudy(ranks, argc, argv);
  return ranks.Agree(status);  // every rank ends as rank 0 does
}
