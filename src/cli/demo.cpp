// `rangekit demo`: the first thing a newcomer runs. Starts a ULS and an LS5
// emulator (child processes of this binary) on pseudo-terminals with moving
// targets, streams both live through the same drivers a real sensor uses,
// captures both into one SQLite file and says how to replay it.
#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "cli/commands.hpp"
#include "cli/demo.hpp"
#include "cli/demo_scenes.hpp"
#include "cli/host_sources.hpp"
#include "cli/sim_process.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/record/merge.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/uls/driver.hpp"

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

int run_live_demo(const DemoOptions& options) {
  std::string pattern = (fs::temp_directory_path() / "rangekit-demo-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    return fail("cannot create a directory in " + fs::temp_directory_path().string());
  const fs::path dir = pattern;
  if (auto status = demo_scenes::write_file(dir / "uls-scene.toml", demo_scenes::uls); !status)
    return fail(status.error().message);
  if (auto status = demo_scenes::write_file(dir / "ls5-scene.toml", demo_scenes::ls5); !status)
    return fail(status.error().message);

  const std::string uls_port = (dir / "uls").string();
  const std::string uls_config_port = (dir / "uls-config").string();
  const std::string ls5_port = (dir / "ls5").string();
  fmt::print("rangekit demo: starting two emulated sensors on pseudo-terminals in {}\n", dir.string());
  const std::string uls_control = (dir / "uls.control").string();
  const std::string ls5_control = (dir / "ls5.control").string();
  auto uls_sim = SimProcess::start({"uls", "--port", uls_port, "--config-port", uls_config_port, "--scene",
                                    (dir / "uls-scene.toml").string(), "--control", uls_control},
                                   (dir / "uls-sim.log").string(), std::chrono::seconds(15));
  if (!uls_sim) return fail(uls_sim.error().message);
  auto ls5_sim = SimProcess::start(
      {"ls5", "--port", ls5_port, "--scene", (dir / "ls5-scene.toml").string(), "--control", ls5_control},
      (dir / "ls5-sim.log").string(), std::chrono::seconds(15));
  if (!ls5_sim) return fail(ls5_sim.error().message);
  fmt::print("  {}\n  {}\n", uls_sim->ready_line(), ls5_sim->ready_line());

  // ULS: its measurement output is the configuration port (§2 Output Setup).
  // 5000 pulses/s over 1024 pulses per reading is about 4.9 readings a second,
  // each with its pulse width (§8 DM).
  {
    auto link = open_serial(uls_config_port, 115200);
    if (!link) return fail(link.error().describe());
    uls::Driver setup(std::move(link).value());
    auto version = setup.version();
    if (!version) return fail("ULS: " + version.error().describe());
    if (auto status = setup.set_prf(5000); !status) return fail("ULS PF: " + status.error().describe());
    if (auto status = setup.set_display_mode(uls::DisplayMode::range_and_intensity); !status) {
      return fail("ULS DM: " + status.error().describe());
    }
    fmt::print("  ULS  {}  averaging, PRF 5000, 1024 pulses per reading, range and pulse width\n", *version);
  }
  auto uls_source = start_uls_source(UlsSourceOptions{uls_config_port, 115200, std::nullopt, "uls-config"});
  if (!uls_source) return fail(uls_source.error().describe());
  // LS5: T = n × t (§8.4), 20 × 10 ms (factory period): 5 readings a second.
  auto ls5_source = start_ls5_source(Ls5SourceOptions{ls5_port, 115200, 0x01, std::uint8_t{20}});
  if (!ls5_source) return fail(ls5_source.error().describe());
  fmt::print("  LS5  address 01  streaming every 20th measurement (§8.4)\n");

  remove_capture(options.capture);
  fmt::print("Streaming both for {:.0f} s (Ctrl-C stops early) and capturing to {}\n\n", options.seconds,
             options.capture);
  std::fflush(stdout);

  std::vector<SampleSourcePtr> sources;
  sources.push_back(std::move(uls_source).value());
  sources.push_back(std::move(ls5_source).value());
  auto merged = record::merge_sources(std::move(sources));
  StreamOptions stream_options;
  stream_options.format = options.format;
  stream_options.duration_s = options.seconds;
  stream_options.capture = options.capture;
  record::StreamStats stats;
  const int code = run_stream_as(*merged, stream_options, "demo", &stats);
  merged.reset();  // stops both streams before the drivers and emulators go

  if (code != exit_ok && code != exit_interrupted) return code;
  // U86: the host stops what it started (ULS ST, LS5 SB); the emulators confirm it.
  fmt::print("\nLeft as found: ULS {}, LS5 {}\n", emulator_state(uls_control, "measuring", "not measuring"),
             emulator_state(ls5_control, "streaming", "not streaming"));
  fmt::print("Captured {} samples from both sensors into {}\n", stats.samples, options.capture);
  const std::string binary = this_binary();
  std::error_code ignored;
  fmt::print("Replay it:  {} replay {} --format jsonl\n", binary, fs::absolute(options.capture, ignored).string());
  fmt::print("Emulators:  {} sim uls --help, {} sim ls5 --help\n", binary, binary);
  uls_sim->stop();
  ls5_sim->stop();
  fs::remove_all(dir, ignored);
  return code;
}

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  static DemoOptions options;
  auto* command = app.add_subcommand("demo", "Run the demonstration: two emulated sensors streamed live and captured");
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
