#include "cli/cli_family.hpp"

#include <array>

#include "rangekit/core/registry.hpp"

namespace rangekit::cli {
namespace {

Registry<CliFamily>& registry() {
  static Registry<CliFamily> families;
  return families;
}

template <class Field>
std::string joined(std::string_view separator, Field field) {
  std::string text;
  for (const CliFamily* family : cli_families()) {
    if (!text.empty()) text += separator;
    text += family->*field;
  }
  return text;
}

}  // namespace

void register_cli_family(const CliFamily& family) { registry().add(family); }

DecoderFactory default_decoders(const CliFamily& family) {
  CLI::App scratch;
  DecoderFactory factory = family.add_decode_options(scratch);
  scratch.parse(std::vector<std::string>{});  // every option at its default
  return factory;
}
FrameDecoder default_decoder(const CliFamily& family, Direction sender) { return default_decoders(family)(sender); }
std::span<const CliFamily* const> cli_families() noexcept { return registry().all(); }
const CliFamily* find_cli_family(std::string_view name) noexcept { return registry().find(name); }

std::string cli_family_names(std::string_view separator) { return joined(separator, &CliFamily::name); }
std::string cli_family_labels(std::string_view separator) { return joined(separator, &CliFamily::label); }

std::vector<std::string> cli_family_name_list() {
  std::vector<std::string> names;
  for (const CliFamily* family : cli_families()) names.emplace_back(family->name);
  return names;
}

std::string_view both_or_all() { return cli_families().size() == 2 ? "both" : "all"; }

std::string count_in_words(std::size_t count) {
  static constexpr std::array<const char*, 10> words{"no",   "one", "two",   "three", "four",
                                                     "five", "six", "seven", "eight", "nine"};
  return count < words.size() ? words[count] : std::to_string(count);
}

}  // namespace rangekit::cli
