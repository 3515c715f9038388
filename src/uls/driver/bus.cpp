#include "rangekit/uls/bus.hpp"

namespace rangekit::uls {

namespace {

DriverOptions bus_driver_options(const BusOptions& options) {
  DriverOptions driver;
  driver.timeout = options.timeout;
  driver.measure_timeout = options.measure_timeout;
  driver.read_retries = 0;  // a silent address is the common case on a scan
  return driver;
}

}  // namespace

std::vector<std::uint8_t> typable_addresses() {
  std::vector<std::uint8_t> list;
  for (char c = '0'; c <= '9'; ++c) list.push_back(static_cast<std::uint8_t>(c));
  for (char c = 'A'; c <= 'Z'; ++c) list.push_back(static_cast<std::uint8_t>(c));
  for (char c = 'a'; c <= 'z'; ++c) list.push_back(static_cast<std::uint8_t>(c));
  return list;
}

std::vector<std::uint8_t> all_unit_addresses() {
  std::vector<std::uint8_t> list;
  for (int a = first_unit_address; a <= last_unit_address; ++a) list.push_back(static_cast<std::uint8_t>(a));
  return list;
}

Bus::Bus(TransportPtr transport, BusOptions options)
    : options_(options), driver_(std::move(transport), bus_driver_options(options)) {}

std::vector<BusUnit> Bus::scan(const std::vector<std::uint8_t>& addresses) { return scan_each(addresses, {}); }

std::vector<BusUnit> Bus::scan_each(const std::vector<std::uint8_t>& addresses, const ScanProgress& progress) {
  std::vector<BusUnit> found;
  std::size_t asked = 0;
  for (const std::uint8_t address : addresses) {
    BusUnit unit;
    unit.address = address;
    (void)driver_.set_address(address);
    const auto before = driver_.counters();
    auto version = driver_.version();
    const auto after = driver_.counters();
    // Garbled bytes, or a second reply from this address: two units answered at once (U66). A
    // whole reply from another address is a unit asked earlier answering late, not a unit here.
    const bool garbled = after.bad_frames > before.bad_frames || after.unexpected > before.unexpected;
    if (version) {
      unit.answered = true;
      unit.version = *version;
      auto status = driver_.status();
      if (status) unit.status = *status;
    }
    if (garbled) {
      unit.answered = true;
      unit.duplicate = true;
      unit.problem = "replies collided: more than one unit has this address";
    }
    ++asked;
    const bool answered = unit.answered;
    if (answered) found.push_back(std::move(unit));
    if (progress) progress(asked, answered ? &found.back() : nullptr);
  }
  return found;
}

std::vector<BusUnit> Bus::scan(const std::vector<std::uint8_t>& addresses, std::chrono::milliseconds per_address,
                               const ScanProgress& progress) {
  driver_.set_timeout(per_address);
  auto found = scan_each(addresses, progress);
  driver_.set_timeout(options_.timeout);
  return found;
}

Status Bus::assign(std::optional<std::uint8_t> from, std::uint8_t to) {
  if (!Address::unit(to).is_unit()) return make_error(Errc::out_of_range, "unit addresses are 0x30..0xEF");
  if (from && *from == to) return ok_status();
  // Refuse an address in use (§7: "will not function correctly with same address assigned to 2 or more units").
  const auto taken = scan({to});
  if (!taken.empty())
    return make_error(Errc::out_of_range, "address '" + address_text(to) + "' is already in use on the bus" +
                                              (taken[0].version.empty() ? "" : " (" + taken[0].version + ")"));
  if (auto set = driver_.set_address(from); !set) return set;
  if (from) {
    if (auto present = driver_.version(); !present)
      return make_error(present.error().code,
                        "no unit answers at '" + address_text(*from) + "': " + present.error().message);
  }
  // A measuring unit refuses UA (error 31, U24): stopped for it, and started again at its new address.
  auto paused = driver_.stop_if_measuring();
  if (!paused) return paused.error();
  const bool measuring = *paused;
  auto assigned = driver_.set_unit_address(to);
  if (!assigned) {
    if (measuring) (void)driver_.start_measuring();  // left as found
    return assigned;
  }
  // Check the unit now answers at its new address.
  (void)driver_.set_address(to);
  auto check = driver_.unit_address();
  if (!check)
    return make_error(check.error().code,
                      "assigned, but '" + address_text(to) + "' does not answer: " + check.error().message);
  if (*check != to) return make_error(Errc::invalid_frame, "the unit reports address " + address_text(*check));
  if (measuring) return driver_.start_measuring();
  return ok_status();
}

std::vector<PollResult> Bus::poll(const std::vector<std::uint8_t>& addresses, bool measure) {
  std::vector<PollResult> results;
  results.reserve(addresses.size());
  for (const std::uint8_t address : addresses) results.push_back(poll_unit(address, measure));
  return results;
}

PollResult Bus::poll_unit(std::uint8_t address, bool measure) {
  PollResult result;
  result.address = address;
  (void)driver_.set_address(address);
  const auto before = driver_.counters();
  auto status = driver_.status();
  if (status) {
    result.answered = true;
    result.status = *status;
    if (measure) {
      auto sample = driver_.measure();
      if (sample) {
        result.sample = std::move(*sample);
      } else {
        result.problem = sample.error().message;
        result.error = sample.error();
      }
    }
  } else {
    result.problem = status.error().message;
    result.error = status.error();
  }
  if (driver_.counters().bad_frames > before.bad_frames) {
    result.problem = "garbled replies (duplicate address?)";
    result.error = make_error(Errc::invalid_frame, result.problem);
  }
  return result;
}

Status Bus::broadcast(std::string_view mnemonic, std::span<const std::string_view> values, std::uint8_t address) {
  return driver_.broadcast(mnemonic, values, address);
}

}  // namespace rangekit::uls
