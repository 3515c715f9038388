#include "host_stream_rig.hpp"
#include "build_paths.hpp"
#include "rangekit/core/fd_transport.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>
#include <utility>

namespace rangekit::bench {
namespace {

// Waits for the child to exit for up to `limit` (waitpid has no timeout: a
// short poll on nothing between checks); true when it has.
bool reap_within(pid_t pid, std::chrono::milliseconds limit, rusage* usage = nullptr) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (true) {
    int status = 0;
    const pid_t done = ::wait4(pid, &status, WNOHANG, usage);
    if (done == pid || (done < 0 && errno == ECHILD)) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    ::poll(nullptr, 0, 10);
  }
}

void stop_child(pid_t pid, rusage* usage = nullptr) {
  if (pid <= 0) return;
  ::kill(pid, SIGTERM);
  if (!reap_within(pid, std::chrono::seconds(2), usage)) {
    ::kill(pid, SIGKILL);
    reap_within(pid, std::chrono::seconds(2), usage);
  }
}

double seconds(const timeval& t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6; }

}  // namespace

ScratchDir::ScratchDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "rangekit-host-stream-XXXXXX").string();
  if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
}

Result<cli::SimProcess> start_emulator(const std::vector<std::string>& arguments, const std::string& log_path,
                                       std::chrono::milliseconds timeout) {
  return cli::SimProcess::start(arguments, log_path, timeout, rangekit::test::cli_path());
}

Result<cli::SimProcess> start_ls5_at_1khz(const std::string& port, int serial, const std::string& log_path) {
  auto started =
      start_emulator({"ls5", "--port", port, "--serial", std::to_string(serial)}, log_path, std::chrono::seconds(10));
  if (!started) return std::move(started).error();
  auto link = SerialPort::open(port, SerialSettings{115200});
  if (!link) return std::move(link).error();
  ls5::Driver driver(std::move(link).value(), ls5::DriverOptions{});
  for (const auto& [name, value] : {std::pair{"period-ms", "1"}, std::pair{"thinning", "1"}}) {
    if (auto done = driver.set(name, value); !done) {
      return make_error(done.error().code, std::string(name) + ": " + done.error().describe());
    }
  }
  return started;
}

Result<cli::SimProcess> start_uls_bus(const std::string& port, const std::vector<std::uint8_t>& addresses,
                                      const std::string& log_path, const std::function<bool(uls::Driver&)>& configure) {
  std::vector<std::string> arguments{"uls", "--bus", port};
  for (const std::uint8_t address : addresses) {
    arguments.insert(arguments.end(), {"--address", std::string(1, static_cast<char>(address))});
  }
  auto started = start_emulator(arguments, log_path, std::chrono::seconds(10));
  if (!started) return std::move(started).error();
  auto link = SerialPort::open(port, SerialSettings{115200});
  if (!link) return std::move(link).error();
  uls::Driver driver(std::move(link).value());
  for (const std::uint8_t address : addresses) {
    if (!driver.set_address(address) || !driver.set_continuous(false) || (configure && !configure(driver))) {
      return make_error(Errc::io, "bus unit " + std::string(1, static_cast<char>(address)) + ": cannot be set up");
    }
  }
  return started;
}

Result<nlohmann::json> control(const std::string& socket_path, const nlohmann::json& request) {
  auto client = ControlClient::connect(socket_path);
  if (!client) return std::move(client).error();
  auto reply = client->request(request, 2000);
  if (!reply) return std::move(reply).error();
  if (reply->contains("error")) return make_error(Errc::io, "control: " + reply->at("error").dump());
  return reply;
}

Result<std::size_t> CountingTransport::read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) {
  auto got = inner_->read_some(out, timeout);
  if (got) bytes_->fetch_add(*got, std::memory_order_relaxed);
  return got;
}

double process_cpu_s() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

CatCopy::CatCopy(pid_t pid, int fd, std::filesystem::path out) : pid_(pid), fd_(fd), out_(std::move(out)) {}

Result<std::unique_ptr<CatCopy>> CatCopy::start(const std::string& tty_path, const std::filesystem::path& out) {
  const int fd = ::open(tty_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return make_error(Errc::io, errno_text("open " + tty_path, errno));
  termios settings{};
  if (::tcgetattr(fd, &settings) != 0) {
    ::close(fd);
    return make_error(Errc::io, errno_text("tcgetattr " + tty_path, errno));
  }
  settings.c_cc[VMIN] = 1;  // speed and raw mode stay as the host set them
  settings.c_cc[VTIME] = 0;
  ::tcsetattr(fd, TCSANOW, &settings);
  const int file = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (file < 0) {
    ::close(fd);
    return make_error(Errc::io, errno_text("cannot create " + out.string(), errno));
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd);
    ::close(file);
    return make_error(Errc::io, errno_text("fork", errno));
  }
  if (pid == 0) {
    ::dup2(fd, STDIN_FILENO);
    ::dup2(file, STDOUT_FILENO);
    ::execlp("cat", "cat", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(file);
  return std::unique_ptr<CatCopy>(new CatCopy(pid, fd, out));
}

CatCopy::~CatCopy() {
  stop_child(pid_);
  if (fd_ >= 0) ::close(fd_);
}

Status CatCopy::send(std::string_view text) {
  if (::write(fd_, text.data(), text.size()) != static_cast<ssize_t>(text.size())) {
    return make_error(Errc::io, errno_text("write to the pty", errno));
  }
  return ok_status();
}

std::uintmax_t CatCopy::file_bytes() const {
  std::error_code error;
  const auto size = std::filesystem::file_size(out_, error);
  return error ? 0 : size;
}

double CatCopy::finish(std::string_view ending, std::chrono::milliseconds limit) {
  // The stream was stopped and the device answered the stop request: cat has
  // copied everything once the file ends with that answer (checked every 10 ms
  // against a deadline).
  const auto deadline = std::chrono::steady_clock::now() + limit;
  auto copied = [&] {
    const auto size = file_bytes();
    if (size < ending.size()) return false;
    std::ifstream in(out_, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(size - ending.size()));
    std::string tail(ending.size(), '\0');
    in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
    return tail == ending;
  };
  while (!copied() && std::chrono::steady_clock::now() < deadline) ::poll(nullptr, 0, 10);
  rusage usage{};
  stop_child(pid_, &usage);
  pid_ = -1;
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Result<CatWindow> cat_window(const std::string& link, const std::filesystem::path& out, std::uint32_t baud,
                             std::string_view start, std::string_view stop, std::string_view stopped,
                             std::chrono::milliseconds settle, std::chrono::milliseconds window,
                             const std::function<Status(std::uintmax_t file_bytes)>& mark) {
  auto port = SerialPort::open(link, SerialSettings{baud});
  if (!port) return std::move(port).error();
  auto cat = CatCopy::start(link, out);
  if (!cat) return std::move(cat).error();
  (*port)->close();
  const auto started = std::chrono::steady_clock::now();
  if (auto sent = (*cat)->send(start); !sent) return sent.error();
  std::this_thread::sleep_until(started + settle);
  if (auto marked = mark((*cat)->file_bytes()); !marked) return marked.error();
  std::this_thread::sleep_for(window);
  if (auto marked = mark((*cat)->file_bytes()); !marked) return marked.error();
  if (auto sent = (*cat)->send(stop); !sent) return sent.error();
  CatWindow result;
  result.stream_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  result.cpu_s = (*cat)->finish(stopped, std::chrono::seconds(3));
  result.copied = read_file(out);
  return result;
}

void run_paired(benchmark::State& state, const HostRun& driver, const HostRun& cat, int pairs) {
  struct Pair {
    HostFigures driver;
    HostFigures cat;
    double ratio = 0;
  };
  std::vector<Pair> runs;
  double lost_all = 0;
  double allocs_per_record_max = 0;
  for (int i = 0; i < pairs; ++i) {
    Pair pair;
    if (auto error = driver(pair.driver); !error.empty()) return state.SkipWithError(error.c_str());
    if (auto error = cat(pair.cat); !error.empty()) return state.SkipWithError(error.c_str());
    const double cat_cpu = pair.cat["host_cpu_pct"];
    pair.ratio = cat_cpu > 0 ? pair.driver["host_cpu_pct"] / cat_cpu : 0;
    lost_all += pair.driver["lost"];
    allocs_per_record_max = std::max(allocs_per_record_max, pair.driver["allocs_per_record"]);
    runs.push_back(std::move(pair));
  }
  std::sort(runs.begin(), runs.end(), [](const Pair& a, const Pair& b) { return a.ratio < b.ratio; });
  const Pair& median = runs[runs.size() / 2];
  for (const auto& [name, value] : median.driver) state.counters["drv_" + name] = value;
  for (const auto& [name, value] : median.cat) state.counters["cat_" + name] = value;
  state.counters["cpu_ratio"] = median.ratio;
  state.counters["cpu_ratio_low"] = runs.front().ratio;
  state.counters["cpu_ratio_high"] = runs.back().ratio;
  state.counters["lost_all"] = lost_all;
  state.counters["allocs_per_record_max"] = allocs_per_record_max;
}

}  // namespace rangekit::bench
