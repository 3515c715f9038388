// The ULS's options of `rangekit decode`: how the BM lines were configured, since a
// measurement line reads differently in each mode (§8).
#include <charconv>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/frame.hpp"
#include "rangekit/uls/reply.hpp"
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

// How each unit's measurement lines read, from the options and then from what the traffic
// says: a set (host) or a value reply (sensor) of MM, DM, MU or TB changes it for that unit,
// so a tap or a decoded log reads a BM line as the unit was configured to send it.
class LearnedContexts {
 public:
  explicit LearnedContexts(const uls::MeasurementContext& given) : given_(given) {}
  const uls::MeasurementContext& of(const uls::FrameView& frame) {
    const auto found = units_.find(key(frame));
    return found == units_.end() ? given_ : found->second;
  }
  void learn(const uls::FrameView& frame) {
    if (frame.kind != uls::FrameKind::message || frame.field_count != 1) return;
    std::uint32_t code = 0;
    const std::string_view field = frame.fields()[0];
    if (std::from_chars(field.data(), field.data() + field.size(), code).ec != std::errc()) return;
    uls::MeasurementContext& context = units_.try_emplace(key(frame), given_).first->second;
    if (frame.is("MM")) context.mode = static_cast<uls::Mode>(code);
    if (frame.is("DM")) context.display = static_cast<uls::DisplayMode>(code);
    if (frame.is("MU")) context.units = static_cast<uls::Units>(code);
    if (frame.is("TB")) context.time_between_events = code != 0;
  }

 private:
  static int key(const uls::FrameView& frame) { return frame.address.addressed ? frame.address.byte : -1; }
  uls::MeasurementContext given_;
  std::map<int, uls::MeasurementContext> units_;
};

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
  // Both sides' decoders share what the traffic taught, as a reply follows its request.
  auto learned = std::make_shared<std::optional<LearnedContexts>>();
  return [options, learned](Direction sender) {
    if (!*learned) learned->emplace(context_of(*options));
    return FrameDecoder{&uls::scan_frame,
                        [sender, learned](Bytes frame) {
                          const auto view = uls::parse_frame(frame);
                          if (!view) return describe_uls_frame(frame, sender, {});
                          (*learned)->learn(*view);
                          return describe_uls_frame(frame, sender, (*learned)->of(*view));
                        },
                        [sender](Bytes frame) {
                          // A measurement line (BM, §9) or a time between events carries what the target made.
                          const auto view = uls::parse_frame(frame);
                          return sender == Direction::from_device && view.ok() &&
                                 (view->kind == uls::FrameKind::time_between_events || view->is("BM"));
                        },
                        [sender, units = context_of(*options).units](Bytes frame) {
                          const auto view = uls::parse_frame(frame);
                          if (!view) return false;
                          if (sender == Direction::to_device) return uls::find_command(view->mnemonic) != nullptr;
                          return view->kind == uls::FrameKind::time_between_events || view->is("BM") ||
                                 uls::decode_reply(*view, units).ok();
                        }};
  };
}

}  // namespace rangekit::cli
