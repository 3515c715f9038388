#include "rangekit/modbus/face.hpp"

#include <set>
#include <thread>

#include "modbus/face_impl.hpp"
#include "modbus/server.hpp"

namespace rangekit::modbus {
namespace {

// Unit ids in 1-247, each once, each naming a sensor the hub has.
Status check_units(const hub::Hub& hub, const std::vector<std::pair<std::uint8_t, std::string>>& units) {
  const auto names = hub.sensor_names();
  std::set<std::uint8_t> seen;
  for (const auto& [unit, sensor] : units) {
    if (unit < 1 || unit > 247) {
      return make_error(Errc::out_of_range,
                        "modbus unit " + std::to_string(unit) + " of '" + sensor + "' is not 1-247");
    }
    if (!seen.insert(unit).second) {
      return make_error(Errc::out_of_range, "modbus unit " + std::to_string(unit) + " is given twice");
    }
    if (std::find(names.begin(), names.end(), sensor) == names.end()) {
      return make_error(Errc::out_of_range, "modbus unit " + std::to_string(unit) + ": no sensor '" + sensor + "'");
    }
  }
  return ok_status();
}

}  // namespace

struct Face::Impl {
  Impl(hub::Hub& h, FaceOptions o, WordOrder order)
      : hub(h), options(std::move(o)), units(h, order, options.writable) {}

  hub::Hub& hub;
  FaceOptions options;
  FaceUnits units;
  ServerCounters counters;
  std::unique_ptr<Server> server;
  hub::SubscriptionPtr subscription;
  std::atomic<bool> stopping{false};
  std::thread server_thread;
  std::thread updater;
  std::thread commander;
  bool stopped = false;
};

Face::Face(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Face::~Face() { stop(); }

Result<std::unique_ptr<Face>> Face::start(hub::Hub& hub, FaceOptions options) {
  const auto order = parse_word_order(options.word_order);
  if (!order) {
    return make_error(Errc::out_of_range,
                      "modbus word order '" + options.word_order + "' is not ABCD, CDAB, BADC or DCBA");
  }
  ServerSettings settings;
  auto listen = parse_endpoint(options.listen);
  if (!listen)
    return make_error(Errc::out_of_range, "modbus listen '" + options.listen + "': " + listen.error().message);
  settings.listen = *listen;
  for (const std::string& text : options.allow) {
    auto range = parse_address_range(text);
    if (!range) return make_error(Errc::out_of_range, "modbus allow " + range.error().message);
    settings.allow.push_back(*range);
  }
  if (auto checked = check_units(hub, options.units); !checked) return std::move(checked).error();
  settings.max_clients = options.max_clients;
  settings.idle_timeout = options.idle_timeout;
  settings.log = options.log;

  auto impl = std::make_unique<Impl>(hub, std::move(options), *order);
  for (const auto& [unit, sensor] : impl->options.units) {
    auto snapshot = hub.sensor(sensor);
    impl->units.add(unit, sensor, snapshot ? snapshot->config.family : std::string());
  }
  auto server = Server::bind(std::move(settings), impl->units, impl->counters);
  if (!server) return std::move(server).error();
  impl->server = std::move(*server);
  // Subscribed last: a start that fails leaves no subscription behind in the hub.
  auto subscription = hub.subscribe("", 8192, hub::OverflowPolicy::drop_oldest);
  if (!subscription) return std::move(subscription).error();
  impl->subscription = *subscription;
  Impl* state = impl.get();
  impl->updater = std::thread([state] { state->units.run_updates(state->subscription, state->stopping); });
  impl->commander = std::thread([state] { state->units.run_commands(); });
  impl->server_thread = std::thread([state] { state->server->run(); });
  return std::unique_ptr<Face>(new Face(std::move(impl)));
}

void Face::stop() {
  if (!impl_ || impl_->stopped) return;
  impl_->stopped = true;
  impl_->server->stop();
  impl_->server_thread.join();
  impl_->stopping = true;
  impl_->subscription->close();
  impl_->updater.join();
  impl_->units.stop_commands();
  impl_->commander.join();
}

Endpoint Face::local_endpoint() const { return impl_->server->local_endpoint(); }

FaceStats Face::stats() const {
  FaceStats stats;
  stats.clients = impl_->counters.clients;
  stats.requests = impl_->counters.requests;
  stats.exceptions = impl_->counters.exceptions;
  stats.refused = impl_->counters.refused;
  stats.malformed = impl_->counters.malformed;
  stats.commands = impl_->units.commands;
  return stats;
}

Result<std::string> register_map_csv(const std::vector<std::pair<std::uint8_t, std::string>>& units,
                                     const std::string& word_order, bool writable) {
  const auto order = parse_word_order(word_order);
  if (!order) return make_error(Errc::out_of_range, "word order '" + word_order + "' is not ABCD, CDAB, BADC or DCBA");
  return write_register_map(units, *order, writable);
}

}  // namespace rangekit::modbus
