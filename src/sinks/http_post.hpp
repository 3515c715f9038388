// A plain blocking HTTP/1.1 POST over one TCP connection per request, with one deadline for
// the whole exchange: all a line-protocol write needs, on the sink's own thread.
#pragma once

#include <chrono>
#include <string>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/hub/site_config.hpp"

namespace rangekit::sinks {

struct HttpAnswer {
  int status = 0;    // 204, 400, 503 ...
  std::string body;  // up to max_answer bytes of it
};

// Sends `body` to the URL and reads the answer's status line, headers and body. A connection
// refused, reset or past the deadline is Errc::io or Errc::timeout; any status is a value.
Result<HttpAnswer> http_post(const hub::HttpUrl& url, std::string_view content_type, std::string_view body,
                             std::chrono::milliseconds timeout, std::size_t max_answer = 65536);

// Whether the bytes read so far are the whole answer: its head and Content-Length's body, or
// max_answer bytes (a longer body is cut there).
bool answer_complete(std::string_view answer, std::size_t max_answer);
// The status and body of a whole answer; Errc::invalid_frame for bytes that are no HTTP answer.
Result<HttpAnswer> parse_http_answer(std::string_view answer);

}  // namespace rangekit::sinks
