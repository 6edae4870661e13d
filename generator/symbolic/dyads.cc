// The closed-form dyad solutions, formulated once. See dyads.h.
#include "symbolic/dyads.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace mechgen {

using GiNaC::ex;

namespace {

bool Number(const ex& e, double* v) {
  const ex n = e.evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(n) || !GiNaC::ex_to<GiNaC::numeric>(n).is_real()) return false;
  *v = GiNaC::ex_to<GiNaC::numeric>(n).to_double();
  return true;
}

}  // namespace

static ex stable_half_evalf(const ex& b, const ex& sq) {
  double B, S;
  if (!Number(b, &B) || !Number(sq, &S)) return stable_half(b, sq).hold();
  return -(B + (B >= 0 ? S : -S)) / 2;
}

static ex quadratic_root_evalf(const ex& a, const ex& b, const ex& c, const ex& qq, const ex& mode) {
  double A, B, C, Q, M;
  if (!Number(a, &A) || !Number(b, &B) || !Number(c, &C) || !Number(qq, &Q) || !Number(mode, &M))
    return quadratic_root(a, b, c, qq, mode).hold();
  return ((M > 0) == (B >= 0)) ? (Q != 0 ? C / Q : 0.0) : Q / A;
}

REGISTER_FUNCTION(stable_half, evalf_func(stable_half_evalf))
REGISTER_FUNCTION(quadratic_root, evalf_func(quadratic_root_evalf))

const char* DyadLocalName(DyadLocal l) {
  switch (l) {
    case DyadLocal::kAx: return "ax";
    case DyadLocal::kAy: return "ay";
    case DyadLocal::kBx: return "bx";
    case DyadLocal::kBy: return "by";
    case DyadLocal::kWx: return "wx";
    case DyadLocal::kWy: return "wy";
    case DyadLocal::kRa2: return "ra2";
    case DyadLocal::kRb2: return "rb2";
    case DyadLocal::kD2: return "d2";
    case DyadLocal::kInvD2: return "inv_d2";
    case DyadLocal::kK: return "k";
    case DyadLocal::kH2: return "h2";
    case DyadLocal::kH2c: return "h2c";
    case DyadLocal::kH: return "h";
    case DyadLocal::kMx: return "mx";
    case DyadLocal::kMy: return "my";
    case DyadLocal::kCrossU: return "cross_u";
    case DyadLocal::kDotU: return "dot_u";
    case DyadLocal::kCrossV: return "cross_v";
    case DyadLocal::kDotV: return "dot_v";
    case DyadLocal::kInvRa2: return "inv_ra2";
    case DyadLocal::kInvRb2: return "inv_rb2";
    case DyadLocal::kC0: return "c0";
    case DyadLocal::kC1: return "c1";
    case DyadLocal::kC2: return "c2";
    case DyadLocal::kRho: return "rho";
    case DyadLocal::kCosArg: return "cos_arg";
    case DyadLocal::kCosArgc: return "cos_argc";
    case DyadLocal::kQuadA: return "A";
    case DyadLocal::kQuadB: return "B";
    case DyadLocal::kQuadC: return "C";
    case DyadLocal::kS: return "s";
    case DyadLocal::kDisc: return "disc";
    case DyadLocal::kDiscc: return "discc";
    case DyadLocal::kDiscScale: return "disc_scale";
    case DyadLocal::kSq: return "sq";
    case DyadLocal::kQq: return "qq";
    case DyadLocal::kA2: return "a2";
    case DyadLocal::kInvA2: return "inv_a2";
    case DyadLocal::kE0x: return "e0x";
    case DyadLocal::kE0y: return "e0y";
    case DyadLocal::kE1x: return "e1x";
    case DyadLocal::kE1y: return "e1y";
    case DyadLocal::kW0x: return "w0x";
    case DyadLocal::kW0y: return "w0y";
    case DyadLocal::kDet: return "det";
    case DyadLocal::kInvDet: return "inv_det";
    case DyadLocal::kInvAx: return "inv_ax";
    case DyadLocal::kInvBx: return "inv_bx";
  }
  return "";
}

namespace {

class Builder {
 public:
  explicit Builder(ClosedForm* f) : f_(*f) {}

  // A named local, or the value itself when it is a number or a symbol already.
  ex Local(DyadLocal local, const ex& value) {
    const std::string name = DyadLocalName(local);
    DyadStep s;
    s.kind = DyadStep::Kind::kLocal;
    s.local = local;
    s.value = value;
    if (GiNaC::is_a<GiNaC::numeric>(value) || GiNaC::is_a<GiNaC::symbol>(value))
      s.symbol = value;
    else
      s.symbol = GiNaC::symbol(name + f_.suffix);
    f_.steps.push_back(s);
    return s.symbol;
  }
  // A requirement; with a slack, also the value clamped into the range (returned; else
  // the value itself).
  ex Require(DyadStep::Require r, const ex& value, const ex& measure, bool singular, const std::string& what,
             const ex& slack = 0, std::optional<DyadLocal> clamped = std::nullopt) {
    DyadStep s;
    s.kind = DyadStep::Kind::kRequire;
    s.require = r;
    s.value = value;
    s.measure = measure;
    s.singular = singular;
    s.what = what;
    s.slack = slack;
    ex result = value;
    if (clamped) {
      s.has_clamped = true;
      s.clamped_local = *clamped;
      s.clamped = GiNaC::symbol(DyadLocalName(*clamped) + f_.suffix);
      result = s.clamped;
    }
    f_.steps.push_back(s);
    return result;
  }
  // Requires a squared length to be positive unless it is a positive number already.
  void RequirePositive(const ex& value, const std::string& what) {
    if (GiNaC::is_a<GiNaC::numeric>(value) && GiNaC::ex_to<GiNaC::numeric>(value).is_positive()) return;
    Require(DyadStep::Require::kPositive, value, value, true, what);
  }
  void RequireNonZero(const ex& value, const std::string& what) {
    if (GiNaC::is_a<GiNaC::numeric>(value) && !value.is_zero()) return;
    Require(DyadStep::Require::kNonZero, value, value, true, what);
  }
  void Angle(int col, const ex& y, const ex& x, const ex& plus = 0) {
    DyadStep s;
    s.kind = DyadStep::Kind::kAngle;
    s.col = col;
    s.y = y;
    s.x = x;
    s.value = plus;
    f_.steps.push_back(s);
  }
  void Value(int col, const ex& value) {
    DyadStep s;
    s.kind = DyadStep::Kind::kValue;
    s.col = col;
    s.value = value;
    f_.steps.push_back(s);
  }
  void Trig(int col, DyadLocal inv, const ex& norm2, const ex& dot, const ex& cross) {
    f_.trig.push_back({col, DyadLocalName(inv), norm2, dot, cross, norm2});
  }
  // A link along its own x axis: cos = dot / a_x, sin = cross / a_x (denom^2 = norm2).
  void TrigOnAxis(int col, DyadLocal inv, const ex& norm2, const ex& dot, const ex& cross, const ex& denom) {
    f_.trig.push_back({col, DyadLocalName(inv), norm2, dot, cross, denom});
  }
  // The local is read by the atan2 of the angles only.
  void AngleOnly(DyadLocal local) {
    for (DyadStep& s : f_.steps)
      if (s.kind == DyadStep::Kind::kLocal && s.local == local) s.angle_only = true;
  }
  // A squared length of the dyad within [norm2_min, norm2_max] (unless it is a number there).
  void RequireNorm2InRange(const ex& value, const std::string& too_small, const std::string& too_large) {
    double v;
    if (Number(value, &v) && v >= kNorm2MinDouble && v <= kNorm2MaxDouble) return;
    Require(DyadStep::Require::kPositive, value - ScalarNorm2Min(), value, true, too_small);
    Require(DyadStep::Require::kPositive, ScalarNorm2Max() - value, value, true, too_large);
  }

 private:
  ClosedForm& f_;
};

}  // namespace

const GiNaC::symbol& ScalarEpsilon() {
  static const GiNaC::symbol eps("scalar_epsilon");
  return eps;
}

const GiNaC::symbol& ScalarNorm2Max() {
  static const GiNaC::symbol s("scalar_norm2_max");
  return s;
}

const GiNaC::symbol& ScalarNorm2Min() {
  static const GiNaC::symbol s("scalar_norm2_min");
  return s;
}

ClosedForm FormulateClosedForm(const Kinematics& k, const Block& b, int index) {
  ClosedForm f;
  f.suffix = "_b" + std::to_string(index);
  f.mode = GiNaC::symbol("mode" + f.suffix);
  Builder s(&f);
  const ex mode = f.mode;
  const ex eps = ScalarEpsilon();
  switch (b.solve) {
    case BlockSolve::kRR: {
      // R(u) a + R(v) b = w: the tip m = R(u) a lies on the circles |m| = |a|, |w - m| = |b|.
      const int u = b.cols[b.iu], v = b.cols[1 - b.iu];
      const ex ax = s.Local(DyadLocal::kAx, b.a[0]), ay = s.Local(DyadLocal::kAy, b.a[1]);
      const ex bx = s.Local(DyadLocal::kBx, b.b[0]), by = s.Local(DyadLocal::kBy, b.b[1]);
      const ex wx = s.Local(DyadLocal::kWx, -b.w0[0]), wy = s.Local(DyadLocal::kWy, -b.w0[1]);
      const ex ra2 = s.Local(DyadLocal::kRa2, ax * ax + ay * ay), rb2 = s.Local(DyadLocal::kRb2, bx * bx + by * by);
      // A link of zero length: its angle is not determined. A link beyond Scalar's range
      // (below): nothing the form computes from it could be trusted to be finite.
      s.RequireNorm2InRange(ra2, "a link of the dyad has zero length", kLinkBeyondRange);
      s.RequireNorm2InRange(rb2, "a link of the dyad has zero length", kLinkBeyondRange);
      const ex d2 = s.Local(DyadLocal::kD2, wx * wx + wy * wy);
      // Coincident centres (to rounding): the dyad may turn about them, nothing fixes it.
      s.Require(DyadStep::Require::kPositive, d2 - eps * eps * (ra2 + rb2), d2, true,
                kCentresCoincide);
      s.Require(DyadStep::Require::kPositive, ScalarNorm2Max() - d2, d2, true, kLinkBeyondRange);
      // Why the checks above make every value below finite (finite_by_checks: the direction
      // cosines need no test of their own). Let F be Scalar's largest value and M = norm2_max,
      // chosen with 6 M^2 <= eps^2 F (double: M = 1e138, float: 1e11). Past the checks (a NaN
      // fails each of them) |a|^2, |b|^2 lie in [1/M, M] and |w|^2 in (eps^2 (|a|^2 + |b|^2), M],
      // so every coordinate of a, b, w is at most sqrt(M) and
      //   1/|w|^2 < M / (2 eps^2)                     (finite),
      //   |a|^2/|w|^2, |b|^2/|w|^2 < 1/eps^2,  |k| <= 1/eps^2,  h^2 finite,
      //   past the h^2 test 0 <= h2c <= |a|^2/|w|^2:  |h| < 1/eps,
      //   |m_x|, |m_y| <= (|k| + |h|) sqrt(M) <= 2 sqrt(M) / eps^2,
      //   dot and cross products with a, or with b of w - m, <= 6 M / eps^2,
      //   cosines: those times 1/|a|^2 or 1/|b|^2 <= M: at most 6 M^2 / eps^2 <= F,
      // and on an axis (m_x / a_x) smaller still. The bounds are loose (once h^2 has passed its
      // test, |k| <= 65/eps + 1): rounding cannot take them past F.
      const ex inv_d2 = s.Local(DyadLocal::kInvD2, 1 / d2);
      const ex kk = s.Local(DyadLocal::kK, GiNaC::numeric(1, 2) + (ra2 - rb2) * inv_d2 / 2);
      const ex h2 = s.Local(DyadLocal::kH2, ra2 * inv_d2 - kk * kk);
      // h2 < 0: the two circles do not meet, the loop cannot close (NaN also fails); within
      // the rounding of its terms, the circles touch (h2 = 0).
      const ex h2c = s.Require(DyadStep::Require::kNonNegative, h2, h2, false, "the two circles do not meet",
                               64 * eps * (ra2 * inv_d2 + GiNaC::abs(kk) * (1 + (ra2 + rb2) * inv_d2)), DyadLocal::kH2c);
      // |m x w| = |h| |w|^2 = |a| |b| |sin(angle between the links)|.
      f.branch_num = h2c * d2 * d2;
      f.branch_den = ra2 * rb2;
      f.has_branch = true;
      f.branch_den_positive = true;
      const ex h = s.Local(DyadLocal::kH, mode * GiNaC::sqrt(h2c));
      const ex mx = s.Local(DyadLocal::kMx, kk * wx - h * wy), my = s.Local(DyadLocal::kMy, kk * wy + h * wx);
      // u: the angle from a to m, v: from b to w - m, each one atan2 of (cross, dot).
      const ex cu = s.Local(DyadLocal::kCrossU, ax * my - ay * mx), du = s.Local(DyadLocal::kDotU, ax * mx + ay * my);
      const ex cv = s.Local(DyadLocal::kCrossV, bx * (wy - my) - by * (wx - mx));
      const ex dv = s.Local(DyadLocal::kDotV, bx * (wx - mx) + by * (wy - my));
      s.Angle(u, cu, du);
      s.Angle(v, cv, dv);
      // m = R(u) a and w - m = R(v) b: a.m = |a|^2 cos u, a x m = |a|^2 sin u, and so for v;
      // a link along its x axis: m = a_x (cos u, sin u) (one product and 1/a_x^2 less).
      if (ay.is_zero()) {
        s.TrigOnAxis(u, DyadLocal::kInvAx, ra2, mx, my, ax);
        s.AngleOnly(DyadLocal::kCrossU);
        s.AngleOnly(DyadLocal::kDotU);
      } else {
        s.Trig(u, DyadLocal::kInvRa2, ra2, du, cu);
      }
      if (by.is_zero()) {
        s.TrigOnAxis(v, DyadLocal::kInvBx, rb2, wx - mx, wy - my, bx);
        s.AngleOnly(DyadLocal::kCrossV);
        s.AngleOnly(DyadLocal::kDotV);
      } else {
        s.Trig(v, DyadLocal::kInvRb2, rb2, dv, cv);
      }
      f.finite_by_checks = true;
      break;
    }
    case BlockSolve::kAngle: {
      // c0 + c1 cos u + c2 sin u = 0: rho cos(u - delta) = -c0.
      const ex c0 = s.Local(DyadLocal::kC0, b.c0), c1 = s.Local(DyadLocal::kC1, b.c1), c2 = s.Local(DyadLocal::kC2, b.c2);
      const ex rho = s.Local(DyadLocal::kRho, GiNaC::sqrt(c1 * c1 + c2 * c2));
      s.RequirePositive(rho, "the angle moves nothing (c1 = c2 = 0: a link of zero length)");
      const ex cos_arg = s.Local(DyadLocal::kCosArg, -c0 / rho);
      const ex cos_argc = s.Require(DyadStep::Require::kAbsAtMostOne, cos_arg, 1 - GiNaC::abs(cos_arg), false,
                                    "the loop cannot close, |c0| > sqrt(c1^2 + c2^2)", 64 * eps, DyadLocal::kCosArgc);
      s.Angle(b.cols[0], c2, c1, mode * GiNaC::acos(cos_argc));
      f.branch_num = 1 - cos_argc * cos_argc;
      f.branch_den = 1;
      f.has_branch = true;
      break;
    }
    case BlockSolve::kLinear: {
      const ex c1 = s.Local(DyadLocal::kC1, b.c1);
      s.RequireNonZero(c1, "its coefficient is zero");
      s.Value(b.cols[0], -b.c0 / c1);
      break;
    }
    case BlockSolve::kRS: {
      const int u = b.cols[b.iu], x = b.cols[1 - b.iu];
      const GiNaC::symbol sx = k.phi[x].symbol;
      // |a(s)|^2 = |w0(s)|^2: A s^2 + B s + C = 0
      const ex poly = (b.a[0] * b.a[0] + b.a[1] * b.a[1] - b.w0[0] * b.w0[0] - b.w0[1] * b.w0[1]).expand();
      const ex A = poly.coeff(sx, 2);
      const ex B = s.Local(DyadLocal::kQuadB, poly.coeff(sx, 1)), C = s.Local(DyadLocal::kQuadC, poly.coeff(sx, 0));
      ex root;
      if (A.is_zero()) {
        s.RequireNonZero(B, "the slide's equation does not depend on it");
        root = s.Local(DyadLocal::kS, -C / B);
      } else {
        const ex An = s.Local(DyadLocal::kQuadA, A);
        s.RequireNonZero(An, "its quadratic has no s^2 term here");
        const ex disc = s.Local(DyadLocal::kDisc, B * B - 4 * An * C);
        // disc < 0: the circle and the line do not meet (within rounding: they touch).
        const ex scale = s.Local(DyadLocal::kDiscScale, B * B + 4 * GiNaC::abs(An * C));
        const ex discc = s.Require(DyadStep::Require::kNonNegative, disc, disc, false,
                                   "the circle and the line do not meet", 64 * eps * scale, DyadLocal::kDiscc);
        const ex sq = s.Local(DyadLocal::kSq, GiNaC::sqrt(discc));
        // The root of the requested sign without cancellation: roots qq / A and C / qq.
        const ex qq = s.Local(DyadLocal::kQq, stable_half(B, sq));
        root = s.Local(DyadLocal::kS, quadratic_root(An, B, C, qq, mode));
        f.branch_num = discc;
        f.branch_den = scale;
        f.has_branch = true;
      }
      GiNaC::exmap at;
      at[sx] = root;
      const ex ax = s.Local(DyadLocal::kAx, b.a[0].subs(at)), ay = s.Local(DyadLocal::kAy, b.a[1].subs(at));
      const ex wx = s.Local(DyadLocal::kWx, -b.w0[0].subs(at)), wy = s.Local(DyadLocal::kWy, -b.w0[1].subs(at));
      s.Value(x, root);
      // a(s) = 0: the slider's point on the pivot, the angle is not determined.
      const ex a2 = s.Local(DyadLocal::kA2, ax * ax + ay * ay);
      s.RequirePositive(a2, "the sliding point lies on the pivot (|a(s)| = 0)");
      // u: the angle from a to w, one atan2 of (cross, dot); R(u) a = w: a.w = |a|^2 cos u.
      const ex cu = s.Local(DyadLocal::kCrossU, ax * wy - ay * wx), du = s.Local(DyadLocal::kDotU, ax * wx + ay * wy);
      s.Angle(u, cu, du);
      s.Trig(u, DyadLocal::kInvA2, a2, du, cu);
      break;
    }
    case BlockSolve::kSS: {
      // w0 + s0 e0 + s1 e1 = 0 by Cramer's rule.
      const ex e0x = s.Local(DyadLocal::kE0x, b.e0[0]), e0y = s.Local(DyadLocal::kE0y, b.e0[1]);
      const ex e1x = s.Local(DyadLocal::kE1x, b.e1[0]), e1y = s.Local(DyadLocal::kE1y, b.e1[1]);
      const ex w0x = s.Local(DyadLocal::kW0x, b.w0[0]), w0y = s.Local(DyadLocal::kW0y, b.w0[1]);
      const ex det = s.Local(DyadLocal::kDet, e0x * e1y - e0y * e1x);
      s.RequireNonZero(det, "the two slides are parallel");
      const ex inv = s.Local(DyadLocal::kInvDet, 1 / det);
      s.Value(b.cols[0], (-w0x * e1y + w0y * e1x) * inv);
      s.Value(b.cols[1], (-e0x * w0y + e0y * w0x) * inv);
      break;
    }
    case BlockSolve::kNewton:
      break;
  }
  return f;
}

bool EvaluateClosedForm(const ClosedForm& f,
                        const GiNaC::exmap& values,
                        int mode,
                        std::map<DyadLocal, double>* locals,
                        std::map<int, double>* solution,
                        const DyadStep** failed) {
  GiNaC::exmap v = values;
  v[f.mode] = mode;
  v[ScalarEpsilon()] = std::numeric_limits<double>::epsilon();
  v[ScalarNorm2Max()] = kNorm2MaxDouble;
  v[ScalarNorm2Min()] = kNorm2MinDouble;
  auto eval = [&](const ex& e) {
    double d;
    return Number(e.subs(v), &d) ? d : std::nan("");
  };
  for (const DyadStep& s : f.steps) {
    switch (s.kind) {
      case DyadStep::Kind::kLocal: {
        const double d = eval(s.value);
        (*locals)[s.local] = d;
        if (GiNaC::is_a<GiNaC::symbol>(s.symbol) && !GiNaC::is_a<GiNaC::symbol>(s.value)) v[s.symbol] = d;
        break;
      }
      case DyadStep::Kind::kRequire: {
        const double d = eval(s.value);
        const double slack = s.slack.is_zero() ? 0.0 : eval(s.slack);
        const bool ok = s.require == DyadStep::Require::kNonNegative    ? d >= -slack
                        : s.require == DyadStep::Require::kAbsAtMostOne ? std::abs(d) <= 1 + slack
                        : s.require == DyadStep::Require::kPositive     ? d > 0
                                                                        : d != 0;
        if (!ok) {
          *failed = &s;
          return false;
        }
        if (s.has_clamped) {
          const double c = s.require == DyadStep::Require::kNonNegative ? std::max(d, 0.0)
                                                                         : std::max(-1.0, std::min(d, 1.0));
          (*locals)[s.clamped_local] = c;
          v[s.clamped] = c;
        }
        break;
      }
      case DyadStep::Kind::kAngle:
        (*solution)[s.col] = std::atan2(eval(s.y), eval(s.x)) + eval(s.value);
        break;
      case DyadStep::Kind::kValue:
        (*solution)[s.col] = eval(s.value);
        break;
    }
  }
  return true;
}

}  // namespace mechgen
