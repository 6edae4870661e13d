// The study command's options with CLI11 (study_args.h). Independent of the model.
#include "study_args.h"

#include <algorithm>
#include <string>
#include <thread>

#include "common/cli.h"

namespace mechgen::study_tool {

int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments) {
  Arguments& a = *arguments;
  a.tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{"A design study of the mechgen model '" + model_name +
               "': parameters varied on a grid, a list, a Latin hypercube or by Monte-Carlo, an analysis per "
               "sample, metrics per sample in a CSV, and the first-order tolerance analysis beside the "
               "Monte-Carlo (docs/studies.md)."};
  app.footer(
      "Exit status: 0 done, 3 done but some samples failed (status column), 2 bad arguments or a bad "
      "study file, 1 the study does not fit the model or an output cannot be written, 4 stopped by "
      "--stop-after (run again to resume). Under mpirun (a driver compiled with MPI) the samples are split "
      "across the ranks, each using --threads threads; rank 0 writes the outputs, the same bytes.");
  a.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--study", a.study_path, "the study file (YAML; docs/studies.md)")->required();
  tools::Count(&app, "--threads", &a.threads, 1, 1024, "threads over the samples (default: the cores)");
  app.add_option("--csv", a.csv_path, "write one row per sample to this CSV file");
  app.add_option("--tolerance-csv", a.tolerance_path,
                 "write the tolerance analysis (first order beside Monte-Carlo) to this CSV file");
  app.add_option("--envelope-csv", a.envelope_path,
                 "write the envelope of the study's point (envelope: {point: P}) to this CSV file: per row its "
                 "nominal place and the first-order and Monte-Carlo sigma of x and y");
  app.add_option("--summary-csv", a.summary_path,
                 "write each metric's statistics over the ok samples to this CSV file: n, mean, sigma, min, the "
                 "quantiles 1, 5, 25, 50, 75, 95, 99 % and max (with rows: none, without a row per sample)");
  app.add_option("--histogram-csv", a.histogram_path,
                 "write each metric's histogram over the ok samples to this CSV file (histogram_bins: equal bins "
                 "from its min to its max)");
  app.add_flag("--quiet", a.quiet, "no progress line on stderr");
  app.add_flag("--timings", a.timings,
               "print each phase's wall and CPU time on stderr (setup, the samples, the rows written after them, "
               "the statistics, the commit) and the serial part's share");
  app.add_option("--shards", a.shards_path,
                 "keep each chunk's results in this directory as it is done, and resume from it when run again "
                 "(default with --csv F: F.shards; removed when the study is done)");
  app.add_flag("--no-shards", a.no_shards, "keep no shards (a study that is stopped starts again from nothing)");
  tools::Count(&app, "--chunk", &a.chunk_size, 1, 1LL << 40,
               "samples per chunk (default: about 1/256 of the study, 64 to 65536); a resumed study needs the same");
  tools::Count(&app, "--stop-after", &a.stop_after, 1, 1LL << 62,
               "evaluate at most this many more samples (whole chunks), keep their shards and stop (exit 4): "
               "running again resumes");
  // The model's parameters before the study's: what the study does not vary keeps these, and a
  // parameter without nominal: is drawn about its value here.
  tools::AddParameterOptions(&app, &a.params);
  if (const int parsed = tools::Parse(&app, argc, argv, a.tool); parsed >= 0) return parsed;
  if (a.no_shards && !a.shards_path.empty()) return tools::UsageError(a.tool, "--shards and --no-shards: give one");
  return -1;
}

}  // namespace mechgen::study_tool
