// Control-socket lines with invalid UTF-8 ({"cmd":"\xff"}) or out-of-range values
// (bit_error_rate 2, drop_rate -1, position_mm -1e308) get one {"error": ...} line naming
// the problem, and the emulator keeps serving (docs/reliability.md).
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/sim/control_socket.hpp"

namespace {

using ls5_driver_test::Child;

using cli_test::contains;

struct BadLine {
  std::string line;
  std::string expected;  // part of the error text, typed from what the value means
};

// Sends every line raw, expects an error naming the problem for each, then checks that the
// emulator still answers `status` and `outputs` and ends cleanly on `shutdown`.
void expect_errors_and_still_serving(Child& sim, const std::string& control, const std::vector<BadLine>& lines) {
  ASSERT_TRUE(contains(sim.read_line(), "ready:"));
  auto client = rangekit::ControlClient::connect(control);
  ASSERT_TRUE(client) << client.error().message;
  for (const auto& bad : lines) {
    auto reply = client->request_line(bad.line);
    ASSERT_TRUE(reply) << bad.line << ": " << reply.error().message;
    ASSERT_TRUE(reply->contains("error")) << bad.line << " got " << reply->dump();
    EXPECT_TRUE(contains((*reply)["error"].get<std::string>(), bad.expected))
        << bad.line << " got " << reply->dump() << ", expected a mention of " << bad.expected;
    EXPECT_FALSE(reply->contains("ok")) << bad.line;
  }
  auto status = client->request({{"cmd", "status"}});
  ASSERT_TRUE(status) << status.error().message;
  EXPECT_EQ(status->value("ok", false), true) << status->dump();
  auto outputs = client->request({{"cmd", "outputs"}});
  ASSERT_TRUE(outputs) << outputs.error().message;
  EXPECT_FALSE(outputs->contains("error")) << outputs->dump();
  auto shutdown = client->request({{"cmd", "shutdown"}});
  ASSERT_TRUE(shutdown) << shutdown.error().message;
  EXPECT_EQ(sim.wait(), 0);
}

// Lines every emulator's runtime answers the same way (docs/emulator-*.md, "Control"):
// `noise` "flipping each bit ... with that probability, and dropped bytes": both are
// probabilities, 0 .. 1.
std::vector<BadLine> runtime_lines() {
  return {
      {"{\"cmd\":\"\xff\"}", "not valid UTF-8"},
      {"{\"cmd\":\"outputs\",\"note\":\"caf\xc3\"}", "not valid UTF-8"},
      {"{\"cmd\":\"\xc0\xaf\"}", "\\xc0\\xaf"},
      {"{\"cmd\":\"noise\",\"bit_error_rate\":2}", "'bit_error_rate' must be a number within 0 .. 1, not 2"},
      {"{\"cmd\":\"noise\",\"drop_rate\":-1}", "'drop_rate' must be a number within 0 .. 1, not -1"},
      {"{\"cmd\":\"noise\",\"bit_error_rate\":\"often\"}", "'bit_error_rate' must be a number within 0 .. 1"},
      {"{\"cmd\":\"noise\",\"drop_rate\":1e999}", "drop_rate"},
      {"{\"cmd\":\"advance\",\"seconds\":-1}", "'seconds' must be a number within 0 .. 86400"},
      {"{\"cmd\":\"advance\",\"seconds\":1e300}", "'seconds' must be a number within 0 .. 86400"},
      {"{\"cmd\":7}", "bad request"},
      {"[1,2]", "not a JSON object"},
  };
}

TEST(ControlSocket, UlsAnswersInvalidUtf8AndOutOfRangeValuesWithErrorsAndKeepsRunning) {
  const ls5_driver_test::TempDir temp;
  const std::string control = (temp.path / "uls.control").string();
  Child sim({"sim", "uls", "--port", (temp.path / "uls").string(), "--control", control});
  auto lines = runtime_lines();
  // docs/emulator-uls.md, scene: distance_m of a target, 0 .. 5000 m as in the scene file.
  lines.push_back({"{\"cmd\":\"move_target\",\"distance_m\":-1e308}",
                   "'distance_m' must be a number within 0 .. 5000, not -1e+308"});
  lines.push_back(
      {"{\"cmd\":\"move_target\",\"distance_m\":5000.5}", "'distance_m' must be a number within 0 .. 5000"});
  lines.push_back({"{\"cmd\":\"move_target\"}", "needs 'distance_m'"});
  lines.push_back({"{\"cmd\":\"move_target\",\"target\":-1,\"distance_m\":3}", "'target' must be the index"});
  lines.push_back({"{\"cmd\":\"move_target\",\"target\":0.5,\"distance_m\":3}", "'target' must be the index"});
  lines.push_back({"{\"cmd\":\"min_pulse_width\",\"ns\":-5}", "ER 87"});
  lines.push_back({"{\"cmd\":\"move_target\",\"device\":\"\xff\",\"distance_m\":3}", "not valid UTF-8"});
  expect_errors_and_still_serving(sim, control, lines);
}

TEST(ControlSocket, Ls5AnswersInvalidUtf8AndOutOfRangeValuesWithErrorsAndKeepsRunning) {
  const ls5_driver_test::TempDir temp;
  const std::string control = (temp.path / "ls5.control").string();
  Child sim({"sim", "ls5", "--port", (temp.path / "ls5").string(), "--control", control});
  auto lines = runtime_lines();
  // docs/emulator-ls5.md, scene: position_mm and speed_mm_per_s within +-1e9 as in the scene
  // file; "reflectivity = 1  # 0 (black) .. 1 (white)".
  lines.push_back({"{\"cmd\":\"move_target\",\"position_mm\":-1e308}",
                   "'position_mm' must be a number within -1e+09 .. 1e+09, not -1e+308"});
  lines.push_back({"{\"cmd\":\"move_target\",\"position_mm\":30,\"speed_mm_per_s\":1e300}", "'speed_mm_per_s'"});
  lines.push_back({"{\"cmd\":\"move_target\",\"position_mm\":30,\"reflectivity\":2}",
                   "'reflectivity' must be a number within 0 .. 1, not 2"});
  lines.push_back({"{\"cmd\":\"move_target\",\"position_mm\":\"far\"}", "'position_mm' must be a number"});
  lines.push_back({"{\"cmd\":\"move_target\"}", "needs 'position_mm'"});
  lines.push_back({"{\"cmd\":\"sync\",\"level\":\"\xe2\x82\"}", "not valid UTF-8"});
  lines.push_back({"{\"cmd\":\"set_scene\",\"toml\":\"[target]\\nreflectivity = 7\"}", "reflectivity"});
  expect_errors_and_still_serving(sim, control, lines);
}

}  // namespace

namespace control_socket_limits {

using namespace std::chrono_literals;

nlohmann::json answer_ok(const nlohmann::json& /*request*/) { return {{"ok", true}}; }

// Anyone who may connect can steer the emulator, so only its owner may, whatever umask the
// process was started with.
TEST(ControlSocketLimits, TheSocketIsOwnerOnlyWhateverTheUmask) {
  const ls5_driver_test::TempDir temp;
  const std::string path = (temp.path / "open.control").string();
  const mode_t previous = ::umask(0);
  auto control = rangekit::ControlSocket::listen(path);
  ::umask(previous);
  ASSERT_TRUE(control) << control.error().message;
  struct stat info {};
  ASSERT_EQ(::lstat(path.c_str(), &info), 0);
  EXPECT_TRUE(S_ISSOCK(info.st_mode));
  EXPECT_EQ(info.st_mode & 07777, 0600u) << "mode " << std::oct << (info.st_mode & 07777);
  EXPECT_TRUE(rangekit::ControlClient::connect(path).ok());
}

// A peer that sends megabytes without a newline is refused once it passes 64 KiB; the
// emulator never holds more than that (and the byte that passes it) for it.
TEST(ControlSocketLimits, APeerSendingMegabytesWithoutANewlineIsCutOffAt64KiB) {
  const ls5_driver_test::TempDir temp;
  const std::string path = (temp.path / "flood.control").string();
  auto control = rangekit::ControlSocket::listen(path);
  ASSERT_TRUE(control) << control.error().message;
  const int peer = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  ASSERT_GE(peer, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  ASSERT_EQ(::connect(peer, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  const std::size_t total = std::size_t{10} << 20;
  const std::string chunk(std::size_t{64} << 10, 'x');
  std::size_t sent = 0;
  bool cut_off = false;
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (!cut_off && sent < total && std::chrono::steady_clock::now() < deadline) {
    // As much as the kernel takes now, then one turn of the emulator's loop.
    while (sent < total) {
      const ssize_t n = ::send(peer, chunk.data(), std::min(chunk.size(), total - sent), MSG_NOSIGNAL);
      if (n > 0) {
        sent += static_cast<std::size_t>(n);
        continue;
      }
      cut_off = n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR;  // EPIPE: closed on us
      break;
    }
    (*control)->service(answer_ok);
  }
  EXPECT_TRUE(cut_off) << "the connection took " << sent << " bytes without a newline";
  EXPECT_LE((*control)->peak_pending(), (std::size_t{64} << 10) + 1);
  // The refusal says why, before the close.
  std::string reply;
  while (reply.find('\n') == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    pollfd readable{peer, POLLIN, 0};
    if (::poll(&readable, 1, 1000) <= 0) continue;
    std::array<char, 512> buffer{};
    const ssize_t n = ::recv(peer, buffer.data(), buffer.size(), 0);
    if (n <= 0) break;
    reply.append(buffer.data(), static_cast<std::size_t>(n));
  }
  ::close(peer);
  EXPECT_NE(reply.find("request line longer than 64 KiB"), std::string::npos) << reply;
}

}  // namespace control_socket_limits
