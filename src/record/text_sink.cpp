#include "rangekit/record/text_sink.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "rangekit/core/fd_transport.hpp"
#include "rangekit/record/format.hpp"

namespace rangekit::record {
namespace {

constexpr std::size_t flush_threshold = std::size_t{64} * 1024;

class TextSink final : public SampleSink {
 public:
  TextSink(OutputFormat format, int fd, bool owns_fd, std::string name)
      : format_(format), fd_(fd), owns_fd_(owns_fd), name_(std::move(name)) {
    if (format_ == OutputFormat::csv) buffer_ += csv_header();
  }
  ~TextSink() override {
    (void)flush();
    if (owns_fd_) ::close(fd_);
  }

  Status write(const Sample& sample) override {
    if (failed_) return failure();
    switch (format_) {
      case OutputFormat::jsonl:
        append_jsonl(buffer_, sample);
        break;
      case OutputFormat::csv:
        append_csv(buffer_, sample);
        break;
      case OutputFormat::text:
        append_text(buffer_, sample);
        break;
    }
    if (buffer_.size() >= flush_threshold) return flush();
    return ok_status();
  }

  // Only JSON lines carry events in the data: a CSV row has no place for them,
  // and readable text shows them on stderr (run_stream) instead.
  Status write_event(const StreamEvent& event) override {
    if (failed_) return failure();
    if (format_ == OutputFormat::jsonl) append_jsonl(buffer_, event);
    if (buffer_.size() >= flush_threshold) return flush();
    return ok_status();
  }

  Status flush() override {
    if (failed_) return failure();
    std::size_t written = 0;
    while (written < buffer_.size()) {
      const auto result = ::write(fd_, buffer_.data() + written, buffer_.size() - written);
      if (result < 0) {
        if (errno == EINTR) continue;
        failed_ = true;
        reason_ = errno_text("cannot write " + name_, errno);
        buffer_.erase(0, written);
        return failure();
      }
      written += static_cast<std::size_t>(result);
    }
    buffer_.clear();
    return ok_status();
  }

 private:
  [[nodiscard]] Error failure() const { return make_error(Errc::io, reason_); }

  OutputFormat format_;
  int fd_;
  bool owns_fd_;
  std::string name_;
  std::string buffer_;
  bool failed_ = false;
  std::string reason_;  // "cannot write NAME: <system message>"
};

}  // namespace

SampleSinkPtr make_text_sink(OutputFormat format, int fd, std::string name) {
  return std::make_unique<TextSink>(format, fd, false, std::move(name));
}

Result<SampleSinkPtr> open_text_sink(OutputFormat format, const std::string& path) {
  if (path.empty() || path == "-") return make_text_sink(format, STDOUT_FILENO, "standard output");
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return make_error(Errc::io, errno_text("cannot open " + path + " for writing", errno));
  return SampleSinkPtr(std::make_unique<TextSink>(format, fd, true, path));
}

}  // namespace rangekit::record
