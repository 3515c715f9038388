// The ULS emulator following a capture's readings (`sim replay CAPTURE`): one target on the
// captured distances, nothing else in the beam, so the nearest target is the captured one.
#include <fmt/core.h>

#include "rangekit/uls/emulator/scene.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {

Result<CaptureScene> uls_capture_scene(const CapturedReadings& readings) {
  if (readings.channel == nullptr || readings.channel->unit != Unit::metre) {
    return make_error(Errc::unsupported, fmt::format("the ULS emulator follows distances, not {}",
                                                     readings.channel ? readings.channel->key : "these readings"));
  }
  std::string path;
  for (const PathPoint& point : readings.points) {
    if (point.position < 0 || point.position > uls::emulator::max_scene_distance_m) {
      return make_error(Errc::out_of_range,
                        fmt::format("a reading of {} m at {:.6f} s is beyond the emulator's {} m", point.position,
                                    point.time_s, uls::emulator::max_scene_distance_m));
    }
    path += fmt::format("{}[{:.6f}, {}]", path.empty() ? "" : ", ", point.time_s, point.position);
  }
  return CaptureScene{{}, "dust = 0\n\n[[targets]]\nname = \"captured\"\nrepeat = true\npath = [" + path + "]\n"};
}

}  // namespace rangekit::cli
