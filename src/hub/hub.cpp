#include "rangekit/hub/hub.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <map>

#include "hub/port_worker.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/hub/backend.hpp"
#include "rangekit/hub/service_family.hpp"

namespace rangekit::hub {

std::string bus_address_text(std::string_view family, std::uint8_t address) { return address_text_of(family, address); }

std::optional<std::uint8_t> parse_bus_address(std::string_view family, std::string_view text) {
  const ServiceFamily* found = find_service_family(family);
  if (found == nullptr || found->parse_address_text == nullptr) return std::nullopt;
  return found->parse_address_text(text);
}

std::string bus_address_help(std::string_view family) {
  const ServiceFamily* found = find_service_family(family);
  return found != nullptr ? std::string(found->address_help) : std::string();
}

namespace {

SensorSnapshot snapshot_of(const Session& session) {
  SensorSnapshot snapshot;
  snapshot.config = session.config;
  std::lock_guard lock(session.mutex);
  snapshot.streaming = session.streaming;
  snapshot.identity = session.identity;
  snapshot.status = session.status;
  snapshot.settings = session.settings;
  snapshot.health = session.health.snapshot(std::chrono::steady_clock::now());
  snapshot.last_sequence = session.last_sequence;
  return snapshot;
}

}  // namespace

struct Hub::Impl final : Publisher {
  HubOptions options;
  std::vector<std::unique_ptr<Session>> sessions;
  std::vector<std::unique_ptr<PortWorker>> workers;
  std::map<std::string, PortWorker*, std::less<>> worker_of;  // sensor name -> its port's worker
  Fanout fanout;
  std::mutex publish_mutex;  // one order of sequence numbers for the ring and every subscriber
  std::uint64_t sequence = 0;
  std::vector<HubItemPtr> numbered;  // numbered but not yet delivered; under publish_mutex
  std::uint64_t dropped_suspects = 0;
  std::atomic<bool> stopped{false};

  void publish(Session& session, StreamItem item) override {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard order(publish_mutex);
    admit(session, std::move(item), now);
    deliver(session, now);
  }

  void publish_batch(Session& session, std::vector<StreamItem>& items) override {
    const auto now = std::chrono::steady_clock::now();
    {
      std::lock_guard order(publish_mutex);
      for (StreamItem& item : items) admit(session, std::move(item), now);
      deliver(session, now);
    }
    items.clear();
  }

  void release_due(Session& session) override {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard order(publish_mutex);
    if (!session.spikes.holding()) return;
    session.released.clear();
    session.spikes.release_due(now, session.released);
    for (StreamItem& released : session.released) number(session, std::move(released));
    deliver(session, now);
  }

  void release_all() {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard order(publish_mutex);
    for (const auto& session : sessions) {
      session->released.clear();
      session->spikes.release_all(session->released);
      for (StreamItem& released : session->released) number(*session, std::move(released));
      deliver(*session, now);
    }
  }

  // The quality check of one item (docs/reliability.md): flagged here, so the ring, the streams,
  // the captures and the health all see the same flag. A distance is held until the next reading
  // tells whether it was a spike (core/spike_check.hpp), events keep their place behind it.
  // Called under publish_mutex.
  void admit(Session& session, StreamItem item, std::chrono::steady_clock::time_point now) {
    // In the service a sample's source is its sensor's name (the port alone would not
    // tell the units of a bus apart in a capture or a download).
    auto* sample = std::get_if<Sample>(&item);
    if (sample != nullptr) sample->source = session.source;
    session.released.clear();
    if (sample != nullptr) session.checker.check(*sample);
    session.spikes.push(std::move(item), now, session.released);
    for (StreamItem& released : session.released) number(session, std::move(released));
  }

  // Gives an item its sequence number and keeps it for deliver(); under publish_mutex.
  void number(Session& session, StreamItem item) {
    const auto* sample = std::get_if<Sample>(&item);
    if (sample != nullptr && sample->suspect && session.config.drop_suspect) {
      ++dropped_suspects;
      return;
    }
    numbered.push_back(std::make_shared<const HubItem>(HubItem{++sequence, session.config.name, std::move(item)}));
  }

  // Counts, rings and fans out what number() kept, as one batch; under publish_mutex.
  void deliver(Session& session, std::chrono::steady_clock::time_point now) {
    if (numbered.empty() && dropped_suspects == 0) return;
    {
      std::lock_guard lock(session.mutex);
      for (; dropped_suspects > 0; --dropped_suspects) session.health.record_dropped_suspect();
      for (const HubItemPtr& item : numbered) session.health.record(item->item, now);
      if (!numbered.empty()) session.last_sequence = numbered.back()->sequence;
    }
    session.ring.push_all(numbered);
    fanout.publish_run(session.config.name, numbered);
    numbered.clear();
  }

  [[nodiscard]] Session* find(std::string_view name) const {
    for (const auto& session : sessions) {
      if (session->config.name == name) return session.get();
    }
    return nullptr;
  }

  [[nodiscard]] Error unknown(std::string_view name) const {
    std::string names;
    for (const auto& session : sessions) names += (names.empty() ? "" : ", ") + session->config.name;
    return make_error(Errc::unknown_parameter, "no sensor named '" + std::string(name) + "' (sensors: " + names + ")");
  }
};

Hub::Hub(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Hub::~Hub() { stop(); }

std::unique_ptr<Hub> Hub::start(const SiteConfig& site, HubOptions options) {
  auto impl = std::make_unique<Impl>();
  if (!options.open_port) options.open_port = open_serial_link;
  impl->options = options;
  for (const SensorConfig& sensor : site.sensors) {
    auto session = std::make_unique<Session>(sensor, options.ring_capacity);
    session->want_stream = sensor.stream;
    impl->sessions.push_back(std::move(session));
  }
  const auto session_of = [&](const SensorConfig* sensor) { return impl->find(sensor->name); };
  for (const PortGroup& group : port_groups(site)) {
    std::vector<Session*> sessions;
    std::transform(group.sensors.begin(), group.sensors.end(), std::back_inserter(sessions), session_of);
    // The site file was checked against the registered families, so the family is there.
    const ServiceFamily& family = *find_service_family(group.family);
    std::unique_ptr<Backend> backend = family.port_backend(sessions, *impl, options.open_port);
    impl->workers.push_back(
        std::make_unique<PortWorker>(std::move(backend), sessions, *impl, options.reconnect_interval));
    for (Session* session : sessions) impl->worker_of[session->config.name] = impl->workers.back().get();
  }
  for (const auto& session : impl->sessions) {
    if (!session->config.port.empty() || session->config.udp.empty()) continue;
    const ServiceFamily& family = *find_service_family(session->config.family);
    impl->workers.push_back(std::make_unique<PortWorker>(
        family.udp_backend(*session, *impl), std::vector<Session*>{session.get()}, *impl, options.reconnect_interval));
    impl->worker_of[session->config.name] = impl->workers.back().get();
  }
  for (const auto& worker : impl->workers) worker->start();
  return std::unique_ptr<Hub>(new Hub(std::move(impl)));
}

void Hub::stop() {
  if (impl_->stopped.exchange(true)) return;
  for (const auto& worker : impl_->workers) worker->stop();
  impl_->release_all();  // the readings the spike check still held reach the captures before they close
}

std::vector<std::string> Hub::sensor_names() const {
  std::vector<std::string> names;
  for (const auto& session : impl_->sessions) names.push_back(session->config.name);
  return names;
}

Result<SensorSnapshot> Hub::sensor(std::string_view name) const {
  const Session* session = impl_->find(name);
  if (session == nullptr) return impl_->unknown(name);
  return snapshot_of(*session);
}

std::vector<SensorSnapshot> Hub::sensors() const {
  std::vector<SensorSnapshot> all;
  for (const auto& session : impl_->sessions) all.push_back(snapshot_of(*session));
  return all;
}

Result<SubscriptionPtr> Hub::subscribe(std::string_view sensor, std::size_t capacity, OverflowPolicy policy) {
  if (!sensor.empty() && impl_->find(sensor) == nullptr) return impl_->unknown(sensor);
  return impl_->fanout.subscribe(std::string(sensor), capacity, policy);
}

Result<SubscriptionPtr> Hub::subscribe(std::vector<std::string> sensors, std::size_t capacity, OverflowPolicy policy) {
  for (const std::string& sensor : sensors) {
    if (impl_->find(sensor) == nullptr) return impl_->unknown(sensor);
  }
  return impl_->fanout.subscribe(std::move(sensors), capacity, policy);
}

Result<SampleRing::Since> Hub::since(std::string_view sensor, std::uint64_t after) const {
  if (!sensor.empty()) {
    const Session* session = impl_->find(sensor);
    if (session == nullptr) return impl_->unknown(sensor);
    return session->ring.since(after);
  }
  SampleRing::Since merged;
  for (const auto& session : impl_->sessions) {
    auto part = session->ring.since(after);
    merged.complete = merged.complete && part.complete;
    merged.items.insert(merged.items.end(), part.items.begin(), part.items.end());
  }
  std::sort(merged.items.begin(), merged.items.end(),
            [](const HubItemPtr& a, const HubItemPtr& b) { return a->sequence < b->sequence; });
  return merged;
}

Result<std::vector<HubItemPtr>> Hub::latest(std::string_view sensor, std::size_t count) const {
  const Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  return session->ring.latest(count);
}

std::uint64_t Hub::last_sequence() const {
  std::lock_guard lock(impl_->publish_mutex);
  return impl_->sequence;
}

std::uint64_t Hub::subscribers_cut_off() const { return impl_->fanout.cut_off_count(); }

Result<std::vector<Field>> Hub::set(std::string_view sensor, const SettingValues& values) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  if (values.empty()) return make_error(Errc::wrong_form, "no settings given");
  return impl_->worker_of.at(session->config.name)
      ->run<std::vector<Field>>(
          [session, values](Backend& backend) { return backend.write_settings(*session, values); },
          impl_->options.command_timeout);
}

Result<std::vector<Field>> Hub::settings(std::string_view sensor) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  return impl_->worker_of.at(session->config.name)
      ->run<std::vector<Field>>([session](Backend& backend) { return backend.read_settings(*session); },
                                impl_->options.command_timeout);
}

Result<std::string> Hub::export_config(std::string_view sensor) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  return impl_->worker_of.at(session->config.name)
      ->run<std::string>([session](Backend& backend) { return backend.export_config(*session); },
                         impl_->options.command_timeout);
}

Result<std::vector<Field>> Hub::import_config(std::string_view sensor, std::string_view toml) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  return impl_->worker_of.at(session->config.name)
      ->run<std::vector<Field>>(
          [session, text = std::string(toml)](Backend& backend) { return backend.import_config(*session, text); },
          impl_->options.command_timeout);
}

Result<ActionResult> Hub::act(std::string_view sensor, std::string_view action, std::string_view argument) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  const ActionDescriptor* known = find_action(session->config.family, action);
  if (known == nullptr) {
    return make_error(Errc::unknown_command, not_an_action(session->config.family, session->config.name, action));
  }
  if (auto checked = check_argument(*known, argument); !checked) return std::move(checked).error();
  if (action == "start" || action == "stop") {
    std::lock_guard lock(session->mutex);
    session->want_stream = action == "start";  // kept across reconnects
  }
  return impl_->worker_of.at(session->config.name)
      ->run<ActionResult>([session, action = std::string(action), argument = std::string(argument)](
                              Backend& backend) { return backend.act(*session, action, argument); },
                          impl_->options.command_timeout);
}

namespace {

// A bus scan asks this many addresses per job, so the poll of the bus's units goes on in between.
constexpr std::size_t scan_chunk = 8;

// The family of a sensor on a bus: one that has buses, and an address in the site file.
const ServiceFamily* bus_family(const Session& session) {
  const ServiceFamily* family = find_service_family(session.config.family);
  if (family == nullptr || !family->bus || family->scan_addresses == nullptr || !session.config.address) return nullptr;
  return family;
}

Error not_on_a_bus(const Session& session) {
  return make_error(Errc::unsupported, "'" + session.config.name +
                                           "' is not on an RS-485 bus (no `address` in the site file): " +
                                           "the RS-485 network is for units addressed on a bus");
}

}  // namespace

Result<BusScan> Hub::scan_bus(std::string_view sensor) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  const ServiceFamily* family = bus_family(*session);
  if (family == nullptr) return not_on_a_bus(*session);
  BusScan scan;
  scan.family = session->config.family;
  scan.port = session->config.port;
  for (const auto& other : impl_->sessions) {
    if (other->config.port == scan.port && other->config.address) {
      scan.site.emplace_back(static_cast<std::uint8_t>(*other->config.address), other->config.name);
    }
  }
  const std::vector<std::uint8_t> addresses = family->scan_addresses();
  scan.asked = addresses.size();
  PortWorker& worker = *impl_->worker_of.at(session->config.name);
  for (std::size_t first = 0; first < addresses.size(); first += scan_chunk) {
    const std::vector<std::uint8_t> chunk(
        addresses.begin() + static_cast<std::ptrdiff_t>(first),
        addresses.begin() + static_cast<std::ptrdiff_t>(std::min(first + scan_chunk, addresses.size())));
    auto found = worker.run<std::vector<BusUnitFound>>([chunk](Backend& backend) { return backend.scan_bus(chunk); },
                                                       impl_->options.command_timeout);
    if (!found) return std::move(found).error();
    scan.found.insert(scan.found.end(), found->begin(), found->end());
  }
  return scan;
}

Status Hub::assign_address(std::string_view sensor, std::optional<std::uint8_t> from, std::uint8_t to) {
  Session* session = impl_->find(sensor);
  if (session == nullptr) return impl_->unknown(sensor);
  if (bus_family(*session) == nullptr) return not_on_a_bus(*session);
  const auto unit = from.value_or(static_cast<std::uint8_t>(*session->config.address));
  return impl_->worker_of.at(session->config.name)
      ->run<Ok>([unit, to](Backend& backend) { return backend.assign_address(unit, to); },
                impl_->options.command_timeout);
}

// ---- helpers the backends share ----

StreamEvent make_event(StreamEventKind kind, std::string message) {
  return StreamEvent{std::chrono::system_clock::now(), kind, std::move(message), 0};
}

std::size_t drain(SampleSource& source, Session& session, Publisher& publisher, std::chrono::milliseconds wait) {
  // Everything already queued goes in one batch; the first wait is the only one.
  thread_local std::vector<StreamItem> batch;
  if (!source.next_batch(batch, wait)) return 0;
  const std::size_t count = batch.size();
  publisher.publish_batch(session, batch);
  return count;
}

Error refused(const Session& session, std::string_view action) {
  return make_error(Errc::unsupported, "'" + std::string(action) + "' is not something " + session.config.family +
                                           " sensor '" + session.config.name + "' can do here");
}

}  // namespace rangekit::hub
