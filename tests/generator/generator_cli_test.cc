// The mechgen command line, end to end: generated/ matches what the generator produces
// now (byte for byte), output is the same on every run, and every kind of bad model gets
// one message with file:line:column and what to change, a non-zero exit, and no files.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

Result RunMechgen(const std::string& args) {
  const std::string cmd = std::string(MECHGEN_EXE) + " " + args + " 2>&1";
  Result r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::vector<std::string> ShippedModels() {
  std::vector<std::string> models;
  std::istringstream in(MECHGEN_SHIPPED_MODELS);
  std::string m;
  while (std::getline(in, m, ','))
    if (!m.empty()) models.push_back(m);
  return models;
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("mechgen_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

const fs::path kSource = MECHGEN_SOURCE_DIR;

TEST(GeneratedFiles, MatchWhatTheGeneratorProducesNow) {
  ASSERT_FALSE(ShippedModels().empty());
  for (const std::string& model : ShippedModels()) {
    TempDir out;
    const Result r = RunMechgen("generate " + (kSource / "models" / (model + ".yaml")).string() +
                         " --quiet --out-dir " + out.path().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const char* ext : {".h", ".cc", "_view.cc"}) {
      const fs::path committed = kSource / "generated" / (model + ext);
      ASSERT_TRUE(fs::exists(committed)) << committed << " is missing: run the regenerate target";
      EXPECT_EQ(Slurp(out.path() / (model + ext)), Slurp(committed))
          << committed << " differs from what mechgen generates now; run "
          << "`cmake --build build --target regenerate` and commit generated/";
    }
  }
}

TEST(GeneratedFiles, SameBytesOnEveryRun) {
  // GiNaC's term order changes from process to process; the output must not.
  for (const std::string& model : ShippedModels()) {
    std::string first;
    for (int run = 0; run < 6; ++run) {
      TempDir out;
      const Result r = RunMechgen("generate " + (kSource / "models" / (model + ".yaml")).string() +
                           " --quiet --out-dir " + out.path().string());
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const std::string text = Slurp(out.path() / (model + ".h")) + Slurp(out.path() / (model + ".cc")) +
                               Slurp(out.path() / (model + "_view.cc"));
      if (run == 0)
        first = text;
      else
        ASSERT_EQ(text, first) << model << " differs between run 0 and run " << run;
    }
  }
}

// A sum inside a product: GiNaC scales it so that its first term in GiNaC's own order (which
// follows hash values that change from process to process) is positive, so the same Phi row was
// -1/2*(-a + b)*s in one run and 1/2*(a - b)*s in the next, and the header's printed Phi changed
// between runs (a third of the runs, slot_whitworth's slot through two points at 45 degrees).
TEST(GeneratedFiles, SameBytesOnEveryRunWithASumInAProduct) {
  const fs::path model = kSource / "tests" / "kinematics" / "models" / "slot_whitworth.yaml";
  std::string first;
  for (int run = 0; run < 12; ++run) {
    TempDir out;
    const Result r = RunMechgen("generate " + model.string() + " --quiet --out-dir " + out.path().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string text = Slurp(out.path() / "slot_whitworth.h") + Slurp(out.path() / "slot_whitworth.cc");
    ASSERT_NE(text.find("Phi(0) = 0.5*((sqrt(2))*cos(theta_rocker) - (sqrt(2))*sin(theta_rocker))*s_slot"),
              std::string::npos)
        << "run " << run;
    if (run == 0)
      first = text;
    else
      ASSERT_EQ(text, first) << "slot_whitworth differs between run 0 and run " << run;
  }
}

TEST(Cli, HelpListsTheSubcommands) {
  const Result r = RunMechgen("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("generate"), std::string::npos);
  EXPECT_NE(r.output.find("report"), std::string::npos);
}

// A load that reads a velocity is taken at rest by the statics (its slow-motion value, 0 for a
// viscous torque): the generator says so, naming the load and the velocity, and the generated
// EvalStatics documents it; a model whose loads read no velocity gets no such note.
TEST(Cli, StaticsAtRestLoadsAreNamed) {
  TempDir out;
  const Result engine = RunMechgen("generate " + (kSource / "models" / "engine_single.yaml").string() + " -o " +
                                   out.path().string());
  ASSERT_EQ(engine.exit_code, 0) << engine.output;
  EXPECT_NE(engine.output.find("note: the statics (EvalStatics) evaluates the torque of load 'load' at rest "
                               "(theta_crank_dot = 0)"),
            std::string::npos)
      << engine.output;
  EXPECT_EQ(engine.output.find("load 'gas_1'"), std::string::npos) << engine.output;  // p_gas_1: no velocity
  EXPECT_NE(Slurp(out.path() / "engine_single.h").find("At rest: the torque of load 'load' is taken with "
                                                       "theta_crank_dot = 0"),
            std::string::npos);
  const Result loaded = RunMechgen("generate " + (kSource / "models" / "fourbar_loaded.yaml").string() + " -o " +
                                   out.path().string());
  ASSERT_EQ(loaded.exit_code, 0) << loaded.output;
  EXPECT_EQ(loaded.output.find("note:"), std::string::npos) << loaded.output;
  EXPECT_EQ(Slurp(out.path() / "fourbar_loaded.h").find("At rest:"), std::string::npos);
}

TEST(Cli, ReportShowsLoopsMobilityEquationsAndK) {
  const Result r = RunMechgen("report " + (kSource / "models" / "fourbar.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Independent loops (1)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("3*(4 - 1) - 2*4 = 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Phi(0) ="), std::string::npos);
  EXPECT_NE(r.output.find("Velocity coefficients K"), std::string::npos);
  // Paul's forms: K = -a sin(q - th_r) / (b sin(th_c - th_r)), det Phi_phi = b c sin(th_c - th_r)
  // (GiNaC orders the terms of a difference as it likes: either sign of the argument).
  EXPECT_TRUE(r.output.find("sin(theta_coupler-theta_rocker)") != std::string::npos ||
              r.output.find("sin(-theta_rocker+theta_coupler)") != std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("Singular configurations"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("block 0 (theta_coupler, theta_rocker): det = "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Transmission angle mu(0) at joint C between coupler 'coupler' and output 'rocker'"),
            std::string::npos)
      << r.output;
  // Its extremes over the crank's turn by the law of cosines (a 1, b 3.5, c 3, d 4):
  // delta = d -+ a gives acos((b^2 + c^2 - delta^2) / (2 b c)) = 54.3 deg and 100.3 deg.
  EXPECT_NE(r.output.find("mu from 54.3 deg (at 0.0 deg) to 100.3 deg (at 180.0 deg)"), std::string::npos)
      << r.output;
  const Result tex = RunMechgen("report --latex " + (kSource / "models" / "fourbar.yaml").string());
  ASSERT_EQ(tex.exit_code, 0) << tex.output;
  EXPECT_NE(tex.output.find("\\begin{pmatrix}"), std::string::npos) << tex.output;
  EXPECT_NE(tex.output.find("\\theta_{\\mathrm{crank}}"), std::string::npos) << tex.output;
}

// ---- bad models ----

// A valid four-bar to mutate: each case replaces one piece of text.
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

struct BadCase {
  const char* name;
  const char* find;      // text in kGoodModel to replace ("" appends `replace`)
  const char* replace;
  int line, column;      // where the error must point
  const char* message;   // a part of the message
};

std::string Mutate(const BadCase& c) {
  std::string text = kGoodModel;
  if (std::string(c.find).empty()) return text + c.replace;
  const auto pos = text.find(c.find);
  if (pos == std::string::npos) return "";
  return text.replace(pos, std::string(c.find).size(), c.replace);
}

class BadModel : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadModel, NamesFileLineColumnExitsNonZeroWritesNothing) {
  const BadCase& c = GetParam();
  const std::string text = Mutate(c);
  ASSERT_FALSE(text.empty()) << "test case text not found: " << c.find;
  TempDir dir;
  const fs::path model = dir.path() / "bad.yaml";
  std::ofstream(model) << text;
  const fs::path out = dir.path() / "out";
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + out.string());
  EXPECT_NE(r.exit_code, 0) << r.output;
  const std::string where = model.string() + ":" + std::to_string(c.line) + ":" + std::to_string(c.column) + ": error: ";
  EXPECT_EQ(r.output.rfind(where, 0), 0u) << "expected the message to start with '" << where << "', got: " << r.output;
  EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one message: " << r.output;
  EXPECT_FALSE(fs::exists(out)) << "output written for a bad model";
}

INSTANTIATE_TEST_SUITE_P(
    Errors, BadModel,
    ::testing::Values(
        // yaml-cpp marks where it noticed the unclosed '[': the start of the next line.
        BadCase{"syntax", "  c: 3.0\n", "  c: [3.0\n", 6, 4, "YAML syntax"},
        BadCase{"unknown_link", "[coupler.C, rocker.C]", "[coupler.C, rockr.C]", 15, 29,
                "unknown link 'rockr'"},
        BadCase{"unknown_point", "[crank.B, coupler.B]", "[crank.B, coupler.X]", 14, 27,
                "link 'coupler' has no point 'X'"},
        BadCase{"duplicate_link", "  rocker:  {points", "  crank:  {points", 11, 3,
                "duplicate name 'crank'"},
        BadCase{"duplicate_point", "{B: [0, 0], C: [b, 0]}", "{B: [0, 0], B: [b, 0]}", 10, 33,
                "duplicate name 'B'"},
        BadCase{"missing_ground", "{ground: true, points", "{ground: false, points", 8, 3,
                "no ground link"},
        BadCase{"self_joint", "[rocker.D, ground.D]", "[rocker.D, rocker.C]", 16, 3,
                "connects link 'rocker' to itself"},
        BadCase{"mobility", "  - {joint: A}\n", "  - {joint: A}\n  - {joint: D}\n", 18, 3,
                "2 input(s) declared but the mechanism has 1 degree(s) of freedom"},
        BadCase{"parameter_not_number", "  b: 3.5\n", "  b: three\n", 4, 6,
                "parameter 'b' must be a number"},
        BadCase{"unknown_parameter", "C: [b, 0]}}", "C: [bb, 0]}}", 10, 37,
                "cannot read 'bb' as an expression"},
        BadCase{"unknown_key", "  - {joint: A}\n", "  - {joint: A, rnage: [0, 1]}\n", 18, 16,
                "unknown key 'rnage'"},
        // A comma in an unquoted doc: text cuts it (a comma ends a value in { }): said at the
        // text, with the quoted text to write instead.
        BadCase{"comma_in_doc", "  a: 1.0\n", "  a: {value: 1.0, doc: crank AB, the input}\n", 3, 24,
                "quote the whole text: doc: \"crank AB, the input\""},
        // A table is called like a function: one named like a function of the language.
        BadCase{"table_named_sin", "", "tables:\n  sin: {x: [0, 1], y: [0, 1]}\n", 20, 3,
                "table name 'sin' is a function of the expression language: 'sin(x)' in an expression calls the "
                "function, never the table; rename it"},
        BadCase{"table_named_step", "", "tables:\n  step: {x: [0, 1], y: [0, 1]}\n", 20, 3,
                "table name 'step' is a function of the expression language"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

TEST(BadModelMore, DisconnectedLinkIsNamed) {
  TempDir dir;
  const fs::path model = dir.path() / "bad.yaml";
  std::string text = kGoodModel;
  text.replace(text.find("links:\n"), 7, "links:\n  lonely: {points: {X: [0, 0]}}\n");
  std::ofstream(model) << text;
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.output.rfind(model.string() + ":8:3: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("link 'lonely' is not connected to the ground"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(BadModelMore, StructureHasNoMobility) {
  // A triangle of three links pinned together and to the ground cannot move.
  const char* text = R"(name: tri
links:
  ground: {ground: true, points: {A: [0, 0], C: [2, 0]}}
  l1: {points: {A: [0, 0], B: [1, 0]}}
  l2: {points: {B: [0, 0], C: [1, 0]}}
joints:
  A: {revolute: [ground.A, l1.A]}
  B: {revolute: [l1.B, l2.B]}
  C: {revolute: [l2.C, ground.C]}
inputs:
  - {joint: A}
)";
  TempDir dir;
  const fs::path model = dir.path() / "tri.yaml";
  std::ofstream(model) << text;
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.output.rfind(model.string() + ":11:3: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("cannot move: mobility 0"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(BadModelMore, AssemblyThatCannotCloseIsReportedAtTheGuess) {
  // The crank reaches [-20, 20] deg (delta <= 6.37 < b + c = 6.5), but the assembly input
  // 180 deg puts B at distance d + a = 8.3 from D: the dyad's circles do not meet.
  std::string text = kGoodModel;
  text.replace(text.find("  d: 4.0"), 8, "  d: 7.3");
  text.replace(text.find("  - {joint: A}\n"), 15,
               "  - {joint: A, range: [-20*deg, 20*deg]}\nassembly:\n  theta_crank: 180*deg\n");
  TempDir dir;
  const fs::path model = dir.path() / "far.yaml";
  std::ofstream(model) << text;
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind(model.string() + ":20:3: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("cannot be assembled at the assembly configuration (theta_crank = 180 deg)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("the two circles do not meet"), std::string::npos) << r.output;
  // In the designer's terms: the links, their lengths and the distance they must span (B at
  // (-1, 0), D at (7.3, 0): 8.3 > 3.5 + 3).
  EXPECT_NE(r.output.find("link 'coupler' (3.5) and link 'rocker' (3) cannot reach each other to close joint C: the "
                          "points they turn about are 8.3 apart, more than 3.5 + 3 = 6.5; together they need at least 8.3"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("change the assembly inputs or the lengths"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(ChangePoint, ParallelogramThroughAFullTurnIsGeneratedWithANote) {
  // tests/kinematics/models/parallelogram.yaml: crank = rocker, coupler = ground, driven over
  // [0, 360 deg]; its change points (all links collinear) at 0, 180 and 360 deg by hand.
  TempDir dir;
  const Result r = RunMechgen("generate " + (kSource / "tests/kinematics/models/parallelogram.yaml").string() +
                              " --out-dir " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir.path() / "out" / "parallelogram.h")) << r.output;
  EXPECT_NE(r.output.find("note: input 'theta_crank' passes change points of block 0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("at theta_crank = 0 deg, 180 deg, 360 deg"), std::string::npos) << r.output;
  // --quiet: nothing.
  const Result quiet = RunMechgen("generate --quiet " + (kSource / "tests/kinematics/models/parallelogram.yaml").string() +
                                  " --out-dir " + (dir.path() / "out2").string());
  EXPECT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output, "");
}

TEST(BadModelMore, RodThatCannotReachTheSlideIsNamedWithItsLengths) {
  // The slider-crank with a rod of 0.2: at the assembly input 90 deg the crank pin B is at
  // (0, 1) and the slide's line at y = 0.4, so the rod must span 1 - 0.4 = 0.6 (by hand).
  std::ifstream in(kSource / "models" / "slider_crank.yaml");
  std::stringstream read;
  read << in.rdbuf();
  std::string text = read.str();
  text.replace(text.find("b: {value: 3.2"), 14, "b: {value: 0.2");
  const std::string guess = "  theta_crank: 90*deg";
  const size_t at = text.find(guess);
  ASSERT_NE(at, std::string::npos);
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
  TempDir dir;
  const fs::path model = dir.path() / "short_rod.yaml";
  std::ofstream(model) << text;
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind(model.string() + ":" + std::to_string(line) + ":3: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("link 'rod' (0.2) cannot reach across to close joint C; it needs at least 0.6: lengthen "
                          "it or shorten what it spans"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(BadModelMore, AssemblyAtADeadPointIsReportedAtTheGuess) {
  // Offset slider-crank with e = a - b: at theta_crank = 90 deg the rod stands vertical,
  // sin(theta_rod) = (e - a) / b = -1 exactly, and d Phi / d theta_rod = b cos(theta_rod) = 0:
  // the loop closes there, but on no branch that can be chosen.
  const char* text = R"(name: tangent
parameters:
  a: 1.0
  b: 3.0
  e: -2.0
links:
  ground: {ground: true, points: {O: [0, 0], S: [0, e]}}
  crank:  {points: {O: [0, 0], B: [a, 0]}}
  rod:    {points: {B: [0, 0], C: [b, 0]}}
  slider: {points: {C: [0, 0]}}
joints:
  O: {revolute: [ground.O, crank.O]}
  B: {revolute: [crank.B, rod.B]}
  C: {revolute: [rod.C, slider.C]}
  slide: {prismatic: {guide: ground.S, slider: slider.C, angle: 0}}
inputs:
  - {joint: O, range: [0, 360*deg]}
assembly:
  theta_crank: 90*deg
  theta_rod: -80*deg
  s_slide: 0.5
)";
  TempDir dir;
  const fs::path model = dir.path() / "tangent.yaml";
  std::ofstream(model) << text;
  const Result r = RunMechgen("generate " + model.string() + " --out-dir " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind(model.string() + ":19:3: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("theta_rod: closed form, one angle"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("its Jacobian is singular there"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(BadModelMore, MissingFileIsReported) {
  const Result r = RunMechgen("generate /nonexistent/model.yaml --out-dir /tmp/never");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/nonexistent/model.yaml: error: cannot open"), std::string::npos) << r.output;
}


// `design: {quantities: [...]}` emits only the derivatives it names (positions always): the
// loaded four-bar with statics, with and without `statics` and `checks` in the list; the
// default is every one the outputs have.
TEST(DesignQuantities, OnlyTheNamedDerivativesAreEmitted) {
  TempDir dir;
  std::string text = Slurp(kSource / "models" / "fourbar_loaded.yaml");
  const size_t at = text.find("\ndesign:");
  ASSERT_NE(at, std::string::npos);
  const std::string before = text.substr(0, at + 1), after = text.substr(text.find('\n', at + 1));
  auto generate = [&](const std::string& design, const std::string& name) {
    const fs::path model = dir.path() / (name + ".yaml");
    std::ofstream(model) << before << design << after;
    const Result r = RunMechgen("generate " + model.string() + " -o " + dir.path().string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return Slurp(dir.path() / (std::string("fourbar_loaded") + ".h"));
  };
  const std::string all = generate("design: [a, b, c, d]", "all");
  EXPECT_NE(all.find("void EvalDesignDerivatives("), std::string::npos);
  EXPECT_NE(all.find("void EvalDesignChecks("), std::string::npos);
  EXPECT_NE(all.find("void EvalStaticsDesign("), std::string::npos);
  const std::string positions = generate("design: {parameters: [a, b, c, d], quantities: [positions]}", "positions");
  EXPECT_NE(positions.find("void EvalDesignDerivatives("), std::string::npos);
  EXPECT_EQ(positions.find("void EvalDesignChecks("), std::string::npos);
  EXPECT_EQ(positions.find("void EvalStaticsDesign("), std::string::npos);
  EXPECT_NE(positions.find("static constexpr bool kHasStaticsDesign = false;"), std::string::npos);
  const std::string statics = generate("design: {parameters: [a, b, c, d], quantities: [statics]}", "statics");
  EXPECT_NE(statics.find("void EvalStaticsDesign("), std::string::npos);
  EXPECT_EQ(statics.find("void EvalDesignChecks("), std::string::npos);
  // A quantity the outputs do not have, or no such quantity: an error at it.
  const fs::path bad = dir.path() / "bad.yaml";
  std::ofstream(bad) << before << "design: {parameters: [a], quantities: [dynamics]}" << after;
  Result r = RunMechgen("generate " + bad.string() + " -o " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("design quantity 'dynamics' needs dynamics in outputs.quantities"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "fourbar_loaded.h"));
}

}  // namespace
