// A site of emulators on ptys for the hub and web tests: an LS5 ("belt"), a ULS
// alone ("silo") and an RS-485 bus of four ULS units ("bay-A" .. "bay-D", Continuous
// Output off as §7 requires), with the site file that names them.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "ls5_driver/cli_process.hpp"
#include "rangekit/hub/site_config.hpp"

namespace hub_test {

using ls5_driver_test::Child;
using ls5_driver_test::TempDir;

inline bool ready(Child& child) { return child.read_line().find("ready") != std::string::npos; }

inline std::string site_text(const std::filesystem::path& dir) {
  const auto path = [&](const char* name) { return (dir / name).string(); };
  return "[[sensor]]\nname = \"belt\"\nfamily = \"ls5\"\nport = \"" + path("ls5") +
         "\"\n"
         "[[sensor]]\nname = \"silo\"\nfamily = \"uls\"\nport = \"" +
         path("uls") + "\"\n" + [&] {
           std::string bus;
           for (const char* unit : {"A", "B", "C", "D"}) {
             bus += "[[sensor]]\nname = \"bay-" + std::string(unit) + "\"\nfamily = \"uls\"\nport = \"" + path("bus") +
                    "\"\naddress = \"" + unit + "\"\n";
           }
           return bus;
         }();
}

struct Site {
  TempDir temp;
  // The emulators' control sockets, to check what reached a sensor from its own side.
  std::string ls5_control = (temp.path / "ls5.control").string();
  std::string bus_control = (temp.path / "bus.control").string();
  Child ls5{{"sim", "ls5", "--port", (temp.path / "ls5").string(), "--control", ls5_control}};
  Child uls{{"sim", "uls", "--port", (temp.path / "uls").string()}};
  Child bus{{"sim", "uls", "--bus", (temp.path / "bus").string(), "--address", "A", "--address", "B", "--address", "C",
             "--address", "D", "--control", bus_control}};
  rangekit::hub::SiteConfig config;
  Site() {
    EXPECT_TRUE(ready(ls5) && ready(uls) && ready(bus));
    // §7: "The Continuous Output setting must be turned off since units only talk on the bus when addressed."
    for (const char* unit : {"A", "B", "C", "D"}) {
      const auto run = ls5_driver_test::run_cli(
          temp.path, {"uls", "set", "--port", (temp.path / "bus").string(), "--address", unit, "continuous=off"});
      EXPECT_EQ(run.exit_code, 0) << run.err;
    }
    auto parsed = rangekit::hub::parse_site_config(site_text(temp.path), "site.toml");
    EXPECT_TRUE(parsed.ok()) << (parsed.ok() ? "" : parsed.error().message);
    if (parsed) config = *parsed;
  }
};

}  // namespace hub_test
