// An LS5 on a serial port (§8.13 stream, table 9.1/9.2 commands) or heard over UDP (§10).
#include <algorithm>
#include <array>
#include <memory>
#include <optional>

#include "ls5/service/service.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/host_config.hpp"
#include "rangekit/ls5/host_settings.hpp"
#include "rangekit/ls5/udp_packet_reader.hpp"

namespace rangekit::ls5::service {
namespace {

using namespace rangekit::hub;

// The service's stream: the reader lets 3 ms of records collect in the port per read and
// hands each read's batch straight to the port worker (no consumer gather on top, which
// cost the worker a second sleep per batch). At 1 kHz: about one wake-up of each thread per
// three records, and 3 ms less latency than the CLI's 2 + 2 ms (docs/mqtt.md, Figures).
ls5::Driver::StreamOptions service_stream_options() {
  ls5::Driver::StreamOptions options;
  options.gather = std::chrono::microseconds(0);
  options.read_gather = std::chrono::microseconds(3000);
  return options;
}

std::string number_text(double value) {
  std::string text = std::to_string(value);
  text.erase(text.find_last_not_of('0') + 1);
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

std::vector<Field> fields_of(const std::vector<ls5::Driver::NamedValue>& values) {
  std::vector<Field> fields;
  fields.reserve(values.size());
  for (const auto& value : values) fields.push_back({value.name, value.text, std::string(value.unit)});
  return fields;
}

// An LR or FR answer as the page and the API show it: "25.3 mm (code 31629)".
std::string describe(const ls5::Measurement& result) {
  const std::string code = " (code " + std::to_string(result.code.value) + ")";
  if (result.distance_mm) return number_text(*result.distance_mm) + " mm" + code;
  if (result.derivative_mm) return number_text(*result.derivative_mm) + " mm (derivative)" + code;
  if (result.code.kind == ls5::CodeKind::no_signal) return "no signal" + code;                    // §8.9: 65535
  if (result.code.kind == ls5::CodeKind::no_measurement_yet) return "no measurement yet" + code;  // 65534
  return "code " + std::to_string(result.code.value);
}

class Ls5Backend final : public Backend {
 public:
  Ls5Backend(Session& session, Publisher& publisher, PortOpener open)
      : session_(session), publisher_(publisher), open_(std::move(open)) {}

  Status connect() override {
    const SensorConfig& config = session_.config;
    auto link = open_(config.port, config.serial);
    if (!link) return std::move(link).error();
    ls5::DriverOptions options;
    options.address = static_cast<std::uint8_t>(config.address.value_or(1));
    auto reopen = [open = open_, port = config.port, serial = config.serial] { return open(port, serial); };
    auto driver = std::make_unique<ls5::Driver>(std::move(link).value(), options, reopen);
    auto info = driver->info();
    if (!info) return make_error(info.error().code, config.port + ": " + info.error().message);
    const ls5::Identification& id = info->identification;
    range_mm_ = id.range_mm;
    std::lock_guard lock(session_.mutex);
    // The names `info --json` prints: the unit is the name's last word.
    session_.identity = {{"version", std::string(id.version_text.view()), ""},
                         {"lower-boundary-mm", number_text(id.lower_boundary_mm), "mm"},
                         {"range-mm", number_text(id.range_mm), "mm"},
                         {"serial", std::to_string(id.serial_number), ""},
                         {"ethernet", info->ethernet ? "yes" : "no", ""}};
    driver_ = std::move(driver);
    return ok_status();
  }

  [[nodiscard]] bool connected() const override { return driver_ != nullptr; }

  bool pump(std::chrono::milliseconds wait) override {
    if (!stream_) return false;
    drain(*stream_, session_, publisher_, wait);
    return true;
  }

  Status set_streaming(Session& /*session*/, bool on) override {
    if (on == (stream_ != nullptr)) return ok_status();
    if (on) {
      auto stream = driver_->start_stream(service_stream_options());
      if (!stream) return std::move(stream).error();
      stream_ = std::move(stream).value();
    } else {
      stream_->stop();  // SB; what was queued still goes out first
      drain(*stream_, session_, publisher_, std::chrono::milliseconds(0));
      stream_.reset();
    }
    std::lock_guard lock(session_.mutex);
    session_.streaming = on;
    return ok_status();
  }

  Result<std::vector<Field>> read_settings(Session& /*session*/) override {
    return paused([&]() -> Result<std::vector<Field>> {
      auto values = driver_->read_all_settings();
      if (!values) return std::move(values).error();
      auto fields = fields_of(*values);
      std::lock_guard lock(session_.mutex);
      session_.settings = fields;
      return fields;
    });
  }

  Result<std::vector<Field>> write_settings(Session& session, const SettingValues& values) override {
    return paused([&]() -> Result<std::vector<Field>> {
      auto context = driver_->context();
      if (!context) return std::move(context).error();
      // Every value checked before the first byte goes out (table 9.2 ranges, firmware).
      std::vector<std::pair<const ls5::HostSetting*, ls5::ParameterWrites>> planned;
      for (const auto& [name, text] : values) {
        const ls5::HostSetting* setting = ls5::find_host_setting(name);
        if (setting == nullptr) return make_error(Errc::unknown_parameter, "no LS5 setting named '" + name + "'");
        if (setting->link) {
          return make_error(Errc::unsupported, name +
                                                   " changes how the service reaches the sensor: change it in the site "
                                                   "file and with `rangekit ls5 set`");
        }
        if (auto available = ls5::check_setting_available(*setting, context->model); !available) {
          return std::move(available).error();
        }
        auto writes = ls5::encode_setting(*setting, text, *context);
        if (!writes) return writes.error();  // its message names the setting and the allowed values
        planned.emplace_back(setting, *writes);
      }
      for (std::size_t i = 0; i < planned.size(); ++i) {
        if (auto written = driver_->set(*planned[i].first, values[i].second); !written)
          return std::move(written).error();
      }
      // Read back: every byte as written, else the sensor kept something else.
      for (const auto& [setting, writes] : planned) {
        auto reading = driver_->get(*setting);
        if (!reading) return std::move(reading).error();
        const auto addresses = setting->addresses();
        for (const ls5::ParameterWrite& write : writes.view()) {
          for (std::size_t b = 0; b < addresses.size(); ++b) {
            if (addresses[b] == write.address && reading->bytes[b] != write.value) {
              return make_error(Errc::device_error,
                                std::string(setting->name) + " reads back as " + reading->text + " after the write");
            }
          }
        }
      }
      auto all = read_settings(session);
      return all;
    });
  }

  Result<ActionResult> act(Session& session, std::string_view action, std::string_view argument) override {
    if (action == "start" || action == "stop") {
      if (auto changed = set_streaming(session, action == "start"); !changed) return std::move(changed).error();
      return ActionResult{};
    }
    if (action == "read") {
      auto settings = read_settings(session);
      if (!settings) return std::move(settings).error();
      return ActionResult{};
    }
    if (action == "single") {
      return paused([&]() -> Result<ActionResult> {
        auto last = driver_->measure();  // LR
        if (!last) return std::move(last).error();
        return answer(*last);
      });
    }
    if (action == "save") return simple([&] { return driver_->store_to_flash(); });
    if (action == "reset") return simple([&] { return driver_->restore_defaults(); });
    if (action == "latch") {
      // FX then FR (table 9.1), as `rangekit ls5 latch` does; argument "read": FR alone.
      return paused([&]() -> Result<ActionResult> {
        if (argument != "read") {
          if (auto latched = driver_->latch(); !latched) return std::move(latched).error();
        }
        auto result = driver_->read_latched();
        if (!result) return std::move(result).error();
        return answer(*result);
      });
    }
    return refused(session_, action);
  }

  Result<std::string> export_config(Session& /*session*/) override {
    return paused([&]() -> Result<std::string> {
      auto config = ls5::read_device_config(*driver_);
      if (!config) return std::move(config).error();
      return ls5::config_to_toml(*config);
    });
  }

  Result<std::vector<Field>> import_config(Session& session, std::string_view toml) override {
    auto file = ls5::parse_config_toml(toml, "the uploaded configuration");
    if (!file) return std::move(file).error();
    return paused([&]() -> Result<std::vector<Field>> {
      auto report = ls5::upload_config(*driver_, *file);  // every value checked before the first is sent
      if (!report) return std::move(report).error();
      if (!report->mismatches.empty()) {
        const auto& first = report->mismatches.front();
        return make_error(Errc::device_error, std::string(first.setting->name) + " reads back as " +
                                                  first.device_value + ", not " + first.file_value);
      }
      return read_settings(session);
    });
  }

  void shutdown() override {
    if (stream_) {
      stream_->stop();
      drain(*stream_, session_, publisher_, std::chrono::milliseconds(0));
      stream_.reset();
    }
    driver_.reset();
  }

 private:
  // The stream holds the line (any byte would stop it, L37): stopped for the call, started again after.
  template <class F>
  auto paused(F&& call) -> decltype(call()) {
    const bool was_streaming = stream_ != nullptr;
    if (was_streaming) {
      if (auto stopped = set_streaming(session_, false); !stopped) return std::move(stopped).error();
    }
    auto result = call();
    if (was_streaming) {
      if (auto restarted = set_streaming(session_, true); !restarted) {
        publisher_.publish(session_, make_event(StreamEventKind::device_error,
                                                "stream not restarted: " + restarted.error().describe()));
      }
    }
    return result;
  }

  template <class F>
  Result<ActionResult> simple(F&& call) {
    return paused([&]() -> Result<ActionResult> {
      if (auto done = call(); !done) return std::move(done).error();
      return ActionResult{};
    });
  }

  // An LR or FR answer as text and as the sample a stream would have given for it.
  ActionResult answer(const ls5::Measurement& result) const {
    return {describe(result), ls5::make_ls5_sample(result.code, range_mm_, session_.config.port,
                                                   session_.config.address.value_or(1), result.derivative)};
  }

  Session& session_;
  Publisher& publisher_;
  PortOpener open_;
  std::unique_ptr<ls5::Driver> driver_;
  std::unique_ptr<ls5::MeasurementStream> stream_;
  std::optional<double> range_mm_;  // from the identification: the formulas need it
};

// An Ethernet LS5 heard over UDP only (§10): samples, no commands. Its worker reads the
// socket itself: a packet goes to the hub without a reader thread or queue in between.
class Ls5UdpBackend final : public Backend {
 public:
  Ls5UdpBackend(Session& session, Publisher& publisher)
      : session_(session), publisher_(publisher), reader_(session.config.address.value_or(-1)) {}

  Status connect() override {
    auto endpoint = parse_endpoint(session_.config.udp);
    if (!endpoint) return std::move(endpoint).error();
    auto socket = UdpSocket::bind(*endpoint);
    if (!socket) return std::move(socket).error();
    socket_ = std::move(socket).value();
    std::lock_guard lock(session_.mutex);
    session_.identity = {{"udp", socket_->local_endpoint().to_string(), ""}};
    session_.streaming = true;
    return ok_status();
  }
  [[nodiscard]] bool connected() const override { return socket_.has_value(); }
  bool pump(std::chrono::milliseconds wait) override {
    if (!socket_) return false;
    // Nothing but `start` is asked of a listener: it may wait longer than the worker offers,
    // up to the spike check's hold limit, so that an idle sensor wakes ten times a second.
    auto got = socket_->receive(buffer_, std::max(wait, listen_slice));
    if (!got) {
      if (got.error().code == Errc::timeout) return true;
      if (got.error().code == Errc::overlong) {  // larger than 512 bytes: not an LS5 packet
        reader_.read_overlong(got.error().message, items_);
      } else {
        items_.emplace_back(make_event(StreamEventKind::disconnected, "UDP socket: " + got.error().message));
        socket_.reset();  // the worker binds it again
      }
      publisher_.publish_batch(session_, items_);
      return true;
    }
    reader_.read(Bytes(buffer_.data(), got->size), got->from, items_);
    publisher_.publish_batch(session_, items_);
    return true;
  }
  Status set_streaming(Session& /*session*/, bool on) override {
    if (on) return ok_status();
    return make_error(Errc::unsupported,
                      "an LS5 heard over UDP only is always listened to; give it a port for commands");
  }
  [[nodiscard]] bool has_settings() const override { return false; }
  Result<std::vector<Field>> read_settings(Session& /*session*/) override { return no_port(); }
  Result<std::vector<Field>> write_settings(Session& /*session*/, const SettingValues& /*values*/) override {
    return no_port();
  }
  Result<ActionResult> act(Session& session, std::string_view action, std::string_view /*argument*/) override {
    if (action == "start") return ActionResult{};
    return refused(session, action);
  }
  Result<std::string> export_config(Session& /*session*/) override { return no_port(); }
  Result<std::vector<Field>> import_config(Session& /*session*/, std::string_view /*toml*/) override {
    return no_port();
  }
  void shutdown() override { socket_.reset(); }

 private:
  [[nodiscard]] Error no_port() const {
    return make_error(
        Errc::unsupported,
        "sensor '" + session_.config.name + "' is heard over UDP only: settings need its serial port in the site file");
  }
  static constexpr std::chrono::milliseconds listen_slice{100};
  Session& session_;
  Publisher& publisher_;
  ls5::UdpPacketReader reader_;
  std::optional<UdpSocket> socket_;
  std::array<std::uint8_t, 2048> buffer_{};
  std::vector<StreamItem> items_;  // one datagram's, storage reused
};

}  // namespace

std::unique_ptr<hub::Backend> make_port_backend(std::vector<hub::Session*> sessions, hub::Publisher& publisher,
                                                const hub::PortOpener& open) {
  return std::make_unique<Ls5Backend>(*sessions.front(), publisher, open);
}

std::unique_ptr<hub::Backend> make_udp_backend(hub::Session& session, hub::Publisher& publisher) {
  return std::make_unique<Ls5UdpBackend>(session, publisher);
}

}  // namespace rangekit::ls5::service
