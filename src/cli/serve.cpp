// `rangekit serve`: the sensor service (docs/service.md). `--check` validates a site file;
// `--config` keeps its sensors live through the hub with a summary line per sensor each
// second; `--demo` does the same for emulators it starts itself (cli/demo_site.hpp).
#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "cli/commands.hpp"
#include "cli/dashboard.hpp"
#include "cli/demo_site.hpp"
#include "cli/serve_monitor.hpp"
#include "cli/serve_sinks.hpp"
#include "cli/stop_signals.hpp"
#include "cli/systemd_notify.hpp"
#include "rangekit/core/descriptor_limit.hpp"
#include "rangekit/hub/captures.hpp"
#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/sink_url.hpp"
#include "rangekit/modbus/face.hpp"
#include "rangekit/mqtt/bridge.hpp"
#include "rangekit/mqtt/local_broker.hpp"
#include "rangekit/web/server.hpp"

namespace rangekit::cli {
namespace {

struct ServeOptions {
  std::string config;
  std::string check;
  bool demo = false;
  std::string listen;              // overrides [service] listen
  std::string mqtt;                // overrides [mqtt] broker
  std::string modbus;              // overrides [modbus] listen
  std::vector<std::string> sinks;  // --sink URLs: sinks of every sensor besides the [[sink]] tables
  bool modbus_map = false;         // print the register map of --config, --demo or --check's site and end
  double duration_s = 0;           // 0: until Ctrl-C or SIGTERM
  bool table = false;              // redraw the table each second even when stdout is no terminal
};

// One line per mistake, all of them (the site file's reader gathers every one).
int site_refused(const std::string& path, const Error& error) {
  std::size_t count = 0;
  std::string_view rest = error.message;
  while (!rest.empty()) {
    const auto end = rest.find('\n');
    fmt::print(stderr, "rangekit serve: {}\n", rest.substr(0, end));
    ++count;
    rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
  }
  if (count > 1) fmt::print(stderr, "rangekit serve: {} mistakes in {}\n", count, path);
  return error.code == Errc::io ? exit_io : exit_bad_input;
}

// "1 belt, 2 silo".
std::string modbus_unit_list(const hub::SiteConfig& site) {
  std::string list;
  for (const auto& [unit, sensor] : hub::modbus_units(site)) {
    list += (list.empty() ? "" : ", ") + std::to_string(unit) + " " + sensor;
  }
  return list;
}

int print_modbus_map(const hub::SiteConfig& site) {
  auto csv = modbus::register_map_csv(hub::modbus_units(site), site.modbus.word_order, site.modbus.writable);
  if (!csv) {
    fmt::print(stderr, "rangekit serve: {}\n", csv.error().message);
    return exit_bad_input;
  }
  fmt::print("{}", *csv);
  return exit_ok;
}

// The Modbus face, when the site file or --modbus asks for it.
Result<std::unique_ptr<modbus::Face>> start_modbus(hub::Hub& hub, const hub::SiteConfig& site,
                                                   const ServeOptions& options) {
  modbus::FaceOptions face_options;
  face_options.listen = options.modbus.empty() ? site.modbus.listen : options.modbus;
  if (face_options.listen.empty()) return std::unique_ptr<modbus::Face>();
  face_options.word_order = site.modbus.word_order;
  face_options.writable = site.modbus.writable;
  face_options.allow = site.modbus.allow;
  face_options.units = hub::modbus_units(site);
  face_options.log = [](const std::string& line) {
    fmt::print("{}\n", line);
    std::fflush(stdout);
  };
  return modbus::Face::start(hub, face_options);
}

int check_site(const std::string& path, const std::vector<std::string>& sink_urls) {
  auto site = hub::load_site_config(path);
  if (!site) return site_refused(path, site.error());
  auto sinks = sink_configs(*site, sink_urls);
  if (!sinks) {
    fmt::print(stderr, "rangekit serve: {}\n", sinks.error().message);
    return exit_bad_input;
  }
  fmt::print("{}: {} sensors on {} ports, listen {}\n", path, site->sensors.size(), hub::port_groups(*site).size(),
             site->service.listen);
  for (const hub::PortGroup& group : hub::port_groups(*site)) {
    fmt::print("  {} ({}{}):", group.port, describe(group.serial), group.bus() ? ", RS-485 bus" : "");
    for (const hub::SensorConfig* sensor : group.sensors) fmt::print(" {}", sensor->name);
    fmt::print("\n");
  }
  for (const hub::SensorConfig& sensor : site->sensors) {
    if (!sensor.udp.empty()) fmt::print("  udp {}: {}\n", sensor.udp, sensor.name);
  }
  if (!site->mqtt.broker.empty()) {
    const hub::MqttConfig& mqtt = site->mqtt;
    fmt::print("  mqtt {} as {}: {}/<sensor>/..., {}, discovery {}{}\n", mqtt.broker, mqtt.client_id, mqtt.base_topic,
               mqtt.max_rate_hz > 0 ? fmt::format("at most {} readings/s per sensor", mqtt.max_rate_hz)
                                    : std::string("every reading"),
               mqtt.discovery ? "under " + mqtt.discovery_prefix + "/" : std::string("off"),
               mqtt.spool ? fmt::format(", readings spooled on disk up to {} MB per sensor", mqtt.spool_max_mb)
                          : std::string());
  }
  if (!site->modbus.listen.empty()) {
    fmt::print("  modbus {}: units {}, word order {}, {}\n", site->modbus.listen, modbus_unit_list(*site),
               site->modbus.word_order, site->modbus.writable ? "writable" : "read only");
  }
  for (const hub::SinkConfig& sink : *sinks) fmt::print("  {}\n", sink_check_line(sink));
  return exit_ok;
}

std::string mqtt_summary(const mqtt::BridgeStats& stats) {
  return fmt::format("mqtt {}: {}, published {}, queued {}, dropped {}, reconnects {}, commands {}{}", stats.broker,
                     stats.connected ? "connected" : "not connected", stats.published, stats.queued, stats.dropped,
                     stats.reconnects, stats.commands, stats.error.empty() ? "" : "; " + stats.error);
}

// Beyond loopback every write and stream needs the token: made on the first start, kept with
// mode 0600 beside the site file or in systemd's state folder (or where [service] token_file
// says), printed once; not into the journal, which more users may read than the file.
Result<std::string> token_for(const hub::SiteConfig& site, const std::string& listen) {
  auto endpoint = parse_endpoint(listen);
  if (!endpoint) return make_error(Errc::out_of_range, "listen '" + listen + "': " + endpoint.error().message);
  if (web::is_loopback_host(endpoint->host)) return std::string();
  const std::string path =
      state_path(site.service.token_file.empty() ? "rangekit-token" : site.service.token_file, site.file);
  auto token = web::load_or_create_token(path);
  if (!token) return std::move(token).error();
  if (token->created && writes_to_journal(stdout)) {
    fmt::print("listening beyond loopback: every write and stream needs the token just made in {} (mode 0600)\n", path);
  } else if (token->created) {
    fmt::print("listening beyond loopback: every write and stream needs this token (kept in {}, shown once):\n  {}\n",
               path, token->value);
  } else {
    fmt::print("listening beyond loopback: writes and streams need the token kept in {}\n", path);
  }
  return token->value;
}

int serve_site(const hub::SiteConfig& site_config, const ServeOptions& options, const StopSignals& signals) {
  (void)raise_descriptor_limit();  // the HTTP limits then run out first
  const hub::SiteConfig* site = &site_config;
  web::ServerOptions server_options;
  server_options.listen = options.listen.empty() ? site->service.listen : options.listen;
  auto token = token_for(*site, server_options.listen);
  if (!token) {
    fmt::print(stderr, "rangekit serve: {}\n", token.error().message);
    return exit_code_for(token.error());
  }
  server_options.token = *token;
  // TLS files, like the capture folder, are found from the site file's folder.
  const auto beside_site = [&](const std::string& path) {
    if (path.empty() || std::filesystem::path(path).is_absolute() || site->file.empty()) return path;
    return (std::filesystem::path(site->file).parent_path() / path).string();
  };
  server_options.tls_certificate = beside_site(site->service.tls_certificate);
  server_options.tls_key = beside_site(site->service.tls_key);
  hub::MqttConfig mqtt_config = site->mqtt;
  if (!options.mqtt.empty()) mqtt_config.broker = options.mqtt;
  if (auto broker = hub::parse_broker_url(mqtt_config.broker); !mqtt_config.broker.empty() && !broker) {
    fmt::print(stderr, "rangekit serve: --mqtt: {}\n", broker.error().message);
    return exit_bad_input;
  }
  auto sink_list_configs = sink_configs(*site, options.sinks);
  if (!sink_list_configs) {
    fmt::print(stderr, "rangekit serve: {}\n", sink_list_configs.error().message);
    return exit_bad_input;
  }
  auto hub = hub::Hub::start(*site);
  // The MQTT face: another face on the same hub, with its health on /healthz.
  std::unique_ptr<mqtt::Bridge> bridge;
  if (!mqtt_config.broker.empty()) {
    mqtt::BridgeOptions bridge_options;
    bridge_options.config = mqtt_config;
    bridge_options.spool_dir = state_path("spool", site->file);  // [mqtt] spool, beside the sinks' spools
    bridge_options.log = [](const std::string& line) {
      fmt::print("{}\n", line);
      std::fflush(stdout);
    };
    auto started_bridge = mqtt::Bridge::start(*hub, bridge_options);
    if (!started_bridge) {
      fmt::print(stderr, "rangekit serve: {}\n", started_bridge.error().message);
      hub->stop();
      return exit_code_for(started_bridge.error());
    }
    bridge = std::move(*started_bridge);
    const auto address = hub::parse_broker_url(mqtt_config.broker);
    fmt::print(
        "rangekit serve: publishing {} sensors to {} under {}/ (watch: mosquitto_sub -h {} -p {} -v -t '{}/#')\n",
        site->sensors.size(), mqtt_config.broker, mqtt_config.base_topic, address->host, address->port,
        mqtt_config.base_topic);
  }
  std::unique_ptr<modbus::Face> modbus_face;
  // A part that cannot start ends the service: what started before it is stopped, the hub last.
  const auto stop_started = [&] {
    if (modbus_face) modbus_face->stop();
    if (bridge) bridge->stop();
    hub->stop();
  };
  auto started_modbus = start_modbus(*hub, *site, options);
  if (!started_modbus) {
    fmt::print(stderr, "rangekit serve: {}\n", started_modbus.error().message);
    stop_started();
    // A setting the face refuses is a mistake of the site file or --modbus, like one --check finds.
    return started_modbus.error().code == Errc::io ? exit_code_for(started_modbus.error()) : exit_bad_input;
  }
  modbus_face = std::move(*started_modbus);
  if (modbus_face) {
    const Endpoint modbus_at = modbus_face->local_endpoint();
    fmt::print(
        "rangekit serve: Modbus TCP on {}:{}, units {} (docs/modbus.md; try: mbpoll -m tcp -p {} -a 1 -t 3 -r 1 "
        "-c 10 -1 {})\n",
        modbus_at.host, modbus_at.port, modbus_unit_list(*site), modbus_at.port, modbus_at.host);
  }
  // The historian sinks: their spools in the service's state folder, beside the captures.
  auto sink_list = start_sinks(*hub, *sink_list_configs, state_path("spool", site->file));
  if (!sink_list) {
    fmt::print(stderr, "rangekit serve: {}\n", sink_list.error().message);
    stop_started();
    return exit_code_for(sink_list.error());
  }
  // The other faces' health on /healthz.
  server_options.faces = [&bridge, &modbus_face] {
    std::vector<web::FaceHealth> faces;
    if (bridge) {
      const mqtt::BridgeStats stats = bridge->stats();
      web::FaceHealth face{"mqtt", stats.error.empty(), stats.error, stats.connected, stats.broker, {}};
      face.counters = {{"published", stats.published},   {"queued", stats.queued},     {"dropped", stats.dropped},
                       {"reconnects", stats.reconnects}, {"commands", stats.commands}, {"refusals", stats.refusals},
                       {"spooled", stats.spooled}};
      faces.push_back(std::move(face));
    }
    if (modbus_face) {
      const modbus::FaceStats stats = modbus_face->stats();
      web::FaceHealth face{"modbus", true, "", true, modbus_face->local_endpoint().to_string(), {}};
      face.counters = {{"clients", stats.clients}, {"requests", stats.requests},   {"exceptions", stats.exceptions},
                       {"refused", stats.refused}, {"malformed", stats.malformed}, {"commands", stats.commands}};
      faces.push_back(std::move(face));
    }
    return faces;
  };
  SinksHealth sinks_now;
  sinks_now.refresh(*sink_list);
  server_options.sinks = [&sinks_now] { return sinks_now.get(); };
  // Captures go where [service] capture_dir says; relative: in systemd's state folder, else beside the site file.
  const std::filesystem::path capture_dir = state_path(site->service.capture_dir, site->file);
  hub::CaptureLimits capture_limits;
  capture_limits.running = site->service.max_captures;
  hub::CaptureManager captures(*hub, capture_dir.string(), capture_limits);
  server_options.captures = &captures;
  server_options.assets = dashboard_assets();
  auto server = web::Server::start(*hub, server_options);
  if (!server) {
    fmt::print(stderr, "rangekit serve: {}\n", server.error().message);
    stop_started();
    return exit_code_for(server.error());
  }
  std::vector<std::string> capture_at_start;
  for (const hub::SensorConfig& sensor : site->sensors) {
    if (sensor.capture) capture_at_start.push_back(sensor.name);
  }
  if (!capture_at_start.empty()) {
    if (auto started = captures.start(capture_at_start); started) {
      fmt::print("capturing {} sensors into {}\n", capture_at_start.size(), started->path);
    } else {
      fmt::print(stderr, "rangekit serve: capture not started: {}\n", started.error().message);
    }
  }
  const Endpoint local = (*server)->local_endpoint();
  const char* scheme = server_options.tls_certificate.empty() ? "http" : "https";
  fmt::print("rangekit serve: {} sensors; API on {}://{}:{}/api/sensors (docs/api.md)\n", site->sensors.size(), scheme,
             local.host, local.port);
  if (!server_options.assets.empty()) {
    // Beyond loopback the page needs the token for its live stream: it reads it from #token=.
    fmt::print("dashboard: {}://{}:{}/{}\n", scheme, local.host, local.port,
               server_options.token.empty() ? "" : "#token=TOKEN");
  }
  std::fflush(stdout);
  SystemdNotify systemd;  // every session and face started: ready (docs/deploy.md)
  systemd.ready(states_line(hub->sensors()));
  const auto started = std::chrono::steady_clock::now();
  const auto limit = std::chrono::duration<double>(options.duration_s);
  auto next_summary = started + std::chrono::seconds(1);
  ServeMonitor monitor(stdout, options.table || ::isatty(STDOUT_FILENO) == 1, !writes_to_journal(stdout));
  while (!signals.stopped() && (options.duration_s <= 0 || std::chrono::steady_clock::now() - started < limit)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // polls the stop flag; not a synchronisation
    systemd.keep_alive([&] { return states_line(hub->sensors()); });
    if (!sink_list->empty()) sinks_now.refresh(*sink_list);  // what the HTTP face shows, 50 ms old at most
    if (std::chrono::steady_clock::now() < next_summary) continue;
    next_summary += std::chrono::seconds(1);
    monitor.tick(hub->sensors());
  }
  systemd.stopping();
  (*server)->stop();  // no new requests; streams closed
  if (modbus_face) modbus_face->stop();
  if (bridge) bridge->stop();  // every sensor marked offline on the broker, then a clean disconnect
  captures.stop_all();         // every capture committed and closed
  for (auto& each : *sink_list) each.sink->stop();  // queued readings spooled for the next start
  hub->stop();                                      // streams ended as found, ports released
  for (const hub::CaptureInfo& capture : captures.list()) {
    fmt::print("capture {}: {} samples, {} lost → {}\n", capture.id, capture.samples, capture.lost, capture.path);
  }
  for (const hub::SensorSnapshot& sensor : hub->sensors()) fmt::print("{}\n", summary_line(sensor));
  if (bridge) fmt::print("{}\n", mqtt_summary(bridge->stats()));
  for (const auto& each : *sink_list) fmt::print("{}\n", sink_summary(each.sink->stats()));
  if (modbus_face) {
    const modbus::FaceStats stats = modbus_face->stats();
    fmt::print("modbus: requests {}, exceptions {}, refused {}, malformed {}, commands {}\n", stats.requests,
               stats.exceptions, stats.refused, stats.malformed, stats.commands);
  }
  return signals.stopped() ? exit_interrupted : exit_ok;
}

int modbus_map_of(const std::string& path) {
  auto site = hub::load_site_config(path);
  if (!site) return site_refused(path, site.error());
  return print_modbus_map(*site);
}

int serve(const ServeOptions& options) {
  auto site = hub::load_site_config(options.config);
  if (!site) return site_refused(options.config, site.error());
  if (options.modbus_map) return print_modbus_map(*site);
  const StopSignals signals;
  return serve_site(*site, options, signals);
}

// Signals are caught before the emulators start; they run in their own process
// group, so Ctrl-C reaches the service only, which ends its streams and then stops them.
int serve_demo(const ServeOptions& options) {
  const StopSignals signals;
  // With --modbus-map stdout is the CSV alone: the emulators' progress goes to stderr.
  const int saved_stdout = options.modbus_map ? ::dup(STDOUT_FILENO) : -1;
  if (saved_stdout >= 0) ::dup2(STDERR_FILENO, STDOUT_FILENO);
  auto demo = DemoSite::start();
  if (saved_stdout >= 0) {
    std::fflush(stdout);
    ::dup2(saved_stdout, STDOUT_FILENO);
    ::close(saved_stdout);
  }
  if (signals.stopped()) return exit_interrupted;  // Ctrl-C while they started: they are stopped
  if (!demo) {
    fmt::print(stderr, "rangekit serve --demo: {}\n", demo.error().describe());
    return exit_code_for(demo.error());
  }
  if (options.modbus_map) {
    const int code = print_modbus_map(demo->site());
    demo->stop();
    return code;
  }
  // No broker given: a mosquitto of its own on a free loopback port, when one is installed.
  ServeOptions with_broker = options;
  std::unique_ptr<mqtt::LocalBroker> broker;
  std::filesystem::path broker_dir;
  if (options.mqtt.empty() && !mqtt::LocalBroker::find_executable().empty()) {
    std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-broker-XXXXXX").string();
    if (::mkdtemp(pattern.data()) != nullptr) {
      broker_dir = pattern;
      mqtt::LocalBrokerOptions broker_options;
      broker_options.dir = broker_dir;
      // Started on the main thread, which lives as long as the service: the broker dies with it.
      auto started = mqtt::LocalBroker::start(broker_options);
      if (started) {
        broker = std::move(*started);
        with_broker.mqtt = broker->url();
        fmt::print(
            "started a local mosquitto on 127.0.0.1:{}; watch it with:\n  mosquitto_sub -h 127.0.0.1 -p {} -v -t "
            "'rangekit/#'\n",
            broker->port(), broker->port());
      } else {
        fmt::print(stderr, "rangekit serve --demo: no local broker: {}\n", started.error().message);
      }
    }
  }
  const int code = serve_site(demo->site(), with_broker, signals);
  if (broker) broker->stop();
  if (!broker_dir.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(broker_dir, ignored);
  }
  demo->stop();
  fmt::print("Emulators stopped.\n");
  return code;
}

}  // namespace

void add_serve_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<ServeOptions>();
  CLI::App* serve_app = app.add_subcommand("serve", "Keep every sensor of a site live (site.toml, docs/service.md)");
  serve_app->add_option("--config", options->config, "site file: the sensors, their ports and what to do at start");
  serve_app->add_option("--check", options->check, "validate a site file without opening anything");
  serve_app->add_flag("--demo", options->demo, "serve a site of emulators started here: " + demo_site_summary());
  serve_app->add_option("--listen", options->listen,
                        "HOST:PORT of the HTTP API (default: the site file's, else 127.0.0.1:8080; port 0 picks one)");
  serve_app->add_option("--mqtt", options->mqtt,
                        "broker URL mqtt://HOST[:PORT] or mqtts://HOST[:PORT]: publish every sensor there (overrides "
                        "[mqtt] broker; --demo without it starts a local mosquitto when one is installed)");
  serve_app->add_option("--sink", options->sinks,
                        "URL: write every reading to a historian, as a [[sink]] table with its defaults would "
                        "(repeatable; docs/sinks.md): " +
                            std::string(hub::sink_option_forms));
  serve_app->add_option("--modbus", options->modbus,
                        "HOST:PORT: answer Modbus TCP there, each sensor a unit (overrides [modbus] listen; "
                        "docs/modbus.md)");
  serve_app->add_flag("--modbus-map", options->modbus_map,
                      "print the Modbus register map of the site (--config, --check or --demo) as CSV and end");
  serve_app->add_flag("--table", options->table,
                      "redraw every sensor's line each second, as on a terminal, also when stdout is not one");
  serve_app->add_option("--duration", options->duration_s, "stop after S seconds (default: until Ctrl-C)")
      ->check(duration_seconds());
  serve_app->callback([options, &exit_code] {
    const auto given = sink_configs(hub::SiteConfig{}, options->sinks);
    if (static_cast<int>(!options->check.empty()) + static_cast<int>(!options->config.empty()) +
            static_cast<int>(options->demo) >
        1) {
      fmt::print(stderr, "rangekit serve: give one of --config, --check and --demo\n");
      exit_code = exit_usage;
    } else if (!given) {
      // A --sink that cannot be one is refused before anything starts (the demo's emulators too).
      fmt::print(stderr, "rangekit serve: {}\n", given.error().message);
      exit_code = exit_bad_input;
    } else if (!options->check.empty()) {
      exit_code = options->modbus_map ? modbus_map_of(options->check) : check_site(options->check, options->sinks);
    } else if (options->demo) {
      exit_code = serve_demo(*options);
    } else if (!options->config.empty()) {
      exit_code = serve(*options);
    } else {
      fmt::print(stderr, "rangekit serve: give --config site.toml, --check site.toml or --demo; see docs/service.md\n");
      exit_code = exit_usage;
    }
  });
}

}  // namespace rangekit::cli
