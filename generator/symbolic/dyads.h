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
//        Its checks bound |a|^2, |b|^2 and |w|^2 within [norm2_min, norm2_max] (ScalarNorm2Max:
//        what Scalar can carry through the form without overflow), so that every value they
//        let through is finite (ClosedForm::finite_by_checks; the proof is in dyads.cc).
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

/// What an RRR dyad's requirement says when its two circle centres coincide (the reach
/// check tells this isolated case, a change point, from the end of a reach).
inline constexpr const char* kCentresCoincide = "the two circle centres coincide";
/// ... when a squared length of the dyad (a link, or the distance of its centres) exceeds
/// norm2_max (ScalarNorm2Max).
inline constexpr const char* kLinkBeyondRange =
    "a length of the dyad is beyond what its closed form carries (|a|^2, |b|^2, |w|^2 <= 1e138)";

/// stable_half(B, sq) = -(B + sign(B) sq) / 2 (sign(0) = +1): the larger-magnitude
/// q of a quadratic's roots q / A and C / q.
DECLARE_FUNCTION_2P(stable_half)
/// quadratic_root(A, B, C, qq, mode): the root of A s^2 + B s + C = 0 of the mode's sign,
/// (-B + mode sqrt(disc)) / 2A, from qq = stable_half(B, sqrt(disc)) without cancellation.
DECLARE_FUNCTION_5P(quadratic_root)

/// The locals of the closed forms, by meaning: the messages of the generator read them
/// (blocks.cc: the radii of two circles that do not meet, ...), and only DyadLocalName()
/// spells them, for the generated code (with the block's suffix) and the symbols' names.
/// RRR: a, b, w = -w0, |a|^2, |b|^2, |w|^2, 1/|w|^2, k, h^2 (h2c: clamped), h, the tip m,
/// cross and dot of each link with its direction, 1/|a|^2, 1/|b|^2; one angle: c0, c1, c2,
/// rho, cos_arg (clamped); RRP: the quadratic's A, B, C, the root s, disc (clamped), its scale,
/// sqrt, stable half qq, |a|^2, 1/|a|^2; PRP: e0, e1, w0, det, 1/det.
enum class DyadLocal {
  kAx, kAy, kBx, kBy, kWx, kWy, kRa2, kRb2, kD2, kInvD2, kK, kH2, kH2c, kH, kMx, kMy, kCrossU,
  kDotU, kCrossV, kDotV, kInvRa2, kInvRb2, kC0, kC1, kC2, kRho, kCosArg, kCosArgc, kQuadA, kQuadB,
  kQuadC, kS, kDisc, kDiscc, kDiscScale, kSq, kQq, kA2, kInvA2, kE0x, kE0y, kE1x, kE1y, kW0x, kW0y,
  kDet, kInvDet, kInvAx, kInvBx,
};

/// The name of a closed form's local in the generated code, without the block's suffix.
const char* DyadLocalName(DyadLocal l);

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
  DyadLocal local = DyadLocal::kAx;  ///< kLocal: which local it is
  GiNaC::ex symbol;  ///< kLocal: its symbol (named name + suffix), or its value when that is a number or a symbol
  GiNaC::ex value;   ///< kLocal, kValue: the value; kAngle: the term added to atan2; kRequire: tested
  GiNaC::ex y, x;    ///< kAngle
  Require require = Require::kNonNegative;
  GiNaC::ex measure;  ///< kRequire
  /// kRequire: a failure means the block is degenerate here (SolveStatus::kSingular: the
  /// solution is not determined), not that the loop cannot close (kNotAssemblable).
  bool singular = false;
  /// kRequire (kNonNegative, kAbsAtMostOne): values outside the range by at most `slack`
  /// (rounding) pass and are clamped into it as the local `clamped` (clamped_local).
  GiNaC::ex slack = 0;
  GiNaC::ex clamped;
  bool has_clamped = false;
  DyadLocal clamped_local = DyadLocal::kH2c;  ///< has_clamped: which local the clamped value is
  std::string what;  ///< kRequire: what a failure means, for the generator's messages
  int col = -1;       ///< kAngle, kValue: index into phi
  /// kLocal: read only by the kAngle steps' atan2 (a SolvePositionsTrig, which computes no
  /// angle, leaves it out).
  bool angle_only = false;
};

/// sin and cos of an angle the closed form solved, from its own dot and cross products:
/// cos = dot / denom, sin = cross / denom. denom is the link's squared length norm2 (dot and
/// cross of the link with the direction it is turned into), or, for a link along its own x
/// axis (a = (a_x, 0)), a_x itself (dot and cross are then the direction's coordinates: one
/// product less, and 1 / a_x in place of 1 / a_x^2).
struct DyadTrig {
  int col = -1;
  std::string inv_name;  ///< name of the local 1 / denom (without suffix): DyadLocalName() of it
  GiNaC::ex norm2, dot, cross;
  GiNaC::ex denom;       ///< norm2, or a_x with denom^2 = norm2
  bool on_axis() const { return !denom.is_equal(norm2); }
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
  /// The steps' checks bound every value they let through, so that the direction cosines
  /// (trig) come out finite without a test of their own (RRR; see dyads.cc).
  bool finite_by_checks = false;
  std::vector<DyadStep> steps;
  std::vector<DyadTrig> trig;
};

/// The machine epsilon of the generated code's Scalar in the slack expressions (printed as
/// the type's epsilon, evaluated as double's by EvaluateClosedForm).
const GiNaC::symbol& ScalarEpsilon();
/// The largest and the smallest squared length an RRR dyad accepts (printed as the locals
/// norm2_max and norm2_min, per Scalar: 1e138 and 1e-138 for double, 1e11 and 1e-11 for float;
/// evaluated as double's by EvaluateClosedForm). See dyads.cc for why these.
const GiNaC::symbol& ScalarNorm2Max();
const GiNaC::symbol& ScalarNorm2Min();
/// Their printed definitions, for the functions whose closed forms read them.
inline constexpr const char* kNorm2MaxDefinition =
    "const Scalar norm2_max = Scalar(sizeof(Scalar) <= 4 ? 1e11 : 1e138);";
inline constexpr const char* kNorm2MinDefinition =
    "const Scalar norm2_min = Scalar(sizeof(Scalar) <= 4 ? 1e-11 : 1e-138);";
inline constexpr double kNorm2MaxDouble = 1e138, kNorm2MinDouble = 1e-138;

/// The closed form of block `b` (index `index` in the solve order); b.solve must not be kNewton.
ClosedForm FormulateClosedForm(const Kinematics& k, const Block& b, int index);

/// The closed form evaluated in double at `values` (parameters, inputs, earlier unknowns)
/// with the given mode. Returns false at the first requirement that fails (*failed is its
/// step). *locals gets every local it computed, *solution every unknown it sets.
bool EvaluateClosedForm(const ClosedForm& f,
                        const GiNaC::exmap& values,
                        int mode,
                        std::map<DyadLocal, double>* locals,
                        std::map<int, double>* solution,
                        const DyadStep** failed);

}  // namespace mechgen
