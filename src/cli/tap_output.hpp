// Where `rangekit tap`'s chunks go on its main thread: the recording and the report. With the
// family given they go at once; otherwise they wait (bounded) while a FamilyGuess reads them,
// and are recorded and reported from the first once the traffic names the family.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "cli/family_guess.hpp"
#include "cli/tap_report.hpp"
#include "rangekit/record/pcapng.hpp"

namespace rangekit::cli {

struct TapOutputSettings {
  TapFormat format = TapFormat::text;
  std::uint64_t every = 100;
  bool colour = false;
  std::vector<std::string> comments;  // the recording's section comments besides "family X"
  std::string interface_name;         // the recording's one interface: "host <-> sensor"
};

class TapOutput {
 public:
  // Undecided chunks kept for the report and the recording; past this the recording starts
  // without a family and the guess goes on alone.
  static constexpr std::size_t pending_limit = 1 << 20;

  // `recording` may be null (no --out); `family` null means: tell it from the traffic.
  TapOutput(TapOutputSettings settings, std::ostream* recording, const CliFamily* family, DecoderFactory decoder_of,
            std::function<void(const std::string&)> note);
  // The lines the chunk completes.
  std::vector<std::string> add(const record::SerialChunk& chunk);
  std::vector<std::string> finish();
  [[nodiscard]] const CliFamily* family() const noexcept { return family_; }
  [[nodiscard]] const TapCounts* counts() const noexcept { return report_ ? &report_->counts() : nullptr; }

 private:
  void decided(const CliFamily& family, DecoderFactory decoder_of, std::vector<std::string>& out);
  void start_recording(const CliFamily* family);
  void record(const record::SerialChunk& chunk);

  TapOutputSettings settings_;
  std::ostream* recording_;
  bool recording_started_ = false;
  bool waited_too_long_ = false;  // past pending_limit undecided: chunks no longer wait
  const CliFamily* family_ = nullptr;
  std::optional<TapReport> report_;
  std::optional<FamilyGuess> guess_;
  std::vector<record::SerialChunk> pending_;
  std::size_t pending_bytes_ = 0;
  std::function<void(const std::string&)> note_;
};

}  // namespace rangekit::cli
