// What a family's service backend works with: a sensor's session inside the hub, the
// publisher it reports through and the Backend interface it implements (service_family.hpp).
#pragma once

#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rangekit/core/sample_quality.hpp"
#include "rangekit/core/spike_check.hpp"
#include "rangekit/hub/hub.hpp"

namespace rangekit::hub {

struct Session {
  Session(SensorConfig sensor, std::size_t ring_capacity)
      : config(std::move(sensor)),
        source(config.name),
        ring(ring_capacity),
        checker(QualitySettings{config.max_speed_mps}) {}
  const SensorConfig config;
  const SharedName source;  // config.name as every sample's source: shared, so no allocation per sample
  SampleRing ring;
  // Both used under the hub's publish order (a serial and a UDP worker may share a session).
  SampleChecker checker;
  SpikeCheck spikes;
  std::vector<StreamItem> released;  // what the spike check let go, reused

  mutable std::mutex mutex;  // guards what follows
  HealthTracker health;
  std::vector<Field> identity;
  std::vector<Field> status;
  std::vector<Field> settings;
  bool streaming = false;
  bool want_stream = false;  // what the user asked for (start/stop); the worker restores it after a reconnect
  std::uint64_t last_sequence = 0;
};

// Where a backend sends what it reads: numbered, ringed, fanned out, counted.
class Publisher {
 public:
  virtual void publish(Session& session, StreamItem item) = 0;
  // The items in order, as publish() one by one would, handed on as one batch; `items` is
  // left empty with its storage.
  virtual void publish_batch(Session& session, std::vector<StreamItem>& items) {
    for (StreamItem& item : items) publish(session, std::move(item));
    items.clear();
  }
  // Publishes the readings the spike check has held past its limit (a stream that paused).
  virtual void release_due(Session& session) = 0;

 protected:
  ~Publisher() = default;
};

// The driver side of one port: one ULS, an RS-485 bus of ULS units, one LS5 or
// an LS5 UDP listener. Called from its port's worker thread only.
class Backend {
 public:
  virtual ~Backend() = default;
  // Opens the port and reads the identity of its sensors into their sessions.
  virtual Status connect() = 0;
  [[nodiscard]] virtual bool connected() const = 0;
  // Whether this session's sensor answered when the port connected: on a bus the port can be
  // up while a unit is silent, and that unit is not announced as connected.
  [[nodiscard]] virtual bool answering(const Session& /*session*/) const { return true; }
  // Reads or polls for up to `wait`, publishing what arrives. False when there
  // was nothing to do (no stream): the worker then waits for a command instead.
  virtual bool pump(std::chrono::milliseconds wait) = 0;
  // When pump() has something to do again without a command (a paced poll); none: only
  // a command or a reconnect wakes the worker.
  [[nodiscard]] virtual std::optional<std::chrono::steady_clock::time_point> next_due() const { return std::nullopt; }
  virtual Status set_streaming(Session& session, bool on) = 0;
  // Whether the sensor has settings to read: the worker reads them once it connects, so that
  // the service shows them before anyone asks. A listener without a port has none.
  [[nodiscard]] virtual bool has_settings() const { return true; }
  virtual Result<std::vector<Field>> read_settings(Session& session) = 0;
  virtual Result<std::vector<Field>> write_settings(Session& session, const SettingValues& values) = 0;
  // One of the family's actions (actions_of), its argument already checked.
  virtual Result<ActionResult> act(Session& session, std::string_view action, std::string_view argument) = 0;
  virtual Result<std::string> export_config(Session& session) = 0;
  virtual Result<std::vector<Field>> import_config(Session& session, std::string_view toml) = 0;
  // An RS-485 bus of ULS units only (§7); the other backends refuse.
  virtual Result<std::vector<BusUnitFound>> scan_bus(const std::vector<std::uint8_t>& /*addresses*/) {
    return make_error(Errc::unsupported, "not an RS-485 bus");
  }
  virtual Status assign_address(std::uint8_t /*from*/, std::uint8_t /*to*/) {
    return make_error(Errc::unsupported, "not an RS-485 bus");
  }
  // Streams ended (the unit left as found), the port closed.
  virtual void shutdown() = 0;

  // Set by the port's worker: what a job that is many slow steps (a bus scan) calls between two
  // of them, so that the commands queued meanwhile are not held up behind it; the poll then
  // also runs for up to `poll_for` (a scan's silent address is idle wire).
  void set_between_steps(std::function<void(std::chrono::nanoseconds)> between) { between_steps_ = std::move(between); }

 protected:
  void between_steps(std::chrono::nanoseconds poll_for) {
    if (between_steps_) between_steps_(poll_for);
  }

 private:
  std::function<void(std::chrono::nanoseconds)> between_steps_;
};

using PortOpener = std::function<Result<TransportPtr>(const std::string&, const SerialSettings&)>;

// Helpers the backends share.
StreamEvent make_event(StreamEventKind kind, std::string message);
// Moves every item the source has ready (waiting up to `wait` for the first) to the publisher.
std::size_t drain(SampleSource& source, Session& session, Publisher& publisher, std::chrono::milliseconds wait);
// An action the family has that this backend cannot take (an LS5 heard over UDP only: no port).
Error refused(const Session& session, std::string_view action);

}  // namespace rangekit::hub
