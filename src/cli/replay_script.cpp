#include "cli/replay_script.hpp"

namespace rangekit::cli {

ReplayScript ReplayScript::from_recording(const record::SerialRecording& recording, ScanFunction host_scan) {
  ReplayScript script;
  FrameAssembler host(host_scan, 4096);
  Answer* current = &script.opening_;
  std::chrono::system_clock::time_point since =
      recording.chunks.empty() ? std::chrono::system_clock::time_point{} : recording.chunks.front().time;
  for (const record::SerialChunk& chunk : recording.chunks) {
    if (chunk.sender == record::Sender::sensor) {
      const auto after = std::chrono::duration_cast<std::chrono::microseconds>(chunk.time - since);
      current->push_back(TimedBytes{std::max(after, std::chrono::microseconds(0)), chunk.bytes});
      continue;
    }
    FrameAssembler::Event event;
    feed_all(host, as_bytes(chunk.bytes), [&] {
      while (host.next(event)) {
        if (event.kind != FrameAssembler::Event::Kind::frame) continue;
        ++script.requests_;
        current = &script.answers_[std::string(as_text(event.frame))].emplace_back();
        since = chunk.time;
      }
    });
  }
  return script;
}

const Answer* ReplayScript::answer(const std::string& request) {
  const auto found = answers_.find(request);
  if (found == answers_.end() || found->second.empty()) return nullptr;
  std::deque<Answer>& answers = found->second;
  if (answers.size() > 1) {
    // Each recorded answer once, in order (a setting read before and after a change).
    last_ = std::move(answers.front());
    answers.pop_front();
    return &last_;
  }
  return &answers.front();
}

}  // namespace rangekit::cli
