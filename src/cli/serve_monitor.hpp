// What `rangekit serve` says while it runs: each sensor's change of state with its reason, once
// per change (a journal reads well), and on a terminal a table of every sensor redrawn in place.
#pragma once

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "rangekit/hub/hub.hpp"

namespace rangekit::cli {

// One line of the table: name, family, state, rate and counts.
std::string summary_line(const hub::SensorSnapshot& sensor);

// "3 sensors: 2 streaming, 1 disconnected": the service's state in a line (systemctl status).
std::string states_line(const std::vector<hub::SensorSnapshot>& sensors);

class ServeMonitor {
 public:
  // `table`: redraw the table each tick (a terminal, or --table); else only the changes.
  // `timestamps`: begin each change with the time; the journal stamps lines itself.
  ServeMonitor(std::FILE* out, bool table, bool timestamps = true)
      : out_(out), table_(table), timestamps_(timestamps) {}
  void tick(const std::vector<hub::SensorSnapshot>& sensors);

 private:
  std::FILE* out_;
  bool table_;
  bool timestamps_;
  std::size_t drawn_ = 0;                    // table lines on the screen, redrawn in place
  std::map<std::string, std::string> said_;  // sensor -> the state last said
};

}  // namespace rangekit::cli
