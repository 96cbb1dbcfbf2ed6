// write_file: a file is replaced whole or not at all.
#include <gtest/gtest.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rayscout/core/input_error.h"
#include "rayscout/core/output_path.h"

namespace rayscout {
namespace {

namespace fs = std::filesystem;

class WriteFileTest : public ::testing::Test {
 protected:
  fs::path dir_;
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rayscout_output_path_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  size_t files_in_dir() const { return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }
};

// A write cut short (here by a file size limit, as a full disk would) must not leave a prefix
// under the final name, nor truncate the file it was to replace: it used to open the file
// with O_TRUNC and write into it, so an old image was lost and, until the error was noticed
// and the file removed, a partial one (or, after Ctrl-C, for good) stood under its name.
TEST_F(WriteFileTest, AFailedWriteLeavesTheOldFileAndNoPartialOne) {
  const fs::path existing = dir_ / "old.png", fresh = dir_ / "new.png";
  write_file(existing, "old contents", "image");
  const std::string big(64 * 1024, 'x');
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
  rlimit limit = old_limit;
  limit.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string error_existing, error_fresh;
  try {
    write_file(existing, big, "image");
  } catch (const InputError& e) {
    error_existing = e.what();
  }
  try {
    write_file(fresh, big, "ray file");
  } catch (const InputError& e) {
    error_fresh = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(error_existing.find("image: cannot write " + existing.string() + " (65536 bytes): File too large"),
            std::string::npos) << error_existing;
  EXPECT_NE(error_fresh.find("ray file: cannot write " + fresh.string()), std::string::npos) << error_fresh;
  EXPECT_EQ(read(existing), "old contents");
  EXPECT_FALSE(fs::exists(fresh));
  EXPECT_EQ(files_in_dir(), 1u) << "the old file is gone or a temporary file was left behind";
}

// The file is replaced whole; its permissions are kept, and a symbolic link is written through
// (the link stays, its target is replaced), as writing into the open file did.
TEST_F(WriteFileTest, ReplacesTheTargetKeepingLinkAndPermissions) {
  const fs::path target = dir_ / "target.rays", link = dir_ / "link.rays";
  write_file(target, "first", "ray file");
  fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::create_symlink("target.rays", link);
  write_file(link, "second", "ray file");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read(target), "second");
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(files_in_dir(), 2u);
}

// Ctrl-C, SIGTERM or SIGHUP during a write used to leave the hidden temporary behind (with
// remove_temporaries_on_signals installed, as the CLI does, it does not). Here
// the signal arrives during the write, deterministically: in a child, a file size limit makes
// the write raise SIGXFSZ, whose handler raises the signal. The child must still die of that
// signal (a shell sees "killed by SIGINT"), and leave neither the target nor the temporary.
TEST_F(WriteFileTest, AnInterruptedWriteRemovesItsTemporary) {
  const std::string big(64 * 1024, 'x');
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    SCOPED_TRACE(::strsignal(sig));
    // Ignored when the test started (a background job's SIGINT): write_file leaves it so.
    struct sigaction now {};
    ASSERT_EQ(::sigaction(sig, nullptr, &now), 0);
    if (now.sa_handler == SIG_IGN) GTEST_SKIP() << ::strsignal(sig) << " is ignored in this process";
    const fs::path target = dir_ / "interrupted.rays";
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      static volatile sig_atomic_t to_raise = 0;
      to_raise = sig;
      struct sigaction on_limit {};
      on_limit.sa_handler = [](int) { ::raise(to_raise); };
      ::sigaction(SIGXFSZ, &on_limit, nullptr);
      const rlimit limit{4096, 4096};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      remove_temporaries_on_signals();
      try {
        write_file(target, big, "ray file");
      } catch (...) {
        ::_exit(2);  // the write failed (EFBIG) and the process lived on
      }
      ::_exit(1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    EXPECT_EQ(WTERMSIG(status), sig);
    std::string left;
    for (const auto& e : fs::directory_iterator(dir_)) (left += ' ') += e.path().filename().string();
    EXPECT_TRUE(left.empty()) << "left behind:" << left;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
}

// A device cannot be renamed over: it is written in place, and its errors are reported.
TEST_F(WriteFileTest, WritesDevicesInPlace) {
  if (!fs::exists("/dev/null") || !fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/null or /dev/full";
  write_file("/dev/null", "bytes", "--stats");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_THROW(write_file("/dev/full", "bytes", "--stats"), InputError);
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

}  // namespace
}  // namespace rayscout
