// The one way both demos (`rangekit demo` and `rangekit serve --demo`) write an
// emulator's scene file; each family holds its scenes (cli_family.hpp).
#pragma once

#include <filesystem>
#include <fstream>

#include "rangekit/core/result.hpp"

namespace rangekit::cli::demo_scenes {

inline Status write_file(const std::filesystem::path& path, const char* text) {
  std::ofstream file(path);
  file << text;
  if (!file.flush()) return make_error(Errc::io, "cannot write " + path.string());
  return ok_status();
}

}  // namespace rangekit::cli::demo_scenes
