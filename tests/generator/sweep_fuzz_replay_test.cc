// Every argument list the sweep fuzzer found (fuzz/regressions/sweep/) and every seed
// (fuzz/seeds/sweep/), through the same body as the libFuzzer program (fuzz/sweep_target.h:
// the sweep command's main() for the fourbar model), in this ordinary build without
// libFuzzer: each must return an exit status (a crash or an escaping exception, e.g.
// std::bad_alloc, fails the test binary).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#define MECHGEN_FUZZ_NO_GENERATOR
#include "sweep_target.h"

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> Files(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

const fs::path kFuzz = fs::path(MECHGEN_SOURCE_DIR) / "fuzz";

TEST(FuzzReplay, SweepArgumentFindingsAndSeeds) {
  auto files = Files(kFuzz / "regressions" / "sweep");
  const auto seeds = Files(kFuzz / "seeds" / "sweep");
  EXPECT_FALSE(seeds.empty());
  files.insert(files.end(), seeds.begin(), seeds.end());
  // The sweep writes its files (if asked) into the working directory: a private one.
  const fs::path dir = fs::temp_directory_path() / ("mechgen_fuzz_replay_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const std::string data = Read(f);
    const int status = mechgen_fuzz::FuzzSweep(reinterpret_cast<const uint8_t*>(data.data()), data.size());
    EXPECT_GE(status, -1) << "exit status " << status;
  }
  fs::current_path(cwd);
  fs::remove_all(dir);
}

TEST(FuzzReplay, SweepArgumentsAreSplitByLine) {
  // The input format of the sweep target (the oracle: the arguments as written).
  const std::string text = "--steps\n10\n--range\ntheta_crank:0:90deg";
  std::vector<std::string> args;
  ASSERT_TRUE(mechgen_fuzz::FuzzSweepArguments(reinterpret_cast<const uint8_t*>(text.data()), text.size(), &args));
  EXPECT_EQ(args, (std::vector<std::string>{"fourbar_sweep", "--steps", "10", "--range", "theta_crank:0:90deg"}));
  const std::string big = "--steps\n1000000\n", path = "--csv\n/etc/x\n";
  EXPECT_FALSE(mechgen_fuzz::FuzzSweepArguments(reinterpret_cast<const uint8_t*>(big.data()), big.size(), &args));
  EXPECT_FALSE(mechgen_fuzz::FuzzSweepArguments(reinterpret_cast<const uint8_t*>(path.data()), path.size(), &args));
}

}  // namespace
