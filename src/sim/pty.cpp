#include "rangekit/sim/pty.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>
#include <cerrno>
#include <cstdlib>

namespace rangekit {

PseudoTerminal::PseudoTerminal(int master_fd, std::string slave_path, std::optional<std::string> link_path)
    : FdTransport(master_fd, "pty " + (link_path ? *link_path : slave_path)),
      slave_path_(std::move(slave_path)),
      link_path_(std::move(link_path)) {}

PseudoTerminal::~PseudoTerminal() {
  if (held_slave_fd_ >= 0) ::close(held_slave_fd_);
  if (link_path_) ::unlink(link_path_->c_str());
}

Result<std::unique_ptr<PseudoTerminal>> PseudoTerminal::open(std::optional<std::string> link_path) {
  if (link_path) {
    struct stat existing {};
    if (::lstat(link_path->c_str(), &existing) == 0) {
      return make_error(Errc::io, *link_path + " already exists; remove it or choose another path");
    }
  }
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (master < 0) return make_error(Errc::io, errno_text("posix_openpt", errno));
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0) {
    const int error_number = errno;
    ::close(master);
    return make_error(Errc::io, errno_text("grantpt/unlockpt", error_number));
  }
  char name[128] = {};
  if (::ptsname_r(master, name, sizeof name) != 0) {
    const int error_number = errno;
    ::close(master);
    return make_error(Errc::io, errno_text("ptsname_r", error_number));
  }
  // Raw mode on the shared termios: no echo, no CR/LF translation, 8 bits.
  termios tio{};
  if (::tcgetattr(master, &tio) == 0) {
    ::cfmakeraw(&tio);
    ::tcsetattr(master, TCSANOW, &tio);
  }
  if (link_path && ::symlink(name, link_path->c_str()) != 0) {
    const int error_number = errno;
    ::close(master);
    return make_error(Errc::io, errno_text("cannot create symlink " + *link_path, error_number));
  }
  return std::unique_ptr<PseudoTerminal>(new PseudoTerminal(master, name, std::move(link_path)));
}

bool pty_target_is_newer_than_link(const struct stat& link, const struct stat& target) {
  if (!S_ISCHR(target.st_mode)) return false;
  // A pty is created before its link (open() below), so its ctime is not later.
  if (target.st_ctim.tv_sec != link.st_ctim.tv_sec) return target.st_ctim.tv_sec > link.st_ctim.tv_sec;
  return target.st_ctim.tv_nsec > link.st_ctim.tv_nsec;
}

bool PseudoTerminal::link_is_stale(const std::string& link_path) {
  struct stat link {};
  if (::lstat(link_path.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) return false;
  struct stat target {};
  if (::stat(link_path.c_str(), &target) != 0) return errno == ENOENT;
  // Under parallel load the kernel hands the dead emulator's /dev/pts number to the
  // next pty opened anywhere; the link then resolves, but to someone else's pty.
  return pty_target_is_newer_than_link(link, target);
}

Status PseudoTerminal::hold_slave_open() {
  if (held_slave_fd_ >= 0) return ok_status();
  held_slave_fd_ = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (held_slave_fd_ < 0) return make_error(Errc::io, errno_text("open " + slave_path_, errno));
  return ok_status();
}

}  // namespace rangekit
