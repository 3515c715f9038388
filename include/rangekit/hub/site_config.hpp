// The site file of `rangekit serve --config site.toml`: a site's sensors, their ports and
// what the service does with each at start. Checked without opening anything, so `--check`
// and the service refuse the same files with the same messages.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/serial_port.hpp"

namespace rangekit::hub {

// One sensor of the site (a `[[sensor]]` table).
struct SensorConfig {
  std::string name;            // unique, used in URLs and topics: [A-Za-z0-9_-]{1,64}
  std::string family;          // a registered service family (service_family.hpp): "uls"
  std::string port;            // serial port or pty path; empty for an LS5 heard over UDP only
  SerialSettings serial;       // baud and byte format ("8N1"; the ULS has only 8N1, §9)
  std::optional<int> address;  // the unit's address on its port, in the family's range
  std::string udp;             // "HOST:PORT" the service listens on for its packets, where the family has it
  bool stream = true;          // stream from start
  bool capture = false;        // capture from start (into the service's capture folder)
  // Quality (docs/reliability.md): the fastest its target moves (m/s; nullopt = the family
  // default of core/sample_quality.hpp), and whether suspect samples are left out.
  std::optional<double> max_speed_mps;
  bool drop_suspect = false;
  std::optional<int> modbus_unit;  // its unit id on the Modbus face (1-247); none: its position from 1
  std::size_t line = 0;            // where it was declared, for later messages
};

struct ServiceConfig {
  std::string listen = "127.0.0.1:8080";
  std::string token_file;  // for a non-loopback listen address; default beside the site file
  std::string capture_dir = "captures";
  std::size_t max_captures = 16;  // running at once
  std::string tls_certificate;    // both or neither
  std::string tls_key;
};

// The `[mqtt]` table: the broker the MQTT face publishes every sensor to (docs/mqtt.md).
// Only settings live here; the hub itself speaks no MQTT.
struct MqttConfig {
  std::string broker;  // mqtt://HOST[:1883] or mqtts://HOST[:8883]; empty: no MQTT
  std::string client_id = "rangekit";
  std::string base_topic = "rangekit";
  std::string username;
  std::string password;           // inline: load_site_config refuses a file group or others may read
  std::size_t password_line = 0;  // where it was given
  std::string ca_file;            // mqtts: the CA that signed the broker's certificate (system store when empty)
  int qos_reading = 0;            // reading messages
  int qos_state = 1;              // status, availability, discovery (all retained)
  int qos_command = 1;            // set/action subscriptions and their results
  double max_rate_hz =
      10;  // reading messages a second per sensor; above it, one window message each 1/rate s; 0: every sample
  bool discovery = true;  // Home Assistant discovery under discovery_prefix
  std::string discovery_prefix = "homeassistant";
  std::size_t queue_limit = 10000;  // messages held per sensor while the broker is away; the oldest go first
  int reconnect_max_s = 30;         // reconnect backoff doubles from 1 s up to this; also the retry after a refusal
  // QoS >= 1 readings wait on disk until the broker acknowledged them, instead of queue_limit
  // in memory (docs/mqtt.md, "Store and forward"); the oldest go past spool_max_mb per sensor.
  bool spool = false;
  std::size_t spool_max_mb = 1024;
  std::size_t line = 0;  // where [mqtt] was declared
};

// The `[modbus]` table: the Modbus TCP face (docs/modbus.md). Only settings live here.
inline constexpr const char* default_modbus_listen = "127.0.0.1:5020";
struct ModbusConfig {
  std::string listen;  // HOST:PORT; empty: no Modbus face (a [modbus] table without it: default_modbus_listen)
  std::string word_order = "ABCD";
  bool writable = false;           // the command register
  std::vector<std::string> allow;  // IPv4 addresses or ranges that may connect besides loopback
  std::size_t line = 0;            // where [modbus] was declared
};
// The word orders of [modbus] word_order, for the check and its message.
inline constexpr std::array<std::string_view, 4> modbus_word_orders{"ABCD", "CDAB", "BADC", "DCBA"};

// One `[[sink]]` table: a historian every reading is written to, through a spool on disk
// (docs/sinks.md). Only settings live here; the hub speaks no historian's protocol.
struct SinkConfig {
  std::string kind;                  // one of sink_kinds
  std::string url;                   // influx: http://HOST:PORT/PATH; postgres: postgresql://USER@HOST:PORT/DB
  std::vector<std::string> sensors;  // names of the site's sensors; empty: all
  double max_rate_hz = 0;            // readings a second per sensor; 0: every sample
  std::size_t spool_max_mb = 1024;   // past it the oldest spooled readings are dropped
  std::size_t drain_rate = 20000;    // spooled rows sent a second, at most
  std::string table = "readings";    // postgres: the table the rows go to (valid_sql_identifier)
  // postgres: where the password is; never in the spool's name or a message. The file's path
  // is made absolute from the site file's folder when read.
  std::string password_file;
  std::string password_env;  // the name of an environment variable holding it
  std::size_t line = 0;      // where [[sink]] was declared
};
// The kinds of [[sink]] kind, for the check and its message.
inline constexpr std::array<std::string_view, 2> sink_kinds{"influx", "postgres"};

// A table name the postgres sink can use as it is: a letter or underscore, then letters,
// digits or underscores, at most 63 bytes (PostgreSQL's NAMEDATALEN - 1). Always quoted in SQL.
bool valid_sql_identifier(std::string_view name);
// A postgresql:// or postgres:// URL that names a host; the error's message shows no password.
Status check_postgres_url(std::string_view url);

// An http:// URL taken apart (no TLS, no credentials in it).
struct HttpUrl {
  std::string host;
  std::uint16_t port = 80;
  std::string path = "/";
};
Result<HttpUrl> parse_http_url(std::string_view url);

// A broker URL taken apart: mqtt://host:port or mqtts://host:port.
struct BrokerAddress {
  bool tls = false;
  std::string host;
  std::uint16_t port = 1883;
};
Result<BrokerAddress> parse_broker_url(std::string_view url);

struct SiteConfig {
  std::string file;  // as given, for messages
  ServiceConfig service;
  MqttConfig mqtt;
  ModbusConfig modbus;
  std::vector<SensorConfig> sensors;
  std::vector<SinkConfig> sinks;
};

// Each sensor's Modbus unit id: its modbus_unit, else its position in the file from 1 (up to 247).
std::vector<std::pair<std::uint8_t, std::string>> modbus_units(const SiteConfig& site);

// The sensors sharing one serial port: one sensor alone, or several of a family that has a
// bus (each with its own address).
struct PortGroup {
  std::string port;
  SerialSettings serial;
  std::string family;
  std::vector<const SensorConfig*> sensors;
  // Several units share the port, or one of a family that has buses is addressed on it.
  [[nodiscard]] bool bus() const noexcept;
};
std::vector<PortGroup> port_groups(const SiteConfig& site);

// Parses and checks the text; errors are Errc::invalid_frame (syntax, unknown
// keys, wrong types) or Errc::out_of_range (values), each "FILE:LINE: reason". Every
// mistake is reported, one line each (the first one's code for all).
Result<SiteConfig> parse_site_config(std::string_view text, std::string_view file_name);
// Reads the file first; an unreadable file is Errc::io naming it, and so is an inline
// [mqtt] password in a file group or others may read ("FILE:LINE: ... chmod 600 FILE").
Result<SiteConfig> load_site_config(const std::string& path);

}  // namespace rangekit::hub
