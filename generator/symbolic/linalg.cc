// The adjugate of a small matrix. See linalg.h.
#include "symbolic/linalg.h"

namespace mechgen {

GiNaC::matrix Adjugate(const GiNaC::matrix& a) {
  const unsigned n = a.rows();
  GiNaC::matrix adj(n, n);
  if (n == 1) {
    adj(0, 0) = 1;
    return adj;
  }
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = 0; j < n; ++j) {
      GiNaC::matrix minor(n - 1, n - 1);
      for (unsigned r = 0, mr = 0; r < n; ++r) {
        if (r == j) continue;
        for (unsigned c = 0, mc = 0; c < n; ++c) {
          if (c == i) continue;
          minor(mr, mc++) = a(r, c);
        }
        ++mr;
      }
      adj(i, j) = ((i + j) % 2 ? -1 : 1) * minor.determinant(GiNaC::determinant_algo::laplace);
    }
  return adj;
}

GiNaC::matrix AdjugateInverse(const GiNaC::matrix& a, const GiNaC::ex& inv_det) {
  const unsigned n = a.rows();
  const GiNaC::matrix adj = Adjugate(a);
  GiNaC::matrix inv(n, n);
  for (unsigned i = 0; i < n; ++i)
    for (unsigned j = 0; j < n; ++j) inv(i, j) = adj(i, j) * inv_det;
  return inv;
}

}  // namespace mechgen
