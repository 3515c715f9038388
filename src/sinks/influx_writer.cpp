#include "sinks/influx_writer.hpp"

#include "sinks/http_post.hpp"

namespace rangekit::sinks {
namespace {

class InfluxWriter final : public Writer {
 public:
  InfluxWriter(hub::HttpUrl url, std::chrono::milliseconds timeout) : url_(std::move(url)), timeout_(timeout) {}

  WriteOutcome write(const std::vector<record::SpoolRow>& rows) override {
    std::string body;
    for (const record::SpoolRow& row : rows) body += row.line;
    auto answer = http_post(url_, "text/plain; charset=utf-8", body, timeout_);
    if (!answer) return {WriteOutcome::Kind::failed, answer.error().message};
    if (answer->status == 204 || answer->status == 200) return {WriteOutcome::Kind::confirmed, ""};
    // A 400 names lines the historian will never take: kept, they would block every row behind them.
    if (answer->status == 400) {
      return {WriteOutcome::Kind::refused, "HTTP 400: " + answer->body.substr(0, 200)};
    }
    return {WriteOutcome::Kind::failed, "HTTP " + std::to_string(answer->status)};
  }

 private:
  hub::HttpUrl url_;
  std::chrono::milliseconds timeout_;
};

}  // namespace

Result<std::unique_ptr<Writer>> open_influx_writer(const SinkOptions& options) {
  auto url = hub::parse_http_url(options.config.url);
  if (!url) return std::move(url).error();
  return std::unique_ptr<Writer>(std::make_unique<InfluxWriter>(std::move(*url), options.timeout));
}

}  // namespace rangekit::sinks
