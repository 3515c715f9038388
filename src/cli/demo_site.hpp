// The site `rangekit serve --demo` serves: an LS5 emulator (serial and Ethernet), a ULS
// and an RS-485 bus of four ULS units, each a child process, and their SiteConfig.
// Destroying it stops the emulators and removes their temporary directory.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "cli/sim_process.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::cli {

class DemoSite {
 public:
  // Starts the emulators and sets the bus units up (Continuous Output off, §7;
  // one in binning, one in look down). Progress goes to stdout.
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
