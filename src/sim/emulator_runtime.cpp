#include "rangekit/sim/emulator_runtime.hpp"

#include <poll.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>

namespace rangekit {
namespace {

double seconds(Nanos time) { return static_cast<double>(time.count()) / 1e9; }

Nanos character_time(const SerialSettings& settings) {
  return Nanos(static_cast<std::int64_t>(settings.bits_per_byte()) * 1'000'000'000LL / settings.baud);
}

}  // namespace

EmulatorRuntime::EmulatorRuntime(std::vector<Line> lines, const RuntimeOptions& options)
    : lines_(std::move(lines)), options_(options), random_(options.seed) {
  if (options.virtual_clock) {
    virtual_clock_ = std::make_unique<VirtualClock>();
  } else {
    real_clock_ = std::make_unique<ScaledSteadyClock>(options.time_scale > 0 ? options.time_scale : 1.0);
  }
}

EmulatorRuntime::~EmulatorRuntime() = default;

Result<std::unique_ptr<EmulatorRuntime>> EmulatorRuntime::create(std::vector<LineConfig> configs,
                                                                 const RuntimeOptions& options) {
  std::vector<Line> lines;
  for (auto& config : configs) {
    for (const auto& attachment : config.attachments) {
      if (attachment.device == nullptr || attachment.port >= attachment.device->port_count()) {
        return make_error(Errc::out_of_range, "line " + config.name + ": attachment names no port of a device");
      }
    }
    auto pty = PseudoTerminal::open(config.link_path);
    if (!pty) return pty.error();
    // Held open by us too, so the master never sees a hang-up while no host is connected.
    if (auto held = (*pty)->hold_slave_open(); !held) return held.error();
    lines.push_back(Line{std::move(config), std::move(*pty), {}});
  }
  auto runtime = std::unique_ptr<EmulatorRuntime>(new EmulatorRuntime(std::move(lines), options));
  if (options.control_path) {
    auto control = ControlSocket::listen(*options.control_path);
    if (!control) return control.error();
    runtime->control_ = std::move(*control);
  }
  if (options.wire_log_path) {
    runtime->wire_log_.reset(std::fopen(options.wire_log_path->c_str(), "wb"));
    if (!runtime->wire_log_) {
      return make_error(Errc::io, "wire log " + *options.wire_log_path + ": cannot be created");
    }
  }
  return runtime;
}

Nanos EmulatorRuntime::now() const { return virtual_clock_ ? virtual_clock_->now() : real_clock_->now(); }

const std::string& EmulatorRuntime::line_path(std::size_t line) const { return lines_.at(line).pty->public_path(); }

void EmulatorRuntime::set_noise(std::size_t line, const LineNoise& noise) { lines_.at(line).noise = noise; }

bool EmulatorRuntime::host_matches(const Result<SerialSettings>& host, const LineAttachment& attachment,
                                   const LineByte* sent) {
  if (!host) return true;  // cannot tell: assume the host is right
  SerialSettings device = attachment.device->port_settings(attachment.port);
  if (sent != nullptr && sent->baud != 0) device.baud = sent->baud;
  if (sent != nullptr && sent->stop_bits != 0) device.stop_bits = sent->stop_bits;
  // Parity cannot be seen through a pty (docs/conformance.md H2).
  return host->baud == device.baud && host->stop_bits == device.stop_bits;
}

std::uint8_t EmulatorRuntime::garble(std::uint8_t value) {
  // What a UART sampling at the wrong speed makes of a byte: unrelated bits.
  return static_cast<std::uint8_t>(value ^ static_cast<std::uint8_t>(random_() | 1U));
}

Status EmulatorRuntime::read_input(Nanos now) {
  for (std::size_t index = 0; index < lines_.size(); ++index) {
    // poll_fds_ starts with the lines in order: a line poll() saw nothing on costs no read().
    if (index < poll_fds_.size() && poll_fds_[index].revents == 0) continue;
    auto& line = lines_[index];
    std::uint8_t buffer[512];
    std::optional<Result<SerialSettings>> host;  // read at the first byte
    while (true) {
      const ssize_t n = ::read(line.pty->native_handle(), buffer, sizeof buffer);
      if (n <= 0) {
        if (n < 0 && errno == EINTR) continue;
        break;  // EAGAIN: nothing more now
      }
      if (!host) host = line.pty->peer_settings();
      for (const auto& attachment : line.config.attachments) {
        const bool matches = host_matches(*host, attachment);
        for (ssize_t i = 0; i < n; ++i) {
          attachment.device->receive(attachment.port, matches ? buffer[i] : garble(buffer[i]), now);
        }
      }
    }
  }
  return ok_status();
}

void EmulatorRuntime::run_devices(Nanos now) {
  // A device on several lines runs once (a handful of devices: a linear search is cheapest).
  advanced_.clear();
  for (auto& line : lines_) {
    for (const auto& attachment : line.config.attachments) {
      if (std::find(advanced_.begin(), advanced_.end(), attachment.device) != advanced_.end()) continue;
      advanced_.push_back(attachment.device);
      attachment.device->advance(now);
    }
  }
}

Status EmulatorRuntime::flush_output(Nanos now) {
  auto& taken = taken_;
  auto& merged = merged_;
  for (auto& line : lines_) {
    merged.clear();
    for (std::size_t i = 0; i < line.config.attachments.size(); ++i) {
      const auto& attachment = line.config.attachments[i];
      taken.clear();
      attachment.device->take_line_output(attachment.port, now, taken);
      for (const auto& byte : taken) merged.push_back(SourcedByte{byte, i});
    }
    if (merged.empty()) continue;
    // One device's bytes are already in order; only a bus needs merging (stable_sort allocates).
    if (line.config.attachments.size() > 1) {
      std::stable_sort(merged.begin(), merged.end(),
                       [](const SourcedByte& a, const SourcedByte& b) { return a.byte.done < b.byte.done; });
    }
    auto& wire = wire_;
    wire.clear();
    const auto host = line.pty->peer_settings();
    for (std::size_t i = 0; i < merged.size(); ++i) {
      const auto& attachment = line.config.attachments[merged[i].source];
      std::uint8_t value = merged[i].byte.value;
      // Half duplex: a byte from another device that overlaps this one in time collides with it.
      const Nanos span = character_time(attachment.device->port_settings(attachment.port));
      while (i + 1 < merged.size() && merged[i + 1].source != merged[i].source &&
             merged[i + 1].byte.done - merged[i].byte.done < span) {
        value = static_cast<std::uint8_t>(value & merged[i + 1].byte.value) ^ 0x5A;
        ++i;
      }
      if (!host_matches(host, attachment, &merged[i].byte)) value = garble(value);
      if (wire_log_) (void)std::fputc(value, wire_log_.get());
      if (line.noise.drop_rate > 0 && std::uniform_real_distribution<double>(0, 1)(random_) < line.noise.drop_rate) {
        continue;
      }
      if (line.noise.bit_error_rate > 0) {
        for (int bit = 0; bit < 8; ++bit) {
          if (std::uniform_real_distribution<double>(0, 1)(random_) < line.noise.bit_error_rate) {
            value = static_cast<std::uint8_t>(value ^ (1U << bit));
          }
        }
      }
      wire.push_back(value);
      if (line.noise.duplicate_rate > 0 &&
          std::uniform_real_distribution<double>(0, 1)(random_) < line.noise.duplicate_rate) {
        wire.push_back(value);
      }
    }
    if (wire_log_) (void)std::fflush(wire_log_.get());
    std::size_t written = 0;
    while (written < wire.size()) {
      const ssize_t n = ::write(line.pty->native_handle(), wire.data() + written, wire.size() - written);
      if (n > 0) {
        written += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      // Nobody is reading and the pty buffer is full: the bytes are lost, as on a real line.
      dropped_output_ += wire.size() - written;
      break;
    }
  }
  return ok_status();
}

Nanos EmulatorRuntime::next_deadline() const {
  Nanos earliest = Nanos::max();
  for (const auto& line : lines_) {
    for (const auto& attachment : line.config.attachments)
      earliest = std::min(earliest, attachment.device->next_deadline());
  }
  return earliest;
}

Nanos EmulatorRuntime::next_wake() const {
  Nanos earliest = Nanos::max();
  for (const auto& line : lines_) {
    for (const auto& attachment : line.config.attachments)
      earliest = std::min(earliest, attachment.device->next_wake());
  }
  return earliest;
}

Status EmulatorRuntime::advance_to(Nanos when) {
  if (!virtual_clock_) return make_error(Errc::unsupported, "advance needs the virtual clock (--virtual-clock)");
  if (when < virtual_clock_->now()) return make_error(Errc::out_of_range, "the virtual clock cannot go back");
  while (true) {
    const Nanos deadline = next_deadline();
    if (deadline > when) break;
    const Nanos at = std::max(deadline, virtual_clock_->now());
    virtual_clock_->advance_to(at);
    run_devices(at);
    if (auto flushed = flush_output(at); !flushed) return flushed;
    if (next_deadline() <= at) {
      return make_error(Errc::invalid_frame,
                        "a device did not move its deadline past " + std::to_string(seconds(at)) + " s");
    }
  }
  virtual_clock_->advance_to(when);
  run_devices(when);
  return flush_output(when);
}

namespace {
constexpr double max_advance_seconds = 86400.0;
}  // namespace

nlohmann::json EmulatorRuntime::handle_control(const nlohmann::json& request) {
  const std::string command = request.value("cmd", "");
  if (command == "status") {
    nlohmann::json lines = nlohmann::json::array();
    for (const auto& line : lines_) {
      nlohmann::json devices = nlohmann::json::array();
      for (const auto& attachment : line.config.attachments) devices.push_back(attachment.device->label());
      lines.push_back({{"name", line.config.name}, {"path", line.pty->public_path()}, {"devices", devices}});
    }
    return {{"ok", true},
            {"time_s", seconds(now())},
            {"virtual_clock", virtual_clock_ != nullptr},
            {"lines", lines},
            {"dropped_output_bytes", dropped_output_}};
  }
  if (command == "advance") {
    // At most a day a request: nanoseconds stay far inside int64, and every step is simulated.
    const auto by = control_number(request, "seconds", 0.0, max_advance_seconds, 0.0);
    if (!by) return {{"error", by.error().message}};
    auto advanced = advance_to(now() + Nanos(static_cast<std::int64_t>(*by * 1e9)));
    if (!advanced) return {{"error", advanced.error().message}};
    return {{"ok", true}, {"time_s", seconds(now())}};
  }
  if (command == "noise") {
    const std::string name = request.value("line", lines_.front().config.name);
    for (auto& line : lines_) {
      if (line.config.name != name) continue;
      // Both are probabilities per bit and per byte, so 0 to 1.
      const auto bit_error_rate = control_number(request, "bit_error_rate", 0.0, 1.0, 0.0);
      if (!bit_error_rate) return {{"error", bit_error_rate.error().message}};
      const auto drop_rate = control_number(request, "drop_rate", 0.0, 1.0, 0.0);
      if (!drop_rate) return {{"error", drop_rate.error().message}};
      const auto duplicate_rate = control_number(request, "duplicate_rate", 0.0, 1.0, 0.0);
      if (!duplicate_rate) return {{"error", duplicate_rate.error().message}};
      line.noise.bit_error_rate = *bit_error_rate;
      line.noise.drop_rate = *drop_rate;
      line.noise.duplicate_rate = *duplicate_rate;
      return {{"ok", true}, {"line", name}};
    }
    return {{"error", "noise: no line named '" + name + "'"}};
  }
  if (command == "shutdown") {
    shutdown_requested_ = true;
    return {{"ok", true}};
  }
  if (extension_) {
    nlohmann::json reply = extension_(request, now());
    if (!reply.is_null()) return reply;
  }
  return {{"error", "unknown command '" + command + "' (runtime: status, advance, noise, shutdown)"}};
}

Nanos loop_wait(Nanos until_deadline, Nanos max_wait, Nanos resolution) {
  Nanos wait = std::clamp(until_deadline, Nanos(0), max_wait);
  // Whole milliseconds (poll()) make records at 1 kHz and above leave in
  // batches (L78); ppoll() takes the wait to the nanosecond.
  if (resolution > Nanos(0)) wait = (wait + resolution - Nanos(1)) / resolution * resolution;
  return wait;
}

Status EmulatorRuntime::step(Nanos max_wait) {
  poll_fds_.clear();
  for (const auto& line : lines_) poll_fds_.push_back(pollfd{line.pty->native_handle(), POLLIN, 0});
  if (control_) control_->add_poll_fds(poll_fds_);
  Nanos wait = max_wait;
  if (real_clock_) {
    // The deadline is absolute (the device's), so a late wake never accumulates: each
    // wait is measured afresh from it.
    // A wait_resolution reproduces the old loop whole: every deadline, rounded up.
    const Nanos deadline = options_.wait_resolution > Nanos(0) ? next_deadline() : next_wake();
    if (deadline != Nanos::max()) {
      wait = loop_wait(real_clock_->real_duration(deadline - now()), max_wait, options_.wait_resolution);
    }
  }
  const auto whole_seconds = std::chrono::duration_cast<std::chrono::seconds>(wait);
  const timespec timeout{static_cast<time_t>(whole_seconds.count()), static_cast<long>((wait - whole_seconds).count())};
  if (::ppoll(poll_fds_.data(), poll_fds_.size(), &timeout, nullptr) < 0 && errno != EINTR) {
    return make_error(Errc::io, "poll failed in the emulator loop");
  }
  const Nanos current = now();
  if (auto read = read_input(current); !read) return read;
  // The control socket's fds follow the lines': nothing there costs no accept() or recv().
  const bool control_ready = std::any_of(poll_fds_.begin() + static_cast<std::ptrdiff_t>(lines_.size()),
                                         poll_fds_.end(), [](const pollfd& fd) { return fd.revents != 0; });
  if (control_ && control_ready) {
    control_->service([this](const nlohmann::json& request) { return handle_control(request); });
  }
  run_devices(current);
  return flush_output(current);
}

Status EmulatorRuntime::run(const std::atomic<bool>& stop) {
  while (!stop.load() && !shutdown_requested_) {
    if (auto stepped = step(std::chrono::milliseconds(50)); !stepped) return stepped;
  }
  return ok_status();
}

}  // namespace rangekit
