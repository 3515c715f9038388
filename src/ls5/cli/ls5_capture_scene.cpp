// The LS5 emulator following a capture's readings (`sim replay CAPTURE`): the target on the
// captured distances, without noise of its own, in a model whose range holds them all. The
// capture keeps no lower boundary, and a distance counts from it (formula 8.1), so any serves.
#include <fmt/core.h>

#include <algorithm>
#include <array>

#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/emulator/firmware.hpp"

namespace rangekit::cli {
namespace {

const double lower_boundary_mm = ls5::emulator::FirmwareConfig{}.lower_boundary_mm;  // the emulator's own
// The emulator's default range first (the demos'), then the catalogue's.
const std::array ranges_mm{
    ls5::emulator::FirmwareConfig{}.range_mm, 2.0, 5.0, 10.0, 25.0, 50.0, 100.0, 250.0, 500.0, 1000.0, 2000.0};

}  // namespace

Result<CaptureScene> ls5_capture_scene(const CapturedReadings& readings) {
  if (readings.channel == nullptr || readings.channel->key != "distance_mm") {
    return make_error(Errc::unsupported, fmt::format("the LS5 emulator follows distances, not {}",
                                                     readings.channel ? readings.channel->key : "these readings"));
  }
  double farthest = 0;
  for (const PathPoint& point : readings.points) farthest = std::max(farthest, point.position);
  const auto range = std::find_if(ranges_mm.begin(), ranges_mm.end(), [&](double r) { return r >= farthest; });
  if (range == ranges_mm.end()) {
    return make_error(Errc::out_of_range, fmt::format("a reading of {} mm is beyond every LS5 range", farthest));
  }
  std::string path;
  for (const PathPoint& point : readings.points) {
    path += fmt::format("{}[{:.6f}, {}]", path.empty() ? "" : ", ", point.time_s, lower_boundary_mm + point.position);
  }
  return CaptureScene{{"--model", fmt::format("{}/{}", lower_boundary_mm, *range)},
                      "[target]\nnoise_mm = 0\nrepeat = true\npath = [" + path + "]\n"};
}

}  // namespace rangekit::cli
