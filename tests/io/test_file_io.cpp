// SPDX-License-Identifier: MIT
/// @file Bounded reads and atomic writes (io/file_io.hpp): a FIFO, a directory or an oversized
/// file is refused without blocking; a failed write leaves the good file that was there and no
/// temporary file; /dev/full fails instead of reporting success.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace cmmcomp::io {
namespace {

namespace fs = std::filesystem;

class FileIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cmmcomp-file-io-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const char* name) const { return (dir_ / name).string(); }
  static std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), {}));
  }
  fs::path dir_;
};

TEST_F(FileIo, ReadsARegularFile) {
  std::ofstream(path("a.txt")) << "hello";
  EXPECT_EQ(read_file_bounded(path("a.txt"), "test file", 100), "hello");
}

TEST_F(FileIo, RefusesAFifoWithoutBlocking) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  try {
    (void)read_file_bounded(path("fifo"), "model file", kMaxModelFileBytes);
    FAIL() << "a FIFO was read";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
}

TEST_F(FileIo, RefusesADirectoryAndAMissingFile) {
  EXPECT_THROW((void)read_file_bounded(dir_.string(), "model file", 100), ConfigError);
  EXPECT_THROW((void)read_file_bounded(path("missing"), "model file", 100), ConfigError);
}

TEST_F(FileIo, RefusesAFileOverTheLimitBeforeReadingIt) {
  { std::ofstream(path("big")); }
  fs::resize_file(path("big"), kMaxModelFileBytes + 1);  // sparse: nothing is written
  try {
    (void)read_file_bounded(path("big"), "model file", kMaxModelFileBytes);
    FAIL() << "an oversized file was read";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("more than the 4194304"), std::string::npos) << e.what();
  }
}

TEST_F(FileIo, WritesAndReplacesAtomically) {
  write_file_atomically(path("out.json"), "first");
  EXPECT_EQ(slurp(path("out.json")), "first");
  write_file_atomically(path("out.json"), "second, longer");
  EXPECT_EQ(slurp(path("out.json")), "second, longer");
  EXPECT_EQ(entries(), 1u) << "a temporary file was left behind";
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(static_cast<mode_t>(fs::status(path("out.json")).permissions()) & 0777, 0666 & ~mask);
}

TEST_F(FileIo, AFailedWriteKeepsTheGoodFileAndLeavesNoTemporary) {
  write_file_atomically(path("model.json"), "the good model");
  // A file size limit makes the write itself fail (EFBIG), even for root.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  struct sigaction old {};
  ASSERT_EQ(::sigaction(SIGXFSZ, &ignore, &old), 0);
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit tiny = saved;
  tiny.rlim_cur = 8;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &tiny), 0);
  bool threw = false;
  try {
    write_file_atomically(path("model.json"), std::string(1000, 'x'));
  } catch (const Error& e) {
    threw = true;
    EXPECT_NE(std::string(e.what()).find("nothing was replaced"), std::string::npos) << e.what();
  }
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &saved), 0);
  ::sigaction(SIGXFSZ, &old, nullptr);
  EXPECT_TRUE(threw);
  EXPECT_EQ(slurp(path("model.json")), "the good model");
  EXPECT_EQ(entries(), 1u) << "a temporary file was left behind";
}

TEST_F(FileIo, DevFullFails) { EXPECT_THROW(write_file_atomically("/dev/full", "rows"), Error); }

TEST_F(FileIo, AMissingDirectoryFails) {
  EXPECT_THROW(write_file_atomically(path("no/such/dir/out.csv"), "rows"), Error);
}

}  // namespace
}  // namespace cmmcomp::io
