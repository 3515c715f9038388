// The mosquitto `rangekit serve --demo` starts ends with the service, also when the service
// dies without stopping it (kill -9, a crash): no orphaned broker is left holding its port.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "child_process.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/mqtt/local_broker.hpp"

namespace local_broker_test {

using namespace std::chrono_literals;

using rangekit::test::OrphanReaper;
using rangekit::test::reaped_within;

TEST(LocalBroker, EndsWhenTheProcessThatStartedItIsKilled) {
  if (rangekit::mqtt::LocalBroker::find_executable().empty()) GTEST_SKIP() << "no mosquitto installed";
  const ls5_driver_test::TempDir dir;
  const OrphanReaper reaper;
  std::array<int, 2> pid_pipe{};
  ASSERT_EQ(::pipe2(pid_pipe.data(), O_CLOEXEC), 0);
  const pid_t service = rangekit::test::fork_child();
  ASSERT_GE(service, 0);
  if (service == 0) {
    // The service's stand-in: starts the broker from its main thread as serve --demo does,
    // tells its pid and dies without a word.
    ::close(pid_pipe[0]);
    rangekit::mqtt::LocalBrokerOptions options;
    options.dir = dir.path;
    auto broker = rangekit::mqtt::LocalBroker::start(options);
    const pid_t pid = broker ? (*broker)->pid() : -1;
    (void)!::write(pid_pipe[1], &pid, sizeof pid);
    ::raise(SIGKILL);
    ::_exit(1);
  }
  ::close(pid_pipe[1]);
  pid_t broker = -1;
  pollfd told{pid_pipe[0], POLLIN, 0};
  // LocalBroker::start gives up after 20 s; the rest is a margin for slow machines.
  const bool heard = ::poll(&told, 1, 60000) == 1 && ::read(pid_pipe[0], &broker, sizeof broker) == sizeof broker;
  ::close(pid_pipe[0]);
  if (!heard) ::kill(service, SIGKILL);
  int status = 0;
  ASSERT_EQ(::waitpid(service, &status, 0), service);
  ASSERT_TRUE(heard && broker > 0) << "the stand-in did not start a broker";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  const bool ended = reaped_within(broker, 10s);
  if (!ended) {  // left running: stopped here, so that the test leaves nothing behind
    ::kill(broker, SIGKILL);
    ::waitpid(broker, nullptr, 0);
  }
  EXPECT_TRUE(ended) << "mosquitto (pid " << broker << ") outlived the process that started it";
}

// The bridge cannot announce a Maximum Packet Size (libmosquitto 2.0 sends CONNECT properties
// only on a blocking connect, and none on its reconnects): the broker it starts bounds what any
// client publishes instead, so a command far over the bridge's 16 KiB never reaches a subscriber.
TEST(LocalBroker, DropsPublicationsOverItsMaximumPacketSize) {
  if (rangekit::mqtt::LocalBroker::find_executable().empty()) GTEST_SKIP() << "no mosquitto installed";
  const ls5_driver_test::TempDir dir;
  rangekit::mqtt::LocalBrokerOptions options;
  options.dir = dir.path;
  auto broker = rangekit::mqtt::LocalBroker::start(options);
  ASSERT_TRUE(broker.ok()) << broker.error().message;
  const std::string at = " -V 5 -h 127.0.0.1 -p " + std::to_string((*broker)->port()) + " -t rangekit/belt/set ";
  // NOLINTBEGIN(concurrency-mt-unsafe): std::system from the test's only thread
  const auto publish = [&](const std::string& what) {
    return std::system(("mosquitto_pub -q 1" + at + what + " >/dev/null 2>&1").c_str());
  };
  const auto received = dir.path / "received";
  ASSERT_EQ(std::system(("timeout 60 mosquitto_sub" + at + "> " + received.string() + " 2>&1 &").c_str()), 0);
  const auto heard = [&](const std::string& text) {
    std::ifstream file(received);
    return std::string(std::istreambuf_iterator<char>(file), {}).find(text) != std::string::npos;
  };
  // Until the subscriber is there: it hears a ping.
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (!heard("ping") && std::chrono::steady_clock::now() < deadline) publish("-m ping");
  ASSERT_TRUE(heard("ping"));
  const auto big = dir.path / "big";
  std::ofstream(big) << std::string(64 * 1024, 'x');
  publish("-f " + big.string());  // QoS 1: the broker has dealt with it when this returns
  publish("-m end");
  while (!heard("end") && std::chrono::steady_clock::now() < deadline) ::poll(nullptr, 0, 20);
  std::system(("pkill -f 'mosquitto_sub" + at + "'").c_str());
  // NOLINTEND(concurrency-mt-unsafe)
  EXPECT_TRUE(heard("end"));
  EXPECT_FALSE(heard(std::string(1000, 'x'))) << "a 64 KiB publication got through";
}

// Tests start brokers in parallel on ports picked a moment before; when another listener took
// the port first, a connect() to it is answered, but not by the broker just started (which
// exits: address in use). Start must say so, not hand out a port that leads to someone else.
TEST(LocalBroker, APortAnotherProcessListensOnIsNotTakenForTheBrokers) {
  if (rangekit::mqtt::LocalBroker::find_executable().empty()) GTEST_SKIP() << "no mosquitto installed";
  const ls5_driver_test::TempDir dir;
  const int other = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(other, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ASSERT_EQ(::bind(other, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(other, 8), 0);
  ASSERT_EQ(::getsockname(other, reinterpret_cast<sockaddr*>(&address), &length), 0);
  rangekit::mqtt::LocalBrokerOptions options;
  options.dir = dir.path;
  options.port = ntohs(address.sin_port);
  auto broker = rangekit::mqtt::LocalBroker::start(options);
  ::close(other);
  ASSERT_FALSE(broker.ok()) << "started on port " << options.port << ", which this test listens on";
  EXPECT_NE(broker.error().message.find("exited at start"), std::string::npos) << broker.error().message;
}

}  // namespace local_broker_test
