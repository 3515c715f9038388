// ULS §8 command rows. Ranges and error numbers follow U18, the measuring
// rule U24, get-reply shapes U29; pages are the document's (index, p. 22-36).
#include "rangekit/uls/commands.hpp"

#include <cctype>

#include <array>

#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

constexpr std::array<ValueName, 2> off_on{{{0, "off"}, {1, "on"}}};
constexpr std::array<ValueName, 2> autostart_names{{{0, "idle on power up"}, {1, "measuring on power up"}}};
constexpr std::array<ValueName, 2> continuous_names{{{0, "off (polled)"}, {1, "on"}}};
constexpr std::array<ValueName, 2> filter_names{
    {{0, "off (non-cooperative targets)"}, {1, "on (cooperative targets)"}}};
constexpr std::array<ValueName, 2> port_names{{{0, "configuration port"}, {1, "output port"}}};
constexpr std::array<ValueName, 9> bin_size_names{{{0, "1 inch"},
                                                   {1, "2 inches"},
                                                   {2, "4 inches"},
                                                   {3, "8 inches"},
                                                   {4, "16 inches"},
                                                   {5, "32 inches"},
                                                   {6, "64 inches"},
                                                   {7, "128 inches"},
                                                   {8, "256 inches"}}};
constexpr std::array<ValueName, 3> display_names{{{1, "range"}, {2, "range and intensity"}, {3, "intensity"}}};
constexpr std::array<ValueName, 3> mode_names{{{1, "averaging"}, {2, "binning"}, {3, "look down"}}};
constexpr std::array<ValueName, 3> output_port_names{
    {{0, "RS232 configuration port"}, {1, "RS232 universal port"}, {2, "RS485 universal port"}}};
constexpr std::array<ValueName, 2> units_names{{{0, "feet"}, {1, "metres"}}};
constexpr std::array<ValueName, 3> power_names{{{0, "high"}, {1, "medium"}, {2, "low"}}};
constexpr std::array<ValueName, 5> status_names{{{0, "error: initialisation failed"},
                                                 {1, "ready, not measuring"},
                                                 {3, "firing, look down"},
                                                 {7, "firing, averaging"},
                                                 {11, "firing, binning"}}};

using A = Access;
using Id = CommandId;
using K = ValueKind;

// U24: whether a set (or GO, U77) is refused with error 31 while the unit measures.
enum class WhileMeasuring { accepted, rejected };
constexpr auto accepted = WhileMeasuring::accepted;
constexpr auto rejected = WhileMeasuring::rejected;

// Row shapes. Most commands are a plain setting: "$CC" gets, "$CC,n" sets,
// "$CC,n" replies; the few others adjust one of these (U16, U29, U30).
constexpr CommandInfo setting(CommandId id, std::string_view mnemonic, std::string_view title, std::string_view cli,
                              ValueKind kind, double min, double max, int value_error, WhileMeasuring measuring,
                              std::string_view unit, std::string_view reference,
                              std::span<const ValueName> names = {}) {
  return CommandInfo{.id = id,
                     .mnemonic = mnemonic,
                     .title = title,
                     .cli_name = cli,
                     .access = A::get_set,
                     .kind = kind,
                     .min = min,
                     .max = max,
                     .value_error = value_error,
                     .port_error = 0,
                     .rejected_while_measuring = measuring == rejected,
                     .value_names = names,
                     .get_fields = 0,
                     .set_fields_min = 1,
                     .set_fields_max = 1,
                     .reply_fields_min = 1,
                     .reply_fields_max = 1,
                     .unit = unit,
                     .reference = reference};
}

constexpr CommandInfo flag(CommandId id, std::string_view mnemonic, std::string_view title, std::string_view cli,
                           WhileMeasuring measuring, std::string_view reference,
                           std::span<const ValueName> names = off_on) {
  return setting(id, mnemonic, title, cli, K::flag, 0, 1, 1, measuring, "", reference, names);
}

constexpr CommandInfo action(CommandId id, std::string_view mnemonic, std::string_view title, std::string_view cli,
                             std::string_view reference, WhileMeasuring measuring = accepted) {
  CommandInfo row = setting(id, mnemonic, title, cli, K::none, 0, 0, 1, measuring, "", reference);
  row.access = A::action;
  row.set_fields_min = row.set_fields_max = 0;
  row.reply_fields_min = row.reply_fields_max = 0;
  return row;
}

constexpr CommandInfo reading(CommandId id, std::string_view mnemonic, std::string_view title, std::string_view cli,
                              ValueKind kind, std::uint8_t reply_fields_max, std::string_view reference,
                              std::span<const ValueName> names = {}) {
  CommandInfo row = setting(id, mnemonic, title, cli, kind, 0, 0, 1, accepted, "", reference, names);
  row.access = A::get_only;
  row.set_fields_min = row.set_fields_max = 0;
  row.reply_fields_max = reply_fields_max;
  return row;
}

constexpr CommandInfo set_only(CommandInfo row) {
  row.access = A::set_only;
  row.reply_fields_min = row.reply_fields_max = 0;
  return row;
}

// PF (1 or 3 values, U14) and PO (1 or 2, U15); the get reply always carries all.
constexpr CommandInfo value_list(CommandInfo row, std::uint8_t values) {
  row.set_fields_max = values;
  row.reply_fields_min = row.reply_fields_max = values;
  return row;
}

// BR: the get names a port, the set and the reply carry port and baud.
constexpr CommandInfo per_port(CommandInfo row, int port_error) {
  row.port_error = port_error;
  row.get_fields = 1;
  row.set_fields_min = row.set_fields_max = 2;
  row.reply_fields_min = row.reply_fields_max = 2;
  return row;
}

constexpr std::array<CommandInfo, command_count> commands{{
    flag(Id::dither, "DD", "Dither On/Off", "dither", rejected, "§8 p.25"),
    reading(Id::measure, "BM", "Get Measurement", "measure", K::measurement, 4, "§8 p.25, formats p.23-24"),
    reading(Id::version, "ID", "Get Software Version", "version", K::text, 8, "§8 p.25"),
    reading(Id::status, "US", "Get Unit Status", "status", K::status, 1, "§8 p.26", status_names),
    flag(Id::autostart, "MA", "Measurement Autostart On/Off", "autostart", accepted, "§8 p.26", autostart_names),
    action(Id::start, "GO", "Measurement Start", "start", "§8 p.26",
           rejected),  // "Instrument Is Already Measuring" (U77)
    action(Id::stop, "ST", "Measurement Stop", "stop", "§8 p.27"),
    flag(Id::pointer_autostart, "PA", "Pointer Autostart On/Off", "pointer-autostart", accepted, "§8 p.27"),
    set_only(flag(Id::pointer, "PT", "Pointer On/Off", "pointer", accepted, "§8 p.27")),
    action(Id::save, "SU", "Save User Settings into Non-Volatile Memory", "save", "§8 p.27"),
    flag(Id::current_loop, "CL", "Set/Get 4-20 mA Current Loop On/Off", "current-loop", accepted, "§8 p.28"),
    setting(Id::averaging_weight, "AW", "Set/Get Averaging Weight (Number of Good Pulses)", "averaging-weight",
            K::unsigned_int, 1, 65535, 35, rejected, "pulses", "§8 p.28"),
    per_port(setting(Id::baud, "BR", "Set/Get Baud Rate", "baud", K::baud_with_port, 1200, 230400, 34, rejected, "baud",
                     "§8 p.28, choices §9 p.37", port_names),
             84),
    setting(Id::bin_size, "BS", "Set/Get Bin Size", "bin-size", K::enumeration, 0, 8, 1, rejected, "",
            "§8 p.29, §9 p.40", bin_size_names),
    setting(Id::bin_threshold, "BH", "Set/Get Bin Threshold", "bin-threshold", K::unsigned_int, 1, 65535, 1, rejected,
            "hits", "§8 p.29"),
    flag(Id::continuous, "CO", "Set/Get Continuous Measurement Output Mode", "continuous", accepted, "§8 p.29",
         continuous_names),
    flag(Id::cooperative_filter, "FL", "Set/Get Cooperative Filter", "cooperative-filter", rejected, "§8 p.30",
         filter_names),
    setting(Id::display, "DM", "Set/Get Display Mode in Averaging", "display", K::enumeration, 1, 3, 1, rejected, "",
            "§8 p.30", display_names),
    setting(Id::fault_current, "AF", "Set/Get 4-20 mA Fault Current Value", "fault-current", K::milliamps, 0, 24, 83,
            accepted, "mA", "§8 p.30, §6"),
    setting(Id::fault_timeout, "AT", "Set/Get Fault Timeout for 4-20 mA Current Loop", "fault-timeout", K::seconds, 0,
            3600, 83, accepted, "s", "§8 p.31, §6"),
    setting(Id::long_gate, "LG", "Set/Get Long Gate", "long-gate", K::distance, 0, 1700, 1, rejected, "user units",
            "§8 p.31"),
    setting(Id::mode, "MM", "Set/Get Measurement Mode", "mode", K::enumeration, 1, 3, 85, rejected, "", "§8 p.31",
            mode_names),
    setting(Id::output_port, "MO", "Set/Get Measurement Output Port", "output-port", K::enumeration, 0, 2, 84, rejected,
            "", "§8 p.32", output_port_names),
    setting(Id::units, "MU", "Set/Get Measurement Units", "units", K::enumeration, 0, 1, 1, rejected, "", "§8 p.32",
            units_names),
    setting(Id::power, "PL", "Set/Get Power Level", "power", K::enumeration, 0, 2, 1, rejected, "", "§8 p.32",
            power_names),
    value_list(
        setting(Id::prf, "PF", "Set/Get PRF", "prf", K::prf_list, 10, 5000, 32, rejected, "Hz", "§8 p.33, §2 p.10"), 3),
    value_list(setting(Id::ppm, "PO", "Set/Get Pulses Per Measurement", "ppm", K::ppm_list, 1, 65535, 1, rejected,
                       "pulses", "§8 p.33"),
               2),
    setting(Id::range_at_20ma, "AH", "Set/Get Range at 20 mA", "range-20ma", K::distance, 0, 1700, 83, accepted,
            "user units", "§8 p.33, §6"),
    setting(Id::range_at_4ma, "AL", "Set/Get Range at 4 mA", "range-4ma", K::distance, 0, 1700, 83, accepted,
            "user units", "§8 p.34, §6"),
    flag(Id::termination, "TE", "Set/Get RS485 Bus Termination On/Off", "termination", accepted, "§8 p.34"),
    setting(Id::short_gate, "SG", "Set/Get Short Gate", "short-gate", K::distance, 0, 1700, 1, rejected, "user units",
            "§8 p.34"),
    flag(Id::time_between_events, "TB", "Set/Get Time between Events", "time-between-events", rejected,
         "§8 p.35, §3 p.15"),
    setting(Id::trip_point, "TP", "Set/Get Trip Point", "trip-point", K::distance, 0, 1700, 1, rejected, "user units",
            "§8 p.35"),
    setting(Id::trip_timeout, "TT", "Set/Get Trip Point Timeout", "trip-timeout", K::hex_pulses, 0, 4294967295.0, 1,
            rejected, "pulses (hex, seconds x 3000)", "§8 p.35, §3"),
    setting(Id::address, "UA", "Set/Get Unit Address", "address", K::address_char, 0x30, 0xEF, 1, rejected, "",
            "§8 p.36, §7"),
    setting(Id::offset, "OF", "Set/Get User Offset", "offset", K::signed_distance, -1700, 1700, 1, rejected,
            "user units", "§8 p.36"),
}};

// command_info() indexes the table by id: the rows must stand in the enum's order.
constexpr bool rows_in_id_order() {
  for (std::size_t i = 0; i < commands.size(); ++i) {
    if (static_cast<std::size_t>(commands[i].id) != i) return false;
  }
  return true;
}
static_assert(rows_in_id_order(), "ULS command rows out of CommandId order");

}  // namespace

const CommandInfo& command_info(CommandId id) noexcept { return commands[static_cast<std::size_t>(id)]; }

std::string_view CommandInfo::value_name(std::uint32_t value) const noexcept {
  for (const ValueName& entry : value_names) {
    if (entry.value == value) return entry.name;
  }
  return {};
}

std::span<const CommandInfo> command_table() noexcept { return commands; }

const CommandInfo* find_command(std::string_view mnemonic) noexcept {
  for (const CommandInfo& row : commands) {
    if (detail::equal_ignoring_case(row.mnemonic, mnemonic)) return &row;
  }
  return nullptr;
}

std::string value_key(std::string_view name) {
  std::string text;
  for (const char c : name) {
    if (c == '(') break;
    text.push_back(c == ' ' || c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  while (!text.empty() && text.back() == '-') text.pop_back();
  return text;
}

const CommandInfo* find_command_by_cli_name(std::string_view cli_name) noexcept {
  for (const CommandInfo& row : commands) {
    if (row.cli_name == cli_name) return &row;
  }
  return nullptr;
}

std::string_view access_name(Access access) noexcept {
  switch (access) {
    case Access::get_set:
      return "get+set";
    case Access::get_only:
      return "get";
    case Access::set_only:
      return "set";
    case Access::action:
      return "action";
  }
  return "unknown";
}

std::string_view value_kind_name(ValueKind kind) noexcept {
  switch (kind) {
    case ValueKind::none:
      return "none";
    case ValueKind::flag:
      return "flag";
    case ValueKind::enumeration:
      return "enumeration";
    case ValueKind::unsigned_int:
      return "unsigned integer";
    case ValueKind::distance:
      return "distance";
    case ValueKind::signed_distance:
      return "signed distance";
    case ValueKind::milliamps:
      return "milliamps";
    case ValueKind::seconds:
      return "seconds";
    case ValueKind::hex_pulses:
      return "hex pulse count";
    case ValueKind::baud_with_port:
      return "port and baud";
    case ValueKind::prf_list:
      return "PRF list (1 or 3)";
    case ValueKind::ppm_list:
      return "PPM list (1 or 2)";
    case ValueKind::address_char:
      return "address character";
    case ValueKind::measurement:
      return "measurement";
    case ValueKind::text:
      return "text";
    case ValueKind::status:
      return "status";
  }
  return "unknown";
}

}  // namespace rangekit::uls
