// ULS §8 command rows. Ranges and error numbers follow U18, the measuring
// rule U24, get-reply shapes U29; pages are the document's (index, p. 22-36).
#include "rangekit/uls/commands.hpp"

#include <array>

#include "uls/fields.hpp"

namespace rangekit::uls {
namespace {

constexpr std::array<ValueName, 2> off_on{{{0, "off"}, {1, "on"}}};
constexpr std::array<ValueName, 2> autostart_names{{{0, "idle on power up"}, {1, "measuring on power up"}}};
constexpr std::array<ValueName, 2> continuous_names{{{0, "off (polled)"}, {1, "on"}}};
constexpr std::array<ValueName, 2> filter_names{{{0, "off (non-cooperative targets)"}, {1, "on (cooperative targets)"}}};
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

constexpr std::span<const ValueName> no_names{};

using A = Access;
using K = ValueKind;

// Field order: mnemonic, title, cli, access, kind, min, max, value_error, port_error,
// rejected_while_measuring, names, get_fields, set min/max, reply min/max, unit, reference.
constexpr std::array<CommandInfo, 36> commands{{
    {"DD", "Dither On/Off", "dither", A::get_set, K::flag, 0, 1, 1, 0, true, off_on, 0, 1, 1, 1, 1, "", "§8 p.25"},
    {"BM", "Get Measurement", "measure", A::get_only, K::measurement, 0, 0, 1, 0, false, no_names, 0, 0, 0, 1, 4,
     "", "§8 p.25, formats p.23-24"},
    {"ID", "Get Software Version", "version", A::get_only, K::text, 0, 0, 1, 0, false, no_names, 0, 0, 0, 1, 8, "",
     "§8 p.25"},
    {"US", "Get Unit Status", "status", A::get_only, K::status, 0, 11, 1, 0, false, status_names, 0, 0, 0, 1, 1, "",
     "§8 p.26"},
    {"MA", "Measurement Autostart On/Off", "autostart", A::get_set, K::flag, 0, 1, 1, 0, false, autostart_names, 0,
     1, 1, 1, 1, "", "§8 p.26"},
    {"GO", "Measurement Start", "start", A::action, K::none, 0, 0, 1, 0, false, no_names, 0, 0, 0, 0, 0, "",
     "§8 p.26"},
    {"ST", "Measurement Stop", "stop", A::action, K::none, 0, 0, 1, 0, false, no_names, 0, 0, 0, 0, 0, "", "§8 p.27"},
    {"PA", "Pointer Autostart On/Off", "pointer-autostart", A::get_set, K::flag, 0, 1, 1, 0, false, off_on, 0, 1, 1,
     1, 1, "", "§8 p.27"},
    {"PT", "Pointer On/Off", "pointer", A::set_only, K::flag, 0, 1, 1, 0, false, off_on, 0, 1, 1, 0, 0, "",
     "§8 p.27"},
    {"SU", "Save User Settings into Non-Volatile Memory", "save", A::action, K::none, 0, 0, 1, 0, false, no_names, 0,
     0, 0, 0, 0, "", "§8 p.27"},
    {"CL", "Set/Get 4-20 mA Current Loop On/Off", "current-loop", A::get_set, K::flag, 0, 1, 1, 0, false, off_on, 0,
     1, 1, 1, 1, "", "§8 p.28"},
    {"AW", "Set/Get Averaging Weight (Number of Good Pulses)", "averaging-weight", A::get_set, K::unsigned_int, 1,
     65535, 35, 0, true, no_names, 0, 1, 1, 1, 1, "pulses", "§8 p.28"},
    {"BR", "Set/Get Baud Rate", "baud", A::get_set, K::baud_with_port, 1200, 230400, 34, 84, true, port_names, 1, 2,
     2, 2, 2, "baud", "§8 p.28, choices §9 p.37"},
    {"BS", "Set/Get Bin Size", "bin-size", A::get_set, K::enumeration, 0, 8, 1, 0, true, bin_size_names, 0, 1, 1, 1,
     1, "", "§8 p.29, §9 p.40"},
    {"BH", "Set/Get Bin Threshold", "bin-threshold", A::get_set, K::unsigned_int, 1, 65535, 1, 0, true, no_names, 0,
     1, 1, 1, 1, "hits", "§8 p.29"},
    {"CO", "Set/Get Continuous Measurement Output Mode", "continuous", A::get_set, K::flag, 0, 1, 1, 0, false,
     continuous_names, 0, 1, 1, 1, 1, "", "§8 p.29"},
    {"FL", "Set/Get Cooperative Filter", "cooperative-filter", A::get_set, K::flag, 0, 1, 1, 0, true, filter_names,
     0, 1, 1, 1, 1, "", "§8 p.30"},
    {"DM", "Set/Get Display Mode in Averaging", "display", A::get_set, K::enumeration, 1, 3, 1, 0, true,
     display_names, 0, 1, 1, 1, 1, "", "§8 p.30"},
    {"AF", "Set/Get 4-20 mA Fault Current Value", "fault-current", A::get_set, K::milliamps, 0, 24, 83, 0, false,
     no_names, 0, 1, 1, 1, 1, "mA", "§8 p.30, §6"},
    {"AT", "Set/Get Fault Timeout for 4-20 mA Current Loop", "fault-timeout", A::get_set, K::seconds, 0, 3600, 83, 0,
     false, no_names, 0, 1, 1, 1, 1, "s", "§8 p.31, §6"},
    {"LG", "Set/Get Long Gate", "long-gate", A::get_set, K::distance, 0, 1700, 1, 0, true, no_names, 0, 1, 1, 1, 1,
     "user units", "§8 p.31"},
    {"MM", "Set/Get Measurement Mode", "mode", A::get_set, K::enumeration, 1, 3, 85, 0, true, mode_names, 0, 1, 1,
     1, 1, "", "§8 p.31"},
    {"MO", "Set/Get Measurement Output Port", "output-port", A::get_set, K::enumeration, 0, 2, 84, 0, true,
     output_port_names, 0, 1, 1, 1, 1, "", "§8 p.32"},
    {"MU", "Set/Get Measurement Units", "units", A::get_set, K::enumeration, 0, 1, 1, 0, true, units_names, 0, 1, 1,
     1, 1, "", "§8 p.32"},
    {"PL", "Set/Get Power Level", "power", A::get_set, K::enumeration, 0, 2, 1, 0, true, power_names, 0, 1, 1, 1, 1,
     "", "§8 p.32"},
    {"PF", "Set/Get PRF", "prf", A::get_set, K::prf_list, 10, 5000, 32, 0, true, no_names, 0, 1, 3, 3, 3, "Hz",
     "§8 p.33, §2 p.10"},
    {"PO", "Set/Get Pulses Per Measurement", "ppm", A::get_set, K::ppm_list, 1, 65535, 1, 0, true, no_names, 0, 1,
     2, 2, 2, "pulses", "§8 p.33"},
    {"AH", "Set/Get Range at 20 mA", "range-20ma", A::get_set, K::distance, 0, 1700, 83, 0, false, no_names, 0, 1,
     1, 1, 1, "user units", "§8 p.33, §6"},
    {"AL", "Set/Get Range at 4 mA", "range-4ma", A::get_set, K::distance, 0, 1700, 83, 0, false, no_names, 0, 1, 1,
     1, 1, "user units", "§8 p.34, §6"},
    {"TE", "Set/Get RS485 Bus Termination On/Off", "termination", A::get_set, K::flag, 0, 1, 1, 0, false, off_on, 0,
     1, 1, 1, 1, "", "§8 p.34"},
    {"SG", "Set/Get Short Gate", "short-gate", A::get_set, K::distance, 0, 1700, 1, 0, true, no_names, 0, 1, 1, 1, 1,
     "user units", "§8 p.34"},
    {"TB", "Set/Get Time between Events", "time-between-events", A::get_set, K::flag, 0, 1, 1, 0, true, off_on, 0,
     1, 1, 1, 1, "", "§8 p.35, §3 p.15"},
    {"TP", "Set/Get Trip Point", "trip-point", A::get_set, K::distance, 0, 1700, 1, 0, true, no_names, 0, 1, 1, 1,
     1, "user units", "§8 p.35"},
    {"TT", "Set/Get Trip Point Timeout", "trip-timeout", A::get_set, K::hex_pulses, 0, 4294967295.0, 1, 0, true,
     no_names, 0, 1, 1, 1, 1, "pulses (hex, seconds x 3000)", "§8 p.35, §3"},
    {"UA", "Set/Get Unit Address", "address", A::get_set, K::address_char, 0x30, 0xEF, 1, 0, true, no_names, 0, 1,
     1, 1, 1, "", "§8 p.36, §7"},
    {"OF", "Set/Get User Offset", "offset", A::get_set, K::signed_distance, -1700, 1700, 1, 0, true, no_names, 0, 1,
     1, 1, 1, "user units", "§8 p.36"},
}};

}  // namespace

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

const CommandInfo* find_command_by_cli_name(std::string_view cli_name) noexcept {
  for (const CommandInfo& row : commands) {
    if (row.cli_name == cli_name) return &row;
  }
  return nullptr;
}

std::string_view access_name(Access access) noexcept {
  switch (access) {
    case Access::get_set: return "get+set";
    case Access::get_only: return "get";
    case Access::set_only: return "set";
    case Access::action: return "action";
  }
  return "unknown";
}

std::string_view value_kind_name(ValueKind kind) noexcept {
  switch (kind) {
    case ValueKind::none: return "none";
    case ValueKind::flag: return "flag";
    case ValueKind::enumeration: return "enumeration";
    case ValueKind::unsigned_int: return "unsigned integer";
    case ValueKind::distance: return "distance";
    case ValueKind::signed_distance: return "signed distance";
    case ValueKind::milliamps: return "milliamps";
    case ValueKind::seconds: return "seconds";
    case ValueKind::hex_pulses: return "hex pulse count";
    case ValueKind::baud_with_port: return "port and baud";
    case ValueKind::prf_list: return "PRF list (1 or 3)";
    case ValueKind::ppm_list: return "PPM list (1 or 2)";
    case ValueKind::address_char: return "address character";
    case ValueKind::measurement: return "measurement";
    case ValueKind::text: return "text";
    case ValueKind::status: return "status";
  }
  return "unknown";
}

}  // namespace rangekit::uls
