// Statement programs: what a generated function body computes, as a list of statements
// whose values are GiNaC expressions. The symbolic layer (symbolic/) builds them without
// any C++ text; codegen/cxx_code.h prints them with common-subexpression elimination.
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <utility>
#include <vector>

namespace mechgen {

/// One statement of a function body.
struct Statement {
  enum class Kind {
    kDefine,         ///< const Scalar <target> = <value>;  (target names `symbol`, used later)
    kStore,          ///< <target> = <value>;  inside `if (<guard> != nullptr)` when guard is set
    kRaw,            ///< a line of code, emitted as is (control flow; built in codegen/ only)
    kMatrix,         ///< a local rows x cols matrix <target>, zeroed when `zero`
    kLuFactor,       ///< <target> = the LU factorization of the rows x rows matrix args[0]
    kLuSolve,        ///< <target> (rows x cols) = -(LU args[0]) \ args[1]
    kLuDeterminant,  ///< <target> = det of the rows x rows matrix args[0]; names its symbol
  };
  Kind kind = Kind::kStore;
  std::string target;
  GiNaC::ex value;
  std::string guard;
  GiNaC::ex symbol;               ///< kDefine: the symbol that later values use
  std::vector<std::string> args;  ///< matrix and LU statements: the locals they read
  int rows = 0, cols = 0;
  bool zero = false;
  /// Symbols this statement introduces with their C++ spelling (e.g. the entries of an LU
  /// solve's result), named for the printer when the program is emitted.
  std::vector<std::pair<GiNaC::ex, std::string>> names;
};
using Program = std::vector<Statement>;

inline Statement Store(const std::string& target, const GiNaC::ex& value, const std::string& guard = "") {
  Statement s;
  s.kind = Statement::Kind::kStore;
  s.target = target;
  s.value = value;
  s.guard = guard;
  return s;
}

/// A statement of the linear-algebra kinds (kMatrix, kLuFactor, kLuSolve, kLuDeterminant).
inline Statement Linear(Statement::Kind kind,
                        const std::string& target,
                        int rows,
                        int cols,
                        const std::vector<std::string>& args = {},
                        bool zero = false) {
  Statement s;
  s.kind = kind;
  s.target = target;
  s.rows = rows;
  s.cols = cols;
  s.args = args;
  s.zero = zero;
  return s;
}

/// A named local: const Scalar name = value; its symbol (named `name`) comes back in *sym.
inline Statement Define(const std::string& name, const GiNaC::ex& value, GiNaC::ex* sym) {
  Statement s;
  s.kind = Statement::Kind::kDefine;
  s.target = name;
  s.value = value;
  s.symbol = GiNaC::symbol(name);
  *sym = s.symbol;
  return s;
}

}  // namespace mechgen
