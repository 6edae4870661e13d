/**
 * \file analysis/study.h
 * The design study as an analysis (issue 43: one analysis layer for every tool): the model's
 * parameters varied as a study file says (docs/studies.md; study/spec.h), an analysis per sample
 * (study/run.h's Study), metrics per sample, asked for by a StudyRequest
 * (analysis/study_request.h). Check(model, request, outputs) says what is wrong with the request
 * on this model; Run(model, request, outputs, ranks) runs the study and writes its outputs, each
 * whole or not at all. One source for the per-model study program (tools/study_main.cc, M the
 * generated model's type, fixed sizes; what `mechgen study MODEL` built for every model before
 * issue 43) and for the model view (M = ViewModel: runtime/view/analysis_study.cc, declared in
 * analysis/view_analysis.h; `mechgen_view study`). The command around it (tools/study_run.h):
 * the options as the request, the MPI ranks (a StudyRanks), what the view refuses.
 *
 * Runs the samples in chunks on N threads (study/run.h's RunPacked: each sample drawn, analysed
 * and packed by the thread that takes it; one model, per-thread solver and rows); each chunk's
 * CSV rows are made by the thread that finished it (study/rows.h) and written in sample order by
 * the calling thread as the chunks are done (the same bytes for any N and ranks); then a summary
 * of each metric, the statistics (--summary-csv, --histogram-csv; with rows: none alone) and,
 * with `tolerance: true`, the first-order tolerance analysis from the generated sensitivities
 * beside the Monte-Carlo's figures. Every CSV is a column table of study/rows.h (its names line by
 * io/csv.h, its cells by AppendRow): the samples', the statistics', the tolerance analysis' and
 * the envelope's. Progress on stderr (rate, time left) for studies longer than
 * ~2 s. Exit statuses as tools/study_main.cc says.
 *
 * --params/--set read the model's parameter table (analysis/view_params.h). Through the view a
 * simulation with drive: (dynamics/prescribed.h compiled once), analysis: flywheel and engine
 * (the machines' cycles compiled once: machines/view_machines.h), Coulomb friction's stick and
 * slip, and the design derivatives (tolerance: true, of analysis: flywheel too: the view's cycle
 * design derivatives; envelope:, the design_margin metric: the view's Design, StaticsDesign and
 * DesignChecks).
 */
#pragma once

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <ostream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"
#include "mechgen/analysis/study_request.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/output_file.h"
#include "mechgen/study/rows.h"
#include "mechgen/study/run.h"
#include "mechgen/study/samples.h"
#include "mechgen/study/shards.h"
#include "mechgen/study/tolerance.h"
#include "mechgen/table/columns.h"

namespace mechgen::analysis {
namespace study_internal {

namespace study = mechgen::study;
namespace tools = mechgen::tools;

using study::G17;  // "%.17g", NaN as "nan" (study/rows.h)

inline double Now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
// CPU seconds of the process (every thread), or of the calling thread.
inline double ProcessCpu() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
inline double ThreadCpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// fn(0) .. fn(n - 1) on `threads` threads (the calling one among them), each index once.
template <class Fn>
void ParallelFor(uint64_t n, int threads, Fn&& fn) {
  std::atomic<uint64_t> next{0};
  auto work = [&]() {
    for (uint64_t i; (i = next.fetch_add(1)) < n;) fn(i);
  };
  std::vector<std::thread> pool;
  const uint64_t workers = std::min<uint64_t>(static_cast<uint64_t>(std::max(threads, 1)), std::max<uint64_t>(n, 1));
  for (uint64_t t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

inline const char* MethodName(study::Method m) {
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

inline const char* AnalysisName(study::Analysis a) {
  return a == study::Analysis::kStatics    ? "statics"
         : a == study::Analysis::kFlywheel ? "flywheel"
         : a == study::Analysis::kSimulate  ? "simulate"
         : a == study::Analysis::kPositions ? "positions"
         : a == study::Analysis::kEngine    ? "engine"
                                            : "sweep";
}

// The CSV's columns (study/rows.h's SampleColumns): the study's parameters, its metrics with
// their units and meanings (the study's Unit and Description).
template <class M>
table::Columns<study::SampleRow> CsvColumns(const study::Study<M>& s) {
  const study::StudySpec& spec = s.spec();
  std::vector<std::string> parameters;
  for (const study::ParameterSpec& p : spec.parameters) parameters.push_back(p.name);
  std::vector<study::MetricColumn> metrics;
  for (size_t k = 0; k < spec.metrics.size(); ++k) metrics.push_back({spec.metrics[k].name, s.Unit(k), s.Description(k)});
  return study::SampleColumns(parameters, metrics);
}

// The CSV's head (io/csv.h): what wrote it, then each column's unit and meaning, the header.
// The rows follow, a chunk at a time (study/rows.h's AppendRows).
template <class M>
void WriteCsvHead(const study::Study<M>& s, const table::Columns<study::SampleRow>& columns, uint64_t count,
                  std::ostream& out) {
  const study::StudySpec& spec = s.spec();
  std::ostringstream about;
  about << "mechgen study, model " << ModelCalls<M>::Name(s.model()) << ": " << spec.path << ", method "
        << MethodName(spec.method) << ", " << count << " samples, seed " << spec.seed << ", analysis "
        << AnalysisName(spec.analysis) << " in " << spec.steps << " steps";
  if (spec.analysis == study::Analysis::kSimulate) about << " to t_end " << G17(spec.t_end) << " s";
  if (spec.analysis == study::Analysis::kEngine) {
    about << " at " << G17(spec.rpm) << " rpm, gas ";
    if (spec.gas.table.empty()) {
      const auto& w = spec.gas.wiebe;
      about << "polytropic-Wiebe (cr " << G17(w.compression_ratio) << ", p_intake " << G17(w.p_intake)
            << " Pa, p_ambient " << G17(w.p_ambient) << " Pa, n " << G17(w.n) << ", burn_start " << G17(w.burn_start)
            << " rad, burn_duration " << G17(w.burn_duration) << " rad, wiebe_a " << G17(w.wiebe_a) << ", wiebe_m "
            << G17(w.wiebe_m) << ", heat " << G17(w.heat) << " J)";
    } else {
      about << "table " << spec.gas.table;
    }
  }
  if (!spec.drive.input.empty()) {
    about << ", " << spec.drive.input << " driven (" << spec.drive.law;
    for (double v : spec.drive.values) about << " " << G17(v);
    about << ")";
  }
  const std::string changed = tools::ChangedModelParameters(s.model(), s.base());
  if (!changed.empty()) about << "; the model's parameters set by --params/--set: " << changed;
  mechgen::WriteCsvHeader(columns, out, mechgen::Described(about.str()));
}

// The chunks of `list` that rank r of `ranks` runs: a contiguous part of it.
inline std::vector<uint64_t> PartOf(const std::vector<uint64_t>& list, int r, int ranks) {
  const uint64_t n = list.size();
  return std::vector<uint64_t>(list.begin() + n * r / ranks, list.begin() + n * (r + 1) / ranks);
}

// What Check and Run share: the model's parameters before the study's (--params, then --set),
// the study file, the study against the model (Study::Prepare into *s), the outputs against
// the study. -1 to go on, else the exit status with *error its one line; *usage: the line is a
// usage error's message ("<tool>: error: " before it), else printed as it is.
template <class M>
int Prepare(const M& model, const StudyRequest& request, const StudyOutputs& outputs, study::StudySpec* spec,
            study::Study<M>* s, std::string* error, bool* usage) {
  using C = ModelCalls<M>;
  *usage = false;
  typename study::Study<M>::Params base = C::DefaultParams(model);
  if (!tools::ApplyModelParameters(request.params, model, &base, error)) {
    *usage = true;
    return tools::kExitUsage;
  }
  if (!study::ReadStudy(request.study_path, spec, error)) return tools::kExitUsage;
  s->SetBase(base);
  if (!s->Prepare(*spec, error)) return 1;
  *usage = true;
  if (!outputs.tolerance_path.empty() && !spec->tolerance) {
    *error = "--tolerance-csv: the study does not ask for it (tolerance: true)";
    return tools::kExitUsage;
  }
  if (!outputs.envelope_path.empty() && spec->envelope.empty()) {
    *error = "--envelope-csv: the study names no point (envelope: {point: P})";
    return tools::kExitUsage;
  }
  if (!outputs.csv_path.empty() && !spec->rows) {
    *error = "--csv: the study asks for its statistics alone (rows: none at " + spec->path + ":" +
             std::to_string(spec->rows_place.line) + ":" + std::to_string(spec->rows_place.column) +
             "); give --summary-csv or --histogram-csv, or rows: all for a row per sample";
    return tools::kExitUsage;
  }
  *usage = false;
  return -1;
}

}  // namespace study_internal

/// What is wrong with `request` (and its `outputs`) on `model` (one line), empty when Run can go
/// on: the parameters, the study file (file:line:column), the study against the model, an
/// output the study does not make.
template <class M>
std::string Check(const M& model, const StudyRequest& request, const StudyOutputs& outputs) {
  study::StudySpec spec;
  study::Study<M> s(model);
  std::string error;
  bool usage = false;
  if (study_internal::Prepare(model, request, outputs, &spec, &s, &error, &usage) < 0) return "";
  return error;
}

/**
 * \brief The study asked for by `request` on `model`, its outputs written to `outputs`, on this
 *        process' `ranks` (a plain StudyRanks: this process alone).
 * \tparam M  A generated model (the per-model study program) or mechgen::ViewModel.
 * \return The exit status (tools/study_main.cc); every rank ends as rank 0 does (the caller's
 *         ranks.Agree).
 */
template <class M>
int Run(const M& model, const StudyRequest& request, const StudyOutputs& outputs, const StudyRanks& ranks) {
  using namespace study_internal;
  using C = ModelCalls<M>;
  const char* const name = C::Name(model);
  const double t_start = Now(), cpu_start = ProcessCpu(), main_cpu_start = ThreadCpu();
  const std::string& tool = outputs.tool;
  const std::string &csv_path = outputs.csv_path, &tolerance_path = outputs.tolerance_path,
                    &envelope_path = outputs.envelope_path;
  std::string shards_path = request.shards_path;
  const int threads = request.threads;
  const bool quiet = request.quiet, no_shards = request.no_shards;
  const long long chunk_size = request.chunk_size, stop_after = request.stop_after;
  study::StudySpec spec;
  study::Study<M> s(model);
  std::string error;
  bool usage = false;
  if (const int status = Prepare(model, request, outputs, &spec, &s, &error, &usage); status >= 0) {
    if (usage) return tools::UsageError(tool, error);
    std::cerr << error << "\n";
    return status;
  }
  const typename study::Study<M>::Params& base = s.base();
  const std::string &summary_path = outputs.summary_path, &histogram_path = outputs.histogram_path;
  mechgen::OutputFile csv, tolerance_csv, envelope_csv, summary_csv, histogram_csv;
  if (ranks.Agree(ranks.rank() == 0 && ((!csv_path.empty() && !csv.Open(csv_path, &error)) ||
                                        (!tolerance_path.empty() && !tolerance_csv.Open(tolerance_path, &error)) ||
                                        (!envelope_path.empty() && !envelope_csv.Open(envelope_path, &error)) ||
                                        (!summary_path.empty() && !summary_csv.Open(summary_path, &error)) ||
                                        (!histogram_path.empty() && !histogram_csv.Open(histogram_path, &error))))) {
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
  // Each chunk's packed results (width doubles per sample: Study::Pack's layout), held only for
  // the chunks read or run here; with rows, its values (until its rows are made) and its rows
  // (until they are written).
  struct Held {
    // Not zero-filled (new double[]): the pages are first touched by the threads that fill them.
    std::unique_ptr<double[]> packed, values;
    std::string text;
    std::atomic<bool> formatted{false};  // text holds the chunk's rows (release: set after them)
  };
  std::vector<Held> held(chunks.number());
  const size_t parameters = spec.parameters.size(), metrics = spec.metrics.size();
  auto samples_of = [&](uint64_t c) { return chunks.end(c) - chunks.begin(c); };
  auto hold = [&](uint64_t c) { held[c].packed.reset(new double[samples_of(c) * width]); };
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
  std::vector<double>().swap(part);
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
  // The rows are made (by the thread that ran or read a chunk, on the rank that ran it) when
  // this run ends the study with a CSV; rank 0 writes them in sample order.
  const bool make_rows = !stopped && spec.rows && ranks.Agree(!csv_path.empty() ? 1 : 0) != 0;
  const table::Columns<study::SampleRow> csv_columns = make_rows ? CsvColumns(s) : table::Columns<study::SampleRow>();
  auto make_text = [&](uint64_t c) {
    Held& h = held[c];
    const uint64_t b = chunks.begin(c), n = chunks.end(c) - b;
    if (!h.values) {  // read from a shard: drawn here
      h.values.reset(new double[n * parameters + 1]);
      for (uint64_t i = 0; i < n; ++i) source.Draw(b + i, &h.values[i * parameters]);
    }
    h.text.clear();
    h.text.reserve(n * (20 + 24 * (parameters + metrics)));
    study::AppendRows(csv_columns, b, n, h.values.get(), parameters, h.packed.get(), width, &h.text);
    h.values.reset();
    h.formatted.store(true, std::memory_order_release);
  };
  // The writer (rank 0, the calling thread): the chunks whose rows are made, in order, as far
  // as they go; the rest after the gather.
  uint64_t written = 0;
  auto write_ready = [&]() {
    if (!make_rows || ranks.rank() != 0) return;
    while (written < chunks.number() && held[written].formatted.load(std::memory_order_acquire)) {
      csv.stream() << held[written].text;
      std::string().swap(held[written].text);
      ++written;
    }
  };
  if (make_rows && ranks.rank() == 0) WriteCsvHead(s, csv_columns, count, csv.stream());
  // The shards' contents, read when this run ends the study (a stopped run needs none), and
  // their rows made on every thread.
  if (ranks.rank() == 0 && !stopped) {
    for (uint64_t c : kept) {
      hold(c);
      if (!shards.Read(c, held[c].packed.get())) {
        std::cerr << "error: the shard of chunk " << c << " in " << shards_path << " changed while the study ran\n";
        return 1;
      }
    }
    if (make_rows) ParallelFor(kept.size(), threads, [&](uint64_t j) { make_text(kept[j]); });
  }
  uint64_t run_samples = 0;  // by every rank
  for (uint64_t c : todo) run_samples += chunks.end(c) - chunks.begin(c);
  const std::vector<uint64_t> mine = PartOf(todo, ranks.rank(), ranks.size());
  uint64_t my_samples = 0;
  for (uint64_t c : mine) my_samples += chunks.end(c) - chunks.begin(c);
  std::printf("mechgen study of '%s': %s, %s, %llu samples of %zu parameters, %s over %d steps, %d threads",
              name, spec.path.c_str(), MethodName(spec.method), static_cast<unsigned long long>(count),
              spec.parameters.size(),
              spec.analysis == study::Analysis::kSweep ? "kinematic sweep" : AnalysisName(spec.analysis),
              spec.steps, threads);
  if (ranks.size() > 1) std::printf(" on each of %d ranks", ranks.size());
  std::printf("\n");
  if (const std::string changed = tools::ChangedModelParameters(model, base); !changed.empty())
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
  // Each chunk, once its last sample is done, on the thread that did it: its shard, its rows.
  std::mutex shard_mutex;
  std::string shard_error;
  auto chunk_done = [&](uint64_t c) {
    if (!shards_path.empty()) {
      std::string why;
      if (!shards.Write(c, held[c].packed.get(), &why)) {
        std::lock_guard<std::mutex> lock(shard_mutex);
        if (shard_error.empty()) shard_error = why;
      }
    }
    if (make_rows) make_text(c);
  };
  for (uint64_t c : mine) {
    hold(c);
    if (make_rows) held[c].values.reset(new double[samples_of(c) * parameters + 1]);
  }
  auto place = [&](uint64_t i) {
    const uint64_t c = i / chunks.size;
    return std::pair<uint64_t, uint64_t>(c, i - chunks.begin(c));
  };
  const double t_run = Now(), cpu_run = ProcessCpu(), main_cpu_run = ThreadCpu();
  s.RunPacked(
      source, chunks, mine, threads,
      make_rows ? std::function<double*(uint64_t)>([&](uint64_t i) {
        const auto [c, k] = place(i);
        return &held[c].values[k * parameters];
      })
                : std::function<double*(uint64_t)>(),
      [&](uint64_t i) {
        const auto [c, k] = place(i);
        return &held[c].packed[k * width];
      },
      chunk_done, progress, write_ready);
  const double t_ran = Now(), cpu_ran = ProcessCpu(), main_cpu_ran = ThreadCpu();
  // Rank 0 gathers the others' samples (and their rows), rank by rank, in the order of their chunks.
  const auto gather_start = std::chrono::steady_clock::now();
  // Every rank done with its part first: the gather's own cost (pack, transfer, unpack) is then
  // timed apart from the wait for the slowest rank.
  ranks.Barrier();
  const auto transfer_start = std::chrono::steady_clock::now();
  if (ranks.size() > 1) {
    if (ranks.rank() > 0) {
      std::vector<double> data;
      data.reserve(my_samples * width);
      std::vector<uint64_t> sizes;
      std::string text;
      for (uint64_t c : mine) {
        data.insert(data.end(), held[c].packed.get(), held[c].packed.get() + samples_of(c) * width);
        held[c].packed.reset();
        if (make_rows) {
          sizes.push_back(held[c].text.size());
          text += held[c].text;
          std::string().swap(held[c].text);
        }
      }
      ranks.Send(data);
      if (make_rows) {
        ranks.Send(sizes);
        ranks.Send(text);
      }
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
          std::copy(data.begin() + at, data.begin() + at + samples_of(c) * width, held[c].packed.get());
          at += samples_of(c) * width;
        }
        if (make_rows) {
          std::vector<uint64_t> sizes(theirs.size());
          ranks.Receive(r, &sizes);
          uint64_t bytes = 0;
          for (uint64_t b : sizes) bytes += b;
          std::string text(bytes, '\0');
          ranks.Receive(r, &text);
          uint64_t from = 0;
          for (size_t j = 0; j < theirs.size(); ++j) {
            held[theirs[j]].text.assign(text, from, sizes[j]);
            from += sizes[j];
            held[theirs[j]].formatted.store(true, std::memory_order_release);
          }
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
  // The rows not written while the samples ran (the other ranks', the last chunks').
  const double t_tail = Now(), main_cpu_tail = ThreadCpu();
  write_ready();
  if (make_rows && written != chunks.number()) {
    std::cerr << "error: internal: the rows of chunk " << written << " were not made\n";
    return 1;
  }
  const double t_written = Now();
  // The whole study's results, in sample order (held by chunk), for the statistics.
  const double code_ok = study::StatusCode("ok");
  // fn(i, r) for every sample i in order, r its Width() doubles.
  auto each_result = [&](auto&& fn) {
    for (uint64_t c = 0; c < chunks.number(); ++c)
      for (uint64_t i = chunks.begin(c), at = 0; i < chunks.end(c); ++i, at += width) fn(i, held[c].packed.get() + at);
  };
  if (printed) std::fprintf(stderr, "\n");

  // Summary: per status, per metric.
  uint64_t ok = 0, rows_failed = 0, not_assembled = 0;
  {
    const double code_rows = study::StatusCode("rows_failed"), code_not = study::StatusCode("not_assembled"),
                 code_cycle = study::StatusCode("cycle_failed");
    for (uint64_t c = 0; c < chunks.number(); ++c)
      for (uint64_t i = 0; i < samples_of(c); ++i) {
        const double code = held[c].packed[i * width];
        ok += code == code_ok;
        rows_failed += code == code_rows;
        not_assembled += code == code_not || code == code_cycle;
      }
  }
  std::printf(
      "%llu ok, %llu with failed rows, %llu not assembled (or their cycle failed); %.3g s (%.3g samples/s, %.3g ms per sample per thread)\n\n",
      static_cast<unsigned long long>(ok), static_cast<unsigned long long>(rows_failed),
      static_cast<unsigned long long>(not_assembled), seconds, run_samples / seconds,
      1e3 * seconds * threads * ranks.size() / std::max<uint64_t>(run_samples, 1));
  const double main_cpu_tail_statistics = ThreadCpu();
  // Each metric's values in sample order: every sample's (the summary's min .. max and mean)
  // and the ok samples' (the others NaN: the statistics, the tolerance table), copied a chunk
  // per thread; their figures on every thread, the same bits for any number (study/rows.h).
  // (Every sample ok: the two are the same, the first is not made.)
  const bool all_ok = ok == count;
  std::vector<std::vector<double>> column(metrics, std::vector<double>(all_ok ? 0 : count)),
      ok_column(metrics, std::vector<double>(count));
  std::vector<std::vector<double>> chunk_low(metrics, std::vector<double>(chunks.number(), INFINITY)),
      chunk_high(metrics, std::vector<double>(chunks.number(), -INFINITY));
  ParallelFor(chunks.number(), threads, [&](uint64_t c) {
    const double* r = held[c].packed.get();
    for (uint64_t i = chunks.begin(c); i < chunks.end(c); ++i, r += width)
      for (size_t k = 0; k < metrics; ++k) {
        const double v = r[1 + k];
        if (!all_ok) column[k][i] = v;
        ok_column[k][i] = r[0] == code_ok ? v : NAN;
        if (std::isfinite(v))
          chunk_low[k][c] = std::min(chunk_low[k][c], v), chunk_high[k][c] = std::max(chunk_high[k][c], v);
      }
  });
  std::vector<study::Moments> all_moments(metrics), ok_moments(metrics);
  std::vector<double> lowest(metrics, INFINITY), highest(metrics, -INFINITY);
  std::vector<study::ColumnStatistics> statistics(metrics);
  const bool want_statistics = !summary_path.empty() || !histogram_path.empty();
  for (size_t k = 0; k < metrics; ++k) {
    ok_moments[k] = study::MomentsOf(ok_column[k], threads);
    // Every sample ok: the same values in the same places, so the same moments.
    all_moments[k] = all_ok ? ok_moments[k] : study::MomentsOf(column[k], threads);
    std::vector<double>().swap(column[k]);
    for (uint64_t c = 0; c < chunks.number(); ++c)
      lowest[k] = std::min(lowest[k], chunk_low[k][c]), highest[k] = std::max(highest[k], chunk_high[k][c]);
    if (want_statistics)
      statistics[k] = study::StatisticsOf(ok_column[k], spec.histogram_bins, threads, &ok_moments[k]);
  }
  const double main_cpu_statistics_parallel = ThreadCpu() - main_cpu_tail_statistics;
  std::printf("%-28s %-14s %14s %14s %14s %14s\n", "metric", "unit", "nominal", "mean", "sigma", "min .. max");
  for (size_t k = 0; k < metrics; ++k)
    std::printf("%-28s %-14s %14.6g %14.6g %14.6g %14.6g .. %.6g\n", spec.metrics[k].name.c_str(), s.Unit(k).c_str(),
                s.Value(k, s.nominal_rows()).value, all_moments[k].mean, all_moments[k].sigma, lowest[k], highest[k]);
  // The statistics of the ok samples (--summary-csv, --histogram-csv).
  std::string summary_text, histogram_text;
  if (want_statistics) {
    const std::string what = "# mechgen study statistics, model " + std::string(name) + ": " + spec.path +
                             ", method " + MethodName(spec.method) + ", " + std::to_string(count) + " samples, " +
                             std::to_string(ok) + " ok, seed " + std::to_string(spec.seed) + ", analysis " +
                             AnalysisName(spec.analysis) + "\n";
    // Each a column table (study/rows.h): its names line (io/csv.h), its rows' cells.
    const table::Columns<study::SummaryRow> summary_columns = study::SummaryColumns();
    const table::Columns<study::HistogramRow> histogram_columns = study::HistogramColumns();
    std::ostringstream summary_names, histogram_names;
    mechgen::WriteCsvHeader(summary_columns, summary_names);
    mechgen::WriteCsvHeader(histogram_columns, histogram_names);
    summary_text = what +
                   "# per metric over the finite values of the ok samples, in the metric's unit: n; mean and sigma "
                   "(n - 1) in two passes in sample order; min; the p-quantiles, each the ceil(p n)-th smallest value "
                   "(exact); max\n" +
                   summary_names.str();
    histogram_text = what +
                     "# per metric over the finite values of the ok samples: " + std::to_string(spec.histogram_bins) +
                     " equal bins from its min to its max (low <= v < high; the last bin includes max), the count "
                     "in each; low and high in the metric's unit\n" +
                     histogram_names.str();
    for (size_t k = 0; k < metrics; ++k) {
      const study::ColumnStatistics& st = statistics[k];
      study::AppendRow(summary_columns, study::SummaryRow{spec.metrics[k].name, s.Unit(k), &st}, &summary_text);
      for (size_t b = 0; b < st.histogram.size(); ++b) {
        const double low = st.min + static_cast<double>(b) * st.bin_width;
        const double high = b + 1 == st.histogram.size() ? st.max : st.min + static_cast<double>(b + 1) * st.bin_width;
        study::AppendRow(histogram_columns,
                         study::HistogramRow{spec.metrics[k].name, b, st.histogram[b], st.moments.n > 0 ? low : NAN,
                                             st.moments.n > 0 ? high : NAN},
                         &histogram_text);
      }
    }
  }

  // The samples' values for the tolerance analysis' curvature, drawn again on every thread.
  std::vector<double> values;
  if (spec.tolerance) {
    values.resize(count * parameters);
    ParallelFor(chunks.number(), threads, [&](uint64_t c) {
      for (uint64_t i = chunks.begin(c); i < chunks.end(c); ++i) source.Draw(i, &values[i * parameters]);
    });
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
      moments[k] = ok_moments[k];
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
    // A column table (study/rows.h): its names line (io/csv.h), its rows' cells.
    const table::Columns<study::ToleranceRow> tolerance_columns = study::ToleranceColumns();
    std::ostringstream tolerance_names;
    mechgen::WriteCsvHeader(tolerance_columns, tolerance_names);
    tolerance_text =
        "# mechgen study tolerance analysis, model " + std::string(name) + ": " + spec.path +
        "\n# fo_sigma: first-order root-sum-square sqrt(sum (dm/dp sigma_p)^2); fo_worst: sum |dm/dp| t_p (t: the "
        "tolerance); clearance: sum |dm/dp| c over the joint clearances (worst direction); mc_*: the Monte-Carlo "
        "of the ok samples, with 95 % intervals; mc_sigma_se: the standard error of mc_sigma from the sample "
        "kurtosis mc_kurtosis; units: the metric's\n" +
        std::string(level_text) +
        "; quadratic_share: the share of the metric's variance over the samples that its quadratic terms in the "
        "standardized parameters explain beyond the linear ones; linear_fit_sigma: the sigma of a linear fit to the "
        "samples; decision: agrees (the interval inside " +
        band + "), DISAGREES (the ratio outside it and the interval excluding 1), inconclusive, none (no figure)\n" +
        tolerance_names.str();
    for (size_t k = 0; k < metrics; ++k) {
      const study::Moments& m = moments[k];
      const study::FirstOrder& f = first[k];
      // The curvature over the ok samples (the others NaN: left out), only where it is read.
      study::Curvature curvature;
      if (f.complete && m.n >= 2) {
        curvature = study::CurvatureOf(ok_column[k], values, s.nominal(), sigma);
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
      study::AppendRow(tolerance_columns,
                       study::ToleranceRow{spec.metrics[k].name, s.Unit(k), s.Value(k, s.nominal_rows()).value, &f, &m,
                                           &curvature, &decision, verdict},
                       &tolerance_text);
    }
  }

  // The envelope: per row, the point's nominal place, first-order sigma (and worst case) of x
  // and y from dr_P/dp, and the Monte-Carlo's sigma with its interval, over the ok samples.
  std::string envelope_text;
  if (!spec.envelope.empty()) {
    const int rows = spec.steps + 1;
    const bool random = spec.method == study::Method::kMonteCarlo;
    // A column table (study/rows.h): its names line (io/csv.h), its rows' cells.
    const table::Columns<study::EnvelopeRow> envelope_columns = study::EnvelopeColumns(C::QName(model, 0));
    std::ostringstream envelope_names;
    mechgen::WriteCsvHeader(envelope_columns, envelope_names);
    envelope_text = "# mechgen study envelope of " + spec.envelope + ", model " + name + ": " + spec.path +
                    "\n# per row of the motion: the input " + C::QName(model, 0) +
                    " (rad or model length), the point's nominal x and y (model length), the first-order sigma "
                    "and worst case of x and y from the generated dr_P/dp (as tolerance.csv), the Monte-Carlo's "
                    "sigma of x and y over the ok samples with 95 % intervals\n" +
                    envelope_names.str();
    const std::vector<double> nominal_path = s.Path(s.nominal_rows());
    // First every (row, axis)'s figures, then their verdicts decided together (as the metrics').
    std::vector<study::FirstOrder> f(2 * rows);
    std::vector<study::Moments> m(2 * rows);
    study::VerdictOptions options;
    options.family = 0;
    // Each (row, axis)'s moments over the ok samples in sample order, on every thread.
    ParallelFor(2 * static_cast<uint64_t>(rows), threads, [&](uint64_t j) {
      std::vector<double> v(count);
      each_result([&](uint64_t i, const double* r) { v[i] = r[0] == code_ok ? r[1 + metrics + j] : NAN; });
      m[j] = study::MomentsOf(v);
    });
    for (int i = 0; i < rows; ++i)
      for (int axis = 0; axis < 2; ++axis) {
        f[2 * i + axis] = study::FirstOrderOf(s.PathGradient(i, axis), sigma, tol, clearance);
        options.family += random && f[2 * i + axis].complete && m[2 * i + axis].n >= 2 && m[2 * i + axis].sigma > 0;
      }
    int compared = 0, agrees = 0, inconclusive = 0, disagrees = 0, worst_row = -1;
    double worst_ratio = 1;
    for (int i = 0; i < rows; ++i) {
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
      study::AppendRow(envelope_columns,
                       study::EnvelopeRow{static_cast<uint64_t>(i), s.nominal_rows().kinematics[i].q(0),
                                          nominal_path[2 * i], nominal_path[2 * i + 1], &f[2 * i], &f[2 * i + 1],
                                          &m[2 * i], &m[2 * i + 1]},
                       &envelope_text);
    }
    if (compared > 0) {
      double level = NAN, z = NAN;
      study::CorrectedLevel(options, &level, &z);
      std::printf(
          "\nenvelope of %s: the first-order sigma of x and y against the Monte-Carlo's at %d (row, axis), each at "
          "%.4g %% (Sidak: %g %% for all together): agrees within %g %% at %d, inconclusive at %d, DISAGREES at %d; "
          "the largest ratio between the two, %.4g, at row %d (%s = %.6g)\n",
          spec.envelope.c_str(), compared, 100 * level, 100 * (1 - options.alpha), 100 * options.delta, agrees,
          inconclusive, disagrees, worst_ratio, worst_row, C::QName(model, 0),
          worst_row >= 0 ? s.nominal_rows().kinematics[worst_row].q(0) : NAN);
    }
  }

  if (!envelope_path.empty()) envelope_csv.stream() << envelope_text;
  if (!tolerance_path.empty()) tolerance_csv.stream() << tolerance_text;
  if (!summary_path.empty()) summary_csv.stream() << summary_text;
  if (!histogram_path.empty()) histogram_csv.stream() << histogram_text;
  const double t_statistics = Now(), main_cpu_statistics = ThreadCpu();
  if ((!csv_path.empty() && !csv.Close(&error)) || (!tolerance_path.empty() && !tolerance_csv.Close(&error)) ||
      (!envelope_path.empty() && !envelope_csv.Close(&error)) ||
      (!summary_path.empty() && !summary_csv.Close(&error)) ||
      (!histogram_path.empty() && !histogram_csv.Close(&error)) || (!csv_path.empty() && !csv.Commit(&error)) ||
      (!tolerance_path.empty() && !tolerance_csv.Commit(&error)) ||
      (!envelope_path.empty() && !envelope_csv.Commit(&error)) ||
      (!summary_path.empty() && !summary_csv.Commit(&error)) ||
      (!histogram_path.empty() && !histogram_csv.Commit(&error))) {
    std::cerr << "error: " << error << "\n";
    return 1;
  }
  if (!shards_path.empty()) shards.Remove();
  if (!csv_path.empty())
    std::printf("\nwrote %s (%llu rows x %zu columns)\n", csv_path.c_str(), static_cast<unsigned long long>(count),
                csv_columns.size());
  if (!tolerance_path.empty()) std::printf("wrote %s\n", tolerance_path.c_str());
  if (!envelope_path.empty()) std::printf("wrote %s\n", envelope_path.c_str());
  if (!summary_path.empty()) std::printf("wrote %s\n", summary_path.c_str());
  if (!histogram_path.empty()) std::printf("wrote %s\n", histogram_path.c_str());
  if (request.timings) {
    // The program's own account (docs/studies.md, "Speed"): wall and CPU of each phase. Serial:
    // what one thread does whatever the threads (the calling thread's CPU: the setup, the
    // writer while the samples run and after, the tolerance and envelope tables, the commit),
    // but for the metrics' statistics, which run on every thread (fixed blocks); parallel: the
    // samples (the workers' CPU) and the statistics.
    const double t_end = Now(), cpu_end = ProcessCpu(), main_cpu_end = ThreadCpu();
    const double samples_cpu = (cpu_ran - cpu_run) - (main_cpu_ran - main_cpu_run);
    const double serial = (main_cpu_end - main_cpu_start) - main_cpu_statistics_parallel;
    const double cpu = cpu_end - cpu_start;
    std::fprintf(stderr,
                 "timings: setup %.4f s (cpu %.4f); samples %.4f s (cpu %.4f on the workers, %.4f ms per sample; the "
                 "writer %.4f cpu alongside); rows after them %.4f s; statistics %.4f s (cpu %.4f of the calling "
                 "thread, %.4f of it on every thread); commit %.4f s; total %.4f s, cpu %.4f; serial cpu %.4f s = "
                 "%.2f %% of the cpu\n",
                 t_run - t_start, main_cpu_run - main_cpu_start, t_ran - t_run, samples_cpu,
                 1e3 * samples_cpu / std::max<uint64_t>(my_samples, 1), main_cpu_ran - main_cpu_run, t_written - t_tail,
                 t_statistics - t_written, main_cpu_statistics - main_cpu_tail, main_cpu_statistics_parallel,
                 t_end - t_statistics, t_end - t_start, cpu, serial, 100 * serial / std::max(cpu, 1e-9));
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "error: cannot write the standard output\n";
    return 1;
  }
  return ok == count ? 0 : 3;

}

}  // namespace mechgen::analysis
