// Two rewrites of statement programs that make a generated function cheaper per call,
// used by EvalRhs (the stages of an integrator):
//
//  - ReduceTrig: an expression polynomial in the sin and cos of the angles, expanded with
//    sin^2 = 1 - cos^2 and collected on everything that is not a parameter, so that
//    m |K_G|^2 over a link's centre of mass becomes the hand derivation's
//    m (a^2 + a b K cos(th2 - th1) + b^2 K^2 / 4) instead of the squares of its components.
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
