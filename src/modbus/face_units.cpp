#include <chrono>
#include <thread>

#include "modbus/face_impl.hpp"
#include "rangekit/hub/hub.hpp"

namespace rangekit::modbus {
namespace {

constexpr std::chrono::milliseconds health_interval{100};
// Items are taken at most this often, so a site's samples cost the face one wake-up per
// gather rather than one per sample; a register is then at most this much older.
constexpr std::chrono::milliseconds gather{10};

}  // namespace

void FaceUnits::add(std::uint8_t id, std::string sensor, std::string family) {
  const std::lock_guard lock(mutex_);
  by_sensor_.emplace(sensor, id);
  units_.emplace(id, Unit{std::move(sensor), std::move(family), {}, {}, false});
}

bool FaceUnits::has_unit(std::uint8_t unit) const {
  const std::lock_guard lock(mutex_);
  return units_.contains(unit);
}

InputImage FaceUnits::input_registers(std::uint8_t unit) const {
  const auto now = std::chrono::steady_clock::now();
  const std::lock_guard lock(mutex_);
  const auto found = units_.find(unit);
  if (found == units_.end()) return {};
  return modbus::input_registers(found->second.state, now, order_);
}

HoldingImage FaceUnits::holding_registers(std::uint8_t unit) const {
  const std::lock_guard lock(mutex_);
  const auto found = units_.find(unit);
  return found == units_.end() ? HoldingImage{} : found->second.holding;
}

// Taken when the code is one and the sensor's family has its action; run later, its outcome
// in command_state. One at a time per unit: another while one runs is busy (0x06).
std::uint8_t FaceUnits::command(std::uint8_t unit, std::uint16_t code) {
  const CommandCode* command = find_command_code(code);
  const std::lock_guard lock(mutex_);
  const auto found = units_.find(unit);
  if (found == units_.end()) return exception::gateway_target_failed;
  if (command == nullptr || hub::find_action(found->second.family, command->action) == nullptr) {
    return exception::illegal_value;
  }
  Unit& target = found->second;
  if (target.command_running || commands_stopped_) return exception::busy;
  target.command_running = true;
  target.holding[holding::command] = code;
  target.holding[holding::command_state] = static_cast<std::uint16_t>(CommandState::running);
  queued_.emplace_back(unit, command);
  ++commands;
  commands_ready_.notify_one();
  return 0;
}

void FaceUnits::run_commands() {
  std::unique_lock lock(mutex_);
  while (true) {
    commands_ready_.wait(lock, [&] { return commands_stopped_ || !queued_.empty(); });
    if (queued_.empty()) return;  // stopped, and nothing left to run
    const auto [unit, command] = queued_.front();
    queued_.pop_front();
    const std::string sensor = units_.at(unit).sensor;
    lock.unlock();
    const auto done = hub_.act(sensor, command->action, command->argument);
    lock.lock();
    Unit& target = units_.at(unit);
    target.command_running = false;
    target.holding[holding::command_state] =
        static_cast<std::uint16_t>(done ? CommandState::done : CommandState::failed);
    ++target.holding[holding::command_done];
  }
}

void FaceUnits::stop_commands() {
  const std::lock_guard lock(mutex_);
  commands_stopped_ = true;
  commands_ready_.notify_all();
}

void FaceUnits::run_updates(const hub::SubscriptionPtr& subscription, const std::atomic<bool>& stopping) {
  auto next_health = std::chrono::steady_clock::now();
  while (!stopping) {
    const std::vector<hub::HubItemPtr> items = subscription->take(4096, health_interval);
    const auto now = std::chrono::steady_clock::now();
    bool link_changed = false;
    {
      const std::lock_guard lock(mutex_);
      for (const hub::HubItemPtr& item : items) {
        const auto unit = by_sensor_.find(item->sensor);
        if (unit == by_sensor_.end()) continue;
        if (const auto* sample = std::get_if<Sample>(&item->item)) {
          apply_sample(units_.at(unit->second).state, *sample, now);
        } else {
          link_changed = true;
        }
      }
    }
    if (link_changed || now >= next_health) {
      next_health = now + health_interval;
      const auto sensors = hub_.sensors();
      const std::lock_guard lock(mutex_);
      for (const hub::SensorSnapshot& sensor : sensors) {
        const auto unit = by_sensor_.find(sensor.config.name);
        if (unit != by_sensor_.end()) apply_health(units_.at(unit->second).state, sensor.streaming, sensor.health);
      }
    }
    if (!items.empty() && !stopping) std::this_thread::sleep_until(now + gather);  // paces the wake-ups
  }
}

}  // namespace rangekit::modbus
