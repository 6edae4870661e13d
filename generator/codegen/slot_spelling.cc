// The slots' C++ spelling. See slot_spelling.h.
#include "codegen/slot_spelling.h"

namespace mechgen {

std::string SlotSpelling(const Slot& s) {
  const std::string i = std::to_string(s.i), j = std::to_string(s.j);
  switch (s.kind) {
    case Slot::Kind::kK: return "c.K(" + i + ", " + j + ")";
    case Slot::Kind::kL: return "c.L(" + i + ", " + j + ")";
    case Slot::Kind::kPhiPhi: return "c.Phi_phi(" + i + ", " + j + ")";
    case Slot::Kind::kQd: return "qd(" + i + ")";
    case Slot::Kind::kQdd: return "qdd(" + i + ")";
    case Slot::Kind::kPhid: return "phid(" + i + ")";
    case Slot::Kind::kTime: return "t";
    case Slot::Kind::kFriction: return "friction_" + i;  // a local of the body (statics_functions.cc)
    case Slot::Kind::kDphiDp: return "dc.dphi_dp(" + i + ", " + j + ")";
    case Slot::Kind::kDKDp: return "dc.dK_dp(" + i + ", " + j + ")";
    case Slot::Kind::kDLDp: return "dc.dL_dp(" + i + ", " + j + ")";
  }
  return "";
}

void NameSlots(const SlotSymbols& slots, CxxPrinter* printer) {
  for (const auto& [sym, slot] : slots.all()) printer->Name(sym, SlotSpelling(slot));
}

}  // namespace mechgen
