// One CLI vocabulary for both families (U96, L70, docs/cli.md): the same key style in
// info/get, get's names accepted by set, the same `config diff` and `connected` event.
// Expectations typed from docs/cli.md and the documents' tables.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_run.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/core/udp.hpp"

namespace {

using cli_test::contains;
using cli_test::run_cli;

// Both emulators on ptys in a fresh directory.
struct VocabularyEmulators {
  ls5_driver_test::TempDir dir;
  std::string uls_port = (dir.path / "uls").string();
  std::string ls5_port = (dir.path / "ls5").string();
  std::string udp;
  std::unique_ptr<ls5_driver_test::Child> uls;
  std::unique_ptr<ls5_driver_test::Child> ls5;

  VocabularyEmulators() {
    auto probe = rangekit::UdpSocket::bind(rangekit::Endpoint{"127.0.0.1", 0});
    if (probe) udp = "127.0.0.1:" + std::to_string(probe->local_endpoint().port);
    uls = std::make_unique<ls5_driver_test::Child>(std::vector<std::string>{"sim", "uls", "--port", uls_port});
    ls5 = std::make_unique<ls5_driver_test::Child>(
        std::vector<std::string>{"sim", "ls5", "--port", ls5_port, "--udp", udp, "--time-scale", "10"});
  }
  bool ready() { return contains(uls->read_line(), "ready:") && contains(ls5->read_line(), "ready:"); }
};

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// `get`'s lines as set arguments: the "# wire" comment dropped, each NAME=VALUE quoted.
std::string as_assignments(const std::string& get_output, const std::vector<std::string>& leave_out) {
  std::string arguments;
  for (std::string line : lines_of(get_output)) {
    if (const auto comment = line.find("  #"); comment != std::string::npos) line.resize(comment);
    const std::string name = line.substr(0, line.find('='));
    bool skip = false;
    for (const auto& left : leave_out) skip = skip || name == left;
    if (!skip) arguments += " '" + line + "'";
  }
  return arguments;
}

// U96, L68: "The same key style in `info` and `get`, with units in the same place" (docs/cli.md):
// lower-case kebab names, the unit the name's last word, the value a bare number.
TEST(OneVocabulary, InfoAndGetOfBothFamiliesUseKebabNamesWithTheUnitInTheName) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  const std::regex kebab_line(R"(^[a-z0-9]+(-[a-z0-9]+)*=.*)");
  const std::regex unit_after_number(R"(^[^=]*=-?[0-9.,]+ [A-Za-z]+.*)");
  for (const std::string& command : {"uls info --port " + sims.uls_port, "uls get --port " + sims.uls_port,
                                     "ls5 info --port " + sims.ls5_port, "ls5 get --port " + sims.ls5_port}) {
    const auto run = run_cli(command);
    ASSERT_EQ(run.exit_code, 0) << command << ": " << run.output;
    for (const std::string& line : lines_of(run.output)) {
      EXPECT_TRUE(std::regex_match(line, kebab_line)) << command << ": " << line;
      EXPECT_FALSE(std::regex_match(line, unit_after_number)) << command << ": " << line;
    }
  }
  // §8 Set/Get Long Gate (metres), Trip Point Timeout "seconds x 3000" (10 s = 30000 = 0x7530
  // pulses), 4-20 mA Fault Current; one PRF value sets the current mode's (U14).
  ASSERT_EQ(
      run_cli("uls set --port " + sims.uls_port + " long-gate-m=12.5 trip-timeout-s=10 fault-current-ma=22 prf-hz=2500")
          .exit_code,
      0);
  const auto uls = run_cli("uls get --port " + sims.uls_port + " long-gate-m trip-timeout-s fault-current-ma prf-hz");
  EXPECT_TRUE(contains(uls.output, "long-gate-m=12.5  # LG=12.500\n")) << uls.output;
  EXPECT_TRUE(contains(uls.output, "trip-timeout-s=10  # TT=7530 (30000 pulses)\n")) << uls.output;
  EXPECT_TRUE(contains(uls.output, "fault-current-ma=22  # AF=22\n")) << uls.output;
  EXPECT_TRUE(contains(uls.output, "prf-hz=2500,2000,2000  # PF=2500,2000,2000\n")) << uls.output;
  const auto uls_json = run_cli("uls get --json --port " + sims.uls_port + " long-gate-m prf-hz mode baud-output");
  EXPECT_EQ(uls_json.output,
            "{\"long-gate-m\":12.5,\"prf-hz\":[2500,2000,2000],\"mode\":\"averaging\",\"baud-output\":115200}\n");

  // Table 9.2: "for t = 5,2 ms parameter is 0034"; median filter points default 05.
  ASSERT_EQ(run_cli("ls5 set --port " + sims.ls5_port + " period-ms=5.2").exit_code, 0);
  const auto ls5_json = run_cli("ls5 get --json --port " + sims.ls5_port + " period-ms median-points pre-filter");
  EXPECT_EQ(ls5_json.output, "{\"period-ms\":5.2,\"median-points\":5,\"pre-filter\":\"average\"}\n");
  const auto ls5_info = run_cli("ls5 info --json --port " + sims.ls5_port);
  EXPECT_TRUE(std::regex_search(ls5_info.output, std::regex(R"("address":1,.*"range-mm":[0-9])"))) << ls5_info.output;

  // One value, one word: info and get name the ULS status alike (§8 US 1: "ready, not measuring").
  const auto status_of = [](const std::string& output) {
    for (const std::string& line : lines_of(output))
      if (line.rfind("status=", 0) == 0) return line.substr(0, line.find("  #"));
    return std::string("(no status line)");
  };
  const auto uls_info = run_cli("uls info --port " + sims.uls_port);
  const auto uls_status = run_cli("uls get --port " + sims.uls_port + " status");
  EXPECT_EQ(status_of(uls_info.output), "status=ready, not measuring") << uls_info.output;
  EXPECT_EQ(status_of(uls_info.output), status_of(uls_status.output)) << uls_status.output;
}

// U97, L68: "`get`'s names are accepted by `set`; read-only names are not offered to `set`."
TEST(OneVocabulary, EveryNameGetPrintsIsAcceptedBySetAndReadOnlyNamesAreRefusedAsSuch) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  // ID and US are only read (§8); "unassigned" is UA's absence (error 82), not a value to set.
  const auto uls_get = run_cli("uls get --port " + sims.uls_port);
  const auto uls_set =
      run_cli("uls set --port " + sims.uls_port + as_assignments(uls_get.output, {"version", "status", "address"}));
  EXPECT_EQ(uls_set.exit_code, 0) << uls_set.output;
  const auto ls5_get = run_cli("ls5 get --port " + sims.ls5_port);
  const auto ls5_set = run_cli("ls5 set --port " + sims.ls5_port + as_assignments(ls5_get.output, {}));
  EXPECT_EQ(ls5_set.exit_code, 0) << ls5_set.output;

  const auto version = run_cli("uls set --port " + sims.uls_port + " version=2");
  EXPECT_EQ(version.exit_code, 2) << version.output;
  EXPECT_TRUE(contains(version.output, "'version' is read-only")) << version.output;
  const auto range = run_cli("ls5 set --port " + sims.ls5_port + " range-mm=10");
  EXPECT_EQ(range.exit_code, 2) << range.output;
  EXPECT_TRUE(contains(range.output, "'range-mm' is read-only")) << range.output;

  // The names an error or --help offers to set are the writable ones only.
  const auto unknown = run_cli("uls set --port " + sims.uls_port + " frob=1");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  const std::string offered = unknown.output.substr(unknown.output.find("writable names: "));
  EXPECT_TRUE(contains(offered, "long-gate-m, ")) << offered;
  EXPECT_FALSE(contains(offered, "version")) << offered;
  EXPECT_FALSE(contains(offered, "status")) << offered;
  for (const char* family : {"uls", "ls5"}) {
    const auto help = run_cli(std::string(family) + " set --help").output;
    ASSERT_TRUE(contains(help, "Writable names (as `get` prints them): ")) << help;
    EXPECT_FALSE(contains(help.substr(help.find("Writable names")), "version")) << help;
  }
}

// docs/cli.md: "get's output can be fed back to set". Whole, through --from: the version's
// spaces survive, read-only names are skipped and said, an unassigned address is left so.
TEST(OneVocabulary, GetsOutputGoesBackIntoSetWholeThroughFrom) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  const auto saved = sims.dir.path / "uls-get.txt";
  auto uls_get = run_cli("uls get --port " + sims.uls_port);
  ASSERT_EQ(uls_get.exit_code, 0) << uls_get.output;
  ASSERT_TRUE(contains(uls_get.output, "address=unassigned")) << uls_get.output;
  std::string edited = uls_get.output;
  const auto gate = edited.find("long-gate-m=0");
  ASSERT_NE(gate, std::string::npos) << edited;
  edited.replace(gate, std::string("long-gate-m=0").size(), "long-gate-m=12.5");
  std::ofstream(saved) << edited;
  const auto uls_set = run_cli("uls set --port " + sims.uls_port + " --from " + saved.string());
  EXPECT_EQ(uls_set.exit_code, 0) << uls_set.output;
  EXPECT_TRUE(contains(uls_set.output, "note: skipped version, status of the file: read-only")) << uls_set.output;
  EXPECT_TRUE(contains(run_cli("uls get --port " + sims.uls_port + " long-gate-m").output, "long-gate-m=12.5"));

  // Through a pipe, for the LS5 too.
  const auto ls5_get = run_cli("ls5 get --port " + sims.ls5_port);
  ASSERT_EQ(ls5_get.exit_code, 0) << ls5_get.output;
  const auto ls5_set = run_cli("ls5 set --port " + sims.ls5_port + " --from -", ls5_get.output);
  EXPECT_EQ(ls5_set.exit_code, 0) << ls5_set.output;

  // A line that is no assignment is named with its line number, before anything is sent.
  std::ofstream(sims.dir.path / "bad.txt") << "mode=binning\nnot an assignment\n";
  const auto bad = run_cli("uls set --port " + sims.uls_port + " --from " + (sims.dir.path / "bad.txt").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_TRUE(contains(bad.output, "bad.txt:2: 'not an assignment' is not NAME=VALUE")) << bad.output;
  EXPECT_TRUE(contains(run_cli("uls get --port " + sims.uls_port + " mode").output, "mode=averaging"));
}

// U96: "The same `config diff` output for `uls config diff` and `ls5 config diff`": one line
// `name: file=X device=Y` per difference, names as get prints them, a summary line, exit 1.
TEST(OneVocabulary, ConfigDiffPrintsTheSameLinesForBothFamilies) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  const std::string uls_file = (sims.dir.path / "uls.toml").string();
  const std::string ls5_file = (sims.dir.path / "ls5.toml").string();
  ASSERT_EQ(run_cli("uls config save --port " + sims.uls_port + " " + uls_file).exit_code, 0);
  ASSERT_EQ(run_cli("ls5 config save --port " + sims.ls5_port + " " + ls5_file).exit_code, 0);
  const std::regex none(R"(^no differences \([0-9]+ settings compared\)\n$)");
  const auto uls_same = run_cli("uls config diff --port " + sims.uls_port + " " + uls_file);
  EXPECT_EQ(uls_same.exit_code, 0) << uls_same.output;
  EXPECT_TRUE(std::regex_match(uls_same.output, none)) << uls_same.output;
  const auto ls5_same = run_cli("ls5 config diff --port " + sims.ls5_port + " " + ls5_file);
  EXPECT_EQ(ls5_same.exit_code, 0) << ls5_same.output;
  EXPECT_TRUE(std::regex_match(ls5_same.output, none)) << ls5_same.output;

  ASSERT_EQ(run_cli("uls set --port " + sims.uls_port + " long-gate-m=12.5").exit_code, 0);
  ASSERT_EQ(run_cli("ls5 set --port " + sims.ls5_port + " median-points=7").exit_code, 0);
  const std::regex one(R"(^[a-z0-9-]+: file=[^ ]+ device=[^ ]+\n1 of [0-9]+ settings differ\n$)");
  const auto uls = run_cli("uls config diff --port " + sims.uls_port + " " + uls_file);
  EXPECT_EQ(uls.exit_code, 1) << uls.output;
  EXPECT_TRUE(std::regex_match(uls.output, one)) << uls.output;
  EXPECT_TRUE(contains(uls.output, "long-gate-m: file=0 device=12.5\n")) << uls.output;
  const auto ls5 = run_cli("ls5 config diff --port " + sims.ls5_port + " " + ls5_file);
  EXPECT_EQ(ls5.exit_code, 1) << ls5.output;
  EXPECT_TRUE(std::regex_match(ls5.output, one)) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "median-points: file=5 device=7\n")) << ls5.output;
}

// L70: "One base per message": the LS5 network address is decimal everywhere ("The sensor has
// its own network address (from 1 to 255)", §9), as --address takes it; the frame is quoted
// as sent (#1AID). It was "LS5 at address 1A ... is its --address 26?" in one message.
TEST(OneVocabulary, AnLs5AddressIsDecimalInEveryMessage) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  const auto silent = run_cli("ls5 info --timeout 100 --address 26 --port " + sims.ls5_port);
  EXPECT_EQ(silent.exit_code, 5) << silent.output;
  EXPECT_TRUE(contains(silent.output, "LS5 at address 26 on ")) << silent.output;
  EXPECT_TRUE(contains(silent.output, "--address 26?")) << silent.output;
  EXPECT_FALSE(contains(silent.output, "address 1A")) << silent.output;
  const auto found = run_cli("detect --timeout 300 --baud 115200 --json --port " + sims.ls5_port);
  EXPECT_TRUE(contains(found.output, "\"address\":\"1\"")) << found.output;

  // The emulator names itself by the same decimal address ("[LS5 26] ready", not "1A").
  const std::string port = (sims.dir.path / "ls5-26").string();
  ls5_driver_test::Child addressed({"sim", "ls5", "--port", port, "--address", "26"});
  const std::string ready = addressed.read_line();
  EXPECT_TRUE(contains(ready, "[LS5 26] ready:")) << ready;
}

// A refused LS5 value is explained in the user's terms only: the allowed values in
// decimal, without the parameter byte's hex ("accepted: 01, 03, ..., 31") beside them.
TEST(OneVocabulary, AnLs5RefusalSpeaksOneBase) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  const auto run = run_cli("ls5 set median-points=99 --port " + sims.ls5_port);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(contains(run.output, "median-points=99 refused: allowed 1, 3, ..., 49 (odd)")) << run.output;
  EXPECT_FALSE(contains(run.output, "63")) << "99 as the hex byte it makes: " << run.output;
  EXPECT_FALSE(contains(run.output, "31")) << "49 as hex: " << run.output;
}

// L69: "A `connected` event for both families": the ULS stream's first item is `connected`
// (host-uls.md); the LS5 serial stream and the UDP receiver say the same when their
// link first comes up.
TEST(OneVocabulary, BothFamiliesStreamsStartWithAConnectedEvent) {
  VocabularyEmulators sims;
  ASSERT_TRUE(sims.ready());
  const auto uls = run_cli("uls stream --count 1 --format jsonl --port " + sims.uls_port);
  EXPECT_EQ(uls.exit_code, 0) << uls.output;
  EXPECT_TRUE(contains(uls.output, "\"event\":\"connected\"")) << uls.output;

  const auto ls5 = run_cli("ls5 stream --count 1 --format jsonl --port " + sims.ls5_port);
  EXPECT_EQ(ls5.exit_code, 0) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "\"event\":\"connected\"")) << ls5.output;
  EXPECT_TRUE(contains(ls5.output, "connected: " + sims.ls5_port + ": streaming")) << ls5.output;

  const auto udp = run_cli("ls5 udp --count 1 --format jsonl --duration 60 --udp-listen " + sims.udp);
  EXPECT_EQ(udp.exit_code, 0) << udp.output;
  EXPECT_TRUE(contains(udp.output, "\"event\":\"connected\"")) << udp.output;
}

}  // namespace
