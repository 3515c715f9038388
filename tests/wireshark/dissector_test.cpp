// packaging/wireshark/rangekit.lua run by tshark: on frames typed from the two documents (each
// expected value read off the document, not from rangekit's codecs) and on the tap's recordings
// of a host talking to the emulators.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <thread>

#include "ls5_driver/cli_process.hpp"
#include "poll_until.hpp"
#include "rangekit/record/pcapng.hpp"

namespace {

using namespace rangekit;
using ls5_driver_test::Child;
using ls5_driver_test::TempDir;
using rangekit::test::path_appears;

std::string script() { return std::string(test::source_dir()) + "/packaging/wireshark/rangekit.lua"; }

struct Tshark {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::vector<std::string> lines() const {
    std::vector<std::string> result;
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) result.push_back(line);
    return result;
  }
};

// tshark -X lua_script:rangekit.lua -r FILE ARGS...; stdout and stderr through files in `dir`.
Tshark tshark(const std::filesystem::path& dir, const std::filesystem::path& file,
              const std::vector<std::string>& arguments) {
  std::vector<std::string> all{"tshark", "-X", "lua_script:" + script(), "-r", file.string()};
  all.insert(all.end(), arguments.begin(), arguments.end());
  const auto out_path = dir / "tshark.out";
  const auto err_path = dir / "tshark.err";
  const pid_t pid = test::fork_child();
  if (pid == 0) {
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execvp("tshark", argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  Tshark run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = ls5_driver_test::read_file(out_path);
  run.err = ls5_driver_test::read_file(err_path);
  return run;
}

// Fields, one line per packet, separated by '|'.
std::vector<std::string> fields(const std::filesystem::path& dir, const std::filesystem::path& file,
                                const std::vector<std::string>& names, const std::vector<std::string>& more = {}) {
  std::vector<std::string> arguments{"-T", "fields", "-E", "separator=|"};
  for (const auto& name : names) {
    arguments.push_back("-e");
    arguments.push_back(name);
  }
  arguments.insert(arguments.end(), more.begin(), more.end());
  const auto run = tshark(dir, file, arguments);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err.find("Lua"), std::string::npos) << run.err;  // the script loaded and ran clean
  return run.lines();
}

using Chunks = std::vector<std::pair<record::Sender, std::string>>;
constexpr auto host = record::Sender::host;
constexpr auto sensor = record::Sender::sensor;

// A recording as the tap writes one, each chunk one packet, 1 ms apart.
std::filesystem::path write_recording(const std::filesystem::path& dir, const std::string& family,
                                      const Chunks& chunks) {
  std::string file = record::pcapng_section_header({"family " + family, "line 115200 8N1"}, "rangekit test");
  file += record::pcapng_serial_interface("test");
  auto time = std::chrono::system_clock::time_point{} + std::chrono::seconds(1'796'000'000);
  for (const auto& [sender, bytes] : chunks) {
    time += std::chrono::milliseconds(1);
    file += record::pcapng_serial_packet({sender, time, bytes});
  }
  const auto path = dir / (family + ".pcapng");
  std::ofstream(path, std::ios::binary) << file;
  return path;
}

TEST(Wireshark, UlsFramesFromTheDocument) {
  TempDir dir;
  // §8 "#ZMM,1 Set ULS with address 0x5a ('Z') to Averaging Mode", its replies, a reply split
  // over two reads, §10's error 4, and a binning array of three targets (§8 "$BM,i,m,n,s",
  // §9 "xxxx.xxx = range (meters)") whose last line continues in the next read.
  const auto file = write_recording(dir.path, "uls",
                                    {{host, "#ZMM,1\r"},
                                     {sensor, "#ZOK\r"},
                                     {host, "#ZMM\r"},
                                     {sensor, "#ZM"},
                                     {sensor, "M,1\r"},
                                     {host, "$BM\r"},
                                     {sensor, "$ER,4\r"},
                                     {sensor, "$BM,0,3,12.345,130\r$BM,1,3,20.010,45\r$BM,2,3,1"},
                                     {sensor, "00.250,9\r"},
                                     {host, "$DD,1\r"},
                                     {sensor, "$ER,31\r"}});
  const std::vector<std::string> expected{
      "1|host|0x5a|MM|Measurement Mode|set|Averaging with Noise Filtering|",
      "2|sensor|0x5a|OK|set value accepted|set value accepted||",
      "3|host|0x5a|MM|Measurement Mode|get||",
      "4|||||||",  // the first part of a frame: nothing to read yet
      "5|sensor|0x5a|MM|Measurement Mode|reply|Averaging with Noise Filtering|4",
      "6|host||BM|Basic Measurement|get||",
      "7|sensor||ER|error encountered|error||",
      "8|sensor,sensor||BM,BM|Basic Measurement,Basic Measurement|measurement,measurement||",
      "9|sensor||BM|Basic Measurement|measurement||8",
      "10|host||DD|Dithering|set|Dither On|",
      "11|sensor||ER|error encountered|error||",
  };
  EXPECT_EQ(fields(dir.path, file,
                   {"frame.number", "uls.sender", "uls.address", "uls.mnemonic", "uls.command", "uls.kind",
                    "uls.value.meaning", "uls.starts_in"}),
            expected);

  // §10: Error Number, Explanation, ULS Interface Display.
  EXPECT_EQ(fields(dir.path, file, {"frame.number", "uls.error", "uls.error.explanation", "uls.error.display"},
                   {"-Y", "uls.error"}),
            (std::vector<std::string>{"7|4|Lock Not Found|Target Not Found",
                                      "11|31|No Serial While Measuring Error|Instrument Is Already Measuring"}));
  EXPECT_EQ(fields(dir.path, file, {"frame.number"}, {"-Y", "uls.error.reply"}),
            (std::vector<std::string>{"7", "11"}));  // expert info on each error reply

  // The binning array as targets: index, number of targets, range and its unit, strength.
  EXPECT_EQ(fields(dir.path, file,
                   {"frame.number", "uls.target.index", "uls.target.count", "uls.target.range", "uls.range.unit",
                    "uls.target.strength"},
                   {"-Y", "uls.target"}),
            (std::vector<std::string>{"8|0,1|3,3|12.345,20.01|m,m|130,45", "9|2|3|100.25|m|9"}));
  EXPECT_EQ(fields(dir.path, file, {"frame.number", "uls.partial"}, {"-Y", "uls.partial"}),
            (std::vector<std::string>{"4|235a4d", "8|24424d2c322c332c31"}));
  // On a second pass the first part names the packet the frame completes in.
  EXPECT_EQ(fields(dir.path, file, {"frame.number", "uls.reassembled_in"}, {"-2", "-Y", "uls.reassembled_in"}),
            (std::vector<std::string>{"4|5", "8|9"}));
}

TEST(Wireshark, UlsAveragingLinesAndTheirUnits) {
  TempDir dir;
  // §9: "$BM,xxxx.xxx,yyyyyyy": range in metres (3 decimals) or feet (2), pulse width in picoseconds.
  const auto file = write_recording(dir.path, "uls",
                                    {{sensor, "$BM,1234.567,18000\r"},
                                     {sensor, "$BM,4050.52\r"},
                                     {host, "$PF,2000,1000,3000\r"},
                                     {host, "$BR,0,115200\r"},
                                     {host, "xyz$MU\r"}});  // F2: noise before a frame
  EXPECT_EQ(fields(dir.path, file, {"uls.range", "uls.range.unit", "uls.pulse_width", "uls.value"}),
            (std::vector<std::string>{"1234.567|m|18000|", "4050.52|ft||", "|||2000,1000,3000", "|||0,115200", "|||"}));
  EXPECT_EQ(fields(dir.path, file, {"uls.skipped", "uls.mnemonic", "uls.command"}, {"-Y", "frame.number == 5"}),
            (std::vector<std::string>{"78797a|MU|Measurement Units"}));
  EXPECT_EQ(fields(dir.path, file, {"uls.value.meaning"}, {"-Y", "frame.number == 3 || frame.number == 4"}),
            (std::vector<std::string>{"2000 Hz,1000 Hz,3000 Hz", "Configuration port,115200 bauds"}));
}

TEST(Wireshark, Ls5FramesFromTheDocument) {
  TempDir dir;
  // §9.4's two sessions, a read of parameter 05 (table 9.2: 05 = 115200 baud), §9.2's
  // identification example, and the result stream (table 9.1 "![5 bytes of result]<cr>",
  // §8.9 65535 "no signal") with a record split over two reads.
  const auto file = write_recording(dir.path, "ls5",
                                    {{host, "#01ON\r"},
                                     {sensor, "!01ON\r"},
                                     {host, "#02W0B01\r"},
                                     {sensor, "!02W0B01\r"},
                                     {host, "#01R05\r"},
                                     {sensor, "!01R0505\r"},
                                     {host, "#01ID\r"},
                                     {sensor, "%01LS5.6.0   b8,1234d40,0010s/n0000157\r"},
                                     {host, "#01ST\r"},
                                     {sensor, "!25000\r!500"},
                                     {sensor, "00\r!65535\r"}});
  const std::vector<std::string> expected{
      "1|host|0x01|ON|Turn on the sensor|||||",
      "2|sensor|0x01|ON|Turn on the sensor|||||",
      "3|host|0x02|W|Write the parameter|0x0b|Data pre-filtering type|0x01|median filtering|",
      "4|sensor|0x02|W|Write the parameter|0x0b|Data pre-filtering type|0x01|median filtering|",
      "5|host|0x01|R|Read the parameter|0x05|Baud rate|||",
      "6|sensor|0x01|R|Read the parameter|0x05|Baud rate|0x05|115200 baud|",
      "7|host|0x01|ID|Identification|||||",
      "8|sensor|0x01|ID|Identification|||||",
      "9|host|0x01|ST|Start the result stream|||||",
      "10|sensor||||||||25000",
      "11|sensor,sensor||||||||50000,65535",
  };
  EXPECT_EQ(fields(dir.path, file,
                   {"frame.number", "ls5.sender", "ls5.address", "ls5.command", "ls5.command.name", "ls5.param",
                    "ls5.param.name", "ls5.param.value", "ls5.param.meaning", "ls5.result"}),
            expected);
  EXPECT_EQ(fields(dir.path, file, {"ls5.id.version", "ls5.id.lower_boundary", "ls5.id.range", "ls5.id.serial"},
                   {"-Y", "ls5.id.version"}),
            (std::vector<std::string>{"LS5.6.0|8,1234|40,0010|0000157"}));
  EXPECT_EQ(fields(dir.path, file, {"frame.number", "ls5.starts_in"}, {"-Y", "ls5.starts_in"}),
            (std::vector<std::string>{"11|10"}));
}

TEST(Wireshark, FamilyPreferenceOverridesTheGuess) {
  TempDir dir;
  // "#01ON": the LS5 "Turn on the sensor"; told it is a ULS line, the dissector finds no mnemonic.
  const auto file = write_recording(dir.path, "ls5", {{host, "#01ON\r"}});
  EXPECT_EQ(fields(dir.path, file, {"ls5.command", "uls.frame"}), (std::vector<std::string>{"ON|"}));
  EXPECT_EQ(fields(dir.path, file, {"ls5.command", "uls.frame"}, {"-o", "rangekit.family:uls"}),
            (std::vector<std::string>{"|#01ON"}));
}

// An Ethernet II / IPv4 / UDP frame from the sensor's defaults (§10: 192.168.0.3:5000 to
// 255.255.255.255, MAC 1E:30:6C:A2:XX:YY) carrying `payload`, as a classic pcap file.
std::filesystem::path write_udp(const std::filesystem::path& dir, const std::vector<std::string>& payloads,
                                std::uint16_t port) {
  auto le32 = [](std::string& s, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>(v >> (8 * i)));
  };
  auto be16 = [](std::string& s, std::uint16_t v) {
    s.push_back(static_cast<char>(v >> 8));
    s.push_back(static_cast<char>(v));
  };
  std::string file;
  le32(file, 0xa1b2c3d4);
  file += std::string("\x02\x00\x04\x00", 4);
  le32(file, 0);
  le32(file, 0);
  le32(file, 65535);
  le32(file, 1);  // LINKTYPE_ETHERNET
  std::uint32_t seconds = 1'796'000'000;
  for (const auto& payload : payloads) {
    std::string frame("\xff\xff\xff\xff\xff\xff\x1e\x30\x6c\xa2\x00\x9d\x08\x00", 14);
    std::string ip("\x45\x00", 2);
    be16(ip, static_cast<std::uint16_t>(20 + 8 + payload.size()));
    ip += std::string("\x00\x00\x00\x00\x40\x11\x00\x00\xc0\xa8\x00\x03\xff\xff\xff\xff", 16);
    std::string udp;
    be16(udp, 5000);
    be16(udp, port);
    be16(udp, static_cast<std::uint16_t>(8 + payload.size()));
    be16(udp, 0);  // no UDP checksum
    frame += ip + udp + payload;
    le32(file, seconds++);
    le32(file, 0);
    le32(file, static_cast<std::uint32_t>(frame.size()));
    le32(file, static_cast<std::uint32_t>(frame.size()));
    file += frame;
  }
  const auto path = dir / "udp.pcap";
  std::ofstream(path, std::ios::binary) << file;
  return path;
}

// §10.1: measurement 1 is code 2080h (formula 10.1: 40 mm × 2080h / 4000h = 20.3125 mm) with state
// 07h (performed, bit 1, in range); the other 167 are 0 with state 02h ("not yet performed", bit 1
// always 1); serial 157 (9Dh), lower boundary 8 mm, range 40 mm, counter 5. The checksum, XOR of
// bytes 0-509 worked by hand: 80h ^ 20h ^ 07h, 167 × 02h (odd: 02h), 9Dh, 08h, 28h = 18h.
std::string ls5_packet(char checksum) {
  std::string packet("\x80\x20\x07", 3);
  for (int i = 0; i < 167; ++i) packet += std::string("\x00\x00\x02", 3);
  packet += std::string("\x9d\x00\x08\x00\x28\x00\x05", 7);
  packet.push_back(checksum);
  return packet;
}

TEST(Wireshark, Ls5UdpPacketAndItsChecksum) {
  TempDir dir;
  const auto file = write_udp(dir.path, {ls5_packet('\x18'), ls5_packet('\x19')}, 603);
  ASSERT_EQ(ls5_packet('\x18').size(), 512u);
  EXPECT_EQ(fields(dir.path, file,
                   {"ls5udp.serial", "ls5udp.lower_boundary", "ls5udp.range", "ls5udp.counter", "ls5udp.checksum",
                    "ls5udp.checksum.status", "ls5udp.code", "ls5udp.distance"},
                   {"-E", "occurrence=f"}),
            (std::vector<std::string>{"157|8|40|5|0x18|Good|0x2080|20.3125", "157|8|40|5|0x19|Bad|0x2080|20.3125"}));
  // Expert info on the bad one only.
  EXPECT_EQ(fields(dir.path, file, {"frame.number"}, {"-Y", "ls5udp.checksum.bad"}), (std::vector<std::string>{"2"}));
  // 168 measurements in each packet.
  const auto states = fields(dir.path, file, {"ls5udp.state"}, {"-c", "1"});
  ASSERT_EQ(states.size(), 1u);
  EXPECT_EQ(std::count(states[0].begin(), states[0].end(), ',') + 1, 168);

  // Another port: only with the preference.
  const auto moved = write_udp(dir.path, {ls5_packet('\x18')}, 7000);
  EXPECT_EQ(fields(dir.path, moved, {"ls5udp.checksum.status"}), (std::vector<std::string>{""}));
  EXPECT_EQ(fields(dir.path, moved, {"ls5udp.checksum.status"}, {"-o", "rangekit.udp_port:7000"}),
            (std::vector<std::string>{"Good"}));
}

// The emulator of `family`, the tap in front of it recording, and `host_arguments` run against
// the tap's pty; gives the recording once the tap has closed it.
std::filesystem::path tapped_session(const TempDir& dir, const std::string& family,
                                     std::vector<std::string> host_arguments) {
  const auto sensor_port = (dir.path / "sensor").string();
  const auto host_port = (dir.path / "host").string();
  const auto recording = dir.path / "session.pcapng";
  Child sim{{"sim", family, "--port", sensor_port}};
  EXPECT_NE(sim.read_line().find("ready"), std::string::npos);
  Child tap{{"tap", family, "--host-pty", host_port, "--sensor", sensor_port, "--baud", "115200", "--format", "jsonl",
             "--out", recording.string()}};
  EXPECT_TRUE(path_appears(host_port));
  host_arguments.push_back("--port");
  host_arguments.push_back(host_port);
  const auto run = ls5_driver_test::run_cli(dir.path, host_arguments);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  tap.terminate();
  while (!tap.read_line().empty()) {
  }
  EXPECT_EQ(tap.wait(), 130);  // the recording closed whole
  return recording;
}

// Every CR in the recording ends one frame the dissector shows.
std::size_t frames_in(const std::filesystem::path& recording) {
  auto read = record::read_serial_pcapng(ls5_driver_test::read_file(recording));
  EXPECT_TRUE(read.ok());
  std::size_t count = 0;
  if (read.ok())
    for (const auto& chunk : read->chunks) count += std::count(chunk.bytes.begin(), chunk.bytes.end(), '\r');
  return count;
}

std::size_t occurrences(const std::vector<std::string>& lines) {
  std::size_t count = 0;
  for (const auto& line : lines)
    if (!line.empty()) count += std::count(line.begin(), line.end(), ',') + 1;
  return count;
}

TEST(Wireshark, TapRecordingOfTheUlsEmulator) {
  TempDir dir;
  const auto recording = tapped_session(dir, "uls", {"uls", "get"});
  // §8 Set/Get Measurement Units: the emulator answers in metres (n = 1 = meters).
  const auto lines = fields(dir.path, recording, {"uls.sender", "uls.mnemonic", "uls.value.meaning"}, {"-Y", "uls"});
  EXPECT_NE(std::find(lines.begin(), lines.end(), "host|MU|"), lines.end());
  EXPECT_NE(std::find(lines.begin(), lines.end(), "sensor|MU|meters"), lines.end());
  EXPECT_EQ(occurrences(fields(dir.path, recording, {"uls.sender"})), frames_in(recording));
  EXPECT_GT(frames_in(recording), 20u);
  EXPECT_TRUE(fields(dir.path, recording, {"frame.number"}, {"-Y", "uls.malformed || ls5"}).empty());
}

TEST(Wireshark, TapRecordingOfTheLs5EmulatorStreaming) {
  TempDir dir;
  const auto recording = tapped_session(dir, "ls5", {"ls5", "stream", "--count", "20", "--format", "jsonl"});
  const auto commands = fields(dir.path, recording, {"ls5.command"}, {"-Y", "ls5.sender == \"host\""});
  EXPECT_NE(std::find(commands.begin(), commands.end(), "ST"), commands.end());
  EXPECT_GE(occurrences(fields(dir.path, recording, {"ls5.result"}, {"-Y", "ls5.stream"})), 20u);
  EXPECT_EQ(occurrences(fields(dir.path, recording, {"ls5.sender"})), frames_in(recording));
  EXPECT_TRUE(fields(dir.path, recording, {"frame.number"}, {"-Y", "ls5.malformed || uls"}).empty());
}

}  // namespace
