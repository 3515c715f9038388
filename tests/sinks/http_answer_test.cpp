// What a historian answers a write, as the sink reads it: whole or not yet, its status, and
// bytes that are no HTTP answer refused rather than taken for a status.
#include <gtest/gtest.h>

#include "sinks/http_post.hpp"

namespace {

using rangekit::sinks::answer_complete;
using rangekit::sinks::parse_http_answer;

TEST(HttpAnswer, AWholeAnswerIsItsHeadAndContentLengthsBody) {
  const std::string no_content = "HTTP/1.1 204 No Content\r\nX-Influxdb-Version: 1.8\r\n\r\n";
  EXPECT_FALSE(answer_complete(no_content, 65536));  // no Content-Length: until the connection closes
  const std::string refused =
      "HTTP/1.1 400 Bad Request\r\nContent-Length: 32\r\n\r\n{\"error\":\"unable to parse line\"}";
  EXPECT_TRUE(answer_complete(refused, 65536));
  EXPECT_FALSE(answer_complete(refused.substr(0, refused.size() - 1), 65536));
  EXPECT_TRUE(answer_complete(refused.substr(0, 20), 20));  // at max_answer bytes it is cut there
  const auto parsed = parse_http_answer(refused);
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed->status, 400);
  EXPECT_EQ(parsed->body, "{\"error\":\"unable to parse line\"}");
  EXPECT_EQ(parse_http_answer(no_content)->status, 204);
}

TEST(HttpAnswer, BytesThatAreNoStatusLineAreRefused) {
  for (const char* text : {"", "HTTP/1.1", "HTTP/1.1 -12 Odd\r\n\r\n", "HTTP/1.1 +20 Odd\r\n\r\n",
                           "HTTP/1.1 2O4 Odd\r\n\r\n", "SSH-2.0-OpenSSH_9.2\r\n", "HTTP/2 204\r\n\r\n"}) {
    EXPECT_FALSE(parse_http_answer(text).ok()) << text;
  }
}

}  // namespace
