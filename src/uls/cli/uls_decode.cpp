// The ULS's options of `rangekit decode`: how the BM lines were configured, since a
// measurement line reads differently in each mode (§8).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/frame.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

struct UlsDecodeOptions {
  std::string mode = "averaging";
  std::string display = "range";
  std::string units = "metres";
  bool time_between_events = false;
};

// A setting's values as `get` prints them ("look-down", "range-and-intensity") with their
// wire codes, so decode's options take the names a unit's settings are read and set by.
std::map<std::string, std::uint32_t> codes_by_name(uls::CommandId id) {
  std::map<std::string, std::uint32_t> codes;
  for (const uls::ValueName& entry : uls::command_info(id).value_names) codes[uls::value_key(entry.name)] = entry.value;
  return codes;
}

// The names in the document's order (the wire codes'), for the option's help.
std::vector<std::string> names_of(uls::CommandId id) {
  std::vector<std::string> names;
  for (const uls::ValueName& entry : uls::command_info(id).value_names) names.push_back(uls::value_key(entry.name));
  return names;
}

uls::MeasurementContext context_of(const UlsDecodeOptions& options) {
  static const auto modes = codes_by_name(uls::CommandId::mode);
  static const auto displays = codes_by_name(uls::CommandId::display);
  static const auto units = codes_by_name(uls::CommandId::units);
  return uls::MeasurementContext{static_cast<uls::Mode>(modes.at(options.mode)),
                                 static_cast<uls::DisplayMode>(displays.at(options.display)),
                                 static_cast<uls::Units>(units.at(options.units)), options.time_between_events};
}

}  // namespace

DecoderFactory add_uls_decode_options(CLI::App& decode) {
  auto options = std::make_shared<UlsDecodeOptions>();
  decode.add_option("--mode", options->mode, "ULS measurement mode the BM lines come from (MM)")
      ->check(CLI::IsMember(names_of(uls::CommandId::mode)));
  decode.add_option("--display", options->display, "ULS averaging display mode (DM)")
      ->check(CLI::IsMember(names_of(uls::CommandId::display)));
  decode.add_option("--units", options->units, "ULS measurement units (MU)")
      ->check(CLI::IsMember(names_of(uls::CommandId::units)));
  decode.add_flag("--time-between-events", options->time_between_events, "ULS look down with TB on");
  return [options](Direction sender) {
    const auto context = context_of(*options);
    return FrameDecoder{&uls::scan_frame,
                        [sender, context](Bytes frame) { return describe_uls_frame(frame, sender, context); },
                        [sender](Bytes frame) {
                          // A measurement line (BM, §9) or a time between events carries what the target made.
                          const auto view = uls::parse_frame(frame);
                          return sender == Direction::from_device && view.ok() &&
                                 (view->kind == uls::FrameKind::time_between_events || view->is("BM"));
                        }};
  };
}

}  // namespace rangekit::cli
