// Slots and their symbols. See slot.h.
#include "symbolic/slot.h"

namespace mechgen {

std::string Slot::SymbolName() const {
  const std::string i_ = std::to_string(i), j_ = std::to_string(j);
  switch (kind) {
    case Kind::kK: return "K_" + i_ + "_" + j_;
    case Kind::kL: return "L_" + i_ + "_" + j_;
    case Kind::kPhiPhi: return "Phi_phi_" + i_ + "_" + j_;
    case Kind::kQd: return "qd_" + i_;
    case Kind::kQdd: return "qdd_" + i_;
    case Kind::kPhid: return "phid_" + i_;
    case Kind::kTime: return "t";
    case Kind::kFriction: return "friction_" + i_;
    case Kind::kDphiDp: return "dphi_dp_" + i_ + "_" + j_;
    case Kind::kDKDp: return "dK_dp_" + i_ + "_" + j_;
    case Kind::kDLDp: return "dL_dp_" + i_ + "_" + j_;
  }
  return "slot";
}

GiNaC::ex SlotSymbols::operator()(const Slot& s) {
  auto it = index_.find(s);
  if (it == index_.end()) {
    const GiNaC::ex sym = GiNaC::symbol(s.SymbolName());
    it = index_.emplace(s, sym).first;
    list_.emplace_back(sym, s);
  }
  return it->second;
}

}  // namespace mechgen
