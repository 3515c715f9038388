// `rangekit replay FILE`: a SQLite capture streamed back through the same loop
// and formats as a live stream, at the recorded pace or at full speed.
#include <fmt/core.h>
#include <unistd.h>

#include <memory>
#include <string>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/record/replay.hpp"

namespace rangekit::cli {
namespace {

struct ReplayArguments {
  std::string file;
  bool full_speed = false;
  bool pace = false;
  double speed = 1.0;
  bool speed_given = false;
  std::string device;
  StreamOptions stream;
};

// The pace factor: as asked, else as recorded for someone watching a terminal, else full
// speed: a pipe or a file is an export, which should not take the recording's length.
double pace_of(const ReplayArguments& arguments) {
  if (arguments.full_speed) return 0.0;
  if (arguments.speed_given) return arguments.speed;
  if (arguments.pace) return 1.0;
  const bool watched = arguments.stream.out.empty() && ::isatty(STDOUT_FILENO) == 1;
  return watched ? 1.0 : 0.0;
}

int run_replay(const ReplayArguments& arguments) {
  record::ReplayOptions options;
  options.speed = pace_of(arguments);
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
  auto* full_speed = command->add_flag("--full-speed", arguments->full_speed,
                                       "no waiting between samples (the default when the output is a file or a pipe)");
  auto* pace =
      command->add_flag("--pace", arguments->pace, "the recorded pace (the default when the output is a terminal)");
  auto* speed = command->add_option("--speed", arguments->speed, "pace factor: 1 = as recorded, 2 = twice as fast");
  speed->check(pace_factor())->excludes(full_speed)->excludes(pace);
  pace->excludes(full_speed);
  command->add_option("--device", arguments->device, "only samples of this family (events always)")
      ->check(CLI::IsMember(cli_family_name_list()));
  add_stream_options(*command, arguments->stream, false);
  command->callback([arguments, speed, &exit_code] {
    arguments->speed_given = speed->count() > 0;
    exit_code = run_replay(*arguments);
  });
}

}  // namespace rangekit::cli
