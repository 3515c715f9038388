#include "modbus/register_map.hpp"

#include <algorithm>
#include <cctype>

#include "rangekit/hub/site_config.hpp"

namespace rangekit::modbus {
namespace {

// The site file's table of word orders, in WordOrder's order.
constexpr const auto& word_order_names = hub::modbus_word_orders;
static_assert(word_order_names[static_cast<std::size_t>(WordOrder::dcba)] == "DCBA");

// The rows before the targets; the targets' rows are made from max_targets.
constexpr std::array<RegisterRow, 10> fixed_input_rows{{
    {input::reading_mm, RegisterType::float32, "reading_mm", "mm",
     "the reading (binning: the nearest target); NaN when the last sample has none"},
    {input::reading_um, RegisterType::int32, "reading_um", "um",
     "the same reading in micrometres; -2147483648 when it has none"},
    {input::status, RegisterType::bits16, "status", "",
     "bit 0 connected, 1 streaming, 2 reading valid, 3 suspect, 4 stale, 5 no target"},
    {input::device_error, RegisterType::uint16, "device_error", "",
     "the last sample's device error number, or its result code when it saw nothing; 0 for none"},
    {input::sequence, RegisterType::uint32, "sequence", "", "rises by one with every new sample"},
    {input::age_ms, RegisterType::uint16, "age_ms", "ms", "since the last sample arrived, at most 65535"},
    {input::records, RegisterType::uint32, "records", "", "samples read since the service started"},
    {input::errors, RegisterType::uint32, "errors", "", "samples that carried a device error"},
    {input::lost, RegisterType::uint32, "lost", "", "records lost on the way (UDP gaps, full queues)"},
    {input::target_count, RegisterType::uint16, "target_count", "",
     "targets of the last binning burst (0-15); 1 for a single reading, 0 for none"},
}};

constexpr std::array<std::string_view, input::max_targets> target_names{
    "target_1_mm",  "target_2_mm",  "target_3_mm",  "target_4_mm",  "target_5_mm",
    "target_6_mm",  "target_7_mm",  "target_8_mm",  "target_9_mm",  "target_10_mm",
    "target_11_mm", "target_12_mm", "target_13_mm", "target_14_mm", "target_15_mm"};

constexpr std::array<RegisterRow, fixed_input_rows.size() + input::max_targets> make_input_rows() {
  std::array<RegisterRow, fixed_input_rows.size() + input::max_targets> rows{};
  std::size_t at = 0;
  for (const RegisterRow& row : fixed_input_rows) rows[at++] = row;
  for (std::size_t target = 0; target < input::max_targets; ++target) {
    rows[at++] = RegisterRow{static_cast<std::uint16_t>(input::first_target_mm + 2 * target), RegisterType::float32,
                             target_names[target], "mm", "a target of the last binning burst, nearest first"};
  }
  return rows;
}
constexpr auto all_input_rows = make_input_rows();
static_assert(all_input_rows.back().address + 2 == input::count);

constexpr std::array<RegisterRow, holding::count> all_holding_rows{{
    {holding::command, RegisterType::uint16, "command", "", "write a command code (docs/modbus.md); reads the last"},
    {holding::command_state, RegisterType::uint16, "command_state", "", "0 idle, 1 running, 2 done, 3 failed"},
    {holding::command_done, RegisterType::uint16, "command_done", "", "commands finished, rising by one each"},
}};

constexpr std::array codes{
    CommandCode{1, "start", "", "start streaming"},
    CommandCode{2, "stop", "", "stop streaming"},
    CommandCode{3, "single", "", "one measurement now"},
    CommandCode{4, "pointer", "on", "the visible pointer on"},
    CommandCode{5, "pointer", "off", "the visible pointer off"},
    CommandCode{6, "latch", "", "latch a result and read it"},
};

// A field of CSV: quoted when it holds a comma or a quote.
std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

void append_rows(std::string& out, std::uint8_t unit, std::string_view sensor, std::string_view table,
                 std::span<const RegisterRow> rows, WordOrder order) {
  for (const RegisterRow& row : rows) {
    out += std::to_string(unit) + "," + csv_field(sensor) + "," + std::string(table) + "," +
           std::to_string(row.address) + "," + std::string(register_type_name(row.type)) + "," + std::string(row.name) +
           "," + std::string(row.unit) + "," + std::string(words_of(row.type) == 2 ? word_order_name(order) : "") +
           "," + csv_field(row.description) + "\n";
  }
}

}  // namespace

std::optional<WordOrder> parse_word_order(std::string_view text) {
  std::string upper(text);
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  for (std::size_t at = 0; at < word_order_names.size(); ++at) {
    if (upper == word_order_names[at]) return static_cast<WordOrder>(at);
  }
  return std::nullopt;
}

std::string_view word_order_name(WordOrder order) noexcept { return word_order_names[static_cast<std::size_t>(order)]; }

std::string_view register_type_name(RegisterType type) noexcept {
  switch (type) {
    case RegisterType::float32:
      return "float32";
    case RegisterType::int32:
      return "int32";
    case RegisterType::uint32:
      return "uint32";
    case RegisterType::uint16:
      return "uint16";
    case RegisterType::bits16:
      return "bits16";
  }
  return "uint16";
}

std::span<const CommandCode> command_codes() noexcept { return codes; }

const CommandCode* find_command_code(std::uint16_t code) noexcept {
  for (const CommandCode& each : codes) {
    if (each.code == code) return &each;
  }
  return nullptr;
}

std::span<const RegisterRow> input_rows() noexcept { return all_input_rows; }
std::span<const RegisterRow> holding_rows() noexcept { return all_holding_rows; }

std::array<std::uint16_t, 2> words_of_u32(std::uint32_t value, WordOrder order) noexcept {
  const auto high = static_cast<std::uint16_t>(value >> 16);
  const auto low = static_cast<std::uint16_t>(value & 0xFFFFU);
  const auto swapped = [](std::uint16_t word) { return static_cast<std::uint16_t>((word >> 8) | (word << 8)); };
  switch (order) {
    case WordOrder::abcd:
      return {high, low};
    case WordOrder::cdab:
      return {low, high};
    case WordOrder::badc:
      return {swapped(high), swapped(low)};
    case WordOrder::dcba:
      return {swapped(low), swapped(high)};
  }
  return {high, low};
}

std::uint32_t u32_of_words(std::uint16_t first, std::uint16_t second, WordOrder order) noexcept {
  // Each order is its own inverse word by word: laying the two words out again undoes it.
  const auto back = words_of_u32((static_cast<std::uint32_t>(first) << 16) | second, order);
  return (static_cast<std::uint32_t>(back[0]) << 16) | back[1];
}

std::string write_register_map(std::span<const std::pair<std::uint8_t, std::string>> units, WordOrder order,
                               bool writable) {
  std::string out = "unit,sensor,table,register,type,name,unit_of_measure,word_order,description\n";
  for (const auto& [unit, sensor] : units) {
    append_rows(out, unit, sensor, "input", input_rows(), order);
    if (writable) append_rows(out, unit, sensor, "holding", holding_rows(), order);
  }
  return out;
}

}  // namespace rangekit::modbus
