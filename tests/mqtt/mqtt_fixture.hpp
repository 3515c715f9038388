// The MQTT tests' rig: a real mosquitto started on a free loopback port (the same
// LocalBroker `rangekit serve --demo` uses; no mock), and a libmosquitto subscriber
// in the test process that keeps every message it hears, retained ones flagged.
#pragma once

#include <gtest/gtest.h>
#include <mosquitto.h>
#include <mqtt_protocol.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "ls5_driver/cli_process.hpp"
#include "rangekit/mqtt/local_broker.hpp"

namespace mqtt_test {

using namespace std::chrono_literals;

struct Heard {
  std::string topic;
  std::string payload;
  bool retained = false;
  std::string correlation;  // MQTT 5 correlation data
};

// A broker of the test's own; `password` set: only that user may connect.
struct Broker {
  ls5_driver_test::TempDir dir;
  std::unique_ptr<rangekit::mqtt::LocalBroker> broker;
  explicit Broker(const std::string& user = {}, const std::string& password = {},
                  const std::string& extra_config = {}) {
    rangekit::mqtt::LocalBrokerOptions options;
    options.dir = dir.path;
    options.extra_config = extra_config;
    options.max_packet_size = 0;  // unbounded unless a test sets one (extra_config): some send megabytes
    if (!user.empty()) {
      options.password_file = (dir.path / "passwords").string();
      const pid_t pid = rangekit::test::fork_child();
      if (pid == 0) {
        ::execlp("mosquitto_passwd", "mosquitto_passwd", "-b", "-c", options.password_file.c_str(), user.c_str(),
                 password.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
      }
      int status = 0;
      ::waitpid(pid, &status, 0);
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "mosquitto_passwd failed";
    }
    auto started = rangekit::mqtt::LocalBroker::start(options);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (started) broker = std::move(*started);
  }
  [[nodiscard]] std::string url() const { return broker ? broker->url() : "mqtt://127.0.0.1:1"; }
  [[nodiscard]] std::uint16_t port() const { return broker ? broker->port() : 1; }
};

class Subscriber {
 public:
  // `persistent_id` set: an MQTT 3.1.1 session that the broker keeps while the subscriber is
  // away (clean session off), so it queues QoS 1 messages for it.
  Subscriber(std::uint16_t port, const std::vector<std::string>& topics, const std::string& persistent_id = {})
      : topics_(topics) {
    mosquitto_lib_init();
    const std::string id = persistent_id.empty()
                               ? "rangekit-test-" + std::to_string(::getpid()) + "-" + std::to_string(++instances())
                               : persistent_id;
    client_ = mosquitto_new(id.c_str(), persistent_id.empty(), this);
    mosquitto_int_option(client_, MOSQ_OPT_PROTOCOL_VERSION,
                         persistent_id.empty() ? MQTT_PROTOCOL_V5 : MQTT_PROTOCOL_V311);
    mosquitto_connect_v5_callback_set(client_,
                                      [](mosquitto* client, void* self, int rc, int, const mosquitto_property*) {
                                        if (rc != 0) return;
                                        for (const std::string& topic : static_cast<Subscriber*>(self)->topics_) {
                                          mosquitto_subscribe(client, nullptr, topic.c_str(), 1);
                                        }
                                        static_cast<Subscriber*>(self)->subscribed();
                                      });
    mosquitto_message_v5_callback_set(
        client_, [](mosquitto*, void* self, const mosquitto_message* message, const mosquitto_property* props) {
          Heard heard{
              message->topic,
              std::string(static_cast<const char*>(message->payload), static_cast<std::size_t>(message->payloadlen)),
              message->retain,
              {}};
          void* data = nullptr;
          std::uint16_t length = 0;
          if (mosquitto_property_read_binary(props, MQTT_PROP_CORRELATION_DATA, &data, &length, false) != nullptr) {
            heard.correlation.assign(static_cast<const char*>(data), length);
            free(data);  // NOLINT(cppcoreguidelines-no-malloc)
          }
          static_cast<Subscriber*>(self)->add(std::move(heard));
        });
    mosquitto_reconnect_delay_set(client_, 1, 2, false);
    mosquitto_connect_async(client_, "127.0.0.1", port, 30);
    mosquitto_loop_start(client_);
  }
  ~Subscriber() {
    mosquitto_disconnect(client_);
    mosquitto_loop_stop(client_, false);
    mosquitto_destroy(client_);
  }
  Subscriber(const Subscriber&) = delete;
  Subscriber& operator=(const Subscriber&) = delete;

  // Waits (generously: sanitizer builds are slow) until `done` holds for what was heard.
  template <class Done>
  bool wait_for(Done done, std::chrono::seconds limit = 90s) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, limit, [&] { return done(heard_); });
  }
  bool wait_subscribed() {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, 60s, [&] { return subscribed_; });
  }
  std::vector<Heard> heard() {
    const std::lock_guard lock(mutex_);
    return heard_;
  }
  void clear() {
    const std::lock_guard lock(mutex_);
    heard_.clear();
  }
  // Publishes a request; MQTT 5 response topic and correlation data when given.
  void publish(const std::string& topic, const std::string& payload, const std::string& response_topic = {},
               const std::string& correlation = {}, bool retain = false) {
    mosquitto_property* props = nullptr;
    if (!response_topic.empty())
      mosquitto_property_add_string(&props, MQTT_PROP_RESPONSE_TOPIC, response_topic.c_str());
    if (!correlation.empty()) {
      mosquitto_property_add_binary(&props, MQTT_PROP_CORRELATION_DATA, correlation.data(),
                                    static_cast<std::uint16_t>(correlation.size()));
    }
    mosquitto_publish_v5(client_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 1, retain,
                         props);
    mosquitto_property_free_all(&props);
  }

 private:
  static int& instances() {
    static int count = 0;
    return count;
  }
  void add(Heard heard) {
    {
      const std::lock_guard lock(mutex_);
      heard_.push_back(std::move(heard));
    }
    changed_.notify_all();
  }
  void subscribed() {
    {
      const std::lock_guard lock(mutex_);
      subscribed_ = true;
    }
    changed_.notify_all();
  }
  std::vector<std::string> topics_;
  mosquitto* client_ = nullptr;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Heard> heard_;
  bool subscribed_ = false;
};

}  // namespace mqtt_test
