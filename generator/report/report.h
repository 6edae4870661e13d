// `mechgen report`: a human-readable account of a model — links, joints, loops, mobility
// by both criteria, coordinates, the loop equations, Phi_phi, Phi_q and K — in plain text
// or LaTeX, so a user can compare them with hand-derived formulas.
#pragma once

#include <ostream>

#include "analysis/grashof.h"
#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "codegen/emit.h"
#include "model/model.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"

namespace mechgen {

enum class ReportFormat { kText, kLatex };

void WriteReport(const Model& m, const Topology& t, const std::vector<FourBarLoop>& four_bars,
                 const Kinematics& k, const SymbolicTable& d,
                 const std::vector<TransmissionAngle>& transmission, const EmittedModel& e, ReportFormat format, std::ostream& os);

}  // namespace mechgen
