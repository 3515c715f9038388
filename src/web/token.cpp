#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <random>
#include <system_error>

#include "rangekit/web/server.hpp"

namespace rangekit::web {

namespace {

std::string system_message(int error_number) { return std::generic_category().message(error_number); }

// Every check is made on the open descriptor, so the file cannot be swapped between check and read.
Result<Token> read_token(const std::string& path, int fd) {
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    const int error_number = errno;
    return make_error(Errc::io, "cannot check token file " + path + ": " + system_message(error_number));
  }
  if (!S_ISREG(info.st_mode)) {
    return make_error(Errc::io, "token file " + path +
                                    " is not a regular file: remove it (a new token is made) or set [service] "
                                    "token_file to a regular file");
  }
  if (info.st_uid != ::geteuid()) {
    return make_error(Errc::io, "token file " + path + " belongs to uid " + std::to_string(info.st_uid) +
                                    ", not to the service's uid " + std::to_string(::geteuid()) +
                                    ": chown it to the service's user, or remove it (a new token is made)");
  }
  if ((info.st_mode & 077) != 0) {
    std::array<char, 8> mode{};
    std::snprintf(mode.data(), mode.size(), "%04o", static_cast<unsigned>(info.st_mode & 07777));
    return make_error(Errc::io, "token file " + path + " may be read or written by group or others (mode " +
                                    mode.data() + "): chmod 600 " + path);
  }
  std::string text;
  std::array<char, 512> buffer{};
  while (text.size() < 4096 && text.find('\n') == std::string::npos) {
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const int error_number = errno;
      return make_error(Errc::io, "cannot read token file " + path + ": " + system_message(error_number));
    }
    if (got == 0) break;
    text.append(buffer.data(), static_cast<std::size_t>(got));
  }
  std::string value = text.substr(0, text.find('\n'));
  if (value.size() < 16 || value.size() > 1024) {
    return make_error(Errc::io, "token file " + path + " holds no token (one line of 16 to 1024 characters)");
  }
  return Token{value, false};
}

}  // namespace

Result<Token> load_or_create_token(const std::string& path) {
  // O_NOFOLLOW: a link planted at the path is refused, not followed; O_NONBLOCK: a FIFO there
  // cannot hold the service at open() (fstat refuses it next).
  const int existing = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  const int open_error = errno;
  if (existing >= 0) {
    auto token = read_token(path, existing);
    ::close(existing);
    return token;
  }
  if (open_error == ELOOP) {
    return make_error(Errc::io, "token file " + path +
                                    " is a symbolic link, which the service does not follow: put the file itself "
                                    "there (mode 0600) or set [service] token_file to the file");
  }
  if (open_error != ENOENT) {
    return make_error(Errc::io, "cannot open token file " + path + ": " + system_message(open_error));
  }
  std::random_device entropy;
  std::string value;
  for (int i = 0; i < 32; ++i) {
    static constexpr char digits[] = "0123456789abcdef";
    const auto byte = static_cast<unsigned>(entropy()) & 0xFFu;
    value.push_back(digits[byte >> 4]);
    value.push_back(digits[byte & 0xF]);
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0)
    return make_error(Errc::io, "cannot create token file " + path + ": " + std::generic_category().message(errno));
  const std::string line = value + "\n";
  const bool written = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  ::close(fd);
  if (!written) return make_error(Errc::io, "cannot write token file " + path);
  return Token{value, true};
}

}  // namespace rangekit::web
