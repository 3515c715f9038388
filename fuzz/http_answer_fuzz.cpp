// What a historian (or anything listening at a sink's URL) answers a line-protocol write: the
// bytes as they arrive, cut anywhere, through the check for a whole answer and the parse of
// its status. Nothing the far end sends may crash the sink or be taken for more than it is.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "sinks/http_post.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view answer(reinterpret_cast<const char*>(data), size);
  constexpr std::size_t max_answer = 512;
  for (std::size_t cut = 0; cut <= answer.size(); cut += 1 + cut / 4) {
    (void)rangekit::sinks::answer_complete(answer.substr(0, cut), max_answer);
  }
  const auto parsed = rangekit::sinks::parse_http_answer(answer);
  if (parsed && (parsed->status < 0 || parsed->status > 999 || parsed->body.size() > answer.size())) std::abort();
  return 0;
}
