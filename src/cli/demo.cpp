// `rangekit demo`: the first thing a newcomer runs. Starts an emulator of each
// family (child processes of this binary) on pseudo-terminals with moving
// targets, streams them live through the same drivers a real sensor uses,
// captures them into one SQLite file and says how to replay it.
#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <vector>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/demo.hpp"
#include "cli/demo_scenes.hpp"
#include "cli/sim_process.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/record/merge.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace rangekit::cli {
namespace {

namespace fs = std::filesystem;

struct DemoOptions {
  double seconds = 20;
  std::string capture = "rangekit-demo.sqlite";
  std::string format = "text";
  bool walkthrough = false;
};

// Removes an earlier demo capture (and its WAL files) so each run starts fresh.
void remove_capture(const std::string& path) {
  std::error_code ignored;
  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(path + suffix, ignored);
}

// "not measuring" when the emulator's `outputs` has `field` false, "still <field>" when true.
std::string emulator_state(const std::string& control, const char* field, const char* idle_text) {
  auto client = ControlClient::connect(control);
  if (!client) return "state unknown (" + client.error().message + ")";
  auto reply = client->request({{"cmd", "outputs"}});
  if (!reply) return "state unknown (" + reply.error().message + ")";
  const nlohmann::json& device = reply->contains("devices") ? (*reply)["devices"][0] : *reply;
  const auto value = device.find(field);
  if (value == device.end() || !value->is_boolean()) return "state unknown";
  return value->get<bool>() ? std::string("still ") + field : std::string(idle_text);
}

// This binary as the user can type it from where they stand: its absolute path, since
// "build/rangekit" only exists from the source folder.
std::string this_binary() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? std::string("rangekit") : self.string();
}

int fail(const std::string& message) {
  fmt::print(stderr, "rangekit demo: {}\n", message);
  return exit_io;
}

// A family's emulator in the demo and its files.
struct DemoSensor {
  const CliFamily* family;
  DemoFiles files;
  std::optional<SimProcess> emulator;
};

int run_live_demo(const DemoOptions& options) {
  std::string pattern = (fs::temp_directory_path() / "rangekit-demo-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    return fail("cannot create a directory in " + fs::temp_directory_path().string());
  const fs::path dir = pattern;
  std::vector<DemoSensor> sensors;
  for (const CliFamily* family : cli_families()) {
    if (family->demo.start_source == nullptr) continue;
    const std::string name(family->name);
    sensors.push_back(DemoSensor{family,
                                 DemoFiles{dir, (dir / name).string(), (dir / (name + "-scene.toml")).string(),
                                           (dir / (name + ".control")).string()},
                                 std::nullopt});
  }
  for (const DemoSensor& sensor : sensors) {
    if (auto status = demo_scenes::write_file(sensor.files.scene, sensor.family->demo.scene); !status)
      return fail(status.error().message);
  }

  fmt::print("rangekit demo: starting {} emulated sensors on pseudo-terminals in {}\n", count_in_words(sensors.size()),
             dir.string());
  for (DemoSensor& sensor : sensors) {
    auto emulator =
        SimProcess::start(sensor.family->demo.sim_arguments(sensor.files),
                          (dir / (std::string(sensor.family->name) + "-sim.log")).string(), std::chrono::seconds(15));
    if (!emulator) return fail(emulator.error().message);
    sensor.emulator = std::move(emulator).value();
  }
  for (const DemoSensor& sensor : sensors) fmt::print("  {}\n", sensor.emulator->ready_line());

  std::vector<SampleSourcePtr> sources;
  for (const DemoSensor& sensor : sensors) {
    auto source = sensor.family->demo.start_source(sensor.files);
    if (!source) return fail(source.error().message);
    sources.push_back(std::move(source).value());
  }

  remove_capture(options.capture);
  fmt::print("Streaming {} for {:.0f} s (Ctrl-C stops early) and capturing to {}\n\n", both_or_all(), options.seconds,
             options.capture);
  std::fflush(stdout);

  auto merged = record::merge_sources(std::move(sources));
  StreamOptions stream_options;
  stream_options.format = options.format;
  stream_options.duration_s = options.seconds;
  stream_options.capture = options.capture;
  record::StreamStats stats;
  const int code = run_stream_as(*merged, stream_options, "demo", &stats);
  merged.reset();  // stops every stream before the drivers and emulators go

  if (code != exit_ok && code != exit_interrupted) return code;
  // U86: the host stops what it started; the emulators confirm it.
  std::string left;
  for (const DemoSensor& sensor : sensors) {
    left += fmt::format(
        "{}{} {}", left.empty() ? "" : ", ", sensor.family->label,
        emulator_state(sensor.files.control, sensor.family->demo.busy_output, sensor.family->demo.idle_text));
  }
  fmt::print("\nLeft as found: {}\n", left);
  fmt::print("Captured {} samples from {} sensors into {}\n", stats.samples, both_or_all(), options.capture);
  const std::string binary = this_binary();
  std::error_code ignored;
  fmt::print("Replay it:  {} replay {} --format jsonl\n", binary, fs::absolute(options.capture, ignored).string());
  std::string emulators;
  for (const DemoSensor& sensor : sensors) {
    emulators += fmt::format("{}{} sim {} --help", emulators.empty() ? "" : ", ", binary, sensor.family->name);
  }
  fmt::print("Emulators:  {}\n", emulators);
  for (DemoSensor& sensor : sensors) sensor.emulator->stop();
  fs::remove_all(dir, ignored);
  return code;
}

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  static DemoOptions options;
  auto* command = app.add_subcommand("demo", "Run the demonstration: " + count_in_words(cli_families().size()) +
                                                 " emulated sensors streamed live and captured");
  command->add_option("--seconds", options.seconds, "how long to stream")
      ->check(duration_seconds())
      ->capture_default_str();
  command->add_option("--capture", options.capture, "SQLite file for the capture")->capture_default_str();
  command->add_option("--format", options.format, "jsonl, csv or text")->capture_default_str();
  command->add_flag("--walkthrough", options.walkthrough,
                    "decode a sample session typed from the documents instead (no emulators)");
  command->callback([&exit_code] { exit_code = options.walkthrough ? run_walkthrough() : run_live_demo(options); });
}

}  // namespace rangekit::cli
