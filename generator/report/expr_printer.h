// The report's printer of expressions, in plain text (GiNaC's syntax, so a reader can
// paste a formula into GiNaC or a CAS) or LaTeX, with the same bytes on every run.
//
// GiNaC orders the operands of sums and products by hash values that change from run to
// run, and normalizes the sign of a sum inside sin(), a power or a product by whichever
// term it happens to see first: sin(a - b) in one run is -sin(b - a) in the next. This
// printer does not print GiNaC's tree: it copies it into its own, in a canonical form
//  - products: one rational coefficient in front, the other factors sorted (symbols,
//    then powers, functions, sums; then by their printed text), negative powers as the
//    denominator of one fraction;
//  - sums: terms sorted by their printed text without the coefficient, numbers last;
//    a sum whose first term is negative is negated, the sign moved outside (into the
//    product's coefficient, or out of an odd power);
//  - sin, tan, asin, atan (odd) and cos, abs (even) of a negative argument: the argument
//    negated, the sign moved outside for odd functions;
// so two trees that differ only in GiNaC's order and in where a sign sits print the same.
//
// LaTeX: names split at the first underscore: a Greek letter or one letter with its
// subscript in roman (theta_crank -> \theta_{\mathrm{crank}}, r_2_3 -> r_{\mathrm{2\_3}}),
// other names in roman as a whole (rocker_link -> \mathrm{rocker\_link}); fractions as
// \frac; cam laws, contours and tables by their joint's or table's name.
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <string>
#include <vector>

#include "model/model.h"

namespace mechgen {

class ReportPrinter {
 public:
  /// Names cam laws (camlaw), contours (camcontour) and tables (mtable) after the model's
  /// joints and tables.
  ReportPrinter(const Model& m, bool latex);

  /// Gives symbol `s` its own spelling in text and LaTeX (e.g. K_0_1 and K_{0,1}).
  void Name(const GiNaC::ex& s, const std::string& text, const std::string& tex);

  /// `e` printed in this printer's format.
  std::string Print(const GiNaC::ex& e) const;

  /// `e` in lines of about `width` characters of plain text each, for a LaTeX multline: a
  /// sum broken between its terms, a fraction over a long sum as -\frac{c}{d} \Bigl(...\Bigr)
  /// broken inside the parentheses. One line when `e` is short or cannot be broken.
  std::vector<std::string> PrintLines(const GiNaC::ex& e, size_t width) const;

  /// Length of `e` in plain text (a measure of its printed width in either format).
  size_t Width(const GiNaC::ex& e) const;

  /// LaTeX for a name as the model writes it (see the file comment).
  static std::string TexName(const std::string& name);
  /// LaTeX-escaped text (for prose: _ % & # $ { } ~ ^ \).
  static std::string TexText(const std::string& text);

  bool latex() const { return latex_; }

 private:
  friend struct ReportPrinterImpl;
  bool latex_;
  std::map<GiNaC::ex, std::pair<std::string, std::string>, GiNaC::ex_is_less> names_;
  std::map<int, std::string> cam_laws_, cam_contours_, tables_;  // index -> joint or table name
};

}  // namespace mechgen
