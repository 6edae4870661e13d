// What a generated function reads besides q, phi and the parameters, by meaning: a slot is
// a coefficient of EvalCoefficients' output (K(i, j), L(i, j + nq k), Phi_phi(r, c)), an
// argument (qd(j), qdd(j), phid(i), t) or a given load (friction(i)). The symbolic layer
// makes one symbol per slot it reads and keeps the slot beside it; only the printer
// (codegen/slot_spelling.h) spells a slot as C++, and a later stage that puts something
// else in a slot's place (EvalRhs: the table's own K and L) looks at the slot, never at a
// name.
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace mechgen {

struct Slot {
  enum class Kind {
    kK,         ///< K(i, j) = dphi_i/dq_j, read from EvalCoefficients
    kL,         ///< L(i, j) with j = j' + nq k': d2phi_i/dq_j' dq_k', read from EvalCoefficients
    kPhiPhi,    ///< Phi_phi(i, j), read from EvalCoefficients
    kQd,        ///< qd(i): the inputs' velocities (argument)
    kQdd,       ///< qdd(i): the inputs' accelerations (argument)
    kPhid,      ///< phid(i): the dependent velocities (argument, excess coordinates)
    kTime,      ///< t (argument)
    kFriction,  ///< friction(i): the given Coulomb friction load of friction joint i (argument)
    kDphiDp,    ///< dphi_dp(i, d), read from EvalDesignDerivatives' output (design sensitivities)
    kDKDp,      ///< dK_dp(i, j + nq d), read from EvalDesignDerivatives' output
    kDLDp,      ///< dL_dp(i, j + nq^2 d), read from EvalDesignDerivatives' output
  };
  Kind kind = Kind::kK;
  int i = 0, j = 0;

  bool operator<(const Slot& o) const { return std::tie(kind, i, j) < std::tie(o.kind, o.i, o.j); }
  bool operator==(const Slot& o) const { return kind == o.kind && i == o.i && j == o.j; }
  /// A name for the symbol (GiNaC's, for debugging; never parsed): "K_0_1", "qd_0", "t".
  std::string SymbolName() const;
};

/// The symbols of the slots one derivation reads, each made at its first use and listed in
/// that order (with its slot).
class SlotSymbols {
 public:
  /// The symbol of `s` (made on the first call).
  GiNaC::ex operator()(const Slot& s);
  GiNaC::ex operator()(Slot::Kind kind, int i = 0, int j = 0) { return (*this)(Slot{kind, i, j}); }
  const std::vector<std::pair<GiNaC::ex, Slot>>& all() const { return list_; }

 private:
  std::map<Slot, GiNaC::ex> index_;
  std::vector<std::pair<GiNaC::ex, Slot>> list_;
};

}  // namespace mechgen
