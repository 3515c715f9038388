// A ULS alone on its port (stream: continuous lines or polled BM, §2 Continuous
// Output), or several on an RS-485 bus (§7: the network poll, one unit after
// another). Settings go through the config-file table and load_config, which
// stops a measuring unit, uploads, reads back and restarts it (U24).
#include <memory>

#include "hub/session.hpp"
#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/host_config.hpp"

namespace rangekit::hub {
namespace {

// "10.5 m" -> {"10.5", "m"}; "binning" -> {"binning", ""}.
Field field_of(const uls::Setting& setting) {
  const std::string text = uls::readable(setting);
  const std::size_t space = text.rfind(' ');
  if (space == std::string::npos) return {std::string(setting.command->cli_name), text, ""};
  return {std::string(setting.command->cli_name), text.substr(0, space), text.substr(space + 1)};
}

std::vector<Field> status_fields(const uls::StatusInfo& status) {
  const auto yes_no = [](bool on) { return std::string(on ? "yes" : "no"); };
  std::vector<Field> fields{{"status", std::to_string(status.value), ""},
                            {"active", yes_no(status.active), ""},
                            {"laser-firing", yes_no(status.laser_firing), ""},
                            {"averaging", yes_no(status.averaging_calc), ""},
                            {"binning", yes_no(status.binning_calc), ""}};
  return fields;
}

Result<std::vector<Field>> read_fields(uls::Driver& driver, Session& session) {
  auto config = uls::read_config(driver);
  if (!config) return std::move(config).error();
  std::vector<Field> fields;
  for (const uls::Setting& setting : config->settings) fields.push_back(field_of(setting));
  std::lock_guard lock(session.mutex);
  session.settings = fields;
  return fields;
}

Result<std::vector<Field>> write_fields(uls::Driver& driver, Session& session, const SettingValues& values) {
  uls::DeviceConfig wanted;
  for (const auto& [name, text] : values) {  // every value checked before anything is sent
    auto setting = uls::setting_from_text(name, text);
    if (!setting) return std::move(setting).error();
    wanted.settings.push_back(std::move(*setting));
  }
  auto report = uls::load_config(driver, wanted);
  if (!report) return std::move(report).error();
  if (!report->mismatches.empty()) {
    const auto& first = report->mismatches.front();
    return make_error(Errc::device_error, std::string(first.command->cli_name) + " reads back as " + first.actual +
                                              ", not " + first.wanted);
  }
  return read_fields(driver, session);
}

std::string sample_text(const Sample& sample) {
  if (sample.device_error) return "error " + std::to_string(*sample.device_error);
  if (sample.distance_m) return std::to_string(*sample.distance_m) + " m";
  if (!sample.targets.empty()) return std::to_string(sample.targets.size()) + " targets";
  if (sample.presence) return *sample.presence ? "ON" : "OFF";
  return "";
}

// Actions on one unit that need no stream of their own.
Result<std::string> unit_action(uls::Driver& driver, Session& session, Action action, std::string_view argument) {
  const auto done = [](Status status) -> Result<std::string> {
    if (!status) return std::move(status).error();
    return std::string();
  };
  switch (action) {
    case Action::single: {
      auto sample = driver.measure();
      if (!sample) return std::move(sample).error();
      return sample_text(*sample);
    }
    case Action::pointer:
      if (argument != "on" && argument != "off") {
        return make_error(Errc::out_of_range, "pointer takes on or off (§8 PT), not '" + std::string(argument) + "'");
      }
      return done(driver.set_pointer(argument == "on"));
    case Action::save:
      return done(driver.save());
    case Action::reset: {
      auto report = uls::load_config(driver, uls::factory_config());
      if (!report) return std::move(report).error();
      auto fields = read_fields(driver, session);
      if (!fields) return std::move(fields).error();
      return std::string();
    }
    case Action::read: {
      auto fields = read_fields(driver, session);
      if (!fields) return std::move(fields).error();
      return std::string();
    }
    case Action::latch:
    case Action::start:
    case Action::stop:
      break;
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
    drain(*driver_, session_, publisher_, wait);
    return true;
  }

  Status set_streaming(Session& /*session*/, bool on) override {
    if (on == streaming_) return ok_status();
    if (on) {
      if (auto started = driver_->start_stream(uls::StreamMode::automatic); !started) return started;
    } else {
      driver_->stop_stream(uls::AfterStream::stop_measuring);  // the user's Stop: ST (§8)
      drain(*driver_, session_, publisher_, std::chrono::milliseconds(0));
    }
    streaming_ = on;
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

  Result<std::string> act(Session& session, Action action, std::string_view argument) override {
    if (action == Action::start || action == Action::stop) {
      if (auto changed = set_streaming(session, action == Action::start); !changed) return std::move(changed).error();
      return std::string();
    }
    return paused([&] { return unit_action(*driver_, session, action, argument); });
  }

  void shutdown() override {
    if (streaming_) driver_->stop_stream(uls::AfterStream::as_found);  // U86: as the service found it
    streaming_ = false;
    driver_.reset();
  }

 private:
  // Settings answer 31 while measuring (U24): the stream ends as found, the call runs, the stream starts again.
  template <class F>
  auto paused(F&& call) -> decltype(call()) {
    const bool was_streaming = streaming_;
    if (was_streaming) {
      driver_->stop_stream(uls::AfterStream::as_found);
      drain(*driver_, session_, publisher_, std::chrono::milliseconds(0));
      streaming_ = false;
    }
    auto result = call();
    if (was_streaming) {
      if (auto restarted = driver_->start_stream(uls::StreamMode::automatic); restarted) {
        streaming_ = true;
      } else {
        std::lock_guard lock(session_.mutex);
        session_.streaming = false;
        publisher_.publish(session_, make_event(StreamEventKind::device_error,
                                                "stream not restarted: " + restarted.error().describe()));
      }
    }
    return result;
  }

  Session& session_;
  Publisher& publisher_;
  PortOpener open_;
  std::unique_ptr<uls::Driver> driver_;
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
        answering_(sessions_.size(), true) {}

  Status connect() override {
    const SensorConfig& first = sessions_.front()->config;
    auto link = open_(first.port, first.serial);
    if (!link) return std::move(link).error();
    auto bus = std::make_unique<uls::Bus>(std::move(link).value());
    std::vector<std::uint8_t> addresses;
    for (const Session* session : sessions_) addresses.push_back(static_cast<std::uint8_t>(*session->config.address));
    const auto units = bus->scan(addresses);
    for (std::size_t i = 0; i < sessions_.size(); ++i) {
      Session& session = *sessions_[i];
      const uls::BusUnit& unit = units[i];
      answering_[i] = unit.answered && !unit.duplicate;
      std::lock_guard lock(session.mutex);
      session.identity = {{"version", unit.version, ""}, {"address", uls::address_text(unit.address), ""}};
      if (unit.status) session.status = status_fields(*unit.status);
    }
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

  bool pump(std::chrono::milliseconds /*wait*/) override {
    // The next polling unit after the last one polled: every unit gets its turn.
    for (std::size_t step = 0; step < sessions_.size(); ++step) {
      next_ = (next_ + 1) % sessions_.size();
      Session& session = *sessions_[next_];
      {
        std::lock_guard lock(session.mutex);
        if (!session.streaming) continue;
      }
      poll(next_);
      return true;
    }
    return false;
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
    return addressed(session, [&](uls::Driver& driver) { return write_fields(driver, session, values); });
  }

  Result<std::string> act(Session& session, Action action, std::string_view argument) override {
    if (action == Action::start || action == Action::stop) {
      if (auto changed = set_streaming(session, action == Action::start); !changed) return std::move(changed).error();
      return std::string();
    }
    return addressed(session, [&](uls::Driver& driver) { return unit_action(driver, session, action, argument); });
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

  void poll(std::size_t index) {
    Session& session = *sessions_[index];
    const auto address = static_cast<std::uint8_t>(*session.config.address);
    const auto results = bus_->poll({address}, true);
    const uls::PollResult& result = results.front();
    if (!result.answered) {
      if (result.error && (result.error->code == Errc::io || result.error->code == Errc::closed)) {
        bus_.reset();  // the port itself went away: the worker reconnects every unit
        return;
      }
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
    if (result.sample) {
      publisher_.publish(session, *result.sample);
    } else if (result.error) {
      publisher_.publish(session, make_event(StreamEventKind::device_error, result.error->describe()));
    }
  }

  std::vector<Session*> sessions_;
  Publisher& publisher_;
  PortOpener open_;
  std::vector<bool> answering_;
  std::unique_ptr<uls::Bus> bus_;
  std::size_t next_ = 0;
};

}  // namespace

std::unique_ptr<Backend> make_uls_backend(Session& session, Publisher& publisher, const PortOpener& open) {
  return std::make_unique<UlsBackend>(session, publisher, open);
}

std::unique_ptr<Backend> make_uls_bus_backend(std::vector<Session*> sessions, Publisher& publisher,
                                              const PortOpener& open) {
  return std::make_unique<UlsBusBackend>(std::move(sessions), publisher, open);
}

}  // namespace rangekit::hub
