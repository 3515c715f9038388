#include "rangekit/sim/state_store.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rangekit/core/fd_transport.hpp"

namespace rangekit {

StateStore::StateStore(std::string directory, std::string device_key)
    : directory_(std::move(directory)), key_(std::move(device_key)) {}

std::string StateStore::file_path() const { return directory_ + "/" + key_ + ".json"; }

Result<std::optional<nlohmann::json>> StateStore::load() const {
  if (!persistent()) return std::optional<nlohmann::json>{};
  std::ifstream in(file_path());
  if (!in) return std::optional<nlohmann::json>{};
  std::stringstream text;
  text << in.rdbuf();
  auto memory = nlohmann::json::parse(text.str(), nullptr, false);
  if (memory.is_discarded() || !memory.is_object()) {
    return make_error(Errc::invalid_frame,
                      "non-volatile memory file " + file_path() + " is corrupt (not a JSON object)");
  }
  return std::optional<nlohmann::json>(std::move(memory));
}

Status StateStore::save(const nlohmann::json& memory) const {
  if (!persistent()) return ok_status();
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) return make_error(Errc::io, "cannot create state directory " + directory_ + ": " + error.message());
  const std::string temporary = file_path() + ".tmp";
  const std::string text = memory.dump(2) + "\n";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return make_error(Errc::io, errno_text("cannot write " + temporary, errno));
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  const int write_error = errno;
  ::close(fd);
  if (!written) return make_error(Errc::io, errno_text("cannot write " + temporary, write_error));
  if (::rename(temporary.c_str(), file_path().c_str()) != 0) {
    return make_error(Errc::io, errno_text("cannot replace " + file_path(), errno));
  }
  return ok_status();
}

}  // namespace rangekit
