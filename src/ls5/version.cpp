#include "rangekit/ls5/version.hpp"

#include "ls5/messages.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::ls5 {
namespace {

enum class VersionProblem { none, prefix, shape, major, minor };

VersionProblem parse_into(std::string_view text, FirmwareVersion& version) noexcept {
  constexpr std::string_view prefix = "LS5.";
  if (text.substr(0, prefix.size()) != prefix) return VersionProblem::prefix;
  const std::string_view rest = text.substr(prefix.size());
  const std::size_t dot = rest.find('.');
  if (dot == std::string_view::npos) return VersionProblem::shape;
  const auto major = text::parse_unsigned(rest.substr(0, dot), 3, 999);
  if (!major) return VersionProblem::major;
  version = FirmwareVersion{static_cast<std::uint16_t>(*major), 0, false};
  const std::string_view minor_text = rest.substr(dot + 1);
  if (minor_text == "x" || minor_text == "X") {
    version.any_minor = true;
    return VersionProblem::none;
  }
  const auto minor = text::parse_unsigned(minor_text, 3, 999);
  if (!minor) return VersionProblem::minor;
  version.minor = static_cast<std::uint16_t>(*minor);
  return VersionProblem::none;
}

}  // namespace

std::string FirmwareVersion::to_string() const {
  return "LS5." + std::to_string(major) + "." + (any_minor ? std::string("x") : std::to_string(minor));
}

std::optional<FirmwareVersion> try_parse_firmware_version(std::string_view text) noexcept {
  FirmwareVersion version;
  if (parse_into(text, version) != VersionProblem::none) return std::nullopt;
  return version;
}

Result<FirmwareVersion> parse_firmware_version(std::string_view text) {
  FirmwareVersion version;
  const char* why = nullptr;
  switch (parse_into(text, version)) {
    case VersionProblem::none:
      return version;
    case VersionProblem::prefix:
      why = "does not start with \"LS5.\"";
      break;
    case VersionProblem::shape:
      why = "expected LS5.<major>.<minor>";
      break;
    case VersionProblem::major:
      why = "the major version is not a 1-3 digit number";
      break;
    case VersionProblem::minor:
      why = "the minor version is not a 1-3 digit number or 'x'";
      break;
  }
  return make_error(Errc::bad_number, "LS5 firmware version " + detail::quote(text) + ": " + why);
}

}  // namespace rangekit::ls5
