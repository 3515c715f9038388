// A real VictoriaMetrics (Debian's victoria-metrics) on a free loopback port with its storage
// in a temp folder, for the sinks' end-to-end tests; it can be stopped and started again on
// the same port and storage, as an outage of the historian.
#pragma once

#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "ls5_driver/cli_process.hpp"
#include "sinks/http_post.hpp"

namespace sinks_test {

// A port no one listens on now: bound to 0, read back, closed.
inline std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t size = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  ::close(fd);
  return ntohs(address.sin_port);
}

struct VictoriaMetrics {
  ls5_driver_test::TempDir dir;
  std::uint16_t port = free_port();
  pid_t pid = -1;

  VictoriaMetrics() { start(); }
  ~VictoriaMetrics() { stop(); }
  VictoriaMetrics(const VictoriaMetrics&) = delete;
  VictoriaMetrics& operator=(const VictoriaMetrics&) = delete;

  [[nodiscard]] std::string write_url() const { return "http://127.0.0.1:" + std::to_string(port) + "/write"; }

  rangekit::Result<rangekit::sinks::HttpAnswer> post(const std::string& path, std::size_t max_answer = 65536) const {
    return rangekit::sinks::http_post(rangekit::hub::HttpUrl{"127.0.0.1", port, path},
                                      "application/x-www-form-urlencoded", "", std::chrono::seconds(10), max_answer);
  }

  // Started and answering /health within 15 s.
  bool start() {
    pid = rangekit::test::fork_child();
    if (pid == 0) {
      const std::string log = (dir.path / "vm.log").string();
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      const std::string listen = "-httpListenAddr=127.0.0.1:" + std::to_string(port);
      const std::string storage = "-storageDataPath=" + (dir.path / "data").string();
      ::execlp("victoria-metrics", "victoria-metrics", listen.c_str(), storage.c_str(), nullptr);
      ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
    while (std::chrono::steady_clock::now() < deadline) {
      auto health = post("/health");
      if (health && health->status == 200) return true;
      if (rangekit::test::waited_within(pid, std::chrono::milliseconds(50))) return false;  // it ended
    }
    return false;
  }

  void stop() {
    if (pid > 0) rangekit::test::end_child(pid);
    pid = -1;
  }

  // Every value of rangekit_seq per sensor, flushed first; {} when the export fails.
  [[nodiscard]] std::map<std::string, std::multiset<std::uint64_t>> sequences() const {
    std::map<std::string, std::multiset<std::uint64_t>> found;
    if (auto flushed = post("/internal/force_flush"); !flushed || flushed->status != 200) return found;
    auto exported = post("/api/v1/export?match%5B%5D=rangekit_seq", std::size_t{1} << 30);
    if (!exported || exported->status != 200) return found;
    std::size_t from = 0;
    while (from < exported->body.size()) {
      auto end = exported->body.find('\n', from);
      if (end == std::string::npos) end = exported->body.size();
      const auto series = nlohmann::json::parse(exported->body.substr(from, end - from), nullptr, false);
      from = end + 1;
      if (series.is_discarded() || !series.contains("metric")) continue;
      auto& values = found[series["metric"].value("sensor", "")];
      for (const auto& value : series["values"]) values.insert(value.get<std::uint64_t>());
    }
    return found;
  }
};

// Each sensor's sequences are 1..N once each; the total of N, or -1 when they are not.
inline long long complete_total(const std::map<std::string, std::multiset<std::uint64_t>>& sequences,
                                std::string& problem) {
  long long total = 0;
  for (const auto& [sensor, values] : sequences) {
    std::uint64_t expected = 1;
    for (const std::uint64_t value : values) {
      if (value != expected) {
        problem = sensor + ": seq " + std::to_string(value) + " where " + std::to_string(expected) + " was due";
        return -1;
      }
      ++expected;
    }
    total += static_cast<long long>(values.size());
  }
  return total;
}

// The total of complete_total once it reaches `expected` or a sequence shows a gap or a
// repeat: rows flushed become searchable shortly after, so it is looked at until then, or 10 s.
inline long long settled_total(const VictoriaMetrics& vm, long long expected, std::string& problem) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (;;) {
    problem.clear();
    const long long total = complete_total(vm.sequences(), problem);
    if (total == expected || !problem.empty() || std::chrono::steady_clock::now() >= deadline) return total;
    ::poll(nullptr, 0, 100);  // between two exports, not a synchronisation
  }
}

}  // namespace sinks_test
