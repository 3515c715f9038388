#include "cli/capture_replay.hpp"

#include <fmt/core.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/sim_process.hpp"
#include "cli/stop_signals.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::cli {
namespace {

constexpr const char* command = "rangekit sim replay";

struct CapturedSensor {
  std::string family;
  std::string source;  // "port" or "port address N"
  CapturedReadings readings;
  std::set<std::string> others;  // the capture's other sensors, "family source"
  std::size_t skipped = 0;       // samples without a reading (an error, no target) or out of order
};

std::string sensor_name(const Sample& sample) {
  return sample.address < 0 ? sample.source.str() : fmt::format("{} address {}", sample.source.str(), sample.address);
}

Result<CapturedSensor> read_captured_sensor(const CaptureReplayOptions& options) {
  CapturedSensor sensor;
  sensor.family = options.family;
  sensor.source = options.source;
  std::optional<std::chrono::system_clock::time_point> first;
  const auto on_sample = [&](const Sample& sample) {
    const std::string name = sensor_name(sample);
    if (sensor.family.empty()) sensor.family = sample.device;
    if (sensor.source.empty() && sample.device == sensor.family) sensor.source = name;
    if (sample.device != sensor.family || (name != sensor.source && sample.source.view() != sensor.source)) {
      sensor.others.insert(sample.device + " " + name);
      return;
    }
    const auto reading = reading_of(sample);
    if (!reading || (sensor.readings.channel != nullptr && reading->channel != sensor.readings.channel)) {
      ++sensor.skipped;
      return;
    }
    sensor.readings.channel = reading->channel;
    if (!first) first = sample.time;
    const double time_s = std::chrono::duration<double>(sample.time - *first).count();
    if (!sensor.readings.points.empty() && time_s <= sensor.readings.points.back().time_s) {
      ++sensor.skipped;  // a path needs rising times
      return;
    }
    sensor.readings.points.push_back(PathPoint{time_s, reading->value});
  };
  if (auto read = record::for_each_in_capture(options.file, options.family, on_sample, [](StreamEvent&&) {}); !read) {
    return read.error();
  }
  if (sensor.readings.points.empty()) {
    return make_error(Errc::invalid_frame, sensor.family.empty()
                                               ? std::string("the capture holds no samples")
                                               : fmt::format("the capture holds no readings of {} {}", sensor.family,
                                                             sensor.source.empty() ? "" : sensor.source));
  }
  return sensor;
}

}  // namespace

bool is_capture_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::string head(16, '\0');
  return file.read(head.data(), static_cast<std::streamsize>(head.size())) &&
         head == std::string("SQLite format 3\0", 16);
}

int run_capture_replay(const CaptureReplayOptions& options) {
  auto sensor = read_captured_sensor(options);
  if (!sensor) {
    fmt::print(stderr, "{}: {}: {}\n", command, options.file, sensor.error().message);
    return sensor.error().code == Errc::io ? exit_io : exit_bad_input;
  }
  const CliFamily* family = find_cli_family(sensor->family);
  if (family == nullptr || family->capture_scene == nullptr) {
    fmt::print(stderr, "{}: {}: no emulator of '{}' in this build follows captured readings\n", command, options.file,
               sensor->family);
    return exit_usage;
  }
  auto scene = family->capture_scene(sensor->readings);
  if (!scene) {
    fmt::print(stderr, "{}: {}: {}\n", command, options.file, scene.error().message);
    return exit_bad_input;
  }
  std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-replay-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    fmt::print(stderr, "{}: cannot make a folder for the emulator's scene\n", command);
    return exit_io;
  }
  const std::filesystem::path dir = pattern;
  const auto scene_path = dir / "scene.toml";
  std::ofstream(scene_path) << scene->scene;
  std::vector<std::string> arguments{std::string(family->name), "--port", options.port, "--scene", scene_path.string()};
  arguments.insert(arguments.end(), scene->sim_arguments.begin(), scene->sim_arguments.end());
  StopSignals signals;
  int code = exit_interrupted;
  {
    auto sim = SimProcess::start(arguments, (dir / "sim.log").string(), std::chrono::seconds(60));
    if (!sim) {
      fmt::print(stderr, "{}: the {} emulator did not start: {}\n", command, family->label, sim.error().message);
      code = exit_io;
    } else {
      const auto& points = sensor->readings.points;
      fmt::print("rangekit sim replay ready: {} ({} {}: {} readings of {} over {:.1f} s, followed by its emulator)\n",
                 options.port, family->label, sensor->source, points.size(), sensor->readings.channel->key,
                 points.back().time_s);
      std::fflush(stdout);
      if (!sensor->others.empty()) {
        fmt::print(stderr, "{}: the capture also holds {} other sensor(s), {}...: --family and --source pick one\n",
                   command, sensor->others.size(), *sensor->others.begin());
      }
      if (sensor->skipped > 0) {
        fmt::print(stderr, "{}: {} samples without a reading (an error, no target) are left out\n", command,
                   sensor->skipped);
      }
      // The emulator runs on; this process only waits for Ctrl-C to stop it and tidy up.
      while (!signals.stopped()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  return code;
}

}  // namespace rangekit::cli
