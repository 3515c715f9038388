// The LS5 model's non-volatile memory: table 9.2's defaults, ROM as delivered and as FL
// stores it, kept in the state store as a 256-byte array.
#include "rangekit/ls5/emulator/firmware.hpp"

#include "ls5/emulator/command_handlers.hpp"

namespace rangekit::ls5::emulator {

std::array<std::uint8_t, 256> Firmware::table_defaults() const {
  std::array<std::uint8_t, 256> memory{};
  for (const auto& parameter : parameter_table()) {
    memory[parameter.address] = default_byte(parameter, config_.serial_number);
  }
  return memory;
}

std::array<std::uint8_t, 256> Firmware::delivered_rom() const {
  auto memory = table_defaults();
  memory[address::network_address] = config_.factory_address;  // --address: set and stored before delivery (L55)
  if (config_.udp_destination) {                               // --udp, the same way (L93)
    for (std::uint8_t i = 0; i < 4; ++i) {
      memory[address::destination_ip_first + i] =
          static_cast<std::uint8_t>(config_.udp_destination->ip >> (24U - 8U * i));
    }
    memory[address::destination_port_high] = static_cast<std::uint8_t>(config_.udp_destination->port >> 8U);
    memory[address::destination_port_low] = static_cast<std::uint8_t>(config_.udp_destination->port & 0xFFU);
  }
  return memory;
}

void Firmware::load_rom_into_ram() {
  ram_ = rom_ ? *rom_ : delivered_rom();
  release_held_numbers();
}

Status Firmware::save_rom() {
  if (!rom_) return ok_status();
  nlohmann::json memory;
  memory["parameters"] = nlohmann::json::array();
  for (const auto byte : *rom_) memory["parameters"].push_back(byte);
  auto saved = store_.save(memory);
  state_error_ = saved;
  return saved;
}

std::optional<std::uint8_t> Firmware::rom(std::uint8_t address) const {
  if (!rom_) return std::nullopt;
  return (*rom_)[address];
}

void Firmware::handle_store_to_flash(const Exchange& exchange) {
  rom_ = ram_in_effect();  // a half-written pair is stored at the value it acts with (L84)
  (void)save_rom();
  echo(exchange);
}

}  // namespace rangekit::ls5::emulator
