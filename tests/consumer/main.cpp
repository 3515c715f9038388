// A consumer of the installed rangekit: decodes one frame of each document with
// the public codecs and prints what it read. Its output is checked by
// scripts/check-consumer.sh against values typed from the documents.
#include <cstdio>
#include <string_view>
#include <variant>

#include "rangekit/ls5/reply.hpp"
#include "rangekit/uls/measurement.hpp"
#include "rangekit/version.hpp"

namespace {

rangekit::Bytes bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

}  // namespace

int main() {
  std::printf("rangekit %s\n", rangekit::version_string);

  // ULS §8 averaging output "$BM,n,p<CR>": range and pulse width (DM 2), as the
  // framer hands the frame over (without its CR).
  rangekit::uls::MeasurementContext context;
  context.display = rangekit::uls::DisplayMode::range_and_intensity;
  const auto uls = rangekit::uls::decode_measurement(bytes_of("$BM,12.345,33000"), context);
  if (!uls) {
    std::printf("uls: %s\n", uls.error().message.c_str());
    return 1;
  }
  const auto& averaging = std::get<rangekit::uls::AveragingReading>(uls->reading);
  std::printf("uls %.3f m %u ps\n", averaging.range->metres, *averaging.pulse_width_ps);

  // LS5 §9.4 example: the echo "!02W0B01" to "set the median filtering for the sensor with address 02".
  const auto ls5 = rangekit::ls5::parse_reply_line(bytes_of("!02W0B01\r"));
  if (!ls5) {
    std::printf("ls5: %s\n", ls5.error().message.c_str());
    return 1;
  }
  std::printf("ls5 address %u parameter %02X value %02X\n", ls5->address, ls5->parameter, ls5->value);
  return 0;
}
