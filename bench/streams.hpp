// Realistic byte streams for the parser benchmarks, built once per run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rangekit::bench {

// ULS binning output (§8/§9 format, conformance U10): measurements of 1 to 15
// targets, "$BM,i,m,xxxx.xxx,sss\r" lines, with the odd streamed error line.
std::string uls_binning_stream(std::size_t bytes, std::uint32_t seed);
// LS5 stream records "!ddddd\r" (§9.2, L1) with codes of a moving target and
// the odd no-signal code.
std::string ls5_stream(std::size_t bytes, std::uint32_t seed);

}  // namespace rangekit::bench
