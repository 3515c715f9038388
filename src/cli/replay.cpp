// `rangekit replay FILE`: a SQLite capture streamed back through the same loop
// and formats as a live stream, at the recorded pace or at full speed.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::cli {
namespace {

struct ReplayArguments {
  std::string file;
  bool full_speed = false;
  double speed = 1.0;
  std::string device;
  StreamOptions stream;
};

int run_replay(const ReplayArguments& arguments) {
  record::ReplayOptions options;
  options.speed = arguments.full_speed ? 0.0 : arguments.speed;
  options.device = arguments.device;
  auto source = record::open_replay(arguments.file, options);
  if (!source) {
    fmt::print(stderr, "rangekit replay: {}\n", source.error().message);
    return exit_io;
  }
  auto stream = arguments.stream;
  stream.link_lost_is_failure = false;
  stream.check_quality = false;  // the capture holds each sample's flag as it was recorded
  return run_stream_as(**source, stream, "replay");
}

}  // namespace

void add_replay_command(CLI::App& app, int& exit_code) {
  auto arguments = std::make_shared<ReplayArguments>();
  auto* command = app.add_subcommand("replay", "stream a SQLite capture back in the formats of `stream`");
  command->add_option("file", arguments->file, "capture file written with --capture")->required();
  auto* full_speed = command->add_flag("--full-speed", arguments->full_speed, "no waiting between samples");
  command->add_option("--speed", arguments->speed, "pace factor: 1 = as recorded (default), 2 = twice as fast")
      ->check(pace_factor())
      ->excludes(full_speed);
  command->add_option("--device", arguments->device, "only samples of this family (events always)")
      ->check(CLI::IsMember({"uls", "ls5"}));
  add_stream_options(*command, arguments->stream, false);
  command->callback([arguments, &exit_code] { exit_code = run_replay(*arguments); });
}

}  // namespace rangekit::cli
