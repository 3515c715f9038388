// The bridge's network thread: one poll() over the hub's wake-ups and every session's
// socket, hub items turned into readings, sessions kept connected, sensors' status and
// availability published, and the clean stop that says offline.
#include "mqtt/bridge_impl.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <ctime>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "mqtt/home_assistant_discovery.hpp"
#include "mqtt/sensor_link.hpp"
#include "rangekit/hub/json_views.hpp"

namespace rangekit::mqtt {
namespace {

using namespace std::chrono_literals;

}  // namespace

// One poll over the wake eventfd and every open session socket, then libmosquitto's read
// and write for the sockets that are ready (its callbacks run here, on the network thread).
// True when the eventfd woke it (hub items, replies or closing); not heard when !hear_wake.
bool Bridge::Impl::serve_sockets(std::chrono::microseconds timeout, bool hear_wake) {
  std::vector<pollfd> fds;
  std::vector<Link*> owners;
  fds.reserve(links.size() + 1);
  owners.reserve(links.size());
  fds.push_back(pollfd{waker->fd, static_cast<short>(hear_wake ? POLLIN : 0), 0});
  for (const auto& link : links) {
    const int sock = mosquitto_socket(link->client);
    if (sock < 0) continue;
    // While part of a fast-path packet is on the wire only its rest may go (Link::out).
    const bool write = mosquitto_want_write(link->client) || !link->out.empty();
    const auto events = static_cast<short>((link->out.mid_packet() ? 0 : POLLIN) | (write ? POLLOUT : 0));
    fds.push_back(pollfd{sock, events, 0});
    owners.push_back(link.get());
  }
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(timeout);
  const timespec wait{seconds.count(), std::chrono::duration_cast<std::chrono::nanoseconds>(timeout - seconds).count()};
  if (::ppoll(fds.data(), fds.size(), &wait, nullptr) <= 0) return false;
  const bool woken = (fds[0].revents & POLLIN) != 0;
  if (woken) {
    std::uint64_t count = 0;
    if (::read(waker->fd, &count, sizeof count) < 0) count = 0;  // nonblocking: nothing to take is fine
  }
  for (std::size_t i = 0; i < owners.size(); ++i) {
    const short revents = fds[i + 1].revents;
    Link& link = *owners[i];
    mosquitto* client = link.client;
    if ((revents & (POLLERR | POLLHUP)) != 0) link.drop_out();  // lost: libmosquitto's read says so
    if ((revents & (POLLIN | POLLERR | POLLHUP)) != 0 && !link.out.mid_packet()) mosquitto_loop_read(client, 1);
    if ((revents & POLLOUT) != 0 && mosquitto_socket(client) >= 0) {
      if (!link.out.mid_packet() && mosquitto_want_write(client)) mosquitto_loop_write(client, 1);
      link.write_out();
    }
  }
  return woken;
}

std::size_t Bridge::Impl::take_items(hub::Subscription& subscription) {
  const hub::MqttConfig& config = options.config;
  std::size_t total = 0;
  // The listener wakes this thread only when an item lands in an empty queue: take it all.
  for (std::size_t taken = 1024; taken == 1024;) {
    const auto batch = subscription.take(1024, 0ms);
    taken = batch.size();
    total += taken;
    // A sensor's items come in runs (a batch of a packet): its link is looked up once a run.
    const std::string* run_sensor = nullptr;
    Link* run_link = nullptr;
    for (const hub::HubItemPtr& item : batch) {
      if (run_sensor == nullptr || item->sensor != *run_sensor) {
        const auto found = by_sensor.find(item->sensor);
        run_sensor = &item->sensor;
        run_link = found == by_sensor.end() ? nullptr : found->second;
      }
      if (run_link == nullptr) continue;
      Link& link = *run_link;
      if (const auto* sample = std::get_if<Sample>(&item->item)) {
        if (auto message = link.window.add(*sample, std::chrono::steady_clock::now())) {
          link.send_reading(std::move(*message), config.qos_reading);
        }
      } else if (const auto* event = std::get_if<StreamEvent>(&item->item);
                 event != nullptr && event->kind == StreamEventKind::lost_records) {
        link.window.add_lost(event->count);
      }
    }
  }
  hub_lost = subscription.lost();
  return total;
}

// Without libmosquitto's thread the bridge keeps each session up itself: keepalive (PINGREQ,
// and a silent broker counted as lost), and a reconnect with backoff doubling from
// reconnect_min_s to reconnect_max_s, or every reconnect_max_s after a refusal.
void Bridge::Impl::keep_connected(Link& link, std::chrono::steady_clock::time_point now) const {
  if (const int sock = mosquitto_socket(link.client); sock >= 0) {
    if (!link.out.mid_packet()) {
      link.mid_packet_since = {};
      mosquitto_loop_misc(link.client);  // keepalive; it may write a PINGREQ
      return;
    }
    // No PINGREQ can go while part of a packet waits, so libmosquitto's keepalive cannot see a
    // broker that stopped reading (a dead host, no RST). A socket that takes nothing more for
    // 1.5 keepalive periods is taken for lost, as libmosquitto would: shut down, its next read
    // reports the loss and the session reconnects.
    if (link.mid_packet_since == std::chrono::steady_clock::time_point{}) link.mid_packet_since = now;
    if (now - link.mid_packet_since > std::chrono::milliseconds(1500) * std::max(options.keepalive_s, 1)) {
      ::shutdown(sock, SHUT_RDWR);
      link.mid_packet_since = {};
    }
    return;
  }
  if (link.next_attempt == std::chrono::steady_clock::time_point{}) {
    const int max_s = std::max(options.config.reconnect_max_s, 1);
    const int delay_s = link.refused ? max_s : std::min(link.backoff_s, max_s);
    if (!link.refused) link.backoff_s = std::min(link.backoff_s * 2, max_s);
    link.refused = false;
    link.next_attempt = now + std::chrono::seconds(delay_s);
    return;
  }
  if (now < link.next_attempt) return;
  link.next_attempt = {};
  // A broker still away fails here or on the socket; the next call plans the next attempt.
  mosquitto_reconnect_async(link.client);
}

// Availability follows the sensor's link; status goes out on a change and every status_interval.
void Bridge::Impl::poll_sensors(std::chrono::steady_clock::time_point now) {
  const hub::MqttConfig& config = options.config;
  for (const auto& link : links) {
    keep_connected(*link, now);
    link->forget_acknowledged();
    auto snapshot = hub.sensor(link->config.name);
    if (!snapshot) continue;
    const bool republish = std::exchange(link->republish, false);
    // What waited goes first: after a reconnect without its stale retained messages; otherwise
    // what a publish refused in passing (a connection that dropped and came back in between).
    if (republish || link->connected) link->flush(republish);
    const bool online = snapshot->health.connected;
    nlohmann::json status = hub::sensor_json(*snapshot);
    nlohmann::json without_health = status;
    without_health.erase("health");
    without_health.erase("last_id");
    std::string fingerprint = without_health.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    const bool changed = fingerprint != link->last_status;
    link->last_status = std::move(fingerprint);
    const bool status_now = link->status_now.exchange(false) || changed;
    if (republish || status_now || link->online != online || now >= link->next_status) {
      if (republish && config.discovery) {
        for (Message& message : discovery_messages(*link, config)) link->send(std::move(message));
      }
      if (republish || link->online != online) {
        link->send(Message{link->topic + "/availability", online ? "online" : "offline", config.qos_state, true});
      }
      status["service"] = config.client_id;
      link->send(Message{link->topic + "/status", status.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                         config.qos_state, true});
      link->online = online;
      link->next_status = now + options.status_interval;
    }
  }
}

// The clean stop's waits: the sockets are served while `pending()` holds, for at most `limit`.
template <class Pending>
void Bridge::Impl::serve_while(Pending pending, std::chrono::milliseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (pending() && std::chrono::steady_clock::now() < until) serve_sockets(50ms);
}

// A clean stop says offline itself (the broker sends no will after a DISCONNECT) and
// waits, bounded, for the broker to acknowledge it, then disconnects every session.
void Bridge::Impl::say_offline_and_disconnect() {
  // The fast path's last readings first, bounded. A session whose socket never takes the rest
  // of a packet writes nothing more: closed without DISCONNECT, its will says offline.
  const auto unsent = [&] {
    return std::any_of(links.begin(), links.end(),
                       [](const auto& link) { return link->connected && !link->out.empty(); });
  };
  for (const auto& link : links) link->write_out();
  serve_while(unsent, 1s);
  const int qos = std::max(options.config.qos_state, 1);
  for (const auto& link : links) {
    int mid = -1;
    if (link->connected && !link->out.mid_packet() &&
        link->try_publish(Message{link->topic + "/availability", "offline", qos, true}, &mid) == Link::Publish::sent) {
      link->offline_mid = mid;
    }
  }
  const auto waiting = [&] {
    return std::any_of(links.begin(), links.end(), [](const auto& link) {
      return link->connected && link->offline_mid >= 0 && !link->offline_acked;
    });
  };
  serve_while(waiting, 5s);
  for (const auto& link : links) {
    if (mosquitto_socket(link->client) >= 0 && !link->out.mid_packet()) {
      mosquitto_disconnect(link->client);
      link->disconnect_sent = true;
    }
  }
  // The DISCONNECTs that did not fit the sockets at once.
  const auto open = [&] {
    return std::any_of(links.begin(), links.end(),
                       [](const auto& link) { return link->disconnect_sent && mosquitto_socket(link->client) >= 0; });
  };
  serve_while(open, 1s);
  // What the broker never took (a session that would not drain) is lost with the socket: counted.
  for (const auto& link : links) link->drop_out();
}

void Bridge::Impl::run_network() {
  auto subscription = hub.subscribe("", 65536, hub::OverflowPolicy::drop_oldest);
  if (!subscription) log("mqtt: cannot subscribe to the hub: " + subscription.error().message);
  if (subscription) (*subscription)->set_listener([waker = waker] { waker->signal(); });
  for (const auto& link : links) {
    // Refused or unreachable now is retried with backoff by keep_connected.
    mosquitto_connect_async(link->client, address.host.c_str(), address.port, options.keepalive_s);
  }
  using Clock = std::chrono::steady_clock;
  auto next_poll = Clock::now();
  // Hub items are taken at most once per drain_gather: woken by the first item of a quiet
  // spell the thread lets the next ones join it, so a drain carries several readings per
  // session and their send() (docs/mqtt.md, "The reading fast path"). While items flow it
  // drains on that timer alone, deaf to the hub's wake-ups (one wake-up per drain, not two);
  // a drain that finds nothing goes back to waiting for the hub, so an idle bridge sleeps.
  bool items_waiting = false;
  bool ticking = false;
  auto last_drain = Clock::now() - options.drain_gather;
  while (!closing) {
    auto now = Clock::now();
    // Wakes for hub items, replies, sockets, and at least every 20 ms for the windows' deadlines.
    auto wait = std::min<Clock::duration>(next_poll - now, 20ms);
    if (items_waiting || ticking) wait = std::min<Clock::duration>(wait, last_drain + options.drain_gather - now);
    const auto timeout = std::chrono::duration_cast<std::chrono::microseconds>(std::max<Clock::duration>(wait, 0us));
    if (serve_sockets(timeout, !ticking)) items_waiting = true;
    now = Clock::now();
    if (subscription && (items_waiting || ticking) && now >= last_drain + options.drain_gather) {
      items_waiting = false;
      last_drain = now;
      ticking = take_items(**subscription) > 0;
    }
    send_replies();
    now = std::chrono::steady_clock::now();
    for (const auto& link : links) {
      if (auto message = link->window.flush_due(now))
        link->send_reading(std::move(*message), options.config.qos_reading);
      link->store_staged();
      link->publish_spooled();
      link->write_out();  // the drain's fast-path readings, in one send() per session
    }
    if (now < next_poll) continue;
    next_poll = now + 100ms;
    poll_sensors(now);
  }
  if (subscription) (*subscription)->close();
  send_replies();
  say_offline_and_disconnect();
  // What the broker acknowledged by now leaves the spools; the rest goes at the next start.
  for (const auto& link : links) {
    link->store_staged();
    link->forget_acknowledged();
  }
}

}  // namespace rangekit::mqtt
