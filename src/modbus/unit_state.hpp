// What a unit's input registers show: the last sample of its sensor and its health, kept as
// samples arrive, and written out as registers when a client asks.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "modbus/register_map.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/hub/health.hpp"

namespace rangekit::modbus {

using InputImage = std::array<std::uint16_t, input::count>;

struct UnitState {
  bool connected = false;
  bool streaming = false;
  // The last sample: its reading in mm (none: it had no distance), what it said about itself.
  bool heard = false;  // a sample arrived since the start
  std::optional<double> reading_mm;
  bool suspect = false;
  bool no_target = false;
  std::uint16_t device_error = 0;
  std::array<float, input::max_targets> targets_mm{};
  std::uint16_t target_count = 0;
  std::uint32_t sequence = 0;
  std::chrono::steady_clock::time_point arrived{};
  // From the hub's health.
  double rate_hz = 0;
  std::uint64_t records = 0;
  std::uint64_t errors = 0;
  std::uint64_t lost = 0;
};

// A new sample of the unit's sensor, arrived at `now`.
void apply_sample(UnitState& state, const Sample& sample, std::chrono::steady_clock::time_point now);
// The sensor's link and counts as the hub reports them.
void apply_health(UnitState& state, bool streaming, const hub::SensorHealth& health);

// Stale: no new sample for three of the sensor's output periods, or for 2 s while its rate is
// not known; never sooner than 100 ms, the longest the hub holds a batch back.
bool is_stale(const UnitState& state, std::chrono::steady_clock::time_point now);

InputImage input_registers(const UnitState& state, std::chrono::steady_clock::time_point now, WordOrder order);

}  // namespace rangekit::modbus
