// The Modbus face's state shared by its threads: the units and their registers (updated from
// the hub's items), the command worker, and the server's counters.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "modbus/request.hpp"
#include "modbus/unit_state.hpp"
#include "rangekit/core/address_range.hpp"
#include "rangekit/modbus/face.hpp"

namespace rangekit::modbus {

struct Unit {
  std::string sensor;
  std::string family;
  UnitState state;
  HoldingImage holding{};
  bool command_running = false;
};

// The units as requests see them; every call takes the lock for one copy of a unit's registers.
class FaceUnits final : public UnitTable {
 public:
  FaceUnits(hub::Hub& hub, WordOrder order, bool writable) : hub_(hub), order_(order), writable_(writable) {}

  void add(std::uint8_t id, std::string sensor, std::string family);
  [[nodiscard]] bool has_unit(std::uint8_t unit) const override;
  [[nodiscard]] InputImage input_registers(std::uint8_t unit) const override;
  [[nodiscard]] bool writable() const override { return writable_; }
  [[nodiscard]] HoldingImage holding_registers(std::uint8_t unit) const override;
  std::uint8_t command(std::uint8_t unit, std::uint16_t code) override;

  // The updater: the hub's items and its health, into the units.
  void run_updates(const hub::SubscriptionPtr& subscription, const std::atomic<bool>& stopping);
  // The command worker: one command at a time, through the hub's checks.
  void run_commands();
  void stop_commands();

  std::atomic<std::uint64_t> commands{0};

 private:
  hub::Hub& hub_;
  WordOrder order_;
  bool writable_;
  mutable std::mutex mutex_;
  std::map<std::uint8_t, Unit> units_;
  std::map<std::string, std::uint8_t, std::less<>> by_sensor_;
  std::condition_variable commands_ready_;
  std::deque<std::pair<std::uint8_t, const CommandCode*>> queued_;
  bool commands_stopped_ = false;
};

}  // namespace rangekit::modbus
