// ULS §10, typed from the document. Texts are as printed; the OCR turned the
// ☒ mark into stray characters, kept only on 10, 23, 28 and 47 (U22).
#include "rangekit/uls/errors.hpp"

#include <algorithm>
#include <array>
#include <string>

namespace rangekit::uls {
namespace {

using G = ErrorGroup;

constexpr std::array<ErrorInfo, 85> errors{{
    {1, "General Command Interface Error", "Invalid Command", false, G::general},
    {4, "Lock Not Found", "Target Not Found", false, G::general},
    {5, "Average Weight Not Filled", "Average Not Filled", false, G::general},
    {6, "Measurement Start Error", "Measurement Start Error", false, G::general},
    {7, "Measurement Read Error", "Measurement Read Error", false, G::general},
    {8, "Measurement Stop Error", "Measurement Stop Error", false, G::general},
    {9, "PTFCAL Bad Status Error", "ER 009", false, G::general},
    {10, "ADC Error", "ER 010", true, G::general},
    {11, "Memory Write Error", "Memory Write Error", false, G::general},
    {12, "Averaging Error", "Averaging Error", false, G::general},
    {13, "General ASIC Error", "General ASIC Error", false, G::general},
    {14, "General Laser CPU Error", "General Laser CPU Error", false, G::general},
    {15, "User Settings Checksum Error", "User Settings Checksum Error", false, G::general},
    {16, "Bad Password Error", "Bad Password", false, G::general},
    {17, "No Measuring Data Available Error", "ER 017", false, G::general},
    {18, "Measurement Data Not OK Error", "ER 018", false, G::general},
    {19, "Cannot Write To Flash Error", "ER 019", false, G::general},
    {20, "Cannot Reset Asic Done Bit", "ER 020", false, G::general},
    {21, "ASIC BIST Test Timeout", "ER 021", false, G::general},
    {22, "ASIC Failed RAM Test", "ER 022", false, G::general},
    {23, "Laser CPU Failed RAM Test", "Laser CPU Failed RAM Test", true, G::general},
    {24, "Serial EEPROM Write Protect Jumper in Place", "ER 024", false, G::general},
    {25, "RX Buffer Overrun", "RX Buffer Overrun", false, G::general},
    {26, "Incorrect ADC Address Error", "ER 026", false, G::general},
    {27, "General Ring Frequency Cal Error", "ER 027", false, G::general},
    {28, "HV CLK Frequency Too High Error", "ER 028", true, G::general},
    {29, "Unsafe DAC Setting Error", "ER 029", false, G::general},
    {30, "PTFCAL Zero Events", "ER 030", false, G::general},
    {31, "No Serial While Measuring Error", "Instrument Is Already Measuring", false, G::general},
    {32, "Invalid Rep Rate", "Invalid PRF", false, G::general},
    {33, "Invalid Input Base", "ER 033", false, G::general},
    {34, "Invalid Baud Rate", "Invalid Baud Rate", false, G::general},
    {35, "Invalid Average Weight", "Invalid Average Weight", false, G::general},
    {36, "Invalid Noise Zone Error", "ER 036", false, G::general},
    {37, "Factory Defaults Checksum Error", "Bad Factory Defaults Checksum", false, G::general},
    {38, "Code Checksum Error", "Bad Code Checksum", false, G::general},
    {39, "Too Many EEPROM Writes Error", "ER 039", false, G::general},
    {40, "Broken EEPROM Error", "ER 040", false, G::general},
    {41, "Unverifiable Image Checksum Error", "ER 041", false, G::general},
    {42, "Bad User Settings Defaults Checksum", "Bad User Settings Defaults Checksum", false, G::general},
    {43, "Bad User Settings Checksum", "Bad User Settings Checksum", false, G::general},
    {44, "Bad Factory Defaults Checksum", "Bad Factory Defaults Checksum", false, G::general},
    {45, "No Factory Defaults Present Error", "No Factory Defaults", false, G::general},
    {46, "EEPROM Not Finished Yet Error", "ER 046", false, G::general},
    {47, "SPI Busy", "ER 047", true, G::general},
    {48, "Serial Checksum Error", "ER 048", false, G::general},
    {49, "Pulse Per Output Must Be Greater Than Average Weight", "PPO Must Be Greater Than Average Weight", false,
     G::general},
    {50, "Dropped Pulse", "ER 050", false, G::interrupt},
    {51, "Measurement Bad Status", "Measurement Bad Status", false, G::interrupt},
    {52, "NEG PW", "ER 052", false, G::interrupt},
    {53, "RFC Fail Bad Status Error", "ER 053", false, G::interrupt},
    {54, "PW Too Long Or Too Short", "ER 054", false, G::interrupt},
    {55, "RFC Fail Zero Event Count Error", "ER 055", false, G::interrupt},
    {56, "Insufficient Cal Data for CALC Error", "ER 056", false, G::interrupt},
    {57, "RXC Fail Bad Status Error", "ER 057", false, G::interrupt},
    {58, "RXC Fail Insufficient Events Error", "ER 058", false, G::interrupt},
    {59, "BAD PTF Table Checksum", "BAD PTF Table Checksum", false, G::table_checksum},
    {60, "Bad Power Table1 Checksum", "ER 060", false, G::table_checksum},
    {61, "Bad Power Table2 Checksum", "ER 061", false, G::table_checksum},
    {62, "Bad Power Table3 Checksum", "ER 062", false, G::table_checksum},
    {63, "Bad Power Table4 Checksum", "ER 063", false, G::table_checksum},
    {64, "Bad Power Table5 Checksum", "ER 064", false, G::table_checksum},
    {65, "Bad Power Table6 Checksum", "ER 065", false, G::table_checksum},
    {66, "Bad Power Table7 Checksum", "ER 066", false, G::table_checksum},
    {67, "Bad Power Table8 Checksum", "ER 067", false, G::table_checksum},
    {68, "Gate Open Cal Invalid", "ER 068", false, G::table_checksum},
    {69, "Gate Close Cal Invalid", "ER 069", false, G::table_checksum},
    {70, "Incorrect Bootloader Password", "ER 070", false, G::table_checksum},
    {71, "Invalid Power Table Selection", "ER 071", false, G::table_checksum},
    {72, "Invalid HV1 Table Selection", "ER 072", false, G::table_checksum},
    {73, "HV1 Not Set", "HV1 Not Set", false, G::table_checksum},
    {74, "Invalid HV1 Sense Table Selection", "ER 074", false, G::table_checksum},
    {75, "Unsafe HV1 Sense Setting", "ER 075", false, G::table_checksum},
    {76, "HV1 Sense Not Set", "ER 076", false, G::table_checksum},
    {77, "HV1 Sense Error", "ER 077", false, G::table_checksum},
    {78, "Invalid Command for Measurement Mode", "ER 078", false, G::table_checksum},
    {79, "Instrument Not Ready", "Instrument Not Ready", false, G::table_checksum},
    {80, "Gate Open Fail Bad Status", "ER 080", false, G::table_checksum},
    {81, "Gate Close Fail Bad Status", "ER 081", false, G::table_checksum},
    {82, "Unit Address Not Assigned", "Unit Address Not Assigned", false, G::rs485},
    {83, "Invalid MA420 Range", "Invalid Current Loop Range", false, G::current_loop},
    {84, "Invalid Port", "Invalid Port", false, G::current_loop},
    {85, "Invalid Measurement Mode", "Invalid Measurement Mode", false, G::current_loop},
    {86, "Instrument Not Measuring", "Instrument Not Measuring", false, G::current_loop},
    {87, "Invalid Minimum Pulse Width", "Invalid Minimum Pulse Width", false, G::current_loop},
}};

}  // namespace

std::span<const ErrorInfo> error_table() noexcept { return errors; }

const ErrorInfo* find_error(int number) noexcept {
  const auto* found = std::lower_bound(errors.begin(), errors.end(), number,
                                       [](const ErrorInfo& row, int n) { return row.number < n; });
  return (found != errors.end() && found->number == number) ? found : nullptr;
}

std::string error_text(int number) {
  const ErrorInfo* info = find_error(number);
  if (info == nullptr) return "not in the ULS's error table";
  std::string text(info->explanation);
  if (info->display != info->explanation) text += " (display: " + std::string(info->display) + ")";
  return text;
}

std::string_view error_group_name(ErrorGroup group) noexcept {
  switch (group) {
    case ErrorGroup::general:
      return "general";
    case ErrorGroup::interrupt:
      return "interrupt";
    case ErrorGroup::table_checksum:
      return "table checksums";
    case ErrorGroup::rs485:
      return "RS485";
    case ErrorGroup::current_loop:
      return "4-20";
  }
  return "unknown";
}

}  // namespace rangekit::uls
