// The public Bridge: start() makes one libmosquitto session per sensor and starts the
// network and command threads; stop() ends them; stats() sums the sessions' counters.
#include "rangekit/mqtt/bridge.hpp"

#include <mosquitto.h>
#include <mqtt_protocol.h>

#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "mqtt/bridge_impl.hpp"
#include "mqtt/mosquitto_callbacks.hpp"
#include "mqtt/sensor_link.hpp"

namespace rangekit::mqtt {
namespace {

void init_library() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

}  // namespace

// Sessions made by a start() that failed before their threads ran, or stopped ones.
Bridge::Impl::~Impl() {
  for (const auto& link : links) {
    if (link->client != nullptr) mosquitto_destroy(link->client);
  }
}

Bridge::Bridge(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Bridge::~Bridge() { stop(); }

Result<std::unique_ptr<Bridge>> Bridge::start(hub::Hub& hub, BridgeOptions options) {
  auto address = hub::parse_broker_url(options.config.broker);
  if (!address) return std::move(address).error();
  init_library();
  auto impl = std::make_unique<Impl>(hub, std::move(options));
  impl->address = *address;
  if (impl->waker->fd < 0) return make_error(Errc::io, "mqtt: cannot make an eventfd for the network thread");
  const hub::MqttConfig& config = impl->options.config;
  if (config.spool) {
    if (impl->options.spool_dir.empty())
      return make_error(Errc::unsupported, "mqtt: spool = true needs a spool folder");
    std::error_code made;
    std::filesystem::create_directories(impl->options.spool_dir, made);
    if (made) return make_error(Errc::io, "mqtt: spool folder " + impl->options.spool_dir + ": " + made.message());
  }
  for (const hub::SensorSnapshot& sensor : hub.sensors()) {
    impl->links.push_back(std::make_unique<Link>(*impl, sensor.config));
    Link& link = *impl->links.back();
    impl->by_sensor.emplace(sensor.config.name, &link);
    const std::string client_id = config.client_id + "-" + sensor.config.name;
    link.client = mosquitto_new(client_id.c_str(), true, &link);
    if (link.client == nullptr) return make_error(Errc::io, "mqtt: cannot make a client (out of memory)");
    mosquitto_int_option(link.client, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V5);
    // Each reading leaves at once: with Nagle on, a publish behind an unacknowledged one
    // waits for the broker's delayed ACK (40 ms on Linux).
    mosquitto_int_option(link.client, MOSQ_OPT_TCP_NODELAY, 1);
    set_session_callbacks(link.client);
    // The fast path writes the socket itself: plain TCP only, and a topic libmosquitto would take.
    link.direct = !address->tls &&
                  mosquitto_validate_utf8(link.reading_topic.c_str(), static_cast<int>(link.reading_topic.size())) ==
                      MOSQ_ERR_SUCCESS &&
                  mosquitto_pub_topic_check2(link.reading_topic.c_str(), link.reading_topic.size()) == MOSQ_ERR_SUCCESS;
    if (config.spool) {
      const auto path =
          std::filesystem::path(impl->options.spool_dir) / reading_spool_name(config.client_id, link.config.name);
      auto spool = ReadingSpool::open(path.string(), static_cast<std::uint64_t>(config.spool_max_mb) * 1024 * 1024,
                                      link.config.name);
      if (!spool) return std::move(spool).error();
      link.spool = std::move(*spool);
    }
    const std::string availability = link.topic + "/availability";
    mosquitto_will_set_v5(link.client, availability.c_str(), 7, "offline", config.qos_state, true, nullptr);
    if (!config.username.empty()) {
      mosquitto_username_pw_set(link.client, config.username.c_str(),
                                config.password.empty() ? nullptr : config.password.c_str());
    }
    if (address->tls) {
      const int rc = mosquitto_tls_set(link.client, config.ca_file.empty() ? nullptr : config.ca_file.c_str(),
                                       config.ca_file.empty() ? "/etc/ssl/certs" : nullptr, nullptr, nullptr, nullptr);
      if (rc != MOSQ_ERR_SUCCESS) {
        return make_error(Errc::io, "mqtt: TLS with CA file '" + config.ca_file + "': " + mosquitto_strerror(rc));
      }
    }
  }
  Impl* raw = impl.get();
  impl->network = std::thread([raw] { raw->run_network(); });
  impl->commander = std::thread([raw] { raw->run_commands(); });
  return std::unique_ptr<Bridge>(new Bridge(std::move(impl)));
}

void Bridge::stop() {
  if (!impl_ || impl_->stopping.exchange(true)) return;
  impl_->command_ready.notify_all();
  if (impl_->commander.joinable()) impl_->commander.join();
  // After the commands, so that their results still go out before offline.
  impl_->closing = true;
  impl_->wake();
  if (impl_->network.joinable()) impl_->network.join();
  for (const auto& link : impl_->links) {
    mosquitto_destroy(link->client);
    link->client = nullptr;
  }
}

BridgeStats Bridge::stats() const {
  BridgeStats stats;
  stats.broker = impl_->options.config.broker;
  stats.connected = impl_->connected_links.load() == static_cast<int>(impl_->links.size());
  {
    const std::lock_guard lock(impl_->state_mutex);
    stats.error = impl_->error;
  }
  stats.dropped = impl_->hub_lost.load();
  stats.commands = impl_->handled.load();
  stats.busy = impl_->busy.load();
  stats.refusals = impl_->refusals.load();
  for (const auto& link : impl_->links) {
    stats.published += link->published.load();
    stats.dropped += link->dropped.load();
    stats.queued += link->queued.load();
    stats.reconnects += link->reconnects.load();
    if (link->spool) {
      const record::SpoolStats spooled = link->spool->stats();
      stats.spooled += spooled.rows;
      stats.spool_bytes += spooled.bytes;
    }
  }
  return stats;
}

}  // namespace rangekit::mqtt
