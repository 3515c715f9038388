// Clients that try to take the service down (docs/security.md, "Limits"): each one as a
// test, with the service still answering after it.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>

#include <filesystem>
#include <thread>

#include "child_process.hpp"
#include "web/live_service.hpp"

namespace hostile_test {

using namespace rangekit;
using web_test::error_code;
using web_test::http;
using web_test::Reply;
using Service = web_test::LiveService;

// Beast bounds the headers but not a chunk-size line: the read buffer does.
TEST(HostileClient, AChunkSizeLineThatNeverEndsIsRefused) {
  Service service("127.0.0.1:0");
  const std::string head =
      "POST /api/sensors/belt/actions/read HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(service.port) +
      "\r\nTransfer-Encoding: chunked\r\n\r\n1;";
  const Reply reply = http(service.port, "POST", "/", {}, {}, head + std::string(16 * 1024, 'a'));
  EXPECT_EQ(reply.status, 400) << reply.body;
  EXPECT_EQ(error_code(reply), "line_too_long");
  service.expect_unharmed();
}

// Streams have a limit of their own, so that they cannot keep requests out.
TEST(HostileClient, StreamsHaveALimitAndRequestsStillGetIn) {
  web::ServerOptions options;
  options.max_streams = 3;
  Service service("127.0.0.1:0", options);
  std::vector<std::unique_ptr<web_test::EventReader>> streams;
  for (int i = 0; i < 3; ++i) {
    streams.push_back(std::make_unique<web_test::EventReader>(service.port, "/api/events"));
    ASSERT_TRUE(streams.back()->read_until([](const web_test::Event&) { return true; }));
  }
  web_test::EventReader over(service.port, "/api/events");
  over.read_to_end(std::chrono::seconds(10));
  EXPECT_EQ(over.status(), 503);
  EXPECT_EQ(http(service.port, "GET", "/api/sensors").status, 200);
  streams.pop_back();  // its stream ends at its next write; then a new one gets in
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  int status = 0;
  while (status != 200 && std::chrono::steady_clock::now() < deadline) {
    status = web_test::stream_status(service.port, "/api/events");
  }
  EXPECT_EQ(status, 200);
  service.expect_unharmed();
}

// A stream resumed with an id of an earlier run (ids begin again at each start) is told so
// and starts now, instead of waiting for the new ids to pass the old one.
TEST(HostileClient, AResumeFromAnEarlierRunIsToldAndStartsNow) {
  Service service("127.0.0.1:0");
  web_test::EventReader reader(service.port, "/api/events", {"Last-Event-ID: 999999999999"});
  ASSERT_TRUE(reader.read_until([](const web_test::Event& event) { return event.type == "sample"; }));
  ASSERT_FALSE(reader.events.empty());
  EXPECT_EQ(reader.events.front().type, "resume");
  EXPECT_FALSE(nlohmann::json::parse(reader.events.front().data)["complete"].get<bool>());
  service.expect_unharmed();
}

// A write on a kept-alive connection while the service stops is answered or closed; before,
// the Host check asked the closed acceptor where it listens, which throws, and the process ended.
TEST(HostileClient, AWriteDuringShutdownNeverEndsTheProcess) {
  Service service("127.0.0.1:0");
  const int kept = web_test::connect_to(service.port);
  ASSERT_GE(kept, 0);
  // A bus scan holds the command pool, so stop() waits for it with the acceptor already closed.
  const int scan = web_test::connect_to(service.port);
  ASSERT_TRUE(
      web_test::send_all(scan, web_test::request_text("POST", "/api/sensors/bay-C/bus/scan", "", {}, service.port)));
  std::thread stopper([&] { service.server->stop(); });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  int probe = 0;
  while ((probe = web_test::connect_to(service.port)) >= 0 && std::chrono::steady_clock::now() < deadline)
    ::close(probe);
  EXPECT_LT(probe, 0) << "the listener did not close";
  const std::string patch =
      "PATCH /api/sensors/belt/settings HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(service.port) +
      "\r\nContent-Length: 2\r\n\r\n{}";
  web_test::send_all(kept, patch);
  std::string answer;
  while (web_test::read_some(kept, answer, std::chrono::milliseconds(200)) &&
         answer.find("\r\n\r\n") == std::string::npos && std::chrono::steady_clock::now() < deadline) {
  }
  stopper.join();
  ::close(kept);
  ::close(scan);
  // Still running; the write got an HTTP answer, or the connection was closed without one.
  EXPECT_TRUE(answer.empty() || answer.rfind("HTTP/1.1 ", 0) == 0) << answer.substr(0, 200);
}

// The request deadline covers reading the request; a download is cut only when it stalls.
TEST(HostileClient, ADownloadLongerThanTheRequestDeadlineIsNotCutWhileItMoves) {
  web::ServerOptions options;
  options.request_timeout = std::chrono::milliseconds(500);
  Service service("127.0.0.1:0", options);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (service.captures.info(service.capture)->samples < 2000 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // polls the capture's count, with a deadline
  }
  ASSERT_TRUE(service.captures.stop(service.capture).ok());
  // A small receive window and a slow reader: the download takes a few request deadlines. The
  // service's 64 KiB send buffer refills when a third is free, a few times per deadline; 2000
  // samples (280 KiB) are enough to outlast two deadlines after what the buffers hold.
  const int fd = web_test::connect_to(service.port, 4096);
  ASSERT_GE(fd, 0);
  const std::string target = "/api/captures/" + service.capture + "/download?format=jsonl";
  ASSERT_TRUE(web_test::send_all(fd, web_test::request_text("GET", target, "", {}, service.port)));
  std::string all;
  const auto started = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < deadline && web_test::read_some(fd, all, std::chrono::milliseconds(50))) {
    std::this_thread::sleep_for(std::chrono::milliseconds(40));  // the slow reader itself, not a wait for the server
  }
  ::close(fd);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const auto head_end = all.find("\r\n\r\n");
  ASSERT_NE(head_end, std::string::npos);
  const auto length_at = all.find("Content-Length: ");
  ASSERT_NE(length_at, std::string::npos);
  const std::size_t length = std::stoul(all.substr(length_at + 16));
  EXPECT_EQ(all.size() - head_end - 4, length) << "cut after " << seconds << " s";
  EXPECT_GT(seconds, 1.0) << "the download was too quick to show anything: " << length << " bytes";
  service.expect_unharmed();
}

// Slowloris: headers trickled a byte a second from 300 sockets, more than the service takes. A
// new client takes the place of the oldest that has waited over half a second, so it is answered.
TEST(HostileClient, TricklingClientsDoNotKeepOthersOut) {
  web::ServerOptions options;
  options.max_connections = 64;
  Service service("127.0.0.1:0", options);
  std::vector<int> trickling;
  for (int i = 0; i < 300; ++i) {
    const int fd = web_test::connect_to(service.port);
    ASSERT_GE(fd, 0);
    web_test::send_all(fd, "G");
    trickling.push_back(fd);
  }
  const std::string rest = "ET /api/sensors HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(service.port) + "\r\nX: ";
  // Over three seconds, a byte a second on every socket; a client asks /healthz meanwhile.
  int answered = 0;
  for (std::size_t second = 0; second < 3; ++second) {
    std::this_thread::sleep_for(std::chrono::seconds(1));  // the trickle's own pace
    for (const int fd : trickling) web_test::send_all(fd, rest.substr(second, 1));
    const auto asked = std::chrono::steady_clock::now();
    const Reply health = http(service.port, "GET", "/healthz");
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
    EXPECT_EQ(health.status, 200) << "second " << second << ": " << health.body;
    EXPECT_LT(took, 1.0) << "second " << second;
    answered += health.status == 200 ? 1 : 0;
  }
  EXPECT_EQ(answered, 3);
  for (const int fd : trickling) ::close(fd);
  service.expect_unharmed();
}

// A Content-Length of 2 GB is refused from the headers, before any of the body is read.
TEST(HostileClient, AHugeContentLengthIsRefusedAtOnce) {
  Service service("127.0.0.1:0");
  const Reply reply =
      http(service.port, "PATCH", "/", {}, {},
           "PATCH /api/sensors/belt/settings HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(service.port) +
               "\r\nContent-Length: 2147483648\r\n\r\n{");
  EXPECT_EQ(reply.status, 413) << reply.body;
  EXPECT_EQ(error_code(reply), "body_too_large");
  service.expect_unharmed();
}

// A client that starts captures without end: each has a thread and open files, so the service
// runs at most 16 at once (one is the fixture's) and refuses the rest, saying what to do.
TEST(HostileClient, CapturesStartedWithoutEndStopAtTheLimit) {
  Service service("127.0.0.1:0");
  int started = 0;
  int refused = 0;
  std::string refusal;
  for (int i = 0; i < 40; ++i) {
    const Reply reply = http(service.port, "POST", "/api/captures", R"({"sensors": ["silo"]})");
    if (reply.status == 201) ++started;
    if (reply.status == 409 && error_code(reply) == "limit") {
      ++refused;
      refusal = reply.body;
    }
  }
  EXPECT_EQ(started, 15);
  EXPECT_EQ(refused, 25);
  EXPECT_NE(refusal.find("stop one first"), std::string::npos) << refusal;
  service.expect_unharmed();
}

// Streams that never read: each fills its socket, then its queue, and is cut off; the sensors
// go on, other clients are answered, and what the service holds stays bounded.
TEST(HostileClient, StreamsThatNeverReadAreCutOffAndTheServiceGoesOn) {
  web::ServerOptions options;
  options.stream_queue = 256;
  Service service("127.0.0.1:0", options);
  std::vector<std::unique_ptr<web_test::EventReader>> idle;
  for (int i = 0; i < 500; ++i) {
    idle.push_back(
        std::make_unique<web_test::EventReader>(service.port, "/api/events", std::vector<std::string>{}, 4096));
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (service.server->stats().streams_cut_off < 200 && std::chrono::steady_clock::now() < deadline) {
    EXPECT_EQ(http(service.port, "GET", "/healthz").status, 200);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // asks now and then, leaving the CPU to the rest
  }
  EXPECT_GE(service.server->stats().streams_cut_off, 200u);
  EXPECT_LE(service.server->stats().streams, 256u);
  web_test::EventReader reader(service.port, "/api/sensors/belt/events");
  idle.clear();
  EXPECT_TRUE(reader.read_until([](const web_test::Event& event) { return event.type == "sample"; }));
  service.expect_unharmed();
}

double cpu_seconds() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
}

std::size_t open_descriptors() {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) ++count;
  return count;
}

// Clients that connect until the service's descriptors run out: accept() fails with EMFILE
// while clients wait in the backlog. The listener waits before it tries again instead of
// spinning, and serves again once descriptors are back.
TEST(HostileClient, OutOfDescriptorsTheListenerWaitsInsteadOfSpinning) {
  Service service("127.0.0.1:0");
  ASSERT_EQ(http(service.port, "GET", "/healthz").status, 200);
  // What the service uses anyway (the sensors' readers, the capture), to compare with.
  const double idle_before = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::seconds(1));  // the window whose CPU is measured
  const double idle = cpu_seconds() - idle_before;
  int gate[2];
  ASSERT_EQ(::pipe(gate), 0);
  const pid_t clients = rangekit::test::fork_child();
  if (clients == 0) {  // a process of its own, so its sockets do not count against the service's limit
    ::close(gate[1]);
    for (int i = 0; i < 200; ++i) web_test::connect_to(service.port);
    char byte = 0;
    (void)::read(gate[0], &byte, 1);  // until the test is done
    ::_exit(0);
  }
  ::close(gate[0]);
  rlimit limit{};
  ::getrlimit(RLIMIT_NOFILE, &limit);
  const rlimit before = limit;
  limit.rlim_cur = open_descriptors() + 16;
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &limit), 0);
  // The service takes clients until it has no descriptor left: then they stay in the backlog.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (service.server->stats().connections < 10 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polls the count, with a deadline
  }
  const double cpu_before = cpu_seconds();
  std::this_thread::sleep_for(std::chrono::seconds(1));  // the window whose CPU is measured
  const double used = cpu_seconds() - cpu_before;
  ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &before), 0);
  ::close(gate[1]);
  int status = 0;
  ::waitpid(clients, &status, 0);
  // A listener that spins takes a whole core: a second of CPU in the second.
  EXPECT_LT(used - idle, 0.5) << "the process used " << used << " s of CPU in 1 s while out of descriptors, " << idle
                              << " s before";
  int health = 0;
  const auto again = std::chrono::steady_clock::now() + std::chrono::seconds(70);
  while (health != 200 && std::chrono::steady_clock::now() < again)
    health = http(service.port, "GET", "/healthz").status;
  EXPECT_EQ(health, 200);
  service.expect_unharmed();
}

}  // namespace hostile_test
