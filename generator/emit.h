// Emission: fills templates/mechanism.{h,cc}.mustache with a model's derivation and
// writes <name>.h and <name>.cc, both or neither (written to temporaries, then renamed).
#pragma once

#include <string>

#include "derivation.h"
#include "analysis/kinematics.h"
#include "model/model.h"
#include "analysis/topology.h"
#include "transmission.h"

namespace mechgen {

struct EmittedModel {
  std::string header, source;  ///< file contents
  OpCounts phi_ops, coefficient_ops, scene_ops, transmission_ops;
};

/// Renders the two files. Fails (std::runtime_error) when a template names a value the
/// generator does not provide, or is malformed.
EmittedModel Emit(const Model& m, const Topology& t, const Kinematics& k, const Derivation& d,
                  const std::vector<TransmissionAngle>& transmission, CxxPrinter* printer,
                  const std::string& templates_dir);

/// Writes both files into `dir` atomically as a pair; returns false with *error set.
bool WriteFiles(const std::string& dir, const std::string& name, const EmittedModel& e,
                std::string* error);

}  // namespace mechgen
