// Realistic byte streams for the parser benchmarks, built once per run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rangekit::bench {

// ULS binning output (§8/§9 format, conformance U10): measurements of 1 to 15
// targets, "$BM,i,m,xxxx.xxx,sss\r" lines, with the odd streamed error line.
std::string uls_binning_stream(std::size_t bytes, std::uint32_t seed);
// ULS averaging output in metres (§9, U9, U27): "$BM,xxxx.xxx\r", or with the
// pulse width "$BM,xxxx.xxx,yyyyyyy\r" (display mode 2), the odd error line.
std::string uls_averaging_stream(std::size_t bytes, std::uint32_t seed, bool with_intensity);
// LS5 UDP datagrams (§10.1, L12) of a moving target, one after another, 512 bytes each.
std::string ls5_udp_stream(std::size_t bytes, std::uint32_t seed);
// LS5 stream records "!ddddd\r" (§9.2, L1) with codes of a moving target and
// the odd no-signal code.
std::string ls5_stream(std::size_t bytes, std::uint32_t seed);

}  // namespace rangekit::bench
