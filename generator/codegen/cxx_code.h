// From GiNaC expressions to C++ statements: a printer for Scalar-templated code and
// common-subexpression elimination over a whole function body (a statement program,
// symbolic/program.h).
//
// Determinism: GiNaC orders the terms of sums and products by hash values that change
// from run to run (they mix in type-info addresses), so nothing here relies on GiNaC's
// order. Operands are sorted by their printed text, and the CSE visits subexpressions in
// that order, so the same model gives the same bytes on every run.
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <string>
#include <vector>

#include "symbolic/program.h"

namespace mechgen {

/// Operation counts of emitted code (after CSE).
struct OpCounts {
  int adds = 0, muls = 0, divs = 0, calls = 0;
  int Total() const { return adds + muls + divs + calls; }
  std::string Text() const;  ///< "57 (adds 20, muls 30, divs 2, calls 5)"
  OpCounts& operator+=(const OpCounts& o);
};

/// Prints expressions as C++ for `template <typename Scalar>` code: literals as
/// Scalar(...), integer powers as products, math calls unqualified (so ceres::Jet's
/// overloads are found), operands in a stable order.
class CxxPrinter {
 public:
  /// Gives symbol `s` the C++ spelling `name` (e.g. q(0), p.a, _tmp3).
  void Name(const GiNaC::ex& s, const std::string& name);
  /// camlaw(index, d, x) (joints/cam_profile.h) prints as `name(p, x, d)`.
  void NameCamLaw(int index, const std::string& name) { cam_laws_[index] = name; }
  /// mtable(index, d, x) (model.h, a `tables:` entry) prints as `name(x, d)`.
  void NameTable(int index, const std::string& name) { tables_[index] = name; }
  /// camcontour(index, c, d, u) (joints/cam_profile.h) prints as `name(p, u, c, d)`.
  void NameCamContour(int index, const std::string& name) { cam_contours_[index] = name; }
  /// stable_half and quadratic_root (symbolic/dyads.h) print as the expressions they stand for.
  /// C++ text of `e`; adds its operations to *ops when not null.
  std::string Print(const GiNaC::ex& e, OpCounts* ops = nullptr);
  /// A stable sort key for `e` (its printed text), memoized.
  const std::string& Key(const GiNaC::ex& e);

 private:
  std::string PrintNumber(const GiNaC::numeric& n) const;
  std::string PrintFactor(const GiNaC::ex& e, OpCounts* ops);
  /// A term of a sum: its text without the sign, and the sign.
  struct Term {
    std::string text;
    bool negative;
  };
  std::vector<Term> AddTerms(const GiNaC::ex& e, OpCounts* ops);
  std::string JoinTerms(std::vector<Term> terms, OpCounts* ops);
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names_;
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> keys_;
  std::map<int, std::string> cam_laws_;
  std::map<int, std::string> tables_;
  std::map<int, std::string> cam_contours_;
};

/// A line of C++ as is: control flow of the generated solvers (codegen/ only; the symbolic
/// layer builds statements without C++ text).
inline Statement Raw(const std::string& line) {
  Statement s;
  s.kind = Statement::Kind::kRaw;
  s.target = line;
  return s;
}

struct Body {
  std::string text;  ///< indented C++ lines
  OpCounts ops;
  int num_temps = 0;
};

/// Emits `program` with common subexpressions of all its values shared (temporaries
/// _tmp0.._tmpN, each emitted just before its first use). Stores are grouped under
/// their guards. `printer` must name every symbol the values use.
Body EmitProgram(const Program& program, CxxPrinter* printer, const std::string& indent = "  ");

}  // namespace mechgen
