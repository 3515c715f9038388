// The Modbus TCP face of the sensor hub (docs/modbus.md): each sensor of a site is a unit a
// PLC polls, its last reading and health in input registers, and with writes allowed a
// command register. It reaches the sensors only through hub::Hub.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/hub/hub.hpp"

namespace rangekit::modbus {

struct FaceOptions {
  std::string listen = "127.0.0.1:5020";  // HOST:PORT; port 0 picks a free one
  std::string word_order = "ABCD";        // of every 32-bit value: ABCD, CDAB, BADC or DCBA
  bool writable = false;                  // holding registers: the command register
  // Who may connect besides loopback: IPv4 addresses or ranges ("10.0.0.0/8"). Modbus has no
  // authentication, so listening beyond loopback needs at least one.
  std::vector<std::string> allow;
  // Unit id (1-247) and the sensor it reads.
  std::vector<std::pair<std::uint8_t, std::string>> units;
  std::size_t max_clients = 64;                   // connections at once; one more is closed at once
  std::chrono::milliseconds idle_timeout{60000};  // a connection that asks nothing this long is closed
  std::function<void(const std::string&)> log;    // one line per event worth telling
};

struct FaceStats {
  std::uint64_t clients = 0;     // connected now
  std::uint64_t requests = 0;    // answered since the start
  std::uint64_t exceptions = 0;  // of those, answered with an exception code
  std::uint64_t refused = 0;     // connections closed at once: not allowed, or over max_clients
  std::uint64_t malformed = 0;   // connections closed for bytes that are no Modbus TCP request
  std::uint64_t commands = 0;    // command codes written
};

class Face {
 public:
  // Binds, then serves on a thread of its own. A sensor the hub does not have, a unit id out
  // of 1-247 or used twice, a bad word order or address range are errors here.
  static Result<std::unique_ptr<Face>> start(hub::Hub& hub, FaceOptions options);
  ~Face();  // stop()
  Face(const Face&) = delete;
  Face& operator=(const Face&) = delete;
  // Closes the listener and every connection; a running command is waited for. Idempotent.
  void stop();
  [[nodiscard]] Endpoint local_endpoint() const;
  [[nodiscard]] FaceStats stats() const;

  struct Impl;

 private:
  explicit Face(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The register map of these units as CSV, for a PLC's tag import (`serve --modbus-map`).
Result<std::string> register_map_csv(const std::vector<std::pair<std::uint8_t, std::string>>& units,
                                     const std::string& word_order, bool writable);

}  // namespace rangekit::modbus
