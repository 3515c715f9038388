#include "rangekit/core/fd_transport.hpp"

#include <poll.h>
#include <unistd.h>
#include <cerrno>
#include <cstring>

namespace rangekit {

std::string errno_text(const std::string& what, int error_number) {
  char buffer[256] = {};
  // GNU strerror_r: thread-safe, returns a pointer that may or may not be `buffer`.
  const char* text = ::strerror_r(error_number, buffer, sizeof buffer);
  return what + ": " + text;
}

FdTransport::FdTransport(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}

FdTransport::~FdTransport() { close_descriptor(); }

void FdTransport::close() noexcept { close_descriptor(); }

void FdTransport::close_descriptor() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

Status FdTransport::write_all(Bytes data) {
  if (fd_ < 0) return make_error(Errc::closed, name_ + ": write after close");
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd waiter{fd_, POLLOUT, 0};
      const int ready = ::poll(&waiter, 1, 1000);
      if (ready == 0)
        return make_error(Errc::timeout, name_ + ": output blocked for 1 s (flow control or a stalled reader)");
      if (ready < 0 && errno != EINTR) return make_error(Errc::io, errno_text(name_ + ": poll", errno));
      if (ready > 0 && (waiter.revents & (POLLHUP | POLLERR)) != 0)
        return make_error(Errc::closed, name_ + ": the other end is gone");
      continue;
    }
    if (n < 0 && (errno == EIO || errno == EPIPE || errno == ECONNRESET)) {
      return make_error(Errc::closed, errno_text(name_ + ": the other end is gone", errno));
    }
    return make_error(Errc::io, errno_text(name_ + ": write", errno));
  }
  return ok_status();
}

Result<std::size_t> FdTransport::read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) {
  if (fd_ < 0) return make_error(Errc::closed, name_ + ": read after close");
  if (out.empty()) return std::size_t{0};
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd waiter{fd_, POLLIN, 0};
    const int ready = ::poll(&waiter, 1, static_cast<int>(left.count() > 0 ? left.count() : 0));
    if (ready < 0) {
      if (errno == EINTR) continue;
      return make_error(Errc::io, errno_text(name_ + ": poll", errno));
    }
    if (ready == 0)
      return make_error(Errc::timeout, name_ + ": no bytes within " + std::to_string(timeout.count()) + " ms");
    const ssize_t n = ::read(fd_, out.data(), out.size());
    if (n > 0) return static_cast<std::size_t>(n);
    if (n == 0) return make_error(Errc::closed, name_ + ": the other end closed");
    if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
    // A pty master reads EIO once no process holds the slave open: the cable is out.
    if (errno == EIO) return make_error(Errc::closed, name_ + ": the other end is gone (EIO)");
    return make_error(Errc::io, errno_text(name_ + ": read", errno));
  }
}

}  // namespace rangekit
