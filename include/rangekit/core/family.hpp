// A sensor family as generic code sees it: its name, its channels and how a sample of it
// reads. Each family fills one descriptor in its own folder; the registration list adds it
// here at start-up, and faces look it up by a sample's `device`.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "rangekit/core/channel.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/sample_writer.hpp"

namespace rangekit {

// How exact a family's distance is where a sample was read: what the quality checks allow.
struct DistanceScale {
  double accuracy_m = 0;     // the stated accuracy
  double resolution_m = 0;   // one step of the sensor
  double max_speed_mps = 0;  // the fastest a real target moves along the beam, unless configured
};

// What the quality checks judge a sample on (core/sample_quality.hpp, core/spike_check.hpp).
struct QualityInput {
  std::optional<double> distance_m;
  // None when this sample does not show it (an LS5 code 0): the stream's last one holds.
  std::optional<DistanceScale> scale;
  // The returned pulse's width in picoseconds, judged by its ratio to the recent ones.
  std::optional<double> pulse_width_ps;
};

// A kind of sample of a family (a ULS binning burst, an LS5 derivative): its name in JSON,
// CSV and captures, and the channels its line shows, in order.
struct KindDescriptor {
  std::string_view name;  // "binning"
  std::span<const std::uint8_t> channels;
  std::string_view former_name = {};  // how captures of older versions spell it

  // Whether its line shows the channel of this index.
  [[nodiscard]] constexpr bool shows(std::size_t channel) const noexcept {
    for (const std::uint8_t shown : channels) {
      if (shown == channel) return true;
    }
    return false;
  }
};

struct FamilyDescriptor {
  std::string_view name;   // the `device` of its samples, its CLI subcommand: "uls"
  std::string_view title;  // "LTI Universal Laser Sensor"
  // At most ChannelValues::capacity; a sample's ChannelKey is an index here.
  std::span<const ChannelDescriptor> channels;
  // A sample's SampleKind is an index here.
  std::span<const KindDescriptor> kinds;
  // The one number a sample reports (channel.hpp), none when it has no value: a gap.
  std::optional<Reading> (*reading)(const Sample& sample) = nullptr;
  // The quality checks' view of a sample; none when its kind is not judged (targets that come
  // and go, edges, errors).
  std::optional<QualityInput> (*quality)(const Sample& sample) = nullptr;
  // A writer of the family's own capture file (the ULS Interface Program's .log), none when
  // it has no such layout: a capture downloads as it with ?format=log.
  std::unique_ptr<SampleWriter> (*program_log)() = nullptr;
  // The sensor's own words for its error number, or "" when it has none.
  std::string (*error_text)(int number) = nullptr;
  // A unit address as the family's documents and site file write it ("A", "0x9C"); none: in
  // decimal, as every other number. Whatever a person reads spells an address this way.
  std::string (*address_text)(int address) = nullptr;
  // The words of a sample in the stream's text form, after its time, family and address
  // ("  1.234 m  pw 12.000 ns"); none: its kind's channels as key=value.
  void (*append_text)(std::string& out, const Sample& sample) = nullptr;
  // Completes a sample read from a capture an older version wrote (a value it kept another
  // way); none when there is nothing to complete.
  void (*read_back)(Sample& sample) = nullptr;
};

// Adds a family; a second one of the same name replaces the first. Called from the
// registration list before any thread reads the registry.
void register_family(const FamilyDescriptor& family);
// The registered families, in registration order.
std::span<const FamilyDescriptor* const> families() noexcept;
const FamilyDescriptor* find_family(std::string_view name) noexcept;
// A channel of a family by its key.
const ChannelDescriptor* find_channel(const FamilyDescriptor& family, std::string_view key) noexcept;
// The index of a family's channel (its ChannelKey's) by its key.
std::optional<std::size_t> channel_index(const FamilyDescriptor& family, std::string_view key) noexcept;
// The index of a family's first channel of `quantity` (its distance, its error number).
std::optional<std::size_t> channel_index(const FamilyDescriptor& family, Quantity quantity) noexcept;

// The decimals a number channel is written with in this sample: its step's when the sample
// has one (an LS5's discreteness, at most 6), the channel's own otherwise.
int channel_decimals(const ChannelDescriptor& channel, const Sample& sample) noexcept;

// The family of a sample; none for a family not registered.
const FamilyDescriptor* family_of(const Sample& sample) noexcept;
// The sample's kind as its family describes it; none for a family not registered or a kind it has not.
const KindDescriptor* kind_of(const Sample& sample) noexcept;
// The same, for a caller that has the sample's family at hand.
const KindDescriptor* kind_of(const FamilyDescriptor* family, const Sample& sample) noexcept;
// The kind's name, "unknown" when kind_of has none.
std::string_view kind_name_of(const Sample& sample) noexcept;
std::string_view kind_name_of(const KindDescriptor* kind) noexcept;
// A kind of the family by its name or former name.
std::optional<SampleKind> find_kind(const FamilyDescriptor& family, std::string_view name) noexcept;
// The value of the sample's first channel of `quantity` (its error number, its signal state).
std::optional<double> value_of(const Sample& sample, Quantity quantity) noexcept;
// Whether the sample says its sensor sees no target: its signal channel in its last state (an
// LS5 65535, not 65534's "no measurement yet").
bool signal_lost(const Sample& sample) noexcept;

// The sample's reading as its family defines it; none for a family not registered.
std::optional<Reading> reading_of(const Sample& sample);
// The sample as its family's quality checks see it; none for a kind not judged or a family not registered.
std::optional<QualityInput> quality_input_of(const Sample& sample);
// The family's words for an error number of its, "" when it has none.
std::string error_text_of(std::string_view family, int number);
std::string error_text_of(const Sample& sample, int number);
// The family's spelling of a unit address; decimal for a family not registered.
std::string address_text_of(std::string_view family, int address);

}  // namespace rangekit
