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

class ServeMonitor {
 public:
  // `table`: redraw the table each tick (a terminal, or --table); else only the changes.
  ServeMonitor(std::FILE* out, bool table) : out_(out), table_(table) {}
  void tick(const std::vector<hub::SensorSnapshot>& sensors);

 private:
  std::FILE* out_;
  bool table_;
  std::size_t drawn_ = 0;                    // table lines on the screen, redrawn in place
  std::map<std::string, std::string> said_;  // sensor -> the state last said
};

}  // namespace rangekit::cli
