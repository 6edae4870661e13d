// The piecewise functions of the expression language. See expression_functions.h.
#include "model/expression_functions.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace mechgen {

double StepValue(double x) { return x >= 0 ? 1.0 : 0.0; }
double SignValue(double x) { return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0; }
double MinValue(double a, double b) { return a <= b ? a : b; }
double MaxValue(double a, double b) { return a >= b ? a : b; }
double ModValue(double x, double p) {
  double r = x - p * std::floor(x / p);
  // Rounding: x a little below a multiple of p gives r = p (or just below 0).
  if (r < 0) r += p;
  if (r >= p) r -= p;
  return r;
}

namespace {

using GiNaC::ex;
using GiNaC::numeric;

bool RealNumber(const ex& x) { return GiNaC::is_exactly_a<numeric>(x) && GiNaC::ex_to<numeric>(x).is_real(); }
const numeric& Num(const ex& x) { return GiNaC::ex_to<numeric>(x); }
bool Rational(const ex& x) { return GiNaC::is_exactly_a<numeric>(x) && Num(x).is_rational(); }

// Exact where the arguments are exact numbers (rationals), in double where they are floats
// (evalf), held otherwise.
ex mstep_eval(const ex& x) { return RealNumber(x) ? ex(Num(x) >= 0 ? 1 : 0) : mstep(x).hold(); }
ex msign_eval(const ex& x) { return RealNumber(x) ? ex(Num(x) > 0 ? 1 : Num(x) < 0 ? -1 : 0) : msign(x).hold(); }
ex mmin_eval(const ex& a, const ex& b) {
  if (a.is_equal(b)) return a;
  if (RealNumber(a) && RealNumber(b)) return Num(a) <= Num(b) ? a : b;
  return mmin(a, b).hold();
}
ex mmax_eval(const ex& a, const ex& b) {
  if (a.is_equal(b)) return a;
  if (RealNumber(a) && RealNumber(b)) return Num(a) >= Num(b) ? a : b;
  return mmax(a, b).hold();
}
ex mmod_eval(const ex& x, const ex& p) {
  if (Rational(x) && Rational(p) && Num(p) > 0) {
    const numeric q = Num(x) / Num(p);
    numeric f = GiNaC::iquo(q.numer(), q.denom());  // truncated towards zero
    if (q < 0 && f != q) f -= 1;                    // floor
    return Num(x) - Num(p) * f;
  }
  return mmod(x, p).hold();
}
ex mmod_evalf(const ex& x, const ex& p) {
  if (RealNumber(x) && RealNumber(p) && Num(p) > 0) return numeric(ModValue(Num(x).to_double(), Num(p).to_double()));
  return mmod(x, p).hold();
}

ex mstep_deriv(const ex&, unsigned) { return 0; }
ex msign_deriv(const ex&, unsigned) { return 0; }
ex mmin_deriv(const ex& a, const ex& b, unsigned param) { return param == 0 ? mstep(b - a) : 1 - mstep(b - a); }
ex mmax_deriv(const ex& a, const ex& b, unsigned param) { return param == 0 ? mstep(a - b) : 1 - mstep(a - b); }
ex mmod_deriv(const ex& x, const ex& p, unsigned param) { return param == 0 ? ex(1) : (mmod(x, p) - x) / p; }

// Printed (error messages, GiNaC's text) with the language's names.
void Print1(const char* name, const ex& x, const GiNaC::print_context& c) {
  c.s << name << "(";
  x.print(c);
  c.s << ")";
}
void Print2(const char* name, const ex& a, const ex& b, const GiNaC::print_context& c) {
  c.s << name << "(";
  a.print(c);
  c.s << ", ";
  b.print(c);
  c.s << ")";
}
void mstep_print(const ex& x, const GiNaC::print_context& c) { Print1("step", x, c); }
void msign_print(const ex& x, const GiNaC::print_context& c) { Print1("sign", x, c); }
void mmin_print(const ex& a, const ex& b, const GiNaC::print_context& c) { Print2("min", a, b, c); }
void mmax_print(const ex& a, const ex& b, const GiNaC::print_context& c) { Print2("max", a, b, c); }
void mmod_print(const ex& a, const ex& b, const GiNaC::print_context& c) { Print2("mod", a, b, c); }

// The reader's functions. GiNaC's parser tells a reader function from a registered function's
// serial number by the pointer's lowest bit (an odd "pointer" is a serial: parser.cpp,
// encode_serial_as_reader_func), so these must sit at even addresses. -O2 aligns functions to
// 16 bytes anyway, but -O1 (the sanitizer build) packs them at any byte: ReadStep at an odd
// address was taken for a serial and crashed in function::eval(). Hence the attribute, and
// the check in ExpressionReader().
#define MECHGEN_READER_FUNCTION __attribute__((aligned(16)))
MECHGEN_READER_FUNCTION ex ReadStep(const GiNaC::exvector& a) { return mstep(a[0]); }
MECHGEN_READER_FUNCTION ex ReadSign(const GiNaC::exvector& a) { return msign(a[0]); }
MECHGEN_READER_FUNCTION ex ReadMin(const GiNaC::exvector& a) { return mmin(a[0], a[1]); }
MECHGEN_READER_FUNCTION ex ReadMax(const GiNaC::exvector& a) { return mmax(a[0], a[1]); }
MECHGEN_READER_FUNCTION ex ReadClamp(const GiNaC::exvector& a) { return mmin(mmax(a[0], a[1]), a[2]); }
MECHGEN_READER_FUNCTION ex ReadMod(const GiNaC::exvector& a) { return mmod(a[0], a[1]); }
#undef MECHGEN_READER_FUNCTION

}  // namespace

REGISTER_FUNCTION(mstep,
                  eval_func(mstep_eval)
                      .evalf_func(mstep_eval)
                      .derivative_func(mstep_deriv)
                      .print_func<GiNaC::print_dflt>(mstep_print)
                      .latex_name("\\operatorname{step}"))
REGISTER_FUNCTION(msign,
                  eval_func(msign_eval)
                      .evalf_func(msign_eval)
                      .derivative_func(msign_deriv)
                      .print_func<GiNaC::print_dflt>(msign_print)
                      .latex_name("\\operatorname{sign}"))
REGISTER_FUNCTION(mmin,
                  eval_func(mmin_eval)
                      .evalf_func(mmin_eval)
                      .derivative_func(mmin_deriv)
                      .print_func<GiNaC::print_dflt>(mmin_print)
                      .latex_name("\\min"))
REGISTER_FUNCTION(mmax,
                  eval_func(mmax_eval)
                      .evalf_func(mmax_eval)
                      .derivative_func(mmax_deriv)
                      .print_func<GiNaC::print_dflt>(mmax_print)
                      .latex_name("\\max"))
REGISTER_FUNCTION(mmod,
                  eval_func(mmod_eval)
                      .evalf_func(mmod_evalf)
                      .derivative_func(mmod_deriv)
                      .print_func<GiNaC::print_dflt>(mmod_print)
                      .latex_name("\\operatorname{mod}"))

const GiNaC::prototype_table& ExpressionReader() {
  static const GiNaC::prototype_table table = [] {
    GiNaC::prototype_table t = GiNaC::get_default_reader();
    t[{"step", 1}] = ReadStep;  // replaces GiNaC's own step (whose step(0) is 1/2)
    t[{"sign", 1}] = ReadSign;
    t[{"min", 2}] = ReadMin;
    t[{"max", 2}] = ReadMax;
    t[{"clamp", 3}] = ReadClamp;
    t[{"mod", 2}] = ReadMod;
    for (GiNaC::reader_func f : {ReadStep, ReadSign, ReadMin, ReadMax, ReadClamp, ReadMod}) {
      if ((reinterpret_cast<std::uintptr_t>(reinterpret_cast<void*>(f)) & 1) != 0)
        throw std::logic_error("a reader function of the expression language is at an odd address, which "
                               "GiNaC's parser would take for a function serial (see ReadStep)");
    }
    return t;
  }();
  return table;
}

bool HasPiecewise(const GiNaC::ex& e, const std::string& name) {
  using GiNaC::wild;
  if ((name.empty() || name == "mstep") && e.has(mstep(wild(0)))) return true;
  if ((name.empty() || name == "msign") && e.has(msign(wild(0)))) return true;
  if ((name.empty() || name == "mmin") && e.has(mmin(wild(0), wild(1)))) return true;
  if ((name.empty() || name == "mmax") && e.has(mmax(wild(0), wild(1)))) return true;
  if ((name.empty() || name == "mmod") && e.has(mmod(wild(0), wild(1)))) return true;
  return false;
}

}  // namespace mechgen
