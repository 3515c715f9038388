// A sensor family as the hub sees it: how its site-file entries read, the backends that run its
// ports, its settings schema and its bus addresses. Each family fills one in its own folder
// (src/<family>/service); the registration list adds it before main().
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/hub/backend.hpp"

namespace rangekit::hub {

// A site file's `address` as written: a number, a text, or neither (another TOML type).
struct AddressValue {
  std::optional<std::int64_t> number;
  std::optional<std::string> text;
};

struct ServiceFamily {
  std::string_view name;          // the site file's `family`, the samples' `device`
  std::string_view manufacturer;  // for MQTT discovery: "Laser Technology Inc."
  std::string_view model;         // "ULS"

  // Site file. A unit address (Errc::invalid_frame for a wrong type, out_of_range outside the
  // family's range), and a byte format ("8N1") on top of `settings`; messages without file:line.
  Result<int> (*parse_address)(const AddressValue& value) = nullptr;
  Result<SerialSettings> (*byte_format)(std::string_view format, SerialSettings settings) = nullptr;
  std::span<const std::uint32_t> (*bauds)() = nullptr;  // the line speeds it can be set to
  bool udp = false;                                     // may be heard on `udp = "HOST:PORT"` instead of a port
  bool bus = false;                                     // several addressed units may share one port (an RS-485 bus)
  std::string_view one_per_port;  // why not, when it is no bus: "an LS5 stream holds its line, ..."

  // The backend of one port's sensors (one, or a bus of them) and of a UDP listener.
  std::unique_ptr<Backend> (*port_backend)(std::vector<Session*> sessions, Publisher& publisher,
                                           const PortOpener& open) = nullptr;
  std::unique_ptr<Backend> (*udp_backend)(Session& session, Publisher& publisher) = nullptr;

  // A bus address's text read back ("A", "0x41"; the FamilyDescriptor writes it), and what a
  // bus scan asks.
  std::optional<std::uint8_t> (*parse_address_text)(std::string_view text) = nullptr;
  std::string_view address_help;  // "0x30..0xEF, e.g. 'E'"
  std::vector<std::uint8_t> (*scan_addresses)() = nullptr;

  // GET /api/sensors/{name}/settings/schema: every setting with its range, unit and values.
  nlohmann::json (*settings_schema)() = nullptr;
  // Its actions besides start, stop and read, with the arguments each takes.
  std::span<const ActionDescriptor> actions;
};

// Adds a family (a second of the same name replaces the first); from the registration list.
void register_service_family(const ServiceFamily& family);
std::span<const ServiceFamily* const> service_families() noexcept;
const ServiceFamily* find_service_family(std::string_view name) noexcept;
// The registered names for messages: "\"uls\" or \"ls5\"".
std::string service_family_names();

}  // namespace rangekit::hub
