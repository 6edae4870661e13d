// The tools' pictures: gnuplot, found on PATH, runs one of the plot scripts of runtime/tools/
// (plot_statics.gnuplot, plot_bearings.gnuplot, plot_energy_loop.gnuplot, ...) on the tool's
// own CSV, without a shell; the picture is written whole or not at all (a temporary file
// renamed when gnuplot succeeded). Used by the statics (--plots) and flywheel (--png, --svg)
// commands. POSIX (posix_spawn); nothing here runs in a solver's loop.
#pragma once

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <system_error>
#include <vector>

extern char** environ;  // the environment gnuplot inherits (posix_spawn)

namespace mechgen::tools {

/// The program `program` on PATH (an executable regular file), or empty.
inline std::filesystem::path FindOnPath(const std::string& program) {
  namespace fs = std::filesystem;
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "";
  for (size_t begin = 0; begin <= dirs.size();) {
    size_t end = dirs.find(':', begin);
    if (end == std::string::npos) end = dirs.size();
    const fs::path candidate = fs::path(end > begin ? dirs.substr(begin, end - begin) : ".") / program;
    if (::access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate;
    begin = end + 1;
  }
  return fs::path();
}

/// The directories the plot scripts are looked up in, in order. `env_dir` ($MECHGEN_TOOLS_DIR),
/// when set and not empty, is the only one: the user said where the scripts are, and a
/// directory that lacks one is an error, not a reason to take another tree's. Otherwise: beside
/// `program` as installed (<prefix>/bin/<tool> -> <prefix>/share/mechgen/tools; none when
/// `program` is empty), so that an installed or copied tool uses the scripts installed with it
/// rather than those of the tree it was built from; then the tools directory the command was
/// compiled from (-DMECHGEN_TOOLS_DIR=..., set by mechgen_add_model() for the statics tools and
/// by the mechgen driver: the source tree's runtime/tools, or share/mechgen/tools of an
/// installed mechgen); then the directory this header lies under (runtime/tools in the source
/// tree, share/mechgen/tools when installed; only when the compiler saw its absolute path).
inline std::vector<std::filesystem::path> PlotScriptDirs(const char* env_dir, const std::filesystem::path& program) {
  namespace fs = std::filesystem;
  if (env_dir != nullptr && *env_dir != 0) return {fs::path(env_dir)};
  std::vector<fs::path> candidates;
  if (!program.empty()) candidates.push_back(program.parent_path().parent_path() / "share" / "mechgen" / "tools");
#ifdef MECHGEN_TOOLS_DIR
  candidates.push_back(MECHGEN_TOOLS_DIR);
#endif
  // __FILE__ is relative where the compiler was given a relative path (ccache's base_dir):
  // relative to a directory unknown at run time, so not a candidate then.
  if (const fs::path header(__FILE__); header.is_absolute()) candidates.push_back(header.parent_path().parent_path());
  return candidates;
}

/// The first of `dirs` that holds every one of `scripts` (regular files), or empty.
inline std::filesystem::path FindPlotScriptsIn(const std::vector<std::filesystem::path>& dirs,
                                               std::initializer_list<const char*> scripts) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const fs::path& dir : dirs) {
    bool all = true;
    for (const char* script : scripts) all = all && fs::is_regular_file(dir / script, ec);
    if (all) return dir;
  }
  return fs::path();
}

/// This program's path (/proc/self/exe), or empty.
inline std::filesystem::path ThisProgram() {
  std::error_code ec;
  std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) self.clear();
  return self;
}

/// The directory that holds every one of `scripts`, or empty: PlotScriptDirs of
/// $MECHGEN_TOOLS_DIR and this program.
inline std::filesystem::path FindPlotScripts(std::initializer_list<const char*> scripts) {
  return FindPlotScriptsIn(PlotScriptDirs(std::getenv("MECHGEN_TOOLS_DIR"), ThisProgram()), scripts);
}

/// The one line a command prints when FindPlotScripts found no directory with every one of
/// `scripts`: the scripts and where they were looked for.
inline std::string PlotScriptsNotFound(std::initializer_list<const char*> scripts) {
  std::string names, where;
  for (const char* script : scripts) names += (names.empty() ? "" : " and ") + std::string(script);
  const char* env_dir = std::getenv("MECHGEN_TOOLS_DIR");
  if (env_dir != nullptr && *env_dir != 0) {
    where = "in $MECHGEN_TOOLS_DIR = " + std::string(env_dir) +
            " (point it at mechgen's runtime/tools or share/mechgen/tools, or unset it)";
  } else {
    for (const std::filesystem::path& dir : PlotScriptDirs(nullptr, ThisProgram()))
      where += (where.empty() ? "in " : ", ") + dir.string();
    where += std::string(where.empty() ? "" : " ") +
             "(set MECHGEN_TOOLS_DIR to mechgen's runtime/tools or share/mechgen/tools)";
  }
  return "cannot find " + names + " " + where;
}

/// Runs `gnuplot -e "csv='<csv>'; <format>='<tmp>'" <script>` (no shell; format png or svg,
/// the variable the scripts read) and renames the temporary picture onto `picture` when
/// gnuplot succeeded and wrote it (creating picture's directory); false with *error (one line).
/// csv and picture must not hold ' or a line break (gnuplot's quoted strings).
inline bool RunGnuplot(const std::filesystem::path& gnuplot, const std::filesystem::path& script,
                       const std::string& csv, const std::string& format, const std::string& picture,
                       std::string* error) {
  namespace fs = std::filesystem;
  const fs::path target(picture);
  const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp");
  std::error_code made;
  if (!target.parent_path().empty()) fs::create_directories(target.parent_path(), made);
  const std::string expression = "csv='" + csv + "'; " + format + "='" + tmp.string() + "'";
  std::vector<std::string> args = {gnuplot.string(), "-e", expression, script.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, gnuplot.c_str(), nullptr, nullptr, argv.data(), environ);
  int status = 0;
  std::error_code ec;
  if (spawned != 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0 ||
      !fs::is_regular_file(tmp, ec) || fs::file_size(tmp, ec) == 0) {
    fs::remove(tmp, ec);
    *error = "gnuplot " + script.filename().string() + " on " + csv + " failed" +
             (spawned != 0 ? std::string(": ") + std::strerror(spawned) : std::string());
    return false;
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    *error = "cannot write " + picture + ": " + ec.message();
    return false;
  }
  return true;
}

}  // namespace mechgen::tools
