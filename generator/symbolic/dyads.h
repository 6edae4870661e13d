// The closed-form position solutions of the dyad blocks (blocks.h), each written ONCE as a
// sequence of GiNaC steps in the block's vectors a, b, w0, ... with the assembly mode as a
// symbol. The same formulation is
//   - printed into the generated SolvePositions (codegen/positions.cc), the mode symbol
//     spelled Scalar(modes[block]), and
//   - evaluated in double by the generator itself at the parameters' defaults
//     (EvaluateClosedForm), to choose the assembly mode that matches the model's assembly
//     guess and to check that the loop can be assembled there (blocks.cc),
// so the sign convention of a mode lives in one place.
//
// The generated solver's contract (issue 12): a closed form never hands out NaN or inf as a
// solution. Each form checks what makes it degenerate before dividing (coincident circle
// centres, a link of zero length, a zero coefficient: DyadStep::singular, reported as
// SolveStatus::kSingular) and what makes it unassemblable (a negative discriminant:
// kNotAssemblable); a discriminant that is negative only by rounding (|value| within
// `slack`, a few ulps of the terms it is computed from) is taken as zero, so that an exact
// change or dead point is solved (the double root) instead of failing at random. Each form
// with two modes also gives its relative discriminant (`branch`, in [0, 1], 0 where its two
// modes meet), which SolvePositions reports as SolveReport::branch_measure.
//
//   RRR  R(u) a + R(v) b = w:   tip m = R(u) a on the circles |m| = |a|, |w - m| = |b|:
//        k = 1/2 + (|a|^2 - |b|^2) / 2|w|^2, h = mode sqrt(|a|^2/|w|^2 - k^2), m = k w + h w^perp
//   RRP  R(u) a(s) = w(s):      |a(s)|^2 = |w(s)|^2, quadratic in s, the root of the mode's sign
//        without cancellation (mode +1 is (-B + sqrt(disc)) / 2A)
//   PRP  w0 + s0 e0 + s1 e1 = 0: Cramer's rule
//   one angle  c0 + c1 cos u + c2 sin u = 0: u = atan2(c2, c1) + mode acos(-c0 / rho)
//   linear     c0 + c1 x = 0
#pragma once

#include <ginac/ginac.h>

#include <map>
#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "symbolic/blocks.h"

namespace mechgen {

/// stable_half(B, sq) = -(B + sign(B) sq) / 2 (sign(0) = +1): the larger-magnitude
/// q of a quadratic's roots q / A and C / q.
DECLARE_FUNCTION_2P(stable_half)
/// quadratic_root(A, B, C, qq, mode): the root of A s^2 + B s + C = 0 of the mode's sign,
/// (-B + mode sqrt(disc)) / 2A, from qq = stable_half(B, sqrt(disc)) without cancellation.
DECLARE_FUNCTION_5P(quadratic_root)

/// One step of a closed form.
struct DyadStep {
  enum class Kind {
    kLocal,    ///< name = value (a symbol later steps use)
    kRequire,  ///< else the block fails (not assemblable, or singular); `measure` is reported
    kAngle,    ///< phi(col) = atan2(y, x) + value, kept continuous with its previous value
    kValue,    ///< phi(col) = value
  };
  enum class Require { kNonNegative, kAbsAtMostOne, kNonZero, kPositive };
  Kind kind = Kind::kLocal;
  std::string name;  ///< kLocal: the local's name without the block suffix
  GiNaC::ex symbol;  ///< kLocal: its symbol (named name + suffix), or its value when that is a number or a symbol
  GiNaC::ex value;   ///< kLocal, kValue: the value; kAngle: the term added to atan2; kRequire: tested
  GiNaC::ex y, x;    ///< kAngle
  Require require = Require::kNonNegative;
  GiNaC::ex measure;  ///< kRequire
  /// kRequire: a failure means the block is degenerate here (SolveStatus::kSingular: the
  /// solution is not determined), not that the loop cannot close (kNotAssemblable).
  bool singular = false;
  /// kRequire (kNonNegative, kAbsAtMostOne): values outside the range by at most `slack`
  /// (rounding) pass and are clamped into it as the local `clamped` (named clamped_name).
  GiNaC::ex slack = 0;
  GiNaC::ex clamped;
  std::string clamped_name;
  std::string what;  ///< kRequire: what a failure means, for the generator's messages
  int col = -1;       ///< kAngle, kValue: index into phi
};

/// sin and cos of an angle the closed form solved, from its own dot and cross products:
/// cos = dot / norm2, sin = cross / norm2.
struct DyadTrig {
  int col = -1;
  std::string inv_name;  ///< name of the local 1 / norm2 (without suffix)
  GiNaC::ex norm2, dot, cross;
};

struct ClosedForm {
  std::string suffix;  ///< "_b<block>": makes the locals' names unique in SolvePositions
  GiNaC::symbol mode;  ///< the assembly mode (+1 or -1)
  /// The relative discriminant of a form with two modes, in [0, 1] (0 at a branch point,
  /// where the two modes meet); 0 (no value) for forms with one solution. In terms of the
  /// steps' locals: RRR sin^2 of the angle between the dyad's two links; one angle
  /// 1 - cos_arg^2; RRP/RPR disc / (B^2 + 4 |A C|).
  /// As branch_num / branch_den (branch_den > 0 where the form holds, or 0 where the
  /// measure means nothing: then the measure is 0).
  GiNaC::ex branch_num = 0, branch_den = 1;
  bool has_branch = false;
  bool branch_den_positive = false;  ///< the steps have required branch_den > 0 already
  std::vector<DyadStep> steps;
  std::vector<DyadTrig> trig;
};

/// The machine epsilon of the generated code's Scalar in the slack expressions (printed as
/// the type's epsilon, evaluated as double's by EvaluateClosedForm).
const GiNaC::symbol& ScalarEpsilon();

/// The closed form of block `b` (index `index` in the solve order); b.solve must not be kNewton.
ClosedForm FormulateClosedForm(const Kinematics& k, const Block& b, int index);

/// The closed form evaluated in double at `values` (parameters, inputs, earlier unknowns)
/// with the given mode. Returns false at the first requirement that fails (*failed is its
/// step). *locals gets every local by name (without suffix), *solution every unknown it sets.
bool EvaluateClosedForm(const ClosedForm& f,
                        const GiNaC::exmap& values,
                        int mode,
                        std::map<std::string, double>* locals,
                        std::map<int, double>* solution,
                        const DyadStep** failed);

}  // namespace mechgen
