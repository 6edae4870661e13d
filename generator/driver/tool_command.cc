// `mechgen sweep|statics|simulate|engine|flywheel`. See tool_command.h.
#include "driver/tool_command.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <utility>

#include "codegen/sha256.h"
#include "common/not_through_view.h"  // runtime/tools: kExitNotThroughView
#include "driver/tool_args.h"

// Set by generator/CMakeLists.txt: where the build found things, and the install layout.
#ifndef MECHGEN_VERSION
#define MECHGEN_VERSION "unknown"
#endif
#ifndef MECHGEN_SOURCE_RUNTIME_INCLUDE
#define MECHGEN_SOURCE_RUNTIME_INCLUDE ""
#endif
#ifndef MECHGEN_SOURCE_TOOLS
#define MECHGEN_SOURCE_TOOLS ""
#endif
#ifndef MECHGEN_EIGEN_INCLUDE_DIR
#define MECHGEN_EIGEN_INCLUDE_DIR "/usr/include/eigen3"
#endif
#ifndef MECHGEN_CLI11_INCLUDE_DIR
#define MECHGEN_CLI11_INCLUDE_DIR ""
#endif
#ifndef MECHGEN_MPI_CXX_COMPILER
#define MECHGEN_MPI_CXX_COMPILER ""
#endif
#ifndef MECHGEN_INSTALL_INCLUDEDIR
#define MECHGEN_INSTALL_INCLUDEDIR "include"
#endif
#ifndef MECHGEN_INSTALL_DATADIR
#define MECHGEN_INSTALL_DATADIR "share"
#endif
#ifndef MECHGEN_BUILD_VIEW_PROGRAM
#define MECHGEN_BUILD_VIEW_PROGRAM ""
#endif

namespace mechgen {
namespace {

namespace fs = std::filesystem;

// Bumped when the layout of an entry or the way it is built changes.
// 2: sweep.sha256 beside sweep; 3: every tool, its name and all of runtime/tools/ in the key;
// 4: every tool's CLI11 part compiled once (<tool>/args-<key>.o), not the sweep's only.
constexpr const char* kCacheFormat = "mechgen tool cache 4";
// The models' shared objects for mechgen_view (cache folder view/).
constexpr const char* kViewCacheFormat = "mechgen view cache 1";
// Every compile, after its optimization level (below); the driver adds its own.
const std::vector<std::string> kFlags = {"-std=c++17", "-DNDEBUG"};
// A per-model program (the runtime compiled for one model) and its parts: -O2, as the build
// compiles the per-model tools (the top-level CMakeLists.txt: -O3 costs them compile time for
// nothing).
constexpr const char* kProgramOptimization = "-O2";
// The model's shared object (BuildView, the generated code only): -O3, as the build compiles
// the model libraries and the runtime the object is loaded into (mechgen_view), so that the
// four-bar benchmark's view figures are those of the object mechgen builds. Against -O2 there
// (README, issue 43): a chained right-hand side 1.11-1.13 of the fixed-size one against
// 1.16-1.18, the statics row 0.98-1.00 against 1.05, the sweep step 2-4 % slower; the compile
// takes the same time (fourbar_massive 1.76 against 1.70 s).
constexpr const char* kViewOptimization = "-O3";

// A command `mechgen <tool> MODEL`: which driver it compiles and what the model must have.
struct ToolSpec {
  std::string name;                // "statics": the command, the cache's folder, the program
  std::string main;                // its driver in runtime/tools/
  std::vector<std::string> flags;  // the driver's own (each is Ceres-free)
  std::string quantity;            // what the model's outputs must have; "" nothing
  std::string summary;             // what the analysis gives (mechgen --help)
  std::vector<std::string> libs = {};  // linked after the objects, beyond the C++ library
  bool mpi = false;  // compiled and linked with an MPI C++ compiler when one is found (-DMECHGEN_STUDY_MPI)
  // Through the runtime compiled once (issue 43): run by the prebuilt `mechgen_view <name>` on
  // the model's shared object; where it says that the view does not do what was asked yet
  // (kExitNotThroughView), the per-model program as before.
  bool view = false;
};

const std::vector<ToolSpec>& Specs() {
  static const std::vector<ToolSpec> specs = {
      {"sweep", "sweep_main.cc", {"-DMECHGEN_SWEEP_NO_CERES"}, "",
       "the positions, velocity and centripetal coefficients and points along the inputs' range: table, "
       "CSV and SVG",
       {},
       false,
       true},
      {"statics", "statics_main.cc", {"-DMECHGEN_TOOL_NO_CERES"}, "forces",
       "the driving forces (with friction: to run the input in +q and in -q), reactions, potential and "
       "mechanical advantage along the range, dead zones and equilibria; --plots draws the driving torque "
       "and the ground bearings' polar diagrams with gnuplot (needs the output `forces`)",
       {},
       false,
       true},
      {"simulate", "simulate_main.cc", {}, "dynamics",
       "forward dynamics from rest or a given state, or a prescribed motion with its motor torque and "
       "bearing loads (needs the output `dynamics`)",
       {},
       false,
       true},
      {"engine", "engine_main.cc", {}, "dynamics",
       "an engine made by tools/make_engine.py: crank torque, bearing loads, flywheel sizing and run-up "
       "(needs the output `dynamics`)",
       {},
       false,
       true},
      {"flywheel", "flywheel_main.cc", {}, "forces",
       "flywheel sizing of a one-input machine: the driving torque at constant speed over a cycle, its "
       "energy loop, the flywheel for a coefficient of speed fluctuation and, with `dynamics`, its "
       "simulated check under a motor law (needs the output `forces`)",
       {},
       false,
       true},
      {"synthesize", "synthesize_main.cc", {}, "",
       "dimensional synthesis from a task file (--task): path generation by differential evolution and "
       "Levenberg-Marquardt on the generated design derivatives (or, `kind: exact`, every four-bar through "
       "five points with both pivots given, by homotopy continuation); the synthesized model file, an SVG and a "
       "report (needs a `design` section; Ceres, yaml-cpp)",
       {"-lceres", "-lglog", "-lgflags", "-lyaml-cpp", "-pthread"},
       false,
       true},
      {"study", "study_main.cc", {"-pthread"}, "",
       "a design study from --study FILE (docs/studies.md): grid, list, Latin hypercube or Monte-Carlo samples "
       "on every core, metrics per sample in a CSV, first-order tolerances beside the Monte-Carlo",
       {"-lyaml-cpp", "-pthread"},
       true,
       true},
  };
  return specs;
}

const ToolSpec* FindSpec(const std::string& tool) {
  for (const ToolSpec& spec : Specs())
    if (spec.name == tool) return &spec;
  return nullptr;
}

int Fail(const std::string& message) {
  std::cerr << "mechgen: error: " << message << "\n";
  return 1;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string Fixed(double x, int digits) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, x);
  return buffer;
}

bool ReadFile(const fs::path& path, std::string* bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream text;
  text << in.rdbuf();
  *bytes = text.str();
  return !in.bad();
}

std::string ReadOrEmpty(const fs::path& path) {
  std::string bytes;
  return ReadFile(path, &bytes) ? bytes : std::string();
}

// The model file as the generator reads it: a regular file of at most 1 MiB (+ 1 byte, so
// that a larger one differs). False if it is not one: the generation then says why.
bool ReadModel(const std::string& path, std::string* bytes) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes->assign(1024 * 1024 + 1, '\0');
  in.read(&(*bytes)[0], static_cast<std::streamsize>(bytes->size()));
  bytes->resize(static_cast<size_t>(in.gcount()));
  return !in.bad();
}

std::string Join(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : " ") + w;
  return text;
}

// ---- where things are ------------------------------------------------------------------

struct Toolchain {
  std::vector<std::string> compiler;  // $CXX split at blanks, or "c++"
  std::string compiler_identity;      // resolved path, size, modification time
  fs::path runtime_include;           // holds mechgen/position/solver.h
  fs::path tools;                     // holds the drivers (<tool>_main.cc, <tool>_args.*, common/)
  std::string eigen_include;          // holds Eigen/Core
  std::string cli11_include;          // holds CLI/CLI.hpp; empty: a default search directory
  std::vector<std::string> mpi_compiler;  // a ToolSpec::mpi driver's compiler (mpicxx); empty: none
  std::string mpi_identity;               // its resolved path, size, modification time
  fs::path view_program;                  // mechgen_view (a ToolSpec::view command); empty: not found
};

// "path size mtime" of a program, or its name if it cannot be resolved.
std::string Identity(const fs::path& program) {
  std::error_code ec;
  const fs::path resolved = fs::canonical(program, ec);
  struct stat st {};
  if (!ec && stat(resolved.c_str(), &st) == 0)
    return resolved.string() + " " + std::to_string(st.st_size) + " " +
           std::to_string(static_cast<long long>(st.st_mtime));
  return program.string();
}

// The installation prefix of this program: <prefix>/bin/mechgen (or the build tree's
// generator/ directory's parent, where nothing is found and the source tree is used).
fs::path Prefix() {
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path().parent_path();
}

fs::path Under(const fs::path& prefix, const char* dir) {
  const fs::path d(dir);
  return d.is_absolute() ? d : prefix / d;
}

bool IsExecutableFile(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && access(path.c_str(), X_OK) == 0;
}

// `name` as execvp() would find it; empty if not found.
fs::path FindProgram(const std::string& name) {
  if (name.find('/') != std::string::npos) return IsExecutableFile(name) ? fs::path(name) : fs::path();
  const char* path_env = std::getenv("PATH");
  std::stringstream dirs(path_env != nullptr ? path_env : "/usr/local/bin:/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    if (IsExecutableFile(candidate)) return candidate;
  }
  return fs::path();
}

bool DefaultIncludeDir(const std::string& dir) {
  return dir == "/usr/include" || dir == "/usr/local/include";
}

bool FindToolchain(const ToolSpec& spec, Toolchain* t) {
  const fs::path prefix = Prefix();
  std::error_code ec;
  // The runtime headers and the driver: installed beside this program, else the source tree.
  const fs::path installed_include = Under(prefix, MECHGEN_INSTALL_INCLUDEDIR);
  t->runtime_include = fs::exists(installed_include / "mechgen/position/solver.h", ec)
                           ? installed_include
                           : fs::path(MECHGEN_SOURCE_RUNTIME_INCLUDE);
  const fs::path installed_tools = Under(prefix, MECHGEN_INSTALL_DATADIR) / "mechgen" / "tools";
  t->tools = fs::exists(installed_tools / spec.main, ec) ? installed_tools : fs::path(MECHGEN_SOURCE_TOOLS);
  if (!fs::exists(t->runtime_include / "mechgen/position/solver.h", ec))
    return Fail("cannot find the mechgen runtime headers (looked in " + installed_include.string() +
                (std::string(MECHGEN_SOURCE_RUNTIME_INCLUDE).empty()
                     ? std::string()
                     : " and " + std::string(MECHGEN_SOURCE_RUNTIME_INCLUDE)) +
                "); is mechgen installed whole?"), false;
  std::vector<std::string> needed = {spec.main, "common/numbers.h", "common/cli.h"};
  needed.insert(needed.end(), {spec.name + "_args.h", spec.name + "_args.cc"});
  for (const std::string& file : needed) {
    if (!fs::exists(t->tools / file, ec))
      return Fail("cannot find the " + spec.name + " driver " + (t->tools / file).string() +
                  "; is mechgen installed whole?"), false;
  }
  // Eigen: $MECHGEN_EIGEN_INCLUDE_DIR, the build's, or the usual places.
  std::vector<std::string> eigen_candidates;
  if (const char* env = std::getenv("MECHGEN_EIGEN_INCLUDE_DIR"); env != nullptr && *env != '\0')
    eigen_candidates.push_back(env);
  eigen_candidates.insert(eigen_candidates.end(),
                          {MECHGEN_EIGEN_INCLUDE_DIR, "/usr/include/eigen3", "/usr/local/include/eigen3"});
  for (const std::string& dir : eigen_candidates) {
    if (!dir.empty() && fs::exists(fs::path(dir) / "Eigen/Core", ec)) {
      t->eigen_include = dir;
      break;
    }
  }
  if (t->eigen_include.empty())
    return Fail("cannot find Eigen (looked for Eigen/Core in " + Join(eigen_candidates) +
                "); install libeigen3-dev or set MECHGEN_EIGEN_INCLUDE_DIR"), false;
  // CLI11: the build's, else where the compiler looks anyway.
  const std::string cli11 = MECHGEN_CLI11_INCLUDE_DIR;
  if (!cli11.empty() && !DefaultIncludeDir(cli11) && fs::exists(fs::path(cli11) / "CLI/CLI.hpp", ec))
    t->cli11_include = cli11;
  // The compiler: $CXX (words: "ccache g++" works), else c++.
  const char* cxx = std::getenv("CXX");
  std::istringstream words(cxx != nullptr ? cxx : "");
  for (std::string w; words >> w;) t->compiler.push_back(w);
  if (t->compiler.empty()) t->compiler.push_back("c++");
  const fs::path program = FindProgram(t->compiler[0]);
  if (program.empty())
    return Fail("no C++ compiler: cannot find '" + t->compiler[0] + "'" +
                (cxx != nullptr && *cxx != '\0' ? " (from CXX)" : " on PATH") +
                "; install g++ (or clang++), or set CXX to a C++17 compiler"), false;
  t->compiler_identity = Identity(program);
  // The runtime compiled once: mechgen_view beside this program (installed), else the build's.
  if (spec.view) {
    const fs::path exe = fs::canonical("/proc/self/exe", ec);
    const fs::path beside = ec ? fs::path() : exe.parent_path() / "mechgen_view";
    for (const fs::path& candidate : {beside, fs::path(MECHGEN_BUILD_VIEW_PROGRAM)}) {
      if (!candidate.empty() && IsExecutableFile(candidate)) {
        t->view_program = candidate;
        break;
      }
    }
  }
  // MPI (the study): $MECHGEN_MPICXX ("" or "none": without MPI), else the MPI C++ compiler
  // the build found, else mpicxx on PATH; none found: the driver is built without MPI.
  if (spec.mpi) {
    const char* env = std::getenv("MECHGEN_MPICXX");
    std::vector<std::string> candidates;
    if (env != nullptr) {
      if (*env != '\0' && std::string(env) != "none") candidates.push_back(env);
    } else {
      candidates = {MECHGEN_MPI_CXX_COMPILER, "mpicxx"};
    }
    for (const std::string& c : candidates) {
      const fs::path found = c.empty() ? fs::path() : FindProgram(c);
      if (found.empty()) continue;
      t->mpi_compiler = {found.string()};
      t->mpi_identity = Identity(found);
      break;
    }
    if (env != nullptr && t->mpi_compiler.empty() && !candidates.empty())
      return Fail("MECHGEN_MPICXX=" + std::string(env) + ": no such program (set it to an MPI C++ compiler such "
                  "as mpicxx, or to none for a study driver without MPI)"), false;
  }
  return true;
}

// ---- the cache ---------------------------------------------------------------------------

// "label\0size\0bytes": parts that cannot run into each other.
void AddPart(std::string* material, const std::string& label, const std::string& bytes) {
  *material += label;
  *material += '\0';
  *material += std::to_string(bytes.size());
  *material += '\0';
  *material += bytes;
}

// Every regular file under dir, sorted, with its path relative to dir.
void AddTree(std::string* material, const fs::path& dir, const std::string& suffix) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->is_regular_file(ec) && name.size() >= suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) AddPart(material, fs::relative(f, dir, ec).string(), ReadOrEmpty(f));
}

std::string ToolchainPart(const Toolchain& t, const char* optimization = kProgramOptimization) {
  std::string material;
  AddPart(&material, "compiler", Join(t.compiler) + "\n" + t.compiler_identity);
  AddPart(&material, "flags", std::string(optimization) + " " + Join(kFlags));
  return material;
}

// The driver's program: the model's bytes and everything the program is built from (all of
// runtime/tools/: the drivers share their command-line layer).
std::string EntryKey(const ToolSpec& spec, const std::string& model_bytes, const std::string& templates,
                     const Toolchain& t) {
  std::string material = kCacheFormat;
  AddPart(&material, "tool", spec.name);
  AddPart(&material, "model", model_bytes);
  AddPart(&material, "version", MECHGEN_VERSION);
  AddPart(&material, "mechgen", ReadOrEmpty("/proc/self/exe"));
  AddTree(&material, templates, ".mustache");
  AddTree(&material, t.tools, "");
  AddTree(&material, t.runtime_include / "mechgen", "");
  material += ToolchainPart(t);
  AddPart(&material, "driver flags", Join(spec.flags));
  AddPart(&material, "eigen", t.eigen_include + "\n" +
                                  ReadOrEmpty(fs::path(t.eigen_include) / "Eigen/src/Core/util/Macros.h"));
  AddPart(&material, "cli11", t.cli11_include);
  AddPart(&material, "mpi", Join(t.mpi_compiler) + "\n" + t.mpi_identity);
  return Sha256Hex(material).substr(0, 32);
}

// A tool's CLI11 part (runtime/tools/<tool>_args.cc), the same for every model: its two files,
// the command-line layer (common/) and every runtime header (what an args file reads from the
// runtime differs by tool: a list of them could miss one).
std::string ArgsKey(const ToolSpec& spec, const Toolchain& t) {
  std::string material = kCacheFormat;
  AddPart(&material, "tool", spec.name);
  for (const std::string& file : {spec.name + "_args.h", spec.name + "_args.cc"})
    AddPart(&material, file, ReadOrEmpty(t.tools / file));
  AddTree(&material, t.tools / "common", "");
  AddTree(&material, t.runtime_include / "mechgen", "");
  material += ToolchainPart(t);
  AddPart(&material, "eigen", t.eigen_include);
  const fs::path cli11 = t.cli11_include.empty() ? fs::path("/usr/include") : fs::path(t.cli11_include);
  AddPart(&material, "cli11", t.cli11_include + "\n" + ReadOrEmpty(cli11 / "CLI/Version.hpp"));
  return Sha256Hex(material).substr(0, 32);
}

// ---- what a cached file must be: its size and SHA-256, recorded when it was built ----------
// A cached program (or object) is checked against its record before it is used, so that one
// truncated or overwritten on disk (a full disk, a crash while copying the cache, a stray
// write) is rebuilt rather than run.

// "<size> <sha256 hex>\n" of `bytes`: the record kept in <file>.sha256.
std::string Record(const std::string& bytes) { return std::to_string(bytes.size()) + " " + Sha256Hex(bytes) + "\n"; }

fs::path RecordPath(const fs::path& file) { return fs::path(file.string() + ".sha256"); }

// Writes the record of `file` (whole, then renamed: a reader sees the old record or the new).
bool WriteRecord(const fs::path& file) {
  std::string bytes;
  if (!ReadFile(file, &bytes)) return false;
  const fs::path record = RecordPath(file), part = fs::path(record.string() + ".part");
  {
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    out << Record(bytes);
    out.close();
    if (!out) return false;
  }
  std::error_code ec;
  fs::rename(part, record, ec);
  return !ec;
}

// Why `bytes` (the contents of `file`) are not what was recorded; "" if they are.
std::string RecordMismatch(const fs::path& file, const std::string& bytes) {
  std::string record;
  if (!ReadFile(RecordPath(file), &record) || record.empty()) return "it has no record of its size and SHA-256";
  const size_t blank = record.find(' ');
  const std::string size = record.substr(0, blank);
  if (blank == std::string::npos || size != std::to_string(bytes.size()))
    return "it is " + std::to_string(bytes.size()) + " bytes, recorded " + size;
  if (record != Record(bytes)) return "its SHA-256 is not the recorded one";
  return "";
}

// Whether `file` is what its record says (false, and *why, if not).
bool MatchesRecord(const fs::path& file, std::string* why) {
  std::string bytes;
  if (!ReadFile(file, &bytes)) return *why = "it cannot be read", false;
  *why = RecordMismatch(file, bytes);
  return why->empty();
}

// The cached program opened for fexecve: read through the descriptor that will be run, so
// that what runs is what was checked (an entry replaced meanwhile is a different file). -1
// and *why if it cannot be opened or does not match its record.
int OpenChecked(const fs::path& program, std::string* why) {
  const int fd = open(program.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return *why = std::string("it cannot be opened: ") + std::strerror(errno), -1;
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      *why = std::string("it cannot be read: ") + std::strerror(errno);
      close(fd);
      return -1;
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<size_t>(n));
  }
  *why = RecordMismatch(program, bytes);
  if (!why->empty()) {
    close(fd);
    return -1;
  }
  return fd;
}

bool CacheRoot(const std::string& option, fs::path* root) {
  const char* env = std::getenv("MECHGEN_CACHE_DIR");
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  if (!option.empty()) {
    *root = option;
  } else if (env != nullptr && *env != '\0') {
    *root = env;
  } else if (xdg != nullptr && *xdg == '/') {  // the XDG spec: relative values are ignored
    *root = fs::path(xdg) / "mechgen";
  } else if (home != nullptr && *home != '\0') {
    *root = fs::path(home) / ".cache" / "mechgen";
  } else {
    return Fail("no cache directory: HOME is not set; set MECHGEN_CACHE_DIR, or use --no-cache"), false;
  }
  std::error_code ec;
  *root = fs::absolute(*root, ec);
  return true;
}

std::string HostName() {
  char buffer[256] = {};
  if (gethostname(buffer, sizeof(buffer) - 1) != 0) return "host";
  std::string host = buffer;
  for (char& c : host)
    if (c == '/' || c == '.') c = '_';
  return host.empty() ? "host" : host;
}

// Temporary build directories (<host>.<pid>.<random>) of runs that were killed: those of a
// process of this host that no longer runs, and any older than a day.
void RemoveStaleTemporaries(const fs::path& tmp) {
  std::error_code ec;
  const std::string host = HostName();
  const auto now = fs::file_time_type::clock::now();
  for (fs::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const size_t last = name.rfind('.');
    const size_t before = last == std::string::npos || last == 0 ? std::string::npos : name.rfind('.', last - 1);
    bool stale = false;
    if (before != std::string::npos && name.compare(0, before, host) == 0 && before == host.size()) {
      const long pid = std::strtol(name.substr(before + 1, last - before - 1).c_str(), nullptr, 10);
      stale = pid > 0 && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
    }
    std::error_code time_ec;
    const auto modified = fs::last_write_time(it->path(), time_ec);
    if (!time_ec && now - modified > std::chrono::hours(24)) stale = true;
    if (stale) fs::remove_all(it->path(), time_ec);
  }
}

// ---- processes ---------------------------------------------------------------------------

// A signal during a build (SIGINT, SIGTERM, SIGHUP) is passed on to the compilers; the build
// then removes its temporary directory and ends by the same signal (status 128 + signal).
// Each compiler runs in a process group of its own (Start), and the signal goes to the whole
// group: the compiler driver (c++) and what it started (cc1plus, as, ld; ccache's compiler),
// which a signal to the driver's pid alone would leave running to the end of the compile.
// Once the compiler drivers have ended, their groups are killed (SIGKILL) and waited for: the
// build is the subreaper of its descendants (SignalGuard, Linux), so a cc1plus whose c++
// ended first is reaped here rather than left to init, and nothing of the build outlives it.
// No group of ours ever receives the terminal's signals: the compilers read /dev/null and
// write to their logs, so they need no terminal.
volatile sig_atomic_t g_signal = 0;
constexpr int kMaxChildren = 4;
// > 0: a compiler's pid, also its process group; < 0: minus the pid of a child in our own
// group (the driver run with --no-cache), signalled alone.
volatile pid_t g_children[kMaxChildren] = {0, 0, 0, 0};

// The signals forwarded, blocked while a child is started and registered.
constexpr int kForwarded[3] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void OnSignal(int sig);

// In a child before exec: the forwarded signals' dispositions as when mechgen started (the
// handler reset; an ignored signal stays ignored), then the mask as before.
void RestoreSignalsInChild(const sigset_t& old_mask) {
  for (int sig : kForwarded) {
    struct sigaction current {};
    if (sigaction(sig, nullptr, &current) == 0 && current.sa_handler == OnSignal) signal(sig, SIG_DFL);
  }
  sigprocmask(SIG_SETMASK, &old_mask, nullptr);
}

sigset_t ForwardedSet() {
  sigset_t set;
  sigemptyset(&set);
  for (int sig : kForwarded) sigaddset(&set, sig);
  return set;
}

extern "C" void OnSignal(int sig) {
  const int saved = errno;
  g_signal = sig;
  for (int i = 0; i < kMaxChildren; ++i) {
    const pid_t child = g_children[i];
    if (child > 0) {
      if (kill(-child, sig) != 0) kill(child, sig);  // its group; the pid if it has none yet
    } else if (child < 0) {
      kill(-child, sig);
    }
  }
  errno = saved;
}

class SignalGuard {
 public:
  SignalGuard() {
    struct sigaction action {};
    action.sa_handler = OnSignal;
    sigemptyset(&action.sa_mask);
    // A signal ignored when mechgen started (nohup, a background job) stays ignored.
    for (int i = 0; i < 3; ++i) {
      sigaction(kForwarded[i], &action, &old_[i]);
      if (old_[i].sa_handler == SIG_IGN) sigaction(kForwarded[i], &old_[i], nullptr);
    }
#ifdef PR_SET_CHILD_SUBREAPER
    prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
#endif
  }
  ~SignalGuard() {
#ifdef PR_SET_CHILD_SUBREAPER
    prctl(PR_SET_CHILD_SUBREAPER, 0, 0, 0, 0);
#endif
    for (int i = 0; i < 3; ++i) sigaction(kForwarded[i], &old_[i], nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;
  // After the cleanup: end by the signal that came, if one did.
  static void ReraiseIfSignalled() {
    if (g_signal == 0) return;
    const int sig = g_signal;
    signal(sig, SIG_DFL);
    raise(sig);
  }

 private:
  struct sigaction old_[3];
};

// A directory removed with everything in it unless Keep() was called.
class TempDir {
 public:
  explicit TempDir(fs::path path) : path_(std::move(path)) {}
  ~TempDir() {
    if (!path_.empty()) {
      std::error_code ec;
      fs::remove_all(path_, ec);
    }
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  void Keep() { path_.clear(); }

 private:
  fs::path path_;
};

// mkdtemp(<dir>/<prefix>XXXXXX).
bool MakeTempDir(const fs::path& dir, const std::string& prefix, fs::path* made) {
  std::string pattern = (dir / (prefix + "XXXXXX")).string();
  if (mkdtemp(&pattern[0]) == nullptr) return false;
  *made = pattern;
  return true;
}

// Starts argv (stdin from /dev/null, stdout and stderr to `log`) in a process group of its
// own, registered in g_children[slot] before a forwarded signal can be handled; -1 with
// *error if it cannot (an exec failure comes back through a close-on-exec pipe), or if a
// signal came before it started (*error then empty).
pid_t Start(const std::vector<std::string>& argv, const fs::path& log, int slot, std::string* error) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) {
    *error = std::string("pipe: ") + std::strerror(errno);
    return -1;
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const sigset_t forwarded = ForwardedSet();
  sigset_t old_mask;
  sigprocmask(SIG_BLOCK, &forwarded, &old_mask);
  if (g_signal != 0) {  // interrupted: start nothing more
    sigprocmask(SIG_SETMASK, &old_mask, nullptr);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    error->clear();
    return -1;
  }
  const pid_t pid = fork();
  if (pid < 0) {
    *error = std::string("fork: ") + std::strerror(errno);
    sigprocmask(SIG_SETMASK, &old_mask, nullptr);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    return -1;
  }
  if (pid == 0) {
    setpgid(0, 0);
    RestoreSignalsInChild(old_mask);
    close(pipe_fds[0]);
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in >= 0) dup2(in, 0);
    if (out >= 0) {
      dup2(out, 1);
      dup2(out, 2);
    }
    execvp(args[0], args.data());
    const int e = errno;
    ssize_t ignored = write(pipe_fds[1], &e, sizeof(e));
    (void)ignored;
    _exit(127);
  }
  setpgid(pid, pid);  // as the child does: whichever runs first (EACCES once it has exec'd)
  if (slot >= 0 && slot < kMaxChildren) g_children[slot] = pid;
  sigprocmask(SIG_SETMASK, &old_mask, nullptr);
  close(pipe_fds[1]);
  int exec_errno = 0;
  ssize_t n;
  do {
    n = read(pipe_fds[0], &exec_errno, sizeof(exec_errno));
  } while (n < 0 && errno == EINTR);
  close(pipe_fds[0]);
  if (n == static_cast<ssize_t>(sizeof(exec_errno))) {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (slot >= 0 && slot < kMaxChildren) g_children[slot] = 0;
    *error = "cannot run '" + argv[0] + "': " + std::strerror(exec_errno);
    return -1;
  }
  return pid;
}

// The exit status of a child: its code, or 128 + the signal that ended it.
int Wait(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return 1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

// After an interruption, with the compiler drivers (the groups' leaders) waited for: every
// group killed, and waited for until none of its processes is left (those reparented to this
// process reaped as they end), at most 10 s.
void KillGroups(const std::vector<pid_t>& groups) {
  for (pid_t g : groups) kill(-g, SIGKILL);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (;;) {
    while (waitpid(-1, nullptr, WNOHANG) > 0) {
    }
    bool left = false;
    for (pid_t g : groups) left = left || kill(-g, 0) == 0;
    if (!left || std::chrono::steady_clock::now() > deadline) return;
    usleep(10000);
  }
}

struct Job {
  std::vector<std::string> argv;
  fs::path log;
  pid_t pid = -1;
  int status = 0;
};

// Runs the jobs at once; false if one failed (its command and output printed).
bool RunJobs(std::vector<Job>* jobs, const std::string& what, bool verbose) {
  std::string error;
  bool started = true;
  for (size_t i = 0; i < jobs->size() && started; ++i) {
    Job& job = (*jobs)[i];
    if (verbose) std::cerr << "mechgen: " << Join(job.argv) << "\n";
    job.pid = Start(job.argv, job.log, static_cast<int>(i), &error);
    if (job.pid < 0) started = false;
  }
  std::vector<pid_t> groups;
  for (const Job& job : *jobs)
    if (job.pid > 0) groups.push_back(job.pid);
  for (size_t i = 0; i < jobs->size(); ++i) {
    Job& job = (*jobs)[i];
    if (job.pid <= 0) continue;
    job.status = Wait(job.pid);
    if (i < static_cast<size_t>(kMaxChildren)) g_children[i] = 0;
  }
  if (g_signal != 0) {  // interrupted: whatever of the groups outlived their compiler drivers goes too
    KillGroups(groups);
    return false;
  }
  if (!started) return Fail(error + "; install g++ (or clang++), or set CXX to a C++17 compiler"), false;
  for (const Job& job : *jobs) {
    if (job.status == 0) continue;
    std::cerr << "mechgen: error: " << what << " failed (exit status " << job.status << "): "
              << Join(job.argv) << "\n";
    std::vector<std::string> lines;
    {
      std::ifstream log(job.log);
      for (std::string line; std::getline(log, line);) lines.push_back(line);
    }
    // The compiler's first error lines first (a template error's "error:" line comes after
    // dozens of "In instantiation of" lines), then the start of its output.
    std::vector<std::string> errors;
    for (const std::string& line : lines) {
      if (line.find("error:") != std::string::npos || line.find("error ") == 0) {
        errors.push_back(line);
        if (errors.size() == 3) break;
      }
    }
    if (!errors.empty()) {
      std::cerr << "the compiler's first error" << (errors.size() > 1 ? "s" : "") << ":\n";
      for (const std::string& e : errors) std::cerr << "  " << e << "\n";
      std::cerr << "(a model that `mechgen generate` accepts should compile: report this with "
                   "the model file; the compiler's output follows)\n";
    }
    for (size_t n = 0; n < lines.size(); ++n) {
      if (n == 60) {
        std::cerr << "[... the rest of the compiler's output (" << lines.size() - 60
                  << " more lines) left out]\n";
        break;
      }
      std::cerr << lines[n] << "\n";
    }
    return false;
  }
  return true;
}

// A compile: the compiler (t's, or `compiler`), the optimization level, kFlags, then args.
std::vector<std::string> Command(const Toolchain& t, std::vector<std::string> args,
                                 const std::vector<std::string>& compiler = {},
                                 const char* optimization = kProgramOptimization) {
  std::vector<std::string> command = compiler.empty() ? t.compiler : compiler;
  command.push_back(optimization);
  command.insert(command.end(), kFlags.begin(), kFlags.end());
  command.insert(command.end(), args.begin(), args.end());
  return command;
}

// The model's outputs have what the command needs (spec.quantity); otherwise the error.
int CheckQuantity(const ToolSpec& spec, const ToolCommand& c, const std::string& name,
                  const std::vector<std::string>& quantities) {
  if (spec.quantity.empty() || std::find(quantities.begin(), quantities.end(), spec.quantity) != quantities.end())
    return 0;
  std::string have;
  for (const std::string& q : quantities) have += (have.empty() ? "" : " ") + q;
  return Fail("the model '" + name + "' (" + c.model_path + ") has no `" + spec.quantity +
              "` among its outputs' quantities (it has: " + have + "), which `mechgen " + spec.name +
              "` needs; add `" + spec.quantity + "` to its outputs (outputs: {quantities: [..., " +
              spec.quantity + "]}, models/README.md)");
}

// Generates and compiles the model's <tool> program in `dir`: dir/<tool>. `args_object` (the
// tool's CLI11 part, <tool>_args.cc): used if it exists, else compiled into dir/args.o and
// renamed to it (when not empty). Returns 0, or the exit status after printing the error.
int Build(const ToolSpec& spec, const ToolCommand& c, const GenerateFn& generate, const Toolchain& t,
          const std::string& model_bytes, const fs::path& dir, const fs::path& args_object,
          std::string* model_name) {
  const auto start = std::chrono::steady_clock::now();
  GeneratedModel model;
  const int generated = generate(c.model_path, dir.string(), &model);
  if (generated != 0 || g_signal != 0) return generated != 0 ? generated : 1;
  *model_name = model.name;
  if (const int status = CheckQuantity(spec, c, model.name, model.quantities); status != 0) return status;
  std::string again;
  if (!ReadModel(c.model_path, &again) || again != model_bytes)
    return Fail(c.model_path + " changed while it was being compiled; run again");
  const double generate_seconds = Seconds(start);
  const std::string& name = *model_name;
  const std::string what = "the " + spec.name + " command of '" + name + "'" +
                           (t.mpi_compiler.empty() ? "" : " with MPI (" + Join(t.mpi_compiler) + ")");
  std::cerr << "mechgen: compiling " << what << " (" << c.model_path << "; once, then cached)...\n";
  const auto compile_start = std::chrono::steady_clock::now();
  std::error_code ec;
  bool have_args = !args_object.empty() && fs::exists(args_object, ec);
  std::string why;
  if (have_args && !MatchesRecord(args_object, &why)) {
    // Damaged: compiled afresh below and put in its place.
    std::cerr << "mechgen: the cached object " << args_object.string() << " is damaged (" << why
              << "); compiling it again\n";
    have_args = false;
  }
  std::vector<std::string> main_args = spec.flags;
  main_args.push_back("-DMECHGEN_TOOL_ARGS_SEPARATE");  // <tool>_args.cc: the object below
  main_args.insert(main_args.end(), {"-DMECHGEN_MODEL_INCLUDE=\"" + name + ".h\"",
                                     "-DMECHGEN_MODEL_NAMESPACE=mech::" + name, "-I" + dir.string(),
                                     "-I" + t.runtime_include.string(), "-isystem", t.eigen_include});
  main_args.push_back("-DMECHGEN_TOOLS_DIR=\"" + t.tools.string() + "\"");  // statics --plots' scripts
  if (!t.mpi_compiler.empty()) main_args.push_back("-DMECHGEN_STUDY_MPI");
  main_args.insert(main_args.end(),
                   {"-c", (t.tools / spec.main).string(), "-o", (dir / "main.o").string()});
  std::vector<Job> jobs;
  jobs.push_back({Command(t, main_args, t.mpi_compiler), dir / "main.log"});
  jobs.push_back({Command(t, {"-isystem", t.eigen_include, "-c", (dir / (name + ".cc")).string(), "-o",
                              (dir / (name + ".o")).string()}),
                  dir / "model.log"});
  if (!have_args) {
    std::vector<std::string> args;
    if (!t.cli11_include.empty()) args = {"-isystem", t.cli11_include};
    // (An args file reads the runtime's requests and constants: mechgen/analysis/sweep_request.h, ...)
    args.insert(args.end(), {"-I" + t.runtime_include.string(), "-isystem", t.eigen_include, "-c",
                             (t.tools / (spec.name + "_args.cc")).string(), "-o", (dir / "args.o").string()});
    jobs.push_back({Command(t, args), dir / "args.log"});
  }
  if (!RunJobs(&jobs, "compiling " + what, c.verbose)) return 1;
  const fs::path program = dir / spec.name;
  std::vector<Job> link(1);
  link[0].argv = t.mpi_compiler.empty() ? t.compiler : t.mpi_compiler;
  link[0].argv.insert(link[0].argv.end(), {(dir / "main.o").string(), (dir / (name + ".o")).string()});
  link[0].argv.push_back(have_args ? args_object.string() : (dir / "args.o").string());
  link[0].argv.insert(link[0].argv.end(), {"-o", program.string()});
  link[0].argv.insert(link[0].argv.end(), spec.libs.begin(), spec.libs.end());
  link[0].log = dir / "link.log";
  if (!RunJobs(&link, "linking " + what, c.verbose)) return 1;
  // The program's record, in the entry; the CLI11 object's for later models, then the object
  // (rename: whole or not at all).
  if (!WriteRecord(program)) return Fail("cannot record the size and SHA-256 of " + program.string());
  if (!have_args && !args_object.empty() && WriteRecord(dir / "args.o")) {
    fs::rename(RecordPath(dir / "args.o"), RecordPath(args_object), ec);
    if (!ec) fs::rename(dir / "args.o", args_object, ec);
  }
  for (const char* file : {"main.o", "main.log", "model.log", "args.o", "args.o.sha256", "args.log", "link.log"})
    fs::remove(dir / file, ec);
  fs::remove(dir / (name + ".o"), ec);
  std::cerr << "mechgen: compiled in " << Fixed(Seconds(compile_start), 1) << " s";
  if (c.verbose) std::cerr << " (generated in " << Fixed(generate_seconds, 2) << " s)";
  std::cerr << "\n";
  return 0;
}

std::vector<std::string> DriverArgv(const ToolCommand& c) {
  std::vector<std::string> argv = {"mechgen " + c.tool + " " + c.model_path};
  argv.insert(argv.end(), c.driver_args.begin(), c.driver_args.end());
  return argv;
}



// ---- the route of a command: the per-model program, or the model's shared object for the
// ---- runtime compiled once (mechgen_view)

// Whether `mechgen <spec.name>` goes through the runtime compiled once: the command does, the
// build has mechgen_view, and MECHGEN_VIEW is not 0 (which keeps the per-model program, e.g. to
// compare the two). What the view does not do yet is for mechgen_view to say
// (kExitNotThroughView): then the per-model program.
bool ThroughView(const ToolSpec& spec, const Toolchain& t) {
  if (!spec.view || t.view_program.empty()) return false;
  const char* env = std::getenv("MECHGEN_VIEW");
  return env == nullptr || std::string(env) != "0";
}

// The model's shared object: the model's bytes and what the object is built from (the
// generator and its templates, the two runtime headers the generated view includes, the
// compiler, Eigen). The runtime's algorithms are not in it: a change of them keeps the object.
std::string ViewKey(const std::string& model_bytes, const std::string& templates, const Toolchain& t) {
  std::string material = kViewCacheFormat;
  AddPart(&material, "model", model_bytes);
  AddPart(&material, "version", MECHGEN_VERSION);
  AddPart(&material, "mechgen", ReadOrEmpty("/proc/self/exe"));
  AddTree(&material, templates, ".mustache");
  for (const char* header : {"mechgen/core/model_view.h", "mechgen/core/view_buffers.h"})
    AddPart(&material, header, ReadOrEmpty(t.runtime_include / header));
  material += ToolchainPart(t, kViewOptimization);
  AddPart(&material, "eigen", t.eigen_include + "\n" +
                                  ReadOrEmpty(fs::path(t.eigen_include) / "Eigen/src/Core/util/Macros.h"));
  return Sha256Hex(material).substr(0, 32);
}

// A view entry's model name and quantities (the files `name` and `quantities` beside the
// object), checked against the command.
int CheckViewEntry(const ToolSpec& spec, const ToolCommand& c, const fs::path& dir) {
  std::string name, text;
  if (!ReadFile(dir / "name", &name) || !ReadFile(dir / "quantities", &text))
    return Fail("the cache entry " + dir.string() + " lacks its model's name or quantities; run with --rebuild");
  std::vector<std::string> quantities;
  std::istringstream lines(text);
  for (std::string q; std::getline(lines, q);) quantities.push_back(q);
  return CheckQuantity(spec, c, name, quantities);
}

// Generates the model in `dir` and compiles it (its <name>.cc and <name>_view.cc, double only)
// into dir/model.so for mechgen_view, with the files `name` and `quantities`. 0, or the exit
// status after printing the error.
int BuildView(const ToolSpec& spec, const ToolCommand& c, const GenerateFn& generate, const Toolchain& t,
              const std::string& model_bytes, const fs::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  GeneratedModel model;
  const int generated = generate(c.model_path, dir.string(), &model);
  if (generated != 0 || g_signal != 0) return generated != 0 ? generated : 1;
  const std::string& name = model.name;
  if (const int status = CheckQuantity(spec, c, name, model.quantities); status != 0) return status;
  std::string again;
  if (!ReadModel(c.model_path, &again) || again != model_bytes)
    return Fail(c.model_path + " changed while it was being compiled; run again");
  const double generate_seconds = Seconds(start);
  {
    std::ofstream names(dir / "name", std::ios::binary), quantities(dir / "quantities", std::ios::binary);
    names << name;
    for (const std::string& q : model.quantities) quantities << q << "\n";
    if (!names || !quantities) return Fail("cannot write in " + dir.string());
  }
  const std::string what = "the model '" + name + "'";
  std::cerr << "mechgen: compiling " << what << " (" << c.model_path
            << "; the runtime is compiled once; once, then cached)...\n";
  const auto compile_start = std::chrono::steady_clock::now();
  // GCC makes the model's constants (static constexpr members: inline variables) STB_GNU_UNIQUE
  // symbols, which bind every object that defines them to the first one loaded and keep it
  // from ever being unloaded (dlclose): a model edited and loaded again would read the old
  // one's constants. -fno-gnu-unique keeps each object's own (clang makes none).
  std::vector<std::string> object_flags = {"-fPIC"};
  if (t.compiler_identity.find("clang") == std::string::npos) object_flags.push_back("-fno-gnu-unique");
  auto with = [&object_flags](std::vector<std::string> args) {
    args.insert(args.begin(), object_flags.begin(), object_flags.end());
    return args;
  };
  std::vector<Job> jobs;
  jobs.push_back({Command(t, with({"-isystem", t.eigen_include, "-c", (dir / (name + ".cc")).string(), "-o",
                                   (dir / "model.o").string()}),
                          {}, kViewOptimization),
                  dir / "model.log"});
  jobs.push_back({Command(t, with({"-DMECHGEN_VIEW_ENTRY", "-I" + dir.string(), "-I" + t.runtime_include.string(),
                                   "-isystem", t.eigen_include, "-c", (dir / (name + "_view.cc")).string(), "-o",
                                   (dir / "view.o").string()}),
                          {}, kViewOptimization),
                  dir / "view.log"});
  if (!RunJobs(&jobs, "compiling " + what, c.verbose)) return 1;
  std::vector<Job> link(1);
  link[0].argv = t.compiler;
  link[0].argv.insert(link[0].argv.end(), {"-shared", (dir / "model.o").string(), (dir / "view.o").string(), "-o",
                                           (dir / "model.so").string()});
  link[0].log = dir / "link.log";
  if (!RunJobs(&link, "linking " + what, c.verbose)) return 1;
  if (!WriteRecord(dir / "model.so")) return Fail("cannot record the size and SHA-256 of " + (dir / "model.so").string());
  std::error_code ec;
  for (const char* file : {"model.o", "view.o", "model.log", "view.log", "link.log"}) fs::remove(dir / file, ec);
  std::cerr << "mechgen: compiled in " << Fixed(Seconds(compile_start), 1) << " s";
  if (c.verbose) std::cerr << " (generated in " << Fixed(generate_seconds, 2) << " s)";
  std::cerr << "\n";
  return 0;
}

// How a command reaches its model: what is built into a cache entry (the per-model program,
// or the model's shared object) and how it is run.
struct Route {
  bool view = false;     // the model's object for mechgen_view (else the per-model program)
  bool verbose = false;  // say what runs (--verbose)
  std::string folder;    // the cache's folder: the command's name, or "view"
  std::string artefact;  // the file built in the entry, checked against its record before use
  std::string what;      // the artefact in the messages: "sweep command", "model object"
  std::string key;       // the entry's name
  std::function<int(const fs::path& dir)> build;         // into a fresh directory
  std::function<int(const fs::path& dir)> check;         // an entry before use (may be empty)
  // The program to run and its argv for the artefact at `path` (a child, or exec'd).
  std::function<std::pair<fs::path, std::vector<std::string>>(const fs::path& path)> command;
};

// Runs `program` with `argv` as a child (in our process group: a forwarded signal reaches it
// alone), with MECHGEN_VIEW_FALLBACK=1 in its environment when `fallback`, the descriptor
// `keep` (>= 0) left open across its exec; its exit status, or 128 + the signal that ended it.
int RunChild(const fs::path& program, const std::vector<std::string>& argv, bool fallback, int keep) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();
  // Registered before a forwarded signal can be handled; the child keeps our process group
  // (and the terminal), with its own dispositions.
  const sigset_t forwarded = ForwardedSet();
  sigset_t old_mask;
  sigprocmask(SIG_BLOCK, &forwarded, &old_mask);
  const pid_t pid = fork();
  if (pid == 0) {
    RestoreSignalsInChild(old_mask);
    if (keep >= 0) fcntl(keep, F_SETFD, 0);
    if (fallback) setenv(tools::kViewFallbackVariable, "1", 1);
    execv(program.c_str(), args.data());
    _exit(127);
  }
  if (pid > 0) g_children[0] = -pid;  // in our group: signalled alone
  sigprocmask(SIG_SETMASK, &old_mask, nullptr);
  if (pid < 0) return Fail(std::string("fork: ") + std::strerror(errno));
  const int status = Wait(pid);
  g_children[0] = 0;
  return status;
}

// Runs route.command(artefact), the artefact the checked descriptor `fd`: the per-model
// program becomes it (fexecve: what runs is what was checked; returns only if exec fails);
// mechgen_view runs as a child on /proc/self/fd/<fd> (what it loads is what was checked), so
// that its kExitNotThroughView can come back to mechgen.
int Launch(const Route& route, int fd, const fs::path& artefact) {
  if (route.view) {
    const auto [program, argv] = route.command(fs::path("/proc/self/fd/" + std::to_string(fd)));
    if (route.verbose) std::cerr << "mechgen: " << Join(argv) << "\n";
    int status = 0;
    {
      SignalGuard guard;
      status = RunChild(program, argv, true, fd);
    }
    close(fd);
    SignalGuard::ReraiseIfSignalled();  // ended by the signal that ended mechgen_view
    return status;
  }
  const auto [program, argv] = route.command(artefact);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();
  fexecve(fd, args.data(), environ);
  const int error = errno;
  close(fd);
  return Fail("cannot run " + program.string() + ": " + std::strerror(error));
}

int RunRoute(const Route& route, const ToolSpec& spec, const ToolCommand& c, bool readable) {
  std::error_code ec;
  if (c.no_cache || !readable) {
    // Built in a temporary directory, run as a child, removed. (An unreadable model ends in
    // the generator's message.)
    fs::path dir;
    if (!MakeTempDir(fs::temp_directory_path(ec), "mechgen-" + spec.name + ".", &dir))
      return Fail(std::string("cannot create a temporary directory: ") + std::strerror(errno));
    int status = 0;
    {
      TempDir temp(dir);
      SignalGuard guard;
      status = route.build(dir);
      if (status == 0 && g_signal == 0) {
        const auto [program, argv] = route.command(dir / route.artefact);
        if (route.verbose) std::cerr << "mechgen: " << Join(argv) << "\n";
        status = RunChild(program, argv, route.view, -1);
      }
    }  // the signal handlers restored, then the directory removed
    SignalGuard::ReraiseIfSignalled();
    return status;
  }

  fs::path root;
  if (!CacheRoot(c.cache_dir, &root)) return 1;
  const fs::path folder = root / route.folder, tmp = folder / "tmp";
  const fs::path entry = folder / route.key, artefact = entry / route.artefact;
  if (c.verbose) std::cerr << "mechgen: cache " << root.string() << ", entry " << entry.string() << "\n";
  bool rebuild = c.rebuild;
  if (!rebuild && fs::exists(entry, ec)) {
    if (route.check) {
      if (const int status = route.check(entry); status != 0) return status;
    }
    std::string why;
    const int fd = OpenChecked(artefact, &why);
    if (fd >= 0) {
      if (c.verbose) std::cerr << "mechgen: cached; running " << artefact.string() << "\n";
      return Launch(route, fd, artefact);
    }
    // Damaged: built again and put in its place (as --rebuild does).
    std::cerr << "mechgen: the cached " << route.what << " " << artefact.string()
              << " is damaged (" << why << "); building it again\n";
    rebuild = true;
  }

  fs::create_directories(tmp, ec);
  if (ec) return Fail("cannot create the cache directory " + tmp.string() + ": " + ec.message() +
                      "; set MECHGEN_CACHE_DIR, or use --no-cache");
  RemoveStaleTemporaries(tmp);
  fs::path dir;
  if (!MakeTempDir(tmp, HostName() + "." + std::to_string(getpid()) + ".", &dir))
    return Fail("cannot create a directory in " + tmp.string() + ": " + std::strerror(errno));
  int status = 0;
  {
    TempDir temp(dir);
    {
      SignalGuard guard;  // restored before the directory goes
      status = route.build(dir);
      if (status == 0 && g_signal == 0) {
        // Into place whole. --rebuild: the old entry moved aside first; a concurrent run
        // that got there first wins (its entry is as good as ours).
        if (rebuild && fs::exists(entry, ec)) {
          fs::path old;
          if (MakeTempDir(tmp, HostName() + "." + std::to_string(getpid()) + ".old.", &old)) {
            TempDir old_dir(old);
            fs::rename(entry, old / "entry", ec);
          }
        }
        fs::rename(dir, entry, ec);
        const std::string rename_error = ec.message();
        if (!ec) {
          temp.Keep();
        } else if (!fs::is_regular_file(artefact, ec) || !fs::exists(RecordPath(artefact), ec)) {
          status = Fail("cannot create the cache entry " + entry.string() + ": " + rename_error);
        }
        if (status == 0) std::cerr << "mechgen: cached in " << entry.string() << "\n";
      }
    }
  }
  SignalGuard::ReraiseIfSignalled();
  if (status != 0) return status;
  // Checked once more: what runs is the file its record describes, even if another run's
  // entry won the rename.
  std::string why;
  const int fd = OpenChecked(artefact, &why);
  if (fd < 0)
    return Fail("the " + route.what + " just built in " + entry.string() +
                " does not match its record (" + why + "); check the disk, or use --no-cache");
  return Launch(route, fd, artefact);
}

}  // namespace

void SplitToolArguments(int argc, const char* const* argv, int first,
                         const std::vector<std::string>& options_with_value, int* model_end,
                         std::vector<std::string>* driver_args) {
  driver_args->clear();
  int i = first;
  while (i < argc) {
    const std::string a = argv[i];
    if (a == "--") {  // the end of mechgen's options: the model follows
      ++i;
      break;
    }
    if (a.size() < 2 || a[0] != '-') break;  // the model
    const bool takes_value =
        std::find(options_with_value.begin(), options_with_value.end(), a) != options_with_value.end();
    i += takes_value ? 2 : 1;
  }
  if (i >= argc) {
    *model_end = argc;
    return;
  }
  *model_end = i + 1;
  int rest = i + 1;
  if (rest < argc && std::string(argv[rest]) == "--") ++rest;
  for (; rest < argc; ++rest) driver_args->push_back(argv[rest]);
}

const std::vector<std::string>& ToolNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const ToolSpec& spec : Specs()) n.push_back(spec.name);
    return n;
  }();
  return names;
}

std::string ToolSummary(const std::string& tool) {
  const ToolSpec* spec = FindSpec(tool);
  return spec != nullptr ? spec->summary : std::string();
}

std::string ToolQuantity(const std::string& tool) {
  const ToolSpec* spec = FindSpec(tool);
  return spec != nullptr ? spec->quantity : std::string();
}

std::vector<std::string> ToolsFor(const std::vector<std::string>& quantities) {
  std::vector<std::string> tools;
  for (const ToolSpec& spec : Specs())
    if (spec.quantity.empty() || std::find(quantities.begin(), quantities.end(), spec.quantity) != quantities.end())
      tools.push_back(spec.name);
  return tools;
}

int RunTool(const ToolCommand& c, const GenerateFn& generate) {
  const ToolSpec* found = FindSpec(c.tool);
  if (found == nullptr) return Fail("no command '" + c.tool + "'");
  const ToolSpec& spec = *found;
  // The options first (tool_args.h): --help and a usage error answered with nothing generated,
  // compiled or cached, no compiler needed. The help names the model by its file's stem.
  const int parsed = ParseToolOptions(spec.name, DriverArgv(c)[0], fs::path(c.model_path).stem().string(),
                                      c.driver_args);
  if (parsed >= 0) {
    std::cout.flush();
    return std::cout ? parsed : Fail("cannot write the standard output");
  }
  g_signal = 0;
  Toolchain t;
  if (!FindToolchain(spec, &t)) return 1;
  std::string model_bytes;
  const bool readable = ReadModel(c.model_path, &model_bytes);

  if (ThroughView(spec, t)) {
    // The model alone, into a shared object run by the prebuilt mechgen_view (one object per
    // model, for every command that goes through the view).
    Route route;
    route.view = true;
    route.verbose = c.verbose;
    route.folder = "view";
    route.artefact = "model.so";
    route.what = "model object";
    route.key = ViewKey(model_bytes, c.templates, t);
    route.build = [&](const fs::path& dir) { return BuildView(spec, c, generate, t, model_bytes, dir); };
    route.check = [&](const fs::path& dir) { return CheckViewEntry(spec, c, dir); };
    route.command = [&](const fs::path& object) {
      std::vector<std::string> argv = {t.view_program.string(), "--name", DriverArgv(c)[0], spec.name,
                                       object.string()};
      argv.insert(argv.end(), c.driver_args.begin(), c.driver_args.end());
      return std::make_pair(t.view_program, argv);
    };
    const int status = RunRoute(route, spec, c, readable);
    if (status != tools::kExitNotThroughView) return status;
    // What the view does not do yet (mechgen_view said nothing and wrote nothing): the
    // per-model program, as before the runtime was compiled once.
    if (c.verbose) std::cerr << "mechgen: not through the model view; the per-model " << spec.name << " command\n";
  }
  {
    Route route;
    route.folder = spec.name;
    route.artefact = spec.name;
    route.what = spec.name + " command";
    route.key = EntryKey(spec, model_bytes, c.templates, t);
    // The tool's CLI11 object, kept for later models in the cache's folder (cached runs only:
    // --no-cache and an unreadable model keep nothing).
    fs::path args_object;
    fs::path root;
    if (!c.no_cache && readable && CacheRoot(c.cache_dir, &root))
      args_object = root / spec.name / ("args-" + ArgsKey(spec, t) + ".o");
    route.build = [&](const fs::path& dir) {
      std::string name;
      return Build(spec, c, generate, t, model_bytes, dir, args_object, &name);
    };
    route.command = [&c](const fs::path& program) { return std::make_pair(program, DriverArgv(c)); };
    return RunRoute(route, spec, c, readable);
  }
}

}  // namespace mechgen
