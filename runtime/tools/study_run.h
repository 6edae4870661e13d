// The study command around the design study (mechgen/analysis/study.h: Check, Run): the parsed
// options (study_args.h) are the analysis's StudyRequest and StudyOutputs, and this process' MPI
// ranks (Ranks below, an analysis::StudyRanks) are the ones it runs on. The per-model study
// program (study_main.cc) runs analysis::Run on the generated model's type (fixed sizes);
// mechgen_view study (view/study.cc) on the model view, instantiated once in
// mechgen_runtime_view (runtime/view/analysis_study.cc). Nothing here depends on the model.
//
// Through the view, not yet (refused by common/not_through_view.h before anything is computed
// or written: a usage error naming the per-model program, or for mechgen the fallback to it):
// where mechgen_view was built without MPI, a run under an MPI launcher (the ranks:
// -DMECHGEN_STUDY_MPI, which the build gives mechgen_view's study where CMake finds MPI, and
// mechgen the per-model program where it finds an MPI C++ compiler).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "common/not_through_view.h"
#include "common/numbers.h"
#include "mechgen/analysis/study_request.h"
#include "study_args.h"

#ifdef MECHGEN_STUDY_MPI
#define OMPI_SKIP_MPICXX 1  // the C interface only (no C++ bindings to compile or link)
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace mechgen::study_tool {
namespace run_internal {

// The ranks of an MPI run (docs/studies.md, "Across machines"). Compiled with
// -DMECHGEN_STUDY_MPI (`mechgen study` does when it finds an MPI C++ compiler), MPI is started
// only when a launcher (mpirun, mpiexec, srun) started this process: a plain run is serial and
// never touches MPI. Rank 0 decides (the chunks to run, whether to go on) and every rank
// follows its decision; the other ranks send their samples to rank 0 and print nothing.
class Ranks : public analysis::StudyRanks {
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
  ~Ranks() override {
#ifdef MECHGEN_STUDY_MPI
    if (started_) MPI_Finalize();
#endif
  }
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  // Several ranks were launched, but this program has no MPI: each would run the whole study.
  bool serial_under_launcher() const { return serial_under_launcher_; }

  // Rank 0's value on every rank.
  int Agree(int value) const override {
#ifdef MECHGEN_STUDY_MPI
    if (size_ > 1) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
    return value;
  }
  void Agree(std::vector<uint64_t>* values) const override {
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
  void Barrier() const override {
#ifdef MECHGEN_STUDY_MPI
    if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
  }
  // Rank r > 0 sends `data`; rank 0 receives rank r's into *data (its size set by the caller):
  // doubles (the packed results), 64-bit counts (the sizes of a rank's rows), bytes (its rows).
  void Send(const std::vector<double>& data) const override { Transfer(data.data(), data.size(), 0, true); }
  void Receive(int from, std::vector<double>* data) const override { Transfer(data->data(), data->size(), from, false); }
  void Send(const std::vector<uint64_t>& data) const override { Transfer(data.data(), data.size(), 0, true); }
  void Receive(int from, std::vector<uint64_t>* data) const override { Transfer(data->data(), data->size(), from, false); }
  void Send(const std::string& data) const override { Transfer(data.data(), data.size(), 0, true); }
  void Receive(int from, std::string* data) const override { Transfer(&(*data)[0], data->size(), from, false); }

 private:
  template <class T>
  void Transfer(const T* data, uint64_t n, int peer, bool send) const {
#ifdef MECHGEN_STUDY_MPI
    // In pieces of at most 2^26 elements (an MPI count is an int).
    const MPI_Datatype type = std::is_same<T, double>::value     ? MPI_DOUBLE
                              : std::is_same<T, uint64_t>::value ? MPI_UINT64_T
                                                                 : MPI_CHAR;
    constexpr uint64_t kPiece = uint64_t(1) << 26;
    for (uint64_t at = 0; at < n; at += kPiece) {
      const int m = static_cast<int>(std::min(kPiece, n - at));
      if (send)
        MPI_Send(const_cast<T*>(data) + at, m, type, peer, 7, MPI_COMM_WORLD);
      else
        MPI_Recv(const_cast<T*>(data) + at, m, type, peer, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
#else
    (void)data, (void)n, (void)peer, (void)send;
#endif
  }
  int rank_ = 0, size_ = 1;
  bool started_ = false;
  bool serial_under_launcher_ = false;
};

}  // namespace run_internal

/// What `run` (analysis::Run on the model) is given: the request, the outputs, the ranks.
using RunFn = std::function<int(const analysis::StudyRequest&, const analysis::StudyOutputs&,
                                const analysis::StudyRanks&)>;

/**
 * \brief The study command with the parsed `arguments` (study_args.h) on this process' MPI
 *        `ranks` (made before the arguments were parsed: MPI_Init reads them): what the ranks
 *        refuse, then `run`.
 * \param model  The model's name (the view's refusal names it).
 * \param view   Run through the model view (mechgen_view study): without MPI, a run under a
 *               launcher is refused (common/not_through_view.h).
 * \return The exit status (study_main.cc); every rank ends as rank 0 does (the caller's
 *         ranks.Agree).
 */
inline int RunCommand(const run_internal::Ranks& ranks, const Arguments& arguments, const std::string& model,
                      bool view, const RunFn& run) {
  const std::string& tool = arguments.tool;
#ifndef MECHGEN_STUDY_MPI
  if (view) {
    // (mechgen_view built without MPI: the ranks are the per-model program's, compiled with it
    // where mechgen finds an MPI C++ compiler; with MPI, the view runs them as it does)
    long launched_size = 0;
    if (run_internal::Ranks::Launched(&launched_size))
      return tools::NotThroughView(tool, "a run under an MPI launcher (the ranks: MPI) is", model, "study");
  }
#else
  (void)model, (void)view;
#endif
  if (ranks.serial_under_launcher())
    return tools::UsageError(tool,
                             "started by an MPI launcher as one of several ranks, but this study driver was compiled "
                             "without MPI (each rank would run the whole study): install libopenmpi-dev and run "
                             "`mechgen study --rebuild ...` once, or run it without mpirun");
  return run(arguments, arguments, ranks);
}

}  // namespace mechgen::study_tool
