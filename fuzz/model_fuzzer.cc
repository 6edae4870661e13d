// libFuzzer target: a model file through the generator's front end.
//
// Each input is written to a temporary file (LoadModel reads a path) and run through
// LoadModel (YAML syntax, names, references, expressions), Validate (loops, mobility, cams,
// ...), DeriveKinematics, the symbolic table (Phi, Phi_phi, Phi_q, K, L) and the function
// builders with CSE. A bad model must end in a mechgen::ModelError or another
// std::exception (GiNaC reports e.g. a division by zero that way); a crash, a sanitizer
// report, a timeout or running out of memory is a finding. Emission (templates) is not
// fuzzed: it only formats what the builders produced.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "analysis/validate.h"
#include "codegen/cxx_code.h"
#include "codegen/functions.h"
#include "model/model.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"

namespace {

std::string TempPath() {
  static const std::string path =
      "/tmp/mechgen_fuzz_" + std::to_string(static_cast<long>(getpid())) + ".yaml";
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // Models are small text files; 64 KiB keeps each run fast without losing structure.
  if (size > 65536) return 0;
  const std::string path = TempPath();
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
