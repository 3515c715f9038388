// One thread per port: connects its backend (retrying while the port is
// missing), reads or polls it, and runs the commands asked of its sensors
// between two reads, so a command and the stream never share the wire.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "rangekit/hub/backend.hpp"

namespace rangekit::hub {

class PortWorker {
 public:
  PortWorker(std::unique_ptr<Backend> backend, std::vector<Session*> sessions, Publisher& publisher,
             std::chrono::milliseconds reconnect_interval);
  ~PortWorker();  // stop()
  PortWorker(const PortWorker&) = delete;
  PortWorker& operator=(const PortWorker&) = delete;

  void start();
  void stop();

  // Runs `job` on the worker thread with the port connected, and waits for it.
  // Errc::timeout when it did not finish within `timeout` (it still runs then);
  // Errc::closed when the worker is stopping.
  template <class T>
  Result<T> run(std::function<Result<T>(Backend&)> job, std::chrono::milliseconds timeout) {
    auto promise = std::make_shared<std::promise<Result<T>>>();
    auto future = promise->get_future();
    if (!post([promise, job = std::move(job)](Backend* backend) {
          promise->set_value(backend != nullptr ? job(*backend)
                                                : Result<T>(make_error(Errc::closed, "the sensor is not connected")));
        })) {
      return make_error(Errc::closed, "the service is stopping");
    }
    if (future.wait_for(timeout) != std::future_status::ready) {
      return make_error(Errc::timeout, "the command did not finish in " + std::to_string(timeout.count()) + " ms");
    }
    return future.get();
  }

 private:
  using Job = std::function<void(Backend*)>;  // nullptr: the port is not connected
  bool post(Job job);
  void loop();
  bool try_connect(bool& was_connected, std::string& last_failure);
  void run_jobs(bool connected);
  // What a long job (a bus scan) runs between two of its steps (Backend::between_steps).
  void serve_between_steps(std::chrono::nanoseconds poll_for);
  // Who hears an announcement: every sensor of the port, or only those whose sensor answered
  // when it connected (Backend::answering: a silent unit on a bus is not "connected").
  enum class Audience : std::uint8_t { every_sensor, answering_sensors };
  void announce(StreamEventKind kind, const std::string& message, Audience audience = Audience::every_sensor);

  std::unique_ptr<Backend> backend_;
  std::vector<Session*> sessions_;
  Publisher& publisher_;
  std::chrono::milliseconds reconnect_interval_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  bool stopping_ = false;
  bool between_steps_ = false;  // worker thread only: inside a job's steps
  std::thread thread_;
};

}  // namespace rangekit::hub
