// Raw bytes as an HTTP request to a running service (web::Server on loopback), as a client
// anywhere on the network could send them: Beast's parser with the service's limits, the
// access check, the router and every handler's query and body parsing, on a hub whose
// sensors are not connected (the request is read and checked before any sensor is asked).
// The first byte picks the server: on loopback without a token, or with one. Each answer is
// an HTTP response or a close, within a bound; a crash, a hang or a throw ends the fuzzer.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "rangekit/hub/site_config.hpp"
#include "rangekit/web/server.hpp"

namespace {

using namespace rangekit;

struct Service {
  std::unique_ptr<hub::Hub> hub;
  std::unique_ptr<hub::CaptureManager> captures;
  std::unique_ptr<web::Server> open;
  std::unique_ptr<web::Server> guarded;  // with the token of the seed corpus
  Service() {
    auto site = hub::parse_site_config(
        "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-fuzz-ls5\"\n"
        "[[sensor]]\nname = \"silo\"\nfamily = \"uls\"\nport = \"/nonexistent/rangekit-fuzz-uls\"\n",
        "site.toml");
    if (!site) std::abort();
    hub = hub::Hub::start(*site);
    const auto folder = std::filesystem::temp_directory_path() / ("rangekit-http-fuzz-" + std::to_string(::getpid()));
    captures = std::make_unique<hub::CaptureManager>(*hub, folder.string());
    // Fixed ports, so the seeds' Host headers name them.
    web::ServerOptions options;
    options.listen = "127.0.0.1:18081";
    options.captures = captures.get();
    options.request_timeout = std::chrono::milliseconds(2000);
    auto started = web::Server::start(*hub, options);
    if (!started) std::abort();
    open = std::move(*started);
    options.listen = "127.0.0.1:18082";
    options.token = "0123456789abcdef0123456789abcdef";
    started = web::Server::start(*hub, options);
    if (!started) std::abort();
    guarded = std::move(*started);
  }
};

int connect_to(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) std::abort();
  return fd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Service service;
  if (size == 0) return 0;
  const int fd = connect_to((data[0] & 1) != 0 ? 18082 : 18081);
  std::size_t sent = 1;
  while (sent < size) {
    const ssize_t n = ::send(fd, data + sent, size - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the service answered and closed before taking it all
    sent += static_cast<std::size_t>(n);
  }
  ::shutdown(fd, SHUT_WR);  // no more is coming: an unfinished request ends now, not at the deadline
  std::string answer;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (;;) {
    if (std::chrono::steady_clock::now() > deadline) std::abort();  // neither answered nor closed
    pollfd entry{fd, POLLIN, 0};
    if (::poll(&entry, 1, 100) <= 0) continue;
    char buffer[4096];
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    answer.append(buffer, static_cast<std::size_t>(n));
    // A stream never ends by itself: its head is the answer.
    if (answer.find("text/event-stream") != std::string::npos) break;
  }
  ::close(fd);
  if (!answer.empty() && answer.rfind("HTTP/1.", 0) != 0) std::abort();
  return 0;
}
