// `rangekit ls5 stream` (serial ST/SB records, §8.13) and `rangekit ls5 udp`
// (Ethernet packets, §10.1): both hand a SampleSource to the shared run_stream.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/stream_runner.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/ls5/udp_receiver.hpp"

namespace rangekit::cli {
namespace {

struct SerialStreamCommand {
  Ls5Connection connection;
  StreamOptions stream;
  int thinning = 0;  // 0: leave parameter 08 as it is
  int reconnect_ms = 500;
  int silence_ms = 3000;
  bool no_reconnect = false;
};

struct UdpStreamCommand {
  std::string listen;
  std::string address;
  StreamOptions stream;
};

// How long without a record means the sensor is gone: --silence-ms, but at least three
// output periods T = n × t (§8.4), and never with sync-input triggering, where records
// come only with the edges (§8.13).
Result<std::chrono::milliseconds> silence_timeout(ls5::Driver& driver, const SerialStreamCommand& command) {
  auto triggering = driver.get("triggering");
  if (!triggering) return triggering.error();
  if (triggering->text == "sync-input")
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::hours(24 * 365));
  auto period = driver.get("period-ms");
  if (!period) return period.error();
  int thinning = command.thinning;
  if (thinning == 0) {
    auto current = driver.get("thinning");
    if (!current) return current.error();
    thinning = std::stoi(current->text);
  }
  const double output_period_ms = std::stod(period->text) * thinning;
  const auto three_periods = std::chrono::milliseconds(static_cast<std::int64_t>(3 * output_period_ms) + 1);
  return std::max(std::chrono::milliseconds(command.silence_ms), three_periods);
}

// No silent waits (docs/cli.md): when nothing has arrived after `patience`, says
// once on stderr what to check. Everything else is passed through unchanged.
class HintWhenSilent final : public SampleSource {
 public:
  HintWhenSilent(SampleSource& inner, std::chrono::milliseconds patience, std::string hint)
      : inner_(inner), patience_(patience), hint_(std::move(hint)), started_(std::chrono::steady_clock::now()) {}
  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override {
    auto item = inner_.next(timeout);
    heard(item.has_value());
    return item;
  }
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) override {
    const bool got = inner_.next_batch(batch, timeout);
    heard(got);
    return got;
  }
  [[nodiscard]] bool finished() const override { return inner_.finished(); }
  void stop() override { inner_.stop(); }
  [[nodiscard]] std::uint64_t lost() const override { return inner_.lost(); }

 private:
  void heard(bool got) {
    if (got) {
      heard_ = true;
    } else if (!heard_ && !hinted_ && std::chrono::steady_clock::now() - started_ >= patience_) {
      hinted_ = true;
      fmt::print(stderr, "{}\n", hint_);
      std::fflush(stderr);
    }
  }

  SampleSource& inner_;
  std::chrono::milliseconds patience_;
  std::string hint_;
  std::chrono::steady_clock::time_point started_;
  bool heard_ = false;
  bool hinted_ = false;
};

}  // namespace

void add_ls5_stream_commands(CLI::App& ls5, int& exit_code) {
  auto serial = std::make_shared<SerialStreamCommand>();
  auto* stream = ls5.add_subcommand(
      "stream", "start the result stream (ST) and print or capture the records; reconnects when the link returns");
  add_ls5_connection_options(*stream, serial->connection);
  add_stream_options(*stream, serial->stream);
  stream->add_option("--thinning", serial->thinning, "write thinning n (parameter 08: every n-th result) first")
      ->check(CLI::Range(1, 255));
  stream->add_option("--reconnect-ms", serial->reconnect_ms, "retry interval after the link went away (default 500)")
      ->check(CLI::Range(10, 60000));
  stream
      ->add_option("--silence-ms", serial->silence_ms,
                   "no record for this long (at least 3 output periods; never with sync triggering) counts as a lost "
                   "sensor; default 3000")
      ->check(CLI::Range(100, 3600000));
  stream->add_flag("--no-reconnect", serial->no_reconnect, "end the stream when the port goes away");
  stream->callback([&exit_code, serial] {
    auto driver = open_ls5_driver(serial->connection, false, !serial->no_reconnect);
    if (!driver) {
      exit_code = report_ls5_failure("stream", driver.error(), serial->connection);
      return;
    }
    ls5::Driver::StreamOptions options;
    if (serial->thinning > 0) options.thinning = static_cast<std::uint8_t>(serial->thinning);
    options.reconnect_interval = std::chrono::milliseconds(serial->reconnect_ms);
    auto silence = silence_timeout(**driver, *serial);
    if (!silence) {
      exit_code = report_ls5_failure("stream", silence.error(), serial->connection);
      return;
    }
    options.silence_timeout = *silence;
    auto source = (*driver)->start_stream(options);
    if (!source) {
      exit_code = report_ls5_failure("stream", source.error(), serial->connection);
      return;
    }
    exit_code = run_stream(**source, serial->stream);
    (*source)->stop();  // SB, so the sensor is quiet for the next program
  });

  auto udp = std::make_shared<UdpStreamCommand>();
  auto* udp_command =
      ls5.add_subcommand("udp", "receive the Ethernet stream (UDP packets), checksum and counter checked");
  udp_command->add_option("--udp-listen", udp->listen, "HOST:PORT to bind (the sensor's destination, default port 603)")
      ->required();
  udp_command->add_option("--address", udp->address, "network address to put in the samples (packets carry none)");
  add_stream_options(*udp_command, udp->stream);
  udp_command->callback([&exit_code, udp] {
    auto endpoint = parse_endpoint(udp->listen);
    if (!endpoint) {
      fmt::print(stderr, "rangekit ls5 udp: --udp-listen {}: {}\n", udp->listen, endpoint.error().message);
      exit_code = exit_usage;
      return;
    }
    ls5::UdpReceiverOptions options;
    if (!udp->address.empty()) {
      auto address = parse_ls5_address(udp->address);
      if (!address) {
        fmt::print(stderr, "rangekit ls5 udp: {}\n", address.error().message);
        exit_code = exit_usage;
        return;
      }
      options.address = *address;
    }
    auto receiver = ls5::UdpReceiver::start(*endpoint, options);
    if (!receiver) {
      fmt::print(stderr, "rangekit ls5 udp: cannot listen on {}: {}\n", udp->listen, receiver.error().message);
      exit_code = exit_io;
      return;
    }
    HintWhenSilent watched(**receiver, std::chrono::seconds(3),
                           fmt::format("rangekit ls5 udp: nothing has arrived on {} for 3 s: is the sensor's "
                                       "destination IP address this host and its destination port {} (its Ethernet "
                                       "settings), and is it streaming?",
                                       endpoint->to_string(), endpoint->port));
    exit_code = run_stream_as(watched, udp->stream, "ls5 udp");
    (*receiver)->stop();
    const auto counters = (*receiver)->counters();
    if (counters.bad_packets > 0 || counters.lost_packets > 0 || counters.duplicates > 0 ||
        counters.suspect_records > 0) {
      fmt::print(stderr,
                 "rangekit ls5 udp: {} packets, {} bad (checksum/size), {} lost ({} records), {} duplicates "
                 "dropped, {} suspect records (state word or code out of the format)\n",
                 counters.packets, counters.bad_packets, counters.lost_packets, counters.lost_records,
                 counters.duplicates, counters.suspect_records);
    }
  });
}

}  // namespace rangekit::cli
