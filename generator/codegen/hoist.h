// Three rewrites of statement programs that make a generated function cheaper per call,
// used by EvalRhs (the stages of an integrator):
//
//  - ReduceTrig: an expression polynomial in the sin and cos of the angles, expanded with
//    sin^2 = 1 - cos^2 and collected on everything that is not a parameter, so that
//    m |K_G|^2 over a link's centre of mass becomes the hand derivation's
//    m (a^2 + a b K cos(th2 - th1) + b^2 K^2 / 4) instead of the squares of its components.
//  - UseAngleDifferences: in such a polynomial, the pairs of terms f (cos x cos y + sin x sin y)
//    and f (sin x cos y - cos x sin y) become f cos(x - y) and f sin(x - y), each a local
//    computed once from the direction cosines (Paul's cos(th2 - th1) of the inertia terms):
//    I and C of a four-bar read cos and sin of the coupler's angle to the crank's, as the
//    hand derivation does, instead of the four products in each term.
//  - HoistParameters: every subexpression that depends on the parameters only (masses,
//    m a b, 1/b^2, ...) becomes a constant computed once per parameter set by a separate
//    function (the caller keeps them: the runtime per Params), so a call computes only what
//    depends on the state.
#pragma once

#include <ginac/ginac.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "codegen/cxx_code.h"
#include "symbolic/program.h"

namespace mechgen {

using ExSet = std::set<GiNaC::ex, GiNaC::ex_is_less>;

/// `e` expanded with sin_i^2 = 1 - cos_i^2 for each (sin_i, cos_i) pair of symbols, then
/// collected (distributed) on the symbols of `e` that are not in `params`. *terms: the number
/// of terms of the result.
GiNaC::ex ReduceTrig(const GiNaC::ex& e,
                     const std::vector<std::pair<GiNaC::ex, GiNaC::ex>>& sin_cos,
                     const ExSet& params,
                     size_t* terms);

/// cos(x - y) and sin(x - y) of two angles x, y (their sin and cos: sin_x, cos_x, ...), as
/// symbols UseAngleDifferences() writes; *_used tells whether it wrote them (define them then).
struct AngleDifference {
  GiNaC::ex sin_x, cos_x, sin_y, cos_y;
  GiNaC::ex cos_d, sin_d;  // symbols
  bool cos_used = false, sin_used = false;
};

/// `e` (a polynomial in the sin and cos of the angles, e.g. from ReduceTrig) with, for each
/// difference d of `diffs` in turn, the terms f cos_x cos_y + f sin_x sin_y replaced by
/// f cos_d and f sin_x cos_y - f cos_x sin_y by f sin_d (the same f: exactly, term by term);
/// the result collected (distributed) on the symbols not in `params`, as ReduceTrig's. No such
/// terms, or not a polynomial in them: `e` as it is.
GiNaC::ex UseAngleDifferences(const GiNaC::ex& e, const ExSet& params, std::vector<AngleDifference>* diffs);

/// Replaces the parameter-only subexpressions of the kDefine and kStore values of `body`
/// by constants named `<access>[i]` (e.g. rc.c[3]); a kDefine whose value becomes one
/// keeps its name (raw lines may read it). `params`: the parameters' symbols. Returns the
/// constants' values in terms of the parameters, in the order of their indices (sorted by
/// their printed text, so the same model gives the same order).
std::vector<GiNaC::ex> HoistParameters(const ExSet& params,
                                       const std::string& access,
                                       CxxPrinter* printer,
                                       std::vector<Program>* body);

}  // namespace mechgen
