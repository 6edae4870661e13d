// The bodies of the fuzz targets, shared by the libFuzzer programs (fuzz/*_fuzzer.cc,
// built by fuzz/CMakeLists.txt with clang and sanitizers) and by the ordinary test binary
// that replays every finding kept in fuzz/regressions/<target>/ (tests/generator/
// fuzz_replay_test.cc, run by ctest without libFuzzer). Each body takes one input and must
// return normally: a bad input ends in a clean rejection (a mechgen::ModelError or another
// std::exception caught here, or a non-zero exit status of the sweep command); a crash, a
// sanitizer report, an escaping exception, a hang or a memory blow-up is a finding.
//
//   model       a model file: LoadModel -> Validate -> DeriveKinematics -> the symbolic
//               table (blocks, closed forms, reach checks) -> the function builders with CSE
//   expression  one expression of the model language (models/README.md, "Expressions"),
//               read as the reader reads a point coordinate; byte 0 selects the names in
//               scope (bit 0: a cam contour's u); then differentiated (as the derivation
//               does) and printed as C++
//   sweep       the sweep command's arguments, one per line (fuzz_sweep_main, the command's
//               main() of runtime/tools/sweep_main.cc compiled for the fourbar model):
//               FuzzSweepArguments turns the input into argv; paths with '/' and step counts
//               above kMaxFuzzSteps are skipped (the target must not write outside its
//               working directory, nor spend seconds on one valid input)
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#ifndef MECHGEN_FUZZ_NO_GENERATOR
#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "analysis/validate.h"
#include "codegen/cxx_code.h"
#include "codegen/functions.h"
#include "model/model.h"
#include "model/reader.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"
#endif

namespace mechgen_fuzz {

#ifndef MECHGEN_FUZZ_NO_GENERATOR

inline std::string TempModelPath() {
  static const std::string path =
      "/tmp/mechgen_fuzz_" + std::to_string(static_cast<long>(getpid())) + ".yaml";
  return path;
}

/// A model file through the generator's front end and builders.
inline int FuzzModel(const uint8_t* data, size_t size) {
  // Models are small text files; 64 KiB keeps each run fast without losing structure.
  if (size > 65536) return 0;
  const std::string path = TempModelPath();
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data, 1, size, file);
  std::fclose(file);
  try {
    const mechgen::Model model = mechgen::LoadModel(path);
    const mechgen::Analysis analysis = mechgen::Validate(model);
    const mechgen::Topology& topology = analysis.topology;
    const mechgen::Kinematics kinematics =
        mechgen::DeriveKinematics(model, topology, &analysis.coordinates, &analysis.cams);
    const mechgen::SymbolicTable table(model, kinematics);
    const auto transmission = mechgen::FindTransmissionAngles(model, topology, kinematics, table.blocks);
    mechgen::CxxPrinter printer;
    for (const mechgen::FunctionSpec& f : mechgen::BuildFunctions(model, kinematics, table, transmission, &printer))
      for (const mechgen::Program& p : f.body) (void)mechgen::EmitProgram(p, &printer);
  } catch (const std::exception&) {
    // A clean rejection.
  }
  return 0;
}

/// One expression through the reader's checked expression language, then d/dparameter and
/// the C++ printer.
inline int FuzzExpression(const uint8_t* data, size_t size) {
  if (size < 1 || size > 8192) return 0;
  static mechgen::Model model = [] {
    mechgen::Model m;
    m.file = "fuzz.yaml";
    const char* names[] = {"a", "b", "c", "d", "e", "r"};
    const double values[] = {1.0, 2.5, 0.0, -3.0, 1e-3, 0.5};
    for (int i = 0; i < 6; ++i) {
      mechgen::Parameter p;
      p.name = names[i];
      p.value = values[i];
      p.symbol = GiNaC::symbol(names[i]);
      m.params.push_back(p);
    }
    return m;
  }();
  static const GiNaC::symbol u("u");
  const bool with_u = (data[0] & 1) != 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    mechgen::SectionReader reader(&model);
    reader.SetSource(&text);
    const YAML::Node node(text);
    const GiNaC::ex e = reader.Expression(node, "x", with_u ? &u : nullptr);
    mechgen::CxxPrinter printer;
    (void)printer.Print(e);
    (void)printer.Print(e.diff(GiNaC::ex_to<GiNaC::symbol>(model.params[0].symbol)));
    if (with_u) (void)printer.Print(e.diff(u, 2));
    if (!with_u) (void)mechgen::ValueAtDefaults(model, e, {}, "x");
  } catch (const std::exception&) {
    // A clean rejection.
  }
  return 0;
}

#endif  // MECHGEN_FUZZ_NO_GENERATOR

/// Step counts above this are skipped by the sweep target (a valid sweep of 10^6 steps is
/// not a bug, only slow).
constexpr long kMaxFuzzSteps = 2000;

/// The input as the sweep command's argv ("fourbar_sweep" first), one argument per line;
/// false if the input is skipped (see the file comment).
inline bool FuzzSweepArguments(const uint8_t* data, size_t size, std::vector<std::string>* args) {
  if (size > 4096) return false;
  args->assign(1, "fourbar_sweep");
  std::string current;
  for (size_t i = 0; i <= size; ++i) {
    if (i == size || data[i] == '\n') {
      if (i < size || !current.empty()) args->push_back(current);
      current.clear();
      continue;
    }
    current += static_cast<char>(data[i]);
  }
  if (args->size() > 64) return false;
  for (size_t i = 1; i < args->size(); ++i) {
    const std::string& a = (*args)[i];
    if (a.find('/') != std::string::npos || a.find('\0') != std::string::npos) return false;
    // Any number-like argument (or option=value) is checked: CLI11 accepts --steps=N,
    // --steps N, and values that follow other options.
    const size_t eq = a.find('=');
    const std::string value = eq == std::string::npos ? a : a.substr(eq + 1);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end != value.c_str() && !(v <= static_cast<double>(kMaxFuzzSteps) && v >= -1e6)) return false;
    // Hex, octal and binary forms CLI11 reads as integers.
    if (value.size() > 2 && value[0] == '0' && (value[1] == 'x' || value[1] == 'X' || value[1] == 'b' ||
                                                value[1] == 'B' || value[1] == 'o' || value[1] == 'O'))
      return false;
  }
  return true;
}

}  // namespace mechgen_fuzz
