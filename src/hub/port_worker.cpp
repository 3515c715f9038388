#include "hub/port_worker.hpp"

namespace rangekit::hub {

PortWorker::PortWorker(std::unique_ptr<Backend> backend, std::vector<Session*> sessions, Publisher& publisher,
                       std::chrono::milliseconds reconnect_interval)
    : backend_(std::move(backend)),
      sessions_(std::move(sessions)),
      publisher_(publisher),
      reconnect_interval_(reconnect_interval) {
  backend_->set_between_steps([this](std::chrono::nanoseconds step) { serve_between_steps(step); });
}

PortWorker::~PortWorker() { stop(); }

void PortWorker::start() {
  thread_ = std::thread([this] { loop(); });
}

void PortWorker::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  // Anything still queued learns the service is stopping.
  std::deque<Job> left;
  {
    std::lock_guard lock(mutex_);
    left.swap(jobs_);
  }
  for (Job& job : left) job(nullptr);
}

bool PortWorker::post(Job job) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    jobs_.push_back(std::move(job));
  }
  wake_.notify_all();
  return true;
}

void PortWorker::announce(StreamEventKind kind, const std::string& message, Audience audience) {
  for (Session* session : sessions_) {
    if (audience == Audience::answering_sensors && !backend_->answering(*session)) continue;
    publisher_.publish(*session, make_event(kind, message));
  }
}

bool PortWorker::try_connect(bool& was_connected, std::string& last_failure) {
  if (auto connected = backend_->connect(); !connected) {
    // Said once per distinct failure, not every retry.
    if (connected.error().message != last_failure) {
      last_failure = connected.error().message;
      announce(StreamEventKind::disconnected, last_failure);
    }
    return false;
  }
  last_failure.clear();
  announce(was_connected ? StreamEventKind::reconnected : StreamEventKind::connected, "connected",
           Audience::answering_sensors);
  was_connected = true;
  // Read before the streams start: nothing has to be paused for it.
  for (Session* session : sessions_) {
    if (!backend_->has_settings() || !backend_->answering(*session)) continue;
    if (auto read = backend_->read_settings(*session); !read) {
      publisher_.publish(*session,
                         make_event(StreamEventKind::device_error, "settings not read: " + read.error().describe()));
    }
  }
  for (Session* session : sessions_) {
    bool wanted = false;
    {
      std::lock_guard lock(session->mutex);
      wanted = session->want_stream;
    }
    if (!wanted) continue;
    if (auto started = backend_->set_streaming(*session, true); !started) {
      publisher_.publish(
          *session, make_event(StreamEventKind::device_error, "stream not started: " + started.error().describe()));
    }
  }
  return true;
}

void PortWorker::run_jobs(bool connected) {
  // Only the jobs queued by now: clients that post again as soon as they are answered would
  // otherwise keep the loop here and the poll of a bus would never run again.
  std::size_t queued = 0;
  {
    std::lock_guard lock(mutex_);
    queued = jobs_.size();
  }
  for (; queued > 0; --queued) {
    Job job;
    {
      std::lock_guard lock(mutex_);
      if (jobs_.empty()) return;  // stop() took them
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job(connected ? backend_.get() : nullptr);
  }
}

void PortWorker::serve_between_steps(std::chrono::nanoseconds poll_for) {
  if (between_steps_) return;  // a long job run from here goes on in one piece
  between_steps_ = true;
  // The loop's own turn: the jobs queued by now, then polls (each followed by the jobs queued
  // meanwhile) for up to `poll_for`, so that a long job shares the wire with the rest.
  const auto until = std::chrono::steady_clock::now() + poll_for;
  run_jobs(backend_->connected());
  while (std::chrono::steady_clock::now() < until && backend_->connected() &&
         backend_->pump(std::chrono::milliseconds(0))) {
    run_jobs(backend_->connected());
  }
  between_steps_ = false;
}

void PortWorker::loop() {
  bool was_connected = false;
  std::string last_failure;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) break;
    }
    bool connected = backend_->connected();
    if (!connected) {
      if (was_connected && last_failure.empty()) {
        last_failure = "the link went away";
        announce(StreamEventKind::disconnected, last_failure);
      }
      connected = try_connect(was_connected, last_failure);
    }
    run_jobs(connected);
    for (Session* session : sessions_) publisher_.release_due(*session);
    if (connected && backend_->pump(std::chrono::milliseconds(20))) continue;
    // Nothing to do now: sleep until a command comes, the next paced poll is due, or it is
    // time to retry the port.
    auto until = std::chrono::steady_clock::now() + (connected ? std::chrono::milliseconds(200) : reconnect_interval_);
    if (connected) {
      if (const auto due = backend_->next_due(); due && *due < until) until = *due;
    }
    std::unique_lock lock(mutex_);
    wake_.wait_until(lock, until, [this] { return stopping_ || !jobs_.empty(); });
  }
  backend_->shutdown();
}

}  // namespace rangekit::hub
