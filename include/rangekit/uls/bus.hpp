// An RS-485 bus of addressed ULS units (§7, §8 RS485 Protocol): which
// addresses answer, address assignment that refuses one already in use, the
// Interface Program's network poll (status and a measurement from each unit in
// turn, §2/§7), and broadcast commands that no unit answers.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/formulas.hpp"  // IWYU pragma: export (unit addresses as text)

namespace rangekit::uls {

struct BusOptions {
  std::chrono::milliseconds timeout{150};  // per unit and request: a missing unit costs this much
  std::chrono::milliseconds measure_timeout{3000};
};

// What a scan found at one address.
struct BusUnit {
  std::uint8_t address = 0;
  bool answered = false;
  bool duplicate = false;  // replies collided: two or more units hold this address (U66)
  std::string version;
  std::optional<StatusInfo> status;
  std::string problem;  // why a unit that was heard is not usable
};

// One unit's line of a poll round.
struct PollResult {
  std::uint8_t address = 0;
  bool answered = false;
  std::optional<StatusInfo> status;
  std::optional<Sample> sample;  // when measurements were asked for
  std::string problem;           // timeout, device error, collision
  // Why US or BM failed: Errc::timeout when the unit stayed silent, device_error, ... (U93).
  std::optional<Error> error;
};

// The addresses a user can type (§8 UA table): '0'-'9', 'A'-'Z', 'a'-'z'.
std::vector<std::uint8_t> typable_addresses();
// Every unit address 0x30..0xEF.
std::vector<std::uint8_t> all_unit_addresses();

class Bus {
 public:
  explicit Bus(TransportPtr transport, BusOptions options = {});

  // Asks ID and US at each address; reports who answered and collisions.
  std::vector<BusUnit> scan(const std::vector<std::uint8_t>& addresses);
  // The same, waiting `per_address` for each reply (a silent address costs that much); the
  // bus's own timeout applies again afterwards. `progress` hears of each address once asked:
  // how many were asked so far, and the unit found there (null when none answered).
  using ScanProgress = std::function<void(std::size_t asked, const BusUnit* found)>;
  std::vector<BusUnit> scan(const std::vector<std::uint8_t>& addresses, std::chrono::milliseconds per_address,
                            const ScanProgress& progress = {});
  // UA from `from` to `to`. Refuses (Errc::out_of_range) when `to` already
  // answers, or when nothing answers at `from`. With `from` none, the `$`
  // protocol (a factory unit, address 0, alone on the line, U3).
  Status assign(std::optional<std::uint8_t> from, std::uint8_t to);
  // One round of the network poll: US (and with `measure`, BM) at each address in turn.
  std::vector<PollResult> poll(const std::vector<std::uint8_t>& addresses, bool measure);
  // The same for one unit: what the service's bus session runs, one unit between two commands.
  PollResult poll_unit(std::uint8_t address, bool measure);
  // A command every unit acts on and none answers (0xF0-0xFF, U4).
  Status broadcast(std::string_view mnemonic, std::span<const std::string_view> values = {},
                   std::uint8_t address = first_broadcast_address);

  Driver& driver() noexcept { return driver_; }

 private:
  std::vector<BusUnit> scan_each(const std::vector<std::uint8_t>& addresses, const ScanProgress& progress);

  BusOptions options_;
  Driver driver_;
};

}  // namespace rangekit::uls
