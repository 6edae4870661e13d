// Every input the generator's fuzzers found (fuzz/regressions/: model files at the top,
// expression/ for the expression target) and every seed, through the same target bodies as
// the libFuzzer programs (fuzz/targets.h), in this ordinary build without libFuzzer (the
// sweep target's: sweep_fuzz_replay_test.cc): each must return normally (a clean rejection or a result). A crash or an
// escaping exception fails the test binary; the sanitizer build (scripts/sanitize.sh) runs
// it under ASan and UBSan too.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "targets.h"

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

TEST(FuzzReplay, ModelFindingsAreRejectedCleanly) {
  const auto files = Files(kFuzz / "regressions");
  EXPECT_FALSE(files.empty());
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const std::string data = Read(f);
    EXPECT_EQ(mechgen_fuzz::FuzzModel(reinterpret_cast<const uint8_t*>(data.data()), data.size()), 0);
  }
}

TEST(FuzzReplay, ExpressionFindingsAndSeeds) {
  auto files = Files(kFuzz / "regressions" / "expression");
  const auto seeds = Files(kFuzz / "seeds" / "expression");
  EXPECT_FALSE(seeds.empty());
  files.insert(files.end(), seeds.begin(), seeds.end());
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const std::string data = Read(f);
    EXPECT_EQ(mechgen_fuzz::FuzzExpression(reinterpret_cast<const uint8_t*>(data.data()), data.size()), 0);
  }
}

}  // namespace
