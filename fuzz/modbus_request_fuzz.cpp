// A Modbus TCP connection's bytes, as the face's server reads them: each request the MBAP
// framer finds is answered by the face's own units (writable, on a hub whose sensors are not
// connected), until bytes that are no Modbus close the connection. Every answer is one
// well-formed response to its request: its transaction id, protocol 0, a length that matches.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "modbus/face_impl.hpp"
#include "rangekit/hub/site_config.hpp"

namespace {

rangekit::modbus::FaceUnits& units() {
  static const auto site = rangekit::hub::parse_site_config(
      "[[sensor]]\nname = \"l\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-fuzz-ls5\"\n"
      "[[sensor]]\nname = \"u\"\nfamily = \"uls\"\nport = \"/nonexistent/rangekit-fuzz-uls\"\n",
      "site.toml");
  if (!site) std::abort();
  static const auto hub = rangekit::hub::Hub::start(*site);
  static rangekit::modbus::FaceUnits table(*hub, rangekit::modbus::WordOrder::cdab, true);
  static const bool added = [] {
    table.add(1, "l", "ls5");
    table.add(2, "u", "uls");
    return true;
  }();
  (void)added;
  return table;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rangekit::Bytes rest(data, size);
  std::vector<std::uint8_t> out;
  while (!rest.empty()) {
    const rangekit::FrameScan scan = rangekit::modbus::scan_mbap_frame(rest);
    if (scan.status != rangekit::FrameStatus::complete) break;  // more needed, or the connection closes
    out.clear();
    (void)rangekit::modbus::answer_request(scan.frame, units(), out);
    if (out.size() < 9 || out[0] != scan.frame[0] || out[1] != scan.frame[1] || out[2] != 0 || out[3] != 0 ||
        static_cast<std::size_t>((out[4] << 8) | out[5]) != out.size() - 6 || out[6] != scan.frame[6]) {
      std::abort();
    }
    rest = rest.subspan(scan.consumed);
  }
  return 0;
}
