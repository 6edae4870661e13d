// The sweep target's body (see targets.h): the sweep command's main() of
// runtime/tools/sweep_main.cc for the fourbar model, renamed fuzz_sweep_main, run on the
// fuzzed argument list. Its headers are included first, so that renaming `main` touches
// only the command's own definition.
#pragma once

#include <CLI/CLI.hpp>

#include "fourbar.h"
#include "mechgen/io/csv.h"
#include "mechgen/io/svg.h"
#include "mechgen/io/table.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/sweep/sweep.h"

#ifndef MECHGEN_MODEL_INCLUDE
#define MECHGEN_MODEL_INCLUDE "fourbar.h"
#define MECHGEN_MODEL_NAMESPACE mech::fourbar
#endif
#define main fuzz_sweep_main
#include MECHGEN_SWEEP_MAIN
#undef main

// Define MECHGEN_FUZZ_NO_GENERATOR before including this file when the generator's headers
// are not wanted (the sweep fuzzer, its replay test).
#include "targets.h"

namespace mechgen_fuzz {

/// Runs the sweep command on the input's arguments; returns its exit status (-1: skipped).
inline int FuzzSweep(const uint8_t* data, size_t size) {
  std::vector<std::string> args;
  if (!FuzzSweepArguments(data, size, &args)) return -1;
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(&a[0]);
  argv.push_back(nullptr);
  return fuzz_sweep_main(static_cast<int>(args.size()), argv.data());
}

}  // namespace mechgen_fuzz
