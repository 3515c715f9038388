// The emulator scenes both demos use (`rangekit demo` and `rangekit serve --demo`),
// and the one way they write a scene file.
#pragma once

#include <filesystem>
#include <fstream>

#include "rangekit/core/result.hpp"

namespace rangekit::cli::demo_scenes {

// A ULS target: a pallet moving between 5 m and 25 m and back every 20 s, with a
// weak far wall behind it (§3: binning would show both).
inline constexpr const char* uls = R"(dust = 0.002

[[targets]]
name = "pallet"
path = [[0, 5], [10, 25], [20, 5]]
repeat = true
reflectivity = 0.6

[[targets]]
name = "back wall"
distance_m = 60
reflectivity = 0.2
)";

// A part passing under the LS5 head: 12 mm to 44 mm from the sensor (the
// 8.1234/40.001 model measures 8.1234 ... 48.1244 mm), with one shading gap.
inline constexpr const char* ls5 = R"([target]
path = [[0.0, 12.0], [10.0, 44.0], [20.0, 12.0]]
repeat = true
reflectivity = 0.8

[[dropout]]
start_s = 6.0
end_s = 6.5
kind = "shading"
)";

inline Status write_file(const std::filesystem::path& path, const char* text) {
  std::ofstream file(path);
  file << text;
  if (!file.flush()) return make_error(Errc::io, "cannot write " + path.string());
  return ok_status();
}

}  // namespace rangekit::cli::demo_scenes
