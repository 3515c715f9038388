// `rangekit tap` between a host program and the ULS emulator, both on this machine: every
// byte forwarded both ways (the host's `get` succeeds through it), each reply paired with its
// request and a round trip, bytes that are no frame shown as hex with the reason without
// stopping the line, and the session recorded as pcapng.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <thread>

#include "ls5_driver/cli_process.hpp"
#include "poll_until.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/record/pcapng.hpp"

namespace {

using namespace rangekit;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;
using rangekit::test::path_appears;

struct Tapped {
  TempDir dir;
  std::string sensor = (dir.path / "uls").string();
  std::string host = (dir.path / "host").string();
  std::string recording = (dir.path / "session.pcapng").string();
  Child sim{{"sim", "uls", "--port", sensor}};
  std::unique_ptr<Child> tap;
  // `before` runs on the sensor's own port, before the tap opens it.
  explicit Tapped(const std::vector<std::string>& before = {}) {
    EXPECT_NE(sim.read_line().find("ready"), std::string::npos);
    if (!before.empty()) {
      std::vector<std::string> command = before;
      command.insert(command.begin() + 2, {"--port", sensor});
      EXPECT_EQ(ls5_driver_test::run_cli(dir.path, command).exit_code, 0);
    }
    tap =
        std::make_unique<Child>(std::vector<std::string>{"tap", "uls", "--host-pty", host, "--sensor", sensor, "--baud",
                                                         "115200", "--format", "jsonl", "--out", recording});
    EXPECT_TRUE(path_appears(host));
  }
  // Ends the tap (as Ctrl-C would) and gives its records.
  std::vector<nlohmann::json> finish(int& exit_code) {
    tap->terminate();
    std::vector<nlohmann::json> records;
    for (std::string line = tap->read_line(); !line.empty(); line = tap->read_line()) {
      records.push_back(nlohmann::json::parse(line, nullptr, false));
    }
    exit_code = tap->wait();
    return records;
  }
};

TEST(Tap, ForwardsBothWaysPairsEachReplyAndRecordsTheSession) {
  Tapped line;
  const auto get = ls5_driver_test::run_cli(line.dir.path, {"uls", "get", "--port", line.host});
  ASSERT_EQ(get.exit_code, 0) << get.err;
  EXPECT_NE(get.out.find("version=ULS emulator"), std::string::npos) << get.out;
  int exit_code = -1;
  const auto records = line.finish(exit_code);
  EXPECT_EQ(exit_code, 130);  // ended by a signal, files closed
  int requests = 0;
  int replies = 0;
  bool units = false;
  for (const auto& record : records) {
    ASSERT_TRUE(record.is_object());
    if (record["direction"] == "host") ++requests;
    if (record["direction"] == "sensor" && record.contains("rtt_ms")) {
      ++replies;
      EXPECT_GE(record["rtt_ms"].get<double>(), 0.0) << record.dump();
    }
    if (record["raw"] == "$MU,1") {
      units = true;
      EXPECT_EQ(record["decoded"], "Measurement Units = 1 (metres)");
    }
  }
  EXPECT_GT(requests, 10);
  EXPECT_EQ(replies, requests);  // `get` asks one thing at a time and hears each answer
  EXPECT_TRUE(units);

  auto recording = record::read_serial_pcapng(ls5_driver_test::read_file(line.recording));
  ASSERT_TRUE(recording.ok()) << recording.error().message;
  EXPECT_NE(std::find(recording->comments.begin(), recording->comments.end(), "family uls"), recording->comments.end());
  EXPECT_NE(std::find(recording->comments.begin(), recording->comments.end(), "line 115200 8N1"),
            recording->comments.end());
  std::string from_host;
  std::string from_sensor;
  for (const auto& chunk : recording->chunks)
    (chunk.sender == record::Sender::host ? from_host : from_sensor) += chunk.bytes;
  EXPECT_NE(from_host.find("$MU\r"), std::string::npos);
  EXPECT_NE(from_sensor.find("$MU,1"), std::string::npos);
}

TEST(Tap, BytesThatAreNoFrameAreShownAndTheLineGoesOn) {
  Tapped line;
  auto port = open_serial_link(line.host, SerialSettings{115200, Parity::none, 1});
  ASSERT_TRUE(port.ok()) << port.error().message;
  ASSERT_TRUE((*port)->write_all(as_bytes("xyz\r$MU\r")).ok());
  std::string heard;
  std::array<std::uint8_t, 256> buffer{};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (heard.find("$MU,1") == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    auto read = (*port)->read_some(buffer, std::chrono::milliseconds(200));
    if (read && *read > 0) heard.append(reinterpret_cast<const char*>(buffer.data()), *read);
  }
  EXPECT_NE(heard.find("$MU,1"), std::string::npos) << "the sensor's reply never came through: " << heard;
  int exit_code = -1;
  const auto records = line.finish(exit_code);
  bool shown = false;
  for (const auto& record : records) {
    if (record.contains("rejected")) {
      shown = true;
      EXPECT_EQ(record["direction"], "host");
      EXPECT_EQ(record["hex"], "78 79 7a 0d") << record.dump();  // the CR ends the garbage
    }
  }
  EXPECT_TRUE(shown) << "the garbage was not reported";
}

// The recording played back as the sensor: the same host program, through the same requests,
// prints the same settings as it did against the emulator.
TEST(SimReplay, TheRecordedSensorAnswersTheHostAsTheEmulatorDid) {
  Tapped line;
  const auto live = ls5_driver_test::run_cli(line.dir.path, {"uls", "get", "--port", line.host});
  ASSERT_EQ(live.exit_code, 0) << live.err;
  int exit_code = -1;
  (void)line.finish(exit_code);
  line.sim.terminate();
  (void)line.sim.wait();
  const std::string port = (line.dir.path / "replayed").string();
  Child replay{{"sim", "replay", line.recording, "--port", port}};
  const std::string ready = replay.read_line();
  ASSERT_NE(ready.find("rangekit sim replay ready: " + port), std::string::npos) << ready;
  const auto replayed = ls5_driver_test::run_cli(line.dir.path, {"uls", "get", "--port", port});
  EXPECT_EQ(replayed.exit_code, 0) << replayed.err;
  EXPECT_EQ(replayed.out, live.out);
  // A request the recording never heard gets no answer, and a note on the replay's stderr.
  const auto unknown = ls5_driver_test::run_cli(line.dir.path, {"uls", "set", "--port", port, "units=feet"});
  EXPECT_NE(unknown.exit_code, 0);
}

// The recording compared with a fresh emulator: a session against the emulator itself agrees;
// one where the unit had another setting shows where, exchange by exchange.
TEST(TapCompare, AgreesWithTheEmulatorItRecordedAndNamesASettingThatDiffers) {
  Tapped line;
  ASSERT_EQ(ls5_driver_test::run_cli(line.dir.path, {"uls", "get", "--port", line.host}).exit_code, 0);
  int exit_code = -1;
  (void)line.finish(exit_code);
  const auto same = ls5_driver_test::run_cli(line.dir.path, {"tap", "compare", line.recording});
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("0 of "), std::string::npos) << same.out;

  Tapped other({"uls", "set", "units=feet"});  // the unit was set up before the session
  ASSERT_EQ(ls5_driver_test::run_cli(other.dir.path, {"uls", "get", "--port", other.host}).exit_code, 0);
  (void)other.finish(exit_code);
  const auto differ = ls5_driver_test::run_cli(other.dir.path, {"tap", "compare", other.recording});
  EXPECT_EQ(differ.exit_code, 3) << differ.out << differ.err;
  // The units read back: feet on the recorded unit, metres on a fresh emulator.
  EXPECT_NE(differ.out.find("$MU: frame 1: recorded $MU,0"), std::string::npos) << differ.out;
}

}  // namespace
