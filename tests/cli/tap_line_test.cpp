// `rangekit tap` as a piece of wire: every byte value, both ways at once, arrives unchanged at
// the other end, whatever the family, baud and byte format; and the family is told from the
// traffic of each family's own host commands against its emulator.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <random>
#include <thread>

#include "ls5_driver/cli_process.hpp"
#include "poll_until.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/record/pcapng.hpp"
#include "rangekit/sim/pty.hpp"

namespace {

using namespace rangekit;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;
using rangekit::test::path_appears;

struct TappedLine {
  std::string family;  // "auto": none given
  std::uint32_t baud;
  std::string byte_format;
};
void PrintTo(const TappedLine& line, std::ostream* out) {
  *out << line.family << " " << line.baud << " " << line.byte_format;
}

std::string noise_bytes(std::size_t count, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::string bytes(count, '\0');
  for (char& c : bytes) c = static_cast<char>(byte(generator));
  return bytes;
}

// Reads `from` until `expected.size()` bytes came or nothing came for 5 s.
std::string read_count(Transport& from, std::size_t expected) {
  std::string heard;
  std::array<std::uint8_t, 4096> buffer{};
  while (heard.size() < expected) {
    auto read = from.read_some(buffer, std::chrono::seconds(5));
    if (!read || *read == 0) break;
    heard.append(reinterpret_cast<const char*>(buffer.data()), *read);
  }
  return heard;
}

class TapLine : public ::testing::TestWithParam<TappedLine> {};

TEST_P(TapLine, PassesEveryByteUnchangedBothWaysAtOnce) {
  const TappedLine& line = GetParam();
  TempDir dir;
  const std::string sensor_path = (dir.path / "sensor").string();
  const std::string host_path = (dir.path / "host").string();
  auto sensor = PseudoTerminal::open(sensor_path);
  ASSERT_TRUE(sensor.ok()) << sensor.error().message;
  std::vector<std::string> arguments{"tap",
                                     "--host-pty",
                                     host_path,
                                     "--sensor",
                                     sensor_path,
                                     "--baud",
                                     std::to_string(line.baud),
                                     "--byte-format",
                                     line.byte_format,
                                     "--format",
                                     "jsonl",
                                     "--out",
                                     (dir.path / "line.pcapng").string()};
  if (line.family != "auto") arguments.insert(arguments.end(), {"--family", line.family});
  Child tap(arguments);
  std::thread reader([&] {  // the jsonl records, read so the tap never blocks on its stdout
    while (!tap.read_line().empty()) {
    }
  });
  ASSERT_TRUE(path_appears(host_path));
  const Parity parity = line.byte_format[1] == 'N'   ? Parity::none
                        : line.byte_format[1] == 'E' ? Parity::even
                                                     : Parity::odd;
  auto host = open_serial_link(host_path, SerialSettings{line.baud, parity, line.byte_format[2] - '0'});
  ASSERT_TRUE(host.ok()) << host.error().message;

  // Every byte value, in 64 KiB of noise each way, written at once from both ends; without a
  // family, 1.5 MiB, past what the tap holds back while it listens for one.
  const std::size_t size = line.family == "auto" ? 1536 * 1024 : 64 * 1024;
  const std::string from_host = noise_bytes(size, 1);
  const std::string from_sensor = noise_bytes(size, 2);
  std::thread host_writer([&] { EXPECT_TRUE((*host)->write_all(as_bytes(from_host)).ok()); });
  std::thread sensor_writer([&] { EXPECT_TRUE((*sensor)->write_all(as_bytes(from_sensor)).ok()); });
  std::string at_host;
  std::thread host_reader([&] { at_host = read_count(**host, from_sensor.size()); });
  const std::string at_sensor = read_count(**sensor, from_host.size());
  host_writer.join();
  sensor_writer.join();
  host_reader.join();
  EXPECT_EQ(at_sensor.size(), from_host.size());
  EXPECT_TRUE(at_sensor == from_host) << "the sensor heard other bytes than the host sent";
  EXPECT_EQ(at_host.size(), from_sensor.size());
  EXPECT_TRUE(at_host == from_sensor) << "the host heard other bytes than the sensor sent";

  tap.terminate();
  reader.join();
  EXPECT_EQ(tap.wait(), 130);
  // The recording holds the same bytes, each side's in order.
  auto recording = record::read_serial_pcapng(ls5_driver_test::read_file(dir.path / "line.pcapng"));
  ASSERT_TRUE(recording.ok()) << recording.error().message;
  std::string recorded_host;
  std::string recorded_sensor;
  for (const auto& chunk : recording->chunks)
    (chunk.sender == record::Sender::host ? recorded_host : recorded_sensor) += chunk.bytes;
  EXPECT_TRUE(recorded_host == from_host);
  EXPECT_TRUE(recorded_sensor == from_sensor);
  const std::string line_comment = "line " + std::to_string(line.baud) + " " + line.byte_format;
  EXPECT_NE(std::find(recording->comments.begin(), recording->comments.end(), line_comment), recording->comments.end());
}

INSTANTIATE_TEST_SUITE_P(FamiliesAndLines, TapLine,
                         ::testing::Values(TappedLine{"uls", 9600, "8N1"}, TappedLine{"ls5", 115200, "8E1"},
                                           TappedLine{"auto", 19200, "8O2"}, TappedLine{"uls", 38400, "8N2"},
                                           TappedLine{"ls5", 9600, "8O1"}),
                         [](const auto& test) {
                           return test.param.family + "_" + std::to_string(test.param.baud) + "_" +
                                  test.param.byte_format;
                         });

struct TappedSession {
  std::string family;
  std::vector<std::string> host_command;  // --port PATH goes after the first two words
  std::string raw;                        // a frame the tap must decode ...
  std::string decoded;                    // ... to these words
};
void PrintTo(const TappedSession& session, std::ostream* out) { *out << session.family; }

class TapFamily : public ::testing::TestWithParam<TappedSession> {};

// No family given: the tap names it from the first frames and decodes the session from the start.
TEST_P(TapFamily, IsToldFromTheTraffic) {
  const TappedSession& conversation = GetParam();
  TempDir dir;
  const std::string sensor = (dir.path / "sensor").string();
  const std::string host = (dir.path / "host").string();
  const std::string recording = (dir.path / "session.pcapng").string();
  Child sim({"sim", conversation.family, "--port", sensor});
  ASSERT_NE(sim.read_line().find("ready"), std::string::npos);
  Child tap(
      {"tap", "--host-pty", host, "--sensor", sensor, "--baud", "115200", "--format", "jsonl", "--out", recording});
  ASSERT_TRUE(path_appears(host));
  std::vector<std::string> command = conversation.host_command;
  command.insert(command.begin() + 2, {"--port", host, "--baud", "115200"});
  const auto run = ls5_driver_test::run_cli(dir.path, command);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  tap.terminate();
  bool found = false;
  bool first_is_host = false;
  int records = 0;
  for (std::string line = tap.read_line(); !line.empty(); line = tap.read_line()) {
    const auto record = nlohmann::json::parse(line, nullptr, false);
    ASSERT_TRUE(record.is_object()) << line;
    if (records++ == 0) first_is_host = record["direction"] == "host";
    if (record["raw"] == conversation.raw) {
      found = true;
      EXPECT_EQ(record["decoded"], conversation.decoded) << line;
    }
  }
  EXPECT_EQ(tap.wait(), 130);
  EXPECT_TRUE(found) << "no " << conversation.raw << " among " << records << " records";
  EXPECT_TRUE(first_is_host) << "the frames before the family was known were not reported";
  auto file = record::read_serial_pcapng(ls5_driver_test::read_file(recording));
  ASSERT_TRUE(file.ok()) << file.error().message;
  EXPECT_EQ(file->comments.front(), "family " + conversation.family);
}

INSTANTIATE_TEST_SUITE_P(
    BothFamilies, TapFamily,
    ::testing::Values(TappedSession{"uls", {"uls", "get"}, "$MU,1", "Measurement Units = 1 (metres)"},
                      TappedSession{
                          "ls5", {"ls5", "get"}, "#01R01", "sensor 01: Read the parameter 01 (Network address)"}),
    [](const auto& test) { return test.param.family; });

// The documents' own example exchanges, typed in: the host's request and the sensor's reply
// through the tap, each decoded with the document's words and the reply paired with it.
struct DocumentExchange {
  std::string family;
  std::string request;  // without its CR
  std::string reply;
  std::string request_decoded;
  std::string reply_decoded;
};
void PrintTo(const DocumentExchange& exchange, std::ostream* out) { *out << exchange.request; }

class TapDecode : public ::testing::TestWithParam<DocumentExchange> {};

TEST_P(TapDecode, ReadsTheDocumentsExamplesAsTheyDo) {
  const DocumentExchange& exchange = GetParam();
  TempDir dir;
  const std::string sensor_path = (dir.path / "sensor").string();
  const std::string host_path = (dir.path / "host").string();
  auto sensor = PseudoTerminal::open(sensor_path);
  ASSERT_TRUE(sensor.ok()) << sensor.error().message;
  Child tap(
      {"tap", "--family", exchange.family, "--host-pty", host_path, "--sensor", sensor_path, "--format", "jsonl"});
  ASSERT_TRUE(path_appears(host_path));
  auto host = open_serial_link(host_path, SerialSettings{9600, Parity::none, 1});
  ASSERT_TRUE(host.ok()) << host.error().message;
  ASSERT_TRUE((*host)->write_all(as_bytes(exchange.request + "\r")).ok());
  EXPECT_EQ(read_count(**sensor, exchange.request.size() + 1), exchange.request + "\r");
  ASSERT_TRUE((*sensor)->write_all(as_bytes(exchange.reply + "\r")).ok());
  EXPECT_EQ(read_count(**host, exchange.reply.size() + 1), exchange.reply + "\r");
  tap.terminate();
  std::vector<nlohmann::json> records;
  for (std::string line = tap.read_line(); !line.empty(); line = tap.read_line()) {
    records.push_back(nlohmann::json::parse(line, nullptr, false));
  }
  EXPECT_EQ(tap.wait(), 130);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0]["direction"], "host");
  EXPECT_EQ(records[0]["raw"], exchange.request);
  EXPECT_EQ(records[0]["decoded"], exchange.request_decoded);
  EXPECT_EQ(records[1]["direction"], "sensor");
  EXPECT_EQ(records[1]["raw"], exchange.reply);
  EXPECT_EQ(records[1]["decoded"], exchange.reply_decoded);
  EXPECT_TRUE(records[1].contains("rtt_ms")) << records[1].dump();
}

INSTANTIATE_TEST_SUITE_P(
    Documents, TapDecode,
    ::testing::Values(
        // ULS §8: "ex. $MM  Get Measurement Mode", "ex. $MM,1" the reply; $ER,n and §10's error 4.
        DocumentExchange{"uls", "$MM", "$MM,1", "get Measurement Mode", "Measurement Mode = 1 (averaging)"},
        DocumentExchange{"uls", "$BM", "$ER,4", "get Measurement",
                         "error 4: Lock Not Found (display \"Target Not Found\")"},
        // LS5 §9.4: "Turn on the sensor with address 01" and "Set the median filtering for the
        // sensor with address 02", each request with its response.
        DocumentExchange{"ls5", "#01ON", "!01ON", "sensor 01: Turn on the sensor",
                         "sensor 01: done: Turn on the sensor"},
        DocumentExchange{"ls5", "#02W0B01", "!02W0B01",
                         "sensor 02: Write the parameter: parameter 0B (Data pre-filtering type) = 01 (median "
                         "filtering)",
                         "sensor 02: done: Write the parameter: parameter 0B (Data pre-filtering type) = 01 (median "
                         "filtering)"}),
    [](const auto& test) { return test.param.family + "_" + std::to_string(test.index); });

}  // namespace
