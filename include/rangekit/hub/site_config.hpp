// The site file `rangekit serve --config site.toml` reads: which sensors a site
// has, on which ports, and what the service does with each at start. Parsed and
// checked without opening anything, so `rangekit serve --check` and the service
// refuse the same files with the same messages (file:line: reason).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/serial_port.hpp"

namespace rangekit::hub {

enum class Family : std::uint8_t { uls, ls5 };
const char* family_name(Family family) noexcept;

// One sensor of the site (a `[[sensor]]` table).
struct SensorConfig {
  std::string name;  // unique, used in URLs and topics: [A-Za-z0-9_-]{1,64}
  Family family = Family::uls;
  std::string port;            // serial port or pty path; empty for an LS5 heard over UDP only
  SerialSettings serial;       // baud and byte format ("8N1"; the ULS has only 8N1, §9)
  std::optional<int> address;  // ULS RS-485 unit address 0x30-0xEF (§7); LS5 network address 1-255 (table 9.2 01)
  std::string udp;             // LS5 Ethernet: "HOST:PORT" the service listens on for its packets (§10)
  bool stream = true;          // stream from start
  bool capture = false;        // capture from start (into the service's capture folder)
  // Quality (issue 18 item 2): the fastest its target moves (m/s; nullopt = the family
  // default of core/sample_quality.hpp), and whether suspect samples are left out.
  std::optional<double> max_speed_mps;
  bool drop_suspect = false;
  std::size_t line = 0;  // where it was declared, for later messages
};

struct ServiceConfig {
  std::string listen = "127.0.0.1:8080";
  std::string token_file;  // for a non-loopback listen address; default beside the site file
  std::string capture_dir = "captures";
  std::string tls_certificate;  // both or neither
  std::string tls_key;
};

struct SiteConfig {
  std::string file;  // as given, for messages
  ServiceConfig service;
  std::vector<SensorConfig> sensors;
};

// The sensors sharing one serial port: one ULS alone, several ULS on an RS-485
// bus (each with its own address), or one LS5.
struct PortGroup {
  std::string port;
  SerialSettings serial;
  Family family = Family::uls;
  std::vector<const SensorConfig*> sensors;
  [[nodiscard]] bool bus() const noexcept { return sensors.size() > 1 || sensors.front()->address.has_value(); }
};
std::vector<PortGroup> port_groups(const SiteConfig& site);

// Parses and checks the text; errors are Errc::invalid_frame (syntax, unknown
// keys, wrong types) or Errc::out_of_range (values), each "FILE:LINE: reason".
Result<SiteConfig> parse_site_config(std::string_view text, std::string_view file_name);
// Reads the file first; an unreadable file is Errc::io naming it.
Result<SiteConfig> load_site_config(const std::string& path);

}  // namespace rangekit::hub
