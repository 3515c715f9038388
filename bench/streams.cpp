#include "streams.hpp"

#include <cstdio>
#include <random>

namespace rangekit::bench {

std::string uls_binning_stream(std::size_t bytes, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> targets(1, 15);
  std::uniform_real_distribution<double> distance(0.15, 1664.0);
  std::uniform_int_distribution<int> strength(1, 999);
  std::uniform_int_distribution<int> error_roll(0, 99);
  std::string stream;
  stream.reserve(bytes + 64);
  char line[64];
  while (stream.size() < bytes) {
    if (error_roll(random) == 0) {
      stream += "$ER,4\r";
      continue;
    }
    const int count = targets(random);
    for (int i = 0; i < count; ++i) {
      const int length =
          std::snprintf(line, sizeof line, "$BM,%d,%d,%.3f,%d\r", i, count, distance(random), strength(random));
      stream.append(line, static_cast<std::size_t>(length));
    }
  }
  return stream;
}

std::string ls5_stream(std::size_t bytes, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> step(0.0, 40.0);
  std::uniform_int_distribution<int> dropout(0, 199);
  std::string stream;
  stream.reserve(bytes + 8);
  double code = 25000.0;
  char line[16];
  while (stream.size() < bytes) {
    code += step(random);
    if (code < 0) code = 0;
    if (code > 50000) code = 50000;
    const unsigned value = dropout(random) == 0 ? 65535U : static_cast<unsigned>(code);
    const int length = std::snprintf(line, sizeof line, "!%05u\r", value);
    stream.append(line, static_cast<std::size_t>(length));
  }
  return stream;
}

}  // namespace rangekit::bench
