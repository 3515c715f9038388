// site.toml: parsed with toml++ (private), every key checked against the rows
// below so an unknown or misspelt key stops the service before it opens a port.
#include "rangekit/hub/site_config.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <map>

#include "core/toml.hpp"  // private: toml++ is no part of the public API
#include "rangekit/core/address_range.hpp"
#include "rangekit/core/text.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/hub/service_family.hpp"
#include "rangekit/hub/sink_url.hpp"

namespace rangekit::hub {
namespace {

// The mistakes of a site file, gathered so that one run reports them all, in file order:
// one line each, the first one's error code for the whole.
class Mistakes {
 public:
  void add(Status status) {
    if (!status) errors_.push_back(std::move(status).error());
  }
  void add(Error error) { errors_.push_back(std::move(error)); }
  [[nodiscard]] Status status() const {
    if (errors_.empty()) return ok_status();
    Error all = errors_.front();
    for (std::size_t i = 1; i < errors_.size(); ++i) all.message += "\n" + errors_[i].message;
    return all;
  }

 private:
  std::vector<Error> errors_;
};

Error at(std::string_view file, const toml::node& node, Errc code, const std::string& what) {
  return make_error(code, toml_place(file, node) + ": " + what);
}

bool valid_name(std::string_view name) {
  if (name.empty() || name.size() > 64) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return text::is_letter(c) || text::is_digit(c) || c == '-' || c == '_'; });
}

// The keys a table may hold; anything else is refused naming the allowed ones.
Status only_keys(std::string_view file, const toml::table& table, std::string_view where,
                 std::initializer_list<std::string_view> allowed) {
  if (const auto unknown = first_unknown_key(table, allowed)) {
    std::string list;
    for (std::string_view name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
    return at(file, *unknown->node, Errc::invalid_frame,
              "unknown key '" + std::string(unknown->key) + "' in " + std::string(where) + " (allowed: " + list + ")");
  }
  return ok_status();
}

Result<std::string> text_of(std::string_view file, const toml::node& node, std::string_view key) {
  const auto* value = node.as_string();
  if (value == nullptr) return at(file, node, Errc::invalid_frame, std::string(key) + " must be a string");
  return value->get();
}

Result<bool> flag_of(std::string_view file, const toml::node& node, std::string_view key) {
  const auto* value = node.as_boolean();
  if (value == nullptr) return at(file, node, Errc::invalid_frame, std::string(key) + " must be true or false");
  return value->get();
}

Result<std::int64_t> integer_of(std::string_view file, const toml::node& node, std::string_view key) {
  const auto* value = node.as_integer();
  if (value == nullptr) return at(file, node, Errc::invalid_frame, std::string(key) + " must be an integer");
  return value->get();
}

// An integer from `lowest` to `highest`; out of range: "key = N: <range>".
Result<std::int64_t> integer_in(std::string_view file, const toml::node& node, std::string_view key,
                                std::int64_t lowest, std::int64_t highest, std::string_view range) {
  auto value = integer_of(file, node, key);
  if (!value) return value;
  if (*value < lowest || *value > highest) {
    return at(file, node, Errc::out_of_range,
              std::string(key) + " = " + std::to_string(*value) + ": " + std::string(range));
  }
  return value;
}

// "LS5 Ethernet models": the families heard over UDP, for the message to one that is not.
std::string udp_models() {
  std::string models;
  for (const ServiceFamily* family : service_families()) {
    if (!family->udp) continue;
    models += (models.empty() ? "" : " and ") + std::string(family->model);
  }
  return models + " Ethernet models";
}

// The family reads its own addresses: a text or a number, in its range.
Result<int> address_of(std::string_view file, const toml::node& node, const ServiceFamily& family) {
  AddressValue value;
  if (const auto* number = node.as_integer()) {
    value.number = number->get();
  } else if (const auto* string = node.as_string()) {
    value.text = string->get();
  }
  auto address = family.parse_address(value);
  if (!address) return at(file, node, address.error().code, address.error().message);
  return address;
}

Result<SerialSettings> byte_format_of(std::string_view file, const toml::node& node, const ServiceFamily& family,
                                      SerialSettings settings) {
  auto text = text_of(file, node, "format");
  if (!text) return std::move(text).error();
  auto format = family.byte_format(*text, settings);
  if (!format) return at(file, node, format.error().code, format.error().message);
  return format;
}

// One key of a [[sensor]] table, once the family is known.
Status read_sensor_key(std::string_view file, std::string_view k, const toml::node& node, const ServiceFamily& family,
                       SensorConfig& sensor) {
  if (k == "port") {
    auto port = text_of(file, node, k);
    if (!port) return std::move(port).error();
    if (port->empty()) return at(file, node, Errc::out_of_range, "port must not be empty");
    sensor.port = *port;
  } else if (k == "baud") {
    auto baud = integer_of(file, node, k);
    if (!baud) return std::move(baud).error();
    const auto bauds = family.bauds();
    if (std::find(bauds.begin(), bauds.end(), *baud) == bauds.end()) {
      std::string listed;
      for (const std::uint32_t choice : bauds) listed += (listed.empty() ? "" : ", ") + std::to_string(choice);
      return at(
          file, node, Errc::out_of_range,
          "baud " + std::to_string(*baud) + " is not a baud of the " + std::string(family.model) + " (" + listed + ")");
    }
    sensor.serial.baud = static_cast<std::uint32_t>(*baud);
  } else if (k == "address") {
    auto address = address_of(file, node, family);
    if (!address) return std::move(address).error();
    sensor.address = *address;
  } else if (k == "udp") {
    if (!family.udp) return at(file, node, Errc::invalid_frame, "udp is for " + udp_models() + " only");
    auto udp = text_of(file, node, k);
    if (!udp) return std::move(udp).error();
    if (auto endpoint = parse_endpoint(*udp); !endpoint) {
      return at(file, node, Errc::out_of_range, "udp '" + *udp + "': " + endpoint.error().message);
    }
    sensor.udp = *udp;
  } else if (k == "stream" || k == "capture" || k == "drop_suspect") {
    auto on = flag_of(file, node, k);
    if (!on) return std::move(on).error();
    (k == "stream" ? sensor.stream : k == "capture" ? sensor.capture : sensor.drop_suspect) = *on;
  } else if (k == "max_speed") {
    const auto speed = node.value<double>();  // an integer reads as a double too
    if (!speed) return at(file, node, Errc::invalid_frame, "max_speed must be a number (metres per second)");
    if (!(*speed > 0) || *speed > 1e6) {
      return at(file, node, Errc::out_of_range, "max_speed must be above 0 and at most 1e6 m/s");
    }
    sensor.max_speed_mps = *speed;
  } else if (k == "modbus_unit") {
    auto unit = integer_in(file, node, k, 1, 247, "a Modbus unit id is 1 to 247");
    if (!unit) return std::move(unit).error();
    sensor.modbus_unit = static_cast<int>(*unit);
  }
  return ok_status();
}

// The sensor as far as it reads, its mistakes added to `found`; an error when it has no name
// or family, without which nothing else of it can be checked.
Result<SensorConfig> sensor_from(std::string_view file, const toml::table& table, Mistakes& found) {
  SensorConfig sensor;
  sensor.line = table.source().begin.line;
  found.add(only_keys(file, table, "[[sensor]]",
                      {"name", "family", "port", "baud", "format", "address", "udp", "stream", "capture", "max_speed",
                       "drop_suspect", "modbus_unit"}));
  const toml::node* name = table.get("name");
  if (name == nullptr)
    return make_error(Errc::invalid_frame,
                      std::string(file) + ":" + std::to_string(sensor.line) + ": [[sensor]] needs a name");
  auto name_text = text_of(file, *name, "name");
  if (!name_text) return std::move(name_text).error();
  if (!valid_name(*name_text)) {
    return at(file, *name, Errc::out_of_range,
              "name '" + *name_text + "' must be 1-64 letters, digits, '-' or '_' (it goes into URLs and topics)");
  }
  sensor.name = *name_text;
  const toml::node* family_node = table.get("family");
  if (family_node == nullptr) {
    return at(file, *name, Errc::invalid_frame,
              "sensor '" + sensor.name + "' needs a family (" + service_family_names() + ")");
  }
  auto family_text = text_of(file, *family_node, "family");
  if (!family_text) return std::move(family_text).error();
  const ServiceFamily* family = find_service_family(*family_text);
  if (family == nullptr) {
    return at(file, *family_node, Errc::out_of_range, "family '" + *family_text + "' is not " + service_family_names());
  }
  sensor.family = *family_text;
  // Every key is read, in the file's order, and every mistake reported, before the sensor is refused.
  Mistakes mistakes;
  std::vector<std::pair<std::string_view, const toml::node*>> keys;
  for (const auto& [key, node] : table) keys.emplace_back(key.str(), &node);
  std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
    return a.second->source().begin.line < b.second->source().begin.line;
  });
  for (const auto& [key, node] : keys) mistakes.add(read_sensor_key(file, key, *node, *family, sensor));
  // The byte format last: it needs the family, and keeps the baud read above.
  if (const toml::node* format = table.get("format")) {
    auto settings = byte_format_of(file, *format, *family, sensor.serial);
    if (settings) {
      sensor.serial = *settings;
    } else {
      mistakes.add(std::move(settings).error());
    }
  }
  if (!sensor.port.empty() && !sensor.udp.empty()) {
    mistakes.add(at(file, *name, Errc::invalid_frame,
                    "sensor '" + sensor.name +
                        "' has both a port and udp: give one (serial stream and commands, or the "
                        "Ethernet stream alone)"));
  }
  if (sensor.port.empty() && sensor.udp.empty()) {
    mistakes.add(at(file, *name, Errc::invalid_frame,
                    "sensor '" + sensor.name + "' needs a port" + (family->udp ? " or udp" : "")));
  }
  found.add(mistakes.status());
  return sensor;
}

Status check_service(std::string_view file, const toml::table& table, ServiceConfig& service) {
  if (auto checked = only_keys(file, table, "[service]",
                               {"listen", "token_file", "capture_dir", "max_captures", "tls_certificate", "tls_key"});
      !checked) {
    return checked;
  }
  for (const auto& [key, node] : table) {
    const std::string_view k = key.str();
    if (k == "max_captures") {
      auto count = integer_in(file, node, k, 1, 1024, "captures running at once, 1 to 1024");
      if (!count) return std::move(count).error();
      service.max_captures = static_cast<std::size_t>(*count);
      continue;
    }
    auto text = text_of(file, node, key.str());
    if (!text) return std::move(text).error();
    if (k == "listen") {
      if (auto endpoint = parse_endpoint(*text); !endpoint) {
        return at(file, node, Errc::out_of_range, "listen '" + *text + "': " + endpoint.error().message);
      }
      service.listen = *text;
    } else if (k == "token_file") {
      service.token_file = *text;
    } else if (k == "capture_dir") {
      service.capture_dir = *text;
    } else if (k == "tls_certificate") {
      service.tls_certificate = *text;
    } else {
      service.tls_key = *text;
    }
  }
  if (service.tls_certificate.empty() != service.tls_key.empty()) {
    return at(file, table, Errc::invalid_frame, "[service] needs both tls_certificate and tls_key, or neither");
  }
  return ok_status();
}

Status check_modbus(std::string_view file, const toml::table& table, ModbusConfig& modbus) {
  modbus.line = table.source().begin.line;
  modbus.listen = default_modbus_listen;  // the table turns the face on, on loopback unless it says
  if (auto checked = only_keys(file, table, "[modbus]", {"listen", "word_order", "writable", "allow"}); !checked) {
    return checked;
  }
  Mistakes mistakes;
  for (const auto& [key, node] : table) {
    const std::string_view k = key.str();
    if (k == "writable") {
      auto flag = flag_of(file, node, k);
      if (!flag) return std::move(flag).error();
      modbus.writable = *flag;
    } else if (k == "allow") {
      const auto* list = node.as_array();
      if (list == nullptr) return at(file, node, Errc::invalid_frame, "allow must be a list: [\"10.0.0.0/8\"]");
      for (const toml::node& each : *list) {
        auto text = text_of(file, each, "each of allow");
        if (!text) return std::move(text).error();
        if (auto range = parse_address_range(*text); !range) {
          mistakes.add(at(file, each, Errc::out_of_range, "allow " + range.error().message));
        }
        modbus.allow.push_back(*text);
      }
    } else {
      auto text = text_of(file, node, k);
      if (!text) return std::move(text).error();
      if (k == "listen") {
        if (auto endpoint = parse_endpoint(*text); !endpoint) {
          return at(file, node, Errc::out_of_range, "listen '" + *text + "': " + endpoint.error().message);
        }
        modbus.listen = *text;
      } else {
        std::string upper = *text;
        std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
        if (std::find(modbus_word_orders.begin(), modbus_word_orders.end(), upper) == modbus_word_orders.end()) {
          return at(file, node, Errc::out_of_range,
                    "word_order '" + *text + "' is not ABCD, CDAB, BADC or DCBA (A: the most significant byte)");
        }
        modbus.word_order = upper;
      }
    }
  }
  return mistakes.status();
}

Status check_qos(std::string_view file, const toml::node& node, std::string_view key, int& qos) {
  auto value = integer_in(file, node, key, 0, 2, "a QoS is 0, 1 or 2");
  if (!value) return std::move(value).error();
  qos = static_cast<int>(*value);
  return ok_status();
}

// Topic levels the service builds on: no wildcards, no empty level, no leading or trailing '/'.
bool valid_topic_base(std::string_view base) {
  if (base.empty() || base.size() > 256 || base.front() == '/' || base.back() == '/') return false;
  if (base.find("//") != std::string_view::npos) return false;
  return base.find_first_of("#+") == std::string_view::npos;
}

Status check_mqtt(std::string_view file, const toml::table& table, MqttConfig& mqtt) {
  mqtt.line = table.source().begin.line;
  if (auto checked = only_keys(file, table, "[mqtt]",
                               {"broker", "client_id", "base_topic", "username", "password", "ca_file", "qos_reading",
                                "qos_state", "qos_command", "max_rate_hz", "discovery", "discovery_prefix",
                                "queue_limit", "reconnect_max_s", "spool", "spool_max_mb"});
      !checked) {
    return checked;
  }
  for (const auto& [key, node] : table) {
    const std::string_view k = key.str();
    Status checked = ok_status();
    if (k == "qos_reading") {
      checked = check_qos(file, node, k, mqtt.qos_reading);
    } else if (k == "qos_state") {
      checked = check_qos(file, node, k, mqtt.qos_state);
    } else if (k == "qos_command") {
      checked = check_qos(file, node, k, mqtt.qos_command);
    } else if (k == "discovery" || k == "spool") {
      auto flag = flag_of(file, node, k);
      if (!flag) return std::move(flag).error();
      (k == "spool" ? mqtt.spool : mqtt.discovery) = *flag;
    } else if (k == "spool_max_mb") {
      auto value = integer_in(file, node, k, 1, 1048576, "1 to 1048576 MB (1 TB)");
      if (!value) return std::move(value).error();
      mqtt.spool_max_mb = static_cast<std::size_t>(*value);
    } else if (k == "max_rate_hz") {
      const double* rate = nullptr;
      double value = 0;
      if (const auto* floating = node.as_floating_point()) {
        value = floating->get();
        rate = &value;
      } else if (const auto* integer = node.as_integer()) {
        value = static_cast<double>(integer->get());
        rate = &value;
      }
      if (rate == nullptr) return at(file, node, Errc::invalid_frame, "max_rate_hz must be a number");
      if (!(value >= 0 && value <= 10000)) {
        return at(file, node, Errc::out_of_range,
                  "max_rate_hz = " + std::to_string(value) + ": 0 (every sample) or up to 10000 messages a second");
      }
      mqtt.max_rate_hz = value;
    } else if (k == "reconnect_max_s") {
      auto value = integer_in(file, node, k, 1, 3600, "1 to 3600 seconds");
      if (!value) return std::move(value).error();
      mqtt.reconnect_max_s = static_cast<int>(*value);
    } else if (k == "queue_limit") {
      auto value = integer_in(file, node, k, 1, 10000000, "1 to 10000000 messages per sensor");
      if (!value) return std::move(value).error();
      mqtt.queue_limit = static_cast<std::size_t>(*value);
    } else {
      auto text = text_of(file, node, k);
      if (!text) return std::move(text).error();
      if (k == "broker") {
        if (auto address = parse_broker_url(*text); !address) {
          return at(file, node, Errc::out_of_range, address.error().message);
        }
        mqtt.broker = *text;
      } else if (k == "client_id") {
        if (text->empty() || text->size() > 64) {
          return at(file, node, Errc::out_of_range, "client_id: 1 to 64 characters");
        }
        mqtt.client_id = *text;
      } else if (k == "base_topic" || k == "discovery_prefix") {
        if (!valid_topic_base(*text)) {
          return at(file, node, Errc::out_of_range,
                    std::string(k) + " '" + *text +
                        "': topic levels without '+', '#', an empty level or a leading or trailing '/'");
        }
        (k == "base_topic" ? mqtt.base_topic : mqtt.discovery_prefix) = *text;
      } else if (k == "username") {
        mqtt.username = *text;
      } else if (k == "password") {
        mqtt.password = *text;
        mqtt.password_line = node.source().begin.line;
      } else {
        mqtt.ca_file = *text;
      }
    }
    if (!checked) return checked;
  }
  if (!mqtt.password.empty() && mqtt.username.empty()) {
    return at(file, table, Errc::invalid_frame, "[mqtt] password needs a username");
  }
  if (!mqtt.ca_file.empty() && !mqtt.broker.empty() && !parse_broker_url(mqtt.broker)->tls) {
    return at(file, table, Errc::invalid_frame, "[mqtt] ca_file needs an mqtts:// broker");
  }
  if (mqtt.spool && mqtt.qos_reading == 0) {
    return at(file, table, Errc::invalid_frame,
              "[mqtt] spool = true keeps each reading until the broker acknowledges it: it needs qos_reading = 1 "
              "or 2 (QoS 0 has no acknowledgement)");
  }
  return ok_status();
}

// A number of readings a second: 0 (every sample) up to 10000; an integer reads as one too.
Result<double> rate_of(std::string_view file, const toml::node& node, std::string_view key) {
  const auto rate = node.value<double>();
  if (!rate) return at(file, node, Errc::invalid_frame, std::string(key) + " must be a number");
  if (!(*rate >= 0 && *rate <= 10000)) {
    return at(file, node, Errc::out_of_range,
              std::string(key) + " = " + std::to_string(*rate) + ": 0 (every sample) or up to 10000 a second");
  }
  return *rate;
}

std::string sink_kind_list() {
  std::string list;
  for (std::string_view kind : sink_kinds) list += (list.empty() ? "" : ", ") + std::string(kind);
  return list;
}

// One [[sink]] table; the sensors it names must be the site's, so it is read after them.
Status check_sink(std::string_view file, const toml::table& table, const std::vector<SensorConfig>& site_sensors,
                  SinkConfig& sink) {
  sink.line = table.source().begin.line;
  if (auto checked = only_keys(file, table, "[[sink]]",
                               {"kind", "url", "sensors", "max_rate_hz", "spool_max_mb", "drain_rate", "table",
                                "password_file", "password_env"});
      !checked) {
    return checked;
  }
  Mistakes mistakes;
  // Checked once the kind is known, whatever the order of the keys.
  const toml::node* url_node = nullptr;
  std::vector<const toml::node*> postgres_only;
  for (const auto& [key, node] : table) {
    const std::string_view k = key.str();
    if (k == "kind" || k == "url") {
      auto text = text_of(file, node, k);
      if (!text) {
        mistakes.add(std::move(text).error());
      } else if (k == "kind") {
        if (std::find(sink_kinds.begin(), sink_kinds.end(), *text) == sink_kinds.end()) {
          mistakes.add(at(file, node, Errc::out_of_range,
                          "kind '" + *text + "' is not a sink kind (accepted: " + sink_kind_list() + ")"));
        }
        sink.kind = *text;
      } else {
        url_node = &node;
        sink.url = *text;
      }
    } else if (k == "table" || k == "password_file" || k == "password_env") {
      postgres_only.push_back(&node);
      auto text = text_of(file, node, k);
      if (!text) {
        mistakes.add(std::move(text).error());
      } else if (k == "table") {
        if (!valid_sql_identifier(*text)) {
          mistakes.add(at(
              file, node, Errc::out_of_range,
              "table '" + *text + "': a letter or '_', then letters, digits or '_', at most 63 (an SQL identifier)"));
        }
        sink.table = *text;
      } else if (text->empty()) {
        mistakes.add(at(file, node, Errc::out_of_range, std::string(k) + " is empty"));
      } else if (k == "password_env") {
        sink.password_env = *text;
      } else {
        // Beside the site file, as the service's other files.
        const std::filesystem::path path(*text);
        sink.password_file = path.is_absolute() ? *text : (std::filesystem::path(file).parent_path() / path).string();
      }
    } else if (k == "sensors") {
      const auto* list = node.as_array();
      if (list == nullptr) {
        mistakes.add(at(file, node, Errc::invalid_frame, "sensors must be a list of sensor names: [\"belt\"]"));
        continue;
      }
      for (const toml::node& each : *list) {
        auto name = text_of(file, each, "each of sensors");
        if (!name) {
          mistakes.add(std::move(name).error());
          continue;
        }
        const bool known = std::any_of(site_sensors.begin(), site_sensors.end(),
                                       [&](const SensorConfig& sensor) { return sensor.name == *name; });
        if (!known) {
          mistakes.add(at(file, each, Errc::out_of_range, "sensors: '" + *name + "' is no sensor of this site"));
        }
        sink.sensors.push_back(*name);
      }
    } else if (k == "max_rate_hz") {
      auto rate = rate_of(file, node, k);
      if (rate) {
        sink.max_rate_hz = *rate;
      } else {
        mistakes.add(std::move(rate).error());
      }
    } else {
      const bool spool = k == "spool_max_mb";
      auto value = spool ? integer_in(file, node, k, 1, 1048576, "1 to 1048576 MB (1 TB)")
                         : integer_in(file, node, k, 1, 10000000, "1 to 10000000 rows a second");
      if (!value) {
        mistakes.add(std::move(value).error());
        continue;
      }
      (spool ? sink.spool_max_mb : sink.drain_rate) = static_cast<std::size_t>(*value);
    }
  }
  if (sink.kind.empty())
    mistakes.add(at(file, table, Errc::invalid_frame, "[[sink]] needs a kind (" + sink_kind_list() + ")"));
  if (sink.url.empty()) mistakes.add(at(file, table, Errc::invalid_frame, "[[sink]] needs a url"));
  const bool postgres = sink.kind == "postgres";
  if (url_node != nullptr) {
    if (postgres) {
      if (auto url = check_postgres_url(sink.url); !url)
        mistakes.add(at(file, *url_node, Errc::out_of_range, url.error().message));
    } else if (auto url = parse_http_url(sink.url); !url) {
      mistakes.add(at(file, *url_node, Errc::out_of_range, url.error().message));
    }
  }
  if (!postgres && !sink.kind.empty()) {
    for (const toml::node* node : postgres_only) {
      mistakes.add(at(file, *node, Errc::invalid_frame, "table, password_file and password_env are for kind postgres"));
    }
  }
  if (!sink.password_file.empty() && !sink.password_env.empty()) {
    mistakes.add(at(file, table, Errc::invalid_frame, "[[sink]]: password_file or password_env, not both"));
  }
  return mistakes.status();
}

std::string line_of(const SensorConfig& sensor) { return "line " + std::to_string(sensor.line); }

// Several sensors on one port must agree on how the port is set up, and only
// addressed ULS units can share one (an RS-485 bus, §7).
// One more sensor on a port another already claimed: the same family, one that has buses,
// the same line settings, and its own address.
Status check_shared_port(const SiteConfig& site, const PortGroup& group, std::size_t i) {
  const SensorConfig& first = *group.sensors.front();
  const SensorConfig& other = *group.sensors[i];
  const std::string where = site.file + ":" + std::to_string(other.line) + ": ";
  const std::string clash = "port " + group.port + " is also claimed by '" + first.name + "' (" + line_of(first) + ")";
  if (other.family != first.family) {
    return make_error(Errc::invalid_frame, where + clash + " as " + first.family + ": one port carries one family");
  }
  if (const ServiceFamily* family = find_service_family(other.family); family != nullptr && !family->bus) {
    return make_error(Errc::invalid_frame, where + clash + ": " + std::string(family->one_per_port));
  }
  if (!(other.serial == first.serial)) {
    return make_error(Errc::invalid_frame, where + clash + " with other settings (" + describe(first.serial) +
                                               " there, " + describe(other.serial) + " here)");
  }
  if (!first.address || !other.address) {
    return make_error(Errc::invalid_frame, where + clash + ": units sharing an RS-485 port each need an address");
  }
  for (std::size_t j = 0; j < i; ++j) {
    if (group.sensors[j]->address == other.address) {
      return make_error(Errc::invalid_frame, where + "address of '" + other.name + "' is also the address of '" +
                                                 group.sensors[j]->name + "' (" + line_of(*group.sensors[j]) +
                                                 ") on port " + group.port + " (one unit per address)");
    }
  }
  return ok_status();
}

Status check_ports(const SiteConfig& site) {
  Mistakes mistakes;
  std::map<std::string, const SensorConfig*> names;
  std::map<std::string, const SensorConfig*> udp;
  for (const SensorConfig& sensor : site.sensors) {
    const std::string where = site.file + ":" + std::to_string(sensor.line) + ": ";
    if (auto [it, inserted] = names.emplace(sensor.name, &sensor); !inserted) {
      mistakes.add(make_error(Errc::invalid_frame,
                              where + "sensor name '" + sensor.name + "' is already used at " + line_of(*it->second)));
    }
    if (!sensor.udp.empty()) {
      if (auto [it, inserted] = udp.emplace(sensor.udp, &sensor); !inserted) {
        mistakes.add(make_error(Errc::invalid_frame, where + "udp " + sensor.udp + " is already the listener of '" +
                                                         it->second->name + "' (" + line_of(*it->second) + ")"));
      }
    }
  }
  for (const PortGroup& group : port_groups(site)) {
    for (std::size_t i = 1; i < group.sensors.size(); ++i) mistakes.add(check_shared_port(site, group, i));
  }
  // Unit ids, given or by position, name one sensor each.
  std::map<std::uint8_t, std::string> units;
  for (const auto& unit : modbus_units(site)) {
    if (auto [it, inserted] = units.emplace(unit); !inserted) {
      const auto sensor = std::find_if(site.sensors.begin(), site.sensors.end(),
                                       [&](const SensorConfig& each) { return each.name == unit.second; });
      mistakes.add(make_error(Errc::invalid_frame,
                              site.file + ":" + std::to_string(sensor->line) + ": Modbus unit " +
                                  std::to_string(unit.first) + " of '" + unit.second + "' is also the unit of '" +
                                  it->second + "' (a sensor without modbus_unit takes its position in the file)"));
    }
  }
  return mistakes.status();
}

}  // namespace

Result<HttpUrl> parse_http_url(std::string_view url) {
  const std::string given(url);
  if (url.rfind("http://", 0) != 0) {
    return make_error(Errc::out_of_range, "url '" + given + "': give http://HOST:PORT/PATH (https is not built)");
  }
  std::string_view rest = url.substr(7);
  HttpUrl parsed;
  const auto slash = rest.find('/');
  if (slash != std::string_view::npos) {
    parsed.path = std::string(rest.substr(slash));
    rest = rest.substr(0, slash);
  }
  if (rest.find('@') != std::string_view::npos) {
    return make_error(Errc::out_of_range, "url '" + given + "': no credentials in the URL");
  }
  const auto colon = rest.rfind(':');
  const std::string_view host = rest.substr(0, colon);
  if (colon != std::string_view::npos) {
    const std::string_view port = rest.substr(colon + 1);
    unsigned value = 0;
    const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (port.empty() || error != std::errc{} || end != port.data() + port.size() || value == 0 || value > 65535) {
      return make_error(Errc::out_of_range, "url '" + given + "': the port '" + std::string(port) + "' is not 1-65535");
    }
    parsed.port = static_cast<std::uint16_t>(value);
  }
  if (host.empty() || host.find_first_of(" ?#[]") != std::string_view::npos) {
    return make_error(Errc::out_of_range, "url '" + given + "': no host name in it");
  }
  if (parsed.path.find_first_of(" \r\n") != std::string::npos) {
    return make_error(Errc::out_of_range, "url '" + given + "': a path without spaces or line breaks");
  }
  parsed.host = std::string(host);
  return parsed;
}

bool valid_sql_identifier(std::string_view name) {
  const auto word = [](char c) { return c == '_' || std::isalnum(static_cast<unsigned char>(c)) != 0; };
  return !name.empty() && name.size() <= 63 && std::isdigit(static_cast<unsigned char>(name[0])) == 0 &&
         std::all_of(name.begin(), name.end(), [&](char c) { return static_cast<unsigned char>(c) < 0x80 && word(c); });
}

Status check_postgres_url(std::string_view url) {
  const std::string shown = redacted_url(url);
  std::string_view rest;
  if (url.rfind("postgresql://", 0) == 0) {
    rest = url.substr(13);
  } else if (url.rfind("postgres://", 0) == 0) {
    rest = url.substr(11);
  } else {
    return make_error(Errc::out_of_range, "url '" + shown + "': give postgresql://USER@HOST[:PORT]/DATABASE");
  }
  rest = rest.substr(0, std::min(rest.find_first_of("/?"), rest.size()));
  if (const auto at = rest.rfind('@'); at != std::string_view::npos) rest.remove_prefix(at + 1);
  const auto colon = rest.rfind(':');
  const bool bracketed = !rest.empty() && rest.front() == '[';  // [::1]:5432
  const std::string_view host =
      colon != std::string_view::npos && (!bracketed || colon > rest.find(']')) ? rest.substr(0, colon) : rest;
  if (host.empty()) return make_error(Errc::out_of_range, "url '" + shown + "': no host name in it");
  if (host.size() < rest.size()) {
    const std::string_view port = rest.substr(host.size() + 1);
    unsigned value = 0;
    const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (port.empty() || error != std::errc{} || end != port.data() + port.size() || value == 0 || value > 65535) {
      return make_error(Errc::out_of_range, "url '" + shown + "': the port '" + std::string(port) + "' is not 1-65535");
    }
  }
  return ok_status();
}

Result<BrokerAddress> parse_broker_url(std::string_view url) {
  BrokerAddress address;
  std::string_view rest;
  if (url.rfind("mqtt://", 0) == 0) {
    rest = url.substr(7);
  } else if (url.rfind("mqtts://", 0) == 0) {
    rest = url.substr(8);
    address.tls = true;
    address.port = 8883;
  } else {
    return make_error(Errc::out_of_range,
                      "broker '" + std::string(url) + "': give mqtt://HOST[:PORT] or mqtts://HOST[:PORT] (TLS)");
  }
  if (!rest.empty() && rest.back() == '/') rest.remove_suffix(1);
  const auto colon = rest.rfind(':');
  std::string_view host = rest.substr(0, colon);
  if (colon != std::string_view::npos) {
    const std::string_view port = rest.substr(colon + 1);
    unsigned value = 0;
    const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (port.empty() || error != std::errc{} || end != port.data() + port.size() || value == 0 || value > 65535) {
      return make_error(Errc::out_of_range,
                        "broker '" + std::string(url) + "': the port '" + std::string(port) + "' is not 1-65535");
    }
    address.port = static_cast<std::uint16_t>(value);
  }
  if (host.empty() || host.find_first_of("/@ ") != std::string_view::npos) {
    return make_error(Errc::out_of_range, "broker '" + std::string(url) + "': no host name in it");
  }
  address.host = std::string(host);
  return address;
}

std::vector<std::pair<std::uint8_t, std::string>> modbus_units(const SiteConfig& site) {
  std::vector<std::pair<std::uint8_t, std::string>> units;
  for (std::size_t at = 0; at < site.sensors.size(); ++at) {
    const SensorConfig& sensor = site.sensors[at];
    if (!sensor.modbus_unit && at + 1 > 247) continue;  // past the last unit id: none unless given
    units.emplace_back(static_cast<std::uint8_t>(sensor.modbus_unit.value_or(static_cast<int>(at + 1))), sensor.name);
  }
  return units;
}

bool PortGroup::bus() const noexcept {
  const ServiceFamily* described = find_service_family(family);
  return sensors.size() > 1 || (described != nullptr && described->bus && sensors.front()->address.has_value());
}

std::vector<PortGroup> port_groups(const SiteConfig& site) {
  std::vector<PortGroup> groups;
  for (const SensorConfig& sensor : site.sensors) {
    if (sensor.port.empty()) continue;
    auto found = std::find_if(groups.begin(), groups.end(), [&](const PortGroup& g) { return g.port == sensor.port; });
    if (found == groups.end()) {
      groups.push_back(PortGroup{sensor.port, sensor.serial, sensor.family, {&sensor}});
    } else {
      found->sensors.push_back(&sensor);
    }
  }
  return groups;
}

Result<SiteConfig> parse_site_config(std::string_view text, std::string_view file_name) {
  auto parsed = parse_toml(text, file_name);
  if (!parsed) return std::move(parsed).error();
  const toml::table& root = *parsed;
  SiteConfig site;
  site.file = std::string(file_name);
  if (auto checked = only_keys(file_name, root, "the site file", {"service", "mqtt", "modbus", "sensor", "sink"});
      !checked) {
    return std::move(checked).error();
  }
  Mistakes mistakes;
  if (const toml::node* service = root.get("service")) {
    const auto* table = service->as_table();
    if (table == nullptr) {
      mistakes.add(at(file_name, *service, Errc::invalid_frame, "service must be a table: [service]"));
    } else {
      mistakes.add(check_service(file_name, *table, site.service));
    }
  }
  if (const toml::node* mqtt = root.get("mqtt")) {
    const auto* table = mqtt->as_table();
    if (table == nullptr) {
      mistakes.add(at(file_name, *mqtt, Errc::invalid_frame, "mqtt must be a table: [mqtt]"));
    } else {
      mistakes.add(check_mqtt(file_name, *table, site.mqtt));
    }
  }
  if (const toml::node* modbus = root.get("modbus")) {
    const auto* table = modbus->as_table();
    if (table == nullptr) {
      mistakes.add(at(file_name, *modbus, Errc::invalid_frame, "modbus must be a table: [modbus]"));
    } else {
      mistakes.add(check_modbus(file_name, *table, site.modbus));
    }
  }
  const toml::node* sensors = root.get("sensor");
  const auto* array = sensors != nullptr ? sensors->as_array() : nullptr;
  if (sensors == nullptr) {
    mistakes.add(
        make_error(Errc::invalid_frame, std::string(file_name) + ": no sensors: add a [[sensor]] table for each"));
  } else if (array == nullptr || !array->is_array_of_tables()) {
    mistakes.add(at(file_name, *sensors, Errc::invalid_frame, "sensor must be an array of tables: [[sensor]]"));
  } else {
    for (const toml::node& node : *array) {
      // Kept with its mistakes too, so the checks across sensors (names, ports) see it.
      auto sensor = sensor_from(file_name, *node.as_table(), mistakes);
      if (sensor) {
        site.sensors.push_back(std::move(*sensor));
      } else {
        mistakes.add(std::move(sensor).error());
      }
    }
  }
  mistakes.add(check_ports(site));
  if (const toml::node* sinks = root.get("sink")) {
    const auto* list = sinks->as_array();
    if (list == nullptr || !list->is_array_of_tables()) {
      mistakes.add(at(file_name, *sinks, Errc::invalid_frame, "sink must be an array of tables: [[sink]]"));
    } else {
      for (const toml::node& node : *list) {
        SinkConfig sink;
        mistakes.add(check_sink(file_name, *node.as_table(), site.sensors, sink));
        site.sinks.push_back(std::move(sink));
      }
    }
  }
  if (auto found = mistakes.status(); !found) return std::move(found).error();
  return site;
}

Result<SiteConfig> load_site_config(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return make_error(Errc::io, "cannot read site file " + path);
  struct stat info {};
  std::string text;
  bool read_all = ::fstat(fd, &info) == 0;
  std::array<char, 8192> buffer{};
  while (read_all) {
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      read_all = got == 0;
      break;
    }
    text.append(buffer.data(), static_cast<std::size_t>(got));
  }
  ::close(fd);
  if (!read_all) return make_error(Errc::io, "cannot read site file " + path);
  auto site = parse_site_config(text, path);
  // The mode of the file read (fstat of its descriptor), not of whatever the path names now.
  if (site && !site->mqtt.password.empty() && (info.st_mode & (S_IRGRP | S_IROTH)) != 0) {
    std::array<char, 8> mode{};
    std::snprintf(mode.data(), mode.size(), "%04o", static_cast<unsigned>(info.st_mode & 07777));
    return make_error(Errc::io, path + ":" + std::to_string(site->mqtt.password_line) +
                                    ": [mqtt] password in a file group or others may read (mode " + mode.data() +
                                    "): chmod 600 " + path);
  }
  return site;
}

}  // namespace rangekit::hub
