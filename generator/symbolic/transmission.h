// Transmission angles of the four-bar loops: at the joint between a loop's coupler and its
// output link, the angle mu between the two links (the transmission angle of Alt; Paul
// appendix A classifies the same loops). mu = 0 or pi is a toggle of the output, where
// Phi_phi loses rank (|det| of the loop's block is b c |sin mu|); 90 deg transmits force
// best. Emitted as EvalTransmissionAngles (codegen/functions.cc) and printed by the report.
#pragma once

#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "model/model.h"
#include "symbolic/blocks.h"

namespace mechgen {

struct TransmissionAngle {
  int loop = -1;                        ///< index into Topology::loops
  std::string joint;                    ///< the coupler–output joint where mu is measured
  std::string driver, coupler, output;  ///< link names
  GiNaC::ex cross, dot;                 ///< mu = atan2(|cross|, dot), in q, phi, p
  GiNaC::ex u2, v2;                     ///< |u|^2, |v|^2: cos mu = dot / sqrt(u2 v2)
  std::string Text() const;  ///< "at joint C between coupler 'coupler' and output 'rocker' (loop 1, driven by 'crank')"
};

/// One entry per four-bar loop (four revolute joints) that holds the ground. The driver
/// is the ground-adjacent link that is an input, or else the one solved first; the other
/// ground-adjacent link is the output.
std::vector<TransmissionAngle> FindTransmissionAngles(const Model& m, const Topology& t, const Kinematics& k,
                                                      const std::vector<Block>& blocks);

}  // namespace mechgen
