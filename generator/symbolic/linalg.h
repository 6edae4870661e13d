// Small symbolic linear algebra shared by the table (K and L block by block), the statics
// (the multipliers, Phi_phi^T lambda = -g_phi) and the report: the adjugate of a small
// matrix and the inverse it gives.
#pragma once

#include <ginac/ginac.h>

namespace mechgen {

/// adj(a): entry (i, j) is the cofactor of a(j, i), (-1)^(i+j) det(a without row j and
/// column i) by Laplace expansion; [1] for a 1 x 1 matrix.
GiNaC::matrix Adjugate(const GiNaC::matrix& a);
/// a^-1 = adj(a) inv_det, each entry cofactor * inv_det (inv_det = 1 / det a, named by the caller).
GiNaC::matrix AdjugateInverse(const GiNaC::matrix& a, const GiNaC::ex& inv_det);

}  // namespace mechgen
