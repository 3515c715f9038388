// The ULS as generic code sees it: its kinds of sample, its channels and the reading of each.
#pragma once

#include <cstdint>

#include "rangekit/core/family.hpp"

namespace rangekit::uls {

const FamilyDescriptor& family() noexcept;

// The kinds of a ULS sample: the line of each measurement mode and a §10 error.
namespace kind {
inline constexpr SampleKind averaging{0};  // distance_m and/or pulse_width_ns
inline constexpr SampleKind binning{1};    // targets (one complete target array)
inline constexpr SampleKind look_down{2};  // presence and/or pulses_between_events (or pulses_overflow)
inline constexpr SampleKind error{3};      // error (e.g. $ER,4 target not found)
}  // namespace kind

// The channels of a ULS sample, by their JSON keys; the targets of a burst are Sample::targets.
namespace channel {
inline constexpr ChannelKey<double> distance_m{"uls", 0};
inline constexpr ChannelKey<double> pulse_width_ns{"uls", 1};
inline constexpr ChannelKey<std::uint32_t> pulse_width_ps{"uls", 1, 1000};  // the same, as on the wire (U8)
inline constexpr std::uint8_t targets = 2;
inline constexpr ChannelKey<bool> presence{"uls", 3};
inline constexpr ChannelKey<std::uint32_t> pulses_between_events{"uls", 4};
// `$0000`: more than 65535 pulses between the edges (§8 "signifying maximum time
// occurred"); pulses_between_events is then empty (U88).
inline constexpr ChannelKey<bool> pulses_overflow{"uls", 5};
inline constexpr ChannelKey<int> error{"uls", 6};  // the unit's error number ($ER,n)
}  // namespace channel

}  // namespace rangekit::uls
