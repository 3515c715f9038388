// The ULS's options of `rangekit decode`: how the BM lines were configured, since a
// measurement line reads differently in each mode (§8).
#include <map>
#include <memory>

#include "rangekit/uls/frame.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

struct UlsDecodeOptions {
  std::string mode = "averaging";
  std::string display = "range";
  std::string units = "m";
  bool time_between_events = false;
};

uls::MeasurementContext context_of(const UlsDecodeOptions& options) {
  static const std::map<std::string, uls::Mode> modes{
      {"averaging", uls::Mode::averaging}, {"binning", uls::Mode::binning}, {"look-down", uls::Mode::look_down}};
  static const std::map<std::string, uls::DisplayMode> displays{{"range", uls::DisplayMode::range},
                                                                {"both", uls::DisplayMode::range_and_intensity},
                                                                {"intensity", uls::DisplayMode::intensity}};
  return uls::MeasurementContext{modes.at(options.mode), displays.at(options.display),
                                 options.units == "ft" ? uls::Units::feet : uls::Units::metres,
                                 options.time_between_events};
}

}  // namespace

DecoderFactory add_uls_decode_options(CLI::App& decode) {
  auto options = std::make_shared<UlsDecodeOptions>();
  decode.add_option("--mode", options->mode, "ULS measurement mode the BM lines come from")
      ->check(CLI::IsMember({"averaging", "binning", "look-down"}));
  decode.add_option("--display", options->display, "ULS averaging display mode (DM)")
      ->check(CLI::IsMember({"range", "both", "intensity"}));
  decode.add_option("--units", options->units, "ULS units (MU)")->check(CLI::IsMember({"m", "ft"}));
  decode.add_flag("--time-between-events", options->time_between_events, "ULS look down with TB on");
  return [options](Direction sender) {
    const auto context = context_of(*options);
    return FrameDecoder{&uls::scan_frame,
                        [sender, context](Bytes frame) { return describe_uls_frame(frame, sender, context); }};
  };
}

}  // namespace rangekit::cli
