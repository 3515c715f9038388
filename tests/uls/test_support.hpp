// Helpers shared by the ULS tests.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "rangekit/uls/uls.hpp"

namespace rangekit::uls::testing {

// Parses a frame written in a test (no CR); fails the test with the codec's message.
inline FrameView must_parse(std::string_view frame) {
  Result<FrameView> parsed = parse_frame(frame);
  EXPECT_TRUE(parsed.ok()) << frame << ": " << (parsed.ok() ? "" : parsed.error().describe());
  return parsed.ok() ? *parsed : FrameView{};
}

inline std::string fields_joined(const FrameView& view) {
  std::string joined;
  for (const std::string_view field : view.fields()) {
    if (!joined.empty()) joined += '|';
    joined += field;
  }
  return joined;
}

// Wire text of an encoder's result, or "<error: ...>".
inline std::string wire_of(const Result<FrameText>& encoded) {
  if (!encoded) return "<error: " + encoded.error().describe() + ">";
  return std::string(encoded->wire());
}

inline std::string describe(const Error& error) { return error.describe(); }

}  // namespace rangekit::uls::testing
