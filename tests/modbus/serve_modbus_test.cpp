// `rangekit serve --demo --modbus` asked by mbpoll, the command-line Modbus client a PLC
// engineer tries first (docs/modbus.md): what it prints is the silo's reading as the HTTP API
// has it, and a unit with no sensor is refused as the map says.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "child_process.hpp"
#include "ls5_driver/cli_process.hpp"
#include "web/http_client.hpp"

namespace {

using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

struct ProgramRun {
  int exit_code = -1;
  std::string out;
};

// Runs a program to its end, its stdout and stderr together.
ProgramRun run_program(const TempDir& dir, const std::vector<std::string>& arguments) {
  const auto out_path = dir.path / "program.out";
  const pid_t pid = rangekit::test::fork_child();
  if (pid == 0) {
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
    std::vector<char*> argv;
    for (const std::string& each : arguments) argv.push_back(const_cast<char*>(each.c_str()));
    argv.push_back(nullptr);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return ProgramRun{WIFEXITED(status) ? WEXITSTATUS(status) : -1, ls5_driver_test::read_file(out_path)};
}

// mbpoll's "[0]: 	10497" lines: register (or value) number and text.
std::map<int, std::string> values_of(const std::string& out) {
  std::map<int, std::string> values;
  static const std::regex line(R"(\[(\d+)\]:\s+(\S+))");
  for (std::sregex_iterator it(out.begin(), out.end(), line), end; it != end; ++it) {
    values[std::stoi((*it)[1])] = (*it)[2];
  }
  return values;
}

TEST(ServeModbus, MbpollReadsTheDemosSiloAsTheApiHasIt) {
  TempDir dir;
  Child service({"serve", "--demo", "--duration", "120", "--listen", "127.0.0.1:0", "--modbus", "127.0.0.1:0"});
  std::string log;
  std::uint16_t api = 0;
  std::uint16_t modbus = 0;
  std::string units;
  static const std::regex api_line(R"(API on http://127\.0\.0\.1:(\d+)/)");
  static const std::regex modbus_line(R"(Modbus TCP on 127\.0\.0\.1:(\d+), units (.*) \(docs)");
  for (std::string line = service.read_line(); !line.empty() && (api == 0 || modbus == 0); line = service.read_line()) {
    log += line;
    std::smatch found;
    if (std::regex_search(line, found, api_line)) api = static_cast<std::uint16_t>(std::stoi(found[1]));
    if (std::regex_search(line, found, modbus_line)) {
      modbus = static_cast<std::uint16_t>(std::stoi(found[1]));
      units = found[2];
    }
  }
  ASSERT_NE(modbus, 0) << log;
  ASSERT_NE(api, 0) << log;
  // --demo's units: 1-7 in the order GET /api/sensors lists the sensors.
  const auto listed = web_test::http(api, "GET", "/api/sensors");
  ASSERT_EQ(listed.status, 200);
  std::string expected;
  int unit = 0;
  const auto sensors = nlohmann::json::parse(listed.body);
  for (const auto& sensor : sensors["sensors"]) {
    expected += (expected.empty() ? "" : ", ") + std::to_string(++unit) + " " + sensor["name"].get<std::string>();
  }
  EXPECT_EQ(units, expected);
  ASSERT_NE(units.find("3 silo"), std::string::npos) << units;
  const std::string silo_unit = "3";

  // Status until the silo's reading is valid (bit 2), as a PLC would poll it.
  const std::string port = std::to_string(modbus);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  ProgramRun status;
  while (std::chrono::steady_clock::now() < deadline) {
    status = run_program(dir, {"mbpoll", "-m", "tcp", "-p", port, "-a", silo_unit, "-t", "3", "-0", "-r", "4", "-c",
                               "1", "-1", "127.0.0.1"});
    const auto values = values_of(status.out);
    if (values.contains(4) && (std::stoi(values.at(4)) & 0b111) == 0b111) break;
  }
  ASSERT_EQ(status.exit_code, 0) << status.out;
  ASSERT_EQ(std::stoi(values_of(status.out).at(4)) & 0b111, 0b111) << status.out;  // connected, streaming, valid
  // The float at 0-1, big-endian words (-B: ABCD, the default word order).
  const ProgramRun reading = run_program(dir, {"mbpoll", "-m", "tcp", "-p", port, "-a", silo_unit, "-t", "3:float",
                                               "-B", "-0", "-r", "0", "-c", "1", "-1", "127.0.0.1"});
  ASSERT_EQ(reading.exit_code, 0) << reading.out;
  const double millimetres = std::stod(values_of(reading.out).at(0));
  const auto samples = web_test::http(api, "GET", "/api/sensors/silo/samples?limit=1000");
  ASSERT_EQ(samples.status, 200) << samples.body;
  std::set<long> distances_um;
  const auto items = nlohmann::json::parse(samples.body);
  for (const auto& item : items["items"]) {
    if (item["data"].contains("distance_m") && item["data"]["distance_m"].is_number()) {
      distances_um.insert(std::lround(item["data"]["distance_m"].get<double>() * 1e6));
    }
  }
  // mbpoll prints 6 significant digits: 10497 mm is 10.497 m to the micrometre.
  EXPECT_TRUE(distances_um.contains(std::lround(millimetres * 1000.0)))
      << millimetres << " mm is none of the silo's last readings\n"
      << reading.out;

  const ProgramRun nobody = run_program(
      dir, {"mbpoll", "-m", "tcp", "-p", port, "-a", "99", "-t", "3", "-0", "-r", "0", "-c", "1", "-1", "127.0.0.1"});
  EXPECT_NE(nobody.out.find("Target device failed to respond"), std::string::npos) << nobody.out;
  service.terminate();
  std::string tail;
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) tail += line;
  EXPECT_EQ(service.wait(), 130);
  EXPECT_NE(tail.find("modbus: requests "), std::string::npos) << tail;
}

}  // namespace

namespace {

std::filesystem::path write_site(const TempDir& dir, const std::string& text) {
  const auto path = dir.path / "site.toml";
  std::ofstream(path) << text;
  return path;
}

// The map a PLC engineer imports: every register of every unit, the site's unit ids and word order.
TEST(ServeModbus, TheMapOfASiteFileIsItsUnitsRegistersAsCsv) {
  TempDir dir;
  const auto site = write_site(dir,
                               "[modbus]\nword_order = \"CDAB\"\nwritable = true\n"
                               "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"/dev/x\"\n"
                               "[[sensor]]\nname = \"silo\"\nfamily = \"uls\"\nport = \"/dev/y\"\nmodbus_unit = 20\n");
  const auto run = ls5_driver_test::run_cli(dir.path, {"serve", "--check", site.string(), "--modbus-map"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::istringstream lines(run.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "unit,sensor,table,register,type,name,unit_of_measure,word_order,description");
  std::map<std::string, int> rows;
  while (std::getline(lines, line)) ++rows[line.substr(0, line.find(',', line.find(',') + 1))];
  EXPECT_EQ(rows, (std::map<std::string, int>{{"1,belt", 25 + 3}, {"20,silo", 25 + 3}}));  // 25 input, 3 holding
  EXPECT_NE(run.out.find("20,silo,input,2,int32,reading_um,um,CDAB,"), std::string::npos) << run.out;
  const auto check = ls5_driver_test::run_cli(dir.path, {"serve", "--check", site.string()});
  EXPECT_EQ(check.exit_code, 0) << check.err;
}

// Modbus has no authentication: beyond loopback the site file must say who may connect.
TEST(ServeModbus, ListeningBeyondLoopbackWithoutAnAllowListIsRefusedAtStart) {
  TempDir dir;
  const auto site = write_site(
      dir, "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + (dir.path / "nothing-here").string() + "\"\n");
  const auto run = ls5_driver_test::run_cli(
      dir.path, {"serve", "--config", site.string(), "--listen", "127.0.0.1:0", "--modbus", "0.0.0.0:0"});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_NE(run.err.find("is beyond loopback: name who may connect with [modbus] allow"), std::string::npos) << run.err;
}

}  // namespace
