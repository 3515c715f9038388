// The sensor hub under `rangekit serve`: one session per sensor of a site, one
// worker thread per port. A worker owns its port's driver (one ULS, an RS-485
// bus of ULS units, one LS5, or an LS5's UDP listener), reads or polls it, and
// runs the commands asked of its sensors in between, so commands and the stream
// never meet on the wire (ULS: stop, ask, restart; LS5: the stream is stopped
// first, since any byte would stop it). Samples and events are numbered, kept in
// each sensor's ring and handed to subscribers through bounded queues.
// The hub knows no HTTP or MQTT: those faces sit on top of it.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/transport.hpp"
#include "rangekit/hub/fanout.hpp"
#include "rangekit/hub/health.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::hub {

// One named value of a sensor's identity, status or settings, as read.
struct Field {
  std::string key;    // kebab-case ("short-gate", "serial-number")
  std::string value;  // as the CLI prints it ("10", "binning", "LS5.12.0")
  std::string unit;   // "m", "Hz", "mm", or empty
  friend bool operator==(const Field&, const Field&) = default;
};

struct SensorSnapshot {
  SensorConfig config;
  bool streaming = false;       // the service is reading measurements from it
  std::vector<Field> identity;  // ULS: ID; LS5: version, range, serial, Ethernet
  std::vector<Field> status;    // ULS: US decoded (§8 Get Unit Status)
  std::vector<Field> settings;  // as last read (empty until read)
  SensorHealth health;
  std::uint64_t last_sequence = 0;  // the newest item of this sensor
};

struct HubOptions {
  std::size_t ring_capacity = 4096;  // recent items kept per sensor
  std::chrono::milliseconds command_timeout{15000};
  std::chrono::milliseconds reconnect_interval{500};
  // How a worker opens its port; tests may hand in loopback transports.
  std::function<Result<TransportPtr>(const std::string& path, const SerialSettings& settings)> open_port;
};

// Settings by name, values as typed ("prf-hz" -> "2000"), in the order to write them.
using SettingValues = std::vector<std::pair<std::string, std::string>>;

// A unit a bus scan heard (ULS §7, `rangekit uls bus scan`).
struct BusUnitFound {
  std::uint8_t address = 0;  // 0x30..0xEF (§8 RS485 Protocol)
  std::string version;       // its ID
  bool duplicate = false;    // replies collided: two or more units hold this address (U66)
  std::string problem;
};

// A scan of the bus a sensor is on, and the site file's sensors on that port.
struct BusScan {
  std::string family;  // the sensors', for their addresses' text (bus_address_text)
  std::string port;
  std::size_t asked = 0;                                   // addresses asked
  std::vector<BusUnitFound> found;                         // those that answered, in the order asked
  std::vector<std::pair<std::uint8_t, std::string>> site;  // address, sensor: the site file's units on the port
};

// A bus address as the family writes it ('A' on a ULS bus, §7), and such text read back
// (nullopt when it is none of the family's): the faces need no family header of their own.
std::string bus_address_text(std::string_view family, std::uint8_t address);
std::optional<std::uint8_t> parse_bus_address(std::string_view family, std::string_view text);
// What a bus address of the family looks like, for messages: "0x30..0xEF, e.g. 'E'".
std::string bus_address_help(std::string_view family);

// An action a sensor takes (POST …/actions/{action}, MQTT …/action): start, stop and read for
// every family, then the family's own (ServiceFamily::actions), each with the arguments it takes.
struct ActionDescriptor {
  std::string_view name;
  std::string_view description;
  std::span<const std::string_view> arguments;  // the values its argument takes; empty: none
  bool argument_optional = false;               // it may also be given none
};
// The actions of a sensor of `family`, the shared ones first; the shared ones alone for a
// family the service does not run.
std::vector<const ActionDescriptor*> actions_of(std::string_view family);
const ActionDescriptor* find_action(std::string_view family, std::string_view name);
// Their names for messages: "start, stop, read, single, pointer, save, reset".
std::string action_names(std::string_view family);
// The refusal of a name that is none of them, naming the sensor and the actions it has.
std::string not_an_action(std::string_view family, std::string_view sensor, std::string_view action);
// `argument` as the action takes it; Errc::out_of_range naming the values it takes.
Status check_argument(const ActionDescriptor& action, std::string_view argument);

// What an action answers: a line for a person, and the measurement it made (single, latch),
// whose reading the faces give as a value with its unit.
struct ActionResult {
  std::string text;  // "25.3 mm (code 31629)"; empty when there is nothing to say
  std::optional<Sample> sample;
};

class Hub {
 public:
  // Starts one worker per port. A sensor whose port cannot be opened is
  // reported disconnected and retried; it does not stop the others.
  static std::unique_ptr<Hub> start(const SiteConfig& site, HubOptions options = {});
  ~Hub();  // stop()
  Hub(const Hub&) = delete;
  Hub& operator=(const Hub&) = delete;
  // Stops every worker: streams stopped as found, ports closed. Idempotent.
  void stop();

  [[nodiscard]] std::vector<std::string> sensor_names() const;
  [[nodiscard]] Result<SensorSnapshot> sensor(std::string_view name) const;
  [[nodiscard]] std::vector<SensorSnapshot> sensors() const;

  // Live items of one sensor, or of all when `sensor` is empty.
  Result<SubscriptionPtr> subscribe(std::string_view sensor, std::size_t capacity, OverflowPolicy policy);
  // One queue for the items of several sensors (none named: every sensor's).
  Result<SubscriptionPtr> subscribe(std::vector<std::string> sensors, std::size_t capacity, OverflowPolicy policy);
  // Items after `after` still in the ring (one sensor, or all merged in order when empty).
  Result<SampleRing::Since> since(std::string_view sensor, std::uint64_t after) const;
  Result<std::vector<HubItemPtr>> latest(std::string_view sensor, std::size_t count) const;
  [[nodiscard]] std::uint64_t last_sequence() const;
  [[nodiscard]] std::uint64_t subscribers_cut_off() const;

  // Validated against the family's tables before anything is sent; written,
  // read back and compared. Returns the settings as read back.
  Result<std::vector<Field>> set(std::string_view sensor,
                                 const std::vector<std::pair<std::string, std::string>>& values);
  Result<std::vector<Field>> settings(std::string_view sensor);  // read now
  // The sensor's settings as the configuration file `rangekit uls|ls5 config save` writes
  // (the Interface Program's saved file, §2 File Menu), read from the sensor now.
  Result<std::string> export_config(std::string_view sensor);
  // Such a file uploaded: every value checked first, written, read back and verified
  // (`config load`). Returns the settings as read back.
  Result<std::vector<Field>> import_config(std::string_view sensor, std::string_view toml);
  // The RS-485 network (§7) of a ULS on a bus: the addresses of §8's UA table (0-9, A-Z,
  // a-z) asked a few at a time between two polls. Errc::unsupported for a sensor alone on its port.
  Result<BusScan> scan_bus(std::string_view sensor);
  // UA on `sensor`'s bus: the unit at `from` (none: `sensor`'s address) takes `to`, refused when
  // a unit answers at `to` or none at `from` (`rangekit uls bus assign`). The site file is not
  // changed: `sensor` keeps its address, so it answers no more until the site file follows or
  // the unit is assigned back (U106).
  Status assign_address(std::string_view sensor, std::optional<std::uint8_t> from, std::uint8_t to);
  // The action's result text ("10.123 m" for single, "" otherwise).
  Result<ActionResult> act(std::string_view sensor, std::string_view action, std::string_view argument = {});

 private:
  struct Impl;
  explicit Hub(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rangekit::hub
