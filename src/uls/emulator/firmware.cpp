// The ULS firmware model; see firmware.hpp and docs/emulator-uls.md. Here: power, the unit's
// outputs and the control socket; the commands, ports and modes have files of their own.
#include "rangekit/uls/emulator/firmware.hpp"

#include "rangekit/sim/control_socket.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace rangekit::uls::emulator {
namespace {

double seconds(Nanos span) { return static_cast<double>(span.count()) / 1e9; }

}  // namespace

// --- Construction and power ---

Firmware::Firmware(FirmwareOptions options, Nanos now)
    : options_(std::move(options)),
      store_(options_.state_dir, options_.state_key),
      scene_(options_.scene),
      random_(options_.seed) {
  if (options_.address) factory_.address = *options_.address;
  if (auto stored = store_.load(); stored) memory_ = std::move(*stored);  // a corrupt file: factory defaults
  boot(now);
}

void Firmware::boot(Nanos now) {
  settings_ = factory_;
  if (memory_) {
    try {
      settings_ = Settings::from_json(*memory_, factory_);
    } catch (const nlohmann::json::exception&) {
      settings_ = factory_;  // unreadable memory: factory defaults
    }
  }
  for (std::size_t i = 0; i < ports_.size(); ++i) {
    ports_[i].input.clear();
    ports_[i].overrun.reset();
    ports_[i].outbox.clear();
    ports_[i].pending_baud.reset();
    ports_[i].last_line_start = Nanos(0);
    ports_[i].pacer = SerialPacer(settings_.baud[i], uls_hundredths_of_bits);
  }
  measuring_ = false;
  latest_.clear();
  polls_.clear();
  last_distance_m_.reset();
  last_error_ = 0;
  error_since_.reset();
  pointer_ = settings_.pointer_autostart;
  last_now_ = now;
  if (settings_.autostart) start_measuring(now);  // §2 ULS Autostart
}

void Firmware::power_cycle(Nanos now) { boot(now); }

std::string Firmware::label() const {
  if (settings_.address == 0) return "ULS (unassigned)";
  return std::string("ULS #") + static_cast<char>(settings_.address);
}

SerialSettings Firmware::port_settings(std::size_t port) const {
  return SerialSettings{settings_.baud[std::min<std::size_t>(port, 1)], Parity::none, 1};
}
// --- Outputs and control ---

Outputs Firmware::outputs(Nanos now) const {
  Outputs out;
  out.measuring = measuring_;
  out.laser_firing = measuring_;
  out.pointer = pointer_;
  out.trip = measuring_ && settings_.mode == Mode::look_down && present_;
  out.status = wire_value(status_for(measuring_, settings_.mode));
  out.measurements = measurements_;
  out.skipped_lines = skipped_;
  out.binning_restarts = restarts_;
  out.last_distance_m = last_distance_m_;
  out.last_error = last_error_;
  if (settings_.current_loop && measuring_) {
    // §6, §8 AT "timeout allowed before 4-20mA goes to the fault current indication": fault
    // current after AT seconds of errors 4/5, also before the run's first distance (U81); until
    // then the last distance of the run is held, 4 mA when there is none yet.
    const bool fault = error_since_ && seconds(now - *error_since_) >= settings_.fault_timeout_s;
    if (fault) {
      out.current_ma = settings_.fault_current_ma;
    } else if (last_distance_m_) {
      out.current_ma = loop_current_ma(*last_distance_m_, settings_.range_at_4ma_m, settings_.range_at_20ma_m)
                           .value_or(settings_.fault_current_ma);
    } else {
      out.current_ma = loop_min_ma;
    }
  }
  return out;
}

void Firmware::set_scene(Scene scene, Nanos now) {
  advance(now);
  scene_ = std::move(scene);
}

bool Firmware::move_target(std::size_t index, double distance_m, Nanos now) {
  advance(now);
  if (index >= scene_.targets.size()) return false;
  scene_.targets[index].motion = Motion::fixed(distance_m);
  return true;
}

void Firmware::set_no_return_fault(bool on, Nanos now) {
  advance(now);
  fault_no_return_ = on;
}

bool Firmware::set_min_pulse_width(double nanoseconds, Nanos now) {
  advance(now);
  if (!(nanoseconds >= 0.0 && nanoseconds <= max_min_pulse_width_ns)) return false;
  settings_.min_pulse_width_ns = nanoseconds;
  return true;
}

nlohmann::json Firmware::control(const nlohmann::json& request, Nanos now) {
  const std::string command = request.value("cmd", "");
  if (command == "outputs") {
    advance(now);
    const Outputs o = outputs(now);
    nlohmann::json reply{{"ok", true},
                         {"device", label()},
                         {"current_ma", o.current_ma},
                         {"trip", o.trip},
                         {"laser_firing", o.laser_firing},
                         {"pointer", o.pointer},
                         {"status", o.status},
                         {"measuring", o.measuring},
                         {"measurements", o.measurements},
                         {"skipped_lines", o.skipped_lines},
                         {"binning_restarts", o.binning_restarts},
                         {"min_pulse_width_ns", settings_.min_pulse_width_ns},
                         // What $PF holds, per mode (averaging, binning, look down), so a test can
                         // check a write from outside the link (the dashboard's PRF test).
                         {"prf_hz", {settings_.prf[0], settings_.prf[1], settings_.prf[2]}},
                         // What $TT holds, in pulses (§8 "seconds * 3000"): the page's Short Timeout
                         // (§3 "8,000 laser pulses") checked from outside the link.
                         {"trip_timeout_pulses", settings_.trip_timeout_pulses},
                         {"last_error", o.last_error}};
    reply["distance_m"] = o.last_distance_m ? nlohmann::json(*o.last_distance_m) : nlohmann::json(nullptr);
    return reply;
  }
  if (command == "set_scene") {
    if (!request.contains("scene")) return {{"error", "set_scene: needs 'scene' (an object like the TOML file)"}};
    auto scene = scene_from_json(request.at("scene"));
    if (!scene) return {{"error", "set_scene: " + scene.error().message}};
    set_scene(std::move(*scene), now);
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "move_target") {
    // The scene file's range (distance_m 0 .. 5000 m), so no value the file refuses gets in this way.
    const auto index = control_number(request, "target", 0.0, static_cast<double>(scene_.targets.size()), 0.0);
    if (!index || *index != std::floor(*index))
      return {{"error", "move_target: 'target' must be the index of one of the scene's " +
                            std::to_string(scene_.targets.size()) + " targets (0, 1, ...)"}};
    const auto distance = control_number(request, "distance_m", 0.0, max_scene_distance_m);
    if (!distance) return {{"error", distance.error().message}};
    if (!move_target(static_cast<std::size_t>(*index), *distance, now))
      return {{"error", "move_target: no target " + std::to_string(static_cast<std::size_t>(*index))}};
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "fault") {
    const std::string kind = request.value("kind", "no_return");
    if (kind != "no_return") return {{"error", "fault: unknown kind '" + kind + "' (no_return)"}};
    set_no_return_fault(request.value("on", true), now);
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "min_pulse_width") {
    if (!request.contains("ns") || !request.at("ns").is_number())
      return {{"error", "min_pulse_width: needs 'ns' (number)"}};
    if (!set_min_pulse_width(request.at("ns").get<double>(), now))
      return {{"error", "min_pulse_width: ER 87 Invalid Minimum Pulse Width (0 .. 9999.999 ns)"}};
    return {{"ok", true}, {"device", label()}};
  }
  if (command == "power_cycle") {
    power_cycle(now);
    return {{"ok", true}, {"device", label()}};
  }
  return {{"error", "unknown command '" + command +
                        "' (ULS: outputs, set_scene, move_target, fault, min_pulse_width, power_cycle)"}};
}

}  // namespace rangekit::uls::emulator
