#include "cli/demo_site.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <utility>

#include "cli/cli_family.hpp"

namespace rangekit::cli {
namespace {

namespace fs = std::filesystem;

// The families' parts in the order their sensors stand in the site.
std::vector<const CliDemoSite*> site_parts() {
  std::vector<const CliDemoSite*> parts;
  for (const CliFamily* family : cli_families()) {
    if (family->demo_site.start != nullptr) parts.push_back(&family->demo_site);
  }
  std::stable_sort(parts.begin(), parts.end(),
                   [](const CliDemoSite* a, const CliDemoSite* b) { return a->position < b->position; });
  return parts;
}

}  // namespace

Status start_site_emulator(const fs::path& dir, const std::vector<std::string>& arguments,
                           std::vector<SimProcess>& emulators) {
  const std::string log = (dir / (fmt::format("sim-{}.log", emulators.size()))).string();
  auto emulator = SimProcess::start(arguments, log, std::chrono::seconds(15));
  if (!emulator) return std::move(emulator).error();
  fmt::print("  {}\n", emulator->ready_line());
  emulators.push_back(std::move(emulator).value());
  return ok_status();
}

hub::SensorConfig site_sensor(std::string name, std::string family, std::string port) {
  hub::SensorConfig config;
  config.name = std::move(name);
  config.family = std::move(family);
  config.port = std::move(port);
  return config;
}

std::string demo_site_summary() {
  std::string text;
  for (const CliDemoSite* part : site_parts()) text += (text.empty() ? "" : ", ") + std::string(part->summary);
  return text;
}

Result<DemoSite> DemoSite::start() {
  std::string pattern = (fs::temp_directory_path() / "rangekit-serve-demo-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    return make_error(Errc::io, "cannot create a directory in " + fs::temp_directory_path().string());
  }
  DemoSite demo;
  demo.dir_ = pattern;
  fmt::print("rangekit serve --demo: starting the emulators on pseudo-terminals in {}\n", demo.dir_.string());
  demo.site_.file = (demo.dir_ / "demo-site.toml").string();  // not written: the site is built here
  demo.site_.service.capture_dir = (demo.dir_ / "captures").string();
  for (const CliDemoSite* part : site_parts()) {
    if (auto status = part->start(demo.dir_, demo.emulators_, demo.site_); !status) return std::move(status).error();
  }
  return demo;
}

DemoSite::DemoSite(DemoSite&& other) noexcept
    : dir_(std::exchange(other.dir_, {})),
      emulators_(std::exchange(other.emulators_, {})),
      site_(std::move(other.site_)) {}

DemoSite& DemoSite::operator=(DemoSite&& other) noexcept {
  if (this != &other) {
    stop();
    dir_ = std::exchange(other.dir_, {});
    emulators_ = std::exchange(other.emulators_, {});
    site_ = std::move(other.site_);
  }
  return *this;
}

DemoSite::~DemoSite() { stop(); }

void DemoSite::stop() noexcept {
  for (SimProcess& emulator : emulators_) emulator.stop();
  emulators_.clear();
  if (!dir_.empty()) {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
    dir_.clear();
  }
}

}  // namespace rangekit::cli
