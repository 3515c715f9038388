// The ULS decoders against their recorded outputs on a large corpus, malformed lines
// included, so optimising them leaves every output unchanged (tests/decoder_corpus.hpp).
// The emulator's lines for every mode, mutated, plus replies and junk, are digested.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "decoder_corpus.hpp"
#include "rangekit/uls/uls.hpp"

namespace rangekit::uls {
namespace {

using testing::corpus::Digest;
using testing::corpus::escaped;
using testing::corpus::exact;
using testing::corpus::Random;

constexpr std::size_t corpus_lines = 60000;

Address random_address(Random& random) {
  switch (random.below(8)) {
    case 0:
      return Address::unit(static_cast<std::uint8_t>('0' + random.below(0x50)));
    case 1:
      return Address::unit(static_cast<std::uint8_t>(0x30 + random.below(0xD0)));  // units and broadcasts
    default:
      return Address::none();
  }
}

Range random_range(Random& random, Units units) {
  const double scale = units == Units::metres ? 1000.0 : 100.0;
  const auto steps = static_cast<double>(random.below(random.one_in(10) ? 100000000U : 2000000U));
  const double user = (random.one_in(20) ? -1.0 : 1.0) * steps / scale;
  return make_range(user, units);
}

Reading random_reading(Random& random, Units units) {
  switch (random.below(10)) {
    case 0:
    case 1: {
      const auto count = static_cast<std::uint8_t>(1 + random.below(max_binning_targets));
      return BinningTarget{static_cast<std::uint8_t>(random.below(count)), count, random_range(random, units),
                           random.below(70000)};
    }
    case 2:
      return AveragingReading{std::nullopt, random.below(12000000)};
    case 3:
    case 4:
      return AveragingReading{random_range(random, units), random.below(12000000)};
    case 5:
      return LookDownReading{random.one_in(2)};
    case 6:
      return random.one_in(3)
                 ? TimeBetweenEvents{}
                 : TimeBetweenEvents{TimeBetweenEvents::Kind::pulses, static_cast<std::uint16_t>(random.below(65536))};
    case 7:
      return MeasurementError{static_cast<int>(random.below(1000))};
    default:
      return AveragingReading{random_range(random, units), std::nullopt};
  }
}

// One line as the emulator writes it, or a reply, junk or a hand-made odd line.
std::string random_line(Random& random) {
  const Units units = random.one_in(3) ? Units::feet : Units::metres;
  if (random.below(10) < 8) {
    if (auto line = encode_measurement(random_address(random), random_reading(random, units))) {
      return std::string(line->wire());
    }
  }
  switch (random.below(6)) {
    case 0:
      return "$OK\r";
    case 1:
      return "#ZMM,1\r";
    case 2:
      return "$bm,12.345\r";
    case 3:
      return "$BM,,1\r";
    case 4: {  // random field text
      std::string line = random.one_in(2) ? "$BM" : "$ER";
      const std::uint32_t fields = random.below(10);
      for (std::uint32_t i = 0; i < fields; ++i) {
        line += ',';
        const std::uint32_t length = random.below(10);
        for (std::uint32_t k = 0; k < length; ++k) line += "0123456789.-"[random.below(12)];
      }
      return line + "\r";
    }
    default:
      return "\r\n";
  }
}

std::string describe(const Error& error) { return std::string(errc_name(error.code)) + " " + error.message; }

std::string describe(const Address& address) {
  return address.addressed ? "#" + std::to_string(address.byte) : std::string("$");
}

std::string describe(const Range& range) {
  return exact(range.user) + "/" + exact(range.metres) + (range.units == Units::metres ? "m" : "ft");
}

std::string describe(const Reading& reading) {
  if (const auto* averaging = std::get_if<AveragingReading>(&reading)) {
    return "avg " + (averaging->range ? describe(*averaging->range) : std::string("-")) + " " +
           (averaging->pulse_width_ps ? std::to_string(*averaging->pulse_width_ps) : std::string("-"));
  }
  if (const auto* target = std::get_if<BinningTarget>(&reading)) {
    return "bin " + std::to_string(target->index) + "/" + std::to_string(target->count) + " " +
           describe(target->range) + " " + std::to_string(target->strength);
  }
  if (const auto* look_down = std::get_if<LookDownReading>(&reading)) return look_down->present ? "ld 1" : "ld 0";
  if (const auto* event = std::get_if<TimeBetweenEvents>(&reading)) {
    return "tbe " + std::to_string(static_cast<int>(event->kind)) + " " + std::to_string(event->pulses);
  }
  return "er " + std::to_string(std::get<MeasurementError>(reading).number);
}

std::string describe(const FrameView& view) {
  std::string text = view.kind == FrameKind::message ? "msg " : "tbe ";
  text += describe(view.address) + " " + std::string(view.mnemonic) + " [" + std::string(view.event_text) + "]";
  for (const auto field : view.fields()) text += " <" + escaped(field) + ">";
  return text;
}

constexpr std::array<MeasurementContext, 10> corpus_contexts{{
    {Mode::averaging, DisplayMode::range, Units::metres, false},
    {Mode::averaging, DisplayMode::range, Units::feet, false},
    {Mode::averaging, DisplayMode::range_and_intensity, Units::metres, false},
    {Mode::averaging, DisplayMode::range_and_intensity, Units::feet, false},
    {Mode::averaging, DisplayMode::intensity, Units::metres, false},
    {Mode::binning, DisplayMode::range, Units::metres, false},
    {Mode::binning, DisplayMode::range, Units::feet, false},
    {Mode::look_down, DisplayMode::range, Units::metres, false},
    {Mode::look_down, DisplayMode::range, Units::metres, true},
    {Mode::averaging, static_cast<DisplayMode>(7), Units::metres, false},
}};

// U11, U27, U32 and the framer rules F1-F5, all at once: the whole output for the corpus.
TEST(UlsDecoderCorpus, OutputsMatchTheRecordedOnes) {
  Random random(17);
  const std::string stream = testing::corpus::corpus_stream(random, corpus_lines, random_line);

  Digest framing("uls_framing");
  Digest parsing("uls_parse_frame");
  Digest decoding("uls_decode_measurement");
  testing::corpus::frame_in_chunks(stream, &scan_frame, random, framing, [&](Bytes frame) {
    const Result<FrameView> view = parse_frame(frame);
    parsing.add(view ? describe(*view) : describe(view.error()));
    for (const auto& context : corpus_contexts) {
      const Result<Measurement> measurement = decode_measurement(frame, context);
      decoding.add(measurement ? describe(measurement->source) + " " + describe(measurement->reading)
                               : describe(measurement.error()));
    }
  });

  // Recorded with the unoptimised decoders of commit 3310b0b; decoding's digest with DM 2's
  // errors naming the display as the setting does ("display range-and-intensity").
  EXPECT_EQ(framing.lines(), 59106U);
  EXPECT_EQ(framing.hex(), "5490866f205fcd97");
  EXPECT_EQ(parsing.lines(), 52552U);
  EXPECT_EQ(parsing.hex(), "f1856e56d76ab289");
  EXPECT_EQ(decoding.lines(), 525520U);
  EXPECT_EQ(decoding.hex(), "d173c658a049ce43");
}

// A stream reader's path: decode_measurements reads good averaging lines
// ("$BM,<range>[,<pulse width>]", §9; U8, U9, U27) straight from the framer's buffer and
// hands every other frame out to be decoded as before. Under each context it must give
// the same frames, rejections and measurements, in the same order, as next() and
// decode_measurement(frame, context) on every frame, over the same reads.
TEST(UlsDecoderCorpus, DecodeMeasurementsMatchesNextAndDecodeMeasurement) {
  Random corpus_random(17);
  const std::string stream = testing::corpus::corpus_stream(corpus_random, corpus_lines, random_line);
  std::size_t direct = 0;
  for (const auto& context : corpus_contexts) {
    auto describe_decoded = [](const Result<Measurement>& measurement) {
      return measurement ? describe(measurement->source) + " " + describe(measurement->reading)
                         : describe(measurement.error());
    };
    Random expected_random(1017);
    Digest expected("uls_next_decode_measurement");
    testing::corpus::frame_in_chunks(stream, &scan_frame, expected_random, expected, [&](Bytes frame) {
      expected.add(describe_decoded(decode_measurement(frame, context)));
    });

    Random random(1017);
    Digest got("uls_next_decode_measurement");
    auto on_measurement = [&](Bytes frame, const Measurement& measurement) {
      testing::corpus::add_frame(got, frame);
      got.add(describe_decoded(measurement));
      ++direct;
    };
    auto on_frame = [&](Bytes frame) {
      testing::corpus::add_frame(got, frame);
      got.add(describe_decoded(decode_measurement(frame, context)));
    };
    auto on_rejected = [&](const FrameAssembler::Event& event) { testing::corpus::add_rejection(got, event); };
    testing::corpus::feed_in_chunks(stream, &scan_frame, random, [&](FrameAssembler& assembler) {
      decode_measurements(assembler, context, on_measurement, on_frame, on_rejected);
    });

    EXPECT_EQ(got.lines(), expected.lines())
        << "context " << static_cast<int>(context.mode) << "/" << static_cast<int>(context.display);
    EXPECT_EQ(got.hex(), expected.hex()) << "context " << static_cast<int>(context.mode) << "/"
                                         << static_cast<int>(context.display);
  }
  EXPECT_GT(direct, 15000U);  // many averaging lines took the direct path
}

}  // namespace
}  // namespace rangekit::uls
