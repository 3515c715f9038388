#include "cli/serve_monitor.hpp"

#include <fmt/core.h>

#include <chrono>

#include "rangekit/record/format.hpp"

namespace rangekit::cli {
namespace {

const char* state_of(const hub::SensorSnapshot& sensor) {
  if (!sensor.health.connected) return "disconnected";
  return sensor.streaming ? "streaming" : "connected";
}

// "disconnected: /dev/ttyUSB9: No such file or directory": a disconnection says why, and a new
// reason is a new change; being connected or streaming needs no reason.
std::string said_state(const hub::SensorSnapshot& sensor) {
  std::string state = state_of(sensor);
  if (!sensor.health.connected && !sensor.health.last_event.empty()) state += ": " + sensor.health.last_event;
  return state;
}

}  // namespace

std::string summary_line(const hub::SensorSnapshot& sensor) {
  const hub::SensorHealth& health = sensor.health;
  return fmt::format("{:<16} {:<3} {:<12} {:>8.1f}/s  records {}  errors {}  lost {}  bad frames {}  reconnects {}",
                     sensor.config.name, sensor.config.family, state_of(sensor), health.rate_hz, health.records,
                     health.errors, health.lost, health.bad_frames, health.reconnects);
}

std::string states_line(const std::vector<hub::SensorSnapshot>& sensors) {
  std::map<std::string, std::size_t> counts;  // by state, in name order
  for (const hub::SensorSnapshot& sensor : sensors) ++counts[state_of(sensor)];
  std::string line = fmt::format("{} sensor{}", sensors.size(), sensors.size() == 1 ? "" : "s");
  const char* separator = ": ";
  for (const auto& [state, count] : counts) {
    line += fmt::format("{}{} {}", separator, count, state);
    separator = ", ";
  }
  return line;
}

void ServeMonitor::tick(const std::vector<hub::SensorSnapshot>& sensors) {
  // Up over the last table and clear it: the changes go above, the new table below them.
  if (table_ && drawn_ > 0) fmt::print(out_, "\x1b[{}A\x1b[J", drawn_);
  for (const hub::SensorSnapshot& sensor : sensors) {
    std::string state = said_state(sensor);
    auto& said = said_[sensor.config.name];
    if (state == said) continue;
    std::string time;
    if (timestamps_) {
      record::append_iso_time(time, std::chrono::system_clock::now());
      time += ' ';
    }
    fmt::print(out_, "{}{}: {}\n", time, sensor.config.name, state);
    said = std::move(state);
  }
  drawn_ = 0;
  if (table_) {
    for (const hub::SensorSnapshot& sensor : sensors) fmt::print(out_, "{}\n", summary_line(sensor));
    drawn_ = sensors.size();
  }
  std::fflush(out_);
}

}  // namespace rangekit::cli
