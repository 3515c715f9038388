// A mosquitto of its own on a free loopback port: what `rangekit serve --demo` starts
// when no broker is given, and what the MQTT tests run against (a real broker, no mock).
// The broker runs as a child process with a generated configuration in `dir`. It gets
// SIGTERM when the thread that started (or restarted) it ends, the service crashing
// included: call start() and restart() from a thread that lives as long as the broker.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "rangekit/core/result.hpp"

namespace rangekit::mqtt {

struct LocalBrokerOptions {
  std::filesystem::path dir;  // its configuration and log go here (must exist)
  std::uint16_t port = 0;     // 0: a free one
  std::string password_file;  // mosquitto_passwd file: anonymous clients refused; empty: anonymous allowed
  std::string executable;     // empty: found on PATH or in /usr/sbin
  // mosquitto's max_packet_size: what any client may publish (the bridge takes commands of up
  // to 16 KiB). The bridge cannot announce a maximum of its own (docs/security.md); 0: none.
  std::uint32_t max_packet_size = 20 * 1024;
  std::string extra_config;  // lines appended to the generated mosquitto.conf (e.g. "max_packet_size 200\n")
};

class LocalBroker {
 public:
  // The mosquitto binary, or empty when none is installed.
  static std::string find_executable();
  // Starts it and waits until it accepts connections (bounded: 20 s).
  static Result<std::unique_ptr<LocalBroker>> start(LocalBrokerOptions options);
  ~LocalBroker();  // stop()
  LocalBroker(const LocalBroker&) = delete;
  LocalBroker& operator=(const LocalBroker&) = delete;

  [[nodiscard]] std::uint16_t port() const noexcept { return options_.port; }
  [[nodiscard]] std::string url() const { return "mqtt://127.0.0.1:" + std::to_string(options_.port); }
  [[nodiscard]] pid_t pid() const noexcept { return pid_; }
  [[nodiscard]] std::string log_path() const { return (options_.dir / "mosquitto.log").string(); }
  // kill -9: the broker vanishes without a word, as a crashed one does.
  void kill_hard();
  // Starts it again on the same port (after kill_hard or stop).
  Status restart();
  // SIGTERM, waited for. Idempotent.
  void stop();

 private:
  explicit LocalBroker(LocalBrokerOptions options) : options_(std::move(options)) {}
  Status launch();
  LocalBrokerOptions options_;
  pid_t pid_ = -1;
};

}  // namespace rangekit::mqtt
