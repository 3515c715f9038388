// The site `rangekit serve --demo` serves: each family's emulators (cli_family.hpp), each a
// child process, and their SiteConfig. Destroying it stops the emulators and removes their
// temporary directory.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "cli/sim_process.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::cli {

// A family's part of the demo site.
struct CliDemoSite {
  std::string_view summary;  // for `serve --demo`'s help: what it runs
  int position = 0;          // where its sensors stand in the site, lowest first
  // Starts its emulators in `dir` (start_site_emulator) and adds their sensors to `site`.
  Status (*start)(const std::filesystem::path& dir, std::vector<SimProcess>& emulators,
                  hub::SiteConfig& site) = nullptr;
};

// Runs `rangekit sim <arguments>` with its log in `dir`, says it is ready on stdout and keeps it.
Status start_site_emulator(const std::filesystem::path& dir, const std::vector<std::string>& arguments,
                           std::vector<SimProcess>& emulators);
// A sensor of the site on a serial port (or none, for a UDP listener).
hub::SensorConfig site_sensor(std::string name, std::string family, std::string port);
// The families' summaries in site order: "an A, a B and a bus of four B".
std::string demo_site_summary();

class DemoSite {
 public:
  // Starts every family's emulators and sets them up. Progress goes to stdout.
  static Result<DemoSite> start();

  DemoSite(DemoSite&& other) noexcept;
  DemoSite& operator=(DemoSite&& other) noexcept;
  DemoSite(const DemoSite&) = delete;
  DemoSite& operator=(const DemoSite&) = delete;
  ~DemoSite();

  [[nodiscard]] const hub::SiteConfig& site() const { return site_; }
  // SIGTERM to each emulator, waited for; the directory removed. Idempotent.
  void stop() noexcept;

 private:
  DemoSite() = default;
  std::filesystem::path dir_;
  std::vector<SimProcess> emulators_;
  hub::SiteConfig site_;
};

}  // namespace rangekit::cli
