// `rangekit tap compare`: a recording's exchanges (each host frame and the sensor frames that
// followed it) and how an emulator's answers differ from them, field by field. Values a
// physical target makes (a distance) are compared by shape only; everything else (frame
// shape, error numbers, settings read back) exactly, and the first reply's delay within a
// tolerance.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "rangekit/record/pcapng.hpp"

namespace rangekit::cli {

struct TimedFrame {
  std::chrono::microseconds after{0};  // from its request
  std::string bytes;                   // without the terminator, as the framer hands it out
};

struct Exchange {
  std::string request_wire;  // the host's bytes as sent, terminator included
  std::string request;       // the frame, as the framer hands it out
  std::vector<TimedFrame> answer;
};

// The recording's exchanges, in order; sensor frames before the first request are left out.
std::vector<Exchange> exchanges_of(const record::SerialRecording& recording, const FrameDecoder& host,
                                   const FrameDecoder& sensor);

// Frames compared per exchange, at most: beyond them an answer is a stream, whose length
// depends on how long one waits.
inline constexpr std::size_t compared_frames = 5;

// Each difference between a recorded answer and the emulator's to the same request, as a
// line; none when they agree.
std::vector<std::string> differences(const Exchange& recorded, const std::vector<TimedFrame>& emulated,
                                     const FrameDecoder& sensor);

}  // namespace rangekit::cli
