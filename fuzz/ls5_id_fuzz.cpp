// The 35-character identification field (§9.2, L2, L17): what decodes must
// encode and decode again to the same values.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "rangekit/ls5/identification.hpp"

using namespace rangekit::ls5;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view field(reinterpret_cast<const char*>(data), size);
  const auto id = decode_identification_field(field);
  if (!id.ok()) return 0;
  const auto encoded = encode_identification_field(*id);
  if (!encoded.ok()) std::abort();
  const auto again = decode_identification_field(encoded->view());
  if (!again.ok()) std::abort();
  if (again->version_text.view() != id->version_text.view() || again->version != id->version ||
      again->lower_boundary_mm != id->lower_boundary_mm || again->range_mm != id->range_mm ||
      again->serial_number != id->serial_number) {
    std::abort();
  }
  return 0;
}
