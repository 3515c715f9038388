// Pieces the service and MQTT benches share: CPU and memory of a process
// from /proc, and a pty relay between an emulator and the program under test that
// notes when each LS5 record's last byte was written, for latencies.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace rangekit::bench {

using RelayClock = std::chrono::steady_clock;

// utime + stime of a process, in seconds.
inline double cpu_seconds(pid_t pid) {
  std::ifstream file("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return 0;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  unsigned long long utime = 0;
  unsigned long long stime = 0;
  // Fields 3.. after the name; utime is field 14, stime 15 (proc(5)).
  for (int number = 3; number <= 15 && fields >> field; ++number) {
    if (number == 14) utime = std::stoull(field);
    if (number == 15) stime = std::stoull(field);
  }
  return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// A "VmRSS:"/"VmHWM:" line of /proc/PID/status, in MB.
inline double status_mb(pid_t pid, const std::string& key) {
  std::ifstream file("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(file, line)) {
    if (line.rfind(key, 0) == 0) return std::stod(line.substr(key.size())) / 1024.0;
  }
  return 0;
}

inline void make_raw(int fd, speed_t speed) {
  termios settings{};
  ::tcgetattr(fd, &settings);
  ::cfmakeraw(&settings);
  ::cfsetispeed(&settings, speed);
  ::cfsetospeed(&settings, speed);
  ::tcsetattr(fd, TCSANOW, &settings);
}

// A pty between an emulator and the service: bytes pass both ways unchanged; each
// `!ddddd\r` record from the emulator is noted with the time its last byte was written.
class Relay {
 public:
  struct Record {
    int code = 0;
    RelayClock::time_point written;
  };
  static std::unique_ptr<Relay> start(const std::string& emulator_path, std::string& error) {
    auto relay = std::unique_ptr<Relay>(new Relay());
    relay->device_ = ::open(emulator_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    relay->master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (relay->device_ < 0 || relay->master_ < 0 || ::grantpt(relay->master_) != 0 || ::unlockpt(relay->master_) != 0) {
      error = "relay: cannot open " + emulator_path + " or a pty";
      return nullptr;
    }
    relay->slave_path_ = ::ptsname(relay->master_);
    // Held open so the master never reads EIO between the service's opens; raw, no echo.
    relay->slave_ = ::open(relay->slave_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    make_raw(relay->device_, B115200);
    make_raw(relay->slave_, B115200);
    relay->thread_ = std::thread([raw = relay.get()] { raw->run(); });
    return relay;
  }
  ~Relay() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    for (const int fd : {device_, master_, slave_}) {
      if (fd >= 0) ::close(fd);
    }
  }
  [[nodiscard]] const std::string& path() const { return slave_path_; }
  std::vector<Record> records() {
    const std::lock_guard lock(mutex_);
    return records_;
  }

 private:
  Relay() = default;
  static bool write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
      const ssize_t n = ::write(fd, data, size);
      if (n <= 0) return false;
      data += n;
      size -= static_cast<std::size_t>(n);
    }
    return true;
  }
  void run() {
    std::array<char, 4096> buffer{};
    while (!stop_) {
      std::array<pollfd, 2> fds{pollfd{device_, POLLIN, 0}, pollfd{master_, POLLIN, 0}};
      if (::poll(fds.data(), fds.size(), 50) <= 0) continue;
      if ((fds[1].revents & POLLIN) != 0) {
        const ssize_t n = ::read(master_, buffer.data(), buffer.size());
        if (n > 0) write_all(device_, buffer.data(), static_cast<std::size_t>(n));
      }
      if ((fds[0].revents & POLLIN) != 0) {
        const ssize_t n = ::read(device_, buffer.data(), buffer.size());
        if (n <= 0) continue;
        write_all(master_, buffer.data(), static_cast<std::size_t>(n));
        const auto now = RelayClock::now();
        const std::lock_guard lock(mutex_);
        for (ssize_t i = 0; i < n; ++i) {
          const char c = buffer[static_cast<std::size_t>(i)];
          if (c == '!') {
            digits_ = 0;
            code_ = 0;
            in_record_ = true;
          } else if (in_record_ && c >= '0' && c <= '9' && digits_ < 5) {
            code_ = code_ * 10 + (c - '0');
            ++digits_;
          } else if (in_record_ && c == '\r' && digits_ == 5) {
            records_.push_back({code_, now});
            in_record_ = false;
          } else {
            in_record_ = false;
          }
        }
      }
    }
  }
  int device_ = -1;
  int master_ = -1;
  int slave_ = -1;
  std::string slave_path_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<Record> records_;
  bool in_record_ = false;
  int digits_ = 0;
  int code_ = 0;
};

// The port of `rangekit serve`'s API from its "API on http://127.0.0.1:PORT" line; 0 when its
// output ended first. `Service` is a child process read line by line.
template <class Service>
std::uint16_t api_port_of(Service& service) {
  for (std::string line = service.read_line(); !line.empty(); line = service.read_line()) {
    const auto at = line.find("API on http://127.0.0.1:");
    if (at != std::string::npos) return static_cast<std::uint16_t>(std::stoi(line.substr(at + 24)));
  }
  return 0;
}

inline double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto index = static_cast<std::size_t>(p / 100.0 * static_cast<double>(values.size() - 1));
  return values[index];
}

}  // namespace rangekit::bench
