// Phi_phi's conditioning for the model view (core/linear_algebra.h, ConditionAndDeterminantDynamic:
// fixed-size copies of 1 to 16 rows, then a bounded one), instantiated once for the library
// mechgen_runtime_view (core/view_runtime.h declares them extern): sixteen sizes of Eigen's
// PartialPivLU and its rcond, the longest compile of the library, in a translation unit of its
// own so that it builds beside the others.
//
// (GCC 12's -Wmaybe-uninitialized sees Eigen's rcond estimate (rcond_invmatrix_L1_norm_estimate)
// compare old_sign_vector before its first write at the odd fixed sizes; the loop writes it on
// the first iteration before any read. Compiled within dynamics.cc and statics.cc, as before,
// the same code drew no warning: inlined there, GCC followed the loop.)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "mechgen/core/view_runtime.h"

namespace mechgen {
template void ConditionAndDeterminantDynamic<1, Eigen::Map<const Eigen::MatrixXd>>(
    const Eigen::Map<const Eigen::MatrixXd>&, double*, double*);
template void ConditionAndDeterminantDynamic<1, ModelTypes<ViewModel>::MatCPhi>(const ModelTypes<ViewModel>::MatCPhi&,
                                                                                double*, double*);
}  // namespace mechgen
