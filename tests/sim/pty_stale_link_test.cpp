// A link left by a kill -9'd emulator must be recognised as stale even when, under
// load, the kernel has already given its /dev/pts number to another program's pty;
// a link to a live pty made by its own emulator must not be.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/pty.hpp"

namespace rangekit {
namespace {

struct stat at(mode_t type, time_t seconds, long nanoseconds) {
  struct stat result {};
  result.st_mode = type | 0620;
  result.st_ctim.tv_sec = seconds;
  result.st_ctim.tv_nsec = nanoseconds;
  return result;
}

TEST(PtyStaleLink, APtyCreatedAfterTheLinkIsSomeoneElses) {
  const struct stat link = at(S_IFLNK, 100, 500);
  EXPECT_TRUE(pty_target_is_newer_than_link(link, at(S_IFCHR, 100, 501)));
  EXPECT_TRUE(pty_target_is_newer_than_link(link, at(S_IFCHR, 101, 0)));
  EXPECT_FALSE(pty_target_is_newer_than_link(link, at(S_IFCHR, 100, 500)));
  EXPECT_FALSE(pty_target_is_newer_than_link(link, at(S_IFCHR, 99, 999)));
  EXPECT_FALSE(pty_target_is_newer_than_link(link, at(S_IFREG, 200, 0))) << "only device nodes are reused";
}

TEST(PtyStaleLink, TheLinkOfALivePtyIsNotStaleAndBecomesStaleWhenItCloses) {
  ls5_driver_test::TempDir dir;
  const std::string path = (dir.path / "port").string();
  const std::string left_behind = (dir.path / "left-behind").string();
  {
    auto pty = PseudoTerminal::open(path);
    ASSERT_TRUE(pty) << pty.error().message;
    EXPECT_FALSE(PseudoTerminal::link_is_stale(path));
    // A second link made while the pty lives, which nobody removes (as after kill -9).
    std::filesystem::create_symlink((*pty)->slave_path(), left_behind);
    EXPECT_FALSE(PseudoTerminal::link_is_stale(left_behind));
  }
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(path))) << "the pty removes its own link";
  // Either the pty is gone or a newer one took its number: stale both ways.
  EXPECT_TRUE(PseudoTerminal::link_is_stale(left_behind));
}

TEST(PtyStaleLink, NoLinkOrALinkToAnythingElseIsNotStale) {
  ls5_driver_test::TempDir dir;
  const std::string path = (dir.path / "port").string();
  EXPECT_FALSE(PseudoTerminal::link_is_stale(path));
  std::filesystem::create_symlink("/dev/null", path);
  EXPECT_FALSE(PseudoTerminal::link_is_stale(path));
}

}  // namespace
}  // namespace rangekit
