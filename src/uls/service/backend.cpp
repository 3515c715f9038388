// A ULS alone on its port (stream: continuous lines or polled BM, §2 Continuous
// Output), or several on an RS-485 bus (§7: the network poll, one unit after
// another). Settings go through the config-file table and load_config, which
// stops a measuring unit, uploads, reads back and restarts it (U24).
#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>

#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/family.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/host_config.hpp"
#include "rangekit/uls/named_settings.hpp"
#include "uls/service/service.hpp"

namespace rangekit::uls::service {
namespace {

using namespace rangekit::hub;

std::vector<Field> status_fields(const uls::StatusInfo& status) {
  const auto yes_no = [](bool on) { return std::string(on ? "yes" : "no"); };
  std::vector<Field> fields{{"status", std::to_string(status.value), ""},
                            {"active", yes_no(status.active), ""},
                            {"laser-firing", yes_no(status.laser_firing), ""},
                            {"averaging", yes_no(status.averaging_calc), ""},
                            {"binning", yes_no(status.binning_calc), ""}};
  return fields;
}

// The settings as `rangekit uls get` lists them (the unit in the name: short-gate-m).
Result<std::vector<Field>> read_fields(uls::Driver& driver, Session& session) {
  auto values = uls::named::read_all(driver);
  if (!values) return std::move(values).error();
  std::vector<Field> fields;
  for (const uls::named::Value& value : *values) fields.push_back({value.key, value.reading.text, ""});
  std::lock_guard lock(session.mutex);
  session.settings = fields;
  return fields;
}

// As `rangekit uls set` (the same names and checks, uls::named::write: a measuring unit is
// stopped for them and restarted, each value read back), then every setting read again.
Result<std::vector<Field>> write_fields(uls::Driver& driver, Session& session, const SettingValues& values) {
  auto work = uls::named::plan(values);  // every value checked before anything is sent
  if (!work) return std::move(work).error();
  if (auto written = uls::named::write(driver, *work); !written) return std::move(written).error();
  return read_fields(driver, session);
}

Result<std::string> export_fields(uls::Driver& driver, const Session& session) {
  auto config = uls::read_config(driver);
  if (!config) return std::move(config).error();
  return uls::config_to_toml(*config, "read by rangekit serve from sensor '" + session.config.name + "'");
}

// `uls config load`: every value checked (by the file's parse) before anything is sent,
// uploaded with the unit stopped (U24), read back and compared.
Result<std::vector<Field>> import_fields(uls::Driver& driver, Session& session, std::string_view toml) {
  auto wanted = uls::config_from_toml(toml, "the uploaded configuration");
  if (!wanted) return std::move(wanted).error();
  if (wanted->settings.empty()) {
    return make_error(Errc::invalid_frame, "the uploaded configuration holds no settings ([settings] is empty)");
  }
  auto report = uls::load_config(driver, *wanted);
  if (!report) return std::move(report).error();
  if (!report->mismatches.empty()) {
    const auto& first = report->mismatches.front();
    return make_error(Errc::device_error, std::string(first.command->cli_name) + " reads back as " + first.actual +
                                              ", not " + first.wanted);
  }
  return read_fields(driver, session);
}

// A distance at the unit's resolution (§9: "Resolution 1 mm or 0.01 ft"), in its units (§8 MU).
std::string distance_text(double metres, uls::Units units) {
  std::array<char, 48> text{};
  if (units == uls::Units::feet) {
    std::snprintf(text.data(), text.size(), "%.2f ft", uls::from_metres(metres, units));
  } else {
    std::snprintf(text.data(), text.size(), "%.3f m", metres);
  }
  return text.data();
}

std::string sample_text(const Sample& sample, uls::Units units) {
  if (const auto number = sample.get(channel::error)) return "error " + std::to_string(*number);
  if (const auto metres = sample.get(channel::distance_m)) return distance_text(*metres, units);
  if (!sample.targets.empty()) {
    std::string text = std::to_string(sample.targets.size()) + (sample.targets.size() == 1 ? " target:" : " targets:");
    for (std::size_t i = 0; i < sample.targets.size(); ++i) {
      text += (i == 0 ? " " : ", ") + distance_text(sample.targets[i].distance_m, units);
    }
    return text;
  }
  if (const auto present = sample.get(channel::presence)) return *present ? "ON" : "OFF";
  return "";
}

// Actions on one unit that need no stream of their own.
Result<ActionResult> unit_action(uls::Driver& driver, Session& session, std::string_view action,
                                 std::string_view argument) {
  const auto done = [](Status status) -> Result<ActionResult> {
    if (!status) return std::move(status).error();
    return ActionResult{};
  };
  if (action == "single") {
    auto sample = driver.measure();
    if (!sample) return std::move(sample).error();
    auto units = driver.units();  // the reply's resolution: 1 mm, or 0.01 ft (§9)
    if (!units) return std::move(units).error();
    return ActionResult{sample_text(*sample, *units), std::move(*sample)};
  }
  if (action == "pointer") return done(driver.set_pointer(argument == "on"));
  if (action == "save") return done(driver.save());
  if (action == "reset") {
    auto report = uls::load_config(driver, uls::factory_config());
    if (!report) return std::move(report).error();
    auto fields = read_fields(driver, session);
    if (!fields) return std::move(fields).error();
    return ActionResult{};
  }
  if (action == "read") {
    auto fields = read_fields(driver, session);
    if (!fields) return std::move(fields).error();
    return ActionResult{};
  }
  return refused(session, action);
}

class UlsBackend final : public Backend {
 public:
  UlsBackend(Session& session, Publisher& publisher, PortOpener open)
      : session_(session), publisher_(publisher), open_(std::move(open)) {}

  Status connect() override {
    const SensorConfig& config = session_.config;
    auto link = open_(config.port, config.serial);
    if (!link) return std::move(link).error();
    uls::DriverOptions options;
    if (config.address) options.address = static_cast<std::uint8_t>(*config.address);
    options.source = config.name;
    auto reopen = [open = open_, port = config.port, serial = config.serial] { return open(port, serial); };
    auto driver = std::make_unique<uls::Driver>(std::move(link).value(), options, reopen);
    auto info = driver->info();
    if (!info) return make_error(info.error().code, config.port + ": " + info.error().message);
    std::lock_guard lock(session_.mutex);
    session_.identity = {{"version", info->version, ""}};
    session_.status = status_fields(info->status);
    driver_ = std::move(driver);
    return ok_status();
  }

  [[nodiscard]] bool connected() const override { return driver_ != nullptr; }

  bool pump(std::chrono::milliseconds wait) override {
    if (!streaming_) return false;
    drain(*stream_, session_, publisher_, wait);
    return true;
  }

  Status set_streaming(Session& /*session*/, bool on) override {
    if (on == streaming_) return ok_status();
    if (on) {
      auto started = start();
      if (!started) return started;
    } else {
      stream_->stop(uls::AfterStream::stop_measuring);  // the user's Stop: ST (§8)
      drain(*stream_, session_, publisher_, std::chrono::milliseconds(0));
      stream_.reset();
      streaming_ = false;
      read_status();
    }
    std::lock_guard lock(session_.mutex);
    session_.streaming = on;
    return ok_status();
  }

  Result<std::vector<Field>> read_settings(Session& session) override {
    return paused([&] { return read_fields(*driver_, session); });
  }

  Result<std::vector<Field>> write_settings(Session& session, const SettingValues& values) override {
    return paused([&] { return write_fields(*driver_, session, values); });
  }

  Result<ActionResult> act(Session& session, std::string_view action, std::string_view argument) override {
    if (action == "start" || action == "stop") {
      if (auto changed = set_streaming(session, action == "start"); !changed) return std::move(changed).error();
      return ActionResult{};
    }
    return paused([&] { return unit_action(*driver_, session, action, argument); });
  }

  Result<std::string> export_config(Session& session) override {
    return paused([&] { return export_fields(*driver_, session); });
  }

  Result<std::vector<Field>> import_config(Session& session, std::string_view toml) override {
    return paused([&] { return import_fields(*driver_, session, toml); });
  }

  void shutdown() override {
    stream_.reset();  // U86: as the service found it (the stream's destructor ends it as_found)
    streaming_ = false;
    driver_.reset();
  }

 private:
  // Settings answer 31 while measuring (U24): the stream ends as found, the call runs, the stream starts again.
  template <class F>
  auto paused(F&& call) -> decltype(call()) {
    const bool was_streaming = streaming_;
    if (was_streaming) {
      stream_->stop(uls::AfterStream::as_found);
      drain(*stream_, session_, publisher_, std::chrono::milliseconds(0));
      stream_.reset();
      streaming_ = false;
    }
    auto result = call();
    if (was_streaming) {
      if (auto restarted = start(); !restarted) {
        std::lock_guard lock(session_.mutex);
        session_.streaming = false;
        publisher_.publish(session_, make_event(StreamEventKind::device_error,
                                                "stream not restarted: " + restarted.error().describe()));
      }
    }
    return result;
  }

  // A streaming unit measures (the stream finds it measuring or sends GO) and is not asked US
  // while its lines arrive (U123): its status is the one US gives for measuring in its mode.
  Status start() {
    auto mode = driver_->mode();
    if (!mode) return std::move(mode).error();
    auto started = driver_->start_stream(uls::StreamMode::automatic);
    if (!started) return std::move(started).error();
    stream_ = std::move(started).value();
    streaming_ = true;
    const auto status = uls::decode_status(uls::wire_value(uls::status_for(true, *mode)));
    std::lock_guard lock(session_.mutex);
    session_.status = status_fields(status);
    return ok_status();
  }

  // US read again once the unit is idle to the host (no stream): what it says now.
  void read_status() {
    auto status = driver_->status();
    if (!status) return;  // the call that needed it reports the link's trouble
    std::lock_guard lock(session_.mutex);
    session_.status = status_fields(*status);
  }

  Session& session_;
  Publisher& publisher_;
  PortOpener open_;
  std::unique_ptr<uls::Driver> driver_;
  std::unique_ptr<uls::MeasurementStream> stream_;  // declared after the driver: destroyed first
  bool streaming_ = false;
};

// Units on one RS-485 line (§7): the service polls the streaming ones in turn
// (US, then BM, as the Interface Program's network poll) and runs commands
// between two polls, addressed to their unit.
class UlsBusBackend final : public Backend {
 public:
  UlsBusBackend(std::vector<Session*> sessions, Publisher& publisher, PortOpener open)
      : sessions_(std::move(sessions)),
        publisher_(publisher),
        open_(std::move(open)),
        answering_(sessions_.size(), true),
        retry_at_(sessions_.size()),
        next_poll_at_(sessions_.size()),
        plans_(sessions_.size()),
        last_look_down_(sessions_.size()) {}

  Status connect() override {
    const SensorConfig& first = sessions_.front()->config;
    auto link = open_(first.port, first.serial);
    if (!link) return std::move(link).error();
    // The driver's usual per-call timeout, not a scan's 150 ms: commands to a unit that is there
    // must not fail on a loaded host. A unit that stays silent is asked again only every few seconds.
    uls::BusOptions options;
    options.timeout = std::chrono::milliseconds(1000);
    auto bus = std::make_unique<uls::Bus>(std::move(link).value(), options);
    std::vector<std::uint8_t> addresses;
    for (const Session* session : sessions_) addresses.push_back(static_cast<std::uint8_t>(*session->config.address));
    // The scan lists the units that answered, in the order asked: a silent one is not in it,
    // so each answer is matched to its session by address.
    std::vector<uls::BusUnit> units(sessions_.size());
    for (std::size_t i = 0; i < sessions_.size(); ++i) units[i].address = addresses[i];
    for (uls::BusUnit& unit : bus->scan(addresses)) {
      const auto at = std::find(addresses.begin(), addresses.end(), unit.address);
      if (at != addresses.end()) units[static_cast<std::size_t>(at - addresses.begin())] = std::move(unit);
    }
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      Session& session = *sessions_[i];
      const uls::BusUnit& unit = units[i];
      answering_[i] = unit.answered && !unit.duplicate;
      std::lock_guard lock(session.mutex);
      session.identity = {{"version", unit.version, ""}, {"address", uls::address_text(unit.address), ""}};
      if (unit.status) session.status = status_fields(*unit.status);
    }
    // §7: "The Continuous Output setting must be turned off since units only talk on the bus
    // when addressed." A unit with CO on talks unasked once it measures, and its lines collide
    // with the replies of the others: said once, not changed behind the user's back.
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      if (!answering_[i]) continue;
      if (bus->driver().set_address(units[i].address) && bus->driver().continuous().value_or(false)) {
        publisher_.publish(*sessions_[i],
                           make_event(StreamEventKind::device_error,
                                      "continuous output is on: on an RS-485 bus it must be off, or this unit "
                                      "talks unasked and collides with the others; set continuous=off"));
      }
    }
    for (auto& plan : plans_) plan.reset();  // read again from the units as they are now
    bus_ = std::move(bus);
    // Units that did not answer are reported on their own; the port itself is up.
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      if (!answering_[i]) {
        publisher_.publish(*sessions_[i], make_event(StreamEventKind::disconnected,
                                                     "no answer at address " + uls::address_text(units[i].address)));
      }
    }
    return ok_status();
  }

  [[nodiscard]] bool connected() const override { return bus_ != nullptr; }
  [[nodiscard]] bool answering(const Session& session) const override {
    const auto at = std::find(sessions_.begin(), sessions_.end(), &session);
    return at != sessions_.end() && answering_[static_cast<std::size_t>(at - sessions_.begin())];
  }

  bool pump(std::chrono::milliseconds /*wait*/) override {
    // The next unit due after the last one polled: every unit gets its turn.
    const auto now = std::chrono::steady_clock::now();
    for (std::size_t step = 0; step < sessions_.size(); ++step) {
      next_ = (next_ + 1) % sessions_.size();
      if (!streaming(next_) || now < due_at(next_)) continue;
      poll(next_);
      return true;
    }
    return false;
  }

  [[nodiscard]] std::optional<std::chrono::steady_clock::time_point> next_due() const override {
    std::optional<std::chrono::steady_clock::time_point> earliest;
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      if (streaming(i) && (!earliest || due_at(i) < *earliest)) earliest = due_at(i);
    }
    return earliest;
  }

  Status set_streaming(Session& session, bool on) override {
    std::lock_guard lock(session.mutex);
    session.streaming = on;  // polled from the next round on
    return ok_status();
  }

  Result<std::vector<Field>> read_settings(Session& session) override {
    return addressed(session, [&](uls::Driver& driver) { return read_fields(driver, session); });
  }

  Result<std::vector<Field>> write_settings(Session& session, const SettingValues& values) override {
    forget_plan(session);  // PF, PO or MM may change the output period
    return addressed(session, [&](uls::Driver& driver) { return write_fields(driver, session, values); });
  }

  Result<ActionResult> act(Session& session, std::string_view action, std::string_view argument) override {
    if (action == "start" || action == "stop") {
      if (auto changed = set_streaming(session, action == "start"); !changed) return std::move(changed).error();
      return ActionResult{};
    }
    forget_plan(session);  // a reset restores the default rates
    return addressed(session, [&](uls::Driver& driver) { return unit_action(driver, session, action, argument); });
  }

  Result<std::string> export_config(Session& session) override {
    return addressed(session, [&](uls::Driver& driver) { return export_fields(driver, session); });
  }

  Result<std::vector<Field>> import_config(Session& session, std::string_view toml) override {
    forget_plan(session);
    return addressed(session, [&](uls::Driver& driver) { return import_fields(driver, session, toml); });
  }

  // One address at a time, the commands and the poll of the units served in between: a silent
  // address costs scan_wait, eight of them more than a whole poll cycle.
  Result<std::vector<BusUnitFound>> scan_bus(const std::vector<std::uint8_t>& addresses) override {
    std::vector<BusUnitFound> found;
    for (const std::uint8_t address : addresses) {
      if (!bus_) return make_error(Errc::closed, "the bus went away during the scan");
      const auto started = Clock::now();
      for (const uls::BusUnit& unit : bus_->scan({address}, scan_wait)) {
        found.push_back({unit.address, unit.version, unit.duplicate, unit.problem});
      }
      between_steps(Clock::now() - started);
    }
    return found;
  }

  // `rangekit uls bus assign --from FROM --to TO`: refused when a unit answers at `to` (§7).
  // A measuring unit refuses settings with 31 (U24): stopped for UA, started again at its new address.
  Status assign_address(std::uint8_t from, std::uint8_t to) override {
    uls::Driver& driver = bus_->driver();
    (void)driver.set_address(from);
    auto status = driver.status();
    const bool measuring = status && status->measuring();
    if (measuring) {
      if (auto stopped = driver.stop_measuring(); !stopped) return stopped;
    }
    Status assigned = bus_->assign(from, to);
    (void)driver.set_address(assigned ? to : from);
    if (measuring) {
      if (auto restarted = driver.start_measuring(); !restarted && assigned) assigned = std::move(restarted).error();
    }
    return assigned;
  }

  void shutdown() override {
    for (Session* session : sessions_) {
      std::lock_guard lock(session->mutex);
      session->streaming = false;
    }
    bus_.reset();
  }

 private:
  template <class F>
  auto addressed(Session& session, F&& call) -> decltype(call(std::declval<uls::Driver&>())) {
    uls::Driver& driver = bus_->driver();
    if (auto moved = driver.set_address(static_cast<std::uint8_t>(*session.config.address)); !moved) {
      return std::move(moved).error();
    }
    return call(driver);
  }

  using Clock = std::chrono::steady_clock;

  [[nodiscard]] bool streaming(std::size_t index) const {
    std::lock_guard lock(sessions_[index]->mutex);
    return sessions_[index]->streaming;
  }
  // A silent unit is asked again every few seconds; one that answers once per output period.
  [[nodiscard]] Clock::time_point due_at(std::size_t index) const {
    return answering_[index] ? next_poll_at_[index] : retry_at_[index];
  }
  void forget_plan(const Session& session) {
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      if (sessions_[i] == &session) plans_[i].reset();
    }
  }
  // The unit's output period (U110), read again after anything that may have changed it.
  const uls::Driver::PollPlan& plan_of(std::size_t index) {
    if (!plans_[index]) {
      uls::Driver& driver = bus_->driver();
      auto mode = driver.mode();
      auto plan = mode ? driver.poll_plan(*mode) : Result<uls::Driver::PollPlan>(std::move(mode).error());
      if (!plan) return fallback_plan;  // read again before the next poll
      plans_[index] = *plan;
      last_look_down_[index].reset();
    }
    return *plans_[index];
  }

  void poll(std::size_t index) {
    Session& session = *sessions_[index];
    const auto address = static_cast<std::uint8_t>(*session.config.address);
    (void)bus_->driver().set_address(address);
    const uls::Driver::PollPlan plan = plan_of(index);
    const uls::PollResult result = bus_->poll_unit(address, true);
    if (!result.answered) {
      if (result.error && (result.error->code == Errc::io || result.error->code == Errc::closed)) {
        bus_.reset();  // the port itself went away: the worker reconnects every unit
        return;
      }
      retry_at_[index] = std::chrono::steady_clock::now() + silent_retry_interval;
      if (answering_[index]) {
        answering_[index] = false;
        publisher_.publish(session, make_event(StreamEventKind::disconnected,
                                               "no answer at address " + uls::address_text(address) +
                                                   (result.problem.empty() ? "" : ": " + result.problem)));
      }
      return;
    }
    if (!answering_[index]) {
      answering_[index] = true;
      publisher_.publish(session, make_event(StreamEventKind::reconnected, "answers again"));
    }
    if (result.status) {
      std::lock_guard lock(session.mutex);
      session.status = status_fields(*result.status);
    }
    // The next BM one output period after this one was answered (U89, U110).
    next_poll_at_[index] = Clock::now() + plan.period;
    if (result.sample) {
      // Look down is reported by its changes (U87): the same answer again is no new edge.
      if (plan.look_down) {
        const bool repeat =
            last_look_down_[index] && uls::same_look_down_answer(*last_look_down_[index], *result.sample);
        last_look_down_[index] = *result.sample;
        if (repeat) return;
      }
      publisher_.publish(session, *result.sample);
    } else if (result.error) {
      publisher_.publish(session, make_event(StreamEventKind::device_error, result.error->describe()));
    }
  }

  std::vector<Session*> sessions_;
  Publisher& publisher_;
  PortOpener open_;
  std::vector<bool> answering_;
  std::vector<std::chrono::steady_clock::time_point> retry_at_;  // when a silent unit is asked again
  std::vector<Clock::time_point> next_poll_at_;
  std::vector<std::optional<uls::Driver::PollPlan>> plans_;
  std::vector<std::optional<Sample>> last_look_down_;      // the previous answer of a unit in look down
  static constexpr uls::Driver::PollPlan fallback_plan{};  // 100 ms while the plan cannot be read
  static constexpr std::chrono::seconds silent_retry_interval{2};
  // A scan's wait at each address: a silent one costs this much (a unit answers in a few ms).
  static constexpr std::chrono::milliseconds scan_wait{200};
  std::unique_ptr<uls::Bus> bus_;
  std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<hub::Backend> make_port_backend(std::vector<hub::Session*> sessions, hub::Publisher& publisher,
                                                const hub::PortOpener& open) {
  const bool bus = sessions.size() > 1 || sessions.front()->config.address.has_value();
  if (bus) return std::make_unique<UlsBusBackend>(std::move(sessions), publisher, open);
  return std::make_unique<UlsBackend>(*sessions.front(), publisher, open);
}

}  // namespace rangekit::uls::service
