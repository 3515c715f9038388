// The §8 command table and the checks a unit applies (U16, U18, U24, U30, U76, U77, U80).
// Expected values are typed from the document and docs/conformance.md.
#include <gtest/gtest.h>

#include <array>
#include <set>
#include <string>

#include "rangekit/uls/uls.hpp"

namespace rangekit::uls {
namespace {

// §8 "ULS Commands", in the order presented, with the headings' pages (index).
struct Expected {
  std::string_view mnemonic;
  std::string_view cli;
  Access access;
  std::string_view page;
};
constexpr std::array<Expected, 36> section8{{
    {"DD", "dither", Access::get_set, "p.25"},
    {"BM", "measure", Access::get_only, "p.25"},
    {"ID", "version", Access::get_only, "p.25"},
    {"US", "status", Access::get_only, "p.26"},
    {"MA", "autostart", Access::get_set, "p.26"},
    {"GO", "start", Access::action, "p.26"},
    {"ST", "stop", Access::action, "p.27"},
    {"PA", "pointer-autostart", Access::get_set, "p.27"},
    {"PT", "pointer", Access::set_only, "p.27"},
    {"SU", "save", Access::action, "p.27"},
    {"CL", "current-loop", Access::get_set, "p.28"},
    {"AW", "averaging-weight", Access::get_set, "p.28"},
    {"BR", "baud", Access::get_set, "p.28"},
    {"BS", "bin-size", Access::get_set, "p.29"},
    {"BH", "bin-threshold", Access::get_set, "p.29"},
    {"CO", "continuous", Access::get_set, "p.29"},
    {"FL", "cooperative-filter", Access::get_set, "p.30"},
    {"DM", "display", Access::get_set, "p.30"},
    {"AF", "fault-current", Access::get_set, "p.30"},
    {"AT", "fault-timeout", Access::get_set, "p.31"},
    {"LG", "long-gate", Access::get_set, "p.31"},
    {"MM", "mode", Access::get_set, "p.31"},
    {"MO", "output-port", Access::get_set, "p.32"},
    {"MU", "units", Access::get_set, "p.32"},
    {"PL", "power", Access::get_set, "p.32"},
    {"PF", "prf", Access::get_set, "p.33"},
    {"PO", "ppm", Access::get_set, "p.33"},
    {"AH", "range-20ma", Access::get_set, "p.33"},
    {"AL", "range-4ma", Access::get_set, "p.34"},
    {"TE", "termination", Access::get_set, "p.34"},
    {"SG", "short-gate", Access::get_set, "p.34"},
    {"TB", "time-between-events", Access::get_set, "p.35"},
    {"TP", "trip-point", Access::get_set, "p.35"},
    {"TT", "trip-timeout", Access::get_set, "p.35"},
    {"UA", "address", Access::get_set, "p.36"},
    {"OF", "offset", Access::get_set, "p.36"},
}};

TEST(UlsCommandTable, HoldsEveryCommandOfSection8InOrder) {
  const auto table = command_table();
  ASSERT_EQ(table.size(), section8.size());
  std::set<std::string_view> mnemonics;
  std::set<std::string_view> cli_names;
  for (std::size_t i = 0; i < table.size(); ++i) {
    SCOPED_TRACE(std::string(section8[i].mnemonic));
    EXPECT_EQ(table[i].mnemonic, section8[i].mnemonic);
    EXPECT_EQ(table[i].cli_name, section8[i].cli);
    EXPECT_EQ(table[i].access, section8[i].access);
    EXPECT_NE(table[i].reference.find(section8[i].page), std::string_view::npos) << table[i].reference;
    EXPECT_FALSE(table[i].title.empty());
    EXPECT_NE(find_error(table[i].value_error), nullptr);
    mnemonics.insert(table[i].mnemonic);
    cli_names.insert(table[i].cli_name);
  }
  EXPECT_EQ(mnemonics.size(), 36U);
  EXPECT_EQ(cli_names.size(), 36U);
}

TEST(UlsCommandTable, TitlesAreTheHeadings) {  // §8 headings
  EXPECT_EQ(find_command("AW")->title, "Set/Get Averaging Weight (Number of Good Pulses)");
  EXPECT_EQ(find_command("SU")->title, "Save User Settings into Non-Volatile Memory");
  EXPECT_EQ(find_command("TB")->title, "Set/Get Time between Events");
  EXPECT_EQ(find_command("CL")->title, "Set/Get 4-20 mA Current Loop On/Off");
}

TEST(UlsCommandTable, LookupByMnemonicAndCliName) {
  EXPECT_EQ(find_command("pf"), find_command("PF"));
  EXPECT_EQ(find_command_by_cli_name("prf"), find_command("PF"));
  EXPECT_EQ(find_command_by_cli_name("mode"), find_command("MM"));
  EXPECT_EQ(find_command_by_cli_name("units"), find_command("MU"));
  EXPECT_EQ(find_command_by_cli_name("averaging-weight"), find_command("AW"));
  EXPECT_EQ(find_command_by_cli_name("bin-size"), find_command("BS"));
  EXPECT_EQ(find_command("XX"), nullptr);
  EXPECT_EQ(find_command(""), nullptr);
  EXPECT_EQ(find_command("MMM"), nullptr);
  EXPECT_EQ(find_command_by_cli_name("PRF"), nullptr);
}

// Code dispatches on a row's id (the emulator's firmware does): each id names its own row.
TEST(UlsCommandTable, LookupById) {
  EXPECT_EQ(command_info(CommandId::dither).mnemonic, "DD");  // §8 p.25, the first command
  EXPECT_EQ(command_info(CommandId::measure).mnemonic, "BM");
  EXPECT_EQ(command_info(CommandId::long_gate).mnemonic, "LG");
  EXPECT_EQ(command_info(CommandId::range_at_4ma).mnemonic, "AL");
  EXPECT_EQ(command_info(CommandId::range_at_20ma).mnemonic, "AH");
  EXPECT_EQ(command_info(CommandId::offset).mnemonic, "OF");  // §8 p.36, the last command
  std::set<CommandId> ids;
  for (const CommandInfo& row : command_table()) {
    ids.insert(row.id);
    EXPECT_EQ(&command_info(row.id), &row) << row.mnemonic;
  }
  EXPECT_EQ(ids.size(), 36u);
}

// §8 AH/AL: "Range at 20mA in user units (decimal feet or meters)"; LG, SG, TP and OF
// are distances the same way. AF (mA), AT (seconds) and the counts are not.
TEST(UlsCommandTable, DistancesAreTheUserUnitValues) {
  for (const std::string_view mnemonic : {"LG", "SG", "TP", "AH", "AL", "OF"})
    EXPECT_TRUE(find_command(mnemonic)->is_distance()) << mnemonic;
  for (const std::string_view mnemonic : {"AF", "AT", "AW", "BH", "TT", "MU", "BM"})
    EXPECT_FALSE(find_command(mnemonic)->is_distance()) << mnemonic;
}

TEST(UlsCommandTable, ValueKindsAndNames) {  // §8 value definitions
  EXPECT_EQ(find_command("DD")->kind, ValueKind::flag);
  EXPECT_EQ(find_command("BR")->kind, ValueKind::baud_with_port);
  EXPECT_EQ(find_command("PF")->kind, ValueKind::prf_list);
  EXPECT_EQ(find_command("PO")->kind, ValueKind::ppm_list);
  EXPECT_EQ(find_command("TT")->kind, ValueKind::hex_pulses);
  EXPECT_EQ(find_command("UA")->kind, ValueKind::address_char);
  EXPECT_EQ(find_command("OF")->kind, ValueKind::signed_distance);
  EXPECT_EQ(find_command("AH")->kind, ValueKind::distance);
  EXPECT_EQ(find_command("AF")->kind, ValueKind::milliamps);
  EXPECT_EQ(find_command("AT")->kind, ValueKind::seconds);
  EXPECT_EQ(find_command("MU")->value_name(0), "feet");
  EXPECT_EQ(find_command("MU")->value_name(1), "metres");
  EXPECT_EQ(find_command("PL")->value_name(0), "high");
  EXPECT_EQ(find_command("PL")->value_name(2), "low");
  EXPECT_EQ(find_command("DM")->value_name(2), "range and intensity");
  EXPECT_EQ(find_command("MO")->value_name(2), "RS485 universal port");
  EXPECT_EQ(find_command("BS")->value_name(8), "256 inches");
  EXPECT_EQ(find_command("US")->value_name(11), "firing, binning");
  EXPECT_EQ(find_command("MM")->value_name(4), "");
}

TEST(UlsConformance, U16_PointerIsSetOnly) {  // §8 Pointer On/Off shows only a Set form
  const CommandInfo& pt = *find_command("PT");
  EXPECT_FALSE(pt.has_get());
  EXPECT_EQ(validate_request(pt, {}).error, 1);
  const std::array<std::string_view, 1> on{"1"};
  EXPECT_TRUE(validate_request(pt, on).ok());
}

Verdict set(std::string_view mnemonic, std::string_view value, Units units = Units::metres) {
  return validate_request(mnemonic, {&value, 1}, units);
}

TEST(UlsConformance, U18_FlagsAreZeroOrOne) {
  for (const std::string_view flag : {"DD", "MA", "PA", "PT", "CL", "CO", "FL", "TE", "TB", "MU"}) {
    SCOPED_TRACE(std::string(flag));
    EXPECT_TRUE(set(flag, "0").ok());
    EXPECT_TRUE(set(flag, "1").ok());
    EXPECT_EQ(set(flag, "2").error, 1);
    EXPECT_EQ(set(flag, "on").error, 1);
  }
}

TEST(UlsConformance, U18_EnumerationsAndTheirErrors) {
  EXPECT_TRUE(set("PL", "2").ok());
  EXPECT_EQ(set("PL", "3").error, 1);
  EXPECT_TRUE(set("BS", "8").ok());
  EXPECT_EQ(set("BS", "9").error, 1);
  EXPECT_TRUE(set("DM", "1").ok());
  EXPECT_EQ(set("DM", "0").error, 1);
  EXPECT_EQ(set("DM", "4").error, 1);
  EXPECT_TRUE(set("MO", "2").ok());
  EXPECT_EQ(set("MO", "3").error, 84);  // Invalid Port
  EXPECT_EQ(set("MM", "0").error, 85);  // Invalid Measurement Mode
}

TEST(UlsConformance, U18_BaudRateAndPort) {  // §8 Set/Get Baud Rate, §9 choices
  const CommandInfo& br = *find_command("BR");
  const auto check = [&](std::string_view port, std::string_view baud) {
    const std::array<std::string_view, 2> fields{port, baud};
    return validate_request(br, fields).error;
  };
  for (const std::string_view baud :
       {"1200", "2400", "4800", "9600", "14400", "19200", "38400", "57600", "115200", "230400"}) {
    EXPECT_EQ(check("0", baud), 0) << baud;
    EXPECT_EQ(check("1", baud), 0) << baud;
  }
  EXPECT_EQ(check("2", "9600"), 84);
  EXPECT_EQ(check("0", "9601"), 34);
  EXPECT_EQ(check("0", "460800"), 34);
  EXPECT_EQ(check("0", "fast"), 1);
  const std::array<std::string_view, 1> get_port{"1"};
  const std::array<std::string_view, 1> get_bad_port{"2"};
  EXPECT_TRUE(validate_request(br, get_port).ok());
  EXPECT_EQ(validate_request(br, get_bad_port).error, 84);
  EXPECT_EQ(validate_request(br, {}).error, 1);  // the get names its port
}

TEST(UlsConformance, U18_CountsAndWeights) {
  EXPECT_TRUE(set("AW", "1").ok());
  EXPECT_TRUE(set("AW", "65535").ok());
  EXPECT_EQ(set("AW", "0").error, 35);  // Invalid Average Weight
  EXPECT_EQ(set("AW", "65536").error, 35);
  EXPECT_EQ(set("AW", "99999999999999999999999").error, 35);  // a number, too large
  EXPECT_TRUE(set("BH", "65535").ok());
  EXPECT_EQ(set("BH", "0").error, 1);
  EXPECT_EQ(set("BH", "65536").error, 1);
}

TEST(UlsConformance, U18_DistancesInUserUnits) {
  for (const std::string_view gate : {"SG", "LG", "TP"}) {
    SCOPED_TRACE(std::string(gate));
    EXPECT_TRUE(set(gate, "0").ok());
    EXPECT_TRUE(set(gate, "1700").ok());
    EXPECT_TRUE(set(gate, "1700.000").ok());
    EXPECT_EQ(set(gate, "1700.001").error, 1);
    EXPECT_EQ(set(gate, "-0.1").error, 1);
    EXPECT_TRUE(set(gate, "5577.42", Units::feet).ok());    // 1699.998 m
    EXPECT_EQ(set(gate, "5577.44", Units::feet).error, 1);  // 1700.004 m
  }
  EXPECT_TRUE(set("OF", "-1700").ok());
  EXPECT_TRUE(set("OF", "1700").ok());
  EXPECT_EQ(set("OF", "-1700.5").error, 1);
  for (const std::string_view loop : {"AL", "AH"}) {
    EXPECT_TRUE(set(loop, "10.000").ok());
    EXPECT_EQ(set(loop, "1701").error, 83);  // Invalid MA420 Range
    EXPECT_EQ(set(loop, "-1").error, 83);
  }
  EXPECT_EQ(check_current_loop_range(0, 10), Verdict::accept());  // §6 example
  EXPECT_EQ(check_current_loop_range(10, 0), Verdict::accept());  // inverted (U23)
  EXPECT_EQ(check_current_loop_range(5, 5).error, 83);
}

TEST(UlsConformance, U18_CurrentLoopFaultValues) {
  EXPECT_TRUE(set("AF", "3.0").ok());  // §6 "Fault Indication 3.0 mA"
  EXPECT_TRUE(set("AF", "24").ok());
  EXPECT_EQ(set("AF", "24.1").error, 83);
  EXPECT_TRUE(set("AT", "0.0").ok());  // §6 "Fault Timeout 0.0 secs"
  EXPECT_TRUE(set("AT", "3600").ok());
  EXPECT_EQ(set("AT", "3601").error, 83);
}

TEST(UlsConformance, U18_NonNumbersAreError1) {
  for (const std::string_view mnemonic : {"AW", "PF", "PO", "MM", "LG", "AF", "AH", "BS"}) {
    EXPECT_EQ(set(mnemonic, "x").error, 1) << mnemonic;
    EXPECT_EQ(set(mnemonic, "1e3").error, 1) << mnemonic;
  }
  EXPECT_TRUE(set("TT", "1e3").ok());  // hex
  EXPECT_EQ(set("XX", "1").error, 1);  // unknown mnemonic
}

// docs/conformance.md U80. §8 TT: "h = Trip Point Timeout ((seconds * 3000) in hexadecimal
// notation)"; §10 33 "Invalid Input Base". TB is a 0/1 flag (§8 "n = 0 = Time between Events
// Off, n = 1 = On"), so its non-numbers stay error 1 like every flag's.
TEST(UlsConformance, U80_TripTimeoutNotInHexIsInvalidInputBase) {
  EXPECT_EQ(set("TT", "x").error, 33);
  EXPECT_EQ(set("TT", "1G40").error, 33);
  EXPECT_EQ(set("TT", "1.5").error, 33);
  EXPECT_EQ(set("TT", "-1").error, 33);
  EXPECT_EQ(set("TT", "123456789").error, 1);  // hex, but more than 8 digits (U18)
  EXPECT_TRUE(set("TT", "FFFFFFFF").ok());
  EXPECT_TRUE(set("TT", "107ac0").ok());
  EXPECT_EQ(set("TB", "x").error, 1);
  EXPECT_EQ(set("TB", "A").error, 1);
  EXPECT_EQ(set("AW", "1F").error, 1);  // decimal fields: no base is stated, so not a number (U18)
}

// docs/conformance.md U76. §9 "Resolution: 0.01 ft or 1 mm", §9 "1700 m or 5577 ft"; a get in
// feet writes the 1700 m limit as 5577.43 (1700 / 0.3048 = 5577.427), which must be accepted back
// although 5577.43 ft x 0.3048 = 1700.0007 m.
TEST(UlsConformance, U76_DistanceLimitsAsTheUnitWritesThem) {
  for (const std::string_view gate : {"SG", "LG", "TP", "OF"}) {
    SCOPED_TRACE(std::string(gate));
    EXPECT_TRUE(set(gate, "5577.43", Units::feet).ok());
    EXPECT_EQ(set(gate, "5577.44", Units::feet).error, 1);
    EXPECT_TRUE(set(gate, "1700.000").ok());
    EXPECT_EQ(set(gate, "1700.001").error, 1);
  }
  EXPECT_TRUE(set("OF", "-5577.43", Units::feet).ok());
  EXPECT_EQ(set("OF", "-5577.44", Units::feet).error, 1);
  EXPECT_TRUE(set("OF", "-1700.000").ok());
  EXPECT_EQ(set("OF", "-1700.001").error, 1);
  for (const std::string_view loop : {"AL", "AH"}) {
    SCOPED_TRACE(std::string(loop));
    EXPECT_TRUE(set(loop, "5577.43", Units::feet).ok());
    EXPECT_EQ(set(loop, "5577.44", Units::feet).error, 83);
  }
  // The host reads the same replies back.
  for (const std::string_view reply :
       {"$LG,5577.43", "$SG,5577.43", "$TP,5577.43", "$OF,-5577.43", "$OF,5577.43", "$AH,5577.43", "$AL,5577.43"}) {
    EXPECT_TRUE(decode_reply(as_bytes(reply), Units::feet)) << reply;
  }
  EXPECT_FALSE(decode_reply(as_bytes("$LG,5577.44"), Units::feet));
  EXPECT_TRUE(decode_reply(as_bytes("$LG,1700.000"), Units::metres));
  EXPECT_FALSE(decode_reply(as_bytes("$LG,1700.001"), Units::metres));
  // A limit in feet stands for the limit itself: a get in metres then shows 1700.000.
  EXPECT_DOUBLE_EQ(distance_to_metres(5577.43, Units::feet, 0, 1700), 1700.0);
  EXPECT_DOUBLE_EQ(distance_to_metres(-5577.43, Units::feet, -1700, 1700), -1700.0);
  EXPECT_DOUBLE_EQ(distance_limit(1700, Units::feet), 5577.43);
}

// docs/conformance.md U24, U77 (GO: §10 31 "Instrument Is Already Measuring").
TEST(UlsConformance, U24_SettingsThatChangeTheMeasurementAnswer31WhileMeasuring) {
  const std::set<std::string_view> rejected{"MM", "PF", "PO", "AW", "BS", "BH", "DD", "MU", "BR", "SG", "LG",
                                            "FL", "PL", "DM", "TB", "TP", "TT", "OF", "MO", "UA", "GO"};
  const std::set<std::string_view> accepted{"ST", "BM", "US", "ID", "PT", "CL", "AF", "AT",
                                            "AH", "AL", "CO", "MA", "PA", "TE", "SU"};
  EXPECT_EQ(rejected.size() + accepted.size(), 36U);
  for (const CommandInfo& command : command_table()) {
    SCOPED_TRACE(std::string(command.mnemonic));
    const bool should_reject = rejected.count(command.mnemonic) == 1;
    EXPECT_EQ(command.rejected_while_measuring, should_reject);
    EXPECT_EQ(accepted.count(command.mnemonic), should_reject ? 0U : 1U);
    // Gets are always accepted; sets and GO only when idle, or when not listed.
    EXPECT_TRUE(check_while_measuring(command, RequestForm::get, true).ok());
    EXPECT_TRUE(check_while_measuring(command, RequestForm::set, false).ok());
    EXPECT_TRUE(check_while_measuring(command, RequestForm::action, false).ok());
    const RequestForm changing = command.access == Access::action ? RequestForm::action : RequestForm::set;
    EXPECT_EQ(check_while_measuring(command, changing, true).error, should_reject ? 31 : 0);
  }
}

TEST(UlsConformance, U30_FormFollowsFieldCount) {
  const auto form = [](std::string_view mnemonic, std::size_t fields) {
    return request_form(*find_command(mnemonic), fields);
  };
  EXPECT_EQ(form("MM", 0).form, RequestForm::get);
  EXPECT_EQ(form("MM", 1).form, RequestForm::set);
  EXPECT_EQ(form("MM", 2).verdict.error, 1);
  EXPECT_EQ(form("GO", 0).form, RequestForm::action);
  EXPECT_EQ(form("GO", 1).verdict.error, 1);
  EXPECT_EQ(form("SU", 1).verdict.error, 1);
  EXPECT_EQ(form("ID", 1).verdict.error, 1);
  EXPECT_EQ(form("BM", 1).verdict.error, 1);
  EXPECT_EQ(form("PT", 0).verdict.error, 1);
  EXPECT_EQ(form("BR", 1).form, RequestForm::get);
  EXPECT_EQ(form("BR", 2).form, RequestForm::set);
  EXPECT_EQ(form("BR", 0).verdict.error, 1);
  EXPECT_EQ(form("PF", 3).form, RequestForm::set);
  EXPECT_EQ(form("PF", 4).verdict.error, 1);
  EXPECT_EQ(form("PO", 2).form, RequestForm::set);
  EXPECT_EQ(form("PO", 3).verdict.error, 1);
  // Integers are digits with an optional sign: a decimal is not an integer, a negative is out of range.
  EXPECT_EQ(set("MM", "1.0").error, 1);
  EXPECT_EQ(set("AW", "-5").error, 35);
  EXPECT_EQ(set("MM", "-1").error, 85);
  EXPECT_EQ(set("MM", "+1").error, 1);
}

}  // namespace
}  // namespace rangekit::uls
