// Hostile input to the mechgen program (issue 12): every bad model gets ONE line,
// `file:line:column: error: what; what to do`, exit status 1, and no output directory; a bad
// --name is a command-line error (`mechgen: error: --name ...`, exit 1) that writes nothing
// anywhere. Each case says where the error must point by the text it points at (the test's
// own knowledge of which character is wrong), not by what the generator answered before.
//
// Also: the reader's name checks against the compiler's own list of macros (the headers the
// generated code includes, `c++ -dM -E`, taken at configure time) and against the C++
// keywords, typed here from the standard.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "model/reader.h"

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code = -1;
  std::string out, err;
};

// Runs mechgen with stdout and stderr apart (the message must be on stderr, stdout empty).
Result RunMechgen(const std::string& args, const fs::path& scratch) {
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const std::string cmd = std::string(MECHGEN_EXE) + " " + args + " >" + out.string() + " 2>" + err.string();
  Result r;
  const int status = std::system(cmd.c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream o(out, std::ios::binary), e(err, std::ios::binary);
  std::ostringstream os, es;
  os << o.rdbuf();
  es << e.rdbuf();
  r.out = os.str();
  r.err = es.str();
  fs::remove(out);
  fs::remove(err);
  return r;
}

std::string Quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("mechgen_hostile_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

// A valid four-bar (tests/generator/generator_cli_test.cc's) to mutate.
const char* kGoodModel = R"(name: fb
parameters:
  a: 1.0
  b: 3.5
  c: 3.0
  d: 4.0
links:
  ground:  {ground: true, points: {A: [0, 0], D: [d, 0]}}
  crank:   {points: {A: [0, 0], B: [a, 0]}}
  coupler: {points: {B: [0, 0], C: [b, 0]}}
  rocker:  {points: {D: [0, 0], C: [c, 0]}}
joints:
  A: {revolute: [ground.A, crank.A]}
  B: {revolute: [crank.B, coupler.B]}
  C: {revolute: [coupler.C, rocker.C]}
  D: {revolute: [rocker.D, ground.D]}
inputs:
  - {joint: A}
)";

struct Hostile {
  std::string name;
  std::string find, replace;  // one replacement in kGoodModel ("" find: append)
  std::string at;             // the error points at the first character of this text, searched
                              // from the replacement on ...
  int at_offset;              // ... plus this many characters
  std::string message;        // a part of the message
};

std::string Mutated(const Hostile& c, size_t* where) {
  std::string text = kGoodModel;
  size_t pos = text.size();
  if (!c.find.empty()) {
    pos = text.find(c.find);
    if (pos == std::string::npos) return "";
    text.replace(pos, c.find.size(), c.replace);
  } else {
    text += c.replace;
  }
  *where = text.find(c.at, pos);
  if (*where != std::string::npos) *where += static_cast<size_t>(c.at_offset);
  return text;
}

// 1-based line and column (bytes) of text[index].
std::pair<int, int> LineColumn(const std::string& text, size_t index) {
  int line = 1;
  size_t start = 0;
  for (size_t i = 0; i < index; ++i)
    if (text[i] == '\n') ++line, start = i + 1;
  return {line, static_cast<int>(index - start) + 1};
}

void ExpectOneLineError(const Result& r, const std::string& prefix, const std::string& message) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.out, "") << "nothing on stdout for a bad model";
  EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << "expected '" << prefix << "...', got: " << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << "expected '" << message << "' in: " << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  EXPECT_EQ(r.err.back(), '\n');
  // "what is wrong; what to do"
  EXPECT_NE(r.err.find("; ", prefix.size()), std::string::npos) << "no '; what to do' in: " << r.err;
  for (const char* internal : {"parser.cpp", "line 0, column 0", "GiNaC::", "power::eval"})
    EXPECT_EQ(r.err.find(internal), std::string::npos) << "internals in: " << r.err;
}

void PrintTo(const Hostile& c, std::ostream* os) { *os << c.name; }

class HostileModel : public ::testing::TestWithParam<Hostile> {};

TEST_P(HostileModel, OneLineAtTheRightCharacterExitOneNothingWritten) {
  const Hostile& c = GetParam();
  size_t where = std::string::npos;
  const std::string text = Mutated(c, &where);
  ASSERT_FALSE(text.empty()) << "case text not found: " << c.find;
  ASSERT_NE(where, std::string::npos) << "case marker not found: " << c.at;
  const auto [line, column] = LineColumn(text, where);
  TempDir dir;
  const fs::path model = dir.path() / "hostile.yaml";
  std::ofstream(model, std::ios::binary) << text;
  const fs::path out = dir.path() / "out";
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + out.string(), dir.path());
  ExpectOneLineError(r, model.string() + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: ",
                     c.message);
  EXPECT_FALSE(fs::exists(out)) << "output written for a bad model";
}

std::string Nested(int depth) { return std::string(depth, '(') + "b" + std::string(depth, ')'); }

INSTANTIATE_TEST_SUITE_P(
    Issue12, HostileModel,
    ::testing::Values(
        // ---- names: C++ keywords, reserved identifiers, macros, the generated code's names ----
        Hostile{"model_keyword", "name: fb", "name: class", "class", 0, "model name 'class' is a C++ keyword"},
        Hostile{"model_alternative_token", "name: fb", "name: and", "and", 0, "is a C++ keyword"},
        Hostile{"model_std", "name: fb", "name: std", "std", 0, "is a name the generated code uses"},
        Hostile{"model_mech", "name: fb", "name: mech", "mech", 0, "is a name the generated code uses"},
        Hostile{"model_leading_underscore", "name: fb", "name: _Fb", "_Fb", 0, "begins with an underscore"},
        Hostile{"model_double_underscore", "name: fb", "name: f__b", "f__b", 0, "contains a double underscore"},
        Hostile{"model_trailing_underscore", "name: fb", "name: fb_", "fb_", 0, "ends with an underscore"},
        Hostile{"model_macro", "name: fb", "name: errno", "errno", 0, "is a macro"},
        Hostile{"model_c_header", "name: fb", "name: math", "math", 0, "shadows the C header <math.h>"},
        Hostile{"model_injection", "name: fb", "name: \"x;int y\"", "\"x;int y\"", 0,
                "model name 'x;int y' is not a C++ identifier"},
        Hostile{"model_path", "name: fb", "name: ../escaped", "../escaped", 0, "is not a C++ identifier"},
        // UTF-8 is echoed as written (not re-encoded), bytes that are not UTF-8 as \xNN.
        Hostile{"model_utf8", "name: fb", "name: kr\xc3\xb6te", "kr", 0,
                "model name 'kr\xc3\xb6te' is not a C++ identifier: use ASCII letters"},
        Hostile{"model_yaml_escape", "name: fb", "name: \"kr\\xf6te\"", "\"kr", 0, "model name 'kr\xc3\xb6te'"},
        Hostile{"model_not_utf8", "name: fb", "name: kr\xf6te", "kr", 0, "model name 'kr\\xf6te'"},
        Hostile{"parameter_T", "  d: 4.0\n", "  d: 4.0\n  T: 1.0\n", "T: 1.0", 0,
                "parameter name 'T' is a name the generated code uses"},
        Hostile{"parameter_p", "  d: 4.0\n", "  d: 4.0\n  p: 1.0\n", "p: 1.0", 0, "parameter name 'p' is a name the generated code uses"},
        Hostile{"parameter_Scalar", "  d: 4.0\n", "  d: 4.0\n  Scalar: 1.0\n", "Scalar", 0, "is a name the generated code uses"},
        Hostile{"parameter_Cast", "  d: 4.0\n", "  d: 4.0\n  Cast: 1.0\n", "Cast", 0, "is a name the generated code uses"},
        Hostile{"parameter_Params", "  d: 4.0\n", "  d: 4.0\n  Params: 1.0\n", "Params", 0, "is a name the generated code uses"},
        Hostile{"parameter_M_PI", "  d: 4.0\n", "  d: 4.0\n  M_PI: 1.0\n", "M_PI", 0, "parameter name 'M_PI' is a macro"},
        Hostile{"parameter_errno", "  d: 4.0\n", "  d: 4.0\n  errno: 1.0\n", "errno", 0, "is a macro"},
        Hostile{"parameter_INFINITY", "  d: 4.0\n", "  d: 4.0\n  INFINITY: 1.0\n", "INFINITY", 0, "is a macro"},
        Hostile{"parameter_NAN", "  d: 4.0\n", "  d: 4.0\n  NAN: 1.0\n", "NAN", 0, "is a macro"},
        Hostile{"parameter_assert", "  d: 4.0\n", "  d: 4.0\n  assert: 1.0\n", "assert", 0, "is a macro"},
        Hostile{"parameter_linux", "  d: 4.0\n", "  d: 4.0\n  linux: 1.0\n", "linux", 0, "is a macro"},
        Hostile{"parameter_eigen_macro", "  d: 4.0\n", "  d: 4.0\n  EIGEN_ANYTHING: 1.0\n", "EIGEN_", 0, "is a macro"},
        Hostile{"parameter_keyword", "  d: 4.0\n", "  d: 4.0\n  int: 1.0\n", "int", 0, "parameter name 'int' is a C++ keyword"},
        Hostile{"parameter_reserved", "  d: 4.0\n", "  d: 4.0\n  _X: 1.0\n", "_X", 0, "begins with an underscore"},
        Hostile{"parameter_expression_name", "  d: 4.0\n", "  d: 4.0\n  deg: 1.0\n", "deg:", 0, "name of the expression language"},
        Hostile{"parameter_contour_u", "  d: 4.0\n", "  d: 4.0\n  u: 1.0\n", "u: 1.0", 0, "name of the expression language"},
        Hostile{"link_keyword", "  crank:   {points", "  class:   {points", "class", 0, "link name 'class' is a C++ keyword"},
        Hostile{"link_double_underscore", "  crank:   {points", "  cr__ank:   {points", "cr__ank", 0, "double underscore"},
        Hostile{"point_keyword", "B: [a, 0]", "new: [a, 0]", "new", 0, "point name 'new' is a C++ keyword"},
        Hostile{"point_reserved", "B: [a, 0]", "_B: [a, 0]", "_B", 0, "point name '_B' begins with an underscore"},
        Hostile{"joint_keyword", "  A: {revolute", "  delete: {revolute", "delete", 0, "joint name 'delete' is a C++ keyword"},
        Hostile{"joint_reserved", "  A: {revolute", "  _a: {revolute", "_a", 0, "joint name '_a' begins with an underscore"},
        // ---- free text copied into the header's comments ----
        Hostile{"title_carriage_return", "name: fb\n", "name: fb\ntitle: \"ok\\r int x;\"\n", "\"ok", 0,
                "title has the control character 0x0d"},
        Hostile{"title_line_break", "name: fb\n", "name: fb\ntitle: \"one\\ntwo\"\n", "\"one", 0, "title has a line break"},
        Hostile{"description_control", "name: fb\n", "name: fb\ndescription: \"bell \\a\"\n", "\"bell", 0,
                "description has the control character 0x07"},
        Hostile{"doc_trailing_backslash", "  a: 1.0", "  a: {value: 1.0, doc: \"crank \\\\\"}", "\"crank", 0,
                "the doc of parameter 'a' ends a line with a backslash"},
        Hostile{"doc_trailing_trigraph", "  a: 1.0", "  a: {value: 1.0, doc: \"crank ?\?/\"}", "\"crank", 0,
                "ends a line with the trigraph"},
        // ---- expressions: GiNaC's parser errors as one line at the character ----
        Hostile{"expression_unclosed", "C: [b, 0]", "C: [b+(, 0]", "b+(", 3, "cannot read 'b+(' as an expression: it ends"},
        Hostile{"expression_unopened", "C: [b, 0]", "C: [b), 0]", "b)", 1, "a ')' without its '('"},
        Hostile{"expression_bang", "C: [b, 0]", "C: [b!, 0]", "b!", 1, "unexpected '!'"},
        Hostile{"expression_double_star", "C: [b, 0]", "C: [b**2, 0]", "b**2", 2, "unexpected '*'"},
        Hostile{"expression_chained_power", "C: [b, 0]", "C: [b^1^1, 0]", "b^1^1", 3, "a second '^'"},
        Hostile{"expression_hash", "C: [b, 0]", "C: [b#1, 0]", "b#1", 1, "unexpected '#'"},
        Hostile{"expression_product", "C: [b, 0]", "C: [2b, 0]", "2b", 1, "right after a number"},
        Hostile{"expression_hex", "C: [b, 0]", "C: [0x1, 0]", "0x1", 1, "right after a number"},
        Hostile{"expression_quoted", "C: [b, 0]", "C: [\"b +\", 0]", "\"b +", 4, "it ends where"},
        Hostile{"expression_unknown_name", "C: [b, 0]", "C: [b + bb, 0]", "bb", 0, "unknown name 'bb'"},
        Hostile{"expression_constant_I", "C: [b, 0]", "C: [b + 0*I, 0]", "I,", 0, "unknown name 'I'"},
        Hostile{"function_zeta", "C: [b, 0]", "C: [b + zeta(2), 0]", "zeta", 0,
                "'zeta' is not a function of the expression language"},
        Hostile{"function_Li2", "C: [b, 0]", "C: [Li2(b), 0]", "Li2", 0, "'Li2' is not a function"},
        Hostile{"function_tgamma", "C: [b, 0]", "C: [tgamma(b), 0]", "tgamma", 0, "'tgamma' is not a function"},
        Hostile{"function_arity", "C: [b, 0]", "C: [sin(b) + atan2(b), 0]", "atan2", 0, "atan2 takes 2 arguments, not 1"},
        Hostile{"function_arity_quoted", "C: [b, 0]", "C: [\"b + sin(b, a)\", 0]", "sin", 0, "sin takes 1 argument, not 2"},
        Hostile{"function_without_argument", "C: [b, 0]", "C: [b*sin, 0]", "sin", 0, "needs its argument"},
        Hostile{"nesting_65", "C: [b, 0]", "C: [" + Nested(65) + ", 0]", "((", 64, "nested deeper than 64"},
        Hostile{"nesting_10000", "C: [b, 0]", "C: [" + Nested(10000) + ", 0]", "((", 0, "longer than 4096 characters"},
        // ---- exact constants GiNaC's reader would compute for minutes (fuzzing, issue 12) ----
        Hostile{"power_huge_exponent", "C: [b, 0]", "C: [b + 22222222222222^2222222222, 0]", "^2222", 0,
                "a power whose exponent is a constant beyond 1000"},
        Hostile{"power_huge_negative_exponent", "C: [b, 0]", "C: [b + 2^(-9827551997708061), 0]", "^(-98", 0,
                "a power whose exponent is a constant beyond 1000"},
        Hostile{"power_of_pi_huge", "C: [b, 0]", "C: [b*Pi^66666666, 0]", "^6666", 0, "exponent is a constant beyond 1000"},
        Hostile{"power_nested_exponent", "C: [b, 0]", "C: [b*(2^10)^(2^10), 0]", "^(2^10), 0", 0,
                "exponent is a constant beyond 1000"},
        Hostile{"power_too_many_digits", "C: [b, 0]", "C: [b*0 + (10^99*10^99)^999, 0]", "^999", 0,
                "would have about"},
        // ---- a sign after a binary operator: GiNaC would read 3*-1 + 4 as 3*(-1 + 4) ----
        Hostile{"sign_after_times", "C: [b, 0]", "C: [b + 3*-1 + 3, 0]", "-1 + 3", 0, "a sign right after '*'"},
        Hostile{"sign_after_power", "C: [b, 0]", "C: [b*2^-1*2, 0]", "-1*2", 0, "a sign right after '^'"},
        Hostile{"sign_after_minus", "C: [b, 0]", "C: [b - -1 + 1, 0]", "-1 + 1", 0, "a sign right after '-'"},
        Hostile{"literal_zero_huge_exponent", "C: [b, 0]", "C: [b + 0e308308045, 0]", "0e30", 0,
                "a number whose exponent (e308308045) is beyond 400"},
        // ---- numbers: inf and NaN at the defaults, division by zero, roots of negatives ----
        Hostile{"literal_inf", "C: [b, 0]", "C: [b + 1e400, 0]", "1e400", 0, "the number 1e400 is outside the range"},
        Hostile{"literal_underflow", "C: [b, 0]", "C: [b + 1e-400, 0]", "1e-400", 0, "outside the range"},
        Hostile{"exp_overflow", "C: [b, 0]", "C: [b + exp(1000), 0]", "b + exp", 0, "is not finite"},
        Hostile{"division_by_zero_parameter", "C: [b, 0]", "C: [a/(d-4) + b, 0]", "a/(d", 0, "divides by zero"},
        Hostile{"division_by_zero_literal", "C: [b, 0]", "C: [b/0, 0]", "b/0", 0, "divides by zero"},
        Hostile{"sqrt_negative", "C: [b, 0]", "C: [sqrt(a - 2) + b, 0]", "sqrt", 0, "square root of a negative number"},
        Hostile{"log_zero", "C: [b, 0]", "C: [log(a - 1) + b, 0]", "log", 0, "logarithm of zero"},
        Hostile{"asin_beyond_one", "C: [b, 0]", "C: [b*asin(2*a), 0]", "b*asin", 0, "asin of a number beyond [-1, 1]"},
        Hostile{"parameter_underflow", "  a: 1.0", "  a: 1e-308", "1e-308", 0, "parameter 'a' = 1e-308 is outside the range"},
        Hostile{"parameter_subnormal", "  a: 1.0", "  a: 1e-320", "1e-320", 0, "is outside the range"},
        Hostile{"parameter_huge", "  a: 1.0", "  a: 1e300", "1e300", 0, "is outside the range"},
        Hostile{"parameter_inf", "  a: 1.0", "  a: .inf", ".inf", 0, "must be a number"},
        Hostile{"range_nan", "  - {joint: A}", "  - {joint: A, range: [0, 0/0]}", "0/0", 0, "divides by zero"},
        // ---- YAML features a model does not use ----
        Hostile{"yaml_anchor", "  b: 3.5", "  b: &len 3.5", "&len", 0, "YAML anchors (&name) are not supported"},
        Hostile{"yaml_anchor_on_mapping", "  crank:   {points", "  crank:   &c {points", "&c", 0, "YAML anchors"},
        Hostile{"yaml_alias", "  c: 3.0", "  c: *len", "*len", 0, "YAML syntax: the referenced anchor is not defined"},
        Hostile{"yaml_second_document", "", "---\nname: other\n", "---", 0, "a second YAML document"},
        Hostile{"yaml_syntax", "  c: 3.0\n", "  c: [3.0\n", "  d:", 3, "YAML syntax"},
        // ---- degenerate geometry at the defaults ----
        Hostile{"zero_length_crank", "  a: 1.0", "  a: 0", "B: [a", 0, "link 'crank' has zero length"},
        Hostile{"zero_length_coupler", "  b: 3.5", "  b: 0", "C: [b", 0, "its angle is in no equation"},
        Hostile{"coincident_ground_pivots", "  d: 4.0", "  d: 0", "ground:  {", 0,
                "link 'ground' has zero length in loop 1"}),
    [](const ::testing::TestParamInfo<Hostile>& info) { return info.param.name; });

// Issue 13 (the model format as users write it): the same contract for its new errors.
INSTANTIATE_TEST_SUITE_P(
    Issue13, HostileModel,
    ::testing::Values(
        Hostile{"acos_beyond_one", "C: [b, 0]", "C: [b*acos(a + 1), 0]", "b*acos", 0, "acos of a number beyond [-1, 1]"},
        Hostile{"atan2_zero_zero", "C: [b, 0]", "C: [\"b + atan2(0, a - 1)\", 0]", "b + atan2", 0, "atan2(0, 0)"},
        Hostile{"function_unknown_lists_the_language", "C: [b, 0]", "C: [b + acosh(a), 0]", "acosh", 0,
                "(abs acos asin atan atan2 clamp cos exp log max min mod sign sin sqrt step tan)"},
        // Issue 26: the piecewise functions' own errors.
        Hostile{"mod_period_not_positive", "C: [b, 0]", "C: [\"b + mod(a, a - 1)\", 0]", "b + mod", 0,
                "takes mod(x, p) with a period p that is not positive"},
        Hostile{"min_one_argument", "C: [b, 0]", "C: [b + min(a), 0]", "min(a)", 0, "min takes 2 arguments, not 1"},
        Hostile{"clamp_without_arguments", "C: [b, 0]", "C: [b + clamp, 0]", "clamp, 0", 0,
                "the function clamp needs its arguments: clamp(x, a, b)"},
        Hostile{"load_jumps_where_a_velocity_is_0", "  rocker:  {points: {D: [0, 0], C: [c, 0]}}\n",
                "  rocker:  {points: {D: [0, 0], C: [c, 0]}, mass: 1, center: [c/2, 0], inertia: 0.1}\nloads:\n"
                "  cut: {torque: \"-5*step(theta_rocker_dot)\", on: crank}\noutputs: {quantities: [dynamics]}\n",
                "step(theta_rocker_dot)", 0, "step(theta_rocker_dot) jumps where the velocity in it is 0"},
        Hostile{"parameter_named_max", "  d: 4.0\n", "  d: 4.0\n  max: 1.0\n", "max:", 0,
                "is a name of the expression language"},
        Hostile{"derived_forward_reference", "  a: 1.0", "  a: {derived: c/3}", "c/3", 0,
                "'c' is a parameter defined further down (line 5)"},
        Hostile{"derived_itself", "  a: 1.0", "  a: {derived: a + 1}", "a + 1", 0, "'a' is the parameter being defined"},
        Hostile{"derived_and_value", "  a: 1.0", "  a: {value: 1, derived: 1}", "derived: 1", 9,
                "has both value and derived"},
        Hostile{"derived_out_of_domain", "  d: 4.0", "  d: {derived: sqrt(a - c)}", "sqrt(a - c)", 0,
                "square root of a negative number"},
        Hostile{"derived_bad_name", "  d: 4.0", "  d: 4.0\n  sin: {derived: a}", "sin:", 0, "is a name of the expression language"},
        Hostile{"pin_lists_a_link_twice", "  B: {revolute: [crank.B, coupler.B]}",
                "  B: {revolute: [crank.B, coupler.B, crank.A]}", "crank.A]}\n  C:", 0, "lists link 'crank' twice"},
        Hostile{"pin_name_taken", "  D: {revolute: [rocker.D, ground.D]}",
                "  D: {revolute: [rocker.D, ground.D]}\n  P_rocker: {revolute: [crank.B, rocker.C]}\n"
                "  P: {revolute: [crank.B, coupler.B, rocker.C]}", "coupler.B, rocker.C", 11, "rename that joint"},
        Hostile{"slot_angle_and_through", "  D: {revolute: [rocker.D, ground.D]}",
                "  D: {slot: {slot: rocker.D, pin: ground.D, angle: 0, through: rocker.C}}", "rocker.C}}", 0,
                "has both angle and through"},
        Hostile{"point_input_unknown_point", "  - {joint: A}", "  - {point: coupler.Q, coordinate: x, range: [0, 1]}",
                "coupler.Q", 0, "link 'coupler' has no point 'Q'"},
        Hostile{"point_input_fixed_point", "  - {joint: A}", "  - {point: crank.A, coordinate: x, range: [0, 1]}",
                "{point:", 0, "input x_crank_A cannot drive the linkage"},
        Hostile{"mode_unknown_coordinate", "", "assembly_modes:\n  crossed: {theta_rock: -2}\n", "theta_rock", 0,
                "assembly mode 'crossed': unknown coordinate 'theta_rock'; the coordinates are: theta_crank"},
        Hostile{"mode_name_not_identifier", "", "assembly_modes:\n  open-branch: {}\n", "open-branch", 0,
                "is not an identifier"},
        Hostile{"mode_without_values", "", "assembly_modes:\n  open:\n  crossed: {}\n", "open:", 0,
                "assembly mode 'open' has no values"},
        Hostile{"mode_twice", "", "assembly_modes:\n  open: {}\n  open: {}\n", "open: {}\n", 11, "duplicate name 'open'"},
        Hostile{"parameter_expression_as_value", "  d: 4.0", "  d: 4*a", "4*a", 0,
                "a parameter computed from others is written d: {derived: <expression>}"}),
    [](const ::testing::TestParamInfo<Hostile>& info) { return info.param.name; });

// Issue 24: a spring without its stiffness gave `invalid node; first invalid key` with no
// place, and one whose ends are one point `power::eval(): division by zero` with exit 2. The
// same classes further: keys given without their values, dampers like springs, ends that are
// one point through a pin over several links or through a second point at the same
// coordinates.
INSTANTIATE_TEST_SUITE_P(
    Issue24, HostileModel,
    ::testing::Values(
        Hostile{"spring_without_stiffness", "", "springs:\n  s1: {between: [crank.B, rocker.C]}\n", "{between", 0,
                "spring 's1' needs stiffness: k"},
        Hostile{"torsional_spring_without_stiffness", "", "springs:\n  s1: {torsional: A}\n", "{torsional", 0,
                "spring 's1' needs stiffness: k"},
        Hostile{"spring_stiffness_without_value", "", "springs:\n  s1: {between: [crank.B, rocker.C], stiffness: }\n",
                "stiffness: }", 11, "stiffness of spring 's1': stiffness has no value"},
        Hostile{"spring_stiffness_null", "", "springs:\n  s1: {between: [crank.B, rocker.C], stiffness: ~}\n", "~}", 0,
                "stiffness has no value"},
        Hostile{"load_point_without_value", "", "loads:\n  l1: {force: [1, 0], at: }\n", "at: }", 4,
                "load 'l1': at has no value"},
        Hostile{"load_link_without_value", "", "loads:\n  l1: {torque: 1, on: }\n", "on: }", 4,
                "load 'l1': on has no value"},
        Hostile{"friction_coefficient_without_value", "", "friction:\n  A: {coefficient: , pin_radius: 0.1}\n",
                "coefficient: ,", 13, "coefficient has no value"},
        Hostile{"spring_ends_at_one_pin", "", "springs:\n  s1: {between: [ground.A, crank.A], stiffness: 10}\n",
                "[ground.A", 0, "joins ground.A and crank.A, which are always at one place (the revolute joint A keeps"},
        Hostile{"spring_ends_at_one_pin_reversed", "", "springs:\n  s1: {between: [coupler.B, crank.B], stiffness: 1}\n",
                "[coupler.B", 0, "which are always at one place (the revolute joint B keeps them together)"},
        Hostile{"spring_ends_at_a_pin_over_three_links", "  B: {revolute: [crank.B, coupler.B]}",
                "  B: {revolute: [crank.B, coupler.B, rocker.C]}\nsprings:\n  s1: {between: [coupler.B, rocker.C], "
                "stiffness: 1}",
                "[coupler.B, rocker.C], stiff", 0, "always at one place (the revolute joints B"},
        Hostile{"spring_end_at_the_same_coordinates", "  rocker:  {points: {D: [0, 0], C: [c, 0]}}\n",
                "  rocker:  {points: {D: [0, 0], C: [c, 0], E: [0, 0]}}\nsprings:\n  s1: {between: [ground.D, rocker.E], "
                "stiffness: 10}\n",
                "[ground.D", 0, "joins ground.D and rocker.E, which are always at one place (the revolute joint D"},
        Hostile{"damper_ends_at_one_pin", "", "dampers:\n  d1: {between: [rocker.D, ground.D], coefficient: 1}\n",
                "[rocker.D", 0, "damper 'd1' joins rocker.D and ground.D, which are always at one place"}),
    [](const ::testing::TestParamInfo<Hostile>& info) { return info.param.name; });

TEST(HostileModel, ZeroLengthCrankIsNeverAGrashofCrankRocker) {
  // The issue's case: a = 0 was "Grashof crank-rocker: 'crank' can turn fully" with K = 0.
  std::string text = kGoodModel;
  text.replace(text.find("  a: 1.0"), 8, "  a: 0.0");
  TempDir dir;
  const fs::path model = dir.path() / "zero.yaml";
  std::ofstream(model) << text;
  const Result r = RunMechgen("report " + model.string(), dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err.find("crank-rocker"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(model.string() + ":9:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("moves nothing (K = 0)"), std::string::npos) << r.err;
}

TEST(HostileModel, RackWhosePinionHasZeroRadius) {
  const std::string text = R"(name: rack
parameters: {r: 0}
links:
  ground: {ground: true, points: {O: [0, 0], G: [0, -1]}}
  pinion: {points: {O: [0, 0]}}
  rack:   {points: {C: [0, 0]}}
joints:
  O: {revolute: [ground.O, pinion.O]}
  slide: {prismatic: {guide: ground.G, slider: rack.C, angle: 0}}
  mesh: {rack: {pinion: pinion, radius: r, slide: slide}}
inputs:
  - {joint: O}
)";
  TempDir dir;
  const fs::path model = dir.path() / "rack.yaml";
  std::ofstream(model) << text;
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string(), dir.path());
  ExpectOneLineError(r, model.string() + ":10:3: error: ", "rack 'mesh': the pinion's pitch radius is 0");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(HostileModel, TheEdgesOfTheLanguageAreAccepted) {
  // What the checks must let through: each replaces b in coupler.C and keeps its value 3.5
  // (so that the loop still closes), read straight from text by the reader.
  const std::string deep = std::string(64, '(') + "b" + std::string(64, ')');  // the limit
  const std::string nested_calls = "abs(abs(abs(abs(b))))";
  std::string long_sum = "b";
  while (long_sum.size() + 6 <= mechgen::kMaxExpressionLength) long_sum += " + 0*a";  // 4093 characters
  for (const std::string& e :
       {std::string("b*(-1)^(d - 2)"), std::string("-----b*(-1)"), std::string("(b^(-1))^(-1)"), std::string("-(-b)"), std::string("(-2*4 + 1)*0 + b"), std::string("b + 0*sqrt(a - 1)"),
        std::string("b*exp(0)*cos(0)^2 + 0*log(a)"), std::string("\"b + 0*atan2(a, d)\""), std::string(".5*7"),
        std::string("35e-1"), std::string("3.5E+0"), std::string("b + 0*1e-100 + 0*1e100"), deep, nested_calls,
        long_sum}) {
    std::string text = kGoodModel;
    text.replace(text.find("C: [b, 0]"), 9, "C: [" + e + ", 0]");
    try {
      const mechgen::Model m = mechgen::LoadModelFromString(text, "edge.yaml");
      GiNaC::exmap d = m.Defaults();
      EXPECT_NEAR(GiNaC::ex_to<GiNaC::numeric>(m.links[2].points[1].x.subs(d).evalf()).to_double(), 3.5, 1e-12) << e;
    } catch (const mechgen::ModelError& err) {
      ADD_FAILURE() << e << ": " << err.what();
    }
  }
}

// ---- files that are not model files ----

TEST(HostileFile, DirectoryIsNotAModel) {
  TempDir dir;
  const Result r = RunMechgen("generate " + dir.path().string() + " --out-dir " + (dir.path() / "out").string(),
                              dir.path());
  ExpectOneLineError(r, dir.path().string() + ": error: ", "the path is a directory, not a model file");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(HostileFile, DeviceIsNotReadUntilMemoryRunsOut) {
  TempDir dir;
  const Result r = RunMechgen("generate /dev/zero --out-dir " + (dir.path() / "out").string(), dir.path());
  ExpectOneLineError(r, "/dev/zero: error: ", "the path is not a regular file");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(HostileFile, FifoIsNotRead) {
  TempDir dir;
  const fs::path fifo = dir.path() / "model.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Result r = RunMechgen("generate " + fifo.string() + " --out-dir " + (dir.path() / "out").string(), dir.path());
  ExpectOneLineError(r, fifo.string() + ": error: ", "the path is not a regular file");
}

TEST(HostileFile, LargerThanOneMebibyteIsRejected) {
  TempDir dir;
  const fs::path model = dir.path() / "big.yaml";
  {
    std::ofstream os(model, std::ios::binary);
    os << kGoodModel;
    const std::string comment = "# " + std::string(1022, 'x') + "\n";
    for (int i = 0; i < 1024; ++i) os << comment;  // 1 MiB of comments after the model
  }
  ASSERT_GT(fs::file_size(model), mechgen::kMaxModelBytes);
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string(), dir.path());
  ExpectOneLineError(r, model.string() + ": error: ", "is larger than 1 MiB");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(HostileFile, DeepYamlNestingIsASyntaxErrorNotACrash) {
  TempDir dir;
  const fs::path model = dir.path() / "deep.yaml";
  std::ofstream(model) << kGoodModel << "assembly: " << std::string(10000, '[') << std::string(10000, ']') << "\n";
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string(), dir.path());
  ExpectOneLineError(r, model.string() + ":19:", "YAML syntax");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

// ---- --name on the command line ----

struct BadName {
  const char* name;
  const char* value;
  const char* message;
};

void PrintTo(const BadName& c, std::ostream* os) { *os << c.name; }

class HostileName : public ::testing::TestWithParam<BadName> {};

TEST_P(HostileName, IsACommandLineErrorAndWritesNothingAnywhere) {
  TempDir dir;
  const fs::path model = dir.path() / "fb.yaml";
  std::ofstream(model) << kGoodModel;
  const fs::path out = dir.path() / "sub" / "out";
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + out.string() + " --name " +
                                  Quoted(GetParam().value), dir.path());
  ExpectOneLineError(r, std::string("mechgen: error: --name '") + GetParam().value + "' ", GetParam().message);
  // Nothing in --out-dir, nor beside or above it (--name ../escaped).
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir.path())) files.push_back(e.path().filename().string());
  EXPECT_EQ(files, std::vector<std::string>{"fb.yaml"});
}

INSTANTIATE_TEST_SUITE_P(
    Issue12, HostileName,
    ::testing::Values(BadName{"path", "../escaped", "is not a C++ identifier"},
                      BadName{"absolute", "/tmp/x", "is not a C++ identifier"},
                      BadName{"injection", "x;int y", "is not a C++ identifier"},
                      BadName{"keyword", "class", "is a C++ keyword"},
                      BadName{"macro", "INFINITY", "is a macro"},
                      BadName{"std", "std", "is a name the generated code uses"},
                      BadName{"reserved", "__x", "begins with an underscore"},
                      BadName{"utf8", "kr\xc3\xb6te", "is not a C++ identifier: use ASCII letters"}),
    [](const ::testing::TestParamInfo<BadName>& info) { return std::string(info.param.name); });

// ---- the reader's name rules against independent lists ----

TEST(Names, EveryMacroOfTheGeneratedHeadersIncludesIsRejected) {
  // `c++ -dM -E` on <array>, <cmath>, <Eigen/Core>, <Eigen/LU> (configure time).
  std::ifstream in(MECHGEN_MACRO_LIST);
  ASSERT_TRUE(in) << MECHGEN_MACRO_LIST;
  int checked = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string define, name;
    if (!(words >> define >> name) || define != "#define") continue;
    name = name.substr(0, name.find('('));
    if (name.empty() || name[0] == '_') continue;  // reserved anyway (and rejected as such)
    ++checked;
    EXPECT_NE(mechgen::NameProblem(name, mechgen::NameRole::kParameter), "") << name;
    EXPECT_NE(mechgen::NameProblem(name, mechgen::NameRole::kModel), "") << name;
  }
  EXPECT_GT(checked, 100) << "the macro list looks empty";
}

TEST(Names, KeywordsAreRejectedEverywhere) {
  // C++20 [lex.key] and [lex.digraph] alternative tokens.
  const char* keywords[] = {
      "alignas", "alignof", "asm", "auto", "bool", "break", "case", "catch", "char", "char8_t", "char16_t",
      "char32_t", "class", "concept", "const", "consteval", "constexpr", "constinit", "const_cast",
      "continue", "co_await", "co_return", "co_yield", "decltype", "default", "delete", "do", "double",
      "dynamic_cast", "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend",
      "goto", "if", "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "nullptr",
      "operator", "private", "protected", "public", "register", "reinterpret_cast", "requires", "return",
      "short", "signed", "sizeof", "static", "static_assert", "static_cast", "struct", "switch", "template",
      "this", "thread_local", "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned",
      "using", "virtual", "void", "volatile", "wchar_t", "while", "and", "and_eq", "bitand", "bitor",
      "compl", "not", "not_eq", "or", "or_eq", "xor", "xor_eq"};
  for (const char* k : keywords)
    for (auto role : {mechgen::NameRole::kModel, mechgen::NameRole::kParameter, mechgen::NameRole::kLink,
                      mechgen::NameRole::kPoint, mechgen::NameRole::kJoint})
      EXPECT_EQ(mechgen::NameProblem(k, role), "is a C++ keyword") << k;
}

TEST(Names, KeywordLikeAndUnusualNamesAreAccepted) {
  for (const char* n : {"class_", "std_link", "delete_me", "new_", "Eigen_", "operator_", "int8", "NAN_", "L", "R",
                        "T1", "O2", "a1", "x6", "Scalar_", "p2", "errno_", "typename_"})
    for (auto role : {mechgen::NameRole::kParameter, mechgen::NameRole::kLink, mechgen::NameRole::kPoint,
                      mechgen::NameRole::kJoint})
      EXPECT_EQ(mechgen::NameProblem(n, role), "") << n;
  // The model name also becomes MECH_<NAME>_INSTANTIATING: no trailing underscore.
  EXPECT_EQ(mechgen::NameProblem("class_model", mechgen::NameRole::kModel), "");
  EXPECT_NE(mechgen::NameProblem("class_", mechgen::NameRole::kModel), "");
  // Links, points and joints are only strings and suffixes: a macro's name is fine there.
  EXPECT_EQ(mechgen::NameProblem("EOF", mechgen::NameRole::kLink), "");
}

}  // namespace
