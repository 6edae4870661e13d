/**
 * \file analysis/study_request.h
 * What the design study is asked for (analysis/study.h runs it): the study file and how to run
 * it (threads, shards, chunks), with their defaults, where its outputs go, and the ranks it runs
 * on, all independent of the model, so that the command line's parser (tools/study_args.cc,
 * CLI11) fills them without compiling anything model-dependent. The counts are checked by
 * whoever fills them (the parser: the ranges its --help lists); the study file, the parameters
 * and the study against the model Check(model, request) in analysis/study.h.
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mechgen/analysis/params.h"

namespace mechgen::analysis {

/// A design study of the model: its study file (docs/studies.md) and how to run it.
struct StudyRequest {
  std::string study_path;     ///< the study file (YAML)
  bool timings = false;       ///< each phase's wall and CPU time on stderr
  int threads = 1;            ///< threads over the samples
  bool quiet = false;         ///< no progress line on stderr
  std::string shards_path;    ///< the shards' directory (empty: F.shards with the CSV F)
  bool no_shards = false;     ///< keep no shards
  long long chunk_size = 0;   ///< samples per chunk (0: study/shards.h's DefaultChunkSize)
  long long stop_after = 0;   ///< run at most this many more samples, then stop (0: to the end)
  tools::ParameterOptions params;  ///< --params, --set: the model's parameters before the study's
};

/// Where the study's outputs go (each empty: not written) and how its messages name the command.
struct StudyOutputs {
  std::string tool = "study";  ///< the command's name in usage errors
  std::string csv_path, tolerance_path, envelope_path;
  std::string summary_path, histogram_path;  ///< the statistics
};

/**
 * The processes a study runs on (docs/studies.md, "Across machines"): this one alone here
 * (rank 0 of 1: every call below does nothing); the study command's MPI ranks
 * (tools/study_run.h) override it. Rank 0 decides and every rank follows its decision; the
 * other ranks send their samples (and rows) to rank 0.
 */
class StudyRanks {
 public:
  virtual ~StudyRanks() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Rank 0's value on every rank.
  virtual int Agree(int value) const { return value; }
  virtual void Agree(std::vector<uint64_t>* /*values*/) const {}
  /// Returns when every rank has called it.
  virtual void Barrier() const {}
  /// Rank r > 0 sends `data`; rank 0 receives rank r's into *data (its size set by the caller).
  virtual void Send(const std::vector<double>& /*data*/) const {}
  virtual void Receive(int /*from*/, std::vector<double>* /*data*/) const {}
  virtual void Send(const std::vector<uint64_t>& /*data*/) const {}
  virtual void Receive(int /*from*/, std::vector<uint64_t>* /*data*/) const {}
  virtual void Send(const std::string& /*data*/) const {}
  virtual void Receive(int /*from*/, std::string* /*data*/) const {}
};

}  // namespace mechgen::analysis
