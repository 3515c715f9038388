// The architecture of docs/architecture.md, checked on the tree itself:
// which library may link which (cmake/architecture.cmake, run here on edges it
// must refuse) and which sources may include which headers.
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "rangekit/core/family.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path root = rangekit::test::source_dir();

// Runs the link rule of cmake/architecture.cmake on one edge list; true when allowed.
bool link_allowed(const std::string& target, const std::string& links) {
  const std::string command = "cmake -DTARGET=" + target + " \"-DLINKS=" + links + "\" -P " +
                              (root / "cmake/architecture_selftest.cmake").string() + " >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

TEST(Architecture, LinkRuleAllowsTheDrawnEdges) {
  EXPECT_TRUE(link_allowed("rangekit_core", "Threads::Threads;nlohmann_json::nlohmann_json"));
  EXPECT_TRUE(link_allowed("rangekit_uls", "rangekit_core;$<LINK_ONLY:tomlplusplus::tomlplusplus>"));
  EXPECT_TRUE(link_allowed("rangekit_ls5", "rangekit::core"));
  EXPECT_TRUE(link_allowed("rangekit_record", "rangekit_core;$<LINK_ONLY:SQLite::SQLite3>"));
  EXPECT_TRUE(link_allowed("rangekit_sim", "rangekit_core;rangekit_uls;rangekit_ls5"));
  EXPECT_TRUE(link_allowed("rangekit_hub", "rangekit_core;rangekit_record"));
  EXPECT_TRUE(link_allowed("rangekit_uls_service", "rangekit_hub;rangekit_uls;rangekit_core"));
  EXPECT_TRUE(link_allowed("rangekit_ls5_service", "rangekit_hub;rangekit_ls5;rangekit_core"));
}

TEST(Architecture, LinkRuleRefusesEveryOtherEdge) {
  EXPECT_FALSE(link_allowed("rangekit_core", "rangekit_uls"));  // core knows no family
  EXPECT_FALSE(link_allowed("rangekit_core", "rangekit::record"));
  EXPECT_FALSE(link_allowed("rangekit_uls", "rangekit_ls5"));  // families never reach each other
  EXPECT_FALSE(link_allowed("rangekit_ls5", "$<LINK_ONLY:rangekit_uls>"));
  EXPECT_FALSE(link_allowed("rangekit_uls", "rangekit_sim"));  // an embedder links no emulator
  EXPECT_FALSE(link_allowed("rangekit_record", "rangekit_sim"));
  EXPECT_FALSE(link_allowed("rangekit_sim", "rangekit_record"));
  EXPECT_FALSE(link_allowed("rangekit_hub", "rangekit_sim"));  // the service serves real sensors
  EXPECT_FALSE(link_allowed("rangekit_uls", "rangekit_hub"));  // drivers know nothing of the hub above them
  EXPECT_FALSE(link_allowed("rangekit_record", "rangekit::hub"));
  EXPECT_FALSE(link_allowed("rangekit_hub", "rangekit_uls"));  // families register with the hub
  EXPECT_FALSE(link_allowed("rangekit_uls_service", "rangekit_ls5"));
  EXPECT_FALSE(link_allowed("rangekit_ls5_service", "rangekit_sim"));
}

struct Include {
  fs::path file;
  std::string header;
};

// Every #include "..." of the sources under `folder` (recursively).
std::vector<Include> includes_under(const fs::path& folder) {
  std::vector<Include> found;
  const std::regex include_line(R"re(^\s*#\s*include\s*"([^"]+)")re");
  for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
    if (!entry.is_regular_file()) continue;
    const auto extension = entry.path().extension();
    if (extension != ".cpp" && extension != ".hpp") continue;
    std::ifstream in(entry.path());
    for (std::string line; std::getline(in, line);) {
      std::smatch match;
      if (std::regex_search(line, match, include_line)) found.push_back({fs::relative(entry.path(), root), match[1]});
    }
  }
  return found;
}

// Fails for each include under `folder` (filtered by `file_filter` on its path) that matches `forbidden`.
void expect_no_include(const fs::path& folder, const std::string& forbidden, const std::string& why,
                       const std::string& file_filter = ".*") {
  const std::regex pattern(forbidden);
  const std::regex files(file_filter);
  for (const auto& include : includes_under(folder)) {
    if (!std::regex_match(include.file.string(), files)) continue;
    EXPECT_FALSE(std::regex_search(include.header, pattern))
        << include.file.string() << " includes \"" << include.header << "\": " << why;
  }
}

TEST(Architecture, CoreKnowsNoFamily) {
  const std::string family = R"(^(rangekit/)?(uls|ls5|record|sim|hub)/)";
  expect_no_include("src/core", family, "core is shared by both families and knows neither");
  expect_no_include("include/rangekit/core", family, "core is shared by both families and knows neither");
}

TEST(Architecture, CodecsNeverReachIo) {
  // The codec is the top level of a family folder; driver/ and emulator/ below it do I/O.
  const std::string io =
      R"((transport|serial_port|udp|pty|fd_transport|loopback|stream_queue|emulator_runtime|control_socket)\.hpp$|/driver/|/emulator/|/driver\.hpp$|/bus\.hpp$|udp_receiver\.hpp$)";
  for (const std::string family : {"uls", "ls5"}) {
    expect_no_include("src/" + family, io, "a codec does no I/O", "src/" + family + "/[^/]+");
  }
}

TEST(Architecture, DriversAndEmulatorsNeverReachEachOther) {
  for (const std::string family : {"uls", "ls5"}) {
    expect_no_include("src/" + family + "/driver", R"(emulator|control_socket|emulator_runtime|device_model)",
                      "a host driver never depends on an emulator");
    for (const std::string& emulator : {"src/" + family + "/emulator", "include/rangekit/" + family + "/emulator"}) {
      expect_no_include(emulator, R"(/driver/|driver\.hpp$|/bus\.hpp$|host_)",
                        "an emulator never depends on a host driver");
    }
  }
}

TEST(Architecture, HostLibrariesNeverReachTheEmulators) {
  // An embedder of the drivers links no emulator (rangekit::sim), so nothing they compile includes
  // one: neither the runtime (rangekit/sim/) nor a family's firmware model (rangekit/<family>/emulator/).
  for (const std::string folder : {"src/uls", "src/ls5", "src/record", "src/core", "include/rangekit/uls",
                                   "include/rangekit/ls5", "include/rangekit/record"}) {
    // A family's emulator and CLI parts are no part of its host library.
    expect_no_include(folder, R"(^rangekit/(sim|uls/emulator|ls5/emulator)/)",
                      "the host libraries never depend on rangekit::sim",
                      "(?!(src|include/rangekit)/(uls|ls5)/(emulator|cli)/).*");
  }
}

TEST(Architecture, HubKnowsNoFamilyNoFaceAndNoEmulator) {
  // The hub sits between the drivers and the faces (HTTP/SSE, MQTT, Python): it knows none of
  // them, and the families register with it (hub/service_family.hpp).
  for (const std::string folder : {"src/hub", "include/rangekit/hub"}) {
    expect_no_include(folder, R"(^rangekit/(sim|uls|ls5)/|^(uls|ls5)/|boost/|beast|httplib|mosquitto|pybind11|^cli/)",
                      "the hub knows no family, HTTP, MQTT, Python face, CLI or emulator");
  }
}

TEST(Architecture, OnlyAFamilysServicePartKnowsTheHub) {
  // A family's codec, driver and emulator are for embedders too; its service/ folder alone
  // implements the hub's backend.
  for (const std::string family : {"uls", "ls5"}) {
    expect_no_include("src/" + family, R"(^rangekit/hub/)", "only src/" + family + "/service knows the hub",
                      "(?!src/" + family + "/service/).*");
    expect_no_include("include/rangekit/" + family, R"(^rangekit/hub/)", "only the service part's header knows the hub",
                      "(?!include/rangekit/" + family + "/service_family\\.hpp$).*");
  }
}

TEST(Architecture, FacesReachTheSensorsOnlyThroughTheHub) {
  // The MQTT bridge (docs/mqtt.md), like the HTTP face, is a face on the hub: no driver, codec or emulator.
  for (const std::string folder : {"src/web", "src/mqtt", "src/sinks", "include/rangekit/web", "include/rangekit/mqtt",
                                   "include/rangekit/sinks"}) {
    expect_no_include(folder, R"(^rangekit/(uls|ls5|sim)/|^(uls|ls5|sim)/)",
                      "a face reaches the sensors only through rangekit::hub");
  }
}

TEST(Architecture, CliIncludesNoPrivateHeaderOfALibrary) {
  // Its own headers (cli/...) and the libraries' public ones (rangekit/...) only; a family's
  // CLI part (src/<family>/cli) its own headers too.
  expect_no_include("src/cli", R"(^(?!cli/|rangekit/))", "the CLI uses the libraries' public headers only");
  for (const std::string family : {"uls", "ls5"}) {
    expect_no_include("src/" + family + "/cli", "^(?!cli/|rangekit/|" + family + "/cli/)",
                      "a family's CLI part uses the CLI's headers, its own and the libraries' public ones only");
  }
}

TEST(Architecture, GenericCliKnowsNoFamily) {
  // Each family adds its subcommands and its part of decode, detect, ... (cli/cli_family.hpp).
  expect_no_include("src/cli", R"(^(rangekit/)?(sim/)?(uls|ls5)/)",
                    "the generic commands name no family: each registers its part from src/<family>/cli");
  expect_no_include("src/uls/cli", R"(^(rangekit/)?(sim/)?ls5/)", "a family's CLI part knows no other family");
  expect_no_include("src/ls5/cli", R"(^(rangekit/)?(sim/)?uls/)", "a family's CLI part knows no other family");
}

TEST(Architecture, PythonModuleUsesThePublicHeadersOnly) {
  // "The Python package must be the same library, not a second implementation" (docs/python.md):
  // its module (python/src) binds the public headers, besides its own and the registration
  // list, and links no emulator (rangekit.sim runs the CLI's `rangekit sim` as a child
  // process) and no hub.
  for (const auto& include : includes_under("python/src")) {
    const bool own = fs::is_regular_file(root / "python/src" / include.header);
    const bool allowed = own || include.header.starts_with("rangekit/") || include.header == "families/list.hpp";
    EXPECT_TRUE(allowed) << include.file.string() << " includes \"" << include.header
                         << "\": the Python module uses the libraries' public headers only";
  }
  expect_no_include("python/src", R"(^rangekit/(sim|hub|uls/emulator|ls5/emulator)/)",
                    "the Python module binds no emulator or hub");
}

TEST(Architecture, PythonSharedPartKnowsNoFamily) {
  // A family's binding lives in python/src/<family>/; the shared part beside those folders
  // reaches them through the registration list (registered_families.cpp) only.
  expect_no_include("python/src", R"(^rangekit/(uls|ls5)/|^(uls|ls5)/)",
                    "the Python module's shared part knows no family", "python/src/[^/]+");
  for (const std::string family : {"uls", "ls5"}) {
    const std::string other = family == "uls" ? "ls5" : "uls";
    expect_no_include("python/src/" + family, "^(rangekit/)?" + other + "/",
                      "a family's binding never reaches another family's");
  }
}

TEST(Architecture, TheDashboardsSharedFilesNameNoFamily) {
  // A family's part of the dashboard lives in web/src/<family>/; the build generates the list of
  // them from families.cmake, so no shared file names one (docs/architecture.md).
  const auto families = rangekit::families();
  ASSERT_FALSE(families.empty());
  for (const rangekit::FamilyDescriptor* family : families) {
    EXPECT_TRUE(fs::is_regular_file(root / "web/src" / family->name / "index.ts")) << family->name;
  }
  for (const auto& entry : fs::directory_iterator(root / "web/src")) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    const std::string content = text.str();
    for (const rangekit::FamilyDescriptor* family : families) {
      const std::regex name("\\b" + std::string(family->name) + "\\b", std::regex::icase);
      EXPECT_FALSE(std::regex_search(content, name))
          << fs::relative(entry.path(), root).string() << " names the family " << family->name;
    }
  }
}

}  // namespace
