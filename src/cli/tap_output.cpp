#include "cli/tap_output.hpp"

#include <fmt/core.h>

namespace rangekit::cli {

TapOutput::TapOutput(TapOutputSettings settings, std::ostream* recording, const CliFamily* family,
                     DecoderFactory decoder_of, std::function<void(const std::string&)> note)
    : settings_(std::move(settings)), recording_(recording), note_(std::move(note)) {
  if (family != nullptr) {
    std::vector<std::string> none;
    decided(*family, std::move(decoder_of), none);
  } else {
    guess_.emplace(cli_families());
  }
}

void TapOutput::start_recording(const CliFamily* family) {
  if (recording_ == nullptr || recording_started_) return;
  recording_started_ = true;
  std::vector<std::string> comments;
  if (family != nullptr) comments.push_back("family " + std::string(family->name));
  comments.insert(comments.end(), settings_.comments.begin(), settings_.comments.end());
  *recording_ << record::pcapng_section_header(comments, "rangekit tap");
  *recording_ << record::pcapng_serial_interface(settings_.interface_name);
}

void TapOutput::record(const record::SerialChunk& chunk) {
  if (recording_ != nullptr) *recording_ << record::pcapng_serial_packet(chunk);
}

void TapOutput::decided(const CliFamily& family, DecoderFactory decoder_of, std::vector<std::string>& out) {
  family_ = &family;
  guess_.reset();
  if (!decoder_of) decoder_of = default_decoders(family);
  report_.emplace(decoder_of(Direction::to_device), decoder_of(Direction::from_device), settings_.format,
                  settings_.every, settings_.colour);
  start_recording(&family);
  for (const record::SerialChunk& chunk : pending_) {
    record(chunk);
    auto lines = report_->add(chunk);
    out.insert(out.end(), std::make_move_iterator(lines.begin()), std::make_move_iterator(lines.end()));
  }
  pending_.clear();
  pending_bytes_ = 0;
}

std::vector<std::string> TapOutput::add(const record::SerialChunk& chunk) {
  if (report_) {
    record(chunk);
    return report_->add(chunk);
  }
  std::vector<std::string> out;
  const CliFamily* found = guess_->add(chunk);
  if (waited_too_long_) {
    record(chunk);  // past the limit: the recording goes on without waiting
  } else {
    pending_bytes_ += chunk.bytes.size();
    pending_.push_back(chunk);
  }
  if (found != nullptr) {
    note_(fmt::format("the traffic is {}", found->label));
    decided(*found, nullptr, out);
  } else if (!waited_too_long_ && pending_bytes_ > pending_limit) {
    waited_too_long_ = true;
    note_(
        fmt::format("no family told apart in the first {} bytes ({}); forwarding and recording them "
                    "undecoded, still listening (--family names it)",
                    pending_bytes_, guess_->summary()));
    start_recording(nullptr);
    for (const record::SerialChunk& waiting : pending_) record(waiting);
    pending_.clear();
    pending_bytes_ = 0;
  }
  return out;
}

std::vector<std::string> TapOutput::finish() {
  if (report_) return report_->finish();
  note_(fmt::format("the family was not told from the traffic ({}); give --family {}", guess_->summary(),
                    cli_family_names("|")));
  start_recording(nullptr);
  for (const record::SerialChunk& waiting : pending_) record(waiting);
  pending_.clear();
  return {};
}

}  // namespace rangekit::cli
