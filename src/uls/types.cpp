#include "rangekit/uls/types.hpp"

namespace rangekit::uls {

std::optional<Mode> to_mode(std::uint64_t number) noexcept {
  if (number < 1 || number > 3) return std::nullopt;
  return static_cast<Mode>(number);
}

std::optional<DisplayMode> to_display_mode(std::uint64_t number) noexcept {
  if (number < 1 || number > 3) return std::nullopt;
  return static_cast<DisplayMode>(number);
}

std::optional<Units> to_units(std::uint64_t number) noexcept {
  if (number > 1) return std::nullopt;
  return static_cast<Units>(number);
}

std::optional<PowerLevel> to_power_level(std::uint64_t number) noexcept {
  if (number > 2) return std::nullopt;
  return static_cast<PowerLevel>(number);
}

std::optional<OutputPort> to_output_port(std::uint64_t number) noexcept {
  if (number > 2) return std::nullopt;
  return static_cast<OutputPort>(number);
}

std::optional<BaudPort> to_baud_port(std::uint64_t number) noexcept {
  if (number > 1) return std::nullopt;
  return static_cast<BaudPort>(number);
}

std::optional<BinSize> to_bin_size(std::uint64_t number) noexcept {
  if (number > 8) return std::nullopt;
  return static_cast<BinSize>(number);
}

std::optional<UnitStatus> to_unit_status(std::uint64_t number) noexcept {
  switch (number) {
    case 0:
      return UnitStatus::error;
    case 1:
      return UnitStatus::ready;
    case 3:
      return UnitStatus::look_down;
    case 7:
      return UnitStatus::averaging;
    case 11:
      return UnitStatus::binning;
    default:
      return std::nullopt;
  }
}

std::optional<Mode> status_mode(UnitStatus status) noexcept {
  switch (status) {
    case UnitStatus::look_down:
      return Mode::look_down;
    case UnitStatus::averaging:
      return Mode::averaging;
    case UnitStatus::binning:
      return Mode::binning;
    case UnitStatus::error:
    case UnitStatus::ready:
      return std::nullopt;
  }
  return std::nullopt;
}

UnitStatus status_for(bool measuring, Mode mode) noexcept {
  if (!measuring) return UnitStatus::ready;
  switch (mode) {
    case Mode::averaging:
      return UnitStatus::averaging;
    case Mode::binning:
      return UnitStatus::binning;
    case Mode::look_down:
      return UnitStatus::look_down;
  }
  return UnitStatus::ready;
}

}  // namespace rangekit::uls
