// OutputFile (io/output_file.h): a file written whole or not at all (issue 12). The
// oracle is the file system itself: what is (and is not) at the destination afterwards,
// and the errno texts of the failures (strerror), independent of the class.
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "mechgen/io/output_file.h"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("output_file_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string Read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // The entries of the directory, sorted, one string.
  std::string Listing(const fs::path& p) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(p)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    std::string all;
    for (const std::string& n : names) all += n + " ";
    return all;
  }
  fs::path dir_;
};

TEST_F(OutputFileTest, NothingAtTheDestinationUntilCommitThenTheWholeFile) {
  const fs::path target = dir_ / "sub" / "a.csv";
  OutputFile f;
  std::string error;
  ASSERT_TRUE(f.Open(target.string(), &error)) << error;
  for (int i = 0; i < 100000; ++i) f.stream() << i << ",x\n";  // more than the buffer
  EXPECT_FALSE(fs::exists(target));
  ASSERT_TRUE(f.Commit(&error)) << error;
  const std::string text = Read(target);
  EXPECT_EQ(text.substr(0, 6), "0,x\n1,");
  EXPECT_EQ(text.substr(text.size() - 8), "99999,x\n");
  EXPECT_EQ(Listing(target.parent_path()), "a.csv ");
  // The permissions of a plain open(): 0666 minus the umask.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  struct stat st;
  ASSERT_EQ(::stat(target.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0666 & ~mask);
}

TEST_F(OutputFileTest, DiscardedOrDestroyedLeavesThePreviousFile) {
  const fs::path target = dir_ / "a.csv";
  std::ofstream(target) << "previous\n";
  {
    OutputFile f;
    std::string error;
    ASSERT_TRUE(f.Open(target.string(), &error));
    f.stream() << "new, partial";
  }  // destroyed without Commit
  EXPECT_EQ(Read(target), "previous\n");
  EXPECT_EQ(Listing(dir_), "a.csv ");
}

TEST_F(OutputFileTest, WriteFailureMidFileReportsTheReasonAndKeepsThePreviousFile) {
  // A file-size limit makes write(2) fail with EFBIG part-way (as a full disk would with
  // ENOSPC), with SIGXFSZ ignored.
  const fs::path target = dir_ / "a.csv";
  std::ofstream(target) << "previous\n";
  struct rlimit old_limit;
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit limit = old_limit;
  limit.rlim_cur = 100000;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  OutputFile f;
  std::string error;
  ASSERT_TRUE(f.Open(target.string(), &error));
  for (int i = 0; i < 100000; ++i) f.stream() << "row " << i << "\n";
  const bool committed = f.Commit(&error);
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_FALSE(committed);
  EXPECT_EQ(error, "cannot write " + target.string() + ": " + std::strerror(EFBIG));
  EXPECT_EQ(Read(target), "previous\n");
  EXPECT_EQ(Listing(dir_), "a.csv ");
}

TEST_F(OutputFileTest, DevFullFailsWithEnospc) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  OutputFile f;
  std::string error;
  ASSERT_TRUE(f.Open("/dev/full", &error)) << error;
  f.stream() << "x\n";
  EXPECT_FALSE(f.Commit(&error));
  EXPECT_EQ(error, std::string("cannot write /dev/full: ") + std::strerror(ENOSPC));
  struct stat st;
  ASSERT_EQ(::stat("/dev/full", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));  // still the device, not replaced by a file
}

// Close() then Commit() (issue 24: a tool with several outputs closes all before renaming
// any): after Close() the destination is still the previous file, after Commit() the new one;
// a second output that fails at Close() leaves the first one's destination unchanged too.
TEST_F(OutputFileTest, CloseChecksEveryWriteBeforeAnyRename) {
  const fs::path a = dir_ / "a.csv";
  std::ofstream(a) << "previous a\n";
  {
    OutputFile first, second;
    std::string error;
    ASSERT_TRUE(first.Open(a.string(), &error)) << error;
    ASSERT_TRUE(second.Open("/dev/full", &error)) << error;
    first.stream() << "new a\n";
    second.stream() << "x\n";
    ASSERT_TRUE(first.Close(&error)) << error;
    EXPECT_EQ(Read(a), "previous a\n");
    EXPECT_FALSE(second.Close(&error));
    EXPECT_EQ(error, std::string("cannot write /dev/full: ") + std::strerror(ENOSPC));
  }  // the tool returns: neither is committed
  EXPECT_EQ(Read(a), "previous a\n");
  EXPECT_EQ(Listing(dir_), "a.csv ");
  OutputFile f;
  std::string error;
  ASSERT_TRUE(f.Open(a.string(), &error)) << error;
  f.stream() << "new a\n";
  ASSERT_TRUE(f.Close(&error)) << error;
  ASSERT_TRUE(f.Close(&error)) << error;  // a second Close() is a no-op
  EXPECT_EQ(Read(a), "previous a\n");
  ASSERT_TRUE(f.Commit(&error)) << error;
  EXPECT_EQ(Read(a), "new a\n");
  EXPECT_EQ(Listing(dir_), "a.csv ");
}

TEST_F(OutputFileTest, UnopenablePathsFailAtOpenAndCreateNothing) {
  std::string error;
  OutputFile f;
  EXPECT_FALSE(f.Open(dir_.string(), &error));
  EXPECT_EQ(error, "cannot write " + dir_.string() + ": " + std::strerror(EISDIR));
  std::ofstream(dir_ / "file") << "x";
  EXPECT_FALSE(f.Open((dir_ / "file" / "a.csv").string(), &error));
  EXPECT_NE(error.find("cannot write " + (dir_ / "file" / "a.csv").string() + ": "), std::string::npos);
  EXPECT_FALSE(f.Open("", &error));
  EXPECT_EQ(Listing(dir_), "file ");
}

}  // namespace
}  // namespace mechgen
