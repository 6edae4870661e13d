// How the generated functions spell the slots (symbolic/slot.h) they read: the only place
// that knows EvalCoefficients' output is the argument `c`, the friction loads locals
// friction_<i> read from the argument `friction`, and so on.
#pragma once

#include <string>

#include "codegen/cxx_code.h"
#include "symbolic/slot.h"

namespace mechgen {

/// c.K(i, j), c.L(i, j), c.Phi_phi(i, j), qd(i), qdd(i), phid(i), t, friction_<i>.
std::string SlotSpelling(const Slot& s);
/// Names every symbol of `slots` for the printer by its slot's spelling.
void NameSlots(const SlotSymbols& slots, CxxPrinter* printer);

}  // namespace mechgen
