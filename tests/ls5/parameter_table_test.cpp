// Table 9.2 (parameters), its notes, and table 9.3 (configuration example).
#include <gtest/gtest.h>

#include <array>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rangekit/ls5/logical_values.hpp"
#include "rangekit/ls5/parameters.hpp"
#include "rangekit/ls5/request.hpp"
#include "rangekit/ls5/settings.hpp"
#include "test_helpers.hpp"

using namespace rangekit;
using namespace rangekit::ls5;
using ls5_test::bytes_of;
using ls5_test::U8s;

namespace {
const SensorModel newest{FirmwareVersion{12, 0}, true};

std::uint64_t combined(LogicalValueId id, std::initializer_list<std::uint8_t> bytes) {
  const std::vector<std::uint8_t> list(bytes);
  const auto value = combine_bytes(logical_value_info(id), list);
  EXPECT_TRUE(value.ok());
  return value.value_or(0);
}

std::uint64_t table_default(LogicalValueId id, std::uint32_t serial = 0) {
  return default_value(logical_value_info(id), serial);
}
}  // namespace

TEST(Ls5ParameterTable, EveryAddressOfTable92) {
  std::set<int> expected;
  for (int a = 0x01; a <= 0x0E; ++a) expected.insert(a);
  for (int a = 0x11; a <= 0x26; ++a) expected.insert(a);
  for (int a = 0x50; a <= 0x70; ++a) expected.insert(a);
  std::set<int> present;
  for (const ParameterInfo& p : parameter_table()) present.insert(p.address);
  EXPECT_EQ(present, expected);
  for (int a = 0; a <= 0xFF; ++a) {
    EXPECT_EQ(find_parameter(static_cast<std::uint8_t>(a)) != nullptr, expected.count(a) == 1) << a;
  }
  const auto unknown = check_parameter_byte(0x0F, 0x00, newest);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().code, Errc::unknown_parameter);
  EXPECT_EQ(unknown.error().message, "LS5 parameter 0F is not in table 9.2");
}

TEST(Ls5ParameterTable, LookupByCliName) {
  EXPECT_EQ(find_parameter_by_cli_name("network-address")->address, 0x01);
  EXPECT_EQ(find_parameter_by_cli_name("baud-rate")->address, 0x05);
  EXPECT_EQ(find_parameter_by_cli_name("median-points")->address, 0x0D);
  EXPECT_EQ(find_parameter_by_cli_name("period.low")->address, 0x06);
  EXPECT_EQ(find_parameter_by_cli_name("destination-port.high")->address, 0x6C);
  EXPECT_EQ(find_logical_value_by_cli_name("period")->id, LogicalValueId::measurement_period);
  EXPECT_EQ(find_logical_value_by_cli_name("analog-lower")->id, LogicalValueId::analog_lower_limit);
  EXPECT_EQ(find_logical_value_by_cli_name("ip-address")->id, LogicalValueId::sensor_ip);
  EXPECT_EQ(find_parameter_by_cli_name("nonsense"), nullptr);

  // One name space for the CLI: bytes and values never share a name.
  std::set<std::string_view> names;
  for (const ParameterInfo& p : parameter_table()) EXPECT_TRUE(names.insert(p.cli_name).second) << p.cli_name;
  for (const LogicalValueInfo& v : logical_value_table()) EXPECT_TRUE(names.insert(v.cli_name).second) << v.cli_name;
}

TEST(Ls5ParameterTable, AcceptedValuesAsPrinted) {
  const SensorModel any{};
  EXPECT_FALSE(check_parameter_byte(0x01, 0x00, any).ok());  // network address 01-FF
  EXPECT_TRUE(check_parameter_byte(0x01, 0xFF, any).ok());
  EXPECT_TRUE(check_parameter_byte(0x04, 0x05, any).ok());  // byte format 00-05
  EXPECT_FALSE(check_parameter_byte(0x04, 0x06, any).ok());
  EXPECT_FALSE(check_parameter_byte(0x05, 0x00, any).ok());  // baud 01-08
  EXPECT_FALSE(check_parameter_byte(0x08, 0x00, any).ok());  // thinning 01-FF
  EXPECT_FALSE(check_parameter_byte(0x0C, 0x00, any).ok());  // averaging points 01-FF
  EXPECT_TRUE(check_parameter_byte(0x1E, 0x01, any).ok());
  EXPECT_FALSE(check_parameter_byte(0x1E, 0x02, any).ok());

  // Discrete outputs setting 15: two digits 0-2 each.
  const std::set<int> outputs = {0x00, 0x01, 0x02, 0x10, 0x11, 0x12, 0x20, 0x21, 0x22};
  for (int v = 0; v <= 0xFF; ++v) {
    EXPECT_EQ(check_parameter_byte(0x15, static_cast<std::uint8_t>(v), any).ok(), outputs.count(v) == 1) << v;
  }
  const auto bad = check_parameter_byte(0x15, 0x13, any);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::out_of_range);
  EXPECT_EQ(bad.error().message,
            "LS5 parameter 15 (Discrete outputs setting) does not accept 13; accepted: 00-02; 10-12; 20-22");
}

TEST(Ls5ParameterTable, MedianPointsAreOddHexL4) {
  // Table 9.2, 0D: "01, 03, 05, ..., 31", m = 2h + 1, h = 0..24: hex 0x01-0x31 odd = 1-49 points.
  int accepted = 0;
  for (int v = 0; v <= 0xFF; ++v) {
    const bool ok = check_parameter_byte(0x0D, static_cast<std::uint8_t>(v), SensorModel{}).ok();
    EXPECT_EQ(ok, v % 2 == 1 && v <= 0x31) << v;
    accepted += ok ? 1 : 0;
  }
  EXPECT_EQ(accepted, 25);  // h = 0..24
  const auto even = check_parameter_byte(0x0D, 0x04, SensorModel{});
  ASSERT_FALSE(even.ok());
  EXPECT_NE(even.error().message.find("01, 03, ..., 31"), std::string::npos) << even.error().message;
  EXPECT_EQ(find_parameter(0x0D)->default_value, 0x05);
}

TEST(Ls5ParameterTable, LowAndHighBytesL5) {
  EXPECT_EQ(byte_role(*find_parameter(0x06)), ByteRole::low_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x07)), ByteRole::high_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x11)), ByteRole::low_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x12)), ByteRole::high_byte);
  // Ports: high byte first.
  EXPECT_EQ(byte_role(*find_parameter(0x6C)), ByteRole::high_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x6D)), ByteRole::low_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x6E)), ByteRole::high_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x6F)), ByteRole::low_byte);
  EXPECT_EQ(byte_role(*find_parameter(0x05)), ByteRole::whole);
  EXPECT_EQ(byte_role(*find_parameter(0x52)), ByteRole::octet);
  EXPECT_EQ(octet_index(*find_parameter(0x52)), 2);
  EXPECT_EQ(octet_index(*find_parameter(0x65)), 5);
  EXPECT_EQ(find_parameter(0x13)->part_of, LogicalValueId::analog_upper_limit);

  // Codes 0-50000: the high byte stops at C3 (table 9.2), the value at 50000 (§8.10, §8.11).
  EXPECT_TRUE(check_parameter_byte(0x12, 0xC3, SensorModel{}).ok());
  EXPECT_FALSE(check_parameter_byte(0x12, 0xC4, SensorModel{}).ok());
  const auto& upper = logical_value_info(LogicalValueId::analog_upper_limit);
  EXPECT_TRUE(check_logical_value(upper, 50000).ok());
  EXPECT_FALSE(check_logical_value(upper, 50001).ok());
  EXPECT_FALSE(split_value(upper, 0xC351).ok());
  const auto writes = split_value(upper, 50000);
  ASSERT_TRUE(writes.ok());
  ASSERT_EQ(writes->count, 2U);
  EXPECT_EQ(writes->items[0], (ParameterWrite{0x13, 0x50}));
  EXPECT_EQ(writes->items[1], (ParameterWrite{0x14, 0xC3}));

  // Period, τ, exposure, fixed ranges: "For the parameter itself" ranges.
  EXPECT_FALSE(check_logical_value(logical_value_info(LogicalValueId::measurement_period), 0).ok());
  EXPECT_TRUE(check_logical_value(logical_value_info(LogicalValueId::signal_absence_time), 0).ok());
  EXPECT_FALSE(check_logical_value(logical_value_info(LogicalValueId::max_exposure_time), 0).ok());
  EXPECT_TRUE(check_logical_value(logical_value_info(LogicalValueId::discrete_fixed_range), 0xFFFF).ok());
  EXPECT_FALSE(check_logical_value(logical_value_info(LogicalValueId::discrete_fixed_range), 0).ok());

  // Ports split high byte first into 6C/6D.
  const auto port = split_value(logical_value_info(LogicalValueId::destination_port), 603);
  ASSERT_TRUE(port.ok());
  EXPECT_EQ(port->items[0], (ParameterWrite{0x6C, 0x02}));
  EXPECT_EQ(port->items[1], (ParameterWrite{0x6D, 0x5B}));
}

TEST(Ls5ParameterTable, PortsTakeEveryValueOfTheParameterItselfL18L51) {
  // Table 9.2, destination and source port: "For the parameter itself: 0001-FFFF", low byte printed
  // "01-FF". Read byte-wise, 256, 512, 1024 ... could never be set: the low byte takes 00-FF and the
  // port is checked as a whole (L51).
  EXPECT_TRUE(check_parameter_byte(0x6D, 0x00, newest).ok());
  EXPECT_TRUE(check_parameter_byte(0x6F, 0x00, newest).ok());
  const auto port = split_value(logical_value_info(LogicalValueId::destination_port), 1024);  // 0x0400
  ASSERT_TRUE(port.ok()) << port.error().message;
  EXPECT_EQ(port->items[0], (ParameterWrite{0x6C, 0x04}));
  EXPECT_EQ(port->items[1], (ParameterWrite{0x6D, 0x00}));
  EXPECT_TRUE(split_value(logical_value_info(LogicalValueId::source_port), 512).ok());
  EXPECT_FALSE(split_value(logical_value_info(LogicalValueId::source_port), 0).ok());
  // Port 0 stays refused: the low byte 00 with the high byte 00.
  std::uint8_t memory[256] = {};
  memory[0x6C] = 0x00;
  memory[0x6D] = 0x5B;
  const auto port_zero = check_value_after_write(0x6D, 0x00, [&](std::uint8_t a) { return memory[a]; });
  ASSERT_FALSE(port_zero.ok());
  EXPECT_EQ(port_zero.error().code, Errc::out_of_range);
  EXPECT_TRUE(check_value_after_write(0x6C, 0x02, [&](std::uint8_t a) { return memory[a]; }).ok());
  // High bytes of codes stay "00-C3" per byte; 0-50000 is checked on the combined value (L50).
  EXPECT_TRUE(check_parameter_byte(0x14, 0xC3, SensorModel{}).ok());
  EXPECT_FALSE(check_parameter_byte(0x14, 0xC4, SensorModel{}).ok());
  EXPECT_TRUE(check_parameter_byte(0x13, 0xFF, SensorModel{}).ok());
  EXPECT_FALSE(check_logical_value(logical_value_info(LogicalValueId::analog_upper_limit), 0xC3FF).ok());
}

namespace {
// Table 9.2 defaults, the memory of a sensor fresh from DF.
std::array<std::uint8_t, 256> default_memory() {
  std::array<std::uint8_t, 256> memory{};
  for (const ParameterInfo& p : parameter_table()) memory[p.address] = default_byte(p, 157);
  return memory;
}

Status write_in(std::array<std::uint8_t, 256>& memory, std::uint8_t address, std::uint8_t value) {
  Status ok = check_value_after_write(address, value, [&](std::uint8_t a) { return memory[a]; });
  if (ok) memory[address] = value;
  return ok;
}
}  // namespace

TEST(Ls5ParameterTable, CombinedCodeCheckedOnEveryByteWriteL50) {
  // §8.10: "The values of the lower and upper bounds can only be in the range 0÷50000."
  // §8.11: "The values of the lower and upper swings can only be in the range 0÷50000."
  auto memory = default_memory();                   // upper limit 13/14 = 50 C3 = 50000
  const auto above = write_in(memory, 0x13, 0xFF);  // C3FF = 50175
  ASSERT_FALSE(above.ok());
  EXPECT_EQ(above.error().code, Errc::out_of_range);
  EXPECT_EQ(above.error().message,
            "LS5 parameter 13 (Upper limit of the analog output, low byte) = FF with 14 = C3 makes analog-upper (Upper "
            "limit of the analog output) 50175, outside 0-50000 (limits and swings are codes 0-50000 over the range)");
  EXPECT_FALSE(write_in(memory, 0x13, 0x51).ok());  // C351 = 50001
  EXPECT_EQ(memory[0x13], 0x50);
  EXPECT_TRUE(write_in(memory, 0x13, 0x50).ok());  // C350 = 50000, the largest
  // Every code value: lower limit, upper limit, the four swings.
  for (const std::uint8_t low : U8s{0x11, 0x13, 0x16, 0x18, 0x1A, 0x1C}) {
    const auto high = static_cast<std::uint8_t>(low + 1);
    memory[high] = 0xC3;
    memory[low] = 0x00;
    EXPECT_TRUE(write_in(memory, low, 0x50).ok()) << int{low};
    EXPECT_FALSE(write_in(memory, low, 0x51).ok()) << int{low};
    memory[high] = 0x00;
    memory[low] = 0xFF;
    EXPECT_FALSE(write_in(memory, high, 0xC3).ok()) << int{high};  // "set 19=C3" after 18=FF: C3FF
    EXPECT_TRUE(write_in(memory, high, 0xC2).ok()) << int{high};
  }
  // τ has the whole 0000-FFFF; IP and MAC octets and single bytes are not numbers with a range.
  EXPECT_TRUE(write_in(memory, 0x0A, 0xFF).ok());
  EXPECT_TRUE(write_in(memory, 0x09, 0x00).ok());
  EXPECT_TRUE(write_in(memory, 0x50, 0x00).ok());
  EXPECT_TRUE(write_in(memory, 0x0D, 0x04).ok());  // the byte's own check is check_parameter_byte's
}

TEST(Ls5ParameterTable, WriteOrderKeepsEveryIntermediateInRangeL50) {
  const auto order = [](LogicalValueId id, std::uint64_t value) {
    const auto writes = split_value_in_write_order(logical_value_info(id), value);
    if (!writes) {
      ADD_FAILURE() << writes.error().message;
      return std::vector<ParameterWrite>{};
    }
    return std::vector<ParameterWrite>(writes->view().begin(), writes->view().end());
  };
  using W = std::vector<ParameterWrite>;
  // Table 9.3 writes the low byte first: every one of its values keeps that order.
  EXPECT_EQ(order(LogicalValueId::output1_first_swing, 20000), (W{{0x16, 0x20}, {0x17, 0x4E}}));
  EXPECT_EQ(order(LogicalValueId::output1_second_swing, 40000), (W{{0x18, 0x40}, {0x19, 0x9C}}));
  EXPECT_EQ(order(LogicalValueId::analog_upper_limit, 50000), (W{{0x13, 0x50}, {0x14, 0xC3}}));
  // 25000 = 0x61A8: A8 under a high byte C3 would be C3A8 = 50072, so 12 goes first.
  EXPECT_EQ(order(LogicalValueId::analog_lower_limit, 25000), (W{{0x12, 0x61}, {0x11, 0xA8}}));
  // Period 25.6 ms = 0x0100: 00 under a high byte 00 would be period 0, so 07 goes first.
  EXPECT_EQ(order(LogicalValueId::measurement_period, 0x0100), (W{{0x07, 0x01}, {0x06, 0x00}}));
  EXPECT_EQ(order(LogicalValueId::measurement_period, 0x0034), (W{{0x06, 0x34}, {0x07, 0x00}}));
  // Ports, high byte first as table 9.2 lists them, unless that high byte is 00.
  EXPECT_EQ(order(LogicalValueId::destination_port, 1024), (W{{0x6C, 0x04}, {0x6D, 0x00}}));
  EXPECT_EQ(order(LogicalValueId::destination_port, 255), (W{{0x6D, 0xFF}, {0x6C, 0x00}}));
  // τ has no forbidden value: table order.
  EXPECT_EQ(order(LogicalValueId::signal_absence_time, 0x0100), (W{{0x09, 0x00}, {0x0A, 0x01}}));

  // From any in-range value to any other, every write in that order passes check_value_after_write.
  const std::uint8_t edges[] = {0x00, 0x01, 0x4F, 0x50, 0x51, 0x7F, 0xC2, 0xC3, 0xC4, 0xFE, 0xFF};
  for (const LogicalValueInfo& info : logical_value_table()) {
    if (info.kind != ValueKind::number) continue;
    for (const std::uint8_t old_high : edges) {
      for (const std::uint8_t old_low : edges) {
        for (const std::uint8_t new_high : edges) {
          for (const std::uint8_t new_low : edges) {
            const std::uint64_t before = std::uint64_t{old_high} << 8 | old_low;
            const std::uint64_t after = std::uint64_t{new_high} << 8 | new_low;
            if (before < info.min || before > info.max || !split_value(info, after).ok()) continue;
            std::uint8_t memory[256] = {};
            const auto old_writes = split_value(info, before);  // kept: view() points into it
            for (const auto& write : old_writes->view()) memory[write.address] = write.value;
            const auto new_writes = split_value_in_write_order(info, after);
            for (const auto& write : new_writes->view()) {
              EXPECT_TRUE(
                  check_value_after_write(write.address, write.value, [&](std::uint8_t a) { return memory[a]; }).ok())
                  << info.cli_name << " " << before << " -> " << after;
              memory[write.address] = write.value;
            }
          }
        }
      }
    }
  }
}

TEST(Ls5ParameterTable, ZeroRefusedWhereTheParameterItselfIs0001ToFFFFL52) {
  // Table 9.2: period, maximum exposure time, both fixed ranges and both ports:
  // "For the parameter itself: 0001-FFFF"; τ: "0000-FFFF".
  for (const auto& [low, high] : {std::pair<std::uint8_t, std::uint8_t>{0x06, 0x07},
                                  {0x20, 0x21},
                                  {0x23, 0x24},
                                  {0x25, 0x26},
                                  {0x6D, 0x6C},
                                  {0x6F, 0x6E}}) {
    auto memory = default_memory();
    memory[high] = 0x00;
    memory[low] = 0x01;
    const auto zero = write_in(memory, low, 0x00);
    ASSERT_FALSE(zero.ok()) << int{low};
    EXPECT_NE(zero.error().message.find("outside 1-65535 (the parameter itself takes 0001-FFFF)"), std::string::npos)
        << zero.error().message;
    EXPECT_EQ(memory[low], 0x01);
    EXPECT_TRUE(write_in(memory, high, 0x01).ok()) << int{high};  // 0x0101
    EXPECT_TRUE(write_in(memory, low, 0x00).ok()) << int{low};    // 0x0100
    EXPECT_FALSE(write_in(memory, high, 0x00).ok()) << int{high};
  }
  auto memory = default_memory();
  EXPECT_TRUE(write_in(memory, 0x09, 0x00).ok());  // τ = 0 ms: "for τ = 0 ms parameter is 0000"
}

TEST(Ls5ParameterTable, FirmwareVersionsL6) {
  const SensorModel v5{FirmwareVersion{5, 0}, false};
  const SensorModel v6{FirmwareVersion{6, 0}, false};
  const SensorModel v7{FirmwareVersion{7, 0}, false};
  const SensorModel v8{FirmwareVersion{8, 0}, false};
  const SensorModel v9{FirmwareVersion{9, 0}, false};
  const SensorModel v12_serial{FirmwareVersion{12, 3}, false};
  const SensorModel v12_ethernet{FirmwareVersion{12, 3}, true};
  const SensorModel v11_ethernet{FirmwareVersion{11, 9}, true};

  // Note 2: baud codes 06-08 from LS5.6.0.
  EXPECT_TRUE(check_parameter_byte(0x05, 0x05, v5).ok());
  const auto fast = check_parameter_byte(0x05, 0x06, v5);
  ASSERT_FALSE(fast.ok());
  EXPECT_EQ(fast.error().code, Errc::unsupported);
  EXPECT_EQ(fast.error().message,
            "LS5 parameter 05 (Baud rate) value 06 needs firmware LS5.6.0 or later; the sensor reports LS5.5.0");
  EXPECT_TRUE(check_parameter_byte(0x05, 0x08, v6).ok());
  EXPECT_FALSE(check_parameter_byte(0x05, 0x09, v12_ethernet).ok());

  // Note 3: 20-22 from LS5.7.0.
  for (const std::uint8_t a : U8s{0x20, 0x21, 0x22}) {
    EXPECT_FALSE(check_parameter_available(a, v6).ok()) << int{a};
    EXPECT_TRUE(check_parameter_available(a, v7).ok()) << int{a};
  }
  // §8.8 footnote: 0E from LS5.8.0.
  EXPECT_FALSE(check_parameter_available(0x0E, v7).ok());
  EXPECT_TRUE(check_parameter_available(0x0E, v8).ok());
  // Note 4 and §8.14: 23-26 and latching 02-09 from LS5.9.0.
  for (const std::uint8_t a : U8s{0x23, 0x24, 0x25, 0x26}) {
    EXPECT_FALSE(check_parameter_available(a, v8).ok()) << int{a};
    EXPECT_TRUE(check_parameter_available(a, v9).ok()) << int{a};
  }
  EXPECT_TRUE(check_parameter_byte(0x1F, 0x01, v5).ok());
  for (std::uint8_t mode = 0x02; mode <= 0x09; ++mode) {
    EXPECT_FALSE(check_parameter_byte(0x1F, mode, v8).ok()) << int{mode};
    EXPECT_TRUE(check_parameter_byte(0x1F, mode, v9).ok()) << int{mode};
  }
  EXPECT_FALSE(check_parameter_byte(0x1F, 0x0A, v12_ethernet).ok());
  // Note 5: 50-70 from LS5.12.x and on Ethernet sensors only.
  for (int a = 0x50; a <= 0x70; ++a) {
    const auto address = static_cast<std::uint8_t>(a);
    EXPECT_TRUE(find_parameter(address)->ethernet_only) << a;
    EXPECT_EQ(find_parameter(address)->since, firmware_12_x) << a;
    EXPECT_TRUE(check_parameter_available(address, v12_ethernet).ok()) << a;
    EXPECT_FALSE(check_parameter_available(address, v11_ethernet).ok()) << a;
    const auto serial_only = check_parameter_available(address, v12_serial);
    ASSERT_FALSE(serial_only.ok()) << a;
    EXPECT_NE(serial_only.error().message.find("Ethernet"), std::string::npos);
  }
  // Everything else: every firmware.
  for (const std::uint8_t a : U8s{0x01, 0x05, 0x0D, 0x15, 0x1F})
    EXPECT_TRUE(check_parameter_available(a, SensorModel{}).ok());
}

TEST(Ls5ParameterTable, DefaultsOfTable92) {
  // Single bytes, as printed.
  const std::pair<int, int> singles[] = {{0x01, 0x01}, {0x02, 0x01}, {0x03, 0x01}, {0x04, 0x00}, {0x05, 0x05},
                                         {0x08, 0x01}, {0x0B, 0x00}, {0x0C, 0x01}, {0x0D, 0x05}, {0x0E, 0x00},
                                         {0x15, 0x12}, {0x1E, 0x00}, {0x1F, 0x01}, {0x22, 0x01}, {0x70, 0x01}};
  for (const auto& [address, value] : singles) {
    EXPECT_EQ(default_byte(*find_parameter(static_cast<std::uint8_t>(address)), 0), value) << address;
  }
  // Every default is an accepted value (MAC bytes from any serial).
  for (const ParameterInfo& p : parameter_table()) {
    EXPECT_TRUE(check_parameter_byte(p.address, default_byte(p, 157), newest).ok()) << int{p.address};
  }

  // Period 0x0064 (64 00) = 100 × 0.1 ms = 10 ms.
  EXPECT_EQ(table_default(LogicalValueId::measurement_period), 0x0064U);
  EXPECT_DOUBLE_EQ(period_ms(0x0064), 10.0);
  EXPECT_EQ(format_value(logical_value_info(LogicalValueId::measurement_period), 0x0064), "10.0 ms");
  // τ 0x000A (0A 00) = 10 ms.
  EXPECT_EQ(table_default(LogicalValueId::signal_absence_time), 0x000AU);
  // Analog limits 0 and 0xC350 = 50000; swings 0/50000 for both outputs.
  EXPECT_EQ(table_default(LogicalValueId::analog_lower_limit), 0U);
  EXPECT_EQ(table_default(LogicalValueId::analog_upper_limit), 50000U);
  EXPECT_EQ(table_default(LogicalValueId::output1_first_swing), 0U);
  EXPECT_EQ(table_default(LogicalValueId::output1_second_swing), 50000U);
  EXPECT_EQ(table_default(LogicalValueId::output2_first_swing), 0U);
  EXPECT_EQ(table_default(LogicalValueId::output2_second_swing), 50000U);
  // Exposure 0x24B8 (B8 24) = 9400 µs.
  EXPECT_EQ(table_default(LogicalValueId::max_exposure_time), 9400U);
  EXPECT_EQ(format_value(logical_value_info(LogicalValueId::max_exposure_time), 9400), "9400 µs");
  // Fixed ranges 0x2710 (10 27) = 10000.
  EXPECT_EQ(table_default(LogicalValueId::analog_fixed_range), 10000U);
  EXPECT_EQ(table_default(LogicalValueId::discrete_fixed_range), 10000U);
  // §10 and table 9.2: network settings.
  const auto& ip = logical_value_info(LogicalValueId::sensor_ip);
  EXPECT_EQ(format_value(ip, table_default(LogicalValueId::sensor_ip)), "192.168.0.3");
  EXPECT_EQ(format_ipv4(static_cast<std::uint32_t>(table_default(LogicalValueId::gateway_ip))), "192.168.0.1");
  EXPECT_EQ(format_ipv4(static_cast<std::uint32_t>(table_default(LogicalValueId::subnet_mask))), "255.255.255.255");
  EXPECT_EQ(format_ipv4(static_cast<std::uint32_t>(table_default(LogicalValueId::destination_ip))), "255.255.255.255");
  EXPECT_EQ(format_mac(table_default(LogicalValueId::destination_mac)), "FF:FF:FF:FF:FF:FF");
  EXPECT_EQ(table_default(LogicalValueId::destination_port), 603U);
  EXPECT_EQ(table_default(LogicalValueId::source_port), 5000U);
}

TEST(Ls5ParameterTable, MacFromSerialNumberL20) {
  // 1E:30:6C:A2:XX:YY, XX the high and YY the low byte of the serial number.
  EXPECT_EQ(format_mac(default_sensor_mac(157)), "1E:30:6C:A2:00:9D");
  EXPECT_EQ(format_mac(default_sensor_mac(0x1234)), "1E:30:6C:A2:12:34");
  EXPECT_EQ(default_sensor_mac(0xABCD), 0x1E306CA2ABCDULL);
  EXPECT_EQ(format_value(logical_value_info(LogicalValueId::sensor_mac), default_sensor_mac(157)), "1E:30:6C:A2:00:9D");
  EXPECT_EQ(default_byte(*find_parameter(0x64), 0x1234), 0x12);
  EXPECT_EQ(default_byte(*find_parameter(0x65), 0x1234), 0x34);
}

TEST(Ls5ParameterTable, PeriodAndTauExamplesOfTable92L21) {
  // "for t = 1 ms parameter is 000A; for t = 5,2 ms parameter is 0034"
  EXPECT_EQ(period_code_from_ms(1.0).value_or(0), 0x000A);
  EXPECT_EQ(period_code_from_ms(5.2).value_or(0), 0x0034);
  EXPECT_EQ(period_code_from_ms(0.1).value_or(0), 0x0001);  // "minimum value - 0.1 ms"
  EXPECT_DOUBLE_EQ(period_ms(0x0034), 5.2);
  // "for τ = 0 ms parameter is 0000; for τ = 10 ms parameter is 000A"
  EXPECT_EQ(signal_absence_code_from_ms(0.0).value_or(1), 0x0000);
  EXPECT_EQ(signal_absence_code_from_ms(10.0).value_or(0), 0x000A);

  EXPECT_FALSE(period_code_from_ms(0.0).ok());
  EXPECT_FALSE(period_code_from_ms(5.25).ok());
  EXPECT_FALSE(period_code_from_ms(6553.6).ok());
  EXPECT_FALSE(signal_absence_code_from_ms(0.5).ok());
  EXPECT_FALSE(signal_absence_code_from_ms(65536.0).ok());
  EXPECT_FALSE(signal_absence_code_from_ms(-1.0).ok());

  const auto writes = split_value(logical_value_info(LogicalValueId::measurement_period), 0x0034);
  ASSERT_TRUE(writes.ok());
  EXPECT_EQ(writes->items[0], (ParameterWrite{0x06, 0x34}));
  EXPECT_EQ(writes->items[1], (ParameterWrite{0x07, 0x00}));
}

TEST(Ls5ParameterTable, ConfigurationExampleOfTable93) {
  struct Row {
    std::string_view command;
    std::uint8_t address;
    std::uint8_t value;
  };
  // Table 9.3, every configuration command, in order.
  const Row rows[] = {
      {"#01W1512\r", 0x15, 0x12}, {"#01W1620\r", 0x16, 0x20}, {"#01W174E\r", 0x17, 0x4E}, {"#01W1840\r", 0x18, 0x40},
      {"#01W199C\r", 0x19, 0x9C}, {"#01W1A10\r", 0x1A, 0x10}, {"#01W1B27\r", 0x1B, 0x27}, {"#01W1C30\r", 0x1C, 0x30},
      {"#01W1D75\r", 0x1D, 0x75}, {"#01W0301\r", 0x03, 0x01}, {"#01W1100\r", 0x11, 0x00}, {"#01W1200\r", 0x12, 0x00},
      {"#01W1350\r", 0x13, 0x50}, {"#01W14C3\r", 0x14, 0xC3},
  };
  std::uint8_t memory[256] = {};
  for (const Row& row : rows) {
    const auto request = parse_request_line(bytes_of(row.command));
    ASSERT_TRUE(request.ok()) << row.command << ": " << request.error().describe();
    EXPECT_EQ(request->address, 0x01);
    EXPECT_EQ(request->command, CommandId::write_parameter);
    EXPECT_EQ(request->parameter, row.address) << row.command;
    EXPECT_EQ(request->value, row.value) << row.command;
    EXPECT_TRUE(check_parameter_byte(request->parameter, request->value, SensorModel{}).ok()) << row.command;
    memory[request->parameter] = request->value;
  }
  // "1st discrete output is enabled, the initial value is 0. 2nd ... initial value - 1."
  EXPECT_EQ(memory[0x15], 0x12);
  EXPECT_EQ(combined(LogicalValueId::output1_first_swing, {memory[0x16], memory[0x17]}), 20000U);   // 0x4E20
  EXPECT_EQ(combined(LogicalValueId::output1_second_swing, {memory[0x18], memory[0x19]}), 40000U);  // 0x9C40
  EXPECT_EQ(combined(LogicalValueId::output2_first_swing, {memory[0x1A], memory[0x1B]}), 10000U);   // 0x2710
  EXPECT_EQ(combined(LogicalValueId::output2_second_swing, {memory[0x1C], memory[0x1D]}), 30000U);  // 0x7530
  EXPECT_EQ(combined(LogicalValueId::analog_lower_limit, {memory[0x11], memory[0x12]}), 0U);
  EXPECT_EQ(combined(LogicalValueId::analog_upper_limit, {memory[0x13], memory[0x14]}), 50000U);  // 0xC350
}

TEST(Ls5ParameterTable, CombineNeedsEveryByte) {
  const std::uint8_t one[] = {0x01};
  const auto value = combine_bytes(logical_value_info(LogicalValueId::measurement_period), one);
  ASSERT_FALSE(value.ok());
  EXPECT_EQ(value.error().code, Errc::wrong_form);
  EXPECT_EQ(combined(LogicalValueId::sensor_ip, {0xC0, 0xA8, 0x00, 0x03}), 0xC0A80003U);
  EXPECT_EQ(combined(LogicalValueId::destination_port, {0x02, 0x5B}), 603U);
}

TEST(Ls5ParameterTable, EnumerationsOfTable92L22) {
  EXPECT_EQ(baud_rate_from_code(0x01).value_or(0), 9600U);
  EXPECT_EQ(baud_rate_from_code(0x05).value_or(0), 115200U);
  EXPECT_EQ(baud_rate_from_code(0x08).value_or(0), 921600U);
  EXPECT_FALSE(baud_rate_from_code(0x09).has_value());
  EXPECT_EQ(baud_code_from_rate(57600).value_or(0), 0x04);
  EXPECT_FALSE(baud_code_from_rate(14400).has_value());

  const auto format = byte_format_from_code(0x04);
  ASSERT_TRUE(format.has_value());
  EXPECT_EQ(format->parity, Parity::even);  // "parity control, 2 stop bits"
  EXPECT_EQ(format->stop_bits, 2);
  EXPECT_EQ(byte_format_from_code(0x02)->parity, Parity::odd);  // "imparity control, 1 stop bit"
  EXPECT_FALSE(byte_format_from_code(0x06).has_value());

  EXPECT_EQ(latching_mode_from_byte(0x09), LatchingMode::output1_lower_output2_upper_to_rom);
  EXPECT_FALSE(latching_mode_from_byte(0x0A).has_value());
  for (const std::uint8_t odd : U8s{0x03, 0x05, 0x07, 0x09})
    EXPECT_TRUE(latching_writes_rom(*latching_mode_from_byte(odd)));
  for (const std::uint8_t even : U8s{0x00, 0x01, 0x02, 0x04, 0x06, 0x08}) {
    EXPECT_FALSE(latching_writes_rom(*latching_mode_from_byte(even)));
  }

  // Every named value is an accepted value of its parameter, and every accepted
  // value of an enumerated parameter has a name.
  for (const ParameterInfo& p : parameter_table()) {
    if (p.named_values.empty()) continue;
    for (const NamedValue& named : p.named_values) EXPECT_TRUE(value_in_spans(p, named.value)) << int{p.address};
    for (int v = 0; v <= 0xFF; ++v) {
      if (!value_in_spans(p, static_cast<std::uint8_t>(v))) continue;
      bool found = false;
      for (const NamedValue& named : p.named_values) found = found || named.value == v;
      EXPECT_TRUE(found) << int{p.address} << " value " << v;
    }
  }
  EXPECT_EQ(find_parameter(0x05)->named_values[4].cli_name, "115200");
  EXPECT_EQ(find_parameter(0x1F)->named_values[9].value, 0x09);
}

TEST(Ls5ParameterTable, DescribeAcceptedValues) {
  EXPECT_EQ(describe_accepted_values(*find_parameter(0x05)), "01-05; 06-08 from LS5.6.0");
  EXPECT_EQ(describe_accepted_values(*find_parameter(0x1F)), "00-01; 02-09 from LS5.9.0");
  EXPECT_EQ(describe_accepted_values(*find_parameter(0x6D)), "00-FF");  // L51
}
