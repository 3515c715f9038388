#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <random>
#include <system_error>

#include "rangekit/web/server.hpp"

namespace rangekit::web {

Result<Token> load_or_create_token(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0) {
    if ((info.st_mode & 077) != 0) {
      return make_error(Errc::io, "token file " + path + " may be read by others: chmod 600 it");
    }
    std::ifstream file(path);
    std::string value;
    std::getline(file, value);
    if (value.size() < 16)
      return make_error(Errc::io, "token file " + path + " holds no token (16 characters or more)");
    return Token{value, false};
  }
  std::random_device entropy;
  std::string value;
  for (int i = 0; i < 32; ++i) {
    static constexpr char digits[] = "0123456789abcdef";
    const auto byte = static_cast<unsigned>(entropy()) & 0xFFu;
    value.push_back(digits[byte >> 4]);
    value.push_back(digits[byte & 0xF]);
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    return make_error(Errc::io, "cannot create token file " + path + ": " + std::generic_category().message(errno));
  const std::string line = value + "\n";
  const bool written = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  ::close(fd);
  if (!written) return make_error(Errc::io, "cannot write token file " + path);
  return Token{value, true};
}

}  // namespace rangekit::web
