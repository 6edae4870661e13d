// `mechgen report`: a human-readable account of a model — parameters, links, joints, loops,
// mobility by both criteria, coordinates and input ranges, the loop equations, Phi_phi,
// Phi_q, and K and L block by block in the solve order as the generated code computes them
// (each block's inverse as fractions: adjugate over determinant), the requested points'
// r_P, K_P and L_P, det Phi_phi, the assembly modes and the branch, transmission angles —
// in plain text or LaTeX (a fragment, or with --standalone a complete document), so a user
// can compare them with hand-derived formulas. The same bytes on every run
// (report/expr_printer.h).
//
// Plain text writes K(i, j) = d phi(i) / d q(j) as K_i_j, L(i, j + nq k) as L_i_j_k, the
// names the generated code gives its locals; every formula is in GiNaC's syntax.
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

enum class ReportFormat {
  kText,
  kLatex,          ///< a fragment for a document with \usepackage{amsmath}
  kLatexDocument,  ///< a complete document (article, amsmath, geometry: texlive-latex-base)
};

void WriteReport(const Model& m, const Topology& t, const std::vector<FourBarLoop>& four_bars,
                 const Kinematics& k, const SymbolicTable& d,
                 const std::vector<TransmissionAngle>& transmission, const EmittedModel& e, ReportFormat format, std::ostream& os);

}  // namespace mechgen
