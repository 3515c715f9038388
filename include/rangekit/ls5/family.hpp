// The LS5 as generic code sees it: its kinds of sample, its channels and the reading of each.
#pragma once

#include <cstdint>
#include <optional>

#include "rangekit/core/family.hpp"

namespace rangekit::ls5 {

const FamilyDescriptor& family() noexcept;

// Result-code meaning (§9.3): a distance, 65534 no measurement yet, 65535 no signal.
enum class SignalState : std::uint8_t { ok, none_yet, lost };
const char* signal_state_name(SignalState state) noexcept;

// The kinds of an LS5 sample: the same record, its value's meaning differs (formula 8.1 or 8.2, L60).
namespace kind {
inline constexpr SampleKind result{0};      // code, distance_mm, signal
inline constexpr SampleKind derivative{1};  // code, derivative_mm, signal: «Type of preliminary result» 01 (§8.8/§8.9)
}  // namespace kind

// The channels of an LS5 sample, by their JSON keys.
namespace channel {
inline constexpr ChannelKey<std::uint16_t> code{"ls5", 0};
inline constexpr ChannelKey<double> distance_mm{"ls5", 1};  // formula 8.1; none on 65534/65535
inline constexpr ChannelKey<SignalState> signal{"ls5", 2};
inline constexpr ChannelKey<double> derivative_mm{"ls5", 3};  // formula 8.2; none on 65534/65535
// The sensor's discreteness (table 3.1): how many decimals its millimetres deserve.
inline constexpr ChannelKey<double> resolution_mm{"ls5", 4};
}  // namespace channel

// The sensor's range from a result: formula 8.1 (distance = code / 50000 × range) read
// backwards; none when the sample carries no distance or its code is 0.
std::optional<double> range_from_result_mm(const Sample& sample) noexcept;

}  // namespace rangekit::ls5
